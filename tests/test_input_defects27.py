"""Input and file defects left on issues 27 (§1, §4, §5) and 28 (§5): a report option its
standard does not use, text files in UTF-16 without a byte-order mark, the model warnings a
refusal makes moot. Each case through the command line in this process (or one reader), before
any analysis: the file costs seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

from degenerate_models import EXTREME as _EXTREME, INSTRUMENTS, variant
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


# ----------------------------------------------------------------------- every sub-command on that model
def _measured(tmp_path) -> str:
    """An FRF file of the instrumented model with sane masses (what ``fit`` is given)."""
    sane = tmp_path / "sane.toml"
    sane.write_text(variant(stator_mass="100.0", rotor_mass="10.0"))
    out = tmp_path / "measured.csv"
    assert main(["frf", str(sane), "--freqs", "1:100:5", "--out", str(out), "--quiet"]) == 0
    return str(out)


def _study(tmp_path) -> str:
    spec = tmp_path / "tiny.study.toml"
    spec.write_text('seed = 1\nsamples = 2\ndesign = "latin-hypercube"\n[[parameters]]\n'
                    'key = "suspensions.s.stiffness"\napply = "scale"\ndistribution = "uniform"\nlow = 0.9\n'
                    'high = 1.1\n[analyses.campbell]\nspeeds_rpm = "0:1000:3"\norders = [1]\n')
    return str(spec)


#: each sub-command's arguments after the model ({tmp}: the test's folder)
_COMMANDS = {
    "check": [], "modes": ["--speed", "1000"], "campbell": ["--speeds", "0:1000:3"],
    "critical-speeds": ["--speeds", "0:1000:5"], "stability": ["--speeds", "0:1000:3"],
    "ucs-map": ["--stiffness", "1e5:1e9:5"], "level1": ["--mcs", "1000", "--station", "r", "--qa", "1e5"],
    "simulate": ["--duration", "0.01", "--speed", "1000"], "frf": ["--freqs", "1:100:5"],
    "frf --force-outputs": ["--freqs", "1:100:5", "--force-outputs", "all"],
    "unbalance": ["--speeds", "100:1000:5"],
    "report": ["--standard", "api684", "--mcs", "1000", "--out", "{tmp}/r.html"],
    "study": ["--spec", "{spec}", "--out", "{tmp}/s.nc"],
    "fit": ["--measured", "{measured}", "--params", "suspensions.s.stiffness", "--out", "{tmp}/f.toml"],
}


def _argv(tmp_path, command: str, model) -> list:
    words = {"tmp": str(tmp_path)}
    if command == "study":
        words["spec"] = _study(tmp_path)
    if command == "fit":
        words["measured"] = _measured(tmp_path)
    return [command.split()[0], str(model), *(a.format(**words) for a in _COMMANDS[command]), "--quiet"]


@pytest.mark.parametrize("command", ["ucs-map", "unbalance", "fit", "study", "frf --force-outputs"])
def test_every_command_refuses_that_model_with_the_line_of_modes(tmp_path, capsys, command):
    """``ucs-map`` skipped the mass check and failed in its Cholesky factorisation ('failed:
    LinAlgError: Matrix is not positive definite', exit 1); ``unbalance``, ``fit`` and ``frf
    --force-outputs`` (direct solves, no state matrix) failed with 'LinAlgError: Singular matrix';
    ``study`` refused it with the sag warning above (two lines). Now each says the line ``modes``
    says (``study`` within its own: the analyses of its file), exit 2, and writes nothing."""
    model = tmp_path / "extreme.toml"
    model.write_text(_EXTREME + INSTRUMENTS)
    argv = _argv(tmp_path, command, model)
    assert main(["modes", str(model), "--speed", "1000", "--quiet"]) == 2
    refusal = _one_line_error(capsys, "mass matrix invertible")
    assert main(argv) == 2
    name, said = command.split()[0], _one_line_error(capsys)
    if name == "study":     # the study file names the analyses the model cannot run, and why
        assert said.startswith(f"rotordyn-modal study: error: {argv[3]}: [analyses]") and \
            said.endswith(f"({refusal.split(': error: ', 1)[1]})"), said
    else:
        assert said == refusal.replace("modes", name, 1)
    assert not [p.name for p in tmp_path.iterdir() if p.suffix in (".html", ".nc")] and \
        not (tmp_path / "f.toml").exists()


def test_a_stator_of_no_mass_under_a_rotor_is_refused_by_ucs_map_as_by_modes(tmp_path, capsys):
    """A stator of 1e-30 kg under a rotor of 10 kg (no warning): the rotor's mass in the
    stator's rows leaves the stator's own lost, and ``ucs-map`` ended in 'failed: LinAlgError'
    (exit 1) where every analysis refuses the model."""
    model = tmp_path / "light_stator.toml"
    model.write_text(variant(rotor_mass="10.0"))
    assert main(["modes", str(model), "--speed", "1000", "--quiet"]) == 2
    refusal = _one_line_error(capsys, "mass matrix invertible")
    assert main(_argv(tmp_path, "ucs-map", model)) == 2
    assert _one_line_error(capsys) == refusal.replace("modes", "ucs-map", 1)


def test_the_python_ucs_map_refuses_that_model_with_the_model_error(tmp_path):
    """The check is made by the analysis itself, not by the command line."""
    import numpy as np

    import rotordyn_modal as rdm
    from rotordyn_modal.errors import ModelError, ModelWarning

    model = tmp_path / "extreme.toml"
    model.write_text(_EXTREME)
    with pytest.warns(ModelWarning):
        machine = rdm.load_model(model)
    with pytest.raises(ModelError, match="mass matrix invertible"):
        rdm.ucs_map(machine, np.geomspace(1e5, 1e9, 5))


#: degenerate models of the same family that a model check refuses when read: (changes, words)
_FAMILY = {
    "rotor-of-no-mass-on-stiff-bearings": ({"stator_mass": "100.0", "rotor_mass": "1e-30", "bearing": "1e12",
                                             "unbalance": "1e-16"},
                                           ["[bearings.a] stiffness", "1e+12"]),
    "casing-without-inertia-about-z": ({"stator_mass": "100.0", "rotor_mass": "10.0",
                                        "stator_inertia": "[10.0, 10.0, 1e-40]"}, ["[stator] inertia", "1e-40"]),
    "rigid-bearings-on-soft-mounts": ({"stator_mass": "100.0", "rotor_mass": "10.0", "bearing": "1e30",
                                       "mount": "[1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3]"},
                                      ["[bearings.a] stiffness", "1e+30"]),
}


@pytest.mark.parametrize("case", list(_FAMILY))
def test_degenerate_models_read_as_one_line_in_every_command(tmp_path, capsys, case):
    """A guard (these pass on main): each model is refused when read, by every sub-command, in
    the one line ``check`` gives."""
    changes, words = _FAMILY[case]
    model = tmp_path / f"{case}.toml"
    model.write_text(variant(**changes))
    assert main(["check", str(model)]) == 2
    refusal = _one_line_error(capsys, str(model), *words)
    for command in _COMMANDS:
        assert main(_argv(tmp_path, command, model)) == 2, command
        assert _one_line_error(capsys) == refusal.replace("check", command.split()[0], 1), command


def test_an_unbalance_response_singular_at_round_off_is_one_line_naming_where(tmp_path, capsys):
    """A rotor of 1e-30 kg with Jp = Jd on bearings of 4e-13 N/m (legal, with the warning that the
    low modes lose 15 of 16 digits): at a synchronous frequency its tilt block
    ``[[k - w^2 Jd, w^2 Jp], [w^2 Jp, k - w^2 Jd]]`` has the determinant ``k (k - 2 w^2 Jd)``,
    zero to round-off, and the direct solve ended in 'failed: LinAlgError: Singular matrix'
    (exit 1). Now one refusal names the frequency and speed: an unbalance's, so f = rpm / 60."""
    import re

    model = tmp_path / "light_rotor.toml"
    model.write_text(variant(stator_mass="100.0", stator_inertia="[10.0, 10.0, 10.0]", rotor_mass="1e-30",
                             bearing="4e-13", unbalance="1e-16"))
    assert main(_argv(tmp_path, "unbalance", model)) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and ": warning: " in err[0] and "lose about 15 of 16" in err[0], err
    found = re.search(r"singular in double precision at ([0-9.e+]+) Hz, reference speed ([0-9.e+]+) rpm", err[1])
    assert err[1].startswith("rotordyn-modal unbalance: error: ") and found, err
    assert float(found[1]) == pytest.approx(float(found[2]) / 60, rel=1e-5)


def test_an_frf_of_that_model_with_a_loss_factor_is_refused_not_made_up(tmp_path, capsys):
    """With a loss factor on its mount the FRF takes the direct engine, which made no mass check:
    exit 0 and numbers solved from a mass matrix rounding had left singular (about 1e-4 m/N at
    90 degrees from 50 to 100 Hz: ten times the mount's own static compliance, 1e-5 m/N, though
    bearings of 1e6 N/m to a rotor of 1e30 kg hold the stator too). Now the line of ``modes``."""
    model = tmp_path / "lossy.toml"
    model.write_text(variant(mount="[1e5, 1e5, 1e5, 1e3, 1e3, 1e3]\nloss_factor = 0.1"))
    assert main(["modes", str(model), "--speed", "1000", "--quiet"]) == 2
    refusal = _one_line_error(capsys, "mass matrix invertible")
    out = tmp_path / "frf.csv"
    assert main(["frf", str(model), "--freqs", "1:100:3", "--out", str(out), "--quiet"]) == 2
    assert _one_line_error(capsys) == refusal.replace("modes", "frf", 1) and not out.exists()


def test_an_api_unbalance_case_of_a_rotor_of_no_mass_names_the_rotors_mass(tmp_path, capsys):
    """API 684's unbalance of a 1e-30 kg rotor at 1000 rpm, 2 x 6350 g mm x m [kg] / N [rpm],
    is 1.27e-35 kg m: below what a model holds, and the report refused it as '[unbalances[0]]
    amount = 1.27e-35', an amount the file does not have (its unbalance is 1e-16 kg m). Now the
    line names the rotor's mass, the speed and the case's amount."""
    model = tmp_path / "light_rotor.toml"
    model.write_text(variant(stator_mass="100.0", stator_inertia="[10.0, 10.0, 10.0]", rotor_mass="1e-30",
                             bearing="4e-13", unbalance="1e-16"))
    out = tmp_path / "r.html"
    assert main(["report", str(model), "--standard", "api684", "--mcs", "1000", "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    amount = 2 * 6350 * 1e-30 / 1000 * 1e-6        # g mm -> kg m
    assert len(err) == 2 and ": warning: " in err[0] and not out.exists(), err
    assert "[rotors.r] mass = 1e-30" in err[1] and "1000 rpm" in err[1] and f"{amount:.3g} kg m" in err[1], err
    assert "[unbalances" not in err[1]
