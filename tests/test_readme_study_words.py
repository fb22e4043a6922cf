"""README's option vocabulary names the study file's keys that take the command line's words
(issue 27 §5): ``[analyses.unbalance] quantity`` those of ``--quantity`` and ``forces`` those of
``--forces`` (docs/study-file.md; ``tests/test_study_vocabulary.py`` computes with them). Each word
the README row lists is read by the study file's parser, and the ``--forces`` row lists the very
words the command line takes."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import build_parser
from rotordyn_modal.study import parse_study

ROOT = Path(__file__).resolve().parent.parent


def _row(option: str) -> list:
    """The cells (meaning, option, sub-commands) of README's vocabulary row of ``option``."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    rows = [line.split(" | ") for line in text.splitlines() if line.startswith("| ") and line.count(" | ") == 2]
    found = [row for row in rows if re.match(rf"`{re.escape(option)}[ `]", row[1])]
    assert len(found) == 1, (option, found)
    return found[0]


def _words(cell: str, option: str) -> list:
    """The words a row's option cell gives its option: ``a\\|b\\|c`` after it, and the backticked
    words in parentheses after that (the FRF's names of the motions)."""
    first = re.match(rf"`{re.escape(option)} ([^`]+)`", cell).group(1)
    return first.split("\\|") + re.findall(r"`([a-z]+)`", cell[len(option) + len(first) + 3:])


@pytest.mark.parametrize("option, key", [("--quantity", "quantity"), ("--forces", "forces")])
def test_the_vocabulary_row_names_the_study_key_and_its_words_are_read(option, key):
    _, cell, where = _row(option)
    assert f"study file the key `[analyses.unbalance] {key}` takes the same words" in where, where
    words = _words(cell, option)
    assert len(words) == (6 if option == "--quantity" else 4), words
    model = rdm.load_model(ROOT / "examples" / "gear_machine.toml")
    for word in words:
        spec = {"seed": 1, "samples": 2, "design": "latin-hypercube",
                "parameters": [{"key": "suspensions.mount-FL.stiffness", "apply": "scale",
                                "distribution": "uniform", "low": 0.9, "high": 1.1}],
                "analyses": {"unbalance": {"speeds_rpm": "300:3000:12", key: word}}}
        assert parse_study(spec, model=model).analyses["unbalance"][key] is not None, word
    if option == "--forces":
        unbalance = build_parser()._subparsers._group_actions[0].choices["unbalance"]
        assert words == list(unbalance._option_string_actions["--forces"].choices)
