"""Generated machines shared by the benchmarks (``bench_bearings.py``, ``bench_scaling.py``).

:func:`gear_chain` is a row of ``count`` rigid rotors, each driving the next through a gear,
each on two flexible bearings (five coordinates per rotor), in a casing on six mounts:
``6 + 5 count`` coordinates. :func:`with_channels` adds an unbalance to every rotor and a few
sensors and excitations (for unbalance responses and FRFs).
"""

from __future__ import annotations

import numpy as np

import rotordyn_modal as rdm

__all__ = ["bearing_pair", "gear_chain", "gear_chain_description", "with_channels"]


def bearing_pair(rotor, spin_axis, offsets, stiffness, damping, axial):
    """Two bearings of ``rotor`` at its centre of mass + ``offsets`` [m] along the spin axis;
    the first (drive end) also locates the rotor axially."""
    centre = np.asarray(rotor["center_of_mass"], dtype=float)
    pair = []
    for side, offset in zip(("DE", "NDE"), offsets):
        bearing = {"name": f"{rotor['name']}-{side}", "rotor": rotor["name"],
                   "position": (centre + offset * np.asarray(spin_axis)).tolist(),
                   "stiffness": stiffness, "damping": damping}
        if side == "DE":
            bearing["axial_stiffness"] = axial
        pair.append(bearing)
    return pair



def gear_chain(count: int = 20, seed: int = 1) -> rdm.Model:
    """The machine of :func:`gear_chain_description` as a model."""
    return rdm.Model.from_dict(gear_chain_description(count, seed))


def gear_chain_description(count: int = 20, seed: int = 1) -> dict:
    """``count`` rotors in a row (0.3 m apart along y, spinning about x), each driving
    the next through a gear (ratios 0.8-1.25, so every rotor turns at 0.6-1.6 x the first),
    each on two bearings (1e7-5e7 N/m, 1e-4 s x k damping), in a casing twice their mass on
    six mounts. Masses, inertias and bearing spans drawn from ``seed``."""
    rng = np.random.default_rng(seed)
    pitch, spin_axis = 0.3, [1.0, 0.0, 0.0]
    rotors, bearings, gears = [], [], []
    log_speed = 0.0
    for j in range(count):
        mass = rng.uniform(5.0, 30.0)
        polar = mass * rng.uniform(0.002, 0.01)
        rotor = {"name": f"r{j:02d}", "mass": mass,
                 "center_of_mass": [rng.uniform(-0.1, 0.1), (j - (count - 1) / 2) * pitch, 0.2],
                 "polar_inertia": polar, "diametral_inertia": polar * rng.uniform(0.6, 2.0)}
        if j == 0:
            rotor["speed_ratio"] = 1.0
        else:  # ratio = |w_driver| / |w_driven|, kept so that |w_j| stays within 0.6..1.6
            step = float(np.clip(rng.uniform(-0.22, 0.22), -0.5 - log_speed, 0.5 - log_speed))
            log_speed += step
            gears.append({"type": "gear", "driver": f"r{j - 1:02d}", "driven": rotor["name"],
                          "ratio": float(np.exp(-step))})
        rotors.append(rotor)
        k = rng.uniform(1e7, 5e7)
        offsets = (rng.uniform(0.08, 0.15), -rng.uniform(0.08, 0.15))
        bearings += bearing_pair(rotor, spin_axis, offsets, k, 1e-4 * k, 0.5 * k)
    casing = 2 * sum(r["mass"] for r in rotors)
    length, width, height = count * pitch, 0.6, 0.4
    inertia = casing / 12 * np.diag([length**2 + height**2, width**2 + height**2, length**2 + width**2])
    mounts = [{"name": f"mount-{i}", "position": [x, y, -0.1], "stiffness": [3e6, 3e6, 6e6],
               "damping": [1e3, 1e3, 2e3]}
              for i, (x, y) in enumerate((x, y) for y in (length / 2, 0.0, -length / 2) for x in (0.3, -0.3))]
    return {
        "name": f"{count} rotors chained by gears on flexible bearings in a casing on mounts",
        "spin_axis": spin_axis, "reference_rotor": "r00",
        "stator": {"mass": casing, "center_of_mass": [0.0, 0.0, 0.1], "inertia": inertia.tolist()},
        "rotors": rotors, "transmissions": gears, "bearings": bearings, "suspensions": mounts,
    }


def with_channels(data: dict, seed: int = 2) -> dict:
    """``data`` (a :func:`gear_chain_description`) with an unbalance on every rotor (1e-5 to
    1e-4 kg m, random phase), a vertical and a lateral accelerometer on the casing, a probe
    pair at the first and at the last rotor, a vertical force on the casing and a lateral
    force on the first rotor."""
    rng = np.random.default_rng(seed)
    data = dict(data)
    rotors = data["rotors"]
    data["unbalances"] = [{"rotor": r["name"], "amount": float(rng.uniform(1e-5, 1e-4)),
                           "phase_deg": float(rng.uniform(0.0, 360.0))} for r in rotors]
    first, last = rotors[0], rotors[-1]
    data["sensors"] = [
        {"name": "casing-z", "position": [0.0, 0.0, 0.3], "direction": [0.0, 0.0, 1.0]},
        {"name": "casing-y", "position": [0.3, 0.0, 0.1], "direction": [0.0, 1.0, 0.0]},
    ] + [{"name": f"{r['name']}-{axis}", "position": list(r["center_of_mass"]), "direction": direction,
          "rotor": r["name"]}
         for r in ({first["name"]: first, last["name"]: last}).values()
         for axis, direction in (("y", [0.0, 1.0, 0.0]), ("z", [0.0, 0.0, 1.0]))]
    data["excitations"] = [
        {"name": "hammer-z", "position": [0.1, 0.0, 0.3], "direction": [0.0, 0.0, 1.0]},
        {"name": "tap-y", "position": list(first["center_of_mass"]), "direction": [0.0, 1.0, 0.0],
         "rotor": first["name"]},
    ]
    return data
