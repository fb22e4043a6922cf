"""The report's unbalance figure labels every peak it chooses (issue 27, section 3: "figures
that cannot mislead"). ``report examples/motor_pump_on_mounts.toml --standard api684 --mcs
3000``: the casing sensors' panel chose six peaks between 262 and 726 rpm and labelled one, the
tall 327 rpm label's leader taking the room above the cluster, while the peaks table lists all.

Checked on the drawn figure (label geometry as tests/test_campbell_figure.py checks it): each
chosen peak (``_marked_peaks``, the figure's own choice, recorded as it is passed on) is read
in the panel: its label at the peak, or a number at the peak and the key's line of it, or
(no room for even a number) the key's line saying so; at least five of the six are marked at
their peak. The labels, numbers and key lines lie inside the axes, apart from each other, no
curve running through their glyphs (but near a label's own peak).
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
        notes = [t for t in casing.texts if t.get_visible() and hasattr(t, "xy")]       # at a peak
        key = [t for t in casing.texts if t.get_visible() and t.get_gid() == "peak-key"]
        marked = 0
        for x, y, text, _, _ in peaks:
            speed = float(re.match(r"AF [\d.]+ at (\d+) rpm", text)[1])
            assert abs(speed - x) <= 0.5
            at_peak = [t for t in notes if np.allclose(t.xy, (x, y))]
            assert len(at_peak) <= 1
            line = text.replace("\n", ", ")
            if at_peak and at_peak[0].get_text() == text:
                marked += 1                              # the label itself
            elif at_peak:                                # a number, and the key's line of it
                assert [t for t in key if t.get_text() == f"{at_peak[0].get_text()}: {line}"], text
                marked += 1
            else:                                        # read in the key, named as not marked
                assert [t for t in key if t.get_text().endswith(line) and "no room" in t.get_text()], text
        assert marked >= 5                               # 1 on main
        boxes = [glyph_box(t, renderer) for t in notes + key]
        frame = casing.get_window_extent(renderer)
        segments = curve_segments(casing)
        radius = 12.0 * fig.dpi / 72.0
        for text, box in zip(notes + key, boxes):
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            anchors = [casing.transData.transform(text.xy)] if hasattr(text, "xy") else []
            assert not len(crossings(box, segments, anchors, radius)), text.get_text()
        for i, a in enumerate(boxes):
            assert not any(a.overlaps(b) for b in boxes[i + 1:])
    finally:
        matplotlib.pyplot.close(fig)
