"""Write the ROSS reference data of tests/data/ross/: rotors saved by ROSS and ROSS's own results.

ROSS (``pip install ross-rotordynamics``) is *not* a dependency of rotordyn_modal; run this in
the separate venv that ``benchmarks/bench_ross.py`` describes::

    ~/.pyenv/versions/3.13.0/bin/python -m venv /work/venvs/ross   # ROSS 3.x needs Python 3.13
    /work/venvs/ross/bin/pip install ross-rotordynamics
    /work/venvs/ross/bin/python benchmarks/ross_reference.py [--out tests/data/ross]

For each rotor it writes ``NAME.toml`` (ROSS's ``Rotor.save``) and ``NAME.json``: the ROSS
version, the element options ROSS used, ROSS's totals (mass, centre of mass, polar and
diametral inertia, node positions), the lateral modes of ``run_modal(speed, sparse=False)``
(all roots, dense) at several speeds, and one ``run_unbalance_response``. The rotors:

* ``rotor_example``: ROSS's ``rotor_example()`` (6 uniform Timoshenko elements, 2 disks,
  2 bearings, Cowper's shear coefficient);
* ``compressor_example``: ROSS's ``compressor_example()`` (91 elements over 55 spans: mass-only
  sleeves over the shaft, 7 disks, 2 bearings and 12 seals with coefficient tables over speed);
* ``tapered_hollow``: hollow and tapered (conical, hollow) elements (Cowper's shear coefficient:
  ROSS's ``"hutchinson"`` is not Hutchinson's, ``docs/ross.md``), two disks, cross-coupled
  damped bearings at overhung positions;
* ``bearing_and_seal``: an overhung rotor on one bearing, held in tilt by a seal at another node
  (ROSS's bearings and seals hold translations only: a rotor on bearings at one node is free to
  tilt, which ROSS solves and this package refuses, docs/ross.md);
* ``speed_tables``: an Euler-Bernoulli shaft (``shear_effects=False``) with an overhung disk on
  bearings whose coefficients are tables over speed, linear in speed (so ROSS's PCHIP
  interpolation and this package's linear interpolation give the same coefficient at every
  speed), with a cross-coupled stiffness that grows with speed (negative log decrements above
  an onset).

``rotor_example_with_damping.toml`` is saved too, without results: its proportional damping
(``alpha``, ``beta``) is what the reader refuses.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent

#: modes kept per speed (the lowest lateral ones)
N_MODES = 16
#: lateral motions of a ROSS node: x, y, alpha, beta (of x, y, z, alpha, beta, theta)
LATERAL = (0, 1, 3, 4)


def quiet_import():
    """Import ROSS with its REFPROP notices (printed by ccp at import) silenced."""
    import contextlib
    import io
    import os

    saved = os.dup(1), os.dup(2)
    with open(os.devnull, "w") as null, contextlib.redirect_stdout(io.StringIO()):
        os.dup2(null.fileno(), 1)
        os.dup2(null.fileno(), 2)
        try:
            import ross
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
    return ross


rs = quiet_import()


def tapered_hollow():
    """Hollow and tapered elements, overhung cross-coupled bearings."""
    steel = rs.Material(name="steel_t", rho=7850.0, E=2.05e11, Poisson=0.29)
    # (L, idl, odl, idr, odr): a hollow shaft whose middle swells conically
    geometry = [
        (0.06, 0.015, 0.040, 0.015, 0.040),
        (0.08, 0.015, 0.040, 0.015, 0.040),
        (0.10, 0.015, 0.040, 0.020, 0.060),
        (0.10, 0.020, 0.060, 0.020, 0.060),
        (0.10, 0.020, 0.060, 0.020, 0.060),
        (0.10, 0.020, 0.060, 0.015, 0.045),
        (0.08, 0.015, 0.045, 0.015, 0.045),
        (0.06, 0.015, 0.045, 0.0, 0.045),
    ]
    shaft = [rs.ShaftElement(L, idl, odl, idr, odr, material=steel, shear_method_calc="cowper")
             for L, idl, odl, idr, odr in geometry]
    disks = [rs.DiskElement(n=3, m=6.5, Id=0.021, Ip=0.038),
             rs.DiskElement(n=5, m=4.0, Id=0.012, Ip=0.022)]
    bearings = [
        rs.BearingElement(n=1, kxx=2.0e7, kyy=3.0e7, kxy=1.5e6, kyx=-2.5e6, cxx=900.0, cyy=1100.0,
                          cxy=40.0, cyx=-60.0),
        rs.BearingElement(n=7, kxx=1.5e7, kyy=1.2e7, kxy=-0.8e6, kyx=1.1e6, cxx=700.0, cyy=650.0),
    ]
    return rs.Rotor(shaft, disks, bearings)


def speed_tables():
    """Euler-Bernoulli shaft, overhung disk, bearing tables linear in speed."""
    steel = rs.Material(name="steel_e", rho=7800.0, E=2.0e11, G_s=7.7e10)
    shaft = [rs.ShaftElement(0.07, 0.0, 0.05, material=steel, shear_effects=False) for _ in range(10)]
    disks = [rs.DiskElement(n=10, m=8.0, Id=0.035, Ip=0.06)]
    speed = np.array([0.0, 400.0, 800.0, 1200.0, 1600.0])  # rad/s

    def linear(at_zero, per_rad_s):
        return at_zero + per_rad_s * speed

    bearings = [
        rs.BearingElement(n=i, kxx=linear(k, 2.0e3), kyy=linear(1.2 * k, 2.5e3),
                          kxy=linear(0.0, 1.2e3), kyx=linear(0.0, -1.2e3),
                          cxx=linear(600.0, -0.1), cyy=linear(700.0, -0.12),
                          cxy=linear(0.0, 0.02), cyx=linear(0.0, -0.02), speed=speed)
        for i, k in ((0, 4.0e6), (7, 6.0e6))
    ]
    return rs.Rotor(shaft, disks, bearings)


def bearing_and_seal():
    """One bearing: an overhung rotor held by one BearingElement and, at another node, one
    SealElement (cross-coupled, damped): the seal is the second support that holds it in tilt
    (ROSS's bearings and seals hold translations only)."""
    steel = rs.Material(name="steel_s", rho=7810.0, E=2.11e11, G_s=8.12e10)
    shaft = [rs.ShaftElement(0.12, 0.0, 0.045, material=steel, shear_method_calc="cowper") for _ in range(7)]
    disks = [rs.DiskElement(n=7, m=9.0, Id=0.04, Ip=0.07), rs.DiskElement(n=3, m=2.5, Id=0.006, Ip=0.01)]
    bearings = [rs.BearingElement(n=1, kxx=3.0e7, kyy=2.5e7, cxx=800.0, cyy=900.0, tag="bearing"),
                rs.SealElement(n=5, kxx=4.0e6, kyy=4.0e6, kxy=6.0e5, kyx=-6.0e5, cxx=300.0, cyy=300.0,
                               tag="seal")]
    return rs.Rotor(shaft, disks, bearings)


#: name: (builder, speeds [rad/s] of run_modal, unbalance node, unbalance speeds [rad/s])
ROTORS = {
    "rotor_example": (rs.rotor_example, [0.0, 300.0, 1000.0, 3000.0],
                      2, [50.0, 91.0, 200.0, 400.0, 800.0]),
    # every table of the compressor holds 6000, 8000 and 10000 rpm: its coefficients there are
    # table points, not interpolated (4000 rpm is a point too, but some seals' tables start a
    # rounding above it: 418.8790204788 rad/s)
    "compressor_example": (rs.compressor_example, [w * np.pi / 30 for w in (6000.0, 8000.0, 10000.0)],
                           26, [w * np.pi / 30 for w in (6000.0, 8000.0, 10000.0)]),
    "tapered_hollow": (tapered_hollow, [0.0, 500.0, 1500.0, 3000.0], 3, [100.0, 400.0, 900.0, 1500.0]),
    "speed_tables": (speed_tables, [0.0, 400.0, 1000.0, 1600.0], 10, [100.0, 300.0, 700.0, 1200.0]),
    "bearing_and_seal": (bearing_and_seal, [0.0, 500.0, 1500.0, 3000.0], 7, [100.0, 400.0, 900.0, 1500.0]),
}


def element_options(rotor) -> dict:
    """The distinct values of ROSS's element options over the rotor's shaft elements."""
    keys = ("shear_effects", "rotary_inertia", "gyroscopic", "shear_method_calc")
    return {k: sorted({getattr(el, k) for el in rotor.shaft_elements}, key=str) for k in keys}


def totals(rotor) -> dict:
    """ROSS's own totals of the rotor."""
    return {
        "m": float(rotor.m), "m_shaft": float(rotor.m_shaft), "m_disks": float(rotor.m_disks),
        "CG": float(rotor.CG), "Ip": float(rotor.Ip), "It": float(rotor.It), "L": float(rotor.L),
        "nodes_pos": [float(z) for z in rotor.nodes_pos], "ndof": int(rotor.ndof),
        "n_shaft_elements": len(rotor.shaft_elements), "n_disks": len(rotor.disk_elements),
        "n_bearings": len(rotor.bearing_elements),
    }


def lateral_modes(rotor, speed: float) -> dict:
    """The lowest lateral modes of ``run_modal(speed, sparse=False)``: those whose eigenvector
    has no axial or torsional part (ROSS's lateral and axial/torsional motions decouple)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        modal = rotor.run_modal(speed, num_modes=2 * rotor.ndof, sparse=False)
    v = np.asarray(modal.evectors)[: rotor.ndof]
    lateral = np.zeros(rotor.ndof, bool)
    for k in LATERAL:
        lateral[k:: rotor.number_dof] = True
    other = np.linalg.norm(v[~lateral], axis=0) / np.linalg.norm(v, axis=0)
    keep = np.flatnonzero(other[: len(modal.wn)] < 1e-6)[:N_MODES]
    whirl = np.asarray(modal.whirl_direction())
    return {
        "speed": float(speed),
        "wn": [float(x) for x in np.asarray(modal.wn)[keep]],
        "wd": [float(x) for x in np.asarray(modal.wd)[keep]],
        "log_dec": [float(x) for x in np.asarray(modal.log_dec)[keep]],
        "whirl": [str(x) for x in whirl[keep]],
        "eigenvalues_re": [float(x) for x in np.asarray(modal.evalues)[keep].real],
        "eigenvalues_im": [float(x) for x in np.asarray(modal.evalues)[keep].imag],
    }


def unbalance(rotor, node: int, speeds) -> dict:
    """``run_unbalance_response(node, 1e-4 kg m, phase 0.3 rad, speeds)``: the complex x and y
    amplitudes at every node, per speed (ROSS: force x = m e w^2 e^{i phase},
    y = -i m e w^2 e^{i phase}, response q e^{i w t})."""
    magnitude, phase = 1e-4, 0.3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_unbalance_response(node, magnitude, phase, np.asarray(speeds, float))
    q = np.asarray(result.forced_resp)  # (ndof, n speeds)
    n = rotor.number_dof
    nodes = len(rotor.nodes_pos)
    x, y = q[0: n * nodes: n], q[1: n * nodes: n]  # (nodes, speeds)
    return {
        "node": node, "magnitude_kg_m": magnitude, "phase_rad": phase,
        "speeds": [float(s) for s in speeds],
        "x_re": x.real.T.tolist(), "x_im": x.imag.T.tolist(),
        "y_re": y.real.T.tolist(), "y_im": y.imag.T.tolist(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO / "tests" / "data" / "ross")
    parser.add_argument("--only", nargs="*", choices=sorted(ROTORS), help="these rotors only")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    import scipy

    about = {"ross_version": rs.__version__, "python": platform.python_version(),
             "numpy": np.__version__, "scipy": scipy.__version__,
             "script": "benchmarks/ross_reference.py"}
    only = set(args.only or ROTORS)
    for name, (build, speeds, node, unbalance_speeds) in ROTORS.items():
        if name not in only:
            continue
        rotor = build()
        toml = args.out / f"{name}.toml"
        toml.unlink(missing_ok=True)  # Rotor.save adds to an existing file
        rotor.save(toml)
        data = {**about, "rotor": name, "units": "SI; speeds and frequencies rad/s",
                "element_options": element_options(rotor), "totals": totals(rotor),
                "run_modal": "run_modal(speed, num_modes=2*ndof, sparse=False): every root, lateral ones kept",
                "modal": [lateral_modes(rotor, s) for s in speeds],
                "unbalance": unbalance(rotor, node, unbalance_speeds)}
        (args.out / f"{name}.json").write_text(json.dumps(data, indent=1) + "\n")
        print(f"{name}: {rotor.ndof} DOF, m = {rotor.m:.6g} kg, first lateral "
              f"{data['modal'][0]['wn'][:4]} rad/s", file=sys.stderr)
    extra = args.out / "rotor_example_with_damping.toml"
    extra.unlink(missing_ok=True)
    rs.rotor_example_with_damping().save(extra)


if __name__ == "__main__":
    main()
