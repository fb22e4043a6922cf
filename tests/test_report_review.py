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
    # the Level I figure; no CSR chart: a rigid rotor has no critical speed on rigid supports, its
    # CSR is not evaluated (tests/test_report29d.py)
    assert len(texts) == 1
    for text in (html, *texts):
        assert "kg/m³" not in text.replace("[kg/m³]", "")               # the chart's second axis says both
        assert density in " ".join(text.split())


def _cells(html):
    """(headers, rows of cell texts) of the one table in ``html``."""
    import re

    headers = [re.sub(r"<[^>]+>", "", h) for h in re.findall(r"<th[^>]*>(.*?)</th>", html)]
    rows = [[re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", html)[1:]]
    return headers, rows


def test_margins_table_names_the_source_of_each_peak():
    """Two rotors' peaks at one sensor (an ISO report: the model's unbalances, no API case) are told
    apart by their source, as the figure labels them '(1X motor)', '(1X fan)'; the table had only the
    output, and two rows at one sensor near one speed could not be traced to their curves."""
    import pandas as pd

    from rotordyn_modal.report.render import margins_table

    margins = pd.DataFrame({"output": ["acc", "acc"], "source": ["motor", "fan"], "speed_rpm": [1421.76, 1457.28],
                            "amplitude": [1e-5, 2e-6], "amplification_factor": [17.0, 7.8],
                            "separation_margin_pct": [60.5, 59.5], "required_margin_pct": [15.9, 14.3],
                            "verdict": ["pass", "pass"]})
    headers, rows = _cells(margins_table(margins))
    assert headers[:3] == ["output", "source (1X of)", "peak speed [rpm]"]
    assert [(r[1], r[2], r[3]) for r in rows] == [("motor", "1421.76", "20"), ("fan", "1457.28", "4")]  # µm pk-pk
    with_cases = margins.assign(case=["api-static:motor", "api-couple:fan"])
    headers, rows = _cells(margins_table(with_cases, amplitude="peak"))
    assert headers[:2] == ["output", "case"] and [r[1] for r in rows] == ["api-static:motor", "api-couple:fan"]
    assert "amplitude, 0-peak [µm]" in headers and [r[3] for r in rows] == ["10", "2"]


def test_probe_limit_table_has_no_empty_zone_column():
    """The API probe-limit table showed an ISO 'zone' column empty on every row; the ISO table keeps it."""
    import pandas as pd

    from rotordyn_modal.report.render import _check_table

    probes = pd.DataFrame({"output": ["DE-x"], "check": ["API 617 probe limit"], "speed_rpm": [5980.8],
                           "value": [1.447e-6], "amplitude": ["peak-to-peak"], "limit": [25.4e-6],
                           "verdict": ["pass"], "zone": [""]})
    headers, rows = _cells(_check_table(probes, 1e6, "µm pk-pk"))
    assert headers == ["output", "speed [rpm]", "value [µm pk-pk]", "limit [µm pk-pk]", "verdict"]
    assert rows == [["DE-x", "5980.8", "1.447", "25.4", "pass"]]
    casing = probes.assign(check="ISO 20816-3", zone="A", value=0.9e-3, limit=4.5e-3)
    headers, rows = _cells(_check_table(casing, 1e3, "mm/s RMS"))
    assert "zone" in headers and rows[0][headers.index("zone")] == "A"


def test_unbalance_figure_names_absolute_rotor_sensors_as_such(tmp_path, monkeypatch):
    """Two absolute sensors at one point of a rotor see an orbit but are no proximity probes: the
    report's figure titled their panel 'probe pairs' under a section that says 'No proximity probe
    (measure = "relative") in the model' (examples/spring_block_rotor.toml); it names them as the
    `unbalance` command does, by what they measure."""
    from rigid_two_forward import MODEL

    from rotordyn_modal.report import render

    sensors = "".join(f"""
[[sensors]]
name = "{name}"
rotor = "rotor"
position = [0.0, 0.0, 0.0]
direction = {direction}
""" for name, direction in (("centre-y", [0.0, 1.0, 0.0]), ("centre-z", [0.0, 0.0, 1.0])))
    path = tmp_path / "rotor.toml"
    path.write_text(MODEL + sensors, encoding="utf-8")
    model = load_model(path)
    data = report_collect.ReportData(ReportInputs("api684", MCS, points=21), model, {}, ("unbalance",))
    report_collect._unbalance(data)
    assert data.results["unbalance"].orbit_pairs                         # the two sensors see an orbit
    titles = []

    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt

        titles.extend(ax.get_title() for ax in fig.axes)
        plt.close(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", fake)
    html = render._unbalance(data, "si")
    assert "No proximity probe" in html
    assert "rotor points, absolute" in titles and "probe pairs" not in titles


SOFT_ROTOR = """
name = "rigid rotor on soft bearings"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = 5.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 1.0e-9
diametral_inertia = 5.0
speed_ratio = 1.0
""" + "".join(f"""
[[bearings]]
name = "{name}"
rotor = "rotor"
position = [{x}, 0.0, 0.0]
stiffness = 2.0e3
""" for name, x in (("A", 0.25), ("B", -0.25)))


def test_ucs_map_reaches_the_bearings_own_stiffness(tmp_path):
    """A rotor on bearings of 2e3 N/m (examples/spring_block_rotor.toml) had a UCS map from 1e5 to
    1e10 N/m: its bearings' line lay off the map, with no crossing to say where the machine is. The
    default range is widened by whole decades to reach them, and the crossings are the closed
    forms of a rigid rotor on two springs k at +-a: sqrt(2 k / m) and sqrt(2 k a^2 / Id)."""
    path = tmp_path / "soft.toml"
    path.write_text(SOFT_ROTOR, encoding="utf-8")
    data = report_collect.ReportData(ReportInputs("api684", MCS), load_model(path), {}, ("ucs",))
    report_collect._ucs(data)
    result = data.results["ucs"]
    assert result.stiffness[0] <= 2e2 and result.stiffness[-1] >= 1e10        # one decade beyond, default kept
    assert np.allclose(np.diff(np.log10(result.stiffness)), 1 / 8)            # 8 points a decade
    speeds = sorted({round(c.speed, 6) for c in result.crossings})
    k, m, a, inertia = 2e3, 5.0, 0.25, 5.0
    np.testing.assert_allclose(speeds, [np.sqrt(2 * k * a ** 2 / inertia), np.sqrt(2 * k / m)], rtol=1e-6)
    given = report_collect.ReportData(ReportInputs("api684", MCS, stiffness=np.geomspace(1e5, 1e10, 11)),
                                      load_model(path), {}, ("ucs",))
    report_collect._ucs(given)
    assert given.results["ucs"].stiffness[0] == 1e5 and given.results["ucs"].stiffness[-1] == 1e10   # as asked


def test_stress_of_an_unloaded_shaft_names_no_station():
    """A flexible shaft without static load (examples/compressor_rotor.toml has no gravity) has 0 MPa
    everywhere: the summary said '0 MPa at n0', a place that governs nothing; it says why it is 0."""
    from types import SimpleNamespace

    data = report_collect.ReportData(ReportInputs("api684", MCS), None, {}, ("static",))
    for stress, allowable, verdict in ((0.0, None, "not evaluated"), (0.0, 2e8, "pass"), (5e7, 2e8, "pass")):
        check = SimpleNamespace(rotor="shaft", label="n3", von_mises=stress, allowable=allowable, verdict=verdict,
                                utilization=stress / (allowable or 1.0))
        report_collect._stress_criterion(data, check)
    assert [c.value for c in data.criteria] == ["0 MPa (no static load)", "0 MPa (no static load)", "50 MPa at n3"]


def test_mode_shape_figure_of_one_mode_keeps_its_title_inside(model, monkeypatch):
    """One mode near the range (examples/rubber_mounts.toml at 3000 rpm) makes a figure one panel
    (3.2 in) wide: its title on one line ran off both sides ('apes at the MCS, 3000 rpm (|shape|, no')."""
    from rotordyn_modal.analysis.modal import modal
    from rotordyn_modal.report import render

    mcs = 12345.6 * np.pi / 30                                   # a long speed: the widest title line
    shapes = report_collect.ModeShapes(modal(model, mcs), (1,), ("one of the lowest",), (mcs, mcs))
    data = report_collect.ReportData(ReportInputs("api684", mcs), model, {}, ("modes",), results={"modes": shapes})
    boxes = []

    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt

        fig.canvas.draw()
        boxes.append((fig._suptitle.get_window_extent(), fig.bbox))
        plt.close(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", fake)
    render._modes(data, "si")
    (title, figure), = boxes
    assert figure.x0 <= title.x0 and title.x1 <= figure.x1, (title, figure)


def test_campbell_axis_ends_above_the_highest_mode_a_1x_line_can_cross():
    """Modes at 5.5 to 16 Hz and one at 300 Hz, the 1X line reaching 93.75 Hz
    (examples/motor_pump_on_mounts.toml at an MCS of 3000 rpm): the axis went to 1.4 x 93.75 Hz,
    the crossings in its bottom eighth with their labels on each other; it ends 1.4 x above the
    highest mode below that reach, which every crossing lies under, and the 300 Hz mode, crossed by
    no 1X line, stays above it."""
    from types import SimpleNamespace

    from rotordyn_modal.report.render import campbell_top

    speeds = np.linspace(0.02, 1.5, 31) * 1.25 * 3000 * np.pi / 30 / 1.25      # the pump's 1X at 1.25 x speed
    modes = np.array([5.45, 5.95, 8.63, 10.97, 12.03, 15.8, 15.84, 300.0])
    frequencies = np.tile(modes, (len(speeds), 1))
    frequencies[:, 6] = np.linspace(15.7, 15.84, len(speeds))                   # one mode moving with speed
    result = SimpleNamespace(oscillatory=np.ones_like(frequencies, dtype=bool), frequencies_hz=frequencies,
                             orders=np.array([1.0]), speeds=speeds, sources=SimpleNamespace(multipliers=(1.0, 1.25)))
    reach = 1.25 * speeds[-1] / (2 * np.pi)
    assert reach == pytest.approx(93.75)
    top = campbell_top(result)
    assert top == pytest.approx(1.4 * 15.84, rel=1e-12)
    assert top < 1.4 * reach and top < 300.0
    # a mode between: the axis reaches it and no further
    frequencies[:, 5] = 50.0
    assert campbell_top(result) == pytest.approx(1.4 * 50.0, rel=1e-12)


def test_clearance_scale_factor_note_is_said_once():
    """The clearance table's 'scale factor' cell repeated '(Amax at 9968 rpm, the sweep's speed
    nearest the operating speeds)' on every row (examples/compressor_rotor.toml, MCS alone): four
    lines a row. Each cell says how (short), the parenthesis stands once under the table."""
    from rotordyn_modal.report.render import _scaling_notes

    where = " (Amax at 9968 rpm, the sweep's speed nearest the operating speeds)"
    how, notes = _scaling_notes(["Avl/Amax capped at 6" + where, "Avl/Amax" + where, "unscaled: no probe on rotor r"])
    assert how == ["Avl/Amax capped at 6", "Avl/Amax", "unscaled: no probe on rotor r"]
    assert notes.count("Amax at 9968 rpm") == 1 and "nearest the operating speeds." in notes
