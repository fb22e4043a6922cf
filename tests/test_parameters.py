"""Dotted keys (rotordyn_modal.model.parameters) and model variants built from them."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.model.parameters import get_value, parse_key, scale_value, set_value


@pytest.fixture
def model(examples_dir):
    return rdm.load_model(examples_dir / "gear_machine.toml")


def test_get_named_tables_indices_and_top_level(model):
    assert model.get("suspensions.mount-FL.damping") == [150.0, 120.0, 300.0]
    assert model.get("suspensions.mount-FL.stiffness[2]") == 4.0e5
    assert model.get("stator.inertia[0][2]") == 0.3
    assert model.get("stator.inertia[-1][0]") == 0.3
    assert model.get("rotors.fan.polar_inertia") == 0.30
    assert model.get("transmissions.0.ratio") == 2.5
    assert model.get("unbalances.1.phase_deg") == 90.0
    assert model.get("spin_axis") == [1.0, 0.0, 0.0]
    assert model.get("reference_rotor") == "motor"


def test_names_with_dots_and_prefixes():
    data = {"rotors": [{"name": "a", "mass": 1.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.1,
                        "diametral_inertia": 0.1, "speed_ratio": 1.0}],
            "suspensions": [{"name": "m", "position": [0, 0, 0], "stiffness": [1.0, 2.0, 3.0]},
                            {"name": "m.1", "position": [0, 0, 0], "stiffness": [4.0, 5.0, 6.0]}]}
    assert get_value(data, "suspensions.m.1.stiffness[0]") == 4.0
    assert get_value(data, "suspensions.m.stiffness[0]") == 1.0


def test_with_values_and_scaled_build_new_validated_models(model):
    stiffer = model.scaled({"suspensions.mount-FL.stiffness": 2.0})
    assert stiffer.get("suspensions.mount-FL.stiffness") == [4.0e5, 3.0e5, 8.0e5]
    assert model.get("suspensions.mount-FL.stiffness") == [2.0e5, 1.5e5, 4.0e5]  # unchanged
    K0, K1 = model.matrices().K, stiffer.matrices().K
    assert not np.allclose(K0, K1)
    heavier = model.with_values({"rotors.fan.polar_inertia": 0.32, "stator.inertia[1][1]": 11.0})
    assert heavier.rotor("fan").polar_inertia == 0.32
    assert heavier.stator.inertia[1, 1] == 11.0
    # a variant that breaks a rule is refused by validation, with the key in the message
    with pytest.raises(rdm.ModelError, match=r"\[rotors.fan\] polar_inertia"):
        model.with_values({"rotors.fan.polar_inertia": 1.0})
    with pytest.raises(rdm.ModelError, match=r"\[stator\] mass"):
        model.scaled({"stator.mass": -1.0})


def test_set_and_scale_in_place():
    data = {"stator": {"mass": 2.0, "inertia": [[1.0, 0.0], [0.0, 1.0]]}}
    set_value(data, "stator.inertia[1][0]", np.float64(0.5))
    assert data["stator"]["inertia"][1][0] == 0.5 and type(data["stator"]["inertia"][1][0]) is float
    scale_value(data, "stator.inertia", 2.0)
    # a product of inertia is one parameter: setting [1][0] sets [0][1] too
    assert data["stator"]["inertia"] == [[2.0, 1.0], [1.0, 2.0]]
    set_value(data, "stator.mass", np.array(3.0))
    assert data["stator"]["mass"] == 3.0


@pytest.mark.parametrize("key, fragment", [
    ("", "dotted key"),
    ("suspensions.nope.damping", "NAME one of mount-FL, mount-FR, mount-RL, mount-RR"),
    ("suspensions.mount-FL.dumping", "no value 'dumping'"),
    ("rotors.fan.polar_inertia[0]", "index 0"),
    ("suspensions.mount-FL.stiffness[7]", "out of range"),
    ("stator.inertia[0][5]", "out of range"),
    ("motors.fan.mass", "expected it to start with one of"),
    ("sensors.acc.position", "NAME one of acc-top-z, acc-side-y"),
    ("transmissions.3.ratio", "NAME one of"),
    ("nothing", "no value 'nothing'"),
])
def test_bad_keys_raise_input_error_naming_the_key(model, key, fragment):
    with pytest.raises(InputError) as info:
        model.get(key)
    assert fragment in str(info.value)
    assert model.source in str(info.value)


def test_scaling_text_is_refused(model):
    with pytest.raises(InputError, match="not numeric"):
        model.scaled({"reference_rotor": 2.0})


def test_no_stator():
    data = {"rotors": [{"name": "a", "mass": 1.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.1,
                        "diametral_inertia": 0.1}]}
    with pytest.raises(InputError, match="no \\[stator\\]"):
        parse_key("stator.mass", data)
