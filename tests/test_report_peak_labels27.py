"""The report's unbalance figure labels every peak it chooses (issue 27, section 3: "figures
that cannot mislead"). ``report examples/motor_pump_on_mounts.toml --standard api684 --mcs
3000``: the casing sensors' panel chose six peaks between 262 and 726 rpm and labelled one, the
tall 327 rpm label's leader taking the room above the cluster, while the peaks table lists all.

Checked on the drawn figure (label geometry as tests/test_campbell_figure.py checks it): each
chosen peak (``_marked_peaks``, the figure's own choice, recorded as it is passed on) has one
label reading its speed and AF, anchored at the peak; the labels lie inside the axes, apart
from each other, no curve running through a label's glyphs (but near its own peak).
"""

from __future__ import annotations

import dataclasses
import importlib
import re
from pathlib import Path

import matplotlib
import numpy as np

import rotordyn_modal as rdm
from label_geometry import crossings, curve_segments, glyph_box

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _figure_and_choices(monkeypatch):
    from rotordyn_modal.plotting import frf
    from rotordyn_modal.report import ReportInputs, collect, render

    collect_module = importlib.import_module("rotordyn_modal.report.collect")
    monkeypatch.setitem(collect_module.STANDARDS, "api684", ("campbell", "unbalance"))
    chosen = {}
    original = frf._marked_peaks

    def recorded(peaks, result, rows, *args, **kwargs):
        found = original(peaks, result, rows, *args, **kwargs)
        chosen[tuple(result.outputs[i] for i in rows)] = found
        return found

    monkeypatch.setattr(frf, "_marked_peaks", recorded)
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    data = collect(model, ReportInputs("api684", rdm.rpm(3000.0), points=61))
    figures = []
    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: figures.append(fig) or "data:image/png;base64,")
    render.render_html(dataclasses.replace(data, sections=("unbalance",)))
    assert len(figures) == 1
    return figures[0], chosen


def test_every_chosen_peak_is_labelled_apart_and_clear_of_the_curves(monkeypatch):
    fig, chosen = _figure_and_choices(monkeypatch)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        casing, = [ax for ax in fig.axes if "casing" in ax.get_title()]
        rows, = [key for key in chosen if "acc-pump-z" in key]
        peaks = chosen[rows]
        assert len(peaks) == 6                           # the six chosen, 262-726 rpm
        labels = [t for t in casing.texts if t.get_visible() and t.get_text().startswith("AF ")]
        for x, y, text, _, _ in peaks:
            mine = [t for t in labels if t.get_text() == text]
            assert len(mine) == 1, f"not labelled: {text.splitlines()[0]}"
            assert np.allclose(mine[0].xy, (x, y))
            speed = float(re.match(r"AF [\d.]+ at (\d+) rpm", text)[1])
            assert abs(speed - x) <= 0.5
        boxes = [glyph_box(t, renderer) for t in labels]
        frame = casing.get_window_extent(renderer)
        segments = curve_segments(casing)
        radius = 12.0 * fig.dpi / 72.0
        for text, box in zip(labels, boxes):
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            anchor = casing.transData.transform(text.xy)
            assert not len(crossings(box, segments, [anchor], radius)), text.get_text()
        for i, a in enumerate(boxes):
            assert not any(a.overlaps(b) for b in boxes[i + 1:])
    finally:
        matplotlib.pyplot.close(fig)
