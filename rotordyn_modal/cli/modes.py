"""``modes MODEL --speed S [--shape MODE | --animate MODE] [--plot FILE]``: modal analysis at one speed."""

from __future__ import annotations

import sys
import numpy as np

from .._progress import ONE_CALL_NOTE, phase
from ..errors import InputError
from ..io.outline import read_outline
from ._common import ESTIMATING, starting
from ._common import (IN_SPEED_UNIT, add_allow_long, add_input_file, add_model_argument, add_output_file, add_outputs,
                      add_speed_unit, check_extra_output, open_model, save_figure, show_progress, speed_value, use_agg,
                      undamped_zeros, whole_number, with_round_off_rows, write_table)

NAME = "modes"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"speed": "--speed"}
HELP = "modal analysis at one speed"
DESCRIPTION = """Eigenvalues of the machine at one speed of the reference rotor: damped natural
frequency, damping ratio, log decrement and whirl direction of every oscillating mode. Roots
that are not modes (real roots: relaxations of rubber mounts, directions without suspension;
overdamped pairs) are counted on a line of their own: every real root of the state matrix,
and how many of them (the half nearest zero) the result keeps beside one root of each pair.
Numbers within the eigen-solve's round-off print as 0 (docs/theory.md section 8). A solve estimated over 20 s of CPU time (a flexible
rotor of hundreds of nodes) is announced on stderr with its estimate before it starts (on a
terminal, a line then shows its elapsed time while it runs), and one over the limit of CPU time (30 min, ROTORDYN_MODAL_MAX_CPU_MINUTES) is refused unless
--allow-long; campbell --lowest N --speeds S:S:1 gives the lowest modes of such a model faster.
--plot draws the modes' participation bars (--modes, default every mode, or modes 1-12 where
there are more than 24), or, on a machine with a flexible rotor, its deflected shaft lines as
--plot-shaft does (hundreds of coordinates make unreadable bars); with --shape MODE the 3D mode shape of that mode
(the machine at rest and displaced, whirl orbits, top/front/side views) and with --animate MODE
an animation of it (--plot FILE.gif, FILE.html or FILE.mp4; MP4 needs ffmpeg). MODE is the
'mode' column of the table. --outline FILE.csv draws the stator as polylines (columns x,y,z
in metres, model axes; an empty row starts a new line; ',', ';' or tab separators and decimal
commas as spreadsheets write them, a length unit in the header: x [mm]) instead of its
inertia-equivalent box; a flexible rotor is drawn as its deflected line through its nodes,
with its disks.
--plot-shaft FILE.png draws the modes as deflected shaft lines along the spin axis, one panel
per mode (--modes, default 1-6): each rotor's displacement in both transverse planes (solid
and dashed, phase 0), the band of its whirl orbits, its bearings (triangles), disks (bars)
and nodes (ticks), normalised so that the largest displacement is 1. A flexible rotor's line
follows its elements' shape functions between the nodes; a rigid rotor's is straight.
Lengths on the figures' axes are in m, or in in with --units us (docs/units.md); the table
has no unit to convert (Hz, ratios) and --outline is read in metres, as the model file.

--measured FILE.uff reads measured mode shapes (dataset 55, as modal analysis programs export
identified modes: normal modes or complex eigenvalues, 3 or 6 values a node) and writes, instead
of the modes table, each measured mode paired one to one with a model mode at --speed by MAC at
the sensors and by frequency (columns measured_mode,measured_hz,measured_damping,model_mode,
model_hz,model_damping,difference_pct,mac; model_mode is the modes table's 'mode'). Sensor k is
node k along its axis, or as --mapping FILE.csv (name,node,direction[,sign]) says, as for frf
--measured; the sensors the file has are named on stderr.

CSV columns: mode,frequency_hz,damping_ratio,log_decrement,whirl,whirl_ratio,real_part (whirl
forward, backward or none; the terminal table says 'no whirl' for none, as the figures and the
report do; real_part is the root's real part in 1/s, in both unit systems: the mode's amplitude
goes as exp(real_part t), so a positive real part grows; damping_ratio, log_decrement and
whirl_ratio have no unit); with a
flexible rotor then shaft_energy,bearing_energy,mount_energy,pedestal_energy,mesh_energy (those
the model has: the fractions of the mode's strain energy in the shafts, bearings, mounts, pedestals
and gear meshes, summing to 1, no unit) and kind ('bending' when over half of it is in the
shafts, else 'rigid-body', 'suspension', 'pedestal' or 'gear-mesh', where most of it is:
docs/model-file.md, "Which modes are bending modes"). docs/units.md lists every column's unit.

examples:
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --out modes.csv
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --shape 5 --plot mode5.png
  rotordyn-modal modes examples/gear_machine.toml --speed 3000 --animate 5 --plot mode5.gif
  rotordyn-modal modes examples/compressor_rotor.toml --speed 3000 --plot-shaft lines.png --modes 1-6
  rotordyn-modal modes examples/gear_machine.toml --measured ema_modes.uff --mapping nodes.csv --out mac.csv"""

def _write_modes(table, args, empty: str):
    """The modes table: the CSV (--out) with its documented whirl values (forward, backward, none:
    scripts read them), the terminal's whirl in the words of the figures and the report ('no
    whirl' for none)."""
    shown = table.copy()                           # its attrs (the round-off marks) too
    shown["whirl"] = shown["whirl"].replace({"none": "no whirl"})
    write_table(table, args, empty=empty, shown=shown)


_ANIMATION_ENDINGS = (".gif", ".html", ".mp4")
#: panels of --plot-shaft in one figure
_MOST_PANELS = 24
#: modes drawn by --plot's bars without --modes when the table has more than _MOST_PANELS
_DEFAULT_BARS = 12


#: how to get a large model's modes faster (said when the solve is long or refused)
_ADVICE = "ask for the lowest modes only (campbell --lowest N --speeds S:S:1)"
#: a solve estimated to take more CPU seconds than this is announced on stderr before it starts
_NOTICE_SECONDS = 20.0


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speed", default="0", metavar="SPEED",
                        help=f"reference rotor speed {IN_SPEED_UNIT} (default 0; negative reverses the spin)")
    add_speed_unit(parser)
    shape = parser.add_mutually_exclusive_group()
    shape.add_argument("--shape", type=whole_number, metavar="MODE", help="draw the 3D shape of this mode to --plot")
    shape.add_argument("--animate", type=whole_number, metavar="MODE",
                       help="animate this mode to --plot FILE.gif|FILE.html|FILE.mp4")
    add_input_file(parser, "--outline", metavar="FILE.csv", help="stator outline as polylines x,y,z [m]")
    parser.add_argument("--frames", type=whole_number, default=36, metavar="N", help="frames per period of --animate (default 36)")
    add_output_file(parser, "--plot-shaft", metavar="FILE.png|FILE.svg|FILE.pdf",
                    help="draw the modes as deflected shaft lines along the axis to this file")
    parser.add_argument("--modes", metavar="LIST",
                        help="modes drawn by --plot-shaft (default 1-6) or by --plot's bars (default every mode, "
                             f"1-{_DEFAULT_BARS} where there are more than {_MOST_PANELS}): numbers and ranges of the "
                             "table's 'mode' column, e.g. 1-6 or 1,3,7-9")
    add_input_file(parser, "--measured", metavar="FILE.uff",
                   help="measured mode shapes (Universal File, dataset 55): the table pairs them with the model's "
                        "modes by MAC at the sensors and by frequency")
    add_input_file(parser, "--mapping", metavar="FILE.csv",
                   help="UFF node/direction to channel table of --measured: name,node,direction[,sign]")
    add_allow_long(parser)
    add_outputs(parser)


def modal(model, speed):
    """:func:`rotordyn_modal.analysis.modal.modal`, imported when a command runs (fast start-up)."""
    from ..analysis.modal import modal as compute

    return compute(model, speed)


def run(args) -> int:
    from ..analysis._work import refuse_long_work
    _check_shape_options(args)
    wanted = _mode_list(args.modes) if args.modes is not None else None
    model = open_model(args)
    speed = speed_value(args.speed, args.speed_unit, "--speed")
    outline = read_outline(args.outline) if args.outline else None   # refused before the solve
    measured = _measured_modes(args, model)                           # refused before the solve too
    # every root is one dense eigen-solution of the state matrix: a long flexible rotor's takes hours;
    # the estimate is the sweeps' (analysis/_cost.py), modal's solve run with one BLAS thread as theirs
    with starting(args, ESTIMATING):
        work = refuse_long_work(model, [speed], critical=False, advice=_ADVICE)
    _announce_long_solve(model, work, args)
    with phase(show_progress(args), f"{NAME}: eigen-solution and shapes"):   # its clock ticks during LAPACK's solve
        result = modal(model, speed)
    view = None
    if args.shape is not None or args.animate is not None:
        from ..analysis.mode_shapes import mode_shape_3d

        mode = args.shape if args.shape is not None else args.animate
        view = mode_shape_3d(result, model, mode, outline=outline)
    if args.plot_shaft or (args.plot and view is None):
        _check_modes(result, wanted, args)
    table = undamped_zeros(with_round_off_rows(result.to_dataframe(), result), model, speed)
    counts = _not_listed(result)
    if measured is not None:
        _write_pairs(model, measured, speed, result, args)
    else:
        _write_modes(table, args, empty=f"no oscillating modes at {args.speed} {args.speed_unit}: {counts}")
    if counts and len(table) and not args.quiet:
        print(f"{counts} not listed as modes (docs/model-file.md, roots that are not modes)", file=sys.stderr)
    if result.unresolved_roots and not args.quiet:
        print(f"{result.unresolved_roots} of the real roots lie below the eigen-solve's round-off "
              f"({result.round_off:.3g} 1/s) with shapes their stiffness loads, but their own shapes do not "
              "resolve them: they may be slow modes this solve cannot tell (docs/theory.md section 8)",
              file=sys.stderr)
    unstrained = _unstrained(result)
    if unstrained and not args.quiet:
        print(f"mode{'s' if len(unstrained) > 1 else ''} {', '.join(map(str, unstrained))} strain nothing to "
              "round-off (a rigid-body motion): no energy fractions, printed as 0 with kind none", file=sys.stderr)
    if args.plot_shaft:
        _plot_shaft(result, model, wanted, args)
    if args.plot:
        use_agg()
        if args.animate is not None:
            view.animate(args.plot, frames=args.frames, inputs=[args.model, args.outline], units=args.units)
            if not args.quiet:
                print(f"animation written to {args.plot}", file=sys.stderr)
        else:
            if view is None and any(rotor.flexible is not None for rotor in model.rotors):
                _plot_shaft(result, model, wanted, args, args.plot, "--plot")
            else:
                save_figure(_bars(result, wanted, args) if view is None else view.plot(units=args.units), args)
    return 0


def _measured_modes(args, model):
    """--measured FILE.uff: its dataset 55 (or 2414) modes at the sensors (None without --measured);
    --mapping without --measured is refused."""
    if args.measured is None:
        if args.mapping is not None:
            raise InputError(f"--mapping {args.mapping}: expected it only beside --measured FILE.uff (it places the "
                             "file's nodes and directions on the sensors)")
        return None
    from ..analysis.correlation import check_mode_sensors
    from ..io.uff_modes import read_uff_modes

    return check_mode_sensors(read_uff_modes(args.measured, model, args.mapping))


def _write_pairs(model, measured, speed, result, args):
    """The table of --measured: each measured mode, the model mode paired to it (MAC at the
    sensors the file has and relative frequency distance) and their MAC; the sensors on stderr."""
    from ..analysis.correlation import correlate_modes

    pairs = correlate_modes(model, measured, speed, model_modes=result)
    write_table(pairs, args, empty=f"no oscillating model modes at {args.speed} {args.speed_unit} to pair with the "
                                   f"{len(measured.poles)} measured modes of {args.measured}")
    if not args.quiet:
        print(f"--measured {args.measured}: {len(measured.poles)} modes (dataset {measured.method.removeprefix('uff-')}) at {len(measured.outputs)} "
              f"sensors ({', '.join(measured.outputs)}); MAC over those sensors", file=sys.stderr)


def _announce_long_solve(model, work, args):
    """Before a long eigen-solution (estimated over :data:`_NOTICE_SECONDS` of CPU time), one
    line on stderr with its estimate: LAPACK's single call has no steps to count (on a terminal, a
    clock shows it running). The
    estimate is :func:`..analysis._work.refuse_long_work`'s (``work``, None where it made none),
    which refused the solve before where it exceeds the limit of CPU time."""
    from ..analysis import _cost, _work

    if args.quiet:
        return
    n_states = _work._n_states(model)
    if work is None:
        if _cost._PESSIMISTIC * n_states ** 3 <= _NOTICE_SECONDS:
            return                                          # small: no timing at all
        seconds = _work.eig_seconds(n_states)
    else:
        seconds = work.sweep_seconds
    if seconds > _NOTICE_SECONDS:
        print(f"{NAME}: one eigen-solution of {n_states:,} states ({model.dofs.n:,} coordinates) with every root: "
              f"about {_cost.duration(seconds)} of CPU time ({ONE_CALL_NOTE}; {_ADVICE})",
              file=sys.stderr, flush=True)


def _bars(result, wanted, args):
    """--plot without --shape: the participation bars of ``wanted`` (default every mode, or the
    first :data:`_DEFAULT_BARS` of a longer table, said on stderr)."""
    count = int(result.oscillatory.sum())
    if wanted is None and count > _MOST_PANELS:
        wanted = list(range(1, _DEFAULT_BARS + 1))
        if not args.quiet:
            print(f"--plot: modes 1-{_DEFAULT_BARS} of {count} drawn (choose with --modes; "
                  "--plot-shaft draws a shaft's modes along its axis)", file=sys.stderr)
    return result.plot(modes=wanted, units=args.units)


def _plot_shaft(result, model, wanted, args, path=None, option="--plot-shaft"):
    """--plot-shaft (or --plot on a machine with a flexible rotor): the chosen modes' deflected
    lines (default the first six)."""
    from ..analysis.mode_shapes import shaft_lines
    from ..plotting.shaft_modes import plot_shaft_modes

    use_agg()
    wanted = wanted or list(range(1, min(int(result.oscillatory.sum()), 6) + 1))
    save_figure(plot_shaft_modes([shaft_lines(result, model, m) for m in wanted], units=args.units), args,
                path or args.plot_shaft, option)


def _check_modes(result, wanted, args):
    """Refuse, before any output, --plot-shaft without modes or --modes beyond the table."""
    count = int(result.oscillatory.sum())
    if not count and args.plot_shaft:
        raise InputError(f"--plot-shaft: no oscillating modes at {args.speed} {args.speed_unit} to draw")
    if wanted and max(wanted) > count:
        raise InputError(f"--modes {args.modes!r}: mode {max(wanted)} does not exist; the table has modes 1 to "
                         f"{count}")


def _mode_list(text: str) -> list[int]:
    """``1-6`` or ``1,3,7-9`` -> [1, 2, ...]: distinct mode numbers >= 1, in the order given."""
    problem = f"--modes {text!r}: expected mode numbers and ranges from 1, e.g. 1-6 or 1,3,7-9"
    out = []
    for part in text.split(","):
        ends = part.strip().split("-")
        if len(ends) > 2 or not all(e.strip().isdigit() for e in ends):
            raise InputError(problem)
        first, last = int(ends[0]), int(ends[-1])
        if first < 1 or last < first or last - first >= _MOST_PANELS:
            raise InputError(problem)
        out += [m for m in range(first, last + 1) if m not in out]
    if len(out) > _MOST_PANELS:
        raise InputError(f"--modes {text!r}: at most {_MOST_PANELS} modes in one figure")
    return out


def _unstrained(result) -> list:
    """The numbers of the listed modes whose strain energy is round-off in every part (their
    fractions are undefined: nan in the result, 0 in the table)."""
    if result.energy_fractions is None or not result.energy_parts:
        return []
    rows = result.energy_fractions[result.oscillatory]
    return [int(i) + 1 for i in np.nonzero(~np.isfinite(rows).all(axis=1))[0]]


def _not_listed(result) -> str:
    """The roots that are not modes, counted: ``48 real roots (relaxation, rigid-body; the 24 nearest
    zero kept as the result's half, docs/theory.md section 8) and 1 overdamped root pair (damping
    ratio > 0.99)``; empty when every root is a mode. Every real root of the state matrix is
    counted: the result keeps one root of each conjugate pair, and of the real roots, which have
    no partner, the half nearest zero."""
    from ..analysis.modal import OVERDAMPED_LIMIT

    parts = []
    kept = int(result.real_roots.sum())
    real = kept if result.state_real_roots is None else result.state_real_roots
    if real:
        why = (f"; the {kept} nearest zero kept as the result's half, docs/theory.md section 8"
               if 0 < kept < real else "")
        parts.append(f"{real} real root{'s' if real > 1 else ''} (relaxation, rigid-body{why})")
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
    if args.modes is not None and not (args.plot_shaft or (args.plot and args.shape is None and args.animate is None)):
        raise InputError("--modes chooses the panels of --plot-shaft FILE.png or --plot FILE.png (the bars): "
                         "give one of them")
    check_extra_output(args, args.plot_shaft, "--plot-shaft", figure=True)
