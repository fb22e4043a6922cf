"""A large measured CSV whose header names none of the FRF columns is refused from its first
lines, before the whole table is parsed (redteam44: a 114 MB file of ``a,b,c`` rows took 17 s
and 4.7 GB of memory to be told "expected the columns ..."; the measured-data limit, 512 MB,
would have needed about 20 GB). A large file with the right columns reads as a small one does."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.io import csv_tables

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(EXAMPLES / "gear_machine.toml")


def _spied(monkeypatch):
    """The byte counts of every table :func:`read_csv_table` is asked to parse."""
    sizes, real = [], csv_tables.read_csv_table

    def spy(data, *args, **kwargs):
        sizes.append(len(data))
        return real(data, *args, **kwargs)

    monkeypatch.setattr(csv_tables, "read_csv_table", spy)
    return sizes


def test_a_large_file_with_wrong_columns_is_refused_from_its_head(tmp_path, model, monkeypatch):
    path = tmp_path / "huge.csv"
    path.write_bytes(b"a,b,c\n" + b"1,2,3\n" * 400_000)          # 2.4 MB
    sizes = _spied(monkeypatch)
    with pytest.raises(InputError, match=r"expected the columns speed_rpm,frequency_hz,output,input.*found a, b, c"):
        rdm.read_measured(path, model)
    assert sizes and max(sizes) < path.stat().st_size / 100      # the whole table was never parsed


def test_a_large_file_with_the_frf_columns_reads_whole(tmp_path, model, monkeypatch):
    """Its values are the model's FRF written to it, at every one of its frequencies."""
    freqs = np.linspace(1.0, 200.0, 4000)
    computed = rdm.frf(model, 0.0, freqs)
    path = tmp_path / "big.csv"
    rdm.write_measured_csv([computed], path)
    assert path.stat().st_size > 1 << 20
    sizes = _spied(monkeypatch)
    read = rdm.read_measured(path, model)[0]
    assert max(sizes) == path.stat().st_size
    order = [computed.outputs.index(o) for o in read.outputs], [computed.inputs.index(i) for i in read.inputs]
    expected = np.asarray(computed.H)[np.ix_(order[0], order[1])]
    assert np.array_equal(read.frequencies_hz, freqs) and np.allclose(read.H, expected, rtol=1e-13, atol=0)
