"""Validation rules of a model description, one small function per table.

Each function takes the raw table (plain Python values, as TOML gives them)
and returns the validated component with numpy arrays, or raises
:class:`~rotordyn_modal.errors.ModelError` naming source, table, key, value and
what was expected.
"""

from __future__ import annotations

import dataclasses
import math
import unicodedata
from collections import deque
from typing import Any, Mapping

import numpy as np

from ..errors import ModelError
from ..unbalance_standards import BALANCE_GRADES, balance_grade, permissible_unbalance
from ..elements import _bearing_validation
from ..elements._mount_validation import suspension as _suspension
from . import flexible as _flexible
from .geometry import gear_mesh
from ._table import SMALLEST_POSITIVE, Table as _Table, magnitude_problem, plain, visible, visible_names
from .components import (
    ARRAY_TABLES, TOP_LEVEL_KEYS, Clearance, Excitation, Rotor, Sensor, Stator, Transmission,
    Unbalance, input_keys,
)

_RATIO_TOLERANCE = 1e-9
#: largest ratio of a rigid body's principal moments of inertia (a thin rod has about 1e5)
_PRINCIPAL_RATIO = 1e12


# ----------------------------------------------------------------------------------------
def plain_copy(data: Mapping[str, Any], source: str) -> dict[str, Any]:
    """A deep copy of the description with numpy arrays turned into lists."""
    if not isinstance(data, Mapping):
        raise ModelError(source, "<model>", type(data).__name__, "a table of keys (a mapping)")
    return plain(data)


def validate(data: dict[str, Any], source: str, previous=None) -> dict[str, Any]:
    """Validate a whole description; returns the validated parts by table name.

    Parameters
    ----------
    data : dict
        The description (plain Python values).
    source : str
        Where it came from, for messages.
    previous : tuple (dict, dict), optional
        The description and validated parts of an earlier model that ``data`` was made from
        by replacing some of its tables with changed copies (a study's variant of its base
        model). A table that *is* (the same object) the earlier one, in the same context,
        takes its earlier validated part: it passed every rule then and would give the same
        part again. Changed tables and the rules across tables are checked as usual.
    """
    reuse = _Reuse(previous)
    top = _Table(source, "", data)
    _check_layout(top, data)
    spin_axis, name = _spin_axis_and_name(top, data)
    stator = None
    if "stator" in data:
        stator = reuse.part("stator", None, data["stator"]) or _stator(source, data["stator"])
    materials = _flexible.materials(source, data)
    rotor_tables = _named_tables(source, data, "rotors")
    if not rotor_tables and stator is None:
        raise top.error("rotors", [], "at least one [[rotors]] table or a [stator] table")
    names_kept = reuse.same_names(rotor_tables)   # what references to rotors are checked against
    reference = _reference_rotor(top, rotor_tables)
    transmission_tables = _indexed_tables(source, data, "transmissions")
    transmissions = [reuse.part("transmissions", i, t.data, names_kept) or _transmission(t, rotor_tables)
                     for i, t in enumerate(transmission_tables)]
    _check_mesh_names(transmission_tables, transmissions, rotor_tables)
    ratios = _speed_ratios(source, rotor_tables, transmissions, reference)
    flexible_kept = reuse.same_list(data, "materials") and reuse.same_axis(spin_axis)
    rotors = [reuse.rotor(i, t.data, ratios[name], flexible_kept or "shaft" not in t.data)
              or _rotor(t, ratios[name], materials, spin_axis)
              for i, (name, t) in enumerate(rotor_tables.items())]
    suspension_tables = _named_tables(source, data, "suspensions")
    suspensions = [_suspension(t, reuse.earlier("suspensions", i)) for i, t in enumerate(suspension_tables.values())]
    shafts = {r.name: r.flexible for r in rotors if r.flexible is not None}
    unbalance_tables = _indexed_tables(source, data, "unbalances")
    # an unbalance given by a balance grade follows its rotor's mass: earlier only with the same rotors
    unbalances = [reuse.part("unbalances", i, t.data, names_kept and not shafts and (
                      "grade" not in t.data or reuse.same_list(data, "rotors")))
                  or _unbalance(t, rotor_tables, rotors)
                  for i, t in enumerate(unbalance_tables)]
    unbalances = [_flexible_unbalance(t, u, rotors) for t, u in zip(unbalance_tables, unbalances)]
    _check_eccentricities(unbalance_tables, unbalances, rotors)
    gravity = top.vector3("gravity", default=[0.0, 0.0, 0.0])
    _check_gravity(source, gravity)
    bearing_tables = _named_tables(source, data, "bearings")
    sensor_tables = _named_tables(source, data, "sensors")
    _check_force_names(rotor_tables, suspension_tables, bearing_tables, sensor_tables)
    bearings = reuse.bearings(data, rotors, spin_axis, gravity)
    if bearings is None:
        bearings = _bearing_validation.bearings(bearing_tables, rotors, spin_axis, gravity)
        _bearing_validation.warn_transmitted_loads(bearing_tables, bearings, transmissions)
    on_bearings = {b.rotor for b in bearings}
    sensors = [reuse.part("sensors", i, t.data, names_kept and reuse.same_carriers(bearings) and not shafts)
               or _sensor(t, rotor_tables, on_bearings, shafts)
               for i, t in enumerate(sensor_tables.values())]
    _no_axial_probe_reading_zero(sensor_tables, sensors, bearings, spin_axis)
    excitations = [reuse.part("excitations", i, t.data, names_kept and not shafts)
                   or _excitation(t, rotor_tables, shafts)
                   for i, t in enumerate(_named_tables(source, data, "excitations").values())]
    _bearing_validation.check_frame(top, stator, suspensions, bearings, sensors, excitations)
    clearances = _clearances(rotor_tables, rotors, on_bearings, np.asarray(spin_axis, dtype=float))
    _check_meshes(transmission_tables, transmissions, rotors, spin_axis)
    rotors = _meshed(top, rotors, bearings, unbalances, sensors, excitations, clearances, transmissions)
    return {
        "name": name, "spin_axis": spin_axis, "reference_rotor": reference, "gravity": gravity,
        "stator": stator, "rotors": tuple(rotors), "transmissions": tuple(transmissions),
        "suspensions": tuple(suspensions), "bearings": tuple(bearings),
        "unbalances": tuple(unbalances),
        "sensors": tuple(sensors), "excitations": tuple(excitations), "clearances": clearances,
    }


def _identical(a: np.ndarray, b: np.ndarray) -> bool:
    """The same numbers bit for bit (``-0.0`` is not ``0.0`` here: a sign can reach a result)."""
    return a.shape == b.shape and a.tobytes() == b.tobytes()


class _Reuse:
    """The validated parts of an earlier description, for the tables ``data`` shares with it
    (see :func:`validate`'s ``previous``). Every question answers None or False without one."""

    def __init__(self, previous):
        self.raw, self.parts = previous if previous is not None else ({}, {})

    def earlier(self, key: str, index):
        """``(raw table, validated part)`` of the earlier table at ``index`` of array ``key``
        (``index`` None: the table ``key``), or None."""
        raw = self.raw.get(key)
        if index is not None:
            if not isinstance(raw, list) or index >= len(raw):
                return None
            return raw[index], self.parts[key][index]
        return None if raw is None else (raw, self.parts[key])

    def part(self, key: str, index, raw, context: bool = True):
        """The earlier validated part when ``raw`` is the earlier table and ``context`` holds."""
        earlier = self.earlier(key, index) if context else None
        return earlier[1] if earlier is not None and earlier[0] is raw else None

    def rotor(self, index: int, raw, ratio: float, context: bool = True):
        """The earlier rotor when its table is shared and its speed ratio unchanged (and, for a
        flexible rotor, the materials too: ``context``)."""
        part = self.part("rotors", index, raw, context)
        return part if part is not None and part.speed_ratio == ratio else None

    def same_names(self, rotor_tables) -> bool:
        """The rotors have the earlier names, in the earlier order."""
        return bool(self.raw) and list(rotor_tables) == [r.name for r in self.parts["rotors"]]

    def same_list(self, data, key: str) -> bool:
        """Every table of array ``key`` is the earlier one (same count, same objects)."""
        mine, earlier = data.get(key, []), self.raw.get(key, [])
        return bool(self.raw) and len(mine) == len(earlier) and all(a is b for a, b in zip(mine, earlier))

    def bearings(self, data, rotors, spin_axis, gravity):
        """The earlier bearings when their tables, the rotors, spin axis and gravity are unchanged."""
        if not self.same_list(data, "bearings") or not self.same_list(data, "rotors"):
            return None
        if any(a is not b for a, b in zip(rotors, self.parts["rotors"])):
            return None
        if not (_identical(spin_axis, self.parts["spin_axis"]) and _identical(gravity, self.parts["gravity"])):
            return None
        return list(self.parts["bearings"])

    def same_axis(self, spin_axis) -> bool:
        """The earlier spin axis, bit for bit (a flexible rotor's shaft runs along it)."""
        return bool(self.raw) and _identical(spin_axis, self.parts["spin_axis"])

    def same_carriers(self, bearings) -> bool:
        """The same rotors sit on bearings as before (what a relative sensor needs)."""
        return {b.rotor for b in bearings} == {b.rotor for b in self.parts.get("bearings", ())}


def _check_layout(top: _Table, data) -> None:
    """Known top-level keys, arrays of tables where arrays are expected, ``[stator]`` a table."""
    top.check_keys(TOP_LEVEL_KEYS)
    for key in ARRAY_TABLES:
        value = data.get(key, [])
        if not isinstance(value, list) or not all(type(v) is dict or isinstance(v, Mapping) for v in value):
            raise top.error(key, value, f"an array of tables ([[{key}]])")
    if "stator" in data and not isinstance(data["stator"], Mapping):
        raise top.error("stator", data["stator"], "a table ([stator])")


def _spin_axis_and_name(top: _Table, data) -> tuple[np.ndarray, str]:
    """The unit spin axis (default x) and the model's name (default empty)."""
    spin_axis = top.vector3("spin_axis", default=[1.0, 0.0, 0.0], nonzero=True)
    name = data.get("name", "")
    if not isinstance(name, str):
        raise top.error("name", name, "a string")
    return spin_axis / np.linalg.norm(spin_axis), name


def _named_tables(source: str, data, key: str) -> dict[str, _Table]:
    """The tables of an array, by their unique ``name``."""
    tables: dict[str, _Table] = {}
    normal: dict[str, str] = {}      # NFC form -> the name as written
    for index, raw in enumerate(data.get(key, [])):
        label = f"{key}[{index}]"
        name = _Table(source, label, raw).text("name", required=True)
        if name in tables:
            raise _Table(source, label, raw).error("name", name, f"a name unique among the [[{key}]]")
        if key == "rotors" and name == "stator":   # --force stator:..., the tables' body column: the casing
            raise _Table(source, label, raw).error("name", name, "a rotor name other than 'stator', which names "
                                                   "the casing in options (--force stator:...) and tables")
        twin = normal.get(unicodedata.normalize("NFC", name))
        if twin is not None:   # 'café' typed precomposed and decomposed: two names that read the same
            codes = [text.encode("unicode_escape").decode() for text in (twin, name)]
            raise _Table(source, label, raw).error("name", name, f"a name unique among the [[{key}]]: it reads as "
                                                   f"{visible(twin)} ({codes[0]} against {codes[1]}: the same "
                                                   "letters written with other Unicode code points)")
        normal[unicodedata.normalize("NFC", name)] = name
        tables[name] = _Table(source, f"{key}.{visible(name)}", raw)
    return tables


#: the components of a force row's name, ``NAME:Fx`` ... ``NAME:Mz`` (``analysis.forces``)
_FORCE_COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def _check_force_names(rotor_tables, suspension_tables, bearing_tables, sensor_tables) -> None:
    """The force rows of ``frf``/``unbalance --forces`` are named ``NAME:Fx`` ... ``NAME:Mz`` by
    suspension, bearing and rotor alike, in the same ``output`` column as the sensors: a bearing
    called as its rotor or as a suspension gave two different forces one name (``--forces all``:
    two series ``fan:Fx``), and a sensor called ``mount-FL:Fz`` would read as that force. So these
    names are unique across the three arrays, and no sensor takes a force row's name."""
    owners: dict[str, str] = {}
    for key, tables in (("rotors", rotor_tables), ("suspensions", suspension_tables), ("bearings", bearing_tables)):
        for name, table in tables.items():
            other = owners.get(unicodedata.normalize("NFC", name))
            if other is not None:
                raise table.error("name", name, f"a name that no [[{other}]] table has: the force rows of "
                                  f"--forces (NAME:Fx ... NAME:Mz) would give the {key[:-1]}'s force and the "
                                  f"{other[:-1]}'s the same name (rename one)")
            owners[unicodedata.normalize("NFC", name)] = key
    for name, table in sensor_tables.items():
        item, _, component = unicodedata.normalize("NFC", name).rpartition(":")
        if component in _FORCE_COMPONENTS and item in owners:
            raise table.error("name", name, f"a sensor name other than a force row's of --forces (the "
                              f"{owners[item][:-1]} {visible(item)}'s {component}; rename the sensor)")


def _indexed_tables(source: str, data, key: str) -> list[_Table]:
    return [_Table(source, f"{key}[{i}]", raw) for i, raw in enumerate(data.get(key, []))]


def _reference_rotor(top: _Table, rotor_tables: Mapping[str, _Table]) -> str | None:
    if not rotor_tables:
        if "reference_rotor" in top.data:
            raise top.error("reference_rotor", top.data["reference_rotor"], "no reference rotor: the model has no rotors")
        return None
    if "reference_rotor" not in top.data:
        if len(rotor_tables) == 1:
            return next(iter(rotor_tables))
        raise top.error("reference_rotor", "<missing>", "the name of one of the rotors "
                        + visible_names(rotor_tables) + " (required with several rotors)")
    return top.name_of("reference_rotor", rotor_tables, "rotors")


# ----------------------------------------------------------------------------------------
def _inertia_tensor(table: _Table, key: str) -> np.ndarray:
    value = table.array(key, [(3,), (3, 3)], required=True)
    tensor = np.diag(value) if value.shape == (3,) else value
    scale = max(np.abs(tensor).max(), 1e-300)
    if np.abs(tensor - tensor.T).max() > 1e-9 * scale:
        raise table.error(key, table.data[key], "a symmetric tensor")
    tensor = 0.5 * (tensor + tensor.T)
    principal = np.linalg.eigvalsh(tensor)
    if not principal[0] >= SMALLEST_POSITIVE:
        raise table.error(key, table.data[key], "a positive definite tensor (principal moments "
                          f"{_fmt(principal)} must all be >= {SMALLEST_POSITIVE:g})")
    if principal[-1] > _PRINCIPAL_RATIO * principal[0]:
        raise table.error(key, table.data[key], f"principal moments within a ratio of {_PRINCIPAL_RATIO:g} "
                          f"(got {_fmt(principal)}; rounding would leave the mass matrix singular)")
    total = principal.sum()
    if np.any(principal > total - principal + 1e-9 * total):
        raise table.error(key, table.data[key], "principal moments that satisfy the triangle "
                          f"inequality (each <= sum of the other two; got {_fmt(principal)})")
    return tensor


def _fmt(values) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"


def _stator(source: str, raw) -> Stator:
    table = _Table(source, "stator", raw)
    table.check_keys(input_keys("stator"))
    return Stator(
        mass=table.number("mass", required=True, positive=True),
        inertia=_inertia_tensor(table, "inertia"),
        center_of_mass=table.vector3("center_of_mass", default=[0.0, 0.0, 0.0]),
    )


def _rotor(table: _Table, ratio: float, materials=None, spin_axis=None) -> Rotor:
    table.check_keys(input_keys("rotors"))
    if "shaft" in table.data:
        return _flexible_rotor(table, ratio, materials or {}, spin_axis)
    for key in _flexible.SHAFT_KEYS:
        if key in table.data:
            raise table.error(key, table.data[key], "no value on a rigid rotor (a rotor with a [[rotors.shaft]] "
                              "is flexible; only then does it take disks, point_masses, start, shear, element_length, "
                              "coupling_position)")
    polar = table.number("polar_inertia", required=True, positive=True)
    diametral = table.number("diametral_inertia", required=True, positive=True)
    if polar > 2.0 * diametral * (1 + 1e-12):
        raise table.error("polar_inertia", polar, f"at most twice diametral_inertia = {diametral:g} "
                          "(triangle inequality of a rigid body's principal moments)")
    if diametral > _PRINCIPAL_RATIO * polar:
        raise table.error("diametral_inertia", diametral, f"at most {_PRINCIPAL_RATIO:g} times polar_inertia "
                          f"= {polar:g} (rounding would leave the mass matrix singular)")
    return Rotor(
        name=table.data["name"],
        mass=table.number("mass", required=True, positive=True),
        center_of_mass=table.vector3("center_of_mass", required=True),
        polar_inertia=polar,
        diametral_inertia=diametral,
        speed_ratio=ratio,
    )


def _flexible_rotor(table: _Table, ratio: float, materials, spin_axis) -> Rotor:
    """A rotor with a shaft: its mass, centre and inertias computed (and any given checked)."""
    shaft = _flexible.shaft(table, materials, spin_axis)
    mass, centre, polar, diametral = _flexible.mass_properties(shaft)
    _flexible.check_consistent(table, {"mass": mass, "center_of_mass": centre, "polar_inertia": polar,
                                       "diametral_inertia": diametral, "_length": shaft.length})
    keys = {k: table.data[k] for k in _flexible.SHAFT_KEYS if k in table.data}
    if "coupling_position" in table.data:      # [m] from the start: where the coupling holds the spin
        keys["coupling_position"] = table.number("coupling_position")
        _flexible._check_on_shaft(table, "coupling_position", keys["coupling_position"], shaft.length)
        keys["coupling_position"] = min(max(keys["coupling_position"], 0.0), shaft.length)
    return Rotor(name=table.data["name"], mass=mass, center_of_mass=centre, polar_inertia=polar,
                 diametral_inertia=diametral, speed_ratio=ratio, **keys, flexible=shaft)


def _flexible_unbalance(table: _Table, unbalance: Unbalance, rotors) -> Unbalance:
    """An unbalance with its station: on a flexible rotor ``axial_position`` (from the shaft's
    start) or ``axial_offset`` (from the centre of mass) places it on the shaft, and
    ``axial_offset`` is made the one from the centre of mass; a rigid rotor takes no
    ``axial_position``."""
    rotor = next(r for r in rotors if r.name == unbalance.rotor)
    shaft = rotor.flexible
    if shaft is None:
        if "axial_position" in table.data:
            raise table.error("axial_position", table.data["axial_position"], "no value: axial_position places "
                              "an unbalance on a flexible rotor (on a rigid rotor use axial_offset)")
        return unbalance
    centre = shaft.z_of(rotor.center_of_mass)
    if "axial_position" in table.data:
        if "axial_offset" in table.data:
            raise table.error("axial_position", table.data["axial_position"], "either axial_offset or "
                              "axial_position, not both")
        _, z = _flexible.station_z(table, shaft, rotor.name, key="axial_position")
    else:
        z = centre + unbalance.axial_offset
        _flexible._check_on_shaft(table, "axial_offset", z, shaft.length, centre=centre)
    return dataclasses.replace(unbalance, axial_offset=z - centre)


def _meshed(top: _Table, rotors, bearings, unbalances, sensors, excitations, clearances=(), transmissions=()):
    """The rotors, each flexible one with its mesh: a node at every station of the model on it
    (a gear with a mesh stiffness or damping: its plane)."""
    out = []
    for rotor in rotors:
        shaft = rotor.flexible
        if shaft is None:
            out.append(rotor)
            continue
        mine = [b for b in bearings if b.rotor == rotor.name]
        if not mine:
            raise _Table(top.source, f"rotors.{visible(rotor.name)}", {}).error(
                "shaft", "[[rotors.shaft]]", "[[bearings]] carrying this rotor: a flexible rotor needs bearings "
                "(one welded to the stator would be a rigid part of it; give it no shaft, or bearings)")
        centre = shaft.z_of(rotor.center_of_mass)
        # (label, z): a station moved to another's node is named in a warning (flexible.merge_lines)
        stations = [(f"bearing {visible(b.name)!r}", shaft.z_of(b.position)) for b in mine]
        stations += [(f"unbalance {i}", centre + u.axial_offset) for i, u in enumerate(unbalances)
                     if u.rotor == rotor.name]
        stations += [(f"{kind} {visible(x.name)!r}", shaft.z_of(x.position))
                     for kind, group in (("sensor", sensors), ("excitation", excitations)) for x in group
                     if x.rotor == rotor.name and x.position is not None]
        stations += [(f"clearance {visible(c.name)!r}", c.axial_position) for c in clearances if c.rotor == rotor.name]
        stations += [("coupling_position", rotor.coupling_position)] if rotor.coupling_position is not None else []
        stations += [(f"the gear mesh {visible(t.driver)} -> {visible(t.driven)}", shaft.z_of(_gear_plane(t, rotors)))
                     for t in transmissions if rotor.name in (t.driver, t.driven) and _has_mesh(t)]
        meshed = _flexible.with_mesh(shaft, stations)
        if meshed.mesh.n_nodes > _flexible.MAX_NODES:
            raise _Table(top.source, f"rotors.{visible(rotor.name)}", {}).error(
                "element_length", shaft.element_length, f"a mesh of at most {_flexible.MAX_NODES} nodes with the "
                f"model's stations (it would have {meshed.mesh.n_nodes}: give a longer element_length; "
                f"{_flexible._dense_size(meshed.mesh.n_nodes)})")
        if shaft.mesh is not None and np.array_equal(shaft.mesh.z, meshed.mesh.z):
            out.append(rotor)            # a study's variant: the same rotor, the same mesh
        else:
            out.append(dataclasses.replace(rotor, flexible=meshed))
    return out


def _has_mesh(t) -> bool:
    """A gear with a mesh stiffness or damping."""
    return t.mesh_stiffness is not None or t.mesh_damping is not None


def _gear_plane(t, rotors):
    """A point of a gear's plane: its ``position``, else the driver's centre of mass."""
    return t.position if t.position is not None else next(r.center_of_mass for r in rotors if r.name == t.driver)


_CLEARANCE_KEYS = ("name", "position", "axial_position", "radial_clearance")


def _clearances(rotor_tables, rotors, on_bearings, spin_axis) -> tuple:
    """The ``[[rotors.clearances]]`` of every rotor (close-clearance stations), validated:
    a name unique in the model, a radial clearance > 0, a point on the rotor's axis (on a
    flexible rotor a station of its shaft), a rotor on bearings."""
    out, names = [], set()
    for rotor in rotors:
        table = rotor_tables[rotor.name]
        raws = table.data.get("clearances", [])
        if not isinstance(raws, list) or not all(isinstance(item, dict) for item in raws):
            raise table.error("clearances", raws, "an array of tables ([[rotors.clearances]])")
        for i, raw in enumerate(raws):
            item = _Table(table.source, f"{table.label}.clearances.{visible(raw.get('name', i))}", raw)
            out.append(_clearance(item, rotor, on_bearings, spin_axis))
            if out[-1].name in names:
                raise item.error("name", out[-1].name, "a name unique among the model's [[rotors.clearances]]")
            names.add(out[-1].name)
    return tuple(out)


def _clearance(table: _Table, rotor, on_bearings, spin_axis) -> Clearance:
    table.check_keys(_CLEARANCE_KEYS)
    name = table.text("name", required=True)
    radial = table.number("radial_clearance", required=True, positive=True)
    if rotor.name not in on_bearings:
        raise table.error("radial_clearance", radial, f"a clearance on a rotor on [[bearings]]: rotor "
                          f"{visible(rotor.name)!r} is rigidly attached to the stator, nothing moves in its clearance")
    shaft = rotor.flexible
    if shaft is not None:
        point, z = _flexible.station_z(table, shaft, rotor.name)
        return Clearance(name, rotor.name, point, radial, z)
    if "axial_position" in table.data:
        raise table.error("axial_position", table.data["axial_position"], "no value: axial_position places a "
                          "clearance on a flexible rotor (on a rigid rotor give position, a point on its axis)")
    point = table.vector3("position", required=True)
    centre = np.asarray(rotor.center_of_mass, dtype=float)
    offset = float((point - centre) @ spin_axis)
    off = float(np.linalg.norm(point - centre - offset * spin_axis))
    if off > _flexible.STATION_TOLERANCE * (1.0 + abs(offset)):
        raise table.error("position", table.data["position"], f"a point on the axis of rotor {visible(rotor.name)!r} "
                          f"(the line through its centre of mass along spin_axis); this point is {off:.4g} m off it")
    return Clearance(name, rotor.name, centre + offset * spin_axis, radial)


def _transmission(table: _Table, rotor_tables) -> Transmission:
    table.check_keys(input_keys("transmissions"))
    kind = table.text("type", required=True, choices=("gear", "belt"))
    names = []
    for key in ("driver", "driven"):
        names.append(table.name_of(key, rotor_tables, "rotors", required=True))
    if names[0] == names[1]:
        raise table.error("driven", names[1], "a rotor other than the driver")
    teeth = table.data.get("driver_teeth")
    if teeth is not None and (isinstance(teeth, bool) or not isinstance(teeth, int) or teeth < 1):
        raise table.error("driver_teeth", teeth, "a whole number >= 1")
    return Transmission(type=kind, driver=names[0], driven=names[1],
                        ratio=table.number("ratio", required=True, positive=True), driver_teeth=teeth,
                        **_transmission_geometry(table, kind))


#: largest gear pressure angle [deg] accepted (standard ones are 14.5, 20 and 25)
_MAX_PRESSURE_ANGLE = 45.0


def _transmission_geometry(table: _Table, kind: str) -> dict:
    """The optional keys of a transmission's static loads (docs/model-file.md), checked."""
    for key, owner in (("pressure_angle", "gear"), ("pretension", "belt"), ("mesh_stiffness", "gear"),
                       ("mesh_damping", "gear")):
        if key in table.data and kind != owner:
            raise table.error(key, table.data[key], f"no value: this key is for type = '{owner}' transmissions")
    angle = table.number("pressure_angle", nonnegative=True)
    if angle is not None and not angle < _MAX_PRESSURE_ANGLE:
        raise table.error("pressure_angle", angle, f"a pressure angle in degrees, at least 0 and below "
                          f"{_MAX_PRESSURE_ANGLE:g} (20 is standard)")
    return {"position": table.vector3("position"),
            "driver_radius": table.number("driver_radius", positive=True),
            "pressure_angle": angle, "pretension": table.number("pretension", nonnegative=True),
            "mesh_stiffness": table.number("mesh_stiffness", positive=True),
            "mesh_damping": table.number("mesh_damping", nonnegative=True)}


def _check_meshes(tables, transmissions, rotors, spin_axis) -> None:
    """A gear with a mesh stiffness or damping needs its line of action: two spin axes apart,
    a pitch radius below their distance, and its plane on each flexible rotor's shaft."""
    by_name = {r.name: r for r in rotors}
    for table, t in zip(tables, transmissions):
        if not _has_mesh(t):
            continue
        mesh = gear_mesh(t, by_name[t.driver], by_name[t.driven], spin_axis)
        if mesh is None:
            key = "mesh_stiffness" if t.mesh_stiffness is not None else "mesh_damping"
            raise table.error(key, getattr(t, key), "a gear between rotors whose spin axes are apart (the "
                              "driver's and the driven rotor's axes coincide: no line of centres)")
        if not mesh.radius < mesh.distance:
            raise table.error("driver_radius", t.driver_radius, f"a pitch radius below the centre distance "
                              f"{mesh.distance:g} m of the two spin axes")
        for name, centre in ((t.driver, mesh.driver_centre), (t.driven, mesh.driven_centre)):
            shaft = by_name[name].flexible
            if shaft is not None and not -1e-9 <= shaft.z_of(centre) <= shaft.length + 1e-9:
                raise table.error("position", table.data.get("position", "<missing>"),
                                  f"a gear plane on rotor {visible(name)!r}'s shaft (0 .. {shaft.length:g} m "
                                  f"from its start; it is at {shaft.z_of(centre):g} m)")


def mesh_name(driver: str, driver_teeth, driven: str) -> str | None:
    """The excitation source of a gear mesh, ``mesh:DRIVER-DRIVEN`` (None without
    ``driver_teeth``): how Campbell diagrams, critical speeds and studies name it."""
    return f"mesh:{driver}-{driven}" if driver_teeth else None


def _check_mesh_names(tables, transmissions, rotor_tables) -> None:
    """Each gear mesh's source name must name it alone: rotors ``a-b`` and ``c`` and rotors
    ``a`` and ``b-c`` would give two meshes ``mesh:a-b-c``; a rotor called ``mesh:a-b`` would
    be taken for the mesh a->b."""
    seen: dict[str, Transmission] = {}
    for table, t in zip(tables, transmissions):
        name = mesh_name(t.driver, t.driver_teeth, t.driven)
        if name is None:
            continue
        if name in rotor_tables:
            raise table.error("driver_teeth", t.driver_teeth, f"a mesh whose source name {name!r} is not "
                              "also a rotor's name (rename the rotor: excitation sources are named by "
                              "rotor and mesh:DRIVER-DRIVEN)")
        if name in seen:
            other = seen[name]
            raise table.error("driven", t.driven, f"rotor names that tell the gear meshes apart: the mesh "
                              f"{visible(t.driver)} -> {visible(t.driven)} and the mesh {visible(other.driver)} "
                              f"-> {visible(other.driven)} would both be the excitation source {name!r} "
                              "(rename a rotor, e.g. without '-')")
        seen[name] = t


def _speed_ratios(source: str, rotor_tables: Mapping[str, _Table], transmissions, reference) -> dict[str, float]:
    """Resolve every rotor's speed ratio from ``speed_ratio`` keys and the transmission graph.

    Each rotor must be fixed by at least one route; routes that disagree are refused.
    """
    fixed: dict[str, tuple[float, str]] = {}
    queue: deque[str] = deque()

    def fix(name: str, ratio: float, route: str, table: _Table, key: str):
        if name in fixed:
            known, known_route = fixed[name]
            if not math.isclose(known, ratio, rel_tol=_RATIO_TOLERANCE, abs_tol=1e-300):
                raise table.error(key, table.data.get(key), f"a value consistent with {known_route}, "
                                  f"which fixes the speed ratio of {name!r} to {known:.10g} (this "
                                  f"route gives {ratio:.10g})")
            return
        fixed[name] = (ratio, route)
        queue.append(name)

    if reference is not None:
        fix(reference, 1.0, "the reference rotor (ratio 1)", rotor_tables[reference], "speed_ratio")
    for name, table in rotor_tables.items():
        if "speed_ratio" in table.data:
            fix(name, table.number("speed_ratio"), f"[rotors.{visible(name)}] speed_ratio", table, "speed_ratio")
    edges: dict[str, list[tuple[str, float, Transmission]]] = {name: [] for name in rotor_tables}
    for t in transmissions:
        factor = t.direction_sign / t.ratio  # omega_driven = factor * omega_driver
        edges[t.driver].append((t.driven, factor, t))
        edges[t.driven].append((t.driver, 1.0 / factor, t))
    while queue:
        name = queue.popleft()
        ratio = fixed[name][0]
        for other, factor, t in edges[name]:
            route = f"the {t.type} {visible(t.driver)}->{visible(t.driven)}"
            fix(other, ratio * factor, route, _Table(source, f"transmissions {visible(t.driver)}->{visible(t.driven)}",
                                                     {"ratio": t.ratio}), "ratio")
    for name, table in rotor_tables.items():
        if name not in fixed:
            raise table.error("speed_ratio", "<missing>", "a speed ratio: neither speed_ratio nor a "
                              "chain of [[transmissions]] from the reference rotor fixes this rotor's speed")
    return {name: value for name, (value, _) in fixed.items()}


def _unbalance(table: _Table, rotor_tables, rotors) -> Unbalance:
    table.check_keys(input_keys("unbalances"))
    rotor = table.name_of("rotor", rotor_tables, "rotors", required=True)
    common = {"rotor": rotor, "phase_deg": table.number("phase_deg", default=0.0),
              "axial_offset": table.number("axial_offset", default=0.0)}
    if "grade" not in table.data:
        for key in ("service_speed_rpm", "mass"):
            if key in table.data:
                raise table.error(key, table.data[key], "no such key without grade (it sets the amount "
                                  "of an ISO 21940-11 balance grade)")
        return Unbalance(amount=table.number("amount", required=True, positive=True), **common)
    return _graded_unbalance(table, next(r for r in rotors if r.name == rotor), common)


def _grade_meant(given) -> str | None:
    """The grade a refused ``grade`` string probably means: ``"G2,5"`` (a decimal comma) or
    ``"2.5"`` (no G) -> ``"G2.5"``; None when it is not one of them either."""
    if not isinstance(given, str):
        return None
    text = given.strip().replace(",", ".")
    grade = balance_grade(text if text[:1] in ("G", "g") else f"G{text}")
    return None if grade is None else f"G{grade:g}"


def _graded_unbalance(table: _Table, rotor, common) -> Unbalance:
    """An unbalance given as an ISO 21940-11 balance grade: the permissible residual unbalance
    ``G m / Omega`` of the rotor's (or the given part's) mass at its service speed."""
    if "amount" in table.data:
        raise table.error("amount", table.data["amount"], "no amount together with grade (give one "
                          "of them: the grade sets the amount)")
    given = table.data["grade"]
    grade = balance_grade(given)
    if grade is None:
        meant = _grade_meant(given)
        raise table.error("grade", given, "an ISO 21940-11 balance grade: one of "
                          + ", ".join(f"G{g:g}" for g in BALANCE_GRADES) + " (a string, or its number in mm/s"
                          + (f"; did you mean {meant!r}?)" if meant else ")"))
    speed = table.number("service_speed_rpm", required=True, positive=True)
    mass = table.number("mass", default=None, positive=True)
    amount = permissible_unbalance(grade, rotor.mass if mass is None else mass, speed * math.pi / 30.0)
    if problem := magnitude_problem(amount, positive=True):
        raise table.error("grade", table.data["grade"], "a grade, mass and service_speed_rpm whose "
                          "amount G m / Omega [kg m] is " + problem)
    return Unbalance(amount=amount, grade=grade, service_speed_rpm=speed, mass=mass, **common)


#: [m] the eccentricity (amount / rotor mass) no unbalance exceeds whatever the rotor's inertia
#: says: no machine's centre of mass runs a metre off its spin axis
ECCENTRICITY_FLOOR = 1.0


#: the largest acceleration of gravity [m/s^2] a model takes without a warning: 5 g (a static load
#: case of a vehicle's machine may exceed 1 g; 9810 is a value in mm/s^2, 386 one in in/s^2)
GRAVITY_WARN = 50.0
#: the standard gravity in ft/s^2: a model's gravity of this size is a value in ft/s^2 typed for m/s^2
_G_FEET = 9.80665 / 0.3048


def _check_gravity(source, gravity) -> None:
    """Warn (one line) where ``gravity`` [m/s^2] is over :data:`GRAVITY_WARN` or the standard
    gravity in ft/s^2: the weights, the static sag, the journal bearings' loads and eccentricities
    follow from it without a word."""
    import warnings

    from ..errors import ModelWarning

    size = float(np.linalg.norm(gravity))
    if size > GRAVITY_WARN or abs(size - _G_FEET) < 0.05:
        warnings.warn(f"{source}: gravity = {[float(g) for g in gravity]}: {size:g} m/s^2 is {size / 9.80665:.4g} g "
                      "(Earth's: 9.81 m/s^2); a value in mm/s^2, in/s^2 or ft/s^2 typed for m/s^2? (model files "
                      "are SI)", ModelWarning, stacklevel=2)


def _check_eccentricities(tables, unbalances, rotors) -> None:
    """Refuse an unbalance whose eccentricity ``e = amount / m`` (``m`` the rotor's mass) no
    rotor can have: a mass ``m_u <= m`` at radius ``r`` is part of the rotor, so ``m_u r^2 <=
    J_p`` and ``e = m_u r / m <= sqrt(m_u) sqrt(m_u r^2) / m <= sqrt(J_p / m)``, the polar radius
    of gyration (Cauchy-Schwarz). The bound taken is that radius or :data:`ECCENTRICITY_FLOOR`,
    whichever is larger, so a model whose inertia is not the whole rotor's keeps working. Above
    it (1e-4 kg m on a rotor of 1e-30 kg: 1e26 m) ``simulate`` failed at t = 0 ("step size too
    small") and every response was the rotor thrown metres off its bearings."""
    by_name = {r.name: r for r in rotors}
    for table, unbalance in zip(tables, unbalances):
        rotor = by_name[unbalance.rotor]
        eccentricity = unbalance.amount / rotor.mass
        bound = max(ECCENTRICITY_FLOOR, math.sqrt(rotor.polar_inertia / rotor.mass))
        if eccentricity > bound:
            key = "grade" if unbalance.grade is not None else "amount"
            raise table.error(key, table.data[key], f"an unbalance whose eccentricity amount / rotor mass is at "
                              f"most {bound:.4g} m (the larger of 1 m and the polar radius of gyration sqrt(Jp / m) "
                              f"of rotor {unbalance.rotor!r}); here {unbalance.amount:.4g} kg m / {rotor.mass:.4g} kg "
                              f"= {eccentricity:.4g} m")


def _sensor(table: _Table, rotor_names, on_bearings, shafts=None) -> Sensor:
    table.check_keys(input_keys("sensors"))
    direction = table.vector3("direction", required=True, nonzero=True)
    rotor = _carrying_rotor(table, rotor_names)
    measure = table.text("measure", default="absolute", choices=("absolute", "relative"))
    if measure == "relative" and rotor is None:
        raise table.error("measure", measure, "'absolute' for a point of the stator (a 'relative' "
                          "sensor, a proximity probe, needs rotor = NAME of a rotor on bearings)")
    if measure == "relative" and rotor not in on_bearings:
        raise table.error("measure", measure, f"'absolute': rotor {rotor!r} has no [[bearings]], so "
                          "its motion relative to the stator is zero")
    position = _station(table, rotor, shafts, required=True)
    return Sensor(name=table.data["name"], position=position,
                  direction=direction / np.linalg.norm(direction), rotor=rotor, measure=measure)


def _no_axial_probe_reading_zero(tables: dict, sensors, bearings, spin_axis) -> None:
    """Refuse a relative sensor along the spin axis of a rotor no bearing holds axially: such a
    rotor follows the stator along its axis (it has no axial coordinate), so the probe read 0 at
    every frequency and speed (FRFs and unbalance responses of exact zeros, without a word)."""
    e = np.asarray(spin_axis, dtype=float) / np.linalg.norm(spin_axis)
    held = {b.rotor for b in bearings if b.coefficients.axial}
    for table, sensor in zip(tables.values(), sensors):
        if sensor.measure == "relative" and sensor.rotor not in held \
                and abs(float(np.dot(sensor.direction, e))) > 1.0 - 1e-9:
            raise table.error("direction", table.data["direction"],
                              f"a direction across the spin axis: rotor {sensor.rotor!r} has no axial coordinate (no "
                              "bearing of it gives axial_stiffness), it follows the stator along the axis, so a "
                              "relative sensor along it reads 0; give a bearing axial_stiffness, or measure "
                              "= 'absolute'")


def _station(table: _Table, rotor, shafts, required: bool):
    """The point of a sensor or excitation: on a flexible rotor a station of its shaft
    (``position`` on its axis, or ``axial_position``), else ``position`` as given."""
    shaft = (shafts or {}).get(rotor)
    if shaft is not None:
        return _flexible.station_z(table, shaft, rotor, required=required)[0]
    if "axial_position" in table.data:
        raise table.error("axial_position", table.data["axial_position"], "no value: axial_position places a "
                          "point on a flexible rotor (rotor = NAME of a rotor with a shaft); give position")
    return table.vector3("position", required=required)


def _excitation(table: _Table, rotor_names, shafts=None) -> Excitation:
    table.check_keys(input_keys("excitations"))
    kind = table.text("kind", default="force", choices=("force", "moment"))
    direction = table.vector3("direction", required=True, nonzero=True)
    rotor = _carrying_rotor(table, rotor_names)
    position = _station(table, rotor, shafts, required=kind == "force")
    if position is None and kind == "moment":
        position = np.zeros(3) if (shafts or {}).get(rotor) is None else None
    if position is None:
        position = table.vector3("position", required=True)
    return Excitation(name=table.data["name"], position=position,
                      direction=direction / np.linalg.norm(direction), kind=kind, rotor=rotor)


def _carrying_rotor(table: _Table, rotor_names) -> str | None:
    """The optional ``rotor`` key of a sensor or excitation (None: the stator)."""
    return table.name_of("rotor", rotor_names, "rotors", hint=" (or no rotor key for a point of the stator)")


__all__ = ["validate", "plain_copy", "mesh_name"]
