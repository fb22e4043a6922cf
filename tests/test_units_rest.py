"""``--units us`` on the figures and tables converted after the first round (docs/units.md):
mode-shape figures, simulate. Each conversion round-trips SI -> US -> SI with factors checked
against the exact definitions (1 in = 0.0254 m, 1 lbf = 4.4482216152605 N)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.analysis.modal import modal
from rotordyn_modal.analysis.mode_shapes import mode_shape_3d, shaft_lines
from rotordyn_modal.cli import main
from rotordyn_modal.io.model_file import load_model
from rotordyn_modal.units import from_system, to_system

#: the examples, named whole: a module's fixture is made before the autouse fixture (conftest.py)
#: that starts each test in the repository's root
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
IN = 0.0254                  # m, exact (NIST SP 811)
LBF = 4.4482216152605        # N, exact: 0.45359237 kg * 9.80665 m/s^2


@pytest.fixture(scope="module")
def compressor():
    model = load_model(EXAMPLES / "compressor_rotor.toml")
    return model, modal(model, 3000 * np.pi / 30)


def _agg():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def test_length_conversion_round_trips_with_the_exact_inch():
    x = np.array([0.0, 1e-9, 0.0254, 1.2345, -3.0])
    np.testing.assert_allclose(to_system(x, "length", "us"), x / IN, rtol=1e-15)
    np.testing.assert_allclose(from_system(to_system(x, "length", "us"), "length", "us"), x, rtol=1e-12, atol=0)
    np.testing.assert_allclose(to_system(x, "displacement", "us"), x / IN * 1000, rtol=1e-15)
    np.testing.assert_allclose(to_system(x, "force", "us"), x / LBF, rtol=1e-15)


def test_shaft_lines_in_inches_are_the_si_ones_over_the_inch(compressor):
    """Every x on the --plot-shaft figure (lines, nodes, disks, bearings) drawn in in is the SI
    position / 0.0254 and comes back to it to 1e-12; the normalised displacements are unchanged."""
    plt = _agg()
    model, result = compressor
    views = [shaft_lines(result, model, m) for m in (1, 2)]
    from rotordyn_modal.plotting.shaft_modes import plot_shaft_modes

    si, us = plot_shaft_modes(views), plot_shaft_modes(views, units="us")
    assert us.axes[-1].get_xlabel().endswith("[in]") and si.axes[-1].get_xlabel().endswith("[m]")
    pairs = [(a, b) for ax_si, ax_us in zip(si.axes, us.axes)
             for a, b in zip(ax_si.get_lines(), ax_us.get_lines()) if a.get_gid()]   # not the axhline
    assert len(pairs) > 10 and all(a.get_gid() == b.get_gid() for a, b in pairs)
    bearing = next(b for a, b in pairs if str(b.get_gid()).startswith("bearing:"))
    name = bearing.get_gid().split(":")[-1]
    bearing_x = next(b.position for b in model.bearings if b.name == name)
    assert bearing.get_xdata()[0] * IN == pytest.approx(float(np.atleast_1d(bearing_x)[0]), rel=1e-12)
    for a, b in pairs:
        x_si = np.asarray(a.get_xdata(), dtype=float)
        x_us = np.asarray(b.get_xdata(), dtype=float)
        np.testing.assert_allclose(x_us, x_si / IN, rtol=1e-12, atol=0)
        np.testing.assert_allclose(from_system(x_us, "length", "us"), x_si, rtol=1e-12, atol=1e-15)
        np.testing.assert_array_equal(a.get_ydata(), b.get_ydata())
    plt.close("all")


def test_modes_command_line_draws_in_inches(monkeypatch, tmp_path):
    plt = _agg()
    import rotordyn_modal.cli.modes as command

    drawn = []
    monkeypatch.setattr(command, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    base = ["modes", "examples/compressor_rotor.toml", "--speed", "3000", "--quiet"]
    assert main(["--units", "us"] + base + ["--plot-shaft", str(tmp_path / "l.png"), "--modes", "1"]) == 0
    assert main(base + ["--shape", "1", "--plot", str(tmp_path / "s.png"), "--units", "us"]) == 0
    assert drawn[0].axes[-1].get_xlabel() == "position along x [in]"
    _ticks_are_round_inches(drawn[1])
    plt.close("all")


def _ticks_are_round_inches(fig):
    """The 3D view and its three projections: every axis labelled in in, its ticks (placed in
    metres) at round numbers of inches, each label the tick's place / 0.0254 (back to 1e-12)."""
    fig.canvas.draw()
    ax3d = fig.axes[0]
    assert [ax3d.get_xlabel(), ax3d.get_ylabel(), ax3d.get_zlabel()] == ["x [in]", "y [in]", "z [in]"]
    axes = [ax3d.xaxis, ax3d.yaxis, ax3d.zaxis] + [a for ax in fig.axes[1:] for a in (ax.xaxis, ax.yaxis)]
    assert len(axes) == 9 and all(a.get_label_text().endswith("[in]") for a in axes)
    for axis in axes:
        ticks = np.asarray(axis.get_major_locator()(), dtype=float)
        shown = np.array([float(axis.get_major_formatter()(t)) for t in ticks])
        assert len(ticks) >= 3
        np.testing.assert_allclose(shown, np.round(shown, 6), rtol=0, atol=1e-9)     # round inches
        np.testing.assert_allclose(from_system(shown, "length", "us"), ticks, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(shown * IN, ticks, rtol=1e-12, atol=1e-15)


@pytest.fixture(scope="module")
def fan_run():
    """A short run of the fan on its bearings (sensors, two rotors, four bearings), its SI table."""
    from rotordyn_modal.simulation import simulate

    model = load_model(EXAMPLES / "fan_on_bearings.toml")
    result = simulate(model, 0.02, 3000 * np.pi / 30, samples=41, backend="numpy")
    return result, result.to_dataframe()


def test_simulate_table_in_us_units_round_trips(fan_run):
    """Every length, force and moment column of simulate's table in US units is the SI one in
    mil (vibration), in (rotor centres), lbf or lbf in, named with its unit; back to SI to 1e-12;
    the rest (time, angles, rad/s, J) unchanged."""
    from rotordyn_modal.cli.simulate import _in_units

    result, si = fan_run
    us = _in_units(si, result, "us")
    assert _in_units(si, result, "si") is si
    sizes = {"_mil": IN / 1000, "_in": IN, "_lbf": LBF, "_lbfin": LBF * IN}
    assert len(us.columns) == len(si.columns)
    converted = 0
    for old, new in zip(si.columns, us.columns):
        ending = next((e for e in sorted(sizes, key=len, reverse=True) if new.endswith(e) and not old.endswith(e)),
                      None)
        if ending is None:
            assert new == old
            np.testing.assert_array_equal(us[new], si[old])
            continue
        converted += 1
        back = us[new].to_numpy() * sizes[ending]
        np.testing.assert_allclose(back, si[old].to_numpy(), rtol=1e-12, atol=1e-300)
        kind = {"_mil": "displacement", "_in": "length", "_lbf": "force", "_lbfin": "moment"}[ending]
        np.testing.assert_allclose(from_system(us[new].to_numpy(), kind, "us"), si[old], rtol=1e-12, atol=1e-300)
    # u_x..u_z, 4 sensors, 2 x 3 centres, 4 bearings x 6, the drive torque
    assert converted == 3 + len(result.sensor_names) + 3 * len(result.rotor_names) + 6 * len(result.bearing_names) + 1
    assert {"u_x_mil", "probe-DE-x_mil", "fan_center_z_in", "fan-DE_Fz_lbf", "fan-DE_Mx_lbfin",
            "drive_torque_lbfin"} <= set(us.columns)
    assert np.abs(us["fan-DE_Fz_lbf"]).max() > 0 and np.abs(us["probe-DE-x_mil"]).max() > 0


def test_simulate_figure_in_mil(fan_run):
    plt = _agg()
    result, _ = fan_run
    si, us = result.plot(), result.plot(units="us")
    per_metre = {"[m]": 1.0, "[mm]": 1e3, "[µm]": 1e6}       # SI paths in the unit of their size
    si_unit = si.axes[0].get_xlabel().rpartition(" ")[2]
    assert si_unit in per_metre and us.axes[0].get_xlabel().endswith("[mil]")
    for a, b in zip(si.axes[0].get_lines(), us.axes[0].get_lines()):
        np.testing.assert_allclose(np.asarray(b.get_xydata()) * IN / 1000,
                                   np.asarray(a.get_xydata()) / per_metre[si_unit], rtol=1e-12, atol=1e-300)
    right_si, right_us = si.axes[-1], us.axes[-1]          # the translation's twin axis
    assert right_si.get_ylabel().rpartition(" ")[2] in per_metre and right_us.get_ylabel() == "Translation [mil]"
    plt.close("all")


def test_runup_figure_in_mil(fan_run):
    """The run-up panels (signal, 1X amplitude, waterfall colour bar) in mil: the signal drawn is
    the SI one in µm times 1e-6 / 2.54e-5 (back to metres to 1e-12)."""
    plt = _agg()
    from rotordyn_modal.plotting.simulation import plot_runup

    result, _ = fan_run
    si, us = (plot_runup(result, "probe-DE-x", segments=2, units=u) for u in ("si", "us"))
    labels = lambda fig: [ax.get_ylabel() for ax in fig.axes]   # noqa: E731
    assert labels(si)[:2] == ["probe-DE-x [µm]", "probe-DE-x, 1X amplitude, 0-peak [µm]"]
    assert labels(us)[:2] == ["probe-DE-x [mil]", "probe-DE-x, 1X amplitude, 0-peak [mil]"]
    assert labels(us)[-1] == "probe-DE-x, amplitude, 0-peak [mil]" and labels(si)[-1] == "probe-DE-x, amplitude, 0-peak [µm]"
    signal = us.axes[0].get_lines()[0].get_ydata()
    np.testing.assert_allclose(signal * IN / 1000, result.sensor("probe-DE-x"), rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(signal * IN / 1000, si.axes[0].get_lines()[0].get_ydata() * 1e-6, rtol=1e-12,
                               atol=1e-300)
    plt.close("all")


def test_simulate_command_line_names_the_us_units(monkeypatch, capsys, tmp_path):
    plt = _agg()
    import rotordyn_modal.cli.simulate as command

    drawn = []
    monkeypatch.setattr(command, "save_figure", lambda fig, *a, **k: drawn.append(fig))
    assert main(["simulate", "examples/spring_block_rotor.toml", "--duration", "0.02", "--samples", "11",
                 "--backend", "numpy", "--quiet", "--out", "-", "--units", "us", "--plot",
                 str(tmp_path / "s.png")]) == 0
    header = capsys.readouterr().out.splitlines()[0].split(",")
    assert header[:4] == ["time_s", "u_x_mil", "u_y_mil", "u_z_mil"] and "drive_torque_lbfin" in header
    assert "y displacement of the rotor centre [mil]" in [ax.get_xlabel() for ax in drawn[0].axes]
    plt.close("all")


def _soft_block(tmp_path, stiffness=(1e3, 1e3, 1e3)):
    """100 kg on one suspension at its centre of mass under 9.81 m/s²: sag m g / k."""
    import tomli_w

    path = tmp_path / "soft.toml"
    path.write_text(tomli_w.dumps({"stator": {"mass": 100.0, "inertia": [2.0, 2.0, 2.0]},
                                   "suspensions": [{"name": "mount", "position": [0.0, 0.0, 0.0],
                                                    "stiffness": [*stiffness, 1e6, 1e6, 1e6]}],
                                   "gravity": [0.0, 0.0, -9.81]}))
    return path


def test_the_sag_warning_says_inches_and_pounds_in_us_units(tmp_path, capsys):
    """The static sag warning: m g / k = 0.981 m is 38.6 in (0.981 / 0.0254), the limit 0.1 m is
    3.94 in; the weight that nothing holds, 100 kg, is 220.5 lb (100 / 0.45359237). SI unchanged."""
    path = _soft_block(tmp_path)
    for argv in (["--units", "us", "check", str(path)], ["modes", str(path), "--quiet", "--units", "us"]):
        assert main(argv) == 0
        (line,) = capsys.readouterr().err.splitlines()
        assert f"would sag {100 * 9.81 / 1e3 / IN:.3g} in at [suspensions.mount]" in line, line
        assert f"over {0.1 / IN:.3g} in is unlikely" in line and " m " not in line
    assert main(["check", str(path)]) == 0
    assert "would sag 0.981 m at [suspensions.mount] (static deflection on its suspensions; mounts deflect " \
           "millimetres, over 0.1 m is unlikely)" in capsys.readouterr().err
    free = _soft_block(tmp_path, (1e6, 1e6, 0.0))
    assert main(["--units", "us", "check", str(free)]) == 0
    assert f"weight ({100 / 0.45359237:.4g} lb under gravity)" in capsys.readouterr().err


@pytest.mark.parametrize("command, says", [
    ("campbell", "nothing here changes"), ("critical-speeds", "nothing here changes"),
    ("stability", "in the model file's SI unit"), ("fit", "si (default) or us"), ("study", "si (default) or us"),
    ("import-ross", "the model file it writes is SI"), ("modes", "si (default) or us"),
    ("simulate", "si (default) or us")])
def test_every_sub_command_says_what_units_does_to_it(command, says, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert says in text[text.index("--units si|us "):]
