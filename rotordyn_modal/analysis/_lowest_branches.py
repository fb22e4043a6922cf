"""The lowest modes of a model whose mounts have Maxwell branches, exact, without its full states.

A branch ``b`` (stiffness ``K_b`` at the stator's coordinates, relaxation time ``tau_b``; its
junction's six first-order states, :func:`..elements.mounts.with_branch_states`) eliminates
exactly: ``tau_b z_b' = E q - z_b`` gives ``z_b = E q / (1 + s tau_b)``, so every root ``s`` of the
state matrix with the branches' states that is not one of the branches' own relaxations solves

    ``T(s) x = (s^2 M + s (C + Omega G) + K + sum_b K_b s tau_b / (1 + s tau_b)) x = 0``

(``docs/theory.md`` section 17, "Mounts with Maxwell branches"). The route of :mod:`._lowest`
serves this rational pencil: the same speed-independent basis (undamped modes of the static
stiffness and attachment directions, the stator's coordinates among the bound's), the projected
pencils with the branches' states kept whole (a few per relaxation time: branches of one time are
one term) for the starts, and Newton's iteration on ``T(s)`` with
``T'(s) = 2 s M + C + Omega G + sum_b K_b tau_b / (1 + s tau_b)^2`` for the exact roots. The
completeness bound takes the branches' stiffness at its largest over the oscillating roots up to
``rho`` (:func:`largest_factor`). The relaxation roots (real, or damped beyond
``OVERDAMPED_LIMIT``) are no modes here as in every modal output; a speed whose lowest roots the
checks cannot confirm is solved whole (the full state matrix), refused before that work over the
limits as before.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np

from . import _batches, _lowest, _lowest_pencils, _lowest_starts, _vectors
from .modal import OVERDAMPED_LIMIT, is_oscillating

__all__ = ["lowest_roots", "roots_below", "roots_near", "largest_factor", "rational_terms"]

#: singular values of a relaxation time's summed stiffness below this times the largest are zero
#: (a branch given on the translations only has none on the rotations)
_RANK = 1e-12
#: entries of a relaxation time's summed stiffness below this times its largest are the shift
#: matrices' round-off (where the static stiffness has exact zeros): zero, so that they do not
#: widen the pencils' pattern (and cost the banded solve)
_ROUNDOFF = 64 * np.finfo(float).eps


def lowest_roots(stack, speeds, count: int, what: str = "speeds"):
    """The ``count`` lowest-frequency oscillating roots of a one-model stack with Maxwell branches
    (``stack.branch_times`` not empty) at every speed, each the full model's root to round-off.

    Parameters
    ----------
    stack : Stack
    speeds : ndarray, shape (S,) [rad/s]
    count : int
        Modes wanted per speed (>= 1).
    what : str
        What ``speeds`` are, in the fallback's warning (as :func:`._lowest.lowest_roots`).

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex [1/s]
        By frequency at each speed (not tracked).
    shapes : ndarray, shape (S, count, n), complex, unit norm
    full : ndarray of bool, shape (S,)
        The speeds solved whole (fallback, with a warning).
    """
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        values, shapes, ok = _reduced_roots(stack, speeds, count)
    if values.shape[1] >= count:            # the first count columns (no copy of every speed's shapes)
        out_values, out_shapes = values[:, :count], shapes[:, :count]
    else:
        out_values = np.full((len(speeds), count), np.nan + 0j)
        out_shapes = np.zeros((len(speeds), count, stack.n_dof), dtype=complex)
        out_values[:, :values.shape[1]], out_shapes[:, :values.shape[1]] = values, shapes
    full = ~ok
    if full.any():
        _lowest._refuse_long_full(stack, speeds[full], len(speeds), "lowest modes", _UNSERVED, "use fewer speeds")
        warnings.warn(f"lowest modes: {int(full.sum())} of {len(speeds)} {what} solved whole (the reduced basis "
                      "could not be shown to hold every root below the wanted ones there)", stacklevel=3)
        out_values[full], out_shapes[full] = _lowest._full_lowest(stack, speeds[full], count)
    return out_values, out_shapes, full


def roots_below(stack, speeds, limit: float, count: int | None = None):
    """:func:`._lowest.roots_below` of a model with Maxwell branches: every mode of frequency
    ``Im lam`` at most ``limit`` [rad/s] at every speed (the lowest ``count`` where given), as the
    lowest modes of :func:`lowest_roots`, as many as the undamped modes of the static stiffness up
    to ``1.1 limit`` and two more, twice as many until the highest lies above the limit at every
    speed (or every mode is among them).

    Returns
    -------
    eigenvalues, shapes, wanted, full
        As :func:`._lowest.roots_below`.
    """
    most = stack.forms[0].n_states // 2 if count is None else min(count, stack.forms[0].n_states // 2)
    omegas = _lowest._stack_bound(stack, RationalPencils(stack, speeds[:1]), _RationalBound).omegas
    first = min(int(np.searchsorted(omegas, 1.1 * limit)) + 2, most)
    values, shapes, full, _, _ = _lowest_past(stack, speeds, first, limit, most)
    return _lowest._cut_below(values, shapes, limit, count) + (full,)


def _lowest_past(stack, speeds, count, above, most):
    """:func:`lowest_roots` of ``count`` modes, twice as many (up to ``most``) until at every speed
    the highest lies above ``above`` [rad/s] (scalar or (S,)) or every mode is among them (fewer
    modes than asked for: relaxation roots after them). Returns its roots, shapes and speeds solved
    whole, and per speed whether every mode is among them (S,) and the highest ``Im lam`` (S,)."""
    while True:
        values, shapes, full = lowest_roots(stack, speeds, count)
        top = np.max(np.where(np.isfinite(values), values.imag, -np.inf), axis=1)
        every = ~is_oscillating(values).all(axis=1) | (count >= most)
        if count >= most or np.all(every | (top > above)):
            return values, shapes, full, every, top
        count = min(2 * count, most)


def roots_near(stack, x, centers, count: int):
    """The modes to pick a tracked mode from at trial speeds ``x`` (R,) of a critical speed's
    refinement, as ``_crossing_roots._roots_near`` returns them: the lowest ``count`` modes, twice as
    many until the highest lies above every center (R,), or every mode is among them.

    Returns
    -------
    lam : ndarray, shape (R, k), complex [1/s]
    shapes : ndarray, shape (R, k, n), complex (a repeated root's pair by whirl)
    radius : ndarray, shape (R,) [1/s]
        Every mode within it of the center is among them (the modes left out lie higher; the
        branches' relaxation roots are no candidates).
    """
    from ._eigensolve import resolve_repeated

    most = stack.forms[0].n_states // 2
    lam, shapes, _, every, top = _lowest_past(stack, x, min(count, most), centers.imag, most)
    radius = np.where(every, np.inf, np.maximum(top - centers.imag, 0.0))
    return lam, resolve_repeated(lam, shapes, stack.repeated_forms, np.zeros(len(x), int)), radius


#: why a speed is left to the full eigen-solve, for the refusal's message
_UNSERVED = ("the reduced basis of the mounts' Maxwell branches' rational stiffness could not be shown to hold "
             "every root there, or its pencil has fewer roots than asked for")


def _reduced_roots(stack, speeds, count):
    """:func:`._lowest._reduced_roots` on the rational pencil: roots (S, k), shapes (S, k, n) and
    whether the speed passed every check (S,). With a basis of every mode (a small model) the
    projected pencil is the full one: the ``count`` lowest of its roots are wanted (no ``count + 1``-th
    to check against), modes first and then, where it has fewer modes, its relaxation roots as
    the full solve's lowest roots are (:func:`._lowest.lowest_of`)."""
    n = stack.n_dof
    size = min(n, max(3 * count, count + 10))
    pencils = RationalPencils(stack, speeds)
    bound = _lowest._stack_bound(stack, pencils, _RationalBound)
    modes = bound.modes
    want = min(count + 1, size)
    few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _lowest._FEW))).astype(int))
    rho = _lowest._MARGIN * np.nanmax(np.abs(_projected_starts(pencils, modes[:, :size], want, few)[0]))
    size = min(n, max(_lowest._needed_size(bound, rho, size), want))
    complete = size >= n
    want = count if complete else want
    _, attached = bound.shares(size, rho)
    basis = np.hstack([modes[:, :size], attached])
    starts, values, shapes, ok, modal = _swept(stack, pencils, basis, want, complete)
    ok &= np.isfinite(starts).all(axis=1) & (modal.all(axis=1) | complete)
    ok &= _lowest._unmissed(starts, values, count)
    values, shapes = _lowest._by_frequency_over(values, shapes, count)
    ok &= _lowest._basis_suffices(np.where(modal, values, 0), bound, size, attached.shape[1], rho)
    if not complete:                    # the count-th root's other half the first start above it
        _lowest._cut_in_a_multiple_root(stack, pencils, bound, (values, shapes, ok), count, _projected_starts)
    return values, shapes, ok


def _swept(stack, pencils, basis, want, complete):
    """The ``want`` lowest projected roots of every speed (S, want), their full roots (S, want) in
    their order, unit shapes (S, want, n), whether each speed's converged to distinct modes (S,)
    and which starts were modes (S, want). Where every start is a mode and the basis is not
    ``complete``, the anchors are refined from their starts and the speeds between continued from
    the anchors' roots (:func:`._lowest._continued_sweep`, in parts of bounded memory); else every
    speed from its starts (:func:`_refined_modes`: the relaxation roots kept as they are)."""
    count = len(pencils.speeds)
    if not complete:
        anchors, at = _lowest._anchored(count)
        starts, vectors = _projected_starts(pencils, basis, want, vectors_at=at)
        modal = is_oscillating(starts)
        if modal.all():
            restart = functools.partial(_projected_starts, pencils, basis, want)
            values, shapes, ok = _lowest._continued_sweep(pencils, starts, vectors, anchors, restart)
            return starts, values, shapes, ok & _lowest._distinct(values, shapes), modal
        del vectors
    starts, vectors = _projected_starts(pencils, basis, want)
    return (starts, *_refined_modes(stack, pencils, starts, vectors))


def _refined_modes(stack, pencils, starts, vectors):
    """The oscillating starts (S, k) refined by :func:`._lowest._refined` on the rational pencil, the
    others (the branches' relaxation roots, by frequency after the modes) kept as they are: near a
    pole of ``T(s)`` they are no starts of Newton's iteration. Returns the roots (S, k), shapes
    (S, k, n), whether a speed's refined roots converged to distinct modes (S,) and which starts
    were modes (S, k)."""
    modal = is_oscillating(starts)
    values, shapes = starts.copy(), vectors.copy()
    ok = np.ones(len(starts), bool)
    found = modal.sum(axis=1)
    for k in np.unique(found[found > 0]):
        rows = np.nonzero(found == k)[0]
        part = pencils if len(rows) == len(starts) else RationalPencils(stack, pencils.speeds[rows])
        refined, refined_shapes, converged = _lowest._refined(part, starts[rows, :k], vectors[rows, :k])
        values[rows, :k], shapes[rows, :k] = refined, refined_shapes
        ok[rows] = converged & _lowest._distinct(refined, refined_shapes)
    return values, shapes, ok, modal


def rational_terms(stack):
    """The branches of one model grouped by relaxation time, each term's summed stiffness factored
    on the coordinates it acts on: ``K_t = U_t V_t^T`` (rank ``r_t``).

    Returns
    -------
    list of (times, coordinates, block, left, right)
        ``tau_t`` [s]; the coordinates (c,) where ``K_t`` has entries; ``K_t[c, c]`` (c, c)
        [N/m, ...]; ``U_t`` (c, r_t) [N/m, ...] and ``V_t`` (c, r_t) [1] (``K_t[c, c] = U_t V_t^T``).
    """
    stiffness, times = stack.branch_blocks(0)       # on the stator's coordinates, the model's first
    terms = []
    for tau in np.unique(times):
        total = stiffness[times == tau].sum(axis=0)
        total[np.abs(total) <= _ROUNDOFF * np.max(np.abs(total), initial=0.0)] = 0.0
        where = np.nonzero(np.any(total != 0, axis=0) | np.any(total != 0, axis=1))[0]
        block = total[np.ix_(where, where)]
        left, sigma, right = np.linalg.svd(block)
        rank = int(np.sum(sigma > _RANK * np.max(sigma, initial=0.0)))
        if rank:
            terms.append((float(tau), where, block, left[:, :rank] * sigma[:rank], right[:rank].T))
    return terms


def largest_factor(rho, tau):
    """The largest ``|s tau / (1 + s tau)|`` (the branch's share of its stiffness at ``s``) over the
    oscillating roots ``|s| <= rho`` (``Im s > 0``, damping ratio at most ``OVERDAMPED_LIMIT``).

    With ``w = 1 / (s tau)`` the factor is ``1 / |1 + w|``; ``|w| >= r_0 = 1 / (rho tau)`` and ``w``
    keeps at least the angle ``phi`` (``cos phi = OVERDAMPED_LIMIT``) from the negative real axis,
    where ``|1 + w|^2 = 1 - 2 |w| cos phi + |w|^2`` is least: ``sin phi`` at ``|w| = cos phi``, or at
    ``|w| = r_0`` where that is farther (``docs/theory.md`` section 17).

    Parameters
    ----------
    rho : float [rad/s]
    tau : ndarray, shape (T,) [s]

    Returns
    -------
    ndarray, shape (T,)
    """
    cosine = OVERDAMPED_LIMIT
    r0 = 1.0 / (rho * np.asarray(tau, dtype=float)) if rho > 0 else np.full(np.shape(tau), np.inf)
    nearest = np.where(r0 <= cosine, np.sqrt(1.0 - cosine ** 2),
                       np.sqrt(np.maximum(1.0 - 2.0 * r0 * cosine + r0 ** 2, 0.0)))
    with np.errstate(divide="ignore"):
        return np.where(np.isfinite(r0), 1.0 / nearest, 0.0)


class RationalPencils(_lowest._Pencils):
    """:class:`._lowest._Pencils` with the branches' rational stiffness: ``T(s)`` and ``T'(s)``
    (module docstring). The branches' coordinates join the bearings' speed-dependent entries (with
    zero coefficients): the sparse pattern holds them and the completeness bound counts them.

    Parameters
    ----------
    stack : Stack
        One model with Maxwell branches.
    speeds : ndarray, shape (S,) [rad/s]
    """

    def __init__(self, stack, speeds):
        self.terms = rational_terms(stack)
        super().__init__(stack, speeds)
        n = self.M.shape[0]
        rows, cols = self.pattern
        keys = cols * n + rows
        self.term_at, self.term_values = [], []
        for _, where, block, _, _ in self.terms:
            i, j = np.nonzero(block)
            self.term_at.append(np.searchsorted(keys, where[j] * n + where[i]))
            self.term_values.append(block[i, j])
        # the highest mode's scale with the branches' stiffness at its largest (``K + sum K_b``)
        stiffest = np.abs(_lowest_pencils._diagonal(self.K)).copy()
        for _, where, block, _, _ in self.terms:
            stiffest[where] += np.abs(np.diagonal(block))
        mass = _lowest_pencils._diagonal(self.M)
        self.scale = max(self.scale, float(np.max(stiffest / np.where(mass > 0, mass, np.inf))))

    def _speed_entries(self, stack, speeds):
        """The bearings' entries and, with zero coefficients, every entry of the branches' blocks
        not among them."""
        rows, cols, kb, cb = super()._speed_entries(stack, speeds)
        n = stack.n_dof
        present = rows * n + cols
        extra = []
        for _, where, block, _, _ in self.terms:
            i, j = np.nonzero(block)
            extra.append(where[i] * n + where[j])
        extra = np.setdiff1d(np.concatenate(extra) if extra else np.zeros(0, int), present)
        zeros = np.zeros((len(speeds), len(extra)))
        return (np.concatenate([rows, extra // n]), np.concatenate([cols, extra % n]),
                np.hstack([kb, zeros]), np.hstack([cb, zeros]))

    def _factors(self, lam, derivative=False):
        """``s tau / (1 + s tau)`` (or its derivative ``tau / (1 + s tau)^2``) of every term (P, T)."""
        tau = np.array([term[0] for term in self.terms], dtype=lam.real.dtype)
        s = lam[:, None]
        return tau / (1 + s * tau) ** 2 if derivative else s * tau / (1 + s * tau)

    def _terms_times(self, factors, x, precision=float, magnitude=False):
        """``sum_t factors[:, t] K_t x`` (P, n) in ``precision`` (moduli with ``magnitude``)."""
        out = np.zeros(x.shape, dtype=np.result_type(precision, x.dtype, 1j))
        for t, (_, where, block, _, _) in enumerate(self.terms):
            if magnitude:
                product = np.abs(x[:, where]) @ np.abs(block).T
            else:
                product = x[:, where] @ block.T.astype(precision)
            out[:, where] += (np.abs(factors[:, t]) if magnitude else factors[:, t])[:, None] * product
        return out.real if magnitude else out

    def more_terms(self, index, lam, x, precision=float, magnitude=False):
        """``sum_t K_t s tau_t / (1 + s tau_t) x`` (P, n) (see :meth:`._lowest._Pencils.more_terms`)."""
        return self._terms_times(self._factors(lam), x, precision, magnitude)

    def derivative_times(self, index, lam, x):
        """``T'(lam_p) x_p`` (P, n)."""
        return super().derivative_times(index, lam, x) + self._terms_times(self._factors(lam, True), x)

    def _entries(self, index, lam):
        """``T(lam_p)``'s entries on the pattern (P, nnz)."""
        data = super()._entries(index, lam)
        factors = self._factors(lam)
        for t, (at, values) in enumerate(zip(self.term_at, self.term_values)):
            data[:, at] += factors[:, t, None] * values
        return data

class _RationalBound(_lowest._Bound):
    """:class:`._lowest._Bound` with the branches' stiffness in the departure from ``K_0`` (the
    static stiffness): ``|B_k| + sum_t |K_t| largest_factor(rho, tau_t)`` at each ``rho``."""

    def __init__(self, pencils, omegas, modes, symmetric, products=None, kept=None):
        super().__init__(pencils, omegas, modes, symmetric, products, kept)
        self.static_norms = self.stiffness_norms
        self.term_norms = np.array([np.linalg.norm(term[2], 2) for term in pencils.terms])
        self.term_times = np.array([term[0] for term in pencils.terms])

    def shares(self, size, rho, directions=None, vectors=True):
        """:meth:`._lowest._Bound.shares` with the branches' stiffness at its largest up to ``rho``."""
        self.stiffness_norms = self.static_norms + self.term_norms @ largest_factor(rho, self.term_times)
        return super().shares(size, rho, directions, vectors)


def _projected_starts(pencils, basis, want, index=None, vectors_at=None):
    """The ``want`` lowest-frequency roots (oscillating first) of the projected rational pencils at
    every speed (or at the speeds ``index``), (S, want), and their vectors in full coordinates
    (S, want, n) (the modes, then the real roots; nan past the roots there are; with ``vectors_at``
    (S,) bool, at those speeds only, zero elsewhere, as :func:`._lowest_starts._projected_starts`): eigenvalues and
    eigenvectors of the projected state matrices with each term's states kept whole,
    ``y = [p, p', z_t]``, ``tau_t z_t' = V_t^T E W p - z_t`` and the force
    ``-W^T E^T U_t (V_t^T E W p - z_t)`` (exact for the projected pencil ``W^T T(s) W``)."""
    n, m = basis.shape
    index = np.arange(len(pencils.speeds)) if index is None else index
    speeds, cb, kb = pencils.speeds[index], pencils.cb[index], pencils.kb[index]
    Wt = basis.T
    # from the sweep's first speed: each speed's projected pencil its own whichever speeds are asked with it
    D0, K0, Gr = _lowest_starts.projected_first(pencils, _lowest_starts._FIRST, basis)
    left, right = basis[pencils.rows].T, basis[pencils.cols]
    ranks = [term[3].shape[1] for term in pencils.terms]
    size = 2 * m + sum(ranks)
    constant = np.zeros((size, size))
    constant[:m, m:2 * m] = np.eye(m)
    at = 2 * m
    for (tau, where, _, u, v), r in zip(pencils.terms, ranks):
        forced, sensed = Wt[:, where] @ u, v.T @ basis[where]               # (m, r), (r, m)
        constant[m:2 * m, :m] -= forced @ sensed
        constant[m:2 * m, at:at + r] = forced
        constant[at:at + r, :m] = sensed / tau
        constant[at:at + r, at:at + r] = -np.eye(r) / tau
        at += r
    starts = np.empty((len(speeds), want), complex)
    vectors = np.empty((len(speeds), want, n), complex)
    # the eigenvectors of every state matrix: in parts of _PART_BYTES, not of every speed at once
    for part in _batches.chunk_slices(len(speeds), 64 * size * size, budget=_batches._PART_BYTES):
        D = D0 + (speeds[part] - pencils.speeds[0])[:, None, None] * Gr
        Kr = np.broadcast_to(K0, D.shape)
        if len(pencils.rows):
            D = D + (left[None] * (cb[part] - pencils.cb[:1])[:, None, :]) @ right
            Kr = Kr + (left[None] * (kb[part] - pencils.kb[:1])[:, None, :]) @ right
        A = np.repeat(constant[None], len(D), axis=0)
        A[:, m:2 * m, :m] -= Kr             # the basis is mass-orthonormal: W^T M W = I
        A[:, m:2 * m, m:2 * m] = -D
        values, states = _batches._threaded(np.linalg.eig, A, item_bytes=80 * size * size)
        # one root of each pair: the modes by frequency, then the real roots; a lower conjugate
        # root is none (nan where fewer roots than wanted)
        key = np.where(values.imag < 0, np.nan, _lowest.frequency_key(values))
        order = np.argsort(key, axis=-1, kind="stable")[:, :want]
        rows, k = np.arange(len(values))[:, None], order.shape[1]
        starts[part, :k] = np.where(np.isnan(key[rows, order]), np.nan, values[rows, order])
        starts[part, k:], vectors[part] = np.nan, 0.0
        wanted = slice(None) if vectors_at is None else vectors_at[part]
        chosen = np.swapaxes(states[wanted], 1, 2)
        vectors[part][wanted, :k] = _vectors.unit_rows(chosen[np.arange(len(chosen))[:, None], order[wanted], :m] @ Wt)
    return starts, vectors
