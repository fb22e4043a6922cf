"""Campbell panels side by side (notebook 07's cell 5): each legend under its own axes.

Since the legend says "no whirl (|whirl ratio| <= 0.001)", its one row was about as wide as
a half-width panel: constrained layout narrowed both axes (about 545 -> 445 px) to make room,
and the two legends read as one row. Measured on the drawn figure (window extents), outside
the code that lays the legend out.
"""
import matplotlib
from pathlib import Path

import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import rotordyn_modal as rdm  # noqa: E402

MARGIN = 2.0          # [px]


@pytest.fixture(scope="module")
def results():
    examples = Path(__file__).resolve().parents[1] / "examples"
    speeds = rdm.rpm(np.linspace(0, 36000, 19))
    return {name: rdm.campbell(rdm.load_model(examples / f"{name}.toml"), speeds)
            for name in ("compressor_rotor", "fan_on_bearings")}


def _two_panels(results):
    """As notebook 07 draws them: 13 x 5 in, constrained layout, shared frequency axis."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), layout="constrained", sharey=True)
    for ax, (name, result) in zip(axes, results.items()):
        result.plot(ax=ax, title=name, freq_range=(0, 700))
        ax.axvline(10000.0, color="k", lw=0.8, ls=":")
    fig.canvas.draw()
    return fig, axes


def test_side_by_side_legends_lie_under_their_own_axes(results):
    fig, axes = _two_panels(results)
    renderer = fig.canvas.get_renderer()
    try:
        for ax in axes:
            box, legend = ax.get_window_extent(renderer), ax.get_legend().get_window_extent(renderer)
            assert box.x0 - MARGIN <= legend.x0 and legend.x1 <= box.x1 + MARGIN, (box, legend)
            assert legend.y1 <= box.y0, (box, legend)                       # under the axes
        assert axes[0].get_legend().get_window_extent(renderer).x1 \
            < axes[1].get_legend().get_window_extent(renderer).x0           # apart: two legends
        widths = [ax.get_window_extent(renderer).width for ax in axes]
        for ax in axes:
            ax.get_legend().remove()
        fig.canvas.draw()
        without = [ax.get_window_extent(renderer).width for ax in axes]
        for width, free in zip(widths, without):
            assert width >= 0.9 * free, (widths, without)
    finally:
        plt.close(fig)


def test_a_single_panel_keeps_its_legend_in_one_row(results):
    """A figure of its own (8 x 5.5 in) has room for the four entries in one row."""
    fig = results["compressor_rotor"].plot(freq_range=(0, 700))
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        ax = fig.axes[0]
        texts = ax.get_legend().get_texts()
        boxes = [t.get_window_extent(renderer) for t in texts]
        centres = [(b.y0 + b.y1) / 2 for b in boxes]
        assert len(texts) >= 3, [t.get_text() for t in texts]
        assert max(centres) - min(centres) < min(b.height for b in boxes) / 2, centres    # one row
        box, legend = ax.get_window_extent(renderer), ax.get_legend().get_window_extent(renderer)
        assert box.x0 - MARGIN <= legend.x0 and legend.x1 <= box.x1 + MARGIN
    finally:
        plt.close(fig)
