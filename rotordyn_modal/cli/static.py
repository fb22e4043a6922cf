"""``static MODEL [--speed S] [--transmitted-power W] [--force BODY:X,Y,Z:FX,FY,FZ | ROTOR@AXIAL:FX,FY,FZ]
[--allowable-stress PA]
[--out FILE.csv]``."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from ..units import from_system, unit_label, unit_scale
from ._common import (IN_SPEED_UNIT, add_alias, add_model_argument, add_outputs, as_typed, add_speed_unit, open_model, parse_number, print_table,
                      save_figure, speed_value, use_agg, write_table)
from ._units import convert_table, kinds_by_ending

NAME = "static"
#: the Python arguments the options set, as messages name them (``main`` says the option as typed)
API_NAMES = {"power": "--transmitted-power", "speed": "--speed"}
HELP = "static displacement and support reactions under gravity, given forces and transmitted power"
DESCRIPTION = """Static analysis: the machine under its weight (the model's gravity), the forces
and moments given here, and the tooth (gear) or strand (belt) forces of the power each
transmission carries at the operating speed. Prints the loads, the displacement of the stator at
its centre of mass and at each mount and of each rotor relative to the stator (at its centre of
mass and at each bearing, and each bearing's pedestal), and the force and moment of every mount,
bearing and pedestal on the body it carries (a pedestal's weight is a load), with the balance of all of them (zero to round-off). Rubber mounts stand on their
static stiffness (Maxwell branches add nothing at zero frequency); bearings on their stiffness at
the operating speed, journal bearings on their light-load film (those of a rotor on three or more
journals, whose loads the analyses solve at each speed, on their loaded film: the same loads;
a journal's given load there is a fixed force), with each journal's eccentricity at its load (docs/static.md).

A flexible rotor's shaft bends under its weight, distributed along it, and the loads on it;
then the sag (relative to the stator and absolute), the shear force and the bending moment in
both planes and the bending stress are listed station by station along it, with a summary
(largest sag, moment and stress, and where); --plot draws them as a sag, shear force and
bending moment diagram along each flexible shaft (bending moments sagging positive).
The torque each shaft carries (from the transmitted power or torque and given moments, taken
by the rotor's coupling at its coupling_position, by default its centre of mass) adds the
torsional shear stress T c / J; the
section's von Mises stress sqrt(sigma^2 + 3 tau^2) is judged against the allowable stress:
the shaft's material's allowable_stress [Pa] in the model file, or --allowable-stress for every
shaft (Pa; psi with --units us). The summary gives the largest von Mises stress, where, and the
verdict (pass when it is at most the allowable stress; 'not evaluated' without one).

BODY is 'stator' or a rotor's name; points and vectors are in model axes, SI units (m, N, N m;
with --units us: in, lbf, lbf in, and --transmitted-power in hp; the tables then in in, lbf, lbf in, their
columns named x_in, Fx_lbf, Mx_lbfin, ux_in; docs/units.md).
On a flexible rotor --force ROTOR@AXIAL:FX,FY,FZ places the force at the station AXIAL from the
shaft's start, as axial_position in the model file (the same as the point there on the axis).
A moment acts on a rigid body as a whole (--moment BODY:MX,MY,MZ); on a flexible rotor at its
station (--moment ROTOR@AXIAL:MX,MY,MZ; without one, at its centre of mass, with a warning). --transmitted-power W is the
power every transmission carries from its driver to its driven rotor (negative: the other way);
--transmitted-power DRIVER->DRIVEN=W names one transmission (repeat the option for others).

CSV columns: table,kind,name,body,x_m,y_m,z_m,Fx_N,Fy_N,Fz_N,Mx_Nm,My_Nm,Mz_Nm,ux_m,uy_m,uz_m,rx_rad,ry_rad,rz_rad,on,eccentricity,attitude_deg
('table' is load, displacement or reaction and each row fills the columns of its table; 'name'
is the load's source, the displaced point, or the support; 'on' what a support stands on).
With a flexible rotor, 'shaft' rows follow (name: the node, n0 at the shaft's start) and add
the columns side,from_start_m,u_m,uy_abs_m,uz_abs_m,Vy_N,Vz_N,V_N,Mby_Nm,Mbz_Nm,Mb_Nm,
outer_diameter_m,stress_Pa,T_Nm,shear_stress_Pa,von_mises_Pa,allowable_Pa,utilization (a shaft
along x; the letters name the plane of u_y or u_z: uy_m is the sag along y relative to the
stator, Vy_N and Mby_Nm the shear force and bending moment in that plane; T_Nm the torque,
utilization von_mises / allowable, empty without an allowable stress; docs/static.md).

examples:
  rotordyn-modal static examples/motor_pump_on_mounts.toml
  rotordyn-modal static examples/gear_machine.toml --speed 3000 --transmitted-power 15000 --out static.csv
  rotordyn-modal static examples/journal_rotor.toml --speed 6000 --force rotor:0,0,0:0,0,-200
  rotordyn-modal static examples/flexible_pump_on_mounts.toml --plot shaft.png
  rotordyn-modal static examples/flexible_pump_on_mounts.toml --force pump@0.03:0,0,-200
  rotordyn-modal static examples/flexible_pump_on_mounts.toml --allowable-stress 120e6"""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--speed", metavar="SPEED",
                        help=f"reference rotor speed of the operating point {IN_SPEED_UNIT} (default: at rest)")
    add_speed_unit(parser)
    parser.add_argument("--transmitted-power", action="append", metavar="W|DRIVER->DRIVEN=W",
                        help="power [W; hp with --units us] each transmission (gear mesh, belt) carries "
                             "(repeat with DRIVER->DRIVEN=W for each one)")
    add_alias(parser, "--transmitted-power", "--power")
    parser.add_argument("--force", action="append", metavar="BODY:X,Y,Z:FX,FY,FZ",
                        help="a static force [N; lbf] at a point [m; in] of the stator or a rotor, or "
                             "ROTOR@AXIAL:FX,FY,FZ at a flexible rotor's station AXIAL [m; in] from its "
                             "shaft's start (repeat for more)")
    parser.add_argument("--moment", action="append", metavar="BODY:MX,MY,MZ",
                        help="a static moment [N m; lbf in] on the stator or a rotor, or ROTOR@AXIAL:MX,MY,MZ "
                             "at a flexible rotor's station (repeat for more)")
    parser.add_argument("--allowable-stress", metavar="STRESS",
                        help="allowable von Mises stress [Pa; psi] of every flexible shaft (default: each "
                             "material's allowable_stress)")
    add_outputs(parser)


def run(args) -> int:
    from ..analysis.static import static

    model = open_model(args)
    if args.plot and not any(r.flexible is not None for r in model.rotors):
        raise InputError(f"--plot {args.plot}: the model has no flexible rotor (one with a shaft): the figure "
                         "draws the sag, shear force and bending moment along flexible shafts")
    speed = None if args.speed is None else speed_value(args.speed, args.speed_unit, "--speed")
    bodies = {"stator"} | {rotor.name for rotor in model.rotors}
    forces = [_force(text, args.units) for text in args.force or ()] + \
        [_moment(text, args.units, bodies) for text in args.moment or ()]
    try:
        power = _power(args.transmitted_power, args.units, as_typed(args, "--transmitted-power"))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = static(model, speed=speed, forces=forces, power=power, units=args.units,
                            allowable_stress=_allowable(args.allowable_stress, args.units))
    except InputError as error:
        raise InputError(_as_typed(str(error), args)) from None
    for warning in caught:         # "forces[0]: a moment ..." said of the option typed, as refusals are
        try:
            said = warning.category(_as_typed(str(warning.message), args))
        except Exception:          # a category made otherwise: its own message
            said = warning.message
        warnings.warn(said, stacklevel=2)
    table = _in_units(result.to_dataframe(), args.units)
    if args.out:
        write_table(table, args) if args.out == "-" else write_table(table, _quietly(args))
    if args.out != "-" and not args.quiet:
        _print(result, args.units)
    if args.plot:
        use_agg()
        save_figure(result.plot_shafts(units=args.units), args)
    return 0


def _as_typed(message: str, args) -> str:
    """A refusal of ``rdm.static``'s ``forces[i] ...`` or ``power: ...`` said of the option typed:
    ``--force nobody:0,0,0:0,0,1: expected 'stator' or ...`` (it read ``forces[0] body = 'nobody'``)."""
    import re

    given = [("--force", text) for text in args.force or ()] + [("--moment", text) for text in args.moment or ()]
    found = re.match(r"forces\[(\d+)\]", message)
    if found and int(found.group(1)) < len(given):
        option, text = given[int(found.group(1))]
        tail = message[found.end():]         # " body = 'nobody': expected ...", " = (...): ...", ": ..."
        if tail.startswith(" = "):
            tail = ": " + tail.partition(": ")[2]
        return f"{option} {text}:{tail}" if tail.startswith(" ") else f"{option} {text}{tail}"
    if message.startswith("power: ") and args.transmitted_power:
        return f"{as_typed(args, '--transmitted-power')} {' '.join(args.transmitted_power)}: " \
               f"{message.removeprefix('power: ')}"
    return message


def _allowable(text, system: str = "si"):
    """``--allowable-stress`` [Pa, or psi in US units] in Pa, or None."""
    if text is None:
        return None
    value = parse_number(text, "--allowable-stress")
    if not value > 0:
        raise InputError(f"--allowable-stress {text}: expected a stress > 0 [{unit_label('pressure', system)}]")
    return float(from_system(value, "pressure", system))


def _quietly(args):
    """``args`` with ``quiet`` set: the tables are printed by :func:`_print`, not by write_table."""
    import argparse

    return argparse.Namespace(**{**vars(args), "quiet": True})


def _in_units(table, system):
    """A static table (SI) in ``system``: points and displacements in m or in, forces in N or lbf,
    moments in N m or lbf in (the columns renamed ``x_in``, ``Fx_lbf``, ``Mx_lbfin``)."""
    return convert_table(table, kinds_by_ending(table.columns), system)


def _print(result, system="si"):
    for title, table in (("loads", result.loads_table()), ("displacements", result.displacements()),
                         ("reactions (on the body each support carries)", result.reactions_table())):
        print(f"{title}:")
        print_table(_in_units(table, system), empty="none")
    if result.shafts:
        print("flexible shafts (sag relative to the stator; every station: --out FILE.csv):")
        for shaft in result.shafts.values():
            print(_shaft_summary(shaft, system))
    force, moment, scale = result.imbalance()
    (f, f_unit), (m, m_unit) = unit_scale("force", system), unit_scale("moment", system)
    print(f"balance of loads and reactions: sum of forces {np.linalg.norm(force) * f:.3g} {f_unit}, sum of "
          f"moments {np.linalg.norm(moment) * m:.3g} {m_unit} (the forces total {scale * f:.6g} {f_unit})")


def _shaft_summary(shaft, system="si") -> str:
    """Two lines per flexible rotor: its largest sag (µm or mil), shear force, bending moment and
    bending stress (MPa or psi), each with its station and position."""
    from ..plotting.shaft_statics import statics_scales

    if not (np.any(shaft.sag) or np.any(shaft.shear) or np.any(shaft.moment)):
        return f"  {shaft.rotor}: no static load on this shaft (the model has no gravity and no given force)"
    scales = statics_scales(system)
    x, x_unit = scales["length"]
    parts = []
    shown = (("sag", "sag"), ("shear", "shear force"), ("moment", "bending moment"), ("stress", "bending stress"))
    for quantity, what in shown:
        scale, unit = scales[quantity]
        value, i = shaft.largest(quantity)
        parts.append(f"{what} {value * scale:.4g} {unit} at {shaft.label(i, quantity)} ({shaft.axis_names[2]} = "
                     f"{shaft.position[i] * x:.4g} {x_unit})")
    indent = " " * (len(shaft.rotor) + 4)
    return f"  {shaft.rotor}: largest {parts[0]}; {parts[1]};\n{indent}{parts[2]}; {parts[3]};\n{indent}" \
        + _stress_line(shaft, system)


def _stress_line(shaft, system="si") -> str:
    """The shaft's stress verdict: its largest von Mises stress (with the torque there), where,
    against the allowable stress."""
    from ..plotting.shaft_statics import statics_scales

    scales = statics_scales(system)
    (s, s_unit), (x, x_unit), (m, m_unit) = scales["stress"], scales["length"], scales["moment"]
    check = shaft.stress_check()
    text = (f"von Mises stress {check.von_mises * s:.4g} {s_unit} (torque {abs(check.torque) * m:.4g} {m_unit}) "
            f"at {check.label} ({shaft.axis_names[2]} = {check.position * x:.4g} {x_unit})")
    if check.verdict == "not evaluated":
        return text + ": not evaluated (no allowable_stress for its material, no --allowable-stress)"
    return text + f", allowable {check.allowable * s:.4g} {s_unit}: {check.verdict} " \
        f"(utilization {check.utilization:.3g})"


def _vector(text: str, option: str, whole: str) -> list:
    parts = text.split(",")
    if len(parts) != 3:
        raise InputError(f"{option} {whole!r}: expected 3 comma-separated numbers in {text!r}")
    return [parse_number(p.strip(), option) for p in parts]


def _force(text: str, system: str = "si"):
    """``BODY:X,Y,Z:FX,FY,FZ`` (in ``system``'s units) -> ``(body, point [m], force [N])``, or
    ``ROTOR@AXIAL:FX,FY,FZ`` (a station of a flexible rotor, ``AXIAL`` from its shaft's start as
    the model file's ``axial_position``) -> ``{"body", "axial_position" [m], "force" [N]}``."""
    head, _, rest = text.rpartition(":")
    body, _, point = head.rpartition(":")
    if not body and "@" in head:
        rotor, _, axial = head.rpartition("@")
        if rotor:
            return {"body": rotor, "axial_position": _axial(axial, "--force", text, system),
                    "force": list(from_system(_vector(rest, "--force", text), "force", system))}
    if not body:
        length, force = unit_label("length", system), unit_label("force", system)
        raise InputError(f"--force {text!r}: expected BODY:X,Y,Z:FX,FY,FZ (body 'stator' or a rotor's name, "
                         f"a point [{length}] and a force [{force}] in model axes) or ROTOR@AXIAL:FX,FY,FZ "
                         f"(a flexible rotor's station, AXIAL [{length}] from its shaft's start)")
    return body, list(from_system(_vector(point, "--force", text), "length", system)), \
        list(from_system(_vector(rest, "--force", text), "force", system))


def _moment(text: str, system: str = "si", bodies=()) -> dict:
    """``BODY:MX,MY,MZ`` (in ``system``'s units) -> ``{"body", "moment" [N m]}`` (a rigid body's
    moment acts anywhere alike), or ``ROTOR@AXIAL:MX,MY,MZ`` -> with ``"axial_position"`` [m]: a
    flexible rotor's station, where it bends and twists the shaft (``bodies``: the model's names,
    one of which, holding an '@', is a body, not a station)."""
    body, _, rest = text.rpartition(":")
    if not body:
        raise InputError(f"--moment {text!r}: expected BODY:MX,MY,MZ (body 'stator' or a rotor's name, a moment "
                         f"[{unit_label('moment', system)}] in model axes) or ROTOR@AXIAL:MX,MY,MZ (a flexible "
                         f"rotor's station, AXIAL [{unit_label('length', system)}] from its shaft's start)")
    load = {"body": body, "moment": list(from_system(_vector(rest, "--moment", text), "moment", system))}
    rotor, _, axial = body.rpartition("@")
    if rotor and body not in bodies:
        load.update(body=rotor, axial_position=_axial(axial, "--moment", text, system))
    return load


def _axial(text: str, option: str, whole: str, system: str) -> float:
    """``AXIAL`` of ``ROTOR@AXIAL`` [m; in in US units] in m."""
    try:
        value = parse_number(text, option)
    except InputError:
        raise InputError(f"{option} {whole!r}: AXIAL {text!r}: expected a number [{unit_label('length', system)}] "
                         "from the shaft's start") from None
    return float(from_system(value, "length", system))


def _power(values, system: str = "si", option: str = "--transmitted-power"):
    """``--transmitted-power`` values [W, or hp in US units]: one number for every transmission, or
    ``DRIVER->DRIVEN=W`` each; returned in W (``option``: as typed, for messages)."""
    if not values:
        return None
    given = _power_numbers(values, option)
    if system == "si":
        return given
    return from_system(given, "power", system) if not isinstance(given, dict) else \
        {label: from_system(value, "power", system) for label, value in given.items()}


def _power_numbers(values, option: str = "--transmitted-power"):
    """The numbers of the ``--transmitted-power`` values as given (one number, or a dict by transmission)."""
    named = [v for v in values if "=" in v]
    if not named:
        if len(values) > 1:
            raise InputError(f"{option} {values[1]!r}: one power for every transmission is given once; name each "
                             "transmission (DRIVER->DRIVEN=W) to give several")
        return parse_number(values[0], option)
    if len(named) != len(values):
        raise InputError(f"{option} {next(v for v in values if '=' not in v)!r}: expected DRIVER->DRIVEN=W like "
                         f"the other {option} options")
    out = {}
    for text in named:
        label, _, number = text.rpartition("=")
        if label in out:
            raise InputError(f"{option} {text!r}: the transmission {label!r} is given twice")
        out[label] = parse_number(number, option)
    return out
