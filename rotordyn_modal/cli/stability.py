"""``stability MODEL --speeds R [--lowest N] [--max-frequency HZ] [--vary KEY (--values R | --scale R)]``."""

from __future__ import annotations

import sys

from ..errors import InputError
from ._common import ESTIMATING, starting
from ._common import (IN_SPEED_UNIT, add_allow_long, add_model_argument, add_outputs, add_speed_unit, lowest_option,
                      max_frequency_option, open_model, parse_list,
                      parse_range, save_figure, show_progress, speeds_option, speeds_text,
                      use_agg, with_round_off_rows, write_table)
from ._units import NOTHING_TO_CONVERT

NAME = "stability"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"speeds": "--speeds"}
HELP = "stability over speed, or a map over speed and one model parameter"
UNITS_HELP = (NOTHING_TO_CONVERT + "; --vary's values and the 'value' column are the model key's, in the "
              "model file's SI unit")   # --units (docs/units.md)
DESCRIPTION = """Real parts, damping ratios and log decrements of every mode over speed; threshold
speeds where a real part crosses zero, refined by root-finding. With --vary KEY and
--values or --scale, a map over speed and that parameter with the boundary drawn.
Real parts within round-off of zero (docs/theory.md) count as zero: no threshold where the
sign is round-off. The terminal names each threshold's mode (its tracked label, frequency,
whirl, and its number N in 'modes --speed THRESHOLD', whose --shape N draws it), then every
interval of speeds where the machine is unstable (per value of a map), or, when it is stable
throughout, the least damped mode and its log decrement.
KEY is a dotted key: suspensions.mount-FL.damping, rotors.fan.polar_inertia,
suspensions.mount-FL.stiffness[3][4]. --values and --scale take START:STOP:N or a
comma-separated list. Work estimated to take more than 30 minutes of CPU time is refused
before it starts, with the estimate (--allow-long runs it anyway, ROTORDYN_MODAL_MAX_CPU_MINUTES
sets the limit).
--lowest N solves and judges only the N lowest-frequency modes of each speed (each the full
model's root to round-off, thresholds refined on them; for flexible rotors of hundreds of
coordinates): the modes above them and real (non-oscillating) roots are NOT checked, and the
summary line says so ("... for the N lowest modes"). It also works with --vary.
--max-frequency HZ solves and judges only the modes of damped natural frequency at most HZ at
each speed (with --lowest N, the lowest N of them), each the full model's root to round-off:
the modes above HZ and real roots are NOT checked, and the summary line says so ("... for the
modes below HZ Hz; modes above HZ Hz and real roots not checked"); the table leaves out a
mode's rows at the speeds where it lies above HZ. It also works with --vary.

CSV columns: speed_rpm,value,mode,real_part,damping_ratio,log_decrement,frequency_hz,whirl,mode_at_speed
(real_part is the root's real part in 1/s, in both unit systems: the mode's amplitude goes as
exp(real_part t), so a positive real part grows; damping_ratio and log_decrement have no unit;
'value' is the model key's value in the model file's SI unit, or the factor; 'mode' is the
mode's label tracked over the sweep; 'mode_at_speed' its number in 'modes --speed SPEED_RPM',
empty for roots that are not modes there; docs/units.md lists every column's unit)

examples:
  rotordyn-modal stability examples/unstable_cross_coupled.toml --speeds 0:20000:401
  rotordyn-modal stability examples/unstable_cross_coupled.toml --speeds 0:20000:201 \\
      --vary suspensions.bearing-A.damping --scale 0.5:2:31 --plot map.png
  rotordyn-modal stability examples/compressor_rotor.toml --speeds 0:12000:201 --lowest 12
  rotordyn-modal stability examples/compressor_rotor.toml --speeds 0:12000:201 --max-frequency 450
  rotordyn-modal stability examples/journal_rotor.toml --speeds 100:20000:201 --plot s.png
      (the figure is scaled to the modes that decide stability, threshold speeds are
      labelled lines, the speed axis in --speed-unit; docs/figures.md)"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, metavar="START:STOP:N",
                        help=f"speeds of the reference rotor {IN_SPEED_UNIT}")
    add_speed_unit(parser)
    parser.add_argument("--lowest", metavar="N",
                        help="only the N lowest-frequency modes of each speed, each the full model's root to "
                             "round-off, without solving for every root (faster for large flexible rotors): "
                             "modes above them and real roots are not checked; docs/theory.md, 'The lowest "
                             "modes only'")
    parser.add_argument("--max-frequency", metavar="HZ",
                        help="only the modes of damped natural frequency at most HZ [Hz] at each speed (with "
                             "--lowest N, the lowest N of them), each the full model's root to round-off: modes "
                             "above HZ and real roots are not checked; docs/theory.md, 'The modes below a "
                             "frequency'")
    parser.add_argument("--vary", metavar="KEY", help="dotted key of the parameter of a map")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--values", metavar="START:STOP:N|LIST", help="values to set KEY to: a range or a comma list")
    group.add_argument("--scale", metavar="START:STOP:N|LIST", help="factors to multiply KEY by: a range or a comma list")
    add_allow_long(parser)
    add_outputs(parser)


def _grid(text, option):
    return parse_range(text, option) if ":" in text else parse_list(text, option)


def run(args) -> int:
    from ..analysis._work import refuse_long_work
    from ..analysis.stability import stability
    model = open_model(args)
    if args.vary and not (args.values or args.scale):
        raise InputError("--vary needs --values or --scale")
    if (args.values or args.scale) and not args.vary:
        raise InputError("--values/--scale need --vary KEY")
    values = _grid(args.values, "--values") if args.values else None
    scale = _grid(args.scale, "--scale") if args.scale else None
    speeds, lowest = speeds_option(args), lowest_option(args.lowest, model)
    limit = max_frequency_option(args.max_frequency)
    count = len(values if values is not None else scale) if args.vary else 1
    if lowest is None and limit is None:
        fewer = ("ask for the lowest modes only (--lowest N, --max-frequency HZ), use fewer speeds (--speeds)"
                 + (" or fewer values (--values, --scale)" if args.vary else ""))
        # the sweep's shapes (as campbell --no-critical's, a map's one value at a time) checked
        # against the memory at hand first: 2,006 coordinates at 11 speeds under 2.4 GiB ran 2 min
        # and died in MemoryError (exit 1)
        with starting(args, ESTIMATING):
            refuse_long_work(model, speeds, critical=False, solutions=count * len(speeds), advice=fewer, memory=True,
                             what="a stability sweep")
    result = stability(model, speeds, vary=args.vary, values=values, scale=scale, progress=show_progress(args),
                       modes=lowest, max_frequency=limit)
    empty = None if limit is None else f"no mode below {limit:g} Hz {speeds_text(args)}"
    table = result.to_dataframe()
    write_table(table, args, empty=empty, shown=with_round_off_rows(table, result))
    if not args.quiet:
        _print_thresholds(result)
    if args.plot:
        use_agg()
        title = model.name or None
        if lowest is not None or limit is not None:         # what the figure leaves out, in its title
            title = (f"{title or ('Stability map' if args.vary else 'Stability over speed')}: "
                     + _judged(lowest, limit) + " only")
        save_figure(result.plot(speed_unit=args.speed_unit, title=title), args)
    return 0


def _print_thresholds(result):
    """Per map value, or for the one sweep: every threshold (with the root that crosses and its
    number in ``modes --speed``), then every interval of instability, or, stable throughout, the
    least damped mode."""
    if hasattr(result, "results"):
        sign = "=" if result.mode_of_variation == "values" else "x"
        for value, each in zip(result.values, result.results):
            print(f"{result.key} {sign} {value:g}: {_summary(each)}", file=sys.stderr)
        return
    for k in range(len(result.thresholds)):
        print(_threshold_line(result, k), file=sys.stderr)
    print(_summary(result), file=sys.stderr)


def _rpm(speed):
    """A speed [rad/s] as rpm to 8 significant digits (what ``modes --speed`` takes back)."""
    import numpy as np

    return f"{speed * 30 / np.pi:.8g}"


def _threshold_line(result, k):
    """``mode 5 loses stability at 10886.198 rpm (6.3662 Hz, backward whirl; mode 2 of modes --speed 10886.198)``."""
    speed = _rpm(result.thresholds[k])
    change = "loses" if result.threshold_onsets[k] else "regains"
    number = int(result.threshold_modes_at_speed[k])
    where = (f"mode {number} of modes --speed {speed}" if number else
             f"a root that is not a mode at that speed: modes --speed {speed} does not list it")
    return (f"mode {result.threshold_modes[k]} {change} stability at {speed} rpm "
            f"({result.threshold_frequencies_hz[k]:.5g} Hz, {_whirl(result.threshold_whirl[k])}; {where})")


def _summary(result):
    """One line: every interval of speeds where the machine is unstable, or else that it is
    stable (naming the least damped mode) or marginal over the range; with ``--lowest N`` or
    ``--max-frequency HZ``, of those modes, and that the others were not checked."""
    intervals = result.unstable_intervals
    limit = result.max_frequency_hz
    lowest = "" if result.lowest is None and limit is None else _judged(result.lowest, limit)
    of = f" for {lowest}" if lowest else ""
    unchecked = f"; {_unchecked(result.lowest, limit)} and real roots not checked" if lowest else ""
    if limit is not None and not result.eigenvalues.shape[1]:
        return f"stability not checked: no mode below {limit:g} Hz at any speed (modes above it and real roots not checked)"
    if intervals:
        return ("unstable " + " and ".join(_interval(result, start, stop) for start, stop in intervals)
                + (f" (among {lowest}{unchecked})" if lowest else ""))
    if result.stable.all():
        return f"stable over the range{of}{unchecked}; least damped: " + _least_damped(result)
    marginal = int((result.largest_real_parts == 0).sum())
    return (f"stable or marginal over the range{of}{unchecked}: at {marginal} of {len(result.speeds)} speeds the "
            "largest real part is zero to round-off (an undamped mode, or a root too small beside the model's "
            "largest to tell its sign; docs/theory.md, section 11); least damped: " + _least_damped(result))


def _judged(lowest, limit):
    """The modes judged: ``the 6 lowest modes``, ``the modes below 450 Hz``, ``the 6 lowest modes
    below 450 Hz`` (``lowest`` an int or None, ``limit`` [Hz] or None, not both None)."""
    modes = ("the modes" if lowest is None else "the lowest mode" if lowest == 1 else f"the {lowest} lowest modes")
    return modes + ("" if limit is None else f" below {limit:g} Hz")


def _unchecked(lowest, limit):
    """The modes not judged: ``modes above them``, ``modes above 450 Hz``, ``modes above them or
    above 450 Hz``."""
    above = [] if lowest is None else ["above it" if lowest == 1 else "above them"]
    above += [] if limit is None else [f"above {limit:g} Hz"]
    return "modes " + " or ".join(above)


def _interval(result, start, stop):
    import numpy as np

    begin = (f"from {start * 30 / np.pi:.6g} rpm" if np.isfinite(start)
             else f"from the start of the range ({result.speeds_rpm[0]:.6g} rpm)")
    return begin + (f" to {stop * 30 / np.pi:.6g} rpm" if np.isfinite(stop) else "")


def _least_damped(result):
    """``mode 4 at 2500 rpm: log decrement 0.123, 6.21 Hz, backward whirl (mode 2 of modes --speed 2500)``."""
    found = result.least_damped()
    if found is None:
        return "none of the roots is a mode (no oscillating root at any speed)"
    mode, k = found
    column = mode - 1
    speed = _rpm(result.speeds[k])
    undamped = result.significant_real_parts[k, column] == 0
    log_dec = "0 (zero to round-off)" if undamped else f"{result.log_decrements[k, column]:.4g}"
    return (f"mode {mode} at {speed} rpm: log decrement {log_dec}, "
            f"{result.frequencies_hz[k, column]:.5g} Hz, {_whirl(result.whirl[k, column])} "
            f"(mode {result.modes_at_speed[k, column]} of modes --speed {speed})")


def _whirl(label):
    return "no whirl" if label == "none" else f"{label} whirl"
