"""A speed-dependent bearing's crossings on the UCS map, found on a Rayleigh-Ritz subspace.

Today's route (:func:`.ucs_map._curve_crossings`) solves the whole synchronous pencil at each of
a curve's ~200 points and at each step of each crossing's refinement. Here the pencil
``K(k) phi = Omega^2 (M - i G) phi``, ``K(k) = K_rest + k K_unit``, is solved whole only at a few
*anchor* stiffness values over the bearing's curves (:data:`CURVE_ANCHORS`); the shapes of the
roots below a level there span a subspace ``V`` on which each curve point's roots are Ritz pairs of
an ``r x r`` pencil. The curve's points are matched to the map's modes and its brackets found as
today, on the Ritz pairs, and each crossing is finished on the whole pencil by Newton's method
on ``(K_rest + k(s) K_unit - s^2 (M - i G)) phi = 0`` (the crossing speed ``s`` and its shape
together, the stiffness ``k(s)`` linear between the bracket's points as today).

The route answers only where it can show that it sees what today's does (else None, and the
caller takes today's route):

- *every root below a level is a Ritz root*: each ordered root's critical speed grows with
  ``k`` (``K_unit`` is positive semidefinite), so over an interval between two anchors the roots
  below a level ``L`` chosen in a gap (the i-th root's speeds at the two anchors not straddling
  ``L``) are exactly ``N``, counted at the anchors; a Ritz root is never below its root (Cauchy's
  interlacing), so ``N`` Ritz roots below ``L`` at a point are those ``N`` roots;
- *each Ritz root is near its root*: the residual's bound ``|nu - nu_true| <= ||r||_{K^-1} / ||x||_K``
  (``nu = Omega^-2``, ``r = B x - nu K x``; ``K(k)^-1 <= K(k_min)^-1``); each point's sign of
  ``critical - s`` must hold over that bound;
- *the matching and whirl decisions are not near their thresholds* (the MAC's 0.5 and its best
  two, the whirl's tolerance, two roots a repeated root), by margins above the Ritz shapes' error;
- *each Newton finish converges* inside its bracket, to the shape it started from.

Not shown, taken as given: that no root above ``L`` (at least :data:`LEVEL_FACTOR` times the
speeds at stake) is the best MAC of a map mode there.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from . import _eigensolve, _whirl
from ._eigensolve import REPEATED_TOLERANCE
from ._lowest_newton import _exact_sums
from ._roots import REPEATED_OWN

#: anchors of a speed-dependent bearing's curves: stiffness values (geometric over its Kxx and Kyy
#: points) where the pencil is solved whole
CURVE_ANCHORS = 3
#: the level below which the roots are followed on the subspace: at least this times the highest
#: speed at stake (the curve's, and the map modes' at the grid points its points are matched to,
#: scaled by the square root of the stiffness ratio, the most a root can grow by)
LEVEL_FACTOR = 2.0
#: anchor roots kept in the subspace: those below this times the level
_SPAN = 1.5
#: more roots below the level than this: the subspace is not worth it (today's route)
_MOST_ROOTS = 60
#: more than this share of a curve's points in doubt on the subspace (each then solved whole):
#: today's route
_MOST_WHOLE = 0.25
#: margins of the decisions: the MAC (absolute), the whirl ratio (relative to its tolerance)
_MAC_MARGIN, _WHIRL_MARGIN = 1e-3, 0.5
#: Newton's steps at most, and its relative step in ``s`` at which it stops
_NEWTON_STEPS, _NEWTON_STOP = 12, 1e-14
#: the whole pencil's crossing speed within this of the subspace's (relative) is the subspace's root
#: refined, whatever its shape's MAC with the start (:func:`_finished`)
_SAME_SPEED = 1e-9


class _Subspace:
    """The projection of the pencil on ``V`` (n, r), orthonormal columns, and what bounds its
    Ritz pairs' errors.

    ``rest``, ``unit``, ``B`` (r, r): ``V^H K_rest V``, ``V^H K_unit V``, ``V^H (M - i G) V``;
    ``mass`` (r, n): ``(L^T V)^T``, ``M = L L^T`` (mass-weighted shapes ``y @ mass``); ``forms``
    (3, r, r): the whirl forms projected; ``triangle`` (3r, 3r): ``R`` of ``C^-1 W^H P = Q R``,
    ``P = [K_rest V, K_unit V, B V]``, ``C C^H = W^H K(k_min) W`` on the constrained coordinates
    ``W``: ``||R z|| >= ||P z||_{K(k)^-1}`` for every ``k >= k_min`` (``K(k) >= K(k_min)``), without
    the cancellation of ``z^H P^H K^-1 P z``; ``condition``: ``C``'s condition number (the
    rounding of ``R``); ``slack`` (3, n, r): the bound of the rounding of ``P``'s three blocks
    (of ``A V``: ``|A| |V|`` times eps and the terms of ``A``'s fullest row), over
    ``lambda_min(K(k_min))^1/2``.
    None of them where ``K(k_min)`` is not positive definite there."""

    def __init__(self, parts, V, k_min):
        B = parts.M - 1j * parts.G
        products = [parts.rest @ V, parts.unit @ V, B @ V]
        self.V = V
        self.rest, self.unit, self.B = (_hermitian(V.conj().T @ P) for P in products)
        self.mass = (np.linalg.cholesky(parts.M).T @ V).T
        self.forms = np.array([V.conj().T @ F @ V for F in parts.forms])
        W = parts._basis
        stiff = W.conj().T @ (parts.rest + k_min * parts.unit) @ W
        try:
            C = np.linalg.cholesky(_hermitian(stiff))
        except np.linalg.LinAlgError:
            self.triangle = None
            return
        scaled = scipy.linalg.solve_triangular(C, W.conj().T @ np.concatenate(products, axis=1), lower=True)
        self.triangle = np.linalg.qr(scaled, mode="r")
        extremes = np.linalg.eigvalsh(_hermitian(stiff))[[0, -1]]
        self.condition = float(np.sqrt(extremes[1] / extremes[0]))
        # the products' own rounding: a row's terms times eps of |A| |V| (a zero term adds exactly
        # nothing), over lambda_min(K)^1/2
        self.slack = np.array([_terms(A) * np.finfo(float).eps * (np.abs(A) @ np.abs(V))
                               for A in (parts.rest, parts.unit, B)]) / np.sqrt(extremes[0])

    def ritz(self, k):
        """Ritz pairs at stiffness values ``k`` (S,) [N/m]: ``nu`` (S, r) decreasing (``Omega^-2``) and
        their coordinates ``y`` (S, r, r) (columns, ``y^H K y = 1``)."""
        K = self.rest + k[:, None, None] * self.unit
        R = np.linalg.cholesky(K)
        Ri = np.linalg.inv(R)
        H = Ri @ self.B @ Ri.conj().swapaxes(-1, -2)
        nu, z = np.linalg.eigh(_hermitian(H))
        nu, z = nu[:, ::-1], z[:, :, ::-1]
        return nu, Ri.conj().swapaxes(-1, -2) @ z

    def nu_errors(self, k, nu, y):
        """Bounds (S, c) of each Ritz root's ``|nu - nu_true|`` (``y`` (S, r, c), ``y^H K y = 1``):
        ``||B x - nu K x||_{K^-1} / ||x||_K`` from ``triangle``, with its rounding."""
        theta = 1.0 / nu                                                        # Omega^2
        z = np.concatenate([y, k[:, None, None] * y, -theta[:, None, :] * y], axis=1)   # (S, 3r, c)
        R = self.triangle
        rounding = 8 * len(R) * np.finfo(float).eps * self.condition * np.linalg.norm(np.abs(R) @ np.abs(z), axis=1)
        size = np.abs(y)
        products = np.linalg.norm(self.slack[0] @ size + k[:, None, None] * (self.slack[1] @ size)
                                  + theta[:, None, :] * (self.slack[2] @ size), axis=1)
        return (np.linalg.norm(R @ z, axis=1) + rounding + products) * np.abs(nu)


def _hermitian(A):
    return 0.5 * (A + A.conj().swapaxes(-1, -2))


def _terms(A) -> int:
    """The most nonzero entries of a row of ``A`` (n, n): the terms of its products' sums."""
    return int(np.count_nonzero(A, axis=1).max(initial=1))


def subspace_crossings(parts, curve, axes, grid, followed, rules):
    """The crossings of a speed-dependent bearing's curves (``axes``: (axis, speeds (S,) [rad/s],
    stiffness (S,) [N/m]) of its Kxx and Kyy, positive points) with the map's modes (``rules``:
    ``ucs_map``'s ``Crossing``, ``_matched`` and ``_SAME_MODE_MAC``, given: no import circle), as
    :func:`.ucs_map._curve_crossings` finds them, on a subspace (module docstring); None where it
    cannot show it sees what that route does."""
    values = np.concatenate([v for _, _, v in axes])
    anchors = np.unique(np.geomspace(values.min(), values.max(), CURVE_ANCHORS))
    exact = parts.roots(anchors)
    level = _needed_level(axes, grid, followed)
    gaps = _gap_levels(exact.omega, level)
    if gaps is None:
        return None
    levels, counts, nexts = gaps
    V = _span(exact, anchors, levels)
    if V is None:
        return None
    space = _Subspace(parts, V, values.min())
    if space.triangle is None:
        return None
    tops = np.max(np.where(np.isfinite(exact.omega), exact.omega, 0.0), axis=1)        # each anchor's largest root
    largest = (float(tops.min()), float(tops.max()))
    out = []
    for axis, speeds, stiffness in axes:
        found = _axis_crossings(parts, space, anchors, (levels, counts, nexts, largest), curve, axis, speeds, stiffness,
                                grid, followed, rules)
        if found is None:
            return None
        out += found
    return out


def _needed_level(axes, grid, followed) -> float:
    """The level [rad/s] below which every root is followed: :data:`LEVEL_FACTOR` times the
    curve's highest speed and the map modes' highest speed at the grid points its points are
    matched to, each times the square root of the largest stiffness ratio between a point and its
    grid point (``Omega_i(k)^2 <= (k / k_g) Omega_i(k_g)^2`` for ``k >= k_g``)."""
    highest = 0.0
    for _, speeds, stiffness in axes:
        distance = np.abs(np.log(stiffness)[:, None] - np.log(grid)[None, :])
        nearest = distance.argmin(axis=-1)
        grow = np.exp(0.5 * distance.min(axis=-1).max())
        at = followed.speeds[nearest]
        mode = float(np.max(at[np.isfinite(at)], initial=0.0))
        highest = max(highest, float(speeds.max()), grow * mode)
    return LEVEL_FACTOR * highest


def _gap_levels(omega, level):
    """For each interval between neighbouring anchors (one interval of a lone anchor), a level
    ``L >= level`` [rad/s] no root's speed crosses inside it, and the number of roots below it.

    ``omega`` (A, m) [rad/s]: each anchor's roots, increasing, inf where none. Returns (levels (I,),
    counts (I,), the least speed of the next root (I,) [rad/s], inf where none), or None where more
    than :data:`_MOST_ROOTS` roots lie below."""
    pairs = [(a, a + 1) for a in range(len(omega) - 1)] or [(0, 0)]
    levels, counts, nexts = [], [], []
    for a, b in pairs:
        low, high = omega[a], omega[b]
        finite = int(np.isfinite(low).sum())
        for n in range(min(finite, _MOST_ROOTS) + 1):
            L = level if n == 0 else max(level, high[n - 1] * (1 + 1e-6))
            if n == finite or L <= low[n] * (1 - 1e-6):
                break
        else:
            return None
        levels.append(L)
        counts.append(n)
        nexts.append(low[n] if n < finite else np.inf)
    return np.array(levels), np.array(counts), np.array(nexts)


def _span(exact, anchors, levels):
    """Orthonormal columns (n, r) spanning the anchors' shapes below :data:`_SPAN` times the
    level of each neighbouring interval (None when the anchors' shapes are all the space: no
    gain)."""
    columns = []
    for a in range(len(anchors)):
        near = levels[max(a - 1, 0):a + 1]
        keep = exact.omega[a] < _SPAN * near.max()
        shapes = exact.shapes[a][keep]
        columns.append(shapes / np.linalg.norm(shapes, axis=-1, keepdims=True))
    stacked = np.concatenate(columns).T
    U, sigma, _ = np.linalg.svd(stacked, full_matrices=False)
    return U[:, sigma > 1e-10 * sigma[0]] if len(sigma) else None


def _axis_crossings(parts, space, anchors, limits, curve, axis, speeds, stiffness, grid, followed, rules):
    """One axis' crossings (list of Crossing), or None (too many points in doubt, or a finish
    failed). The points whose decisions the Ritz pairs do not show are solved whole and decided
    as today (:func:`.ucs_map._matched`)."""
    Crossing, _matched, same_mode = rules
    nearest = np.abs(np.log(stiffness)[:, None] - np.log(grid)[None, :]).argmin(axis=-1)
    reference = followed.weighted[nearest]                                        # (S, L, n)
    at, index, y, doubt = _ritz_decisions(space, anchors, limits, speeds, stiffness, reference, same_mode)
    if doubt.sum() > _MOST_WHOLE * len(doubt):
        return None
    whole = np.flatnonzero(doubt)
    shapes = {}
    if len(whole):
        roots = parts.roots(stiffness[whole])
        at[whole], index[whole] = _matched(parts, roots, reference[whole])
        shapes = {int(i): roots.shapes[p] for p, i in enumerate(whole)}              # (m, n) each
    out = []
    for i, j in _brackets(at, speeds):
        line = (speeds[i], speeds[i + 1], stiffness[i], stiffness[i + 1])
        gaps = at[i, j] - speeds[i], at[i + 1, j] - speeds[i + 1]
        start = speeds[i] - gaps[0] * (speeds[i + 1] - speeds[i]) / (gaps[1] - gaps[0])
        if i in shapes:
            s = _finished(parts, space, line, start, x=shapes[i][index[i, j]])
        else:
            s = _finished(parts, space, line, start, y=y[i][:, index[i, j]])
        if s is None:
            return None
        t = (s - speeds[i]) / (speeds[i + 1] - speeds[i])
        out.append(Crossing(curve.name, axis, int(j) + 1, float((1 - t) * stiffness[i] + t * stiffness[i + 1]),
                            float(s), followed.names[j]))
    return out


def _brackets(at, speeds) -> list:
    """(point, mode) of each sign change of ``at[:, j] - speeds`` between neighbouring points with
    both finite, mode by mode (as :func:`.ucs_map._curve_crossings` lists them)."""
    brackets = []
    for j in range(at.shape[1]):
        gap = at[:, j] - speeds
        brackets += [(int(i), j) for i in np.nonzero(np.isfinite(gap[:-1]) & np.isfinite(gap[1:])
                                                     & (np.sign(gap[:-1]) != np.sign(gap[1:])))[0]]
    return brackets


def _ritz_decisions(space, anchors, limits, speeds, stiffness, reference, same_mode):
    """The map modes' roots at the curve's points (S,) decided on the Ritz pairs.

    Returns
    -------
    at : ndarray, shape (S, L) [rad/s], nan where none
    index : ndarray of int, shape (S, L): the Ritz root
    y : ndarray, shape (S, r, c): the followed Ritz roots' coordinates
    doubt : ndarray of bool, shape (S,): points where a decision is not shown
    """
    levels, counts, nexts, largest = limits
    interval = np.clip(np.searchsorted(anchors, stiffness, side="right") - 1, 0, len(levels) - 1)
    nu, y = space.ritz(stiffness)
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.where(nu > 0, 1 / np.sqrt(np.where(nu > 0, nu, 1.0)), np.inf)
    below = omega < levels[interval][:, None]
    seen = below.sum(axis=1) == counts[interval]                  # else a root below the level not seen
    S, L = reference.shape[:2]
    c = int(counts[interval].max())
    if not c:
        return np.full((S, L), np.nan), np.zeros((S, L), int), y[:, :, :0], ~seen
    nu, omega, y = nu[:, :c], omega[:, :c], y[:, :, :c]
    valid = below[:, :c]                              # roots past the point's own count are not followed
    error = space.nu_errors(stiffness, nu, y)
    with np.errstate(invalid="ignore", divide="ignore"):
        most = np.where(nu > error, (nu - error) ** -0.5, np.inf)             # Omega's bounds
        least = (nu + error) ** -0.5
    clear = _pairs_clear(valid, least, most, nexts[interval], largest)
    y = _resolved(omega, y, space.forms, largest[1])
    weighted = y.swapaxes(-1, -2) @ space.mass                                   # (S, c, n)
    weighted /= np.linalg.norm(weighted, axis=-1, keepdims=True)
    values = np.stack([np.sum(y.conj() * (form @ y), axis=-2) for form in space.forms], axis=-1)   # (S, c, 3)
    ratios = _whirl.ratios_of_forms(values, np.ones(len(stiffness)))
    correlation = np.abs(reference.conj() @ weighted.swapaxes(-1, -2)) ** 2       # (S, L, c)
    correlation = np.where(valid[:, None, :], correlation, -1.0)
    at, index, unsure = _decided(correlation, ratios, valid, omega, least, most, speeds, same_mode)
    return at, index, y, ~seen | ~clear | unsure


def _pairs_clear(valid, least, most, next_low, largest) -> np.ndarray:
    """Whether (S,) at each point each two neighbouring followed roots are surely one repeated root, or surely two,
    as :func:`._eigensolve._repeated_pairs` judges them (within ``REPEATED_TOLERANCE`` of the row's
    largest root, between ``largest`` (low, high) [rad/s], and within ``REPEATED_OWN`` of the
    larger), over the Ritz roots' bounds ``least``, ``most`` (S, c) [rad/s]; the highest followed
    root at each point surely apart from the next root, at least ``next_low`` (S,) [rad/s]."""
    tolerance = REPEATED_TOLERANCE * np.asarray(largest, dtype=float)
    with np.errstate(invalid="ignore"):
        nearest = np.maximum(least[:, 1:] - most[:, :-1], 0.0)                 # the pairs' distance, (S, c - 1)
        farthest = most[:, 1:] - least[:, :-1]
        one = (farthest <= tolerance[0]) & (farthest <= REPEATED_OWN * least[:, 1:] * (1 - 1e-3))
        two = (nearest > tolerance[1]) | (nearest > REPEATED_OWN * most[:, 1:] * (1 + 1e-3))
        top = valid.sum(axis=1) - 1                                            # each point's highest followed
        highest = most[np.arange(len(most)), np.maximum(top, 0)]
        apart = (next_low - highest > tolerance[1]) | (next_low * (1 - REPEATED_OWN) > highest * (1 + 1e-3))
    inner = valid[:, 1:] & valid[:, :-1]
    return ~np.any(inner & ~(one | two), axis=1) & ((top < 0) | apart)


def _resolved(omega, y, forms, largest):
    """The Ritz coordinates ``y`` (S, r, c) with each repeated pair or group made its extreme-whirl
    combinations, as :func:`._eigensolve.resolve_repeated` makes the whole pencil's (its forms
    projected: (3, r, r); the row's largest root ``largest`` [rad/s] put beside the roots: its scale)."""
    S, r, c = y.shape
    lam = 1j * np.concatenate([np.where(np.isfinite(omega), omega, 0.0), np.full((S, 1), largest)], axis=1)
    shapes = np.concatenate([y.swapaxes(-1, -2), np.zeros((S, 1, r), complex)], axis=1)
    resolved = _eigensolve.resolve_repeated(lam, shapes, _whirl.WhirlForms(*forms))
    return resolved[:, :c].swapaxes(-1, -2)


def _decided(correlation, ratios, valid, omega, least, most, speeds, _SAME_MODE_MAC):
    """Each map mode's root at each point as :func:`.ucs_map._matched` decides it (the largest MAC,
    above ``_SAME_MODE_MAC`` and forward), shown by margins: speeds (S, L) [rad/s] nan where none,
    the Ritz roots' index (S, L), and (S,) bool the points where a decision or a sign is in doubt.

    ``correlation`` (S, L, c): MAC with each map mode's shape (-1 where not a followed root);
    ``ratios`` (S, c) whirl ratios; ``omega``, ``least``, ``most`` (S, c) [rad/s]: the Ritz roots'
    speeds and their bounds; ``speeds`` (S,) [rad/s] the curve's; ``_SAME_MODE_MAC`` the map's."""

    index = correlation.argmax(axis=-1)
    ordered = np.sort(correlation, axis=-1)
    best = ordered[..., -1]
    second = ordered[..., -2] if correlation.shape[-1] > 1 else np.full(best.shape, -1.0)
    tolerance = _whirl.WHIRL_TOLERANCE
    points = np.arange(len(index))[:, None]
    ratio = ratios[points, index]
    forward = valid[points, index] & np.isfinite(omega[points, index]) & (ratio > tolerance)
    good = (best > _SAME_MODE_MAC) & forward
    doubt = (np.abs(best - _SAME_MODE_MAC) < _MAC_MARGIN) | ((best > _SAME_MODE_MAC - _MAC_MARGIN)
                                                             & (second > best - _MAC_MARGIN))
    doubt |= (best > _SAME_MODE_MAC - _MAC_MARGIN) & (np.abs(np.abs(ratio) - tolerance) < _WHIRL_MARGIN * tolerance)
    s = speeds[:, None]
    doubt |= good & ~((least[points, index] > s) | (most[points, index] < s))      # the sign of critical - s
    return np.where(good, omega[points, index], np.nan), index, doubt.any(axis=1)


def _finished(parts, space, line, start, y=None, x=None):
    """The crossing speed [rad/s] on the bracket's line ``(s_a, s_b, k_a, k_b)``: Newton's method
    on the subspace from ``start`` [rad/s] and the Ritz coordinates ``y`` (r,), then on the whole
    pencil (``K_rest`` products summed exactly, as the map's polished roots); from a whole
    pencil's shape ``x`` (n,) on the whole pencil only. None where either does not converge,
    leaves the bracket, or the whole pencil's shape is not the start's."""
    s = start
    on_subspace = None
    if x is None:
        found = _newton(space.rest, space.unit, space.B, line, start, y, exact=False)
        if found is None:
            return None
        s, y = found
        on_subspace, x = s, space.V @ y
    found = _newton(parts.rest, parts.unit, parts.M - 1j * parts.G, line, s, x, exact=True)
    if found is None:
        return None
    s, shape = found
    low, high = line[0], line[1]
    inside = low * (1 - 1e-12) <= s <= high * (1 + 1e-12)
    mac = abs(np.vdot(x, shape)) ** 2 / (np.vdot(x, x).real * np.vdot(shape, shape).real)
    # a root of a close pair (a journal rotor's two directions) has a well-kept speed and a shape
    # that round-off turns within the pair (MAC 0.96 with OpenBLAS's Haswell kernels, 0.999 with
    # SkylakeX's): the whole pencil's Newton that does not move the subspace's speed found its root
    kept = on_subspace is not None and abs(s - on_subspace) <= _SAME_SPEED * abs(s)
    return float(s) if inside and (mac > 0.99 or kept) else None


def _newton(rest, unit, B, line, s, x, exact):
    """Newton's method on ``T(s) x = 0``, ``T(s) = K_rest + k(s) K_unit - s^2 B``, ``k(s)`` linear on
    the line ``(s_a, s_b, k_a, k_b)``, with ``c^H x = 1`` (``c`` the start's shape): the bordered
    system ``[[T, T' x], [c^H, 0]]`` solved each step. ``exact``: ``K_rest x`` of the residual
    summed exactly. Returns (s [rad/s], x) or None."""
    s_a, s_b, k_a, k_b = line
    slope = (k_b - k_a) / (s_b - s_a)
    c = x / np.vdot(x, x)
    n = len(x)
    for _ in range(_NEWTON_STEPS):
        t = (s - s_a) / (s_b - s_a)
        k = (1 - t) * k_a + t * k_b
        stiff = (_exact_sums(rest, x[:, None])[:, 0] if exact else rest @ x) + k * (unit @ x)
        Bx = B @ x
        J = np.empty((n + 1, n + 1), dtype=complex)
        J[:n, :n] = rest + k * unit - s * s * B
        J[:n, n] = slope * (unit @ x) - 2 * s * Bx
        J[n, :n] = c.conj()
        J[n, n] = 0.0
        right = -np.append(stiff - s * s * Bx, np.vdot(c, x) - 1.0)
        try:
            d = scipy.linalg.solve(J, right, check_finite=False)
        except (ValueError, np.linalg.LinAlgError):
            return None
        if not np.all(np.isfinite(d)):
            return None
        x = x + d[:n]
        step = d[n].real
        s = s + step
        if abs(step) <= _NEWTON_STOP * abs(s):
            return s, x
    return None
