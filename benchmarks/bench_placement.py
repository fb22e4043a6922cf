"""Label placing: the CPU time of drawing the figures whose labels cost most, two source trees
compared in one run (a base, e.g. ``git archive <commit> | tar -x -C /tmp/base``, against this
tree).

Figures (each ``result.plot()`` and ``savefig`` to PNG at 150 dpi, the analysis not timed):

* ``ucs-fan-all``: fan_on_bearings' UCS map, every bearing chosen (1e5 .. 1e9 N/m, 41 values,
  operating 1000 .. 3000 rpm), drawn in five test files;
* ``ucs-plain``: compressor_on_journals' UCS map (1e5 .. 1e9 N/m, 41 values);
* ``ucs-fan-e10``: fan_on_bearings' UCS map (1e5 .. 1e10 N/m, 31 values), the figure of
  ``tests/test_ucs_map.py::test_figure_writes_every_crossing_and_name_clear_of_curves_markers_and_each_other``;
* ``campbell-fan``: fan_on_bearings' Campbell diagram, 0 .. 9000 rpm at 121 speeds, orders 1, 2;
* ``campbell-chain40``: the 40-rotor gear chain (``tests/test_large_machine_cli.chained_gear_toml``),
  0 .. 4500 rpm at 22 speeds;
* ``campbell-chain60``: the 60-rotor gear chain, the same speeds, titled and saved as the report
  page saves it (``figure_png`` at 110 dpi), the figure of ``tests/test_campbell_chain32.py``;
* ``campbell-report6``: the report page's Campbell figure of the 6-rotor gear chain (with the
  channels of ``tests/test_report_estimate27r.py``, API 684, 3000 rpm, 21 points): its sweep
  from ``report.collect``, drawn as ``report.render`` draws it and saved by ``figure_png``;
* ``campbell-compressor``: compressor_rotor's Campbell diagram, 0 .. 15000 rpm at 151 speeds,
  orders 1, 2;
* ``campbell-motor-pump``: motor_pump_on_mounts' Campbell diagram, 0 .. 3600 rpm at 181 speeds,
  orders 1, 2 (modes from 5 Hz to 1.2 kHz on a logarithmic axis; the leaders that ran along its
  mode lines, issue 27 §3).

Each drawing runs in a process of its own (one thread), the two trees in turn, ``--repeat``
times; each process loads its tree's results from a pickle made once per tree (in
``--cache``). Printed: each tree's min / median / max CPU seconds per figure and the ratio
base / this tree (min, median, max over the pairs of one repeat).

Run from the repository root::

    python benchmarks/bench_placement.py --base /tmp/base [--repeat 5] [--figures ucs-fan-all,ucs-plain]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _timing import print_base_ratio  # noqa: E402  (benchmarks/ is on sys.path when run as a script)

ROOT = Path(__file__).resolve().parent.parent
FIGURES = ("ucs-fan-all", "ucs-plain", "ucs-fan-e10", "campbell-fan", "campbell-chain40", "campbell-chain60",
           "campbell-report6", "campbell-compressor", "campbell-motor-pump")

_CHILD = r'''
import importlib, io, os, pickle, sys, time, tomllib
from pathlib import Path
os.environ["OMP_NUM_THREADS"] = "1"
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import rotordyn_modal as rdm

tree, cache, name = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
examples = tree / "examples"


def results():
    fan = rdm.load_model(examples / "fan_on_bearings.toml")
    out = {"ucs-fan-all": rdm.ucs_map(fan, np.geomspace(1e5, 1e9, 41),
                                      bearings=["motor-DE", "motor-NDE", "fan-DE", "fan-NDE"],
                                      operating=(1000.0 * np.pi / 30.0, 3000.0 * np.pi / 30.0)),
           "ucs-plain": rdm.ucs_map(rdm.load_model(examples / "compressor_on_journals.toml"),
                                    np.geomspace(1e5, 1e9, 41)),
           "ucs-fan-e10": rdm.ucs_map(fan, np.geomspace(1e5, 1e10, 31)),
           "campbell-fan": rdm.campbell(fan, rdm.rpm(np.linspace(0.0, 9000.0, 121)), orders=(1, 2))}
    sys.path.insert(0, str(tree / "tests"))
    from test_large_machine_cli import chained_gear_toml
    for rotors in (40, 60):
        chain = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(rotors, rotors)), source="chain.toml")
        out[f"campbell-chain{rotors}"] = rdm.campbell(chain, rdm.rpm(np.linspace(0.0, 4500.0, 22)))
    from test_report_estimate27r import CHANNELS
    collect = importlib.import_module("rotordyn_modal.report.collect")   # (report.collect is also a function)
    chain = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(6, 6) + CHANNELS), source="chain.toml")
    with rdm.long_work_allowed():
        data = collect.collect(chain, collect.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=21))
    out["campbell-report6"] = (data.results["campbell"], data.model_info["name"], data.inputs.range)
    out["campbell-compressor"] = rdm.campbell(rdm.load_model(examples / "compressor_rotor.toml"),
                                              rdm.rpm(np.linspace(0.0, 15000.0, 151)), orders=(1, 2))
    out["campbell-motor-pump"] = rdm.campbell(rdm.load_model(examples / "motor_pump_on_mounts.toml"),
                                              rdm.rpm(np.linspace(0.0, 3600.0, 181)), orders=(1, 2))
    return out


def draw(name, result):
    """The figure drawn and saved as its users save it (the report page's by ``figure_png``)."""
    if name == "campbell-report6":
        from rotordyn_modal.report.render import campbell_top, figure_png
        result, title, (low, high) = result
        top = campbell_top(result)
        figure_png(result.plot(title=title, freq_range=None if top is None else (None, top),
                               operating=(low * 30 / np.pi, high * 30 / np.pi)))
    elif name == "campbell-chain60":
        from rotordyn_modal.report.render import figure_png
        figure_png(result.plot(title="60 rotors chained by gears"), dpi=110)
    else:
        result.plot().savefig(io.BytesIO(), format="png", dpi=150)


if not cache.exists():
    pickle.dump(results(), open(cache, "wb"))
    sys.exit(0)
result = pickle.load(open(cache, "rb"))[name]
warm = plt.figure()
warm.text(0.5, 0.5, "0123 mode")
warm.savefig(io.BytesIO(), format="png")
plt.close(warm)
start = time.process_time()
draw(name, result)
print(time.process_time() - start)
'''


def _run(tree: Path, cache: Path, name: str) -> float | None:
    """CPU seconds of one drawing of ``name`` by the code of ``tree`` (None: the pickle made)."""
    env = dict(os.environ, PYTHONPATH=str(tree), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1", MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, "-c", _CHILD, str(tree), str(cache), name], env=env, cwd=str(tree),
                          capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"{tree}: {name} failed:\n{done.stderr}")
    out = done.stdout.strip()
    return float(out.splitlines()[-1]) if out else None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, type=Path, help="the base source tree")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--figures", default=",".join(FIGURES))
    parser.add_argument("--cache", type=Path, default=None, help="folder of the results' pickles")
    args = parser.parse_args(argv)
    cache = args.cache or Path(tempfile.mkdtemp(prefix="bench_placement_"))
    cache.mkdir(parents=True, exist_ok=True)
    trees = {"base": args.base.resolve(), "this": ROOT}
    pickles = {label: cache / f"{label}.pkl" for label in trees}
    for label, tree in trees.items():
        if not pickles[label].exists():
            _run(tree, pickles[label], FIGURES[0])
    names = [n for n in args.figures.split(",") if n]
    for name in names:
        times = {label: [] for label in trees}
        for _ in range(args.repeat):
            for label, tree in trees.items():
                times[label].append(_run(tree, pickles[label], name))
        print_base_ratio(name, times["base"], times["this"], width=18)


if __name__ == "__main__":
    main()
