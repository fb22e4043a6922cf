"""A CSV of FRFs with a row of units under its header, as data recorders and spreadsheets export
them (``Hz,,,g/N,g/N``): the units are read as header units are (``frequency [Hz]``) and the
values converted with their factors (g = 9.80665 m/s², kHz = 1000 Hz); it was refused as "column
frequency_hz line 2 = 'Hz': expected a number"."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(EXAMPLE)


def test_a_units_row_converts_g_per_newton(model, tmp_path):
    path = tmp_path / "frf.csv"
    path.write_text("frequency,output,input,real,imag\nHz,,,g/N,g/N\n"
                    "1.0,acc-top-z,hammer-z,0.5,0.1\n2.0,acc-top-z,hammer-z,0.6,0.2\n")
    frf, = rdm.read_measured(path, model)
    assert frf.quantity == "accelerance"
    np.testing.assert_array_equal(frf.frequencies_hz, [1.0, 2.0])
    np.testing.assert_allclose(frf.H[0, 0], 9.80665 * np.array([0.5 + 0.1j, 0.6 + 0.2j]), rtol=1e-15)


def test_a_units_row_with_semicolons_decimal_commas_and_khz(model, tmp_path):
    path = tmp_path / "frf.txt"
    path.write_text("Frequency;Output;Input;Magnitude;Phase\nkHz;;;mm/s/N;deg\n"
                    "0,5;acc-side-y;shaker-y;2,0;90\n1,5;acc-side-y;shaker-y;4,0;180\n", encoding="latin-1")
    frf, = rdm.read_measured(path, model)
    assert frf.quantity == "mobility"
    np.testing.assert_allclose(frf.frequencies_hz, [500.0, 1500.0], rtol=1e-15)
    np.testing.assert_allclose(frf.H[0, 0], [2e-3j, -4e-3], atol=1e-15)


def test_a_unit_said_twice_differently_is_refused(model, tmp_path):
    path = tmp_path / "frf.csv"
    path.write_text("frequency,output,input,real [m/s^2/N],imag\nHz,,,g/N,g/N\n1.0,acc-top-z,hammer-z,0.5,0.1\n")
    with pytest.raises(InputError, match=r"column 'real \[m/s\^2/N\]': unit \[m/s\^2/N\] in the header and 'g/N' on "
                                         r"the line under it"):
        rdm.read_measured(path, model)


def test_lines_are_counted_in_the_file_after_a_units_row(model, tmp_path):
    path = tmp_path / "frf.csv"
    path.write_text("frequency,output,input,real,imag\nHz,,,g/N,g/N\n"
                    "1.0,acc-top-z,hammer-z,0.5,0.1\n2.0,acc-top-z,hammer-z,x,0.2\n")
    with pytest.raises(InputError, match=r"line 4 = 'x': expected a number"):
        rdm.read_measured(path, model)
