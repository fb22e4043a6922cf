"""The work estimate follows the critical speeds' route (refine40): where a crossing's mode is
picked among Ritz pairs (constant coefficients, more than 48 coordinates) no root of the whole
state matrix is solved for it, and the estimate counts none; below, and with speed-dependent
coefficients, every root is still a candidate and counted."""
from __future__ import annotations

import tomllib

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _crossing_roots, _pencils, _work
from test_large_machine_cli import chained_gear_toml


def _chain(rotors):
    return rdm.Model.from_dict(tomllib.loads(chained_gear_toml(rotors, rotors)), source="chain.toml")


def test_a_chain_of_50_coordinates_solves_no_state_matrix_whole_and_its_estimate_counts_none(monkeypatch):
    model = _chain(11)
    assert model.dofs.n == 50 and 48 < model.dofs.n <= _pencils.NEAREST_ROOTS_DOF
    whole = []
    original = _crossing_roots._all_roots
    monkeypatch.setattr(_crossing_roots, "_all_roots",
                        lambda stack, variants, x, shapes=False: whole.append(len(x)) or original(stack, variants, x, shapes))
    speeds = rdm.rpm(np.linspace(0, 4500, 12))
    crossings = len(rdm.campbell(model, speeds).critical.speeds)
    assert crossings > 100 and whole == []
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1.0)
    work = _work.estimate(model, speeds, (1,))
    per = _work._COORDINATE_SECONDS * 50 + _work._FACTOR_SHARE * 1.0           # no dense roots
    assert work.crossing_seconds == pytest.approx(work.crossings * per, rel=1e-12)


@pytest.mark.parametrize("rotors, speed_dependent", [(9, False), (11, True)])
def test_every_root_is_still_counted_below_49_coordinates_and_with_speed_dependent_bearings(monkeypatch, rotors,
                                                                                            speed_dependent):
    model = _chain(rotors)
    if speed_dependent:
        monkeypatch.setattr(type(model), "speed_dependent", property(lambda self: True))
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1.0)
    speeds = rdm.rpm(np.linspace(0, 4500, 12))
    work = _work.estimate(model, speeds, (1,))
    n = model.dofs.n
    per = _work._COORDINATE_SECONDS * n + _work._FACTOR_SHARE + _work._DENSE_ROOTS * _cost.EIGVALS_SHARE
    assert work.crossing_seconds == pytest.approx(work.crossings * per, rel=1e-12)
