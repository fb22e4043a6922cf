"""A third round of inputs of the families a reviewer tries (after ``test_input_families.py`` and
``test_input_families2.py``): negative numbers written with an exponent, stations off a
flexible rotor's shaft, measured levels in dB and infinite cells, fits whose parameters sit near
their start. Each case through the command line in this process (the right answer, or exit 2
with one line naming the file or option and nothing written) or through the Python API."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
GEAR = str(ROOT / "examples" / "gear_machine.toml")
FAN = str(ROOT / "examples" / "fan_on_bearings.toml")
JOURNAL = str(ROOT / "examples" / "journal_rotor.toml")
COMPRESSOR = str(ROOT / "examples" / "compressor_rotor.toml")


# ----------------------------------------------------------------------- negative numbers
@pytest.mark.parametrize("argv, words", [
    (["level1", JOURNAL, "--speed", "4000", "--station", "rotor", "--qa", "-2e5"], ["--qa '-2e5'", "> 0"]),
    (["unbalance", FAN, "--speeds", "100:3000:3", "--mcs", "-3e3"], ["--mcs -3e3", "> 0"]),
    (["simulate", GEAR, "--duration", "0.1", "--rtol", "-1e-9"], ["--rtol -1e-9", "tolerance"]),    # the option as typed (round 5)
    (["static", GEAR, "--allowable-stress", "-1e8"], ["--allowable-stress -1e8", "> 0"]),
    (["campbell", GEAR, "--speeds", "0:3000:3", "--lowest", "-1e3"], ["--lowest '-1e3'", ">= 1"]),
], ids=["level1-qa", "unbalance-mcs", "simulate-rtol", "static-stress", "campbell-lowest"])
def test_a_negative_number_with_an_exponent_reaches_the_options_own_check(capsys, argv, words):
    """argparse takes ``-3e3`` for an option, not a number: it printed its whole usage and
    'argument --mcs: expected one argument' (the value was given), a SystemExit out of ``main``."""
    assert main(argv + ["--quiet"] * (argv[0] != "level1")) == 2
    _one_line_error(capsys, *words)


# ----------------------------------------------------------------------- flexible rotors' stations
@pytest.mark.parametrize("station, at", [("compressor@5", 5.583265), ("compressor@-0.7", -0.116735)],
                         ids=["beyond-the-end", "before-the-start"])
def test_a_level1_station_off_a_flexible_shaft_is_refused(capsys, station, at):
    """The compressor's shaft runs 0 to 1.2 m from its start, its centre of mass at 0.5833 m: a
    station 5 m from the centre was taken by the shaft's end node without a word (exit 0, a
    different mode followed and another log decrement)."""
    model = rdm.load_model(COMPRESSOR)
    shaft = model.dofs.shafts[model.dofs.rotors.index("compressor")]
    centre = shaft.z_of(model.rotor("compressor").center_of_mass)
    assert shaft.length == pytest.approx(1.2, rel=1e-12)
    offset = float(station.split("@")[1])
    assert centre + offset == pytest.approx(at, abs=1e-6) and not 0 <= centre + offset <= shaft.length
    assert main(["level1", COMPRESSOR, "--speed", "4000", "--station", station, "--qa", "2e5", "--quiet"]) == 2
    _one_line_error(capsys, f"OFFSET = {offset:g} m", "on rotor 'compressor''s shaft", f"{-centre:.6g} to")
    with pytest.raises(InputError, match="shaft"):
        rdm.level1(model, rdm.rpm(4000), [station], 2e5)


# ----------------------------------------------------------------------- measured CSV cells
def _measured(tmp_path, change):
    out = tmp_path / "m.csv"
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--out", str(out), "--quiet"]) == 0
    table = change(pd.read_csv(out))
    table.to_csv(out, index=False)
    return out


@pytest.mark.parametrize("change, words", [
    (lambda t: t.drop(columns=["real", "imag"]).assign(magnitude=20 * np.log10(t.magnitude)),
     ["magnitude = -122", "data row 1", "20 such row(s)", "not a level in dB"]),
    (lambda t: t.assign(imag=np.where(t.index == 3, np.inf, t.imag)), ["imag = inf", "data row 4", "30.5 Hz"]),
], ids=["magnitude-in-db", "infinite-imaginary-part"])
def test_a_measured_cell_of_no_frf_is_refused_by_column_and_row(tmp_path, capsys, change, words):
    """A magnitude column in dB (every value negative) was read as a linear FRF of those
    magnitudes, drawn and fitted (exit 0); an infinite cell gave a numpy warning line before
    the refusal."""
    path = _measured(tmp_path, change)
    plot = tmp_path / "p.png"
    assert main(["frf", GEAR, "--freqs", "2:40:5", "--measured", str(path), "--plot", str(plot), "--quiet"]) == 2
    _one_line_error(capsys, "m.csv", *words)
    assert not plot.exists()


# ----------------------------------------------------------------------- fits near their start
@pytest.mark.parametrize("key, start, freqs", [
    ("suspensions.mount-FL.stiffness", 1.0, [11.5]),
    ("suspensions.mount-FL.stiffness", 1.0005, [11.5]),
    ("stator.mass", 1.0, [11.5, 30.5]),
], ids=["stiffness-at-the-truth", "stiffness-0.05%-off", "mass-at-the-truth"])
def test_a_fit_whose_optimum_is_near_its_start_is_determined(key, start, freqs):
    """Data of the model itself: the fitted factor is the truth over the start. With the
    optimum within 1e-3 of log 1, scipy's relative step (1e-6 x the log) left the factor equal
    in every bit, the Jacobian was 0 and the fit said 'the measured FRFs do not determine the
    parameters' (not converged, exit 1)."""
    truth = rdm.load_model(GEAR)
    measured = rdm.frf(truth, rdm.rpm(600), np.array(freqs))
    model = truth.scaled({key: start})
    result = rdm.fit(model, measured, [key], starts=1)
    assert result.converged, result.message
    assert result.factors[0] == pytest.approx(1.0 / start, rel=1e-7)


# ----------------------------------------------------------------------- unbalance sweeps in any order
@pytest.mark.parametrize("order", ["reversed", "repeated", "negative", "negative-reversed"])
def test_amplification_factors_of_a_sweep_in_any_order(order):
    """A single degree of freedom under unbalance, ``|r^2 / (1 - r^2 + 2 i zeta r)|``: its peak
    lies at ``r = 1 / sqrt(1 - 2 zeta^2)`` and its half-power amplification factor is the peak's
    ``r`` over the width between the two ``r`` where the curve is at peak / sqrt(2) (found here by
    brentq, about ``1 / (2 zeta)``). A run-down (speeds decreasing), a sweep with a repeated
    speed and one of negative speeds (every rotor reversed) gave NaN (not evaluated: the
    half-power points were looked for in the wrong direction)."""
    from scipy.optimize import brentq

    from rotordyn_modal.analysis.unbalance import amplification_factors

    zeta, omega_n = 0.02, 300.0
    curve = lambda r: np.abs(r ** 2 / (1 - r ** 2 + 2j * zeta * r))   # noqa: E731
    r_peak = 1 / np.sqrt(1 - 2 * zeta ** 2)
    half = lambda r: curve(r) - curve(r_peak) / np.sqrt(2)            # noqa: E731
    exact_af = r_peak / (brentq(half, r_peak, 1.5) - brentq(half, 0.5, r_peak))
    speeds = np.linspace(0.5, 1.5, 2001) * omega_n
    arranged = {"reversed": speeds[::-1], "repeated": np.insert(speeds, 1000, speeds[1000]),
                "negative": -speeds[::-1], "negative-reversed": -speeds}[order]
    [(speed, amplitude, af)] = amplification_factors(arranged, curve(np.abs(arranged) / omega_n))
    assert abs(speed) == pytest.approx(omega_n * r_peak, rel=5e-4) and np.sign(speed) == np.sign(arranged[0])
    assert amplitude == pytest.approx(curve(r_peak), rel=1e-4)   # the sample nearest the peak
    assert exact_af == pytest.approx(1 / (2 * zeta), rel=0.01) and af == pytest.approx(exact_af, rel=1e-3)


# ----------------------------------------------------------------------- materials in other units
@pytest.mark.parametrize("key, value, words", [
    ("young_modulus", "200.0", ["young_modulus = 200:", "GPa or MPa"]),              # GPa typed for Pa
    ("young_modulus", "210000.0", ["young_modulus = 210000:", "GPa or MPa"]),         # N/mm^2
    ("density", "7.81", ["density = 7.81:", "g/cm^3"]),                               # g/cm^3
], ids=["E-in-GPa", "E-in-MPa", "density-in-g-per-cm3"])
def test_a_shaft_material_in_other_units_draws_one_warning(tmp_path, capsys, key, value, words):
    """A steel shaft of E = 200 (GPa typed for Pa) bends with frequencies sqrt(1e9) times too
    low; ``check`` said nothing of the material (the density in g/cm^3: nothing at all)."""
    text = Path(COMPRESSOR).read_text()
    line = {"young_modulus": "young_modulus = 2.11e11", "density": "density = 7810.0"}[key]
    assert text.count(line) == 1
    model_file = tmp_path / "units.toml"
    model_file.write_text(text.replace(line, f"{key} = {value}"))
    assert main(["check", str(model_file)]) == 0
    lines = [x for x in capsys.readouterr().err.splitlines() if "[materials.steel]" in x]
    assert len(lines) == 1 and "warning" in lines[0] and "units.toml" in lines[0], lines
    for word in words:
        assert word in lines[0], lines[0]
    assert main(["check", COMPRESSOR]) == 0
    assert "materials" not in capsys.readouterr().err   # steel in SI: no word


# ----------------------------------------------------------------------- level1 on an undamped rotor
@pytest.mark.parametrize("real_part, sweep_log_dec, q0", [
    (+1e-15, [1e-16, -0.5, -1.0], 0.0),    # unstable by round-off at Q = 0 already: Q0 = 0
    (-0.5, [0.3, -1e-16, -1e-16], 100.0),   # stable at both ends, the sweep's sign change round-off: the grid's Q
    (-0.05, [0.3, -0.2, -0.5], 50.0),       # a real crossing: Re = -0.05 + 1e-3 Q reaches 0 at Q = 50
], ids=["unstable-at-zero", "no-crossing", "real-crossing"])
def test_level1_q0_where_the_sweeps_sign_change_is_round_off(real_part, sweep_log_dec, q0):
    """A flexible shaft on undamped bearings (``level1`` at its centre: log decrement 0 at Q = 0
    to round-off) ended in scipy's 'f(a) and f(b) must have different signs' (exit 1): the
    sweep's sign change and the re-solved root's disagreed at round-off (that model takes 20 s;
    the step is checked alone). Here a mode ``lambda = a + 1e-3 Q +- 10 i``: Q0 is where
    ``a + 1e-3 Q`` reaches 0, or the end of the grid step the sweep found."""
    from rotordyn_modal.analysis.level1 import _zero_crossing

    base = np.array([[real_part, -10.0], [10.0, real_part]])
    unit = np.eye(2) * 1e-3
    grid = np.array([0.0, 100.0, 200.0])
    followed = real_part + 1e-3 * grid + 10j
    assert _zero_crossing(base, unit, 1, grid, followed, np.array(sweep_log_dec)) == pytest.approx(q0, abs=1e-9)


# ----------------------------------------------------------------------- report ranges
def test_a_report_operating_range_above_the_mcs_is_refused(tmp_path, capsys):
    """The maximum continuous speed is the top of the operating range: ``--mcs 9000 --operating
    7000:12000`` wrote a report (exit 0) whose separation margins were measured from 12,000 rpm,
    a speed the sweep (to 1.5 MCS) barely reached and the machine never runs at."""
    out = tmp_path / "r.html"
    assert main(["report", COMPRESSOR, "--standard", "api684", "--mcs", "9000", "--operating", "7000:12000",
                 "--out", str(out), "--quiet"]) == 2
    _one_line_error(capsys, "--operating 7000:12000", "at most --mcs 9000")
    assert not out.exists()
    from rotordyn_modal.report import ReportInputs, collect

    with pytest.raises(InputError, match="at most the maximum continuous speed"):
        collect(rdm.load_model(COMPRESSOR), ReportInputs(standard="api684", mcs=rdm.rpm(9000),
                                                          operating=(rdm.rpm(7000), rdm.rpm(12000))))


def test_unbalance_min_speed_without_a_check_is_refused(capsys):
    """``--min-speed`` is the bottom of the API 617 / ISO 20816-3 checks' speeds: given without
    --mcs or --iso-group it was dropped without a word (exit 0)."""
    assert main(["unbalance", FAN, "--speeds", "100:3000:3", "--min-speed", "500", "--quiet"]) == 2
    _one_line_error(capsys, "--min-speed 500", "--mcs", "--iso-group")


def test_an_operating_speed_against_the_sweeps_direction_is_refused(tmp_path, capsys):
    """The separation margin of a peak at +1500 rpm from an operating speed of -1500 rpm was given
    as 200 % (exit 0): a margin across zero speed. Refused before anything is written, in the
    command line and in ``peaks``; the same direction on both sides still gives margins."""
    out = tmp_path / "u.csv"
    assert main(["unbalance", FAN, "--speeds", "100:3000:5", "--operating-speed", "-1500", "--out", str(out)]) == 2
    _one_line_error(capsys, "-1500 rpm", "direction of spin", "100 to 3000 rpm")
    assert not out.exists()
    result = rdm.unbalance_response(rdm.load_model(FAN), np.linspace(-300.0, -10.0, 30))
    with pytest.raises(InputError, match="direction of spin"):
        result.peaks(operating_speed=157.0)
    margins = result.peaks(operating_speed=-157.0)["separation_margin_pct"]
    assert len(margins) and np.all(np.isfinite(margins))


# ----------------------------------------------------------------------- --outline files
@pytest.mark.parametrize("rows, words", [
    ("0,0,0\ninf,0,0\n", ["point 1 x = inf", "finite"]),
    ("0,0,0\n1,-1e300,0\n", ["point 1 y = -1e+300", "at most 1e+30"]),
    ("0,0,0\n", ["n >= 2"]),
], ids=["infinite", "beyond-every-scale", "one-point"])
def test_an_outline_of_no_drawable_point_is_refused_naming_the_file(tmp_path, capsys, rows, words):
    """An infinite coordinate reached matplotlib: 'Axis limits ... cannot be infinite' (exit 1,
    after a numpy overflow warning line); an outline of one point was refused without the
    file's name."""
    outline = tmp_path / "outline.csv"
    outline.write_text("x,y,z\n" + rows)
    plot = tmp_path / "s.png"
    assert main(["modes", GEAR, "--speed", "100", "--shape", "1", "--plot", str(plot), "--outline", str(outline),
                 "--quiet"]) == 2
    _one_line_error(capsys, "outline.csv", *words)
    assert not plot.exists()


# ----------------------------------------------------------------------- repeated orders
@pytest.mark.parametrize("command", ["critical-speeds", "campbell"])
def test_a_repeated_order_is_refused(capsys, command):
    """``--orders 1,2,1``: every 1X critical speed was listed twice (exit 0)."""
    assert main([command, GEAR, "--speeds", "0:3000:4", "--orders", "1,2,1", "--quiet"]) == 2
    _one_line_error(capsys, "orders", "each order once", "element 2")
    with pytest.raises(InputError, match="each order once"):
        rdm.campbell(rdm.load_model(GEAR), [0.0, 100.0], orders=[2, 2.0])


@pytest.mark.parametrize("argv, words", [
    (["simulate", FAN, "--duration", "0.1", "--ramp", "0:100", "--free-spin"], ("--free-spin", "not allowed")),
    (["campbell", FAN, "--speeds", "0:100:3", "--no-such-option"], ("unrecognized arguments", "--no-such-option")),
    ([], ("required", "SUB")),
])
def test_an_option_argparse_refuses_gets_one_line(capsys, argv, words):
    """argparse's refusals printed its usage block (several lines) before the error line."""
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    _one_line_error(capsys, *words, "--help")
