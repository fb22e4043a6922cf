"""The start-up of an analysis on a terminal shows a line once it lasts (issue 27 §1.9).

Before its first bar, a command read and checked the model and estimated its CPU time without a
word: 17-19 s at 500 geared rotors for ``stability``, 5-8 s for ``modes`` at 200 (clock27o's
report). Here the reading and the estimate are made slow on purpose (each sleeps several of the
line's delays, then does the real work), and the terminal must not stay silent much longer than
one delay during them.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

from rotordyn_modal import _progress
from rotordyn_modal.analysis import _work
from rotordyn_modal.cli import _common, main
from test_progress_solve_ticks import Terminal   # a stream that is a terminal, noting its writes' times

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _slowed(function, seconds, ends, starts):
    def slow(*args, **kwargs):
        starts.append(time.monotonic())
        time.sleep(seconds)
        try:
            return function(*args, **kwargs)
        finally:
            ends.append(time.monotonic())
    return slow


@pytest.mark.parametrize("command", [["stability", "--speeds", "0:3000:3"], ["modes", "--speed", "3000"],
                                     ["critical-speeds", "--speeds", "0:3000:5"]])
def test_reading_the_model_and_estimating_the_work_show_a_line_once_they_last(command, monkeypatch, tmp_path):
    monkeypatch.setattr(_progress, "TICK_SECONDS", 0.05)
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.2)
    slow = 4 * _progress.PHASE_DELAY
    starts, ends = [], []
    monkeypatch.setattr(_common, "load_model", _slowed(_common.load_model, slow, ends, starts))
    monkeypatch.setattr(_work, "refuse_long_work", _slowed(_work.refuse_long_work, slow, ends, starts))
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    name, *options = command
    assert main([name, str(EXAMPLES / "gear_machine.toml"), *options, "--out", str(tmp_path / "o.csv")]) == 0
    assert len(ends) == 2, ends                                 # both slowed steps ran
    start = starts[0]                                           # from the model's reading (after the imports)
    times = [start] + [t for t in terminal.times if t < ends[-1]] + [ends[-1]]
    silence = max(b - a for a, b in zip(times, times[1:]))
    text = terminal.getvalue()
    gaps = [(round(a - start, 2), round(b - a, 2)) for a, b in zip(times, times[1:]) if b - a > 0.3]
    assert silence < _progress.PHASE_DELAY + 2 * _progress.TICK_SECONDS + 0.1, (silence, gaps, [round(e - start, 2) for e in ends], text[:300])
    assert "reading and checking the model: [" in text and "estimating the work: [" in text, text


def test_quiet_start_up_says_nothing(monkeypatch, tmp_path):
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.0)
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["stability", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:3000:3", "--quiet",
                 "--out", str(tmp_path / "o.csv")]) == 0
    assert terminal.getvalue() == ""


def test_the_first_line_counts_its_delay_from_the_start_of_the_program(monkeypatch, tmp_path):
    """Work before the model is read (here the parser, slowed) is part of the silence: the model's
    line shows about one delay after ``main`` starts, not one delay after the reading starts."""
    import importlib

    cli_main = importlib.import_module("rotordyn_modal.cli.main")    # the module (the package exports main)

    monkeypatch.setattr(_progress, "TICK_SECONDS", 0.05)
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.5)
    monkeypatch.setattr(_progress, "_silence", dict(_progress._silence))   # this test's own program
    slow = 2 * _progress.PHASE_DELAY
    starts, ends = [], []
    monkeypatch.setattr(cli_main, "build_parser", _slowed(cli_main.build_parser, slow, [], []))
    monkeypatch.setattr(_common, "load_model", _slowed(_common.load_model, slow, ends, starts))
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    begun = time.monotonic()
    assert main(["stability", str(EXAMPLES / "gear_machine.toml"), "--speeds", "0:3000:3", "--out",
                 str(tmp_path / "o.csv")]) == 0
    assert "reading and checking the model: [" in terminal.getvalue()
    first = terminal.times[0] - begun
    assert first < slow + 0.5 * _progress.PHASE_DELAY, (first, starts[0] - begun)


def test_phases_after_the_program_s_first_one_keep_counting_from_its_start(monkeypatch):
    """The start-up's phases, none drawn, then the analysis' own line: that line shows about one
    delay after the program started (``frf`` at 200 rotors showed its line 2 s after its own start,
    after a silent model reading)."""
    monkeypatch.setattr(_progress, "TICK_SECONDS", 0.05)
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.5)
    monkeypatch.setattr(_progress, "_silence", dict(_progress._silence))
    terminal = Terminal()
    begun = time.monotonic()
    _progress.program_started()
    with _progress.phase(True, "reading", file=terminal):
        time.sleep(0.8 * _progress.PHASE_DELAY)
    with _progress.phase(True, "work", file=terminal):
        time.sleep(2 * _progress.PHASE_DELAY)
    first = terminal.times[0] - begun
    assert "work: [" in terminal.getvalue() and first < 1.4 * _progress.PHASE_DELAY, (first, terminal.getvalue())
