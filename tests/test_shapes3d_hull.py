"""The outlines of the 3-D view's bodies (``shapes3d._convex_hull``, the polygons the names keep
away from): the corners of the convex hull, counter-clockwise from the lowest x, and on the flat
and degenerate inputs a body seen edge-on projects to, no polygon.

Truth from outside the code under test: every point inside or on the polygon (cross products),
every corner one of the points and a strict turn, the two ends of a line."""

from __future__ import annotations

import numpy as np
import pytest

from rotordyn_modal.plotting.shapes3d import _convex_hull


def _turns(corners):
    """z of the cross products at each corner of a closed polygon (k,)."""
    before, after = corners - np.roll(corners, 1, axis=0), np.roll(corners, -1, axis=0) - corners
    return before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]


@pytest.mark.parametrize("seed", range(5))
def test_the_hull_holds_every_point_and_turns_left_at_each_corner(seed):
    """Random pixels and a square with points on its edges and inside: the corners are points,
    each a strict left turn (no point on an edge kept), start at the lowest x, and no point lies to
    the right of any edge."""
    rng = np.random.default_rng(seed)
    points = np.vstack([rng.integers(0, 50, (40, 2)), [[0, 0], [60, 0], [60, 60], [0, 60], [30, 0], [0, 30]]])
    points = points.astype(float)
    corners = _convex_hull(np.vstack([points, [[np.nan, 1.0]]]))
    assert {tuple(c) for c in corners} <= {tuple(p) for p in points}
    assert (_turns(corners) > 0).all()
    assert tuple(corners[0]) == min(map(tuple, points))
    edges = np.roll(corners, -1, axis=0) - corners
    offsets = points[:, None, :] - corners[None, :, :]
    assert (edges[None, :, 0] * offsets[..., 1] - edges[None, :, 1] * offsets[..., 0] >= 0).all()
    assert {tuple(c) for c in _convex_hull(points[[0, 1, 2, 40, 41, 42, 43, 44, 45]])} == {(0, 0), (60, 0), (60, 60), (0, 60)}


@pytest.mark.parametrize("points, expected", [
    ([[100, 200], [100, 260], [100, 230], [100, 200]], [[100, 200], [100, 260]]),       # a box seen edge-on
    ([[0, 0], [3, 3], [1, 1], [2, 2]], [[0, 0], [3, 3]]),
    ([[5, 5], [5, 5], [1, 2]], [[1, 2], [5, 5]]),
    ([[5, 5]], [[5, 5]]),
])
def test_flat_or_fewer_than_three_points_give_their_ends_and_no_polygon(points, expected):
    """Points on one line (Qhull refuses them) or fewer than three distinct: the distinct ends,
    fewer than three corners, which the occupied cells take no polygon from."""
    np.testing.assert_array_equal(_convex_hull(np.array(points, float)), np.array(expected, float))
