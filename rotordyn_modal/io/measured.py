"""Measured FRFs: plain CSV files, the channel mapping table, and dispatch by file type.

A measured data set is a list of :class:`~rotordyn_modal.analysis.frf.FRFResult`,
one per spin speed, each with ``H`` of shape (n_outputs, n_inputs, n_freq)
named after the model's ``[[sensors]]`` and ``[[excitations]]`` (NaN where a
pair was not measured) and ``coherence`` when the file has it.

CSV layout (one row per output, input and frequency; ``--out`` of ``frf`` writes it)::

    speed_rpm,frequency_hz,output,input,real,imag[,coherence][,quantity]

``speed_rpm`` may be left out (0); ``magnitude,phase_deg`` may replace ``real,imag``; ``quantity``
(receptance, mobility or accelerance) is read in any case (``Receptance``). A
``unit`` column (what ``frf --out`` writes with ``--units us``: ``in/lbf``, ``g/lbf``; or an SI
label such as ``m/N``) gives each row's unit: the values are converted to SI and the labels
give the quantity (they must agree with a ``quantity`` column).

Mapping table (CSV ``name,node,direction[,sign]``): which UFF node and
direction code (1/2/3 = +X/+Y/+Z, negative for minus, 4-6 rotations) is which
sensor or excitation of the model; ``sign`` -1 flips a channel. Without a table
the default mapping is used: sensor k (from 1) is node k, excitation k is node
100 + k, and the direction code is the model axis nearest to the channel's
direction (signed).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..analysis.frf import FRFResult
from ..errors import InputError
from ..model._table import visible_names
from .channels import _LARGEST_VALUE, ChannelMap, assemble, default_mapping, read_mapping, unknown_columns, \
    unread_columns

__all__ = ["read_measured", "read_csv", "write_csv", "read_mapping", "default_mapping", "ChannelMap",
           "check_mapping_used", "is_universal_file", "sniffed_ending", "piped_copy"]

_QUANTITIES = ("receptance", "mobility", "accelerance")


def read_measured(path, model, mapping=None) -> list[FRFResult]:
    """Read measured FRFs (UFF 58/58b ``.uff``/``.unv``, or CSV) into model-named FRF sets.

    Parameters
    ----------
    path : str or path-like
    model : Model
        Gives the sensor and excitation names (and the default mapping).
    mapping : str, path-like or ChannelMap, optional
        Mapping table for UFF files (see the module docstring).

    Returns
    -------
    list of FRFResult
        One per speed, sorted by speed; ``engine='measured'``.
    """
    from .limits import input_path, is_fifo

    path = input_path(path, "measured-data file")
    if is_fifo(path):
        return _read_from_pipe(path, model, mapping)
    if not path.is_file():
        if path.is_symlink() and not path.exists():
            raise InputError(f"{path}: a symbolic link that leads to no file (to {os.readlink(path)}, a missing file "
                             "or a loop of links)")
        raise InputError(f"{path}: measured data file not found" if not path.exists() else
                         f"{path}: expected a measured data file, not a "
                         f"{'folder' if path.is_dir() else 'device (a terminal, /dev/zero: its size is not known before reading)'}")
    from .limits import refuse_compressed

    try:
        with open(path, "rb") as handle:
            head = handle.read(512)
    except OSError as error:   # a file without read permission: PermissionError, exit 1
        raise InputError(f"{path}: cannot read the measured-data file ({error.strerror or error})") from None
    refuse_compressed(head, path, "measured-data file")   # m.uff.gz was "unknown measured data format '.gz'"
    if path.suffix.lower() in UFF_ENDINGS or _universal_head(head):   # is_universal_file of the head read
        from .uff import NoFunctionData, read_uff58

        if mapping is None or isinstance(mapping, ChannelMap):
            channel_map = mapping or default_mapping(model)
        else:
            channel_map = read_mapping(mapping, model)
        try:
            return read_uff58(path, model, channel_map)
        except NoFunctionData as error:
            raise _with_2414(error, path) from None
    ending = path.suffix.lower() or sniffed_ending(head)    # /dev/stdin of a file, a name without an ending
    if ending in TABLE_ENDINGS:
        if mapping is not None and not isinstance(mapping, ChannelMap):
            read_mapping(mapping, model)   # a missing or broken table named is refused, never passed over
        return read_csv(path, model)
    time_records = (f": a {ending} file holds time records, not FRFs: read them with rdm.read_tdms_records "
                    "and compute the FRFs with rdm.estimate_frf (docs/frf-and-measurement.md, 'From time records')"
                    if ending == ".tdms" else "")
    raise InputError(f"{path}: unknown measured data format {path.suffix!r}: expected .uff/.unv "
                     "(UFF 58/58b) or a text table .csv (also .txt or .tsv, as other tools export it)"
                     f"{time_records}")


def _read_from_pipe(path, model, mapping):
    """:func:`read_measured` of a pipe: its bytes copied into a temporary file
    (:func:`piped_copy`), read, and removed; messages name the pipe."""
    from .limits import named_as

    with piped_copy(path) as copy, named_as(copy, path):
        return read_measured(copy, model, mapping)


def _with_2414(error, path) -> InputError:
    """The FRF reader's refusal of a file without dataset 58, with what its dataset 2414 sets hold
    (FE results: mode shapes read by ``modes --measured``, frequency response sets that are no
    FRFs, static results)."""
    from .uff_modes import describe_2414

    held = describe_2414(path) if 2414 in error.types else ""
    return InputError(f"{error}: {held}") if held else error


#: endings of the Universal Files a mapping table places the channels of
UFF_ENDINGS = (".uff", ".unv", ".uf")


def is_universal_file(path) -> bool:
    """True for a Universal File: one of :data:`UFF_ENDINGS`, or a file of another ending (tools
    write ``.ufb``, ``.bunv``, ``.frf``, ``.58``, ...; a ``.txt`` as users rename a ``.unv`` to attach
    it to a message) whose first line, after blank lines and a byte-order mark, is the ``-1`` that
    opens a dataset, followed by a dataset number (``58``, ``58b``, ``151``): no table's header.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    bool
    """
    path = Path(path)
    if path.suffix.lower() in UFF_ENDINGS:
        return True
    if not path.is_file():   # never opens a pipe (it could wait)
        return False
    try:
        with open(path, "rb") as handle:
            head = handle.read(512)
    except OSError:
        return False
    return _universal_head(head)


def _universal_head(head: bytes) -> bool:
    """True when the first bytes of a file open a Universal File's dataset (:func:`is_universal_file`)."""
    import re

    lines = [line.strip() for line in head.removeprefix(b"\xef\xbb\xbf").splitlines() if line.strip()]
    return len(lines) >= 2 and lines[0] == b"-1" and re.fullmatch(rb"\d{1,6}b?(\s.*)?", lines[1]) is not None


def sniffed_ending(head: bytes) -> str:
    """The ending of the measured-data format that a file's first bytes (512 are enough) show:
    ``'.tdms'`` (npTDMS's 'TDSm'), ``'.uff'`` (:func:`is_universal_file`'s test), else ``'.csv'``
    (a text table, which the CSV reader refuses on one line if it is none)."""
    from .uff import TDMS_MAGIC

    if head[:4] == TDMS_MAGIC:
        return ".tdms"
    return ".uff" if _universal_head(head) else ".csv"


#: endings whose name says a measured file's format (any other is told from the bytes)
_KNOWN_ENDINGS = (".uff", ".unv", ".uf", ".csv", ".txt", ".tsv", ".tdms")


def piped_copy(path):
    """A pipe's bytes (``<(cat m.uff)``, ``/dev/stdin`` of a pipe, a FIFO a program writes to) read
    once, up to the measured-data limit, into a temporary file removed at the end
    (:func:`.limits.pipe_copied`, which the UFF and TDMS readers share): named ``pipe`` and the
    pipe's ending when it is one of the formats', else the ending its bytes show
    (:func:`sniffed_ending`).

    Parameters
    ----------
    path : path-like
        A named pipe (:func:`.limits.is_fifo`).

    Returns
    -------
    context manager
        Yielding the copy's :class:`~pathlib.Path`.

    Raises
    ------
    InputError
        The pipe holds more than the limit, or nothing writes to it (:func:`.limits.read_limited`).
    """
    from .limits import pipe_copied

    ending = Path(path).suffix.lower()
    return pipe_copied(path, ending if ending in _KNOWN_ENDINGS else sniffed_ending)
#: endings of a measured FRF table read as CSV (``,``, ``;`` or tab separated: :mod:`.csv_tables`);
#: test rigs and spreadsheets export tab-separated text as .txt or .tsv
TABLE_ENDINGS = (".csv", ".txt", ".tsv")


def check_mapping_used(mapping, measured=None, out=None) -> None:
    """Refuse a mapping table (the command line's ``--mapping``) where no Universal File is read
    (``measured``) or written (``out``): a CSV names its channels, so the table would be passed
    over without a word (a missing or empty one included).

    Parameters
    ----------
    mapping, measured, out : str, path-like or None
        The files named (None: not given).

    Raises
    ------
    InputError
    """
    if mapping is None or (out and str(out).lower().endswith(UFF_ENDINGS)) or (measured and
                                                                                is_universal_file(measured)):
        return
    raise InputError(f"--mapping {mapping}: expected it only beside a Universal File (--measured or --out "
                     "FILE.uff): it places a UFF file's channels, and a CSV names its own (leave --mapping out)")


def _check_column(table, column, name, path, valid, expected) -> None:
    """Refuse the first row of ``column[name]`` (one value per row of ``table``) that is not
    ``valid``, naming the column, the value and the row's channel pair and frequency."""
    from .csv_tables import file_line

    values = column[name]
    bad = np.flatnonzero(~valid(values))
    if bad.size:
        first = int(bad[0])
        row = table.iloc[first]
        where = f"{row.get('output', '?')} / {row.get('input', '?')} at {column['frequency_hz'][first]:g} Hz"
        typed = str(row.get(name, "")).strip()
        shown = f"{values[first]:g}"
        if not np.isfinite(values[first]) and typed and typed.lower().lstrip("+-") not in ("inf", "infinity", "nan"):
            shown = f"{typed} (read as {shown}: beyond a double)"      # 1e400 was shown as 'inf' only
        raise InputError(f"{path}: {name} = {shown} in data row {first + 1} (line {file_line(table, first)}, "
                         f"{where}; {bad.size} such "
                         f"row(s)): expected {expected}")


#: how far a CSV's magnitude [relative] and phase [deg] may stray from its real and imag columns
#: (a spreadsheet's rounding to 3 or 4 digits passes; an edited or rescaled column does not)
_POLAR_AGREEMENT = (1e-2, 1.0)


def _check_polar_agrees(table, column, values, path) -> None:
    """Refuse a CSV whose ``magnitude`` (and ``phase_deg``) columns, given beside ``real`` and
    ``imag`` (as ``frf --out`` writes them), say another FRF: the file would be read by its real
    and imag columns alone, an edited magnitude passed over without a word."""
    if "magnitude" not in column:
        return
    relative, degrees = _POLAR_AGREEMENT
    size = np.abs(values)
    magnitude = column["magnitude"]
    with np.errstate(invalid="ignore"):
        # a value past _LARGEST_VALUE is refused as such by the check after this one
        judged = np.isfinite(magnitude) & (size <= _LARGEST_VALUE) & (np.abs(magnitude) <= _LARGEST_VALUE)
        bad = judged & ~(np.abs(magnitude - size) <= relative * np.maximum(size, np.abs(magnitude)))
        what = "|real + i imag|"
        if "phase_deg" in column and not bad.any():
            turn = np.angle(values, deg=True) - column["phase_deg"]
            bad = judged & (size > 0) & np.isfinite(turn) & ~(np.abs((turn + 180.0) % 360.0 - 180.0) <= degrees)
            what = "the phase of real + i imag"
    if not bad.any():
        return
    from .csv_tables import file_line

    first = int(np.flatnonzero(bad)[0])
    row = table.iloc[first]
    name, given = ("magnitude", magnitude) if what.startswith("|") else ("phase_deg", column["phase_deg"])
    said = size[first] if name == "magnitude" else np.angle(values[first], deg=True)
    raise InputError(f"{path}: {name} = {given[first]:g} in data row {first + 1} (line {file_line(table, first)}, "
                     f"{row.get('output', '?')} / {row.get('input', '?')} at {column['frequency_hz'][first]:g} Hz; "
                     f"{int(bad.sum())} such row(s)): expected {what} = {said:g}, as its real and imag columns "
                     f"give it (within {relative:g} relative, {degrees:g} deg): the two say different FRFs; keep "
                     "real,imag or magnitude,phase_deg")


def _universal_hint(table) -> str:
    """What to add to a CSV refusal whose header is a Universal File's first line (``    -1``):
    such a file named .csv or .txt was refused as "found -1", naming no format."""
    if [str(c).strip() for c in table.columns] == ["-1"]:
        return " (the file begins as a Universal File, '    -1': name it .uff or .unv to read it as one)"
    return ""


#: cells of the row of display formats Simcenter Testlab writes under the units row of a text export
_DISPLAY_FORMATS = {"linear", "log", "phase", "real", "imaginary", "db", "amplitude", "magnitude"}


def _refuse_testlab_layout(data: bytes, path) -> None:
    """Refuse, on one line, a Simcenter Testlab text export of FRFs: metadata lines, a row of
    units (``Hz  g/N  °`` for each FRF), a row of display formats (``Linear  Log  Phase``), then
    the numbers. It names no output and input channel in its columns (was "cannot read as CSV
    (Error tokenizing data ...)"), so it cannot be placed on the model's sensors and excitations."""
    import re

    from .text import decode_text

    lines = decode_text(data[:65536]).splitlines()[:200]
    for k in range(len(lines) - 1):
        formats = [c.strip() for c in re.split(r"[\t;]", lines[k + 1]) if c.strip()]
        units = [c.strip() for c in re.split(r"[\t;]", lines[k]) if c.strip()]
        if (len(formats) >= 2 and all(f.lower() in _DISPLAY_FORMATS for f in formats) and units
                and units[0].lower() in ("hz", "khz", "s")):
            functions = max(1, sum(u.lower() in ("hz", "khz", "s") for u in units))
            raise InputError(f"{path}: line {k + 1}: units {', '.join(units)} over display formats "
                             f"{', '.join(formats)} (line {k + 2}), as Simcenter Testlab's text export writes them: "
                             f"its columns name no output and input channel of its {functions} function(s), so they "
                             "cannot be placed on the model's sensors and excitations; export the FRFs as UFF 58 "
                             "(nodes and directions, placed by --mapping), or write the columns frequency_hz,output,"
                             "input,magnitude [unit],phase_deg, one line per frequency and channel pair")


def read_csv(path, model) -> list[FRFResult]:
    """Read the plain CSV layout (see the module docstring): also with ``;`` or tabs between the
    cells and decimal commas, header names in any case with their units (``Frequency [kHz]``,
    ``Phase [rad]``, ``Real [g/N]``; :mod:`.csv_tables`)."""
    from .csv_tables import numbers, read_csv_table
    from .limits import read_limited

    from .uff import TDMS_MAGIC, TDMS_WORDS

    data = read_limited(path, "measured", "measured-data file")
    if data[:4] == TDMS_MAGIC:     # was "cannot read as CSV (Error tokenizing data ...)"
        raise InputError(f"{path}: {TDMS_WORDS}")
    _refuse_testlab_layout(data, path)
    _refuse_columns_early(data, path)
    _refuse_beyond_memory(data, path)
    table, decimal = read_csv_table(data, path, "as CSV")
    table = _units_row_folded(table, path)
    table, scales, value_unit = _canonical_columns(table, path)
    _refuse_missing_columns(table, path)
    if table.empty:   # was refused as "quantity column holds []", of a column no line filled
        raise InputError(f"{path}: a header and no data line: expected a line per frequency and channel pair")
    column = {name: numbers(table, name, path, decimal) * scales.get(name, 1.0) for name in
              ("speed_rpm", "frequency_hz", "real", "imag", "magnitude", "phase_deg", "coherence")
              if name in table.columns}
    parts = ("real", "imag") if {"real", "imag"} <= set(table.columns) else ("magnitude", "phase_deg")
    for name in ("frequency_hz", *parts):
        _check_column(table, column, name, path, lambda x: np.isfinite(x), "a finite number")
    if parts[0] == "real":
        values = column["real"] + 1j * column["imag"]
        _check_polar_agrees(table, column, values, path)
    else:   # a level in dB is negative: read as a linear magnitude it would be a wrong FRF
        _check_column(table, column, "magnitude", path, lambda x: x >= 0,
                      "a magnitude >= 0 (a linear FRF, not a level in dB)")
        values = column["magnitude"] * np.exp(1j * np.radians(column["phase_deg"]))
    quantity = _csv_quantity(table, path)
    if value_unit is not None:
        table["unit"] = value_unit
    if "unit" in table.columns:
        quantity, factors = _csv_units(table, quantity, model, path)
        values = values * factors
    unread_columns([c for c in table.columns if c not in _KNOWN_COLUMNS], path, _LAYOUT)
    records = {"speed_rpm": column.get("speed_rpm", np.zeros(len(table))), "frequency_hz": column["frequency_hz"],
               "output": _names(table, "output"), "input": _names(table, "input"),
               "value": values, "coherence": column.get("coherence")}
    return assemble(records, model, quantity, str(path))


def _refuse_missing_columns(table, path) -> None:
    """Refuse a table (its header names made the layout's) without the columns an FRF needs."""
    needed = {"frequency_hz", "output", "input"}
    if not needed <= set(table.columns) or not ({"real", "imag"} <= set(table.columns)
                                                or {"magnitude", "phase_deg"} <= set(table.columns)):
        raise InputError(f"{path}: expected the columns speed_rpm,frequency_hz,output,input,real,imag"
                         f"[,coherence] (or magnitude,phase_deg); found {visible_names(map(str, table.columns))}"
                         f"{_universal_hint(table)}")


#: memory a CSV table takes while it is read, per byte of the file and per cell [bytes]: the text,
#: its bytes and the parser's, and each cell a string of its own in the table (measured with
#: ``/usr/bin/time -v``: 600,000 lines of 7 cells, 41.6 MB, took 335 MB beyond the interpreter's;
#: this estimate says 419 MB)
_BYTES_PER_BYTE, _BYTES_PER_CELL = 3, 70


def _refuse_beyond_memory(data: bytes, path) -> None:
    """Refuse, before it is parsed, a CSV file whose table would not fit in the memory available
    (:func:`.._limits.memory_problem`): a 512 MB file, within the size limit, would take about 4 GB
    (in proportion to the 41.6 MB file's 335 MB)."""
    from .limits import refuse_beyond_memory

    cells = data.count(b",") + data.count(b";") + data.count(b"\t") + data.count(b"\n") + 1
    refuse_beyond_memory(path, _BYTES_PER_BYTE * len(data) + _BYTES_PER_CELL * cells,
                         f"{len(data) / 1e6:.3g} MB, about {cells:,} cells",
                         "split it (a file per speed or per channel pair), or write it as UFF 58b (binary)")


#: a CSV file over this many bytes has its header looked at before the whole table is read [bytes]
EARLY_HEADER_BYTES = 1 << 20
#: lines of such a file read to look at its header (comments, the header, a units row...)
EARLY_HEADER_LINES = 200


def _refuse_columns_early(data: bytes, path) -> None:
    """Refuse a large CSV file (over :data:`EARLY_HEADER_BYTES`) whose header lacks the columns
    an FRF needs from its first lines, before the whole table is read: a 114 MB file of
    ``a,b,c`` rows took 17 s and 4.7 GB of memory to be told so (the measured-data limit, 512
    MB, would have needed about 20 GB). The message is :func:`_refuse_missing_columns`'s; a
    head that cannot be read alone (a quoted cell over the cut, UTF-16) is left to the whole
    table's reading."""
    from .csv_tables import read_csv_table

    if len(data) <= EARLY_HEADER_BYTES:
        return
    end = -1
    for _ in range(EARLY_HEADER_LINES):
        end = data.find(b"\n", end + 1)
        if end < 0:
            return
    try:
        table, _ = read_csv_table(data[:end + 1], path, "as CSV")
        table, _, _ = _canonical_columns(_units_row_folded(table, path), path)
    except (InputError, UnicodeError):
        return
    _refuse_missing_columns(table, path)


#: header names of the CSV columns -> the column
_ALIASES = {"frequency": "frequency_hz", "freq": "frequency_hz", "freq_hz": "frequency_hz", "f": "frequency_hz",
            "f_hz": "frequency_hz",
            "speed": "speed_rpm", "rpm": "speed_rpm", "phase": "phase_deg", "mag": "magnitude",
            "imaginary": "imag", "re": "real", "im": "imag"}
#: units a header may give its column, and the factor to the column's own unit
_HEADER_UNITS = {"frequency_hz": {"hz": 1.0, "khz": 1e3, "rad/s": 0.5 / np.pi, "cpm": 1.0 / 60.0, "1/min": 1.0 / 60.0},
                 "speed_rpm": {"rpm": 1.0, "1/min": 1.0, "r/min": 1.0, "rev/min": 1.0, "rad/s": 30.0 / np.pi, "hz": 60.0,
                               "rps": 60.0, "r/s": 60.0, "rev/s": 60.0},
                 "phase_deg": {"deg": 1.0, "°": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / np.pi}}
_VALUE_COLUMNS = ("real", "imag", "magnitude")
#: the layout's columns, as messages name them
_LAYOUT = "speed_rpm,frequency_hz,output,input,real,imag,magnitude,phase_deg,coherence,quantity,unit"
#: every column the layout reads (after :data:`_ALIASES`); others are not read
_KNOWN_COLUMNS = ("speed_rpm", "frequency_hz", "output", "input", "real", "imag", "magnitude", "phase_deg", "coherence",
                  "quantity", "unit")


def _units_row_folded(table, path):
    """The table with a row of units under its header (``Hz,,,g/N,g/N`` under
    ``frequency,output,input,real,imag``, as data recorders and spreadsheets export them) folded
    into the header names (``frequency [Hz]``, ``real [g/N]``), read then as header units are;
    unchanged without such a row. A units row is the first row when it holds no number and its
    frequency column holds text (a unit)."""
    from .csv_tables import split_header

    if table.empty:
        return table
    first = {column: str(table.iloc[0][column]).strip() for column in table.columns}
    frequency = [c for c in table.columns if _ALIASES.get(split_header(c)[0], split_header(c)[0]) == "frequency_hz"]
    if not frequency or not first[frequency[0]] or any(_is_number(cell) for cell in first.values()):
        return table
    renamed = {}
    for column, unit in first.items():
        if not unit or unit == "-" and split_header(column)[0] in ("output", "input"):
            continue
        name, given = split_header(column)
        if given is not None and given != unit:
            raise InputError(f"{path}: column {column!r}: unit [{given}] in the header and {unit!r} on the line "
                             "under it (a row of units): expected one unit")
        renamed[column] = f"{column} [{unit}]" if given is None else column
    folded = table.iloc[1:].rename(columns=renamed).reset_index(drop=True)
    folded.attrs = {**table.attrs, "lines": table.attrs.get("lines", [])[1:]}
    return folded


def _is_number(cell: str) -> bool:
    """True for a cell that reads as a number (a decimal comma too)."""
    try:
        float(cell.replace(",", "."))
    except ValueError:
        return False
    return True


def _canonical_columns(table, path):
    """The table with its header names made the layout's (``Frequency [kHz]`` -> ``frequency_hz``),
    the factors of the numeric columns to the layout's units, and the unit the header gives the
    FRF values (``Real [m/s^2/N]``; None without one).

    Returns
    -------
    (DataFrame, dict, str or None)
    """
    from .csv_tables import split_header

    names, scales, value_units = {}, {}, set()
    for cell in table.columns:
        name, unit = split_header(cell)
        name = _ALIASES.get(name, name)
        if name in names.values():
            first = next(c for c, n in names.items() if n == name)
            raise InputError(f"{path}: two columns are {name} ({first!r} and {cell!r}): expected each column once")
        names[cell] = name
        if unit is None:
            continue
        if name in _HEADER_UNITS:
            factor = _HEADER_UNITS[name].get(unit.lower())
            if factor is None:
                raise InputError(f"{path}: column {cell!r}: unit {unit!r} not understood: expected one of "
                                 f"{', '.join(_HEADER_UNITS[name])}")
            scales[name] = factor
        elif name in _VALUE_COLUMNS:
            value_units.add(unit)
        elif name != "coherence" or unit not in ("-", "1"):
            raise InputError(f"{path}: column {cell!r}: a unit {unit!r} where the column has none")
    unknown_columns([c for c, n in names.items() if n not in _KNOWN_COLUMNS], _KNOWN_COLUMNS + tuple(_ALIASES), path,
                    _LAYOUT)
    if len(value_units) > 1:
        raise InputError(f"{path}: the FRF columns give the units {', '.join(sorted(map(repr, value_units)))}: "
                         "expected one unit of every value")
    value_unit = value_units.pop() if value_units else None
    if value_unit is not None and "unit" in names.values():
        raise InputError(f"{path}: the FRF values' unit is given in their header ({value_unit!r}) and in a unit "
                         "column: expected one of them")
    return table.rename(columns=names), scales, value_unit


def _names(table, name) -> np.ndarray:
    """A column's channel names, an object array of the cells' own strings (a numpy string array
    took the longest name's 4 bytes a character for every line)."""
    return np.array([str(v) for v in table[name]], dtype=object)


def _csv_quantity(table, path):
    """The FRF quantity the ``quantity`` column names, in any case (``Receptance``, as test-lab
    exports write it); ``receptance`` without the column."""
    if "quantity" not in table.columns:
        return "receptance"
    found = {str(v) for v in table["quantity"]}
    read = {v.strip().lower() for v in found}
    if len(read) != 1 or not read <= set(_QUANTITIES):
        raise InputError(f"{path}: quantity column holds {sorted(found)}: expected one of "
                         f"{', '.join(_QUANTITIES)} (in any case), the same in every row")
    return read.pop()


def _csv_units(table, quantity, model, path):
    """The quantity and the factor to SI of every row of a CSV with a ``unit`` column (what
    ``frf --out`` writes with ``--units us``: ``in/lbf``, ``in/s/lbf``, ``g/lbf``, ``... in`` over a
    moment), or a refusal of a label that says no FRF of a known quantity. Without a
    ``quantity`` column the labels give it; with one they must agree with it.

    Returns
    -------
    (str, ndarray of shape (n_rows,))
    """
    from ..units import FRF_OUTPUT_KINDS, ratio_scale
    from .csv_tables import file_line
    from .unit_labels import quantity_of

    moments = {x.name for x in model.excitations if getattr(x, "kind", "force") == "moment"}
    given = "quantity" in table.columns
    found, factors = set(), np.empty(len(table))
    for row, (label, source) in enumerate(zip(table["unit"], table["input"])):
        kind = "moment" if str(source) in moments else "force"
        known = {ratio_scale(FRF_OUTPUT_KINDS[q], kind, system)[1]: (q, 1.0 / ratio_scale(FRF_OUTPUT_KINDS[q], kind,
                                                                                          system)[0])
                 for q in _QUANTITIES for system in ("si", "us")}
        read = known.get(str(label).strip()) or (quantity_of(label) if kind == "force" else None)
        if read is None or read[0] not in _QUANTITIES or (given and read[0] != quantity):
            wanted = [lab for lab, (q, _) in known.items() if not given or q == quantity]
            raise InputError(f"{path}: column unit line {file_line(table, row)} = {str(label)[:40]!r}: expected a unit of "
                             f"{quantity if given else ' or '.join(_QUANTITIES)} over a {kind} "
                             f"({', '.join(wanted)})")
        found.add(read[0])
        factors[row] = read[1]
    if len(found) > 1:
        raise InputError(f"{path}: column unit holds {' and '.join(sorted(found))}: expected one quantity "
                         "in every row")
    return found.pop(), factors


def write_csv(results, path, inputs=()) -> None:
    """Write FRF sets (one per speed) in the plain CSV layout, atomically."""
    import pandas as pd

    from .atomic import atomic_write, check_not_input

    check_not_input(path, inputs)
    tables = []
    for res in results:
        t = res.to_dataframe()
        t.insert(0, "speed_rpm", res.speed * 30 / np.pi)
        t["quantity"] = res.quantity
        tables.append(t)
    with atomic_write(path, "w", newline="") as handle:
        pd.concat(tables).to_csv(handle, index=False, float_format="%.17g")
