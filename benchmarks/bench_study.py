"""Parameter study at scale: 2,000 variants x 201 speeds of the gear machine.

Runs the mount-tolerance study (``examples/mount_tolerance.study.toml``: four mount
stiffness factors, Latin hypercube; Campbell 0-6,000 rpm and its 1X critical speeds) with
2,000 samples and 201 speeds:

* serially (``executor=None``),
* on a local process pool of 2 workers (``ProcessPoolExecutor``),
* on a ``dask.distributed`` LocalCluster of 2 worker processes (``client.get_executor()``),
  with dask's statistical profiler on (its default) and off,

and compares the serial cost per variant (one core: ``ROTORDYN_MODAL_THREADS=1`` and one
BLAS thread, as in the workers) with its floor, the bare batched ``numpy.linalg.eig`` of
that variant's 201 state matrices (built beforehand), and with one ``rdm.campbell`` call.
The serial study and the floor alternate ``--repeat`` times (the machine is shared: the
ratios of each repetition, min / median / max, are what counts). The variants of a chunk
are solved as one batch (``campbell_many``). Checks that the three runs give the same
results.

    python benchmarks/bench_study.py [--variants 2000] [--speeds 201] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.study import parse_study
from rotordyn_modal.study.execution import variant_model, worker_initializer
from _timing import best_time  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def spec(variants: int, speeds: int) -> dict:
    import tomllib

    data = tomllib.loads((EXAMPLES / "mount_tolerance.study.toml").read_text())
    data["samples"] = variants
    data["analyses"]["campbell"]["speeds_rpm"] = f"0:6000:{speeds}"
    return data




def single_campbell(model, definition, count: int = 100):
    """Best-of-5 time of one campbell call: base model, and mean over `count` variant models."""
    speeds = definition.analyses["campbell"]["speeds"]
    base = best_time(lambda: rdm.campbell(model, speeds), 5)
    values = rdm.study.sample_variants(definition)[:count]
    keys = tuple(p.keys for p in definition.parameters)
    applies = tuple(p.apply for p in definition.parameters)
    models = [variant_model(model.to_dict(), model.source, keys, applies, v) for v in values]
    variants = best_time(lambda: [rdm.campbell(m, speeds) for m in models], 3) / count
    return base, variants


def bare_eig(model, definition, count: int = 200):
    """Mean time of a bare batched numpy.linalg.eig of one variant's state matrices [s]."""
    from rotordyn_modal.linear_system import speed_linear_form

    speeds = definition.analyses["campbell"]["speeds"]
    values = rdm.study.sample_variants(definition)[:count]
    keys = tuple(p.keys for p in definition.parameters)
    applies = tuple(p.apply for p in definition.parameters)
    matrices = [speed_linear_form(variant_model(model.to_dict(), model.source, keys, applies, v)).at(speeds)
                for v in values]
    return best_time(lambda: [np.linalg.eig(a) for a in matrices], 3) / len(matrices)


def timed_study(model, definition, executor=None):
    start = time.perf_counter()
    result = rdm.study(model, definition, executor=executor)
    return time.perf_counter() - start, result


def same(a, b) -> bool:
    return all(np.array_equal(a.dataset[n].values, b.dataset[n].values, equal_nan=True)
               for n in ("sample_value", "frequency_hz", "damping_ratio", "critical_speed"))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--variants", type=int, default=2000)
    parser.add_argument("--speeds", type=int, default=201)
    parser.add_argument("--repeat", type=int, default=3, help="alternations of the floor and the serial study")
    args = parser.parse_args()
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    definition = parse_study(spec(args.variants, args.speeds), "mount_tolerance", model)
    n = args.variants
    print(f"model: gear_machine.toml, {n} variants x {args.speeds} speeds, 1X critical speeds of 3 sources, "
          f"{os.cpu_count()} cores")
    rdm.study(model, spec(4, 11))  # warm-up: imports (xarray, scipy.stats) are not per-variant costs
    from threadpoolctl import threadpool_limits

    os.environ["ROTORDYN_MODAL_THREADS"] = "1"
    with threadpool_limits(1):
        base, variants = single_campbell(model, definition)
        runs = []
        for _ in range(max(1, args.repeat)):   # the floor and the serial study alternate
            floor = bare_eig(model, definition)
            serial_time, serial = timed_study(model, definition)
            runs.append((floor, serial_time))
    del os.environ["ROTORDYN_MODAL_THREADS"]
    floors, serial_times = (np.array(column) for column in zip(*runs))
    ratios = serial_times / n / floors
    middle = int(np.argsort(ratios)[len(ratios) // 2])          # the repetition of the median ratio
    floor, serial_time = floors[middle], serial_times[middle]
    per_variant = serial_time / n
    print(f"floor: bare numpy.linalg.eig of one variant's sweep     : {floor * 1e3:8.2f} ms  (one core)")
    print(f"one rdm.campbell call, base model (best of 5)           : {base * 1e3:8.2f} ms")
    print(f"one rdm.campbell call, mean over 100 variant models     : {variants * 1e3:8.2f} ms")
    print(f"study serial, one core                                  : {serial_time:8.2f} s  "
          f"({per_variant * 1e3:.2f} ms/variant = {per_variant / floor:.2f}x the floor (target <= 1.5), "
          f"{per_variant / variants:.2f}x one campbell call)")
    print(f"per variant / floor over {len(runs)} repetitions (min median max)  : "
          + " ".join(f"{r:.2f}" for r in (ratios.min(), np.median(ratios), ratios.max()))
          + "   (ms/variant " + " ".join(f"{t / n * 1e3:.2f}" for t in serial_times)
          + "; floor ms " + " ".join(f"{f * 1e3:.2f}" for f in floors) + ")")

    start = time.perf_counter()
    with ProcessPoolExecutor(2, initializer=worker_initializer) as pool:
        started = time.perf_counter() - start
        pool_time, pooled = timed_study(model, definition, pool)
    total = time.perf_counter() - start
    print(f"study, ProcessPoolExecutor(2)                           : {pool_time:8.2f} s  "
          f"speed-up {serial_time / pool_time:.2f}x  (with pool start-up and shutdown {total:.2f} s: "
          f"{serial_time / total:.2f}x)  same results: {same(pooled, serial)}")

    try:
        from distributed import Client, LocalCluster
    except ImportError:
        print("dask.distributed not installed: LocalCluster skipped")
        return
    import dask

    for profile in (True, False):  # dask's statistical profiler samples worker stacks every 10 ms
        with dask.config.set({"distributed.worker.profile.enabled": profile}):
            start = time.perf_counter()
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
                    Client(cluster) as client:
                started = time.perf_counter() - start
                cluster_time, clustered = timed_study(model, definition, client.get_executor())
        print(f"study, dask LocalCluster(2 processes), profiler {'on ' if profile else 'off'}   : {cluster_time:8.2f} s  "
              f"speed-up {serial_time / cluster_time:.2f}x  (cluster start-up {started:.2f} s)  "
              f"same results: {same(clustered, serial)}")
    print(f"failed variants: {int(serial.failed.sum())}")


if __name__ == "__main__":
    main()
