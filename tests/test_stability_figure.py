"""The stability figure: scaled to the modes that decide stability, threshold speeds marked
where the closed forms put them, a legend of distinct styles, labels inside the figure and apart.

Journal bearings' overdamped roots reach real parts of -24,000 1/s and log decrements of 300;
the crossing at 11,628 rpm (Lund's analysis, README) must still be seen.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def journal():
    return rdm.stability(rdm.load_model(EXAMPLES / "journal_rotor.toml"), rdm.rpm(np.linspace(100, 20000, 201)))


def _zero_fraction(ax):
    bottom, top = ax.get_ylim()
    return (ax.transAxes.inverted().transform(ax.transData.transform((0.0, 0.0))))[1], bottom, top


def test_the_crossing_mode_fills_each_panel_and_zero_is_well_inside(journal):
    """The mode that crosses zero spans at least a third of each panel's height (the old figure:
    1 % of it, under roots at -24,000 1/s), and zero lies inside, not in the bottom or top 2 %."""
    import matplotlib.pyplot as plt

    assert len(journal.thresholds) == 1
    m = list(journal.modes).index(journal.threshold_modes[0])
    fig = journal.plot()
    top, bottom = fig.axes[:2]
    for ax, values in ((top, journal.real_parts[:, m]), (bottom, journal.log_decrements[:, m])):
        zero, low, high = _zero_fraction(ax)
        assert 0.02 < zero < 0.98, (zero, low, high)
        assert np.ptp(values) >= (high - low) / 3, (np.ptp(values), low, high)
        assert low <= values.min() and values.max() <= high        # the crossing mode is drawn whole
    plt.close(fig)


def test_threshold_lines_sit_at_the_closed_forms_speeds(tmp_path, monkeypatch):
    """unstable_cross_coupled loses stability at 10,886.198 rpm (closed form, docs/theory.md),
    journal_rotor at 11,628 rpm (Lund): a vertical line in each panel there, labelled with the
    speed in the unit of the axis (rpm, then rad/s through the command line)."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml"),
                           rdm.rpm(np.linspace(0, 20000, 201)))
    fig = result.plot()
    for ax in fig.axes[:2]:
        lines = [line for line in ax.get_lines() if line.get_gid() == "threshold"]
        assert len(lines) == 1 and abs(lines[0].get_xdata()[0] - 10886.198) < 1e-3
    labels = [t.get_text() for t in fig.axes[0].texts if t.get_gid() == "threshold-label"]
    assert labels and labels[0].startswith("10,886 rpm: mode") and "unstable" in labels[0]
    plt.close(fig)

    from rotordyn_modal.cli import stability as cli_stability
    from rotordyn_modal.cli.main import main

    figures = []
    monkeypatch.setattr(cli_stability, "save_figure", lambda fig, args: figures.append(fig))
    assert main(["stability", str(EXAMPLES / "journal_rotor.toml"), "--speeds", "10:2100:106", "--speed-unit",
                 "rad/s", "--plot", str(tmp_path / "s.png"), "--quiet"]) == 0
    top = figures[0].axes[0]
    assert "[rad/s]" in figures[0].axes[1].get_xlabel() and top.get_xlim() == (10.0, 2100.0)
    line = next(line for line in top.get_lines() if line.get_gid() == "threshold")
    assert abs(line.get_xdata()[0] - 11628 * np.pi / 30) < 0.1
    assert any(t.get_text().startswith("1,218 rad/s") for t in top.texts)
    plt.close(figures[0])


@pytest.mark.parametrize("model,rpm", [("fan_on_bearings.toml", (0, 9000, 91)),
                                       ("motor_pump_on_mounts.toml", (0, 3600, 73)),
                                       ("journal_rotor.toml", (100, 20000, 201))])
def test_legend_styles_are_distinct_and_few(model, rpm):
    """At most eight legend entries, no two of the same colour and line style, each naming a
    mode once; the least damped mode of every speed among them."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(*rpm)))
    fig = result.plot()
    handles, labels = fig.axes[0].get_legend_handles_labels()
    assert len(labels) <= 8 and len(set(labels)) == len(labels)
    styles = [(matplotlib.colors.to_hex(h.get_color()), h.get_linestyle()) for h in handles]
    assert len(set(styles)) == len(styles)
    named = {label for label in labels if label.startswith("mode ")}
    log_dec = np.where(np.isfinite(result.log_decrements), result.log_decrements, np.inf)
    for k in range(len(result.speeds)):
        if np.isfinite(log_dec[k]).any():
            assert f"mode {result.modes[np.argmin(log_dec[k])]}" in named, k
    plt.close(fig)


@pytest.mark.parametrize("model,rpm", [("journal_rotor.toml", (100, 20000, 201)),
                                       ("fan_on_bearings.toml", (0, 9000, 91)),
                                       ("unstable_cross_coupled.toml", (0, 20000, 201)),
                                       ("spring_block_rotor.toml", (0, 3000, 31))])
def test_texts_are_inside_the_figure_and_apart(model, rpm):
    """Threshold labels, notes of roots beyond the axes and the legend: inside the figure, no
    two overlapping; an undamped machine (spring_block_rotor) gets a readable, finite axis."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(*rpm)))
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for ax in fig.axes for t in ax.texts if t.get_text()]
    boxes += [ax.get_legend().get_window_extent(renderer) for ax in fig.axes if ax.get_legend()]
    for box in boxes:
        assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (a, b)
    for ax in fig.axes[:2]:
        zero, low, high = _zero_fraction(ax)
        assert np.isfinite([low, high]).all() and 0.02 < zero < 0.98
    plt.close(fig)


@pytest.mark.parametrize("model,rpm", [("motor_pump_on_mounts.toml", (0, 3600, 37)),
                                       ("fan_on_bearings.toml", (0, 9000, 46)),
                                       ("journal_rotor.toml", (100, 20000, 101))])
def test_the_least_damped_margin_is_readable(model, rpm):
    """The mode with the smallest log decrement at each speed lies inside both panels, and its
    distance from zero reaches a tenth of each panel's height (the motor and pump's axial modes,
    log decrement 0.0009, real part -0.46 1/s, beside bearing modes at -164 1/s)."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(*rpm)))
    log_dec = np.where(np.isfinite(result.log_decrements), result.log_decrements, np.inf)
    least = np.argmin(log_dec, axis=1)
    rows = np.arange(len(least))
    fig = result.plot()
    for ax, values in zip(fig.axes[:2], (result.real_parts[rows, least], result.log_decrements[rows, least])):
        low, high = ax.get_ylim()
        assert low <= values.min() and values.max() <= high
        assert np.abs(values).max() >= (high - low) / 10, (model, np.abs(values).max(), low, high)
    plt.close(fig)


def test_threshold_label_lies_where_no_curve_runs():
    """unstable_cross_coupled over 0-15,000 rpm: the label of the threshold at 10,886 rpm is drawn,
    touches its own line, and no other curve (modes, zero line) runs through its glyphs."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    result = rdm.stability(model, rdm.rpm(np.linspace(0, 15000, 101)))
    fig, labels, own = _threshold_labels_and_lines(result)
    assert len(labels) == 1 and len(own) == 1
    _assert_beside_its_line_clear_of_the_curves(labels[0], own[0])
    plt.close(fig)


def _threshold_labels_and_lines(result):
    """``result``'s stability figure drawn: the figure, its top panel's threshold labels and lines."""
    fig = result.plot()
    fig.canvas.draw()
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_gid() == "threshold-label"]
    lines = [line for line in ax.get_lines() if line.get_gid() == "threshold"]
    return fig, labels, lines


def _assert_beside_its_line_clear_of_the_curves(text, own):
    """A threshold label's glyphs end within 6 pt of its own line, and no other curve (modes, zero
    line) runs through them."""
    from label_geometry import crossings, curve_segments, glyph_box

    ax = own.axes
    fig = ax.figure
    box = glyph_box(text, fig.canvas.get_renderer())
    line_x = ax.transData.transform((own.get_xdata()[0], 0.0))[0]
    assert min(abs(box.x0 - line_x), abs(box.x1 - line_x)) < 6 * fig.dpi / 72, text.get_text()     # beside its line
    assert not len(crossings(box, curve_segments(ax, skip=[own]))), text.get_text()


def test_a_fast_shaft_mode_does_not_flatten_the_least_damped_modes_onto_zero(examples_dir):
    """The flexible pump's 69 kHz shaft modes set the round-off floor of the real-part panel to
    1e-4 |s| = 43 1/s, so the panel reached +58 1/s though no real part is positive, and its least
    damped modes (real parts about -5e-4 1/s) lay on the zero line. The floor is for real parts
    spanning round-off only: the panel now shows the least damped mode's real parts apart from zero.
    (The axes are scaled to the modes within a decade of the top running speed, 100 Hz, since
    test_figure_audit11: the least damped of those, the 69 kHz modes being named in a note.)"""
    model = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")
    result = rdm.stability(model, rdm.rpm(np.linspace(0.0, 6000.0, 4)))
    top = result.plot().axes[0]
    bottom, upper = top.get_ylim()
    near = np.nanmin(result.frequencies_hz, axis=0) <= 1000.0
    least = np.nanargmax(np.where(near, np.nanmax(result.real_parts, axis=0), -np.inf))
    real = result.real_parts[:, least]
    assert np.all(real < 0) and np.all((real > bottom) & (real < upper))
    assert upper - bottom < 20 * np.abs(real).max()          # the mode spans a visible part of the panel


def test_every_threshold_label_of_an_island_lies_beside_its_line_clear_of_the_curves(tmp_path):
    """The island rotor (tests/test_stability_report.py: unstable, stable again, unstable again,
    each at a closed-form speed): every threshold has its label, beside its own line, and no
    other curve runs through its glyphs. The label of the first onset (1,581 rpm) stood upright
    at the top of its line with its white box over the unstable mode's curve just where that
    curve crosses zero: the crossing the figure is drawn to show was hidden."""
    import matplotlib.pyplot as plt

    from test_stability_report import _crossings_rpm, _island_rotor

    result = rdm.stability(rdm.Model.from_dict(_island_rotor()), rdm.rpm(np.linspace(0.0, 8000.0, 41)))
    expected = [speed for speed, _ in _crossings_rpm(20.0)]
    np.testing.assert_allclose(result.thresholds * 30 / np.pi, expected, rtol=1e-6)
    fig, labels, lines = _threshold_labels_and_lines(result)
    assert len(labels) == len(lines) == len(expected)
    for text in labels:
        speed = float(text.get_text().split(" ")[0].replace(",", ""))
        own = min(lines, key=lambda line: abs(line.get_xdata()[0] - speed))
        _assert_beside_its_line_clear_of_the_curves(text, own)
    plt.close(fig)


# -- the map over speed and a parameter ---------------------------------------------------------

def _map(model, rpm, key, scale):
    if isinstance(model, str):
        model = rdm.load_model(EXAMPLES / model)
    return rdm.stability_map(model, rdm.rpm(np.linspace(*rpm)), key, scale=scale)


@pytest.fixture(scope="module")
def island_map():
    """The island rotor over its mass: an onset, a return to stability and a second onset."""
    from test_stability_report import _island_rotor

    return _map(rdm.Model.from_dict(_island_rotor()), (0.0, 8000.0, 41), "rotors.r.mass", [0.5, 1.0, 2.0, 3.0])


def test_the_map_legend_names_the_boundary_and_covers_no_cell(island_map):
    """The black line (the stability boundary) is named in the legend (the command line's title,
    the model's name, replaces the default title that said so), and the legend lies outside the
    map's axes (it stood over the unstable cells in the upper right)."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.stability import plot_stability_map

    fig = plot_stability_map(island_map, title="the model's name")
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend()
    names = [t.get_text() for t in legend.get_texts()]
    assert any("boundary" in name for name in names), names
    box, frame = legend.get_window_extent(fig.canvas.get_renderer()), ax.get_window_extent()
    assert not box.overlaps(frame), (box, frame)
    assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1
    plt.close(fig)


def test_the_most_unstable_cell_is_drawn_full_red(island_map):
    """The colours are centred on zero with each side scaled to its own extreme: the least
    damping ratio of the map is the colour map's red end, the largest its blue end (a
    symmetric scale drew damping ratios of -0.03 beside +0.08 a pale pink)."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import QuadMesh

    from rotordyn_modal.plotting.stability import plot_stability_map

    fig = plot_stability_map(island_map)
    mesh = [c for c in fig.axes[0].collections if isinstance(c, QuadMesh)][0]
    field = island_map.min_damping_ratios
    assert field.min() < 0 < field.max()
    norm = mesh.norm
    assert norm(field.min()) == pytest.approx(0.0) and norm(field.max()) == pytest.approx(1.0)
    assert norm(0.0) == pytest.approx(0.5)
    plt.close(fig)


def test_a_map_stable_everywhere_says_so_without_a_warning():
    """No boundary, no threshold: the legend says the map is stable everywhere; matplotlib's
    'No artists with labels found to put in legend' (printed by the command line) is not raised."""
    import warnings

    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.stability import plot_stability_map

    result = _map("motor_fan_minimal.toml", (0.0, 6000.0, 4), "suspensions.mount-FL.damping", [0.5, 2.0])
    assert all(not r.unstable_intervals for r in result.results)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = plot_stability_map(result)
    names = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any("stable" in name and "everywhere" in name for name in names), names
    plt.close(fig)


def test_undamped_modes_drawn_over_one_another_on_zero_are_named():
    """spring_block_rotor has no damping: every mode's real part and log decrement are 0 (to
    round-off) at every speed, so the five coloured curves lie on one another on the zero line
    and only the last drawn shows, while the legend lists five. A note beside the panel names
    the modes that lie on zero throughout."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / "spring_block_rotor.toml"), rdm.rpm(np.linspace(0, 3000, 31)))
    assert np.all(result.significant_real_parts[np.isfinite(result.log_decrements)] == 0)
    fig = result.plot()
    top = fig.axes[0]
    legend = [t.get_text() for t in top.get_legend().get_texts() if t.get_text().startswith("mode ")]
    assert len(legend) == 5
    notes = " ".join(t.get_text().replace("\n", " ") for t in top.texts if t.get_gid() == "zero-note")
    assert "modes 1-5" in notes and "on zero" in notes, notes
    plt.close(fig)
