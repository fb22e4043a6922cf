"""The numeric arguments of the analyses' Python entry points, checked before any work.

``rdm.modal(model, "3000")``, a NaN among the speeds or a 2-D array of frequencies would
otherwise convert silently, give NaN results or fail inside numpy with a message that names no
argument. Each check raises :class:`~rotordyn_modal.errors.InputError` naming the argument, its
value and what was expected.
"""

from __future__ import annotations

import numpy as np

from .errors import InputError
from .model._table import LARGEST

__all__ = ["speed", "values", "speeds", "frequencies", "orders", "whole_number", "number"]


def _plain(value):
    """``value`` with numpy arrays and numbers as Python lists and numbers (their repr reads
    ``array([...])``, ``np.float64(-1.0)``)."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (list, tuple)):
        return type(value)(_plain(v) for v in value)
    return value


def _shown(value, limit: int = 80) -> str:
    """``repr(value)`` on one line, at most ``limit`` characters, numpy's values as Python's."""
    text = " ".join(repr(_plain(value)).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _numbers(value, name: str, expected: str) -> np.ndarray:
    """``value`` as an array of floats; strings, booleans, complex numbers and other objects
    are refused (``numpy.asarray(["1", "2"], float)`` would read the strings)."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):           # ragged nested lists
        raise InputError(f"{name} = {_shown(value)}: expected {expected}") from None
    if array.dtype.kind not in "iuf":
        raise InputError(f"{name} = {_shown(value)}: expected {expected}")
    return array.astype(float)


def speed(value, name: str = "speed") -> float:
    """One finite speed [rad/s], of magnitude at most ``LARGEST`` (1e30, as a model's numbers)."""
    expected = "one finite number [rad/s]"
    array = _numbers(value, name, expected)
    if array.ndim != 0:
        raise InputError(f"{name} = {_shown(value)}: expected {expected}, got an array of shape {array.shape}")
    if not np.isfinite(array):
        raise InputError(f"{name} = {_shown(value)}: expected {expected}")
    if abs(float(array)) > LARGEST:
        raise InputError(f"{name} = {_shown(value)}: expected a speed of magnitude at most {LARGEST:g} rad/s (beyond "
                         "it the gyroscopic terms of the model's numbers overflow)")
    return float(array)


def values(value, name: str, unit: str, positive: bool = False, non_negative: bool = False,
           increasing: bool = False) -> np.ndarray:
    """A non-empty 1-D array of finite numbers of magnitude at most ``LARGEST`` (1e30, as a model's
    numbers: beyond it products with them overflow); a scalar is one value.

    Parameters
    ----------
    value : array_like
    name : str
        The argument's name, as the message shows it.
    unit : str
        Its unit, as the message shows it.
    positive, non_negative, increasing : bool
        Also require values > 0, values >= 0, strictly increasing values.

    Returns
    -------
    ndarray of float, shape (N,)
    """
    expected = f"a non-empty 1-D array of finite numbers [{unit}]"
    array = np.atleast_1d(_numbers(value, name, expected))
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"{name} = {_shown(value)}: expected {expected}, got shape {array.shape}")
    for test, what in ((~np.isfinite(array), "finite numbers"),
                       (np.abs(array) > LARGEST, f"numbers of magnitude at most {LARGEST:g}"),
                       (array <= 0 if positive else None, "numbers > 0"),
                       (array < 0 if non_negative else None, "numbers >= 0")):
        if test is not None and test.any():
            i = int(np.argmax(test))
            raise InputError(f"{name} = {_shown(value)}: expected {what} [{unit}]; "
                             f"element {i} is {float(array[i])!r}")
    if increasing and len(array) > 1 and not (np.diff(array) > 0).all():
        i = int(np.argmax(~(np.diff(array) > 0)))
        raise InputError(f"{name} = {_shown(value)}: expected strictly increasing values [{unit}]; element {i + 1} "
                         f"({float(array[i + 1])!r}) does not exceed element {i} ({float(array[i])!r})")
    return array


def speeds(value, name: str = "speeds", increasing: bool = True) -> np.ndarray:
    """Speeds of a sweep [rad/s]: finite, strictly increasing unless ``increasing`` is False."""
    return values(value, name, "rad/s", increasing=increasing)


def frequencies(value, name: str = "freqs_hz") -> np.ndarray:
    """Frequencies [Hz]: finite, >= 0."""
    try:
        return values(value, name, "Hz", non_negative=True)
    except InputError as error:
        raise InputError(f"frequencies: expected a 1-D array of finite values >= 0 Hz; {error}") from None


def orders(value, name: str = "orders") -> tuple:
    """Excitation orders (1X, 2X, ...): finite, > 0, each once (a repeated order listed every
    critical speed of its line twice); an empty sequence is no order."""
    if isinstance(value, (list, tuple, np.ndarray)) and len(value) == 0:
        return ()
    out = tuple(float(v) for v in values(value, name, "multiples of the speed", positive=True))
    for index, order in enumerate(out):
        if order in out[:index]:
            raise InputError(f"{name} = {_shown(list(out))}: expected each order once; element {index} ({order:g}) "
                             f"repeats element {out.index(order)}")
    return out


def whole_number(value, name: str, low: int, high: int) -> int:
    """One whole number from ``low`` to ``high`` (``2.0`` is one; ``2.5``, NaN, a string or a
    boolean is not): a count or an index, refused by name before it reaches numpy (a count of
    1e7 points drew the memory of the machine, -3 failed inside ``numpy.linspace``)."""
    expected = f"a whole number from {low} to {high}"
    array = _numbers(value, name, expected)
    if array.ndim != 0 or not np.isfinite(array) or float(array) != round(float(array)) \
            or not low <= float(array) <= high:
        raise InputError(f"{name} = {_shown(value)}: expected {expected}")
    return int(array)


def number(value, name: str, unit: str) -> float:
    """One finite number [``unit``] (a string, a boolean, NaN or an array is refused)."""
    expected = f"one finite number [{unit}]"
    array = _numbers(value, name, expected)
    if array.ndim != 0 or not np.isfinite(array):
        raise InputError(f"{name} = {_shown(value)}: expected {expected}")
    return float(array)
