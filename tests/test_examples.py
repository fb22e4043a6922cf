"""Every bundled example loads, and each shows what its header promises."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm


@pytest.mark.parametrize("name", ["gear_machine.toml", "unstable_cross_coupled.toml", "counter_rotating.toml"])
def test_example_is_valid_and_solvable(examples_dir, name):
    model = rdm.load_model(examples_dir / name)
    result = rdm.campbell(model, rdm.rpm(np.linspace(0, 3000, 11)))
    assert np.all(np.isfinite(result.eigenvalues))


def test_counter_rotating_pair_has_a_flat_campbell_diagram(examples_dir):
    model = rdm.load_model(examples_dir / "counter_rotating.toml")
    assert model.speed_ratios == {"upper": 1.0, "lower": -1.0}
    result = rdm.campbell(model, rdm.rpm(np.linspace(-20000, 20000, 81)))
    spread = result.eigenvalues - result.eigenvalues[0]
    assert np.abs(spread).max() <= 1e-12 * np.abs(result.eigenvalues).max()


def test_gear_machine_speed_ratio_follows_the_gear(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    assert model.speed_ratios["fan"] == pytest.approx(-1 / 2.5, rel=1e-15)
