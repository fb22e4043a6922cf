"""Flexible rotors: materials, shaft sections, disks and point masses, their mass
properties and the mesh of stations (``docs/model-file.md``, "Flexible rotors").

A rotor with a ``shaft`` is flexible. Its shaft runs from ``start`` along ``+spin_axis``
(``z`` [m] is measured from ``start``), made of consecutive sections. The mesh has a node
wherever a section ends and wherever a disk, point mass, bearing, unbalance, sensor or
excitation sits; between them elements no longer than ``element_length``
(:func:`default_element_length` when not given) or, for a section with ``elements = n``,
that section cut into ``n`` equal elements (and at its stations). A station closer than
:data:`MERGE_FRACTION` of its section's element length to another mark shares its node
(:attr:`Mesh.merged`, named by :func:`merge_lines`); a section shorter than that fraction of a
neighbouring section's element length makes no element: its ends share one node and it is lumped
there as a rigid piece (:func:`short_runs`, :attr:`Mesh.absorbed`, named by :func:`merge_lines`).

Its mass, centre of mass and inertias are those of the element mass matrices, the disks and the
point masses for a rigid motion (the elements reproduce a rigid motion's kinetic energy
exactly), so that with a very stiff shaft the rotor behaves as the rigid rotor with these values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..elements.shaft import Material, material_problem
from ._table import Table, and_others, visible, visible_names
from .geometry import shift_matrices, transverse_axes

__all__ = ["Material", "Layer", "Section", "Disk", "PointMass", "Shaft", "Mesh", "materials", "shaft",
           "mass_properties", "mesh", "default_element_length", "station_z", "SHAFT_KEYS",
           "STATION_TOLERANCE", "MERGE_FRACTION", "short_runs", "POSITION_ROUND_OFF", "DEFAULT_ELEMENTS", "MAX_NODES", "node_matrices", "lateral_basis", "bending_frequencies", "held_modes", "off_node"]

#: [m]: a station closer than this to a node is at that node; a point this far off the shaft's
#: axis or beyond its ends (plus the same fraction of the shaft's length) is off the shaft
STATION_TOLERANCE = 1e-6
#: a station closer than this fraction of its section's element length to another mark of the
#: mesh (the shaft's ends, a section's end, another station, a cut between equal elements) is
#: placed at that mark's node (and named by a warning, :func:`merge_lines`): a shorter element,
#: of length h beside elements of length H, would raise the stiffness by (H/h)^3 and cost the
#: low modes that many digits in round-off (docs/theory.md §16, "Stations close together")
MERGE_FRACTION = 1e-3
#: [m] largest round-off of a point given in the model file (double precision's spacing at its
#: coordinates): beyond it (coordinates over about 8e6 m) points along a shaft, or a bearing's
#: place along a rigid rotor's axis, are no longer resolved to a small part of the stations' tolerance
POSITION_ROUND_OFF = 1e-9
#: default element length: the shaft's length over this (see :func:`default_element_length`)
DEFAULT_ELEMENTS = 20
#: [m] shortest section (stations closer than :data:`STATION_TOLERANCE` share a node)
SHORTEST_SECTION = 1e-5
#: [m] the range of a shaft's outer diameters (beyond it the section's area or second moment
#: rounds badly: a shaft is neither a micron nor a kilometre thick)
THINNEST, THICKEST = 1e-6, 1e3
#: most nodes of one flexible rotor's mesh. Its node matrices are sparse (O(N) entries), but the
#: machine's matrices M, C, G, K are dense over the generalized coordinates (4 per node): 2,500
#: nodes make 10,000 coordinates, 0.8 GB per matrix, and the lowest modes' basis, the mass's
#: inverse and the whirl forms about ten such matrices (docs/model-file.md, "Mesh")
MAX_NODES = 2500
#: keys of a rotor table that make it flexible or only mean something on a flexible rotor
SHAFT_KEYS = ("shaft", "disks", "point_masses", "start", "shear", "element_length", "coupling_position")
_MATERIAL_KEYS = ("name", "density", "young_modulus", "shear_modulus", "poisson_ratio", "allowable_stress")
_SECTION_KEYS = ("length", "outer_diameter", "inner_diameter", "material", "elements", "layers")
_LAYER_KEYS = ("outer_diameter", "inner_diameter", "material")
_DISK_KEYS = ("name", "axial_position", "mass", "polar_inertia", "diametral_inertia", "outer_diameter",
              "inner_diameter", "width", "material")
_POINT_MASS_KEYS = ("name", "axial_position", "mass")
_SHEAR = ("cowper", "hutchinson", "none")
#: relative tolerance of a flexible rotor's mass, centre and inertias given beside its shaft
CONSISTENCY = 1e-6


@dataclass(frozen=True)
class Layer:
    """One of a section's ``layers``: a concentric tube over the section's whole length, in
    parallel with it; ``outer``/``inner`` diameters [m] at the section's left and right ends."""

    outer: tuple
    inner: tuple
    material: Material


@dataclass(frozen=True)
class Section:
    """One ``[[rotors.shaft]]`` section: ``outer``/``inner`` diameters [m] at its left and right
    ends, shape (2,); ``elements`` the count the user asked for (None: by length); ``layers``
    further tubes (:class:`Layer`) whose element matrices are added to the section's."""

    length: float
    outer: tuple
    inner: tuple
    material: Material
    elements: int | None = None
    layers: tuple = ()


@dataclass(frozen=True)
class Disk:
    """A rigid disk at ``z`` [m] from the shaft's start; ``width`` [m] or None; ``bore`` [m] its
    ``inner_diameter`` where it is given by its geometry (None: by mass and inertias)."""

    name: str
    z: float
    mass: float
    polar_inertia: float
    diametral_inertia: float
    width: float | None = None
    bore: float | None = None


@dataclass(frozen=True)
class PointMass:
    """A mass [kg] without rotational inertia at ``z`` [m]."""

    name: str
    z: float
    mass: float


@dataclass(frozen=True)
class Mesh:
    """The stations of a flexible rotor.

    Attributes
    ----------
    z : ndarray, shape (N,) [m]
        Nodes along the axis from the shaft's start, increasing.
    elements : tuple of (int, int, float, tuple, tuple)
        ``(left node, section index, length [m], outer (2,), inner (2,))`` of each element.
    """

    z: np.ndarray
    elements: tuple
    #: each named station placed at a node over :data:`STATION_TOLERANCE` from where it was given:
    #: ``(label, z [m], node's z [m], element length [m] of its section)``
    merged: tuple = field(default=(), compare=False)
    #: each run of sections too short for an element of their own (:func:`short_runs`), lumped as a
    #: rigid piece at one node: ``(first section, last section, joint z [m], neighbouring element
    #: length [m])``
    absorbed: tuple = field(default=(), compare=False)

    @property
    def n_nodes(self) -> int:
        return len(self.z)

    def node(self, z: float) -> int:
        """The node at (or nearest to) ``z`` [m]."""
        return int(np.argmin(np.abs(self.z - float(z))))


@dataclass(frozen=True)
class Shaft:
    """A flexible rotor's shaft, disks and point masses (validated), and its mesh once the model's
    stations are known.

    Attributes
    ----------
    start : ndarray, shape (3,) [m]
    axis : ndarray, shape (3,)
        The unit spin axis ``e``; the shaft runs along ``+e``.
    """

    start: np.ndarray
    axis: np.ndarray
    sections: tuple
    disks: tuple
    point_masses: tuple
    shear: str
    element_length: float
    mesh: Mesh | None = field(default=None, compare=False)

    @property
    def _made(self) -> dict:
        """Node matrices already made for :attr:`mesh`, by kind (an attribute, not a field: a
        new mesh is a new Shaft, with nothing made)."""
        return self.__dict__.setdefault("_node_matrices", {})

    @property
    def length(self) -> float:
        """[m]"""
        return float(sum(s.length for s in self.sections))

    @property
    def ends(self) -> np.ndarray:
        """Section ends along the axis from the start [m], shape (n_sections + 1,)."""
        return np.concatenate([[0.0], np.cumsum([s.length for s in self.sections])])

    def point(self, z) -> np.ndarray:
        """Points at ``z`` [m] on the axis, model axes, shape (..., 3)."""
        return self.start + np.asarray(z, dtype=float)[..., None] * self.axis

    def z_of(self, point) -> float:
        """Axial position [m] of a point (projected on the axis)."""
        return float((np.asarray(point, dtype=float) - self.start) @ self.axis)

    @property
    def node_positions(self) -> np.ndarray:
        """The mesh nodes, model axes [m], shape (N, 3)."""
        return self.point(self.mesh.z)


# ----------------------------------------------------------------------------------------
def default_element_length(sections) -> float:
    """The element length when ``element_length`` is not given: the shaft's length over
    :data:`DEFAULT_ELEMENTS` (about 20 elements, enough for the first bending modes within
    well under 0.1 %: cubic elements converge as h^4)."""
    return sum(s.length for s in sections) / DEFAULT_ELEMENTS


def materials(source: str, data) -> dict[str, Material]:
    """The ``[[materials]]`` tables by name."""
    out: dict[str, Material] = {}
    for index, raw in enumerate(data.get("materials", [])):
        table = Table(source, f"materials[{index}]", raw)
        name = table.text("name", required=True)
        if name in out:
            raise table.error("name", name, "a name unique among the [[materials]]")
        table = Table(source, f"materials.{visible(name)}", raw)
        table.check_keys(_MATERIAL_KEYS)
        density = table.number("density", required=True, positive=True)
        if "young_modulus" not in raw:
            raise table.error("young_modulus", "<missing>", "Young's modulus [Pa] (a material needs it for "
                              "the shaft's bending stiffness)")
        young = table.number("young_modulus", required=True, positive=True)
        if ("shear_modulus" in raw) == ("poisson_ratio" in raw):
            raise table.error("shear_modulus", raw.get("shear_modulus", "<missing>"),
                              "exactly one of shear_modulus [Pa] and poisson_ratio")
        shear = table.number("shear_modulus", positive=True)
        nu = table.number("poisson_ratio")
        if problem := material_problem(density, young, shear, nu):
            raise table.error(problem[0], raw.get(problem[0]), problem[2])
        if shear is None:
            shear = young / (2.0 * (1.0 + nu))
        allowable = table.number("allowable_stress", positive=True)
        out[name] = Material(name=name, density=density, young_modulus=young, shear_modulus=shear,
                             allowable_stress=allowable)
    return out


def _pair(table: Table, key: str, default=None):
    """A diameter given as a number or ``[left, right]``: a 2-tuple [m], >= 0."""
    value = table.array(key, [(), (2,)], default=default, required=default is None)
    value = np.broadcast_to(value, (2,)).astype(float)
    if np.any(value < 0):
        raise table.error(key, table.data[key], "diameters >= 0 [m]")
    return float(value[0]), float(value[1])


def _material(table: Table, key: str, known) -> Material:
    name = table.text(key, required=True)
    if name not in known:
        alike = [k for k in known if k.strip().casefold() == name.strip().casefold()]   # 'Steel', 'steel '
        raise table.error(key, name, "the name of one of the [[materials]] "
                          + (visible_names(known) or "(none defined: add a [[materials]] table)")
                          + (f" (did you mean {alike[0]!r}?)" if len(alike) == 1 else ""))
    return known[name]


def _tube(table: Table) -> tuple:
    """A section's or a layer's outer and inner diameters [m], (left, right) each."""
    outer = _pair(table, "outer_diameter")
    inner = _pair(table, "inner_diameter", default=0.0)
    if not (THINNEST <= min(outer) and max(outer) <= THICKEST):
        raise table.error("outer_diameter", table.data["outer_diameter"],
                          f"outer diameters from {THINNEST:g} to {THICKEST:g} m")
    if inner[0] >= outer[0] or inner[1] >= outer[1]:
        raise table.error("inner_diameter", table.data["inner_diameter"],
                          f"an inner diameter below the outer diameter {table.data['outer_diameter']!r} "
                          "at both ends of the section")
    if min(outer[0] - inner[0], outer[1] - inner[1]) < THINNEST:
        # a wall of 1e-16 m (a bore typed as the outer diameter times 1 - 1e-15) has a mass matrix
        # no solver inverts: it was refused as '[stator], [[rotors]] mass and inertia', no key named
        raise table.error("inner_diameter", table.data["inner_diameter"],
                          f"a bore at least {THINNEST:g} m below the outer diameter "
                          f"{table.data['outer_diameter']!r} at both ends (a tube wall thicker than "
                          f"{THINNEST / 2:g} m)")
    return outer, inner


def _layers(table: Table, known) -> tuple:
    """A section's ``layers`` (an array of tables): validated :class:`Layer` s."""
    raw = table.data.get("layers", [])
    if not isinstance(raw, list) or not all(isinstance(item, dict) for item in raw):
        raise table.error("layers", raw, "an array of tables with outer_diameter, inner_diameter, material "
                          "(layers = [{outer_diameter = ..., material = ...}, ...])")
    out = []
    for j, item in enumerate(raw):
        layer = Table(table.source, f"{table.label}.layers.{j}", item)
        layer.check_keys(_LAYER_KEYS)
        outer, inner = _tube(layer)
        out.append(Layer(outer=outer, inner=inner, material=_material(layer, "material", known)))
    return tuple(out)


def _section(table: Table, known) -> Section:
    table.check_keys(_SECTION_KEYS)
    length = table.number("length", required=True)
    if not length >= SHORTEST_SECTION:
        raise table.error("length", length, f"a section length > 0, at least {SHORTEST_SECTION:g} m")
    outer, inner = _tube(table)
    elements = table.data.get("elements")
    if elements is not None and (isinstance(elements, bool) or not isinstance(elements, int)
                                 or not 1 <= elements <= 10_000):
        raise table.error("elements", elements, "a whole number of elements from 1 to 10000")
    return Section(length=length, outer=outer, inner=inner, material=_material(table, "material", known),
                   elements=elements, layers=_layers(table, known))


def _disk(table: Table, index: int, known) -> Disk:
    table.check_keys(_DISK_KEYS)
    name = table.text("name", default=str(index))
    z = table.number("axial_position", required=True)
    width = table.number("width", positive=True)
    geometry = [k for k in ("outer_diameter", "inner_diameter", "material") if k in table.data]
    given = [k for k in ("mass", "polar_inertia", "diametral_inertia") if k in table.data]
    if given and geometry:
        raise table.error(geometry[0], table.data[geometry[0]], "no value: a disk is given either by mass, "
                          "polar_inertia and diametral_inertia or by outer_diameter, width and material")
    if geometry:
        outer = table.number("outer_diameter", required=True, positive=True)
        inner = table.number("inner_diameter", default=0.0, nonnegative=True)
        if inner >= outer:
            raise table.error("inner_diameter", inner, f"a bore below outer_diameter = {outer:g} [m]")
        if width is None:
            table.require("width")
        density = _material(table, "material", known).density
        mass = density * math.pi / 4 * (outer ** 2 - inner ** 2) * width
        polar = mass / 8 * (outer ** 2 + inner ** 2)
        return Disk(name, z, mass, polar, polar / 2 + mass * width ** 2 / 12, width, inner)
    mass = table.number("mass", required=True, positive=True)
    polar = table.number("polar_inertia", required=True, nonnegative=True)
    diametral = table.number("diametral_inertia", required=True, nonnegative=True)
    if polar > 2.0 * diametral * (1 + 1e-12):
        raise table.error("polar_inertia", polar, f"at most twice diametral_inertia = {diametral:g} "
                          "(triangle inequality of a rigid body's principal moments)")
    return Disk(name, z, mass, polar, diametral, width)


def _point_mass(table: Table, index: int) -> PointMass:
    table.check_keys(_POINT_MASS_KEYS)
    return PointMass(table.text("name", default=str(index)), table.number("axial_position", required=True),
                     table.number("mass", required=True, positive=True))


def _items(rotor: Table, key: str):
    """The sub-tables ``[[rotors.shaft]]`` etc. of a rotor, as (label, raw) pairs."""
    raw = rotor.data.get(key, [])
    if not isinstance(raw, list) or not all(isinstance(item, dict) for item in raw):
        raise rotor.error(key, raw, f"an array of tables ([[rotors.{key}]])")
    return raw


def shaft(rotor: Table, known, spin_axis: np.ndarray) -> Shaft:
    """Validate a flexible rotor's shaft, disks and point masses (``rotor`` its table)."""
    source, label = rotor.source, rotor.label
    raws = _items(rotor, "shaft")
    if not raws:
        raise rotor.error("shaft", raws, "at least one [[rotors.shaft]] section")
    sections = tuple(_section(Table(source, f"{label}.shaft.{i}", raw), known) for i, raw in enumerate(raws))
    start = rotor.vector3("start", required=True)
    shear = rotor.text("shear", default="cowper", choices=_SHEAR)
    length = sum(s.length for s in sections)
    _check_resolved(rotor, start, length)
    element_length = rotor.number("element_length", positive=True)
    longest = element_length if element_length is not None else default_element_length(sections)
    count = sum(s.elements if s.elements is not None else math.ceil(s.length / longest - 1e-9) for s in sections)
    if count >= MAX_NODES:
        key = "element_length" if element_length is not None else "shaft"
        raise rotor.error(key, rotor.data[key] if key == "element_length" else f"<{len(sections)} sections>",
                          f"a mesh of at most {MAX_NODES} nodes (these sections make {count} elements: "
                          f"give a longer element_length or fewer elements; {_dense_size(count + 1)})")
    disks, names = [], set()
    for i, raw in enumerate(_items(rotor, "disks")):
        table = Table(source, f"{label}.disks.{visible(raw.get('name', i))}", raw)
        disk = _disk(table, i, known)
        if disk.name in names:
            raise table.error("name", disk.name, "a name unique among the rotor's [[rotors.disks]]")
        names.add(disk.name)
        _check_on_shaft(table, "axial_position", disk.z, length)
        for other in disks:
            _check_apart(table, disk, other)
        disks.append(disk)
    points = []
    for i, raw in enumerate(_items(rotor, "point_masses")):
        table = Table(source, f"{label}.point_masses.{visible(raw.get('name', i))}", raw)
        point = _point_mass(table, i)
        _check_on_shaft(table, "axial_position", point.z, length)
        points.append(point)
    return Shaft(start=start, axis=np.asarray(spin_axis, dtype=float), sections=sections, disks=tuple(disks),
                 point_masses=tuple(points), shear=shear,
                 element_length=element_length if element_length is not None else default_element_length(sections))


def _check_resolved(rotor: Table, start: np.ndarray, length: float) -> None:
    """Refuse a ``start`` [m] so far from the origin that double precision cannot place points
    along the shaft (``start + z e``, ``length`` [m] long) to :data:`POSITION_ROUND_OFF`: at
    ``start = [1e29, 0, 0]`` every station of a 0.45 m shaft was the same point, and the refusal
    spoke of bearings at a single point."""
    far = float(np.abs(start).max()) + length
    spacing = float(np.spacing(far))
    if spacing > POSITION_ROUND_OFF:
        raise rotor.error("start", rotor.data["start"], f"a start near the machine (coordinates in metres, within "
                          f"about 8e+06 m of the origin): {far:.3g} m from it double precision rounds points to "
                          f"{spacing:.2g} m, so the points along the {length:.6g} m shaft cannot be placed to "
                          f"{POSITION_ROUND_OFF:g} m")


def _dense_size(nodes: int) -> str:
    """What a mesh of ``nodes`` nodes costs: its coordinates and one dense matrix over them."""
    return (f"{nodes} nodes make {4 * nodes} coordinates, {8 * (4 * nodes) ** 2 / 1e9:.2g} GB per dense matrix "
            "of the machine")


def _check_on_shaft(table: Table, key: str, z: float, length: float, centre: float | None = None) -> None:
    """Refuse a station ``z`` [m from the start] off the shaft; ``centre`` [m from the start]: the
    key's value is an offset from the centre of mass there (``axial_offset``), and its range is
    said as such."""
    slack = STATION_TOLERANCE * (1.0 + length)
    if not -slack <= z <= length + slack:
        if centre is not None:   # 'from 0 to 1.2 m from the start' misread an offset from the centre
            raise table.error(key, table.data.get(key, z), f"an offset that stays on the shaft: from {-centre:.6g} "
                              f"to {length - centre:.6g} m (measured from the rotor's centre of mass, "
                              f"{centre:.6g} m from its start along its {length:g} m)")
        raise table.error(key, table.data.get(key, z), f"an axial position on the shaft, from 0 to its length "
                          f"{length:g} m (measured from the rotor's start)")


def _check_apart(table: Table, disk: Disk, other: Disk) -> None:
    """Refuse ``disk`` at ``other``'s station or overlapping it; a disk without ``width`` is a
    point on the axis, refused inside the other's width as well."""
    gap = abs(disk.z - other.z)
    if gap <= STATION_TOLERANCE:
        raise table.error("axial_position", disk.z, f"a position other than disk {visible(other.name)!r}'s "
                          f"({other.z:g} m): two disks at one station are one disk")
    if disk.width is None and other.width is None:
        return
    widths = [w for w in (disk.width, other.width) if w is not None]
    if gap < 0.5 * sum(widths) - 1e-12:
        said = (f"widths {disk.width:g} and {other.width:g} m" if len(widths) == 2 else
                f"width {widths[0]:g} m; a disk without width is a point on the axis")
        raise table.error("axial_position", disk.z, f"a disk that does not overlap disk {visible(other.name)!r} "
                          f"at {other.z:g} m ({said}: their centres must be at least {0.5 * sum(widths):g} m "
                          "apart)")


# ----------------------------------------------------------------------------------------
def station_z(table: Table, shaft: Shaft, rotor_name: str, key: str = "position", required: bool = True):
    """A station of a flexible rotor: its point on the axis and ``z`` [m], from ``key`` (a 3-D
    point on the axis) or ``axial_position`` (from the shaft's start); exactly one of them."""
    given = [k for k in dict.fromkeys((key, "axial_position")) if k in table.data]
    if len(given) == 2:
        raise table.error("axial_position", table.data["axial_position"],
                          f"either {key} or axial_position, not both")
    if not given:
        if not required:
            return None, None
        table.require(key)
    length = shaft.length
    if given[0] == "axial_position":
        z = table.number("axial_position")
    else:
        point = table.vector3(key)
        z = shaft.z_of(point)
        off = float(np.linalg.norm(point - shaft.point(z)))
        if off > STATION_TOLERANCE * (1.0 + abs(z)):
            raise table.error(key, table.data[key], f"a point on the axis of the flexible rotor {rotor_name!r} "
                              f"(the line from its start {_fmt(shaft.start)} along spin_axis); this point is "
                              f"{off:.4g} m off it")
    _check_on_shaft(table, given[0], z, length)
    z = min(max(z, 0.0), length)
    return shaft.point(z), z


def _fmt(values) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"


# ----------------------------------------------------------------------------------------
def mesh(shaft: Shaft, stations, fraction: float = MERGE_FRACTION) -> Mesh:
    """The nodes and elements of ``shaft`` with a node at every station ``z`` [m] of ``stations``
    (disks and point masses are added here).

    Parameters
    ----------
    shaft : Shaft
    stations : sequence of float or of (str, float)
        Each station's ``z`` [m], or ``(label, z)`` (a label such as ``"bearing 'b2'"`` names it
        in :attr:`Mesh.merged` when it is moved to a node).
    fraction : float
        Marks (stations, section ends, cuts) closer than ``fraction`` times their section's element
        length (:func:`section_element_length`), and at least :data:`STATION_TOLERANCE`, share a
        node (0: :data:`STATION_TOLERANCE` only, as for the mass properties, where elements of
        any length are exact). A section shorter than ``fraction`` times a neighbouring section's
        element length (:func:`short_runs`) makes no element: its two ends share one node, at
        its middle, which the neighbours' elements reach, and its mass and inertia are lumped
        there as a rigid piece (:attr:`Mesh.absorbed`).
    """
    ends = shaft.ends
    length = shaft.length
    named = [item if isinstance(item, tuple) else (None, item) for item in stations]
    named += [(f"disk {visible(d.name)!r}", d.z) for d in shaft.disks]
    named += [(f"point mass {visible(p.name)!r}", p.z) for p in shaft.point_masses]
    runs = short_runs(shaft, fraction)
    lefts, rights = list(ends[:-1]), list(ends[1:])        # what each section is meshed over
    absorbed = set()
    points = np.array([float(z) for _, z in named], dtype=float).reshape(-1)
    for first, last, at, _ in runs:
        absorbed.update(range(first, last + 1))
        if first > 0:
            rights[first - 1] = at
        if last + 1 < len(shaft.sections):
            lefts[last + 1] = at
        # a station on the absorbed piece is at its joint (a node there, never one microns away)
        points = np.where((points >= ends[first]) & (points <= ends[last + 1]), at, points)
    nodes, elements, spacing = [0.0], [], []
    for index, section in enumerate(shaft.sections):
        if index in absorbed:
            continue
        start, left, right = ends[index], lefts[index], rights[index]
        h = section_element_length(shaft, index)
        tolerance = max(STATION_TOLERANCE, fraction * h)
        if section.elements is not None:
            cuts = list(np.linspace(left, right, section.elements + 1)[1:-1])
        else:
            cuts = []
        inside = [p for p in points if left + tolerance < p < right - tolerance]
        marks = _merged(sorted([left, right, *cuts, *inside]), tolerance)
        marks[0], marks[-1] = left, right
        spacing.append((left, right, h))
        for a, b in zip(marks[:-1], marks[1:]):
            # the reach over an absorbed neighbour adds no element: a stretch of two element lengths
            # stays two elements when it reaches 10 um further
            reach = (max(start - left, 0.0) if a == left else 0.0) + (max(right - ends[index + 1], 0.0) if b == right else 0.0)
            count = 1 if section.elements is not None else \
                max(1, math.ceil((b - a - reach) / shaft.element_length - 1e-9))
            for k in range(count):
                z0, z1 = a + (b - a) * k / count, a + (b - a) * (k + 1) / count
                if k == count - 1:
                    z1 = b
                elements.append((len(nodes) - 1, index, z1 - z0, _diameters(section.outer, section.length, start, z0, z1),
                                 _diameters(section.inner, section.length, start, z0, z1)))
                nodes.append(z1)
    nodes[-1] = length
    z = np.array(nodes)
    return Mesh(z=z, elements=tuple(elements), merged=_moved_stations(named, z, spacing), absorbed=tuple(runs))


def short_runs(shaft: Shaft, fraction: float = MERGE_FRACTION) -> list:
    """The runs of consecutive sections each shorter than ``fraction`` times a neighbouring
    section's element length (:func:`section_element_length`): such a section would make an
    element of length ``h`` beside elements of length ``H``, ``(H/h)^3`` stiffer, and cost the low
    modes that many digits in round-off (docs/theory.md §16, "Sections shorter than a
    thousandth of an element").

    Returns
    -------
    list of (int, int, float, float)
        ``(first, last, z, H)``: the sections ``first .. last`` (inclusive), the joint ``z`` [m]
        their ends share (the run's middle, or the shaft's end a run reaches), the longest
        neighbouring element length ``H`` [m].
    """
    count = len(shaft.sections)
    if fraction <= 0.0 or count < 2:
        return []
    h = [section_element_length(shaft, i) for i in range(count)]
    ends = shaft.ends
    short = [shaft.sections[i].length < fraction * max(h[j] for j in (i - 1, i + 1) if 0 <= j < count)
             for i in range(count)]
    runs, i = [], 0
    while i < count:
        if not short[i]:
            i += 1
            continue
        first = i
        while i + 1 < count and short[i + 1]:
            i += 1
        last = i
        i += 1
        if first == 0 and last == count - 1:
            continue                                   # nothing to join it to
        neighbours = [h[j] for j in (first - 1, last + 1) if 0 <= j < count]
        at = 0.0 if first == 0 else shaft.length if last == count - 1 else 0.5 * (ends[first] + ends[last + 1])
        runs.append((first, last, float(at), max(neighbours)))
    return runs


def section_element_length(shaft: Shaft, index: int) -> float:
    """The length [m] of section ``index``'s elements before stations cut them: its length over its
    ``elements``, or over as many as ``element_length`` asks."""
    section = shaft.sections[index]
    count = section.elements if section.elements is not None else \
        max(1, math.ceil(section.length / shaft.element_length - 1e-9))
    return section.length / count


def _moved_stations(named, z, spacing) -> tuple:
    """The labelled stations of ``named`` ((label or None, z [m]) pairs) over
    :data:`STATION_TOLERANCE` from their node (the nearest of ``z``), as :attr:`Mesh.merged`;
    ``spacing`` each section's (left, right, element length) [m]."""
    out = []
    for label, position in named:
        node = float(z[int(np.argmin(np.abs(z - position)))])
        if label is None or abs(position - node) <= STATION_TOLERANCE:
            continue
        h = next((h for left, right, h in spacing if left <= position <= right), spacing[-1][2])
        there = [other for other, at in named if other is not None and abs(at - node) <= STATION_TOLERANCE]
        out.append((label, float(position), node, h, there[0] if there else None))
    return tuple(out)


#: [m] outer diameter of a shaft section or layer above which a model draws a warning: no
#: machine's shaft is this thick (kilns and tube mills reach ~6 m), while a shaft of 10 to
#: 1000 mm typed in mm for m lands here
PLAUSIBLE_SHAFT_DIAMETER = 10.0
#: [m] length of a flexible rotor's shaft above which a model draws a warning: the longest
#: machine rotors, turbine-generator trains, run 50 to 70 m, while a rotor of 0.1 to 10 m given
#: in mm for m lands at 100 m to 10 km
PLAUSIBLE_SHAFT_LENGTH = 100.0
#: a section longer than this many of its outer diameters draws the same warning (a single
#: short section in mm: 50 mm of a 10 mm shaft typed as 50 is 5000 diameters; line shafts and
#: quills run below 200)
PLAUSIBLE_SLENDERNESS = 1000.0


def size_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft`` when a section (or layer) is thicker than
    :data:`PLAUSIBLE_SHAFT_DIAMETER`, most likely a diameter in mm typed for m: the thickest
    named, with the count of the others."""
    lines = _length_lines(source, rotor, shaft) + _heavy_disk_lines(source, rotor, shaft) + \
        _wide_disk_lines(source, rotor, shaft) + _overhanging_disk_lines(source, rotor, shaft) + \
        _bored_disk_lines(source, rotor, shaft)
    thick = [(max(tube.outer), where) for i, section in enumerate(shaft.sections)
             for where, tube in ((f"shaft.{i}", section), *((f"shaft.{i}.layers.{k}", layer)
                                                          for k, layer in enumerate(section.layers)))
             if max(tube.outer) > PLAUSIBLE_SHAFT_DIAMETER]
    if not thick:
        return lines
    diameter, where = max(thick)
    others = f" (and {len(thick) - 1} other tubes over it)" if len(thick) > 1 else ""
    return lines + [f"{source}: [rotors.{visible(rotor)}.{where}] outer_diameter = {diameter:g}{others}: a shaft "
                    f"over {PLAUSIBLE_SHAFT_DIAMETER:g} m thick; a diameter in mm typed for m? (model files are SI)"]


#: a disk whose polar radius of gyration sqrt(Ip / m) is below this fraction of the shaft's outer
#: radius where it sits draws a warning: a disk around the shaft has it at least that radius (a
#: thin ring at the bore) and a solid piece of the shaft itself 0.71 of it, while a mass in g typed
#: for kg puts it sqrt(1000) = 32 times lower
LIGHTEST_DISK_RADIUS = 0.25


def _heavy_disk_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft``'s disks given by mass and inertias whose polar radius of
    gyration is below :data:`LIGHTEST_DISK_RADIUS` of the shaft's outer radius at the disk: most
    likely a mass in g typed for kg (ROSS's ``m``, a model file's ``mass``). A disk of no polar
    inertia (a lumped mass) is left out. The first named, with the count of the others. One more
    for disks whose polar radius of gyration exceeds half :data:`PLAUSIBLE_SHAFT_DIAMETER`:
    inertias in kg mm^2 typed for kg m^2 (a million times too large)."""
    ends = shaft.ends
    found = []
    for disk in shaft.disks:
        if not disk.polar_inertia > 0:
            continue
        touching = [max(s.outer) for s, a, b in zip(shaft.sections, ends[:-1], ends[1:])
                    if a - STATION_TOLERANCE <= disk.z <= b + STATION_TOLERANCE]
        radius = 0.5 * min(touching) if touching else 0.0
        gyration = math.sqrt(disk.polar_inertia / disk.mass)
        if gyration < LIGHTEST_DISK_RADIUS * radius:
            found.append((disk, gyration, radius))
    lines = []
    if found:
        disk, gyration, radius = found[0]
        others = and_others(len(found), "disk")
        lines.append(f"{source}: [rotors.{visible(rotor)}.disks.{visible(disk.name)}] mass = {disk.mass:g}{others}: its "
                     f"polar radius of gyration sqrt(polar_inertia / mass) = {gyration:.3g} m is {gyration / radius:.2g} of "
                     f"the shaft's radius {radius:.3g} m there (a disk around the shaft has at least that radius): a mass "
                     "in g typed for kg? (model files are SI)")
    wide = [d for d in shaft.disks if d.polar_inertia > d.mass * (PLAUSIBLE_SHAFT_DIAMETER / 2) ** 2]
    if wide:
        disk = wide[0]
        others = and_others(len(wide), "disk")
        lines.append(f"{source}: [rotors.{visible(rotor)}.disks.{visible(disk.name)}] polar_inertia = "
                     f"{disk.polar_inertia:g}{others}: a polar radius of gyration sqrt(polar_inertia / mass) = "
                     f"{math.sqrt(disk.polar_inertia / disk.mass):.3g} m, over {PLAUSIBLE_SHAFT_DIAMETER / 2:g} m (no "
                     "machine's disk is that wide): inertias in kg mm^2 typed for kg m^2? (model files are SI)")
    return lines


def _wide_disk_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft``'s disks wider than the whole shaft (``width`` longer than
    its length): no disk on a shaft is, while a width in mm typed for m (50 for 0.05) is, and
    makes a disk given by its geometry that much heavier; the widest named, with the count of
    the others."""
    wide = [d for d in shaft.disks if d.width is not None and d.width > shaft.length]
    if not wide:
        return []
    disk = max(wide, key=lambda d: d.width)
    return [f"{source}: [rotors.{visible(rotor)}.disks.{visible(disk.name)}] width = {disk.width:g}"
            f"{and_others(len(wide), 'disk')}: wider than the whole shaft it sits on ({shaft.length:g} m long); a "
            "width in mm typed for m? (model files are SI)"]


def shaft_diameter_at(shaft: Shaft, z: float) -> float:
    """The shaft's outer diameter [m] at ``z`` [m] from its start (linear along a tapered
    section; the larger of two sections at their joint; the section's own outer tube, not its
    layers)."""
    ends = shaft.ends
    found = [s.outer[0] + (s.outer[1] - s.outer[0]) * (min(max(z, a), b) - a) / (b - a)
             for s, a, b in zip(shaft.sections, ends[:-1], ends[1:])
             if a - STATION_TOLERANCE <= z <= b + STATION_TOLERANCE and b > a]
    return float(max(found)) if found else 0.0


def _bored_disk_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft``'s disks given by their geometry whose bore
    (``inner_diameter``, default 0) is below the shaft's outer diameter at their station: the
    disk's ring ``rho pi/4 (D^2 - d^2) w`` then holds the shaft inside it, which the shaft's own
    elements carry already, so its mass is counted twice (a 0.3 m steel disk 0.05 m wide on a 0.05
    m shaft, bore left at 0: 0.766 kg of its 27.6 kg, and the rotor 1.8 % heavier than it is). A
    disk around a shaft has a bore at least the shaft's diameter (ROSS's ``i_d``, "the diameter of
    the shaft on which the disk is mounted"). The one counting most named, with the count of the
    others."""
    found = []
    for disk in shaft.disks:
        if disk.bore is None or disk.width is None:
            continue
        diameter = shaft_diameter_at(shaft, disk.z)
        if disk.bore < diameter * (1.0 - 1e-6):
            found.append((disk, diameter))
    if not found:
        return []
    disk, diameter = found[0]
    outer_squared = 8 * disk.polar_inertia / disk.mass - disk.bore ** 2            # J_p = m (D^2 + d^2) / 8
    twice = disk.mass * (diameter ** 2 - disk.bore ** 2) / (outer_squared - disk.bore ** 2)
    return [f"{source}: [rotors.{visible(rotor)}.disks.{visible(disk.name)}] inner_diameter = {disk.bore:g}"
            f"{and_others(len(found), 'disk')}: a bore below the shaft's outer diameter {diameter:g} m at its station: "
            f"the disk's ring holds the shaft inside it, {twice:.3g} kg the shaft's elements carry already (counted "
            f"twice); give the disk's bore, inner_diameter = {diameter:g} (a disk around the shaft)"]


#: a disk may reach beyond a shaft's end by this share of its width (round-off of positions
#: typed to a few digits) without a warning
_OVERHANG_SLACK = 1e-6


def _overhanging_disk_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft``'s disks whose width reaches beyond an end of the shaft (a
    disk given at the end, ``axial_position = 0.5`` on a 0.5 m shaft, where its mid-plane was
    meant half its width inside): the disk's mass and inertia act at its station all the same,
    while half of it hangs over nothing. The one reaching furthest named, with the count of the
    others; disks wider than the whole shaft have their own line (:func:`_wide_disk_lines`)."""
    def beyond(disk):
        return max(disk.width / 2 - disk.z, disk.z + disk.width / 2 - shaft.length)

    over = [d for d in shaft.disks if d.width is not None and d.width <= shaft.length
            and beyond(d) > _OVERHANG_SLACK * d.width]
    if not over:
        return []
    disk = max(over, key=beyond)
    return [f"{source}: [rotors.{visible(rotor)}.disks.{visible(disk.name)}] axial_position = {disk.z:g} m, width = "
            f"{disk.width:g} m{and_others(len(over), 'disk')}: the disk reaches {beyond(disk):.3g} m beyond the end of "
            f"its shaft (0 to {shaft.length:g} m); its mid-plane {disk.width / 2:g} m inside the end was meant?"]


def _length_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line for ``shaft`` when it is longer than :data:`PLAUSIBLE_SHAFT_LENGTH` or a
    section is longer than :data:`PLAUSIBLE_SLENDERNESS` of its outer diameters, most likely
    lengths in mm typed for m: the longest section named, with the shaft's length."""
    slender = [i for i, s in enumerate(shaft.sections) if s.length > PLAUSIBLE_SLENDERNESS * max(s.outer)]
    total = shaft.length
    if not slender and not total > PLAUSIBLE_SHAFT_LENGTH:
        return []
    i = max(slender or range(len(shaft.sections)), key=lambda k: shaft.sections[k].length)
    section = shaft.sections[i]
    others = and_others(len(shaft.sections), "section")
    why = (f"a shaft {total:.4g} m long, over {PLAUSIBLE_SHAFT_LENGTH:g} m (turbine-generator trains, the longest "
           "rotors, run 50 to 70 m)" if total > PLAUSIBLE_SHAFT_LENGTH else
           f"{section.length / max(section.outer):.3g} times its outer diameter {max(section.outer):g} m, over "
           f"{PLAUSIBLE_SLENDERNESS:g} (line shafts run below 200)")
    return [f"{source}: [rotors.{visible(rotor)}.shaft.{i}] length = {section.length:g}{others}: {why}; "
            "lengths in mm typed for m? (model files are SI)"]


def merge_lines(source: str, rotor: str, shaft: Shaft) -> list[str]:
    """One warning line per station of ``shaft``'s mesh placed at the node of another mark
    (:attr:`Mesh.merged`), naming it, its distance and where it now is, and one per run of
    sections too short for an element (:attr:`Mesh.absorbed`), naming it, its length, the
    neighbouring element length and the node its ends share."""
    lines = []
    joints = shaft.ends
    for label, position, node, h, other in shaft.mesh.merged if shaft.mesh is not None else ():
        joint = int(np.argmin(np.abs(joints - node)))
        at_joint = abs(joints[joint] - node) <= STATION_TOLERANCE
        if at_joint and joint in (0, len(joints) - 1):
            end = "start" if joint == 0 else "end"
            where, placed = f"the shaft's {end}", f"at the {end}"
        elif other is not None:
            where, placed = f"{other} at {node:.7g} m", "at its node"
        elif at_joint:
            where, placed = f"the joint of sections {joint - 1} and {joint} at {node:.7g} m", "there"
        else:
            where, placed = f"the mesh's node at {node:.7g} m", "there"
        piece = next(((first, last) for first, last, _, _ in shaft.mesh.absorbed
                      if joints[first] - STATION_TOLERANCE <= position <= joints[last + 1] + STATION_TOLERANCE), None)
        why = (f"closer than {MERGE_FRACTION:g} of the element length {h:.4g} m" if piece is None else
               f"on shaft.{piece[0]}" + (f" to shaft.{piece[1]}" if piece[1] != piece[0] else "")
               + ", too short for an element of its own")
        lines.append(f"{source}: [rotors.{visible(rotor)}] {label} at {position:.7g} m is {abs(position - node):.2g} m "
                     f"from {where}: placed {placed} ({why}; a shorter element would swamp the shaft's stiffness "
                     "in round-off)")
    for first, last, at, h in shaft.mesh.absorbed if shaft.mesh is not None else ():
        size = sum(s.length for s in shaft.sections[first:last + 1])
        which = f"shaft.{first}" if first == last else f"shaft.{first} to shaft.{last}"
        lines.append(f"{source}: [rotors.{visible(rotor)}.{which}] length = {size:.3g} m is shorter than "
                     f"{MERGE_FRACTION:g} of the neighbouring element length {h:.4g} m: it makes no element "
                     f"(one would swamp the shaft's stiffness in round-off); its ends share the node at "
                     f"{at:.7g} m and its mass and inertia are lumped there as a rigid piece (merge it into a "
                     "neighbouring section to silence this)")
    return lines


def _merged(values, tolerance):
    """Sorted ``values`` without those within ``tolerance`` of the one before; the last kept
    is the last value (a section's right end)."""
    out = [values[0]]
    for v in values[1:]:
        if v - out[-1] > tolerance:
            out.append(v)
    if len(out) == 1:
        out.append(values[-1])
    out[-1] = values[-1]
    return out


def _diameters(d: tuple, length: float, left: float, z0: float, z1: float) -> tuple:
    """Diameters ``d`` [m] (left, right) of a section of ``length`` [m] starting at ``left`` [m],
    linear along it, at the ends ``z0``, ``z1`` [m] of an element."""
    # within [0, 1]: the section's end found by summing lengths may lie past left + length by
    # round-off, and a weight below 0 would take a bore tapering to 0 below 0 (refused)
    t0, t1 = (min(max((z - left) / length, 0.0), 1.0) for z in (z0, z1))
    # weights, not d0 + (d1 - d0) t: no cancellation, so a diameter stays between its ends
    return (d[0] * (1 - t0) + d[1] * t0, d[0] * (1 - t1) + d[1] * t1)


# ----------------------------------------------------------------------------------------
def rotation(spin_axis) -> np.ndarray:
    """``R``, rows ``a, b, e``: local components = ``R @`` model components, (3, 3)."""
    a, b = transverse_axes(spin_axis)
    e = np.asarray(spin_axis, dtype=float)
    return np.array([a, b, e])


def element_blocks(shaft: Shaft, mesh: Mesh):
    """Each element's ``M, K, G`` (12 x 12, local axes ``a, b, e`` per node, G per unit spin): the
    section's tube's plus, for a layered section, each layer's over the same element (its own
    diameters there, material and shear coefficient), as ROSS adds parallel shaft elements."""
    from ..elements.shaft import element_matrices

    def matrices(length, outer, inner, material):
        return element_matrices(length, outer, inner, material, shear=shaft.shear)

    ends = shaft.ends
    out = []
    for left_node, index, length, outer, inner in mesh.elements:
        section = shaft.sections[index]
        blocks = matrices(length, outer, inner, section.material)
        z0, z1 = float(mesh.z[left_node]), float(mesh.z[left_node + 1])
        for layer in section.layers:
            extra = matrices(length, _diameters(layer.outer, section.length, ends[index], z0, z1),
                             _diameters(layer.inner, section.length, ends[index], z0, z1), layer.material)
            blocks = tuple(a + b for a, b in zip(blocks, extra))
        out.append(blocks)
    return out


def node_matrices(shaft: Shaft, mesh: Mesh, kinds=("M", "K", "G")):
    """The shaft's, disks' and point masses' matrices on the nodes' 6 motions ``[u, theta]`` each
    (model axes), shape (6 N, 6 N) each, sparse (``scipy.sparse.csr_matrix``, read-only: an
    element couples its two nodes only, so a shaft of thousands of nodes stores O(N) entries):
    mass [kg, kg m^2], stiffness, gyroscopic per unit spin."""
    import scipy.sparse

    if mesh is shaft.mesh:          # all three made and kept at once: the element blocks are made together
        if not all(kind in shaft._made for kind in kinds):
            shaft._made.update(zip("MKG", _node_matrices(shaft, mesh, "MKG")))
        return tuple(shaft._made[kind] for kind in kinds)
    return _node_matrices(shaft, mesh, kinds)


def _node_matrices(shaft: Shaft, mesh: Mesh, kinds):
    """:func:`node_matrices` made anew."""
    import scipy.sparse

    size = 6 * mesh.n_nodes
    rot = rotation(shaft.axis)
    Q = np.kron(np.eye(4), rot)                      # local = Q @ model on [node1 (6), node2 (6)]
    lefts = np.array([left for left, *_ in mesh.elements], dtype=int)
    # each element's 12 x 12 block at rows and columns 6 left .. 6 left + 12; summed where they
    # overlap (a node shared by two elements) in element order, then the disks and point masses
    block = 6 * lefts[:, None] + np.arange(12)                                   # (E, 12)
    rows, cols = (np.broadcast_to(x, (len(lefts), 12, 12)).ravel() for x in (block[:, :, None], block[:, None, :]))
    parts = {k: ([rows], [cols], []) for k in kinds}
    blocks = element_blocks(shaft, mesh)
    for kind, i in (("M", 0), ("K", 1), ("G", 2)):
        if kind in parts:
            parts[kind][2].append((Q.T @ np.array([b[i] for b in blocks]).reshape(-1, 12, 12) @ Q).ravel())
    e = shaft.axis
    eye, outer, skew = np.eye(3), np.outer(e, e), _skew(e)
    for disk in shaft.disks:
        i = 6 * mesh.node(disk.z)
        _add_block(parts.get("M"), i, disk.mass * eye)
        _add_block(parts.get("M"), i + 3, disk.diametral_inertia * eye + (disk.polar_inertia - disk.diametral_inertia) * outer)
        _add_block(parts.get("G"), i + 3, -disk.polar_inertia * skew)
    for point in shaft.point_masses:
        _add_block(parts.get("M"), 6 * mesh.node(point.z), point.mass * eye)
    for first, last, at, _ in mesh.absorbed:
        i = 6 * mesh.node(at)
        for kind, block in zip("MG", _rigid_piece(shaft, first, last, at)):
            if kind in parts:
                rows, cols = np.meshgrid(i + np.arange(6), i + np.arange(6), indexing="ij")
                parts[kind][0].append(rows.ravel())
                parts[kind][1].append(cols.ravel())
                parts[kind][2].append(block.ravel())
    out = {}
    for kind, (r, c, data) in parts.items():
        matrix = scipy.sparse.csr_matrix((np.concatenate(data), (np.concatenate(r), np.concatenate(c))),
                                         shape=(size, size))
        matrix.sum_duplicates()
        for array in (matrix.data, matrix.indices, matrix.indptr):
            array.flags.writeable = False
        out[kind] = matrix
    return tuple(out[k] for k in kinds)


def _rigid_piece(shaft: Shaft, first: int, last: int, at: float):
    """Mass and gyroscopic matrices (6 x 6 each, model axes, on ``[u, theta]`` of the node at
    ``at`` [m]) lumped there for the sections ``first .. last`` absorbed (:func:`short_runs`):
    those sections as a rigid piece moving with the node, less the neighbouring sections'
    elements' reach over them (the neighbours' end diameters from their ends to ``at``), so that
    the shaft's mass, centre of mass, inertias and spin moment stay those of its sections
    exactly (:func:`mass_properties`); the piece's stiffness is dropped (a rigid piece)."""
    ends = shaft.ends
    parts = [(+1.0, i, ends[i], ends[i + 1]) for i in range(first, last + 1)]
    if first > 0 and at > ends[first]:
        parts.append((-1.0, first - 1, ends[first], at))
    if last + 1 < len(shaft.sections) and at < ends[last + 1]:
        parts.append((-1.0, last + 1, at, ends[last + 1]))
    M6, G6 = np.zeros((6, 6)), np.zeros((6, 6))
    for sign, i, z0, z1 in parts:
        section = shaft.sections[i]
        element = (0, i, z1 - z0, _diameters(section.outer, section.length, ends[i], z0, z1),
                   _diameters(section.inner, section.length, ends[i], z0, z1))
        M, G = _node_matrices(replace(shaft, disks=(), point_masses=(), mesh=None),
                              Mesh(z=np.array([z0, z1]), elements=(element,)), ("M", "G"))
        R = rigid_motion(shaft.point(np.array([z0, z1])), shaft.point(at))
        M6 += sign * (R.T @ (M @ R))
        G6 += sign * (R.T @ (G @ R))
    return M6, G6


def _add_block(part, start: int, block) -> None:
    """Append a 3 x 3 ``block`` at rows and columns ``start .. start + 3`` to a matrix's
    ``(rows, cols, data)`` lists (nothing when the matrix is not asked for)."""
    if part is None:
        return
    index = start + np.arange(3)
    part[0].append(np.repeat(index, 3))
    part[1].append(np.tile(index, 3))
    part[2].append(np.asarray(block, dtype=float).ravel())


def _skew(v):
    x, y, z = (float(c) for c in v)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rigid_motion(points, reference) -> np.ndarray:
    """Node motions of a rigid motion ``[u, theta]`` at ``reference``: (6 N, 6)."""
    return shift_matrices(reference, points).transpose(0, 2, 1).reshape(-1, 6)


def mass_properties(shaft: Shaft):
    """Mass [kg], centre of mass (3,) [m], polar and diametral inertia [kg m^2] of the rotor
    (shaft, disks, point masses), from the same matrices the model uses.

    Returns
    -------
    mass, centre, polar, diametral
    """
    # one element per section: a rigid motion's kinetic energy is exact on any mesh
    shaft = replace(shaft, sections=tuple(replace(s, elements=1) for s in shaft.sections))
    coarse = mesh(shaft, [], fraction=0.0)
    (M,) = node_matrices(shaft, coarse, kinds=("M",))
    R = rigid_motion(shaft.point(coarse.z), shaft.start)
    M6 = R.T @ M @ R
    mass = float(M6[0, 0])
    # M6 = B diag(m I, J) B^T about the start: its lower left block is m skew(c - start)
    arm = np.array([M6[5, 1] - M6[4, 2], M6[3, 2] - M6[5, 0], M6[4, 0] - M6[3, 1]]) / (2.0 * mass)
    z = float(arm @ shaft.axis)
    centre = shaft.point(z)
    R_c = rigid_motion(shaft.point(coarse.z), centre)
    J = (R_c.T @ M @ R_c)[3:, 3:]
    rot = rotation(shaft.axis)
    local = rot @ J @ rot.T
    return mass, centre, float(local[2, 2]), float(0.5 * (local[0, 0] + local[1, 1]))


def with_mesh(shaft: Shaft, stations) -> Shaft:
    """``shaft`` with its mesh (a node at each station: ``z`` [m] or ``(label, z)``, :func:`mesh`)."""
    return replace(shaft, mesh=mesh(shaft, stations))


def check_consistent(table: Table, values: dict) -> None:
    """A flexible rotor's table may give its mass, centre of mass and inertias only as
    computed (within :data:`CONSISTENCY` relative)."""
    for key, computed in values.items():
        if key not in table.data:
            continue
        if key == "center_of_mass":
            given = table.vector3(key)
            scale = max(float(np.linalg.norm(computed)), values["_length"])
            ok = float(np.linalg.norm(given - computed)) <= CONSISTENCY * scale
            shown = _fmt(computed)
        elif key.startswith("_"):
            continue
        else:
            given = table.number(key)
            ok = abs(given - computed) <= CONSISTENCY * abs(computed)
            shown = f"{computed:.10g}"
        if not ok:
            raise table.error(key, table.data[key], f"the value computed from the rotor's shaft, disks and "
                              f"point masses, {shown} (or no {key} key: a flexible rotor's {key} follows "
                              "from its shaft)")



def lateral_basis(shaft: Shaft):
    """Each node's motion ``[u, theta]`` (model axes) per lateral coordinate ``[u_a, u_b, theta_a,
    theta_b]`` of every node (the flexible rotor's coordinates without the axial one), sparse (CSR)
    (6 N, 4 N): node ``k``'s rows ``6 k .. 6 k + 2`` take ``a``, ``b`` in columns ``4 k``, ``4 k + 1``,
    its rows ``6 k + 3 .. 6 k + 5`` take them in ``4 k + 2``, ``4 k + 3``."""
    import scipy.sparse

    a, b = transverse_axes(shaft.axis)
    count = shaft.mesh.n_nodes
    node = np.arange(count)
    rows = 6 * node[:, None, None] + np.array([[0, 1, 2]] * 2 + [[3, 4, 5]] * 2)[None]        # (N, 4, 3)
    cols = np.broadcast_to((4 * node[:, None] + np.arange(4))[..., None], rows.shape)
    data = np.broadcast_to(np.array([a, b, a, b]), rows.shape)
    keep = data != 0.0
    return scipy.sparse.csr_matrix((data[keep], (rows[keep], cols[keep])), shape=(6 * count, 4 * count))


#: lateral coordinates (4 per node) up to which :func:`bending_frequencies` solves every mode
#: (a dense ``eigh``); beyond, the lowest few by shift-invert Lanczos on the sparse matrices
DENSE_BENDING = 400
#: modes the sparse route finds at first, doubled (up to :data:`MOST_BENDING`) until one is
#: mostly bending
FIRST_BENDING, MOST_BENDING = 12, 192


def bending_frequencies(shaft: Shaft, supports=()):
    """The first bending natural frequency [Hz] of a flexible rotor at rest, free-free, and its
    lowest modes on its supports (the stator held still) with their share of strain energy in
    the shaft.

    Parameters
    ----------
    shaft : Shaft
        With its mesh.
    supports : sequence of (z [m], ndarray (6, 6))
        Each bearing's stiffness on the node's motion ``[u, theta]`` (model axes) at rest; its
        symmetric part is used.

    Returns
    -------
    free : float
        Free-free: the lowest frequency after the four rigid-body motions (two per plane) [Hz].
    lowest : (float, float)
        On the supports: the lowest mode's frequency [Hz] and the fraction of its strain energy
        in the shaft (the rest in the bearings).
    bending : float
        On the supports: the lowest mode with over half its strain energy in the shaft [Hz]
        (nan if none; on a mesh of over :data:`DENSE_BENDING` lateral coordinates, nan too if
        none among the lowest :data:`MOST_BENDING`).
    """
    import scipy.sparse

    M, K = node_matrices(shaft, shaft.mesh, kinds=("M", "K"))
    L = lateral_basis(shaft)
    mass, shaft_k = (L.T @ M @ L).tocsr(), (L.T @ K @ L).tocsr()
    mass, shaft_k = 0.5 * (mass + mass.T), 0.5 * (shaft_k + shaft_k.T)
    supported_k = shaft_k.copy()
    for z, k6 in supports:
        i = 6 * shaft.mesh.node(z)
        rows = L[i:i + 6]
        supported_k = supported_k + rows.T @ scipy.sparse.csr_matrix(0.5 * (k6 + k6.T)) @ rows
    if mass.shape[0] <= DENSE_BENDING:
        return _bending_dense(mass.toarray(), shaft_k.toarray(), supported_k.toarray())
    return _bending_sparse(mass.tocsc(), shaft_k.tocsc(), supported_k.tocsc())


def _bending_dense(mass, shaft_k, supported_k):
    """:func:`bending_frequencies` from every mode (dense ``eigh``), each matrix (4 N, 4 N)."""
    import scipy.linalg

    free = scipy.linalg.eigh(shaft_k, mass, eigvals_only=True)
    values, vectors = scipy.linalg.eigh(supported_k, mass)
    return (_hz(free[4]),) + _supported(values, vectors, shaft_k, supported_k)


def off_node(shaft, z: float):
    """Where a load or station at ``z`` [m] from a shaft's start stands against its mesh: ``(node,
    offset)``, the nearest node and ``z`` less that node's place [m], or None where the point
    shares the node as the mesh's own stations do (within :data:`MERGE_FRACTION` of the element
    it lies in, and at least :data:`STATION_TOLERANCE`): a point a node stands for.

    Parameters
    ----------
    shaft : Shaft
        With its mesh.
    z : float [m]

    Returns
    -------
    (int, float) or None
    """
    nodes = np.asarray(shaft.mesh.z, dtype=float)
    node = shaft.mesh.node(z)
    offset = float(z) - float(nodes[node])
    inside = int(np.clip(np.searchsorted(nodes, z) - 1, 0, len(nodes) - 2))
    element = float(nodes[inside + 1] - nodes[inside])
    if abs(offset) <= max(MERGE_FRACTION * element, STATION_TOLERANCE * (1.0 + shaft.length)):
        return None
    return node, offset


#: a part's strain energy is none where it is within this many ``eps`` of ``1/2 |phi|^T |K| |phi|``,
#: what rounding can make of a product that is zero (measured: up to 0.1 of it for rigid-body modes
#: of a 2 mm shaft and a 1000 m disk; a strained part has 1e11 of it and more); the rule of
#: ``analysis.modal``'s strain-energy shares and of :func:`held_modes`
ENERGY_ROUND_OFF = 1e3


def held_modes(values, vectors, stiffness, shift=0.0):
    """Which undamped modes a stiffness holds: not a rigid-body motion it leaves free.

    A mode is free when its eigenvalue ``omega^2 = phi^T K phi`` (``phi`` mass-normalised) lies
    within the rounding of that product and of the solver's shift,
    :data:`ENERGY_ROUND_OFF` ``eps (|phi|^T |K| |phi| + |shift|)``
    (the rule that sets a mode's strain energy in a part to none; a shift-invert solve about
    ``shift`` returns ``1/theta + shift``, rounded to ``eps |shift|``: a body no spring touches
    has ``|K| phi = 0`` and its zero comes back as ``1e-14`` from a shift of ``-5``). The rule is
    the mode's own: a bound set from the highest mode instead (``1e-9`` of it, before) took a
    pinned shaft's first bending mode for a free motion where a fine mesh or very stiff bearings
    raise the highest mode (a 2 m, 20 mm shaft of 500 elements on 1e8 N/m bearings: 9.9 Hz,
    ``omega^2 = 3.9e3`` against ``1e-9`` of ``5e12``; its rounding is ``1e-4``).

    Parameters
    ----------
    values : ndarray, shape (k,) [rad^2/s^2]
        Eigenvalues ``omega^2`` of ``K phi = omega^2 M phi``.
    vectors : ndarray, shape (n, k)
        Their shapes, mass-normalised (``phi^T M phi = 1``, as ``eigh`` and ``eigsh`` give them).
    stiffness : ndarray or scipy.sparse matrix, shape (n, n) [N/m, N m/rad]
        The symmetric stiffness ``K``.
    shift : float [rad^2/s^2]
        The shift of a shift-invert solve that found them (0: a direct solve, ``eigh``).

    Returns
    -------
    ndarray of bool, shape (k,)
    """
    size = abs(stiffness) if hasattr(stiffness, "multiply") else np.abs(stiffness)
    rounding = np.einsum("im,im->m", np.abs(vectors), size @ np.abs(vectors)) + abs(shift)
    return values > ENERGY_ROUND_OFF * np.finfo(float).eps * rounding


def _supported(values, vectors, shaft_k, supported_k, shift=0.0):
    """The lowest mode (frequency [Hz], share of strain energy in the shaft) and the lowest mostly
    bending (or nan) of modes ``values`` (k,) ascending, ``vectors`` (4 N, k) mass-normalised, of
    ``supported_k`` (the shaft's and the supports' stiffness; ``shift`` that of a shift-invert
    solve); a rigid-body motion the supports leave free (:func:`held_modes`) counts as
    frequency 0."""
    held = held_modes(values, vectors, supported_k, shift)
    values = np.where(held, values, 0.0)
    energy = np.einsum("im,im->m", vectors, shaft_k @ vectors)
    share = np.where(held, energy / np.where(held, values, 1.0), 0.0)
    bending = values[(share > 0.5) & held]
    return (_hz(values[0]), float(share[0])), _hz(bending[0]) if bending.size else float("nan")


def _bending_sparse(mass, shaft_k, supported_k):
    """:func:`bending_frequencies` of a long mesh from its lowest modes only: shift-invert Lanczos
    (``eigsh``) about ``-s``, just below zero (the rigid-body motions make ``K`` singular; ``s`` a
    ``1e-12`` part of the largest diagonal ratio ``K_ii / M_ii``, the scale of the highest mode:
    ``K + s M`` stays well inside double precision, and the eigenvalues ``1/theta - s`` keep their
    digits while ``s`` is below a thousand times the lowest)."""
    import scipy.sparse.linalg

    from .._blas import seeded_start

    diagonal = mass.diagonal()
    largest = float(np.max(shaft_k.diagonal() / np.where(diagonal > 0, diagonal, np.inf)))
    largest = max(largest, float(np.max(supported_k.diagonal() / np.where(diagonal > 0, diagonal, np.inf))))
    shift = -1e-12 * largest

    def lowest(stiffness, count):
        values, vectors = scipy.sparse.linalg.eigsh(stiffness, k=count, M=mass, sigma=shift, which="LM",
                                                    v0=seeded_start(stiffness.shape[0]))
        order = np.argsort(values)
        return values[order], vectors[:, order]

    free = lowest(shaft_k, 5)[0]
    count = FIRST_BENDING
    while True:
        values, vectors = lowest(supported_k, min(count, mass.shape[0] - 2))
        (first, share), bending = _supported(values, vectors, shaft_k, supported_k, shift)
        if bending == bending or count >= MOST_BENDING:
            return _hz(free[4]), (first, share), bending
        count *= 2


def _hz(value: float) -> float:
    """The frequency [Hz] of an eigenvalue omega^2 [rad^2/s^2]."""
    return float(np.sqrt(max(value, 0.0)) / (2 * np.pi))
