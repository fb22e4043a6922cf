"""Batched eigen-solutions of the speed-dependent state matrix, whirl and MAC.

Speed: eigenvalues and eigenvectors of all speeds come from one batched LAPACK
call split over threads (numpy releases the GIL); a mode shape is the
displacement part of its state eigenvector. (One step of inverse iteration on the
quadratic pencil ``Q(lam) = lam^2 M + lam (C + Omega G) + K`` per mode, which an
earlier version used, costs as much for 6 coordinates and grows as n^4 per speed;
it still gives the shape at a single known eigenvalue, e.g. at a critical speed.)
"""

from __future__ import annotations

import contextlib
import functools
import os
from concurrent.futures import ThreadPoolExecutor

from typing import NamedTuple

import numpy as np

from ..assembly import add_rotor_bodies, body_inertias
from ..model.dofs import frame_block
from ..model.geometry import skew

__all__ = ["select_upper", "upper_indices", "upper_shapes", "one_blas_thread", "eigenvalues_of", "solve_batch",
           "pencil_shapes", "PencilFactors", "PencilRows", "SparseLayout", "sparse_layout", "SPARSE_DOF",
           "SPARSE_DENSITY", "BATCHED_DOF", "nearest_roots", "NEAREST_ROOTS_DOF",
           "residual_inverse_iteration",
           "chunk_slices", "concatenated", "CHUNK_BYTES", "whirl_forms", "rotor_whirl_forms", "stacked_forms", "whirl_ratios",
           "whirl_labels", "row_norms", "unit_rows", "mass_normalized", "mac_matrix", "real_product",
           "quadratic_forms", "WhirlForms", "OSCILLATORY_TOLERANCE", "WHIRL_TOLERANCE"]

#: |Im lam| below this fraction of the largest |lam| of a speed counts as non-oscillatory
OSCILLATORY_TOLERANCE = 1e-6
#: |whirl ratio| below this counts as no whirl (a straight-line orbit): for an elliptic
#: orbit the ratio is 2ab/(a^2+b^2), so this is a minor/major axis ratio of 5e-4
WHIRL_TOLERANCE = 1e-3

_THREADS = max(1, min(4, os.cpu_count() or 1))
#: batches whose work arrays exceed this are shared between threads [bytes]
_THREAD_BYTES = 2**20
#: upper bound of the work arrays of one part of a batch [bytes]
_PART_BYTES = 64 * 2**20
_START_SEED = 20261122
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


def _start_vectors(m: int, n: int) -> np.ndarray:
    """Fixed pseudo-random complex start vectors of inverse iteration, shape (m, n)."""
    return _start_block(max(64, m, n))[:m, :n]


@functools.lru_cache(maxsize=4)
def _start_block(size: int) -> np.ndarray:
    draws = np.random.default_rng(_START_SEED).standard_normal((2, size, size))
    return draws[0] + 1j * draws[1]


_POOL: ThreadPoolExecutor | None = None


def _forget_pool():
    """A forked child inherits the pool object but not its threads: start afresh."""
    global _POOL
    _POOL = None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def _threaded(function, *batches: np.ndarray, item_bytes: int = 0):
    """Apply a batched numpy routine over the first axis of its arrays using a few threads.

    LAPACK-backed numpy routines and large array arithmetic release the GIL, so
    the parts run in parallel. Set ``ROTORDYN_MODAL_THREADS=1`` (as parameter
    studies do in their worker processes) to stay on one core. ``item_bytes``
    (the work memory per item, a measure of its cost) splits large batches into
    parts of at most about ``_PART_BYTES``, and shares batches beyond
    ``_THREAD_BYTES`` between threads. ``function`` returns an array or a tuple
    of arrays; the parts' results are concatenated.
    """
    global _POOL
    count = len(batches[0])
    threads = int(os.environ.get("ROTORDYN_MODAL_THREADS", _THREADS))
    pieces = max(1, min(count, -(-count * item_bytes // _PART_BYTES)))
    if threads > 1 and count * item_bytes >= _THREAD_BYTES:
        pieces = max(pieces, min(count, threads))
    if pieces == 1:
        return function(*batches)
    parts = [np.array_split(batch, pieces) for batch in batches]
    if threads > 1:
        if _POOL is None or _POOL._max_workers != threads:
            _POOL = ThreadPoolExecutor(threads, thread_name_prefix="rotordyn-eig")
        with one_blas_thread(item_bytes):
            results = list(_POOL.map(function, *parts))
    else:
        results = [function(*part) for part in zip(*parts)]
    return concatenated(results)


def concatenated(results):
    """The parts' results joined along the first axis: arrays, or tuples of arrays joined
    column by column."""
    if isinstance(results[0], tuple):
        return tuple(np.concatenate(column) for column in zip(*results))
    return np.concatenate(results)


#: items (matrices) whose work exceeds this may make BLAS start threads of its own [bytes]
_BLAS_THREADED_BYTES = 72 * 48 * 48


def one_blas_thread(item_bytes: int):
    """One BLAS/LAPACK thread each while our own threads share the cores (through
    threadpoolctl when installed): BLAS's own threads on top of ours would oversubscribe
    the cores, which slows large eigenproblems several times over. Small matrices never
    start BLAS threads, and asking threadpoolctl costs about a millisecond: skipped there."""
    if item_bytes < _BLAS_THREADED_BYTES:
        return contextlib.nullcontext()
    controller = _blas_controller()
    return contextlib.nullcontext() if controller is None else controller.limit(limits=1, user_api="blas")


@functools.lru_cache(maxsize=1)
def _blas_controller():
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # pragma: no cover
        return None
    return ThreadpoolController()


def upper_shapes(matrices: np.ndarray, n: int):
    """Upper eigenvalues (see :func:`upper_indices`) and unit-norm displacement shapes of a
    stack of state matrices: ``numpy.linalg.eig`` in threads and parts of bounded memory, each
    part's eigenvectors reduced to its shapes at once (the parts' results are a quarter of
    the eigenvectors, so joining them copies little).

    Parameters
    ----------
    matrices : ndarray, shape (R, n_states, n_states)
    n : int
        Number of generalized coordinates (the displacement rows of the eigenvectors).

    Returns
    -------
    eigenvalues : ndarray, shape (R, m), complex; shapes : ndarray, shape (R, m, n), complex
    """
    size = matrices.shape[-1]
    return _threaded(functools.partial(_upper_part, n=n), matrices, item_bytes=72 * size * size)


def _upper_part(matrices: np.ndarray, n: int):
    values, vectors = np.linalg.eig(matrices)
    index, eigenvalues = upper_indices(values)
    # advanced indices apart put their axes first: shapes[r, k, j] = vectors[r, j, index[r, k]]
    shapes = vectors[np.arange(len(vectors))[:, None], :n, index]
    return eigenvalues, unit_rows(shapes)


def eigenvalues_of(matrices: np.ndarray) -> np.ndarray:
    """``numpy.linalg.eigvals`` of a stack of matrices, in threads and parts of bounded memory."""
    size = matrices.shape[-1]
    return _threaded(np.linalg.eigvals, matrices, item_bytes=24 * size * size)


def select_upper(values: np.ndarray) -> np.ndarray:
    """Pick the upper half of each row of eigenvalues; one of each conjugate pair and the smaller half of the real roots."""
    return upper_indices(values)[1]


def upper_indices(values: np.ndarray):
    """Where the upper half of each row of eigenvalues sits, and those eigenvalues.

    Returns
    -------
    index : ndarray of int, shape (..., n)
        Positions in ``values`` (and in the columns of the eigenvector matrices).
    upper : ndarray, shape (..., n), complex
        Sorted by imaginary part, then real part (one of each conjugate pair and the smaller half of the real roots); roots
        whose imaginary part is round-off are made real.
    """
    n = values.shape[-1] // 2
    magnitude = np.abs(values)
    scale = magnitude.max(axis=-1, keepdims=True)
    tol = OSCILLATORY_TOLERANCE * np.where(scale > 0, scale, 1.0)
    imag = np.where(np.abs(values.imag) <= tol, 0.0, values.imag)
    # by imaginary part; within the real block the smaller |lam| last, so that the upper half
    # takes it
    order = np.lexsort((-magnitude, imag), axis=-1)
    chosen = order[..., n:]
    along = _gather(values.shape)
    upper = along(values, chosen)
    upper = np.where(along(imag, chosen) == 0.0, upper.real + 0j, upper)
    final = np.lexsort((upper.real, upper.imag), axis=-1)
    return along(chosen, final), along(upper, final)


def _gather(shape):
    """``numpy.take_along_axis(array, index, axis=-1)`` for arrays of leading shape ``shape[:-1]``;
    for rows (2-D) one advanced index with the row numbers made once (the same elements, without
    take_along_axis's per-call index building)."""
    if len(shape) != 2:
        return lambda array, index: np.take_along_axis(array, index, axis=-1)
    rows = np.arange(shape[0])[:, None]
    return lambda array, index: array[rows, index]


def pencil_shapes(M, damping, stiffness, eigenvalues, branches=None) -> np.ndarray:
    """One inverse-iteration step per row for a single known eigenvalue: ``Q(lam) phi = 0``.

    Parameters
    ----------
    M : ndarray, shape (P, n, n) or (n, n)
        Each row's mass, or one for all.
    damping, stiffness : ndarray, shape (P, n, n)
        Each row's ``C + Omega G`` and stiffness.
    eigenvalues : ndarray, shape (P,), complex
    branches : (ndarray (P, n_b, n, n), ndarray (P, n_b)), optional
        Each row's Maxwell branches (stiffness, relaxation times).

    Returns
    -------
    ndarray, shape (P, n), complex, unit norm
    """
    lam = np.asarray(eigenvalues, dtype=complex)
    shifted = lam + 1e-13 * (np.abs(lam) + 1e-300) * (1 + 1j)   # round-off shift keeps an exactly singular pencil solvable
    pencil = _quadratic(M, damping, stiffness, shifted)
    if branches is not None and branches[1].shape[-1]:
        stiffness_b, times = branches
        factor = shifted[:, None] * times / (1 + shifted[:, None] * times)        # (P, n_b)
        pencil += np.einsum("pb,pbij->pij", factor, stiffness_b)
    start = np.broadcast_to(_start_vectors(1, M.shape[-1])[0][:, None], pencil.shape[:-1] + (1,))
    return unit_rows(_solve(pencil, start)[..., 0])


#: rows of pencils built together: their real and imaginary planes stay in the cache [bytes]
_CACHE_BYTES = 2**20


#: pencils of at most this many coordinates are kept whole and solved in one batched call;
#: larger ones are factored once (LU per row) and solved by triangular substitution
BATCHED_DOF = 48


#: pencils of at least this many coordinates, of which at most ``SPARSE_DENSITY`` of the entries
#: can be nonzero, are factored as sparse matrices (SuperLU): a large machine's rotors couple only
#: to their neighbours and the casing, so its pencils' factors fill in little (at 151 coordinates
#: and 11 % nonzero a sparse LU costs 0.6 of a dense one, at 301 and 5 % a sixth; at 101 and 16 %
#: it costs twice as much)
SPARSE_DOF = 150
SPARSE_DENSITY = 0.15


class SparseLayout(NamedTuple):
    """Compressed-column layout of the entries that may be nonzero in a model's pencils: the
    row and column of each stored entry, in the layout's order, and the columns' starts."""

    rows: np.ndarray
    cols: np.ndarray
    starts: np.ndarray

    def matrix(self, data):
        """The ``scipy.sparse.csc_matrix`` with values ``data`` (nnz,) at the layout's entries."""
        from scipy.sparse import csc_matrix

        n = len(self.starts) - 1
        return csc_matrix((data, self.rows, self.starts), shape=(n, n))


def sparse_layout(pattern) -> SparseLayout | None:
    """The layout of the pencils whose possible nonzeros are ``pattern`` (n, n) bool, or None
    where they are better factored dense (see ``SPARSE_DOF``)."""
    n = len(pattern)
    if n < SPARSE_DOF or np.count_nonzero(pattern) > SPARSE_DENSITY * n * n:
        return None
    cols, rows = np.nonzero(pattern.T)                        # column by column, rows ascending
    return SparseLayout(rows.astype(np.int32), cols, np.searchsorted(cols, np.arange(n + 1)).astype(np.int32))


def _sparse_lu(pencils, row, shift):
    """SuperLU factors of row ``row``'s pencil ``Q(shift)`` (or None where it is singular), with
    the row's sparse parts (:meth:`~._stack.Pencils.sparse_parts`: layout, mass, damping,
    stiffness).

    The minimum-degree ordering of ``A^T + A`` suits these structurally symmetric pencils (a
    tenth of COLAMD's fill at 506 coordinates)."""
    from scipy.sparse.linalg import splu

    parts = layout, mass, damping, stiffness = pencils.sparse_parts(row)
    try:
        return splu(layout.matrix((shift * shift) * mass + shift * damping + stiffness), permc_spec="MMD_AT_PLUS_A"), parts
    except RuntimeError:            # exactly singular: its solves give NaN, as a dense LU's give inf
        return None, parts


class PencilFactors:
    """Factorisations of the quadratic pencils ``Q(s) = s^2 M + s D + K`` of many rows, kept for
    repeated solves with ``Q(s)`` and ``Q(s)^H`` (see :func:`residual_inverse_iteration`).

    Small pencils are kept as they are and solved together in one batched LAPACK call each time
    (a factorisation of a few coordinates costs less than the Python calls around it); larger
    ones are factored once per row, sparse (SuperLU) where the model's layout is sparse
    (:func:`sparse_layout`), else dense (``getrf``), and solved by substitution (O(nnz) or O(n^2)).

    Parameters
    ----------
    count : int
        Rows.
    n : int
        Coordinates.
    """

    def __init__(self, count: int, n: int):
        self.whole = n <= BATCHED_DOF
        self.matrices = np.empty((count if self.whole else 0, n, n), dtype=complex)   # small pencils, whole
        self.factors = [None] * count            # larger: each row's SuperLU object or (LU, pivots)
        self.ready = np.zeros(count, dtype=bool)

    def factor(self, rows, pencils, shifts):
        """Factor ``Q(shifts[i])`` of row ``i`` of ``pencils`` (a :class:`~._stack.Pencils`, one row
        per storage row in ``rows``) into storage ``rows[i]``; dense ones a few rows at a time
        (each part's pencils stay in the cache). Returns the small pencils' matrices
        ``Q(shifts)`` (P, n, n), as stored (None for the larger, factored ones)."""
        if not len(rows):
            return None
        if self.whole:
            matrices = self.matrices[rows] = _quadratic(*pencils.matrices(slice(None)), shifts)
            self.ready[rows] = True
            return matrices
        rows = np.asarray(rows)
        shifts = np.asarray(shifts, dtype=complex)
        sparse = pencils.sparse(np.arange(len(rows)))
        for i in np.nonzero(sparse)[0]:
            self.factors[rows[i]] = _sparse_lu(pencils, i, shifts[i])[0]
        dense = np.nonzero(~sparse)[0]
        n = pencils.n_dof
        step = max(1, _CACHE_BYTES // (16 * n * n))
        for part in (dense[start:start + step] for start in range(0, len(dense), step)):
            self._factor_dense(rows[part], _quadratic(*pencils.matrices(part), shifts[part]))
        self.ready[rows] = True
        return None

    def _factor_dense(self, rows, quadratic):
        from scipy.linalg import lapack

        for row, matrix in zip(rows, quadratic):
            lu, pivots, _ = lapack.zgetrf(matrix, overwrite_a=True)    # info > 0: singular, solves give inf
            self.factors[row] = (lu, pivots)

    def solve(self, rows, rhs, adjoint: bool = False):
        """``Q^-1 rhs`` (or ``Q^-H rhs``) for storage ``rows``; ``rhs`` (R, n) complex."""
        if self.whole:
            matrices = self.matrices[rows]
            if adjoint:
                matrices = matrices.swapaxes(-1, -2).conj()
            return _solve(matrices, rhs[..., None])[..., 0]
        from scipy.linalg import lapack

        out = np.empty(rhs.shape, dtype=complex)
        for i, row in enumerate(rows):
            factor = self.factors[row]
            if factor is None:
                out[i] = np.nan
            elif isinstance(factor, tuple):
                out[i] = lapack.zgetrs(*factor, rhs[i], trans=2 if adjoint else 0)[0]
            else:
                out[i] = factor.solve(rhs[i], trans="H" if adjoint else "N")
        return out


def residual_inverse_iteration(factors, rows, pencils, eigenvalues, vectors, iterations: int = 12,
                               matrices=None):
    """Eigenpairs of ``Q(lam) phi = 0`` near guesses, with one fixed factorisation per row.

    Neumaier's residual inverse iteration: with ``F`` a factorisation of ``Q(sigma)`` at a shift
    ``sigma`` near the eigenvalue (of this pencil or of a nearby one: another speed) and ``c``
    the first guess's shape, scaled so that ``c^H phi = 1``, each step takes the ``lam`` nearest
    the last that makes ``w^H Q(lam) phi`` vanish, ``w = F^-H c`` (a quadratic in ``lam``), and
    moves ``phi <- phi - F^-1 Q(lam) phi``. The residual is formed before the solve, so the
    near-singular ``F`` amplifies only its component along the mode, which the scaling
    ``c^H phi = 1`` removes. It converges linearly, the faster the nearer ``sigma``, at three
    matrix-vector products and one pair of triangular solves per step: O(n^2) instead of the
    O(n^3) of a new factorisation (small pencils, solved whole, are shifted to the new
    eigenvalue at every step instead: Newton's convergence). A row ends when its step (the larger of the eigenvalue's
    and the shape's, each relative) is below 1e-14, or below 1e-9 with the contraction of the
    last two steps promising an error below 1e-14.

    Parameters
    ----------
    factors : PencilFactors
    rows : ndarray of int, shape (P,)
        Each row's factorisation in ``factors``.
    pencils : Pencils
        The pencils whose eigenpairs are wanted, P rows (their speeds may differ from the
        factorisations').
    eigenvalues : ndarray, shape (P,), complex
        Guesses.
    vectors : ndarray, shape (P, n), complex
        Guessed shapes (any scale).
    iterations : int
        Most steps.
    matrices : ndarray, shape (P, n, n), complex, optional
        The small pencils' matrices of ``rows`` as :meth:`PencilFactors.factor` returned them
        (else read from ``factors``).

    Returns
    -------
    eigenvalues : ndarray (P,), complex
    vectors : ndarray (P, n), complex, unit norm
    converged : ndarray (P,) bool
    """
    s = np.array(eigenvalues, dtype=complex)
    phi = unit_rows(np.asarray(vectors, dtype=complex))                # a new array: c, with c^H phi = 1
    normal_conj = phi.conj()
    last = np.full(len(s), np.inf)
    converged = np.zeros(len(s), dtype=bool)
    whole = factors.whole
    with np.errstate(all="ignore"):                                     # a singular factor is dropped below
        if whole:
            if matrices is None:
                matrices = factors.matrices[rows]
            left = _adjoint_solve(matrices, normal_conj)
        else:
            left = factors.solve(rows, phi, adjoint=True).conj()
        active = np.isfinite(left).all(axis=-1)
        # every row at once while all iterate (the usual case): no gathers and scatters, the small
        # pencils' matrices at hand
        everyone = bool(active.all()) and len(s) > 0
        for _ in range(iterations):
            if everyone:
                i, phi_i, s_i, left_i, normal_i = slice(None), phi, s, left, normal_conj
            else:
                i = active.nonzero()[0]
                if not len(i):
                    break
                phi_i, s_i, left_i, normal_i = phi[i], s[i], left[i], normal_conj[i]
            new, phi_new, size = _step(factors, rows, pencils, i, phi_i, s_i, left_i, normal_i,
                                       matrices if whole and everyone else None)
            finite = np.isfinite(size)
            regular = finite.all()
            if regular and everyone:
                s, phi = new, phi_new
            elif regular:
                s[i], phi[i] = new, phi_new
            else:
                size = np.where(finite, size, np.inf)
                s[i] = np.where(finite, new, s_i)
                phi[i] = np.where(finite[:, None], phi_new, phi_i)
            done = _settled(size, last if everyone else last[i])
            stop = done if regular else done | ~finite
            if everyone:
                last = size
            else:
                last[i] = size
            if stop.any():
                if everyone:
                    converged[done], active[stop] = True, False
                else:
                    converged[i[done]], active[i[stop]] = True, False
                everyone = False
                if stop.all():
                    break
            if whole:
                # small pencils are refactored at every step anyway: shift them to the new eigenvalue
                # (Newton's convergence instead of linear), with the left vector to match
                if everyone:
                    matrices = factors.factor(rows, pencils, s)
                    left = _adjoint_solve(matrices, normal_conj)
                else:
                    more = active.nonzero()[0]
                    left[more] = _adjoint_solve(factors.factor(rows[more], PencilRows(pencils, more), s[more]),
                                                normal_conj[more])
    return s, unit_rows(phi), converged


def _step(factors, rows, pencils, i, phi, s, left, normal_conj, matrices=None):
    """One step of :func:`residual_inverse_iteration` for its rows ``i`` (shapes ``phi``,
    eigenvalues ``s``, left vectors ``left``, ``conj(c)``): the new eigenvalue, the new shape
    (scaled to ``c^H phi = 1``) and the step's size (:func:`_step_size`). ``matrices``: the small
    pencils of all rows at hand (else solved through ``factors``)."""
    products = pencils.products(i, phi)                                 # M phi, D phi, K phi
    new = _nearest_root(*np.einsum("pi,kpi->kp", left, products), s)
    m_phi, d_phi, k_phi = products
    column = new[:, None]
    residual = column ** 2 * m_phi + column * d_phi + k_phi
    # the new shape and its step, side by side (normed together: see _step_size)
    pair = np.empty((2,) + phi.shape, dtype=complex)
    phi_new = pair[1]
    if matrices is not None:
        np.subtract(phi, _solve(matrices, residual[..., None])[..., 0], out=phi_new)
    else:
        np.subtract(phi, factors.solve(rows[i], residual), out=phi_new)
    phi_new /= np.einsum("pi,pi->p", normal_conj, phi_new)[:, None]
    return new, phi_new, _step_size(new, s, pair, phi)


def _settled(size, last):
    """Rows whose step ``size`` is below 1e-14, or below 1e-9 with the contraction from the last
    step's ``last`` promising an error below 1e-14."""
    rate = size / last
    done = size <= 1e-9
    if done.any():
        done = (size <= 1e-14) | (done & (rate < 0.5) & (size * rate <= 1e-14))
    return done


def _adjoint_solve(matrices, normal_conj):
    """``conj(Q^-H c)`` for whole pencils ``Q`` (P, n, n), from ``conj(c)`` (P, n): the solve of
    ``Q^T`` with ``conj(c)`` (the same numbers as conjugating ``Q^T``, solving and conjugating
    back, without the two copies)."""
    return _solve(matrices.swapaxes(-1, -2), normal_conj[..., None])[..., 0]


def _step_size(new, old, pair, phi_old):
    """The larger of the relative steps of each row's eigenvalue and shape (P,): the eigenvalue
    alone can settle while the shape still holds a neighbouring mode. ``pair`` (2, P, n) holds
    the new shapes in ``pair[1]``; the shapes' steps are written to ``pair[0]`` (normed together)."""
    np.subtract(pair[1], phi_old, out=pair[0])
    norms = row_norms(pair)[..., 0]
    return np.maximum(np.abs(new - old) / np.abs(new), norms[0] / norms[1])


def speed_newton_step(matrices, speeds, eigenvalues, vectors, normal_conj, line):
    """One Newton step on eigenpairs of ``Q(lam, Omega) phi = 0`` and on their speeds together,
    towards the speed where ``Im lam = line Omega``.

    The unknowns of a row are its shape ``phi`` (n, complex), eigenvalue ``lam`` and speed
    ``Omega`` (real); the equations ``Q(lam, Omega) phi = 0``, ``c^H phi = 1`` and
    ``Im lam - line Omega = 0``, with ``Q = lam^2 M + lam (C + Omega G) + K``. One solve of the
    bordered matrix ``[[Q, Q_lam phi], [c^H, 0]]`` with two right-hand sides gives the eigenpair's
    Newton step at this speed, from ``-(Q phi, c^H phi - 1)``, and its derivative along the speed,
    from ``-(Q_Omega phi, 0) = -(lam G phi, 0)`` (that derivative's last entry is
    ``dlam/dOmega = -y^H Q_Omega phi / y^H Q_lam phi``, without the left vector ``y``); the speed
    step is the one that zeroes the last equation linearised, and the eigenpair moves with it.
    The bordered matrix is regular at a simple eigenvalue, so the step stays well conditioned
    while ``Q`` itself becomes singular: the iteration converges quadratically. Every row's
    numbers are its own (batched products and solves, one matrix at a time). A singular row
    (its least-squares solution) or a vanishing derivative gives steps that are not finite: the
    caller ignores floating-point errors and drops such rows.

    Parameters
    ----------
    matrices : tuple of ndarray
        ``M, C, G, K`` of the rows, each (n, n) where the rows share it, else (P, n, n).
    speeds : ndarray, shape (P,) [rad/s]
    eigenvalues : ndarray, shape (P,), complex
    vectors : ndarray, shape (P, n), complex
    normal_conj : ndarray, shape (P, n), complex
        ``conj(c)``.
    line : ndarray, shape (P,)
        The excitation's frequency per speed [rad/s per rad/s] (signed: ``slope sign(Omega)``).

    Returns
    -------
    speed_steps : ndarray (P,) [rad/s]; eigenvalue_steps : ndarray (P,), complex;
    shape_steps : ndarray (P, n), complex
    """
    count, n = vectors.shape
    # a few rows at a time, so that each part's matrices stay in the cache (as in _quadratic)
    parts = chunk_slices(count, 48 * (n + 1) ** 2, budget=_CACHE_BYTES)
    if len(parts) == 1:
        return _speed_newton_part(matrices, speeds, eigenvalues, vectors, normal_conj, line)
    steps = []
    for part in parts:
        mine = tuple(matrix if matrix.ndim == 2 else matrix[part] for matrix in matrices)
        steps.append(_speed_newton_part(mine, speeds[part], eigenvalues[part], vectors[part], normal_conj[part],
                                        line[part]))
    return tuple(np.concatenate(column) for column in zip(*steps))


def _speed_newton_part(matrices, speeds, eigenvalues, vectors, normal_conj, line):
    """:func:`speed_newton_step` of a part of the rows."""
    mass, damping, gyroscopic, stiffness = matrices
    count, n = vectors.shape
    lam = eigenvalues[:, None, None]
    column = vectors[..., None]
    speed_damping = damping + speeds[:, None, None] * gyroscopic
    quadratic = np.empty((count, n, n), dtype=complex)
    _quadratic_part(quadratic, mass, speed_damping, stiffness, eigenvalues ** 2, eigenvalues)
    bordered = np.empty((count, n + 1, n + 1), dtype=complex)
    bordered[:, :n, :n] = quadratic
    np.matmul(2 * lam * mass + speed_damping, column, out=bordered[:, :n, n:])      # Q_lam phi
    bordered[:, n, :n] = normal_conj
    bordered[:, n, n] = 0.0
    rhs = np.empty((count, n + 1, 2), dtype=complex)
    np.negative(quadratic @ column, out=rhs[:, :n, :1])
    np.multiply(-lam, gyroscopic @ column, out=rhs[:, :n, 1:])                       # -Q_Omega phi
    rhs[:, n, 0] = 1.0 - np.einsum("pi,pi->p", normal_conj, vectors)
    rhs[:, n, 1] = 0.0
    solution = _solve(bordered, rhs)                 # (the caller ignores floating-point errors)
    fixed, along = solution[:, n, 0], solution[:, n, 1]
    speed_steps = -((eigenvalues + fixed).imag - line * speeds) / (along.imag - line)
    shape_steps = solution[:, :n, 0] + solution[:, :n, 1] * speed_steps[:, None]
    return speed_steps, fixed + along * speed_steps, shape_steps


class PencilRows:
    """Rows ``rows`` of a :class:`~._stack.Pencils`, numbered from 0."""

    def __init__(self, pencils, rows):
        self.pencils, self.rows = pencils, rows

    @property
    def n_dof(self) -> int:
        return self.pencils.n_dof

    def matrices(self, rows):
        return self.pencils.matrices(self.rows[rows])

    def sparse(self, rows):
        return self.pencils.sparse(self.rows[rows])

    def sparse_parts(self, row):
        return self.pencils.sparse_parts(self.rows[row])

    def products(self, rows, vectors):
        return self.pencils.products(self.rows[rows], vectors)


#: pencils of more coordinates than this find the roots near a point by shift-invert Arnoldi
#: (:func:`nearest_roots`) instead of taking all eigenvalues of the state matrix
NEAREST_ROOTS_DOF = 96


#: ARPACK's tolerance on the shifted-inverse's Ritz values ``nu = 1 / (lam - sigma)``: a root's
#: error is about this times its distance from the shift, far below round-off of ``lam`` itself
_ARNOLDI_TOLERANCE = 1e-12


def nearest_roots(pencils, centers, count: int = 8):
    """The ``count`` roots of each row's pencil nearest a point, with their shapes.

    Shift-invert Arnoldi (ARPACK, :func:`scipy.sparse.linalg.eigs`) on the first-order form
    ``[[0, I], [-M^-1 K, -M^-1 D]]`` shifted to the point: ``(A - sigma I)^-1 [u; v] = [x; u +
    sigma x]`` with ``Q(sigma) x = -(M v + (D + sigma M) u)``, one LU of the n x n pencil per row
    and O(n^2) per Arnoldi step, instead of all 2n eigenvalues (O(n^3) with a larger constant).

    Parameters
    ----------
    pencils : Pencils
        P rows.
    centers : ndarray, shape (P,), complex
        The points [1/s].
    count : int
        Roots per row (at most 2n - 2).

    Returns
    -------
    eigenvalues : ndarray (P, count), complex
        By distance from the point; NaN in a row where ARPACK did not converge.
    shapes : ndarray (P, count, n), complex
        Unit-norm displacement parts of the eigenvectors.
    radius : ndarray (P,)
        Every root nearer the point than this is among the row's eigenvalues [1/s] (NaN where
        ARPACK did not converge).
    """
    from scipy.sparse.linalg import ArpackError, LinearOperator, eigs

    n = pencils.n_dof
    count = min(count, 2 * n - 2)
    start = _start_vectors(1, 2 * n)[0]          # a fixed start: the same roots on every run
    values = np.empty((len(centers), count), dtype=complex)
    shapes = np.empty((len(centers), count, n), dtype=complex)
    radius = np.full(len(centers), np.nan)
    # off the point by a little: the point may be a root itself (a mode the speed leaves alone)
    shifts = np.asarray(centers, dtype=complex) * (1 + 1e-9 * (1 + 1j)) + 1e-300
    sparse = pencils.sparse(np.arange(len(shifts)))
    for row, sigma in enumerate(shifts):
        solve, both = (_sparse_shifted if sparse[row] else _dense_shifted)(pencils, row, sigma)
        if solve is None:                                   # singular at the shift: all roots instead
            values[row], shapes[row] = np.nan, 0.0
            continue

        def inverse(w, solve=solve, both=both, sigma=sigma):
            x = -solve(both @ w)
            return np.concatenate([x, w[:n] + sigma * x])

        def unused(w):
            raise RuntimeError("shift-invert mode applies only the inverse")

        try:
            lam, vectors = eigs(LinearOperator((2 * n, 2 * n), matvec=unused, dtype=complex), k=count, sigma=sigma,
                                OPinv=LinearOperator((2 * n, 2 * n), matvec=inverse, dtype=complex), which="LM",
                                tol=_ARNOLDI_TOLERANCE, v0=start)
        except ArpackError:
            values[row], shapes[row] = np.nan, 0.0          # the caller takes all roots instead
            continue
        order = np.argsort(np.abs(lam - centers[row]))
        values[row] = lam[order]
        shapes[row] = unit_rows(vectors[:n, order].T)
        # ARPACK's roots are those nearest the shift: any other is at least as far from it
        radius[row] = np.abs(lam - sigma).max() - np.abs(sigma - centers[row])
    return values, shapes, radius


def _dense_shifted(pencils, row, sigma):
    """``Q(sigma)^-1`` of a row as a function, by a dense LU, and ``[D + sigma M, M]`` (n, 2n)."""
    from scipy.linalg import lapack

    matrices = pencils.matrices(np.array([row]))
    n = pencils.n_dof
    mass, damping = (np.reshape(matrix, (n, n)) for matrix in matrices[:2])
    lu, pivots, _ = lapack.zgetrf(_quadratic(*matrices, np.array([sigma]))[0], overwrite_a=True)
    both = np.concatenate([damping + sigma * mass, mass.astype(complex)], axis=1)

    def solve(rhs):
        return lapack.zgetrs(lu, pivots, rhs)[0]

    return solve, both


def _sparse_shifted(pencils, row, sigma):
    """As :func:`_dense_shifted`, with SuperLU and sparse ``[D + sigma M, M]``; (None, None)
    where ``Q(sigma)`` is singular."""
    from scipy.sparse import hstack

    factor, (layout, mass, damping, _) = _sparse_lu(pencils, row, sigma)
    if factor is None:
        return None, None
    both = hstack([layout.matrix(damping + sigma * mass), layout.matrix(mass.astype(complex))], format="csr")
    return factor.solve, both


def _nearest_root(a, b, c, near):
    """The root of ``a x^2 + b x + c`` nearest ``near`` (each an array (P,), complex)."""
    root = np.sqrt(b * b - 4 * a * c)
    q = -0.5 * (b + np.where((b.conj() * root).real >= 0, root, -root))   # no cancellation in b + root
    first, second = q / a, c / q
    return np.where(np.abs(first - near) <= np.abs(second - near), first, second)


def _quadratic(M, damping, stiffness, lam):
    """``lam^2 M + lam D + K`` for rows (P, n, n), one complex array (``M`` and ``K`` (n, n) where
    the rows share them, else (P, n, n)).

    Built as real and imaginary planes, a few rows at a time, so that every pass runs in the
    cache (whole-array complex products of these sizes ran at memory speed, 10x slower)."""
    lam = np.asarray(lam, dtype=complex)
    out = np.empty(damping.shape, dtype=complex)
    squares = lam**2
    step = max(1, _CACHE_BYTES // (8 * damping[0].size))
    for part in (slice(p, p + step) for p in range(0, len(lam), step)):
        _quadratic_part(out[part], M if M.ndim == 2 else M[part], damping[part],
                        stiffness if stiffness.ndim == 2 else stiffness[part], squares[part], lam[part])
    return out


def _quadratic_part(out, mass, damping, stiffness, squares, lam):
    """``out = squares M + lam D + K``, the real plane and then the imaginary one."""
    real, imaginary = out.real, out.imag
    np.multiply(mass, squares.real[:, None, None], out=real)
    real += damping * lam.real[:, None, None]
    real += stiffness
    np.multiply(mass, squares.imag[:, None, None], out=imaginary)
    imaginary += damping * lam.imag[:, None, None]


def _solve(matrices, rhs):
    """``numpy.linalg.solve`` of a stack (..., n, n) with right-hand sides (..., n, k); where a
    matrix is singular, that row's least-squares solution.

    numpy refuses a whole stack for one singular matrix. The stack is then halved until the
    singular rows stand alone (a few batched solves, not one per row), so that each row's result
    is its own whatever the other rows are: a study's variant and its model's own analysis agree
    bit for bit."""
    try:
        return np.linalg.solve(matrices, rhs)
    except np.linalg.LinAlgError:
        rhs = np.broadcast_to(rhs, matrices.shape[:-2] + rhs.shape[-2:])
        flat = _solve_halves(matrices.reshape((-1,) + matrices.shape[-2:]), rhs.reshape((-1,) + rhs.shape[-2:]))
        return flat.reshape(rhs.shape)


def _solve_halves(matrices, rhs):
    """:func:`_solve` of a stack (P, n, n) known to hold a singular matrix."""
    if len(matrices) == 1:
        return np.linalg.lstsq(matrices[0], rhs[0], rcond=None)[0][None].astype(complex)
    parts = []
    for part in (slice(0, len(matrices) // 2), slice(len(matrices) // 2, None)):
        try:
            parts.append(np.linalg.solve(matrices[part], rhs[part]))
        except np.linalg.LinAlgError:
            parts.append(_solve_halves(matrices[part], rhs[part]))
    return np.concatenate(parts)


def solve_batch(form, speeds, forms=None):
    """Upper eigenvalues and their mode shapes at many speeds.

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    forms : WhirlForms, optional
        When given, the shapes of repeated eigenvalues are made the circular
        (extreme-whirl) combinations; see :func:`resolve_repeated`.

    Returns
    -------
    eigenvalues : ndarray, shape (N, m), complex [1/s]
        ``m = n_states / 2`` roots per speed.
    shapes : ndarray, shape (N, m, n), complex
        Unit-norm displacement parts of the state eigenvectors.
    """
    speeds = np.asarray(speeds, dtype=float)
    eigenvalues, shapes = upper_shapes(form.at(speeds), form.n_dof)
    if forms is not None:
        shapes = resolve_repeated(eigenvalues, shapes, forms)
    return eigenvalues, shapes


#: eigenvalues closer than this (relative) are one repeated eigenvalue
REPEATED_TOLERANCE = 1e-9


def resolve_repeated(eigenvalues, shapes, forms, variants=None):
    """Make the shapes of a repeated eigenvalue its forward and backward whirl combinations.

    Any combination of the shapes of a double eigenvalue is a mode shape, so the
    solver's choice (and with it the whirl label) would be arbitrary. Within each
    pair this picks the two combinations with extreme whirl ratio: the
    eigenvectors of ``-i Phi^H W Phi v = mu Phi^H M Phi v`` (circular orbits, one
    turning each way, for an axisymmetric machine). Pairs whose motion has no
    whirl keep their shapes. Groups of three or more are left as they are.

    Parameters
    ----------
    eigenvalues : ndarray, shape (N, m), sorted so that equal values are adjacent
    shapes : ndarray, shape (N, m, n)
    forms : WhirlForms
        Each (n, n), or (V, n, n) for rows of several variants.
    variants : ndarray of int, shape (N,), optional
        The variant of each row, with forms stacked over variants.

    Returns
    -------
    ndarray, shape (N, m, n): shapes, with repeated pairs replaced (backward first)
    """
    rows, first = _repeated_pairs(eigenvalues)
    if not len(rows):
        return shapes
    if variants is not None:
        forms = WhirlForms(*(f[variants[rows]] for f in forms))
    basis = np.stack([shapes[rows, first], shapes[rows, first + 1]], axis=-1)  # (P, n, 2)
    rule = "pia,pij,pjb->pab" if forms.total.ndim == 3 else "pia,ij,pjb->pab"
    total = np.einsum(rule, basis.conj(), forms.total, basis)
    # the two shapes must span a plane (two inverse iterations could give one direction)
    spans = np.abs(np.linalg.det(total)) > 1e-6 * np.abs(total[:, 0, 0] * total[:, 1, 1])
    rows, first, basis, total = rows[spans], first[spans], basis[spans], total[spans]
    if forms.total.ndim == 3:
        forms = WhirlForms(*(f[spans] for f in forms))
    if not rows.size:
        return shapes
    momentum = -1j * np.einsum(rule, basis.conj(), forms.W, basis)
    mu, resolved = _extreme_whirl(basis, total, momentum)
    whirling = np.abs(mu[:, 1] - mu[:, 0]) > 1e-6
    out = shapes.copy()
    out[rows[whirling], first[whirling]] = resolved[whirling, :, 0]
    out[rows[whirling], first[whirling] + 1] = resolved[whirling, :, 1]
    return out


def _repeated_pairs(lam):
    """Rows and first columns of the eigenvalues equal to the next one, exactly two equal (not
    three) and not rigid-body zeros; ``lam`` shape (N, m), equal values adjacent."""
    scale = np.abs(lam).max(axis=-1, keepdims=True) + 1e-300
    close = np.abs(lam[..., 1:] - lam[..., :-1]) <= REPEATED_TOLERANCE * scale  # (N, m-1), numpy.diff
    if not close.any():                    # the usual case: no repeated eigenvalue at all
        return close.nonzero()
    padded = np.pad(close, ((0, 0), (1, 1)))
    pair = close & ~padded[:, :-2] & ~padded[:, 2:]
    pair &= np.abs(lam[:, :-1]) > OSCILLATORY_TOLERANCE * scale
    return pair.nonzero()


def _extreme_whirl(basis, total, momentum):
    """The combinations of each pair's two shapes with extreme whirl ratio.

    Solves ``momentum v = mu total v`` (both Hermitian, ``total`` positive definite) by a
    Cholesky reduction.

    Returns
    -------
    mu : ndarray, shape (P, 2)
        Whirl ratios, increasing (backward first).
    resolved : ndarray, shape (P, n, 2)
        The combined shapes, unit norm.
    """
    momentum = 0.5 * (momentum + np.conj(np.swapaxes(momentum, -1, -2)))
    factor = np.linalg.cholesky(0.5 * (total + np.conj(np.swapaxes(total, -1, -2))))
    inverse = np.linalg.inv(factor)
    reduced = inverse @ momentum @ np.conj(np.swapaxes(inverse, -1, -2))
    mu, vectors = np.linalg.eigh(reduced)
    combinations = np.conj(np.swapaxes(inverse, -1, -2)) @ vectors  # (P, 2, 2)
    resolved = basis @ combinations  # (P, n, 2)
    resolved /= np.linalg.norm(resolved, axis=1, keepdims=True)
    return mu, resolved


# ----------------------------------------------------------------------------------------
_SKEW_BASIS = skew(np.eye(3))   # E_k = skew(unit_k), shape (3, 3, 3)


def _bodies_quadratic(masses, second_moments, X, first, products) -> np.ndarray:
    """``sum_p m_p Z_p^T X Z_p`` over the particles of each rigid body, Z_p = [I, -skew(r_p)],
    for several directions X at once.

    Needs only each body's mass, first moment and second-moment tensor about the reference
    point: ``sum_p m_p skew(r_p) X skew(r_p) = sum_kl Q_kl E_k X E_l`` with ``E_k = skew(unit_k)``.

    Parameters
    ----------
    masses : ndarray (B,); second_moments : ndarray (B, 3, 3)
    X : ndarray, shape (D, 3, 3)
    first : ndarray (B, 3, 3)
        ``skew(masses * centers)``.
    products : ndarray (D, 3, 3, 3, 3)
        ``E_k X E_l`` of each direction (see :func:`_directions`).

    Returns
    -------
    ndarray, shape (D, B, 6, 6)
    """
    X = X[:, None]                                            # (D, 1, 3, 3)
    out = np.zeros((len(X), len(masses), 6, 6))
    out[..., :3, :3] = masses[:, None, None] * X
    out[..., :3, 3:] = -X @ first
    out[..., 3:, :3] = first @ X
    out[..., 3:, 3:] = -np.einsum("zkl,xklad->xzad", second_moments, products)
    return out


def _direction_products(X) -> np.ndarray:
    """``E_k X E_l`` for a (3, 3) matrix X, shape (3, 3, 3, 3), with ``E_k = skew(unit_k)``."""
    return np.einsum("kab,bc,lcd->klad", _SKEW_BASIS, X, _SKEW_BASIS)


@functools.lru_cache(maxsize=16)
def _directions(axis: tuple):
    """The whirl forms' 3 x 3 directions W, N, total about the spin axis ``axis`` (a tuple of 3
    floats) and their :func:`_direction_products`, stacked: (3, 3, 3) and (3, 3, 3, 3, 3),
    read-only. A function of the axis alone, kept for the next model with the same axis."""
    e = np.array(axis, dtype=float)
    X = np.stack([skew(e), np.eye(3) - np.outer(e, e), np.eye(3)])
    products = np.stack([_direction_products(x) for x in X])
    X.flags.writeable = products.flags.writeable = False
    return X, products


class WhirlForms(NamedTuple):
    """Quadratic forms of the whirl ratio (each (n, n)); see :func:`whirl_forms`."""

    W: np.ndarray
    N: np.ndarray
    total: np.ndarray


_DIRECTIONS = ("W", "N", "total")


def _bodies_forms(model) -> np.ndarray:
    """The 6x6 forms W, N, total (stacked in this order) of each body's rigid motion at the
    reference point (stator first, then the rotors): shape (3, B, 6, 6)."""
    X, products = _directions(tuple(float(x) for x in model.spin_axis))
    bodies = body_inertias(model)
    masses = np.array([m for m, _, _ in bodies], dtype=float)
    arms = np.array([np.asarray(c, dtype=float) for _, c, _ in bodies]) - model.reference_point
    inertias = np.array([np.asarray(j, dtype=float) for _, _, j in bodies])
    traces = inertias.trace(axis1=1, axis2=2)
    second = (0.5 * traces[:, None, None] * np.eye(3) - inertias
              + masses[:, None, None] * arms[:, :, None] * arms[:, None, :])
    first = skew(masses[:, None] * arms)
    return _bodies_quadratic(masses, second, X, first, products)


def whirl_forms(model) -> WhirlForms:
    """Quadratic forms ``W``, ``N`` and ``total`` of the whirl ratio of a mode shape phi.

    ``-i phi^H W phi`` is the mass-weighted orbital angular momentum of the
    whole machine's vibration about the spin axis (per unit frequency),
    ``phi^H N phi`` the mass-weighted mean square motion normal to it and
    ``phi^H total phi`` that of the whole motion (``total`` equals the mass
    matrix). Each body contributes ``T_b^T X_b T_b`` (its motion ``T_b`` over the
    generalized coordinates). See ``docs/theory.md``.
    """
    forms = _bodies_forms(model)                                          # (3, B, 6, 6)
    parts = frame_block(model, forms.sum(axis=1))                         # (3, n, n)
    first_rotor = forms.shape[1] - len(model.rotors)
    for j, rotor in enumerate(model.rotors):
        if model.dofs.on_bearings(rotor.name):
            add_rotor_bodies([parts], model, rotor.name, [forms[:, first_rotor + j]])
    return WhirlForms(*parts)


def rotor_whirl_forms(model, rotor: str) -> WhirlForms:
    """The whirl forms of one rotor's own motion (absolute), each (n, n)."""
    index = [r.name for r in model.rotors].index(rotor)
    forms = _bodies_forms(model)
    body = forms[:, forms.shape[1] - len(model.rotors) + index]            # (3, 6, 6)
    motion = model.dofs.body_motion(rotor)
    return WhirlForms(*(motion.T @ body[d] @ motion for d in range(len(_DIRECTIONS))))


def stacked_forms(forms: WhirlForms) -> np.ndarray:
    """The transposes of the three whirl forms side by side, (..., n, 3 n), contiguous (see
    :func:`quadratic_forms`)."""
    return np.ascontiguousarray(
        np.concatenate([np.swapaxes(f, -1, -2) for f in (forms.W, forms.N, forms.total)], axis=-1))


def whirl_ratios(shapes, forms: WhirlForms, speeds, stacked=None) -> np.ndarray:
    """Signed whirl ratio in [-1, 1] relative to the reference rotor's spin.

    +1 for a circular orbit normal to the spin axis turning with the spin, -1
    against it, 0 for straight-line orbits. Modes whose motion normal to the
    axis is below ``1e-9`` of their whole motion (pure axial or roll motion)
    get 0, not a ratio of round-off to round-off.

    Parameters
    ----------
    shapes : ndarray, shape (..., m, n)
    forms : WhirlForms
        Each (n, n), or stacked like the shapes' leading axes, (..., n, n); unused (may be None)
        when ``stacked`` is given.
    speeds : ndarray, shape (...) [rad/s]; the sign of the spin (0 counts as +)
    stacked : ndarray, optional
        :func:`stacked_forms` of ``forms``, when the caller keeps it.

    Returns
    -------
    ndarray, shape (..., m)
    """
    # phi^H X phi of the three forms for every shape from one product with [W^T N^T total^T]
    values = quadratic_forms(shapes, stacked_forms(forms) if stacked is None else stacked).reshape(
        shapes.shape[:-1] + (3,))
    momentum = values[..., 0].imag  # Re(-i phi^H W phi)
    across = values[..., 1].real
    whole = values[..., 2].real
    ratio = np.zeros(across.shape)
    np.divide(momentum, across, out=ratio, where=across > 1e-9 * whole)
    against = np.asarray(speeds) < 0
    if against.any():
        np.negative(ratio, out=ratio, where=np.broadcast_to(against[..., None], ratio.shape))
    np.maximum(ratio, -1.0, out=ratio)                                   # numpy.clip, in place
    return np.minimum(ratio, 1.0, out=ratio)


def real_product(shapes, matrix) -> np.ndarray:
    """``shapes @ matrix`` for complex shapes (..., m, n) and a real matrix (n, p) or (..., n, p),
    as real products of the real and imaginary parts (half the work of a complex product;
    one matrix product over all shapes when the matrix is shared)."""
    if np.iscomplexobj(matrix):
        return shapes @ matrix
    parts = np.empty((2,) + shapes.shape, dtype=shapes.real.dtype)   # contiguous, (2, ..., m, n)
    parts[0], parts[1] = shapes.real, shapes.imag
    if matrix.ndim == 2:
        out = (parts.reshape(-1, parts.shape[-1]) @ matrix).reshape(parts.shape[:-1] + matrix.shape[-1:])
    else:
        out = parts @ matrix
    combined = np.empty(out.shape[1:], dtype=complex)
    combined.real, combined.imag = out[0], out[1]
    return combined


#: shapes of at most this many coordinates take their quadratic forms by one complex product
_COMPLEX_PRODUCT_DOF = 24


def quadratic_forms(shapes, stacked) -> np.ndarray:
    """``phi^H X_k phi`` of every shape (..., m, n) for real forms whose transposes are
    side by side in ``stacked`` (n, K n) or (..., n, K n).

    Returns
    -------
    ndarray, shape (..., m, K), complex
    """
    n = shapes.shape[-1]
    # small shapes: complex products, one per speed (numpy makes the forms complex, a few
    # hundred numbers), cost less than the real parts' copies and their product's large
    # temporaries, and each is too small to start BLAS threads (which a loaded machine makes
    # wait). Single shapes (critical speeds) of pencils solved whole also take one product per
    # row: in one product of all rows a row's bits depend on its place among the others, and a
    # study's variant would then differ from its model's own analysis in the last bit.
    single = shapes.shape[-2] == 1 and n <= BATCHED_DOF
    if n > _COMPLEX_PRODUCT_DOF and not single:
        product = real_product(shapes, stacked)
    else:
        product = shapes @ stacked
    products = product.reshape(shapes.shape[:-1] + (-1, n))   # (..., m, K, n)
    return np.einsum("...i,...ki->...k", shapes.conj(), products)


_WHIRL_NAMES = np.array(["backward", "none", "forward"])


def whirl_labels(ratios) -> np.ndarray:
    """'forward', 'backward' or 'none' from whirl ratios (array of str)."""
    ratios = np.asarray(ratios)
    return _WHIRL_NAMES[(ratios > WHIRL_TOLERANCE).astype(np.intp) - (ratios < -WHIRL_TOLERANCE) + 1]


def row_norms(x) -> np.ndarray:
    """Euclidean norms of the last axis of a complex array, shape (..., 1) (``numpy.linalg.norm``
    with ``keepdims``, without its temporaries)."""
    pairs = np.ascontiguousarray(x).view(float)
    return np.sqrt(np.einsum("...i,...i->...", pairs, pairs))[..., None]


def unit_rows(x) -> np.ndarray:
    """Rows of the last axis scaled to unit length; zero rows stay zero (a Maxwell junction's
    relaxation root moves no mass and has no displacement: its shape stays zero, MAC 0)."""
    norms = row_norms(x)
    return x / np.where(norms > 0, norms, 1.0)


def mass_normalized(shapes, M) -> np.ndarray:
    """``L^T phi`` normalised to unit length, with ``M = L L^T``: shapes whose plain
    inner product is the mass-weighted one (unit-consistent MAC)."""
    factor = np.linalg.cholesky(M)
    return unit_rows(real_product(shapes, factor))


def mac_matrix(a, b) -> np.ndarray:
    """Modal assurance criterion between unit shape sets ``a`` (..., m, n) and ``b`` (..., p, n).

    Returns
    -------
    ndarray, shape (..., m, p), values in [0, 1]
    """
    return np.abs(a.conj() @ np.swapaxes(b, -1, -2)) ** 2  # batched BLAS, not einsum's loops
