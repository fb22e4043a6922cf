"""Every validation rule, with its message: file, table and key, value, what was expected."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import tomli_w

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError, ModelError

BASE = {
    "name": "valid",
    "spin_axis": [1.0, 0.0, 0.0],
    "reference_rotor": "motor",
    "stator": {"mass": 150.0, "center_of_mass": [0.0, 0.0, 0.1],
               "inertia": [[12.0, 0.0, 0.3], [0.0, 10.0, 0.0], [0.3, 0.0, 8.0]]},
    "rotors": [
        {"name": "motor", "mass": 20.0, "center_of_mass": [0.2, 0.0, 0.15], "polar_inertia": 0.08,
         "diametral_inertia": 0.05, "speed_ratio": 1.0},
        {"name": "fan", "mass": 8.0, "center_of_mass": [-0.3, 0.0, 0.25], "polar_inertia": 0.3,
         "diametral_inertia": 0.16},
    ],
    "transmissions": [{"type": "gear", "driver": "motor", "driven": "fan", "ratio": 2.5, "driver_teeth": 23}],
    "suspensions": [{"name": "mount-FL", "position": [0.4, 0.3, -0.2], "stiffness": [2e5, 1.5e5, 4e5],
                     "damping": [150.0, 120.0, 300.0]},
                    {"name": "mount-RR", "position": [-0.4, -0.3, -0.2], "stiffness": [2e5, 1.5e5, 4e5]}],
    "unbalances": [{"rotor": "fan", "amount": 2e-4}],
    "sensors": [{"name": "acc", "position": [0.0, 0.0, 0.5], "direction": [0.0, 0.0, 1.0]}],
    "excitations": [{"name": "hammer", "position": [0.0, 0.3, 0.5], "direction": [0.0, 0.0, 1.0]}],
}


def test_base_is_valid():
    model = rdm.Model.from_dict(BASE)
    assert model.speed_ratios == {"motor": 1.0, "fan": pytest.approx(-0.4, rel=1e-15)}


def edit(path, value):
    """A description with one value replaced (path: keys and indices), or deleted (value=DEL)."""
    data = copy.deepcopy(BASE)
    target = data
    for key in path[:-1]:
        target = target[key]
    if value is DEL:
        del target[path[-1]]
    else:
        target[path[-1]] = value
    return data


class _Deleted:
    """Marks a key removed from the model (a stable repr keeps test ids equal across pytest-xdist workers)."""

    def __repr__(self):
        return "<deleted>"


DEL = _Deleted()
NOT_SPD = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]
NOT_SYMMETRIC = [[12.0, 0.5, 0.3], [0.0, 10.0, 0.0], [0.3, 0.0, 8.0]]
TRIANGLE = [1.0, 1.0, 3.0]

CASES = [
    # (path, value, where, expected (substring))
    (("stator", "mass"), -1.0, "[stator] mass", "> 0"),
    (("stator", "mass"), 0.0, "[stator] mass", "> 0"),
    (("stator", "mass"), math.nan, "[stator] mass", "finite"),
    (("stator", "mass"), math.inf, "[stator] mass", "finite"),
    (("stator", "mass"), "heavy", "[stator] mass", "finite number"),
    (("stator", "mass"), True, "[stator] mass", "finite number"),
    (("stator", "mass"), DEL, "[stator] mass", "required"),
    (("rotors", 1, "mass"), -8.0, "[rotors.fan] mass", "> 0"),
    (("rotors", 0, "polar_inertia"), 0.0, "[rotors.motor] polar_inertia", "> 0"),
    (("rotors", 0, "diametral_inertia"), math.nan, "[rotors.motor] diametral_inertia", "finite"),
    (("stator", "inertia"), NOT_SYMMETRIC, "[stator] inertia", "symmetric"),
    (("stator", "inertia"), NOT_SPD, "[stator] inertia", "positive definite"),
    (("stator", "inertia"), [0.0, 1.0, 1.0], "[stator] inertia", "positive definite"),
    (("stator", "inertia"), TRIANGLE, "[stator] inertia", "triangle inequality"),
    (("stator", "inertia"), [1.0, 2.0], "[stator] inertia", "3-list or a 3x3 matrix"),
    (("stator", "inertia"), [[1.0, 0.0], [0.0, 1.0]], "[stator] inertia", "3x3"),
    (("rotors", 1, "polar_inertia"), 0.33, "[rotors.fan] polar_inertia", "at most twice diametral_inertia"),
    (("rotors", 0, "center_of_mass"), [0.1, 0.2], "[rotors.motor] center_of_mass", "3-list"),
    (("rotors", 0, "center_of_mass"), [0.1, 0.2, math.inf], "[rotors.motor] center_of_mass", "finite"),
    (("rotors", 0, "center_of_mass"), DEL, "[rotors.motor] center_of_mass", "required"),
    (("suspensions", 0, "position"), [[0.0, 0.0, 0.0]], "[suspensions.mount-FL] position", "3-list"),
    (("suspensions", 0, "stiffness"), [1.0, 2.0, 3.0, 4.0], "[suspensions.mount-FL] stiffness", "6x6"),
    (("suspensions", 0, "stiffness"), [1e5, -1e5, 1e5], "[suspensions.mount-FL] stiffness", "non-negative"),
    (("suspensions", 0, "stiffness"), DEL, "[suspensions.mount-FL] stiffness", "required"),
    (("suspensions", 0, "damping"), [[1.0, 2.0]], "[suspensions.mount-FL] damping", "3x3"),
    (("suspensions", 0, "loss_factor"), -0.1, "[suspensions.mount-FL] loss_factor", ">= 0"),
    (("suspensions", 0, "axes"), [[1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 1.0]],
     "[suspensions.mount-FL] axes", "orthogonal"),
    (("suspensions", 0, "axes"), [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
     "[suspensions.mount-FL] axes", "non-zero"),
    (("suspensions", 0, "axes"), [1.0, 0.0, 0.0], "[suspensions.mount-FL] axes", "3x3"),
    (("reference_rotor",), "pump", "reference_rotor", "one of the rotors motor, fan"),
    (("reference_rotor",), DEL, "reference_rotor", "required with several rotors"),
    (("reference_rotor",), ["motor"], "reference_rotor", "a non-empty string"),
    (("reference_rotor",), {"a": 1}, "reference_rotor", "a non-empty string"),
    (("transmissions", 0, "driver"), "pump", "[transmissions[0]] driver", "one of the rotors motor, fan"),
    (("transmissions", 0, "driven"), "pump", "[transmissions[0]] driven", "one of the rotors motor, fan"),
    (("transmissions", 0, "driven"), "motor", "[transmissions[0]] driven", "other than the driver"),
    (("transmissions", 0, "type"), "chain", "[transmissions[0]] type", "'gear', 'belt'"),
    (("transmissions", 0, "ratio"), 0.0, "[transmissions[0]] ratio", "> 0"),
    (("transmissions", 0, "driver_teeth"), 2.5, "[transmissions[0]] driver_teeth", "whole number"),
    (("unbalances", 0, "rotor"), "pump", "[unbalances[0]] rotor", "one of the rotors motor, fan"),
    (("unbalances", 0, "amount"), -1e-4, "[unbalances[0]] amount", "> 0"),
    (("spin_axis",), [0.0, 0.0, 0.0], "spin_axis", "non-zero length"),
    (("spin_axis",), [1.0, 0.0], "spin_axis", "3-list"),
    (("sensors", 0, "direction"), [0.0, 0.0, 0.0], "[sensors.acc] direction", "non-zero length"),
    (("excitations", 0, "kind"), "torque", "[excitations.hammer] kind", "'force', 'moment'"),
    (("colour",), "red", "colour", "unknown key"),
    (("stator", "colour"), "red", "[stator] colour", "unknown key"),
    (("rotors", 0, "spin"), 1.0, "[rotors.motor] spin", "unknown key"),
    (("suspensions", 1, "stifness"), [1.0, 1.0, 1.0], "[suspensions.mount-RR] stifness", "unknown key"),
    (("transmissions", 0, "teeth"), 3, "[transmissions[0]] teeth", "unknown key"),
    (("rotors", 1, "name"), "motor", "[rotors[1]] name", "unique"),
    (("rotors",), {"name": "x"}, "rotors", "array of tables"),
    (("stator",), [1, 2], "stator", "a table"),
    # strings and booleans are never numbers, in lists too (as `mass = "150"` above)
    (("spin_axis",), ["1e0", "0", "0"], "spin_axis", "[0] is the string '1e0', not a number"),
    (("spin_axis",), [True, False, False], "spin_axis", "[0] is the boolean True, not a number"),
    (("spin_axis",), [1.0, 0, "0"], "spin_axis", "[2] is the string '0', not a number"),
    (("suspensions", 0, "stiffness"), [2e5, "1.5e5", 4e5], "[suspensions.mount-FL] stiffness",
     "[1] is the string '1.5e5', not a number"),
    (("stator", "inertia"), [[12.0, 0.0, 0.3], [0.0, "10", 0.0], [0.3, 0.0, 8.0]], "[stator] inertia",
     "[1][1] is the string '10', not a number"),
    (("rotors", 0, "center_of_mass"), [0.2, False, 0.15], "[rotors.motor] center_of_mass",
     "[1] is the boolean False, not a number"),
    (("sensors", 0, "direction"), [0.0, 0.0, {"z": 1}], "[sensors.acc] direction", "not a number"),
]


@pytest.mark.parametrize("path, value, where, expected", CASES,
                         ids=[f"{'.'.join(map(str, c[0]))}={c[1]!r}"[:60] for c in CASES])
def test_rule_and_message(path, value, where, expected):
    data = edit(path, value)
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="machine.toml")
    error = info.value
    message = str(error)
    assert message.startswith("machine.toml: ")
    assert where in message, message
    assert expected in message, message
    assert error.source == "machine.toml"
    if value is not DEL and not isinstance(value, dict):
        assert repr(value)[:20] in message or str(value)[:20] in message, message
    assert isinstance(error, InputError)


def test_rotor_that_nothing_fixes():
    data = edit(("transmissions",), [])
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="m.toml")
    assert "[rotors.fan] speed_ratio" in str(info.value)
    assert "neither speed_ratio nor a chain" in str(info.value)


def test_two_routes_that_disagree():
    data = edit(("rotors", 1, "speed_ratio"), 0.4)  # the gear gives -0.4
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="m.toml")
    message = str(info.value)
    assert "fan" in message and "-0.4" in message and "0.4" in message
    # two routes that agree are accepted
    assert rdm.Model.from_dict(edit(("rotors", 1, "speed_ratio"), -0.4)).speed_ratios["fan"] == -0.4


@pytest.mark.parametrize("relative, accepted", [(1e-12, True), (1e-7, False)])
def test_two_routes_agree_only_to_round_off(relative, accepted):
    """A stated speed ratio may differ from the gear chain's (-1/2.5) by round-off, not by more."""
    data = edit(("rotors", 1, "speed_ratio"), -0.4 * (1 + relative))
    if accepted:
        assert rdm.Model.from_dict(data).speed_ratios["fan"] == pytest.approx(-0.4, rel=2e-12)
    else:
        with pytest.raises(ModelError, match="fixes the speed ratio of 'fan'"):
            rdm.Model.from_dict(data)


def test_a_cycle_of_transmissions_that_disagrees():
    data = copy.deepcopy(BASE)
    data["rotors"].append({"name": "pump", "mass": 3.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.01,
                           "diametral_inertia": 0.01})
    data["transmissions"] += [{"type": "belt", "driver": "motor", "driven": "pump", "ratio": 2.0},
                              {"type": "belt", "driver": "pump", "driven": "fan", "ratio": 1.0}]
    with pytest.raises(ModelError, match="speed ratio"):
        rdm.Model.from_dict(data)
    data["transmissions"][2]["type"] = "gear"
    data["transmissions"][2]["ratio"] = 1.25  # motor -> pump 0.5 -> fan -0.4: consistent
    assert rdm.Model.from_dict(data).speed_ratios["fan"] == pytest.approx(-0.4, rel=1e-12)


def test_spin_axis_is_normalised_and_axes_orthonormalised():
    data = edit(("spin_axis",), [3.0, 0.0, 4.0])
    data["suspensions"][0]["axes"] = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 0.5]]
    model = rdm.Model.from_dict(data)
    np.testing.assert_allclose(model.spin_axis, [0.6, 0.0, 0.8], rtol=1e-15)
    np.testing.assert_allclose(model.suspensions[0].axes, np.eye(3), atol=1e-15)


def test_axes_rounded_in_the_file_become_exactly_orthonormal():
    """Axes turned 0.7 rad about (1, 2, 3), written to 7 digits: the model's are the nearest
    orthonormal axes (exactly orthonormal to round-off, within the file's rounding of the
    true ones), so that the rounding does not leak into the stiffness as a spurious coupling."""
    from scipy.spatial.transform import Rotation

    exact = Rotation.from_rotvec(0.7 * np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)).as_matrix()
    data = copy.deepcopy(BASE)
    data["suspensions"][0]["axes"] = np.round(exact, 7).tolist()
    axes = rdm.Model.from_dict(data).suspensions[0].axes
    # SVD factors and two 3 x 3 products: round-off of a few n eps; the rounding was 1e-8
    np.testing.assert_allclose(axes @ axes.T, np.eye(3), rtol=0, atol=4e-15)
    np.testing.assert_allclose(axes, exact, rtol=0, atol=1e-7)


def test_no_rotors_and_no_stator():
    with pytest.raises(ModelError, match="at least one"):
        rdm.Model.from_dict({"suspensions": []})


def test_not_a_mapping():
    with pytest.raises(ModelError):
        rdm.Model.from_dict([1, 2, 3])


# -- files ---------------------------------------------------------------------------------
def test_file_that_is_not_toml(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[stator\nmass = 1\n")
    with pytest.raises(ModelError) as info:
        rdm.load_model(path)
    assert str(path) in str(info.value) and "valid TOML" in str(info.value)


def test_byte_order_mark_is_skipped(tmp_path, examples_dir):
    """Windows editors begin UTF-8 files with a byte-order mark: the model reads as without it."""
    text = (examples_dir / "fan_on_bearings.toml").read_bytes()
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + text)
    assert rdm.load_model(path).to_dict() == rdm.load_model(examples_dir / "fan_on_bearings.toml").to_dict()


@pytest.mark.parametrize("depth", [33, 400, 5000])
def test_deeply_nested_arrays_are_refused_in_one_line(tmp_path, depth, capsys):
    """A 10 kB file of nested brackets made Python's TOML parser exhaust its recursion (exit 1)."""
    from rotordyn_modal.cli import main

    path = tmp_path / "deep.toml"
    path.write_text("spin_axis = " + "[" * depth + "]" * depth + "\n")
    with pytest.raises(ModelError, match=r"expected TOML with arrays and tables nested at most 32 deep"):
        rdm.load_model(path)
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err and "nested at most 32 deep" in err


def test_nesting_up_to_the_limit_reaches_the_rules(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text("spin_axis = " + "[" * 32 + "]" * 32 + "\n")
    with pytest.raises(ModelError, match=r"spin_axis = .*expected a 3-list"):
        rdm.load_model(path)


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.toml"
    with pytest.raises(ModelError) as info:
        rdm.load_model(path)
    assert str(path) in str(info.value) and "no such file" in str(info.value)


def test_a_folder_and_binary_file(tmp_path):
    with pytest.raises(ModelError, match="folder"):
        rdm.load_model(tmp_path)
    binary = tmp_path / "x.toml"
    binary.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(ModelError, match="UTF-8"):
        rdm.load_model(binary)


def test_file_errors_name_the_file(tmp_path):
    path = tmp_path / "fan.toml"
    path.write_bytes(tomli_w.dumps(edit(("rotors", 1, "mass"), -3.0)).encode())
    with pytest.raises(ModelError) as info:
        rdm.load_model(path)
    assert str(info.value) == f"{path}: [rotors.fan] mass = -3.0: expected a finite number > 0"


def test_model_built_in_code_is_validated_too():
    with pytest.raises(ModelError, match=r"\[rotors.r\] mass = -1.0"):
        rdm.Model(rotors=[rdm.Rotor("r", -1.0, [0, 0, 0], 0.05, 0.04, speed_ratio=1.0)])


def test_boundaries_are_accepted():
    """A thin disc (Jp = 2 Jd) and a flat plate (Izz = Ixx + Iyy) are rigid bodies."""
    data = edit(("rotors", 1, "polar_inertia"), 0.32)
    data["stator"]["inertia"] = [3.0, 5.0, 8.0]
    model = rdm.Model.from_dict(data)
    assert model.rotor("fan").polar_inertia == 0.32


def test_reference_rotor_with_a_ratio_other_than_one():
    data = edit(("rotors", 0, "speed_ratio"), 2.0)
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="m.toml")
    assert "[rotors.motor] speed_ratio = 2.0" in str(info.value) and "ratio 1" in str(info.value)


# a tab or a line break in a name is refused at the name itself (tests/test_input_families5.py)
@pytest.mark.parametrize("name, shown", [("mount\u200b-FL", r"'mount\u200b-FL'"), ("mount-FL\xa0", r"'mount-FL\xa0'"),
                                         (" mount-FL", "' mount-FL'")])
def test_names_with_invisible_characters_are_shown_escaped(name, shown):
    """A zero-width space, a non-breaking space, a leading space or a tab in a name would make a
    message name something the reader cannot tell from a plain name: it is shown escaped, in the
    table's label and in the lists of names the message offers."""
    data = edit(("suspensions", 0, "name"), name)
    data["suspensions"][0]["stiffness"] = [1e5, -1e5, 1e5]
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="machine.toml")
    assert str(info.value).startswith(f"machine.toml: [suspensions.{shown}] stiffness = ")
    data = edit(("rotors", 1, "name"), name.replace("mount", "fan"))
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="machine.toml")   # the gear's driven rotor is now unknown
    assert str(info.value).endswith(f"expected the name of one of the rotors motor, {shown.replace('mount', 'fan')}")


def test_plain_names_are_shown_as_they_are():
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(edit(("suspensions", 0, "stiffness"), [1e5, -1e5, 1e5]), source="m.toml")
    assert str(info.value).startswith("m.toml: [suspensions.mount-FL] stiffness = ")


def _geared(names, meshes):
    """Rotors on the stator of BASE, geared in a chain: meshes (driver, driven, teeth)."""
    data = copy.deepcopy(BASE)
    rotor = data["rotors"][1]
    data["rotors"] = [dict(rotor, name=n, **({"speed_ratio": 1.0} if n == names[0] else {})) for n in names]
    data["reference_rotor"] = names[0]
    data["transmissions"] = [{"type": "gear", "driver": a, "driven": b, "ratio": 2.0, "driver_teeth": z}
                             for a, b, z in meshes]
    data["unbalances"] = []
    return data


def test_gear_meshes_whose_source_names_coincide_are_refused():
    """Rotors 'a-b' and 'c', 'a' and 'b-c': the meshes a-b->c and a->b-c would both be the excitation
    source 'mesh:a-b-c' (Campbell diagrams, critical speeds); the second one is refused, naming both."""
    data = _geared(["a-b", "c", "a", "b-c"], [("a-b", "c", 20), ("c", "a", 30), ("a", "b-c", 25)])
    with pytest.raises(ModelError) as info:
        rdm.Model.from_dict(data, source="m.toml")
    message = str(info.value)
    assert message.startswith("m.toml: [transmissions[2]] driven = 'b-c': expected rotor names that tell")
    assert "a -> b-c and the mesh a-b -> c would both be the excitation source 'mesh:a-b-c'" in message
    from rotordyn_modal.analysis.critical_speeds import excitation_sources

    del data["transmissions"][2]["driver_teeth"]      # without teeth the third gear is no source
    names = excitation_sources(rdm.Model.from_dict(data)).names
    assert len(set(names)) == len(names) and "mesh:a-b-c" in names


def test_a_rotor_named_like_a_mesh_is_refused():
    data = _geared(["a", "b", "mesh:a-b"], [("a", "b", 20), ("b", "mesh:a-b", 1)])
    data["transmissions"][1].pop("driver_teeth")
    with pytest.raises(ModelError, match=r"\[transmissions\[0\]\] driver_teeth = 20: expected a mesh whose "
                                         r"source name 'mesh:a-b' is not also a rotor's name"):
        rdm.Model.from_dict(data)


def test_names_with_dashes_are_fine_while_the_meshes_stay_apart():
    from rotordyn_modal.analysis.critical_speeds import excitation_sources

    model = rdm.Model.from_dict(_geared(["motor-1", "fan-2"], [("motor-1", "fan-2", 23)]))
    assert excitation_sources(model).names == ("motor-1", "fan-2", "mesh:motor-1-fan-2")


# -- legal but implausible: one warning line ------------------------------------------------------
def _block_on_a_spring(k, gravity=-9.81, mass=100.0):
    """A 100 kg block on one suspension at its centre of mass, stiffness k [N/m] in translation
    (stiff in rotation): its static sag under gravity is m g / k, its translation modes
    sqrt(k / m) / (2 pi)."""
    return {"stator": {"mass": mass, "inertia": [2.0, 2.0, 2.0]},
            "suspensions": [{"name": "mount\u200b", "position": [0.0, 0.0, 0.0],
                             "stiffness": [k, k, k, 1e6, 1e6, 1e6]}],
            "gravity": [0.0, 0.0, gravity]}


def _load_warnings(tmp_path, data):
    import warnings

    path = tmp_path / "m.toml"
    path.write_text(tomli_w.dumps(data))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rdm.load_model(path)
    return [str(w.message) for w in caught if issubclass(w.category, rdm.errors.ModelWarning)]


def test_a_mount_stiffness_that_would_let_the_machine_sag_metres_draws_one_warning(tmp_path):
    """1e3 N/m under 100 kg: a sag of m g / k = 0.981 m (a 1e6 N/m mount typed in N/mm)."""
    lines = _load_warnings(tmp_path, _block_on_a_spring(1e3))
    assert len(lines) == 1
    assert f"under gravity the machine would sag {100 * 9.81 / 1e3:.3g} m at [suspensions.'mount\\u200b']" in lines[0]
    assert _load_warnings(tmp_path, _block_on_a_spring(100 * 9.81 / 0.099)) == []       # 99 mm: plausible


def test_a_mount_mode_below_half_a_hertz_draws_one_warning_without_gravity(tmp_path):
    k = (2 * np.pi * 0.3)**2 * 100.0                            # translation modes at 0.3 Hz
    lines = _load_warnings(tmp_path, _block_on_a_spring(k, gravity=0.0))
    assert len(lines) == 1 and "lowest mode on its suspensions is at 0.3 Hz, below 0.5 Hz" in lines[0]
    assert _load_warnings(tmp_path, _block_on_a_spring(k * (0.51 / 0.3)**2, gravity=0.0)) == []


def test_suspensions_that_do_not_hold_the_weight_draw_a_warning(tmp_path):
    data = _block_on_a_spring(1e6)
    data["suspensions"][0]["stiffness"] = [1e6, 1e6, 0.0, 1e6, 1e6, 1e6]
    (line,) = _load_warnings(tmp_path, data)
    assert "do not hold the machine's weight (100 kg under gravity)" in line


def test_a_journal_bearing_longer_than_its_diameter_draws_a_warning(tmp_path, examples_dir):
    import tomllib

    data = tomllib.loads((examples_dir / "journal_rotor.toml").read_text())
    data["bearings"][0]["length"] = 0.05                                 # L/D = 1: no word
    assert _load_warnings(tmp_path, data) == []
    data["bearings"][0]["length"] = 0.075
    (line,) = _load_warnings(tmp_path, data)
    assert "[bearings.DE] length = 0.075: L/D = 1.5 is beyond 1" in line


def test_the_examples_draw_no_warning(examples_dir, tmp_path):
    import tomllib

    for path in sorted(examples_dir.glob("*.toml")):
        if not path.name.endswith(".study.toml"):
            assert _load_warnings(tmp_path, tomllib.loads(path.read_text())) == [], path.name


def test_the_command_line_prints_the_warning_once_and_goes_on(tmp_path, capsys):
    from rotordyn_modal.cli import main

    path = tmp_path / "soft.toml"
    path.write_text(tomli_w.dumps(_block_on_a_spring(1e3)))
    for command in (["check"], ["modes", "--speed", "0", "--quiet"]):
        assert main([*command, str(path)]) == 0
        lines = capsys.readouterr().err.splitlines()
        assert len(lines) == 1 and lines[0].startswith(f"rotordyn-modal {command[0]}: warning: {path}: under "
                                                       "gravity the machine would sag 0.981 m")
