"""``simulate``'s count of the steps an impulse forces, on a large machine, without a dense eigen-solve
(issue 27 §1.9).

The CPU check counts DOP853's fewest steps from the fastest mode the impulse excites: a mode whose
share ``|c_k| max|v_k|`` of the impulse's initial state is at least 1e-9 of the largest. Where the
bound (the largest ``|lambda|`` of all) was refused, that count came from every root and shape of
the state matrix (142 s of CPU at 4,012 states). It now comes from ARPACK's largest roots with
their right and left shapes (``c_k = w_k^T x0 / w_k^T v_k``), on the block of states the impulse
reaches through the matrix's nonzero entries. The truth: the dense decomposition, made here with
scipy, and matrices whose roots and shapes are built by hand.
"""

from __future__ import annotations

import importlib
import tomllib

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve
from rotordyn_modal.assembly import excitation_columns
from rotordyn_modal.linear_system import speed_linear_form
from test_large_machine_cli import chained_gear_toml

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")

ROTORS = 75                 # 306 coordinates, 612 states: the large machine's route
SPEED = 100.0               # rad/s
DURATION = 0.05             # s
TAP = ('\n[[excitations]]\nname = "tap"\nrotor = "r001"\nposition = [-1.99, 0.1, 0.45]\n'
       'direction = [0.0, 1.0, 0.0]\n')


@pytest.fixture(scope="module")
def model():
    built = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(ROTORS, ROTORS) + TAP), source="chain.toml")
    assert built.dofs.n == 306
    return built


def _dense_truth(matrix, state):
    """The largest ``|lambda|`` of the modes with a share of at least 1e-9 of the largest: every root
    and right shape (scipy), the shares from a solve."""
    roots, shapes = scipy.linalg.eig(matrix)
    shares = np.abs(np.linalg.solve(shapes, state)) * np.abs(shapes).max(axis=0)
    return np.abs(roots[shares >= 1e-9 * shares.max()]).max()


def _no_dense_solve(monkeypatch):
    """Every dense eigen-solution's calls, recorded in the list returned."""
    calls = []
    for module, names in ((scipy.linalg, ("eig", "eigvals")), (np.linalg, ("eig", "eigvals")), (_eigensolve, ("eig",))):
        for name in names:
            original = getattr(module, name)

            def recorded(*args, _original=original, _name=name, **kwargs):
                calls.append(_name)
                return _original(*args, **kwargs)

            monkeypatch.setattr(module, name, recorded)
    return calls


def test_the_exact_count_on_a_large_machine_is_the_dense_ones_without_a_dense_solve(monkeypatch):
    """30 rotors (126 coordinates) taken as large (the route from 60 coordinates, not 300), so that
    the dense truth costs a second, not 6 s at 612 states."""
    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(30, 30) + TAP), source="chain.toml")
    monkeypatch.setattr(simulate_module, "_KRYLOV_DOF", 60)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1")
    form = speed_linear_form(model)
    state = np.zeros(form.n_states)
    state[form.n_dof:] = form.mass_inverse @ excitation_columns(model, ["tap"])[:, 0]
    truth = DURATION * _dense_truth(form.at(SPEED), state) / (2 * 6.77)      # DOP853's reach, twice
    calls = _no_dense_solve(monkeypatch)
    steps = simulate_module._fewest_steps(model, SPEED, DURATION, "tap")
    assert calls == []                                   # main: ['eig'] (every root and shape)
    assert steps == pytest.approx(truth, rel=1e-9)


def test_a_refused_bound_on_a_large_machine_is_made_exact_without_a_dense_solve(model, monkeypatch):
    """A 5 s run with 3 output times under a limit of 0.1 s: the output times pass the check, the
    steps' bound is refused, the exact count is made and its own line refuses (its count, not the
    bound's), with no dense eigen-solution on the way."""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", repr(0.1 / 60))
    exact = simulate_module._fewest_steps(model, SPEED, 5.0, "tap")
    calls = _no_dense_solve(monkeypatch)
    with pytest.raises(rdm.InputError, match="integrator steps for the fastest mode the impulse excites") as refused:
        rdm.simulate(model, 5.0, speed=SPEED, samples=3, impulse="tap", impulse_size=0.01)
    assert calls == []                                   # main: ['eig']
    assert f"at least {exact:.3g} integrator steps" in str(refused.value)


def _built(roots, seed=3):
    """A real matrix (n, n) with the given roots (conjugate pairs as 2 x 2 blocks) in a random,
    far from orthogonal basis ``T``: its right shapes are ``T``'s columns (pairs combined)."""
    rng = np.random.default_rng(seed)
    blocks = []
    for root in roots:
        blocks.append(np.array([[root.real, root.imag], [-root.imag, root.real]]) if root.imag else np.array([[root.real]]))
    diagonal = scipy.linalg.block_diag(*blocks)
    basis = rng.normal(size=diagonal.shape) + 3.0 * np.eye(len(diagonal))
    return basis @ diagonal @ np.linalg.inv(basis), basis


@pytest.mark.parametrize("repeated", [False, True])
def test_the_fastest_mode_not_in_the_state_is_skipped_and_the_next_is_found(repeated):
    """60 states: the two fastest pairs (|lambda| 1e6 and 5e5, or the same pair twice: a repeated
    root, whose shapes are any basis of its plane) are not in the state, so the answer is the
    third's |lambda| (2e4), whatever the basis; with the fastest pair in it at 1e-6 of the
    others it is that pair's."""
    slow = [complex(-1.0 - k, 10.0 + 7 * k) for k in range(27)]
    second = complex(-1e3, 1e6) if repeated else complex(-10.0, 5e5)
    roots = [complex(-1e3, 1e6), second, complex(-20.0, 2e4)] + slow
    matrix, basis = _built(roots)
    moving = np.ones(60)
    moving[:4] = 0.0                                     # no share of the two fastest pairs
    state = basis @ moving
    assert simulate_module._fastest_excited(matrix, state) == pytest.approx(abs(roots[2]), rel=1e-8)
    moving[:2] = 1e-6
    assert simulate_module._fastest_excited(matrix, basis @ moving) == pytest.approx(abs(roots[0]), rel=1e-8)


def test_the_block_the_impulse_reaches_is_its_own_motion():
    """Two oscillators and a one-way link from the first to the third state: from the first
    oscillator's velocity the block holds its two states and the third's; from the second
    oscillator's, only its own two."""
    matrix = np.zeros((5, 5))
    matrix[0, 1], matrix[1, 0] = 1.0, -4.0               # oscillator 1: states 0, 1
    matrix[2, 3], matrix[3, 2] = 1.0, -9.0               # oscillator 2: states 2, 3
    matrix[4, 0], matrix[4, 4] = 2.0, -1.0               # state 4 driven by state 0
    block, state = simulate_module._reached(matrix, np.array([0.0, 1.0, 0.0, 0.0, 0.0]))
    assert np.array_equal(block, matrix[np.ix_([0, 1, 4], [0, 1, 4])]) and np.array_equal(state, [0.0, 1.0, 0.0])
    block, state = simulate_module._reached(matrix, np.array([0.0, 0.0, 0.0, 1.0, 0.0]))
    assert np.array_equal(block, matrix[2:4, 2:4]) and np.array_equal(state, [0.0, 1.0])
