"""Reading one table of a model description, with messages that say where a value sits."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from .components import is_finite_number
from ..errors import ModelError

__all__ = ["Table", "unknown_key", "close_key", "did_you_mean", "and_others", "shape_text", "LARGEST", "SMALLEST_POSITIVE", "magnitude_problem", "non_number",
           "visible", "visible_names", "semidefinite_problem", "plain", "line_break_problem"]

#: largest magnitude of a number in a model description (SI units): no machine needs more, and
#: products of two such numbers (stiffness over mass, squared frequencies) stay far from overflow
LARGEST = 1e30
#: smallest value of a quantity that must be > 0 (masses, inertias, lengths, times): its inverse
#: stays finite in the mass matrix's inverse and the relaxation rates
SMALLEST_POSITIVE = 1e-30


class Table:
    """Where a value sits in the description, for messages: ``[rotors.fan]``."""

    def __init__(self, source: str, label: str, data: Mapping[str, Any]):
        self.source = source
        self.label = label
        self.data = data

    def error(self, key: str, value, expected: str) -> ModelError:
        where = f"[{self.label}] {key}" if self.label else key
        return ModelError(self.source, where, value, expected)

    def check_keys(self, allowed) -> None:
        for key in self.data:
            if key not in allowed:
                raise self.error(visible(key), self.data[key], "one of the keys " + ", ".join(allowed)
                                 + unknown_key(key, allowed))

    def require(self, key: str):
        if key not in self.data:
            raise self.error(key, "<missing>", "a value (the key is required)")
        return self.data[key]

    # -- typed readers ---------------------------------------------------------------
    def number(self, key: str, default=None, *, positive=False, nonnegative=False,
               required=False) -> float:
        if key not in self.data:
            if required:
                self.require(key)
            return default
        value = self.data[key]
        if not is_finite_number(value):
            raise self.error(key, value, "a finite number")
        value = float(value)
        if positive and not value > 0:
            raise self.error(key, value, "a finite number > 0")
        if nonnegative and not value >= 0:
            raise self.error(key, value, "a finite number >= 0")
        problem = magnitude_problem(value, positive=positive)
        if problem:
            raise self.error(key, value, problem)
        return value

    def text(self, key: str, default=None, *, choices=None, required=False) -> str:
        if key not in self.data:
            if required:
                self.require(key)
            return default
        value = self.data[key]
        if not isinstance(value, str) or not value.strip():
            raise self.error(key, value, "a non-empty string")
        if (problem := line_break_problem(value)):
            raise self.error(key, value, problem)
        if choices is not None and value not in choices:
            raise self.error(key, value, "one of " + ", ".join(repr(c) for c in choices))
        return value

    def name_of(self, key: str, names, what: str, *, required=False, hint: str = "") -> str | None:
        """A :meth:`text` that names one of ``names`` (None when absent and not ``required``):
        else ``expected the name of one of the WHAT NAMES HINT``."""
        value = self.text(key, required=required)
        if value is not None and value not in names:
            raise self.error(key, value, f"the name of one of the {what} " + visible_names(names) + hint)
        return value

    def array(self, key: str, shapes, default=None, *, required=False) -> np.ndarray:
        """A finite numeric array of one of ``shapes``."""
        if key not in self.data:
            if required:
                self.require(key)
            return None if default is None else np.array(default, dtype=float)
        value = self.data[key]

        def expected():
            return " or ".join(shape_text(s) for s in shapes)

        if (found := non_number(value)) is not None:
            raise self.error(key, value, expected() + " of numbers (" + found + ")")
        try:
            arr = np.array(value, dtype=float)
        except (TypeError, ValueError, OverflowError):   # OverflowError: an integer beyond every float
            raise self.error(key, value, expected() + " of numbers") from None
        if isinstance(value, (str, bytes)) or arr.shape not in shapes:
            raise self.error(key, value, expected() + f" (got shape {arr.shape})")
        if abs(arr).max(initial=0.0) <= LARGEST:   # finite and not too large: the usual case
            return arr
        if not np.isfinite(arr).all():
            raise self.error(key, value, expected() + " of finite numbers")
        problem = magnitude_problem(arr)
        if problem:
            raise self.error(key, value, expected() + " of " + problem.removeprefix("a ").replace("number", "numbers"))
        return arr

    def vector3(self, key: str, default=None, *, required=False, nonzero=False) -> np.ndarray:
        vec = self.array(key, [(3,)], default, required=required)
        if nonzero and vec is not None and not np.linalg.norm(vec) > 0:
            raise self.error(key, self.data.get(key), "a 3-vector of non-zero length")
        return vec


#: names other codes and textbooks give a model file's keys (ROSS's ``E``, ``rho``, ``odl``, ``Ip``,
#: ``kxx``; a shaft's plain ``diameter``), too unlike them for a similarity of spelling to find:
#: the key meant, offered where the table has it (:func:`close_key`)
OTHER_NAMES = {
    "E": "young_modulus", "elastic_modulus": "young_modulus", "rho": "density", "G": "shear_modulus",
    "G_s": "shear_modulus", "nu": "poisson_ratio", "Poisson": "poisson_ratio", "poisson": "poisson_ratio",
    "L": "length", "diameter": "outer_diameter", "od": "outer_diameter", "odl": "outer_diameter",
    "odr": "outer_diameter", "id": "inner_diameter", "idl": "inner_diameter", "idr": "inner_diameter",
    "bore": "inner_diameter", "Ip": "polar_inertia", "Id": "diametral_inertia", "m": "mass",
    "n_elements": "elements", "element_size": "element_length", "kxx": "stiffness", "cxx": "damping",
}


def close_key(key, allowed) -> str | None:
    """The key of ``allowed`` that ``key`` is probably a typo of (``stifness`` -> ``'stiffness'``),
    or None: the closest by :func:`difflib.get_close_matches` at a similarity of 0.75 or more,
    else the key another code's name means (:data:`OTHER_NAMES`: ``E`` -> ``'young_modulus'``)
    where ``allowed`` has it.

    Parameters
    ----------
    key : str
        A key the table holds and ``allowed`` lacks.
    allowed : iterable of str
    """
    import difflib

    allowed = [str(a) for a in allowed]
    close = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.75)
    if close:
        return close[0]
    meant = OTHER_NAMES.get(str(key))
    return meant if meant in allowed else None


def unknown_key(key, allowed) -> str:
    """The end of an unknown key's message: ``" (unknown key)"``, with the allowed key it is
    probably a typo of (``stifness`` -> ``" (unknown key; did you mean 'stiffness'?)"``,
    :func:`close_key`)."""
    return did_you_mean(close_key(key, allowed))


def and_others(count: int, noun: str) -> str:
    """A warning's note of the ``count - 1`` others beside the one it names (``count`` found in
    all): ``" (and 2 other disks)"``, ``" (and 1 other point)"``, ``""`` for one."""
    return f" (and {count - 1} other {noun}{'s' if count > 2 else ''})" if count > 1 else ""


def did_you_mean(meant) -> str:
    """The end of an unknown key's message naming the key ``meant`` (None: not one)."""
    return f" (unknown key; did you mean {meant!r}?)" if meant is not None else " (unknown key)"


def non_number(value, deepest: int = 3) -> str | None:
    """What in a number or (nested) list of numbers is not a number, or None.

    A string (``"1e0"``), a boolean, a table or a missing value is never read as a number,
    wherever it sits: ``mass = "150"`` and ``spin_axis = ["1e0", "0", "0"]`` are refused
    alike. Lists nested deeper than ``deepest`` are left to the shape check.

    Returns
    -------
    str or None
        E.g. ``"[1] is the string '0', not a number"``.
    """
    if type(value) is list and all(type(v) is float or type(v) is int for v in value):
        return None                                  # the usual vector, at the cost of one pass
    stack = [("", value, 0)]
    while stack:
        where, item, depth = stack.pop()
        if isinstance(item, np.ndarray):
            if item.dtype.kind in "iuf":
                continue
            item = item.tolist()
        if isinstance(item, (list, tuple)):
            if depth < deepest:
                stack.extend((f"{where}[{i}]", v, depth + 1) for i, v in reversed(list(enumerate(item))))
            continue
        if isinstance(item, (int, float, np.integer, np.floating)) and not isinstance(item, (bool, np.bool_)):
            continue
        kind = {str: "the string", bool: "the boolean", np.bool_: "the boolean"}.get(type(item), "")
        shown = f"{kind} {item!r}" if kind else f"{item!r}"
        shown = f"{shown[:60]}..." if len(shown) > 63 else shown
        return f"{where + ' is ' if where else ''}{shown}, not a number"
    return None


def magnitude_problem(value, positive: bool = False) -> str:
    """What is wrong with the size of a finite number (or array), or '' when nothing is.

    Parameters
    ----------
    value : float or ndarray
    positive : bool
        The quantity must be > 0 (then it must also be at least :data:`SMALLEST_POSITIVE`).
    """
    scalar = isinstance(value, float)             # a plain float needs no numpy reduction
    if (abs(value) if scalar else float(np.max(np.abs(value), initial=0.0))) > LARGEST:
        return f"a number of magnitude at most {LARGEST:g} (SI units)"
    if positive and not (value if scalar else float(np.min(value))) >= SMALLEST_POSITIVE:
        return f"a number >= {SMALLEST_POSITIVE:g} (SI units)"
    return ""


def semidefinite_problem(matrix: np.ndarray) -> str:
    """What is wrong with a stiffness or damping matrix whose symmetric part has a negative
    eigenvalue, or '' when it is positive semidefinite (to round-off).

    The symmetric part is what stores (stiffness) or dissipates (damping) energy: negative, it
    is the negative value a scalar or a diagonal list is refused for. The antisymmetric part
    (cross-coupled stiffness of oil films and seals, gyroscopic-like terms) is free.

    Parameters
    ----------
    matrix : ndarray, shape (k, k)
    """
    symmetric = 0.5 * (matrix + matrix.T)
    lowest = float(np.linalg.eigvalsh(symmetric)[0])
    if lowest >= -1e-12 * float(np.abs(matrix).max(initial=0.0)):
        return ""
    return (f"a matrix whose symmetric part is positive semidefinite (its lowest eigenvalue is {lowest:.4g}: "
            "a negative stiffness or damping, refused as a negative scalar is; antisymmetric, "
            "cross-coupled terms are allowed)")


def visible(name) -> str:
    """A name or key as a message shows it: as it is when every character is visible, else
    quoted with the invisible ones escaped (``'mount\\u200b-FL'``, ``'fan\\xa0'``, ``' fan'``):
    a zero-width or non-breaking space, a control character, a space at either end; quoted too
    when it holds a comma (``'acc, top'``), which would read as two names in a list."""
    text = str(name)
    return text if text and text.isprintable() and text.strip() == text and "," not in text else repr(text)


def line_break_problem(text) -> str:
    """'' for a name or word that prints on one line; else what was expected: no control character
    (a tab, a line break, a NUL: category Cc) and no Unicode line or paragraph separator. Such a
    name breaks a table's columns or a message's one line, and reads as another name."""
    import unicodedata

    bad = [c for c in str(text) if unicodedata.category(c) in ("Cc", "Zl", "Zp")]
    if not bad:
        return ""
    return f"a text without control characters (it holds {', '.join(dict.fromkeys(repr(c) for c in bad))}: " \
           "a tab or a line break would split the tables and messages that print it)"


def visible_names(names) -> str:
    """``'motor, fan'``: names joined for a message, each :func:`visible`."""
    return ", ".join(visible(n) for n in names)


def shape_text(shape) -> str:
    """``'a number'``, ``'a 3-list'`` or ``'a 3x3 matrix'``."""
    if len(shape) == 0:
        return "a number"
    if len(shape) == 1:
        return f"a {shape[0]}-list"
    return f"a {shape[0]}x{shape[1]} matrix"


_SCALARS = (str, int, float, bool, type(None))


def plain(value):
    """``value`` in plain Python types: numpy arrays and scalars as lists and numbers, mappings as
    dicts with string keys, tuples as lists; every container a copy (a flat list copied flat)."""
    kind = type(value)
    if kind in _SCALARS:                       # the common case first: the ABC checks are slow
        return value
    if kind is dict:
        return {str(k): plain(v) for k, v in value.items()}
    if kind is list:
        if all(type(v) in _SCALARS for v in value):   # a vector: a flat copy will do
            return value.copy()
        return [plain(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value
