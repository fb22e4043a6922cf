"""Limits on the sizes a user may ask for, checked before anything is allocated.

A count (points of a ``START:STOP:N`` range, samples of a simulation, variants of a study)
above :data:`MAX_POINTS` is refused with a message that names the limit and the way around
it: split the work into several runs, or raise the limit with the environment variable
``ROTORDYN_MODAL_MAX_POINTS`` when the memory is there.
"""

from __future__ import annotations

import os

from .errors import InputError

__all__ = ["MAX_POINTS", "max_points", "count_problem"]

#: default largest count of points, samples or variants (a million speeds of a Campbell sweep
#: of a 6-coordinate machine hold about 1 GB of eigenvectors)
MAX_POINTS = 1_000_000
#: environment variable that replaces :data:`MAX_POINTS`
ENVIRONMENT = "ROTORDYN_MODAL_MAX_POINTS"


def max_points() -> int:
    """The limit in force: ``ROTORDYN_MODAL_MAX_POINTS`` when set, else :data:`MAX_POINTS`."""
    text = os.environ.get(ENVIRONMENT)
    if text is None or not text.strip():
        return MAX_POINTS
    try:
        value = int(float(text))
    except (ValueError, OverflowError):
        raise InputError(f"{ENVIRONMENT}={text!r}: expected a whole number >= 1") from None
    if value < 1:
        raise InputError(f"{ENVIRONMENT}={text!r}: expected a whole number >= 1")
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
