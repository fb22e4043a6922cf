"""Every figure the command line draws, looked at (issue 27 §3, figs35).

- The fan's UCS map with every bearing chosen: '3644' stood 28.7 points from its circle (and
  nearer the 3394 rpm circle than its own), '8029/8514' 27 points from its circles and nearer
  the 6956 rpm circle. A label naming two or more circles may now stand on two lines.

Measured on the drawn figure at the saved 150 dpi; the circles' places come from the analysis'
results (stiffness and speed of each crossing; critical speeds), never from the plotting code.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
DPI = 150.0
POINTS = DPI / 72.0
#: N/m in one lbf/in (0.45359237 kg x 9.80665 m/s^2 / 0.0254 m)
LBF_PER_IN = 0.45359237 * 9.80665 / 0.0254
#: a leader longer than this [points] no longer reads as joining a label to its circle
LONG_LEADER = 24.0


@pytest.fixture(scope="module")
def fan_every_bearing():
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    return rdm.ucs_map(model, np.geomspace(1e5, 1e9, 41), bearings=["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"],
                       operating=(1000.0 * np.pi / 30.0, 3000.0 * np.pi / 30.0))


def _box_distance(box, point):
    """Distance [pixels] from ``point`` to the box (0 inside it)."""
    return float(np.hypot(min(max(point[0], box.x0), box.x1) - point[0], min(max(point[1], box.y0), box.y1) - point[1]))


def _written(text):
    """The speeds [rpm] a crossing label writes, on one line or several ('8029/\\n8514')."""
    return [float(part) for part in text.replace("\n", "/").split("/") if part]


@pytest.mark.parametrize("units", ["si", "us"])
def test_every_fan_bearing_crossing_label_stands_by_its_own_circles(fan_every_bearing, units):
    """fan_on_bearings, every bearing chosen (1e5 .. 1e9 N/m, 41 values, operating 1000 .. 3000
    rpm), SI and US: every crossing label stands at most 24 points from the nearest circle it
    names, and nearer a circle it names than any circle it does not name; the labels lie inside
    the axes and apart. On the base '3644' stood 28.7 points away, '8029/8514' 27 points and
    nearer the 6956 rpm circle than its own."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Annotation, Text

    result = fan_every_bearing
    fig = result.plot(units=units)
    fig.set_dpi(DPI)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    frame = ax.get_window_extent(renderer)
    factor = 1.0 if units == "si" else 1.0 / LBF_PER_IN
    speeds = np.array([c.speed * 30.0 / np.pi for c in result.crossings])
    circles = ax.transData.transform(np.column_stack([[c.stiffness * factor for c in result.crossings], speeds]))
    labels = [t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() != "ucs-end-name" and t.get_visible()
              and t.get_text()[:1].isdigit() and len(t.get_text()) >= 3]
    assert len(labels) >= 8
    boxes = [Text.get_window_extent(t, renderer) for t in labels]
    named = set()
    for text, box in zip(labels, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, text.get_text()
        written = _written(text.get_text())
        mine = np.array([any(abs(s - w) <= 0.5 for w in written) for s in speeds])
        assert mine.any(), text.get_text()
        named |= {round(w) for w in written}
        own = min(_box_distance(box, c) for c in circles[mine])
        assert own <= LONG_LEADER * POINTS, (text.get_text(), own / POINTS)
        others = [_box_distance(box, c) for c in circles[~mine]]
        assert own < min(others), (text.get_text(), own / POINTS, min(others) / POINTS)
    assert named == {round(s) for s in speeds}          # every crossing written
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
    plt.close(fig)
