"""The notebooks show their figures where they are read: each is kept with the outputs of one
run from top to bottom (a notebook viewer, GitHub's included, shows them without running it),
while the test suite executes it (nbmake does not write them back; docs/DEVELOPING.md,
"Notebooks"). What a user reads (notebooks, README, --help) speaks of the physics and of
docs/theory.md's sections, not of the seed documents it was derived from."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
DRAWS = re.compile(r"\.plot\w*\(|\bplot_\w+\(|\bplt\.subplots\(|\.widget\(\)|overlay_figure\(")
FIGURES = ("image/png", "image/svg+xml", "application/vnd.plotly.v1+json")
SEED = re.compile(r"\bseed\s*(document\s*)?0\d\d\b|\bseed('s)?\s+(eq|eqs|section|document)\b", re.I)


def _cells(path):
    return json.loads(path.read_text(encoding="utf-8"))["cells"]


def test_there_are_seven_notebooks():
    assert len(NOTEBOOKS) == 7


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_the_notebook_keeps_the_outputs_of_one_whole_run(path):
    code = [cell for cell in _cells(path) if cell["cell_type"] == "code"]
    assert [cell["execution_count"] for cell in code] == list(range(1, len(code) + 1))   # in order, none left out
    drawing = 0
    for cell in code:
        outputs = cell.get("outputs", [])
        assert not [o for o in outputs if o["output_type"] == "error"], "".join(cell["source"])[:80]
        if DRAWS.search("".join(cell["source"])):
            drawing += 1
            assert any(kind in o.get("data", {}) for o in outputs for kind in FIGURES), "".join(cell["source"])[:80]
    assert drawing >= 3


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_the_notebook_speaks_of_physics_not_of_seed_documents(path):
    text = "\n".join("".join(cell["source"]) for cell in _cells(path))
    assert not SEED.search(text)


def test_the_readme_and_help_speak_of_physics_not_of_seed_documents():
    from rotordyn_modal.cli.main import build_parser

    parser = build_parser()
    texts = [(ROOT / "README.md").read_text(encoding="utf-8"), parser.format_help()]
    texts += [sub.format_help() for sub in parser._subparsers._group_actions[0].choices.values()]
    assert not [t for t in texts if SEED.search(t)]
    assert SEED.search("the shift matrices of seed 000 (eqs. 1-11)") and SEED.search("seed eqs. 52")
    assert not SEED.search('"seed": 2026') and not SEED.search("The same seed gives the same samples")
