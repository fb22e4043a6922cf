"""Issue 29 section 2: a UCS map follows the same modes whatever the user's stiffness grid and
whatever the round-off of its values.

On ``examples/flexible_pump_on_mounts.toml`` a map of 5 values (one decade a step) followed other
modes than the same map with its values 1 ulp larger (45 rows against 40, 'pump conical'
becoming 'pump cylindrical'), and other modes than a map of 41 values. The truth asserted here
is independent of the code's following: the same machine sampled at 41 values, a finer grid,
must show each curve of the 5-value map at the values they share (the curve is a property of
the machine and the stiffness, not of the grid), and a 1-ulp change of the inputs changes no
curve, no name and no row.
"""

import numpy as np
import pytest

from rotordyn_modal.analysis.ucs_map import ucs_map
from rotordyn_modal.io import load_model

EXAMPLE = "examples/flexible_pump_on_mounts.toml"
COARSE = np.geomspace(1e5, 1e9, 5)


@pytest.fixture(scope="module")
def maps():
    model = load_model(EXAMPLE)
    return {"coarse": ucs_map(model, COARSE), "ulp": ucs_map(model, np.nextafter(COARSE, np.inf)),
            "fine": ucs_map(model, np.geomspace(1e5, 1e9, 41))}


def _same_curve(a, b):
    """Same nan pattern and speeds to 1e-9 (relative)."""
    return bool(np.array_equal(np.isnan(a), np.isnan(b))
                and np.allclose(a[~np.isnan(a)], b[~np.isnan(b)], rtol=1e-9, atol=0))


def test_each_coarse_curve_is_a_fine_curve(maps):
    coarse, fine = maps["coarse"], maps["fine"]
    shared = np.searchsorted(fine.stiffness, COARSE * (1 - 1e-12))
    np.testing.assert_allclose(fine.stiffness[shared], COARSE, rtol=1e-15)
    found = fine.mode_speeds[shared]                                                  # (5, L fine)
    for j in range(coarse.mode_speeds.shape[1]):
        curve = coarse.mode_speeds[:, j]
        assert any(_same_curve(curve, found[:, i]) for i in range(found.shape[1])), \
            f"mode {j + 1} ({coarse.mode_names[j]}) {curve * 30 / np.pi} rpm is no curve of the 41-value map"


def test_fine_curves_among_the_lowest_at_shared_values_are_on_the_coarse_map(maps):
    """Each 41-value curve that is among the 4 lowest forward critical speeds at one of the 5
    shared values is on the 5-value map (the map shows the modes among the lowest at its values)."""
    coarse, fine = maps["coarse"], maps["fine"]
    shared = np.searchsorted(fine.stiffness, COARSE * (1 - 1e-12))
    found = fine.mode_speeds[shared]
    lowest = coarse.speeds                                                           # (5, 4) ranks
    for i in range(found.shape[1]):
        curve = found[:, i]
        if not np.isclose(curve[:, None], lowest, rtol=1e-9, atol=0).any():
            continue
        assert any(_same_curve(curve, coarse.mode_speeds[:, j]) for j in range(coarse.mode_speeds.shape[1])), \
            f"41-value mode {i + 1} ({fine.mode_names[i]}) {curve * 30 / np.pi} rpm missing from the 5-value map"


def test_one_ulp_changes_nothing(maps):
    coarse, ulp = maps["coarse"], maps["ulp"]
    assert ulp.mode_names == coarse.mode_names
    assert ulp.mode_speeds.shape == coarse.mode_speeds.shape
    for j in range(coarse.mode_speeds.shape[1]):
        assert _same_curve(ulp.mode_speeds[:, j], coarse.mode_speeds[:, j]), coarse.mode_names[j]
    assert len(ulp.modes_dataframe()) == len(coarse.modes_dataframe())
