"""The tracked mode's eigenvalue at a trial speed inside a crossing's bracket, for the refinement
(:mod:`._crossing_refinement`): the pencil's iteration from the bracket's interpolation, the Ritz
pairs of the sweep's shapes at the bracket's ends for large models, or the roots nearest the
interpolation, the mode identified among them by its shape (``docs/theory.md``, section 10).
"""

from __future__ import annotations

import numpy as np

from . import _batches, _eigensolve, _pencils, _vectors
from ._stack import Pencils

#: roots at each end of a bracket whose shapes span the subspace that a crossing among close
#: roots picks its mode from (:func:`_ritz_picked`) where the first, smaller one left it
_RITZ_ROOTS = 8
#: ... and of the first subspace tried (:func:`_ritz_evaluated`): a projected eigen-solve of 16
#: states instead of 32, which keeps nearly every pick (the 40-rotor chain's Ritz picks: 2.8 s
#: of CPU before, 1.0 s with the 294 of 4,009 rows it leaves tried again in the larger one)
_RITZ_FIRST = 4


#: pencils of more coordinates than this pick a crossing among close roots from Ritz pairs first
#: (:func:`_by_ritz`); up to ``_pencils.NEAREST_ROOTS_DOF`` the rows they leave take every root
_RITZ_DOF = 48


def _by_ritz(stack, shapes, iterates) -> bool:
    """Whether crossings among close roots are first picked from Ritz pairs (:func:`_ritz_picked`):
    one model of constant coefficients of more than ``_RITZ_DOF`` coordinates (or than
    ``_pencils.NEAREST_ROOTS_DOF``, where that is lower: every model whose roots near a point
    come from Arnoldi), with the sweep's shapes at hand (never where ``_RITZ_ROOTS`` is 0). The
    rows the pairs leave take the roots near the point (:func:`_tracked`): every root up to
    ``_pencils.NEAREST_ROOTS_DOF`` coordinates, above it the nearest by shift-invert Arnoldi
    (see :func:`_roots_near`)."""
    return (_RITZ_ROOTS > 0 and shapes is not None and iterates.shape.shape[-1] > 0 and len(stack) == 1
            and not stack.dependent
            and not stack.branch_times.shape[-1] and ritz_sized(stack.n_dof))


def ritz_sized(n_dof: int) -> bool:
    """Whether a pencil of ``n_dof`` coordinates is large enough for :func:`_by_ritz`'s route:
    more than ``_RITZ_DOF`` coordinates (or than ``_pencils.NEAREST_ROOTS_DOF``, where that is
    lower), and than ``_NEAREST_ROOTS``."""
    return n_dof > max(min(_RITZ_DOF, _pencils.NEAREST_ROOTS_DOF), _NEAREST_ROOTS)


def _ritz_evaluated(stack, speeds, values, shapes, weighted, brackets, rows, x, iterates):
    """The tracked modes' eigenvalues at ``x`` for crossings among close roots, without the
    roots near each point (one shift-invert Arnoldi call per crossing): the mode picked among
    the Ritz pairs of the sweep's shapes at the bracket's ends (:func:`_ritz_picked`, all rows
    in a few batched calls), then refined on the pencil from that pair (:func:`_pencil_at`: one
    factorisation per crossing, reused by its later points, which follow it there).

    The subspace is first the shapes of the ``_RITZ_FIRST`` roots nearest the interpolation at
    each end (a projected eigen-solve of ``4 _RITZ_FIRST`` states); the rows it leaves (no pick
    kept, or not converged) try the ``_RITZ_ROOTS`` nearest, with their iterates as they were
    (:func:`_ritz_tried`).

    A row counts only where the pencil's eigenpair converged within a quarter of the distance
    from its Ritz value to the nearest other one (and to its own conjugate), with a shape
    whose MAC with the Ritz vector is at least ``_RITZ_MAC``; the others are left to
    :func:`_tracked` as before, with their iterates as they were.

    Returns
    -------
    lam : ndarray (P,), complex
    ok : ndarray (P,) bool
    """
    lam = np.full(len(rows), np.nan, dtype=complex)
    ok = np.zeros(len(rows), dtype=bool)
    left = np.arange(len(rows))
    for count in sorted({min(_RITZ_FIRST, _RITZ_ROOTS), _RITZ_ROOTS} - {0}):
        if not len(left):
            break
        lam[left], ok[left] = _ritz_tried(stack, speeds, values, shapes, weighted, brackets, rows[left], x[left],
                                          iterates, count)
        left = left[~ok[left]]
    return lam, ok


def _ritz_tried(stack, speeds, values, shapes, weighted, brackets, rows, x, iterates, count):
    """:func:`_ritz_evaluated` with the subspace of the ``count`` roots nearest the interpolation
    at each end of the bracket: (lam (P,), ok (P,)); the rows not ok keep their iterates as
    they were."""
    lam = np.full(len(rows), np.nan, dtype=complex)
    ok = np.zeros(len(rows), dtype=bool)
    size = 2 * min(count, values.shape[-1])
    for part in _batches.chunk_slices(len(rows), 64 * size * stack.n_dof, budget=_RITZ_BYTES):
        picked, vectors, gap, good = _ritz_picked(stack, values, shapes, weighted, brackets, rows[part], x[part],
                                                  count)
        at = np.arange(part.start, part.stop)[good]
        if not len(at):
            continue
        mine = rows[at]
        saved = (iterates.x[mine], iterates.lam[mine], iterates.shape[mine], iterates.gap[mine],
                 iterates.factors.ready[mine])
        iterates.x[mine], iterates.lam[mine], iterates.shape[mine], iterates.gap[mine] = \
            x[at], picked[good], vectors[good], gap[good]
        found, converged = _pencil_at(stack, speeds, brackets, mine, x[at], iterates)
        mac = np.abs(np.einsum("pi,pi->p", vectors[good].conj(), iterates.shape[mine])) ** 2
        converged &= mac >= _RITZ_MAC
        lost = (~converged).nonzero()[0]
        if len(lost):                                   # as they were, for the next try or _tracked
            for column, value in zip((iterates.x, iterates.lam, iterates.shape, iterates.gap, iterates.factors.ready),
                                     saved):
                column[mine[lost]] = value[lost]
        lam[at], ok[at] = found, converged
    return lam, ok


#: the least MAC of a Ritz vector with the pencil's eigenvector refined from it
_RITZ_MAC = 0.9
#: the largest part of the Ritz subspaces built at once [bytes]
_RITZ_BYTES = 64 * 2**20


def _ritz_picked(stack, values, shapes, weighted, brackets, rows, x, count=None):
    """The tracked mode at ``x`` among the Ritz pairs (:func:`_pencils.projected_roots`) of the
    pencil in the span of the sweep's shapes of the ``count`` (default ``_RITZ_ROOTS``) roots
    nearest the bracket's interpolation at each end of the bracket, picked as :func:`_identified`
    picks among roots: by the mass-weighted MAC with its shape at the bracket's start and the
    distance from the interpolation.

    Every root at ``x`` nearer the interpolation than ``radius`` (the nearest root left out at
    either end, less the fastest travel of any root across the bracket) was among those roots
    at both ends; a pick is kept where its cost is within ``radius / spread`` (as
    :func:`_identified` asks of the roots at hand), finite, and apart from every other Ritz
    value (and its own conjugate) by more than a repeated root.

    Returns
    -------
    picked : ndarray (P,), complex
        The Ritz value.
    vectors : ndarray (P, n), complex, unit norm
        Its Ritz vector.
    gap : ndarray (P,)
        Its distance to the nearest other Ritz value of the upper half-plane or its conjugate.
    kept : ndarray (P,) bool
    """
    count = min(_RITZ_ROOTS if count is None else count, values.shape[-1])
    every = np.arange(len(rows))
    v, k, mode = brackets.variant[rows], brackets.k[rows], brackets.mode[rows]
    expected = _interpolated(brackets, rows, x)
    spread = brackets.spread[rows]
    ends = k[:, None] + np.arange(2)                                                   # (P, 2)
    roots = values[v[:, None], ends]                                                   # (P, 2, m)
    distance = np.abs(roots - expected[:, None, None])
    distance[np.isnan(distance)] = np.inf
    nearest = np.argsort(distance, axis=-1)
    radius = np.full(len(rows), np.inf)
    if count < values.shape[-1]:
        beyond = np.take_along_axis(distance, nearest[..., count:count + 1], axis=-1)[..., 0]
        radius = beyond.min(axis=1) - brackets.travel[rows]
    vectors = shapes[v[:, None, None], ends[:, :, None], nearest[..., :count]]        # (P, 2, c, n)
    basis = np.linalg.qr(vectors.reshape(len(rows), 2 * count, -1).swapaxes(1, 2))[0]  # (P, n, 2c)
    theta, coefficients, mass = _pencils.projected_roots(basis, _basis_products(stack, basis), x)
    theta = np.where(theta.imag > 0, theta, np.nan)                                     # upper roots only
    # mass-weighted correlation with the reference: psi^H L^T W y, with M = L L^T
    left = stack.unweighted(weighted[v, k, mode].conj())                                # (P, n)
    along = np.einsum("pr,prj->pj", np.einsum("pn,pnr->pr", left, basis), coefficients)
    norms = np.einsum("prj,prs,psj->pj", coefficients.conj(), mass, coefficients).real
    with np.errstate(all="ignore"):
        cost = (1 - np.abs(along) ** 2 / norms) + np.abs(theta - expected[:, None]) / spread[:, None]
    cost[~np.isfinite(cost)] = np.inf
    j = np.argmin(cost, axis=1)
    picked, best = theta[every, j], cost[every, j]
    apart = np.abs(theta - picked[:, None])
    apart[every, j] = np.inf
    apart[np.isnan(apart)] = np.inf
    gap = np.minimum(apart.min(axis=1), 2 * np.abs(picked.imag))
    scale = np.nanmax(np.abs(roots[:, 0]), axis=1)
    kept = np.isfinite(best) & (best <= radius / spread) & (gap > _eigensolve.REPEATED_TOLERANCE * scale)
    vectors = _vectors.unit_rows(np.einsum("pnr,pr->pn", basis, coefficients[every, :, j]))
    return picked, vectors, gap, kept


def _basis_products(stack, basis):
    """``M W, C W, G W, K W`` of one model's constant matrices and bases ``W`` (P, n, r): sparse
    products where the model's pencils are sparse (:meth:`~._stack.Stack.sparse_entries`)."""
    count, n, r = basis.shape
    sparse = stack.sparse_matrices()
    if sparse is None:
        flat = basis.swapaxes(1, 2)                                                     # (P, r, n)
        return tuple(_vectors.real_product(flat, matrix[0].T).swapaxes(1, 2) for matrix in
                     (stack.M, stack.C, stack.G, stack.K))
    columns = basis.transpose(1, 0, 2).reshape(n, count * r)
    return tuple((matrix @ columns).reshape(n, count, r).transpose(1, 0, 2) for matrix in sparse)


def _followed(brackets, rows, x, iterates):
    """Crossings whose mode was picked from the roots at a point so near ``x`` that no root
    can have moved a tenth of the distance to its nearest neighbour there (at four times the
    fastest travel across the bracket of any root of the sweep): the pencil's iteration from
    that eigenpair then finds the same mode."""
    moved = 4 * brackets.travel[rows] * np.abs(x - iterates.x[rows]) / brackets.width[rows]
    with np.errstate(invalid="ignore"):
        return ~iterates.usable[rows] & (moved < 0.1 * iterates.gap[rows])


def _pencil_at(stack, speeds, brackets, rows, x, iterates):
    """Eigenvalues of isolated or followed modes (:func:`_followed`) at ``x`` by residual inverse
    iteration on the pencil (:func:`_pencils.residual_inverse_iteration`), started from the last
    point's eigenvalue (moved by the interpolation's change) and shape. A crossing's first
    evaluation factors its pencil at the cubic interpolation of the sweep's eigenvalues there;
    later ones reuse that factorisation, and factor anew only where the iteration did not
    converge. Returns the eigenvalues and which converged to the tracked mode."""
    pencils = Pencils(stack, brackets.variant[rows], x)
    unready = ~iterates.factors.ready[rows]
    if unready.all() and (iterates.x[rows] == brackets.start[rows]).all():
        # every crossing's first evaluation (the usual case): all start from the cubic, factored there
        expected = _interpolated(brackets, rows, x)
        start = _cubic_value(speeds, brackets, rows, x, expected)
        matrices = iterates.factors.factor(rows, pencils, start)
        again = ()
    else:
        matrices = None
        # the interpolation here and at the last point, together
        expected, before = _interpolated(brackets, rows, np.array((x, iterates.x[rows])))
        start = iterates.lam[rows] + expected - before
        fresh = unready.nonzero()[0]
        if len(fresh):
            untouched = fresh[iterates.x[rows[fresh]] == brackets.start[rows[fresh]]]    # nothing evaluated yet
            if len(untouched):
                start[untouched] = _cubic_value(speeds, brackets, rows[untouched], x[untouched])
        if iterates.factors.whole:
            # small pencils anew at this speed's start: the last point's are at its converged
            # eigenvalue, singular to round-off, and a residual step through them barely contracts
            # (a step of 4e-10 left an error of 1e-8 in the shape)
            matrices = iterates.factors.factor(rows, pencils, start)
            again = ()
        else:
            if len(fresh):
                iterates.factors.factor(rows[fresh], _pencils.PencilRows(pencils, fresh), start[fresh])
            again = None
    lam, shapes, converged = _pencils.residual_inverse_iteration(iterates.factors, rows, pencils, start,
                                                               iterates.shape[rows], matrices=matrices)
    if again is None:
        again = (~converged & np.isfinite(lam) & ~unready).nonzero()[0]
    if len(again):
        # far from the factored point (or a poor start there): factor here and iterate again
        part = _pencils.PencilRows(pencils, again)
        iterates.factors.factor(rows[again], part, lam[again])
        lam[again], shapes[again], converged[again] = _pencils.residual_inverse_iteration(
            iterates.factors, rows[again], part, lam[again], shapes[again])
    ok = converged & (np.abs(lam - expected) <= 2 * brackets.spread[rows])
    followed = ~iterates.usable[rows]
    if followed.any():
        with np.errstate(invalid="ignore"):
            ok[followed] &= np.abs(lam - start)[followed] < 0.25 * iterates.gap[rows[followed]]
    if ok.all():
        iterates.x[rows], iterates.lam[rows], iterates.shape[rows] = x, lam, shapes
    else:
        iterates.x[rows[ok]], iterates.lam[rows[ok]], iterates.shape[rows[ok]] = x[ok], lam[ok], shapes[ok]
    return lam, ok


def _cubic_value(speeds, brackets, rows, x, linear=None):
    """The tracked modes' eigenvalues at ``x`` by the cubic through the sweep's four nearest
    points (linear across the bracket where fewer than four oscillating points are at hand;
    ``linear``, :func:`_interpolated` at ``x``, when the caller has it)."""
    if len(speeds) < 4 or not len(rows):
        return _interpolated(brackets, rows, x) if linear is None else linear
    xs, lam = brackets.near_speeds[rows], brackets.near_values[rows]
    # Lagrange weights: factor[p, j, m] = (x - xs_m) / (xs_j - xs_m), 1 where m = j (exact, so the
    # products below equal the ones over m != j in the same order)
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = (x[:, None, None] - xs[:, None, :]) / (xs[:, :, None] - xs[:, None, :])
    factor.reshape(len(x), 16)[:, ::5] = 1.0                        # the diagonals
    weights = factor[..., 0] * factor[..., 1] * factor[..., 2] * factor[..., 3]
    cubic = np.einsum("pj,pj->p", weights, lam)
    cubic_here = brackets.near_oscillating[rows]
    if cubic_here.all():
        return cubic
    linear = _interpolated(brackets, rows, x) if linear is None else linear
    return np.where(cubic_here, cubic, linear)


def _interpolated(brackets, rows, x):
    """The tracked modes' eigenvalues interpolated linearly across their brackets at ``x``."""
    t = (x - brackets.start[rows]) / brackets.width[rows]
    return (1 - t) * brackets.low[rows] + t * brackets.high[rows]


def _tracked(stack, speeds, values, weighted, brackets, rows, x):
    """The tracked modes' eigenvalues at speeds ``x``: the nearest to the bracket's
    interpolation, confirmed by the mode shape where another eigenvalue is about as near.

    Returns
    -------
    lam : ndarray (P,), complex
    sure : ndarray (P,) bool
        Told apart by distance alone and single (its shape then follows from one
        inverse-iteration step).
    shapes : ndarray (P, n), complex
        The shape of each eigenvalue where ``known`` (the roots came with their shapes, or the
        mode was identified by its shape).
    known : ndarray (P,) bool
    gap : ndarray (P,)
        Distance from each eigenvalue to the nearest other root (of those at hand) [1/s].
    """
    expected = _interpolated(brackets, rows, x)
    lam, phi, radius, paired = _candidates_of(stack, values, brackets, rows, x, expected)
    distance = np.abs(lam - expected[:, None])
    nearest, second = np.argsort(distance, axis=1)[:, :2].T
    every = np.arange(len(x))
    picked = lam[every, nearest]
    shapes = np.zeros((len(x), stack.n_dof), dtype=complex)
    known = np.zeros(len(x), dtype=bool)
    if phi is not None:
        shapes, known = phi[every, nearest], np.ones(len(x), dtype=bool)
    unsure = _unsure(distance, nearest, second, brackets.spread[rows])
    if paired is not None:                    # identified below
        unsure[paired[0]] = False
    if unsure.any():
        mine = brackets.subset(rows[unsure])
        if phi is None:
            picked[unsure], shapes[unsure] = _modes_at(stack, speeds, values, weighted, mine, x[unsure])
        else:
            picked[unsure], shapes[unsure] = _identified(stack, speeds, values, weighted, mine, x[unsure],
                                                         lam[unsure], phi[unsure], radius[unsure])
        known |= unsure
    if paired is not None:                    # rows whose shapes came with their roots: identified by them
        at, lam_at, phi_at, radius_at = paired
        mine = brackets.subset(rows[at])
        picked[at], shapes[at] = _identified(stack, speeds, values, weighted, mine, x[at], lam_at, phi_at, radius_at)
        known[at] = unsure[at] = True
    scale = np.nanmax(np.abs(lam), axis=1)
    if lam.shape[1] < values.shape[-1]:       # a few roots only: the largest is the sweep's
        scale = np.maximum(scale, np.abs(values[brackets.variant[rows], brackets.k[rows]]).max(axis=1))
    repeated = np.sort(np.abs(lam - picked[:, None]), axis=1)[:, 1] <= _eigensolve.REPEATED_TOLERANCE * scale
    known &= unsure | ~repeated            # a repeated root's shape is told by the MAC (_modes_at)
    gap = np.sort(np.abs(lam - picked[:, None]), axis=1)[:, 1]
    return picked, ~unsure & ~repeated, shapes, known, gap


def _unsure(distance, nearest, second, spread):
    """Rows (P,) whose nearest root to the interpolation (``distance`` (P, j), the columns
    ``nearest`` and ``second`` (P,)) is not told apart from the next by distance alone."""
    every = np.arange(len(distance))
    return distance[every, second] <= 4 * distance[every, nearest] + 2 * spread


def _candidates_of(stack, values, brackets, rows, x, expected):
    """:func:`_tracked`'s roots at ``x``: :func:`_candidates` (no shapes where they are all the
    roots of a small model, found by ``eigvals``), and the rows whose mode is a repeated root at
    both ends of its bracket (:func:`_repeated_at_ends`) solved with their shapes at once and
    kept apart, where they are not told apart by distance: their mode is identified by its shape
    (:func:`_identified`, as :func:`_modes_at` would after an ``eigvals`` of the same matrices).

    Returns
    -------
    lam (P, j), phi (P, j, n) or None, radius (P,) : as :func:`_candidates` for every row;
    paired : None, or (rows (Q,) of those kept apart, and their roots (Q, j), shapes
    (Q, j, n) and radii (Q,)), whose ``lam`` rows are these roots
    """
    variants = brackets.variant[rows]
    paired = _repeated_at_ends(values, brackets, rows) if _without_shapes(stack, values) else None
    if paired is None or not paired.any():
        return (*_candidates(stack, values, variants, x, expected), None)
    at = paired.nonzero()[0]
    lam_at, phi_at, radius_at = _candidates(stack, values, variants[at], x[at], expected[at], True)
    distance = np.abs(lam_at - expected[at, None])
    nearest, second = np.argsort(distance, axis=1)[:, :2].T
    told = ~_unsure(distance, nearest, second, brackets.spread[rows[at]])
    if told.any():                            # told apart by distance after all: as every other row
        paired[at[told]] = False
        at, lam_at, phi_at, radius_at = at[~told], lam_at[~told], phi_at[~told], radius_at[~told]
    rest = (~paired).nonzero()[0]
    lam = np.empty((len(x), lam_at.shape[1]), dtype=complex)
    radius = np.full(len(x), np.inf)
    if len(rest):
        lam[rest], _, radius[rest] = _candidates(stack, values, variants[rest], x[rest], expected[rest])
    if not len(at):
        return lam, None, radius, None
    lam[at], radius[at] = lam_at, radius_at
    return lam, None, radius, (at, lam_at, phi_at, radius_at)


def _without_shapes(stack, values) -> bool:
    """Whether :func:`_candidates` without shapes gives every root of a small model, without
    their shapes (``eigvals``)."""
    lowest_branches = (len(stack) == 1 and stack.branch_times.shape[-1]
                       and values.shape[-1] < stack.forms[0].n_states // 2)
    return not lowest_branches and (stack.n_dof <= max(_pencils.NEAREST_ROOTS_DOF, _NEAREST_ROOTS)
                                    or bool(stack.branch_times.shape[-1]))


def _repeated_at_ends(values, brackets, rows):
    """(P,) bool: the tracked mode of each crossing ``rows`` is a repeated root (another within
    ``_eigensolve.REPEATED_TOLERANCE`` of the largest root, as :func:`_tracked` tests) at both
    ends of its bracket in the sweep's roots ``values`` (V, N, m): its eigenvalue inside the
    bracket is then almost surely repeated too, and identified by its shape."""
    v, k, mode = brackets.variant[rows], brackets.k[rows], brackets.mode[rows]
    ends = values[v[:, None], k[:, None] + np.arange(2)]                              # (P, 2, m)
    own = ends[np.arange(len(rows)), :, mode]                                           # (P, 2)
    apart = np.abs(ends - own[..., None])
    apart[np.arange(len(rows)), :, mode] = np.inf
    apart[np.isnan(apart)] = np.inf
    scale = np.abs(np.where(np.isnan(ends), 0, ends)).max(axis=-1)
    return (apart.min(axis=-1) <= _eigensolve.REPEATED_TOLERANCE * scale).all(axis=1)


#: roots nearest the interpolation that a large model's crossing first picks its mode from
#: (more where a root beyond them could be the mode: see :func:`_identified`)
_NEAREST_ROOTS = 8


def _roots_near(stack, variants, x, centers, shapes=False, count=None):
    """The upper roots at speeds ``x`` to pick the tracked mode from, their unit shapes, and the
    distance from ``centers`` within which every root is among them: for large models (see
    :func:`_pencils.nearest_roots`) the ``count`` nearest ``centers``, (R, count) and (R, count,
    n); else (or where ``count`` reaches the coordinates) all of them, (R, m), with shapes (R, m,
    n) only when ``shapes`` (None otherwise), and an infinite radius. ``count`` defaults to
    ``_NEAREST_ROOTS``."""
    count = _NEAREST_ROOTS if count is None else count
    if stack.n_dof <= max(_pencils.NEAREST_ROOTS_DOF, count) or stack.branch_times.shape[-1]:
        return (*_all_roots(stack, variants, x, shapes), np.full(len(x), np.inf))
    lam, phi, radius = _pencils.nearest_roots(Pencils(stack, variants, x), centers, count)
    failed = np.nonzero(np.all(np.isnan(lam), axis=1))[0]
    if len(failed):                                    # ARPACK did not converge: all roots, the nearest kept
        every, every_phi = _all_roots(stack, variants[failed], x[failed], True)
        distance = np.abs(every - centers[failed, None])
        nearest = np.argsort(distance, axis=1)
        kept = min(lam.shape[1], nearest.shape[1])     # a small model may have fewer roots than asked
        lam[failed, :kept] = np.take_along_axis(every, nearest[:, :kept], axis=1)
        phi[failed, :kept] = np.take_along_axis(every_phi, nearest[:, :kept, None], axis=1)
        radius[failed] = np.inf if kept == nearest.shape[1] else \
            np.take_along_axis(distance, nearest[:, kept:kept + 1], axis=1)[:, 0]
    lam = np.where(lam.imag < 0, np.nan, lam)          # the lower roots are not candidates
    return lam, _eigensolve.resolve_repeated(lam, phi, stack.repeated_forms, variants), radius


def _candidates(stack, values, variants, x, centers, shapes=False, count=None):
    """:func:`_roots_near`; where the sweep's roots ``values`` (V, S, k) are the lowest modes only
    (fewer columns than roots) of a model with Maxwell branches, the lowest modes up to past the
    centers from their rational pencil instead (no state matrix solved whole:
    :func:`._lowest_branches.roots_near`)."""
    if len(stack) == 1 and stack.branch_times.shape[-1] and values.shape[-1] < stack.forms[0].n_states // 2:
        from ._lowest_branches import roots_near

        return roots_near(stack, x, centers, _NEAREST_ROOTS if count is None else count)
    return _roots_near(stack, variants, x, centers, shapes, count)


def _masses(stack, variants):
    """The mass matrix of each row's variant (n, n) or (P, n, n), with which a slow root is judged
    by its shape (:func:`._eigensolve.eigenvalues_of`); None for a model kept sparse (no dense n x n
    matrix of it is formed: its slow roots below the square root of round-off are zero roots)."""
    if stack.sparse_constant is not None:
        return None
    return stack.M[0] if len(stack.M) == 1 else stack.M[variants]


def _all_roots(stack, variants, x, shapes):
    """All upper roots of the state matrices at ``x`` (R, m), with their unit shapes (R, m, n)
    when ``shapes`` (None otherwise)."""
    size = stack.forms[0].n_states
    if shapes:
        return _batches.concatenated([stack.solve(stack.at(variants[part], x[part]), variants[part])
                                    for part in _batches.chunk_slices(len(x), 80 * size * size)])
    return _batches.concatenated([_eigensolve.select_upper(_eigensolve.eigenvalues_of(
        stack.at(variants[part], x[part]), stack.n_dof, _masses(stack, variants[part])))
                                for part in _batches.chunk_slices(len(x), 32 * size * size)]), None


def _shapes_at(stack, speeds, values, weighted, brackets, roots, lam, sure, iterates):
    """Eigenvalues and shapes at the roots: the last evaluation's where it was at the root and
    gave one (the pencil iteration's, the nearest roots', an identification's), else one
    inverse-iteration step on the eigenvalue found, or a full identification
    (:func:`_modes_at`) where it was unsure or the eigenvalue is repeated."""
    known = (iterates.x == roots) & (iterates.lam == lam)
    if known.all() and iterates.shape.shape[-1]:
        return lam.copy(), iterates.shape.copy()        # every root the pencil iteration's last point
    lam = lam.copy()
    phi = np.empty((len(roots), stack.n_dof), dtype=complex)
    if known.any():
        phi[known] = iterates.shape[known]
    rest = np.nonzero(~known & sure)[0]
    if len(rest):
        phi[rest] = stack.shapes_at(brackets.variant[rest], roots[rest], lam[rest])
    rows = np.nonzero(~sure & ~known)[0]
    if len(rows):
        lam[rows], phi[rows] = _modes_at(stack, speeds, values, weighted, brackets.subset(rows), roots[rows])
    return lam, phi


def _modes_at(stack, speeds, values, weighted, brackets, x):
    """Eigenvalue and shape of each bracket's tracked mode at ``x`` (see :func:`_identified`)."""
    expected = _interpolated(brackets, np.arange(len(x)), x)
    lam, phi, radius = _candidates(stack, values, brackets.variant, x, expected, True)
    return _identified(stack, speeds, values, weighted, brackets, x, lam, phi, radius)


def _identified(stack, speeds, values, weighted, brackets, x, lam, phi, radius):
    """The tracked mode among roots ``lam`` (P, j) with shapes ``phi`` (P, j, n) at ``x``:
    by the mass-weighted MAC against its shape at the bracket's start and the eigenvalue
    distance. Returns its eigenvalue (P,) and shape (P, n).

    The roots at hand are every root within ``radius`` (P,) of the bracket's interpolation. A
    root beyond costs at least ``radius / spread``; where the best at hand costs more (a
    cluster of many close roots, such as the like rotors of a large machine), that row takes
    four times as many roots nearest the interpolation, until this holds or it has them all."""
    rows = np.arange(len(x))
    expected = _interpolated(brackets, rows, x)
    psi = stack.weighted(phi, brackets.variant)
    reference = weighted[brackets.variant, brackets.k, brackets.mode]                   # (P, n)
    correlation = np.abs(np.einsum("pn,pjn->pj", reference.conj(), psi)) ** 2
    spread = brackets.spread[rows]
    cost = (1 - correlation) + np.abs(lam - expected[:, None]) / spread[:, None]
    j = np.argmin(np.where(np.isnan(cost), np.inf, cost), axis=1)
    picked, shape = lam[rows, j], phi[rows, j]
    short = np.nonzero(~(cost[rows, j] <= radius / spread) & np.isfinite(radius))[0]
    if len(short):
        more = _candidates(stack, values, brackets.variant[short], x[short], expected[short], True, 4 * lam.shape[1])
        picked[short], shape[short] = _identified(stack, speeds, values, weighted, brackets.subset(short), x[short],
                                                  *more)
    return picked, shape
