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


#: compressor_on_journals.toml's operating range [rpm], as its header gives it
COMPRESSOR_RANGE = (6000.0, 6600.0)


def test_compressor_on_journals_has_what_its_header_promises(examples_dir):
    """compressor_on_journals.toml: a few hundred kg on two plain journal bearings of L/D 0.5 and a
    clearance of 1-2 per mille of the diameter; its first bending critical speeds lie 15 % below
    the operating range, and it loses stability above the MCS in oil whirl: the full state
    matrix's largest real part (numpy's eigenvalues, outside the analysis) changes sign at the
    threshold, whose root whirls at about half the running speed."""
    from rotordyn_modal.linear_system import state_matrices

    model = rdm.load_model(examples_dir / "compressor_on_journals.toml")
    assert 200.0 < sum(r.mass for r in model.rotors) < 400.0
    for bearing in model.bearings:
        journal = bearing.coefficients.journal
        assert 0.4 <= journal.length / journal.diameter <= 0.6
        assert 1e-3 <= 2 * journal.clearance / journal.diameter <= 2e-3 and journal.viscosity == 0.02
    speeds = rdm.rpm(np.linspace(500.0, 12000.0, 12))
    critical = rdm.critical_speeds(model, speeds, max_frequency=150.0)
    assert len(critical) == 2
    assert np.all((critical.speeds_rpm > 4800.0) & (critical.speeds_rpm < COMPRESSOR_RANGE[0] * (1 - 0.14)))
    result = rdm.stability(model, speeds, max_frequency=150.0)
    assert len(result.thresholds) == 1 and result.threshold_onsets[0]
    threshold = result.threshold_speed
    assert rdm.rpm(1.05 * COMPRESSOR_RANGE[1]) < threshold < rdm.rpm(1.15 * COMPRESSOR_RANGE[1])
    largest = [np.linalg.eigvals(A).real.max() for A in state_matrices(model, [threshold * 0.999, threshold * 1.001])]
    assert largest[0] < 0 < largest[1]
    assert 0.45 < 2 * np.pi * result.threshold_frequencies_hz[0] / threshold < 0.55


@pytest.mark.parametrize("arguments", [
    ["check"], ["modes", "--speed", "6000"], ["campbell", "--speeds", "500:9000:5", "--orders", "1,0.5"],
    ["critical-speeds", "--speeds", "500:9000:9"], ["stability", "--speeds", "500:9000:5"],
    ["unbalance", "--speeds", "500:9000:9"], ["static", "--speed", "6000"],
    ["simulate", "--duration", "0.01", "--speed", "6000", "--initial", "equilibrium", "--backend", "numpy"],
], ids=lambda arguments: arguments[0])
def test_compressor_on_journals_runs_in_every_command(examples_dir, arguments, capsys):
    from rotordyn_modal.cli.main import main

    quiet = [] if arguments[0] == "check" else ["--quiet"]
    assert main([arguments[0], str(examples_dir / "compressor_on_journals.toml"), *arguments[1:], *quiet]) == 0
