"""What a reviewer of ``rotordyn-modal report`` checks, beyond tests/test_report.py: the Level I
verdict is the machine's (the least stable forward mode, against an eigen-analysis written out
here), the Level I figure's title stays inside the figure, the command's help states the mode
window the report uses, and the terminal prints no empty limit.

Fast: a rigid rotor's Level I sweeps and one figure, no report is rendered."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from rotordyn_modal.analysis.level1 import Station, level1
from rotordyn_modal.cli import main
from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs

# the hand-written rigid rotor whose first forward mode is not its least stable
from rigid_two_forward import MCS, QA, least_log_decrement, threshold, write_model

#: the module (the package's ``collect`` is its function)
report_collect = importlib.import_module("rotordyn_modal.report.collect")

@pytest.fixture(scope="module")
def model(tmp_path_factory):
    return load_model(write_model(tmp_path_factory.mktemp("level1")))


def test_level1_verdict_is_that_of_the_least_stable_forward_mode(model):
    """The report judges the machine: its threshold Q0 is where the first root crosses into the
    right half-plane, its log decrement at Qa the least of its modes'. The first forward mode
    alone (what the report judged before) passes both criteria; the machine fails both."""
    q0, least = threshold(), least_log_decrement(QA)
    assert least < 0.1 and q0 / QA < 2                          # the machine fails both criteria

    first = level1(model, MCS, [Station("rotor", 0.0)], QA, forward_mode=1)     # the first forward mode alone
    assert first.log_decrement_at_qa > 0.1 and not np.isfinite(first.q0)

    data = report_collect.ReportData(ReportInputs("api617", MCS, level1={"stations": [Station("rotor", 0.0)],
                                                                         "qa": QA}), model, {}, ("level1",))
    report_collect._level1(data)
    result = data.results["level1"]
    assert result.q0 == pytest.approx(q0, rel=1e-8)
    assert result.log_decrement_at_qa == pytest.approx(least, rel=1e-8)
    verdicts = {c.name: c.verdict for c in data.criteria}
    assert verdicts == {"API 617 Level I: log decrement at Qa": "fail", "API 617 Level I: Q0/Qa": "fail"}
    assert [run.mode for run in result.swept] == [first.mode, result.mode]


def test_level1_figure_title_stays_inside_the_figure(model):
    """With a gas density the verdict is a line of some 150 characters: it is wrapped, not cut
    off at the figure's edges."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # the first forward mode alone: Q0/Qa > 10, and the verdict says the CSR is not applied
    result = level1(model, MCS, [Station("rotor", 0.0)], QA, gas_density=20.0, forward_mode=1)
    assert len(result.verdict()) > 120
    fig = result.plot()
    fig.canvas.draw()
    box = fig.bbox
    for ax in fig.axes:
        title = ax.title.get_window_extent()
        assert box.x0 - 0.5 <= title.x0 and title.x1 <= box.x1 + 0.5, (title, box)
    plt.close(fig)


def test_report_help_states_the_mode_window(capsys):
    """The help names the window the mode-shapes section uses (16 % below, 26 % above)."""
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    low, high = (round(100 * x) for x in report_collect.MODE_WINDOW)
    assert (low, high) == (16, 26)
    assert f"within {low} % below or {high} % above the operating range" in text


def test_terminal_line_prints_no_empty_limit():
    from rotordyn_modal.cli.report import _terminal_line

    no_peak = report_collect.Criterion("API 684 separation margin", "no resonance peak", "", "pass", "campbell",
                                       "no peak of the response over the sweep")
    assert _terminal_line(no_peak) == "API 684 separation margin: pass (no resonance peak)"
    probe = report_collect.Criterion("API 617 probe vibration limit", "1.45 µm pk-pk", "<= 25.4 µm pk-pk", "pass",
                                     "unbalance")
    assert _terminal_line(probe) == "API 617 probe vibration limit: pass (1.45 µm pk-pk; limit <= 25.4 µm pk-pk)"
    missing = report_collect.Criterion("API 617 Level I: Q0/Qa", "", "", "not evaluated", "level1", "no --station")
    assert _terminal_line(missing) == "API 617 Level I: Q0/Qa: not evaluated: no --station"


def test_us_level1_section_states_the_gas_density_in_us_units(model, monkeypatch):
    """A report in US units says the CSR's gas density in lb/ft³ everywhere: in the section's
    verdict sentence and in the Level I figure's title (they said kg/m³ while the summary and the
    chart said lb/ft³)."""
    from matplotlib.text import Text

    from rotordyn_modal.report import render

    inputs = ReportInputs("api617", MCS, level1={"stations": [Station("rotor", 0.0)], "qa": QA, "gas_density": 20.0})
    data = report_collect.ReportData(inputs, model, {}, ("level1",))
    report_collect._level1(data)
    texts = []

    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt

        texts.append(" ".join(t.get_text() for t in fig.findobj(Text)))
        plt.close(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", fake)
    html = render._level1(data, "us")
    density = f"{20.0 / (0.45359237 / 0.3048 ** 3):.4g} lb/ft³"          # lb and ft by definition
    assert len(texts) == 2                                               # the Level I figure, the CSR chart
    for text in (html, *texts):
        assert "kg/m³" not in text.replace("[kg/m³]", "")               # the chart's second axis says both
        assert density in " ".join(text.split())
