"""Figures' words (issue 27 §3): an order label of coinciding lines reads as one label.

counter_rotating's twin rotors geared 1:1 draw one 1X line for both; its label read
'1X upper, lower', which reads as '1X upper' and a second label 'lower' naming no order.
"""

from __future__ import annotations

import pytest

from rotordyn_modal.plotting._labels import _order_words


@pytest.mark.parametrize("names, words", [
    (["upper"], "upper"),
    (["upper", "lower"], "upper & lower"),
    (["a", "b", "c"], "a, b & c"),
])
def test_coinciding_lines_of_one_order_name_their_rotors_as_one_list(names, words):
    members = [(1.0, name, "C0") for name in names]
    assert _order_words(members) == ("1X", words)


def test_coinciding_lines_of_different_orders_say_which_order_of_which_rotor():
    assert _order_words([(2.0, "motor", "C0"), (1.0, "fan", "C1")]) == ("2X", "motor = 1X fan")
