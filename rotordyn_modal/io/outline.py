"""The stator's outline file (``modes --outline FILE.csv``, docs/mode-shapes-and-views.md): polylines
of points ``x,y,z`` in metres, model axes, an empty row between two lines; read as other tools
and spreadsheets write CSV (:mod:`.csv_tables`: ``,``, ``;`` or tab separators, decimal commas, a
byte-order mark, Latin-1/cp1252), the header's names in any case, each with a length unit in
brackets if it is not in metres (``X [mm]``, ``y (in)``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..model._table import visible_names

__all__ = ["read_outline", "outline_scale_words", "OutlinePoints"]


class OutlinePoints(np.ndarray):
    """:func:`read_outline`'s points: an ndarray of shape (n, 3) [m] that also names its file
    (``source``), so that the warning of an outline far wider than the machine, given where
    the outline is drawn (``rotordyn_modal.analysis.mode_shapes.machine_outline``), names it."""

    source: str | None = None

    def __array_finalize__(self, obj):
        self.source = getattr(obj, "source", None)

_COLUMNS = ("x", "y", "z")
_LENGTHS = "m, cm, mm, um, in, mil or ft"


def read_outline(path):
    """The points of an outline file, in metres.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    OutlinePoints, shape (n, 3)
        ``x, y, z`` [m] in model axes; a row of NaN (the file's empty row) between two polylines.
        An ndarray whose ``source`` is ``str(path)``: the drawing that takes it
        (``mode_shape_3d(..., outline=...)``, ``machine_outline``) warns, naming the file, of an
        outline more than 30 times wider than the machine (millimetres read as metres).

    Raises
    ------
    InputError
        On one line naming the file: it cannot be read, a column is missing or named twice, a
        unit is no length, a cell is no number (its line and column), or no line can be drawn.
    """
    from ..analysis.mode_shapes import _outline_body
    from .csv_tables import read_csv_table
    from .limits import read_limited, unreadable

    try:
        data = read_limited(path, "model", "stator outline")
    except OSError as error:
        raise unreadable(path, "outline", error) from None
    table, decimal = read_csv_table(data, path, "the outline", text_only=True, skip_blank_lines=False)
    points = _coordinates(table, decimal, path)
    try:
        _outline_body(points)
    except InputError as error:   # the same rule, said with the file's name
        raise InputError(f"{path}: {error}") from None
    points = points.view(OutlinePoints)
    points.source = str(path)
    return points


def _coordinates(table, decimal, path):
    """The columns x, y, z of the table in metres, shape (n, 3); an empty cell is NaN."""
    import numpy as np

    from .csv_tables import numbers

    found = _columns(table, path)
    if set(found) != set(_COLUMNS):
        raise InputError(f"{path}: the outline needs the columns x,y,z (metres, model axes); found "
                         f"{visible_names(map(str, table.columns))}")
    points = np.empty((len(table), 3))
    for k, name in enumerate(_COLUMNS):
        cell, factor = found[name]
        try:
            points[:, k] = numbers(table, cell, path, decimal) * factor
        except InputError as error:
            raise InputError(f"{error} (an empty row starts a new line)") from None
    _check_whole_rows(points, table, path)
    return points


def _check_whole_rows(points, table, path):
    """Refuse a row with some of x, y, z empty: neither a point nor the empty row between lines."""
    import numpy as np

    from .csv_tables import file_line

    empty = np.isnan(points)
    partial = empty.any(axis=1) & ~empty.all(axis=1)
    if partial.any():
        row = int(np.argmax(partial))
        found = _columns(table, path)
        cells = {name: str(table.iloc[row][found[name][0]]).strip() for name in _COLUMNS}
        typed = [f"{name} = {cells[name]!r}" for name, e in zip(_COLUMNS, empty[row]) if e and cells[name]]
        missing = ", ".join(typed) or ",".join(name for name, e in zip(_COLUMNS, empty[row]) if e) + " empty"
        raise InputError(f"{path}: line {file_line(table, row)}: {missing}: expected a point "
                         f"x,y,z (three numbers) or an empty row between two lines")


def _columns(table, path):
    """Header cell and factor to metres of each of the columns x, y, z the header names.

    Returns
    -------
    dict
        ``name -> (header cell, factor)``.
    """
    from .csv_tables import split_header
    from .unit_labels import parse_unit

    found = {}
    for cell in table.columns:
        name, unit = split_header(cell)
        if name not in _COLUMNS:
            continue
        if name in found:
            raise InputError(f"{path}: two columns are {name} ({found[name][0]!r} and {cell!r}): expected each "
                             f"column once")
        parsed = parse_unit(unit) if unit is not None else (1.0, (1, 0, 0))
        if parsed is None or tuple(parsed[1]) != (1, 0, 0):
            raise InputError(f"{path}: column {cell!r}: unit {unit!r} is no length: expected {_LENGTHS} "
                             f"(or no unit: metres)")
        found[name] = (cell, parsed[0])
    return found


def outline_scale_words(points, machine_size: float, path) -> str | None:
    """The warning for an outline far wider than the machine, else None:
    :func:`rotordyn_modal.analysis.mode_shapes.outline_scale_words`, which ``machine_outline``
    says (the command line and the Python API alike)."""
    from ..analysis.mode_shapes import outline_scale_words as words

    return words(points, machine_size, path)
