"""Unit systems (docs/units.md): SI inside, SI or US customary at the edge. The factors are
checked against their exact definitions (NIST SP 811 appendix B, written here), conversions
round-trip, and the command line in US units says the same as in SI."""

from __future__ import annotations

import io
import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotordyn_modal.cli import main
from rotordyn_modal.units import QUANTITIES, from_system, to_system, unit_label, unit_scale

# exact definitions (NIST SP 811, B.8 and B.9), independent of the module's constants
IN = 0.0254                  # m, exact
LB = 0.45359237              # kg, exact
GN = 9.80665                 # m/s^2, standard gravity, exact
LBF = 4.4482216152605        # N = LB * GN exactly
NIST_US = {                  # kind: (label, size in SI)
    "length": ("in", 0.0254),
    "displacement": ("mil", 2.54e-5),
    "velocity": ("in/s", 0.0254),
    "acceleration": ("g", 9.80665),
    "force": ("lbf", 4.4482216152605),
    "moment": ("lbf in", 0.1129848290276167),       # 4.4482216152605 * 0.0254
    "stiffness": ("lbf/in", 175.1268352464764),     # 4.4482216152605 / 0.0254 (175.12683524647637...)
    "damping": ("lbf s/in", 175.1268352464764),
    "mass": ("lb", 0.45359237),
    "inertia": ("lb in²", 2.926396534292e-4),       # 0.45359237 * 0.0254**2, exact
    "unbalance": ("oz in", 7.20077887375e-4),       # 0.45359237 / 16 * 0.0254 kg m, exact
    "pressure": ("psi", 6894.757293168361),         # 4.4482216152605 / 0.0254**2 (...8361336...)
    "viscosity": ("reyn", 6894.757293168361),
    "power": ("hp", 745.69987158227022),            # 550 ft lbf/s
    "frequency": ("Hz", 1.0),
    "speed": ("rpm", 1.0),
    "angle": ("rad", 1.0),
    "density": ("lb/ft³", 16.018463373960138),      # 0.45359237 / 0.3048**3
}


@pytest.mark.parametrize("kind", sorted(NIST_US))
def test_us_factors_are_the_exact_definitions(kind):
    label, size = NIST_US[kind]
    assert unit_label(kind, "us") == label
    factor, shown = unit_scale(kind, "us")
    assert shown == label
    assert math.isclose(1.0 / factor, size, rel_tol=1e-14)
    assert math.isclose(from_system(1.0, kind, "us"), size, rel_tol=1e-14)


def test_every_kind_is_checked_and_si_is_si():
    assert set(QUANTITIES) == set(NIST_US)
    for kind in QUANTITIES:
        expected = 1e-6 if kind == "unbalance" else 1.0         # unbalance: kg m inside, g mm shown
        assert from_system(1.0, kind, "si") == expected


@settings(max_examples=150, deadline=None)
@given(st.sampled_from(sorted(NIST_US)), st.sampled_from(["si", "us"]),
       st.floats(min_value=-1e12, max_value=1e12, allow_nan=False).filter(lambda v: v == 0 or abs(v) > 1e-12))
def test_round_trips_both_ways(kind, system, value):
    back = from_system(to_system(value, kind, system), kind, system)
    assert math.isclose(back, value, rel_tol=1e-12, abs_tol=0.0)
    there = to_system(from_system(value, kind, system), kind, system)
    assert math.isclose(there, value, rel_tol=1e-12, abs_tol=0.0)
    array = np.array([value, -value, 0.0])
    np.testing.assert_allclose(from_system(to_system(array, kind, system), kind, system), array, rtol=1e-12, atol=0)


def _csv(capsys, argv):
    assert main(argv) == 0
    return pd.read_csv(io.StringIO(capsys.readouterr().out))


def _same_numbers(us, si, factor, column):
    """US column = SI column x factor to 1e-12, every value (the CSV keeps every digit, issue 29)."""
    np.testing.assert_allclose(us, si * factor, rtol=1e-12, atol=0, err_msg=column)


def test_unbalance_in_us_units_says_the_same(capsys):
    argv = ["unbalance", "examples/fan_on_bearings.toml", "--speeds", "300:9000:30", "--forces", "all",
            "--amplitude", "rms", "--out", "-", "--quiet"]
    si = _csv(capsys, argv)
    us = _csv(capsys, ["--units", "us"] + argv)
    assert list(us.columns) == list(si.columns) + ["unit"]
    component = si["output"].str.rsplit(":", n=1).str[1].fillna("")
    factor = np.where(component.str.startswith("F"), 1 / LBF,
                      np.where(component.str.startswith("M"), 1 / (LBF * IN), 1000 / IN))   # sensors: mil
    labels = np.where(component.str.startswith("F"), "lbf", np.where(component.str.startswith("M"), "lbf in", "mil"))
    assert (us["unit"].to_numpy() == labels).all()
    for column in si.columns:
        if column in ("amplitude", "amplitude_rms"):
            _same_numbers(us[column].to_numpy(), si[column].to_numpy(), factor, column)
        elif si[column].dtype.kind == "f" and column != "phase_deg":
            np.testing.assert_array_equal(us[column], si[column], err_msg=column)
        elif column != "phase_deg":
            assert (us[column] == si[column]).all(), column
    moving = si["amplitude"].to_numpy() > 1e-6 * si["amplitude"].max()    # phases of round-off noise are noise
    np.testing.assert_allclose(us["phase_deg"][moving], si["phase_deg"][moving], atol=1e-6)


def test_static_in_us_units_says_the_same(capsys, monkeypatch):
    si_argv = ["static", "examples/gear_machine.toml", "--speed", "3000", "--power", "15000",
               "--force", "stator:0.1,0.2,0.3:10,-20,30", "--moment", "fan:1,2,3", "--out", "-"]
    us_argv = ["static", "examples/gear_machine.toml", "--speed", "3000", "--power", repr(15000 / 745.69987158227022),
               "--force", f"stator:{0.1 / IN!r},{0.2 / IN!r},{0.3 / IN!r}:{10 / LBF!r},{-20 / LBF!r},{30 / LBF!r}",
               "--moment", f"fan:{1 / (LBF * IN)!r},{2 / (LBF * IN)!r},{3 / (LBF * IN)!r}", "--out", "-"]
    si = _csv(capsys, si_argv)
    monkeypatch.setenv("ROTORDYN_MODAL_UNITS", "us")       # set once for the session
    us = _csv(capsys, us_argv)
    renamed = {"x_m": "x_in", "y_m": "y_in", "z_m": "z_in", "ux_m": "ux_in", "uy_m": "uy_in", "uz_m": "uz_in",
               "Fx_N": "Fx_lbf", "Fy_N": "Fy_lbf", "Fz_N": "Fz_lbf",
               "Mx_Nm": "Mx_lbfin", "My_Nm": "My_lbfin", "Mz_Nm": "Mz_lbfin"}
    assert list(us.columns) == [renamed.get(c, c) for c in si.columns]
    factors = {column: 1 / IN if column.endswith("_m") else 1 / LBF if column.endswith("_N") else 1 / (LBF * IN)
               for column in renamed}
    for column in si.columns:
        if column in renamed:
            _same_numbers(us[renamed[column]].to_numpy(float), si[column].to_numpy(float), factors[column], column)
        elif si[column].dtype.kind == "f":        # angles, eccentricities: the same numbers
            np.testing.assert_allclose(us[column], si[column], rtol=1e-12, atol=0, err_msg=column)
        else:
            assert (us[column].fillna("") == si[column].fillna("")).all(), column


def test_the_option_wins_over_the_environment(capsys, monkeypatch):
    monkeypatch.setenv("ROTORDYN_MODAL_UNITS", "us")
    si = _csv(capsys, ["static", "examples/motor_pump_on_mounts.toml", "--units", "si", "--out", "-"])
    assert "x_m" in si.columns and "Fx_N" in si.columns


@pytest.mark.parametrize("argv, source", [(["--units", "imperial"], "--units 'imperial'"),
                                          (["--units", ""], "--units ''"),
                                          ([], "ROTORDYN_MODAL_UNITS 'cgs'")])
def test_a_bad_unit_system_exits_2_in_one_line(capsys, monkeypatch, argv, source):
    monkeypatch.setenv("ROTORDYN_MODAL_UNITS", "cgs")
    assert main(argv + ["static", "examples/motor_pump_on_mounts.toml"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and source in err and "si, us" in err, err


def test_ucs_map_and_level1_in_us_units_say_the_same(capsys):
    si = _csv(capsys, ["ucs-map", "examples/journal_rotor.toml", "--stiffness", "1e6:1e9:7", "--modes", "2",
                       "--out", "-", "--quiet"])
    k = 1 / (LBF / IN)                                           # N/m -> lbf/in
    us = _csv(capsys, ["--units", "us", "ucs-map", "examples/journal_rotor.toml", "--stiffness",
                       f"{1e6 * k!r}:{1e9 * k!r}:7", "--modes", "2", "--out", "-", "--quiet"])
    assert list(us.columns) == ["stiffness_lbf_per_in"] + list(si.columns[1:])
    _same_numbers(us["stiffness_lbf_per_in"].to_numpy(), si["stiffness_n_per_m"].to_numpy(), k, "stiffness")
    np.testing.assert_allclose(us["speed_rpm"], si["speed_rpm"], rtol=1e-9)
    si = _csv(capsys, ["level1", "examples/journal_rotor.toml", "--speed", "4000", "--station", "rotor@0.05",
                       "--qa", "2e5", "--out", "-", "--quiet"])
    us = _csv(capsys, ["level1", "examples/journal_rotor.toml", "--speed", "4000", "--station",
                       f"rotor@{0.05 / IN!r}", "--qa", repr(2e5 * k), "--out", "-", "--quiet", "--units", "us"])
    assert list(us.columns) == ["q_lbf_per_in"] + list(si.columns[1:])
    _same_numbers(us["q_lbf_per_in"].to_numpy(), si["q_n_per_m"].to_numpy(), k, "q")
    np.testing.assert_allclose(us["log_decrement"], si["log_decrement"], rtol=1e-8, atol=1e-12)


def test_figures_say_the_us_unit():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import rotordyn_modal as rdm

    model = rdm.load_model("examples/fan_on_bearings.toml")
    result = rdm.unbalance_response(model, np.linspace(100, 900, 9), amplitude="pk-pk")
    checks = result.checks(model, mcs=314.0, iso_group=2, iso_support="flexible")
    labels = lambda fig: " ".join(ax.get_ylabel() + " " + ax.get_xlabel() for ax in fig.axes)   # noqa: E731
    texts = lambda fig: " ".join(t.get_text() for legend in [ax.get_legend() for ax in fig.axes] + fig.legends  # noqa: E731
                                 if legend for t in legend.get_texts())          # the axes' and the figure's legends
    us = result.plot(forces="bearings", checks=checks, units="us")
    assert "peak-to-peak [mil]" in labels(us) and "[lbf]" in labels(us) and "RMS [in/s]" in labels(us)
    assert "mil pk-pk" in texts(us) and "[m]" not in labels(us) and "[N]" not in labels(us)
    si = result.plot(forces="bearings", checks=checks)
    assert "peak-to-peak [µm]" in labels(si) and "[N]" in labels(si) and "RMS [mm/s]" in labels(si)
    # the same curves, drawn in mil: the SI ones (µm) times 1e-6 * 1000/0.0254 (the probe panel, first axes)
    for a, b in zip(us.axes[0].get_lines(), si.axes[0].get_lines()):
        np.testing.assert_allclose(a.get_ydata(), b.get_ydata() * 1e-6 * 1000 / IN, rtol=1e-12)
    assert "[mil]" in labels(result.plot_orbits(units="us"))
    ucs = rdm.ucs_map(rdm.load_model("examples/journal_rotor.toml"), np.geomspace(1e6, 1e9, 4), modes=1)
    assert "[lbf/in]" in labels(ucs.plot(units="us"))
    level1 = rdm.level1(rdm.load_model("examples/journal_rotor.toml"), 400.0, [rdm.Station("rotor")], 2e5,
                        factor=2.0)
    fig = level1.plot(units="us")
    # Q swept to 10 Qa = 11,420 lbf/in: the top axis in klbf/in, its ticks below 1000
    assert [child.get_xlabel() for ax in fig.axes for child in ax.child_axes] == ["Q [klbf/in]"]
    assert "at Qa = 1142 lbf/in" in texts(fig)             # 2e5 N/m = 1142.0 lbf/in
    plt.close("all")


def test_check_prints_masses_and_inertias_in_us_units(capsys):
    import rotordyn_modal as rdm

    rotor = rdm.load_model("examples/journal_rotor.toml").rotors[0]
    assert main(["--units", "us", "check", "examples/journal_rotor.toml"]) == 0
    out = capsys.readouterr().out
    assert f"total mass {rotor.mass / LB:.6g} lb" in out
    inertia = LB * IN ** 2
    assert f"Jp {rotor.polar_inertia / inertia:.4g}  Jd {rotor.diametral_inertia / inertia:.4g} lb in²" in out
    assert " kg" not in out and " m," not in out and "N/m" not in out


@pytest.mark.parametrize("quantity, factor, unit", [("receptance", LBF / IN, "in/lbf"),
                                                    ("accelerance", LBF / GN, "g/lbf")])
def test_frf_in_us_units_says_the_same(capsys, quantity, factor, unit):
    argv = ["frf", "examples/gear_machine.toml", "--speed", "3000", "--freqs", "1:60:20", "--quantity", quantity,
            "--out", "-", "--quiet"]
    si = _csv(capsys, argv)
    us = _csv(capsys, argv + ["--units", "us"])
    assert list(us.columns) == list(si.columns) + ["unit"] and (us["unit"] == unit).all()
    for column in ("real", "imag", "magnitude"):
        _same_numbers(us[column].to_numpy(), si[column].to_numpy(), factor, column)
    np.testing.assert_array_equal(us["frequency_hz"], si["frequency_hz"])


def test_frf_figure_says_the_us_unit():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import rotordyn_modal as rdm

    model = rdm.load_model("examples/gear_machine.toml")
    result = rdm.frf(model, 314.0, np.linspace(1, 60, 12), quantity="mobility")
    us, si = result.plot(units="us"), result.plot()
    assert us.axes[0].get_ylabel() == "|H| [in/s/lbf]" and si.axes[0].get_ylabel() == "|H| [m/s/N]"
    for a, b in zip(us.axes[0].get_lines(), si.axes[0].get_lines()):
        np.testing.assert_allclose(a.get_ydata(), b.get_ydata() * LBF / IN, rtol=1e-12)
    plt.close("all")


def test_unbalance_checks_in_us_units(tmp_path, capsys):
    argv = ["unbalance", "examples/fan_on_bearings.toml", "--speeds", "300:6000:20", "--mcs", "3000", "--iso-group", "2",
            "--iso-support", "flexible", "--quiet"]
    assert main(argv + ["--checks", str(tmp_path / "si.csv")]) == 0
    assert main(["--units", "us"] + argv + ["--checks", str(tmp_path / "us.csv")]) == 0
    si, us = pd.read_csv(tmp_path / "si.csv"), pd.read_csv(tmp_path / "us.csv")
    probe = si["check"].str.startswith("API").to_numpy()
    assert probe.any() and (~probe).any()
    factor = np.where(probe, 1000 / IN, 1 / IN)                  # probes pk-pk in mil, casing RMS in in/s
    for column in ("value", "limit"):
        _same_numbers(us[column].to_numpy(), si[column].to_numpy(), factor, column)
    assert list(us["unit"]) == ["mil" if p else "in/s" for p in probe]
    np.testing.assert_allclose(us.loc[probe, "limit"], 1.0, rtol=1e-9)   # API 617: 25.4 um pk-pk = 1 mil at most


def test_level1_names_the_station_in_inches():
    import rotordyn_modal as rdm

    assert rdm.Station("fan", -0.0254).label("us") == "fan@-1" and rdm.Station("fan", -0.0254).label() == "fan@-0.0254"
