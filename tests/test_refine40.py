"""Critical speeds among close roots of machines of 49-96 coordinates are picked from Ritz pairs
of the sweep's shapes (no longer from every root of the state matrix at each trial speed), the
first pick in the span of the 4 nearest roots' shapes at each end of the bracket and the rows
it leaves in that of the 8 nearest (``docs/theory.md``, section 10). The crossings are roots of
the full state matrix on their order lines (``scipy.linalg.eigvals`` of the model's own M, C,
G, K), and the same crossings as every root's route gives."""

from __future__ import annotations

import sys
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _crossing_roots

sys.path.insert(0, str(Path(__file__).parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

SPEEDS = rdm.rpm(np.linspace(0.0, 4500.0, 12))


def _chain():
    """The 11-rotor gear chain: 50 coordinates, 669 crossings of order 1 at these speeds, most in
    brackets among the like rotors' close roots."""
    return rdm.Model.from_dict(tomllib.loads(chained_gear_toml(11, 11)), source="chain.toml")


def _campbell(model, monkeypatch=None):
    """The result of ``campbell``, the rows of state matrices solved whole for them
    (``_crossing_roots._all_roots``) and the calls of ``_crossing_roots._ritz_tried`` (its rows
    and subspace size, and which rows it kept)."""
    solved, tries = [0], []
    every_root, tried = _crossing_roots._all_roots, getattr(_crossing_roots, "_ritz_tried", None)

    def counted(stack, variants, x, shapes):
        solved[0] += len(x)
        return every_root(stack, variants, x, shapes)

    def recorded(stack, speeds, values, shapes, weighted, brackets, rows, x, iterates, count):
        lam, ok = tried(stack, speeds, values, shapes, weighted, brackets, rows, x, iterates, count)
        tries.append((rows.copy(), count, ok.copy()))
        return lam, ok

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(_crossing_roots, "_all_roots", counted)
        if tried is not None:
            patch.setattr(_crossing_roots, "_ritz_tried", recorded)
        if monkeypatch is not None:
            monkeypatch(patch)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = rdm.campbell(model, SPEEDS)
    return result, solved[0], tries


@pytest.fixture(scope="module")
def chain():
    model = _chain()
    return model, _campbell(model)


def test_close_roots_of_a_50_coordinate_machine_are_picked_from_ritz_pairs(chain):
    """The 11-rotor chain (50 coordinates, above the 48 of the pencils solved whole) solves no
    state matrix whole at its trial speeds: each crossing among close roots is picked from Ritz
    pairs, first in the smaller subspace, and only the rows that try left take the larger one
    (on the base, 520 rows took every root)."""
    _, (result, solved, tries) = chain
    assert len(result.critical.speeds) > 600
    assert solved == 0
    assert tries, "no crossing among close roots went through the Ritz pairs"
    first = [t for t in tries if t[1] == _crossing_roots._RITZ_FIRST]
    assert first and all(count in (_crossing_roots._RITZ_FIRST, _crossing_roots._RITZ_ROOTS) for _, count, _ in tries)
    # each call of the smaller subspace is followed, for the rows it did not keep, by the larger
    for at, (rows, count, ok) in enumerate(tries):
        if count != _crossing_roots._RITZ_FIRST or ok.all():
            continue
        rows_next, count_next, _ = tries[at + 1]
        assert count_next == _crossing_roots._RITZ_ROOTS
        np.testing.assert_array_equal(rows_next, rows[~ok])


def test_the_crossings_are_roots_of_the_full_state_matrix_on_their_order_lines(chain):
    """Every 24th crossing: ``scipy.linalg.eigvals`` of ``[[0, I], [-M^-1 K, -M^-1 (C + Omega G)]]``
    at its speed, from the model's own matrices, has an eigenvalue within 1e-9 (relative) of the
    crossing's (its frequency and damping ratio), and that frequency is the order line's,
    ``multiplier * |Omega|``, to 1e-9."""
    model, (result, _, _) = chain
    critical = result.critical
    matrices = model.matrices()
    M, C, G, K = (np.asarray(m, dtype=float) for m in (matrices.M, matrices.C, matrices.G, matrices.K))
    n = M.shape[0]
    stiffness, damping, gyroscopic = (np.linalg.solve(M, m) for m in (K, C, G))
    multipliers = dict(zip(result.sources.names, result.sources.multipliers))
    checked = 0
    for row in range(0, len(critical.speeds), 24):
        speed = float(critical.speeds[row])
        omega = 2 * np.pi * float(critical.frequencies_hz[row])
        zeta = float(critical.damping_ratios[row])
        line = float(critical.order[row]) * multipliers[critical.source[row]] * abs(speed)
        assert abs(omega - line) <= 1e-9 * line, (row, omega, line)
        state = np.block([[np.zeros((n, n)), np.eye(n)], [-stiffness, -(damping + speed * gyroscopic)]])
        roots = scipy.linalg.eigvals(state)
        found = omega / np.sqrt(1 - zeta ** 2) * (-zeta + 1j * np.sqrt(1 - zeta ** 2))
        assert np.min(np.abs(roots - found)) <= 1e-9 * abs(found), (row, found)
        checked += 1
    assert checked > 25


def test_the_same_crossings_as_every_roots_route(chain):
    """With the Ritz route kept above 96 coordinates (as on the base), the chain's crossings are
    the same: the same sources, orders, modes and whirl, speeds and frequencies to 1e-10."""
    model, (result, _, _) = chain
    critical = result.critical
    every, solved, _ = _campbell(model, lambda patch: patch.setattr(_crossing_roots, "_RITZ_DOF", 96))
    every = every.critical
    assert solved > 0
    assert len(every.speeds) == len(critical.speeds)
    for column in ("source", "order", "mode", "whirl"):
        assert list(getattr(every, column)) == list(getattr(critical, column)), column
    np.testing.assert_allclose(critical.speeds, every.speeds, rtol=1e-10)
    np.testing.assert_allclose(critical.frequencies_hz, every.frequencies_hz, rtol=1e-10)
