"""A fourth round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families3.py``): positions far from the origin, fits of parameters the model fixes,
Level I stations off a rigid rotor, numbers beyond every scale in options, other tools' measured
files (UFF of real values, CSV headers and rows of spreadsheets, mapping tables with letters,
TDMS channels), names that read alike. Each case through the command line in this process (the
right answer, or exit 2 with one line naming the file, key or option and nothing written) or
through the reader or entry point the command line calls."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import pyuff

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import default_mapping, read_measured
from rotordyn_modal.io.uff import write_uff58
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
GEAR, FAN = EXAMPLES / "gear_machine.toml", EXAMPLES / "fan_on_bearings.toml"
PUMP, JOURNAL = EXAMPLES / "flexible_pump_on_mounts.toml", EXAMPLES / "journal_rotor.toml"
COMPRESSOR = EXAMPLES / "compressor_on_journals.toml"


def _edited(tmp_path, source, old, new, name="edited.toml"):
    text = Path(source).read_text()
    assert text.count(old) == 1, old
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


# ----------------------------------------------------------------------- positions far from the origin
@pytest.mark.parametrize("source, old, new, words", [
    (PUMP, "start = [-0.50, -0.12, 0.22]", "start = [1e29, 0, 0]",
     ["[rotors.pump] start = [1e+29, 0, 0]", "1.8e+13 m", "0.45 m shaft"]),
    (PUMP, "start = [-0.50, -0.12, 0.22]", "start = [1e7, 0, 0]", ["[rotors.pump] start", "1.9e-09 m"]),
    (FAN, "center_of_mass = [0.25, 0.0, 0.05]", "center_of_mass = [1e29, 0.0, 0.05]",
     ["[bearings.motor-DE] position = [0.4, 0.0, 0.05]", "1e+29 m from the rotor's center_of_mass",
      "moves it 0.4 m"]),
], ids=["flexible-start-1e29", "flexible-start-1e7", "rigid-centre-1e29"])
def test_a_position_that_round_off_cannot_place_is_refused_by_its_key(tmp_path, capsys, source, old, new, words):
    """Double precision holds about 16 digits: 1e29 + 0.45 is 1e29, so every station of the
    pump's 0.45 m shaft (and both bearings of the fan's motor, measured from a centre at 1e29 m)
    was one point, refused as 'sits on bearings at a single point of its axis': a statement
    about a file that places its bearings 0.21 m apart."""
    assert np.spacing(1e29) > 0.45 and np.spacing(1e7) > 1e-9       # what the refusals rest on
    assert main(["check", str(_edited(tmp_path, source, old, new))]) == 2
    err = _one_line_error(capsys, "edited.toml", *words)
    assert "single point" not in err


def test_bearings_written_at_one_far_point_say_why(tmp_path, capsys):
    """Every x of the fan machine moved by 1e29 m: its positions are then equal numbers in the
    file, so the refusal is that of one bearing point, but it says what made them equal."""
    text = FAN.read_text()
    for x in ("0.40", "0.10", "0.25"):   # the motor's bearings and centre
        text = text.replace(f"[{x}, 0.0, 0.05]", "[1e29, 0.0, 0.05]")
    path = tmp_path / "far.toml"
    path.write_text(text)
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "far.toml", "single point", "double precision rounds positions to 1.8e+13 m")


def test_the_example_moved_a_kilometre_keeps_its_modes(tmp_path):
    """Moving the origin changes nothing: the refusals above leave a machine 1 km away alone."""
    text = FAN.read_text()
    import re

    moved, count = re.subn(r"(position|center_of_mass) = \[([-0-9.]+),",
                           lambda m: f"{m.group(1)} = [{float(m.group(2)) + 1000.0!r},", text)
    assert count >= 14          # the stator, both rotors, every mount, bearing, sensor and excitation
    path = tmp_path / "moved.toml"
    path.write_text(moved)
    near, far = rdm.modal(rdm.load_model(FAN), 300.0), rdm.modal(rdm.load_model(path), 300.0)
    np.testing.assert_allclose(far.eigenvalues, near.eigenvalues, rtol=1e-9)


# ----------------------------------------------------------------------- fits of fixed or bounded parameters
def test_a_fit_of_a_speed_ratio_the_model_fixes_says_so(tmp_path, capsys):
    """The gear machine's motor is the reference rotor (ratio 1): the fit's first trial was
    refused as '[rotors.motor] speed_ratio = 1.0000000149011612: expected a value consistent
    with the reference rotor', a value the user never wrote."""
    measured = tmp_path / "m.csv"
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--out", str(measured), "--quiet"]) == 0
    out = tmp_path / "fit.toml"
    assert main(["fit", str(GEAR), "--measured", str(measured), "--params", "rotors.0.speed_ratio",
                 "--out", str(out), "--quiet"]) == 2
    err = _one_line_error(capsys, "rotors.0.speed_ratio = 1.0", "speed ratio is fixed", "reference rotor",
                          "transmissions.N.ratio")
    assert "1.00000001" not in err and not out.exists()


def test_a_fit_whose_bound_gives_no_model_is_refused_before_it_starts():
    """The motor's polar inertia 0.08 with bounds x100 reaches 8 > 2 x 0.05 (its diametral): the
    fit stopped in its second start at 'polar_inertia = 0.2824468504326876: expected at most
    twice diametral_inertia' (a trial value)."""
    model = rdm.load_model(GEAR)
    measured = rdm.frf(model, rdm.rpm(600), np.linspace(2, 40, 5))
    with pytest.raises(InputError) as info:
        rdm.fit(model, measured, ["rotors.motor.polar_inertia"])
    message = str(info.value)
    assert "upper bound (factor 100)" in message and "at most twice diametral_inertia" in message
    assert "narrower bounds" in message and "0.28" not in message
    result = rdm.fit(model, measured, ["rotors.motor.polar_inertia"], bounds={"rotors.motor.polar_inertia": (0.5, 1.2)},
                     starts=1)
    assert result.factors[0] == pytest.approx(1.0, rel=1e-6)      # within bounds the model allows, the truth


# ----------------------------------------------------------------------- Level I stations on a rigid rotor
@pytest.mark.parametrize("offset, accepted", [(-0.1, True), (0.3, True), (-0.29, False), (0.31, False),
                                              (50.0, False), (1e6, False)])
def test_a_level1_station_off_a_rigid_rotor_is_refused_naming_its_extent(capsys, offset, accepted):
    """The fan's rotor: centre of mass at x = -0.32 m, bearings at -0.22 and -0.02 (offsets 0.1
    and 0.3), the hub tapped at -0.42 (-0.1); the slender rod of its mass 11 kg and diametral
    inertia 0.30 kg m^2 reaches sqrt(3 x 0.30 / 11) = 0.286 m either side. Its extent is
    -0.286 to 0.3 m; a station 50 m or 1e6 m away was taken without a word."""
    half = np.sqrt(3 * 0.30 / 11.0)
    low, high = min(-half, -0.1), max(half, 0.3)
    assert (low <= offset <= high) == accepted
    model = rdm.load_model(FAN)
    station = f"fan@{offset:g}"
    if accepted:
        assert rdm.level1(model, rdm.rpm(3000), [station], 2e4).stations[0].offset == offset
        return
    with pytest.raises(InputError, match=rf"OFFSET from {low:.6g} to {high:.6g} m"):
        rdm.level1(model, rdm.rpm(3000), [station], 2e4)
    assert main(["level1", str(FAN), "--speed", "3000", "--station", station, "--qa", "2e4", "--quiet"]) == 2
    _one_line_error(capsys, f"OFFSET = {offset:g} m", "rigid rotor 'fan'", f"{low:.6g} to {high:.6g} m")


# ----------------------------------------------------------------------- options beyond every scale
@pytest.mark.parametrize("argv, words", [
    (["unbalance", str(FAN), "--speeds", "100:3000:3", "--mcs", "1e308"], ["--mcs 1e308", "at most 1e+30 rad/s"]),
    (["simulate", str(GEAR), "--duration", "0.05", "--impulse", "hammer-z", "--impulse-size", "1e15",
      "--backend", "numpy"],
     ["--impulse-size 1e15", "'hammer-z'", "2.39e+13 m/s"]),         # the options as typed (round 5)
    (["campbell", str(GEAR), "--speeds", "0:3000:3", "--orders", "-1"], ["--orders -1", "numbers > 0"]),
    (["frf", str(GEAR), "--freqs", "2:40:3", "--sensor", "acc-top-z,acc-top-z"], ["--sensor", "given twice"]),
], ids=["mcs", "impulse", "orders", "sensor-twice"])
def test_an_option_of_no_machine_is_refused_in_one_line(tmp_path, capsys, argv, words):
    """--mcs 1e308 made the API 617 probe limit 0 m and failed every probe (exit 0); an impulse
    of 1e15 N s ran for minutes (1e308: ZeroDivisionError in the integrator, exit 1); the
    orders' refusal read 'orders = (np.float64(-1.0),)'; --sensor a,a wrote every FRF twice,
    a CSV the package then refused to read back."""
    out = tmp_path / "o.csv"
    assert main(argv + ["--out", str(out), "--quiet"]) == 2
    err = _one_line_error(capsys, *words)
    assert "np.float64" not in err and not out.exists()
    mass = 150.0 + 18.0 + 9.0   # the gear machine's stator and rotors [kg]: 1e15 N s is > 1e12 m/s
    assert 1e15 / mass > 1e12


def test_a_level1_figure_of_a_table_ending_is_refused_before_the_work(tmp_path, capsys):
    """``--csr-plot c.csv``: the whole sweep ran and printed its table, then the refusal."""
    assert main(["level1", str(JOURNAL), "--speed", "4000", "--station", "rotor", "--qa", "2e5",
                 "--gas-density", "10", "--csr-plot", str(tmp_path / "c.csv")]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1 and "--csr-plot" in captured.err


def test_import_ross_refuses_an_empty_name(tmp_path, capsys):
    out = tmp_path / "r.toml"
    assert main(["import-ross", str(ROOT / "tests" / "data" / "ross" / "rotor_example.toml"), "--out", str(out),
                 "--name", ""]) == 2
    _one_line_error(capsys, "--name ''", "rotor's name")
    assert not out.exists()


def test_a_memory_refusal_names_the_model_file(tmp_path, capsys, monkeypatch):
    """A mesh of 1,365 coordinates under 0.5 GB: 'a Campbell sweep of 1,365 coordinates ...
    needs about 2.9 GiB' without the file (the fuzz test's judge counted it as a crash)."""
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "0.5")
    model = _edited(tmp_path, COMPRESSOR, "element_length = 0.2 ", "element_length = 0.005 ", "fine.toml")
    out = tmp_path / "c.csv"
    assert main(["campbell", str(model), "--speeds", "60:3000:5", "--out", str(out), "--quiet"]) == 2
    _one_line_error(capsys, "fine.toml: a Campbell sweep of 1,365 coordinates", "GiB")
    assert not out.exists()


# ----------------------------------------------------------------------- UFF of real values
def test_a_uff_frf_of_real_values_is_refused(tmp_path, capsys):
    """pyuff writes real data as ordinate data type 4: a magnitude-only export was read as an
    FRF of phase 0 at every line (drawn and fitted)."""
    freqs = np.linspace(2, 40, 5)
    path = tmp_path / "magnitude.uff"
    pyuff.UFF(str(path)).write_sets([pyuff.prepare_58(
        func_type=4, rsp_node=1, rsp_dir=3, ref_node=101, ref_dir=3, x=freqs, data=np.linspace(1, 2, 5) * 1e-6,
        id1="x", binary=0, abscissa_spec_data_type=18, ordinate_spec_data_type=8, orddenom_spec_data_type=13,
        ordinate_axis_units_lab="m", orddenom_axis_units_lab="N")], mode="add")
    assert pyuff.UFF(str(path)).read_sets(0)["ord_data_type"] == 4
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--measured", str(path), "--out", "-", "--quiet"]) == 2
    _one_line_error(capsys, "magnitude.uff", "ordinate data type 4", "complex values")


# ----------------------------------------------------------------------- CSV of spreadsheets
def _frf_csv(tmp_path):
    out = tmp_path / "f.csv"
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--out", str(out), "--quiet"]) == 0
    return pd.read_csv(out), rdm.frf(rdm.load_model(GEAR), 0.0, np.linspace(2, 40, 5))


@pytest.mark.parametrize("change, words", [
    (lambda t, p: t.rename(columns={"quantity": "frequency_hz"}).to_csv(p, index=False),
     ["column 'frequency_hz' is named twice", "columns 1 and 9"]),
    (lambda t, p: t.assign(frequency_hz=t.frequency_hz * 1e40).to_csv(p, index=False),
     ["frequency line of 2e+40 Hz", "at most 1e+30 Hz"]),
    (lambda t, p: t.assign(output=np.where(t.index == 1, "acc-top-z\u200b", t.output)).to_csv(p, index=False),
     ["'acc-top-z\\u200b' are not sensors"]),
], ids=["column-twice", "frequency-1e40", "invisible-name"])
def test_a_measured_csv_of_no_meaning_is_refused_by_name(tmp_path, capsys, change, words):
    """A second frequency_hz column was left unread whatever it held; lines at 2e40 Hz were
    read and drawn; a zero-width space in a channel name was printed invisible."""
    table, _ = _frf_csv(tmp_path)
    path = tmp_path / "m.csv"
    change(table, path)
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--measured", str(path), "--out", "-", "--quiet"]) == 2
    _one_line_error(capsys, "m.csv", *words)


def test_a_spreadsheets_trailing_empty_rows_are_no_lines(tmp_path):
    """``,,,,`` rows after the data (a spreadsheet's export) were refused as a line at nan Hz."""
    table, exact = _frf_csv(tmp_path)
    path = tmp_path / "trailing.csv"
    path.write_text(table.to_csv(index=False) + ",,,,,,,,\n\n,,,\n")
    [back] = read_measured(path, rdm.load_model(GEAR))
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-9)


# ----------------------------------------------------------------------- mapping tables
def test_a_mapping_with_direction_letters_reads_as_the_codes(tmp_path):
    """Channel tables of other tools write +Z, Y-, -X: read as UFF codes 3, -2, -1 (they were
    refused: 'expected a whole number'); a sign flips the channel."""
    model = rdm.load_model(GEAR)
    exact = rdm.frf(model, 0.0, np.linspace(2, 40, 5))
    uff = tmp_path / "m.uff"
    write_uff58([exact], uff, default_mapping(model))      # acc-top-z 1:+3, acc-side-y 2:+2, 101:+3, 102:+2
    letters, flipped = tmp_path / "letters.csv", tmp_path / "flipped.csv"
    letters.write_text("name,node,direction\nacc-top-z,1,+Z\nacc-side-y,2,Y+\nhammer-z,101,z\nshaker-y,102,Y\n")
    flipped.write_text("name,node,direction\nacc-top-z,1,-Z\nacc-side-y,2,y\nhammer-z,101,Z\nshaker-y,102,Y\n")
    [same] = read_measured(uff, model, letters)
    [minus] = read_measured(uff, model, flipped)
    np.testing.assert_allclose(same.H, exact.H, rtol=1e-10)
    row = minus.outputs.index("acc-top-z")
    np.testing.assert_allclose(minus.H[row], -exact.H[exact.outputs.index("acc-top-z")], rtol=1e-10)


@pytest.mark.parametrize("rows, words", [
    ("", ["map.csv", "no rows"]),
    ("acc-top-z,1,up\nacc-side-y,2,2\nhammer-z,101,3\nshaker-y,102,2\n", ["map.csv", "line 2", "'up'", "+Z"]),
], ids=["header-only", "unknown-letter"])
def test_a_mapping_of_no_channel_is_refused_by_its_name(tmp_path, capsys, rows, words):
    """A header alone was refused as the data file's 'node 1 direction 3 is not in the mapping
    table (node:direction=name: )', naming neither the mapping nor what it lacked."""
    uff = tmp_path / "m.uff"
    model = rdm.load_model(GEAR)
    write_uff58([rdm.frf(model, 0.0, np.linspace(2, 40, 5))], uff, default_mapping(model))
    mapping = tmp_path / "map.csv"
    mapping.write_text("name,node,direction\n" + rows)
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--measured", str(uff), "--mapping", str(mapping),
                 "--out", "-", "--quiet"]) == 2
    _one_line_error(capsys, *words)


# ----------------------------------------------------------------------- names that read alike
def test_two_names_that_read_the_same_are_refused(tmp_path, capsys):
    """'café' precomposed (U+00E9) and decomposed (e + U+0301) are two sensors that print alike:
    ``--sensor café`` chose one of them by the terminal's input method."""
    text = GEAR.read_text()
    text = text.replace('name = "acc-top-z"', 'name = "caf\u00e9"')
    text = text.replace('name = "acc-side-y"', 'name = "cafe\u0301"')
    path = tmp_path / "cafe.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "cafe.toml", "[sensors[1]] name", "caf\\xe9 against cafe\\u0301")


# ----------------------------------------------------------------------- TDMS channels
@pytest.mark.parametrize("samples, properties, options, words", [
    (None, {}, {"channels": ["acc", "acc"]}, ["channels = acc, acc", "acc is asked for twice"]),
    (None, {"wf_increment": 1e-320}, {}, ["sampling interval 9.99989e-321 s", "finite"]),
    (np.full(16, 1e300), {}, {}, ["sample 0 is 1e+300", "at most 1e+30"]),
    (None, {}, {"speed": float("nan")}, ["speed = nan", "finite speed"]),
], ids=["channel-twice", "subnormal-interval", "samples-1e300", "speed-nan"])
def test_a_tdms_record_of_no_meaning_is_refused(tmp_path, samples, properties, options, words):
    """Each was read: a channel twice (the same samples as two channels), an infinite sampling
    rate, infinite spectra, a record at NaN rpm."""
    nptdms = pytest.importorskip("nptdms")
    from rotordyn_modal.io.tdms import read_tdms_records

    path = tmp_path / "r.tdms"
    data = np.sin(np.arange(16) * 0.3) if samples is None else samples
    with nptdms.TdmsWriter(str(path)) as writer:
        writer.write_segment([nptdms.ChannelObject("record", "acc", data,
                                                   properties={"unit_string": "m/s^2", "wf_increment": 1e-3,
                                                               **properties})])
    with pytest.raises(InputError) as info:
        read_tdms_records(path, **options)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    for word in words:
        assert word in message, message
