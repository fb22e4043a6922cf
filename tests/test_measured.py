"""Measured data: UFF 58/58b and CSV round trips, a file from another tool, refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import default_mapping, read_measured, write_csv
from rotordyn_modal.io.uff import write_uff58

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
FREQS = np.linspace(1.0, 40.0, 79)


@pytest.fixture
def model():
    return rdm.load_model(EXAMPLE)


def _sets(model, quantity="accelerance"):
    out = []
    for speed in (0.0, rdm.rpm(3000)):
        res = rdm.frf(model, speed, FREQS, quantity=quantity)
        coh = np.linspace(0.5, 1.0, res.H.size).reshape(res.H.shape)
        out.append(FRFResult(**{**res.__dict__, "coherence": coh}))
    return out


@pytest.mark.parametrize("suffix,binary", [(".uff", False), (".uff", True), (".csv", None)])
def test_round_trip(tmp_path, model, suffix, binary):
    sets = _sets(model)
    path = tmp_path / f"m{suffix}"
    if suffix == ".csv":
        write_csv(sets, path)
    else:
        write_uff58(sets, path, default_mapping(model), binary=binary)
        assert (path.read_bytes()[:200].lower().count(b"58b") == 1) == bool(binary)
    back = read_measured(path, model)
    assert [b.speed for b in back] == pytest.approx([s.speed for s in sets])
    for b, s in zip(back, sets):
        assert b.outputs == s.outputs and b.inputs == s.inputs and b.quantity == "accelerance"
        # ASCII UFF holds 12 significant digits, binary and CSV hold all of them
        np.testing.assert_allclose(b.H, s.H, rtol=1e-10 if binary is False else 1e-15)
        np.testing.assert_allclose(b.coherence, s.coherence, rtol=1e-10)
        np.testing.assert_allclose(b.frequencies_hz, FREQS, rtol=1e-12)


@pytest.mark.parametrize("suffix", [".uff", ".csv"])
def test_round_trip_keeps_the_models_channel_order_when_it_is_not_alphabetical(tmp_path, model, suffix):
    data = model.to_dict()
    data["sensors"].reverse()
    data["excitations"].reverse()
    reversed_model = rdm.Model.from_dict(data)
    assert [x.name for x in reversed_model.excitations] == ["shaker-y", "hammer-z"]
    sets = _sets(reversed_model)
    path = tmp_path / f"m{suffix}"
    if suffix == ".csv":
        write_csv(sets, path)
    else:
        write_uff58(sets, path, default_mapping(reversed_model), binary=True)
    for b, s in zip(read_measured(path, reversed_model), sets):
        assert b.outputs == s.outputs == ("acc-side-y", "acc-top-z") and b.inputs == s.inputs
        np.testing.assert_allclose(b.H, s.H, rtol=1e-15)


def test_uff_records_speed_units_and_types(tmp_path, model):
    path = tmp_path / "m.uff"
    write_uff58(_sets(model, "mobility"), path, default_mapping(model))
    sets = pyuff.UFF(str(path)).read_sets()
    frfs = [s for s in sets if s["func_type"] == 4]
    assert sorted({s["z_axis_value"] for s in frfs}) == pytest.approx([0.0, 3000.0])
    assert {s["ordinate_spec_data_type"] for s in frfs} == {11}
    assert {s["orddenom_spec_data_type"] for s in frfs} == {13}
    assert {s["abscissa_spec_data_type"] for s in frfs} == {18}
    assert len([s for s in sets if s["func_type"] == 6]) == len(frfs)


def _foreign_file(path, **overrides):
    """A file as another tool writes it: its own node numbers, one FRF, units labelled."""
    h = rdm.frf(rdm.load_model(EXAMPLE), 0.0, FREQS, "hammer-z", "acc-top-z", "accelerance").H[0, 0]
    data = dict(binary=0, func_type=4, rsp_node=7, rsp_dir=3, ref_node=12, ref_dir=-3,
                ordinate_spec_data_type=12, ordinate_axis_units_lab="m/s^2", orddenom_spec_data_type=13,
                orddenom_axis_units_lab="N", abscissa_spec_data_type=18, data=-h, x=FREQS, z_axis_value=0.0)
    data.update(overrides)
    open(path, "w").close()
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(**data)], mode="add")
    return h


def test_file_from_another_tool_with_mapping_table(tmp_path, model):
    h = _foreign_file(tmp_path / "lab.unv")
    table = tmp_path / "map.csv"
    table.write_text("name,node,direction,sign\nacc-top-z,7,3,1\nhammer-z,12,-3,-1\n")
    res, = read_measured(tmp_path / "lab.unv", model, table)
    assert res.outputs == ("acc-top-z",) and res.inputs == ("hammer-z",)
    np.testing.assert_allclose(res.H[0, 0], h, rtol=1e-10)


def test_a_mapping_sign_flips_what_is_written_and_is_undone_on_reading(tmp_path, model):
    """A channel mounted against its node's direction (sign -1): the file holds the FRF as that
    node and direction see it, -H; read with the same table it is H again."""
    from rotordyn_modal.io.channels import read_mapping

    table = tmp_path / "map.csv"
    table.write_text("name,node,direction,sign\nacc-top-z,7,3,-1\nacc-side-y,8,2,1\n"
                     "hammer-z,12,3,1\nshaker-y,13,2,1\n")
    sets = _sets(model)[:1]
    write_uff58(sets, tmp_path / "m.uff", read_mapping(table, model), binary=True)
    raw = {(int(d["rsp_node"]), int(d["ref_node"])): np.asarray(d["data"])
           for d in pyuff.UFF(str(tmp_path / "m.uff")).read_sets() if d["func_type"] == 4}
    np.testing.assert_array_equal(raw[(7, 12)], -sets[0].H[0, 0])
    np.testing.assert_array_equal(raw[(8, 12)], sets[0].H[1, 0])
    back, = read_measured(tmp_path / "m.uff", model, table)
    np.testing.assert_array_equal(back.H, sets[0].H)


def test_unmapped_channel_is_refused_with_the_table(tmp_path, model):
    _foreign_file(tmp_path / "lab.unv")
    with pytest.raises(InputError) as info:
        read_measured(tmp_path / "lab.unv", model)
    assert "response node 7 direction 3 is not in the mapping table" in str(info.value)
    assert "1:3=acc-top-z" in str(info.value) and "--mapping" in str(info.value)


@pytest.mark.parametrize("overrides,message", [
    ({"ordinate_axis_units_lab": "V"}, "ordinate unit 'V' is not understood: expected units such as"),
    ({"ordinate_axis_units_lab": "N"}, "expected a displacement, velocity or acceleration over an excitation force"),
    ({"orddenom_axis_units_lab": "m"}, "(data type 13, excitation force; unit 'm'): expected a displacement"),
    ({"ordinate_axis_units_lab": "m/s"}, "ordinate data type 12 (acceleration) but unit 'm/s' gives mobility"),
    ({"orddenom_spec_data_type": 8}, "denominator data type 8: expected 13"),
    ({"ordinate_spec_data_type": 2}, "ordinate data type(s) [2]: expected one of 8"),
    ({"func_type": 1}, "no FRF (dataset 58, function type 4) in the file; function types found: [1]"),
])
def test_wrong_units_and_types_are_refused(tmp_path, model, overrides, message):
    _foreign_file(tmp_path / "lab.uff", **overrides)
    table = tmp_path / "map.csv"
    table.write_text("name,node,direction\nacc-top-z,7,3\nhammer-z,12,-3\n")
    with pytest.raises(InputError) as info:
        read_measured(tmp_path / "lab.uff", model, table)
    assert message in str(info.value)


def test_broken_file_is_refused(tmp_path, model):
    path = tmp_path / "broken.uff"
    write_uff58(_sets(model), path, default_mapping(model))
    text = path.read_text()
    # cut in its first dataset: text after a complete dataset's closing -1 is read with a warning (io34)
    path.write_text(text[: len(text) // 20] + "garbage 1.2.3\n")
    with pytest.raises(InputError, match="broken.uff: "):
        read_measured(path, model)


def test_not_a_uff_file(tmp_path, model):
    path = tmp_path / "notes.uff"
    path.write_text("hello\n")
    with pytest.raises(InputError, match="notes.uff: "):
        read_measured(path, model)


def test_missing_file_and_unknown_format(tmp_path, model):
    with pytest.raises(InputError, match="measured data file not found"):
        read_measured(tmp_path / "nope.uff", model)
    (tmp_path / "x.mat").write_text("")
    with pytest.raises(InputError, match="unknown measured data format '.mat'"):
        read_measured(tmp_path / "x.mat", model)


def test_csv_refusals(tmp_path, model):
    path = tmp_path / "m.csv"
    path.write_text("frequency_hz,output,real,imag\n1,acc-top-z,1,0\n")
    with pytest.raises(InputError, match="expected the columns speed_rpm,frequency_hz,output,input,real,imag"):
        read_measured(path, model)
    path.write_text("frequency_hz,output,input,real,imag\n1,acc-top-q,hammer-z,1,0\n")
    with pytest.raises(InputError, match="channel\\(s\\) acc-top-q are not sensors"):
        read_measured(path, model)
    path.write_text("frequency_hz,output,input,real,imag\n1,acc-top-z,hammer-z,1,0\n2,acc-top-z,hammer-z,1,0\n"
                    "1,acc-side-y,hammer-z,1,0\n")
    with pytest.raises(InputError, match="has 1 frequencies where the data of that speed has 2"):
        read_measured(path, model)
    path.write_text("frequency_hz,output,input,real,imag,quantity\n1,acc-top-z,hammer-z,1,0,force\n")
    with pytest.raises(InputError, match="quantity column holds \\['force'\\]"):
        read_measured(path, model)


def test_mapping_table_refusals(tmp_path, model):
    _foreign_file(tmp_path / "lab.uff")
    table = tmp_path / "map.csv"
    table.write_text("name,node\nacc-top-z,7\n")
    with pytest.raises(InputError, match="lacks the column\\(s\\) direction"):
        read_measured(tmp_path / "lab.uff", model, table)
    table.write_text("name,node,direction\nacc-top-q,7,3\n")
    with pytest.raises(InputError, match="name 'acc-top-q' is neither a sensor"):
        read_measured(tmp_path / "lab.uff", model, table)
    # UFF direction codes are +-1 .. +-6 (X, Y, Z, then rotations), 0 a scalar; 7 names nothing
    for code in (7, -7):
        table.write_text(f"name,node,direction\nacc-top-z,7,{code}\n")
        with pytest.raises(InputError, match=f"line 2: direction = {code}: expected a UFF direction code"):
            read_measured(tmp_path / "lab.uff", model, table)


def test_the_default_mapping_uses_the_uff_direction_codes(model):
    """UFF direction codes: +-1, +-2, +-3 along +-X, +-Y, +-Z; +-4, +-5, +-6 about them (moments)."""
    data = model.to_dict()
    data["sensors"][0]["direction"] = [0.0, 0.0, -1.0]
    data["excitations"][1].update(kind="moment", direction=[0.0, -1.0, 0.0])
    mapping = default_mapping(rdm.Model.from_dict(data))
    codes = {name: direction for (node, direction), (name, sign) in {**mapping.outputs, **mapping.inputs}.items()}
    assert codes == {"acc-top-z": -3, "acc-side-y": 2, "hammer-z": 3, "shaker-y": -5}


def test_writes_never_over_an_input(tmp_path, model):
    path = tmp_path / "m.uff"
    path.write_text("keep")
    with pytest.raises(InputError, match="refusing to write over the input file"):
        write_uff58(_sets(model), path, default_mapping(model), inputs=[path])
    assert path.read_text() == "keep"


def test_a_step_the_uff_header_rounds_is_said(tmp_path, model):
    """Evenly spaced frequencies are UFF even data: record 7 holds the first frequency and the step
    in E13.5 (6 digits), in ASCII and in 58b alike (its header is ASCII too): 37/199 Hz steps move
    the last line by 7e-5 Hz, said in a warning. (58b used to write each frequency as an 8-byte
    double, a layout the UFF definition does not have: other tools read other numbers.)"""
    res = rdm.frf(model, rdm.rpm(2400), np.linspace(3.0, 40.0, 200))
    for binary in (None, False, True):
        path = tmp_path / f"{binary}.uff"
        with pytest.warns(UserWarning, match="holds the first frequency and the step to 6 digits"):
            write_uff58([res], path, default_mapping(model), binary=binary)
        rounded, = read_measured(path, model)
        assert 0 < np.abs(rounded.frequencies_hz - res.frequencies_hz).max() <= 5e-6 * 40


def test_written_uff_says_hz_and_keeps_long_channel_names(tmp_path, model):
    """Record 8 names the abscissa unit (Hz, not NONE); a name longer than record 6's 10-character
    entity field is never cut: the field says NONE and ID line 1 holds the whole name."""
    data = model.to_dict()
    data["sensors"][0]["name"] = "accelerometer-top-z"
    long = rdm.Model.from_dict(data)
    path = tmp_path / "long.uff"
    write_uff58([rdm.frf(long, 0.0, FREQS, quantity="accelerance")], path, default_mapping(long))
    sets = [s for s in pyuff.UFF(str(path)).read_sets() if s["func_type"] == 4]
    assert {s["abscissa_axis_units_lab"] for s in sets} == {"Hz"}
    first = [s for s in sets if s["rsp_node"] == 1]
    assert first and all(s["rsp_ent_name"] == "NONE" and s["id1"].startswith("accelerometer-top-z / ") for s in first)
    assert {s["rsp_ent_name"] for s in sets if s["rsp_node"] == 2} == {"acc-side-y"}
    assert read_measured(path, long)[0].outputs == ("accelerometer-top-z", "acc-side-y")


def test_an_oblique_channel_is_not_written_as_the_nearest_axis(tmp_path, model):
    """A sensor along (0, 0.6, 0.8): UFF 58 direction codes are the node's axes only, so without a
    mapping naming its node and direction the file is refused (exit 2, nothing written); the
    default mapping lists it as oblique."""
    from rotordyn_modal.cli.main import main
    from rotordyn_modal.io.channels import read_mapping

    data = model.to_dict()
    data["sensors"][1]["direction"] = [0.0, 0.6, 0.8]
    oblique = rdm.Model.from_dict(data)
    mapping = default_mapping(oblique)
    assert list(mapping.oblique) == ["acc-side-y"]
    res = rdm.frf(oblique, 0.0, FREQS, quantity="accelerance")
    with pytest.raises(InputError, match="channel 'acc-side-y' measures along \\(0, 0.6, 0.8\\), along no model axis"):
        write_uff58([res], tmp_path / "o.uff", mapping)
    assert not (tmp_path / "o.uff").exists()
    table = tmp_path / "map.csv"
    table.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,40,1\nhammer-z,101,3\nshaker-y,102,2\n")
    write_uff58([res], tmp_path / "o.uff", read_mapping(table, oblique))
    assert (40, 1) in {(s["rsp_node"], s["rsp_dir"]) for s in pyuff.UFF(str(tmp_path / "o.uff")).read_sets()}
    model_file = tmp_path / "oblique.toml"
    rdm.io.model_file.save_model(oblique, model_file)
    assert main(["frf", str(model_file), "--freqs", "1:40:5", "--out", str(tmp_path / "c.uff"), "--quiet"]) == 2
    assert not (tmp_path / "c.uff").exists()


@pytest.mark.parametrize("field", ["rsp_dir", "ref_dir"])
def test_a_direction_given_negative_reads_as_the_same_measurement(tmp_path, model, field):
    """Another tool writes a sensor (or a force) along -Z as direction -3 with the FRF of that
    direction, -H: without a mapping table the file reads back as the model's +z channel's H (the
    sign the direction code gives undone), the same as the package's own file of +3 (redteam44's
    "direction -3 asks for --mapping": not so, now tested; -H would be off by 2 |H|)."""
    sets = _sets(model)[:1]
    path = tmp_path / "own.uff"
    write_uff58(sets, path, default_mapping(model))
    records = pyuff.UFF(str(path)).read_sets()
    turned = []
    for record in records:          # the FRFs (4) negated, their coherences (6) not: a coherence has no sign
        if abs(int(record[field])) == 3:
            data = -np.asarray(record["data"]) if record["func_type"] == 4 else record["data"]
            record = dict(record, **{field: -int(record[field]), "data": data})
        turned.append(record)
    assert any(int(r[field]) == -3 for r in turned)
    other = tmp_path / "other.uff"
    open(other, "w").close()
    pyuff.UFF(str(other)).write_sets(turned, mode="add")
    own, = read_measured(path, model)
    back, = read_measured(other, model)
    assert back.outputs == own.outputs and back.inputs == own.inputs
    # pyuff writes the turned file's numbers to its own ASCII precision (3.7e-12 of the largest here)
    np.testing.assert_allclose(back.H, own.H, rtol=0, atol=1e-10 * np.abs(own.H).max())
