"""The exact roots of the lowest modes: Newton's iteration on the full pencil from the starts, and
the polish of roots whose double-precision round-off exceeds ``_CERTAIN`` (``docs/theory.md``
section 17, steps 3 and 4).

:func:`_refined`: ``u = Q(s)^-1 Q'(s) x``, ``s <- s - c^H x / c^H u``, batched over speeds and roots,
until the step (or the error it leaves) is at round-off; :func:`_roundoff`: the relative error
double precision can leave in a root for its own shape; :func:`_polished`: Newton's steps on the
bordered system with the residual in extended precision.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from . import _batches, _vectors
from ._polish_plan import _clusters, _nearest_other, polish_budget, polish_work

__all__ = ["pair_polished", "root_polished", "block_polished", "rational_root_polished"]

#: speeds named in a warning (and in the full solve's refusal, :mod:`._lowest`) at most
_NAMED = 5

#: Newton iterations at most; the starts from the projected pencils take 2 to 4
_ITERATIONS = 12
#: a step below this times |lam| ends the iteration (quadratic convergence: the root is then
#: exact to round-off, far inside the 1e-9 promised)
_STEP = 1e-11
#: a step below this times |lam| is in Newton's quadratic regime, where the error the step leaves,
#: predicted from the last two steps, ends the iteration when below ``_LEFT`` times |lam| (one
#: solve fewer than waiting for a step at round-off)
_ASYMPTOTIC, _LEFT = 1e-5, 1e-13


def _refined(pencils, starts, vectors, rows=None):
    """Newton's iteration on the full quadratic pencil from every start, batched over speeds
    and roots: ``u = Q(s)^-1 Q'(s) x``, ``s <- s - (c^H x)/(c^H u)``, ``x <- u / (c^H u)``
    (``c`` the start vector, fixing the scale). ``rows`` (S,): the speeds (of ``pencils``) of the
    starts' rows, default all. Returns the roots (S, k), unit shapes (S, k, n) and whether every
    root of a speed converged (S,)."""
    S, k, n = vectors.shape
    index = np.repeat(np.arange(S) if rows is None else np.asarray(rows), k)
    lam, x, ok = _newton(pencils, index, starts.reshape(-1).copy(), vectors.reshape(-1, n).copy())
    lam, x = _certain(pencils, index, lam, x, ok)
    return lam.reshape(S, k), _vectors.unit_rows(x.reshape(S, k, n)), ok.reshape(S, k).all(axis=1)


def _continued(pencils, guesses, vectors, rows):
    """:func:`_refined` from starts close to their roots (a few 1e-9 relative, from the
    neighbouring speeds: ``_lowest_starts._expansion_guesses``) at the speeds ``rows`` (S,): one
    factorisation per root, a Newton step and a chord step (``_Pencils.newton_chord``), where the
    chord step shows the root at round-off (the same rule as :func:`_newton`'s on its steps: at most
    ``_STEP``, or the error it leaves, ``second^2 / first``, at most ``_LEFT``); a root whose Newton
    step is already at most ``_STEP`` takes no chord step (one back-substitution: Newton's own rule);
    Newton's iteration for the others (and everywhere the pencils are not banded without a border)."""
    S, k, n = vectors.shape
    index = np.repeat(np.asarray(rows), k)
    lam, x = guesses.reshape(-1), vectors.reshape(-1, n)          # read only: the chord's results are new arrays
    chord = pencils.newton_chord(index, lam, x, None, _STEP)       # c = conj(x), made a part at a time
    if chord is None:
        return _refined(pencils, guesses, vectors, rows)
    lam, x, first, second, slope = chord
    with np.errstate(divide="ignore", invalid="ignore"):
        done = np.isfinite(lam) & ((second <= _STEP) | ((second <= _ASYMPTOTIC) & (second ** 2 / first <= _LEFT)))
    ok = done.copy()
    rest = np.nonzero(~done)[0]
    if len(rest):
        start = np.where(np.isfinite(lam[rest]), lam[rest], guesses.reshape(-1)[rest])
        again = np.where(np.isfinite(lam[rest])[:, None], x[rest], vectors.reshape(-1, n)[rest])
        lam[rest], x[rest], ok[rest] = _newton(pencils, index[rest], start, again)
        slope[rest] = np.nan
    lam, x = _certain(pencils, index, lam, x, ok, slope)
    return lam.reshape(S, k), _vectors.unit_rows(x.reshape(S, k, n)), ok.reshape(S, k).all(axis=1)


def _newton(pencils, index, lam, x):
    """:func:`_refined`'s iteration on roots ``lam`` (P,) with vectors ``x`` (P, n) at the speeds
    ``index`` (P,), both overwritten: the roots, their vectors (scaled by ``c^H x = c^H x_0``) and
    whether each converged (P,)."""
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
    return lam, x, done & np.isfinite(lam)


def _certain(pencils, index, lam, x, ok, slope=None):
    """The converged roots (``ok``) whose double-precision round-off exceeds ``_CERTAIN``
    polished (:func:`_polished`): Newton's steps on the double pencil cannot show its round-off
    (they converge to a nearby pencil's root). ``slope`` (P,): :func:`_roundoff`'s. Returns
    ``lam`` (P,), ``x`` (P, n)."""
    polish = np.nonzero(ok)[0]
    known = None if slope is None else slope[polish]
    polish = polish[_roundoff(pencils, index[polish], lam[polish], x[polish], known) > _CERTAIN]
    if len(polish):
        lam[polish], x[polish] = _polished(pencils, index[polish], lam[polish], x[polish])
    return lam, x


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


def _roundoff(pencils, index, lam, x, slope=None):
    """The relative error (P,) that double precision can leave in roots ``lam`` (P,) with shapes
    ``x`` (P, n): ``eps |x|^T (|s|^2 |M| + |s| |C + Omega G + C_b| + |K + K_b|) |x| / (|s| |x^H Q'(s) x|)``,
    the first-order change of the root under a change of each entry of the pencil by ``eps`` of
    itself, for the root's own shape (a low mode's smooth shape against stiff elements: the
    products cancel to a small part of their terms). Measured against extended-precision roots, the
    error of Newton's root on the double pencil was 0.01 to 0.35 times it. ``slope`` (P,), where
    finite: ``|x^H Q'(s) x| / |x|^2`` already known (the chord's, ``_Pencils.newton_chord``), not
    formed again."""
    s, a = np.abs(lam), np.abs(x)
    speeds = np.abs(pencils.speeds[index])
    magnitudes = pencils.__dict__.get("_magnitudes")
    if magnitudes is None:      # |M|, |C|, |G|, |K| stacked, sparse (a dense |K| product per root costs n^2): made once
        magnitudes = pencils.__dict__["_magnitudes"] = scipy.sparse.vstack(
            [abs(matrix) for matrix in pencils.sparse] + [scipy.sparse.csr_matrix(abs(pencils.K))], format="csr")
    n = x.shape[1]
    products = magnitudes @ np.ascontiguousarray(a.T)                                     # (4 n, P)
    terms = (s * (s * products[:n] + products[n:2 * n] + speeds * products[2 * n:3 * n]) + products[3 * n:]).T
    s = s[:, None]
    if len(pencils.rows):
        np.add.at(terms, (slice(None), pencils.rows), (s * np.abs(pencils.cb[index]) + np.abs(pencils.kb[index]))
                  * a[:, pencils.cols])
    terms = terms + pencils.more_terms(index, lam, a, magnitude=True)
    derivative = (np.nan if slope is None else slope) * np.einsum("pi,pi->p", a, a)      # |x^H Q'(s) x|
    todo = np.nonzero(~np.isfinite(derivative))[0]
    if len(todo):
        derivative[todo] = np.abs(np.einsum("pi,pi->p", x[todo].conj(),
                                            pencils.derivative_times(index[todo], lam[todo], x[todo])))
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
    double = _roundoff(pencils, index, lam, x)
    lam, x, paired = _pairs_polished(pencils, index, lam, x, double)
    left = np.maximum(double * np.finfo(_EXTENDED).eps / np.finfo(float).eps, _unseparated(index, lam, double))
    left = np.where(np.isfinite(paired), paired, left)      # a pair polished together: its last step
    uncertain = left > _PROMISED
    if uncertain.any():         # the full solve's polish, its residual's stiffness summed exactly
        exact = _exactly_polished(pencils, index, lam, x, double, uncertain)
        left = np.where(np.isfinite(exact), exact, left)
        uncertain = left > _PROMISED
    if uncertain.any():
        named = _speeds_named(np.unique(pencils.speeds[index[uncertain]]))
        warnings.warn(f"lowest modes: {int(uncertain.sum())} root(s) (at {named}) "
                      f"exact only to about {np.max(left[uncertain]):.1e} relative, not 1e-9: the pencil's round-off "
                      f"(a low mode beside stiff elements), which a residual of {np.finfo(_EXTENDED).nmant + 1} "
                      "significant bits cannot remove"
                      + (", nor tell apart roots closer than double precision can"
                         if np.any(uncertain & (left > double * np.finfo(_EXTENDED).eps / np.finfo(float).eps))
                         else ""), stacklevel=5)
    return lam, x


def _exactly_polished(pencils, index, lam, x, double, uncertain):
    """The roots ``lam`` (P,) at the speeds ``index`` (P,) with shapes ``x`` (P, n), both changed in
    place, that the extended residual leaves further off than ``_PROMISED`` (``uncertain`` (P,)),
    polished as the full solve polishes its roots (``_eigensolve.refined_pairs``): the neighbours
    closer than their double round-off ``double`` (P,) together (:func:`block_polished`), the
    others one at a time (a root whose steps do not converge with its nearest neighbour), the
    residual's stiffness term summed exactly, on the rational pencil where the model has Maxwell
    branches; lowest first within ``_polish_plan.polish_budget`` a speed, and only up to
    ``_PAIR_LARGEST`` coordinates (dense systems). Returns the error left (P,), NaN where not
    polished. A 1 mm shaft section in a casing on Maxwell mounts: the lowest pair 5.5e-6 and
    1.7e-6 off after the extended residual, within 1e-12 after."""
    left = np.full(len(lam), np.nan)
    if x.shape[1] > _PAIR_LARGEST:
        return left
    M = pencils.M.toarray() if scipy.sparse.issparse(pencils.M) else np.asarray(pencils.M, dtype=float)
    branches = _branches_of(pencils)
    n = x.shape[1]
    for speed in np.unique(index[uncertain]):
        at = np.flatnonzero(index == speed)
        wanted = np.flatnonzero(uncertain[at])
        values, shapes = lam[at], x[at]
        damping, stiffness = _dense_pencil(pencils, int(speed))
        spent = 0.0
        for run in _clusters(values, double[at], wanted[np.argsort(values[wanted].imag)]):
            tries = [run] if len(run) > 1 else [run, np.array([run[0], _nearest_other(values, run[0])])]
            for group in tries:
                if spent + polish_work(len(group), n) > polish_budget(n):
                    break
                spent += polish_work(len(group), n)
                found = block_polished(M, damping, stiffness, values[group], shapes[group], branches)
                if found is not None:
                    values[group] = found[0]
                    shapes[group] = [_vectors.phase_aligned(new, old) for new, old in zip(found[1], shapes[group])]
                    left[at[group]] = found[2]
                    break
        lam[at], x[at] = values, shapes
    return left


def _branches_of(pencils):
    """The Maxwell branches of rational ``pencils`` as :func:`block_polished` takes them: ``K_t``
    (b, q, q) on the first ``q`` coordinates (the stator's) and ``tau_t`` (b,) [s]; None for a
    quadratic pencil."""
    terms = getattr(pencils, "terms", None)
    if not terms:
        return None
    q = max(int(term[1].max()) for term in terms) + 1
    stiffness = np.zeros((len(terms), q, q))
    for K, (_, where, block, _, _) in zip(stiffness, terms):
        K[np.ix_(where, where)] = block
    return stiffness, np.array([term[0] for term in terms], dtype=float)


def _unseparated(index, lam, double):
    """(P,) the error a polish may leave in roots ``lam`` (P,) at speeds ``index`` (P,) with a
    neighbour closer than their double-precision round-off ``double`` (P,, relative) allows to tell
    apart: ``double min(1, (double / gap)^_POLISH_STEPS)``, ``gap`` the relative distance to the
    nearest other root of the speed. The polish's steps solve in double precision, so each takes
    the error down by about ``double / gap`` only: where the gap is below the round-off, the
    shapes stay mixtures of the two roots' and the roots as far off as Newton's on the double
    pencil left them (a 10 m shaft with a 1 mm section: a pair 6.5e-5 apart, round-off 2e-4, roots
    2.4e-5 off, where the extended round-off alone said 1e-7; issue 28). That error is at most the
    round-off: the pencil is Hermitian at an undamped root, whose roots move by at most its
    change (Weyl), however close."""
    gap = np.full(len(lam), np.inf)
    order = np.lexsort((lam.imag, index))
    same = index[order][1:] == index[order][:-1]
    apart = np.abs(np.diff(lam[order])) / np.abs(lam[order][1:])
    apart = np.where(same, apart, np.inf)
    gap[order[1:]] = np.minimum(gap[order[1:]], apart)
    gap[order[:-1]] = np.minimum(gap[order[:-1]], apart)
    with np.errstate(divide="ignore", invalid="ignore"):
        return double * np.minimum(1.0, np.nan_to_num((double / gap) ** _POLISH_STEPS, nan=1.0))



#: a pair's block polish (:func:`pair_polished`): steps, and the most coordinates (its dense
#: system has ``2 n + 4`` unknowns)
_PAIR_STEPS, _PAIR_LARGEST = 3, 1200


def _pairs_polished(pencils, index, lam, x, double):
    """The pairs of roots ``lam`` (P,) at one speed (``index`` (P,)) closer than their round-off
    ``double`` (P,, relative) allows Newton's steps on one root to tell apart, polished together
    (:func:`pair_polished`), where the pencil is quadratic (no Maxwell branches) and dense enough.
    Returns ``lam`` (P,), ``x`` (P, n) and the error left in the roots polished as a pair (P,),
    NaN elsewhere; the others (every root but an unseparated pair's) are returned as they are."""
    paired = np.full(len(lam), np.nan)
    if type(pencils).more_terms is not _plain_more_terms() or x.shape[1] > _PAIR_LARGEST:
        return lam, x, paired
    M = pencils.M.toarray() if scipy.sparse.issparse(pencils.M) else np.asarray(pencils.M, dtype=float)
    order = np.lexsort((lam.imag, index))
    for a, b in zip(order[:-1], order[1:]):
        gap = abs(lam[b] - lam[a]) / max(abs(lam[b]), abs(lam[a]))
        if index[a] != index[b] or np.isfinite(paired[a]) or not gap < max(double[a], double[b]):
            continue
        found = pair_polished(M, *_dense_pencil(pencils, int(index[a])), lam[[a, b]], x[[a, b]])
        if found is not None:
            lam[[a, b]], x[[a, b]], paired[[a, b]] = found
    return lam, x, paired


def _plain_more_terms():
    from ._lowest_pencils import _Pencils

    return _Pencils.more_terms


def pair_polished(M, damping, stiffness, pair, shapes, branches=None):
    """Two roots ``pair`` (2,) of the quadratic pencil ``M s^2 + D s + K`` (``M``, ``damping``,
    ``stiffness`` dense (n, n)) with shapes (2, n) (any scale), closer than double precision can separate one at a time,
    polished together (:func:`block_polished`). The pair's plane is as well conditioned as its
    distance to the other roots, however close the two are: measured on a 10 m shaft with a 1 mm
    section, a pair 6.5e-5 apart whose round-off is 2e-4 came within 5e-13 of a 40-digit solve (the
    steps 1.8e-4, 1.5e-8, 7e-15: quadratic), where the 64-bit residual alone left 1.4e-8 and the
    one-root polish 1.2e-4. ``branches``: the rational pencil of Maxwell branches (see
    :func:`block_polished`).

    Returns
    -------
    None or (roots (2,), shapes (2, n), left): see :func:`block_polished`
    """
    return block_polished(M, damping, stiffness, pair, shapes, branches)


def root_polished(M, damping, stiffness, root, shape):
    """One root ``root`` (complex [1/s]) of the quadratic pencil ``M s^2 + D s + K`` (dense (n, n)
    each) with its shape (n,), polished (:func:`block_polished` of one root: Newton's steps on the
    bordered system, the residual's stiffness term summed exactly, the shape kept in double-double),
    the shape returned with the phase of the one given. Measured on a 10 m shaft with a 1 mm section
    at 3,000 rpm: modes 5 and 6, which the full solve's QR gave 3.1e-6 off (round-off 1.3e-5),
    within 1e-13 of a 40-digit Newton solve.

    Returns
    -------
    None where a step fails or does not converge, else root : complex; shape : ndarray, shape (n,),
    unit; left : float, the error left (relative)
    """
    found = block_polished(M, damping, stiffness, np.array([root]), np.asarray(shape)[None])
    if found is None:
        return None
    roots, shapes, left = found
    return roots[0], _vectors.phase_aligned(shapes[0], shape), left


def bordered_lu(T, slope, border, finite_only=False):
    """The LU factors (``scipy.linalg.lu_factor``) of Newton's bordered matrix ``[[T, slope],
    [border, 0]]`` ((n + 1) x (n + 1), of ``T``'s type: real or complex), or None where it cannot
    be factored (or, with ``finite_only``, holds a value that is not finite). ``T`` (n, n) is the
    pencil at the root, ``slope`` (n,) its derivative times the shape, ``border`` (n,) the row
    that fixes the shape's scale."""
    n = T.shape[0]
    J = np.zeros((n + 1, n + 1), np.result_type(T, slope, border))
    J[:n, :n], J[:n, n], J[n, :n] = T, slope, border
    if finite_only and not np.all(np.isfinite(J)):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            return scipy.linalg.lu_factor(J, check_finite=False)
    except (ValueError, np.linalg.LinAlgError):
        return None


def rational_root_polished(M, damping, stiffness, branches, root, shape):
    """:func:`root_polished` on the rational pencil of Maxwell branches, ``T(s) = M s^2 + D s + K +
    sum_t K_t s tau_t / (1 + s tau_t)`` (``branches`` = ``K_t`` (b, k, k) on the first ``k``
    coordinates, ``tau_t`` (b,) [s]):
    chord steps of Newton's bordered system ``[[T(s), T'(s) x], [x0^H, 0]]`` (factored once), the
    residual's ``K x`` and ``K_t x`` summed exactly (:func:`_exact_sums`), the rest in
    ``_EXTENDED``. Returns None where the steps do not converge below ``_PROMISED``, else the root,
    its unit shape (the phase of ``shape``) and the error left (relative)."""
    K_t, times = branches
    n, k = M.shape[0], np.shape(K_t)[-1]
    wide = np.result_type(_EXTENDED, 1j)
    x = np.asarray(shape, complex) / np.linalg.norm(shape)
    start = x.copy()
    s = complex(root)

    def factors(value, derivative=False):
        return [t / (1.0 + value * t) ** 2 if derivative else value * t / (1.0 + value * t) for t in times]

    T = M * s * s + damping * s + stiffness + 0j
    T[:k, :k] += sum(f * K for f, K in zip(factors(s), K_t))
    slope = (2.0 * s * M + damping) @ x
    slope[:k] += sum(f * K for f, K in zip(factors(s, True), K_t)) @ x[:k]
    lu = bordered_lu(T, slope, start.conj())
    if lu is None:
        return None
    moved = np.inf
    stacked = np.asarray(K_t, dtype=float).reshape(-1, k)                # (b k, k): every branch's rows
    for _ in range(_PAIR_STEPS + 1):
        sw, xw = np.asarray(s, wide), x.astype(wide)
        residual = (M.astype(_EXTENDED) @ xw) * sw * sw + (damping.astype(_EXTENDED) @ xw) * sw \
            + _exact_sums(stiffness, x[:, None])[:, 0].astype(wide)
        products = _exact_sums(stacked, x[:k, None])[:, 0].astype(wide).reshape(len(times), k)   # each K_t x
        ratios = sw * np.asarray(times, _EXTENDED) / (1 + sw * np.asarray(times, _EXTENDED))
        residual[:k] = residual[:k] + ratios @ products
        d = scipy.linalg.lu_solve(lu, -np.append(residual.astype(complex), 0.0), check_finite=False)
        if not np.all(np.isfinite(d)):
            return None
        x, s = x + d[:n], s + d[n]
        moved = abs(d[n]) / abs(s)
        if moved <= 4 * np.finfo(float).eps:
            break
    if not moved <= _PROMISED:
        return None
    unit = _vectors.phase_aligned(x / np.linalg.norm(x), shape)
    inertia = float(_round_off_of(M, damping, np.array([s]), unit[None])[0]) * np.finfo(_EXTENDED).eps / np.finfo(float).eps
    return s, unit, max(moved, inertia, 4 * np.finfo(float).eps)


def block_polished(M, damping, stiffness, roots, shapes, branches=None):
    """``k`` roots ``roots`` (k,) of the quadratic pencil ``M s^2 + D s + K`` (``M``, ``damping``,
    ``stiffness`` dense (n, n)) with shapes (k, n) (any scale), polished together: Newton's steps for
    an invariant pair ``(X, S)``, ``X`` (n, k), ``S`` (k, k), ``M X S^2 + D X S + K X = 0`` with
    ``W^H X = I`` (``W`` the start's orthonormal basis), the residual in ``_EXTENDED`` precision
    (block Newton, Kressner 2009; for one root the bordered Newton step). The roots are the
    eigenvalues of ``S``. The residual's stiffness term is summed exactly (:func:`_exact_product`),
    and ``X`` is kept as double-double (a stiff element's product of ``X``'s rounding exceeds what
    tells two close roots apart, and what a low mode's residual is). ``branches`` (``K_t`` (b, q, q)
    on the first ``q`` coordinates, ``tau_t`` (b,) [s]), where given: the rational pencil of Maxwell
    branches, ``+ sum_t K_t X F_t(S)`` with ``F_t(S) = tau_t S (I + tau_t S)^-1``
    (:func:`_branch_block`), its ``K_t X`` summed exactly too.

    Returns
    -------
    None where a step fails or the last step is above ``_PROMISED`` (the roots left as they were), else
    roots : ndarray, shape (k,), in the order of ``roots``' frequencies; shapes : ndarray, shape
    (k, n), unit; left : float, the last step relative to ``|S|`` (at least 4 eps), the error left
    """
    n, k = M.shape[0], len(roots)
    basis, triangle = np.linalg.qr(np.asarray(shapes).T)
    X = basis
    S = triangle @ np.diag(roots) @ np.linalg.inv(triangle)
    W, Ik = basis.conj(), np.eye(k)
    low = np.zeros_like(X)        # X's low part: X + low in double-double
    factors = None
    for _ in range(_PAIR_STEPS):
        residual = _block_residual(M, damping, stiffness, X, S) + _block_residual(M, damping, stiffness, low, S, False)
        if branches is not None:
            residual = residual + _branch_block(branches, X, low, S)
        right = -np.concatenate([residual.reshape(-1, order="F"), np.zeros(k * k)])
        if factors is None:
            J = np.zeros((k * n + k * k, k * n + k * k), complex)
            J[:k * n, :k * n] = np.kron((S @ S).T, M) + np.kron(S.T, damping) + np.kron(Ik, stiffness)
            MX = M @ X
            J[:k * n, k * n:] = np.kron(S.T, MX) + np.kron(Ik, MX @ S + damping @ X)
            J[k * n:, :k * n] = np.kron(Ik, W.T)
            if branches is not None:
                _branch_jacobian(J, branches, X, S)
        try:
            if k > 1:
                d = np.linalg.solve(J, right)
            else:                 # one root: the first step's factors kept (chord steps; each gains the root's
                if factors is None:   # relative error over again, 1e-6 -> 1e-12 -> round-off)
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
                        factors = scipy.linalg.lu_factor(J, check_finite=False)
                d = scipy.linalg.lu_solve(factors, right, check_finite=False)
        except (np.linalg.LinAlgError, ValueError):
            return None
        if not np.all(np.isfinite(d)):
            return None
        more = low + d[:k * n].reshape((n, k), order="F")
        high = X + more
        X, low = high, more - (high - X)                   # two-sum: X + low the exact sum
        step = d[k * n:].reshape((k, k), order="F")
        S = S + step
        moved = np.abs(step).max() / np.abs(S).max()
    if not moved <= _PROMISED:                 # not converged (or not finite): the roots are left as they were
        return None
    found, combinations = np.linalg.eig(S)
    order = np.argsort(found.imag) if k < 2 or roots[0].imag <= roots[1].imag else np.argsort(-found.imag)
    shapes = _vectors.unit_rows((X @ combinations[:, order]).T)
    # the mass and damping terms' residual is 64-bit: what it can leave (the stiffness's is exact)
    inertia = np.max(_round_off_of(M, damping, found[order], shapes)) * np.finfo(_EXTENDED).eps / np.finfo(float).eps
    return found[order], shapes, max(moved, inertia, 4 * np.finfo(float).eps)


def _branch_inverses(times, S):
    """``H_t = (I + tau_t S)^-1`` (b, k, k) for the times ``tau_t`` (b,) [s] and ``S`` (k, k), in
    ``_EXTENDED`` precision (solved in double, then one step of iterative refinement)."""
    wide = np.result_type(_EXTENDED, 1j)
    tau = np.asarray(times, float)[:, None, None]
    A = np.eye(len(S)) + tau * S                                               # (b, k, k), double
    H = np.linalg.inv(A).astype(wide)
    Aw = np.eye(len(S), dtype=wide) + np.asarray(times, _EXTENDED)[:, None, None] * S.astype(wide)
    return H + H @ (np.eye(len(S), dtype=wide) - Aw @ H)


def _branch_block(branches, X, low, S):
    """The Maxwell branches' part of the block residual, ``sum_t K_t X_q F_t(S)`` on the first ``q``
    rows (n, k) (``F_t = I - H_t``, :func:`_branch_inverses`), with ``K_t X_q`` summed exactly
    (:func:`_exact_sums`) and ``K_t low_q`` (``X``'s low part) in ``_EXTENDED``, rounded to complex."""
    K_t, times = branches
    b, q = len(times), np.shape(K_t)[-1]
    wide = np.result_type(_EXTENDED, 1j)
    stacked = np.asarray(K_t, dtype=float).reshape(-1, q)                   # (b q, q)
    products = _exact_sums(stacked, X[:q]).astype(wide).reshape(b, q, -1) \
        + (stacked.astype(_EXTENDED) @ low[:q].astype(wide)).reshape(b, q, -1)
    F = np.eye(len(S), dtype=wide) - _branch_inverses(times, S)
    out = np.zeros(X.shape, complex)
    out[:q] = np.sum(products @ F, axis=0).astype(complex)
    return out


def _branch_jacobian(J, branches, X, S):
    """The Maxwell branches' terms added to :func:`block_polished`'s Jacobian ``J`` in place: in
    ``X``, ``kron(F_t^T, K_t)`` on each block's first ``q`` rows and columns; in ``S``, the
    derivative of ``F_t``, ``H_t tau_t dS H_t``: ``kron(H_t^T, tau_t K_t X_q H_t)``."""
    K_t, times = branches
    n, k = X.shape
    q = np.shape(K_t)[-1]
    H = _branch_inverses(times, S).astype(complex)
    eye = np.eye(k)
    for K, tau, h in zip(np.asarray(K_t, float), times, H):
        F = eye - h
        for i in range(k):
            for j in range(k):
                J[i * n:i * n + q, j * n:j * n + q] += F[j, i] * K
        part = np.zeros((n, k), complex)
        part[:q] = tau * (K @ X[:q]) @ h
        J[:k * n, k * n:] += np.kron(h.T, part)


def _round_off_of(M, damping, roots, shapes):
    """``eps |x|^T (|s|^2 |M| + |s| |D|) |x| / (|s| |x^H (2 s M + D) x|)`` (2,): :func:`_roundoff`'s
    mass and damping part, for roots (2,) with shapes (2, n)."""
    a, x, s = np.abs(shapes).T, shapes.T, np.abs(roots)
    terms = s * s * np.einsum("im,im->m", a, np.abs(M) @ a) + s * np.einsum("im,im->m", a, np.abs(damping) @ a)
    derivative = np.abs(np.einsum("im,im->m", x.conj(), 2.0 * roots * (M @ x) + damping @ x))
    return np.finfo(float).eps * terms / (s * derivative)


def _dense_pencil(pencils, speed):
    """``D = C + Omega G + C_b`` and ``K + K_b`` (n, n) each, dense, at the speed ``speed``."""
    def dense(matrix):
        return matrix.toarray() if scipy.sparse.issparse(matrix) else np.asarray(matrix, dtype=float)

    damping = dense(pencils.C) + pencils.speeds[speed] * dense(pencils.G)
    stiffness = dense(pencils.K).copy()
    if len(pencils.rows):
        np.add.at(damping, (pencils.rows, pencils.cols), pencils.cb[speed])
        np.add.at(stiffness, (pencils.rows, pencils.cols), pencils.kb[speed])
    return damping, stiffness


def _block_residual(M, damping, stiffness, X, S, exact=True):
    """``M X S^2 + D X S + K X`` (n, 2) in ``_EXTENDED`` precision from the double ``X``, ``S``, rounded
    to complex (the products of a low mode's smooth shape with stiff elements cancel); ``exact``:
    the stiffness term summed exactly (:func:`_exact_product`), else in ``_EXTENDED`` (``X`` a
    low part)."""
    wide = np.result_type(_EXTENDED, 1j)
    Xw, Sw = X.astype(wide), S.astype(wide)
    XS = Xw @ Sw
    K = _exact_product(stiffness, X) if exact else stiffness.astype(_EXTENDED) @ Xw
    out = M.astype(_EXTENDED) @ (XS @ Sw) + damping.astype(_EXTENDED) @ XS + K
    return out.astype(complex)


#: 2^27 + 1: Dekker's splitting of a double (:func:`_halves`)
_SPLIT = 134217729.0


def _halves(a):
    """Dekker's splitting of doubles ``a`` (any shape): ``high + low == a`` exactly, each half of
    at most 26 significant bits, so that the product of two halves is exact in double."""
    c = _SPLIT * a
    high = c - (c - a)
    return high, a - high


def _exact_product(matrix, X):
    """``matrix @ X`` (n, k) of a double matrix (n, n) and complex ``X`` (n, k), each entry the exact
    sum rounded once (Dekker's exact products, ``math.fsum``), as ``_EXTENDED`` complex: the stiffness
    term, whose terms are up to 1e12 times their sum beside a 1 mm shaft section, so that even the
    64-bit residual leaves a pair 1e-8 off."""
    import math

    A = np.asarray(matrix, dtype=float)
    a_hi, a_lo = _halves(A)
    out = np.zeros(X.shape, np.result_type(_EXTENDED, 1j))
    for k in range(X.shape[1]):
        for part, unit in ((X[:, k].real, 1.0), (X[:, k].imag, 1j)):
            b_hi, b_lo = _halves(part)
            p = A * part
            e = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo
            terms = np.concatenate([p, e], axis=1)
            out[:, k] += unit * np.array([math.fsum(row) for row in terms], dtype=_EXTENDED)
    return out


def _exact_sums(matrix, X):
    """``matrix @ X`` (n, k) of a double matrix (n, n) and complex ``X`` (n, k), each entry within
    ``eps`` of itself plus ``n eps^2`` of its terms' sum of magnitudes, rounded to complex: the
    products exact (Dekker's splitting) and summed in pairs with their rounding errors kept
    (``TwoSum`` in a tree, the errors added at the end), all in array operations (:func:`_exact_product`
    sums each row with ``math.fsum``, exactly but a row at a time). The rows go through in parts of
    about ``_batches._PART_BYTES`` (n = 2,000, k = 4: not 1.5 GB at once); each row's sums are its
    own, so the parts do not change them."""
    A = np.asarray(matrix, dtype=float)
    parts = np.concatenate([X.real, X.imag], axis=1)       # (n, 2k)
    out = np.empty((A.shape[0], parts.shape[1]))
    for rows in _batches.chunk_slices(A.shape[0], _SUMS_ROW_BYTES * A.shape[1] * parts.shape[1],
                                      budget=_batches._PART_BYTES):
        out[rows] = _row_sums(A[rows], parts)
    k = X.shape[1]
    return out[:, :k] + 1j * out[:, k:]


#: work memory of :func:`_row_sums` per row, column of ``matrix`` and column of ``parts`` [bytes]
#: (tracemalloc: 66 at n = 400, k = 4, the terms (2n, 2k) and their pairs' sums and errors)
_SUMS_ROW_BYTES = 68


def _row_sums(A, parts):
    """:func:`_exact_sums`'s sums of the rows ``A`` (r, n) times the real parts ``parts`` (n, 2k),
    shape (r, 2k)."""
    a_hi, a_lo = _halves(A)
    b_hi, b_lo = _halves(parts)
    p = A[:, :, None] * parts[None, :, :]                   # (r, n, 2k)
    e = ((a_hi[:, :, None] * b_hi[None] - p) + a_hi[:, :, None] * b_lo[None] + a_lo[:, :, None] * b_hi[None]) \
        + a_lo[:, :, None] * b_lo[None]
    terms = np.concatenate([p, e], axis=1)                  # (r, 2n, 2k)
    return tree_sum(terms)


def tree_sum(terms):
    """Sums over axis 1 of ``terms`` (r, t, c), shape (r, c): pairwise ``TwoSum`` in a tree with
    the rounding errors kept and added at the end."""
    errors = []
    while terms.shape[1] > 1:
        if terms.shape[1] % 2:
            terms = np.concatenate([terms, np.zeros_like(terms[:, :1])], axis=1)
        a, b = terms[:, 0::2], terms[:, 1::2]
        total = a + b
        virtual = total - a
        errors.append((a - (total - virtual)) + (b - virtual))
        terms = total
    return terms[:, 0] + np.concatenate(errors, axis=1).sum(axis=1)


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
