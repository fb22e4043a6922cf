"""The one placer of point labels (``plotting._labels``): a crowd of labels at one point is
spread around it, every box inside the axes and apart, each label joined to its own point.

Measured on the drawn figure (``Text.get_window_extent`` of the glyphs), as
``test_campbell_figure.py`` does.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from rotordyn_modal.plotting._labels import first_free_box, place_point_labels

matplotlib.use("Agg")


def _glyph_boxes(texts, renderer):
    """The boxes of the texts' glyphs only (an annotation's own extent includes its leader line)."""
    return [matplotlib.text.Text.get_window_extent(t, renderer) for t in texts]


def _assert_leaders_cross_no_other_label(drawn, boxes, renderer):
    """Points along each drawn leader line lie in no other label's glyph box."""
    for i, text in enumerate(drawn):
        path = text.arrow_patch.get_path().transformed(text.arrow_patch.get_transform())
        vertices = path.vertices
        along = np.linspace(0.0, 1.0, 200)[:, None]
        samples = np.concatenate([a + along * (b - a) for a, b in zip(vertices[:-1], vertices[1:])])
        for j, box in enumerate(boxes):
            if j != i:
                inside = (samples[:, 0] > box.x0 + 0.5) & (samples[:, 0] < box.x1 - 0.5) \
                    & (samples[:, 1] > box.y0 + 0.5) & (samples[:, 1] < box.y1 - 0.5)
                assert not inside.any(), (text.get_text(), drawn[j].get_text())


@pytest.mark.parametrize("lines", [1, 2])
def test_twenty_labels_at_one_point_are_all_drawn_inside_and_apart(lines):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    anchors = [(5.0, 5.0)] * 20
    texts = [f"label {k}" + (f"\nsecond line {k}" if lines == 2 else "") for k in range(20)]
    drawn = place_point_labels(ax, anchors, texts, ["k"] * 20)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert [t.get_text() for t in drawn] == texts
    frame = ax.get_window_extent(renderer)
    boxes = _glyph_boxes(drawn, renderer)
    point = ax.transData.transform((5.0, 5.0))
    for text, box in zip(drawn, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            (text.get_text(), box, frame)
        assert text.xy == (5.0, 5.0) and text.arrow_patch is not None        # joined to its point
        assert not box.contains(*point)                                       # the point stays free
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), (drawn[i].get_text(), a, b)
    _assert_leaders_cross_no_other_label(drawn, boxes, renderer)
    plt.close(fig)


def test_labels_at_a_corner_stay_inside_and_apart():
    """Near the axes' corner only the grid's inner quarter is inside: what is drawn lies there,
    apart (at least a column of labels below the point); the labels left out are the last given."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    texts = [f"label {k}" for k in range(20)]
    drawn = place_point_labels(ax, [(9.9, 9.9)] * 20, texts, ["k"] * 20)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert len(drawn) >= 8 and [t.get_text() for t in drawn] == texts[:len(drawn)]
    frame = ax.get_window_extent(renderer)
    boxes = _glyph_boxes(drawn, renderer)
    for box in boxes:
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    _assert_leaders_cross_no_other_label(drawn, boxes, renderer)
    plt.close(fig)


def test_first_free_box_takes_the_first_candidate_inside_and_clear():
    placed = [(0.0, 0.0, 1.0, 1.0)]
    candidates = [(0.5, 0.5, 1.5, 1.5),      # overlaps the box placed
                  (1.05, 0.0, 2.05, 1.0),    # within the gap of it
                  (3.5, 0.0, 4.5, 1.0),      # outside the frame
                  (1.5, 0.0, 2.5, 1.0), (2.5, 0.0, 3.5, 1.0)]
    box = first_free_box(candidates, placed, gap=(0.2, 0.2), frame=(0.0, 0.0, 4.0, 4.0))
    assert box == (1.5, 0.0, 2.5, 1.0) and placed[-1] == box
    assert first_free_box(candidates[:3], placed, (0.2, 0.2), (0.0, 0.0, 4.0, 4.0)) is None
    assert first_free_box([(2.0, 2.0, 3.0, 3.0)], [], obstacles=[(2.5, 2.5, 2.6, 2.6)],
                          frame=(0.0, 0.0, 4.0, 4.0)) is None


# -- labels clear of the curves ------------------------------------------------------------------

def _fan_of_lines(ax, n=6, points=2000, lw=1.5):
    """``n`` wavy curves across the axes (log y), thousands of points each."""
    x = np.linspace(0.0, 10.0, points)
    for k in range(n):
        ax.plot(x, 10.0 ** (0.8 * k + 0.2 * np.sin(3 * x + k) + 0.05 * x), lw=lw)
    ax.set_yscale("log")
    ax.set_xlim(0, 10)
    ax.set_ylim(0.5, 10.0 ** 4.5)


def test_curve_map_never_calls_a_crossed_box_free_and_frees_boxes_away_from_the_curves():
    """Against exact geometry (each segment clipped to the box): a box some curve runs through is
    never free; a box no curve comes within 3 points of is free (a label keeps at most about a
    cell and half a line width from the curves)."""
    import matplotlib.pyplot as plt
    from matplotlib.transforms import Bbox

    from label_geometry import crossings, curve_segments
    from rotordyn_modal.plotting._labels import CurveMap, laid_out_renderer

    fig, ax = plt.subplots(figsize=(8, 5))
    _fan_of_lines(ax, n=12, points=300, lw=0.5)          # thin lines, long segments
    renderer = laid_out_renderer(fig)
    curves = CurveMap(ax, renderer)
    segments = curve_segments(ax)
    frame = ax.get_window_extent(renderer)
    reach = 3 * fig.dpi / 72
    rng = np.random.default_rng(1)
    seen = {True: 0, False: 0}
    for _ in range(1500):
        w, h = rng.uniform(0.5, 30, 2)
        x, y = rng.uniform(frame.x0, frame.x1 - w), rng.uniform(frame.y0, frame.y1 - h)
        box = (x, y, x + w, y + h)
        crossed = len(crossings(Bbox.from_extents(*box), segments, inset=0.0)) > 0
        near = len(crossings(Bbox.from_extents(x - reach, y - reach, x + w + reach, y + h + reach), segments,
                             inset=0.0)) > 0
        if crossed:
            assert not curves.free(box), box
        if not near:
            assert curves.free(box), box
        seen[crossed] += 1
    assert min(seen.values()) > 20
    plt.close(fig)


def test_point_labels_among_curves_lie_where_no_other_curve_runs():
    """Peaks on the middle curves of a dense fan: each label drawn lies where no curve runs
    (but within 6 sqrt(2) points of its own point), inside the axes and apart."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments

    fig, ax = plt.subplots(figsize=(8, 5))
    _fan_of_lines(ax)
    lines = ax.get_lines()
    anchors = [(x, float(np.interp(x, lines[k].get_xdata(), lines[k].get_ydata())))
               for k, x in ((3, 2.0), (4, 5.0), (5, 8.0), (2, 6.5))]
    texts = [f"AF {k}.0 at {1000 * k} rpm\nSM {10 * k} %" for k in range(len(anchors))]
    drawn = place_point_labels(ax, anchors, texts, ["k"] * len(anchors))
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert len(drawn) >= 3
    boxes = _glyph_boxes(drawn, renderer)
    segments = curve_segments(ax)
    radius = 6 * np.sqrt(2) * fig.dpi / 72 + 1
    for text, box in zip(drawn, boxes):
        crossed = crossings(box, segments, [ax.transData.transform(text.xy)], radius)
        assert not len(crossed), (text.get_text(), crossed[:4])
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    _assert_leaders_cross_no_other_label(drawn, boxes, renderer)
    plt.close(fig)
