"""Batches of small dense problems: chunks of bounded memory, thread pools (numpy releases
the GIL), and BLAS held to one thread where its own threads would wait for a core
(:func:`one_blas_thread`, from :mod:`rotordyn_modal._blas`, which the lower floors use too)."""

from __future__ import annotations

import contextlib
import os
import threading
import weakref
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .._blas import BLAS_THREADED_BYTES as _BLAS_THREADED_BYTES  # noqa: F401 - the callers name it here
from .._blas import one_blas_thread
from .._limits import environment_number

__all__ = ["CHUNK_BYTES", "chunk_slices", "concatenated", "one_blas_thread", "reordered_over"]


_THREADS = max(1, min(4, os.cpu_count() or 1))
#: environment variable: the threads of a batch (1: one core, as a study's workers set it)
THREADS_ENVIRONMENT = "ROTORDYN_MODAL_THREADS"


#: batches whose work arrays exceed this are shared between threads [bytes]
_THREAD_BYTES = 2**20
#: ... and batches of linear solves (LU of small pencils, banded solves) from this much: their work
#: is cheap for its memory (a dense LU of 44 complex coordinates 25 us for 93 kB, a banded solve
#: 16 us for 17 kB, against some 3 ms for an ``eig`` of 88 states' 372 kB), and a thread's part of
#: a millisecond or two cost more CPU than it saved (ROSS's speed_tables, ``campbell(modes=12)``
#: at 21 speeds: 41-46 against 37-42 ms of CPU, no shorter in wall time, at load 3)
SOLVE_THREAD_BYTES = 8 * 2**20


#: upper bound of the work arrays of one part of a batch [bytes]
_PART_BYTES = 64 * 2**20


#: memory of one chunk of a sweep or of a stack of systems (matrices, factors, LAPACK's work) [bytes]
CHUNK_BYTES = 512 * 2**20


def chunk_slices(count: int, item_bytes: int, largest: int | None = None, budget: int | None = None) -> list:
    """Consecutive slices of ``count`` items, each holding about ``budget`` of work.

    Parameters
    ----------
    count : int
        Items (matrices, speeds) of the batch.
    item_bytes : int
        Work memory of one item [bytes].
    largest : int, optional
        Most items of one slice.
    budget : int, optional
        Work memory of one slice [bytes]; default ``CHUNK_BYTES``.

    Returns
    -------
    list of slice
    """
    step = max(1, (CHUNK_BYTES if budget is None else budget) // max(int(item_bytes), 1))
    if largest is not None:
        step = min(step, largest)
    return [slice(i, min(i + step, count)) for i in range(0, count, step)]


_POOL: ThreadPoolExecutor | None = None

#: :func:`calling_thread`'s flag, per thread (a pool's worker threads never see it set)
_LOCAL = threading.local()


@contextlib.contextmanager
def calling_thread(active: bool = True):
    """Within it (where ``active``), every batch of :func:`_threaded` called from this thread runs
    in this thread, as with ``ROTORDYN_MODAL_THREADS=1``: each part of a batch is its own, so the
    results are the same bits. For sweeps whose batches take a few milliseconds each, where handing
    the parts to the pool's threads costs more than it saves on a shared machine
    (``campbell._campbell_lowest``)."""
    before = getattr(_LOCAL, "single", False)
    _LOCAL.single = before or bool(active)
    try:
        yield
    finally:
        _LOCAL.single = before


def _forget_pool():
    """A forked child inherits the pool object but not its threads: start afresh."""
    global _POOL
    _POOL = None


def stop_pool(wait: float = 0.5) -> bool:
    """Cancel the batches' parts not started yet, and say whether a worker thread still runs one
    after ``wait`` [s]: the command line's SIGTERM and SIGHUP call it (``cli.main``). A part
    started runs compiled code (LAPACK) that no signal stops, and the interpreter's exit joins the
    pool's threads: minutes of a large sweep's part where the shared machine gives the thread a
    small share of a core. The pool is forgotten (a later batch starts another).

    Parameters
    ----------
    wait : float
        Seconds [s] a running part is given to end.

    Returns
    -------
    bool
        True where a thread of the pool still runs a part: the caller ends the process without
        joining it (``os._exit``), its own clean-up done first.
    """
    import time

    global _POOL
    pool, _POOL = _POOL, None
    if pool is None:
        return False
    pool.shutdown(wait=False, cancel_futures=True)
    end = time.monotonic() + wait
    while any(future.running() for future in list(_SUBMITTED)) and time.monotonic() < end:
        time.sleep(0.02)
    return any(future.running() for future in list(_SUBMITTED))


#: the parts given to the pool (futures; a finished batch's are let go): :func:`stop_pool` reads them
_SUBMITTED = weakref.WeakSet()


def _pooled(function, parts) -> list:
    """``function``'s results on each of ``parts`` (tuples of arguments), in order, run by the pool's
    threads: ``Executor.map``, its parts kept in :data:`_SUBMITTED` (the parts not started are
    cancelled where one fails or a signal stops the wait)."""
    futures = [_POOL.submit(function, *part) for part in parts]
    _SUBMITTED.update(futures)
    try:
        return [future.result() for future in futures]
    finally:
        for future in futures:
            future.cancel()


def _threaded(function, *batches: np.ndarray, item_bytes: int = 0, thread_bytes: int | None = None):
    """Apply a batched numpy routine over the first axis of its arrays using a few threads.

    LAPACK-backed numpy routines and large array arithmetic release the GIL, so
    the parts run in parallel. Set ``ROTORDYN_MODAL_THREADS=1`` (as parameter
    studies do in their worker processes) to stay on one core. ``item_bytes``
    (the work memory per item, a measure of its cost) splits large batches into
    parts of at most about ``_PART_BYTES``, and shares batches beyond
    ``thread_bytes`` (default ``_THREAD_BYTES``; larger for work that is cheap for
    its memory, as banded solves) between threads. ``function`` returns an array or
    a tuple of arrays; the parts' results are concatenated.
    """
    global _POOL
    count = len(batches[0])
    threads = int(environment_number(THREADS_ENVIRONMENT, "a whole number of threads >= 1",
                                     lambda v: v >= 1 and v.is_integer(), _THREADS))
    if getattr(_LOCAL, "single", False):
        threads = 1
    pieces = max(1, min(count, -(-count * item_bytes // _PART_BYTES)))
    if threads > 1 and count * item_bytes >= (_THREAD_BYTES if thread_bytes is None else thread_bytes):
        pieces = max(pieces, min(count, threads))
    if pieces == 1:
        with one_blas_thread(item_bytes):        # as estimated (analysis/_cost.py), on a shared machine too
            return function(*batches)
    parts = [np.array_split(batch, pieces) for batch in batches]
    if threads > 1:
        if _POOL is None or _POOL._max_workers != threads:
            _POOL = ThreadPoolExecutor(threads, thread_name_prefix="rotordyn-eig")
        with one_blas_thread(item_bytes):
            results = _pooled(function, zip(*parts))
    else:
        with one_blas_thread(item_bytes):
            results = [function(*part) for part in zip(*parts)]
    return concatenated(results)


def concatenated(results):
    """The parts' results joined along the first axis: arrays, or tuples of arrays joined
    column by column."""
    if isinstance(results[0], tuple):
        return tuple(np.concatenate(column) for column in zip(*results))
    return np.concatenate(results)


#: rows of pencils built together: their real and imaginary planes stay in the cache [bytes]
_CACHE_BYTES = 2**20


def reordered_over(shapes: np.ndarray, order: np.ndarray, budget: int) -> np.ndarray:
    """``shapes[v, s, order[v, s]]`` for shapes (V, S, m, n) and ``order`` (V, S, c), ``c <= m``,
    written over the first ``c`` columns of ``shapes`` itself, a part of at most ``budget`` bytes
    of the speeds at a time, and returned as a view of them: a reordered copy of the whole would
    double a sweep's largest arrays (two of them at once for a 100-rotor machine: 420 MB at 51
    speeds). A copy, so the parts give the same bits."""
    variants = np.arange(len(order))[:, None, None]
    columns = order.shape[-1]
    for part in chunk_slices(order.shape[1], shapes[:, 0].nbytes, budget=budget):
        shapes[:, part, :columns] = shapes[variants, np.arange(part.start, part.stop)[None, :, None], order[:, part]]
    return shapes[:, :, :columns]
