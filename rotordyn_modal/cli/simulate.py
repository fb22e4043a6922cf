"""``simulate MODEL --duration T [--speed S] [--ramp STOP | --free-spin]``."""

from __future__ import annotations

import sys

import numpy as np

from .._limits import count_problem
from ..errors import InputError
from ..units import to_system
from ._common import (IN_SPEED_UNIT, add_alias, add_allow_long, as_typed, add_model_argument, check_known, add_outputs, add_speed_unit, open_model, parse_number,
                      save_figure, show_progress, speed_value, use_agg, whole_number, write_table)

NAME = "simulate"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"duration": "--duration", "rtol": "--rtol", "atol": "--atol", "impulse_size": "--impulse-size",
             "speed": "--speed", "final_speed": "--ramp", "samples": "--samples"}
HELP = ("nonlinear large-rotation time simulation (constant speed, run-up ramp or free spin), rotors on bearings; "
        "flexible rotors, pedestals and gear meshes in the linear time model")
DESCRIPTION = """Integrate the machine's nonlinear equations of motion in time: the stator as a rigid
body with large rotation (axial angle + transverse Euler vector, docs/theory-large-rotations.md), every rotor on
[[bearings]] a rigid body of its own moving in its bearings' springs and dampers (its tilt
relative to the stator again an axial angle + transverse Euler vector), the other rotors
turning in the stator, spins coupled by the transmissions, exact gyroscopic coupling,
unbalances as rotating masses, gravity (top-level 'gravity' key) and suspension forces that
follow their attachment points. Without a [stator] the bearings stand on the ground. At
t = 0 the machine is at rest in its undeformed position (springs unstretched, --initial
rest) or in static equilibrium under gravity (--initial equilibrium), and the rotors spin at
--speed. Tabulated bearing coefficients follow each rotor's own speed; a plain journal
bearing (type = 'journal') pushes its journal with the oil film's nonlinear force
(short-bearing theory, pi-film), loaded by gravity: start such a model from --initial
equilibrium at a running speed; a journal that reaches its bearing wall ends the run (exit 2).

Drive modes: an ideal drive holds --speed (default; the drive torque is an output);
--ramp STOP runs the speed up (or down) linearly from --speed to STOP over --duration
(the rotors' angular acceleration terms included); --free-spin leaves the spin free.
Damping is the suspensions' and bearings' viscous damping; a hysteretic loss_factor is
refused (exit 2), since it has no time-domain meaning.

--plot draws the time histories (path of the rotors' centres, transverse rotation of the
stator and of each rotor in its bearings, axial angular velocity, energy terms) or, with
--ramp, the run-up figures: the sensor's signal, its order-tracked (1X) amplitude and phase
(unwrapped) for every rotor, the amplitude beside the linear model's steady unbalance response at the
same speeds (dashed), and a waterfall (log colour scale, frequencies up to its
content), with the Campbell diagram's critical speeds overlaid and labelled (mode, order,
rpm). With numba the first run compiles the kernels (~20 s, said on stderr). A run of the
nonlinear model estimated to take more than 30 minutes of CPU time (the integrator's steps follow
the fastest motion: a stiff mode of a light part makes them many) is refused before it starts,
with the estimate (--allow-long runs it anyway, ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit).
A --duration whose end time's float resolution (duration x 2.2e-16) is not well below the fastest
motion's period is refused before the work, naming the largest that passes (no CPU time lifts it:
docs/simulate.md).

A model with a flexible rotor ([[rotors.shaft]]), with bearing pedestals (pedestal_mass) or
with gear mesh stiffness (mesh_stiffness, mesh_damping), which the nonlinear model cannot
carry, is integrated as its linear model instead (said once on stderr; docs/simulate.md,
'Flexible rotors'): the drive's angle prescribed
(--speed, or --ramp), every body and every node of the shafts moving by small motions about
the spinning machine (M q'' + (C + w G) q' + K q = unbalance forces, w the drive speed), the
unbalances as rotating forces (with their angular-acceleration part on a ramp). It keeps the
undamped modes below 4 times the fastest spin frequency (at least the 6 lowest; after an
impulse (--excitation), or weights set on from --initial rest, also every mode carrying over
0.1 % of that load's largest modal response at a sensor, and every mode below the Nyquist
frequency of the output times: at rest the spin gives none) plus the static deflections under
the unbalances and weights; the default output times then also give 10 a period of the fastest
mode the load reaches (said on stderr past 10 times the usual count, else with --verbose), and
--samples that cannot resolve a mode carrying over 1 % get a warning naming it (docs/simulate.md,
'Under a sudden load'); --max-frequency HZ sets that limit,
'all' keeps every mode (the linear model exactly, slower). --free-spin is refused with such
a model (exit 2); a plain journal bearing (type = 'journal') keeps its film's nonlinear force
on the linear structure (oil whirl and whip of flexible rotors; the basis then also holds the
static deflections under forces at the journals). The energies in the CSV are then
those of the small motions, the drive torque the one spinning up the rotors' polar inertias.

CSV columns: time_s,u_x,u_y,u_z,theta_x,theta_y,theta_z,spin_speed_rad_s,drive_torque_nm,
drive_speed_rad_s, then one column per sensor [m], rotor centres [m], each bearing's force
and moment on the stator (NAME_Fx..NAME_Mz [N, N m], stator axes) and the energies [J].
u is the displacement of the reference point [m], theta = gamma + psi e the stator's
transverse Euler vector plus roll angle [rad], model axes.
The SI names carry no unit, so: u_x, u_y and u_z are in m; theta_x, theta_y and theta_z in rad;
each sensor's column (named by the sensor) in m; the rotor centres NAME_center_x, NAME_center_y
and NAME_center_z in m; a bearing's forces NAME_Fx, NAME_Fy and NAME_Fz in N; its moments NAME_Mx,
NAME_My and NAME_Mz in N m (docs/units.md).
With --units us (docs/units.md) the displacements u_x..u_z and the sensors are in mil, the
rotor centres in in, the bearings' forces in lbf and moments in lbf in, the drive torque in
lbf in, each such column named with its unit (u_x_mil, NAME_center_x_in, NAME_Fx_lbf,
NAME_Mx_lbfin, drive_torque_lbfin); times, angles, rad/s and energies [J] stay. The figures
then draw displacements in mil.

examples:
  rotordyn-modal simulate examples/spring_block_rotor.toml --speed 50 --speed-unit rad/s \\
      --free-spin --duration 10 --plot spring_block.png
  rotordyn-modal simulate examples/gear_machine.toml --speed 0 --ramp 4000 --duration 3 \\
      --sensor acc-top-z --plot runup.png --out runup.csv
  rotordyn-modal simulate examples/gear_machine.toml --speed 3000 --duration 0.5 \\
      --excitation hammer-z --impulse-size 0.5
  rotordyn-modal simulate examples/fan_on_bearings.toml --speed 0 --ramp 9000 --duration 3 \\
      --samples 30001 --sensor probe-DE-x --plot fan_runup.png
  rotordyn-modal simulate examples/compressor_rotor.toml --speed 3000 --ramp 9000 --duration 2 \\
      --sensor midspan-y --plot compressor_runup.png"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--duration", required=True, metavar="T", help="simulated time [s]")
    parser.add_argument("--speed", default="0", metavar="SPEED",
                        help=f"reference rotor speed at t = 0 {IN_SPEED_UNIT} (default 0)")
    add_speed_unit(parser)
    drive = parser.add_mutually_exclusive_group()
    drive.add_argument("--ramp", metavar="SPEED", help="run-up: speed at the end of --duration (unit of --speed)")
    drive.add_argument("--free-spin", action="store_true", help="no drive torque: the spin is free")
    parser.add_argument("--initial", choices=["rest", "equilibrium"], default="rest",
                        help="initial state of the stator, at rest with the rotors spinning at --speed: "
                        "'rest' undeformed (springs unstretched, default), 'equilibrium' in static "
                        "equilibrium under gravity")
    parser.add_argument("--excitation", dest="impulse", metavar="NAME",
                        help="hit this [[excitations]] entry at t = 0 with an impulse of --impulse-size")
    add_alias(parser, "--excitation", "--impulse")
    parser.add_argument("--impulse-size", default="1", metavar="J", help="impulse [N s] (N m s for a moment), default 1")
    parser.add_argument("--samples", type=whole_number, metavar="N", help="number of output times (default: 20 per period of the "
                        "fastest spin or natural frequency; flexible rotors after a sudden load also 10 per "
                        "period of the fastest mode it reaches)")
    parser.add_argument("--rtol", default="1e-9", metavar="R", help="relative tolerance of the integrator (default 1e-9)")
    parser.add_argument("--atol", default="1e-12", metavar="A", help="absolute tolerance of the integrator (default 1e-12)")
    parser.add_argument("--backend", choices=["auto", "numba", "numpy"], default="auto",
                        help="right-hand side: numba-compiled when installed (auto), or plain numpy")
    parser.add_argument("--sensor", metavar="NAME", help="sensor of the run-up figures (default: the first)")
    parser.add_argument("--max-frequency", dest="modes_below", metavar="HZ",
                        help="flexible rotors: the linear time model keeps the modes (undamped, at the start "
                             "speed) below HZ [Hz] (default: 4 times the fastest spin frequency), at least the 6 "
                             "lowest; or 'all'")
    add_alias(parser, "--max-frequency", "--modes-below")
    add_allow_long(parser)
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.campbell import campbell
    from ..simulation import simulate
    from ..simulation.runup import steady_orders
    from ..simulation.simulate import _LARGEST_SPEED as LARGEST_SPEED

    model = open_model(args)
    speed = speed_value(args.speed, args.speed_unit, "--speed", largest=LARGEST_SPEED)
    final = speed_value(args.ramp, args.speed_unit, "--ramp", largest=LARGEST_SPEED) if args.ramp is not None else None
    if args.samples is not None and args.samples < 2:
        raise InputError(f"--samples {args.samples}: expected a whole number >= 2")
    if args.samples is not None and (problem := count_problem(args.samples, "samples")):
        raise InputError(f"--samples {args.samples}: expected {problem}")
    if args.sensor is not None:
        check_known([args.sensor], args.sensor, "--sensor", "sensor", [s.name for s in model.sensors])
    if args.impulse is not None:     # before the kernel's compilation, naming the option as typed
        check_known([args.impulse], args.impulse, as_typed(args, "--excitation"), "excitation",
                    [x.name for x in model.excitations])
    drive = "ramp" if final is not None else ("free" if args.free_spin else "constant")
    result = simulate(model, parse_number(args.duration, "--duration"), speed, drive=drive, final_speed=final,
                      initial=args.initial, impulse=args.impulse, impulse_size=parse_number(args.impulse_size, "--impulse-size"),
                      samples=args.samples, rtol=parse_number(args.rtol, "--rtol"),
                      atol=parse_number(args.atol, "--atol"), backend=args.backend, progress=show_progress(args),
                      modes_below=_modes_below(args.modes_below, as_typed(args, "--max-frequency")))
    if args.out or not args.quiet:
        write_table(_in_units(result.to_dataframe(), result, args.units), args)
    if not args.quiet:
        _summary(result)
    if args.plot:
        use_agg()
        critical, steady = None, None
        if drive == "ramp" and final != speed:
            critical = campbell(model, np.linspace(min(speed, final), max(speed, final), 121)).critical
        if drive == "ramp" and result.sensor_names:      # the run-up figure: the steady response beside the tracks
            steady = steady_orders(model, result, args.sensor or result.sensor_names[0])
        save_figure(result.plot(sensor=args.sensor, critical=critical, title=model.name or None,
                                units=args.units, steady=steady), args)
    return 0


#: quantity kind of the table's columns with a unit -> the ending its US name gets
_US_ENDINGS = {"displacement": "_mil", "length": "_in", "force": "_lbf", "moment": "_lbfin"}


def _column_kinds(result) -> dict:
    """Column of :meth:`SimulationResult.to_dataframe` -> quantity kind, for those with a length,
    force or moment: the reference point's and the sensors' vibration (displacement), the rotor
    centres (points: length), the bearings' forces and moments and the drive torque."""
    kinds = {f"u_{axis}": "displacement" for axis in "xyz"}
    kinds |= {name: "displacement" for name in result.sensor_names}
    kinds |= {f"{name}_center_{axis}": "length" for name in result.rotor_names for axis in "xyz"}
    kinds |= {f"{name}_{c}": "force" if c.startswith("F") else "moment" for name in result.bearing_names
              for c in ("Fx", "Fy", "Fz", "Mx", "My", "Mz")}
    kinds["drive_torque_nm"] = "moment"
    return kinds


def _in_units(table, result, system):
    """The table in ``system`` (as it is in SI): with --units us, the columns of
    :func:`_column_kinds` converted and named with their unit (``u_x_mil``, ``probe_mil``,
    ``rotor_center_x_in``, ``DE_Fx_lbf``, ``DE_Mx_lbfin``, ``drive_torque_lbfin``)."""
    if system == "si":
        return table
    table = table.copy()
    names = {}
    for column, kind in _column_kinds(result).items():
        table[column] = to_system(table[column].to_numpy(dtype=float), kind, system)
        stem = column[:-len("_nm")] if column == "drive_torque_nm" else column
        names[column] = stem + _US_ENDINGS[kind]
    return table.rename(columns=names)


def _modes_below(text, option="--max-frequency"):
    """``--max-frequency``: a frequency [Hz] > 0 to rad/s, 'all' (every mode), or None."""
    if text is None:
        return None
    if text.strip().lower() == "all":
        return float("inf")
    value = parse_number(text, option)
    if not np.isfinite(value) or value <= 0:
        raise InputError(f"{option} {text}: expected a frequency [Hz] > 0, or 'all'")
    return 2 * np.pi * value


def _summary(result):
    energy = result.total_energy
    drift = np.abs(energy - energy[0]).max() / max(abs(energy[0]), np.abs(result.kinetic_energy).max(), 1e-300)
    tilt = max(np.linalg.norm(result.gamma, axis=1).max(initial=0.0),
               np.linalg.norm(result.rotor_tilts, axis=2).max(initial=0.0))
    print(f"simulated {result.time[-1]:.6g} s ({len(result.time)} samples, drive {result.drive}); "
          f"largest transverse rotation {np.degrees(tilt):.4g} deg; "
          f"spin speed {result.spin_speed.min():.6g}..{result.spin_speed.max():.6g} rad/s; "
          f"relative change of total energy {drift:.3g}", file=sys.stderr)
