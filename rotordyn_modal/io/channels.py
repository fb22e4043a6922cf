"""Channels of measured data: which file channel is which sensor or excitation of the model,
and the grouping of measured FRF lines into model-named FRF sets.

Mapping table (CSV ``name,node,direction[,sign]``): which UFF node and direction code
(1/2/3 = +X/+Y/+Z, negative for minus, 4-6 rotations, 0 a scalar channel without direction,
as some tools write) is which sensor or excitation of the model; ``sign`` -1 flips a channel.
A sensor and an excitation may share a node and direction (a driving-point FRF). Without a
table the default mapping is used: sensor k (from 1) is node k, excitation k is node 100 + k,
and the direction code is the model axis nearest to the channel's direction (signed; a channel
along no axis is listed in ``ChannelMap.oblique`` and not written to UFF).
"""

from __future__ import annotations

import numpy as np

from ..analysis.frf import FRFResult
from ..errors import InputError
from ..model._table import visible, visible_names

__all__ = ["ChannelMap", "default_mapping", "read_mapping", "assemble"]


class ChannelMap:
    """``(node, direction) -> (name, sign)`` for outputs (sensors) and inputs (excitations).

    Attributes
    ----------
    outputs, inputs : dict[tuple[int, int], tuple[str, float]]
    oblique : dict[str, tuple of float]
        Channels the default mapping gave the nearest axis code although they measure along no
        model axis: name -> direction. A UFF 58 file cannot say such a direction (it is not written).
    twice : dict[str, tuple]
        Driving points given two rows of a mapping table: name -> (the table's path,
        [(line, (node, direction)), ...]); both read as the channel, but a UFF file written needs one.
    source : path-like or None
        The mapping table read (None: the default mapping), for messages.
    """

    def __init__(self, outputs, inputs, oblique=None, twice=None, source=None):
        self.outputs = dict(outputs)
        self.inputs = dict(inputs)
        self.oblique = dict(oblique or {})
        self.twice = dict(twice or {})
        self.source = source

    def node_of(self, name):
        """``(node, direction, sign)`` of a sensor or excitation name."""
        for table in (self.outputs, self.inputs):
            for (node, direction), (n, sign) in table.items():
                if n == name:
                    return node, direction, sign
        where = f"{self.source}: " if self.source else ""
        raise InputError(f"{where}channel {visible(name)} is not in the mapping table: expected a row "
                         "name,node,direction for it")


def _axis_code(direction, rotation: bool = False) -> int:
    d = np.asarray(direction, dtype=float)
    k = int(np.argmax(np.abs(d)))
    return (k + 1 + 3 * rotation) * (1 if d[k] > 0 else -1)


def default_mapping(model) -> ChannelMap:
    """Sensor k -> node k, excitation k -> node 100 + k; direction = nearest signed model axis
    (a channel along no axis is listed in ``oblique``)."""
    outputs = {(k + 1, _axis_code(s.direction)): (s.name, 1.0) for k, s in enumerate(model.sensors)}
    inputs = {(101 + k, _axis_code(x.direction, x.kind == "moment")): (x.name, 1.0)
              for k, x in enumerate(model.excitations)}
    oblique = {c.name: tuple(float(v) for v in c.direction) for c in (*model.sensors, *model.excitations)
               if not _along_an_axis(c.direction)}
    return ChannelMap(outputs, inputs, oblique)


def _along_an_axis(direction) -> bool:
    """True when a direction is a model axis (to 1e-12 of its length)."""
    d = np.abs(np.asarray(direction, dtype=float))
    return bool(d.max() >= (1.0 - 1e-12) * np.linalg.norm(d))


def read_mapping(path, model) -> ChannelMap:
    """Read a mapping table ``name,node,direction[,sign]`` (CSV) against the model's channel names."""
    from .csv_tables import read_csv_table, split_header
    from .limits import read_limited, unreadable

    try:
        data = read_limited(path, "model", "mapping table")  # a pipe too, bounded
    except OSError as error:
        raise unreadable(path, "mapping table", error) from None
    table, _ = read_csv_table(data, path, "the mapping table")   # ';' or tabs, names as written
    table.columns = [split_header(c)[0] for c in table.columns]
    unknown_columns([c for c in table.columns if c not in _MAPPING_COLUMNS], _MAPPING_COLUMNS, path,
                    "name,node,direction[,sign]")
    missing = {"name", "node", "direction"} - set(table.columns)
    if missing:
        raise InputError(f"{path}: mapping table lacks the column(s) {', '.join(sorted(missing))}: "
                         "expected name,node,direction[,sign]")
    if table.empty:   # a header alone: every channel was then 'not in the mapping table' of the data file
        raise InputError(f"{path}: mapping table has no rows: expected one row name,node,direction per channel")
    sensors, excitations = {s.name for s in model.sensors}, {x.name for x in model.excitations}
    outputs, inputs = {}, {}
    given = {}          # name -> (line, key) of its first row
    for line, row in zip(table.attrs["lines"], table.itertuples(index=False)):
        key, sign = _mapping_row(row, "sign" in table.columns, path, line)
        _check_one_node(given, row.name, key, line, path, both=row.name in sensors and row.name in excitations)
        # a name that is a sensor's and an excitation's (a driving point named once) maps both
        roles = [role for role, names in ((outputs, sensors), (inputs, excitations)) if row.name in names]
        if not roles:
            raise InputError(f"{path}: line {line}: name {row.name!r} is neither a sensor "
                             f"({visible_names(sorted(sensors))}) nor an excitation "
                             f"({visible_names(sorted(excitations))}) of the model")
        for role in roles:
            if key in role:   # a response and a reference may share a node and direction (a driving point)
                raise InputError(f"{path}: line {line}: node {key[0]} direction {key[1]} is given to "
                                 f"{role[key][0]!r} already: expected each node and direction once among the "
                                 f"{'sensors' if role is outputs else 'excitations'}")
            role[key] = (row.name, sign)
    unread_columns([c for c in table.columns if c not in _MAPPING_COLUMNS], path, "name,node,direction[,sign]")
    return ChannelMap(outputs, inputs, twice={name: (path, rows) for name, rows in given.items() if len(rows) > 1},
                      source=path)


#: the columns of a mapping table
_MAPPING_COLUMNS = ("name", "node", "direction", "sign")


def unknown_columns(columns, known, path, layout: str) -> None:
    """Refuse a column of a table that its reader does not read (``columns``, header names as
    read) when it is a near miss of a ``known`` name (``quantitiy``, ``sing``, ``coherance``),
    naming the name meant: its data were dropped without a word (a mobility read as the default
    receptance, a sign of -1 lost). Others are named by :func:`unread_columns` once the table is
    read.

    Raises
    ------
    InputError
    """
    import difflib

    for column in columns:
        close = difflib.get_close_matches(str(column), known, n=1, cutoff=0.75)
        if close:
            raise InputError(f"{path}: column {visible(str(column))!r} is not a column of the layout "
                             f"({layout}): did you mean {close[0]!r}?")


def unread_columns(columns, path, layout: str) -> None:
    """One warning line naming the columns of a table read that its reader passed over (a
    comment, a tool's own column): after the table's refusals, so that a refused file gets one line."""
    import warnings

    if columns:
        warnings.warn(f"{path}: column(s) {visible_names(map(str, columns))} not read (the columns read are "
                      f"{layout})", stacklevel=3)


def _check_one_node(given, name, key, line, path, both):
    """Refuse a second node and direction for a name (the first was taken silently when writing
    UFF), except one second row of a name that is a sensor and an excitation (a driving point
    whose response and reference a file numbers apart); ``given[name]``: its rows' (line, key)."""
    rows = given.setdefault(name, [])
    if rows and (not both or len(rows) > 1):
        first_line, (node, direction) = rows[0]
        raise InputError(f"{path}: line {line}: name {name!r} is given node {key[0]} direction {key[1]} here and "
                         f"node {node} direction {direction} on line {first_line}: expected one node and direction "
                         "per name" + (" (two for a driving point: its response and its reference)" if both else ""))
    rows.append((line, key))


#: largest node number of a UFF 58 record (a 10-character integer field, a 32-bit integer in readers)
_LARGEST_NODE = 2**31 - 1


#: directions as other tools' channel tables write them (LMS, m+p, Siemens: ``+Z``, ``Y-``, ``-RX``):
#: the UFF codes +-1 .. +-6
_LETTERS = {f"{a}{axis}{b}": sign * code for code, axis in enumerate(("X", "Y", "Z", "RX", "RY", "RZ"), start=1)
            for sign, (a, b) in ((1, ("", "")), (1, ("+", "")), (1, ("", "+")), (-1, ("-", "")), (-1, ("", "-")))}


def _is_number(value) -> bool:
    try:
        float(value)
    except (TypeError, ValueError):
        return False
    return True


def _mapping_row(row, has_sign, path, line):
    """``((node, direction), sign)`` of one row of a mapping table, or a refusal naming the line."""
    def whole(name):
        value = getattr(row, name)
        try:   # float() reads '1_0' as 10: a digit separator no channel table writes, refused
            number = float("nan") if "_" in str(value) else float(value)
        except (TypeError, ValueError):
            number = float("nan")
        if not np.isfinite(number) or number != int(number):
            raise InputError(f"{path}: line {line}: {name} = {value!r}: expected a whole number"
                             + (" or X, Y, Z, RX, RY, RZ with a sign (+Z, Y-)" if name == "direction" else ""))
        return int(number)

    node = whole("node")
    direction = _LETTERS.get(str(row.direction).strip().upper().replace(" ", "")) if not _is_number(row.direction) \
        else None
    direction = whole("direction") if direction is None else direction
    if not abs(node) <= _LARGEST_NODE:
        raise InputError(f"{path}: line {line}: node = {row.node!r}: expected a UFF node number of at most "
                         f"{_LARGEST_NODE} (its 10-character field)")
    if not abs(direction) <= 6:
        raise InputError(f"{path}: line {line}: direction = {direction}: expected a UFF direction code "
                         "+-1 .. +-6 (X, Y, Z, then rotations), or 0 (a scalar channel, no direction)")
    if not has_sign:
        return (node, direction), 1.0
    try:
        sign = float(row.sign)
    except (TypeError, ValueError):
        sign = float("nan")
    if sign not in (1.0, -1.0):
        raise InputError(f"{path}: line {line}: sign = {row.sign!r}: expected 1 or -1")
    return (node, direction), sign


def assemble(records, model, quantity, source) -> list[FRFResult]:
    """Group measured lines into one FRF set per speed.

    Parameters
    ----------
    records : dict of arrays, each shape (n_lines,)
        ``speed_rpm``, ``frequency_hz``, ``output``, ``input`` (names), ``value`` (complex) and
        ``coherence`` (or None).
    model : Model
    quantity : str
    source : str
        File name, for messages.

    Returns
    -------
    list of FRFResult, sorted by speed
    """
    sensors = [s.name for s in model.sensors]
    excitations = [x.name for x in model.excitations]
    # each line's channel as a whole number into the names found: a Python or numpy string per line
    # took 300 MB beside 20 MB of values for 1.2 million FRF lines
    out_codes, out_names = _codes(records["output"])
    in_codes, in_names = _codes(records["input"])
    unknown = sorted(set(out_names) - set(sensors)) + sorted(set(in_names) - set(excitations))
    if unknown:
        raise InputError(f"{source}: channel(s) {visible_names(unknown)} are not sensors ({visible_names(sensors)}) "
                         f"or excitations ({visible_names(excitations)}) of the model")
    if len(out_codes) == 0:
        raise InputError(f"{source}: no FRF found in the file")
    speeds = np.asarray(records["speed_rpm"], dtype=float)
    if not np.all(np.isfinite(speeds)):
        bad = speeds[~np.isfinite(speeds)][0]
        raise InputError(f"{source}: a spin speed of {bad} rpm (an empty speed_rpm cell, or a UFF z-axis value): "
                         "expected a finite speed for every line")
    coherence = records.get("coherence")
    _check_lines(records, coherence, source)
    results = []
    for speed in np.unique(speeds):
        at = speeds == speed
        results.append(_one_speed(speed, np.asarray(records["frequency_hz"], float)[at],
                                  (out_codes[at], out_names), (in_codes[at], in_names),
                                  np.asarray(records["value"], complex)[at],
                                  None if coherence is None else np.asarray(coherence, float)[at],
                                  sensors, excitations, quantity, source))
    return results


def _codes(names):
    """``(codes (n,) int, names (k,) list of str)``: each line's channel name (an object array, as
    both readers give them) as its place among the distinct names (``str`` of each, as read)."""
    import pandas as pd

    codes, found = pd.factorize(np.asarray(names, dtype=object), use_na_sentinel=False)
    return codes, [str(name) for name in found]


#: largest |H| of a measured FRF in SI units (as the model's numbers): beyond it a value is a
#: mistake (a unit or format), and its square would overflow in the figures and the fits
_LARGEST_VALUE = 1e30
#: how far above 1 a coherence may be by the round-off of a tool that stores it in single precision
_COHERENCE_ROUND_OFF = 1e-6


def _check_lines(records, coherence, source):
    """Refuse frequency lines below 0 Hz, values of no physical size, and coherences outside
    [0, 1] (an empty coherence, NaN, means none measured), each with the first bad line."""
    freq = np.asarray(records["frequency_hz"], dtype=float)
    if np.any(bad := ~(freq >= 0)):
        raise InputError(f"{source}: a frequency line of {freq[np.argmax(bad)]:g} Hz: expected frequencies >= 0 Hz")
    if np.any(bad := ~(freq <= _LARGEST_VALUE)):   # 2e40 Hz was read, drawn and fitted
        raise InputError(f"{source}: a frequency line of {freq[np.argmax(bad)]:g} Hz: expected frequencies of at "
                         f"most {_LARGEST_VALUE:g} Hz")
    size = np.abs(np.asarray(records["value"], dtype=complex))
    if np.any(bad := ~(size <= _LARGEST_VALUE)):
        raise InputError(f"{source}: an FRF value of magnitude {size[np.argmax(bad)]:g} (SI units) at "
                         f"{freq[np.argmax(bad)]:g} Hz: expected a finite magnitude at most {_LARGEST_VALUE:g}")
    if coherence is not None:
        coh = np.asarray(coherence, dtype=float)
        if np.any(bad := (coh < 0) | (coh > 1 + _COHERENCE_ROUND_OFF) | np.isinf(coh)):
            raise InputError(f"{source}: a coherence of {coh[np.argmax(bad)]:g} at {freq[np.argmax(bad)]:g} Hz: "
                             "expected a coherence from 0 to 1")


def _one_speed(speed, freq, outs, ins, values, coherence, sensors, excitations, quantity, source):
    """One speed's FRF set; ``outs`` and ``ins`` are each ``(codes (n,), names)`` (:func:`_codes`)."""
    outputs, o_index = _in_model_order(*outs, sensors)
    inputs, i_index = _in_model_order(*ins, excitations)
    freqs, f_index = np.unique(freq, return_inverse=True)
    shape = (len(outputs), len(inputs), len(freqs))
    _check_repeats(o_index, i_index, f_index, outputs, inputs, freqs, speed, source)
    counts = np.zeros(shape[:2], dtype=int)
    np.add.at(counts, (o_index, i_index), 1)
    partial = (counts > 0) & (counts != len(freqs))
    if partial.any():
        a, b = (int(x[0]) for x in np.nonzero(partial))
        raise InputError(f"{source}: at {speed:g} rpm the FRF {outputs[a]} / {inputs[b]} has {counts[a, b]} "
                         f"frequencies where the data of that speed has {len(freqs)}: every FRF of one "
                         "speed must share the frequency lines")
    H = np.full(shape, np.nan + 0j)
    H[o_index, i_index, f_index] = values
    coh = None
    if coherence is not None:
        coh = np.full(shape, np.nan)
        coh[o_index, i_index, f_index] = coherence
    return FRFResult(H=H, frequencies_hz=freqs, speed=float(speed) * np.pi / 30, inputs=tuple(inputs),
                     outputs=tuple(outputs), quantity=quantity, engine="measured", coherence=coh)


def _in_model_order(codes, names, model_names):
    """The channels of ``names`` found among ``codes`` (n,), in the model's order, and each line's
    index into them (n,)."""
    present = np.unique(codes)
    found = {names[c] for c in present}
    ordered = [name for name in model_names if name in found]
    place = np.zeros(len(names), dtype=np.int64)
    place[present] = [ordered.index(names[c]) for c in present]
    return ordered, place[codes]


def _check_repeats(o_index, i_index, f_index, outputs, inputs, freqs, speed, source):
    """Refuse a channel pair given twice at one frequency (a duplicated channel)."""
    # one whole number per line, ordered as the rows (output, input, frequency): np.unique of rows
    # (axis=0) took several copies of them
    sizes = (len(outputs), len(inputs), len(freqs))
    keys = (np.asarray(o_index, np.int64) * sizes[1] + i_index) * sizes[2] + f_index
    unique, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 1):
        a, b, f = np.unravel_index(unique[np.argmax(counts > 1)], sizes)
        raise InputError(f"{source}: at {speed:g} rpm the FRF {outputs[a]} / {inputs[b]} is given "
                         f"{counts.max()} times at {freqs[f]:g} Hz: expected each channel pair once per "
                         "frequency (a duplicated channel?)")
