"""What the Campbell figure draws is computed by the result, not by the figure.

``CampbellResult`` gives the order lines (``order_frequencies``), whether they meet a mode
(``order_crossings``, ``crosses_orders``), each critical speed's order-line frequency
(``critical_line_frequencies``) and each mode's curve with its critical speeds among its points
(``mode_curves``); ``plotting/campbell.py`` only reads them. Checked against values written out
here (``order * multiplier * |Omega| / 2 pi``, a hand-made sweep whose lines cross or do not), and
on the drawn figure: on a sweep of 5 speeds each critical speed's circle lies on its mode's curve
as drawn (a pixel), where chords between the sweep's points alone pass up to tens of pixels away.
"""

from __future__ import annotations

import ast
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.campbell import CampbellResult
from rotordyn_modal.analysis.critical_speeds import ExcitationSources, _critical_table

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def _hand_made(speeds, frequencies_hz, real_parts=None, multipliers=(2.0,), orders=(1.0, 3.0)):
    """A CampbellResult of one mode of the given frequencies [Hz] over ``speeds`` [rad/s]
    (damped lightly; ``real_parts`` where given; a root with no imaginary part is no mode)."""
    speeds = np.asarray(speeds, float)
    f = np.asarray(frequencies_hz, float)[:, None]
    real = np.full_like(f, -0.1) if real_parts is None else np.asarray(real_parts, float)[:, None]
    lam = real + 2j * np.pi * f
    n = len(speeds)
    return CampbellResult(
        speeds=speeds, eigenvalues=lam, frequencies_hz=f, damping_ratios=np.zeros((n, 1)),
        log_decrements=np.zeros((n, 1)), whirl_ratios=np.ones((n, 1)), whirl=np.full((n, 1), "forward", object),
        shapes=np.zeros((n, 1, 2), complex), modes=np.array([1]),
        sources=ExcitationSources(tuple(f"source {k}" for k in range(len(multipliers))),
                                  np.array(multipliers, float)),
        critical=_critical_table([], [], [], [], [], [], [], []), orders=tuple(orders))


def test_order_frequencies_are_order_times_multiplier_times_speed_over_two_pi():
    result = _hand_made([-300.0, 0.0, 50.0, 400.0], [10.0] * 4, multipliers=(2.0, 0.5), orders=(1.0, 3.0))
    lines = result.order_frequencies()
    assert lines.shape == (2, 2, 4)
    # written out: source 0 (x2), order 1 at -300 rad/s: 600 / 2 pi Hz; source 1 (x0.5), order 3 at 400: 600 / 2 pi
    assert lines[0, 0] == pytest.approx([600 / (2 * np.pi), 0.0, 100 / (2 * np.pi), 800 / (2 * np.pi)], rel=1e-15)
    assert lines[0, 1] == pytest.approx([1800 / (2 * np.pi), 0.0, 300 / (2 * np.pi), 2400 / (2 * np.pi)], rel=1e-15)
    assert lines[1, 0] == pytest.approx([150 / (2 * np.pi), 0.0, 25 / (2 * np.pi), 200 / (2 * np.pi)], rel=1e-15)
    assert lines[1, 1] == pytest.approx([450 / (2 * np.pi), 0.0, 75 / (2 * np.pi), 600 / (2 * np.pi)], rel=1e-15)
    # at speeds of one's own: 1 rad/s of order 3, source x2 is 6 / 2 pi Hz
    assert result.order_frequencies([1.0, -2.0])[0, 1] == pytest.approx([6 / (2 * np.pi), 12 / (2 * np.pi)], rel=1e-15)


def test_order_slopes_are_order_times_multiplier_over_two_pi_per_unit_of_speed():
    result = _hand_made([0.0, 10.0], [10.0] * 2, multipliers=(2.0, 0.5), orders=(1.0, 3.0))
    assert result.order_slopes() == pytest.approx(np.array([[2.0, 6.0], [0.5, 1.5]]) / (2 * np.pi), rel=1e-15)
    # per rpm: 1 rpm is pi / 30 rad/s; order 3 of x2 at 60 rpm (2 pi rad/s) is 6 Hz
    assert result.order_slopes(30 / np.pi)[0, 1] * 60 == pytest.approx(6.0, rel=1e-15)


def test_crossing_flag_of_lines_that_cross_and_lines_that_do_not():
    # a 10 Hz mode up to 20 rad/s: order 1 of x2 reaches 40 / 2 pi = 6.4 Hz (below), order 3 19.1 Hz (above)
    result = _hand_made([0.0, 10.0, 20.0], [10.0, 10.0, 10.0])
    assert result.order_crossings.tolist() == [[False, True]]
    assert result.crosses_orders
    # only order 1: no line meets the mode
    assert not _hand_made([0.0, 10.0, 20.0], [10.0, 10.0, 10.0], orders=(1.0,)).crosses_orders
    # a line reaching the mode exactly at a speed of the sweep: 3 x 2 x 10 / 2 pi Hz at 10 rad/s
    assert _hand_made([0.0, 10.0], [60 / (2 * np.pi)] * 2, orders=(3.0,)).crosses_orders
    # where the root is no mode (real: overdamped at 20 rad/s) the line's crossing is no crossing
    assert not _hand_made([0.0, 10.0, 20.0], [10.0, 10.0, 0.0], real_parts=[-0.1, -0.1, -5.0]).crosses_orders
    # reversed spin crosses as its magnitude
    assert _hand_made([-20.0, -10.0, 0.0], [10.0, 10.0, 10.0], orders=(3.0,)).crosses_orders


def test_the_critical_speeds_order_line_frequency_is_order_times_multiplier_times_speed():
    result = rdm.campbell(rdm.load_model(EXAMPLES / "gear_machine.toml"), rdm.rpm(np.linspace(0, 6000, 61)),
                          orders=(1, 2))
    table = result.critical
    assert len(table) > 3
    multipliers = dict(zip(result.sources.names, result.sources.multipliers))
    written = [order * multipliers[name] * abs(speed) / (2 * np.pi)
               for name, order, speed in zip(table.source, table.order, table.speeds)]
    assert result.critical_line_frequencies == pytest.approx(written, rel=1e-14)
    # at a crossing the mode's frequency is the line's
    crossing = ~result.critical_jumps
    assert crossing.any()
    assert table.frequencies_hz[crossing] == pytest.approx(result.critical_line_frequencies[crossing], rel=1e-8)


def test_the_figure_module_computes_no_order_line_nor_crossing():
    """``plotting/campbell.py`` reads the order lines, the crossing flag and the critical speeds'
    line frequencies from the result: no ``_crosses``, no ``2 pi`` of its own, no instability test."""
    from rotordyn_modal.plotting import campbell as figure

    assert not hasattr(figure, "_crosses")
    source = (ROOT / "rotordyn_modal" / "plotting" / "campbell.py").read_text()
    tree = ast.parse(source)
    pis = [node for node in ast.walk(tree) if isinstance(node, ast.Attribute) and node.attr == "pi"]
    reals = [node for node in ast.walk(tree) if isinstance(node, ast.Attribute) and node.attr in ("real", "imag")]
    assert not pis, [ast.get_source_segment(source, n) for n in pis]
    assert not reals, [ast.get_source_segment(source, n) for n in reals]
    for name in ("order_frequencies", "order_slopes", "order_crossings", "critical_line_frequencies", "mode_curves", "unstable",
                 "instability_onsets", "settled"):
        assert f".{name}" in source, name


def _distance_to_polyline(point, xy):
    """Least distance [pixels] of ``point`` from the polyline ``xy`` (K, 2) (NaN points break it)."""
    a, b = xy[:-1], xy[1:]
    ok = np.all(np.isfinite(a), axis=1) & np.all(np.isfinite(b), axis=1)
    a, b = a[ok], b[ok]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
    return float(np.min(np.hypot(*(a + t[:, None] * d - point).T), initial=np.inf))


def _mode_lines(ax, result, m):
    """The drawn lines of mode column ``m``: those whose points at the sweep's speeds are the mode's
    frequencies (wherever drawn)."""
    freqs = np.where(result.oscillatory[:, m], result.frequencies_hz[:, m], np.nan)
    found = []
    for line in ax.get_lines():
        x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
        if len(x) < len(result.speeds) or line.get_linewidth() != 1.6:
            continue
        at = np.isclose(x[:, None], result.speeds_rpm[None, :], rtol=1e-12, atol=1e-9).any(axis=1)
        if at.sum() != len(result.speeds):
            continue
        drawn = np.isfinite(y[at])
        if drawn.any() and np.array_equal(y[at][drawn], freqs[drawn]):
            found.append(line)
    return found


@pytest.mark.parametrize("model,rpm,orders", [
    ("fan_on_bearings.toml", (0, 40000, 5), (0.5, 1, 2)),          # main: up to 14 pixels off
    ("unstable_cross_coupled.toml", (0, 40000, 5), (0.5, 1, 2)),   # main: 1.4 pixels off
])
def test_each_critical_speeds_circle_lies_on_its_curve_as_drawn_on_a_sparse_sweep(model, rpm, orders):
    result = rdm.campbell(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(*rpm)), orders=orders)
    fig = result.plot()
    fig.canvas.draw()
    ax = fig.axes[0]
    marker = next(line for line in ax.get_lines() if line.get_label() == "critical speed")
    table = result.critical
    assert len(table) >= 3
    centres = ax.transData.transform(np.column_stack([marker.get_xdata(), marker.get_ydata()]))
    worst = 0.0
    for k in np.flatnonzero(~result.critical_jumps):
        centre = ax.transData.transform([[table.speeds_rpm[k], table.frequencies_hz[k]]])[0]
        assert np.min(np.hypot(*(centres - centre).T)) < 1e-6           # the circle drawn is the row's
        lines = _mode_lines(ax, result, int(table.mode[k]) - 1)
        assert lines, table.mode[k]
        distance = min(_distance_to_polyline(centre, ax.transData.transform(
            np.column_stack([line.get_xdata(), line.get_ydata()]))) for line in lines)
        worst = max(worst, distance)
    assert worst <= 1.0, f"a critical speed's circle {worst:.1f} pixels off its curve"
