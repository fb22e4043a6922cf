"""A study's results assembled on disk (issue 27 §1.9: memory stays bounded at every size): each
chunk goes into the results file as it comes, which is byte for byte the file the results held
in memory give; a resume reads each saved chunk once; a study that cannot fit is refused in one
line naming the study file, the key and value that set its variants, the estimate and the limit.

The chunks of the memory test are made by a stand-in of ``run_chunk`` with the real shapes
(what is measured is what the package does with the results, not the analyses)."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from study_stand_in import stand_in_chunk

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")

pytest.importorskip("xarray")

SPEC = """seed = 1
samples = {samples}
design = "monte-carlo"
[[parameters]]
key = "stator.mass"
distribution = "uniform"
low = 140.0
high = 160.0
[analyses.campbell]
speeds_rpm = "0:6000:201"
"""
#: one variant's results of SPEC: 201 speeds x 6 modes x 4 quantities [bytes]
VARIANT_BYTES = 201 * 6 * 4 * 8


def _traced_peak(tmp_path, samples: int, name: str, traced: bool = True) -> int:
    """The peak of memory traced while the study command runs ``samples`` variants in chunks of
    50 [bytes] (0 where not ``traced``); the file's rows checked in their places."""
    import xarray as xr

    from rotordyn_modal.cli import main

    spec = tmp_path / f"{name}.toml"
    spec.write_text(SPEC.format(samples=samples))
    out = tmp_path / f"{name}.nc"
    if traced:
        tracemalloc.start()
    try:
        code = main(["study", EXAMPLE, "--spec", str(spec), "--out", str(out), "--quiet", "--chunk-size", "50"])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert code == 0
    with xr.open_dataset(out, engine="scipy") as ds:
        assert ds.sizes["variant"] == samples
        for variant in (0, samples // 2, samples - 1):
            assert np.all(ds["frequency_hz"][variant].values == variant)
    return peak


def test_the_memory_of_a_study_does_not_grow_with_its_chunks(tmp_path, monkeypatch):
    """4 and 16 chunks of 50 variants (7.7 and 31 MB of results): the peak of the larger study is
    that of the smaller one but for a few bytes per variant (the failure flags, the parameter),
    where it grew with the results before (held whole, 23 and 48 MB traced)."""
    from rotordyn_modal.study import execution

    monkeypatch.setattr(execution, "run_chunk", stand_in_chunk)
    _traced_peak(tmp_path, 50, "warm", traced=False)          # imports and caches out of the way
    small = _traced_peak(tmp_path, 200, "small")
    large = _traced_peak(tmp_path, 800, "large")
    assert large < small + 200 * 600, (small, large)          # under 200 bytes more per variant
    assert large < 1.1 * small, (small, large)


def _spec_with_failures():
    return {"seed": 5, "samples": 40, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 100.0, "high": 160.0},
        {"key": "suspensions.mount-RR.stiffness", "apply": "scale", "distribution": "uniform",
         "low": 0.3, "high": 1.1},
        # failures the model refuses variant by variant (a range through zero is refused as the
        # study is read): polar inertias beyond twice the diametral (0.32 and 0.1 kg m^2)
        {"key": "rotors.fan.polar_inertia", "distribution": "uniform", "low": 0.1, "high": 0.45},
        {"key": "rotors.motor.polar_inertia", "distribution": "uniform", "low": 0.02, "high": 0.12}],
        "analyses": {"modes": {"speed_rpm": 1000.0}, "campbell": {"speeds_rpm": "0:3000:7"},
                     "critical_speeds": {}}}


@pytest.mark.parametrize("block", [1, 3000, 8 * 2**20])
def test_the_file_written_chunk_by_chunk_is_the_one_of_the_results_in_memory(tmp_path, monkeypatch, block):
    """Failures of texts of different lengths (about half the variants: polar inertias beyond
    twice the diametral) widen the records at the end, a block of one variant, a few or all at a time:
    the file is byte for byte what ``StudyResult.save`` writes of the results held in memory
    (itself checked against xarray's own writer in test_study_scale.py), and the result read
    from the file gives the same summary and table."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import results

    model = rdm.load_model(EXAMPLE)
    held = rdm.study(model, _spec_with_failures(), chunk_size=3)
    assert 5 < held.failed.sum() < 35 and len(set(held.dataset["error"].values.tolist())) > 5
    held.save(tmp_path / "held.nc")
    monkeypatch.setattr(results, "_BLOCK_BYTES", block)
    streamed = rdm.study(model, _spec_with_failures(), chunk_size=3, out=tmp_path / "streamed.nc")
    assert (tmp_path / "streamed.nc").read_bytes() == (tmp_path / "held.nc").read_bytes()
    assert streamed.summary().equals(held.summary())
    assert streamed.to_dataframe().equals(held.to_dataframe())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["held.nc", "streamed.nc"]


def test_a_resume_reads_each_saved_chunk_once(tmp_path, monkeypatch):
    """Three chunks saved by an earlier run: the resumed study unpacks each once (it was twice:
    checked before the work, read again into the results) and gives the same file."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import execution

    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 3, "samples": 9, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"modes": {"speed_rpm": 0.0}}}
    fresh = rdm.study(model, spec, chunk_size=3)
    fresh.save(tmp_path / "fresh.nc")
    rdm.study(model, spec, chunk_size=3, checkpoint=tmp_path / "r.nc.partial")
    unpacked = []
    unpack = execution._unpack

    def counted(payload):
        unpacked.append(len(payload))
        return unpack(payload)

    monkeypatch.setattr(execution, "_unpack", counted)
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a saved chunk was computed"))
    resumed = rdm.study(model, spec, chunk_size=3, checkpoint=tmp_path / "r.nc.partial")
    assert resumed.resumed_chunks == 3 and len(unpacked) == 3
    resumed.save(tmp_path / "r.nc")
    assert (tmp_path / "r.nc").read_bytes() == (tmp_path / "fresh.nc").read_bytes()


GRID_SPEC = """[[parameters]]
key = "stator.mass"
values = "140:160:30"
[[parameters]]
key = "rotors.fan.diametral_inertia"
values = "0.15:0.17:40"
[analyses.campbell]
speeds_rpm = "0:6000:201"
"""


def test_a_grid_study_that_cannot_fit_is_refused_in_one_line_naming_its_key(tmp_path, monkeypatch, capsys):
    """30 x 40 grid points with 16 MiB to count on: one line naming the study file, the grids, the
    estimate and the limit."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    spec = tmp_path / "g.toml"
    spec.write_text(GRID_SPEC)
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", str(16 / 1024))
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    code = main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    line = err.strip()
    assert line.startswith(f"rotordyn-modal study: error: {spec}: [[parameters]] grids = '30 x 40 points': "
                           "1,200 variants need about 0.0"), line
    assert "more than the 0.01678 GB left (ROTORDYN_MODAL_MEMORY_GB=" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.toml"]


def test_a_study_that_cannot_fit_on_the_disk_is_refused_in_one_line_naming_its_key(tmp_path, monkeypatch, capsys):
    """The disk's refusal names the study file, ``samples = 200``, the estimate and the free space."""
    import shutil

    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=200))
    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda path: real(path)._replace(free=10**6))
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    code = main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith(f"rotordyn-modal study: error: {spec}: samples = 200: 200 variants x 38.6 kB"), err
    assert "more than the 0.001 GB free there" in err, err


def test_the_curves_read_from_the_file_are_those_load_study_reads(tmp_path, monkeypatch):
    """The result of a study written to its file reads its curves from the file as asked for
    (blocks of a few variants here): any selection, a pickled copy and the Campbell band equal
    those of the data set ``load_study`` reads whole."""
    import pickle

    import rotordyn_modal as rdm
    from rotordyn_modal.study import results

    monkeypatch.setattr(results, "_BLOCK_BYTES", 5000)
    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 2, "samples": 23, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"campbell": {"speeds_rpm": "0:3000:9"}}}
    streamed = rdm.study(model, spec, chunk_size=4, out=tmp_path / "r.nc")
    whole = rdm.load_study(tmp_path / "r.nc")
    curves, expected = streamed.dataset["frequency_hz"], whole.dataset["frequency_hz"].values
    for key in (np.s_[:], np.s_[5], np.s_[-1], np.s_[2:19:3, ::2, 1], np.s_[::-4, 3], np.s_[[7, 0, 22]]):
        np.testing.assert_array_equal(curves[key].values, expected[key])
    copy = pickle.loads(pickle.dumps(streamed))
    np.testing.assert_array_equal(copy.dataset["damping_ratio"].values, whole.dataset["damping_ratio"].values)
    for mine, theirs in zip(streamed.frequency_bands(), whole.frequency_bands()):
        np.testing.assert_array_equal(mine, theirs)


def test_a_study_over_the_cpu_time_limit_is_refused_before_any_work_unless_allowed(tmp_path, monkeypatch, capsys):
    """200 variants of a 201-speed Campbell diagram and its crossings, about 2 s of CPU time by
    the estimate the other commands use, under a limit of 0.06 s: one line naming the study file,
    ``samples = 200``, the estimate and the limit, nothing computed; ``--allow-long`` runs it."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(samples=200))
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "0.001")
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith(f"rotordyn-modal study: error: {spec}: samples = 200: 200 variants x about "), err
    assert "201 eigen-solutions of 12 states" in err and "more than the limit of 0.06 s" in err, err
    assert "--allow-long" in err and sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    monkeypatch.setattr(execution, "run_chunk", stand_in_chunk)
    assert main(argv + ["--allow-long"]) == 0
    assert (tmp_path / "r.nc").exists()
