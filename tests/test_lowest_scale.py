"""The lowest modes of large models with bounded memory (issue 28 item 4, issue 27 item 1.9):
the critical speeds of a lowest-modes sweep never solve every root of the state matrices, the
shapes at known roots of a large sparse model are solved sparse, the lowest modes' set-up holds
no n x n array beyond the basis and the model's own matrices, and a sweep of every root that
cannot fit is refused naming the way that fits (``--lowest N`` or ``--max-frequency HZ``).

Truth from outside the code under test: the full sweep's critical speeds (crossings of the
full model's roots with the order lines), dense solves of the same pencils, array sizes."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal import _limits
from rotordyn_modal.analysis import _lowest, _pencils, _stack
from rotordyn_modal.analysis import campbell as campbell_module
from rotordyn_modal.analysis import critical_speeds as critical_module
from rotordyn_modal.cli import main

from test_flexible_large import _on_bearings
from test_large_machine_cli import chained_gear_toml


def test_critical_speeds_of_a_lowest_sweep_never_solve_every_root(monkeypatch):
    """A chain of 8 geared rotors on bearings (38 coordinates, ``DENSE_BELOW``): its 12
    lowest modes cross the orders in brackets that are swept again; those sub-sweeps take the
    lowest roots from the reduced basis (no state matrix is formed at their speeds), and every
    crossing found is one of the full sweep's, to 1e-9 of its speed."""
    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(8, 8)))
    assert model.dofs.n >= _lowest.DENSE_BELOW
    speeds = np.linspace(0.0, rdm.rpm(3000.0), 7)
    full = rdm.campbell(model, speeds, orders=(1,)).critical
    swept = []
    real_sub = critical_module._crossings_in

    def sub_sweep(*args, **kwargs):
        swept.append(args[2])
        return real_sub(*args, **kwargs)

    monkeypatch.setattr(critical_module, "_crossings_in", sub_sweep)
    # the checks of the mode links take the dense route (state matrices) below CHECK_DENSE_BELOW
    # coordinates (ross40); this test is about the sub-sweeps: the checks as before
    monkeypatch.setattr(_lowest, "CHECK_DENSE_BELOW", _lowest.DENSE_BELOW)
    monkeypatch.setattr(_stack.Stack, "sweep", lambda *a, **k: pytest.fail("the state matrices of a sweep formed"))
    lowest = rdm.campbell(model, speeds, orders=(1,), modes=12).critical
    assert swept, "no bracket was swept again: the test no longer reaches the sub-sweeps"
    assert len(lowest) > 50
    for source, order, speed in zip(lowest.source, lowest.order, lowest.speeds):
        same = (full.source == source) & (full.order == order)
        assert np.min(np.abs(full.speeds[same] - speed)) <= 1e-9 * speed


def test_shapes_at_known_roots_by_sparse_lu_equal_the_dense_ones(monkeypatch):
    """``Stack.shapes_at`` of a shaft of 40 elements (168 coordinates) with the sparse route
    taken from 100 coordinates on: the same inverse-iteration step as the dense pencils' (the same
    unit vector to 1e-9 but for its phase, which the shift's nearness to the root leaves to
    round-off), without forming an n x n pencil."""
    model = _on_bearings(40)
    stack = _stack.Stack([model])
    speeds = np.array([300.0, 600.0])
    lam, _, _ = _lowest.lowest_roots(stack, speeds, 3)
    x, lam = np.repeat(speeds, 3), lam.reshape(-1)
    variants = np.zeros(len(x), int)
    dense = stack.shapes_at(variants, x, lam)
    monkeypatch.setattr(_pencils, "SPARSE_SHAPES_DOF", 100, raising=False)
    monkeypatch.setattr(_pencils, "pencil_shapes", lambda *a, **k: pytest.fail("a dense pencil was formed"))
    sparse = stack.shapes_at(variants, x, lam)
    assert np.allclose(np.linalg.norm(sparse, axis=1), 1.0, rtol=0, atol=1e-12)
    assert np.max(1.0 - np.abs(np.einsum("pi,pi->p", dense.conj(), sparse))) <= 1e-9


def test_a_sweep_of_every_root_that_cannot_fit_names_the_lowest_modes_which_fit(tmp_path, capsys, monkeypatch):
    """A shaft of 40 elements (168 coordinates) at 101 speeds with 20 MiB at hand: every root's
    shapes do not fit; the refusal names ``--lowest N`` and ``--max-frequency HZ``, and
    ``--lowest 4`` runs under the same limit."""
    from rotordyn_modal.io.model_file import save_model

    path = tmp_path / "shaft.toml"
    save_model(_on_bearings(40), path)
    monkeypatch.setattr(_limits, "available_memory", lambda: 20.0 * 2**20)
    monkeypatch.setattr(campbell_module, "_CHECKED_BYTES", 0)
    argv = ["campbell", str(path), "--speeds", "0:6000:101", "--no-critical", "--quiet"]
    assert main(argv) == 2
    message = capsys.readouterr().err
    assert "--lowest N" in message and "--max-frequency HZ" in message
    assert main(argv + ["--lowest", "4", "--out", str(tmp_path / "c.csv")]) == 0
    assert len((tmp_path / "c.csv").read_text().splitlines()) == 1 + 4 * 101
