"""``ucs-map MODEL --stiffness 1e5:1e9:41 [--lowest 4] [--bearings NAME[,NAME]]``."""

from __future__ import annotations

import sys
import warnings

import numpy as np

from .._progress import phase
from ..errors import InputError
from ._common import (IN_SPEED_UNIT, add_alias, as_typed, NAME_LIST_HELP, add_model_argument, add_outputs, add_speed_unit, check_speeds, open_model,
                      parse_band, parse_names, parse_range, save_figure, show_progress, use_agg, whole_number, write_table)
from ..units import from_system, to_system, unit_label
from ._units import convert_table, kinds_by_ending

NAME = "ucs-map"
HELP = "undamped critical speed map: forward critical speeds against bearing stiffness"
DESCRIPTION = """Undamped critical speed map (API 684): the chosen bearings' radial stiffness set
isotropic to each value of --stiffness (log-spaced: START:STOP:N with N values from START to
STOP, both included), their cross-coupling and all damping of the machine removed, their axial
and tilt stiffness kept; at each value the lowest forward critical speeds (a forward-whirling
mode's natural frequency equal to the reference rotor's speed: order 1). The figure draws each
mode followed over the stiffness by its shape (curves may cross; a square where a mode stops
being a forward crossing), named by the body and motion with most of its kinetic energy ("2
pump conical"), against the stiffness on log-log axes, each chosen bearing's own Kxx and Kyy
over speed over them (tables and journal bearings; constant ones as vertical lines), their
crossings marked, the rigid-support asymptotes (the chosen bearings radially rigid) beyond the
sweep's last stiffness, and --operating-range as a band (a single rated speed, LO = HI, as a
dashed line). Bearings not chosen keep their coefficients, which must be constant.
docs/level1_and_ucs.md gives the definitions.

CSV columns: stiffness_n_per_m,mode,name,speed_rpm,frequency_hz (stiffness_lbf_per_in with --units us;
mode and name = the followed mode, numbered and named as on the figure and in the terminal's
crossings; speed empty where that mode is no forward critical speed at that stiffness). The terminal lists the crossings of the bearings' curves with the followed modes (their
numbers and names as on the figure).

examples:
  rotordyn-modal ucs-map examples/journal_rotor.toml --stiffness 1e5:1e10:51 --plot ucs.png
  rotordyn-modal ucs-map examples/fan_on_bearings.toml --stiffness 1e5:1e9:41 \\
      --bearings fan-DE,fan-NDE --operating-range 1000:3000 --out ucs.csv"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--stiffness", required=True, metavar="START:STOP:N",
                        help="radial stiffness values [N/m; lbf/in with --units us], log-spaced, e.g. 1e5:1e9:41")
    parser.add_argument("--lowest", dest="modes", metavar="N", default="4",
                        help="the N lowest forward critical speeds at each stiffness (default 4)")
    add_alias(parser, "--lowest", "--modes")
    parser.add_argument("--bearings", metavar="NAME[,NAME]",
                        help=f"the bearings whose stiffness is swept, {NAME_LIST_HELP} (default all)")
    parser.add_argument("--speeds", metavar="START:STOP:N",
                        help=f"speeds {IN_SPEED_UNIT} at which the speed-dependent bearings' stiffness is drawn "
                             "(default: over the map's speeds)")
    parser.add_argument("--operating-range", dest="operating", metavar="LO:HI",
                        help=f"operating speed range {IN_SPEED_UNIT}, drawn as a band (LO = HI: one rated "
                             "speed, drawn as a line)")
    add_alias(parser, "--operating-range", "--operating")
    add_speed_unit(parser)
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.ucs_map import check_operating_tables, ucs_map

    stiffness = _stiffness(args.stiffness, args.units)
    modes = _modes(args.modes, as_typed(args, "--lowest"))
    speeds = check_speeds(parse_range(args.speeds, "--speeds", largest=None), args.speeds, args.speed_unit,
                          "--speeds") if args.speeds else None
    if speeds is not None and not (speeds > 0).any():   # the curves are drawn at positive speeds only
        raise InputError(f"{as_typed(args, '--speeds')} {args.speeds!r}: expected a speed > 0 [{args.speed_unit}] "
                         "(the speed-dependent bearings' stiffness is drawn at positive speeds)")
    operating = _operating(args) if args.operating is not None else None
    model = open_model(args)
    bearings = parse_names(args.bearings, "--bearings", [b.name for b in model.bearings])
    chosen = [b for b in model.bearings if bearings is None or b.name in bearings]
    check_operating_tables(model, operating, chosen, f"{as_typed(args, '--operating-range')} {args.operating}")
    if speeds is not None:
        _warn_speeds_unused(chosen, args)
    # one batched solve per stiffness value, no steps to count (500 geared rotors: more than 400 s)
    with phase(show_progress(args), f"ucs-map: {len(stiffness):,} stiffness values, {model.dofs.n:,} coordinates"):
        result = ucs_map(model, stiffness, modes=modes, bearings=bearings, speeds=speeds, operating=operating)
    table = result.modes_dataframe()      # the figure's followed modes: one numbering
    write_table(convert_table(table, kinds_by_ending(table.columns), args.units), args)
    if not args.quiet:
        _print_crossings(result, args.units)
    if args.plot:
        use_agg()
        save_figure(result.plot(units=args.units), args)
    return 0


def _warn_speeds_unused(chosen, args) -> None:
    """One warning line where ``--speeds`` is given but none of the map's bearings ``chosen`` has
    speed-dependent coefficients: the option only sets where their stiffness curves are drawn,
    and a constant bearing's stiffness is one vertical line whatever the speeds (it was ignored
    without a word)."""
    if any(bearing.coefficients.kind != "constant" for bearing in chosen):
        return
    from ..model._table import visible

    names = ", ".join(visible(bearing.name) for bearing in chosen)
    warnings.warn(f"{as_typed(args, '--speeds')} {args.speeds}: changes nothing: it sets the speeds at which "
                  f"speed-dependent bearings' stiffness is drawn, and the map's bearings ({names}) are constant "
                  "(each drawn as one vertical line)")


def _stiffness(text, system="si"):
    """``START:STOP:N`` (in the unit of ``system``) -> N log-spaced values [N/m], START > 0."""
    from ..analysis.ucs_map import STIFFNESS_RANGE

    linear = parse_range(text, "--stiffness")
    low, high = to_system(np.array(STIFFNESS_RANGE), "stiffness", system)
    if not (low <= linear[0] and linear[-1] <= high):
        raise InputError(f"--stiffness {text!r}: START and STOP must lie from {low:g} to {high:g} "
                         f"{unit_label('stiffness', system)} (log-spaced stiffness)")
    return from_system(np.geomspace(linear[0], linear[-1], len(linear)), "stiffness", system)


def _modes(text, option="--lowest"):
    try:
        value = whole_number(text)
    except ValueError:
        raise InputError(f"{option} {text!r}: expected a whole number from 1 to 1000") from None
    if not 1 <= value <= 1000:
        raise InputError(f"{option} {text!r}: expected a whole number from 1 to 1000")
    return value


def _operating(args, low_open=False):
    """--operating-range LO:HI [--speed-unit] -> (low, high) [rad/s], LO <= HI (LO = HI: one rated
    speed), HI > 0; LO > 0 with ``low_open``."""
    option = as_typed(args, "--operating-range")
    band = parse_band(args.operating, option, args.speed_unit, low_open=low_open, example="1000:3000",
                      largest=None, single=True)
    if not band[1] > 0:
        raise InputError(f"{option} {args.operating!r}: expected HI > 0 [{args.speed_unit}]")
    return tuple(check_speeds(np.array(band), args.operating, args.speed_unit, option))


def _print_crossings(result, system="si"):
    table = result.crossings_dataframe()
    if table.empty:
        print("no bearing's stiffness curve meets a mode's curve on the map", file=sys.stderr)
        return
    for row in table.itertuples(index=False):
        stiffness = f"{to_system(row.stiffness_n_per_m, 'stiffness', system):.4g} {unit_label('stiffness', system)}"
        print(f"bearing {row.bearing} K{row.axis} = {stiffness} meets mode {row.mode} "
              f"({row.name}) at {row.speed_rpm:.6g} rpm", file=sys.stderr)
