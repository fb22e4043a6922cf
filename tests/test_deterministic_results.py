"""A result depends on its input alone: not on the work parts' sizes, the threads (ours and BLAS's)
or the run (issue 28; a Campbell run under heavy load once warned of a fallback that later runs
did not give: that was the double root at rest of the code before its fix, given on every run).

- The lowest modes' roots, shapes, whirl, critical speeds and warnings are bit for bit the same
  with every work part of the sweep one item long and with every part whole. On main they were
  not: a speed's projected pencil was taken relative to the first speed asked with it
  (``_lowest_starts._projected_starts``), so a restarted speed's start, and so its root's last
  bits, depended on which other speeds its part held.
- The same call in fresh processes with ``OPENBLAS_NUM_THREADS`` 1 and 2 and
  ``ROTORDYN_MODAL_THREADS`` 1 and 4 gives the same bits (every dense step runs one BLAS thread
  per item; the thread pools' parts are gathered in order).

Models: compressor_rotor (53 coordinates), flexible_pump_on_mounts (68, bearings on a casing)
and a 100-coordinate shaft (benchmarks/bench_flexible.py's fan shaft), each with ``modes`` and
with ``max_frequency``.
"""

from __future__ import annotations

import hashlib
import importlib
import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest_starts
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack

from shaft_models import fan_shaft

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

ROOT = Path(__file__).resolve().parents[1]
RPM = np.pi / 30

#: every work-part size of the sweep (module, name); ``_batches.CHUNK_BYTES`` apart (below)
PARTS = [("_batches", "_PART_BYTES"), ("_batches", "_THREAD_BYTES"), ("_lowest", "_MOVE_BYTES"),
         ("_lowest", "_LEVEL_BYTES"), ("_lowest", "_NEWTON_BYTES"), ("_pencils", "_SKIP_BYTES"),
         ("_roots", "_BALANCE_BYTES"), ("_crossing_roots", "_RITZ_BYTES"),
         ("_crossing_brackets", "_LINES_BYTES"), ("_crossing_brackets", "_ENDS_BYTES"),
         ("campbell", "_REORDER_BYTES"), ("tracking", "_MAC_BYTES"), ("mode_numbers", "_PART_BYTES")]


def _cases():
    """(name, model, speeds [rad/s], keywords of campbell)."""
    compressor = rdm.load_model(ROOT / "examples" / "compressor_rotor.toml")
    pump = rdm.load_model(ROOT / "examples" / "flexible_pump_on_mounts.toml")
    shaft = fan_shaft(100)
    return [("compressor", compressor, np.linspace(0, 12000, 61) * RPM, {"modes": 6}),
            ("compressor", compressor, np.linspace(0, 12000, 61) * RPM, {"max_frequency": 500.0}),
            ("pump", pump, np.linspace(0, 6000, 31) * RPM, {"modes": 8}),
            ("pump", pump, np.linspace(0, 6000, 31) * RPM, {"max_frequency": 300.0}),
            ("shaft", shaft, np.linspace(0, 1500, 31), {"modes": 6}),
            ("shaft", shaft, np.linspace(0, 1500, 31), {"max_frequency": 400.0})]


def _digest(result) -> str:
    """sha256 of every number and label of a Campbell result (roots, shapes, whirl, critical speeds)."""
    h = hashlib.sha256()
    arrays = [result.eigenvalues, result.shapes, result.whirl_ratios, result.whirl, result.modes]
    table = result.critical
    arrays += [table.source, table.order, table.mode, table.speeds, table.frequencies_hz, table.whirl,
               table.whirl_ratios, table.damping_ratios]
    for array in arrays:
        array = np.asarray(array)
        h.update(repr((array.dtype.str, array.shape)).encode())
        h.update(repr(array.tolist()).encode() if array.dtype == object else array.tobytes())   # not pointers
    return h.hexdigest()


def _run(model, speeds, keywords, critical=True):
    """The result's digest and its warnings' texts (sorted)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.campbell(model, speeds, orders=(1, 2), critical=critical, **keywords)
    return _digest(result), sorted({str(w.message) for w in caught})


def _all_runs(critical=True):
    return {f"{name} {keywords}": _run(model, speeds, keywords, critical)
            for name, model, speeds, keywords in _cases()}


def _set_parts(monkeypatch, size, names=PARTS):
    for module, name in names:
        monkeypatch.setattr(importlib.import_module(f"rotordyn_modal.analysis.{module}"), name, size)


def test_projected_starts_are_each_speeds_own():
    """A speed's projected roots and vectors, asked alone, among a few speeds, or with the whole
    sweep, are the same bits (main: taken relative to the first speed asked, they differed)."""
    for name, model, speeds, _ in _cases()[::2]:
        stack = Stack([model])
        pencils = _Pencils(stack, speeds)
        basis = np.linalg.qr(np.random.default_rng(3).standard_normal((stack.n_dof, 12)))[0]
        starts, vectors = _lowest_starts._projected_starts(pencils, basis, 4)
        for rows in (np.array([7]), np.array([3, 7, 20]), np.array([29, 7])):
            some, some_vectors = _lowest_starts._projected_starts(pencils, basis, 4, rows)
            assert np.array_equal(some, starts[rows]), (name, rows)
            assert np.array_equal(some_vectors, vectors[rows]), (name, rows)


def test_parts_of_one_item_and_whole_parts_give_the_same_bits(monkeypatch):
    """Every work part of the sweep one item long, then as large as the whole work: the same
    digest and warnings as the default parts, for each model and route."""
    default = _all_runs()
    _set_parts(monkeypatch, 1)
    tiny = _all_runs()
    _set_parts(monkeypatch, 2**30)
    whole = _all_runs()
    for key in default:
        assert tiny[key] == default[key], key
        assert whole[key] == default[key], key


def test_chunks_of_one_item_give_the_same_roots(monkeypatch):
    """``_batches.CHUNK_BYTES`` (the stacks' chunks, the projected pencils' parts) of one item: the
    same roots and shapes. The critical speeds are left out: their refinement decides some steps
    for the crossings of a chunk together (``_crossing_refinement._evaluate``), so their last bits
    depend on which crossings share a chunk (a chunk holds 512 MB: thousands of crossings)."""
    default = _all_runs(critical=False)
    _set_parts(monkeypatch, 1, [("_batches", "CHUNK_BYTES")])
    assert _all_runs(critical=False) == default


_CHILD = """
import json, sys, warnings
sys.path.insert(0, {tests!r})
import test_deterministic_results as t
print(json.dumps({{key: list(value) for key, value in t._all_runs().items()}}))
"""


def _child(blas, threads):
    """:func:`_all_runs` in a fresh process with ``blas`` BLAS threads and ``threads`` of ours."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS=str(blas), OMP_NUM_THREADS=str(blas), MKL_NUM_THREADS=str(blas),
               ROTORDYN_MODAL_THREADS=str(threads), PYTHONPATH=os.pathsep.join([str(ROOT)] + sys.path))
    done = subprocess.run([sys.executable, "-c", _CHILD.format(tests=str(ROOT / "tests"))], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def one_thread():
    """:func:`_all_runs` with one BLAS thread and one of ours."""
    return _child(1, 1)


@pytest.mark.parametrize("blas, threads", [(2, 4), (2, 1)])
def test_blas_threads_and_our_threads_give_the_same_bits(one_thread, blas, threads):
    """The same digests and warnings with 1 BLAS thread and 1 of ours as with 2 BLAS threads and
    1 or 4 of ours, in fresh processes."""
    assert _child(blas, threads) == one_thread


def test_a_repeated_run_gives_the_same_bits(one_thread):
    """This process's runs, twice, give the fresh process's digests and warnings."""
    for _ in range(2):
        assert {key: list(value) for key, value in _all_runs().items()} == one_thread


def _other_lanczos():
    """An ``eigsh`` without a start vector: ARPACK's random start sequence runs on."""
    import scipy.sparse
    import scipy.sparse.linalg

    matrix = scipy.sparse.diags([np.full(39, -1.0), np.full(40, 2.0), np.full(39, -1.0)], [-1, 0, 1]).tocsc()
    scipy.sparse.linalg.eigsh(matrix, k=3, sigma=-1e-3, which="LM")


def test_the_route_tests_lanczos_modes_do_not_depend_on_earlier_solves():
    """The cheap route test's undamped modes (``_lowest_route._cheap_modes``) of the 100-coordinate
    shaft, made twice on fresh stacks with another Lanczos solve between: the same bits (main:
    ARPACK's default start, drawn from a sequence that runs on in the process, gave other last bits
    and signs)."""
    from rotordyn_modal.analysis import _lowest_route

    model, speeds = fan_shaft(100), np.linspace(0, 1500, 31)
    made = []
    for _ in range(2):
        stack = Stack([model])
        made.append(_lowest_route._cheap_modes(stack, _Pencils(stack, speeds), 12)[2])
        _other_lanczos()
    assert np.array_equal(made[0], made[1])
