"""The lowest modes by shift-invert Arnoldi (the crowded route, ``_arnoldi``) of an axisymmetric
machine at rest, where every root is a double root and the requested count may cut one (issue 28
§4; lowest28g added the retry to ``roots_below`` and the Maxwell route). Main solved every such
speed whole ("1 of 2 speeds solved whole"): ARPACK gives a double root's two copies apart by its
own error, which Newton's iteration then moved them by (the start's "own root" check), and
ARPACK's own count ``k`` cutting inside a group of four equal-modulus roots ended without
convergence.

Truth from outside the code: numpy's eigenvalues of the full state matrix, and symmetry: 30
rigid rotors each on two isotropic bearings (no coupling between them, axisymmetric) have at rest
only double roots, each a backward and a forward circular whirl; the lower half once the rotor
turns is the backward one, so the root kept below a cut inside a double root whirls backward
(ratio -1), as the reduced route and the full solve keep it.
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _arnoldi, _lowest, _lowest_route
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.linear_system import state_matrices
from test_cut_in_double_root_routes28g import _no_fallback

SPEEDS = np.array([0.0, 50.0])


def _row_of_rotors(count=30, seed=2):
    """``count`` rigid rotors (5-30 kg) side by side, each on two isotropic bearings of its own
    stiffness (1e7-5e7 N/m, damping 1e-4 s times it), nothing between them: 4 coordinates each."""
    rng = np.random.default_rng(seed)
    rotors, bearings = [], []
    for j in range(count):
        mass = rng.uniform(5.0, 30.0)
        polar = mass * rng.uniform(0.002, 0.01)
        centre = [0.0, j * 0.5, 0.0]
        rotors.append({"name": f"r{j:02d}", "mass": mass, "center_of_mass": centre, "polar_inertia": polar,
                       "diametral_inertia": polar * rng.uniform(0.6, 2.0), "speed_ratio": 1.0 + 0.1 * j})
        k = rng.uniform(1e7, 5e7)
        for side, offset in (("DE", 0.1), ("NDE", -0.12)):
            bearings.append({"name": f"r{j:02d}-{side}", "rotor": f"r{j:02d}", "position": [offset, centre[1], 0.0],
                             "stiffness": k, "damping": 1e-4 * k})
    return rdm.Model.from_dict({"name": "row of rotors", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "r00",
                                "rotors": rotors, "bearings": bearings})


@pytest.fixture(scope="module")
def row():
    model = _row_of_rotors()
    stack = Stack([model])
    assert stack.n_dof >= _arnoldi.MIN_DOF and _lowest_route._crowded(stack, _Pencils(stack, SPEEDS), count=5)
    return model


def _reference(model, count):
    out = []
    for A in state_matrices(model, SPEEDS):
        roots = np.linalg.eigvals(A)
        roots = roots[roots.imag > 1e-9 * np.abs(roots)]
        out.append(roots[np.argsort(roots.imag)][:count + 1])
    return np.array(out)


@pytest.mark.parametrize("count", [1, 3, 5])
def test_lowest_route_cut_inside_a_double_root(row, count):
    reference = _reference(row, count)
    assert abs(reference[0, count] - reference[0, count - 1]) < 1e-9 * abs(reference[0, count - 1])   # the cut
    values, _, full = _no_fallback(lambda: _lowest.lowest_roots(Stack([row]), SPEEDS, count))
    assert not full.any()
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)
    assert np.max(np.abs(values - reference[:, :count]) / np.abs(reference[:, :1])) < 1e-9
    result = _no_fallback(lambda: rdm.campbell(row, SPEEDS, critical=False, modes=count))
    assert result.whirl_ratios[0, count - 1] == pytest.approx(-1.0, abs=1e-6)
    assert result.whirl[0, count - 1] == "backward"


def test_max_frequency_route_cut_inside_a_double_root(row):
    count = 3
    reference = _reference(row, count)
    limit = 2 * reference[0, count].imag
    values, _, wanted, full = _no_fallback(lambda: _lowest.roots_below(Stack([row]), SPEEDS, limit, count))
    assert not full.any() and (wanted.sum(axis=1) == count).all()
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)[:, :count]
    assert np.max(np.abs(values - reference[:, :count]) / np.abs(reference[:, :1])) < 1e-9
    result = _no_fallback(lambda: rdm.campbell(row, SPEEDS, critical=False, modes=count,
                                               max_frequency=limit / (2 * np.pi)))
    assert result.whirl_ratios[0, count - 1] == pytest.approx(-1.0, abs=1e-6)
