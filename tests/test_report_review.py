"""What a reviewer of ``rotordyn-modal report`` checks, beyond tests/test_report.py: the Level I
verdict is the machine's (the least stable forward mode, against an eigen-analysis written out
here), the Level I figure's title stays inside the figure, the command's help states the mode
window the report uses, and the terminal prints no empty limit.

Fast: a rigid rotor's Level I sweeps and one figure, no report is rendered."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from scipy.optimize import brentq

from rotordyn_modal.analysis.level1 import Station, level1
from rotordyn_modal.cli import main
from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs

#: the module (the package's ``collect`` is its function)
report_collect = importlib.import_module("rotordyn_modal.report.collect")

# A rigid rotor (mass m, diametral inertia Id, polar inertia ~0: no gyroscopic coupling) on two
# isotropic bearings of slightly different stiffness: its lowest forward mode at the centre of
# mass is nearly a pure tilt (the centre barely moves: a cross-coupling there hardly reaches it),
# the second nearly a pure translation, which the cross-coupling drives unstable.
MASS, DIAMETRAL = 50.0, 5.0
BEARINGS = ((0.25, 1.0e6, 300.0), (-0.25, 1.2e6, 300.0))      # (position x [m], stiffness, damping)
QA, MCS = 8.0e4, 3000 * np.pi / 30

MODEL = f"""
name = "rigid rotor, two forward modes"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = {MASS}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 1.0e-9
diametral_inertia = {DIAMETRAL}
speed_ratio = 1.0
""" + "".join(f"""
[[bearings]]
name = "B{i}"
rotor = "rotor"
position = [{x}, 0.0, 0.0]
stiffness = {k}
damping = {c}
""" for i, (x, k, c) in enumerate(BEARINGS))


def _roots(q):
    """Eigenvalues of the rotor written out here: translations y, z of the centre of mass and
    tilts theta_z, theta_y (a bearing at x moves by y + x theta_z and z - x theta_y), the
    cross-coupling q between y and z at the centre of mass."""
    K, C = np.zeros((4, 4)), np.zeros((4, 4))
    for x, k, c in BEARINGS:
        for rows, sign in (([0, 1], 1.0), ([2, 3], -1.0)):      # (y, theta_z), (z, theta_y)
            arm = np.array([1.0, sign * x])
            K[np.ix_(rows, rows)] += k * np.outer(arm, arm)
            C[np.ix_(rows, rows)] += c * np.outer(arm, arm)
    K[0, 2] += q
    K[2, 0] -= q
    M = np.diag([MASS, DIAMETRAL, MASS, DIAMETRAL])
    A = np.block([[np.zeros((4, 4)), np.eye(4)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    return np.linalg.eigvals(A)


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    path = tmp_path_factory.mktemp("level1") / "two_forward_modes.toml"
    path.write_text(MODEL, encoding="utf-8")
    return load_model(path)


def test_level1_verdict_is_that_of_the_least_stable_forward_mode(model):
    """The report judges the machine: its threshold Q0 is where the first root crosses into the
    right half-plane, its log decrement at Qa the least of its modes'. The first forward mode
    alone (what the report judged before) passes both criteria; the machine fails both."""
    threshold = brentq(lambda q: _roots(q).real.max(), 1.0, 1e7, xtol=1e-6)
    roots = _roots(QA)
    roots = roots[roots.imag > 0]
    least = (-2 * np.pi * roots.real / roots.imag).min()
    assert least < 0.1 and threshold / QA < 2                   # the machine fails both criteria

    first = level1(model, MCS, [Station("rotor", 0.0)], QA)     # the first forward mode alone
    assert first.log_decrement_at_qa > 0.1 and not np.isfinite(first.q0)

    data = report_collect.ReportData(ReportInputs("api617", MCS, level1={"stations": [Station("rotor", 0.0)],
                                                                         "qa": QA}), model, {}, ("level1",))
    report_collect._level1(data)
    result = data.results["level1"]
    assert result.q0 == pytest.approx(threshold, rel=1e-8)
    assert result.log_decrement_at_qa == pytest.approx(least, rel=1e-8)
    verdicts = {c.name: c.verdict for c in data.criteria}
    assert verdicts == {"API 617 Level I: log decrement at Qa": "fail", "API 617 Level I: Q0/Qa": "fail"}
    assert [run.mode for run in data.results["level1_runs"]] == [first.mode, result.mode]


def test_level1_figure_title_stays_inside_the_figure(model):
    """With a gas density the verdict is a line of some 150 characters: it is wrapped, not cut
    off at the figure's edges."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = level1(model, MCS, [Station("rotor", 0.0)], QA, gas_density=20.0)
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
