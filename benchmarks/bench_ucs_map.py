"""Cost of the undamped critical speed map on journal bearings (``examples/compressor_on_journals.toml``).

Times, each repeat:

- ``ucs_map`` as the report calls it (41 stiffness values 1e5 to 1e10 N/m, 4 modes): the map, the
  four journal-bearing stiffness curves (~200 points each) and their crossings with the modes;
- ``loop``: the obvious alternative for the curve points, a plain loop of the same eigen-solves,
  one ``_Pencil.roots([k])`` per curve point (no matching, no refinement: a lower bound of that
  approach);
- ``batched``: the same points in one batched ``_Pencil.roots`` call (what ``ucs_map`` does);
- ``threaded``: that batched call with BLAS's own threads (what ``ucs_map`` did before it asked
  for one BLAS thread; on a shared machine those threads mostly wait for a core);
- ``old route``: ``ucs_map`` by today's route for the speed-dependent bearings' crossings
  (``ucs_map.SUBSPACE_CROSSINGS`` False: the whole pencil at every curve point and refinement
  step) against ``ucs_map`` (their crossings on Rayleigh-Ritz subspaces, issue 29 §2), with the
  largest relative difference of their crossings (speed and stiffness).

Prints each time's min/median over the repeats and the ratios loop/ucs_map, loop/batched,
threaded/batched and old route/ucs_map (min/median/max over the repeats). With ``--ross NAME`` the
model is ROSS's ``tests/data/ross/NAME.toml`` and the stiffness 5 values (compressor_example: the
old route takes about 2 min a repeat; only ``ucs_map`` and ``old route`` are timed). Run::

    python benchmarks/bench_ucs_map.py [--repeat 3] [--model examples/compressor_on_journals.toml]
    python benchmarks/bench_ucs_map.py --ross compressor_example --repeat 3
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, ucs_map as ucs_module
from rotordyn_modal.analysis.ucs_map import _chosen_bearings, _Pencil, ucs_map
from rotordyn_modal.io import load_model
from rotordyn_modal.io.ross_file import read_ross_rotor

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "compressor_on_journals.toml"
STIFFNESS = np.geomspace(1e5, 1e10, 41)


def _timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def curve_points(result) -> np.ndarray:
    """Every positive point (N/m) of the speed-dependent bearings' Kxx and Kyy curves."""
    values = [v[v > 0] for c in result.curves if not c.constant for v in (c.kxx, c.kyy)]
    return np.concatenate(values) if values else np.zeros(0)


def _one_thread(function):
    def run():
        with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
            function()
    return run


def _old_route(model, stiffness):
    ucs_module.SUBSPACE_CROSSINGS = False
    try:
        return ucs_map(model, stiffness, modes=4)
    finally:
        ucs_module.SUBSPACE_CROSSINGS = True


def _difference(new, old) -> float:
    """Largest relative difference of two maps' crossings (speed, stiffness); inf where their
    lists (bearing, axis, mode) differ."""
    if [(c.bearing, c.axis, c.mode) for c in new.crossings] != [(c.bearing, c.axis, c.mode) for c in old.crossings]:
        return np.inf
    return max([max(abs(a.speed - b.speed) / b.speed, abs(a.stiffness - b.stiffness) / b.stiffness)
                for a, b in zip(new.crossings, old.crossings)], default=0.0)


def _ross_model(name):
    path = Path(__file__).resolve().parent.parent / "tests" / "data" / "ross" / f"{name}.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict(read_ross_rotor(path), source=path), path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--model", default=str(EXAMPLE))
    parser.add_argument("--ross", default=None)
    args = parser.parse_args(argv)
    model, path = _ross_model(args.ross) if args.ross else (load_model(args.model), Path(args.model))
    stiffness = np.geomspace(1e5, 1e10, 5) if args.ross else STIFFNESS
    result = ucs_map(model, stiffness, modes=4)
    parts = _Pencil(model, _chosen_bearings(model, None))
    points = curve_points(result)
    print(f"{path.name}: {parts.M.shape[0]} coordinates, {len(points)} curve points, "
          f"{len(result.crossings)} crossings; old route's crossings within "
          f"{_difference(result, _old_route(model, stiffness)):.2g} (relative)")
    cases = {"ucs_map": lambda: ucs_map(model, stiffness, modes=4), "old route": lambda: _old_route(model, stiffness)}
    if not args.ross:
        cases |= {"loop": _one_thread(lambda: [parts.roots([k]) for k in points]),
                  "batched": _one_thread(lambda: parts.roots(points)),
                  "threaded": lambda: parts.roots(points)}
    times = {name: [] for name in cases}
    for _ in range(max(1, args.repeat)):
        for name, function in cases.items():
            times[name].append(_timed(function))
    times = {name: np.array(t) for name, t in times.items()}
    for name, t in times.items():
        print(f"{name:10s} min {t.min():8.3f} s  median {np.median(t):8.3f} s")
    for top, bottom in (("old route", "ucs_map"), ("loop", "ucs_map"), ("loop", "batched"), ("threaded", "batched")):
        if top not in times:
            continue
        ratio = times[top] / times[bottom]
        print(f"{top}/{bottom}: min {ratio.min():.2f}  median {np.median(ratio):.2f}  max {ratio.max():.2f}")


if __name__ == "__main__":
    main()
