"""A key or table given twice in a model or study file is refused naming the key, its table,
its line and the second value (docs/model-file.md). Before, the line held only tomllib's
words and no key: ``m.toml: <file> = 'Cannot overwrite a value (at line 8, column 12)': expected
valid TOML`` (or ``Cannot declare ('stator',) twice``)."""

from __future__ import annotations

import pytest

from rotordyn_modal.cli import main

MODEL = """\
name = "rigid rotor"
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
position = [-0.2, 0.0, 0.0]
stiffness = 1.0e6
"""


def _refusal(path, capsys, *argv):
    code = main(["check", str(path), *argv] if not argv else [*argv])
    _, err = capsys.readouterr()
    assert code == 2 and "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize("edit, said", [
    # the rotor's mass twice: line 8, in [[rotors]], the second value
    (("mass = 10.0\n", "mass = 10.0\nmass = 11.0   # kg\n"),
     "line 8: [[rotors]] mass = 11.0: expected each key once in its table: mass is given a second time"),
    # a top-level key twice
    (('name = "rigid rotor"\n', 'name = "rigid rotor"\nname = "a # b"\n'),
     'line 2: name = "a # b": expected each key once in its table: name is given a second time'),
    # a bearing's stiffness twice, written as a dotted key of the same table
    (("stiffness = 1.0e6\n\n[[bearings]]", "stiffness = 1.0e6\nstiffness = 2.0e6\n\n[[bearings]]"),
     "line 18: [[bearings]] stiffness = 2.0e6: expected each key once in its table"),
])
def test_a_key_given_twice_is_named_with_its_line_table_and_value(tmp_path, capsys, edit, said):
    path = tmp_path / "twice.toml"
    path.write_text(MODEL.replace(*edit, 1))
    line = _refusal(path, capsys)
    assert f"twice.toml: {said}" in line, line


def test_a_table_declared_twice_is_named_with_its_line(tmp_path, capsys):
    path = tmp_path / "stator.toml"
    path.write_text(MODEL + "\n[stator]\nmass = 100.0\n\n[stator]\ninertia = [1.0, 1.0, 1.0]\n")
    line = _refusal(path, capsys)
    assert "stator.toml: line 28: table header = [stator]: expected each table once" in line, line


def test_a_study_file_with_a_key_twice_is_refused_alike(tmp_path, capsys):
    model = tmp_path / "m.toml"
    model.write_text(MODEL)
    spec = tmp_path / "s.study.toml"
    spec.write_text("samples = 4\nsamples = 8\n[[parameters]]\nkey = \"bearings.A.stiffness\"\n"
                    "distribution = \"uniform\"\nlow = 1e6\nhigh = 2e6\n[analyses.campbell]\nspeeds_rpm = \"0:100:3\"\n")
    line = _refusal(None, capsys, "study", str(model), "--spec", str(spec), "--out", str(tmp_path / "r.nc"))
    assert "s.study.toml: line 2: samples = 8: expected each key once in its table" in line, line
