"""``campbell MODEL --speeds R``: tracked Campbell diagram."""

from __future__ import annotations

import sys

import numpy as np

from ._common import ESTIMATING, starting
from ._common import (IN_SPEED_UNIT, add_allow_long, add_model_argument, add_outputs, add_speed_unit, lowest_option,
                      max_frequency_option, open_model, parse_list,
                      save_figure, show_progress, speeds_option, speeds_text, use_agg,
                      undamped_zeros, with_round_off_rows, write_table)
from ._units import NOTHING_TO_CONVERT

NAME = "campbell"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"orders": "--orders", "speeds": "--speeds"}
HELP = "Campbell diagram: modes tracked across speeds"
UNITS_HELP = NOTHING_TO_CONVERT   # --units (docs/units.md)
DESCRIPTION = """Natural frequencies, damping and whirl of every mode over a speed range, each mode
tracked by its shape so that it keeps its label where frequencies cross. The figure
shows forward (solid blue) and backward (dashed red) whirl, every rotor's and gear
mesh's excitation orders, and the critical speeds (where crossings crowd, a note says how
many are labelled and lists the others by mode; where the curves' ends crowd, one label
beside the right edge names several, 'modes 11, 12'); unstable stretches lie on a red band,
a red triangle where a mode becomes unstable. Its speed axis is in --speed-unit; its
frequency axis is logarithmic when the modes at one speed span more than 30x (e.g. mount
modes at 5 Hz and bearing modes at 1 kHz), else linear (--freq-scale); --freq-range or
--freq-max limit it. --lowest N or --max-frequency HZ solve only the modes asked for
(exact, faster for large flexible rotors; docs/theory.md section 17). Where the modes crowd
right above the N lowest (hundreds of rotors on bearings), --lowest N takes shift-invert
Arnoldi at each speed, with a bar of the speeds on a terminal (section 17, "Crowded spectra").

CSV columns: speed_rpm,mode,frequency_hz,damping_ratio,log_decrement,whirl,whirl_ratio,real_part,mode_at_speed
(real_part is the root's real part in 1/s, in both unit systems: the mode's amplitude goes as
exp(real_part t); damping_ratio, log_decrement and whirl_ratio have no unit; 'mode' is the
mode's label tracked over the sweep; 'mode_at_speed' its number in 'modes --speed SPEED_RPM',
whose --shape draws it; docs/units.md lists every column's unit)

A sweep or a set of critical speeds that would not fit in the memory at hand is refused
before its work, with its estimate (exit 2); ROTORDYN_MODAL_MEMORY_GB sets the memory to
count on. So is one estimated to take more than 30 minutes of CPU time (its eigen-solutions
and crossings counted from the model's size; --allow-long runs it anyway,
ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit). With --lowest or --max-frequency, the speeds
the reduced basis cannot serve (an axisymmetric rotor at rest) are solved whole, and that solve is
refused alike before its work, naming the speeds (mounts with Maxwell branches are served by
their rational stiffness, docs/theory.md section 17). On a terminal, bars show the progress of the
eigen-solutions and of the critical speeds' refinement.

examples:
  rotordyn-modal campbell examples/gear_machine.toml --speeds 0:12000:241 --plot campbell.png
  rotordyn-modal campbell examples/motor_pump_on_mounts.toml --speeds 0:3600:181 --orders 1,2 \\
      --freq-range 0:40 --plot mounts.png
  rotordyn-modal campbell examples/compressor_rotor.toml --speeds 0:12000:201 --orders 1,2 \\
      --max-frequency 450 --plot compressor.png"""

#: what to do about work over the CPU-time limit
LONG_ADVICE = ("ask for the lowest modes only (--lowest N, --max-frequency HZ), fewer excitation orders (--orders) "
               "or fewer speeds (--speeds), or leave out the critical speeds (--no-critical)")
#: the same for a diagram already without its critical speeds (--no-critical)
NO_CRITICAL_ADVICE = "ask for the lowest modes only (--lowest N, --max-frequency HZ) or fewer speeds (--speeds)"


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, metavar="START:STOP:N",
                        help=f"speeds of the reference rotor {IN_SPEED_UNIT}")
    add_speed_unit(parser)
    parser.add_argument("--orders", default="1", metavar="ORDER[,ORDER]", help="excitation orders drawn and marked (default 1), e.g. 1,2")
    parser.add_argument("--no-critical", action="store_true",
                        help="do not find the critical speeds (the orders are still drawn): large machines "
                             "cross the orders of every rotor and gear mesh many thousand times")
    parser.add_argument("--lowest", metavar="N",
                        help="only the N lowest-frequency modes at each speed, each the full model's root to "
                             "round-off, without solving for every root (faster for large flexible rotors; the "
                             "columns then follow those N; docs/theory.md, 'The lowest modes only'); N at least the "
                             "model's number of roots is every root")
    parser.add_argument("--max-frequency", metavar="HZ",
                        help="only the modes of damped natural frequency at most HZ [Hz] at each speed, each the "
                             "full model's root to round-off, without solving for every root (with --lowest N, the "
                             "lowest N of them); a mode is drawn and listed at the speeds where it lies below HZ, "
                             "and the critical speeds are those at frequencies up to HZ (docs/theory.md, 'The "
                             "modes below a frequency')")
    parser.add_argument("--color-by", choices=["log_decrement", "damping_ratio"],
                        help="colour the curves by this quantity instead of by whirl")
    _add_frequency_axis(parser)
    add_allow_long(parser)
    add_outputs(parser)


def run(args) -> int:
    from ..analysis._work import refuse_long_work
    from ..analysis.campbell import campbell
    model = open_model(args)
    axis = _frequency_axis(args)    # bad limits refused before the work
    speeds, orders = speeds_option(args), tuple(parse_list(args.orders, "--orders"))
    lowest, limit = lowest_option(args.lowest, model), max_frequency_option(args.max_frequency)
    if lowest is None and limit is None:
        # without critical speeds, what is left to advise is the lowest modes and fewer speeds
        with starting(args, ESTIMATING):
            refuse_long_work(model, speeds, orders, critical=not args.no_critical, memory=True,
                             advice=NO_CRITICAL_ADVICE if args.no_critical else LONG_ADVICE)
    result = campbell(model, speeds, orders=orders, progress=show_progress(args), critical=not args.no_critical,
                      modes=lowest, max_frequency=limit)
    empty = (f"no oscillating modes {speeds_text(args)}: {result.eigenvalues.shape[1]} roots at each speed, all "
             "real or overdamped") if limit is None else f"no mode below {limit:g} Hz {speeds_text(args)}"
    table = result.to_dataframe()
    write_table(table, args, empty=empty, shown=undamped_zeros(with_round_off_rows(table, result), model))
    if (counts := _not_listed(result)) and len(table) and not args.quiet:
        print(f"{counts} not listed as modes (docs/model-file.md, roots that are not modes)", file=sys.stderr)
    if args.plot:
        use_agg()
        save_figure(result.plot(color_by=args.color_by, title=model.name or None, speed_unit=args.speed_unit,
                                **axis), args)
    return 0


def _not_listed(result) -> str:
    """The result's roots that are not modes, counted as ``modes`` counts them at one speed:
    ``24 real roots kept (relaxation, rigid-body; ...) at each speed and up to 2 overdamped root pairs
    (damping ratio > 0.99) a speed``; empty when every root is a mode. Real roots are the
    result's own (it keeps one root of each conjugate pair, and of the real roots, which have no
    partner, the half nearest zero: docs/theory.md section 8); a sweep of the lowest modes
    counts only those it solved."""
    from ..analysis.modal import OVERDAMPED_LIMIT

    lam = result.eigenvalues
    solved = np.isfinite(lam)
    real = np.sum(solved & (lam.imag == 0), axis=1)
    overdamped = np.sum(solved & (lam.imag != 0) & ~result.oscillatory, axis=1)
    parts = []
    for counts, what in ((real, "real root{} kept (relaxation, rigid-body; the half nearest zero, docs/theory.md "
                                "section 8)"),
                         (overdamped, f"overdamped root pair{{}} (damping ratio > {OVERDAMPED_LIMIT})")):
        if counts.max(initial=0):
            plural = "s" if counts.max() > 1 else ""
            parts.append(f"{counts.max()} {what.format(plural)} at each speed" if counts.min() == counts.max()
                         else f"up to {counts.max()} {what.format(plural)} a speed")
    return " and ".join(parts)


def _add_frequency_axis(parser):
    """``--freq-range LO:HI`` or ``--freq-max HZ``, and ``--freq-scale`` of the figure's frequency axis."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--freq-range", metavar="LO:HI",
                       help="frequency axis of the figure from LO to HI [Hz] (default: from the modes)")
    group.add_argument("--freq-max", metavar="HZ", help="frequency axis of the figure up to HZ [Hz]: the figure "
                       "only (--max-frequency HZ leaves out the modes above HZ from the solution and the table)")
    parser.add_argument("--freq-scale", choices=["auto", "linear", "log"], default="auto", type=str.lower,
                        help="frequency axis of the figure: 'auto' (default) is logarithmic when the modes "
                             "at one speed span more than 30x, else linear")


def _frequency_axis(args) -> dict:
    """``freq_range`` and ``freq_scale`` for ``plot()`` from the options (checked: one line, exit 2)."""
    from ..errors import InputError
    from ..plotting.campbell import MAX_FREQUENCY_HZ, MAX_LOG_DECADES

    option = "--freq-max" if args.freq_max is not None else "--freq-range"
    text = args.freq_max if args.freq_max is not None else args.freq_range
    freq_range = _frequency_range(args.freq_max, args.freq_range)
    if freq_range is not None and freq_range[1] > MAX_FREQUENCY_HZ:
        raise InputError(f"{option} {text!r}: expected at most {MAX_FREQUENCY_HZ:g} Hz")
    if freq_range is not None and args.freq_scale == "log" and freq_range[0] \
            and freq_range[1] > freq_range[0] * 10.0 ** MAX_LOG_DECADES:
        raise InputError(f"{option} {text!r}: a logarithmic axis spans at most {MAX_LOG_DECADES} decades")
    return {"freq_range": freq_range, "freq_scale": args.freq_scale}


def _frequency_range(freq_max, freq_range):
    """(low or None, high) [Hz] from --freq-max or --freq-range, or None."""
    from ..errors import InputError
    from ._common import parse_band, parse_number

    if freq_max is not None:
        high = parse_number(freq_max, "--freq-max")
        if not high > 0:
            raise InputError(f"--freq-max {freq_max!r}: expected a frequency > 0 [Hz]")
        return None, high
    if freq_range is None:
        return None
    return parse_band(freq_range, "--freq-range", "Hz")
