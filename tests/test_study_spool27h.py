"""``rdm.study`` without ``out=`` (a notebook's call) keeps its memory bounded (issue 27 §1.9):
results larger than ``SPOOL_BYTES`` go chunk by chunk to a temporary file, unlinked as soon as it
is opened, and the result reads its curves from it; it is the same result as one held in memory,
leaves nothing in the temporary folder, pickles with its values, and lets go of the file on
``close()``, at the end of a ``with`` block or when garbage-collected.

The chunks of the memory test are made by a stand-in of ``run_chunk`` with the real shapes (what
is measured is what the package does with the results, not the analyses)."""

from __future__ import annotations

import gc
import os
import pickle
import tempfile
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from study_stand_in import stand_in_chunk

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")

pytest.importorskip("xarray")


def _spec(samples, speeds=201):
    return {"seed": 2, "samples": samples, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"campbell": {"speeds_rpm": f"0:6000:{speeds}"}}}


@pytest.fixture
def spool(tmp_path, monkeypatch):
    """Every study's results spooled (``SPOOL_BYTES`` 0) into an empty temporary folder."""
    import rotordyn_modal.study as study

    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(study, "SPOOL_BYTES", 0, raising=False)
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def _open_spools() -> list:
    """The spooled results files this process holds open (unlinked: '... (deleted)')."""
    found = []
    for fd in os.listdir("/proc/self/fd"):
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if "rotordyn_modal-study-" in target:
            found.append(target)
    return found


def _traced_peak(model, samples: int) -> int:
    """The peak of memory traced while ``rdm.study`` runs ``samples`` variants in chunks of 50
    [bytes]; rows checked in their places."""
    import rotordyn_modal as rdm

    tracemalloc.start()
    try:
        result = rdm.study(model, _spec(samples), chunk_size=50)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    frequency = result.dataset["frequency_hz"]
    for variant in (0, samples // 2, samples - 1):
        assert np.all(frequency[variant].values == variant)
    del result, frequency
    gc.collect()
    return peak


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="Linux: /proc/self/fd")
def test_the_memory_of_a_study_without_a_file_does_not_grow_with_its_results(spool, monkeypatch):
    """200 and 800 variants of a 201-speed Campbell diagram (7.7 and 31 MB of results) without
    ``out=``: the peak of the larger is that of the smaller but for a few bytes per variant, where
    it grew with the results (held whole in memory)."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import execution

    monkeypatch.setattr(execution, "run_chunk", stand_in_chunk)
    model = rdm.load_model(EXAMPLE)
    _traced_peak(model, 50)                                    # imports and caches out of the way
    small = _traced_peak(model, 200)
    large = _traced_peak(model, 800)
    assert large < small + 200 * 600, (small, large)          # under 200 bytes more per variant
    assert large < 1.1 * small, (small, large)
    assert list(spool.iterdir()) == [] and _open_spools() == []


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="Linux: /proc/self/fd")
def test_a_spooled_result_is_the_result_held_in_memory_and_lets_go_of_its_file(spool, tmp_path, monkeypatch):
    """With failures (polar inertias beyond twice the diametral; a range of negative masses is
    refused as the study is read) and every analysis over speed: the same data set, summary,
    table and saved file as the results held in memory (``SPOOL_BYTES`` left as it is: 23
    variants stay in memory); a pickled copy carries the values; nothing is left in the
    temporary folder; ``close()``, the end of a ``with`` block and garbage collection let go of
    the unlinked file."""
    import rotordyn_modal as rdm
    import rotordyn_modal.study as study

    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 5, "samples": 23, "parameters": [   # beyond 0.32, twice the diametral: refused variant by variant
        {"key": "rotors.fan.polar_inertia", "distribution": "uniform", "low": 0.1, "high": 0.45}],
        "analyses": {"modes": {"speed_rpm": 1000.0}, "campbell": {"speeds_rpm": "0:3000:7"},
                     "critical_speeds": {}, "stability": {"speeds_rpm": "0:3000:5"}}}
    monkeypatch.setattr(study, "SPOOL_BYTES", 256 * 2**20)
    held = rdm.study(model, spec, chunk_size=4)
    assert 3 < held.failed.sum() < 20 and _open_spools() == []
    monkeypatch.setattr(study, "SPOOL_BYTES", 0)
    spooled = rdm.study(model, spec, chunk_size=4)
    assert list(spool.iterdir()) == [] and len(_open_spools()) == 5       # the curves over speed: 4 Campbell, 1 stability
    assert all(path.endswith("(deleted)") for path in _open_spools())
    assert spooled.dataset.equals(held.dataset)
    assert spooled.summary().equals(held.summary()) and spooled.to_dataframe().equals(held.to_dataframe())
    spooled.save(tmp_path / "spooled.nc")
    held.save(tmp_path / "held.nc")
    assert (tmp_path / "spooled.nc").read_bytes() == (tmp_path / "held.nc").read_bytes()
    copy = pickle.loads(pickle.dumps(spooled))
    spooled.close()
    assert _open_spools() == []
    assert copy.dataset.equals(held.dataset)
    with rdm.study(model, spec, chunk_size=4) as result:
        assert len(_open_spools()) == 5 and result.dataset.equals(held.dataset)
    assert _open_spools() == []
    result = rdm.study(model, spec, chunk_size=4)
    assert len(_open_spools()) == 5
    del result
    gc.collect()
    assert _open_spools() == [] and list(spool.iterdir()) == []


def test_results_too_large_for_the_temporary_folder_are_refused_before_any_work(spool, monkeypatch):
    """A temporary folder with less free space than the results: one line naming the study, its
    variants, the results' size, the folder and its free space, and ``out=``; nothing computed."""
    import shutil

    import rotordyn_modal as rdm
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.study import execution

    model = rdm.load_model(EXAMPLE)
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    usage = shutil.disk_usage(spool)
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage._replace(free=1_000_000))
    with pytest.raises(InputError) as refused:
        rdm.study(model, _spec(100))
    text = str(refused.value)
    results = 100 * (201 * 6 * 4 + 1) * 8 + 100 * 5             # the outputs and the parameter
    assert "\n" not in text and text.startswith("<study>: samples = 100: 100 variants x "), text
    assert f"= {results / 1e9:.4g} GB of results, kept in a temporary file in {spool}" in text, text
    assert "more than the 0.001 GB free there: give out= a file on a larger disk" in text, text
