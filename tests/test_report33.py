"""Issue 29 §7, the report read as the engineer who signs it (report33): every verdict traceable
to its numbers.

- The summary's stability row named its least damped mode by number only ("mode 42"), a mode that
  may lie far above the Campbell figure's axis (examples/compressor_on_journals.toml: a 20.9 kHz
  shaft bending mode, where the figure stops at 143 Hz): nothing in the report said which mode
  that was. The note now gives its frequency and whirl at that speed.
- An undamped resonance has an infinite amplification factor (N1 = N2, judged against the largest
  margin any AF requires): the summary said "AF inf" while the AF table said "unknown*" for the same
  peak, with a note that the amplitude "does not fall to peak/sqrt 2 within the sweep"
  (examples/spring_block_rotor.toml). The table now says "inf" too; the note is for NaN only.
- A response without a peak passed the separation margin with an empty limit: the summary row now
  names the rule and the swept range it looked over.
"""

from __future__ import annotations

import html
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.io import load_model

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
RPM = np.pi / 30


def _rows(table_html: str) -> list:
    """The cells (tags out) of each row of one HTML table."""
    return [[html.unescape(re.sub(r"<[^>]+>", "", c)).strip() for c in re.findall(r"<t[dh][^>]*>(.*?)</t[dh]>", row, re.S)]
            for row in re.findall(r"<tr.*?</tr>", table_html, re.S)]


def _summary(page: str) -> dict:
    """criterion -> (value, limit, verdict, note) of the report's summary table."""
    table = re.search(r'<h2 id="summary".*?(<table.*?</table>)', page, re.S).group(1)
    rows = _rows(table)
    return {r[0]: tuple(r[1:5]) for r in rows[1:]}


def _report(tmp_path, name, *options) -> str:
    out = tmp_path / f"{name}.html"
    assert main(["report", str(EXAMPLES / f"{name}.toml"), *options, "--out", str(out), "--quiet"]) == 0
    return out.read_text(encoding="utf-8")


def test_the_least_damped_mode_of_the_stability_row_is_named_by_its_frequency_and_whirl():
    """The stability row's note names the least damped mode's frequency and whirl at the speed it
    names; checked against ``modal`` at that speed solved on its own: the oscillating root of least
    log decrement has that frequency (5 significant digits) and that whirl."""
    import importlib

    from rotordyn_modal.analysis.campbell import campbell
    from rotordyn_modal.report import ReportInputs

    collect = importlib.import_module("rotordyn_modal.report.collect")

    model = load_model(EXAMPLES / "fan_on_bearings.toml")
    inputs = ReportInputs("api684", 3000 * RPM, points=15)
    data = collect.ReportData(inputs, model, {}, ("campbell",))
    data.results["campbell"] = campbell(model, inputs.speeds, orders=(1,))
    collect._stability(data)
    (row,) = [c for c in data.criteria if c.name == collect.STABILITY_CRITERION]
    found = re.search(r"least damped: mode (\d+) \(Campbell diagram's number; ([\d.]+) Hz, (\w+) whirl\) "
                      r"at (\d+) rpm", row.why)
    assert found, row.why
    speed = float(found.group(4)) * RPM
    alone = rdm.modal(model, speed).to_dataframe()
    least = alone.loc[alone["log_decrement"].idxmin()]
    assert float(found.group(2)) == pytest.approx(least["frequency_hz"], rel=1e-4)
    assert found.group(3) == least["whirl"]
    assert f"log dec {least['log_decrement']:.3g}" in row.value


def test_an_infinite_af_is_shown_as_infinite_not_unknown():
    """An undamped resonance's AF is infinite (known): the AF table shows it so, and the note
    that explains unknown AFs (a half-power point beyond the sweep) is left out; an unknown AF
    still reads "unknown*" with its note."""
    from rotordyn_modal.report.render import margins_table

    margins = pd.DataFrame({"output": ["p", "p"], "case": ["api-static:r", "api-static:r"],
                            "speed_rpm": [119.2, 726.0], "amplitude": [2e-5, 2e-6],
                            "amplification_factor": [np.inf, np.nan], "separation_margin_pct": [96.0, 75.8],
                            "required_margin_pct": [16.0, 16.0], "verdict": ["pass", "pass"]})
    table = margins_table(margins.iloc[:1])
    rows = _rows(table)
    af = rows[0].index("AF [-]")
    assert rows[1][af] == "inf"
    assert "AF unknown" not in table
    both = _rows(margins_table(margins))
    assert [r[af] for r in both[1:]] == ["inf", "unknown*"]


def test_summary_and_af_table_say_the_same_of_an_undamped_peak(tmp_path):
    """examples/spring_block_rotor.toml has no damping: its peak's AF is infinite. The summary's
    separation-margin value and the AF table's row of the governing peak give the same AF."""
    page = _report(tmp_path, "spring_block_rotor", "--standard", "api684", "--mcs", "3000", "--points", "31",
                   "--stiffness", "1e2:1e10:9")
    value, limit, verdict, note = _summary(page)["API 684 separation margin"]
    assert "(AF inf)" in value and verdict == "pass", value
    section = page[page.index("Amplification factors and separation margins"):]
    rows = _rows(re.search(r"<table.*?</table>", section, re.S).group(0))
    af = rows[0].index("AF [-]")
    assert {r[af] for r in rows[1:]} == {"inf"}
    assert "* AF unknown" not in section[:section.index("</table>") + 400]


def test_a_response_without_a_peak_names_the_rule_it_passes(tmp_path):
    """examples/journal_rotor.toml (its modes damped past any peak): the separation margin passes
    with "no resonance peak"; its limit names the rule and the note the swept range."""
    page = _report(tmp_path, "journal_rotor", "--standard", "api684", "--mcs", "3000", "--points", "15",
                   "--stiffness", "1e5:1e10:6")
    value, limit, verdict, note = _summary(page)["API 684 separation margin"]
    assert (value, verdict) == ("no resonance peak", "pass")
    assert limit == "each peak's required SM"
    assert re.search(r"over the sweep, 60 to 4500 rpm", note), note


def test_the_level1_figure_title_fits_with_several_stations():
    """A compressor's Level I names a station per impeller: with four, the title's line
    "at 6600 rpm, Q at compressor@-0.364254 m, ..." ran off both sides of the report's figure
    (examples/compressor_on_journals.toml, api617 with stage data). Every title line now lies
    inside the figure, and the station names are all there."""
    import matplotlib

    matplotlib.use("Agg")
    from rotordyn_modal.analysis.level1 import Station, level1

    model = load_model(EXAMPLES / "journal_rotor.toml")
    # six stations, as a six-impeller compressor gives (offsets typed to the micrometre)
    stations = [Station.parse(f"rotor@{x}") for x in (-0.081234, -0.051234, -0.021234, 0.011234, 0.041234, 0.071234)]
    fig = level1(model, 3000 * RPM, stations, 2e5).plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    title = fig.axes[0].title
    extent = title.get_window_extent(renderer)
    assert box.x0 - 0.5 <= extent.x0 and extent.x1 <= box.x1 + 0.5, (extent, box)
    text = title.get_text().replace("\n", " ")
    for station in stations:
        assert station.named("si") in text


@pytest.mark.parametrize("units", ["si", "us"])
def test_the_level1_section_shows_the_stage_data_that_give_qa(tmp_path, units):
    """With stage data, the report's Level I section gave Qa (7.321e+04 N/m) and nothing it came
    from but the command line. It now lists each stage's P, D, H and density ratio, as typed, in the
    report's units, with its q_A = 3 P / (Omega_r D H) rho_d/rho_s worked here by hand (Omega_r the
    MCS, 3000 rpm), and their sum, the Qa of the quantity table."""
    hp, inch, lbf_per_in = 550 * 12 * 0.0254 * 4.4482216152605, 0.0254, 4.4482216152605 / 0.0254
    power, diameter, height, ratio = [15e3, 20e3], 0.3, [0.015, 0.02], [1.1, 1.2]
    omega = 3000 * RPM
    by_hand = [3 * p / omega / (diameter * h) * r for p, h, r in zip(power, height, ratio)]       # N/m
    if units == "si":
        typed = ["15e3,20e3", "0.3", "0.015,0.02"]
        shown = [(p, diameter, h, r, q) for p, h, r, q in zip(power, height, ratio, by_hand)]
    else:
        typed = [f"{power[0] / hp!r},{power[1] / hp!r}", f"{diameter / inch!r}",
                 f"{height[0] / inch!r},{height[1] / inch!r}"]
        shown = [(p / hp, diameter / inch, h / inch, r, q / lbf_per_in) for p, h, r, q in zip(power, height, ratio, by_hand)]
    page = _report(tmp_path, "journal_rotor", "--standard", "api617", "--mcs", "3000", "--station", "rotor",
                   "--rated-power", typed[0], "--impeller-diameter", typed[1], "--restriction-height", typed[2],
                   "--density-ratio", "1.1,1.2", "--points", "15", "--stiffness", "1e5:1e10:6" if units == "si"
                   else "571:5.7e7:6", "--units", units)
    section = page[page.index('<h2 id="level1"'):]
    tables = re.findall(r"<table.*?</table>", section, re.S)
    stages = [t for t in tables if "q_A [" in t]
    assert len(stages) == 1, "no table of the stage data"
    rows = _rows(stages[0])
    assert rows[0] == ["stage", f"P [{'W' if units == 'si' else 'hp'}]", f"D [{'m' if units == 'si' else 'in'}]",
                       f"H [{'m' if units == 'si' else 'in'}]", "ρd/ρs [-]",
                       f"q_A [{'N/m' if units == 'si' else 'lbf/in'}]"]
    for row, expected in zip(rows[1:3], shown):
        assert [float(x) for x in row[1:]] == pytest.approx(list(expected), rel=1e-5), row
    total = sum(q for *_, q in shown)
    assert rows[3][0] == "sum: Qa" and float(rows[3][-1]) == pytest.approx(total, rel=1e-5)
    quantities = _rows(tables[0])
    (qa_row,) = [r for r in quantities if r[0].startswith("anticipated cross-coupling Qa")]
    assert float(qa_row[1]) == pytest.approx(total, rel=1e-3)           # shown to 4 digits
    assert "N<sub>r</sub> = 3000 rpm" in section
