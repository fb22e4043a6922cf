"""Which route serves a lowest-modes sweep, told before the reduced basis's dense set-up
(``docs/theory.md`` section 17, "Crowded spectra: shift-invert Arnoldi").

:func:`_crowded`: a lower bound of the completeness bound from one undamped mode in the middle of
the spectrum (bisection on Sylvester's inertia of ``K_0 - w^2 M``, shift-invert Lanczos), so that a
model whose reduced basis would hold more than half its coordinates goes to
:mod:`._arnoldi` without the ``O(n^3)`` ``eigh`` of every mode; where it is not shown, the reduced
route's own rule decides (:func:`._lowest._reduced_roots`).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from . import _arnoldi, _lowest_bound
from ._lowest_bound import _FEW, _MARGIN
from ._lowest_pencils import _block, _nonzero
from ._lowest_starts import projected_roots_kept
from .._blas import seeded_start

__all__: list[str] = []


#: the cheap test's margins: the highest root wanted taken this much below its estimate from the
#: first modes (the reduced route takes it from the ``eigh``'s), and the lower bound of the
#: completeness bound asked to exceed ``_SHARE`` this many times
_LOWER_RHO, _CLEAR = 0.9, 2.0


#: bisection steps for a mode in the middle of the spectrum (one sparse factorisation each)
_BISECTIONS = 16
#: models of at most this many coordinates take the modes of the cheap test from one dense
#: ``eigh`` of ``(K_0, M)``: below it that costs less than the sparse factorisations (measured at
#: 224 coordinates, ROSS's compressor_example: 5 ms against 37 ms for Lanczos and 16 inertia counts)
_DENSE_MODES = 400


def _crowded(stack, pencils, count=None, limit=None) -> bool:
    """The reduced route's rule would send this sweep to shift-invert Arnoldi
    (:func:`._arnoldi.takes`), shown without that route's dense set-up (the ``eigh`` of every
    undamped mode, the 2-norm of the modes at the bearings, ``Phi^T G Phi``: ``O(n^3)``, about 20 s
    at 2,506 coordinates); False where it is not shown (the set-up decides as before).

    A basis of at most ``n/2`` coordinates leaves out the undamped mode ``j`` of index ``n // 2``
    and every mode above it, and :class:`_Bound`'s share is at least that mode's part of its
    attachment term: ``rho^2 / (omega_j^2 (omega_j^2 - rho^2)) |phi_j,L|^2 (rho |B_c| + |B_k|)``
    (``|phi_j,L|`` is one column of ``Phi_L``: at most its 2-norm, the bound's ``mu``; the norms
    taken no larger than the largest entry, :func:`_local_largest`); where that
    exceeds ``_CLEAR`` times ``_SHARE`` at some speed (or ``omega_j <= rho``), no such basis meets
    the bound. ``rho`` is the reduced route's (``1.05 limit``; for ``count`` roots, from the projected
    roots on the first modes, found here by sparse shift-invert Lanczos, times ``_LOWER_RHO``: the
    term grows with ``rho``); the mode ``j``, or one above it, by bisection on Sylvester's inertia of
    ``K_0 - w^2 M`` (one sparse factorisation each) and shift-invert Lanczos near ``w``. A model of
    at most ``_DENSE_MODES`` coordinates takes the first modes and the mode ``j`` itself from one
    dense ``eigh`` instead (:func:`_cheap_modes`): there it costs less.

    Parameters
    ----------
    stack : Stack
    pencils : _Pencils
    count : int, optional
        The lowest roots wanted (``lowest_roots``).
    limit : float, optional
        The highest frequency wanted [rad/s] (``roots_below``).
    """
    n = stack.n_dof
    if n < _arnoldi.MIN_DOF:
        return False
    size = 0 if count is None else min(n, max(3 * count, count + 10))
    cheap = _cheap_modes(stack, pencils, size)
    if cheap is None:
        return False
    symmetric, mass, modes = cheap
    if count is None:
        rho = _MARGIN * limit
    else:
        speeds = pencils.speeds
        few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _FEW))).astype(int))
        starts = projected_roots_kept(pencils, modes[:, :size], min(count + 1, size), few)
        rho = _LOWER_RHO * _MARGIN * np.max(np.abs(starts))
    middle = stack.__dict__.get("_lowest_middle")     # from the dense eigh of a small model
    if middle is None:
        middle = _mode_above(symmetric, mass, n // 2, rho ** 2, pencils.scale)
    if middle is None:
        return False
    omega, phi = middle
    if omega <= rho:
        return True
    offset = scipy.sparse.csr_matrix(pencils.K) - symmetric
    offset.eliminate_zeros()
    local = np.unique(np.concatenate([*_nonzero(pencils.C), *offset.nonzero(), pencils.rows,
                                      pencils.cols])).astype(int)
    damping_norms, stiffness_norms = _local_largest(pencils, offset, local)
    share = float(np.sum(phi[local] ** 2))
    lower = rho ** 2 / (omega ** 2 * (omega ** 2 - rho ** 2)) * share * (rho * damping_norms + stiffness_norms)
    return bool(np.max(lower, initial=0.0) > _CLEAR * _lowest_bound._SHARE)


def _local_largest(pencils, offset, local):
    """The largest entry of the damping ``C + C_b`` and of ``K + K_b - K_0`` on the coordinates
    ``local`` at every speed, (S,) each: at most their 2-norms and Frobenius norms
    (:func:`_local_norms`), without a dense block per speed."""
    count = len(pencils.speeds)
    if not len(local):
        return np.zeros(count), np.zeros(count)
    at = _lowest_bound.local_entries(pencils, offset.shape[0], local)
    out = []
    for constant, entries in ((_block(pencils.C, local), pencils.cb),
                              (offset[local][:, local].toarray(), pencils.kb)):
        flat = np.abs(constant.reshape(-1))
        flat[at] = 0.0
        largest = np.max(np.abs(constant.reshape(-1)[at] + entries), axis=1, initial=0.0) if len(at) else 0.0
        out.append(np.maximum(np.max(flat, initial=0.0), largest) + np.zeros(count))
    return out[0], out[1]


def _cheap_modes(stack, pencils, size: int):
    """The symmetric stiffness ``K_0`` at the first speed (CSR, as :func:`_basis` makes it), the
    mass (CSC) and the first ``size`` undamped modes (n, size), mass-orthonormal, by sparse
    shift-invert Lanczos (one sparse LU); kept on the stack for its other sweeps; None where
    Lanczos fails. At most ``_DENSE_MODES`` coordinates, every mode by one dense ``eigh``, and the
    mode of index ``n // 2`` (frequency, mass-normalised shape) kept on the stack for :func:`_crowded`,
    and the whole ``eigh`` (with its speed and ``K_0``) for ``_lowest_bound._basis``."""
    cached = stack.__dict__.get("_lowest_cheap")
    if cached is not None and cached[2].shape[1] >= size:
        return cached
    speed = float(np.ravel(pencils.speeds)[0])
    sparse = stack.sparse_constant
    if sparse is not None:
        from ..assembly import sparse_bearing_matrices

        K, mass = sparse.K, scipy.sparse.csc_matrix(sparse.M)
        if stack.dependent:
            K = K + sparse_bearing_matrices(stack.models[0], speed, dependent_only=True)[0]
        symmetric = ((K + K.T) * 0.5).tocsr()
    else:
        _, stiffness = stack.damping_stiffness(np.zeros(1, int), np.array([speed]))
        K = stiffness[0] if stiffness.ndim == 3 else stiffness
        K = K + K.T
        K *= 0.5
        symmetric, mass = scipy.sparse.csr_matrix(K), scipy.sparse.csc_matrix(stack.M[0])
    modes = np.zeros((symmetric.shape[0], 0))
    if symmetric.shape[0] <= _DENSE_MODES:      # every mode by one dense eigh (and the one in the middle)
        values, vectors = scipy.linalg.eigh(symmetric.toarray(), mass.toarray())
        # the same eigh as the completeness bound's basis (_lowest_bound._basis), bit for bit: kept for it
        stack.__dict__["_lowest_eigh"] = speed, symmetric, values, vectors
        middle = symmetric.shape[0] // 2
        stack.__dict__["_lowest_middle"] = np.sqrt(max(values[middle], 0.0)), vectors[:, middle].copy()
        modes = vectors[:, :size].copy()
    elif size:
        try:
            _, modes = scipy.sparse.linalg.eigsh(symmetric.tocsc(), k=size, M=mass, sigma=-1e-6 * pencils.scale,
                                                 which="LM", v0=seeded_start(symmetric.shape[0]))
        except (ValueError, RuntimeError, scipy.sparse.linalg.ArpackError):
            return None
        modes = modes / np.sqrt(np.einsum("ij,ij->j", modes, mass @ modes))
    cached = stack.__dict__["_lowest_cheap"] = (symmetric, mass, modes)
    return cached


def _mode_above(symmetric, mass, index: int, low: float, scale: float):
    """An undamped mode of ``(K_0, M)`` of at least the ``index``-th frequency (0-based, ascending),
    near it: ``(omega [rad/s], mass-normalised shape (n,))``; ``(sqrt(low), zeros)`` where the
    ``index``-th eigenvalue lies below ``low`` [rad^2/s^2]; None where an inertia count or Lanczos
    fails. The bracket ``[low, high)`` of the ``index``-th eigenvalue is narrowed by bisection on
    the number of eigenvalues below ``w^2`` (:func:`._arnoldi._negative` of ``K_0 - w^2 M``); the mode
    is the first at or above ``low`` where exactly ``index`` lie below it (the ``index``-th), else
    the first above ``high``, whose index is at least the count there."""
    def below(value):
        return _arnoldi._negative((symmetric - value * mass).tocsc())

    n = symmetric.shape[0]
    counted = below(low)
    if counted is None:
        return None
    if counted > index:
        return np.sqrt(max(low, 0.0)), np.zeros(n)
    at_low, high = counted, max(4.0 * scale, 2.0 * low)
    for _ in range(8):
        counted = below(high)
        if counted is None:
            return None
        if counted > index:
            break
        low, high, at_low = high, 4.0 * high, counted
    else:
        return None
    for _ in range(_BISECTIONS):
        middle = np.sqrt(low * high) if low > 0 else 0.5 * high
        counted = below(middle)
        if counted is None:
            return None
        if counted > index:
            high = middle
        else:
            low, at_low = middle, counted
    # with exactly ``index`` eigenvalues below ``low``, the first at or above it is the index-th;
    # else (a cluster the bisection could not split) the first at or above ``high``, of a higher index
    edge = low if at_low == index else high
    try:
        values, vectors = scipy.sparse.linalg.eigsh(symmetric.tocsc(), k=min(3, n - 2), M=mass, sigma=edge,
                                                    which="LM", v0=seeded_start(n))
    except (ValueError, RuntimeError, scipy.sparse.linalg.ArpackError):
        return None
    above = np.nonzero(values >= edge)[0]
    if not len(above):
        return None
    j = above[np.argmin(values[above])]
    phi = vectors[:, j] / np.sqrt(vectors[:, j] @ (mass @ vectors[:, j]))
    return np.sqrt(values[j]), phi
