"""Progress bars seen on real pseudo-terminals of known sizes (issue 27 §1.9: long work shows
its progress).

The command line runs in a child process on a pseudo-terminal (``pty.fork``) whose size is set
before the program starts, as a terminal would; what the terminal receives is read back. tqdm
sizes its bar from the terminal, less one column and one row: a terminal that reports 0 x 0
(``script`` without a terminal, a container's ``-t`` before its size is set) got a height of -1,
which hid every bar, and a width of -1, which cut each bar's last character off.
"""

from __future__ import annotations

import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import sys
import termios
import time
from pathlib import Path

import pytest

import rotordyn_modal

PACKAGE_ROOT = Path(rotordyn_modal.__file__).resolve().parent.parent
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: a study of three variants of the gear machine's lowest modes (a few seconds)
STUDY = """samples = 3
seed = 1
[[parameters]]
key = "suspensions.mount-FL.stiffness"
apply = "scale"
distribution = "uniform"
low = 0.9
high = 1.1
[analyses.modes]
speed_rpm = 1000.0
"""


def _environment():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(PACKAGE_ROOT), os.environ.get("PYTHONPATH", "")]))
    for name in ("COLUMNS", "LINES"):       # the terminal's own size, not a variable's
        env.pop(name, None)
    return env


def _on_terminal(argv, columns, rows, timeout=180.0):
    """(exit code, everything the terminal received) of the command line run on a
    pseudo-terminal of ``columns`` x ``rows`` (stdin, stdout and stderr all on it)."""
    env = _environment()
    pid, fd = pty.fork()
    if pid == 0:                                               # pragma: no cover - the child
        try:
            fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", rows, columns, 0, 0))
            os.execve(sys.executable, [sys.executable, "-m", "rotordyn_modal", *argv], env)
        finally:
            os._exit(127)
    received, deadline = [], time.monotonic() + timeout
    while time.monotonic() < deadline:
        ready, _, _ = select.select([fd], [], [], 1.0)
        if not ready:
            continue
        try:
            data = os.read(fd, 65536)
        except OSError:                                        # the child closed the terminal
            break
        if not data:
            break
        received.append(data)
    else:                                                      # pragma: no cover
        os.kill(pid, 9)
    os.close(fd)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), b"".join(received).decode("utf-8", "replace")


def _study_argv(tmp_path):
    spec = tmp_path / "three.study.toml"
    spec.write_text(STUDY)
    return ["study", str(EXAMPLES / "gear_machine.toml"), "--spec", str(spec), "--out", str(tmp_path / "out.nc"),
            "--workers", "1"]


def _drawings(text, description):
    """Every drawing of the bar ``description`` the terminal received (tqdm redraws a bar after
    a carriage return)."""
    parts = (part.split("\n")[0].rstrip("\r") for part in re.split(r"\r(?!\n)", text))
    return [part for part in parts if part.startswith(description)]


@pytest.mark.parametrize("columns, rows", [(0, 0), (0, 40), (100, 40), (100, 2)],
                         ids=["no-size", "no-width", "100x40", "two-rows"])
def test_the_study_bar_is_drawn_whole_and_ends_at_every_variant(tmp_path, columns, rows):
    """On any terminal the study's bar is drawn, each drawing whole (ending in its rates' ``]``)
    and within the width where the terminal has one, the last one at 3/3 variants followed by a
    new line before the summary."""
    code, text = _on_terminal(_study_argv(tmp_path), columns, rows)
    assert code == 0, text
    drawings = _drawings(text, "study:")
    assert drawings, f"no bar on a {columns} x {rows} terminal: {text!r}"
    assert all(drawing.endswith("]") for drawing in drawings), drawings
    assert "3/3" in drawings[-1], drawings
    if columns:
        assert all(len(drawing) <= columns - 1 for drawing in drawings), drawings
    assert re.search(r"3/3[^\r\n]*\]\r?\n3 variants, 0 failed", text), text


def test_no_bar_where_stderr_is_no_terminal(tmp_path):
    """With stderr sent to a file (a log), no bar and no carriage return are written there."""
    result = subprocess.run([sys.executable, "-m", "rotordyn_modal", *_study_argv(tmp_path)], capture_output=True,
                            text=True, env=_environment(), timeout=180)
    assert result.returncode == 0, result.stderr
    assert "study:" not in result.stderr and "\r" not in result.stderr, result.stderr
    assert "3 variants, 0 failed" in result.stderr + result.stdout


def test_the_critical_speeds_bar_shows_on_a_terminal_without_size(tmp_path):
    """The critical speeds' refinement shows its bar on a terminal that reports 0 x 0 too."""
    code, text = _on_terminal(["critical-speeds", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:6000:61",
                               "--out", str(tmp_path / "c.csv")], 0, 0)
    assert code == 0, text
    drawings = _drawings(text, "critical speeds:")
    assert drawings and all(drawing.endswith("]") for drawing in drawings), text
