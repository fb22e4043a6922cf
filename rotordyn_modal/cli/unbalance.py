"""``unbalance MODEL --speeds R [--output NAME]``: steady unbalance response vs speed."""

from __future__ import annotations

import sys

from ..analysis.unbalance import unbalance_response
from ._common import (add_model_argument, add_outputs, add_speed_unit, open_model, parse_number,
                      print_table, save_figure, speeds_option, to_rad_s, use_agg, write_table)
from .frf import names

NAME = "unbalance"
HELP = "steady unbalance response vs speed, each rotor's harmonic at its own spin frequency"
DESCRIPTION = """Response of the sensors to the model's [[unbalances]] over a speed sweep. Every
rotor's unbalances excite at that rotor's own spin frequency (|speed ratio| x speed,
turning its own way); each rotor (source) is reported separately: amplitude (0-peak) and
phase (x(t) = amplitude cos(2 pi frequency t + phase)). Rows for the force each suspension
passes to the ground (output NAME:Fx ... NAME:Mz, N and N m) follow the sensors'. Peaks get
the API 684 amplification factor and, with --operating-speed, the separation margin.

CSV columns: speed_rpm,output,source,frequency_hz,amplitude,phase_deg

example:
  rotordyn-modal unbalance examples/gear_machine.toml --speeds 0:6000:601 --output acc-top-z \\
      --operating-speed 3000 --plot unbalance.png"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, help="START:STOP:N speeds of the reference rotor")
    add_speed_unit(parser)
    parser.add_argument("--output", help="sensor name(s), comma-separated (default all)")
    parser.add_argument("--quantity", choices=["displacement", "velocity", "acceleration"], default="displacement")
    parser.add_argument("--operating-speed", help="operating speed (same unit as --speeds) for the separation margin")
    add_outputs(parser)


def run(args) -> int:
    model = open_model(args)
    result = unbalance_response(model, speeds_option(args), outputs=names(args.output), quantity=args.quantity)
    write_table(result.to_dataframe(), args)
    operating = None if args.operating_speed is None else \
        float(to_rad_s(parse_number(args.operating_speed, "--operating-speed"), args.speed_unit))
    peaks = result.peaks(operating)
    if not args.quiet:
        print("\npeaks (API 684):", file=sys.stderr)
        print_table(peaks)
    if args.plot:
        use_agg()
        save_figure(result.plot(peaks=peaks, speed_unit=args.speed_unit), args)
    return 0
