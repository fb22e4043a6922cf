"""Unit labels of measured files (``m/s^2``, ``g``, ``mm/s``, ``(1/N)*(m/s²)``): what they measure and
the factor to SI.

A label is read as a product of known units with integer powers: ``*`` (or ``·``, or a space)
multiplies, ``/`` divides (left to right: ``m/s/s`` is m s^-2), ``^n``, ``**n``, ``²``, ``³`` or
digits right after a unit (``m/s2``) raise to a power, ``1`` and parentheses group. Known units
(any case where that is unambiguous): length ``m``, ``cm``, ``mm``, ``um``/``µm``, ``in``,
``mil``, ``ft``; time ``s`` (``sec``), ``ms``, ``us``/``µs``, ``ns``, ``min``, ``h``; frequency ``Hz``,
``kHz``; velocity ``ips`` (in/s); acceleration of gravity ``g`` (standard,
9.80665 m/s^2); force ``N``, ``mN``, ``kN``, ``lbf``; mass ``kg``; pressure ``Pa``, ``hPa``, ``kPa``,
``MPa``, ``bar``, ``mbar``, ``psi``. A label of other units (``V``, ``mV/g``, ``dB``) is not
understood, never guessed.

The quantity follows from the dimension (metre, kilogram, second exponents): e.g. ``g`` and
``m/s2`` are accelerations, ``(1/N)*(m/s²)`` and ``g/lbf`` accelerances.
"""

from __future__ import annotations

import re

__all__ = ["STANDARD_GRAVITY", "QUANTITY_DIMENSIONS", "parse_unit", "quantity_of", "is_none"]

#: standard acceleration of gravity [m/s^2] (the unit ``g`` of accelerometers)
STANDARD_GRAVITY = 9.80665
_INCH = 0.0254
_POUND_FORCE = 0.45359237 * STANDARD_GRAVITY      # N (avoirdupois pound times standard gravity)

_LENGTH, _MASS, _TIME = (1, 0, 0), (0, 1, 0), (0, 0, 1)
_FORCE = (1, 1, -2)
_PRESSURE = (-1, 1, -2)
_ACCELERATION = (1, 0, -2)

#: unit -> (factor to SI, exponents of metre, kilogram, second)
_UNITS = {
    "m": (1.0, _LENGTH), "cm": (1e-2, _LENGTH), "mm": (1e-3, _LENGTH), "um": (1e-6, _LENGTH),
    "µm": (1e-6, _LENGTH), "μm": (1e-6, _LENGTH), "in": (_INCH, _LENGTH), "mil": (1e-3 * _INCH, _LENGTH),
    "mils": (1e-3 * _INCH, _LENGTH), "ft": (12 * _INCH, _LENGTH),
    "s": (1.0, _TIME), "sec": (1.0, _TIME), "ms": (1e-3, _TIME), "us": (1e-6, _TIME), "µs": (1e-6, _TIME),
    "μs": (1e-6, _TIME), "ns": (1e-9, _TIME), "min": (60.0, _TIME), "h": (3600.0, _TIME), "Hz": (1.0, (0, 0, -1)), "kHz": (1e3, (0, 0, -1)),
    "ips": (_INCH, (1, 0, -1)),
    "g": (STANDARD_GRAVITY, _ACCELERATION), "gn": (STANDARD_GRAVITY, _ACCELERATION),
    "N": (1.0, _FORCE), "mN": (1e-3, _FORCE), "kN": (1e3, _FORCE), "lbf": (_POUND_FORCE, _FORCE),
    "kg": (1.0, _MASS),
    "Pa": (1.0, _PRESSURE), "hPa": (1e2, _PRESSURE), "kPa": (1e3, _PRESSURE), "MPa": (1e6, _PRESSURE),
    "bar": (1e5, _PRESSURE), "mbar": (1e2, _PRESSURE), "psi": (_POUND_FORCE / _INCH ** 2, _PRESSURE),
}
# case-insensitive spellings (M/S^2, HZ, LBF); 'mN' and 'MPa' keep their case only
_FOLDED = {k.lower(): v for k, v in _UNITS.items() if k not in ("mN", "MPa")}

#: quantity -> exponents of metre, kilogram, second
QUANTITY_DIMENSIONS = {
    "displacement": _LENGTH, "velocity": (1, 0, -1), "acceleration": _ACCELERATION, "force": _FORCE,
    "pressure": _PRESSURE,
    "receptance": (0, -1, 2), "mobility": (0, -1, 1), "accelerance": (0, -1, 0),
}
_OF_DIMENSIONS = {v: k for k, v in QUANTITY_DIMENSIONS.items()}

_TOKEN = re.compile(r"\s*(\*\*|\^|[*/()·]|[²³]|[+-]?\d+|[A-Za-zµμ]+)")
_SUPERSCRIPT = {"²": 2, "³": 3}
_LARGEST_POWER = 4
_LONGEST = 80           # characters of a label (UFF: 20; deeper nesting is no unit)


def is_none(label) -> bool:
    """True for a label that gives no unit (``NONE``, empty)."""
    return str(label).strip().upper() in ("", "NONE")


def parse_unit(label):
    """Factor to SI and dimension of a unit label.

    Parameters
    ----------
    label : str

    Returns
    -------
    (float, tuple of int) or None
        SI value = file value x factor; exponents of metre, kilogram, second. None when the label
        is not understood (an unknown unit or a malformed expression).
    """
    tokens, text, at = [], str(label).strip(), 0
    if len(text) > _LONGEST:
        return None
    while at < len(text):
        found = _TOKEN.match(text, at)
        if not found:
            return None
        tokens.append(found.group(1))
        at = found.end()
        while at < len(text) and text[at].isspace():
            at += 1
    if not tokens:
        return None
    try:
        value, rest = _product(tokens)
    except (ValueError, IndexError, KeyError, ArithmeticError):
        return None
    return None if rest or not 0.0 < value[0] < float("inf") else value


def quantity_of(label):
    """``(quantity, factor to SI)`` of a unit label, or None when it is not understood or measures
    none of :data:`QUANTITY_DIMENSIONS`."""
    parsed = parse_unit(label)
    if parsed is None or parsed[1] not in _OF_DIMENSIONS:
        return None
    return _OF_DIMENSIONS[parsed[1]], parsed[0]


def _combine(a, b, power=1):
    return a[0] * b[0] ** power, tuple(x + power * y for x, y in zip(a[1], b[1]))


def _product(tokens):
    """expr := term (('*' | '·' | '/' | juxtaposition) term)*; returns (value, remaining tokens)."""
    value, tokens = _power(tokens)
    while tokens and tokens[0] != ")":
        op = tokens[0]
        if op in ("*", "·", "/"):
            tokens = tokens[1:]
        right, tokens = _power(tokens)
        value = _combine(value, right, -1 if op == "/" else 1)
    return value, tokens


def _power(tokens):
    """term := atom [('^' | '**') int | '²' | '³' | digits right after a unit]."""
    head = tokens[0]
    if head == "(":
        value, tokens = _product(tokens[1:])
        if not tokens or tokens[0] != ")":
            raise ValueError("unbalanced parenthesis")
        tokens = tokens[1:]
    elif head == "1":
        value, tokens = (1.0, (0, 0, 0)), tokens[1:]
    else:
        value = _UNITS.get(head) or _FOLDED[head.lower()]
        tokens = tokens[1:]
    if tokens and tokens[0] in ("^", "**"):
        exponent, tokens = int(tokens[1]), tokens[2:]
    elif tokens and tokens[0] in _SUPERSCRIPT:
        exponent, tokens = _SUPERSCRIPT[tokens[0]], tokens[1:]
    elif tokens and head not in ("(", "1") and re.fullmatch(r"\d+", tokens[0]):
        exponent, tokens = int(tokens[0]), tokens[1:]
    else:
        exponent = 1
    if abs(exponent) > _LARGEST_POWER:
        raise ValueError(f"power {exponent}")
    return (value[0] ** exponent, tuple(exponent * x for x in value[1])), tokens
