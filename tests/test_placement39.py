"""The Campbell critical-speed labels' box tests made on many boxes at once, the answers kept (cplace39).

The 6-rotor gear chain's report figure asked ``uncrossed`` (a leader's end near no other circle,
the box on no curve and no leader, the leader through no label, no leader and no circle, and
across no mode's curve) 127,383 times, one box at a time, and placed every label a fourth time
to undo a retry. Each batched test is checked here against the one-box test it replaces, written
out as the base had it; :func:`first_free_box` with a batched test against the same test asked box
by box; and the retry's replay against a placing run again. The figures were compared byte for
byte (PNG) and text by text with the base's.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from rotordyn_modal.plotting import _labels, campbell  # noqa: E402

_NEAREST_OWN, _BESIDE_POINTS = campbell._NEAREST_OWN, campbell._BESIDE_POINTS


def _labels_at(to_u, to_v, points):
    """A bare :class:`campbell._CampbellLabels` with the scales given (no figure)."""
    labels = object.__new__(campbell._CampbellLabels)
    labels.to_u, labels.to_v, labels.points = to_u, to_v, points
    return labels


# -- the one-box tests as the base wrote them (eb690308) ---------------------------------------
def _short_of(labels, start, centre, clear_px):
    u, v = centre
    direction = np.array([(start[0] - u) / labels.to_u, (start[1] - v) / labels.to_v])
    shorten = clear_px / max(float(np.hypot(*direction)), 1e-9)
    return (u + shorten * direction[0] * labels.to_u, v + shorten * direction[1] * labels.to_v)


def _ends_nearest(labels, end, markers, clear_px):
    if not len(markers):
        return True
    boxes = np.asarray(markers, float)
    middle_u, middle_v = (boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2
    du = (middle_u - end[0]) / labels.to_u
    dv = (middle_v - end[1]) / labels.to_v
    return bool(np.all(np.hypot(du, dv) >= _NEAREST_OWN * clear_px))


def _nearest_own(labels, box, anchor, markers, leader=False):
    if not len(markers):
        return True
    scale = np.array([labels.to_u, labels.to_v])
    boxes = np.asarray(markers, float)
    centres = np.column_stack([boxes[:, 0] + boxes[:, 2], boxes[:, 1] + boxes[:, 3]]) / 2 / scale
    low, high = np.array(box[:2]) / scale, np.array(box[2:]) / scale
    point = np.asarray(anchor) / scale
    own = float(np.hypot(*np.maximum(np.maximum(low - point, point - high), 0.0)))
    near = np.hypot(*np.maximum(np.maximum(low - centres, centres - high), 0.0).T)
    least = min(_NEAREST_OWN * own, _BESIDE_POINTS * labels.points) if leader else _NEAREST_OWN * own
    return bool(np.all(near >= least))


def _boxes(rng, n, size=0.08):
    corner = rng.uniform(-0.05, 1.0, size=(n, 2))
    extent = rng.uniform(0.0, size, size=(n, 2))
    return np.column_stack([corner, corner + extent])


def _snapped(rng, values, step=1 / 64):
    """``values`` with about half of them on a coarse grid (ties: equal coordinates, zero lengths)."""
    snap = rng.random(values.shape) < 0.5
    return np.where(snap, np.round(values / step) * step, values)


def test_nearest_points_and_shortened_leaders_are_each_boxes_own():
    """``nearest_each`` and ``_short_of_each`` give, box by box, the very floats of ``nearest_in``
    and of the base's ``_short_of`` (the anchor inside some boxes: a zero-length leader)."""
    rng = np.random.default_rng(39)
    for _ in range(30):
        labels = _labels_at(1 / rng.uniform(200, 900), 1 / rng.uniform(150, 700), rng.uniform(1.0, 3.0))
        boxes = _snapped(rng, _boxes(rng, 60))
        anchor = tuple(_snapped(rng, rng.uniform(0.0, 1.0, 2)).tolist())
        starts = _labels.nearest_each(boxes, anchor)
        assert starts.tolist() == [list(_labels.nearest_in(tuple(b), anchor)) for b in boxes.tolist()]
        clear_px = rng.uniform(2.0, 8.0)
        ends = labels._short_of_each(starts, anchor, clear_px)
        assert ends.tolist() == [[float(c) for c in _short_of(labels, tuple(s), anchor, clear_px)]
                                 for s in starts.tolist()]


def test_leader_ends_and_boxes_near_other_circles_as_one_by_one():
    """``_ends_nearest_each`` and ``_nearest_own_each`` (with and without a leader) say of each
    box what the base's one-box tests say, markers on the grid of the boxes (ties) included."""
    rng = np.random.default_rng(7)
    for _ in range(30):
        labels = _labels_at(1 / rng.uniform(200, 900), 1 / rng.uniform(150, 700), rng.uniform(1.0, 3.0))
        markers = [tuple(m) for m in _snapped(rng, _boxes(rng, rng.integers(0, 40), 0.02)).tolist()]
        boxes = _snapped(rng, _boxes(rng, 80))
        anchor = tuple(rng.uniform(0.0, 1.0, 2).tolist())
        ends = _snapped(rng, rng.uniform(0.0, 1.0, size=(80, 2)))
        clear_px = rng.uniform(2.0, 8.0)
        got = labels._ends_nearest_each(ends, markers, clear_px)
        assert got.tolist() == [_ends_nearest(labels, tuple(e), markers, clear_px) for e in ends.tolist()]
        for leader in (False, True):
            got = labels._nearest_own_each(boxes, anchor, markers, leader)
            assert got.tolist() == [_nearest_own(labels, tuple(b), anchor, markers, leader) for b in boxes.tolist()]


@pytest.mark.parametrize("keep", [False, True])
def test_cuts_of_many_leaders_are_each_leaders_cuts(keep):
    """``cuts_each`` counts, leader by leader, what ``cuts`` counts (with the segments' bounds and
    without; leaders ending at the marker, of zero length, along a segment, through its ends),
    and both count the crossings a plain parametric test finds on leaders in general position."""
    rng = np.random.default_rng(27)
    for _ in range(25):
        points = _snapped(rng, rng.uniform(0.0, 1.0, size=(rng.integers(0, 120), 2)), 1 / 32)
        segments = np.column_stack([points, points + _snapped(rng, rng.normal(0.0, 0.1, size=points.shape), 1 / 32)])
        segments = np.asarray(segments, float).reshape(-1, 4) * [640, 480, 640, 480]
        origin, size = (rng.uniform(0, 50), rng.uniform(0, 50)), (640.0, 480.0)
        segments += [origin[0], origin[1], origin[0], origin[1]]
        end = tuple(_snapped(rng, rng.uniform(0.1, 0.9, 2), 1 / 32).tolist())
        starts = _snapped(rng, rng.uniform(0.0, 1.0, size=(70, 2)), 1 / 32)
        starts[:3] = end                                       # zero length
        marker = (end[0] - 0.01, end[1] - 0.01, end[0] + 0.01, end[1] + 0.01) if keep else None
        bounds = _labels.segment_bounds(segments)
        for with_bounds in (None, bounds):
            got = _labels.cuts_each(segments, origin, size, starts, end, marker, bounds=with_bounds)
            assert got.tolist() == [_labels.cuts(segments, origin, size, tuple(s), end, marker, bounds=with_bounds)
                                    for s in starts.tolist()]


def test_cuts_each_counts_crossings_found_by_a_plain_test():
    """Leaders and segments in general position (random floats): the count is the number of
    segments the leader properly crosses, found with orientations in plain Python."""
    rng = np.random.default_rng(5)

    def side(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    for _ in range(20):
        segments = rng.uniform(0.0, 100.0, size=(50, 4))
        starts = rng.uniform(0.0, 1.0, size=(30, 2))
        end = tuple(rng.uniform(0.0, 1.0, 2).tolist())
        got = _labels.cuts_each(segments, (0.0, 0.0), (100.0, 100.0), starts, end)
        for s, count in zip(starts.tolist(), got.tolist()):
            p, q = (100 * s[0], 100 * s[1]), (100 * end[0], 100 * end[1])
            plain = sum(side(p, q, seg[:2]) * side(p, q, seg[2:]) < 0 and side(seg[:2], seg[2:], p)
                        * side(seg[:2], seg[2:], q) < 0 for seg in segments.tolist())
            assert count == plain


def test_first_free_box_with_a_batched_test_takes_the_box_of_the_one_box_test():
    """``first_free_box(each=...)`` takes the box that the same test asked box by box
    (``allowed``) takes: the first one, or with ``cost`` and ``bound`` the least costly; the
    batched test is asked in chunks, in the candidates' order, and not beyond the chunk where
    the search ends."""
    rng = np.random.default_rng(11)
    for trial in range(200):
        candidates = [tuple(b) for b in _boxes(rng, rng.integers(0, 300), 0.05).tolist()]
        placed = [tuple(b) for b in _boxes(rng, rng.integers(0, 6), 0.1).tolist()]
        good = {b for b in candidates if rng.random() < rng.choice([0.002, 0.05, 0.5])}
        costs = {b: rng.uniform(0, 10) for b in candidates}
        options = {} if trial % 2 else {"cost": costs.get, "bound": None}
        if trial % 4 == 0:         # a bound (here the cost) not decreasing along the candidates
            candidates = sorted(candidates, key=lambda b: costs[b])
            options["bound"] = costs.get
        asked = []

        def each(boxes):
            asked.append(len(boxes))
            return np.array([tuple(b) in good for b in boxes.tolist()], bool)

        one = list(placed)
        wanted = _labels.first_free_box(candidates, one, (0.01, 0.01), allowed=lambda b: b in good, **options)
        many = list(placed)
        got = _labels.first_free_box(_labels.BoxRows(np.asarray(candidates, float).reshape(-1, 4)), many,
                                     (0.01, 0.01), each=each, **options)
        assert got == wanted and many == one
        assert all(size in (8, 24, 64) for size in asked[:-1])
        assert sum(asked) <= len(candidates)
        if "cost" not in options and wanted is not None:       # asked up to the chunk of the box taken
            clear = np.flatnonzero(_labels._inside_and_clear(candidates, placed, (0.01, 0.01),
                                                             (0.0, 0.0, 1.0, 1.0), ()))
            assert sum(asked[:-1]) <= clear.tolist().index(candidates.index(wanted)) < sum(asked)


def test_a_failed_order_retry_leaves_the_figure_as_placing_it_again_would():
    """Where the order labels' retry labels no more critical speeds, :meth:`place` makes again
    the first run's settings (:meth:`_replayed`); every text and line then is as a fourth
    :meth:`_place_all` (the base's way) leaves it. fan_on_bearings (0:9000:121, orders 1, 2,
    saved at 150 dpi) retries; its retry is made to fail here (fewer order labels shown at each
    count)."""
    import io

    import matplotlib.pyplot as plt

    import rotordyn_modal as rdm
    from rotordyn_modal.plotting.campbell import _CampbellLabels

    model = rdm.load_model("examples/fan_on_bearings.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 9000.0, 121)), orders=(1, 2))
    states, counted = [], []
    replayed, shown = _CampbellLabels._replayed, _CampbellLabels._orders_shown

    def replay_then_place(self, *first):
        placed = replayed(self, *first)
        again = _state(self.ax), list(placed), list(self.leader_lines), list(self.shared)
        placed = self._place_all(self.renderer)
        states.append((again, (_state(self.ax), list(placed), list(self.leader_lines), list(self.shared))))
        return placed

    def fewer_each_time(self):
        counted.append(shown(self))
        return 10 ** 6 - len(counted)

    _CampbellLabels._replayed, _CampbellLabels._orders_shown = replay_then_place, fewer_each_time
    try:
        result.plot().savefig(io.BytesIO(), format="png", dpi=150)
    finally:
        _CampbellLabels._replayed, _CampbellLabels._orders_shown = replayed, shown
        plt.close("all")
    assert states, "fan_on_bearings' order labels are placed again, and the retry fails"
    for again, placed in states:
        assert again == placed


def _state(ax):
    """Every text's and line's drawn properties (the curves' gaps, nan, compared as written)."""
    texts = [(t.get_text(), t.get_visible(), tuple(map(float, t.get_position())), t.get_color(), t.get_rotation(),
              t.get_fontsize(), t.get_va(), t.get_ha(), t.get_clip_on()) for t in ax.texts]
    lines = [(repr(np.asarray(line.get_xdata(), float).tolist()), repr(np.asarray(line.get_ydata(), float).tolist()),
              line.get_visible(), str(line.get_color())) for line in ax.get_lines()]     # (repr: nan is nan)
    return texts, lines
