"""Two roots closer than double precision can tell apart (issue 27 §1 "silent wrong answers",
issue 28 "eigenvalues equal to those of the full model to 1e-9"): the full solve and the lowest
modes' route polish such a pair together (block Newton on the quadratic pencil,
``_lowest_newton.pair_polished``), and warn of the roots they leave further off than
``_eigensolve.INEXACT_LEVEL``.

Truth from outside the code: (1) the 40-digit mpmath roots of the 10 m shaft with a 1 mm section
at 3,000 rpm, stored in ``test_lowest_unseparated28g`` (recipe in its docstring); (2) two
identical two-mass chains (a stiff link of 1e14 N/m, grounded by 1e3 and 1e3 + 1/32 N/m, every
entry of K exact in double) whose lowest roots are ``sqrt(k / m)`` exactly.
"""

from __future__ import annotations

import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve
from rotordyn_modal.errors import ModelWarning

from test_input_families10 import _shaft_model
from test_lowest_unseparated28g import TRUTH_HZ

SPEED = rdm.rpm(3000.0)


def _model(tmp_path):
    return rdm.load_model(_shaft_model(tmp_path / "shaft.toml", [(5.0, 0.05), (0.001, 0.05), (4.999, 0.05)],
                                       [1.0, 9.0], 1e3, element_length=1.0))


def _caught(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call()
    return result, [w for w in caught]


def _lowest_four(frequencies):
    return np.sort(np.asarray(frequencies))[:4]


def test_full_campbell_separates_the_pair(tmp_path):
    """Main: the full solve's pair 6.6e-5 and 4.7e-5 off, without a word."""
    result, _ = _caught(lambda: rdm.campbell(_model(tmp_path), np.array([SPEED]), critical=False))
    error = np.abs(_lowest_four(result.frequencies_hz[0]) - TRUTH_HZ) / TRUTH_HZ
    assert error[:2].max() < 1e-9, error
    assert error[2:].max() < 1e-8, error          # the separated roots: eig's own (3e-9), not polished


def test_modal_separates_the_pair(tmp_path):
    result, caught = _caught(lambda: rdm.modal(_model(tmp_path), SPEED))
    error = np.abs(_lowest_four(result.frequencies_hz[result.frequencies_hz > 0]) - TRUTH_HZ) / TRUTH_HZ
    assert error[:2].max() < 1e-9, error


def test_lowest_route_separates_the_pair(tmp_path):
    """Main: the lowest route's pair 6.2e-5 and 1.2e-4 off (its warning said so since 28g)."""
    result, _ = _caught(lambda: rdm.campbell(_model(tmp_path), np.array([SPEED]), modes=4, critical=False))
    error = np.abs(_lowest_four(result.frequencies_hz[0]) - TRUTH_HZ) / TRUTH_HZ
    assert error.max() < 1e-9, error


def test_full_solve_leaves_no_root_inexact(tmp_path):
    """Modes 5 and 6 (single roots, round-off 1.3e-5) were warned of here; since roots27l they are
    polished one at a time (``_lowest_newton.root_polished``): they agree with the lowest route's
    roots (Newton on the pencil with an extended-precision residual, an independent algorithm) to
    1e-9, and nothing is warned (the warning for a root the polish leaves: test_exact_roots27l)."""
    model = _model(tmp_path)
    full, caught = _caught(lambda: rdm.modal(model, SPEED))
    lines = [str(w.message) for w in caught if issubclass(w.category, ModelWarning) and "exact only to" in str(w.message)]
    assert lines == []
    lowest, _ = _caught(lambda: rdm.campbell(model, np.array([SPEED]), modes=6, critical=False))
    mine, theirs = np.sort(full.frequencies_hz[full.frequencies_hz > 0])[:6], np.sort(lowest.frequencies_hz[0])
    distance = np.abs(mine - theirs) / theirs
    assert distance[4:].max() < 1e-9, distance


def _chains(m=1.0, k=1e3, link=1e14):
    """Two uncoupled two-mass chains (M = m I, D = 0): lowest roots sqrt(k/m), sqrt(k_y/m)."""
    ky = k + 2 * 0.015625            # k + link and ky + link exact in double (ulp of 1e14: 1/64)
    K = np.zeros((4, 4))
    for at, spring in ((0, k), (2, ky)):
        K[at:at + 2, at:at + 2] = [[spring + link, -link], [-link, spring + link]]
    return m * np.eye(4), np.zeros((4, 4)), K, np.sqrt(np.array([k, ky]) / m)


def test_a_pair_closer_than_its_round_off_polished_to_closed_form():
    """The full solve's path: QR of the state matrix (numpy's eig, 2e-6 and 1e-5 off for a pair
    1.6e-5 apart whose round-off is 2.2e-5; 8.6e-7 and 6.8e-7 with OpenBLAS's Haswell kernels),
    then :func:`_eigensolve.refined_pairs`."""
    M, D, K, exact = _chains()
    A = np.block([[np.zeros((4, 4)), np.eye(4)], [-K, -D]])
    lam, vectors = np.linalg.eig(A)
    up = np.argsort(np.where(lam.imag > 0, lam.imag, np.inf))[:4]
    values, shapes = lam[up].copy(), vectors[:4, up].T.copy()
    # the case is what it tests: QR's pair far from the 1e-12 asserted below (8.6e-7 with OpenBLAS's
    # Haswell kernels, 1e-5 with SkylakeX's: the round-off's size, not its value, is the case's)
    assert np.abs(values.imag[:2] - exact).max() / exact[0] > 1e-7
    bound = _eigensolve.pencil_round_off(values, shapes, M, D, K)
    assert bound[:2].min() > abs(exact[1] - exact[0]) / exact[0]          # closer than their round-off
    left = _eigensolve.refined_pairs(values, shapes, M, D, K, bound)
    assert np.abs(values[:2] - 1j * exact).max() / exact[0] < 1e-12, values[:2] - 1j * exact
    assert left[:2].max() < 1e-12
    # each shape is its own chain's (the chains are uncoupled): x's root moves x's masses only
    assert np.abs(shapes[0, 2:]).max() < 1e-9 and np.abs(shapes[1, :2]).max() < 1e-9, shapes[:2]
