"""Input and file defects left on issues 27 (§1, §4, §5) and 28 (§5): a report option its
standard does not use, text files in UTF-16 without a byte-order mark, the model warnings a
refusal makes moot. Each case through the command line in this process (or one reader), before
any analysis: the file costs seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotordyn_modal.cli import main
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
FAN = str(ROOT / "examples" / "fan_on_bearings.toml")
PUMP = str(ROOT / "examples" / "motor_pump_on_mounts.toml")


# ----------------------------------------------------------------------- report --stiffness
def test_an_iso_report_refuses_the_stiffness_of_a_map_it_does_not_draw(tmp_path, capsys):
    """``--standard iso --stiffness ...`` was accepted (exit 0) and dropped without a word: the
    ISO report has no undamped critical speed map (docs/report.md's table), as ``--iso-group``
    is refused in an API report."""
    out = tmp_path / "r.html"
    assert main(["report", PUMP, "--standard", "iso", "--mcs", "3000", "--iso-group", "2", "--iso-support",
                 "flexible", "--stiffness", "1e5:1e10:9", "--out", str(out)]) == 2
    _one_line_error(capsys, "--stiffness 1e5:1e10:9", "--standard iso", "undamped critical speed map", "api684")
    assert not out.exists()
