"""Stability of the lowest modes only (``stability(modes=N)``) against the full ``stability``.

``examples/compressor_rotor.toml`` with its shaft meshed finer (``--element``) and cross-coupled
bearings (a speed table: cross-coupled stiffness growing linearly from 0 at rest to ``--q`` N/m at
15,000 rpm, as a seal's or an oil film's; the thrust bearing given axial damping), so that its
first forward mode loses stability inside the range. Times ``rdm.stability(model, speeds)`` and
``rdm.stability(model, speeds, modes=N)`` in the same run, interleaved repeats, and prints the
ratio's min / median / max, the thresholds' relative difference and the largest relative
difference of the N lowest roots from the full sweep's N lowest.

Usage::

    python benchmarks/bench_stability_lowest.py [--element 0.05] [--speeds 201] [--modes 12] [--repeat 3]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.io.model_file import read_toml


def cross_coupled_compressor(element_length, q_top):
    """The compressor example meshed at ``element_length`` [m], its bearings cross-coupled."""
    data = read_toml("examples/compressor_rotor.toml", "model")
    data["rotors"][0]["element_length"] = element_length
    for bearing in data["bearings"]:
        k, c = bearing["stiffness"], bearing["damping"]
        bearing["speeds_rpm"] = [0.0, 15000.0]
        bearing["stiffness"] = [[[k, 0.0], [0.0, k]], [[k, q_top], [-q_top, k]]]
        bearing["damping"] = [[c, c], [c, c]]
        if "axial_stiffness" in bearing:
            bearing["axial_stiffness"] = [bearing["axial_stiffness"]] * 2
            bearing["axial_damping"] = [2.0e4, 2.0e4]
    return rdm.Model.from_dict(data)


def _timed(function):
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = function()
    return out, time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--element", type=float, default=0.05, help="element length of the shaft [m]")
    parser.add_argument("--q", type=float, default=5.0e6, help="cross-coupled stiffness at 15,000 rpm [N/m]")
    parser.add_argument("--speeds", type=int, default=201)
    parser.add_argument("--top", type=float, default=12000.0, help="highest speed [rpm]")
    parser.add_argument("--modes", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    model = cross_coupled_compressor(args.element, args.q)
    speeds = np.linspace(0.0, args.top, args.speeds) * np.pi / 30
    full_t, low_t = [], []
    for _ in range(args.repeat):
        full, t = _timed(lambda: rdm.stability(model, speeds))
        full_t.append(t)
        low, t = _timed(lambda: rdm.stability(model, speeds, modes=args.modes))
        low_t.append(t)
    ratios = np.array(full_t) / np.array(low_t)
    n = model.dofs.n
    print(f"compressor, element {args.element:g} m: {n} coordinates, {args.speeds} speeds, {args.modes} modes, "
          f"{args.repeat} repeats")
    print(f"full stability [s]:   min {min(full_t):.2f}  median {np.median(full_t):.2f}  max {max(full_t):.2f}")
    print(f"lowest {args.modes} [s]:       min {min(low_t):.2f}  median {np.median(low_t):.2f}  max {max(low_t):.2f}")
    print(f"ratio full / lowest:  min {ratios.min():.1f}  median {np.median(ratios):.1f}  max {ratios.max():.1f}")
    print(f"thresholds [rpm]: full {full.thresholds * 30 / np.pi}, lowest {low.thresholds * 30 / np.pi}")
    if len(full.thresholds) == len(low.thresholds) and len(full.thresholds):
        print(f"thresholds' relative difference: {np.max(np.abs(low.thresholds / full.thresholds - 1)):.1e}")
    reference = np.sort_complex(np.where(is_oscillating(full.eigenvalues), full.eigenvalues, np.nan) * -1j)[:, :args.modes] * 1j
    got = np.take_along_axis(low.eigenvalues, np.argsort(low.eigenvalues.imag, axis=1), axis=1)
    print(f"lowest roots' largest relative difference: {np.nanmax(np.abs(got - reference) / np.abs(reference)):.1e}")


if __name__ == "__main__":
    main()
