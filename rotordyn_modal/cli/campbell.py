"""``campbell MODEL --speeds R``: tracked Campbell diagram."""

from __future__ import annotations

from ._common import (add_model_argument, add_outputs, add_speed_unit, open_model, parse_list,
                      save_figure, show_progress, speeds_option, use_agg, write_table)
from ._resources import add_verbose, report_peak_memory

NAME = "campbell"
HELP = "Campbell diagram: modes tracked across speeds"
DESCRIPTION = """Natural frequencies, damping and whirl of every mode over a speed range, each mode
tracked by its shape so that it keeps its label where frequencies cross. The figure
shows forward (solid blue) and backward (dashed red) whirl, every rotor's and gear
mesh's excitation orders, and the critical speeds.

CSV columns: speed_rpm,mode,frequency_hz,damping_ratio,log_decrement,whirl,whirl_ratio,real_part

A sweep or a set of critical speeds that would not fit in the memory at hand is refused
before its work, with its estimate (exit 2); ROTORDYN_MODAL_MEMORY_GB sets the memory to
count on. On a terminal, bars show the progress of the eigen-solutions and of the critical
speeds' refinement.

example:
  rotordyn-modal campbell examples/gear_machine.toml --speeds 0:12000:241 --plot campbell.png"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, help="START:STOP:N speeds of the reference rotor")
    add_speed_unit(parser)
    parser.add_argument("--orders", default="1", help="excitation orders drawn and marked (default 1), e.g. 1,2")
    parser.add_argument("--no-critical", action="store_true",
                        help="do not find the critical speeds (the orders are still drawn): large machines "
                             "cross the orders of every rotor and gear mesh many thousand times")
    parser.add_argument("--color-by", choices=["log_decrement", "damping_ratio"],
                        help="colour the curves by this quantity instead of by whirl")
    add_outputs(parser)
    add_verbose(parser)


def run(args) -> int:
    from ..analysis.campbell import campbell
    model = open_model(args)
    result = campbell(model, speeds_option(args), orders=tuple(parse_list(args.orders, "--orders")),
                      progress=show_progress(args), critical=not args.no_critical)
    write_table(result.to_dataframe(), args)
    if args.plot:
        use_agg()
        save_figure(result.plot(color_by=args.color_by, title=model.name or None), args)
    report_peak_memory(args)
    return 0
