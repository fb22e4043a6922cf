"""The lowest modes of a flexible rotor in a casing on Maxwell mounts: rational pencil against full solve.

``examples/flexible_pump_on_mounts.toml`` with its pump shaft meshed at ``--element`` and two
Maxwell branches on each of its four mounts (as stiff as the mount's static stiffness at high
frequency, and half of it; relaxation times 1 ms and 20 ms: 48 branch states). Times the ``--modes``
lowest roots at ``--speeds`` speeds from 0 to 6,000 rpm by the reduced route on the rational pencil
(``analysis/_lowest_branches.lowest_roots``, what ``campbell(modes=N)`` now calls) and by the full
solve every model with branches took before (``_lowest._full_lowest``: eigenvalues and eigenvectors
of the state matrix with the branches' states at every speed), in the same run, interleaved
repeats, each on a fresh one-model stack; the peak traced memory of one more run of each
(tracemalloc), and the largest relative difference of the roots.

Usage::

    python benchmarks/bench_branches.py [--element 0.0075] [--speeds 41] [--modes 12] [--repeat 2]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_branches
from rotordyn_modal.analysis.campbell import lowest_stack
from rotordyn_modal.io.model_file import read_toml


def pump_on_maxwell_mounts(element_length):
    """The pump example meshed at ``element_length`` [m], two Maxwell branches on each mount."""
    data = read_toml("examples/flexible_pump_on_mounts.toml", "model")
    data["rotors"][1]["element_length"] = element_length
    for mount in data["suspensions"]:
        k = np.asarray(mount["stiffness"])
        mount["maxwell_stiffness"] = [(0.5 * k).tolist(), k.tolist()]
        mount["maxwell_time"] = [0.02, 0.001]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict(data)


def _routes(model, speeds, count):
    return {
        "rational": lambda: _lowest_branches.lowest_roots(lowest_stack(model), speeds, count)[0],
        "full": lambda: _lowest._full_lowest(lowest_stack(model), speeds, count)[0],
    }


def _peak(function):
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element", type=float, default=0.0075, help="element length of the pump shaft [m]")
    parser.add_argument("--speeds", type=int, default=41)
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args(argv)
    model = pump_on_maxwell_mounts(args.element)
    speeds = np.linspace(0.0, 6000.0, args.speeds) * np.pi / 30
    routes = _routes(model, speeds, args.modes)
    times = {name: [] for name in routes}
    roots = {}
    for _ in range(args.repeat):
        for name, function in routes.items():
            start = time.perf_counter()
            roots[name] = function()
            times[name].append(time.perf_counter() - start)
    peaks = {name: _peak(function) for name, function in routes.items()}
    a, b = (np.sort_complex(roots[name]) for name in ("rational", "full"))
    print(f"{model.dofs.n} coordinates, {len(speeds)} speeds, {args.modes} modes")
    for name in routes:
        t = np.array(times[name])
        print(f"  {name:9s} time [s] min {t.min():.2f} median {np.median(t):.2f} max {t.max():.2f}, "
              f"peak {peaks[name] / 2**20:.0f} MB")
    ratio = np.array(times["full"]) / np.array(times["rational"])
    print(f"  ratio full / rational: min {ratio.min():.1f} median {np.median(ratio):.1f} max {ratio.max():.1f}")
    print(f"  max rel diff {np.max(np.abs(a - b) / np.abs(b)):.1e}")


if __name__ == "__main__":
    main()
