"""Studies that survive ``kill -9``, damaged checkpoints, and a second study on the same file.

The situations are made, not listed: the study command is killed with SIGKILL at a
moment drawn from a seeded random generator: after a drawn number of its chunks are
logged, plus a drawn delay (``ROTORDYN_MODAL_KILL_TRIALS`` kills, default 3); then the same command is run again; its chunk log (``--verbose``) shows which
chunks it computed and which it took from the checkpoint, and the checkpoint's state at
the moment of the kill is read here independently of the package (each chunk's manifest
against the SHA-256 and size of its file). Checkpoints are damaged at random
(``ROTORDYN_MODAL_CORRUPTION_TRIALS`` rounds, default 4): truncated, byte-flipped,
swapped or foreign files, missing or damaged manifests.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import random
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.study import load_study

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")
KILLS = int(os.environ.get("ROTORDYN_MODAL_KILL_TRIALS", "3"))
CORRUPTIONS = int(os.environ.get("ROTORDYN_MODAL_CORRUPTION_TRIALS", "4"))

pytest.importorskip("xarray")
pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="kill -9 and fork: POSIX")

SPEC = """seed = 11
samples = 96
chunk_size = 6
[[parameters]]
key = "suspensions.mount-FL.stiffness"
apply = "scale"
distribution = "uniform"
low = 0.85
high = 1.15
[[parameters]]
key = "stator.mass"
distribution = "normal"
mean = 150.0
std = 5.0
[analyses.campbell]
speeds_rpm = "0:6000:241"
orders = [1]
[analyses.critical_speeds]
"""
N_CHUNKS = 16
_CHUNK_LINE = re.compile(r"chunk (\d+) (computed|resumed)")


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "small.study.toml"
    path.write_text(SPEC)
    return path


def study_command(spec, out, *extra):
    return [sys.executable, "-c", "import sys; from rotordyn_modal.cli import main; sys.exit(main())",
            "study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--workers", "2", "--quiet", "--verbose",
            *extra]


def chunk_log(text):
    """{'computed': set of chunk indices, 'resumed': set}, from the --verbose lines."""
    found = {"computed": set(), "resumed": set()}
    for index, what in _CHUNK_LINE.findall(text):
        assert int(index) not in found[what], f"chunk {index} {what} twice"
        found[what].add(int(index))
    return found


def finished_chunks(folder):
    """Chunks of a checkpoint folder whose manifest matches their file, checked here."""
    finished = set()
    for manifest in Path(folder).glob("chunk-*.json"):
        try:
            record = json.loads(manifest.read_text())
            payload = manifest.with_suffix(".npz").read_bytes()
        except (OSError, ValueError):
            continue
        if record["bytes"] == len(payload) and record["sha256"] == hashlib.sha256(payload).hexdigest():
            finished.add(record["index"])
    return finished


def assert_same_results(path, reference):
    """Every variable and coordinate equal bit for bit (NaN where NaN)."""
    got, want = load_study(path).dataset, load_study(reference).dataset
    assert set(got.variables) == set(want.variables)
    for name in want.variables:
        a, b = got[name].values, want[name].values
        if a.dtype.kind == "f":
            assert np.array_equal(a.view(np.uint64 if a.itemsize == 8 else np.uint32),
                                  b.view(np.uint64 if b.itemsize == 8 else np.uint32)), name
        else:
            assert np.array_equal(a, b), name


def children_of(pid):
    """Process ids whose parent is ``pid`` (Linux /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def alive(pid):
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return False
    return fields[0] != "Z"


@pytest.fixture(scope="module")
def reference(spec, tmp_path_factory):
    """An uninterrupted run: its results, its chunks and when they were logged [s]."""
    out = tmp_path_factory.mktemp("reference") / "r.nc"
    start = time.monotonic()
    process = subprocess.Popen(study_command(spec, out), stderr=subprocess.PIPE, text=True)
    times, text = [], ""
    for line in process.stderr:
        text += line
        if _CHUNK_LINE.search(line):
            times.append(time.monotonic() - start)
    assert process.wait() == 0, text
    end = time.monotonic() - start
    log = chunk_log(text)
    assert log == {"computed": set(range(N_CHUNKS)), "resumed": set()}
    return {"out": out, "first": times[0], "last": times[-1], "end": end}


def test_kill_9_at_random_moments_then_the_same_command_gives_identical_results(spec, reference, tmp_path):
    rng = random.Random(20261123)
    on_linux = Path("/proc/self/stat").exists()
    mid_run = 0
    for trial in range(KILLS):
        folder = tmp_path / f"trial{trial}"
        folder.mkdir()
        out = folder / "r.nc"
        # a moment drawn from the run's own progress (so that a slow or busy machine does not
        # move every kill past the end): after `after` chunks are logged, then `extra` seconds;
        # after none: during the start; after all: while the results are written
        after = rng.randint(0, N_CHUNKS)
        extra = rng.uniform(0.0, reference["first"] if after == 0 else 0.2)
        process = subprocess.Popen(study_command(spec, out), stderr=subprocess.PIPE, text=True)
        seen = 0
        while seen < after:
            line = process.stderr.readline()
            if not line:
                break
            seen += bool(_CHUNK_LINE.search(line))
        time.sleep(extra)
        delay = extra
        workers = children_of(process.pid) if on_linux else []
        process.send_signal(signal.SIGKILL)
        process.wait()
        process.stderr.close()
        if on_linux:  # the pool's workers end with the study, not later
            deadline = time.monotonic() + 10
            while any(alive(w) for w in workers) and time.monotonic() < deadline:
                time.sleep(0.05)
            assert not any(alive(w) for w in workers)
        before = finished_chunks(out.with_name("r.nc.partial"))
        mid_run += 0 < len(before) < N_CHUNKS
        print(f"kill {trial}: {delay:.2f} s after chunk line {after}, {len(before)} of {N_CHUNKS} chunks finished, "
              f"lock left: {(folder / 'r.nc.lock').exists()}")
        rerun = subprocess.run(study_command(spec, out), capture_output=True, text=True)
        assert rerun.returncode == 0, rerun.stderr
        log = chunk_log(rerun.stderr)
        if out.exists() and not before and not log["computed"]:
            continue  # pragma: no cover - the first run had finished before the kill
        assert log["resumed"] == before, (delay, rerun.stderr)
        assert log["computed"] == set(range(N_CHUNKS)) - before, (delay, rerun.stderr)
        assert_same_results(out, reference["out"])
        assert sorted(p.name for p in folder.iterdir()) == ["r.nc"]  # no lock, checkpoint or temporary left
    assert mid_run >= min(1, KILLS), "no kill landed while chunks were being computed"


# ------------------------------------------------------------------------- damaged checkpoints
def _flip(path, rng):
    data = bytearray(path.read_bytes())
    i = rng.randrange(len(data))
    data[i] ^= 1 << rng.randrange(8)
    path.write_bytes(bytes(data))


def _truncate(path, rng):
    data = path.read_bytes()
    path.write_bytes(data[:rng.randrange(len(data))])


def _truncate_with_matching_manifest(npz, rng):
    """A half-written chunk whose manifest (forged) matches it: unreadable, so redone."""
    data = npz.read_bytes()[:rng.randrange(1, len(npz.read_bytes()))]
    npz.write_bytes(data)
    manifest = npz.with_suffix(".json")
    record = json.loads(manifest.read_text())
    record.update(bytes=len(data), sha256=hashlib.sha256(data).hexdigest())
    manifest.write_text(json.dumps(record))


def _other_chunk(npz, rng):
    """The file of another chunk under this chunk's name (manifest and all)."""
    others = sorted(p for p in npz.parent.glob("chunk-*.npz") if p != npz and p.with_suffix(".json").exists())
    donor = rng.choice(others)
    npz.write_bytes(donor.read_bytes())
    npz.with_suffix(".json").write_bytes(donor.with_suffix(".json").read_bytes())


def _foreign_fingerprint(npz, rng):
    manifest = npz.with_suffix(".json")
    record = json.loads(manifest.read_text())
    record["fingerprint"] = hashlib.sha256(str(rng.random()).encode()).hexdigest()
    manifest.write_text(json.dumps(record))


DAMAGES = {
    "npz byte flipped": lambda npz, rng: _flip(npz, rng),
    "npz truncated": lambda npz, rng: _truncate(npz, rng),
    "npz empty": lambda npz, rng: npz.write_bytes(b""),
    "manifest missing": lambda npz, rng: npz.with_suffix(".json").unlink(),
    "manifest truncated": lambda npz, rng: _truncate(npz.with_suffix(".json"), rng),
    "manifest byte flipped": lambda npz, rng: _flip(npz.with_suffix(".json"), rng),
    "half-written chunk with a matching manifest": _truncate_with_matching_manifest,
    "another chunk's files": _other_chunk,
    "manifest of another study": _foreign_fingerprint,
}


def _small_spec():
    return {"seed": 5, "samples": 12, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0},
        {"key": "suspensions.mount-RR.stiffness", "apply": "scale", "distribution": "uniform",
         "low": 0.9, "high": 1.1}],
        "analyses": {"modes": {"speed_rpm": 1000.0}, "campbell": {"speeds_rpm": "0:3000:7"}}}


def test_damaged_checkpoints_are_detected_and_redone_never_trusted(tmp_path, caplog):
    """Round 0 damages nine chunks, one of each kind; later rounds a random set at random."""
    model = rdm.load_model(EXAMPLE)
    fresh = rdm.study(model, _small_spec(), chunk_size=1)
    rng = random.Random(4)
    names = list(DAMAGES)
    for trial in range(max(CORRUPTIONS, 1)):
        folder = tmp_path / f"c{trial}"
        rdm.study(model, _small_spec(), checkpoint=folder, chunk_size=1)  # twelve chunks, all kept
        if trial == 0:
            plan = dict(zip(rng.sample(range(12), len(names)), names))
        else:
            plan = {index: rng.choice(names) for index in rng.sample(range(12), rng.randint(1, 6))}
        for index, name in sorted(plan.items()):
            DAMAGES[name](folder / f"chunk-{index:06d}.npz", rng)
        caplog.clear()
        with caplog.at_level(logging.INFO, logger="rotordyn_modal.study"):
            resumed = rdm.study(model, _small_spec(), checkpoint=folder, chunk_size=1)
        log = chunk_log(caplog.text)
        assert log["computed"] == set(plan), (plan, caplog.text)
        assert log["resumed"] == set(range(12)) - set(plan)
        assert resumed.resumed_chunks == 12 - len(plan)
        for name in fresh.dataset.data_vars:
            np.testing.assert_array_equal(resumed.dataset[name].values, fresh.dataset[name].values)
        assert finished_chunks(folder) == set(range(12))  # the redone chunks are saved whole


def test_an_unreadable_study_manifest_discards_the_checkpoint(tmp_path, caplog):
    model = rdm.load_model(EXAMPLE)
    folder = tmp_path / "c"
    fresh = rdm.study(model, _small_spec(), checkpoint=folder, chunk_size=3)
    (folder / "study.json").write_bytes(b'{"fingerprint": "ab')
    with caplog.at_level(logging.INFO, logger="rotordyn_modal.study"):
        again = rdm.study(model, _small_spec(), checkpoint=folder, chunk_size=3)
    assert chunk_log(caplog.text) == {"computed": set(range(4)), "resumed": set()}
    np.testing.assert_array_equal(again.dataset["modal_frequency_hz"].values,
                                  fresh.dataset["modal_frequency_hz"].values)


# ------------------------------------------------------------------------- one writer at a time
def test_a_second_study_on_the_same_results_is_refused_while_the_first_runs(spec, reference, tmp_path):
    out = tmp_path / "r.nc"
    first = subprocess.Popen(study_command(spec, out), stderr=subprocess.PIPE, text=True)
    lock = tmp_path / "r.nc.lock"
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and not (lock.exists() and lock.read_text().strip()):
        time.sleep(0.02)
    assert lock.read_text().split()[0] == str(first.pid)
    second = subprocess.run(study_command(spec, out), capture_output=True, text=True)
    err = [line for line in second.stderr.splitlines() if line.strip()]
    assert second.returncode == 2 and len(err) == 1, second.stderr
    assert "another study" in err[0] and str(first.pid) in err[0] and str(out) in err[0]
    _, text = first.communicate()
    assert first.returncode == 0, text
    assert chunk_log(text)["computed"] == set(range(N_CHUNKS))  # the first was not disturbed
    assert_same_results(out, reference["out"])
    assert not lock.exists()


def test_a_stale_lock_of_a_dead_process_is_taken_over(spec, reference, tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    out = tmp_path / "r.nc"
    (tmp_path / "r.nc.lock").write_text(f"{dead.pid} somehost\n")
    run = subprocess.run(study_command(spec, out), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert f"of process {dead.pid} somehost (no longer running) taken over" in run.stderr
    assert_same_results(out, reference["out"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc"]


@pytest.mark.parametrize("naming", ["link-to-file", "linked-folder"])
def test_a_second_study_naming_the_results_through_a_link_is_refused(naming, spec, tmp_path):
    out = tmp_path / "r.nc"
    if naming == "link-to-file":
        other = tmp_path / "alias.nc"
        other.symlink_to(out)  # dangling until the first study writes r.nc
    else:
        (tmp_path / "linked").symlink_to(tmp_path)
        other = tmp_path / "linked" / "r.nc"
    first = subprocess.Popen(study_command(spec, out), stderr=subprocess.PIPE, text=True)
    lock = tmp_path / "r.nc.lock"
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and not (lock.exists() and lock.read_text().strip()):
        time.sleep(0.02)
    second = subprocess.run(study_command(spec, other), capture_output=True, text=True)
    err = [line for line in second.stderr.splitlines() if line.strip()]
    first.communicate()
    assert second.returncode == 2 and len(err) == 1, second.stderr
    assert "another study" in err[0] and str(first.pid) in err[0]
    assert first.returncode == 0


def test_two_names_of_one_file_share_its_lock(tmp_path):
    """In one process too (the file's own lock is held by its open file, not by the process):
    a hard link in another folder is the same results file; the second lock is refused with
    the one-line message, leaves no lock file of its own, and is free once the first is let go."""
    from rotordyn_modal.errors import OutputError
    from rotordyn_modal.study.execution import ResultsLock

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first, second = tmp_path / "a" / "r.nc", tmp_path / "b" / "alias.nc"
    first.write_bytes(b"earlier results")
    os.link(first, second)
    with ResultsLock(first):
        with pytest.raises(OutputError) as refused:
            with ResultsLock(second):
                pass
        assert os.listdir(tmp_path / "b") == ["alias.nc"]
    message = str(refused.value)
    assert "\n" not in message and message.startswith(f"{second}: another study")
    if Path("/proc/locks").exists():
        assert f"(process {os.getpid()})" in message
    with ResultsLock(second):
        pass
    assert sorted(os.listdir(tmp_path / "a")) == ["r.nc"] and os.listdir(tmp_path / "b") == ["alias.nc"]


def test_a_study_writing_a_hard_link_of_results_being_written_is_refused_before_its_work(spec, tmp_path, capsys):
    """The command line: exit 2, one line naming the file and the study writing it, nothing written."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.study.execution import ResultsLock

    out, other = tmp_path / "r.nc", tmp_path / "elsewhere" / "alias.nc"
    out.write_bytes(b"earlier results")
    other.parent.mkdir()
    os.link(out, other)
    with ResultsLock(out):       # the first study, writing r.nc
        code = main(["study", EXAMPLE, "--spec", str(spec), "--out", str(other), "--quiet"])
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1, err
    assert f"{other}: another study" in err[0] and "is writing it" in err[0]
    assert os.listdir(other.parent) == ["alias.nc"] and other.read_bytes() == b"earlier results"


# ------------------------------------------------------------------------- a worker killed (out of memory)
def _killing_run_chunk(task):
    """``run_chunk``, but the worker computing chunk 2 is killed as the out-of-memory killer
    would (once, or every time when ``KILL_ALWAYS`` exists; never the study's own process)."""
    from rotordyn_modal.study import execution

    marker = Path(os.environ["ROTORDYN_TEST_KILL_MARKER"])
    if task.index == 2 and os.getpid() != int(os.environ["ROTORDYN_TEST_PARENT"]) \
            and (marker.with_name("KILL_ALWAYS").exists() or not marker.exists()):
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return execution._real_run_chunk(task)


def _run_with_killer(argv, tmp_path, monkeypatch, capsys):
    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    monkeypatch.setenv("ROTORDYN_TEST_KILL_MARKER", str(tmp_path / "killed"))
    monkeypatch.setenv("ROTORDYN_TEST_PARENT", str(os.getpid()))
    monkeypatch.setattr(execution, "_real_run_chunk", execution.run_chunk, raising=False)
    monkeypatch.setattr(execution, "run_chunk", _killing_run_chunk)
    code = main(argv)
    return code, capsys.readouterr().err


def _small_study_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('seed = 5\nsamples = 24\nchunk_size = 3\n[[parameters]]\nkey = "stator.mass"\n'
                    'distribution = "uniform"\nlow = 140.0\nhigh = 160.0\n[analyses.campbell]\n'
                    'speeds_rpm = "0:3000:7"\n')
    return path


def test_a_killed_worker_is_replaced_and_its_chunk_computed(tmp_path, monkeypatch, capsys):
    from rotordyn_modal.cli import main

    spec = _small_study_file(tmp_path)
    assert main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "serial.nc"), "--quiet"]) == 0
    out = tmp_path / "r.nc"
    code, err = _run_with_killer(["study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--workers", "2",
                                  "--quiet"], tmp_path, monkeypatch, capsys)
    assert (tmp_path / "killed").exists()  # a worker was killed
    assert code == 0, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "warning: a worker process died" in lines[0], err
    assert_same_results(out, tmp_path / "serial.nc")
    assert not (tmp_path / "r.nc.partial").exists()


def test_a_worker_killed_twice_stops_the_study_with_one_line_and_a_rerun_resumes(tmp_path, monkeypatch, capsys):
    from rotordyn_modal.cli import main

    spec = _small_study_file(tmp_path)
    (tmp_path / "KILL_ALWAYS").touch()
    out = tmp_path / "r.nc"
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--workers", "4", "--quiet"]
    code, err = _run_with_killer(argv, tmp_path, monkeypatch, capsys)
    lines = err.strip().splitlines()
    assert code == 1 and len(lines) == 2 and "Traceback" not in err, err  # the warning, then the error
    saved = finished_chunks(tmp_path / "r.nc.partial")
    assert 2 not in saved
    assert "a worker process died twice" in lines[1]
    if saved:
        assert f"{len(saved)} finished chunks kept in {tmp_path / 'r.nc.partial'} for the next run" in lines[1]
    else:        # the pool died twice before any chunk finished (a loaded machine): nothing to keep
        assert "chunks kept" not in lines[1] and not (tmp_path / "r.nc.partial").exists(), err
    assert not out.exists()
    monkeypatch.undo()
    assert main(argv + ["--verbose"]) == 0
    log = chunk_log(capsys.readouterr().err)
    assert log["resumed"] == saved and log["computed"] == set(range(8)) - saved
    assert main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "serial.nc"), "--quiet"]) == 0
    assert_same_results(out, tmp_path / "serial.nc")


class _DaskClusterKillingChunk2:
    """What ``--scheduler`` gets from a dask cluster whose workers all die running chunk 2
    (the scheduler has computed a lost worker's chunk elsewhere up to its allowed failures,
    then gives up with ``KilledWorker``): the chunks before it arrive, then the error."""

    def __init__(self, args, attempt=1):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def map(self, function, tasks):
        from types import SimpleNamespace

        from distributed import KilledWorker

        for task in tasks:
            if task.index == 2:
                raise KilledWorker(f"run_chunk-{task.index}", SimpleNamespace(address="tcp://10.0.0.7:40001"), 3)
            yield function(task)


def test_a_dask_chunk_whose_workers_all_died_stops_the_study_with_one_line_and_a_rerun_resumes(
        tmp_path, monkeypatch, capsys):
    pytest.importorskip("distributed")
    from rotordyn_modal.cli import main
    from rotordyn_modal.cli import study as study_command_module

    spec = tmp_path / "s.toml"
    spec.write_text(_small_study_file(tmp_path).read_text().replace("samples = 24", "samples = 12"))
    out = tmp_path / "r.nc"
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--quiet"]
    monkeypatch.setattr(study_command_module, "_executor", _DaskClusterKillingChunk2)
    code = main(argv + ["--scheduler", "tcp://10.0.0.5:8786"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and len(lines) == 1, lines
    saved = finished_chunks(tmp_path / "r.nc.partial")
    assert saved == {0, 1}
    assert "every dask worker that ran one chunk died (4 workers" in lines[0]
    assert f"2 finished chunks kept in {tmp_path / 'r.nc.partial'} for the next run" in lines[0]
    assert not out.exists()
    monkeypatch.undo()
    assert main(argv + ["--verbose"]) == 0
    log = chunk_log(capsys.readouterr().err)
    assert log["resumed"] == {0, 1} and log["computed"] == {2, 3}
    assert out.exists() and not (tmp_path / "r.nc.partial").exists()


# ------------------------------------------------------------------------- checkpoints that cannot be one
def test_a_file_where_the_checkpoint_folder_goes_is_refused_with_one_line(tmp_path, capsys):
    from rotordyn_modal.cli import main

    spec = _small_study_file(tmp_path)
    (tmp_path / "r.nc.partial").write_text("my notes\n")
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]
    for _ in range(2):  # and the same again: never an internal error
        code = main(argv)
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1, err
        assert "r.nc.partial: a file is where the study keeps its checkpoint folder" in err
    assert (tmp_path / "r.nc.partial").read_text() == "my notes\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc.partial", "s.toml"]


@pytest.mark.parametrize("which", ["study.json", "chunk-000001.json"])
def test_a_manifest_of_deeply_nested_brackets_is_discarded_not_an_internal_error(which, tmp_path, capsys, caplog):
    from rotordyn_modal.cli import main

    spec = _small_study_file(tmp_path)
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]
    assert main(argv) == 0
    reference = tmp_path / "reference.nc"
    (tmp_path / "r.nc").rename(reference)
    folder = tmp_path / "r.nc.partial"
    rdm.study(rdm.load_model(EXAMPLE), spec, checkpoint=folder)  # a full checkpoint, as a killed run leaves
    (folder / which).write_text("[" * 200_000 + "]" * 200_000)
    with caplog.at_level(logging.WARNING, logger="rotordyn_modal.study"):
        code = main(argv)
    err = capsys.readouterr().err
    assert code == 0 and "Traceback" not in err, err
    assert ("unreadable" if which == "study.json" else "chunk 1 ") in caplog.text
    assert_same_results(tmp_path / "r.nc", reference)
    assert not folder.exists()


def test_sigterm_to_the_process_group_stops_the_study_keeping_its_chunks(spec, reference, tmp_path):
    """What a batch scheduler or ``timeout`` does: SIGTERM to the study and its workers."""
    out = tmp_path / "r.nc"
    process = subprocess.Popen(study_command(spec, out), stderr=subprocess.PIPE, text=True,
                               start_new_session=True)
    seen, text = 0, ""
    while seen < 2:
        line = process.stderr.readline()
        assert line, text
        text += line
        seen += bool(_CHUNK_LINE.search(line))
    workers = children_of(process.pid)
    os.killpg(process.pid, signal.SIGTERM)
    _, rest = process.communicate(timeout=60)
    assert process.returncode == 128 + signal.SIGTERM, text + rest
    assert "terminated by SIGTERM" in rest and "Traceback" not in rest
    deadline = time.monotonic() + 10
    while any(alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(alive(w) for w in workers)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc.partial"]  # no lock, no temporary
    kept = finished_chunks(tmp_path / "r.nc.partial")
    assert len(kept) >= 2 and all(not p.name.startswith(".") for p in (tmp_path / "r.nc.partial").iterdir())
    rerun = subprocess.run(study_command(spec, out), capture_output=True, text=True)
    assert rerun.returncode == 0, rerun.stderr
    assert chunk_log(rerun.stderr)["resumed"] == kept
    assert_same_results(out, reference["out"])
