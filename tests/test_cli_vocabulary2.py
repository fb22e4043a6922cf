"""One vocabulary on the command line, walked over every sub-command's parser: one meaning is
shown under one spelling (an earlier spelling still works, hidden from --help and the docs,
with the very same value), a range is written one way (``START:STOP:N`` for a sweep, ``LO:HI``
for a band) and a speed says its unit. A message names an option as the user typed it."""

from __future__ import annotations

import argparse
import re
import shlex
from pathlib import Path

import pytest

from rotordyn_modal.cli._common import VALUE_OPTIONS, join_negative_values
from rotordyn_modal.cli.main import build_parser, main

ROOT = Path(__file__).resolve().parent.parent

#: the declared synonyms: the one spelling --help and the docs show -> the earlier spellings of
#: the same meaning, by the sub-commands where they meant it (written out here, not read from
#: the code, so that the code is checked against them)
SYNONYMS = {
    "--sensor": {"--output": ("frf", "unbalance")},
    "--excitation": {"--input": ("frf",), "--impulse": ("simulate",)},
    "--freq-band": {"--band": ("fit",)},
    "--operating-range": {"--operating": ("ucs-map", "report"), "--speed-band": ("study",), "--band": ("study",)},
    "--lowest": {"--modes": ("ucs-map",)},
    "--mcs": {"--speed": ("level1",)},
    "--max-frequency": {"--modes-below": ("simulate",)},
}
#: (sub-command, shown spelling, earlier spelling) of every declared synonym
PAIRS = [(command, new, old) for new, olds in SYNONYMS.items() for old, commands in olds.items()
         for command in commands]
#: the forms of a value made of several numbers joined by ':'
RANGE_FORMS = {"START:STOP:N", "LO:HI", "START:STOP:N|LIST"}


def _subs() -> dict:
    return build_parser()._subparsers._group_actions[0].choices


def _shown(sub) -> list:
    """The actions --help shows."""
    return [a for a in sub._actions if a.help is not argparse.SUPPRESS]


def _mentions(text: str, option: str) -> bool:
    """``option`` written in ``text`` as an option (``--band``, not ``--freq-band`` nor ``--band-x``)."""
    return re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", text) is not None


@pytest.mark.parametrize("command", sorted(_subs()))
def test_help_shows_no_two_spellings_of_one_meaning(command):
    """Neither as an option nor in the help's words does an earlier spelling appear beside the
    one it was replaced by (``--lowest N, --modes N``; ``--speed-band LOW:HIGH, --band
    LOW:HIGH``), and a spelling that named one meaning in one sub-command and is gone everywhere
    (``--output``, ``--band`` ...) appears in no help."""
    sub = _subs()[command]
    text = sub.format_help()
    options = {s for a in _shown(sub) for s in a.option_strings}
    for new, olds in SYNONYMS.items():
        for old, commands in olds.items():
            if new in options or command in commands:
                assert old not in options and not _mentions(text, old), (command, new, old)


def test_every_declared_synonym_is_a_hidden_alias_of_the_shown_option():
    subs = _subs()
    for command, new, old in PAIRS:
        sub = subs[command]
        shown, hidden = sub._option_string_actions[new], sub._option_string_actions[old]
        assert shown.help is not argparse.SUPPRESS and hidden.help is argparse.SUPPRESS, (command, old)
        assert (hidden.dest, hidden.type, hidden.choices, hidden.nargs, hidden.const) == \
            (shown.dest, shown.type, shown.choices, shown.nargs, shown.const), (command, old)


@pytest.mark.parametrize("command", sorted(_subs()))
def test_range_metavars_have_one_form(command):
    """A sweep is START:STOP:N, a band LO:HI, in the metavar (not LOW:HIGH, not a metavar
    SPEEDS with the form in the words); every speed option states its unit."""
    sub = _subs()[command]
    text = " ".join(sub.format_help().split())
    for word in ("LOW:HIGH", "LOW", "HIGH", "MIN:MAX", "START:END"):
        assert not _mentions(text, word), (command, word)
    for action in _shown(sub):
        metavar, words = action.metavar or "", action.help or ""
        if ":" in metavar and not metavar.startswith("BODY:"):   # static --force BODY:X,Y,Z:FX,FY,FZ
            assert metavar in RANGE_FORMS, (command, action.option_strings, metavar)
        if any(form in words for form in ("START:STOP:N", "LO:HI")):
            assert metavar in RANGE_FORMS, (command, action.option_strings, words)
        if metavar == "SPEED" or action.dest in ("speeds", "operating") \
                or (action.dest == "band" and command == "study"):
            assert re.search(r"rpm|--speed-unit|same unit as --speeds|unit of --speed", words), \
                (command, action.option_strings, words)


def _parse(argv):
    return vars(build_parser().parse_args(join_negative_values(argv, VALUE_OPTIONS)))


#: a command line of each sub-command with an option that has earlier spellings
BASE = {"frf": ["frf", "m.toml", "--freqs", "1:40:5"], "unbalance": ["unbalance", "m.toml", "--speeds", "0:100:3"],
        "simulate": ["simulate", "m.toml", "--duration", "0.1"], "fit": ["fit", "m.toml", "--measured", "x.uff",
                                                                       "--params", "gain", "--out", "f.toml"],
        "ucs-map": ["ucs-map", "m.toml", "--stiffness", "1e5:1e8:3"], "report": ["report", "m.toml", "--standard",
                                                                                  "api684", "--mcs", "3000", "--out",
                                                                                  "r.html"],
        "study": ["study", "m.toml", "--spec", "s.toml", "--out", "r.nc"],
        "level1": ["level1", "m.toml", "--station", "rotor", "--qa", "1e4"]}
VALUE = {"--sensor": "acc-top-z,acc-side-y", "--excitation": "hammer-z", "--freq-band": "2:40",
         "--operating-range": "-1000:2000", "--lowest": "3", "--mcs": "-3000", "--max-frequency": "all"}


@pytest.mark.parametrize("command, new, old", PAIRS)
def test_the_earlier_spelling_reads_the_same_value(command, new, old):
    """Every option the command holds is the same, typed either way (a negative range too)."""
    value = VALUE[new]
    as_new = _parse(BASE[command] + [new, value])
    as_old = _parse(BASE[command] + [old, value])
    assert as_new == as_old and as_new[build_parser()._subparsers._group_actions[0].choices[command]
                                       ._option_string_actions[new].dest] == value
    assert _parse(BASE[command] + [f"{old}={value}"]) == as_new


def test_ucs_map_earlier_spellings_give_the_same_map(tmp_path, examples_dir):
    """``--modes N --operating LO:HI`` (ucs-map's earlier spellings) writes the very same file as
    ``--lowest N --operating-range LO:HI``."""
    base = ["ucs-map", str(examples_dir / "fan_on_bearings.toml"), "--stiffness", "1e5:1e8:2", "--quiet"]
    new, old = tmp_path / "new.csv", tmp_path / "old.csv"
    assert main(base + ["--lowest", "1", "--operating-range", "1000:2000", "--out", str(new)]) == 0
    assert main(base + ["--modes", "1", "--operating", "1000:2000", "--out", str(old)]) == 0
    assert new.read_bytes() == old.read_bytes()
    assert new.read_text().startswith("stiffness_n_per_m,mode,")


def test_simulate_impulse_is_the_excitation_hit(tmp_path, examples_dir):
    base = ["simulate", str(examples_dir / "gear_machine.toml"), "--duration", "0.002", "--backend", "numpy",
            "--samples", "11", "--quiet"]
    new, old, rest = tmp_path / "new.csv", tmp_path / "old.csv", tmp_path / "rest.csv"
    assert main(base + ["--excitation", "hammer-z", "--out", str(new)]) == 0
    assert main(base + ["--impulse", "hammer-z", "--out", str(old)]) == 0
    assert main(base + ["--out", str(rest)]) == 0
    assert new.read_bytes() == old.read_bytes() != rest.read_bytes()      # the hit moves the machine


@pytest.mark.parametrize("argv, typed", [
    (["ucs-map", "{fan}", "--stiffness", "1e5:1e8:3", "--modes", "0"], "--modes '0'"),
    (["ucs-map", "{fan}", "--stiffness", "1e5:1e8:3", "--lowest", "0"], "--lowest '0'"),
    (["ucs-map", "{fan}", "--stiffness", "1e5:1e8:3", "--operating", "3:1"], "--operating '3:1'"),
    (["ucs-map", "{fan}", "--stiffness", "1e5:1e8:3", "--operating-range", "3:1"], "--operating-range '3:1'"),
    (["fit", "{fan}", "--measured", "{fan}", "--params", "gain", "--out", "{out}", "--band", "40:2"],
     "--band 40:2: expected LO:HI in Hz"),
    (["level1", "{fan}", "--station", "fan", "--qa", "1e4", "--speed", "x"], "--speed 'x'"),
    (["level1", "{fan}", "--station", "fan", "--qa", "1e4", "--speed", "0"], "--speed 0:"),   # the API's message
    (["level1", "{fan}", "--station", "fan", "--qa", "1e4", "--mcs", "0"], "--mcs 0:"),
    (["simulate", "{fan}", "--duration", "0.1", "--modes-below", "-3"], "--modes-below -3:"),
    (["simulate", "{fan}", "--duration", "0.1", "--max-frequency", "-3"], "--max-frequency -3:"),
])
def test_a_message_names_the_option_as_typed(argv, typed, tmp_path, examples_dir, capsys):
    fill = {"{fan}": str(examples_dir / "fan_on_bearings.toml"), "{out}": str(tmp_path / "f.toml")}
    assert main([fill.get(a, a) for a in argv]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and f"error: {typed}" in err, err


def test_two_spellings_of_one_option_are_refused_and_a_required_one_is_named_once(examples_dir, capsys):
    fan = str(examples_dir / "fan_on_bearings.toml")
    with pytest.raises(SystemExit) as stop:
        main(["ucs-map", fan, "--stiffness", "1e5:1e8:3", "--lowest", "2", "--modes", "3"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "--modes" in err and "--lowest" in err
    with pytest.raises(SystemExit) as stop:
        main(["level1", fan, "--station", "fan", "--qa", "1e4"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "the following arguments are required: --mcs (see" in err and "--speed" not in err.replace("--speed-", "")


def _documented_lines():
    """(where, sub-command, words) of every ``rotordyn-modal SUB ...`` line a user reads:
    README, docs, notebooks, the examples' comments and every --help (placeholders included)."""
    from test_docs_model import _command_lines, _texts

    subs = _subs()
    for where, text in _texts().items():
        for line in _command_lines(text):
            words = shlex.split(line.replace("\\|", "|"), posix=False)[1:]
            while words and words[0].startswith("--"):     # rotordyn-modal --units us SUB ...
                words = words[2:]
            if words and words[0] in subs:
                yield where, words[0], words[1:]


def test_the_docs_and_helps_show_no_earlier_spelling():
    """Every command line the pages, notebooks, examples and --help texts show uses the spellings
    --help shows (the earlier ones still parse: tests/test_docs_model.py parses them all)."""
    subs = _subs()
    seen, found = 0, []
    for where, command, words in _documented_lines():
        hidden = {old for where_used, _, old in PAIRS if where_used == command} | \
            {s for a in subs[command]._actions if a.help is argparse.SUPPRESS for s in a.option_strings}
        seen += 1
        found += [(where, command, w) for w in words if w.split("=")[0].strip("[(") in hidden]
    assert seen >= 100 and found == []


def test_a_hidden_spelling_of_a_file_option_is_one_file_option():
    """An earlier spelling of a file option reads the same file, and the file is checked once
    (listed twice, an output would be 'the same file' as itself)."""
    from rotordyn_modal.cli._common import add_alias, add_input_file, add_output_file, file_options

    parser = argparse.ArgumentParser()
    add_input_file(parser, "--measured", metavar="FILE")
    add_output_file(parser, "--out", metavar="FILE.csv")
    add_alias(parser, "--measured", "--data")
    add_alias(parser, "--out", "--output-file")
    assert file_options(parser) == {"input": [("measured", "--measured")], "output": [("out", "--out")]}
    assert vars(parser.parse_args(["--data", "m.uff", "--output-file", "t.csv"])) == {"measured": "m.uff",
                                                                                      "out": "t.csv"}
