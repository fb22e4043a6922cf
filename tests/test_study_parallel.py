"""The same study serially, on a process pool and on a dask.distributed LocalCluster gives
the same samples and the same results; workers run with one BLAS thread."""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.study.execution import limit_threads, worker_initializer

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

SPEC = {"seed": 42, "samples": 12, "design": "sobol",
        "parameters": [{"key": "suspensions.mount-FL.stiffness", "apply": "scale", "distribution": "uniform",
                        "low": 0.85, "high": 1.15},
                       {"key": "stator.mass", "distribution": "normal", "mean": 150.0, "std": 5.0}],
        "analyses": {"campbell": {"speeds_rpm": "0:6000:31"}, "critical_speeds": {},
                     "stability": {"speeds_rpm": "0:6000:11"}}}


@pytest.fixture(scope="module")
def serial(examples_dir_module):
    model = rdm.load_model(examples_dir_module / "gear_machine.toml")
    return model, rdm.study(model, SPEC, chunk_size=3)


@pytest.fixture(scope="module")
def examples_dir_module():
    from pathlib import Path

    return Path(__file__).resolve().parent.parent / "examples"


def _same(a, b):
    for name in ("sample_value", "frequency_hz", "damping_ratio", "critical_speed", "threshold_speed"):
        np.testing.assert_array_equal(a.dataset[name].values, b.dataset[name].values)
    assert list(a.dataset["error"].values) == list(b.dataset["error"].values)


def test_process_pool_gives_the_serial_samples_and_results(serial):
    model, reference = serial
    with ProcessPoolExecutor(2, initializer=worker_initializer) as pool:
        _same(rdm.study(model, SPEC, executor=pool, chunk_size=3), reference)


def test_dask_local_cluster_gives_the_serial_samples_and_results(serial):
    distributed = pytest.importorskip("distributed")
    model, reference = serial
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        _same(rdm.study(model, SPEC, executor=client.get_executor()), reference)


def test_workers_run_with_one_blas_thread_and_restore_the_settings():
    from threadpoolctl import threadpool_info

    before = os.environ.get("ROTORDYN_MODAL_THREADS")
    with limit_threads():
        assert os.environ["ROTORDYN_MODAL_THREADS"] == "1"
        assert all(pool["num_threads"] == 1 for pool in threadpool_info())
        with limit_threads():  # nested (threads of one worker)
            assert os.environ["ROTORDYN_MODAL_THREADS"] == "1"
        assert os.environ["ROTORDYN_MODAL_THREADS"] == "1"
    assert os.environ.get("ROTORDYN_MODAL_THREADS") == before


def _worker_threads(_):
    from threadpoolctl import threadpool_info

    return os.environ.get("ROTORDYN_MODAL_THREADS"), os.environ.get("OPENBLAS_NUM_THREADS"), \
        max([p["num_threads"] for p in threadpool_info()] or [1])


def test_the_pool_initializer_sets_one_thread_per_worker():
    with ProcessPoolExecutor(2, initializer=worker_initializer) as pool:
        for threads in pool.map(_worker_threads, range(2)):
            assert threads == ("1", "1", 1)
