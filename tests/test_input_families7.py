"""A seventh round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families6.py``): combinations of elements not tried together (two flexible rotors
on one belt), rotors written by hand in ROSS's file format (a material given by E and
Poisson's ratio, a coefficient table without its speeds, diameters in mm), and what the
terminal prints of a sweep. Each case through the command line in this process or through the
reader the command line calls."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.io.ross_file import read_ross_rotor
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
ROSS = ROOT / "tests" / "data" / "ross"

#: two flexible rotors on the ground, the second driven by a belt from the first
TWO_SHAFTS = """
name = "two flexible rotors on one belt"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "motor"

[[materials]]
name = "steel"
density = 7810.0
young_modulus = 2.11e11
poisson_ratio = 0.3

[[rotors]]
name = "motor"
start = [0.0, 0.2, 0.0]
element_length = 0.1
[[rotors.shaft]]
length = 0.4
outer_diameter = 0.05
material = "steel"

[[rotors]]
name = "pump"
start = [0.0, -0.2, 0.0]
element_length = 0.1
[[rotors.shaft]]
length = 0.6
outer_diameter = 0.04
material = "steel"

[[transmissions]]
type = "belt"
driver = "motor"
driven = "pump"
ratio = 0.5

[[bearings]]
name = "m1"
rotor = "motor"
axial_position = 0.0
stiffness = 1.0e7
[[bearings]]
name = "m2"
rotor = "motor"
axial_position = 0.4
stiffness = 1.0e7
[[bearings]]
name = "p1"
rotor = "pump"
axial_position = 0.0
stiffness = 1.0e7
[[bearings]]
name = "p2"
rotor = "pump"
axial_position = 0.6
stiffness = 1.0e7
"""


# ----------------------------------------------------------------------- combinations
def test_check_lists_the_coordinates_of_two_flexible_rotors(tmp_path, capsys):
    """Two flexible rotors in one model: ``check`` ended in IndexError (exit 1) collapsing the
    second shaft's node coordinates at indices the first collapse had shifted."""
    model_file = tmp_path / "two.toml"
    model_file.write_text(TWO_SHAFTS)
    assert main(["check", str(model_file)]) == 0
    out = capsys.readouterr().out
    [line] = [line for line in out.splitlines() if line.strip().startswith("coordinates")]
    # 0.4 m in elements of at most 0.1 m: 5 nodes; 0.6 m: 7 nodes; 4 coordinates each
    assert line.strip() == ("coordinates (48): motor.n0.uy ... motor.n4.rz (5 nodes x 4), "
                            "pump.n0.uy ... pump.n6.rz (7 nodes x 4)")


# ----------------------------------------------------------------------- ROSS files by hand
def _ross_text(**replace) -> str:
    text = (ROSS / "rotor_example.toml").read_text()
    for old, new in replace.values():
        assert old in text
        text = text.replace(old, new)
    return text


_G = "G_s = 81200000000.0"
_E = "E = 211000000000.0"


@pytest.mark.parametrize("edit", [
    {"g": (_G, f"Poisson = {211e9 / (2 * 81.2e9) - 1!r}")},
    {"e": (_E, f"Poisson = {211e9 / (2 * 81.2e9) - 1!r}")},
    {"g": (_G, f"{_G}\nPoisson = {211e9 / (2 * 81.2e9) - 1!r}")},
], ids=["E-and-Poisson", "G-and-Poisson", "all-three-agreeing"])
def test_a_ross_material_of_any_two_elastic_constants_is_the_same_rotor(tmp_path, edit):
    """ROSS's ``Material`` takes any two of E, G_s and Poisson (it computes the third); a rotor
    written by hand with E and Poisson's ratio was refused ('G_s = <missing>'). The same steel
    given either way is the same rotor: the same lowest frequencies at rest."""
    hand = tmp_path / "hand.toml"
    hand.write_text(_ross_text(**edit))

    def lowest(path):
        model = rdm.Model.from_dict(read_ross_rotor(path))
        return np.sort(rdm.modal(model, 0.0).frequencies_hz)[:6]

    np.testing.assert_allclose(lowest(hand), lowest(ROSS / "rotor_example.toml"), rtol=1e-9)


@pytest.mark.parametrize("edit, words", [
    ({"g": (_G + "\n", "")}, ["G_s or Poisson", "<missing>", "gives E"]),
    ({"g": (_G, f"{_G}\nPoisson = 0.3")}, ["Poisson = 0.3", "0.299261"]),
], ids=["one-constant", "three-that-disagree"])
def test_a_ross_material_that_is_no_material_is_refused_by_name(tmp_path, capsys, edit, words):
    bad = tmp_path / "bad.toml"
    bad.write_text(_ross_text(**edit))
    out = tmp_path / "m.toml"
    assert main(["import-ross", str(bad), "--out", str(out)]) == 2
    _one_line_error(capsys, "bad.toml", "ShaftElement_Shaft Element 0.material", *words)
    assert not out.exists()


@pytest.mark.parametrize("speeds, words", [
    (None, ["speed, which the table lacks", "expected 1 value,"]),
    ("[ 0.0, 400.0, 800.0, 1200.0,]", ["expected 4 values", "speed = [0.0, 400.0, 800.0, 1200.0] [rad/s]"]),
], ids=["no-speeds", "one-speed-short"])
def test_a_ross_table_whose_speeds_miss_is_named_by_its_speeds(tmp_path, capsys, speeds, words):
    """Coefficient lists of 5 values beside no ``speed`` list were refused as 'mxx = [0, ...]:
    expected 1 values (one per speed of the table)', naming neither the speeds nor their lack."""
    text = (ROSS / "speed_tables.toml").read_text()
    line = "speed = [ 0.0, 400.0, 800.0, 1200.0, 1600.0,]\n"
    assert line in text
    text = text.replace(line, "" if speeds is None else f"speed = {speeds}\n", 1)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    assert main(["import-ross", str(bad), "--out", str(tmp_path / "m.toml")]) == 2
    _one_line_error(capsys, "bad.toml", "[BearingElement_Bearing 0]", *words)


def _in_mm(text: str) -> str:
    """The ROSS file with every length and diameter in mm, as a hand-written file may have them."""
    return re.sub(r"^(L|odl|odr) = ([0-9.e]+)$", lambda m: f"{m.group(1)} = {float(m.group(2)) * 1000!r}",
                  text, flags=re.M)


@pytest.mark.parametrize("edit, words", [
    (_in_mm, ["[rotors.mm.shaft.", "outer_diameter = 50", "mm typed for m"]),
    (lambda t: t.replace(_E, "E = 211.0"), ["[materials.Steel] young_modulus = 211", "GPa"]),
], ids=["diameters-in-mm", "modulus-in-GPa"])
def test_import_ross_says_what_check_would_warn_about(tmp_path, capsys, edit, words):
    """A ROSS rotor in mm (a shaft 1.5 km long and 50 m thick, 2.3e10 kg) or with E in GPa was
    written without a word (exit 0); ``check`` of the written file warned of the modulus only,
    and of the diameters nothing at all."""
    source = tmp_path / "mm.toml"
    source.write_text(edit((ROSS / "rotor_example.toml").read_text()))
    out = tmp_path / "m.toml"
    assert main(["import-ross", str(source), "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "import-ross: warning: " in err and all(word in err for word in words), err
    assert main(["check", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "check: warning: " in err and all(word in err for word in words), err


def test_a_shaft_of_plausible_diameters_draws_no_size_warning(tmp_path, capsys):
    """ROSS's own rotors (diameters of centimetres) and the flexible examples stay quiet."""
    out = tmp_path / "m.toml"
    assert main(["import-ross", str(ROSS / "rotor_example.toml"), "--out", str(out), "--quiet"]) == 0
    assert main(["check", str(ROOT / "examples" / "flexible_pump_on_mounts.toml"), "--quiet"]) == 0
    assert "thick" not in capsys.readouterr().err


# ----------------------------------------------------------------------- what a sweep prints
def test_campbell_prints_an_undamped_modes_damping_as_zero(capsys):
    """The compressor's axial mode (its thrust bearing has stiffness and no damping, and the
    axial motion couples to nothing that damps) is undamped: ``stability`` and
    ``critical-speeds`` print its damping ratio 0, ``campbell`` printed -3.9e-15 and a real part
    of 4.6e-12 (read as unstable)."""
    model = ROOT / "examples" / "compressor_rotor.toml"
    assert main(["campbell", str(model), "--speeds", "0:1000:2", "--lowest", "4"]) == 0
    header, *lines = capsys.readouterr().out.splitlines()
    columns = header.split()
    rows = [dict(zip(columns, line.split())) for line in lines]
    axial = [row for row in rows if row["whirl"] == "none"]
    assert len(axial) == 2, rows                     # at 0 and at 1000 rpm
    for row in axial:
        assert math.isclose(float(row["frequency_hz"]), 185.245, rel_tol=1e-5)
        assert (row["damping_ratio"], row["log_decrement"], row["real_part"]) == ("0", "0", "0"), row


# ----------------------------------------------------------------------- numbers at the edges
def test_a_power_at_a_speed_of_no_machine_is_refused_before_the_forces_overflow(tmp_path, capsys):
    """``static --speed 1e-300 --transmitted-power 15000``: the torque power / speed, 1.4e305 N m,
    overflowed the tooth forces (numpy's 'overflow encountered' warnings) and a CSV of inf and
    nan was written (exit 0)."""
    out = tmp_path / "s.csv"
    assert main(["static", str(ROOT / "examples" / "gear_machine.toml"), "--speed", "1e-300",
                 "--transmitted-power", "15000", "--out", str(out), "--quiet"]) == 2
    _one_line_error(capsys, "--transmitted-power 15000", "torque", "1e+30 N m")
    assert not out.exists()
    # at an engineer's speed the same power gives the torque power / speed, 47.7 N m at 3000 rpm
    from rotordyn_modal.analysis.static import transmission_torques

    model = rdm.load_model(ROOT / "examples" / "gear_machine.toml")
    torques = transmission_torques(model, 3000 * math.pi / 30, 15000.0)
    assert torques and all(math.isclose(t, 15000.0 / (3000 * math.pi / 30 * abs(model.speed_ratios[k.split("->")[0]])))
                           for k, t in torques.items())


_STAGE = ["--rated-power", "5e5", "--impeller-diameter", "0.3", "--restriction-height", "0.02"]


@pytest.mark.parametrize("operating, words", [
    ("1e-300", ["at --operating-speed 1e-300", "Qa = inf", "1e+27"]),
    ("1e-20", ["at --operating-speed 1e-20", "Qa = 2.387e+29"]),
    ("-3000", ["--operating-speed -3000", "sense of --mcs 3000"]),
], ids=["overflow", "beyond-every-machine", "against-the-mcs"])
def test_a_level1_operating_speed_of_no_machine_is_refused_by_name(capsys, operating, words):
    """N_r of the API's Qa = B C P / (D H N_r): at 1e-300 rpm numpy's 'overflow encountered in
    divide' came on a line before the refusal, and that refusal (as at 1e-20 rpm) named the stage
    data but not the speed that made Qa so large; -3000 rpm beside --mcs 3000 was taken as 3000
    (exit 0)."""
    argv = ["level1", str(ROOT / "examples" / "fan_on_bearings.toml"), "--mcs", "3000", "--station", "fan",
            *_STAGE, "--operating-speed", operating, "--quiet"]
    assert main(argv) == 2
    _one_line_error(capsys, *words)


def test_a_level1_operating_speed_of_the_mcs_sense_keeps_the_apis_qa(capsys):
    """Qa = 3 (P / Omega) / (D H) at N_r = 2900 rpm: 3 x 5e5 / (2900 pi / 30) / (0.3 x 0.02)."""
    argv = ["level1", str(ROOT / "examples" / "fan_on_bearings.toml"), "--mcs", "3000", "--station", "fan",
            *_STAGE, "--operating-speed", "2900", "--factor", "2"]
    assert main(argv) == 0
    qa = 3 * 5e5 / (2900 * math.pi / 30) / (0.3 * 0.02)
    [line] = [line for line in capsys.readouterr().err.splitlines() if line.startswith("Qa = ")]
    assert math.isclose(float(line.split()[2]), qa, rel_tol=1e-5), (line, qa)


# ----------------------------------------------------------------------- other tools' files
@pytest.mark.parametrize("command", [["check"], ["modes", "--speed", "1000"]])
def test_a_ross_file_given_as_a_model_names_the_command_that_reads_it(capsys, command):
    """A ROSS user's first try, ``check rotor.toml`` on ROSS's own file, was refused by its first
    key ('ross_version = 3.1.0: expected one of the keys name, spin_axis, ...')."""
    ross = ROSS / "rotor_example.toml"
    assert main([command[0], str(ross), *command[1:]]) == 2
    _one_line_error(capsys, "rotor_example.toml", "ROSS", f"import-ross {ross}")


# ----------------------------------------------------------------------- report options
@pytest.mark.parametrize("standard, extra, words", [
    ("api684", ["--station", "nobody", "--qa", "1e5"], ["--station:", "api684", "Level I", "api617"]),
    ("iso", ["--station", "fan", "--qa", "1e5"], ["--station:", "iso", "Level I"]),
    ("api684", ["--machine", "turbine"], ["--machine:", "api684"]),
    ("api617", ["--iso-group", "1", "--iso-support", "rigid"], ["--iso-group:", "api617", "ISO 20816-3"]),
    ("api617", ["--operating-speed", "nan"], ["--operating-speed given without --station"]),
    ("api617", ["--density-ratio", "-4"], ["--density-ratio given without --station"]),
], ids=["level1-in-api684", "level1-in-iso", "machine-in-api684", "iso-in-api617", "operating-speed-alone",
        "density-ratio-alone"])
def test_a_report_option_its_standard_does_not_use_is_refused(tmp_path, capsys, standard, extra, words):
    """Each was dropped without a word (exit 0, the report written without it): a Level I
    station on a rotor the model lacks under --standard api684, ISO classes in an API 617
    report, Level I stage data without a station (--qa alone was refused)."""
    out = tmp_path / "r.html"
    assert main(["report", str(ROOT / "examples" / "fan_on_bearings.toml"), "--standard", standard, "--mcs", "3000",
                 *extra, "--out", str(out)]) == 2
    _one_line_error(capsys, *words)
    assert not out.exists()


def test_a_level1_station_on_a_machine_without_rotors_says_so(tmp_path, capsys):
    """A casing on mounts alone: the refusal ended in "the model's rotors are " and nothing."""
    model = tmp_path / "block.toml"
    model.write_text('name = "block"\n[stator]\nmass = 50.0\ninertia = [2.0, 3.0, 4.0]\n'
                     + "".join(f'[[suspensions]]\nname = "{n}"\nposition = [{x}, {y}, 0.0]\nstiffness = [1e5, 1e5, 2e5]\n'
                               for n, x, y in (("a", 0.3, 0.2), ("b", -0.3, 0.2), ("c", 0.0, -0.3))))
    assert main(["level1", str(model), "--mcs", "3000", "--station", "stator", "--qa", "1e5"]) == 2
    err = _one_line_error(capsys, "no rotor 'stator'", "no [[rotors]]")
    assert not err.rstrip().endswith("are"), err


# ----------------------------------------------------------------------- '-' as an output
@pytest.mark.parametrize("argv, option", [
    (["unbalance", "FAN", "--speeds", "100:3000:3", "--mcs", "3000", "--checks", "-", "--quiet"], "--checks"),
    (["unbalance", "FAN", "--speeds", "100:3000:3", "--orbits", "-", "--quiet"], "--orbits"),
    (["report", "FAN", "--standard", "api684", "--mcs", "3000", "--out", "-"], "--out"),
    (["report", "FAN", "--standard", "api684", "--mcs", "3000", "--out", "r.html", "--pdf", "-"], "--pdf"),
    (["fit", "GEAR", "--measured", "g.csv", "--params", "suspensions.mount-FL.stiffness", "--out", "-"], "--out"),
], ids=["unbalance-checks", "unbalance-orbits", "report-out", "report-pdf", "fit-out"])
def test_an_output_never_written_to_standard_output_refuses_a_dash(tmp_path, monkeypatch, capsys, argv, option):
    """``-`` is standard output for the tables of --out; these outputs are files only, and each
    wrote a file named '-' in the working folder (exit 0; ``fit`` said 'fitted model written to -')."""
    monkeypatch.chdir(tmp_path)
    examples = ROOT / "examples"
    if "GEAR" in argv:
        assert main(["frf", str(examples / "gear_machine.toml"), "--freqs", "2:40:5", "--out", "g.csv", "--quiet"]) == 0
    argv = [{"FAN": str(examples / "fan_on_bearings.toml"), "GEAR": str(examples / "gear_machine.toml")}.get(a, a)
            for a in argv]
    capsys.readouterr()
    assert main(argv) == 2
    _one_line_error(capsys, f"{option} -", "give a file name")
    assert not (tmp_path / "-").exists()


def test_bearings_twelve_decades_apart_are_not_said_to_hold_nothing(tmp_path, capsys):
    """ROSS's rotor on 1e13 N/m at one end and 10 N/m at the other: its tilt is held (10 N/m on
    a 1.5 m arm), too softly beside the other bearing for double precision to keep, and was
    refused as 'nothing holds its tilt about the x axis'."""
    text = (ROSS / "rotor_example.toml").read_text()
    first, second = text.split('["BearingElement_Bearing 1"]')
    first = first.replace("kxx = [ 1000000.0,]", "kxx = [ 1e13,]").replace("kyy = [ 800000.0,]", "kyy = [ 1e13,]")
    second = second.replace("kxx = [ 1000000.0,]", "kxx = [ 10.0,]", 1).replace("kyy = [ 800000.0,]", "kyy = [ 10.0,]", 1)
    bad = tmp_path / "spread.toml"
    bad.write_text(first + '["BearingElement_Bearing 1"]' + second)
    assert main(["import-ross", str(bad), "--out", str(tmp_path / "m.toml")]) == 2
    err = _one_line_error(capsys, "spread.toml", "tilt about the x axis", "held only", "10 to 1e+13 N/m")
    assert "nothing holds" not in err


def test_a_report_whose_sweep_leaves_a_speed_table_names_mcs(tmp_path, capsys):
    """The report sweeps 2 % of --mcs to 1.5 x --mcs, and no option moves that range: a bearing
    tabulated to 15,279 rpm (ROSS's 1600 rad/s) under --mcs 12000 was refused as '... outside the
    coefficient table's speeds_rpm range ...: extend the table or the sweep's range'."""
    from rotordyn_modal.io.ross_file import write_model_file

    model = tmp_path / "tables.toml"
    write_model_file(read_ross_rotor(ROSS / "speed_tables.toml"), model)
    out = tmp_path / "r.html"
    assert main(["report", str(model), "--standard", "api684", "--mcs", "12000", "--out", str(out)]) == 2
    _one_line_error(capsys, "--mcs 12000", "1.5 x", "240 .. 18000 rpm", "speeds_rpm 0 .. 15278.9 rpm")
    assert not out.exists()


@pytest.mark.parametrize("ending", [".txt", ".tsv"])
def test_a_tab_separated_text_export_reads_as_the_csv(tmp_path, ending):
    """Test rigs and spreadsheets export a tab-separated table as .txt or .tsv: the same table as
    the CSV ``frf --out`` writes was refused as 'unknown measured data format'."""
    import pandas as pd
    from rotordyn_modal.io.measured import read_measured

    gear = ROOT / "examples" / "gear_machine.toml"
    csv = tmp_path / "g.csv"
    assert main(["frf", str(gear), "--speed", "600", "--freqs", "2:40:5", "--out", str(csv), "--quiet"]) == 0
    text = tmp_path / f"g{ending}"
    pd.read_csv(csv, dtype=str, keep_default_na=False).to_csv(text, sep="\t", index=False)
    model = rdm.load_model(gear)
    [a], [b] = read_measured(csv, model), read_measured(text, model)
    assert (a.inputs, a.outputs, a.speed) == (b.inputs, b.outputs, b.speed)
    np.testing.assert_array_equal(a.frequencies_hz, b.frequencies_hz)
    np.testing.assert_array_equal(a.H, b.H)


def test_a_rotor_named_stator_is_refused(tmp_path, capsys):
    """``import-ross --name stator`` (or a rotor table so named) made a model whose rotor the
    options and tables could not tell from the casing: ``static --force stator:0,0,0.75:100,0,0``
    put the 100 N on the (absent) casing, the shaft took none and the balance line said 'sum of
    forces 100 N' (exit 0)."""
    out = tmp_path / "m.toml"
    assert main(["import-ross", str(ROSS / "rotor_example.toml"), "--out", str(out), "--name", "stator"]) == 2
    _one_line_error(capsys, "[rotors[0]] name", "'stator'", "casing")
    assert not out.exists()
    model_file = tmp_path / "two.toml"
    model_file.write_text(TWO_SHAFTS.replace('"motor"', '"stator"'))
    assert main(["check", str(model_file)]) == 2
    _one_line_error(capsys, "two.toml", "name = 'stator'")


def test_campbell_prints_a_planar_modes_whirl_ratio_as_zero(tmp_path, capsys):
    """ROSS's rotor at rest on bearings of 1e6 N/m along x and 8e5 N/m along y: without spin its
    modes move in the x or the y plane alone (whirl ratio exactly 0, whirl 'none'); ``campbell``
    printed -1.6e-11 and 1.1e-11 at 0 rpm."""
    from rotordyn_modal.io.ross_file import write_model_file

    model = tmp_path / "rotor.toml"
    write_model_file(read_ross_rotor(ROSS / "rotor_example.toml"), model)
    assert main(["campbell", str(model), "--speeds", "0:1000:2", "--lowest", "4"]) == 0
    header, *lines = capsys.readouterr().out.splitlines()
    rows = [dict(zip(header.split(), line.split())) for line in lines]
    at_rest = [row for row in rows if row["speed_rpm"] == "0"]
    assert len(at_rest) == 4 and all((row["whirl"], row["whirl_ratio"]) == ("none", "0") for row in at_rest), rows
    spinning = [row for row in rows if row["speed_rpm"] == "1000"]
    assert all(abs(float(row["whirl_ratio"])) > 0.05 for row in spinning), rows   # not zeroed where it whirls
