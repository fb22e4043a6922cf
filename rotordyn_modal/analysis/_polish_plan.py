"""The polish's plan at one speed: which inexact roots are polished together (clusters of
neighbours closer than their round-off, the others one by one) and how much polishing a speed
may cost, in eigen-solves of that speed, on a machine of a given size (docs/theory.md §8,
"Close roots"). Shared by the full solve (:func:`._eigensolve.refined_pairs`) and the lowest
route (:func:`._lowest_newton._exactly_polished`)."""

from __future__ import annotations

import numpy as np

__all__ = ["POLISH_WORK", "SMALL_MACHINE", "BIG_MACHINE_WORK", "BATCHED_ROOT_WORK", "SPARSE_ROOT_WORK", "DENSE_ROOT_WORK",
           "polish_budget",
           "polish_work", "run_work"]


def _nearest_other(values, a):
    """The index of the root of ``values`` (m,) nearest ``values[a]``, itself excepted."""
    distance = np.abs(values - values[a])
    distance[a] = np.inf
    return int(np.argmin(distance))


#: the polish's work at one speed at most on a small machine (up to :data:`SMALL_MACHINE`
#: coordinates), in eigen-solves of that speed (:func:`polish_work`, :func:`run_work`): however many roots need it,
#: polishing costs a speed at most this many times its own solve, so a machine with many inexact
#: roots stays linear in them (the lowest first; past it the roots keep their bound and are warned
#: of). A big machine's is smaller (:func:`polish_budget`)
POLISH_WORK = 10.0
#: coordinates up to which :data:`POLISH_WORK` holds, and the polish's units are those measured
#: (one root 0.5 to 0.9 of the speed's solve, a pair 1.5 to 2)
SMALL_MACHINE = 240
#: the polish's work at one speed at most on a big machine (from about 540 coordinates), in
#: eigen-solves: a pair still fits, and, the units being about twice the measured cost there,
#: the polish costs about one solve of the speed at most, half the run's time
BIG_MACHINE_WORK = 2.0


def polish_budget(n):
    """The polish's work at one speed at most [eigen-solves of the speed] on a machine of ``n``
    coordinates: :data:`POLISH_WORK` up to :data:`SMALL_MACHINE` coordinates, falling as
    ``(SMALL_MACHINE / n)^2`` above (a big machine's solve is long, and the polish had taken 68 %
    of a 624-coordinate run with ten inexact roots a speed) to :data:`BIG_MACHINE_WORK` (or
    :data:`POLISH_WORK` where smaller)."""
    return max(min(BIG_MACHINE_WORK, POLISH_WORK), POLISH_WORK * min(1.0, SMALL_MACHINE / max(n, 1)) ** 2)


def polish_work(size, n=0):
    """The work of polishing a cluster of ``size`` roots, in eigen-solves of the speed (the QR of
    the ``2n`` state matrix with its vectors), on a machine of ``n`` coordinates. Measured
    (``docs/theory.md``, "Close roots"; CPU, same process, random SPD pencils): one root 0.87,
    0.84, 0.52, 0.34, 0.23, 0.21 of the solve at 60, 120, 240, 600, 1,000, 1,500 coordinates, a
    pair 1.96, 2.0, 1.45, 1.12, 0.85, 0.75, three roots 2.5, 2.5, 1.9 at 240, 600, 1,000. Counted
    as 1 for one root, ``k^3 / 4`` for ``k`` (2 for a pair: ``k n + k^2`` unknowns solved three
    times), times ``sqrt(SMALL_MACHINE / n)`` above :data:`SMALL_MACHINE` coordinates (at most
    twice the measured cost)."""
    work = 1.0 if size == 1 else size ** 3 / 4.0
    return work * min(1.0, np.sqrt(SMALL_MACHINE / n)) if n > SMALL_MACHINE else work


#: the work of one single root polished with the others of its speed at once
#: (:func:`._eigensolve.single_roots_polished`), in eigen-solves of the speed, as :func:`polish_work`
#: counts (times ``sqrt(SMALL_MACHINE / n)`` above it). Measured (CPU, one BLAS thread, medians of
#: 3): the 16 single roots of the 48-coordinate 1 mm shaft at 3,000 rpm about 0.1 each, one at a
#: time 0.5 to 0.9 each
BATCHED_ROOT_WORK = 0.2
#: the work of one root on a sparse pencil (``._eigensolve._sparse``: a meshed shaft), polished
#: with the others at once or in a cluster by a sparse LU (``._eigensolve.sparse_block_polished``),
#: in eigen-solves of the speed; a cluster of ``k`` counts ``k^3 / 4`` of it. Measured (CPU, one
#: BLAS thread, 3 runs): all 46 roots over 1e-9 of the 624-coordinate cut shaft at 3,000 rpm (44
#: single, a pair) 0.44 to 0.75 of its solve with their round-off estimate, about 0.005 a root
SPARSE_ROOT_WORK = 0.02


#: the work of one single root polished with the others of its speed at once on a dense pencil of
#: more than :data:`SMALL_MACHINE` coordinates, in eigen-solves of the speed (in place of
#: :data:`BATCHED_ROOT_WORK` of :func:`polish_work`, 0.18 to 0.12 there). Measured (roots33; CPU, one
#: BLAS thread, 3 runs; ``/tmp/roots33/full_cost.py``): the cut shaft's pencil with ten rows and
#: columns coupled to every coordinate (a casing's: 7 to 10 % of the entries nonzero), 47 and 48
#: single roots, 0.044 to 0.054 of the solve a root at 308 coordinates, 0.034 to 0.039 at 448; the
#: pencil's rows padded to the widest (before roots33) cost about 0.3 a root at 308
DENSE_ROOT_WORK = 0.06


def run_work(size, n, sparse=False):
    """The work of polishing a run of ``size`` roots (:func:`_clusters`; one root: with the speed's
    other single roots at once; real roots as complex ones since roots33, a real run as a complex
    cluster) on a machine of ``n`` coordinates, in eigen-solves of the
    speed: :data:`SPARSE_ROOT_WORK` a root on a sparse pencil, else :data:`BATCHED_ROOT_WORK` of
    :func:`polish_work` for one root (:data:`DENSE_ROOT_WORK` above :data:`SMALL_MACHINE`
    coordinates) and :func:`polish_work` for a cluster."""
    if sparse:
        return SPARSE_ROOT_WORK * (1.0 if size == 1 else size ** 3 / 4.0)
    if size == 1:
        return DENSE_ROOT_WORK if n > SMALL_MACHINE else BATCHED_ROOT_WORK * polish_work(1, n)
    return polish_work(size, n)


def _clusters(values, bound, order):
    """The roots ``order`` (indices into ``values``, by frequency) in clusters (a list of index
    arrays, by frequency): runs of neighbours closer than either's round-off ``bound`` (relative),
    which one-root steps cannot tell apart, and the others one by one."""
    runs = [[order[0]]]
    for a, b in zip(order[:-1], order[1:]):
        gap = abs(values[b] - values[a]) / max(abs(values[a]), abs(values[b]))
        if gap < max(bound[a], bound[b]):
            runs[-1].append(b)
        else:
            runs.append([b])
    return [np.array(run) for run in runs]
