"""The starts of the lowest modes' Newton iteration, and which roots are the lowest
(``docs/theory.md`` section 17, step 2 and "Ties").

:func:`_projected_starts`: the lowest roots of the projected pencils ``W^T Q(s) W`` of every speed
(one batched ``eigvals``, the wanted roots' vectors by one inverse-iteration step each);
:func:`frequency_key` and :func:`lowest_order`: roots by frequency, the modes first, and at a tie
across the ``count``-th place the least stable kept.
"""

from __future__ import annotations

import copy
import functools
import typing

import numpy as np
import scipy.sparse

from . import _batches, _pencils, _vectors
from .modal import is_oscillating

__all__ = ["frequency_key", "lowest_order"]


#: the speed the projected pencils are taken from (:func:`_projected_starts`): the sweep's first
_FIRST = np.zeros(1, int)


def _projected_starts(pencils, basis, want, index=None, vectors_at=None):
    """The ``want`` lowest-frequency oscillating roots of the projected pencils at every speed
    (or at the speeds ``index``) (S, want) and their vectors in full coordinates (S, want, n);
    with ``vectors_at`` (S,) bool, the vectors of those speeds only (zero elsewhere: the speeds
    whose Newton starts come from their neighbours)."""
    n, m = basis.shape
    index = np.arange(len(pencils.speeds)) if index is None else index
    speeds, cb, kb = pencils.speeds[index], pencils.cb[index], pencils.kb[index]
    S = len(speeds)
    starts = np.empty((S, want), complex)
    vectors = np.empty((S, want, n), complex)
    Wt = basis.T
    # from the sweep's first speed, not the first asked: a speed's projected pencil (to its last bit)
    # is its own whichever speeds are asked with it (the parts of a sweep, its restarts)
    D0, K0, Gr = projected_first(pencils, _FIRST, basis)
    # the bearings' changes from the first speed, projected entry by entry
    left, right = basis[pencils.rows].T, basis[pencils.cols]
    for part in _batches.chunk_slices(S, 64 * m * m):
        D = D0 + (speeds[part] - pencils.speeds[0])[:, None, None] * Gr            # (P, m, m)
        Kr = np.broadcast_to(K0, D.shape)
        if len(pencils.rows):
            D = D + (left[None] * (cb[part] - pencils.cb[:1])[:, None, :]) @ right
            Kr = Kr + (left[None] * (kb[part] - pencils.kb[:1])[:, None, :]) @ right
        A = np.zeros((len(D), 2 * m, 2 * m))
        A[:, :m, m:] = np.eye(m)
        A[:, m:, :m] = -Kr              # the basis is mass-orthonormal: W^T M W = I
        A[:, m:, m:] = -D
        wanted = None if vectors_at is None else vectors_at[part]
        lam, shapes = _projected_roots(A, D, Kr, want, wanted)
        starts[part] = lam
        if wanted is None:
            vectors[part] = _vectors.unit_rows(shapes @ Wt)
        else:
            rows = np.arange(part.start, part.stop)
            vectors[rows[wanted]] = _vectors.unit_rows(shapes[wanted] @ Wt)
            vectors[rows[~wanted]] = 0.0
    return starts, vectors


def projected_roots_kept(pencils, basis, want, index):
    """The roots of :func:`_projected_starts` (S, want) at the speeds ``index``, the last asked kept on
    ``pencils``: the reduced route's highest root wanted (``_lowest._reduced_roots``) asks for those
    the Arnoldi test (``_lowest_route._crowded``) made, on the same modes (one dense ``eigh``: equal
    bit for bit), and takes them again. Anything else asked is made. No vectors are made (one
    inverse-iteration step per root, and their products with the basis: a third of the time of a
    check's few speeds on a 44-coordinate rotor)."""
    kept = pencils.__dict__.get("_kept_roots")
    if kept is not None and kept[1] == want and np.array_equal(kept[2], index) and kept[0].shape == basis.shape \
            and np.array_equal(kept[0], basis):
        return kept[3]
    # the roots alone: no speed's vectors (its roots are eigvals' or eig's either way, the same bits)
    roots = _projected_starts(pencils, basis, want, index, vectors_at=np.zeros(len(index), bool))[0]
    pencils.__dict__["_kept_roots"] = (basis.copy(), want, np.array(index), roots)
    return roots


def frequency_key(lam):
    """The sort key of roots ``lam`` (any shape) by frequency: ``Im lam`` of the oscillating roots,
    ``inf`` for the others (pushed to the end)."""
    return np.where(is_oscillating(lam), lam.imag, np.inf)


#: roots whose frequencies differ by at most this times their modulus are of one frequency for the
#: choice of the lowest (the accuracy promised: an undamped cross-coupled model's pairs ``-a + ib``,
#: ``a + ib`` are equal to round-off)
_TIE = 1e-9


def lowest_order(lam, count=None):
    """Where the roots of each row of ``lam`` (S, m) stand by frequency (:func:`frequency_key`, a
    stable sort), (S, m); where the ``count``-th place falls inside a group of roots of one
    frequency (within ``_TIE``), that group by decreasing real part, so that the first ``count``
    keep its least stable roots: an undamped cross-coupled model has pairs ``-a + ib``, ``a + ib``
    of one frequency, and keeping the stable one of a split pair would hide the unstable one."""
    key = frequency_key(lam)
    order = np.argsort(key, axis=-1, kind="stable")
    if count is None or not 0 < count < lam.shape[-1]:
        return order
    key, values = np.take_along_axis(key, order, -1), np.take_along_axis(lam, order, -1)
    with np.errstate(invalid="ignore"):
        tied = np.abs(np.diff(key, axis=-1)) <= _TIE * np.abs(values[:, 1:])        # (S, m - 1): j, j + 1
    for row in np.nonzero(tied[:, count - 1])[0]:
        first, last = count - 1, count
        while first > 0 and tied[row, first - 1]:
            first -= 1
        while last + 1 < lam.shape[-1] and tied[row, last]:
            last += 1
        group = order[row, first:last + 1]
        order[row, first:last + 1] = group[np.argsort(-lam[row, group].real, kind="stable")]
    return order


def _by_frequency(values, shapes, count=None):
    """Roots (S, k) and shapes (S, k, n) in the order of :func:`lowest_order` (``count``: the place
    of the cut)."""
    order = lowest_order(values, count)
    return np.take_along_axis(values, order, 1), np.take_along_axis(shapes, order[..., None], 1)


def _projected_roots(A, damping, stiffness, want, wanted=None):
    """The ``want`` lowest-frequency oscillating roots (P, want) of the projected state matrices
    ``A`` (P, 2 m, 2 m) and their shapes (P, want, m): the roots by a batched ``eigvals``, the shapes
    by one inverse-iteration step each on the projected pencils (``damping``, ``stiffness`` (P, m, m),
    unit mass); a speed where a root picked is not a mode or lies within ``_CLOSE`` of another
    takes ``eig``'s roots and eigenvectors. Threads, one BLAS thread each (BLAS's own threads on
    top oversubscribe the cores). ``wanted`` (P,) bool: the speeds whose shapes are wanted
    (default all; the others' are left unset)."""
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
    sure = np.nonzero(~whole if wanted is None else ~whole & wanted)[0]
    if len(sure):
        part = functools.partial(_pencil_shapes_part, np.eye(m))
        shapes[sure] = _batches._threaded(part, stiffness[sure], picked[sure], damping[sure],
                                          item_bytes=48 * want * m * m, thread_bytes=_batches.SOLVE_THREAD_BYTES)
    return picked, shapes


#: a projected root is matched to the nearest of the next speed's where that is at most this part of
#: the distance to the next nearest (and the match is mutual)
_MATCH = 0.5

#: every this many speeds (and the last), an anchor: its Newton starts are the projected roots
_STRIDE = 4


#: every this many anchors (and the last) solve their projected pencils whole (``eig``, :class:`_Expansions`)
_SOLVED = 2


def _anchors(count: int) -> np.ndarray:
    """The anchors (A,) of ``count`` speeds: every ``_STRIDE``-th and the last."""
    return np.unique(np.append(np.arange(0, count, _STRIDE), count - 1))


def _continuation_guesses(starts, speeds, anchors, values, shapes, ok):
    """Newton's starts at the speeds between anchors from the anchors' refined roots.

    A projected root is off its full root by the projection's error (about 4e-5 relative on a
    shaft), which changes slowly with the speed: the start is the projected root plus that error
    interpolated linearly between the neighbouring anchors (measured on ROSS's
    compressor_example, 201 speeds, every fourth an anchor: 1e-9 relative typically, 8e-8 at the
    99th percentile), with the vector of the nearer anchor's root. Each projected root is followed
    from speed to speed to the anchors (:func:`_matched`); a speed where a root cannot be followed
    unambiguously (a crossing, or a root coming from above near the cut), or whose anchors failed,
    is not continued (``sure`` False).

    Parameters
    ----------
    starts : ndarray, shape (S, k), complex
        The projected roots of every speed, by frequency.
    speeds : ndarray, shape (S,) [rad/s]
    anchors : ndarray of int, shape (A,)
        Ascending, the first 0 and the last ``S - 1``.
    values : ndarray, shape (A, k), complex
        The anchors' refined roots, in their starts' order.
    shapes : ndarray, shape (A, k, n), complex
    ok : ndarray of bool, shape (A,)

    Returns
    -------
    between : ndarray of int, shape (J,)
        The speeds that are not anchors.
    guesses : ndarray, shape (J, k), complex; vectors : ndarray, shape (J, k, n), complex
    sure : ndarray of bool, shape (J,)
    """
    count, k = starts.shape
    between = np.setdiff1d(np.arange(count), anchors)
    right = np.searchsorted(anchors, between)
    left = right - 1
    # each root's place at the speed before (S - 1, k), and whether every root of a speed has one
    back, linked = _matched(starts[1:], starts[:-1])
    at_left, at_right = np.tile(np.arange(k), (len(between), 1)), np.tile(np.arange(k), (len(between), 1))
    sure = ok[left] & ok[right]
    rows = np.arange(k)
    for row, speed in enumerate(between):
        for step in range(speed, anchors[left[row]], -1):       # back to the anchor before
            at_left[row] = back[step - 1][at_left[row]]
            sure[row] &= linked[step - 1]
        for step in range(speed + 1, anchors[right[row]] + 1):  # on to the anchor after
            forward = np.zeros(k, int)             # a permutation where linked (else not sure)
            forward[back[step - 1]] = rows
            at_right[row] = forward[at_right[row]]
            sure[row] &= linked[step - 1]
    span = speeds[anchors[right]] - speeds[anchors[left]]
    t = np.where(span != 0, (speeds[between] - speeds[anchors[left]]) / np.where(span != 0, span, 1.0), 0.5)
    error = values - starts[anchors]
    guesses = starts[between] + (1 - t)[:, None] * np.take_along_axis(error[left], at_left, axis=1) \
        + t[:, None] * np.take_along_axis(error[right], at_right, axis=1)
    nearer = np.where((t < 0.5)[:, None], at_left, at_right)
    anchor = np.where(t < 0.5, left, right)
    sure &= np.isfinite(guesses).all(axis=1)
    return between, guesses, shapes[anchor[:, None], nearer], sure


def _matched(roots, others):
    """Each root of ``roots`` (J, k) matched to its nearest in ``others`` (J, k): where (J, k), and
    whether every root of a row is matched unambiguously (J,): the nearest at most ``_MATCH`` of the
    next nearest's distance, and nearest back (one to one)."""
    distance = np.abs(roots[:, :, None] - others[:, None, :])             # (J, k, k)
    nearest = np.argmin(distance, axis=2)
    ordered = np.sort(distance, axis=2)
    second = ordered[:, :, 1] if distance.shape[2] > 1 else np.full(roots.shape, np.inf)
    back = np.argmin(distance, axis=1)                                     # (J, k): the nearest root of each other
    mutual = np.take_along_axis(back, nearest, axis=1) == np.arange(roots.shape[1])
    return nearest, (mutual & (ordered[:, :, 0] <= _MATCH * second)).all(axis=1)


def _lowest_order(lam, want):
    """Where the ``want`` lowest-frequency oscillating roots of each row of ``lam`` are (P, want):
    the oscillating roots by frequency, the others pushed to the end."""
    return np.argsort(frequency_key(lam), axis=-1)[:, :want]



#: a wanted root closer than this times |lam| to another root (or to its conjugate) takes its
#: shape from the full eigen-solve: one inverse-iteration step leaves an error of about its
#: shift (1e-13 |lam|) over that gap
_CLOSE = 1e-4


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


def projected_first(pencils, index, basis):
    """The damping, stiffness and gyroscopic matrices at the first speed of ``index`` projected
    on ``basis`` (n, m): ``W^T D W``, ``W^T K W``, ``W^T G W``, (m, m) each (a large model's by
    products with its sparse matrices)."""
    if scipy.sparse.issparse(pencils.M):
        return pencils.projected(index[0], basis)
    damping0, stiffness0 = (matrix[0] for matrix in pencils.dense(index[:1]))
    Wt = basis.T
    return Wt @ damping0 @ basis, Wt @ stiffness0 @ basis, Wt @ pencils.G @ basis


#: the interpolation's nodes: this many refined speeds around a speed between anchors (cubic in the speed)
_NODES = 4
#: as many nodes as this where the refined speeds allow (quintic): a carried root whose Newton step
#: is then at round-off takes no chord step (``_Pencils.newton_chord``; measured on
#: ``compressor_example`` at 201 speeds, the median start error 1e-12 against 1e-10 with four)
_MOST_NODES = 6
#: speed-dependent entries within this share of their largest over the sweep from the straight line
#: through the neighbouring speeds' are affine in the speed there (a bearing's table between its
#: speeds, :func:`_affine_pieces`)
_AFFINE = 1e-9


class _Expansions:
    """The projected pencils' eigen-decompositions at some anchors, and what they tell of the other
    speeds (``docs/theory.md`` section 17, "Speeds between anchors").

    At each anchor ``a`` (``solved``) the projected state matrix ``A_a`` (``2m`` square) is solved by
    ``eig``: its roots ``Lambda``, unit eigenvectors ``V``; the ``want`` lowest oscillating roots and
    their vectors start Newton's iteration there (``starts`` (A, want), ``vectors`` (A, want, n)). At
    another speed ``j``, ``V^-1 A_j V = Lambda + F_j`` with
    ``F_j = -V^-1 [0; I] (dK V_top + dD V_bottom)``: ``dD = dOmega W^T G W + W^T dC_b W``,
    ``dK = W^T dK_b W`` (the bearings' entries: a product of rank at most their number). For each
    speed ``j`` of ``levels``, with ``a`` the nearer anchor: the Gershgorin discs of ``Lambda + F_j``
    (``centers``, ``radii``, (J, 2m); each radius plus its row's share of the decomposition's own
    error ``V^-1 A_a V - Lambda``, at most ``|V^-1| |A_a V - V Lambda|`` summed), and for each root ``k`` followed from ``a`` the second-order change of its projected
    root, ``F_kk + sum_l F_kl F_lk / (lambda_k - lambda_l)``, at the speed (``changes`` (J, want)) and
    at the ``q`` refined speeds around it (``node_changes`` (J, q, want); ``q`` from ``_NODES`` up to
    ``_MOST_NODES``, within the speed's piece of the bearing tables where it holds them, :func:`_around`).

    Parameters
    ----------
    pencils : _Pencils
    basis : ndarray, shape (n, m)
    solved : ndarray of int, shape (A,)
        The anchors, ascending (the first speed and the last among them).
    want : int
    levels : list of (ndarray of int, ndarray of int)
        The other speeds, in the order they are refined, each part with the refined speeds its
        nodes are taken from (ascending).
    eigen : dict, optional
        The anchors' ``eig`` (roots (2m,), eigenvectors (2m, 2m)) by speed: those found there are
        taken, not solved again (the state matrices are the same bits where ``solved[0]`` is:
        :func:`_state_matrices` is relative to it), with their products (:func:`_decomposition`).
        Without ``nodes`` (the pilot) those solved here are added; with (the main pass) those
        taken are removed as they are used, so the dict holds no more than the pilot's anchors, and
        none once the main pass is made (``_lowest._PILOT_BYTES`` bounds them).
    nodes : bool
        Make the roots' changes at the nodes (``node_changes``); without, only the discs and the
        changes at the speeds (:func:`._lowest._solved_levels`' pilot).

    Attributes
    ----------
    between : ndarray of int, shape (J,)
        The speeds of ``levels``, in turn.
    near : ndarray of int, shape (J,)
        The nearer anchor (a place in ``solved``).
    nodes : ndarray of int, shape (J, q); weights : ndarray, shape (J, q)
        The refined speeds around each speed and the Lagrange weights of the speed among theirs.
    """

    def __init__(self, pencils, basis, solved, want, levels, eigen=None, nodes=True):
        speeds = pencils.speeds
        self.eigen, self.at_nodes = eigen, nodes
        n, m = basis.shape
        count, two = len(solved), 2 * basis.shape[1]
        self.solved, self.speeds = solved, speeds
        self.between = np.concatenate([part for part, _ in levels]).astype(int)
        right = np.clip(np.searchsorted(solved, self.between), 1, count - 1)
        left = right - 1
        span = speeds[solved[right]] - speeds[solved[left]]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(span != 0, (speeds[self.between] - speeds[solved[left]]) / span, 0.5)
        self.near = np.where(t < 0.5, left, right)
        q = min([_MOST_NODES] + [len(grid) for _, grid in levels])
        self.pieces = pieces = _affine_pieces(speeds, np.hstack([pencils.kb, pencils.cb]))
        self.nodes = np.concatenate([_around(grid, part, q, pieces) for part, grid in levels]).reshape(
            len(self.between), q)
        at = speeds[self.nodes]                                                      # (J, q)
        self.weights = _lagrange_weights(at, speeds[self.between])
        # the ``_NODES`` of them nearest each speed (columns, (J, p)): a speed whose roots cannot be
        # followed to the farther ones takes these (:meth:`narrowed`)
        p = min(q, _NODES)
        first = np.clip(np.sum(at < speeds[self.between][:, None], axis=1) - p // 2, 0, q - p)
        self.inner = first[:, None] + np.arange(p)
        self.starts = np.empty((count, want), complex)
        self.vectors = np.empty((count, want, n), complex)
        J = len(self.between)
        self.centers, self.radii = np.full((J, two), np.nan + 0j), np.full((J, two), np.nan)
        self.changes = np.full((J, want), np.nan + 0j)
        self.node_changes = np.full((J, q, want), np.nan + 0j)
        self._solve(pencils, basis, want)

    def narrowed(self):
        """These expansions with each speed's nodes the ``_NODES`` nearest it of its ``q`` (``inner``):
        ``nodes``, ``node_changes`` and ``weights`` taken at them, the rest shared; made once (after
        :meth:`_solve`)."""
        if self.__dict__.get("_narrowed") is not None:
            return self._narrowed
        if self.inner.shape[1] == self.nodes.shape[1]:
            return self
        view = copy.copy(self)
        view.nodes = np.take_along_axis(self.nodes, self.inner, axis=1)
        view.node_changes = np.take_along_axis(self.node_changes, self.inner[..., None], axis=1)
        view.weights = _lagrange_weights(self.speeds[view.nodes], self.speeds[self.between])
        view.inner = np.broadcast_to(np.arange(self.inner.shape[1]), self.inner.shape)      # all of its own
        self._narrowed = view
        return view

    def _solve(self, pencils, basis, want):
        """``eig`` at the anchors, a part of them at a time, and the speeds nearer each."""
        m, solved = basis.shape[1], self.solved
        D0, K0, Gr = projected_first(pencils, solved, basis)
        left, right = basis[pencils.rows].T, basis[pencils.cols]
        self.pencils, self.first = pencils, (D0, K0, Gr, left, right)
        entries = _BearingEntries.of(pencils)
        # a part of the anchors at a time: their state matrices, eigenvectors, inverses and products
        for part in _batches.chunk_slices(len(solved), 16 * 8 * (2 * m) ** 2, budget=_batches._PART_BYTES):
            A = _state_matrices(pencils, solved[part], solved[0], D0, K0, Gr, left, right)
            lam, V = self._eig(A, solved[part])
            order = _lowest_order(lam, want)
            self.starts[part] = np.take_along_axis(lam, order, axis=1)
            shapes = np.take_along_axis(V, order[:, None, :], axis=2)[:, :m]           # (P, m, want)
            self.vectors[part] = _vectors.unit_rows(np.swapaxes(shapes, 1, 2) @ basis.T)
            # each anchor's decomposition and the speeds nearer it: in threads (numpy's products release the GIL)
            work = functools.partial(self._decomposed, pencils, basis, Gr, entries)
            _batches._threaded(work, np.arange(part.start, part.stop), A, lam, V, order, item_bytes=80 * (2 * m) ** 2)

    def _eig(self, A, at):
        """``eig`` of the state matrices ``A`` (P, 2m, 2m) of the anchors ``at`` (P,): roots (P, 2m)
        and eigenvectors (P, 2m, 2m), those in ``eigen`` taken from it, the others solved (and kept
        there)."""
        known = np.array([self.eigen is not None and int(a) in self.eigen for a in at], bool)
        if not known.any():
            lam, V = _batches._threaded(np.linalg.eig, A, item_bytes=48 * A.shape[-1] ** 2)
        else:
            lam, V = np.empty(A.shape[:2], complex), np.empty(A.shape, complex)
            for place in np.nonzero(known)[0]:
                lam[place], V[place] = self.eigen[int(at[place])][:2]
            if not known.all():
                lam[~known], V[~known] = _batches._threaded(np.linalg.eig, A[~known], item_bytes=48 * A.shape[-1] ** 2)
        if self.eigen is not None and not self.at_nodes:        # the pilot's, for the main pass
            for place, a in enumerate(at):
                self.eigen.setdefault(int(a), (lam[place], V[place]))
        return lam, V

    def _decomposed(self, pencils, basis, Gr, entries, places, A, lam, V, order):
        """:meth:`_near` of the anchors ``places`` (P,) from their state matrices ``A`` (P, 2m, 2m),
        roots ``lam`` (P, 2m), eigenvectors ``V`` (P, 2m, 2m) and wanted roots ``order`` (P, want):
        (P,) bool, whether each was decomposed (False: a defective anchor, whose nearer speeds take
        their own roots). Each anchor's numbers are its own, whichever anchors share the call; an
        anchor's products (:func:`_decomposition`) are taken from ``eigen`` where they are there."""
        at = self.solved[places]
        kept = {} if self.eigen is None else self.eigen
        # the main pass takes the pilot's anchors out of ``eigen`` as it uses them: the pilot's are held no longer
        held = [kept.get(int(a), ()) if not self.at_nodes else kept.pop(int(a), ()) for a in at]
        parts = [entry[2] if len(entry) > 2 else None for entry in held]
        new = np.array([part is None for part in parts], bool)
        if new.any():
            made = iter(_decomposition(basis, Gr, entries, A[new], lam[new], V[new]))
            parts = [next(made) if part is None else part for part in parts]
            if self.eigen is not None and not self.at_nodes:
                for a, part in zip(at[new], [part for part, made_here in zip(parts, new) if made_here]):
                    self.eigen[int(a)] = self.eigen[int(a)][:2] + (part,)
        for j, place in enumerate(places):
            if parts[j] is not False:
                error, factors = parts[j]
                self._near(pencils, place, lam[j], order[j], error, list(factors) + [entries])
        return np.array([part is not False for part in parts], bool)

    def _near(self, pencils, place, lam, order, error, factors):
        """The discs and the roots' changes at the speeds nearer the anchor ``place`` and at their
        nodes, from that anchor's decomposition (``error`` (2m,): its rows' error). Where the
        bearings' entries are affine in the speed from the anchor to a speed (:meth:`_affine`),
        ``F`` there is the step times one matrix per piece: the discs and changes are that matrix's
        scaled (its products made once, not at every speed)."""
        rows = np.nonzero(self.near == place)[0]
        if not len(rows):
            return
        anchor = self.solved[place]
        gaps = lam[order][:, None] - lam[None, :]                                   # (want, 2m)
        gaps[np.arange(len(order)), order] = np.inf
        nodes = np.unique(self.nodes[rows]) if self.at_nodes else np.zeros(0, int)
        at = np.concatenate([self.between[rows], nodes])
        unit, which, slack = self._affine(pencils, anchor, at, factors)
        step = pencils.speeds[at] - pencils.speeds[anchor]
        # the unit matrices' discs and second-order terms: a change is ``t F_kk + t^2 sum F_kl F_lk / gap``
        diagonal = np.einsum("gii->gi", unit)
        off = np.abs(unit).sum(axis=2) - np.abs(diagonal)
        along, across = unit[:, order, :], np.swapaxes(unit[:, :, order], 1, 2)
        own = np.take_along_axis(along, order[None, :, None], axis=2)[..., 0]
        square = np.sum(along * across / gaps, axis=2)                                 # (G, want)
        affine, count = which >= 0, len(rows)
        change = np.empty((len(at), len(order)), complex)
        t, g = step[affine], which[affine]
        change[affine] = t[:, None] * own[g] + (t ** 2)[:, None] * square[g]
        here = affine[:count]
        t, g = step[:count][here], which[:count][here]
        self.centers[rows[here]] = lam + t[:, None] * diagonal[g]
        self.radii[rows[here]] = np.abs(t)[:, None] * off[g] + error + slack[:count][here]
        direct = rows[~here]
        if len(direct):
            F = _changed(pencils, self.between[direct], anchor, factors)            # (R, 2m, 2m)
            diagonal = np.einsum("xii->xi", F)
            self.centers[direct] = lam + diagonal
            self.radii[direct] = np.abs(F).sum(axis=2) - np.abs(diagonal) + error
            change[np.nonzero(~here)[0]] = _second_order(F[:, order, :], np.swapaxes(F[:, :, order], 1, 2),
                                                          order, gaps)
        self.changes[rows] = change[:count]
        if not self.at_nodes:
            return
        others = np.nonzero(~affine[count:])[0]
        if len(others):
            along, across = _changed(pencils, nodes[others], anchor, factors, order)   # F's rows and columns of the roots
            change[count + others] = _second_order(along, across, order, gaps)
        self.node_changes[rows] = change[count:][np.searchsorted(nodes, self.nodes[rows])]

    def _affine(self, pencils, anchor, at, factors):
        """Where ``F`` (:func:`_changed`) at the speeds ``at`` (X,) is the step from the anchor times
        one matrix: the speed's piece (``pieces``, :func:`_affine_pieces`) holds the anchor, so the
        bearings' entries change by the step times the piece's slope (the line through its ends).
        Returns that matrix of each piece (G, 2m, 2m) (``F`` per unit of speed), each speed's piece
        (X,) (-1 where the piece does not hold the anchor: ``F`` made there) and a bound (X, 2m) on
        each row's ``sum_l |F_il - t F'_il|``, the entries' departures from the line (a table's
        round-off; :func:`_affine_pieces` takes entries within ``_AFFINE`` as affine), added to the
        radii: a disc then holds the exact ``F``'s."""
        gyroscopic, lower, stiff, damp, entries = factors
        speeds = pencils.speeds
        first, last = self.pieces[at, 0], self.pieces[at, 1]
        inside = (first <= anchor) & (anchor <= last) & (speeds[last] > speeds[first])
        span = (speeds[last] - speeds[first])[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            slope_k = (pencils.kb[last] - pencils.kb[first]) / span              # (X, e): each speed's piece's
            slope_c = (pencils.cb[last] - pencils.cb[first]) / span
        step = (speeds[at] - speeds[anchor])[:, None]
        off_k = np.abs(pencils.kb[at] - pencils.kb[anchor] - step * slope_k)
        off_c = np.abs(pencils.cb[at] - pencils.cb[anchor] - step * slope_c)
        # a piece of the whole sweep may be coefficients smooth in the speed, not affine (a journal
        # bearing's): a speed whose entries leave the line by more than ``_AFFINE`` takes ``F`` whole
        with np.errstate(invalid="ignore"):
            inside &= (off_k <= _AFFINE * np.max(np.abs(pencils.kb), axis=0, initial=0.0)).all(axis=1) \
                & (off_c <= _AFFINE * np.max(np.abs(pencils.cb), axis=0, initial=0.0)).all(axis=1)
        which = np.full(len(at), -1)
        # pieces by both ends (speeds left out of every piece take the whole sweep's, which may share a first speed)
        keys, place, which[inside] = np.unique((first * len(speeds) + last)[inside], return_index=True,
                                               return_inverse=True)
        at_key = np.nonzero(inside)[0][place]                                  # a speed of each piece
        unit = _changed_by(np.ones(len(keys)), slope_k[at_key], slope_c[at_key], factors)    # (G, 2m, 2m)
        slack = np.zeros((len(at), lower.shape[0]))
        if len(pencils.rows) and inside.any():
            # sum_l |dK_e V_top + dC_e V_bottom| of each entry's row of the factors, by the entries' rows
            size_k = np.abs(stiff).sum(axis=1)[entries.column]                   # (r, q)
            size_c = np.abs(damp).sum(axis=1)[entries.column]
            terms = np.where(entries.used, off_k[inside][:, entries.entry] * size_k
                             + off_c[inside][:, entries.entry] * size_c, 0.0)
            slack[inside] = terms.sum(axis=2) @ np.abs(lower).T                  # (X', 2m)
        return unit, which, slack


def _decomposition(basis, Gr, entries, A, lam, V):
    """The products of anchors' decompositions that :meth:`_Expansions._near` takes, from their state
    matrices ``A`` (P, 2m, 2m), roots ``lam`` (P, 2m) and eigenvectors ``V`` (P, 2m, 2m): for each
    anchor, its rows' error (2m,) and the factors of :func:`_changed`, or False where ``V`` is
    singular (a defective anchor). Each anchor's numbers are its own, whichever share the call."""
    m = basis.shape[1]
    try:
        inverse = np.linalg.inv(V)
        done = np.ones(len(V), bool)
    except np.linalg.LinAlgError:            # each alone: only a defective anchor is left out
        inverse, done = np.empty(V.shape, complex), np.zeros(len(V), bool)
        for at in range(len(V)):
            try:
                inverse[at], done[at] = np.linalg.inv(V[at]), True
            except np.linalg.LinAlgError:
                pass
        A, lam, V, inverse = A[done], lam[done], V[done], inverse[done]
    # the decomposition's own error R_a = V^-1 (A V - V Lambda): each row's sum of moduli at most
    # |V^-1| |A V - V Lambda| summed (added to the discs' radii)
    error = np.abs(A @ V - V * lam[:, None, :]).sum(axis=2)
    error = np.einsum("pij,pj->pi", np.abs(inverse), error)
    lower = inverse[:, :, m:]                                               # V^-1 [0; I], (P, 2m, m)
    # the bearings' entries by their distinct rows and columns (a bearing's 2 x 2 block: half as many)
    at_rows, at_cols = basis[entries.rows].T, basis[entries.cols]
    factors = (lower @ Gr @ V[:, m:], lower @ at_rows, at_cols @ V[:, :m], at_cols @ V[:, m:])
    out, j = [], 0
    for ok in done:
        out.append((error[j], tuple(f[j] for f in factors)) if ok else False)
        j += int(ok)
    return out


def _lagrange_weights(at, x):
    """The Lagrange weights (J, q) of the points ``x`` (J,) among their nodes ``at`` (J, q)."""
    q = at.shape[1]
    weights = np.ones(at.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        for r in range(q):
            other = np.arange(q) != r
            weights[:, r] = np.prod((x[:, None] - at[:, other]) / (at[:, [r]] - at[:, other]), axis=1)
    return weights


def _second_order(along, across, order, gaps):
    """The second-order changes ``F_kk + sum_l F_kl F_lk / (lambda_k - lambda_l)`` (X, want) of the
    roots ``order`` (want,) from ``F``'s rows ``along`` and columns ``across`` (transposed) at them,
    (X, want, 2m) each, and the roots' gaps (want, 2m), ``inf`` at the root itself."""
    own = np.take_along_axis(along, order[None, :, None], axis=2)[..., 0]
    return own + np.sum(along * across / gaps, axis=2)


def _around(grid, speeds, q, pieces=None):
    """The ``q`` speeds of ``grid`` (ascending, G >= q) around each of ``speeds`` (J,): half on each
    side where there are, (J, q); with ``pieces`` (S, 2) (:func:`_affine_pieces`), all in the
    speed's piece where it holds ``q`` of them (the roots are smooth in the speed within a piece, a
    bearing table's knot bends them: an interpolation across it left starts off by 1e-7)."""
    first = np.clip(np.searchsorted(grid, speeds) - q // 2, 0, len(grid) - q)
    if pieces is not None:
        low = np.searchsorted(grid, pieces[speeds, 0])                  # the piece's first node
        high = np.searchsorted(grid, pieces[speeds, 1], side="right")   # past its last
        inside = high - low >= q
        first[inside] = np.minimum(np.maximum(first[inside], low[inside]), high[inside] - q)
    return grid[first[:, None] + np.arange(q)]


def _affine_pieces(speeds, entries):
    """The first and last speed (places in the sweep) of the piece each speed lies in, (S, 2): the
    sweep cut where the speed-dependent entries ``entries`` (S, e) bend (a bearing's coefficients
    interpolated linearly in a table of speeds: a knot), each piece a run of speeds over which every
    entry is affine in the speed (within ``_AFFINE``). A speed at a knot ends the piece before it,
    speeds between two close knots lie in the whole sweep's, as every speed where the entries bend
    at most speeds (coefficients that are smooth in the speed, not tabulated) or are constant."""
    S = len(speeds)
    out = np.tile([0, S - 1], (S, 1))
    if S < 3 or not entries.shape[1]:
        return out
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((speeds[1:-1] - speeds[:-2]) / (speeds[2:] - speeds[:-2]))[:, None]
        line = (1 - t) * entries[:-2] + t * entries[2:]
        bent = ~(np.abs(entries[1:-1] - line) <= _AFFINE * np.max(np.abs(entries), axis=0)).all(axis=1)
    if not bent.any() or 2 * bent.sum() > len(bent):
        return out
    places = np.nonzero(bent)[0] + 1
    breaks = np.nonzero(np.diff(places) > 1)[0]
    ends = np.append(places[np.r_[0, breaks + 1]], S - 1)                 # a run of bent speeds ends the piece before
    starts = np.insert(places[np.r_[breaks, len(places) - 1]], 0, 0)      # and starts the one after at its last
    out[:] = -1
    for start, end in zip(starts[::-1], ends[::-1]):                      # a knot's speed in the piece before it
        out[start:end + 1] = start, end
    out[out[:, 0] < 0] = 0, S - 1
    return out


def _state_matrices(pencils, index, base, D0, K0, Gr, left, right):
    """The projected state matrices ``[[0, I], [-W^T K W, -W^T D W]]`` at the speeds ``index`` (P, 2m, 2m)
    from the projected pencil at the speed ``base`` (``D0``, ``K0``), ``W^T G W`` and the bearings'
    entries' rows of the basis (``left`` (m, e), ``right`` (e, m)), as :func:`_projected_starts`."""
    m = D0.shape[0]
    D = D0 + (pencils.speeds[index] - pencils.speeds[base])[:, None, None] * Gr
    Kr = np.broadcast_to(K0, D.shape)
    if len(pencils.rows):
        D = D + (left[None] * (pencils.cb[index] - pencils.cb[base])[:, None, :]) @ right
        Kr = Kr + (left[None] * (pencils.kb[index] - pencils.kb[base])[:, None, :]) @ right
    A = np.zeros((len(D), 2 * m, 2 * m))
    A[:, :m, m:] = np.eye(m)
    A[:, m:, :m] = -Kr
    A[:, m:, m:] = -D
    return A


class _BearingEntries(typing.NamedTuple):
    """The speed-dependent bearings' entries (``pencils.rows``, ``pencils.cols``, (e,) each) by
    their distinct rows (r,) and columns (c,), ascending: a bearing's 2 x 2 block has two rows and
    two columns for its four entries, so ``W^T dK_b W`` is a product through ``r``, not ``e``,
    terms (:func:`_changed`). Each row's entries are padded to the most any row has (``q``): an
    entry ``e`` (a zero coefficient where a row has fewer)."""

    rows: np.ndarray           # (r,) the distinct rows
    cols: np.ndarray           # (c,) the distinct columns
    entry: np.ndarray          # (r, q) each row's entries (any, where ``used`` is False)
    column: np.ndarray         # (r, q) their columns' places in ``cols``
    used: np.ndarray           # (r, q) bool: a real entry

    @classmethod
    def of(cls, pencils):
        rows, row_of = np.unique(pencils.rows, return_inverse=True)
        cols, col_of = np.unique(pencils.cols, return_inverse=True)
        by_row = np.argsort(row_of, kind="stable")
        counts = np.bincount(row_of, minlength=len(rows))
        q = int(counts.max(initial=0))
        slot = np.arange(len(by_row)) - np.repeat(np.cumsum(counts) - counts, counts)
        entry, used = np.zeros((len(rows), q), int), np.zeros((len(rows), q), bool)
        entry[row_of[by_row], slot], used[row_of[by_row], slot] = by_row, True
        return cls(rows, cols, entry, col_of[entry], used)


def _changed(pencils, at, anchor, factors, order=None):
    """``F = V^-1 (A_j - A_a) V`` at the speeds ``at`` (X,) from the anchor's decomposition:
    ``factors`` = (``V^-1 [0; I] W^T G W V_bottom``, ``V^-1 [0; I] W^T`` at the bearings' distinct
    rows (2m, r), ``W`` at their distinct columns times ``V_top`` and ``V_bottom`` (c, 2m) each, and
    their :class:`_BearingEntries`). (X, 2m, 2m); with ``order`` (k,) its rows and columns
    (transposed) at those roots only, (X, k, 2m) each."""
    return _changed_by(pencils.speeds[at] - pencils.speeds[anchor], pencils.kb[at] - pencils.kb[anchor],
                       pencils.cb[at] - pencils.cb[anchor], factors, order)


def _changed_by(step, dk, dc, factors, order=None):
    """:func:`_changed` of the changes ``step`` (X,) [rad/s] of the speed and ``dk``, ``dc`` (X, e) of
    the bearings' entries (``pencils.kb``, ``pencils.cb``)."""
    gyroscopic, lower, stiff, damp, entries = factors
    step = np.asarray(step)[:, None, None]
    if dk.shape[1]:
        # dK_b V_top + dC_b V_bottom on the bearings' distinct rows, (X, r, 2m): each row's entries in turn
        dk = np.where(entries.used, dk[:, entries.entry], 0.0)
        dc = np.where(entries.used, dc[:, entries.entry], 0.0)
        rows = dk[:, :, 0, None] * stiff[entries.column[:, 0]] + dc[:, :, 0, None] * damp[entries.column[:, 0]]
        for j in range(1, entries.entry.shape[1]):
            rows += dk[:, :, j, None] * stiff[entries.column[:, j]] + dc[:, :, j, None] * damp[entries.column[:, j]]
    if order is None:
        F = -step * gyroscopic
        if dk.shape[1]:
            F -= lower @ rows
        return F
    along, across = -step * gyroscopic[order], -step * gyroscopic[:, order].T
    if dk.shape[1]:
        along = along - lower[order] @ rows
        across = across - np.swapaxes(lower @ rows[:, :, order], 1, 2)
    return along, across


def _at_nodes(expansions, rows, values, ok):
    """Where each root followed from the nearer anchor is among the refined roots of the nodes of
    the speeds ``expansions.between[rows]``: the one nearest the anchor's root plus its change to
    the node (at most ``_MATCH`` of the distance to the next nearest, one to one), (R, q, want); and
    whether every root of a speed is found so at nodes that converged (``ok`` (S,)), (R,)."""
    ex = expansions
    nodes, changes = ex.nodes[rows], ex.node_changes[rows]                         # (R, q), (R, q, want)
    want = changes.shape[2]
    anchor = ex.solved[ex.near[rows]]
    predicted = values[anchor][:, None, :] + changes                                 # the roots at the nodes
    distance = np.abs(predicted[..., None] - values[nodes][:, :, None, :])          # (R, q, want, want)
    found = np.argmin(distance, axis=3)
    ordered = np.sort(distance, axis=3)
    second = ordered[..., 1] if want > 1 else np.full(found.shape, np.inf)
    own = nodes == anchor[:, None]
    found = np.where(own[..., None], np.arange(want), found)
    with np.errstate(invalid="ignore"):
        clear = own[..., None] | (ordered[..., 0] <= _MATCH * second)
    ranked = np.sort(found, axis=2)
    sure = clear.all(axis=(1, 2)) & (ranked[..., 1:] != ranked[..., :-1]).all(axis=(1, 2)) & ok[nodes].all(axis=1)
    return found, sure


def _interpolated_shapes(expansions, rows, shapes, found, which=None):
    """The start vectors (R, k, n) of the speeds ``expansions.between[rows]``: the shapes of their
    nodes' roots ``found`` (R, q, want) (of the anchor's roots ``which`` (R, k), default all),
    each turned to the phase of the nearest node's (``x_q (x_q^H x_c) / |x_q^H x_c|``) and
    interpolated in the speed with the roots' Lagrange weights. A shape changes smoothly with the
    speed, so the interpolated vector is off by about the fourth power of the nodes' spacing where
    the nearest node's shape alone is off by its first; the error Newton's first step leaves grows
    with the start vector's (measured on ``compressor_example`` at 201 speeds: with the nearest
    node's shape 327 of 2,275 roots failed the chord step's test and took Newton's iteration, with
    the interpolated vector none)."""
    ex = expansions
    nodes = ex.nodes[rows]
    closest = np.argmin(np.abs(ex.speeds[nodes] - ex.speeds[ex.between[rows]][:, None]), axis=1)
    at = np.arange(len(rows))
    place = found if which is None else np.take_along_axis(found, which[:, None, :], axis=2)   # (R, q, k)
    nearest = shapes[nodes[at, closest][:, None], place[at, closest]]                         # (R, k, n)
    out, conjugate = np.zeros(nearest.shape, complex), np.empty(nearest.shape, complex)
    for r in range(nodes.shape[1]):
        shape = shapes[nodes[:, r][:, None], place[:, r]]                  # a copy: scaled in place
        turn = np.einsum("rki,rki->rk", np.conjugate(shape, out=conjugate), nearest)
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.where(np.abs(turn) > 0, turn / np.abs(turn), 1.0)
        out += np.multiply((ex.weights[rows, r][:, None] * turn)[..., None], shape, out=shape)
    lost = ~np.isfinite(out).all(axis=2)
    out[lost] = nearest[lost]
    return out


def _expansion_guesses(expansions, rows, values, shapes, ok):
    """Newton's starts at the speeds ``expansions.between[rows]`` from the refined roots of their
    nodes and the projected roots' changes (:class:`_Expansions`): for each root followed from the
    nearer anchor, ``g = root - change`` at the ``q`` refined speeds around the speed (:class:`_Expansions`'
    ``nodes``, :func:`_at_nodes`), interpolated in the speed (Lagrange, up to quintic), plus the change at the speed;
    its vector the nodes' shapes interpolated (:func:`_interpolated_shapes`). A speed where a root
    cannot be followed to every node, or a node failed, is not ``sure``.

    Parameters
    ----------
    expansions : _Expansions
    rows : ndarray of int, shape (R,)
        Places in ``expansions.between``.
    values : ndarray, shape (S, want), complex; shapes : ndarray, shape (S, want, n), complex
        Refined at the nodes of ``rows``, the anchors' in their starts' order.
    ok : ndarray of bool, shape (S,)

    Returns
    -------
    guesses : ndarray, shape (R, want), complex; vectors : ndarray, shape (R, want, n), complex
    sure : ndarray of bool, shape (R,)
    """
    ex = expansions
    want = values.shape[1]
    guesses, sure = np.empty((len(rows), want), complex), np.empty(len(rows), bool)
    vectors = np.empty((len(rows), want, shapes.shape[2]), complex)
    for part in _batches.chunk_slices(len(rows), 64 * ex.nodes.shape[1] * want * want, budget=_batches._PART_BYTES):
        sure[part] = _guesses_into(ex, rows, part, values, shapes, ok, guesses, vectors)
    # the speeds whose roots cannot be followed to the farther of more than ``_NODES`` nodes: the nearest
    # ``_NODES`` (measured: at 101 speeds, 5 of the first 13 speeds with six nodes)
    again = np.nonzero(~sure)[0]
    if len(again) and ex.nodes.shape[1] > _NODES:
        sure[again] = _guesses_into(ex.narrowed(), rows, again, values, shapes, ok, guesses, vectors)
    sure &= np.isfinite(guesses).all(axis=1)
    return guesses, vectors, sure


def _guesses_into(ex, rows, part, values, shapes, ok, guesses, vectors):
    """:func:`_expansion_guesses` of the rows ``rows[part]``, written into ``guesses`` and
    ``vectors`` at ``part``; whether each is sure (:func:`_at_nodes`)."""
    at = rows[part]
    found, sure = _at_nodes(ex, at, values, ok)
    nodes, changes = ex.nodes[at], ex.node_changes[at]
    guesses[part] = np.einsum("jq,jqk->jk", ex.weights[at], values[nodes[..., None], found] - changes) \
        + ex.changes[at]
    # the vectors from the nearest ``_NODES`` of the nodes: as good a start (measured on compressor_example at
    # 201 speeds, the same share of roots whose Newton step is at round-off) at two thirds of the work
    inner = ex.inner[at][..., None]
    vectors[part] = _interpolated_shapes(ex.narrowed(), at, shapes, np.take_along_axis(found, inner, axis=1))
    return sure


def _projected_guesses(expansions, rows, values, shapes, ok):
    """Newton's starts at the speeds ``expansions.between[rows]`` whose nodes are anchors (solved
    whole): their own projected roots (the ``want`` lowest of one batched ``eigvals``), each plus its
    projection error at the nodes (refined less projected root), interpolated in the speed: the
    projected root's root at the nearer anchor is the one whose root plus change to the speed is
    nearest it (``_MATCH``, one to one), followed to the other nodes by :func:`_at_nodes`.

    Returns
    -------
    guesses : ndarray, shape (R, want), complex; vectors : ndarray, shape (R, want, n), complex
    sure : ndarray of bool, shape (R,)
    projected : ndarray, shape (R, want), complex
        The projected roots, by frequency (the starts of :func:`._lowest._unmissed`).
    """
    ex = expansions
    found, sure = _at_nodes(ex, rows, values, ok)
    want = found.shape[2]
    A = _state_matrices(ex.pencils, ex.between[rows], ex.solved[0], *ex.first)
    lam = _batches._threaded(np.linalg.eigvals, A, item_bytes=24 * A.shape[-1] ** 2)
    projected = np.take_along_axis(lam, _lowest_order(lam, want), axis=1)
    predicted = ex.starts[ex.near[rows]] + ex.changes[rows]                        # the anchor's roots, carried
    distance = np.abs(projected[:, :, None] - predicted[:, None, :])              # (R, want, want)
    which = np.argmin(distance, axis=2)
    ordered = np.sort(distance, axis=2)
    second = ordered[..., 1] if want > 1 else np.full(which.shape, np.inf)
    ranked = np.sort(which, axis=1)
    with np.errstate(invalid="ignore"):
        sure &= (ordered[..., 0] <= _MATCH * second).all(axis=1) & (ranked[:, 1:] != ranked[:, :-1]).all(axis=1)
    nodes = ex.nodes[rows]
    place = np.searchsorted(ex.solved, nodes)                                       # the nodes are anchors
    error = values[nodes[..., None], found] - ex.starts[place[..., None], found]    # (R, q, want)
    carried = np.einsum("jq,jqk->jk", ex.weights[rows], error)
    guesses = projected + np.take_along_axis(carried, which, axis=1)
    sure &= np.isfinite(guesses).all(axis=1)
    return guesses, _interpolated_shapes(ex, rows, shapes, found, which), sure, projected
