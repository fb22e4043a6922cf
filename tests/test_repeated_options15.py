"""A value option given twice is refused in one line (exit 2), never answered for its last value
alone: ``frf --sensor probe-pump-x --sensor acc-pump-z`` computed acc-pump-z's FRF only, exit 0
(redteam13's find); every sub-command's value options, from the parser itself."""

import argparse

import pytest

from rotordyn_modal.cli.main import build_parser, main


def _value_options():
    """(sub-command, option, a value it takes) for every visible single-value option of every
    sub-command."""
    parser = build_parser()
    commands = parser._subparsers._group_actions[0].choices
    for name, sub in commands.items():
        for action in sub._actions:
            if (action.option_strings and action.nargs is None and action.help != "==SUPPRESS=="
                    and isinstance(action, argparse._StoreAction) and action.choices is None):
                yield name, action.option_strings[-1], _accepted_value(action)


def _accepted_value(action):
    """A value the option's type takes (argparse checks each value as it is read)."""
    for value in ("1", "0:10:3", "displacement", "x"):
        try:
            action.type(value) if action.type else None
        except Exception:  # noqa: BLE001 - not this type's value: the next
            continue
        return value
    raise AssertionError(f"{action.option_strings}: no candidate value accepted")


def test_the_sensor_option_given_twice_is_refused_naming_both_values(examples_dir, capsys):
    model = str(examples_dir / "motor_pump_on_mounts.toml")
    with pytest.raises(SystemExit) as stop:
        main(["frf", model, "--speed", "3000", "--freqs", "10:100:3", "--sensor", "probe-pump-x",
              "--sensor", "acc-pump-z"])
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "--sensor given twice" in err and "probe-pump-x" in err and "acc-pump-z" in err
    assert "--sensor a,b" in err


@pytest.mark.parametrize("command, option, value", sorted(set(_value_options())))
def test_every_value_option_given_twice_is_refused(command, option, value, capsys):
    with pytest.raises(SystemExit) as stop:
        build_parser().parse_args([command, "m.toml", option, value, option, value])
    assert stop.value.code == 2
    assert f"{option} given twice" in capsys.readouterr().err


def test_an_option_given_once_in_each_of_two_parses_is_not_a_repeat():
    parser = build_parser()
    first = parser.parse_args(["campbell", "m.toml", "--speeds", "0:3000:5"])
    second = parser.parse_args(["campbell", "m.toml", "--speeds", "0:100:3"])
    assert (first.speeds, second.speeds) == ("0:3000:5", "0:100:3")
