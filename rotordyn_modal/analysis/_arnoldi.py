"""The lowest roots of a model whose undamped modes crowd right above the wanted ones: shift-invert
Arnoldi on a sparse LU of each speed's pencil, the roots below a gap counted by Sylvester's inertia.

``docs/theory.md`` section 17, "Crowded spectra: shift-invert Arnoldi". The reduced route of
:mod:`._lowest` needs a basis that holds every root up to the wanted ones; where the completeness
bound asks for more than half of the model's coordinates (a chain of rotors on bearings, whose
thousands of bearing modes start right above the 12th root), :func:`takes` says so and
:func:`lowest` serves the speeds instead:

1. at each speed, ARPACK's shift-invert Arnoldi (:func:`scipy.sparse.linalg.eigs`, real
   arithmetic, shift ``sigma`` on the real axis near 0) on the first-order form, one sparse LU of
   ``Q(sigma) = sigma^2 M + sigma D + K`` per speed: the ``2 (count + 1 + _EXTRA)`` roots nearest
   ``sigma``;
2. **the count** (:func:`count_below`): the number of roots below a frequency ``omega_c`` (in the
   widest relative gap of the roots found above the wanted ones) of the pencil's conservative part,
   the negative eigenvalues of the Hermitian ``K_s - omega_c^2 M + i omega_c D_g``, must equal the
   number of roots found below it; else more roots are asked for, and at last the speed is left to
   the full eigen-solve;
3. the wanted roots refined on the full pencil by the reduced route's Newton iteration (passed
   in: ``refine``), so that both routes give each root to round-off the same way.

M, C, G and K may be dense or ``scipy.sparse`` (n, n): they are taken as ``scipy.sparse.csc_array``.
"""

from __future__ import annotations

import copy

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from .._blas import seeded_start
from . import _batches
from .modal import is_oscillating

__all__ = ["MIN_DOF", "SHARE", "below", "count_below", "lowest", "takes"]

#: the rule: Arnoldi where the reduced basis (modes and attachment directions) would hold more
#: than this share of the coordinates ...
SHARE = 0.5
#: ... in a model of at least this many coordinates (below, the full-size projected pencil is small)
MIN_DOF = 100

#: roots asked of ARPACK beyond the ``count + 1`` wanted, per conjugate pair (doubled while the
#: count disagrees, up to ``_TRIES`` times)
_EXTRA, _TRIES = 6, 4
#: roots first asked for at each speed for the modes below a frequency without a count (doubled until
#: the highest lies above the frequency)
_FIRST = 12
#: ARPACK's tolerance on the shifted inverse's Ritz values (the roots are refined by Newton after)
_TOLERANCE = 1e-10
#: ARPACK's roots this close (relative) are taken for the copies of one multiple root: its copies
#: came 1e-9 to 1e-12 apart on a row of 30 rotors on isotropic bearings at rest, its distinct roots
#: further apart than 1e-3
_COINCIDE = 1e-7
#: times ARPACK is asked again, for 2 more roots each, where it ends without convergence (its
#: count cut inside a multiple root)
_CUT_RETRIES = 2


def takes(basis: int, n: int) -> bool:
    """The rule of the route: shift-invert Arnoldi where the reduced basis the completeness bound
    asks for (``basis`` = modes + attachment directions) holds more than ``SHARE`` of the ``n``
    coordinates, in a model of at least ``MIN_DOF`` coordinates."""
    return n >= MIN_DOF and basis > SHARE * n


def lowest(pencils, count: int, refine, distinct, progress: bool | str = False):
    """The ``count + 1`` lowest oscillating roots of every speed of ``pencils``, counted complete
    (:func:`count_below`) and refined on the full pencil.

    Parameters
    ----------
    pencils : _lowest_pencils._Pencils
        The sweep's pencils: ``M, C, G, K`` (n, n, dense or sparse), ``speeds`` (S,) [rad/s], the
        speed-dependent bearings' entries ``rows, cols`` (nb,) and ``kb, cb`` (S, nb).
    count : int
        Modes wanted (>= 1).
    refine : callable
        ``refine(pencils, starts (S, k), vectors (S, k, n)) -> roots, unit shapes, ok (S,)``
        (:func:`._lowest_newton._refined`).
    distinct : callable
        ``distinct(roots (S, k), shapes (S, k, n)) -> (S,)`` the roots are distinct modes (:func:`._lowest._distinct`).
    progress : bool or str
        A progress bar over the speeds, kept through their refinement (17 s at 200 geared rotors);
        a str names it (default "lowest modes (Arnoldi)"; the mode numbers of
        ``critical-speeds --lowest N`` name theirs).

    Returns
    -------
    roots : ndarray, shape (S, count + 1), complex [1/s]
        By frequency.
    shapes : ndarray, shape (S, count + 1, n), complex, unit norm
    ok : ndarray of bool, shape (S,)
        The speed's roots were counted complete and refined (else: to be solved whole).
    """
    parts = _Parts(pencils)
    S, want, n = len(pencils.speeds), count + 1, parts.n
    starts = np.full((S, want), np.nan + 0j)
    vectors = np.zeros((S, want, n), complex)
    ok = np.zeros(S, bool)
    bar = None
    if progress:
        from .._progress import tqdm

        desc = progress if isinstance(progress, str) else "lowest modes (Arnoldi)"
        bar = tqdm(total=S, desc=desc, unit="speed", leave=False)
    reach = np.full((S, want), np.inf)
    try:
        for p in range(S):
            found = _counted_roots(parts, p, want)
            if found is not None:
                starts[p], vectors[p], reach[p] = found
                ok[p] = True
            if bar is not None:
                bar.update(1)
        if bar is not None:       # the bar, its clock running, stays through the refinement of every speed
            bar.set_description(f"{desc}, refining", refresh=False)
        return _refined_found(pencils, starts, vectors, reach, ok, refine, distinct)
    finally:
        if bar is not None:
            bar.close()


def below(pencils, limit: float, count, refine, distinct):
    """The oscillating roots of frequency ``Im s`` up to ``limit`` of every speed of ``pencils`` (at
    most ``count``, the lowest) and the next, counted complete (:func:`count_below`) and refined on
    the full pencil: the modes below a frequency on this route (``--max-frequency``).

    At each speed, ARPACK is asked for the lowest roots until the highest found lies above
    ``limit`` (their number doubled, from ``count + 1`` or ``_FIRST``), the count by inertia
    placed above it; every speed then takes the most any speed needs (its roots below the limit
    and one more), the later ones fillers exact as the others.

    Parameters
    ----------
    pencils, refine, distinct
        As :func:`lowest`.
    limit : float
        Highest frequency wanted [rad/s].
    count : int or None
        At most this many roots below the limit per speed.

    Returns
    -------
    roots : ndarray, shape (S, k), complex [1/s]
        By frequency; nan at a speed left to the full eigen-solve.
    shapes : ndarray, shape (S, k, n), complex, unit norm
    ok : ndarray of bool, shape (S,)
    """
    parts = _Parts(pencils)
    S, n = len(pencils.speeds), parts.n
    most = n - 2                              # ARPACK finds fewer than n pairs
    want = min(most, _FIRST if count is None else count + 1)
    found = [None] * S
    for p in range(S):
        while True:
            roots = _counted_roots(parts, p, want)
            if roots is not None and (roots[0][-1].imag > limit or (count is not None and want > count)):
                found[p] = roots
                break
            if roots is None or want >= most:
                break
            want = min(most, 2 * want)
    ok = np.array([roots is not None for roots in found], bool)
    below_limit = [int(np.sum(roots[0].imag <= limit)) for roots in found if roots is not None]
    k = min(most, max(below_limit, default=0) + 1)
    if count is not None:
        k = min(k, count + 1)
    starts = np.full((S, k), np.nan + 0j)
    vectors = np.zeros((S, k, n), complex)
    reach = np.full((S, k), np.inf)
    for p in np.nonzero(ok)[0]:
        roots = found[p] if len(found[p][0]) >= k else _counted_roots(parts, p, k)
        found[p] = None                 # its shapes are copied below: not held twice
        if roots is None:
            ok[p] = False
            continue
        starts[p], vectors[p], reach[p] = (part[:k] for part in roots)
    return _refined_found(pencils, starts, vectors, reach, ok, refine, distinct)


#: complex vectors of ``n`` Newton's iteration holds per root at once (``_lowest._NEWTON_VECTORS``):
#: the speeds are refined in parts of ``_batches._PART_BYTES`` of that work
_NEWTON_VECTORS = 24


def _refined_found(pencils, starts, vectors, reach, ok, refine, distinct):
    """The roots found by ARPACK (S, k) at the speeds ``ok`` (S,), with their shapes (S, k, n) and
    distances to the nearest other root (S, k), refined by ``refine`` in parts of bounded memory
    (each root's iteration is its own): roots by frequency, unit shapes (written over ``vectors``)
    and whether each speed's refined roots are distinct and Newton reached the root its start
    stands for (S,)."""
    values = starts.copy()
    sure = np.nonzero(ok)[0]
    k, n = vectors.shape[1:]
    for part in _batches.chunk_slices(len(sure), 16 * _NEWTON_VECTORS * k * n, budget=_batches._PART_BYTES):
        rows = sure[part]
        refined, unit, converged = refine(_speeds_of(pencils, rows), starts[rows], vectors[rows])
        # Newton reached the root its start stands for (nearer it than half the way to another root)
        own = np.all(np.abs(refined - starts[rows]) < 0.5 * reach[rows], axis=1)
        ok[rows] = converged & own & distinct(refined, unit)
        order = np.argsort(np.where(is_oscillating(refined), refined.imag, np.inf), axis=1, kind="stable")
        values[rows] = np.take_along_axis(refined, order, 1)
        vectors[rows] = np.take_along_axis(unit, order[..., None], 1)
    return values, vectors, ok


def _speeds_of(pencils, index):
    """``pencils`` of the speeds ``index`` only (a shallow copy: the constant matrices shared)."""
    if len(index) == len(pencils.speeds):
        return pencils
    part = copy.copy(pencils)
    part.speeds, part.kb, part.cb = pencils.speeds[index], pencils.kb[index], pencils.cb[index]
    return part


class _Parts:
    """The sparse parts of the sweep's pencils and the pattern their sum shares."""

    def __init__(self, pencils):
        self.pencils = pencils
        self.M, self.C, self.G, self.K = (scipy.sparse.csc_array(x) for x in
                                          (pencils.M, pencils.C, pencils.G, pencils.K))
        self.n = self.M.shape[0]
        self.scale = float(getattr(pencils, "scale", 1.0))

    def at(self, p):
        """``M, D, K`` (csc, one shared pattern: ``indices, indptr``) of speed ``p``, as data arrays
        (nnz,) each, and the pattern."""
        pencils = self.pencils
        D = self.C + pencils.speeds[p] * self.G
        K = self.K
        if len(pencils.rows):
            shape = (self.n, self.n)
            D = D + scipy.sparse.csc_array((pencils.cb[p], (pencils.rows, pencils.cols)), shape=shape)
            K = K + scipy.sparse.csc_array((pencils.kb[p], (pencils.rows, pencils.cols)), shape=shape)
        # one pattern for the three: the union, each part's entries placed on it
        union = (abs(self.M) + abs(D) + abs(K)).tocsc()
        union.sort_indices()
        rows = union.indices
        cols = np.repeat(np.arange(self.n), np.diff(union.indptr))
        data = [np.asarray(scipy.sparse.csr_array(X)[rows, cols]).ravel() for X in (self.M, D, K)]
        return data, union.indices, union.indptr

    def conservative(self, p):
        """``K_s = (K + K^T)/2``, ``D_g = (D - D^T)/2`` and ``M`` of speed ``p`` (csc each)."""
        (Md, Dd, Kd), indices, indptr = self.at(p)
        shape = (self.n, self.n)
        K = scipy.sparse.csc_array((Kd, indices, indptr), shape=shape)
        D = scipy.sparse.csc_array((Dd, indices, indptr), shape=shape)
        return ((K + K.T) * 0.5).tocsc(), ((D - D.T) * 0.5).tocsc(), self.M


def _counted_roots(parts, p, want):
    """The ``want`` lowest oscillating roots of speed ``p`` by ARPACK, counted complete: starts
    (want,), shapes (want, n) and each one's distance to the nearest other root found (want,);
    None where the count never agreed (or ARPACK failed)."""
    (Md, Dd, Kd), indices, indptr = parts.at(p)
    n = parts.n

    def pencil(s):
        dtype = complex if np.iscomplexobj(s) else float
        return scipy.sparse.csc_array(((s * s) * Md + s * Dd + Kd, indices, indptr), shape=(n, n), dtype=dtype)

    pairs = want + _EXTRA
    for _ in range(_TRIES):
        k = min(2 * pairs, 2 * n - 3)
        found = _arnoldi(pencil, Md, Dd, indices, indptr, n, k, parts.scale)
        if found is None:
            return None
        lam, x = found
        picked = _picked(lam, x, want, k >= 2 * n - 3)
        if picked is not None:
            roots, shapes, reach, top = picked
            shapes = _own_shapes(pencil, roots, shapes)
            counted = count_below(parts, p, top)
            below = np.sum((lam.imag > 0) & (lam.imag < top))
            if counted is not None and counted == below:
                return roots, shapes, reach
        if k >= 2 * n - 3:
            return None
        pairs *= 2
    return None


def _own_shapes(pencil, roots, shapes):
    """The shapes (want, n) of ``roots`` (want,) by one step of inverse iteration from ARPACK's
    shapes: ``y = Q(s)^-1 x`` and ``Q(s)^-1 conj(x)``, the larger (the one holding more of the
    root's own shape), unit norm; ARPACK's shape where ``Q(s)`` cannot be factored.

    ARPACK's real shift-invert mode (:func:`scipy.sparse.linalg.eigs`, scipy 1.17) gives exact roots
    (1e-11) but some with their conjugate root's displacement shape, or a mixture of the two: on a
    chain of 100 rotors on bearings 157 of 231 shapes at 11 speeds (MAC with the true shape 0 to
    0.4). Newton's iteration started there left for a distant root (one at 578 rad/s went to
    917 rad/s), the speed's check rejected it, and the speed was solved whole: every speed of the
    500-rotor chain, 11 dense eigen-solutions of 4,012 states. At a root exact to round-off one
    solve gives its shape to round-off, and the conjugate root's shape is no part of it."""
    out = np.array(shapes, complex)
    for j, s in enumerate(roots):
        try:
            factor = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(pencil(complex(s))))
        except RuntimeError:                  # exactly singular: the shape stays ARPACK's
            continue
        with np.errstate(all="ignore"):
            y = factor.solve(np.stack([shapes[j], shapes[j].conj()], axis=1))
        size = np.linalg.norm(y, axis=0)
        best = int(np.argmax(np.where(np.isfinite(size), size, -1.0)))
        if np.isfinite(size[best]) and size[best] > 0:
            out[j] = y[:, best] / size[best]
    return out


def _arnoldi(pencil, Md, Dd, indices, indptr, n, k, scale):
    """ARPACK's ``k`` roots nearest a real shift near 0 and their displacement shapes (n, k); None
    where every shift tried is a root or ARPACK fails."""
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, LinearOperator, eigs

    for sigma in (0.0, -1e-6 * np.sqrt(scale), -1e-3 * np.sqrt(scale)):
        try:
            factor = scipy.sparse.linalg.splu(pencil(sigma))
        except RuntimeError:                 # exactly singular: a root at the shift
            continue
        mass = scipy.sparse.csr_array((Md, indices, indptr), shape=(n, n))
        damping = scipy.sparse.csr_array((Dd + sigma * Md, indices, indptr), shape=(n, n))

        def inverse(w, factor=factor, sigma=sigma, mass=mass, damping=damping):
            # (A - sigma I)^-1 [u; v] = [x; u + sigma x], Q(sigma) x = -(M v + (D + sigma M) u)
            w = np.asarray(w).ravel()
            x = -factor.solve(mass @ w[n:] + damping @ w[:n])
            return np.concatenate([x, w[:n] + sigma * x])

        def unused(w):
            raise RuntimeError("shift-invert mode applies only the inverse")

        start = seeded_start(2 * n)
        # ARPACK's count k cutting inside a multiple root (an axisymmetric machine at rest: four
        # roots of one modulus, two double roots and their conjugates) ends without convergence
        # though every vector converged: asked again for the whole group, k + 2 then k + 4
        for asked in range(k, min(k + 2 * _CUT_RETRIES, 2 * n - 3) + 1, 2):
            try:
                lam, vectors = eigs(LinearOperator((2 * n, 2 * n), matvec=unused, dtype=float), k=asked, sigma=sigma,
                                    OPinv=LinearOperator((2 * n, 2 * n), matvec=inverse, dtype=float), which="LM",
                                    tol=_TOLERANCE, v0=start)
            except ArpackNoConvergence:
                continue
            except ArpackError:
                return None
            if not np.all(np.isfinite(lam)):
                return None
            return lam, vectors[:n]
        return None
    return None


def _picked(lam, x, want, every):
    """The ``want`` lowest oscillating roots of ``lam`` (k,) (ARPACK's, shapes ``x`` (n, k)) with
    unit shapes (want, n), each one's distance to the nearest other root of ``lam`` or its own
    conjugate (want,), and the frequency ``omega_c`` [rad/s] below which the count must find as
    many roots as ARPACK did (:func:`count_below`): in the middle of the widest relative gap between
    the frequencies found from the ``want``-th on (below the highest found: ARPACK's roots are those
    nearest the shift, so every root near the imaginary axis below it was in reach); twice the
    highest where ``every`` root was asked for; None where too few were found to place it."""
    key = np.where(is_oscillating(lam), lam.imag, np.inf)
    order = np.argsort(key, kind="stable")
    if not np.isfinite(key[order[want - 1]]):
        return None
    upper = np.sort(lam.imag[lam.imag > 0])
    wanted_top = key[order[want - 1]]
    above = upper[upper >= wanted_top]
    if len(above) < 2:
        if not every:
            return None
        top = 2.0 * above[-1]
    else:
        gaps = (above[1:] - above[:-1]) / above[1:]
        j = int(np.argmax(gaps))
        if gaps[j] <= 0:
            return None
        top = 0.5 * (above[j] + above[j + 1])
    shapes = x[:, order[:want]].T
    shapes = shapes / np.linalg.norm(shapes, axis=1, keepdims=True)
    picked = lam[order[:want]]
    others = np.abs(picked[:, None] - lam[None, :])
    others[np.arange(want), order[:want]] = np.inf
    # the copies of one multiple root (an axisymmetric machine at rest) are no other root: ARPACK
    # gives them apart by its own error, which Newton's iteration moves them by (every such speed was
    # solved whole); ``distinct`` then tells a multiple root from one root reached twice
    others[others <= _COINCIDE * np.abs(picked)[:, None]] = np.inf
    reach = np.minimum(others.min(axis=1), 2 * np.abs(picked.imag))     # its conjugate, too
    return picked, shapes, reach, top


def count_below(parts, p, omega):
    """The number of roots ``s = i w``, ``0 < w < omega`` [rad/s], of the conservative part of speed
    ``p``'s pencil, ``s^2 M + s D_g + K_s`` (``D_g = (D - D^T)/2`` gyroscopic, ``K_s = (K + K^T)/2``):
    the number of negative eigenvalues of the Hermitian ``H(omega) = K_s - omega^2 M + i omega D_g``
    (Sylvester's law of inertia on an ``L D L^H`` factorisation: SuperLU with diagonal pivots in
    a symmetric order). None where ``K_s`` is not positive definite (the count needs it), where
    SuperLU left the diagonal, or where the factorisation's backward error exceeds ``_BACKWARD``.

    Parameters
    ----------
    parts : _Parts
    p : int
        The speed.
    omega : float [rad/s]

    Returns
    -------
    int or None
    """
    stiffness, gyroscopic, mass = parts.conservative(p)
    if _negative(stiffness) != 0:
        return None
    return _negative((stiffness - omega ** 2 * mass + 1j * omega * gyroscopic).tocsc())


def _negative(H):
    """The number of negative eigenvalues of the sparse Hermitian ``H`` (n, n) from the pivots of
    ``P H P^T = L D L^H``; None where that factorisation is not at hand (see :func:`count_below`)."""
    H = scipy.sparse.csc_array(H, dtype=complex)
    try:
        factor = scipy.sparse.linalg.splu(H, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                          options=dict(SymmetricMode=True))
    except RuntimeError:                  # singular: an eigenvalue at 0
        return None
    if not np.array_equal(factor.perm_r, factor.perm_c):
        return None
    pivots = factor.U.diagonal()
    rhs = seeded_start(H.shape[0]) + 0j
    x = factor.solve(rhs)
    size = scipy.sparse.linalg.norm(H, 1)
    residual = np.linalg.norm(H @ x - rhs, 1) / (size * np.linalg.norm(x, 1))
    if not np.isfinite(residual) or residual > _BACKWARD or np.any(np.abs(pivots.imag) > _BACKWARD * size):
        return None
    return int(np.sum(pivots.real < 0))


#: the largest backward error of the L D L^H factorisation the count accepts (relative to |H|_1)
_BACKWARD = 1e-10
