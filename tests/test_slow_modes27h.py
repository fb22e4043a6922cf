"""A slow mode is a mode by its own numbers (issue 27 §1.1; docs/theory.md section 8): a rigid
rotor's cylindrical pair at sqrt(2 k / m) stays listed however slow it is beside an unrelated
root (here the forward conical whirl, 180 rad/s at 100 rad/s), in ``modes``, ``campbell`` and
``critical-speeds``. The roots are checked against the closed forms of a symmetric rigid rotor
(centre of mass midway between two equal isotropic bearings at +-a): cylindrical
``w^2 = 2 k / m``; conical ``Id w^2 -+ Ip Omega w - 2 k a^2 = 0``."""

from __future__ import annotations

import io
import itertools

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

ARM = 0.2
MASSES = (1e-3, 1.0, 1e3, 1e6, 1e9)
STIFFNESSES = (1e-6, 1e-2, 1e2, 1e6, 1e12)


def _rotor(mass, stiffness, extra=""):
    return f"""
name = "rigid rotor on two soft bearings"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "heavy"

[[rotors]]
name = "heavy"
mass = {mass!r}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = {0.09 * mass!r}
diametral_inertia = {0.05 * mass!r}

[[bearings]]
name = "A"
rotor = "heavy"
position = [{ARM}, 0.0, 0.0]
stiffness = {stiffness!r}

[[bearings]]
name = "B"
rotor = "heavy"
position = [{-ARM}, 0.0, 0.0]
stiffness = {stiffness!r}
""" + extra


def _load(tmp_path, mass, stiffness, extra=""):
    path = tmp_path / f"rotor_{mass:g}_{stiffness:g}.toml"
    path.write_text(_rotor(mass, stiffness, extra))
    return rdm.load_model(path), path


def _cylindrical(mass, stiffness):
    return np.sqrt(2.0 * stiffness / mass)


def _conical(mass, stiffness, speed):
    """Forward and backward conical whirl [rad/s] (the backward one without cancellation)."""
    gyro = 0.09 / 0.05 * speed
    tilt = 2.0 * stiffness * ARM ** 2 / (0.05 * mass)
    root = np.sqrt(gyro ** 2 + 4.0 * tilt)
    return 0.5 * (gyro + root), 2.0 * tilt / (gyro + root)


def _count_near(values, target):
    return int(np.sum(np.isclose(values, target, rtol=1e-9, atol=0.0)))


@pytest.mark.parametrize("mass,stiffness", list(itertools.product(MASSES, STIFFNESSES)))
def test_modes_keep_the_cylindrical_pair_at_any_scale(tmp_path, mass, stiffness):
    """At 100 rad/s a rotor of 1e6 kg on 1e-6 N/m lost its cylindrical pair (1.4e-6 rad/s) to a
    zero-root rule that took every undamped root below sqrt(round-off) as free."""
    model, _ = _load(tmp_path, mass, stiffness)
    for speed in (0.0, 100.0):
        result = rdm.modal(model, speed)
        listed = result.eigenvalues[result.oscillatory].imag
        assert _count_near(listed, _cylindrical(mass, stiffness)) == 2, (speed, listed)
        forward = _conical(mass, stiffness, speed)[0]
        assert _count_near(listed, forward) == (2 if speed == 0 else 1), (speed, listed)


@pytest.mark.parametrize("mass,stiffness", [(1e6, 1e-6), (1e9, 1e-6), (1e9, 1e-2), (1.0, 1.0)])
def test_the_campbell_diagram_keeps_the_cylindrical_pair(tmp_path, mass, stiffness):
    model, _ = _load(tmp_path, mass, stiffness)
    speeds = np.array([0.0, 1.0, 100.0, 1e4])
    sweep = rdm.campbell(model, speeds)
    for row, speed in enumerate(speeds):
        listed = sweep.eigenvalues[row][sweep.oscillatory[row]].imag
        assert _count_near(listed, _cylindrical(mass, stiffness)) == 2, (speed, listed)
        assert _count_near(listed, _conical(mass, stiffness, speed)[0]) >= 1, (speed, listed)


def test_the_command_line_lists_the_slow_pair(tmp_path, capsys):
    """The red-team repro: ``modes --speed 100 --speed-unit rad/s`` printed 1 mode and
    "6 real roots"; the cylindrical pair is 2.25079e-07 Hz (sqrt(2e-12) / 2 pi)."""
    _, path = _load(tmp_path, 1e6, 1e-6)
    assert main(["modes", str(path), "--speed", "100", "--speed-unit", "rad/s", "--out", "-"]) == 0
    out = capsys.readouterr().out
    table = pd.read_csv(io.StringIO(out))
    hz = table["frequency_hz"].to_numpy(dtype=float)
    assert _count_near(hz, _cylindrical(1e6, 1e-6) / (2 * np.pi)) == 2, out


_LIGHT = """
[[rotors]]
name = "light"
mass = 1.0
speed_ratio = 1e8
center_of_mass = [0.0, 0.0, 1.0]
polar_inertia = 0.09
diametral_inertia = 0.05

[[bearings]]
name = "C"
rotor = "light"
position = [0.2, 0.0, 1.0]
stiffness = 1e-6

[[bearings]]
name = "D"
rotor = "light"
position = [-0.2, 0.0, 1.0]
stiffness = 1e-6
"""


def test_a_critical_speed_on_a_very_slow_mode(tmp_path, capsys):
    """A 1e6 kg rotor on 1e-6 N/m bearings beside a light rotor geared 1e8:1 (whose gyroscopic
    roots, ~250 rad/s at the crossing, set the round-off): the heavy rotor's 1X crosses its
    cylindrical pair at Omega = sqrt(2 k / m) = 1.41421356e-6 rad/s, backward and forward."""
    model, path = _load(tmp_path, 1e6, 1e-6, _LIGHT)
    expected = _cylindrical(1e6, 1e-6)
    critical = rdm.critical_speeds(model, np.linspace(0.0, 3e-6, 31))
    heavy = np.asarray(critical.speeds)[np.asarray(critical.source) == "heavy"]
    assert _count_near(heavy, expected) == 2, critical
    rpm = expected * 60 / (2 * np.pi)
    assert main(["critical-speeds", str(path), "--speeds", f"0:{3 * rpm / 1.41421356}:31", "--out", "-"]) == 0
    table = pd.read_csv(io.StringIO(capsys.readouterr().out))
    table = table[table["source"] == "heavy"]
    assert _count_near(table["speed_rpm"].to_numpy(dtype=float), rpm) == 2, table
