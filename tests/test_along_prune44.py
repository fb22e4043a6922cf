"""How far a leader runs along drawn curves (``_labels.along_each``), against its definition.

``along_each`` skips the segments farther than its reach from a leader and the leader's points
beside no segment, so that a long leader across a dense figure is not tested point by point
against every segment of its bounding box (a report's unbalance figure spent 5.5 of its 8 s
there). The lengths must stay exactly those of the definition: the leader's points every
``reach / 8``, each counted where it lies within ``reach`` of a segment whose direction is within
``degrees`` of the leader's. The reference below tests every point against every segment.
"""

import numpy as np
from hypothesis import given, settings, strategies as st

from rotordyn_modal.plotting._labels import along_each


def along_by_definition(segments, starts, ends, reach, degrees):
    lengths = []
    for start, end in zip(starts, ends):
        way = end - start
        size = np.hypot(*way)
        if size == 0:
            lengths.append(0.0)
            continue
        count = int(np.ceil(size / (reach / 8.0)))
        points = start + ((np.arange(count) + 0.5) / count)[:, None] * way
        within = np.zeros(count, bool)
        for x0, y0, x1, y1 in segments:
            piece = np.array([x1 - x0, y1 - y0])
            length = np.hypot(*piece)
            if length == 0 or abs(way[0] * piece[1] - way[1] * piece[0]) / size > np.sin(np.radians(degrees)) * length:
                continue
            t = np.clip((points - [x0, y0]) @ piece / length ** 2, 0.0, 1.0)
            off = points - ([x0, y0] + t[:, None] * piece)
            within |= off[:, 0] ** 2 + off[:, 1] ** 2 <= reach * reach
        lengths.append(np.count_nonzero(within) * size / count)
    return np.array(lengths)


def curve_segments(xs, ys):
    return np.column_stack([xs[:-1], ys[:-1], xs[1:], ys[1:]])


coordinate = st.floats(0.0, 400.0, allow_nan=False)


@settings(max_examples=150, deadline=None)
@given(curve=st.lists(st.tuples(coordinate, coordinate), min_size=2, max_size=40),
       leaders=st.lists(st.tuples(coordinate, coordinate, coordinate, coordinate), min_size=1, max_size=4),
       reach=st.floats(0.5, 30.0), degrees=st.floats(1.0, 45.0))
def test_lengths_equal_the_definition_on_random_curves(curve, leaders, reach, degrees):
    xs, ys = np.array(curve).T
    segments = curve_segments(xs, ys)
    leaders = np.array(leaders)
    got = along_each(segments, leaders[:, :2], leaders[:, 2:], reach, degrees)
    np.testing.assert_allclose(got, along_by_definition(segments, leaders[:, :2], leaders[:, 2:], reach, degrees),
                               rtol=1e-12, atol=0)


def test_a_long_leader_beside_a_dense_curve_counts_only_its_part_beside_it():
    """A dense curve (2,000 segments) along y = 0 from x = 0 to 100, and a leader along y = 2 from
    x = -300 to 300: 100 pixels (+ the reach at each end, by the points' spacing) run along it."""
    xs = np.linspace(0.0, 100.0, 2001)
    segments = curve_segments(xs, np.zeros_like(xs))
    reach = 4.0
    got = along_each(segments, [[-300.0, 2.0]], [[300.0, 2.0]], reach, 15.0)[0]
    # the points within reach: |x| in [-sqrt(12), 100 + sqrt(12)] (reach^2 - 2^2 = 12), spacing 0.5
    expected = 100.0 + 2 * np.sqrt(reach ** 2 - 2.0 ** 2)
    assert abs(got - expected) <= 0.5 + 1e-9
    np.testing.assert_allclose(got, along_by_definition(segments, np.array([[-300.0, 2.0]]),
                                                        np.array([[300.0, 2.0]]), reach, 15.0), rtol=1e-12)
