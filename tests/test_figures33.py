"""UCS map figures that cannot mislead (issue 27 §3, issue 29 §2).

- The same machine reads the same in SI and US units: the legend stood centred under the axes
  inside the layout, so its wider US entries ('5.71e+05 lbf/in' for '1e+08 N/m') narrowed the
  axes (motor_pump_on_mounts: 567 -> 418 pixels at 150 dpi), and the crossings' labels, grouped
  and placed by their distances in pixels, came out otherwise (a label drawn in one system and
  not the other).
- A shared label stands by what it names: with every bearing of fan_on_bearings chosen,
  '3939/3943/3959/4184' stood 42.5 points from its circles.

Measured on the drawn figure at the saved 150 dpi; the circles' places come from the analysis'
crossings (stiffness, speed), not from the plotting code.
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


@pytest.fixture(scope="module")
def motor_pump(ucs_figure):
    """``motor_pump(units)``: (map, its figure in ``units`` drawn at :data:`DPI`) of
    motor_pump_on_mounts as the api617 report maps it: 4 lowest modes, 1e5 .. 1e10 N/m in 41
    values, one operating speed of 3000 rpm. Mapped once and plotted once per system
    (conftest.ucs_figure): three tests measure the same figures."""
    speed = 3000.0 * np.pi / 30.0

    def get(units="si"):
        result, fig = ucs_figure("motor_pump_on_mounts", (1e5, 1e10, 41), units=units, modes=4,
                                 operating=(speed, speed))
        fig.set_dpi(DPI)
        fig.canvas.draw()
        return result, fig
    return get


@pytest.fixture(scope="module")
def fan_every_bearing(ucs_figure):
    """(map, its SI figure): plotted once per worker with test_figures35's (conftest.ucs_figure)."""
    return ucs_figure("fan_on_bearings", (1e5, 1e9, 41), units="si",
                      bearings=["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"],
                      operating=(1000.0 * np.pi / 30.0, 3000.0 * np.pi / 30.0))


def _drawn(result, units="si"):
    import matplotlib

    matplotlib.use("Agg")
    fig = result.plot(units=units)
    fig.set_dpi(DPI)
    fig.canvas.draw()
    return fig


def _crossing_labels(ax):
    """The labels placed among the curves (not the names at the right edge)."""
    from matplotlib.text import Annotation

    return [t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() != "ucs-end-name"]


def _circles(ax, result, factor=1.0):
    """Pixel centres of the crossings' circles and their speeds [rpm], from the analysis."""
    points = [(c.stiffness * factor, c.speed * 30.0 / np.pi) for c in result.crossings]
    return ax.transData.transform(np.array(points)), np.array([p[1] for p in points])


def _named(text, circles, speeds):
    """The circles a crossing label names: each speed it writes, rounded as written."""
    written = [float(part) for part in text.get_text().split("/")]
    return circles[[any(abs(s - w) <= 0.5 for w in written) for s in speeds]]


def _box_distance(box, point):
    return float(np.hypot(min(max(point[0], box.x0), box.x1) - point[0], min(max(point[1], box.y0), box.y1) - point[1]))


@pytest.mark.parametrize("case", ["motor_pump 5", "motor_pump 41", "flexible_pump 41"])
def test_the_same_map_reads_the_same_in_si_and_us_units(case, motor_pump, ucs_figure):
    """motor_pump_on_mounts' map (the api617 report's: 4 lowest modes, one operating speed) and
    flexible_pump_on_mounts' (as test_ucs32 draws it) in SI and US units: the axes stand in the
    same place of the figure, the same labels are drawn among the curves (grouped alike), each
    at the same place. On the base the US axes were 149 pixels narrower (motor_pump, 5 values),
    the 41-value map wrote 'operating speed 3000 rpm' beside its line in US units only, and
    flexible_pump's '26494' stood 7.4 points from its circle in SI, 32.9 in US."""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    name, grid = case.split()
    if case == "motor_pump 41":                    # the module's map: its figures are shared
        result = motor_pump("si")[0]
    elif name == "motor_pump":
        model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
        speed = 3000.0 * np.pi / 30.0
        result = rdm.ucs_map(model, np.geomspace(1e5, 1e10, int(grid)), modes=4, operating=(speed, speed))
    else:                                          # mapped once per worker with test_ucs32's (conftest.ucs_figure)
        result = ucs_figure("flexible_pump_on_mounts", (1e5, 1e10, 41), units="si")[0]
    drawn = {}
    for units in ("si", "us"):
        if case == "motor_pump 41":
            fig = motor_pump(units)[1]
        elif name == "flexible_pump":
            fig = ucs_figure("flexible_pump_on_mounts", (1e5, 1e10, 41), units=units)[1]
            fig.set_dpi(DPI)
            fig.canvas.draw()
        else:
            fig = _drawn(result, units)
        ax = fig.axes[0]
        renderer = fig.canvas.get_renderer()
        frame = ax.get_window_extent(renderer)
        labels = {t.get_text(): np.array(Text.get_window_extent(t, renderer).extents) for t in _crossing_labels(ax)}
        drawn[units] = (np.array(frame.extents), labels)
        plt.close(fig)
    (frame_si, si), (frame_us, us) = drawn["si"], drawn["us"]
    assert np.allclose(frame_si, frame_us, atol=0.5), (frame_si, frame_us)
    assert sorted(si) == sorted(us)
    for text in si:
        assert np.allclose(si[text], us[text], atol=0.5), text


def test_the_us_stiffness_axis_is_the_si_one_divided_by_lbf_per_in(motor_pump):
    """The US map's stiffness axis is in lbf/in: its limits are the SI ones / 175.1268 N/m."""
    import matplotlib.pyplot as plt

    (_, si), (_, us) = motor_pump("si"), motor_pump("us")
    assert np.allclose(np.array(us.axes[0].get_xlim()) * LBF_PER_IN, si.axes[0].get_xlim(), rtol=1e-12)
    plt.close(si)
    plt.close(us)


def test_every_fan_bearing_labels_stand_by_their_circles(fan_every_bearing):
    """fan_on_bearings, every bearing chosen (1e5 .. 1e9 N/m, 41 values, operating 1000 .. 3000
    rpm): the label naming 3939 rpm (its circles and those touching them, on two stiffness lines
    4 points apart) stands at most 24 points from the nearest circle it names (42.5 on the base)
    and nearer a circle it names than any circle it does not name; every crossing label lies
    inside the axes and overlaps no other label. ('8029/8514' is still 27 points from its circles
    and nearer 6956's: not asserted, left.)"""
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    result, fig = fan_every_bearing
    fig.set_dpi(DPI)
    fig.canvas.draw()
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    circles, speeds = _circles(ax, result)
    labels = _crossing_labels(ax)
    numbers = [t for t in labels if t.get_text()[:1].isdigit() and len(t.get_text()) >= 3]
    assert len(numbers) >= 8
    boxes = [Text.get_window_extent(t, renderer) for t in labels]
    found = False
    for text, box in zip(labels, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            text.get_text()
        if text not in numbers:
            continue
        mine = _named(text, circles, speeds)
        assert len(mine), text.get_text()
        if "3939" in text.get_text():
            found = True
            own = min(_box_distance(box, c) for c in mine)
            others = [c for c in circles if not np.any(np.all(np.isclose(c, mine), axis=1))]
            assert all(own < _box_distance(box, c) for c in others), text.get_text()
            assert own <= 24 * POINTS, (text.get_text(), own / POINTS)
    assert found
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
    plt.close(fig)


def test_the_speed_label_fits_the_axes_height(motor_pump):
    """The speed axis's label is no taller than the axes (on one line it ran past the axes' top
    into the title, '[rpm]' over 'Undamped')."""
    import matplotlib.pyplot as plt

    _, fig = motor_pump("si")
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    label = ax.yaxis.label.get_window_extent(renderer)
    frame = ax.get_window_extent(renderer)
    assert label.y0 >= frame.y0 - 1 and label.y1 <= frame.y1 + 1, (label, frame)
    assert not label.overlaps(ax.title.get_window_extent(renderer))
    plt.close(fig)
