"""Input files as a new user gives them (issue 27 §1.5, §4, §5, the red team's small finds):
measured files through a pipe (``--measured <(cat m.uff)``, ``/dev/stdin``) as models are read;
``import-ross`` of a pipe names no rotor '63'; CSV tables that are no table (outline, mapping,
measured) refused in the package's words, naming the file, the line and the column; every input
option given a folder, an empty file, a gzip file or a file it may not read: one line, exit 2.

The pipes are real (a subprocess reading ``/dev/fd/N`` or its standard input); the refusals run
``main`` in this process. The expected values come from reading the same bytes as a regular file."""

from __future__ import annotations

import gzip
import os
import shutil
import subprocess
import sys
import threading
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.cli import main
from test_input_families import _one_line_error
from test_output_paths import FILE_OPTIONS, REQUIRED

ROOT = Path(__file__).resolve().parent.parent
GEAR = ROOT / "examples" / "gear_machine.toml"
FAN = ROOT / "examples" / "fan_on_bearings.toml"
ROSS = ROOT / "tests" / "data" / "ross" / "rotor_example.toml"
SPEC = ROOT / "examples" / "mount_tolerance.study.toml"
FREQS = ["--freqs", "1:40:5"]
#: the words of pandas' CSV parser, which no message may quote
PANDAS_WORDS = ("Error tokenizing", "C error", "No columns to parse", "EOF inside string", "Errno")


def _cli(argv, tmp_path, stdin=None, pass_fds=()):
    """``python -m rotordyn_modal ARGV`` in a process whose temporary folder is ``tmp_path/tmp``:
    (exit code, stdout, stderr)."""
    temporary = tmp_path / "tmp"
    temporary.mkdir(exist_ok=True)
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MPLBACKEND": "Agg", "TMPDIR": str(temporary)}
    done = subprocess.run([sys.executable, "-m", "rotordyn_modal", *map(str, argv)], input=stdin,
                          capture_output=True, env=env, cwd=tmp_path, timeout=300, pass_fds=pass_fds)
    return done.returncode, done.stdout.decode(), done.stderr.decode()


def _through_pipe(data: bytes):
    """(the read end of a pipe a thread writes ``data`` into, the thread): what bash's
    ``<(cat FILE)`` gives a program as ``/dev/fd/N``."""
    read_end, write_end = os.pipe()

    def write():
        with os.fdopen(write_end, "wb") as handle:
            try:
                handle.write(data)
            except BrokenPipeError:
                pass

    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    return read_end, writer


@pytest.fixture(scope="module")
def measured_files(tmp_path_factory):
    """The gear machine's FRFs written by ``frf --out`` as CSV and as UFF."""
    folder = tmp_path_factory.mktemp("measured")
    for ending in ("csv", "uff"):
        assert main(["frf", str(GEAR), *FREQS, "--out", str(folder / f"m.{ending}"), "--quiet"]) == 0
    return folder


# ----------------------------------------------------------------------- measured files from pipes
@pytest.mark.parametrize("ending", ["uff", "csv"])
def test_measured_through_a_descriptor_pipe_is_read_as_the_file(tmp_path, measured_files, ending):
    """On main ``frf MODEL --measured <(cat m.uff)`` was refused ('not a pipe or device'); the same
    bytes are read as the file's (their channels and speed checked against the model's), and
    the temporary copy is removed."""
    data = (measured_files / f"m.{ending}").read_bytes()
    read_end, writer = _through_pipe(data)
    try:
        code, _, err = _cli(["frf", GEAR, *FREQS, "--measured", f"/dev/fd/{read_end}", "--out", "f.csv",
                             "--quiet"], tmp_path, pass_fds=(read_end,))
    finally:
        os.close(read_end)
        writer.join(timeout=10)
    assert code == 0 and "error" not in err, err      # read, its channels and speed checked against the model's
    assert (tmp_path / "f.csv").stat().st_size > 0
    assert list((tmp_path / "tmp").iterdir()) == []          # the pipe's copy is removed


@pytest.mark.parametrize("ending", ["csv"])
def test_measured_from_standard_input_is_read_by_its_bytes(tmp_path, measured_files, ending):
    """``--measured /dev/stdin``: a pipe (``cat m.csv | ...``), named with no ending, is told CSV by
    its bytes (UFF: the FIFO test below); ``fit`` fits the same gain as from the file itself."""
    data = (measured_files / f"m.{ending}").read_bytes()
    argv = ["fit", GEAR, "--params", "gain", "--starts", "1", "--quiet"]
    code, _, err = _cli([*argv, "--measured", "/dev/stdin", "--out", "piped.toml"], tmp_path, stdin=data)
    assert code == 0, err
    code, _, err = _cli([*argv, "--measured", measured_files / f"m.{ending}", "--out", "file.toml"], tmp_path)
    assert code == 0, err
    assert (tmp_path / "piped.toml").read_text() == (tmp_path / "file.toml").read_text()


def test_a_measured_pipe_is_named_as_typed_in_its_refusal(tmp_path, measured_files):
    """A broken file through a pipe is refused naming ``/dev/stdin``, never the temporary copy."""
    # cut short inside its first dataset (cut in a later one, the complete datasets are read with a warning)
    data = (measured_files / "m.uff").read_bytes()[:600]
    code, _, err = _cli(["frf", GEAR, *FREQS, "--measured", "/dev/stdin"], tmp_path, stdin=data)
    assert code == 2
    assert err.count("\n") == 1 and "error: /dev/stdin: incomplete Universal File" in err, err
    assert "rotordyn-modal-pipe" not in err and str(tmp_path) not in err


def test_the_api_reads_a_measured_fifo_as_the_file(tmp_path, measured_files):
    """``rdm.read_measured`` of a FIFO a program writes to (was refused): the same FRFs as the file."""
    from rotordyn_modal import load_model
    from rotordyn_modal.io.measured import read_measured

    model = load_model(GEAR)
    fifo = tmp_path / "frf-pipe"                 # no ending: told by its bytes
    os.mkfifo(fifo)
    source = measured_files / "m.uff"

    def write():
        with open(fifo, "wb") as handle:
            handle.write(source.read_bytes())

    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    piped = read_measured(fifo, model)
    writer.join(timeout=10)
    direct = read_measured(source, model)
    assert len(piped) == len(direct) == 1
    np.testing.assert_array_equal(piped[0].H, direct[0].H)
    np.testing.assert_array_equal(piped[0].frequencies_hz, direct[0].frequencies_hz)


# ----------------------------------------------------------------------- import-ross of a pipe
@pytest.mark.parametrize("name", [None, "shaft"])
def test_import_ross_of_a_pipe_names_no_rotor_after_the_descriptor(tmp_path, name):
    """On main ``import-ross <(cat r.toml)`` named the rotor '63' (the stem of /dev/fd/63). A ROSS
    file holds no rotor name: a pipe's rotor is 'rotor', said on stderr; --name still names it."""
    read_end, writer = _through_pipe(ROSS.read_bytes())
    try:
        code, _, err = _cli(["import-ross", f"/dev/fd/{read_end}", "--out", "r.toml",
                             *(["--name", name] if name else [])], tmp_path, pass_fds=(read_end,))
    finally:
        os.close(read_end)
        writer.join(timeout=10)
    assert code == 0, err
    written = tomllib.loads((tmp_path / "r.toml").read_text())
    rotor = written["rotors"][0]["name"]
    assert rotor == (name or "rotor")
    assert str(read_end) not in written["name"] and "read from a pipe" in written["name"]
    assert ("named 'rotor' (give --name NAME" in err) == (name is None), err


# ----------------------------------------------------------------------- CSV tables that are no table
#: (file option, the valid header and rows, what the command needs besides) of each CSV reader
_TABLES = {
    "outline": ("x,y,z\n0,0,0\n0.5,0,0\n0.5,0.3,0\n",
                lambda path, tmp: ["modes", FAN, "--shape", "1", "--plot", tmp / "s.png", "--outline", path]),
    "mapping": ("name,node,direction\nacc-top-z,1,3\nacc-side-y,2,2\nhammer-z,101,3\nshaker-y,102,2\n",
                lambda path, tmp: ["frf", GEAR, *FREQS, "--measured", tmp / "m.uff", "--mapping", path]),
    "measured": ("frequency_hz,output,input,real,imag\n1,acc-top-z,hammer-z,1e-6,0\n2,acc-top-z,hammer-z,1e-6,0\n",
                 lambda path, tmp: ["frf", GEAR, *FREQS, "--measured", path]),
}


def _refused(tmp_path, capsys, kind, text):
    path = tmp_path / f"{kind} table.csv"
    path.write_text(text, encoding="utf-8")
    argv = [str(a) for a in _TABLES[kind][1](path, tmp_path)]
    assert main(argv) == 2
    err = _one_line_error(capsys, str(path))
    assert not any(word in err for word in PANDAS_WORDS), err
    return err


@pytest.fixture
def with_uff(tmp_path, measured_files):
    shutil.copy(measured_files / "m.uff", tmp_path / "m.uff")


@pytest.mark.parametrize("kind", list(_TABLES))
def test_a_cell_beyond_the_header_is_refused_naming_its_line_and_column(tmp_path, capsys, with_uff, kind):
    """On main: pandas' "Error tokenizing data. C error: Expected 3 fields in line 4, saw 4"."""
    header, *rows = _TABLES[kind][0].splitlines()
    text = "\n".join([header, rows[0], rows[1] + ",7", *rows[2:]]) + "\n"
    err = _refused(tmp_path, capsys, kind, text)
    width = header.count(",") + 1
    assert f"line 3, column {width + 1}: '7' beyond the header's {width} column(s)" in err, err
    assert f"expected at most {width} cells on a line" in err


@pytest.mark.parametrize("kind", list(_TABLES))
def test_every_row_one_cell_longer_is_refused_not_shifted(tmp_path, capsys, with_uff, kind):
    """On main pandas took such a file's first column as row labels without a word: the outline
    was drawn from the wrong columns (exit 0) and the mapping named its channels by node numbers."""
    header, *rows = _TABLES[kind][0].splitlines()
    text = "\n".join([header, *(f"9,{row}" for row in rows)]) + "\n"
    err = _refused(tmp_path, capsys, kind, text)
    assert "line 2, column" in err and "beyond the header's" in err, err


@pytest.mark.parametrize("kind", list(_TABLES))
def test_an_unclosed_quote_is_refused_naming_its_line(tmp_path, capsys, with_uff, kind):
    """On main: "Error tokenizing data. C error: EOF inside string starting at row 1"."""
    header, *rows = _TABLES[kind][0].splitlines()
    text = "\n".join([header, rows[0], '"' + rows[1], *rows[2:]]) + "\n"
    err = _refused(tmp_path, capsys, kind, text)
    assert "line 3: a quoted cell" in err and "never closed" in err, err


@pytest.mark.parametrize("kind", list(_TABLES))
@pytest.mark.parametrize("text", ["", "\n\n  \n"], ids=["empty", "blank-lines"])
def test_an_empty_table_is_refused_saying_so(tmp_path, capsys, with_uff, kind, text):
    """On main: "No columns to parse from file"."""
    err = _refused(tmp_path, capsys, kind, text)
    assert "no line of text (empty, or blank lines only)" in err and "expected a header line" in err, err


def test_a_cell_beyond_the_csv_modules_field_limit_is_one_line(tmp_path, capsys, with_uff):
    """Python's csv module refuses a cell over 131,072 characters ('field larger than field limit'):
    said on one line with exit 2, never exit 1 (pandas, on main, read it and refused the number)."""
    _refused(tmp_path, capsys, "outline", "x,y,z\n0,0,0\n" + "1" * 200_000 + ",1,1\n")


def test_separators_at_the_line_ends_are_no_column():
    """``x,y,z,`` rows of a spreadsheet: on main the first column became row labels, so the
    outline was refused as 'z empty' (or read shifted); now the same points as without them."""
    from rotordyn_modal.io.csv_tables import read_csv_table, numbers

    plain = "x,y,z\n0,0,0\n0.5,0,0\n0.5,0.3,0\n"
    padded = "x,y,z\n0,0,0,\n0.5,0,0,\n0.5,0.3,0,,\n"
    for text in (plain, padded, plain.replace("\n", ",\n")):
        table, decimal = read_csv_table(text.encode(), "o.csv", "the outline")
        assert list(table.columns) == ["x", "y", "z"]
        np.testing.assert_array_equal(np.column_stack([numbers(table, c, "o.csv", decimal) for c in "xyz"]),
                                      [[0, 0, 0], [0.5, 0, 0], [0.5, 0.3, 0]])


def test_a_number_error_names_the_files_own_line_after_blank_lines(tmp_path, capsys):
    """Blank lines between rows are left out of the table; the message still names the file's line
    (on main it counted rows from the header: line 3 for the file's line 5)."""
    text = "frequency_hz,output,input,real,imag\n\n1,acc-top-z,hammer-z,1e-6,0\n\n2,acc-top-z,hammer-z,abc,0\n"
    path = tmp_path / "m.csv"
    path.write_text(text)
    assert main(["frf", str(GEAR), *FREQS, "--measured", str(path)]) == 2
    _one_line_error(capsys, "column real line 5 = 'abc': expected a number")


# ----------------------------------------------------------------------- every input, as a new user gives it
def _input_cases():
    """(command, option) of every input file option; the model for one command (one reader)."""
    for command, (inputs, _) in FILE_OPTIONS.items():
        for option in inputs:
            if option != "MODEL" or command == "check":
                yield command, option


_VALID = {"MODEL": GEAR, "--spec": SPEC, "ROSS.toml": ROSS}


def _argv(command, option, path, tmp_path):
    """The command line with ``option`` naming ``path``, the other inputs valid."""
    valid = {**_VALID, "--measured": tmp_path / "m.uff", "--outline": tmp_path / "o.csv",
             "--mapping": tmp_path / "map.csv"}
    argv = [command]
    for other in FILE_OPTIONS[command][0]:
        value = path if other == option else valid[other]
        if other in ("--outline", "--mapping") and other != option:
            continue
        if other == "--measured" and other != option and option != "--mapping" and command != "fit":
            continue
        argv += [str(value)] if not other.startswith("-") else [other, str(value)]
    argv += REQUIRED[command]
    if command == "modes" and option == "--outline":
        argv += ["--shape", "1", "--plot", str(tmp_path / "s.png")]
    if command in ("study", "fit", "import-ross"):
        argv += ["--out", str(tmp_path / {"study": "o.nc", "fit": "o.toml", "import-ross": "o.toml"}[command])]
    return argv


def _valid_file(option, tmp_path) -> Path:
    return {"--measured": tmp_path / "m.uff", "--outline": tmp_path / "o.csv",
            "--mapping": tmp_path / "map.csv"}.get(option) or _VALID[option]


@pytest.fixture
def inputs(tmp_path, measured_files):
    shutil.copy(measured_files / "m.uff", tmp_path / "m.uff")
    (tmp_path / "o.csv").write_text(_TABLES["outline"][0])
    (tmp_path / "map.csv").write_text(_TABLES["mapping"][0])


@pytest.mark.parametrize("kind, words", [
    ("folder", ["folder"]),
    ("empty", ["empty"]),
    ("gzip", ["a gzip-compressed file: expected the", "itself, uncompressed (gunzip it first)"]),
    ("gzip-same-name", ["a gzip-compressed file"]),
], ids=["folder", "empty", "gzip", "gzip-same-name"])
@pytest.mark.parametrize("command, option", list(_input_cases()), ids=[f"{c}:{o}" for c, o in _input_cases()])
def test_every_input_option_refuses_what_is_no_input_in_one_line(tmp_path, capsys, inputs, command, option, kind,
                                                                 words):
    """On main a gzip file was 'byte 1: expected UTF-8 text', 'control character \\x1f', 'no dataset
    58', 'unknown measured data format .gz' or 'lacks the column(s)'; an empty model 'rotors = []';
    an outline or mapping folder '[Errno 21] Is a directory'."""
    valid = _valid_file(option, tmp_path)
    case = tmp_path / "case"
    case.mkdir()
    if kind == "folder":
        path = case / valid.name
        path.mkdir()
    elif kind == "empty":
        path = case / valid.name
        path.write_bytes(b"")
    else:
        path = case / (valid.name + (".gz" if kind == "gzip" else ""))
        path.write_bytes(gzip.compress(valid.read_bytes()))
    assert main(_argv(command, option, path, tmp_path)) == 2
    err = _one_line_error(capsys, f"error: {path}", *words)
    assert not any(word in err for word in PANDAS_WORDS), err


@pytest.mark.skipif(os.geteuid() == 0 and not shutil.which("setpriv"), reason="root reads every file")
@pytest.mark.parametrize("command, option", [("check", "MODEL"), ("modes", "--outline"), ("modes", "--measured"),
                                             ("frf", "--mapping"), ("study", "--spec"), ("import-ross", "ROSS.toml")])
def test_an_input_it_may_not_read_is_refused_in_one_line(tmp_path, inputs, command, option):
    """A file without read permission (root reads every file: the process drops the capabilities
    that let it). On main the outline and mapping said Python's '[Errno 13] Permission denied: ...'."""
    path = tmp_path / "secret" / _valid_file(option, tmp_path).name
    path.parent.mkdir()
    shutil.copy(_valid_file(option, tmp_path), path)
    path.chmod(0)
    argv = _argv(command, option, path, tmp_path)
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""), "MPLBACKEND": "Agg"}
    prefix = ["setpriv", "--bounding-set=-dac_override,-dac_read_search"] if os.geteuid() == 0 else []
    done = subprocess.run([*prefix, sys.executable, "-m", "rotordyn_modal", *argv], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and f"error: {path}" in lines[0], done.stderr
    assert "ermission" in lines[0] and "Errno" not in lines[0], lines[0]
