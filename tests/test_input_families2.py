"""More inputs of the families a reviewer tries (after ``test_input_families.py``): names that
hold commas in list options, mapping tables that give a name two nodes, other tools' ways of
writing UFF directions and units. Each case through the command line in this process (the
right answer, or exit 2 with one line naming the file or option and nothing written) or
through the reader the command line calls."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.io.measured import default_mapping, read_measured
from rotordyn_modal.io.uff import write_uff58
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"
FAN = ROOT / "examples" / "fan_on_bearings.toml"


def _renamed(tmp_path, source, renames, name="renamed.toml"):
    """A copy of an example whose ``name = "OLD"`` lines read ``name = "NEW"``."""
    text = Path(source).read_text()
    for old, new in renames.items():
        assert f'name = "{old}"' in text
        text = text.replace(f'name = "{old}"', f'name = "{new}"')
    path = tmp_path / name
    path.write_text(text)
    return path


def _csv_rows(capsys):
    import io

    import pandas as pd

    return pd.read_csv(io.StringIO(capsys.readouterr().out))


# ----------------------------------------------------------------------- names holding commas
@pytest.mark.parametrize("sensor, excitation", [
    ("acc, top z", "hammer,z"),                      # given whole: the known name first
    ('"acc, top z"', '"hammer,z",shaker-y'),         # quoted
    ("acc\\, top z", "hammer\\,z,shaker-y"),         # commas escaped
], ids=["whole", "quoted", "escaped"])
def test_a_name_holding_commas_is_chosen_in_a_list_option(tmp_path, capsys, sensor, excitation):
    """``--sensor "acc, top z"`` was split at its comma into 'acc' and 'top z': exit 2, no
    such sensor; the name could not be chosen at all."""
    model_file = _renamed(tmp_path, GEAR, {"acc-top-z": "acc, top z", "hammer-z": "hammer,z"})
    assert main(["frf", str(model_file), "--freqs", "2:40:3", "--sensor", sensor, "--excitation", excitation,
                 "--out", "-", "--quiet"]) == 0
    table = _csv_rows(capsys)
    model = rdm.load_model(model_file)
    wanted = ["hammer,z"] + (["shaker-y"] if "shaker" in excitation else [])
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 3), inputs=wanted, outputs=["acc, top z"])
    assert set(table["output"]) == {"acc, top z"} and list(dict.fromkeys(table["input"])) == wanted
    first = table[table["input"] == "hammer,z"]
    np.testing.assert_allclose(first["real"] + 1j * first["imag"], exact.H[0, 0], rtol=1e-9)


def test_a_list_that_reads_as_two_sets_of_names_is_refused(tmp_path, capsys):
    """Sensors 'a', 'b' and 'a,b': ``--sensor a,b`` is either; it is refused with the way out."""
    model_file = _renamed(tmp_path, FAN, {"probe-DE-x": "a", "probe-DE-y": "b", "acc-fan-z": "a,b"})
    assert main(["unbalance", str(model_file), "--speeds", "100:3000:3", "--sensor", "a,b", "--quiet"]) == 2
    _one_line_error(capsys, "--sensor 'a,b'", "'a', 'b'", "'a,b'", "quote")
    assert main(["unbalance", str(model_file), "--speeds", "100:3000:3", "--sensor", '"a,b"', "--out", "-",
                 "--quiet"]) == 0
    assert set(_csv_rows(capsys)["output"]) == {"a,b"}
    assert main(["unbalance", str(model_file), "--speeds", "100:3000:3", "--sensor", '"a","b"', "--out", "-",
                 "--quiet"]) == 0
    assert list(dict.fromkeys(_csv_rows(capsys)["output"])) == ["a", "b"]


def test_a_bearing_name_holding_a_comma_is_chosen_in_ucs_map(tmp_path, capsys):
    model_file = _renamed(tmp_path, FAN, {"fan-DE": "fan, DE"})
    out = tmp_path / "u.csv"
    assert main(["ucs-map", str(model_file), "--stiffness", "1e6:1e8:3", "--bearings", "fan, DE,fan-NDE",
                 "--out", str(out), "--quiet"]) == 0
    assert main(["ucs-map", str(model_file), "--stiffness", "1e6:1e8:3", "--bearings", "fan",
                 "--quiet"]) == 2
    _one_line_error(capsys, "'fan'", "'fan, DE'")    # the names listed unambiguously, quoted


@pytest.mark.parametrize("text, words", [('"acc-top-z', ["not closed"]), ("acc-top-z\\", ["backslash"]),
                                         (" , ", ["one or more names"])],
                         ids=["open-quote", "trailing-backslash", "nothing"])
def test_a_malformed_name_list_is_one_line(capsys, text, words):
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--sensor", text, "--quiet"]) == 2
    _one_line_error(capsys, "--sensor", *words)


# ----------------------------------------------------------------------- mapping tables
def test_a_mapping_that_gives_a_name_two_nodes_is_refused_naming_both(tmp_path, capsys):
    """The UFF was written with the first row's node, silently (exit 0)."""
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,101,3\nshaker-y,102,2\n"
                       "acc-top-z,7,3\n")
    out = tmp_path / "f.uff"
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--mapping", str(mapping), "--out", str(out),
                 "--quiet"]) == 2
    _one_line_error(capsys, "map.csv", "line 6", "'acc-top-z'", "node 7", "node 1", "line 2")
    assert not out.exists()


def test_a_driving_point_with_two_rows_reads_but_is_not_written(tmp_path, capsys):
    """A name that is a sensor and an excitation may have its response's and its reference's
    row (for reading a file that numbers them apart); a UFF written from it needs one."""
    model_file = tmp_path / "same.toml"
    model_file.write_text(GEAR.read_text().replace('name = "hammer-z"', 'name = "acc-top-z"'))
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nacc-top-z,101,3\nshaker-y,102,2\n")
    out = tmp_path / "f.uff"
    assert main(["frf", str(model_file), "--freqs", "2:40:3", "--mapping", str(mapping), "--out", str(out),
                 "--quiet"]) == 2
    _one_line_error(capsys, "map.csv", "line 4", "'acc-top-z'", "node 101", "node 1", "line 2")
    assert not out.exists()
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nacc-top-z,101,3\nshaker-y,102,2\n"
                       "acc-top-z,5,3\n")
    assert main(["frf", str(model_file), "--freqs", "2:40:3", "--mapping", str(mapping), "--out", str(out),
                 "--quiet"]) == 2
    _one_line_error(capsys, "map.csv", "line 6", "node 5")


def test_a_channel_left_out_of_a_mapping_is_named_with_the_mapping_file(tmp_path, capsys):
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,101,3\n")
    out = tmp_path / "f.uff"
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--mapping", str(mapping), "--out", str(out),
                 "--quiet"]) == 2
    _one_line_error(capsys, "map.csv", "shaker-y", "not in the mapping table")
    assert not out.exists()


# ----------------------------------------------------------------------- UFF of other tools
def test_a_direction_opposite_to_the_mapped_one_reads_with_its_sign_flipped(tmp_path):
    """A file that says -Z for a sensor the mapping puts at +Z measures minus its FRF (it was
    refused: node 1 direction -3 not in the mapping table)."""
    model = rdm.load_model(GEAR)
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 5))
    mapping = default_mapping(model)
    flipped = type(mapping)({(node, -direction) if name == "acc-top-z" else (node, direction): (name, sign)
                             for (node, direction), (name, sign) in mapping.outputs.items()}, mapping.inputs)
    path = tmp_path / "minus_z.uff"
    write_uff58([exact], path, flipped)
    [back] = read_measured(path, model)              # the default mapping: acc-top-z at node 1, +Z
    row = back.outputs.index("acc-top-z")
    np.testing.assert_allclose(back.H[row], -exact.H[exact.outputs.index("acc-top-z")], rtol=1e-10)
    other = back.outputs.index("acc-side-y")
    np.testing.assert_allclose(back.H[other], exact.H[exact.outputs.index("acc-side-y")], rtol=1e-10)


@pytest.mark.parametrize("change, scale, hz", [
    (dict(abscissa_axis_units_lab="kHz"), 1.0, 1e3),
    (dict(ordinate_spec_data_type=11, ordinate_axis_units_lab="ips", orddenom_axis_units_lab="lbf"),
     0.0254 / (0.45359237 * 9.80665), 1.0),
], ids=["kHz-abscissa", "ips-over-lbf"])
def test_uff_units_of_other_tools_are_converted(tmp_path, change, scale, hz):
    """kHz on the abscissa and ips (in/s, a US velocity unit) were refused as not understood."""
    freqs, values = np.linspace(0.0, 0.05, 6), np.linspace(1.0, 2.0, 6) * (1 - 0.5j)
    quantity = "mobility" if change.get("ordinate_spec_data_type") == 11 else "accelerance"
    fields = dict(func_type=4, rsp_node=1, rsp_dir=3, ref_node=101, ref_dir=3, x=freqs, data=values, id1="x",
                  binary=0, abscissa_spec_data_type=18, ordinate_spec_data_type=12, orddenom_spec_data_type=13,
                  ordinate_axis_units_lab="m/s^2", orddenom_axis_units_lab="N")
    path = tmp_path / "other.uff"
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(**{**fields, **change})], mode="add")
    [back] = read_measured(path, rdm.load_model(GEAR))
    assert back.quantity == quantity
    np.testing.assert_allclose(back.frequencies_hz, freqs * hz, rtol=1e-12)
    np.testing.assert_allclose(back.H[back.outputs.index("acc-top-z"), back.inputs.index("hammer-z")],
                               values * scale, rtol=1e-10)


# ----------------------------------------------------------------------- CSV of spreadsheets and other tools
def _frf_table(tmp_path):
    """The gear machine's FRF CSV (``frf --out``) as a DataFrame, and the model's FRF."""
    import pandas as pd

    out = tmp_path / "f.csv"
    assert main(["frf", str(GEAR), "--speed", "1200", "--freqs", "2:40:5", "--quantity", "accelerance",
                 "--out", str(out), "--quiet"]) == 0
    model = rdm.load_model(GEAR)
    return pd.read_csv(out), model, rdm.frf(model, rdm.rpm(1200), np.linspace(2, 40, 5), quantity="accelerance")


@pytest.mark.parametrize("layout", ["semicolon-decimal-comma", "tab-utf16", "units-in-headers"])
def test_a_measured_csv_of_a_spreadsheet_reads_as_the_same_frf(tmp_path, layout):
    """A European spreadsheet's export (``;`` and decimal commas), a UTF-16 tab-separated text and
    headers that carry their units (``Frequency [kHz]``, ``Phase [rad]``, ``Magnitude [g/N]``)
    were refused: the columns were not found."""
    table, model, exact = _frf_table(tmp_path)
    path = tmp_path / f"{layout}.csv"
    if layout == "semicolon-decimal-comma":
        path.write_text("# exported by a spreadsheet\n" + table.to_csv(sep=";", decimal=",", index=False,
                                                                         float_format="%.12g"), encoding="cp1252")
    elif layout == "tab-utf16":
        path.write_bytes(table.to_csv(sep="\t", index=False, float_format="%.12g").encode("utf-16"))
    else:
        renamed = table.drop(columns=["real", "imag"]).rename(columns={
            "frequency_hz": "Frequency [kHz]", "magnitude": "Magnitude [g/N]", "phase_deg": "Phase [rad]",
            "speed_rpm": "Speed (rpm)", "output": "Output", "input": "Input"}).drop(columns=["quantity"])
        renamed["Frequency [kHz]"] = table["frequency_hz"] / 1e3
        renamed["Magnitude [g/N]"] = table["magnitude"] / 9.80665
        renamed["Phase [rad]"] = np.radians(table["phase_deg"])
        renamed.to_csv(path, index=False, float_format="%.15g")
    [back] = read_measured(path, model)
    assert back.quantity == "accelerance" and back.speed == pytest.approx(rdm.rpm(1200), rel=1e-12)
    np.testing.assert_allclose(back.frequencies_hz, np.linspace(2, 40, 5), rtol=1e-12)
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-9)


def test_a_header_unit_that_is_no_unit_of_its_column_is_refused(tmp_path, capsys):
    table, _, _ = _frf_table(tmp_path)
    path = tmp_path / "rpm.csv"
    table.rename(columns={"frequency_hz": "frequency [rpm]"}).to_csv(path, index=False)
    assert main(["frf", str(GEAR), "--speed", "1200", "--freqs", "2:40:5", "--quantity", "accelerance",
                 "--measured", str(path), "--plot", str(tmp_path / "f.png"), "--quiet"]) == 2
    _one_line_error(capsys, "rpm.csv", "'frequency [rpm]'", "'rpm'")
    assert not (tmp_path / "f.png").exists()


def test_a_mapping_with_semicolons_and_names_that_look_like_numbers(tmp_path):
    """Sensor names '01' and 'NA' (a test rig's channel numbers) in a ``;``-separated mapping:
    they were read as the number 1 and as a missing value, and the table was refused."""
    model_file = _renamed(tmp_path, GEAR, {"acc-top-z": "01", "acc-side-y": "NA"})
    model = rdm.load_model(model_file)
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 5))
    uff = tmp_path / "m.uff"
    write_uff58([exact], uff, default_mapping(model))
    mapping = tmp_path / "map.csv"
    mapping.write_text("Name;Node;Direction\n01;1;3\nNA;2;2\nhammer-z;101;3\nshaker-y;102;2\n")
    [back] = read_measured(uff, model, mapping)
    assert back.outputs == ("01", "NA")
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-10)


def test_an_outline_the_csv_parser_refuses_is_one_line(tmp_path, capsys):
    """pandas' message ended in a line break: the error took two lines."""
    outline = tmp_path / "outline.csv"
    outline.write_bytes(bytes(range(256)) * 40)
    assert main(["modes", str(GEAR), "--speed", "100", "--shape", "1", "--plot", str(tmp_path / "s.png"),
                 "--outline", str(outline), "--quiet"]) == 2
    _one_line_error(capsys, "outline.csv", "cannot read the outline")


# ----------------------------------------------------------------------- TDMS records
def _tdms(path, data, **properties):
    nptdms = pytest.importorskip("nptdms")
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.ChannelObject("record", "acc", data,
                                                   properties={"unit_string": "g", "wf_increment": 1e-3,
                                                               **properties})])
    return path


@pytest.mark.parametrize("data, properties, units, words", [
    (np.r_[np.zeros(5), np.nan, np.zeros(4)], {}, None, ["'acc'", "sample 5", "finite"]),
    (np.zeros(10) + 1j, {}, None, ["'acc'", "complex128", "real numbers"]),
    (np.zeros(1), {}, None, ["1 sample", "at least 2"]),
    (np.zeros(10), {"wf_xunit_string": "Hz"}, None, ["wf_xunit_string", "'Hz'"]),
    (np.zeros(10), {"unit_string": "V"}, {"V": ("acceleration", 0.0)}, ["units['V']", "other than 0"]),
], ids=["nan-sample", "complex", "one-sample", "frequency-x-unit", "zero-factor"])
def test_a_tdms_record_of_no_meaning_is_refused(tmp_path, data, properties, units, words):
    """A NaN sample, complex samples, one sample and a declared factor of 0 were read without a
    word (NaN spectra, the imaginary part dropped, a zero record); a time unit of Hz was ignored."""
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.io.tdms import read_tdms_records

    path = _tdms(tmp_path / "r.tdms", data, **properties)
    with pytest.raises(InputError) as info:
        read_tdms_records(path, units=units)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    for word in words:
        assert word in message, message


def test_a_tdms_interval_in_milliseconds_gives_the_rate_in_hz(tmp_path):
    """``wf_xunit_string = 'ms'`` with an increment of 1: 1000 Hz (it read 1 Hz)."""
    from rotordyn_modal.io.tdms import read_tdms_records

    samples = np.sin(np.arange(64) * 0.3)
    records = read_tdms_records(_tdms(tmp_path / "ms.tdms", samples, wf_increment=1.0, wf_xunit_string="ms"),
                                channels="acc")
    assert records.sampling_rate_hz == pytest.approx(1000.0, rel=1e-12) and records.channels == ("acc",)
    np.testing.assert_allclose(records.signals[0, 0], samples * 9.80665, rtol=1e-15)


# ----------------------------------------------------------------------- file options: empty names, pipes
@pytest.mark.parametrize("argv, option", [
    (["frf", str(GEAR), "--freqs", "2:40:3", "--mapping", "", "--out", "{tmp}/f.uff"], "--mapping"),
    (["frf", str(GEAR), "--freqs", "2:40:3", "--measured", "", "--plot", "{tmp}/f.png"], "--measured"),
    (["campbell", str(GEAR), "--speeds", "0:100:3", "--out", ""], "--out"),
    (["check", ""], "MODEL"),
], ids=["mapping", "measured", "out", "model"])
def test_an_empty_file_name_is_refused_not_taken_as_not_given(tmp_path, capsys, argv, option):
    """A script's empty variable (``--mapping "$MAP"``): the option was dropped without a word
    (the default mapping written, no overlay drawn, no file written; exit 0)."""
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv] + ["--quiet"] * (argv[0] != "check")) == 2
    _one_line_error(capsys, f"{option} ''", "expected a file name")
    assert not list(tmp_path.iterdir())


def test_out_into_a_pipe_without_an_ending_is_csv(tmp_path):
    """``--out >(gzip > c.csv.gz)`` or ``--out /dev/stdout`` into a pipe: /dev/fd/N links to
    'pipe:[...]', which has no name to follow; the write failed (exit 2, no such file)."""
    import os
    import threading

    read_end, write_end = os.pipe()
    chunks = []
    reader = threading.Thread(target=lambda: chunks.append(os.read(read_end, 1 << 20)))
    reader.start()
    try:
        assert main(["campbell", str(GEAR), "--speeds", "0:100:3", "--out", f"/dev/fd/{write_end}",
                     "--quiet"]) == 0
    finally:
        os.close(write_end)
        reader.join(timeout=30)
        os.close(read_end)
    assert main(["campbell", str(GEAR), "--speeds", "0:100:3", "--out", str(tmp_path / "c.csv"), "--quiet"]) == 0
    assert b"".join(chunks).decode() == (tmp_path / "c.csv").read_text()


def test_fit_params_keep_a_dotted_key_whose_name_holds_a_comma(tmp_path):
    """``--params suspensions.mount,FL.stiffness,gain``: the key of the mount named 'mount,FL'
    and the gain (it was split into 'suspensions.mount', 'FL.stiffness' and 'gain')."""
    from rotordyn_modal.cli._common import parse_names
    from rotordyn_modal.cli.fit import _is_key

    model = rdm.load_model(_renamed(tmp_path, GEAR, {"mount-FL": "mount,FL"}))
    keys = parse_names("suspensions.mount,FL.stiffness,gain", "--params",
                       lambda key: key == "gain" or _is_key(model, key))
    assert keys == ["suspensions.mount,FL.stiffness", "gain"]
    assert model.get(keys[0]) == [2.0e5, 1.5e5, 4.0e5]


def test_a_time_record_in_the_direction_opposite_to_the_mapped_one_is_flipped(tmp_path):
    from rotordyn_modal.io.channels import ChannelMap
    from rotordyn_modal.io.uff import read_uff_time_records

    samples = np.sin(np.arange(64) * 0.2)
    path = tmp_path / "minus_z.uff"
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(
        func_type=1, rsp_node=5, rsp_dir=-3, ref_node=0, ref_dir=0, x=np.arange(64) * 1e-3, data=samples, id1="x",
        binary=1, abscissa_spec_data_type=17, ordinate_spec_data_type=12, orddenom_spec_data_type=0,
        ordinate_axis_units_lab="m/s^2", abscissa_axis_units_lab="s")], mode="add")
    records = read_uff_time_records(path, ChannelMap({(5, 3): ("acc-top", 1.0)}, {}))
    assert records.channels == ("acc-top",)
    np.testing.assert_allclose(records.signals[0, 0], -samples, rtol=1e-15)


def _time_set(node, data, label):
    return pyuff.prepare_58(func_type=1, rsp_node=node, rsp_dir=3, ref_node=0, ref_dir=0, x=np.arange(len(data)) * 1e-3,
                            data=data, id1="x", binary=1, abscissa_spec_data_type=17, ordinate_spec_data_type=1,
                            orddenom_spec_data_type=0, ordinate_axis_units_lab=label, abscissa_axis_units_lab="s")


def test_a_uff_channel_recorded_in_volts_is_read_with_its_declared_unit(tmp_path):
    """One channel of a recording in V (an accelerometer of 100 mV/g recorded uncalibrated):
    the whole file was refused and, unlike TDMS, a UFF had no way to declare the unit."""
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.io.uff import read_uff_time_records

    samples = np.sin(np.arange(64) * 0.2)
    path = tmp_path / "volts.uff"
    pyuff.UFF(str(path)).write_sets([_time_set(1, samples, "g"), _time_set(2, 0.5 * samples, "V")], mode="add")
    with pytest.raises(InputError, match="'V' is not understood"):
        read_uff_time_records(path)
    records = read_uff_time_records(path, units={"V": ("acceleration", 9.80665 / 0.1)})
    assert records.quantities == ("acceleration", "acceleration")
    np.testing.assert_allclose(records.signals[0, 1], 0.5 * samples * 98.0665, rtol=1e-12)
    np.testing.assert_allclose(records.signals[0, 0], samples * 9.80665, rtol=1e-12)


def test_complex_uff_time_samples_are_refused(tmp_path):
    """Complex samples of a time record lost their imaginary part without a word."""
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.io.uff import read_uff_time_records

    path = tmp_path / "complex.uff"
    pyuff.UFF(str(path)).write_sets([_time_set(1, np.sin(np.arange(64) * 0.2) + 1j, "g")], mode="add")
    with pytest.raises(InputError, match="complex samples"):
        read_uff_time_records(path)


def test_an_output_that_is_a_loop_of_links_is_refused_and_kept(tmp_path, capsys):
    """``--out loop.csv`` where loop.csv -> loop.csv: the link was replaced by the CSV (exit 0)."""
    loop = tmp_path / "loop.csv"
    loop.symlink_to(loop.name)
    assert main(["campbell", str(GEAR), "--speeds", "0:100:3", "--out", str(loop), "--quiet"]) == 2
    _one_line_error(capsys, "loop.csv", "symbolic links")
    assert loop.is_symlink() and os.readlink(loop) == "loop.csv"


def test_measured_data_through_a_broken_link_names_the_link(tmp_path, capsys):
    link = tmp_path / "m.uff"
    link.symlink_to(tmp_path / "moved.uff")
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--measured", str(link), "--quiet"]) == 2
    _one_line_error(capsys, "m.uff", "symbolic link", "moved.uff")


# ----------------------------------------------------------------------- numbers beyond every scale
@pytest.mark.parametrize("call, words", [
    (lambda m: rdm.modal(m, 1e299), ["speed = 1e+299", "at most 1e+30"]),
    (lambda m: rdm.frf(m, 0.0, [1.0, 1e300]), ["freqs_hz", "at most 1e+30", "element 1"]),
    (lambda m: rdm.campbell(m, [0.0, 1e299]), ["speeds", "at most 1e+30", "element 1"]),
    (lambda m: rdm.unbalance_response(m, [1.0, 1e299]), ["speeds", "at most 1e+30"]),
], ids=["modal-speed", "frf-frequencies", "campbell-speeds", "unbalance-speeds"])
def test_speeds_and_frequencies_beyond_the_models_scale_are_refused(call, words):
    """``modes --speed 1e300`` printed "no oscillating modes at 1e300 rpm: 6 real roots" under
    an overflow warning (exit 0): a speed of no machine, computed into nonsense."""
    from rotordyn_modal.errors import InputError

    with pytest.raises(InputError) as info:
        call(rdm.load_model(GEAR))
    for word in words:
        assert word in str(info.value), str(info.value)


def test_a_level1_cross_coupling_beyond_every_scale_is_refused(capsys):
    """``--qa 1e300`` overflowed and was reported as 'there are 0 modes whirling forward'."""
    assert main(["level1", str(FAN), "--speed", "3000", "--station", "fan", "--qa", "1e300", "--quiet"]) == 2
    _one_line_error(capsys, "--qa '1e300'", "at most 1e+30")     # the option as typed (round 5)


def test_a_typo_beside_a_name_holding_commas_is_named_alone(tmp_path, capsys):
    """``--sensor "acc, top z,acc-typo"``: the refusal named 'acc', 'top z' and the typo as unknown."""
    model_file = _renamed(tmp_path, GEAR, {"acc-top-z": "acc, top z"})
    assert main(["frf", str(model_file), "--freqs", "2:40:3", "--sensor", "acc, top z,acc-typo", "--quiet"]) == 2
    err = _one_line_error(capsys, "'acc-typo'")
    assert "'acc'" not in err and "'top z'" not in err
