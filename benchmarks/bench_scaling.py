"""Growth with model size and speed count: Campbell, FRF and unbalance response, each
against its floor.

Machines: ``benchmarks/_machines.py``'s gear chain (shared with ``bench_bearings.py``) of
1, 2, 5, 20 and 100 rotors, each driving the next through a gear, each on two flexible
bearings, in a casing on six mounts (``6 + 5 R`` coordinates, ``12 + 10 R`` states), with an
unbalance on every rotor, six sensors and two excitations (``with_channels``).

Cases, each timed side by side with its floor, alternating, in every repetition:

* **campbell**: ``rdm.campbell(model, speeds)`` (eigenvalues, shapes, tracking, whirl, 1X
  critical speeds of every rotor) over ``--campbell-speeds`` speeds 0..6,000 rpm. Floor: a
  bare batched ``numpy.linalg.eig`` of the same state matrices
  (``speed_linear_form(model).at(part)``, building included), in parts of the size the
  sweep uses (memory bounded the same way; the parts do not change the work).
* **frf**: ``rdm.frf(model, 3000 rpm, freqs, inputs=2, outputs=6)`` over ``--frequencies``
  frequencies 1..1,000 Hz. Floor: one ``numpy.linalg.eig`` of the state matrix and the modal
  sum ``sum_k (C V)_k (V^-1 B)_k / (i w - lam_k)`` for every frequency. The other obvious way,
  a batched solve of the dynamic stiffness at every frequency, costs ``n_freq`` LU
  factorisations of n x n complex matrices against one eigendecomposition of 2n x 2n: for
  2,000 frequencies it is 10-100 x dearer at every size here, so it would be no floor.
* **unbalance**: ``rdm.unbalance_response(model, speeds)`` (every rotor's unbalance, each
  at its own speed; all sensors, suspension, rotor and bearing forces) over
  ``--unbalance-speeds`` speeds (``--unbalance-speeds-large`` for the 100-rotor machine:
  100 systems of 506 coordinates per speed). Floor: a batched ``numpy.linalg.solve`` of the same harmonic
  systems ``Z(w_j) q = F_j``, one per source and speed (building ``Z`` included), in parts of
  the size the package uses.
* **speeds**: the campbell case at a fixed size (``--sweep-size``) for several speed counts
  (``--sweep-speeds``).

Every repetition runs the package then the floor; min / median / max of the times and of the
per-repetition ratios are printed (the machine is shared and noisy: the ratios measured side
by side are what counts), and the median of the package's time above the floor in
milliseconds (a fixed cost per call, which dominates the ratio of the smallest models, shows
as about the same milliseconds at every size). Peak memory: ``tracemalloc`` around one more, untimed call of each
contender (numpy reports its array buffers to tracemalloc, so this is the peak of the arrays
a call holds at once, temporaries included; LAPACK's own work space, O(n^2) per call, is not
seen; the process's ``ru_maxrss`` at the end is printed too, for the whole run). The growth
exponent is the least-squares slope of log(median time per speed, or per frequency) against
log(n_states) over the sizes. Each case runs at least ``--repeat`` pairs, and fast ones as
many more as fill about ``--min-seconds`` (1 s, at most 101 pairs: a 1-rotor Campbell call of
7 ms is sampled about 80 times, so that its median is not that of three noisy samples).
Models above 600 states run ``--repeat-large`` times (one by default: then that timed call is
also the traced one, without a warm-up).

One core for everything by default (``ROTORDYN_MODAL_THREADS=1`` and one BLAS thread through
threadpoolctl), so the ratios compare work, not the scheduling of a shared machine. Run::

    python benchmarks/bench_scaling.py [--quick] [--sizes 1,2,5,20,100] [--cases campbell,frf,unbalance,speeds]
        [--repeat 3] [--min-seconds 1] [--repeat-large 1] [--campbell-speeds 51] [--unbalance-speeds 201]
        [--unbalance-speeds-large 21] [--frequencies 2000] [--sweep-size 5] [--sweep-speeds 51,201,1001,5001] [--threads 1]
        [--no-memory]

``--quick``: sizes 1, 2, 5, 20; 21 speeds; 500 frequencies; speed counts 51, 201, 1001;
2 repetitions (``--min-seconds 0``).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machines import gear_chain_description, with_channels  # noqa: E402

_LARGE_STATES = 600  # models with more states than this are repeated --repeat-large times
_TOP_RPM = 6000.0
_FRF_RPM = 3000.0


# --------------------------------------------------------------------------- contenders
def machine(rotors: int):
    import rotordyn_modal as rdm

    return rdm.Model.from_dict(with_channels(gear_chain_description(rotors)))


def speeds_of(count: int) -> np.ndarray:
    import rotordyn_modal as rdm

    return rdm.rpm(np.linspace(0.0, _TOP_RPM, count))


def campbell_pair(model, count):
    """rdm.campbell and its floor: bare batched eig of the same state matrices, in the
    sweep's parts."""
    import rotordyn_modal as rdm
    from rotordyn_modal.analysis import _batches
    from rotordyn_modal.linear_system import speed_linear_form

    speeds = speeds_of(count)

    def package():
        return rdm.campbell(model, speeds)

    def floor():
        form = speed_linear_form(model)
        size = form.n_states
        parts = _batches.chunk_slices(len(speeds), 72 * size * size, largest=4096)   # the package's parts
        return [np.linalg.eig(form.at(speeds[part]))[0] for part in parts]

    return package, floor


def frf_pair(model, count):
    """rdm.frf (modal engine) and its floor: one eig and the modal sum."""
    import rotordyn_modal as rdm
    from rotordyn_modal.assembly import excitation_columns, sensor_rows
    from rotordyn_modal.linear_system import speed_linear_form

    speed = float(rdm.rpm(_FRF_RPM))
    freqs = np.linspace(1.0, 1000.0, count)

    def package():
        return rdm.frf(model, speed, freqs)

    def floor():
        form = speed_linear_form(model)
        n = form.n_dof
        columns, rows = excitation_columns(model), sensor_rows(model)
        values, vectors = np.linalg.eig(form.at(speed))
        b = np.zeros((form.n_states, columns.shape[1]))
        b[n:2 * n] = form.mass_inverse @ columns
        left = rows @ vectors[:n]
        right = np.linalg.solve(vectors, b)
        poles = 1.0 / (1j * 2 * np.pi * freqs[None, :] - values[:, None])
        return np.einsum("sk,ki,kf->sif", left, right, poles)

    return package, floor


def unbalance_pair(model, count):
    """rdm.unbalance_response and its floor: batched solve of the same harmonic systems."""
    import rotordyn_modal as rdm
    from rotordyn_modal.analysis import _batches, frf as frf_module
    from rotordyn_modal.analysis.unbalance import unbalance_forces
    from rotordyn_modal.assembly import constant_matrices, generalized_force

    speeds = speeds_of(count)

    def package():
        return rdm.unbalance_response(model, speeds)

    def floor():
        M, C, G, K = constant_matrices(model)
        sources, w, forces = unbalance_forces(model, speeds)
        rhs = np.stack([generalized_force(model, s, model.rotor(s).center_of_mass, forces[j])
                        for j, s in enumerate(sources)]).reshape(-1, M.shape[0], 1)
        omega, speed = w.ravel(), np.tile(speeds, len(sources))
        n = M.shape[0]
        out = []
        for part in _batches.chunk_slices(len(omega), 48 * n * n, budget=frf_module._SOLVE_PART_BYTES):
            o, s = omega[part, None, None], speed[part, None, None]
            Z = K + 1j * o * (C + s * G) - o**2 * M
            out.append(np.linalg.solve(Z, rhs[part]))
        return np.concatenate(out)

    return package, floor


PAIRS = {"campbell": campbell_pair, "frf": frf_pair, "unbalance": unbalance_pair}


# --------------------------------------------------------------------------- measuring
def timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def peak_bytes(function) -> int:
    """Peak of the arrays held during one call (tracemalloc; see the module's docstring)."""
    tracemalloc.start()
    tracemalloc.reset_peak()
    try:
        function()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def spread(values, scale=1.0, fmt="{:8.3f}") -> str:
    values = [v * scale for v in values]
    return " / ".join(fmt.format(v) for v in (min(values), statistics.median(values), max(values)))


#: most repetitions of a fast case (see ``--min-seconds``)
_MOST_REPEATS = 101


def repetitions(pair_seconds, repeat, min_seconds) -> int:
    """At least ``repeat``, and enough pairs of calls taking ``pair_seconds`` to fill
    ``min_seconds`` (at most ``_MOST_REPEATS``): a 7 ms case is sampled 70 times, not 3."""
    wanted = int(np.ceil(min_seconds / max(pair_seconds, 1e-9)))
    return max(repeat, min(wanted, _MOST_REPEATS))


def measure(case, model, count, repeat, memory, warm=True, min_seconds=0.0):
    """Times of the package and the floor per repetition (alternating) and their peak memory.

    With ``warm=False`` (the largest models, one repetition) there is no warm-up call and the
    one repetition is also the traced call (tracemalloc's cost per numpy allocation is
    negligible beside LAPACK work of seconds). Fast cases repeat until about ``min_seconds``
    (:func:`repetitions`)."""
    package, floor = PAIRS[case](model, count)
    if not warm:
        mine, peak_mine = traced(package, memory)
        base, peak_base = traced(floor, memory)
        return np.array([mine]), np.array([base]), (peak_mine, peak_base)
    package(), floor()                             # warm-up: imports, caches, thread pool
    times = [(timed(package), timed(floor))]
    for _ in range(repetitions(sum(times[0]), repeat, min_seconds) - 1):
        times.append((timed(package), timed(floor)))
    mine, base = (np.array(column) for column in zip(*times))
    peaks = (peak_bytes(package), peak_bytes(floor)) if memory else (np.nan, np.nan)
    return mine, base, peaks


def traced(function, memory):
    """Seconds and peak traced bytes of one call (NaN bytes without ``memory``)."""
    if not memory:
        return timed(function), np.nan
    tracemalloc.start()
    try:
        seconds = timed(function)
        return seconds, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def report(label, states, mine, base, peaks):
    """One row: times, their ratio, the package's time above the floor (the median of the
    repetitions' differences: a fixed cost shows as the same milliseconds at every size) and
    the peak memory."""
    ratio = mine / base
    extra = statistics.median(mine - base) * 1e3
    print(f"{label:>22} {states:6d} | package {spread(mine)} s | floor {spread(base)} s | "
          f"ratio {spread(ratio, fmt='{:5.2f}')} | above floor {extra:9.2f} ms | "
          f"peak MB {peaks[0] / 2**20:8.1f} {peaks[1] / 2**20:8.1f} | pairs {len(mine)}", flush=True)


def exponent(states, times) -> float:
    """Least-squares slope of log(time) against log(n_states)."""
    return float(np.polyfit(np.log(states), np.log(times), 1)[0])


def run_sizes(case, sizes, count, count_large, args):
    """One case over the model sizes; the growth exponent is fitted to the time per speed
    (per frequency) where the largest models use fewer speeds."""
    from rotordyn_modal.linear_system import speed_linear_form

    unit = "frequencies" if case == "frf" else "speeds"
    print(f"\n{case}, {count} {unit} ({count_large} above {_LARGE_STATES} states): "
          "min / median / max of the repetitions")
    print(f"{'rotors':>22} {'states':>6} |")
    rows = []
    for rotors in sizes:
        model = machine(rotors)
        states = speed_linear_form(model).n_states
        large = states > _LARGE_STATES
        points = count_large if large else count
        mine, base, peaks = measure(case, model, points, args.repeat_large if large else args.repeat,
                                    not args.no_memory, warm=not large or args.repeat_large > 1,
                                    min_seconds=0.0 if large else args.min_seconds)
        report(f"{rotors} rotors" + (f", {points} {unit}" if large else ""), states, mine, base, peaks)
        rows.append((states, statistics.median(mine) / points, statistics.median(base) / points))
    if len(rows) > 1:
        states, mine, base = (np.array(c) for c in zip(*rows))
        print(f"{'growth exponent':>22}        | package {exponent(states, mine):5.2f} "
              f"(time per {'frequency' if case == 'frf' else 'speed'} ~ n_states^p)   floor {exponent(states, base):5.2f}")
        big = states >= 60
        if big.sum() > 1:
            print(f"{'(sizes >= 60 states)':>22}        | package {exponent(states[big], mine[big]):5.2f}"
                  f"                                   floor {exponent(states[big], base[big]):5.2f}")


def run_speeds(size, counts, args):
    model = machine(size)
    from rotordyn_modal.linear_system import speed_linear_form

    states = speed_linear_form(model).n_states
    print(f"\ncampbell at {size} rotors ({states} states) against the speed count")
    print(f"{'speeds':>22} {'states':>6} |")
    rows = []
    for count in counts:
        mine, base, peaks = measure("campbell", model, count, args.repeat, not args.no_memory,
                                    min_seconds=args.min_seconds)
        report(f"{count} speeds", states, mine, base, peaks)
        rows.append((count, statistics.median(mine), statistics.median(base)))
    if len(rows) > 1:
        counts, mine, base = (np.array(c) for c in zip(*rows))
        print(f"{'growth exponent':>22}        | package {exponent(counts, mine):5.2f} (time ~ speeds^p)   "
              f"floor {exponent(counts, base):5.2f}")


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a short run (see the docstring)")
    parser.add_argument("--sizes", default="1,2,5,20,100", help="rotor counts")
    parser.add_argument("--cases", default="campbell,frf,unbalance,speeds")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--min-seconds", type=float, default=1.0,
                        help=f"repeat fast cases until about this many seconds (at most {_MOST_REPEATS} times)")
    parser.add_argument("--repeat-large", type=int, default=1, help=f"repetitions above {_LARGE_STATES} states")
    parser.add_argument("--campbell-speeds", type=int, default=51)
    parser.add_argument("--unbalance-speeds", type=int, default=201)
    parser.add_argument("--unbalance-speeds-large", type=int, default=21,
                        help=f"unbalance speeds above {_LARGE_STATES} states (100 rotors: 100 systems per speed)")
    parser.add_argument("--frequencies", type=int, default=2000)
    parser.add_argument("--sweep-size", type=int, default=5, help="rotors of the speed-count sweep")
    parser.add_argument("--sweep-speeds", default="51,201,1001,5001")
    parser.add_argument("--threads", default="1", help="'1' (one core for all) or 'default'")
    parser.add_argument("--no-memory", action="store_true", help="skip the tracemalloc calls")
    args = parser.parse_args(argv)
    if args.quick:
        args.sizes, args.repeat, args.min_seconds = "1,2,5,20", 2, 0.0
        args.campbell_speeds = args.unbalance_speeds = args.unbalance_speeds_large = 21
        args.frequencies, args.sweep_speeds = 500, "51,201,1001"
    return args


def main(argv=None) -> None:
    args = parse(argv)
    if args.threads != "default":
        os.environ["ROTORDYN_MODAL_THREADS"] = args.threads
        import scipy.linalg  # noqa: F401  (scipy's own BLAS must be loaded to be limited)
        from threadpoolctl import threadpool_limits

        threadpool_limits(int(args.threads), user_api="blas")
    sizes = [int(s) for s in args.sizes.split(",")]
    cases = args.cases.split(",")
    print(f"threads: {args.threads}; sizes {sizes} rotors; repetitions at least {args.repeat}, fast cases until "
          f"about {args.min_seconds:g} s (at most {_MOST_REPEATS}); {args.repeat_large} above {_LARGE_STATES} states")
    counts = {"campbell": (args.campbell_speeds, args.campbell_speeds),
              "frf": (args.frequencies, args.frequencies),
              "unbalance": (args.unbalance_speeds, args.unbalance_speeds_large)}
    for case in ("campbell", "frf", "unbalance"):
        if case in cases:
            run_sizes(case, sizes, *counts[case], args)
    if "speeds" in cases:
        run_speeds(args.sweep_size, [int(c) for c in args.sweep_speeds.split(",")], args)
    print(f"\npeak resident memory of the whole run (ru_maxrss): "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10:.0f} MB")


if __name__ == "__main__":
    main()
