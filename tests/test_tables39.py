"""The lowest modes' route's per-stack memos (issue 28 section 4, tables39).

``campbell``'s checks of its mode links solve the lowest modes again on the same stack at some
sweep speeds (for more roots) and at speeds between them. What a speed's solve made that does not
depend on the number of roots asked is kept on the stack by speed and taken again, not made twice:
the full eigen-solves of a small model (``_lowest._kept_or_solved``, only the speeds not kept are
solved) and the completeness bound's norms of the bearings' blocks (``_lowest_bound._Local``).
Checked here: what is solved, and that the roots equal scipy's eigenvalues of the state matrices
built here from ``Model.matrices``, and the norms numpy's 2-norms of blocks taken here.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_bound
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor

DATA = Path(__file__).parent / "data" / "ross"


def damped_rotor() -> rdm.Model:
    """A rigid rotor on two damped isotropic bearings: 4 lateral coordinates (a small model)."""
    return rdm.Model.from_dict({
        "name": "damped rigid rotor",
        "rotors": [{"name": "rotor", "mass": 30.0, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.4, "diametral_inertia": 0.9, "speed_ratio": 1.0}],
        "bearings": [{"name": name, "rotor": "rotor", "position": [x, 0.0, 0.0], "stiffness": 1e6, "damping": 300.0}
                     for name, x in (("a", -0.25), ("b", 0.25))],
    })


def state_roots(model, speed):
    """The roots of ``s^2 M + s (C + speed G) + K`` in the upper half plane, by frequency: scipy's
    eigenvalues of the state matrix built here."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    inverse = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ K, -inverse @ (C + speed * G)]])
    roots = scipy.linalg.eigvals(A)
    roots = roots[roots.imag > 0]
    return roots[np.argsort(roots.imag)]


def test_a_small_models_full_solves_are_made_only_for_speeds_not_kept(monkeypatch):
    """A second call with one speed solved before and one new solves the new one alone; the kept
    speed's roots and shapes are the first call's bit for bit, and every root is scipy's."""
    model = damped_rotor()
    stack = Stack([model])
    solved, solve = [], stack.solve
    monkeypatch.setattr(stack, "solve", lambda matrices, variants, *rest: (solved.append(len(matrices)),
                                                                         solve(matrices, variants, *rest))[1])
    first = _lowest._full_lowest(stack, np.array([0.0, 500.0, 1000.0]), 4)
    again = _lowest._full_lowest(stack, np.array([500.0, 1500.0]), 4)
    assert solved == [3, 1]
    assert np.array_equal(again[0][0], first[0][1]) and np.array_equal(again[1][0], first[1][1])
    for speed, roots in zip((500.0, 1500.0), again[0]):
        np.testing.assert_allclose(roots[np.argsort(roots.imag)], state_roots(model, speed), rtol=1e-9)


def test_the_checks_take_the_bounds_norms_of_sweep_speeds_kept(monkeypatch):
    """The reduced route (ROSS's speed_tables rotor, 44 coordinates, bearings from tables of speed):
    a check's solve at two sweep speeds computes no norms of the bearings' blocks again, one at a
    new speed computes that speed's; the norms are numpy's 2-norms of the blocks of ``C`` and of
    ``K - K_0`` on the bound's coordinates, and the check's roots are scipy's."""
    path = DATA / "speed_tables.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    reference = [case["speed"] for case in json.loads(path.with_suffix(".json").read_text())["modal"]]
    speeds = np.linspace(min(reference), max(reference), 9)
    stack = Stack([model])
    computed, norms = [], _lowest_bound._block_norms
    monkeypatch.setattr(_lowest_bound, "_block_norms",
                        lambda blocks, at, cb, kb: (computed.append(len(cb)), norms(blocks, at, cb, kb))[1])
    assert not _lowest.lowest_roots(stack, speeds, 12)[2].any()               # the reduced route, no speed whole
    assert computed == [len(speeds)]
    values, _, whole = _lowest.lowest_roots(stack, speeds[[2, 3]], 14)     # a check's: sweep speeds, more roots
    assert computed == [len(speeds)] and not whole.any()
    middle = np.array([0.5 * (speeds[2] + speeds[3])])
    more, _, _ = _lowest.lowest_roots(stack, middle, 14)
    assert computed == [len(speeds), 1]
    for speed, roots in zip(np.append(speeds[[2, 3]], middle), np.vstack([values, more])):
        np.testing.assert_allclose(np.sort(roots.imag), state_roots(model, speed)[:14].imag, rtol=1e-9)
    bound = _lowest_bound._stack_bound(stack, _Pencils(stack, speeds))
    symmetric = stack.lowest_basis["basis"][2].toarray()
    local = np.ix_(bound.local, bound.local)
    for p, speed in enumerate(speeds):
        _, C, _, K = model.matrices(speed)
        np.testing.assert_allclose(bound.damping_norms[p], np.linalg.norm(C[local], 2), rtol=1e-12)
        np.testing.assert_allclose(bound.stiffness_norms[p], np.linalg.norm((K - symmetric)[local], 2), rtol=1e-12)
    assert computed == [len(speeds), 1]
