"""Campbell sweep of the lowest modes only (``campbell(modes=N)``) against the full solve.

For flexible rotors of growing mesh (``element_length`` of ``examples/compressor_rotor.toml``,
alone; ``examples/flexible_pump_on_mounts.toml``, inside a casing on mounts), times
``campbell(model, speeds, critical=False, modes=N)`` and a dense batched ``numpy.linalg.eig``
of the full state matrices at the same speeds (same run, interleaved repeats), prints the
ratio (min / median / max over repeats), the peak memory of each (tracemalloc) and the largest
relative difference of the N lowest roots from the dense solve's.

Usage::

    python benchmarks/bench_flexible.py [--speeds 201] [--modes 12] [--repeat 3] [--sizes 0.2,0.05,0.012]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.io.model_file import read_toml


def _model(path, element_length):
    data = read_toml(path, "model")
    for rotor in data["rotors"]:
        if "shaft" in rotor:
            rotor["element_length"] = element_length
    return rdm.Model.from_dict(data)


def _dense(model, speeds, count):
    M, C, G, K = model.matrices()
    n = len(M)
    A = np.zeros((len(speeds), 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, :n] = -np.linalg.solve(M, K)
    A[:, n:, n:] = -np.linalg.solve(M, C)[None] - speeds[:, None, None] * np.linalg.solve(M, G)[None]
    roots = np.linalg.eigvals(A)
    roots = np.where(is_oscillating(roots) & (roots.imag > 1e-9 * np.abs(roots)), roots, np.nan + 1e300j)
    return np.sort_complex(roots * -1j)[:, :count] * 1j          # by imaginary part


def _timed(function):
    start = time.perf_counter()
    out = function()
    return out, time.perf_counter() - start


def _peak(function):
    """Peak traced memory [bytes] of one more run (apart: tracemalloc slows Python-heavy code)."""
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def _lowest(model, speeds, count):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.campbell(model, speeds, critical=False, modes=count)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=201)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="0.2,0.05,0.012", help="element lengths [m] of the compressor shaft")
    args = parser.parse_args(argv)
    cases = [("examples/compressor_rotor.toml", float(x)) for x in args.sizes.split(",")]
    cases += [("examples/flexible_pump_on_mounts.toml", x) for x in (0.05, 0.01)]
    speeds = np.linspace(0.0, 1500.0, args.speeds)
    print(f"{'model':40s} {'n':>5s} {'full [s]':>9s} {'lowest [s]':>10s} {'ratio min/med/max':>20s} "
          f"{'peak MB full/low':>17s} {'max rel diff':>12s}")
    for path, length in cases:
        model = _model(path, length)
        n = len(model.matrices()[0])
        ratios, full_t, low_t = [], [], []
        for _ in range(args.repeat):
            reference, t_full = _timed(lambda: _dense(model, speeds, args.modes))
            result, t_low = _timed(lambda: _lowest(model, speeds, args.modes))
            ratios.append(t_full / t_low)
            full_t.append(t_full)
            low_t.append(t_low)
        m_full, m_low = _peak(lambda: _dense(model, speeds, args.modes)), _peak(lambda: _lowest(model, speeds, args.modes))
        got = np.take_along_axis(result.eigenvalues, np.argsort(result.eigenvalues.imag, axis=1), axis=1)
        diff = np.nanmax(np.abs(got - reference) / np.abs(reference))
        name = f"{path.split('/')[-1]} el={length:g}"
        print(f"{name:40s} {n:5d} {np.median(full_t):9.2f} {np.median(low_t):10.2f} "
              f"{min(ratios):6.1f}/{np.median(ratios):5.1f}/{max(ratios):5.1f}     "
              f"{m_full / 2**20:7.0f}/{m_low / 2**20:<7.0f} {diff:12.1e}", flush=True)


if __name__ == "__main__":
    main()
