"""The cut inside a double root on the ``max_frequency`` route (``_lowest.roots_below`` with a
count) and on the route of mounts with Maxwell branches (issue 28 §4). Since track28e the
``modes=N`` route refines a speed whose N-th and (N+1)-th roots are one double root again from
more starts; these two routes still solved that speed whole ("1 of 2 speeds solved whole").

Truth from outside the code: the eigenvalues of the full state matrix (numpy; with the branches'
own states for the Maxwell mounts), and symmetry: an axisymmetric machine at rest has exact
double roots, each a backward and a forward circular whirl, of which the lower half once the rotor
turns is the backward one, so the root kept below the cut at rest whirls backward (ratio -1).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_branches
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.linear_system import state_matrices

from test_lowest_branches import _true_roots

SPEEDS = np.array([0.0, 50.0])


def _axisymmetric_on_maxwell_mounts():
    """A steel shaft (0.8 m, 40 mm, a 4 kg wheel in the middle) on two isotropic bearings in a
    60 kg casing whose inertia is symmetric about the spin axis, on eight equal mounts at four
    places around the axis at each end (isotropic, two Maxwell branches each): the whole machine
    is axisymmetric, so every root at rest whirling about the axis is a double root."""
    k = 4e5
    mounts = [{"name": f"m{i}{j}", "position": [x, y, z], "stiffness": [k, k, k], "damping": [80.0] * 3,
               "maxwell_stiffness": [[0.5 * k] * 3, [k] * 3], "maxwell_time": [0.02, 0.001]}
              for i, x in enumerate((-0.3, 0.3))
              for j, (y, z) in enumerate(((0.2, 0.0), (-0.2, 0.0), (0.0, 0.2), (0.0, -0.2)))]
    return rdm.Model.from_dict({
        "name": "axisymmetric shaft in a casing on Maxwell mounts", "spin_axis": [1.0, 0.0, 0.0],
        "reference_rotor": "a",
        "materials": [{"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
        "stator": {"mass": 60.0, "center_of_mass": [0.0, 0.0, 0.0], "inertia": [[3.0, 0, 0], [0, 2.0, 0], [0, 0, 2.0]]},
        "rotors": [{"name": "a", "start": [-0.4, 0.0, 0.0], "speed_ratio": 1.0, "element_length": 0.05,
                    "shaft": [{"length": 0.8, "outer_diameter": 0.04, "material": "steel"}],
                    "disks": [{"name": "wheel", "axial_position": 0.4, "mass": 4.0, "polar_inertia": 0.25,
                               "diametral_inertia": 0.13}]}],
        "bearings": [{"name": f"b{i}", "rotor": "a", "axial_position": z, "stiffness": 2e7, "damping": 500.0}
                     for i, z in enumerate((0.0, 0.8))],
        "suspensions": mounts})


def _lowest_of_the_state_matrix(model, speeds, count):
    """The ``count`` lowest-frequency oscillating roots of the full state matrix (S, count): numpy."""
    out = []
    for A in state_matrices(model, speeds):
        roots = np.linalg.eigvals(A)
        roots = roots[(roots.imag > 1e-9 * np.abs(roots)) & is_oscillating(roots)]
        out.append(roots[np.argsort(roots.imag)][:count])
    return np.array(out)


def _no_fallback(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call()
    assert not [w for w in caught if "solved whole" in str(w.message)], [str(w.message) for w in caught]
    return result


def _assert_roots(values, reference):
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)[:, :reference.shape[1]]
    assert np.max(np.abs(values - reference) / np.abs(reference)) < 1e-9


@pytest.fixture(scope="module")
def compressor():
    return rdm.load_model("examples/compressor_rotor.toml")


@pytest.mark.parametrize("count", [1, 4, 6])
def test_max_frequency_with_a_count_inside_a_double_root(compressor, count):
    speeds = rdm.rpm(np.array([0.0, 600.0]))
    reference = _lowest_of_the_state_matrix(compressor, speeds, count + 1)
    assert abs(reference[0, count] - reference[0, count - 1]) < 1e-9 * abs(reference[0, count - 1])
    limit = 2 * np.pi * 2000.0
    assert reference[0, count].imag < limit
    values, _, wanted, full = _no_fallback(lambda: _lowest.roots_below(Stack([compressor]), speeds, limit, count))
    assert not full.any() and (wanted.sum(axis=1) == count).all()
    _assert_roots(values[:, :count], reference[:, :count])
    result = _no_fallback(lambda: rdm.campbell(compressor, speeds, critical=False, modes=count, max_frequency=2000.0))
    assert result.whirl_ratios[0, count - 1] == pytest.approx(-1.0, abs=1e-6)


@pytest.fixture(scope="module")
def maxwell():
    model = _axisymmetric_on_maxwell_mounts()
    assert Stack([model]).branch_times.shape[1] and model.dofs.n >= _lowest.DENSE_BELOW
    return model


@pytest.mark.parametrize("count", [2, 5, 9])
def test_maxwell_mounts_with_the_cut_inside_a_double_root(maxwell, count):
    """The roots at the turning speed are the state matrix's refined in extended precision
    (``test_lowest_branches._true_roots``; numpy's own round-off there, ``eps |A|``, reaches 1e-9
    of these roots). At rest the refinement cannot take a double root (its bordered matrix is
    singular there): the roots equal numpy's to its round-off (1e-8 here), and each double root
    found is one: ``A - lam I`` has two singular values at round-off."""
    A = state_matrices(maxwell, SPEEDS)
    reference = _lowest_of_the_state_matrix(maxwell, SPEEDS, count + 1)
    assert abs(reference[0, count] - reference[0, count - 1]) < 1e-8 * abs(reference[0, count - 1])
    values, _, full = _no_fallback(lambda: _lowest_branches.lowest_roots(Stack([maxwell]), SPEEDS, count))
    assert not full.any()
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)
    _assert_roots(values[1:], _true_roots(A[1], count)[None])
    assert np.max(np.abs(values[0] - reference[0, :count]) / np.abs(reference[0, :count])) < 1e-8
    at_cut = values[0, count - 1]
    singular = np.linalg.svd(A[0] - at_cut * np.eye(len(A[0])), compute_uv=False)
    assert singular[-2] < 1e-13 * singular[0], singular[-3:] / singular[0]
    result = _no_fallback(lambda: rdm.campbell(maxwell, SPEEDS, critical=False, modes=count))
    assert result.whirl_ratios[0, count - 1] == pytest.approx(-1.0, abs=1e-6)
