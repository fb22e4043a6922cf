"""``campbell``'s lowest modes run their batches in the calling thread below ``_lowest.POOL_FROM``
coordinates (``_batches.calling_thread``): the same bits as with the pool's threads."""

from __future__ import annotations

import threading
import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, _lowest
from rotordyn_modal.io.ross_file import read_ross_rotor

DATA = Path(__file__).parent / "data" / "ross"


def _threads_of_parts(monkeypatch, single):
    """The threads that ran the parts of a batch large enough to be shared (4 threads asked)."""
    monkeypatch.setenv(_batches.THREADS_ENVIRONMENT, "4")
    seen = []

    def part(values):
        seen.append(threading.get_ident())
        return values * 2

    values = np.arange(64.0)
    with _batches.calling_thread(single):
        doubled = _batches._threaded(part, values, item_bytes=2**20)
    assert np.array_equal(doubled, 2 * values)
    return seen


def test_calling_thread_keeps_every_part_in_the_caller(monkeypatch):
    """Within ``calling_thread()`` one part, run by the calling thread; without, four parts, by the
    pool's threads."""
    assert _threads_of_parts(monkeypatch, True) == [threading.get_ident()]
    pooled = _threads_of_parts(monkeypatch, False)
    assert len(pooled) == 4 and threading.get_ident() not in pooled


def test_lowest_campbell_is_the_same_in_one_thread(monkeypatch):
    """ROSS's compressor_example (224 coordinates, below POOL_FROM), lowest 12 at 21 speeds: the
    roots and shapes in the calling thread equal those with the pool's threads (POOL_FROM 0) bit for
    bit, and the route ran no part in another thread."""
    monkeypatch.setenv(_batches.THREADS_ENVIRONMENT, "4")
    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    speeds = np.linspace(628.3185307179587, 1047.1975511965977, 21)
    assert model.dofs.n < _lowest.POOL_FROM
    pooled, calls = _batches._pooled, []

    def recording(function, parts):
        calls.append(function)
        return pooled(function, parts)

    monkeypatch.setattr(_batches, "_pooled", recording)
    one = rdm.campbell(model, speeds, critical=False, modes=12)
    assert not calls
    monkeypatch.setattr(_lowest, "POOL_FROM", 0)
    shared = rdm.campbell(rdm.Model.from_dict(read_ross_rotor(path), source=path), speeds, critical=False, modes=12)
    assert calls
    assert np.array_equal(one.eigenvalues, shared.eigenvalues)
    assert np.array_equal(one.shapes, shared.shapes)
