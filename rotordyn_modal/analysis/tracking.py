"""Mode tracking across a speed sweep by mode-shape correlation.

Between neighbouring speeds the assignment is the one that maximises the
mass-weighted MAC, with the eigenvalue distance as a tie-breaker. Most steps
are unambiguous (each mode's best match is distinct and close to 1) and are
resolved in one vectorised pass. The rest (degenerate points such as the
zero-speed double roots of a symmetric machine, coarse steps through a
veering) are solved one by one with an optimal assignment against the last
unambiguous shape of each mode and a linear extrapolation of its eigenvalue,
so a mode keeps its label through crossings and through points where its
shape is not defined. Before that assignment, each root that plainly continues
a mode (the one root of its nature, mode, overdamped pair or real root, of a
sure MAC with it, and near its extrapolated eigenvalue) keeps it, and so does
each root that stands still (a relaxation root of Maxwell branches, many times
over, its shapes any basis of its eigenspace): where the set of kept roots
changes (two real roots meeting into a pair, a root entering or leaving the
kept half), only the roots left over are assigned.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from ._batches import chunk_slices

from ._vectors import mac_matrix
from .modal import is_oscillating

__all__ = ["track_modes", "track_modes_many", "doubtful_steps"]

_CONFIDENT_MAC = 0.8
_EIGEN_WEIGHT_RELATIVE = 0.02


def track_modes(eigenvalues: np.ndarray, shapes: np.ndarray, speeds=None) -> np.ndarray:
    """Order that follows each mode across speeds.

    Parameters
    ----------
    eigenvalues : ndarray, shape (N, n), complex
    shapes : ndarray, shape (N, n, d), complex
        Unit-norm (mass-weighted) shapes.
    speeds : ndarray, shape (N,), optional
        The speeds (or any parameter) of the rows, increasing: a mode's eigenvalue is extrapolated
        linearly in them over an unsure step. Default: equally spaced.

    Returns
    -------
    ndarray of int, shape (N, n)
        ``order[k, label]`` is the index, at speed k, of the mode called ``label``;
        labels are numbered by ascending frequency at the first speed.
    """
    return track_modes_many(eigenvalues[None], shapes[None], speeds)[0]


def track_modes_many(eigenvalues: np.ndarray, shapes: np.ndarray, speeds=None) -> np.ndarray:
    """:func:`track_modes` for the sweeps of several variants at once.

    Parameters
    ----------
    eigenvalues : ndarray, shape (V, N, n), complex
    shapes : ndarray, shape (V, N, n, d), complex
    speeds : ndarray, shape (N,), optional
        As for :func:`track_modes` (the same for every variant).

    Returns
    -------
    ndarray of int, shape (V, N, n)
    """
    variants, count, n = eigenvalues.shape
    order = np.empty((variants, count, n), dtype=int)
    order[:, 0] = np.arange(n)
    if count == 1:
        return order
    best, kept, confident = _steps(shapes)
    events = (~kept.all(axis=0)).nonzero()[0] + 1
    if not len(events):                       # every mode in place all along (the usual small model)
        order[:, 1:] = order[:, :1]
        return order
    confident = confident[:, events - 1]                                                # (V, n_events)
    last_good = np.zeros((variants, n), dtype=int)  # last speed at which each label's shape was sure
    rows = np.arange(variants)[:, None]
    previous = 0
    for event, k in enumerate(events):
        order[:, previous + 1:k] = order[:, previous, None]
        if k - 1 > previous:
            last_good[:] = k - 1
        order[:, k] = best[:, k - 1][rows, order[:, k - 1]]
        sure_step = confident[:, event]
        last_good[sure_step] = k
        for v in np.nonzero(~sure_step)[0]:
            order[v, k], sure = _ambiguous_step(k, order[v], eigenvalues[v], _of_variant(shapes, v), last_good[v],
                                                _stretch(speeds, k))
            last_good[v, sure] = k
        previous = k
    order[:, previous + 1:] = order[:, previous, None]
    return order


#: the largest part of the MAC matrices between neighbouring speeds (and their complex
#: products, and the weighted shapes of a :class:`._weighted_rows.WeightedRows` read for them)
#: computed at once [bytes]; each step's MAC is its own: the parts change no number
_MAC_BYTES = 8 * 2**20


def _steps(shapes):
    """Each step's matches between neighbouring speeds of shapes (V, N, n, d), the MAC
    matrices a part of the steps at a time (``_MAC_BYTES``: all of them at once would be
    (V, N - 1, n, n), 32 GB for a machine of 2,000 coordinates at 101 speeds).

    Returns
    -------
    best : ndarray of int, shape (V, N-1, n)
        Each mode's best match at the next speed.
    kept : ndarray of bool, shape (V, N-1)
        Every mode's best match is itself, a confident one (the MAC on the diagonal): steps that
        need no work.
    confident : ndarray of bool, shape (V, N-1)
        The other steps' :func:`_confident_steps` (False where ``kept``).
    """
    variants, count, n, d = shapes.shape
    best = np.empty((variants, count - 1, n), dtype=int)
    kept = np.empty((variants, count - 1), dtype=bool)
    confident = np.zeros((variants, count - 1), dtype=bool)
    for part in chunk_slices(count - 1, variants * (40 * n * n + 32 * n * d), budget=_MAC_BYTES):
        both = shapes[:, part.start:part.stop + 1]          # a view, or the weighted rows computed once
        correlation = mac_matrix(both[:, :-1], both[:, 1:])
        mine = best[:, part] = correlation.argmax(axis=-1)
        kept[:, part] = (mine == np.arange(n)).all(axis=-1) & \
            (np.diagonal(correlation, axis1=-2, axis2=-1) > _CONFIDENT_MAC).all(axis=-1)
        events = (~kept[:, part].all(axis=0)).nonzero()[0]
        if len(events):
            confident[:, part.start + events] = _confident_steps(correlation, mine, events)
    return best, kept, confident


def _of_variant(shapes, v):
    """``shapes[v]`` of shapes (V, N, n, d): the array's view, or a :class:`._weighted_rows.WeightedRows`'
    variant read by part (not every speed's weighted shapes at once)."""
    return shapes[v] if isinstance(shapes, np.ndarray) else shapes.variant(v)


def _confident_steps(correlation, best, steps):
    """Whether each variant's step ``steps[e]`` (from speed ``steps[e]`` to the next) is sure:
    every mode's best match is distinct and above the confident MAC.

    Parameters
    ----------
    correlation : ndarray, shape (V, N-1, n, n); best : ndarray of int, shape (V, N-1, n)
    steps : ndarray of int, shape (E,)

    Returns
    -------
    ndarray of bool, shape (V, E)
    """
    n = best.shape[-1]
    distinct = (np.sort(best[:, steps], axis=-1) == np.arange(n)).all(axis=-1)
    return distinct & (correlation[:, steps].max(axis=-1) > _CONFIDENT_MAC).all(axis=-1)


def _stretch(speeds, k):
    """The step to speed k over the step before it (1 where ``speeds`` is None: equal steps), by
    which a mode's last change is extrapolated."""
    if speeds is None or k < 2 or speeds[k - 1] == speeds[k - 2]:
        return 1.0
    return float((speeds[k] - speeds[k - 1]) / (speeds[k - 1] - speeds[k - 2]))


def _ambiguous_step(k, order, eigenvalues, shapes, last_good, stretch=1.0):
    """Optimal assignment at speed k against each mode's last sure shape and trend (its last change
    times ``stretch``, :func:`_stretch`).

    The roots that plainly continue a mode (:func:`_kept_in_place`) keep it first; the others
    are assigned among themselves: where the set of roots changes (two real roots meeting into
    a pair, a root entering or leaving the kept half), only they take the place left."""
    n = eigenvalues.shape[1]
    labels = np.arange(n)
    reference = shapes[last_good, order[last_good, labels]]  # (n, d)
    correlation = mac_matrix(reference, shapes[k])  # (n, n)
    previous = eigenvalues[k - 1, order[k - 1]]
    if k >= 2:
        predicted = 2 * previous - eigenvalues[k - 2, order[k - 2]] if stretch == 1.0 else \
            previous + stretch * (previous - eigenvalues[k - 2, order[k - 2]])
    else:
        predicted = previous
    scale = _EIGEN_WEIGHT_RELATIVE * np.maximum(np.abs(predicted), np.abs(eigenvalues[k]).max() * 1e-3 + 1e-300)
    distance = np.abs(predicted[:, None] - eigenvalues[k][None, :]) / scale[:, None]
    cost = (1.0 - correlation) + distance
    assigned = np.empty(n, dtype=int)
    natures = _nature(previous), _nature(eigenvalues[k])          # asked for twice below
    kept_rows, kept_columns = _kept_in_place(previous, eigenvalues[k], correlation, predicted, natures)
    assigned[kept_rows] = kept_columns
    free_rows, free_columns = _left_over(n, kept_rows), _left_over(n, kept_columns)
    rows, columns = linear_sum_assignment(cost[np.ix_(free_rows, free_columns)])
    assigned[free_rows[rows]] = free_columns[columns]
    _keep_still(assigned, previous, eigenvalues[k], predicted, free_rows, natures)
    local = mac_matrix(shapes[k - 1, order[k - 1]], shapes[k, assigned])
    sure = np.diagonal(local) > _CONFIDENT_MAC
    return assigned, sure


def _left_over(n, taken):
    """The indices of ``range(n)`` not in ``taken``, increasing (``numpy.setdiff1d`` of ``arange(n)``,
    without its sort)."""
    free = np.ones(n, dtype=bool)
    free[taken] = False
    return np.flatnonzero(free)


#: a root continues a mode plainly where its MAC with the mode's shapes is at least this ...
_KEPT_MAC = 0.99
#: ... and it lies within this fraction of |lambda| of the mode's extrapolated eigenvalue
_KEPT_DISTANCE = 0.1


def _kept_in_place(previous, current, correlation, predicted, natures=None):
    """The labels (rows) whose mode plainly continues in one root (columns) at the next speed.

    A root continues a label's mode when, of the roots of the label's nature (:func:`_nature`),
    it alone has a MAC of at least ``_KEPT_MAC`` with the label's last sure shape; when, of the
    labels of its nature, that label alone has; and when it lies within ``_KEPT_DISTANCE``
    times ``|predicted|`` of the label's extrapolated eigenvalue. These are kept before the
    optimal assignment of the others, which weighs each eigenvalue distance relative to its own
    label's |lambda|: where a root enters the kept half (a real root taking the place two real
    roots meeting into a pair left), handing it to the label that lost its root can cost more
    than moving a chain of labels each by one, modes included, however sure each mode's MAC
    with itself.

    Parameters
    ----------
    previous, current : ndarray, shape (n,), complex [1/s]
        Each label's root at the speed before; the roots at the speed.
    correlation : ndarray, shape (n, n)
        MAC of each label's last sure shape (rows) with the roots at the speed (columns).
    predicted : ndarray, shape (n,), complex [1/s]
        Each label's extrapolated eigenvalue at the speed.
    natures : (ndarray, ndarray), optional
        ``_nature(previous)`` and ``_nature(current)``, where the caller has them.

    Returns
    -------
    rows, columns : ndarray of int, shape (p,)
    """
    before, now = (_nature(previous), _nature(current)) if natures is None else natures
    sure = (correlation >= _KEPT_MAC) & (before[:, None] == now[None, :])
    alone = sure & (sure.sum(axis=1) == 1)[:, None] & (sure.sum(axis=0) == 1)[None, :]
    near = np.abs(current[None, :] - predicted[:, None]) <= _KEPT_DISTANCE * np.abs(predicted)[:, None]
    return np.nonzero(alone & near)


#: a root that moved less than this fraction of the speed's largest |lambda| has not moved
#: (round-off of one eigen-solution)
_STILL = 1e-9


def _keep_still(assigned, previous, current, predicted, rows, natures=None):
    """Give back, in ``assigned`` (each label's root at the speed, changed in place), each label
    of ``rows`` whose root stands still a root at that same value.

    A label stands still where its extrapolated eigenvalue is its root at the speed before
    (the root did not move over the last two steps), both to :data:`_STILL` of the largest
    |lambda|. Where the assignment gave it a root elsewhere while a root of its nature at its
    value went to a label that does not stand at that value, the two labels exchange their
    roots. Such roots are a relaxation root of rubber mounts' Maxwell branches, -1/tau, as many
    times as the branches' states: their shapes are any basis of their eigenspace, or none,
    and say nothing, and the assignment, weighing each eigenvalue distance relative to its own
    label's |lambda|, could hand a root entering the kept half (two real roots meeting into a
    pair) to one of their labels and one of them to the label that lost its root.

    Parameters
    ----------
    assigned : ndarray of int, shape (n,)
        Each label's root (column) at the speed.
    previous, current, predicted : ndarray, shape (n,), complex [1/s]
        As for :func:`_kept_in_place`.
    rows : ndarray of int
        The labels assigned (not kept in place).
    natures : (ndarray, ndarray), optional
        As for :func:`_kept_in_place`.
    """
    tolerance = _STILL * max(np.abs(current).max(), np.abs(previous).max())
    still = [int(r) for r in rows if abs(previous[r] - predicted[r]) <= tolerance]
    if not still:
        return
    # (label, column): the root at the label's value, of its nature; every pair at once (the loop
    # below asks for many: at the second speed every label stands still)
    before, now = (_nature(previous), _nature(current)) if natures is None else natures
    at = ((np.abs(current[None, :] - previous[:, None]) <= tolerance) & (before[:, None] == now[None, :])).tolist()

    def at_value(label, column):
        return at[label][column]

    holder = {int(c): int(r) for r, c in zip(rows, assigned[rows])}
    for label in still:
        if at_value(label, assigned[label]):
            continue
        for column, other in holder.items():
            if other != label and at_value(label, column) and not (other in still and at_value(other, column)):
                holder[column], holder[int(assigned[label])] = label, other
                assigned[label], assigned[other] = column, assigned[label]
                break


def _nature(values):
    """0 for real roots, 1 for pairs that do not oscillate (overdamped), 2 for modes
    (:func:`.modal.is_oscillating`); ``values`` (n,) complex. Where two real roots meet into a
    pair, or a mode becomes overdamped, the root changes its nature: it is never kept in place
    (:func:`_kept_in_place`) but assigned."""
    return np.where(is_oscillating(values), 2, (values.imag != 0).astype(int))


def doubtful_steps(eigenvalues: np.ndarray, shapes, order: np.ndarray) -> np.ndarray:
    """The steps of a tracked sweep over which a mode's match is in doubt: a mode (an oscillating
    root, :func:`.modal.is_oscillating`) at one speed whose tracked root at the next is no mode, or
    whose shape there has a MAC of at most :data:`_CONFIDENT_MAC` with its own. A grid too coarse
    for the modes' changes shows so (``journal_rotor.toml`` at 5 speeds from 100 to 20,000 rpm:
    the cylindrical mode at 5,075 rpm was matched with an overdamped root at 10,050 rpm, the mode
    that loses stability with a third label); a finer grid there resolves it
    (:func:`.campbell._tracked`).

    Parameters
    ----------
    eigenvalues : ndarray, shape (V, N, n), complex
    shapes : ndarray or WeightedRows, shape (V, N, n, d)
        Unit (mass-weighted) shapes.
    order : ndarray of int, shape (V, N, n)
        The tracking (:func:`track_modes_many`).

    Returns
    -------
    ndarray of bool, shape (V, N-1)
    """
    variants, count, n = eigenvalues.shape
    doubtful = np.zeros((variants, max(count - 1, 0)), dtype=bool)
    if count < 2:
        return doubtful
    rows = np.arange(variants)[:, None, None]
    tracked = eigenvalues[rows, np.arange(count)[None, :, None], order]
    modes = is_oscillating(tracked)
    for part in chunk_slices(count - 1, variants * 32 * n * shapes.shape[-1], budget=_MAC_BYTES):
        k = np.arange(part.start, part.stop + 1)[None, :, None]
        both = shapes[np.broadcast_to(rows, (variants, len(k[0]), n)), np.broadcast_to(k, (variants, len(k[0]), n)),
                      order[:, part.start:part.stop + 1]]
        mac = np.abs(np.sum(both[:, :-1].conj() * both[:, 1:], axis=-1)) ** 2          # (V, P, n)
        here, there = modes[:, part.start:part.stop], modes[:, part.start + 1:part.stop + 1]
        lost = here & there & (mac <= _CONFIDENT_MAC)
        for v, p, label in zip(*np.nonzero(lost)):
            lost[v, p, label] = not _in_twin_plane(tracked[v, part.start + p], modes[v, part.start + p], both[v, p],
                                                   both[v, p + 1, label], label)
        doubtful[:, part] = (here & ~there | lost).any(axis=-1)
    return doubtful


#: two modes whose eigenvalues agree to this fraction of their size are twins: a repeated root
#: split by round-off or a trace of asymmetry, whose shapes are any basis of their plane
_TWIN_GAP = 1e-5


def _in_twin_plane(values, modes, shapes, following, label) -> bool:
    """Whether the mode ``label`` is one of twins at a speed (:data:`_TWIN_GAP`; ``values`` (n,)
    complex its tracked roots there, ``modes`` (n,) which are modes, ``shapes`` (n, d) their unit
    weighted shapes) and its shape at the next speed, ``following`` (d,), lies in the twins' plane
    (a MAC above :data:`_CONFIDENT_MAC` with it): such a step is no doubt of the tracking, which
    no finer grid could resolve (the shaft's bending pairs of flexible_pump_on_mounts.toml at rest,
    2e-9 to 9e-7 apart)."""
    twins = modes & (np.abs(values - values[label]) <= _TWIN_GAP * np.abs(values[label]))
    if twins.sum() < 2:
        return False
    basis, _ = np.linalg.qr(shapes[twins].T)                      # (d, t), orthonormal columns
    return float(np.linalg.norm(basis.conj().T @ following) ** 2) > _CONFIDENT_MAC
