"""``simulate`` of machines with bearing pedestals and gear mesh stiffness: the linear time model
(docs/simulate.md, "Flexible rotors"; docs/theory.md §19). Truths from outside the time model:
the linear steady unbalance response, the energy of an undamped gyroscopic system (gyroscopic
forces do no work) in the linear model's own matrices, and each mass's weight ``m g`` (statics
by hand)."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from steady_harmonics import assert_steady_harmonics_equal_the_linear_response

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
MOUNTS = [[0, 0.2, -0.2], [0, -0.2, -0.2], [0.6, 0.2, -0.2], [0.6, -0.2, -0.2]]
PEDESTAL = {"pedestal_mass": 3.0, "pedestal_stiffness": [4e6, 6e6]}


def _machine(damping=1.0, casing=True, flexible=True, gravity=(0.0, 0.0, 0.0)) -> dict:
    """A shaft (flexible: two Euler-Bernoulli elements with a disk at mid-span; or rigid) on
    bearings A and B, A on a pedestal, meshing (mesh stiffness along the line of action) with a
    rigid gear on bearing G, which stands on a pedestal too; in a casing on four mounts or on the
    ground. ``damping`` scales every damper (0: undamped)."""
    if flexible:
        shaft = {"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": "none",
                 "shaft": [{"length": 0.3, "outer_diameter": 0.03, "material": "steel", "elements": 1}] * 2,
                 "disks": [{"name": "disk", "axial_position": 0.3, "mass": 10.0, "polar_inertia": 0.05,
                            "diametral_inertia": 0.03}]}
        at = [{"axial_position": x} for x in (0.0, 0.6)]
        unbalance = {"rotor": "shaft", "amount": 1e-4, "axial_position": 0.3, "phase_deg": 30.0}
        sensor = {"axial_position": 0.3}
    else:
        shaft = {"name": "shaft", "speed_ratio": 1.0, "mass": 12.0, "center_of_mass": [0.3, 0.0, 0.0],
                 "polar_inertia": 0.05, "diametral_inertia": 0.4}
        at = [{"position": [x, 0.0, 0.0]} for x in (0.0, 0.6)]
        unbalance = {"rotor": "shaft", "amount": 1e-4, "axial_offset": 0.1, "phase_deg": 30.0}
        sensor = {"position": [0.3, 0.0, 0.0]}
    data = {
        "name": "geared", "reference_rotor": "shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
        "gravity": list(gravity),
        "rotors": [shaft, {"name": "gear", "mass": 3.0, "center_of_mass": [0.3, 0.15, 0.0], "polar_inertia": 0.01,
                           "diametral_inertia": 0.008}],
        "bearings": [{"name": "A", "rotor": "shaft", **at[0], "stiffness": [1.0e6, 1.3e6], "damping": 800.0 * damping,
                      **PEDESTAL, "pedestal_damping": 300.0 * damping},
                     {"name": "B", "rotor": "shaft", **at[1], "stiffness": 1.1e6, "damping": 800.0 * damping},
                     {"name": "G", "rotor": "gear", "position": [0.3, 0.15, 0.0], "stiffness": 5e6,
                      "moment_stiffness": 2e4, "damping": 500.0 * damping, "moment_damping": 2.0 * damping,
                      "pedestal_mass": 2.0, "pedestal_stiffness": 8e6}],
        "transmissions": [{"type": "gear", "driver": "shaft", "driven": "gear", "ratio": 1.5,
                           "position": [0.3, 0.0, 0.0], "pressure_angle": 20.0, "mesh_stiffness": 3e6,
                           "mesh_damping": 200.0 * damping}],
        "unbalances": [unbalance,
                       {"rotor": "gear", "amount": 5e-5, "axial_offset": 0.02, "phase_deg": -40.0}],
        "sensors": [{"name": "disk-y", "rotor": "shaft", **sensor, "direction": [0, 1, 0]},
                    {"name": "disk-z", "rotor": "shaft", **sensor, "direction": [0, 0, 1]},
                    {"name": "gear-y", "rotor": "gear", "position": [0.3, 0.15, 0.0], "direction": [0, 1, 0]},
                    {"name": "gear-z", "rotor": "gear", "position": [0.3, 0.15, 0.0], "direction": [0, 0, 1]}],
        "excitations": [{"name": "hammer", "rotor": "shaft", **sensor, "direction": [0, 0.6, 0.8]}],
    }
    if casing:
        data["stator"] = {"mass": 40.0, "inertia": [1.0, 1.5, 1.6], "center_of_mass": [0.3, 0.0, -0.1]}
        data["suspensions"] = [{"name": f"m{i}", "position": p, "stiffness": [2e5, 2.2e5, 3e5],
                                "damping": [300.0 * damping] * 3} for i, p in enumerate(MOUNTS)]
        data["sensors"].append({"name": "casing-z", "position": [0.6, 0.1, 0.0], "direction": [0, 0, 1]})
    return data


@pytest.mark.parametrize("flexible, casing", [(True, True), (False, False)])
def test_steady_unbalance_orbits_with_pedestals_and_a_mesh_equal_the_linear_response(flexible, casing):
    """Constant speed, damped, every mode kept: after the transient every sensor's harmonic at
    each rotor's own frequency equals ``rdm.unbalance_response`` to 1e-6 (a flexible shaft in a
    casing on mounts; a rigid machine on the ground)."""
    model = rdm.Model.from_dict(_machine(damping=10.0, casing=casing, flexible=flexible), source="geared.toml")
    assert model.dofs.pedestals and model.transmissions[0].mesh_stiffness
    speed = 300.0
    res = rdm.simulate(model, 0.4, speed, modes_below=np.inf, samples=1601, rtol=1e-10, atol=1e-14)
    assert_steady_harmonics_equal_the_linear_response(res, model, speed, after=0.3, rtol=1e-6)
