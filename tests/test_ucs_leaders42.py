"""UCS map (issue 27 §3, "figures that cannot mislead"): no crossing label's leader runs along a
curve or touches another label's text.

fan_on_bearings' map as ``ucs-map examples/fan_on_bearings.toml --stiffness 1e5:1e10:26`` (and
``:51``) draws it, measured on the figure laid out at the saved 150 dpi. On the base the leader of
'3394/3644/3943' ran some 60 points along mode 5's line 1 to 3 points beside it (its placer's
test of "along a curve" looked at grid cells the line passes through), and the leader of
'3608/3939/3943/3959/4184' passed under half a point from the curve number '8' (curve numbers are
labels like the others). Measured here from the drawn artists: the annotations' arrows as drawn
and the texts' glyph boxes against the axes' lines as drawn, independent of the placer.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import curve_segments, glyph_box, point_segments_distance, segment_box_distance

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: as the CLI saves its figures
DPI = 150.0
POINT = DPI / 72.0
#: a leader within this many points of a line and within this angle of its direction runs along
#: it where that holds over this many points and this share of its length (the Campbell rule)
REACH, DEGREES, LEAST, SHARE = 4.0, 15.0, 8.0, 1 / 3
#: a leader keeps this many points off every other text
GAP = 1.0
#: the crossings' circles: 6 points across
RADIUS = 3.0


@pytest.fixture(scope="module", params=[26, 51])
def fan_map(request):
    """The fan's map over 1e5 .. 1e10 N/m (the CLI's defaults: every bearing, the 4 lowest
    forward speeds): (result, figure, axes)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.ucs_map(model, np.geomspace(1e5, 1e10, request.param), modes=4)
    fig = result.plot()
    yield result, fig, fig.axes[0]
    plt.close(fig)


def _saved(fig):
    """``fig`` laid out as saved (150 dpi), on an Agg canvas (each test's own: the figures are
    closed after each test, which leaves them a bare canvas): its renderer."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    fig.set_dpi(DPI)
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _labels(ax):
    """The annotations placed among the curves (crossings' speeds, curve numbers): not the names
    beside the right edge."""
    from matplotlib.text import Annotation

    return [t for t in ax.texts if isinstance(t, Annotation) and t.get_visible() and t.get_gid() != "ucs-end-name"]


def _drawn_leader(text, renderer):
    """The annotation's arrow as drawn: segments (k, 4) [display pixels]."""
    text.update_positions(renderer)
    patch = text.arrow_patch
    path = patch.get_path()
    points = patch.get_transform().transform(path.vertices)
    return np.hstack([points[:-1], points[1:]])


def _seen(segment, anchor):
    """The part of ``segment`` (4,) outside the circle of radius :data:`RADIUS` points around
    ``anchor`` (the circle, white-filled, hides what runs inside it); None where none is."""
    a, b = segment[:2], segment[2:]
    samples = a + np.linspace(0.0, 1.0, 801)[:, None] * (b - a)
    outside = np.hypot(*(samples - anchor).T) > RADIUS * POINT
    if not outside.any():
        return None
    kept = samples[outside]
    return np.r_[kept[0], kept[-1]]


def _length_along(segment, curves):
    """Length [pixels] of ``segment`` (4,) whose points lie within :data:`REACH` points of a curve
    segment within :data:`DEGREES` of its direction (sampled every 0.1 point)."""
    a, b = segment[:2], segment[2:]
    size = float(np.hypot(*(b - a)))
    if size == 0.0:
        return 0.0
    direction = (b - a) / size
    pieces = curves[:, 2:] - curves[:, :2]
    lengths = np.hypot(*pieces.T)
    usable = lengths > 0
    cosines = np.abs(pieces[usable] @ direction) / lengths[usable]
    parallel = curves[usable][cosines >= np.cos(np.radians(DEGREES))]
    if not len(parallel):
        return 0.0
    count = max(int(np.ceil(size / (0.1 * POINT))), 1)
    points = a + ((np.arange(count) + 0.5) / count)[:, None] * (b - a)
    near = [point_segments_distance(parallel, p) <= REACH * POINT for p in points]
    return float(np.count_nonzero(near)) * size / count


def test_no_leader_runs_along_a_curve(fan_map):
    """No label's leader, the part outside its circle, lies within 4 points of a drawn line and
    within 15 degrees of its direction over 8 points and a third of its length (base, 26
    values: '3394/3644/3943', 60 of its 62 points beside mode 5's line)."""
    _, fig, ax = fan_map
    renderer = _saved(fig)
    curves = curve_segments(ax)
    for text in _labels(ax):
        anchor = ax.transData.transform(text.xy)
        for segment in _drawn_leader(text, renderer):
            seen = _seen(segment, anchor)
            if seen is None:
                continue
            along = _length_along(seen, curves)
            size = float(np.hypot(*(seen[2:] - seen[:2])))
            assert along < max(LEAST * POINT, SHARE * size), \
                (text.get_text(), round(along / POINT, 1), round(size / POINT, 1))


def test_no_leader_touches_another_text(fan_map):
    """Every label's leader as drawn keeps 1 point off every other text's glyph box inside the
    axes, the curve numbers' among them (base: '3608/3939/3943/3959/4184' under '8')."""
    _, fig, ax = fan_map
    renderer = _saved(fig)
    frame = ax.get_window_extent(renderer)
    texts = [t for t in ax.texts if t.get_visible() and t.get_text().strip()]
    for text in _labels(ax):
        leader = _drawn_leader(text, renderer)
        for other in texts:
            if other is text:
                continue
            box = glyph_box(other, renderer)
            if box.x1 < frame.x0 or box.x0 > frame.x1 or box.y1 < frame.y0 or box.y0 > frame.y1:
                continue
            extents = (box.x0, box.y0, box.x1, box.y1)
            gap = min(segment_box_distance(segment, extents) for segment in leader)
            assert gap >= GAP * POINT, (text.get_text(), other.get_text(), round(gap / POINT, 2))


def test_every_crossing_is_still_written(fan_map):
    """Each crossing inside the axes is read on the figure: in a label or in the note of those
    left out."""
    result, fig, ax = fan_map
    _saved(fig)
    low, high = ax.get_ylim()
    written = {w for t in _labels(ax) for w in t.get_text().replace("\n", "").split("/")}
    written |= {w for t in ax.texts if t.get_gid() == "ucs-note" and t.get_visible()
                for w in re.findall(r"\d+", t.get_text().replace(",", ""))}
    wanted = {f"{c.speed * 30 / np.pi:.0f}" for c in result.crossings if low <= c.speed * 30 / np.pi <= high}
    assert len(wanted) >= 12
    assert wanted <= written, sorted(wanted - written)
