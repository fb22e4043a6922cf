"""Outputs that cannot be written: a full disk, a file-size limit, a read-only folder, a
missing folder, a folder in the way. Each situation is made for real (a full device, an
operating-system file-size limit drawn at random below the output's size, a read-only
mount or permissions) and the command runs in a forked process, as a user would run it:
the outcome is one line naming the file and the reason, exit code 2 when the path cannot
be used (missing or read-only folder, a folder in the way) and 1 when the machine fails the
write (full disk, size limit), and the output folder is left exactly as it was (no partial
file, no temporary file). Twenty processes
writing the same output at once leave one complete file.

``ROTORDYN_MODAL_OUTPUT_TRIALS`` sets how many random size limits each output is tried
with (default 3).
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from forked import run_forked
import rotordyn_modal as rdm
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.io.measured import default_mapping
from rotordyn_modal.io.uff import write_uff58

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")
TRIALS = int(os.environ.get("ROTORDYN_MODAL_OUTPUT_TRIALS", "3"))

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork (POSIX)")


def listing(folder):
    """Name -> (size, mtime_ns) of every entry, hidden ones included."""
    return {p.name: (p.stat().st_size, p.stat().st_mtime_ns) for p in Path(folder).iterdir()}


def assert_one_clear_line(code, text, path, reason, expected_code=2):
    lines = [line for line in text.splitlines() if line.strip()]
    assert code == expected_code, text
    assert len(lines) == 1, text
    assert "Traceback" not in text
    assert str(path) in lines[0] and reason in lines[0], lines[0]


# ------------------------------------------------------------------------- the outputs
def _measured(folder):
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, rdm.rpm(3000), np.linspace(2, 40, 60))
    path = Path(folder) / "measured.uff"
    write_uff58([FRFResult(**{**res.__dict__, "coherence": np.full(res.H.shape, 0.99)})], path,
                default_mapping(model))
    return path


def _study_spec(folder):
    path = Path(folder) / "s.study.toml"
    path.write_text('seed = 3\nsamples = 4\n[[parameters]]\nkey = "stator.mass"\ndistribution = "uniform"\n'
                    'low = 140.0\nhigh = 160.0\n[analyses.modes]\nspeed_rpm = 0.0\n')
    return path


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("inputs")
    start = folder / "start.toml"
    rdm.save_model(rdm.load_model(EXAMPLE).scaled({"suspensions.mount-FL.stiffness": 1.5}), start)
    return {"measured": _measured(folder), "spec": _study_spec(folder), "start": start}


def command(kind, out, inputs):
    """The command line that writes ``out`` (an output of each kind of writer)."""
    if kind == "campbell-csv":
        return ["campbell", EXAMPLE, "--speeds", "0:3000:31", "--out", str(out), "--quiet"]
    if kind == "campbell-plot":
        return ["campbell", EXAMPLE, "--speeds", "0:3000:31", "--plot", str(out), "--quiet"]
    if kind == "study-nc":
        return ["study", EXAMPLE, "--spec", str(inputs["spec"]), "--out", str(out), "--quiet"]
    if kind == "fit-model":
        return ["fit", str(inputs["start"]), "--measured", str(inputs["measured"]), "--params",
                "suspensions.mount-FL.stiffness", "--starts", "1",
                "--out", str(out), "--quiet"]
    raise AssertionError(kind)


KINDS = {"campbell-csv": "c.csv", "campbell-plot": "c.png", "study-nc": "r.nc", "fit-model": "fitted.toml"}


@pytest.fixture(scope="module")
def full_sizes(inputs, tmp_path_factory):
    """Size of each output when written without hindrance."""
    sizes = {}
    for kind, name in KINDS.items():
        out = tmp_path_factory.mktemp(kind) / name
        code, text = run_forked(command(kind, out, inputs))
        assert code == 0, text
        sizes[kind] = out.stat().st_size
    return sizes


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_write_cut_short_by_the_size_limit_leaves_nothing(kind, inputs, full_sizes, tmp_path):
    rng = np.random.default_rng(sorted(KINDS).index(kind))
    limits = [0, *rng.integers(1, full_sizes[kind], size=TRIALS)]
    for limit in limits:
        out = tmp_path / KINDS[kind]
        before = listing(tmp_path)
        code, text = run_forked(command(kind, out, inputs), limit_bytes=int(limit))
        assert_one_clear_line(code, text, out, "File too large", 1)
        assert_only_finished_chunks_kept(tmp_path, text)
        assert listing(tmp_path) == before, f"limit {limit}: {text}"


def assert_only_finished_chunks_kept(folder, text):
    """A study whose results could not be written keeps its finished chunks (and says so)
    for the next run, and nothing else; remove them so that the folder can be compared."""
    from rotordyn_modal.study.execution import remove_checkpoint

    partial = [p for p in Path(folder).iterdir() if p.name.endswith(".partial")]
    for checkpoint in partial:
        names = sorted(p.name for p in checkpoint.iterdir())
        chunks = [n for n in names if n.endswith(".json") and n.startswith("chunk-")]
        assert chunks and f"{len(chunks)} finished chunks kept in {checkpoint}" in text, (names, text)
        assert all(not n.startswith(".") for n in names), names
        assert set(names) == {"study.json"} | set(chunks) | {n[:-5] + ".npz" for n in chunks}
        remove_checkpoint(checkpoint)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_failed_write_keeps_the_previous_file_whole(kind, inputs, full_sizes, tmp_path):
    out = tmp_path / KINDS[kind]
    out.write_bytes(b"the previous results\n")
    limit = int(np.random.default_rng(7).integers(len(b"the previous results\n") + 1, full_sizes[kind]))
    code, text = run_forked(command(kind, out, inputs), limit_bytes=limit)
    assert_one_clear_line(code, text, out, "File too large", 1)
    assert_only_finished_chunks_kept(tmp_path, text)
    assert out.read_bytes() == b"the previous results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]


@contextlib.contextmanager
def full_device(tmp_path):
    """A character device that fails every write with ENOSPC: ``/dev/full``, or (as root) a
    copy of it made in ``tmp_path`` so that no system file is ever at stake."""
    if os.geteuid() == 0:
        path = tmp_path / "full"
        try:
            os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 7))
        except OSError:
            pytest.skip("cannot make a full device here")
        yield path
    elif Path("/dev/full").exists():
        yield Path("/dev/full")
    else:
        pytest.skip("no /dev/full")


@pytest.mark.parametrize("kind", ["campbell-csv", "campbell-plot", "fit-model"])
def test_a_full_device_is_written_in_place_and_its_error_reported(kind, inputs, tmp_path):
    with full_device(tmp_path) as device:
        target = tmp_path / ("x" + Path(KINDS[kind]).suffix)
        os.symlink(device, target)  # the ending the command expects, pointing at the device
        before = listing(tmp_path)
        code, text = run_forked(command(kind, target, inputs))
        assert_one_clear_line(code, text, target, "No space left on device", 1)
        assert listing(tmp_path) == before
        assert stat.S_ISCHR(os.stat(device).st_mode)


def test_the_study_on_a_full_device_is_refused(inputs, tmp_path):
    with full_device(tmp_path) as device:
        target = tmp_path / "r.nc"
        os.symlink(device, target)
        before = listing(tmp_path)
        code, text = run_forked(command("study-nc", target, inputs))
        assert_one_clear_line(code, text, target, "No space left on device", 1)
        assert_only_finished_chunks_kept(tmp_path, text)
        assert listing(tmp_path) == before


@contextlib.contextmanager
def read_only_folder(tmp_path):
    """A folder that refuses new files: permissions for a normal user; for root (who
    ignores permissions) a read-only tmpfs mount when mounting is allowed."""
    folder = tmp_path / "locked"
    folder.mkdir()
    if os.geteuid() != 0:
        folder.chmod(0o555)
        try:
            yield folder
        finally:
            folder.chmod(0o755)
        return
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=1m", "tmpfs", str(folder)],
                             capture_output=True).returncode == 0
    if not mounted:
        pytest.skip("root without permission to mount: no way to make a read-only folder")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_read_only_folder_is_refused_before_any_work(kind, inputs, tmp_path):
    with read_only_folder(tmp_path) as folder:
        out = folder / KINDS[kind]
        code, text = run_forked(command(kind, out, inputs))
        assert_one_clear_line(code, text, out, "Read-only file system" if os.geteuid() == 0
                              else "Permission denied")
        assert list(folder.iterdir()) == []


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_folder_that_refuses_the_rename_leaves_nothing(kind, inputs, tmp_path, monkeypatch):
    """The folder turns read-only between the check and the rename (EROFS from os.replace)."""
    out = tmp_path / KINDS[kind]

    def refuse_rename():
        def replace(*args, **kwargs):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS))
        os.replace = replace

    code, text = run_forked(command(kind, out, inputs), before=refuse_rename)
    assert_one_clear_line(code, text, out, os.strerror(errno.EROFS))
    assert [p.name for p in tmp_path.iterdir()] == []


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_missing_folder_or_a_folder_in_the_way_is_refused(kind, inputs, tmp_path):
    code, text = run_forked(command(kind, tmp_path / "no-such-folder" / KINDS[kind], inputs))
    assert_one_clear_line(code, text, tmp_path / "no-such-folder", "does not exist")
    in_the_way = tmp_path / KINDS[kind]
    in_the_way.mkdir()
    code, text = run_forked(command(kind, in_the_way, inputs))
    assert_one_clear_line(code, text, in_the_way, "folder")
    assert [p.name for p in tmp_path.iterdir()] == [in_the_way.name] and not any(in_the_way.iterdir())


# ------------------------------------------------------------------------- many writers
def _writers_at_once(n, target):
    """Fork ``n`` processes that start ``target(i)`` together; returns their exit codes."""
    import multiprocessing

    context = multiprocessing.get_context("fork")
    barrier = context.Barrier(n)

    def body(i):
        os.environ["ROTORDYN_MODAL_THREADS"] = "1"
        sys.stdout = sys.stderr = open(os.devnull, "w")
        barrier.wait()
        os._exit(int(target(i) or 0))

    processes = [context.Process(target=body, args=(i,)) for i in range(n)]
    for process in processes:
        process.start()
    for process in processes:
        process.join(120)
    return [process.exitcode for process in processes]


def test_twenty_commands_writing_the_same_csv_leave_one_complete_file(tmp_path):
    from rotordyn_modal.cli import main

    reference = tmp_path / "reference.csv"
    assert main(["campbell", EXAMPLE, "--speeds", "0:3000:301", "--out", str(reference), "--quiet"]) == 0
    out = tmp_path / "same.csv"
    codes = _writers_at_once(20, lambda i: main(["campbell", EXAMPLE, "--speeds", "0:3000:301",
                                                 "--out", str(out), "--quiet"]))
    assert codes == [0] * 20
    assert out.read_bytes() == reference.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["reference.csv", "same.csv"]


def test_twenty_writers_of_a_model_and_of_study_results_leave_one_complete_file(tmp_path):
    """The two other kinds of atomic writer: a binary stream (model TOML) and a writer
    that takes a file name (netCDF). Each process writes its own distinct content, so
    the file must be exactly one of them, whole."""
    model = rdm.load_model(EXAMPLE)
    variants = [model.scaled({"stator.mass": (100.0 + i) / 150.0}) for i in range(20)]
    masses = {v.get("stator.mass") for v in variants}         # as written (scaling rounds)
    assert len(masses) == 20
    out = tmp_path / "m.toml"
    assert _writers_at_once(20, lambda i: rdm.save_model(variants[i], out)) == [0] * 20
    assert rdm.load_model(out).get("stator.mass") in masses
    result = rdm.study(model, {"seed": 1, "samples": 3, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"modes": {"speed_rpm": 0.0}}})
    nc = tmp_path / "r.nc"

    def save(i):
        ds = result.dataset.copy()
        ds.attrs["writer"] = i
        type(result)(ds).save(nc)

    assert _writers_at_once(20, save) == [0] * 20
    loaded = rdm.load_study(nc)
    assert int(loaded.dataset.attrs["writer"]) in range(20)
    np.testing.assert_array_equal(loaded.dataset["modal_frequency_hz"].values,
                                  result.dataset["modal_frequency_hz"].values)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.toml", "r.nc"]


@pytest.mark.parametrize("umask", [0o022, 0o077], ids=["umask-022", "umask-077"])
def test_an_output_gets_the_permissions_any_new_file_gets(tmp_path, umask):
    """Written through a temporary file (created private), the output still ends up with the
    mode the user's umask gives every new file: readable by others where it lets them."""
    from rotordyn_modal.io.atomic import atomic_write

    previous = os.umask(umask)
    try:
        with atomic_write(tmp_path / "out.csv") as handle:
            handle.write("a,b\n")
        with open(tmp_path / "plain.csv", "w") as handle:
            handle.write("a,b\n")
    finally:
        os.umask(previous)
    mode = stat.S_IMODE((tmp_path / "out.csv").stat().st_mode)
    assert mode == stat.S_IMODE((tmp_path / "plain.csv").stat().st_mode) == 0o666 & ~umask


# ------------------------------------------------------------------------- two outputs of one command
def test_when_the_second_output_fails_the_first_is_not_written_either(tmp_path):
    """``--out`` is written before ``--plot``; a size limit between their sizes fails the
    figure: the table must not be left behind, since the message says nothing was written."""
    sizes = {}
    for name in ("a.csv", "a.png"):
        code, text = run_forked(["campbell", EXAMPLE, "--speeds", "0:3000:31", "--quiet",
                                 "--out" if name.endswith(".csv") else "--plot", str(tmp_path / name)])
        assert code == 0, text
        sizes[name] = (tmp_path / name).stat().st_size
        (tmp_path / name).unlink()
    assert sizes["a.csv"] < sizes["a.png"]
    out, plot = tmp_path / "c.csv", tmp_path / "c.png"
    code, text = run_forked(["campbell", EXAMPLE, "--speeds", "0:3000:31", "--quiet", "--out", str(out),
                             "--plot", str(plot)], limit_bytes=sizes["a.csv"] + 1)
    assert_one_clear_line(code, text, plot, "File too large", 1)
    assert "nothing was written" in text
    assert listing(tmp_path) == {}


def test_a_rename_failing_at_the_end_names_the_outputs_that_were_written(tmp_path, monkeypatch, capsys):
    """The outputs are renamed into place together at the end; should the second rename
    fail (the folder's permissions changed meanwhile), the message says which is in place."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.io import atomic

    renames = []

    def replace(source, target):
        if Path(target).parent != tmp_path:  # someone else's rename (a cache)
            return os.rename(source, target)
        renames.append(target)
        if len(renames) == 2:
            raise PermissionError(errno.EACCES, "Permission denied")
        os.rename(source, target)

    monkeypatch.setattr(atomic.os, "replace", replace)
    out, plot = tmp_path / "c.csv", tmp_path / "c.png"
    code = main(["campbell", EXAMPLE, "--speeds", "0:3000:7", "--quiet", "--out", str(out), "--plot", str(plot)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert f"cannot write {plot}: Permission denied (only {out} was written)" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.csv"]
