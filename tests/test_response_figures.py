"""The unbalance, orbit, FRF and run-up figures are readable: measured on the drawn figure
(``fig.canvas.draw()``, ``Text.get_window_extent``) as ``test_campbell_figure.py`` does.

Labels lie inside their axes and apart, every curve is named (legend or label) by the
quantity it draws, one axis carries one unit, the orbit figure has one panel per (pair,
source) of the orbit table, the run-up's phase is a line, unwrapped.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.plotting.frf import _MAX_LEGEND

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
UNIT = re.compile(r"\[([^\]]*)\]")


@pytest.fixture(scope="module")
def fan_unbalance():
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    return model, rdm.unbalance_response(model, rdm.rpm(np.linspace(0, 9000, 181)))


def _text_box(text, renderer):
    """The box of a text's glyphs only (an annotation's own extent includes its leader line)."""
    return matplotlib.text.Text.get_window_extent(text, renderer)


def _assert_inside_and_apart(ax, texts, renderer):
    frame = ax.get_window_extent(renderer)
    boxes = [_text_box(t, renderer) for t in texts]
    for t, box in zip(texts, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            (t.get_text(), box, frame)
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (texts[i].get_text(), a, b)


def _curves(ax):
    return [line for line in ax.get_lines() if not line.get_label().startswith("_") and line.get_linestyle() != "None"]


def _every_curve_in_its_legend(ax):
    legend = ax.get_legend()
    named = {t.get_text() for t in legend.get_texts()} if legend else set()
    for line in _curves(ax):
        assert line.get_label() in named, line.get_label()


# -- unbalance --------------------------------------------------------------------------------

#: metres per unit of an amplitude axis
PER_METRE = {"m": 1.0, "mm": 1e3, "µm": 1e6}


def test_unbalance_amplitudes_on_log_axes_probes_apart_from_casing(fan_unbalance):
    """The probes' 0.1 µm and the casing's 100 µm curves are both readable: every amplitude axis
    is logarithmic, probe pairs' sensors never share an axis with the other sensors, and each
    curve drawn is the result's amplitude of the sensor and source its legend names (in the
    axis' unit)."""
    import matplotlib.pyplot as plt

    model, result = fan_unbalance
    fig = result.plot()
    probes = {name for pair in result.orbit_pairs for name in pair}
    amplitude_axes = [ax for ax in fig.axes if "Amplitude" in ax.get_ylabel()]
    assert len(amplitude_axes) == 2
    for ax in amplitude_axes:
        assert ax.get_yscale() == "log"
        _every_curve_in_its_legend(ax)
        names = [line.get_label().split(" (= ")[0].split(": 1X ") for line in _curves(ax)]
        kinds = {name in probes for name, _ in names}
        assert len(kinds) == 1, names
        per_metre = PER_METRE[UNIT.findall(ax.get_ylabel())[0]]
        for line, (name, source) in zip(_curves(ax), names):
            expected = result.amplitude[result.outputs.index(name), result.sources.index(source)]
            np.testing.assert_allclose(np.nan_to_num(line.get_ydata()), expected * per_metre, rtol=1e-15)
    plt.close(fig)


def _plain(text):
    """A tick label's text without matplotlib's math wrapper."""
    return text.replace("$\\mathdefault{", "").replace("}$", "").replace("\\minus", "-").replace("−", "-")


@pytest.mark.parametrize("case, units", [("fan", "si"), ("pump", "si"), ("fan", "us")])
def test_unbalance_amplitude_ticks_read_in_an_engineering_unit(fan_unbalance, pump_unbalance, case, units):
    """Amplitudes were drawn in metres (ticks 10^-6 m): each amplitude axis is in µm or mm (mil
    in US units), the one where the largest curve reads between 1 and 1000 (µm or mil below),
    and every tick label from a thousandth of that curve (and 0.001) up is a plain decimal
    (0.1, 1, 10) equal to its tick's value, never a power of ten."""
    import matplotlib.pyplot as plt

    model, result = fan_unbalance if case == "fan" else pump_unbalance
    fig = result.plot(units=units)
    fig.canvas.draw()
    for ax in [ax for ax in fig.axes if "Amplitude" in ax.get_ylabel()]:
        unit = UNIT.findall(ax.get_ylabel())[0]
        per_metre = {"si": PER_METRE, "us": {"mil": 1e3 / 0.0254, "in": 1 / 0.0254}}[units][unit]
        rows = [result.outputs.index(line.get_label().split(": 1X ")[0]) for line in _curves(ax)]
        largest = np.nanmax(result.amplitude[rows]) * per_metre
        assert 1.0 <= largest < 1000.0 or (unit in ("µm", "mil") and largest < 1.0), (unit, largest)
        low, high = ax.get_ylim()
        shown = [(tick.get_loc(), _plain(tick.label1.get_text())) for tick in ax.yaxis.get_major_ticks()
                 if low <= tick.get_loc() <= high and tick.label1.get_text()]
        assert len(shown) >= 2
        for value, text in shown:
            if value >= max(largest / 1000, 1e-3):
                assert re.fullmatch(r"\d+(\.\d+)?", text), (unit, value, text)
                assert float(text) == pytest.approx(value, rel=1e-9)
    plt.close(fig)


def test_unbalance_peak_labels_inside_and_apart(fan_unbalance):
    """fan_on_bearings over 0-9000 rpm has ~55 peaks: the labels drawn (at most a few per
    panel) lie inside their axes, apart from each other, each at a peak of the result."""
    import matplotlib.pyplot as plt

    model, result = fan_unbalance
    peaks = result.peaks(rdm.rpm(3000))
    fig = result.plot(peaks=peaks, forces="all")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    total = 0
    for ax in fig.axes:
        labels = [t for t in ax.texts if t.get_text().startswith("AF ")]
        total += len(labels)
        assert len(labels) <= 6
        _assert_inside_and_apart(ax, labels, renderer)
        for label in labels:
            speed = float(re.search(r"at (\d+) rpm", label.get_text()).group(1))
            assert np.any(np.abs(peaks.speed_rpm - speed) < 0.5) and "SM " in label.get_text()
    assert total >= 4
    plt.close(fig)


@pytest.fixture(scope="module")
def pump_unbalance():
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    return model, rdm.unbalance_response(model, rdm.rpm(np.linspace(100, 3600, 176)))


@pytest.mark.parametrize("case", ["fan", "pump"])
def test_no_curve_runs_through_an_unbalance_peak_label(fan_unbalance, pump_unbalance, case):
    """fan_on_bearings (0.1 µm probes beside 100 µm casing curves) and the motor + belt-driven
    pump on mounts (modes 5 Hz to 1 kHz, four sensors of two rotors on log axes): no curve of
    a panel (other sensors', other sources', the probe limits) runs through an AF / SM label's
    glyphs but within 6 sqrt(2) points of its own peak; the labels stay inside and apart."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box

    model, result = fan_unbalance if case == "fan" else pump_unbalance
    fig = result.plot(peaks=result.peaks(rdm.rpm(3000)), checks=result.checks(model, mcs=rdm.rpm(3000)) if case == "fan"
                      else None)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    radius = 6 * np.sqrt(2) * fig.dpi / 72 + 1
    total = 0
    for ax in fig.axes:
        labels = [t for t in ax.texts if t.get_text().startswith("AF ")]
        # a peak is named by its label or by a numbered key line ('2: AF 7.6 at 649 rpm ...'):
        # the pump's probe panel numbers two peaks whose leaders would cross a curve (figs30b)
        total += len(labels) + sum(bool(re.match(r"\d+: AF ", t.get_text())) for t in ax.texts)
        _assert_inside_and_apart(ax, labels, renderer)
        segments = curve_segments(ax)
        for label in labels:
            crossed = crossings(glyph_box(label, renderer), segments, [ax.transData.transform(label.xy)], radius)
            assert not len(crossed), (label.get_text(), crossed[:4])
    assert total >= 4
    plt.close(fig)


def test_unbalance_force_panels_one_unit_each(fan_unbalance):
    """--forces all: one panel per kind of force, in newtons, every item of the kind named; no
    axis carries two units."""
    import matplotlib.pyplot as plt

    model, result = fan_unbalance
    fig = result.plot(forces="all")
    force_axes = [ax for ax in fig.axes if ax.get_ylabel() == "Force amplitude, 0-peak [N]"]
    assert len(force_axes) == 3
    named = {line.get_label().split(": 1X ")[0] for ax in force_axes for line in _curves(ax)}
    assert named == set(result.suspension_names) | set(result.bearing_names) | set(result.rotor_names)
    for ax in fig.axes:
        assert len(UNIT.findall(ax.get_ylabel())) == 1, ax.get_ylabel()
        if ax.get_legend():
            _every_curve_in_its_legend(ax)
    plt.close(fig)


# -- orbits -------------------------------------------------------------------------------------

def test_orbit_figure_has_a_panel_per_pair_and_source_as_the_table(fan_unbalance):
    """One panel per (pair, source) of ``orbits()``; each panel's largest drawn orbit is the
    table's largest major semi-axis of that pair and source (in µm): the fan's own 0.73 mm
    orbit is in the figure as in the CSV."""
    import matplotlib.pyplot as plt

    model, result = fan_unbalance
    table = result.orbits()
    fig = result.plot_orbits()
    axes = [ax for ax in fig.axes if ax.get_visible()]
    groups = table.groupby(["pair", "source"])["major"].max()
    assert len(axes) == len(groups)
    for ax in axes:
        first, second, source = re.match(r"^(.*) / (.*), 1X (.*)$", ax.get_title()).groups()
        radius = max(np.hypot(line.get_xdata(), line.get_ydata()).max() for line in ax.get_lines()
                     if len(line.get_xdata()) > 2)
        np.testing.assert_allclose(radius, groups[(f"{first}/{second}", source)] * 1e6, rtol=1e-3)
    plt.close(fig)


# -- FRF ----------------------------------------------------------------------------------------

def test_frf_of_suspension_forces_names_every_curve():
    """The help's ``--forces suspensions`` example (gear_machine, 0 rpm, 48 FRFs): every curve is
    in a legend of at most 12 entries, under its suspension's title, and is |H| of the output
    and input its legend names; forces and moments never share an axis."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    result = rdm.force_frf(model, 0.0, np.linspace(1, 60, 120), where="suspensions")
    assert len(result.outputs) * len(result.inputs) > _MAX_LEGEND
    fig = result.plot()
    drawn = 0
    magnitude_axes = [ax for ax in fig.axes if ax.get_ylabel().startswith("|H|")]
    for ax in magnitude_axes:
        _every_curve_in_its_legend(ax)
        assert len(_curves(ax)) <= _MAX_LEGEND
        item = next(a.get_title() for a in ax.figure.axes if a.get_title())   # the block's title
        units = set()
        for line in _curves(ax):
            component, excitation = line.get_label().split(" (= ")[0].split(" / ")
            units.add(component[0])
            h = result.H[result.outputs.index(f"{item}:{component}"), result.inputs.index(excitation)]
            np.testing.assert_array_equal(line.get_ydata(), np.abs(h))
            drawn += 1
        assert len(units) == 1 and (("N m/N" in ax.get_ylabel()) == (units == {"M"}))
    nonzero = sum(bool(np.any(result.H[o, i])) for o in range(len(result.outputs)) for i in range(len(result.inputs)))
    assert drawn == nonzero
    plt.close(fig)


def test_frf_of_forces_and_moments_of_several_items_names_each_curve_apart():
    """Compressor, every force at 6000 rpm (eight FRFs: both bearings' and the rotor's forces,
    the rotor's moments) in one block of force and moment panels: 'Fy / shaker-y' named three
    curves. Every legend entry is one curve, and that curve is |H| of the output and input the
    entry names."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.force_frf(model, rdm.rpm(6000), np.linspace(1, 200, 50), where="all")
    fig = result.plot()
    magnitude_axes = [ax for ax in fig.axes if ax.get_ylabel().startswith("|H|")]
    assert len(magnitude_axes) == 2 and not any(a.get_title() for a in fig.axes[1:])   # one block, no item title
    drawn = 0
    for ax in magnitude_axes:
        _every_curve_in_its_legend(ax)
        names = [line.get_label() for line in _curves(ax)]
        assert len(names) == len(set(names)), names
        for line in _curves(ax):
            output, excitation = line.get_label().split(" (= ")[0].split(" / ")
            h = result.H[result.outputs.index(output), result.inputs.index(excitation)]
            np.testing.assert_array_equal(line.get_ydata(), np.abs(h))
            drawn += 1
    assert drawn >= 6
    # the one phase panel: each curve in the style of one magnitude curve, no two alike (the
    # moments' curves took the first forces' colours)
    styles = [(line.get_color(), line.get_linestyle()) for ax in magnitude_axes for line in _curves(ax)]
    phase_styles = [(line.get_color(), line.get_linestyle()) for line in fig.axes[-1].get_lines()
                    if line.get_label() != "_overlap"]      # not the dashes drawn where curves lie on each other
    assert len(set(styles)) == len(styles) and sorted(phase_styles) == sorted(styles)
    plt.close(fig)


def test_frf_over_measurement_keeps_one_legend_entry_per_curve():
    """With a measurement (the model itself, 10 % larger) each model curve is named once and its
    dots follow it in its colour."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.frf import FRFResult

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.frf(model, rdm.rpm(3000), np.linspace(1, 100, 200))
    measured = FRFResult(**{**result.__dict__, "H": 1.1 * result.H})
    fig = result.plot(measured=measured)
    mag = fig.axes[0]
    _every_curve_in_its_legend(mag)
    assert len(_curves(mag)) == len(result.outputs) * len(result.inputs)
    plt.close(fig)


# -- run-up ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def gear_runup():
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    result = rdm.simulate(model, 1.5, 0.0, drive="ramp", final_speed=rdm.rpm(3000), samples=6001)
    critical = rdm.campbell(model, rdm.rpm(np.linspace(0, 3000, 61))).critical
    return result, critical


@pytest.fixture(scope="module")
def gear_runup_figure(gear_runup):
    """``gear_runup_figure()``: the run-up's figure of sensor acc-top-z with its critical speeds,
    plotted once for the four tests that measure it (they draw it and read it, and change
    nothing), on a canvas of its own (a figure pyplot closed has none)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    result, critical = gear_runup
    fig = result.plot(sensor="acc-top-z", critical=critical)

    def get():
        if not hasattr(fig.canvas, "get_renderer"):
            FigureCanvasAgg(fig)
        return fig
    return get


def test_runup_phase_is_a_joined_unwrapped_line_and_critical_lines_are_labelled(gear_runup, gear_runup_figure):
    import matplotlib.pyplot as plt

    result, critical = gear_runup
    fig = gear_runup_figure()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    phase_ax, = [ax for ax in fig.axes if "phase" in ax.get_ylabel().lower()]
    lines = _curves(phase_ax)
    assert len(lines) == len(result.rotor_names)
    for line in lines:
        assert line.get_linestyle() not in ("None", "")
        track = result.order_track("acc-top-z", rotor=line.get_label().split("1X ")[1])
        y = np.asarray(line.get_ydata())
        known = np.isfinite(y)                      # NaN: a phase under the other rotors' leakage, not drawn
        assert np.array_equal(known, np.isfinite(track.phase_deg))
        assert np.all(np.abs(np.diff(y[known])) <= 180.0)             # unwrapped
        np.testing.assert_allclose(np.cos(np.radians(y)), np.cos(np.radians(track.phase_deg)), atol=1e-9)
    shown = [c for c in range(len(critical)) if critical.source[c] in result.rotor_names]
    labels = {ax: [t for t in ax.texts if t.get_text().startswith("mode ")] for ax in fig.axes}
    texts = [t.get_text() for group in labels.values() for t in group]
    assert len(texts) >= len(shown) - 2 and texts
    for c in shown:
        wanted = f"mode {critical.mode[c]}, {critical.order[c]:g}X {critical.source[c]}, {critical.speeds_rpm[c]:.0f} rpm"
        assert texts.count(wanted) <= 1
    for ax, group in labels.items():
        _assert_inside_and_apart(ax, group, renderer)
    plt.close(fig)


def test_no_curve_runs_through_a_critical_speed_label(gear_runup, gear_runup_figure):
    """Issue 27: the run-up's critical-speed labels were placed clear of each other only: the
    sensor's signal and the order tracks ran through them. Measured on the drawn figure
    (``label_geometry``): neither crosses a label's glyphs (where critical lines crowd closer
    than a label's width a label may lie across the other critical lines), and every critical
    line keeps its label."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box

    result, critical = gear_runup
    fig = gear_runup_figure()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    checked = 0
    for ax in fig.axes:
        for text in (t for t in ax.texts if t.get_text().startswith("mode ")):
            lines = [line for line in ax.get_lines() if line.get_label() == "_critical"]
            assert any(np.allclose(line.get_xdata(), text.xy[0]) for line in lines), text.get_text()
            through = crossings(glyph_box(text, renderer), curve_segments(ax, skip=lines))
            assert len(through) == 0, (ax.get_title(), text.get_text())
            checked += 1
    assert checked == np.isin(critical.source, result.rotor_names).sum()
    plt.close(fig)


def _runup_from_tracks(monkeypatch, tracks, rotor_names=("shaft",), critical=None):
    """The run-up figure of given order tracks ({rotor: OrderTrack}, over the same speeds [rad/s]),
    with a flat waterfall and a sine time record: the figure computes nothing, so these are what
    it draws."""
    import types

    from rotordyn_modal.plotting.simulation import plot_runup
    from rotordyn_modal.simulation import runup

    speeds = next(iter(tracks.values())).speeds
    fall = runup.Waterfall(speeds, np.linspace(0.0, 200.0, 41), np.full((len(speeds), 41), 1e-9), "probe")
    monkeypatch.setattr(runup, "order_track", lambda *args, rotor=None, **kwargs: tracks[rotor])
    monkeypatch.setattr(runup, "waterfall", lambda *args, **kwargs: fall)
    t = np.linspace(0.0, 1.0, 400)
    result = types.SimpleNamespace(drive_speed=np.linspace(speeds[0], speeds[-1], 400),
                                   rotor_names=list(rotor_names), model_name="test",
                                   sensor=lambda name: 1e-6 * np.sin(300 * t))
    fig = plot_runup(result, "probe", critical=critical)
    fig.canvas.draw()
    return fig


def test_runup_track_legends_hide_no_track(monkeypatch):
    """The order-tracked amplitude's and phase's legends stand where no track runs under them:
    fixed in the upper left, the phase of a rotor through its critical speed (-90 deg falling to
    -270 deg, as the compressor example's) ran under it. Drawn from given tracks (the plotting
    computes nothing), measured on the drawn figure."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments
    from rotordyn_modal.simulation import runup

    speeds = rdm.rpm(np.linspace(3000.0, 9000.0, 60))
    ratio = speeds / rdm.rpm(6000.0)
    response = 1.0 / (1.0 - ratio ** 2 + 0.1j * ratio)
    track = runup.OrderTrack(speeds, 1e-6 * np.abs(response), np.degrees(np.angle(response)) - 90.0,
                             "probe", "shaft", 1.0)
    fig = _runup_from_tracks(monkeypatch, {None: track, "shaft": track})
    renderer = fig.canvas.get_renderer()
    checked = 0
    for ax in fig.axes:
        if ax.get_legend() is not None and ax.get_title().startswith("Order-tracked"):
            assert len(crossings(ax.get_legend().get_window_extent(renderer), curve_segments(ax))) == 0, ax.get_title()
            checked += 1
    assert checked == 2
    plt.close(fig)


def test_runup_track_legends_hide_no_track_among_critical_lines(monkeypatch):
    """The fan's run-up: 22 critical speeds' lines cross every place a legend could take inside
    the order-tracked panels, and matplotlib's 'best' place put the phase's legend on both
    tracks (the amplitude's on the fan's peak). Drawn from given tracks (a resonance at 7700 rpm
    and a small one; the plotting computes nothing), measured on the drawn figure: no track
    runs under a legend."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments
    from rotordyn_modal.analysis.critical_speeds import CriticalSpeeds
    from rotordyn_modal.simulation import runup

    speeds = rdm.rpm(np.linspace(500.0, 8700.0, 25))
    ratio = speeds / rdm.rpm(7700.0)
    response = 1.0 / (1.0 - ratio ** 2 + 0.05j * ratio)
    tracks = {"fan": runup.OrderTrack(speeds, 1e-6 * np.abs(response), np.degrees(np.angle(response)) - 90.0,
                                      "probe", "fan", 1.0),
              "motor": runup.OrderTrack(speeds, 0.15e-6 * np.abs(response) ** 0.5, np.degrees(np.angle(response)),
                                        "probe", "motor", 1.0)}
    at = rdm.rpm(np.array([499, 550, 798, 866, 880, 941, 1063, 1092, 1385, 1502, 1694, 1757, 2740, 3587, 3898,
                           3943, 4157, 5774, 6308, 6929, 7885, 8029.0]))
    n = len(at)
    critical = CriticalSpeeds(np.full(n, "fan"), np.ones(n), np.arange(1, n + 1), at, at / (2 * np.pi),
                              np.full(n, "forward"), np.ones(n), np.full(n, 0.01))
    fig = _runup_from_tracks(monkeypatch, tracks, ("motor", "fan"), critical)
    renderer = fig.canvas.get_renderer()
    checked = 0
    for ax in fig.axes:
        if ax.get_title().startswith("Order-tracked"):
            tracks_only = curve_segments(ax, skip=[line for line in ax.get_lines() if line.get_label() == "_critical"])
            assert len(tracks_only) and ax.get_legend() is not None
            assert len(crossings(ax.get_legend().get_window_extent(renderer), tracks_only)) == 0, ax.get_title()
            checked += 1
    assert checked == 2
    plt.close(fig)


@pytest.mark.parametrize("swing", [65.0, 200.0, 500.0])
def test_runup_phase_axis_has_readable_ticks(monkeypatch, swing):
    """The order-tracked phase's axis is ticked at least three times within its limits: ticks
    every 90 deg on a phase that swings 65 deg (the compressor's run-up, 60 to 125 deg) left one
    tick on the axis. Drawn from a given track, the ticks counted on the drawn axis."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.simulation import runup

    speeds = rdm.rpm(np.linspace(1000.0, 12000.0, 30))
    phase = 60.0 + swing * np.linspace(0.0, 1.0, 30) ** 2
    track = runup.OrderTrack(speeds, 1e-6 * np.ones(30), phase, "probe", "shaft", 1.0)
    fig = _runup_from_tracks(monkeypatch, {None: track, "shaft": track})
    ax, = [a for a in fig.axes if a.get_title() == "Order-tracked phase"]
    low, high = ax.get_ylim()
    ticks = [v for v in ax.get_yticks() if low <= v <= high]
    assert len(ticks) >= 3, ticks
    plt.close(fig)


def test_runup_waterfall_shows_its_content_only(gear_runup, gear_runup_figure):
    """The waterfall's frequency axis ends within 1.5 times the highest frequency where the
    spectrum (or a critical speed) is above 1e-3 of the largest, and nothing above that floor
    lies beyond it."""
    import matplotlib.pyplot as plt

    result, critical = gear_runup
    fig = gear_runup_figure()
    ax, = [a for a in fig.axes if a.get_title() == "Waterfall"]
    fall = result.waterfall("acc-top-z")
    spectrum = fall.amplitude.max(axis=0)
    content = fall.frequencies_hz[spectrum >= 1e-3 * spectrum.max()].max()
    highest = max(content, critical.frequencies_hz.max())
    top = ax.get_xlim()[1]
    assert top <= 1.5 * highest and top >= highest
    assert np.all(spectrum[fall.frequencies_hz > top] < 1e-3 * spectrum.max())
    plt.close(fig)


def test_every_simulation_axis_has_one_unit(gear_runup, gear_runup_figure):
    """Degrees and millimetres (and any other pair of units) never share an axis."""
    import matplotlib.pyplot as plt

    result, critical = gear_runup
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    constant = rdm.simulate(model, 0.3, rdm.rpm(1500), samples=301)
    for fig in (gear_runup_figure(), constant.plot()):
        for ax in fig.axes:
            if ax.get_ylabel():
                assert len(UNIT.findall(ax.get_ylabel())) == 1, ax.get_ylabel()
            for line in _curves(ax):
                units = UNIT.findall(line.get_label())
                assert all(f"[{u}]" in ax.get_ylabel() or u == "deg" and "deg" in ax.get_ylabel()
                           for u in units), (line.get_label(), ax.get_ylabel())
        plt.close(fig)


def test_time_history_legends_hide_no_curve():
    """Issue 27: the energy and rotation panels' legends sat inside the axes over the curves'
    peaks (the spring-block rotor's kinetic energy). Measured on the drawn figure: no curve of
    any panel runs under a legend's box."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments

    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    fig = rdm.simulate(model, 10.0, 50.0, drive="free", samples=2001).plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    segments = [curve_segments(ax) for ax in fig.axes]
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert len(legends) >= 2
    for legend in legends:
        box = legend.get_window_extent(renderer)
        for found in segments:
            assert len(crossings(box, found)) == 0, [t.get_text() for t in legend.get_texts()]
    plt.close(fig)


def test_time_history_axes_need_no_offset_multiplier():
    """Issue 27: the gear machine's rotor paths (tens of µm) were drawn in metres, the ticks
    reading -4 ... 4 with a '1e-5' multiplier in the corner beside '[m]'. Every axis of the
    time histories writes its values in its own unit, without an offset or multiplier, and the
    path's extent in its unit is the rotor centres' largest excursion."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    result = rdm.simulate(model, 0.3, rdm.rpm(1500), samples=301)
    fig = result.plot()
    fig.canvas.draw()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert axis.get_offset_text().get_text() == "", (ax.get_title(), axis.get_label_text())
    path_ax, = [ax for ax in fig.axes if ax.get_title().startswith("Path")]
    unit = UNIT.findall(path_ax.get_xlabel())[0]
    largest = max(np.abs(line.get_xydata()).max() for line in path_ax.get_lines())
    excursion = np.abs((result.rotor_centers - result.rotor_centers[0])[:, :, 1:]).max()
    np.testing.assert_allclose(largest, excursion * {"µm": 1e6, "mm": 1e3, "m": 1.0}[unit], rtol=1e-12)
    plt.close(fig)


# -- the compile notice -------------------------------------------------------------------------

class _Dispatcher:
    def __init__(self, signatures, index):
        self.signatures = signatures
        self._index = index

    @property
    def _cache(self):
        if self._index is None:
            raise AttributeError("no cache")
        return type("C", (), {"_cache_file": type("F", (), {"_load_index": lambda s: self._index})()})()


@pytest.mark.parametrize("signatures,index,printed", [
    ([], None, True),                 # never compiled, no cache: compiles now
    ([], {}, True),                   # cache empty or stale
    ([], {"sig": "entry"}, False),    # loaded from numba's cache
    (["float64(float64)"], None, False),   # compiled already in this process
])
def test_compile_notice_only_when_numba_compiles(signatures, index, printed, capsys):
    from types import SimpleNamespace

    from rotordyn_modal.simulation.simulate import COMPILE_NOTICE, announce_compilation

    assert announce_compilation(SimpleNamespace(rhs_flat=_Dispatcher(signatures, index))) is printed
    assert capsys.readouterr().err == (COMPILE_NOTICE + "\n" if printed else "")
    assert announce_compilation(SimpleNamespace(rhs=None)) is False           # the numpy backend


def test_frf_at_round_off_is_named_so_and_draws_no_phase():
    """compressor_rotor at 0 rpm, shaker in y: the z probes' FRFs are zero by symmetry (1e-17
    against 8e-7 m/N): their legend entries say round-off and no phase of noise is drawn; the
    other FRFs keep their phase."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.frf(model, 0.0, np.linspace(1, 200, 100))
    largest = np.abs(result.H).max()
    fig = result.plot()
    mag, phase = fig.axes[:2]
    for line, phase_line in zip(_curves(mag), phase.get_lines()):
        o, i = line.get_label().split(" (")[0].split(" / ")
        zero = np.abs(result.H[result.outputs.index(o), result.inputs.index(i)]).max() < 1e-6 * largest
        assert ("round-off" in line.get_label()) == zero
        assert np.all(np.isnan(phase_line.get_ydata())) == zero
    assert sum("round-off" in line.get_label() for line in _curves(mag)) == 2
    plt.close(fig)


# -- mode shapes ----------------------------------------------------------------------------------

def test_mode_titles_never_write_a_small_ratio_as_minus_zero():
    """fan_on_bearings at 3000 rpm: mode 1 whirls backward with a ratio of about -0.003; its
    title writes that ratio (not -0.00), and each title's damping and whirl ratio read back
    as the result's to their printed digits; a round-off ratio is written 0."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.modes import small_number

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.modal(model, rdm.rpm(3000))
    fig = result.plot()
    titles = [ax.get_title() for ax in fig.axes if ax.get_visible()]
    modes = np.nonzero(result.oscillatory)[0]
    assert len(titles) == len(modes)
    for title, m in zip(titles, modes):
        zeta, ratio = re.search(r"ζ=(\S+)\n.*\(ratio (\S+)\)", title).groups()
        assert "-0.00" not in title and "+0.00" not in title, title
        for text, value in ((zeta, result.damping_ratios[m]), (ratio, result.whirl_ratios[m])):
            digits = 0 if "." not in text or "e" in text else len(text.split(".")[1])
            last = 0.051 * abs(value) if "e" in text else 0.5 * 10.0 ** -digits + 1e-12
            assert abs(float(text) - value) <= last, (title, value)
    assert small_number(-5.6e-25) == "0" and small_number(-3.2e-3, sign=True) == "-3.2e-03"
    plt.close(fig)


def test_unbalance_curves_that_coincide_are_both_visible(examples_dir):
    """The compressor's probes read the same amplitude in y and z (isotropic bearings): the z
    curve was drawn solid over the y curve, which no reader could see. A curve that covers an
    earlier one within 1 % is drawn in dashes over it and its legend says which it equals."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(examples_dir / "compressor_rotor.toml")
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(500.0, 12000.0, 24)))
    fig = result.plot()
    for ax in fig.axes:
        lines = [line for line in ax.get_lines() if not line.get_label().startswith("_")]
        for k, line in enumerate(lines):
            for earlier in lines[:k]:
                a, b = np.asarray(line.get_ydata(), float), np.asarray(earlier.get_ydata(), float)
                if a.shape == b.shape and np.allclose(a, b, rtol=1e-2, equal_nan=True):
                    assert line.get_linestyle() != earlier.get_linestyle(), line.get_label()
                    assert "(= " in line.get_label()
    plt.close(fig)


def _colour_near_path(image, line, colour, window):
    """For each ``window`` of display x along ``line`` (drawn, inside its axes): whether a pixel
    of ``colour`` (RGB 0-1, within 0.12) lies within two pixels of the line's path there."""
    ax = line.axes
    frame = ax.get_window_extent()
    xy = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
    xy = xy[np.all(np.isfinite(xy), axis=1)]
    height = image.shape[0]
    px = np.arange(np.ceil(max(xy[0, 0], frame.x0)), np.floor(min(xy[-1, 0], frame.x1)))
    py = np.interp(px, xy[:, 0], xy[:, 1])
    matches = np.zeros(len(px), bool)
    target = np.asarray(colour[:3])
    for k, (x, y) in enumerate(zip(px, py)):
        if not frame.y0 <= y <= frame.y1:
            continue
        row = int(round(height - y))
        patch = image[max(row - 2, 0):row + 3, int(x) - 1:int(x) + 2, :3] / 255.0
        matches[k] = np.any(np.all(np.abs(patch - target) < 0.12, axis=-1))
    edges = np.arange(px[0], px[-1], window)
    return px, [bool(matches[(px >= a) & (px < a + window)].any()) for a in edges], edges


def test_unbalance_curves_lying_on_each_other_over_part_of_the_range_all_show(pump_unbalance):
    """The pump's x and y probes for the pump's unbalance differ by more than 1 % and lie on each
    other above 1500 rpm (closer than a line width): the y curve (drawn later, dashed like the
    x curve) covered the x curve there.
    Measured on the rendered pixels: along every curve of the probe panel, in every 20-pixel
    stretch of speed, the curve's own colour shows on its path."""
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    model, result = pump_unbalance
    fig = result.plot()
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())
    ax = next(ax for ax in fig.axes if ax.get_title() == "probe pairs")
    curves = _curves(ax)
    assert len(curves) == 4
    x, y = (next(line for line in curves if line.get_label().startswith(f"probe-pump-{d}: 1X pump")) for d in "xy")
    a, b = (np.asarray(line.get_ydata(), float) for line in (x, y))
    assert np.abs(a - b).max() > 0.01 * np.abs(a).max()              # not one curve within 1 %
    high = np.asarray(x.get_xdata()) >= 1500
    gap = np.abs(ax.transData.transform(np.column_stack([x.get_xdata(), a]))[high, 1]
                 - ax.transData.transform(np.column_stack([y.get_xdata(), b]))[high, 1])
    assert gap.max() < x.get_linewidth() * fig.dpi / 72           # on each other above 1500 rpm
    for line in curves:
        _, shown, edges = _colour_near_path(image, line, mcolors.to_rgb(line.get_color()), 20)
        hidden = [float(ax.transData.inverted().transform((e, 0))[0]) for e, s in zip(edges, shown) if not s]
        assert not hidden, (line.get_label(), np.round(hidden[:8]))
    plt.close(fig)


@pytest.fixture
def layouts(monkeypatch):
    """The constrained layouts run since the fixture began (a list, one entry per layout)."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    done, execute = [], ConstrainedLayoutEngine.execute
    monkeypatch.setattr(ConstrainedLayoutEngine, "execute", lambda self, fig: done.append(fig) or execute(self, fig))
    return done


def test_the_overlaps_cost_no_layout_of_their_own(layouts):
    """Laying a figure out is most of its drawing (its log axes' ticks). The curves lying on each
    other were found on a layout of their own, done again by the save: an FRF figure (each move
    of the tuning widget's slider) is laid out once, by its save (the overlaps found on that
    layout); an unbalance figure whose legends the overlaps widen, twice (the overlaps', the
    save's), as when they widen none."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.interactive import TuningWidget

    gear = rdm.load_model(EXAMPLES / "gear_machine.toml")
    tuner = TuningWidget(gear, [rdm.frf(gear, 0.0, np.linspace(2, 40, 77))], ["suspensions.mount-FL.stiffness"])
    tuner.update(**{"suspensions.mount-FL.stiffness": 1.2}).draw_without_rendering()     # as saved, not rendered
    assert len(layouts) == 1
    result = rdm.unbalance_response(rdm.load_model(EXAMPLES / "compressor_rotor.toml"),
                                    rdm.rpm(np.linspace(500.0, 12000.0, 24)))
    fig = result.plot(outputs=["probe-left-y", "probe-left-z"])        # isotropic: z on y
    assert any("(= " in line.get_label() for ax in fig.axes for line in ax.get_lines())   # legends widened
    fig.draw_without_rendering()
    assert len(layouts) == 1 + 2
    plt.close("all")


@pytest.mark.parametrize("case", ["fan", "pump", "gear", "rubber"])
def test_unbalance_peak_leaders_cross_no_curve(fan_unbalance, pump_unbalance, case):
    """Leader lines of AF / SM labels crossed curves (fan_on_bearings' AF 95.7 at 5800 rpm across
    the casing's curves, gear_machine's and rubber_mounts' labels below their peaks across
    the other sensors'): every leader line drawn (from its label to its peak) crosses no
    curve of its panel but within 6 sqrt(2) points of its own peak, and is at most 2 inches
    long; each panel with peaks still labels its largest peak."""
    import matplotlib.pyplot as plt

    from label_geometry import curve_segments, segment_crossings

    if case in ("fan", "pump"):
        model, result = fan_unbalance if case == "fan" else pump_unbalance
    else:
        model = rdm.load_model(EXAMPLES / ("gear_machine.toml" if case == "gear" else "rubber_mounts.toml"))
        result = rdm.unbalance_response(model, rdm.rpm(np.linspace(0, 6000 if case == "gear" else 3000, 151)))
    fig = result.plot(peaks=result.peaks(rdm.rpm(3000 if case != "rubber" else 1500)))
    fig.canvas.draw()
    radius = 6 * np.sqrt(2) * fig.dpi / 72 + 1
    total = 0
    for ax in fig.axes:
        segments = curve_segments(ax)
        for label in [t for t in ax.texts if t.get_text().startswith("AF ")]:
            total += 1
            anchor = ax.transData.transform(label.xy)
            start = label.arrow_patch.get_path().vertices[0]
            crossed = segment_crossings(start, anchor, segments, anchor, radius)
            assert not len(crossed), (label.get_text(), crossed[:4])
            assert np.hypot(*(start - anchor)) <= 2 * fig.dpi, label.get_text()
    assert total >= 2
    plt.close(fig)


def test_frf_curves_equal_by_symmetry_all_show_and_say_which_they_equal():
    """motor_fan_minimal's mounts stand symmetric about the hammer's plane: the front-right
    mount's Fy equals the front-left's, the rear mounts' Fx the front mounts' (within round-off,
    by the symmetry of the model, not of the code). Drawn solid one over the other, the earlier
    curve was hidden. Each curve equal to an earlier one says which in its legend, and on the
    rendered pixels every curve's own colour shows along its path in every stretch of 30 pixels (a group of up to five curves on each other alternates
    dashes of 4 pt = 5.6 px: a period of up to 28 px)."""
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "motor_fan_minimal.toml")
    result = rdm.force_frf(model, 0.0, np.linspace(1.0, 100.0, 300), where="suspensions")
    fig = result.plot()
    fig.canvas.draw()
    image = np.asarray(fig.canvas.buffer_rgba())
    ax = next(ax for ax in fig.axes if ax.get_ylabel().startswith("|H|"))
    curves = _curves(ax)
    equal = 0
    for k, line in enumerate(curves):
        h = np.asarray(line.get_ydata(), float)
        twins = [e for e in curves[:k] if np.allclose(np.asarray(e.get_ydata(), float), h, rtol=1e-2)]
        if twins:
            equal += 1
            twin = twins[0].get_label().split(" (= ")[0]
            assert line.get_label().endswith(f"(= {twin})"), line.get_label()
    assert equal >= 3
    for line in curves:
        _, shown, edges = _colour_near_path(image, line, mcolors.to_rgb(line.get_color()), 30)
        hidden = [float(ax.transData.inverted().transform((e, 0))[0]) for e, s in zip(edges, shown) if not s]
        assert not hidden, (line.get_label(), np.round(hidden[:8], 2))
    plt.close(fig)
