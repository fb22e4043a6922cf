"""The forces of every item computed together (``forces.all_forces``, the unbalance response's
path for small models) equal the three per-kind functions' (``suspension_forces``,
``bearing_forces``, ``bearing_point_forces``) bit for bit: per item they are meant to be the
same products, so any drift of one path from the other shows here. The per-kind functions'
physics (stator equilibrium, a rotor's bearing forces against its inertia and unbalance) is
tested in ``test_frf.py`` and ``test_bearings.py``."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rotordyn_modal as rdm
from reference_bearings import random_bearing_description
from rotordyn_modal.analysis.forces import all_forces, bearing_forces, bearing_point_forces, suspension_forces


def _models(examples_dir):
    models = {path.name: rdm.load_model(path) for path in sorted(examples_dir.glob("*.toml"))
              if not path.name.endswith(".study.toml")}
    gear = rdm.load_model(examples_dir / "gear_machine.toml")
    lossy = copy.deepcopy(gear.to_dict())
    for i, suspension in enumerate(lossy["suspensions"]):
        suspension["loss_factor"] = 0.01 * (i + 1)
    models["gear_machine, loss factors"] = rdm.Model.from_dict(lossy)
    return models


def _case(model, seed):
    rng = np.random.default_rng(seed)
    count, n = 7, model.dofs.n
    omega = np.linspace(1.0, 900.0, count)
    speed = np.linspace(50.0, 600.0, count)
    q = rng.normal(size=(count, n, 2)) + 1j * rng.normal(size=(count, n, 2))
    external = rng.normal(size=(len(model.rotors), count, 6, 2)) + 1j * rng.normal(size=(len(model.rotors), count, 6, 2))
    return speed, omega, q, external


def _compared_bit_for_bit(name, model, seed) -> int:
    """Assert both paths give the same bits; the number of values compared."""
    speed, omega, q, external = _case(model, seed)
    together = all_forces(model, speed, omega, q, external)
    apart = (suspension_forces(model, omega, q), bearing_forces(model, speed, omega, q, external),
             bearing_point_forces(model, speed, omega, q))
    compared = 0
    for kind, a, b in zip(("suspensions", "rotors", "bearings"), together, apart):
        assert a.shape == b.shape, (name, kind)
        assert a.tobytes() == b.tobytes(), (name, kind)
        compared += a.size
    return compared


def test_forces_together_equal_each_kind_bit_for_bit(examples_dir):
    compared = sum(_compared_bit_for_bit(name, model, len(name)) for name, model in _models(examples_dir).items())
    assert compared > 0


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rotors=st.integers(1, 3), stator=st.booleans())
def test_forces_together_equal_each_kind_on_random_machines(seed, rotors, stator):
    """Random machines on bearings with cross-coupled coefficients, inclined axes, moment
    stiffness, rigidly attached rotors, with or without a stator."""
    data = random_bearing_description(np.random.default_rng(seed), n_rotors=rotors, stator=stator)
    assert _compared_bit_for_bit(f"seed {seed}", rdm.Model.from_dict(data), seed) > 0


@pytest.mark.parametrize("rotors_given", [False, True])
def test_forces_together_take_the_rotors_centres_when_given(examples_dir, rotors_given):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speed, omega, q, external = _case(model, 3)
    centres = None
    if rotors_given:
        from rotordyn_modal.model.geometry import shift_matrix

        centres = np.concatenate([shift_matrix(model.reference_point, r.center_of_mass).T
                                  @ model.dofs.body_motion(r.name) for r in model.rotors])
    together = all_forces(model, speed, omega, q, external, centres)
    alone = bearing_forces(model, speed, omega, q, external)
    assert together[1].tobytes() == alone.tobytes()
