"""A ninth round of inputs of the families a reviewer tries (after ``test_input_families.py`` to
``test_input_families8.py``): every file-valued option given a named pipe (FIFO) that no program
writes to or reads from, and the surfaces of flexible rotors, ROSS files, ``static``,
``ucs-map``, ``level1`` and ``report`` tried at the edges. Each case through the command line in
this process or through the Python API; every refusal comes before the work or after a short
wait, so the file costs seconds."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from rotordyn_modal.cli import main
from test_input_families import _one_line_error

ROOT = Path(__file__).resolve().parent.parent
FAN = str(ROOT / "examples" / "fan_on_bearings.toml")
ROSS = ROOT / "tests" / "data" / "ross"


# ----------------------------------------------------------------------- named pipes nothing writes or reads
def _main_or_hang(argv, fifo: Path, reading: bool) -> int | None:
    """``main(argv)`` in a thread; None when it still waits after 20 s (it is then released by
    opening the pipe's other end, so no thread stays blocked)."""
    result = []

    def run():
        try:
            result.append(main(argv))
        except SystemExit as exit_:   # 'study' exits
            result.append(exit_.code)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(timeout=20)
    if worker.is_alive():
        fd = os.open(fifo, (os.O_WRONLY if reading else os.O_RDONLY) | os.O_NONBLOCK)
        os.close(fd)
        worker.join(timeout=20)
        return None
    return result[0]


@pytest.mark.parametrize("argv, what", [
    (["check", "{fifo}"], "model file"),
    (["modes", FAN, "--speed", "0", "--shape", "1", "--plot", "{out}.png", "--outline", "{fifo}"], "stator outline"),
    (["study", FAN, "--spec", "{fifo}", "--out", "{out}.nc"], "study file"),
    (["import-ross", "{fifo}", "--out", "{out}.toml"], "ROSS rotor file"),
], ids=["model", "outline", "spec", "ross"])
def test_an_input_pipe_nothing_writes_to_is_refused_after_a_wait(tmp_path, capsys, monkeypatch, argv, what):
    """``check fifo.toml`` of a FIFO no program writes to waited forever in ``open`` (a hang
    with no word); a pipe is read (``<(cat m.toml)``, a writer started just after), so it is
    waited for a while, then refused in one line."""
    monkeypatch.setattr("rotordyn_modal.io.limits.PIPE_WAIT_S", 0.3)
    fifo = tmp_path / "fifo.input"
    os.mkfifo(fifo)
    out = tmp_path / "out"
    argv = [a.format(fifo=fifo, out=out) for a in argv]
    assert _main_or_hang(argv, fifo, reading=True) == 2
    _one_line_error(capsys, str(fifo), "nothing writes to", what)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fifo.input"]


def test_an_input_pipe_written_just_after_is_read_whole(tmp_path, capsys):
    fifo = tmp_path / "late.toml"
    os.mkfifo(fifo)

    def write():
        import time

        time.sleep(0.5)
        with open(fifo, "w") as handle:
            handle.write(Path(FAN).read_text())

    writer = threading.Thread(target=write)
    writer.start()
    assert main(["check", str(fifo)]) == 0
    writer.join(timeout=10)
    assert "valid model" in capsys.readouterr().out


@pytest.mark.parametrize("argv, name", [
    (["static", FAN, "--out", "{fifo}"], "fifo.csv"),
    (["import-ross", str(ROSS / "rotor_example.toml"), "--out", "{fifo}"], "fifo.toml"),
], ids=["static-out", "import-ross-out"])
def test_an_output_pipe_nothing_reads_is_refused_after_a_wait(tmp_path, capsys, monkeypatch, argv, name):
    """``static m.toml --out fifo.csv`` into a FIFO no program reads waited forever in
    ``open``; ``--out >(gzip > c.gz)`` is written, so it is waited for a while, then refused."""
    monkeypatch.setattr("rotordyn_modal.io.limits.PIPE_WAIT_S", 0.3)
    fifo = tmp_path / name
    os.mkfifo(fifo)
    code = _main_or_hang([a.format(fifo=fifo) for a in argv], fifo, reading=False)
    assert code == 2
    _one_line_error(capsys, str(fifo), "nothing reads from", "nothing was written")


# ----------------------------------------------------------------------- a Maxwell branch far faster than the modes
def _rubber(tmp_path, times: str, slow_only: bool = False) -> Path:
    """``rubber_mounts.toml`` with other relaxation times of its mounts' two Maxwell branches, or
    (``slow_only``) with the first branch alone."""
    text = (ROOT / "examples" / "rubber_mounts.toml").read_text()
    old_k = "maxwell_stiffness = [[6.0e4, 4.5e4, 1.2e5], [3.0e4, 2.0e4, 6.0e4]]"
    assert "maxwell_time = [0.02, 0.002]" in text and old_k in text
    if slow_only:
        text = text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02]").replace(
            old_k, "maxwell_stiffness = [[6.0e4, 4.5e4, 1.2e5]]")
    else:
        text = text.replace("maxwell_time = [0.02, 0.002]", f"maxwell_time = {times}")
    path = tmp_path / f"rubber{len(list(tmp_path.iterdir()))}.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("tau", ["1e-14", "1e-15", "1e-20"])
def test_a_maxwell_branch_too_fast_for_double_precision_is_refused(tmp_path, capsys, tau):
    """A branch of 1e-14 s relaxes at once: at the mount modes it is a damper of 5e-10 N s/m, so the
    six modes are those without it (the first branch alone). ``modes`` put them 17 % off (1e-14 s),
    listed four of six (1e-15 s) or none (1e-20 s), exit 0 without a word."""
    path = _rubber(tmp_path, f"[0.02, {tau}]")
    assert main(["modes", str(path), "--speed", "1000"]) == 2
    _one_line_error(capsys, "[suspensions.mount-FL] maxwell_time[1]", f"'{tau}'", "acts only as a damper")
    import rotordyn_modal as rdm

    with pytest.raises(rdm.InputError, match=r"maxwell_time\[1\]"):
        rdm.load_model(path)


def test_a_fast_maxwell_branch_kept_is_named_and_its_modes_are_the_slow_branchs(tmp_path, capsys):
    """A branch of 1e-10 s is kept, with a warning of the digits it costs; the mount modes are those
    of the mounts without it to 1e-5 (7e-7 measured)."""
    import warnings

    import numpy as np

    import rotordyn_modal as rdm

    path = _rubber(tmp_path, "[0.02, 1e-10]")
    assert main(["check", str(path)]) == 0
    [line] = [x for x in capsys.readouterr().err.splitlines() if "warning" in x]
    assert "maxwell_time[1] = 1e-10" in line and "lose about 8 of 16" in line and "(and 3 other branches)" in line
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fast = rdm.modal(rdm.load_model(path), rdm.rpm(1000))
    slow = rdm.modal(rdm.load_model(_rubber(tmp_path, "", slow_only=True)), rdm.rpm(1000))
    assert fast.oscillatory.sum() == slow.oscillatory.sum() == 6
    np.testing.assert_allclose(np.sort(fast.frequencies_hz[fast.oscillatory]),
                               np.sort(slow.frequencies_hz[slow.oscillatory]), rtol=1e-5)


# ----------------------------------------------------------------------- a Level I station given twice
@pytest.mark.parametrize("first, second", [("compressor@0.3", "compressor@0.3"), ("compressor", "compressor@0")],
                         ids=["same-offset", "centre-and-zero"])
def test_a_level1_station_given_twice_is_refused(capsys, first, second):
    """``--station c@0.3 --station c@0.3 --qa 1e5,1e5`` ran (both shares at one node: one station
    of 2e5 N/m), the second stage's place mistyped without a word."""
    compressor = str(ROOT / "examples" / "compressor_rotor.toml")
    argv = ["level1", compressor, "--mcs", "9000", "--station", first, "--station", second, "--qa", "1e5,1e5", "--quiet"]
    assert main(argv) == 2
    _one_line_error(capsys, f"station {first}", "given twice", "stations 1 and 2")


# ----------------------------------------------------------------------- ucs_map's speeds and stiffness
@pytest.fixture
def speed_tables(tmp_path) -> Path:
    """ROSS's rotor of two bearings with coefficient tables over 0 to 1600 rad/s, as a model file."""
    out = tmp_path / "speed_tables_model.toml"
    assert main(["import-ross", str(ROSS / "speed_tables.toml"), "--out", str(out), "--quiet"]) == 0
    return out


@pytest.mark.parametrize("speeds, words", [
    ([float("nan")], "finite numbers"), ([], "non-empty"), ([[100.0]], "1-D"), ("fast", "non-empty"),
    ([-300.0, 0.0], "at least one speed > 0"),
], ids=["nan", "empty", "2-d", "text", "none-positive"])
def test_ucs_map_refuses_speeds_that_draw_no_curve(speed_tables, speeds, words):
    """``speeds=[nan]``, ``[]`` or ``[-300, 0]`` drew the tabulated bearings' curves empty, without a
    word (``'fast'`` raised numpy's ValueError)."""
    import rotordyn_modal as rdm

    model = rdm.load_model(speed_tables)
    with pytest.raises(rdm.InputError, match="speeds") as error:
        rdm.ucs_map(model, [1e6, 1e7, 1e8], speeds=speeds)
    assert words in str(error.value) and len(str(error.value).splitlines()) == 1


def test_ucs_map_refuses_a_stiffness_given_as_the_command_lines_text():
    import rotordyn_modal as rdm

    model = rdm.load_model(FAN)
    with pytest.raises(rdm.InputError, match=r"stiffness = '1e6:1e8:3': expected an array"):
        rdm.ucs_map(model, "1e6:1e8:3")


def test_ucs_map_speeds_of_no_positive_speed_is_refused_by_the_option(speed_tables, tmp_path, capsys):
    """``ucs-map --speeds 0:0:1 --plot u.png`` failed with numpy's 'zero-size array to reduction
    operation' (exit 1)."""
    capsys.readouterr()
    argv = ["ucs-map", str(speed_tables), "--stiffness", "1e5:1e9:5", "--speeds", "0:0:1", "--plot", str(tmp_path / "u.png")]
    assert main(argv) == 2
    _one_line_error(capsys, "--speeds '0:0:1'", "expected a speed > 0 [rpm]")
    assert not (tmp_path / "u.png").exists()


# ----------------------------------------------------------------------- level1's arguments in Python
@pytest.fixture(scope="module")
def compressor():
    import rotordyn_modal as rdm

    return rdm.load_model(ROOT / "examples" / "compressor_rotor.toml")


def test_level1_takes_one_station_name_as_one_station(compressor):
    """``level1(model, speed, 'compressor', qa)`` was read as the stations 'c', 'o', 'm', ...
    ("station c: no rotor 'c'"); one name is one station, as ``['compressor']``."""
    import numpy as np

    import rotordyn_modal as rdm

    speed = rdm.rpm(9000)
    one = rdm.level1(compressor, speed, "compressor", 1e5, factor=1.0, steps_per_qa=2, forward_mode=1)
    listed = rdm.level1(compressor, speed, ["compressor"], 1e5, factor=1.0, steps_per_qa=2, forward_mode=1)
    np.testing.assert_array_equal(one.to_dataframe().to_numpy(), listed.to_dataframe().to_numpy())


@pytest.mark.parametrize("change, words", [
    ({"qa": [1e5, 1e5]}, "qa = [100000.0, 100000.0]: expected the anticipated cross-coupling, one number"),
    ({"qa": "1e5"}, "qa = '1e5'"),
    ({"factor": "10"}, "factor = '10'"),
    ({"steps_per_qa": 2.5}, "steps_per_qa = 2.5: expected a whole number"),
    ({"forward_mode": True}, "forward_mode = True: expected a whole number >= 1"),
], ids=["qa-list", "qa-text", "factor-text", "steps-fraction", "forward-bool"])
def test_level1_refuses_an_argument_of_no_meaning_by_name(compressor, change, words):
    """``qa=[1e5, 1e5]`` raised numpy's 'truth value of an array' ValueError, ``qa='1e5'`` a
    TypeError; ``steps_per_qa=2.5`` ran 2 steps and ``forward_mode=True`` mode 1."""
    import rotordyn_modal as rdm

    arguments = {"qa": 1e5, **change}
    with pytest.raises(rdm.InputError) as error:
        rdm.level1(compressor, rdm.rpm(9000), ["compressor"], **arguments)
    assert words in str(error.value), str(error.value)


# ----------------------------------------------------------------------- an output name ending in '/'
@pytest.mark.parametrize("argv, option", [
    (["static", str(ROOT / "examples" / "compressor_rotor.toml"), "--out", "{name}.csv/", "--quiet"], "--out"),
    (["import-ross", str(ROSS / "rotor_example.toml"), "--out", "{name}.toml/", "--quiet"], "--out"),
    (["modes", FAN, "--speed", "0", "--plot", "{name}.png/", "--quiet"], "--plot"),
], ids=["static-out", "import-ross-out", "modes-plot"])
def test_an_output_name_ending_in_a_slash_is_refused(tmp_path, monkeypatch, capsys, argv, option):
    """``static m.toml --out results.csv/`` (a folder meant, or a slip of the tab key) wrote a file
    named results.csv (Path drops the '/'), exit 0."""
    monkeypatch.chdir(tmp_path)
    assert main([a.format(name="results") for a in argv]) == 2
    _one_line_error(capsys, option, "results.", "ending in '/' is a folder")
    assert not list(tmp_path.iterdir())


# ----------------------------------------------------------------------- a study file given as the model
@pytest.mark.parametrize("command", [["check"], ["modes", "--speed", "1000"]])
def test_a_study_file_given_as_a_model_names_the_command_that_runs_it(capsys, command):
    """``check mount_tolerance.study.toml`` was refused as "seed = 2026: unknown key" (a ROSS file
    there already names ``import-ross``)."""
    study = str(ROOT / "examples" / "mount_tolerance.study.toml")
    assert main([command[0], study, *command[1:]]) == 2
    _one_line_error(capsys, "a study file", f"rotordyn-modal study MODEL --spec {study}")


# ----------------------------------------------------------------------- a probe along the axis of a rotor held radially only
_AXIAL_PROBE = """
[[sensors]]
name = "probe-axial"
rotor = "{rotor}"
{where}
direction = [1.0, 0.0, 0.0]
measure = "relative"
"""


def _with_axial_probe(tmp_path, source: Path, rotor: str, where: str, drop: str = "") -> Path:
    text = Path(source).read_text()
    if drop:
        assert drop in text
        text = text.replace(drop, "")
    path = tmp_path / "axial_probe.toml"
    path.write_text(text + _AXIAL_PROBE.format(rotor=rotor, where=where))
    return path


@pytest.mark.parametrize("source, rotor, where, drop", [
    (ROOT / "examples" / "compressor_rotor.toml", "compressor", "axial_position = 0.3",
     "axial_stiffness = 2.0e8           # the thrust bearing"),
    (ROOT / "examples" / "journal_rotor.toml", "rotor", "position = [0.0, 0.0, 0.0]", ""),
], ids=["flexible", "rigid"])
def test_a_relative_probe_along_the_axis_of_a_rotor_without_axial_coordinate_is_refused(tmp_path, capsys, source,
                                                                                          rotor, where, drop):
    """A rotor no bearing holds axially follows the stator along its axis (it has no axial
    coordinate): a relative probe along that axis read exact zeros (``frf``: magnitude 0 at every
    frequency), exit 0."""
    path = _with_axial_probe(tmp_path, source, rotor, where, drop)
    assert main(["check", str(path)]) == 2
    _one_line_error(capsys, "[sensors.probe-axial] direction", "no axial coordinate", "reads 0")


def test_a_relative_probe_along_the_axis_of_a_thrust_held_rotor_reads_its_axial_motion(tmp_path):
    """With its thrust bearing (axial_stiffness 2e8 N/m) the compressor's probe reads the rotor's
    axial motion: at 0 Hz under a unit axial force, 1 / 2e8 m/N (the rotor on the ground)."""
    import numpy as np

    import rotordyn_modal as rdm

    path = _with_axial_probe(tmp_path, ROOT / "examples" / "compressor_rotor.toml", "compressor", "axial_position = 0.3")
    text = path.read_text() + ('[[excitations]]\nname = "push"\nrotor = "compressor"\naxial_position = 0.3\n'
                               'direction = [1.0, 0.0, 0.0]\n')
    path.write_text(text)
    model = rdm.load_model(path)
    result = rdm.frf(model, 0.0, np.array([0.0]), outputs=["probe-axial"], inputs=["push"])
    assert abs(result.H[0, 0, 0]) == pytest.approx(1 / 2.0e8, rel=1e-9)


# ----------------------------------------------------------------------- a clearance in mm typed for m
def test_a_clearance_in_mm_typed_for_m_draws_one_warning(tmp_path, capsys):
    """``radial_clearance = 0.25`` (0.25 mm meant) loaded without a word, and the API 617 clearance
    check then passed any vibration against 75 % of a 0.5 m diametral clearance."""
    text = (ROOT / "examples" / "compressor_rotor.toml").read_text()
    assert "radial_clearance = 0.25e-3" in text
    path = tmp_path / "mm.toml"
    path.write_text(text.replace("radial_clearance = 0.25e-3", "radial_clearance = 0.25", 1))
    assert main(["check", str(path)]) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "radial_clearance = 0.25: over 0.01 m" in warnings[0], warnings
    assert "a value in mm typed for m?" in warnings[0]
    assert main(["check", str(ROOT / "examples" / "compressor_rotor.toml")]) == 0
    assert "warning" not in capsys.readouterr().err


# ----------------------------------------------------------------------- file arguments of the Python API
@pytest.mark.parametrize("reader", ["load_model", "read_ross_rotor", "read_measured", "load_study"])
@pytest.mark.parametrize("path", [None, 5, b"model.toml", ""], ids=["none", "number", "bytes", "empty"])
def test_a_file_argument_that_is_no_file_name_raises_input_error(reader, path):
    """``rdm.load_model(None)`` (or a number, bytes) raised TypeError inside ``open``; ``''`` was
    refused as the folder '.'."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.ross_file import read_ross_rotor

    call = {"load_model": rdm.load_model, "read_ross_rotor": read_ross_rotor, "load_study": rdm.load_study,
            "read_measured": lambda p: rdm.read_measured(p, rdm.load_model(FAN))}[reader]
    with pytest.raises(rdm.InputError, match="expected the name of a file"):
        call(path)


@pytest.mark.parametrize("content", ["missing", "folder", "empty", "garbage", "model", "other-netcdf"])
def test_load_study_of_a_file_that_holds_no_study_raises_input_error(tmp_path, content):
    """``rdm.load_study`` let FileNotFoundError, IsADirectoryError, numpy's 'cannot mmap an empty
    file' ValueError and scipy's multi-line 'is not a valid NetCDF 3 file' TypeError through."""
    import numpy as np
    import xarray as xr

    import rotordyn_modal as rdm

    path = tmp_path / "results.nc"
    if content == "folder":
        path.mkdir()
    elif content == "empty":
        path.write_bytes(b"")
    elif content == "garbage":
        path.write_bytes(bytes(range(256)) * 8)
    elif content == "model":
        path.write_text(Path(FAN).read_text())
    elif content == "other-netcdf":
        xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(path, engine="scipy")
    with pytest.raises(rdm.InputError, match="results") as error:
        rdm.load_study(path)
    assert str(path) in str(error.value) and len(str(error.value).splitlines()) == 1
