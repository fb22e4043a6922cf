"""The CPU time of dense eigen-solutions from the size of the state matrix alone, and the limit of
CPU time in force: the part of :mod:`._work`'s estimate that needs no model.

It stands apart so that the lowest modes' full-solve fallback (:mod:`._lowest`) can be refused
before its work without importing :mod:`._work`, which reads the sweep's modules (``campbell``,
``critical_speeds``) that import ``_lowest``. The limit is ``DEFAULT_MINUTES`` of CPU time; the
environment variable ``ROTORDYN_MODAL_MAX_CPU_MINUTES`` sets another (``inf``: no check).

The estimate (:func:`eig_seconds`) is of one LAPACK ``geev`` with vectors run by one BLAS thread,
the way every dense eigen-solution of the package runs (the sweeps' threads, ``modal``): a random
matrix of the size, or of ``_CALIBRATION_STATES`` for larger ones, is timed (best of
``_REPEATS``) and scaled by the cube of the size, the operations' count (docs/theory.md, "How long
a sweep takes"). Measured with ``benchmarks/bench_cost_estimate.py`` on gear chains and flexible
shafts of 500 to 4,000 states, the state matrices' solutions take 0.3-0.9 of it; what had been
8 times above it was ``modal``'s solve run by OpenBLAS's own threads (their CPU time on a shared
machine 6-20 times one thread's), not the estimate. The eigenvalues alone
(:func:`eigvals_seconds`) take ``EIGVALS_SHARE`` of it.

Whether long work runs anyway is said in one place, :func:`long_work_is_allowed`, read by every
check (the command line's sweeps in :mod:`._work`, the lowest modes' fallback in :mod:`._lowest`);
it is set by :func:`long_work_allowed` alone, which the command line enters for a run with
``--allow-long`` and Python code as ``with rdm.long_work_allowed(): ...``.
"""

from __future__ import annotations

import contextlib
import functools
import time

import numpy as np

from .._limits import environment_number

__all__ = ["ENVIRONMENT", "DEFAULT_MINUTES", "EIGVALS_SHARE", "limit_seconds", "eig_seconds", "eigvals_seconds",
           "duration", "long_work_allowed", "long_work_is_allowed", "eigen_solutions_over_limit"]

#: environment variable: the CPU minutes an analysis may be estimated to take (``inf``: any)
ENVIRONMENT = "ROTORDYN_MODAL_MAX_CPU_MINUTES"
#: the default limit [CPU minutes]
DEFAULT_MINUTES = 30.0
#: the largest matrix timed to calibrate the eigen-solutions [states]: from about this size on, a
#: solution's time per operation no longer falls much (one thread, random matrices: 0.93 ns per
#: cubed state at 500, 0.69 at 1,000, 0.57 at 2,000, 0.50 at 4,000), so scaling its time by the
#: cube of the size errs high by less than 2 at 4,000 states; smaller matrices are timed at their
#: own size. Not a power of two: 512 states took 2.4 times 500's (the columns' stride of 4 kB
#: falls on the same cache sets)
_CALIBRATION_STATES = 500
#: timings of the calibration matrix, of which the shortest is taken (a shared machine's single
#: timing of a small matrix varied 10-fold)
_REPEATS = 3
#: the eigenvalues alone (``geev`` without vectors: ``numpy.linalg.eigvals``) take about this share
#: of a solution with vectors (measured 0.51-0.72 on random matrices of 64-4,000 states, 0.54-0.71
#: on the state matrices of benchmarks/bench_cost_estimate.py; the operations' count says 0.4, but
#: the Hessenberg reduction both share is the slower part per operation)
EIGVALS_SHARE = 0.7
#: pessimistic CPU seconds of one eigen-solution per cubed state, for a bound without timing
#: (about ten times what the calibration measures from 500 states on)
_PESSIMISTIC = 1e-8

#: set by :func:`long_work_allowed` alone (a module flag, not a context variable: the analyses'
#: worker threads read it too)
_ALLOWED = [False]


def limit_seconds() -> float:
    """The limit in force [CPU s]: ``ROTORDYN_MODAL_MAX_CPU_MINUTES`` when set, else
    :data:`DEFAULT_MINUTES`."""
    minutes = environment_number(ENVIRONMENT, "a number of CPU minutes > 0 (or inf)", lambda v: v > 0,
                                 DEFAULT_MINUTES)
    return 60.0 * minutes


@contextlib.contextmanager
def long_work_allowed(allowed: bool = True):
    """Run work estimated to exceed the limit of CPU time anyway, inside the ``with`` block: the
    Python form of the command line's ``--allow-long`` (which runs its command inside it).

    Parameters
    ----------
    allowed : bool
        Whether :func:`long_work_is_allowed` holds inside (``False``: the limit holds again, e.g.
        in a part of a longer block); the value before is restored on leaving.

    Examples
    --------
    >>> import rotordyn_modal as rdm
    >>> with rdm.long_work_allowed():                                # doctest: +SKIP
    ...     result = rdm.campbell(model, speeds, modes=4)   # its full-solve fallback not refused

    The memory's limit is not lifted: what cannot fit is refused all the same.
    """
    before = _ALLOWED[0]
    _ALLOWED[0] = bool(allowed)
    try:
        yield
    finally:
        _ALLOWED[0] = before


def long_work_is_allowed() -> bool:
    """Whether work over :func:`limit_seconds` runs anyway: the one answer every check of the CPU
    time reads (inside :func:`long_work_allowed`, ``--allow-long``)."""
    return _ALLOWED[0]


@functools.lru_cache(maxsize=16)
def _timed_eig(size: int) -> float:
    """CPU seconds of one ``numpy.linalg.eig`` with vectors of a random real ``size`` x ``size``
    matrix, with one BLAS thread (as every dense eigen-solution runs): the shortest of
    ``_REPEATS`` timings."""
    from ._batches import one_blas_thread

    matrix = np.random.default_rng(size).standard_normal((size, size))
    with one_blas_thread(72 * size * size):
        np.linalg.eig(matrix[:8, :8])                                   # the library loaded
        shortest = shortest_cpu(lambda: np.linalg.eig(matrix))
    return max(shortest, 1e-6)


def shortest_cpu(call, repeats: int | None = None) -> float:
    """CPU seconds (``time.process_time``) of the shortest of ``repeats`` (default
    :data:`_REPEATS`) calls of ``call()``: a shared machine's single timing varies.

    Parameters
    ----------
    call : callable
        Called with no argument; its result is dropped.
    repeats : int, optional

    Returns
    -------
    float
        Seconds [s].
    """
    best = np.inf
    for _ in range(_REPEATS if repeats is None else repeats):
        start = time.process_time()
        call()
        best = min(best, time.process_time() - start)
    return best


def eig_seconds(n_states: int, timed=None) -> float:
    """CPU seconds of one dense eigen-solution with vectors of ``n_states`` states on this machine,
    one BLAS thread: a timed solution (``timed(size)`` [s], default :func:`_timed_eig`) of
    ``size = min(n_states, _CALIBRATION_STATES)`` states, scaled by ``(n_states / size) ** 3``."""
    size = max(1, min(int(n_states), _CALIBRATION_STATES))
    return (timed or _timed_eig)(size) * (n_states / size) ** 3


def eigvals_seconds(n_states: int, timed=None) -> float:
    """CPU seconds of the eigenvalues alone of ``n_states`` states (``numpy.linalg.eigvals``):
    :data:`EIGVALS_SHARE` of :func:`eig_seconds`."""
    return EIGVALS_SHARE * eig_seconds(n_states, timed)


def duration(seconds: float) -> str:
    """``42 s``, ``12.5 min``, ``9.6 h``, ``1,234 h``."""
    if seconds < 100:
        return f"{seconds:.2g} s"
    if seconds < 6000:
        return f"{seconds / 60:.3g} min"
    if seconds < 360000:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 3600:,.0f} h"


def eigen_solutions_over_limit(n_states: int, count: int) -> tuple[float, float] | None:
    """The estimate [CPU s] of ``count`` dense eigen-solutions of ``n_states`` states and the limit
    [CPU s] where the estimate exceeds the limit in force and ``--allow-long`` was not given; else
    None. A pessimistic bound without any timing passes small work first.

    Parameters
    ----------
    n_states : int
        States of each state matrix.
    count : int or float
        Eigen-solutions (speeds; a share of one counts eigenvalue-only solutions, ``EIGVALS_SHARE``
        each).
    """
    if long_work_is_allowed():
        return None
    limit = limit_seconds()
    if count * _PESSIMISTIC * float(n_states) ** 3 <= limit:
        return None
    seconds = count * eig_seconds(n_states)
    return (seconds, limit) if seconds > limit else None
