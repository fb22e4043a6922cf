"""The lowest modes of a speed sweep, exact, without every root at every speed.

Three steps (``docs/theory.md``, "The lowest modes only"):

1. a speed-independent basis: the ``m`` lowest undamped modes of the symmetric parts of the
   stiffness and mass at the sweep's first speed, mass-orthonormal, and ``k`` attachment
   directions (the static response to forces where the bearings act, outside those modes);
2. the projected pencils (``(m + k)`` square) of every speed, solved in one batched
   ``numpy.linalg.eigvals`` of their state matrices, the wanted roots' vectors by inverse
   iteration: starts for the wanted roots;
3. each start refined to the full model's root by Newton's iteration on the full quadratic
   pencil ``Q(s) = s^2 M + s (C + Omega G) + K`` (a banded LU per root and iteration where the
   pencils are banded, with a casing's coordinates as a border; batched dense LU for small
   models; SuperLU otherwise), until the error left is at round-off.

A speed where the refined roots are not ``count + 1`` distinct modes, where a projected root
left unrefined could stand for a lower root, or where the basis cannot be shown to hold every
root below the wanted ones (see :class:`_Bound`), is solved whole instead (the full
eigen-solve), with a notice. Models below ``DENSE_BELOW`` coordinates solve every root of every
speed (eigenvalues alone, the wanted roots' shapes by inverse iteration: :func:`_dense_lowest`;
an undamped gyroscopic model's from a Hermitian matrix of its states: :func:`_gyroscopic_lowest`).
"""

from __future__ import annotations

import functools
import typing
import warnings

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from scipy.linalg.lapack import zgbsv as _zgbsv

from . import _arnoldi, _batches, _cost, _eigensolve, _pencils, _roots, _vectors
from .modal import is_oscillating

__all__ = ["lowest_roots"]

#: Newton iterations at most; the starts from the projected pencils take 2 to 4
_ITERATIONS = 12
#: a step below this times |lam| ends the iteration (quadratic convergence: the root is then
#: exact to round-off, far inside the 1e-9 promised)
_STEP = 1e-11
#: a step below this times |lam| is in Newton's quadratic regime, where the error the step leaves,
#: predicted from the last two steps, ends the iteration when below ``_LEFT`` times |lam| (one
#: solve fewer than waiting for a step at round-off)
_ASYMPTOTIC, _LEFT = 1e-5, 1e-13
#: refined roots closer than this times |lam| are one root reached twice
_SAME = 1e-8

#: models of fewer coordinates solve every root of every speed (one batched eig) and keep the
#: lowest: faster there (benchmarks/README.md, "The lowest modes only": the dense solve is faster
#: up to about 50 coordinates, but from 39 on the Newton roots are kept, 10-20 % dearer: they keep
#: an undamped gyroscopic model's roots on the imaginary axis to 1e-12, the dense eig to 3e-10)
DENSE_BELOW = 38


def lowest_roots(stack, speeds, count: int, progress: bool = False):
    """The ``count`` lowest-frequency oscillating roots of a one-model stack at every speed.

    Parameters
    ----------
    stack : Stack
        One model without frequency-dependent branches (``stack.branch_times`` empty).
    speeds : ndarray, shape (S,) [rad/s]
    count : int
        Modes wanted per speed (>= 1).
    progress : bool
        A progress bar over the speeds where they are solved by shift-invert Arnoldi.

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex [1/s]
        By frequency at each speed (not tracked).
    shapes : ndarray, shape (S, count, n), complex, unit norm
    full : ndarray of bool, shape (S,)
        The speeds solved whole (fallback).
    """
    if stack.n_dof < DENSE_BELOW:           # every root of every speed costs less here
        lam, phi = _small_lowest(stack, speeds, count)
        return lam, phi, np.ones(len(speeds), bool)
    # its dense steps are small BLAS calls (n x n once, m x m per speed): BLAS's own threads only
    # wait for a core on a shared machine (measured up to 10x slower at load 5); the batched
    # eigen-solves and banded solves run in threads of their own
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        values, shapes, ok = _reduced_roots(stack, speeds, count, progress)
    n = stack.n_dof
    out_values = np.full((len(speeds), count), np.nan + 0j)
    out_shapes = np.zeros((len(speeds), count, n), dtype=complex)
    k = min(count, values.shape[1])
    out_values[:, :k], out_shapes[:, :k] = values[:, :k], shapes[:, :k]
    full = ~ok
    if full.any():
        _refuse_long_full(stack, speeds[full], len(speeds), "lowest modes", _UNSERVED)
        warnings.warn(f"lowest modes: {int(full.sum())} of {len(speeds)} speeds solved whole (the reduced basis "
                      "could not be shown to hold every root below the wanted ones there)", stacklevel=3)
        lam, phi = _full_lowest(stack, speeds[full], count)
        out_values[full], out_shapes[full] = lam, phi
    return out_values, out_shapes, full


def _reduced_roots(stack, speeds, count, progress=False):
    """The ``count + 1`` lowest roots of every speed from the reduced basis, refined: roots (S, k),
    shapes (S, k, n) and whether the speed passed every check (S,); by shift-invert Arnoldi
    (:mod:`._arnoldi`, with a progress bar where ``progress``) where that basis would be too large."""
    n = stack.n_dof
    size = min(n, max(3 * count, count + 10))
    pencils = _Pencils(stack, speeds)
    bound = _stack_bound(stack, pencils)
    modes = bound.modes
    want = min(count + 1, size)
    # the highest root wanted, from a few speeds (an underestimate only makes the final check stricter)
    few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _FEW))).astype(int))
    rho = _MARGIN * np.max(np.abs(_projected_starts(pencils, modes[:, :size], want, few)[0]))
    size = min(n, max(_needed_size(bound, rho, size), want))
    _, attached = bound.shares(size, rho)
    if _arnoldi.takes(size + attached.shape[1], n):     # the undamped modes crowd above the wanted roots
        return _arnoldi.lowest(pencils, count, _refined, _distinct, progress)
    starts, vectors = _projected_starts(pencils, np.hstack([modes[:, :size], attached]), want)
    values, shapes, ok = _refined(pencils, starts, vectors)
    ok &= _distinct(values) & _unmissed(starts, values, count)
    # Newton may reorder roots of close frequency: by frequency again
    order = np.argsort(frequency_key(values), axis=1, kind="stable")
    values, shapes = np.take_along_axis(values, order, 1), np.take_along_axis(shapes, order[..., None], 1)
    return values, shapes, ok & _basis_suffices(values, bound, size, attached.shape[1], rho)


def _basis(stack, speed):
    """The undamped modes of the symmetric parts of K and M at ``speed`` (an array of one
    speed): the square roots of their eigenvalues (n,) [rad/s], the symmetric stiffness (n, n,
    ``scipy.sparse`` CSR: a large model's is sparse, and only its departures from K are used),
    and the mass-orthonormal modes (n, n), ascending."""
    sparse = stack.sparse_constant
    if sparse is not None:       # a large model's: dense only for the eigh, from its sparse K and M
        return _sparse_basis(stack, sparse, float(np.ravel(speed)[0]))
    _, stiffness = stack.damping_stiffness(np.zeros(1, int), speed)
    K = stiffness[0] if stiffness.ndim == 3 else stiffness
    K = K + K.T
    K *= 0.5
    symmetric = scipy.sparse.csr_matrix(K)
    # all of them: a dense eigh of n x n costs less than one speed's full solve; on K's own copy,
    # overwritten (K is exactly symmetric: its transpose is the Fortran-ordered array LAPACK
    # takes, not copied again) and a Fortran copy of M: the modes are the only n x n array left
    values, vectors = scipy.linalg.eigh(K.T, np.asfortranarray(stack.M[0]), overwrite_a=True, overwrite_b=True)
    return np.sqrt(np.maximum(values, 0.0)), symmetric, vectors


def _sparse_basis(stack, sparse, speed: float):
    """:func:`_basis` of a large model from its sparse matrices (``sparse``: M, C, G, K as
    ``scipy.sparse``): the symmetric stiffness at ``speed`` [rad/s] summed sparse, and the dense
    K and M made for the eigh alone (overwritten by it, in their own Fortran order: both are
    exactly symmetric), so that the modes, LAPACK's work space and these two are the only n x n
    arrays (the model's own dense matrices and M's inverse are never made)."""
    from ..assembly import sparse_bearing_matrices

    K = sparse.K
    if stack.dependent:
        K = K + sparse_bearing_matrices(stack.models[0], speed, dependent_only=True)[0]
    symmetric = ((K + K.T) * 0.5).tocsr()
    values, vectors = scipy.linalg.eigh(symmetric.toarray().T, sparse.M.toarray().T, overwrite_a=True,
                                        overwrite_b=True)
    return np.sqrt(np.maximum(values, 0.0)), symmetric, vectors


def _stack_bound(stack, pencils, kind=None):
    """The :class:`_Bound` of ``pencils`` on the undamped modes of ``stack`` at the first speed it
    is asked for, computed once per stack: the critical speeds' sub-sweeps of the lowest modes
    reuse the sweep's basis (any speed's basis serves, :class:`_Bound` measures the stiffness's
    departure from it) and its speed-independent products, an ``eigh`` and ``n^3`` products fewer
    each. ``kind``: the bound's class (default :class:`_Bound`)."""
    cached = stack.lowest_basis
    if cached is None:
        omegas, symmetric, modes = _basis(stack, pencils.speeds[:1])
        cached = stack.lowest_basis = {"basis": (omegas, modes, symmetric)}
    bound = (kind or _Bound)(pencils, *cached["basis"], products=cached.get("products"))
    cached["products"] = bound.products
    return bound


class _Bound:
    """How much of a root below ``rho`` can lie outside a basis of the first ``m`` undamped modes
    and ``k`` attachment directions, at every speed (docs/theory.md section 17, "Completeness").

    With ``Phi`` the mass-orthonormal undamped modes of ``(K_0, M)`` (all ``n``), the damping
    ``C + C_b(Omega)`` and the stiffness's departure ``K(Omega) - K_0`` act on a few coordinates
    ``L`` only (bearings, seals, dampers: ``B_c``, ``B_k``, ``|L| x |L|``), the gyroscopic matrix
    ``G`` everywhere. A root ``(s, x = Phi q)`` has, along a left-out mode ``j``,
    ``q_j = -(phi_j^T (s Omega G x + F z)) / (s^2 + omega_j^2)``, ``z = (s B_c + B_k) x_L``; the part
    ``-phi_j^T F z / omega_j^2`` is the static response to the bearing forces (the attachments
    ``K_0^-1 F``, kept in the basis along their ``k`` strongest directions), and the rest is at
    most ``(a + sigma_k) mu (rho |B_c| + |B_k|) + rho |Omega| g`` times ``|q|``, with
    ``a = |diag(rho^2 / (omega_j^2 (omega_j^2 - rho^2))) Phi_L^T|``, ``sigma_k`` the largest
    attachment direction left out, ``mu = |Phi_L|`` and ``g = |diag(1 / (omega_j^2 - rho^2))
    Phi^T G Phi|`` over the left-out modes (Frobenius norms where cheaper, 2-norms of the
    bearings' blocks at every speed).

    Parameters
    ----------
    pencils : _Pencils
    omegas : ndarray, shape (n,) [rad/s]
    modes : ndarray, shape (n, n)
        Mass-orthonormal undamped modes, ascending.
    symmetric : ndarray or scipy.sparse matrix, shape (n, n)
        ``K_0`` [N/m].
    """

    def __init__(self, pencils, omegas, modes, symmetric, products=None):
        self.omegas, self.modes, self.speeds = omegas, modes, pencils.speeds
        # K's departure from K_0, sparse (K_0 dense where a caller gives it so)
        offset = scipy.sparse.csr_matrix(pencils.K) - scipy.sparse.csr_matrix(symmetric)
        offset.eliminate_zeros()
        self.local = np.unique(np.concatenate([*_nonzero(pencils.C), *offset.nonzero(),
                                               pencils.rows, pencils.cols])).astype(int)
        self.damping_norms, self.stiffness_norms = _local_norms(pencils, offset, self.local)
        del offset
        if products is None or not np.array_equal(products[0], self.local):
            reach = np.linalg.norm(modes[self.local], 2) if len(self.local) else 0.0
            local_rows = np.einsum("ij,ij->j", modes[self.local], modes[self.local])
            products = self.local, reach, _gyro_rows(pencils.sparse[2], modes), local_rows
        #: the speed-independent parts, kept for another sweep of the same basis (:func:`_stack_bound`)
        self.products = products
        _, self.reach, self.gyro_rows, self.local_rows = products

    def shares(self, size: int, rho: float, directions: int | None = None, vectors: bool = True):
        """The bound at every speed (S,) for roots up to ``rho`` [rad/s] and the basis of the first
        ``size`` modes with ``directions`` attachment directions (default: the fewest meeting
        ``_SHARE`` at every speed, or all), and those directions (n, k), mass-orthonormal (without
        ``vectors``: their number only, as (0, k) zeros; the singular values alone cost a fraction
        of the vectors where the bearings reach most coordinates, a chain of rotors on bearings)."""
        n = len(self.omegas)
        if size >= n:
            return np.zeros(len(self.speeds)), np.zeros((n, 0))
        if self.omegas[size] <= rho:
            return np.full(len(self.speeds), np.inf), np.zeros((n, 0))
        omega2 = self.omegas[size:] ** 2
        w = 1.0 / (omega2 - rho ** 2)
        gyro = np.sqrt(w ** 2 @ self.gyro_rows[size:])
        attached = np.sqrt((rho ** 2 * w / omega2) ** 2 @ self.local_rows[size:])
        force = self.reach * (rho * self.damping_norms + self.stiffness_norms)
        base = rho * np.abs(self.speeds) * gyro
        if not vectors and np.any(attached * force + base > _SHARE):
            # not met even with every direction (the least the bound can be): no SVD needed to say so
            return attached * force + base, np.zeros((0, min(n - size, len(self.local))))
        static = self.modes[self.local, size:].T / omega2[:, None]            # (n - m, |L|)
        if vectors:
            left, sigma, _ = np.linalg.svd(static, full_matrices=False)
        else:
            left, sigma = None, np.linalg.svd(static, compute_uv=False)
        tails = np.append(sigma, 0.0)                                         # sigma_k, k = 0 .. |L|
        if directions is None:
            meets = np.nonzero((attached + tails) * np.max(force, initial=0.0) + np.max(base) <= _SHARE)[0]
            directions = int(meets[0]) if len(meets) else len(sigma)
        bound = (attached + tails[directions]) * force + base
        if not vectors:
            return bound, np.zeros((0, directions))
        return bound, self.modes[:, size:] @ left[:, :directions]


def _gyro_rows(G, modes):
    """The squared norms of the rows of ``modes^T G modes`` (n,), for a sparse ``G`` (n, n), a
    block of columns at a time (never a second n x n array)."""
    n = modes.shape[1]
    out = np.zeros(n)
    step = max(1, _batches.CHUNK_BYTES // (16 * max(modes.shape[0], 1)))
    for start in range(0, n, step):
        part = modes.T @ (G @ modes[:, start:start + step])          # columns of modes^T G modes
        out += np.einsum("ji,ji->j", part, part)
    return out


def _local_norms(pencils, offset, local):
    """2-norms of the damping ``C + C_b`` and of ``K + K_b - K_0`` on the coordinates ``local``
    at every speed, (S,) each (zeros without such coordinates)."""
    count = len(pencils.speeds)
    if not len(local):
        return np.zeros(count), np.zeros(count)
    place = np.full(offset.shape[0], -1)
    place[local] = np.arange(len(local))
    at = place[pencils.rows] * len(local) + place[pencils.cols]        # the bearings' entries in the block
    offset = offset[local][:, local].toarray()                            # (|L|, |L|)
    out = np.empty((2, count))
    for part in _batches.chunk_slices(count, 16 * len(local) ** 2):
        for i, (constant, entries) in enumerate(((_block(pencils.C, local), pencils.cb), (offset, pencils.kb))):
            matrices = np.repeat(constant.reshape(1, -1), part.stop - part.start, axis=0)
            np.add.at(matrices, (slice(None), at), entries[part])
            # 2-norms of small blocks; Frobenius norms (larger, as cheap as the entries) of large ones
            order = 2 if len(local) <= _EXACT_NORMS else "fro"
            out[i, part] = np.linalg.norm(matrices.reshape(-1, len(local), len(local)), order, axis=(1, 2))
    return out[0], out[1]


def _needed_size(bound, rho, size):
    """The modes of the basis: of the sizes from the first mode above ``rho`` on, the one whose
    bound holds at every speed with the fewest modes and attachment directions together."""
    n = len(bound.omegas)
    first = int(np.searchsorted(bound.omegas, 1.1 * rho))
    best, best_total = n, n
    for m in np.unique(np.round(np.geomspace(max(first, 1), n, 24)).astype(int)):
        if m >= best_total:
            break
        shares, directions = bound.shares(int(m), rho, vectors=False)
        if np.all(shares <= _SHARE) and m + directions.shape[1] < best_total:
            best, best_total = int(m), int(m) + directions.shape[1]
    return best


def _projected_starts(pencils, basis, want, index=None):
    """The ``want`` lowest-frequency oscillating roots of the projected pencils at every speed
    (or at the speeds ``index``) (S, want) and their vectors in full coordinates (S, want, n)."""
    n, m = basis.shape
    index = np.arange(len(pencils.speeds)) if index is None else index
    speeds, cb, kb = pencils.speeds[index], pencils.cb[index], pencils.kb[index]
    S = len(speeds)
    starts = np.empty((S, want), complex)
    vectors = np.empty((S, want, n), complex)
    Wt = basis.T
    if scipy.sparse.issparse(pencils.M):     # a large model's: products with its sparse matrices
        D0, K0, Gr = pencils.projected(index[0], basis)
    else:
        damping0, stiffness0 = (matrix[0] for matrix in pencils.dense(index[:1]))
        D0, K0, Gr = Wt @ damping0 @ basis, Wt @ stiffness0 @ basis, Wt @ pencils.G @ basis
    # the bearings' changes from the first speed, projected entry by entry
    left, right = basis[pencils.rows].T, basis[pencils.cols]
    for part in _batches.chunk_slices(S, 64 * m * m):
        D = D0 + (speeds[part] - speeds[0])[:, None, None] * Gr                  # (P, m, m)
        Kr = np.broadcast_to(K0, D.shape)
        if len(pencils.rows):
            D = D + (left[None] * (cb[part] - cb[:1])[:, None, :]) @ right
            Kr = Kr + (left[None] * (kb[part] - kb[:1])[:, None, :]) @ right
        A = np.zeros((len(D), 2 * m, 2 * m))
        A[:, :m, m:] = np.eye(m)
        A[:, m:, :m] = -Kr              # the basis is mass-orthonormal: W^T M W = I
        A[:, m:, m:] = -D
        lam, shapes = _projected_roots(A, D, Kr, want)
        starts[part] = lam
        vectors[part] = _vectors.unit_rows(shapes @ Wt)
    return starts, vectors


def frequency_key(lam):
    """The sort key of roots ``lam`` (any shape) by frequency: ``Im lam`` of the oscillating roots,
    ``inf`` for the others (pushed to the end)."""
    return np.where(is_oscillating(lam), lam.imag, np.inf)


def _projected_roots(A, damping, stiffness, want):
    """The ``want`` lowest-frequency oscillating roots (P, want) of the projected state matrices
    ``A`` (P, 2 m, 2 m) and their shapes (P, want, m): the roots by a batched ``eigvals``, the shapes
    by one inverse-iteration step each on the projected pencils (``damping``, ``stiffness`` (P, m, m),
    unit mass); a speed where a root picked is not a mode or lies within ``_CLOSE`` of another
    takes ``eig``'s roots and eigenvectors. Threads, one BLAS thread each (BLAS's own threads on
    top oversubscribe the cores)."""
    m = damping.shape[-1]
    lam = _batches._threaded(np.linalg.eigvals, A, item_bytes=24 * (2 * m) ** 2)
    order = _lowest_order(lam, want)
    picked = np.take_along_axis(lam, order, axis=1)
    whole = ~is_oscillating(picked).all(axis=1) | _close(picked, lam, order)
    shapes = np.empty(picked.shape + (m,), complex)
    if whole.any():
        values, vectors = np.linalg.eig(A[whole])
        order = _lowest_order(values, want)
        rows = np.arange(len(values))[:, None]
        picked[whole], shapes[whole] = values[rows, order], vectors[rows, :m, order]
    sure = np.nonzero(~whole)[0]
    if len(sure):
        part = functools.partial(_pencil_shapes_part, np.eye(m))
        shapes[sure] = _batches._threaded(part, stiffness[sure], picked[sure], damping[sure],
                                          item_bytes=48 * want * m * m)
    return picked, shapes


def _lowest_order(lam, want):
    """Where the ``want`` lowest-frequency oscillating roots of each row of ``lam`` are (P, want):
    the oscillating roots by frequency, the others pushed to the end."""
    return np.argsort(frequency_key(lam), axis=-1)[:, :want]


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
        if stack.sparse_constant is not None:     # a large model's, kept sparse (CSR)
            self.M, self.C, self.G, self.K = stack.sparse_constant
        else:
            self.M, self.C, self.G, self.K = form.matrices.M, form.matrices.C, stack.G[0], form.matrices.K
        n = self.M.shape[0]
        self.rows, self.cols, self.kb, self.cb = self._speed_entries(stack, speeds)
        # the sparse LU's pattern: every entry of any of them, column by column (compressed-column order)
        cols, rows = _pattern(self.M, self.C, self.G, self.K, self.rows, self.cols)
        self._values = None       # the matrices' entries on the pattern, made on first use
        self.pattern = rows, cols
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=n))]).astype(np.int32)
        self.indices = rows.astype(np.int32)
        # each bearing entry's place on the pattern (its keys col * n + row ascend)
        self.bearing_at = np.searchsorted(cols * n + rows, self.cols * n + self.rows)
        self.scatter = np.zeros((len(self.rows), n))
        self.scatter[np.arange(len(self.rows)), self.rows] = 1.0
        self.band = _band(rows, cols, n)
        # omega_max^2: the largest ratio of the stiffness's diagonal (with the bearings' at any speed) to the mass's
        diagonal = np.abs(_diagonal(self.K)).copy()
        on = self.rows == self.cols
        if on.any():
            np.maximum.at(diagonal, self.rows[on], np.abs(_diagonal(self.K)[self.rows[on]] + self.kb[:, on]).max(axis=0))
        mass = _diagonal(self.M)
        self.scale = float(np.max(diagonal / np.where(mass > 0, mass, np.inf)))
        # the products Q'(s) x: sparse (a dense complex product of n x n per root cost more than the solves)
        self.sparse = [scipy.sparse.csr_matrix(matrix) for matrix in (self.M, self.C, self.G)]

    def _speed_entries(self, stack, speeds):
        """The entries of K and C that change with the speed (the bearings'): rows (nb,), columns
        (nb,), stiffness and damping (S, nb) each; a subclass adds entries of its own to the
        pattern and the completeness bound's coordinates (``_lowest_branches``)."""
        if stack.dependent:
            return _bearing_entries(stack.models[0], speeds)
        return np.zeros(0, int), np.zeros(0, int), np.zeros((len(speeds), 0)), np.zeros((len(speeds), 0))

    def more_terms(self, index, lam, x, precision=float, magnitude=False):
        """The pencil's terms beyond ``s^2 M + s (C + Omega G + C_b) + K + K_b`` times ``x`` (P, n)
        at roots ``lam`` (P,) in ``precision`` (with ``magnitude``: their entries' moduli times
        ``x``), for the residuals and the round-off estimate: none here (0); the Maxwell branches'
        rational stiffness in ``_lowest_branches``."""
        return 0.0

    def projected(self, first: int, basis):
        """``W^T (C + Omega G + C_b) W``, ``W^T (K + K_b) W`` at the speed ``first`` and ``W^T G W``
        of a basis ``W`` (n, m), (m, m) each, by products with the sparse matrices (a large model's)."""
        Wt = basis.T
        damping = Wt @ ((self.C + self.speeds[first] * self.G) @ basis)
        stiffness, gyroscopic = Wt @ (self.K @ basis), Wt @ (self.G @ basis)
        if len(self.rows):
            left, right = basis[self.rows].T, basis[self.cols]
            damping = damping + (left * self.cb[first]) @ right
            stiffness = stiffness + (left * self.kb[first]) @ right
        return damping, stiffness, gyroscopic

    def dense(self, index):
        """``C + Omega G + C_b`` and ``K + K_b`` of the speeds ``index`` (P,), (P, n, n) each."""
        damping = self.C + self.speeds[index, None, None] * self.G
        stiffness = np.array(np.broadcast_to(self.K, damping.shape))
        damping[:, self.rows, self.cols] += self.cb[index]
        stiffness[:, self.rows, self.cols] += self.kb[index]
        return damping, stiffness

    def derivative_times(self, index, lam, x):
        """``Q'(lam_p) x_p = (2 lam_p M + C + Omega G + C_b) x_p`` (P, n)."""
        M, C, G = self.sparse
        out = 2 * lam[:, None] * (M @ x.T).T + (C @ x.T).T + self.speeds[index, None] * (G @ x.T).T
        return out + (self.cb[index] * x[:, self.cols]) @ self.scatter

    def solve(self, index, lam, rhs):
        """``Q(lam_p)^-1 rhs_p`` for every row: batched dense up to ``_DENSE_DOF`` coordinates; a
        banded LU each where the pencils are banded (a shaft on the ground: its elements couple
        neighbouring nodes), in threads; else a sparse LU each (SuperLU)."""
        n = self.M.shape[0]
        if n <= _DENSE_DOF:         # from the entries: a subclass's own terms (_lowest_branches) included
            rows, cols = self.pattern
            Q = np.zeros((len(lam), n * n), complex)
            Q[:, rows * n + cols] = self._entries(index, lam)
            return _pencils._solve(Q.reshape(-1, n, n), rhs[..., None])[..., 0]
        if self.band is not None:
            width = 2 * self.band.lower + self.band.upper + 1
            return _batches._threaded(self._banded_solve, index, lam, rhs, item_bytes=16 * n * (width + 2))
        out = np.empty(rhs.shape, complex)
        for p in range(len(lam)):
            Q = scipy.sparse.csc_matrix((self._entries(index[p:p + 1], lam[p:p + 1])[0], self.indices, self.indptr),
                                        shape=(n, n))
            out[p] = scipy.sparse.linalg.splu(Q).solve(rhs[p])
        return out

    @property
    def values(self) -> np.ndarray:
        """M, C, G and K on the pattern (nnz, 4), made on first use: every row's entries are one
        product with them (:meth:`_entries`)."""
        if self._values is None:
            rows, cols = self.pattern
            self._values = np.ascontiguousarray(np.stack(
                [_entries_at(matrix, rows, cols) for matrix in (self.M, self.C, self.G, self.K)], axis=-1))
        return self._values

    def _entries(self, index, lam):
        """The pencils' entries on the pattern, (P, nnz) complex: the coefficients ``s^2, s, s Omega, 1``
        of each row (real and imaginary parts, (P, 4, 2)) times the pattern's M, C, G and K (nnz, 4),
        one product (a quarter of the time of the terms summed as complex arrays)."""
        s = lam
        coefficients = np.empty((len(s), 4, 2))
        for term, value in enumerate((s * s, s, s * self.speeds[index])):
            coefficients[:, term, 0], coefficients[:, term, 1] = value.real, value.imag
        coefficients[:, 3] = (1.0, 0.0)
        data = np.matmul(self.values, coefficients).view(complex)[..., 0]      # (P, nnz, 2) as complex
        data[:, self.bearing_at] += s[:, None] * self.cb[index] + self.kb[index]
        return data

    def _banded_solve(self, index, lam, rhs):
        """:meth:`solve` by LAPACK's banded LU with partial pivoting (``zgbsv``), one row at a
        time, and a Schur complement for the border (a casing's coordinates), batched."""
        band = self.band
        n, k = self.M.shape[0], len(band.order) - band.size
        size, width = band.size, 2 * band.lower + band.upper + 1
        out = np.empty(rhs.shape, complex)
        for part in _batches.chunk_slices(len(lam), 16 * n * (width + 3 * k + 2), budget=2**24):
            data = self._entries(index[part], lam[part])
            count = len(data)
            # LAPACK's band storage A(i, j) -> ab[kl + ku + i - j, j], Fortran order: ab.T in C order
            ab = np.zeros((count, size, width), complex)
            ab[:, band.cols[band.inside], band.rows[band.inside]] = data[:, band.inside]
            # the border's columns (every row) and rows (the band's columns), (P, n, k) and (P, k, size)
            columns, rows = np.zeros((count, n, k), complex), np.zeros((count, k, size), complex)
            columns[:, band.place_rows[band.right], band.cols[band.right] - size] = data[:, band.right]
            rows[:, band.place_rows[band.below] - size, band.cols[band.below]] = data[:, band.below]
            b = rhs[part][:, band.order]
            # B^-1 [b_1, E]: one banded solve with k + 1 right-hand sides each
            y = np.empty((count, k + 1, size), complex)
            y[:, 0], y[:, 1:] = b[:, :size], np.swapaxes(columns[:, :size], 1, 2)
            for p in range(count):
                _, _, x, info = _zgbsv(band.lower, band.upper, ab[p].T, y[p].T, overwrite_ab=1, overwrite_b=1)
                y[p] = x.T if info == 0 else np.nan
            solution = np.empty((count, n), complex)
            solution[:, :size] = y[:, 0]
            if k:
                schur = columns[:, size:] - rows @ np.swapaxes(y[:, 1:], 1, 2)                 # (P, k, k)
                border = _pencils._solve(schur, (b[:, size:] - np.einsum("pki,pi->pk", rows, y[:, 0]))[..., None])[..., 0]
                solution[:, size:] = border
                solution[:, :size] -= np.einsum("pki,pk->pi", y[:, 1:], border)
            out[part][:, band.order] = solution
        return out


def _band(rows, cols, n):
    """The band of a pattern ``(rows, cols)`` (nnz,) each: a border of at most ``_BORDER``
    coordinates (a casing's, coupled to distant nodes) set apart, the others in their own order
    or reverse Cuthill-McKee's, whichever is narrower: ``_Band``, or None where the band is too
    wide to pay."""
    border = []
    for _ in range(_BORDER + 1):
        best = _narrowest(rows, cols, n, border)
        if (2 * best.lower + best.upper + 1) * _BAND_SHARE <= n:
            return best
        if len(border) == _BORDER:
            return None
        # the coordinate coupled farthest in the band's order goes to the border
        keep = np.isin(rows, border, invert=True) & np.isin(cols, border, invert=True)
        where = best.place_rows[keep], best.cols[keep]
        reach = np.zeros(n)
        np.maximum.at(reach, best.order[where[0]], np.abs(where[0] - where[1]))
        reach[border] = -1.0
        border.append(int(np.argmax(reach)))
    return None


def _narrowest(rows, cols, n, border):
    """:func:`_band` with the coordinates ``border`` set apart (last)."""
    import scipy.sparse.csgraph

    inner = np.setdiff1d(np.arange(n), border)
    keep = np.isin(rows, inner) & np.isin(cols, inner)
    graph = scipy.sparse.csr_matrix((np.ones(int(keep.sum())), (rows[keep], cols[keep])), shape=(n, n))
    graph = (graph + graph.T)[inner][:, inner]
    best = None
    for order in (inner, inner[scipy.sparse.csgraph.reverse_cuthill_mckee(graph.tocsr(), symmetric_mode=True)]):
        order = np.concatenate([order, np.asarray(border, int)])
        place = np.empty(n, int)
        place[order] = np.arange(n)
        i, j = place[rows], place[cols]
        size = len(inner)
        inside = (i < size) & (j < size)
        lower = int(max(0, np.max(i - j, where=inside, initial=0)))
        upper = int(max(0, np.max(j - i, where=inside, initial=0)))
        if best is None or lower + upper < best.lower + best.upper:
            best = _Band(lower, upper, order, size, i, j, lower + upper + i - j, inside, j >= size, (i >= size) & (j < size))
    return best


class _Band(typing.NamedTuple):
    lower: int
    upper: int
    order: np.ndarray          # (n,) the band's coordinates, then the border's: q[order]
    size: int                  # coordinates in the band
    place_rows: np.ndarray     # (nnz,) each entry's row in that order
    cols: np.ndarray           # (nnz,) each entry's column in that order
    rows: np.ndarray           # (nnz,) each entry's row in LAPACK's band storage
    inside: np.ndarray         # (nnz,) bool: the entry is in the band
    right: np.ndarray          # (nnz,) bool: in a border column
    below: np.ndarray          # (nnz,) bool: in a border row, a band column


def _pattern(M, C, G, K, bearing_rows, bearing_cols):
    """Where any of ``M, C, G, K`` (dense, or ``scipy.sparse`` for a large model) or a bearing
    entry is nonzero: ``(cols, rows)`` (nnz,) each, column by column, rows ascending in each."""
    if scipy.sparse.issparse(M):
        n = M.shape[0]
        found = (abs(M) + abs(C) + abs(G) + abs(K)).tocoo()
        keys = np.unique(np.concatenate([found.col[found.data != 0].astype(np.int64) * n + found.row[found.data != 0],
                                         bearing_cols.astype(np.int64) * n + bearing_rows]))
        return keys // n, keys % n
    pattern = (M != 0) | (C != 0) | (G != 0) | (K != 0)
    pattern[bearing_rows, bearing_cols] = True
    return np.nonzero(pattern.T)


def _entries_at(matrix, rows, cols) -> np.ndarray:
    """``matrix[rows, cols]`` (nnz,) of a dense or ``scipy.sparse`` matrix."""
    if scipy.sparse.issparse(matrix):
        return np.asarray(matrix.tocsr()[rows, cols]).reshape(-1)
    return matrix[rows, cols]


def _diagonal(matrix) -> np.ndarray:
    """The diagonal (n,) of a dense or ``scipy.sparse`` matrix."""
    return matrix.diagonal() if scipy.sparse.issparse(matrix) else np.diagonal(matrix)


def _nonzero(matrix):
    """``numpy.nonzero`` of a dense or ``scipy.sparse`` matrix: (rows, cols)."""
    if scipy.sparse.issparse(matrix):
        coo = matrix.tocoo()
        keep = coo.data != 0
        return coo.row[keep], coo.col[keep]
    return np.nonzero(matrix)


def _block(matrix, local) -> np.ndarray:
    """``matrix[local][:, local]`` dense (|L|, |L|) of a dense or ``scipy.sparse`` matrix."""
    if scipy.sparse.issparse(matrix):
        return matrix.tocsr()[local][:, local].toarray()
    return matrix[np.ix_(local, local)]


def _bearing_entries(model, speeds):
    """The speed-dependent bearings' entries of K and C: positions (nb,), (nb,) and values
    (S, nb), (S, nb) at every speed (the rows and columns a bearing's relative motion touches)."""
    from ..assembly import bearing_coefficients, bearing_motion

    n = model.dofs.n
    keys, stiffness, damping = [], [], []
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            continue
        k6, c6 = bearing_coefficients(model, bearing, speeds)
        where, moves = bearing_motion(model, bearing)
        used = np.nonzero(np.any(moves != 0, axis=0))[0]
        part = moves[:, used]
        index = np.arange(n)[where][used]
        keys.append((index[:, None] * n + index[None, :]).reshape(-1))
        stiffness.append((part.T @ k6 @ part).reshape(len(speeds), -1))
        damping.append((part.T @ c6 @ part).reshape(len(speeds), -1))
    if not keys:
        return np.zeros(0, int), np.zeros(0, int), np.zeros((len(speeds), 0)), np.zeros((len(speeds), 0))
    unique, inverse = np.unique(np.concatenate(keys), return_inverse=True)
    kb, cb = np.zeros((len(speeds), len(unique))), np.zeros((len(speeds), len(unique)))
    np.add.at(kb, (slice(None), inverse), np.hstack(stiffness))
    np.add.at(cb, (slice(None), inverse), np.hstack(damping))
    # the entries some speed's coefficients make nonzero (a bearing's tilt coordinates carry none)
    used = np.any(kb != 0, axis=0) | np.any(cb != 0, axis=0)
    return unique[used] // n, unique[used] % n, kb[:, used], cb[:, used]


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
    last = np.full(len(lam), np.inf)          # the previous relative step (none yet)
    for _ in range(_ITERATIONS):
        todo = np.nonzero(~done)[0]
        if not len(todo):
            break
        u = pencils.solve(index[todo], lam[todo], pencils.derivative_times(index[todo], lam[todo], x[todo]))
        # a singular solve gives inf/nan: that root is left unconverged (ok False), not warned about
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            cu = np.einsum("pi,pi->p", c[todo], u)
            step = np.einsum("pi,pi->p", c[todo], x[todo]) / cu
            lam[todo] -= step
            x[todo] = u / cu[:, None]
            relative = np.abs(step) / np.abs(lam[todo])
            # quadratic convergence (error e' = k e^2, the steps are the errors): the error left after
            # this step is about k relative^2 with k = relative / last^2
            left = relative ** 3 / np.where(np.isfinite(last[todo]), last[todo], np.nan) ** 2
        done[todo] = (relative <= _STEP) | ((relative <= _ASYMPTOTIC) & (left <= _LEFT)) \
            | _stagnant(relative, last[todo], pencils.scale / np.abs(lam[todo]) ** 2)
        last[todo] = relative
    ok = done & np.isfinite(lam)
    # Newton's steps on the double pencil cannot show its round-off (they converge to a nearby
    # pencil's root): where the shape's round-off exceeds _CERTAIN, the root is polished
    polish = np.nonzero(ok)[0]
    polish = polish[_roundoff(pencils, index[polish], lam[polish], x[polish]) > _CERTAIN]
    if len(polish):
        lam[polish], x[polish] = _polished(pencils, index[polish], lam[polish], x[polish])
    return lam.reshape(S, k), _vectors.unit_rows(x.reshape(S, k, n)), ok.reshape(S, k).all(axis=1)


#: a step of at most this many ``eps (omega_max / |lam|)^2`` (``omega_max^2`` the largest ratio
#: ``K_ii / M_ii``, the highest mode's scale) that no longer falls quadratically is round-off: the
#: pencil's conditioning leaves a low root of a fine mesh no more digits (a shaft of 300 elements
#: stalls at relative steps of 1e-9, above ``_STEP``), and the full eigen-solve has the same floor
_ROUNDOFF, _STALLED = 10.0, 0.5


def _stagnant(relative, last, spread):
    """Roots whose relative Newton step ``relative`` is at their round-off floor, ``_ROUNDOFF eps
    spread`` (``spread`` = ``omega_max^2 / |lam|^2``), and has stopped falling (at least
    ``_STALLED`` times the step before)."""
    return (relative <= _ROUNDOFF * np.finfo(float).eps * spread) & (relative >= _STALLED * last)


#: a root whose round-off (:func:`_roundoff`, double precision) exceeds this is polished
#: (:func:`_polished`); measured, the error of Newton's root was 0.01 to 0.35 times that estimate
_CERTAIN = 1e-10
#: the relative accuracy promised for the roots (issue 28: the full model's eigenvalues to 1e-9)
_PROMISED = 1e-9
#: the polishing residual's precision: numpy's extended type (x86: 64-bit significand, 2,048 times
#: double's; where it is double, the polish cannot help and the warning tells the accuracy reached)
_EXTENDED = np.longdouble
#: polishing steps at most (measured: one brings a root from 6e-7 to 6e-11, a second is round-off)
_POLISH_STEPS = 2


def _roundoff(pencils, index, lam, x):
    """The relative error (P,) that double precision can leave in roots ``lam`` (P,) with shapes
    ``x`` (P, n): ``eps |x|^T (|s|^2 |M| + |s| |C + Omega G + C_b| + |K + K_b|) |x| / (|s| |x^H Q'(s) x|)``,
    the first-order change of the root under a change of each entry of the pencil by ``eps`` of
    itself, for the root's own shape (a low mode's smooth shape against stiff elements: the
    products cancel to a small part of their terms). Measured against extended-precision roots, the
    error of Newton's root on the double pencil was 0.01 to 0.35 times it."""
    s, a = np.abs(lam)[:, None], np.abs(x)
    speeds = np.abs(pencils.speeds[index])[:, None]
    M, C, G = (abs(matrix) for matrix in pencils.sparse)
    K = scipy.sparse.csr_matrix(abs(pencils.K))          # sparse: a dense |K| product per root costs n^2
    terms = s * s * (M @ a.T).T + s * ((C @ a.T).T + speeds * (G @ a.T).T) + (K @ a.T).T
    if len(pencils.rows):
        np.add.at(terms, (slice(None), pencils.rows), (s * np.abs(pencils.cb[index]) + np.abs(pencils.kb[index]))
                  * a[:, pencils.cols])
    terms = terms + pencils.more_terms(index, lam, a, magnitude=True)
    derivative = np.abs(np.einsum("pi,pi->p", x.conj(), pencils.derivative_times(index, lam, x)))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.finfo(float).eps * np.einsum("pi,pi->p", a, terms) / (np.abs(lam) * derivative)


def _polished(pencils, index, lam, x):
    """Roots ``lam`` (P,) whose round-off in double precision exceeds ``_CERTAIN``, with shapes ``x``
    (P, n), polished: Newton's steps on the bordered system
    ``[[Q(s), Q'(s) x], [x^H, 0]] [dx; ds] = -[Q(s) x; 0]`` with the residual ``Q(s) x`` in extended
    precision (:func:`_residuals`) and the system solved whole by a sparse LU (well conditioned where
    ``Q(s)`` is nearly singular): iterative refinement, whose accuracy is the residual's (measured on
    a shaft on soft supports: 6e-7 relative before, 6e-11 after; docs/theory.md section 17). Where
    the round-off left (:func:`_roundoff` scaled to the extended precision) may exceed
    ``_PROMISED``, a warning names it. In chunks of bounded memory (the residuals' products).

    Returns
    -------
    lam : ndarray, shape (P,), complex [1/s]; x : ndarray, shape (P, n), complex
    """
    lam, x = lam.copy(), x.copy()
    parts = [scipy.sparse.csr_matrix(matrix) for matrix in (pencils.M, pencils.C, pencils.G, pencils.K)]
    entries = sum(part.nnz for part in parts) + 4 * x.shape[1]
    for chunk in _batches.chunk_slices(len(lam), 64 * entries):
        lam[chunk], x[chunk] = _polish_part(pencils, parts, index[chunk], lam[chunk], x[chunk])
    left = _roundoff(pencils, index, lam, x) * np.finfo(_EXTENDED).eps / np.finfo(float).eps
    uncertain = left > _PROMISED
    if uncertain.any():
        named = _speeds_named(np.unique(pencils.speeds[index[uncertain]]))
        warnings.warn(f"lowest modes: {int(uncertain.sum())} root(s) (at {named}) "
                      f"exact only to about {np.max(left[uncertain]):.1e} relative, not 1e-9: the pencil's round-off "
                      f"(a low mode beside stiff elements), which a residual of {np.finfo(_EXTENDED).nmant + 1} "
                      "significant bits cannot remove", stacklevel=5)
    return lam, x


def _polish_part(pencils, parts, index, lam, x):
    """:func:`_polished`'s steps on some roots (P,), shapes (P, n); ``parts`` are M, C, G, K as CSR."""
    n = x.shape[1]
    active = np.arange(len(lam))
    for _ in range(_POLISH_STEPS):
        residual = _residuals(pencils, parts, index[active], lam[active], x[active])
        derivative = pencils.derivative_times(index[active], lam[active], x[active])
        entries = pencils._entries(index[active], lam[active])
        moved = np.zeros(len(active))
        for j, p in enumerate(active):
            Q = scipy.sparse.csc_matrix((entries[j], pencils.indices, pencils.indptr), shape=(n, n))
            J = scipy.sparse.bmat([[Q, derivative[j][:, None]], [x[p].conj()[None, :], None]], format="csc")
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
                d = scipy.sparse.linalg.splu(J).solve(-np.append(residual[j], 0.0))
            if np.all(np.isfinite(d)):
                x[p] += d[:n]
                lam[p] += d[n]
                moved[j] = abs(d[n]) / abs(lam[p])
        active = active[moved > _STEP]
        if not len(active):
            break
    return lam, x


def _speeds_named(speeds):
    """``600, 1,200, ... rpm`` of speeds [rad/s] (S,), the first ``_NAMED`` of them as given."""
    rpm = ", ".join(f"{speed * 30 / np.pi:,.6g}" for speed in speeds[:_NAMED])
    return f"{rpm}{', ...' if len(speeds) > _NAMED else ''} rpm"


def _residuals(pencils, parts, index, lam, x):
    """``Q(lam_p) x_p`` (P, n) computed in ``_EXTENDED`` precision from the pencil's double entries
    (``parts``: M, C, G, K as CSR), rounded to complex: the products of a low mode's smooth shape
    with stiff elements cancel to a small part of their terms, which double precision leaves at
    round-off."""
    wide = np.result_type(_EXTENDED, 1j)
    X, s = x.astype(wide), lam.astype(wide)[:, None]

    def times(csr):
        products = np.zeros((len(X), csr.nnz + 1), wide)          # a zero past the end: empty last rows
        products[:, :-1] = csr.data.astype(_EXTENDED) * X[:, csr.indices]
        out = np.add.reduceat(products, csr.indptr[:-1], axis=1)
        out[:, csr.indptr[:-1] == csr.indptr[1:]] = 0.0           # reduceat gives an entry for an empty row
        return out

    speed = pencils.speeds[index].astype(_EXTENDED)[:, None]
    M, C, G, K = parts
    out = s * s * times(M) + s * (times(C) + speed * times(G)) + times(K)
    if len(pencils.rows):
        coefficients = s * pencils.cb[index].astype(_EXTENDED) + pencils.kb[index].astype(_EXTENDED)
        np.add.at(out, (slice(None), pencils.rows), coefficients * X[:, pencils.cols])
    out = out + pencils.more_terms(index, s[:, 0], X, wide)
    return out.astype(complex)


#: the largest share of a wanted root's shape the bound allows outside the basis
_SHARE = 0.1

#: the bearings' blocks up to this size get their 2-norms at every speed, larger ones Frobenius norms
_EXACT_NORMS = 64

#: speeds whose projected roots estimate the highest root wanted, and the margin put on it
_FEW, _MARGIN = 5, 1.05


#: pencils up to this many coordinates are solved dense and batched, larger banded ones by a banded
#: LU each (measured, 2,613 pencils: 36 coordinates dense 120 ms, banded 124 ms; 44 coordinates 221
#: against 120 ms)
_DENSE_DOF = 36

#: a banded LU is taken where the band storage (2 kl + ku + 1 rows) is at most this part of n,
#: with at most ``_BORDER`` coordinates set apart as a border (a casing's six motions, mounts)
_BAND_SHARE, _BORDER = 2, 12


def _distinct(values):
    """(S,) no two refined roots of a speed are one root, and all are modes."""
    lam = values
    gaps = np.abs(lam[:, :, None] - lam[:, None, :])
    same = gaps <= _SAME * np.abs(lam[:, :, None])
    np.einsum("sii->si", same)[...] = False
    return ~same.any(axis=(1, 2)) & is_oscillating(lam).all(axis=1)


def _unmissed(starts, values, count):
    """(S,) no projected root left unrefined can stand for a root below the ``count``-th found.

    The starts are the lowest projected roots by frequency (S, k), ``values`` (S, k) their refined
    roots in the same order. A root of the full model missing from ``values`` has a projected root
    near it (see :func:`_basis_suffices`) that was not refined: its frequency is at least the
    highest start's. Taking the largest move from start to root of the speed as how near, that root
    lies above the ``count``-th lowest found when the highest start, less that move, does."""
    if starts.shape[1] <= count:        # a basis of every mode (n <= count): the projected pencil is the full one
        return np.ones(len(values), bool)
    moved = np.max(np.abs(starts - values), axis=1)
    found = np.sort(values.imag, axis=1)[:, count - 1]
    return starts[:, -1].imag - moved > found


def _basis_suffices(values, bound, size, directions, rho):
    """(S,) the basis (``size`` modes, ``directions`` attachment directions) holds at least 90 % of
    every root up to the highest one refined (:class:`_Bound`, at ``rho`` or that root if higher);
    otherwise the projected pencil may lack a root and the speed is solved whole."""
    highest = np.max(np.abs(values), axis=1)
    top = np.max(highest[np.isfinite(highest)], initial=rho)
    shares, _ = bound.shares(size, max(rho, top), directions)
    return np.isfinite(highest) & (shares <= _SHARE)


#: why the reduced basis leaves a speed to the full eigen-solve, for the refusal's message
_UNSERVED = ("the reduced basis could not be shown to hold every root there; an axisymmetric rotor at rest has "
             "double roots")
#: the full eigen-solve's memory is measured against the memory at hand above this [bytes]
_CHECKED_BYTES = 2**30


def _refuse_long_full(stack, speeds, total: int, what: str, why: str, advice: str = "") -> None:
    """Refuse, before it, the full eigen-solve of ``speeds`` [rad/s] (of ``total``) where its
    arrays would not fit in the memory at hand, or where it is estimated to take longer than the
    limit of CPU time (``_cost``, lifted by ``--allow-long``): one line naming the speeds, the
    size, the estimate and the way out (``advice``, default: leave those speeds out). A long
    flexible rotor's full solve is a dense eigen-solution of thousands of states per speed
    (minutes each, GB of memory).

    Raises
    ------
    InputError
        ``MODEL: lowest modes: the full eigen-solve of 1 of 5 speeds (0 rpm; WHY), 1 eigen-solution
        of 16,008 states, would take about 39.8 min of CPU time, more than the limit of 30 min: leave
        those speeds out of the sweep, or add --allow-long (ROTORDYN_MODAL_MAX_CPU_MINUTES sets the
        limit)``; or ``MODEL: ... needs about 4.1 GiB of memory, 2.0 GiB is available: ...``.
    """
    from .._limits import memory_problem
    from ..errors import InputError

    n_states, count = stack.forms[0].n_states, len(speeds)
    named = _speeds_named(speeds)
    source = getattr(stack.models[0], "source", None)
    head = (f"{source + ': ' if source else ''}{what}: the full eigen-solve of {count:,} of {total:,} speeds "
            f"({named}; {why})")
    advice = advice or "leave those speeds out of the sweep"
    solutions = f"{count:,} eigen-solution{'s' if count > 1 else ''} of {n_states:,} states"
    # the state matrices, one part's eigen-solution and the shapes kept
    needed = 8.0 * count * n_states ** 2 + max(_batches.CHUNK_BYTES, 72.0 * n_states ** 2) \
        + 16.0 * count * n_states * stack.n_dof
    if needed >= _CHECKED_BYTES:
        problem = memory_problem(needed, f"{head}, {solutions},", advice)
        if problem:
            raise InputError(problem)
    over = _cost.eigen_solutions_over_limit(n_states, count)
    if over is not None:
        seconds, limit = over
        raise InputError(f"{head}, {solutions}, would take about "
                         f"{_cost.duration(seconds)} of CPU time, more than the limit of {_cost.duration(limit)}: "
                         f"{advice}, or add --allow-long ({_cost.ENVIRONMENT} sets the limit)")


#: speeds named in the refusal at most
_NAMED = 5


#: why a model with frequency-dependent branches is solved whole, for the refusal's message
_BRANCHES = "the mounts' frequency-dependent (Maxwell) branches add states the reduced basis does not hold"


def _full_lowest(stack, speeds, count):
    """The full eigen-solve of some speeds, their ``count`` lowest oscillating roots."""
    lam, phi = stack.solve(stack.sweep(speeds)[0], np.zeros(len(speeds), int))
    return lowest_of(lam, phi, count)


def lowest_of(lam, phi, count):
    """The ``count`` lowest oscillating roots (then the others) of full eigen-solves, by speed:
    ``lam`` (N, m), ``phi`` (N, m, n) -> (N, count), (N, count, n)."""
    order = np.argsort(frequency_key(lam), axis=-1, kind="stable")[:, :count]
    rows = np.arange(len(lam))[:, None]
    return lam[rows, order], phi[rows, order]


# ----------------------------------------------------------------------------------------
# The modes below a frequency (campbell(max_frequency=F), campbell --max-frequency F)

def roots_below(stack, speeds, limit: float, count: int | None = None):
    """Every oscillating root of frequency ``Im lam`` at most ``limit`` at every speed (the lowest
    ``count`` of them where ``count`` is given), each the full model's root to round-off.

    The basis is made complete for ``limit`` (:class:`_Bound` at ``1.05 limit``, or at the
    largest ``|lam|`` of the projected roots below it) instead of for a number of roots; every root
    below the limit is refined with the first above it, and a speed passes the checks of
    :func:`lowest_roots` with the limit in place of the ``count``-th root (no projected root left
    unrefined can stand for a root below it), else it is solved whole.

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (S,) [rad/s]
    limit : float
        Highest frequency wanted, ``Im lam`` [rad/s] (> 0).
    count : int, optional
        At most this many roots per speed (the lowest).

    Returns
    -------
    eigenvalues : ndarray, shape (S, K), complex [1/s]
        By frequency at each speed (not tracked); ``K`` the most roots wanted at any speed. The
        entries past a speed's wanted roots are other roots of the full model (exact, but not
        shown to be the next ones): fillers that let the columns be tracked.
    shapes : ndarray, shape (S, K, n), complex, unit norm
    wanted : ndarray of bool, shape (S, K)
        The roots asked for (the first ones of each row).
    full : ndarray of bool, shape (S,)
        The speeds solved whole.
    """
    reduced = None
    if stack.n_dof >= DENSE_BELOW and not stack.branch_times.shape[1]:
        with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
            reduced = _reduced_below(stack, speeds, limit, count)
    if reduced is None:             # a small model, branches, or a basis of every mode: every root of every speed
        if stack.branch_times.shape[1]:
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency", _BRANCHES, "use fewer speeds")
        elif stack.n_dof >= DENSE_BELOW:
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency",
                              "a basis for the frequency would hold every mode",
                              "use fewer speeds, or a lower frequency")
        values, shapes = _full_lowest(stack, speeds, stack.forms[0].n_states)
        return _cut_below(values, shapes, limit, count) + (np.ones(len(speeds), bool),)
    values, shapes, ok = reduced
    full = ~ok
    if full.any():
        _refuse_long_full(stack, speeds[full], len(speeds), "modes below a frequency", _UNSERVED)
        warnings.warn(f"modes below a frequency: {int(full.sum())} of {len(speeds)} speeds solved whole (the "
                      "reduced basis could not be shown to hold every root below it there)", stacklevel=3)
        lam, phi = _full_lowest(stack, speeds[full], stack.forms[0].n_states)
        if _wanted(lam, limit, count).sum(axis=1).max(initial=0) > values.shape[1]:
            # more roots below the limit than columns (a root the basis missed): every speed whole
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency",
                              "the reduced basis missed a root below it", "use fewer speeds")
            values, shapes = _full_lowest(stack, speeds, stack.forms[0].n_states)
            return _cut_below(values, shapes, limit, count) + (np.ones(len(speeds), bool),)
        k = values.shape[1]
        values[full], shapes[full] = lam[:, :k], phi[:, :k]
    return values, shapes, _wanted(values, limit, count), full


def _wanted(values, limit, count):
    """(S, k) the roots asked for, of roots (S, k) sorted by frequency with the modes first."""
    wanted = is_oscillating(values) & (values.imag <= limit)
    if count is not None:
        wanted[:, count:] = False
    return wanted


def _cut_below(values, shapes, limit, count):
    """Roots (S, k) and shapes by frequency cut to the most wanted at any speed: the roots, the
    shapes and which are wanted."""
    wanted = _wanted(values, limit, count)
    k = int(wanted.sum(axis=1).max(initial=0))
    return values[:, :k], shapes[:, :k], wanted[:, :k]


def _reduced_below(stack, speeds, limit, count):
    """:func:`_reduced_roots` for the roots below ``limit`` [rad/s] (at most ``count``): roots (S, k)
    by frequency, the wanted ones first, shapes (S, k, n) and whether the speed passed every check;
    None where the basis would hold every mode (the full eigen-solve costs less)."""
    n = stack.n_dof
    pencils = _Pencils(stack, speeds)
    bound = _stack_bound(stack, pencils)
    omegas, modes = bound.omegas, bound.modes
    # the largest |lam| below the limit, from a few speeds' projected roots on the modes up to twice it
    few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _FEW))).astype(int))
    size = min(n, int(np.searchsorted(omegas, 2.0 * limit)) + 10)
    starts = _projected_starts(pencils, modes[:, :size], size, few)[0]
    below = _wanted(starts, limit, count)
    rho = _MARGIN * max(limit, np.max(np.abs(starts), where=below, initial=0.0))
    size = min(n, _needed_size(bound, rho, size))
    if size >= n:
        return None
    _, attached = bound.shares(size, rho)
    basis = np.hstack([modes[:, :size], attached])
    starts, vectors = _starts_below(pencils, basis, limit, count, int(below.sum(axis=1).max(initial=0)) + 3)
    values, shapes, ok = _refined(pencils, starts, vectors)
    ok &= _distinct(values) & _unmissed_below(starts, values, limit, count)
    order = np.argsort(frequency_key(values), axis=1, kind="stable")
    values, shapes = np.take_along_axis(values, order, 1), np.take_along_axis(shapes, order[..., None], 1)
    # the bound at the wanted roots (a missed one lies below the limit, :func:`_unmissed_below`)
    wanted = _wanted(values, limit, count)
    return values, shapes, ok & _basis_suffices(np.where(wanted, values, 0), bound, size, attached.shape[1], rho)


def _starts_below(pencils, basis, limit, count, want):
    """The projected roots of every speed up to the first above ``limit`` (or past the ``count``-th),
    the same number at every speed (the most any speed needs): starts (S, k) and vectors (S, k, n).
    ``want`` is a first guess of ``k``, doubled until every speed has a start above the limit."""
    most = basis.shape[1]
    while True:
        want = min(want, most)
        starts, vectors = _projected_starts(pencils, basis, want)
        needed = _wanted(starts, limit, count).sum(axis=1) + 1
        if needed.max() <= want or want == most:
            k = int(min(needed.max(), want))
            return starts[:, :k], vectors[:, :k]
        want *= 2


def _unmissed_below(starts, values, limit, count):
    """:func:`_unmissed` for the roots below ``limit``: (S,) no projected root left unrefined can
    stand for a root below the limit (or below the ``count``-th root found, where lower)."""
    top = np.full(len(values), float(limit))
    if count is not None and values.shape[1] >= count:
        top = np.minimum(top, np.sort(frequency_key(values), axis=1)[:, count - 1])
    moved = np.max(np.abs(starts - values), axis=1)
    return starts[:, -1].imag - moved > top


# ----------------------------------------------------------------------------------------
# Small models' lowest roots from eigenvalues alone

#: a wanted root closer than this times |lam| to another root (or to its conjugate) takes its
#: shape from the full eigen-solve: one inverse-iteration step leaves an error of about its
#: shift (1e-13 |lam|) over that gap
_CLOSE = 1e-4


def _dense_lowest(stack, speeds, count):
    """:func:`_full_lowest` of a small model (``DENSE_BELOW``) from eigenvalues alone: every root of
    every speed by one batched ``eigvals``, the ``count`` lowest oscillating roots' shapes by one
    inverse-iteration step each on the pencil (``_pencils.pencil_shapes``). A speed whose roots
    need their eigenvectors to be judged, whose wanted roots are not all modes, or where a
    wanted root lies within ``_CLOSE`` of another, is solved whole by :func:`_full_lowest`.

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex; shapes : ndarray, shape (S, count, n)
    """
    upper, whole = _eigensolve.upper_eigenvalues(stack.sweep(speeds)[0])
    return _lowest_of_upper(stack, speeds, count, upper, whole)


def _small_lowest(stack, speeds, count):
    """The lowest roots of a small model: :func:`_gyroscopic_lowest` where the model is undamped
    gyroscopic, else :func:`_dense_lowest`."""
    lowest = _gyroscopic_lowest(stack, speeds, count)
    return _dense_lowest(stack, speeds, count) if lowest is None else lowest


def _gyroscopic_lowest(stack, speeds, count):
    """:func:`_dense_lowest` of an undamped gyroscopic model, its roots from the eigenvalues of a
    Hermitian matrix (:func:`_gyroscopic_roots`) instead of ``eigvals`` of the state matrices;
    None for any other model."""
    upper, whole = _gyroscopic_roots(stack, speeds)
    return None if upper is None else _lowest_of_upper(stack, speeds, count, upper, whole)


def _lowest_of_upper(stack, speeds, count, upper, whole):
    """The ``count`` lowest oscillating roots (S, count) of every speed's upper roots ``upper``
    (S, m) and their shapes (S, count, n) by inverse iteration on the pencil; the speeds ``whole``
    (S,), and those where the roots kept are not all modes or one lies within ``_CLOSE`` of another,
    solved whole (:func:`_full_lowest`)."""
    order = np.argsort(frequency_key(upper), axis=-1, kind="stable")[:, :count]
    lam = np.take_along_axis(upper, order, axis=1)
    whole |= ~is_oscillating(lam).all(axis=1) | _close(lam, upper, order)
    shapes = np.empty(lam.shape + (stack.n_dof,), complex)
    if whole.any():
        lam[whole], shapes[whole] = _full_lowest(stack, speeds[whole], count)
    sure = np.nonzero(~whole)[0]
    if len(sure):
        shapes[sure] = _pencil_shapes(stack, speeds[sure], lam[sure])
    return lam, shapes


def _gyroscopic_roots(stack, speeds):
    """The upper roots (S, n) of an undamped gyroscopic model at every speed from the eigenvalues
    of a Hermitian matrix of its ``2 n`` states, and which speeds are to be solved whole (a root
    within the square root of the round-off of zero); ``(None, None)`` for any other model.

    With ``M = L L^T``, ``K_h = L^-1 K L^-T = R^T R`` (both Cholesky: M and K positive definite)
    and ``G_h = L^-1 G L^-T`` (skew), the state ``y = [R x_h, s x_h]``, ``x_h = L^T x``, of a root
    ``s`` of ``s^2 M + s Omega G + K`` solves ``s y = H y``, ``H = [[0, R], [-R^T, -Omega G_h]]``
    real and skew: ``B = -i H`` is Hermitian, its eigenvalues the ``+-omega`` of the roots
    ``s = i omega``. ``eigvalsh`` of ``B`` costs a third of ``eigvals`` of the real state matrix
    (benchmarks/README.md, "Undamped gyroscopic models") and keeps the roots on the imaginary
    axis; within ``eps |B|`` of the roots where ``eig`` of the state matrix is within ``eps |A|``
    (rotor_example: 1e-13 against 1.5e-12 relative, from an extended-precision Newton
    refinement).

    Parameters
    ----------
    stack : Stack
        One model; the route applies where its damping is zero, its stiffness constant, symmetric
        and positive definite, its gyroscopic matrix skew, and it has no Maxwell branches.
    speeds : ndarray, shape (S,) [rad/s]

    Returns
    -------
    upper : ndarray, shape (S, n), complex [1/s], or None
        ``i omega``, ascending.
    whole : ndarray of bool, shape (S,), or None
    """
    hermitian = _hermitian_form(stack)
    if hermitian is None:
        return None, None
    constant, gyroscopic = hermitian
    n = stack.n_dof
    omega = _batches._threaded(functools.partial(_hermitian_eigenvalues, constant, gyroscopic), speeds,
                               item_bytes=64 * n * n)
    # the round-off of each solve (eps |B|_F, as :func:`._roots.round_off` takes it from the
    # balanced state matrix): a root within its square root of zero needs its shape to be judged
    noise = _roots.BACKWARD_FACTOR * np.finfo(float).eps * np.hypot(np.linalg.norm(constant),
                                                                     speeds * np.linalg.norm(gyroscopic))
    whole = omega[:, n] <= _roots.zero_floor(noise)
    return 1j * omega[:, n:], whole


def _hermitian_form(stack):
    """``B(Omega) = B_0 + Omega B_1`` of :func:`_gyroscopic_roots`: ``B_0 = [[0, -i R], [i R^T, 0]]``
    and ``B_1`` (2 n, 2 n), complex, each Hermitian; None where the model is not undamped
    gyroscopic with M and K positive definite."""
    if len(stack) != 1 or stack.dependent or stack.branch_times.shape[1] or np.any(stack.C[0]):
        return None
    M, G, K = stack.M[0], stack.G[0], stack.K[0]
    if not (_within_round_off(K - K.T, K) and _within_round_off(G + G.T, G) and _within_round_off(M - M.T, M)):
        return None             # cross-coupled (or circulatory) stiffness: the state matrices' eigvals
    n = len(M)
    inverse = scipy.linalg.solve_triangular(stack.factor[0], np.eye(n), lower=True, check_finite=False)
    stiffness = inverse @ (0.5 * (K + K.T)) @ inverse.T
    gyroscopic = inverse @ (0.5 * (G - G.T)) @ inverse.T
    try:
        root = np.linalg.cholesky(0.5 * (stiffness + stiffness.T)).T       # K_h = R^T R
    except np.linalg.LinAlgError:       # K singular (a rotor free to move): eigvals of the state matrix
        return None
    constant = np.zeros((2 * n, 2 * n), complex)
    constant[:n, n:] = -1j * root
    constant[n:, :n] = 1j * root.T
    speed_part = np.zeros((2 * n, 2 * n), complex)
    speed_part[n:, n:] = 0.5j * (gyroscopic - gyroscopic.T)
    return constant, speed_part


def _within_round_off(part, matrix) -> bool:
    """``part`` (the departure of ``matrix`` from symmetry or skew symmetry) is round-off of the
    assembly: no entry above ``8 eps`` times the largest of ``matrix``."""
    return bool(np.max(np.abs(part), initial=0.0) <= 8 * np.finfo(float).eps * np.max(np.abs(matrix), initial=0.0))


def _hermitian_eigenvalues(constant, gyroscopic, speeds):
    """Ascending eigenvalues (P, 2 n) of ``constant + speeds[p] gyroscopic`` (Hermitian)."""
    matrices = np.multiply(speeds[:, None, None], gyroscopic)
    matrices += constant
    return np.linalg.eigvalsh(matrices)


def _pencil_shapes(stack, speeds, lam):
    """Unit shapes (S, k, n) of the roots ``lam`` (S, k), one inverse-iteration step each on its
    speed's pencil (``_pencils.pencil_shapes``), the speeds shared between threads."""
    damping, stiffness = stack.damping_stiffness(np.zeros(len(speeds), int), speeds)
    k, n = lam.shape[1], stack.n_dof
    if stiffness.ndim == 2:             # one stiffness for every speed
        part = functools.partial(_pencil_shapes_part, stack.M[0], stiffness)
        return _batches._threaded(part, lam, damping, item_bytes=48 * k * n * n)
    return _batches._threaded(functools.partial(_pencil_shapes_part, stack.M[0]), stiffness, lam, damping,
                              item_bytes=48 * k * n * n)


def _pencil_shapes_part(M, stiffness, lam, damping):
    """:func:`_pencil_shapes` of some speeds: ``stiffness`` (n, n), or (P, n, n) per speed."""
    shapes = _pencils.pencil_shapes(M, damping, stiffness, lam).reshape(-1, M.shape[-1])
    # the phase of eig's state eigenvectors [phi, lam phi]: their largest entry real (up to its
    # sign, which eig leaves open)
    roots = lam.reshape(-1, 1)
    largest = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=-1)[:, None], axis=-1)
    largest = np.where(np.abs(roots) > 1.0, roots * largest, largest)
    shapes *= largest.conj() / np.abs(largest)
    return shapes.reshape(lam.shape + (M.shape[-1],))


def _close(lam, upper, order):
    """(S,) a root of ``lam`` (S, k) lies within ``_CLOSE`` times its modulus of another root of
    ``upper`` (S, m), the upper roots it was picked from (at ``order`` (S, k)), or of its own
    conjugate."""
    distance = np.abs(lam[:, :, None] - upper[:, None, :])
    np.put_along_axis(distance, order[:, :, None], np.inf, axis=-1)          # itself
    nearest = np.minimum(distance.min(axis=-1), 2 * np.abs(lam.imag))
    return (nearest <= _CLOSE * np.abs(lam)).any(axis=1)
