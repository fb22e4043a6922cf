"""Roots of multiplicity three or more in the full eigen-solve (issue 28 §4): two identical,
uncoupled shafts at rest have every bending root four times (two rotors, two whirl directions
each). ``_eigensolve.resolve_repeated`` made a double root's shapes its backward and forward
whirl combinations but left groups of three or more as LAPACK gave them: whirl ratios anywhere in
[-1, 1], labels that changed from rest to the next speed.

Truth from outside the code: scipy's eigenvalues of the full state matrix, and symmetry: each
rotor's double root at rest is a circular backward orbit (whirl ratio -1) and a circular forward
one (+1), so the group of four holds two of each, and once the rotors turn the backward pair
falls and the forward pair rises (each a double root of the two identical rotors).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve, _whirl
from rotordyn_modal.linear_system import speed_linear_form

from test_lowest_cut_in_double_root import _twin_shafts
from test_lowest_modes import _lowest_by_scipy

SPEEDS = np.array([0.0, 20.0, 40.0])


@pytest.fixture(scope="module")
def twins():
    model = _twin_shafts()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return model, rdm.campbell(model, SPEEDS, critical=False), _lowest_by_scipy(model, SPEEDS, 12)


def _groups_at_rest(reference):
    """The first places of each group of four coinciding roots at rest (by frequency)."""
    lam = reference[0]
    return [j for j in range(0, len(lam) - 3, 4) if np.ptp(lam[j:j + 4]) < 1e-9 * abs(lam[j])]


def test_groups_of_four_at_rest_are_two_backward_then_two_forward(twins):
    model, result, reference = twins
    groups = _groups_at_rest(reference)
    assert groups[:3] == [0, 4, 8]                   # the model does have them
    at_rest = result.eigenvalues[0]
    for j in groups:
        # campbell's columns at rest are by frequency: the group's places are scipy's roots
        assert np.max(np.abs(at_rest[j:j + 4] - reference[0, j:j + 4])) < 1e-9 * abs(reference[0, j])
        assert np.allclose(result.whirl_ratios[0, j:j + 4], [-1, -1, 1, 1], atol=1e-6), result.whirl_ratios[0, j:j + 4]


def test_a_group_at_rest_goes_on_as_the_split_roots(twins):
    """Each tracked mode of a group keeps its whirl once the rotors turn: the two backward ones
    go on as the lower (backward) double root, the forward ones as the upper."""
    model, result, reference = twins
    for j in _groups_at_rest(reference):
        for column in range(j, j + 4):
            labels = set(result.whirl[:, column])
            assert len(labels) == 1, (column, result.whirl[:, column])
        lower, upper = result.eigenvalues[1:, j:j + 2], result.eigenvalues[1:, j + 2:j + 4]
        assert np.all(lower.imag < reference[0, j].imag) and np.all(upper.imag > reference[0, j].imag)
        # and they are scipy's split roots
        assert np.max(np.abs(np.sort_complex(-1j * lower[0]) - np.sort_complex(-1j * reference[1, j:j + 2]))) \
            < 1e-9 * abs(reference[1, j])


def test_any_basis_of_the_group_gives_the_same_whirl_sorted_shapes(twins):
    """The resolved shapes do not depend on the basis the solver gave: a random unitary mixing
    of the group's four shapes resolves to shapes of ratios -1, -1, +1, +1 that span the same
    backward and forward planes as the solve's own (principal angles ~0)."""
    model, _, _ = twins
    form = speed_linear_form(model)
    forms = _whirl.whirl_forms(model)
    lam, shapes = _eigensolve.upper_shapes(form.at(np.array([0.0])), form.n_dof, mass=form.matrices.M)
    own = _eigensolve.resolve_repeated(lam, shapes, forms)
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(4, 4)) + 1j * rng.normal(size=(4, 4)))
    mixed = shapes.copy()
    mixed[0, 0:4] = (shapes[0, 0:4].T @ q).T
    again = _eigensolve.resolve_repeated(lam, mixed, forms)
    assert again is not mixed and np.array_equal(mixed[0, 0:4], (shapes[0, 0:4].T @ q).T)   # input left as it was
    # whirl ratio Re(-i phi^H W phi) / phi^H N phi of each shape (docs/theory.md)
    ratios = np.array([(-1j * p.conj() @ forms.W @ p).real / (p.conj() @ forms.N @ p).real for p in again[0, 0:4]])
    for half in (slice(0, 2), slice(2, 4)):
        a, b = own[0, half].T, again[0, half].T
        overlap = np.linalg.svd(np.linalg.qr(a)[0].conj().T @ np.linalg.qr(b)[0], compute_uv=False)
        assert np.min(overlap) > 1 - 1e-9, overlap
    assert np.allclose(ratios, [-1, -1, 1, 1], atol=1e-6), ratios
