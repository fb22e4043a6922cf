"""The cut of the lowest modes inside a double root (issue 28 §4; the left-over of
test_lowest_multiple_roots.py): an axisymmetric rotor on isotropic bearings has exact double
roots at rest (its two whirl directions, by symmetry). Where ``modes=N`` puts the N-th and the
(N+1)-th root into one of them, the reduced route could not show that no root was missed below
the N-th (the highest start was the root's other half) and 0 rpm was solved whole.

Truth from outside the code: scipy's eigenvalues of the full state matrix, and the symmetry of
the pair: once the rotor turns, a double root splits into a backward root below it and a forward
root above it, so the root kept below the cut at rest is the backward one (whirl ratio -1), the
one that continues as the N-th lowest at the next speed.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.analysis._stack import Stack

from test_lowest_modes import _lowest_by_scipy

COMPRESSOR = "examples/compressor_rotor.toml"       # 53 coordinates, axisymmetric on isotropic bearings


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(COMPRESSOR)


@pytest.mark.parametrize("count", [1, 4, 6])
def test_a_cut_inside_a_double_root_at_rest_is_not_solved_whole(model, count):
    speeds = rdm.rpm(np.array([0.0, 600.0]))
    reference = _lowest_by_scipy(model, speeds, count + 1)
    # the count-th and (count + 1)-th roots at rest are one double root
    assert abs(reference[0, count] - reference[0, count - 1]) < 1e-9 * abs(reference[0, count - 1])
    assert model.dofs.n >= _lowest.DENSE_BELOW
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        values, _, full = _lowest.lowest_roots(Stack([model]), speeds, count)
    assert not full.any(), full
    assert not [w for w in caught if "solved whole" in str(w.message)], [str(w.message) for w in caught]
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)
    assert np.max(np.abs(values - reference[:, :count]) / np.abs(reference[:, :count])) < 1e-9


@pytest.mark.parametrize("count", [1, 4])
def test_the_root_kept_below_the_cut_at_rest_is_the_backward_one(model, count):
    """At rest the N-th mode whirls backward (ratio -1, a circular orbit), and it is the tracked
    mode N that goes on as the lower, backward root of the split pair once the rotor turns."""
    speeds = rdm.rpm(np.array([0.0, 600.0]))
    reference = _lowest_by_scipy(model, speeds, count + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.campbell(model, speeds, critical=False, modes=count)
    assert result.whirl_ratios[0, count - 1] == pytest.approx(-1.0, abs=1e-6)
    assert result.whirl[0, count - 1] == result.whirl[1, count - 1] == "backward"
    # at 600 rpm mode N is the lower half of the split pair: below its value at rest
    assert abs(result.eigenvalues[1, count - 1] - reference[1, count - 1]) < 1e-9 * abs(reference[1, count - 1])
    assert reference[1, count - 1].imag < reference[0, count - 1].imag < reference[1, count].imag
