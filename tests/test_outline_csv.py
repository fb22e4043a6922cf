"""``modes --outline FILE.csv`` reads the outline as spreadsheets write CSV (``io/outline.py`` through
``io/csv_tables.py``): ``;`` or tab separators with decimal commas (European Excel), a UTF-8
byte-order mark, cp1252, Excel's ``sep=;`` line, comment lines, header names with length units.
Each spelling of the one outline below must give the stator the same drawn geometry as the
points written here (in metres); what cannot be understood is refused on one line naming the
file, the line and column, and what was expected.

On main such a ``;`` file was refused as "cannot read the outline (Error tokenizing data ...)".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.cli import main

GEAR = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"

#: two polylines of the stator [m]: an L in the plane z = 0, a line at z = 0.3
LINES = ([(0.0, 0.0, 0.0), (0.5, 0.0, 0.0), (0.5, 0.3, -0.125)], [(0.0, 0.0, 0.3), (0.5, 0.0, 0.3)])


def _rows(separator=",", decimal=".", scale=1.0, empty=""):
    """The outline's data rows as text, lengths divided by ``scale`` (a header's unit), an
    ``empty`` row between the lines."""
    def cell(value):
        return repr(value / scale).replace(".", decimal)
    lines = [[separator.join(cell(v) for v in point) for point in line] for line in LINES]
    return lines[0] + [empty] + lines[1]


def _file(header, separator=",", decimal=".", scale=1.0, empty="", before=(), newline="\n"):
    return newline.join([*before, header, *_rows(separator, decimal, scale, empty)]) + newline


SPELLINGS = {
    # European Excel: ';' between cells, decimal commas, CRLF, an empty row written as ';;'
    "semicolon-decimal-comma": lambda: _file("x;y;z", ";", ",", empty=";;", newline="\r\n").encode("cp1252"),
    # the same with a UTF-8 byte-order mark and units in the header
    "bom-units": lambda: b"\xef\xbb\xbf" + _file("x [m];y [m];z [m]", ";", ",", empty=";;",
                                                  newline="\r\n").encode(),
    # cp1252 text (an en dash and a micro sign no UTF-8 reader decodes), millimetres and micrometres
    "cp1252-mm": lambda: (_file("X [mm];Y [mm];Z [mm]", ";", ",", scale=1e-3, before=["# Gehäuse – Umriss"])
                          .encode("cp1252")),
    "tab-decimal-comma": lambda: _file("x\ty\tz", "\t", ",", newline="\r\n").encode("cp1252"),
    # Excel's first line naming the separator
    "excel-sep-line": lambda: _file("x;y;z", ";", ",", before=["sep=;"]).encode(),
    "inches-in-parentheses": lambda: _file("x (in),y (in),z (in)", scale=0.0254).encode(),
}


def _drawn_outline(tmp_path, monkeypatch, data: bytes, name: str):
    """The stator's drawn body (vertices [m], polylines) of ``modes --shape 2 --outline`` run on
    a file of ``data``; the figure is written."""
    import rotordyn_modal.analysis.mode_shapes as mode_shapes

    drawn = []
    real = mode_shapes.mode_shape_3d

    def spy(*args, **kwargs):
        view = real(*args, **kwargs)
        drawn.append([b for b in view.outline.bodies if b.name == "stator"][0])
        return view

    monkeypatch.setattr(mode_shapes, "mode_shape_3d", spy)
    outline = tmp_path / f"{name}.csv"
    outline.write_bytes(data)
    plot = tmp_path / f"{name}.png"
    assert main(["modes", str(GEAR), "--speed", "3000", "--shape", "2", "--outline", str(outline),
                 "--plot", str(plot), "--quiet"]) == 0
    assert plot.read_bytes()[:4] == b"\x89PNG"
    [body] = drawn
    return body


@pytest.fixture(scope="module")
def expected():
    """The points as the drawing holds them: one row per point, a zero row at the break."""
    points = np.array([*LINES[0], (np.nan,) * 3, *LINES[1]])
    return np.nan_to_num(points), ((0, 1, 2), (4, 5))


_COMMA = {}


@pytest.mark.parametrize("spelling", list(SPELLINGS))
def test_every_spelling_draws_the_outline_the_comma_file_draws(tmp_path, monkeypatch, expected, spelling):
    if "comma" not in _COMMA:   # the plain file's drawing, once
        _COMMA["comma"] = _drawn_outline(tmp_path, monkeypatch, _file("x,y,z").encode(), "comma")
        monkeypatch.undo()
    comma = _COMMA["comma"]
    other = _drawn_outline(tmp_path, monkeypatch, SPELLINGS[spelling](), spelling)
    vertices, faces = expected
    np.testing.assert_allclose(comma.vertices, vertices, rtol=0, atol=1e-15)
    assert comma.kind == other.kind == "outline" and comma.faces == other.faces == faces
    np.testing.assert_allclose(other.vertices, comma.vertices, rtol=1e-15, atol=1e-15)


def _refusal(tmp_path, capsys, data: bytes):
    outline = tmp_path / "outline.csv"
    outline.write_bytes(data)
    plot = tmp_path / "s.png"
    assert main(["modes", str(GEAR), "--speed", "3000", "--shape", "2", "--outline", str(outline),
                 "--plot", str(plot), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{outline}: " in err, err
    assert not plot.exists()
    return err


@pytest.mark.parametrize("text, words", [
    # a ';' file's cell that is no number: its line (after a comment line) and column
    ("# exported\r\nx;y;z\r\n0;0;0\r\n0,5;abc;0\r\n", ["column y line 4 = 'abc'", "expected a number"]),
    # a header unit that is no length
    ("x [s],y,z\n0,0,0\n1,0,0\n", ["column 'x [s]'", "unit 's' is no length", "expected m, cm, mm"]),
    # a row of more cells than the header: the file's own line, counting the comment line
    ("# exported by CAD\n# units: m\nx,y,z\n0,0,0\n1,2,3,4\n",
     ["cannot read the outline", "line 5, column 4: '4' beyond the header's 3 column(s) (x, y, z)",
      "expected at most 3 cells on a line"]),
    # x twice, once in millimetres: which one is meant?
    ("x,y,z,X [mm]\n0,0,0,0\n1,0,0,1000\n", ["two columns are x", "'x' and 'X [mm]'", "each column once"]),
    # a point without its y: neither a point nor the empty row between two lines
    ("x;y;z\n0;0;0\n0,5;;0\n0;1;0\n", ["line 3: y empty", "expected a point x,y,z"]),
], ids=["no-number", "unit-no-length", "ragged-row", "x-twice", "point-without-y"])
def test_what_cannot_be_understood_is_refused_on_one_line(tmp_path, capsys, text, words):
    err = _refusal(tmp_path, capsys, text.encode())
    for word in words:
        assert word in err, err


def test_a_binary_file_is_no_outline(tmp_path, capsys):
    """Read as Latin-1 a binary file would be a table of control characters: refused as no text,
    naming the line of the first one."""
    err = _refusal(tmp_path, capsys, b"x,y,z\n0,0,0\n1,\x00\x07,0\n")
    assert "cannot read the outline (no text: control character '\\x00' on line 3)" in err
