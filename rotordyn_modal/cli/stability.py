"""``stability MODEL --speeds R [--vary KEY (--values R | --scale R)]``."""

from __future__ import annotations

import sys

from ..errors import InputError
from ._common import (add_model_argument, add_outputs, add_speed_unit, open_model, parse_list,
                      parse_range, save_figure, show_progress, speeds_option, use_agg, write_table)

NAME = "stability"
HELP = "stability over speed, or a map over speed and one model parameter"
DESCRIPTION = """Real parts, damping ratios and log decrements of every mode over speed; threshold
speeds where a real part crosses zero, refined by root-finding. With --vary KEY and
--values or --scale, a map over speed and that parameter with the boundary drawn.
KEY is a dotted key: suspensions.mount-FL.damping, rotors.fan.polar_inertia,
suspensions.mount-FL.stiffness[3][4]. --values and --scale take START:STOP:N or a
comma-separated list.

CSV columns: speed_rpm,value,mode,real_part,damping_ratio,log_decrement,frequency_hz,whirl

examples:
  rotordyn-modal stability examples/unstable_cross_coupled.toml --speeds 0:20000:401
  rotordyn-modal stability examples/unstable_cross_coupled.toml --speeds 0:20000:201 \\
      --vary suspensions.bearing-A.damping --scale 0.5:2:31 --plot map.png
  rotordyn-modal stability examples/journal_rotor.toml --speeds 100:20000:201 --plot s.png
      (the figure is scaled to the modes that decide stability, threshold speeds are
      labelled lines, the speed axis in --speed-unit; docs/figures.md)"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, help="START:STOP:N speeds of the reference rotor")
    add_speed_unit(parser)
    parser.add_argument("--vary", metavar="KEY", help="dotted key of the parameter of a map")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--values", help="values to set KEY to: START:STOP:N or a list")
    group.add_argument("--scale", help="factors to multiply KEY by: START:STOP:N or a list")
    add_outputs(parser)


def _grid(text, option):
    return parse_range(text, option) if ":" in text else parse_list(text, option)


def run(args) -> int:
    from ..analysis.stability import stability
    model = open_model(args)
    if args.vary and not (args.values or args.scale):
        raise InputError("--vary needs --values or --scale")
    if (args.values or args.scale) and not args.vary:
        raise InputError("--values/--scale need --vary KEY")
    values = _grid(args.values, "--values") if args.values else None
    scale = _grid(args.scale, "--scale") if args.scale else None
    result = stability(model, speeds_option(args), vary=args.vary, values=values, scale=scale,
                       progress=show_progress(args))
    write_table(result.to_dataframe(), args)
    if not args.quiet:
        _print_thresholds(result)
    if args.plot:
        use_agg()
        save_figure(result.plot(speed_unit=args.speed_unit, title=model.name or None), args)
    return 0


def _print_thresholds(result):
    import numpy as np

    if hasattr(result, "results"):
        for value, speed in zip(result.values, result.threshold_speeds):
            text = "stable over the range" if np.isnan(speed) else f"unstable from {speed * 30 / np.pi:.6g} rpm"
            print(f"{result.key} {'=' if result.mode_of_variation == 'values' else 'x'} {value:g}: {text}",
                  file=sys.stderr)
        return
    for speed, mode, onset in zip(result.thresholds, result.threshold_modes, result.threshold_onsets):
        print(f"mode {mode} {'loses' if onset else 'regains'} stability at {speed * 30 / np.pi:.8g} rpm",
              file=sys.stderr)
    if not len(result.thresholds):
        print("no change of stability over the range "
              f"({'stable' if result.stable.all() else 'unstable'} throughout)", file=sys.stderr)
