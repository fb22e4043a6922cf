"""Universal Files (UFF): FRFs and coherence (dataset 58/58b) written and read;
time records (58, function type 1), header (151), units (164), coordinate systems (18, 2420)
and node coordinates (15, 2411) read (through ``pyuff``).

Written (here, as the UFF definition lays dataset 58/58b out; pyuff's writer puts 8-byte
abscissa values and a wrong byte count into 58b): function type 4 (FRF), abscissa frequency
(type 18, label ``Hz``), ordinate displacement (8), velocity (11) or acceleration (12) over
excitation force (13; a moment, label ``N*m``, where the reference direction is a rotation), SI
unit labels, spin speed in the z-axis value [rpm] (z-axis type 19,
label ``rpm``); coherence as function type 6 next to each FRF. Evenly spaced frequencies are
even data (record 7: first frequency and step, E13.5), others uneven (an abscissa per line: E13.5
in ASCII, 4 bytes in 58b); ordinates doubles (E20.12 in ASCII). Channel names: ID line 1
(``output / input``, or the output there and the input in ID line 2 when both do not fit 80
characters); record 6's entity names (10 characters) hold a name that fits, else ``NONE``.
Directions are UFF codes +-1..+-6 (X, Y, Z, RX, RY, RZ) of the node's coordinate system: a
channel along no model axis is refused unless a mapping table names its node and direction.

Read: FRFs and time records as other tools write them, converted to SI with their unit labels
(:mod:`.unit_labels`: ``g``, ``mm/s``, ``um``, ``lbf``, ``(1/N)*(m/s²)``, ...) or, without a
label, with the dataset 164 factors (a label contradicting a 164 of other than SI units is
refused); node coordinates with the 164 length factor.
"""

from __future__ import annotations

import contextlib
import functools
import io
import os
from dataclasses import dataclass

import numpy as np

from ..analysis.spectra import QUANTITY_OF_RESPONSE
from ..errors import InputError
from .channels import assemble
from .limits import reads_pipes
from .unit_labels import is_none, parse_unit, quantity_of

__all__ = ["read_uff58", "write_uff58", "ORDINATE_TYPES", "read_uff_info", "read_uff_nodes", "NodeTable",
           "UffUnits", "read_uff_time_records", "place_channels"]

#: UFF specific data type of the ordinate -> FRF quantity
ORDINATE_TYPES = {8: "receptance", 11: "mobility", 12: "accelerance"}
_TYPE_OF = {v: k for k, v in ORDINATE_TYPES.items()}
_FORCE = 13
_FREQUENCY = 18
_FRF, _COHERENCE = 4, 6
_TIME = 17
#: dataset 58 specific data types (records 8 to 10)
_TYPE_NAMES = {0: "unknown", 1: "general", 2: "stress", 3: "strain", 5: "temperature", 6: "heat flux",
               8: "displacement", 9: "reaction force", 11: "velocity", 12: "acceleration", 13: "excitation force",
               15: "pressure", 16: "mass", 17: "time", 18: "frequency", 19: "rpm", 20: "order",
               21: "sound pressure", 22: "sound intensity", 23: "sound power"}
#: specific data type -> quantity read (unknown 0 and general 1: the unit label tells)
_SPECIFIC = {8: "displacement", 11: "velocity", 12: "acceleration", 9: "force", 13: "force", 15: "pressure",
             21: "pressure"}
#: dataset 58 Addendum A: (length, force) exponents of the dataset 164 factors, translational and
#: rotational direction (sound pressure 21, not in the table, as pressure 15)
_EXPONENTS = {0: ((0, 0), (0, 0)), 8: ((1, 0), (0, 0)), 9: ((0, 1), (1, 1)), 11: ((1, 0), (0, 0)),
              12: ((1, 0), (0, 0)), 13: ((0, 1), (1, 1)), 15: ((-2, 1), (-1, 1)), 21: ((-2, 1), (-1, 1))}
_PART_NAMES = {"ordinate": "ordinate", "orddenom": "denominator"}
_FRF_ORDINATES = (0, 1, 8, 11, 12)
_FORCE_DENOMINATORS = (0, 1, 9, 13)
_FRF_OF = QUANTITY_OF_RESPONSE


def write_uff58(results, path, mapping, binary: bool | None = None, inputs=()) -> None:
    """Write FRF sets (one per speed) as UFF dataset 58 (ASCII) or 58b (binary), atomically,
    as the Universal File definition lays them out.

    Frequencies of a constant step (each within 1e-12 of the largest frequency of
    ``f0 + k * step``) are *even* data: record 7 holds the first frequency and the step (E13.5,
    6 significant digits), no abscissa values are written. Other frequencies are *uneven*: each
    line's abscissa is written before its values, in E13.5 (ASCII) or in 4 bytes (binary 58b:
    the definition stores an uneven abscissa in single precision). Ordinates are complex
    doubles (coherence real doubles): E20.12 (13 significant digits) in ASCII, 8 bytes in
    binary. The speed is record 7's z value [rpm] (E13.5) with an rpm z-axis (record 11, type
    19). What the layout cannot keep is said in one warning: a step or first frequency of more
    than 6 digits (the largest move of a frequency read back), uneven frequencies of more digits
    than E13.5 or 4 bytes hold, a speed of more than 6 digits.

    Parameters
    ----------
    results : list of FRFResult
    path : str or path-like
    mapping : ChannelMap
        Node and direction of every sensor and excitation.
    binary : bool or None
        58b when True; ASCII 58 when False or None (every reader, pyuff too, reads ASCII; pyuff
        2.5 misreads the 4-byte abscissa of a definition-conforming uneven 58b).
    inputs : iterable of path-like
        Files that must not be overwritten.
    """
    from .atomic import atomic_write, check_not_input
    from .channels import ChannelMap

    if not isinstance(mapping, ChannelMap):     # None failed inside as "'NoneType' object has no attribute 'oblique'"
        raise InputError(f"{path}: mapping = {mapping!r}: expected a ChannelMap, the node and direction of every "
                         "channel (rotordyn_modal.io.channels.default_mapping(model), or read_mapping(FILE, model))")
    check_not_input(path, inputs)
    _check_writable_channels(results, mapping, path)
    binary = bool(binary)
    chunks = []
    for res in results:
        grid = _even_grid(res.frequencies_hz)
        _warn_abscissa_loss(res.frequencies_hz, grid, binary, path)
        _warn_speed_loss(res.speed * 30 / np.pi, path)
        chunks.extend(_datasets(res, mapping, binary, grid))
    with atomic_write(path, "wb") as handle:
        handle.write(b"".join(chunks))


def _even_grid(frequencies):
    """``(first, step)`` [Hz] of frequencies of a constant step (each within 1e-12 of the largest
    frequency of ``first + k * step``; at least two), else None (uneven)."""
    x = np.asarray(frequencies, dtype=float)
    if len(x) < 2:
        return None
    step = (x[-1] - x[0]) / (len(x) - 1)
    if not step > 0:
        return None
    grid = x[0] + step * np.arange(len(x))
    return (float(x[0]), float(step)) if np.max(np.abs(grid - x)) <= 1e-12 * np.max(np.abs(x)) else None


def _e13(value) -> float:
    """``value`` as a Universal File's E13.5 field reads back."""
    return float(f"{value:13.5E}")


def _warn_abscissa_loss(frequencies, grid, binary, path) -> None:
    """One warning when the frequencies read back from the layout differ from ``frequencies``
    by more than round-off (1e-12 of the largest), naming the largest move [Hz]."""
    import warnings

    x = np.asarray(frequencies, dtype=float)
    scale = 1e-12 * np.max(np.abs(x)) if len(x) else 0.0
    if grid is not None:
        first, step = grid
        back = _e13(first) + _e13(step) * np.arange(len(x))
        move = float(np.max(np.abs(back - x)))
        if move > scale:
            warnings.warn(f"{path}: frequencies {first:.12g} to {x[-1]:.12g} Hz in a step of {step:.12g} Hz: a UFF 58 "
                          f"header (record 7, E13.5) holds the first frequency and the step to 6 digits "
                          f"({_e13(first):.5E}, {_e13(step):.5E}), so the frequencies read back move by up to "
                          f"{move:.2g} Hz; a step and first frequency of 6 digits (e.g. 0.5 Hz) keep them, "
                          "and so does CSV", stacklevel=3)
        return
    back = x.astype(np.float32).astype(float) if binary else np.array([_e13(v) for v in x])
    moved = np.abs(back - x) > scale
    if np.any(moved):
        kept = "4 bytes (single precision, about 7 digits)" if binary else "E13.5 (6 digits)"
        warnings.warn(f"{path}: {int(moved.sum())} of {len(x)} frequencies are uneven and have more digits than the "
                      f"UFF 58 abscissa holds, {kept}: read back they move by up to "
                      f"{float(np.max(np.abs(back - x))):.2g} Hz; frequencies of a constant step keep them (even "
                      "data), and so does CSV", stacklevel=3)


def _warn_speed_loss(rpm, path) -> None:
    import warnings

    if abs(_e13(rpm) - rpm) > 1e-9 * max(abs(rpm), 1.0):
        warnings.warn(f"{path}: speed {rpm:.12g} rpm: a UFF 58 z-axis value (record 7, E13.5) holds 6 digits: read "
                      f"back as {_e13(rpm):.6g} rpm", stacklevel=3)


def _check_writable_channels(results, mapping, path):
    """Refuse what UFF 58 cannot say: a channel along no model axis (without a mapping naming its
    node and direction), or a name longer than an ID line (80 bytes in UTF-8)."""
    for name in sorted({n for res in results for n in (*res.outputs, *res.inputs)}):
        if name in mapping.oblique:
            direction = ", ".join(f"{v:.4g}" for v in mapping.oblique[name])
            raise InputError(f"{path}: channel {name!r} measures along ({direction}), along no model axis: UFF 58 "
                             "gives a direction only as a code +-1..+-6 (X, Y, Z, RX, RY, RZ) of its node's "
                             "coordinate system; give a mapping table (--mapping FILE.csv: name,node,direction) "
                             "naming a node whose coordinate system has that axis, or write CSV")
        size = len(name.encode("utf-8"))
        if size > 80:   # the line is written in UTF-8: 80 bytes, not characters (a 'ü' takes 2)
            count = f"{len(name)} characters" if size == len(name) else f"{len(name)} characters, {size} bytes in UTF-8"
            raise InputError(f"{path}: channel name {name[:40]!r}... has {count}: a UFF 58 ID line holds 80 bytes")
        if name in getattr(mapping, "twice", {}):
            table, ((line_a, (node_a, dir_a)), (line_b, (node_b, dir_b))) = mapping.twice[name]
            raise InputError(f"{table}: line {line_b}: name {name!r} is given node {node_b} direction {dir_b} here "
                             f"and node {node_a} direction {dir_a} on line {line_a}: writing {path} (UFF) needs one "
                             "node and direction per name (two read a file that numbers a driving point's response "
                             "and reference apart)")


def _entity(name):
    """Record 6 holds 10 columns of an entity name: longer names are 'NONE' there (ID lines 1-2
    hold them), and so are names beyond ASCII, whose columns a reader counting bytes (the
    definition, UFFFiles.jl) and one counting characters (pyuff) would find in different places."""
    return name if name.isascii() and len(name) <= 10 else "NONE"


def _datasets(res, mapping, binary, grid):
    """The bytes of the FRF sets (function type 4) of one result, each followed by its
    coherence (type 6) when the result has one."""
    rpm = res.speed * 30 / np.pi
    for a, out in enumerate(res.outputs):
        for b, inp in enumerate(res.inputs):
            rsp_node, rsp_dir, rsp_sign = mapping.node_of(out)
            ref_node, ref_dir, ref_sign = mapping.node_of(inp)
            both = f"{out} / {inp}"
            names = (both, "NONE") if len(both.encode("utf-8")) <= 80 else (out, inp)
            dof = (rsp_node, rsp_dir, _entity(out), ref_node, ref_dir, _entity(inp))
            frf = np.asarray(res.H[a, b] * rsp_sign * ref_sign, complex)
            ordinate = (_TYPE_OF[res.quantity], 1, 0, _label(res.quantity))
            # excitation force 13 along a rotation (codes 4-6) is a moment: N*m (Addendum A: length and force 1)
            denominator = (_FORCE, 1, 1, "N*m") if abs(int(ref_dir)) > 3 else (_FORCE, 0, 1, "N")
            yield _dataset(_FRF, names, dof, ordinate, denominator, res.frequencies_hz, frf, rpm, grid, binary)
            if res.coherence is not None:
                yield _dataset(_COHERENCE, names, dof, (0, 0, 0, "NONE"), (0, 0, 0, "NONE"), res.frequencies_hz,
                               np.asarray(res.coherence[a, b], float), rpm, grid, binary)


def _dataset(function, names, dof, ordinate, denominator, x, values, rpm, grid, binary) -> bytes:
    """One dataset 58 (ASCII) or 58b (binary) as the Universal File definition lays it out.

    Parameters
    ----------
    function : int
        Function type (4 FRF, 6 coherence).
    names : (str, str)
        ID lines 1 and 2.
    dof : tuple
        Response node, direction, entity name; reference node, direction, entity name.
    ordinate, denominator : (int, int, int, str)
        Records 9 and 10: specific data type, length and force unit exponents, unit label.
    x : array (n,)
        Frequencies [Hz].
    values : array (n,), complex or real
    rpm : float
        Speed [rpm], the z-axis value.
    grid : (float, float) or None
        First frequency and step [Hz] of even data; None: uneven.
    binary : bool
    """
    values = np.asarray(values)
    complex_ = np.iscomplexobj(values)
    count, even = len(values), grid is not None
    first, step = grid if even else (0.0, 0.0)
    rsp_node, rsp_dir, rsp_name, ref_node, ref_dir, ref_name = dof
    data = _data_binary(x, values, even) if binary else _data_ascii(x, values, even)
    ident = (f"{58:6d}b{1:6d}{2:6d}{11:12d}{len(data):12d}{0:6d}{0:6d}{0:12d}{0:12d}" if binary else f"{58:6d}")
    lines = [f"{-1:6d}", ident, *(_padded(text, 80) for text in (*names, "NONE", f"{rpm:.6g} rpm"[:80], "NONE")),
             f"{function:5d}{0:10d}{0:5d}{0:10d} {rsp_name:<10s}{rsp_node:10d}{rsp_dir:4d} {ref_name:<10s}{ref_node:10d}"
             f"{ref_dir:4d}",
             f"{6 if complex_ else 4:10d}{count:10d}{int(even):10d}{first:13.5E}{step:13.5E}{rpm:13.5E}",
             _axis(_FREQUENCY, 0, 0, "Hz"), _axis(*ordinate), _axis(*denominator), _axis(_RPM, 0, 0, "rpm")]
    return ("\n".join(lines) + "\n").encode("utf-8") + data + f"{-1:6d}\n".encode()


def _padded(text, width) -> str:
    """``text`` and blanks to ``width`` bytes in UTF-8, the columns a reader of the definition
    counts (``f"{text:<80s}"`` counts characters: 40 'ü' made a line of 120 bytes)."""
    return text + " " * (width - len(text.encode("utf-8")))


def _axis(kind, length, force, unit) -> str:
    """Records 8 to 11: specific data type, unit exponents (length, force, temperature), axis
    label (NONE) and unit label."""
    return f"{kind:10d}{length:5d}{force:5d}{0:5d} {'NONE':<20s} {unit:<20s}"


def _data_binary(x, values, even) -> bytes:
    """Record 12 of a 58b, little-endian IEEE 754 (record 1: byte order 1, format 2): ordinate
    doubles (real and imaginary parts), each line of uneven data led by its abscissa in 4 bytes."""
    fields = [("re", "<f8")] + ([("im", "<f8")] if np.iscomplexobj(values) else [])
    if not even:
        fields.insert(0, ("x", "<f4"))
    rows = np.zeros(len(values), dtype=np.dtype(fields))
    rows["re"] = np.real(values)
    if np.iscomplexobj(values):
        rows["im"] = np.imag(values)
    if not even:
        rows["x"] = np.asarray(x, dtype=float)
    return rows.tobytes()


def _data_ascii(x, values, even) -> bytes:
    """Record 12 of an ASCII 58 of double-precision ordinates: even 4E20.12 (cases 5 and 7),
    uneven E13.5,2E20.12 a line (complex, case 8) or 2(E13.5,E20.12) (real, case 6)."""
    values = np.asarray(values)
    parts = [np.real(values), np.imag(values)] if np.iscomplexobj(values) else [np.real(values)]
    if even:
        numbers = np.column_stack(parts).ravel()
        fields, per_line = ["%20.12E" % v for v in numbers], 4
    else:
        columns = [np.asarray(x, dtype=float), *parts]
        fields = [("%13.5E" if k == 0 else "%20.12E") % v for row in zip(*columns) for k, v in enumerate(row)]
        per_line = 3 if len(parts) == 2 else 4
    lines = ["".join(fields[k:k + per_line]) for k in range(0, len(fields), per_line)]
    return ("\n".join(lines) + "\n").encode() if lines else b""


def _label(quantity):
    return {"receptance": "m", "mobility": "m/s", "accelerance": "m/s^2"}[quantity]


def read_uff58(path, model, mapping):
    """Read every dataset 58/58b of a UFF file into model-named FRF sets (one per speed).

    The FRF quantity and the factor to SI come from each set's unit labels (records 9 and 10,
    e.g. ``m/s^2`` over ``N``, ``g/lbf``, ``(1/N)*(m/s²)``; see :mod:`.unit_labels`), or, where
    the labels are ``NONE``, from its specific data types with the dataset 164 unit factors.

    The FRFs (function type 4) and the coherence of their pairs (6) are read; the file's other
    dataset 58 sets (time records, PSDs, auto-spectra, cross-spectra beside their pair's FRF, ...)
    are skipped with one warning naming their places, function types and nodes. A file without an
    FRF is refused naming what it holds (with time records: how FRFs are computed from them), and
    so is a cross-spectrum of a pair without its FRF.

    Parameters
    ----------
    path : path-like
    model : Model
    mapping : ChannelMap

    Returns
    -------
    list of FRFResult
    """
    _refuse_beyond_memory(path)
    sets, units = _read_sets(path)
    frfs = [s for s in sets if _function_type(s) == _FRF]
    if not frfs:
        raise InputError(_no_frf_line(path, sets))
    kept = {id(s) for s in _complete_frfs(frfs, path)}
    frfs = [s for s in frfs if id(s) in kept]
    sets = [s for s in sets if _function_type(s) != _FRF or id(s) in kept]
    read = [_frf_units(s, units, path) for s in frfs]
    quantities = sorted({q for q, _ in read})
    if len(quantities) != 1:
        raise InputError(f"{path}: the FRFs hold {', '.join(quantities)}: expected one quantity in a file")
    quantity = quantities[0]
    _refuse_lone_spectra(sets, frfs, path)
    _refuse_named_apart(frfs, path)
    pairs = {_key(s) for s in frfs}
    coherence = {_key(s): np.real(np.asarray(s["data"])) for s in sets if _is_frf_coherence(s, pairs)}
    skipped = [s for s in sets if _function_type(s) != _FRF and not _is_frf_coherence(s, pairs)]
    parts = []
    for s, (_, factor) in zip(frfs, read):
        _check_set(s, path)
        out, out_sign = _lookup(mapping.outputs, s["rsp_node"], s["rsp_dir"], "response", path)
        inp, in_sign = _lookup(mapping.inputs, s["ref_node"], s["ref_dir"], "reference", path)
        x = np.asarray(s["x"], float) * _abscissa_factor(s, _FREQUENCY, path)
        coh = coherence.get(_key(s))
        if coh is not None and len(coh) != len(x):
            raise InputError(f"{path}: coherence of the FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:"
                             f"{s['ref_dir']} has {len(coh)} values for {len(x)} frequencies: expected one per frequency")
        parts.append({"speed_rpm": np.full(len(x), _speed_rpm(s, path)),
                      "frequency_hz": x, "output": _repeated(out, len(x)), "input": _repeated(inp, len(x)),
                      "value": np.asarray(s["data"], complex) * (factor * out_sign * in_sign),
                      "coherence": np.full(len(x), np.nan) if coh is None else coh})
    records = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    if not coherence:
        records["coherence"] = None
    result = assemble(records, model, quantity, str(path))
    _warn_named_otherwise(frfs, quantity, path)
    if skipped:       # warned once the FRFs are read: a refused file gets its one error line alone
        import warnings

        warnings.warn(_skipped_frf_line(path, len(frfs), bool(coherence), skipped), stacklevel=3)
    return result


#: memory reading a Universal File's FRFs takes per byte of the file, ASCII and binary (58b) [bytes]:
#: pyuff's sets and the lines made of them (``benchmarks/bench_measured_memory.py``: 5.3-6.3 and
#: 13.5-16 times the file at 1.2 and 0.6 million lines)
_UFF_BYTES_PER_BYTE = {"ascii": 7, "binary": 17}


def _refuse_beyond_memory(path) -> None:
    """Refuse, before it is read, a Universal File whose FRFs would not fit in the memory
    available (:func:`.._limits.memory_problem`; binary when its first 4 kB name a dataset 58b)."""
    import os

    from .limits import refuse_beyond_memory

    try:
        size = os.path.getsize(path)
        with open(path, "rb") as handle:
            binary = b"58b" in handle.read(4096).lower()
    except OSError:           # said by the reader, in its own words
        return
    refuse_beyond_memory(path, _UFF_BYTES_PER_BYTE["binary" if binary else "ascii"] * size,
                         f"{size / 1e6:.3g} MB, {'UFF 58b' if binary else 'UFF 58 ASCII'}",
                         "split it (a file per speed or per channel pair)")


def _repeated(name: str, count: int) -> np.ndarray:
    """``count`` references to one name, an object array (8 bytes a line): ``np.full`` made a
    string apiece (58 bytes a line; 1.2 million FRF lines: 132 MB)."""
    lines = np.empty(count, dtype=object)
    lines.fill(name)
    return lines


#: z-axis unit labels of a rotational speed -> factor to rpm
_SPEED_UNITS = {"rpm": 1.0, "1/min": 1.0, "rev/min": 1.0, "r/min": 1.0, "u/min": 1.0, "hz": 60.0, "1/s": 60.0,
                "rev/s": 60.0, "rps": 60.0, "rad/s": 30.0 / np.pi, "rad/sec": 30.0 / np.pi}
_RPM = 19


def _speed_rpm(s, path) -> float:
    """An FRF set's spin speed [rpm] from its z-axis (record 11): data type 19 (rpm), or 0/1
    (unknown/general, as ``write_uff58`` writes it), in rpm or in the unit its label gives
    (``1/min``, ``Hz``, ``rad/s``). A z-axis of another data type (time 17 of a run-up waterfall,
    order 20, ...) says no speed: 0 is taken as none; another value is refused, not read as rpm."""
    value = float(s.get("z_axis_value", 0.0))
    kind = int(s.get("z_axis_spec_data_type", 0))
    label = _label_text(s, "z_axis_axis_units_lab", path)
    where = f"{path}: FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:{s['ref_dir']}"
    if kind not in (0, 1, _RPM):
        if value == 0.0:
            return 0.0
        raise InputError(f"{where}: z-axis value {value:g} of data type {kind} ({_type_name(kind)}, unit {label!r}) "
                         "is no spin speed: expected the speed in the z-axis, data type 19 (rpm) or 0, one speed per "
                         "FRF set")
    if is_none(label):
        factor = 1.0
    elif label.strip().lower() in _SPEED_UNITS:
        factor = _SPEED_UNITS[label.strip().lower()]
    else:
        raise InputError(f"{where}: z-axis unit {label!r} (data type {kind}, {_type_name(kind)}): expected a spin "
                         f"speed in {', '.join(_SPEED_UNITS)}")
    return round(value * factor, 9)


def _refuse_named_apart(frfs, path) -> None:
    """Refuse FRFs of one response and reference node and direction (and speed) that only their
    entity names (record 6) tell apart, as tools write that number no nodes (node 0 direction 0,
    the point in the name: ``.1.Z-``): a mapping table places channels by node and direction, so
    which is which cannot be told (read as one pair, they were refused as a duplicated channel)."""
    seen = {}
    for s in frfs:
        names = (str(s.get("rsp_ent_name", "")).strip(), str(s.get("ref_ent_name", "")).strip())
        first = seen.setdefault(_key(s), (s, names))
        if first[1] != names:
            other = first[0]
            raise InputError(f"{path}: the FRFs of datasets {other.get('_dataset', '?')} and {s.get('_dataset', '?')} "
                             f"are both {_nodes(s)} and differ only by their entity names ({' / '.join(first[1])!r} "
                             f"and {' / '.join(names)!r}): a mapping table places channels by node and direction; "
                             "export the FRFs with node numbers and directions")


#: words of an ordinate's axis label (record 9, free text) that name an FRF's quantity
_NAMED = {"receptance": "receptance", "compliance": "receptance", "dynamic compliance": "receptance",
          "mobility": "mobility", "accelerance": "accelerance", "inertance": "accelerance"}


def _warn_named_otherwise(frfs, quantity, path) -> None:
    """One warning where FRFs' axis labels (record 9, free text: ``Receptance``) name another
    quantity than their unit labels give (``(m/s)/N``, a mobility): the unit decides, as it is the
    field that gives the unit, and the user is told."""
    import re
    import warnings

    words = "|".join(sorted(_NAMED, key=len, reverse=True))
    named = {}
    for s in frfs:
        found = re.search(rf"\b({words})\b", str(s.get("ordinate_axis_lab", "")).strip().lower())
        if found and _NAMED[found.group(1)] != quantity:
            named.setdefault(str(s.get("ordinate_axis_lab")).strip(), []).append(s)
    for label, sets in named.items():
        unit = _label_text(sets[0], "ordinate_axis_units_lab", path)
        kind = int(sets[0].get("ordinate_spec_data_type", 0))
        field, said = (("data type", f"the ordinate data type {kind} ({_type_name(kind)})") if is_none(unit)
                       else ("unit", f"the unit {unit!r}"))
        where = "the FRF" if len(sets) == len(frfs) == 1 else f"{len(sets)} of the {len(frfs)} FRFs"
        verb = "has" if len(sets) == 1 else "have"
        warnings.warn(f"{path}: {where} ({_listed(dict.fromkeys(_nodes(s) for s in sets))}) {verb} the axis label "
                      f"{label!r} but {said}, a {quantity}: read as {quantity}, as the {field} says (the axis label "
                      "is free text)", stacklevel=4)


#: dataset 58 function types that hold a pair's spectrum, not its FRF
_SPECTRA = {2: "auto-spectrum", 3: "cross-spectrum"}


def _is_frf_coherence(s, pairs) -> bool:
    """A coherence set (function type 6) of a pair, speed included, whose FRF the file holds."""
    return _function_type(s) == _COHERENCE and _key(s) in pairs


def _no_frf_line(path, sets) -> str:
    """The line refusing a file of dataset 58 sets none of which is an FRF: what it holds, and,
    where it holds time records, how FRFs are computed from them."""
    kinds = sorted({_function_type(s) for s in sets})
    line = (f"{path}: no FRF (dataset 58, function type 4) in the file; function types found: {kinds}: "
            f"{_by_function(sets)}")
    if any(_is_time_record(s) for s in sets):
        line += (": time records are no FRFs; compute the FRFs from them in Python, frf = rdm.estimate_frf("
                 "rdm.read_uff_time_records(FILE, mapping, speed), inputs, outputs, estimator='H1' or 'H2'), and write "
                 "them with rdm.write_measured_csv([frf], FILE.csv) for --measured (docs/frf-and-measurement.md, "
                 "'From time records')")
    return line


def _skipped_frf_line(path, count: int, with_coherence: bool, skipped) -> str:
    """One line naming the dataset 58 sets an FRF file holds beside its FRFs and their coherence."""
    frfs = "the FRF" if count == 1 else f"the {count} FRFs"
    read = f"{frfs} (dataset 58, function type 4){' and their coherence' if with_coherence else ''}"
    note = "only FRFs and the coherence of an FRF's pair are read"
    if any(_is_time_record(s) for s in skipped):
        note += "; FRFs are computed from time records by rdm.estimate_frf"
    return _skipped_line(path, read, "FRF", skipped, note)


def _refuse_lone_spectra(sets, frfs, path):
    """Refuse a cross-spectrum (function type 3) of a response/reference pair that has no FRF in
    the file: it was skipped without a word and the pair read as NaN, and a cross-spectrum in
    place of an FRF is most likely the wrong export. Beside its pair's FRF (as analysers export
    both) it is extra data, left unread and named in the reader's warning. An auto-spectrum
    (function type 2) is one channel's power, never an FRF's pair: beside FRFs (the force's and
    the responses' auto-spectra, from which an analyser computed them) it is skipped and named
    alike; a file of spectra without any FRF is refused by ``_no_frf_line``."""
    pairs = {_key(s) for s in frfs}
    for s in sets:
        kind = _function_type(s)
        if kind == 3 and _key(s) not in pairs:
            raise InputError(f"{path}: dataset {s.get('_dataset', '?')} ({s.get('rsp_node')}:{s.get('rsp_dir')} / "
                             f"{s.get('ref_node')}:{s.get('ref_dir')}): function type {kind} ({_SPECTRA[kind]}) is "
                             "not an FRF (function type 4), and the file has no FRF of that pair: export the FRF")


#: the UTF-8 byte order mark as read in Latin-1
_BOM_LATIN1 = "\ufeff".encode("utf-8").decode("latin-1")


#: the first bytes of every TDMS file (a segment's lead-in)
TDMS_MAGIC = b"TDSm"
#: what a TDMS file given as a Universal File or a CSV table of FRFs is
TDMS_WORDS = ("a TDMS file (it begins with 'TDSm'), not a Universal File or a table of FRFs: read its time "
              "records with rdm.read_tdms_records (and estimate FRFs from them with rdm.estimate_frf)")


def _not_wide_text(head: bytes, path) -> None:
    """Refuse a Universal File saved as UTF-16 or UTF-32 text (with a byte-order mark or, UTF-16,
    without one: :func:`.text.utf16_without_mark`): pyuff reads ASCII only, and such a file was
    taken for binary 58b sets and failed inside pyuff."""
    from .text import UTF16_WITHOUT_MARK, marked_encoding, utf16_without_mark

    if (marked := marked_encoding(head)) in ("utf-16", "utf-32"):
        said = f"it is {marked.upper()} text (a byte-order mark)"
    elif utf16_without_mark(head):
        said = UTF16_WITHOUT_MARK
    else:
        return
    raise InputError(f"{path}: cannot read the Universal File: {said}: expected ASCII text (save it as ASCII "
                     "or UTF-8)")


def _check_complete(path):
    """Refuse a truncated or padded ASCII file: datasets sit between pairs of ``-1`` lines. A file
    whose last dataset is cut short (no ``-1`` closes it) after at least one complete dataset
    draws one warning line naming that dataset and its first line, and the complete ones are
    read, as a test-lab export cut in its last dataset is still worth reading. Text after the
    last dataset (an export's ``end of export`` line) draws one warning line naming the line it
    starts at, and the datasets are read.

    Returns
    -------
    int or None
        The count of the file's lines that hold its complete datasets when the last one is cut
        short or text follows it (read those: :func:`_pyuff_read`'s ``lines``), else None (read
        the whole file).
    """
    from .limits import check_size, refuse_compressed, refuse_unsized, unreadable

    check_size(path, "measured", "measured-data file")
    refuse_unsized(path, "a Universal File")   # pyuff read /dev/zero to its end: rdm.read_uff_info hung
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096)
    except OSError as error:   # missing, a folder, no read permission: PermissionError out of the API
        raise unreadable(path, "Universal File", error) from None
    if not head.strip():       # was "no dataset 58/58b (FRF) in the file; datasets found: none"
        raise InputError(f"{path}: an empty file: expected a Universal File (datasets between '    -1' lines)")
    refuse_compressed(head, path, "Universal File")
    _not_wide_text(head, path)
    if head[:4] == TDMS_MAGIC:     # was "no dataset 58/58b (FRF) in the file; datasets found: none"
        raise InputError(f"{path}: {TDMS_WORDS}")
    if b"\0" in head or b"58b" in head.lower():
        return  # binary 58b sets: pyuff checks their byte counts
    with open(path, encoding="latin-1") as handle:
        # a UTF-8 byte order mark (Windows tools write one) before the first '    -1': pyuff reads past it
        lines = handle.read().removeprefix(_BOM_LATIN1).splitlines()
    marks = [k for k, line in enumerate(lines) if _is_delimiter(line)]
    tail = [line for line in lines[(marks[-1] + 1 if marks else 0):] if line.strip()]
    if len(marks) % 2 and len(marks) > 1:
        _warn_cut_short(path, lines, marks)
        return marks[-2] + 1
    if tail and marks and not len(marks) % 2:
        _warn_trailing_text(path, lines, marks)
        return marks[-1] + 1
    if len(marks) % 2 or tail:
        line = (marks[-1] + 2) if marks else 1
        raise InputError(f"{path}: incomplete Universal File: a dataset is not closed by a '    -1' line "
                         f"(from line {line}): the file is truncated or has trailing text")
    if any(not lines[k].rstrip().endswith(DELIMITER) for k in marks):
        return len(lines)     # read from a copy with its delimiters as pyuff finds them (_first_lines)


#: a dataset delimiter as the Universal File format writes it (columns 1-6) and pyuff finds it
DELIMITER = "    -1"


def _is_delimiter(line: str) -> bool:
    """Whether a line of a Universal File is a dataset delimiter: ``-1`` alone within its first
    8 columns, written ``    -1`` or not (a tab or fewer blanks before it, as hand-edited and some
    exported files have; pyuff finds only ``    -1``)."""
    return line.strip() == "-1" and len(line.rstrip()) <= 8


def _warn_trailing_text(path, lines, marks) -> None:
    """The warning about text after a file's last dataset (closed at line ``marks[-1] + 1``):
    a note or an end marker an export wrote after its datasets, left out."""
    import warnings

    start = next(k for k in range(marks[-1] + 1, len(lines)) if lines[k].strip())
    count = len(marks) // 2
    warnings.warn(f"{path}: text after the last dataset, from line {start + 1} ({lines[start].strip()[:40]!r}; "
                  f"no dataset between '    -1' lines): left out, the {count} dataset{'s' if count > 1 else ''} "
                  "before it read", stacklevel=4)


def _warn_cut_short(path, lines, marks) -> None:
    """The warning about a file's last dataset, opened at line ``marks[-1] + 1`` and closed by
    no ``-1`` line (``lines`` the file's, ``marks`` the places of its ``-1`` lines)."""
    import warnings

    complete = (len(marks) - 1) // 2
    number = lines[marks[-1] + 1].strip() if marks[-1] + 1 < len(lines) else ""
    kind = f"dataset {number}" if number else "a dataset"
    warnings.warn(f"{path}: dataset {complete + 1} ({kind} from line {marks[-1] + 1}) is cut short: no '    -1' "
                  f"line closes it (the file ends at line {len(lines)}); left out, the "
                  f"{'complete dataset' if complete == 1 else f'{complete} complete datasets'} before it read",
                  stacklevel=4)


class NoFunctionData(InputError):
    """A Universal File without dataset 58, refused by the FRF reader; ``types`` its dataset
    numbers (:func:`.measured.read_measured` adds what its dataset 2414 sets hold)."""

    def __init__(self, message, types):
        super().__init__(message)
        self.types = [int(t) for t in types]


def _read_sets(path):
    """``(sets, units)``: the file's datasets 58 and its units (dataset 164), in one read."""
    complete = _check_complete(path)
    uff, types, index, sets = _pyuff_read(path, (58, 164), complete)
    if 58 not in types:
        modes = " (mode shapes: modes --measured, rdm.read_uff_modes)" if 55 in types else ""
        raise NoFunctionData(f"{path}: no dataset 58/58b (FRF) in the file; datasets found: "
                             f"{_datasets_named(int(t) for t in types)}{modes}", types)
    units = _units([{**s, "type": 164} for number, s in zip(index, sets) if types[number] == 164], path)
    frfs = []
    for number, s in zip(index, sets):
        if types[number] == 58:
            s["_dataset"] = number + 1                  # its place among the file's datasets, for messages
            _as_the_header_says(uff, number, s, path, warn_cut_short=False)
            frfs.append(s)
    return frfs, units


def _pyuff_read(path, kinds=None, lines=None):
    """``(uff, types, index, sets)``: the file's datasets as pyuff reads them, every one or those
    whose dataset number is one of ``kinds`` (their places ``index``, from 0); of the file's first
    ``lines`` lines only when given (its complete datasets, :func:`_check_complete`), read from
    a copy of them in a temporary folder.

    pyuff refuses an ASCII file whose lines end in blanks where it reads fixed-width numbers (the
    last, short line of a double-precision dataset 58 padded to 80 columns, as Fortran writers and
    DataPhysics SignalStar do, pyuff issue 20): such a file is read again from a copy without the
    blanks at the ends of its lines (in a temporary folder; the file itself is never changed).
    Whatever pyuff raises on a file it cannot read is one ``InputError`` naming the file.
    """
    import tempfile
    from pathlib import Path

    import pyuff

    def read(name):
        uff = pyuff.UFF(name)
        types = [int(t) for t in uff.get_set_types()]
        index = [i for i, t in enumerate(types) if kinds is None or t in kinds]
        with contextlib.redirect_stdout(io.StringIO()):    # pyuff prints some datasets (2467) as it reads
            sets = uff.read_sets(index) if index else []
        return uff, types, index, [sets] if isinstance(sets, dict) else list(sets)

    if lines is not None:
        with tempfile.TemporaryDirectory() as folder:
            copy = Path(folder) / "complete.uff"
            copy.write_bytes(_first_lines(path, lines))
            try:
                return _pyuff_read(copy, kinds)
            except InputError as error:   # named as the file given, not the copy
                raise InputError(str(error).replace(str(copy), str(path), 1)) from None
    try:
        return read(str(path))
    except Exception as error:  # pyuff raises many kinds on a broken file
        first = error
    stripped = _without_trailing_blanks(path)
    if stripped is not None:
        with tempfile.TemporaryDirectory() as folder:
            copy = Path(folder) / "stripped.uff"
            copy.write_bytes(stripped)
            try:
                return read(str(copy))
            except Exception:   # the blanks were not the trouble: the first error is the file's
                pass
            found = _read_each(str(copy), kinds, path)
    else:
        found = _read_each(str(path), kinds, path)
    if found is not None:
        return found
    raise InputError(f"{path}: not a readable Universal File ({type(first).__name__}: {first})") from None


NEWLINE = b"\n"


def _read_each(name, kinds, path):
    """``(uff, types, index, sets)`` of :func:`_pyuff_read` read one dataset at a time, after pyuff
    failed on them together: the datasets 58 pyuff cannot read (one cut short inside its header,
    then closed by ``-1``) are left out with one warning line naming the first, its place and its
    first line; another dataset that cannot be read (units, geometry) is refused so. None when
    pyuff cannot even list the datasets, or every one reads alone."""
    import warnings

    import pyuff

    try:
        uff = pyuff.UFF(name)
        types = [int(t) for t in uff.get_set_types()]
    except Exception:   # noqa: BLE001 - the file's first error is said
        return None
    index, sets, failed = [], [], []
    for i, kind in enumerate(types):
        if kinds is not None and kind not in kinds:
            continue
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                sets.append(uff.read_sets(i))
            index.append(i)
        except Exception as error:   # noqa: BLE001 - pyuff raises many kinds on a broken set
            failed.append((i, error))
    if not failed:
        return None
    i, error = failed[0]
    try:
        with open(name, "rb") as handle:
            before = handle.read(int(uff._block_ind[i][0]))
        line = f" from line {before.count(NEWLINE) + 1}"
    except (AttributeError, IndexError, TypeError, ValueError, OSError):   # pyuff's own bookkeeping
        line = ""
    where = f"dataset {i + 1} (dataset {types[i]}{line})"
    why = f"{type(error).__name__}: {error}"
    if not index or any(types[k] != 58 for k, _ in failed):
        raise InputError(f"{path}: not a readable Universal File: {where} cannot be read ({why}): cut short "
                         "or damaged")
    more = f" (and {len(failed) - 1} more dataset{'s' if len(failed) > 2 else ''} 58)" if len(failed) > 1 else ""
    warnings.warn(f"{path}: {where}{more} cannot be read ({why}): cut short or damaged; left out, the "
                  f"{len(index)} other dataset{'s' if len(index) > 1 else ''} read", stacklevel=5)
    return uff, types, index, sets


def _first_lines(path, count: int) -> bytes:
    """The bytes of the first ``count`` lines of ``path`` (lines as :func:`_check_complete` counts
    them: of its Latin-1 text, a leading byte-order mark passed over), each with its line end;
    a dataset delimiter written otherwise (:func:`_is_delimiter`) written ``    -1``."""
    with open(path, "rb") as handle:
        data = handle.read()
    text = data.decode("latin-1")
    mark = len(_BOM_LATIN1) if text.startswith(_BOM_LATIN1) else 0
    kept = text[mark:].splitlines(keepends=True)[:count]
    if all(line.rstrip().endswith(DELIMITER) for line in kept if _is_delimiter(line)):
        return data[:mark + sum(len(line) for line in kept)]
    written = (DELIMITER + line[len(line.rstrip("\r\n")):] if _is_delimiter(line) else line for line in kept)
    return data[:mark] + "".join(written).encode("latin-1")


def _without_trailing_blanks(path):
    """The bytes of an ASCII Universal File with the blanks at the ends of its lines removed, or
    None for a file with binary sets (58b) or without such blanks."""
    import re

    with open(path, "rb") as handle:
        data = handle.read()
    if b"\0" in data or re.search(rb"(?m)^\s*58b", data):
        return None
    stripped = re.sub(rb"[ \t]+(?=\r?\n|\Z)", b"", data)
    return None if stripped == data else stripped


def _as_the_header_says(uff, number, s, path, warn_cut_short=True) -> None:
    """A dataset 58's abscissa and values made what its header says (in place), where pyuff reads
    otherwise.

    - Record 7 gives the count of values (``num_pts``); pyuff returns every number of the data
      lines, so an ASCII writer's zeros filling the last line (tools write 6 numbers a line)
      became extra frequency lines or samples of value 0 (a 1600-line FRF read as 1602 lines up
      to 800.5 Hz; a 4096-sample record as 4098 samples), and the bytes of a binary set's
      trailing line end values. The values beyond the count are dropped, in ASCII with a warning
      when they are not all zero; a dataset holding fewer values than its count (a file cut
      short) is marked ``_cut_short`` and read as it is, with a warning unless
      ``warn_cut_short`` is False (the FRF reader's :func:`_complete_frfs` says what it does).
    - Binary 58b with an uneven abscissa and double-precision ordinates (record 7 types 4 and 6):
      the UFF definition stores each abscissa value in single precision (4 bytes) before its
      8- or 16-byte ordinate; pyuff reads 8 bytes there, so the whole record was misread. The
      values are decoded again from the file, the abscissa's width told by record 1's byte count
      (4 bytes as the definition says, or 8 as pyuff writes).

    Parameters
    ----------
    uff : pyuff.UFF
        The file, read (its datasets' places).
    number : int
        The dataset's place among the file's datasets (from 0).
    s : dict
        The dataset as pyuff read it; ``x`` and ``data`` are replaced.
    path : path-like
    """
    import warnings

    if s.get("data") is None:
        return
    if int(s.get("binary", 0)) and int(s.get("abscissa_spacing", 1)) == 0 and int(s.get("ord_data_type", 0)) in (4, 6):
        s["x"], s["data"] = _uneven_double_values(uff, number, s, path)
    data, x = np.asarray(s["data"]), np.asarray(s["x"])
    count = int(s.get("num_pts", len(data)))
    where = f"{path}: dataset {number + 1} ({_nodes(s)}, {_function_words(_function_type(s))})"
    if len(data) > count >= 0:
        # binary: record 1's byte count delimits the values, and bytes after them (a line end before
        # the closing '-1', as Simcenter Test.Lab writes) are no values; ASCII: zeros fill the last line
        if not int(s.get("binary", 0)) and np.any(data[count:] != 0):
            warnings.warn(f"{where} holds {len(data)} values where its header (record 7) gives {count}: read the "
                          f"first {count}", stacklevel=4)
        s["data"], s["x"] = data[:count], x[:count]
    elif len(data) < count:
        s["_cut_short"] = True
        if warn_cut_short:
            warnings.warn(f"{_cut_short_words(s, number, path)}: read the {len(data)}", stacklevel=4)


def _cut_short_words(s, number, path) -> str:
    """``PATH: dataset K (NODES, FUNCTION) holds N of the M values its header (record 7) gives (the
    file is cut short)``: the words on a dataset 58 holding fewer values than its count, at place
    ``number`` (from 0) among the file's datasets."""
    return (f"{path}: dataset {number + 1} ({_nodes(s)}, {_function_words(_function_type(s))}) holds "
            f"{len(s['data'])} of the {int(s['num_pts'])} values its header (record 7) gives (the file is cut short)")


def _complete_frfs(frfs, path) -> list:
    """The FRF sets of a file (datasets 58 read by :func:`_read_sets`) without those cut short
    (fewer values than their header counts, :func:`_as_the_header_says`), which are left out with
    one warning line naming the first, where the file holds complete ones: one cut-short FRF used to
    make the whole file refused ('every FRF of one speed must share the frequency lines'). Where
    every FRF is cut short, each is read as it is, with one warning line each."""
    import warnings

    cut = [s for s in frfs if s.get("_cut_short")]
    if len(cut) == len(frfs):
        for s in cut:
            warnings.warn(f"{_cut_short_words(s, s['_dataset'] - 1, path)}: read the {len(s['data'])}", stacklevel=4)
        return frfs
    if cut:
        kept = len(frfs) - len(cut)
        more = f" (and {len(cut) - 1} more FRF{'s' if len(cut) > 2 else ''})" if len(cut) > 1 else ""
        warnings.warn(f"{_cut_short_words(cut[0], cut[0]['_dataset'] - 1, path)}{more}: left out, the {kept} "
                      f"complete FRF{'s' if kept > 1 else ''} read", stacklevel=4)
    return [s for s in frfs if not s.get("_cut_short")]


def _uneven_double_values(uff, number, s, path):
    """``(x, data)`` of a binary 58b of uneven abscissa and double-precision ordinates, decoded
    from the file: per value an abscissa of 4 bytes (the UFF definition) or 8 (as pyuff writes
    it), told by the byte count of record 1, then 1 or 2 doubles."""
    count, size = int(s.get("num_pts", 0)), int(s.get("n_bytes", 0))
    parts = 1 if int(s["ord_data_type"]) == 4 else 2
    order = "<" if int(s.get("byte_ordering", 1)) == 1 else ">"
    sizes = {width: count * (width + 8 * parts) for width in (4, 8)}
    where = f"{path}: dataset {number + 1} ({_nodes(s)})"
    try:
        start, end = (int(v) for v in uff._block_ind[number])
        with open(path, "rb") as handle:
            handle.seek(start)
            block = handle.read(end - start + 1)
    except (AttributeError, IndexError, OSError, TypeError, ValueError) as error:
        raise InputError(f"{where}: cannot read its binary values again ({type(error).__name__}: {error})") from None
    body = b"".join(block.splitlines(True)[13:])
    # record 1's count tells the width; pyuff writes num_pts x 8 there whatever the layout, so
    # then the data's own length does (4 bytes a value more than a line end or two)
    width = next((w for w, n in sizes.items() if n == size), None) if count > 0 else None
    if width is None and count > 0:
        width = next((w for w in (8, 4) if len(body) >= sizes[w]), None)
    if width is None or len(body) < sizes[width]:
        raise InputError(f"{where}: binary 58b of {count} uneven abscissa values and double-precision ordinates "
                         f"in {len(body)} bytes (record 1 says {size}): expected {sizes[4]} bytes (4-byte abscissa "
                         f"values, as the UFF definition says) or {sizes[8]}")
    fields = [("x", f"{order}f{width}"), ("re", f"{order}f8")] + ([("im", f"{order}f8")] if parts == 2 else [])
    values = np.frombuffer(body, dtype=np.dtype(fields), count=count)
    data = values["re"] if parts == 1 else values["re"] + 1j * values["im"]
    return values["x"].astype(float), data.astype(complex if parts == 2 else float)


def _key(s):
    return (int(s["rsp_node"]), int(s["rsp_dir"]), int(s["ref_node"]), int(s["ref_dir"]),
            round(float(s.get("z_axis_value", 0.0)), 9))


def _frf_units(s, units, path):
    """``(quantity, factor to SI)`` of an FRF set: a response over a force, from its labels or data types."""
    where = f"{path}: FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:{s['ref_dir']}"
    kind = int(s.get("ordinate_spec_data_type", -1))
    if kind not in _FRF_ORDINATES:
        raise InputError(f"{where}: ordinate data type(s) [{kind}]: expected one of 8 (displacement), 11 (velocity), "
                         f"12 (acceleration), or 0/1 (unknown/general) with a unit label; {kind} is {_type_name(kind)}")
    bottom_kind = int(s.get("orddenom_spec_data_type", 0))
    if bottom_kind not in _FORCE_DENOMINATORS:
        raise InputError(f"{where}: denominator data type {bottom_kind}: expected 13 (excitation force) or 9 "
                         f"(reaction force), or 0/1 (unknown/general) with a unit label; {bottom_kind} is "
                         f"{_type_name(bottom_kind)}")
    top, top_factor, top_label = _measure(s, "ordinate", units, abs(int(s["rsp_dir"])) > 3, path, where)
    bottom, bottom_factor, bottom_label = _measure(s, "orddenom", units, abs(int(s["ref_dir"])) > 3, path, where)
    if top in _FRF_OF and bottom in ("force", None):
        quantity = _FRF_OF[top]
        if bottom is None:       # no denominator type or unit: the excitation force in the file's force unit
            bottom_factor = 1.0 / units.force
    elif top in ORDINATE_TYPES.values() and bottom in ("force", None):
        # the label holds the whole unit, e.g. (1/N)*(m/s²); a denominator label only repeats its force
        quantity, bottom_factor = top, 1.0
    else:
        raise InputError(f"{where}: ordinate {_describe(s, 'ordinate', top_label)} over "
                         f"{_describe(s, 'orddenom', bottom_label)}: expected a displacement, velocity or "
                         "acceleration over an excitation force (e.g. m/s^2 over N, g/lbf, (1/N)*(m/s²))")
    if kind in ORDINATE_TYPES and ORDINATE_TYPES[kind] != quantity:
        raise InputError(f"{where}: ordinate data type {kind} ({_type_name(kind)}) but unit {top_label!r} "
                         f"gives {quantity}: the file contradicts itself")
    return quantity, top_factor / bottom_factor


def _type_name(kind):
    return _TYPE_NAMES.get(int(kind), "not a UFF specific data type")


def _describe(s, part, label):
    kind = int(s.get(f"{part}_spec_data_type", 0))
    return f"(data type {kind}, {_type_name(kind)}; unit {label!r})"


def _measure(s, part, units, rotational, path, where):
    """``(quantity or None, factor to SI, label)`` of a set's ordinate numerator (``part='ordinate'``)
    or denominator (``'orddenom'``).

    A unit label, when given, says the unit (dataset 58: labels take precedence); a dataset 164
    of other than SI units must then agree with it. Without a label the specific data type gives
    the quantity and Addendum A of dataset 58 the length and force exponents of the 164 factors
    (the record's own exponents for type 1, general)."""
    kind = int(s.get(f"{part}_spec_data_type", 0))
    label = _label_text(s, f"{part}_axis_units_lab", path)
    if is_none(label):
        if kind in _EXPONENTS:
            length, force = _EXPONENTS[kind][int(rotational)]
        else:          # general (1) and types without a row in the table: the record gives the exponents
            length, force = int(s.get(f"{part}_len_unit_exp", 0)), int(s.get(f"{part}_force_unit_exp", 0))
        return _SPECIFIC.get(kind), 1.0 / (units.length ** length * units.force ** force), label
    parsed = parse_unit(label)
    if parsed is None:
        raise InputError(f"{where}: {_PART_NAMES[part]} unit {label!r} is not understood: expected units such as "
                         "m, mm, um, m/s, mm/s, in/s, m/s^2, g, N, lbf, Pa (see docs/frf-and-measurement.md)")
    factor, (metre, kilogram, _) = parsed
    # the 164 factors a value of this dimension would need: force = kg m s^-2, so F^kg L^(m - kg)
    implied = 1.0 / (units.length ** (metre - kilogram) * units.force ** kilogram)
    if not units.is_si and abs(implied - factor) > 1e-6 * factor:
        raise InputError(f"{where}: {_PART_NAMES[part]} unit {label!r} (factor {factor:g} to SI) contradicts "
                         f"the dataset 164 units {units.description!r} (length factor {units.length:g}, force "
                         f"factor {units.force:g}: {implied:g} to SI): cannot tell which is right")
    return quantity_of(label)[0] if quantity_of(label) else None, factor, label


def _label_text(s, key, path):
    """A label as the file wrote it: pyuff decodes UTF-8 and puts U+FFFD for another encoding's bytes
    (``m/s²`` written in Latin-1); those labels are read again from the file as Latin-1."""
    import re

    label = str(s.get(key, "NONE")).strip()
    if "\ufffd" not in label:
        return label
    pattern = ".".join(re.escape(piece) for piece in label.split("\ufffd"))
    stat = os.stat(path)
    found = set(re.findall(pattern, _latin1(str(path), stat.st_mtime_ns, stat.st_size)))
    return found.pop() if len(found) == 1 else label


@functools.lru_cache(maxsize=1)
def _latin1(path, mtime_ns, size):
    """The file as Latin-1 text (one file kept: the labels of its sets are looked up one by one)."""
    with open(path, encoding="latin-1") as handle:
        return handle.read()


#: frequency units of no dimension the unit parser reads: angular frequency, cycles per minute -> Hz
_FREQUENCY_WORDS = {"rad/s": 1.0 / (2.0 * np.pi), "rad/sec": 1.0 / (2.0 * np.pi), "cpm": 1.0 / 60.0}


def _abscissa_factor(s, expected, path):
    """Factor of the abscissa to s (time) or Hz (frequency), from its data type and unit label."""
    kind = int(s.get("abscissa_spec_data_type", expected))
    name, unit = {_TIME: ("17 (time)", "s"), _FREQUENCY: ("18 (frequency)", "Hz")}[expected]
    where = f"{path}: set {s.get('rsp_node')}:{s.get('rsp_dir')}"
    if kind not in (expected, 0, 1):
        raise InputError(f"{where}: abscissa data type {kind} ({_type_name(kind)}): expected {name}")
    label = _label_text(s, "abscissa_axis_units_lab", path)
    if is_none(label):
        return 1.0
    if expected == _FREQUENCY and label.strip().lower() in _FREQUENCY_WORDS:   # was refused: 'expected Hz'
        return _FREQUENCY_WORDS[label.strip().lower()]
    parsed = parse_unit(label)
    if parsed is None or parsed[1] != ((0, 0, 1) if expected == _TIME else (0, 0, -1)):
        raise InputError(f"{where}: abscissa unit {label!r}: expected {unit} (data type {name})")
    return parsed[0]


def _check_set(s, path):
    where = f"{path}: FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:{s['ref_dir']}"
    data, count = np.asarray(s["data"]), len(np.asarray(s["x"]))
    if len(data) != count:
        raise InputError(f"{where}: {len(data)} values for {count} frequencies: expected one value per frequency")
    if not np.all(np.isfinite(data)):       # was "50 values for 50 frequencies, or non-finite values"
        bad = int(np.flatnonzero(~np.isfinite(data))[0])
        raise InputError(f"{where}: value {bad + 1} of {count} (at {float(np.real(s['x'][bad])):.6g} Hz) is "
                         f"{data[bad]}, and {int(np.sum(~np.isfinite(data)))} in all: expected finite numbers")
    if int(s.get("abscissa_spacing", 0)) == 1 and count > 1 and not float(s.get("abscissa_inc", 1.0)) > 0:
        # every line at one frequency: was "given 10 times at 5 Hz ... (a duplicated channel?)"
        raise InputError(f"{where}: even abscissa spacing with the increment {float(s.get('abscissa_inc')):g} "
                         f"(record 7) for {count} values: expected a frequency step > 0")
    kind = int(s.get("ord_data_type", 5))
    if kind in _REAL_ORDINATES:
        # a magnitude-only export was read as an FRF of phase 0 everywhere (drawn, fitted)
        raise InputError(f"{where}: ordinate data type {kind} ({_REAL_ORDINATES[kind]}): expected complex values "
                         "(5 or 6): an FRF has a magnitude and a phase, and real values (a magnitude-only export) "
                         "would be read as a phase of 0 at every line")


#: dataset 58 record 7 ordinate data types of real values
_REAL_ORDINATES = {2: "real, single precision", 4: "real, double precision"}


def _lookup(table, node, direction, what, path):
    """``(name, sign)`` of a file's node and direction: a direction opposite to the mapped one
    (``-3`` where the mapping says ``+3``, as tools write a sensor mounted upside down) is the
    same channel with its sign flipped."""
    key = (int(node), int(direction))
    if key in table:
        return table[key]
    if key[1] and (key[0], -key[1]) in table:
        name, sign = table[(key[0], -key[1])]
        return name, -sign
    known = ", ".join(f"{n}:{d}={name}" for (n, d), (name, _) in sorted(table.items()))
    raise InputError(f"{path}: {what} node {node} direction {direction} is not in the mapping table "
                     f"(node:direction=name: {known}); give --mapping FILE.csv with columns name,node,direction")


# ---------------------------------------------------------------------------------------------
# header (151), units (164), coordinate systems (18, 2420), nodes (15, 2411), time records (58)
# ---------------------------------------------------------------------------------------------
#: quantities of time records
_TIME_QUANTITIES = ("displacement", "velocity", "acceleration", "force", "pressure")


class UffUnits:
    """Dataset 164: factors from the file's units to SI (SI value = file value / factor).

    Attributes
    ----------
    code : int
    description : str
    length, force, temperature : float
    """

    def __init__(self, code=1, description="SI (no dataset 164)", length=1.0, force=1.0, temperature=1.0):
        self.code, self.description = int(code), str(description).strip()
        self.length, self.force, self.temperature = float(length), float(force), float(temperature)

    @property
    def is_si(self) -> bool:
        return self.length == 1.0 and self.force == 1.0

    def __repr__(self) -> str:
        return (f"UffUnits(code={self.code}, description={self.description!r}, length={self.length:g}, "
                f"force={self.force:g}, temperature={self.temperature:g})")


@reads_pipes(".uff", "Universal File")
def read_uff_info(path) -> dict:
    """Header (dataset 151) and units (dataset 164) of a Universal File.

    Returns
    -------
    dict
        ``program``, ``model_name``, ``description``, ``date`` (from 151, '' where absent),
        ``units`` (:class:`UffUnits`, SI when there is no 164) and ``datasets`` (the dataset
        numbers in file order).
    """
    sets, types = _all_sets(path)
    header = next((s for s in sets if s["type"] == 151), {})
    return {"program": str(header.get("program", "")).strip(), "model_name": str(header.get("model_name", "")).strip(),
            "description": str(header.get("description", "")).strip(),
            "date": str(header.get("date_file_written", "")).strip(), "units": _units(sets, path),
            "datasets": types}


def _all_sets(path):
    uff, types, _, sets = _pyuff_read(path, lines=_check_complete(path))
    for number, (s, t) in enumerate(zip(sets, types)):
        s.setdefault("type", t)
        if t == 58:
            _as_the_header_says(uff, number, s, path)
    return sets, types


def _units(sets, path) -> UffUnits:
    found = [s for s in sets if s["type"] == 164]
    if not found:
        return UffUnits()
    u = found[0]
    units = UffUnits(u.get("units_code", 1), u.get("units_description", ""), u.get("length", 1.0),
                     u.get("force", 1.0), u.get("temp", 1.0))
    if not (units.length > 0 and units.force > 0):
        raise InputError(f"{path}: dataset 164 unit factors length={units.length:g}, force={units.force:g}: "
                         "expected positive numbers")
    return units


@dataclass(frozen=True)
class NodeTable:
    """Node coordinates of a Universal File, in SI and global axes.

    Attributes
    ----------
    numbers : ndarray of int, shape (n_nodes,)
    coordinates : ndarray, shape (n_nodes, 3) [m]
        Global position (dataset 15/2411 coordinates in their definition system, times the
        dataset 164 length factor's inverse).
    axes : ndarray, shape (n_nodes, 3, 3)
        Rows: the node's displacement directions 1, 2, 3 (+X, +Y, +Z of its displacement
        coordinate system) in global axes.
    units : UffUnits
    """

    numbers: np.ndarray
    coordinates: np.ndarray
    axes: np.ndarray
    units: UffUnits

    def position(self, node: int) -> np.ndarray:
        """Global position of a node [m]."""
        return self.coordinates[self._index(node)]

    def direction(self, node: int, code: int) -> np.ndarray:
        """Unit vector of a UFF direction code (1/2/3 = +X/+Y/+Z, negative for minus) at a node."""
        if abs(int(code)) not in (1, 2, 3):
            raise InputError(f"node {node} direction {code}: expected a translation code +-1, +-2 or +-3")
        return np.sign(code) * self.axes[self._index(node), abs(int(code)) - 1]

    def _index(self, node):
        found = np.nonzero(self.numbers == int(node))[0]
        if not found.size:
            raise InputError(f"node {node} is not in the file's node table (nodes {self.numbers.min()} to "
                             f"{self.numbers.max()})")
        return int(found[0])

    def to_dataframe(self):
        """``node,x,y,z`` [m] (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame({"node": self.numbers, "x": self.coordinates[:, 0], "y": self.coordinates[:, 1],
                             "z": self.coordinates[:, 2]})


@reads_pipes(".uff", "Universal File")
def read_uff_nodes(path) -> NodeTable:
    """Nodes of a Universal File (dataset 15 or 2411) in metres and global axes.

    Coordinates are converted with dataset 164 (SI value = file value / length factor); nodes
    defined or displaced in a local Cartesian system are placed through dataset 18 or 2420.

    Raises
    ------
    InputError
        No node dataset, or a node in an undefined or non-Cartesian coordinate system.
    """
    sets, types = _all_sets(path)
    nodes = [s for s in sets if s["type"] in (15, 2411)]
    if not nodes:
        raise InputError(f"{path}: no node coordinates (dataset 15 or 2411) in the file; datasets found: "
                         f"{_datasets_named(int(t) for t in types)}")
    units = _units(sets, path)
    systems = _coordinate_systems(sets, path)
    numbers, coordinates, axes = [], [], []
    for block in nodes:
        local = np.column_stack([block["x"], block["y"], block["z"]]).astype(float) / units.length
        for k, number in enumerate(np.asarray(block["node_nums"], dtype=float).astype(int)):
            origin, rotation = _system(systems, block["def_cs"][k], number, path)
            coordinates.append(origin / units.length + local[k] @ rotation)
            axes.append(_system(systems, block["disp_cs"][k], number, path)[1])
            numbers.append(number)
    return NodeTable(numbers=np.array(numbers), coordinates=np.array(coordinates), axes=np.array(axes),
                     units=units)


def _coordinate_systems(sets, path):
    """``{number: (origin [file units], rotation rows = local axes in global, type)}`` from 18 and 2420."""
    systems = {}
    for s in sets:
        if s["type"] == 18:
            for k, number in enumerate(np.asarray(s["cs_num"]).astype(int)):
                origin = np.asarray(s["ref_o"][k], float)
                ex = np.asarray(s["x_point"][k], float) - origin
                ex = ex / np.linalg.norm(ex)
                in_xz = np.asarray(s["xz_point"][k], float) - origin
                ey = np.cross(in_xz, ex)
                ey = ey / np.linalg.norm(ey)
                systems[int(number)] = (origin, np.array([ex, ey, np.cross(ex, ey)]), int(s["cs_type"][k]),
                                        int(s["ref_cs_num"][k]))
        elif s["type"] == 2420:
            for number, kind, matrix in zip(s["CS_sys_labels"], s["CS_types"], s["CS_matrices"]):
                matrix = np.asarray(matrix, float)
                systems[int(number)] = (matrix[3], matrix[:3], int(kind), 0)
    return systems


def _system(systems, number, node, path):
    """Origin (file units, global) and rotation (rows: local axes in global) of a coordinate system."""
    number = int(number)
    if number == 0 or (number not in systems and number == 1):
        return np.zeros(3), np.eye(3)       # 0 is global; 1 is the global system when not defined
    if number not in systems:
        raise InputError(f"{path}: node {node} uses coordinate system {number}, which the file does not define "
                         "(datasets 18 or 2420)")
    origin, rotation, kind, parent = systems[number]
    if kind != 0:
        raise InputError(f"{path}: node {node} uses coordinate system {number} of type {kind}: only Cartesian "
                         "systems (type 0) are read")
    if parent:
        parent_origin, parent_rotation = _system(systems, parent, node, path)
        return parent_origin + origin @ parent_rotation, rotation @ parent_rotation
    return origin, rotation


@reads_pipes(".uff", "Universal File")
def read_uff_time_records(path, mapping=None, speed: float = 0.0, units=None):
    """Time records (dataset 58/58b, function type 1) of a Universal File.

    A time record is a set of function type 1 (time response), or of type 0 (general or unknown)
    over an abscissa of data type 17 (time). The file's other dataset 58 sets (auto- and
    cross-spectra, FRFs, coherence, PSDs, ..., as analysers export beside the time data) are
    skipped with one warning naming their places in the file, function types and nodes; a file
    without a time record is refused, naming what it holds.

    Each set is a channel: its response node and direction, force or response, and entity name
    (record 6: a recorder that numbers no nodes names its channels). When every channel appears equally
    often, its k-th set belongs to record k (e.g. one record per hit). When some channel appears
    more often than others, the sets are one recording of that many channels: a node and
    direction given twice (an export that numbered two sensors alike) is a channel of its own,
    named ``NODE:DIRECTION#2``, with a warning; with a mapping it is refused (the mapping cannot
    tell which set is the model's channel). So are channels at one node and direction that only
    their entity names tell apart.

    Quantities: displacement, velocity, acceleration, force (ordinate data types 8, 11, 12, 9/13),
    pressure (15, sound pressure 21), or what the unit label says for types 0 (unknown) and 1
    (general). Values are converted to SI with the unit label (``g``, ``mm/s``, ``um``, ``lbf``,
    ...; see :mod:`.unit_labels`), or without a label with the dataset 164 factors.

    Parameters
    ----------
    path : path-like
    mapping : ChannelMap, optional
        Names the channels after the model (forces from its inputs, responses from its outputs);
        default ``NODE:DIRECTION`` (e.g. ``7:+3``).
    speed : float
        Reference rotor speed during the records [rad/s].
    units : dict, optional
        Unit labels declared, or overridden: ``{label: (quantity, factor to SI)}``, e.g.
        ``{"V": ("acceleration", 9.80665 / 0.1)}`` for a 100 mV/g accelerometer recorded in volts
        (as :func:`~rotordyn_modal.io.tdms.read_tdms_records` takes them).

    Returns
    -------
    TimeRecords
        Signals in SI units: N, m, m/s, m/s^2, Pa. NaN, infinite or complex samples are refused.
    """
    from ..analysis.spectra import TimeRecords
    from .tdms import declared_units

    declared = declared_units(units, path)
    sets, types = _all_sets(path)
    found, skipped = _time_sets(sets)
    if not found:
        raise InputError(f"{path}: no time record (dataset 58, function type 1) in the file; {_holdings(sets, types)}")
    file_units = _units(sets, path)
    rate, channels = None, []
    for s in found:
        label = _label_text(s, "ordinate_axis_units_lab", path)
        quantity, factor = declared[label] if label in declared else _time_quantity(s, file_units, path)
        dt = _time_step(s, path) * _abscissa_factor(s, _TIME, path)
        rate = 1.0 / dt if rate is None else rate
        # a channel: node, direction, force or response (a driving point has both) and entity name
        # (a recorder that numbers no nodes names its channels)
        entity = str(s.get("rsp_ent_name", "NONE")).strip()
        key = (int(s.get("rsp_node", 0)), int(s.get("rsp_dir", 0)), quantity == "force",
               "" if is_none(entity) else entity)
        if abs(1.0 / dt - rate) > 1e-6 * rate:
            raise InputError(f"{path}: channel {key[0]}:{key[1]:+d} is sampled at {1 / dt:g} Hz, another at "
                             f"{rate:g} Hz: every record must share one sampling rate")
        label = f"{len(channels) + 1} ({entity!r}, {str(s.get('id1', '')).strip()!r})"     # for messages
        channels.append((key, quantity, _samples(s, path) * float(factor), label))
    names, quantities, signals = _arrange(channels, mapping, path)
    if skipped:       # warned once the records are read: a refused file gets its one error line alone
        import warnings

        records = "the time record" if len(found) == 1 else f"the {len(found)} time records"
        warnings.warn(_skipped_line(path, f"{records} (dataset 58, function type 1)", "time record", skipped,
                                    "spectra and FRFs are computed from the time records: rdm.estimate_frf"),
                      stacklevel=2)
    return TimeRecords(signals=signals, sampling_rate_hz=float(rate), channels=tuple(names),
                       quantities=tuple(quantities), speed=float(speed))


#: dataset 58 function types (record 6), for messages
_FUNCTION_NAMES = {0: "general or unknown", 1: "time response", 2: "auto-spectrum", 3: "cross-spectrum",
                   4: "FRF", 5: "transmissibility", 6: "coherence", 7: "auto-correlation", 8: "cross-correlation",
                   9: "power spectral density", 10: "energy spectral density", 11: "probability density function",
                   12: "spectrum", 13: "cumulative frequency distribution", 14: "peaks valley",
                   15: "stress/cycles", 16: "strain/cycles", 17: "orbit", 18: "mode indicator function",
                   19: "force pattern", 20: "partial power", 21: "partial coherence", 22: "eigenvalue",
                   23: "eigenvector", 24: "shock response spectrum", 25: "finite impulse response filter",
                   26: "multiple coherence", 27: "order function", 28: "phase compensation"}
#: datasets other than 58 by number, for messages
_DATASET_NAMES = {15: "nodes", 18: "coordinate systems", 82: "trace lines", 151: "header", 164: "units",
                  2411: "nodes", 2412: "elements", 2414: "analysis results", 2420: "coordinate systems",
                  2467: "groups", 55: "data at nodes", 58: "function data"}


def _function_type(s) -> int:
    return int(s.get("func_type", -1))


def _is_time_record(s) -> bool:
    """A dataset 58 of samples in time: function type 1 (time response), or 0 (general or unknown)
    over an abscissa of data type 17 (time)."""
    kind = _function_type(s)
    return kind == 1 or (kind == 0 and int(s.get("abscissa_spec_data_type", 0)) == _TIME)


def _time_sets(sets) -> tuple:
    """``(time records, other 58 sets)`` of a file's datasets, each 58 set given its place among
    the file's datasets (``_dataset``, from 1) for messages."""
    records, others = [], []
    for place, s in enumerate(sets, start=1):
        if s["type"] != 58:
            continue
        s.setdefault("_dataset", place)
        (records if _is_time_record(s) else others).append(s)
    return records, others


def _function_words(kind: int) -> str:
    """``'function type 2 (auto-spectrum)'``."""
    return f"function type {kind} ({_FUNCTION_NAMES.get(kind, 'not a UFF function type')})"


def _nodes(s) -> str:
    """``'1:+3'`` (response), or ``'1:+3 / 101:+3'`` when a reference other than the response is given."""
    rsp = (int(s.get("rsp_node", 0)), int(s.get("rsp_dir", 0)))
    ref = (int(s.get("ref_node", 0)), int(s.get("ref_dir", 0)))
    text = f"{rsp[0]}:{rsp[1]:+d}"
    return text if ref in ((0, 0), rsp) else f"{text} / {ref[0]}:{ref[1]:+d}"


def _listed(items, most: int = 4) -> str:
    """Items joined by ', ', the first ``most`` of a longer list and how many in all."""
    items = list(items)
    shown = ", ".join(items[:most])
    return shown if len(items) <= most else f"{shown}, ... ({len(items)} in all)"


def _by_function(sets) -> str:
    """The sets grouped by function type: ``auto-spectra (function type 2): datasets 5, 6 at 1:+3, 2:+3``."""
    groups = {}
    for s in sets:
        groups.setdefault(_function_type(s), []).append(s)
    parts = []
    for kind, group in groups.items():
        places = _listed(str(s["_dataset"]) for s in group)
        nodes = _listed(dict.fromkeys(_nodes(s) for s in group))
        word = "dataset" if len(group) == 1 else "datasets"
        parts.append(f"{_function_words(kind)}: {word} {places} at {nodes}")
    return "; ".join(parts)


def _holdings(sets, types) -> str:
    """What a file without a time record holds, for the message that refuses it."""
    others = _time_sets(sets)[1]
    if others:
        kinds = sorted({_function_type(s) for s in others})
        advice = " (FRFs are read by rotordyn_modal.io.measured.read_measured, frf --measured)" \
            if _FRF in kinds else ""
        return f"dataset 58 function types found: {kinds}: {_by_function(others)}{advice}"
    return f"no dataset 58 at all; datasets found: {_datasets_named(types)}"


def _datasets_named(types) -> str:
    """The dataset numbers of a file, each with its name where known: ``15 (nodes), 164 (units)``."""
    found = sorted(set(types))
    return ", ".join(f"{t} ({_DATASET_NAMES[t]})" if t in _DATASET_NAMES else str(t) for t in found) or "none"


def _skipped_line(path, read: str, kind: str, skipped, note: str) -> str:
    """One line naming the dataset 58 sets a reader skipped beside those it read (the time records'
    and the FRFs' readers).

    Parameters
    ----------
    path : path-like
    read : str
        What was read, ``'the 2 time records (dataset 58, function type 1)'``.
    kind : str
        What the skipped sets are not, ``'time record'``.
    skipped : list of dict
        The skipped sets (pyuff's, with their places ``_dataset``).
    note : str
        Why they were skipped, in parentheses at the end.
    """
    sets = "set" if len(skipped) == 1 else "sets"
    return (f"{path}: read {read} and skipped {len(skipped)} dataset 58 {sets} of no {kind}: "
            f"{_by_function(skipped)} ({note})")


def _samples(s, path) -> np.ndarray:
    """A time record's samples as floats; complex or non-finite samples are refused."""
    data = np.asarray(s["data"])
    where = f"{path}: time record {s.get('rsp_node')}:{int(s.get('rsp_dir', 0)):+d}"
    if data.dtype.kind == "c":
        raise InputError(f"{where} holds complex samples: expected real numbers (a time record)")
    data = data.astype(float)
    if not np.all(np.isfinite(data)):
        bad = int(np.argmax(~np.isfinite(data)))
        raise InputError(f"{where}: sample {bad} is {data[bad]}: expected finite samples")
    return data


def _arrange(channels, mapping, path):
    """Names, quantities and signals (n_records, n_channels, n_samples) of the sets, in file order."""
    from collections import Counter

    counts = Counter(key for key, *_ in channels)
    if len(set(counts.values())) == 1:               # every channel as often: record k holds the k-th of each
        keys = list(counts)
        columns = {key: [c for c in channels if c[0] == key] for key in keys}
        records = [[columns[key][r] for key in keys] for r in range(counts[keys[0]])]
    else:                                            # one recording; a repeated channel is one more channel
        records = [channels]
    _check_alike(records[0], mapping, path)
    seen = Counter()
    names = []
    for key, quantity, _, _ in records[0]:
        name = _channel_name(key[:2], quantity, mapping, path)
        seen[name] += 1
        names.append(name if seen[name] == 1 else f"{name}#{seen[name]}")
    lengths = {len(c[2]) for c in channels}
    if len(lengths) != 1:
        raise InputError(f"{path}: time records of {sorted(lengths)} samples: every record must hold every "
                         "channel with as many samples")
    quantities = [c[1] for c in records[0]]
    for record in records[1:]:
        for (key, quantity, _, _), expected in zip(record, quantities):
            if quantity != expected:
                raise InputError(f"{path}: channel {key[0]}:{key[1]:+d} holds {expected} in one record and "
                                 f"{quantity} in another: expected one quantity per channel")
    signs = [_sign(key[:2], mapping, quantity) for key, quantity, _, _ in records[0]]
    signals = np.array([[sign * c[2] for sign, c in zip(signs, record)] for record in records])
    return names, quantities, signals


def _check_alike(record, mapping, path):
    """Channels of one record at one node and direction (both forces or both responses): a repeat in
    a recording, or channels told apart by their entity names only. Warn (the later ones are
    ``NODE:DIRECTION#2``, ...), or refuse with a mapping, which cannot tell which is its channel."""
    import warnings
    from collections import defaultdict

    alike = defaultdict(list)
    for key, _, _, label in record:
        alike[key[:3]].append(label)
    for (node, direction, _), labels in alike.items():
        if len(labels) < 2:
            continue
        text = (f"{path}: node {node} direction {direction:+d} is given by the time records {' and '.join(labels)} "
                f"of one recording of {len(record)} channels")
        if mapping is not None:
            raise InputError(f"{text}: the mapping cannot tell which is its channel; read the file without a "
                             "mapping (channels NODE:DIRECTION, the repeats NODE:DIRECTION#2) or correct its nodes")
        repeats = ", ".join(f"{node}:{direction:+d}" + (f"#{k + 1}" if k else "") for k in range(len(labels)))
        warnings.warn(f"{text}: read as channels {repeats}", stacklevel=4)


def _time_quantity(s, units, path):
    """``(quantity, factor to SI)`` of a time record."""
    kind = int(s.get("ordinate_spec_data_type", -1))
    direction = int(s.get("rsp_dir", 0))
    where = f"{path}: time record {s.get('rsp_node')}:{direction}"
    if kind not in _SPECIFIC and kind not in (0, 1):
        raise InputError(f"{where}: ordinate data type {kind} ({_type_name(kind)}): expected 8 (displacement), "
                         "11 (velocity), 12 (acceleration), 9/13 (force), 15/21 (pressure), or 0/1 "
                         "(unknown/general) with a unit label")
    label = _label_text(s, "ordinate_axis_units_lab", path)
    if not is_none(label) and parse_unit(label) is None:   # a voltage, a level: the caller knows its factor
        raise InputError(f"{where}: ordinate unit {label!r} is not understood: expected units such as m, mm, um, m/s, "
                         "mm/s, in/s, m/s^2, g, N, lbf, Pa, or declare it: read_uff_time_records(..., units="
                         f"{{{label!r}: (quantity, factor to SI)}}), e.g. a voltage with its sensor's sensitivity")
    quantity, factor, label = _measure(s, "ordinate", units, abs(direction) > 3, path, where)
    if kind in _SPECIFIC and quantity != _SPECIFIC[kind]:
        raise InputError(f"{where}: ordinate data type {kind} ({_type_name(kind)}) but unit {label!r} is "
                         f"{'a ' + quantity if quantity else 'no such quantity'}: the file contradicts itself")
    if quantity not in _TIME_QUANTITIES:
        raise InputError(f"{where}: ordinate data type {kind} ({_type_name(kind)}) with unit {label!r}: "
                         "cannot tell what was measured; expected a unit of displacement, velocity, "
                         "acceleration, force or pressure (m, m/s, m/s^2, g, N, Pa, ...)")
    return quantity, factor


def _time_step(s, path):
    """Sampling interval (abscissa units): the header's increment, or the abscissa's (6 digits in ASCII)."""
    dt = float(s.get("abscissa_inc", 0.0))
    if int(s.get("abscissa_spacing", 1)) == 1 and dt > 0:
        return dt
    x = np.asarray(s["x"], dtype=float)
    dt = (x[-1] - x[0]) / (len(x) - 1) if len(x) > 1 else 0.0
    even = x[0] + dt * np.arange(len(x))
    if not dt > 0 or np.any(np.abs(x - even) > 1e-5 * np.abs(x) + 1e-9 * dt):
        raise InputError(f"{path}: time record {s.get('rsp_node')}:{s.get('rsp_dir')} is not evenly sampled")
    return float(dt)


def _channel_name(key, quantity, mapping, path):
    node, direction = key
    if mapping is None:
        return f"{node}:{direction:+d}"
    table = mapping.inputs if quantity == "force" else mapping.outputs
    what = "force" if quantity == "force" else "response"
    return _lookup(table, node, direction, what, path)[0]


def _sign(key, mapping, quantity):
    if mapping is None:
        return 1.0
    table = mapping.inputs if quantity == "force" else mapping.outputs
    return _lookup(table, *key, "channel", "")[1]


def place_channels(model, nodes, mapping):
    """The model with its sensors and excitations placed at their mapped nodes and directions.

    Parameters
    ----------
    model : Model
    nodes : NodeTable
    mapping : ChannelMap
        Node and direction of each channel (channels not in the mapping keep their place).

    Returns
    -------
    Model
    """
    from ..model.machine import Model

    data = model.to_dict()
    for table, entries in (("sensors", mapping.outputs), ("excitations", mapping.inputs)):
        placed = {name: (node, code, sign) for (node, code), (name, sign) in entries.items()}
        for item in data.get(table, []):
            if item["name"] in placed:
                node, code, sign = placed[item["name"]]
                item["position"] = [float(v) for v in nodes.position(node)]
                item["direction"] = [float(v) for v in sign * nodes.direction(node, code)]
    return Model.from_dict(data, model.source)
