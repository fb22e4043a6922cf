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
from label_geometry import clip_segments, curve_segments, glyph_box, named_modes, outline_crossings

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
    # the mode curves: the sweep's points, and between them the critical speeds of their mode
    # (test_campbell_result_lines.py), drawn without a break from each speed to the next
    # (a whirl change splits a step between two lines, one per style, which meet at the change)
    curves = [(x, y) for x, y, label in lines if label != "critical speed" and len(x) >= len(rpm)]
    curves = [(y, at) for (x, y), at in zip(curves, [_sweep_positions(x, rpm) for x, _ in curves]) if at is not None]
    for mode in range(result.frequencies_hz.shape[1]):
        f = np.where(result.oscillatory[:, mode], result.frequencies_hz[:, mode], np.nan)
        for k in np.nonzero(np.isfinite(f[:-1]) & np.isfinite(f[1:]))[0]:
            own = [(y, at) for y, at in curves if y[at[k]] == f[k] or y[at[k + 1]] == f[k + 1]]
            assert own, (mode + 1, k)
            pieces = range(own[0][1][k], own[0][1][k + 1])
            assert all(any(np.isfinite(y[i]) and np.isfinite(y[i + 1]) for y, _ in own) for i in pieces), (mode + 1, k)
    plt.close(fig)


def _sweep_positions(x, rpm):
    """Where a drawn line's speeds ``x`` hold the sweep's speeds ``rpm`` (shape (N,)); None where
    the line misses one."""
    at = np.argmin(np.abs(x[:, None] - rpm[None, :]), axis=0)
    return at if np.allclose(x[at], rpm, rtol=1e-12, atol=1e-9) else None


# -- every label of the figure: inside, apart, on (or pointing to) its own curve ---------------
# Three decades (motor_pump_on_mounts: mounts at 5-16 Hz, bearings at 530-1,170 Hz), the issue's
# fan sweep, limits on the frequency axis, rad/s, and the axes zoomed after drawing.

MODE_LABEL = re.compile(r"^mode (\d+)$")


def _drawn(fig):
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _labels(ax):
    """Visible texts of the diagram: (kind, text artist), kind 'mode', 'critical', 'key', 'note'
    (of the critical speeds left unlabelled) or 'order'."""
    out = []
    for t in ax.texts:
        if not t.get_visible() or not t.get_text():
            continue
        kind = "mode" if MODE_LABEL.match(t.get_text()) or named_modes(t.get_text()) and t.get_gid() == "mode-label" \
            else "critical" if t.get_gid() == "critical-label" \
            else "key" if t.get_gid() == "order-key" else "note" if t.get_gid() == "critical-note" else "order"
        out.append((kind, t))
    return out


def _leader(ax, label):
    leaders = [line for line in ax.get_lines() if line.get_gid() == f"mode-leader {label}" and line.get_visible()]
    return leaders[0] if leaders else None


def _pointed_height(ax, text, renderer, label=None):
    """Display height a mode label points at: its leader's start on the curve, or its own centre
    (``label``: which of the modes a shared label names, 'modes 7, 8')."""
    label = int(MODE_LABEL.match(text.get_text()).group(1)) if label is None else label
    leader = _leader(ax, label)
    if leader is not None:
        return ax.transAxes.transform((leader.get_xdata()[0], leader.get_ydata()[0]))[1]
    box = text.get_window_extent(renderer)
    return 0.5 * (box.y0 + box.y1)


def _check_labels(result, fig, ax, renderer):
    """Label boxes inside (order and critical-speed labels inside the axes; mode labels beside
    them, within their height), no two overlapping; each mode label points at its own curve's
    end, nearer to it than to any other curve's; each critical-speed label touches a marker
    of the speed it reads."""
    frame = ax.get_window_extent(renderer)
    figure = fig.bbox
    labels = _labels(ax)
    boxes = [(kind, t, t.get_window_extent(renderer)) for kind, t in labels]
    for kind, t, box in boxes:
        assert figure.x0 <= box.x0 and box.x1 <= figure.x1 and figure.y0 <= box.y0 and box.y1 <= figure.y1, t
        if kind == "key":        # an order line's key above the axes (test_figure_audit5)
            assert box.y0 > frame.y1, (t.get_text(), box, frame)
            continue
        assert frame.y0 - 1 <= box.y0 and box.y1 <= frame.y1 + 1, (t.get_text(), box, frame)
        if kind != "mode":
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1, (t.get_text(), box, frame)
    for i, (_, a, box_a) in enumerate(boxes):
        for _, b, box_b in boxes[i + 1:]:
            assert not box_a.overlaps(box_b), (a.get_text(), b.get_text())
    ends = _curve_ends(result, ax)
    for kind, t in labels:
        for label in named_modes(t.get_text()) if kind == "mode" else []:
            if label not in ends:   # its curve ends inside the axes: labelled there
                continue
            height = _pointed_height(ax, t, renderer, label)
            nearest = min(abs(end - height) for end in ends.values())
            assert abs(ends[label] - height) < 0.5 and abs(ends[label] - height) == nearest, (t.get_text(), height, ends)
            if len(named_modes(t.get_text())) > 1:      # a shared label: each curve's leader ends at it
                box, leader = t.get_window_extent(renderer), _leader(ax, label)
                end = leader.get_transform().transform((leader.get_xdata()[-1], leader.get_ydata()[-1]))
                assert box.y0 <= end[1] <= box.y1 and box.x0 - 3 * fig.dpi / 72 <= end[0] <= box.x0, (t.get_text(), label)
    points = fig.dpi / 72
    markers = [line for line in ax.get_lines() if line.get_label() == "critical speed"]
    anchors = {}
    for kind, t in labels:
        if kind == "critical":
            box = t.get_window_extent(renderer)
            speeds = np.asarray(markers[0].get_xdata(), float)
            xy = ax.transData.transform(np.column_stack(markers[0].get_data()))
            reach = 6 * points
            leader = _critical_leader(ax, box)
            if leader is None:      # beside its marker
                near = [k for k, (u, v) in enumerate(xy)
                        if box.x0 - reach <= u <= box.x1 + reach and box.y0 - reach <= v <= box.y1 + reach]
            else:                   # its leader line ends at its marker's edge (4 points from the centre)
                near = [k for k, p in enumerate(xy) if np.hypot(*(p - leader[1])) <= 4 * points + 1]
            reads = [f"{s:.0f}" if abs(s) >= 100 else f"{s:.3g}" for s in speeds[near]]
            # circles that read as one share a label '2842/2855' (issue 27: no overprinted labels)
            words = t.get_text().split("/")
            assert set(words) <= set(reads), (t.get_text(), reads)
            anchors[t] = xy[[k for k in near if reads[near.index(k)] in words]]
    _check_no_curve_through_a_label(result, ax, labels, anchors, renderer)
    _check_leaders_do_not_cross(ax)


def _check_leaders_do_not_cross(ax):
    """No two critical-speed leader lines cross (each pair's segments, exact orientation test)."""
    ends = [line.get_transform().transform(np.column_stack(line.get_data()))[[0, -1]] for line in ax.get_lines()
            if line.get_gid() == "critical-leader" and line.get_visible() and len(line.get_xdata())]

    def side(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    for i, (a, b) in enumerate(ends):
        for c, d in ends[i + 1:]:
            assert not (side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0), (a, b, c, d)


def _critical_leader(ax, box):
    """(start, end) [display] of the visible critical-speed leader line starting at ``box``, or None."""
    for line in ax.get_lines():
        if line.get_gid() == "critical-leader" and line.get_visible() and len(line.get_xdata()):
            start, end = line.get_transform().transform(np.column_stack(line.get_data()))[[0, -1]]
            if box.x0 - 1 <= start[0] <= box.x1 + 1 and box.y0 - 1 <= start[1] <= box.y1 + 1:
                return start, end
    return None


def _check_no_curve_through_a_label(result, ax, labels, anchors, renderer):
    """No curve drawn (mode, order line, instability band; leader lines aside) runs through a
    label's glyphs but within 6 sqrt(2) points of the label's anchor: a critical speed's
    marker, a curve's last point inside the axes (mode labels), the exits of the order lines
    of the label's colour."""
    leaders = [line for line in ax.get_lines() if (line.get_gid() or "").endswith("leader")
               or (line.get_gid() or "").startswith("mode-leader")]
    segments = curve_segments(ax, skip=leaders)
    frame = ax.get_window_extent(renderer)
    radius = 6 * np.sqrt(2) * ax.figure.dpi / 72 + 1
    for kind, t in labels:
        if kind == "critical":
            points = anchors[t]
        elif kind == "mode":
            points = [p for label in named_modes(t.get_text()) for p in _last_points_inside(result, ax, label)]
        elif kind == "note":        # no anchor: no curve through it at all
            points = []
        else:
            points = [p for line in ax.get_lines() if line.get_color() == t.get_color() and len(line.get_xdata()) > 2
                      for p in _exits(line, frame)]
        crossed = outline_crossings(t, renderer, segments, points, radius)      # a turned text: its own outline
        assert not len(crossed), (t.get_text(), crossed[:4])


def _last_points_inside(result, ax, label):
    """The display point of mode ``label``'s last sample inside the axes (where its label sits)."""
    m = list(result.modes).index(label)
    x = _sweep_x(result, ax)
    f = np.where(result.oscillatory[:, m], result.frequencies_hz[:, m], np.nan)
    (lo, hi), (bottom, top) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    view = np.isfinite(f) & (x >= lo) & (x <= hi) & (f >= bottom) & (f <= top)
    return ax.transData.transform(np.column_stack([x[view], f[view]]))[-1:] if view.any() else []


def _sweep_x(result, ax):
    """The sweep's speeds in the unit of the axes' speed axis (the mode curves' points hold
    their critical speeds too)."""
    from rotordyn_modal.plotting._style import speed_label, speed_scale

    unit = next(u for u in ("rpm", "rad/s", "hz") if speed_label(u) == ax.get_xlabel())
    return result.speeds * speed_scale(unit)


def _exits(line, frame):
    """Where a line's drawn path leaves the frame (its last point inside, display)."""
    xy = line.get_transform().transform(np.column_stack(line.get_data()))
    inside = np.all(np.isfinite(xy), axis=1) & (xy[:, 0] >= frame.x0 - 1) & (xy[:, 0] <= frame.x1 + 1) \
        & (xy[:, 1] >= frame.y0 - 1) & (xy[:, 1] <= frame.y1 + 1)
    if not inside.any():
        return []
    k = int(np.nonzero(inside)[0][-1])
    if k + 1 < len(xy) and np.all(np.isfinite(xy[k + 1])):     # the crossing of the frame
        part = clip_segments(np.hstack([xy[k], xy[k + 1]])[None], (frame.x0, frame.y0, frame.x1, frame.y1))
        return [part[0, 2:]] if len(part) else [xy[k]]
    return [xy[k]]


def _curve_ends(result, ax):
    """{mode label: display height where its curve meets the right edge of the axes} (modes
    inside the frequency limits there), from the result's own numbers."""
    x_right = ax.get_xlim()[1]
    speeds = _sweep_x(result, ax)
    ends = {}
    (bottom, top) = ax.get_ylim()
    for m, label in enumerate(result.modes):
        f = np.where(result.oscillatory[:, m], result.frequencies_hz[:, m], np.nan)
        value = np.interp(x_right, speeds, f)
        if np.isfinite(value) and bottom <= value <= top:
            ends[int(label)] = ax.transData.transform((x_right, value))[1]
    return ends


FIGURES = [
    ("fan_on_bearings.toml", np.linspace(0, 9000, 181), (1, 2), {}),                 # the issue's sweep
    ("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2), {}),            # three decades, log
    ("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2), {"freq_range": (0, 40)}),
    ("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2), {"freq_scale": "linear"}),
    ("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2), {"freq_range": (4, 2000), "speed_unit": "rad/s"}),
    ("gear_machine.toml", np.linspace(0, 3000, 301), (1, 2), {"speed_unit": "hz"}),
    ("counter_rotating.toml", np.linspace(0, 12000, 121), (0.5, 1, 2, 3), {}),
    ("unstable_cross_coupled.toml", np.linspace(0, 20000, 201), (1,), {"color_by": "log_decrement"}),
]


@pytest.fixture(scope="module")
def sweeps():
    cache = {}

    def get(model, rpm, orders):
        key = (model, rpm[0], rpm[-1], len(rpm), orders)
        if key not in cache:
            cache[key] = rdm.campbell(rdm.load_model(EXAMPLES / model), rdm.rpm(rpm), orders=orders)
        return cache[key]
    return get


@pytest.mark.parametrize("model,rpm,orders,options", FIGURES)
def test_every_label_is_inside_apart_and_on_its_own_curve(sweeps, model, rpm, orders, options):
    import matplotlib.pyplot as plt

    result = sweeps(model, rpm, orders)
    fig = result.plot(**options)
    renderer = _drawn(fig)
    ax = fig.axes[0]
    _check_labels(result, fig, ax, renderer)
    assert sum(kind == "mode" for kind, _ in _labels(ax)) >= 4
    plt.close(fig)


def test_the_issue_fan_curve_at_36_hz_is_labelled_mode_7(sweeps):
    """fan_on_bearings 0-9000 rpm: the curve ending at 36 Hz is mode 7; its label points there."""
    import matplotlib.pyplot as plt

    result = sweeps("fan_on_bearings.toml", np.linspace(0, 9000, 181), (1, 2))
    m = int(np.argmin(np.abs(np.where(result.oscillatory[-1], result.frequencies_hz[-1], np.inf) - 36.0)))
    assert result.modes[m] == 7 and abs(result.frequencies_hz[-1, m] - 36.3) < 0.5
    fig = result.plot()
    renderer = _drawn(fig)
    ax = fig.axes[0]
    label = next(t for kind, t in _labels(ax) if t.get_text() == "mode 7")
    target = ax.transData.transform((ax.get_xlim()[1], result.frequencies_hz[-1, m]))[1]
    assert abs(_pointed_height(ax, label, renderer) - target) < 0.5
    plt.close(fig)


def test_three_decades_draw_on_a_log_axis_and_the_limits_hold(sweeps):
    """Mounts at 5-16 Hz and bearings up to 1,174 Hz (a span of 200 at one speed): log axis by
    default, reaching below the lowest and above the highest mode; linear where asked or where
    the range starts at 0; given limits are the axis' limits."""
    import matplotlib.pyplot as plt

    result = sweeps("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2))
    f = np.where(result.oscillatory, result.frequencies_hz, np.nan)
    for options, scale, limits in [({}, "log", None), ({"freq_scale": "linear"}, "linear", None),
                                   ({"freq_range": (0, 40)}, "linear", (0, 40)),
                                   ({"freq_range": (2, 3000)}, "log", (2, 3000)),
                                   ({"freq_range": (None, 40)}, "linear", None)]:
        fig = result.plot(**options)
        ax = fig.axes[0]
        assert ax.get_yscale() == scale, options
        bottom, top = ax.get_ylim()
        if limits is not None:
            assert (bottom, top) == limits
        elif "freq_range" in options:
            assert top == 40 and bottom == 0
        else:
            assert bottom < np.nanmin(f) and top > np.nanmax(f)
        plt.close(fig)
    with pytest.raises(rdm.InputError, match="freq_range"):
        result.plot(freq_range=(40, 10))
    with pytest.raises(rdm.InputError, match="freq_scale"):
        result.plot(freq_scale="semilog")


def test_labels_follow_a_zoom(sweeps):
    """Zoomed to the mounts' 0-25 Hz and 0-1,500 rpm after the first drawing: the labels are
    placed again, inside, apart and on their curves."""
    import matplotlib.pyplot as plt

    result = sweeps("motor_pump_on_mounts.toml", np.linspace(0, 3600, 181), (1, 2))
    fig = result.plot()
    _drawn(fig)
    ax = fig.axes[0]
    ax.set_yscale("linear")
    ax.set_ylim(0, 25)
    ax.set_xlim(0, 1500)
    renderer = _drawn(fig)
    _check_labels(result, fig, ax, renderer)
    shown = [t.get_text() for kind, t in _labels(ax) if kind == "mode"]
    assert sorted(shown) == [f"mode {k}" for k in range(1, 7)]
    assert any(kind == "order" for kind, _ in _labels(ax)) and any(kind == "critical" for kind, _ in _labels(ax))
    plt.close(fig)


def test_speed_axis_follows_the_unit(sweeps, tmp_path, monkeypatch):
    """--speed-unit rad/s: the axis is labelled rad/s and the critical-speed markers sit at the
    table's speeds in rad/s (rpm pi / 30), through the command line."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.cli import campbell as cli_campbell
    from rotordyn_modal.cli.main import main

    figures = []
    monkeypatch.setattr(cli_campbell, "save_figure", lambda fig, args: figures.append(fig))
    assert main(["campbell", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:300:61", "--speed-unit", "rad/s",
                 "--plot", str(tmp_path / "c.png"), "--quiet", "--freq-max", "30"]) == 0
    ax = figures[0].axes[0]
    assert "[rad/s]" in ax.get_xlabel() and ax.get_xlim() == (0.0, 300.0) and ax.get_ylim() == (0.0, 30.0)
    result = rdm.campbell(rdm.load_model(EXAMPLES / "gear_machine.toml"), np.linspace(0, 300, 61))
    markers = next(line for line in ax.get_lines() if line.get_label() == "critical speed")
    np.testing.assert_allclose(markers.get_xdata(), result.critical.speeds_rpm * np.pi / 30, rtol=1e-12)
    plt.close(figures[0])


@pytest.mark.parametrize("argv,message", [
    (["--freq-range", "40:10"], "--freq-range '40:10': expected 0 <= LO < HI"),
    (["--freq-range", "40"], "--freq-range '40': expected LO:HI"),
    (["--freq-max", "-3"], "--freq-max '-3': expected a frequency > 0"),
    (["--freq-max", "nan"], "--freq-max 'nan': expected a finite number"),
])
def test_bad_frequency_limits_are_one_line_and_exit_2(tmp_path, capsys, argv, message):
    from rotordyn_modal.cli.main import main

    code = main(["campbell", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:3000:11", "--plot",
                 str(tmp_path / "c.png"), "--quiet"] + argv)
    err = capsys.readouterr().err
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "c.png").exists()


def test_instability_is_marked_where_the_closed_form_puts_it(sweeps):
    """unstable_cross_coupled: the backward mode loses stability at 10,886.198 rpm (closed form,
    docs/theory.md); with --color-by log_decrement the onset triangle sits there (within the
    linear interpolation of a 100 rpm grid) and the red band covers only faster speeds."""
    import matplotlib.pyplot as plt

    result = sweeps("unstable_cross_coupled.toml", np.linspace(0, 20000, 201), (1,))
    for options in ({"color_by": "log_decrement"}, {}):
        fig = result.plot(**options)
        ax = fig.axes[0]
        onset = [line for line in ax.get_lines() if line.get_marker() == "^"]
        assert len(onset) == 1 and len(onset[0].get_xdata()) == 1
        assert abs(onset[0].get_xdata()[0] - 10886.198) < 2.0
        band = next(line for line in ax.get_lines() if line.get_label() == "unstable (real part > 0)")
        x = np.asarray(band.get_xdata(), float)[np.isfinite(np.asarray(band.get_ydata(), float))]
        assert x.min() == 10800.0 and x.max() == 20000.0
        plt.close(fig)


def test_critical_speeds_figure_follows_the_unit(tmp_path, monkeypatch):
    """critical-speeds --plot with --speed-unit hz: the axis in Hz, markers at rpm / 60."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.cli import critical_speeds as cli_critical
    from rotordyn_modal.cli.main import main

    figures = []
    monkeypatch.setattr(cli_critical, "save_figure", lambda fig, args: figures.append(fig))
    assert main(["critical-speeds", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:50:51", "--speed-unit", "hz",
                 "--plot", str(tmp_path / "c.png"), "--quiet"]) == 0
    ax = figures[0].axes[0]
    assert "[Hz]" in ax.get_xlabel() and ax.get_xlim() == (0.0, 50.0)
    result = rdm.campbell(rdm.load_model(EXAMPLES / "gear_machine.toml"), rdm.hz(np.linspace(0, 50, 51)))
    markers = next(line for line in ax.get_lines() if line.get_label() == "critical speed")
    np.testing.assert_allclose(markers.get_xdata(), result.critical.speeds_rpm / 60, rtol=1e-12)
    plt.close(figures[0])


def test_an_order_label_reads_as_its_own_line():
    """Gear machine to 6000 rpm, orders 1 and 2: the gear mesh's lines leave the top within
    60 rpm of the origin, where there is no room; their label slid along its row to 1400 rpm,
    between the motor's and the fan's lines. Measured on the drawn figure: at the height of each
    order label the nearest order line (straight through the origin) is one of its colour."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgba

    _, fig, ax = _figure("gear_machine.toml", np.linspace(0, 6000, 61), (1, 2))
    renderer = fig.canvas.get_renderer()
    straight = []
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if len(x) > 2 and x[0] == 0 and y[0] == 0 and y[-1] > 0 and np.allclose(y, y[-1] / x[-1] * x, rtol=1e-9):
            straight.append(line)
    labels = _order_labels(ax)
    assert len(straight) >= 6 and labels
    for text in labels:
        box = glyph_box(text, renderer)
        height = ax.transData.inverted().transform(((box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2))[1]
        gaps = []
        for line in straight:
            x, y = (np.asarray(v, float) for v in line.get_data())
            at = ax.transData.transform((height * x[-1] / y[-1], height))[0]      # the line's x at that height
            gaps.append((max(box.x0 - at, at - box.x1, 0.0), to_rgba(line.get_color())))
        nearest = min(gaps, key=lambda g: g[0])
        assert nearest[1] == to_rgba(text.get_color()), (text.get_text(), nearest[0])
    plt.close(fig)


# -- lines of two sources that coincide: counter_rotating's twin rotors, geared 1:1 -------------

def test_coinciding_order_lines_share_one_label_in_the_colour_drawn_on_top():
    """counter_rotating: the two rotors turn at the same speed, so each order of 'upper' is the
    same line as that order of 'lower', drawn over it. Each such line has one label naming both
    sources, in the colour of the line that shows; the old figure wrote '1X upper' and '2X upper'
    in upper's grey beside a line that shows only lower's green, away from any line. And each
    critical speed where both cross one mode (one circle) is written once, not twice."""
    import matplotlib.pyplot as plt

    result = rdm.campbell(rdm.load_model(EXAMPLES / "counter_rotating.toml"), rdm.rpm(np.linspace(0, 6000, 121)),
                          orders=(1, 2))
    fig = result.plot()
    renderer = _drawn(fig)
    ax = fig.axes[0]
    rpm = result.speeds_rpm
    drawn = {}           # slope [Hz/rpm] -> colour of the last line drawn with it (the one seen)
    for line in ax.get_lines():
        y, x = np.asarray(line.get_ydata(), float), np.asarray(line.get_xdata(), float)
        if len(x) == len(rpm) and np.all(np.isfinite(y)) and x[-1] > 0 and y[-1] > 0 \
                and np.allclose(y[1:] / x[1:], y[-1] / x[-1], rtol=1e-12):
            drawn[round(y[-1] / x[-1], 12)] = matplotlib.colors.to_hex(line.get_color())
    assert len(drawn) == 4                                    # 1X, 2X of both rotors and of the mesh
    texts = [t for kind, t in _labels(ax) if kind == "order"]
    assert any(not t.get_text().endswith("mesh:upper-lower") for t in texts)
    for t in texts:
        orders = [float(o) for o in re.findall(r"(\d+(?:\.\d+)?)X", t.get_text())]
        sources = re.sub(r"^[\d.X, ]+", "", t.get_text())
        if sources.startswith("mesh"):
            continue
        assert sources == "upper & lower", t.get_text()
        for order in orders:
            assert matplotlib.colors.to_hex(t.get_color()) == drawn[round(order / 60.0, 12)], t.get_text()
    critical = [t for kind, t in _labels(ax) if kind == "critical"]
    markers = [line for line in ax.get_lines() if line.get_label() == "critical speed"][0]
    points = np.column_stack(markers.get_data())
    distinct = np.unique(np.round(points / np.abs(points).max(axis=0), 9), axis=0)
    assert len(points) == len(distinct)                       # one circle per point
    table = result.critical
    both = np.unique(np.round(np.column_stack([table.speeds_rpm, table.frequencies_hz]) / np.abs(points).max(axis=0),
                              9), axis=0)
    assert len(distinct) == len(both) < len(table.speeds_rpm)   # every point of the table, each once
    assert 0 < len(critical) <= len(distinct)
    plt.close(fig)


def test_coloured_curves_of_modes_above_max_frequency_part_of_the_sweep():
    """compressor_rotor up to 450 Hz coloured by log decrement: mode 7 lies below 450 Hz only
    up to ~3000 rpm (NaN beyond, its coloured segments there empty), and modes 1 and 2 lie on
    each other at 95 Hz; drawing the figure re-coloured the pair's dashes by looking for the
    segment starting at the stretch's first point and failed with IndexError on the empty
    segments. Both modes of the pair show their colour (the colour map at their log decrement)."""
    import matplotlib.pyplot as plt

    result = rdm.campbell(rdm.load_model(EXAMPLES / "compressor_rotor.toml"), rdm.rpm(np.linspace(0.0, 12000.0, 21)),
                          orders=(1,), max_frequency=450.0)
    assert np.isnan(result.frequencies_hz).any()
    fig = result.plot(color_by="log_decrement")
    fig.canvas.draw()
    ax = fig.axes[0]
    pair = [int(np.nonzero(result.modes == m)[0][0]) for m in (1, 2)]
    delta = result.log_decrements
    finite = delta[np.isfinite(delta) & result.oscillatory]
    norm = matplotlib.colors.Normalize(finite.min(), finite.max())
    image = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(float)
    k = int(np.argmin(np.abs(result.speeds_rpm - 10000.0)))
    x, y = ax.transData.transform((result.speeds_rpm[k], result.frequencies_hz[k, pair[0]]))
    window = image[int(image.shape[0] - y) - 3:int(image.shape[0] - y) + 4, int(x) - 15:int(x) + 16]
    for m in pair:
        colour = 255.0 * np.asarray(matplotlib.colormaps["viridis"](norm(delta[k, m]))[:3])
        assert (np.linalg.norm(window - colour, axis=-1) < 30.0).sum() >= 6, result.modes[m]
    plt.close(fig)
