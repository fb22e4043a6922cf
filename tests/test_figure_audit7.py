"""Figures of the seventh audit (issue 27, section 3: figures that cannot mislead), measured on
the drawn figure, independent of the code that draws it: the 3-D mode shapes of ``modes
--shape``, the model-over-measurement FRF of ``frf --measured``, the study figures and the
run-up of ``simulate --ramp``.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("model, mode", [("spring_block_rotor.toml", 1), ("fan_on_bearings.toml", 5)])
def test_mode_shape_legend_names_every_displaced_colour(model, mode):
    """The legend's 'displaced' entries show exactly the colours the displaced bodies are drawn
    in: a machine of rotors only (the spring block's rotor, the compressor's shaft: orange) had
    one blue 'displaced' entry and no orange one; a stator (blue) and rotors (orange) get one
    entry each."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    machine = rdm.load_model(EXAMPLES / model)
    view = mode_shape_3d(rdm.modal(machine, rdm.rpm(3000.0)), machine, mode)
    fig = plot_mode_shape(view, orbits=False, labels=False, projections=False)
    ax = fig.axes[0]
    drawn = {matplotlib.colors.to_hex(line.get_color()) for line in ax.get_lines()
             if str(line.get_gid()).startswith("displaced") and not str(line.get_gid()).startswith("displaced-")
             or str(line.get_gid()).startswith("displaced-bracket")}
    keyed = {matplotlib.colors.to_hex(handle.get_color()) for handle in ax.get_legend().legend_handles
             if "displaced" in handle.get_label()}
    assert drawn and keyed == drawn


@pytest.fixture(scope="module")
def gear_frf():
    """The gear machine's accelerances at standstill, 1-60 Hz (60 frequencies), and a
    'measurement' equal to them but for a phase error of +-2 deg, alternating."""
    import dataclasses

    model = rdm.frf(rdm.load_model(EXAMPLES / "gear_machine.toml"), 0.0, np.linspace(1.0, 60.0, 60),
                    quantity="accelerance")
    error = np.exp(1j * np.radians(2.0) * (-1.0) ** np.arange(60))
    return model, dataclasses.replace(model, H=model.H * error)


def _phase_curves(ax):
    """{colour: (model line's x, y), measured dots' x, y} of an FRF phase panel."""
    lines, dots = {}, {}
    for line in ax.get_lines():
        colour = matplotlib.colors.to_hex(line.get_color())
        xy = (np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
        (dots if line.get_linestyle() in ("None", "", " ") else lines)[colour] = xy
    return lines, dots


def test_frf_phase_lines_do_not_jump_across_the_panel(gear_frf):
    """A phase that wraps from -180 to 180 deg is not joined by a line across the panel (it
    read as a curve of its own crossing the others): no segment drawn between neighbouring
    frequencies of a model phase line spans more than 180 deg; the green accelerance
    (acc-side-y / hammer-z) wraps near 12 Hz."""
    model, measured = gear_frf
    fig = model.plot(measured=measured)
    lines, _ = _phase_curves(fig.axes[1])
    assert len(lines) >= 3
    wrapped = 0
    for colour, (x, y) in lines.items():
        finite = np.isfinite(y)
        steps = np.abs(np.diff(y))[finite[1:] & finite[:-1]]
        assert np.all(steps <= 180.0), colour
        wrapped += np.sum(~finite[1:-1])
    assert wrapped >= 1                                  # a wrap is there, drawn as a break


def test_measured_phase_lies_on_its_model_line(gear_frf):
    """A measurement within 2 deg of the model everywhere is drawn within 2 deg of the model's
    line at every frequency, also where the phase is near +-180 deg (the accelerances below
    the first mode): the dots of -179 deg under a line at 179 deg stood at the panel's other
    edge, 358 deg away, reading as another curve."""
    model, measured = gear_frf
    fig = model.plot(measured=measured)
    lines, dots = _phase_curves(fig.axes[1])
    near_180 = 0
    for colour, (x, y) in dots.items():
        lx, ly = lines[colour]
        keep = np.isfinite(ly)
        if not keep.any():                              # round-off: no phase line drawn
            continue
        on_line = np.interp(x, lx[keep], ly[keep])     # same frequencies: the line's own points
        difference = np.abs((y - on_line))
        assert np.all(difference <= 2.0 + 1e-9), (colour, x[difference > 2.0 + 1e-9])
        near_180 += np.sum(np.abs(on_line) > 175.0)
    assert near_180 >= 20


def _simulation(n=400, kinetic=None, potential=None, moving=True):
    """A stand-in for a SimulationResult of two rotors over 0.2 s (``n`` samples): the energies
    given [J], the stator's and rotors' motion zero unless ``moving``."""
    import types

    t = np.linspace(0.0, 0.2, n)
    wave = np.sin(2 * np.pi * 50.0 * t)
    kinetic = np.zeros(n) if kinetic is None else kinetic
    potential = np.zeros(n) if potential is None else potential
    centres = np.zeros((n, 2, 3))
    displacement = np.zeros((n, 3))
    if moving:
        centres[:, 0, 1], centres[:, 0, 2] = 1e-5 * wave, 1e-5 * np.cos(2 * np.pi * 50.0 * t)
        displacement[:, 2] = 1e-6 * wave
    return types.SimpleNamespace(time=t, rotor_names=["upper", "lower"], rotor_centers=centres,
                                 displacement=displacement, gamma=np.zeros((n, 3)), gamma_deg=np.zeros(n),
                                 rotor_tilts=np.zeros((n, 2, 3)), rotor_tilts_deg=np.zeros((n, 2)),
                                 spin_speed=np.full(n, 314.0),
                                 kinetic_energy=kinetic, total_energy=kinetic + potential,
                                 elastic_energy=potential, gravity_energy=np.zeros(n), model_name="test")


def _pixels(fig):
    """The rendered image ``(rows, columns, 3)`` [0-255], row 0 at the top."""
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(float)


def _near(pixels, colour, tolerance=60.0):
    """Whether each pixel is within ``tolerance`` (RGB distance) of ``colour``."""
    rgb = 255.0 * np.asarray(matplotlib.colors.to_rgb(colour))
    return np.linalg.norm(pixels - rgb, axis=-1) < tolerance


def test_total_energy_shows_where_it_lies_on_the_potential_energy():
    """A rotor on journal bearings at constant speed: the kinetic energy stays constant, the
    total energy equals the potential energy. The total (dashed) was drawn under the
    potential's line and hidden there (journal_rotor.toml, --speed 3000 --duration 0.2): along
    the potential's curve the total's colour shows."""
    from rotordyn_modal.plotting.simulation import plot_simulation

    t = np.linspace(0.0, 0.2, 400)
    potential = -0.002 * (1.0 - np.cos(2 * np.pi * 50.0 * t))
    fig = plot_simulation(_simulation(potential=potential))
    ax, = [a for a in fig.axes if a.get_title() == "Energy"]
    total = [line for line in ax.get_lines() if "total" in line.get_label()][0]
    image = _pixels(fig)
    height = image.shape[0]
    shown = 0
    for k in range(20, 400, 40):
        x, y = ax.transData.transform((t[k], potential[k]))
        window = image[int(height - y) - 3:int(height - y) + 4, int(x) - 12:int(x) + 13]
        shown += _near(window, total.get_color()).sum() >= 4
    assert shown >= 8, shown


def test_motion_that_is_zero_throughout_is_shown_and_named():
    """A machine that does not move (counter_rotating.toml run up: balanced, no stator motion):
    each rotor's path of no length is drawn as a point (rings of their own sizes, both
    visible at one place) named 'no motion'; the stator's rotation and translations, zero
    throughout, lie on each other on the zero line and each legend entry says so. Before, the
    path panel was empty and the four zero curves showed as one."""
    from rotordyn_modal.plotting.simulation import plot_simulation

    fig = plot_simulation(_simulation(moving=False))
    paths, frame = fig.axes[0], fig.axes[1]
    drawn = [line for line in paths.get_lines() if line.get_visible()]
    assert len(drawn) == 2
    sizes = set()
    for line in drawn:
        assert line.get_marker() not in (None, "None", "", " ") and "no motion" in line.get_label()
        sizes.add(line.get_markersize())
    assert len(sizes) == 2                                 # one ring does not hide the other
    named = [text.get_text() for text in frame.get_legend().get_texts()]
    assert len(named) == 4 and all("0 throughout" in name for name in named), named


def test_motion_that_is_not_zero_is_not_called_zero():
    """The same figure for a machine that moves: its paths are lines, no legend says '0
    throughout' of a curve that is not (the stator's u_z moves, its rotation does not)."""
    from rotordyn_modal.plotting.simulation import plot_simulation

    fig = plot_simulation(_simulation(moving=True))
    paths, frame = fig.axes[0], fig.axes[1]
    moving = [line for line in paths.get_lines() if "upper" in line.get_label()][0]
    assert moving.get_linestyle() == "-" and "no motion" not in moving.get_label()
    named = {text.get_text().split(" [")[0].split(":")[0]: text.get_text() for text in frame.get_legend().get_texts()}
    assert "0 throughout" not in named["u_z"] and "0 throughout" in named["u_x"], named


_TOLERANCE = {"seed": 3, "samples": 3, "design": "latin-hypercube",
              "parameters": [{"key": "suspensions.mount-FL.stiffness", "apply": "scale", "distribution": "uniform",
                              "low": 0.85, "high": 1.15}],
              "analyses": {"campbell": {"speeds_rpm": "0:6000:3", "orders": [1]}}}


@pytest.fixture(scope="module")
def tolerance_study():
    """The gear machine under a +-15 % tolerance of one mount (3 variants, 3 speeds): a
    Campbell sweep and no critical-speed analysis."""
    return rdm.study(rdm.load_model(EXAMPLES / "gear_machine.toml"), _TOLERANCE)


def _legend_colours(ax):
    """{label: RGB} of each legend entry as drawn: a line's colour, a filled patch's face, an
    unfilled (hatched) patch's edge."""
    colours = {}
    for handle, text in zip(ax.get_legend().legend_handles, ax.get_legend().get_texts()):
        if hasattr(handle, "get_facecolor") and not hasattr(handle, "get_xdata"):
            face = handle.get_facecolor()
            colour = face if face[3] > 0 else handle.get_edgecolor()
        else:
            colour = handle.get_color()
        colours[text.get_text()] = matplotlib.colors.to_hex(colour, keep_alpha=False)
    return colours


def test_study_operating_band_is_not_coloured_as_a_mode(tolerance_study):
    """`study --plot` with an operating band: the band was shaded in orange, mode 2's colour (its
    median line and its 5-95 % band), so the band read as a mode's band. Every legend entry
    has a colour of its own."""
    fig = tolerance_study.plot_campbell(band_rpm=(3400.0, 3700.0))
    colours = _legend_colours(fig.axes[0])
    assert "operating band" in colours and "mode 2" in colours
    assert len(set(colours.values())) == len(colours), colours


def test_study_figure_of_an_analysis_not_run_is_one_clear_line(tolerance_study, tmp_path, capsys):
    """A figure of an analysis the study file does not run: the histograms of a study without
    critical speeds failed with 'KeyError: No variable named critical_speed' (exit 1) after
    the whole study was computed; the function refuses it in words, and the command before
    any work (exit 2, no results, no checkpoint)."""
    import json

    from rotordyn_modal.cli.main import main
    from rotordyn_modal.errors import InputError

    with pytest.raises(InputError, match="critical_speeds"):
        tolerance_study.plot_critical_histograms()
    spec = tmp_path / "tolerance.study.toml"
    spec.write_text("\n".join([
        "seed = 3", "samples = 6", "[[parameters]]", 'key = "suspensions.mount-FL.stiffness"', 'apply = "scale"',
        'distribution = "uniform"', "low = 0.85", "high = 1.15", "[analyses.campbell]",
        f"speeds_rpm = {json.dumps('0:6000:7')}"]))
    out = tmp_path / "r.nc"
    code = main(["study", str(EXAMPLES / "gear_machine.toml"), "--spec", str(spec), "--out", str(out),
                 "--plot-histogram", str(tmp_path / "h.png"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "--plot-histogram" in err and "critical_speeds" in err and len(err.splitlines()) == 1, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tolerance.study.toml"]


def test_study_map_axis_of_set_values_names_its_unit(tmp_path, monkeypatch):
    """`study --plot-map` over a grid of values set on a key (bearing damping [N s/m]): the axis
    named the key without its unit in SI (only --units us named one); a factor (apply =
    'scale') stays a bare name."""
    import matplotlib.figure

    from rotordyn_modal.cli.main import main

    spec = tmp_path / "map.study.toml"
    spec.write_text("\n".join([
        "[[parameters]]", 'name = "damping"',
        'keys = ["suspensions.bearing-A.damping[1]", "suspensions.bearing-A.damping[2]",',
        '        "suspensions.bearing-B.damping[1]", "suspensions.bearing-B.damping[2]"]', "values = [200.0, 400.0]",
        "[[parameters]]", 'name = "cross-coupling factor"',
        'keys = ["suspensions.bearing-A.stiffness[1][2]", "suspensions.bearing-B.stiffness[1][2]"]',
        "scale = [0.5, 1.0]", "[analyses.stability]", 'speeds_rpm = "0:30000:4"']))
    drawn = []
    save = matplotlib.figure.Figure.savefig
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig",
                        lambda fig, *a, **k: (drawn.append((fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel())),
                                              save(fig, *a, **k))[1])
    code = main(["study", str(EXAMPLES / "unstable_cross_coupled.toml"), "--spec", str(spec),
                 "--out", str(tmp_path / "map.nc"), "--plot-map", str(tmp_path / "map.png"), "--quiet"])
    assert code == 0 and drawn == [("damping [N s/m]", "cross-coupling factor")], drawn


def test_runup_waterfall_legend_hides_no_critical_speed(monkeypatch):
    """The waterfall's legend ('critical speeds (Campbell)') stood in the upper right corner,
    where the highest critical speeds' circles lie (fan_on_bearings.toml run up to 9000 rpm:
    mode 12 at 131 Hz and 7885 rpm under the legend's box). No circle's centre lies in a
    legend's box."""
    import types

    from rotordyn_modal.analysis.critical_speeds import CriticalSpeeds
    from rotordyn_modal.plotting.simulation import plot_runup
    from rotordyn_modal.simulation import runup

    speeds = rdm.rpm(np.linspace(0.0, 9000.0, 31))
    track = runup.OrderTrack(speeds, 1e-6 * np.ones(31), np.zeros(31), "probe", "fan", 1.0)
    fall = runup.Waterfall(speeds, np.linspace(0.0, 200.0, 41), np.full((31, 41), 1e-9), "probe")
    monkeypatch.setattr(runup, "order_track", lambda *args, **kwargs: track)
    monkeypatch.setattr(runup, "waterfall", lambda *args, **kwargs: fall)
    t = np.linspace(0.0, 1.0, 500)
    result = types.SimpleNamespace(drive_speed=np.linspace(speeds[0], speeds[-1], 500), rotor_names=["fan"],
                                   model_name="test", sensor=lambda name: 1e-6 * np.sin(3000 * t))
    at = rdm.rpm(np.array([1000.0, 7885.0, 8500.0]))
    hz = np.array([10.0, 131.0, 170.0])
    critical = CriticalSpeeds(np.array(["fan"] * 3), np.ones(3), np.arange(1, 4), at, hz,
                              np.array(["forward"] * 3), np.ones(3), np.full(3, 0.01))
    fig = plot_runup(result, "probe", critical=critical)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax, = [a for a in fig.axes if a.get_title() == "Waterfall"]
    circles, = [line for line in ax.get_lines() if line.get_marker() == "o"]
    centres = ax.transData.transform(np.column_stack([circles.get_xdata(), circles.get_ydata()]))
    inside = ax.get_window_extent(renderer)
    assert all(inside.contains(*c) for c in centres)               # all three drawn in the panel
    for legend in [a.get_legend() for a in fig.axes if a.get_legend()] + fig.legends:
        box = legend.get_window_extent(renderer)
        assert not any(box.contains(*c) for c in centres), legend.get_texts()[0].get_text()


def test_sensitivity_first_order_marks_are_told_from_the_error_bars():
    """The Sobol chart (`study --plot-sensitivity`, mount_sobol.study.toml) marked S1 with a black
    '|' on the black line of ST's standard error, where it read as the error bar's end. The S1
    marks differ from the error bars in colour, and the legend names both."""
    import pandas as pd
    from matplotlib.container import ErrorbarContainer

    from rotordyn_modal.plotting.study import plot_sensitivity

    table = pd.DataFrame({"output": ["f1", "f1", "f2", "f2"], "parameter": ["mass", "mounts"] * 2,
                          "S1": [0.12, 0.40, 0.05, 0.70], "ST": [0.10, 0.45, 0.06, 0.75],
                          "S1_se": [0.02] * 4, "ST_se": [0.03] * 4})
    fig = plot_sensitivity(table)
    ax = fig.axes[0]
    marks = [line for line in ax.get_lines() if line.get_linestyle() in ("None", "", " ") and len(line.get_xdata()) == 2]
    assert len(marks) == 2 and all(np.allclose(np.sort(m.get_xdata()), np.sort(table[table.parameter == p].S1))
                                   for m, p in zip(marks, ("mass", "mounts")))
    bars = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    error_colours = {matplotlib.colors.to_hex(c.lines[2][0].get_color()[0]) for c in bars}
    assert len(bars) == 2 and error_colours
    for mark in marks:
        assert matplotlib.colors.to_hex(mark.get_color()) not in error_colours
    named = " ".join(t.get_text() for t in ax.get_legend().get_texts())
    assert "S1" in named and "standard error" in named, named
