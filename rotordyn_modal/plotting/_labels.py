"""Labels placed inside (or beside) the axes, apart from each other and from markers.

One placer serves every label inside the axes: :func:`first_free_box` takes the first of a
label's candidate boxes that lies inside the axes and clear of every label already placed (and
of markers); a label with no such candidate is left out. The callers only choose the candidates:

- straight lines' labels (:func:`edge_label_boxes`): a few boxes next to where the line leaves
  the axes (a line whose label is left out keeps its colour); labels of one source whose exits
  are closer than a label's width are merged first (``1X, 2X fan``);
- labels of points without a leader line (Campbell mode ends and critical speeds, stability
  thresholds): a few boxes touching the point's marker;
- labels of points with a leader line (:func:`place_point_labels`, unbalance peaks): a grid
  of boxes around the point, nearest first (:func:`boxes_around`), a box taken only where its
  leader line crosses no label; a crowd of labels at one point fans out in columns beside it.

Curves' labels beside the axes (:func:`column_positions`) keep their curves' order and move
apart only as far as they must; a leader line joins each to its curve.
:func:`draw_time_layout` re-places a figure's labels each time it is drawn, so that they follow
zooming, panning and resizing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: gap between a label and its line's exit point, and between labels [points]
_PAD_POINTS = 3.0
#: labels keep this far from the axes' frame [points]
_MARGIN_POINTS = 2.0
#: rows of labels under the top edge
_ROWS = 3
#: a crowded label may slide along its row by up to this many half widths
_SLIDES = 6


@dataclass
class EdgeLabel:
    """A line's label anchored where the line leaves the axes.

    ``edge`` is 'top', 'right' or 'left'; ``u, v`` the exit point in axes fraction;
    ``direction`` +1 where the line rises to the right, -1 to the left; ``spread`` the
    extent along the edge of the exits of a merged label (from ``u`` or ``v`` on).
    """

    prefix: str
    suffix: str
    color: str
    edge: str
    u: float
    v: float
    direction: int
    spread: float = 0.0

    @property
    def text(self) -> str:
        return f"{self.prefix} {self.suffix}"


def line_exit(slope: float, x_limits, top: float, bottom: float = 0.0, to_axes=None):
    """Where ``f = slope |x|`` leaves the box ``x_limits x [bottom, top]``, toward the larger ``|x|``.

    Parameters
    ----------
    slope : float
        [frequency per unit of x], > 0.
    x_limits : (float, float)
    top, bottom : float
        The box's upper and lower frequency.
    to_axes : callable, optional
        ``(x, f) -> (u, v)`` in axes fraction (the axes' own transform: a logarithmic axis);
        linear in both when not given.

    Returns
    -------
    (edge, u, v, direction) or None
        ``u, v`` in axes fraction; None when the line is outside the box.
    """
    lo, hi = x_limits
    direction = 1 if hi >= abs(lo) else -1
    far = hi if direction > 0 else lo
    width = hi - lo
    if slope <= 0 or width <= 0 or top <= bottom:
        return None
    if to_axes is None:
        def to_axes(x, f):
            return (x - lo) / width, (f - bottom) / (top - bottom)
    if slope * abs(far) > top:
        x = direction * top / slope
        if not lo <= x <= hi:
            return None
        return "top", to_axes(x, top)[0], 1.0, direction
    if far * direction < 0 or slope * abs(far) < bottom:
        return None
    u, v = to_axes(far, slope * abs(far))
    return ("right" if direction > 0 else "left"), u, v, direction


def laid_out_renderer(fig):
    """Lay the figure out (constrained layout runs) and return its renderer."""
    fig.draw_without_rendering()
    return fig.canvas.get_renderer()


def place_edge_labels(ax, labels, fontsize="x-small", renderer=None):
    """Draw ``labels`` (list of :class:`EdgeLabel`) inside ``ax`` without overlaps.

    ``renderer`` from :func:`laid_out_renderer` once the figure is complete (labels inside
    the axes do not move it); laid out here when not given.

    Returns
    -------
    list of matplotlib.text.Text
        The labels drawn (merged or left out ones are not drawn).
    """
    fig = ax.figure
    renderer = renderer or laid_out_renderer(fig)
    drawn = []
    for label, (left, bottom, _, _) in edge_label_boxes(ax, labels, fontsize, renderer, []):
        drawn.append(ax.text(left, bottom, label.text, transform=ax.transAxes, fontsize=fontsize,
                             color=label.color, ha="left", va="bottom", clip_on=True))
    return drawn


def text_size(fig, text, fontsize, renderer):
    """(width, height) [pixels] of ``text`` at ``fontsize`` drawn by ``renderer``."""
    from matplotlib.text import Text

    artist = Text(0, 0, text, fontsize=fontsize)
    artist.set_figure(fig)
    extent = artist.get_window_extent(renderer)
    return extent.width, extent.height


def edge_label_boxes(ax, labels, fontsize, renderer, placed):
    """Boxes (axes fraction) of the :class:`EdgeLabel` s that find room, merged where close.

    ``placed`` holds the boxes (left, bottom, right, top in axes fraction) taken already;
    the new ones are appended to it.

    Returns
    -------
    list of (EdgeLabel, (left, bottom, right, top))
    """
    box = ax.get_window_extent(renderer)
    to_u, to_v = 1.0 / max(box.width, 1.0), 1.0 / max(box.height, 1.0)
    points = renderer.points_to_pixels(1.0)

    def size(text):
        width, height = text_size(ax.figure, text, fontsize, renderer)
        return width * to_u, height * to_v

    pad_u, pad_v = _PAD_POINTS * points * to_u, _PAD_POINTS * points * to_v
    margin = (_MARGIN_POINTS * points * to_u, _MARGIN_POINTS * points * to_v)
    frame = (margin[0], margin[1], 1.0 - margin[0], 1.0 - margin[1])
    taken = []
    for label in _merge_close(labels, size):
        w, h = size(label.text)
        box = first_free_box([(left, bottom, left + w, bottom + h)
                              for left, bottom in _candidates(label, w, h, pad_u, pad_v)],
                             placed, (pad_u, pad_v), frame)
        if box is not None:
            taken.append((label, box))
    return taken


def first_free_box(candidates, placed, gap=(0.0, 0.0), frame=(0.0, 0.0, 1.0, 1.0), obstacles=(), allowed=None):
    """The first of ``candidates`` inside ``frame`` and clear of every box in ``placed``.

    Boxes are (left, bottom, right, top) in one coordinate system; ``gap`` (along x, y) is
    kept from the boxes placed; ``obstacles`` (markers) are only not overlapped; ``allowed``
    (a function of a box, optional) must also say True (e.g. a leader line crossing no label).
    The box taken is appended to ``placed``.

    Returns
    -------
    tuple or None
    """
    for candidate in candidates:
        inside = (candidate[0] >= frame[0] and candidate[1] >= frame[1] and candidate[2] <= frame[2]
                  and candidate[3] <= frame[3])
        if inside and not any(_overlap(candidate, other, *gap) for other in placed) \
                and not any(_overlap(candidate, other, 0.0, 0.0) for other in obstacles) \
                and (allowed is None or allowed(candidate)):
            placed.append(candidate)
            return candidate
    return None


def segment_crosses_box(start, end, box) -> bool:
    """Whether the segment ``start -> end`` (points (x, y)) passes through ``box`` (Liang-Barsky)."""
    (x0, y0), (x1, y1) = start, end
    low, high = 0.0, 1.0
    for delta, near, far in ((x1 - x0, box[0] - x0, box[2] - x0), (y1 - y0, box[1] - y0, box[3] - y0)):
        if delta == 0.0:
            if near > 0.0 or far < 0.0:
                return False
            continue
        a, b = sorted((near / delta, far / delta))
        low, high = max(low, a), min(high, b)
        if low > high:
            return False
    return True


def column_positions(targets, heights, lo, hi, gap=0.0):
    """Centres of labels stacked in one column: as near their targets as they can be, apart.

    Labels keep the order of their targets; a group of labels that would overlap moves as a
    block centred on its targets' mean (the positions nearest the targets in least squares),
    then the column is pushed inside ``[lo, hi]`` where it fits.

    Parameters
    ----------
    targets, heights : array_like, shape (n,)
        Wanted centres and the labels' heights (one unit, e.g. pixels).
    lo, hi : float
        The column's ends.
    gap : float
        Space kept between neighbours.

    Returns
    -------
    ndarray, shape (n,)
        Centres, in the order of ``targets``.
    """
    targets = np.asarray(targets, float)
    heights = np.asarray(heights, float) + gap
    order = np.argsort(targets, kind="stable")
    blocks = []  # [first, last, bottom]
    for i, k in enumerate(order):
        blocks.append([i, i, targets[k] - heights[k] / 2])
        while len(blocks) > 1:
            first, last, bottom = blocks[-1]
            previous = blocks[-2]
            top_of_previous = previous[2] + heights[order[previous[0]:previous[1] + 1]].sum()
            if bottom >= top_of_previous:
                break
            members = order[previous[0]:last + 1]
            stack = np.concatenate(([0.0], np.cumsum(heights[members])[:-1])) + heights[members] / 2
            blocks[-2:] = [[previous[0], last, float(np.mean(targets[members] - stack))]]
    centres = np.empty(len(targets))
    for first, last, bottom in blocks:
        members = order[first:last + 1]
        centres[members] = bottom + np.concatenate(([0.0], np.cumsum(heights[members])[:-1])) + heights[members] / 2
    below = np.concatenate(([0.0], np.cumsum(heights[order])[:-1]))
    if heights.sum() <= hi - lo:
        # inside [lo, hi]: the elementwise max (min) of two sequences spaced at least their
        # half heights apart is spaced so too
        low = lo + below + heights[order] / 2
        high = hi - heights.sum() + low - lo
        centres[order] = np.minimum(np.maximum(centres[order], low), high)
    return centres


def draw_time_layout(place):
    """An artist that calls ``place(renderer)`` each time its axes are drawn (add it to them).

    It is drawn first of the axes' children (lowest z-order), so the labels that ``place``
    moves are drawn where it put them, with the figure's final layout, limits and
    resolution: after zooming, panning or resizing, the labels are placed again.
    """
    from matplotlib.artist import Artist

    class _Layout(Artist):
        def draw(self, renderer):
            if self.get_visible():
                place(renderer)

    artist = _Layout()
    artist.set_zorder(-1.0e9)
    artist.set_in_layout(False)
    return artist


def set_if_changed(artist, **properties):
    """Set ``properties`` of ``artist`` only where they change (a redraw marks nothing stale)."""
    for name, value in properties.items():
        current = getattr(artist, f"get_{name}")()
        same = np.array_equal(np.asarray(current, dtype=object), np.asarray(value, dtype=object)) \
            if not isinstance(value, str) else current == value
        if not same:
            getattr(artist, f"set_{name}")(value)


def _merge_close(labels, size):
    """One label per source and edge for exits closer than that label's width (height)."""
    merged = []
    for label in sorted(labels, key=lambda lab: (lab.edge, lab.suffix, lab.u, lab.v)):
        last = merged[-1] if merged else None
        if last is not None and last.edge == label.edge and last.suffix == label.suffix:
            along = 0 if label.edge == "top" else 1
            start = (last.u, last.v)[along]
            if (label.u, label.v)[along] - (start + last.spread) < size(last.text)[along]:
                spread = (label.u, label.v)[along] - start
                merged[-1] = EdgeLabel(_join(last.prefix, label.prefix), last.suffix, last.color, last.edge,
                                       last.u, last.v, last.direction, spread)
                continue
        merged.append(label)
    return sorted(merged, key=lambda lab: (lab.edge != "top", -lab.direction * lab.u, -lab.v))


def _join(first: str, second: str) -> str:
    """``'2X', '1X'`` -> ``'1X, 2X'``: orders increasing when they read as numbers."""
    parts = first.split(", ") + [second]
    try:
        parts.sort(key=lambda part: float(part.rstrip("X")))
    except ValueError:
        pass
    return ", ".join(parts)


def _candidates(label, w, h, pad_u, pad_v):
    """Lower-left corners of boxes next to the exit point, the side above the line first."""
    if label.edge == "top":
        lo, hi = label.u, label.u + label.spread
        before, after = lo - pad_u - w, hi + pad_u
        behind, ahead = (before, after) if label.direction > 0 else (after, before)
        rows = [1.0 - k * (pad_v + h) for k in range(1, _ROWS + 1)]
        slides = [0.0] + [k * w / 2 for k in range(1, _SLIDES + 1)]
        away = -1.0 if behind < ahead else 1.0
        return [(side + sign * slide, row) for slide in slides for row in rows
                for side, sign in ((behind, away), (ahead, -away))]
    lo, hi = label.v, label.v + label.spread
    left = 1.0 - pad_u - w if label.edge == "right" else pad_u
    return [(left, hi + pad_v), (left, lo - pad_v - h), (left, hi + 2 * pad_v + h), (left, lo - 2 * (pad_v + h))]


def _overlap(a, b, gap_u, gap_v):
    return a[0] < b[2] + gap_u and b[0] < a[2] + gap_u and a[1] < b[3] + gap_v and b[1] < a[3] + gap_v


def exits_of_orders(orders, lines, x_limits, top, per_x, bottom=0.0, to_axes=None):
    """:class:`EdgeLabel` of every order line ``f = order multiplier |x| per_x``.

    ``lines`` is a list of (name, multiplier, colour), one per source; ``per_x`` turns a
    plotted speed into Hz per unit of order and multiplier; ``bottom`` and ``to_axes`` as
    for :func:`line_exit`.
    """
    labels = []
    for name, multiplier, color in lines:
        for order in orders:
            exit_ = line_exit(float(np.abs(order * multiplier * per_x)), x_limits, top, bottom, to_axes)
            if exit_ is not None:
                labels.append(EdgeLabel(f"{order:g}X", name, color, *exit_))
    return labels


#: half size of the marker at a point label's anchor, kept free of labels [points]
_MARKER_POINTS = 3.0

#: a label with a leader line may sit this many rows (label heights) above and below its
#: point, and this many columns (label widths) right and left of it
_GRID_ROWS, _GRID_COLUMNS = 8, 2

#: a box below the point counts this many times as far (a peak's curve falls away below it)
_BELOW = 2.0


def boxes_around(x, y, w, h, pad, clear):
    """Boxes of size ``w x h`` on a grid around the point ``(x, y)``, nearest first.

    Rows are centred on the point's height and a little more than ``pad`` apart (so that
    round-off cannot bring neighbours within ``pad``), up to :data:`_GRID_ROWS` each way;
    columns lie right and left of the point (none across it: its leader lines would block
    the others'), up to :data:`_GRID_COLUMNS` each way, as far apart and clear of the point's
    marker (half size ``clear``). Nearest is by the distance from the point to the box, those below the point
    counted :data:`_BELOW` times; ties: above before below, right before left.

    Parameters
    ----------
    x, y, w, h, pad, clear : float
        One unit (e.g. pixels).

    Returns
    -------
    list of (left, bottom, right, top)
    """
    pad = 1.25 * pad
    lefts = [left for j in range(_GRID_COLUMNS)
             for left in (x + clear + pad + j * (w + pad), x - clear - pad - w - j * (w + pad))]
    rows = sorted(range(-_GRID_ROWS, _GRID_ROWS + 1), key=lambda k: (abs(k), k < 0))
    boxes = [(left, y - h / 2 + k * (h + pad), left + w, y + h / 2 + k * (h + pad)) for k in rows for left in lefts]

    def distance(box):
        du = max(box[0] - x, 0.0, x - box[2])
        dv = max(box[1] - y, 0.0, _BELOW * (y - box[3]))
        return du * du + dv * dv

    return sorted(boxes, key=distance)


def place_point_labels(ax, anchors, texts, colors, fontsize="x-small", renderer=None):
    """Annotate points of ``ax`` in the order given, each label inside the axes and apart.

    Each label takes the nearest free box (:func:`first_free_box`: inside the axes, clear of
    every label placed before and of every anchor, its leader line crossing no label and no
    leader line crossing it) of a grid around its anchor (:func:`boxes_around`); a leader
    line joins the box's point nearest the anchor to the anchor. Labels crowded at one point
    so fan out in columns beside it. A label with no free box is left out: give the anchors
    most important first.

    Parameters
    ----------
    anchors : list of (x, y)
        Points in data coordinates.
    texts, colors : list of str
        One per anchor.
    renderer : optional
        From :func:`laid_out_renderer` once the figure is complete.

    Returns
    -------
    list of matplotlib.text.Annotation
        The labels drawn, in the order of ``anchors`` (left-out ones missing).
    """
    fig = ax.figure
    renderer = renderer or laid_out_renderer(fig)
    frame = ax.get_window_extent(renderer)
    points = fig.dpi / 72.0
    margin, pad = _MARGIN_POINTS * points, _PAD_POINTS * points
    inner = (frame.x0 + margin, frame.y0 + margin, frame.x1 - margin, frame.y1 - margin)
    pixels = [ax.transData.transform((x, y)) for x, y in anchors]
    marker = _MARKER_POINTS * points
    placed = [(px - marker, py - marker, px + marker, py + marker) for px, py in pixels]   # keep the points free
    labels, leaders = [], []        # the boxes and leader lines drawn
    drawn = []
    for (x, y), (px, py), text, color in zip(anchors, pixels, texts, colors):
        if not (frame.x0 <= px <= frame.x1 and frame.y0 <= py <= frame.y1):
            continue

        def leader_clear(box, point=(px, py)):
            end = _nearest_in(box, point)
            return not any(segment_crosses_box(end, point, other) for other in labels) \
                and not any(segment_crosses_box(*leader, box) for leader in leaders)

        w, h = text_size(fig, text, fontsize, renderer)
        box = first_free_box(boxes_around(px, py, w, h, pad, marker), placed, (pad, pad), inner, allowed=leader_clear)
        if box is None:
            continue
        end = _nearest_in(box, (px, py))
        labels.append(box)
        leaders.append((end, (px, py)))
        drawn.append(ax.annotate(text, (x, y), xytext=((box[0] - px) / points, (box[1] - py) / points),
                                 textcoords="offset points", ha="left", va="bottom", fontsize=fontsize,
                                 color=color, annotation_clip=True,
                                 bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none",
                                       "alpha": 0.75},
                                 arrowprops={"arrowstyle": "-", "color": color, "lw": 0.5, "shrinkA": 0, "shrinkB": 2,
                                             "relpos": ((end[0] - box[0]) / w, (end[1] - box[1]) / h)}))
    return drawn


def _nearest_in(box, point):
    """The point of ``box`` nearest ``point``: where a leader line from ``point`` meets the box."""
    return min(max(point[0], box[0]), box[2]), min(max(point[1], box[1]), box[3])
