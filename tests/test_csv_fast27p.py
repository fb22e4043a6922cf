"""CSV tables (outline, mapping, measured) are read by pandas' C parser where the table is plain,
and by Python's csv module otherwise (issue 27 §1.4: a 200,000-line table read 1.5x slower than
with pandas since the csv module read every table). The reference is the csv module's reading
of the same text (``_fast_table`` made to decline): the same frame cell for cell, the same file
lines, the same decimal mark, the same refusal word for word, over texts made of what
spreadsheets and test rigs write (three separators, padded and empty cells, short rows, blank
lines and lines of blanks, comments, ``sep=`` lines, CRLF, quotes, decimal commas)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotordyn_modal.errors import InputError
from rotordyn_modal.io import csv_tables
from rotordyn_modal.io.csv_tables import numbers, read_csv_table

SETTINGS = settings(max_examples=300, deadline=None, derandomize=True)

_CELLS = ["1", "2.5", "-3e-4", " 7 ", "", "  ", "nan", "NA", "acc-top-z", "hammer z", "ü", "1,5", "#", "x\u00a0",
          "'q'", '"a"', '"a,b"', '"a""b"', "inf", "\x0b1", "\t2"]


@st.composite
def tables(draw):
    """The text of a table: header names, rows of cells (some short, some long), blank lines,
    line endings, an optional comment and ``sep=`` line before the header."""
    separator = draw(st.sampled_from([",", ";", "\t"]))
    width = draw(st.integers(1, 4))
    names = draw(st.lists(st.sampled_from(["a", "b", " c ", "d [Hz]", "", "e"]), min_size=width, max_size=width))
    rows = draw(st.lists(st.lists(st.sampled_from(_CELLS), min_size=0, max_size=width + 1), max_size=8))
    end = draw(st.sampled_from(["\n", "\r\n"]))
    lines = []
    if draw(st.booleans()):
        lines.append("# written by a test rig")
    if draw(st.booleans()):
        lines.append(f"sep={separator}")
    lines.append(separator.join(names) + draw(st.sampled_from(["", separator])))
    for row in rows:
        lines.append(separator.join(row))
        if draw(st.integers(0, 5)) == 0:
            lines.append(draw(st.sampled_from(["", "   ", separator * width])))
    return end.join(lines) + draw(st.sampled_from(["", end, end + end]))


def _read(text: str, skip_blank_lines: bool):
    """(table, decimal) of ``read_csv_table``, or the refusal's words."""
    try:
        return read_csv_table(text.encode(), "t.csv", "as CSV", skip_blank_lines=skip_blank_lines)
    except InputError as error:
        return str(error)


def _same(fast, slow) -> None:
    if isinstance(slow, str) or isinstance(fast, str):
        assert fast == slow
        return
    (a, decimal_a), (b, decimal_b) = fast, slow
    assert decimal_a == decimal_b
    assert list(a.columns) == list(b.columns)
    assert a.shape == b.shape and (a.to_numpy(object) == b.to_numpy(object)).all()
    assert all(a.iloc[:, k].dtype == object for k in range(a.shape[1]))
    np.testing.assert_array_equal(a.attrs["lines"], b.attrs["lines"])


@SETTINGS
@given(text=tables(), skip_blank_lines=st.booleans())
def test_the_fast_reading_is_the_csv_modules(text, skip_blank_lines):
    fast = _read(text, skip_blank_lines)
    original = csv_tables._fast_table
    csv_tables._fast_table = lambda *args: None
    try:
        slow = _read(text, skip_blank_lines)
    finally:
        csv_tables._fast_table = original
    _same(fast, slow)


def test_a_plain_table_is_read_without_the_csv_module(monkeypatch):
    """A table of 20,000 lines without quotes is parsed by pandas (not split by the csv module,
    ``_rows``); its numbers are the text's."""
    def refused(*args, **kwargs):
        raise AssertionError("the csv module read a plain table")

    monkeypatch.setattr(csv_tables, "_rows", refused)
    rng = np.random.default_rng(3)
    values = rng.normal(size=(20_000, 2))
    text = "frequency_hz,output,real,imag\r\n" + "".join(
        f"{k + 1},acc-top-z,{float(a)!r},{float(b)!r}\r\n" for k, (a, b) in enumerate(values))
    table, decimal = read_csv_table(text.encode(), "m.csv", "as CSV")
    assert decimal == "." and table.shape == (20_000, 4)
    np.testing.assert_array_equal(numbers(table, "real", "m.csv"), values[:, 0])
    np.testing.assert_array_equal(numbers(table, "imag", "m.csv"), values[:, 1])
    np.testing.assert_array_equal(table.attrs["lines"], np.arange(2, 20_002))
    assert set(table["output"]) == {"acc-top-z"}


@pytest.mark.parametrize("text, words", [
    ("x,y\n1,2\n3,4,5\n", "line 3, column 3: '5' beyond the header's 2 column(s) (x, y)"),
    ("x,y\n1,2\n\n3,zz\n", "column y line 4 = 'zz': expected a number"),
    ("# c\nx;y\n1;2\n3; q \n", "column y line 4 = 'q': expected a number"),
])
def test_refusals_still_name_the_line_and_column(text, words):
    """A table the fast reading declines (a cell beyond the header) or reads (a cell that is no
    number) is refused naming the file's line: blank and comment lines counted."""
    with pytest.raises(InputError) as raised:
        table, decimal = read_csv_table(text.encode(), "t.csv", "as CSV")
        for column in table.columns:
            numbers(table, column, "t.csv", decimal)
    assert words in str(raised.value)
