"""The report's mode shapes near the operating range and its clearance check.

A small flexible rotor with two close-clearance stations (``tests/data/flexible_with_seals.toml``)
reported to API 684: the ``modes`` section shows the modes the documented rule picks (computed
here from ``modal`` at the MCS: a frequency at the MCS, as a 1X speed, within 16 % below / 26 % above the
operating range), captioned with number, frequency, whirl and log decrement as ``modal`` gives
them, drawn as deflected shaft lines; the clearance table holds one row per station and API
case with the values of the analysis called alone and the 75 % rule's verdicts; the summary
carries the clearance criterion. The rigid journal rotor's report (tests/test_report.py) shows
the mode-shape bar chart of the modes the same rule picks.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.analysis.modal import modal
from rotordyn_modal.analysis.unbalance import api_unbalance_response
from rotordyn_modal.cli import main
from rotordyn_modal.io import load_model

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "tests" / "data" / "flexible_with_seals.toml"
MCS_RPM, LOW_RPM, POINTS = 5000.0, 4000.0, 15


def _section(html, name):
    """The HTML of section ``name`` (from its heading to the next section's)."""
    start = html.index(f'<h2 id="{name}">')
    following = html.find("<h2 id=", start + 1)
    return html[start:following if following > 0 else len(html)]


def _rows(table_html):
    """The body rows of the first table of ``table_html``, cells as text."""
    body = table_html[table_html.index("<tbody>"):table_html.index("</tbody>")]
    return [[re.sub(r"<[^>]+>", "", cell).strip() for cell in re.findall(r"<td[^>]*>(.*?)</td>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", body)]


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """(HTML, texts of each figure) of the flexible rotor's API 684 report (figures built, not
    rasterised)."""
    from matplotlib.text import Text

    import rotordyn_modal.report.render as render

    texts = []

    def fake(fig, dpi=110):
        import matplotlib.pyplot as plt

        texts.append([t.get_text() for t in fig.findobj(Text) if t.get_text()])
        plt.close(fig)
        return "data:image/png;base64,"

    out = tmp_path_factory.mktemp("modes") / "r.html"
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(render, "figure_png", fake)
        assert main(["report", str(MODEL), "--standard", "api684", "--mcs", str(MCS_RPM), "--operating",
                     f"{LOW_RPM}:{MCS_RPM}", "--points", str(POINTS), "--stiffness", "1e5:1e10:5", "--out", str(out),
                     "--quiet"]) == 0
    return out.read_text(encoding="utf-8"), texts


def _expected_modes(model):
    """The rule of docs/report.md written here: modes at the MCS whose frequency (as a 1X speed)
    lies within 16 % below or 26 % above the operating range (the largest separation margins of
    API 617, ``min(16, ...)`` below and ``min(26, ...)`` above: docs/standards.md)."""
    result = modal(model, MCS_RPM * np.pi / 30)
    table = result.to_dataframe()
    rpm = table["frequency_hz"] * 60
    return result, table[(rpm >= 0.84 * LOW_RPM) & (rpm <= 1.26 * MCS_RPM)]


def test_mode_shapes_of_the_modes_near_the_operating_range(page):
    html, texts = page
    result, expected = _expected_modes(load_model(MODEL))
    assert list(expected["mode"]) == [1, 2]          # the model is made so (its first pair at 4600 rpm)
    section = _section(html, "modes")
    rows = _rows(section)
    assert [int(r[0]) for r in rows] == list(expected["mode"])
    for row, mode in zip(rows, expected.itertuples()):
        assert float(row[1]) == pytest.approx(mode.frequency_hz, rel=1e-4)
        assert row[2] == f"{mode.whirl} whirl"
        assert float(row[3]) == pytest.approx(mode.log_decrement, rel=2e-3)
        caption = f"mode {mode.mode}: {mode.frequency_hz:.4g} Hz, {mode.whirl} whirl, log dec {mode.log_decrement:.3g}"
        assert caption in section
    assert section.count("<img ") == 1 and "<figcaption>" in section
    # the figure drawn is the deflected shaft lines, one panel per mode with its number
    shaft = [t for t in texts if any(s.startswith("Mode shapes at the MCS") for s in t)]
    assert len(shaft) == 1
    titles = [s for s in shaft[0] if s.startswith("mode ")]
    assert [int(s.split(":")[0].split()[1]) for s in titles] == list(expected["mode"])
    assert any("position along x [m]" in s for s in shaft[0])


def test_clearance_table_and_criterion_equal_the_analysis(page):
    html, _ = page
    model = load_model(MODEL)
    mcs = MCS_RPM * np.pi / 30
    speeds = np.union1d(np.linspace(0.02 * mcs, 1.5 * mcs, POINTS), [LOW_RPM * np.pi / 30, mcs])   # the report's sweep
    check = api_unbalance_response(model, speeds, mcs).clearance_check(
        model, mcs=mcs, min_operating=LOW_RPM * np.pi / 30).to_dataframe()
    section = _section(html, "unbalance")
    clearance = section[section.index('id="clearance"'):]
    rows = _rows(clearance)
    radial = {c.name: c.radial_clearance for c in model.clearances}
    # two stations, three API cases: static, couple and the flexible shaft's first mode (api-mode1)
    assert len(rows) == len(model.clearances) * 3 == len(check)
    assert sorted(set(check.case)) == ["api-couple:shaft", "api-mode1:shaft", "api-static:shaft"]
    for row, expected in zip(rows, check.itertuples()):
        name, rotor, case, radial_um, speed, response, scale, scaling, value, limit, ratio, verdict = row
        assert (name, rotor, case) == (expected.clearance, expected.rotor, expected.case)
        assert float(radial_um) == pytest.approx(radial[name] * 1e6, rel=1e-12)
        assert float(response) == pytest.approx(expected.response * 1e6, rel=5e-4)
        assert float(scale) == pytest.approx(expected.scale_factor, rel=5e-3) and scaling == expected.scaling
        assert float(value) == pytest.approx(expected.value * 1e6, rel=5e-4)
        assert float(limit) == pytest.approx(0.75 * 2 * radial[name] * 1e6, rel=1e-12)   # 75 % of diametral
        assert verdict == ("pass" if expected.value <= 1.5 * radial[name] else "fail")
    summary = _section(html, "summary") if '<h2 id="summary">' in html else html
    row = re.search(r'<a href="#unbalance">API 617 clearance \(75 % of diametral\)</a></td>(.*?)</tr>', summary)
    assert row
    worst = check.iloc[int(np.argmax(check["ratio"]))]
    verdict = "pass" if (check["value"] <= 1.5 * check["clearance"].map(radial)).all() else "fail"
    assert f">{verdict}<" in row.group(1) and worst.clearance in row.group(1)


def test_static_section_shows_the_flexible_shafts_largest_moment_and_diagram(monkeypatch):
    """The report's static section of a flexible machine under gravity: the largest bending
    moment row is the largest |M| of the shaft's stations (N m, and lbf in = N m / 0.112984829),
    with the sag/shear/moment diagram embedded."""
    import rotordyn_modal.report.render as render
    from rotordyn_modal.analysis.static import static

    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: "data:image/png;base64,")
    result = static(load_model(ROOT / "examples" / "flexible_pump_on_mounts.toml"))
    (rotor, shaft), = result.shafts.items()
    largest = shaft.table()["Mb_Nm"].abs().max()
    assert largest > 0
    for units, factor in (("si", 1.0), ("us", 1 / 0.112984829)):
        html = "".join(render._shaft_statics(result, units))
        rows = _rows(html)
        moment = [r for r in rows if r[1].startswith("largest bending moment")]
        assert len(moment) == 1 and moment[0][0] == rotor
        assert float(moment[0][2]) == pytest.approx(largest * factor, rel=1e-3)
        assert html.count("<img ") == 1


def test_static_section_gives_the_shaft_sag_in_the_unit_of_the_figure_and_the_terminal(monkeypatch):
    """The largest sag of a flexible shaft in the report: µm (SI) or mil (US, 1 mil = 2.54e-5 m
    exactly), the unit the shaft statics figure's sag axis and the ``static`` command's summary use."""
    import rotordyn_modal.report.render as render
    from rotordyn_modal.analysis.static import static
    from rotordyn_modal.cli.static import _shaft_summary

    labels = []

    def keep_labels(fig, dpi=110):
        labels.extend(ax.get_ylabel() for ax in fig.axes)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", keep_labels)
    result = static(load_model(ROOT / "examples" / "flexible_pump_on_mounts.toml"))
    (rotor, shaft), = result.shafts.items()
    largest = np.hypot(*shaft.sag.T).max()
    for units, unit, factor in (("si", "µm", 1e6), ("us", "mil", 1 / 2.54e-5)):
        labels.clear()
        rows = _rows("".join(render._shaft_statics(result, units)))
        (sag,) = [r for r in rows if r[1].startswith("largest sag")]
        assert sag[1] == f"largest sag [{unit}]"
        assert float(sag[2]) == pytest.approx(largest * factor, rel=1e-3)
        assert any(label.startswith("sag") and f"[{unit}]" in label for label in labels), labels
        assert re.search(rf"largest sag {float(sag[2]):.3g}\d* {unit} ", _shaft_summary(shaft, units))
