"""LabVIEW TDMS time records through ``npTDMS`` (the ``tdms`` extra).

One group of a TDMS file is one record: every channel of the group must share its sampling
interval (``wf_increment``) and length. The channel's ``unit_string`` gives its quantity and
the factor to SI: ``N``, ``kN``, ``lbf`` (force), ``m``, ``mm``, ``um`` (displacement), ``m/s``,
``mm/s``, ``in/s`` (velocity), ``m/s^2``, ``g`` (9.80665 m/s^2; acceleration), ``Pa``, ``hPa``,
``bar`` (pressure), read by :mod:`.unit_labels`; ``units`` declares others or overrides,
e.g. ``units={"V": ("acceleration", 9.80665 / 0.1)}`` (quantity and factor to SI). A unit that
is neither (``V``, ``C``, ``°``) is refused.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .unit_labels import quantity_of

__all__ = ["read_tdms_records", "SI_UNITS"]

#: unit string -> (quantity, factor to SI)
SI_UNITS = {"N": ("force", 1.0), "m": ("displacement", 1.0), "m/s": ("velocity", 1.0),
            "m/s^2": ("acceleration", 1.0), "m/s²": ("acceleration", 1.0), "m/s2": ("acceleration", 1.0)}
_QUANTITIES = ("force", "displacement", "velocity", "acceleration", "pressure")


def _tdms_file(path):
    try:
        from nptdms import TdmsFile
    except ImportError:
        raise InputError(f"{path}: reading TDMS needs npTDMS: pip install 'rotordyn_modal[tdms]'") from None
    from .limits import check_size

    check_size(path, "measured", "measured-data file")
    try:
        return TdmsFile.read(str(path))
    except FileNotFoundError:
        raise InputError(f"{path}: TDMS file not found") from None
    except Exception as error:  # npTDMS raises ValueError, struct errors, ... on a damaged file
        raise InputError(f"{path}: not a readable TDMS file ({type(error).__name__}: {error})") from None


def read_tdms_records(path, group: str | None = None, channels=None, units=None, speed: float = 0.0):
    """Read one group of a TDMS file as one time record.

    Parameters
    ----------
    path : path-like
    group : str, optional
        Group name (default: the only group of the file).
    channels : list of str, optional
        Channels to read (default: every channel of the group).
    units : dict, optional
        More units: ``{unit_string: (quantity, factor to SI)}``.
    speed : float
        Reference rotor speed during the record [rad/s].

    Returns
    -------
    TimeRecords
        One record (``signals`` of shape (1, n_channels, n_samples)), SI units.
    """
    from ..analysis.spectra import TimeRecords

    tdms = _tdms_file(path)
    chosen = _group(tdms, group, path)
    known = {**SI_UNITS, **(units or {})}
    available = {c.name: c for c in chosen.channels()}
    names = list(available) if channels is None else list(channels)
    missing = [n for n in names if n not in available]
    if missing or not names:
        raise InputError(f"{path}: group {chosen.name!r} has no channel {', '.join(missing) or '(none)'}; its channels: "
                         f"{', '.join(available) or 'none'}")
    signals, quantities, steps = [], [], set()
    for name in names:
        channel = available[name]
        unit = str(channel.properties.get("unit_string", "")).strip()
        read = known.get(unit) or quantity_of(unit)
        if read is None or read[0] not in _QUANTITIES:
            raise InputError(f"{path}: channel {name!r} has unit {unit!r}: expected a unit of force, displacement, "
                             f"velocity, acceleration or pressure (e.g. {', '.join(SI_UNITS)}, g, mm/s), or declare "
                             f"it, e.g. units={{{unit!r}: ('acceleration', factor to SI)}}")
        quantity, factor = read
        signals.append(np.asarray(channel[:], dtype=float) * float(factor))
        quantities.append(quantity)
        steps.add(float(channel.properties.get("wf_increment", 0.0)))
    lengths = {len(s) for s in signals}
    if len(steps) != 1 or len(lengths) != 1 or not min(steps) > 0:
        raise InputError(f"{path}: channels of group {chosen.name!r} have sampling intervals {sorted(steps)} s and "
                         f"lengths {sorted(lengths)}: one record needs one interval (> 0) and one length")
    return TimeRecords(signals=np.stack(signals)[None], sampling_rate_hz=1.0 / steps.pop(), channels=tuple(names),
                       quantities=tuple(quantities), speed=float(speed))


def _group(tdms, name, path):
    groups = {g.name: g for g in tdms.groups()}
    if name is None and len(groups) == 1:
        return next(iter(groups.values()))
    if name not in groups:
        raise InputError(f"{path}: {'no group ' + repr(name) if name else 'several groups'}: give group= one of "
                         f"{', '.join(groups) or 'none'}")
    return groups[name]
