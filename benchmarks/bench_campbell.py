"""Campbell diagram speed: the package against the floor and the obvious loop.

For the two-rotor gear machine (examples/gear_machine.toml) it times

* ``rdm.campbell`` (eigenvalues, shapes, tracking, whirl and critical speeds of 1X),
* the floor: one bare batched ``numpy.linalg.eig`` of the same state matrices (built in the
  timed call, as ``rdm.campbell`` builds them),
* the loop: ``scipy.linalg.eig`` called once per speed,

for 10,001 speeds (the sweep) and for 201 speeds (the call a parameter study makes per
variant, where refining the critical speeds weighs most). The two are timed alternately,
``--repeat`` times, and the ratio of each pair is reported as min/median/max, so that load
from other processes hits both alike. ``ROTORDYN_MODAL_THREADS=1`` measures one core.

One rigid rotor (``--part one-rotor``, the default part too): a rotor on two damped bearings to
the ground (4 coordinates) and the same kind of rotor on bearings in a casing on six mounts
(``_machines.gear_chain(1)``, 11 coordinates), at 201 and 1001 speeds (``--one-rotor-speeds``):
``rdm.campbell(model, speeds, orders=(1,))`` (the critical speeds of 1X refined too) against the
obvious loop, ``scipy.linalg.eig`` of each speed's state matrix (built in the timed call),
alternately; the ratio loop / campbell of each pair as min/median/max (above 1: the package is
faster), of the wall times and, on a second line, of the CPU times (``time.process_time``: the
load of other processes shows in the wall times far more than in these). Run::

    python benchmarks/bench_campbell.py [--repeat 15] [--part all|gear|one-rotor]
        [--one-rotor-speeds 201 1001]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.linear_system import state_matrices

MODEL = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


def _pairs(first, second, repeat, cpu=None):
    """Wall times of ``first()`` and ``second()`` called alternately, ``repeat`` times each
    (2, repeat) [s]; their CPU times (``time.process_time``) into ``cpu`` (2, repeat) when given."""
    times = np.zeros((2, repeat))
    for i in range(repeat):
        for j, function in enumerate((first, second)):
            start, start_cpu = time.perf_counter(), time.process_time()
            function()
            times[j, i] = time.perf_counter() - start
            if cpu is not None:
                cpu[j, i] = time.process_time() - start_cpu
    return times


def _report(label, times, target):
    ratio = times[0] / times[1]
    print(f"{label}: rdm.campbell {np.median(times[0]) * 1e3:8.2f} ms, floor {np.median(times[1]) * 1e3:8.2f} ms; "
          f"campbell / floor min {ratio.min():.2f} median {np.median(ratio):.2f} max {ratio.max():.2f}"
          f"  (target <= {target})")


def _loop(model, speeds):
    """The obvious loop: ``scipy.linalg.eig`` (eigenvalues and eigenvectors) of each speed's state matrix."""
    for a in state_matrices(model, speeds):
        scipy.linalg.eig(a)


def one_rotor_models():
    """A rigid rotor on two damped bearings to the ground (4 coordinates), and a rigid rotor on
    bearings in a casing on six mounts (``_machines.gear_chain(1)``, 11 coordinates)."""
    from _machines import gear_chain

    bare = rdm.Model.from_dict({
        "name": "rigid rotor on two bearings",
        "rotors": [{"name": "rotor", "mass": 30.0, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.4, "diametral_inertia": 0.9, "speed_ratio": 1.0}],
        "bearings": [{"name": f"brg-{side}", "rotor": "rotor", "position": [x, 0.0, 0.0], "stiffness": 1e6,
                      "damping": 100.0} for side, x in (("A", -0.25), ("B", 0.25))]})
    return {"rotor on two bearings": bare, "rotor on bearings in a casing on mounts": gear_chain(1)}


def one_rotor(repeat: int, counts=(201, 1001)) -> None:
    """rdm.campbell of one rigid rotor against the scipy.linalg.eig loop, at ``counts`` speeds."""
    for count in counts:
        speeds = rdm.rpm(np.linspace(0.0, 3000.0, count))
        for name, model in one_rotor_models().items():
            _one_rotor_pairs(name, model, speeds, repeat)


def _one_rotor_pairs(name, model, speeds, repeat) -> None:
    """Time rdm.campbell and the loop alternately over ``speeds``; print their ratio's spread."""
    rdm.campbell(model, speeds)                                        # warm caches and threads
    cpu = np.zeros((2, repeat))
    times = _pairs(lambda: rdm.campbell(model, speeds, orders=(1,)), lambda: _loop(model, speeds), repeat, cpu)
    ratio = times[1] / times[0]
    print(f"one rotor, {name} ({model.dofs.n} coordinates), {len(speeds)} speeds: rdm.campbell "
          f"{np.median(times[0]) * 1e3:7.2f} ms, scipy.linalg.eig loop {np.median(times[1]) * 1e3:7.2f} ms; "
          f"loop / campbell min {ratio.min():.2f} median {np.median(ratio):.2f} max {ratio.max():.2f}  (target > 1)",
          flush=True)
    # CPU time (time.process_time: the threads of a threaded eigen-solve add up) says less of the load
    ratio = cpu[1] / np.maximum(cpu[0], 1e-9)
    print(f"    CPU: rdm.campbell min {cpu[0].min() * 1e3:.2f} median {np.median(cpu[0]) * 1e3:.2f} ms, loop min "
          f"{cpu[1].min() * 1e3:.2f} median {np.median(cpu[1]) * 1e3:.2f} ms; loop / campbell min {ratio.min():.2f} "
          f"median {np.median(ratio):.2f} max {ratio.max():.2f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--part", choices=("all", "gear", "one-rotor"), default="all",
                        help="the gear machine against the floor, one rigid rotor against the loop, or both")
    parser.add_argument("--one-rotor-speeds", type=int, nargs="+", default=[201, 1001],
                        help="speeds of the one-rotor sweeps (default 201 1001)")
    args = parser.parse_args()
    if args.part in ("all", "one-rotor"):
        one_rotor(args.repeat, args.one_rotor_speeds)
    if args.part == "one-rotor":
        return
    model = rdm.load_model(MODEL)
    for count, target in ((201, 1.5), (10001, 1.5)):
        speeds = rdm.rpm(np.linspace(0.0, 3000.0 if count == 201 else 12000.0, count))
        rdm.campbell(model, speeds)                                    # warm caches and threads
        times = _pairs(lambda: rdm.campbell(model, speeds, orders=(1,)),
                       lambda: np.linalg.eig(state_matrices(model, speeds)), args.repeat)
        _report(f"{count:6d} speeds", times, target)
    matrices = state_matrices(model, speeds)
    start = time.perf_counter()
    for a in matrices:
        scipy.linalg.eig(a)
    loop = time.perf_counter() - start
    print(f"loop: scipy.linalg.eig per speed, 10001 speeds: {loop * 1e3:8.1f} ms = "
          f"{loop / np.median(times[0]):.2f} x rdm.campbell")


if __name__ == "__main__":
    main()
