"""Input and file defects left on issues 27 (§1, §4, §5) and 28 (§5): a report option its
standard does not use, text files in UTF-16 without a byte-order mark, the model warnings a
refusal makes moot. Each case through the command line in this process (or one reader), before
any analysis: the file costs seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotordyn_modal.cli import main
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
FAN = str(ROOT / "examples" / "fan_on_bearings.toml")
PUMP = str(ROOT / "examples" / "motor_pump_on_mounts.toml")


# ----------------------------------------------------------------------- report --stiffness
def test_an_iso_report_refuses_the_stiffness_of_a_map_it_does_not_draw(tmp_path, capsys):
    """``--standard iso --stiffness ...`` was accepted (exit 0) and dropped without a word: the
    ISO report has no undamped critical speed map (docs/report.md's table), as ``--iso-group``
    is refused in an API report."""
    out = tmp_path / "r.html"
    assert main(["report", PUMP, "--standard", "iso", "--mcs", "3000", "--iso-group", "2", "--iso-support",
                 "flexible", "--stiffness", "1e5:1e10:9", "--out", str(out)]) == 2
    _one_line_error(capsys, "--stiffness 1e5:1e10:9", "--standard iso", "undamped critical speed map", "api684")
    assert not out.exists()


# ----------------------------------------------------------------------- UTF-16 without a byte-order mark
GEAR = ROOT / "examples" / "gear_machine.toml"
NO_MARK = ["utf-16-le", "utf-16-be"]


def _wide(path: Path, text: str, encoding: str) -> Path:
    """``text`` written to ``path`` in ``encoding`` (no byte-order mark: 'utf-16-le' writes none)."""
    path.write_bytes(text.encode(encoding))
    assert not path.read_bytes().startswith((b"\xff\xfe", b"\xfe\xff"))
    return path


@pytest.mark.parametrize("encoding", NO_MARK)
def test_a_model_file_in_utf16_without_a_mark_reads_as_its_utf8_text(tmp_path, capsys, encoding):
    """Read as UTF-8 it was 'Invalid statement (line 1, column 1)' or a NUL-laden key: what
    some Windows programs write. The model is the one its UTF-8 text
    gives, key for key, and the command line runs on it."""
    import rotordyn_modal as rdm

    text = (ROOT / "examples" / "fan_on_bearings.toml").read_text(encoding="utf-8")
    utf8, wide = tmp_path / "utf8.toml", _wide(tmp_path / "wide.toml", text, encoding)
    utf8.write_text(text, encoding="utf-8")
    assert rdm.load_model(wide).to_dict() == rdm.load_model(utf8).to_dict()
    assert main(["modes", str(wide), "--speed", "1000"]) == 0
    from_wide = capsys.readouterr().out
    assert main(["modes", str(utf8), "--speed", "1000"]) == 0
    assert from_wide == capsys.readouterr().out and from_wide


def test_a_ross_file_in_utf16_without_a_mark_reads_as_its_utf8_text(tmp_path):
    """The ROSS reader reads TOML through the same function as the model file."""
    from rotordyn_modal.io.ross_file import read_ross_rotor

    source = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"
    wide = _wide(tmp_path / "rotor_example.toml", source.read_text(encoding="utf-8"), "utf-16-le")
    assert read_ross_rotor(wide) == read_ross_rotor(source)


@pytest.mark.parametrize("encoding", NO_MARK)
def test_a_measured_csv_in_utf16_without_a_mark_reads_as_its_utf8_text(tmp_path, encoding):
    """Read as UTF-8 (every other byte a NUL) its header named no column."""
    import numpy as np

    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import read_measured, write_csv

    model = rdm.load_model(GEAR)
    exact = rdm.frf(model, rdm.rpm(1200), np.linspace(2, 40, 5), quantity="accelerance")
    utf8 = tmp_path / "utf8.csv"
    write_csv([exact], utf8)
    wide = _wide(tmp_path / "wide.csv", utf8.read_text(encoding="utf-8").replace(",", "\t"), encoding)
    [back], [same] = read_measured(wide, model), read_measured(utf8, model)
    assert back.outputs == same.outputs and back.inputs == same.inputs and back.quantity == same.quantity
    np.testing.assert_array_equal(back.H, same.H)
    np.testing.assert_allclose(back.H, exact.H, rtol=1e-12)


@pytest.mark.parametrize("encoding", NO_MARK)
def test_a_mapping_table_in_utf16_without_a_mark_reads_as_its_utf8_text(tmp_path, encoding):
    import rotordyn_modal as rdm
    from rotordyn_modal.io.channels import read_mapping

    model = rdm.load_model(GEAR)
    text = "Name;Node;Direction;Sign\nacc-top-z;7;3;1\nhammer-z;12;-3;-1\n"
    utf8 = tmp_path / "map8.csv"
    utf8.write_text(text, encoding="utf-8")
    back, same = read_mapping(_wide(tmp_path / "map.csv", text, encoding), model), read_mapping(utf8, model)
    assert (back.outputs, back.inputs) == (same.outputs, same.inputs)
    assert back.outputs == {(7, 3): ("acc-top-z", 1.0)} and back.inputs == {(12, -3): ("hammer-z", -1.0)}


@pytest.mark.parametrize("encoding", NO_MARK)
def test_an_outline_in_utf16_without_a_mark_reads_as_its_utf8_text(tmp_path, encoding):
    import numpy as np

    from rotordyn_modal.io.outline import read_outline

    text = "# Gehäuse – Umriss\nX [mm]\tY [mm]\tZ [mm]\n0\t0\t0\n100\t0\t0\n\n0\t50\t0\n0\t50\t200\n"
    utf8 = tmp_path / "o8.csv"
    utf8.write_text(text, encoding="utf-8")
    back = read_outline(_wide(tmp_path / "o.csv", text, encoding))
    np.testing.assert_array_equal(back, read_outline(utf8))
    np.testing.assert_allclose(back[1], [0.1, 0.0, 0.0], rtol=1e-15)


@pytest.mark.parametrize("kind", ["model", "csv"])
def test_utf16_without_a_mark_that_is_no_utf16_is_one_line(tmp_path, capsys, kind):
    """Its last byte cut off (an odd count of bytes): refused on one line saying what it looks
    like, not read as Latin-1 garbage or TOML's 'Invalid statement'."""
    if kind == "model":
        text = (ROOT / "examples" / "fan_on_bearings.toml").read_text(encoding="utf-8")
        path = tmp_path / "cut.toml"
        path.write_bytes(text.encode("utf-16-le")[:-1])
        argv = ["check", str(path)]
    else:
        path = tmp_path / "cut.csv"
        path.write_bytes("x,y,z\n0,0,0\n1,0,0\n".encode("utf-16-le")[:-1])
        argv = ["modes", str(GEAR), "--speed", "100", "--shape", "1", "--plot", str(tmp_path / "s.png"),
                "--outline", str(path), "--quiet"]
    assert main(argv) == 2
    _one_line_error(capsys, str(path), "UTF-16", "without a byte-order mark")


@pytest.mark.parametrize("encoding", ["utf-16-le", "utf-16-be", "utf-16"])
def test_a_universal_file_in_utf16_is_refused_on_one_line(tmp_path, capsys, encoding):
    """pyuff reads ASCII: such a file was taken for binary 58b sets and failed inside pyuff."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import default_mapping
    from rotordyn_modal.io.uff import write_uff58
    import numpy as np

    model = rdm.load_model(GEAR)
    ascii_file = tmp_path / "a.uff"
    write_uff58([rdm.frf(model, 0.0, np.linspace(2, 40, 5))], ascii_file, default_mapping(model))
    wide = tmp_path / "w.uff"
    wide.write_bytes(ascii_file.read_text(encoding="latin-1").encode(encoding))
    assert main(["frf", str(GEAR), "--freqs", "2:40:5", "--measured", str(wide), "--plot",
                 str(tmp_path / "f.png"), "--quiet"]) == 2
    _one_line_error(capsys, str(wide), "UTF-16", "expected ASCII")


# ----------------------------------------------------------------------- ROSS rotors on one bearing
ROSS = ROOT / "tests" / "data" / "ross"


def _ross_variant(tmp_path, case: str) -> Path:
    """ROSS's rotor_example (bearings at nodes 0 and 6) with its bearings changed: ``one`` (Bearing
    1 removed), ``one-node`` (Bearing 1 moved to node 0), ``none``. ROSS 3.1 builds and solves
    each (``Rotor(shaft, disks, bearings)`` then ``run_modal``; its modes leave the rigid-body
    roots at zero frequency out)."""
    import tomllib

    import tomli_w

    data = tomllib.loads((ROSS / "rotor_example.toml").read_text(encoding="utf-8"))
    if case == "one":
        del data["BearingElement_Bearing 1"]
    elif case == "one-node":
        data["BearingElement_Bearing 1"]["n"] = 0
    else:
        del data["BearingElement_Bearing 0"], data["BearingElement_Bearing 1"]
    path = tmp_path / f"{case}.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    return path


@pytest.mark.parametrize("case", ["one", "one-node", "none"])
def test_a_ross_rotor_on_bearings_at_fewer_than_two_nodes_is_refused_in_rosss_words(tmp_path, capsys, case):
    """Free to tilt (ROSS's bearings hold translations only) or free-free: no model of this
    package. The refusal named the model file's ``moment_stiffness`` (which a ROSS file cannot
    give) or said 'a flexible rotor needs bearings ... give it no shaft'; it now names the
    ROSS elements and what to do in ROSS, and writes nothing."""
    path, out = _ross_variant(tmp_path, case), tmp_path / "m.toml"
    assert main(["import-ross", str(path), "--out", str(out)]) == 2
    err = _one_line_error(capsys, str(path), "BearingElement or SealElement at two nodes or more",
                          "free-free" if case == "none" else "free to tilt")
    assert "in the model file it makes" not in err
    assert not out.exists()


def test_a_ross_rotor_on_one_bearing_given_a_moment_stiffness_in_python_is_a_model(tmp_path):
    """What the refusal offers: read in Python, the one bearing given a moment stiffness, the
    rotor is held (its bending modes on that support; the bearing's translation stiffness as
    ROSS's file gives it)."""
    import numpy as np

    import rotordyn_modal as rdm
    from rotordyn_modal.io.ross_file import read_ross_rotor

    description = read_ross_rotor(_ross_variant(tmp_path, "one"))
    [bearing] = description["bearings"]
    assert bearing["stiffness"] == [1e6, 8e5]
    bearing["moment_stiffness"] = 1e5
    model = rdm.Model.from_dict(description)
    roots = rdm.modal(model, 0.0).eigenvalues
    assert np.all(np.abs(np.asarray(roots).real) <= 1e-9 * np.abs(roots)) and np.min(np.abs(roots)) > 1.0


# ----------------------------------------------------------------------- the flexible pump's belt
FLEXIBLE_PUMP = ROOT / "examples" / "flexible_pump_on_mounts.toml"


def test_the_flexible_pumps_belt_passes_a_power_at_its_pulley_without_a_warning(capsys):
    """``static --speed 3000 --transmitted-power 5000`` on the example: refused for a missing
    ``driver_radius``, and with one the belt acted at the motor's centre of mass, off the pump's
    shaft (a warning). The pull is torque / driver radius, P / (w r) with w = 3000 rpm, in the
    plane of the pump's pulley (start x = -0.50 m plus its axial position 0.42 m)."""
    import math

    assert main(["static", str(FLEXIBLE_PUMP), "--speed", "3000", "--transmitted-power", "5000"]) == 0
    assert capsys.readouterr().err == ""
    import rotordyn_modal as rdm

    result = rdm.static(rdm.load_model(FLEXIBLE_PUMP), speed=rdm.rpm(3000), power=5000.0)
    belt = [load for load in result.loads if load.kind == "belt"]
    assert {load.body for load in belt} == {"motor", "pump"}
    pull = 5000.0 / (3000 * math.pi / 30) / 0.10
    for load in belt:
        assert load.point[0] == pytest.approx(-0.50 + 0.42, abs=1e-15)
        assert math.hypot(*load.force) == pytest.approx(pull, rel=1e-12)


def test_the_flexible_pumps_belt_position_changes_no_matrix(tmp_path):
    """The belt's ``position`` and ``driver_radius`` serve the static loads only: the model's
    M, C, G, K, bit for bit, are those of the file without them (modes, campbell, unbalance and
    frf read nothing else of a belt)."""
    import numpy as np

    import rotordyn_modal as rdm

    text = FLEXIBLE_PUMP.read_text(encoding="utf-8")
    lines = [line for line in text.splitlines(keepends=True)
             if not line.startswith(("position = [-0.08", "driver_radius = 0.10"))]
    assert len(lines) == len(text.splitlines()) - 2
    bare = tmp_path / "bare.toml"
    bare.write_text("".join(lines), encoding="utf-8")
    given, without = rdm.load_model(FLEXIBLE_PUMP).matrices(), rdm.load_model(bare).matrices()
    for name in "MCGK":
        a, b = getattr(given, name), getattr(without, name)
        a, b = (a.toarray(), b.toarray()) if hasattr(a, "toarray") else (a, b)
        assert np.array_equal(a, b), name


# ----------------------------------------------------------------------- a refusal without moot warnings
_EXTREME = """gravity = [0.0, 0.0, -9.81]
[stator]
mass = 1e-30
inertia = [1.0, 1.0, 1.0]
[[rotors]]
name = "r"
mass = 1e30
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.05
[[bearings]]
name = "a"
rotor = "r"
position = [0.2, 0.0, 0.0]
stiffness = 1e6
[[bearings]]
name = "b"
rotor = "r"
position = [-0.2, 0.0, 0.0]
stiffness = 1e6
[[suspensions]]
name = "s"
position = [0.0, 0.0, 0.0]
stiffness = [1e5, 1e5, 1e5, 1e3, 1e3, 1e3]
"""


@pytest.mark.parametrize("argv", [["check"], ["modes", "--speed", "1000"], ["campbell", "--speeds", "0:1000:3"],
                                  ["stability", "--speeds", "0:1000:3"], ["simulate", "--duration", "0.01"]],
                         ids=["check", "modes", "campbell", "stability", "simulate"])
def test_a_model_every_analysis_refuses_reads_as_one_line(tmp_path, capsys, argv):
    """A stator of 1e-30 kg under a rotor of 1e30 kg on bearings: its mass matrix is singular in
    double precision, and every analysis refuses it; the refusal was preceded by a true but moot
    line (the machine would sag 9.8e25 m under gravity): two lines on stderr."""
    model = tmp_path / "extreme.toml"
    model.write_text(_EXTREME)
    assert main([argv[0], str(model), *argv[1:]]) == 2
    err = _one_line_error(capsys, str(model), "mass matrix invertible")
    assert "sag" not in err


def test_a_command_that_needs_no_mass_matrix_still_says_the_warning(tmp_path, capsys):
    """``static`` solves K x = f without the mass matrix: it runs on that model, and the sag
    warning, true and not moot there, is said."""
    model = tmp_path / "extreme.toml"
    model.write_text(_EXTREME)
    assert main(["static", str(model), "--quiet"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ": warning: " in err[0] and "sag 9.81e+25 m" in err[0], err


def test_a_warning_of_a_model_the_analyses_take_comes_before_the_work(tmp_path, capsys, monkeypatch):
    """The warnings of a model whose mass matrix is fine are said at once, before the analysis
    runs (a long sweep does not hold them back to its end)."""
    import rotordyn_modal.analysis.modal as modal

    model = tmp_path / "heavy.toml"
    model.write_text(_EXTREME.replace("mass = 1e-30", "mass = 10.0").replace("mass = 1e30", "mass = 1e5"))
    before, analysis = [], modal.modal

    def watched(*args, **kwargs):       # stderr as the analysis starts
        before.append(capsys.readouterr().err)
        return analysis(*args, **kwargs)

    monkeypatch.setattr(modal, "modal", watched)
    assert main(["modes", str(model), "--speed", "1000", "--quiet"]) == 0
    assert before and ": warning: " in before[0] and "would sag" in before[0], before
