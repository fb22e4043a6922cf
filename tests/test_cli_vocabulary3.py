"""One vocabulary, continued (issue 27 §5): a spelling shown by two sub-commands means one thing
in both. ``--power`` was the power a transmission carries in ``static`` and a stage's rated power
in ``level1``/``report``: now ``--transmitted-power`` and ``--rated-power``. ``--forces`` added
force rows in ``unbalance`` but replaced the sensors in ``frf``: ``frf --force-outputs`` now.
``--quantity`` takes the same words in ``frf`` and ``unbalance`` (the motion, or the FRF's name of
it). The earlier spellings still work, hidden, with the very same result; an unknown sensor or
excitation is named by its option as typed."""

from __future__ import annotations

import argparse
import re

import numpy as np
import pandas as pd
import pytest

from rotordyn_modal.cli._common import VALUE_OPTIONS, join_negative_values
from rotordyn_modal.cli.main import build_parser, main

#: (sub-command, the spelling --help shows, the earlier spelling kept hidden)
RENAMED = [("static", "--transmitted-power", "--power"), ("level1", "--rated-power", "--power"),
           ("report", "--rated-power", "--power"), ("frf", "--force-outputs", "--forces")]
#: the motion a sensor reads and the FRF's name of that motion per unit force
WORDS = {"displacement": "receptance", "velocity": "mobility", "acceleration": "accelerance"}


def _subs() -> dict:
    return build_parser()._subparsers._group_actions[0].choices


def _mentions(text: str, option: str) -> bool:
    return re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", text) is not None


@pytest.mark.parametrize("command, new, old", RENAMED)
def test_a_renamed_option_is_shown_once_and_its_old_spelling_hidden(command, new, old):
    sub = _subs()[command]
    shown, hidden = sub._option_string_actions[new], sub._option_string_actions[old]
    assert shown.help is not argparse.SUPPRESS and hidden.help is argparse.SUPPRESS
    assert (hidden.dest, hidden.type, hidden.choices, hidden.nargs) == (shown.dest, shown.type, shown.choices,
                                                                        shown.nargs)
    assert not _mentions(sub.format_help(), old), (command, old)


def test_power_names_one_quantity_per_spelling():
    """The power a transmission carries and a stage's rated power have different spellings, and
    no sub-command shows a bare --power."""
    subs = _subs()
    assert "rated" not in subs["static"]._option_string_actions["--transmitted-power"].help
    for command in ("level1", "report"):
        assert "rated power" in subs[command]._option_string_actions["--rated-power"].help
        assert "--transmitted-power" not in subs[command]._option_string_actions
    assert "--rated-power" not in subs["static"]._option_string_actions
    for command, sub in subs.items():
        shown = {s for a in sub._actions if a.help is not argparse.SUPPRESS for s in a.option_strings}
        assert "--power" not in shown, command


def _parse(argv):
    return vars(build_parser().parse_args(join_negative_values(argv, VALUE_OPTIONS)))


@pytest.mark.parametrize("base, new, old, value", [
    (["static", "m.toml", "--speed", "3000"], "--transmitted-power", "--power", "-15000"),
    (["static", "m.toml", "--speed", "3000"], "--transmitted-power", "--power", "motor->fan=10"),
    (["level1", "m.toml", "--mcs", "3000", "--station", "fan"], "--rated-power", "--power", "1e4,2e4"),
    (["report", "m.toml", "--standard", "api617", "--mcs", "3000", "--out", "r.html"], "--rated-power", "--power",
     "1e4"),
    (["frf", "m.toml", "--freqs", "1:40:5"], "--force-outputs", "--forces", "bearings"),
])
def test_the_earlier_spelling_parses_to_the_same_options(base, new, old, value):
    assert _parse(base + [old, value]) == _parse(base + [new, value]) == _parse(base + [f"{old}={value}"])


def test_static_transmitted_power_is_the_earlier_power(tmp_path, examples_dir):
    """Both spellings give the very same file, and the power loads the gears (the file differs
    from the one without it)."""
    base = ["static", str(examples_dir / "gear_machine.toml"), "--speed", "3000", "--quiet"]
    new, old, none = tmp_path / "new.csv", tmp_path / "old.csv", tmp_path / "none.csv"
    assert main(base + ["--transmitted-power", "15000", "--out", str(new)]) == 0
    assert main(base + ["--power", "15000", "--out", str(old)]) == 0
    assert main(base + ["--out", str(none)]) == 0
    assert new.read_bytes() == old.read_bytes() != none.read_bytes()


def test_level1_rated_power_is_the_earlier_power(tmp_path, examples_dir):
    base = ["level1", str(examples_dir / "fan_on_bearings.toml"), "--mcs", "3000", "--station", "fan@-0.1",
            "--impeller-diameter", "0.5", "--restriction-height", "0.03", "--quiet"]
    new, old = tmp_path / "new.csv", tmp_path / "old.csv"
    assert main(base + ["--rated-power", "15e3", "--out", str(new)]) == 0
    assert main(base + ["--power", "15e3", "--out", str(old)]) == 0
    assert new.read_bytes() == old.read_bytes()


@pytest.mark.parametrize("argv, typed", [
    (["static", "{gear}", "--power", "0"], "--power 0: expected a speed"),
    (["static", "{gear}", "--transmitted-power", "0"], "--transmitted-power 0: expected a speed"),
    (["static", "{gear}", "--speed", "100", "--power", "fan->motor=1e3"], "--power fan->motor=1e3: unknown"),
    (["static", "{gear}", "--speed", "100", "--transmitted-power", "1", "--transmitted-power", "2"],
     "--transmitted-power '2': one power"),
    (["level1", "{fan}", "--mcs", "3000", "--station", "fan", "--power", "0", "--impeller-diameter", "0.3",
      "--restriction-height", "0.01"], "--power 0: expected"),
    (["level1", "{fan}", "--mcs", "3000", "--station", "fan", "--rated-power", "0", "--impeller-diameter", "0.3",
      "--restriction-height", "0.01"], "--rated-power 0: expected"),
    (["level1", "{fan}", "--mcs", "3000", "--station", "fan", "--qa", "1e4", "--power", "1e3"],
     "--qa and the stage data (--power, "),
    (["level1", "{fan}", "--mcs", "3000", "--station", "fan", "--impeller-diameter", "0.3"],
     "give --qa N/m, or --rated-power, "),
])
def test_a_power_message_names_the_option_as_typed(argv, typed, examples_dir, capsys):
    fill = {"{fan}": str(examples_dir / "fan_on_bearings.toml"), "{gear}": str(examples_dir / "gear_machine.toml")}
    assert main([fill.get(a, a) for a in argv] + ["--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and f"error: {typed}" in err, err


# --- --forces: one meaning (force rows added after the sensors) --------------------------------

def test_forces_adds_rows_where_it_is_shown_and_force_outputs_replaces_the_sensors(tmp_path, examples_dir):
    """``unbalance --forces`` (shown) keeps the sensors' rows and adds the force rows; ``frf``
    shows no ``--forces``: its ``--force-outputs`` gives forces in place of the sensors, and the
    hidden ``frf --forces`` the very same file."""
    gear = str(examples_dir / "gear_machine.toml")
    for command, sub in _subs().items():
        shown = {s for a in sub._actions if a.help is not argparse.SUPPRESS for s in a.option_strings}
        if "--forces" in shown:
            assert command == "unbalance" and "add" in sub._option_string_actions["--forces"].help
    assert not _mentions(_subs()["frf"].format_help(), "--forces")
    sensors = {"acc-top-z", "acc-side-y"}
    unb = tmp_path / "u.csv"
    assert main(["unbalance", gear, "--speeds", "100:3000:3", "--forces", "suspensions", "--out", str(unb),
                 "--quiet"]) == 0
    outputs = set(pd.read_csv(unb)["output"])
    assert sensors <= outputs and any(o.endswith(":Fx") for o in outputs)
    new, old = tmp_path / "new.csv", tmp_path / "old.csv"
    base = ["frf", gear, "--freqs", "1:40:4", "--quiet"]
    assert main(base + ["--force-outputs", "suspensions", "--out", str(new)]) == 0
    assert main(base + ["--forces", "suspensions", "--out", str(old)]) == 0
    assert new.read_bytes() == old.read_bytes()
    outputs = set(pd.read_csv(new)["output"])
    assert not sensors & outputs and any(o.endswith(":Fx") for o in outputs)


# --- --quantity: one set of words ---------------------------------------------------------------

@pytest.mark.parametrize("command", ["frf", "unbalance"])
def test_quantity_takes_the_same_words_in_frf_and_unbalance(command):
    sub = _subs()[command]
    action = sub._option_string_actions["--quantity"]
    assert action.metavar == _subs()["frf"]._option_string_actions["--quantity"].metavar
    base = {"frf": ["frf", "m.toml", "--freqs", "1:40:5"], "unbalance": ["unbalance", "m.toml", "--speeds", "0:9:3"]}
    for motion, frf_name in WORDS.items():
        assert _parse(base[command] + ["--quantity", motion]) == _parse(base[command] + ["--quantity", frf_name])
        assert motion in action.help + str(action.metavar) and frf_name in action.help


@pytest.mark.parametrize("command", ["frf", "unbalance"])
def test_quantity_refuses_other_words_in_one_line(command, capsys):
    base = {"frf": ["frf", "m.toml", "--freqs", "1:40:5"], "unbalance": ["unbalance", "m.toml", "--speeds", "0:9:3"]}
    with pytest.raises(SystemExit) as stop:
        main(base[command] + ["--quantity", "jerk"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "--quantity" in err and "'jerk'" in err and "velocity" in err


def test_frf_velocity_is_mobility_and_the_derivative_of_receptance(tmp_path, examples_dir):
    """``frf --quantity velocity`` writes the very file of ``mobility``, and it is j omega times
    the receptance (H_v = j 2 pi f H_x)."""
    base = ["frf", str(examples_dir / "gear_machine.toml"), "--speed", "1200", "--freqs", "2:40:5", "--quiet"]
    paths = {q: tmp_path / f"{q}.csv" for q in ("velocity", "mobility", "displacement")}
    for quantity, path in paths.items():
        assert main(base + ["--quantity", quantity, "--out", str(path)]) == 0
    assert paths["velocity"].read_bytes() == paths["mobility"].read_bytes()
    v, x = pd.read_csv(paths["velocity"]), pd.read_csv(paths["displacement"])
    hv, hx = v["real"] + 1j * v["imag"], x["real"] + 1j * x["imag"]
    np.testing.assert_allclose(hv, 2j * np.pi * x["frequency_hz"] * hx, rtol=1e-8, atol=0)


def test_unbalance_mobility_is_velocity_and_omega_times_displacement(tmp_path, examples_dir):
    base = ["unbalance", str(examples_dir / "gear_machine.toml"), "--speeds", "300:3000:4", "--quiet"]
    paths = {q: tmp_path / f"{q}.csv" for q in ("mobility", "velocity", "receptance")}
    for quantity, path in paths.items():
        assert main(base + ["--quantity", quantity, "--out", str(path)]) == 0
    assert paths["mobility"].read_bytes() == paths["velocity"].read_bytes()
    v, x = pd.read_csv(paths["mobility"]), pd.read_csv(paths["receptance"])
    np.testing.assert_allclose(v["amplitude"], 2 * np.pi * x["frequency_hz"] * x["amplitude"], rtol=1e-8)


# --- unknown names: said of the option typed --------------------------------------------------

@pytest.mark.parametrize("argv, typed", [
    (["frf", "{gear}", "--freqs", "1:40:5", "--sensor", "nope"], "--sensor nope: unknown sensor 'nope'"),
    (["frf", "{gear}", "--freqs", "1:40:5", "--output", "acc-top-z,nope"],
     "--output acc-top-z,nope: unknown sensor 'nope'"),
    (["frf", "{gear}", "--freqs", "1:40:5", "--excitation", "kick"], "--excitation kick: unknown excitation 'kick'"),
    (["frf", "{gear}", "--freqs", "1:40:5", "--input", "kick"], "--input kick: unknown excitation 'kick'"),
    (["unbalance", "{gear}", "--speeds", "0:100:3", "--sensor", "nope"], "--sensor nope: unknown sensor 'nope'"),
    (["unbalance", "{gear}", "--speeds", "0:100:3", "--output", "nope"], "--output nope: unknown sensor 'nope'"),
    (["simulate", "{gear}", "--duration", "0.002", "--backend", "numpy", "--excitation", "kick"],
     "--excitation kick: unknown excitation 'kick'"),
    (["simulate", "{gear}", "--duration", "0.002", "--backend", "numpy", "--impulse", "kick"],
     "--impulse kick: unknown excitation 'kick'"),
    (["simulate", "{gear}", "--duration", "0.002", "--backend", "numpy", "--sensor", "nope"],
     "--sensor nope: unknown sensor 'nope'"),
])
def test_an_unknown_name_is_said_of_its_option_with_the_valid_names(argv, typed, examples_dir, capsys):
    gear = str(examples_dir / "gear_machine.toml")
    assert main([gear if a == "{gear}" else a for a in argv] + ["--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and f"error: {typed}" in err, err
    valid = "acc-top-z, acc-side-y" if "sensor" in typed else "hammer-z, shaker-y"
    assert err.rstrip().endswith(f"are {valid}"), err


# --- rdm.simulate's docstring ------------------------------------------------------------------

def test_simulate_docs_say_the_lowest_modes_the_code_keeps():
    """``modes_below``'s floor is :data:`flexible.LOWEST` modes, as the docstring and --help say."""
    import rotordyn_modal as rdm
    from rotordyn_modal.simulation.flexible import LOWEST

    doc = " ".join(rdm.simulate.__doc__.split())
    assert re.findall(r"at least the (\d+) lowest", doc) == [str(LOWEST)]
    help_text = " ".join(_subs()["simulate"]._option_string_actions["--max-frequency"].help.split())
    assert re.findall(r"at least the (\d+) lowest", help_text) == [str(LOWEST)]


@pytest.mark.parametrize("option", ["--transmitted-power", "--rated-power", "--forces", "--force-outputs",
                                    "--quantity"])
def test_the_readme_vocabulary_table_names_where_each_option_is_shown(option):
    """README's vocabulary row of ``option`` lists the very sub-commands whose --help shows it."""
    from pathlib import Path

    text = (Path(__file__).resolve().parent.parent / "README.md").read_text(encoding="utf-8")
    rows = [line.split(" | ") for line in text.splitlines() if line.startswith("| ") and line.count(" | ") == 2]
    found = [row for row in rows if re.match(rf"`{re.escape(option)}[ `]", row[1])]
    assert len(found) == 1, (option, found)
    listed = set(re.findall(r"`([a-z0-9-]+)`", found[0][2]))
    shown = {command for command, sub in _subs().items()
             if any(option in a.option_strings and a.help is not argparse.SUPPRESS for a in sub._actions)}
    assert listed == shown, (option, listed, shown)
