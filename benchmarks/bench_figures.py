"""Figure time: what a user waits for per FRF / unbalance figure saved and per move of the
tuning widget's slider (``plotting.interactive.TuningWidget``), layouts included.

Cases (each timed ``--repeat`` times, min / median / max of the wall and of the CPU time
printed: on a shared machine the CPU time is the steadier):

* ``frf-save``: ``force_frf`` of motor_fan_minimal's mounts (symmetric: curves on each other),
  ``.plot()`` and ``savefig`` to PNG (the analysis not timed);
* ``unbalance-save``: the compressor's unbalance response (isotropic probes: y on z),
  ``.plot()`` and ``savefig`` to PNG;
* ``widget``: one ``TuningWidget.update`` (the FRFs recomputed, the overlay drawn) and the PNG
  the notebook shows (``display(fig)`` renders it so), gear machine, four FRFs at 77 lines;
* ``layouts``: how often the figure is laid out (constrained layout run) per case, counted.

Run from the repository root (``PYTHONPATH=$PWD`` for a worktree)::

    python benchmarks/bench_figures.py [--repeat 15] [--cases frf-save,unbalance-save,widget]
"""

from __future__ import annotations

import argparse
import io
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rotordyn_modal as rdm  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _saved(draw):
    """``draw()`` (a figure) saved to PNG in memory, then closed."""
    def run():
        fig = draw()
        fig.savefig(io.BytesIO(), format="png")
        plt.close(fig)
    return run


def cases():
    """name -> a function of no argument doing one case's work."""
    from rotordyn_modal.plotting.interactive import TuningWidget

    forces = rdm.force_frf(rdm.load_model(EXAMPLES / "motor_fan_minimal.toml"), 0.0, np.linspace(1.0, 100.0, 300),
                           where="suspensions")
    compressor = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    unbalance = rdm.unbalance_response(compressor, rdm.rpm(np.linspace(500.0, 12000.0, 24)))
    gear = rdm.load_model(EXAMPLES / "gear_machine.toml")
    tuner = TuningWidget(gear.scaled({"suspensions.mount-FL.stiffness": 1.6}),
                         [rdm.frf(gear, 0.0, np.linspace(2, 40, 77))], ["suspensions.mount-FL.stiffness"])
    factors = iter(np.geomspace(0.3, 3.0, 10_000))

    def widget():
        fig = tuner.update(**{"suspensions.mount-FL.stiffness": next(factors)})
        fig.savefig(io.BytesIO(), format="png")

    return {"frf-save": _saved(forces.plot), "unbalance-save": _saved(unbalance.plot), "widget": widget}


def _layouts(run):
    """Constrained layouts run during ``run()``."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    count, execute = [0], ConstrainedLayoutEngine.execute

    def counted(self, fig):
        count[0] += 1
        return execute(self, fig)

    ConstrainedLayoutEngine.execute = counted
    try:
        run()
    finally:
        ConstrainedLayoutEngine.execute = execute
    return count[0]


def _spread(seconds):
    """``min / median / max`` of ``seconds`` in ms."""
    ms = 1e3 * np.asarray(seconds)
    return f"min / median / max {ms.min():6.0f} / {np.median(ms):6.0f} / {ms.max():6.0f} ms"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--cases", default="frf-save,unbalance-save,widget")
    args = parser.parse_args(argv)
    work = cases()
    for name in args.cases.split(","):
        run = work[name]
        run()                                               # fonts and caches warm
        wall, cpu = [], []
        for _ in range(args.repeat):
            start, used = time.perf_counter(), time.process_time()
            run()
            wall.append(time.perf_counter() - start)
            cpu.append(time.process_time() - used)
        print(f"{name:15s} {_spread(wall)} wall, {_spread(cpu)} CPU ({args.repeat} runs; {_layouts(run)} layouts each)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
