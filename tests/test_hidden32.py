"""Hidden checks of issue 27 with inputs not tried before, in its families: model files whose
numbers a double cannot hold or whose characters no one sees, measured tables whose columns are
misspelled, other tools' files with a value or a property missing, and physics typed in the
wrong unit (a gravity in mm/s^2, a bearing stiffness in N/mm). Each through the reader the
command line calls, or the command line in this process (exit 2 with one line)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError, ModelError
from rotordyn_modal.io.measured import read_measured
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
SPRING_BLOCK = ROOT / "examples" / "spring_block_rotor.toml"
GEAR = ROOT / "examples" / "gear_machine.toml"
MAPPING = "name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,101,3\nshaker-y,102,2\n"
#: the spring block's rotor [kg] and its bearing's radial stiffness [N/m], as the example gives them
BLOCK_MASS, BLOCK_STIFFNESS = 5.0, 2000.0


def _model_text(**replace) -> str:
    text = SPRING_BLOCK.read_text()
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def _write(tmp_path, text, name="m.toml", encoding="utf-8") -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode(encoding))
    return path


# ----------------------------------------------------------------------- numbers a double cannot hold
@pytest.mark.parametrize("typed", ["1e400", "-1.5E+400"])
def test_a_literal_beyond_any_double_is_refused_as_typed_with_its_line(tmp_path, typed):
    """``stiffness = 1e400`` was refused as 'stiffness = inf', a value the file does not hold."""
    text = _model_text(**{"stiffness = 2000.0 ": f"stiffness = {typed} "})
    line = next(n for n, row in enumerate(text.splitlines(), start=1) if typed in row)
    with pytest.raises(ModelError) as caught:
        rdm.load_model(_write(tmp_path, text))
    message = str(caught.value)
    assert f"line {line}: stiffness = {typed}:" in message and "inf" not in message, message


@pytest.mark.parametrize("key, old, new", [
    ("gravity", "-9.81]", "-9.81e-400]"),
    ("stiffness", "stiffness = 2000.0 ", "stiffness = 1e-400 "),
])
def test_a_non_zero_literal_below_any_double_is_refused(tmp_path, key, old, new):
    """``gravity = [0, 0, -9.81e-400]`` was read as no gravity at all without a word (float()
    gives 0.0): a number the file does not say."""
    with pytest.raises(ModelError) as caught:
        rdm.load_model(_write(tmp_path, _model_text(**{old: new})))
    assert f"{key} = " in str(caught.value) and "e-400" in str(caught.value), caught.value


def test_zero_written_with_an_exponent_and_subnormal_numbers_are_read(tmp_path):
    """``0.0e-400`` is zero as typed, 1e-310 a double (subnormal): neither is refused."""
    model = rdm.load_model(_write(tmp_path, _model_text(**{"position = [0.0, 0.0, 0.0]":
                                                           "position = [0.0e-400, 1e-310, 0.0]"})))
    assert np.abs(model.bearings[0].position).max() <= 1e-310


# ----------------------------------------------------------------------- characters no one sees
@pytest.mark.parametrize("text, code", [
    ("\ufeff\ufeff" + SPRING_BLOCK.read_text(), "U+FEFF"),                        # a second byte-order mark
    (_model_text(**{"mass = 5.0": "\u200bmass = 5.0"}), "U+200B"),               # a zero-width space
    (_model_text(**{"mass = 5.0": "mass\u00a0= 5.0"}), "U+00A0"),                # a no-break space
    (SPRING_BLOCK.read_text() + "\0", "U+0000"),                                 # a NUL at the end
])
def test_a_toml_error_at_an_invisible_character_names_it(tmp_path, text, code):
    """'Invalid statement (at line 1, column 1)' pointed at a character no editor shows."""
    with pytest.raises(ModelError) as caught:
        rdm.load_model(_write(tmp_path, text))
    assert code in str(caught.value) and "invisible" in str(caught.value), caught.value


# ----------------------------------------------------------------------- measured tables' columns
@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """The gear machine's FRFs at 600 rpm, 2 to 40 Hz in 5 lines, written by ``frf --out`` as
    CSV and UFF 58 (read only)."""
    folder = tmp_path_factory.mktemp("measured")
    for name in ("g.csv", "g.uff"):
        assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--out", str(folder / name),
                     "--quiet"]) == 0
    return folder


@pytest.mark.parametrize("column, meant", [("quantity", "quantitiy"), ("speed_rpm", "speed_rmp")])
def test_a_misspelled_measured_column_is_refused_naming_the_column_meant(tmp_path, capsys, measured, column,
                                                                        meant):
    """A mobility whose 'quantitiy' column was misspelled was read as the default receptance
    without a word (a wrong FRF), a 'speed_rmp' column as 0 rpm."""
    text = (measured / "g.csv").read_text().replace("receptance", "mobility")
    lines = text.splitlines()
    lines[0] = lines[0].replace(column, meant)
    path = _write(tmp_path, "\n".join(lines) + "\n", "m.csv")
    model = rdm.load_model(GEAR)
    with pytest.raises(InputError) as caught:
        read_measured(path, model)
    assert repr(meant) in str(caught.value) and f"did you mean {column!r}" in str(caught.value), caught.value
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--quantity", "mobility", "--measured",
                 str(path), "--out", str(tmp_path / "o.csv"), "--quiet"]) == 2
    _one_line_error(capsys, meant, column)
    assert not (tmp_path / "o.csv").exists()


def test_an_extra_measured_column_is_named_in_a_warning_and_the_data_read(tmp_path, measured):
    """A column the layout does not read (a comment) is passed over with one warning line."""
    lines = (measured / "g.csv").read_text().splitlines()
    text = "\n".join([lines[0] + ",comment"] + [row + ",ok" for row in lines[1:]]) + "\n"
    model = rdm.load_model(GEAR)
    with pytest.warns(UserWarning, match="comment"):
        got = read_measured(_write(tmp_path, text, "m.csv"), model)
    plain = read_measured(measured / "g.csv", model)
    assert np.array_equal(got[0].H, plain[0].H)


def test_a_misspelled_sign_column_of_a_mapping_table_is_refused(tmp_path, measured):
    """'sing' for 'sign': the sign -1 of a channel mounted upside down was dropped silently."""
    table = _write(tmp_path, MAPPING.replace("direction\n", "direction,sing\n").replace(",3\n", ",3,-1\n")
                   .replace(",2\n", ",2,1\n"), "map.csv")
    with pytest.raises(InputError) as caught:
        read_measured(measured / "g.uff", rdm.load_model(GEAR), table)
    assert "'sing'" in str(caught.value) and "did you mean 'sign'" in str(caught.value), caught.value


def test_a_node_with_a_digit_separator_is_refused(tmp_path, measured):
    """Python's float() reads '1_0' as 10: the channel was placed on node 10 without a word."""
    table = _write(tmp_path, MAPPING.replace("acc-top-z,1,3", "acc-top-z,1_0,3"), "map.csv")
    with pytest.raises(InputError) as caught:
        read_measured(measured / "g.uff", rdm.load_model(GEAR), table)
    assert "map.csv: line 2: node = '1_0'" in str(caught.value), caught.value


# ----------------------------------------------------------------------- other tools' files
def test_a_universal_file_frf_with_a_nan_names_the_value_and_its_frequency(tmp_path, measured):
    """Was 'FRF 1:3 / 101:3: 5 values for 5 frequencies, or non-finite values'."""
    text = (measured / "g.uff").read_text().splitlines(keepends=True)
    header_end = next(i for i, row in enumerate(text) if row.strip().startswith("18 ") or
                      row.split()[:1] == ["18"]) + 4          # records 8 to 11, then the data
    first = text[header_end].split()[0]
    text[header_end] = text[header_end].replace(first, "NaN".rjust(len(first)), 1)
    with pytest.raises(InputError) as caught:
        read_measured(_write(tmp_path, "".join(text), "m.uff"), rdm.load_model(GEAR))
    assert "value 1 of 5 (at 2 Hz)" in str(caught.value) and "nan" in str(caught.value), caught.value


def test_a_tdms_channel_without_its_sampling_interval_says_so(tmp_path):
    """Was 'sampling intervals [0.0] s': a number the file does not hold."""
    nptdms = pytest.importorskip("nptdms")
    path = tmp_path / "r.tdms"
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.RootObject(), nptdms.GroupObject("g"),
                              nptdms.ChannelObject("g", "a", np.sin(np.arange(64.0)), properties={"unit_string": "g"})])
    with pytest.raises(InputError) as caught:
        rdm.read_tdms_records(path)
    assert "no wf_increment" in str(caught.value), caught.value


# ----------------------------------------------------------------------- physics in the wrong unit
def _warnings_of(path) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rdm.load_model(path)
    return [str(w.message) for w in caught]


def test_a_bearing_stiffness_in_n_per_mm_draws_the_sag_of_its_rotor(tmp_path):
    """The spring block's 2000 N/m typed as 2 (N/mm): its rotor would sag m g / k = 24.5 m in its
    bearing, and the model was read without a word (only the stator's sag on mounts was looked
    at)."""
    path = _write(tmp_path, _model_text(**{"stiffness = 2000.0 ": "stiffness = 2.0 "}))
    sag = BLOCK_MASS * 9.81 / (BLOCK_STIFFNESS / 1000)     # the bearing carries the whole weight
    lines = [w for w in _warnings_of(path) if "sag" in w]
    assert len(lines) == 1 and f"sag {sag:.3g} m at [bearings.spring-block]" in lines[0], lines


def test_a_plausible_bearing_sag_draws_no_warning():
    """The example itself sags m g / k = 2.5 cm in its spring block: no warning."""
    assert BLOCK_MASS * 9.81 / BLOCK_STIFFNESS < 0.1
    assert not [w for w in _warnings_of(SPRING_BLOCK) if "sag" in w or "gravity" in w]


@pytest.mark.parametrize("gravity, warned", [(-9810.0, True), (-386.09, True), (-32.174, True), (-9.81, False),
                                             (-1.62, False)])
def test_a_gravity_in_another_unit_draws_one_warning(tmp_path, gravity, warned):
    """9810 (mm/s^2), 386 (in/s^2) and 32.17 (ft/s^2) were taken as m/s^2 without a word: a
    journal bearing's load and eccentricity, a sag, follow from it; the Moon's is legal."""
    path = _write(tmp_path, _model_text(**{"gravity = [0.0, 0.0, -9.81]": f"gravity = [0.0, 0.0, {gravity}]"}))
    lines = [w for w in _warnings_of(path) if "gravity = " in w]
    assert len(lines) == int(warned), lines
    if warned:
        assert f"{abs(gravity) / 9.80665:.4g} g" in lines[0], lines


# ----------------------------------------------------------------------- outline tables
@pytest.mark.parametrize("text, words", [
    ("0,0,0\n1,0,0\n", ["holds numbers", "header line"]),          # was "column '0' is named twice"
    ("z,y,x\n0,0,0\nnan,1,0\n", ["line 3: z = 'nan'"]),              # was "z empty": a cell that is not
])
def test_an_outline_without_a_header_or_with_a_nan_cell_says_what_it_holds(tmp_path, capsys, text, words):
    path = _write(tmp_path, text, "o.csv")
    assert main(["modes", str(GEAR), "--speed", "600", "--outline", str(path), "--shape", "1", "--plot",
                 str(tmp_path / "s.png"), "--quiet"]) == 2
    _one_line_error(capsys, *words)
    assert not (tmp_path / "s.png").exists()


def test_a_measured_table_refused_gets_one_line_without_a_warning_of_its_columns(tmp_path, capsys, measured):
    """A table without its header line was refused after a warning naming its first row's
    numbers as unread columns: two lines for one mistake."""
    lines = (measured / "g.csv").read_text().splitlines()
    path = _write(tmp_path, "\n".join(lines[1:]) + "\n", "m.csv")
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--measured", str(path), "--out",
                 str(tmp_path / "o.csv"), "--quiet"]) == 2
    _one_line_error(capsys, "expected the columns")


def test_a_measured_value_beyond_a_double_is_named_as_typed(tmp_path, measured):
    """``1e400`` in a CSV's real column was refused as 'real = inf', a value the file does not hold."""
    lines = (measured / "g.csv").read_text().splitlines()
    cells = lines[1].split(",")
    cells[lines[0].split(",").index("real")] = "1e400"
    path = _write(tmp_path, "\n".join([lines[0], ",".join(cells), *lines[2:]]) + "\n", "m.csv")
    with pytest.raises(InputError) as caught:
        read_measured(path, rdm.load_model(GEAR))
    assert "real = 1e400 " in str(caught.value) and "line 2" in str(caught.value), caught.value
