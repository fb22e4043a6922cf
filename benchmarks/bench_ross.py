"""Side-by-side with ROSS: a rigid rotor on two isotropic bearings, and ROSS's flexible rotors
read from their saved files; accuracy and Campbell speed.

ROSS (https://ross.readthedocs.io/, ``pip install ross-rotordynamics``) is *not* a
dependency of rotordyn_modal; this script runs in a separate venv where both import::

    ~/.pyenv/versions/3.13.0/bin/python -m venv /work/venvs/ross   # ROSS 3.x needs Python 3.13
    /work/venvs/ross/bin/pip install ross-rotordynamics
    /work/venvs/ross/bin/python benchmarks/bench_ross.py [--repeat 3] [--repeat-long 1] [--figure]
        [--part rigid|flexible|both] [--flexible-speeds 21,201] [--rotors NAME ...]

rotordyn_modal is imported from this checkout (the repository root is put on ``sys.path``)
unless it is already installed in that venv. Without ROSS the script says so and exits 0.

The machine: a steel shaft (L = 0.5 m, d = 0.1 m, 2 Timoshenko elements in ROSS) carrying a
disk at mid-span, on two isotropic bearings k = 1e6 N/m at its ends (axial positions +-a,
a = L/2), spinning about its axis, no damping. rotordyn_modal models it as one rigid rotor
whose mass, polar and diametral inertia are the totals of ROSS's disk + shaft, in two ways
that must give the same frequencies:

* ``[[bearings]]``: the rotor on two bearings at +-a to the ground (no ``[stator]``); its
  coordinates are its two lateral translations and two tilts (4 DOF, 8 states);
* suspensions: the rotor rigidly on a massless frame (no ``[stator]``, no bearings) held by
  two suspensions at +-a (6 DOF; small axial and roll stiffness, which ROSS leaves free).

The 4 lateral rigid-body modes have closed forms:

* cylindrical (twice): w = sqrt(2 k / m)
* conical: w = (Omega Jp +- sqrt((Omega Jp)^2 + 4 Jt kt)) / (2 Jt), kt = 2 a^2 k

rotordyn_modal should equal them to rounding; ROSS (a flexible shaft) should approach them
as the shaft's E (and G) grows, which the script shows for E x 1, 10, 100, 1000.

Flexible rotors (``--part flexible``): the four rotors of ``tests/data/ross`` (ROSS's
``rotor_example`` and ``compressor_example``, a tapered hollow rotor, a rotor on bearings
tabulated over speed; ``benchmarks/ross_reference.py``), loaded in ROSS with ``Rotor.load``
and in rotordyn_modal with ``rotordyn_modal.io.ross_file.read_ross_rotor`` from the same
file. Per rotor: the largest relative difference of ROSS's lateral roots (dense
``run_modal`` at the reference speeds) to rotordyn_modal's, the largest difference of their
log decrements, and the Campbell time per speed of both (ROSS ``run_campbell(speeds,
frequencies=12)``; ``rdm.campbell(model, speeds, critical=False)`` of all modes, and with ``modes=12`` (the
lowest 12 only) where it offers that) as ratios from one run: the three are timed in turn
``--repeat`` times, and the ratios' min / median / max printed (once per count of
``--flexible-speeds``, default 21 and 201: a call's fixed cost, the reduced basis and its
completeness checks, weighs most on a coarse sweep, while ROSS's cost per speed does not fall
with the count; a closing line per count gives the median ratios against issue 28's 50x), with the largest relative
difference of the lowest 12 roots from the 12 lowest of all modes ("low vs all"). Where the
package has the Hermitian route of small undamped gyroscopic models (``_lowest._gyroscopic_lowest``),
each repeat also times ``modes=12`` with that route switched off (``eigvals`` of the state
matrices, the route before it): a baseline from the same run, printed under the rotor's row as
its time per speed, ROSS / it, and it / the lowest 12 (min/median/max). The same calls' CPU times (``time.process_time``: every thread of
the process, so rotordyn_modal's second thread counts against it) give a second ratio, ROSS / the
lowest 12, which other processes' load sways less than the wall times; each timed call follows an
untimed pause of ``_SETTLE_SECONDS``, so that the threads of the call before it, spinning a while
on a free core, are not charged to it. rotordyn_modal keeps a small model's speed-independent parts
between analyses of the same model object (``analysis._stack.model_constants``), as ROSS's ``Rotor``
builds its ``M0``, ``K0``, ``G0`` when it is made: the timed calls reuse one model, and one more line
per rotor times the first call on a fresh model (made untimed, as ROSS's ``Rotor``), which makes
them. Without flexible rotors in rotordyn_modal (a checkout
before them) the script says so and keeps the rigid comparison.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _timing import best_time  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

REPO = Path(__file__).resolve().parent.parent

# --------------------------------------------------------------------------- imports


@contextlib.contextmanager
def _quiet():
    """Silence C-level and Python output (ROSS's ccp dependency prints REFPROP notices)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(os.devnull, "w") as null:
        os.dup2(null.fileno(), 1)
        os.dup2(null.fileno(), 2)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                yield
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


try:
    with _quiet():
        import ross as rs
except ImportError:
    print(
        "ross is not installed in this interpreter; nothing to compare. To run the comparison:\n"
        "  ~/.pyenv/versions/3.13.0/bin/python -m venv /work/venvs/ross\n"
        "  /work/venvs/ross/bin/pip install ross-rotordynamics\n"
        f"  /work/venvs/ross/bin/python {Path(__file__).resolve()}"
    )
    sys.exit(0)

try:
    import rotordyn_modal as rdm
except ImportError:
    sys.path.insert(0, str(REPO))
    import rotordyn_modal as rdm

# --------------------------------------------------------------------------- machine

L = 0.5  # shaft length [m]; bearings at both ends
D = 0.1  # shaft diameter [m]
A = L / 2  # bearing half-span [m]
K = 1.0e6  # bearing stiffness [N/m], each, isotropic
DISK_M, DISK_ID, DISK_IP = 20.0, 0.2, 0.35  # [kg], [kg m^2]
RHO, E, G = 7810.0, 211e9, 81.2e9  # steel
N_EL = 2  # shaft elements (disk on the middle node)

SPEEDS_RPM = (0.0, 1000.0, 3000.0, 6000.0, 10000.0)
E_SCALES = (1.0, 10.0, 100.0, 1000.0)
MODES = ("cyl", "con-bw", "con-fw")


def ross_rotor(e_scale: float = 1.0, n_el: int = N_EL):
    steel = rs.Material(name=f"steel_x{e_scale:g}", rho=RHO, E=E * e_scale, G_s=G * e_scale)
    shaft = [rs.ShaftElement(L / n_el, idl=0.0, odl=D, material=steel) for _ in range(n_el)]
    disk = rs.DiskElement(n=n_el // 2, m=DISK_M, Id=DISK_ID, Ip=DISK_IP)
    bearings = [rs.BearingElement(n=0, kxx=K, cxx=0.0), rs.BearingElement(n=n_el, kxx=K, cxx=0.0)]
    return rs.Rotor(shaft, [disk], bearings)


def rigid_properties():
    """Total mass, polar and diametral inertia of disk + shaft about the centre (analytic)."""
    m_shaft = RHO * np.pi * D**2 / 4 * L
    mass = DISK_M + m_shaft
    jp = DISK_IP + m_shaft * D**2 / 8
    jd = DISK_ID + m_shaft * (L**2 / 12 + D**2 / 16)
    return mass, jp, jd


def ross_rigid_projection(rotor):
    """ROSS's own M and G projected on the 4 lateral rigid-body motions: (m, Jd, Jp)."""
    n = rotor.number_dof  # 6 per node in ROSS 3: x, y, z, alpha, beta, theta
    T = np.zeros((rotor.ndof, 4))
    for i, z in enumerate(rotor.nodes_pos):
        zc = float(z) - L / 2
        T[n * i + 0, 0] = 1.0  # x translation
        T[n * i + 1, 1] = 1.0  # y translation
        T[n * i + 0, 2], T[n * i + 4, 2] = zc, 1.0  # tilt: x = zc beta
        T[n * i + 1, 3], T[n * i + 3, 3] = -zc, 1.0  # tilt: y = -zc alpha
    Mr = T.T @ rotor.M(0.0) @ T
    Gr = T.T @ rotor.G() @ T
    return Mr[0, 0], Mr[2, 2], abs(Gr[2, 3])


def rdm_model_bearings(mass, jp, jd):
    """The rigid rotor on two ``[[bearings]]`` to the ground: 4 lateral coordinates."""
    return rdm.Model.from_dict({
        "name": "rigid rotor on two bearings (ROSS comparison)",
        "rotors": [{"name": "rotor", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": jp, "diametral_inertia": jd, "speed_ratio": 1.0}],
        "bearings": [{"name": "brg-A", "rotor": "rotor", "position": [-A, 0.0, 0.0], "stiffness": K},
                     {"name": "brg-B", "rotor": "rotor", "position": [A, 0.0, 0.0], "stiffness": K}],
    })


def rdm_model_suspensions(mass, jp, jd):
    """The rigid rotor on a massless frame held by two suspensions: 6 coordinates."""
    # axial and torsional directions: small stiffness (ROSS leaves them free); only the 4
    # lateral modes are compared
    stiff = [1e2, K, K, 1e-2, 0.0, 0.0]
    return rdm.Model(
        name="rigid rotor on two suspensions (ROSS comparison)",
        rotors=[rdm.Rotor("rotor", mass, [0.0, 0.0, 0.0], jp, jd, speed_ratio=1.0)],
        suspensions=[
            rdm.Suspension("brg-A", [-A, 0.0, 0.0], stiff),
            rdm.Suspension("brg-B", [A, 0.0, 0.0], stiff),
        ],
    )


def closed_form(speed, mass, jp, jd):
    """(cylindrical, conical backward, conical forward) [rad/s] at spin speed [rad/s]."""
    speed = np.asarray(speed, dtype=float)
    kt = 2 * A**2 * K
    root = np.sqrt((speed * jp) ** 2 + 4 * jd * kt)
    cyl = np.sqrt(2 * K / mass) * np.ones_like(speed)
    return cyl, (root - speed * jp) / (2 * jd), (root + speed * jp) / (2 * jd)


# --------------------------------------------------------------------------- classification


def rotor_energies(model, shapes, mass, jd):
    """Mass-weighted square motion of the rotor in lateral translation, tilt and the rest
    (axial, roll), per shape: three arrays shaped like ``shapes[..., 0]``.

    The shapes are over ``model.dofs.names`` (the frame's six motions, or the rotor's own
    ``rotor.uy, rotor.uz, rotor.ry, rotor.rz`` on bearings); the rotor's motion
    ``[u, theta]`` at its centre (the origin, the models' reference point) is
    ``model.dofs.body_motion("rotor") @ shape``.
    """
    assert np.allclose(model.dofs.reference_point, 0.0)
    s = np.abs(np.asarray(shapes) @ model.dofs.body_motion("rotor").T) ** 2  # ux uy uz thx thy thz
    trans, rot = mass * (s[..., 1] + s[..., 2]), jd * (s[..., 4] + s[..., 5])
    return trans, rot, mass * s[..., 0] + jd * s[..., 3]


def rdm_lateral(model, result, mass, jd):
    """Frequencies [rad/s] of rotordyn_modal's lateral modes: dict cyl (2), con-bw, con-fw."""
    w = 2 * np.pi * np.asarray(result.frequencies_hz)
    trans, rot, other = rotor_energies(model, result.shapes, mass, jd)
    cyl = np.sort(w[(trans > rot) & (trans > other)])
    con = np.sort(w[(rot > trans) & (rot > other)])
    assert cyl.size == 2 and con.size == 2, (cyl, con)
    return {"cyl": cyl, "con-bw": con[0], "con-fw": con[1]}


def ross_lateral(modal, rotor):
    """The 4 lowest ROSS modes, split into cylindrical / conical by the mid-span node."""
    w = np.asarray(modal.wd)[:4]
    c = (len(rotor.nodes_pos) // 2) * rotor.number_dof
    v = np.abs(np.asarray(modal.evectors)[: rotor.ndof, :4]) ** 2
    mass, jp, jd = rigid_properties()
    trans, rot = mass * (v[c] + v[c + 1]), jd * (v[c + 3] + v[c + 4])
    cyl, con = np.sort(w[trans > rot]), np.sort(w[rot > trans])
    assert cyl.size == 2 and con.size == 2, (w, trans, rot)
    return {"cyl": cyl, "con-bw": con[0], "con-fw": con[1]}


def rel_errors(found, exact):
    cyl, bw, fw = exact
    return (
        float(np.max(np.abs(found["cyl"] - cyl) / cyl)),
        abs(found["con-bw"] - bw) / bw,
        abs(found["con-fw"] - fw) / fw,
    )


def lateral_campbell_rdm(model, camp, mass, jd):
    """(N, 4) sorted lateral frequencies [rad/s] of an rdm Campbell result."""
    trans, rot, other = rotor_energies(model, camp.shapes, mass, jd)
    lateral = trans + rot > other
    assert np.all(lateral.sum(axis=1) == 4)
    w = 2 * np.pi * camp.frequencies_hz
    return np.sort(w[lateral].reshape(len(camp.speeds), 4), axis=1)


# --------------------------------------------------------------------------- main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="best of N (ROSS 1001 speeds: --repeat-long)")
    parser.add_argument("--repeat-long", type=int, default=1, help="best of N for ROSS at 1001 speeds")
    parser.add_argument("--figure", action="store_true", help="write benchmarks/ross_comparison.png")
    parser.add_argument("--part", choices=("rigid", "flexible", "both"), default="both",
                        help="the rigid rotor, the flexible rotors of tests/data/ross, or both (default)")
    parser.add_argument("--flexible-speeds", type=_speed_counts, default=(21, 201),
                        help="speeds of the flexible rotors' Campbell diagrams, one comparison per count, "
                             "comma-separated (default 21,201: a coarse sweep, where the fixed cost of a "
                             "call weighs most, and a Campbell diagram's usual resolution)")
    parser.add_argument("--rotors", nargs="*", choices=FLEXIBLE, default=list(FLEXIBLE),
                        help="flexible rotors compared (default: all)")
    args = parser.parse_args()

    import scipy

    print(
        f"ROSS {rs.__version__}, Python {sys.version.split()[0]}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}; rotordyn_modal from {Path(rdm.__file__).parent}"
    )
    if args.part in ("rigid", "both"):
        rigid_comparison(args)
    if args.part in ("flexible", "both"):
        for n_speeds in args.flexible_speeds:
            flexible_comparison(args.rotors, n_speeds, args.repeat)


def _speed_counts(text: str) -> tuple[int, ...]:
    """``--flexible-speeds``: whole numbers of speeds, at least 3 each, comma-separated."""
    try:
        counts = tuple(int(part) for part in text.split(","))
    except ValueError:
        counts = ()
    if not counts or min(counts) < 3:
        raise argparse.ArgumentTypeError(f"{text!r}: expected whole numbers of speeds >= 3, comma-separated (e.g. 21,201)")
    return counts


def rigid_comparison(args) -> None:
    """The rigid rotor: rotordyn_modal against the closed forms, ROSS as its shaft stiffens,
    Campbell time."""
    mass, jp, jd = rigid_properties()
    rotor1 = ross_rotor(1.0)
    with _quiet():
        start = time.perf_counter()
        rotor1.run_modal(0.0)  # ROSS's first call compiles / caches (numba); timed apart
        warm = time.perf_counter() - start
    pm, pjd, pjp = ross_rigid_projection(rotor1)
    print(
        f"rigid properties: m = {mass:.6f} kg, Jp = {jp:.6f}, Jd = {jd:.6f} kg m^2 "
        f"(ROSS M, G projected on rigid motions: rel. diff {abs(pm - mass) / mass:.1e}, "
        f"{abs(pjp - jp) / jp:.1e}, {abs(pjd - jd) / jd:.1e})"
    )
    models = {"bearings": rdm_model_bearings(mass, jp, jd), "suspensions": rdm_model_suspensions(mass, jp, jd)}
    for name, model in models.items():
        print(f"rotordyn_modal, {name:11s}: coordinates {', '.join(model.dofs.names)}")

    rdm_worst = rdm_accuracy(models, mass, jp, jd)
    ross_table = ross_accuracy(mass, jp, jd)
    whirl_labels(models["bearings"], rotor1)
    print(f"\n(ROSS's first run_modal call, excluded below: {warm:.1f} s; ROSS model: {N_EL} elements, "
          f"{rotor1.ndof} DOF; rotordyn_modal: 4 DOF on [[bearings]], 6 on suspensions)")
    figure_data = campbell_speed(models, mass, jp, jd, args.repeat, args.repeat_long)
    if args.figure:
        write_figure(figure_data, ross_table, rdm_worst)


def rdm_accuracy(models, mass, jp, jd) -> float:
    """Print rdm.modal's lateral frequencies against the closed forms, for both models;
    return the worst relative difference."""
    speeds = np.array(SPEEDS_RPM) * np.pi / 30
    print("\nclosed form [Hz] and rotordyn_modal's relative difference to it (rdm.modal), "
          "rotor on [[bearings]] | on suspensions")
    print(f"{'rpm':>7} | {'cyl':>9} {'con-bw':>9} {'con-fw':>9} | {'cyl':>8} {'con-bw':>8} {'con-fw':>8} |"
          f" {'cyl':>8} {'con-bw':>8} {'con-fw':>8} | bearings vs suspensions")
    worst = between = 0.0
    for rpm, speed in zip(SPEEDS_RPM, speeds):
        exact = closed_form(speed, mass, jp, jd)
        found = {name: rdm_lateral(model, rdm.modal(model, speed), mass, jd) for name, model in models.items()}
        errors = {name: rel_errors(f, exact) for name, f in found.items()}
        worst = max(worst, *errors["bearings"], *errors["suspensions"])
        both = rel_errors(found["bearings"], tuple(found["suspensions"][k] for k in ("cyl", "con-bw", "con-fw")))
        between = max(between, *both)
        hz = [float(x) / (2 * np.pi) for x in exact]
        print(f"{rpm:7.0f} | {hz[0]:9.4f} {hz[1]:9.4f} {hz[2]:9.4f} | "
              + " ".join(f"{e:8.1e}" for e in errors["bearings"]) + " | "
              + " ".join(f"{e:8.1e}" for e in errors["suspensions"]) + f" | {max(both):8.1e}")
    print(f"largest relative difference, [[bearings]] vs suspensions: {between:.1e}")
    return worst


def ross_accuracy(mass, jp, jd) -> dict:
    """Print ROSS's lateral frequencies against the closed forms as the shaft stiffens;
    return {E scale: (speeds, 3) relative differences}."""
    speeds = np.array(SPEEDS_RPM) * np.pi / 30
    print("\nROSS run_modal(speed, sparse=False): relative difference to the closed form")
    print(f"{'E x':>6} {'1st bending Hz':>15} | " + " | ".join(f"{r:>5.0f} rpm: cyl  bw  fw".rjust(30) for r in SPEEDS_RPM[::2]))
    ross_table = {}
    for scale in E_SCALES:
        rotor = ross_rotor(scale)
        rows = []
        for speed in speeds:
            with _quiet():
                modal = rotor.run_modal(speed, num_modes=12, sparse=False)
            rows.append(rel_errors(ross_lateral(modal, rotor), closed_form(speed, mass, jp, jd)))
            if speed == 0:
                bending = float(np.asarray(modal.wd)[4]) / (2 * np.pi)
        ross_table[scale] = np.array(rows)
        cells = [" ".join(f"{e:8.1e}" for e in rows[i]) for i in range(0, len(speeds), 2)]
        print(f"{scale:6g} {bending:15.1f} | " + " | ".join(c.rjust(30) for c in cells))
    print("worst over the speeds " + ", ".join(f"{r:g}" for r in SPEEDS_RPM) + " rpm:")
    for scale in E_SCALES:
        worst = ross_table[scale].max(axis=0)
        print(f"  ROSS E x {scale:<6g}: cyl {worst[0]:.2e}  con-bw {worst[1]:.2e}  con-fw {worst[2]:.2e}")
    ratios = [ross_table[a].max() / ross_table[b].max() for a, b in zip(E_SCALES, E_SCALES[1:])]
    print("  ROSS worst-error ratio per x10 of E: " + ", ".join(f"{r:.1f}" for r in ratios))
    return ross_table


def whirl_labels(model, ross_rotor_1):
    """Whirl of the 4 lateral modes at 3000 rpm (the cylindrical pair is degenerate)."""
    speed = 3000 * np.pi / 30
    res = rdm.modal(model, speed)
    camp = rdm.campbell(model, np.array([0.0, speed]))
    with _quiet():
        ross_modal = ross_rotor_1.run_modal(speed, num_modes=12, sparse=False)
    lateral = np.argsort(res.frequencies_hz)[-4:]
    order_c = np.argsort(camp.frequencies_hz[1])[-4:]
    print("\nwhirl of the 4 lateral modes at 3000 rpm (ascending frequency: cyl, cyl, con-bw, con-fw), "
          "rotor on [[bearings]]")
    print("  rdm.modal   : " + " ".join(f"{w}({r:+.2f})" for w, r in zip(res.whirl[lateral], res.whirl_ratios[lateral])))
    print("  rdm.campbell: " + " ".join(f"{w}({r:+.2f})" for w, r in zip(camp.whirl[1, order_c], camp.whirl_ratios[1, order_c])))
    print("  ROSS        : " + " ".join(str(w) for w in np.asarray(ross_modal.whirl_direction())[:4]))


def campbell_speed(models, mass, jp, jd, repeat, repeat_long):
    """Time ROSS's and rotordyn_modal's Campbell diagrams side by side; return the figure's
    data of the finest grid (speeds, closed form, rdm on bearings, ROSS)."""
    print(f"\nCampbell diagram 0..10000 rpm, best of {repeat} (ROSS at 1001 speeds: best of {repeat_long}); "
          "rdm: rotor on [[bearings]] | on suspensions")
    for model in models.values():
        rdm.campbell(model, np.linspace(0, 100, 3))
    figure_data = None
    for n_speeds in (101, 1001):
        grid = np.linspace(0.0, 10000.0, n_speeds) * np.pi / 30
        rep = repeat if n_speeds <= 101 else repeat_long
        # ROSS memoises run_modal per Rotor instance (methodtools lru_cache, 128 entries):
        # each repetition gets a fresh, identical Rotor, built outside the timed part
        t_ross = np.inf
        for _ in range(rep):
            rotor = ross_rotor(1.0)
            start = time.perf_counter()
            with _quiet():
                ross_campbell = rotor.run_campbell(grid)
            t_ross = min(t_ross, time.perf_counter() - start)
        exact = np.sort(np.column_stack([closed_form(grid, mass, jp, jd)[i] for i in (0, 0, 1, 2)]), axis=1)
        w_ross = np.sort(np.asarray(ross_campbell.wd), axis=1)[:, :4]
        cells, w_rdm = [], {}
        for name, model in models.items():
            t_rdm = best_time(lambda: rdm.campbell(model, grid), max(repeat, 5))
            w_rdm[name] = lateral_campbell_rdm(model, rdm.campbell(model, grid), mass, jd)
            cells.append(f"rdm.campbell {t_rdm * 1e3:6.2f} ms, ROSS / rdm = {t_ross / t_rdm:5.0f}x, "
                         f"max rel. diff {np.max(np.abs(w_rdm[name] - exact) / exact):.1e}")
        print(f"{n_speeds:5d} speeds: ROSS run_campbell {t_ross * 1e3:8.1f} ms ({t_ross / n_speeds * 1e3:.1f} ms/speed, "
              f"max rel. diff to closed form {np.max(np.abs(w_ross - exact) / exact):.1e})\n"
              f"             [[bearings]]: {cells[0]}\n             suspensions: {cells[1]}")
        figure_data = (grid, exact, w_rdm["bearings"], w_ross)
    return figure_data


# --------------------------------------------------------------------------- flexible rotors

#: the rotors of tests/data/ross (benchmarks/ross_reference.py): ROSS's file and its results
FLEXIBLE = ("rotor_example", "compressor_example", "tapered_hollow", "speed_tables")
DATA = REPO / "tests" / "data" / "ross"
#: modes per speed in both Campbell diagrams (ROSS's run_campbell(frequencies=...))
CAMPBELL_MODES = 12


def flexible_missing() -> str | None:
    """Why this checkout's model takes no flexible rotor (None when it does): a bare shaft on
    two bearings as docs/model-file.md writes it."""
    minimal = {
        "name": "capability", "spin_axis": [0.0, 0.0, 1.0],
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "shear_modulus": 8e10}],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0],
                    "shaft": [{"length": 0.5, "outer_diameter": 0.05, "material": "steel"}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z, "stiffness": 1e6}
                     for i, z in enumerate((0.0, 0.5))],
    }
    try:
        rdm.Model.from_dict(minimal)
    except Exception as problem:  # noqa: BLE001 - any refusal means: no flexible rotors here
        text = str(problem)
        return f"{type(problem).__name__}: {text if len(text) <= 160 else '...' + text[-157:]}"
    return None


#: issue 28's target: ROSS's Campbell time over rotordyn_modal's lowest 12 modes' at the same accuracy
TARGET_RATIO = 50


def flexible_comparison(names, n_speeds: int, repeat: int) -> None:
    """ROSS's rotors read by rotordyn_modal.io.ross_file: lateral roots against ROSS's (dense
    run_modal at the reference speeds) and Campbell time per speed, ROSS / rotordyn_modal, one run."""
    import json

    from ross_reference import lateral_modes

    print(f"\nflexible rotors (tests/data/ross, ROSS files read by rotordyn_modal.io.ross_file); "
          f"Campbell diagrams of {n_speeds} speeds, {CAMPBELL_MODES} modes in ROSS")
    missing = flexible_missing()
    if missing is not None:
        print(f"  rotordyn_modal on this checkout has no flexible rotors ({missing}): nothing to compare; "
              "the rigid comparison above stands")
        return
    from rotordyn_modal.io.ross_file import read_ross_rotor

    print(f"{'rotor':>20} {'ROSS DOF':>8} {'rdm DOF':>7} | {'max rel. diff':>13} {'log dec diff':>12} "
          f"{'low vs all':>10} | {'ROSS ms/speed':>13} {'rdm all':>9} {'rdm low 12':>10} | "
          f"{'ROSS/all min/med/max':>20} {'ROSS/low min/med/max':>20}")
    verdicts = []
    for name in names:
        path = DATA / f"{name}.toml"
        reference = json.loads((DATA / f"{name}.json").read_text())
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
        with _quiet():
            rotor = rs.Rotor.load(path)
        rel, log_dec = root_agreement(model, rotor, reference, lateral_modes)
        speeds = [case["speed"] for case in reference["modal"]]
        grid = np.linspace(min(speeds), max(speeds), n_speeds)
        t_ross, t_all, t_low, low_vs_all = campbell_times(model, path, grid, repeat)
        cpu = _CPU[0]
        per_speed = [f"{np.median(t) / n_speeds * 1e3:{w}.3f}" if t is not None else f"{'-':>{w}}"
                     for t, w in ((t_all, 9), (t_low, 10))]
        ratios = [_spread(t_ross / t) if t is not None else f"{'-':>20}" for t in (t_all, t_low)]
        print(f"{name:>20} {rotor.ndof:8d} {model.dofs.n:7d} | {rel:13.1e} {log_dec:12.1e} {low_vs_all:10.1e} | "
              f"{np.median(t_ross) / n_speeds * 1e3:13.2f} {per_speed[0]} {per_speed[1]} | {ratios[0]} {ratios[1]}")
        if t_low is not None:
            verdicts.append(f"{name} {np.median(t_ross / t_low):.0f}x")
            print(f"{'':>20} CPU time (all threads of the process) of the same calls: ROSS "
                  f"{np.median(cpu[0]) / n_speeds * 1e3:.2f} ms/speed, rdm low 12 {np.median(cpu[2]) / n_speeds * 1e3:.3f} "
                  f"ms/speed, ROSS/low {_spread(cpu[0] / cpu[2]).strip()} (less swayed by other processes' load "
                  "than the wall times)")
        fresh = _FRESH[0]
        if t_low is not None and np.isfinite(fresh).all():
            print(f"{'':>20} lowest 12, the first call on a fresh model (the model's constants made in the call, "
                  f"as ROSS's Rotor makes M0, K0, G0 untimed): {np.median(fresh) / n_speeds * 1e3:.3f} ms/speed, "
                  f"ROSS/it {_spread(t_ross / fresh).strip()}")
        base = _BASELINE[0]
        if t_low is not None and np.isfinite(base).all():
            print(f"{'':>20} lowest 12 by the state matrices' eigvals (the route before the Hermitian one, same run): "
                  f"{np.median(base) / n_speeds * 1e3:.3f} ms/speed, ROSS/it {_spread(t_ross / base).strip()}, "
                  f"it/rdm low 12 {np.min(base / t_low):.2f}/{np.median(base / t_low):.2f}/{np.max(base / t_low):.2f}")
    if verdicts:
        print(f"  at {n_speeds} speeds, ROSS / rdm lowest 12 (median wall ratio; issue 28's target: at least "
              f"{TARGET_RATIO}x): " + ", ".join(verdicts))


def _spread(ratios) -> str:
    """min / median / max of the ratios of one run's repeats, as ``12x/14x/15x``."""
    return f"{np.min(ratios):.0f}x/{np.median(ratios):.0f}x/{np.max(ratios):.0f}x".rjust(20)


def root_agreement(model, rotor, reference, lateral_modes):
    """Largest relative difference of ROSS's lateral roots (now, dense, at the reference speeds)
    to the nearest roots of rdm.modal, and the largest difference of their log decrements."""
    rel = log_dec = 0.0
    for case in reference["modal"]:
        ross = lateral_modes(rotor, case["speed"])
        lam = np.array(ross["eigenvalues_re"]) + 1j * np.array(ross["eigenvalues_im"])
        ours = np.asarray(rdm.modal(model, case["speed"]).eigenvalues)
        nearest = ours[[int(np.argmin(np.abs(ours - x))) for x in lam]]
        rel = max(rel, float(np.max(np.abs(nearest - lam) / np.abs(lam))))
        ld = -2 * np.pi * nearest.real / np.abs(nearest.imag)
        log_dec = max(log_dec, float(np.max(np.abs(ld - np.array(ross["log_dec"])))))
    return rel, log_dec


def campbell_times(model, path, grid, repeat):
    """Wall times [s] over ``grid`` of ROSS's run_campbell, rdm.campbell of all modes and of the
    lowest 12 (None where campbell has no ``modes``), each (repeat,), taken in turn within each
    repeat (a noisy machine then weighs on all three alike); and the largest relative difference
    of the lowest 12 roots from the 12 lowest of all modes at every speed. ROSS gets a fresh Rotor
    each time (it memoises run_modal), after a first call on two speeds that compiles and caches."""
    import inspect

    keywords = {"critical": False}
    lowest = dict(keywords, modes=CAMPBELL_MODES) if "modes" in inspect.signature(rdm.campbell).parameters else None
    with _quiet():
        rs.Rotor.load(path).run_campbell(grid[:2], frequencies=CAMPBELL_MODES)  # first call: numba, caches
    rdm.campbell(model, grid[:3], **keywords)  # first call: imports, caches
    if lowest is not None:
        rdm.campbell(model, grid[:3], **lowest)
    times, cpu = np.full((5, repeat), np.nan), np.full((3, repeat), np.nan)
    baseline = _state_matrix_route() if lowest is not None else None
    for r in range(repeat):
        with _quiet():
            rotor = rs.Rotor.load(path)
            time.sleep(_SETTLE_SECONDS)
            start, busy = time.perf_counter(), time.process_time()
            rotor.run_campbell(grid, frequencies=CAMPBELL_MODES)
            times[0, r], cpu[0, r] = time.perf_counter() - start, time.process_time() - busy
        time.sleep(_SETTLE_SECONDS)
        start, busy = time.perf_counter(), time.process_time()
        every = rdm.campbell(model, grid, **keywords)
        times[1, r], cpu[1, r] = time.perf_counter() - start, time.process_time() - busy
        if lowest is not None:
            time.sleep(_SETTLE_SECONDS)
            start, busy = time.perf_counter(), time.process_time()
            low = rdm.campbell(model, grid, **lowest)
            times[2, r], cpu[2, r] = time.perf_counter() - start, time.process_time() - busy
        if lowest is not None:          # a fresh model (made untimed, as ROSS's Rotor): its constants made in the call
            fresh = _fresh_model(path)
            time.sleep(_SETTLE_SECONDS)
            start = time.perf_counter()
            rdm.campbell(fresh, grid, **lowest)
            times[4, r] = time.perf_counter() - start
        if baseline is not None:
            with baseline():
                start = time.perf_counter()
                rdm.campbell(model, grid, **lowest)
                times[3, r] = time.perf_counter() - start
    _BASELINE[:] = [times[3]]
    _FRESH[:] = [times[4] if lowest is not None else np.full(repeat, np.nan)]
    _CPU[:] = [cpu]
    if lowest is None:
        return times[0], times[1], None, np.nan
    roots = np.where(every.oscillatory, every.eigenvalues, np.nan + 1e30j)
    reference = np.take_along_axis(roots, np.argsort(roots.imag, axis=1), axis=1)[:, :CAMPBELL_MODES]
    found = np.take_along_axis(low.eigenvalues, np.argsort(low.eigenvalues.imag, axis=1), axis=1)
    return times[0], times[1], times[2], float(np.max(np.abs(found - reference) / np.abs(reference)))


#: a pause [s] before each timed call (not timed): the BLAS and numba threads of the call before
#: spin on a free core for a while after it, and the process's CPU time would charge that to the
#: next call (rotor_example at load 2: our call's CPU right after ROSS's 29-40 ms, its own thread
#: 12-14 ms, after a pause of 0.5 s 16-20 ms)
_SETTLE_SECONDS = 0.5

#: the last campbell_times' baseline times [s] (repeat,), NaN where there is none
_BASELINE = [np.array([np.nan])]
#: the last campbell_times' times [s] (repeat,) of the lowest 12 on a fresh model (its first call), NaN where none
_FRESH = [np.array([np.nan])]


def _fresh_model(path):
    """rotordyn_modal's model of the ROSS file ``path``, made anew (its warnings muted): nothing of an
    earlier analysis of the same rotor is kept on it (``analysis._stack.model_constants``)."""
    from rotordyn_modal.io.ross_file import read_ross_rotor

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict(read_ross_rotor(path), source=path)


#: the last campbell_times' CPU times [s] of the process (every thread) (3, repeat): ROSS, rdm all, rdm low 12
_CPU = [np.full((3, 1), np.nan)]


def _state_matrix_route():
    """A context in which the lowest modes of a small model take the route before the Hermitian
    one (``eigvals`` of the real state matrices, ``_lowest._dense_lowest``): the baseline timed in
    the same run; None on a checkout without the Hermitian route."""
    from rotordyn_modal.analysis import _lowest

    if not hasattr(_lowest, "_gyroscopic_lowest"):
        return None

    @contextlib.contextmanager
    def context():
        plain = _lowest._gyroscopic_lowest
        _lowest._gyroscopic_lowest = lambda stack, speeds, count: None
        try:
            yield
        finally:
            _lowest._gyroscopic_lowest = plain

    return context


def write_figure(data, ross_table, rdm_worst):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid, exact, w_rdm, w_ross = data
    rpm = grid * 30 / np.pi
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9.0, 3.6))
    step = max(1, len(rpm) // 40)
    for j in range(4):
        ax1.plot(rpm, exact[:, j] / (2 * np.pi), "k-", lw=1, label="closed form" if j == 0 else None)
        ax1.plot(rpm[::step], w_rdm[::step, j] / (2 * np.pi), "o", ms=3, mfc="none", color="C0",
                 label="rotordyn_modal ([[bearings]])" if j == 0 else None)
        ax1.plot(rpm[step // 2::step], w_ross[step // 2::step, j] / (2 * np.pi), "x", ms=3, color="C3",
                 label="ROSS (E x 1)" if j == 0 else None)
    ax1.plot(rpm, grid / (2 * np.pi), "k:", lw=0.8, label="1X")
    ax1.set(xlabel="speed [rpm]", ylabel="frequency [Hz]", title="Campbell: 4 lateral rigid-body modes",
            ylim=(0, 1.1 * exact.max() / (2 * np.pi)))
    ax1.legend(fontsize=7)
    scales = np.array(E_SCALES)
    for i, name in enumerate(("cylindrical", "conical backward", "conical forward")):
        ax2.loglog(scales, [ross_table[s][:, i].max() for s in scales], "o-", ms=4, label=f"ROSS {name}")
    ax2.axhline(max(rdm_worst, 1e-16), color="C0", ls="--", lw=1, label="rotordyn_modal (all modes)")
    ax2.set(xlabel="shaft E, G scale factor", ylabel="max relative difference to closed form",
            title="convergence to the rigid-rotor limit")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    out = REPO / "benchmarks" / "ross_comparison.png"
    fig.savefig(out, dpi=90)
    print(f"figure: {out} ({out.stat().st_size / 1024:.0f} kB)")


if __name__ == "__main__":
    main()
