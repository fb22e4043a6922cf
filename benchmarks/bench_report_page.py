"""The report page's CPU time (``render_html``: every figure drawn, laid out and encoded) by
section, in reference drawings, against the estimate the ``report`` command makes of it
(``rotordyn_modal.report.collect.RENDER_DRAWINGS``, the part ``"page"`` of ``estimate_work``).

A reference drawing (:func:`rotordyn_modal.report.collect.reference_drawing_seconds`) is timed
in this process first; each section's CPU (``time.process_time``) is printed in those units, so
the figures carry from one machine to another. Machines:

* **chain R**: ``tests/test_large_machine_cli.py``'s stator on four mounts with R rigid rotors
  chained by gears, each on two bearings, two unbalances and two sensors (the report estimate's
  test, ``tests/test_report_estimate27r.py``), API 684 at 21 speeds, MCS 3,000 rpm;
* the examples ``journal_rotor``, ``compressor_rotor``, ``compressor_on_journals`` and
  ``flexible_pump_on_mounts``: API 617 with Level I at the reference rotor (Qa = 2e5 N/m).

The last column is the estimated page over the measured one (1: right; above 1: the estimate is
high).

Usage::

    python benchmarks/bench_report_page.py [--chains 1,3,6,10,20] [--examples] [--repeat 1]
"""

from __future__ import annotations

import argparse
import importlib
import sys
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))                   # this checkout's package, not an installed one
sys.path.insert(1, str(ROOT / "tests"))

import rotordyn_modal as rdm  # noqa: E402
from rotordyn_modal.analysis.level1 import Station  # noqa: E402
from rotordyn_modal.report import render  # noqa: E402

from test_large_machine_cli import chained_gear_toml  # noqa: E402
from test_report_estimate27r import CHANNELS  # noqa: E402

collect = importlib.import_module("rotordyn_modal.report.collect")
EXAMPLES = (("journal_rotor", "rotor", 6000.0), ("compressor_rotor", "compressor", 9000.0),
            ("compressor_on_journals", "compressor", 9000.0), ("flexible_pump_on_mounts", "pump", 2970.0))


def chain(rotors: int):
    path = Path(tempfile.mkdtemp()) / f"chain{rotors}.toml"
    path.write_text(chained_gear_toml(rotors, rotors) + CHANNELS)
    return f"chain {rotors}", rdm.load_model(path), collect.ReportInputs(standard="api684", mcs=rdm.rpm(3000.0), points=21)


def example(name: str, rotor: str, mcs_rpm: float):
    model = rdm.load_model(ROOT / "examples" / f"{name}.toml")
    inputs = collect.ReportInputs(standard="api617", mcs=rdm.rpm(mcs_rpm), points=21,
                                  level1={"stations": [Station.parse(rotor)], "qa": 2e5, "shares": None})
    return name, model, inputs


def sections_cpu(data, repeat: int) -> dict:
    """CPU seconds [s] of each section of the page (the shortest of ``repeat``)."""
    cpu = {}
    for section in data.sections:
        best = float("inf")
        for _ in range(repeat):
            start = time.process_time()
            render._SECTION_RENDERERS[section](data, "si")
            best = min(best, time.process_time() - start)
        cpu[section] = best
    return cpu


def measure(label: str, model, inputs, drawing: float, repeat: int) -> None:
    estimate = dict((p, s) for p, s, _ in collect.estimate_work(model, inputs).parts)["page"]
    with rdm.long_work_allowed():
        data = collect.collect(model, inputs)
    cpu = sections_cpu(data, repeat)
    shown = "  ".join(f"{s} {c / drawing:5.1f}" for s, c in cpu.items() if s not in ("model",))
    page = sum(cpu.values())
    print(f"{label:26s} {model.dofs.n:4d} coordinates  {shown}  | page {page / drawing:6.1f} drawings, "
          f"{page:6.2f} s; estimate / measured {estimate / page:5.2f}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--chains", default="1,3,6,10,20")
    parser.add_argument("--examples", action="store_true", help="the four examples too")
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    drawing = collect.reference_drawing_seconds()
    print(f"reference drawing: {drawing:.4f} s CPU")
    cases = [chain(int(r)) for r in args.chains.split(",") if r]
    cases += [example(*e) for e in EXAMPLES] if args.examples else []
    for label, model, inputs in cases:
        measure(label, model, inputs, drawing, args.repeat)


if __name__ == "__main__":
    main()
