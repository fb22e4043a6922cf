"""Figures of the fifth audit (issue 27, section 3), measured on the drawn figure
(``fig.canvas.draw()``), independent of the code that places things.

Campbell diagrams of the geared examples at 0-12000 rpm with orders 1-4: the steep order lines
(the gear mesh's, the motor's 1X, the fan's 3X) had no label, because the label written along
a line was tested with the axis-aligned box around the turned text. Here each text's own
outline is rebuilt from the figure (its box as drawn, its angle and its unturned size: the
rectangle inscribed in the box) and every order line must be named: by a label inside the
axes whose centre is nearer one of the lines it names than any other order line, or by a key
above the axes joined by a leader line to the top exit of a line it names.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import curve_segments, outline, outlines_overlap

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

_ORDER_WORDS = r"(?P<orders>\d+(?:\.\d+)?X(?:, \d+(?:\.\d+)?X)*|\d+(?:\.\d+)?\u2013\d+(?:\.\d+)?X) (?P<source>.+)"


def _named_orders(words):
    """Orders a label's prefix names: '1X, 2X' -> [1, 2]; a range '2–4X' -> [2, 3, 4]."""
    if "\u2013" in words:
        first, last = (float(w) for w in words.rstrip("X").split("\u2013"))
        return list(np.arange(first, last + 0.5))
    return [float(w.rstrip("X")) for w in words.split(", ")]


def _curve_through(polygon, segments) -> bool:
    """Whether any of ``segments`` (n, 4) runs through the convex ``polygon`` shrunk by half a
    pixel (Cyrus-Beck: each segment clipped by the polygon's edges)."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    area = np.sum(polygon[:, 0] * np.roll(polygon[:, 1], -1) - np.roll(polygon[:, 0], -1) * polygon[:, 1])
    outward = np.sign(area) * np.column_stack([edges[:, 1], -edges[:, 0]])
    outward /= np.hypot(outward[:, 0], outward[:, 1])[:, None]
    limit = np.sum(polygon * outward, axis=1) - 0.5                  # (E,) inside: p . n < limit
    start, step = segments[:, :2], segments[:, 2:] - segments[:, :2]
    a, b = start @ outward.T - limit, step @ outward.T              # (S, E): a + t b < 0 inside
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -a / b
    low = np.max(np.where(b < 0, t, 0.0), axis=1, initial=0.0)
    high = np.min(np.where(b > 0, t, 1.0), axis=1, initial=1.0)
    parallel_out = np.any((b == 0) & (a >= 0), axis=1)
    return bool(np.any((low < high) & ~parallel_out))


def _order_lines(ax):
    """{slope [Hz per rpm]: (display segment from the origin to the far end inside the axes, line)}."""
    lines = {}
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if len(x) > 2 and x[0] == 0 and y[0] == 0 and y[-1] > 0 and np.allclose(y, y[-1] / x[-1] * x, rtol=1e-9):
            slope = y[-1] / x[-1]
            far = min(x1, y1 / slope)
            lines[round(slope, 9)] = (ax.transData.transform([(0.0, 0.0), (far, slope * far)]), line)
    return lines


def _distance(segment, point):
    a, b = segment
    t = np.clip(np.dot(point - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
    return float(np.hypot(*(a + t * (b - a) - point)))


@pytest.mark.parametrize("model", ["gear_machine.toml", "rubber_mounts.toml"])
def test_every_order_line_is_named_beside_itself(model):
    """gear_machine and rubber_mounts, 0-12000 rpm, orders 1-4 (12 order lines: the mesh's
    four within 1 % of the width, the motor's and the fan's steep lines between): every order
    line drawn is named. A label inside the axes lies inside them, no curve runs through its
    turned outline, and the order line nearest its centre is one it names; a key above the
    axes lies inside the figure, clear of the axes and the title, its leader line running
    from the key's bottom edge to the top exit of a line it names. No two texts of the axes
    (order, mode and critical-speed labels, keys) overlap, compared by their turned
    outlines."""
    import matplotlib.pyplot as plt

    result = rdm.campbell(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(0, 12000, 25)), orders=(1, 2, 3, 4))
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    frame = ax.get_window_extent(renderer)
    lines = _order_lines(ax)
    multiplier = dict(zip(result.sources.names, result.sources.multipliers))
    assert len(lines) == 4 * len(multiplier)
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    outlines = [outline(t, renderer) for t in texts]
    for i, a in enumerate(outlines):
        for j in range(i + 1, len(outlines)):
            assert not outlines_overlap(a, outlines[j]), (texts[i].get_text(), texts[j].get_text())
    segments = curve_segments(ax)
    leaders = [line for line in ax.get_lines() if line.get_visible() and len(line.get_xdata()) == 2]
    title = ax.title.get_window_extent(renderer)
    named = set()
    for text, corners in zip(texts, outlines):
        match = re.fullmatch(_ORDER_WORDS, text.get_text())
        if match is None or match["source"] not in multiplier:
            continue
        mine = {round(o * abs(multiplier[match["source"]]) / 60.0, 9) for o in _named_orders(match["orders"])}
        assert mine <= set(lines), text.get_text()
        if np.all((corners >= (frame.x0, frame.y0)) & (corners <= (frame.x1, frame.y1))):
            assert not _curve_through(corners, segments), text.get_text()
            centre = corners.mean(axis=0)
            nearest = min(lines, key=lambda s: _distance(lines[s][0], centre))
            assert nearest in mine, (text.get_text(), nearest, mine)
        else:                               # a key above the axes, joined to its line's exit
            box = text.get_window_extent(renderer)
            assert box.y0 > frame.y1 and fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 \
                and box.y1 <= fig.bbox.y1, text.get_text()
            assert not box.overlaps(title), text.get_text()
            ends = [line.get_transform().transform(np.column_stack(line.get_data())) for line in leaders]
            joined = [e for e in ends if any(abs(p[1] - box.y0) < 1.0 and box.x0 - 1 <= p[0] <= box.x1 + 1 for p in e)]
            assert joined, text.get_text()
            exits = {s: lines[s][0][1] for s in mine if abs(lines[s][0][1][1] - frame.y1) < 1.0}
            assert any(np.hypot(*(p - exit_)) < 1.0 for e in joined for p in e for exit_ in exits.values()), \
                text.get_text()
        named |= mine
    assert named == set(lines), sorted(set(lines) - named)
    plt.close(fig)
