"""Two refusals of ``level1`` read as English: ``--mcs 0`` said "of magnitude least 1e-30
rad/s" (a word missing) and ``--forward-mode 9`` on a rotor of one forward mode at its station
"there are 1 modes"."""

from __future__ import annotations

from rotordyn_modal.cli import main

MODEL = """\
name = "symmetric rigid rotor"
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
damping = 500.0

[[bearings]]
name = "B"
rotor = "r"
position = [-0.3, 0.0, 0.0]
stiffness = 1.0e6
damping = 500.0
"""


def _error(tmp_path, capsys, *options):
    path = tmp_path / "rotor.toml"
    path.write_text(MODEL)
    code = main(["level1", str(path), "--station", "r", "--qa", "1e4", *options])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    return err


def test_a_zero_mcs_is_refused_in_a_whole_sentence(tmp_path, capsys):
    assert "expected a maximum continuous speed other than 0 (of magnitude at least 1e-30 rad/s)" in \
        _error(tmp_path, capsys, "--mcs", "0")


def test_one_forward_mode_is_counted_in_the_singular(tmp_path, capsys):
    # at its centre of mass only the cylindrical forward whirl moves the rotor: one forward mode there
    assert "forward mode 9: there is 1 mode of rotor 'r' whirling forward at station r" in \
        _error(tmp_path, capsys, "--mcs", "3000", "--forward-mode", "9")


def test_a_journal_at_rest_asks_for_a_speed_not_a_sweep(capsys):
    """``modes --speed 0`` on journal bearings said "start the speed sweep above zero" (no sweep
    was asked for)."""
    from pathlib import Path

    example = Path(__file__).resolve().parent.parent / "examples" / "journal_rotor.toml"
    code = main(["modes", str(example), "--speed", "0"])
    err = capsys.readouterr().err
    assert code == 2 and "no oil film (eccentricity 1); give a speed above zero" in err and "sweep above" not in err, err
