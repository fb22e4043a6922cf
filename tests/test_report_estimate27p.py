"""The report's CPU estimate follows the sweep's own grid, the UCS map's crossings and the Level I
sweep's following of its modes (issue 27 §1.9, issue 29 §7).

Before: the unbalance's search for damped critical speeds counted 8 halvings a bracket whatever
the grid and the modes' damping (6.6 were made at 60 rotors, 5 at 61 speeds), so the estimate was
1.28 times the CPU at 30 rotors; the refinement of a speed-dependent bearing's crossings on the
UCS map was not counted; the Level I sweep was counted one eigen-solution a value of Q where it
takes about two (the MAC that follows its modes). The counts are checked against what the
analyses solve; the Level I and whole-report estimates against the CPU time (``process_time``,
not wall time: a shared machine's load moves both the estimate's timed solution and the run).
"""

from __future__ import annotations

import importlib
import sys
import time
from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, level1 as level1_module, ucs_map as ucs_module

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402
from test_long_report_level1 import SENSOR  # noqa: E402

collect_module = importlib.import_module("rotordyn_modal.report.collect")   # not the function collect


@pytest.fixture(autouse=True)
def default_limit(monkeypatch):
    monkeypatch.delenv(_cost.ENVIRONMENT, raising=False)


def _chain(tmp_path, rotors):
    path = tmp_path / f"chain{rotors}.toml"
    path.write_text(chained_gear_toml(rotors, rotors) + SENSOR)
    return rdm.load_model(path)


def _parts(model, inputs):
    return {section: (seconds, what) for section, seconds, what in collect_module.estimate_work(model, inputs).parts}


@pytest.mark.parametrize("points", [11, 61])
def test_the_search_for_damped_critical_speeds_is_counted_on_its_own_grid(tmp_path, monkeypatch, points):
    """Six geared rotors: the eigenvalue solutions the API cases' search makes (each swept speed
    once a distinct ratio, then each bracket halved to a 64th of its mode's band: fewer halvings
    on a finer grid) against those the estimate counts. On main, 8 a bracket: 1.6 times the
    solutions at 62 speeds."""
    from rotordyn_modal.analysis import unbalance_peaks
    from rotordyn_modal.analysis.unbalance import api_unbalance_response

    model = _chain(tmp_path, 6)
    inputs = collect_module.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=points)
    solved = []
    real = unbalance_peaks.eigenvalues_of
    monkeypatch.setattr(unbalance_peaks, "eigenvalues_of", lambda matrices, *a, **k: solved.append(len(matrices))
                        or real(matrices, *a, **k))
    response = api_unbalance_response(model, inputs.speeds, inputs.mcs)
    assert response.resonance_speeds is not None                                  # looked for
    what = _parts(model, inputs)["unbalance"][1]
    counted = float(what.split("between speeds: ")[1].split(" eigenvalue solutions")[0].replace(",", ""))
    swept = 6 * len(inputs.speeds)                                                 # 6 distinct ratios
    assert sum(solved) > swept
    assert 0.85 <= counted / sum(solved) <= 1.15, (counted, sum(solved))


def test_the_ucs_maps_crossings_refinement_is_counted(examples_dir, monkeypatch):
    """journal_rotor's two speed-dependent bearings: every stiffness value the report's UCS map
    solves, its crossings' refinement on the bearings' curves included, is within the count
    (on main the refinement's values, 44 of 885, were not counted)."""
    model = rdm.load_model(examples_dir / "journal_rotor.toml")
    inputs = collect_module.ReportInputs(standard="api684", mcs=rdm.rpm(6000.0), points=11)
    solved = []
    real = ucs_module._synchronous_roots
    monkeypatch.setattr(ucs_module, "_synchronous_roots", lambda M, G, K, *a, **k: solved.append(len(K))
                        or real(M, G, K, *a, **k))
    collect_module._ucs(data := collect_module.ReportData(inputs, model, {}, ("ucs",)))
    assert len(data.results["ucs"].crossings)
    what = _parts(model, inputs)["ucs"][1]
    counted = int(what.split(" stiffness values")[0].replace(",", ""))
    if "more" in what:
        counted += int(what.split("refinement: at most ")[1].split(" more")[0].replace(",", ""))
    assert sum(solved) <= counted <= 1.25 * sum(solved), (counted, sum(solved))


def _fresh_timing(monkeypatch):
    """The estimate's timed eigen-solution timed again now, under the load the run then meets
    (the process keeps its first timing, made under another load)."""
    from rotordyn_modal.analysis import _work

    timed = _cost._timed_eig.__wrapped__
    monkeypatch.setattr(_work, "_timed_eig", lambda size: timed(size))


def test_the_level1_sweep_estimate_against_its_cpu_time(tmp_path, monkeypatch):
    """Ten geared rotors (92 states), 165 values of Q: the Level I part of the estimate against
    the CPU time of the sweep (its second run; the solution timed just before and after it). On
    main 0.46-0.54 of it: the modes' following by MAC from one value of Q to the next was not
    counted."""
    model = _chain(tmp_path, 10)
    stations = [level1_module.Station.parse("r000")]
    inputs = collect_module.ReportInputs(standard="api617", mcs=rdm.rpm(3000.0), points=11,
                                         level1={"stations": stations, "qa": 2e5, "shares": None})
    _fresh_timing(monkeypatch)
    with rdm.long_work_allowed():
        level1_module.level1(model, inputs.mcs, stations, 2e5)                  # first use's work done
        before = _parts(model, inputs)["level1"][0]
        start = time.process_time()
        level1_module.level1(model, inputs.mcs, stations, 2e5)
        measured = time.process_time() - start
    estimate = 0.5 * (before + _parts(model, inputs)["level1"][0])
    assert 0.65 <= estimate / measured <= 1.6, (estimate, measured)
