"""The report of every example opens in a real browser (headless Chromium, when installed): every
figure drawn and decoded, nothing wider than the window, not a blank page (the checks of
``tests/test_report.py::test_a_real_browser_renders_the_report_with_every_image``, which renders
the journal rotor's API 617 report; here every other example with the standard its file or
docs/report.md documents for it).

Speed: one report per example, built by a module-scoped fixture parametrized by example, so that
pytest-xdist spreads the examples over its workers and each worker builds only its own. The
reports are made cheap with the options that exist for it, not a test-only switch: ``--points 15``
(speeds of the Campbell and unbalance sweeps, default 151) and ``--stiffness 1e5:1e10:9`` (the
undamped critical speed map's stiffness grid, default 41 points; widened as by default where a
bearing's stiffness lies outside). The figures are drawn in full (PNG at the report's dpi)."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_report import _BROWSER, NO_BROWSER, assert_a_real_browser_renders

from rotordyn_modal.cli import main

ROOT = Path(__file__).resolve().parent.parent
#: the options that make a report cheap (see the module's docstring)
CHEAP = ["--points", "15", "--stiffness", "1e5:1e10:9"]
_ISO = ["--iso-group", "2", "--iso-support", "flexible"]

#: example -> (standard, options): the command its comment lines document where they do
#: (compressor_on_journals, compressor_rotor), else the standard of its kind of machine (API for a
#: rotor on bearings or probes, ISO zones for a casing on mounts with casing sensors); the journal
#: rotor is rendered by tests/test_report.py
EXAMPLES = {
    "compressor_on_journals": ("api684", ["--mcs", "6600", "--operating-range", "6000:6600"]),
    "compressor_rotor": ("api684", ["--mcs", "9000", "--operating-range", "7000:9000"]),
    "counter_rotating": ("api617", ["--mcs", "3000"]),
    "fan_on_bearings": ("api684", ["--mcs", "3000"]),
    "flexible_pump_on_mounts": ("iso", ["--mcs", "3000", *_ISO]),
    "gear_machine": ("iso", ["--mcs", "3700", "--operating-range", "3400:3700", *_ISO]),
    "motor_fan_minimal": ("iso", ["--mcs", "3000", *_ISO]),
    "motor_pump_on_mounts": ("iso", ["--mcs", "3000", *_ISO]),
    "rubber_mounts": ("iso", ["--mcs", "3700", "--operating-range", "3400:3700", *_ISO]),
    "spring_block_rotor": ("api684", ["--mcs", "3000"]),
    "spring_block_rotor_suspension": ("api684", ["--mcs", "3000"]),
    "unstable_cross_coupled": ("api617", ["--mcs", "9000"]),       # no bearings: no Level I station
}


def test_every_example_is_rendered_by_a_browser_check():
    """No example is forgotten: each model file of examples/ is here or in tests/test_report.py."""
    from test_report import DRAWN

    models = {p.stem for p in (ROOT / "examples").glob("*.toml") if not p.stem.endswith(".study")}
    assert models == set(EXAMPLES) | {DRAWN}


@pytest.fixture(scope="module", params=list(EXAMPLES))
def report(request, tmp_path_factory):
    """(example, its report's HTML file), built once per example."""
    name = request.param
    standard, options = EXAMPLES[name]
    out = tmp_path_factory.mktemp(name) / "report.html"
    cheap = CHEAP if standard != "iso" else CHEAP[:2]       # the ISO report has no UCS map: no --stiffness
    assert main(["report", str(ROOT / "examples" / f"{name}.toml"), "--standard", standard, *options, *cheap,
                 "--out", str(out), "--quiet"]) == 0
    return name, out


@pytest.mark.skipif(_BROWSER is None, reason=NO_BROWSER)
def test_a_real_browser_renders_every_example_report(report):
    name, out = report
    assert f"{name}.toml" in out.read_text(encoding="utf-8")
    assert_a_real_browser_renders(out)


def test_figure_png_lays_a_figure_out_once_and_draws_the_same_png():
    """``report.render.figure_png`` lays a constrained-layout figure out once (the cost of a
    report is mostly its figures' layout): the PNG is byte for byte the one ``savefig`` writes
    laying it out twice, on a figure with what the report's figures hold (panels sharing an axis,
    a suptitle, a legend outside the axes, a colorbar, log axes, annotations)."""
    import base64
    import io

    import matplotlib.pyplot as plt
    import numpy as np

    from rotordyn_modal.report.render import figure_png

    def figure():
        fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8, 5), layout="constrained")
        x = np.logspace(5, 10, 41)
        for k in range(4):
            top.loglog(x, np.sqrt(x) * (k + 1), label=f"mode {k + 1} forward critical speed")
        top.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
        top.annotate("AF 8.6 at 3553 rpm (1X fan)", (1e7, 1e4), xytext=(1e6, 1e5), arrowprops={"arrowstyle": "->"})
        image = bottom.pcolormesh(np.outer(np.arange(5), np.arange(41)))
        fig.colorbar(image, ax=bottom, label="amplitude, peak-to-peak [µm]")
        bottom.set_xlabel("bearing stiffness [N/m]")
        fig.suptitle("Undamped critical speed map")
        return fig

    twice = io.BytesIO()
    fig = figure()
    fig.savefig(twice, format="png", dpi=110)
    plt.close(fig)
    once = base64.b64decode(figure_png(figure(), dpi=110).split(",", 1)[1])
    assert once == twice.getvalue()
