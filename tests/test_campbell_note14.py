"""The Campbell figure's critical-speed note stands off the axes' spines (issue 27, section 3:
no text touching a frame). On the flexible pump's Campbell (``campbell
flexible_pump_on_mounts.toml --speeds 0:3600:37 --orders 1,2``) the note listing the critical
speeds left unlabelled sat 1 pt from the left spine, read as touching it.

Checked on the drawn text's bounding box against the axes' frame.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("scale", ["auto", "log", "linear"])
def test_the_critical_note_stands_off_the_spines(scale):
    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3600.0, 37)), orders=(1, 2))
    fig = result.plot(title=model.name or None, freq_scale=scale)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        notes = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_gid() == "critical-note" and t.get_visible()]
        assert notes, "the example leaves critical speeds unlabelled: its note is drawn"
        for ax, note in notes:
            box, frame = note.get_window_extent(renderer), ax.get_window_extent(renderer)
            gaps = np.array([box.x0 - frame.x0, box.y0 - frame.y0, frame.x1 - box.x1, frame.y1 - box.y1])
            assert np.all(gaps * 72.0 / fig.dpi >= 3.0), gaps * 72.0 / fig.dpi
    finally:
        plt.close(fig)
