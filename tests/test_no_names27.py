"""A name asked of a model that has no table of its kind says so: ``the model has no
[[sensors]]``. Before: ``unknown sensor 'z': the model's sensors are none defined``."""

from __future__ import annotations

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError

RIGID = """\
name = "rigid rotor, no sensor, no excitation"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"

[[rotors]]
name = "r"
mass = 10.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.2
diametral_inertia = 0.5
speed_ratio = 1.0

[[bearings]]
name = "A"
rotor = "r"
position = [0.3, 0.0, 0.0]
stiffness = 1.0e6

[[bearings]]
name = "B"
rotor = "r"
position = [-0.3, 0.0, 0.0]
stiffness = 1.0e6

[[unbalances]]
rotor = "r"
amount = 1.0e-4
"""


@pytest.fixture
def path(tmp_path):
    file = tmp_path / "rigid.toml"
    file.write_text(RIGID)
    return file


@pytest.mark.parametrize("argv, said", [
    (["unbalance", "{}", "--speeds", "100:200:2", "--sensor", "z"], "--sensor z: unknown sensor 'z': the model has no [[sensors]]"),
    (["simulate", "{}", "--speed", "100", "--duration", "0.1", "--excitation", "hit"],
     "--excitation hit: unknown excitation 'hit': the model has no [[excitations]]"),
])
def test_the_command_line_says_the_model_has_none(path, capsys, argv, said):
    code = main([a.format(path) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and said in err and "none defined" not in err, err


def test_python_says_the_model_has_none(path):
    model = rdm.load_model(path)
    with pytest.raises(InputError, match=r"unknown sensor 'z': the model has no \[\[sensors\]\]$"):
        model.state_space(0.0, outputs=["z"])
