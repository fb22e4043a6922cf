"""The lowest modes of a speed sweep, exact, without every root at every speed.

Three steps (``docs/theory.md``, "The lowest modes only"):

1. a speed-independent basis: the ``m`` lowest undamped modes of the symmetric parts of the
   stiffness and mass at the sweep's first speed, mass-orthonormal;
2. the projected pencils (``m x m``) of every speed, solved in one batched ``numpy.linalg.eig``
   of their ``2m x 2m`` state matrices: starts for the wanted roots;
3. each start refined to the full model's root by Newton's iteration on the full quadratic
   pencil ``Q(s) = s^2 M + s (C + Omega G) + K`` (batched LU solves over speeds and roots),
   until the step is at round-off.

A speed where the refined roots are not ``count + 1`` distinct roots (two starts reaching one
root), or where the basis cannot be shown to hold every root below the wanted ones (see
:func:`_basis_suffices`), is solved whole instead (the full eigen-solve), with a notice.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from . import _batches, _vectors
from .modal import is_oscillating

__all__ = ["lowest_roots"]

#: Newton iterations at most; the starts from the projected pencils take 2 to 4
_ITERATIONS = 12
#: a step below this times |lam| ends the iteration (quadratic convergence: the root is then
#: exact to round-off, far inside the 1e-9 promised)
_STEP = 1e-11
#: refined roots closer than this times |lam| are one root reached twice
_SAME = 1e-8


def lowest_roots(stack, speeds, count: int):
    """The ``count`` lowest-frequency oscillating roots of a one-model stack at every speed.

    Parameters
    ----------
    stack : Stack
        One model without frequency-dependent branches (``stack.branch_times`` empty).
    speeds : ndarray, shape (S,) [rad/s]
    count : int
        Modes wanted per speed (>= 1).

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex [1/s]
        By frequency at each speed (not tracked).
    shapes : ndarray, shape (S, count, n), complex, unit norm
    full : ndarray of bool, shape (S,)
        The speeds solved whole (fallback).
    """
    n = stack.n_dof
    size = first = min(n, max(3 * count, count + 10))
    pencils = _Pencils(stack, speeds)
    omegas, symmetric, modes = _basis(stack, speeds[:1])
    d_norm, e_norm = _coupling_norms(stack, pencils, symmetric)
    want = min(count + 1, size)
    starts, vectors = _projected_starts(pencils, _chosen(stack, speeds, modes, size, first), want)
    # the basis the completeness bound asks for, from the starts (within a few 1e-5 of the roots)
    needed = _needed_size(starts, omegas, d_norm, e_norm)
    if needed > size:
        size = min(n, needed)
        starts, vectors = _projected_starts(pencils, _chosen(stack, speeds, modes, size, first), want)
    values, shapes, ok = _refined(pencils, starts, vectors)
    ok &= _distinct(values) & _basis_suffices(values, omegas, size, d_norm, e_norm)
    out_values = np.full((len(speeds), count), np.nan + 0j)
    out_shapes = np.zeros((len(speeds), count, n), dtype=complex)
    k = min(count, values.shape[1])
    out_values[:, :k], out_shapes[:, :k] = values[:, :k], shapes[:, :k]
    full = ~ok
    if full.any():
        warnings.warn(f"lowest modes: {int(full.sum())} of {len(speeds)} speeds solved whole (the reduced basis "
                      "could not be shown to hold every root below the wanted ones there)", stacklevel=3)
        lam, phi = _full_lowest(stack, speeds[full], count)
        out_values[full], out_shapes[full] = lam, phi
    return out_values, out_shapes, full


def _basis(stack, speed):
    """The undamped modes of the symmetric parts of K and M at ``speed`` (an array of one
    speed): the square roots of their eigenvalues (n,) [rad/s], the symmetric stiffness (n, n),
    and the mass-orthonormal modes (n, n), ascending."""
    _, stiffness = stack.damping_stiffness(np.zeros(1, int), speed)
    K = stiffness[0] if stiffness.ndim == 3 else stiffness
    K = 0.5 * (K + K.T)
    # all of them: a dense eigh of n x n costs less than one speed's full solve
    values, vectors = scipy.linalg.eigh(K, stack.M[0])
    return np.sqrt(np.maximum(values, 0.0)), K, vectors


def _chosen(stack, speeds, modes, size, extra):
    """The basis (n, m): the first ``size`` modes; with speed-dependent bearings joined by the
    first ``extra`` modes of the stiffness at the sweep's last speed (better starts where the
    bearings stiffen with speed)."""
    basis = modes[:, :size]
    if stack.dependent and len(speeds) > 1 and size < len(modes):
        basis = _joined(stack.M[0], basis, _basis(stack, speeds[-1:])[2][:, :extra])
    return basis


def _scaled_norms(pencils, entries, Linv):
    """Frobenius norms of ``L^-1 X_s L^-T`` (S,) of the bearings' entries ``entries`` (S, nb)."""
    rows, cols = pencils.rows, pencils.cols
    out = np.empty(len(entries))
    for part in _batches.chunk_slices(len(entries), 32 * len(Linv) ** 2):
        scaled = (Linv[:, rows][None] * entries[part, None, :]) @ Linv[:, cols].T
        out[part] = np.linalg.norm(scaled, axis=(-2, -1))
    return out


def _needed_size(starts, omegas, d_norm, e_norm):
    """The number of modes whose first left-out one meets :func:`_basis_suffices`'s bound for
    roots up to 1.01 times the highest start, at every speed."""
    rho = 1.01 * np.max(np.abs(starts), axis=1)
    level = np.max(rho ** 2 + (rho * d_norm + e_norm) / _SHARE)
    return int(np.searchsorted(omegas ** 2, level))


def _coupling_norms(stack, pencils, symmetric):
    """Upper bounds of the mass-normalized norms of ``C + Omega G + C_b`` and of ``K(Omega) - K_0``
    at each speed (S,) and (S,): the 2-norms at the first speed plus ``|Omega - Omega_0|`` times
    the gyroscopic matrix's 2-norm plus the Frobenius norms of the bearings' changes."""
    Linv = np.linalg.inv(np.linalg.cholesky(stack.M[0]))

    def scaled(matrix):
        return Linv @ matrix @ Linv.T

    speeds = pencils.speeds
    damping0, stiffness0 = (matrix[0] for matrix in pencils.dense(np.zeros(1, int)))
    gyro = np.linalg.norm(scaled(pencils.G), 2)
    d_norm = np.linalg.norm(scaled(damping0), 2) + np.abs(speeds - speeds[0]) * gyro
    e_norm = np.full(len(speeds), np.linalg.norm(scaled(stiffness0 - symmetric), 2))
    if len(pencils.rows):
        d_norm += _scaled_norms(pencils, pencils.cb - pencils.cb[:1], Linv)
        e_norm += _scaled_norms(pencils, pencils.kb - pencils.kb[:1], Linv)
    return d_norm, e_norm


def _joined(M, first, second):
    """A mass-orthonormal basis of the span of two bases (n, m1) and (n, m2): the speed-dependent
    bearings' stiffness at the sweep's two ends each gives its modes."""
    both = np.hstack([first, second])
    values, vectors = scipy.linalg.eigh(both.T @ M @ both)
    keep = values > 1e-10 * values.max()
    return both @ (vectors[:, keep] / np.sqrt(values[keep]))


def _projected_starts(pencils, basis, want):
    """The ``want`` lowest-frequency oscillating roots of the projected pencils at every speed
    (S, want) and their vectors in full coordinates (S, want, n)."""
    n, m = basis.shape
    speeds = pencils.speeds
    S = len(speeds)
    starts = np.empty((S, want), complex)
    vectors = np.empty((S, want, n), complex)
    Wt = basis.T
    damping0, stiffness0 = (matrix[0] for matrix in pencils.dense(np.zeros(1, int)))
    D0, K0, Gr = Wt @ damping0 @ basis, Wt @ stiffness0 @ basis, Wt @ pencils.G @ basis
    # the bearings' changes from the first speed, projected entry by entry
    left, right = basis[pencils.rows].T, basis[pencils.cols]
    for part in _batches.chunk_slices(S, 64 * m * m):
        D = D0 + (speeds[part] - speeds[0])[:, None, None] * Gr                  # (P, m, m)
        Kr = np.broadcast_to(K0, D.shape)
        if len(pencils.rows):
            D = D + (left[None] * (pencils.cb[part] - pencils.cb[:1])[:, None, :]) @ right
            Kr = Kr + (left[None] * (pencils.kb[part] - pencils.kb[:1])[:, None, :]) @ right
        A = np.zeros((len(D), 2 * m, 2 * m))
        A[:, :m, m:] = np.eye(m)
        A[:, m:, :m] = -Kr              # the basis is mass-orthonormal: W^T M W = I
        A[:, m:, m:] = -D
        # in threads, one BLAS thread each (BLAS's own threads on top oversubscribe the cores)
        lam, vec = _batches._threaded(np.linalg.eig, A, item_bytes=72 * (2 * m) ** 2)
        # oscillating roots by frequency; the others pushed to the end
        key = np.where(is_oscillating(lam), lam.imag, np.inf)
        order = np.argsort(key, axis=-1)[:, :want]
        rows = np.arange(len(D))[:, None]
        starts[part] = lam[rows, order]
        vectors[part] = _vectors.unit_rows(vec[rows, :m, order] @ Wt)
    return starts, vectors


class _Pencils:
    """The full pencils ``Q(s) = s^2 M + s (C + Omega G + C_b(Omega)) + K + K_b(Omega)`` of every
    speed of a sweep: the constant matrices (n, n) and the speed-dependent bearings' few
    entries (S, nb), evaluated once for the sweep.

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (S,) [rad/s]
    """

    def __init__(self, stack, speeds):
        form = stack.forms[0]
        self.speeds = speeds
        self.M, self.C, self.G, self.K = form.matrices.M, form.matrices.C, stack.G[0], form.matrices.K
        n = len(self.M)
        self.rows = self.cols = np.zeros(0, int)
        self.kb = self.cb = np.zeros((len(speeds), 0))
        if stack.dependent:
            from ..assembly import dependent_bearing_matrices

            parts = [(part, *dependent_bearing_matrices(stack.models[0], speeds[part]))
                     for part in _batches.chunk_slices(len(speeds), 32 * n * n)]
            used = np.zeros((n, n), bool)
            for _, K, C in parts:
                used |= np.any(K != 0, axis=0) | np.any(C != 0, axis=0)
            self.rows, self.cols = np.nonzero(used)
            self.kb = np.concatenate([K[:, self.rows, self.cols] for _, K, _ in parts])
            self.cb = np.concatenate([C[:, self.rows, self.cols] for _, _, C in parts])
        # the sparse LU's pattern: every entry of any of them
        pattern = (self.M != 0) | (self.C != 0) | (self.G != 0) | (self.K != 0)
        pattern[self.rows, self.cols] = True
        cols, rows = np.nonzero(pattern.T)                # column by column: compressed-column order
        self.pattern = rows, cols
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=n))]).astype(np.int32)
        self.indices = rows.astype(np.int32)
        where = np.full((n, n), -1)
        where[self.pattern] = np.arange(len(self.pattern[0]))
        self.bearing_at = where[self.rows, self.cols]
        self.scatter = np.zeros((len(self.rows), n))
        self.scatter[np.arange(len(self.rows)), self.rows] = 1.0

    def dense(self, index):
        """``C + Omega G + C_b`` and ``K + K_b`` of the speeds ``index`` (P,), (P, n, n) each."""
        damping = self.C + self.speeds[index, None, None] * self.G
        stiffness = np.array(np.broadcast_to(self.K, damping.shape))
        damping[:, self.rows, self.cols] += self.cb[index]
        stiffness[:, self.rows, self.cols] += self.kb[index]
        return damping, stiffness

    def derivative_times(self, index, lam, x):
        """``Q'(lam_p) x_p = (2 lam_p M + C + Omega G + C_b) x_p`` (P, n)."""
        out = 2 * lam[:, None] * (x @ self.M.T) + x @ self.C.T + self.speeds[index, None] * (x @ self.G.T)
        return out + (self.cb[index] * x[:, self.cols]) @ self.scatter

    def solve(self, index, lam, rhs):
        """``Q(lam_p)^-1 rhs_p`` for every row: batched dense up to ``_DENSE_DOF`` coordinates, else
        a sparse LU each (SuperLU; a shaft's pencils are banded, the stator's few coordinates a
        border)."""
        n = len(self.M)
        if n <= _DENSE_DOF:
            damping, stiffness = self.dense(index)
            Q = (lam[:, None, None] ** 2) * self.M + lam[:, None, None] * damping + stiffness
            return np.linalg.solve(Q, rhs[..., None])[..., 0]
        rows, cols = self.pattern
        m_e, c_e, g_e, k_e = (matrix[rows, cols] for matrix in (self.M, self.C, self.G, self.K))
        out = np.empty(rhs.shape, complex)
        for p in range(len(lam)):
            s, speed = lam[p], self.speeds[index[p]]
            data = s * s * m_e + s * (c_e + speed * g_e) + k_e
            data[self.bearing_at] += s * self.cb[index[p]] + self.kb[index[p]]
            Q = scipy.sparse.csc_matrix((data, self.indices, self.indptr), shape=(n, n))
            out[p] = scipy.sparse.linalg.splu(Q).solve(rhs[p])
        return out


def _refined(pencils, starts, vectors):
    """Newton's iteration on the full quadratic pencil from every start, batched over speeds
    and roots: ``u = Q(s)^-1 Q'(s) x``, ``s <- s - (c^H x)/(c^H u)``, ``x <- u / (c^H u)``
    (``c`` the start vector, fixing the scale). Returns the roots (S, k), unit shapes (S, k, n)
    and whether every root of a speed converged (S,)."""
    S, k, n = vectors.shape
    lam = starts.reshape(-1).copy()
    x = vectors.reshape(-1, n).copy()
    index = np.repeat(np.arange(S), k)
    c = x.conj()
    done = np.zeros(len(lam), bool)
    for _ in range(_ITERATIONS):
        todo = np.nonzero(~done)[0]
        if not len(todo):
            break
        u = pencils.solve(index[todo], lam[todo], pencils.derivative_times(index[todo], lam[todo], x[todo]))
        cu = np.einsum("pi,pi->p", c[todo], u)
        step = np.einsum("pi,pi->p", c[todo], x[todo]) / cu
        lam[todo] -= step
        x[todo] = u / cu[:, None]
        done[todo] = np.abs(step) <= _STEP * np.abs(lam[todo])
    ok = done & np.isfinite(lam)
    return lam.reshape(S, k), _vectors.unit_rows(x.reshape(S, k, n)), ok.reshape(S, k).all(axis=1)


#: the largest share of a wanted root's shape the bound allows outside the basis
_SHARE = 0.1

#: pencils up to this many coordinates are solved dense and batched
_DENSE_DOF = 48


def _distinct(values):
    """(S,) no two refined roots of a speed are one root, and they are still by frequency."""
    lam = values
    gaps = np.abs(lam[:, :, None] - lam[:, None, :])
    same = gaps <= _SAME * np.abs(lam[:, :, None])
    np.einsum("sii->si", same)[...] = False
    ordered = np.all(np.diff(lam.imag, axis=1) >= -_SAME * np.abs(lam[:, 1:]), axis=1)
    return ~same.any(axis=(1, 2)) & ordered & is_oscillating(lam).all(axis=1)


def _basis_suffices(values, omegas, size, d_norm, e_norm):
    """(S,) the undamped modes left out of the basis are far enough above the wanted roots.

    A root ``s`` with shape ``x`` of the full pencil has, along a left-out undamped mode ``j``
    (``omega_j``) of the basis's symmetric stiffness ``K_0``, the modal amplitude
    ``|q_j| <= (|s| d + e) ||x|| / (omega_j^2 - |s|^2)``, ``d`` and ``e`` the mass-normalized
    norms of ``C + Omega G`` and of ``K(Omega) - K_0``. Every root up to the highest one refined,
    ``rho``, is required to lie at least 90 % in the basis: ``(rho d + e) <= 0.1 (omega_m^2 -
    rho^2)``. Otherwise the projected pencil may lack it and the speed is solved whole."""
    if size >= len(omegas):
        return np.ones(len(values), bool)
    rho = np.max(np.abs(values), axis=1)
    margin = omegas[size] ** 2 - rho ** 2
    return (margin > 0) & (rho * d_norm + e_norm <= _SHARE * np.where(margin > 0, margin, 1.0))


def _full_lowest(stack, speeds, count):
    """The full eigen-solve of some speeds, their ``count`` lowest oscillating roots."""
    lam, phi = stack.solve(stack.sweep(speeds)[0], np.zeros(len(speeds), int))
    key = np.where(is_oscillating(lam), lam.imag, np.inf)
    order = np.argsort(key, axis=-1, kind="stable")[:, :count]
    rows = np.arange(len(speeds))[:, None]
    return lam[rows, order], phi[rows, order]
