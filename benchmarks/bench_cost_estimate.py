"""The estimate of a dense eigen-solution's CPU time (``rotordyn_modal.analysis._cost``) against
the measured solve of real state matrices.

Machines, each at about ``--states`` states:

* **chain**: ``benchmarks/_machines.py``'s gear chain of R rigid rotors, each on two bearings,
  each driving the next through a gear, in a casing on six mounts (``12 + 10 R`` states);
* **shaft**: ``bench_flexible.py``'s uniform 4 m flexible shaft of E elements on two bearings
  (4 coordinates per node, ``8 (E + 1)`` states).

For each: the estimate (:func:`rotordyn_modal.analysis._cost.eig_seconds`, eigenvalues with
vectors, and :func:`~rotordyn_modal.analysis._cost.eigvals_seconds`, eigenvalues only), made in
this process just before the measurement, and the CPU time (``time.process_time``: every thread
of the process) of

* ``eig``: ``numpy.linalg.eig`` of the state matrix at 300 rad/s with one BLAS thread (what the
  sweeps of ``campbell``, ``critical-speeds`` and ``stability`` run per speed);
* ``eigvals``: ``numpy.linalg.eigvals`` of the same, one BLAS thread (the critical speeds' mode
  numbers, the sub-sweeps' and stability maps' roots without shapes);
* ``modal``: ``rdm.modal(model, 300)`` whole (what ``modes --speed`` runs);
* ``threads``: ``scipy.linalg.eig`` of the same with BLAS's own threads (OpenBLAS's default, one
  per core; what ``modal`` ran before 2026-11-29), up to ``--threaded-up-to`` states.

Ratios are measured / estimated (1: the estimate is right; above 1: it is low). The machine is
shared: each line is one measurement (``--repeat`` more for min/median/max).

With ``--blas N,N,...`` it measures instead the dense steps around the solves that
``rotordyn_modal/_blas.py`` holds to one thread (``inv(M)``, the check ``inv(M) @ M`` and the
state matrices' products, ``cholesky(M)``) on a symmetric positive definite matrix of each size:
with BLAS's own threads and with one, alternated in this one process, ``--repeat`` times; the
ratios threaded / one thread of wall and CPU time, min/median/max.

Usage::

    python benchmarks/bench_cost_estimate.py [--kinds chain,shaft] [--states 500,1000,2000,4000]
                                             [--repeat 1] [--threaded-up-to 1000]
    python benchmarks/bench_cost_estimate.py --blas 406,1000,2006 --repeat 5
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost
from rotordyn_modal.analysis._batches import one_blas_thread
from rotordyn_modal.linear_system import speed_linear_form

from _machines import gear_chain
from bench_flexible import _long_shaft

_SPEED = 300.0


def _machine(kind: str, states: int):
    """The model of ``kind`` with about ``states`` states."""
    if kind == "chain":
        return gear_chain(max(1, round((states - 12) / 10)))
    return _long_shaft(max(2, round(states / 8) - 1))


def _cpu(function) -> float:
    """CPU seconds of ``function()``, every thread of the process counted."""
    start = time.process_time()
    function()
    return time.process_time() - start


def _stats(values) -> str:
    values = np.asarray(values)
    if len(values) == 1:
        return f"{values[0]:8.2f}"
    return f"{values.min():.2f}/{np.median(values):.2f}/{values.max():.2f}"


def _clocks(function) -> tuple:
    """(wall, CPU) seconds of ``function()``."""
    wall, cpu = time.perf_counter(), time.process_time()
    function()
    return time.perf_counter() - wall, time.process_time() - cpu


def blas_threads(sizes, repeat: int) -> None:
    """Print, for each size and step, one thread's wall time and the ratios threaded / one thread
    (wall and CPU, min/median/max of ``repeat`` alternated pairs)."""
    print(f"{'size':>5s} {'step':12s} {'one thread':>11s}   threaded / one thread: wall, CPU (min/median/max)")
    for n in sizes:
        rng = np.random.default_rng(n)
        a = rng.standard_normal((n, n))
        mass = a @ a.T + n * np.eye(n)
        inverse = np.linalg.inv(mass)
        steps = {"inv(M)": lambda: np.linalg.inv(mass), "inv(M) @ M": lambda: inverse @ mass,
                 "cholesky(M)": lambda: np.linalg.cholesky(mass)}
        for name, step in steps.items():
            step()
            walls, cpus, one = [], [], []
            for _ in range(repeat):
                threaded = _clocks(step)
                with one_blas_thread(72 * n * n):
                    single = _clocks(step)
                walls.append(threaded[0] / single[0])
                cpus.append(threaded[1] / max(single[1], 1e-9))
                one.append(single[0])
            print(f"{n:5d} {name:12s} {1e3 * np.median(one):8.1f} ms   {_stats(walls)}, {_stats(cpus)}", flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kinds", default="chain,shaft")
    parser.add_argument("--states", default="500,1000,2000,4000")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--threaded-up-to", type=int, default=1000,
                        help="largest state matrix also solved with BLAS's own threads")
    parser.add_argument("--blas", default="", metavar="N,N",
                        help="measure the dense steps held to one BLAS thread at these sizes instead")
    args = parser.parse_args(argv)
    if args.blas:
        blas_threads([int(s) for s in args.blas.split(",")], args.repeat)
        return
    print(f"{'machine':6s} {'states':>6s} {'est eig':>8s} {'eig':>8s} {'ratio':>6s} {'est vals':>8s} {'eigvals':>8s} "
          f"{'ratio':>6s} {'modal':>8s} {'ratio':>6s} {'threads':>8s} {'ratio':>6s}   [CPU s]")
    for kind in args.kinds.split(","):
        for states in (int(s) for s in args.states.split(",")):
            model = _machine(kind, states)
            matrix = speed_linear_form(model).at(_SPEED)
            n = len(matrix)
            estimate = _cost.eig_seconds(n)
            values_estimate = _cost.eigvals_seconds(n)
            eig, values, modal, threads = [], [], [], []
            for _ in range(args.repeat):
                with one_blas_thread(72 * n * n):
                    eig.append(_cpu(lambda: np.linalg.eig(matrix)))
                    values.append(_cpu(lambda: np.linalg.eigvals(matrix)))
                modal.append(_cpu(lambda: rdm.modal(model, _SPEED)))
                if n <= args.threaded_up_to:
                    threads.append(_cpu(lambda: scipy.linalg.eig(matrix)))
            threaded = (f"{_stats(threads):>8s} {np.median(threads) / estimate:6.2f}" if threads
                        else f"{'-':>8s} {'-':>6s}")
            print(f"{kind:6s} {n:6d} {estimate:8.2f} {_stats(eig):>8s} {np.median(eig) / estimate:6.2f} "
                  f"{values_estimate:8.2f} {_stats(values):>8s} {np.median(values) / values_estimate:6.2f} "
                  f"{_stats(modal):>8s} {np.median(modal) / estimate:6.2f} {threaded}", flush=True)


if __name__ == "__main__":
    main()
