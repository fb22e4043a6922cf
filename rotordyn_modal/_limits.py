"""Limits on the sizes a user may ask for, checked before anything is allocated.

A count (points of a ``START:STOP:N`` range, samples of a simulation, variants of a study)
above :data:`MAX_POINTS` is refused with a message that names the limit and the way around
it: split the work into several runs, or raise the limit with the environment variable
``ROTORDYN_MODAL_MAX_POINTS`` when the memory is there.

An analysis whose arrays would not fit in the memory at hand (:func:`available_memory`) is
refused before its work with its estimate (:func:`memory_problem`); the environment variable
``ROTORDYN_MODAL_MEMORY_GB`` sets the memory to count on instead (``inf``: no check).

The limit of CPU time is not here: every command reads it from :mod:`.analysis._cost` (30 min,
``ROTORDYN_MODAL_MAX_CPU_MINUTES``; ``--allow-long`` and ``rdm.long_work_allowed()`` lift it), the
study command and ``rdm.study`` included (:func:`.study.execution.check_cpu_time`).
"""

from __future__ import annotations

import math
import os

from .errors import InputError

__all__ = ["MAX_POINTS", "max_points", "count_problem", "available_memory", "memory_room", "memory_problem"]

#: default largest count of points, samples or variants (a million speeds of a Campbell sweep
#: of a 6-coordinate machine hold about 1 GB of eigenvectors)
MAX_POINTS = 1_000_000
#: environment variable that replaces :data:`MAX_POINTS`
ENVIRONMENT = "ROTORDYN_MODAL_MAX_POINTS"


def max_points() -> int:
    """The limit in force: ``ROTORDYN_MODAL_MAX_POINTS`` when set, else :data:`MAX_POINTS`."""
    value = environment_number(ENVIRONMENT, "a whole number >= 1", lambda v: math.isfinite(v) and v >= 1)
    return MAX_POINTS if value is None else int(value)


def environment_number(variable: str, expected: str, valid, default=None):
    """The number the environment variable ``variable`` holds, ``default`` when it is unset or blank.

    Parameters
    ----------
    variable : str
    expected : str
        What it must hold, for the message ('a number of CPU minutes > 0 (or inf)').
    valid : callable
        ``valid(value) -> bool`` of the float read (nan where the text is no number).
    default : optional
        Returned when the variable is unset or blank.

    Raises
    ------
    InputError
        ``VARIABLE='TEXT': expected EXPECTED`` where the text is no number or ``valid`` refuses it.
    """
    text = os.environ.get(variable, "")
    if not text.strip():
        return default
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not valid(value):
        raise InputError(f"{variable}={text!r}: expected {expected}")
    return value


def count_problem(count: int, what: str = "points") -> str:
    """'' when ``count`` is within the limit, else what to say about it.

    Parameters
    ----------
    count : int
        The number asked for.
    what : str
        What is counted, for the message ('points', 'samples', 'variants').
    """
    limit = max_points()
    if count <= limit:
        return ""
    return (f"at most {limit:,} {what} (asked for {count:,}): split the work into several runs, or "
            f"raise the limit with the environment variable {ENVIRONMENT}")


#: environment variable: the memory [GiB] to count on instead of measuring it (``inf``: no check)
MEMORY_ENVIRONMENT = "ROTORDYN_MODAL_MEMORY_GB"


def available_memory() -> float:
    """Bytes this process may still allocate: the least of the system's available memory
    (``MemAvailable`` of ``/proc/meminfo``, else ``psutil`` where installed), the room under
    the process's address-space limit (``RLIMIT_AS``) and under its control group's memory
    limit (cgroup v2); ``ROTORDYN_MODAL_MEMORY_GB`` replaces the measurement. ``inf`` where
    nothing can be measured."""
    return memory_room()[0]


def memory_room() -> tuple[float, str]:
    """:func:`available_memory` [bytes] and which limit it is, in words for a message."""
    value = environment_number(MEMORY_ENVIRONMENT, "a number of GiB >= 0 (or inf)", lambda v: v >= 0)
    if value is not None:
        return value * 2**30, f"{MEMORY_ENVIRONMENT}={os.environ[MEMORY_ENVIRONMENT].strip()}"
    return min((_system_available(), "the memory this machine has available (MemAvailable)"),
               _address_space_room(), _cgroup_room())


def _gb(count: float) -> str:
    return f"{count / 1e9:.4g} GB"


def _system_available() -> float:
    available = _meminfo_available()
    if available != float("inf"):
        return available
    try:
        import psutil
    except ImportError:
        return available
    return float(psutil.virtual_memory().available)


def _meminfo_available() -> float:
    """``MemAvailable`` of ``/proc/meminfo`` (Linux) [bytes], inf elsewhere."""
    return _proc_bytes("/proc/meminfo", "MemAvailable", float("inf"))


def _address_space_room() -> tuple[float, str]:
    """``RLIMIT_AS`` minus the process's virtual size now (inf without a limit), and why."""
    try:
        import resource
    except ImportError:  # pragma: no cover - Windows
        return float("inf"), "no address-space limit"
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    if soft == resource.RLIM_INFINITY:
        return float("inf"), "no address-space limit"
    size = _virtual_size()
    return float(soft) - size, (f"the address-space limit (ulimit -v) of {_gb(soft)} less the {_gb(size)} "
                                "this process takes")


def _virtual_size() -> float:
    """``VmSize`` of ``/proc/self/status`` (Linux) [bytes], 0 elsewhere."""
    return _proc_bytes("/proc/self/status", "VmSize", 0.0)


def _proc_bytes(path: str, field: str, missing: float) -> float:
    """The ``FIELD:  N kB`` line of a ``/proc`` file [bytes], ``missing`` without the file or line."""
    try:
        with open(path) as handle:
            for line in handle:
                if line.startswith(field + ":"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return missing


def _cgroup_room() -> tuple[float, str]:
    """The control group's ``memory.max`` minus ``memory.current`` (inf where there is none), and why."""
    try:
        with open("/sys/fs/cgroup/memory.max") as handle:
            limit = handle.read().strip()
        with open("/sys/fs/cgroup/memory.current") as handle:
            current = float(handle.read().strip())
    except (OSError, ValueError):
        return float("inf"), "no container memory limit"
    if limit == "max":
        return float("inf"), "no container memory limit"
    return float(limit) - current, f"the container's memory limit of {_gb(float(limit))} less the {_gb(current)} in use"


def memory_problem(needed: float, what: str, advice: str) -> str:
    """'' when ``needed`` bytes fit in :func:`available_memory`, else the message refusing the
    work: ``WHAT needs about X GiB of memory, Y GiB is available: ADVICE``.

    Parameters
    ----------
    needed : float
        The estimate [bytes].
    what : str
        What needs it ('a Campbell sweep of 2,006 coordinates at 101 speeds').
    advice : str
        How to need less ('use at most 40 speeds').
    """
    available = available_memory()
    if needed <= available:
        return ""
    digits = 1       # more where one decimal shows the two alike ("needs about 0.3 GiB, 0.3 GiB is available")
    while digits < 6 and round(needed / 2**30, digits) <= round(available / 2**30, digits):
        digits += 1
    return (f"{what} needs about {needed / 2**30:.{digits}f} GiB of memory, {available / 2**30:.{digits}f} GiB is "
            f"available: {advice}; {MEMORY_ENVIRONMENT} sets the memory to count on")
