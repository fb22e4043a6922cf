"""Binary 58b in big-endian byte order (record 1, field 1: 2), as workstation tools (HP-UX, SGI
I-DEAS) wrote them: made here from UFFFiles.jl's little-endian excerpt by swapping each value's
bytes and the record 1 field, then read as its ASCII twin (values from the ASCII file's text)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.io.channels import ChannelMap
from rotordyn_modal.io.uff import read_uff58

DATA = Path(__file__).resolve().parent / "data" / "uff"


def _big_endian(tmp_path, fields):
    raw = (DATA / "ufffiles_uneven_double_excerpt_binary.unv").read_bytes()
    head = b"\n".join(raw.split(b"\n", 13)[:13]) + b"\n"
    lines = head.split(b"\n")
    assert lines[1][6:13] == b"b     1"                # little-endian (1) in the original
    lines[1] = lines[1][:12] + b"2" + lines[1][13:]
    count = int(lines[1][31:43])                          # record 1: the byte count
    little = np.frombuffer(raw[len(head):len(head) + count], np.dtype([(k, "<" + t) for k, t in fields]))
    big = little.astype(np.dtype([(k, ">" + t) for k, t in fields])).tobytes()
    path = tmp_path / "big_endian.unv"
    path.write_bytes(b"\n".join(lines) + big + raw[len(head) + count:])
    return path


def test_a_big_endian_58b_reads_as_its_ascii_twin(tmp_path):
    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml")
    mapping = ChannelMap({(1, 1): ("acc-top-z", 1.0)}, {(22, 1): ("hammer-z", 1.0)})
    path = _big_endian(tmp_path, [("x", "f4"), ("re", "f8"), ("im", "f8")])
    lines = (DATA / "ufffiles_uneven_double_excerpt_ascii.unv").read_text().splitlines()[13:-1]
    x = np.array([float(line[:13]) for line in lines])
    values = np.array([float(line[13:33]) + 1j * float(line[33:53]) for line in lines])
    read, = read_uff58(path, model, mapping)
    np.testing.assert_allclose(read.frequencies_hz, x, rtol=6e-6)
    np.testing.assert_allclose(read.H[0, 0], values, rtol=1e-11)
