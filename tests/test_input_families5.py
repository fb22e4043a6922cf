"""A fifth round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families4.py``): messages of the command line that named the Python argument or
quoted a speed in rad/s the user never typed, a stability map's refusal that read as if the
model file held the scaled value, fits of keys no factor can scale, time units and padded cells
of other tools' files, names holding a tab or a line break, options that were taken without a
word. Each case through the command line in this process (exit 2 with one line naming the option
as typed, or the file, key and value) or through the reader the command line calls."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import read_measured
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
GEAR, FAN = EXAMPLES / "gear_machine.toml", EXAMPLES / "fan_on_bearings.toml"
JOURNAL, BLOCK = EXAMPLES / "journal_rotor.toml", EXAMPLES / "spring_block_rotor.toml"
#: 1e30 rad/s, the largest speed of any analysis, in rpm and Hz (rad/s x 30 / pi, rad/s / 2 pi)
LARGEST_RPM, LARGEST_HZ = 1e30 * 30 / math.pi, 1e30 / (2 * math.pi)


@pytest.fixture(scope="module")
def frf_csv(tmp_path_factory):
    """The gear machine's FRFs at 600 rpm, 2 to 40 Hz in 5 lines, as ``frf --out`` writes them
    (read only: each test writes its own files)."""
    path = tmp_path_factory.mktemp("frf") / "plain.csv"
    assert main(["frf", str(GEAR), "--speed", "600", "--freqs", "2:40:5", "--out", str(path), "--quiet"]) == 0
    return path


# ----------------------------------------------------------------------- options named as typed
@pytest.mark.parametrize("argv, words, argument", [
    (["simulate", BLOCK, "--duration", "-1"], ["--duration -1:", "> 0"], "duration"),
    (["simulate", BLOCK, "--duration", "0.01", "--rtol", "0.5"], ["--rtol 0.5:", "1e-13 to 0.1"], "rtol"),
    (["simulate", BLOCK, "--duration", "0.01", "--atol", "2"], ["--atol 2:", "1e-20 to 1"], "atol"),
    (["simulate", GEAR, "--duration", "0.05", "--impulse", "hammer-z", "--impulse-size", "1e15",
      "--backend", "numpy"], ["--impulse-size 1e15 (excitation 'hammer-z'):", "m/s"], "impulse_size"),
    (["campbell", GEAR, "--speeds", "0:3000:3", "--orders", "1,-1"], ["--orders 1,-1:", "numbers > 0"], "orders"),
    (["critical-speeds", GEAR, "--speeds", "0:3000:3", "--orders", "2,2"], ["--orders 2,2:", "each order once"],
     "orders"),
    (["level1", JOURNAL, "--speed", "4000", "--station", "rotor", "--qa", "2e5", "--factor", "0.5"],
     ["--factor 0.5:", "from 1 to 1000"], "factor"),
    (["level1", JOURNAL, "--speed", "4000", "--station", "rotor", "--power", "0", "--impeller-diameter", "0.3",
      "--restriction-height", "0.01"], ["--power 0:", "> 0"], "power"),
    (["fit", GEAR, "--measured", "{csv}", "--params", "suspensions.mount-FL.damping", "--starts", "0",
      "--out", "{tmp}/f.toml"], ["--starts 0:", "at least 1"], "starts"),
    (["static", GEAR, "--power", "0"], ["--power 0:", "speed"], "power"),
    (["static", GEAR, "--force", "nobody:0,0,0:0,0,1"], ["--force nobody:0,0,0:0,0,1: body = 'nobody'", "'stator' or"],
     "forces[0]"),
    (["static", GEAR, "--force", "fan:0,0,0:0,0,1", "--moment", "nobody:1,0,0"],
     ["--moment nobody:1,0,0: body", "'stator' or"], "forces[1]"),
    (["static", GEAR, "--speed", "100", "--power", "fan->motor=1e3"], ["--power fan->motor=1e3:", "motor->fan"],
     "power:"),
    (["level1", FAN, "--speed", "3000", "--station", "fan@", "--qa", "2e4"], ["--station 'fan@':", "ROTOR@OFFSET"],
     "error: station"),
], ids=["duration", "rtol", "atol", "impulse-size", "orders", "orders-twice", "level1-factor", "level1-power",
        "fit-starts", "static-power", "static-force-body", "static-moment-body", "static-power-unknown",
        "level1-station"])
def test_a_refused_option_is_named_as_typed(tmp_path, capsys, frf_csv, argv, words, argument):
    """Each read ``duration = -1.0``, ``rtol = 0.5``, ``orders = (1.0, -1.0)``, ``factor = 0.5,
    steps_per_qa = 10``, ``power = [0.0]``, ``starts = 0``: the Python argument, not the option
    the user typed."""
    argv = [str(a).replace("{csv}", str(frf_csv)).replace("{tmp}", str(tmp_path)) for a in argv]
    assert main(argv + ["--quiet"]) == 2
    err = _one_line_error(capsys, *words)
    assert (argument if argument.endswith((":", "]")) or " " in argument else f"{argument} = ") not in err


def test_the_python_api_keeps_naming_its_argument():
    """The renaming is the command line's: ``rdm.simulate(model, -1.0)`` still says ``duration``."""
    with pytest.raises(InputError, match=r"^duration = -1.0: expected a number > 0"):
        rdm.simulate(rdm.load_model(BLOCK), -1.0)
    with pytest.raises(InputError, match=r"^orders = \(1, -1\)"):
        rdm.critical_speeds(rdm.load_model(GEAR), np.linspace(0, 300, 3), orders=(1, -1))


# ----------------------------------------------------------------------- speeds in the unit typed
@pytest.mark.parametrize("argv, unit, typed, limit", [
    (["modes", GEAR, "--speed", "1e308"], "rpm", "--speed 1e308", LARGEST_RPM),
    (["frf", GEAR, "--freqs", "2:40:3", "--speed", "1e31"], "rpm", "--speed 1e31", LARGEST_RPM),
    (["modes", GEAR, "--speed", "2e29", "--speed-unit", "hz"], "hz", "--speed 2e29", LARGEST_HZ),
    (["campbell", GEAR, "--speeds", "0:1e31:3"], "rpm", "--speeds 0:1e31:3", LARGEST_RPM),
    (["level1", FAN, "--speed", "1e31", "--station", "fan", "--qa", "2e4"], "rpm", "--speed 1e31", LARGEST_RPM),
    (["ucs-map", FAN, "--stiffness", "1e5:1e8:3", "--speeds", "0:1e31:3"], "rpm", "--speeds 0:1e31:3",
     LARGEST_RPM),
    (["simulate", BLOCK, "--duration", "0.01", "--ramp", "1e7"], "rpm", "--ramp 1e7", 1e6 * 30 / math.pi),
], ids=["modes-1e308", "frf-1e31", "modes-hz", "campbell-range", "level1", "ucs-speeds", "simulate-ramp"])
def test_a_speed_beyond_every_machine_is_refused_in_the_unit_typed(capsys, argv, unit, typed, limit):
    """``--speed 1e308`` read ``speed = 1.0471975511965977e+307: expected ... 1e+30 rad/s``: a
    number the user never typed, in a unit they did not use. The limit (1e30 rad/s; a simulation's
    1e6 rad/s) is said in the unit typed, as 30/pi rpm per rad/s and 1/(2 pi) Hz per rad/s give it."""
    assert 1e308 * math.pi / 30 > 1e30 and 1e31 * math.pi / 30 > 1e30 and 2e29 * 2 * math.pi > 1e30
    assert main([str(a) for a in argv] + ["--quiet"]) == 2
    err = _one_line_error(capsys, f"{typed}:", f"at most {limit:.4g} {unit}")
    assert " = " not in err.partition("error: ")[2].split(":")[0]


# ----------------------------------------------------------------------- a stability map's own values
@pytest.mark.parametrize("option, grid, words", [
    ("--scale", "0:2:3", ["[bearings.DE] viscosity = 0.0", "the map's scale 0 x the file's 0.02", "> 0"]),
    ("--scale", "1,-1", ["viscosity = -0.02", "the map's scale -1 x the file's 0.02"]),
    ("--values", "0.02,0", ["viscosity = 0.0", "a value of the map; the file's is 0.02"]),
], ids=["scale-0", "scale-negative", "values-0"])
def test_a_maps_refused_value_says_it_is_the_maps(capsys, option, grid, words):
    """``--vary bearings.DE.viscosity --scale 0:2:3`` was refused as ``[bearings.DE] viscosity =
    0.0: expected a finite number > 0``, as if the model file (which holds 0.02) said 0."""
    assert rdm.load_model(JOURNAL).get("bearings.DE.viscosity") == 0.02
    assert main(["stability", str(JOURNAL), "--speeds", "1000:3000:3", "--vary", "bearings.DE.viscosity",
                 option, grid, "--quiet"]) == 2
    _one_line_error(capsys, "journal_rotor.toml", *words)


def test_a_maps_value_refused_by_another_key_names_both():
    """Ten times the polar inertia is refused by the diametral (at most twice it): the message
    says which key the map changed and by how much."""
    model = rdm.load_model(JOURNAL)
    with pytest.raises(InputError) as info:
        rdm.stability(model, rdm.rpm(np.array([1000.0, 2000.0])), vary="rotors.rotor.polar_inertia", scale=[1, 10])
    message = str(info.value)
    assert "polar_inertia = 5.0 (the map's scale 10 x the file's 0.5)" in message, message


# ----------------------------------------------------------------------- fits of keys no factor scales
@pytest.mark.parametrize("key, why", [
    ("spin_axis", "places or orients"), ("sensors.0.direction", "places or orients"),
    ("stator.center_of_mass", "places or orients"), ("suspensions.mount-FL.axes", "places or orients"),
    ("unbalances.0.amount", "enters no FRF"), ("transmissions.0.driver_teeth", "counts teeth"),
    ("rotors.0.name", "holds no number"), ("transmissions.0.type", "holds no number"),
], ids=lambda v: str(v).replace(".", "-").replace(" ", "_"))
def test_a_fit_of_a_key_no_factor_scales_is_refused_before_it_starts(tmp_path, capsys, frf_csv, key, why):
    """``fit --params spin_axis`` ran the whole fit (a direction scaled by any factor is the same
    direction) and ended with exit 1, 'the data do not determine the parameters'."""
    out = tmp_path / "f.toml"
    assert main(["fit", str(GEAR), "--measured", str(frf_csv), "--params", key, "--out", str(out), "--quiet"]) == 2
    _one_line_error(capsys, f"{key} = ", why, "expected a key of a magnitude", "or 'gain'")
    assert not out.exists()


# ----------------------------------------------------------------------- TDMS time units
@pytest.mark.parametrize("unit, seconds", [("min", 60.0), ("h", 3600.0), ("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6),
                                           ("sec", 1.0)], ids=["min", "h", "ms", "us", "micro-s", "sec"])
def test_a_tdms_time_unit_is_converted(tmp_path, unit, seconds):
    """``wf_xunit_string = 'min'`` (or h, us) was refused: 'expected s or ms'."""
    nptdms = pytest.importorskip("nptdms")
    from rotordyn_modal.io.tdms import read_tdms_records

    path = tmp_path / "r.tdms"
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.ChannelObject("record", "acc", np.sin(np.arange(16) * 0.3), properties={
            "unit_string": "m/s^2", "wf_increment": 0.5, "wf_xunit_string": unit})])
    assert read_tdms_records(path).sampling_rate_hz == pytest.approx(1.0 / (0.5 * seconds), rel=1e-12)


# ----------------------------------------------------------------------- CSV cells padded with spaces
def _padded(text: str, header: str | None = None) -> str:
    lines = text.splitlines()
    rows = [",".join(f"  {cell} " for cell in line.split(",")) for line in lines[1:]]
    return "\n".join([header or ",".join(f" {cell}  " for cell in lines[0].split(","))] + rows) + "\n"


@pytest.mark.parametrize("header", [None, " f [Hz] ,output,input,real,imag,magnitude,phase_deg,speed_rpm,quantity",
                                    " Frequency [kHz] ,output,input,real,imag,magnitude,phase_deg,speed_rpm,quantity"],
                         ids=["every-cell", "f-Hz", "kHz"])
def test_a_csv_of_padded_cells_reads_as_the_plain_one(tmp_path, frf_csv, header):
    """Cells written `` 1.0 `` and `` receptance `` (a text editor's alignment) were refused
    ('quantity column holds [' receptance ']'); a header `` f [Hz] `` too."""
    plain = frf_csv
    text = plain.read_text()
    if header and "kHz" in header:      # the frequency column in kHz: the values / 1000
        table = pd.read_csv(plain)
        table["frequency_hz"] = table["frequency_hz"] / 1000.0
        text = table.to_csv(index=False, float_format="%.17g")
    padded = tmp_path / "padded.csv"
    padded.write_text(_padded(text, header))
    model = rdm.load_model(GEAR)
    [expected], [found] = read_measured(plain, model), read_measured(padded, model)
    np.testing.assert_allclose(found.frequencies_hz, np.linspace(2, 40, 5), rtol=1e-12)
    np.testing.assert_allclose(found.H, expected.H, rtol=1e-9)
    assert found.outputs == expected.outputs and found.inputs == expected.inputs


def test_a_padded_mapping_table_reads_as_the_plain_one(tmp_path):
    uff, mapping = tmp_path / "m.uff", tmp_path / "map.csv"
    model = rdm.load_model(GEAR)
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--out", str(uff), "--quiet"]) == 0
    mapping.write_text("name , node , direction\n acc-top-z , 1 , +Z \n acc-side-y , 2 , 2\n hammer-z , 101 , 3\n"
                       " shaker-y , 102 , Y \n")
    [found] = read_measured(uff, model, mapping)
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 5))
    np.testing.assert_allclose(found.H, exact.H, rtol=1e-9)


# ----------------------------------------------------------------------- names with a tab or a line break
@pytest.mark.parametrize("old, new, where", [
    ('name = "motor"', 'name = "mo\\ttor"', "[rotors[0]] name = 'mo\\ttor'"),
    ('name = "acc-top-z"', 'name = "acc\\ntop"', "[sensors[0]] name = 'acc\\ntop'"),
    ('name = "mount-FL"', 'name = "mount-FL\\r"', "[suspensions[0]] name = 'mount-FL\\r'"),
    ('name = "hammer-z"', 'name = "ham\\u2028mer"', "[excitations[0]] name = 'ham\\u2028mer'"),
], ids=["rotor-tab", "sensor-newline", "mount-cr", "excitation-line-separator"])
def test_a_name_with_a_tab_or_line_break_is_refused_escaped(tmp_path, capsys, old, new, where):
    """Such a name was taken: it splits every table and message that prints it over two lines
    or columns, and reads as another name."""
    text = GEAR.read_text()
    assert text.count(old) == 1
    text = text.replace(old, new)
    if "motor" in old:   # the references to the rotor follow its name
        text = text.replace('"motor"', '"mo\\ttor"')
    path = tmp_path / "named.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "named.toml", where, "without control characters")


def test_a_bearing_name_with_a_tab_is_refused(tmp_path, capsys):
    path = tmp_path / "b.toml"
    path.write_text(JOURNAL.read_text().replace('name = "DE"', 'name = "D\\tE"'))
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "[bearings[0]] name = 'D\\tE'")


def test_a_tdms_channel_name_with_a_line_break_is_refused(tmp_path):
    nptdms = pytest.importorskip("nptdms")
    from rotordyn_modal.io.tdms import read_tdms_records

    path = tmp_path / "r.tdms"
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.ChannelObject("record", "acc\nx", np.sin(np.arange(16) * 0.3), properties={
            "unit_string": "m/s^2", "wf_increment": 1e-3})])
    with pytest.raises(InputError) as info:
        read_tdms_records(path)
    message = str(info.value)
    assert "\n" not in message and "'acc\\nx'" in message and message.startswith(str(path))


# ----------------------------------------------------------------------- options taken without a word
@pytest.mark.parametrize("argv, words", [
    (["level1", FAN, "--speed", "3000", "--station", "fan", "--qa", "2e4", "--operating-speed", "nan"],
     ["--operating-speed nan", "stage data"]),
    (["level1", FAN, "--speed", "3000", "--station", "fan", "--power", "1e6", "--impeller-diameter", "1e-300",
      "--restriction-height", "0.01"],
     ["--impeller-diameter 1e-300", f"Qa = {3 * 60 / (2 * math.pi) * 1e6 / (1e-300 * 0.01 * 3000):.4g} N/m",
      "at most 1e+27"]),
    (["level1", FAN, "--speed", "3000", "--station", "fan", "--qa", "2e4", "--gas-density", "1e300"],
     ["--gas-density '1e300'", "at most 1e+30"]),
    (["static", GEAR, "--allowable-stress", "1e300"], ["--allowable-stress '1e300'", "at most 1e+30"]),
    (["ucs-map", FAN, "--stiffness", "1e5:1e8:3", "--operating", "0:1e300"], ["--operating 0:1e300", "at most"]),
    (["unbalance", FAN, "--speeds", "100:3000:3", "--trip-speed", "100"], ["--trip-speed 100", "--mcs too"]),
    (["unbalance", FAN, "--speeds", "100:3000:3", "--operating-speed", "-1"],
     ["--operating-speed -1 rpm:", "direction of spin"]),
    (["unbalance", FAN, "--speeds", "100:3000:3", "--mcs", "1e-300"], ["--mcs 1e-300", "at least 1e-30 rad/s"]),
], ids=["level1-operating-speed-unused", "level1-qa-from-stages", "gas-density", "allowable-stress",
        "ucs-operating", "trip-speed-without-mcs", "operating-speed-negative", "mcs-1e-300"])
def test_an_option_of_no_effect_or_no_machine_is_refused(tmp_path, capsys, argv, words):
    """``--operating-speed nan`` beside --qa was taken (it is used only with the stage data);
    a Qa of 9.5e305 N/m from the stage data (API 617: Qa = B C P / (D H N), B = 3, C = 60 / 2 pi,
    N in rpm) was refused as 'qa = 9.549e+305', an option not given;
    a gas density, an allowable stress or an operating band of 1e300 were taken; '--mcs None'
    was printed where --mcs was not given; an operating speed was quoted in rad/s; an MCS of
    1e-300 rpm made every swept speed 0 and printed 'warning: All-NaN slice encountered'."""
    out = tmp_path / "o.csv"
    assert main([str(a) for a in argv] + ["--out", str(out), "--quiet"]) == 2
    err = _one_line_error(capsys, *words)
    assert "None" not in err and "rad/s (" not in err and " = " not in err.partition("error: ")[2][:20]
    assert not out.exists()


# ----------------------------------------------------------------------- CSV of spreadsheets, UFF abscissae
def _semicolon_csv(plain, quoting=0):
    table = pd.read_csv(plain)[["speed_rpm", "frequency_hz", "output", "input", "real", "imag"]]
    return plain, table.to_csv(index=False, sep=";", float_format="%.12g", quoting=quoting).replace(".", ",")


@pytest.mark.parametrize("prefix, quoting", [("sep=;\n", 0), ("", 1)], ids=["excel-sep-line", "quoted-decimal-commas"])
def test_a_spreadsheets_csv_reads_as_the_plain_one(tmp_path, frf_csv, prefix, quoting):
    """Excel's first line ``sep=;`` was read as the header ('found sep=, unnamed:_1'); cells
    quoted as ``"11,5"`` beside ``;`` were refused ('line 3 = '11,5': expected a number')."""
    plain, text = _semicolon_csv(frf_csv, quoting=quoting)
    assert quoting == 0 or '"11,5"' in text
    path = tmp_path / "excel.csv"
    path.write_text(prefix + text)
    model = rdm.load_model(GEAR)
    [expected], [found] = read_measured(plain, model), read_measured(path, model)
    np.testing.assert_allclose(found.H, expected.H, rtol=1e-9)
    assert found.speed == pytest.approx(rdm.rpm(600), rel=1e-12)


@pytest.mark.parametrize("label, per_hz", [("rad/s", 2 * math.pi), ("CPM", 60.0), ("kHz", 1e-3)],
                         ids=["rad-per-s", "cpm", "khz"])
def test_a_uff_frequency_axis_in_other_units_reads_in_hz(tmp_path, label, per_hz):
    """An abscissa of data type 18 labelled ``rad/s`` (angular frequency) was refused: 'expected
    Hz'; each is the frequency times 2 pi (rad/s), 60 (cycles per minute), 1/1000 (kHz)."""
    pyuff = pytest.importorskip("pyuff")
    model = rdm.load_model(GEAR)
    freqs = np.linspace(2, 40, 5)
    exact = rdm.frf(model, 0.0, freqs)
    path = tmp_path / "f.uff"
    sets = [pyuff.prepare_58(func_type=4, rsp_node=node, rsp_dir=3 if i == 0 else 2, ref_node=101 + j,
                             ref_dir=3 if j == 0 else 2, x=freqs * per_hz, data=exact.H[i, j], id1="x", binary=1,
                             abscissa_spec_data_type=18, abscissa_axis_units_lab=label, ordinate_spec_data_type=8,
                             ordinate_axis_units_lab="m", orddenom_spec_data_type=13, orddenom_axis_units_lab="N")
            for i, node in enumerate((1, 2)) for j in range(2)]
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    [found] = read_measured(path, model)
    np.testing.assert_allclose(found.frequencies_hz, freqs, rtol=1e-12)
    np.testing.assert_allclose(found.H, exact.H, rtol=1e-12)


# ----------------------------------------------------------------------- file options
@pytest.mark.parametrize("argv, options", [
    (["frf", str(GEAR), "--freqs", "2:40:3", "--measured", "-", "--mapping", "-"], "--measured - and --mapping -"),
    (["modes", "-", "--shape", "1", "--outline", "-", "--plot", "{tmp}/s.png"], "MODEL - and --outline -"),
], ids=["measured", "outline"])
def test_standard_input_as_an_input_file_is_read_by_one_option(tmp_path, capsys, argv, options):
    """``-`` was read as a file named '-' ('-: <file> = '-': expected an existing model file (no
    such file)'); it is standard input now (tests/test_standard_input27p.py), which one option
    may read: two are refused, naming both."""
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv]) == 2
    _one_line_error(capsys, f"{options}: standard input is read once", "name files for the others")


def test_a_header_of_control_characters_is_shown_escaped(tmp_path, capsys):
    """A file of three NUL bytes printed them raw in 'found ...' (invisible on a terminal)."""
    path = tmp_path / "nul.csv"
    path.write_bytes(b"\x00\x00\x00\n")
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--measured", str(path), "--out", "-", "--quiet"]) == 2
    err = _one_line_error(capsys, "nul.csv", "found '\\x00\\x00\\x00'")
    assert "\x00" not in err


@pytest.mark.parametrize("suffix", [".csv", ".uff"])
def test_a_measured_file_without_read_permission_is_refused_by_name(tmp_path, capsys, monkeypatch, suffix):
    """``frf --measured m.csv`` of a file the user may not read ended in 'failed: PermissionError'
    (exit 1). The refusal is forced here (the tests may run as root, who reads every file)."""
    import builtins

    import rotordyn_modal.io.measured as measured_module

    path = tmp_path / f"m{suffix}"
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--out", str(path), "--quiet"]) == 0

    def refused(file, *args, **kwargs):
        if str(file) == str(path):
            raise PermissionError(13, "Permission denied", str(file))
        return builtins.open(file, *args, **kwargs)

    monkeypatch.setattr(measured_module, "open", refused, raising=False)
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--measured", str(path), "--out", "-", "--quiet"]) == 2
    _one_line_error(capsys, f"m{suffix}: cannot read the measured-data file (Permission denied)")
