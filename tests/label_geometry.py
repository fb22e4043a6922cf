"""Where a drawn figure's curves run under its labels: measured on the rendered figure.

Independent of the placer (``rotordyn_modal.plotting._labels``): the curves are the axes'
visible lines and line collections as drawn (their data through their own transforms, log
axes included, clipped to the axes' frame), the labels the texts' glyph boxes
(``Text.get_window_extent``), and a crossing is exact geometry (each segment clipped to the
box), not a grid.
"""

from __future__ import annotations

import matplotlib
import numpy as np


def glyph_box(text, renderer):
    """The box of a text's glyphs only (an annotation's own extent includes its leader line)."""
    return matplotlib.text.Text.get_window_extent(text, renderer)


def arrow_segments(ax) -> dict:
    """The 3-D view's drawn arrows by name: segments ``(k, 4)`` x0, y0, x1, y1 [display pixels] of
    each line collection whose gid is ``displaced-arrow:NAME``."""
    arrows = {}
    for collection in ax.collections:
        gid = str(collection.get_gid())
        if gid.startswith("displaced-arrow:"):
            segments = [ax.transData.transform(np.asarray(s, float)) for s in collection.get_segments()]
            arrows[gid.split(":", 1)[1]] = np.concatenate([np.hstack([s[:-1], s[1:]]) for s in segments])
    return arrows


def curve_segments(ax, skip=()):
    """Segments ``(n, 4)``: x0, y0, x1, y1 [display pixels] of every visible curve of ``ax``
    (lines with a line style, line collections), clipped to the axes' frame; ``skip``: artists
    left out (a label's own leader line)."""
    from matplotlib.collections import LineCollection

    frame = ax.get_window_extent()
    pieces = []
    for line in ax.get_lines():
        if line in skip or not line.get_visible() or line.get_linestyle() in ("None", "", " ") \
                or line.get_linewidth() == 0:
            continue
        xy = np.column_stack([np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)])
        if len(xy) < 2:
            continue
        with np.errstate(all="ignore"):
            points = line.get_transform().transform(xy)
        pieces.append(np.hstack([points[:-1], points[1:]]))
    for collection in ax.collections:
        if isinstance(collection, LineCollection) and collection.get_visible() and collection not in skip:
            transform = collection.get_transform()
            for path in collection.get_paths():
                points = transform.transform(path.vertices)
                pieces.append(np.hstack([points[:-1], points[1:]]))
    if not pieces:
        return np.empty((0, 4))
    segments = np.concatenate(pieces)
    segments = segments[np.all(np.isfinite(segments), axis=1)]
    return clip_segments(segments, (frame.x0, frame.y0, frame.x1, frame.y1))


def clip_segments(segments, box):
    """The parts of ``segments`` ``(n, 4)`` inside ``box`` (x0, y0, x1, y1): Liang-Barsky."""
    x0, y0, x1, y1 = segments.T
    dx, dy = x1 - x0, y1 - y0
    low, high = np.zeros(len(segments)), np.ones(len(segments))
    for delta, near, far in ((dx, box[0] - x0, box[2] - x0), (dy, box[1] - y0, box[3] - y0)):
        flat = delta == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = near / delta, far / delta
        outside = flat & ((near > 0) | (far < 0))
        low = np.where(flat, low, np.maximum(low, np.minimum(a, b)))
        high = np.where(flat, high, np.minimum(high, np.maximum(a, b)))
        high = np.where(outside, -1.0, high)
    keep = low <= high
    low, high = low[keep], high[keep]
    x0, y0, dx, dy = x0[keep], y0[keep], dx[keep], dy[keep]
    return np.column_stack([x0 + low * dx, y0 + low * dy, x0 + high * dx, y0 + high * dy])


def crossings(box, segments, anchors=(), radius=0.0, inset=0.5):
    """Points ``(k, 2)`` where a curve runs through ``box`` (shrunk by ``inset`` pixels) farther
    than ``radius`` from every one of ``anchors`` (display points): the ends of each segment's
    part inside the box (a part inside a disc has both its ends in it)."""
    inner = (box.x0 + inset, box.y0 + inset, box.x1 - inset, box.y1 - inset)
    if inner[0] >= inner[2] or inner[1] >= inner[3]:
        return np.empty((0, 2))
    parts = clip_segments(segments, inner)
    ends = parts.reshape(-1, 2)
    if len(anchors) and len(ends):
        anchors = np.asarray(anchors, float).reshape(-1, 2)
        far = np.ones(len(parts), bool)
        for anchor in anchors:
            near = np.all(np.hypot(*(ends - anchor).T).reshape(-1, 2) <= radius, axis=1)
            far &= ~near
        return parts[far].reshape(-1, 2)
    return ends


def segment_crossings(start, end, segments, anchor=None, radius=0.0):
    """Points ``(k, 2)`` where the segment ``start -> end`` (display) crosses ``segments``
    ``(n, 4)`` (exact: both segments' parameters in [0, 1]), those within ``radius`` of
    ``anchor`` left out (a leader line meets its own curve at its anchor)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    d = end - start
    p, q = segments[:, :2], segments[:, 2:]
    e = q - p
    denominator = d[0] * e[:, 1] - d[1] * e[:, 0]
    w = p - start
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / denominator
        u = (w[:, 0] * d[1] - w[:, 1] * d[0]) / denominator
    hit = (denominator != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    points = start + t[hit, None] * d
    if anchor is not None:
        points = points[np.hypot(*(points - np.asarray(anchor, float)).T) > radius]
    return points


def outline(text, renderer):
    """Corners (4, 2) [display pixels] of the turned text's own rectangle: its unturned width
    and height (a copy at angle 0) turned by its angle and fitted into its box as drawn."""
    from matplotlib.text import Text

    box = Text.get_window_extent(text, renderer)
    flat = Text(0, 0, text.get_text(), fontproperties=text.get_fontproperties())
    flat.set_figure(text.figure)
    unturned = flat.get_window_extent(renderer)
    angle = np.radians(text.get_rotation())
    along, across = np.array([np.cos(angle), np.sin(angle)]), np.array([-np.sin(angle), np.cos(angle)])
    corners = np.array([(0.0, 0.0), unturned.width * along, unturned.width * along + unturned.height * across,
                        unturned.height * across])
    corners += np.array([box.x0, box.y0]) - corners.min(axis=0)
    assert abs(corners[:, 0].max() - box.x1) < 1.0 and abs(corners[:, 1].max() - box.y1) < 1.0
    return corners


def outlines_overlap(a, b) -> bool:
    """Whether two convex polygons (n, 2) overlap (separating axes of both's edges)."""
    for polygon in (a, b):
        edges = np.roll(polygon, -1, axis=0) - polygon
        for nx, ny in np.column_stack([-edges[:, 1], edges[:, 0]]):
            pa, pb = a @ (nx, ny), b @ (nx, ny)
            if pa.max() <= pb.min() or pb.max() <= pa.min():
                return False
    return True


def outline_crossings(text, renderer, segments, anchors=(), radius=0.0, inset=0.5):
    """:func:`crossings` of ``segments`` through the text's own (turned) rectangle
    (:func:`outline`), reckoned in the text's frame (along and across its lines); points in
    that frame. For an unturned text the same as through its glyph box."""
    from matplotlib.transforms import Bbox

    corners = outline(text, renderer)
    origin = corners[0]
    along = (corners[1] - origin) / np.hypot(*(corners[1] - origin))
    across = np.array([-along[1], along[0]])
    turn = np.column_stack([along, across])                     # display -> text frame: (p - origin) @ turn

    def local(points):
        return (np.asarray(points, float).reshape(-1, 2) - origin) @ turn

    width, height = np.hypot(*(corners[1] - origin)), np.hypot(*(corners[3] - origin))
    moved = np.hstack([local(segments[:, :2]), local(segments[:, 2:])]) if len(segments) else segments
    return crossings(Bbox([[0.0, 0.0], [width, height]]), moved, local(anchors) if len(anchors) else (),
                     radius, inset)


def named_orders(words):
    """Orders a Campbell label's prefix names: '1X, 2X' -> [1, 2]; a range '2–4X' -> [2, 3, 4]."""
    if "\u2013" in words:
        first, last = (float(w) for w in words.rstrip("X").split("\u2013"))
        return list(np.arange(first, last + 0.5))
    return [float(w.rstrip("X")) for w in words.split(", ")]


def order_lines(ax) -> dict:
    """{slope [Hz per rpm]: (display segment from the origin to the far end inside the axes,
    the line)} of the straight lines through the origin that the figure draws."""
    lines = {}
    (_, x1), (_, y1) = ax.get_xlim(), ax.get_ylim()
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if len(x) > 2 and x[0] == 0 and y[0] == 0 and y[-1] > 0 and np.allclose(y, y[-1] / x[-1] * x, rtol=1e-9):
            slope = y[-1] / x[-1]
            far = min(x1, y1 / slope)
            lines[round(slope, 9)] = (ax.transData.transform([(0.0, 0.0), (far, slope * far)]), line)
    return lines


def point_segment_distance(segment, point) -> float:
    """Display distance of ``point`` (2,) from ``segment`` ((2,), (2,))."""
    a, b = segment
    t = np.clip(np.dot(point - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.hypot(*(a + t * (b - a) - point)))


def named_modes(words):
    """Mode numbers a Campbell mode label names: 'mode 7' -> [7]; a label shared by curves
    whose ends crowd, 'modes 3, 7\u20139' -> [3, 7, 8, 9] (an en dash: a range); a long shared
    label in its compact form, '14 modes: 11, 21, 23 \u2026 111' -> [11, 21, 23, 111] (the
    numbers it writes; an ellipsis: numbers left out, :func:`counted_modes` says how many it
    names in all); [] for any other text."""
    import re

    compact = re.fullmatch(r"(\d+) modes: (\d+(?:(?:, | \u2026 )\d+)*)", words)
    if compact:
        return [int(n) for n in re.split(r", | \u2026 ", compact.group(2))]
    found = re.fullmatch(r"modes? (\d+(?:\u2013\d+)?(?:, \d+(?:\u2013\d+)?)*)", words)
    if not found:
        return []
    numbers = []
    for part in found.group(1).split(", "):
        first, _, last = part.partition("\u2013")
        numbers += list(range(int(first), int(last or first) + 1))
    return numbers


def counted_modes(words):
    """How many modes a Campbell mode label names: the count a compact label states ('14 modes:
    11, 21, 23 \u2026 111' -> 14), else the numbers it writes (:func:`named_modes`)."""
    import re

    compact = re.fullmatch(r"(\d+) modes: .*", words)
    return int(compact.group(1)) if compact else len(named_modes(words))


def order_curves(ax) -> dict:
    """{slope [Hz per unit of speed]: display segments (n, 4) of the line as drawn, clipped to
    the axes} of the straight lines through the origin (the order lines) that ``ax`` draws; on
    a logarithmic frequency axis too, where :func:`order_lines`' straight display segment from
    the origin does not exist (each drawn point through the line's own transform)."""
    frame = ax.get_window_extent()
    curves = {}
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if len(x) > 2 and x[0] == 0 and y[0] == 0 and y[-1] > 0 and np.allclose(y, y[-1] / x[-1] * x, rtol=1e-9):
            with np.errstate(all="ignore"):
                points = line.get_transform().transform(np.column_stack([x, y]))
            segments = np.hstack([points[:-1], points[1:]])
            segments = segments[np.all(np.isfinite(segments), axis=1)]
            curves[round(y[-1] / x[-1], 9)] = clip_segments(segments, (frame.x0, frame.y0, frame.x1, frame.y1))
    return curves


def point_segments_distance(segments, point) -> float:
    """Display distance of ``point`` (2,) from the nearest of ``segments`` (n, 4) (inf for none)."""
    if not len(segments):
        return float("inf")
    a, b = segments[:, :2], segments[:, 2:]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * d - point).T)))


def marker_points(ax) -> list:
    """``(x, y)`` in data units of every point of the axes' marker-only lines (no line style, a
    marker other than a dot): the peak marks an FRF or unbalance figure draws."""
    points = []
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if line.get_linestyle() in ("None", "none", "", " ") and len(x) \
                and line.get_marker() not in (None, "None", "", "."):
            points += list(zip(x, y))
    return points


def assert_each_critical_speed_in_view_is_read(ax, critical, top_rpm, least=20):
    """Assert that each critical speed of ``critical`` (a CriticalSpeeds result) inside the axes
    ``ax`` (0 to ``top_rpm`` [rpm], within the frequency axis' limits; at least ``least`` of them)
    is read in a visible critical-speed label or in the note of those left out, its speed
    rounded to whole rpm; return the visible labels."""
    import re

    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    words = {w for t in labels for w in t.get_text().split("/")}
    note = " ".join(t.get_text() for t in ax.texts if t.get_gid() == "critical-note" and t.get_visible())
    rpm = critical.speeds * 30.0 / np.pi
    low, high = ax.get_ylim()
    shown = (rpm >= 0.0) & (rpm <= top_rpm) & (critical.frequencies_hz >= low) & (critical.frequencies_hz <= high)
    assert shown.sum() >= least
    for speed in rpm[shown]:
        word = f"{speed:.0f}"
        assert word in words or word in re.findall(r"\d+", note), (word, sorted(words), note)
    return labels


def segment_box_distance(segment, box) -> float:
    """Display distance of the segment ``segment`` (x0, y0, x1, y1) from the rectangle ``box``
    (x0, y0, x1, y1): 0 where it runs through the box, else the least of its ends' distances
    from the box and the box's corners' distances from the segment (exact for a segment
    outside a rectangle)."""
    segment = np.asarray(segment, float).reshape(1, 4)
    if len(clip_segments(segment, box)):
        return 0.0
    x0, y0, x1, y1 = box
    ends = [np.hypot(max(x0 - x, 0.0, x - x1), max(y0 - y, 0.0, y - y1)) for x, y in segment.reshape(2, 2)]
    corners = [point_segments_distance(segment, np.array(c, float)) for c in ((x0, y0), (x0, y1), (x1, y0), (x1, y1))]
    return float(min(ends + corners))


def length_inside(segment, box) -> float:
    """Display length of the part of ``segment`` (x0, y0, x1, y1) inside ``box`` (x0, y0, x1, y1)."""
    parts = clip_segments(np.asarray(segment, float).reshape(1, 4), box)
    return float(np.hypot(*(parts[:, 2:] - parts[:, :2]).T).sum()) if len(parts) else 0.0


def leader_lines(ax, gids=("critical-leader",)) -> list:
    """``(line, segments (k, 4) [display pixels])`` of the visible lines of ``ax`` whose gid is one of
    ``gids`` (a Campbell diagram's leader lines), through their own transforms."""
    drawn = []
    for line in ax.get_lines():
        if line.get_visible() and line.get_gid() in gids and len(line.get_xdata()) > 1:
            points = line.get_transform().transform(np.column_stack(line.get_data()))
            drawn.append((line, np.hstack([points[:-1], points[1:]])))
    return drawn
