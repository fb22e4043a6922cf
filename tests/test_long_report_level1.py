"""``report`` and ``level1`` refuse work estimated over the CPU-time limit before it starts, with the
estimate, as ``campbell``, ``critical-speeds`` and ``stability`` do (issue 27 §1.9; tests/test_long_work.py).

A report of 500 geared rotors on bearings (2,006 coordinates) ran its Campbell section for more
than 4 minutes with no estimate (its API unbalance section alone is 1,000 cases); ``level1`` at
that size is about 130 eigen-solutions of 4,012 states. What the estimates count is checked
against what the analyses then do (values of Q solved, stiffness values mapped, API cases made),
not against times (a shared machine's vary).
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _eigensolve, level1 as level1_module, ucs_map as ucs_module
from rotordyn_modal.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402
from test_long_work import _refusal  # noqa: E402

#: a casing sensor: the report's unbalance section runs (a model without sensors skips it)
SENSOR = """
[[sensors]]
name = "acc-top-z"
position = [0.0, 0.0, 0.5]
direction = [0.0, 0.0, 1.0]
"""
JOURNAL = ["examples/journal_rotor.toml", "--mcs", "4000", "--station", "rotor", "--qa", "2e5"]


@pytest.fixture(autouse=True)
def default_limit(monkeypatch):
    monkeypatch.delenv(_cost.ENVIRONMENT, raising=False)


def _solved_values(monkeypatch):
    """Count the matrices Level I's sweep solves (its values of Q; the module's function is shared)."""
    solved = []
    real = _eigensolve.upper_shapes

    def counted(matrices, *args, **kwargs):
        if sys._getframe(1).f_globals["__name__"] == level1_module.__name__:       # not the Campbell sweep's
            solved.append(len(matrices))
        return real(matrices, *args, **kwargs)

    monkeypatch.setattr(_eigensolve, "upper_shapes", counted)
    return solved


def mapped_values(monkeypatch):
    """Count the stiffness values the UCS map solves (``len(K)`` of each call of
    ``ucs_map._synchronous_roots`` from the map's grid, its bearings' curves and its rigid
    supports, and, by the subspace route, its bearings' anchors; not the crossings' refinement):
    the list, filled as the map runs."""
    mapped = []
    real_roots = ucs_module._synchronous_roots

    def roots(M, G, K, *args, **kwargs):
        caller = sys._getframe(1)
        if {caller.f_code.co_name, caller.f_back.f_code.co_name} & {"_ucs_map", "_curve_crossings", "_rigid_support",
                                                                     "subspace_crossings"}:
            mapped.append(len(K))
        return real_roots(M, G, K, *args, **kwargs)

    monkeypatch.setattr(ucs_module, "_synchronous_roots", roots)
    return mapped


def test_a_report_of_500_geared_rotors_is_refused_before_any_section(tmp_path, capsys, no_solutions):
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(500, 500) + SENSOR)
    out = tmp_path / "report.html"
    line = _refusal(capsys, ["report", path, "--standard", "api684", "--mcs", "3000", "--out", out])
    assert line.startswith(f"rotordyn-modal report: error: {path}: this report of 2,006 coordinates would take about")
    hours = float(line.split("would take about ")[1].split(" h of CPU time")[0].replace(",", ""))
    assert hours > 1.0                                              # far above the 30 minutes
    # every section that solves is named, with what it counts: 152 speeds (151 and the MCS), 1,000
    # API cases (a static and a couple case for each of the 500 rotors on two bearings)
    assert "Campbell diagram and critical speeds" in line and "152 eigen-solutions of 4,012 states" in line
    assert "1,000 API unbalance cases at 152 speeds" in line
    assert "Undamped critical speed map" in line and "Mode shapes near the operating range" in line
    assert "--allow-long" in line and _cost.ENVIRONMENT in line
    assert not out.exists()


def test_the_report_estimate_counts_what_the_report_then_solves(monkeypatch, capsys, tmp_path):
    """Level I's values of Q, the UCS map's stiffness values and the API cases, as the estimate
    counts them (``collect.estimate_work``), against those the report's analyses then solve."""
    from rotordyn_modal.analysis import unbalance as unbalance_module

    collect_module = importlib.import_module("rotordyn_modal.report.collect")   # not the function collect

    solved = _solved_values(monkeypatch)
    mapped = mapped_values(monkeypatch)
    cases = []
    real_cases = unbalance_module.api_unbalance_cases
    monkeypatch.setattr(unbalance_module, "api_unbalance_cases", lambda *a: cases.append(real_cases(*a)) or cases[-1])
    estimates = []
    real_estimate = collect_module.estimate_work
    monkeypatch.setattr(collect_module, "estimate_work",
                        lambda *a, **k: estimates.append(real_estimate(*a, **k)) or estimates[-1])
    monkeypatch.setenv(_cost.ENVIRONMENT, "1e-9")                   # the estimate is made, then run anyway
    code = main([str(a) for a in ["report", "examples/journal_rotor.toml", "--standard", "api617", "--mcs", "6000",
                 "--station", "rotor", "--qa", "2e5", "--points", "21", "--out", tmp_path / "r.html", "--allow-long",
                                  "--quiet"]])
    assert code == 0, capsys.readouterr().err
    monkeypatch.delenv(_cost.ENVIRONMENT)
    model = rdm.load_model("examples/journal_rotor.toml")
    inputs = collect_module.ReportInputs(standard="api617", mcs=rdm.rpm(6000.0), points=21, level1={
        "stations": [level1_module.Station.parse("rotor")], "qa": 2e5, "shares": None})
    parts = {section: what for section, _, what in real_estimate(model, inputs).parts}
    assert parts["level1"] == f"{sum(solved)} values of Q"
    ucs = int(parts["ucs"].split(" stiffness values")[0].replace(",", ""))
    # 41 values and the two speed-dependent bearings' anchors, 3 each (the rigid supports counted:
    # pinned at both bearings the rotor has no mode left to solve). Today's route solved their
    # curves' 2 x 200 points each (sum(mapped) > 800): the subspace route solves the anchors
    # instead (issue 29 §2), the curves' points on r x r Ritz pencils; the count must still
    # hold more than the grid, each bearing's anchors
    assert ucs - 1 <= sum(mapped) <= ucs and sum(mapped) >= 41 + 2 * 3
    assert parts["unbalance"].startswith(f"{len(cases[0])} API unbalance cases at {len(inputs.speeds)} speeds")
    assert parts["campbell"].startswith(f"{len(inputs.speeds)} eigen-solutions of 8 states")


def test_the_api_cases_are_counted_without_being_made(examples_dir):
    from rotordyn_modal.analysis.unbalance_checks import api_unbalance_cases
    from rotordyn_modal.report.collect import _api_cases

    for name in ("journal_rotor", "gear_machine", "motor_pump_on_mounts", "fan_on_bearings", "compressor_rotor"):
        for rpm in (3000.0, 9000.0):                # compressor_rotor's first bending mode within reach at 9000
            model = rdm.load_model(examples_dir / f"{name}.toml")
            assert _api_cases(model, rdm.rpm(rpm)) == len(api_unbalance_cases(model, rdm.rpm(rpm))), (name, rpm)
    assert _api_cases(model, rdm.rpm(9000.0)) == 3            # static, couple, api-mode1


def test_level1_over_the_limit_is_refused_before_its_sweep_with_the_count_it_would_solve(monkeypatch, capsys):
    monkeypatch.setattr(_cost, "_timed_eig", lambda size: 1e-3)     # 1 ms a solution of the 8 states
    monkeypatch.setenv(_cost.ENVIRONMENT, "1e-6")                   # below the bound without timing
    solved = _solved_values(monkeypatch)
    line = _refusal(capsys, ["level1", *JOURNAL])
    assert solved == []                                              # refused before the sweep
    count = int(line.split(" coordinates at ")[1].split(" values of Q")[0])
    assert line.startswith("rotordyn-modal level1: error: examples/journal_rotor.toml: an API 617 Level I sweep of "
                           f"4 coordinates at {count} values of Q would take about")
    assert "--factor" in line and "--allow-long" in line and _cost.ENVIRONMENT in line
    # 1 ms per value of Q and Q0's search (3 modes, 16 eigenvalue-only solutions each), 2 digits shown
    seconds = float(line.split("would take about ")[1].split(" s of CPU time")[0])
    assert seconds == pytest.approx((count + 3 * 16 * _cost.EIGVALS_SHARE) * 1e-3, rel=0.04)
    assert main(["level1", *JOURNAL, "--allow-long", "--out", "/dev/null"]) == 0, capsys.readouterr().err
    assert solved == [count]                                         # what was counted is what is solved


def test_level1_python_call_is_refused_and_runs_inside_long_work_allowed(monkeypatch):
    monkeypatch.setattr(_cost, "_timed_eig", lambda size: 1e-3)
    monkeypatch.setenv(_cost.ENVIRONMENT, "1e-6")
    model = rdm.load_model("examples/journal_rotor.toml")
    with pytest.raises(rdm.InputError, match="Level I sweep .* would take about"):
        rdm.level1(model, rdm.rpm(4000.0), ["rotor"], 2e5)
    with rdm.long_work_allowed():
        assert rdm.level1(model, rdm.rpm(4000.0), ["rotor"], 2e5).passes_log_decrement


def test_the_q0_search_solves_at_most_what_is_counted_for_it(monkeypatch, examples_dir):
    """``ZERO_SOLUTIONS`` per followed mode: the eigenvalue-only solutions of Q0's search counted
    on the documented commands (fan: two modes cross zero; journal at a Qa of 2e7 N/m: one)."""
    calls = []
    real = np.linalg.eigvals
    monkeypatch.setattr(level1_module.np.linalg, "eigvals", lambda a: calls.append(1) or real(a))
    for name, mcs, station, qa in (("fan_on_bearings", 3000, "fan@-0.1", 1e4), ("journal_rotor", 4000, "rotor", 2e7)):
        calls.clear()
        result = rdm.level1(rdm.load_model(examples_dir / f"{name}.toml"), rdm.rpm(mcs), [station], qa)
        crossing = sum(np.isfinite(run.q0) and run.q0 > 0 for run in result.swept)
        assert crossing >= 1 and 0 < len(calls) <= crossing * level1_module.ZERO_SOLUTIONS, name


def test_a_report_that_fits_is_passed_without_a_measurement(monkeypatch, tmp_path, capsys):
    def measured(size):
        raise AssertionError("a small model was timed")

    monkeypatch.setattr(_cost, "_timed_eig", measured)
    from rotordyn_modal.analysis import _work

    monkeypatch.setattr(_work, "_timed_eig", measured)
    from rotordyn_modal.report.collect import refuse_long_work, ReportInputs

    model = rdm.load_model("examples/journal_rotor.toml")
    inputs = ReportInputs(standard="api617", mcs=rdm.rpm(6000.0), level1={
        "stations": [level1_module.Station.parse("rotor")], "qa": 2e5, "shares": None})
    assert refuse_long_work(model, inputs) is None


def test_unbalance_makes_the_state_form_once_where_the_peaks_are_not_looked_for(monkeypatch, examples_dir):
    """The form was made three times a call (the model's check, the peaks' search, the note saying
    they are not looked for): about 4 s each at 500 geared rotors. The note is the same."""
    from rotordyn_modal import linear_system
    from rotordyn_modal.analysis import unbalance as unbalance_module, unbalance_peaks

    made = []
    real = linear_system.speed_linear_form
    for module in (linear_system, unbalance_module, unbalance_peaks):
        monkeypatch.setattr(module, "speed_linear_form", lambda *a, **k: made.append(1) or real(*a, **k))
    monkeypatch.setattr(unbalance_peaks, "_WORK", 0.0)               # as a large model: not looked for
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speeds = rdm.rpm(np.linspace(100, 3000, 11))
    result = rdm.unbalance_response(model, speeds)
    assert len(made) == 1
    assert result.cut_peak_note == unbalance_peaks.not_looked_for(model, speeds) != ""
    assert result.resonance_speeds is None


def test_the_critical_speeds_round_off_holds_a_bounded_part_of_the_state_matrices(monkeypatch, examples_dir):
    """``critical_round_off`` stacked the state matrix of every critical speed at once: 60 geared
    rotors (16,600 critical speeds of 492 states) asked for 32 GB and the report was killed. Now
    a part at a time, each matrix's round-off the same to the bit."""
    from rotordyn_modal.analysis import _roots

    collect_module = importlib.import_module("rotordyn_modal.report.collect")
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    critical = rdm.campbell(model, rdm.rpm(np.linspace(100, 3000, 31)), orders=(1, 2)).critical
    from rotordyn_modal.linear_system import speed_linear_form

    form = speed_linear_form(model)
    speeds = np.asarray(critical.speeds_rpm, dtype=float) * (np.pi / 30)
    assert len(speeds) > 6
    whole = _roots.round_off(np.stack([form.at(s) for s in speeds]))
    batches = []
    real = _roots.round_off
    monkeypatch.setattr(_roots, "round_off", lambda matrices: batches.append(len(matrices)) or real(matrices))
    monkeypatch.setattr(collect_module, "_ROUND_OFF_BYTES", 3 * 8 * form.n_states ** 2)
    shown = collect_module.critical_round_off(model, critical)
    assert max(batches) == 3 and sum(batches) == len(speeds)
    zeta = np.clip(np.abs(np.asarray(critical.damping_ratios, dtype=float)), 0.0, 1.0 - 1e-12)
    size = 2 * np.pi * np.asarray(critical.frequencies_hz, dtype=float) / np.sqrt(1 - zeta ** 2)
    finite = np.isfinite(shown)
    assert finite.any() and np.array_equal(shown[finite], (whole / size)[finite])
