"""'-' is standard input (issue 27 §4, §1.4): ``frf MODEL --measured -``, ``--mapping -``,
``--outline -``, ``check -``, ``study --spec -``, ``import-ross -`` read what is piped or
redirected into the command, messages naming it "standard input"; at most one option may be
'-', and a terminal (nothing piped in) is refused in one line. The UFF and TDMS readers of the
Python API read a named pipe (FIFO) as a file.

The truth is always the same bytes read from a regular file named on the command line (or
given to the reader by name). The commands run in real processes whose standard input is a
pipe, a redirected file or a terminal (a pseudo-terminal)."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"
ROSS = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"
UFF = ROOT / "tests" / "data" / "uff"
TDMS = ROOT / "tests" / "data" / "tdms"
FRF = ["frf", GEAR, "--speed", "1500", "--speed-unit", "rpm", "--freqs", "1:60:30", "--quiet"]


def _run(argv, tmp_path, stdin=subprocess.DEVNULL):
    """``python -m rotordyn_modal ARGV`` with ``stdin`` (bytes: a pipe; a path: the file
    redirected, as ``< FILE``; else a descriptor), its temporary folder ``tmp_path/tmp``:
    (exit code, stdout, stderr)."""
    temporary = tmp_path / "tmp"
    temporary.mkdir(exist_ok=True)
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MPLBACKEND": "Agg", "TMPDIR": str(temporary)}
    command = [sys.executable, "-m", "rotordyn_modal", *map(str, argv)]
    if isinstance(stdin, Path):
        with open(stdin, "rb") as handle:
            done = subprocess.run(command, stdin=handle, capture_output=True, env=env, cwd=tmp_path, timeout=300)
    elif isinstance(stdin, bytes):
        done = subprocess.run(command, input=stdin, capture_output=True, env=env, cwd=tmp_path, timeout=300)
    else:
        done = subprocess.run(command, stdin=stdin, capture_output=True, env=env, cwd=tmp_path, timeout=300)
    assert not any(temporary.iterdir()), "a copy of standard input was left behind"
    return done.returncode, done.stdout.decode(), done.stderr.decode()


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """A UFF of FRFs and a mapping table written by ``frf`` (the measured files read back)."""
    folder = tmp_path_factory.mktemp("written")
    mapping = folder / "map.csv"
    mapping.write_text("name,node,direction\nacc-top-z,11,+Z\nacc-side-y,12,+Y\nhammer-z,101,+Z\nshaker-y,102,+Y\n")
    code, _, err = _run([*FRF, "--mapping", mapping, "--out", folder / "m.uff"], folder)
    assert code == 0, err
    code, _, err = _run([*FRF, "--out", folder / "m.csv"], folder)
    assert code == 0, err
    return folder


@pytest.mark.parametrize("how", ["pipe", "redirect"])
def test_check_reads_the_model_from_standard_input(tmp_path, how):
    """The summary is the file's, named "standard input" (main: '-' refused)."""
    code, by_name, _ = _run(["check", GEAR], tmp_path)
    assert code == 0
    code, out, err = _run(["check", "-"], tmp_path, GEAR.read_bytes() if how == "pipe" else GEAR)
    assert code == 0, err
    first, *rest = out.splitlines()
    assert first == by_name.splitlines()[0].replace(str(GEAR), "standard input")
    assert rest == by_name.splitlines()[1:]


def test_measured_uff_from_standard_input_is_the_file(tmp_path, written):
    """``--measured -`` of a piped UFF (its format told by its bytes) with ``--mapping FILE``:
    the CSV written is the one of ``--measured FILE`` byte for byte; the same with the mapping
    table piped and the UFF named."""
    args = [*FRF, "--mapping", written / "map.csv"]
    code, _, err = _run([*args, "--measured", written / "m.uff", "--out", "by_name.csv"], tmp_path)
    assert code == 0, err
    code, _, err = _run([*args, "--measured", "-", "--out", "piped.csv"], tmp_path, (written / "m.uff").read_bytes())
    assert code == 0, err
    assert (tmp_path / "piped.csv").read_bytes() == (tmp_path / "by_name.csv").read_bytes()
    code, _, err = _run([*FRF, "--mapping", "-", "--measured", written / "m.uff", "--out", "mapped.csv"], tmp_path,
                        written / "map.csv")
    assert code == 0, err
    assert (tmp_path / "mapped.csv").read_bytes() == (tmp_path / "by_name.csv").read_bytes()


def test_a_mapping_from_standard_input_places_the_written_uff(tmp_path, written):
    """``frf --out f.uff --mapping -`` reads the table as ``--mapping FILE`` does: the same file."""
    code, _, err = _run([*FRF, "--mapping", "-", "--out", "piped.uff"], tmp_path, (written / "map.csv").read_bytes())
    assert code == 0, err
    assert (tmp_path / "piped.uff").read_bytes() == (written / "m.uff").read_bytes()


def test_a_measured_table_from_standard_input_and_its_refusals_name_it(tmp_path, written):
    """A CSV table piped in is read as the file (the frequencies and H written again equal);
    a broken one is refused in one line naming "standard input", the line and the column."""
    code, _, err = _run([*FRF, "--measured", "-", "--out", "piped.csv"], tmp_path, (written / "m.csv").read_bytes())
    assert code == 0, err
    code, _, err = _run([*FRF, "--measured", written / "m.csv", "--out", "by_name.csv"], tmp_path)
    assert (tmp_path / "piped.csv").read_bytes() == (tmp_path / "by_name.csv").read_bytes()
    lines = (written / "m.csv").read_bytes().splitlines()
    broken = b"\n".join(lines[:3] + [b",".join(lines[3].split(b",")[:3] + [b"zz"] + lines[3].split(b",")[4:])]
                        + lines[4:]) + b"\n"
    code, out, err = _run([*FRF, "--measured", "-", "--out", "-"], tmp_path, broken)
    assert code == 2 and out == ""
    [line] = err.splitlines()
    assert line.startswith("rotordyn-modal frf: error: standard input: ") and "line 4" in line and "zz" in line, line
    assert "/tmp" not in line and "stdin" not in line, line


def test_an_outline_from_standard_input(tmp_path):
    """``modes --outline -``: the figure of the piped outline is the named file's, byte for byte;
    a cell that is no number is refused naming "standard input", its line and column."""
    outline = tmp_path / "o.csv"
    outline.write_text("x,y,z\n0,0,0\n0.1,0,0\n0.1,0.1,0\n")
    args = ["modes", GEAR, "--shape", "1", "--quiet"]
    code, _, err = _run([*args, "--outline", outline, "--plot", "by_name.png"], tmp_path)
    assert code == 0, err
    code, _, err = _run([*args, "--outline", "-", "--plot", "piped.png"], tmp_path, outline)
    assert code == 0, err
    assert (tmp_path / "piped.png").read_bytes() == (tmp_path / "by_name.png").read_bytes()
    code, _, err = _run([*args, "--outline", "-", "--plot", "bad.png"], tmp_path, b"x,y,z\n0,0,0\n0.1,0,zz\n")
    assert code == 2 and not (tmp_path / "bad.png").exists()
    assert err.splitlines() == ["rotordyn-modal modes: error: standard input: column z line 3 = 'zz': expected a "
                                "number (an empty row starts a new line)"]


def test_import_ross_from_standard_input(tmp_path):
    """``import-ross -`` writes the model of ``import-ross FILE``; the rotor is named 'rotor' (no
    file's stem), said on stderr naming standard input."""
    code, _, err = _run(["import-ross", ROSS, "--out", "by_name.toml", "--quiet"], tmp_path)
    assert code == 0, err
    code, _, err = _run(["import-ross", "-", "--out", "piped.toml"], tmp_path, ROSS)
    assert code == 0, err
    assert "standard input gives no file's name: the rotor is named 'rotor'" in err
    piped = tomllib.loads((tmp_path / "piped.toml").read_text())
    by_name = tomllib.loads((tmp_path / "by_name.toml").read_text())
    assert piped.pop("name") == "rotor (ROSS 3.1.0 file read from standard input)"
    assert piped["rotors"][0].pop("name") == "rotor"
    by_name.pop("name")
    by_name["rotors"][0].pop("name")
    for bearing in piped["bearings"] + by_name["bearings"]:
        bearing.pop("rotor")
    assert piped == by_name


def test_two_options_given_standard_input_are_refused(capsys):
    """Standard input can be read once: one line naming both options, before any work."""
    assert main(["frf", str(GEAR), "--freqs", "2:40:3", "--measured", "-", "--mapping", "-"]) == 2
    [line] = capsys.readouterr().err.splitlines()
    assert line == ("rotordyn-modal frf: error: --measured - and --mapping -: standard input is read once: give '-' "
                    "to one of them and name files for the others")


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="no pseudo-terminals")
def test_a_terminal_as_standard_input_is_refused(tmp_path):
    """``check -`` typed with nothing piped in would wait for the model to be typed: refused."""
    leader, follower = os.openpty()
    try:
        code, _, err = _run(["check", "-"], tmp_path, follower)
    finally:
        os.close(leader)
        os.close(follower)
    assert code == 2
    assert err.splitlines() == ["rotordyn-modal check: error: MODEL -: standard input is a terminal, nothing is piped "
                                "in: pipe the file in (... < FILE, or cat FILE | ...) or name it"]


def test_the_file_redirected_into_standard_input_is_protected(tmp_path, written):
    """``frf ... --measured - --out m.csv < m.csv`` would write over the file read: refused."""
    table = tmp_path / "m.csv"
    table.write_bytes((written / "m.csv").read_bytes())
    code, _, err = _run([*FRF, "--measured", "-", "--out", table], tmp_path, table)
    assert code == 2
    assert err.splitlines() == [f"rotordyn-modal frf: error: --out {table}: refusing to write over the input file "
                                f"{table} (--measured -)"]
    assert table.read_bytes() == (written / "m.csv").read_bytes()


# ------------------------------------------------------------------ the API's readers of a FIFO
def _fifo(tmp_path, data: bytes) -> tuple[Path, threading.Thread]:
    """A named pipe a thread writes ``data`` into (as a program writing into a FIFO)."""
    path = tmp_path / "pipe"
    os.mkfifo(path)

    def write():
        with open(path, "wb") as handle:
            handle.write(data)

    thread = threading.Thread(target=write, daemon=True)
    thread.start()
    return path, thread


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
@pytest.mark.parametrize("reader, source", [
    ("info", UFF / "testlab_151_164_18_15_82.uff"),
    ("time", UFF / "time-history-not-all-columns-filled.uff"),
    ("modes", UFF / "permas_2414_modes_excerpt.uff"),
    ("tdms", TDMS / "good_tdms_2.tdms"),
])
def test_the_readers_read_a_fifo_as_the_file(tmp_path, reader, source):
    """``read_uff_info``, ``read_uff_time_records``, ``read_uff_modes`` and ``read_tdms_records``
    of a FIFO give what they give of the file (main: 'not a pipe or device')."""
    if reader == "tdms":
        pytest.importorskip("nptdms")
    model = rdm.load_model(GEAR)
    read = {"info": rdm.read_uff_info, "time": rdm.read_uff_time_records,
            "modes": lambda p: rdm.read_uff_modes(p, model),
            "tdms": lambda p: rdm.read_tdms_records(p, group="acceleration")}[reader]
    fifo, thread = _fifo(tmp_path, source.read_bytes())
    got = read(fifo)
    thread.join(10)
    expected = read(source)
    if reader == "info":
        assert {k: v for k, v in got.items() if k != "units"} == {k: v for k, v in expected.items() if k != "units"}
        assert repr(got["units"]) == repr(expected["units"])
        return
    for field in ("signals", "shapes", "poles", "sample_rate"):
        if hasattr(expected, field):
            np.testing.assert_array_equal(getattr(got, field), getattr(expected, field))
    assert list(tmp_path.iterdir()) == [fifo]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_refusal_of_a_fifo_names_the_fifo(tmp_path):
    """The reader's message names the pipe given, not its temporary copy."""
    pytest.importorskip("nptdms")
    fifo, thread = _fifo(tmp_path, (TDMS / "good_tdms_2.tdms").read_bytes())
    with pytest.raises(InputError) as raised:
        rdm.read_tdms_records(fifo)
    thread.join(10)
    assert str(raised.value).startswith(f"{fifo}: several groups: give group= one of ")
