"""Two things a reviewer of ``rotordyn-modal report`` could not trace to their numbers (redteam28,
reports of every example looked at in headless Chromium):

* the static displacement table mixed two references without saying so: the stator's rows are
  relative to the ground (flexible_pump_on_mounts: -3373 µm on its rubber mounts), a rotor's
  relative to the stator (its motion in its bearings: -0.40 µm), docs/static.md; a reader took
  the pump's +0.30 µm as the pump rising while its casing sinks 3.4 mm. A "relative to" column
  now says which, checked here against the stator's own motion (the rotor rows are not it);
* an AF table row "not evaluated" showed empty AF and required-margin cells with no reason (the
  reason was only in the summary's note).
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import numpy as np

from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs

report_collect = importlib.import_module("rotordyn_modal.report.collect")
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _cells(html: str):
    headers = [re.sub(r"<[^>]+>", "", h) for h in re.findall(r"<th[^>]*>(.*?)</th>", html)]
    rows = [[re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", html)[1:]]
    return headers, rows


def _static_table(name: str):
    from rotordyn_modal.report import render

    model = load_model(EXAMPLES / f"{name}.toml")
    data = report_collect.ReportData(ReportInputs("api684", 3000 * np.pi / 30), model, {}, ("static",))
    report_collect._static(data)
    html = render._static(data, "si")
    table = html[html.index("Static displacement"):html.index("Reactions")]
    return data.results["static"], _cells(table)


def test_static_rows_say_what_they_are_relative_to():
    result, (headers, rows) = _static_table("flexible_pump_on_mounts")
    assert headers[:3] == ["body", "point", "relative to"], headers
    bodies = {r[0]: r[2] for r in rows}
    assert bodies == {"stator": "ground", "motor": "stator", "pump": "stator"}, bodies
    # the stator's rows are its motion over the ground: its centre sinks by about weight / stiffness
    stator_z = float(rows[0][5])
    assert stator_z < -1000.0                                          # µm: 3.4 mm on the rubber mounts
    # a rotor's rows are not the stator's motion at that point (they are the motion in its bearings)
    for row in rows:
        if row[0] != "stator":
            assert abs(float(row[5])) < 1e-3 * abs(stator_z), row


def test_static_rows_of_a_rotor_on_the_ground_are_relative_to_the_ground():
    _, (headers, rows) = _static_table("journal_rotor")
    assert headers[2] == "relative to" and {r[2] for r in rows} == {"ground"}


def test_af_rows_not_evaluated_say_why():
    import pandas as pd

    from rotordyn_modal.report.render import margins_table

    margins = pd.DataFrame({"output": ["p", "p"], "case": ["api-static:r", "api-static:r"],
                            "speed_rpm": [948.0, 726.0], "amplitude": [1e-6, 2e-6],
                            "amplification_factor": [np.nan, 5.54], "separation_margin_pct": [68.4, 75.8],
                            "required_margin_pct": [np.nan, 12.8], "verdict": ["not evaluated", "pass"]})
    html = margins_table(margins)
    headers, rows = _cells(html)
    af, required = headers.index("AF [-]"), headers.index("required margin [%]")
    assert (rows[0][af], rows[0][required]) == ("unknown*", "unknown*")
    assert (rows[1][af], rows[1][required]) == ("5.54", "12.8")
    assert "* AF unknown: the amplitude does not fall to peak/&radic;2 on both sides" in html
    assert "AF unknown" not in margins_table(margins.iloc[1:])        # no note where every AF is known


def _shaft_rows(name: str):
    from rotordyn_modal.report import render

    model = load_model(EXAMPLES / f"{name}.toml")
    data = report_collect.ReportData(ReportInputs("api684", 3000 * np.pi / 30), model, {}, ("static",))
    report_collect._static(data)
    html = render._static(data, "si")
    return _cells(html[html.index("Flexible shafts"):])[1]


def test_a_quantity_zero_along_the_whole_shaft_names_no_station():
    """examples/compressor_rotor.toml has no gravity: every quantity is 0 along its shaft, and the
    table named 'n0, x = 0' as where the largest is (the summary already said '(no static load)');
    flexible_pump_on_mounts carries no torque: its torque row named n0 likewise."""
    rows = _shaft_rows("compressor_rotor")
    assert len(rows) == 6 and all((r[2], r[3], r[4]) == ("0", "none (0 everywhere)", "") for r in rows), rows
    rows = {r[1].split(" [")[0]: r for r in _shaft_rows("flexible_pump_on_mounts")}
    assert rows["largest torque"][3] == "none (0 everywhere)"
    assert rows["largest sag"][3] == "n0" and float(rows["largest sag"][2]) > 0      # a loaded shaft names it


def test_probe_limit_takes_the_peak_found_between_swept_speeds():
    """examples/compressor_rotor.toml at 41 speeds (a report's --points 41): the AF table's peak
    (found between swept speeds) was 57.4 µm pk-pk at 5,726 rpm, while the probe-limit table and
    summary, "largest over 0 to MCS", said 35.7 µm at the swept 5,841 rpm. The true largest is
    taken here from a fine sweep of the same response (0.5 rpm steps around the peak): the probe
    limit's value must reach it."""
    import rotordyn_modal as rdm
    from rotordyn_modal.analysis.unbalance import api_unbalance_response

    model = load_model(EXAMPLES / "compressor_rotor.toml")
    mcs = 9000 * np.pi / 30
    data = report_collect.ReportData(ReportInputs("api617", mcs, operating=(7000 * np.pi / 30, mcs), points=41),
                                     model, {}, ("unbalance",))
    report_collect._unbalance(data)
    data.results["peaks"] = report_collect.separation_margins(data.results["unbalance"], data.inputs.range)
    table = report_collect.probe_limit_table(data)
    row = table[(table["output"] == "probe-left-y") & (table["case"] == "api-static:compressor")].iloc[0]
    result = data.results["unbalance"]
    swept = 2.0 * np.abs(np.asarray(result.response)[list(result.outputs).index("probe-left-y"),
                                                       list(result.sources).index("api-static:compressor")])
    fine = rdm.rpm(np.arange(row.speed_rpm - 60.0, row.speed_rpm + 60.0, 0.5))
    response = api_unbalance_response(model, fine, mcs)
    k = list(response.outputs).index("probe-left-y")
    case = list(response.sources).index("api-static:compressor")
    truth = 2.0 * np.abs(np.asarray(response.response)[k, case]).max()      # pk-pk of the probe's direction
    assert swept[np.abs(result.speeds) <= mcs].max() < 0.8 * truth          # the swept largest misses the top
    assert row.value >= truth * (1 - 1e-4) and row.value <= truth * (1 + 1e-3), (row.value, truth)
    assert row.verdict == ("pass" if row.value <= row.limit else "fail")


def test_level2_note_names_the_criterion_that_requires_it():
    """compressor_rotor's API 617 report: 'Q0/Qa 6.12 >= 2 pass' carried the note 'Level II
    required' (the log decrement at Qa, 0.0815 < 0.1, requires it): the note names which."""
    from types import SimpleNamespace

    for log_dec, ratio, csr, expected in ((False, True, True, "Level II required (by the log decrement at Qa)"),
                                          (True, False, True, "Level II required (by Q0/Qa)"),
                                          (False, False, True, "Level II required (by the log decrement at Qa and Q0/Qa)"),
                                          (True, True, False, "Level II required (by the critical speed ratio)"),
                                          (True, True, True, "Level II not required")):
        result = SimpleNamespace(passes_log_decrement=log_dec, passes_ratio=ratio, passes_csr=csr,
                                 level2_required=not (log_dec and ratio and csr))
        assert report_collect._level2_note(result) == expected
