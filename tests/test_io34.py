"""Measured files as a test lab exports them (issue 27 §4): a CSV whose ``quantity`` column is
capitalised (``Receptance``), a Universal File with text after its last dataset, a TDMS file
cut inside its last segment's data. Each was refused whole; the truth is the uncut file read by
pandas, pyuff or npTDMS directly."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import read_measured

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"


def _frf_file(tmp_path, name, quantity="receptance") -> Path:
    """The gear machine's four FRFs at 600 rpm written by ``frf --out`` (CSV or ASCII UFF 58)."""
    path = tmp_path / name
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--quantity", quantity,
                 "--out", str(path), "--quiet"]) == 0
    return path


def _pairs(results) -> dict:
    (result,) = results
    return {(o, i): result.H[a, b] for a, o in enumerate(result.outputs) for b, i in enumerate(result.inputs)
            if np.all(np.isfinite(result.H[a, b]))}


# ----------------------------------------------------------------------- the quantity in any case
@pytest.mark.parametrize("quantity, typed", [("receptance", "Receptance"), ("mobility", "MOBILITY"),
                                             ("accelerance", "Accelerance")])
def test_a_capitalised_quantity_in_a_measured_csv_is_read(tmp_path, quantity, typed):
    """``quantity = Receptance`` was refused: 'quantity column holds ['Receptance']'."""
    path = _frf_file(tmp_path, "g.csv", quantity)
    table = pd.read_csv(path)
    assert set(table["quantity"]) == {quantity}
    table["quantity"] = typed
    table.to_csv(path, index=False, float_format="%.17g")
    (result,) = read_measured(path, rdm.load_model(GEAR))
    assert result.quantity == quantity
    read = _pairs([result])
    assert len(read) == len(table.groupby(["output", "input"]))
    for (output, source), rows in table.groupby(["output", "input"]):
        np.testing.assert_array_equal(read[output, source], rows["real"].to_numpy() + 1j * rows["imag"].to_numpy())


def test_two_quantities_in_a_csv_are_still_refused_in_any_case(tmp_path):
    path = _frf_file(tmp_path, "g.csv")
    table = pd.read_csv(path)
    table.loc[table.index[0], "quantity"] = "Mobility"
    table.to_csv(path, index=False)
    with pytest.raises(InputError, match=r"quantity column holds \['Mobility', 'receptance'\]"):
        read_measured(path, rdm.load_model(GEAR))


# ----------------------------------------------------------------------- text after the last UFF dataset
def test_a_universal_file_with_text_after_its_last_dataset_reads_the_datasets(tmp_path):
    """An export ending in 'end of export' after its last '    -1' was refused whole as
    'truncated or has trailing text'."""
    pyuff = pytest.importorskip("pyuff")
    whole = _frf_file(tmp_path, "g.uff")
    text = whole.read_text()
    trail = tmp_path / "trail.uff"
    trail.write_text(text + "\nend of export\n")
    start = len(text.splitlines()) + 2     # the blank line, then the text
    with pytest.warns(UserWarning, match=rf"trail.uff: text after the last dataset, from line {start} "
                                         r"\('end of export'"):
        read = _pairs(read_measured(trail, rdm.load_model(GEAR)))
    truth = [np.asarray(s["data"]) for s in pyuff.UFF(str(whole)).read_sets() if s["type"] == 58]
    assert len(truth) == len(read) == 4
    for data in truth:   # each dataset of the uncut file is one pair read, bit for bit
        assert sum(np.array_equal(values, data) for values in read.values()) == 1


def test_a_universal_file_with_only_text_after_a_lone_opening_mark_is_still_refused(tmp_path):
    whole = _frf_file(tmp_path, "g.uff")
    cut = tmp_path / "cut.uff"
    cut.write_text("".join(whole.read_text().splitlines(keepends=True)[:10]) + "end of export\n")
    with pytest.raises(InputError, match="incomplete Universal File"):
        read_measured(cut, rdm.load_model(GEAR))


# ----------------------------------------------------------------------- TDMS cut in its last segment's data
@pytest.fixture()
def three_segments(tmp_path) -> Path:
    """A TDMS file of three segments of 1000 samples of a force (N) and an acceleration (g)."""
    nptdms = pytest.importorskip("nptdms")
    rng = np.random.default_rng(34)
    force, acc = rng.standard_normal(3000), rng.standard_normal(3000)
    path = tmp_path / "whole.tdms"
    props = {"wf_increment": 1e-3, "wf_start_offset": 0.0}
    with nptdms.TdmsWriter(str(path)) as writer:
        for k in range(3):
            part = slice(1000 * k, 1000 * (k + 1))
            writer.write_segment([nptdms.RootObject(), nptdms.GroupObject("g"),
                                  nptdms.ChannelObject("g", "force", force[part], properties={**props, "unit_string": "N"}),
                                  nptdms.ChannelObject("g", "acc", acc[part], properties={**props, "unit_string": "g"})])
    return path


@pytest.mark.parametrize("short", [8, 5000, 8008])
def test_a_tdms_file_cut_in_its_last_segments_data_reads_the_complete_segments(tmp_path, three_segments, capfd,
                                                                               short):
    """Cut 8 bytes, 5000 bytes (inside the acceleration's data) or 8008 bytes (inside the
    force's) short of its end, the file was refused ('lengths [...]' or 'cut short inside its
    last segment's data')."""
    nptdms = pytest.importorskip("nptdms")
    data = three_segments.read_bytes()
    cut = tmp_path / "cut.tdms"
    cut.write_bytes(data[:len(data) - short])
    with pytest.warns(UserWarning, match=r"cut.tdms: the file is cut short inside its last segment's data .*"
                                         r"\(2000 samples a channel\)") as caught:
        records = rdm.read_tdms_records(cut)
    assert len([w for w in caught if "cut short" in str(w.message)]) == 1
    assert "\n" not in str(caught[0].message)
    whole = nptdms.TdmsFile.read(str(three_segments))
    assert records.channels == ("force", "acc")
    np.testing.assert_array_equal(records.signals[0, 0], whole["g"]["force"][:2000])
    np.testing.assert_allclose(records.signals[0, 1], 9.80665 * whole["g"]["acc"][:2000], rtol=1e-15)
    assert records.sampling_rate_hz == pytest.approx(1e3, rel=1e-12)
    assert "nptdms" not in capfd.readouterr().err


def test_a_tdms_file_cut_in_its_only_segments_data_is_still_refused(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    path = tmp_path / "one.tdms"
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.RootObject(), nptdms.GroupObject("g"),
                              nptdms.ChannelObject("g", "force", np.arange(1000.0),
                                                   properties={"wf_increment": 1e-3, "unit_string": "N"})])
    data = path.read_bytes()
    path.write_bytes(data[:len(data) - 100])
    with pytest.raises(InputError, match=re.escape("cut short inside its first segment's data")):
        rdm.read_tdms_records(path)
