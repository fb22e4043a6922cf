"""The crossings of the critical speeds refined on their brackets: Newton's method on the eigenpair
and the speed together for the isolated modes of small pencils, else secant (Illinois) steps on
the speed from a cubic start, with the tracked mode's eigenvalue evaluated at each step
(:mod:`._crossing_roots`); in parts of bounded memory (``docs/theory.md``, section 10).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import _batches, _pencils, _vectors
from ._critical_progress import _progress_advance
from ._crossing_roots import (_by_ritz, _cubic_value, _followed, _interpolated, _pencil_at, _ritz_evaluated,
                              _shapes_at, _tracked)

#: evaluations allowed per crossing (it needs two or three; bisection steps guarantee the rest)
_MAX_ITERATIONS = 200
#: a step below this fraction of max(|Omega|, 1 rad/s) ends the iteration (Brent's xtol before)
_STEP_TOLERANCE = 1e-13


def _refine_parts(stack, speeds, values, weighted, brackets, shapes=None):
    """The crossings refined (:func:`_refined_part`: Newton's method where it applies, else the
    secant of :func:`_refine_together`) with the eigenvalues and shapes at the roots, in parts
    of the crossings whose factorisations fit in ``_batches.CHUNK_BYTES``.

    Returns
    -------
    roots : ndarray (P,) [rad/s]; lam : ndarray (P,), complex; ratio : ndarray (P,), the whirl
    ratios; fingerprint : ndarray (P, f), complex (:func:`_fingerprints`); sure : ndarray (P,) bool
    """
    chunks = _batches.chunk_slices(len(brackets.k), 64 * stack.n_dof ** 2)
    if len(chunks) == 1:                             # all in one part (small models): no copies
        found = _compact(stack, brackets, *_exact_crossings(
            stack, brackets, *_refined_part(stack, speeds, values, weighted, brackets, shapes)))
        _progress_advance(len(brackets.k))
        return found
    parts = []
    for part in chunks:
        mine = brackets.subset(part)
        parts.append(_compact(stack, mine, *_exact_crossings(
            stack, mine, *_refined_part(stack, speeds, values, weighted, mine, shapes))))
        _progress_advance(len(mine.k))
    return _batches.concatenated(parts)


def _compact(stack, brackets, roots, lam, phi, sure):
    """A part's refined crossings with each shape replaced by what is kept of it: its whirl
    ratio and its fingerprint (:func:`_fingerprints`)."""
    ratio = stack.whirl_ratios(phi[:, None], brackets.variant, roots)[:, 0]
    return roots, lam, ratio, _fingerprints(phi), sure


#: secant steps at most of a crossing on the polished roots (:func:`_exact_crossings`; it takes 2 to 4)
_EXACT_STEPS = 10


def _exact_crossings(stack, brackets, roots, lam, phi, sure):
    """The crossings ``roots`` (P,) [rad/s] with eigenvalues ``lam`` (P,) and shapes ``phi`` (P, n)
    of a stack whose sweep had roots double precision leaves further off than
    :data:`._eigensolve.POLISH_LEVEL` (``stack.inexact``, set by :func:`.campbell._refine_inexact`),
    solved again on the polished roots: where the tracked root at the crossing is itself inexact,
    secant steps on ``g(Omega) = Im lam(Omega) - slope |Omega|`` with ``lam`` the polished root
    (:func:`_exact_root_at`) until a step is below ``_STEP_TOLERANCE``; the pencil iteration above
    converges to a nearby pencil's root (its residual in double), off by the root's round-off
    (docs/theory.md, "Close roots"). Every other stack's crossings are returned as they are."""
    if not stack.inexact or not len(roots):
        return roots, lam, phi, sure
    roots, lam, phi = roots.copy(), lam.copy(), phi.copy()
    for p in range(len(roots)):
        found = _exact_crossing(stack, brackets.subset([p]), roots[p], lam[p], phi[p])
        if found is not None:
            roots[p], lam[p], phi[p] = found
    return roots, lam, phi, sure


def _exact_crossing(stack, bracket, speed, value, shape):
    """:func:`_exact_crossings` of one crossing (``bracket`` its one row): the speed, eigenvalue
    and unit shape on the polished roots, or None where the root there is exact in double (or
    the steps do not converge inside the bracket)."""
    slope, start, width = float(bracket.slope[0]), float(bracket.start[0]), float(bracket.width[0])
    sign = np.sign(stack.whirl_ratios(shape[None, None], bracket.variant, np.array([speed]))[0, 0])
    found = _exact_root_at(stack, int(bracket.variant[0]), speed, value, sign)
    if found is None:
        return None
    x0, lam0 = speed, found[0]
    g0 = lam0.imag - slope * abs(x0)
    # the first step's slope from the bracket's ends (g moves by its own error's size only)
    dg = (bracket.high[0].imag - bracket.low[0].imag) / width - slope * np.sign(x0 if x0 else 1.0)
    x1 = x0 - g0 / dg
    for _ in range(_EXACT_STEPS):
        if not start - 1e-9 * width <= x1 <= start + width * (1 + 1e-9):
            return None
        found = _exact_root_at(stack, int(bracket.variant[0]), x1, lam0, sign, always=True)
        if found is None:
            return None
        lam1, phi1 = found
        g1 = lam1.imag - slope * abs(x1)
        step = 0.0 if g1 == g0 else -g1 * (x1 - x0) / (g1 - g0)
        if abs(x1 - x0) <= _STEP_TOLERANCE * max(abs(x1), 1.0) or step == 0.0:
            return x1, lam1, phi1
        x0, g0, x1 = x1, g1, x1 + step
    return None


def _exact_root_at(stack, v, speed, near, sign, always=False):
    """The root of variant ``v`` at ``speed`` [rad/s] nearest ``near`` among those of whirl sign
    ``sign`` (any where none is), with its unit shape, after the full solve's polish
    (:func:`._eigensolve.refined_pairs`); None where that root is exact in double (its round-off
    at most :data:`._eigensolve.POLISH_LEVEL`) unless ``always``."""
    from . import _eigensolve

    form = stack.forms[v]
    values, shapes = _eigensolve.solve_batch(form, np.array([speed]))
    values, shapes = values[0], shapes[0]
    bound, damping, stiffness, branches = _eigensolve.round_off_at(form, speed, values, shapes)
    reach = max(np.max(bound), 1e-6) * 4 * abs(near)
    close = np.flatnonzero(np.abs(values - near) <= reach)
    if not len(close):
        close = np.array([int(np.argmin(np.abs(values - near)))])
    if not always and np.all(bound[close] <= _eigensolve.POLISH_LEVEL):
        return None
    _eigensolve.refined_pairs(values, shapes, form.matrices.M, damping, stiffness, bound, stack.whirl, v,
                              branches=branches)
    close = np.flatnonzero(np.abs(values - near) <= reach)
    if not len(close):
        return None
    ratios = stack.whirl_ratios(shapes[close][None], np.array([v]), np.array([speed]))[0]
    same = close[np.sign(ratios) == sign]
    pick = same if len(same) else close
    best = pick[int(np.argmin(np.abs(values[pick] - near)))]
    return values[best], shapes[best] / np.linalg.norm(shapes[best])


#: shapes of more coordinates than this are kept as fingerprints of this many numbers
_FINGERPRINT = 48


def _fingerprints(phi):
    """What :func:`_unresolved` compares of the shapes ``phi`` (P, n): the shapes themselves up to
    ``_FINGERPRINT`` coordinates, else their products with a fixed random complex matrix (n,
    ``_FINGERPRINT``). The MAC of two fingerprints is 1 to round-off where the shapes are
    parallel (one root found twice); for shapes apart, a product that brings them within the
    test's 1e-9 of parallel would have to fall within about 1e-9 of a subspace of codimension
    ``_FINGERPRINT``: a chance far below 1e-100."""
    n = phi.shape[-1]
    if n <= _FINGERPRINT:
        return phi
    draws = np.random.default_rng(_FINGERPRINT_SEED).standard_normal((2, n, _FINGERPRINT))
    return phi @ (draws[0] + 1j * draws[1])


_FINGERPRINT_SEED = 20261128


def _refined_part(stack, speeds, values, weighted, brackets, shapes):
    """:func:`_refine_parts` of one part: the crossings of isolated modes of small pencils by
    :func:`_joint_newton`, the others (and any it leaves) by :func:`_refine_together` and
    :func:`_shapes_at`."""
    starts = _starts(speeds, brackets)               # once for both routes
    newton = _by_newton(stack, brackets, shapes, starts)
    rows = newton.nonzero()[0]
    if len(rows):
        every = newton.all()
        found = _joint_newton(stack, speeds, brackets if every else brackets.subset(rows), shapes,
                              starts if every else starts.subset(rows))
        if found[-1].all() and every:                # the usual case for small models: all done
            return found
        newton[rows] = found[-1]
    rest = (~newton).nonzero()[0]
    mine = brackets.subset(rest)
    roots, lam, sure, iterates = _refine_together(stack, speeds, values, weighted, mine, shapes, starts.subset(rest))
    lam, phi = _shapes_at(stack, speeds, values, weighted, mine, roots, lam, sure, iterates)
    count = len(brackets.k)
    out = (np.empty(count), np.empty(count, dtype=complex), np.empty((count, stack.n_dof), dtype=complex),
           np.ones(count, dtype=bool))
    for column, value in zip(out, (roots, lam, phi, sure)):
        column[rest] = value
    if len(rows):
        ended = found[-1].nonzero()[0]
        for column, value in zip(out[:3], found[:3]):
            column[rows[ended]] = value[ended]
    return out


#: pencils of up to this many coordinates refine their isolated modes by :func:`_joint_newton`
#: (a dense bordered solve per step costs less than the Python calls of the secant's nested
#: iteration; above, one factorisation per crossing reused by every step costs less)
_NEWTON_DOF = 48
#: most joint Newton steps of a crossing (from the cubic start it takes two to four)
_NEWTON_STEPS = 12


def _by_newton(stack, brackets, shapes, starts):
    """Crossings that :func:`_joint_newton` refines: isolated modes (:func:`_isolated`) of
    pencils of at most ``_NEWTON_DOF`` coordinates with constant coefficients, strictly between
    two speeds of the sweep on one side of zero (``starts``: :func:`_starts` of ``brackets``)."""
    count = len(brackets.k)
    if shapes is None or stack.dependent or stack.branch_times.shape[-1] or stack.n_dof > _NEWTON_DOF:
        return np.zeros(count, dtype=bool)
    a, b, ga, gb = starts.a, starts.b, starts.ga, starts.gb
    return brackets.isolated & (ga != 0) & (gb != 0) & ((a >= 0) | (b <= 0))


def _joint_newton(stack, speeds, brackets, shapes, starts=None):
    """Roots of ``g(Omega) = Im lam(Omega) - slope |Omega|`` in every bracket by Newton's method
    on the tracked mode's eigenpair and the speed together (:func:`_pencils.speed_newton_step`),
    all crossings in one batch.

    The start is the cubic's (:func:`_cubic_start`, error of order h^4), with the eigenvalue the
    cubic through the sweep's points gives there and the sweep's shape at the nearer end of the
    bracket (which also fixes the scaling ``c^H phi = 1``, so that the shape's entries are at
    most about 1). Each step's size is the largest of the speed's (relative to
    ``max(|Omega|, 1 rad/s)``), the eigenvalue's (relative) and the shape's largest entry. A
    crossing ends after a step below ``_STEP_TOLERANCE``: its point is then the root, with the
    eigenpair there, and the error left is of the order of that step squared. (Ending a step
    earlier, where the last two steps' sizes promised quadratic convergence, left errors of
    2e-13: the first step's size is the start shape's error, which says little of the
    speed's.)

    A crossing fails where its speed leaves the bracket, a step is not finite, it has not
    ended after ``_NEWTON_STEPS`` steps, or its eigenvalue is not the tracked mode's (farther
    than twice the mode's travel across the bracket from its interpolation, as in
    :func:`_pencil_at`): the caller refines those by :func:`_refine_together`, whose iteration
    keeps every point inside its bracket. Rows stop stepping as they end, so each row's numbers
    are its own whatever the others are (a study's variant equals its model's own analysis bit
    for bit).

    ``starts``, :func:`_starts` of ``brackets``, where the caller has it.

    Returns
    -------
    roots : ndarray (P,) [rad/s]
    lam : ndarray (P,), complex
    phi : ndarray (P, n), complex, unit norm
    done : ndarray (P,) bool
        Ended at a root (the other rows' values are meaningless).
    """
    k, slope = brackets.k, brackets.slope
    count = len(k)
    a, b, _, _, x = _starts(speeds, brackets) if starts is None else starts
    x = x.copy()                                     # stepped in place
    every = np.arange(count)
    lam = _cubic_value(speeds, brackets, every, x)
    phi = shapes[brackets.variant, np.where(x - a <= b - x, k, k + 1), brackets.mode]    # unit: c = phi
    normal_conj = phi.conj()
    line = np.where(b <= 0, -slope, slope)            # |Omega| = sign Omega across the bracket
    done = np.zeros(count, dtype=bool)
    active = every
    constant = (stack.M, stack.C, stack.G, stack.K)
    with np.errstate(all="ignore"):                  # a row whose step is not finite fails below
        for _ in range(_NEWTON_STEPS):
            i = slice(None) if len(active) == count else active
            matrices = tuple(m[0] for m in constant) if len(stack) == 1 else \
                tuple(m[brackets.variant[i]] for m in constant)
            steps = _pencils.speed_newton_step(matrices, x[i], lam[i], phi[i], normal_conj[i], line[i])
            x[i] += steps[0]
            lam[i] += steps[1]
            phi[i] += steps[2]
            size = np.maximum(np.abs(steps[0]) / np.maximum(np.abs(x[i]), 1.0),
                              np.maximum(np.abs(steps[1]) / np.abs(lam[i]), np.abs(steps[2]).max(axis=1)))
            ended = size <= _STEP_TOLERANCE
            inside = (x[i] >= a[i]) & (x[i] <= b[i])
            done[active[ended & inside]] = True
            active = active[~ended & inside & np.isfinite(size)]
            if not len(active):
                break
    done &= np.abs(lam - _interpolated(brackets, every, x)) <= 2 * brackets.spread
    return x, lam, _vectors.unit_rows(phi), done


def _refine_together(stack, speeds, values, weighted, brackets, shapes=None, starts=None):
    """Roots of ``g(Omega) = Im lam(Omega) - slope |Omega|`` in every bracket, iterated together.

    The first point is the root of the cubic through the sweep's four nearest points of g
    (error of order h^4); then secant steps between the two latest points, kept strictly inside
    the bracket (regula falsi with the Illinois modification where they would leave it, and
    bisection where the bracket stops shrinking). Each step solves the eigenvalues of all
    unfinished crossings in one batch. A crossing is done when its next step is below
    ``1e-13 max(|Omega|, 1)``: the last point evaluated is the root, with its eigenvalue.
    The eigenvalue of a mode isolated from every other root across its bracket comes from
    residual inverse iteration on the quadratic pencil (:func:`_pencil_at`): one factorisation
    per crossing, at its first point, serves every later point. The others (and any that does
    not converge there) are picked from the roots near the bracket's interpolation (all
    eigenvalues of the state matrix, or for large models the nearest by shift-invert Arnoldi)
    as described in :func:`_tracked`, and then followed on the pencil where the next point is
    near enough (:func:`_followed`).

    ``starts``, :func:`_starts` of ``brackets``, where the caller has it.

    Returns
    -------
    roots : ndarray (P,) [rad/s]
    lam : ndarray (P,), complex
        The tracked mode's eigenvalue at each root.
    sure : ndarray (P,) bool
        The eigenvalue was told apart by distance alone and is not repeated.
    iterates : _Iterates
        The pencil iteration's last points, eigenvalues and shapes.
    """
    slope = brackets.slope
    count = len(brackets.k)
    a, b, ga, gb, x = _starts(speeds, brackets) if starts is None else starts
    a, b, ga, gb, x = a.copy(), b.copy(), ga.copy(), gb.copy(), x.copy()     # the brackets shrink in place
    iterates = _Iterates.start(stack, brackets, shapes)
    previous = np.full((2, count), np.nan)          # the last point evaluated and its g
    state = _Bracket(a, b, ga, gb, np.zeros(count, dtype=int), np.full((2, count), np.inf))
    on_grid = (ga == 0) | (gb == 0)
    if on_grid.any():
        roots = np.where(ga == 0, a, np.where(gb == 0, b, np.nan))
        lam = np.where(ga == 0, brackets.low, brackets.high)
        sure = np.zeros(count, dtype=bool)
        done, evaluations = on_grid, 0
    else:
        # every crossing between grid points (the usual case): the first evaluation of all of them,
        # which usually ends them all (the cubic start lands at round-off of the root)
        every = np.arange(count)
        lam, sure = _evaluate(stack, speeds, values, weighted, brackets, every, x.copy(), iterates, shapes)
        roots, done, evaluations = x.copy(), np.zeros(count, dtype=bool), 1
        x = _advance(state, previous, done, every, x, lam.imag - slope * np.abs(x))
    for _ in range(_MAX_ITERATIONS - evaluations):
        i = (~done).nonzero()[0]
        if not len(i):
            break
        x_i = x[i]
        lam_x, sure_x = _evaluate(stack, speeds, values, weighted, brackets, i, x_i, iterates, shapes)
        gx = lam_x.imag - slope[i] * np.abs(x_i)
        roots[i], lam[i], sure[i] = x_i, lam_x, sure_x
        x[i] = _advance(state, previous, done, i, x_i, gx)
    return roots, lam, sure, iterates


class _Starts(NamedTuple):
    """Each bracket's ends, ``g`` there (:func:`_ends_and_gaps`) and the cubic's root
    (:func:`_cubic_start`), each (P,): what both routes of :func:`_refined_part` start from."""

    a: np.ndarray
    b: np.ndarray
    ga: np.ndarray
    gb: np.ndarray
    x: np.ndarray

    def subset(self, rows):
        return _Starts(*(column[rows] for column in self))


def _starts(speeds, brackets) -> _Starts:
    """:class:`_Starts` of ``brackets``."""
    a, b, ga, gb = _ends_and_gaps(speeds, brackets)
    return _Starts(a, b, ga, gb, _cubic_start(speeds, brackets, a, b, ga, gb))


def _ends_and_gaps(speeds, brackets):
    """Each bracket's ends ``a = speeds[k]``, ``b = speeds[k + 1]`` [rad/s] and ``g`` there
    (see :func:`_refine_together`), each (P,)."""
    a, b = speeds[brackets.k], speeds[brackets.k + 1]
    return a, b, brackets.low.imag - brackets.slope * np.abs(a), brackets.high.imag - brackets.slope * np.abs(b)


def _advance(state, previous, done, rows, x, gx):
    """Update the brackets ``rows`` with the points (x, gx) (see :func:`_next_step`), mark those
    that end there done, and return the next points."""
    step = _next_step(state, rows, x, gx, previous[:, rows])
    previous[:, rows] = x, gx
    done[rows[_finished(x, gx, step)]] = True
    return step


def _finished(x, gx, step):
    """A crossing ends where ``g`` vanishes or its next step is below ``_STEP_TOLERANCE``."""
    return (gx == 0) | (np.abs(step - x) <= _STEP_TOLERANCE * np.maximum(np.abs(x), 1.0))


class _Bracket(NamedTuple):
    """Brackets being shrunk (arrays updated in place): ends, their g (Illinois-scaled), the end
    moved last (+1 a, -1 b) and the bracket's width one and two steps ago."""

    a: np.ndarray
    b: np.ndarray
    ga: np.ndarray
    gb: np.ndarray
    last: np.ndarray
    widths: np.ndarray


def _next_step(state, rows, x, gx, previous):
    """Update the brackets ``rows`` with the point (x, gx) and return the next point."""
    moved = gx != 0
    left = (np.sign(gx) == np.sign(state.ga[rows])) & moved
    right = ~left & moved
    if left.any():
        _illinois(state.a, state.ga, state.gb, state.last, rows[left], x[left], gx[left], +1)
    if right.any():
        _illinois(state.b, state.gb, state.ga, state.last, rows[right], x[right], gx[right], -1)
    a, b = state.a[rows], state.b[rows]
    width, gb = b - a, state.gb[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = x - gx * (x - previous[0]) / (gx - previous[1])
        falsi = b - gb * width / (gb - state.ga[rows])
    slow = width > 0.5 * state.widths[1, rows]
    state.widths[1, rows], state.widths[0, rows] = state.widths[0, rows], width
    inside = np.isfinite(secant) & (secant > a) & (secant < b)
    fallback = np.where(np.isfinite(falsi) & (falsi > a) & (falsi < b) & ~slow, falsi, 0.5 * (a + b))
    return np.where(gx == 0, x, np.where(inside, secant, fallback))


def _cubic_start(speeds, brackets, a, b, ga, gb):
    """Root in (a, b) of the cubic through g at the sweep's four points around each bracket
    (the chord's root where fewer than four oscillating points are at hand)."""
    width = b - a
    with np.errstate(all="ignore"):
        chord = b - gb * width / (gb - ga)
        chord = np.where(np.isfinite(chord) & (chord > a) & (chord < b), chord, 0.5 * (a + b))
        if len(speeds) < 4:
            return chord
        xs, lam = brackets.near_speeds, brackets.near_values
        gs = lam.imag - brackets.slope[:, None] * np.abs(xs)
        # the four speeds ascend: all on one side of zero where the first or the last is
        usable = brackets.near_oscillating & ((xs[:, 0] >= 0) | (xs[:, 3] <= 0))
        # the cubic in t = (x - a) / (b - a): coefficients from the 4x4 Vandermonde systems
        t_nodes = (xs - a[:, None]) / width[:, None]
        vandermonde = t_nodes[..., None] ** np.arange(4)
        coefficients = np.linalg.solve(vandermonde, gs[..., None])[..., 0]
        t = (chord - a) / width
        c0, c1, c2, c3 = coefficients.T
        slope3, slope2 = 3 * c3, 2 * c2                 # the derivative's coefficients
        for _ in range(4):                              # Newton on the cubic, from the chord's root
            t = t - (((c3 * t + c2) * t + c1) * t + c0) / ((slope3 * t + slope2) * t + c1)
        x = a + t * width
        good = usable & np.isfinite(x) & (x > a) & (x < b)
    return np.where(good, x, chord)


def _illinois(end, g_end, g_other, last_side, rows, x, gx, side):
    """Move one end of the brackets ``rows`` to ``x``; halve the other end's value when this
    end moved last time too (Illinois), so the other end moves next."""
    repeat = last_side[rows] == side
    g_other[rows[repeat]] *= 0.5
    end[rows] = x
    g_end[rows] = gx
    last_side[rows] = side


class _Iterates(NamedTuple):
    """Per crossing: whether its mode is isolated (see :func:`_isolated`) and may be evaluated
    on the pencil, the last point, eigenvalue and shape found (by the pencil, or by picking
    from the roots), the distance from that eigenvalue to the nearest other root where it was
    picked, and the factorisation of the pencil (at a point near the root) that the iteration
    reuses (updated in place)."""

    usable: np.ndarray
    x: np.ndarray
    lam: np.ndarray
    shape: np.ndarray
    gap: np.ndarray
    factors: _pencils.PencilFactors

    @classmethod
    def start(cls, stack, brackets, shapes):
        count = len(brackets.k)
        gap = np.full(count, np.nan)
        if shapes is None or stack.branch_times.shape[-1]:
            # Maxwell branches make the pencil rational: every evaluation takes all eigenvalues
            return cls(np.zeros(count, dtype=bool), np.full(count, np.nan), np.zeros(count, complex),
                       np.zeros((count, 0), complex), gap, _pencils.PencilFactors(0, 0))
        v, k, mode = brackets.variant, brackets.k, brackets.mode
        return cls(brackets.isolated, brackets.start.astype(float), brackets.low.copy(),
                   shapes[v, k, mode], gap, _pencils.PencilFactors(count, stack.n_dof))


def _evaluate(stack, speeds, values, weighted, brackets, rows, x, iterates, shapes=None):
    """The tracked modes' eigenvalues at speeds ``x`` and whether each is sure (see
    :func:`_tracked`): the pencil's iteration for isolated modes and for modes picked from the
    roots at a point so near that no other root can have come close (:func:`_followed`); for
    large models, the mode picked among the Ritz pairs of the sweep's shapes at the bracket's
    ends (:func:`_ritz_evaluated`, from ``shapes``) and refined on the pencil; the roots near
    the bracket's interpolation for the rest and for any that did not converge to the tracked
    mode."""
    fast = iterates.usable[rows]
    isolated = fast.all()
    if isolated:                         # every mode isolated (the usual case): all on the pencil
        found, ok = _pencil_at(stack, speeds, brackets, rows, x, iterates)
        if ok.all():
            return found, ok
    else:
        fast |= _followed(brackets, rows, x, iterates)
    lam = np.empty(len(rows), dtype=complex)
    sure = np.zeros(len(rows), dtype=bool)
    if isolated:
        lam[ok], sure[ok] = found[ok], True
        fast[~ok] = False
    elif fast.any():
        f = fast.nonzero()[0]
        found, ok = _pencil_at(stack, speeds, brackets, rows[f], x[f], iterates)
        lam[f[ok]], sure[f[ok]] = found[ok], True
        fast[f[~ok]] = False
    slow = (~fast).nonzero()[0]
    if len(slow) and _by_ritz(stack, shapes, iterates):
        found, ok = _ritz_evaluated(stack, speeds, values, shapes, weighted, brackets, rows[slow], x[slow], iterates)
        lam[slow[ok]], sure[slow[ok]] = found[ok], True
        slow = slow[~ok]
    if len(slow):
        lam[slow], sure[slow], shapes, known, gap = _tracked(stack, speeds, values, weighted, brackets, rows[slow],
                                                             x[slow])
        if iterates.shape.shape[-1]:
            # a mode told apart by distance among roots that came without shapes: its shape by one
            # inverse-iteration step, so that later points follow it on the pencil (_followed)
            # instead of taking every root again
            bare = (~known & sure[slow]).nonzero()[0]
            if len(bare):
                at = slow[bare]
                shapes[bare] = stack.shapes_at(brackets.variant[rows[at]], x[at], lam[at])
                known[bare] = True
            # kept for the shape at the root, should this point be it, and to follow the mode
            mine, at = rows[slow[known]], slow[known]
            iterates.x[mine], iterates.lam[mine], iterates.shape[mine] = x[at], lam[at], shapes[known]
            iterates.gap[mine] = gap[known]
    return lam, sure
