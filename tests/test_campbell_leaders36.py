"""Campbell critical-speed labels whose leader lines cross other modes' curves (issue 27 §3, lead36).

``campbell EXAMPLE --speeds 0:TOP:121 --orders 1,2 --plot c.png``: figs35 counted leaders that
crossed a mode's curve beyond the circle they end at (fan_on_bearings 8, '941' and '1502'
across mode 3's line; flexible_pump_on_mounts 4; motor_pump_on_mounts 6). A leader across
another curve makes the label read as that curve's. Measured on the drawn figure (150 dpi):
the leaders and curves as drawn (``label_geometry``: the lines' data through their own
transforms, exact segment crossings), the labels' glyph boxes, and the critical speeds from the
result's own table, never the placer's numbers.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import assert_each_critical_speed_in_view_is_read, glyph_box

from test_figure_audit27p import _crossed_mode_curves

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: (example, top of the speed range [rpm]: each example's own command line's)
CASES = [("fan_on_bearings.toml", 9000.0), ("flexible_pump_on_mounts.toml", 3600.0),
         ("motor_pump_on_mounts.toml", 3600.0)]


@pytest.mark.parametrize("example,top", CASES)
def test_no_critical_speed_leader_crosses_another_modes_curve(example, top):
    """On the drawn figure: no leader crosses a mode's curve farther than its circle's radius from
    the circle it ends at; every critical speed inside the axes is read in a label or in the
    note of those left out; the labels lie inside the axes and apart."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / example)
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, top, 121)), orders=(1, 2))
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()

    crossed = _crossed_mode_curves(fig, ax, result.critical)
    assert not crossed, crossed

    labels = assert_each_critical_speed_in_view_is_read(ax, result.critical, top)

    frame = ax.get_window_extent(renderer)
    boxes = [glyph_box(t, renderer) for t in labels]
    for t, box in zip(labels, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            (t.get_text(), box, frame)
    for i, a in enumerate(boxes):
        for j in range(i + 1, len(boxes)):
            b = boxes[j]
            overlap = min(a.x1, b.x1) - max(a.x0, b.x0) > 0 and min(a.y1, b.y1) - max(a.y0, b.y0) > 0
            assert not overlap, (labels[i].get_text(), labels[j].get_text())
    plt.close(fig)
