"""Universal Files of other tools beyond pyuff's test data (tests/data/uff/README.md): the test
files of UFFFiles.jl and of the MATLAB readuff/writeuff. Every expected value is read here from
the file's text or bytes with the UFF layout (fixed-width fields, 13 characters a number), or
follows from the unit definitions, never from the reader under test."""

from __future__ import annotations

import struct
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.channels import ChannelMap
from rotordyn_modal.io.measured import read_measured
from rotordyn_modal.io.uff import read_uff58, read_uff_time_records, write_uff58

DATA = Path(__file__).resolve().parent / "data" / "uff"
EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"


@pytest.fixture(scope="module")
def model():
    return rdm.load_model(EXAMPLE)


def _numbers(path, width=13):
    """Every number of a one-dataset ASCII file's data lines (after its 13 header lines), read by
    fixed width as the UFF layout gives them."""
    lines = path.read_text(encoding="latin-1").splitlines()[13:-1]
    return np.array([float(line[k:k + width]) for line in lines for k in range(0, len(line.rstrip()), width)])


def _mapping(response, reference):
    return ChannelMap({response: ("acc-top-z", 1.0)}, {reference: ("hammer-z", 1.0)})


def test_an_frf_reads_the_lines_its_header_counts_not_the_zeros_filling_its_last_line(model):
    """UFFFiles.jl's dataset58_FRF.unv (an excerpt of 40 lines): record 7 counts 40 complex values
    at 0.5 Hz; the writer filled its last line of 6 numbers with four zeros. pyuff returns them as
    two more lines, 20 and 20.5 Hz, of value 0."""
    path = DATA / "ufffiles_frf_filled_excerpt.unv"
    numbers = _numbers(path)
    assert len(numbers) == 84 and np.all(numbers[80:] == 0)
    with pytest.warns(UserWarning, match="axis label 'Receptance' but the unit '\\(m/s\\)/N', a mobility: read as "
                                         "mobility, as the unit says"):
        res, = read_uff58(path, model, _mapping((0, 0), (0, 0)))
    np.testing.assert_array_equal(res.frequencies_hz, 0.5 * np.arange(40))
    np.testing.assert_allclose(res.H[0, 0], numbers[0:80:2] + 1j * numbers[1:80:2], rtol=1e-6)
    assert res.quantity == "mobility"


def test_a_time_record_reads_the_samples_its_header_counts(model):
    """UFFFiles.jl's dataset58_time.unv (an excerpt of 64 samples, force in N): its last line of 6
    filled with two zeros."""
    path = DATA / "ufffiles_time_filled_excerpt.unv"
    numbers = _numbers(path)
    assert len(numbers) == 66
    records = read_uff_time_records(path)
    assert records.signals.shape == (1, 1, 64) and records.quantities == ("force",)
    np.testing.assert_allclose(records.signals[0, 0], numbers[:64], rtol=1e-6)
    # the header's interval, 4.88281E-04 s, to its 6 digits
    assert records.sampling_rate_hz == pytest.approx(1 / 4.88281e-4, rel=1e-12)


def test_values_beyond_the_count_that_are_not_fill_are_named(tmp_path):
    text = (DATA / "ufffiles_time_filled_excerpt.unv").read_text()
    path = tmp_path / "extra.unv"
    path.write_text(text.replace("  0.00000E+00  0.00000E+00\n    -1", "  1.00000E+00  0.00000E+00\n    -1"))
    with pytest.warns(UserWarning, match="dataset 1 .* holds 66 values where its header \\(record 7\\) gives 64: "
                                         "read the first 64"):
        records = read_uff_time_records(path)
    assert records.signals.shape == (1, 1, 64)


def test_a_dataset_holding_fewer_values_than_its_count_is_read_with_a_warning():
    """pyuff's dataset_milestone_in_header.uff: record 7 counts 2,508,876 samples, the file holds 42
    (pyuff's test data keep the start of a longer recording)."""
    path = DATA / "dataset_milestone_in_header.uff"
    with pytest.warns(UserWarning, match="holds 42 of the 2508876 values its header \\(record 7\\) gives \\(the file "
                                         "is cut short\\): read the 42"):
        records = read_uff_time_records(path)
    assert records.signals.shape == (1, 1, 42)


def _binary_body(path):
    raw = path.read_bytes()
    return raw[len(b"\n".join(raw.split(b"\n", 13)[:13])) + 1:]


def test_binary_uneven_double_precision_reads_as_the_same_ascii_file(model):
    """UFFFiles.jl's dataset58_case8 (20 lines): complex doubles over an uneven abscissa, ASCII and
    binary 58b. The UFF definition stores such an abscissa in single precision (4 bytes before
    the two 8-byte doubles; record 1 counts 20 x 20 = 400 bytes); pyuff read 8 bytes there and
    the binary file came out as other numbers (a frequency below 0: refused)."""
    ascii_path = DATA / "ufffiles_uneven_double_excerpt_ascii.unv"
    binary_path = DATA / "ufffiles_uneven_double_excerpt_binary.unv"
    lines = ascii_path.read_text().splitlines()[13:-1]
    x = np.array([float(line[:13]) for line in lines])
    values = np.array([float(line[13:33]) + 1j * float(line[33:53]) for line in lines])
    body = _binary_body(binary_path)
    assert struct.unpack("<f", body[:4])[0] == pytest.approx(x[0], rel=1e-7)   # the definition's layout
    mapping = _mapping((1, 1), (22, 1))
    for path in (ascii_path, binary_path):
        res, = read_uff58(path, model, mapping)
        assert res.quantity == "accelerance"
        np.testing.assert_allclose(res.frequencies_hz, x, rtol=6e-6)       # ASCII abscissa: 6 digits (E13.5)
        np.testing.assert_allclose(res.H[0, 0], values, rtol=1e-11)         # E20.12: 12 digits


@pytest.mark.parametrize("writer", ["ours-binary", "ours-ascii", "pyuff-binary"])
def test_uneven_frequencies_written_here_read_back(model, tmp_path, writer):
    """Uneven frequencies (single-precision numbers) written here (58b: a 4-byte abscissa as the
    UFF definition says, record 1 counting 20 bytes a line; ASCII: E13.5) and by pyuff's writer
    (58b with 8-byte abscissa values and a byte count of num_pts x 8) read back: the data's
    length tells the width."""
    import pyuff

    freqs = np.array([1.0, 2.5, 3.0, 7.25, 11.0])
    res = rdm.frf(model, 0.0, freqs, quantity="accelerance")
    path = tmp_path / "uneven.uff"
    mapping = rdm.io.measured.default_mapping(model)
    if writer == "pyuff-binary":
        sets = []
        for a, out in enumerate(res.outputs):
            for b, inp in enumerate(res.inputs):
                (rsp_node, rsp_dir, rsp_sign), (ref_node, ref_dir, ref_sign) = mapping.node_of(out), mapping.node_of(inp)
                sets.append(pyuff.prepare_58(binary=1, func_type=4, rsp_node=rsp_node, rsp_dir=rsp_dir,
                                             ref_node=ref_node, ref_dir=ref_dir, ordinate_spec_data_type=12,
                                             ordinate_axis_units_lab="m/s^2", orddenom_spec_data_type=13,
                                             orddenom_axis_units_lab="N", abscissa_spec_data_type=18,
                                             abscissa_axis_units_lab="Hz", x=freqs,
                                             data=res.H[a, b] * rsp_sign * ref_sign))
        pyuff.UFF(str(path)).write_sets(sets, mode="add")
        assert str(8 * len(freqs)).encode() in path.read_bytes()[:200]        # pyuff's byte count
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            write_uff58([res], path, mapping, binary=writer == "ours-binary")
    back, = read_measured(path, model)
    np.testing.assert_array_equal(back.frequencies_hz, freqs)
    np.testing.assert_allclose(back.H, res.H, rtol=1e-12 if writer == "ours-ascii" else 0)


def test_inch_pound_units_of_dataset_164_are_converted(model):
    """UFFFiles.jl's dataset151_164_58_55.unv: dataset 164 says inch and pound-force (factors
    39.37... and 0.2248...), the FRF (accelerance, 12 over 13, no labels) is in in/s^2/lbf:
    times 0.0254 / (0.45359237 x 9.80665)."""
    path = DATA / "ufffiles_units_inch_pound.unv"
    lines = path.read_text().splitlines()
    start = lines.index("    58" + " " * 74) + 12         # the 13 header lines begin with the "-1" before it
    numbers = np.array([float(line[k:k + 13]) for line in lines[start:start + 4]
                        for k in range(0, len(line.rstrip()), 13)])
    assert len(numbers) == 20
    res, = read_uff58(path, model, _mapping((1, 1), (22, 1)))
    factor = 0.0254 / (0.45359237 * 9.80665)
    np.testing.assert_allclose(res.H[0, 0], (numbers[0::2] + 1j * numbers[1::2]) * factor, rtol=1e-14)
    np.testing.assert_array_equal(res.frequencies_hz, 0.25 * np.arange(10))


def test_a_universal_file_of_another_ending_is_read(model, tmp_path):
    """readuff's UFF58B.FRF: a 58b FRF (velocity over a reference, 1601 lines of 12.5 Hz) saved
    as .FRF, read by its content (the '-1' and dataset number opening it), also with --mapping."""
    from rotordyn_modal.cli.main import main

    path = DATA / "murmlgrmpf_UFF58B.FRF"
    body = _binary_body(path)
    values = np.frombuffer(body[:1601 * 8], dtype="<f4").astype(float)
    table = tmp_path / "map.csv"
    table.write_text("name,node,direction\nacc-top-z,192,0\nhammer-z,0,0\n")
    res, = read_measured(path, model, table)
    assert res.quantity == "mobility"
    np.testing.assert_array_equal(res.frequencies_hz, 12.5 * np.arange(1601))
    np.testing.assert_array_equal(res.H[0, 0], values[0::2] + 1j * values[1::2])
    out = tmp_path / "frf.csv"
    code = main(["frf", str(EXAMPLE), "--speed", "0", "--freqs", "10:1000:5", "--measured", str(path), "--mapping",
                 str(table), "--quantity", "mobility", "--input", "hammer-z", "--output", "acc-top-z", "--quiet",
                 "--out", str(out)])
    assert code == 0 and out.exists()


def test_a_tdms_file_given_for_frfs_is_told_where_time_records_go(model):
    path = Path(__file__).resolve().parent / "data" / "tdms" / "good_tdms_2.tdms"
    with pytest.raises(InputError, match="holds time records, not FRFs: read them with rdm.read_tdms_records"):
        read_measured(path, model)


def test_a_record_in_volts_is_refused_with_how_to_declare_it():
    """UFFFiles.jl's dataset58_nospacing.uff (a DT9837-A recorder, numbers written without a space
    between them): a time record of unit '(V^2)'. What a volt measures is the sensor's: refused,
    saying how to declare it; declared, it reads."""
    path = DATA / "ufffiles_nospacing_volts.uff"
    with pytest.raises(InputError, match="ordinate unit '\\(V\\^2\\)' is not understood: .*or declare it: "
                                         "read_uff_time_records\\(\\.\\.\\., units=\\{'\\(V\\^2\\)': "):
        read_uff_time_records(path)
    numbers = _numbers(path)
    records = read_uff_time_records(path, units={"(V^2)": ("acceleration", 98.0665)})
    np.testing.assert_allclose(records.signals[0, 0], numbers * 98.0665, rtol=1e-12)
    assert records.sampling_rate_hz == pytest.approx(1 / 4.99942e-4, rel=1e-12)


def test_frfs_told_apart_only_by_their_entity_names_are_refused_naming_them(model, tmp_path):
    """The tool of dataset58_FRF.unv numbers no nodes: node 0 direction 0, the point in the entity
    name ('.1.Z-'). Two such FRFs in one file cannot be placed by a mapping of nodes."""
    text = (DATA / "ufffiles_frf_filled_excerpt.unv").read_text()
    path = tmp_path / "two.unv"
    path.write_text(text + text.replace(".1.Z-", ".2.Z-"))
    with pytest.raises(InputError, match="the FRFs of datasets 1 and 2 are both 0:\\+0 and differ only by their entity "
                                         "names \\('.1.Z- / .56.Z' and '.2.Z- / .56.Z'\\)"):
        read_uff58(path, model, _mapping((0, 0), (0, 0)))


@pytest.mark.parametrize("kind,label,value,rpm", [
    (19, "NONE", 1500.0, 1500.0),                  # rpm
    (19, "rad/s", 100.0, 100.0 * 30.0 / np.pi),
    (0, "Hz", 20.0, 1200.0),                       # revolutions per second
    (0, "1/min", 900.0, 900.0),
])
def test_the_speed_is_read_in_the_unit_of_the_z_axis(model, tmp_path, kind, label, value, rpm):
    import pyuff

    res = rdm.frf(model, 0.0, np.linspace(1.0, 40.0, 40), quantity="accelerance")
    path = tmp_path / "z.uff"
    write_uff58([res], path, rdm.io.measured.default_mapping(model))
    sets = pyuff.UFF(str(path)).read_sets()
    for s in sets:
        s.update(z_axis_spec_data_type=kind, z_axis_axis_units_lab=label, z_axis_value=value)
    path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    back, = read_measured(path, model)
    assert back.speed * 30.0 / np.pi == pytest.approx(rpm, rel=1e-12)


@pytest.mark.parametrize("kind,label", [(17, "s"), (17, "NONE"), (20, "NONE"), (0, "s")])
def test_a_z_axis_of_no_speed_is_not_read_as_rpm(model, tmp_path, kind, label):
    """A run-up waterfall's FRFs carry their time (data type 17) or order (20) in the z-axis: 2.5 s
    was read as 2.5 rpm."""
    import pyuff

    res = rdm.frf(model, 0.0, np.linspace(1.0, 40.0, 40), quantity="accelerance")
    path = tmp_path / "z.uff"
    write_uff58([res], path, rdm.io.measured.default_mapping(model))
    sets = pyuff.UFF(str(path)).read_sets()
    for s in sets:
        s.update(z_axis_spec_data_type=kind, z_axis_axis_units_lab=label, z_axis_value=2.5)
    path.unlink()
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    with pytest.raises(InputError, match="z-axis"):
        read_measured(path, model)


def test_bytes_after_a_binary_sets_values_are_no_value(tmp_path):
    """Exporters write line ends between a 58b set's values and its closing '-1' (pyuff issues 38
    and 88, the latter a Simcenter Test.Lab 2021 file); 8 bytes of them are one more double to
    pyuff (2.95e-260 here). Record 7's count delimits the values: pyuff's binary8byte.uff with 8
    such bytes reads as the file without them, without a word."""
    raw = (DATA / "binary8byte.uff").read_bytes()
    assert raw.endswith(b"    -1\r\n")
    path = tmp_path / "trailing.uff"
    path.write_bytes(raw[:-8] + b"\r\n" * 4 + b"    -1\r\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        records = read_uff_time_records(path)
    plain = read_uff_time_records(DATA / "binary8byte.uff")
    assert records.signals.shape == plain.signals.shape == (1, 1, 250)
    np.testing.assert_array_equal(records.signals, plain.signals)


def test_a_double_precision_set_whose_last_line_is_padded_with_blanks(model, tmp_path):
    """UFFFiles.jl's dataset58_case7_ascii.unv (an excerpt of 9 lines): complex doubles, 4E20.12 a
    line, even abscissa. Read as it is, and with its last, short line padded to 80 columns with
    blanks, as Fortran writers and DataPhysics SignalStar write their last lines (pyuff issue 20):
    pyuff refused that ('Error when reading data-set(s)'); the file is read from a copy without
    the blanks, the values being the text's."""
    path = DATA / "ufffiles_even_double_excerpt.unv"
    numbers = _numbers(path, width=20)
    assert len(numbers) == 18
    expected = numbers[0::2] + 1j * numbers[1::2]
    padded = tmp_path / "padded.unv"
    lines = path.read_text().split("\n")
    lines[-3] = lines[-3].ljust(80)
    padded.write_text("\n".join(lines))
    before = padded.read_bytes()
    for source in (path, padded):
        res, = read_uff58(source, model, _mapping((1, 1), (22, 1)))
        np.testing.assert_array_equal(res.H[0, 0], expected)
        np.testing.assert_array_equal(res.frequencies_hz, 0.25 * np.arange(9))
    assert padded.read_bytes() == before          # read from a copy: the file is left as it was


def test_a_universal_file_saved_as_txt_is_read_as_one(model, tmp_path):
    """Users rename a .unv to .txt to attach it to a message (OpenModal issues 14 and 17): its
    content, the '-1' and '58' opening it, says what it is; it was read as a CSV table and refused."""
    path = tmp_path / "1m.txt"
    path.write_bytes((DATA / "ufffiles_units_inch_pound.unv").read_bytes())
    res, = read_measured(path, model, ChannelMap({(1, 1): ("acc-top-z", 1.0)}, {(22, 1): ("hammer-z", 1.0)}))
    direct, = read_uff58(DATA / "ufffiles_units_inch_pound.unv", model, _mapping((1, 1), (22, 1)))
    np.testing.assert_array_equal(res.H, direct.H)
