"""Small defects of the rendered report (issue 29, section 7; seen by report33 in chromium).

- the ISO summary limit wrote 2.8 mm/s as '0.11 in/s' where the checks table wrote 0.1102;
- a model without gravity drew a full-page figure of zero shaft loads;
- fan_on_bearings, ``--standard iso --units us``: the unbalance figure's key of numbered peaks
  ran under the 'AF 31.2 at 4157 rpm' label once the report laid the figure out at 110 dpi;
- spring_block_rotor: its undamped (AF inf) resonance had no label on the unbalance figure;
- a 16-coordinate machine's mode-share bar labels were shrunk to about 8 px on the page.

Geometry is measured on the figures as the report saves them (``figure_png``: laid out at its
resolution), text boxes without their leader arrows.
"""

from __future__ import annotations

import dataclasses
import importlib
import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

#: the report saves its figures at 110 dpi (figure_png) on a page at most 1100 px wide (its style)
DPI = 110
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
collect_module = importlib.import_module("rotordyn_modal.report.collect")
render = importlib.import_module("rotordyn_modal.report.render")


def _rendered(name, inputs, sections, units):
    """``(html, figures)`` of the report of ``examples/<name>.toml`` restricted to ``sections``;
    the figures kept (laid out and saved as the report saves them) for measuring."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figures = []
    original = render.figure_png

    def kept(fig, dpi=DPI):
        figures.append(fig)
        uri = original(fig, dpi)
        FigureCanvasAgg(fig)                 # closed by figure_png: a canvas to measure it on
        fig.set_dpi(dpi)
        fig.canvas.draw()
        return uri

    with pytest.MonkeyPatch.context() as mp:
        mp.setitem(collect_module.STANDARDS, inputs.standard, sections)
        mp.setattr(render, "figure_png", kept)
        data = collect_module.collect(rdm.load_model(EXAMPLES / f"{name}.toml"), inputs)
        html = render.render_html(dataclasses.replace(data, sections=sections), units=units)
    return html, data, figures


@pytest.fixture(scope="module")
def fan_iso_us():
    inputs = collect_module.ReportInputs("iso", rdm.rpm(3000.0), iso_group=2, iso_support="rigid")
    return _rendered("fan_on_bearings", inputs, ("campbell", "modes", "unbalance", "iso"), "us")


def _figure(figures, title):
    found = [f for f in figures if f._suptitle is not None and f._suptitle.get_text().startswith(title)]
    assert len(found) == 1, [f._suptitle.get_text() if f._suptitle else None for f in figures]
    return found[0]


def _text_boxes(ax):
    """``[(text, (x0, y0, x1, y1))]`` of the visible texts of ``ax`` in pixels, arrows left out."""
    from matplotlib.text import Text

    renderer = ax.figure.canvas.get_renderer()
    return [(t.get_text(), tuple(Text.get_window_extent(t, renderer).extents)) for t in ax.texts
            if t.get_visible() and t.get_text()]


def _apart(a, b) -> bool:
    return a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]


def test_iso_limit_has_one_format_in_the_summary_the_sentence_and_the_table(fan_iso_us):
    """ISO 20816-3 group 2 on rigid supports: zone B/C at 2.8 mm/s RMS, 2.8 / 25.4 in/s (exact
    inch); the summary wrote '<= 0.11 in/s' beside the table's 0.1102."""
    html = fan_iso_us[0]
    limit = f"{2.8 / 25.4:.4g}"
    assert limit == "0.1102"
    summary = re.search(r"ISO 20816-3 zone.*?</tr>", html, re.S).group(0)
    assert f"&lt;= {limit} in/s RMS (zone B)" in summary, summary
    section = html[html.index('<h2 id="iso">'):]
    assert f"B/C {limit}," in section
    cells = re.findall(r"<td[^>]*>([^<]*)</td>", section)
    assert limit in cells and "0.11" not in cells


def test_a_shaft_without_static_load_gets_a_sentence_not_a_figure():
    """examples/compressor_rotor.toml gives no gravity and no torque: nothing loads its shaft, and
    the report drew a page of zero curves. flexible_pump_on_mounts (gravity) keeps its figure."""
    for name, loaded in (("compressor_rotor", False), ("flexible_pump_on_mounts", True)):
        model = rdm.load_model(EXAMPLES / f"{name}.toml")
        assert bool(np.any(np.asarray(model.gravity, dtype=float))) == loaded
        data = collect_module.ReportData(collect_module.ReportInputs("api684", rdm.rpm(3000.0)), model, {},
                                         ("static",))
        collect_module._static(data)
        html = render._static(data, "si")
        shafts = html[html.index("Flexible shafts"):]
        assert ("<img" in shafts) == loaded
        assert ("No static load acts on the flexible shafts" in shafts) == (not loaded)


def test_the_numbered_peaks_key_is_clear_of_every_peak_label(fan_iso_us):
    """Every text of each amplitude panel (peak labels, their numbers, the key's lines) apart from
    every other, as the report saves the figure: the key's '(API 26 %)' ran 2 px under 'AF 31.2
    at 4157 rpm (1X fan)'."""
    fig = _figure(fan_iso_us[2], "Unbalance response")
    panels = [ax for ax in fig.axes if ax.get_ylabel().startswith("Amplitude")]
    assert panels
    keys = 0
    for ax in panels:
        boxes = _text_boxes(ax)
        keys += sum(t.get_gid() == "peak-key" for t in ax.texts)
        clashes = [(a, b) for i, (a, ba) in enumerate(boxes) for b, bb in boxes[i + 1:] if not _apart(ba, bb)]
        assert not clashes, clashes
    assert keys >= 3                              # the probes' panel numbers three peaks


def test_an_undamped_resonance_is_labelled_where_the_analysis_puts_it():
    """examples/spring_block_rotor.toml has no damping (every critical speed's damping ratio 0):
    its resonance is unbounded, AF inf. The figure labelled no peak; its label now reads
    'AF inf' at the speed of the analysis' peaks table (the plot computes none)."""
    inputs = collect_module.ReportInputs("api684", rdm.rpm(3000.0))
    html, data, figures = _rendered("spring_block_rotor", inputs, ("campbell", "unbalance"), "si")
    critical = data.results["campbell"].critical
    assert np.all(np.abs(critical.damping_ratios) < 1e-12)
    peaks = data.results["peaks"]
    assert np.isinf(peaks["amplification_factor"]).all()
    fig = _figure(figures, "Unbalance response")
    labels = [t for ax in fig.axes for t in ax.texts if t.get_text().startswith("AF inf")]
    assert len(labels) == 1
    speed = float(peaks["speed_rpm"].iloc[0])
    assert labels[0].xy[0] == pytest.approx(speed, rel=1e-12)
    assert f"at {speed:.0f} rpm" in labels[0].get_text()          # unbounded: at its exact critical speed (unb35)


def test_mode_bar_labels_of_a_16_coordinate_machine_are_readable_on_the_page(fan_iso_us):
    """The page shows a figure at most 1100 px wide (the body's max-width, the style sheet); a
    wider PNG is shrunk. fan_on_bearings has 16 coordinates: two panels a row made the figure
    13.2 in (1452 px at 110 dpi) and its x-small bar labels 9.6 px. At least 11 px (0.7 of the
    page's 16 px text) on the page."""
    html, data, figures = fan_iso_us
    assert len(data.results["modes"].modal.dof_names) == 16
    assert "max-width: 1100px" in html
    fig = _figure(figures, "Mode shapes")
    width_px = fig.get_figwidth() * DPI
    shrink = min(1.0, 1100 / width_px)
    sizes = [label.get_fontsize() for ax in fig.axes if ax.get_visible() for label in ax.get_xticklabels()
             if label.get_text()]
    assert sizes
    assert min(sizes) * DPI / 72 * shrink >= 11.0
