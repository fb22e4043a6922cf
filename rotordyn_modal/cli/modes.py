"""``modes MODEL --speed S``: modal analysis at one speed."""

from __future__ import annotations

import sys

from ..analysis import modal
from ..analysis.modal import OVERDAMPED_LIMIT
from ._common import (add_model_argument, add_outputs, add_speed_unit, open_model, parse_number,
                      save_figure, to_rad_s, use_agg, write_table)

NAME = "modes"
HELP = "modal analysis at one speed"
DESCRIPTION = """Eigenvalues of the machine at one speed of the reference rotor: damped natural
frequency, damping ratio, log decrement and whirl direction of every oscillating mode.

CSV columns: mode,frequency_hz,damping_ratio,log_decrement,whirl,whirl_ratio,real_part

example:
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --out modes.csv"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speed", default="0", help="reference rotor speed (default 0; negative reverses the spin)")
    add_speed_unit(parser)
    add_outputs(parser)


def run(args) -> int:
    model = open_model(args)
    speed = float(to_rad_s(parse_number(args.speed, "--speed"), args.speed_unit))
    result = modal(model, speed)
    write_table(result.to_dataframe(), args)
    overdamped = int(result.overdamped.sum())
    if overdamped and not args.quiet:
        print(f"{overdamped} overdamped root pair(s) (damping ratio > {OVERDAMPED_LIMIT}) not listed as modes "
              "(docs/model-file.md, roots that are not modes)", file=sys.stderr)
    if args.plot:
        use_agg()
        save_figure(result.plot(), args)
    return 0
