"""Long work shows its progress while a step runs (issue 27 §1.9).

A sweep's bar advanced once per part, and each part of a large model is one LAPACK call (about
100 s at 4,012 states on a shared machine): tqdm draws only when a bar advances, so its elapsed
time stood still for the whole call, and the work after the sweep (tracking, round-off,
thresholds: about 40 s at 500 geared rotors) and an unbalance sweep (about 40 s) showed nothing.

The slow steps are made slow here by wrapping the real functions in a sleep, and the bars are
drawn on a stream that says it is a terminal, as the command line's standard error on a
terminal; what was drawn is read back. The clock ticks every 0.2 s and a phase's line shows
after 0.5 s here (``TICK_SECONDS``, ``PHASE_DELAY``), so each test costs a second or two.
"""

from __future__ import annotations

import io
import re
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal import _progress
from rotordyn_modal.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: how long a slowed step sleeps [s]: several ticks of the clock below
SLOW = 1.2


class Terminal(io.StringIO):
    """A stream that says it is a terminal (of unknown size), keeping what is written to it."""

    def isatty(self):
        return True


@pytest.fixture(autouse=True)
def quick_clock(monkeypatch):
    monkeypatch.setattr(_progress, "TICK_SECONDS", 0.2, raising=False)
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.5, raising=False)


def on_terminal(monkeypatch):
    """Standard error replaced by a :class:`Terminal` for the rest of the test (set inside the
    test: pytest sets its own capture again when the test starts)."""
    stream = Terminal()
    monkeypatch.setattr(sys, "stderr", stream)
    return stream


def slowed(function, times=1):
    """``function`` whose first ``times`` calls each sleep :data:`SLOW` seconds first."""
    calls = [0]

    def wrapper(*args, **kwargs):
        calls[0] += 1
        if calls[0] <= times:
            time.sleep(SLOW)
        return function(*args, **kwargs)

    return wrapper


def drawings(text, description):
    """Every drawing of the line that starts with ``description`` (tqdm redraws after ``\\r``)."""
    return [part for part in re.split(r"[\r\n]+", text) if part.startswith(description)]


def seconds(drawing):
    """The elapsed time [s] a drawing shows (``[mm:ss`` or ``[mm:ss<...``)."""
    minutes, secs = re.search(r"\[(\d+):(\d\d)", drawing).groups()
    return 60 * int(minutes) + int(secs)


def ticker_threads():
    return [t for t in threading.enumerate() if t.name == "rotordyn_modal progress ticker"]


def test_the_sweep_bar_clock_runs_during_its_one_step(monkeypatch):
    """While the sweep's single part is solved (slowed by 1.2 s), the eigen-solve bar is drawn
    again at 0 parts done with a clock past 00:00 (it stood at 00:00 until the part ended)."""
    from rotordyn_modal.analysis import _stack

    monkeypatch.setattr(_stack.Stack, "solve", slowed(_stack.Stack.solve))
    terminal = on_terminal(monkeypatch)
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    rdm.stability(model, np.linspace(0, 300, 4), progress=True)
    before_the_step_ends = [d for d in drawings(terminal.getvalue(), "eigen-solve") if " 0/" in d]
    assert before_the_step_ends, terminal.getvalue()
    assert max(seconds(d) for d in before_the_step_ends) >= 1, before_the_step_ends
    assert not ticker_threads()                      # stopped with the bar


@pytest.mark.parametrize("module, name, description", [
    ("campbell", "track_modes_many", "tracking modes"),
    ("stability", "roundoff_levels", "whirl and round-off"),
    ("stability", "_crossing_roots", "modes at the thresholds"),
])
def test_the_work_after_the_sweep_is_named_with_its_clock(monkeypatch, module, name, description):
    """Each stage after the sweep, made slow, is shown by name with an elapsed time that
    advances, and cleared when it ends (the last thing on the line is not its drawing)."""
    import importlib

    target = importlib.import_module(f"rotordyn_modal.analysis.{module}")
    monkeypatch.setattr(target, name, slowed(getattr(target, name)))
    terminal = on_terminal(monkeypatch)
    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    result = rdm.stability(model, np.linspace(0, 20000, 11) * np.pi / 30, progress=True)
    assert len(result.thresholds) == 1                           # the stage of the crossing roots runs
    shown = drawings(terminal.getvalue(), f"{description}: ")
    assert len({seconds(d) for d in shown}) >= 2, terminal.getvalue()   # 00:00 and 00:01 at least
    assert terminal.getvalue().rstrip(" ").endswith("\r")               # cleared
    assert not ticker_threads()


def test_the_thresholds_count_their_eigen_solutions(monkeypatch):
    """The thresholds' refinement (one whole eigen-solution a step) names how many it has made."""
    from rotordyn_modal.analysis import stability

    monkeypatch.setattr(stability, "_largest_real_part", slowed(stability._largest_real_part, times=3))
    terminal = on_terminal(monkeypatch)
    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    rdm.stability(model, np.linspace(0, 20000, 11) * np.pi / 30, progress=True)
    shown = drawings(terminal.getvalue(), "stability thresholds: ")
    assert any(d.startswith("stability thresholds: 1 eigen-solution: [") for d in shown), shown
    assert any(d.startswith("stability thresholds: 2 eigen-solutions: [") for d in shown), shown


def test_unbalance_on_a_terminal_shows_its_solves_with_a_clock(monkeypatch, tmp_path):
    """``unbalance`` on a terminal: while the direct solves run (slowed), a line names them and the
    model's size, its clock advancing (the command showed nothing until its table)."""
    from rotordyn_modal.analysis import unbalance

    monkeypatch.setattr(unbalance, "dof_response", slowed(unbalance.dof_response))
    terminal = on_terminal(monkeypatch)
    code = main(["unbalance", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:3000:11",
                 "--out", str(tmp_path / "u.csv")])
    assert code == 0
    shown = drawings(terminal.getvalue(), "unbalance: direct solves at 11 speeds (6 coordinates): [")
    assert len({seconds(d) for d in shown}) >= 2, terminal.getvalue()
    assert not ticker_threads()


def test_unbalance_where_stderr_is_no_terminal_writes_no_line(monkeypatch, tmp_path, capsys):
    """With standard error a file or a pipe, the slowed unbalance writes no line and no carriage
    return there."""
    from rotordyn_modal.analysis import unbalance

    monkeypatch.setattr(unbalance, "dof_response", slowed(unbalance.dof_response))
    assert main(["unbalance", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:3000:11",
                 "--out", str(tmp_path / "u.csv")]) == 0
    err = capsys.readouterr().err
    assert "\r" not in err and "direct solves" not in err, err


def test_a_bar_on_a_file_writes_nothing_for_short_work():
    """A bar written to a file (a log, not a terminal) writes whole lines only, the first after
    ``LOG_DELAY`` s of work (tests/test_progress_log43.py): short work leaves the file empty (tqdm
    wrote three ``\\r`` drawings into it)."""
    stream = io.StringIO()
    bar = _progress.tqdm(total=2, file=stream, desc="work")
    time.sleep(0.5)
    bar.update(1)
    bar.close()
    assert stream.getvalue() == "", stream.getvalue()


def test_a_bar_left_unclosed_stops_its_clock_when_collected():
    """A bar abandoned without close (a loop left early) is collected as tqdm's own would be:
    the clock holds it only weakly, and its thread ends."""
    import gc

    stream = Terminal()
    for _ in _progress.tqdm(range(3), file=stream, desc="left"):
        break
    gc.collect()
    deadline = time.monotonic() + 2.0
    while ticker_threads() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not ticker_threads()


def test_ucs_map_on_a_terminal_shows_its_solve_with_a_clock(monkeypatch, tmp_path):
    """``ucs-map`` on a terminal names its work and the model's size while it runs (slowed), its
    clock advancing (500 geared rotors ran more than 400 s without a word)."""
    from rotordyn_modal.analysis import ucs_map

    monkeypatch.setattr(ucs_map, "ucs_map", slowed(ucs_map.ucs_map))
    terminal = on_terminal(monkeypatch)
    assert main(["ucs-map", str(EXAMPLES / "fan_on_bearings.toml"), "--stiffness", "1e5:1e8:3",
                 "--out", str(tmp_path / "u.csv")]) == 0
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    shown = drawings(terminal.getvalue(), f"ucs-map: 3 stiffness values, {model.dofs.n} coordinates: [")
    assert len({seconds(d) for d in shown}) >= 2, terminal.getvalue()


def test_report_names_each_section_under_way_with_its_clock(monkeypatch):
    """``report``'s analyses, section after section, each shown by its heading while it runs more
    than the line's delay (a section made slow here; the others do nothing), its clock advancing."""
    import importlib

    collect = importlib.import_module("rotordyn_modal.report.collect")    # the module (the package names its function)
    steps = {name: (lambda data: None) for name in collect._STEPS}
    steps["static"] = slowed(lambda data: None)
    monkeypatch.setattr(collect, "_STEPS", steps)
    terminal = on_terminal(monkeypatch)
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    collect.collect(model, collect.ReportInputs("api684", 300.0), progress=True)
    shown = drawings(terminal.getvalue(), "report: ")
    assert shown and all(d.startswith("report: Static loads and sag: [") for d in shown), shown
    assert len({seconds(d) for d in shown}) >= 2, shown
