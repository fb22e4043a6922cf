"""The lowest modes of ROSS's rotors, cheaper, still the full model's roots (issue 28 section 4, ross40).

``campbell(modes=12)`` of ROSS's speed_tables rotor (44 coordinates, bearings from tables of speed)
spent its time on the estimate of the highest root wanted (``eigvals`` of the 72-state projected
pencils of 36 modes), on the checks of its mode links (the reduced route again, with an 84-state
estimate, for a few speeds) and on threads for batches of a millisecond. Checked here: the lowest
twelve roots of every speed equal scipy's eigenvalues of the full state matrix built from
``Model.matrices`` (``test_tables39.state_roots``); the estimate projects on fewer modes, and where it is too low the basis is sized
again from the careful one; the checks below ``_lowest.CHECK_DENSE_BELOW`` coordinates take the
dense route; small batches of solves stay on one thread.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, _lowest, _lowest_starts, campbell
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor
from test_tables39 import state_roots

DATA = Path(__file__).parent / "data" / "ross"


def ross_rotor(name: str, count: int):
    """ROSS's rotor ``name`` of tests/data/ross and ``count`` speeds over its reference speeds [rad/s]."""
    path = DATA / f"{name}.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    reference = [case["speed"] for case in json.loads(path.with_suffix(".json").read_text())["modal"]]
    return model, np.linspace(min(reference), max(reference), count)


def assert_lowest(model, speeds, values, count):
    """Each row of ``values`` (S, k), in any order, is the ``count`` lowest roots of the full model to 1e-9."""
    for speed, row in zip(speeds, values):
        row = row[np.isfinite(row)]
        assert len(row) == count
        exact = state_roots(model, speed)[:count]
        np.testing.assert_allclose(row[np.argsort(row.imag)], exact, rtol=1e-9, atol=0)


@pytest.mark.parametrize("name", ["speed_tables", "ball_roller_mixed"])
def test_the_lowest_twelve_are_the_full_models_roots(name):
    """``campbell(modes=12)`` at 21 speeds (the reduced route, the checks of its links on the dense
    one): every speed's twelve roots are scipy's twelve lowest of the full state matrix to 1e-9."""
    model, speeds = ross_rotor(name, 21)
    result = rdm.campbell(model, speeds, critical=False, modes=12)
    assert_lowest(model, speeds, result.eigenvalues, 12)


def test_the_estimate_projects_on_fewer_modes(monkeypatch):
    """The highest root wanted is estimated on the modes up to 1.5 times the 13th undamped frequency
    (17 of speed_tables' 44), not on 36: no projected pencil of the sweep has 36 modes, and the
    roots are scipy's."""
    model, speeds = ross_rotor("speed_tables", 9)
    states, projected = [], _lowest_starts._projected_roots
    monkeypatch.setattr(_lowest_starts, "_projected_roots",
                        lambda A, *rest: (states.append(A.shape[-1]), projected(A, *rest))[1])
    values, _, whole = _lowest.lowest_roots(Stack([model]), speeds, 12)
    assert states and max(states) < 2 * 3 * 12 and not whole.any()
    assert_lowest(model, speeds, values, 12)


def test_a_too_low_estimate_sizes_the_basis_again(monkeypatch):
    """Where the cheap estimate is too low (here halved), the basis fails its check at the highest
    root refined and the sweep is made again on the basis the careful estimate sizes: no speed is
    solved whole, and the roots are scipy's."""
    model, speeds = ross_rotor("speed_tables", 9)
    asked, highest = [], _lowest._highest_wanted

    def halved(*arguments, cheap=True):
        rho, was_cheap = highest(*arguments, cheap=cheap)
        asked.append(was_cheap)
        return (0.5 * rho if was_cheap else rho), was_cheap

    monkeypatch.setattr(_lowest, "_highest_wanted", halved)
    values, _, whole = _lowest.lowest_roots(Stack([model]), speeds, 12)
    assert asked == [True, False] and not whole.any()
    assert_lowest(model, speeds, values, 12)


def test_the_checks_take_the_dense_route_below_the_threshold(monkeypatch):
    """``campbell``'s check of its mode links on speed_tables (44 coordinates, below
    ``CHECK_DENSE_BELOW``) solves no reduced basis; with the threshold below 44 it does. Both give
    scipy's fourteen lowest roots."""
    model, speeds = ross_rotor("speed_tables", 5)
    reduced, route = [], _lowest._reduced_roots
    monkeypatch.setattr(_lowest, "_reduced_roots", lambda *arguments, **named: (reduced.append(1),
                                                                               route(*arguments, **named))[1])
    assert _lowest.CHECK_DENSE_BELOW > model.dofs.n
    dense, _ = campbell._check_roots(Stack([model]), speeds, 14)
    assert not reduced
    monkeypatch.setattr(_lowest, "CHECK_DENSE_BELOW", 40)
    again, _ = campbell._check_roots(Stack([model]), speeds, 14)
    assert reduced
    assert_lowest(model, speeds, dense, 14)
    assert_lowest(model, speeds, again, 14)


def test_small_batches_of_solves_stay_on_one_thread(monkeypatch):
    """A batch below ``thread_bytes`` is one part (no pool), one above is shared, with the same
    result; the banded solves of 78 roots of speed_tables (1.3 MB) are not shared, and equal
    numpy's dense solves of the pencils built here."""
    monkeypatch.setenv(_batches.THREADS_ENVIRONMENT, "2")
    pooled, pool = [], _batches._pooled
    monkeypatch.setattr(_batches, "_pooled", lambda function, parts: (pooled.append(1), pool(function, parts))[1])
    batch = np.arange(40.0).reshape(4, 10)
    rows = lambda part: np.cumsum(part, axis=1)             # noqa: E731 - each row its own
    shared = _batches._threaded(rows, batch, item_bytes=2**19)
    assert len(pooled) == 1
    alone = _batches._threaded(rows, batch, item_bytes=2**19, thread_bytes=_batches.SOLVE_THREAD_BYTES)
    assert len(pooled) == 1 and np.array_equal(alone, shared)
    model, speeds = ross_rotor("speed_tables", 21)
    pencils = _Pencils(Stack([model]), speeds)
    rng = np.random.default_rng(40)
    index = rng.integers(0, len(speeds), 78)
    lam = 1j * rng.uniform(400.0, 26000.0, 78)
    rhs = rng.standard_normal((78, model.dofs.n)) + 0j
    out = pencils.solve(index, lam, rhs)
    assert len(pooled) == 1 and pencils.band is not None
    for p in (0, 40, 77):
        M, C, G, K = model.matrices(speeds[index[p]])
        Q = lam[p] ** 2 * M + lam[p] * (C + speeds[index[p]] * G) + K
        np.testing.assert_allclose(out[p], np.linalg.solve(Q, rhs[p]), rtol=1e-9, atol=1e-9 * np.abs(out[p]).max())
