"""Campbell labels of large machines stay inside the figure (issue 27 §3, labels32).

The 20-rotor gear chain (``tests/test_large_machine_cli.py``'s ``chained_gear_toml(20, 20)``)
swept 0-4500 rpm at 22 speeds: its figure saved as a PNG at 100 dpi ran the shared right-edge
labels 'modes 15, 40, 85, 86', 'modes 24, 42, 73, 74' (and two more) off the figure's right
edge; the 10-rotor chain's 'modes 25, 37, 38' at 150 dpi. The words of a shared label depend on
the axes' height as laid out, which the figure's first layout had only guessed.

Measured on the figure as saved (``savefig`` at the resolution asked; the report's
``figure_png`` at 110 dpi), from outside the placer: every visible text of the axes and of the
legend lies inside the figure's box; no two texts' outlines overlap (turned texts by their
turned rectangles, ``label_geometry.outline``); each mode a right-edge label names has its
leader start where that mode's curve (the result's own frequencies) meets the right edge,
nearer to it than to any other curve's end.
"""

from __future__ import annotations

import io

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from label_geometry import named_modes, outline, outlines_overlap  # noqa: E402
from test_campbell_figure import _curve_ends, _pointed_height  # noqa: E402

SPEEDS_RPM = np.linspace(0.0, 4500.0, 22)


@pytest.fixture
def chains(chain_campbell):
    """``chains(rotors)``: the chain's sweep at :data:`SPEEDS_RPM`, swept once per worker
    (``conftest.chain_campbell``, which test_campbell_chain32 and test_campbell_labels32 share)."""
    return lambda rotors: chain_campbell(rotors, SPEEDS_RPM)


def _saved(result, dpi, report=False, then=None):
    """The figure of ``result`` saved as a PNG at ``dpi`` (``report``: as the report's page
    encodes it), and a renderer of its size at that resolution (nothing drawn again); ``then``
    [dpi]: after saving, drawn again at that resolution (shown on a screen), and measured so."""
    fig = result.plot()
    if then is not None:
        fig.savefig(io.BytesIO(), format="png", dpi=dpi)
        fig.set_dpi(then)
        fig.canvas.draw()
        return fig, fig.canvas.get_renderer()
    if report:
        from rotordyn_modal.report.render import figure_png

        figure_png(fig, dpi=dpi)
    else:
        fig.savefig(io.BytesIO(), format="png", dpi=dpi)
        import matplotlib.pyplot as plt

        plt.close(fig)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig.set_dpi(dpi)
    return fig, FigureCanvasAgg(fig).get_renderer()      # (a closed figure keeps no canvas of its own)


def _texts(fig):
    ax = fig.axes[0]
    legend = ax.get_legend()
    texts = list(ax.texts) + (list(legend.get_texts()) if legend is not None else [])
    return [t for t in texts if t.get_visible() and t.get_text()]


def _check(result, fig, renderer):
    ax = fig.axes[0]
    figure = fig.bbox
    texts = _texts(fig)
    named = [t for t in texts if t.get_gid() == "mode-label" and len(named_modes(t.get_text())) > 1]
    assert named, "the chain's figure has shared right-edge labels"
    for t in texts:
        box = t.get_window_extent(renderer)
        assert figure.x0 <= box.x0 and box.x1 <= figure.x1 and figure.y0 <= box.y0 and box.y1 <= figure.y1, \
            (t.get_text(), box.bounds, figure.bounds)
    outlines = [outline(t, renderer) for t in texts]
    for i, a in enumerate(outlines):
        for j in range(i + 1, len(outlines)):
            assert not outlines_overlap(a, outlines[j]), (texts[i].get_text(), texts[j].get_text())
    ends = _curve_ends(result, ax)
    for t in texts:
        if t.get_gid() != "mode-label" or t.get_window_extent(renderer).x0 < ax.get_window_extent(renderer).x1:
            continue                # a label inside the axes (its curve ends there)
        for label in named_modes(t.get_text()):
            height = _pointed_height(ax, t, renderer, label)
            nearest = min(abs(end - height) for end in ends.values())
            assert abs(ends[label] - height) < 0.5 and abs(ends[label] - height) == nearest, (t.get_text(), label)


@pytest.mark.parametrize("rotors, dpi", [(20, 100), (20, 200)])
def test_chain_labels_stay_inside_the_saved_figure(chains, rotors, dpi):
    result = chains(rotors)
    _check(result, *_saved(result, dpi))


def test_chain_labels_stay_inside_a_figure_drawn_again(chains):
    """Saved at 150 dpi, then drawn at 100 (the 10-rotor chain's 'modes 25, 37, 38' ran off)."""
    result = chains(10)
    _check(result, *_saved(result, 150, then=100))


def test_chain_labels_stay_inside_the_report_figure(chains):
    result = chains(20)
    _check(result, *_saved(result, 110, report=True))
