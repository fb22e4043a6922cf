"""Whirl labels and real roots after the polish (issue 27 sections 1 and 3, "whirl labels of
near-planar modes flip with noise").

rubber_mounts with a 1e-12 s Maxwell branch: the state matrix's norm is 7e12 1/s, so the dense
solve knows the mount modes to about 1e-4 and their shapes' whirl ratios to 3e-2; every mode is
then polished on the rational pencil. The truth here is a 50-digit Newton solve (mpmath) of that
pencil, ``M s^2 + D s + K + sum_t K_t s tau_t / (1 + s tau_t)``, each root's last step below 1e-45
of it.

- A polished mode's whirl label was still decided by the solve's round-off: mode 1, whose ratio
  is 2.2e-3 to 1.3e-2 (500 to 3000 rpm), read 'none' in every route. Its own round-off decides.
- Real roots (the mounts' relaxations) were not polished: `modes` warned of them, 7e-6 to 3e-4
  off. They are polished by a real Newton on the pencil.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import mpmath
import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve, _whirl
from rotordyn_modal.linear_system import speed_linear_form

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def fast_branch(tmp_path_factory):
    text = (EXAMPLES / "rubber_mounts.toml").read_text()
    assert "maxwell_time = [0.02, 0.002]" in text
    path = tmp_path_factory.mktemp("roots30") / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.load_model(path)


def _exact_root(model, speed, root, shape):
    """The root of the rational pencil at ``speed`` [rad/s] that Newton's steps in 50 digits
    (bordered system) reach from ``root`` and ``shape``, and its shape (mpmath)."""
    mpmath.mp.dps = 50
    form = speed_linear_form(model)
    M = np.asarray(form.matrices.M)
    n = len(M)
    K, C = form.pencil_at(np.array([speed]))
    D = C.reshape(M.shape) + speed * np.asarray(form.matrices.G)
    Mm, Dm, Km = (mpmath.matrix(A.tolist()) for A in (M, D, K.reshape(M.shape)))
    branches = [(mpmath.matrix(B.tolist()), mpmath.mpf(float(t))) for B, t in zip(*_eigensolve.branch_terms(form))]
    lam, x = mpmath.mpc(complex(root)), mpmath.matrix([mpmath.mpc(complex(v)) for v in shape])
    fixed = x.copy()
    for _ in range(30):
        T, dT = lam * lam * Mm + lam * Dm + Km, 2 * lam * Mm + Dm
        for B, tau in branches:
            k = B.rows
            f, g = lam * tau / (1 + lam * tau), tau / (1 + lam * tau) ** 2
            for a in range(k):
                for b in range(k):
                    T[a, b] += f * B[a, b]
                    dT[a, b] += g * B[a, b]
        J = mpmath.zeros(n + 1, n + 1)
        for a in range(n):
            for b in range(n):
                J[a, b] = T[a, b]
        slope, residual = dT * x, T * x
        for a in range(n):
            J[a, n], J[n, a] = slope[a], mpmath.conj(fixed[a])
        step = mpmath.lu_solve(J, mpmath.matrix([-residual[a] for a in range(n)] + [0]))
        for a in range(n):
            x[a] += step[a]
        lam += step[n]
        if abs(step[n]) < mpmath.mpf(10) ** -45 * abs(lam):
            return lam, x
    raise AssertionError("no convergence")


@pytest.mark.parametrize("rpm", [500.0, 3000.0])
def test_a_polished_mode_is_labelled_by_its_own_round_off(fast_branch, rpm):
    """Mode 1 at 500 and 3000 rpm: its whirl ratio is the 50-digit solve's (2.2e-3, 1.3e-2, with
    the same whirl forms) to 1e-9, so it whirls forward beyond WHIRL_TOLERANCE; `modes` says so,
    and its whirl round-off is below 1e-6. On main it read 'none' (round-off 3.2e-2, the solve's)."""
    speed = rdm.rpm(rpm)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.modal(fast_branch, speed)
    first = int(np.flatnonzero(result.oscillatory)[0])
    lam, x = _exact_root(fast_branch, speed, result.eigenvalues[first], result.shapes[first])
    W, N, _ = _whirl.whirl_forms(fast_branch)
    xh = x.H
    truth = float(mpmath.im((xh * mpmath.matrix(W.tolist()) * x)[0]) / mpmath.re((xh * mpmath.matrix(N.tolist()) * x)[0]))
    assert abs(complex(lam) - result.eigenvalues[first]) < 1e-12 * abs(complex(lam))
    assert abs(result.whirl_ratios[first] - truth) < 1e-9
    assert truth > 2 * _whirl.WHIRL_TOLERANCE
    assert result.whirl_round_off[first] < 1e-6
    assert result.whirl[first] == "forward"


def test_every_route_labels_a_polished_mode_as_modes_does(fast_branch):
    """The Campbell diagram (full and lowest modes' route), the stability result and the critical
    speeds label mode 1 as `modes` does at each speed: forward from 500 rpm on."""
    speeds = rdm.rpm(np.array([0.0, 500.0, 1000.0, 3000.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = rdm.campbell(fast_branch, speeds, orders=(1,), critical=False)
        lowest = rdm.campbell(fast_branch, speeds, orders=(1,), critical=False, modes=6)
        stability = rdm.stability(fast_branch, speeds)
        labels = [rdm.modal(fast_branch, s) for s in speeds]
    first = [str(r.whirl[np.flatnonzero(r.oscillatory)[0]]) for r in labels]
    assert first == ["none", "forward", "forward", "forward"]
    assert list(full.whirl[:, 0]) == first and list(lowest.whirl[:, 0]) == first
    column = np.argmin(np.abs(stability.eigenvalues - full.eigenvalues[:, :1]), axis=1)
    assert list(stability.whirl[np.arange(len(speeds)), column]) == first


@pytest.mark.parametrize("rpm", [0.0, 500.0])
def test_real_roots_are_polished(fast_branch, rpm):
    """The six real roots between -42 and -38 1/s (the mounts' relaxations coupled to the machine)
    are the 50-digit solve's to 1e-12 in `modes` and in the Campbell diagram; main left them 7e-6
    to 3e-4 off (and warned of them)."""
    speed = rdm.rpm(rpm)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.modal(fast_branch, speed)
        sweep = rdm.campbell(fast_branch, np.array([speed]), orders=(1,), critical=False)
    real = np.flatnonzero((result.eigenvalues.imag == 0) & (np.abs(result.eigenvalues + 40.0) < 3.0))
    assert len(real) == 6
    for j in real:
        lam = complex(_exact_root(fast_branch, speed, result.eigenvalues[j], result.shapes[j])[0])
        assert lam.imag == 0.0 and abs(lam + 40.0) < 3.0
        assert abs(result.eigenvalues[j] - lam) < 1e-12 * abs(lam)
        assert np.min(np.abs(sweep.eigenvalues[0] - lam)) < 1e-12 * abs(lam)


def test_a_real_root_beside_a_large_one_is_polished():
    """``m s^2 + c s + k`` with m = 1, c = 1e8, k = 1 (n = 1, two coordinates uncoupled to make
    it a pencil): the slow root ``2 k / (-c - sqrt(c^2 - 4 m k))`` (closed form, no cancellation)
    from a start 1e-6 off is polished to 1e-15, the fast one ``-c`` nearly left as it is."""
    M, D, K = np.eye(2), np.diag([1e8, 3.0]), np.diag([1.0, 2.0])
    slow = 2.0 / (-1e8 - np.sqrt(1e16 - 4.0))
    values = np.array([slow * (1 + 1e-6), -1.0, -2.0]) + 0j        # the second coordinate's roots -1, -2
    shapes = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 1.0]], dtype=complex)
    bound = np.array([1e-6, 1e-12, 1e-12])
    left = _eigensolve.refined_pairs(values, shapes, M, D, K, bound)
    assert values[0].imag == 0.0 and abs(values[0].real - slow) < 1e-15 * abs(slow)
    assert left[0] < 1e-9
    assert values[1] == -1.0 and values[2] == -2.0                  # exact already: untouched


def _uncoupled_roots50(model):
    """The uncoupled rotor's roots at rest to 50 digits (``tests/test_roots31.py``'s Newton solves
    of the two planes' blocks): the package's own roots of the uncoupled model, the reference
    before, were 2.3e-12 off with OpenBLAS's Haswell kernels where the coupled model's were 4e-16."""
    from test_roots31 import _newton50, _planes

    M, C, _, K = (np.asarray(A) for A in model.matrices(0.0))
    roots = []
    for plane in _planes(M, C, K):
        block = [A[np.ix_(plane, plane)] for A in (M, C, K)]
        start = np.sqrt(np.linalg.eigvals(np.linalg.solve(block[0], block[2])).astype(complex)) * 1j
        roots += [_newton50(*block, s) for s in start]
    return np.array(roots)


def test_defective_double_roots_are_polished_to_their_mean(tmp_path):
    """Friswell 5.9.4 as ROSS builds it, at rest: kxy alone makes K block-triangular, so every root
    is a defective double root (a Jordan block), exactly a root of the same rotor with kxy = 0.
    The solve splits each by the square root of its round-off; the estimate took them for exact
    (1e-12). Now nearly parallel shapes of roots this close are estimated at their split, polished
    as a pair and made their mean: the lowest ten within 1e-12 of the uncoupled rotor's (50-digit
    roots), in `modes` and in the Campbell diagram (main: 1.9e-7 off)."""
    from rotordyn_modal.cli import main

    source = Path(__file__).parent / "data" / "ross" / "friswell_5_9_4.toml"
    path = tmp_path / "friswell_5_9_4.toml"
    assert main(["import-ross", str(source), "--out", str(path), "--quiet"]) == 0
    model = rdm.load_model(path)
    truth = _uncoupled_roots50(model)
    result = rdm.modal(model, 0.0)
    sweep = rdm.campbell(model, np.array([0.0, 10.0]), orders=(1,), critical=False)
    for roots in (result.eigenvalues[result.oscillatory][:10], sweep.eigenvalues[0][sweep.oscillatory[0]][:10]):
        nearest = truth[[int(np.argmin(np.abs(truth - lam))) for lam in roots]]
        assert np.max(np.abs(roots - nearest) / np.abs(nearest)) < 1e-12
