"""One amplitude convention per output (issue 29 §6): the user's one choice, 0-peak, peak-to-peak
or RMS (``--amplitude``), governs the peaks table with the amplification factors and separation
margins, the CSV's added column and the figure of ``unbalance``, and every vibration amplitude of
``report`` (its AF table, unbalance figure, probe-limit and clearance tables and summary) alike;
each column and axis names it.

The reference is the analysis's own 0-peak amplitude (``UnbalanceResult.amplitude``, closed-form
tested in tests/test_standard_unbalance.py) times the exact factors of a harmonic
``A cos(w t + phi)``: peak-to-peak 2 A, RMS A / sqrt 2; a table value equals the figure's curve
at the same speed. Fast: a rigid rotor on two bearings (4 coordinates), figures not rasterised."""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from test_exact_af29 import _closed_form          # the rigid rotor's peak by hand: MODEL is that rotor

#: convention -> (factor on the 0-peak amplitude, words of the axis label, column of the tables)
CONVENTIONS = {"peak": (1.0, "0-peak", "amplitude_0pk"), "pk-pk": (2.0, "peak-to-peak", "amplitude_pkpk"),
               "rms": (1.0 / math.sqrt(2.0), "RMS", "amplitude_rms")}

#: a rigid rotor on two equal damped bearings, a probe at its centre of mass: one resonance near
#: sqrt(2 k / m) = 3487 rpm (AF about 14), above an operating speed of 3000 rpm
MODEL = """
name = "rotor on two bearings"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "shaft"
mass = 30.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.4
diametral_inertia = 0.9
speed_ratio = 1.0

[[bearings]]
name = "DE"
rotor = "shaft"
position = [0.25, 0.0, 0.0]
stiffness = 2.0e6
damping = 400.0

[[bearings]]
name = "NDE"
rotor = "shaft"
position = [-0.25, 0.0, 0.0]
stiffness = 2.0e6
damping = 400.0

[[unbalances]]
rotor = "shaft"
amount = 5.0e-5

[[sensors]]
name = "probe-z"
rotor = "shaft"
measure = "relative"
position = [0.0, 0.0, 0.0]
direction = [0.0, 0.0, 1.0]
"""

#: the axis label's unit -> metres per unit
PER_METRE = {"[m]": 1.0, "[mm]": 1e3, "[µm]": 1e6}


@pytest.fixture(scope="module")
def model_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("convention") / "rotor.toml"
    path.write_text(MODEL, encoding="utf-8")
    return path


def _curve_at(fig, output, speed_rpm):
    """The amplitude the figure draws for ``output`` at ``speed_rpm`` [m], the axis label's words."""
    ax = fig.axes[0]
    label = ax.get_ylabel()
    curve = next(line for line in ax.get_lines() if line.get_label().startswith(output + ":"))
    i = int(np.argmin(np.abs(np.asarray(curve.get_xdata()) - speed_rpm)))
    assert curve.get_xdata()[i] == pytest.approx(speed_rpm, rel=1e-12)
    return curve.get_ydata()[i] / PER_METRE[label.rpartition(" ")[2]], label


# -- unbalance ----------------------------------------------------------------------------------

@pytest.mark.parametrize("amplitude", list(CONVENTIONS))
def test_unbalance_peaks_table_csv_and_figure_show_the_one_convention(amplitude, model_path, tmp_path, monkeypatch):
    """The printed peaks table holds one amplitude column, named by the convention asked, whose
    value is the figure's curve at the peak and the 0-peak amplitude times the exact factor; the
    CSV's column of that convention equals the curve at every speed (its ``amplitude`` stays
    0-peak: the command's fixed columns)."""
    import pandas as pd

    from rotordyn_modal.cli import unbalance as command

    tables, figures = [], []
    printed = command.print_table
    monkeypatch.setattr(command, "print_table", lambda table, **k: tables.append(table) or printed(table, **k))
    monkeypatch.setattr(command, "save_figure", lambda fig, args, *a: figures.append(fig))
    out = tmp_path / "u.csv"
    assert main(["unbalance", str(model_path), "--speeds", "100:8000:80", "--operating-speed", "3000",
                 "--amplitude", amplitude, "--plot", str(tmp_path / "u.png"), "--out", str(out)]) == 0
    factor, words, column = CONVENTIONS[amplitude]
    speeds = np.linspace(100.0, 8000.0, 80)
    reference = rdm.unbalance_response(rdm.load_model(model_path), rdm.rpm(speeds)).amplitude[0, 0]   # 0-peak

    (peaks,) = [t for t in tables if "amplification_factor" in t]
    assert [c for c in peaks.columns if c.startswith("amplitude")] == [column]
    (fig,) = figures
    assert len(peaks) == 1
    row = peaks.iloc[0]
    drawn, label = _curve_at(fig, "probe-z", speeds[np.argmax(reference)])
    assert words in label
    assert drawn == pytest.approx(factor * reference[np.argmax(reference)], rel=1e-12)
    # the table's peak is the exact response's (issue 29 §4): the closed form's, in the convention
    n_c, _, _, peak = _closed_form()
    assert row[column] == pytest.approx(factor * peak, rel=1e-9)
    assert row.speed_rpm == pytest.approx(n_c * 30 / np.pi, rel=1e-6) and row.amplification_factor > 2.5

    csv = pd.read_csv(out)
    np.testing.assert_allclose(csv["amplitude"], reference, rtol=1e-9)            # 0-peak, as always
    if amplitude != "peak":
        np.testing.assert_allclose(csv[column], factor * reference, rtol=1e-9)
        for speed, value in zip(csv.speed_rpm[::7], csv[column][::7]):
            assert value == pytest.approx(_curve_at(fig, "probe-z", speed)[0], rel=1e-9)


# -- report -------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def collected(model_path):
    """The API 684 report's results (no figure drawn yet), with the default convention."""
    from rotordyn_modal.report import ReportInputs, collect

    model = rdm.load_model(model_path)
    inputs = ReportInputs("api684", rdm.rpm(3000.0), points=61, stiffness=np.geomspace(1e5, 1e10, 5))
    return collect(model, inputs)


def _rendered(data, monkeypatch):
    """The page of ``data`` and the figures it drew (not rasterised)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.report import render

    figures = []
    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: figures.append(fig) or "data:image/png;base64,")
    page = render.render_html(dataclasses.replace(data, sections=("campbell", "unbalance")))   # the figures that matter
    plt.close("all")
    return page, figures


def _table_after(page, anchor):
    """(headers, rows of cell texts) of the first table after ``anchor`` in ``page``."""
    part = page[page.index(anchor):]
    part = part[part.index("<table>"):part.index("</table>")]
    headers = [re.sub(r"<[^>]+>", "", h) for h in re.findall(r"<th[^>]*>(.*?)</th>", part)]
    rows = [[re.sub(r"<[^>]+>", "", cell) for cell in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", part)[1:]]
    return headers, rows


@pytest.mark.parametrize("amplitude", [None, "peak", "rms"])
def test_report_af_table_figure_and_limits_show_the_one_convention(amplitude, collected, monkeypatch):
    """The AF table's amplitude (4 digits) is the unbalance figure's curve at the peak and the
    0-peak amplitude times the exact factor; the probe-limit table and the summary give the
    peak-to-peak value and limit (API 617) times the factor over 2; every header names the
    convention. Default (None): peak-to-peak, as the figure always was."""
    data = collected
    if amplitude is not None:
        data = dataclasses.replace(collected, inputs=dataclasses.replace(collected.inputs, amplitude=amplitude))
    factor, words, _ = CONVENTIONS[amplitude or "pk-pk"]
    page, figures = _rendered(data, monkeypatch)
    response = data.results["unbalance"]
    reference = response.amplitude[0, 0]                                   # 0-peak, the API static case
    speeds = response.speeds * 30 / np.pi

    headers, rows = _table_after(page, 'id="margins"')
    column = headers.index(f"amplitude, {words} [µm]")
    (row,) = [r for r in rows if "api-static" in " ".join(r)]
    peak_rpm = float(row[headers.index("peak speed [rpm]")])
    shown = float(row[column]) * 1e-6
    unbalance = next(f for f in figures if f.axes and f.axes[0].get_ylabel().startswith("Amplitude"))
    curve = next(line for line in unbalance.axes[0].get_lines() if line.get_label() == "probe-z: 1X api-static:shaft")
    i = int(np.argmax(reference))
    drawn = curve.get_ydata()[i] / PER_METRE[unbalance.axes[0].get_ylabel().rpartition(" ")[2]]
    assert words in unbalance.axes[0].get_ylabel()
    assert curve.get_xdata()[i] == pytest.approx(speeds[i], rel=1e-12)
    assert drawn == pytest.approx(factor * reference[i], rel=1e-9)
    # the table's peak is the exact response's (issue 29 §4): the closed form's, in the convention
    # (the API static case's amount 2 x 6350 m / N g mm = 127 g mm, the closed form's 5e-5 kg m scaled)
    n_c, _, _, peak = _closed_form()
    assert shown == pytest.approx(factor * peak * (2 * 6350 * 30.0 / 3000 * 1e-6) / 5e-5, rel=5e-4)   # 4 digits
    assert peak_rpm == pytest.approx(n_c * 30 / np.pi, rel=2e-6)                                         # 6 digits

    check = data.results["checks"].to_dataframe().iloc[0]                   # judged peak-to-peak
    short = {"0-peak": "0-peak", "peak-to-peak": "pk-pk", "RMS": "RMS"}[words]
    headers, rows = _table_after(page, "<h3>API 617 probe vibration limit</h3>")
    assert f"value [µm {short}]" in headers and f"limit [µm {short}]" in headers
    value, limit = (float(rows[0][headers.index(f"{h} [µm {short}]")]) * 1e-6 for h in ("value", "limit"))
    assert value == pytest.approx(check.value * factor / 2, rel=5e-4)
    assert limit == pytest.approx(check.limit * factor / 2, rel=5e-4)
    summary = next(c for c in data.criteria if c.name == "API 617 probe vibration limit")
    shown_summary = summary.in_system("si", amplitude or "pk-pk")
    assert shown_summary.value == f"{check.value * factor / 2 * 1e6:.3g} µm {short}"
    assert shown_summary.limit == f"<= {check.limit * factor / 2 * 1e6:.3g} µm {short}"
    assert f"{shown_summary.value}</td>" in page and f"Vibration amplitudes are {words} throughout" in page


def test_report_refuses_an_unknown_convention_by_name(model_path, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["report", str(model_path), "--standard", "api684", "--mcs", "3000", "--amplitude", "p2p",
              "--out", str(tmp_path / "r.html")])
    err = capsys.readouterr().err
    assert exit_.value.code == 2 and "--amplitude" in err and "'p2p'" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "r.html").exists()


def test_report_judges_no_peak_of_a_round_off_curve(collected):
    """The API couple case of a symmetric rotor is a pure tilt: at the centre of mass the probe sees
    nothing (exactly 0; computed, round-off of 1e-21 m beside the static case's 6e-5 m). Its
    'peaks' got an amplification factor and a separation-margin verdict ('fail') in the report;
    only the static case's resonance is judged."""
    response = collected.results["unbalance"]
    couple = list(response.sources).index("api-couple:shaft")
    assert response.amplitude[0, couple].max() < 1e-12 * response.amplitude.max()        # zero to round-off
    margins = collected.results["margins"]
    assert list(margins["case"]) == ["api-static:shaft"]


@pytest.mark.parametrize("amplitude, shown", [("peak", "12.7 µm 0-peak (25.4 µm pk-pk)"),
                                              ("rms", "8.98 µm RMS (25.4 µm pk-pk)"),
                                              ("pk-pk", "25.4 µm pk-pk")])
def test_figure_names_the_probe_limit_in_its_convention(amplitude, shown, model_path):
    """The probe-limit line of an RMS figure is drawn at 25.4 µm / (2 sqrt 2) = 8.98 µm; its legend
    said '25.4 µm pk-pk' beside an axis in µm RMS. It names the drawn value in the axis's
    convention, the rule's pk-pk value after it."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(model_path)
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(100.0, 8000.0, 41)), amplitude=amplitude)
    fig = result.plot(checks=result.checks(model, mcs=rdm.rpm(3000.0)))
    labels = [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    limit = [text for text in labels if text.startswith("API 617 probe limit")]
    plt.close(fig)
    assert limit and limit[0].removesuffix(" (above the axis)") == f"API 617 probe limit {shown}"
    factor = CONVENTIONS[amplitude][0]
    assert f"{25.4 * factor / 2:.3g}" in limit[0]                          # the value drawn, by the exact factor
