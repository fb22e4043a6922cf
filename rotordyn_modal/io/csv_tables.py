"""CSV tables as other tools and spreadsheets write them: the text's encoding (UTF-8 with or
without a byte-order mark, UTF-16 with or without one, else Latin-1: :mod:`.text`), the separator (``,``, ``;`` or a tab, read
from the header line or from Excel's ``sep=;`` line before it), decimal commas (``1,5`` beside a
``;`` or tab separator, quoted or not), comment lines (``# ...``) before the header, header
names in any case with a unit in brackets (``Frequency [kHz]``, ``phase (rad)``), and cells
padded with spaces (`` 1.0 ``, `` f [Hz] ``). Messages name the file's own lines, counting the
comment and ``sep=`` lines before the header.
"""

from __future__ import annotations

import contextlib
import io
import re

from ..errors import InputError
from .text import decode_text

__all__ = ["read_csv_table", "numbers", "split_header", "file_line"]

_SEPARATORS = (",", ";", "\t")
#: the first line Excel writes to name the separator (``sep=;``)
_SEPARATOR_LINE = re.compile(r"^\s*sep=([,;\t])\s*$")
#: cells that say "no value" (NaN), as pandas reads them by default
_EMPTY = ["", "nan", "-nan", "na", "n/a", "#n/a", "#na", "null", "none", "<na>"]
#: ``name [unit]`` or ``name (unit)``: a header cell with its unit
_HEADER = re.compile(r"^(?P<name>.*?)\s*(?:\[(?P<bracket>[^\]]*)\]|\((?P<paren>[^)]*)\))\s*$")


def read_csv_table(data: bytes, path, what: str, text_only: bool = False, skip_blank_lines: bool = True):
    """A CSV table of ``data`` (a file's bytes): its cells as text without the spaces around them
    (names stay as written otherwise: ``01``, ``NA``), the header names stripped, and the decimal
    mark of its numbers. ``table.attrs['lines']`` holds the file's line of each row
    (:func:`numbers` and :func:`file_line` name lines by it).

    Parameters
    ----------
    data : bytes
    path : path-like
        Named in messages.
    what : str
        Completes the message "cannot read ..." ('as CSV', 'the mapping table').
    text_only : bool
        Refuse text holding control characters other than tabs and line breaks (a binary file
        read as Latin-1) as "cannot read ...", naming the line; else such a header is read and
        shown escaped by the caller's message about its columns.
    skip_blank_lines : bool
        Leave out the empty lines (else each is a row of empty cells: an outline's break).

    Returns
    -------
    (DataFrame of str, str)
        The table and its decimal mark ('.' or ',', for :func:`numbers`).

    Raises
    ------
    InputError
        The text is no table, on one line naming the file, the line (and the column) and what
        was expected: no header (an empty file), a quoted cell never closed, a line with a cell
        beyond the header's columns (pandas took such a file's first column as its row labels
        without a word, or refused it in its own words).
    """
    try:
        text = decode_text(data)
    except UnicodeDecodeError as problem:   # UTF-16 without a mark that is no UTF-16
        raise InputError(f"{path}: cannot read {what} (byte {problem.start}: {problem.reason}): "
                         "expected text in UTF-8 or whole UTF-16") from None
    if text_only:
        _check_text(text, path, what)
    lines = _first_lines(text, _HEAD_LINES)
    start = 0
    while start < len(lines) and lines[start].lstrip().startswith("#"):   # a tool's comment lines
        start += 1
        if start == len(lines) == _HEAD_LINES:          # more comment lines than looked at: all of them
            lines = text.splitlines(keepends=True)
    declared = _SEPARATOR_LINE.match(lines[start]) if start < len(lines) else None
    start += declared is not None      # Excel's "sep=;" line names the separator (it was read as the header)
    if start + 200 > len(lines) >= _HEAD_LINES:
        lines = _first_lines(text, start + 200)
    if start:
        text = text[sum(map(len, lines[:start])):]
    header = lines[start] if start < len(lines) else ""
    separator = declared.group(1) if declared else max(_SEPARATORS, key=lambda s: (header.count(s), s == ","))
    body = "".join(lines[start + 1:start + 200])
    # a decimal comma: '1,5', and '7,52E-07' as a spreadsheet in a German locale writes an FRF's
    # small values (every value of a receptance; without the exponent the file was read as '.')
    decimal = "," if separator != "," and re.search(r'(^|[;\t])\s*"?[-+]?\d+,\d+(?:[eE][-+]?\d+)?"?\s*([;\t]|$)',
                                                    body, re.M) else "."
    with _collector_paused():
        table = _fast_table(text, separator, start, skip_blank_lines)   # pandas' C parser: a plain table
        if table is None:       # the csv module reads what it does not, and names what is wrong
            table = _table(_rows(text, separator, path, what, start, skip_blank_lines), path, what)
    _check_columns_once(header, separator, path)
    lines = table.attrs["lines"]
    table = _without_trailing_empty_rows(table)
    table.attrs["lines"] = lines[:len(table)]
    return table, decimal


#: lines of a table's head looked at for comments, a ``sep=`` line, the header and the decimal mark
_HEAD_LINES = 400


def _first_lines(text: str, count: int) -> list:
    """``text.splitlines(keepends=True)[:count]`` without splitting the whole text (a list of every
    line of a measured file of 600,000 lines took 70 MB beside the table): prefixes of growing
    size, until one holds two more line breaks than wanted (the prefix's last line may be cut,
    and a cut between ``\r`` and ``\n`` would end the line before it early)."""
    size = 1 << 16
    while True:
        lines = text[:size].splitlines(keepends=True)
        if size >= len(text) or len(lines) > count + 1:
            return lines[:count]
        size *= 4


@contextlib.contextmanager
def _collector_paused():
    """Python's cyclic garbage collector paused while a table's millions of small lists and strings
    are made (none holds a cycle): it ran over them again and again, 3x the parse (a 200,000-line
    table: 6 s, 2 s paused, pandas' parser 2.4 s)."""
    import gc

    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


#: a line of blanks only (the csv module reads it as a cell, pandas' parser as no line)
_BLANK_LINE = re.compile(r"^[^\S\r\n]+\r?$", re.M)


def _fast_table(text: str, separator: str, start: int, skip_blank_lines: bool):
    """:func:`_table` of :func:`_rows` (the same frame, cell for cell, and ``attrs['lines']``) made
    by pandas' C parser, 3-5x faster, for a plain table: no quote, no NUL, no line break but
    ``\n`` and ``\r\n``, the header on the first line with a name in its last cell, no line of
    blanks, no line longer than the csv module's field limit, no line with more cells than the
    header. None for any other text: the csv module reads it, and names what is wrong.

    Parameters
    ----------
    text : str
        The table from its header line on.
    separator : str
    start : int
        Lines of the file before ``text``.
    skip_blank_lines : bool

    Returns
    -------
    DataFrame of str or None
    """
    import csv

    import numpy as np
    import pandas as pd

    if '"' in text or "\0" in text or ("\r" in text and text.count("\r") != text.count("\r\n")):
        return None
    padded = _has_blanks(text, separator)       # cells to strip (`` 1.0 ``, `` acc-top-z ``)
    if padded and _BLANK_LINE.search(text):
        return None
    lengths = _line_lengths(text)      # of the lines between "\n"s, a "\r" before one counted
    header = text[:lengths[0]].rstrip("\r").split(separator) if len(lengths) else [""]
    if not header[-1].strip() or (len(lengths) and lengths.max() > csv.field_size_limit()):
        return None
    try:
        # bytes, not io.StringIO(text): its buffer holds 4 bytes a character (166 MB for a 41 MB file)
        cells = pd.read_csv(io.BytesIO(text.encode("utf-8", "surrogatepass")), encoding="utf-8",
                            encoding_errors="surrogatepass", sep=separator, header=None, dtype=object, na_filter=False,
                            skip_blank_lines=skip_blank_lines, quoting=csv.QUOTE_NONE, engine="c")
    except (ValueError, pd.errors.ParserError):      # a line of more cells than the header
        return None
    lines = np.arange(start + 2, start + 1 + len(lengths), dtype=np.int64)
    if skip_blank_lines:
        lines = lines[~_blank_lines(text, lengths)[1:]]
    if cells.shape != (len(lines) + 1, len(header)):
        return None
    return _frame(header, [cells[k].to_numpy(dtype=object)[1:] for k in cells.columns], lines, strip=padded)


def _line_lengths(text: str):
    """The length of each line of ``text`` split at ``"\n"`` (its ``"\r"`` counted; no line after a
    last ``"\n"``), shape (lines,), as ``map(len, text.split("\n"))``: for ASCII text from the
    positions of its line breaks, without a list of every line (70 MB for 600,000 lines)."""
    import numpy as np

    if not text.isascii():
        physical = text.split("\n")
        if physical[-1] == "":
            physical.pop()
        return np.fromiter(map(len, physical), dtype=np.int64, count=len(physical))
    ends = np.flatnonzero(np.frombuffer(text.encode("ascii"), dtype=np.uint8) == 10)
    if not len(ends) or ends[-1] != len(text) - 1:
        ends = np.append(ends, len(text)) if text else ends
    return np.diff(ends, prepend=-1) - 1


def _blank_lines(text: str, lengths):
    """Which lines of :func:`_line_lengths` are empty or a lone ``"\r"``, shape (lines,) bool."""
    import numpy as np

    starts = np.concatenate([[0], np.cumsum(lengths[:-1] + 1)])
    blank = lengths == 0
    single = np.flatnonzero(lengths == 1)
    blank[single] = [text[i] == "\r" for i in starts[single]]
    return blank


#: the characters ``str.strip`` removes that ASCII text may hold, but line breaks
_ASCII_BLANKS = " \t\x0b\x0c\x1c\x1d\x1e\x1f"


def _has_blanks(text: str, separator: str) -> bool:
    """Whether ``text`` holds a character ``str.strip`` removes, other than line breaks and the
    separator (a tab): memory scans of ASCII text, a regular expression of other text."""
    if text.isascii():
        return any(blank in text for blank in _ASCII_BLANKS if blank != separator)
    return re.search(r"[^\S\r\n\t]" if separator == "\t" else r"[^\S\r\n]", text) is not None


def _rows(text: str, separator: str, path, what: str, start: int, skip_blank_lines: bool):
    """``[(file line, cells), ...]`` of the text's records, the header first (the first line that
    is not empty); an empty line is left out or, without ``skip_blank_lines``, a row of no cell.
    ``start`` lines of the file (comments, ``sep=``) come before ``text``.

    Raises
    ------
    InputError
        No header line; a quoted cell not closed before the end of the file.
    """
    import csv

    def records(strict):
        reader = csv.reader(io.StringIO(text, newline=""), delimiter=separator, strict=strict)
        found, first = [], 1
        try:
            for cells in reader:
                found.append((start + first, cells))
                first = reader.line_num + 1
        except csv.Error as error:
            if "end of data" in str(error):   # pandas: "EOF inside string starting at row N"
                raise InputError(f"{path}: cannot read {what}: line {start + first}: a quoted cell (\") is never "
                                 "closed: expected a closing quote before the end of the file") from None
            if "field limit" in str(error):
                raise InputError(f"{path}: cannot read {what}: line {start + first}: a cell of more than "
                                 f"{csv.field_size_limit():,} characters: expected a table's cells") from None
            if strict:
                raise
            raise InputError(f"{path}: cannot read {what}: line {start + first}: {error}: expected cells "
                             f"separated by {separator!r}") from None
        return found

    try:
        found = records(strict=True)
    except csv.Error:              # a quote inside a cell ('"ab"c'): read as pandas read it
        found = records(strict=False)
    found = [(line, cells) for line, cells in found if cells or not skip_blank_lines]
    while found and not any(cell.strip() for cell in found[0][1]):
        found.pop(0)              # empty lines before the header
    if not found:
        raise InputError(f"{path}: cannot read {what}: the file holds no line of text (empty, or blank lines only): "
                         "expected a header line naming the columns, then a line per row")
    return found


def _table(rows, path, what: str):
    """The DataFrame of ``rows`` (:func:`_rows`): the header's cells as column names (an empty one
    ``Unnamed: k``, as pandas named it), every row as many cells as the header (missing cells
    empty, empty cells beyond the header dropped: a spreadsheet's trailing separators), and
    ``attrs['lines']`` the file line of each row. A cell beyond the header is refused."""
    import numpy as np

    (_, header), body = rows[0], rows[1:]
    header = list(header)
    while len(header) > 1 and not header[-1].strip():     # 'x,y,z,': the trailing separator names no column
        header.pop()
    width = len(header)
    shown = _escaped(", ".join(name.strip() for name in header))
    kept = []
    for line, cells in body:
        if len(cells) != width:
            extra = next((k for k in range(width, len(cells)) if cells[k].strip()), None)
            if extra is not None:
                raise InputError(f"{path}: cannot read {what}: line {line}, column {extra + 1}: "
                                 f"{cells[extra].strip()[:40]!r} beyond the header's {width} column(s) "
                                 f"({shown[:120]}): expected at most {width} cells on a line (a separator too many?)")
            cells = (cells + [""] * width)[:width]
        kept.append(cells)
    # cells padded to line up in a text editor or exported so (`` 1.0 ``, `` acc-top-z ``)
    columns = zip(*kept) if kept else [()] * width
    return _frame(header, columns, np.array([line for line, _ in body], dtype=np.int64))


def _frame(header, columns, lines, strip=True):
    """The DataFrame of str of the cells ``columns`` (one sequence per column of ``header``,
    stripped if ``strip``): the header's cells as column names (an empty one ``Unnamed: k``, as
    pandas named it) and ``attrs['lines']`` the file line ``lines`` (int64 array: pandas copies
    attrs) of each row."""
    import pandas as pd

    table = pd.DataFrame({k: pd.Series([cell.strip() for cell in column] if strip else column, dtype=object)
                          for k, column in enumerate(columns)})
    table.columns = [name.strip() or f"Unnamed: {k}" for k, name in enumerate(header)]
    table.attrs["lines"] = lines
    return table


#: control characters no text table holds (tab, line feed, carriage return and form feed may)
_CONTROL = re.compile(r"[\x00-\x08\x0b\x0e-\x1f\x7f]")


def _escaped(text: str) -> str:
    """``text`` with its control characters written as escapes (``\\x00``), for a message on one
    line: a binary file read as Latin-1 put its NUL bytes and escape sequences, as its header,
    on the terminal."""
    return re.sub(r"[\x00-\x1f\x7f-\x9f]", lambda found: repr(found.group())[1:-1], text)


def _check_text(text: str, path, what: str) -> None:
    """Refuse text with a control character: a binary file, which Latin-1 reads as characters."""
    found = _CONTROL.search(text)
    if found:
        line = text.count("\n", 0, found.start()) + 1
        raise InputError(f"{path}: cannot read {what} (no text: control character {found.group()!r} on line {line})")


def _check_columns_once(header: str, separator: str, path) -> None:
    """Refuse a header that names a column twice: pandas renamed the second ``frequency_hz.1``
    and it was left unread without a word, whatever it held."""
    import csv

    names = [name.strip() for name in next(csv.reader([header.strip("\r\n")], delimiter=separator), [])]
    if len(names) > 1 and all(_is_number_text(name) for name in names):   # was "column '0' is named twice"
        raise InputError(f"{path}: the first line ({separator.join(names)[:60]}) holds numbers, not column names: "
                         "expected a header line naming the columns first")
    seen = {}
    for index, name in enumerate(names):
        if name and name.lower() in seen:
            raise InputError(f"{path}: column {name!r} is named twice in the header (columns {seen[name.lower()] + 1} "
                             f"and {index + 1}): expected each column once")
        seen[name.lower()] = index


def _is_number_text(text: str) -> bool:
    """True for a cell that reads as a number (a decimal comma too); an empty cell is none."""
    try:
        float(text.replace(",", "."))
    except ValueError:
        return False
    return bool(text)


def _without_trailing_empty_rows(table):
    """The table without the rows of empty cells at its end (a spreadsheet's export: ``,,,,``),
    which were read as a line of no frequency and no channel."""
    empty = (table.to_numpy(dtype=object) == "").all(axis=1)       # cells stripped by _table
    keep = len(empty)
    while keep and empty[keep - 1]:
        keep -= 1
    return table.iloc[:keep]


def numbers(table, name, path, decimal: str = "."):
    """A column of text cells (:func:`read_csv_table`) as floats; an empty cell is NaN, a cell that
    is no number is refused naming its line (:func:`file_line`).

    Returns
    -------
    ndarray of float, shape (n_rows,)
    """
    import numpy as np
    import pandas as pd

    cells = table[name].astype(str)     # stripped by read_csv_table
    text = cells.str.replace(",", ".", regex=False) if decimal == "," else cells
    values = pd.to_numeric(text, errors="coerce").to_numpy(float)
    if not np.isnan(values).any():
        return values
    cells = cells.str.strip()
    bad = np.isnan(values) & ~cells.str.lower().isin(_EMPTY).to_numpy()
    if bad.any():
        row = int(np.argmax(bad))
        raise InputError(f"{path}: column {name} line {file_line(table, row)} = {cells.iloc[row][:40]!r}: "
                         f"expected a number{_foreign_character(cells.iloc[row])}")
    return values


def _foreign_character(text: str) -> str:
    """`` (it holds U+2212, MINUS SIGN, not ASCII: ...)`` for a cell's first character beyond ASCII
    (a typographic minus, a no-break space, as word processors and some locales write them), or ''."""
    import unicodedata

    found = next((c for c in text if ord(c) > 127), None)
    if found is None:
        return ""
    hint = ": type the ASCII '-'" if found in "\u2212\u2013\u2010\u2011\u2012\ufe63\uff0d" else ""
    return f" (it holds U+{ord(found):04X}, {unicodedata.name(found, 'unnamed')}, not ASCII{hint})"


def file_line(table, row: int) -> int:
    """The file line of the table's row ``row`` (from 0): ``attrs['lines']`` (:func:`read_csv_table`),
    else the row plus 2 (a header on line 1)."""
    lines = table.attrs.get("lines")
    if lines is not None and len(lines) == len(table):
        return int(lines[row])
    return row + 2


def split_header(cell) -> tuple[str, str | None]:
    """``('frequency', 'kHz')`` of a header cell ``Frequency [kHz]``: the name in lower case with
    spaces as ``_``, and its unit (None without one)."""
    text = str(cell).strip()
    found = _HEADER.match(text)
    name, unit = (found.group("name"), found.group("bracket") or found.group("paren")) if found else (text, None)
    return re.sub(r"\s+", "_", name.strip().lower()), (unit.strip() if unit and unit.strip() else None)
