"""``critical-speeds MODEL --speeds R [--orders 1,2]``."""

from __future__ import annotations

from ._common import (add_model_argument, add_outputs, add_speed_unit, open_model, parse_list,
                      save_figure, show_progress, speeds_option, use_agg, write_table)

NAME = "critical-speeds"
HELP = "crossings of natural frequencies with every rotor's and gear mesh's excitation orders"
DESCRIPTION = """Critical speeds: where a tracked natural frequency equals an excitation order of a
rotor's own spin (which differs from rotor to rotor through the transmissions) or of
a gear mesh. Each crossing is refined by root-finding on the eigenproblem, so the
result does not depend on the grid beyond bracketing the crossing.

CSV columns: source,order,mode,speed_rpm,frequency_hz,whirl,whirl_ratio,damping_ratio

A sweep or a set of crossings that would not fit in the memory at hand is refused before
its work, with its estimate (exit 2); ROTORDYN_MODAL_MEMORY_GB sets the memory to count on.
On a terminal, bars show the progress of the eigen-solutions and of the refinement.

example:
  rotordyn-modal critical-speeds examples/gear_machine.toml --speeds 0:12000:241 --orders 1,2"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, help="START:STOP:N search grid of reference speeds")
    add_speed_unit(parser)
    parser.add_argument("--orders", default="1", help="comma-separated excitation orders (default 1)")
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.campbell import campbell
    model = open_model(args)
    result = campbell(model, speeds_option(args), orders=tuple(parse_list(args.orders, "--orders")),
                      progress=show_progress(args))
    write_table(result.critical.to_dataframe(), args)
    if args.plot:
        use_agg()
        save_figure(result.plot(title=model.name or None), args)
    return 0
