"""The four band options (``campbell --freq-range``, ``ucs-map``/``report --operating``,
``study --speed-band``, ``fit --freq-band``) read ``LO:HI`` with one parser: every one refuses the
same malformed values in one line with exit 2, before any computation."""

from __future__ import annotations

import pytest

from rotordyn_modal.cli.main import main

#: command -> (argv before the band option, the band option, whether a negative LO is meaningful)
COMMANDS = {
    "campbell": (lambda ex, tmp: ["campbell", str(ex / "gear_machine.toml"), "--speeds", "0:3000:11",
                                  "--plot", str(tmp / "c.png"), "--quiet"], "--freq-range", False),
    "ucs-map": (lambda ex, tmp: ["ucs-map", str(ex / "journal_rotor.toml"), "--stiffness", "1e5:1e10:11",
                                 "--modes", "2", "--out", str(tmp / "u.csv")], "--operating", False),
    "report": (lambda ex, tmp: ["report", str(ex / "motor_fan_minimal.toml"), "--standard", "api617",
                                "--mcs", "3000", "--out", str(tmp / "r.html"), "--quiet"], "--operating", False),
    "study": (lambda ex, tmp: ["study", str(ex / "gear_machine.toml"), "--spec",
                               str(ex / "mount_tolerance.study.toml"), "--out", str(tmp / "s.nc"), "--quiet"],
              "--speed-band", True),
    "fit": (lambda ex, tmp: ["fit", str(ex / "gear_machine.toml"), "--measured", str(ex / "gear_machine.toml"),
                             "--params", "gain", "--out", str(tmp / "f.toml"), "--quiet"], "--freq-band", False),
}

#: values that are no band: not two numbers joined by one ':', not finite, or LO >= HI
#: sub-commands whose operating range may be one speed (LO = HI): the UCS map draws it as a line
ONE_SPEED_COMMANDS = {"ucs-map", "report"}

MALFORMED = ["", "10", "1,10", "1:2:3", "1::2", "x:10", "nan:10", "0:inf", "5:5", "10:5"]


@pytest.mark.parametrize("value", MALFORMED + ["-5:10"], ids=repr)
@pytest.mark.parametrize("command", COMMANDS)
def test_a_malformed_band_is_one_line_and_exit_2(command, value, examples_dir, tmp_path, capsys):
    base, option, negatives = COMMANDS[command]
    if value == "-5:10" and negatives:
        pytest.skip(f"{option}: a band of negative speeds is meaningful (as in the study file)")
    if value == "5:5" and command in ONE_SPEED_COMMANDS:
        pytest.skip(f"{command} {option}: LO = HI is one rated speed, drawn as a line "
                    "(tests/test_ucs_operating_speed.py)")
    code = main(base(examples_dir, tmp_path) + [f"{option}={value}"])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and f": error: {option} " in lines[0], err
    assert not any(tmp_path.iterdir())      # refused before anything is written


@pytest.mark.parametrize("command", COMMANDS)
def test_a_negative_value_reaches_the_band_parser(command, examples_dir, tmp_path, capsys):
    """``--option -5:10`` (no '='): the value is read as the option's, not as another option."""
    base, option, negatives = COMMANDS[command]
    if negatives:
        pytest.skip("accepted: would run the study")
    code = main(base(examples_dir, tmp_path) + [option, "-5:10"])
    err = capsys.readouterr().err
    assert code == 2 and f": error: {option} " in err and "-5:10" in err and "<" in err, err
