"""``modes MODEL --speed S [--shape MODE | --animate MODE] [--plot FILE]``: modal analysis at one speed."""

from __future__ import annotations

import sys

from ..errors import InputError
from ._common import (add_input_file, add_model_argument, add_outputs, add_speed_unit, open_model, parse_number,
                      save_figure, to_rad_s, use_agg, write_table)

NAME = "modes"
HELP = "modal analysis at one speed"
DESCRIPTION = """Eigenvalues of the machine at one speed of the reference rotor: damped natural
frequency, damping ratio, log decrement and whirl direction of every oscillating mode. Roots
that are not modes (real roots: relaxations of rubber mounts, directions without suspension;
overdamped pairs) are counted on a line of their own. Numbers within the eigen-solve's round-off
print as 0 (docs/theory.md section 8).
--plot draws the modes' participation bars; with --shape MODE the 3D mode shape of that mode
(the machine at rest and displaced, whirl orbits, top/front/side views) and with --animate MODE
an animation of it (--plot FILE.gif, FILE.html or FILE.mp4; MP4 needs ffmpeg). MODE is the
'mode' column of the table. --outline FILE.csv draws the stator as polylines (columns x,y,z
in metres, model axes; an empty row starts a new line) instead of its inertia-equivalent box.

CSV columns: mode,frequency_hz,damping_ratio,log_decrement,whirl,whirl_ratio,real_part

examples:
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --out modes.csv
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --shape 5 --plot mode5.png
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --animate 5 --plot mode5.gif"""

_ANIMATION_ENDINGS = (".gif", ".html", ".mp4")


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speed", default="0", help="reference rotor speed (default 0; negative reverses the spin)")
    add_speed_unit(parser)
    shape = parser.add_mutually_exclusive_group()
    shape.add_argument("--shape", type=int, metavar="MODE", help="draw the 3D shape of this mode to --plot")
    shape.add_argument("--animate", type=int, metavar="MODE",
                       help="animate this mode to --plot FILE.gif|FILE.html|FILE.mp4")
    add_input_file(parser, "--outline", metavar="FILE.csv", help="stator outline as polylines x,y,z [m]")
    parser.add_argument("--frames", type=int, default=36, help="frames per period of --animate (default 36)")
    add_outputs(parser)


def modal(model, speed):
    """:func:`rotordyn_modal.analysis.modal.modal`, imported when a command runs (fast start-up)."""
    from ..analysis.modal import modal as compute

    return compute(model, speed)


def run(args) -> int:
    _check_shape_options(args)
    model = open_model(args)
    speed = float(to_rad_s(parse_number(args.speed, "--speed"), args.speed_unit))
    result = modal(model, speed)
    outline = _read_outline(args.outline) if args.outline else None
    view = None
    if args.shape is not None or args.animate is not None:
        from ..analysis.mode_shapes import mode_shape_3d

        mode = args.shape if args.shape is not None else args.animate
        view = mode_shape_3d(result, model, mode, outline=outline)
    table = result.to_dataframe()
    counts = _not_listed(result)
    write_table(table, args, empty=f"no oscillating modes at {args.speed} {args.speed_unit}: {counts}")
    if counts and len(table) and not args.quiet:
        print(f"{counts} not listed as modes (docs/model-file.md, roots that are not modes)", file=sys.stderr)
    if args.plot:
        use_agg()
        if args.animate is not None:
            view.animate(args.plot, frames=args.frames, inputs=[args.model, args.outline])
            if not args.quiet:
                print(f"animation written to {args.plot}", file=sys.stderr)
        else:
            save_figure(result.plot() if view is None else view.plot(), args)
    return 0


def _not_listed(result) -> str:
    """The roots that are not modes, counted: ``24 real roots (relaxation, rigid-body) and 1
    overdamped root pair (damping ratio > 0.99)``; empty when every root is a mode."""
    from ..analysis.modal import OVERDAMPED_LIMIT

    parts = []
    if real := int(result.real_roots.sum()):
        parts.append(f"{real} real root{'s' if real > 1 else ''} (relaxation, rigid-body)")
    if overdamped := int(result.overdamped.sum()):
        parts.append(f"{overdamped} overdamped root pair{'s' if overdamped > 1 else ''} "
                     f"(damping ratio > {OVERDAMPED_LIMIT})")
    return " and ".join(parts)


def _check_shape_options(args):
    if args.animate is not None:
        args.plot_endings = _ANIMATION_ENDINGS
        if not args.plot:
            raise InputError("--animate MODE needs --plot FILE.gif, FILE.html or FILE.mp4")
    elif args.shape is not None and not args.plot:
        raise InputError("--shape MODE needs --plot FILE.png, FILE.svg or FILE.pdf")
    if args.outline and args.shape is None and args.animate is None:
        raise InputError("--outline is drawn with --shape MODE or --animate MODE only")
    if not 2 <= args.frames <= 720:
        raise InputError(f"--frames {args.frames}: expected a whole number from 2 to 720")


def _read_outline(path):
    """Polylines ``x,y,z`` [m]; empty rows (NaN) separate the lines."""
    import pandas as pd

    try:
        table = pd.read_csv(path, skip_blank_lines=False)
    except (OSError, ValueError) as error:
        raise InputError(f"{path}: cannot read the outline ({error})") from None
    if not {"x", "y", "z"} <= set(table.columns):
        raise InputError(f"{path}: the outline needs the columns x,y,z (metres, model axes); found "
                         f"{','.join(map(str, table.columns))}")
    try:
        return table[["x", "y", "z"]].to_numpy(dtype=float)
    except ValueError:
        raise InputError(f"{path}: the outline's x,y,z must be numbers (an empty row starts a new line)") from None
