"""``simulate`` of machines with bearing pedestals and gear mesh stiffness: the linear time model
(docs/simulate.md, "Flexible rotors"; docs/theory.md §19). Truths from outside the time model:
the linear steady unbalance response, the energy of an undamped gyroscopic system (gyroscopic
forces do no work) in the linear model's own matrices, and each mass's weight ``m g`` (statics
by hand)."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
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


@pytest.mark.parametrize("flexible", [True, False])
def test_undamped_machine_with_pedestals_and_a_mesh_keeps_its_energy(flexible):
    """No damping, no unbalance, no gravity, a hammer blow: the small motions' energy
    ``q'^T M q' / 2 + q^T K q / 2`` in the linear model's own matrices (the pedestals' masses and
    springs and the mesh's spring in them) stays constant to the integrator's tolerance, at rest
    and spinning (the gyroscopic forces do no work)."""
    data = _machine(damping=0.0, flexible=flexible)
    data["unbalances"] = []
    model = rdm.Model.from_dict(data)
    M, C, G, K = model.matrices(0.0)
    assert not C.any() and np.abs(G).max() > 0
    n = model.dofs.n
    for speed in (0.0, 800.0):
        res = rdm.simulate(model, 0.1, speed, impulse="hammer", impulse_size=0.5, samples=201, rtol=1e-11,
                           atol=1e-14)
        q, dq = res.states[:, :n], res.states[:, n:]
        assert np.abs(q[:, [r.start for _, r in model.dofs.pedestals]]).max() > 0     # the pedestals move
        energy = 0.5 * np.einsum("ti,ij,tj->t", dq, M, dq) + 0.5 * np.einsum("ti,ij,tj->t", q, K, q)
        assert energy[0] > 0
        assert np.abs(energy - energy[0]).max() < 1e-8 * energy[0]
        np.testing.assert_allclose(res.total_energy, energy, rtol=1e-9)


@pytest.mark.parametrize("casing", [True, False])
def test_equilibrium_under_gravity_carries_every_weight_the_pedestals_too(casing):
    """Started in equilibrium under gravity (no unbalance), the machine stays there, and the
    supports to the ground carry every mass's weight, the pedestals' ``m_p g`` included: on the
    ground the pedestals' springs and bearing B (the one without a pedestal) hold the rotors and
    pedestals; in the casing the mounts hold everything."""
    data = _machine(flexible=True, casing=casing, gravity=(0.0, 0.0, -9.81))
    data["unbalances"] = []
    model = rdm.Model.from_dict(data)
    res = rdm.simulate(model, 0.01, 100.0, initial="equilibrium", samples=11, rtol=1e-11, atol=1e-16)
    q = res.states[:, :model.dofs.n]
    np.testing.assert_allclose(q[-1], q[0], rtol=0, atol=1e-9 * np.abs(q[0]).max())
    weight = 9.81 * (sum(r.mass for r in model.rotors) + PEDESTAL["pedestal_mass"] + 2.0)
    if casing:
        weight += 9.81 * data["stator"]["mass"]
        held = sum(np.diag(s.stiffness_matrix)[2] * (q[0, 2] + np.cross(q[0, 3:6], np.asarray(s.position) -
                                                                         model.reference_point)[2])
                   for s in model.suspensions)
    else:
        lateral = {name: q[0, rows] for name, rows in model.dofs.pedestals}     # (y, z) per pedestal
        held = PEDESTAL["pedestal_stiffness"][1] * lateral["A"][1] + 8e6 * lateral["G"][1]
        held += res.bearing_forces[0, [b.name for b in model.bearings].index("B"), 2]
    np.testing.assert_allclose(-held, weight, rtol=1e-9)
