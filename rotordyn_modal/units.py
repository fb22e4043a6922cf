"""Unit conversions at the edge: SI (rad/s) inside, rpm and Hz for people, and the unit
systems (SI or US customary) that the command line and the figures show (docs/units.md)."""

from __future__ import annotations

import numpy as np

__all__ = ["rpm", "to_rpm", "hz", "to_hz", "SPEED_UNITS", "speed_to_rad_s", "speed_from_rad_s",
           "UNIT_SYSTEMS", "QUANTITIES", "unit_size", "unit_label", "unit_scale", "to_system", "from_system",
           "check_system", "ratio_scale", "FRF_OUTPUT_KINDS", "rpm_text"]

_RPM = np.pi / 30.0
_HZ = 2.0 * np.pi

#: factors from each speed unit to rad/s
SPEED_UNITS = {"rpm": _RPM, "rad/s": 1.0, "hz": _HZ}


def rpm(value):
    """Speed in rpm -> rad/s. ``rpm(3000)`` is 314.159..."""
    return np.asarray(value, dtype=float) * _RPM if np.ndim(value) else float(value) * _RPM


def to_rpm(value):
    """Speed in rad/s -> rpm."""
    return np.asarray(value, dtype=float) / _RPM if np.ndim(value) else float(value) / _RPM


def rpm_text(speed) -> str:
    """A speed [rpm] as text for a sentence, title, label or legend, without its unit: whole rpm
    from 99.5 rpm up (as the report and the figures always wrote it), else to 3 significant
    digits (``5.75``, ``0.0573``), so that a slow machine's 5.75 rpm is not written "6 rpm".
    0, inf and nan as whole numbers."""
    import math

    speed = float(speed)
    if not np.isfinite(speed) or abs(speed) >= 99.5 or speed == 0.0:
        return f"{speed:.0f}"
    return f"{speed:.{max(0, 2 - math.floor(math.log10(abs(speed))))}f}"


def hz(value):
    """Frequency (or speed in rev/s) in Hz -> rad/s."""
    return np.asarray(value, dtype=float) * _HZ if np.ndim(value) else float(value) * _HZ


def to_hz(value):
    """rad/s -> Hz."""
    return np.asarray(value, dtype=float) / _HZ if np.ndim(value) else float(value) / _HZ


def speed_to_rad_s(value, unit: str):
    """Convert speeds given in ``unit`` ('rpm', 'rad/s' or 'hz', any case) to rad/s."""
    return np.asarray(value, dtype=float) * _factor(unit)


def speed_from_rad_s(value, unit: str):
    """Convert speeds in rad/s to ``unit``."""
    return np.asarray(value, dtype=float) / _factor(unit)


def _factor(unit: str) -> float:
    factor = SPEED_UNITS.get(str(unit).lower())
    if factor is None:
        from .errors import InputError

        raise InputError(f"speed unit {unit!r}: expected one of {', '.join(SPEED_UNITS)}")
    return factor


# --- unit systems: SI or US customary, for what people read and type (SI inside) ----------------

#: exact definitions (NIST SP 811, appendix B): inch, avoirdupois pound, standard gravity
INCH = 0.0254                       # m
POUND = 0.45359237                  # kg
STANDARD_GRAVITY = 9.80665          # m/s^2
POUND_FORCE = POUND * STANDARD_GRAVITY   # N
OUNCE = POUND / 16.0                # kg
HORSEPOWER = 550.0 * 12.0 * INCH * POUND_FORCE   # W: 550 ft lbf/s (mechanical horsepower)

#: the unit systems, by the name given to ``--units``
UNIT_SYSTEMS = ("si", "us")

#: quantity kind -> {system: (label, size of one such unit in the SI unit of the kind)}; a value in
#: SI divided by the size is the number shown. The SI unit of each kind is the one used inside
#: the package, except ``unbalance`` (kg m inside, g mm shown), ``frequency`` (Hz) and ``speed``
#: (rpm), which are the same in both systems.
QUANTITIES = {
    "length": {"si": ("m", 1.0), "us": ("in", INCH)},
    "displacement": {"si": ("m", 1.0), "us": ("mil", INCH / 1000.0)},   # vibration amplitude
    "velocity": {"si": ("m/s", 1.0), "us": ("in/s", INCH)},
    "acceleration": {"si": ("m/s²", 1.0), "us": ("g", STANDARD_GRAVITY)},
    "force": {"si": ("N", 1.0), "us": ("lbf", POUND_FORCE)},
    "moment": {"si": ("N m", 1.0), "us": ("lbf in", POUND_FORCE * INCH)},
    "stiffness": {"si": ("N/m", 1.0), "us": ("lbf/in", POUND_FORCE / INCH)},
    "damping": {"si": ("N s/m", 1.0), "us": ("lbf s/in", POUND_FORCE / INCH)},
    "mass": {"si": ("kg", 1.0), "us": ("lb", POUND)},
    "inertia": {"si": ("kg m²", 1.0), "us": ("lb in²", POUND * INCH ** 2)},
    "unbalance": {"si": ("g mm", 1e-6), "us": ("oz in", OUNCE * INCH)},
    "pressure": {"si": ("Pa", 1.0), "us": ("psi", POUND_FORCE / INCH ** 2)},
    "viscosity": {"si": ("Pa s", 1.0), "us": ("reyn", POUND_FORCE / INCH ** 2)},
    "power": {"si": ("W", 1.0), "us": ("hp", HORSEPOWER)},
    "frequency": {"si": ("Hz", 1.0), "us": ("Hz", 1.0)},
    "speed": {"si": ("rpm", 1.0), "us": ("rpm", 1.0)},
    "angle": {"si": ("rad", 1.0), "us": ("rad", 1.0)},
    "density": {"si": ("kg/m³", 1.0), "us": ("lb/ft³", POUND / (12.0 * INCH) ** 3)},
}


def check_system(system: str) -> str:
    """``system`` in lower case if it is one of :data:`UNIT_SYSTEMS`.

    Raises
    ------
    InputError
    """
    name = str(system).strip().lower()
    if name not in UNIT_SYSTEMS:
        from .errors import InputError

        raise InputError(f"unit system {system!r}: expected one of {', '.join(UNIT_SYSTEMS)}")
    return name


def _entry(kind: str, system: str):
    try:
        table = QUANTITIES[kind]
    except KeyError:
        raise ValueError(f"quantity kind {kind!r}: expected one of {', '.join(QUANTITIES)}") from None
    return table[check_system(system)]


def unit_size(kind: str, system: str) -> float:
    """Size of the unit of ``kind`` in ``system``, in the SI unit of that kind (``unit_size('length',
    'us')`` is 0.0254: one inch in metres)."""
    return _entry(kind, system)[1]


def unit_label(kind: str, system: str) -> str:
    """The unit of ``kind`` in ``system`` as written on axes and in tables (``'lbf/in'``)."""
    return _entry(kind, system)[0]


def unit_scale(kind: str, system: str = "si") -> tuple:
    """``(factor, label)``: a value of ``kind`` in SI times ``factor`` is the number in ``label``,
    the unit of ``system``: the figures' presentation scale (plotting computes nothing else)."""
    label, size = _entry(kind, system)
    return 1.0 / size, label


def to_system(value, kind: str, system: str):
    """SI values of ``kind`` -> numbers in the unit of ``system`` (float or array, as given)."""
    size = unit_size(kind, system)
    return np.asarray(value, dtype=float) / size if np.ndim(value) else float(value) / size


def from_system(value, kind: str, system: str):
    """Numbers in the unit of ``system`` -> SI values of ``kind`` (the inverse of :func:`to_system`)."""
    size = unit_size(kind, system)
    return np.asarray(value, dtype=float) * size if np.ndim(value) else float(value) * size


#: quantity kind of an FRF's output, by the FRF's quantity (a force FRF's moment rows: 'moment')
FRF_OUTPUT_KINDS = {"receptance": "length", "mobility": "velocity", "accelerance": "acceleration", "force": "force"}


def ratio_scale(numerator: str, denominator: str, system: str = "si") -> tuple:
    """``(factor, label)`` of a ratio of two kinds (an FRF: ``('length', 'force')`` -> in/lbf in US
    units): an SI ratio times ``factor`` is the number in ``label``."""
    (top, top_label), (bottom, bottom_label) = unit_scale(numerator, system), unit_scale(denominator, system)
    return top / bottom, f"{top_label}/{bottom_label}"
