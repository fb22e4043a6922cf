"""The quadratic pencil ``Q(lam) = lam^2 M + lam (C + Omega G) + K`` of each speed: shapes at
known roots (inverse iteration), factorisations (batched, LU, sparse), residual inverse
iteration, the joint Newton step on eigenpair and speed, the roots nearest a point by
shift-invert Arnoldi."""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np

from . import _batches, _vectors

__all__ = ["BATCHED_DOF", "NEAREST_ROOTS_DOF", "PencilFactors", "PencilRows", "SPARSE_DENSITY", "SPARSE_DOF", "SparseLayout", "nearest_roots", "pencil_shapes", "projected_roots", "residual_inverse_iteration", "sparse_layout", "speed_newton_step"]


_START_SEED = 20261122


@functools.lru_cache(maxsize=8)
def _start_vectors(m: int, n: int) -> np.ndarray:
    """Fixed pseudo-random complex start vectors of inverse iteration, shape (m, n): the first
    ``m`` rows and ``n`` columns of the real and imaginary planes of a block of standard normal
    draws (2, size, size), ``size = max(64, m, n)``. Only those rows are kept: the draws between
    them are made and dropped a part at a time (the whole block of a machine of 2,006
    coordinates, for Arnoldi's start of 4,012 states, would hold 512 MB for the whole run)."""
    size = max(64, m, n)
    rng = np.random.default_rng(_START_SEED)
    real = rng.standard_normal((m, size))[:, :n]
    skipped = size * size - m * size
    for part in _batches.chunk_slices(skipped, 8, budget=_SKIP_BYTES):
        rng.standard_normal(part.stop - part.start)
    return real + 1j * rng.standard_normal((m, size))[:, :n]


#: the largest part of the start vectors' skipped draws made at once [bytes]
_SKIP_BYTES = 8 * 2**20


def pencil_shapes(M, damping, stiffness, eigenvalues, branches=None) -> np.ndarray:
    """One inverse-iteration step per known eigenvalue: ``Q(lam) phi = 0``, for one eigenvalue of
    each row or ``k`` of each row.

    Parameters
    ----------
    M : ndarray, shape (P, n, n) or (n, n)
        Each row's mass, or one for all.
    damping : ndarray, shape (P, n, n)
        Each row's ``C + Omega G``.
    stiffness : ndarray, shape (P, n, n) or (n, n)
        Each row's stiffness, or one for all.
    eigenvalues : ndarray, shape (P,) or (P, k), complex
        One root of each row's pencil, or ``k``: then the ``k`` pencils of a row are built in one
        product, their (k, 3) coefficients times the row's ``M``, ``C + Omega G`` and ``K``
        (3, n^2), a third of the time of building each pencil apart (rotor_example, 2,412
        pencils: 8 ms against 24).
    branches : (ndarray (P, n_b, n, n), ndarray (P, n_b)), optional
        Each row's Maxwell branches (stiffness, relaxation times); with eigenvalues (P,) only.

    Returns
    -------
    ndarray, shape (P, n) or (P, k, n), complex, unit norm
    """
    shifted = shifted_roots(eigenvalues)
    if shifted.ndim == 2:
        start = np.broadcast_to(_start_vectors(1, M.shape[-1])[0][:, None], (shifted.size, M.shape[-1], 1))
        shapes = _vectors.unit_rows(_solve(_row_pencils(M, damping, stiffness, shifted), start)[..., 0])
        return shapes.reshape(shifted.shape + (M.shape[-1],))
    pencil = _quadratic(M, damping, stiffness, shifted)
    if branches is not None and branches[1].shape[-1]:
        stiffness_b, times = branches
        factor = shifted[:, None] * times / (1 + shifted[:, None] * times)        # (P, n_b)
        pencil += np.einsum("pb,pbij->pij", factor, stiffness_b)
    start = np.broadcast_to(_start_vectors(1, M.shape[-1])[0][:, None], pencil.shape[:-1] + (1,))
    return _vectors.unit_rows(_solve(pencil, start)[..., 0])


def shifted_roots(eigenvalues) -> np.ndarray:
    """The shifts of :func:`pencil_shapes`' inverse iteration: each root moved by its round-off,
    ``1e-13 |lam| (1 + i)``, which keeps an exactly singular pencil solvable."""
    lam = np.asarray(eigenvalues, dtype=complex)
    return lam + 1e-13 * (np.abs(lam) + 1e-300) * (1 + 1j)


#: :meth:`~._stack.Stack.shapes_at` of larger models with sparse pencils factors them sparse
#: (:func:`sparse_pencil_shapes`): a dense pencil per row is ``16 n^2`` bytes and ``n^3`` work
SPARSE_SHAPES_DOF = 400


def sparse_pencil_shapes(pencils, eigenvalues) -> np.ndarray:
    """:func:`pencil_shapes` of sparse pencils (rows of a ``_stack.Pencils`` whose variants
    have a sparse layout, no Maxwell branches): the same shifted step from the same start, by a
    SuperLU factorisation per row. Returns (P, n) complex, unit norm."""
    lam = np.asarray(eigenvalues, dtype=complex)
    shifted = shifted_roots(lam)
    start = _start_vectors(1, pencils.n_dof)[0].astype(complex)
    out = np.empty((len(lam), pencils.n_dof), dtype=complex)
    for row in range(len(lam)):
        lu, _ = _sparse_lu(pencils, row, shifted[row])
        out[row] = np.nan if lu is None else lu.solve(start)
    return _vectors.unit_rows(out)


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
    row and column of each stored entry, in the layout's order, and the columns' starts; and
    the same entries with rows and columns in a fill-reducing order (:func:`sparse_layout`):
    ``order`` (n,), the permuted matrix's row of each entry, its columns' starts, and the
    layout's entries in the permuted matrix's order."""

    rows: np.ndarray
    cols: np.ndarray
    starts: np.ndarray
    order: np.ndarray
    ordered_rows: np.ndarray
    ordered_starts: np.ndarray
    ordered_entries: np.ndarray

    def matrix(self, data):
        """The ``scipy.sparse.csc_matrix`` with values ``data`` (nnz,) at the layout's entries."""
        from scipy.sparse import csc_matrix

        n = len(self.starts) - 1
        return csc_matrix((data, self.rows, self.starts), shape=(n, n))

    def ordered(self, data):
        """``A[order][:, order]`` of the matrix ``A`` of :meth:`matrix`, as a ``csc_matrix``."""
        from scipy.sparse import csc_matrix

        n = len(self.starts) - 1
        return csc_matrix((data[self.ordered_entries], self.ordered_rows, self.ordered_starts), shape=(n, n))


def sparse_layout(pattern) -> SparseLayout | None:
    """The layout of the pencils whose possible nonzeros are ``pattern`` (n, n) bool (an array, or
    a ``scipy.sparse`` matrix: a large model's), or None where they are better factored dense
    (see ``SPARSE_DOF``).

    The fill-reducing order is SuperLU's minimum-degree ordering of ``A^T + A`` (it suits these
    structurally symmetric pencils: a tenth of COLAMD's fill at 506 coordinates), found once
    from the pattern: every factorisation of the model's pencils then skips it (at 406
    coordinates it was half of each factorisation's time, at 2,006 four fifths)."""
    import scipy.sparse
    from scipy.sparse.linalg import splu

    n = pattern.shape[0]
    if scipy.sparse.issparse(pattern):
        pattern = scipy.sparse.csc_matrix(pattern != 0)
        pattern.sort_indices()
        if n < SPARSE_DOF or pattern.nnz > SPARSE_DENSITY * n * n:
            return None
        cols, rows = np.repeat(np.arange(n), np.diff(pattern.indptr)), pattern.indices.astype(np.int64)
    else:
        if n < SPARSE_DOF or np.count_nonzero(pattern) > SPARSE_DENSITY * n * n:
            return None
        cols, rows = np.nonzero(pattern.T)                    # column by column, rows ascending
    layout = SparseLayout(rows.astype(np.int32), cols, np.searchsorted(cols, np.arange(n + 1)).astype(np.int32),
                          *(np.zeros(0, dtype=np.int32) for _ in range(4)))
    # the ordering depends on the pattern alone: any regular matrix of it gives it
    order = splu(layout.matrix(np.where(rows == cols, 2.0 * n, 1.0)), permc_spec="MMD_AT_PLUS_A").perm_c
    inverse = np.empty(n, dtype=np.int64)
    inverse[order] = np.arange(n)
    new_rows, new_cols = inverse[rows], inverse[cols]
    entries = np.lexsort((new_rows, new_cols))
    return layout._replace(order=order.astype(np.int64), ordered_rows=new_rows[entries].astype(np.int32),
                           ordered_starts=np.searchsorted(new_cols[entries], np.arange(n + 1)).astype(np.int32),
                           ordered_entries=entries)


class _OrderedLU:
    """SuperLU factors of ``A[order][:, order]``, solving with ``A`` (and ``A^H``)."""

    __slots__ = ("lu", "order")

    def __init__(self, lu, order):
        self.lu, self.order = lu, order

    def solve(self, rhs, trans="N"):
        out = np.empty(rhs.shape, dtype=complex)
        out[self.order] = self.lu.solve(rhs[self.order], trans=trans)
        return out


def _sparse_lu(pencils, row, shift):
    """SuperLU factors of row ``row``'s pencil ``Q(shift)`` (or None where it is singular), with
    the row's sparse parts (:meth:`~._stack.Pencils.sparse_parts`: layout, mass, damping,
    stiffness), in the layout's fill-reducing order (see :func:`sparse_layout`)."""
    from scipy.sparse.linalg import splu

    parts = layout, mass, damping, stiffness = pencils.sparse_parts(row)
    try:
        lu = splu(layout.ordered((shift * shift) * mass + shift * damping + stiffness), permc_spec="NATURAL")
    except RuntimeError:            # exactly singular: its solves give NaN, as a dense LU's give inf
        return None, parts
    return _OrderedLU(lu, layout.order), parts


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
        step = max(1, _batches._CACHE_BYTES // (16 * n * n))
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
    phi = _vectors.unit_rows(np.asarray(vectors, dtype=complex))                # a new array: c, with c^H phi = 1
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
    return s, _vectors.unit_rows(phi), converged


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
    norms = _vectors.row_norms(pair)[..., 0]
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
    parts = _batches.chunk_slices(count, 48 * (n + 1) ** 2, budget=_batches._CACHE_BYTES)
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
        shapes[row] = _vectors.unit_rows(vectors[:n, order].T)
        # ARPACK's roots are those nearest the shift: any other is at least as far from it
        radius[row] = np.abs(lam - sigma).max() - np.abs(sigma - centers[row])
    return values, shapes, radius


def projected_roots(basis, products, speeds):
    """Ritz pairs of the pencils ``Q(lam) = lam^2 M + lam (C + Omega G) + K`` of rows in
    subspaces: the roots ``theta`` and coefficients ``y`` of ``W^H Q(theta) W y = 0``, with ``W`` a
    row's orthonormal basis, all rows in one batched eigen-solve of the projected first-order
    forms (size ``2 r``).

    Where ``W`` holds the eigenvectors of a root (to a small angle), one Ritz value is that root
    (to about the angle times the root's distance to the others); the caller refines it on the
    full pencil. ``W^H M W`` is Hermitian positive definite (M is), so the projected pencil has
    ``2 r`` finite roots.

    Parameters
    ----------
    basis : ndarray, shape (P, n, r), complex
        Orthonormal columns.
    products : tuple of ndarray
        ``M W, C W, G W, K W``, each (P, n, r).
    speeds : ndarray, shape (P,) [rad/s]

    Returns
    -------
    theta : ndarray (P, 2 r), complex
    coefficients : ndarray (P, r, 2 r), complex
        Column ``j`` gives the Ritz vector ``W y_j`` of ``theta_j``.
    mass : ndarray (P, r, r), complex
        ``W^H M W`` (``||L^T W y||^2 = y^H (W^H M W) y`` with ``M = L L^T``).
    """
    adjoint = basis.conj().swapaxes(-1, -2)
    mass, damping, gyroscopic, stiffness = (adjoint @ product for product in products)
    damping = damping + speeds[:, None, None] * gyroscopic
    r = mass.shape[-1]
    first_order = np.zeros((len(speeds), 2 * r, 2 * r), dtype=complex)
    first_order[:, :r, r:] = np.eye(r)
    first_order[:, r:, :r] = -np.linalg.solve(mass, stiffness)
    first_order[:, r:, r:] = -np.linalg.solve(mass, damping)
    theta, vectors = np.linalg.eig(first_order)
    return theta, vectors[:, :r], mass


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
    step = max(1, _batches._CACHE_BYTES // (8 * damping[0].size))
    for part in (slice(p, p + step) for p in range(0, len(lam), step)):
        _quadratic_part(out[part], M if M.ndim == 2 else M[part], damping[part],
                        stiffness if stiffness.ndim == 2 else stiffness[part], squares[part], lam[part])
    return out


def _row_pencils(M, damping, stiffness, lam):
    """The pencils ``lam^2 M + lam D + K`` (P k, n, n) of ``k`` roots ``lam`` (P, k) of each row:
    each row's (k, 3) coefficients times its ``M``, ``D`` and ``K`` (3, n^2), one product
    (``M`` and ``K`` (n, n) where the rows share them, else (P, n, n); ``D`` (P, n, n))."""
    count, k = lam.shape
    n = M.shape[-1]
    coefficients = np.stack([lam ** 2, lam, np.ones_like(lam)], axis=-1)
    terms = np.empty((count, 3, n * n), complex)
    terms[:, 0] = M.reshape(-1, n * n)
    terms[:, 1] = damping.reshape(count, -1)
    terms[:, 2] = stiffness.reshape(-1, n * n)
    return (coefficients @ terms).reshape(count * k, n, n)


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
