"""The label placers' fast paths answer as the box-by-box tests they replace (place37).

The UCS map and Campbell placers asked the same questions box by box tens of thousands of
times (is this box free of curves, does this leader cross a label, a leader, a box) and laid the
figure out again before each measurement (the fan's UCS map with every bearing chosen: 30
layouts, 6.6 s of its 12-15 s of CPU). They now ask for every candidate box at once and skip a
layout that would start where an earlier one started. Nothing may change: each batched test is
checked here against the single test it replaces, on boxes and segments of every kind (touching,
flat, vertical, degenerate, far) and on the curves of a real figure; the layout memo against the
layouts it skips. The figures themselves were compared byte for byte (PNG at 150 dpi) with the
base's: 42 figures, the UCS maps of 7 examples (two stiffness ranges, SI and US) and 12 Campbell
diagrams (benchmarks/bench_placement.py measures the time).
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from rotordyn_modal.plotting import _labels, ucs_map  # noqa: E402


def _random_boxes(rng, n, scale=60.0):
    """``n`` boxes (x0, y0, x1, y1) [pixels], some rounded to whole pixels (edges that touch), some flat."""
    low = np.round(rng.uniform(0.0, scale, size=(n, 2)), rng.integers(0, 3))
    size = np.round(rng.uniform(0.0, 0.3 * scale, size=(n, 2)), rng.integers(0, 2))
    size[rng.random(n) < 0.05] = 0.0
    return np.column_stack([low, low + size])


def _random_segments(rng, n, scale=60.0):
    """``n`` segments (x0, y0, x1, y1) [pixels]: some vertical, some horizontal, some points."""
    segments = np.round(rng.uniform(0.0, scale, size=(n, 4)), rng.integers(0, 3))
    vertical, flat, point = (rng.random(n) < 0.15 for _ in range(3))
    segments[vertical, 2] = segments[vertical, 0]
    segments[flat, 3] = segments[flat, 1]
    segments[point, 2:] = segments[point, :2]
    return segments


def _liang_barsky(segment, box) -> bool:
    """Whether ``segment`` passes through ``box``: the clipping written out on its own (closed box)."""
    (x0, y0, x1, y1), (bx0, by0, bx1, by1) = segment, box
    low, high = 0.0, 1.0
    for delta, near, far in ((x1 - x0, bx0 - x0, bx1 - x0), (y1 - y0, by0 - y0, by1 - y0)):
        if delta == 0.0:
            if near > 0.0 or far < 0.0:
                return False
            continue
        a, b = sorted((near / delta, far / delta))
        low, high = max(low, a), min(high, b)
    return low <= high


def test_every_pair_of_segment_and_box_answers_as_the_clipping_does():
    """``crosses_any`` (one pair by one, or numpy for many), ``crossing_pairs`` (the matrix) and
    ``segment_crosses_box`` agree with the Liang-Barsky clipping written out here, pair by pair,
    on 20,000 pairs that touch, graze, run flat along edges or are points."""
    rng = np.random.default_rng(37)
    for _ in range(400):
        segments, boxes = _random_segments(rng, int(rng.integers(1, 8))), _random_boxes(rng, int(rng.integers(1, 8)))
        expected = np.array([[_liang_barsky(s, b) for b in boxes.tolist()] for s in segments.tolist()])
        assert np.array_equal(_labels.crossing_pairs(segments, boxes), expected)
        assert _labels.crosses_any(segments, boxes) == bool(expected.any())
        for s, row in zip(segments.tolist(), expected):
            assert _labels.crosses_any([s], boxes) == bool(row.any())
            for b, hit in zip(boxes.tolist(), row):
                assert _labels.segment_crosses_box(s[:2], s[2:], b) == hit


def test_leaders_crossed_at_once_as_one_by_one():
    """``_segments_crossed`` (every leader from its start to one point at once) equals
    ``crosses_segments`` asked for each leader."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        starts = np.round(rng.uniform(0, 50, size=(int(rng.integers(1, 30)), 2)), 1)
        end = np.round(rng.uniform(0, 50, size=2), 1)
        segments = _random_segments(rng, int(rng.integers(1, 12)), 50.0)
        expected = [_labels.crosses_segments(tuple(s), tuple(end), segments) for s in starts.tolist()]
        assert _labels._segments_crossed(starts, end, segments).tolist() == expected


def test_box_distances_are_box_distance_of_each():
    """The distances of a grid of boxes (:func:`boxes_around`, the placer's candidates) computed at
    once are, to the last bit, those of ``box_distance`` box by box; the grid's array is its list."""
    rng = np.random.default_rng(5)
    for _ in range(50):
        x, y = rng.uniform(0, 500, size=2)
        grid = _labels.boxes_around(x, y, rng.uniform(10, 40), rng.uniform(5, 12), 3.0, 4.0, 24, 4, split=3)
        assert np.array_equal(grid.array, np.array(list(grid)))
        px, py = x + rng.normal(0, 3), y + rng.normal(0, 3)
        assert _labels.box_distances(grid, px, py).tolist() == [_labels.box_distance(b, px, py) for b in grid]


@pytest.fixture(scope="module")
def curves():
    """A CurveMap of a figure with crossing, steep and flat curves and markers, in pixels and
    in axes fraction."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
    x = np.linspace(0.0, 10.0, 200)
    ax.plot(x, np.sin(x) * 3 + 5, linewidth=1.5)
    ax.plot(x, 0.8 * x, linewidth=1.0)
    ax.plot([0, 10], [5, 5], linewidth=3.0)
    ax.plot([3, 7], [1, 9], "o", markersize=6)
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    renderer = _labels.laid_out_renderer(fig)
    maps = {units: _labels.CurveMap(ax, renderer, units=units) for units in ("pixels", "axes")}
    frame = ax.get_window_extent(renderer)
    yield maps, frame
    plt.close(fig)


@pytest.mark.parametrize("units", ["pixels", "axes"])
def test_free_each_answers_as_free_box_by_box(curves, units):
    """``CurveMap.free_each`` of 3,000 boxes (with and without the anchor's square, boxes reaching
    past the frame) equals ``CurveMap.free`` of each."""
    maps, frame = curves
    rng = np.random.default_rng(11)
    boxes = _random_boxes(rng, 3000, 1.0)
    boxes = boxes * (1.2 * frame.width, 1.2 * frame.height, 1.2 * frame.width, 1.2 * frame.height) \
        + (frame.x0 - 0.1 * frame.width, frame.y0 - 0.1 * frame.height) * 2
    boxes[:, 2:] = np.maximum(boxes[:, 2:], boxes[:, :2])
    if units == "axes":
        boxes = (boxes - (frame.x0, frame.y0) * 2) / ((frame.width, frame.height) * 2)
    curve_map = maps[units]
    for keep in (None, tuple(boxes[7]), tuple(boxes[8] + np.array([0.0, 0.0, 0.05, 0.05]) * (units == "axes"))):
        expected = [curve_map.free(tuple(b), keep) for b in boxes.tolist()]
        assert curve_map.free_each(boxes, keep).tolist() == expected
    assert 0 < sum(expected) < len(expected)


def test_a_layout_that_would_start_where_one_started_is_not_run_again(monkeypatch):
    """Inside ``ucs_map._steady_layout`` a figure is laid out only from axes places (at one
    resolution) no layout started from before; the axes end where such a layout left them.
    Five measurements at one resolution then two at another lay a figure that settles in one
    layout out 4 times, not 7 (the fan's every-bearing map: 8, not 30), and every axes stands
    where the 7 layouts put it."""
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    def figure():
        fig, ax = plt.subplots(figsize=(6, 4), dpi=100, layout="constrained")
        ax.plot([1, 2, 3], [3, 1, 2], label="a curve with a long name")
        ax.set_xlabel("stiffness [N/m]")
        ax.set_ylabel("speed [rpm]")
        ax.set_title("title")
        return fig

    runs = []
    original = Figure.draw_without_rendering

    def counted(self):
        runs.append(self.dpi)
        return original(self)

    def measure(fig, layouts):
        places = []
        for dpi in (100, 100, 100, 100, 100, 150, 150):
            fig.set_dpi(dpi)
            layouts(fig)
            places.append(ucs_map._axes_places(fig))
        return places

    monkeypatch.setattr(Figure, "draw_without_rendering", counted)
    every = figure()
    expected = measure(every, _labels.laid_out_renderer)
    assert len(runs) == 7
    runs.clear()
    fig = figure()
    with ucs_map._steady_layout(fig):
        places = measure(fig, ucs_map._laid_out)
    assert places == expected
    assert runs == [100, 100, 150, 150]
    assert not hasattr(fig, "_ucs_layouts")
    plt.close(every)
    plt.close(fig)
