"""The complete short model file that README.md and docs/model-file.md open with is the
bundled ``examples/motor_fan_minimal.toml`` to the letter, and it loads."""

from __future__ import annotations

import functools
import json
import re
import shlex
from pathlib import Path

import pytest

import rotordyn_modal as rdm

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "motor_fan_minimal.toml"


def first_toml_block(path: Path) -> str:
    found = re.search(r"```toml\n(.*?)```", path.read_text(encoding="utf-8"), re.S)
    assert found, f"{path.name} shows no model file"
    return found.group(1)


@pytest.mark.parametrize("page", ["README.md", "docs/model-file.md"])
def test_the_page_opens_with_the_bundled_short_model(page):
    assert first_toml_block(ROOT / page) == EXAMPLE.read_text(encoding="utf-8")


def test_the_short_model_is_complete_and_valid(tmp_path):
    shown = tmp_path / "shown.toml"
    shown.write_text(first_toml_block(ROOT / "README.md"), encoding="utf-8")
    model = rdm.load_model(shown)
    assert sorted(model.speed_ratios) == ["fan", "motor"]
    assert model.speed_ratios["fan"] == pytest.approx(1 / 1.6, rel=1e-15)   # belt: same direction
    assert model.dofs.n == 6


# --- the command lines the pages and --help show -------------------------------------------------

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
PLACEHOLDER = re.compile(r"\[|\||\.\.\.|\bSUB\b|\bMODEL\b|\bFILE\b|^[A-Z]+\.toml$")


@functools.lru_cache(maxsize=1)
def _parser():
    from rotordyn_modal.cli.main import build_parser

    return build_parser()


def _sub_commands() -> dict:
    return _parser()._subparsers._group_actions[0].choices


def _command_lines(text: str) -> list[str]:
    """Every ``rotordyn-modal ...`` line of a text: in code blocks (continuation lines joined) and
    in inline code."""
    text = re.sub(r"\\\n\s*", " ", text)
    found = re.findall(r"^\s*(rotordyn-modal [^\n`]*)$", text, re.M)
    found += re.findall(r"`(rotordyn-modal [^`\n]*)`", text)
    return [re.sub(r"\s+", " ", line.strip()) for line in found]


def _texts() -> dict[str, str]:
    """The README, docs/*.md, the notebooks' text, the examples' header comments and every
    sub-command's --help, by where they are read."""
    texts = {page.relative_to(ROOT).as_posix(): page.read_text(encoding="utf-8") for page in PAGES}
    for notebook in sorted((ROOT / "notebooks").glob("*.ipynb")):
        cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
        texts[notebook.name] = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    for example in sorted((ROOT / "examples").glob("*.toml")):
        comments = re.findall(r"^#(.*)$", example.read_text(encoding="utf-8"), re.M)
        texts[example.name] = "\n".join(comments)
    texts.update({f"{name} --help": sub.format_help() for name, sub in _sub_commands().items()})
    return texts


def documented_commands() -> list[tuple[str, str]]:
    """(where, command line) of every concrete command shown (placeholders such as MODEL, FILE,
    [...] or a|b left out)."""
    names = (*_sub_commands(), "--units")
    commands = []
    for where, text in _texts().items():
        for line in _command_lines(text):
            words = line.split()[1:]
            if len(words) >= 2 and words[0] in names and not any(PLACEHOLDER.search(w) for w in words):
                commands.append((where, line))
    return commands


def test_the_pages_show_many_concrete_commands():
    commands = documented_commands()
    assert len(commands) >= 70
    assert {where for where, _ in commands} >= {"README.md", "docs/figures.md", "campbell --help",
                                                "compressor_on_journals.toml", "01_campbell_and_stability.ipynb"}


@pytest.mark.parametrize("where, line", documented_commands())
def test_every_documented_command_parses_and_names_files_that_exist(where, line):
    """Each command shown parses with today's options (an option renamed or mistyped in a page
    fails here), and each bundled file it reads exists."""
    from rotordyn_modal.cli._common import VALUE_OPTIONS, join_negative_values

    argv = shlex.split(line)[1:]
    try:
        args = _parser().parse_args(join_negative_values(argv, VALUE_OPTIONS))
    except SystemExit:
        pytest.fail(f"{where}: {line!r} does not parse")
    assert args.command in argv
    bundled = [w for w in argv if w.startswith(("examples/", "tests/data/"))]
    assert all((ROOT / w).is_file() for w in bundled), (where, line)


def test_the_second_quick_start_line_is_what_ci_runs():
    block = re.search(r"## Quick start\n\n```bash\n(.*?)```", (ROOT / "README.md").read_text(encoding="utf-8"), re.S)
    first, second = block.group(1).strip().splitlines()
    assert first.startswith("pip install . && rotordyn-modal campbell examples/gear_machine.toml ")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert second in [line.strip() for line in ci]


def test_the_readme_commands_on_the_short_model_print_what_it_says(capsys):
    """"`check` prints its masses and mounts; `modes --speed 1500` its six modes at 1500 rpm":
    the rotors turn in the one rigid stator (no bearings): six coordinates, six modes listed."""
    from rotordyn_modal.cli.main import main

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    check, modes = re.findall(r"`rotordyn-modal ((?:check|modes) examples/motor_fan_minimal\.toml[^`]*)`", text)[:2]
    assert main(check.split()) == 0
    out = capsys.readouterr().out
    model = rdm.load_model(EXAMPLE)
    assert f"total mass {model.total_mass:.6g} kg" in out and "stator: 120 kg" in out
    assert len(model.suspensions) == 4 and all(f"    {s.name} " in out for s in model.suspensions)
    assert main(modes.split() + ["--out", "-"]) == 0
    rows = capsys.readouterr().out.strip().splitlines()
    assert rows[0].startswith("mode,frequency_hz") and [r.split(",")[0] for r in rows[1:]] == list("123456")


def test_every_path_the_pages_name_is_in_the_repository():
    """A reader can open each file a page names (no path outside the repository, such as the
    project's shared specification beside it)."""
    pattern = re.compile(r"(?<![\w/.])((?:\.\./)*(?:docs|examples|notebooks|benchmarks|tests|rotordyn_modal|shared)"
                         r"/[\w./*-]*\w)")
    missing = [(page.name, path) for page in PAGES for path in pattern.findall(page.read_text(encoding="utf-8"))
               if "*" not in path and path != "tests/test_x.py" and not (ROOT / path).exists()]
    assert not missing
