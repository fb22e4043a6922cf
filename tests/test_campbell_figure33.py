"""Campbell figures that cannot mislead (issue 27 §3; figc33).

compressor_rotor swept to 15,000 rpm (``campbell examples/compressor_rotor.toml --speeds
0:15000:151 --plot c.png``) left its critical speed at 14388 rpm unlabelled: the order line's
label '1X compressor' stood in the only room beside its circle (mode 5's line under it, modes 4
and 3 6.5 and 14 pixels below). The order labels are now placed again, kept off the room
straight above such a circle, where that labels more critical speeds and names every order line.

Measured on the drawn figure, from outside the placer (``test_campbell_figure._check_labels``:
every label inside, none over another, each on its own curve or marker, no curve through a
label), and: every critical speed in view is read by a label (no note of unlabelled ones); no
mode's curve runs between the order line's label and its line (straight from the label's edge
to the line, the line from the result's own multipliers: f = order x multiplier x rpm / 60).

:meth:`CurveMap.free_outlines` (many turned outlines at once, for the 60-rotor chain's order
labels) is checked against a direct test of every marked cell against each rectangle widened
by a cell (matplotlib's ``Path.contains_points``).
"""

from __future__ import annotations

import io
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

from label_geometry import curve_segments, segment_crossings  # noqa: E402
from test_campbell_figure import _check_labels, _labels  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def compressor_15k():
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    return model, rdm.campbell(model, rdm.rpm(np.linspace(0.0, 15000.0, 151)))


def _drawn(result, title, dpi):
    """The figure as the command line saves it (``savefig`` at ``dpi``), and its renderer."""
    fig = result.plot(title=title)
    fig.savefig(io.BytesIO(), format="png", dpi=dpi)
    fig.set_dpi(dpi)
    fig.canvas.draw()
    return fig, fig.canvas.get_renderer()


def _speed_words(speeds):
    return [f"{s:.0f}" if abs(s) >= 100 else f"{s:.3g}" for s in speeds]


@pytest.mark.parametrize("dpi", [150, 100])
def test_compressor_to_15000_rpm_labels_every_critical_speed(compressor_15k, dpi):
    import matplotlib.pyplot as plt

    model, result = compressor_15k
    fig, renderer = _drawn(result, model.name, dpi)
    ax = fig.axes[0]
    _check_labels(result, fig, ax, renderer)
    labels = _labels(ax)
    read = {w for kind, t in labels if kind == "critical" for w in t.get_text().split("/")}
    speeds = np.asarray(result.critical.speeds_rpm, float)
    in_view = speeds[(speeds >= ax.get_xlim()[0]) & (speeds <= ax.get_xlim()[1])]
    assert "14388" in _speed_words(in_view)
    assert set(_speed_words(in_view)) <= read, (sorted(read), _speed_words(in_view))
    assert not [t for kind, t in labels if kind == "note"]
    # the order line's label: shown, and no mode's curve between it and its own line
    orders = [t for kind, t in labels if kind == "order" and t.get_text().startswith("1X ")]
    assert [t.get_text() for t in orders] == ["1X compressor"]
    box = orders[0].get_window_extent(renderer)
    slope = float(result.sources.multipliers[0]) * float(result.orders[0]) / 60.0      # Hz per rpm
    leaders = [line for line in ax.get_lines() if (line.get_gid() or "").endswith("leader")
               or (line.get_gid() or "").startswith("mode-leader")]
    order_lines = [line for line in ax.get_lines() if line.get_gid() == "order-line"]
    modes = curve_segments(ax, skip=leaders + order_lines)
    # the line's point nearest the label (sampled every 0.1 rpm inside the axes) and the
    # label's point nearest that
    rpm = np.arange(*ax.get_xlim(), 0.1)
    line = ax.transData.transform(np.column_stack([rpm, slope * rpm]))
    frame = ax.get_window_extent(renderer)
    line = line[(line[:, 1] >= frame.y0) & (line[:, 1] <= frame.y1)]
    near = np.column_stack([np.clip(line[:, 0], box.x0, box.x1), np.clip(line[:, 1], box.y0, box.y1)])
    k = int(np.argmin(np.hypot(*(line - near).T)))
    assert not len(segment_crossings(near[k], line[k], modes)), (near[k], line[k])
    plt.close(fig)


def _reference_free(curves, rectangles):
    """Whether no marked cell's centre of ``curves`` (a CurveMap in pixels) in the rectangle's
    window (its bounding box and a cell around it) lies inside the rectangle widened by a cell
    on every side (the half-planes of its edges moved out by a cell)."""
    from matplotlib.path import Path as MplPath

    cell, (x0, y0) = curves.cell, curves.origin
    rows, columns = curves.grid.shape
    out = []
    for corners in rectangles:
        lo, hi = corners.min(axis=0) - cell, corners.max(axis=0) + cell
        i0, j0 = max(int(np.floor((lo[0] - x0) / cell)), 0), max(int(np.floor((lo[1] - y0) / cell)), 0)
        i1, j1 = min(int(np.ceil((hi[0] - x0) / cell)), columns), min(int(np.ceil((hi[1] - y0) / cell)), rows)
        j, i = np.nonzero(curves.grid[j0:j1, i0:i1])
        centres = np.column_stack([x0 + (i + i0 + 0.5) * cell, y0 + (j + j0 + 0.5) * cell])
        centre = corners.mean(axis=0)
        along = corners[1] - corners[0]
        across = corners[3] - corners[0]
        grown = centre + (corners - centre) + cell * (np.sign(np.array([-1, 1, 1, -1]))[:, None] * along / np.hypot(*along)
                                                      + np.sign(np.array([-1, -1, 1, 1]))[:, None] * across / np.hypot(*across))
        out.append(not len(centres) or not MplPath(grown).contains_points(centres).any())
    return np.array(out)


def test_free_outlines_match_each_outline_tested_alone():
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting._labels import CurveMap

    rng = np.random.default_rng(33)
    fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
    x = np.linspace(0, 10, 400)
    for k in range(8):
        ax.plot(x, np.sin(x * (0.3 + 0.2 * k)) * (1 + k) + 2 * k, linewidth=1 + k % 3)
    ax.plot(x, 0.8 * x, ":", linewidth=1.5)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    curves = CurveMap(ax, renderer)
    frame = ax.get_window_extent(renderer)
    rectangles = []
    for _ in range(400):
        w, h = rng.uniform(5, 80), rng.uniform(4, 14)
        angle = rng.uniform(-np.pi / 2, np.pi / 2)
        c, s = np.cos(angle), np.sin(angle)
        base = np.array([(0, 0), (w, 0), (w, h), (0, h)]) @ np.array([[c, s], [-s, c]])
        rectangles.append(base + [rng.uniform(frame.x0 - 20, frame.x1), rng.uniform(frame.y0 - 20, frame.y1)])
    rectangles = np.array(rectangles)
    got = curves.free_outlines(rectangles)
    expected = _reference_free(curves, rectangles)
    assert expected.any() and not expected.all()
    np.testing.assert_array_equal(got, expected)
    assert [curves.free_outline(r) for r in rectangles[:50]] == list(expected[:50])
    plt.close(fig)
