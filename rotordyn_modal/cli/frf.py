"""``frf MODEL --speed S --freqs R [--excitation NAME] [--sensor NAME] [--quantity Q] [--measured FILE]``."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..analysis.spectra import QUANTITY_OF_RESPONSE
from .._progress import ONE_CALL_NOTE, phase
from ..errors import InputError
from ..units import FRF_OUTPUT_KINDS, ratio_scale
from ._common import (IN_SPEED_UNIT, NAME_LIST_HELP, add_alias, add_input_file, add_model_argument, add_outputs,
                      add_sensor_argument, add_speed_unit, as_typed, check_known, open_model, parse_names, parse_range,
                      save_figure, show_progress, speed_value, use_agg, write_table)

NAME = "frf"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"speed": "--speed"}
HELP = "frequency response from excitations to sensors (or forces), over measured data"
#: --quantity's words (``frf`` and ``unbalance``, and the study file's ``quantity``): the motion a
#: sensor reads -> the FRF of that motion per unit force, either word accepted by both commands
#: (docs/frf-and-measurement.md); one table, :data:`~rotordyn_modal.analysis.spectra.QUANTITY_OF_RESPONSE`
QUANTITIES = QUANTITY_OF_RESPONSE
QUANTITY_METAVAR = "displacement|velocity|acceleration"
QUANTITY_HELP = "(or the FRF's name of it: receptance, mobility, accelerance)"
DESCRIPTION = """Frequency response functions at one speed of the reference rotor, from the
[[excitations]] to the [[sensors]]: --quantity displacement (receptance [m/N]), velocity
(mobility [m/s/N]) or acceleration (accelerance [m/s^2/N]) per unit force, either word (with
--units us: in/lbf, in/s/lbf, g/lbf, and a last column unit; docs/units.md).
Viscous models use modal superposition, models with loss factors or Maxwell
branches a direct solve at every frequency. --force-outputs replaces the sensors by forces:
--force-outputs suspensions gives the force each suspension passes to the ground per unit input
(transmissibility), --force-outputs bearings the force each [[bearings]] entry passes to the
stator (or the ground) at its point and each rigidly attached rotor at its centre of mass
(docs/theory.md §13), --force-outputs rotors the total force each rotor passes to the stator
(the unbalance command adds such rows after its sensors). --measured FILE (UFF 58/58b
.uff/.unv, or CSV) draws the measurement of the same speed under the model in --plot.
--plot draws up to 12 FRFs in one magnitude and phase panel; more (or forces beside
moments) in groups, one per force item (else per input), each with its legend.
--out FILE.uff (or .unv) writes ASCII UFF 58 instead of CSV (nodes from --mapping, or the default
mapping: sensor k is node k, excitation k is node 100 + k, direction the model axis; a sensor or
excitation along no model axis needs --mapping, as UFF 58 directions are axis codes only; frequencies of
a constant step are even data, the first frequency and the step kept to 6 digits: a step of more
says how far the frequencies move, e.g. 1:60:591 keeps 0.1 Hz exactly, 1:60:600 not). Measured
UFF files are read in their own units (g, mm/s, lbf, dataset 164 factors) and converted to SI.

CSV columns: frequency_hz,output,input,real,imag,magnitude,phase_deg,speed_rpm,quantity (then unit
with --units us; quantity is receptance, mobility, accelerance or force): the file reads back as
--measured data of its speed, quantity and units. real, imag and magnitude are in the SI unit of
the row's quantity: receptance m/N, mobility m/s/N, accelerance m/s^2/N, force (--force-outputs)
N/N, a moment's N m/N, where an input that is a moment divides by N m instead of N (with --units
us: in/lbf, in/s/lbf, g/lbf, lbf/lbf, lbf in/lbf, named by the row's unit column; docs/units.md).

examples:
  rotordyn-modal frf examples/gear_machine.toml --speed 3000 --freqs 1:60:600 \\
      --excitation hammer-z --sensor acc-top-z --quantity acceleration --plot frf.png
  rotordyn-modal frf examples/gear_machine.toml --speed 0 --freqs 1:60:300 --force-outputs suspensions"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speed", default="0", metavar="SPEED",
                        help=f"reference rotor speed {IN_SPEED_UNIT} (default 0; negative reverses the spin)")
    add_speed_unit(parser)
    parser.add_argument("--freqs", required=True, metavar="START:STOP:N", help="frequencies [Hz]")
    parser.add_argument("--excitation", dest="input", metavar="NAME[,NAME]",
                        help=f"excitation name(s), {NAME_LIST_HELP} (default all)")
    add_alias(parser, "--excitation", "--input")
    add_sensor_argument(parser)
    parser.add_argument("--quantity", type=quantity_type(frf_names=True), default="receptance",
                        metavar=QUANTITY_METAVAR, help="the sensors' motion per unit force (default displacement) "
                        + QUANTITY_HELP)
    parser.add_argument("--force-outputs", dest="forces", choices=["suspensions", "bearings", "rotors", "all"],
                        help="forces per unit input instead of the sensors (all: the three kinds)")
    add_alias(parser, "--force-outputs", "--forces")
    add_input_file(parser, "--measured", metavar="FILE", help="measured FRFs (.uff/.unv, or a .csv table; .txt and .tsv read as CSV) to draw under the model")
    add_input_file(parser, "--mapping", metavar="FILE.csv", help="UFF node/direction to channel table: name,node,direction[,sign]")
    add_outputs(parser, out_endings=(".csv", ".uff", ".unv"))


def quantity_type(frf_names: bool):
    """argparse type of ``--quantity``: a word of :data:`QUANTITIES` (either side) as the
    command's Python API names it, the FRF's (receptance ...) or the motion's (displacement ...)."""
    def quantity(text: str) -> str:
        for motion, frf_name in QUANTITIES.items():
            if text in (motion, frf_name):
                return frf_name if frf_names else motion
        raise argparse.ArgumentTypeError(f"{text!r}: expected displacement, velocity or acceleration "
                                         f"{QUANTITY_HELP}")
    return quantity


def sensor_names(args, model):
    """The sensors named by --sensor (None: all), a name holding commas given whole or quoted;
    an unknown one refused naming the option as typed."""
    known, option = [s.name for s in model.sensors], as_typed(args, "--sensor")
    names = parse_names(args.output, option, known)
    check_known(names, args.output, option, "sensor", known)
    return names


def excitation_names(args, model):
    """The excitations named by --excitation (None: all); an unknown one refused naming the option."""
    known, option = [x.name for x in model.excitations], as_typed(args, "--excitation")
    names = parse_names(args.input, option, known)
    check_known(names, args.input, option, "excitation", known)
    return names


def run(args) -> int:
    from ..analysis.forces import force_frf
    from ..analysis.frf import frf
    from ..io.measured import check_mapping_used
    model = open_model(args)
    if args.forces and args.out and args.out.lower().endswith((".uff", ".unv")):
        raise InputError(f"--out {args.out}: force FRFs are written as CSV only")
    check_mapping_used(args.mapping, args.measured, args.out)
    speed = speed_value(args.speed, args.speed_unit, "--speed")
    freqs = parse_range(args.freqs, "--freqs")
    if freqs.min() < 0:
        raise InputError(f"--freqs {args.freqs}: frequencies must be >= 0 Hz")
    if args.forces:
        result = force_frf(model, speed, freqs, inputs=excitation_names(args, model), where=args.forces)
    else:
        inputs, outputs = excitation_names(args, model), sensor_names(args, model)
        _announce_long_solve(model, args)
        with phase(show_progress(args), f"{NAME}: FRFs at {len(freqs):,} frequencies"):   # ticks during LAPACK's solve
            result = frf(model, speed, freqs, inputs=inputs, outputs=outputs, quantity=args.quantity)
    measured = _measured_at(args, model, speed) if args.measured else None
    if args.out and args.out.lower().endswith((".uff", ".unv")):
        _write_uff(result, model, args)
    else:
        table = _with_speed_and_quantity(result) if args.out else result.to_dataframe()  # the file's own columns
        write_table(_in_units(table, result, model, args.units), args)
    if args.plot:
        use_agg()
        save_figure(result.plot(measured=measured, units=args.units, input_kinds=_input_kinds(model)), args)
    return 0


#: CPU seconds of the modal superposition's eigen-solution above which it is announced
_NOTICE_SECONDS = 20.0


def _announce_long_solve(model, args):
    """Before the modal superposition's eigen-solution of a large model (estimated over
    :data:`_NOTICE_SECONDS` of CPU time), one line on stderr with its estimate, as ``modes``
    gives: LAPACK's single call has no steps to count (500 geared rotors, 2,006 coordinates: about
    4 min of wall time on a shared machine; on a terminal the clock of ``frf``'s line runs)."""
    from ..analysis import _cost, _work
    from ..analysis.frf import choose_engine

    if args.quiet or choose_engine(model) != "modal":
        return
    n_states = _work._n_states(model)
    if _cost._PESSIMISTIC * n_states ** 3 <= _NOTICE_SECONDS:
        return                                          # small: no timing at all
    seconds = _work.eig_seconds(n_states)
    if seconds > _NOTICE_SECONDS:
        print(f"{NAME}: one eigen-solution of {n_states:,} states ({model.dofs.n:,} coordinates) for the modal "
              f"superposition: about {_cost.duration(seconds)} of CPU time ({ONE_CALL_NOTE})",
              file=sys.stderr, flush=True)


def _is_moment(output: str) -> bool:
    """A force FRF's moment row (``NAME:Mx``, ``:My``, ``:Mz``)."""
    return output.rsplit(":", 1)[-1] in ("Mx", "My", "Mz") and ":" in output


def _input_kinds(model) -> dict:
    """``{excitation name: 'force' or 'moment'}``."""
    return {x.name: "moment" if getattr(x, "kind", "force") == "moment" else "force" for x in model.excitations}


def _with_speed_and_quantity(result):
    """The FRF table with the speed [rpm] and the quantity of every row as its last columns, so
    that the file reads back (``--measured``) as what it holds (``io.measured.read_csv``)."""
    table = result.to_dataframe()
    table["speed_rpm"] = result.speed * 30 / np.pi
    table["quantity"] = result.quantity
    return table


def _in_units(table, result, model, system):
    """The FRF table (SI) in ``system``: real, imag and magnitude of each row times its factor
    (output quantity over input force or moment), a last column ``unit`` (in/lbf, in/s/lbf,
    g/lbf, lbf/lbf, lbf in/lbf); SI unchanged."""
    if system == "si":
        return table
    inputs, output = _input_kinds(model), FRF_OUTPUT_KINDS[result.quantity]
    scales = [ratio_scale("moment" if result.quantity == "force" and _is_moment(o) else output,
                          inputs.get(i, "force"), system) for o, i in zip(table["output"], table["input"])]
    factors = np.array([factor for factor, _ in scales])
    table = table.copy()
    for column in ("real", "imag", "magnitude"):
        table[column] = table[column].to_numpy(dtype=float) * factors
    table["unit"] = [label for _, label in scales]
    return table


def _write_uff(result, model, args):
    import sys

    from ..io.measured import default_mapping, read_mapping
    from ..io.uff import write_uff58

    mapping = read_mapping(args.mapping, model) if args.mapping else default_mapping(model)
    write_uff58([result], args.out, mapping, inputs=[args.model, args.measured])
    if not args.quiet:
        print(f"{result.H.shape[0] * result.H.shape[1]} FRFs written to {args.out} (UFF 58)", file=sys.stderr)


def _measured_at(args, model, speed):
    import numpy as np

    from ..io.measured import read_measured

    sets = read_measured(args.measured, model, args.mapping)
    best = min(sets, key=lambda s: abs(s.speed - speed))
    if abs(best.speed - speed) > 1e-6 * max(1.0, abs(speed)):
        raise InputError(f"--measured {args.measured}: no data at {speed * 30 / np.pi:g} rpm; the file has "
                         f"{', '.join(f'{s.speed * 30 / np.pi:g}' for s in sets)} rpm")
    if best.quantity != args.quantity and not args.forces:
        raise InputError(f"--measured {args.measured}: the file holds {best.quantity}, the model is asked for "
                         f"{args.quantity}: give --quantity {best.quantity}")
    for option, wanted, present in ((as_typed(args, "--sensor"), sensor_names(args, model), best.outputs),
                                    (as_typed(args, "--excitation"), excitation_names(args, model), best.inputs)):
        missing = [n for n in (wanted or []) if n not in present]
        if missing and not args.forces:
            raise InputError(f"--measured {args.measured}: no channel {', '.join(missing)} ({option}) in the "
                             f"file at this speed; it has {', '.join(present)}")
    return best
