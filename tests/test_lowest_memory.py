"""``campbell(modes=N)``'s peak memory does not grow with the speeds beyond its result (issue 28,
section 4: "memory bounded by chunking"): Newton's refinement of the lowest roots runs in parts of
``_lowest._NEWTON_BYTES`` of speeds and the shapes' weighting and whirl ratios in parts of
``_batches._PART_BYTES``; the parts give the roots, shapes and whirl ratios of one part bit for bit.

The budgets are made small here (a few hundred kB) so that a model of 60 coordinates at a few
hundred speeds is cut into many parts and costs a second; the rule measured is the one at any
size: doubling the speeds adds at most the result's own growth, a few times over (the result's
shapes, the mass-weighted shapes tracking needs, their reordered copies), not the working arrays
of every speed at once (on main: 1.3 MB per speed at 400 coordinates, the lowest roots' Newton
vectors and the whirl ratios' products of all speeds together).
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, _lowest

from shaft_models import fan_shaft

_SMALL = 256 * 2**10           # [bytes] the parts' budget in this test
_HUGE = 2**40                  # [bytes] no parts at all


def _budgets(monkeypatch, size):
    monkeypatch.setattr(_lowest, "_NEWTON_BYTES", size, raising=False)
    monkeypatch.setattr(_batches, "_PART_BYTES", size)


def _campbell(model, count):
    # from 10 rad/s: no speed at rest (its double roots are solved whole, a cost of their own)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.campbell(model, np.linspace(10.0, 1500.0, count), critical=False, modes=6)


def _traced(model, count):
    """Peak traced memory of the sweep [bytes] and the result's shapes' size [bytes]."""
    tracemalloc.start()
    try:
        result = _campbell(model, count)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, result.shapes.nbytes


def test_peak_memory_grows_with_the_speeds_only_by_the_result(monkeypatch):
    model = fan_shaft()
    _budgets(monkeypatch, _SMALL)
    _campbell(model, 11)                                # caches (the basis's forms) made before measuring
    peak_1, result_1 = _traced(model, 300)
    peak_2, result_2 = _traced(model, 600)
    grown, result_grown = peak_2 - peak_1, result_2 - result_1
    # the shapes, the weighted shapes, a reordered copy of each: four times the result's growth at most
    assert grown <= 4 * result_grown, (grown, result_grown)


def test_parts_give_the_unparted_sweep_bit_for_bit(monkeypatch):
    model = fan_shaft()
    _budgets(monkeypatch, _HUGE)
    whole = _campbell(model, 301)
    _budgets(monkeypatch, _SMALL)
    parted = _campbell(model, 301)
    for name in ("eigenvalues", "shapes", "whirl_ratios"):        # NaN where a root is not among the lowest
        assert np.array_equal(getattr(whole, name), getattr(parted, name), equal_nan=True), name
