"""The command line (../shared/spec/cli.md): help, exit codes, CSV columns, negative speeds,
speed units, atomic outputs, figures. In-process through ``main(argv)``, plus real runs."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import SUBCOMMANDS, main

COLUMNS = {
    "modes": ["mode", "frequency_hz", "damping_ratio", "log_decrement", "whirl"],
    "campbell": ["speed_rpm", "mode", "frequency_hz", "damping_ratio", "log_decrement", "whirl"],
    "critical-speeds": ["source", "order", "mode", "speed_rpm", "frequency_hz", "whirl"],
    "stability": ["speed_rpm", "value", "mode", "real_part", "damping_ratio", "log_decrement"],
}


@pytest.fixture
def gear(examples_dir, tmp_path):
    path = tmp_path / "gear.toml"
    shutil.copy(examples_dir / "gear_machine.toml", path)
    return path


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("name", [m.NAME for m in SUBCOMMANDS] + [None])
def test_help_of_every_subcommand(name, capsys):
    argv = ["--help"] if name is None else [name, "--help"]
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: rotordyn-modal")
    if name in COLUMNS:
        assert ",".join(COLUMNS[name]) in out.replace("\n", "")  # the help states the columns


def test_check_valid_model(gear, capsys):
    code, out, err = run(["check", gear], capsys)
    assert code == 0
    assert "valid model" in out and "fan" in out and "-0.4" in out
    assert "total mass 178 kg" in out                     # 150 + 20 + 8 kg in the file
    assert "note:" not in out                             # mounts restrain all six directions


def test_check_notes_a_direction_nothing_restrains(examples_dir, capsys):
    """The spring-block rotor (no stator) rolls freely about its axis: one zero eigenvalue."""
    code, out, err = run(["check", examples_dir / "spring_block_rotor_suspension.toml"], capsys)
    assert code == 0
    assert "note: the suspensions and bearings restrain 5 of 6 directions" in out


def test_check_lists_each_bearings_radial_stiffness_whatever_its_axial_one(examples_dir, tmp_path, capsys):
    """Radial means normal to the spin axis: a bearing twice as stiff axially as radially still
    reads its two radial stiffnesses (before, the larger two principal stiffnesses of its 3x3
    translational block were printed: the axial one among them)."""
    text = (examples_dir / "fan_on_bearings.toml").read_text()
    stiff = text.replace("axial_stiffness = 2.0e6", "axial_stiffness = 8.0e6")
    assert stiff != text
    path = tmp_path / "stiff_axially.toml"
    path.write_text(stiff)
    code, out, err = run(["check", path], capsys)
    assert code == 0, err
    line, = [line for line in out.splitlines() if line.strip().startswith("motor-DE")]
    assert line.endswith("radial stiffness [4000000. 4000000.] N/m")     # stiffness = 4.0e6
    fan, = [line for line in out.splitlines() if line.strip().startswith("fan-DE")]
    assert fan.endswith("radial stiffness [3000000. 4500000.] N/m")


@pytest.mark.parametrize("argv, fragment", [
    (["check", "{bad}"], "[rotors.fan] mass = -8.0: expected a finite number > 0"),
    (["check", "{missing}"], "no such file"),
    (["modes", "{gear}", "--speed", "fast"], "--speed 'fast': expected a number"),
    (["campbell", "{gear}", "--speeds", "0:100"], "expected START:STOP:N"),
    (["campbell", "{gear}", "--speeds", "100:0:5"], "STOP must be greater than START"),
    (["campbell", "{gear}", "--speeds", "100:100:5"], "STOP must be greater than START"),
    (["stability", "{gear}", "--speeds", "0:100:3", "--vary", "rotors.fan.nope", "--scale", "1,2"],
     "no value 'nope'"),
    (["stability", "{gear}", "--speeds", "0:100:3", "--vary", "rotors.fan.mass"], "--vary needs"),
    (["modes", "{gear}", "--plot", "{tmp}/x.bmp"], "expected a file ending in .png, .svg or .pdf"),
    (["modes", "{gear}", "--out", "{tmp}/no/such/dir/x.csv"], "does not exist"),
    (["modes", "{gear}", "--out", "{gear}"], "refusing to write over the input file"),
])
def test_bad_input_exit_2_one_message_no_traceback(argv, fragment, gear, tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(gear.read_text().replace("mass = 8.0", "mass = -8.0"))
    names = {"bad": bad, "missing": tmp_path / "missing.toml", "gear": gear, "tmp": tmp_path}
    before = gear.read_bytes()
    code, out, err = run([a.format(**names) for a in argv], capsys)
    assert code == 2
    assert fragment in err, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert gear.read_bytes() == before  # the input model is never overwritten
    assert not (tmp_path / "x.bmp").exists()


def test_usage_errors_exit_2(gear, capsys):
    with pytest.raises(SystemExit) as info:
        main(["campbell", str(gear)])  # --speeds is required
    assert info.value.code == 2
    assert "--speeds" in capsys.readouterr().err
    with pytest.raises(SystemExit) as info:
        main(["modes", str(gear), "--speed-unit", "furlong/s"])
    assert info.value.code == 2


def test_other_failure_exit_1(gear, capsys, monkeypatch):
    import rotordyn_modal.cli.modes as modes_cli

    def broken(*args, **kwargs):
        raise RuntimeError("LAPACK went away")

    monkeypatch.setattr(modes_cli, "modal", broken)
    code, out, err = run(["modes", gear], capsys)
    assert code == 1
    assert "LAPACK went away" in err and "Traceback" not in err


@pytest.mark.parametrize("name, extra", [
    ("modes", ["--speed", "3000"]),
    ("campbell", ["--speeds", "0:6000:7"]),
    ("critical-speeds", ["--speeds", "0:12000:61", "--orders", "1,2"]),
    ("stability", ["--speeds", "0:6000:4"]),
    ("stability", ["--speeds", "0:6000:4", "--vary", "suspensions.mount-FL.damping", "--scale", "0.5:2:3"]),
])
def test_csv_columns_in_spec_order(name, extra, gear, tmp_path, capsys):
    out = tmp_path / "table.csv"
    code, _, err = run([name, gear, *extra, "--out", out, "--quiet"], capsys)
    assert code == 0, err
    table = pd.read_csv(out)
    assert list(table.columns[: len(COLUMNS[name])]) == COLUMNS[name]
    assert len(table) > 0
    if name == "stability":
        assert ("--vary" in extra) == table["value"].notna().all()


def test_modes_csv_equals_python(gear, tmp_path, capsys):
    out = tmp_path / "m.csv"
    for argv in (["--speed", "-3000"], ["--speed=-3000"]):
        assert run(["modes", gear, *argv, "--out", out, "--quiet"], capsys)[0] == 0
        table = pd.read_csv(out)
        expected = rdm.modal(rdm.load_model(gear), rdm.rpm(-3000.0))
        np.testing.assert_allclose(table.frequency_hz, expected.frequencies_hz[expected.oscillatory], rtol=1e-9)
        assert list(table.whirl) == list(expected.whirl[expected.oscillatory])


@pytest.mark.parametrize("argv", [["--speeds", "-6000:6000:13"], ["--speeds=-6000:6000:13"]])
def test_negative_speed_ranges(argv, gear, tmp_path, capsys):
    out = tmp_path / "c.csv"
    code, _, err = run(["campbell", gear, *argv, "--out", out, "--quiet"], capsys)
    assert code == 0, err
    table = pd.read_csv(out)
    np.testing.assert_allclose(np.unique(table.speed_rpm), np.linspace(-6000, 6000, 13), atol=1e-6)
    reference = rdm.campbell(rdm.load_model(gear), rdm.rpm(np.linspace(-6000, 6000, 13)))
    np.testing.assert_allclose(table.frequency_hz, reference.to_dataframe().frequency_hz, rtol=1e-9)


@pytest.mark.parametrize("unit, factor", [("rad/s", 1.0), ("hz", 2 * np.pi), ("rpm", np.pi / 30)])
def test_speed_unit(unit, factor, gear, tmp_path, capsys):
    out = tmp_path / "m.csv"
    assert run(["modes", gear, "--speed", "50", "--speed-unit", unit, "--out", out, "--quiet"], capsys)[0] == 0
    expected = rdm.modal(rdm.load_model(gear), 50 * factor)
    np.testing.assert_allclose(pd.read_csv(out).frequency_hz, expected.frequencies_hz[expected.oscillatory],
                               rtol=1e-9)
    assert run(["campbell", gear, "--speeds", "-10:10:3", "--speed-unit", unit, "--out", out, "--quiet"],
               capsys)[0] == 0
    np.testing.assert_allclose(np.unique(pd.read_csv(out).speed_rpm), np.array([-10, 0, 10]) * factor * 30 / np.pi,
                               rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("suffix, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")])
def test_plots(suffix, magic, gear, tmp_path, capsys):
    for name, extra in (("campbell", ["--speeds", "0:6000:7"]), ("modes", ["--speed", "1000"]),
                        ("stability", ["--speeds", "0:6000:4"]),
                        ("critical-speeds", ["--speeds", "0:6000:13"]),
                        ("stability", ["--speeds", "0:6000:4", "--vary", "rotors.fan.polar_inertia",
                                       "--scale", "0.5,0.8,1"])):
        path = tmp_path / f"{name}-{len(extra)}{suffix}"
        code, _, err = run([name, gear, *extra, "--plot", path, "--quiet"], capsys)
        assert code == 0, err
        assert path.read_bytes().startswith(magic)
    assert not [p for p in os.listdir(tmp_path) if p.startswith(".")]  # no temporary files left


def test_a_failing_output_leaves_no_file(gear, tmp_path, capsys, monkeypatch):
    out = tmp_path / "table.csv"

    def half_written(self, handle, *args, **kwargs):
        handle.write("speed_rpm,mode\n1,")
        raise OSError("disk full")

    monkeypatch.setattr(pd.DataFrame, "to_csv", half_written)
    code, _, err = run(["campbell", gear, "--speeds", "0:1000:3", "--out", out, "--quiet"], capsys)
    assert code == 1 and "disk full" in err
    assert os.listdir(tmp_path) == ["gear.toml"]


def test_existing_output_replaced_whole(gear, tmp_path, capsys):
    out = tmp_path / "m.csv"
    out.write_text("old")
    assert run(["modes", gear, "--out", out, "--quiet"], capsys)[0] == 0
    assert out.read_text().startswith("mode,frequency_hz")


def test_out_dash_writes_csv_to_stdout(gear, capsys):
    code, out, _ = run(["modes", gear, "--out", "-"], capsys)
    assert code == 0 and out.startswith(",".join(COLUMNS["modes"]))


@pytest.mark.skipif(shutil.which("rotordyn-modal") is None, reason="console script not installed")
def test_real_subprocess_runs(gear, tmp_path):
    ok = subprocess.run(["rotordyn-modal", "critical-speeds", str(gear), "--speeds", "-6000:6000:25",
                         "--out", str(tmp_path / "c.csv")], capture_output=True, text=True, timeout=120)
    assert ok.returncode == 0, ok.stderr
    assert pd.read_csv(tmp_path / "c.csv").columns[0] == "source"
    broken = tmp_path / "broken.toml"
    broken.write_text("name = 'x'\n[stator]\nmass = 1.0\ninertia = [1.0, 1.0, 5.0]\n")
    bad = subprocess.run(["rotordyn-modal", "check", str(broken)], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2
    assert "triangle inequality" in bad.stderr and "Traceback" not in bad.stderr
    assert str(broken) in bad.stderr


def test_python_module_entry(gear):
    result = subprocess.run([sys.executable, "-c", "import sys; from rotordyn_modal.cli import main; "
                             f"sys.exit(main(['check', {str(gear)!r}]))"], capture_output=True, text=True,
                            timeout=60)
    assert result.returncode == 0


def test_progress_bar_only_on_a_terminal_and_not_quiet(gear, capsys, monkeypatch):
    argv = ["campbell", str(gear), "--speeds", "0:6000:9000", "--out", "-"]
    main(argv)
    assert "eigen-solve" not in capsys.readouterr().err  # not a terminal
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    main(argv)
    assert "eigen-solve" in capsys.readouterr().err
    main(argv + ["--quiet"])
    assert "eigen-solve" not in capsys.readouterr().err


def test_output_through_a_link_to_the_model_is_refused(gear, tmp_path, capsys):
    link = tmp_path / "link.csv"
    link.symlink_to(gear)
    hard = tmp_path / "hard.csv"
    os.link(gear, hard)
    before = gear.read_bytes()
    for target in (link, hard):
        code, _, err = run(["modes", gear, "--out", target, "--quiet"], capsys)
        assert code == 2 and "refusing to write over the input file" in err
    assert gear.read_bytes() == before


def test_save_model_never_overwrites_its_source(gear, tmp_path):
    model = rdm.load_model(gear)
    before = gear.read_bytes()
    with pytest.raises(rdm.InputError, match="refusing"):
        rdm.save_model(model, gear)
    with pytest.raises(rdm.InputError, match="refusing"):
        rdm.save_model(model, tmp_path / "other.toml", inputs=[tmp_path / "other.toml"])
    assert gear.read_bytes() == before
    rdm.save_model(model, tmp_path / "copy.toml")
    assert rdm.load_model(tmp_path / "copy.toml").to_dict() == {
        k: v for k, v in model.to_dict().items() if v not in ([], None, "")}


def test_stability_map_prints_each_values_threshold_in_rpm(examples_dir, tmp_path, capsys):
    """``stability --vary KEY --scale ...`` prints, per factor, every interval of speeds the Python
    map finds unstable (in rpm), or that the machine is stable over the range."""
    model_path = examples_dir / "unstable_cross_coupled.toml"
    code, out, err = run(["stability", model_path, "--speeds", "0:20000:41", "--vary",
                          "suspensions.bearing-A.damping", "--scale", "0.5,1,4", "--out", tmp_path / "s.csv"],
                         capsys)
    assert code == 0, err
    expected = rdm.stability_map(rdm.load_model(model_path), rdm.rpm(np.linspace(0, 20000, 41)),
                                 "suspensions.bearing-A.damping", scale=[0.5, 1.0, 4.0])
    lines = [line for line in err.splitlines() if line.startswith("suspensions.bearing-A.damping x ")]
    assert len(lines) == 3
    for line, factor, speed in zip(lines, (0.5, 1, 4), expected.threshold_speeds):
        text = "stable over the range" if np.isnan(speed) else f"unstable from {speed * 30 / np.pi:.6g} rpm"
        assert line.startswith(f"suspensions.bearing-A.damping x {factor:g}: {text}")
    assert "unstable from" in lines[0] and "stable over the range; least damped: mode" in lines[2]  # both kinds
    # at half the damping the machine is stable again between two intervals (an island): both shown
    (start, stop), (again, _) = expected.results[0].unstable_intervals
    assert lines[0].endswith(f"from {start * 30 / np.pi:.6g} rpm to {stop * 30 / np.pi:.6g} rpm "
                             f"and from {again * 30 / np.pi:.6g} rpm")


def test_python_dash_m_runs_the_command_line_without_a_warning(examples_dir):
    """``python -m rotordyn_modal`` is the ``rotordyn-modal`` command (no scripts folder on the
    PATH needed): same exit codes, and nothing on stderr but the command's own lines (running
    ``python -m rotordyn_modal.cli.main`` prints runpy's RuntimeWarning)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": str(root)}
    done = subprocess.run([sys.executable, "-m", "rotordyn_modal", "check", str(examples_dir / "gear_machine.toml")],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == 0 and "Warning" not in done.stderr, done.stderr
    assert "gear" in done.stdout.lower()
    bad = subprocess.run([sys.executable, "-m", "rotordyn_modal", "modes", str(examples_dir / "missing.toml")],
                         capture_output=True, text=True, env=env, timeout=120)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
