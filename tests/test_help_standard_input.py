"""Every input option that reads '-' (standard input) says so in ``--help`` (issue 27 §4: the
files27p session made '-' work for MODEL, --measured, --mapping, --outline, study --spec and
import-ross, but no help text mentioned it)."""
import argparse

from rotordyn_modal.cli.main import build_parser

_READS_DASH = {"model", "spec", "measured", "mapping", "outline", "ross_file"}


def _sub_parsers():
    parser = build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    raise AssertionError("no sub-commands")


def test_every_dash_reading_input_names_standard_input_in_its_help():
    seen = []
    for command, sub in _sub_parsers().items():
        for action in sub._actions:
            if action.dest in _READS_DASH:
                seen.append((command, action.dest))
                assert "'-' reads it from standard input" in (action.help or ""), (command, action.dest, action.help)
    assert {dest for _, dest in seen} == _READS_DASH, seen      # every such input exists somewhere

