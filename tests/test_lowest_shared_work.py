"""Work the lowest modes' sweep no longer does twice, and products it now takes by entries
(issue 28's speed against ROSS), on ROSS's ``compressor_example`` (224 coordinates).

- one dense ``eigh`` of ``(K_0, M)`` for both the cheap route test and the completeness bound's
  basis (two before), its modes those of scipy's ``eigh`` computed here;
- the whirl ratios of a flexible shaft summed over the forms' nonzero entries, equal to the
  ratios of the dense forms computed here;
- the discs of the speeds between anchors (centres ``lam + F_ii``, radii ``sum |F_il|``) equal
  to ``F = V^-1 (A_j - A_a) V`` formed here from the two projected state matrices.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_starts, _whirl
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor

PATH = Path(__file__).parent / "data" / "ross" / "compressor_example.toml"
#: within the file's bearing tables (6,000-10,000 rpm) [rad/s]
SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 17)


@pytest.fixture(scope="module")
def model():
    return rdm.Model.from_dict(read_ross_rotor(PATH), source=PATH)


def test_one_dense_eigh_serves_the_route_test_and_the_basis(model, monkeypatch):
    """The sweep solves the undamped modes of ``(K_0, M)`` once (n x n), and the basis it keeps
    equals scipy's ``eigh`` of the symmetric stiffness at the first speed and the mass."""
    n = model.dofs.n
    square = []
    plain = scipy.linalg.eigh

    def counted(a, b=None, *args, **kwargs):
        if np.shape(a) == (n, n):
            square.append(1)
        return plain(a, b, *args, **kwargs)

    monkeypatch.setattr(scipy.linalg, "eigh", counted)
    stack = Stack([model])
    _lowest.lowest_roots(stack, SPEEDS, 12)
    assert len(square) == 1
    monkeypatch.setattr(scipy.linalg, "eigh", plain)
    matrices = model.matrices(SPEEDS[0])
    K, M = np.asarray(matrices.K), np.asarray(matrices.M)
    symmetric = 0.5 * (K + K.T)
    values, vectors = scipy.linalg.eigh(symmetric, M)
    omegas, modes, _ = stack.lowest_basis["basis"]
    assert np.allclose(omegas, np.sqrt(np.maximum(values, 0.0)), rtol=1e-9, atol=0.0)
    # each mode up to its sign: the first 40 (the basis' and the bound's), mass-normalised
    dots = np.einsum("ij,ij->j", modes[:, :40], M @ vectors[:, :40])
    assert np.allclose(np.abs(dots), 1.0, atol=1e-8)


def test_whirl_ratios_by_entries_equal_the_dense_forms(model):
    """A flexible shaft's whirl forms go by their entries; the ratios of random complex shapes
    equal those of the dense forms' quadratic products."""
    stack = Stack([model])
    rng = np.random.default_rng(28)
    shapes = rng.standard_normal((5, 12, model.dofs.n)) + 1j * rng.standard_normal((5, 12, model.dofs.n))
    speeds = np.linspace(100.0, 900.0, 5)
    got = stack.whirl_ratios(shapes, np.zeros(5, int), speeds)
    assert isinstance(stack._whirl_stacked[0], _whirl.EntryForms)
    forms = _whirl.whirl_forms(model)
    quadratic = [np.einsum("rki,ij,rkj->rk", shapes.conj(), form, shapes) for form in forms]
    expected = np.clip(quadratic[0].imag / quadratic[1].real, -1.0, 1.0)
    assert np.allclose(got, expected, rtol=0.0, atol=1e-13)


def test_discs_between_anchors_equal_the_dense_change(model):
    """The discs of every speed between anchors from ``F = V^-1 (A_j - A_a) V`` with ``A_j``, ``A_a``
    the projected state matrices at the speed and at its nearer solved anchor, ``V`` the
    anchor's eigenvectors (the decomposition's own error added to the radii is at round-off)."""
    stack = Stack([model])
    pencils = _Pencils(stack, SPEEDS)
    matrices = model.matrices(SPEEDS[0])
    K, M = np.asarray(matrices.K), np.asarray(matrices.M)
    basis = scipy.linalg.eigh(0.5 * (K + K.T), M)[1][:, :30]
    grid = _lowest_starts._anchors(len(SPEEDS))
    solved = np.unique(np.append(grid[::2], grid[-1]))
    levels = [(np.setdiff1d(grid, solved), solved), (np.setdiff1d(np.arange(len(SPEEDS)), grid), grid)]
    expansions = _lowest_starts._Expansions(pencils, basis, solved, 13, levels)
    assert len(expansions.between) == len(SPEEDS) - len(solved)
    for place, speed in enumerate(expansions.between):
        anchor = solved[expansions.near[place]]
        A_a, A_j = (_lowest_starts._state_matrices(pencils, np.array([at]), solved[0], *expansions.first)[0]
                    for at in (anchor, speed))
        lam, V = np.linalg.eig(A_a)
        F = np.linalg.solve(V, (A_j - A_a) @ V)
        diagonal = np.diag(F)
        scale = np.max(np.abs(lam))
        assert np.allclose(expansions.centers[place], lam + diagonal, rtol=0.0, atol=1e-9 * scale)
        radii = np.abs(F).sum(axis=1) - np.abs(diagonal)
        assert np.all(expansions.radii[place] >= radii - 1e-9 * scale)
        assert np.allclose(expansions.radii[place], radii, rtol=0.0, atol=1e-6 * scale)
