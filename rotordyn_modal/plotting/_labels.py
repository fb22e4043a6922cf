"""Labels placed inside (or beside) the axes, apart from each other and from markers.

One placer serves every label inside the axes: :func:`first_free_box` takes the first of a
label's candidate boxes that lies inside the axes and clear of every label already placed (and
of markers) and, where the callers ask (:class:`CurveMap`), where no drawn curve runs but near
the label's own anchor; a label with no such candidate is left out. The callers only choose
the candidates:

- straight lines' labels (:func:`edge_label_boxes`): a few boxes next to where the line leaves
  the axes, then beside the line farther back (down from the top edge where the exits there
  are crowded; the line nearest the label at its height is its own); a line whose label is
  left out keeps its colour; labels of one source whose exits are closer than a label's width
  and have no other source's exit between them are merged first (``1X, 2X fan``); with
  ``along``, a top-edge label with no such box is written along its line, turned to its slope
  (:func:`_along_the_line`);
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

import dataclasses
import math
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
#: a label at the right or left edge may step away from its line by up to this many quarter heights
_STEPS = 6


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
    #: points (u, v) along the line back from its exit at the right or left edge, nearest first;
    #: down from its exit at the top edge (every 1/25 of the axes' height), nearest first
    back: tuple = ()
    #: the line (or merged lines) as drawn inside the axes: polylines of points (u, v), from the
    #: exit down (empty where not known: then no label slides down along it)
    paths: tuple = ()
    #: the label's text angle [degrees]: 0 (flat), or along its line where no flat box was free
    angle: float = 0.0
    #: ... and its font size [points] there (None: the caller's)
    fontsize: float | None = None

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


def edge_label_boxes(ax, labels, fontsize, renderer, placed, curves=None, along=False, smaller=False):
    """Boxes (axes fraction) of the :class:`EdgeLabel` s that find room, merged where close.

    ``placed`` holds the boxes (left, bottom, right, top in axes fraction) taken already;
    the new ones are appended to it. With ``curves`` (a :class:`CurveMap` in axes fraction)
    a label takes the first of its boxes that no curve crosses (but near its own exits) or
    is left out. With ``along`` too, a top-edge label that found no flat box is written along
    its own line (its ``angle``), beside it just under the top edge or farther down
    (:func:`_along_the_line`); the caller turns its text by that angle. With ``smaller`` too, a
    side-edge label that found no box either way takes a flat box in :data:`_SMALLER_ALONG`
    (its ``fontsize``).

    Returns
    -------
    list of (EdgeLabel, (left, bottom, right, top))
    """
    box = ax.get_window_extent(renderer)
    to_u, to_v = 1.0 / max(box.width, 1.0), 1.0 / max(box.height, 1.0)
    pixels = (box.width, box.height)
    points = renderer.points_to_pixels(1.0)

    def size(text):
        width, height = text_size(ax.figure, text, fontsize, renderer)
        return width * to_u, height * to_v

    pad_u, pad_v = _PAD_POINTS * points * to_u, _PAD_POINTS * points * to_v
    margin = (_MARGIN_POINTS * points * to_u, _MARGIN_POINTS * points * to_v)
    frame = (margin[0], margin[1], 1.0 - margin[0], 1.0 - margin[1])
    taken = []
    anchor_u, anchor_v = ANCHOR_POINTS * points * to_u, ANCHOR_POINTS * points * to_v

    def flat_box(label, w, h):
        boxes = [(left, bottom, left + w, bottom + h) for left, bottom in _candidates(label, w, h, pad_u, pad_v)]
        if curves is None:
            return first_free_box(boxes, placed, (pad_u, pad_v), frame)
        along_u, along_v = (label.spread, 0.0) if label.edge == "top" else (0.0, label.spread)
        keep = (label.u - anchor_u, label.v - anchor_v, label.u + along_u + anchor_u, label.v + along_v + anchor_v)
        others = [other for other in merged if other is not label]
        return first_free_box(boxes, placed, (pad_u, pad_v), frame,
                              allowed=lambda b: curves.free(b, keep) and nearest_own_exit(b, label, others, pixels)
                              and _no_curve_between(b, label, curves, keep, 2 * pad_u))

    merged = _merge_close(labels, size)
    for label in merged:
        box = flat_box(label, *size(label.text))
        if box is not None:
            taken.append((label, box))
    if along and curves is not None:
        turned = {}             # the turned labels' outlines (by their boxes in ``placed``)
        # top-edge labels first (by their exits along the edge), then those of the side edges
        missing = sorted([label for label in merged if label.paths and all(label is not t for t, _ in taken)],
                         key=lambda lab: (lab.edge != "top", lab.direction * lab.u, -lab.v))
        for label in missing:
            along_v = label.edge != "top"
            members = [m for m in labels if m.edge == label.edge and m.suffix == label.suffix
                       and (label.v, label.u)[not along_v] - 1e-12 <= (m.v, m.u)[not along_v]
                       <= (label.v, label.u)[not along_v] + label.spread + 1e-12]
            others = [o for o in labels if all(o is not m for m in members)]
            found = _along_the_line(ax, dataclasses.replace(label, prefix=_short_orders(label.prefix)), others,
                                    fontsize, renderer, placed, curves, frame, (pad_u, pad_v), turned)
            # else each of its lines on its own
            singles = [] if found is not None or len(members) < 2 else \
                [_along_the_line(ax, m, others + [o for o in members if o is not m], fontsize, renderer, placed,
                                 curves, frame, (pad_u, pad_v), turned) for m in members]
            taken += [item for item in [found] + singles if item is not None]
            if found is None and not any(singles) and label.edge != "top" and smaller:
                # flat in the smaller font beside its exit (compressor_rotor's '1X compressor',
                # kept off the room above the 14388 rpm circle, between modes 5 and 6)
                small = dataclasses.replace(label, fontsize=font_points(_SMALLER_ALONG))
                w, h = text_size(ax.figure, label.text, _SMALLER_ALONG, renderer)
                box = flat_box(small, w * to_u, h * to_v)
                if box is not None:
                    taken.append((small, box))
    return taken


def _no_curve_between(box, label, curves, keep, reach):
    """Whether no curve runs between a side-edge label's ``box`` (axes fraction) standing at its
    edge (within ``reach`` of it) and its exit: the straight way from the exit along the edge
    to the box's nearest point crosses none ('1X compressor' stood two heights above its
    exit at the right edge, mode 4's line between them, as if naming it). A box away from the
    edge (beside the line farther back, :func:`_candidates`): no curve runs between it and the
    nearest of the line's points it was set beside (compressor_rotor's '1X compressor', moved
    off the 14388 rpm circle, stood under mode 3's line with its own line above that).
    Top-edge labels: True."""
    if label.edge == "top":
        return True
    if not (box[2] >= 1.0 - reach or box[0] <= reach):
        if not label.back:
            return True
        back = np.asarray(label.back, float)
        gaps = np.maximum(np.maximum(np.asarray(box[:2]) - back, back - np.asarray(box[2:])), 0.0)
        point = back[np.argmin(np.hypot(gaps[:, 0], gaps[:, 1]))]
        start = np.asarray(nearest_in(box, point), float)
        way = point - start
        length = float(np.hypot(*way))
        if length <= 2e-3:
            return True
        # stopped short of the line itself (a thousandth of the axes)
        return curves.cut(tuple(start), tuple(point - way * (1e-3 / length)), None) == 0
    v = min(max(0.5 * (box[1] + box[3]), label.v), label.v + label.spread)
    near = (min(max(label.u, box[0]), box[2]), min(max(v, box[1]), box[3]))
    return curves.crossings((label.u, v), near, keep) == 0


def _short_orders(prefix: str) -> str:
    """``'1X, 2X, 3X, 4X'`` -> ``'1\u20134X'`` (an en dash): three or more consecutive whole
    orders written as a range; other prefixes as they are."""
    parts = prefix.split(", ")
    try:
        orders = [float(part.rstrip("X")) for part in parts]
    except ValueError:
        return prefix
    whole = all(o == int(o) for o in orders)
    if len(orders) >= 3 and whole and all(b - a == 1 for a, b in zip(orders, orders[1:])):
        return f"{orders[0]:g}\u2013{orders[-1]:g}X"
    return prefix


#: a label written along its line slides down from the top edge to this height (axes fraction);
#: where its font finds no room there, it tries this one
_LOWEST_ALONG, _SMALLER_ALONG = 0.3, "xx-small"


def _along_the_line(ax, label, others, fontsize, renderer, placed, curves, frame, pad, turned=None):
    """``(label turned along its line, box)`` or None: the text parallel to its line (or to the
    outermost of its merged lines on either side), slid down from the top edge to
    :data:`_LOWEST_ALONG`, right of the line first, then left, in ``fontsize`` then
    :data:`_SMALLER_ALONG`; the first place where the turned text itself (its rotated outline,
    not the box around it) lies half ``pad`` and a cell of ``curves`` clear of the line (so no
    curve runs through it, not even its own), inside ``frame``, ``pad`` clear of ``placed``
    (boxes, or the outlines in ``turned`` of the labels turned before) and of every curve,
    and where its centre is nearer its own lines than any of ``others``'.

    The box (left, bottom, right, top; axes fraction) around the turned text is drawn with the
    text's lower-left corner there (``ha='left', va='bottom'``, turned by the label's ``angle``
    [degrees]); it is appended to ``placed`` and its outline (4, 2) [axes fraction] to
    ``turned`` (a dict: box -> outline)."""
    extent = ax.get_window_extent(renderer)
    size = np.array([max(extent.width, 1.0), max(extent.height, 1.0)])
    gap = 0.5 * float(np.mean(np.asarray(pad) * size))
    offset = gap + curves.cell          # the own line's marked cells lie up to a cell from it
    turned = {} if turned is None else turned
    others = [np.asarray(o.paths[0], float) * size for o in others if o.paths]
    own = [np.asarray(path, float) * size for path in label.paths]
    own_segments, other_segments = [_Segments(p) for p in own], [_Segments(p) for p in others]
    sides = []
    for side in (1.0, -1.0):
        line = max(own, key=lambda p: side * p[0, 0])       # the outermost of its lines on that side
        down = (line[1] - line[0]) / np.hypot(*(line[1] - line[0]))
        normal = np.array([down[1], -down[0]])
        sides.append((line, down, normal if normal[0] * side > 0 else -normal))
    along = -sides[0][1] if sides[0][1][0] < 0 else sides[0][1]      # the text reads left to right
    angle = float(np.degrees(np.arctan2(along[1], along[0])))
    lowest = (1.0 - _LOWEST_ALONG) * size[1] / max(abs(sides[0][1][1]), 1e-9)
    inner = np.asarray(frame, float) * np.tile(size, 2)
    obstacles = np.array([turned[tuple(b)] * size if tuple(b) in turned else _box_corners(np.asarray(b) * np.tile(size, 2))
                          for b in placed], float).reshape(-1, 4, 2)
    for font in dict.fromkeys((fontsize, _SMALLER_ALONG)):
        length, height = text_size(ax.figure, label.text, font, renderer)
        steps = np.arange(0.0, lowest, gap)
        # (steps, sides, 4 corners, 2): down the line, each step right of it, then left
        candidates = np.stack([_parallel(line[0], down, normal, steps, length, height, offset)
                               for line, down, normal in sides], axis=1).reshape(-1, 4, 2)
        ok = np.all((candidates[..., 0] >= inner[0]) & (candidates[..., 0] <= inner[2])
                    & (candidates[..., 1] >= inner[1]) & (candidates[..., 1] <= inner[3]), axis=1)
        ok &= outlines_apart(candidates, obstacles, 2.0 * gap)
        for k in _nearest_own_in_order(_free_chunks(curves, candidates, np.nonzero(ok)[0], size), candidates,
                                       own_segments, other_segments):
                box = tuple(float(c) for c in np.concatenate([candidates[k].min(axis=0), candidates[k].max(axis=0)])
                            / np.tile(size, 2))
                placed.append(box)
                turned[box] = candidates[k] / size
                return dataclasses.replace(label, angle=angle, fontsize=font_points(font)), box
    return None


def _box_corners(box):
    """Corners (4, 2) of ``box`` (left, bottom, right, top), counter-clockwise."""
    return np.array([(box[0], box[1]), (box[2], box[1]), (box[2], box[3]), (box[0], box[3])], float)


def outlines_apart(candidates, obstacles, gap=0.0):
    """Mask (K,): whether each of ``candidates`` (K, 4, 2), rectangles (turned or not, corners in
    order), lies at least ``gap`` apart from every one of ``obstacles`` (M, 4, 2) (one unit, e.g.
    pixels): separating axes, the rectangles' edge directions."""
    candidates = np.asarray(candidates, float).reshape(-1, 4, 2)
    obstacles = np.asarray(obstacles, float).reshape(-1, 4, 2)
    if not len(obstacles) or not len(candidates):
        return np.ones(len(candidates), bool)

    def axes_of(rects):                     # (N, 2, 2): the two edge directions' normals
        edges = np.stack([rects[:, 1] - rects[:, 0], rects[:, 2] - rects[:, 1]], axis=1)
        lengths = np.maximum(np.hypot(edges[..., 0], edges[..., 1]), 1e-300)
        return np.stack([-edges[..., 1], edges[..., 0]], axis=-1) / lengths[..., None]

    k, m = len(candidates), len(obstacles)
    axes = np.concatenate([np.broadcast_to(axes_of(candidates)[:, None], (k, m, 2, 2)),
                           np.broadcast_to(axes_of(obstacles)[None], (k, m, 2, 2))], axis=2)    # (K, M, 4, 2)
    a = np.einsum("kcd,kmad->kmac", candidates, axes)          # (K, M, 4 axes, 4 corners)
    b = np.einsum("mcd,kmad->kmac", obstacles, axes)
    apart = (a.max(axis=3) + gap <= b.min(axis=3)) | (b.max(axis=3) + gap <= a.min(axis=3))
    return np.all(np.any(apart, axis=2), axis=1)


def font_points(font) -> float:
    """Size [points] of a font size given as points or a name ('x-small')."""
    from matplotlib.font_manager import FontProperties

    return float(FontProperties(size=font).get_size_in_points())


def _parallel(point, down, normal, steps, length, height, gap):
    """Corners (S, 4, 2) [pixels] of a text ``length`` x ``height`` parallel to the straight line
    through ``point`` along ``down`` (unit vector), beginning ``steps`` (S,) down from ``point``,
    ``gap`` from the line on the side of ``normal``."""
    start = point + steps[:, None] * down + gap * normal
    return np.stack([start, start + length * down, start + length * down + height * normal,
                     start + height * normal], axis=1)


class _Segments:
    """The segments of a polyline (n, 2) [pixels], for :func:`_distance_to` from many points at
    once, with the same arithmetic point by point (so the same floats)."""

    def __init__(self, path):
        self.a = path[:-1]
        self.ab = path[1:] - self.a
        self.square = np.maximum(np.einsum("ij,ij->i", self.ab, self.ab), 1e-12)

    def distances(self, points):
        """Distance (k,) [pixels] from each of ``points`` (k, 2) to the polyline."""
        t = np.clip(np.einsum("kij,ij->ki", points[:, None, :] - self.a, self.ab) / self.square, 0.0, 1.0)
        gaps = self.a + t[..., None] * self.ab - points[:, None, :]
        return np.min(np.hypot(gaps[..., 0], gaps[..., 1]), axis=1)


def _free_chunks(curves, candidates, indices, size):
    """The ``indices`` of ``candidates`` (K, 4, 2) [pixels] whose outlines no curve crosses
    (:meth:`CurveMap.free_outlines`, axes fraction: ``size`` [pixels]), in order, a chunk of
    :data:`_OUTLINE_CHUNK` at a time as they are asked for: arrays of indices."""
    for start in range(0, len(indices), _OUTLINE_CHUNK):
        part = indices[start:start + _OUTLINE_CHUNK]
        yield part[curves.free_outlines(candidates[part] / size)]


def _nearest_own_in_order(chunks, candidates, own, others):
    """The indices (in order) of ``candidates`` (K, 4, 2) [pixels] from ``chunks`` whose centre
    lies nearer the nearest of the ``own`` polylines (:class:`_Segments`) than every one of
    ``others``: a chunk's candidates against one other line at a time, only those still in."""
    for part in chunks:
        if not len(part):
            continue
        centres = candidates[part].mean(axis=1)
        mine = np.min([o.distances(centres) for o in own], axis=0)
        alive = np.ones(len(part), bool)
        for other in others:
            alive[alive] = mine[alive] < other.distances(centres[alive])
            if not alive.any():
                break
        yield from part[alive]


def _distance_to(path, point) -> float:
    """Distance [pixels] from ``point`` to the polyline ``path`` (n, 2)."""
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - point).T)))


def nearest_own_exit(box, label, others, size=(1.0, 1.0)) -> bool:
    """Whether a top-edge label's ``box`` lies no farther from its own exits along the edge than
    from any other line's exit (as near: lines leaving together), so that a label slid along its
    row cannot read as another line's. A label at the right or left edge: whether its box's
    centre lies no farther from its own lines (``paths``) than from any other label's, measured
    in pixels (``size``: the axes' width and height [pixels]); a step away from its exit put
    '1X pump' under the 1X motor line where a logarithmic axis squeezed the order lines 20 pixels
    apart."""
    if label.edge != "top":
        if not label.paths:
            return True
        scale = np.asarray(size, float)
        centre = np.array([0.5 * (box[0] + box[2]), 0.5 * (box[1] + box[3])]) * scale
        own = min(_distance_to(np.asarray(path, float) * scale, centre) for path in label.paths if len(path) > 1)
        return all(own <= _distance_to(np.asarray(path, float) * scale, centre)
                   for other in others for path in other.paths if len(path) > 1)
    if label.paths and box[1] < 1.0 - _ROWS * (box[3] - box[1]) * 1.5:
        own = _gap_at_height(box, label.paths)
        return own < np.inf and all(own <= _gap_at_height(box, o.paths) for o in others)

    def gap(lo, hi):
        return max(lo - box[2], box[0] - hi, 0.0)

    own = gap(label.u, label.u + label.spread)
    return all(own <= gap(o.u, o.u + o.spread) for o in others if o.edge == "top")


def first_free_box(candidates, placed, gap=(0.0, 0.0), frame=(0.0, 0.0, 1.0, 1.0), obstacles=(), allowed=None,
                   cost=None, bound=None, each=None):
    """The first of ``candidates`` inside ``frame`` and clear of every box in ``placed``.

    Boxes are (left, bottom, right, top) in one coordinate system; ``gap`` (along x, y) is
    kept from the boxes placed; ``obstacles`` (markers) are only not overlapped; ``allowed``
    (a function of a box, optional) must also say True (e.g. a leader line crossing no label,
    no curve through the box: :meth:`CurveMap.free`). ``each`` (optional), a function of an
    (n, 4) array of candidates giving a mask (n,), must say True too: it is asked of a few
    candidates at a time (:data:`_EACH_CHUNKS`), in their order, and ``allowed`` only of those
    it passes (the tests of one box each, made on many boxes at once; the same answers). With
    ``cost`` (a function of a box), the free candidate of least cost is taken instead of the
    first (the first of equals);
    ``bound`` (a function of a box, not above its cost and not decreasing along the
    candidates) ends the search where no later candidate can cost less.
    The box taken is appended to ``placed``.

    Returns
    -------
    tuple or None
    """
    best = None
    clear = np.nonzero(_inside_and_clear(candidates, placed, gap, frame, obstacles))[0]
    passed = _passed_in_chunks(candidates, clear, each)
    for n, k in enumerate(clear):
        candidate = candidates[k]
        if best is not None and bound is not None and bound(candidate) >= best[0]:
            break
        if (passed is None or passed(n)) and (allowed is None or allowed(candidate)):
            if cost is None:
                best = (0.0, candidate)
                break
            score = cost(candidate)
            if best is None or score < best[0]:
                best = (score, candidate)
    if best is None:
        return None
    placed.append(best[1])
    return best[1]


#: :func:`first_free_box` asks its ``each`` about 8 candidates, then 24, then 64 at a time
#: (the box taken is often among the first few)
_EACH_CHUNKS = (8, 24, 64)


def _passed_in_chunks(candidates, indices, each):
    """``passed(n)``: ``each``'s verdict on ``candidates[indices[n]]``, asked of the candidates in
    chunks (:data:`_EACH_CHUNKS`) as ``n`` reaches them; None without ``each``."""
    if each is None:
        return None
    boxes, verdicts = as_boxes(candidates), []

    def passed(n):
        while n >= len(verdicts):
            done = len(verdicts)
            size = next((c for c in _EACH_CHUNKS if c > done), _EACH_CHUNKS[-1])
            verdicts.extend(np.asarray(each(boxes[indices[done:done + size]]), bool).reshape(-1).tolist())
        return verdicts[n]
    return passed


def _inside_and_clear(candidates, placed, gap, frame, obstacles):
    """Mask of the ``candidates`` inside ``frame``, ``gap`` clear of ``placed`` and not on ``obstacles``."""
    boxes = as_boxes(candidates)
    ok = (boxes[:, 0] >= frame[0]) & (boxes[:, 1] >= frame[1]) & (boxes[:, 2] <= frame[2]) & (boxes[:, 3] <= frame[3])
    for others, spacing in ((placed, gap), (obstacles, (0.0, 0.0))):
        ok &= ~overlaps_any(boxes, others, spacing)
    return ok


def overlaps_any(boxes, others, gap=(0.0, 0.0)):
    """Mask (n,): whether each of ``boxes`` (n, 4) comes within ``gap`` (along x, y) of any of
    ``others`` (boxes; :func:`_overlap` of every pair at once)."""
    boxes = as_boxes(boxes)
    if not len(others):
        return np.zeros(len(boxes), bool)
    gap_u, gap_v = gap
    b, other = boxes[:, None, :], np.asarray(others, float).reshape(1, -1, 4)
    return np.any((b[..., 0] < other[..., 2] + gap_u) & (other[..., 0] < b[..., 2] + gap_u)
                  & (b[..., 1] < other[..., 3] + gap_v) & (other[..., 1] < b[..., 3] + gap_v), axis=1)


def crosses_any(segments, boxes) -> bool:
    """Whether any of ``segments`` ((start, end) pairs of points) passes through any of ``boxes``
    (Liang-Barsky on every pair at once)."""
    if not len(segments) or not len(boxes):
        return False
    lines = np.asarray(segments, float).reshape(-1, 4)
    boxes = np.asarray(boxes, float).reshape(-1, 4)
    if lines.shape[0] * boxes.shape[0] <= _FEW_PAIRS and np.isfinite(lines).all() and np.isfinite(boxes).all():
        return any(_crosses_box(line, box) for line in lines.tolist() for box in boxes.tolist())
    return bool(np.any(crossing_pairs(lines, boxes)))


def crossing_pairs(segments, boxes):
    """Mask (n, m): whether each of ``segments`` (n, 4) (x0, y0, x1, y1) passes through each of
    ``boxes`` (m, 4) (Liang-Barsky on every pair at once; :func:`crosses_any` is its any)."""
    lines = np.asarray(segments, float).reshape(-1, 1, 4)
    boxes = np.asarray(boxes, float).reshape(1, -1, 4)
    x0, y0, x1, y1 = (lines[..., k] for k in range(4))
    low, high = np.zeros(np.broadcast_shapes(lines.shape[:2], boxes.shape[:2])), 1.0
    for delta, near, far in ((x1 - x0, boxes[..., 0] - x0, boxes[..., 2] - x0),
                             (y1 - y0, boxes[..., 1] - y0, boxes[..., 3] - y0)):
        flat = delta == 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = near / delta, far / delta
        low = np.where(flat, low, np.maximum(low, np.minimum(a, b)))
        high = np.where(flat, np.where((near > 0.0) | (far < 0.0), -1.0, high), np.minimum(high, np.maximum(a, b)))
    return low <= high


#: :func:`crosses_any` tests this many (segment, box) pairs or fewer one by one (most calls ask
#: about one leader or one box: numpy's set-up cost more than the test)
_FEW_PAIRS = 16


def _crosses_box(line, box) -> bool:
    """Whether the segment ``line`` (x0, y0, x1, y1) passes through ``box`` (x0, y0, x1, y1): one
    pair of :func:`crosses_any`, finite floats, its very operations (the same answer)."""
    x0, y0, x1, y1 = line
    low, high = 0.0, 1.0
    for delta, near, far in ((x1 - x0, box[0] - x0, box[2] - x0), (y1 - y0, box[1] - y0, box[3] - y0)):
        if delta == 0.0:
            if near > 0.0 or far < 0.0:
                high = -1.0
            continue
        a, b = near / delta, far / delta
        low, high = max(low, min(a, b)), min(high, max(a, b))
    return low <= high


def crosses_segments(start, end, segments) -> bool:
    """Whether the segment ``start -> end`` crosses any of ``segments`` ((start, end) pairs);
    segments that share an end point (leaders of one anchor) do not count."""
    if not len(segments):
        return False
    others = np.asarray(segments, float).reshape(-1, 4)
    p, r = np.asarray(start, float), np.asarray(end, float) - np.asarray(start, float)
    q, t = others[:, :2], others[:, 2:] - others[:, :2]
    denominator = r[0] * t[:, 1] - r[1] * t[:, 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        u = (qp[:, 0] * t[:, 1] - qp[:, 1] * t[:, 0]) / denominator
        v = (qp[:, 0] * r[1] - qp[:, 1] * r[0]) / denominator
    inside = (denominator != 0) & (u > 1e-9) & (u < 1 - 1e-9) & (v > 1e-9) & (v < 1 - 1e-9)
    return bool(np.any(inside))


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


#: cell of the grid on which :class:`CurveMap` marks the curves [points]: a label keeps about
#: this far from every curve
_CELL_POINTS = 1.0
#: a curve may run through a label's box this near its anchor (a marker's half size and a gap) [points]
ANCHOR_POINTS = 6.0
#: at most this many points of the curves are marked at once (bounded memory)
_CHUNK = 1_000_000


#: polygons tested together against the marked cells by :meth:`CurveMap.free_outlines`
_OUTLINE_CHUNK = 64


class CurveMap:
    """Where the curves of an axes run as drawn: the cells of a grid over the axes' frame
    that a visible line (or line collection) passes through, each widened by half its line
    width; markers without a line mark their size. A box is free (:meth:`free`) when it
    holds no marked cell (a summed-area table: one look-up per box, whatever the curves'
    number of points).

    Parameters
    ----------
    ax : matplotlib Axes
    renderer
        The figure's renderer, laid out (:func:`laid_out_renderer`).
    skip : iterable of artists
        Lines not to mark (the labels' own leader lines).
    units : {'pixels', 'axes'}
        Coordinates of the boxes asked about: display pixels or the axes' fraction.
    """

    def __init__(self, ax, renderer, skip=(), units="pixels"):
        frame = ax.get_window_extent(renderer)
        self.origin, self.size = (frame.x0, frame.y0), (frame.width, frame.height)
        self.units = units
        self.points = renderer.points_to_pixels(1.0)        # pixels per point
        self.cell = max(_CELL_POINTS * self.points, 0.5)
        width, height = (max(int(np.ceil(d / self.cell)), 1) for d in self.size)
        grid = np.zeros((height, width), bool)
        paths = _drawn_paths(ax, skip, (frame.x0, frame.y0, frame.x1, frame.y1))
        for reach, points in _curve_points(ax, skip, (frame.x0, frame.y0, frame.x1, frame.y1), self.cell, paths):
            marked = np.zeros_like(grid)
            i = np.clip(((points[:, 0] - frame.x0) / self.cell).astype(int), 0, width - 1)
            j = np.clip(((points[:, 1] - frame.y0) / self.cell).astype(int), 0, height - 1)
            marked[j, i] = True
            grid |= _dilate(marked, reach)
        self.grid = grid
        self.table = np.zeros((height + 1, width + 1), np.int64)
        self.table[1:, 1:] = grid.cumsum(axis=0).cumsum(axis=1)
        self._segments = _joined(paths)

    def _cells(self, box):
        """Marked cells overlapping ``box`` widened by half a cell (a crossing between two samples)."""
        if self.units == "axes":
            box = (self.origin[0] + box[0] * self.size[0], self.origin[1] + box[1] * self.size[1],
                   self.origin[0] + box[2] * self.size[0], self.origin[1] + box[3] * self.size[1])
        rows, columns = self.table.shape[0] - 1, self.table.shape[1] - 1
        half = 0.5 * self.cell
        i0 = min(max(int(np.floor((box[0] - half - self.origin[0]) / self.cell)), 0), columns)
        i1 = min(max(int(np.ceil((box[2] + half - self.origin[0]) / self.cell)), 0), columns)
        j0 = min(max(int(np.floor((box[1] - half - self.origin[1]) / self.cell)), 0), rows)
        j1 = min(max(int(np.ceil((box[3] + half - self.origin[1]) / self.cell)), 0), rows)
        if i1 <= i0 or j1 <= j0:
            return 0
        t = self.table
        return int(t[j1, i1] - t[j0, i1] - t[j1, i0] + t[j0, i0])

    def free(self, box, keep=None) -> bool:
        """Whether no curve runs through ``box`` (left, bottom, right, top), but inside ``keep``
        (a box around the label's anchor, where its own curve and marker are, or None)."""
        crossed = self._cells(box)
        if crossed and keep is not None:
            inside = (max(box[0], keep[0]), max(box[1], keep[1]), min(box[2], keep[2]), min(box[3], keep[3]))
            if inside[0] < inside[2] and inside[1] < inside[3]:
                crossed -= self._cells(inside)
        return crossed == 0

    def _cells_each(self, boxes):
        """:meth:`_cells` of each of ``boxes`` (n, 4) at once, shape (n,): the same counts."""
        boxes = np.asarray(boxes, float).reshape(-1, 4)
        if self.units == "axes":
            boxes = np.column_stack([self.origin[0] + boxes[:, 0] * self.size[0], self.origin[1] + boxes[:, 1] * self.size[1],
                                     self.origin[0] + boxes[:, 2] * self.size[0], self.origin[1] + boxes[:, 3] * self.size[1]])
        rows, columns = self.table.shape[0] - 1, self.table.shape[1] - 1
        half = 0.5 * self.cell
        i0 = np.clip(np.floor((boxes[:, 0] - half - self.origin[0]) / self.cell), 0, columns).astype(np.int64)
        i1 = np.clip(np.ceil((boxes[:, 2] + half - self.origin[0]) / self.cell), 0, columns).astype(np.int64)
        j0 = np.clip(np.floor((boxes[:, 1] - half - self.origin[1]) / self.cell), 0, rows).astype(np.int64)
        j1 = np.clip(np.ceil((boxes[:, 3] + half - self.origin[1]) / self.cell), 0, rows).astype(np.int64)
        t = self.table
        counts = t[j1, i1] - t[j0, i1] - t[j1, i0] + t[j0, i0]
        return np.where((i1 <= i0) | (j1 <= j0), 0, counts)

    def free_each(self, boxes, keep=None):
        """:meth:`free` of each of ``boxes`` (n, 4) at once: mask (n,), the same answers (one
        look-up per box in arrays, not one call)."""
        boxes = np.asarray(boxes, float).reshape(-1, 4)
        crossed = self._cells_each(boxes)
        if keep is not None:
            inside = np.column_stack([np.maximum(boxes[:, 0], keep[0]), np.maximum(boxes[:, 1], keep[1]),
                                      np.minimum(boxes[:, 2], keep[2]), np.minimum(boxes[:, 3], keep[3])])
            some = (crossed != 0) & (inside[:, 0] < inside[:, 2]) & (inside[:, 1] < inside[:, 3])
            if some.any():
                crossed[some] -= self._cells_each(inside[some])
        return crossed == 0

    def free_outline(self, corners) -> bool:
        """Whether no curve runs through the convex polygon ``corners`` (n, 2) (a turned
        label's outline, corners in order; in the map's units), nor within a cell of it."""
        return bool(self.free_outlines(np.asarray(corners, float)[None])[0])

    def free_outlines(self, outlines):
        """:meth:`free_outline` of each of the convex polygons ``outlines`` (K, n, 2) at once:
        mask (K,). One look-up in the summed-area table a polygon; the marked cells of the
        window around those not clear there are tested against every polygon's edges together
        (the 60-rotor chain asked 36,000 single polygons, 60 % of its labels' placing)."""
        outlines = np.asarray(outlines, float).reshape(len(outlines), -1, 2)
        free = np.ones(len(outlines), bool)
        if not len(outlines):
            return free
        if self.units == "axes":
            outlines = np.asarray(self.origin) + outlines * np.asarray(self.size)
        rows, columns = self.grid.shape
        lo, hi = outlines.min(axis=1) - self.cell, outlines.max(axis=1) + self.cell
        i0 = np.maximum(np.floor((lo[:, 0] - self.origin[0]) / self.cell), 0).astype(np.int64)
        j0 = np.maximum(np.floor((lo[:, 1] - self.origin[1]) / self.cell), 0).astype(np.int64)
        i1 = np.minimum(np.ceil((hi[:, 0] - self.origin[0]) / self.cell), columns).astype(np.int64)
        j1 = np.minimum(np.ceil((hi[:, 1] - self.origin[1]) / self.cell), rows).astype(np.int64)
        window = (i1 > i0) & (j1 > j0)
        t = self.table
        a, b, c, d = (np.clip(x, 0, n) for x, n in ((i0, columns), (j0, rows), (i1, columns), (j1, rows)))
        marked = window & (t[d, c] - t[b, c] - t[d, a] + t[b, a] > 0)
        asked = np.flatnonzero(marked)
        if not len(asked):
            return free
        for start in range(0, len(asked), _OUTLINE_CHUNK):
            free[asked[start:start + _OUTLINE_CHUNK]] = self._outlines_clear(
                outlines[asked[start:start + _OUTLINE_CHUNK]], *(x[asked[start:start + _OUTLINE_CHUNK]]
                                                                 for x in (i0, j0, i1, j1)))
        return free

    def _outlines_clear(self, polygons, i0, j0, i1, j1):
        """Mask: whether no marked cell's centre in each polygon's window (cells ``i0:i1``,
        ``j0:j1``) lies within a cell of the convex ``polygons`` (a, n, 2) [pixels]."""
        rows, columns = self.grid.shape
        i = i0[:, None] + np.arange(int((i1 - i0).max()))[None]             # (a, wide)
        j = j0[:, None] + np.arange(int((j1 - j0).max()))[None]             # (a, high)
        marked = self.grid[np.minimum(j, rows - 1)[:, :, None], np.minimum(i, columns - 1)[:, None, :]] \
            & (j < j1[:, None])[:, :, None] & (i < i1[:, None])[:, None, :]   # (a, high, wide)
        x = self.origin[0] + (i + 0.5) * self.cell
        y = self.origin[1] + (j + 0.5) * self.cell
        following = np.concatenate([polygons[:, 1:], polygons[:, :1]], axis=1)
        edges = following - polygons
        area = np.sum(polygons[..., 0] * following[..., 1] - following[..., 0] * polygons[..., 1], axis=1)
        outward = np.sign(area)[:, None, None] * np.stack([edges[..., 1], -edges[..., 0]], axis=-1)
        outward /= np.maximum(np.hypot(outward[..., 0], outward[..., 1]), 1e-300)[..., None]
        offsets = np.sum(polygons * outward, axis=2)                                    # (a, n)
        within = marked
        for e in range(polygons.shape[1]):          # each edge's half-plane, widened by a cell
            within = within & (x[:, None, :] * outward[:, e, 0, None, None] + y[:, :, None] * outward[:, e, 1, None, None]
                               - offsets[:, e, None, None] <= self.cell)
        return ~np.any(within, axis=(1, 2))

    def crossings(self, start, end, keep=None) -> int:
        """How many curves the segment ``start -> end`` crosses (runs of marked cells along it),
        those inside ``keep`` not counted (curves a few cells apart count as one: :meth:`cut`
        counts them exactly)."""
        if self.units == "axes":
            start, end = ((self.origin[0] + p[0] * self.size[0], self.origin[1] + p[1] * self.size[1])
                          for p in (start, end))
            if keep is not None:
                keep = (self.origin[0] + keep[0] * self.size[0], self.origin[1] + keep[1] * self.size[1],
                        self.origin[0] + keep[2] * self.size[0], self.origin[1] + keep[3] * self.size[1])
        steps = int(np.hypot(end[0] - start[0], end[1] - start[1]) / (0.5 * self.cell)) + 2
        t = np.linspace(0.0, 1.0, steps)
        x, y = start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])
        i, j = ((x - self.origin[0]) / self.cell).astype(int), ((y - self.origin[1]) / self.cell).astype(int)
        rows, columns = self.grid.shape
        marked = (i >= 0) & (i < columns) & (j >= 0) & (j < rows)
        marked[marked] = self.grid[j[marked], i[marked]]
        if keep is not None:
            inside = (x >= keep[0]) & (x <= keep[2]) & (y >= keep[1]) & (y <= keep[3])
            marked &= ~inside
        return int(np.count_nonzero(marked[1:] & ~marked[:-1]) + marked[0])

    def cut(self, start, end, keep=None) -> int:
        """How many pieces of curve the segment ``start -> end`` crosses outside the box ``keep``
        (a marker's): exact geometry on the curves' drawn segments, not the grid, on which curves
        closer than a few cells merge into one run (compressor_rotor's modes 3, 4 and 5, 4 to 7
        pixels apart: a leader from mode 3's circle across modes 4 and 5 counted as running
        beside its own curve). ``keep`` is a marker's square: the leader is cut where it meets the
        circle inside it (a curve through the square's corner, outside the circle, counts). A
        curve through the marker (its own) meets a leader aimed at the marker only there."""
        # asked again and again about one leader (a label's every place is tried in several
        # stages and passes; the fan's map asked 64,050 times about 23,287 leaders): kept
        key = (tuple(map(float, start)), tuple(map(float, end)), None if keep is None else tuple(map(float, keep)))
        known = self.__dict__.setdefault("_cut", {})
        if key not in known:
            known[key] = self._cut_now(start, end, keep)
        return known[key]

    def _cut_now(self, start, end, keep):
        """:meth:`cut`, counted."""
        if self.__dict__.get("_bounds") is None:
            self._bounds = segment_bounds(self._segments)
        if self.units == "axes":
            return cuts(self._segments, self.origin, self.size, start, end, keep, bounds=self._bounds)
        return cuts(self._segments, (0.0, 0.0), (1.0, 1.0), start, end, keep, bounds=self._bounds)

    def runs_along(self, start, end) -> bool:
        """Whether the leader ``start -> end`` (pixels) runs along a drawn curve
        (:func:`runs_along_each` on the curves' drawn segments, not the grid, on which a leader
        1 to 3 points beside a line lies in no marked cell). Kept: a label's boxes are asked
        about in several stages and passes."""
        key = (*map(float, start), *map(float, end))
        known = self.__dict__.setdefault("_along", {})
        if key not in known:
            known[key] = self._runs_along_now(key)
        return known[key]

    def _runs_along_now(self, leader) -> bool:
        """:meth:`runs_along` of the leader (x0, y0, x1, y1), reckoned: only the segments near it
        and within :data:`ALONG_DEGREES` of its direction go to :func:`runs_along_each` (most
        leaders have none: asked 30,000 times on the fan's map)."""
        x0, y0, x1, y1 = leader
        size = np.hypot(x1 - x0, y1 - y0)
        if size < ALONG_POINTS * self.points or not len(self._segments):
            return False                # shorter than ALONG_POINTS, none does
        if self.__dict__.get("_pieces") is None:
            low, high = segment_bounds(self._segments)
            pieces = self._segments[:, 2:] - self._segments[:, :2]
            self._pieces = (low, high, pieces, np.hypot(pieces[:, 0], pieces[:, 1]))
        low, high, pieces, sizes = self._pieces
        reach = ALONG_REACH_POINTS * self.points
        near = (high[:, 0] >= min(x0, x1) - reach) & (low[:, 0] <= max(x0, x1) + reach) \
            & (high[:, 1] >= min(y0, y1) - reach) & (low[:, 1] <= max(y0, y1) + reach) \
            & (np.abs((x1 - x0) * pieces[:, 1] - (y1 - y0) * pieces[:, 0])
               <= np.sin(np.radians(ALONG_DEGREES)) * size * sizes)
        if not near.any():
            return False
        return bool(runs_along_each(self._segments[near], leader[:2], leader[2:], self.points)[0])

    def along(self, start, end, keep=None) -> float:
        """How much of the segment ``start -> end`` runs on curves (its length on marked cells,
        in the map's units), its part inside ``keep`` not counted: a leader laid along a curve
        is hidden by it."""
        if self.units == "axes":
            scale = np.asarray(self.size, float)
            start, end = np.asarray(start, float) * scale, np.asarray(end, float) * scale
            keep = None if keep is None else (keep[0] * scale[0], keep[1] * scale[1], keep[2] * scale[0],
                                              keep[3] * scale[1])
            origin = (0.0, 0.0)
        else:
            origin = self.origin
        length = float(np.hypot(end[0] - start[0], end[1] - start[1]))
        steps = int(length / (0.5 * self.cell)) + 2
        t = np.linspace(0.0, 1.0, steps)
        x, y = start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])
        i, j = ((x - origin[0]) / self.cell).astype(int), ((y - origin[1]) / self.cell).astype(int)
        rows, columns = self.grid.shape
        marked = (i >= 0) & (i < columns) & (j >= 0) & (j < rows)
        marked[marked] = self.grid[j[marked], i[marked]]
        if keep is not None:
            marked &= ~((x >= keep[0]) & (x <= keep[2]) & (y >= keep[1]) & (y <= keep[3]))
        share = np.count_nonzero(marked) / steps
        return share * length if self.units == "pixels" else share * length / float(np.hypot(*self.size))


def _curve_points(ax, skip, frame, cell, paths):
    """``(reach, points (n, 2))``: points [pixels] every half ``cell`` along each visible curve
    of ``ax`` inside ``frame`` (``paths``: :func:`_drawn_paths`) and each marker of a line
    without a line style, in groups of at most :data:`_CHUNK`; ``reach`` [cells]: half the
    line's width (the marker's size)."""
    points_px = ax.figure.dpi / 72.0
    for line in ax.get_lines():
        if line in skip or not line.get_visible():
            continue
        if line.get_linestyle() not in ("None", "", " ") and line.get_linewidth() != 0:
            continue
        xy = np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        if not len(xy) or line.get_marker() in ("None", "", " ", None):
            continue
        with np.errstate(all="ignore"):
            display = line.get_transform().transform(xy)
        reach = int(round(0.5 * line.get_markersize() * points_px / cell))
        inside = display[np.all(np.isfinite(display), axis=1)]
        yield reach, inside[(inside[:, 0] >= frame[0]) & (inside[:, 0] <= frame[2])
                            & (inside[:, 1] >= frame[1]) & (inside[:, 1] <= frame[3])]
    by_reach = {}
    for width, segments in paths:
        by_reach.setdefault(int(round(0.5 * width * points_px / cell)), []).append(segments)
    for reach, pieces in by_reach.items():
        segments = np.concatenate(pieces)
        steps = np.ceil(np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
                        / (0.5 * cell)).astype(np.int64) + 1
        ends = np.cumsum(steps)
        start = 0
        while start < len(segments):
            stop = max(int(np.searchsorted(ends, ends[start] - steps[start] + _CHUNK, side="right")), start + 1)
            yield reach, _samples(segments[start:stop], steps[start:stop])
            start = stop


#: :func:`cuts` leaves out the segments whose bounding box lies this far [pixels] from the
#: segment's asked about (they cannot cross it; the margin keeps any that round-off might count)
_BOUNDS_MARGIN = 2.0


def segment_bounds(segments):
    """``(low, high)``: each of the ``segments`` ``(n, 4)``' bounding box corners ``(n, 2)``,
    for :func:`cuts`."""
    segments = np.asarray(segments, float).reshape(-1, 4)
    return np.minimum(segments[:, :2], segments[:, 2:]), np.maximum(segments[:, :2], segments[:, 2:])


def cuts(segments, origin, size, start, end, keep=None, bounds=None) -> int:
    """How many of the ``segments`` ``(n, 4)`` [pixels] the segment ``start -> end`` crosses
    outside the marker's square ``keep`` (:meth:`CurveMap.cut`); ``start``, ``end`` and ``keep``
    are in units of ``size`` [pixels] from ``origin`` [pixels] (axes fraction: the axes' origin
    and size; pixels: (0, 0) and (1, 1)). ``bounds`` (:func:`segment_bounds` of ``segments``):
    only the segments whose bounding boxes come near the segment's are tested (the count is the
    same; the work is the few near it, for a leader asked about again and again)."""
    to_px = np.array(size)
    origin = np.array(origin)
    p, q = origin + np.asarray(start, float) * to_px, origin + np.asarray(end, float) * to_px
    if keep is not None:
        keep = np.r_[origin + np.asarray(keep[:2], float) * to_px, origin + np.asarray(keep[2:], float) * to_px]
        q = p + _entry(p, q, keep) * (q - p)
    # (np.allclose's test, written out: it was a tenth of the placing's time)
    if not len(segments) or all(abs(a - b) <= 1e-8 + 1e-5 * abs(b) for a, b in zip(p.tolist(), q.tolist())):
        return 0
    if bounds is not None:
        low, high = np.minimum(p, q) - _BOUNDS_MARGIN, np.maximum(p, q) + _BOUNDS_MARGIN
        near = np.all((bounds[1] >= low) & (bounds[0] <= high), axis=1)
        segments = segments[near]
        if not len(segments):
            return 0
    r, a, t = q - p, segments[:, :2], segments[:, 2:] - segments[:, :2]
    denominator = r[0] * t[:, 1] - r[1] * t[:, 0]
    ap = a - p
    with np.errstate(divide="ignore", invalid="ignore"):
        u = (ap[:, 0] * t[:, 1] - ap[:, 1] * t[:, 0]) / denominator
        v = (ap[:, 0] * r[1] - ap[:, 1] * r[0]) / denominator
    return int(np.count_nonzero((denominator != 0) & (u >= 0) & (u <= 1) & (v >= 0) & (v < 1)))


def cuts_each(segments, origin, size, starts, end, keep=None, bounds=None):
    """:func:`cuts` of each segment ``starts[k] -> end`` (``starts`` (n, 2)) at once: counts (n,),
    the same numbers (each segment's entry into ``keep`` is :func:`_entry`'s, one by one; the
    rest the same operations on arrays, the segments near each leader tested, as ``bounds`` has
    :func:`cuts` test them)."""
    starts = np.asarray(starts, float).reshape(-1, 2)
    counts = np.zeros(len(starts), np.int64)
    if not len(starts) or not len(segments):
        return counts
    to_px, origin = np.array(size), np.array(origin)
    p, q = origin + starts * to_px, origin + np.asarray(end, float) * to_px
    if keep is not None:
        keep = np.r_[origin + np.asarray(keep[:2], float) * to_px, origin + np.asarray(keep[2:], float) * to_px]
        q = p + np.array([_entry(a, q, keep) for a in p])[:, None] * (q - p)
    else:
        q = np.broadcast_to(q, p.shape)
    asked = ~np.all(np.abs(p - q) <= 1e-8 + 1e-5 * np.abs(q), axis=1)
    p, q = p[asked], q[asked]
    if bounds is not None:
        low, high = np.minimum(p, q) - _BOUNDS_MARGIN, np.maximum(p, q) + _BOUNDS_MARGIN
        # those near any of the leaders first (a segment near one is near their span), then each leader's
        some = np.flatnonzero(np.all((bounds[1] >= low.min(axis=0, initial=np.inf))
                                     & (bounds[0] <= high.max(axis=0, initial=-np.inf)), axis=1))
        segments, lo, hi = segments[some], bounds[0][some], bounds[1][some]
        near = np.all((hi[None] >= low[:, None]) & (lo[None] <= high[:, None]), axis=2)   # (n, m)
    else:
        near = True
    r, a, t = (q - p)[:, None, :], segments[None, :, :2], segments[None, :, 2:] - segments[None, :, :2]
    denominator = r[..., 0] * t[..., 1] - r[..., 1] * t[..., 0]
    ap = a - p[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = (ap[..., 0] * t[..., 1] - ap[..., 1] * t[..., 0]) / denominator
        v = (ap[..., 0] * r[..., 1] - ap[..., 1] * r[..., 0]) / denominator
    counts[asked] = np.count_nonzero(near & (denominator != 0) & (u >= 0) & (u <= 1) & (v >= 0) & (v < 1), axis=1)
    return counts


def along_each(segments, starts, ends, reach, degrees, bounds=None):
    """How much of each segment ``starts[k] -> ends[k]`` (``starts``, ``ends`` (n, 2) [pixels])
    runs along the ``segments`` ``(m, 4)`` [pixels]: the length [pixels] of its points that lie
    within ``reach`` [pixels] of a segment whose direction is within ``degrees`` of its own.

    A leader line so near a curve and so nearly parallel to it reads as a piece of that curve,
    or as a second curve beside it, not as a pointer (flexible_pump_on_mounts' '700': 40 points
    long, 3.5 degrees off mode 5's line and under 3 points from it). The points are taken every
    ``reach / 8`` along each segment (each length is exact to that); ``bounds``
    (:func:`segment_bounds` of ``segments``): only the segments near each are tested.

    Returns
    -------
    numpy.ndarray
        (n,) [pixels].
    """
    starts, ends = np.asarray(starts, float).reshape(-1, 2), np.asarray(ends, float).reshape(-1, 2)
    lengths = np.zeros(len(starts))
    segments = np.asarray(segments, float).reshape(-1, 4)
    if not len(starts) or not len(segments):
        return lengths
    low, high = bounds if bounds is not None else segment_bounds(segments)
    ways = ends - starts
    sizes = np.hypot(ways[:, 0], ways[:, 1])
    reach_low, reach_high = np.minimum(starts, ends) - reach, np.maximum(starts, ends) + reach
    # the segments near any of the leaders first, then each leader's: near it, within the angle
    # either way (a curve's direction has no sense here), not a point
    some = np.flatnonzero(np.all((high >= reach_low.min(axis=0)) & (low <= reach_high.max(axis=0)), axis=1))
    segments, low, high = segments[some], low[some], high[some]
    pieces = segments[:, 2:] - segments[:, :2]
    pieces_size = np.hypot(pieces[:, 0], pieces[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        way = ways / sizes[:, None]
    near = np.all((high[None] >= reach_low[:, None]) & (low[None] <= reach_high[:, None]), axis=2)      # (n, m)
    near &= (pieces_size > 0)[None] & (np.abs(way[:, :1] * pieces[None, :, 1] - way[:, 1:] * pieces[None, :, 0])
                                       <= np.sin(np.radians(degrees)) * pieces_size[None])
    step = reach / 8.0
    for k in np.flatnonzero((sizes > 0) & near.any(axis=1)):
        near[k, near[k]] = _segment_distances(starts[k], ends[k], segments[near[k]]) <= reach * (1 + 1e-9)
        if not near[k].any():
            continue
        count = int(np.ceil(sizes[k] / step))
        fractions = (np.arange(count) + 0.5) / count
        first, piece, size = segments[near[k], :2], pieces[near[k]], pieces_size[near[k]]
        fractions = fractions[_beside(fractions * sizes[k], starts[k], way[k], first, first + piece, reach)]
        points = starts[k] + fractions[:, None] * ways[k]        # (count, 2), those that may lie within reach
        t = np.clip(((points[:, None, :] - first[None]) * piece[None]).sum(axis=2) / (size * size)[None], 0.0, 1.0)
        off = points[:, None, :] - (first[None] + t[..., None] * piece[None])
        within = np.any(off[..., 0] ** 2 + off[..., 1] ** 2 <= reach * reach, axis=1)
        lengths[k] = np.count_nonzero(within) * sizes[k] / count
    return lengths


def _segment_distances(start, end, segments):
    """The shortest distance [pixels] between the segment ``start -> end`` ((2,) each [pixels]) and
    each of the ``segments`` ``(m, 4)`` [pixels]: 0 where they cross, else the least of the four
    distances from an end of one to the other. Shape (m,).

    :func:`along_each` tests only the segments within its reach of a leader (a point of the leader
    can lie within the reach of no other): a long leader across a dense figure had its thousand
    points tested against a thousand segments of its bounding box (60 ms, half of a report's
    unbalance figure)."""
    a, b = np.asarray(start, float), np.asarray(end, float)
    c, d = segments[:, :2], segments[:, 2:]
    distances = np.minimum(np.minimum(_point_distances(c, a, b), _point_distances(d, a, b)),
                           np.minimum(_to_segments(a, c, d), _to_segments(b, c, d)))
    def side(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])
    crossing = ((side(a, b, c) * side(a, b, d) <= 0) & (side(c, d, a) * side(c, d, b) <= 0))
    return np.where(crossing, 0.0, distances)


def _beside(along, start, way, c, d, reach):
    """Mask of the points ``start + along[i] * way`` (``along`` (count,) [pixels], ``way`` a unit
    vector) that lie beside a segment ``c[j] -> d[j]`` ((m, 2) each [pixels]): whose position along
    the leader is within ``reach`` [pixels] of the segment's shadow on it. A point farther along
    lies farther than ``reach`` from every segment (its distance is at least the gap of shadows)."""
    ends = np.stack([(c - start) @ way, (d - start) @ way], axis=1)
    slack = reach * (1 + 1e-9) + 1e-9
    low, high = ends.min(axis=1) - slack, ends.max(axis=1) + slack
    order = np.argsort(low)
    low, high = low[order], np.maximum.accumulate(high[order])
    last = np.searchsorted(low, along, side="right") - 1          # the last shadow starting before each point
    return (last >= 0) & (along <= high[np.maximum(last, 0)])


def _point_distances(points, a, b):
    """Distances [pixels] of ``points`` (m, 2) from the one segment ``a -> b`` ((2,) each)."""
    way = b - a
    size2 = float(way @ way)
    t = np.zeros(len(points)) if size2 == 0 else np.clip((points - a) @ way / size2, 0.0, 1.0)
    off = points - (a + t[:, None] * way)
    return np.hypot(off[:, 0], off[:, 1])


def _to_segments(point, c, d):
    """Distances [pixels] of the one ``point`` (2,) from each segment ``c[j] -> d[j]`` ((m, 2) each)."""
    way = d - c
    size2 = np.einsum("ij,ij->i", way, way)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(size2 > 0, np.clip(np.einsum("ij,ij->i", point - c, way) / size2, 0.0, 1.0), 0.0)
    off = point - (c + t[:, None] * way)
    return np.hypot(off[:, 0], off[:, 1])


#: a leader line within this many points of a drawn curve, at an angle below :data:`ALONG_DEGREES`
#: to it, over :data:`ALONG_POINTS` or more and :data:`ALONG_SHARE` of its length or more, runs
#: along that curve: it reads as a piece of it or as a second curve beside it
#: (flexible_pump_on_mounts' Campbell '700' hung 40 points right of its circle on a leader 3.5
#: degrees off mode 5's line and under 3 points from it; the fan's UCS '3394/3644/3943', 60 points
#: along mode 5's line 1 to 3 points beside it). No label takes such a leader. (Nearer than about
#: 4 points, two thin lines read as one doubled line; within 15 degrees, as parallel over a
#: label's width.)
ALONG_REACH_POINTS, ALONG_DEGREES, ALONG_POINTS, ALONG_SHARE = 4.0, 15.0, 8.0, 1 / 3


def runs_along_each(segments, starts, ends, points, degrees=ALONG_DEGREES, bounds=None):
    """Whether each leader ``starts[k] -> ends[k]`` (``starts``, ``ends`` (n, 2) [pixels]) runs
    along one of the drawn ``segments`` ``(m, 4)`` [pixels] (:data:`ALONG_REACH_POINTS`,
    ``degrees``, :data:`ALONG_POINTS`, :data:`ALONG_SHARE`; :func:`along_each`); ``points``: pixels
    per point; ``bounds``: :func:`segment_bounds` of ``segments`` (optional). Mask (n,)."""
    starts, ends = np.asarray(starts, float).reshape(-1, 2), np.asarray(ends, float).reshape(-1, 2)
    along = along_each(segments, starts, ends, ALONG_REACH_POINTS * points, degrees, bounds)
    return along >= np.maximum(ALONG_POINTS * points, ALONG_SHARE * np.hypot(*(ends - starts).T))


def short_of_each(starts, end, clear):
    """The point ``clear`` [pixels] short of ``end`` (2,) toward each of ``starts`` (n, 2) [pixels]:
    a leader's end outside its marker's circle (a curve through the marker meets it there); ``end``
    itself for a start nearer than that. Shape (n, 2)."""
    starts = np.asarray(starts, float).reshape(-1, 2)
    way = starts - np.asarray(end, float)
    size = np.hypot(*way.T)
    shorten = np.where(size > clear, clear / np.maximum(size, 1e-300), 0.0)
    return np.asarray(end, float) + shorten[:, None] * way


def widened(boxes, gap):
    """``boxes`` (n, 4) (left, bottom, right, top) widened by ``gap`` on every side, shape (n, 4)."""
    return np.asarray(boxes, float).reshape(-1, 4) + np.array([-gap, -gap, gap, gap])


def _entry(start, end, box) -> float:
    """Where [0, 1] the segment ``start -> end`` enters the disc inscribed in the square ``box``
    (a marker's circle): 1 where it never does."""
    centre = np.array([box[0] + box[2], box[1] + box[3]]) / 2
    radius = min(box[2] - box[0], box[3] - box[1]) / 2
    d, f = np.asarray(end, float) - start, np.asarray(start, float) - centre
    a, b, c = d @ d, 2 * f @ d, f @ f - radius ** 2
    if a == 0.0 or b * b - 4 * a * c < 0.0:
        return 1.0
    t = (-b - np.sqrt(b * b - 4 * a * c)) / (2 * a)
    return float(min(max(t, 0.0), 1.0))


def _drawn_paths(ax, skip, frame):
    """``[(width [points], segments (n, 4) [pixels])]``: each visible line with a line style and
    each path of the visible line collections of ``ax`` but ``skip``, its finite segments
    clipped to ``frame``."""
    from matplotlib.collections import LineCollection

    paths = []
    for line in ax.get_lines():
        if line in skip or not line.get_visible() or line.get_linestyle() in ("None", "", " ") \
                or line.get_linewidth() == 0:
            continue
        xy = np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        if len(xy):
            with np.errstate(all="ignore"):
                paths.append((line.get_transform().transform(xy), line.get_linewidth()))
    for collection in ax.collections:
        if isinstance(collection, LineCollection) and collection.get_visible() and collection not in skip:
            widths = np.atleast_1d(collection.get_linewidth())
            transform = collection.get_transform()
            for n, path in enumerate(collection.get_paths()):
                paths.append((transform.transform(path.vertices), float(widths[n % len(widths)])))
    drawn = []
    for display, width in paths:
        segments = np.hstack([display[:-1], display[1:]])
        drawn.append((width, _clipped(segments[np.all(np.isfinite(segments), axis=1)], frame)))
    return drawn


def _joined(paths):
    """The segments ``(n, 4)`` of all ``paths`` (:func:`_drawn_paths`)."""
    return np.concatenate([segments for _, segments in paths]) if paths else np.zeros((0, 4))


def _drawn_segments(ax, skip, frame):
    """Segments ``(n, 4)`` [pixels] of the visible lines (with a line style) and line
    collections of ``ax`` but ``skip``, clipped to ``frame``."""
    return _joined(_drawn_paths(ax, skip, frame))


def _samples(segments, steps):
    """``steps[k]`` points evenly along each segment ``k`` (its ends included)."""
    owner = np.repeat(np.arange(len(segments)), steps)
    first = np.repeat(np.cumsum(steps) - steps, steps)
    t = (np.arange(len(owner)) - first) / np.maximum(steps[owner] - 1, 1)
    x0, y0, x1, y1 = segments[owner].T
    return np.column_stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0)])


def _clipped(segments, box):
    """The parts ``(m, 4)`` of ``segments`` ``(n, 4)`` inside ``box`` (Liang-Barsky, vectorised)."""
    x0, y0, x1, y1 = segments.T
    dx, dy = x1 - x0, y1 - y0
    low, high = np.zeros(len(segments)), np.ones(len(segments))
    for delta, near, far in ((dx, box[0] - x0, box[2] - x0), (dy, box[1] - y0, box[3] - y0)):
        flat = delta == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = near / delta, far / delta
        low = np.where(flat, low, np.maximum(low, np.minimum(a, b)))
        high = np.where(flat, np.where((near > 0) | (far < 0), -1.0, high), np.minimum(high, np.maximum(a, b)))
    keep = low <= high
    low, high, x0, y0, dx, dy = low[keep], high[keep], x0[keep], y0[keep], dx[keep], dy[keep]
    return np.column_stack([x0 + low * dx, y0 + low * dy, x0 + high * dx, y0 + high * dy])


def _dilate(grid, reach):
    """``grid`` with every marked cell widened by ``reach`` cells each way."""
    for axis in (0, 1):
        wide = grid.copy()
        for shift in range(1, reach + 1):
            if axis == 0:
                wide[shift:] |= grid[:-shift]
                wide[:-shift] |= grid[shift:]
            else:
                wide[:, shift:] |= grid[:, :-shift]
                wide[:, :-shift] |= grid[:, shift:]
        grid = wide
    return grid


def anchor_box(x, y, half):
    """The square of half size ``half`` around an anchor: where its own curves may cross its label."""
    return (x - half, y - half, x + half, y + half)


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


#: :func:`lay_out_again_when` lays a figure out at most this many more times per layout
_MOST_LAYOUTS = 3


def lay_out_again_when(fig, grown):
    """Have each constrained layout of ``fig`` call ``grown(renderer)`` when done, and lay the
    figure out once more where it returns True (and so on, at most :data:`_MOST_LAYOUTS` more
    times).

    For labels whose words depend on the axes' laid-out size (the Campbell diagram's shared
    right-edge labels, its legend's count of the critical speeds labelled): ``grown`` sets them
    for the axes as laid out and says whether they now take more room than the layout left
    them; the next layout leaves it. Only on a figure with constrained layout (its engine, and
    its settings, are kept inside); else nothing.
    """
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    inner = fig.get_layout_engine()
    if not isinstance(inner, ConstrainedLayoutEngine):
        return

    class _LaidOutAgain(type(inner)):
        def __init__(self):             # noqa: D401 - the inner engine's state, not a new one
            self.__dict__.update(inner.__dict__)

        def execute(self, figure):
            inner.execute(figure)
            for _ in range(_MOST_LAYOUTS):
                if not grown(figure._get_renderer()):
                    break
                ConstrainedLayoutEngine.execute(inner, figure)

        def set(self, **settings):
            inner.set(**settings)
            self.__dict__.update(inner.__dict__)

    fig.set_layout_engine(_LaidOutAgain())


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
            # never across another source's line: the label would stand beside lines it does not name
            between = any(o.edge == label.edge and o.suffix != label.suffix
                          and start < (o.u, o.v)[along] < (label.u, label.v)[along] for o in labels)
            if not between and (label.u, label.v)[along] - (start + last.spread) < size(last.text)[along]:
                spread = (label.u, label.v)[along] - start
                merged[-1] = EdgeLabel(_join(last.prefix, label.prefix), last.suffix, last.color, last.edge,
                                       last.u, last.v, last.direction, spread, paths=last.paths + label.paths)
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
                for side, sign in ((behind, away), (ahead, -away))] + _down_the_line(label, w, h, pad_u, pad_v)
    lo, hi = label.v, label.v + label.spread
    left = 1.0 - pad_u - w if label.edge == "right" else pad_u
    # then stepping away from the line by quarter heights (below a rising line: past its fall
    # over the label's width), up to one and a half heights
    steps = [k * h / 4 for k in range(1, _STEPS + 1)]
    # then beside the line farther back: above it on the edge's side, below it on the other
    rising = [(u - w if label.edge == "right" else u, v + pad_v) for u, v in label.back if not label.spread]
    falling = [(u if label.edge == "right" else u - w, v - pad_v - h) for u, v in label.back if not label.spread]
    return [(left, hi + pad_v), (left, lo - pad_v - h)] \
        + [corner for step in steps for corner in ((left, hi + pad_v + step), (left, lo - pad_v - h - step))] \
        + [(left, hi + 2 * pad_v + h), (left, lo - 2 * (pad_v + h))] \
        + [corner for pair in zip(rising, falling) for corner in pair]


def _down_the_line(label, w, h, pad_u, pad_v):
    """Lower-left corners of boxes beside a top-edge line farther down (its ``back`` points), on
    the side where the line runs away from the box: above it on its rising side, below it on
    the other (where the exits at the top are too crowded for the label)."""
    if label.spread:
        return []
    corners = []
    for u, v in label.back:
        if label.direction > 0:
            corners += [(u - pad_u - w, v + pad_v), (u + pad_u, v - pad_v - h)]
        else:
            corners += [(u + pad_u, v + pad_v), (u - pad_u - w, v - pad_v - h)]
    return corners


def _gap_at_height(box, paths):
    """Horizontal gap between ``box`` and the nearest of ``paths`` (polylines (u, v)) at the
    box's middle height (inf where none reaches that height)."""
    middle = 0.5 * (box[1] + box[3])
    gap = np.inf
    for path in paths:
        u = _u_at_heights(path, [middle])[0] if len(path) >= 2 else np.nan
        if np.isfinite(u):
            gap = min(gap, max(box[0] - u, u - box[2], 0.0))
    return gap


def _u_at_heights(path, heights) -> np.ndarray:
    """u (H,) of the polyline ``path`` (points (u, v), at least two) at each of ``heights`` (H,),
    nan where it does not reach that height."""
    points = np.asarray(path, float)
    order = np.argsort(points[:, 1])
    v, heights = points[order, 1], np.asarray(heights, float)
    u = np.interp(heights, v, points[order, 0])
    return np.where((v[0] <= heights) & (heights <= v[-1]), u, np.nan)


def _overlap(a, b, gap_u, gap_v):
    return a[0] < b[2] + gap_u and b[0] < a[2] + gap_u and a[1] < b[3] + gap_v and b[1] < a[3] + gap_v


def exits_of_orders(orders, lines, slopes, x_limits, top, bottom=0.0, to_axes=None, to_axes_many=None):
    """:class:`EdgeLabel` of every order line ``f = slope |x|``.

    ``lines`` is a list of (name, multiplier, colour), one per source; ``slopes[i][o]`` the
    slope of line ``i``'s order ``orders[o]`` [Hz per unit of the plotted speed]; ``bottom`` and ``to_axes`` as
    for :func:`line_exit`; ``to_axes_many``, optional, the same map for arrays ``(x (n,), f (n,))
    -> (n, 2)``, with the same floats point by point (the lines' paths in one call each, not 200).
    Lines of several sources that coincide (twin rotors at one speed,
    a rotor's 2X on another's 1X) get one label naming them all, in the colour of the one
    drawn last (on top, the one seen): ``1X upper & lower``, ``2X motor = 1X fan``.
    """
    labels = []
    for slope, members in _coinciding_orders(orders, lines, slopes):
        exit_ = line_exit(slope, x_limits, top, bottom, to_axes)
        if exit_ is not None:
            path = _line_path(slope, x_limits, top, bottom, to_axes, exit_[3], to_axes_many)
            back = _back_along(slope, x_limits, top, bottom, to_axes, exit_[3]) if exit_[0] != "top" \
                else _down_from_top(path)
            labels.append(EdgeLabel(*_order_words(members), members[-1][2], *exit_, back=back,
                                    paths=(path,) if len(path) > 1 else ()))
    return labels


#: samples of a line's path inside the axes; a top-edge label may slide down it in this many steps
_PATH_SAMPLES, _DOWN_STEPS = 200, 25


def _line_path(slope, x_limits, top, bottom, to_axes, direction, to_axes_many=None):
    """Points (u, v) of ``f = slope |x|`` inside the box, from its far end toward ``x = 0``
    (geometric steps where the box's bottom is above 0: a logarithmic axis); ``to_axes_many``
    (see :func:`exits_of_orders`) maps them all at once."""
    lo, hi = x_limits
    far = min(hi, top / slope) if direction > 0 else max(lo, -top / slope)
    near_limit = max(lo, 0.0) if direction > 0 else min(hi, 0.0)
    near = direction * max(abs(near_limit), max(bottom, 0.0) / slope)
    if abs(far) <= abs(near) or far * direction <= 0:
        return ()
    x = np.geomspace(far, near, _PATH_SAMPLES) if near != 0 else np.linspace(far, near, _PATH_SAMPLES)
    if to_axes is None:
        points = [((a - lo) / (hi - lo), (slope * abs(a) - bottom) / (top - bottom)) for a in x]
    elif to_axes_many is not None:
        points = np.asarray(to_axes_many(x, np.array([slope * abs(a) for a in x])), float).tolist()
    else:
        points = [to_axes(a, slope * abs(a)) for a in x]
    return tuple((float(u), float(v)) for u, v in points)


def _down_from_top(path):
    """Points of ``path`` (from the top edge down) every 1/:data:`_DOWN_STEPS` of the height."""
    if len(path) < 2:
        return ()
    heights = [1.0 - k / _DOWN_STEPS for k in range(1, _DOWN_STEPS)]
    return tuple((float(u), v) for u, v in zip(_u_at_heights(path, heights), heights) if np.isfinite(u))


def _coinciding_orders(orders, lines, slopes):
    """``[(slope, [(order, name, colour), ...]), ...]``: the order lines in the order they are
    drawn (source by source, order by order), those of one slope (to 1e-9) together."""
    groups = []
    for (name, _, color), line_slopes in zip(lines, slopes):
        for order, slope in zip(orders, line_slopes):
            slope = float(np.abs(slope))
            same = [g for g in groups if np.isclose(g[0], slope, rtol=1e-9, atol=0.0)]
            if same:
                same[0][1].append((order, name, color))
            else:
                groups.append((slope, [(order, name, color)]))
    return groups


def _order_words(members):
    """(prefix, suffix) of a label of coinciding lines: ``('1X', 'upper & lower')`` where the
    orders are one (``'a, b & c'`` for three), else ``('2X', 'motor = 1X fan')``. ('1X upper,
    lower' read as two labels, the second naming no order: counter_rotating's.)"""
    first = f"{members[0][0]:g}X"
    if all(order == members[0][0] for order, _, _ in members):
        names = [name for _, name, _ in members]
        return first, " & ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
    return first, " = ".join([members[0][1]] + [f"{order:g}X {name}" for order, name, _ in members[1:]])


#: a line's points back from its exit: this many steps of 1/50 of the axes' width
_BACK_STEPS = 25


def _back_along(slope, x_limits, top, bottom, to_axes, direction):
    """Points (u, v) of ``f = slope |x|`` back from the side edge it leaves by, inside the box."""
    lo, hi = x_limits
    far = hi if direction > 0 else lo
    points = []
    for k in range(1, _BACK_STEPS + 1):
        x = far - direction * k * (hi - lo) / 50.0
        f = slope * abs(x)
        if not bottom < f < top or x * direction <= 0:
            break
        points.append(tuple(float(c) for c in to_axes(x, f)) if to_axes is not None
                      else ((x - lo) / (hi - lo), (f - bottom) / (top - bottom)))
    return tuple(points)


#: half size of the marker at a point label's anchor, kept free of labels [points]
_MARKER_POINTS = 3.0

#: a label with a leader line may sit this many rows (label heights) above and below its
#: point, and this many columns (label widths) right and left of it
_GRID_ROWS, _GRID_COLUMNS = 8, 2
#: ... and, where no such box is clear of the curves, this many (farther, above the curves)
_FAR_ROWS, _FAR_COLUMNS = 24, 4
#: ... with rows this many times closer than a label's height and gap, where every label is
#: written (``crossing``): the fan's UCS map had room for '3943' between mode 8's line and mode
#: 6's above it, 5 to 15 pixels up, that no row met; the Campbell diagram's critical-speed labels
#: too (compressor_rotor at 0:15000:151: the 23 pixels between modes 2 and 3 below '11115' held no row)
_ROW_SPLIT = 3
#: labels with fewer boxes than this whose leaders cross no curve are placed first, fewest first
_FREEDOM = 16
#: a leader line crossing a curve costs as much as this many label heights farther away
_CROSSING_COST = 2.0
#: a label whose leader crosses curves and costs more (label heights: its distance and its
#: leader's crossings) is left out
_MOST_COST = 12.0

#: without crossings (``place_point_labels(crossing=False)``) a leader line is at most this many
#: label heights long
_LONGEST_LEADER = 6.0

#: a leader's length laid along curves (hidden by them) counts this many times its length
_ALONG_COST = 2.0

#: a box below the point counts this many times as far (a peak's curve falls away below it)
_BELOW = 2.0
#: a Campbell diagram's leader line keeps at least this many points (its centre line to the box)
#: off every other label's text box: nearer, it reads as touching the text
#: (unstable_cross_coupled's '11.8' Hz ran 0.3 points over the '10.9' label's top). A point
#: leaves about 0.75 point of white beside a 0.5-point line, 1.5 pixels at 150 dpi and 1 at 100
#: dpi, outside the box, whose top is near the digits' tops; half a point left about one pixel at
#: 150 dpi, which the eye closes
LEADER_GAP_POINTS = 1.0


def boxes_around(x, y, w, h, pad, clear, rows=_GRID_ROWS, columns=_GRID_COLUMNS, across=False, split=1, straddle=()):
    """:func:`boxes_around_array` as a :class:`BoxRows`."""
    return BoxRows(boxes_around_array(x, y, w, h, pad, clear, rows, columns, across, split, straddle))


def boxes_around_array(x, y, w, h, pad, clear, rows=_GRID_ROWS, columns=_GRID_COLUMNS, across=False, split=1,
                       straddle=()):
    """Boxes of size ``w x h`` on a grid around the point ``(x, y)``, nearest first.

    Rows are centred on the point's height and a little more than ``pad`` apart (so that
    round-off cannot bring neighbours within ``pad``), up to ``rows`` each way;
    columns lie right and left of the point (none across it: its leader lines would block
    the others'; with ``across``, also one centred on it, for a short straight leader up
    or down), half a label's width apart, reaching ``columns`` label widths each way,
    clear of the point's marker (half size ``clear``). Nearest is by the distance from the point to the box, those below the point
    counted :data:`_BELOW` times; ties: above before below, right before left. With ``split``,
    rows also at that many steps between (a gap between two curves a little more than a
    label's height holds a box only where a row falls into it). With ``straddle`` (fractions of
    the width), only columns across the point: each box that far left of it (a short, steep
    leader up or down, where every leader at a slant crosses a curve).

    Parameters
    ----------
    x, y, w, h, pad, clear : float
        One unit (e.g. pixels).

    Returns
    -------
    numpy.ndarray
        (n, 4): left, bottom, right, top.
    """
    pad = 1.25 * pad
    steps = np.arange(2 * columns - 1) * (w + pad) / 2
    lefts = np.column_stack([x + clear + pad + steps, x - clear - pad - w - steps]).ravel()
    if across:
        lefts = np.concatenate([[x - w / 2], lefts])
    if len(straddle):
        lefts = x - w * np.asarray(straddle, float)
    heights = np.array(sorted(range(-rows * split, rows * split + 1), key=lambda k: (abs(k), k < 0)), float) / split
    bottoms = np.repeat(y - h / 2 + heights * (h + pad), len(lefts))
    lefts = np.tile(lefts, len(heights))
    boxes = np.column_stack([lefts, bottoms, lefts + w, bottoms + h])
    du = np.maximum(np.maximum(boxes[:, 0] - x, x - boxes[:, 2]), 0.0)
    dv = np.maximum(np.maximum(boxes[:, 1] - y, _BELOW * (y - boxes[:, 3])), 0.0)
    return boxes[np.argsort(np.hypot(du, dv), kind="stable")]


class BoxRows:
    """Boxes (left, bottom, right, top) as an (n, 4) array (``array``), read as tuples: one at a
    time (``boxes[k]``, made when asked: :func:`first_free_box` reads few of many), or all by
    iterating (each made once then, and kept: the UCS placer reads every box, some several
    times). Questions about all of them at once read ``array``."""

    def __init__(self, array):
        self.array = np.asarray(array, float).reshape(-1, 4)
        self._rows = None

    def __len__(self):
        return len(self.array)

    def __getitem__(self, k):
        if self._rows is not None:
            return self._rows[k]
        return tuple(self.array[k].tolist())

    def __iter__(self):
        if self._rows is None:
            self._rows = [tuple(box) for box in self.array.tolist()]
        return iter(self._rows)


def as_boxes(boxes):
    """``boxes`` (a :class:`BoxRows`, a list of boxes or an array) as an (n, 4) array."""
    array = getattr(boxes, "array", None)
    return array if array is not None else np.asarray(boxes, float).reshape(-1, 4)


def box_distance(box, x, y) -> float:
    """Distance from the point ``(x, y)`` to ``box``, below the point counted :data:`_BELOW` times."""
    du = max(box[0] - x, 0.0, x - box[2])
    dv = max(box[1] - y, 0.0, _BELOW * (y - box[3]))
    return float(np.hypot(du, dv))


def box_distances(boxes, x, y):
    """:func:`box_distance` of each of ``boxes`` (n, 4) at once, shape (n,): the same numbers (the same
    operations, element by element)."""
    boxes = as_boxes(boxes)
    du = np.maximum(np.maximum(boxes[:, 0] - x, 0.0), x - boxes[:, 2])
    dv = np.maximum(np.maximum(boxes[:, 1] - y, 0.0), _BELOW * (y - boxes[:, 3]))
    return np.hypot(du, dv)


def place_point_labels(ax, anchors, texts, colors, fontsize="x-small", renderer=None, curves=None, crossing=True,
                       members=None):
    """Annotate points of ``ax`` in the order given, each label inside the axes and apart.

    Each label takes the free box (:func:`first_free_box`: inside the axes, clear of every
    label placed before and of every anchor, its leader line crossing no label and no other
    leader line (with ``crossing``: where some box allows), and no leader line crossing it, and no curve of the axes running through it but within
    :data:`ANCHOR_POINTS` of its own anchor: :class:`CurveMap`) of a grid around its anchor
    (:func:`boxes_around`) that costs least: its distance plus :data:`_CROSSING_COST` label
    heights for each curve its leader line crosses; a leader line joins the box's point
    nearest the anchor to the anchor. No leader runs along a drawn line (:func:`runs_along_each`)
    or passes within :data:`LEADER_GAP_POINTS` of another label (with ``crossing``: where every
    label finds a box so; else the labels are placed again without that gap, kept if more are).
    Labels crowded at one point so fan out in columns beside it. A label with no free box, or whose leader crosses curves at a cost above
    :data:`_MOST_COST` label heights, is left out: give the anchors most important first. With
    ``crossing``, the labels that have a box whose leader neither crosses nor runs along a curve
    take such boxes first, those with fewest first; the others follow, in the order given.

    Parameters
    ----------
    anchors : list of (x, y)
        Points in data coordinates.
    texts, colors : list of str
        One per anchor.
    renderer : optional
        From :func:`laid_out_renderer` once the figure is complete.
    curves : CurveMap, optional
        Where the curves run (default: every curve of ``ax`` as drawn now).
    crossing : bool
        Whether a leader line may cross curves (at the cost above); False: only boxes whose
        leader crosses no curve (but within :data:`ANCHOR_POINTS` of its anchor) and is at
        most :data:`_LONGEST_LEADER` label heights long are taken, the nearest, boxes straight
        above and below the anchor among them. True: a leader passes through no other point's
        circle (of :data:`_MARKER_POINTS`) where some box allows, and labels whose leaders cross
        curves after the first pass get another chance (:func:`_second_pass`).
    members : list of list of (x, y), optional
        One per anchor: the other points (data coordinates) that its label names too (a group
        of circles that touch, one label '3939/4184'): kept free of labels like the anchors, and
        its leader may pass through their circles.

    Returns
    -------
    list of matplotlib.text.Annotation
        The labels drawn, in the order of ``anchors`` (left-out ones missing).
    """
    fig = ax.figure
    renderer = renderer or laid_out_renderer(fig)
    curves = curves or CurveMap(ax, renderer)
    frame = ax.get_window_extent(renderer)
    points = fig.dpi / 72.0
    margin, pad = _MARGIN_POINTS * points, _PAD_POINTS * points
    inner = (frame.x0 + margin, frame.y0 + margin, frame.x1 - margin, frame.y1 - margin)
    pixels = [ax.transData.transform((x, y)) for x, y in anchors]
    marker = _MARKER_POINTS * points
    members = [[ax.transData.transform(p) for p in group] for group in members or [[] for _ in anchors]]
    every = [(k, p) for k, group in enumerate(members) for p in group] + list(enumerate(pixels))
    markers = [(px - marker, py - marker, px + marker, py + marker) for _, (px, py) in every]   # keep the points free
    jobs = {}
    for k, ((px, py), text) in enumerate(zip(pixels, texts)):
        if frame.x0 <= px <= frame.x1 and frame.y0 <= py <= frame.y1:
            w, h = text_size(fig, text, fontsize, renderer)
            jobs[k] = (boxes_around(px, py, w, h, pad, marker, _FAR_ROWS, _FAR_COLUMNS, across=not crossing,
                                    split=_ROW_SPLIT if crossing else 1), (px, py), h)
    # with ``crossing``, a plain leader passes through no other point's circle either (the fan's
    # '3959' ran through the circle of '4184', 7 pixels from its own, as if naming it)
    centres, owners = np.array([p for _, p in every], float).reshape(-1, 2), np.array([k for k, _ in every])
    circles = {k: (centres[owners != k], marker) for k in jobs} if crossing else dict.fromkeys(jobs)
    scene = (jobs, markers, (pad, inner), curves, ANCHOR_POINTS * points, crossing, circles)
    boxes = _boxes_of(scene, LEADER_GAP_POINTS * points)
    if crossing and len(boxes) < len(jobs):
        # every label must be written: where the leader's gap leaves some out (twenty two-line
        # labels at one point, in one column each side), leaders may pass next to other labels
        closer = _boxes_of(scene, 0.0)
        boxes = closer if len(closer) > len(boxes) else boxes
    drawn = []
    for k in sorted(boxes):
        (x, y), (px, py), text, color, box = anchors[k], pixels[k], texts[k], colors[k], boxes[k]
        w, h = box[2] - box[0], box[3] - box[1]
        end = nearest_in(box, (px, py))
        drawn.append(ax.annotate(text, (x, y), xytext=((box[0] - px) / points, (box[1] - py) / points),
                                 textcoords="offset points", ha="left", va="bottom", fontsize=fontsize,
                                 color=color, annotation_clip=True,
                                 bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none",
                                       "alpha": 0.75},
                                 arrowprops={"arrowstyle": "-", "color": color, "lw": 0.5, "shrinkA": 0, "shrinkB": 2,
                                             "relpos": ((end[0] - box[0]) / w, (end[1] - box[1]) / h)}))
    return drawn


def _boxes_of(scene, gap):
    """The labels' boxes of :func:`place_point_labels` (index -> box), each leader ``gap``
    [pixels] clear of the other labels. ``scene``: the labels' jobs (index -> (candidate boxes,
    point, height)), the markers' boxes, (pad, frame), the curves, the half size of the square
    around a point where curves may cross its label, ``crossing`` and each label's ``circles``
    (:func:`_leader_box`)."""
    jobs, markers, (pad, inner), curves, keep, crossing, circles = scene
    room = (pad, inner, gap)
    placed = list(markers)
    labels, leaders = [], []        # the boxes and leader lines drawn
    # where every label is written (``crossing``): first the boxes whose leaders cross no curve,
    # the labels with fewest such boxes first, then the others in the order given (the fan's UCS
    # map gave '3394' the one such box of '3644', two circles 5 pixels apart, and '3644' a leader
    # across mode 8); else each label in the order given, the most important first
    stages = [("both", sorted(jobs))]
    if crossing:
        freedom = {k: _leader_box(*job, placed, room, ([], []), curves, keep, crossing, stage="count",
                                  circles=circles[k]) for k, job in jobs.items()}
        stages = [("plain", sorted(jobs, key=lambda k: (freedom[k], k))), ("fallback", sorted(jobs))]
    boxes, plain = {}, set()
    for stage, order in stages:
        for k in order:
            if k in boxes:
                continue
            candidates, (px, py), h = jobs[k]
            box = _leader_box(candidates, (px, py), h, placed, room, (labels, leaders), curves, keep, crossing,
                              stage=stage, circles=circles[k])
            if box is not None:
                boxes[k] = box
                labels.append(box)
                leaders.append((nearest_in(box, (px, py)), (px, py)))
                if stage == "plain":
                    plain.add(k)
    if crossing:
        _second_pass(jobs, boxes, plain, placed, (labels, leaders), (room, curves, keep), circles)
    return boxes


def _second_pass(jobs, boxes, plain, placed, drawn, context, circles):
    """Labels whose leaders cross curves (or left out) after the first pass take a plain box (one
    whose leader crosses no curve, :func:`_leader_box`) where moving one label placed before to
    another plain box makes room: the nearest such label first (compressor_on_journals' UCS map:
    '31284', placed first for its fewer plain boxes, took the row that held the only plain box of
    '31385' beside it, whose leader then crossed mode 3; '31284' had others). ``boxes`` (index ->
    box), ``plain`` (the indices placed so), ``placed`` (boxes and markers) and ``drawn`` (label
    boxes, leader lines) are updated in place; ``context`` is (room, curves, keep) and
    ``circles`` maps each index to its :func:`_leader_box` ``circles``."""
    labels, leaders = drawn
    room, curves, keep = context

    def remove(k):
        box, (px, py) = boxes.pop(k), jobs[k][1]
        placed.remove(box)
        labels.remove(box)
        leaders.remove((nearest_in(box, (px, py)), (px, py)))
        plain.discard(k)
        return box

    def put(k, box, is_plain):
        boxes[k] = box
        labels.append(box)
        leaders.append((nearest_in(box, jobs[k][1]), jobs[k][1]))
        placed.append(box)
        if is_plain:
            plain.add(k)

    def try_plain(k):
        candidates, point, h = jobs[k]
        return _leader_box(candidates, point, h, placed, room, drawn, curves, keep, True, stage="plain",
                           circles=circles[k])

    for k in [k for k in sorted(jobs) if k not in plain]:
        point, h = jobs[k][1], jobs[k][2]
        near = sorted((j for j in plain if box_distance(boxes[j], *point) <= _MOST_COST * h),
                      key=lambda j: box_distance(boxes[j], *point))
        for j in near:
            old_k = remove(k) if k in boxes else None
            old_j = remove(j)
            new_k = try_plain(k)
            if new_k is not None:
                labels.append(new_k)            # the moved label keeps clear of it and of its leader
                leaders.append((nearest_in(new_k, jobs[k][1]), jobs[k][1]))
            new_j = try_plain(j) if new_k is not None else None
            if new_k is not None:
                labels.pop()
                leaders.pop()
            for box in (new_k, new_j):
                if box is not None:
                    placed.remove(box)
            if new_k is not None and new_j is not None:
                put(k, new_k, True)
                put(j, new_j, True)
                break
            put(j, old_j, True)
            if old_k is not None:
                put(k, old_k, False)


def _leader_box(candidates, point, h, placed, room, drawn, curves, keep, crossing=True, stage="both", circles=None):
    """The box of ``candidates`` for a label of height ``h`` joined to ``point`` by a leader
    line, of least cost (:func:`place_point_labels`), or None.

    ``room`` is (pad between labels, frame, the leader's gap from other labels; pixels), ``drawn`` (label boxes, leader lines) drawn so far, ``keep``
    the half size of the square around ``point`` where curves may cross the label (and its
    leader), ``crossing`` whether the leader may cross curves beyond it. ``stage``: 'plain'
    only a box whose leader neither crosses nor runs along a curve (nor, with ``circles``,
    passes through another point's circle), 'fallback' only the others, 'both' the first where
    it has one, else the second; 'count' returns how many plain boxes there are (up to
    :data:`_FREEDOM`, nothing placed). In every stage no box is taken whose leader runs along a
    drawn line (:meth:`CurveMap.runs_along`, beyond the marker) or passes within ``room``'s gap of
    another label (nor another leader as near the box). ``circles``: (centres (n, 2), radius) of every point's
    circle, or None.
    """
    labels, leaders = drawn
    square = anchor_box(*point, keep)
    quick = {}          # box -> (clear of curves, labels and leaders; and its leader crossing no leader)
    pad, frame, gap = room
    marker = keep * _MARKER_POINTS / ANCHOR_POINTS

    lying = {}          # box -> whether its leader runs along a drawn line

    def runs_along(box):
        # the leader as seen: from the box to the marker's circle (a curve through the marker meets
        # it); one shorter than ALONG_POINTS runs along none
        if box not in lying:
            (x, y), (px, py) = nearest_in(box, point), point
            size = math.hypot(x - px, y - py)
            lying[box] = size >= ALONG_POINTS * curves.points + marker and curves.runs_along(
                (x, y), (px + marker / size * (x - px), py + marker / size * (y - py)))
        return lying[box]

    def clear(box, apart=True):
        if box not in quick:
            _clear_each([box], point, (labels, leaders), curves, square, quick, gap)
        return quick[box][1 if apart else 0] and not runs_along(box) \
            and (crossing or (not curves.crossings(nearest_in(box, point), point, square)
                              and not curves.cut(nearest_in(box, point), point, circle)
                              and np.hypot(*np.subtract(nearest_in(box, point), point)) <= _LONGEST_LEADER * h))

    def crossing_cost(box):
        start = nearest_in(box, point)
        return box_distance(box, *point) + _CROSSING_COST * h * (curves.crossings(start, point, square)
                                                                 + _through_circles(start, point, circles))

    def cost(box):
        # (defined before ``circle``, read when called) a leader's length along curves counts
        # twice: the fan's '3943' took a box 58 pixels off along its own curve over one whose
        # leader crossed a curve (not in the limit: a label is left out for its crossings only)
        return crossing_cost(box) + _ALONG_COST * curves.along(nearest_in(box, point), point, circle)

    # a leader across a curve, or laid along one, reads as naming a point of that curve or is
    # hidden (the fan's UCS map: the 3e6 N/m crossing's '3943' stood 39 pixels right of its
    # circle, its leader along the mode's line, beside the next line's circle): first the
    # nearest box within the cost's reach whose leader does neither beyond the marker
    circle = anchor_box(*point, marker)

    def plain(box):
        start = nearest_in(box, point)
        return clear(box) and not curves.cut(start, point, circle) and curves.along(start, point, circle) <= 0.5 * h \
            and not _through_circles(start, point, circles)

    near = BoxRows(as_boxes(candidates)[box_distances(candidates, *point) <= _MOST_COST * h])
    _clear_each(near, point, drawn, curves, square, quick, gap)
    if stage == "count":
        free = np.nonzero(_inside_and_clear(near, placed, (pad, pad), frame, ()))[0]
        return sum(1 for _ in zip(range(_FREEDOM), (k for k in free if plain(near[k]))))
    if stage != "fallback":
        box = first_free_box(near, placed, (pad, pad), frame, allowed=plain, cost=lambda b: box_distance(b, *point),
                             bound=lambda b: box_distance(b, *point))
        if box is not None or stage == "plain":
            return box
    # a leader crossing another leader makes each label seem to point at the other's point:
    # where leaders may cross curves (every label must be written: a map's crossings), they may
    # cross each other too where no box avoids it; else the label is left out
    _clear_each([b for b in candidates if b not in quick], point, drawn, curves, square, quick, gap)
    for apart in (True, False) if crossing else (True,):
        box = first_free_box(candidates, placed, (pad, pad), frame, allowed=lambda b: clear(b, apart), cost=cost,
                             bound=lambda box: box_distance(box, *point))
        if box is not None and crossing_cost(box) > max(_MOST_COST * h, box_distance(box, *point)):
            placed.pop()            # far, its leader across curves: left out
            box = None
        if box is not None:
            return box
    return None


def _clear_each(boxes, point, drawn, curves, square, out, gap=0.0):
    """For each of ``boxes`` (tuples) of a label joined to ``point`` by a leader: whether no curve
    runs through it (but inside ``square``), its leader passes ``gap`` [pixels] clear of every
    label and every leader passes ``gap`` clear of it (``drawn``: label boxes, leader lines:
    nearer than :data:`LEADER_GAP_POINTS`, a leader reads as touching the text; the fan's UCS
    '3608/3939/3943/3959/4184' ran its leader against the curve number '8'); and whether, besides,
    its leader crosses no other leader. Written into ``out`` (box -> (bool, bool)); every box at
    once, the same answers as :meth:`CurveMap.free`, :func:`crosses_any` and
    :func:`crosses_segments` box by box (a crowded UCS map asked them 60,000 times one by one)."""
    if not len(boxes):
        return
    labels, leaders = drawn
    array = as_boxes(boxes)
    starts = np.column_stack([np.minimum(np.maximum(point[0], array[:, 0]), array[:, 2]),
                              np.minimum(np.maximum(point[1], array[:, 1]), array[:, 3])])
    ok = curves.free_each(array, square)
    if len(labels):
        ways = np.column_stack([starts, np.broadcast_to(np.asarray(point, float), starts.shape)])
        ok &= ~np.any(crossing_pairs(ways, widened(labels, gap)), axis=1)
    if len(leaders):
        ok = ok & ~np.any(crossing_pairs(leaders, widened(array, gap)), axis=0)
    apart = ok & ~_segments_crossed(starts, point, leaders) if len(leaders) else ok
    out.update(zip(boxes, zip(ok.tolist(), apart.tolist())))


def _segments_crossed(starts, end, segments):
    """:func:`crosses_segments` of each segment ``starts[k] -> end`` (``starts`` (n, 2)) at once: mask (n,)."""
    others = np.asarray(segments, float).reshape(1, -1, 4)
    p = np.asarray(starts, float).reshape(-1, 1, 2)
    r = np.asarray(end, float) - p
    q, t = others[..., :2], others[..., 2:] - others[..., :2]
    denominator = r[..., 0] * t[..., 1] - r[..., 1] * t[..., 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        u = (qp[..., 0] * t[..., 1] - qp[..., 1] * t[..., 0]) / denominator
        v = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / denominator
    inside = (denominator != 0) & (u > 1e-9) & (u < 1 - 1e-9) & (v > 1e-9) & (v < 1 - 1e-9)
    return np.any(inside, axis=1)


def _through_circles(start, end, circles) -> bool:
    """Whether the segment ``start -> end`` passes through a circle of ``circles`` ((centres (n, 2),
    radius) or None: the other labels' points) whose centre lies outside the circle around ``end``
    (those that overlap its own nearly whole cannot be missed)."""
    if circles is None:
        return False
    centres, radius = circles
    start, end = np.asarray(start, float), np.asarray(end, float)
    others = centres[np.hypot(*(centres - end).T) > radius]
    if not len(others):
        return False
    d = end - start
    t = np.clip((others - start) @ d / max(float(d @ d), 1e-300), 0.0, 1.0)
    return bool(np.any(np.hypot(*(start + t[:, None] * d - others).T) < radius))


def touching_groups(centres, within, chain=True, beside=None):
    """Indices of the points ``centres`` (n, 2) [pixels] in groups whose circles read as one:
    each point closer than ``within`` [pixels] to another of its group (``chain``: through a
    chain of such points), else (not ``chain``) to the group's first, so that a group stays
    within one circle; with ``beside`` [pixels], points more than half a pixel apart across
    (side by side, not on one vertical line) touch closer than that. Groups in the order of
    their first points, members in the order given; one label names each group (the Campbell
    diagram's critical speeds, the UCS map's crossings).

    Returns
    -------
    list of list of int
    """
    centres = np.asarray(centres, float).reshape(-1, 2)

    def touch(g, j):
        apart = centres[g if chain else g[:1]] - centres[j]
        reach = within if beside is None else np.where(np.abs(apart[:, 0]) > 0.5, beside, within)
        return bool(np.any(np.hypot(*apart.T) < reach))

    groups = []
    for j in range(len(centres)):
        near = [g for g in groups if touch(g, j)]
        if not near:
            groups.append([j])
            continue
        near[0].append(j)
        for g in near[1:] if chain else []:          # j joins groups that were apart
            near[0] += g
            groups.remove(g)
    return [sorted(g) for g in groups]


def nearest_in(box, point):
    """The point of ``box`` nearest ``point``: where a leader line from ``point`` meets the box."""
    return min(max(point[0], box[0]), box[2]), min(max(point[1], box[1]), box[3])


def nearest_each(boxes, point):
    """:func:`nearest_in` of each of ``boxes`` (n, 4) at once: the points (n, 2), the same numbers."""
    boxes = as_boxes(boxes)
    return np.column_stack([np.minimum(np.maximum(point[0], boxes[:, 0]), boxes[:, 2]),
                            np.minimum(np.maximum(point[1], boxes[:, 1]), boxes[:, 3])])


def operating_band(ax, low, high, label, vertical=True, edge=True, gid=None):
    """The operating speed range under a figure's curves: a grey band from ``low`` to ``high``
    [speed axis units] where ``high > low``, else a dashed line at ``low`` (one speed), named
    ``label`` in the legend.

    ``vertical``: the speed on the x axis (``axvspan``/``axvline``, Campbell diagrams), else on
    the y axis (``axhspan``/``axhline``, the UCS map); ``edge`` False draws the band without its
    outline; ``gid`` names the artist (in an SVG)."""
    if high > low:
        span = ax.axvspan if vertical else ax.axhspan
        span(low, high, color="0.6", alpha=0.25, zorder=0.5, label=label, gid=gid,
             **({} if edge else {"linewidth": 0}))
    else:
        line = ax.axvline if vertical else ax.axhline
        line(low, color="0.35", linestyle="--", linewidth=1.2, zorder=0.6, label=label, gid=gid)
