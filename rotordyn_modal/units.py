"""Unit conversions at the edge: SI (rad/s) inside, rpm and Hz for people."""

from __future__ import annotations

import numpy as np

__all__ = ["rpm", "to_rpm", "hz", "to_hz", "SPEED_UNITS", "speed_to_rad_s", "speed_from_rad_s"]

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
