"""Validation rules of ``[[bearings]]`` and of the frame that bearings need.

A bearing is checked on its own (rotor, point on the spin axis, axes,
coefficients and their speed table, or a journal bearing's physical data),
then with the other bearings of its rotor (the static load share of a journal
bearing, and whether the rotor is held in tilt), then with the rest of the
model (without a ``[stator]`` bearings go to the ground, so nothing may stand
on a stator that is not there).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ..model._table import LARGEST, Table, magnitude_problem, semidefinite_problem, visible
from .bearings import BearingCoefficients, JournalData, local_to_model
from .journal_bearing import JournalLoadOverSpeed
from ..model.components import Bearing, Pedestal, input_keys, is_finite_number
from ..errors import ModelError, ModelWarning
from ..model.flexible import (PLAUSIBLE_SHAFT_DIAMETER, POSITION_ROUND_OFF, lateral_basis, node_matrices, station_z,
                              with_mesh)
from ..model.geometry import shift_matrix, transverse_axes

__all__ = ["bearings", "warn_transmitted_loads", "check_frame", "journal_load_shares", "continuous_beam_loads", "LONGEST_JOURNAL",
           "LONG_JOURNAL"]

_ON_AXIS_TOLERANCE = 1e-6  # m, plus the same fraction of the distance along the axis
_AXES_TOLERANCE = 1e-6
_LEAST_SHARE = 1e-9  # of the rotor's weight: below it a journal's load is zero for all purposes
_RADIAL_KEYS = ("stiffness", "damping", "moment_stiffness", "moment_damping")
_AXIAL_KEYS = ("axial_stiffness", "axial_damping")
_JOURNAL_KEYS = ("diameter", "length", "clearance", "viscosity", "load", "load_direction")
_JOURNAL_COMPUTES = ("stiffness", "damping", "speeds_rpm")
_PEDESTAL_KEYS = ("pedestal_mass", "pedestal_stiffness", "pedestal_damping")
#: longest journal bearing (length / diameter) that short-bearing theory is used for: DuBois and
#: Ocvirk (NACA Report 1157, 1953) found it close to measurements up to L/D = 1; a longer one
#: (up to this) draws a warning (:data:`LONG_JOURNAL`), beyond it the theory means nothing
LONGEST_JOURNAL = 2.0
#: length / diameter above which a journal bearing draws a warning
LONG_JOURNAL = 1.0
#: radial clearance / journal radius above which a journal bearing draws a warning: plain
#: bearings run at about 0.001 to 0.003 (the examples: 0.002), while a clearance in mm typed for
#: m (0.05 for 50 micrometres) lands at 0.1 to 1
WIDE_CLEARANCE = 0.02
#: radial clearance / journal radius below which a journal bearing draws a warning: a tenth of the
#: tightest plain bearings' (0.001); a clearance in micrometres typed as nanometres lands below it
TIGHT_CLEARANCE = 1e-4
#: [Pa s] oil viscosity above which a journal bearing draws a warning: lubricating oils run 0.002
#: to about 1 Pa s (ISO VG 680 cold), honey 10; mPa s (cP) typed for Pa s lands at 2 to 1000
THICK_OIL = 5.0
#: [Pa s] viscosity below which a journal bearing draws a warning: a tenth of water's (0.001);
#: gases (air 1.8e-5) need a compressible film theory, and a kinematic viscosity in m^2/s
#: (ISO VG 32: 3.2e-5) typed for the dynamic one lands below it
THIN_FLUID = 1e-4


def bearings(tables: dict, rotors, spin_axis: np.ndarray, gravity: np.ndarray) -> list[Bearing]:
    """Validate every ``[[bearings]]`` table.

    Parameters
    ----------
    tables : dict of str to Table
        The bearing tables by name.
    rotors : sequence of Rotor
        Validated rotors.
    spin_axis, gravity : ndarray, shape (3,)

    Returns
    -------
    list of Bearing, with :attr:`Bearing.coefficients` filled.
    """
    by_name = {r.name: r for r in rotors}
    parsed = [_bearing(table, by_name, spin_axis) for table in tables.values()]
    parsed = [_with_journal_load(b, tables, parsed, by_name, spin_axis, gravity) for b in parsed]
    parsed = _with_loads_over_speed(parsed, tables, by_name, spin_axis, gravity)
    for rotor in dict.fromkeys(b.rotor for b in parsed):
        mates = [b for b in parsed if b.rotor == rotor]
        _check_tilt_support(rotor, mates, tables, spin_axis)
        _check_held(by_name[rotor], mates, tables, spin_axis)
    return parsed


def warn_transmitted_loads(tables: dict, bearings, transmissions) -> None:
    """One warning line for each rotor in a gear or belt transmission whose journal bearings take
    their load from the weight alone (no ``load`` given): the tooth force or belt pull at the
    operating point is not in that load, and the film's coefficients follow it.

    Parameters
    ----------
    tables : dict of str to Table
        The bearing tables by name.
    bearings : sequence of Bearing
        The validated bearings.
    transmissions : sequence of Transmission
    """
    for rotor in dict.fromkeys(b.rotor for b in bearings):
        links = [t for t in transmissions if rotor in (t.driver, t.driven)]
        weighed = [b for b in bearings if b.rotor == rotor and b.type == "journal"
                   and "load" not in tables[b.name].data]
        if not links or not weighed:
            continue
        table = tables[weighed[0].name]
        names = ", ".join(f"[bearings.{visible(b.name)}] {b.coefficients.journal.load:.4g} N" for b in weighed)
        forces = " and ".join(dict.fromkeys("tooth force" if t.type == "gear" else "belt pull" for t in links))
        how = ", ".join(f"{t.type} {visible(t.driver)} -> {visible(t.driven)}" for t in links)
        warnings.warn(f"{table.source}: rotor {visible(rotor)!r} is in a transmission ({how}): the load of its "
                      f"journals without `load` ({names}) is their share of the weight alone, without the {forces} "
                      "at the operating point, and the film's coefficients follow the load (give load and "
                      "load_direction; `static --transmitted-power` computes the loads, docs/static.md)",
                      ModelWarning, stacklevel=2)


# ----------------------------------------------------------------------------------------
def _bearing(table: Table, rotors, e: np.ndarray) -> Bearing:
    table.check_keys(input_keys("bearings"))
    rotor = table.name_of("rotor", rotors, "rotors", required=True)
    position = _on_spin_axis(table, rotors[rotor], e)
    kind = table.text("type", default="linear", choices=("linear", "journal"))
    _check_keys_of_type(table, kind)
    axes = _radial_axes(table, e)
    speeds = _speed_table(table) if kind == "linear" else None
    count = 1 if speeds is None else len(speeds)
    local_k, local_c = _local_matrices(table, count, radial_required=kind == "linear")
    coefficients = BearingCoefficients(
        kind="journal" if kind == "journal" else ("table" if speeds is not None else "constant"),
        stiffness=local_to_model(local_k, axes), damping=local_to_model(local_c, axes),
        speeds=speeds, axial="axial_stiffness" in table.data,
    )
    values = {key: table.data.get(key) for key in input_keys("bearings")}
    values.update(name=table.data["name"], rotor=rotor, position=position, type=kind, axes=axes[:2])
    return Bearing(**values, coefficients=coefficients, pedestal=_pedestal(table, axes))


def _pedestal(table: Table, axes: np.ndarray):
    """The bearing's :class:`Pedestal` (None without ``pedestal_mass``): its stiffness and
    damping, symmetric 2x2 in the bearing's radial axes, to 3x3 model axes (zero along e)."""
    given = [key for key in _PEDESTAL_KEYS if key in table.data]
    if not given:
        return None
    for key in _PEDESTAL_KEYS[:2]:
        if key not in table.data:
            raise table.error(key, "<missing>", f"a value: a pedestal needs both pedestal_mass [kg] and "
                              f"pedestal_stiffness [N/m] ({given[0]} is given)")
    mass = table.number("pedestal_mass", positive=True)
    stiffness = _pedestal_matrix(table, "pedestal_stiffness", definite=True)
    damping = _pedestal_matrix(table, "pedestal_damping", definite=False)
    radial = axes[:2]
    return Pedestal(mass=mass, stiffness=radial.T @ stiffness @ radial, damping=radial.T @ damping @ radial)


def _pedestal_matrix(table: Table, key: str, definite: bool) -> np.ndarray:
    """A pedestal's symmetric 2x2 stiffness (positive definite: it alone holds the pedestal's
    mass) or damping (positive semidefinite) from a number, a 2-list or a 2x2 matrix."""
    if key not in table.data:
        return np.zeros((2, 2))
    raw = table.data[key]
    value = table.array(key, [(), (2,), (2, 2)])
    matrix = np.diag(np.broadcast_to(value, (2,))).astype(float) if value.ndim < 2 else value
    what = "positive definite" if definite else "positive semidefinite"
    if not np.allclose(matrix, matrix.T, rtol=1e-12, atol=0.0):
        raise table.error(key, raw, f"a symmetric {what} 2x2 matrix (a pedestal is a structure: its "
                          "coefficients are symmetric), a number or a 2-list")
    lowest = float(np.linalg.eigvalsh(matrix)[0])
    scale = float(np.abs(matrix).max(initial=0.0))
    if (definite and not lowest > 1e-12 * scale) or (not definite and lowest < -1e-12 * scale):
        raise table.error(key, raw, f"a {what} value ({'numbers > 0' if definite else 'numbers >= 0'} "
                          f"as a number or 2-list; a 2x2 matrix's lowest eigenvalue is {lowest:.4g})")
    return matrix


def _on_spin_axis(table: Table, rotor, e: np.ndarray) -> np.ndarray:
    """The bearing point, which must lie on the rotor's spin axis (snapped onto it); on a
    flexible rotor a station of its shaft (``position`` or ``axial_position``)."""
    if rotor.flexible is not None:
        return station_z(table, rotor.flexible, rotor.name)[0]
    if "axial_position" in table.data:
        raise table.error("axial_position", table.data["axial_position"], "no value: axial_position places a "
                          "bearing on a flexible rotor (one with a [[rotors.shaft]]); give position")
    position = table.vector3("position", required=True)
    centre = np.asarray(rotor.center_of_mass)
    along = (position - centre) @ e
    off = np.linalg.norm(position - centre - along * e)
    if off > _ON_AXIS_TOLERANCE * (1.0 + abs(along)):
        raise table.error("position", table.data["position"],
                          f"a point on the spin axis of rotor {rotor.name!r} (the line through its "
                          f"center_of_mass {_fmt(centre)} along spin_axis); this point is {off:.4g} m off it")
    snapped = centre + along * e
    # the place along the axis, measured from a centre far from the origin, may be lost to round-off
    moved = abs(float((snapped - position) @ e))
    if moved > POSITION_ROUND_OFF:
        raise table.error("position", table.data["position"],
                          f"a point whose place along rotor {rotor.name!r}'s axis double precision keeps: it is "
                          f"{abs(along):.3g} m from the rotor's center_of_mass {_fmt(centre)}, and measured from "
                          f"there round-off moves it {moved:.2g} m (give positions near the machine, in metres)")
    return snapped


def _check_keys_of_type(table: Table, kind: str) -> None:
    if kind == "journal":
        for key in _JOURNAL_COMPUTES:
            if key in table.data:
                raise table.error(key, table.data[key], "no value: a type = 'journal' bearing computes "
                                  "its radial coefficients from diameter, length, clearance, viscosity "
                                  "and load (use type = 'linear' to give them)")
        return
    for key in _JOURNAL_KEYS:
        if key in table.data:
            raise table.error(key, table.data[key], "no value: this key is for type = 'journal' bearings")


def _radial_axes(table: Table, e: np.ndarray) -> np.ndarray:
    """Rows: the bearing's two radial axes, then their cross product (+-e)."""
    if "axes" not in table.data:
        pair = transverse_axes(e)
    else:
        pair = table.array("axes", [(2, 3)])
        norms = np.linalg.norm(pair, axis=1)
        if np.any(norms == 0):
            raise table.error("axes", table.data["axes"], "two non-zero rows (the bearing's radial axes)")
        pair = pair / norms[:, None]
        if abs(pair[0] @ pair[1]) > _AXES_TOLERANCE or np.any(np.abs(pair @ e) > _AXES_TOLERANCE):
            raise table.error("axes", table.data["axes"], "two orthogonal rows normal to spin_axis "
                              "(the bearing's radial axes)")
        pair = pair - np.outer(pair @ e, e)                      # exactly normal to e
        pair[1] -= (pair[1] @ pair[0]) / (pair[0] @ pair[0]) * pair[0]
        pair = pair / np.linalg.norm(pair, axis=1)[:, None]
    return np.array([pair[0], pair[1], np.cross(pair[0], pair[1])])


def _speed_table(table: Table) -> np.ndarray | None:
    """Table speeds [rad/s] from ``speeds_rpm``: at least two, strictly increasing."""
    if "speeds_rpm" not in table.data:
        return None
    raw = table.data["speeds_rpm"]
    values = np.array(raw, dtype=float) if _is_number_list(raw) else None
    if values is None or values.ndim != 1 or len(values) < 2 or not np.all(np.isfinite(values)) \
            or magnitude_problem(values):
        raise table.error("speeds_rpm", raw, "a list of at least two finite speeds [rpm] of magnitude "
                          f"at most {LARGEST:g}")
    if not np.all(np.diff(values) > 0):
        raise table.error("speeds_rpm", raw, "strictly increasing speeds [rpm]")
    return values * np.pi / 30.0


def _is_number_list(value) -> bool:
    return isinstance(value, list) and all(is_finite_number(v) or isinstance(v, float) for v in value)


def _local_matrices(table: Table, count: int, radial_required: bool):
    """(count, 6, 6) stiffness and damping in the bearing's own axes."""
    stiffness, damping = np.zeros((count, 6, 6)), np.zeros((count, 6, 6))
    if radial_required and "stiffness" not in table.data:
        table.require("stiffness")
    for key, target, block in (("stiffness", stiffness, slice(0, 2)), ("damping", damping, slice(0, 2)),
                               ("moment_stiffness", stiffness, slice(3, 5)),
                               ("moment_damping", damping, slice(3, 5))):
        if key in table.data:
            target[:, block, block] = _per_speed(table, key, count, _radial_matrix)
    for key, target in (("axial_stiffness", stiffness), ("axial_damping", damping)):
        if key in table.data:
            target[:, 2, 2] = _per_speed(table, key, count, _axial_value)
    return stiffness, damping


def _per_speed(table: Table, key: str, count: int, reader):
    """One value (count 1) or one per table speed, each read by ``reader``."""
    raw = table.data[key]
    if count == 1:
        return np.asarray(reader(table, key, raw))[None]
    if not isinstance(raw, list) or len(raw) != count:
        raise table.error(key, raw, f"a list of {count} values, one per speed of speeds_rpm")
    return np.array([reader(table, f"{key}[{i}]", value) for i, value in enumerate(raw)])


def _radial_matrix(table: Table, key: str, raw) -> np.ndarray:
    """A 2x2 matrix from a scalar (isotropic), a 2-list (diagonal) or a 2x2 matrix."""
    sub = Table(table.source, table.label, {key: raw})
    value = sub.array(key, [(), (2,), (2, 2)], required=True)
    if value.ndim < 2:
        if np.any(value < 0):
            raise table.error(key, raw, "non-negative values (a scalar or 2-list is a diagonal "
                              "matrix; give a 2x2 matrix for coupled values)")
        return np.diag(np.broadcast_to(value, (2,))).astype(float)
    if problem := semidefinite_problem(value):
        raise table.error(key, raw, problem)
    return value


def _axial_value(table: Table, key: str, raw) -> float:
    sub = Table(table.source, table.label, {key: raw})
    return sub.number(key, required=True, nonnegative=True)


# ----------------------------------------------------------------------------------------
def _with_journal_load(bearing: Bearing, tables, every, rotors, e, gravity) -> Bearing:
    """A journal bearing with its :class:`JournalData` (load given, or the weight share)."""
    if bearing.type != "journal":
        return bearing
    table = tables[bearing.name]
    diameter = table.number("diameter", required=True, positive=True)
    if diameter > PLAUSIBLE_SHAFT_DIAMETER:   # its film coefficients follow from it without a word
        warnings.warn(f"{table.source}: [{table.label}] diameter = {diameter:g}: a journal over "
                      f"{PLAUSIBLE_SHAFT_DIAMETER:g} m across; a diameter in mm typed for m? (model files are SI)",
                      ModelWarning, stacklevel=2)
    clearance = table.number("clearance", required=True, positive=True)
    if not clearance < 0.5 * diameter:
        raise table.error("clearance", clearance, f"a radial clearance smaller than the journal's "
                          f"radius {0.5 * diameter:g} m")
    viscosity = table.number("viscosity", required=True, positive=True)
    _warn_journal_units(table, diameter, clearance, viscosity)
    length = table.number("length", required=True, positive=True)
    if length > LONGEST_JOURNAL * diameter:
        raise table.error("length", length, f"a bearing length at most {LONGEST_JOURNAL:g} x its diameter "
                          f"{diameter:g} m (L/D = {length / diameter:.3g}): the film's coefficients come from "
                          f"short-bearing (Ocvirk) theory, which holds for L/D up to about {LONG_JOURNAL:g} "
                          "(docs/model-file.md)")
    load_vector = _static_load(bearing, tables, every, rotors[bearing.rotor], e, gravity)
    _warn_hold_down(table, load_vector, gravity, e)
    x = load_vector / np.linalg.norm(load_vector)
    journal = JournalData(
        diameter=diameter, length=length,
        clearance=clearance, viscosity=viscosity,
        load=float(np.linalg.norm(load_vector)), axes=np.array([x, np.cross(e, x), e]),
    )
    coefficients = dataclasses.replace(bearing.coefficients, journal=journal)
    return dataclasses.replace(bearing, coefficients=coefficients)


def _warn_journal_units(table: Table, diameter: float, clearance: float, viscosity: float) -> None:
    """One warning line each for a journal's clearance over :data:`WIDE_CLEARANCE` of its radius
    or under :data:`TIGHT_CLEARANCE`, and a viscosity over :data:`THICK_OIL` or under
    :data:`THIN_FLUID`: most likely mm typed for m, mPa s for Pa s, m^2/s for Pa s. Either
    moves the film's eccentricity, so its coefficients, without another word at ``check`` (an
    analysis says only that the eccentricity is high)."""
    ratio = clearance / (0.5 * diameter)
    if ratio > WIDE_CLEARANCE:
        warnings.warn(f"{table.source}: [{table.label}] clearance = {clearance:g}: {ratio:.3g} of the journal's radius "
                      f"{0.5 * diameter:g} m, over {WIDE_CLEARANCE:g} (plain bearings run 0.001 to 0.003); a "
                      "clearance in mm typed for m? (model files are SI)", ModelWarning, stacklevel=3)
    if ratio < TIGHT_CLEARANCE:
        warnings.warn(f"{table.source}: [{table.label}] clearance = {clearance:g}: {ratio:.3g} of the journal's radius "
                      f"{0.5 * diameter:g} m, under {TIGHT_CLEARANCE:g} (plain bearings run 0.001 to 0.003); a "
                      "clearance converted to m twice? (model files are SI: 50 micrometres = 5e-5)", ModelWarning,
                      stacklevel=3)
    if viscosity < THIN_FLUID:
        warnings.warn(f"{table.source}: [{table.label}] viscosity = {viscosity:g}: under {THIN_FLUID:g} Pa s (lubricating "
                      "oils run 0.002 to 1 Pa s, water 0.001; a gas film needs a compressible theory); a kinematic "
                      "viscosity in m^2/s typed for the dynamic one in Pa s (= m^2/s x density)? (model files are SI)",
                      ModelWarning, stacklevel=3)
    if viscosity > THICK_OIL:
        warnings.warn(f"{table.source}: [{table.label}] viscosity = {viscosity:g}: over {THICK_OIL:g} Pa s (lubricating "
                      "oils run 0.002 to 1 Pa s, honey 10); a viscosity in mPa s (cP) typed for Pa s? (model files "
                      "are SI)", ModelWarning, stacklevel=3)


def _static_load(bearing, tables, every, rotor, e, gravity) -> np.ndarray:
    """The static load vector on the journal [N], normal to the spin axis."""
    table = tables[bearing.name]
    given = table.number("load", positive=True)
    direction = _load_direction(table, e)
    if given is not None:
        if direction is None:
            direction = _normal_part(gravity, e)
            if not np.linalg.norm(direction) > 0:
                raise table.error("load_direction", "<missing>", "the direction in which the load pushes "
                                  "the journal (gravity has no component normal to spin_axis)")
        return given * direction / np.linalg.norm(direction)
    weight = rotor.mass * _normal_part(gravity, e)
    if not np.linalg.norm(weight) > 0:
        raise table.error("load", "<missing>", "a static load [N] > 0 (without it the load is the "
                          "rotor's weight share, but gravity has no component normal to spin_axis)")
    mates = [b for b in every if b.rotor == bearing.rotor]
    if len(mates) > 2 and any("load" in tables[b.name].data for b in mates):
        return _split_beside_given(bearing, table, mates, rotor, e, gravity, tables)
    if rotor.flexible is not None and len(mates) > 2:
        return _continuous_beam_load(bearing, table, mates, rotor, gravity, tables)
    share = _weight_share(bearing, table, mates, rotor, e, tables)
    return share * weight


def _warn_hold_down(table: Table, load, gravity, e) -> None:
    """One line when a weight share pushes the journal against gravity: the film then holds the
    shaft down, at a load whose coefficients describe a journal lifted to the top of its
    bearing, which the statics alone does not vouch for."""
    if "load" in table.data:
        return
    down = _normal_part(gravity, e)
    if not float(np.asarray(load) @ down) < 0.0:
        return
    warnings.warn(f"{table.source}: [{table.label}] load: the rotor's weight gives this journal "
                  f"{-float(np.linalg.norm(load)):.4g} N (it holds the shaft down, against gravity); its "
                  f"coefficients are those of a {float(np.linalg.norm(load)):.4g} N load lifting the journal "
                  "to the top of its film (give load and load_direction if that is not meant)",
                  ModelWarning, stacklevel=2)


def _load_direction(table: Table, e):
    if "load_direction" not in table.data:
        return None
    direction = _normal_part(table.vector3("load_direction", nonzero=True), e)
    if not np.linalg.norm(direction) > 1e-6 * np.linalg.norm(table.vector3("load_direction")):
        raise table.error("load_direction", table.data["load_direction"], "a direction normal to spin_axis")
    return direction


def _normal_part(vector, e) -> np.ndarray:
    vector = np.asarray(vector, dtype=float)
    return vector - (vector @ e) * e


def _weight_share(bearing, table: Table, mates, rotor, e, tables) -> float:
    """Fraction of the rotor's weight this bearing carries.

    One or two bearings: the lever rule, exact whatever their stiffness (statics alone fixes
    the split). More bearings (statically indeterminate; a flexible rotor's are taken by
    :func:`_continuous_beam_load` before this): the rigid rotor on its bearings as springs,
    :func:`journal_load_shares`, when every one is a plain journal bearing without
    ``moment_stiffness``; otherwise the split depends on stiffnesses given at speed, and the
    load must be given.
    """
    if len(mates) == 1:
        return 1.0
    if len(mates) > 2:
        if not all(b.type == "journal" and b.moment_stiffness is None for b in mates):
            raise table.error("load", "<missing>", f"a static load [N]: rotor {rotor.name!r} has "
                              f"{len(mates)} bearings, so its weight split is statically indeterminate, "
                              "and not all are plain journal bearings without moment_stiffness (whose "
                              "split follows from their film, docs/static.md)")
        shares = journal_load_shares([_film_weight(tables[b.name]) for b in mates],
                                     [(np.asarray(b.position) - np.asarray(rotor.center_of_mass)) @ e
                                      for b in mates])
        share = shares[[b.name for b in mates].index(bearing.name)]
    else:
        centre = np.asarray(rotor.center_of_mass)
        s_self, s_other = ((np.asarray(b.position) - centre) @ e for b in
                           sorted(mates, key=lambda b: b is not bearing))
        share = s_other / (s_other - s_self) if s_other != s_self else 0.0
    if not abs(share) > _LEAST_SHARE:
        raise table.error("load", "<missing>", f"a static load [N]: this bearing carries none of rotor "
                          f"{rotor.name!r}'s weight (" + ("its centre of mass is at the other bearing)"
                                                          if len(mates) == 2 else "its share on the films is 0)"))
    return float(share)


def _splits_over_speed(mates, rotor, tables) -> bool:
    """True for a rotor (rigid or flexible) on three or more plain journals, three at least
    without a given ``load``: those journals' loads are solved at each speed (the given ones
    fixed, :func:`_with_loads_over_speed`). Two journals left to solve are the lever rule
    (statically determinate, :func:`_split_beside_given`)."""
    return (len(mates) > 2 and all(b.type == "journal" and b.moment_stiffness is None for b in mates)
            and sum("load" not in tables[b.name].data for b in mates) > 2)


def _fixed_journals(mates, tables) -> list:
    """The journals of a rotor on three or more plain journals whose ``load`` is given while two at
    least are not: fixed forces in the split (:attr:`JournalData.fixed_load`)."""
    if not (len(mates) > 2 and all(b.type == "journal" and b.moment_stiffness is None for b in mates)):
        return []
    given = [b for b in mates if "load" in tables[b.name].data]
    return given if len(mates) - len(given) > 1 else []


def _given_loads(mates, rotor, tables, e, gravity):
    """``(stations (G,), loads (G, 3))`` of the journals of ``mates`` whose ``load`` is given: their
    axial place from the rotor's centre of mass [m] and the force each puts on its bearing [N]."""
    given = [b for b in mates if "load" in tables[b.name].data]
    stations = np.array([(np.asarray(b.position) - np.asarray(rotor.center_of_mass)) @ e for b in given])
    loads = np.array([_static_load(b, tables, mates, rotor, e, gravity) for b in given]).reshape(-1, 3)
    return stations, loads


def _split_beside_given(bearing, table: Table, mates, rotor, e, gravity, tables) -> np.ndarray:
    """The load vector [N] on ``bearing`` (no ``load`` given), one of three or more journals of a
    rotor some of which have their ``load`` given: the given loads are fixed forces on the rotor
    and the journals left carry the rest of its weight. Two left: the lever rule (statics alone);
    three or more: as the rigid rotor on their light-load films splits it (a flexible rotor's: its
    continuous beam on them), the speed-free limit of what the analyses solve at each speed
    (:func:`_with_loads_over_speed`). One left: its load is fixed by the force balance, and the
    moment balance must hold too, else refused naming its ``load``."""
    if not all(b.type == "journal" and b.moment_stiffness is None for b in mates):
        raise table.error("load", "<missing>", f"a static load [N]: rotor {rotor.name!r} has "
                          f"{len(mates)} bearings, so its weight split is statically indeterminate, "
                          "and not all are plain journal bearings without moment_stiffness (docs/static.md)")
    weight = rotor.mass * _normal_part(gravity, e)
    given_stations, given_loads = _given_loads(mates, rotor, tables, e, gravity)
    left = [b for b in mates if "load" not in tables[b.name].data]
    stations = np.array([(np.asarray(b.position) - np.asarray(rotor.center_of_mass)) @ e for b in left])
    rest, moment = weight - given_loads.sum(0), -(given_stations @ given_loads)   # on the journals left
    if len(left) == 1:
        span = max(np.ptp(np.r_[stations, given_stations]), 1e-300)
        if np.linalg.norm(moment - stations[0] * rest) > 1e-9 * np.linalg.norm(weight) * span:
            raise table.error("load", "<missing>", f"a static load [N]: the loads given to the other journals of "
                              f"rotor {rotor.name!r} leave this one alone to carry the rest of its weight, "
                              "which then cannot balance its moment: give this journal's load too, or leave "
                              "two journals' load ungiven (docs/static.md)")
        load = rest
    elif rotor.flexible is not None and len(left) > 2:
        shaft = rotor.flexible
        given = [b for b in mates if b not in left]
        loads = continuous_beam_loads(
            shaft, [shaft.z_of(b.position) for b in left], gravity, [_film_weight(tables[b.name]) for b in left],
            [None if b.pedestal is None else b.pedestal.stiffness for b in left],
            [None if b.pedestal is None else b.pedestal.mass * np.asarray(gravity, dtype=float) for b in left],
            point_loads=[(shaft.z_of(b.position), -f) for b, f in zip(given, given_loads)])
        load = loads[left.index(bearing)]
    else:
        load = beam_on_springs([_film_weight(tables[b.name]) for b in left], stations, rest, moment)[left.index(bearing)]
    if not np.linalg.norm(load) > _LEAST_SHARE * np.linalg.norm(weight):
        raise table.error("load", "<missing>", f"a static load [N]: this bearing carries none of rotor "
                          f"{rotor.name!r}'s weight beside the loads given to its other journals")
    return load


def beam_on_springs(weights, stations, force, moment) -> np.ndarray:
    """The forces [N] (N, 3) on springs of stiffness proportional to ``weights`` at ``stations``
    [m] along a rigid rotor that carry ``force`` [N] (3,) and the ``moment`` [N m] (3,) of the
    forces they carry about the origin of the stations, ``sum F_i = force``, ``sum s_i F_i =
    moment``: the rotor moves by ``u + s theta`` and ``F_i = k_i (u + s_i theta)``. Two springs
    at different stations: the lever rule, whatever their stiffness."""
    k, s = np.asarray(weights, dtype=float), np.asarray(stations, dtype=float)
    matrix = np.array([[k.sum(), k @ s], [k @ s, k @ s**2]])
    u, theta = np.linalg.solve(matrix, np.array([force, moment], dtype=float))
    return k[:, None] * (u[None] + s[:, None] * theta[None])


def _with_loads_over_speed(parsed, tables, rotors, e, gravity) -> list:
    """The bearings, each journal of a rotor that :func:`_splits_over_speed` names given its
    load over speed: the rotor's static equilibrium on its nonlinear films and its pedestals'
    springs at each speed (:func:`~rotordyn_modal.elements.journal_bearing.
    rigid_rotor_journal_loads`, one solver shared by the rotor's journals; a flexible rotor's
    with its shaft's flexibility and sag on two journals, :func:`shaft_flexibility`)."""
    out = list(parsed)
    for name in dict.fromkeys(b.rotor for b in parsed):
        rotor = rotors[name]
        mates = [b for b in parsed if b.rotor == name]
        for bearing in _fixed_journals(mates, tables):
            journal = dataclasses.replace(bearing.coefficients.journal, fixed_load=True)
            coefficients = dataclasses.replace(bearing.coefficients, journal=journal)
            out[next(i for i, b in enumerate(out) if b is bearing)] = dataclasses.replace(bearing, coefficients=coefficients)
        mates = [b for b in out if b.rotor == name]
        if not _splits_over_speed(mates, rotor, tables):
            continue
        solved = [b for b in mates if "load" not in tables[b.name].data]
        journals = [b.coefficients.journal for b in solved]
        given_stations, given_loads = _given_loads(mates, rotor, tables, e, gravity)
        solver = dict(
            stations=[float((np.asarray(b.position) - np.asarray(rotor.center_of_mass)) @ e) for b in solved],
            weight=rotor.mass * _normal_part(gravity, e), spin_axis=e,
            diameter=[j.diameter for j in journals], length=[j.length for j in journals],
            clearance=[j.clearance for j in journals], viscosity=[j.viscosity for j in journals],
            pedestal_stiffness=[None if b.pedestal is None else b.pedestal.stiffness for b in solved],
            pedestal_weight=[None if b.pedestal is None else b.pedestal.mass * np.asarray(gravity, dtype=float)
                             for b in solved],
            cache={})
        if len(given_loads):
            solver["given_stations"], solver["given_loads"] = given_stations, given_loads
        if rotor.flexible is not None:
            order = solved + [b for b in mates if b not in solved]
            flexibility, sag = shaft_flexibility(rotor.flexible, [rotor.flexible.z_of(b.position) for b in order],
                                                 gravity)
            n = len(solved)       # the given loads bend the shaft too: a sag of -phi_ig F_g
            solver["flexibility"] = flexibility[:n, :n]
            solver["sag"] = sag[:n] - flexibility[:n, n:] @ given_loads
        for index, (bearing, journal) in enumerate(zip(solved, journals)):
            journal = dataclasses.replace(journal, load_over_speed=JournalLoadOverSpeed(index, solver))
            coefficients = dataclasses.replace(bearing.coefficients, journal=journal)
            place = next(i for i, b in enumerate(out) if b is bearing)
            out[place] = dataclasses.replace(bearing, coefficients=coefficients)
    return out


def journal_load_shares(weights, stations) -> np.ndarray:
    """Shares of a rigid rotor's weight carried by bearings that act as springs of stiffness
    proportional to ``weights``, at ``stations`` along its axis from its centre of mass.

    Plain journal bearings on one rotor at light load (small eccentricity) are such springs:
    the film holds the journal with ``k = pi viscosity |speed| D L**3 / (8 c**3)`` at 90 degrees
    to its offset, the same turn for every bearing of the rotor, so the split of the weight is
    that of a rigid beam on springs ``k_i`` whatever the speed (docs/static.md). The rigid
    rotor moves by ``u + theta s``; force and moment balance under a unit weight at ``s = 0``::

        [sum k, sum k s; sum k s, sum k s**2] [u, theta] = [1, 0],   share_i = k_i (u + theta s_i)

    Parameters
    ----------
    weights : sequence of float, shape (N,)
        Relative stiffness of each bearing [any unit], > 0.
    stations : sequence of float, shape (N,)
        Axial position of each bearing from the centre of mass [m].

    Returns
    -------
    ndarray, shape (N,)
        Fractions of the weight (sum 1; negative: the bearing holds the rotor down). Bearings
        all at one station share in proportion to ``weights`` (nothing then holds the tilt,
        which the validation refuses separately).
    """
    k, s = np.asarray(weights, dtype=float), np.asarray(stations, dtype=float)
    total, first, second = k.sum(), k @ s, k @ s**2
    determinant = total * second - first**2
    if not determinant > 1e-12 * total * second:
        return k / total
    u, theta = second / determinant, -first / determinant
    return k * (u + theta * s)


def _continuous_beam_load(bearing, table: Table, mates, rotor, gravity, tables) -> np.ndarray:
    """The load vector [N] on ``bearing``, one of three or more on a flexible rotor: the reaction
    of the shaft under its weight on supports at the journals (:func:`continuous_beam_loads`),
    rigid where the journal stands on the stator or the ground, elastic with the pedestal's
    stiffness where it stands on a pedestal (the film taken as rigid in both; the pedestal's own
    weight is carried by its springs, not by the journal, but settles the support)."""
    if not all(b.type == "journal" and b.moment_stiffness is None for b in mates):
        raise table.error("load", "<missing>", f"a static load [N]: rotor {rotor.name!r} has "
                          f"{len(mates)} bearings, so its weight split is statically indeterminate, "
                          "and not all are plain journal bearings without moment_stiffness (docs/static.md)")
    shaft = rotor.flexible
    loads = continuous_beam_loads(shaft, [shaft.z_of(b.position) for b in mates], gravity,
                                  [_film_weight(tables[b.name]) for b in mates],
                                  [None if b.pedestal is None else b.pedestal.stiffness for b in mates],
                                  [None if b.pedestal is None else b.pedestal.mass * np.asarray(gravity, dtype=float)
                                   for b in mates])
    load = loads[[b.name for b in mates].index(bearing.name)]
    weight = rotor.mass * np.linalg.norm(_normal_part(gravity, shaft.axis))
    if not np.linalg.norm(load) > _LEAST_SHARE * weight:
        raise table.error("load", "<missing>", f"a static load [N]: this bearing carries none of rotor "
                          f"{rotor.name!r}'s weight (the shaft on its journals' supports puts none on it)")
    return load


def continuous_beam_loads(shaft, stations, gravity, weights=None, supports=None, pedestal_loads=None,
                          point_loads=()) -> np.ndarray:
    """The loads a flexible shaft puts on supports at ``stations`` under its weight: the
    statically indeterminate continuous beam, solved on the shaft's finite elements.

    A support holds the two translations normal to the axis at its node and nothing else (no
    tilt, like a short journal): rigidly, or through a spring (a journal on a pedestal, the film
    taken as rigid: the pedestal's ``pedestal_stiffness``), which the pedestal's own weight loads
    too: the pedestal settles by ``k^-1 (R + m_p g)`` under the journal's load ``R`` and its
    weight, a settlement of the support that moves every reaction. The weight is the consistent load
    ``M g`` of the shaft, its disks and point masses; with cubic beam elements the reactions of
    point loads at nodes and of a uniform section's own weight are those of the beam theory
    exactly (on elastic supports too: the springs act at nodes).

    Parameters
    ----------
    shaft : Shaft
        A validated shaft (:class:`rotordyn_modal.model.flexible.Shaft`), meshed or not.
    stations : sequence of float, shape (N,)
        Axial positions of the supports from the shaft's start [m], N >= 2.
    gravity : array_like, shape (3,)
        [m/s^2], model axes.
    weights : sequence of float, shape (N,), optional
        How rigid supports at one node share its reaction (default: equally).
    supports : sequence of (ndarray, shape (3, 3), or None), shape (N,), optional
        Each support's stiffness [N/m], model axes, symmetric, acting on the node's translation
        normal to the axis (its part along the axis is ignored); None: rigid (the default for
        every support). At a node held rigidly by one support, its springs carry nothing (their
        pedestals hang on the shaft there).
    pedestal_loads : sequence of (array_like, shape (3,), or None), shape (N,), optional
        The weight [N], model axes, of each elastic support's pedestal (its part normal to the
        axis counts): a load on the spring, not on the support (None or omitted: none).
    point_loads : sequence of (float, array_like shape (3,))
        Further forces on the shaft beside its weight: the axial position from the shaft's start
        [m] and the force [N], model axes (its part normal to the axis counts); e.g. a journal's
        given load, pushing the shaft up with ``-load``.

    Returns
    -------
    ndarray, shape (N, 3)
        The force of the shaft on each support [N], model axes, normal to the axis (their sum is
        the weight's part normal to the axis; a component against gravity: the support holds
        the shaft down).
    """
    import scipy.sparse.linalg

    z = np.asarray(stations, dtype=float)
    springs = [None] * len(z) if supports is None else list(supports)
    mesh, M, K, T, g = _lateral_shaft(shaft, np.r_[z, [p for p, _ in point_loads]], gravity)
    force = T.T @ (M @ g)
    a, b = transverse_axes(shaft.axis)                          # lateral_basis's a, b
    ab = np.array([a, b])                                       # (2, 3)
    for place, load in point_loads:
        node = mesh.node(place)
        force[[4 * node, 4 * node + 1]] += ab @ np.asarray(load, dtype=float)
    nodes = np.array([mesh.node(s) for s in z])
    settling = [np.zeros(2) if w is None else ab @ np.asarray(w, dtype=float)
                for w in ([None] * len(z) if pedestal_loads is None else pedestal_loads)]
    for node, spring, weight in zip(nodes, springs, settling):
        if spring is not None:
            force[[4 * node, 4 * node + 1]] += weight           # on the pedestal, which moves with the node
    rigid = np.array([k is None for k in springs])
    lateral = [ab @ np.asarray(k, dtype=float) @ ab.T if k is not None else None for k in springs]
    stiffness = (T.T @ K @ T + _support_springs(nodes, lateral, 4 * mesh.n_nodes)).tocsc()
    held = np.unique(np.concatenate([4 * nodes[rigid], 4 * nodes[rigid] + 1])).astype(int)
    free = np.setdiff1d(np.arange(4 * mesh.n_nodes), held)
    q = np.zeros(4 * mesh.n_nodes)
    q[free] = scipy.sparse.linalg.spsolve(stiffness[free][:, free], force[free])
    on_support = force - stiffness @ q                           # the rigid supports' share of each held coordinate
    share = np.ones(len(z)) if weights is None else np.asarray(weights, dtype=float)
    out = np.zeros((len(z), 3))
    for i, node in enumerate(nodes):
        if rigid[i]:
            together = share[(nodes == node) & rigid]
            out[i] = share[i] / together.sum() * (on_support[4 * node] * a + on_support[4 * node + 1] * b)
        else:      # the spring's k u less the pedestal's weight (at a node held rigidly: the weight, hung on the shaft)
            out[i] = (lateral[i] @ q[[4 * node, 4 * node + 1]] - settling[i]) @ ab
    return out


def _lateral_shaft(shaft, stations, gravity):
    """The shaft meshed with a node at each of ``stations`` [m]: ``(mesh, M, K, T, g)``, its
    node mass and stiffness matrices (6 N, 6 N), the lateral basis ``T`` (6 N, 4 N) and gravity
    ``g`` [m/s^2] (6 N,) at every node's translations."""
    meshed = with_mesh(shaft, stations)
    mesh = meshed.mesh
    M, K = node_matrices(meshed, mesh, kinds=("M", "K"))
    T = lateral_basis(meshed)
    g = np.zeros(6 * mesh.n_nodes)
    g.reshape(-1, 6)[:, :3] = np.asarray(gravity, dtype=float)
    return mesh, M, K, T, g


def shaft_flexibility(shaft, stations, gravity):
    """A flexible shaft held rigidly at two of its journals (the first and the last along it): its
    deflection at every journal under a unit force at each (its flexibility) and under its weight
    (its sag), the journals holding the two translations normal to the axis and not the tilt.

    For loads in balance with the weight the free shaft bends as the shaft held there does (the
    two held journals' reactions being their loads), up to a rigid motion: what
    :func:`~rotordyn_modal.elements.journal_bearing.rigid_rotor_journal_loads` adds to a rigid
    rotor's journals. The weight is the consistent load ``M g`` of the shaft, its disks and point
    masses (as :func:`continuous_beam_loads`).

    Parameters
    ----------
    shaft : Shaft
    stations : sequence of float, shape (N,)
        The journals' axial positions from the shaft's start [m], at two nodes at least.
    gravity : array_like, shape (3,) [m/s^2]

    Returns
    -------
    flexibility : ndarray, shape (N, N) [m/N]
        ``phi_ik``: the deflection at journal ``i`` along a unit force at journal ``k`` (an
        axisymmetric shaft bends alike in every plane through its axis).
    sag : ndarray, shape (N, 3) [m]
        The deflection at each journal under the weight, model axes.
    """
    import scipy.sparse.linalg

    z = np.asarray(stations, dtype=float)
    mesh, M, K, T, g = _lateral_shaft(shaft, z, gravity)
    a, b = transverse_axes(shaft.axis)
    nodes = np.array([mesh.node(s) for s in z])
    held = np.array([nodes[int(np.argmin(z))], nodes[int(np.argmax(z))]])
    held = np.concatenate([4 * held, 4 * held + 1])
    free = np.setdiff1d(np.arange(4 * mesh.n_nodes), held)
    loads = np.zeros((4 * mesh.n_nodes, len(z) + 1))
    loads[4 * nodes, np.arange(len(z))] = 1.0                    # a unit force along a at each journal
    loads[:, -1] = T.T @ (M @ g)
    stiffness = (T.T @ K @ T).tocsc()[free][:, free]
    solved = np.zeros_like(loads)
    solved[free] = scipy.sparse.linalg.splu(stiffness).solve(loads[free])
    flexibility = solved[4 * nodes, :-1]
    sag = np.outer(solved[4 * nodes, -1], a) + np.outer(solved[4 * nodes + 1, -1], b)
    return flexibility, sag


def _support_springs(nodes, lateral, size: int):
    """The elastic supports' stiffness on the shaft's lateral coordinates, sparse (size, size):
    each 2x2 ``lateral`` [N/m] (None: a rigid support, nothing added) at its node's two
    translations (coordinates ``4 node``, ``4 node + 1``)."""
    import scipy.sparse

    added = [(4 * node + i, 4 * node + j, k[i, j]) for node, k in zip(nodes, lateral) if k is not None
             for i in range(2) for j in range(2)]
    rows, columns, values = zip(*added) if added else ((), (), ())
    return scipy.sparse.coo_matrix((values, (rows, columns)), shape=(size, size))


def _film_weight(table: Table) -> float:
    """``viscosity D L**3 / c**3`` of a journal bearing's table: its light-load film stiffness
    over ``pi |speed| / 8`` [Pa s m]."""
    values = [table.number(key, required=True, positive=True)
              for key in ("viscosity", "diameter", "length", "clearance")]
    return values[0] * values[1] * values[2]**3 / values[3]**3


def _check_tilt_support(rotor: str, mates, tables, e) -> None:
    """A rotor on bearings must be held in tilt: two bearing points, or a moment stiffness."""
    if any(b.moment_stiffness is not None for b in mates):
        return
    stations = {round(float(np.asarray(b.position) @ e), 12) for b in mates}
    if len(stations) < 2:
        table = tables[mates[0].name]
        raise table.error("moment_stiffness", "<missing>", f"a tilt stiffness [N m/rad]: rotor {rotor!r} "
                          "sits on bearings at a single point of its axis, so nothing holds it in tilt "
                          f"(add a second bearing elsewhere on the axis, or moment_stiffness){_far_hint(mates)}")


def _far_hint(mates) -> str:
    """Why bearings written apart may be one point: far from the origin, round-off."""
    far = max(float(np.abs(b.position).max()) for b in mates)
    spacing = float(np.spacing(far))
    if spacing <= POSITION_ROUND_OFF:
        return ""
    return (f"; at {far:.3g} m from the origin double precision rounds positions to {spacing:.2g} m: "
            "give positions near the machine, in metres")


def _check_held(rotor, mates, tables, e) -> None:
    """The bearings of a rotor together must hold it in each of its own coordinates (two lateral
    translations, two tilts, and the axial translation when a bearing gives axial_stiffness):
    their stiffness, moved to the rotor's centre of mass and taken on those motions, must be
    regular (at every row of a speed table). ``moment_stiffness = 0`` on a single bearing, or
    ``stiffness = 0`` on every bearing, leaves a motion that nothing holds.

    A journal bearing's film stiffness exists at speed only: such rotors are left to
    :func:`_check_tilt_support` (two bearing points) and the film's own checks.
    """
    if any(b.coefficients.kind == "journal" for b in mates):
        return
    motions = _relative_motions(e, axial=any(b.coefficients.axial for b in mates))
    moved = [shift_matrix(rotor.center_of_mass, b.position) for b in mates]
    rows = max(len(b.coefficients.stiffness) for b in mates)
    for row in range(rows):
        total = sum(s @ b.coefficients.stiffness[min(row, len(b.coefficients.stiffness) - 1)] @ s.T
                    for s, b in zip(moved, mates))
        free = _free_motion(motions.T @ total @ motions)
        if free is not None:
            raise _not_held(rotor, mates, tables, motions, free, row if rows > 1 else None,
                            _held_fraction(motions.T @ total @ motions))


def _relative_motions(e: np.ndarray, axial: bool) -> np.ndarray:
    """Columns: a rotor's own motions ``[u, theta]`` at its centre of mass, shape (6, 4 or 5)."""
    a, b = transverse_axes(e)
    zero = np.zeros(3)
    columns = [np.r_[a, zero], np.r_[b, zero]] + ([np.r_[e, zero]] if axial else []) \
        + [np.r_[zero, a], np.r_[zero, b]]
    return np.array(columns).T


def _free_motion(stiffness: np.ndarray):
    """The motion a (k, k) stiffness leaves free, shape (k,), in coordinates scaled by the
    stiffness's rows and columns (N/m beside N m/rad, short arms: only a stiffness singular to
    round-off counts, whatever the units), or None when it is regular."""
    size = np.sqrt(np.linalg.norm(stiffness, axis=0) * np.linalg.norm(stiffness, axis=1))
    if not (size > 0).all():
        return np.eye(len(size))[np.flatnonzero(~(size > 0))[0]]
    # D^-1/2 K D^-1/2 (unit diagonal): K / (size_i size_j) made the diagonal 1 / K_ii, so that a
    # stiff axial bearing beside soft radial ones read as the free motion (and a soft one as held)
    root = np.sqrt(size)
    _, values, vt = np.linalg.svd(stiffness / np.outer(root, root))
    return None if values[-1] > 1e-12 * values[0] else vt[-1]


def _held_fraction(stiffness: np.ndarray) -> float:
    """The smallest over the largest singular value of ``stiffness`` scaled as :func:`_free_motion`
    scales it: 0 where a motion is free, a tiny positive number where soft bearings hold it
    beside bearings stiffer by twelve decades and more."""
    size = np.sqrt(np.linalg.norm(stiffness, axis=0) * np.linalg.norm(stiffness, axis=1))
    if not (size > 0).all():
        return 0.0
    root = np.sqrt(size)
    values = np.linalg.svd(stiffness / np.outer(root, root), compute_uv=False)
    return float(values[-1] / values[0])


def _not_held(rotor, mates, tables, motions: np.ndarray, free: np.ndarray, row, fraction: float = 0.0) -> ModelError:
    """The refusal of a rotor that its bearings leave free in ``motions @ free`` (a tilt
    when the free motion turns the rotor at all, about some point of its axis); ``fraction``
    (:func:`_held_fraction`) above round-off says that it is held, too softly to be kept."""
    tilt = np.abs(free[-2:]).max() > 1e-8
    axis = motions[3:, -2:] @ free[-2:] if tilt else motions[:3, :-2] @ free[:-2]
    axis = axis / np.linalg.norm(axis)
    key = "moment_stiffness" if tilt else ("axial_stiffness" if _along_spin(axis, mates) else "stiffness")
    bearing = next((b for b in mates if key in tables[b.name].data), mates[0])
    table = tables[bearing.name]
    where = f" at speeds_rpm[{row}]" if row is not None else ""
    what = f"its {'tilt about' if tilt else 'translation along'} {_axis_text(axis)}"
    if fraction > 1e-15:   # held, by bearings twelve decades softer than others: not 'nothing holds'
        stiffness = [float(np.abs(b.coefficients.stiffness).max()) for b in mates]
        return table.error(key, table.data.get(key, "<missing>"),
                           f"bearings that hold rotor {rotor.name!r} in each of its motions within what double "
                           f"precision keeps: {what}{where} is held only {fraction:.3g} as stiffly as its stiffest "
                           f"motion (their stiffness, moved to its centre of mass, scaled), below 1e-12: bearings "
                           f"of {min(stiffness):.3g} to {max(stiffness):.3g} N/m on one rotor (a value in other units?)")
    return table.error(key, table.data.get(key, "<missing>"),
                       f"bearings that together hold rotor {rotor.name!r} in each of its motions: nothing "
                       f"holds {what}{where} (their stiffness, moved to its centre of mass, is singular; "
                       "give a non-zero value, a second bearing elsewhere on its axis, or moment_stiffness)")


def _along_spin(axis, mates) -> bool:
    e = np.cross(mates[0].axes[0], mates[0].axes[1])
    return abs(float(np.asarray(axis) @ e)) > 0.5


def _axis_text(axis) -> str:
    """``'the y axis'`` for a model axis, else the direction's components."""
    axis = np.asarray(axis, dtype=float)
    k = int(np.argmax(np.abs(axis)))
    if abs(abs(axis[k]) - 1.0) < 1e-12:
        return f"the {'xyz'[k]} axis"
    return "the direction " + _fmt(axis)


# ----------------------------------------------------------------------------------------
def check_frame(top: Table, stator, suspensions, bearings, sensors, excitations) -> None:
    """Without a ``[stator]``, bearings go to the ground: nothing may stand on the stator."""
    if stator is not None or not bearings:
        return
    if suspensions:
        raise top.error("suspensions", [s.name for s in suspensions], "no [[suspensions]]: without a "
                        "[stator] the [[bearings]] connect the rotors to the ground (add a [stator] "
                        "to put the machine on mounts)")
    for kind, items in (("sensors", sensors), ("excitations", excitations)):
        for item in items:
            if item.rotor is None:
                raise ModelError(top.source, f"[{kind}.{visible(item.name)}] rotor", "<missing>",
                                 "the name of a rotor: without a [stator] the [[bearings]] are fixed to "
                                 "the ground, so a point of the stator does not move")


def _fmt(values) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"
