"""Inputs a new user tries in the families of issues 28 and 29 that no earlier test named (session
42's probes: /work/notes/reports42/probe42_tried.md lists every one tried).

Each test here failed on the code before its fix: an option of another sub-command
(``frf --amplitude rms``) refused as the program's, not the sub-command's, naming no command that
takes it; and the others listed in each test's docstring.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from quiet_cli import run_quietly

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
COMPRESSOR = EXAMPLES / "compressor_rotor.toml"


def _one_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    return lines[0]


# ------------------------------------------------------------------ options of other sub-commands
@pytest.mark.parametrize("command, required", [
    ("frf", ["--freqs", "1:500:5"]),
    ("campbell", ["--speeds", "0:1000:3"]),
    ("check", []),
])
def test_an_option_of_other_sub_commands_is_refused_by_this_one_naming_those(command, required):
    """``frf MODEL --amplitude rms`` said ``rotordyn-modal: error: unrecognized arguments:
    --amplitude rms (see 'rotordyn-modal --help')``: neither the sub-command refused nor those
    that take --amplitude (unbalance and report, where it is documented)."""
    code, err = run_quietly([command, str(COMPRESSOR), *required, "--amplitude", "rms"])
    line = _one_line(err)
    assert code == 2
    assert line.startswith(f"rotordyn-modal {command}: error: unrecognized arguments: --amplitude rms")
    assert "--amplitude is an option of unbalance, report" in line
    assert f"see 'rotordyn-modal {command} --help'" in line


def test_a_typo_of_the_sub_commands_own_option_names_the_option_meant():
    """``campbell --lowset 6`` (a typo of ``--lowest``) named no option."""
    code, err = run_quietly(["campbell", str(COMPRESSOR), "--speeds", "0:1000:3", "--lowset", "6"])
    assert code == 2
    assert "did you mean '--lowest'?" in _one_line(err)


def test_an_extra_positional_argument_is_still_refused_by_its_sub_command():
    code, err = run_quietly(["check", str(COMPRESSOR), "second.toml"])
    assert code == 2
    assert _one_line(err).startswith("rotordyn-modal check: error: unrecognized arguments: second.toml (see")


# ------------------------------------------------------------------ API 617 Level I stage data
@pytest.mark.parametrize("command, extra", [
    ("level1", []),
    ("report", ["--standard", "api617", "--out", "report.html"]),
])
def test_a_density_ratio_beside_turbine_stages_is_refused(tmp_path, monkeypatch, command, extra):
    """``--machine turbine --density-ratio 1.2`` was dropped without a word (API 617's turbine
    formula qa = 1.5 T / (D H) has no density ratio): Qa came out 265258 N/m for a ratio the user
    had given, and no report file was to be written either."""
    monkeypatch.chdir(tmp_path)
    code, err = run_quietly([command, str(COMPRESSOR), "--mcs", "9000", "--station", "compressor",
                             "--rated-power", "1e6", "--impeller-diameter", "0.3", "--restriction-height", "0.02",
                             "--machine", "turbine", "--density-ratio", "1.2", "--quiet", *extra])
    assert code == 2
    line = _one_line(err)
    assert "--density-ratio 1.2" in line and "--machine turbine" in line
    assert not (tmp_path / "report.html").exists()


def test_a_stage_value_out_of_range_names_the_stage_count_in_words():
    """``--impeller-diameter -0.3`` said 'expected 1 finite values > 0'."""
    code, err = run_quietly(["level1", str(COMPRESSOR), "--mcs", "9000", "--station", "compressor",
                             "--rated-power", "1e6", "--impeller-diameter", "-0.3", "--restriction-height", "0.02"])
    assert code == 2
    assert _one_line(err).endswith("--impeller-diameter -0.3: expected finite values > 0, one per stage (1 stage)")


# ------------------------------------------------------------------ ROSS files
ROSS = ROOT / "tests" / "data" / "ross" / "speed_tables.toml"


def test_a_ross_save_cut_short_before_its_material_tables_names_the_missing_table(tmp_path):
    """A ROSS save ends with its elements' material tables; cut there, it is still TOML, and the
    refusal said ``material = None: expected a table with name, rho, E and G_s`` (Python's None,
    neither the table's name nor why it may be missing)."""
    text = ROSS.read_text(encoding="utf-8")
    cut = tmp_path / "cut.toml"
    cut.write_text(text[:text.index('["ShaftElement_Shaft Element 0".material]')], encoding="utf-8")
    code, err = run_quietly(["import-ross", str(cut), "--out", str(tmp_path / "model.toml")])
    line = _one_line(err)
    assert code == 2 and not (tmp_path / "model.toml").exists()
    assert "material = '<missing>'" in line and "None" not in line
    assert '["ShaftElement_Shaft Element 0".material]' in line and "cut short" in line


def test_a_ross_version_older_than_the_readers_is_said(tmp_path):
    """``ross_version = "0.3.0"`` (older than the 0.4 to 3.1 this reader was checked on) was read
    without a word, while a newer one drew a warning."""
    old = tmp_path / "old.toml"
    old.write_text(ROSS.read_text(encoding="utf-8").replace('ross_version = "3.1.0"', 'ross_version = "0.3.0"'),
                   encoding="utf-8")
    code, err = run_quietly(["import-ross", str(old), "--out", str(tmp_path / "model.toml")])
    assert code == 0 and (tmp_path / "model.toml").exists()
    assert "ross_version = '0.3.0': older than the ROSS versions this reader was checked on (ROSS 0.4 to 3.1)" in err


# ------------------------------------------------------------------ ISO 21940-11 balance grades
BASE = """
name = "probe base"
spin_axis = [1.0, 0.0, 0.0]

[[materials]]
name = "steel"
density = 7810.0
young_modulus = 2.11e11
poisson_ratio = 0.3

[[rotors]]
name = "r"
start = [0.0, 0.0, 0.0]

[[rotors.shaft]]
length = 0.5
outer_diameter = 0.05
material = "steel"

[[bearings]]
name = "b1"
rotor = "r"
axial_position = 0.0
stiffness = 1e8

[[bearings]]
name = "b2"
rotor = "r"
axial_position = 0.5
stiffness = 1e8

[[unbalances]]
rotor = "r"
axial_position = 0.25
"""


@pytest.mark.parametrize("typed, meant", [('"G2,5"', "G2.5"), ('"6,3"', "G6.3"), ('"2.5"', "G2.5")])
def test_a_grade_with_a_decimal_comma_or_without_its_g_names_the_grade_meant(tmp_path, typed, meant):
    """``grade = "G2,5"`` (a decimal comma, as written in much of Europe) or the number as text
    was refused listing the eleven grades, without the one meant."""
    path = tmp_path / "m.toml"
    path.write_text(BASE + f"grade = {typed}\nservice_speed_rpm = 3000.0\n", encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    assert code == 2
    assert f"grade = {typed.replace(chr(34), chr(39))}" in _one_line(err)
    assert f"did you mean '{meant}'?" in err


@pytest.mark.parametrize("typed", ['"G3"', '"G0"', "-2.5", '"G2.5 mm/s"'])
def test_a_grade_that_is_none_of_the_eleven_suggests_none(tmp_path, typed):
    path = tmp_path / "m.toml"
    path.write_text(BASE + f"grade = {typed}\nservice_speed_rpm = 3000.0\n", encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    assert code == 2 and "did you mean" not in _one_line(err)


# ------------------------------------------------------------------ keys of other codes
@pytest.mark.parametrize("table, typed, meant", [
    ("[rotors.r.shaft.0]", "diameter", "outer_diameter"),      # the plain word
    ("[rotors.r.shaft.0]", "L", "length"),                     # ROSS's ShaftElement
    ("[rotors.r.shaft.0]", "odl", "outer_diameter"),
    ("[materials.steel]", "E", "young_modulus"),               # ROSS's Material
    ("[materials.steel]", "rho", "density"),
    ("[materials.steel]", "nu", "poisson_ratio"),
    ("[bearings.b1]", "kxx", "stiffness"),                     # ROSS's BearingElement
    ("[rotors.r]", "element_size", "element_length"),
])
def test_a_key_as_another_code_names_it_gets_the_key_meant(tmp_path, table, typed, meant):
    """A ROSS user writing a model file by hand types ROSS's names (``E = 2.11e11``, ``L = 0.5``,
    ``kxx = 1e8``) and anyone may type a shaft's ``diameter``: refused as unknown keys with no
    key meant (difflib's similarity of ``diameter`` to ``outer_diameter`` is 0.73, below 0.75)."""
    replaced = {"diameter": ("outer_diameter = 0.05", "diameter = 0.05"), "L": ("length = 0.5", "L = 0.5"),
                "odl": ("outer_diameter = 0.05", "odl = 0.05"), "E": ("young_modulus =", "E ="),
                "rho": ("density =", "rho ="), "nu": ("poisson_ratio =", "nu ="),
                "kxx": ("stiffness = 1e8", "kxx = 1e8"),
                "element_size": ('start = [0.0, 0.0, 0.0]', 'start = [0.0, 0.0, 0.0]\nelement_size = 0.05')}[typed]
    path = tmp_path / "m.toml"
    path.write_text((BASE + "amount = 1e-4\n").replace(*replaced, 1), encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    line = _one_line(err)
    assert code == 2 and f"{table} {typed} = " in line
    assert line.endswith(f"(unknown key; did you mean '{meant}'?)")


def test_another_codes_name_is_offered_only_where_the_table_has_the_key_meant():
    from rotordyn_modal.model._table import close_key

    assert close_key("E", ["name", "density", "young_modulus"]) == "young_modulus"
    assert close_key("E", ["stiffness", "damping"]) is None          # a bearing has no modulus
    assert close_key("m", ["name", "axial_position"]) is None


@pytest.mark.parametrize("old, new, where", [
    ("n = 7\nscale_factor", "scale_factor", "[BearingElement_Bearing 1] n"),
    ("n = 10\nm = 8.0", "m = 8.0", "[DiskElement_Disk 0] n"),
    ("n = 3\naxial_force", "axial_force", "[ShaftElement_Shaft Element 3] n"),
])
def test_a_ross_element_without_its_node_says_the_node_is_missing(tmp_path, old, new, where):
    """An element table without ``n`` was refused as ``n = None`` (Python's word for nothing)."""
    path = tmp_path / "no_n.toml"
    path.write_text(ROSS.read_text(encoding="utf-8").replace(old, new, 1), encoding="utf-8")
    code, err = run_quietly(["import-ross", str(path), "--out", str(tmp_path / "model.toml")])
    line = _one_line(err)
    assert code == 2 and f"{where} = '<missing>': expected " in line and "None" not in line


# ------------------------------------------------------------------ --units before and after
def test_two_unit_systems_before_and_after_the_sub_command_are_refused():
    """``rotordyn-modal --units us static M --units si`` printed SI (the later won) without a
    word, while an option given twice in one place is refused; a system given twice alike stands."""
    code, err = run_quietly(["--units", "us", "static", str(COMPRESSOR), "--units", "si", "--quiet"])
    assert code == 2
    assert _one_line(err).startswith("rotordyn-modal static: error: --units given twice ('us' before the "
                                     "sub-command, then 'si'): give it once")
    code, err = run_quietly(["--units", "us", "static", str(COMPRESSOR), "--units", "US", "--quiet"])
    assert code == 0, err


# ------------------------------------------------------------------ Level I stations named by a disk
@pytest.mark.parametrize("command, extra, units, scale", [
    ("level1", [], "si", 1.0),
    ("level1", ["--units", "us"], "us", 0.0254),
    ("report", ["--standard", "api617", "--out", "r.html"], "si", 1.0),
])
def test_a_station_named_by_its_disk_gets_the_offset_to_type(tmp_path, monkeypatch, command, extra, units, scale):
    """``--station compressor@impeller-1`` (the impeller as the model names it: API 617 puts Qa at
    the impellers) said only 'expected ROTOR or ROTOR@OFFSET (OFFSET in m ... from the rotor's
    centre of mass)': the user had to work out the impeller's offset from a centre of mass the
    file does not give. The refusal now gives the OFFSET, which puts the station on the disk."""
    import re

    import rotordyn_modal as rdm

    monkeypatch.chdir(tmp_path)
    code, err = run_quietly([command, str(COMPRESSOR), "--mcs", "9000", "--station", "compressor@impeller-1",
                             "--qa", "1e5", "--quiet", *extra])
    line = _one_line(err)
    assert code == 2 and line.startswith(f"rotordyn-modal {command}: error: --station 'compressor@impeller-1': ")
    offset = float(re.search(r"--station compressor@(\S+)$", line)[1]) * scale
    model = rdm.load_model(COMPRESSOR)
    rotor = model.rotor("compressor")
    centre_from_start = float((rotor.center_of_mass - rotor.start) @ model.spin_axis)
    assert abs(centre_from_start + offset - 0.30) < 1e-6        # impeller-1's axial_position in the file
    assert not (tmp_path / "r.html").exists()


def test_a_malformed_station_says_the_offset_unit_the_option_is_read_in():
    """With --units us the OFFSET of ``--station ROTOR@OFFSET`` is read in inches, and the
    refusal of ``compressor@`` said 'OFFSET in m'."""
    for units, unit in (("us", "in"), ("si", "m")):
        code, err = run_quietly(["level1", str(COMPRESSOR), "--mcs", "9000", "--station", "compressor@",
                                 "--qa", "1e5", "--units", units])
        assert code == 2 and f"ROTOR@OFFSET (OFFSET [{unit}] along spin_axis" in _one_line(err)


@pytest.mark.parametrize("typed", ["Steel", "steel ", "STEEL"])
def test_a_material_named_in_other_case_or_with_blanks_gets_the_name_meant(tmp_path, typed):
    """``material = "Steel"`` (ROSS's materials are often capitalised) beside ``[[materials]] name =
    "steel"`` was refused listing the names, without saying which was meant."""
    path = tmp_path / "m.toml"
    path.write_text((BASE + "amount = 1e-4\n").replace('material = "steel"', f'material = "{typed}"'), encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    line = _one_line(err)
    assert code == 2 and f"[rotors.r.shaft.0] material = '{typed}'" in line
    assert line.endswith("(did you mean 'steel'?)")


# ------------------------------------------------------------------ a disk wider than its shaft
@pytest.mark.parametrize("width", ["2.0", "50.0"])
def test_a_disk_wider_than_its_whole_shaft_draws_a_warning(tmp_path, width):
    """``width = 50`` (50 mm typed for m) or 2 m on a 0.5 m shaft was taken without a word: the
    disk then spanned the whole shaft and far past both its ends."""
    disk = ('\n[[rotors.disks]]\nname = "d"\naxial_position = 0.25\nmass = 10.0\npolar_inertia = 0.05\n'
            f'diametral_inertia = 0.03\nwidth = {width}\n')
    path = tmp_path / "m.toml"
    text = BASE + "amount = 1e-4\n"
    path.write_text(text.replace("[[bearings]]", disk + "\n[[bearings]]", 1), encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    assert code == 0
    line = _one_line(err)
    assert f"[rotors.r.disks.d] width = {float(width):g}: wider than the whole shaft it sits on (0.5 m long)" in line


def test_a_disk_as_wide_as_its_shaft_draws_none(tmp_path):
    disk = ('\n[[rotors.disks]]\nname = "d"\naxial_position = 0.25\nmass = 10.0\npolar_inertia = 0.05\n'
            'diametral_inertia = 0.03\nwidth = 0.5\n')
    path = tmp_path / "m.toml"
    path.write_text((BASE + "amount = 1e-4\n").replace("[[bearings]]", disk + "\n[[bearings]]", 1), encoding="utf-8")
    code, err = run_quietly(["check", str(path)])
    assert code == 0 and "wider" not in err


# ------------------------------------------------------------------ static: a speed-dependent bearing
def test_static_of_journals_without_a_speed_names_the_option():
    """``static`` of a rotor on journal bearings without ``--speed`` said 'give the operating
    speed', naming no option (the command's help calls it 'default: at rest')."""
    code, err = run_quietly(["static", str(EXAMPLES / "compressor_on_journals.toml"), "--quiet"])
    line = _one_line(err)
    assert code == 2 and "[bearings.NDE]: its stiffness depends on speed" in line and "--speed" in line


@pytest.mark.parametrize("extra, words", [
    (["--qa", "0"], "--qa '0': expected values > 0 [lbf/in]"),
    ([], "give --qa lbf/in, or --rated-power"),
])
def test_a_qa_refused_under_us_units_names_lbf_per_in(extra, words):
    """With --units us --qa is read in lbf/in (level1's and report's help), and its refusals
    said '[N/m]' and 'give --qa N/m'."""
    code, err = run_quietly(["level1", str(COMPRESSOR), "--mcs", "9000", "--station", "compressor", "--units", "us",
                             *extra])
    assert code == 2 and words in _one_line(err)


@pytest.mark.parametrize("model, station, words", [
    (COMPRESSOR, "compressor@500", ("OFFSET = 500 in", "OFFSET from -22.9632 to 24.2809 in")),
    (EXAMPLES / "fan_on_bearings.toml", "fan@500", ("OFFSET = 500 in", " in (its extent along spin_axis")),
])
def test_a_station_off_its_rotor_under_us_units_is_refused_in_inches(model, station, words):
    """``--units us --station compressor@500`` (500 in) was refused as 'OFFSET = 12.7 m: expected
    ... OFFSET from -0.583265 to 0.616735 m': neither the value typed nor the option's unit.
    The range in inches is the shaft's, from the file: the centre of mass 0.583265 m from the
    start of the 1.2 m shaft, 1 in = 0.0254 m."""
    code, err = run_quietly(["level1", str(model), "--mcs", "3000", "--station", station, "--qa", "1e3",
                             "--units", "us"])
    line = _one_line(err)
    assert code == 2 and all(w in line for w in words), line
    assert -0.583265 / 0.0254 == pytest.approx(-22.9632, abs=1e-4) and 0.616735 / 0.0254 == pytest.approx(24.2809, abs=1e-4)


def test_a_ross_table_with_its_speeds_under_another_key_names_that_key(tmp_path):
    """``speed_rpm = [...]`` for ``speed`` (difflib 0.71 from it, no near miss) was refused on
    ``mxx ... one per speed of [...] speed, which the table lacks`` without naming the key that
    held the speeds."""
    path = tmp_path / "speed_rpm.toml"
    path.write_text(ROSS.read_text(encoding="utf-8").replace("speed = [", "speed_rpm = [", 1), encoding="utf-8")
    code, err = run_quietly(["import-ross", str(path), "--out", str(tmp_path / "model.toml")])
    line = _one_line(err)
    assert code == 2 and "speed, which the table lacks (it has 'speed_rpm', not read here" in line


@pytest.mark.parametrize("units, shown", [("si", "-0.283265 m"), ("us", "-11.1522 in")])
def test_a_disk_given_as_the_stations_rotor_gets_the_station_to_type(units, shown):
    """``--station impeller-1`` (the impeller alone, as a rotor) said only 'no rotor
    'impeller-1': the model's rotors are compressor'. -11.1522 in = -0.283265 m / 0.0254."""
    code, err = run_quietly(["level1", str(COMPRESSOR), "--mcs", "9000", "--station", "impeller-1", "--qa", "1e5",
                             "--units", units])
    line = _one_line(err)
    assert code == 2 and "no rotor 'impeller-1'" in line
    assert f"disk 'impeller-1' of rotor 'compressor' is at OFFSET {shown} from its centre of mass" in line
    assert -0.283265 / 0.0254 == pytest.approx(-11.1522, abs=1e-4)
