"""The compiled right-hand side through ``rdm.simulate`` (numba), this checkout against another.

CPU time (``time.process_time``, less disturbed by other processes on a shared machine than the
wall clock) of ``rdm.simulate`` on ``fan_on_bearings`` (3000 rpm, 0.5 s) and the seed 001
example ``spring_block_rotor`` (50 rad/s, 10 s), after one warm-up run that compiles. Each
checkout runs in fresh interpreters, alternating, ``--rounds`` times; the minimum of
``--repeat`` runs per round, then the minimum over rounds, and the ratio to ``--source``::

    python benchmarks/bench_rhs.py --source /path/to/other/checkout [--rounds 3] [--repeat 5]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

#: import the package from a given folder even when another checkout is installed in editable mode
_CODE = """
import json, sys, time
sys.meta_path[:] = [f for f in sys.meta_path if 'editable' not in repr(f)]
sys.path.insert(0, {source!r})
import rotordyn_modal as rdm
examples = {examples!r}
cases = {{"fan_on_bearings": dict(duration=0.5, speed=rdm.rpm(3000), rtol=1e-10, atol=1e-13),
          "spring_block_rotor": dict(duration=10.0, speed=50.0, rtol=1e-10, atol=1e-12)}}
out = {{}}
for name, options in cases.items():
    model = rdm.load_model(f"{{examples}}/{{name}}.toml")
    rdm.simulate(model, 0.01, speed=options["speed"], backend="numba")
    times = []
    for _ in range({repeat}):
        start = time.process_time()
        rdm.simulate(model, backend="numba", **options)
        times.append(time.process_time() - start)
    out[name] = min(times)
print(json.dumps(out))
"""


def _run(source: Path, repeat: int) -> dict:
    code = _CODE.format(source=str(source), examples=str(REPO / "examples"), repeat=repeat)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env=dict(os.environ, MPLBACKEND="Agg"))
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=Path, required=True, help="the other checkout (its folder)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    best = {"this": {}, "other": {}}
    for _ in range(args.rounds):
        for label, source in (("other", args.source.resolve()), ("this", REPO)):
            for name, seconds in _run(source, args.repeat).items():
                best[label][name] = min(seconds, best[label].get(name, float("inf")))
    for name in best["this"]:
        this, other = best["this"][name], best["other"][name]
        print(f"{name:20s} this {this:.3f} s  other {other:.3f} s  ratio {this / other:.3f}")


if __name__ == "__main__":
    main()
