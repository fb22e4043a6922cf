"""The Campbell figure: the result's numbers in rpm and Hz, order-line labels inside the axes
and apart from each other.

Measured on the drawn figure (``fig.canvas.draw()``, ``Text.get_window_extent``), for the
README's quick start and for sweeps with negative speeds, many orders and steep gear-mesh
lines near zero speed.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
ORDER_LABEL = re.compile(r"^\d+(\.\d+)?X(, \d+(\.\d+)?X)* ")


def _figure(model, rpm, orders):
    result = rdm.campbell(rdm.load_model(EXAMPLES / model), rdm.rpm(rpm), orders=orders)
    fig = result.plot()
    fig.canvas.draw()
    return result, fig, fig.axes[0]


def _order_labels(ax):
    return [t for t in ax.texts if ORDER_LABEL.match(t.get_text()) and t.get_visible()]


CASES = [
    ("gear_machine.toml", np.linspace(0, 3000, 301), (1, 2)),          # README quick start
    ("gear_machine.toml", np.linspace(0, 6000, 201), (1,)),
    ("gear_machine.toml", np.linspace(-6000, 6000, 201), (1,)),
    ("gear_machine.toml", np.linspace(-6000, 1000, 101), (1, 2, 3)),
    ("counter_rotating.toml", np.linspace(0, 12000, 121), (0.5, 1, 2, 3)),
    ("fan_on_bearings.toml", np.linspace(0, 9000, 91), (1, 2)),
]


@pytest.mark.parametrize("model,rpm,orders", CASES)
def test_order_labels_lie_inside_the_axes_and_apart(model, rpm, orders):
    import matplotlib.pyplot as plt

    _, fig, ax = _figure(model, rpm, orders)
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    boxes = [t.get_window_extent(renderer) for t in _order_labels(ax)]
    assert boxes
    for t, box in zip(_order_labels(ax), boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            (t.get_text(), box, frame)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a, b)
    plt.close(fig)


@pytest.mark.parametrize("model,rpm,orders", CASES[:2] + CASES[4:5])
def test_mode_labels_do_not_overlap(model, rpm, orders):
    import matplotlib.pyplot as plt

    _, fig, ax = _figure(model, rpm, orders)
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in ax.texts if re.match(r"^mode \d+$", t.get_text())]
    assert len(boxes) >= 6
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a, b)
    plt.close(fig)


def test_every_order_of_the_quick_start_is_labelled_once():
    """README quick start: each source's orders 1 and 2 appear in exactly one label."""
    import matplotlib.pyplot as plt

    result, fig, ax = _figure(*CASES[0])
    named = []
    for text in (t.get_text() for t in _order_labels(ax)):
        prefixes, source = re.match(r"^(.*X) (.*)$", text).groups()
        named += [(source, float(p.rstrip("X"))) for p in prefixes.split(", ")]
    assert sorted(named) == sorted((s, o) for s in result.sources.names for o in (1.0, 2.0))
    plt.close(fig)


def test_the_figure_draws_the_results_numbers_in_rpm_and_hz():
    """README quick start: the order lines rise by order x multiplier / 60 Hz per rpm (Omega in
    rad/s is rpm pi / 30), the critical-speed markers sit at the table's rpm and Hz, and every
    mode's curve joins each pair of neighbouring speeds where it is a mode, whirl changes
    included (the curve is drawn in pieces, one style per whirl direction)."""
    import matplotlib.pyplot as plt

    result, fig, ax = _figure(*CASES[0])
    rpm = result.speeds_rpm
    lines = [(np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float), line.get_label())
             for line in ax.get_lines()]
    markers = [(x, y) for x, y, label in lines if label == "critical speed"]
    assert len(markers) == 1
    np.testing.assert_allclose(markers[0][0], result.critical.speeds_rpm, rtol=1e-12)
    np.testing.assert_allclose(markers[0][1], result.critical.frequencies_hz, rtol=1e-12)
    curves = [(x, y) for x, y, label in lines if label != "critical speed" and len(x) == len(rpm)]
    positive = rpm > 0
    slopes = sorted(float(np.mean(y[positive] / rpm[positive])) for x, y in curves
                    if np.all(np.isfinite(y)) and np.allclose(y[positive] / rpm[positive], y[-1] / rpm[-1], rtol=1e-12))
    expected = sorted(order * m / 60.0 for m in result.sources.multipliers for order in result.orders)
    np.testing.assert_allclose(slopes, expected, rtol=1e-12)
    for mode in range(result.frequencies_hz.shape[1]):
        f = np.where(result.oscillatory[:, mode], result.frequencies_hz[:, mode], np.nan)
        for k in np.nonzero(np.isfinite(f[:-1]) & np.isfinite(f[1:]))[0]:
            assert any(y[k] == f[k] and y[k + 1] == f[k + 1] for _, y in curves), (mode + 1, k)
    plt.close(fig)
