"""The Hermitian route's eigenvalues (``_lowest._hermitian_eigenvalues``, issue 28 §4) in real
arithmetic: ``B = i S`` with ``S`` real skew, reduced to a skew tridiagonal by an orthogonal
Hessenberg reduction. Truth from outside the code: matrices built with known eigenvalues
(rotated 2 x 2 rotation blocks), and scipy's complex ``eigh`` of the same Hermitian matrix."""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.stats

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.io.ross_file import read_ross_rotor

ROTOR_EXAMPLE = "tests/data/ross/rotor_example.toml"


def _skew_with(frequencies, seed):
    """A real skew matrix (2 m, 2 m) whose eigenvalues are ``+-i frequencies`` (m,): rotation
    generators ``[[0, -w], [w, 0]]`` on the diagonal, turned by a random orthogonal matrix."""
    m = len(frequencies)
    blocks = np.zeros((2 * m, 2 * m))
    for k, w in enumerate(frequencies):
        blocks[2 * k, 2 * k + 1], blocks[2 * k + 1, 2 * k] = -w, w
    turn = scipy.stats.ortho_group.rvs(2 * m, random_state=seed)
    skew = turn @ blocks @ turn.T
    return 0.5 * (skew - skew.T)


def test_eigenvalues_of_a_skew_matrix_are_its_rotation_frequencies():
    """``i S`` of known ``+-w`` over four decades: every eigenvalue within ``4 n eps |S|`` of its
    closed form, in ascending order; a second term ``speed * gyroscopic`` added as the route adds it."""
    frequencies = np.geomspace(1.0, 1e4, 14)
    skew = _skew_with(frequencies, 7)
    speeds = np.array([0.0, 1.0, 2.5])
    zero = np.zeros_like(skew)
    found = _lowest._hermitian_eigenvalues(1j * skew, zero + 0j, speeds)
    truth = np.sort(np.concatenate([-frequencies, frequencies]))
    bound = 4 * len(skew) * np.finfo(float).eps * np.linalg.norm(skew, 2)
    assert found.shape == (3, 28)
    assert np.max(np.abs(found - truth)) <= bound
    # the speed's term: S_0 + speed S_1 is the known matrix at speed 2.5 when S_1 = S / 2.5, S_0 = 0
    at = _lowest._hermitian_eigenvalues(zero + 0j, 1j * skew / 2.5, speeds[2:])
    assert np.max(np.abs(at[0] - truth)) <= bound


def test_route_eigenvalues_equal_complex_eigh_of_the_hermitian_matrix():
    """rotor_example's ``B(Omega)`` (56 states) at five speeds: within ``8 n eps |B|`` of scipy's
    complex ``eigh`` of the same matrix (both are backward stable: the bound is their round-off)."""
    from rotordyn_modal.analysis._stack import Stack

    model = rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))
    constant, gyroscopic = _lowest._hermitian_form(Stack([model]))
    speeds = np.linspace(0.0, 1500.0, 5)
    found = _lowest._hermitian_eigenvalues(constant, gyroscopic, speeds)
    for speed, values in zip(speeds, found):
        B = constant + speed * gyroscopic
        reference = scipy.linalg.eigh(B, eigvals_only=True)
        assert np.max(np.abs(values - reference)) <= 8 * len(B) * np.finfo(float).eps * np.linalg.norm(B, 2)


def test_campbell_of_rotor_example_makes_no_complex_hermitian_solve(monkeypatch):
    """``campbell(modes=12)`` of rotor_example takes its roots from the real reduction: no complex
    ``eigvalsh`` of the 56-state Hermitian matrices (a complex reduction: 1.5 times the work)."""
    model = rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))
    sizes, plain = [], np.linalg.eigvalsh

    def recording(a, *args, **kwargs):
        sizes.append(np.shape(a)[-1])
        return plain(a, *args, **kwargs)

    monkeypatch.setattr(np.linalg, "eigvalsh", recording)
    result = rdm.campbell(model, np.linspace(0.0, 1500.0, 11), critical=False, modes=12)
    assert 2 * model.dofs.n not in sizes
    assert np.all(result.eigenvalues[1:].real == 0)
