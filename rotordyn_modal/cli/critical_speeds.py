"""``critical-speeds MODEL --speeds R [--orders 1,2]``."""

from __future__ import annotations

from ._common import ESTIMATING, starting
from ._common import (IN_SPEED_UNIT, add_allow_long, add_model_argument, add_outputs, add_speed_unit, lowest_option,
                      max_frequency_option, open_model, parse_list,
                      save_figure, show_progress, speeds_option, speeds_text, use_agg,
                      undamped_zeros, write_table)
from ._units import NOTHING_TO_CONVERT

NAME = "critical-speeds"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"orders": "--orders", "speeds": "--speeds"}
HELP = "crossings of natural frequencies with every rotor's and gear mesh's excitation orders"
UNITS_HELP = NOTHING_TO_CONVERT   # --units (docs/units.md)
DESCRIPTION = """Critical speeds: where a tracked natural frequency equals an excitation order of a
rotor's own spin (which differs from rotor to rotor through the transmissions) or of
a gear mesh. Each crossing is refined by root-finding on the eigenproblem, so the
result does not depend on the grid beyond bracketing the crossing.

CSV columns: source,order,mode,speed_rpm,frequency_hz,whirl,whirl_ratio,damping_ratio,mode_at_speed
('mode' is the mode's label tracked over the sweep, as in campbell; 'mode_at_speed' its number
in 'modes --speed SPEED_RPM', whose --shape draws it)

A sweep or a set of crossings that would not fit in the memory at hand is refused before
its work, with its estimate (exit 2); ROTORDYN_MODAL_MEMORY_GB sets the memory to count on.
So is one estimated to take more than 30 minutes of CPU time (--allow-long runs it anyway,
ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit).
On a terminal, bars show the progress of the eigen-solutions and of the refinement.

example:
  rotordyn-modal critical-speeds examples/gear_machine.toml --speeds 0:12000:241 --orders 1,2"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, metavar="START:STOP:N",
                        help=f"search grid of reference speeds {IN_SPEED_UNIT}")
    add_speed_unit(parser)
    parser.add_argument("--orders", default="1", metavar="ORDER[,ORDER]", help="comma-separated excitation orders (default 1)")
    parser.add_argument("--lowest", metavar="N",
                        help="only the crossings of the N lowest-frequency modes at each speed, each mode the "
                             "full model's root to round-off, without solving for every root (see campbell "
                             "--lowest)")
    parser.add_argument("--max-frequency", metavar="HZ",
                        help="only the crossings at frequencies up to HZ [Hz], from the modes below HZ at each "
                             "speed, each the full model's root to round-off, without solving for every root (see "
                             "campbell --max-frequency)")
    add_allow_long(parser)
    add_outputs(parser)


def run(args) -> int:
    from ..analysis._work import refuse_long_work
    from ..analysis.campbell import campbell
    from ..linear_system import kept_form
    model = open_model(args)
    modes, limit = lowest_option(args.lowest, model), max_frequency_option(args.max_frequency)
    speeds, orders = speeds_option(args), tuple(parse_list(args.orders, "--orders"))
    if modes is None and limit is None:
        with starting(args, ESTIMATING):
            refuse_long_work(model, speeds, orders, numbers=True, advice="ask for the lowest modes only (--lowest "
                             "N, --max-frequency HZ), fewer excitation orders (--orders) or fewer speeds (--speeds)",
                             memory=True)
    with kept_form(model):              # the sweep and the mode numbers build one linear form
        result = campbell(model, speeds, orders=orders, progress=show_progress(args), modes=modes, max_frequency=limit)
        # the table's mode_at_speed: the number 'modes --speed' gives each crossing's mode there
        table = undamped_zeros(result.critical.to_dataframe(), model)
    write_table(table, args, empty=f"no critical speed {speeds_text(args)} (orders {args.orders})")
    if args.plot:
        use_agg()
        save_figure(result.plot(title=model.name or None, speed_unit=args.speed_unit), args)
    return 0

