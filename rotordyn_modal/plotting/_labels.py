"""Labels of straight lines placed where the lines leave the axes, inside and apart.

Each label offers a few candidate boxes next to its line's exit point (in axes fraction);
the first candidate that lies inside the axes and clear of every label already placed is
taken; a label with no such candidate is left out (its line keeps its colour). Labels of
one source whose exits are closer than a label's width are merged first (``1X, 2X fan``).
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


def line_exit(slope: float, x_limits, top: float):
    """Where ``f = slope |x|`` leaves the box ``x_limits x [0, top]``, toward the larger ``|x|``.

    Returns
    -------
    (edge, u, v, direction) or None
        ``u, v`` in axes fraction; None when the line is outside the box.
    """
    lo, hi = x_limits
    direction = 1 if hi >= abs(lo) else -1
    far = hi if direction > 0 else lo
    width = hi - lo
    if slope <= 0 or width <= 0:
        return None
    if slope * abs(far) > top:
        x = direction * top / slope
        if not lo <= x <= hi:
            return None
        return "top", (x - lo) / width, 1.0, direction
    if far * direction < 0:
        return None
    return ("right" if direction > 0 else "left"), (far - lo) / width, slope * abs(far) / top, direction


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
    box = ax.get_window_extent(renderer)
    to_u, to_v = 1.0 / box.width, 1.0 / box.height
    points = fig.dpi / 72.0

    def size(text):
        artist = ax.text(0, 0, text, fontsize=fontsize)
        extent = artist.get_window_extent(renderer)
        artist.remove()
        return extent.width * to_u, extent.height * to_v

    pad_u, pad_v = _PAD_POINTS * points * to_u, _PAD_POINTS * points * to_v
    margin = (_MARGIN_POINTS * points * to_u, _MARGIN_POINTS * points * to_v)
    placed, drawn = [], []
    for label in _merge_close(labels, size):
        w, h = size(label.text)
        for left, bottom in _candidates(label, w, h, pad_u, pad_v):
            candidate = (left, bottom, left + w, bottom + h)
            if _inside(candidate, margin) and not any(_overlap(candidate, other, pad_u, pad_v)
                                                        for other in placed):
                placed.append(candidate)
                drawn.append(ax.text(left, bottom, label.text, transform=ax.transAxes, fontsize=fontsize,
                                     color=label.color, ha="left", va="bottom", clip_on=True))
                break
    return drawn


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


def _inside(box, margin):
    left, bottom, right, top = box
    mu, mv = margin
    return left >= mu and bottom >= mv and right <= 1 - mu and top <= 1 - mv


def _overlap(a, b, gap_u, gap_v):
    return a[0] < b[2] + gap_u and b[0] < a[2] + gap_u and a[1] < b[3] + gap_v and b[1] < a[3] + gap_v


def exits_of_orders(orders, lines, x_limits, top, per_x):
    """:class:`EdgeLabel` of every order line ``f = order multiplier |x| per_x``.

    ``lines`` is a list of (name, multiplier, colour), one per source; ``per_x`` turns a
    plotted speed into Hz per unit of order and multiplier.
    """
    labels = []
    for name, multiplier, color in lines:
        for order in orders:
            exit_ = line_exit(float(np.abs(order * multiplier * per_x)), x_limits, top)
            if exit_ is not None:
                labels.append(EdgeLabel(f"{order:g}X", name, color, *exit_))
    return labels


def spread_apart(annotations, gap_points: float = 1.0, renderer=None):
    """Move annotations (offset in points) up just enough that no two of them overlap.

    Lowest first, each annotation rises above every earlier one its box meets; its anchor
    stays, only the offset changes. ``renderer`` as for :func:`place_edge_labels`.
    """
    if not annotations:
        return
    fig = annotations[0].figure
    renderer = renderer or laid_out_renderer(fig)
    points = fig.dpi / 72.0
    boxes = sorted(((a.get_window_extent(renderer), a) for a in annotations), key=lambda item: item[0].y0)
    placed = []
    for box, annotation in boxes:
        x0, y0, x1, y1 = box.x0, box.y0, box.x1, box.y1
        rise = 0.0
        for px0, py0, px1, py1 in placed:
            if x0 < px1 and px0 < x1 and y0 + rise < py1 + gap_points * points and py0 < y1 + rise:
                rise = py1 + gap_points * points - y0
        placed.append((x0, y0 + rise, x1, y1 + rise))
        if rise:
            dx, dy = annotation.xyann
            annotation.xyann = (dx, dy + rise / points)


#: offsets (in label widths and heights) of a point label's lower-left corner from its anchor,
#: tried in this order: above right, above left, right, left, further above, below
_POINT_OFFSETS = [(0.1, 0.6), (-1.1, 0.6), (0.15, -0.5), (-1.15, -0.5), (0.1, 1.8), (-1.1, 1.8),
                  (0.1, -1.8), (-1.1, -1.8), (-0.5, 3.0), (0.1, 3.0), (-1.1, 3.0), (-0.5, -1.8),
                  (0.1, -3.0), (-1.1, -3.0)]


#: half size of the marker at a point label's anchor, kept free of labels [points]
_MARKER_POINTS = 3.0


def place_point_labels(ax, anchors, texts, colors, fontsize="x-small", renderer=None):
    """Annotate points of ``ax`` in the order given, each label inside the axes and apart.

    Each label tries a few boxes around its anchor (:data:`_POINT_OFFSETS`); the first
    inside the axes and clear of every label placed before and of every anchor is taken; a label with no free
    box is left out. Give the anchors most important first.

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
    pixels = [ax.transData.transform((x, y)) for x, y in anchors]
    marker = _MARKER_POINTS * points
    placed = [(px - marker, py - marker, px + marker, py + marker) for px, py in pixels]   # keep the points free
    drawn = []
    for (x, y), (px, py), text, color in zip(anchors, pixels, texts, colors):
        if not (frame.x0 <= px <= frame.x1 and frame.y0 <= py <= frame.y1):
            continue
        probe = ax.text(0, 0, text, fontsize=fontsize)
        extent = probe.get_window_extent(renderer)
        probe.remove()
        w, h = extent.width, extent.height
        for du, dv in _POINT_OFFSETS:
            left, bottom = px + du * w, py + dv * h
            box = (left, bottom, left + w, bottom + h)
            inside = (box[0] >= frame.x0 + margin and box[1] >= frame.y0 + margin
                      and box[2] <= frame.x1 - margin and box[3] <= frame.y1 - margin)
            if inside and not any(_overlap(box, other, pad, pad) for other in placed):
                placed.append(box)
                drawn.append(ax.annotate(text, (x, y), xytext=((left - px) / points, (bottom - py) / points),
                                         textcoords="offset points", ha="left", va="bottom", fontsize=fontsize,
                                         color=color, annotation_clip=True,
                                         bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none",
                                               "alpha": 0.75},
                                         arrowprops={"arrowstyle": "-", "color": color, "lw": 0.5,
                                                     "shrinkA": 0, "shrinkB": 2}))
                break
    return drawn
