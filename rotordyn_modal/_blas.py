"""BLAS/LAPACK held to one thread for the dense steps of the analyses (through threadpoolctl
when installed).

Every dense step runs with one BLAS thread: the eigen-solutions (whose CPU time
:mod:`.analysis._cost` estimates for one thread), and the steps around them that had been left to
OpenBLAS's own threads: the mass matrix's inverse and its check, the state matrices' products
(:mod:`.linear_system`), the mass matrix's Cholesky factor (:mod:`.analysis._stack`,
:mod:`.analysis._vectors`), the undamped frequencies of the CPU-time estimate. On a machine whose
cores are shared (by the analyses' own threads, a study's workers, other jobs), BLAS's threads
wait for a core: measured in one process, alternated (``python benchmarks/bench_cost_estimate.py
--blas 406,1000,2006 --repeat 5`` on the 2-core machine at load 10), the threaded call took
(min/median/max of the ratios) 1.2/2.7/12 times one thread's wall time for ``inv`` at 406 x 406,
1.2/3.0/3.3 at 1,000 and 1.3/1.4/1.5 at 2,006; ``cholesky`` 1.3/5.7/7.1 at 1,000 and 2.9/5.9/22
at 2,006; the product ``inv(M) @ M`` 0.92/1.07/1.33 at 1,000 and 1.01/1.05/1.08 at 2,006 (no gain
from the threads). A study's workers hold every library to one thread already
(:func:`.study.execution.worker_initializer`); this is the same limit in the
command line's and the Python API's own process.

:func:`seeded_start`: the one fixed start vector of ARPACK's iterations (and of an inverse
iteration's right-hand side), for every caller on every floor (the shaft's bending frequencies in
:mod:`.model.flexible`, the analyses' Lanczos and Arnoldi, ``check``'s rigid-body count).

:func:`lapack`: a LAPACK routine called through ``ctypes`` (the GIL released), for the dense
eigen-solution (:func:`.analysis._eigensolve.eig`) and the banded solves of
:mod:`.analysis._lowest_pencils`.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import sys

__all__ = ["one_blas_thread", "BLAS_THREADED_BYTES", "seeded_start", "lapack"]

#: the seed of :func:`seeded_start`
_START_SEED = 20261129

#: items (matrices) whose work exceeds this may make BLAS start threads of its own [bytes]
BLAS_THREADED_BYTES = 72 * 48 * 48


def one_blas_thread(item_bytes: int):
    """One BLAS/LAPACK thread each while our own threads share the cores (through
    threadpoolctl when installed): BLAS's own threads on top of ours would oversubscribe
    the cores, which slows large eigenproblems several times over. Small matrices never
    start BLAS threads, and asking threadpoolctl costs about a millisecond: skipped there.

    Parameters
    ----------
    item_bytes : int
        The work memory of one item of the step [bytes] (``72 n**2`` for a matrix of ``n``
        rows): below :data:`BLAS_THREADED_BYTES` nothing is asked.

    Returns
    -------
    context manager
    """
    if item_bytes < BLAS_THREADED_BYTES:
        return contextlib.nullcontext()
    # made again once scipy.linalg has loaded its own BLAS library, which a controller made
    # before would not know (modal's scipy.linalg.eig ran with OpenBLAS's threads)
    controller = _blas_controller("scipy.linalg" in sys.modules)
    return contextlib.nullcontext() if controller is None else controller.limit(limits=1, user_api="blas")


@functools.lru_cache(maxsize=2)
def _blas_controller(scipy_linalg_loaded: bool):
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover
        return None
    return ThreadpoolController()


def seeded_start(n: int):
    """A fixed start vector (n,) of standard normal draws for ARPACK (``eigsh``/``eigs``'s ``v0``)
    and inverse iterations: without one, ARPACK draws its start from a random sequence that runs
    on from call to call in a process, so the modes' last bits (and their signs) depended on how
    many solves the process had made before. The one start of every such call (Lanczos of the
    lowest-modes route test, the shaft's bending frequencies, shift-invert Arnoldi, the rigid-body
    count of ``check``)."""
    import numpy as np

    return np.random.default_rng(_START_SEED).standard_normal(n)


@functools.lru_cache(maxsize=5)
def lapack(name: str):
    """LAPACK's ``zgbsv``, ``zgbtrf``, ``zgbtrs`` or ``dgeev`` as a ``ctypes`` function (its pointer
    from ``scipy.linalg.cython_lapack``; ``ctypes`` releases the GIL during the call), or None where
    it cannot be had."""
    try:
        from scipy.linalg import cython_lapack

        capsule = cython_lapack.__pyx_capi__[name]
        get_name = ctypes.PYFUNCTYPE(ctypes.c_char_p, ctypes.py_object)(("PyCapsule_GetName", ctypes.pythonapi))
        pointer = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object, ctypes.c_char_p)(
            ("PyCapsule_GetPointer", ctypes.pythonapi))
        address = pointer(capsule, get_name(capsule))
    except (ImportError, AttributeError, KeyError, ValueError, OSError):   # pragma: no cover
        return None
    arguments = {"zgbsv": 10, "zgbtrf": 8, "zgbtrs": 11, "dgeev": 14}[name]
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * arguments))(address) if address else None
