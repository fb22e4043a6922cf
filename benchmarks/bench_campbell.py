"""Campbell diagram speed: the package against the floor and the obvious loop.

For 10,001 speeds of the two-rotor gear machine (examples/gear_machine.toml) it times

* ``rdm.campbell`` (eigenvalues, shapes, tracking, whirl and critical speeds of 1X),
* the floor: one bare batched ``numpy.linalg.eig`` of the same 10,001 state matrices,
* the loop: ``scipy.linalg.eig`` called once per speed,

and prints the best of several runs and the ratios. Run::

    python benchmarks/bench_campbell.py [--speeds 10001] [--repeat 5]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.linear_system import state_matrices
from _timing import best_time  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

MODEL = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"




def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=int, default=10001)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    model = rdm.load_model(MODEL)
    speeds = rdm.rpm(np.linspace(0.0, 12000.0, args.speeds))
    matrices = state_matrices(model, speeds)

    package = best_time(lambda: rdm.campbell(model, speeds), args.repeat)
    floor = best_time(lambda: np.linalg.eig(state_matrices(model, speeds)), args.repeat)
    loop = best_time(lambda: [scipy.linalg.eig(a) for a in matrices], max(1, args.repeat // 2))

    print(f"model: {MODEL.name}, {args.speeds} speeds, 12 states, best of {args.repeat}")
    print(f"rdm.campbell (tracking, whirl, 1X critical speeds): {package * 1e3:8.1f} ms")
    print(f"floor: batched numpy.linalg.eig                    : {floor * 1e3:8.1f} ms")
    print(f"loop: scipy.linalg.eig per speed                   : {loop * 1e3:8.1f} ms")
    print(f"campbell / floor = {package / floor:.2f}  (target <= 1.5)")
    print(f"loop / campbell  = {loop / package:.2f}  (target >= 2.5)")


if __name__ == "__main__":
    main()
