"""Progress in a log for work done as a chain of short phases (issue 27 §1.9: long work shows progress).

Where stderr is no terminal, a bar or phase wrote its first line only after ``LOG_DELAY`` seconds
of its *own* work, so work split into phases one after the other, each shorter than that delay (a
report's many analyses), wrote nothing to a log however long the chain ran. Now the delay counts
from the start of the chain (the program's start, or the first of the bars and phases that follow
each other within ``PHASE_DELAY``), and a log still gets at most one line every ``LOG_SECONDS``.
"""

import io
import time

import pytest

from rotordyn_modal import _progress

STEP = 0.3          # s, one phase's work: shorter than the log's delay below


@pytest.fixture
def slow_log(monkeypatch):
    """A log whose delay is two phases' work and whose interval is three [s]."""
    monkeypatch.setattr(_progress, "LOG_DELAY", 2 * STEP)
    monkeypatch.setattr(_progress, "LOG_SECONDS", 3 * STEP)
    _progress.program_started()


def _chain(log, phases):
    start = time.monotonic()
    for number in range(phases):
        with _progress.phase(True, f"analysis {number}", file=log):
            time.sleep(STEP)
    return time.monotonic() - start


def test_one_short_phase_writes_nothing(slow_log):
    log = io.StringIO()
    _chain(log, 1)
    assert log.getvalue() == ""


def test_a_chain_of_phases_each_shorter_than_the_delay_shows_in_the_log(slow_log):
    log = io.StringIO()
    _chain(log, 4)
    lines = log.getvalue().splitlines()
    assert lines and all(line.startswith("analysis ") for line in lines), lines


def test_a_chain_writes_at_most_one_line_an_interval(slow_log):
    log = io.StringIO()
    elapsed = _chain(log, 12)
    lines = log.getvalue().splitlines()
    # the first line once the delay is past, then at most one per interval
    assert 2 <= len(lines) <= 1 + (elapsed - 2 * STEP) / (3 * STEP) + 1, (len(lines), elapsed, lines)


class _TimedLog(io.StringIO):
    """A log that notes when each of its lines was written [s, monotonic]."""

    def __init__(self):
        super().__init__()
        self.times = []

    def write(self, text):
        self.times.extend(time.monotonic() for _ in range(text.count("\n")))
        return super().write(text)


def test_the_clock_waits_an_interval_after_the_bars_own_line(monkeypatch):
    """The clock's lines and tqdm's own (written on an update) share one interval: a campbell of 500
    geared rotors wrote lines 10 s apart in a log whose interval is 30 s (tqdm's own at 03:28, the
    clock's at 03:38, on its own schedule)."""
    interval = 0.6
    monkeypatch.setattr(_progress, "LOG_DELAY", 0.1)
    monkeypatch.setattr(_progress, "LOG_SECONDS", interval)
    _progress.program_started()
    log = _TimedLog()
    with _progress.tqdm(total=10, desc="critical speeds", leave=False, file=log) as bar:
        time.sleep(0.4)                      # the clock's first line at 0.1 s
        bar.n = 5
        bar.last_print_t = bar._time()       # tqdm's own line on an update, as its update() writes it
        bar.refresh()
        time.sleep(1.5)
    gaps = [b - a for a, b in zip(log.times, log.times[1:])]
    assert len(log.times) >= 3 and "5/10" in log.getvalue().splitlines()[1], log.getvalue()
    assert min(gaps[1:]) >= 0.9 * interval, (gaps, log.getvalue())      # from the bar's own line on
