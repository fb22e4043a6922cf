"""One mode numbering: the number ``modes --speed S`` gives a root, for the tracked modes of a sweep.

A sweep (Campbell diagram, critical speeds, stability) labels each mode once and keeps the
label over its speeds (the number by frequency at the sweep's speed nearest zero); :func:`.modal.modal`
numbers the modes at one speed by frequency. Where frequencies cross, a tracked label and the
number at that speed differ, so the sweeps' tables and lines also give the number at the speed
(``mode_at_speed``): the mode ``modes --speed S --shape N`` draws.
"""

from __future__ import annotations

import numpy as np

from ..linear_system import speed_linear_form
from . import _arnoldi, _batches, _eigensolve, _roots
from ._whirl import about_spin_axis
from .modal import is_oscillating

__all__ = ["numbers_at_speed", "number_of_root", "numbers_at_crossings", "repeated_in_whirl_order"]


def numbers_at_speed(eigenvalues, whirl_about_axis=None) -> np.ndarray:
    """The number :func:`.modal.modal` (and ``modes``) gives each root of one speed.

    Parameters
    ----------
    eigenvalues : array_like, shape (..., m), complex [1/s]
        The upper roots of each speed (one of each conjugate pair), any order.
    whirl_about_axis : array_like, shape (..., m), optional
        Each root's whirl ratio about ``+spin_axis`` (the tables' ratio times the sign of the
        speed): a repeated root's members numbered as ``modes`` lists them, backward first
        (without it, in the order given).

    Returns
    -------
    ndarray of int, shape (..., m)
        1, 2, ... by frequency (then real part) among the roots that are modes at that speed
        (:func:`.modal.is_oscillating`); 0 for the roots that are not modes.
    """
    lam = np.asarray(eigenvalues)
    modes = is_oscillating(lam)
    # the modes first, by frequency then real part: modal's order (its upper roots sorted by
    # imaginary, then real part, the modes numbered in that order; a frequency shared to
    # round-off by modes of different damping: the least damped first, _eigensolve.frequency_order)
    order = _eigensolve.frequency_order(lam, ~modes, whirl_about_axis)
    ranks = np.empty(lam.shape, dtype=int)
    np.put_along_axis(ranks, order, np.broadcast_to(np.arange(lam.shape[-1]), lam.shape), axis=-1)
    return np.where(modes, ranks + 1, 0)


def number_of_root(roots, eigenvalue) -> int:
    """The number ``modes`` gives the root of ``roots`` (one speed's upper roots) nearest
    ``eigenvalue`` [1/s]; 0 when that root is not a mode. A repeated root (the roots within
    ``_eigensolve.REPEATED_TOLERANCE`` of the largest, :func:`._roots.one_root`: an isotropic
    rotor's cylindrical whirl) gives its lowest number, whichever of its copies the solver put
    first; ``modes`` lists its members backward whirl first (:func:`repeated_in_whirl_order`)."""
    roots = np.asarray(roots)
    numbers = numbers_at_speed(roots)
    nearest = int(np.argmin(np.abs(roots - eigenvalue)))
    if not numbers[nearest]:
        return 0
    scale = _eigensolve.REPEATED_TOLERANCE * np.abs(roots[np.isfinite(roots)]).max()
    same = _roots.one_root(roots, roots[nearest], scale) & (numbers > 0)
    return int(numbers[same].min())


def repeated_in_whirl_order(speeds, eigenvalues, whirl_ratios, numbers, modes) -> np.ndarray:
    """Numbers of the members of a repeated root, told apart by their whirl.

    Two tracked modes of one repeated root (an isotropic rotor's cylindrical whirl: one
    frequency, one backward and one forward orbit) cross an order line at one speed, and
    :func:`number_of_root` gives both the root's lowest number. ``modes`` lists a repeated
    root's members by their whirl about ``+spin_axis``, backward first
    (``_eigensolve.resolve_repeated``), so the member of the ``k``-th lowest whirl ratio about the
    axis is that number plus ``k``. The ratios given are relative to the spin, whose sign a
    negative speed reverses (``_whirl.ratios_of_forms``): there the forward whirl comes first.
    Rows of one tracked mode (its crossings of two sources of one speed ratio) keep one number.

    Parameters
    ----------
    speeds : ndarray, shape (P,) [rad/s]
    eigenvalues : ndarray, shape (P,), complex [1/s]
    whirl_ratios : ndarray, shape (P,)
        Relative to the reference rotor's spin (as every table gives them).
    numbers : ndarray of int, shape (P,)
        Each row's number at its speed (0: not a mode).
    modes : ndarray of int, shape (P,)
        Each row's tracked mode (its label): rows of one label are one root.

    Returns
    -------
    ndarray of int, shape (P,): ``numbers``, with those of a repeated root's members spread
    """
    speeds, eigenvalues = np.asarray(speeds, dtype=float), np.asarray(eigenvalues)
    modes, out = np.asarray(modes, dtype=int), np.array(numbers, dtype=int)
    about_axis = about_spin_axis(whirl_ratios, speeds)
    for number in np.unique(out[out > 0]):
        rows = np.flatnonzero(out == number)
        while len(rows) > 1:
            first = rows[0]
            group = rows[(np.abs(speeds[rows] - speeds[first]) <= _SAME_SPEED * np.abs(speeds[first]))
                         & _roots.one_root(eigenvalues[rows], eigenvalues[first],
                                           _eigensolve.REPEATED_TOLERANCE * np.abs(eigenvalues[first]))]
            labels, where = np.unique(modes[group], return_index=True)
            if len(labels) > 1:             # members of one root: each label ranked by its whirl
                rank = np.empty(len(labels), dtype=int)
                rank[np.argsort(about_axis[group[where]], kind="stable")] = np.arange(len(labels))
                out[group] = number + rank[np.searchsorted(labels, modes[group])]
            rows = np.setdiff1d(rows, group)
    return out


#: critical speeds closer than this (relative) are one speed: a repeated root's members' crossings,
#: each refined on its own, agree to round-off
_SAME_SPEED = 1e-9


def numbers_at_crossings(model, sweep_speeds, sweep_eigenvalues, speeds, modes, eigenvalues,
                         progress=False, whirl_ratios=None) -> np.ndarray:
    """The number ``modes --speed`` gives tracked modes at speeds between a sweep's speeds.

    The number is one more than the count of the other roots below the mode's own eigenvalue at
    that speed, each root's frequency there interpolated from the sweep (the same number at both
    grid speeds around the speed is not trusted: two other roots may cross the mode's frequency
    in between in opposite senses)
    (:func:`_counted_below`); only where a root lies too near that frequency for the
    interpolation to tell its side are the roots at the speed solved (the state matrix is built
    only then), all such speeds in one batch.

    Parameters
    ----------
    model : Model
    sweep_speeds : ndarray, shape (N,) [rad/s], increasing
    sweep_eigenvalues : ndarray, shape (N, m), complex, tracked columns
    speeds : ndarray, shape (P,) [rad/s]
    modes : ndarray of int, shape (P,)
        Tracked labels (1-based columns of ``sweep_eigenvalues``).
    eigenvalues : ndarray, shape (P,), complex [1/s]
        The mode's eigenvalue at each speed.
    progress : bool
        A bar (tqdm) over the crossings whose roots are solved (eigenvalues of the state matrix at
        each: about an hour for 20,000 crossings of 800 states).
    whirl_ratios : ndarray, shape (P,), optional
        Each mode's whirl ratio: the members of a repeated root crossing at one speed are then
        numbered as ``modes`` lists them, backward first (:func:`repeated_in_whirl_order`);
        without them they share the root's lowest number.

    Returns
    -------
    ndarray of int, shape (P,); 0 where the root is not a mode at that speed
    """
    sweep_speeds, values = np.asarray(sweep_speeds, dtype=float), np.asarray(sweep_eigenvalues)
    speeds, eigenvalues = np.asarray(speeds, dtype=float), np.asarray(eigenvalues)
    grid = numbers_at_speed(values)
    k = np.clip(np.searchsorted(sweep_speeds, speeds) - 1, 0, max(len(sweep_speeds) - 2, 0))
    column = np.asarray(modes, dtype=int) - 1
    below, above = grid[k, column], grid[np.minimum(k + 1, len(sweep_speeds) - 1), column]
    out = np.where(below == above, below, 0)
    # The same number at both grid speeds does not make it the number in between: two other
    # roots may cross the mode's frequency there in opposite senses (the gear chains of
    # tests/test_large_machine_cli.py did so at 15 % of their crossings), so every crossing is
    # decided by the interpolated roots, or solved.
    rest = np.arange(len(speeds)) if len(sweep_speeds) > 1 else np.nonzero(below == 0)[0]
    if len(rest) and len(sweep_speeds) > 1:
        # a sweep of the lowest roots only (campbell --lowest): the roots left out lie above its columns
        partial = values.shape[-1] < model.dofs.n
        counted, known = _counted_below(sweep_speeds, values, speeds[rest], k[rest], column[rest], eigenvalues[rest],
                                        partial)
        out[rest[known]] = counted[known]
        rest = rest[~known]
    if len(rest):
        out[rest] = _solved_numbers(model, speeds[rest], eigenvalues[rest], values.shape[-1] if partial else None,
                                    progress)
    if whirl_ratios is not None and len(speeds) > 1:
        out = repeated_in_whirl_order(speeds, eigenvalues, whirl_ratios, out, modes)
    return out


#: the largest part of the crossings' interpolated roots computed at once [bytes]
_PART_BYTES = 16 * 2**20
#: a root counts on one side of the mode's frequency only beyond this many times the
#: difference between its cubic and linear interpolations (the cubic's error is far smaller)
_MARGIN = 4.0
#: and beyond this fraction of its travel across the bracket (for a root that veers inside it)
_TRAVEL_MARGIN = 0.25
#: and beyond this fraction of the mode's |eigenvalue| (repeated roots)
_RELATIVE_MARGIN = 1e-8


def _counted_below(sweep_speeds, values, speeds, k, column, eigenvalues, partial=False):
    """The number of each mode at its speed from the sweep's roots interpolated there: one more
    than the count of the other roots that are modes and lie below its eigenvalue (by frequency,
    as :func:`numbers_at_speed` orders them); 0 where its own root is not a mode.

    A root is counted on one side only where its interpolated frequency is farther from the
    mode's than a margin (:data:`_MARGIN` times the cubic's difference from the linear
    interpolation, :data:`_TRAVEL_MARGIN` of its travel across the bracket, :data:`_RELATIVE_MARGIN`
    of the mode's eigenvalue) and it is a mode at both ends of the bracket (or at neither).
    Where the sweep holds the lowest roots only (``partial``), a root it left out lies above its
    columns: the mode's number is told only where some column lies surely above it.

    Returns
    -------
    numbers : ndarray of int, shape (P,)
    known : ndarray of bool, shape (P,)
        Every other root's side told apart (the others' numbers are meaningless).
    """
    count = len(k)
    numbers, known = np.zeros(count, dtype=int), np.zeros(count, dtype=bool)
    own_mode = is_oscillating(eigenvalues)
    m = values.shape[-1]
    step = max(1, _PART_BYTES // (16 * 12 * m))
    for start in range(0, count, step):
        part = slice(start, min(start + step, count))
        estimate, margin, mode_both, mode_neither = _interpolated_roots(sweep_speeds, values, speeds[part], k[part])
        lam = eigenvalues[part]
        margin += _RELATIVE_MARGIN * np.abs(lam)[:, None]
        low = mode_both & (estimate.imag + margin < lam.imag[:, None])
        high = mode_both & (estimate.imag - margin > lam.imag[:, None])
        told = low | high | mode_neither
        rows = np.arange(len(lam))
        told[rows, column[part]], low[rows, column[part]] = True, False
        numbers[part] = np.where(own_mode[part], 1 + low.sum(axis=1), 0)
        known[part] = ~own_mode[part] | (told.all(axis=1) & (high.any(axis=1) | (not partial)))
    return numbers, known


def _interpolated_roots(sweep_speeds, values, speeds, k):
    """Every tracked root of the sweep at ``speeds`` (P,) inside brackets ``k`` (P,): the cubic
    through the four nearest speeds of the sweep, the margin of its frequency (see
    :func:`_counted_below`), and whether it is a mode at both ends of the bracket, or at
    neither. Each (P, m). With fewer than four speeds, or where the root is not a mode at all
    four, the linear interpolation across the bracket, with its whole travel as the margin."""
    ends = values[k[:, None] + np.arange(2)]                                         # (P, 2, m)
    t = ((speeds - sweep_speeds[k]) / (sweep_speeds[k + 1] - sweep_speeds[k]))[:, None]
    linear = (1 - t) * ends[:, 0] + t * ends[:, 1]
    oscillating = is_oscillating(ends)
    travel = np.abs(ends[:, 1] - ends[:, 0])
    if len(sweep_speeds) < 4:
        return linear, travel, oscillating.all(axis=1), ~oscillating.any(axis=1)
    nodes = np.minimum(np.maximum(k - 1, 0), len(sweep_speeds) - 4)[:, None] + np.arange(4)         # (P, 4)
    xs, near = sweep_speeds[nodes], values[nodes]                                                   # (P, 4, m)
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = (speeds[:, None, None] - xs[:, None, :]) / (xs[:, :, None] - xs[:, None, :])
    factor.reshape(len(speeds), 16)[:, ::5] = 1.0                                                   # the diagonals
    cubic = np.einsum("pj,pjm->pm", factor.prod(axis=2), near)
    smooth = is_oscillating(near).all(axis=1)
    estimate = np.where(smooth, cubic, linear)
    margin = np.where(smooth, _TRAVEL_MARGIN * travel + _MARGIN * np.abs(cubic - linear), travel)
    return estimate, margin, oscillating.all(axis=1), ~oscillating.any(axis=1)


def _solved_numbers(model, speeds, eigenvalues, lowest=None, progress=False):
    """The numbers by the roots solved at each speed (all speeds in one batch, in parts). After a
    sweep of the ``lowest`` lowest roots of a model of at least ``_arnoldi.MIN_DOF`` coordinates,
    by the ``lowest + 1`` lowest roots at each speed (:func:`_numbers_among_lowest`) first: every
    root of the state matrix of thousands of states costs about a minute per speed."""
    out = np.empty(len(speeds), dtype=int)
    todo = np.arange(len(speeds))
    if lowest is not None and model.dofs.n >= _arnoldi.MIN_DOF:
        numbers = _numbers_among_lowest(model, speeds, eigenvalues, lowest + 1, progress)
        known = numbers > 0
        out[known] = numbers[known]
        todo = todo[~known]
    if not len(todo):
        return out
    form = speed_linear_form(model)
    size = form.n_states
    bar = _bar(progress, len(todo))
    try:
        for part in _batches.chunk_slices(len(todo), 32 * size * size):
            rows = todo[part]
            roots = _eigensolve.select_upper(_eigensolve.eigenvalues_of(form.at(speeds[rows]), form.n_dof, form.matrices.M))
            out[rows] = [number_of_root(row, lam) for row, lam in zip(roots, eigenvalues[rows])]
            if bar is not None:
                bar.update(len(rows))
    finally:
        if bar is not None:
            bar.close()
    return out


def _bar(enabled, total):
    """A bar over ``total`` crossings whose roots are solved, where ``enabled``; else None."""
    if not enabled or not total:
        return None
    from .._progress import tqdm

    return tqdm(total=total, desc="mode numbers", unit="crossing", leave=False)


#: the bar over the speeds whose lowest roots give the mode numbers (shift-invert Arnoldi at each
#: critical speed: 177 s of silence at 200 geared rotors before it)
_LOWEST_BAR = "mode numbers (lowest modes)"


def _numbers_among_lowest(model, speeds, eigenvalues, count, progress=False):
    """The number of each root ``eigenvalues`` (P,) at its speed (P,) [rad/s] among the ``count``
    lowest roots there (``_lowest.lowest_roots``: each the full model's, every lower root among
    them): one more than the modes below it; 0 where it is not among them (within ``1e-6`` of one,
    not the last) or not a mode. ``progress``: a bar over the speeds (:data:`_LOWEST_BAR`)."""
    from ._lowest import lowest_roots
    from ._stack import Stack

    roots, _, _ = lowest_roots(Stack([model]), np.asarray(speeds, dtype=float), count,
                               progress=_LOWEST_BAR if progress else False, what="speeds at which the mode numbers of modes --speed are found")
    out = np.zeros(len(speeds), dtype=int)
    for p, (row, lam) in enumerate(zip(roots, eigenvalues)):
        gaps = np.abs(row - lam)
        j = int(np.nanargmin(gaps)) if np.isfinite(gaps).any() else -1
        if 0 <= j < count - 1 and gaps[j] <= 1e-6 * abs(lam) and is_oscillating(lam):
            out[p] = number_of_root(row, lam)
    return out
