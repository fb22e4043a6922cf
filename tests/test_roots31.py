"""Exact roots where the polish's budget stopped (issue 27 §1, issue 28 §4: "eigenvalues equal to
those of the full model to 1e-9 relative").

Friswell et al. Example 5.9.4 as ROSS builds it, at rest: a cross-coupled kxy alone makes K
block-triangular, so every root is a defective double root (a Jordan block), which the dense solve
splits by about the square root of its round-off. Each split pair costs the polish about 4 of the
speed's eigen-solves at 28 coordinates; the budget (10 a speed) polished the lowest five pairs and
left modes 11 to 20 split: modes 11 and 12 1.5e-9 off, silently (their bound, 5.9e-9, was under the
warning's 1e-6). A split pair the budget leaves is now made its mean (exact to first order: the
split is symmetric about the double root), where the mean's own error, measured on the pencil,
is within 1e-9: every mode within 1e-13.

Truth from outside the code: 50-digit Newton solves (mpmath) of the same M, C, G, K. The test
checks that the pencil is block-triangular (two planes that M couples nowhere, K one way only), so
its roots are exactly those of its two diagonal blocks, whose roots are simple: Newton's steps on
each block converge quadratically.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import mpmath
import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.csgraph

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

ROSS = Path(__file__).parent / "data" / "ross"


@pytest.fixture(scope="module")
def friswell_5_9_4(tmp_path_factory):
    path = tmp_path_factory.mktemp("roots31") / "friswell_5_9_4.toml"
    assert main(["import-ross", str(ROSS / "friswell_5_9_4.toml"), "--out", str(path), "--quiet"]) == 0
    return rdm.load_model(path)


def _planes(M, D, K):
    """The two sets of coordinates M and D never couple and K couples one way only (index arrays)."""
    count, label = scipy.sparse.csgraph.connected_components(scipy.sparse.csr_matrix((np.abs(M) + np.abs(D)) > 0))
    assert count == 2
    a, b = np.flatnonzero(label == 0), np.flatnonzero(label == 1)
    assert not np.any(K[np.ix_(b, a)]) or not np.any(K[np.ix_(a, b)])     # block-triangular
    return a, b


def _newton50(M, D, K, root):
    """The root of ``M s^2 + D s + K`` (a diagonal block: simple roots) that 50-digit Newton steps on
    the bordered system reach from ``root`` [1/s]."""
    mpmath.mp.dps = 50
    n = len(M)
    Mm, Dm, Km = (mpmath.matrix(A.tolist()) for A in (M, D, K))
    T = root * root * M + root * D + K
    x = np.linalg.svd(T)[2][-1].conj()                       # the start's null vector
    lam, xs = mpmath.mpc(complex(root)), mpmath.matrix([mpmath.mpc(complex(v)) for v in x])
    fixed = xs.copy()
    for _ in range(40):
        Tm, dT = lam * lam * Mm + lam * Dm + Km, 2 * lam * Mm + Dm
        J = mpmath.zeros(n + 1, n + 1)
        for i in range(n):
            for j in range(n):
                J[i, j] = Tm[i, j]
        slope, residual = dT * xs, Tm * xs
        for i in range(n):
            J[i, n], J[n, i] = slope[i], mpmath.conj(fixed[i])
        step = mpmath.lu_solve(J, mpmath.matrix([-residual[i] for i in range(n)] + [0]))
        for i in range(n):
            xs[i] += step[i]
        lam += step[n]
        if abs(step[n]) < mpmath.mpf(10) ** -45 * abs(lam):
            return complex(lam)
    raise AssertionError("no convergence")


@pytest.fixture(scope="module")
def truth(friswell_5_9_4):
    """The 28 roots (Im > 0) of the model at rest, 50 digits, from the uncoupled rotor's double roots."""
    M, C, G, K = (np.asarray(A) for A in friswell_5_9_4.matrices(0.0))
    D = C                                                      # at rest: no gyroscopic term
    roots = []
    for plane in _planes(M, D, K):
        block = [A[np.ix_(plane, plane)] for A in (M, D, K)]
        # starts: the block's roots in double (simple roots of an undamped, uncoupled plane)
        start = np.sqrt(np.linalg.eigvals(np.linalg.solve(block[0], block[2])).astype(complex)) * 1j
        roots += [_newton50(*block, s) for s in start]
    roots = np.array(roots)
    return roots[np.argsort(roots.imag)]


def _errors(found, truth):
    """Each root's relative distance to the nearest root of ``truth``, and each truth root's count of
    found roots nearest it (a double root is found twice)."""
    found = np.asarray(found)
    found = found[np.argsort(found.imag)]
    nearest = np.argmin(np.abs(found[:, None] - truth[None, :]), axis=1)
    return np.abs(found - truth[nearest]) / np.abs(truth[nearest]), np.bincount(nearest, minlength=len(truth))


def test_every_mode_at_rest_is_exact_in_modes(friswell_5_9_4, truth):
    """Main: modes 11 to 20 1.5e-9, 1.1e-9, 1.4e-9, 4.6e-10, 3.0e-10 off (11 and 12 over the 1e-9 the
    issue asks), the lowest ten within 5e-14 (polished), without a warning. The pairs past the
    polish's budget are their means, within the 1e-9 asked: how far within depends on the
    round-off of the dense solve's split, that is on the BLAS kernels (OpenBLAS's SkylakeX kernels:
    modes 11 to 20 within 2.3e-15; its Haswell kernels, on an AMD EPYC: 2.2e-10; session 46)."""
    assert len(truth) == 28 and np.all(truth.imag > 0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.modal(friswell_5_9_4, 0.0)
    roots = result.eigenvalues[result.oscillatory]
    assert len(roots) == 28
    error, _ = _errors(roots, truth)
    assert error[:10].max() < 1e-13, error
    assert error.max() < 1e-9, error
    assert not [w for w in caught if "exact only to" in str(w.message)]


def test_every_mode_at_rest_is_exact_in_the_campbell_diagram(friswell_5_9_4, truth):
    """The sweep's polish, with its whirl forms: the same (main: 1.5e-9 for modes 11 and 12; modes
    11 to 20 as in ``modes``, within 1e-9 by their BLAS kernels' round-off)."""
    sweep = rdm.campbell(friswell_5_9_4, np.array([0.0, 10.0]), orders=(1,), critical=False)
    roots = sweep.eigenvalues[0][sweep.oscillatory[0]]
    error, _ = _errors(roots, truth)
    assert error[:10].max() < 1e-13, error
    assert error.max() < 1e-9, error


# -- a big machine's roots past the polish's budget: named, each with its own error ------------------

def _refined40(M, D, K, root, shape):
    """The root of ``M s^2 + D s + K`` near ``root`` [1/s] (shape (n,) its start): Newton's steps on
    the bordered system with the residual ``T(s) x`` in 40-digit arithmetic (mpmath, over each
    row's nonzeros; ``x`` and ``s`` kept in it) and the correction from a double LU at the current
    iterate (iterative refinement: each step gains the root's error over its gap, and the limit is
    the exact root of the pencil, not of a rounded one). The correction's LU is SuperLU's of the
    bordered matrix (sparse: the pencils are banded; a dense LU of a 625-coordinate shaft's took
    most of a test's time), and each row's sum is ``mpmath.fdot`` (the products exact, one
    rounding): the limit is the same root, the residual's."""
    import scipy.sparse
    import scipy.sparse.linalg

    mpmath.mp.dps = 40
    n = len(M)
    rows = [[[(j, mpmath.mpf(float(A[i, j]))) for j in np.flatnonzero(A[i])] for i in range(n)] for A in (M, D, K)]
    c = np.asarray(shape) / np.linalg.norm(shape)
    x, lam = [mpmath.mpc(complex(v)) for v in c], mpmath.mpc(complex(root))
    Ms, Ds, Ks = (scipy.sparse.csr_matrix(np.asarray(A, dtype=complex)) for A in (M, D, K))
    gauge_row = scipy.sparse.csr_matrix(c.conj()[None, :])
    for _ in range(30):
        s, xd = complex(lam), np.array([complex(v) for v in x])
        J = scipy.sparse.bmat([[Ms * (s * s) + Ds * s + Ks, ((2 * s) * Ms + Ds) @ xd[:, None]], [gauge_row, None]],
                              format="csc")
        products = [[mpmath.fdot((a, x[j]) for j, a in row[i]) for i in range(n)] for row in rows]
        residual = [lam * lam * products[0][i] + lam * products[1][i] + products[2][i] for i in range(n)]
        gauge = mpmath.fsum(mpmath.conj(mpmath.mpc(complex(c[i]))) * x[i] for i in range(n)) - 1
        d = scipy.sparse.linalg.splu(J).solve(-np.array([complex(v) for v in residual] + [complex(gauge)]))
        x = [x[i] + d[i] for i in range(n)]
        lam += d[n]
        if abs(d[n]) < 1e-32 * abs(s):
            return complex(lam)
    raise AssertionError("no convergence")


def test_roots_the_budget_leaves_are_each_named_with_their_error(monkeypatch):
    """The 10 m shaft with six 1 mm sections (624 coordinates) at 3,000 rpm has 46 roots over
    1e-9; the budget (2 eigen-solves a speed from about 540 coordinates) polishes three, and polishing
    all 46 costs 12 to 14 times the eigen-solve. Main warned of modes 4 to 10 only (those over
    1e-6) with one bound for all, and said nothing of modes 11 and 12, 1.0e-7 off a 40-digit solve.
    Now its line gives every mode left over 1e-9 its own bound, at least its error. (Since roots32
    the sparse polish takes all 46 within the budget: the budget is set to 0 here, so that every
    root is left.)"""
    import re

    from rotordyn_modal.analysis import _eigensolve
    from test_exact_roots27p import _cut_shaft

    monkeypatch.setattr(_eigensolve, "polish_budget", lambda n: 0.0)
    model = _cut_shaft()
    assert model.dofs.n > 540
    speed = rdm.rpm(3000.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.modal(model, speed)
    said = [str(w.message) for w in caught if "exact only to" in str(w.message)]
    assert len(said) == 1, said
    each = {int(k): float(e) for k, e in re.findall(r"mode (\d+) ([0-9.]+e[+-]\d+)", said[0])}
    M, C, G, K = (np.asarray(A) for A in model.matrices(speed))
    modes = np.flatnonzero(result.oscillatory)                  # mode N: the N-th oscillating root
    for number in (11, 12):
        index = modes[number - 1]
        root = result.eigenvalues[index]
        exact = _refined40(M, C + speed * G, K, root, result.shapes[index])
        error = abs(root - exact) / abs(exact)
        assert error > 1e-9                                      # unpolished: over the promise
        assert number in each and error <= each[number], (number, error, each)
    assert all(k in each for k in range(4, 13)), each
