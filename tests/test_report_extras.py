"""The report's tables and figures as a reviewer reads them: the critical-speed table prints a
damping ratio at round-off as 0 (as ``modes`` and ``critical-speeds`` do), not -1.9e-18.

Fast: a small model's Campbell sweep at a few speeds, no figure rasterised."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.io import load_model
from rotordyn_modal.report import ReportInputs, render

#: the module (the package's ``collect`` is its function)
report_collect = importlib.import_module("rotordyn_modal.report.collect")
ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture
def no_figures(monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def fake(fig, dpi=110):
        plt.close(fig)
        return "data:image/png;base64,"

    monkeypatch.setattr(render, "figure_png", fake)


def _column(html, header):
    """The cells of the first table's column ``header`` in ``html``."""
    table = html[html.index("<table>"):html.index("</table>")]
    headers = re.findall(r"<th[^>]*>(.*?)</th>", table)
    column = headers.index(header)
    return [re.findall(r"<td[^>]*>(.*?)</td>", row)[column] for row in re.findall(r"<tr>(.*?)</tr>", table)[1:]]


def test_critical_speed_table_prints_round_off_damping_as_zero(no_figures, monkeypatch):
    """spring_block_rotor.toml has no damping anywhere (no bearing, mount or material damping):
    a conservative gyroscopic machine, every root on the imaginary axis, every critical speed's
    damping ratio exactly 0. The eigen-solve leaves -1.9e-18 and -7e-33: shown as 0."""
    text = (ROOT / "examples" / "spring_block_rotor.toml").read_text(encoding="utf-8")
    assert "damping" not in re.sub(r"#.*", "", text)
    model = load_model(ROOT / "examples" / "spring_block_rotor.toml")
    data = report_collect.ReportData(ReportInputs("api684", 3000 * np.pi / 30, points=12), model,
                                     {"name": model.name}, ("campbell",))
    # the unbalance response (the margins' table) is not what is checked here: skipped for speed
    monkeypatch.setattr(report_collect, "_unbalance", lambda data: data.skipped.setdefault("unbalance", "skipped"))
    report_collect._campbell(data)
    raw = data.results["campbell"].critical.damping_ratios
    assert len(raw) >= 2 and np.any(raw != 0)              # the solve's round-off is there to clean
    cells = _column(render._campbell(data, "si"), "damping ratio [-]")
    assert len(cells) == len(raw) and set(cells) == {"0"}


def test_mode_shapes_of_a_window_without_lateral_modes_show_the_nearest_lateral_ones(no_figures):
    """compressor_rotor.toml at 9,000 rpm, operating 7,000 to 9,000 rpm: the window (5,880 to
    11,340 rpm) holds only an axial/torsional mode (185 Hz), whose shaft lines are flat. The
    section shows the lateral modes nearest it instead, below and above, and says so."""
    model = load_model(ROOT / "examples" / "compressor_rotor.toml")
    rpm = np.pi / 30
    data = report_collect.ReportData(ReportInputs("api684", 9000 * rpm, operating=(7000 * rpm, 9000 * rpm)), model,
                                     {"name": model.name}, ("modes",))
    report_collect._modes(data)
    shapes = data.results["modes"]
    low, high = shapes.window
    speeds = {n: 2 * np.pi * shapes.modal.frequencies_hz[shapes.modal.oscillatory][n - 1] for n in shapes.numbers}
    assert any(w < low for w in speeds.values()) and any(w > high for w in speeds.values())
    for line in shapes.lines:                              # each drawn mode moves the shaft sideways
        assert max(np.abs(rotor.displacement).max() for rotor in line.lines) == pytest.approx(1.0)
    html = render._modes(data, "si")
    assert "The window holds no lateral mode" in html and "shown instead" in html
    assert len(_column(html, "shown because")) == len(shapes.numbers)
