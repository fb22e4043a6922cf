"""``unbalance MODEL --speeds R [--sensor NAME] [--forces WHERE]``: steady unbalance response vs speed."""

from __future__ import annotations

import sys

from ..errors import InputError
from ._common import (add_model_argument, add_output_file, add_outputs, add_speed_unit, check_ending, check_extra_output,
                      open_model, parse_number, print_table, save_figure, speeds_option, speeds_text, to_rad_s,
                      use_agg, write_csv, write_table)
from .frf import names

NAME = "unbalance"
HELP = "steady unbalance response vs speed, each rotor's harmonic at its own spin frequency"
DESCRIPTION = """Response of the sensors to the model's [[unbalances]] over a speed sweep. Every
rotor's unbalances excite at that rotor's own spin frequency (|speed ratio| x speed,
turning its own way); each rotor (source) is reported separately: amplitude (0-peak) and
phase (x(t) = amplitude cos(2 pi frequency t + phase)). The table holds the sensors named by
--sensor (default every sensor) and nothing else; --forces adds rows of forces (output
NAME:Fx ... NAME:Mz, N and N m) after them: suspensions (each suspension's force on the
ground), bearings (each [[bearings]] entry's force on the stator or the ground at its point,
and each rigidly attached rotor's at its centre of mass), rotors (each rotor's total force
on the stator) or all (suspensions, bearings and rotors). Peaks get the API 684
amplification factor and, with --operating-speed, the separation margin.

Two sensors at one point of the same body with directions normal to the spin axis (a
pair of proximity probes, measure = "relative") see an orbit: --orbits FILE.csv writes
each pair's ellipse per source and speed (semi-axes, inclination, forward/backward
precession) and --orbit-plot FILE.png draws them, one panel per pair and source (as in
the CSV), at that source's largest orbit and at the last speed.

--plot draws one amplitude (log axis) and phase panel per kind of sensor (shaft probes,
rotor points, stator), with --forces one panel per kind of force (the amplitude of each
item's force vector, N); the largest peaks (amplification factor >= 2.5) are labelled.

CSV columns: speed_rpm,output,source,frequency_hz,amplitude,phase_deg
orbit CSV columns: speed_rpm,pair,source,frequency_hz,major,minor,inclination_deg,precession,precession_ratio

examples:
  rotordyn-modal unbalance examples/gear_machine.toml --speeds 0:6000:601 --sensor acc-top-z \\
      --operating-speed 3000 --plot unbalance.png
  rotordyn-modal unbalance examples/gear_machine.toml --speeds 0:6000:61 --sensor acc-top-z \\
      --forces suspensions --out unbalance.csv"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, help="START:STOP:N speeds of the reference rotor")
    add_speed_unit(parser)
    parser.add_argument("--sensor", "--output", dest="output", metavar="NAME[,NAME]",
                        help="sensor name(s), comma-separated (default all; --output is the same)")
    parser.add_argument("--quantity", choices=["displacement", "velocity", "acceleration"], default="displacement")
    parser.add_argument("--forces", choices=["suspensions", "bearings", "rotors", "all"],
                        help="add force rows after the sensors' (default none)")
    parser.add_argument("--operating-speed", help="operating speed (same unit as --speeds) for the separation margin")
    add_output_file(parser, "--orbits", metavar="FILE.csv", help="write the orbits of the probe pairs")
    add_output_file(parser, "--orbit-plot", metavar="FILE",
                    help="draw the orbits of the probe pairs (.png, .svg, .pdf)")
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.unbalance import unbalance_response
    check_extra_output(args, args.orbits, "--orbits")
    check_ending(args.orbits, (".csv",), "--orbits")
    check_extra_output(args, args.orbit_plot, "--orbit-plot", figure=True)
    model = open_model(args)
    operating = None if args.operating_speed is None else \
        float(to_rad_s(parse_number(args.operating_speed, "--operating-speed"), args.speed_unit))
    if operating == 0:
        raise InputError(f"--operating-speed {args.operating_speed}: expected a speed other than 0 (the "
                         "separation margin is a percentage of it)")
    result = unbalance_response(model, speeds_option(args), outputs=names(args.output), quantity=args.quantity)
    if (args.orbits or args.orbit_plot) and not result.orbit_pairs:
        raise InputError(f"{model.source}: --orbits/--orbit-plot need a probe pair among the outputs: two "
                         "sensors at one point of the same body, directions normal to spin_axis")
    write_table(result.to_dataframe(forces=args.forces), args)
    peaks = result.peaks(operating)
    if not args.quiet:
        print("\npeaks (API 684):", file=sys.stderr)
        print_table(peaks, empty=f"no resonance peak {speeds_text(args)}")
    if args.plot:
        use_agg()
        save_figure(result.plot(peaks=peaks, speed_unit=args.speed_unit, groups=sensor_groups(model),
                                forces=args.forces), args)
    _write_orbits(result, args)
    return 0


def sensor_groups(model) -> dict:
    """Panel title of each sensor: shaft probes (relative), rotor points, stator points."""
    def title(sensor):
        if sensor.rotor is None:
            return "stator (casing) sensors, absolute"
        return "shaft relative to the stator (probes)" if sensor.measure == "relative" else \
            "rotor points, absolute"
    return {s.name: title(s) for s in model.sensors}


def _write_orbits(result, args):
    if result.orbit_pairs and not args.quiet:
        table = result.orbits()
        largest = table.loc[table.groupby(["pair", "source"])["major"].idxmax()]
        print("\nlargest orbit of each probe pair:", file=sys.stderr)
        print_table(largest)
    if args.orbits:
        write_csv(result.orbits(), args.orbits)
    if args.orbit_plot:
        use_agg()
        save_figure(result.plot_orbits(), args, args.orbit_plot, "--orbit-plot")
