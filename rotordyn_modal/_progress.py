"""Progress bars (``tqdm.auto``) that show on every terminal, whatever size it reports.

tqdm sizes its bar from the terminal of its stream, taking one column and one row off what the
terminal reports. A pseudo-terminal that reports no size at all (0 x 0: ``script`` run without a
terminal, a container's ``-t`` before its size is set, some CI runners) then gives a width of -1,
which cuts the bar's last character off, and a height of -1, which hides the bar altogether: a
study or a sweep of an hour ran without any sign of progress (tqdm 4.70). A terminal of two rows
showed ``... (more hidden) ...`` in place of the bar. :func:`tqdm` gives such terminals tqdm's own
defaults for an unknown size instead: the counts and rates without the meter (``ncols=0``: nothing
to overflow a width that is not known) and 20 rows; terminals of a known size, files, pipes and
notebooks are left to tqdm.

A bar on a terminal also keeps its clock going between its steps (:class:`_Ticker`): tqdm draws
only when the bar advances, so a step of one long LAPACK call (a sweep's part of 4,012 states:
about 100 s on a shared machine) left the elapsed time standing, as if the program had stopped. A
thread redraws the bar every :data:`TICK_SECONDS` until it closes. :func:`phase` shows one line
naming work that has no steps to count (tracking the modes after a sweep, the thresholds), with
its clock. The clock runs while the step's LAPACK call runs only where that call releases the GIL:
``numpy.linalg``'s do (the sweeps' eigen-solutions, the direct solves), and so does
:func:`.analysis._eigensolve.eig` (``modes``, frf's modal superposition, the modes at the stability
thresholds); ``scipy.linalg``'s wrappers do not (a thread cannot draw during ``scipy.linalg.eig``:
``modes`` at 500 geared rotors showed nothing for 181 s).

Where stderr is no terminal (a log file, a pipe, a batch scheduler's output), a bar writes whole
lines instead, without carriage returns or a meter of blocks (:class:`_LogLines`): nothing for work
shorter than :data:`LOG_DELAY`, then a line at most every :data:`LOG_SECONDS`, its clock kept going
through a long step as on a terminal. A campbell of 100 geared rotors run with its stderr sent to a
file showed nothing for 103 s of CPU time (tqdm drew its ``\r`` updates only on a terminal here).
The delay counts from the start of the chain of work a bar continues (:func:`_log_delay`): a
report's sections, each shorter than it, wrote nothing to a log in 27 s.

A phase's delay counts from the terminal's last drawing by these bars, not from the phase's own
start, where the phase follows other work at once (within :data:`PHASE_DELAY`): phases one after
the other, each shorter than the delay, showed nothing for their sum (3.7 s at 200 geared rotors).
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
import threading
import time
import weakref

__all__ = ["tqdm", "terminal_defaults", "phase", "program_started", "TICK_SECONDS", "PHASE_DELAY", "LOG_DELAY",
           "LOG_SECONDS"]

#: seconds between two drawings of a bar on a terminal while its step runs
TICK_SECONDS = 1.0
#: where stderr is no terminal: seconds of work before a bar's or a phase's first line (shorter
#: work writes nothing to a log), and the shortest time between two of its lines
LOG_DELAY = 10.0
LOG_SECONDS = 30.0
#: the longest wait for the clock's thread to end when its bar closes [s]
_JOIN_SECONDS = 5.0
#: seconds of work a :func:`phase` waits before its line is shown (shorter work shows nothing)
PHASE_DELAY = 2.0

#: what a long single solve's notice says of its progress (``modes``, ``frf``): no steps to count,
#: but the clock of its line (:func:`phase`) runs through it on a terminal
ONE_CALL_NOTE = "one LAPACK call: on a terminal a clock shows it running"

#: rows tqdm assumes where the terminal's height is not known
_UNKNOWN_ROWS = 20
#: the shortest delay of a phase's line, however long the terminal has been silent before it, as a
#: fraction of :data:`PHASE_DELAY` (0.25 s)
_SHORTEST_DELAY = 0.125
#: monotonic times [s]: ``since``, the start of the terminal's silence (the last drawing or clearing
#: by a bar of this module, or the start of the work that followed it); ``ended``, when the last bar
#: or phase ended (None: none yet); ``program``, when the command line started (:func:`program_started`)
#: ``chain``, when the work the last bars and phases did one after the other (each starting within
#: :data:`PHASE_DELAY` of the last one's end) started; ``logged``, when a log last got a line
#: (:class:`_LogLines`)
_silence = {"since": None, "ended": None, "program": None, "chain": None, "logged": None}


def terminal_defaults(stream=None) -> dict:
    """The ``ncols`` and ``nrows`` a tqdm bar on ``stream`` (default ``sys.stderr``) needs where
    the terminal reports a size of 0 (or a height that leaves the bar no row); empty where tqdm's
    own reading serves (a sized terminal, or no terminal at all)."""
    stream = sys.stderr if stream is None else stream
    try:
        if not stream.isatty():
            return {}
        columns, rows = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):
        return {}
    sizes = {}
    if columns <= 1:                      # tqdm would draw within columns - 1 <= 0
        sizes["ncols"] = 0
    if rows <= 2:                         # tqdm hides bar 0 from rows - 1 <= 1 on
        sizes["nrows"] = _UNKNOWN_ROWS if rows <= 0 else 2
    if sizes:                             # tqdm reads the other from the terminal only if both are unset
        sizes.setdefault("ncols", columns - 1)
        sizes.setdefault("nrows", rows - 1)
    return sizes


def tqdm(*args, **kwargs):
    """A ``tqdm.auto.tqdm`` bar with the same arguments, sized for terminals that report no size
    (:func:`terminal_defaults`, for the bar's ``file``, default ``sys.stderr``)."""
    from tqdm.auto import tqdm as bar

    for key, value in terminal_defaults(kwargs.get("file")).items():
        kwargs.setdefault(key, value)
    if _writes_a_log(bar, kwargs.get("file")):
        kwargs.update(_log_options(kwargs))
    return _ticking(bar)(*args, **kwargs)


def _writes_a_log(bar_class, stream) -> bool:
    """Whether a bar of ``bar_class`` on ``stream`` (None: ``sys.stderr``) writes to no terminal:
    a file or a pipe (not a notebook's widget, nor an IPython kernel's stream, which draws ``\r``)."""
    if "ipykernel" in sys.modules or any(c.__module__ == "tqdm.notebook" for c in bar_class.__mro__):
        return False
    stream = sys.stderr if stream is None else stream
    try:
        return stream is not None and not stream.isatty()
    except (AttributeError, OSError, ValueError):
        return True


def _log_options(kwargs) -> dict:
    """The tqdm arguments of a bar written to a log (:func:`_writes_a_log`): whole lines
    (:class:`_LogLines`), the first after :data:`LOG_DELAY` s, then at most one every
    :data:`LOG_SECONDS` s, ASCII only."""
    stream = kwargs.get("file")
    return {"file": _LogLines(sys.stderr if stream is None else stream),
            "delay": _log_delay(),
            "mininterval": max(float(kwargs.get("mininterval") or 0.0), LOG_SECONDS),
            "ascii": True, "ncols": kwargs.get("ncols") or 80}


def _log_delay() -> float:
    """Seconds before a bar's or a phase's first line on a log: :data:`LOG_DELAY` after the start of
    the chain of work it continues (bars and phases one after the other, :func:`_chain_start`), and
    :data:`LOG_SECONDS` after the log's last line where that chain has written one, so that phases
    each shorter than the delay still show their sum and a log gets at most a line an interval;
    never less than a phase's shortest delay. (A phase's own delay is a terminal's: a log's is
    longer.)"""
    now = time.monotonic()
    start, logged = _chain_start(now), _silence["logged"]
    due = start + LOG_DELAY
    if logged is not None and logged >= start:
        due = max(due, logged + LOG_SECONDS)
    return max(due - now, _SHORTEST_DELAY * PHASE_DELAY)


def _chain_start(now) -> float:
    """When the chain of work that a bar starting at ``now`` continues started [s, monotonic]: the
    program's start before its first bar has ended (:func:`program_started`), the last chain's start
    where the last bar or phase ended at most :data:`PHASE_DELAY` ago, else ``now``."""
    ended, chain = _silence["ended"], _silence["chain"]
    if ended is None:
        chain = now if _silence["program"] is None else _silence["program"]
    elif now - ended > PHASE_DELAY or chain is None:
        chain = now
    _silence["chain"] = chain
    return chain


class _LogLines:
    """A stream for a tqdm bar that writes each of its drawings as one whole line on ``stream``
    (a log): tqdm's carriage returns and cursor moves taken out, a drawing equal to the last line
    (or blank: a bar cleared) not written again."""

    def __init__(self, stream):
        self._stream = stream
        self._last = None

    def write(self, text) -> int:
        import re

        for part in re.split(r"[\r\n]", str(text).replace("\x1b[A", "")):
            line = part.rstrip()
            if line and line != self._last:
                self._stream.write(line + "\n")
                self._last = line
                _silence["logged"] = time.monotonic()
        return len(text)

    def flush(self):
        getattr(self._stream, "flush", lambda: None)()

    def isatty(self) -> bool:
        return False

    def __getattr__(self, name):          # encoding, errors, ... of the log's stream
        return getattr(self._stream, name)


@contextlib.contextmanager
def phase(enabled, description, delay=None, file=None):
    """While the ``with`` block runs: one line ``description: [elapsed]`` on ``file`` (default
    ``sys.stderr``), its clock ticking, shown once the work has taken ``delay`` seconds (default
    :data:`PHASE_DELAY`) and cleared at the end; nothing when not ``enabled``.

    Yields the bar (a :func:`tqdm` bar without a total: ``set_description(text, refresh=False)``
    renames the work, e.g. with a count of its steps, drawn at the clock's next tick), or None when
    not ``enabled``."""
    if not enabled:
        yield None
        return
    bar = tqdm(total=None, desc=f"{description}: ", bar_format="{desc}[{elapsed}]", leave=False, file=file,
               delay=_phase_delay() if delay is None else delay)
    try:
        yield bar
    finally:
        bar.close()


def _phase_delay() -> float:
    """:data:`PHASE_DELAY` less the silence the phase continues: the time since the terminal's
    last drawing where the last bar or phase ended at most :data:`PHASE_DELAY` ago (work one step
    after another), at least its fraction :data:`_SHORTEST_DELAY`; else :data:`PHASE_DELAY` (a new
    silence)."""
    now = time.monotonic()
    since, ended = _silence["since"], _silence["ended"]
    if ended is None and _silence["program"] is not None:
        _silence["since"] = since = _silence["program"]     # the program's first line: silent since it started
    elif since is None or ended is None or now - ended > PHASE_DELAY:
        _silence["since"] = since = now
    return max(PHASE_DELAY - (now - since), _SHORTEST_DELAY * PHASE_DELAY)


def program_started():
    """Mark the start of the program (the command line's ``main``): until a bar or phase has ended,
    the terminal has been silent since then, and the first phase (reading the model, after the
    imports and the parsing) is shown :data:`PHASE_DELAY` after the start, not after its own."""
    _silence.update(since=None, ended=None, program=time.monotonic(), chain=None, logged=None)


def _drawn():
    """The terminal was drawn on (a bar's line drawn or cleared) just now: its silence starts again."""
    _silence["since"] = time.monotonic()


@functools.lru_cache(maxsize=None)
def _ticking(base):
    """``base`` (a tqdm class) whose bars on a terminal redraw themselves every
    :data:`TICK_SECONDS` until closed (:class:`_Ticker`)."""

    class Ticking(base):
        def __init__(self, *args, **kwargs):
            self._ticker = None
            super().__init__(*args, **kwargs)
            if _on_terminal(self):
                self._ticker = _Ticker(self)
            elif _on_log(self):
                self._ticker = _Ticker(self, LOG_SECONDS)

        def close(self):
            ticker, self._ticker = getattr(self, "_ticker", None), None
            if ticker is not None:
                ticker.stop()
                if ticker.drawn and hasattr(self, "last_print_t"):   # tqdm clears only a bar it knows it drew
                    self.last_print_t = max(self.last_print_t, self.start_t + self.delay)
                if ticker.drawn or not getattr(self, "delay", 0):    # drawn, now cleared or left
                    _drawn()
                _silence["ended"] = time.monotonic()
            super().close()

    Ticking.__name__ = Ticking.__qualname__ = base.__name__
    Ticking.__doc__ = base.__doc__
    return Ticking


def _on_terminal(bar) -> bool:
    """Whether ``bar`` draws on a terminal (not a file, a pipe or a notebook's widget)."""
    try:
        return not bar.disable and bool(bar.fp.isatty())
    except (AttributeError, OSError, ValueError):
        return False


def _on_log(bar) -> bool:
    """Whether ``bar`` writes whole lines to a log (:class:`_LogLines`, inside tqdm's own wrapper)."""
    stream = getattr(bar, "fp", None)
    return not getattr(bar, "disable", True) and isinstance(getattr(stream, "_wrapped", stream), _LogLines)


class _Ticker:
    """A daemon thread that redraws a bar every :data:`TICK_SECONDS` (``seconds``: every so many; a
    log's bar :data:`LOG_SECONDS`) (its elapsed time, rate and
    remaining time as of now) until :meth:`stop`, or until the bar is closed or gone. It holds the
    bar by a weak reference only: a bar left unclosed is still collected (and closed) as tqdm's
    own would be. A bar with a ``delay`` is first drawn once that delay is past."""

    def __init__(self, bar, seconds=None):
        self.drawn = False
        self._seconds = seconds         # None: TICK_SECONDS as it is when each wait starts
        self._stopped = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(weakref.ref(bar),), daemon=True,
                                        name="rotordyn_modal progress ticker")
        self._thread.start()

    def _run(self, reference):
        while not self._stopped.wait(self._wait(reference)):
            bar = reference()
            if bar is None or bar.disable:
                return
            try:
                if self._seconds is not None and self.drawn and bar._time() < self._due(bar):
                    continue                           # the bar wrote its own line meanwhile: none more yet
                if bar._time() >= bar.start_t + bar.delay:
                    bar.refresh()
                    if self._seconds is not None:      # a log's line: the next update's waits from it
                        bar.last_print_t, bar.last_print_n = bar._time(), bar.n
                    self.drawn = True
                    _drawn()
            except Exception:          # a closed or broken stream: stop drawing, never raise here
                return
            finally:
                del bar

    def _wait(self, reference) -> float:
        """Seconds to the next drawing: :data:`TICK_SECONDS`, or less to the end of the first
        drawing's delay (a phase's delay shortened by the silence before it is kept to)."""
        tick = TICK_SECONDS if self._seconds is None else self._seconds
        bar = reference()
        try:
            if bar is None:
                left = tick
            elif not self.drawn:
                left = bar.start_t + bar.delay - bar._time()
            elif self._seconds is not None:    # a log's next line: an interval after the bar's last, whoever wrote it
                return min(tick, max(self._due(bar) - bar._time(), 0.0) + 0.001)
            else:
                left = tick
        except Exception:
            left = tick
        return min(tick, left + 0.001) if left > 0 else tick

    def _due(self, bar) -> float:
        """When a log's bar may write its next line: :data:`LOG_SECONDS` (``seconds``) after its
        last one, the clock's or tqdm's own on an update [s, the bar's clock]."""
        return bar.last_print_t + self._seconds

    def stop(self):
        """Stop redrawing; returns once the thread has ended (at once from the thread itself: a
        bar collected there)."""
        self._stopped.set()
        if threading.current_thread() is not self._thread and not sys.is_finalizing():
            self._thread.join(_JOIN_SECONDS)     # a bound: never hang on a thread the interpreter froze
