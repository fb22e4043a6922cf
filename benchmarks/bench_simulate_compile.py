"""numba's first compilation of the simulation kernels, this checkout against another.

Each run is a fresh interpreter with an empty ``NUMBA_CACHE_DIR`` calling
``rdm.simulate(rdm.load_model('examples/counter_rotating.toml'), 0.01, speed=100.0)`` (what
the first simulation in a process pays: numba compiles ``rhs_flat`` and ``sample_outputs``); then
a second interpreter on the same cache folder (numba loads the machine code). Reported: the CPU
time (``time.process_time``) of the ``simulate`` call in each, min / median / max over
``--rounds``, the two checkouts alternating, and the ratio of the medians::

    python benchmarks/bench_simulate_compile.py --source /path/to/other/checkout [--rounds 3]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

#: import the package from a given folder even when another checkout is installed in editable mode
_CODE = """
import json, sys, time
sys.meta_path[:] = [f for f in sys.meta_path if 'editable' not in repr(f)]
sys.path.insert(0, {source!r})
import rotordyn_modal as rdm
model = rdm.load_model({model!r})
start = time.process_time()
rdm.simulate(model, 0.01, speed=100.0)
print(json.dumps(time.process_time() - start))
"""


def _seconds(source: Path, cache: str, model: Path) -> float:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    env.pop("PYTHONPATH", None)
    done = subprocess.run([sys.executable, "-c", _CODE.format(source=str(source), model=str(model))],
                          env=env, capture_output=True, text=True, check=True, cwd=str(source))
    return json.loads(done.stdout.strip().splitlines()[-1])


def _summary(values) -> str:
    values = sorted(values)
    return f"{values[0]:6.2f} / {values[len(values) // 2]:6.2f} / {values[-1]:6.2f} s"


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True, help="the other checkout (the baseline)")
    parser.add_argument("--rounds", type=int, default=3)
    options = parser.parse_args(argv)
    checkouts = {"baseline": Path(options.source).resolve(), "this": REPO}
    model = REPO / "examples" / "counter_rotating.toml"
    first = {name: [] for name in checkouts}
    cached = {name: [] for name in checkouts}
    for _ in range(options.rounds):
        for name, source in checkouts.items():
            with tempfile.TemporaryDirectory(prefix="numba_cache_") as cache:
                first[name].append(_seconds(source, cache, model))
                cached[name].append(_seconds(source, cache, model))
    for name in checkouts:
        print(f"{name:9s} first run (compiles) {_summary(first[name])}   second process (cache) "
              f"{_summary(cached[name])}")
    median = {name: sorted(values)[len(values) // 2] for name, values in first.items()}
    print(f"first compile: baseline / this = {median['baseline'] / median['this']:.2f} (medians)")


if __name__ == "__main__":
    main()
