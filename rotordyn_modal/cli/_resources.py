"""``--verbose``: progress of long runs on the log and the peak memory of the command."""

from __future__ import annotations

import contextlib
import logging
import sys

__all__ = ["add_verbose", "verbose_log", "peak_memory_bytes", "report_peak_memory"]


def add_verbose(parser, what: str = "") -> None:
    parser.add_argument("--verbose", action="store_true",
                        help="the package's log lines on stderr, and the peak memory of the command when done"
                             + (f"; {what}" if what else ""))


@contextlib.contextmanager
def verbose_log(args, logger: str = "rotordyn_modal"):
    """With ``--verbose``: the package's log messages (INFO and up) on stderr, one line each."""
    if not getattr(args, "verbose", False):
        yield
        return
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(f"rotordyn-modal {args.command}: %(message)s"))
    log = logging.getLogger(logger)
    level = log.level
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield
    finally:
        log.removeHandler(handler)
        log.setLevel(level)


def peak_memory_bytes() -> int:
    """Peak resident memory of this process so far [bytes]: on Linux the ``VmHWM`` of
    ``/proc/self/status``, counted from the program's start; elsewhere ``getrusage``'s ru_maxrss
    (bytes on macOS); 0 where neither is available. Linux's ru_maxrss is not reset by exec: a
    command started from a process that once held 981 MB said 981 MB, its own peak 14 MB."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return 0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(peak if sys.platform == "darwin" else peak * 1024)


def report_peak_memory(args) -> None:
    """With ``--verbose``: ``peak memory: N MB`` on stderr (the whole process, Python included)."""
    if getattr(args, "verbose", False):
        print(f"rotordyn-modal {args.command}: peak memory {peak_memory_bytes() / 2**20:.1f} MB "
              "(resident, whole process)", file=sys.stderr)
