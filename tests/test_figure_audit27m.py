"""Figure audit of issue 27 (figs27m): every CLI figure of every example looked at.

Measured on the drawn figure (the axes' limits and the data of the lines they draw), against
the result's own numbers, never the placer's.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _drawn_inside(ax):
    """Every finite y value [panel units] of the panel's drawn lines (modes and grey roots; not
    the zero line or thresholds, which are axhline/axvline) that lies within its limits."""
    low, high = ax.get_ylim()
    values = []
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), float)
        if not line.get_visible() or y.size < 3:
            continue
        values.append(y[np.isfinite(y) & (y >= low) & (y <= high)])
    return np.concatenate(values) if values else np.empty(0)


@pytest.fixture(scope="module")
def compressor():
    """compressor_rotor, 0-12,000 rpm, modes below 450 Hz (docs: stability --max-frequency 450)."""
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    return rdm.stability(model, rdm.rpm(np.linspace(0.0, 12000.0, 13)), max_frequency=450.0)


def test_the_log_decrement_panel_shows_the_damped_modes_beside_an_undamped_axial_one(compressor):
    """The compressor's axial mode is undamped (real part 0 to round-off, log decrement 1e-31)
    and held the log decrement panel at 0 to 0.001: the bending modes (log decrements 0.09 to
    0.39) all lay above it, the panel empty but for the zero line. On the drawn figure: the
    least damped mode that is damped (the smallest log decrement at each speed among the roots
    whose real part is not round-off, from the result) lies inside the panel, at least a third
    of the panel's height above zero."""
    import matplotlib.pyplot as plt

    significant = compressor.significant_real_parts
    log_dec = np.where(np.isfinite(compressor.log_decrements) & (significant != 0), compressor.log_decrements, np.inf)
    assert np.any(np.all(significant[:, np.isfinite(compressor.log_decrements).all(axis=0)] == 0, axis=0))
    least = log_dec.min(axis=1)
    assert np.all(np.isfinite(least)) and least.min() > 0.05
    fig = compressor.plot()
    bottom = fig.axes[1]
    low, high = bottom.get_ylim()
    assert low <= least.min() and least.max() <= high, (least, low, high)
    assert least.min() >= (high - low) / 3, (least, low, high)
    plt.close(fig)


def _cross_coupled():
    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    return rdm.stability(model, rdm.rpm(np.linspace(0.0, 20000.0, 41)))


@pytest.mark.parametrize("case", ["cross_coupled", "compressor"])
def test_the_real_part_panel_ends_at_its_lowest_curve(case, compressor):
    """unstable_cross_coupled, 0-20,000 rpm: the real-part panel reached -3.6 1/s, its lowest
    curve inside ending at -2.2 (a third of the panel empty); the compressor's reached -29 1/s
    under curves at -9.4 (two thirds empty): the panel was held at three times the least damped
    mode's real part, the modes beyond being named in a note. On the drawn figure: the gap between
    the panel's bottom and the lowest value drawn inside it is at most an eighth of the panel's
    height (the limits reach 10 % beyond the data)."""
    import matplotlib.pyplot as plt

    result = _cross_coupled() if case == "cross_coupled" else compressor
    fig = result.plot()
    top = fig.axes[0]
    low, high = top.get_ylim()
    inside = _drawn_inside(top)
    assert inside.size and inside.min() < 0
    assert inside.min() - low <= (high - low) / 8, (inside.min(), low, high)
    plt.close(fig)


def _line_style(handle):
    """What tells a legend entry's line apart: colour (RGBA), dash pattern, marker."""
    from matplotlib.colors import to_rgba

    offset, dashes = handle._unscaled_dash_pattern if hasattr(handle, "_unscaled_dash_pattern") else (0, None)
    pattern = None if handle.get_linestyle() in ("-", "solid", "None", "") else (offset, tuple(dashes or ()))
    return to_rgba(handle.get_color()), handle.get_linestyle() if pattern is None else pattern, handle.get_marker()


def test_the_ucs_map_legend_gives_every_mode_its_own_line():
    """``ucs-map fan_on_bearings.toml --stiffness 1e5:1e9:41 --bearings fan-DE,fan-NDE`` follows
    11 modes; its 10 colours came round again, and '1 fan cylindrical' and '11 motor
    cylindrical' were drawn and listed in the legend with the same blue solid line. On the drawn
    figure: the legend's mode entries ('N name') differ pairwise in colour, dash pattern or
    marker, and there are more of them than colours (else the test proves nothing)."""
    import re

    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.ucs_map(model, np.geomspace(1e5, 1e9, 9), modes=12, bearings=["fan-DE", "fan-NDE"])
    fig = result.plot()
    fig.canvas.draw()
    legend = fig.axes[0].get_legend()
    entries = [(t.get_text(), h) for t, h in zip(legend.get_texts(), legend.legend_handles)
               if re.fullmatch(r"\d+ .+", t.get_text())]
    assert len(entries) == result.mode_speeds.shape[1] and len(entries) > 10, [t for t, _ in entries]
    styles = [_line_style(h) for _, h in entries]
    for i in range(len(styles)):
        for j in range(i):
            assert styles[i] != styles[j], (entries[i][0], entries[j][0], styles[i])
    plt.close(fig)


def test_the_largest_moment_note_of_an_arch_hides_no_curve():
    """``static compressor_on_journals.toml --speed 9000 --plot``: the bending moment is an arch
    with its top (536 N m) at mid-span; the note of the largest moment (an opaque box) found no
    free corner of its point and stood where the line falling from the top ran under it. On
    the drawn figure: no curve (but the disks' pale bands) runs under either note's box, and
    the moment's note names the largest moment."""
    from test_static_shafts import assert_largest_value_notes_hide_no_curve

    model = rdm.load_model(EXAMPLES / "compressor_on_journals.toml")
    shaft = rdm.static(model, rdm.rpm(9000.0)).shafts["compressor"]
    assert_largest_value_notes_hide_no_curve(shaft)


def test_the_reports_campbell_diagram_shows_the_operating_range(tmp_path, monkeypatch):
    """``report --standard api684 --operating-range 2000:3000``: the separation margins are
    measured from the operating range, the UCS map shades it, but the Campbell diagram only
    named it in its caption. On the drawn figure: the Campbell axes hold a band whose speed
    extent is the range given, with a legend entry."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.cli import main

    figures = []

    def keep(fig, **kwargs):
        fig.canvas.draw()
        figures.append(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr("rotordyn_modal.report.render.figure_png", keep)
    out = tmp_path / "r.html"
    assert main(["report", str(EXAMPLES / "spring_block_rotor.toml"), "--standard", "api684", "--mcs", "3000",
                 "--operating-range", "2000:3000", "--points", "15", "--stiffness", "1e5:1e10:9",
                 "--out", str(out), "--quiet"]) == 0
    campbell = [ax for fig in figures for ax in fig.axes if ax.get_ylabel().startswith("Damped natural frequency")]
    assert len(campbell) == 1
    ax = campbell[0]
    spans = []
    for patch in ax.patches:
        x = ax.transData.inverted().transform(patch.get_window_extent())[:, 0]
        spans.append((round(float(x.min()), 6), round(float(x.max()), 6)))
    assert (2000.0, 3000.0) in spans, spans
    assert "operating range" in [t.get_text() for t in ax.get_legend().get_texts()]
    for fig in figures:
        plt.close(fig)


def test_a_ucs_map_within_a_decade_numbers_its_speed_axis():
    """``ucs-map spring_block_rotor.toml --stiffness 1e3:1e8:41``: the speed axis spans 62 to
    194 rpm (less than a decade, log scale) and only '10^2' was numbered: the curve's plateau
    (129 rpm) could not be read. On the drawn figure: at least four numbered speed ticks
    inside the axis, and the plateau lies between two of them, which read as their own
    positions (plain numbers)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = rdm.ucs_map(model, np.geomspace(1e3, 1e8, 11))
    fig = result.plot()
    fig.canvas.draw()
    ax = fig.axes[0]
    low, high = ax.get_ylim()
    assert high < 10 * low
    ticks = [(t.get_position()[1], t.get_text()) for minor in (False, True)
             for t in ax.get_yticklabels(minor=minor) if t.get_text() and low <= t.get_position()[1] <= high]
    assert len(ticks) >= 4, ticks
    for value, text in ticks:
        assert float(text.replace(",", "").replace("\u2212", "-")) == pytest.approx(value), (value, text)
    plateau = float(np.nanmax(result.mode_speeds[:, 0]) * 30 / np.pi)
    assert min(v for v, _ in ticks) < plateau < max(v for v, _ in ticks), (plateau, ticks)
    plt.close(fig)


def test_an_order_label_at_the_right_edge_has_no_curve_between_it_and_its_exit():
    """``campbell compressor_rotor.toml --speeds 0:12000:201 --orders 1,2 --max-frequency 450``:
    the 1X line leaves the axes at the right edge at 200 Hz; its label '1X compressor' stood two
    heights above the exit, mode 4's dashed line (216 Hz) between them, as if it named that mode.
    On the drawn figure: the vertical way along the right edge from the 1X line's exit to the
    label's glyph box crosses no other curve (exact segment geometry, tests/label_geometry.py)."""
    import matplotlib.pyplot as plt
    from label_geometry import curve_segments, glyph_box

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 201)), orders=(1, 2), max_frequency=450.0)
    fig = result.plot(title=model.name)
    fig.set_dpi(150)                                  # as the command line saves it
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    label = next(t for t in ax.texts if t.get_visible() and t.get_text() == "1X compressor")
    box = glyph_box(label, renderer)
    exit_y = ax.transData.transform((12000.0, 12000.0 / 60.0))[1]
    x = box.x1 - 1.0                      # beside the right edge, where the way runs
    low, high = sorted((exit_y, box.y0 if box.y0 > exit_y else box.y1))
    own = [line for line in ax.get_lines() if len(line.get_xdata()) >= 2
           and np.allclose(np.asarray(line.get_ydata(), float)[-1:], 200.0, rtol=1e-9)
           and np.isclose(np.asarray(line.get_xdata(), float)[-1], 12000.0)]
    segments = curve_segments(ax, skip=own)
    x0, y0, x1, y1 = segments.T
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (x - x0) / (x1 - x0)
        y = y0 + t * (y1 - y0)
    between = (t >= 0) & (t <= 1) & (y > low + 1.0) & (y < high - 1.0)
    assert not between.any(), (label.get_text(), box, exit_y, y[between])
    plt.close(fig)
