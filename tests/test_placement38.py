"""The label placers' repeated work removed, the answers kept (place38).

The fan's UCS map (1e5 .. 1e10 N/m) asked ``crosses_any`` 110,000 times (one place against
every drawn segment) and ``CurveMap.cut`` 64,050 times about 23,287 leaders, and moved each
label's annotation again for every other label; the 40-rotor gear chain's Campbell diagram
merged its right-edge labels one pair at a time, stacking the whole column 550 times, and
measured 27,630 distances from a candidate place to an order line one line at a time. Each fast
path is checked here against the plain computation it replaces, written out in the test; the
figures were compared byte for byte (PNG at 150 dpi) and text by text with the base's.
"""

from __future__ import annotations

import matplotlib
import numpy as np

matplotlib.use("Agg")

from rotordyn_modal.plotting import _labels, campbell, ucs_map  # noqa: E402


def _point_to_polyline(path, point) -> float:
    """Distance from ``point`` to the polyline ``path`` (n, 2), segment by segment in plain Python."""
    best = np.inf
    for (ax_, ay), (bx, by) in zip(path[:-1].tolist(), path[1:].tolist()):
        dx, dy = bx - ax_, by - ay
        t = ((point[0] - ax_) * dx + (point[1] - ay) * dy) / max(dx * dx + dy * dy, 1e-12)
        t = min(max(t, 0.0), 1.0)
        best = min(best, float(np.hypot(ax_ + t * dx - point[0], ay + t * dy - point[1])))
    return best


def test_distances_from_many_points_are_each_points_own():
    """``_Segments.distances`` gives, for each point, the very float ``_distance_to`` gives, and
    the distance written out segment by segment to 1e-12."""
    rng = np.random.default_rng(38)
    for _ in range(20):
        path = np.cumsum(rng.normal(size=(rng.integers(2, 40), 2)) * 30.0, axis=0)
        path[rng.integers(0, len(path))] = path[0]          # a repeated point: a zero-length segment
        points = rng.uniform(-100.0, 100.0, size=(50, 2))
        got = _labels._Segments(path).distances(points)
        assert [float(g) for g in got] == [_labels._distance_to(path, p) for p in points]
        np.testing.assert_allclose(got, [_point_to_polyline(path, p) for p in points], rtol=1e-12, atol=1e-9)


def test_nearest_own_places_are_those_a_place_by_place_test_keeps_in_order():
    """The candidates kept by ``_nearest_own_in_order`` (a chunk at a time, one other line at a
    time) are, in order, those whose centre lies nearer the nearest own line than every other."""
    rng = np.random.default_rng(3)
    for _ in range(10):
        own = [np.cumsum(rng.normal(size=(30, 2)) * 20.0, axis=0) for _ in range(rng.integers(1, 3))]
        others = [np.cumsum(rng.normal(size=(30, 2)) * 20.0, axis=0) for _ in range(rng.integers(0, 6))]
        candidates = rng.uniform(-150.0, 150.0, size=(200, 4, 2))
        chunks = [np.arange(0, 64), np.arange(64, 64), np.arange(64, 150, 2), np.arange(151, 200)]
        got = list(_labels._nearest_own_in_order(iter(chunks), candidates, [_labels._Segments(p) for p in own],
                                                 [_labels._Segments(p) for p in others]))
        wanted = []
        for k in np.concatenate(chunks):
            centre = candidates[k].mean(axis=0)
            mine = min(_point_to_polyline(p, centre) for p in own)
            if all(mine < _point_to_polyline(p, centre) for p in others):
                wanted.append(int(k))
        assert [int(k) for k in got] == wanted


def _grouped_by_merging_one_pair_at_a_time(targets, height, gap):
    """The right-edge grouping as specified, stacking the column before every merge."""
    targets = np.asarray(targets, float)
    groups = [[int(k)] for k in np.argsort(targets, kind="stable")]
    pitch = height + gap
    while True:
        low, high = np.array([targets[g[0]] for g in groups]), np.array([targets[g[-1]] for g in groups])
        wanted = 0.5 * (low + high)
        centres = _labels.column_positions(wanted, [height] * len(groups), 0.0, 1.0, gap=gap)
        shift = np.abs(centres - wanted)
        if len(groups) == 1 or (len(groups) * pitch <= 1.0 and shift.max() <= campbell._MOST_SHIFT * pitch):
            return groups, centres
        first, last = 0, len(groups) - 1
        if len(groups) * pitch <= 1.0:
            first = last = int(np.argmax(shift))
            while first > 0 and centres[first] - centres[first - 1] <= pitch * (1 + 1e-9):
                first -= 1
            while last < len(groups) - 1 and centres[last + 1] - centres[last] <= pitch * (1 + 1e-9):
                last += 1
            if first == last:
                first, last = (first, last + 1) if last + 1 < len(groups) else (first - 1, last)
        j = first + int(np.argmin(high[first + 1:last + 1] - low[first:last]))
        groups[j:j + 2] = [groups[j] + groups[j + 1]]


def test_right_edge_groups_as_when_the_column_is_stacked_before_every_merge():
    """Crowded columns (up to 300 curve ends for 40 label places) merge to the same groups and
    centres when the column is not stacked while it cannot fit."""
    rng = np.random.default_rng(7)
    for n in (1, 2, 5, 39, 41, 80, 300):
        for _ in range(3):
            targets = np.round(rng.uniform(0.0, 1.0, n), rng.integers(2, 6))     # ties: ends on each other
            got = campbell._grouped_beside(targets, 0.02, 0.005)
            wanted = _grouped_by_merging_one_pair_at_a_time(targets, 0.02, 0.005)
            assert got[0] == wanted[0]
            assert got[1].tolist() == wanted[1].tolist()


def test_lines_through_places_answer_as_crosses_any_place_by_place():
    """``ucs_map._lines_through`` (segments near the places only, 64 places at once) answers as
    ``crosses_any`` of every segment against each place, also for segments with NaN ends, far
    segments and segments ending a pixel from a place."""
    rng = np.random.default_rng(11)
    for n_segments in (0, 3, 40, 400):
        segments = rng.uniform(0.0, 600.0, size=(n_segments, 4))
        segments[::7, 2:] = segments[::7, :2] + rng.uniform(-5.0, 5.0, size=(len(segments[::7]), 2))
        segments[::11, 3] = np.nan
        boxes = np.sort(rng.uniform(200.0, 320.0, size=(150, 2, 2)), axis=1).transpose(0, 2, 1).reshape(-1, 4)
        if n_segments:
            segments[0] = (boxes[0, 2] + 1.0, 0.0, boxes[0, 2] + 1.0, 600.0)      # a pixel right of a place
        got = list(ucs_map._lines_through([tuple(s) for s in segments], boxes, _labels.crossing_pairs))
        assert got == [_labels.crosses_any(segments, [b]) for b in boxes]


def test_a_curve_map_counts_a_leader_once_and_answers_as_counted():
    """``CurveMap.cut`` keeps each leader's count: asked again (as tuples or arrays), the same
    number, and no second count; every answer is that of ``cuts`` on the map's segments."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3), dpi=100)
    x = np.linspace(0.0, 1.0, 50)
    for k in range(5):
        ax.plot(x, 0.2 * k + 0.3 * x ** 2)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    curves = _labels.CurveMap(ax, renderer, units="axes")
    rng = np.random.default_rng(5)
    counted = []
    curves._cut_now = lambda *a: counted.append(a) or _labels.CurveMap._cut_now(curves, *a)
    questions = [(tuple(rng.uniform(0, 1, 2)), tuple(rng.uniform(0, 1, 2)), None) for _ in range(30)]
    questions += [(s, e, (e[0] - 0.01, e[1] - 0.01, e[0] + 0.01, e[1] + 0.01)) for s, e, _ in questions[:10]]
    for start, end, keep in questions + [(np.array(s), np.array(e), k) for s, e, k in questions]:
        wanted = _labels.cuts(curves._segments, curves.origin, curves.size, start, end, keep)
        assert curves.cut(start, end, keep) == wanted
    assert len(counted) == len(questions)
    assert sum(curves.cut(s, e, k) for s, e, k in questions) > 0       # the leaders do cross curves
    plt.close(fig)


def test_order_line_paths_mapped_at_once_are_the_points_mapped_one_by_one():
    """On logarithmic and linear axes, the order lines' paths mapped in one call per line are
    the points mapped one at a time, float for float."""
    import matplotlib.pyplot as plt

    for scale in ("log", "linear"):
        fig, ax = plt.subplots()
        ax.set_xlim(0.0, 9000.0)
        ax.set_yscale(scale)
        ax.set_ylim(1.0 if scale == "log" else 0.0, 400.0)
        to_axes = (ax.transData + ax.transAxes.inverted()).transform
        for slope in (0.01, 1 / 60, 0.05, 0.2, 3.0):
            for direction in (1, -1):
                one = _labels._line_path(slope, (-9000.0, 9000.0), 400.0, ax.get_ylim()[0],
                                         lambda x, f: tuple(to_axes((x, f))), direction)
                many = _labels._line_path(slope, (-9000.0, 9000.0), 400.0, ax.get_ylim()[0],
                                          lambda x, f: tuple(to_axes((x, f))), direction,
                                          lambda x, f: to_axes(np.column_stack([x, f])))
                assert many == one and len(one) in (0, _labels._PATH_SAMPLES)
        plt.close(fig)
