"""Critical speeds among clusters of close roots: the refinement against the sweep and the floor.

Machines of many like rotors on flexible bearings have clusters of close roots: a crossing of
such a mode with an order line cannot be told from its neighbours by distance alone, so its
refinement takes all the roots of the state matrix at its first trial speed (and follows the
mode on the pencil after that). With every rotor a source and orders 1 and 2, such machines have
thousands of crossings, and refining them, not the sweep, is most of the call.

For the property tests' random machines on bearings in a casing
(``tests/reference_bearings.random_bearing_description``: rotors of random inertia on bearings
of random, cross-coupled coefficients, each rotor a source) of 6, 10 and 19 rotors (31, 51 and
96 coordinates), at 21 speeds 0-3,000 rad/s, orders 1 and 2, it times side by side in every
repetition

* ``rdm.campbell`` (sweep, tracking, whirl, every critical speed),
* the sweep alone, ``rdm.campbell(..., orders=())``,
* the floor: one bare batched ``numpy.linalg.eig`` of the same 21 state matrices,

and prints the median times, the ratios, the number of crossings, how many of them are among
close roots (not isolated: see ``campbell._isolated``), and the time per crossing. Run::

    python benchmarks/bench_clusters.py [--rotors 6,10,19] [--seed 0] [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import campbell as campbell_module
from rotordyn_modal.analysis import _crossing_brackets
from rotordyn_modal.analysis import critical_speeds as critical_module
from rotordyn_modal.linear_system import speed_linear_form

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from reference_bearings import random_bearing_description  # noqa: E402

SPEEDS = np.linspace(0.0, 3000.0, 21)
ORDERS = (1, 2)


def _machine(rotors: int, seed: int) -> rdm.Model:
    return rdm.Model.from_dict(random_bearing_description(np.random.default_rng(seed), n_rotors=rotors))


def _among_close_roots(model) -> tuple[int, int]:
    """Crossings and those not isolated, from the sweep's brackets."""
    stack = campbell_module.Stack([model])
    values, _, _ = campbell_module.solve_sweeps(stack, SPEEDS)
    sources = [critical_module.excitation_sources(model)]
    brackets = critical_module._crossing_brackets(SPEEDS, values, sources, ORDERS,
                                                  _crossing_brackets.is_oscillating(values))
    return len(brackets.k), int((~brackets.isolated).sum())


def _timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rotors", default="6,10,19")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print(f"21 speeds 0-3000 rad/s, orders {ORDERS}, seed {args.seed}; medians of {args.repeat} "
          "repetitions (ratios per repetition: min / median / max)")
    for rotors in (int(r) for r in args.rotors.split(",")):
        model = _machine(rotors, args.seed)
        form = speed_linear_form(model)
        crossings, close = _among_close_roots(model)
        contenders = {
            "campbell": lambda: rdm.campbell(model, SPEEDS, orders=ORDERS),
            "sweep": lambda: rdm.campbell(model, SPEEDS, orders=()),
            "floor": lambda: np.linalg.eig(speed_linear_form(model).at(SPEEDS)),
        }
        times = {name: [] for name in contenders}
        for _ in range(args.repeat):
            for name, function in contenders.items():
                times[name].append(_timed(function))
        times = {name: np.array(values) for name, values in times.items()}
        ratio = times["campbell"] / times["floor"]
        median = {name: float(np.median(values)) for name, values in times.items()}
        per_crossing = (median["campbell"] - median["sweep"]) / max(crossings, 1)
        print(f"{rotors:3d} rotors {form.n_dof:4d} coordinates: {crossings:5d} crossings, {close:4d} among close "
              f"roots | campbell {median['campbell']:7.2f} s, sweep {median['sweep']:6.2f} s, floor "
              f"{median['floor']:6.2f} s | campbell / floor {ratio.min():6.1f} / {np.median(ratio):6.1f} / "
              f"{ratio.max():6.1f} | {per_crossing * 1e3:5.2f} ms per crossing")


if __name__ == "__main__":
    main()
