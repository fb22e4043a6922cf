"""``report MODEL --standard api617|api684|iso --mcs RPM --out report.html``."""

from __future__ import annotations

import dataclasses
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


from .._progress import phase
from ..errors import InputError
from ..io import atomic_write
from ..io.text import shown_text
from ..units import from_system
from ._common import IN_SPEED_UNIT, add_alias, add_allow_long, add_model_argument, add_output_file, as_typed, add_speed_unit, check_ending, check_extra_output, \
    mcs_option, open_model, show_progress, whole_number
from .level1 import add_stage_arguments, anticipated_stages, gas_density, parse_stations
from .ucs_map import _operating, _stiffness

NAME = "report"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"qa": "--qa", "power": "--rated-power", "diameter": "--impeller-diameter", "height": "--restriction-height",
             "density_ratio": "--density-ratio"}
HELP = "one self-contained HTML report against API 617, API 684 or ISO: figures, tables, verdicts"
DESCRIPTION = """A rotordynamic report in one HTML file (figures embedded as PNG; print it to PDF
from a browser, or --pdf with Chromium): a summary of the criteria (value, limit, verdict: pass,
fail or not evaluated and why, each linking to its section), the model (bodies, bearings,
mounts, sensors, the model file's name and SHA-256, the package version, the date, the command
line), the static sag and reactions, the Campbell diagram with the critical speeds, the API 684
amplification factors and separation margins (required margin and verdict per peak), the mode
shapes at the MCS of the modes whose 1X critical speed or frequency lies within 16 % below or
26 % above the operating range (else the lowest 4; shaft lines for flexible rotors), then by
--standard:
  api684  the undamped critical speed map; the API unbalance cases' response with the API 617
          probe limits and, for a model with [[rotors.clearances]], the clearance check (pk-pk
          at each station <= 75 % of its diametral clearance)
  api617  the same plus API 617 Level I stability (with --station and --qa or the stage data
          of 'level1'; otherwise 'not evaluated'), judged on the least stable of the rotor's
          first three forward modes at the station; with --gas-density also the critical speed
          ratio against average gas density (its criterion line and chart, as 'level1')
  iso     the response to the model's [[unbalances]] (amounts or ISO 21940-11 grades) and the
          ISO 20816-3 zones of the casing sensors (--iso-group and --iso-support)
The sweeps run from 2 % of --mcs to 1.5 x --mcs (--points speeds, with --mcs and the operating
range's ends among them); the operating range
(--operating-range LO:HI, default the MCS alone) measures the separation margins and, where
given, is the span the ISO zones judge (steady operation; without it 0 to the MCS). docs/report.md
lists what each section holds and where its numbers come from. With --units us (or
ROTORDYN_MODAL_UNITS=us) every table, figure and criterion shows US customary units: vibration
in mil, casing velocity in in/s RMS, static displacement in in, forces in lbf, stiffness and Q
in lbf/in, masses in lb (docs/units.md); the verdicts are the same. The options are then read in
US units too, as by 'level1' and 'ucs-map': --qa and --stiffness in lbf/in, --rated-power in hp, the
impeller diameter, restriction height and station OFFSET in in, --gas-density in lb/ft^3.
Amplitudes (--amplitude pk-pk|peak|rms, default pk-pk): one convention for every vibration
amplitude of the report, the AF table, the unbalance figure, the probe-limit and clearance
tables and the summary alike (the API limits, written peak-to-peak, converted exactly: 0-peak =
pk-pk / 2, RMS = pk-pk / (2 sqrt 2)); the page says which under its title. The ISO 20816-3
casing velocities are RMS whatever it is (the zones are RMS).
A report estimated to take more than 30 minutes of CPU time (its sections' sweeps counted from
the model's size, an eigen-solution timed on this machine) is refused before any section runs,
with the estimate by section (--allow-long runs it anyway, ROTORDYN_MODAL_MAX_CPU_MINUTES sets
the limit).

examples:
  rotordyn-modal report examples/journal_rotor.toml --standard api617 --mcs 6000 \\
      --operating-range 4000:6000 --station rotor --qa 2e5 --out report.html
  rotordyn-modal report examples/motor_pump_on_mounts.toml --standard iso --mcs 3000 \\
      --iso-group 2 --iso-support flexible --out report.html --pdf report.pdf"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--standard", required=True, choices=["api617", "api684", "iso"],
                        help="which criteria and sections")
    parser.add_argument("--mcs", required=True, metavar="SPEED",
                        help=f"maximum continuous speed of the reference rotor {IN_SPEED_UNIT}")
    parser.add_argument("--operating-range", dest="operating", metavar="LO:HI",
                        help=f"operating speed range {IN_SPEED_UNIT} (default: the MCS alone)")
    add_alias(parser, "--operating-range", "--operating")
    add_speed_unit(parser)
    parser.add_argument("--points", default="151", metavar="N", help="speeds of the sweeps (default 151; the MCS and the operating range's ends are added)")
    parser.add_argument("--stiffness", metavar="START:STOP:N",
                        help="bearing stiffness of the UCS map (api617, api684) [N/m; lbf/in with --units us], log-spaced "
                             "(default 1e5:1e10:41 N/m, widened by decades to reach the bearings' own stiffness)")
    parser.add_argument("--iso-group", type=whole_number, choices=[1, 2],
                        help="ISO 20816-3 machine group (1: above 300 kW, 2: 15-300 kW), with --iso-support")
    parser.add_argument("--iso-support", choices=["rigid", "flexible"], help="ISO 20816-3 support class")
    parser.add_argument("--amplitude", choices=["peak", "pk-pk", "rms"], default="pk-pk",
                        help="convention of every vibration amplitude in the report: 0-peak, peak-to-peak "
                             "(default: probes are read and the API limits written so) or RMS")
    add_stage_arguments(parser, required=False, speed_option="--mcs")
    add_output_file(parser, "--out", required=True, metavar="FILE.html", help="the report")
    parser.set_defaults(out_endings=(".html", ".htm"))
    add_output_file(parser, "--pdf", metavar="FILE.pdf", help="also print the report to PDF (needs Chromium)")
    add_allow_long(parser)
    parser.add_argument("--quiet", action="store_true", help="nothing on the terminal")


def run(args) -> int:
    from ..report import collect, render_html

    check_ending(args.out, (".html", ".htm"), "--out", stdout=False)
    check_ending(args.pdf, (".pdf",), "--pdf", stdout=False)
    check_extra_output(args, args.pdf, "--pdf")
    if args.pdf and _browser() is None:
        raise InputError(f"--pdf {args.pdf}: no Chromium on the PATH to print the report (open the HTML "
                         "in a browser and print it instead)")
    inputs = _inputs(args)
    model = open_model(args)
    _check_tables(model, inputs, args)
    import matplotlib

    matplotlib.use("Agg")
    # refused before any section where over the limit (one line with the estimate, nothing written)
    data = collect(model, inputs, progress=show_progress(args))
    units = getattr(args, "units", None) or "si"
    with phase(show_progress(args), "report: drawing the figures"):     # several seconds on flexible rotors
        html = render_html(data, units=units)
    with atomic_write(args.out, "w", encoding="utf-8") as handle:
        handle.write(html)
    if args.pdf:
        _print_pdf(html, args.pdf)
    if not args.quiet:
        for c in (c.in_system(units, inputs.amplitude) for c in data.criteria):
            print(_terminal_line(c), file=sys.stderr)
    return 0


def _terminal_line(criterion) -> str:
    """``NAME: VERDICT (VALUE; limit LIMIT)``, the parts a criterion has (no empty limit), and why
    when it is not evaluated."""
    shown = "; ".join(part for part in (criterion.value, criterion.limit and f"limit {criterion.limit}") if part)
    return (f"{criterion.name}: {criterion.verdict}" + (f" ({shown})" if criterion.value else "")
            + (f": {criterion.why}" if criterion.verdict == "not evaluated" else ""))


def _inputs(args):
    from ..report import ReportInputs

    mcs = mcs_option(args)      # 1e-300 rpm: every swept speed 0 to round-off (level1 checks the same)
    operating = _operating(args, low_open=True) if args.operating is not None else None
    if operating is not None and operating[1] > mcs * (1 + 1e-12):
        raise InputError(f"{as_typed(args, '--operating-range')} {args.operating}: expected HI at most --mcs "
                         f"{args.mcs} (the maximum "
                         "continuous speed is the top of the operating range)")
    try:
        points = whole_number(args.points)
    except ValueError:
        points = 0
    if not 5 <= points <= 5001:
        raise InputError(f"--points {args.points!r}: expected a whole number from 5 to 5001")
    if (args.iso_group is None) != (args.iso_support is None):
        raise InputError("--iso-group/--iso-support: expected both (ISO 20816-3 machine group 1 or 2 and "
                         "support rigid or flexible) or neither")
    _check_sections(args)
    units = getattr(args, "units", None) or "si"
    level1 = None
    if args.station:
        stations = parse_stations(args)
        if units != "si":      # ROTOR@OFFSET: the offset in in, as in 'level1'
            stations = [dataclasses.replace(s, offset=from_system(s.offset, "length", units), units=units) for s in stations]
        qa, shares, stages = anticipated_stages(args, len(stations), mcs)
        level1 = {"stations": stations, "qa": qa, "shares": shares, "gas_density": gas_density(args),
                  "stages": stages}
    elif _level1_options(args):
        raise InputError(f"{_level1_options(args)[0]} given without --station: name where the cross-coupling acts "
                         "(with --qa or the stage data)")
    return ReportInputs(standard=args.standard, mcs=mcs, operating=operating, points=points,
                        iso_group=args.iso_group, iso_support=args.iso_support, level1=level1,
                        stiffness=_stiffness(args.stiffness, units) if args.stiffness else None,
                        command=_command_line(), amplitude=args.amplitude)


#: the Level I options of ``report`` (besides --station) and their ``args`` names
_LEVEL1_OPTIONS = (("--qa", "qa"), ("--rated-power", "rated_power"), ("--impeller-diameter", "impeller_diameter"),
                   ("--restriction-height", "restriction_height"), ("--density-ratio", "density_ratio"),
                   ("--operating-speed", "operating_speed"), ("--gas-density", "gas_density"))


def _level1_options(args) -> list[str]:
    """The Level I options given (as typed; ``--machine`` when not its default), --station aside."""
    given = [as_typed(args, option) for option, name in _LEVEL1_OPTIONS if getattr(args, name) is not None]
    return given + (["--machine"] if args.machine != "compressor" else [])


def _check_sections(args):
    """Refuse an option whose section ``--standard`` does not have: it was dropped without a
    word (``--standard api684 --station nobody --qa 1e5``, ``--standard api617 --iso-group 1``,
    ``--standard iso --stiffness 1e5:1e10:9``: the ISO report has no undamped critical speed map)."""
    from ..report.collect import STANDARDS

    sections = STANDARDS[args.standard]
    for section, options, where in (
            ("level1", (["--station"] if args.station else []) + _level1_options(args),
             "API 617 Level I stability, in --standard api617"),
            ("ucs", [f"--stiffness {args.stiffness}"] if args.stiffness is not None else [],
             "the undamped critical speed map, in --standard api617 or api684"),
            ("iso", ["--iso-group"] if args.iso_group is not None else [], "ISO 20816-3 zones, in --standard iso")):
        if options and section not in sections:
            raise InputError(f"{options[0]}: --standard {args.standard} has no section it serves ({where}): "
                             "drop it or choose that standard")


def _check_tables(model, inputs, args):
    """Refuse, before the work and naming --mcs, a speed table that the report's sweeps (2 % of
    --mcs to 1.5 x --mcs, no option of the report moves them) leave: the table's own refusal
    ended in 'extend the table or the sweep's range'."""
    import math

    from ..elements.bearings import table_left

    ends = [inputs.speeds[0], inputs.speeds[-1]]
    left = table_left(model, ends)
    if left is None:
        return
    bearing, own = left
    table, rpm = bearing.coefficients.speeds, 30.0 / math.pi
    raise InputError(
        f"{as_typed(args, '--mcs')} {args.mcs}: the report sweeps the reference speed from 2 % of it to "
        f"1.5 x it, {ends[0] * rpm:.6g} .. {ends[1] * rpm:.6g} rpm, where rotor {bearing.rotor!r} turns at "
        f"{own.min() * rpm:.6g} .. {own.max() * rpm:.6g} rpm: expected within [bearings.{bearing.name}] "
        f"speeds_rpm {table[0] * rpm:.6g} .. {table[-1] * rpm:.6g} rpm (extend the table, or a lower --mcs)")


def _command_line() -> str:
    return "rotordyn-modal " + " ".join(shlex.quote(shown_text(a)) for a in sys.argv[1:]) if sys.argv[1:] else ""


def _browser():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if path := shutil.which(name):
            return path
    return None


def _print_pdf(html: str, pdf: str):
    """Print the page to ``pdf`` with headless Chromium, through a temporary HTML file."""
    with tempfile.TemporaryDirectory() as folder:
        page = Path(folder) / "report.html"
        page.write_text(html, encoding="utf-8")
        with atomic_write(pdf, None) as temporary:
            done = subprocess.run([_browser(), "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                                   "--disable-background-networking", "--disable-component-update", "--disable-sync",
                                   f"--user-data-dir={folder}/profile", "--no-pdf-header-footer",
                                   f"--print-to-pdf={temporary}", page.as_uri()],
                                  capture_output=True, timeout=180)
            if done.returncode != 0 or not Path(temporary).is_file() or Path(temporary).stat().st_size == 0:
                raise InputError(f"--pdf {pdf}: Chromium could not print the report (exit {done.returncode})")
