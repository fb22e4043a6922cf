"""Figure audit of issue 27 §3 (figs30): one rule for circles that read as one.

The Campbell diagram's critical speeds and the UCS map's crossings each grouped the circles that
lie on each other with a loop of their own (``campbell._critical_groups``, ``ucs_map._touching``);
both now call ``_labels.touching_groups``. Its groups are checked here on points whose grouping
is read off their coordinates by hand.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

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
    assert "touching_groups(" in inspect.getsource(campbell._CampbellLabels._grouped_critical)   # (cached by _critical_groups)
    assert "touching_groups(" in inspect.getsource(ucs_map._touching)


@pytest.mark.parametrize("example", ["motor_pump_on_mounts", "flexible_pump_on_mounts"])
def test_overlapping_circles_share_one_label_with_a_clean_leader(example, ucs_figure):
    """``ucs-map examples/motor_pump_on_mounts.toml --stiffness 1e5:1e10:41 --plot``: at 1e8 N/m
    the crossings 52517, 56625 and 62212 rpm lie 3.4 points apart on one stiffness line (circles
    6 points across, overlapping); '52517' and '56625' stood side by side and the leader of
    '56625' crossed mode 2's line (drawn at 150 dpi); flexible_pump_on_mounts.toml over the same
    stiffness: the leader of '31315' crossed mode 7's line. On the drawn figure (exact geometry,
    ``test_figure_audit27r._ucs_label_problems``): every crossing's speed is written, no label
    leaves the axes or lies over another, no leader crosses a mode's curve beyond its circle
    or passes through the circle of a crossing its label does not name."""
    import matplotlib.pyplot as plt

    from test_figure_audit27r import _ucs_label_problems

    # mapped and plotted once per worker (conftest.ucs_figure): the pump's with test_ucs32's
    result, fig = ucs_figure(example, (1e5, 1e10, 41))
    fig.set_dpi(150)
    assert not _ucs_label_problems(result, fig)
    plt.close(fig)
