"""Curves that lie on each other over part of their range, drawn there in turn.

Two curves of an axes whose drawn lines are closer than their line width hide one another
where they are: the one drawn last covers the other (a probe pair's x and y curves above
1500 rpm, an isotropic rotor's y and z probes everywhere). :func:`show_overlaps` finds, on
the laid-out figure, the stretches where curves run within a line width of each other
(measured across the curve, in points, on the axes' scales as drawn) and draws each group of
such curves there in dashes of one length at different phases, each curve in its own
colour, one after the other: every curve shows in every such stretch, and nothing changes
where the curves are apart. :func:`at_first_layout` runs it on the layout the figure's first
drawing does anyway (its save, its display), instead of laying the figure out once more.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
from matplotlib.layout_engine import ConstrainedLayoutEngine

#: length of each curve's dash where curves lie on each other [points]
DASH_POINTS = 4.0
#: a stretch where curves lie on each other shorter than this along the curve [points] is a crossing
_SHORTEST_POINTS = 12.0
#: zorder above a curve's own of its dashes where it lies on others
_OVER = 0.5
#: axes with more curves than this are left as drawn (one bit per curve in a group's mask; the
#: work grows with the cube of the count)
MOST_CURVES = 32


#: the dash pattern of each dashed stretch drawn, as set (matplotlib keeps it only privately)
_PATTERNS = weakref.WeakKeyDictionary()


def dash_pattern(line):
    """``(offset, (on, off))`` [line widths] of a dashed stretch :func:`show_overlaps` drew."""
    return _PATTERNS[line]


@dataclass(frozen=True)
class Overlap:
    """A stretch where ``line`` lies on ``other`` (an earlier curve of its group): points
    ``start`` to ``stop`` (inclusive) of the line's data."""

    line: object
    other: object
    start: int
    stop: int


def show_overlaps(ax, lines):
    """Draw ``lines`` (curves of ``ax`` sharing their x samples, in their drawing order) in
    turn where they lie on each other; return the stretches found.

    Where a group of ``n`` curves runs within a line width of each other for at least
    :data:`_SHORTEST_POINTS`, each member is drawn over that stretch again (above the curves,
    a line of its own) in dashes of :data:`DASH_POINTS` with gaps of ``(n - 1)`` dashes, the
    k-th member shifted by k dashes: the members alternate along the stretch, the curves
    drawn beneath are covered. A curve that lies on earlier ones over all of its range gets
    dashes as its own line style (its legend handle shows them). More than
    :data:`MOST_CURVES` curves are left as drawn.

    Parameters
    ----------
    ax : matplotlib Axes
    lines : list of matplotlib.lines.Line2D
        Drawn on a figure laid out (:func:`._labels.laid_out_renderer`, or inside its drawing:
        :func:`at_first_layout`): the axes' size and limits as they are drawn.

    Returns
    -------
    list of Overlap
        For every curve that lies on earlier ones, the stretches, once with each earlier
        curve of its group there (for the legend: "(= other)").
    """
    lines = [line for line in lines if len(line.get_xdata()) > 1]
    if not 2 <= len(lines) <= MOST_CURVES:
        return []
    points = _display_points(lines)
    if points is None:
        return []
    groups = _groups(points, lines, ax.figure.dpi / 72.0)
    found = []
    for k, line in enumerate(lines):
        stretches = _stretches(groups[k], points[k], ax.figure.dpi / 72.0)
        for start, stop, members, along, long_ in stretches:
            rank = members.index(k)
            if long_:
                found += [Overlap(line, lines[m], start, stop) for m in members[:rank]]
            x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
            pattern = _dashes(rank, len(members), line.get_linewidth(), along / (ax.figure.dpi / 72.0))
            dashed, = ax.plot(x[start:stop + 1], y[start:stop + 1], color=line.get_color(), lw=line.get_linewidth(),
                              ls=pattern, zorder=line.get_zorder() + _OVER, label="_overlap")
            _PATTERNS[dashed] = pattern
        long_ = [s for s in stretches if s[4]]         # its dashes as its own style: as the legend names it
        if long_ and all(s[2].index(k) for s in stretches) and _covered(long_, points[k]):
            line.set_linestyle(_dashes(1, 2, line.get_linewidth()))    # the legend shows its dashes
    return found


class _OverlapsAtFirstLayout(ConstrainedLayoutEngine):
    """Constrained layout that, the first time it lays its figure out, calls ``show()`` (the
    overlaps found and drawn on that layout) and lays the figure out again only where ``show``
    says the figure changed outside its axes (a legend's notes widened it)."""

    def __init__(self, show, **settings):
        super().__init__(**settings)
        self._show = show

    def execute(self, fig):
        super().execute(fig)
        show, self._show = self._show, None
        if show is not None and show():
            super().execute(fig)


def at_first_layout(fig, show):
    """Have ``show()`` (-> whether the figure changed outside its axes) run on the constrained
    layout of ``fig``'s first drawing, before anything is drawn: the drawing lays the figure out
    anyway, so the overlaps cost no layout of their own (a figure saved once, each redraw of the
    tuning widget). ``fig`` has constrained layout (its settings are kept)."""
    fig.set_layout_engine(_OverlapsAtFirstLayout(show, **fig.get_layout_engine().get()))


def _display_points(lines):
    """``(curves, n, 2)`` display points of ``lines`` (NaN where not drawn), or None when their
    x samples differ."""
    n = len(lines[0].get_xdata())
    if any(len(line.get_xdata()) != n for line in lines):
        return None
    with np.errstate(all="ignore"):
        points = np.stack([line.get_transform().transform(
            np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)]))
            for line in lines])
    points[~np.all(np.isfinite(points), axis=2)] = np.nan
    return points


def _groups(points, lines, pixels_per_point):
    """``(curves, n)`` bit masks: at each point, the curves whose lines lie within a line width
    of the curve's (across it), joined through each other (a group)."""
    count, n = points.shape[:2]
    near = np.zeros((count, count, n), bool)
    for k in range(count):
        for m in range(k + 1, count):
            width = 0.5 * (lines[k].get_linewidth() + lines[m].get_linewidth()) * pixels_per_point
            near[k, m] = near[m, k] = _across(points[k], points[m]) < width
    label = np.repeat(np.arange(count)[:, None], n, axis=1)
    for _ in range(count):                        # each point's groups: the least index joined
        joined = np.where(near, label[None, :, :], count).min(axis=1)
        label = np.minimum(label, joined)
    bits = (1 << np.arange(count)).astype(np.int64)
    same = label[:, None, :] == label[None, :, :]          # (k, m, n): m in k's group at each point
    return np.einsum("kmn,m->kn", same.astype(np.int64), bits)


def _across(a, b):
    """Distance [pixels] between two curves' points ``(n, 2)`` across them: the vertical gap
    times the cosine of their mean slope; inf where either is not drawn."""
    gap = np.abs(a[:, 1] - b[:, 1])
    with np.errstate(all="ignore"):
        slope = 0.5 * (_slope(a) + _slope(b))
        distance = gap / np.sqrt(1.0 + slope ** 2)
    return np.where(np.isfinite(distance), distance, np.inf)


def _slope(p):
    """Display slope dy/dx at each point (one-sided at the ends), NaN where undefined."""
    with np.errstate(all="ignore"):
        if len(p) < 2:
            return np.zeros(len(p))
        return np.gradient(p[:, 1], p[:, 0])


def _stretches(masks, points, pixels_per_point):
    """``[(start, stop, members, along, long), ...]``: the stretches where the curve's group
    (``masks``, one bit per curve) holds others and stays the same, members in drawing order;
    ``along`` [pixels]: how far along the curve the stretch begins from the start of its run
    (below); ``long``: whether the stretch is at least :data:`_SHORTEST_POINTS` long itself.

    A run of points where the group holds others, at least :data:`_SHORTEST_POINTS` long
    along the curve, is cut where the group changes, and each piece is a stretch however short:
    a third curve grazing the group, or the members passing in and out of a line width of each
    other, cut it into pieces whose lengths the display's geometry decides (the figure's size,
    a legend's place); pieces too short once left out left the curves there hidden under the
    one drawn last. A run shorter than that is a crossing: no stretch."""
    shared = (masks & (masks - 1)) != 0           # more than one bit: other curves
    with np.errstate(invalid="ignore"):
        lengths = np.hypot(*np.diff(points, axis=0).T)
    lengths = np.where(np.isfinite(lengths), lengths, 0.0)
    shortest = _SHORTEST_POINTS * pixels_per_point
    found = []
    for start, stop in _runs(shared):
        if stop == start or lengths[start:stop].sum() < shortest:
            continue
        i = start
        while i <= stop:
            j = i
            while j + 1 <= stop and masks[j + 1] == masks[i]:
                j += 1
            stretch = (i, min(j + 1, stop))          # to the next piece's first point: no gap between
            if stretch[1] > stretch[0]:
                found.append((*stretch, _bits(masks[i]), float(lengths[start:i].sum()),
                              bool(lengths[stretch[0]:stretch[1]].sum() >= shortest)))
            i = j + 1
    return found


def _runs(flags):
    """``[(start, stop), ...]`` (inclusive) of the runs of True in ``flags``."""
    edges = np.diff(np.concatenate([[0], np.asarray(flags, np.int8), [0]]))
    return list(zip(np.nonzero(edges == 1)[0].tolist(), (np.nonzero(edges == -1)[0] - 1).tolist()))


def _bits(mask: int) -> list:
    """The curves (bit numbers) of ``mask``, in order."""
    return [b for b in range(int(mask).bit_length()) if int(mask) >> b & 1]


def _covered(stretches, points):
    """Whether ``stretches`` together span every drawn point of the curve."""
    inside = np.zeros(len(points), bool)
    for start, stop, *_ in stretches:
        inside[start:stop + 1] = True
    return bool(np.all(inside | ~np.all(np.isfinite(points), axis=1)))


def _dashes(rank, members, width, along=0.0):
    """Line style of the ``rank``-th of ``members`` curves lying on each other: dashes of
    :data:`DASH_POINTS` with ``members - 1`` dashes' gaps, shifted to the rank's turn (a
    pattern in points, matplotlib scales it by the line width); ``along`` [points]: where
    the stretch begins along its run, so that the turns go on across the run's stretches."""
    dash = DASH_POINTS / max(width, 1e-3)
    return (((members - rank) % members * dash + along / max(width, 1e-3)) % (members * dash),
            (dash, (members - 1) * dash))
