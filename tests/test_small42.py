"""Small input families of issue 27 (hidden checks in the families of other tools' files and of
physics out of range), session 42."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from quiet_cli import run_quietly
from test_probe41 import written_uff

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_RUBBER = ROOT / "examples" / "rubber_mounts.toml"


@pytest.mark.parametrize("delimiter", ["\t-1", "-1", " -1", "  \t-1", "      -1"])
def test_a_uff_dataset_delimiter_written_with_a_tab_or_fewer_blanks_is_read(tmp_path, delimiter):
    """The Universal File's delimiter is '    -1' (columns 1-6); hand-edited files and some exports
    write '\\t-1' or '-1'. pyuff finds only the first form, so such a file was refused as "a dataset
    is not closed by a '    -1' line (from line 2): the file is truncated"; it holds the same FRF as
    the file written with the standard delimiters."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import read_measured

    model = rdm.load_model(EXAMPLE_RUBBER)
    good = written_uff(tmp_path / "good.uff")
    lines = good.read_text().splitlines(keepends=True)
    marks = [k for k, line in enumerate(lines) if line.rstrip("\r\n") == "    -1"]
    assert len(marks) >= 2 and len(marks) % 2 == 0
    for k in marks:                                        # every delimiter, opening and closing
        lines[k] = delimiter + lines[k][len("    -1"):]
    odd = tmp_path / "odd_delimiters.uff"
    odd.write_text("".join(lines))
    (expected,), (read,) = read_measured(good, model), read_measured(odd, model)
    np.testing.assert_array_equal(read.frequencies_hz, expected.frequencies_hz)
    np.testing.assert_array_equal(read.H, expected.H)
    assert read.outputs == expected.outputs and read.inputs == expected.inputs


EXAMPLE_JOURNAL = ROOT / "examples" / "journal_rotor.toml"


def _journal_model(tmp_path, old, new):
    """journal_rotor.toml with ``old`` replaced by ``new`` in both bearings, written to tmp_path."""
    text = EXAMPLE_JOURNAL.read_text()
    assert text.count(old) == 2
    path = tmp_path / "journal.toml"
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("old,new,key,value", [
    ("viscosity = 0.02", "viscosity = 2e-8", "viscosity", "2e-08"),       # below any fluid
    ("viscosity = 0.02", "viscosity = 3.2e-5", "viscosity", "3.2e-05"),   # ISO VG 32's 32 cSt in m^2/s
    ("clearance = 5.0e-5", "clearance = 5.0e-8", "clearance", "5e-08"),   # 50 micrometres converted twice
])
def test_a_journal_fluid_thinner_than_water_or_a_clearance_below_a_tenth_of_a_per_mille_draws_one_line(
        tmp_path, old, new, key, value):
    """Plain journal bearings run radial clearances of 0.001 to 0.003 of the radius on oils of
    0.002 to 1 Pa s; a viscosity of 2e-8 Pa s (no fluid is that thin) or a clearance of 5e-8 m on a
    50 mm journal went into the film's coefficients without a word (`check` exit 0, nothing on
    stderr), while the same mistakes upwards (THICK_OIL, WIDE_CLEARANCE) warned."""
    model = _journal_model(tmp_path, old, new)
    code, err = run_quietly(["check", str(model)])
    assert code == 0, err
    said = [line for line in err.splitlines() if f"] {key} = {value}" in line]
    assert [line.split("[")[1].split("]")[0] for line in said] == ["bearings.DE", "bearings.NDE"], err
    code, err = run_quietly(["check", str(EXAMPLE_JOURNAL)])                # the example as given: no line
    assert code == 0 and "viscosity =" not in err and "clearance =" not in err, err


def _frf_uff(path):
    """``path``: a Universal File of the 4 FRFs (2 sensors x 2 excitations) of rubber_mounts.toml
    at rest, 40 lines 5-20 Hz, as the command line writes it."""
    code, err = run_quietly(["frf", str(EXAMPLE_RUBBER), "--speed", "0", "--freqs", "5:20:40", "--out", str(path)])
    assert code == 0, err
    return path


def test_an_frf_dataset_cut_short_among_complete_ones_is_left_out_and_the_others_read(tmp_path):
    """A file whose second dataset 58 holds 6 of its 40 values (a copy cut in the middle of an
    export, the closing '-1' kept) was refused as a whole ("at 0 rpm the FRF acc-top-z / shaker-y
    has 6 frequencies where the data of that speed has 40"): its 3 complete FRFs are read, equal
    to the whole file's, and one line names the dataset left out."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import read_measured

    model = rdm.load_model(EXAMPLE_RUBBER)
    whole = _frf_uff(tmp_path / "whole.uff")
    lines = whole.read_text().splitlines(keepends=True)
    marks = [k for k, line in enumerate(lines) if line.rstrip("\r\n") == "    -1"]
    assert len(marks) == 8                                        # 4 datasets
    start, end = marks[2], marks[3]              # the second dataset: its number and records 1-11, then its data
    assert lines[start + 1].strip() == "58" and end - start - 1 - 12 == 20      # 2 complex values a line
    cut = tmp_path / "cut.uff"
    cut.write_text("".join(lines[:start + 1 + 12 + 3] + lines[end:]))          # 3 data lines (6 values) kept
    with pytest.warns(UserWarning, match=r"cut\.uff: dataset 2 \(.*\) holds 6 of the 40 values .*cut short\): "
                                         r"left out, the 3 complete FRFs read"):
        (read,) = read_measured(cut, model)
    (expected,) = read_measured(whole, model)
    assert read.outputs == expected.outputs and read.inputs == expected.inputs
    missing = np.isnan(read.H).all(axis=-1)
    assert missing.sum() == 1                                     # the pair left out
    np.testing.assert_array_equal(read.H[~missing], expected.H[~missing])
