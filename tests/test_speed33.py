"""Cheaper link checks and whirl forms of the lowest modes (issue 28 "How it will be judged": ROSS's
``rotor_example`` at 21 speeds).

* ``campbell``'s checks of its mode links (``campbell._check_roots``) solve a small undamped
  gyroscopic model's roots at up to six sets of finer speeds and compare their shapes by the MAC
  alone. Their shapes now come from the Hermitian matrix's own eigenvectors
  (``_lowest.weighted_lowest_roots``) instead of one complex LU solve per root and a product with
  the mass matrix's factor.
* A flexible rotor's whirl forms build their block diagonals directly (``_whirl._block_diagonal``)
  instead of through ``scipy.sparse.block_diag``'s COO, and multiply the three forms' in one product.

Truth from outside the code: the roots against scipy's eigenvalues of the first-order state matrix,
the shapes against the pencil ``s^2 M + s Omega G + K`` (residual) and against scipy's eigenvectors
of the state matrix (MAC), the block diagonals against ``scipy.sparse.block_diag`` itself, the
forms against the same products written with it.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_pairs, _whirl
from rotordyn_modal.analysis import campbell as campbell_module
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor

ROTOR_EXAMPLE = "tests/data/ross/rotor_example.toml"


def _rotor_example():
    return rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))


def _state_eig(M, G, K, speed):
    """scipy's roots (2 n,) and eigenvectors' displacement part (n, 2 n) of the first-order state
    matrix of ``s^2 M + s speed G + K``."""
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, speed * G)]])
    roots, vectors = scipy.linalg.eig(A)
    return roots, vectors[:n]


@pytest.mark.parametrize("speed", [0.0, 4.6875, 37.5, 150.0, 3000.0])
def test_check_roots_from_hermitian_eigenvectors(speed):
    """The check's 14 lowest roots are the route's own (bit for bit) and the state matrix's (1e-9),
    each shape solves the pencil (relative residual below 1e-12) and is scipy's eigenvector of the
    root, mass-weighted (MAC above 1 - 1e-9)."""
    model = _rotor_example()
    stack = Stack([model])
    found = _lowest.weighted_lowest_roots(stack, np.array([speed]), 14)
    assert found is not None
    lam, weighted = found
    assert lam.shape == (1, 14) and weighted.shape == (1, 14, stack.n_dof)
    np.testing.assert_array_equal(lam, _lowest.lowest_roots(stack, np.array([speed]), 14)[0])   # the route's bits
    M, G, K = stack.M[0], stack.G[0], stack.K[0]
    roots, vectors = _state_eig(M, G, K, speed)
    upper = np.argsort(np.where(roots.imag > 0, roots.imag, np.inf))[:14]
    np.testing.assert_allclose(lam[0], roots[upper], rtol=1e-9)
    L = np.linalg.cholesky(M)                                    # M = L L^T: a weighted shape is L^T x
    for j, s in enumerate(lam[0]):
        w = weighted[0, j]
        assert abs(np.linalg.norm(w) - 1.0) < 1e-12
        x = scipy.linalg.solve_triangular(L.T, w, lower=False)
        pencil = s * s * M + s * speed * G + K
        residual = np.linalg.norm(pencil @ x) / (np.linalg.norm(pencil, 2) * np.linalg.norm(x))
        assert residual < 1e-12, (j, residual)
        reference = L.T @ vectors[:, upper[j]]
        mac = abs(np.vdot(reference, w)) ** 2 / np.vdot(reference, reference).real
        assert mac > 1 - 1e-9, (j, mac)


def test_check_roots_left_to_the_route_elsewhere():
    """A damped model, and a speed where two roots are one (an isotropic rotor at rest: the
    forward and backward modes repeated), are not served: the check takes the route's own roots
    and shapes (its full solve of close roots)."""
    model = _rotor_example()
    data = read_ross_rotor(ROTOR_EXAMPLE)
    stack = Stack([model])
    assert _lowest.weighted_lowest_roots(stack, np.array([0.0, 100.0]), 14) is not None
    damped = rdm.Model.from_dict(read_ross_rotor("tests/data/ross/compressor_example.toml"))
    assert _lowest.weighted_lowest_roots(Stack([damped]), np.array([0.0]), 6) is None
    for bearing in data["bearings"]:                             # isotropic: kxx = kyy (1e6 N/m)
        bearing["stiffness"] = [bearing["stiffness"][0]] * 2
    isotropic = Stack([rdm.Model.from_dict(data)])
    M, G, K = isotropic.M[0], isotropic.G[0], isotropic.K[0]
    roots, _ = _state_eig(M, G, K, 0.0)
    upper = np.sort(roots[roots.imag > 0].imag)
    assert np.min(np.diff(upper[:6]) / upper[1:6]) < 1e-9          # the modes at rest repeated
    assert _lowest.weighted_lowest_roots(isotropic, np.array([0.0]), 6) is None
    assert _lowest.weighted_lowest_roots(isotropic, np.array([300.0]), 6) is not None


def test_links_unchanged_by_the_check_shapes(monkeypatch):
    """The columns (which tracked root is which mode) of ``campbell(modes=12)`` on rotor_example at
    21 speeds are those of the check with the route's own shapes (pencil solves): the check reads
    shapes by their MAC, which a shape's phase and round-off do not move. The check still halves
    the first step down to 150 / 2**5 rad/s."""
    model = _rotor_example()
    speeds = np.linspace(0.0, 3000.0, 21)
    solved = []
    plain = campbell_module._check_roots

    def noted(stack, where, more):
        solved.extend(np.asarray(where, dtype=float).tolist())
        return plain(stack, where, more)

    monkeypatch.setattr(campbell_module, "_check_roots", noted)
    # the halvings these shapes judge: without the bound that settles the first step unhalved (test_speed35)
    monkeypatch.setattr(_lowest_pairs, "pairs_kept", lambda stack, start, stop, ranks: np.zeros(len(ranks), bool))
    now = rdm.campbell(model, speeds, critical=True, modes=12)
    assert 150.0 / 2**5 in solved
    monkeypatch.setattr(_lowest, "weighted_lowest_roots", lambda *args: None)
    before = rdm.campbell(model, speeds, critical=True, modes=12)
    np.testing.assert_array_equal(now.eigenvalues, before.eigenvalues)
    np.testing.assert_array_equal(now.whirl_ratios, before.whirl_ratios)
    assert list(now.critical.speeds) == list(before.critical.speeds)


def test_block_diagonal_is_scipys():
    """``_whirl._block_diagonal`` of stacked dense blocks holds the arrays of
    ``scipy.sparse.block_diag(..., format="csr")`` of each stack, one above the other: every
    entry (zeros too), the same order."""
    rng = np.random.default_rng(33)
    blocks = rng.standard_normal((3, 7, 6, 6))
    blocks[:, :, 2] = 0.0
    blocks[1, 4] = 0.0
    made = _whirl._block_diagonal(blocks)
    expected = scipy.sparse.vstack([scipy.sparse.csr_matrix(scipy.sparse.block_diag(list(b), format="csr"))
                                    for b in blocks], format="csr")
    assert made.shape == expected.shape == (3 * 42, 42)
    np.testing.assert_array_equal(made.indptr, expected.indptr)
    np.testing.assert_array_equal(made.indices, expected.indices)
    np.testing.assert_array_equal(made.data, expected.data)
    single = _whirl._block_diagonal(blocks[0])
    reference = scipy.sparse.csr_matrix(scipy.sparse.block_diag(list(blocks[0]), format="csr"))
    np.testing.assert_array_equal(single.toarray(), reference.toarray())
    np.testing.assert_array_equal(single.indices, reference.indices)


def test_flexible_whirl_forms_as_block_diag_products():
    """A flexible rotor's whirl forms equal, bit for bit, ``T^T (blockdiag(X_i) T)`` written form by
    form with ``scipy.sparse.block_diag`` (rotor_example, 7 nodes), and its node motions
    ``blockdiag(B_i^T) T_rel`` likewise."""
    model = _rotor_example()
    rotor = next(r for r in model.rotors if r.flexible is not None)
    seen, plain, plain_motions = {}, _whirl._block_diagonal, _whirl._node_motions_at_reference

    def kept(blocks):
        seen.setdefault(blocks.ndim, []).append(np.array(blocks))
        return plain(blocks)

    def motions_kept(model_, shaft, relative):
        seen["relative"] = relative
        seen["motions"] = plain_motions(model_, shaft, relative)
        return seen["motions"]

    _whirl._block_diagonal, _whirl._node_motions_at_reference = kept, motions_kept
    try:
        pieces = _whirl._node_pieces(model, rotor)
    finally:
        _whirl._block_diagonal, _whirl._node_motions_at_reference = plain, plain_motions
    (forms,), (shifts,), motions = seen[4], seen[3], seen["motions"]
    assert forms.shape == (3, len(rotor.flexible.node_positions), 6, 6)
    assert model.dofs.n_frame == 0                               # no frame: the node motions are the product
    moved = scipy.sparse.block_diag(list(shifts), format="csr") @ seen["relative"]
    np.testing.assert_array_equal(moved.toarray(), motions.toarray())
    for piece, form in zip(pieces, forms):
        reference = motions.T @ (scipy.sparse.block_diag(list(form), format="csr") @ motions)
        np.testing.assert_array_equal(piece.toarray(), reference.toarray())


def test_close_upper_is_the_routes_whole_test():
    """``_lowest._close_upper`` of ascending frequencies marks the speeds ``_lowest_of_upper``
    solves whole (a root within 1e-4 of its modulus of another or of its conjugate,
    ``lowest_order``'s ties included), and those with a zero root (which the route's zero floor
    solves whole): random spectra with repeated, near and zero frequencies."""
    from rotordyn_modal.analysis._lowest_starts import _close, lowest_order
    from rotordyn_modal.analysis.modal import is_oscillating

    rng = np.random.default_rng(3)
    for count, m in ((1, 5), (4, 5), (5, 5), (14, 28)):
        omega = np.sort(rng.uniform(10.0, 1000.0, (400, m)), axis=1)
        for row in range(0, 400, 4):                                 # a repeated, a near, a zero root
            j = rng.integers(0, m - 1)
            omega[row + 1, j + 1] = omega[row + 1, j]
            omega[row + 2, j + 1] = omega[row + 2, j] * (1 + rng.choice([0.5e-4, 2e-4, 1e-10]))
            omega[row + 3, 0] = 0.0
        omega = np.sort(omega, axis=1)
        upper = 1j * omega
        order = lowest_order(upper, count)[:, :count]
        lam = np.take_along_axis(upper, order, axis=1)
        whole = ~is_oscillating(lam).all(axis=1) | _close(lam, upper, order)
        found = _lowest._close_upper(omega, count)
        zero = omega[:, 0] == 0.0                   # solved whole by the zero floor (_near_zero) anyway
        np.testing.assert_array_equal(found[~zero], whole[~zero])
        assert found[zero].all() and zero.any()
        assert whole[~zero].any() and not whole[~zero].all()
