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


def test_motor_pump_modes_span_the_decades_its_header_promises(examples_dir):
    """motor_pump_on_mounts.toml: six baseplate modes on the mounts at 5-16 Hz, the rotors'
    ten modes in their 1e8 N/m bearings at 500-1,200 Hz (a rotor of 6-8 kg on two such
    bearings: sqrt(2e8 / m) / 2 pi = 800-920 Hz), and each mount mode crossed by the 1X and 2X
    lines of both rotors below 1,000 rpm (24 critical speeds)."""
    model = rdm.load_model(examples_dir / "motor_pump_on_mounts.toml")
    assert model.speed_ratios["pump"] == pytest.approx(1 / 0.8, rel=1e-15)
    result = rdm.campbell(model, rdm.rpm(np.linspace(0, 3600, 73)), orders=(1, 2))
    f = np.sort(result.frequencies_hz[0][result.oscillatory[0]])
    assert len(f) == 16
    assert np.all((5 < f[:6]) & (f[:6] < 16)) and np.all((500 < f[6:]) & (f[6:] < 1200))
    critical = result.critical
    assert len(critical) == 24 and critical.speeds_rpm.max() < 1000
    assert sorted(set(zip(critical.source, critical.order))) == [("motor", 1), ("motor", 2), ("pump", 1), ("pump", 2)]
