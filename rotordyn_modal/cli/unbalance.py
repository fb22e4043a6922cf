"""``unbalance MODEL --speeds R [--sensor NAME] [--forces WHERE]``: steady unbalance response vs speed."""

from __future__ import annotations

import sys
import warnings

import numpy as np

from .._progress import phase
from ..errors import InputError
from ..unbalance_standards import amplitude_column, amplitude_label, largest_margins_text, one_convention
from ._common import (IN_SPEED_UNIT, add_alias, add_model_argument, as_typed, add_output_file, add_outputs, add_sensor_argument, add_speed_unit, check_ending,
                      check_extra_output, check_speeds, mcs_option, open_model, parse_band, print_table, save_figure, show_progress,
                      speeds_option, speed_value, speeds_text, use_agg, whole_number, write_csv, write_table)
from ._units import convert_table
from .frf import QUANTITY_HELP, QUANTITY_METAVAR, quantity_type, sensor_names

NAME = "unbalance"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"speeds": "--speeds"}
HELP = "steady unbalance response vs speed, each rotor's harmonic at its own spin frequency"
DESCRIPTION = f"""Response of the sensors to the model's [[unbalances]] over a speed sweep. Every
rotor's unbalances excite at that rotor's own spin frequency (|speed ratio| x speed,
turning its own way); each rotor (source) is reported separately: amplitude (0-peak) and
phase (x(t) = amplitude cos(2 pi frequency t + phase)). The table holds the sensors named by
--sensor (default every sensor) and nothing else; --forces adds rows of forces (output
NAME:Fx ... NAME:Mz, N and N m) after them: suspensions (each suspension's force on the
ground), bearings (each [[bearings]] entry's force on the stator or the ground at its point,
and each rigidly attached rotor's at its centre of mass), rotors (each rotor's total force
on the stator) or all (suspensions, bearings and rotors). Peaks get the API 684
amplification factor (the peak and its half-power points found on the exact response between
the swept speeds: the same whatever --speeds, a large model aside) and, with --operating-range LO:HI (as report, study and ucs-map take it)
or --operating-speed SPEED (a range of one speed), the separation margin and its verdict: a
peak below the range measured from LO (the minimum operating speed), above it from HI (the
maximum continuous speed), each as a percentage of that end; a peak inside the range has
margin 0 and fails where API 684 requires a margin; a peak of unknown AF (no half-power
point within the sweep on one side) passes where its margin is at least what any AF requires
({largest_margins_text()}), else is not evaluated (docs/standards.md).

Amplitudes (--amplitude peak|pk-pk|rms, default peak: 0-peak): one choice for the printed
peaks table, the CSV and the figure. The peaks table (AF and separation margins) holds the
peak's amplitude in that convention only, its column named by it (amplitude_0pk,
amplitude_pkpk or amplitude_rms); the figure draws it (the axis label says which: 0-peak,
peak-to-peak or RMS); the CSV adds the column amplitude_pkpk or amplitude_rms after
phase_deg. The CSV's amplitude column stays 0-peak (amplitude x cos(...)) whatever is asked:
its columns are the command's fixed contract, which scripts read by name.

Standards (docs/standards.md): --mcs (maximum continuous speed of the reference rotor)
gives each proximity probe (measure = "relative") the API 617 limit
A1 = 25.4 um sqrt(12000/N), at most 25.4 um peak-to-peak (N the probe's rotor's MCS in
rpm), checked on the probe's peak-to-peak displacement over the speeds from --min-speed
(default 0) to --mcs, its maxima between swept speeds and the MCS itself included (as the
clearance check: each swept local maximum refined on the exact response) (a sweep stopping below --mcs, or below --trip-speed, is
warned of: the speeds above it go unchecked); --iso-group 1|2 with --iso-support
rigid|flexible evaluates the RMS vibration velocity of every stator (casing) sensor in the ISO 20816-3 zones A-D over the
same speeds (the whole sweep without --mcs), or over --operating-range where it is given (the
zones judge steady operation, not the run-up through a mount's resonance; --operating-speed
leaves them over the checked speeds). The checks table (output, check, speed_rpm,
value, amplitude, limit, verdict, zone: value and limit in m peak-to-peak for the API probe
limit, in m/s RMS for the ISO zones, amplitude the word naming that convention) is printed
and written by --checks FILE.csv; --plot draws the probe limits and a velocity panel with the zones.
--api-unbalance (with --mcs) replaces the model's [[unbalances]] by the API 617/684
cases of every rotor, Ua = 2 Ur, Ur = 6350 W/N g mm (= 4 W/N oz in): api-static:ROTOR at its centre
of mass (W its mass) and api-couple:ROTOR at its outermost bearing planes, 180 deg apart
(W half its mass: a pure couple); for a flexible rotor (one with a shaft) also
api-mode1:ROTOR, api-mode2:ROTOR, ... one per lateral mode of interest (the undamped modes at
the MCS up to 1.3 x the rotor's 1X frequency, most of their kinetic energy its lateral motion; a
backward/forward pair once, by ascending frequency) at the mesh node of the mode's largest
deflection (W its mass), or, where an antinode of the opposite sign reaches half of it, at the
two antinodes 180 deg apart (W half its mass); each case is its own response, named in a last column
case of the CSV, peaks and checks tables, and in the figure's legend.
With --mcs, a model with close-clearance stations ([[rotors.clearances]]) gets the API
617/684 clearance check, printed after the checks: at each station the peak-to-peak
displacement of the rotor relative to the stator (twice its orbit's semi-major axis),
scaled by Scc = Avl/Amax (at most 6; Avl the probe limit A1, Amax the largest pk-pk at the
rotor's probes from --min-operating-speed (default the low end of --operating-range, or
--operating-speed, where one is given, else --min-speed) to --mcs; 1 without a
probe), against 75 % of the diametral clearance (1.5 x radial_clearance), largest over the
speeds from --min-speed to --trip-speed (default --mcs) and the maxima between them (found
on the exact response; Amax takes the peaks table's), each API case on its own with
--api-unbalance (the criterion's unbalance), else the model's unbalances together; value,
limit and the unscaled response in m (mil with --units us), peak-to-peak whatever
--amplitude is.

Two sensors at one point of the same body with directions normal to the spin axis (a
pair of proximity probes, measure = "relative") see an orbit: --orbits FILE.csv writes
each pair's ellipse per source and speed (semi-axes: 0-peak, inclination, forward/backward
precession) and --plot-orbits FILE.png draws them, one panel per pair and source (as in
the CSV), at that source's largest orbit and at the last speed.

--plot draws one amplitude (log axis, in um or mm, mil with --units us, whichever reads the
largest curve from 1 up) and phase panel per kind of sensor (shaft probes, rotor points,
stator), with --forces one panel per kind of force (the amplitude of each item's force
vector, N); curves lying on each other are drawn there in alternating dashes; the largest
peaks (amplification factor >= 2.5) are labelled where a short leader crosses no curve.

Units (--units us, docs/units.md): amplitudes in mil, in/s or g (--quantity), forces in lbf and
moments in lbf in, in every table (a last column unit gives each row's) and on the figure's axes.

CSV columns: speed_rpm,output,source,frequency_hz,amplitude,phase_deg[,amplitude_pkpk|amplitude_rms][,case][,unit]
(amplitude is 0-peak, amplitude_pkpk peak-to-peak and amplitude_rms RMS, each in the unit of the
sensor's --quantity, m, m/s or m/s^2, or for a --forces row in N, a moment's in N m; with --units
us in mil, in/s, g, lbf or lbf in, named by the row's unit column)
orbit CSV columns: speed_rpm,pair,source,frequency_hz,major,minor,inclination_deg,precession,precession_ratio[,unit]
(major and minor are the ellipse's semi-axes, 0-peak, in the pair's --quantity, m, m/s or
m/s^2; with --units us in mil, in/s or g, named by the row's unit column; precession_ratio has
no unit). docs/units.md lists every column's unit.

examples:
  rotordyn-modal unbalance examples/gear_machine.toml --speeds 0:6000:601 --sensor acc-top-z \\
      --operating-range 2700:3000 --plot unbalance.png
  rotordyn-modal unbalance examples/gear_machine.toml --speeds 0:6000:61 --sensor acc-top-z \\
      --forces suspensions --out unbalance.csv
  rotordyn-modal unbalance examples/fan_on_bearings.toml --speeds 100:9000:446 --mcs 3000 \\
      --iso-group 2 --iso-support flexible --amplitude pk-pk --plot unbalance.png"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speeds", required=True, metavar="START:STOP:N",
                        help=f"speeds of the reference rotor {IN_SPEED_UNIT}")
    add_speed_unit(parser)
    add_sensor_argument(parser)
    parser.add_argument("--quantity", type=quantity_type(frf_names=False), default="displacement",
                        metavar=QUANTITY_METAVAR, help="what the sensors read (default displacement) "
                        + QUANTITY_HELP)
    parser.add_argument("--forces", choices=["suspensions", "bearings", "rotors", "all"],
                        help="add force rows after the sensors' (default none)")
    parser.add_argument("--operating-range", dest="operating", metavar="LO:HI",
                        help="operating speed range (same unit as --speeds, in the direction of spin of the sweep; "
                             "LO = HI: one speed) for the separation margins and the ISO 20816-3 zones")
    parser.add_argument("--operating-speed", metavar="SPEED", help="operating speed (same unit as --speeds, in the "
                        "direction of spin of the sweep) for the separation margin: --operating-range SPEED:SPEED")
    parser.add_argument("--amplitude", choices=["peak", "pk-pk", "rms"], default="peak",
                        help="amplitude convention of the peaks table, the figure and the CSV's added column: "
                             "0-peak (default, as the CSV's amplitude column), peak-to-peak or RMS")
    parser.add_argument("--mcs", metavar="SPEED", help="maximum continuous speed of the reference rotor (same "
                        "unit as --speeds): API 617 probe limits, top of the checked speeds")
    parser.add_argument("--min-speed", metavar="SPEED", help="bottom of the checked speeds of --mcs's and --iso-group's "
                        "checks, with one of them (same unit as --speeds; default 0)")
    parser.add_argument("--trip-speed", metavar="SPEED", help="top of the speeds of the clearance check (same "
                        "unit as --speeds; default --mcs)")
    parser.add_argument("--min-operating-speed", metavar="SPEED", help="minimum allowable speed (same unit as "
                        "--speeds): bottom of the probe amplitudes of the clearance check's scale factor "
                        "Scc = Avl/Amax (default the low end of --operating-range or --operating-speed, else --min-speed)")
    parser.add_argument("--iso-group", type=whole_number, choices=[1, 2],
                        help="ISO 20816-3 machine group (1: above 300 kW, 2: 15-300 kW), with --iso-support")
    parser.add_argument("--iso-support", choices=["rigid", "flexible"], help="ISO 20816-3 support class")
    parser.add_argument("--api-unbalance", action="store_true",
                        help="replace the model's unbalances by the API 617/684 cases (needs --mcs)")
    add_output_file(parser, "--checks", metavar="FILE.csv", help="write the table of the standards' checks")
    add_output_file(parser, "--orbits", metavar="FILE.csv", help="write the orbits of the probe pairs")
    add_output_file(parser, "--plot-orbits", dest="orbit_plot", metavar="FILE.png|FILE.svg|FILE.pdf",
                    help="draw the orbits of the probe pairs")
    add_alias(parser, "--plot-orbits", "--orbit-plot")   # a second figure is --plot-WHAT, as modes --plot-shaft
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.unbalance import api_unbalance_response, unbalance_response
    from ..analysis.unbalance_checks import AF_UNBOUNDED, AF_UNKNOWN, separation_margins
    check_extra_output(args, args.orbits, "--orbits")
    check_ending(args.orbits, (".csv",), "--orbits", stdout=False)
    check_ending(args.checks, (".csv",), "--checks", stdout=False)
    check_extra_output(args, args.orbit_plot, as_typed(args, "--plot-orbits"), figure=True)
    model = open_model(args)
    operating = _operating_range(args)
    mcs, min_speed, min_operating = _check_options(args, operating, model)   # refused before anything is written
    _warn_below_checked_speeds(speeds_option(args), mcs, args)
    if args.api_unbalance:
        result = api_unbalance_response(model, speeds_option(args), mcs, outputs=sensor_names(args, model),
                                        quantity=args.quantity, amplitude=args.amplitude, progress=show_progress(args))
    else:
        result = unbalance_response(model, speeds_option(args), outputs=sensor_names(args, model),
                                    quantity=args.quantity, amplitude=args.amplitude, progress=show_progress(args))
    if (args.orbits or args.orbit_plot) and not result.orbit_pairs:
        raise InputError(f"{model.source}: --orbits/{as_typed(args, '--plot-orbits')} need a probe pair among the outputs: two "
                         "sensors at one point of the same body, directions normal to spin_axis")
    if not args.quiet and args.out != "-":
        print(_response_heading(args.amplitude), file=sys.stderr)
    write_table(in_units(result.to_dataframe(forces=args.forces), result, args.units), args)
    with phase(show_progress(args), "unbalance: peaks"):
        peaks = result.peaks() if operating is None else separation_margins(result, operating, amplitude=args.amplitude)
    if not args.quiet:
        print(f"\npeaks (API 684; amplitude {amplitude_label(args.amplitude)}):", file=sys.stderr)
        print_table(in_units(one_convention(peaks, args.amplitude), result, args.units),
                    empty=f"no resonance peak {speeds_text(args)}")
        if "verdict" in peaks and np.isnan(peaks["amplification_factor"].to_numpy(dtype=float)).any():
            print(AF_UNKNOWN, file=sys.stderr)            # what a verdict of an unknown AF rests on
        if np.isposinf(peaks["amplitude"].to_numpy(dtype=float)).any():
            print(AF_UNBOUNDED, file=sys.stderr)          # what an amplitude of inf means
    checks = _write_checks(result, model, mcs, min_speed, args,
                           None if args.operating is None else operating)
    _print_clearances(result, model, mcs, min_speed, args, min_operating)
    if args.plot:
        use_agg()
        save_figure(result.plot(peaks=peaks, speed_unit=args.speed_unit, groups=sensor_groups(model),
                                forces=args.forces, checks=checks, units=args.units), args)
    _write_orbits(result, args)
    return 0


def _speed(args, text, option):
    """A speed option in rad/s (None when not given), of magnitude at most 1e30 rad/s as every
    speed (``--mcs 1e308`` made the API 617 probe limit 0 m and failed every probe)."""
    if text is None:
        return None
    return speed_value(text, args.speed_unit, option)


def _operating_range(args):
    """``(low, high)`` [rad/s] of --operating-range LO:HI or --operating-speed SPEED (a range of
    one speed), None with neither: finite, not 0, of one direction of spin, and that of some
    speed of the sweep (checked before anything is computed or written)."""
    from ..analysis.unbalance import check_operating_speed

    if args.operating is not None and args.operating_speed is not None:
        raise InputError(f"--operating-speed {args.operating_speed}: expected it or --operating-range "
                         f"{args.operating}, not both (one speed is the range SPEED:SPEED)")
    if args.operating is not None:
        option, text = as_typed(args, "--operating-range"), args.operating
        band = parse_band(text, option, args.speed_unit, low=None, example="2000:3000", largest=None, single=True)
        ends = tuple(check_speeds(np.array(band), text, args.speed_unit, option))
        if not (min(band) > 0 or max(band) < 0):
            raise InputError(f"{option} {text!r}: expected LO and HI of one sign and not 0 [{args.speed_unit}] "
                             "(the separation margin is a percentage of them)")
    elif args.operating_speed is not None:
        option, text = "--operating-speed", args.operating_speed
        speed = _speed(args, text, option)
        if speed == 0:
            raise InputError(f"--operating-speed {text}: expected a speed other than 0 (the "
                             "separation margin is a percentage of it)")
        ends = (speed, speed)
    else:
        return None
    try:
        for end in ends:
            check_operating_speed(speeds_option(args), end)
    except InputError as error:    # 'operating speed -0.10472 rad/s (-1 rpm)': said as typed
        raise InputError(f"{option} {text} {args.speed_unit}: {str(error).partition(': ')[2]}") from None
    return ends


def _warn_below_checked_speeds(speeds, mcs, args):
    """One warning line where the sweep ``speeds`` [rad/s] (N,) stops below the top of the API
    checks' speeds (``--mcs``, or ``--trip-speed`` for the clearances): the probe limits and
    clearances are judged on the swept speeds only, and the speeds above them go unchecked."""
    trip = _speed(args, args.trip_speed, "--trip-speed")
    top, option, text = (trip, "--trip-speed", args.trip_speed) if trip is not None else (mcs, "--mcs", args.mcs)
    if top is None:
        return
    reached = float(np.max(np.abs(speeds)))
    if reached < top * (1.0 - 1e-12):
        warnings.warn(f"--speeds {args.speeds} stops below {option} {text}: the API checks judge the swept "
                      f"speeds only, those above {reached / top:.0%} of {option} go unchecked (sweep up to it)")


def _check_options(args, operating, model):
    """``(mcs, min_speed, min_operating)`` [rad/s] of the standards' checks, the options checked
    together; ``operating`` [rad/s] the operating range (:func:`_operating_range`), the default of
    the minimum operating speed (:func:`_min_operating`)."""
    mcs = None if args.mcs is None else mcs_option(args)      # the one check level1 and report share
    min_speed = _speed(args, args.min_speed, "--min-speed")
    if min_speed is not None and not min_speed >= 0:
        raise InputError(f"--min-speed {args.min_speed}: expected a speed >= 0")
    if min_speed is not None and mcs is None and args.iso_group is None:
        raise InputError(f"--min-speed {args.min_speed}: expected --mcs (API 617 probe limits, clearances) or "
                         "--iso-group and --iso-support (ISO 20816-3 zones) too: it is the bottom of their checked "
                         "speeds, and nothing else uses it")
    if min_speed is not None and mcs is not None and min_speed > mcs:
        raise InputError(f"--min-speed {args.min_speed}: expected at most --mcs {args.mcs} (the checked speeds "
                         "run from one to the other)")
    trip = _speed(args, args.trip_speed, "--trip-speed")
    given = "" if mcs is None else f" {args.mcs}"      # not 'at least --mcs None' when it is not given
    if trip is not None and (mcs is None or not trip >= mcs):
        raise InputError(f"--trip-speed {args.trip_speed}: expected --mcs too and a trip speed at least --mcs"
                         f"{given} (the clearance check's speeds run up to it)")
    operating_speed = _speed(args, args.min_operating_speed, "--min-operating-speed")
    if operating_speed is not None and not (mcs is not None and 0 <= operating_speed <= mcs):
        raise InputError(f"--min-operating-speed {args.min_operating_speed}: expected --mcs too and a speed >= 0 "
                         f"and at most --mcs{given} (the scale factor's probe amplitudes run from one to the other)")
    if args.api_unbalance and mcs is None:
        raise InputError("--api-unbalance: expected --mcs too (the API amount 2 x 6350 W/N needs the maximum "
                         "continuous speed N)")
    if (args.iso_group is None) != (args.iso_support is None):
        raise InputError("--iso-group/--iso-support: expected both (ISO 20816-3 machine group 1 or 2 and "
                         "support rigid or flexible) or neither")
    if args.checks and mcs is None and args.iso_group is None:
        raise InputError(f"--checks {args.checks}: expected --mcs (API 617 probe limits) or --iso-group and "
                         "--iso-support (ISO 20816-3 zones): nothing to check")
    return mcs, min_speed or 0.0, _min_operating(args, operating, mcs, model, given=operating_speed)


def _write_checks(result, model, mcs, min_speed, args, iso_range=None):
    """The standards' checks (None when none is asked): printed, and written to --checks; the ISO
    zones over ``iso_range`` [rad/s] (--operating-range) where it is given."""
    from ..analysis.unbalance_checks import unbalance_checks

    if mcs is None and args.iso_group is None:
        return None
    checks = unbalance_checks(result, model, mcs=mcs, min_speed=min_speed, iso_group=args.iso_group,
                              iso_support=args.iso_support, iso_range=iso_range if args.iso_group else None)
    table = checks.to_dataframe()
    if args.units != "si":
        kinds = ["displacement" if check.startswith("API") else "velocity" for check in table["check"]]
        table = convert_table(table, {"value": "row", "limit": "row"}, args.units, kinds, unit_column=True)
    if not args.quiet:
        print("\nchecks (API 617 probe limits, ISO 20816-3 zones; "
              f"{'m, m/s' if args.units == 'si' else 'mil, in/s'}):", file=sys.stderr)
        print_table(table, empty="no probe (measure = \"relative\") or casing sensor to check among the outputs")
    if args.checks:
        write_csv(table, args.checks)
    return checks


def _min_operating(args, operating, mcs, model, given=None):
    """The minimum operating speed [rad/s] of the clearance check's scale factor: ``given``
    (--min-operating-speed, checked by :func:`_check_options`), else the low end (in magnitude) of
    the operating range ``operating`` [rad/s] (--operating-range, or --operating-speed's range of one
    speed) as the report takes it, else None (--min-speed). An operating range whose low end lies
    above --mcs is refused where the clearance check runs."""
    if given is not None or operating is None or mcs is None or not model.clearances:
        return given
    low = float(min(abs(operating[0]), abs(operating[1])))
    if low > mcs:
        option, text = ((as_typed(args, "--operating-range"), args.operating) if args.operating is not None
                        else ("--operating-speed", args.operating_speed))
        raise InputError(f"{option} {text}: expected its low end at most --mcs {args.mcs} (the minimum operating "
                         "speed, bottom of the clearance check's scale factor Scc = Avl/Amax; or give "
                         "--min-operating-speed)")
    return low


def _print_clearances(result, model, mcs, min_speed, args, operating=None):
    """The clearance check (with --mcs, when the model has close-clearance stations), printed;
    ``operating`` [rad/s] the minimum operating speed (:func:`_min_operating`; None: --min-speed)."""
    trip = _speed(args, args.trip_speed, "--trip-speed")
    if mcs is None or not model.clearances or args.quiet:
        return
    table = result.clearance_check(model, mcs=mcs, min_speed=min_speed, trip_speed=trip,
                                   min_operating=operating).to_dataframe()
    if args.units != "si":
        table = convert_table(table, {"value": "row", "limit": "row", "response": "row"}, args.units,
                              ["displacement"] * len(table), unit_column=True)
    which = "the API unbalance cases" if args.api_unbalance else "the model's [[unbalances]], not the API amount"
    print(f"\nclearance check (API 617/684: Scc x pk-pk relative to the stator <= 75 % of the diametral clearance; "
          f"{which}; {'m' if args.units == 'si' else 'mil'}):", file=sys.stderr)
    print_table(table)


#: columns of the response and peaks tables whose unit is the row's (a sensor's or a force's)
_AMPLITUDE_COLUMNS = {"amplitude": "row", "amplitude_0pk": "row", "amplitude_pkpk": "row", "amplitude_rms": "row"}


def in_units(table, result, system: str):
    """A response or peaks table (SI) in ``system``: each row's amplitudes in the unit of its
    sensor's quantity, or of its force (``NAME:Fx``) or moment (``NAME:Mx``) row, with a last
    column ``unit`` outside SI."""
    if system == "si":
        return table
    sensors = set(result.outputs)
    kinds = [result.quantity if name in sensors else ("moment" if name.rsplit(":", 1)[-1].startswith("M")
                                                      else "force") for name in table["output"]]
    return convert_table(table, _AMPLITUDE_COLUMNS, system, kinds, unit_column=True)


def sensor_groups(model) -> dict:
    """Panel title of each sensor (:func:`rotordyn_modal.analysis.unbalance_checks.sensor_groups`,
    which the report's figure uses too)."""
    from ..analysis.unbalance_checks import sensor_groups as groups

    return groups(model)


def _response_heading(amplitude: str) -> str:
    """The line over the printed response table: the convention of each amplitude column (the
    CSV's ``amplitude`` is 0-peak whatever ``--amplitude`` asks, docs/standards.md)."""
    extra = "" if amplitude == "peak" else \
        f", {amplitude_column(amplitude).replace('_0pk', '')} {amplitude_label(amplitude)}"
    return f"unbalance response (amplitude 0-peak{extra}; x(t) = amplitude cos(2 pi frequency t + phase)):"


def _write_orbits(result, args):
    if result.orbit_pairs and not args.quiet:
        table = result.orbits()
        largest = table.loc[table.groupby(["pair", "source"])["major"].idxmax()]
        print("\nlargest orbit of each probe pair (major, minor: semi-axes, 0-peak):", file=sys.stderr)
        print_table(_orbits_in_units(largest, result, args.units))
    if args.orbits:
        write_csv(_orbits_in_units(result.orbits(), result, args.units), args.orbits)
    if args.orbit_plot:
        use_agg()
        save_figure(result.plot_orbits(units=args.units), args, args.orbit_plot, as_typed(args, "--plot-orbits"))


def _orbits_in_units(table, result, system):
    """The orbits table (semi-axes of the sensors' quantity) in ``system``, a last column ``unit``."""
    kinds = [result.quantity] * len(table)
    return convert_table(table, {"major": "row", "minor": "row"}, system, kinds, unit_column=True)
