"""``level1 MODEL --mcs SPEED --station ROTOR[@OFFSET] (--qa N/m | --rated-power W ...)``."""

from __future__ import annotations

import dataclasses
import sys

import numpy as np

from ..errors import InputError
from ..model._table import LARGEST
from ..units import from_system, unit_scale
from ._units import convert_table, kinds_by_ending
from ._common import (IN_SPEED_UNIT, add_alias, add_allow_long, as_typed, add_model_argument, add_output_file, add_outputs, add_speed_unit, check_extra_output,
                      mcs_option, open_model, parse_count, parse_list, parse_number, save_figure, speed_value, use_agg,
                      write_table)

NAME = "level1"
#: the largest anticipated cross-coupling [N/m] (``analysis.level1`` sweeps to 1000 Qa: products stay finite)
LARGEST_QA = LARGEST / 1000
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"speed": "--mcs", "qa": "--qa", "power": "--rated-power", "diameter": "--impeller-diameter",
             "height": "--restriction-height", "density_ratio": "--density-ratio", "factor": "--factor"}
HELP = "API 617 Level I stability screening: log decrement against applied cross-coupling"
DESCRIPTION = """API 617 Level I stability screening. A cross-coupled stiffness Q (k_ab = +Q,
k_ba = -Q in the radial axes a, b = spin axis x a: destabilising for forward whirl) acts between
each --station's rotor and the stator, Q swept from 0 to --factor x Qa (API: 10); at --mcs
(the maximum continuous speed) the log decrement of each of the rotor's first three forward
modes by frequency (whirling with the rotor's spin at the station, relative to the stator;
those there are) is followed by its shape, and the least stable is judged: the log decrement
at Qa is the lowest of theirs, Q0 the smallest (the first by frequency may be a mode the
cross-coupling at the station barely reaches, while the next goes unstable). --forward-mode N
follows the N-th forward mode alone. The terminal, the figure (one curve per mode, the
governing one bold) and the CSV (columns per mode) show every followed mode. Qa is given
(--qa, N/m) or is the API anticipated cross-coupling summed over the stages:
  qa = B T / (D H) (rho_d / rho_s),  T = P / Omega_r  (= B 9.55 P / (D H N_r) with P in W,
  D and H in m, N_r in rpm, q in N/m; B = 3 compressors, 1.5 turbines without density ratio)
with one --rated-power, --impeller-diameter, --restriction-height and --density-ratio per stage
(comma lists) and N_r = --operating-speed (default --mcs). Criteria: log decrement at Qa
>= 0.1 and Q0/Qa >= 2.0 (Q0 where the log decrement reaches 0); otherwise Level II is required.
With one station all of Q acts there; with one station per stage each takes its stage's share.
A station is ROTOR (its centre of mass: a rigid rotor's) or ROTOR@OFFSET (m along spin_axis
from the centre of mass: an impeller; on a flexible rotor a point of its shaft, the node
nearest it; on a rigid rotor within its extent: its bearings and the points the model places on
it, at least the slender rod of its mass and diametral inertia). docs/level1_and_ucs.md gives
the formulas and sources.

With --gas-density RHO (the average gas density) or RHO_SUCTION,RHO_DISCHARGE (averaged), in
kg/m^3, the critical speed ratio CSR = MCS / first forward critical speed on rigid supports
(every bearing radially rigid, the casing and pedestals held) is placed on API 617's chart
against the average density: above the dividing line (Region B: CSR 2.5 up to 16.53 kg/m^3,
then 2.69 - 0.0115 rho to 2.0 at 60 kg/m^3, as ROSS implements it) with Q0/Qa below 10, Level
II is required too. --plot-csr FILE draws the chart. docs/standards.md gives the line's source.

A sweep estimated to take more than 30 minutes of CPU time (one eigen-solution of the machine per
value of Q, timed on this machine before the first) is refused before it starts, with the
estimate (--allow-long runs it anyway, ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit); so is one
whose arrays cannot fit in memory.

With --units us, --qa is in lbf/in, --rated-power in hp, the diameter, height and OFFSET in in, the
gas density in lb/ft^3; the table's
first column is then q_lbf_per_in and Q is printed and drawn in lbf/in (the formula is the same
physics: its inputs are converted to SI, docs/units.md).

CSV columns: q_n_per_m,q_over_qa,log_decrement,frequency_hz (the mode of the lowest log
decrement at Qa), then log_decrement_mode_N,frequency_hz_mode_N for each followed mode N
(modes numbering) when several are followed

examples:
  rotordyn-modal level1 examples/journal_rotor.toml --mcs 4000 --station rotor --qa 2e5 --plot l1.png
  rotordyn-modal level1 examples/fan_on_bearings.toml --mcs 3000 --station fan@-0.1 \\
      --rated-power 15e3 --impeller-diameter 0.5 --restriction-height 0.03 --density-ratio 1.05"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--mcs", required=True, metavar="SPEED",
                        help=f"maximum continuous speed of the reference rotor {IN_SPEED_UNIT}, where the screening "
                             "is made")
    add_alias(parser, "--mcs", "--speed")
    add_speed_unit(parser)
    add_stage_arguments(parser)
    parser.add_argument("--factor", default="10", help="the sweep reaches FACTOR x Qa (default 10)")
    parser.add_argument("--forward-mode", metavar="N",
                        help="follow the N-th forward mode alone (default: the first three, the least stable judged)")
    add_output_file(parser, "--plot-csr", dest="csr_plot", metavar="FILE.png|FILE.svg|FILE.pdf",
                    help="draw the CSR against gas density chart (needs --gas-density)")
    add_alias(parser, "--plot-csr", "--csr-plot")   # a second figure is --plot-WHAT, as modes --plot-shaft
    add_allow_long(parser)
    add_outputs(parser)


def add_stage_arguments(parser, required: bool = True, speed_option: str = "--mcs"):
    """--station, --qa and the stage data of the API anticipated cross-coupling (also used by
    ``report``, where they are optional and the analysis speed is ``--mcs``)."""
    parser.add_argument("--station", action="append", required=required, metavar="ROTOR[@OFFSET]",
                        help="where Q acts (repeat for several stations)")
    parser.add_argument("--qa", metavar="Q[,Q]", help="anticipated cross-coupling [N/m; lbf/in with --units us], or one per "
                                     "station (comma list)")
    parser.add_argument("--rated-power", metavar="P[,P]", help="rated power of each stage [W; hp] (comma list)")
    add_alias(parser, "--rated-power", "--power")
    parser.add_argument("--impeller-diameter", metavar="D[,D]", help="impeller (or blade pitch) diameter of each stage [m; in]")
    parser.add_argument("--restriction-height", metavar="H[,H]",
                        help="smaller of diffuser and impeller discharge width (turbines: effective blade height) "
                             "of each stage [m; in]")
    parser.add_argument("--density-ratio", metavar="R[,R]", help="discharge over suction density of each stage (default 1)")
    parser.add_argument("--machine", choices=["compressor", "turbine"], default="compressor",
                        help="B = 3 (compressor) or 1.5 (turbine, no density ratio)")
    parser.add_argument("--operating-speed", metavar="SPEED",
                        help=f"normal operating speed N_r of the formula {IN_SPEED_UNIT} (default {speed_option})")
    parser.add_argument("--gas-density", metavar="RHO[,RHO_DISCHARGE]",
                        help="average gas density, or suction and discharge densities [kg/m^3; lb/ft^3 with --units "
                             "us]: adds the critical speed ratio chart (compressors)")


def gas_density(args):
    """--gas-density in kg/m^3: None, or a tuple of one or two values > 0."""
    if getattr(args, "gas_density", None) is None:
        return None
    values = parse_list(args.gas_density, "--gas-density")
    if not 1 <= len(values) <= 2 or not np.all(np.isfinite(values) & (values > 0)):
        raise InputError(f"--gas-density {args.gas_density!r}: expected the average gas density, or the suction and "
                         "discharge densities RHO_S,RHO_D, > 0 [kg/m^3; lb/ft^3 with --units us]")
    if args.machine != "compressor":
        raise InputError(f"--gas-density with --machine {args.machine}: the critical speed ratio chart screens "
                         "compressors (--machine compressor)")
    return tuple(float(v) for v in from_system(values, "density", getattr(args, "units", None) or "si"))


def run(args) -> int:
    from ..analysis.level1 import Station, level1

    stations = parse_stations(args)
    if args.units != "si":      # ROTOR@OFFSET: the offset in in
        stations = [dataclasses.replace(s, offset=from_system(s.offset, "length", args.units), units=args.units) for s in stations]
    speed = mcs_option(args, signed=True)    # the check report makes (there > 0)
    qa, shares = anticipated(args, len(stations), speed)
    factor = parse_number(args.factor, "--factor")
    forward = None if args.forward_mode is None else parse_count(args.forward_mode, "--forward-mode")
    density = gas_density(args)
    if args.csr_plot and density is None:
        raise InputError(f"{as_typed(args, '--plot-csr')}: give --gas-density (the chart places the rotor by its average gas density)")
    check_extra_output(args, args.csr_plot, as_typed(args, "--plot-csr"), figure=True)   # before the work and its table
    model = open_model(args)
    result = level1(model, speed, stations, qa, shares=shares, factor=factor, forward_mode=forward,
                    gas_density=density)
    table = result.to_dataframe()
    write_table(convert_table(table, kinds_by_ending(table.columns), args.units), args)
    if not args.quiet:
        scale, unit = unit_scale("stiffness", args.units)
        where = ", ".join(s.label(args.units) for s in result.stations)
        if len(result.swept) > 1:
            for run in result.swept:
                print(_mode_line(run, result, scale, unit), file=sys.stderr)
        followed = (_at_zero(result, "{} ({:.5g} Hz at Q = 0) ", " ")
                    + ("followed" if len(result.swept) <= 1 else "the least stable"))
        print(f"Qa = {result.qa * scale:.6g} {unit} at {where}; {followed}; "
              + (f"Q0 = {result.q0 * scale:.6g} {unit}; " if np.isfinite(result.q0) else
                 f"Q0 beyond {result.cross_coupling[-1] * scale:.6g} {unit}; ") + result.verdict(args.units),
              file=sys.stderr)
    if args.plot:
        use_agg()
        save_figure(result.plot(units=args.units), args)
    if args.csr_plot:
        use_agg()
        save_figure(result.csr.plot(units=args.units, title=f"API 617 Level I: {result.title}" if result.title
                                    else None, verdict=result.verdict().rpartition(": ")[2]), args, args.csr_plot, as_typed(args, "--plot-csr"))
    return 0


def _at_zero(run, form: str, after: str) -> str:
    """The followed mode at Q = 0 by ``form`` (its label and frequency [Hz]), or, for a root
    that is no mode there (0 Hz, no number), its label and ``after``."""
    return form.format(run.mode_label, run.frequencies_hz[0]) if run.mode else run.mode_label + after


def _mode_line(run, result, scale, unit) -> str:
    """``forward mode 2: mode 7, 57.7 Hz at Q = 0, log dec at Qa 0.255, Q0 = ... (governs ...)``."""
    governs = [what for what, yes in (("log dec at Qa", run.forward_mode == result.forward_mode),
                                      ("Q0", result.governs_q0 is run)) if yes]
    q0 = f"Q0 = {run.q0 * scale:.6g} {unit}" if np.isfinite(run.q0) else "Q0 beyond the sweep"
    return (f"forward mode {run.forward_mode}: {_at_zero(run, '{}, {:.5g} Hz at Q = 0, ', ', ')}"
            f"log dec at Qa {run.log_decrement_at_qa:.3g}, {q0}" + (f" (governs {' and '.join(governs)})"
                                                                     if governs else ""))


def parse_stations(args) -> list:
    """The --station options as :class:`~rotordyn_modal.analysis.level1.Station`; one that is not
    ROTOR[@OFFSET] is refused as the option, and where its OFFSET names a disk of the rotor
    (``compressor@impeller-1``) the refusal gives that disk's OFFSET to type (the model is read
    for it)."""
    from ..analysis.level1 import Station, disk_offset_hint

    stations = []
    for text in args.station:
        try:
            stations.append(Station.parse(text, args.units or "si"))
        except InputError as error:     # "station 'fan@': ..." said of the option
            hint = disk_offset_hint(open_model(args), text, args.units or "si") if "@" in text else ""
            raise InputError(f"--{error}{hint}") from None
    return stations


def anticipated(args, count, speed):
    """(Qa [N/m], shares per station) from --qa or the stage data."""
    qa, shares, _ = anticipated_stages(args, count, speed)
    return qa, shares


def anticipated_stages(args, count, speed):
    """(Qa [N/m], shares per station, stages) from --qa or the stage data: ``stages`` None with
    --qa, else the formula's inputs and result per stage, SI (the report shows them, so that its
    Qa can be checked by hand): ``{"machine": str, "power" [W], "diameter" [m], "height" [m],
    "density_ratio" [-], "speed" [rad/s] (N_r, one value), "qa" [N/m]}``, arrays of one value a stage."""
    from ..analysis.level1 import anticipated_cross_coupling

    stage_options = (args.rated_power, args.impeller_diameter, args.restriction_height)
    power_option = as_typed(args, "--rated-power")
    if args.qa is not None:
        if any(o is not None for o in stage_options) or args.density_ratio is not None:
            raise InputError(f"--qa and the stage data ({power_option}, --impeller-diameter, ...) both given: give one")
        if args.operating_speed is not None:   # was taken without a word, even 'nan'
            raise InputError(f"--operating-speed {args.operating_speed}: expected the stage data ({power_option}, "
                             "--impeller-diameter, --restriction-height) too: it is N_r of their formula, and --qa "
                             "gives Qa without it")
        values = from_system(parse_list(args.qa, "--qa"), "stiffness", args.units)
        if not np.all(values > 0):
            raise InputError(f"--qa {args.qa!r}: expected values > 0 [{unit_scale('stiffness', args.units)[1]}]")
        return (*_spread(values, count, "--qa"), None)
    if any(o is None for o in stage_options):
        raise InputError(f"give --qa {unit_scale('stiffness', args.units)[1]}, or {power_option}, --impeller-diameter "
                         "and --restriction-height (one per stage)")
    power, diameter, height = (from_system(parse_list(o, name), kind, args.units) for o, name, kind in zip(
        stage_options, (power_option, "--impeller-diameter", "--restriction-height"), ("power", "length", "length")))
    if args.density_ratio is not None and args.machine == "turbine":   # was dropped without a word
        raise InputError(f"--density-ratio {args.density_ratio}: expected none with --machine turbine (API 617's "
                         "turbine stages have no density ratio: qa = 1.5 T / (D H))")
    ratio = parse_list(args.density_ratio, "--density-ratio") if args.density_ratio else np.ones(1)
    stages = max(len(power), len(diameter), len(height), len(ratio))
    power, diameter, height, ratio = (_per_stage(v, stages, name) for v, name in zip(
        (power, diameter, height, ratio), (power_option, "--impeller-diameter", "--restriction-height",
                                           "--density-ratio")))
    operating = speed if args.operating_speed is None else \
        speed_value(args.operating_speed, args.speed_unit, "--operating-speed")
    if operating == 0:      # the API's 'speed = 0.0' named neither option
        raise InputError(f"--operating-speed {args.operating_speed}: expected a speed other than 0 (Qa is power / "
                         "speed)")
    if operating * speed < 0:   # -3000 beside --speed 3000 was taken as +3000 without a word
        raise InputError(f"--operating-speed {args.operating_speed}: expected a speed of the sense of "
                         f"{as_typed(args, '--mcs')} {args.mcs} (the machine runs one way; N_r is its speed)")
    with np.errstate(over="ignore"):    # a tiny speed: Qa overflows, refused below by the options given
        q = anticipated_cross_coupling(power, abs(operating), diameter, height, ratio, machine=args.machine)
    if not np.all(q <= LARGEST_QA):      # 'qa = 7.2e+305' named no option the user gave
        at = "" if args.operating_speed is None else f" at --operating-speed {args.operating_speed}"
        raise InputError(f"{power_option} {args.rated_power}, --impeller-diameter {args.impeller_diameter}, --restriction-height "
                         f"{args.restriction_height}{at}: give Qa = {q.max():.4g} N/m: expected at most {LARGEST_QA:g} "
                         "N/m (check their units: W, m, m, and the speed's)")
    stages = {"machine": args.machine, "power": power, "diameter": diameter, "height": height,
              "density_ratio": ratio, "speed": abs(operating), "qa": q}
    return (*_spread(q, count, "the stages"), stages)


def _per_stage(values, stages, option):
    if len(values) == 1:
        return np.full(stages, values[0])
    if len(values) != stages:
        raise InputError(f"{option}: {len(values)} values for {stages} stages: give one per stage (or one for all)")
    return values


def _spread(values, count, what):
    """Qa = the sum; shares per station: all at the one station, or one value per station."""
    if count == 1:
        return float(values.sum()), None
    if len(values) != count:
        raise InputError(f"{what}: {len(values)} values for {count} stations: give one per station (or one station)")
    return float(values.sum()), values / values.sum()
