"""A rotor without bearings in a model without a [stator] is held to the ground (it has no
coordinate). ``modes`` died on it, ``failed: ValueError: cannot reshape array of size 0 into
shape (1,4,newaxis,0)`` (exit 1), while campbell and stability gave the modes: each rotor's own
whirl ratio was formed on the coordinates it moves with, none here."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

MODEL = """\
name = "a belt-driven rotor on bearings, its driver held to the ground"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "motor"

[[rotors]]
name = "motor"
mass = 5.0
center_of_mass = [1.0, 0.0, 0.0]
polar_inertia = 0.01
diametral_inertia = 0.02
speed_ratio = 1.0

[[rotors]]
name = "pump"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.2
diametral_inertia = 0.5

[[transmissions]]
type = "belt"
driver = "motor"
driven = "pump"
ratio = 0.5

[[bearings]]
name = "A"
rotor = "pump"
position = [0.3, 0.0, 0.0]
stiffness = 1.5e6

[[bearings]]
name = "B"
rotor = "pump"
position = [-0.3, 0.0, 0.0]
stiffness = 1.5e6
"""


def _closed_form_hz(reference_rpm):
    """The pump (m = 10 kg, Ip = 0.2, Id = 0.5 kg m^2) on k = 1.5e6 N/m at +-0.3 m, turning
    twice the motor's speed: cylindrical sqrt(2 k / m) (twice), conical roots of
    Id w^2 -+ Ip W w - 2 k a^2 = 0."""
    spin = 2 * reference_rpm * np.pi / 30
    cylindrical = np.sqrt(2 * 1.5e6 / 10.0)
    root = np.sqrt((0.2 * spin) ** 2 + 4 * 0.5 * 2 * 1.5e6 * 0.09)
    return np.sort([cylindrical, cylindrical, (root - 0.2 * spin) / 1.0, (root + 0.2 * spin) / 1.0]) / (2 * np.pi)


@pytest.mark.parametrize("speed_rpm", [0.0, 2500.0, -2500.0])
def test_modes_of_a_machine_with_a_grounded_rotor(tmp_path, capsys, speed_rpm):
    path = tmp_path / "grounded.toml"
    path.write_text(MODEL)
    code = main(["modes", str(path), "--speed", str(speed_rpm), "--out", "-"])
    out, err = capsys.readouterr()
    assert code == 0, err
    table = pd.read_csv(io.StringIO(out))
    np.testing.assert_allclose(table.frequency_hz, _closed_form_hz(abs(speed_rpm)), rtol=1e-9)
    result = rdm.modal(rdm.load_model(path), rdm.rpm(speed_rpm))
    modes = result.oscillatory
    assert list(result.rotor_whirl[modes, 0]) == ["none"] * 4            # the motor does not move
    assert sorted(result.rotor_whirl[modes, 1]) == ["backward", "backward", "forward", "forward"]
