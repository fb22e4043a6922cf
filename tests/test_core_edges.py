"""Edge cases of the core found in review: left-handed suspension axes, products of
inertia as parameters, the same file for two outputs, a closed pipe."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

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
