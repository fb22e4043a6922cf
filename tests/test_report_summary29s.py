"""The report's summary says when the machine is unstable in its operating range, and a mode has
one number across the report (issue 29 section 7, issue 27 section 2; helper rep29s).

Truth from outside the report: ``stability``'s own root-found threshold and least damped mode
(an analysis the report does not call), and ``modal`` at the MCS for the number ``modes --speed``
gives a mode. Each test fails on 5e4071e: it has no stability row, and its mode-shape table
numbered modes at the MCS only.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs
from rotordyn_modal.report.collect import collect

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RPM = np.pi / 30
ROW = "Stability over the operating range"


def _row(data):
    rows = [c for c in data.criteria if c.name == ROW]
    assert len(rows) == 1, [c.name for c in data.criteria]
    return rows[0]


def test_unstable_inside_the_range_fails_from_stabilitys_threshold():
    """journal_rotor, MCS 12,500 rpm, range 10,000-12,500 rpm: `stability` finds the onset at
    11,628 rpm; the summary row fails, naming that onset (within stability's Brent tolerance,
    here taken as 1e-9 relative, on a grid of its own) and the mode stability names."""
    from rotordyn_modal.analysis.stability import stability
    from rotordyn_modal.report import render
    from rotordyn_modal.units import rpm_text

    model = load_model(EXAMPLES / "journal_rotor.toml")
    inputs = ReportInputs("api684", 12500 * RPM, (10000 * RPM, 12500 * RPM), points=21)
    data = collect(model, inputs)
    own = stability(model, np.linspace(9000, 14000, 11) * RPM)       # another grid: the same root's zero
    assert 10000 * RPM < own.threshold_speed < 12500 * RPM
    assert data.results["onset"] == pytest.approx(own.threshold_speed, rel=1e-9)
    same = stability(model, inputs.speeds)                             # the report's speeds: its mode numbers
    mode = int(same.threshold_modes[np.argmin(np.abs(same.thresholds - same.threshold_speed))])
    row = _row(data)
    assert row.verdict == "fail"
    assert f"mode {mode} (Campbell diagram's number) unstable from {rpm_text(own.threshold_speed / RPM)} rpm" in row.why
    assert row.value.endswith(f"(mode {mode})")
    assert "no steady" in row.why
    html = render._unbalance(data, "si")
    assert f"Not a steady state above {own.threshold_speed / RPM:,.0f} rpm" in html


def test_stable_range_passes_with_stabilitys_least_log_decrement():
    """journal_rotor, MCS 6,000 rpm, range 4,000-6,000 rpm: every mode decays there; the row passes
    and its least log decrement is that of `stability` over the report's speeds in the range."""
    from rotordyn_modal.analysis.stability import stability

    model = load_model(EXAMPLES / "journal_rotor.toml")
    inputs = ReportInputs("api684", 6000 * RPM, (4000 * RPM, 6000 * RPM), points=21)
    data = collect(model, inputs)
    speeds = inputs.speeds[(inputs.speeds >= 4000 * RPM * (1 - 1e-12)) & (inputs.speeds <= 6000 * RPM * (1 + 1e-12))]
    own = stability(model, speeds)
    assert own.stable.all()
    mode, k = own.least_damped()
    expected = own.log_decrements[k, mode - 1]
    row = _row(data)
    assert row.verdict == "pass"
    shown = float(re.search(r"log dec (\S+)", row.value).group(1))
    assert shown == float(f"{expected:.3g}")
    assert expected > 0


def test_mode_shape_table_names_the_unstable_mode_by_the_campbell_number():
    """unstable_cross_coupled at 9,000 rpm: the mode `stability` finds unstable (above the range)
    is its tracked mode 5; `modes --speed 9000` numbers it otherwise. The mode-shape table's row of
    that root carries the tracked number (the Campbell's), with the MCS number in brackets."""
    from rotordyn_modal.analysis.modal import modal
    from rotordyn_modal.analysis.stability import stability
    from rotordyn_modal.report import render

    model = load_model(EXAMPLES / "unstable_cross_coupled.toml")
    inputs = ReportInputs("api684", 9000 * RPM, points=21)
    own = stability(model, inputs.speeds)
    tracked = int(own.threshold_modes[np.argmin(np.abs(own.thresholds - own.threshold_speed))])
    k = int(np.argmin(np.abs(own.speeds - 9000 * RPM)))
    roots = modal(model, 9000 * RPM)
    nearest = int(np.argmin(np.abs(roots.eigenvalues - own.eigenvalues[k, tracked - 1])))
    at_mcs = int(roots.oscillatory[:nearest + 1].sum())
    assert at_mcs != tracked                          # the two numberings differ for this mode
    data = collect(model, inputs)
    html = render._modes(data, "si")
    first = re.findall(r'<tr><td class="text">([^<]*)</td>', html)       # each row's mode cell
    assert f"{tracked} ({at_mcs} at the MCS)" in first
    assert str(at_mcs) not in first                   # no row gives the unstable mode's MCS number alone
    assert _row(data).verdict == "pass"
