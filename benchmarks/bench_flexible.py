"""Campbell sweep of the lowest modes only (``campbell(modes=N)``) against the full solve.

For flexible rotors of growing mesh (``element_length`` of ``examples/compressor_rotor.toml``,
alone; ``examples/flexible_pump_on_mounts.toml``, inside a casing on mounts), times
``campbell(model, speeds, critical=False, modes=N)`` and a dense batched ``numpy.linalg.eig``
of the full state matrices at the same speeds (same run, interleaved repeats), prints the
ratio (min / median / max over repeats), the peak memory of each (tracemalloc) and the largest
relative difference of the N lowest roots from the dense solve's. With ``--max-frequency HZ``,
``campbell(..., max_frequency=HZ)`` instead: every mode below HZ at each speed (``--modes`` unused),
compared with the dense solve's roots below HZ.

Usage::

    python benchmarks/bench_flexible.py [--speeds 201] [--modes 12] [--repeat 3] [--sizes 0.2,0.05,0.012]
                                        [--max-frequency HZ]
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


def _dense(model, speeds, count, limit=None):
    M, C, G, K = model.matrices()
    n = len(M)
    A = np.zeros((len(speeds), 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, :n] = -np.linalg.solve(M, K)
    A[:, n:, n:] = -np.linalg.solve(M, C)[None] - speeds[:, None, None] * np.linalg.solve(M, G)[None]
    roots = np.linalg.eigvals(A)
    roots = np.where(is_oscillating(roots) & (roots.imag > 1e-9 * np.abs(roots)), roots, np.nan + 1e300j)
    roots = np.sort_complex(roots * -1j) * 1j                         # by imaginary part
    if limit is None:
        return roots[:, :count]
    return np.where(roots.imag <= 2 * np.pi * limit, roots, np.nan + 1e300j)


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


def _lowest(model, speeds, count, limit=None):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if limit is not None:
            return rdm.campbell(model, speeds, critical=False, max_frequency=limit)
        return rdm.campbell(model, speeds, critical=False, modes=count)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=201)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="0.2,0.05,0.012", help="element lengths [m] of the compressor shaft")
    parser.add_argument("--max-frequency", type=float, help="every mode below this [Hz] instead of the lowest N")
    args = parser.parse_args(argv)
    limit = args.max_frequency
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
            reference, t_full = _timed(lambda: _dense(model, speeds, args.modes, limit))
            result, t_low = _timed(lambda: _lowest(model, speeds, args.modes, limit))
            ratios.append(t_full / t_low)
            full_t.append(t_full)
            low_t.append(t_low)
        m_full = _peak(lambda: _dense(model, speeds, args.modes, limit))
        m_low = _peak(lambda: _lowest(model, speeds, args.modes, limit))
        got = np.sort_complex(np.where(result.oscillatory, result.eigenvalues, np.nan + 1e300j) * -1j) * 1j
        k = max(got.shape[1], reference.shape[1])
        got, reference = (np.pad(x, ((0, 0), (0, k - x.shape[1])), constant_values=np.nan + 1e300j)
                          for x in (got, reference))
        # a root missing from either side (a root against the padding): an infinite difference
        missing = np.isnan(got) != np.isnan(reference)
        diff = np.nanmax(np.where(missing, np.inf, np.abs(got - reference) / np.abs(reference)))
        name = f"{path.split('/')[-1]} el={length:g}"
        print(f"{name:40s} {n:5d} {np.median(full_t):9.2f} {np.median(low_t):10.2f} "
              f"{min(ratios):6.1f}/{np.median(ratios):5.1f}/{max(ratios):5.1f}     "
              f"{m_full / 2**20:7.0f}/{m_low / 2**20:<7.0f} {diff:12.1e}", flush=True)


if __name__ == "__main__":
    main()
