"""Figure audit of issue 27 §3 (figs30): one rule for circles that read as one.

The Campbell diagram's critical speeds and the UCS map's crossings each grouped the circles that
lie on each other with a loop of their own (``campbell._critical_groups``, ``ucs_map._touching``);
both now call ``_labels.touching_groups``. Its groups are checked here on points whose grouping
is read off their coordinates by hand.
"""

from __future__ import annotations

import inspect

import numpy as np

from rotordyn_modal.plotting import _labels, campbell, ucs_map


def test_a_chain_of_circles_is_one_group_only_where_chains_are_asked_for():
    """Three circles 2 px apart on one line (each within 3 px of the next, the ends 4 px apart):
    one group through the chain; without chains the third lies 4 px from the group's first and
    starts its own. A fourth point 10 px away is alone either way."""
    points = [(0.0, 0.0), (0.0, 2.0), (0.0, 4.0), (0.0, 14.0)]
    assert _labels.touching_groups(points, 3.0) == [[0, 1, 2], [3]]
    assert _labels.touching_groups(points, 3.0, chain=False) == [[0, 1], [2], [3]]


def test_circles_side_by_side_touch_farther_apart_than_circles_on_one_line():
    """``beside``: 5 px apart across (two stiffness lines) touch at 6 px; 5 px apart on one
    vertical line do not at 3 px. Groups keep the order of their first points and members the
    order given, where a later point joins two groups that were apart."""
    assert _labels.touching_groups([(0.0, 0.0), (5.0, 0.0)], 3.0, beside=6.0) == [[0, 1]]
    assert _labels.touching_groups([(0.0, 0.0), (0.0, 5.0)], 3.0, beside=6.0) == [[0], [1]]
    assert _labels.touching_groups([(0.0, 0.0), (0.0, 4.0), (0.0, 2.0)], 3.0) == [[0, 1, 2]]
    assert _labels.touching_groups(np.zeros((0, 2)), 3.0) == []


def test_the_campbell_diagram_and_the_ucs_map_group_circles_with_the_one_function():
    """Neither figure keeps a loop of its own: both call ``touching_groups`` (the Campbell
    diagram without chains, so that a group stays within one circle; the UCS map through
    chains, circles side by side on two stiffness lines twice as far apart)."""
    assert campbell.touching_groups is _labels.touching_groups
    assert "touching_groups(" in inspect.getsource(campbell._CampbellLabels._critical_groups)
    assert "touching_groups(" in inspect.getsource(ucs_map._touching)
