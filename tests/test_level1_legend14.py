"""The API 617 Level I figure's legend hides none of the lines it names (issue 27, section 3: "no
hidden crossing"). ``level1 compressor_on_journals.toml --mcs 12000 --station compressor ...``
placed the legend 'best' inside the axes, over the log decrement criterion (0.1) and the zero
line. Checked on the drawn figure: the legend's box meets no line drawn in the axes.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_the_legend_covers_no_line():
    from rotordyn_modal.analysis.level1 import level1

    model = rdm.load_model(EXAMPLES / "compressor_on_journals.toml")
    result = level1(model, rdm.rpm(12000.0), ["compressor"], qa=3.183e6)
    fig = result.plot()
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()] + list(fig.legends)
        assert legends
        for legend in legends:
            box = legend.get_window_extent(renderer)
            for ax in fig.axes:
                frame = ax.get_window_extent(renderer)
                for line in ax.get_lines():
                    xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
                    xy = xy[np.all(np.isfinite(xy), axis=1)]
                    if len(xy) == 1:
                        inside = box.contains(*xy[0])
                    else:           # sample each segment finely, within the axes
                        t = np.linspace(0.0, 1.0, 200)[:, None]
                        points = np.concatenate([a + t * (b - a) for a, b in zip(xy[:-1], xy[1:])])
                        points = points[(points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1)
                                        & (points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1)]
                        inside = np.any((points[:, 0] > box.x0) & (points[:, 0] < box.x1)
                                        & (points[:, 1] > box.y0) & (points[:, 1] < box.y1))
                    assert not inside, line.get_label()
    finally:
        plt.close(fig)
