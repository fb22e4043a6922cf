"""Figures looked at once more, example by example: what a reviewer flagged, measured on the
drawn figure (``fig.canvas.draw()``, ``Text.get_window_extent``), independent of the placer."""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import glyph_box

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
ORDER_LABEL = re.compile(r"^((?:\d+(?:\.\d+)?X)(?:, \d+(?:\.\d+)?X)*) (.+)$")


@pytest.fixture(scope="module")
def pump_sweep():
    """motor_pump_on_mounts, 0-3000 rpm, orders 1 and 2 (its modes span 5 Hz to 1.2 kHz)."""
    return rdm.campbell(rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"), rdm.rpm(np.linspace(0, 3000, 61)),
                        orders=(1, 2))


@pytest.fixture(scope="module")
def pump_figure(pump_sweep):
    """``pump_sweep`` drawn to 18.2 Hz (its six mount modes; ``--max-frequency 30``): the figure
    and the renderer it was drawn with (kept: closing the figures after a test drops its canvas)."""
    fig = pump_sweep.plot(freq_range=(0, 18.2))
    fig.canvas.draw()
    return fig, fig.canvas.get_renderer()


def test_every_order_line_of_crowded_exits_is_labelled_beside_its_own_line(pump_sweep, pump_figure):
    """motor_pump_on_mounts to 18.2 Hz, 0-3000 rpm, orders 1 and 2: the four order lines leave
    the top within 1,000 rpm, two pairs a label's width apart; '1X pump' found no room in the
    rows under the top edge and was left out (the line unnamed). Every line is named once, and
    at the height of each label the nearest order line (straight through the origin, slope
    order x multiplier / 60 Hz per rpm from the result's sources) is the one it names."""
    result, (fig, renderer) = pump_sweep, pump_figure
    ax = fig.axes[0]
    slopes = {(order, name): order * multiplier / 60.0 for name, multiplier in
              zip(result.sources.names, result.sources.multipliers) for order in result.orders}
    named = []
    for text in ax.texts:
        match = ORDER_LABEL.match(text.get_text())
        if not (match and text.get_visible()):
            continue
        orders = [float(o.rstrip("X")) for o in match.group(1).split(", ")]
        own = [slopes[(o, match.group(2))] for o in orders]
        named += [(o, match.group(2)) for o in orders]
        box = glyph_box(text, renderer)
        height = ax.transData.inverted().transform(((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2))[1]
        gaps = []
        for slope in set(slopes.values()):
            at = ax.transData.transform((height / slope, height))[0]      # the line's x at that height
            gaps.append((max(box.x0 - at, at - box.x1, 0.0), slope))
        assert min(gaps)[1] in own, (text.get_text(), sorted(gaps)[:2])
    assert sorted(named) == sorted(slopes)


def test_critical_speed_numbers_side_by_side_never_read_as_one(pump_figure):
    """Two critical speeds' labels on one line were placed 0.5 points apart: '286' beside '357'
    (motor_pump_on_mounts to 18.2 Hz), '1157' beside '2313' read '11572313' (rubber_mounts).
    Measured on the glyphs: labels that share a line are at least half a label's height
    apart (about a digit's width), wherever the placer puts them."""
    fig, renderer = pump_figure
    texts = [t for t in fig.axes[0].texts if t.get_visible() and re.fullmatch(r"[\d.]+", t.get_text())]
    boxes = [glyph_box(t, renderer) for t in texts]
    assert len(boxes) >= 12
    for i, a in enumerate(boxes):
        for j, b in enumerate(boxes[i + 1:], i + 1):
            if min(a.y1, b.y1) > max(a.y0, b.y0):                   # on one line
                gap = max(b.x0 - a.x1, a.x0 - b.x1)
                assert gap >= 0.5 * max(a.height, b.height), (texts[i].get_text(), texts[j].get_text(), gap)


def test_level1_top_axis_reads_q_without_a_floating_multiplier():
    """The top axis of the Level I figure read 'Q [N/m]' with ticks 0.25 ... 2.00 and '1e7' in
    the corner (Q = 0.25 N/m at a glance). Each tick's number times its unit's prefix is Q =
    (Q/Qa) Qa at that tick's position on the bottom axis, and no offset or multiplier text is
    shown."""
    import matplotlib.pyplot as plt

    model = rdm.Model(rotors=[rdm.Rotor("r", 20.0, [0.0, 0.0, 0.0], 0.1, 0.5, speed_ratio=1.0)],
                      bearings=[dict(name=n, rotor="r", position=[x, 0.0, 0.0], stiffness=1e6, damping=200.0)
                                for n, x in (("A", 0.4), ("B", -0.4))])
    qa = 2.0e6
    result = rdm.level1(model, rdm.rpm(3000), ["r"], qa=qa)
    fig = result.plot()
    fig.canvas.draw()
    ax = fig.axes[0]
    top = next(child for child in ax.get_children() if type(child).__name__ == "SecondaryAxis")
    unit = re.fullmatch(r"Q \[(k|M|G)?N/m\]", top.get_xlabel())
    assert unit, top.get_xlabel()
    factor = {None: 1.0, "k": 1e3, "M": 1e6, "G": 1e9}[unit.group(1)]
    assert top.xaxis.get_offset_text().get_text() == ""
    renderer = fig.canvas.get_renderer()
    to_data = ax.transData.inverted()
    (left, right), ticks = ax.get_xlim(), []
    for label in top.get_xticklabels():
        box = label.get_window_extent(renderer)
        x = to_data.transform(((box.x0 + box.x1) / 2, 0.0))[0]           # Q / Qa on the bottom axis
        if label.get_text() and left <= x <= right:
            ticks.append((x, float(label.get_text().replace("\u2212", "-"))))
    assert len(ticks) >= 3
    for x, value in ticks:
        assert abs(value) < 1000
        assert value * factor == pytest.approx(x * qa, abs=0.01 * (right - left) * qa)
    plt.close(fig)


def test_the_reports_campbell_diagram_shows_its_crossings_not_the_bearing_modes(pump_sweep, monkeypatch):
    """The report drew motor_pump_on_mounts' Campbell diagram to 1.7 kHz (its bearing modes) on
    a log axis: the order lines (at most 125 Hz: 2X of the pump at 3000 rpm) and all their
    crossings with the mount modes (5-16 Hz) in the bottom third. The figure the report embeds
    shows, whole, every mode an order line of the sweep can cross (each crossing is drawn; the
    axis may end below the lines' reach where no mode lies between: test_report_review) and
    reaches no higher than three times the highest line (frequency = order x multiplier x
    speed / 2 pi, from the result's sources)."""
    from types import SimpleNamespace

    from rotordyn_modal.report import render

    drawn = []
    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: drawn.append(fig) or "")
    data = SimpleNamespace(results={"campbell": pump_sweep}, inputs=SimpleNamespace(range=(0.0, 300.0)),
                           model_info={"name": "pump"}, skipped={"unbalance": "not asked"})
    render._campbell(data, "si")
    (fig,) = drawn
    ax = fig.axes[0]
    lines = max(pump_sweep.orders) * max(pump_sweep.sources.multipliers) * pump_sweep.speeds.max() / (2 * np.pi)
    bottom, top = ax.get_ylim()
    assert top <= 3 * lines, (lines, top)
    freqs = np.where(pump_sweep.oscillatory, pump_sweep.frequencies_hz, np.nan)
    crossable = np.nanmin(freqs, axis=0) <= lines             # modes an order line can reach
    assert crossable.any()
    assert np.nanmax(freqs[:, crossable]) <= top, (np.nanmax(freqs[:, crossable]), top)
    assert np.all(pump_sweep.critical.frequencies_hz <= top)
