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


def _twin_shafts():
    """Two identical steel shafts (0.8 m, 40 mm, a 4 kg wheel in the middle) side by side, each on
    its own two isotropic bearings, not coupled: every bending root at rest is a root of
    multiplicity four (two rotors, two whirl directions each)."""
    def shaft(name, y):
        return {"name": name, "start": [0.0, y, 0.0], "speed_ratio": 1.0, "element_length": 0.1,
                "shaft": [{"length": 0.8, "outer_diameter": 0.04, "material": "steel"}],
                "disks": [{"name": "wheel " + name, "axial_position": 0.4, "mass": 4.0, "polar_inertia": 0.25,
                           "diametral_inertia": 0.13}]}

    return rdm.Model.from_dict({
        "name": "twins", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "a",
        "materials": [{"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
        "rotors": [shaft("a", 0.0), shaft("b", 1.0)],
        "bearings": [{"name": f"{r}{i}", "rotor": r, "axial_position": z, "stiffness": 2e7, "damping": 500.0}
                     for r in "ab" for i, z in enumerate((0.0, 0.8))]})


@pytest.mark.parametrize("count", [1, 3, 5])
def test_a_root_of_multiplicity_four_is_sorted_by_whirl(count):
    """Each rotor's double root at rest is a circular backward orbit and a circular forward one
    (symmetry); two identical rotors make it a root of multiplicity four, whose eigenspace holds
    two of each. The lowest modes' shapes there are whirl-sorted combinations (ratios -1, -1, +1,
    +1; the roots kept below a cut inside the group the backward ones first), not any basis of
    the space Newton's iteration left (ratios anywhere in [-1, 1] on main); the roots are scipy's."""
    model = _twin_shafts()
    assert model.dofs.n >= _lowest.DENSE_BELOW
    speeds = np.array([0.0, 20.0])
    reference = _lowest_by_scipy(model, speeds, 5)
    assert np.ptp(reference[0, :4]) < 1e-9 * abs(reference[0, 0]) < abs(reference[0, 4] - reference[0, 3])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.campbell(model, speeds, critical=False, modes=count)
    values = np.sort_complex(result.eigenvalues[0] * -1j) * 1j
    assert np.max(np.abs(values - reference[0, :count]) / np.abs(reference[0, :count])) < 1e-9
    at_rest = np.sort(result.whirl_ratios[0][:min(count, 4)])
    expected = np.array([-1.0, -1.0, 1.0, 1.0])[:min(count, 4)]
    assert np.allclose(at_rest, expected, atol=1e-6), result.whirl_ratios[0]
