"""One definition where the code said a thing twice (issue 27 §5, duplicates folded): the
amplitude conventions' words, the ``--sensor`` option of ``frf`` and ``unbalance``, the table of
a motion's FRF name. What users see is unchanged (``--help`` compared byte for byte when the
change was made; the report's words below are the ones it always wrote)."""

from __future__ import annotations

import argparse

import pytest

from rotordyn_modal.cli.main import build_parser


def _subs() -> dict:
    return build_parser()._subparsers._group_actions[0].choices


def test_the_report_writes_the_amplitude_words_of_the_standards_module():
    """``12.7 µm 0-peak``, ``25.4 µm pk-pk``, ``8.98 µm RMS``: one table, beside the conventions'
    factors (0-peak x 1, pk-pk x 2, RMS x 1/sqrt 2)."""
    import importlib

    from rotordyn_modal import unbalance_standards as standards

    collect = importlib.import_module("rotordyn_modal.report.collect")     # the package names a function so

    assert collect.AMPLITUDE_WORDS is standards.AMPLITUDE_WORDS
    assert standards.AMPLITUDE_WORDS == {"peak": "0-peak", "pk-pk": "pk-pk", "rms": "RMS"}
    assert set(standards.AMPLITUDE_WORDS) == set(standards.AMPLITUDES)
    assert [standards.amplitude_factor(a) for a in ("peak", "pk-pk", "rms")] == pytest.approx([1, 2, 0.5 ** 0.5])


def _option(sub, spelling):
    action = sub._option_string_actions[spelling]
    return action.option_strings, action.dest, action.metavar, action.help, action.nargs, action.type


@pytest.mark.parametrize("command", ["frf", "unbalance"])
def test_sensor_is_the_one_declaration_of_the_common_helper(command):
    """``frf`` and ``unbalance`` declare ``--sensor`` (and its hidden ``--output``) through
    ``_common.add_sensor_argument``: the same option as the helper gives a bare parser."""
    from rotordyn_modal.cli._common import add_sensor_argument

    bare = argparse.ArgumentParser()
    add_sensor_argument(bare)
    sub = _subs()[command]
    for spelling in ("--sensor", "--output"):
        assert _option(sub, spelling) == _option(bare, spelling), (command, spelling)
    assert sub._option_string_actions["--output"].help is argparse.SUPPRESS


def test_the_motion_and_its_frf_name_are_one_table():
    """``--quantity`` (cli.frf), the study file's ``quantity`` and the UFF reader name a motion's
    FRF by one table."""
    from rotordyn_modal.analysis.spectra import QUANTITY_OF_RESPONSE
    from rotordyn_modal.cli import frf
    from rotordyn_modal.io import uff

    assert frf.QUANTITIES is QUANTITY_OF_RESPONSE and uff._FRF_OF is QUANTITY_OF_RESPONSE
    assert QUANTITY_OF_RESPONSE == {"displacement": "receptance", "velocity": "mobility",
                                    "acceleration": "accelerance"}
