"""The speed-independent basis of the lowest modes and its completeness bound (``docs/theory.md``
section 17, steps 1 and "Completeness").

:func:`_basis`: the undamped modes of the symmetric parts of the stiffness and mass at the sweep's
first speed (all ``n``, one dense ``eigh``), kept on the stack by :func:`_stack_bound` for its other
sweeps; :class:`_Bound`: how much of a root up to ``rho`` can lie outside the first ``m`` modes and
``k`` attachment directions at every speed, the basis chosen where that share is at most
``_SHARE``.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.csgraph

from . import _batches
from ._lowest_pencils import _block, _nonzero

__all__: list[str] = []

#: the largest share of a wanted root's shape the bound allows outside the basis
_SHARE = 0.1

#: the bearings' blocks up to this size get their 2-norms at every speed, larger ones Frobenius norms
_EXACT_NORMS = 64

#: speeds whose projected roots estimate the highest root wanted, and the margin put on it
_FEW, _MARGIN = 5, 1.05


def _basis(stack, speed):
    """The undamped modes of the symmetric parts of K and M at ``speed`` (an array of one
    speed): the square roots of their eigenvalues (n,) [rad/s], the symmetric stiffness (n, n,
    ``scipy.sparse`` CSR: a large model's is sparse, and only its departures from K are used),
    and the mass-orthonormal modes (n, n), ascending. Where the cheap route test
    (``_lowest_route._cheap_modes``) solved the same ``eigh`` at this speed, its result (the same
    bits: the same K_0 and M in the same routine)."""
    sparse = stack.sparse_constant
    done = stack.__dict__.get("_lowest_eigh")
    if done is not None and sparse is None and done[0] == float(np.ravel(speed)[0]):
        _, symmetric, values, vectors = done
        return np.sqrt(np.maximum(values, 0.0)), symmetric, vectors
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
    bound = (kind or _Bound)(pencils, *cached["basis"], products=cached.get("products"), kept=cached)
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

    def __init__(self, pencils, omegas, modes, symmetric, products=None, kept=None):
        self.omegas, self.modes, self.speeds = omegas, modes, pencils.speeds
        local = _Local.of(pencils, symmetric, kept)
        self.local = local.local
        self.damping_norms, self.stiffness_norms = local.norms(pencils)
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


class _Local:
    """The bound's coordinates ``L`` where the damping and K's departure from ``K_0`` act
    (``local`` (|L|,)), those two matrices' blocks there (|L|, |L|) and where the bearings' entries
    fall in them, and the blocks' norms at each speed asked (:func:`_local_norms`), kept by speed:
    ``campbell``'s checks of the mode links solve the lowest modes again at sweep speeds on the same
    stack, with the same basis (:func:`_stack_bound`), and each speed's norms are its own (the same
    bits whichever speeds are asked with it)."""

    def __init__(self, pencils, symmetric):
        # K's departure from K_0, sparse (K_0 dense where a caller gives it so)
        offset = scipy.sparse.csr_matrix(pencils.K) - scipy.sparse.csr_matrix(symmetric)
        offset.eliminate_zeros()
        self.local = local = np.unique(np.concatenate([*_nonzero(pencils.C), *offset.nonzero(),
                                                       pencils.rows, pencils.cols])).astype(int)
        self.at = local_entries(pencils, offset.shape[0], local) if len(local) else None
        self.blocks = (_block(pencils.C, local), offset[local][:, local].toarray()) if len(local) else None
        self.by_speed = {}

    @classmethod
    def of(cls, pencils, symmetric, kept=None):
        """The :class:`_Local` of ``pencils`` on the basis of ``K_0`` = ``symmetric``, taken from
        ``kept`` (a stack's ``lowest_basis``, whose basis ``symmetric`` is) where a sweep of the same
        kind of pencils with the same bearing entries made it, else made (and kept there)."""
        if kept is None:
            return cls(pencils, symmetric)
        key = ("local", type(pencils).__name__, pencils.rows.tobytes(), pencils.cols.tobytes())
        if key not in kept:
            kept[key] = cls(pencils, symmetric)
        return kept[key]

    def norms(self, pencils):
        """:func:`_local_norms` of ``pencils``' speeds (S,) each, those of a speed asked before
        taken (with its bearings' entries the same), the others computed together."""
        count = len(pencils.speeds)
        if not len(self.local):
            return np.zeros(count), np.zeros(count)
        keys = [(float(speed), pencils.cb[p].tobytes(), pencils.kb[p].tobytes())
                for p, speed in enumerate(pencils.speeds)]
        new = [p for p, key in enumerate(keys) if key not in self.by_speed]
        if new:
            damping, stiffness = _block_norms(self.blocks, self.at, pencils.cb[new], pencils.kb[new])
            self.by_speed.update((keys[p], (damping[i], stiffness[i])) for i, p in enumerate(new))
        both = np.array([self.by_speed[key] for key in keys]).reshape(count, 2)
        return both[:, 0].copy(), both[:, 1].copy()


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


def local_entries(pencils, n: int, local) -> np.ndarray:
    """Where the bearings' entries (``pencils.rows``, ``pencils.cols``) fall in the flattened
    block of the coordinates ``local`` of an (n, n) matrix: (nb,) int."""
    place = np.full(n, -1)
    place[local] = np.arange(len(local))
    return place[pencils.rows] * len(local) + place[pencils.cols]


def _local_norms(pencils, offset, local):
    """2-norms of the damping ``C + C_b`` and of ``K + K_b - K_0`` on the coordinates ``local``
    at every speed, (S,) each (zeros without such coordinates)."""
    count = len(pencils.speeds)
    if not len(local):
        return np.zeros(count), np.zeros(count)
    at = local_entries(pencils, offset.shape[0], local)
    blocks = (_block(pencils.C, local), offset[local][:, local].toarray())        # (|L|, |L|) each
    return _block_norms(blocks, at, pencils.cb, pencils.kb)


def _block_norms(blocks, at, cb, kb):
    """:func:`_local_norms` from the constant blocks of the damping and of K's departure from
    ``K_0`` on ``L`` (``blocks``: two (|L|, |L|)), the bearings' places in them ``at`` (nb,) and
    their entries ``cb``, ``kb`` (S, nb): (S,) each. Each speed's norms are its own."""
    count, size = len(cb), blocks[0].shape[0]
    out = np.empty((2, count))
    for part in _batches.chunk_slices(count, 16 * size ** 2):
        for i, (constant, entries) in enumerate(((blocks[0], cb), (blocks[1], kb))):
            matrices = np.repeat(constant.reshape(1, -1), part.stop - part.start, axis=0)
            np.add.at(matrices, (slice(None), at), entries[part])
            # 2-norms of small blocks; Frobenius norms (larger, as cheap as the entries) of large ones
            order = 2 if size <= _EXACT_NORMS else "fro"
            out[i, part] = np.linalg.norm(matrices.reshape(-1, size, size), order, axis=(1, 2))
    return out[0], out[1]


def _gershgorin_count(centers, radii, limit):
    """At most how many eigenvalues ``s`` with ``0 < Im s < limit`` a real matrix similar to
    ``diag(centers) + F`` has, from its Gershgorin discs (``docs/theory.md`` section 17, "Speeds
    between anchors"): centers ``lam_i + F_ii`` and radii ``sum_{l != i} |F_il|``.

    Every eigenvalue lies in a disc, and a connected part of the discs' union made of ``c`` discs
    holds exactly ``c`` eigenvalues (Gershgorin's theorem, by continuity from ``diag(centers)``).
    A part lying wholly at or above ``limit`` or wholly in the lower half-plane counts none; a part
    in the upper half-plane counts its ``c``; a part reaching the real axis holds conjugate pairs
    and real roots (the matrix is real, the discs symmetric to round-off) and counts its centers
    with ``Im >= 0``, at least as many as its roots above the axis. Damped roots beyond the modes
    (damping ratio above 0.99) are counted like modes: the count can only be too high.

    Parameters
    ----------
    centers : ndarray, shape (J, p), complex [1/s]
    radii : ndarray, shape (J, p) [1/s]
    limit : ndarray, shape (J,) [rad/s]

    Returns
    -------
    ndarray of int, shape (J,)
    """
    # parts of the speeds, in threads: their discs' (p, p) contacts (each speed's count its own)
    if not len(centers):
        return np.zeros(0, int)
    return _batches._threaded(_counted, centers, radii, np.asarray(limit), item_bytes=40 * centers.shape[1] ** 2)


def _counted(centers, radii, limit):
    """:func:`_gershgorin_count` of some speeds: the discs' connected parts from the pairs that touch
    (:func:`_touching`), by ``scipy.sparse.csgraph`` over every speed's discs at once (a part never
    spans two speeds)."""
    J, p = centers.shape
    finite = np.isfinite(centers).all(axis=1) & np.isfinite(radii).all(axis=1)
    c, r = np.where(finite[:, None], centers, 0), np.where(finite[:, None], radii, 0.0)
    first, second = _touching(c, r)
    graph = scipy.sparse.csr_matrix((np.ones(len(first), bool), (first, second)), shape=(J * p, J * p))
    parts, label = scipy.sparse.csgraph.connected_components(graph, directed=False)
    speed = np.zeros(parts, int)
    speed[label] = np.repeat(np.arange(J), p)
    low, high = np.full(parts, np.inf), np.full(parts, -np.inf)
    np.minimum.at(low, label, (c.imag - r).ravel())
    np.maximum.at(high, label, (c.imag + r).ravel())
    size = np.bincount(label, minlength=parts)
    upper = np.bincount(label, weights=(c.imag >= 0).ravel(), minlength=parts).astype(int)
    counted = (low < limit[speed]) & (high > 0)
    counts = np.bincount(speed, weights=np.where(counted, np.where(low > 0, size, upper), 0), minlength=J)
    return np.where(finite, counts.astype(int), np.iinfo(int).max)


#: the imaginary extents of two discs whose distance is compared (:func:`_touching`) are widened by
#: this times their moduli: the extents' round-off cannot drop a pair that touches
_WIDENED = 1e-12


def _touching(centers, radii):
    """The pairs of discs that touch (``|c_a - c_b| <= r_a + r_b``) of every row of ``centers`` and
    ``radii`` (J, p), as places in the flattened rows (J p,) each way: only the pairs whose
    imaginary extents overlap are compared. By each row's discs in the order of their extents'
    lower ends, the discs after a disc that overlap it are the next ones up to the first that starts
    above its upper end: offsets ``k = 1, 2, ...`` in turn while any pair that far apart overlaps
    (the speeds' ``p^2`` distances cost more than finding their few parts, measured on
    ``compressor_example``: 98 discs, 2 % touching)."""
    J, p = centers.shape
    slack = _WIDENED * (np.abs(centers.imag) + radii)
    order = np.argsort(centers.imag - radii - slack, axis=1)
    c, r = np.take_along_axis(centers, order, 1), np.take_along_axis(radii, order, 1)
    low = c.imag - r - np.take_along_axis(slack, order, 1)
    high = c.imag + r + np.take_along_axis(slack, order, 1)
    flat = order + p * np.arange(J)[:, None]
    first, second = [], []
    for k in range(1, p):
        row, at = np.nonzero(low[:, k:] <= high[:, :-k])
        if not len(row):
            break
        near = np.abs(c[row, at] - c[row, at + k]) <= r[row, at] + r[row, at + k]
        first.append(flat[row[near], at[near]])
        second.append(flat[row[near], at[near] + k])
    empty = np.zeros(0, int)
    return np.concatenate(first + [empty]), np.concatenate(second + [empty])
