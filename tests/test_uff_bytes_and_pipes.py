"""A UFF line is 80 columns of bytes: channel names beyond ASCII are counted in UTF-8 bytes when
written; and the one refusal of a pipe or device shared by the UFF and TDMS readers."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import default_mapping, read_measured
from rotordyn_modal.io.uff import write_uff58

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
FREQS = np.linspace(1.0, 40.0, 79)


def _named(first_sensor):
    data = rdm.load_model(EXAMPLE).to_dict()
    data["sensors"][0]["name"] = first_sensor
    return rdm.Model.from_dict(data)


def _write(model, path):
    res = rdm.frf(model, 0.0, FREQS, quantity="accelerance")
    write_uff58([res], path, default_mapping(model))
    return res


def test_a_name_of_80_bytes_keeps_every_line_within_80_bytes(tmp_path):
    """40 'ü' are 40 characters and 80 bytes: the ID line holds them exactly; the blanks that pad
    a line are counted in bytes (padding to 80 characters made a line of 120 bytes)."""
    name = "ü" * 40
    model = _named(name)
    path = tmp_path / "u.uff"
    res = _write(model, path)
    lines = path.read_bytes().split(b"\n")
    assert max(len(line) for line in lines) == 80
    assert name.encode("utf-8") in lines
    back = read_measured(path, model)[0]
    assert name in back.outputs
    np.testing.assert_allclose(back.H, res.H, rtol=1e-11)
    assert any(s["id1"] == name for s in pyuff.UFF(str(path)).read_sets())


def test_a_short_name_beyond_ascii_is_not_put_in_record_6_columns(tmp_path):
    """'üü' is 2 characters but 4 bytes: record 6's entity field (10 columns) says NONE, so a
    reader counting bytes and one counting characters find the nodes in the same columns."""
    model = _named("üü")
    path = tmp_path / "u.uff"
    res = _write(model, path)
    record6 = [line for line in path.read_bytes().split(b"\n") if line.startswith(b"    4         0")]
    assert record6 and all(len(line) == 80 and line.isascii() for line in record6)
    back = read_measured(path, model)[0]
    assert back.outputs[0] == "üü"
    np.testing.assert_allclose(back.H, res.H, rtol=1e-11)


def test_a_name_of_41_characters_but_82_bytes_is_refused(tmp_path):
    model = _named("ü" * 41)
    path = tmp_path / "u.uff"
    with pytest.raises(InputError, match=r"41 characters, 82 bytes in UTF-8: a UFF 58 ID line holds 80 bytes"):
        _write(model, path)
    assert not path.exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_one_refusal_of_a_pipe_for_both_readers(tmp_path, monkeypatch):
    """io.limits.refuse_unsized is the one check of a device; the readers' messages keep their
    words. A FIFO is read (tests/test_standard_input27p.py): one nothing writes to is refused
    after the wait for a writer (io.limits.PIPE_WAIT_S, shortened here)."""
    from rotordyn_modal.io import limits
    from rotordyn_modal.io.limits import refuse_unsized

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"expected a thing, not a pipe or device \(its size is not known"):
        refuse_unsized(fifo, "a thing")
    refuse_unsized(tmp_path, "a thing")                 # a folder: the reader says so
    refuse_unsized(tmp_path / "missing", "a thing")     # missing: the reader says so
    if os.path.exists("/dev/zero"):
        with pytest.raises(InputError, match=r"zero: expected a Universal File, not a pipe or device \(its size is "
                                             r"not known before reading\)"):
            rdm.read_uff_info("/dev/zero")
    monkeypatch.setattr(limits, "PIPE_WAIT_S", 0.1)
    with pytest.raises(InputError, match=r"pipe: a pipe nothing writes to: no byte of the Universal File came"):
        rdm.read_uff_info(fifo)
    pytest.importorskip("nptdms")
    if os.path.exists("/dev/zero"):
        with pytest.raises(InputError, match=r"zero: expected a TDMS file, not a pipe or device \(its size is not "
                                             r"known before reading\)"):
            rdm.read_tdms_records("/dev/zero")
    with pytest.raises(InputError, match=r"pipe: a pipe nothing writes to: no byte of the TDMS file came"):
        rdm.read_tdms_records(fifo)
