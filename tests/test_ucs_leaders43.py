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
from test_ucs_leaders42 import DPI, GAP, LEAST, POINT, SHARE, _drawn_leader, _labels, _length_along, _saved, _seen

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


# -- a shared label's leader re-pointed to the circle nearest its text ----------------------------

def _shared_label(line=True, blocker=False):
    """A figure (150 dpi) with a label '1234/5678' naming the circles at A = (60, 20) and B = (60,
    50) [data], placed 2 points above y = 50 and left of B, its leader to A (steep, clear of
    everything); ``line``: a line along y = 50 through B; ``blocker``: another text between the
    label and B, on the way of a leader to B. (figure, axes, label, A, B)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4.0, 3.0), dpi=DPI)
    ax.set_xlim(0.0, 100.0)
    ax.set_ylim(0.0, 100.0)
    if line:
        ax.plot([0.0, 100.0], [50.0, 50.0], color="C0", lw=1.5)
    a, b = (60.0, 20.0), (60.0, 50.0)
    fig.canvas.draw()
    to_points = 72.0 / fig.dpi
    a_px, b_px = ax.transData.transform(a), ax.transData.transform(b)
    # the label's box starts 70 points left of B, its bottom 2 points above B
    offset = ((b_px[0] - a_px[0]) * to_points - 70.0, (b_px[1] - a_px[1]) * to_points + 2.0)
    label = ax.annotate("1234/5678", a, xytext=offset, textcoords="offset points", ha="left", va="bottom",
                        fontsize="x-small", arrowprops={"arrowstyle": "-", "shrinkA": 0, "shrinkB": 2,
                                                        "relpos": (1.0, 0.0)})
    if blocker:
        ax.annotate("9", b, xytext=(-16.0, 0.5), textcoords="offset points", fontsize="x-small", va="bottom")
    return fig, ax, label, a, b


def _ends_at(ax, text, renderer):
    """The data point whose circle the drawn leader of ``text`` ends in (its last vertex)."""
    end = _drawn_leader(text, renderer)[-1, 2:]
    return ax.transData.inverted().transform(end)


@pytest.mark.parametrize("case", ["along a line", "through a text"])
def test_a_shared_label_is_not_re_pointed_onto_a_leader_that_breaks_a_rule(case):
    """``_lead_to_nearest`` joins a shared label to the circle nearest its text; where that
    leader (to B, from the label's lower right corner 2 points above the line) would run along
    the line through B, or through the text '9' in its way, the label keeps its leader to A.
    Before, it was re-pointed whatever: 14.5 points of it within 4 points of the line, or
    through '9' (0.0 points from its box)."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.ucs_map import _lead_to_nearest

    fig, ax, label, a, b = _shared_label(line=case == "along a line", blocker=case == "through a text")
    fig.canvas.draw()
    _lead_to_nearest(ax, label, [b], fig.canvas.get_renderer())
    renderer = _saved(fig)
    curves = curve_segments(ax)
    anchor = ax.transData.transform(label.xy)
    for segment in _drawn_leader(label, renderer):
        seen = _seen(segment, anchor)
        if seen is not None and len(curves):
            along, size = _length_along(seen, curves), float(np.hypot(*(seen[2:] - seen[:2])))
            assert along < max(LEAST * POINT, SHARE * size), round(along / POINT, 1)
    for other in ax.texts:
        if other is not label:
            box = glyph_box(other, renderer)
            gap = min(segment_box_distance(s, (box.x0, box.y0, box.x1, box.y1)) for s in _drawn_leader(label, renderer))
            assert gap >= GAP * POINT, round(gap / POINT, 2)
    assert np.allclose(_ends_at(ax, label, renderer), a, atol=3.0)
    plt.close(fig)


def test_a_shared_label_with_a_clear_way_is_still_led_to_its_nearest_circle():
    """Where nothing is in the way, the leader goes to the circle nearest the text (B) as before."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.ucs_map import _lead_to_nearest

    fig, ax, label, a, b = _shared_label(line=False)
    fig.canvas.draw()
    _lead_to_nearest(ax, label, [b], fig.canvas.get_renderer())
    renderer = _saved(fig)
    assert np.allclose(_ends_at(ax, label, renderer), b, atol=3.0)
    plt.close(fig)
