"""The CPU time of dense eigen-solutions from the size of the state matrix alone, and the limit of
CPU time in force: the part of :mod:`._work`'s estimate that needs no model.

It stands apart so that the lowest modes' full-solve fallback (:mod:`._lowest`) can be refused
before its work without importing :mod:`._work`, which reads the sweep's modules (``campbell``,
``critical_speeds``) that import ``_lowest``. The limit is ``DEFAULT_MINUTES`` of CPU time; the
environment variable ``ROTORDYN_MODAL_MAX_CPU_MINUTES`` sets another (``inf``: no check).

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

__all__ = ["ENVIRONMENT", "DEFAULT_MINUTES", "limit_seconds", "eig_seconds", "duration", "long_work_allowed",
           "long_work_is_allowed", "eigen_solutions_over_limit"]

#: environment variable: the CPU minutes an analysis may be estimated to take (``inf``: any)
ENVIRONMENT = "ROTORDYN_MODAL_MAX_CPU_MINUTES"
#: the default limit [CPU minutes]
DEFAULT_MINUTES = 30.0
#: the smallest matrix timed to calibrate the eigen-solutions [states]
_SMALLEST = 64
#: exponent of the eigen-solution's time in the number of states (measured 2.5 to 2.8)
_EXPONENT = 2.7
#: pessimistic CPU seconds of one eigen-solution per cubed state, for a bound without timing
#: (about ten times what a 4,000-state solution measured)
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
    matrix, with one BLAS thread (as the sweep's threads run it)."""
    from ._batches import one_blas_thread

    matrix = np.random.default_rng(size).standard_normal((size, size))
    with one_blas_thread(72 * size * size):
        np.linalg.eig(matrix[:8, :8])                                   # the library loaded
        start = time.process_time()
        np.linalg.eig(matrix)
        return max(time.process_time() - start, 1e-6)


def eig_seconds(n_states: int, timed=None) -> float:
    """CPU seconds of one dense eigen-solution (with vectors) of ``n_states`` states on this
    machine: a timed solution (``timed(size)`` [s], default :func:`_timed_eig`) of an eighth of the
    size, at least ``_SMALLEST``, scaled by ``_EXPONENT``."""
    size = max(_SMALLEST, n_states // 8)
    return (timed or _timed_eig)(size) * (n_states / size) ** _EXPONENT


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
    count : int
        Eigen-solutions (speeds).
    """
    if long_work_is_allowed():
        return None
    limit = limit_seconds()
    if count * _PESSIMISTIC * float(n_states) ** 3 <= limit:
        return None
    seconds = count * eig_seconds(n_states)
    return (seconds, limit) if seconds > limit else None
