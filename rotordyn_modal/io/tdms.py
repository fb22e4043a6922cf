"""LabVIEW TDMS time records through ``npTDMS`` (the ``tdms`` extra).

One group of a TDMS file is one record: every channel of the group must share its sampling
interval (``wf_increment``) and length. The channel's ``unit_string`` gives its quantity and
the factor to SI: ``N``, ``kN``, ``lbf`` (force), ``m``, ``mm``, ``um`` (displacement), ``m/s``,
``mm/s``, ``in/s`` (velocity), ``m/s^2``, ``g`` (9.80665 m/s^2; acceleration), ``Pa``, ``hPa``,
``bar`` (pressure), read by :mod:`.unit_labels`; ``units`` declares others or overrides,
e.g. ``units={"V": ("acceleration", 9.80665 / 0.1)}`` (quantity and factor to SI). A unit that
is neither (``V``, ``C``, ``°``) is refused. The interval is in the unit of ``wf_xunit_string``
(``s``, ``ms``, ``us``, ``min``, ``h``: a time unit of :mod:`.unit_labels`; seconds without one).
Refused too: text or complex samples, a NaN or infinite sample, a channel of fewer than 2 samples, a declared unit of no time-record quantity or of a
factor 0.
"""

from __future__ import annotations

import contextlib

import numpy as np

from ..errors import InputError
from ..model._table import LARGEST, line_break_problem, visible, visible_names
from .limits import reads_pipes
from .unit_labels import quantity_of

__all__ = ["read_tdms_records", "SI_UNITS", "declared_units"]

#: unit string -> (quantity, factor to SI)
SI_UNITS = {"N": ("force", 1.0), "m": ("displacement", 1.0), "m/s": ("velocity", 1.0),
            "m/s^2": ("acceleration", 1.0), "m/s²": ("acceleration", 1.0), "m/s2": ("acceleration", 1.0)}
_QUANTITIES = ("force", "displacement", "velocity", "acceleration", "pressure")


def _tdms_file(path):
    try:
        from nptdms import TdmsFile
    except ImportError:
        raise InputError(f"{path}: reading TDMS needs npTDMS: pip install 'rotordyn_modal[tdms]'") from None
    from .limits import check_size, refuse_unsized

    check_size(path, "measured", "measured-data file")
    refuse_unsized(path, "a TDMS file")   # a pipe no program writes to blocked npTDMS for ever
    tdms, said = _read(TdmsFile, path, path)
    if any("less data" in line or "chunk size" in line for line in said):
        return _complete_segments(TdmsFile, said, path)
    _check_complete(tdms, said, path)
    return tdms


def _read(TdmsFile, name, path):
    """``(tdms, said)``: the file ``name`` read whole by npTDMS and the warnings it logged;
    whatever npTDMS raises is one ``InputError`` naming ``path``."""
    try:
        with _npTDMS_said() as said:
            tdms = TdmsFile.read(str(name))
    except FileNotFoundError:
        raise InputError(f"{path}: TDMS file not found") from None
    except Exception as error:  # npTDMS raises ValueError, struct errors, ... on a damaged file
        raise InputError(f"{path}: not a readable TDMS file ({type(error).__name__}: {error})") from None
    return tdms, said


def _complete_segments(TdmsFile, said, path):
    """The file cut short inside its last segment's data read up to the end of its last complete
    segment (from a copy of those bytes in a temporary folder; the file itself is never changed),
    with one warning line saying how many samples a channel were kept. npTDMS read the cut
    segment's partial data to channels of different lengths. Refused when no segment before the
    cut one is complete."""
    import tempfile
    import warnings
    from pathlib import Path

    end = _complete_end(path)
    if end == 0:
        raise InputError(f"{path}: the file is cut short inside its first segment's data (npTDMS: {said[0]}): no "
                         "complete segment to read; expected a complete TDMS file (a recording stopped while "
                         "writing, or a copy cut off)")
    with open(path, "rb") as handle:
        data = handle.read(end)
    with tempfile.TemporaryDirectory() as folder:
        copy = Path(folder) / "complete.tdms"
        copy.write_bytes(data)
        kept, again = _read(TdmsFile, copy, path)
    if again or not list(kept.groups()):   # the lead-ins walked wrongly: say the first refusal
        raise InputError(f"{path}: the file is cut short inside its last segment's data (npTDMS: {said[0]}): "
                         "expected a complete TDMS file (a recording stopped while writing, or a copy cut off)")
    lengths = sorted({len(c) for g in kept.groups() for c in g.channels()})
    warnings.warn(f"{path}: the file is cut short inside its last segment's data (npTDMS: {said[0]}): left out, "
                  f"the complete segments before it read ({'/'.join(map(str, lengths))} samples a channel)",
                  stacklevel=4)
    return kept


def _complete_end(path) -> int:
    """The byte offset where the last complete segment of a TDMS file ends (0: none is). Each
    segment opens with a 28-byte lead-in: ``TDSm``, the table-of-contents mask (bit 14 big
    endian), the version, then the offset of the next segment from the end of this lead-in (all
    ones: a segment LabVIEW never closed)."""
    import os
    import struct

    size, end = os.path.getsize(path), 0
    with open(path, "rb") as handle:
        while True:
            handle.seek(end)
            lead = handle.read(28)
            if len(lead) < 28 or lead[:4] != b"TDSm":
                return end
            order = ">" if struct.unpack("<l", lead[4:8])[0] & (1 << 14) else "<"
            offset = struct.unpack(order + "Q", lead[12:20])[0]
            following = end + 28 + offset
            if offset == 0xFFFFFFFFFFFFFFFF or following > size:
                return end
            end = following


@contextlib.contextmanager
def _npTDMS_said():
    """The warnings npTDMS logs while it reads (a file cut short: 'Last segment metadata is
    incomplete', '... less data than expected'), kept from the terminal and collected in the
    list this yields: :func:`_check_complete` says them in one line."""
    import logging

    said: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record):
            said.append(record.getMessage())

    # npTDMS gives each of its modules' loggers a handler printing to stderr (nptdms/log.py)
    names = ["nptdms", *(name for name in logging.Logger.manager.loggerDict if name.startswith("nptdms."))]
    loggers = [logging.getLogger(name) for name in names]
    saved = [(logger.handlers[:], logger.propagate) for logger in loggers]
    handler = Keep(logging.WARNING)
    for logger in loggers:
        logger.handlers, logger.propagate = [handler], False
    try:
        yield said
    finally:
        for logger, (handlers, propagate) in zip(loggers, saved):
            logger.handlers, logger.propagate = handlers, propagate


def _check_complete(tdms, said, path) -> None:
    """Refuse a TDMS file cut short in its first segment's metadata; warn, in one line, of one cut
    in a later segment's metadata (npTDMS leaves that segment out: the complete ones are read).
    A cut inside a segment's data is :func:`_complete_segments`'s."""
    if not said:
        return
    groups = list(tdms.groups())
    if any("incomplete" in line for line in said):
        if not groups:
            raise InputError(f"{path}: the file is cut short in its first segment (npTDMS: {said[0]}): no channel "
                             "can be read; expected a complete TDMS file")
        import warnings

        lengths = sorted({len(c) for g in groups for c in g.channels()})
        warnings.warn(f"{path}: the file is cut short in its last segment (npTDMS: {said[0]}): left out, the "
                      f"complete segments before it read ({'/'.join(map(str, lengths))} samples a channel)",
                      stacklevel=4)


@reads_pipes(".tdms", "TDMS file")
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

    known = {**SI_UNITS, **declared_units(units, path)}
    tdms = _tdms_file(path)
    chosen = _group(tdms, group, path)
    available = {c.name: c for c in chosen.channels()}
    names = list(available) if channels is None else [channels] if isinstance(channels, str) else list(channels)
    missing = [n for n in names if n not in available]
    if missing or not names:
        raise InputError(f"{path}: group {chosen.name!r} has no channel {visible_names(missing) or '(none)'}; its "
                         f"channels: {visible_names(available) or 'none'}")
    broken = next((n for n in names if line_break_problem(n)), None)
    if broken is not None:   # a tab or line break splits the spectra's tables and figure legends
        raise InputError(f"{path}: channel name {broken!r}: expected {line_break_problem(broken)}")
    if channels is None:
        names = _measured_channels(available, names, known, path)
    twice = [n for i, n in enumerate(names) if n in names[:i]]
    if twice:   # the same samples read as two channels, without a word
        raise InputError(f"{path}: channels = {visible_names(names)}: expected each channel once ({visible(twice[0])} "
                         "is asked for twice)")
    try:
        given, speed = speed, float(speed)
    except (TypeError, ValueError):
        given, speed = speed, float("nan")
    if not np.isfinite(speed) or abs(speed) > LARGEST:
        raise InputError(f"{path}: speed = {given!r}: expected a finite speed [rad/s] of magnitude at most {LARGEST:g}")
    signals, quantities, steps = [], [], set()
    for name in names:
        channel = available[name]
        unit = str(channel.properties.get("unit_string", "")).strip()
        read = known.get(unit) or quantity_of(unit)
        if read is None or read[0] not in _QUANTITIES:
            raise InputError(f"{path}: channel {name!r} has unit {unit!r}: expected a unit of force, displacement, "
                             f"velocity, acceleration or pressure (e.g. {', '.join(SI_UNITS)}, g, mm/s), or declare "
                             f"it, e.g. units={{{unit!r}: ('acceleration', factor to SI)}}"
                             + (", or read the others only: channels=[...]" if channels is None and len(names) > 1
                                else ""))
        quantity, factor = read
        signals.append(_samples(channel, path) * float(factor))
        quantities.append(quantity)
        steps.add(_increment(channel, path))
    lengths = {len(s) for s in signals}
    if len(steps) != 1 or len(lengths) != 1 or not min(steps) > 0:
        raise InputError(f"{path}: channels of group {chosen.name!r} have sampling intervals {sorted(steps)} s and "
                         f"lengths {sorted(lengths)}: one record needs one interval (> 0) and one length")
    step = steps.copy().pop()
    if not (np.isfinite(1.0 / step) and step <= LARGEST):   # 1e-320 s read as an infinite sampling rate
        raise InputError(f"{path}: channels of group {chosen.name!r} have the sampling interval {step:g} s: expected "
                         f"an interval whose rate 1 / interval is finite, at most {LARGEST:g} s")
    if min(lengths) < 2:
        raise InputError(f"{path}: the channels of group {chosen.name!r} hold {min(lengths)} sample(s): expected a "
                         "time record of at least 2 samples")
    return TimeRecords(signals=np.stack(signals)[None], sampling_rate_hz=1.0 / steps.pop(), channels=tuple(names),
                       quantities=tuple(quantities), speed=float(speed))


#: units of a group's channels that are no measurement of the record: its time axis, a tachometer's
#: speed, an angle (LabVIEW exports write a ``Time`` channel in s beside the signals)
_AXIS_UNITS = {"rpm": "a speed", "rev/min": "a speed", "r/min": "a speed", "1/min": "a speed", "hz": "a frequency",
               "deg": "an angle", "°": "an angle", "degree": "an angle", "degrees": "an angle", "rad": "an angle"}


def _axis_word(unit: str):
    """What a channel of ``unit`` is when it is no measurement (``'a time axis'``), else None."""
    from .unit_labels import parse_unit

    parsed = parse_unit(unit)
    if parsed is not None and tuple(parsed[1]) == (0, 0, 1):
        return "a time axis"
    return _AXIS_UNITS.get(unit.strip().lower())


def _measured_channels(available, names, known, path) -> list:
    """``names`` (every channel of the group) without the channels of a time axis, speed or
    angle, left out with a warning naming them (was: the whole group refused by the first); all
    of them when nothing else is left (refused then by the unit check)."""
    import warnings

    axes = {}
    for name in names:
        unit = str(available[name].properties.get("unit_string", "")).strip()
        if not (known.get(unit) or quantity_of(unit)) and _axis_word(unit):
            axes[name] = f"{name!r} ({unit}: {_axis_word(unit)})"
    kept = [n for n in names if n not in axes]
    if not axes or not kept:
        return names
    warnings.warn(f"{path}: read the channels {visible_names(kept)}; left out {', '.join(axes.values())}, no "
                  "measurement of the record (channels= chooses them)", stacklevel=3)
    return kept


def declared_units(units, path) -> dict:
    """``units`` checked: ``{unit_string: (quantity, factor to SI)}`` with a quantity of a time
    record and a finite factor other than 0 (a factor of 0 would read every sample as 0)."""
    if units is None:
        return {}
    if not isinstance(units, dict):
        raise InputError(f"{path}: units = {units!r}: expected a dict {{unit_string: (quantity, factor to SI)}}")
    for unit, read in units.items():
        try:
            quantity, factor = read
            factor = float(factor)
        except (TypeError, ValueError):
            quantity, factor = None, float("nan")
        if quantity not in _QUANTITIES or not np.isfinite(factor) or factor == 0:
            raise InputError(f"{path}: units[{unit!r}] = {read!r}: expected (quantity, factor to SI) with a quantity "
                             f"of {', '.join(_QUANTITIES)} and a finite factor other than 0")
    return dict(units)


def _samples(channel, path) -> np.ndarray:
    """A channel's samples as floats; text, complex or non-finite samples are refused."""
    data = np.asarray(channel[:])
    if data.dtype.kind not in "biuf":
        raise InputError(f"{path}: channel {channel.name!r} holds {data.dtype} data: expected real numbers "
                         "(a time record)")
    data = data.astype(float)
    if not np.all(np.isfinite(data)):
        bad = int(np.argmax(~np.isfinite(data)))
        raise InputError(f"{path}: channel {channel.name!r} sample {bad} is {data[bad]}: expected finite samples")
    if np.any(np.abs(data) > LARGEST):   # 1e300 was read, its spectra infinite
        bad = int(np.argmax(np.abs(data) > LARGEST))
        raise InputError(f"{path}: channel {channel.name!r} sample {bad} is {data[bad]:g}: expected samples of "
                         f"magnitude at most {LARGEST:g}")
    return data


def _increment(channel, path) -> float:
    """A channel's sampling interval [s]: ``wf_increment`` in the unit of ``wf_xunit_string``
    (seconds when it says none)."""
    from .unit_labels import is_none, parse_unit

    if "wf_increment" not in channel.properties:     # was "sampling intervals [0.0] s": a value not in the file
        raise InputError(f"{path}: channel {channel.name!r} has no wf_increment property (its sampling interval): "
                         "expected a waveform channel, as NI DAQmx and LabVIEW write them")
    try:
        step = float(channel.properties.get("wf_increment", 0.0))
    except (TypeError, ValueError):
        step = float("nan")
    unit = str(channel.properties.get("wf_xunit_string", "s")).strip()
    if is_none(unit):
        return step
    parsed = parse_unit(unit)
    if parsed is None or parsed[1] != (0, 0, 1):
        raise InputError(f"{path}: channel {channel.name!r} has the time unit wf_xunit_string = {unit!r}: expected "
                         "a unit of time such as s, ms, us, min or h (a time record)")
    return step * parsed[0]


def _group(tdms, name, path):
    """The group asked for; without a name the file's only group, or its only group holding a
    waveform (a channel of 2 samples or more) beside groups of single values (NI InsightCM writes
    a ``Static`` group of one temperature beside its ``Waveform`` group), with a warning naming
    the others."""
    groups = {g.name: g for g in tdms.groups()}
    if name is None and len(groups) == 1:
        return next(iter(groups.values()))
    if not groups:     # an empty file (or /dev/null) was "several groups: give group= one of none"
        raise InputError(f"{path}: no group of channels in the file: expected a TDMS file holding a time record")
    waveforms = [g for g in groups.values() if any(len(c) >= 2 for c in g.channels())]
    if name is None and len(waveforms) == 1:
        import warnings

        def held(group):
            return ", ".join(f"channel {c.name!r}: {len(c)} samples" for c in group.channels()) or "no channel"

        others = ", ".join(f"{g!r} ({held(groups[g])})" for g in groups if g != waveforms[0].name)
        warnings.warn(f"{path}: read group {waveforms[0].name!r}, the only one holding waveforms; skipped the groups "
                      f"of fewer than 2 samples a channel: {others}", stacklevel=3)
        return waveforms[0]
    if name not in groups:
        raise InputError(f"{path}: {'no group ' + repr(name) if name else 'several groups'}: give group= one of "
                         f"{', '.join(groups)}")
    return groups[name]
