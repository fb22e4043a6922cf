"""Universal Files written by ``write_uff58`` (``frf --out f.uff``) as the UFF definition reads
them. Every dataset is decoded here from the file's bytes with the layout of dataset 58 and 58b
(record 1 of a 58b: byte order, floating-point format, ASCII line count, byte count; record 7:
3I10,3E13.5; record 12: 4E20.12 (even), E13.5,2E20.12 or 2(E13.5,E20.12) (uneven) in ASCII; in
binary the same fields by their data type, the abscissa of uneven data in 4 bytes), as MATLAB's
readuff and UFFFiles.jl read them (and as tests/test_uff_other_tools.py reads other tools'
files), never by the reader under test. The files are then read by pyuff and by our reader."""

from __future__ import annotations

import re
import struct
import warnings
from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.io.measured import default_mapping, read_measured
from rotordyn_modal.io.uff import write_uff58

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
EVEN = np.linspace(1.0, 40.0, 79)                    # steps of 0.5 Hz
UNEVEN = np.array([1.0, 2.5, 3.0, 7.25, 11.0])      # single-precision numbers, 6 digits


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(EXAMPLE)


def _fields(line, widths, kinds):
    out, start = [], 0
    for width, kind in zip(widths, kinds):
        text = line[start:start + width]
        out.append(kind(text.strip()) if text.strip() else None)
        start += width
    return out


def _decode(path):
    """Every dataset 58/58b of a file, by the UFF definition: a list of dicts with the header
    fields and ``x``, ``values`` (complex or real), and what the layout was."""
    raw = path.read_bytes()
    sets, at = [], 0
    while True:
        start = raw.find(b"    -1\n", at)
        if start < 0:
            return sets
        lines, pos = [], start + 7
        for _ in range(12):                               # the identifier line, records 1 to 11
            end = raw.index(b"\n", pos)
            lines.append(raw[pos:end].decode("latin-1"))
            pos = end + 1
        ident = lines[0]
        assert ident[:6] == "    58", ident
        binary = ident[6:7].lower() == "b"
        d = {"binary": binary}
        if binary:
            d["order"], d["fp"], d["n_ascii"], d["n_bytes"] = _fields(ident[7:], (6, 6, 12, 12), (int,) * 4)
        d["id1"], d["id2"] = lines[1].rstrip(), lines[2].rstrip()
        (d["func"], _, _, _, d["rsp_ent"], d["rsp_node"], d["rsp_dir"], d["ref_ent"], d["ref_node"],
         d["ref_dir"]) = _fields(lines[6], (5, 10, 5, 10, 11, 10, 4, 11, 10, 4),
                                 (int, int, int, int, str, int, int, str, int, int))
        d["type"], d["n"], d["even"], d["xmin"], d["dx"], d["z"] = _fields(
            lines[7], (10, 10, 10, 13, 13, 13), (int, int, int, float, float, float))
        for key, line in zip(("abscissa", "ordinate", "denominator", "zaxis"), lines[8:12]):
            d[key] = _fields(line, (10, 5, 5, 5, 21, 21), (int, int, int, int, str, str))
        n, complex_, double, even = d["n"], d["type"] in (5, 6), d["type"] in (4, 6), d["even"] == 1
        parts = 2 if complex_ else 1
        if binary:
            assert d["n_ascii"] == 11 and d["fp"] == 2          # 11 ASCII lines, IEEE 754
            order = "<" if d["order"] == 1 else ">"
            real = "d" if double else "f"
            field = (real * parts) if even else "f" + real * parts      # uneven: the abscissa in 4 bytes
            size = struct.calcsize(order + field)
            assert d["n_bytes"] == n * size, (d["n_bytes"], n, size)    # record 1's byte count
            body = raw[pos:pos + d["n_bytes"]]
            rows = np.array(list(struct.iter_unpack(order + field, body)), float).reshape(n, -1)
            pos += d["n_bytes"]
            assert raw[pos:pos + 7] == b"    -1\n"          # the closing -1 right after the values
            pos += 7
            d["layout"] = "binary"
        else:
            stop = raw.index(b"    -1\n", pos)
            text = raw[pos:stop].decode("latin-1").splitlines()
            if even:
                widths = [20] * 4 if double else [13] * 6
            elif double:
                widths = [13, 20, 20] if complex_ else [13, 20, 13, 20]
            else:
                widths = [13] * 6
            numbers = [float(line[sum(widths[:k]):sum(widths[:k + 1])])
                       for line in text for k in range(len(widths)) if line[sum(widths[:k]):sum(widths[:k + 1])].strip()]
            rows = np.array(numbers).reshape(n, -1)
            pos = stop + 7
            d["layout"] = "ascii"
            d["lines"] = text
        if even:
            d["x"] = d["xmin"] + d["dx"] * np.arange(n)
            values = rows
        else:
            d["x"], values = rows[:, 0], rows[:, 1:]
        d["values"] = values[:, 0] + 1j * values[:, 1] if complex_ else values[:, 0]
        sets.append(d)
        at = pos


def _written(model, path, freqs, binary, speed=0.0, expect=None):
    res = rdm.frf(model, speed, freqs, quantity="accelerance")
    coh = np.linspace(0.5, 1.0, res.H.size).reshape(res.H.shape)
    res = type(res)(**{**res.__dict__, "coherence": coh})
    if expect is None:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            write_uff58([res], path, default_mapping(model), binary=binary)
    else:
        with pytest.warns(UserWarning, match=expect):
            write_uff58([res], path, default_mapping(model), binary=binary)
    return res


def _check_frfs(sets, res, freq_rtol, value_rtol):
    frfs = [d for d in sets if d["func"] == 4]
    cohs = [d for d in sets if d["func"] == 6]
    assert len(frfs) == len(cohs) == res.H.shape[0] * res.H.shape[1]
    for d in frfs:
        np.testing.assert_allclose(d["x"], res.frequencies_hz, rtol=freq_rtol, atol=0)
    stacked = np.array([d["values"] for d in frfs])
    expected = np.array([res.H[a, b] for a in range(res.H.shape[0]) for b in range(res.H.shape[1])])
    # each set is one of the FRFs, times the sign of the mapping's directions
    for row in stacked:
        best = min(np.max(np.abs(row - sign * e) / np.abs(e)) for e in expected for sign in (1, -1))
        assert best <= value_rtol
    for d in cohs:
        assert any(np.allclose(d["values"], c, rtol=value_rtol, atol=0) for c in res.coherence.reshape(-1, len(d["x"])))


@pytest.mark.parametrize("binary", [True, False])
def test_even_frequencies_are_written_as_even_data(model, tmp_path, binary):
    """Frequencies of a constant step are even data (record 7: spacing 1, minimum, increment; no
    abscissa values), binary as 8-byte doubles counted in record 1 (16 bytes a complex value)."""
    path = tmp_path / "even.uff"
    res = _written(model, path, EVEN, binary)
    sets = _decode(path)
    assert {d["layout"] for d in sets} == {"binary" if binary else "ascii"}
    assert all(d["even"] == 1 and d["xmin"] == 1.0 and d["dx"] == 0.5 and d["n"] == 79 for d in sets)
    assert {d["type"] for d in sets if d["func"] == 4} == {6} and {d["type"] for d in sets if d["func"] == 6} == {4}
    _check_frfs(sets, res, 0, 0 if binary else 1e-12)
    if not binary:      # 4E20.12: four fields of 20 columns a line, 13 digits
        lines = next(d for d in sets if d["func"] == 4)["lines"]
        assert all(len(line) == 80 for line in lines[:-1]) and re.fullmatch(r"( [- ]\d\.\d{12}E[-+]\d\d){4}", lines[0])


@pytest.mark.parametrize("binary", [True, False])
def test_even_frequencies_read_back_by_pyuff_and_by_us(model, tmp_path, binary):
    path = tmp_path / "even.uff"
    res = _written(model, path, EVEN, binary)
    frfs = [s for s in pyuff.UFF(str(path)).read_sets() if s["func_type"] == 4]
    for s in frfs:
        np.testing.assert_array_equal(s["x"], EVEN)
        assert len(s["data"]) == len(EVEN)
    back, = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, EVEN)
    np.testing.assert_allclose(back.H, res.H, rtol=0 if binary else 1e-12)


def test_uneven_binary_stores_the_abscissa_in_four_bytes(model, tmp_path):
    """58b of uneven data: per line a 4-byte abscissa, then the two 8-byte doubles; record 1
    counts 20 bytes a line. Frequencies that are single-precision numbers and the values survive
    exactly, read by the definition and by our reader."""
    path = tmp_path / "uneven.uff"
    res = _written(model, path, UNEVEN, True)
    sets = _decode(path)
    assert all(d["even"] == 0 and d["layout"] == "binary" for d in sets)
    assert {d["n_bytes"] for d in sets if d["func"] == 4} == {20 * len(UNEVEN)}
    assert {d["n_bytes"] for d in sets if d["func"] == 6} == {12 * len(UNEVEN)}
    _check_frfs(sets, res, 0, 0)
    back, = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, UNEVEN)
    np.testing.assert_array_equal(back.H, res.H)


def test_uneven_ascii_is_case_8(model, tmp_path):
    """ASCII uneven complex doubles: E13.5 abscissa and two E20.12 values a line (53 columns)."""
    path = tmp_path / "uneven.uff"
    res = _written(model, path, UNEVEN, False)
    sets = _decode(path)
    frf = next(d for d in sets if d["func"] == 4)
    assert frf["even"] == 0 and all(len(line) == 53 for line in frf["lines"])
    _check_frfs(sets, res, 0, 1e-12)
    for s in (s for s in pyuff.UFF(str(path)).read_sets() if s["func_type"] == 4):
        np.testing.assert_array_equal(s["x"], UNEVEN)
    back, = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, UNEVEN)


def test_uneven_frequencies_beyond_single_precision_are_said(model, tmp_path):
    """A frequency of more digits than 4 bytes hold moves to its single-precision value, said in
    one warning with the largest move."""
    freqs = np.array([1.0, 2.5, 10.0 / 3.0, 7.25, 11.0])
    path = tmp_path / "third.uff"
    res = _written(model, path, freqs, True, expect=r"third.uff: 1 of 5 frequencies .* 4 bytes .* up to 7.9e-08 Hz")
    sets = _decode(path)
    for d in sets:
        np.testing.assert_array_equal(d["x"], freqs.astype(np.float32).astype(float))
    back, = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, freqs.astype(np.float32).astype(float))
    np.testing.assert_array_equal(back.H, res.H)


def test_an_even_step_the_header_rounds_is_said(model, tmp_path):
    """37/199 Hz steps: record 7 keeps the increment to 6 digits (E13.5), so the 200th line is
    read 199 x (1.85930e-01 - 37/199) Hz away; the warning gives that move; what is read is the
    header's grid (by the definition, by pyuff and by us)."""
    freqs = np.linspace(3.0, 40.0, 200)
    header = 3.0 + 0.185930 * np.arange(200)
    move = abs(header[-1] - 40.0)
    assert 6.9e-5 < move < 7.1e-5
    path = tmp_path / "step.uff"
    _written(model, path, freqs, None, expect=r"step.uff: .* step of 0.185929648241 Hz: .* 6 digits .* up to 7e-05 Hz")
    sets = _decode(path)
    assert all(d["even"] == 1 and d["dx"] == 0.18593 and d["layout"] == "ascii" for d in sets)
    for s in (s for s in pyuff.UFF(str(path)).read_sets() if s["func_type"] == 4):
        np.testing.assert_allclose(s["x"], header, rtol=1e-15)
    back, = read_measured(path, model)
    np.testing.assert_allclose(back.frequencies_hz, header, rtol=1e-15)


def test_the_speed_is_an_rpm_z_axis(model, tmp_path):
    """Record 11: data type 19 (rpm) with the unit label rpm; record 7's z value the speed."""
    path = tmp_path / "speed.uff"
    _written(model, path, EVEN, True, speed=rdm.rpm(3000))
    sets = _decode(path)
    assert all(d["z"] == 3000.0 and d["zaxis"][0] == 19 and d["zaxis"][5] == "rpm" for d in sets)
    assert read_measured(path, model)[0].speed == pytest.approx(rdm.rpm(3000), rel=1e-12)


def test_units_names_and_entity_fields(model, tmp_path):
    """Record 8 says Hz; record 9/10 the ordinate over N; entity names left-justified in their
    10 columns (a longer name: NONE there, whole in ID line 1)."""
    data = model.to_dict()
    data["sensors"][0]["name"] = "accelerometer-top-z"
    long = rdm.Model.from_dict(data)
    path = tmp_path / "names.uff"
    _written(long, path, EVEN, False)
    sets = _decode(path)
    raw_lines = path.read_text(encoding="latin-1").splitlines()
    record6 = [line for line in raw_lines if line.startswith("    4         0")]
    assert record6 and all(line[31:41] in ("NONE      ", "acc-side-y") for line in record6)
    frfs = [d for d in sets if d["func"] == 4]
    assert {d["abscissa"][0] for d in frfs} == {18} and {d["abscissa"][5] for d in frfs} == {"Hz"}
    assert {d["ordinate"][5] for d in frfs} == {"m/s^2"} and {d["denominator"][5] for d in frfs} == {"N"}
    assert any(d["id1"].startswith("accelerometer-top-z / ") and d["rsp_ent"] == "NONE" for d in frfs)


def test_a_moment_excitation_is_written_in_newton_metres(model, tmp_path):
    """An excitation of kind moment about -Y is reference direction -5 (a rotation); dataset 58's
    excitation force (13) along a rotation is a moment: unit label N*m, length and force exponents
    1 and 1 (Addendum A), not N. Read back as written."""
    data = model.to_dict()
    data["excitations"][1].update(kind="moment", direction=[0.0, -1.0, 0.0])
    moment = rdm.Model.from_dict(data)
    path = tmp_path / "moment.uff"
    res = _written(moment, path, EVEN, True)
    frfs = [d for d in _decode(path) if d["func"] == 4]
    assert {d["ref_dir"] for d in frfs} == {3, -5}
    for d in frfs:
        expected = [13, 1, 1, 0, "NONE", "N*m"] if d["ref_dir"] == -5 else [13, 0, 1, 0, "NONE", "N"]
        assert d["denominator"] == expected
    back, = read_measured(path, moment)
    np.testing.assert_array_equal(back.H, res.H)


def test_a_step_within_round_off_is_even_data(model, tmp_path):
    """Frequencies summed step by step (0.1 Hz added 399 times: round-off of some 1e-14 Hz, not
    a linspace) are even data of step 0.1 Hz, without a warning."""
    freqs = np.cumsum(np.full(400, 0.1))
    assert np.any(freqs != 0.1 * np.arange(1, 401)) and np.max(np.abs(freqs - 0.1 * np.arange(1, 401))) < 1e-12
    path = tmp_path / "summed.uff"
    _written(model, path, freqs, False)
    sets = _decode(path)
    assert all(d["even"] == 1 and d["xmin"] == 0.1 and d["dx"] == 0.1 for d in sets)
    back, = read_measured(path, model)
    np.testing.assert_allclose(back.frequencies_hz, freqs, rtol=1e-13)
