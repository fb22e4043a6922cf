"""Progress where stderr is no terminal (a log file, a pipe, a batch job): whole lines, late and sparse.

A campbell of 100 geared rotors (103 s of CPU time) run with its stderr sent to a file showed no sign
of progress at all: the bars were drawn only on a terminal. Now such work writes whole lines there
(no carriage return, no cursor moves), the first after ``LOG_DELAY`` seconds and then at most one
every ``LOG_SECONDS``; short work writes nothing, and ``--quiet`` nothing at all.
"""

import io
import time

import pytest

from rotordyn_modal import _progress
from rotordyn_modal.cli.main import main

from test_cli import gear  # noqa: F401  (the fixture)


@pytest.fixture
def fast_log(monkeypatch):
    """The log's delay and interval shortened to a test's time scale [s]."""
    monkeypatch.setattr(_progress, "LOG_DELAY", 0.2)
    monkeypatch.setattr(_progress, "LOG_SECONDS", 0.4)


def test_a_bar_on_a_file_writes_whole_lines_at_most_one_an_interval(fast_log):
    log = io.StringIO()
    start = time.monotonic()
    with _progress.tqdm(total=20, desc="eigen-solve", unit="chunk", leave=False, file=log) as bar:
        for _ in range(20):
            time.sleep(0.1)
            bar.update()
    elapsed = time.monotonic() - start
    text = log.getvalue()
    lines = text.splitlines()
    assert "\r" not in text and "\x1b" not in text and text.endswith("\n")
    assert lines and all(line.startswith("eigen-solve:") for line in lines), text
    # none before the delay, then one per interval at the most (and the clock's own lines)
    assert 1 <= len(lines) <= 1 + (elapsed - 0.2) / 0.4 + 1, (len(lines), elapsed, text)
    assert lines[-1] != lines[0]                      # the count moves on


def test_short_work_writes_nothing_to_a_log():
    log = io.StringIO()
    with _progress.tqdm(total=5, desc="eigen-solve", leave=False, file=log) as bar:
        for _ in range(5):
            bar.update()
    with _progress.phase(True, "tracking modes", file=log):
        pass
    assert log.getvalue() == ""


def test_a_long_step_without_updates_still_writes_its_clock(fast_log):
    """One long LAPACK call (a phase, no steps to count): its line and clock reach the log."""
    log = io.StringIO()
    with _progress.phase(True, "tracking modes", delay=0.2, file=log):
        time.sleep(1.3)
    lines = log.getvalue().splitlines()
    assert len(lines) >= 2 and all(line.startswith("tracking modes: [00:0") for line in lines), lines
    assert len(set(lines)) == len(lines)              # each a later time


def test_the_command_line_shows_progress_in_a_log_unless_quiet(gear, capsys, fast_log, monkeypatch):  # noqa: F811
    # the eigen-solve made to last past a bar's shortest delay (0.25 s) whatever the machine: on an
    # idle one its 9,000 speeds took 0.16 s and its bar wrote nothing (session 46; under load it did)
    from rotordyn_modal.analysis import campbell as campbell_module

    real, slept = campbell_module._solved_at, []

    def slow_first_chunk(*args, **kwargs):
        if not slept:
            time.sleep(0.6)
            slept.append(True)
        return real(*args, **kwargs)

    monkeypatch.setattr(campbell_module, "_solved_at", slow_first_chunk)
    argv = ["campbell", str(gear), "--speeds", "0:6000:9000", "--out", "-"]
    main(argv)                                        # capsys: stderr is no terminal
    err = capsys.readouterr().err
    assert "eigen-solve" in err and "\r" not in err, err
    main(argv + ["--quiet"])
    assert "eigen-solve" not in capsys.readouterr().err
