"""``rotordyn-modal simulate`` as a user runs it: outputs, figures, refusals with exit 2."""

from __future__ import annotations

import pandas as pd

from degenerate_models import EXTREME
from rotordyn_modal.cli import main


def test_run_up_writes_table_and_figure(examples_dir, tmp_path):
    out, plot = tmp_path / "runup.csv", tmp_path / "runup.png"
    code = main(["simulate", str(examples_dir / "gear_machine.toml"), "--speed", "0", "--ramp", "1500",
                 "--duration", "0.5", "--samples", "2001", "--sensor", "acc-top-z", "--out", str(out),
                 "--plot", str(plot), "--quiet"])
    assert code == 0
    table = pd.read_csv(out)
    assert list(table.columns[:9]) == ["time_s", "u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z",
                                       "spin_speed_rad_s", "drive_torque_nm"]
    assert len(table) == 2001 and abs(table["drive_speed_rad_s"].iloc[-1] - 1500 * 3.141592653589793 / 30) < 1e-6
    assert plot.stat().st_size > 10_000


def test_paper_example_free_spin_in_rad_per_s(examples_dir, tmp_path, capsys):
    out = tmp_path / "sb.csv"
    code = main(["simulate", str(examples_dir / "spring_block_rotor.toml"), "--speed", "50", "--speed-unit", "rad/s",
                 "--free-spin", "--duration", "0.5", "--samples", "51", "--out", str(out)])
    assert code == 0
    table = pd.read_csv(out)
    assert abs(table["spin_speed_rad_s"] / 50 - 1).max() < 1e-3
    assert (table["drive_torque_nm"] == 0).all()
    assert "relative change of total energy" in capsys.readouterr().err


def test_hysteretic_model_is_refused_with_exit_2(examples_dir, tmp_path, capsys):
    text = (examples_dir / "gear_machine.toml").read_text()
    lossy = tmp_path / "lossy.toml"
    lossy.write_text(text.replace("damping = [150.0, 120.0, 300.0]", "damping = [150.0, 120.0, 300.0]\nloss_factor = 0.1", 1))
    assert main(["simulate", str(lossy), "--duration", "0.1", "--speed", "1000"]) == 2
    err = capsys.readouterr().err
    assert "loss_factor = 0.1" in err and "time domain" in err and "Traceback" not in err


def test_impulse_through_a_missing_excitation_is_refused_with_exit_2(examples_dir, capsys):
    assert main(["simulate", str(examples_dir / "gear_machine.toml"), "--duration", "0.1", "--impulse", "kick"]) == 2
    assert "unknown excitation 'kick'" in capsys.readouterr().err


def test_negative_ramp_is_read_as_a_value(examples_dir, tmp_path):
    out = tmp_path / "down.csv"
    assert main(["simulate", str(examples_dir / "gear_machine.toml"), "--speed", "300", "--ramp", "-300",
                 "--duration", "0.2", "--samples", "101", "--out", str(out), "--quiet"]) == 0
    assert pd.read_csv(out)["drive_speed_rad_s"].iloc[-1] < 0


def test_run_up_of_rotors_on_bearings_through_their_critical_speeds(examples_dir, tmp_path):
    """The fan in its bearings, from static equilibrium, 0 -> 9000 rpm in 1 s: the probe's largest swing
    comes near a critical speed of the fan (Campbell); bearing forces in the table; figure."""
    import numpy as np

    import rotordyn_modal as rdm

    out, plot = tmp_path / "fan.csv", tmp_path / "fan.png"
    code = main(["simulate", str(examples_dir / "fan_on_bearings.toml"), "--speed", "0", "--ramp", "9000",
                 "--duration", "1", "--samples", "10001", "--initial", "equilibrium", "--sensor", "probe-DE-x",
                 "--out", str(out), "--plot", str(plot), "--quiet"])
    assert code == 0 and plot.stat().st_size > 10_000
    table = pd.read_csv(out)
    assert {"fan-DE_Fx", "fan-DE_Mz", "motor-NDE_Fy"} <= set(table.columns)
    swing = (table["probe-DE-x"] - table["probe-DE-x"][0]).abs()     # about the static sag
    peak = table["drive_speed_rad_s"][swing.idxmax()]
    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    critical = rdm.campbell(model, rdm.rpm(np.linspace(1, 9000, 181)), orders=(1,)).critical
    fan = critical.speeds[critical.source == "fan"]
    assert np.min(np.abs(fan - peak)) < 0.15 * peak
    assert swing.max() > 10 * swing[table["drive_speed_rad_s"] < 0.3 * peak].max()   # the bearing mode stands out


def test_a_duration_of_more_periods_than_the_count_limit_is_refused_at_once(examples_dir, tmp_path, capsys):
    """1e9 s of the gear machine would be about 1e10 periods of its fastest mode: refused before
    integrating, naming the duration, the limit and the frequency that sets it."""
    import time

    out = tmp_path / "run.csv"
    start = time.perf_counter()
    code = main(["simulate", str(examples_dir / "gear_machine.toml"), "--speed", "3000", "--duration", "1e9",
                 "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert err.count("\n") == 0 and "--duration 1e9:" in err and "periods of the fastest motion" in err
    assert "ROTORDYN_MODAL_MAX_POINTS" in err and " Hz)" in err
    assert time.perf_counter() - start < 30


def test_a_long_duration_within_the_limit_is_accepted_by_the_check(examples_dir):
    """The check refuses nothing a run could finish: 10 s of the fastest motion at 1 kHz is 1e4 periods."""
    from rotordyn_modal.simulation.simulate import _check_duration

    _check_duration(10.0, 2 * 3.141592653589793 * 1000.0)


def test_model_every_analysis_refuses_is_refused_by_simulate_too(tmp_path, capsys):
    """A stator of 1e-30 kg under a rotor of 1e30 kg on bearings: its mass matrix is singular in
    double precision (the masses are 60 orders apart), so `modes` refuses it; `simulate` refuses it
    with the same line and exit 2 (it once swallowed the refusal and died in the integrator with a
    ZeroDivisionError, exit 1)."""
    model = tmp_path / "extreme.toml"
    model.write_text(EXTREME)
    def errors():   # the line of the refusal (a 1e30 kg rotor on 1e5 N/m mounts also draws a sag warning)
        return [line for line in capsys.readouterr().err.splitlines() if ": warning: " not in line]

    assert main(["modes", str(model), "--speed", "1000", "--quiet"]) == 2
    (refusal,) = errors()
    assert "mass matrix invertible" in refusal
    for backend in ("numpy", "auto"):
        assert main(["simulate", str(model), "--duration", "0.01", "--speed", "1000", "--quiet",
                     "--backend", backend]) == 2
        assert errors() == [refusal.replace("modes", "simulate", 1)]
