"""The 60-rotor Campbell figure reads well (issue 27 §3, large machines; chain32).

The 60-rotor gear chain (``tests/test_large_machine_cli.py``'s ``chained_gear_toml(60, 60)``,
0-4500 rpm at 22 speeds, 246 modes, 16864 critical speeds) drew right-edge labels naming up to
22 modes each ('modes 16, 35, 49, 60, 81, 106, 108, 225–238', 258 pixels at 110 dpi), which
squeezed the axes to 43 % of the figure's width; at 110 dpi the legend's entry of the critical
speeds took the note's count after the layout had fixed the legend's columns, and its first
entry began 208 pixels left of the figure. The 40-rotor chain's axes kept 60 %.

Measured on the figure as saved (``savefig``, or the report's ``figure_png``), from outside the
placer: every visible text of the axes, of the legend and the title lies inside the figure; no
two texts' outlines overlap (``label_geometry.outline``), and the title keeps a word's space
(4 points, a space of its 12-point font) from the keys of the order lines beside it; the axes
keep at least 60 % of the figure's width; a right-edge label writes at most 5 mode numbers
(the issue's 'compact form when long'), and says how many modes it names: that many leaders end
at it, among them those of the numbers it writes, each starting where its own mode's curve (the
result's frequencies) meets the right edge, nearer to it than to any other curve's end.
"""

from __future__ import annotations

import re

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from label_geometry import counted_modes, named_modes, outline, outlines_overlap  # noqa: E402
from test_campbell_figure import _curve_ends  # noqa: E402
from test_campbell_labels32 import _texts  # noqa: E402

SPEEDS_RPM = np.linspace(0.0, 4500.0, 22)
#: the axes' share of the figure's width at least
AXES_SHARE = 0.6
#: mode numbers a right-edge label writes at most
MOST_NUMBERS = 5
#: the title's distance from a key of the order lines beside it at least [points]
TITLE_GAP_POINTS = 4.0


@pytest.fixture
def chains(chain_campbell):
    """``chains(rotors)``: the chain's sweep at :data:`SPEEDS_RPM`, swept once per worker
    (``conftest.chain_campbell``, which test_campbell_chain32 and test_campbell_labels32 share)."""
    return lambda rotors: chain_campbell(rotors, SPEEDS_RPM)


def _saved(result, dpi, report=False, **options):
    """The figure ``result.plot(**options)`` saved as a PNG at ``dpi`` (``report``: as the
    report's page encodes it, ``figure_png``), and a renderer of its size at that resolution
    (nothing drawn again)."""
    import io

    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = result.plot(**options)
    if report:
        from rotordyn_modal.report.render import figure_png

        figure_png(fig, dpi=dpi)
    else:
        fig.savefig(io.BytesIO(), format="png", dpi=dpi)
        plt.close(fig)
    fig.set_dpi(dpi)
    return fig, FigureCanvasAgg(fig).get_renderer()      # (a closed figure keeps no canvas of its own)


def _leaders_at(fig, renderer, label):
    """{mode: leader line} of the visible mode leaders whose drawn end lies at ``label``'s left
    edge (within 3 points), within its height."""
    box = label.get_window_extent(renderer)
    out = {}
    for line in fig.axes[0].get_lines():
        gid = line.get_gid() or ""
        if not gid.startswith("mode-leader ") or not line.get_visible():
            continue
        end = line.get_transform().transform((line.get_xdata()[-1], line.get_ydata()[-1]))
        if box.y0 <= end[1] <= box.y1 and box.x0 - 3 * fig.dpi / 72 <= end[0] <= box.x0:
            out[int(gid.split()[1])] = line
    return out


def _check(result, fig, renderer, share=AXES_SHARE):
    ax = fig.axes[0]
    figure, frame = fig.bbox, ax.get_window_extent(renderer)
    texts = _texts(fig) + [ax.title]
    for t in texts:
        box = t.get_window_extent(renderer)
        assert figure.x0 <= box.x0 and box.x1 <= figure.x1 and figure.y0 <= box.y0 and box.y1 <= figure.y1, \
            (t.get_text(), box.bounds, figure.bounds)
    outlines = [outline(t, renderer) for t in texts]
    for i, a in enumerate(outlines):
        for j in range(i + 1, len(outlines)):
            assert not outlines_overlap(a, outlines[j]), (texts[i].get_text(), texts[j].get_text())
    title = ax.title.get_window_extent(renderer)
    for key in [t for t in texts if t.get_gid() == "order-key"]:
        box = key.get_window_extent(renderer)
        if box.y0 < title.y1 and title.y0 < box.y1:
            assert max(box.x0 - title.x1, title.x0 - box.x1) >= TITLE_GAP_POINTS * fig.dpi / 72, key.get_text()
    if share is not None:
        assert frame.width >= share * figure.width, (frame.width, figure.width)
    ends = _curve_ends(result, ax)
    beside = [t for t in texts if t.get_gid() == "mode-label" and t.get_window_extent(renderer).x0 >= frame.x1]
    assert any(counted_modes(t.get_text()) > MOST_NUMBERS for t in beside), "the chain has long shared labels"
    for t in beside:
        words = t.get_text()
        written = re.findall(r"\d+", words.partition(":")[2] or words)
        assert len(written) <= MOST_NUMBERS, words
        leaders = _leaders_at(fig, renderer, t)
        assert len(leaders) == counted_modes(words) and set(named_modes(words)) <= set(leaders), \
            (words, sorted(leaders))
        for mode, line in leaders.items():
            height = line.get_transform().transform((line.get_xdata()[0], line.get_ydata()[0]))[1]
            nearest = min(abs(end - height) for end in ends.values())
            assert abs(ends[mode] - height) < 0.5 and abs(ends[mode] - height) == nearest, (words, mode)


def test_chain60_figures_read_well(chains):
    """The report's figure (``figure_png`` at 110 dpi) and the command line's (``savefig`` at 150
    dpi), with the model's name as title; and on a smaller figure (6 x 4.5 inches, constrained
    layout) at 110 dpi, where the count of the critical speeds labelled finds no room inside the
    axes and goes into the legend's entry: the legend is laid out with it, inside the figure (the
    axes' share of a figure this small is not checked: the tick labels and the right-edge labels
    keep their size). One test, so that one worker sweeps the chain."""
    import matplotlib.pyplot as plt

    result = chains(60)
    for dpi, report in ((110, True), (150, False)):
        _check(result, *_saved(result, dpi, report=report, title="60 rotors chained by gears"))
    ax = plt.figure(figsize=(6, 4.5), layout="constrained").add_subplot()
    fig, renderer = _saved(result, 110, ax=ax)
    entry = [t for t in fig.axes[0].get_legend().get_texts() if t.get_text().startswith("critical speed")]
    assert entry and re.match(r"critical speed \(0 of \d+ labelled", entry[0].get_text()), entry
    _check(result, fig, renderer, share=None)


def test_chain40_figures_read_well(chains):
    """``plot()`` saved at 100, 110, 150 and 200 dpi (at 110 as the report saves it)."""
    result = chains(40)
    for dpi in (100, 110, 150, 200):
        _check(result, *_saved(result, dpi, report=dpi == 110))
