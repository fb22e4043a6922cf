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
def fan_every_bearing(ucs_figure):
    """``fan_every_bearing(units)``: (map, its figure), plotted once per worker with
    test_figures33's SI one (conftest.ucs_figure)."""
    return lambda units: ucs_figure("fan_on_bearings", (1e5, 1e9, 41), units=units,
                                    bearings=["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"],
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

    result, fig = fan_every_bearing(units)
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


# -- the orbit figure: every tick label on the saved figure ------------------------------------

def _saved_texts(fig, dpi=DPI):
    """Save ``fig`` as the command line does (PNG at ``dpi``) and measure, in the renderer that
    draws the file, each axes' drawn tick labels (those inside its limits) and texts: a list
    of (axes, x tick label boxes, every box with its text), and the figure's box [pixels]."""
    import io

    measured = []

    def measure(event):
        renderer = event.renderer
        measured.clear()
        for ax in fig.axes:
            def inside(axis, lo_hi):
                lo, hi = sorted(lo_hi)
                slack = 1e-9 * (hi - lo)
                return [t.label1 for t in axis.get_major_ticks()
                        if lo - slack <= t.get_loc() <= hi + slack and t.label1.get_visible() and t.label1.get_text()]
            xs = inside(ax.xaxis, ax.get_xlim())
            ys = inside(ax.yaxis, ax.get_ylim())
            texts = xs + ys + [t for t in ax.texts if t.get_visible() and t.get_text()] \
                + [ax.title, ax.xaxis.label, ax.yaxis.label]
            measured.append((ax, [t.get_window_extent(renderer) for t in xs],
                             [(t.get_text(), t.get_window_extent(renderer)) for t in texts if t.get_text()]))
        measured.append(event.canvas.figure.bbox.frozen())

    hook = fig.canvas.mpl_connect("draw_event", measure)
    fig.savefig(io.BytesIO(), format="png", dpi=dpi)
    fig.canvas.mpl_disconnect(hook)
    return measured[:-1], measured[-1]


@pytest.mark.parametrize("example, top, units", [("flexible_pump_on_mounts", 3600.0, "us"),
                                                 ("flexible_pump_on_mounts", 3600.0, "si"),
                                                 ("fan_on_bearings", 9000.0, "si")])
def test_the_orbit_figures_tick_labels_stay_on_the_saved_figure_and_apart(example, top, units):
    """``unbalance EXAMPLE --speeds TOP/100:TOP:201 --plot-orbits`` (saved at 150 dpi): every
    tick label and text of every orbit panel lies inside the figure, the speed axis's labels
    apart, and each panel still draws its orbits to scale (as many pixels per unit across as
    up) with the largest orbit (the table's major semi-axis, ``result.orbits()``) inside the
    limits. On the base, the pump orbit's '0.010' (US units) ran off the figure's right edge:
    the panels' limits widened for the equal aspect after the layout had made room for the
    tick labels it knew. (The SI cases guard the change: they pass on the base too.)"""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(top / 100.0, top, 201)))
    fig = result.plot_orbits(units=units)
    panels, figure = _saved_texts(fig)
    assert panels
    for ax, xs, texts in panels:
        for text, box in texts:
            assert figure.x0 - 0.5 <= box.x0 and box.x1 <= figure.x1 + 0.5 \
                and figure.y0 - 0.5 <= box.y0 and box.y1 <= figure.y1 + 0.5, (ax.get_title(), text, box, figure)
        xs = sorted(xs, key=lambda b: b.x0)
        for a, b in zip(xs, xs[1:]):
            assert a.x1 < b.x0, (ax.get_title(), a, b)
    # to scale: equal pixels per unit across and up (as saved: the layout at 150 dpi)
    fig.set_dpi(DPI)
    fig.canvas.draw()
    table = result.orbits()
    mil = 1e6 / 25.4 if units == "us" else 1e6
    for ax, _, _ in panels:
        (x0, y0), (x1, y1) = ax.transData.transform([(0.0, 0.0), (1.0, 1.0)])
        assert np.isclose(x1 - x0, y1 - y0, rtol=0.01), ax.get_title()      # an ellipse's shape within 1 %
        # every line drawn lies inside the limits (nothing clipped), the largest orbit filling the
        # panel: its major semi-axis (the table's, at the speed its legend names) reaches more
        # than half way to the edge
        pair, source = ax.get_title().split(", 1X ")
        rows = table[(table["pair"] == pair.replace(" / ", "/")) & (table["source"] == source)]
        drawn = [rows.loc[(rows["speed_rpm"] - float(line.get_label().split()[0])).abs().idxmin(), "major"] * mil
                 for line in ax.get_lines() if line.get_label().endswith(" rpm")]
        assert drawn, ax.get_title()
        reach = min(ax.get_xlim()[1], ax.get_ylim()[1], -ax.get_xlim()[0], -ax.get_ylim()[0])
        assert 0.5 * reach < max(drawn), (ax.get_title(), drawn, reach)
        for line in [line for line in ax.get_lines() if line.get_transform() == ax.transData]:   # not the zero lines
            xy = np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float)
            assert np.all(np.abs(xy) <= reach), (ax.get_title(), line.get_label())
    plt.close(fig)
