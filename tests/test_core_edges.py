"""Edge cases of the core found in review: left-handed suspension axes, products of
inertia as parameters, the same file for two outputs, a closed pipe."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main


def _machine(stiffness, axes=None):
    mount = {"name": "m", "position": [0.1, 0.2, -0.3], "stiffness": stiffness}
    if axes is not None:
        mount["axes"] = axes
    return rdm.Model.from_dict({
        "stator": {"mass": 10.0, "inertia": [1.0, 1.0, 1.0]},
        "suspensions": [mount],
    })


def test_left_handed_axes_transform_moments_as_axial_vectors():
    rng = np.random.default_rng(3)
    coupled = rng.normal(size=(6, 6)) * 1e3 + np.eye(6) * 1e5
    mirror = np.diag([1.0, 1.0, -1.0])  # rows: x, y, -z: a left-handed set of axes
    # the same physical mount seen in the mirrored axes: translations are polar vectors
    # (u' = L u), rotations and moments axial vectors (theta' = det(L) L theta = -L theta)
    transform = np.zeros((6, 6))
    transform[:3, :3] = mirror
    transform[3:, 3:] = -mirror
    in_mirrored_axes = transform @ coupled @ transform.T
    reference = _machine(coupled.tolist()).matrices().K
    mirrored = _machine(in_mirrored_axes.tolist(), mirror.tolist()).matrices().K
    np.testing.assert_allclose(mirrored, reference, rtol=1e-13, atol=1e-9)


def test_a_product_of_inertia_is_one_parameter(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    varied = model.with_values({"stator.inertia[0][2]": 0.5})
    tensor = np.array(varied.to_dict()["stator"]["inertia"])
    assert tensor[0, 2] == tensor[2, 0] == 0.5


def test_out_and_plot_naming_the_same_file_are_refused(examples_dir, tmp_path, capsys):
    target = tmp_path / "same.png"
    code = main(["modes", str(examples_dir / "gear_machine.toml"), "--out", str(target),
                 "--plot", str(target)])
    assert code == 2
    assert "same file" in capsys.readouterr().err
    assert not target.exists()
    # the same file under two spellings
    (tmp_path / "sub").mkdir()
    code = main(["modes", str(examples_dir / "gear_machine.toml"), "--out", str(tmp_path / "sub" / ".." / "same.png"),
                 "--plot", str(target)])
    assert code == 2
    assert "same file" in capsys.readouterr().err
    assert not target.exists()


def test_a_closed_pipe_ends_quietly(examples_dir):
    command = (f"{sys.executable} -m rotordyn_modal.cli.main campbell "
               f"{examples_dir / 'gear_machine.toml'} --speeds 0:3000:3001 | head -1")
    completed = subprocess.run(["bash", "-c", command], capture_output=True, text=True, timeout=120)
    assert "Traceback" not in completed.stderr and "BrokenPipe" not in completed.stderr


def test_unit_conversions_are_exact_and_refuse_unknown_units():
    """One revolution per second is 2 pi rad/s, 60 rpm and 1 Hz; the conversions invert each
    other, keep scalars scalar, and a unit that is none of rpm, rad/s, hz is refused by name."""
    from rotordyn_modal import units
    from rotordyn_modal.errors import InputError

    assert units.rpm(60.0) == units.hz(1.0) == 2 * np.pi
    assert units.to_rpm(2 * np.pi) == 60.0 and units.to_hz(2 * np.pi) == 1.0
    assert isinstance(units.hz(1), float) and isinstance(units.to_hz(1), float)
    np.testing.assert_array_equal(units.to_hz(units.hz([0.5, 2.0])), [0.5, 2.0])
    for unit, factor in (("rpm", np.pi / 30), ("RPM", np.pi / 30), ("rad/s", 1.0), ("Hz", 2 * np.pi)):
        np.testing.assert_array_equal(units.speed_to_rad_s([1.0, 3.0], unit), [factor, 3 * factor])
        np.testing.assert_allclose(units.speed_from_rad_s(units.speed_to_rad_s([1.0, 3.0], unit), unit),
                                   [1.0, 3.0], rtol=1e-15)
    with pytest.raises(InputError, match=r"speed unit 'rev/min': expected one of rpm, rad/s, hz"):
        units.speed_to_rad_s(1.0, "rev/min")
    with pytest.raises(InputError, match=r"speed unit 'deg/s'"):
        units.speed_from_rad_s(1.0, "deg/s")


def test_unknown_rotor_is_named_with_the_models_rotors(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    assert model.rotor("fan") is model.rotors[1]
    with pytest.raises(KeyError, match="no rotor 'fann': the model's rotors are motor, fan"):
        model.rotor("fann")
