"""UCS map (issue 27 §3, "figures that cannot mislead"): with every bearing of fan_on_bearings
chosen, each crossing label stands by its own circles (24 points at most) AND its leader neither
runs along a line nor passes by another text.

The map of tests/test_figures35.py (1e5 .. 1e9 N/m, 41 values, operating 1000 .. 3000 rpm).
main met the 24 points with '8029/' over '8514' 17 points up the cyan line (mode 8), its leader
parallel to that line a few points above it; t-ucs42, which forbids such leaders, left
'8029/8514' 27 points and '3394/3644/3943' 44 points from their circles (the latter nearer
6956's circle than its own). Measured on the figure as saved (150 dpi): the arrows as drawn,
the texts' glyph boxes, the circles from the analysis' crossings (tests/test_ucs_leaders42.py's
measures, independent of the placer).
"""

from __future__ import annotations

import numpy as np
import pytest

from label_geometry import curve_segments, glyph_box, segment_box_distance
from test_ucs_leaders42 import GAP, LEAST, POINT, SHARE, _drawn_leader, _labels, _length_along, _saved, _seen

#: a leader longer than this [points] no longer reads as joining a label to its circle
LONG_LEADER = 24.0


@pytest.fixture(scope="module")
def every_bearing(ucs_figure):
    """(result, figure, axes): the fan's map with every bearing chosen, shared with
    test_figures35 and test_figures33 (conftest.ucs_figure)."""
    result, fig = ucs_figure("fan_on_bearings", (1e5, 1e9, 41), bearings=["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"],
                             operating=(1000.0 * np.pi / 30.0, 3000.0 * np.pi / 30.0))
    return result, fig, fig.axes[0]


def _crossing_labels(ax):
    """The crossings' labels (speeds, 3 digits or more; not the curve numbers)."""
    return [t for t in _labels(ax) if t.get_text()[:1].isdigit() and len(t.get_text()) >= 3]


def _box_distance(box, point) -> float:
    return float(np.hypot(min(max(point[0], box.x0), box.x1) - point[0], min(max(point[1], box.y0), box.y1) - point[1]))


def test_every_bearing_labels_stand_by_their_circles_on_clear_leaders(every_bearing):
    """Each crossing label: at most 24 points from the nearest circle it names and nearer it than
    any other circle; its leader, outside its circle, not along a line (4 points, 15 degrees, 8
    points and a third of its length); 1 point off every other text."""
    result, fig, ax = every_bearing
    renderer = _saved(fig)
    frame = ax.get_window_extent(renderer)
    speeds = np.array([c.speed * 30.0 / np.pi for c in result.crossings])
    circles = ax.transData.transform(np.column_stack([[c.stiffness for c in result.crossings], speeds]))
    curves = curve_segments(ax)
    texts = [t for t in ax.texts if t.get_visible() and t.get_text().strip()]
    labels = _crossing_labels(ax)
    assert len(labels) >= 8
    for text in labels:
        box = glyph_box(text, renderer)
        written = [float(w) for w in text.get_text().replace("\n", "/").split("/") if w]
        mine = np.array([any(abs(s - w) <= 0.5 for w in written) for s in speeds])
        own = min(_box_distance(box, c) for c in circles[mine])
        assert own <= LONG_LEADER * POINT, (text.get_text(), round(own / POINT, 1))
        assert own < min(_box_distance(box, c) for c in circles[~mine]), text.get_text()
    for text in _labels(ax):
        anchor = ax.transData.transform(text.xy)
        leader = _drawn_leader(text, renderer)
        for segment in leader:
            seen = _seen(segment, anchor)
            if seen is not None:
                along, size = _length_along(seen, curves), float(np.hypot(*(seen[2:] - seen[:2])))
                assert along < max(LEAST * POINT, SHARE * size), (text.get_text(), round(along / POINT, 1))
        for other in texts:
            box = glyph_box(other, renderer)
            if other is text or box.x1 < frame.x0 or box.x0 > frame.x1 or box.y1 < frame.y0 or box.y0 > frame.y1:
                continue
            gap = min(segment_box_distance(s, (box.x0, box.y0, box.x1, box.y1)) for s in leader)
            assert gap >= GAP * POINT, (text.get_text(), other.get_text(), round(gap / POINT, 2))
