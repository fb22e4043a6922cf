"""The lowest modes' completeness between anchors without the projected roots (``docs/theory.md``
section 17, "Speeds between anchors"): the Gershgorin discs of the projected state matrix in the
nearer anchor's eigenbasis bound how many projected roots lie below a frequency.

Truth from outside the code: numpy's / scipy's eigenvalues of the matrices themselves (random real
matrices near a known diagonalisable one; the projected state matrices of ROSS's
``compressor_example`` built here from ``model.matrices(speed)`` and the sweep's basis), and scipy's
eigenvalues of the full state matrix."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.analysis._lowest_bound import _gershgorin_count

from shaft_models import assert_lowest_are_the_full_models, one_blas_thread as _one_blas_thread

DATA = Path(__file__).parent / "data" / "ross"


def _real_matrix(rng, pairs, reals):
    """A real matrix ``V diag(lam) V^-1`` with the conjugate pairs ``pairs`` and real roots ``reals``
    (its roots, and ``V``, by the real Jordan form ``S blocks S^-1``)."""
    size = 2 * len(pairs) + len(reals)
    blocks = np.zeros((size, size))
    for i, lam in enumerate(pairs):
        blocks[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[lam.real, lam.imag], [-lam.imag, lam.real]]
    for i, lam in enumerate(reals):
        blocks[2 * len(pairs) + i, 2 * len(pairs) + i] = lam
    S = np.eye(size) + 0.3 * rng.standard_normal((size, size))
    return S @ blocks @ np.linalg.inv(S)


def _discs(A_a, A_j):
    """The Gershgorin discs of ``V^-1 A_j V`` in ``A_a``'s eigenbasis (``numpy.linalg.eig``)."""
    lam, V = np.linalg.eig(A_a)
    F = np.linalg.solve(V, A_j @ V)
    diagonal = np.diag(F)
    return diagonal[None], (np.abs(F).sum(axis=1) - np.abs(diagonal))[None]


def _below(A, limit):
    roots = np.linalg.eigvals(A)
    return int(np.sum((roots.imag > 0) & (roots.imag < limit)))


@pytest.mark.parametrize("reals", [[], [-0.5, -20.0]])
def test_the_count_bounds_the_roots_below_any_frequency(reals):
    """For random changes of a real matrix with roots at frequencies 1 to 10 (with two real roots, or
    none), the count is never below the number of eigenvalues with ``0 < Im < limit``; without real
    roots it equals it where the discs are apart (the smaller changes). A real root's disc reaches
    the real axis and is counted (the count can only be too high)."""
    rng = np.random.default_rng(7)
    pairs = [complex(-0.05 * f, f) for f in range(1, 11)]
    A = _real_matrix(rng, pairs, reals)
    exact = 0
    for scale in (1e-4, 1e-3, 1e-2, 3e-2, 1e-1):
        for _ in range(8):
            changed = A + scale * rng.standard_normal(A.shape)
            centers, radii = _discs(A, changed)
            for limit in (0.5, 2.5, 5.5, 9.5, 12.0):
                truth = _below(changed, limit)
                count = _gershgorin_count(centers, radii, np.array([limit]))[0]
                assert count >= truth, (scale, limit)
                exact += count == truth
    if not reals:
        assert exact >= 80, exact          # of 200 (90 with this seed)


def test_a_root_entering_from_above_is_counted():
    """A root above the limit at the anchor (frequency 6) pulled below it (to 4.4) by the change:
    the count rises from 3 to 4 (the roots at 1, 2, 3), so a certificate asking for at most 3 fails;
    the discs of the anchor alone would not show it."""
    rng = np.random.default_rng(3)
    pairs = [complex(-0.1, f) for f in (1.0, 2.0, 3.0, 6.0, 9.0)]
    A = _real_matrix(rng, pairs, [])
    lam, V = np.linalg.eig(A)
    moved = lam.copy()
    moved[np.isclose(lam, pairs[3])] = complex(-0.1, 4.4)
    moved[np.isclose(lam, np.conj(pairs[3]))] = complex(-0.1, -4.4)
    changed = (V @ np.diag(moved) @ np.linalg.inv(V)).real
    assert _below(A, 5.0) == 3 and _below(changed, 5.0) == 4
    centers, radii = _discs(A, changed)
    assert _gershgorin_count(centers, radii, np.array([5.0]))[0] >= 4
    centers, radii = _discs(A, A + 1e-3 * rng.standard_normal(A.shape))
    assert _gershgorin_count(centers, radii, np.array([5.0]))[0] == 3


SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 201)[1:18]


@pytest.fixture(scope="module")
def sweep():
    """``campbell(modes=12)`` of ROSS's compressor_example at 17 speeds (anchors 0, 8, 16 solved by
    eig, 4 and 12 by their projected roots, the rest by the discs), with what the certificate saw."""
    from rotordyn_modal.io.ross_file import read_ross_rotor

    path = DATA / "compressor_example.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    seen = {}
    certified, expansions = _lowest._certified, _lowest._Expansions

    def recording(ex, places, values, moved, count):
        result = certified(ex, places, values, moved, count)
        seen.setdefault("certified", []).append((ex, places, values.copy(), moved, count, result))
        return result

    def keeping(pencils, basis, *args):
        seen["basis"] = basis
        return expansions(pencils, basis, *args)

    _lowest._certified, _lowest._Expansions = recording, keeping
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = rdm.campbell(model, SPEEDS, critical=False, modes=12)
    finally:
        _lowest._certified, _lowest._Expansions = certified, expansions
    return model, result, seen, [str(warning.message) for warning in caught]


def _projected_state(model, basis, speed):
    """The projected state matrix ``[[0, I], [-W^T K W, -W^T (C + Omega G) W]]`` from the model's
    own matrices (``W^T M W = I``)."""
    M, C, G, K = model.matrices(speed)
    m = basis.shape[1]
    assert np.allclose(basis.T @ M @ basis, np.eye(m), atol=1e-9)
    return np.block([[np.zeros((m, m)), np.eye(m)], [-basis.T @ K @ basis, -basis.T @ (C + speed * G) @ basis]])


def test_the_certified_speeds_have_no_more_projected_roots_below_the_limit(sweep):
    """At every speed the discs certify, the projected pencil (scipy's eigenvalues) has at most 12
    roots with ``0 < Im < T`` (``T``: the 12th root found plus twice the anchors' projection error);
    and with ``T`` raised past its 13th root, the discs' count exceeds 12 (a root that could stand
    for a missed one is seen)."""
    model, _, seen, _ = sweep
    ex, places, values, moved, count, result = seen["certified"][0]
    between = ex.between[places]
    assert result.all() and len(between) == 12
    right = np.clip(np.searchsorted(ex.solved, between), 1, len(moved) - 1)
    limit = np.sort(values[between].imag, axis=1)[:, count - 1] + 2 * np.maximum(moved[right - 1], moved[right])
    above = np.empty(len(between))
    for row, (speed, top) in enumerate(zip(ex.speeds[between], limit)):
        with _one_blas_thread():
            roots = scipy.linalg.eigvals(_projected_state(model, seen["basis"], speed))
        frequencies = np.sort(roots.imag[roots.imag > 0])
        assert np.sum(frequencies < top) <= count
        above[row] = frequencies[count] * 1.001
    counts = _gershgorin_count(ex.centers[places], ex.radii[places], above)
    assert np.all(counts > count)
    # roots found 50 % higher put T above the 13th projected root (8,975 against 6,470 rad/s): no speed passes
    assert not _lowest._certified(ex, places, values * 1.5, moved, count).any()


def test_the_lowest_twelve_are_the_full_models_to_1e_9(sweep):
    """The 12 lowest roots at every speed equal scipy's eigenvalues of the full state matrix to 1e-9,
    no speed solved whole."""
    model, result, _, caught = sweep
    assert not [message for message in caught if "solved whole" in message]
    for row, speed in enumerate(SPEEDS):
        assert_lowest_are_the_full_models(model, speed, result.eigenvalues[row])
