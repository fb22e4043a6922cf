"""Every CSV column without a unit in its name has its unit in the writing sub-command's --help
(issue 29 §6).

docs/units.md, "Every CSV column without a unit in its name", is a table of such columns and
their SI units. It is parsed here (not copied): for each sub-command and column it lists, one
sentence of that sub-command's ``--help`` must name the column and every SI unit the table gives
it. On the base, ``modes`` (real_part, 1/s), ``frf`` (real, imag, magnitude), ``unbalance``
(amplitude, major, minor, value, limit), ``simulate`` (theta_x ... in rad, the bearings' forces)
and ``study`` (the --table's speeds in rad/s) did not.
"""

from __future__ import annotations

import functools
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS_UNITS = ROOT / "docs" / "units.md"
SECTION = "## Every CSV column without a unit in its name"
#: the sub-commands whose --help is checked (fit prints its table, no CSV)
COMMANDS = ("modes", "campbell", "stability", "frf", "unbalance", "simulate", "study")
#: SI units, longest first so that "N m/N" is not read as "N m" and "N"
UNIT = re.compile(r"(?<![\w/^])(m/s\^2/N|m/s/N|N m/N|m/N|N/N|1/s|rad/s|m/s\^2|m/s|N m|rad|m|N)(?![\w/^])")
#: placeholders of docs/units.md's column names (``BEARING_Fx``: NAME_Fx in --help)
PLACEHOLDER = re.compile(r"^(BEARING|ROTOR)(?=_)")


def _units(text):
    """The SI units named in ``text`` (m/s² written m/s^2, as --help does)."""
    return set(UNIT.findall(text.replace("²", "^2")))


def _top_level_split(text, separator=";"):
    """``text`` split at ``separator`` outside parentheses."""
    parts, depth, start = [], 0, 0
    for i, char in enumerate(text):
        depth += {"(": 1, ")": -1}.get(char, 0)
        if char == separator and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    return [*parts, text[start:]]


def _names(group):
    """The column names of one ';' group of the table's column cell: the backquoted words, their
    [...] and placeholders dropped; 'each sensor's column' is named 'sensor'."""
    names = [PLACEHOLDER.sub("", name) for name in re.findall(r"`([A-Za-z_]+)(?:\[[^`]*\])?`", group)]
    names += re.findall(r"each (\w+)'s column", group)
    return names


def _documented():
    """(command, column, SI units) of every row of the section's table."""
    text = DOCS_UNITS.read_text()
    start = text.index(SECTION)
    section = text[start:text.index("\n## ", start + 1)]
    rows = []
    for line in section.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) != 4 or not cells[0].startswith("`"):
            continue
        commands = [word.split()[0] for word in re.findall(r"`([^`]+)`", cells[0])]
        groups, units = _top_level_split(cells[1]), _top_level_split(cells[2])
        if len(groups) != len(units):                          # one group: every unit applies
            groups, units = [cells[1]], [cells[2]]
        for group, unit in zip(groups, units):
            for name in _names(group):
                for command in commands:
                    if command in COMMANDS and _units(unit):
                        rows.append((command, name, frozenset(_units(unit))))
    return rows


DOCUMENTED = _documented()


@functools.lru_cache(maxsize=None)
def _help(command):
    """``rotordyn-modal COMMAND --help``, in sentences (split at '; ' and '. ', lines joined)."""
    env = {**os.environ, "COLUMNS": "100", "PYTHONPATH": str(ROOT)}
    text = subprocess.run([sys.executable, "-m", "rotordyn_modal", command, "--help"], capture_output=True,
                          text=True, check=True, cwd=ROOT, env=env).stdout
    return re.split(r";\s|\.\s", " ".join(text.split()))


def _names_column(sentence, name):
    if name.startswith("_"):                                    # NAME_Fx
        return name in sentence
    return re.search(rf"(?<![\w-]){re.escape(name)}(?!\w)", sentence) is not None


def test_the_table_is_read():
    """The parse finds each sub-command's columns (a broken parse would check nothing)."""
    found = {(command, name) for command, name, _ in DOCUMENTED}
    for pair in [("modes", "real_part"), ("frf", "real"), ("frf", "magnitude"), ("unbalance", "amplitude"),
                 ("unbalance", "amplitude_rms"), ("unbalance", "major"), ("unbalance", "limit"),
                 ("simulate", "u_x"), ("simulate", "theta_z"), ("simulate", "_Fz"), ("simulate", "_Mx"),
                 ("simulate", "sensor"), ("simulate", "_center_x"), ("study", "critical_speed"),
                 ("study", "threshold_speed"), ("study", "unbalance_peak_amplitude")]:
        assert pair in found, pair
    units = {(command, name): unit for command, name, unit in DOCUMENTED}
    assert units["modes", "real_part"] == {"1/s"}
    assert units["study", "critical_speed"] == {"rad/s"}
    assert units["simulate", "theta_x"] == {"rad"}
    assert units["simulate", "_Mz"] == {"N m"}
    assert {"m/N", "m/s/N", "m/s^2/N"} <= units["frf", "real"]


@pytest.mark.parametrize("command,name,units", DOCUMENTED, ids=[f"{c}-{n}" for c, n, _ in DOCUMENTED])
def test_help_names_each_columns_unit(command, name, units):
    """One sentence of the --help names the column and all its SI units of docs/units.md."""
    sentences = [s for s in _help(command) if _names_column(s, name)]
    assert sentences, f"{command} --help does not name {name}"
    best = max(sentences, key=lambda s: len(units & _units(s)))
    assert units <= _units(best), f"{command} --help: {name} without {sorted(units - _units(best))}: {best!r}"


@pytest.mark.parametrize("name,convention", [("amplitude", "0-peak"), ("amplitude_pkpk", "peak-to-peak"),
                                             ("amplitude_rms", "RMS")])
def test_unbalance_help_gives_each_amplitudes_convention(name, convention):
    """docs/units.md: amplitude, amplitude_pkpk, amplitude_rms are 0-peak, peak-to-peak, RMS."""
    assert re.search(r"`amplitude`, `amplitude_pkpk`, `amplitude_rms` \| [^|]*\(0-peak, peak-to-peak, RMS",
                     DOCS_UNITS.read_text())
    assert any(re.search(rf"(?<!\w){name} (is )?{convention}", s) for s in _help("unbalance")), name


def test_study_help_says_table_speeds_are_not_rpm():
    """The --table's speeds are rad/s where every other CSV's are rpm: --help and docs say so."""
    assert any("rad/s, not rpm" in s and "threshold_speed" in s for s in _help("study"))
    assert "**rad/s**, not rpm" in DOCS_UNITS.read_text()
