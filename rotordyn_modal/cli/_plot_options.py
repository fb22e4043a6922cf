"""Options of the figures' axes shared by sub-commands (``--freq-range``, ``--freq-max``, ``--freq-scale``)."""

from __future__ import annotations

from ..errors import InputError
from ._common import parse_number


def add_frequency_axis(parser):
    """``--freq-range LO:HI`` or ``--freq-max HZ``, and ``--freq-scale`` of a figure's frequency axis."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--freq-range", metavar="LO:HI",
                       help="frequency axis of the figure from LO to HI [Hz] (default: from the modes)")
    group.add_argument("--freq-max", metavar="HZ", help="frequency axis of the figure up to HZ [Hz]")
    parser.add_argument("--freq-scale", choices=["auto", "linear", "log"], default="auto", type=str.lower,
                        help="frequency axis of the figure: 'auto' (default) is logarithmic when the modes "
                             "at one speed span more than 30x, else linear")


def frequency_axis_options(args) -> dict:
    """``freq_range`` and ``freq_scale`` for ``plot()`` from the options (checked: one line, exit 2)."""
    from ..plotting.campbell import MAX_FREQUENCY_HZ, MAX_LOG_DECADES

    freq_range = _frequency_range(args)
    option = "--freq-max" if args.freq_max is not None else "--freq-range"
    text = args.freq_max if args.freq_max is not None else args.freq_range
    if freq_range is not None and freq_range[1] > MAX_FREQUENCY_HZ:
        raise InputError(f"{option} {text!r}: expected at most {MAX_FREQUENCY_HZ:g} Hz")
    if freq_range is not None and args.freq_scale == "log" and freq_range[0] \
            and freq_range[1] > freq_range[0] * 10.0 ** MAX_LOG_DECADES:
        raise InputError(f"{option} {text!r}: a logarithmic axis spans at most {MAX_LOG_DECADES} decades")
    return {"freq_range": freq_range, "freq_scale": args.freq_scale}


def _frequency_range(args):
    if args.freq_max is not None:
        high = parse_number(args.freq_max, "--freq-max")
        if not high > 0:
            raise InputError(f"--freq-max {args.freq_max!r}: expected a frequency > 0 [Hz]")
        return None, high
    if args.freq_range is None:
        return None
    parts = args.freq_range.split(":")
    if len(parts) != 2:
        raise InputError(f"--freq-range {args.freq_range!r}: expected LO:HI [Hz], e.g. 0:40")
    low, high = (parse_number(part, "--freq-range") for part in parts)
    if not 0 <= low < high:
        raise InputError(f"--freq-range {args.freq_range!r}: expected 0 <= LO < HI [Hz]")
    return low, high
