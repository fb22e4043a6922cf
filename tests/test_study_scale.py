"""Studies whose results are large: memory holds the results once (assembled chunk by chunk
into arrays of their final size, written to netCDF a block at a time), and a study whose
results cannot fit is refused before any work, with the estimate. Each runs in a forked
process under an address-space limit (RLIMIT_AS, as ``ulimit -v`` sets), its chunks made
quickly by a stand-in of ``run_chunk`` with the real shapes (what is measured is what the
package does with the results, not the analyses)."""

from __future__ import annotations

import os
import re
import resource
from pathlib import Path

import numpy as np
import pytest
from forked import run_forked
from study_stand_in import stand_in_chunk

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")

pytest.importorskip("xarray")
pytestmark = pytest.mark.skipif(not hasattr(os, "fork") or not Path("/proc/self/status").exists(),
                                reason="fork and /proc (Linux)")

SPEC = """seed = 1
samples = {samples}
design = "monte-carlo"
[[parameters]]
key = "stator.mass"
distribution = "uniform"
low = 140.0
high = 160.0
[analyses.campbell]
speeds_rpm = "0:6000:{speeds}"
"""
MODES = 6  # the gear machine's roots per speed


def _vm_size() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmSize:"):
            return int(line.split()[1]) * 1024
    raise AssertionError("no VmSize")


def _run_limited(argv, headroom: int, stand_in=True):
    """``main(argv)`` in a forked child whose address space may grow by ``headroom`` bytes
    beyond what it takes once everything is imported; (exit code, stderr)."""
    def limited():
        import pandas  # noqa: F401 - everything the study imports, before the limit
        import scipy.io  # noqa: F401
        import scipy.stats  # noqa: F401
        import xarray  # noqa: F401

        import rotordyn_modal.cli  # noqa: F401
        from rotordyn_modal.study import execution

        def never(task):
            raise AssertionError("a chunk was computed")

        execution.run_chunk = stand_in_chunk if stand_in else never
        limit = _vm_size() + headroom
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    return run_forked(argv, before=limited)


def test_results_three_times_larger_than_the_spare_memory_would_need_are_written(tmp_path):
    """8,000 variants x 201 speeds x 6 modes x 4 quantities = 309 MB of results, under a
    limit that leaves 1.3 times that and 128 MiB (the command's own growth: the model, a
    chunk): holding the chunks, their concatenation and the netCDF writer's copies (as
    before) needs three to four times the results."""
    samples, speeds = 8000, 201
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=samples, speeds=speeds))
    results = samples * speeds * MODES * 4 * 8
    out = tmp_path / "r.nc"
    code, text = _run_limited(["study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--quiet",
                               "--chunk-size", "250"], headroom=int(1.3 * results) + 2**27)
    assert code == 0, text
    import xarray as xr

    with xr.open_dataset(out, engine="scipy") as ds:
        assert ds.sizes["variant"] == samples
        frequency = ds["frequency_hz"]
        for variant in (0, 1, samples // 2, samples - 1):
            assert np.all(frequency[variant].values == variant)  # each row in its place
        assert np.all(ds["failed"].values == 0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc", "s.toml"]


def test_a_study_that_cannot_fit_is_refused_before_any_work_with_the_estimate(tmp_path):
    """Written to its file chunk by chunk, a study still reads some numbers of every variant
    whole afterwards (here one parameter and one mode's 201 frequencies for the Campbell band,
    three copies: 4.8 kB a variant): a million variants under a 2 GiB limit are refused before
    any work, in one line naming the study file, its key and value, the estimate and the limit."""
    samples, speeds = 1_000_000, 201
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=samples, speeds=speeds))
    code, text = _run_limited(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc")],
                              headroom=2**31, stand_in=False)
    lines = text.strip().splitlines()
    assert code == 2 and len(lines) == 1, text
    assert lines[0].startswith(f"rotordyn-modal study: error: {spec}: samples = {samples}: 1,000,000 variants"), lines[0]
    assert "ulimit -v" in lines[0] and "GB left" in lines[0]
    estimate = float(re.search(r"need about ([0-9.]+) GB of memory", lines[0]).group(1)) * 1e9
    held = samples * 3 * 8 * (1 + speeds)          # the parameter and one mode's band, three copies
    assert held <= estimate <= held + 2**28
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_results_too_large_for_memory_go_to_a_temporary_file_not_a_refusal(tmp_path):
    """``rdm.study`` without a file: 200,000 variants x 201 speeds x 6 modes x 4 quantities (1.9 GB
    of results) under a 2 GiB limit were refused (held in memory); they now go to a temporary file
    (results over ``SPOOL_BYTES``), whose memory is the per-variant numbers only (1 GB here):
    the study gets past every memory check to its temporary file in ``TMPDIR``."""
    samples, speeds = 200_000, 201
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=samples, speeds=speeds))
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        code = 99
        try:
            os.close(read)
            import tempfile

            import xarray  # noqa: F401

            import rotordyn_modal as rdm
            import rotordyn_modal.study as study

            def reached(run, folder):
                os.write(write, f"spooled in {folder}".encode())
                os._exit(3)

            os.environ["ROTORDYN_MODAL_MAX_CPU_MINUTES"] = "inf"
            tempfile.tempdir = str(tmp_path)
            study._Run.spooled = reached
            model = rdm.load_model(EXAMPLE)
            limit = _vm_size() + 2**31
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
            try:
                rdm.study(model, str(spec))
            except Exception as error:  # noqa: BLE001 - reported to the parent
                os.write(write, f"{type(error).__name__}: {error}".encode())
                code = 2
        finally:
            os._exit(code)
    os.close(write)
    with os.fdopen(read) as pipe:
        text = pipe.read()
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 3 and text == f"spooled in {tmp_path}", text


def test_the_file_written_a_block_at_a_time_is_the_one_xarray_writes(tmp_path, monkeypatch):
    """Byte for byte what xarray's own writer gives for the same data set (``variant`` the
    record dimension), with failures whose texts differ in length and hold non-ASCII
    characters, over blocks of a few variants; read back equal to the data set."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import load_study, results

    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 5, "samples": 13, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0},
        {"key": "suspensions.mount-RR.stiffness", "apply": "scale", "distribution": "uniform",
         "low": 0.9, "high": 1.1}],
        "analyses": {"modes": {"speed_rpm": 1000.0}, "campbell": {"speeds_rpm": "0:3000:7"},
                     "critical_speeds": {}}}
    ds = rdm.study(model, spec, chunk_size=4).dataset
    errors = [""] * 13
    errors[3], errors[5] = "ValueError: rotor \u00abfan\u00bb m\u00e4ss \u2264 0", "x"
    ds["error"] = ("variant", np.array(errors, dtype=str))
    monkeypatch.setattr(results, "_BLOCK_BYTES", 3000)  # blocks of a few variants
    import xarray as xr

    written_by_xarray = []
    to_netcdf = xr.Dataset.to_netcdf

    def counted(self, *args, **kwargs):
        written_by_xarray.append(self.sizes["variant"])
        return to_netcdf(self, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", counted)
    results.write_netcdf(ds, str(tmp_path / "blocks.nc"))
    assert written_by_xarray == [1]  # the header and first variant only: the rest in blocks here
    monkeypatch.undo()
    ds.to_netcdf(tmp_path / "xarray.nc", engine="scipy", format="NETCDF3_64BIT", unlimited_dims=["variant"])
    assert (tmp_path / "blocks.nc").read_bytes() == (tmp_path / "xarray.nc").read_bytes()
    back = load_study(tmp_path / "blocks.nc").dataset
    assert back.drop_encoding().identical(ds) if hasattr(back, "drop_encoding") else back.identical(ds)


def test_a_study_whose_results_cannot_fit_on_the_disk_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    """The checkpoint and the results file each hold the results: a disk with room for one of
    them only (the free space reported by the system made small) refuses the study."""
    import shutil

    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    samples, speeds = 200, 201
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=samples, speeds=speeds))
    results = samples * speeds * MODES * 4 * 8
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda path: real(path)._replace(free=int(1.5 * results)))

    def never(task):
        raise AssertionError("a chunk was computed")

    monkeypatch.setattr(execution, "run_chunk", never)
    code = main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert f"on the disk of {tmp_path / 'r.nc.partial'}" in err and "200 variants" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
