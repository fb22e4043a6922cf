"""The lowest modes of a chain of geared rotors on bearings (``_machines.gear_chain``): CPU time
and peak memory of ``rdm.campbell(model, speeds, modes=12, critical=False)`` in a fresh process
per run, for one or two checkouts of the package (``--source``), and the CPU time per speed (the
slope between two sweep lengths: the set-up before the first speed cancels).

    python benchmarks/bench_chain_lowest.py --rotors 100 --speeds 3,11 --source . /path/to/old

The 500-rotor chain's reduced basis would hold every mode: ``analysis/_arnoldi.py`` serves it
(docs/theory.md section 17, "Crowded spectra"); benchmarks/README.md has the figures.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

_CHILD = r"""
import json, resource, sys, time
import numpy as np
sys.path.insert(0, {bench!r})
import rotordyn_modal as rdm
from _machines import gear_chain
model = gear_chain({rotors})
speeds = np.linspace(0.0, rdm.rpm(3000.0), {count})
start = time.process_time()
result = rdm.campbell(model, speeds, modes=12, critical=False)
cpu = time.process_time() - start
print(json.dumps({{"file": rdm.__file__, "cpu": cpu, "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "n": model.dofs.n, "lowest_hz": float(np.nanmin(result.frequencies_hz))}}))
"""


def run(source, rotors, count):
    """One fresh process of ``source``'s package: its CPU time [s], peak RSS [MB] and size."""
    bench = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, PYTHONPATH=os.path.abspath(source))
    out = subprocess.run([sys.executable, "-c", _CHILD.format(bench=bench, rotors=rotors, count=count)],
                         env=env, cwd=os.path.abspath(source), capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rotors", type=int, default=100)
    parser.add_argument("--speeds", default="3,11", help="two sweep lengths, e.g. 3,11")
    parser.add_argument("--source", nargs="+", default=["."], help="checkouts of the package to compare")
    args = parser.parse_args(argv)
    short, long = (int(x) for x in args.speeds.split(","))
    for source in args.source:
        a, b = run(source, args.rotors, short), run(source, args.rotors, long)
        per_speed = (b["cpu"] - a["cpu"]) / (long - short)
        print(f"{source}: {args.rotors} rotors ({b['n']} coordinates): {short} speeds {a['cpu']:.2f} s, "
              f"{long} speeds {b['cpu']:.2f} s CPU (peak RSS {b['rss_mb']:.0f} MB), per speed {per_speed:.3f} s")


if __name__ == "__main__":
    main()
