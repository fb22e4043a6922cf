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

* ``friswell_5_9_4``, ``ball_roller_mixed``, ``damping_geometry``, ``tables_linear_tapered``
  (``tests/test_ross_more28.py``): Friswell's Example 5.9.4 as ROSS's tests build it (disks
  from geometry, kxy alone); ball and roller bearings with two materials (one by Poisson's
  ratio), a hollow span and two disks on one node; ``rotor_example_with_damping``'s 33
  unequal elements and inboard bearings without its proportional damping; Euler-Bernoulli
  tapered hollow elements with tables not linear in speed saved with ``interpolation="linear"``
  (a bearing with ``kzz``, a seal over ``frequency``), so both codes agree between table speeds.

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


# redteam28 (issue 28): four more rotors, tests/test_ross_more28.py

def friswell_5_9_4():
    """ROSS tests/test_examples.py rotor_example6(6): Friswell 5.9.4, kxy = 5e5 only, disks from geometry."""
    n_el = 6
    shaft = [rs.ShaftElement(L=1.5 / n_el, material=rs.materials.steel, n=i, idl=0, odl=0.05) for i in range(n_el)]
    d0 = rs.DiskElement.from_geometry(n=int(n_el / 1.5 * 0.5), material=rs.materials.steel, width=0.07, i_d=0.05, o_d=0.28)
    d1 = rs.DiskElement.from_geometry(n=int(n_el / 1.5), material=rs.materials.steel, width=0.07, i_d=0.05, o_d=0.35)
    b0 = rs.BearingElement(n=0, kxx=1e6, kyy=1e6, cxx=0, kxy=5e5, cyy=0)
    b1 = rs.BearingElement(n=n_el, kxx=1e6, kyy=1e6, cxx=0, kxy=5e5, cyy=0)
    return rs.Rotor(shaft, [d0, d1], [b0, b1])


def ball_roller_mixed():
    """Ball and roller bearings (ROSS computes their coefficients), two materials (one given by
    Poisson), a hollow section, two disks on one node, a disk from geometry."""
    alu = rs.Material(name="alu_p", rho=2700.0, E=7.0e10, Poisson=0.33)
    shaft = [rs.ShaftElement(0.1, 0.0, 0.05, material=rs.materials.steel, n=i) for i in range(3)]
    shaft += [rs.ShaftElement(0.12, 0.02, 0.06, material=alu, n=3 + i) for i in range(3)]
    shaft += [rs.ShaftElement(0.1, 0.0, 0.05, material=rs.materials.steel, n=6 + i) for i in range(3)]
    disks = [rs.DiskElement.from_geometry(n=2, material=rs.materials.steel, width=0.05, i_d=0.05, o_d=0.25, tag="g"),
             rs.DiskElement(n=5, m=3.0, Id=0.01, Ip=0.018, tag="a"),
             rs.DiskElement(n=5, m=1.5, Id=0.004, Ip=0.007, tag="b")]
    bearings = [rs.BallBearingElement(n=1, n_balls=8, d_balls=0.012, fs=400.0, alpha=np.pi / 9, tag="ball"),
                rs.RollerBearingElement(n=8, n_rollers=10, l_rollers=0.015, fs=600.0, alpha=0.0, tag="roller")]
    return rs.Rotor(shaft, disks, bearings)


def damping_geometry():
    """ROSS's rotor_example_with_damping without its proportional damping (alpha = beta = 0):
    33 unequal elements, bearings inboard at nodes 4 and 31 (overhung ends), kyy/kxx = 115."""
    steel2 = rs.Material(name="Steel2", rho=7850, E=2.17e11, G_s=81.2e9)
    pos = np.array([0, 25, 64, 104, 124, 143, 175, 207, 239, 271, 303, 335, 345, 355, 380, 408, 436,
                    466, 496, 526, 556, 586, 614, 647, 657, 667, 702, 737, 772, 807, 842, 862, 881, 914]) * 1e-3
    shaft = [rs.ShaftElement(l, 0, 0.019, material=steel2, rotary_inertia=True, shear_effects=True)
             for l in np.diff(pos)]
    m, Id, Ip = 2.6375, 0.003844540885417, 0.007513248437500
    disks = [rs.DiskElement(n=12, m=m, Id=Id, Ip=Ip), rs.DiskElement(n=24, m=m, Id=Id, Ip=Ip)]
    b0 = rs.BearingElement(n=4, kxx=4.40e5, kyy=4.6114e5, cxx=27.4, cyy=2.505, kzz=0, czz=0)
    b1 = rs.BearingElement(n=31, kxx=9.50e5, kyy=1.09e8, cxx=50.4, cyy=100.4553, kzz=0, czz=0)
    return rs.Rotor(shaft, disks, [b0, b1])


#: the table speeds of tables_linear_tapered [rad/s]
SPEED = np.array([0.0, 300.0, 700.0, 1200.0, 2000.0])


def tables_linear_tapered():
    """Euler-Bernoulli, tapered hollow elements; a bearing whose tables are NOT linear in speed,
    with interpolation='linear' (so between table speeds both codes interpolate linearly), a
    seal with cross-coupling on a frequency axis, a bearing with axial stiffness kzz."""
    mat = rs.Material(name="steel_q", rho=7850.0, E=2.1e11, G_s=8.1e10)
    geo = [(0.08, 0.0, 0.04, 0.0, 0.04), (0.08, 0.0, 0.04, 0.01, 0.06), (0.10, 0.01, 0.06, 0.01, 0.06),
           (0.10, 0.01, 0.06, 0.01, 0.06), (0.10, 0.01, 0.06, 0.0, 0.045), (0.08, 0.0, 0.045, 0.0, 0.045),
           (0.08, 0.0, 0.045, 0.0, 0.045)]
    shaft = [rs.ShaftElement(L, idl, odl, idr, odr, material=mat, shear_effects=False) for L, idl, odl, idr, odr in geo]
    disks = [rs.DiskElement(n=3, m=7.0, Id=0.03, Ip=0.05), rs.DiskElement(n=7, m=2.0, Id=0.004, Ip=0.006)]
    k = 2e7 * (1 + 0.5 * np.sqrt(SPEED / 2000.0))
    bearing = rs.BearingElement(n=1, kxx=k, kyy=1.3 * k, kxy=0.1 * k, kyx=-0.12 * k, cxx=800.0 - 0.1 * SPEED,
                                cyy=900.0 - 0.05 * SPEED ** 1.2 / 10, speed=SPEED, interpolation="linear",
                                kzz=1e7, czz=0.0, tag="tab")
    seal = rs.SealElement(n=5, kxx=3e6 + 1e3 * SPEED, kyy=3e6 + 1e3 * SPEED, kxy=2e3 * SPEED, kyx=-2e3 * SPEED,
                          cxx=200.0 + 0 * SPEED, cyy=200.0 + 0 * SPEED, frequency=SPEED, interpolation="linear",
                          tag="seal")
    b2 = rs.BearingElement(n=6, kxx=1.5e7, kyy=1.5e7, cxx=500.0, tag="plain")
    return rs.Rotor(shaft, disks, [bearing, seal, b2])


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
    "friswell_5_9_4": (friswell_5_9_4, [0.0, 100.0, 200.0, 300.0, 4000 * np.pi / 30, 600.0, 800.0], 4, [50.0, 86.0, 150.0, 300.0, 600.0]),
    "ball_roller_mixed": (ball_roller_mixed, [0.0, 500.0, 1000.0, 1500.0, 2000.0, 3000.0], 5, [100.0, 400.0, 900.0, 1500.0]),
    "damping_geometry": (damping_geometry, [0.0, 50.0, 100.0, 200.0, 300.0, 450.0, 600.0], 12, [30.0, 90.0, 200.0, 400.0]),
    "tables_linear_tapered": (tables_linear_tapered, [0.0, 75.0, 150.0, 300.0, 500.0, 700.0, 950.0, 1200.0, 1450.0, 1700.0, 2000.0], 3,
                              [100.0, 450.0, 700.0, 1500.0]),
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
