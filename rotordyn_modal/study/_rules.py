"""What the study file's readers share: the error type and the rules of numbers and grids.

Below both :mod:`.definition` (the file) and :mod:`.analyses` (its ``[analyses]`` table).
"""

from __future__ import annotations

import math

import numpy as np

from .._limits import count_problem
from ..errors import InputError

__all__ = ["StudyError", "is_number", "grid_values"]


class StudyError(InputError):
    """A study file that fails validation: ``file: where = value: expected ...``; a value of None
    (TOML has no null: a key not given) reads ``'<missing>'``, as in model files."""

    def __init__(self, source: str, where: str, value, expected: str):
        self.source, self.where, self.value, self.expected = source, where, value, expected
        text = repr("<missing>" if value is None else value)
        text = text if len(text) <= 80 else text[:77] + "..."
        super().__init__(f"{source}: {where} = {text}: expected {expected}")


def is_number(value) -> bool:
    """A finite int or float (not a bool, not a string)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def grid_values(value, where, source) -> np.ndarray:
    """A list of finite numbers or ``'START:STOP:N'`` -> the points, shape (G,)."""
    if isinstance(value, str):
        parts = value.split(":")
        try:
            if "_" in value:    # Python reads '0:3000:5_0' as 50 points (digit separators), a typo as a count
                raise ValueError(value)
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except (ValueError, IndexError):
            raise StudyError(source, where, value, "a list of numbers or 'START:STOP:N'") from None
        if len(parts) != 3 or count < 1 or not (math.isfinite(start) and math.isfinite(stop)):
            raise StudyError(source, where, value, "'START:STOP:N' with N >= 1 and finite ends")
        if count == 1 and start != stop:   # one point would silently drop STOP
            raise StudyError(source, where, value, "'START:STOP:N' with N >= 2 for a range (or START = STOP "
                             "with N = 1)")
        if problem := count_problem(count):
            raise StudyError(source, where, value, "'START:STOP:N' with N " + problem)
        return np.linspace(start, stop, count)
    if not isinstance(value, list) or not value or not all(is_number(v) for v in value):
        raise StudyError(source, where, value, "a non-empty list of finite numbers or 'START:STOP:N'")
    return np.array(value, dtype=float)
