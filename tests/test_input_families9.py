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
