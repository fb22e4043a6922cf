"""``fit MODEL --measured FILE --params KEY[,KEY...] --out FITTED.toml``."""

from __future__ import annotations

import sys

import numpy as np

from ..errors import InputError
from ..io import save_model
from ._common import (add_alias, as_typed, add_input_file, add_model_argument, add_output_file, check_ending, check_output_options,
                      check_outputs, open_model, parse_band, parse_list, parse_names, save_figure, show_progress, use_agg, whole_number)
from ._units import ENVIRONMENT, key_unit, key_value_in

NAME = "fit"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"starts": "--starts"}
HELP = "identify model parameters (mount stiffness, damping, ...) from measured FRFs"
UNITS_HELP = ("unit system of what is printed and drawn: si (default) or us (the parameters' start and fitted "
              "values in lb, lbf/in, lbf s/in, lb in², in ..., with a unit column; the --plot FRFs in in/lbf, "
              f"in/s/lbf, g/lbf); also set once by {ENVIRONMENT}. The model files read and written stay SI "
              "(docs/units.md)")   # --units
DESCRIPTION = """Least-squares fit of model parameters to measured FRFs (UFF 58/58b or CSV), at
every speed in the file: log-scaled parameters within bounds, relative complex residual,
coherence weighting, an optional frequency band, several starting points. Prints the fitted
values with standard uncertainties and the correlation matrix and writes the fitted model
file (never over the input). A fit that does not converge, or whose parameters the data do
not determine, says why and exits with code 1 without writing the model.

KEY is a dotted key (a whole array is scaled as one) or 'gain'. With --units us the table gives
the start and fitted values in US units (lb, lbf/in, lbf s/in, lb in², in, oz in, psi) and a last
column unit; factors, uncertainties, correlations and residuals have no unit. The model files
(MODEL, --out) are SI whatever --units says.

example:
  rotordyn-modal fit start.toml --measured measured.uff --freq-band 2:40 \\
      --params suspensions.mount-FL.stiffness,suspensions.mount-FL.damping --out fitted.toml"""


def add_arguments(parser):
    add_model_argument(parser)
    add_input_file(parser, "--measured", required=True, metavar="FILE", help="measured FRFs (.uff/.unv, or a .csv table; .txt and .tsv read as CSV)")
    add_input_file(parser, "--mapping", metavar="FILE.csv", help="UFF node/direction to channel table")
    parser.add_argument("--params", required=True, metavar="KEY[,KEY]",
                        help="dotted keys (or 'gain'), comma-separated; a key whose names hold ',' is given as "
                             "it is, or quoted (\"a,b\"), or with its commas escaped (a\\,b)")
    add_output_file(parser, "--out", required=True, metavar="FITTED.toml", help="fitted model file to write")
    parser.add_argument("--freq-band", dest="band", metavar="LO:HI", help="frequency band of the measured FRFs used [Hz]")
    add_alias(parser, "--freq-band", "--band")
    parser.add_argument("--bound-factor", default="100", metavar="F", help="each parameter within start/F .. start*F (default 100)")
    parser.add_argument("--starts", type=whole_number, default=3, metavar="N", help="starting points (default 3)")
    parser.add_argument("--no-coherence", action="store_true", help="do not weight by coherence")
    add_output_file(parser, "--plot", metavar="FILE.png|FILE.svg|FILE.pdf",
                        help="overlay of the fitted model on the measurement at every speed")
    parser.add_argument("--quiet", action="store_true", help="no progress (bars, or lines where stderr is a log), no table on the terminal")


def run(args) -> int:
    from ..analysis.fit import fit
    from ..io.measured import check_mapping_used, read_measured
    check_outputs(args, args.out)
    check_ending(args.out, (".toml",), "--out", stdout=False)
    check_output_options(args)
    model = open_model(args)   # its warnings held when every analysis refuses it: one line
    params = parse_names(args.params, "--params", lambda key: key == "gain" or _is_key(model, key))
    band = parse_band(args.band, as_typed(args, "--freq-band"), "Hz", example="2:40", wording="form") \
        if args.band is not None else None
    factor = float(parse_list(args.bound_factor, "--bound-factor")[0])
    if not factor > 1:
        raise InputError(f"--bound-factor {args.bound_factor}: expected a number > 1")
    check_mapping_used(args.mapping, args.measured)
    measured = read_measured(args.measured, model, args.mapping)
    if band is not None and not any(((m.frequencies_hz >= band[0]) & (m.frequencies_hz <= band[1])).any()
                                    for m in measured):
        lines = np.concatenate([m.frequencies_hz for m in measured])
        raise InputError(f"{args.measured}: {as_typed(args, '--freq-band')} {args.band}: expected a band that holds measured frequency "
                         f"lines (the file's lines run from {lines.min():.6g} to {lines.max():.6g} Hz)")
    result = fit(model, measured, params, bounds={p: (1 / factor, factor) for p in params}, band_hz=band,
                 weighting="none" if args.no_coherence else "coherence", starts=args.starts,
                 progress=show_progress(args))
    fitted = result.fitted_model(model)
    if not args.quiet:
        _report(result, model, args.units)
        _print_frac(model, fitted, measured)
    if args.plot:
        _overlay(fitted, measured, args)
    if not result.converged:
        print(f"rotordyn-modal fit: not converged: {result.message}", file=sys.stderr)
        return 1
    save_model(fitted, args.out, inputs=[args.model, args.measured])
    if not args.quiet:
        print(f"fitted model written to {args.out}", file=sys.stderr)
    return 0


def _report(result, model=None, system="si"):
    import pandas as pd

    table = _in_units(result, model, system)
    with pd.option_context("display.width", 200, "display.max_colwidth", 80):
        print(table.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
        print("\nparameter correlation:")
        print(pd.DataFrame(result.correlation, index=result.keys, columns=range(1, len(result.keys) + 1))
              .to_string(float_format=lambda v: f"{v:+.3f}"))
    print(f"\nRMS relative residual {result.cost:.4g} over {result.n_points} frequency lines; "
          f"from each start: {', '.join(f'{c:.3g}' for c in result.start_costs)}")


def _in_units(result, model, system):
    """The parameter table (:meth:`FitResult.to_dataframe`, SI) in ``system``: start and fitted
    values in the unit of each key's quantity, and a last column ``unit``; SI unchanged."""
    table = result.to_dataframe()
    if system == "si":
        return table
    shown = (lambda values: [_text(key_value_in(k, v, system, model)) for k, v in zip(result.keys, values)])
    table["start"], table["fitted"] = shown(result.start_values), shown(result.values)
    table["unit"] = [key_unit(k, system, model) for k in result.keys]
    return table


def _text(value):
    """As :meth:`FitResult.to_dataframe` writes a value: 6 digits, a list in brackets."""
    return f"{value:.6g}" if np.ndim(value) == 0 else "[" + ", ".join(f"{v:.6g}" for v in np.ravel(value)) + "]"


def _model_sets(model, measured):
    from ..analysis.frf import frf

    return [frf(model, m.speed, m.frequencies_hz, list(m.inputs), list(m.outputs), m.quantity) for m in measured]


def _print_frac(start, fitted, measured):
    from ..analysis.correlation import frac

    for m, a, b in zip(measured, _model_sets(start, measured), _model_sets(fitted, measured)):
        keep = np.all(np.isfinite(m.H), axis=-1)
        print(f"FRAC at {m.speed * 30 / np.pi:g} rpm: start {np.round(frac(a.H[keep], m.H[keep]), 3)}, "
              f"fitted {np.round(frac(b.H[keep], m.H[keep]), 3)}")


def _overlay(fitted, measured, args):
    from ..plotting.frf import plot_overlay
    from .frf import _input_kinds

    use_agg()
    save_figure(plot_overlay(_model_sets(fitted, measured), measured,
                             title="Fitted model (lines) over the measurement (dots)", units=args.units,
                             input_kinds=_input_kinds(fitted)), args)


def _is_key(model, key: str) -> bool:
    """True when ``key`` is a dotted key of one of the model's values."""
    try:
        model.get(key)
    except (InputError, LookupError, TypeError, ValueError):
        return False
    return True
