"""One vocabulary on the command line: a sensor is ``--sensor``, an excitation ``--excitation``,
a band says what it holds (``--freq-band`` in Hz, ``--speed-band`` in rpm), ``--forces`` takes
the same kinds everywhere, and every sub-command has ``--verbose``. The old spellings
(``--output``, ``--input``, ``--band``) still work and give the very same results."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli.commands import SUBCOMMANDS
from rotordyn_modal.cli.main import build_parser, main

ROOT = Path(__file__).resolve().parent.parent


def _csv(tmp_path, name, argv):
    out = tmp_path / name
    assert main(argv + ["--out", str(out), "--quiet"]) == 0
    return out.read_text()


def test_frf_sensor_and_excitation_equal_the_old_output_and_input(tmp_path, examples_dir):
    base = ["frf", str(examples_dir / "gear_machine.toml"), "--freqs", "1:60:40"]
    new = _csv(tmp_path, "new.csv", base + ["--sensor", "acc-top-z", "--excitation", "hammer-z"])
    old = _csv(tmp_path, "old.csv", base + ["--output", "acc-top-z", "--input", "hammer-z"])
    assert new == old
    assert {line.split(",")[1:3] == ["acc-top-z", "hammer-z"] for line in new.splitlines()[1:]} == {True}


def test_unbalance_sensor_equals_the_old_output(tmp_path, examples_dir):
    base = ["unbalance", str(examples_dir / "gear_machine.toml"), "--speeds", "0:3000:31"]
    new = _csv(tmp_path, "new.csv", base + ["--sensor", "acc-top-z"])
    assert new == _csv(tmp_path, "old.csv", base + ["--output", "acc-top-z"])
    assert {line.split(",")[1] for line in new.splitlines()[1:]} == {"acc-top-z"}


@pytest.mark.parametrize("command, new, old", [("fit", "--freq-band", "--band"), ("study", "--operating-range", "--band"),
                                               ("study", "--operating-range", "--speed-band"),
                                               ("ucs-map", "--lowest", "--modes"), ("level1", "--mcs", "--speed")])
def test_bands_say_what_they_hold_and_keep_the_old_spelling(command, new, old):
    """A band says what it holds; the N lowest modes are --lowest N (as in campbell), the maximum
    continuous speed --mcs (as in unbalance and report): one option, both spellings (the old one
    hidden from --help, tests/test_cli_vocabulary2.py)."""
    parser = build_parser()
    sub = parser._subparsers._group_actions[0].choices[command]
    shown, hidden = sub._option_string_actions[new], sub._option_string_actions[old]
    assert (hidden.dest, hidden.type, hidden.choices, hidden.nargs) == (shown.dest, shown.type, shown.choices, shown.nargs)


def test_frf_forces_all_is_the_three_kinds_together(examples_dir):
    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    freqs = np.linspace(1.0, 60.0, 9)
    kinds = [rdm.force_frf(model, 300.0, freqs, where=w) for w in ("suspensions", "bearings", "rotors")]
    every = rdm.force_frf(model, 300.0, freqs, where="all")
    n_sus, n_brg = 6 * len(model.suspensions), 6 * len(model.bearings)
    np.testing.assert_array_equal(every.H[:n_sus], kinds[0].H)
    np.testing.assert_array_equal(every.H[n_sus:n_sus + n_brg], kinds[1].H[:n_brg])   # the [[bearings]]
    np.testing.assert_array_equal(every.H[n_sus + n_brg:], kinds[2].H)
    assert every.outputs == kinds[0].outputs + kinds[1].outputs[:n_brg] + kinds[2].outputs


def test_frf_forces_all_on_the_command_line(tmp_path, examples_dir):
    text = _csv(tmp_path, "f.csv", ["frf", str(examples_dir / "fan_on_bearings.toml"), "--freqs", "1:60:5",
                                    "--forces", "all"])
    outputs = {line.split(",")[1].split(":")[0] for line in text.splitlines()[1:]}
    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    assert outputs == {x.name for x in (*model.suspensions, *model.bearings, *model.rotors)}


@pytest.mark.parametrize("module", SUBCOMMANDS, ids=lambda m: m.NAME)
def test_every_sub_command_has_verbose_and_quiet(module):
    sub = build_parser()._subparsers._group_actions[0].choices[module.NAME]
    assert "--verbose" in sub._option_string_actions and "--quiet" in sub._option_string_actions


def test_check_quiet_says_valid_by_its_exit_code_alone(tmp_path, examples_dir, capsys):
    assert main(["check", str(examples_dir / "motor_fan_minimal.toml"), "--quiet"]) == 0
    assert capsys.readouterr() == ("", "")
    bad = tmp_path / "bad.toml"
    bad.write_text((examples_dir / "motor_fan_minimal.toml").read_text().replace("mass = 120.0", "mass = -120.0"))
    assert main(["check", str(bad), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "mass" in err and "bad.toml" in err


def test_import_ross_quiet_writes_the_same_model_without_its_summary(tmp_path, capsys):
    ross = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"
    assert main(["import-ross", str(ross), "--out", str(tmp_path / "a.toml")]) == 0
    assert "shaft sections" in capsys.readouterr().err
    assert main(["import-ross", str(ross), "--out", str(tmp_path / "b.toml"), "--quiet"]) == 0
    assert capsys.readouterr() == ("", "")
    assert (tmp_path / "a.toml").read_text().replace("a.toml", "b.toml") == (tmp_path / "b.toml").read_text()


def test_verbose_reports_the_peak_memory_once(examples_dir, capsys):
    assert main(["modes", str(examples_dir / "gear_machine.toml"), "--speed", "1000", "--quiet", "--verbose"]) == 0
    err = capsys.readouterr().err
    assert err.count("peak memory") == 1
