"""A measured CSV file is read without a list of its lines or a 4-byte-a-character copy of its
text, and one whose table would not fit in the memory available is refused before it is parsed
(session 46: 41.6 MB of FRFs took 645 MB, now 390 MB; /usr/bin/time -v, docs/frf-and-measurement.md)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.csv_tables import _first_lines, read_csv_table
from rotordyn_modal.io.measured import read_measured, write_csv

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


@pytest.fixture
def measured(tmp_path):
    model = rdm.load_model(EXAMPLE)
    path = tmp_path / "m.csv"
    write_csv([rdm.frf(model, 0.0, np.linspace(1.0, 40.0, 200))], path)
    return model, path


def test_a_file_beyond_the_memory_is_refused_before_it_is_read(measured, monkeypatch, capsys):
    model, path = measured
    size = path.stat().st_size
    lines = path.read_text().splitlines()
    cells = len(lines) * len(lines[0].split(",")) + 1      # the estimate counts separators and line breaks, + 1
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", f"{size * 2 / 2**30:.9f}")     # twice the file: too little
    with pytest.raises(InputError) as refused:
        read_measured(path, model)
    said = str(refused.value)
    assert said.startswith(f"{path}: reading this measured-data file ({size / 1e6:.3g} MB, about {cells:,} cells)"
                           " needs about ")
    assert "is available: split it (a file per speed or per channel pair), or write it as UFF 58b" in said
    assert main(["frf", str(EXAMPLE), "--speed", "0", "--freqs", "1:40:5", "--measured", str(path), "--quiet"]) == 2
    assert "reading this measured-data file" in capsys.readouterr().err
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1")
    (back,) = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, np.linspace(1.0, 40.0, 200))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.sampled_from(["a", "bc", "\n", "\r", "\r\n", "\x0b", "\x1c", "\u2028", "x" * 7000]), max_size=60),
       st.integers(0, 70))
def test_first_lines_are_those_of_splitlines(parts, count):
    text = "".join(parts)
    assert _first_lines(text, count) == text.splitlines(keepends=True)[:count]


@pytest.mark.parametrize("cut", [65535, 65536, 65537])
def test_first_lines_across_a_crlf_at_the_prefix_boundary(cut):
    """The first prefix read is 65,536 characters: a ``\\r\\n`` across it is one line break."""
    text = "x" * (cut - 1) + "\r\n" + "y\r\n" * 5
    assert _first_lines(text, 3) == text.splitlines(keepends=True)[:3]


def test_a_table_after_more_comment_lines_than_the_head_looked_at(tmp_path):
    comments = "".join(f"# line {k}\n" for k in range(450))
    table, decimal = read_csv_table((comments + "a;b\n1,5;2\n3;4\n").encode(), tmp_path / "t.csv", "as CSV")
    assert list(table.columns) == ["a", "b"] and decimal == ","
    assert table["a"].tolist() == ["1,5", "3"] and list(table.attrs["lines"]) == [452, 453]


@pytest.mark.parametrize("binary, words, per_byte", [(False, "UFF 58 ASCII", 7), (True, "UFF 58b", 17)])
def test_a_universal_file_beyond_the_memory_is_refused_before_it_is_read(tmp_path, monkeypatch, binary, words,
                                                                         per_byte):
    """A Universal File's FRFs take 5-6 (ASCII) and 13-16 (binary) times the file's size
    (benchmarks/bench_measured_memory.py): the estimate, 7 and 17 times, against the memory."""
    from rotordyn_modal.io.measured import default_mapping
    from rotordyn_modal.io.uff import write_uff58

    model = rdm.load_model(EXAMPLE)
    path = tmp_path / "m.uff"
    write_uff58([rdm.frf(model, 0.0, np.linspace(1.0, 40.0, 200))], path, default_mapping(model), binary=binary)
    size = path.stat().st_size
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", f"{0.99 * per_byte * size / 2**30:.12f}")
    with pytest.raises(InputError) as refused:
        read_measured(path, model)
    said = str(refused.value)
    assert said.startswith(f"{path}: reading this measured-data file ({size / 1e6:.3g} MB, {words}) needs about ")
    needed, available = (float(x) for x in re.findall(r"([0-9.]+) GiB", said))
    assert needed != available                       # as many digits as tell them apart
    assert needed == pytest.approx(per_byte * size / 2**30, rel=1e-2)
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", f"{1.01 * per_byte * size / 2**30:.12f}")
    (back,) = read_measured(path, model)
    assert back.H.shape == (2, 2, 200)
