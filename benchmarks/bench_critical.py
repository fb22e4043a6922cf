"""Critical speeds of large machines: the CPU time of ``rdm.campbell`` (its critical speeds
included) and of ``rdm.critical_speeds``, two source trees compared in one run (a base, e.g.
``git worktree add /tmp/base <commit>``, against this tree).

Cases:

* ``chain20``, ``chain40``, ``chain60``: ``rdm.campbell`` of the 20-, 40- and 60-rotor gear
  chains (``tests/test_large_machine_cli.chained_gear_toml(n, n)``, 0 .. 4500 rpm at 22 speeds,
  order 1): the sweeps of ``tests/conftest.chain_campbell`` (the 60-rotor chain's is most of
  ``test_campbell_chain32::test_chain60_figures_read_well``);
* ``pump``: ``rdm.critical_speeds`` of examples/flexible_pump_on_mounts.toml, 100 .. 15000 rpm at
  61 speeds, orders 1 and 2;
* ``hrs113``: ``rdm.critical_speeds`` of tests/data/ross/hrs113.toml (a flexible rotor), 0 ..
  20000 rpm at 41 speeds.

Each call runs in a process of its own (one BLAS thread), the two trees in turn, ``--repeat``
times; the model is built before the clock starts. Printed: each tree's min / median / max CPU
seconds (``time.process_time``, every thread of the process) and the ratio base / this tree
(min, median, max over the pairs of one repeat; above 1: this tree is faster).

Run from the repository root::

    python benchmarks/bench_critical.py --base /tmp/base [--repeat 3] [--cases chain60,pump]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

from _timing import print_base_ratio  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

ROOT = Path(__file__).resolve().parent.parent
CASES = ("chain20", "chain40", "chain60", "pump", "hrs113")

_CHILD = r'''
import sys, time, tomllib, warnings
from pathlib import Path
import numpy as np
import rotordyn_modal as rdm

tree, name = Path(sys.argv[1]), sys.argv[2]
warnings.simplefilter("ignore")
if name.startswith("chain"):
    sys.path.insert(0, str(tree / "tests"))
    from test_large_machine_cli import chained_gear_toml
    count = int(name[5:])
    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(count, count)), source="chain.toml")
    call = lambda: rdm.campbell(model, rdm.rpm(np.linspace(0.0, 4500.0, 22)))
elif name == "pump":
    model = rdm.load_model(tree / "examples" / "flexible_pump_on_mounts.toml")
    call = lambda: rdm.critical_speeds(model, rdm.rpm(np.linspace(100.0, 15000.0, 61)), orders=(1, 2))
else:
    from rotordyn_modal.io.ross_file import read_ross_rotor
    model = rdm.Model.from_dict(read_ross_rotor(tree / "tests" / "data" / "ross" / "hrs113.toml"))
    call = lambda: rdm.critical_speeds(model, rdm.rpm(np.linspace(0.0, 20000.0, 41)))
start = time.process_time()
call()
print(time.process_time() - start)
'''


def _run(tree: Path, name: str) -> float:
    """CPU seconds of one call of case ``name`` by the code of ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    done = subprocess.run([sys.executable, "-c", _CHILD, str(tree), name], env=env, cwd=str(tree),
                          capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"{tree}: {name} failed:\n{done.stderr}")
    return float(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, type=Path, help="the base source tree")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cases", default=",".join(CASES))
    args = parser.parse_args(argv)
    trees = {"base": args.base.resolve(), "this": ROOT}
    for name in (n for n in args.cases.split(",") if n):
        times = {label: [] for label in trees}
        for _ in range(args.repeat):
            for label, tree in trees.items():
                times[label].append(_run(tree, name))
        print_base_ratio(name, times["base"], times["this"], width=8)


if __name__ == "__main__":
    main()
