"""The report does not work out the critical speeds' ``mode_at_speed`` (the number ``modes --speed
S`` gives each crossing's mode at its own speed), which no table or figure of the page shows: at 60
geared rotors (16,614 critical speeds) that lazy column was 47 of the report's 56 minutes, under a
progress line that said "Mode shapes" (docs/report.md). The page's critical-speed table still lists
every crossing, and the mode-shape section's bracketed numbers at the MCS come from the MCS's own
roots (``_critical_numbers``), not from that column."""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import mode_numbers

collect_module = importlib.import_module("rotordyn_modal.report.collect")
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_the_report_solves_no_mode_numbers_at_the_critical_speeds(monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    from rotordyn_modal.report import render_html

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    inputs = collect_module.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=21)
    with rdm.long_work_allowed():
        data = collect_module.collect(model, inputs)
    expected = data.results["campbell"].critical
    calls = []
    monkeypatch.setattr(mode_numbers, "numbers_at_crossings", lambda *a, **k: calls.append(a) or None)
    with rdm.long_work_allowed():
        data = collect_module.collect(model, inputs)
        html = render_html(data)
    assert calls == []
    table = data.results["campbell"].critical.to_dataframe(numbers=False)
    assert len(table) == len(expected) > 0 and "mode_at_speed" not in table
    np.testing.assert_array_equal(table["speed_rpm"], expected.speeds_rpm)
    for speed in table["speed_rpm"][:5]:
        assert f"{speed:.6g}" in html


def test_the_table_with_numbers_is_unchanged():
    """``to_dataframe()`` keeps its column (``critical-speeds``' CSV reads it); ``numbers=False``
    is the same table without it."""
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    table = rdm.critical_speeds(model, rdm.rpm(np.linspace(0.0, 3000.0, 11)))
    full, bare = table.to_dataframe(), table.to_dataframe(numbers=False)
    assert list(full.columns)[:-1] == list(bare.columns) and full.columns[-1] == "mode_at_speed"
    assert full.drop(columns="mode_at_speed").equals(bare)
