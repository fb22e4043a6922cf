"""The UCS map's operating range of zero width: one rated speed (issue 29 section 2,
docs/report.md). ``--operating-range 3000:3000`` and a report's default range (the MCS alone)
drew a band of zero height, which shows nothing; the speed is now a dashed line, named in the
legend and beside it, and the command line takes LO = HI."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.ucs_map import ucs_map
from rotordyn_modal.cli import main

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
STIFFNESS = np.geomspace(1e5, 1e10, 11)


def _model():
    return rdm.load_model(EXAMPLES / "journal_rotor.toml")


def _operating_lines(ax):
    """The horizontal lines of ``ax`` labelled as an operating speed: (speed [rpm], label)."""
    found = []
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), dtype=float)
        if line.get_label().startswith("operating speed") and y.size and np.all(y == y[0]):
            found.append((float(y[0]), line.get_label()))
    return found


def _bands(ax):
    return [p for p in ax.patches if p.get_label() == "operating range"]


def _legend_texts(ax):
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def test_one_operating_speed_is_a_labelled_line_on_the_map():
    import matplotlib.pyplot as plt

    speed = rdm.rpm(3000.0)
    fig = ucs_map(_model(), STIFFNESS, modes=2, operating=(speed, speed)).plot()
    ax = fig.axes[0]
    lines = _operating_lines(ax)
    assert len(lines) == 1 and lines[0][0] == pytest.approx(3000.0, rel=1e-12)
    assert lines[0][1] == "operating speed 3000 rpm" and "operating speed 3000 rpm" in _legend_texts(ax)
    assert ax.get_ylim()[0] < 3000.0 < ax.get_ylim()[1]
    assert any(t.get_text() == "operating speed 3000 rpm" for t in ax.texts)      # beside the line
    assert not _bands(ax)
    plt.close(fig)


def test_a_range_is_still_a_band_and_no_line():
    import matplotlib.pyplot as plt

    fig = ucs_map(_model(), STIFFNESS, modes=2, operating=(rdm.rpm(1000.0), rdm.rpm(3000.0))).plot()
    ax = fig.axes[0]
    bands = _bands(ax)
    assert len(bands) == 1 and not _operating_lines(ax)
    heights = bands[0].get_path().transformed(bands[0].get_patch_transform()).vertices[:, 1]   # data units [rpm]
    assert heights.min() == pytest.approx(1000.0, rel=1e-12) and heights.max() == pytest.approx(3000.0, rel=1e-12)
    plt.close(fig)


def test_a_reversed_or_negative_operating_range_is_refused_in_python():
    model = _model()
    for operating in ((rdm.rpm(3000.0), rdm.rpm(2000.0)), (-1.0, 10.0), (1.0, 2.0, 3.0), (np.nan, 1.0), (0.0, 0.0)):
        with pytest.raises(rdm.InputError, match="operating = "):
            ucs_map(model, STIFFNESS, modes=2, operating=operating)


def test_command_line_takes_one_rated_speed(tmp_path, capsys):
    plot = tmp_path / "ucs.png"
    base = ["ucs-map", str(EXAMPLES / "journal_rotor.toml"), "--stiffness", "1e5:1e10:11", "--lowest", "2"]
    assert main(base + ["--operating-range", "3000:3000", "--plot", str(plot)]) == 0
    assert plot.stat().st_size > 0
    capsys.readouterr()
    assert main(base + ["--operating-range", "3000:2000"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--operating-range '3000:2000': expected 0 <= LO <= HI [rpm]" in err[0]
    assert main(base + ["--operating-range", "0:0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--operating-range '0:0': expected HI > 0 [rpm]" in err[0]


@pytest.mark.parametrize("operating, drawn", [(None, "the operating speed (3000 rpm) as a dashed line"),
                                              ((2000.0, 3000.0), "the operating range as a band")])
def test_report_draws_its_single_operating_speed(operating, drawn, monkeypatch):
    """The report's UCS section: the default range (the MCS alone) is a line, and the caption and
    the model table say so."""
    import importlib

    from rotordyn_modal.report import render

    collect_module = importlib.import_module("rotordyn_modal.report.collect")   # the package's collect is a function

    model = _model()
    inputs = collect_module.ReportInputs(
        standard="api684", mcs=rdm.rpm(3000.0), stiffness=STIFFNESS,
        operating=None if operating is None else tuple(rdm.rpm(np.array(operating))))
    data = collect_module.ReportData(inputs, model, collect_module.model_summary(model), ("ucs",))
    collect_module._ucs(data)
    figures = []
    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: figures.append(fig) or "data:image/png;base64,")
    html = render._ucs(data, "si")
    assert drawn in html
    lines = _operating_lines(figures[0].axes[0])
    assert (lines == [(pytest.approx(3000.0, rel=1e-12), "operating speed 3000 rpm")]) if operating is None \
        else (not lines and _bands(figures[0].axes[0]))
    table = render._model(data, "si")
    assert ("3000 (one speed)" in table) == (operating is None)
