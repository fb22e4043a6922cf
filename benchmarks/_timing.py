"""Timing helper shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import time


def best_time(function, repeat: int) -> float:
    """Best wall time of ``repeat`` calls of ``function()`` [s]."""
    times = []
    for _ in range(max(1, repeat)):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def print_base_ratio(name: str, base, this, width: int = 8) -> None:
    """One line: ``name``, the base tree's and this tree's min / median / max [s] and the ratio
    base / this (min, median, max over the pairs of one repeat; above 1: this tree is faster).

    Parameters
    ----------
    base, this : sequence of float, same length
        Seconds of each repeat, the two trees run in turn.
    """
    import numpy as np

    base, this = np.asarray(base, float), np.asarray(this, float)
    ratio = base / this
    print(f"{name:{width}s} base {base.min():6.2f} {np.median(base):6.2f} {base.max():6.2f} s | "
          f"this {this.min():6.2f} {np.median(this):6.2f} {this.max():6.2f} s | "
          f"base/this {ratio.min():5.2f} {np.median(ratio):5.2f} {ratio.max():5.2f}", flush=True)
