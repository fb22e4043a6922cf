"""The report's CPU estimate counts every piece of work the report does, and ``collect()`` from
Python refuses work over the limit as the ``report`` command does (issue 27 §1.9).

On a chain of 60 geared rotors the report estimated 12.5 min and ran more than 16.8 min of CPU:
the estimate left out the damped critical speeds and peaks the unbalance response looks for
between swept speeds, a UCS map widened to the bearings' own stiffness, the static loads, the
critical speeds' round-off and the crossings' dense roots of a small pencil. What is counted is
checked against what the analyses then solve (eigen-solutions, stiffness values), not against
times (a shared machine's vary); the times are measured in docs/report.md.
"""

from __future__ import annotations


import importlib
import sys
from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _work, level1 as level1_module

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402
from test_long_report_level1 import SENSOR, mapped_values  # noqa: E402

collect_module = importlib.import_module("rotordyn_modal.report.collect")   # not the function collect


@pytest.fixture(autouse=True)
def default_limit(monkeypatch):
    monkeypatch.delenv(_cost.ENVIRONMENT, raising=False)


def _journal(examples_dir):
    model = rdm.load_model(examples_dir / "journal_rotor.toml")
    inputs = collect_module.ReportInputs(standard="api617", mcs=rdm.rpm(6000.0), points=11, level1={
        "stations": [level1_module.Station.parse("rotor")], "qa": 2e5, "shares": None})
    return model, inputs


def _over_the_limit(monkeypatch):
    """1 ms a solution of any size (and a call of the direct solve), and a limit below the bound
    without timing."""
    monkeypatch.setattr(_cost, "_timed_eig", lambda size: 1e-3)
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1e-3)
    monkeypatch.setattr(collect_module, "_timed_response", lambda model, speed: (1e-3, 1e-4), raising=False)
    monkeypatch.setenv(_cost.ENVIRONMENT, "1e-6")


def test_collect_from_python_is_refused_before_any_section_with_the_estimate(examples_dir, no_solutions,
                                                                           monkeypatch):
    model, inputs = _journal(examples_dir)
    _over_the_limit(monkeypatch)
    with pytest.raises(rdm.InputError) as refused:
        collect_module.collect(model, inputs)
    line = str(refused.value)
    assert "\n" not in line
    assert line.startswith(f"{model.source}: this report of 4 coordinates would take about ")
    # the estimate it names is the one estimate_work makes, every section of api617 in it
    work = collect_module.estimate_work(model, inputs)
    assert f"about {_cost.duration(work.seconds)} of CPU time" in line
    for section in ("static", "campbell", "modes", "ucs", "unbalance", "level1"):
        assert collect_module.SECTIONS[section] in line, section
    assert "--allow-long" in line and _cost.ENVIRONMENT in line


def test_collect_runs_over_the_limit_with_allow_long_or_inside_long_work_allowed(examples_dir, monkeypatch):
    model, inputs = _journal(examples_dir)
    _over_the_limit(monkeypatch)
    data = collect_module.collect(model, inputs, allow_long=True)
    assert data.results["campbell"].speeds.shape == inputs.speeds.shape and "level1" in data.results
    assert not _cost.long_work_is_allowed()                   # the limit holds again after the call
    with pytest.raises(rdm.InputError, match="this report of 4 coordinates would take about"):
        collect_module.collect(model, inputs)
    with rdm.long_work_allowed():
        assert "ucs" in collect_module.collect(model, inputs).results


def test_the_unbalance_search_for_damped_critical_speeds_is_counted(tmp_path, monkeypatch):
    """Six geared rotors on bearings, 12 speeds: the eigenvalue solutions the API cases' search
    for damped critical speeds makes (every swept speed once a distinct speed ratio, then each
    bracket halved), against those the estimate counts; on main the estimate counted none."""
    from rotordyn_modal.analysis import unbalance_peaks
    from rotordyn_modal.analysis.unbalance import api_unbalance_response

    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(6, 6) + SENSOR)
    model = rdm.load_model(path)
    inputs = collect_module.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=11)
    solved = []
    real = unbalance_peaks.eigenvalues_of
    monkeypatch.setattr(unbalance_peaks, "eigenvalues_of", lambda matrices, *a, **k: solved.append(len(matrices))
                        or real(matrices, *a, **k))
    response = api_unbalance_response(model, inputs.speeds, inputs.mcs)
    assert response.resonance_speeds is not None                  # looked for
    parts = {section: what for section, _, what in collect_module.estimate_work(model, inputs).parts}
    counted = float(parts["unbalance"].split("between speeds: ")[1].split(" eigenvalue solutions")[0].replace(",", ""))
    # every swept speed once each of the 6 rotors' ratios, then about 8 halvings a bracket (8.1 here)
    assert sum(solved) > 6 * len(inputs.speeds)
    assert 0.9 * sum(solved) <= counted <= 1.5 * sum(solved)          # 696 counted, 702 solved


def test_a_ucs_map_widened_to_the_bearings_own_stiffness_is_counted(examples_dir, monkeypatch):
    """spring_block_rotor's 2e3 N/m lies below the default map (1e5 to 1e10 N/m): the report maps
    again from 1e2 N/m; the values counted are those mapped (grid, rigid supports; on main the
    second map was not counted)."""
    model = rdm.load_model(examples_dir / "spring_block_rotor.toml")
    inputs = collect_module.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=11)
    mapped = mapped_values(monkeypatch)
    collect_module._ucs(data := collect_module.ReportData(inputs, model, {}, ("ucs",)))
    result = data.results["ucs"]
    assert result.stiffness[0] < 2e3 < 1e5                        # the second map's grid
    parts = {section: what for section, _, what in collect_module.estimate_work(model, inputs).parts}
    counted = int(parts["ucs"].split(" stiffness values")[0].replace(",", ""))
    assert len(result.stiffness) + len(collect_module.UCS_STIFFNESS) <= counted
    assert counted - 2 <= sum(mapped) <= counted


def test_every_piece_of_the_report_is_in_its_estimate(examples_dir, monkeypatch):
    """The static loads, the critical speeds' round-off, the mode shapes' solution and the
    crossings' dense roots of a small pencil (every root a candidate) are counted."""
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1.0)
    monkeypatch.setattr(collect_module, "_timed_response", lambda model, speed: (0.5, 0.25), raising=False)
    model, inputs = _journal(examples_dir)
    work = collect_module.estimate_work(model, inputs)
    parts = {section: (seconds, what) for section, seconds, what in work.parts}
    assert parts["static"][0] > 0 and "their round-off" in parts["campbell"][1]
    # the report shows no mode numbers at the critical speeds (mode_at_speed): none counted
    campbell = _work.estimate(model, inputs.speeds, (1,), numbers=False)
    per = (_work._COORDINATE_SECONDS * 4 + _work._FACTOR_SHARE + _work._DENSE_ROOTS * _cost.EIGVALS_SHARE)
    assert campbell.crossing_seconds == pytest.approx(campbell.crossings * per)
    round_off = collect_module.ROUND_OFF_SECONDS * campbell.crossings * 8 ** 2      # 8 states
    assert parts["campbell"][0] == pytest.approx(campbell.seconds + round_off)
    assert work.seconds == pytest.approx(sum(seconds for seconds, _ in parts.values()))
    # the unbalance: 2 API cases at 12 speeds, the damped critical speeds looked for (12
    # eigenvalue solutions of the one speed ratio, no bracket: one rotor), each case's calls of
    # the direct solve for its peaks
    assert parts["unbalance"][1].startswith("2 API unbalance cases at 12 speeds; their damped critical speeds")
    cases = 2 * (collect_module.CASE_SHARE + collect_module.SOLVE_SHARE * 12)
    search = 12 * _cost.EIGVALS_SHARE + 2 * collect_module.PEAK_CALLS * 0.5
    # and the work outside the solves: each case's set-up (4 coordinates) and the probe limits'
    # search (two proximity probes; no [[clearances]]: no clearance check)
    outside = 2 * collect_module.CASE_DOF_SECONDS * 4 + collect_module.CHECK_SECONDS
    assert parts["unbalance"][0] == pytest.approx(cases + search + outside)
