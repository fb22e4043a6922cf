"""Rotors saved by ROSS (``Rotor.save``, a TOML file) read into this package's model-file
description: a flexible rotor with its shaft, disks and bearings (``docs/ross.md``).

ROSS is not imported: the file is read with :mod:`tomllib`. A ROSS file holds one table per
element, named ``<ElementClass>_<tag>``, with the arguments that rebuild it (ROSS's
``ross/rotor_assembly.py`` ``Rotor.save``); ``parameters`` holds the rotor's own.

Axes: ROSS's ``x, y, z`` (``z`` along the shaft, spin about ``+z``) become the model's axes as
they are, ``spin_axis = [0, 0, 1]``, so the rotor's transverse axes ``a, b`` are ``x, y``
(``rotordyn_modal.model.geometry.transverse_axes``) and a ROSS bearing's
``[[kxx, kxy], [kyx, kyy]]`` is this package's bearing ``stiffness`` matrix in its default
axes, signs unchanged (both are the stiffness added to the equations of motion, force on the
shaft ``-K u``). The shaft starts at the origin (ROSS's node 0).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

from ..errors import ModelError, ModelWarning
from .atomic import atomic_write, check_not_input
from .model_file import read_toml
from .text import shown_text

__all__ = ["read_ross_rotor", "check_description", "write_model_file", "model_text", "BEARING_CLASSES"]

#: ROSS element classes whose saved tables hold their coefficients (read as bearings)
BEARING_CLASSES = ("BearingElement", "SealElement", "BallBearingElement", "RollerBearingElement")
_COEFFICIENTS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy", "kzz", "czz")
_MASS_COEFFICIENTS = ("mxx", "mxy", "myx", "myy", "mzz")
#: why an element class that ROSS saves cannot be read
_REFUSED = {
    "PointMass": "a ROSS point mass is a support mass linked to the shaft through bearings "
                 "(n_link); bearings on pedestals are not read",
    "MagneticBearingElement": "an active magnetic bearing (its controller) is not modelled; "
                              "give its equivalent coefficients as a BearingElement",
}
_RAD_S_TO_RPM = 30.0 / math.pi
#: the keys ROSS (0.4 to 3.1) saves in each element's table: its ``__init__`` arguments
#: (``Element.save``); a bearing's table also holds what a subclass saved under
#: ``BearingElement_<tag>`` keeps (``BearingElement.save``), so only its near misses are refused
_SHAFT_KEYS = ("L", "idl", "odl", "idr", "odr", "material", "n", "axial_force", "torque", "shear_effects",
               "rotary_inertia", "gyroscopic", "shear_method_calc", "tag", "alpha", "beta", "color")
_DISK_KEYS = ("n", "m", "Id", "Ip", "tag", "scale_factor", "color")
_MATERIAL_KEYS = ("name", "rho", "E", "G_s", "Poisson", "specific_heat", "thermal_conductivity", "color")
_BEARING_KEYS = ("n", *_COEFFICIENTS, *_MASS_COEFFICIENTS, "speed", "frequency", "tag", "n_link", "scale_factor",
                 "color", "interpolation", "radial_clearance", "seal_leakage", "n_balls", "d_balls", "n_rollers",
                 "l_rollers", "fs", "alpha")
_PARAMETER_KEYS = ("min_w", "max_w", "rated_w", "modal_damping_ratio", "default_damping_ratio", "alpha", "beta", "tag")
#: the ROSS versions whose saves this reader was checked on (oldest, newest), as (major, minor)
ROSS_VERSIONS = ((0, 4), (3, 1))
#: what ``import-ross`` reads, said when a file is something else
ROSS_SAVE = ("a rotor saved by ROSS's Rotor.save('NAME.toml'): one TOML file of tables 'ShaftElement_<tag>', "
             "'DiskElement_<tag>', 'BearingElement_<tag>', ... as ROSS 0.4 to 3.1 write it (docs/ross.md)")


#: the rotor's name when neither ``--name`` nor the file's name gives one (a pipe)
DEFAULT_NAME = "rotor"


def without_name(path) -> bool:
    """True when ``path`` names a pipe or a descriptor, not a file whose stem names the rotor:
    ``/dev/fd/N`` (bash's ``<(cat r.toml)``), ``/proc/self/fd/N``, ``/proc/PID/fd/N``,
    ``/dev/stdin``."""
    import re

    text = str(path)
    return (text in ("/dev/stdin", "-") or re.fullmatch(r"/dev/fd/\d+|/proc/(self|\d+)/fd/\d+", text) is not None)


def read_ross_rotor(path, name: str | None = None) -> dict:
    """Read a rotor saved by ROSS's ``Rotor.save`` (TOML) into a model-file description.

    Parameters
    ----------
    path : str or path-like
        The ROSS file.
    name : str, optional
        The rotor's name. By default the file's stem (ROSS's ``Rotor.save`` writes no name of the
        rotor), or :data:`DEFAULT_NAME` for a pipe, whose name (``/dev/fd/63`` of ``<(cat r.toml)``,
        ``/dev/stdin``) is no file's (:func:`without_name`).

    Returns
    -------
    dict
        A model file's tables (``docs/model-file.md``): ``name``, ``spin_axis`` ``[0, 0, 1]``,
        ``materials``, one flexible rotor (``shaft``: one section per ROSS shaft element, with
        ``elements = 1``; ``disks``) starting at the origin, and its ``bearings`` placed by
        ``axial_position`` [m].

    Raises
    ------
    ModelError
        The file is not a ROSS rotor, or holds what this package does not model (named:
        the element, the key, the value and why), e.g. proportional damping, bearing mass
        coefficients, a point mass, a magnetic bearing, mixed shear options; a key that is a
        near miss of one ROSS saves and the table lacks (``odll``: "did you mean 'odl'?").

    Warns
    -----
    ModelWarning
        A ``ross_version`` newer than :data:`ROSS_VERSIONS` (or no version number); keys of
        shaft, disk and material tables that ROSS does not save (not read); coefficient tables
        that ROSS interpolates otherwise.
    """
    source = str(path)
    data = _read_ross_data(path)
    elements = _elements(source, data)
    _check_element_keys(source, elements)
    _warn_version(source, data.get("ross_version"))
    _check_parameters(source, data)
    named = not without_name(source)
    rotor_name = name or (shown_text(Path(source).stem) if named else DEFAULT_NAME)
    materials: dict[str, dict] = {}
    sections, shear, node_z = _shaft(source, elements.get("ShaftElement", []), materials)
    rotor = {"name": rotor_name, "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "shear": shear,
             "shaft": sections}
    pchip: list = []
    try:
        disks = _disks(source, elements.get("DiskElement", []), node_z)
        bearings = [_bearing(source, key, table, node_z, rotor_name, pchip)
                    for cls in BEARING_CLASSES for key, table in elements.get(cls, [])]
    except ModelError as error:   # a node beyond the shaft: say so when a repeated n shortened it
        note = _repeated_note(elements.get("ShaftElement", []), node_z) if error.where.endswith("] n") else ""
        if not note or not error.expected.startswith("a node of the shaft"):
            raise
        raise ModelError(source, error.where, error.value, error.expected + note) from None
    if disks:
        rotor["disks"] = disks
    _warn_pchip(source, pchip)
    bearings.sort(key=lambda b: b["axial_position"])
    version = data.get("ross_version", "unknown")
    origin = (f"file {shown_text(Path(source).name)}" if named else
              "file read from standard input" if source in ("/dev/stdin", "-") else "file read from a pipe")
    return {"name": f"{rotor_name} (ROSS {version} {origin})", "spin_axis": [0.0, 0.0, 1.0],
            "materials": list(materials.values()), "rotors": [rotor], "bearings": bearings}


def _read_ross_data(path) -> dict:
    """The TOML tables of ``path``, or one line saying what the file is instead and what is
    read: a JSON file (ROSS 2.1 and later save JSON when the name ends in ``.json``), text that
    is no TOML, an empty or binary file."""
    try:
        return read_toml(path, "ROSS rotor file")
    except ModelError as error:
        if error.where != "<file>" or not (error.expected == "valid TOML" or "TOML" in error.expected
                                            and error.expected.startswith(("UTF-8", "a ROSS rotor file"))):
            raise   # a missing file, a folder, an unreadable one: said as for any input
        if error.expected == "valid TOML":
            value, expected = _not_toml(path, error.value)
        elif error.expected.startswith("UTF-8"):   # 'byte 24': a binary file (a spreadsheet, a pickle)
            value, expected = f"{error.value}: no UTF-8 text", ROSS_SAVE
        else:
            value, expected = error.value, ROSS_SAVE
        raise ModelError(error.source, "<file>", value, expected) from None


def _not_toml(path, problem: str) -> tuple:
    """What a file that is no TOML holds, and what is expected instead: ``(value, expected)``
    of the message. JSON is recognised in a file that can be read again (not a pipe)."""
    import json

    from .limits import read_limited
    from .text import decode_text

    document = None
    if Path(path).is_file():
        try:
            document = json.loads(decode_text(read_limited(path, "model", "ROSS rotor file")))
        except (ValueError, OSError, RecursionError):
            document = None
    if isinstance(document, dict) and any(str(key).startswith("ShaftElement_") for key in document):
        name = Path(path).stem
        return ("a rotor saved by ROSS as JSON (Rotor.save('NAME.json'), ROSS 2.1 and later)",
                f"its TOML save, which import-ross reads: in ROSS, Rotor.load('{name}.json').save('{name}.toml') "
                "writes it (docs/ross.md)")
    if isinstance(document, dict):
        keys = ", ".join(shown_text(str(key)) for key in list(document)[:4]) + (", ..." if len(document) > 4 else "")
        return f"JSON, not TOML (keys {keys})" if document else "JSON, not TOML (an empty object)", ROSS_SAVE
    if document is not None:
        return f"JSON, not TOML (a {type(document).__name__})", ROSS_SAVE
    return f"no TOML: {problem}", ROSS_SAVE


def check_description(description: dict, source) -> None:
    """Refuse a rotor read from a ROSS file that is no valid model (a negative length,
    density or coefficient, a disk's inertias that no body has, bearings that hold nothing),
    before a model file is written that ``check`` would refuse.

    Parameters
    ----------
    description : dict
        From :func:`read_ross_rotor`.
    source : str or path-like
        The ROSS file, named in the message.

    Raises
    ------
    ModelError
        Naming the ROSS file and the model file's key (section ``k`` is ROSS's shaft element
        starting at node ``k``; disks and bearings keep ROSS's tags).

    Warns
    -----
    ModelWarning
        What is legal but probably not meant, as ``check`` says it of the model file
        (:func:`rotordyn_modal.plausibility.implausible`: a modulus or a diameter in other units).
    """
    from ..plausibility import implausible
    from ..model.machine import Model

    _check_support_points(description, source)
    try:
        model = Model.from_dict(description, source=str(source))
    except ModelError as error:
        raise ModelError(str(source), f"{error.where} (in the model file it makes)", error.value,
                         error.expected) from None
    for line in implausible(model):   # what `check` would warn about, said before it is written
        warnings.warn(line, ModelWarning, stacklevel=2)


def _check_support_points(description: dict, source) -> None:
    """Refuse, in ROSS's words, a rotor on bearings and seals at fewer than two nodes. ROSS's
    bearings and seals hold translations only, so such a rotor is free to tilt (without bearings,
    free-free); ROSS solves it and leaves the rigid-body roots at zero frequency out of its
    modes, while a model of this package holds every motion of a rotor on bearings (the model's
    refusal named a ``moment_stiffness`` that a ROSS file cannot give). A rotor on one bearing
    and a seal at another node is held and read."""
    bearings = description.get("bearings", [])
    nodes = sorted({b["axial_position"] for b in bearings})
    if len(nodes) >= 2:
        return
    how = ("give it a BearingElement or SealElement at two nodes or more in ROSS and save it again, or read it "
           "in Python (rotordyn_modal.io.ross_file.read_ross_rotor) and add a bearing, or a moment_stiffness, "
           "before Model.from_dict (docs/ross.md)")
    if not bearings:
        raise ModelError(str(source), "<file>", "no BearingElement or SealElement tables",
                         "bearings at two nodes of the shaft or more: ROSS solves a rotor without bearings free-free "
                         f"(its rigid-body roots at zero frequency left out), which this package does not model; {how}")
    names = ", ".join(repr(b["name"]) for b in bearings)
    raise ModelError(str(source), "bearings", f"{names}, all at z = {nodes[0]:g} m",
                     "bearings or seals at two nodes of the shaft or more: ROSS's bearings hold translations only, "
                     "so on one node the rotor is free to tilt (ROSS leaves the tilt's roots at zero frequency "
                     f"out of its modes), which this package does not model; {how}")


def write_model_file(description: dict, path, inputs=()) -> None:
    """Write a model description as a TOML model file, atomically, never over ``inputs``.

    Parameters
    ----------
    description : dict
        From :func:`read_ross_rotor`.
    path : str or path-like
    inputs : iterable of path-like
        Files that must not be overwritten (the ROSS file).
    """
    check_not_input(path, list(inputs))
    with atomic_write(path, "w", encoding="utf-8") as handle:
        handle.write(model_text(description))


def model_text(description: dict) -> str:
    """The model file's text: a two-line comment on its origin and axes, then the TOML."""
    import tomli_w

    return ("# Read from a ROSS rotor file by rotordyn-modal import-ross (docs/ross.md).\n"
            "# ROSS axes x, y, z are the model axes; the shaft starts at the origin, spin about +z.\n"
            + tomli_w.dumps(description))


# --------------------------------------------------------------------------- elements


def _elements(source: str, data: dict) -> dict[str, list]:
    """The file's element tables grouped by ROSS class, in file order: ``{class: [(key, table)]}``."""
    if "ShaftElement" not in {key.split("_")[0] for key in data}:
        if {"rotors", "stator"} & set(data):   # this package's own model file: nothing to import
            raise ModelError(source, "<file>", "a model file of rotordyn-modal (no ShaftElement tables)",
                             f"{ROSS_SAVE}; a model file is read as it is: rotordyn-modal check {source}")
        keys = ", ".join(shown_text(str(key)) for key in list(data)[:4]) + (", ..." if len(data) > 4 else "")
        raise ModelError(source, "<file>", f"no ShaftElement tables (keys {keys})", ROSS_SAVE)
    grouped: dict[str, list] = {}
    for key, table in data.items():
        if key in ("parameters", "ross_version") or key.startswith("_"):
            continue
        cls = key.split("_")[0]
        if not isinstance(table, dict):
            raise ModelError(source, f"[{key}]", table, "a table of a ROSS element")
        if cls in _REFUSED:
            raise ModelError(source, f"[{key}]", cls, f"an element this package reads: {_REFUSED[cls]}")
        if cls not in ("ShaftElement", "DiskElement", *BEARING_CLASSES):
            raise ModelError(source, f"[{key}]", cls, "a ROSS element this package reads: ShaftElement, "
                             "DiskElement, " + ", ".join(BEARING_CLASSES))
        grouped.setdefault(cls, []).append((key, table))
    return grouped


def _check_element_keys(source: str, elements: dict) -> None:
    """Refuse a key that is a near miss of one ROSS saves and the table lacks (``odll`` for
    ``odl``, ``kyyy`` for ``kyy``: read, the element would take ROSS's default or be refused as
    missing the key); say in one warning line which other keys of shaft, disk and material
    tables are not read (bearing tables hold what ROSS's bearing subclasses save)."""
    from ..model._table import close_key, did_you_mean

    unread = []
    for cls, tables in elements.items():
        for key, table in tables:
            known = _BEARING_KEYS if cls in BEARING_CLASSES else _SHAFT_KEYS if cls == "ShaftElement" else _DISK_KEYS
            places = [(f"[{key}]", table, known)]
            if cls == "ShaftElement" and isinstance(table.get("material"), dict):
                places.append((f"[{key}.material]", table["material"], _MATERIAL_KEYS))
            for where, keys, allowed in places:
                for name in keys:
                    if name in allowed:
                        continue
                    absent = [a for a in allowed if a not in keys]
                    same = [a for a in absent if a.lower() == str(name).lower()]   # 'Kxx' for 'kxx'
                    meant = same[0] if same else close_key(name, absent)
                    if meant is not None:
                        raise ModelError(source, f"{where} {shown_text(str(name))}", keys[name],
                                         f"one of the keys ROSS saves in a {cls}{did_you_mean(meant)}")
                    if cls not in BEARING_CLASSES:
                        unread.append(f"{where} {shown_text(str(name))}")
    if unread:
        warnings.warn(f"{shown_text(source)}: {len(unread)} key{'s' if len(unread) > 1 else ''} that ROSS does not "
                      f"save, not read: {', '.join(unread[:3])}{', ...' if len(unread) > 3 else ''} (docs/ross.md, "
                      "'What is read')", ModelWarning, stacklevel=3)


def _warn_version(source: str, version) -> None:
    """One warning line for a ``ross_version`` outside :data:`ROSS_VERSIONS` (a newer one's saves
    may hold what this reader does not know, an older one's were never compared), or that is no
    version number."""
    import re

    if version is None:
        return
    (old_major, old_minor), (major, minor) = ROSS_VERSIONS
    tested = f"ROSS {old_major}.{old_minor} to {major}.{minor}"
    found = re.match(r"\s*v?(\d+)\.(\d+)", version) if isinstance(version, str) else None
    if found is None:
        warnings.warn(f"{shown_text(source)}: ross_version = {version!r}: no version number (e.g. '3.1.0'); "
                      f"read as a save of {tested}, the versions this reader was checked on (docs/ross.md)",
                      ModelWarning, stacklevel=3)
    elif not (old_major, old_minor) <= (int(found[1]), int(found[2])) <= (major, minor):
        side = "newer" if (int(found[1]), int(found[2])) > (major, minor) else "older"
        warnings.warn(f"{shown_text(source)}: ross_version = {version!r}: {side} than the ROSS versions this reader "
                      f"was checked on ({tested}); read as their saves are: compare its totals and modes with "
                      "ROSS's (docs/ross.md)", ModelWarning, stacklevel=3)


def _check_parameters(source: str, data: dict) -> None:
    """Refuse the rotor-level damping ROSS adds to the matrices (not modelled here)."""
    from ..model._table import close_key, did_you_mean

    parameters = data.get("parameters", {})
    if not isinstance(parameters, dict):
        raise ModelError(source, "parameters", parameters, "a table")
    for name in parameters:     # 'alpah' for 'alpha': proportional damping lost without a word
        meant = None if name in _PARAMETER_KEYS else close_key(name, [k for k in _PARAMETER_KEYS
                                                                         if k not in parameters])
        if meant is not None:
            raise ModelError(source, f"[parameters] {shown_text(str(name))}", parameters[name],
                             "one of the keys ROSS saves in [parameters]" + did_you_mean(meant))
    for key in ("alpha", "beta", "default_damping_ratio"):
        value = parameters.get(key, 0.0)
        if _number(source, f"[parameters] {key}", value) != 0.0:
            raise ModelError(source, f"[parameters] {key}", value,
                             "0: proportional and modal damping of the rotor are not modelled")
    if parameters.get("modal_damping_ratio"):
        raise ModelError(source, "[parameters] modal_damping_ratio", parameters["modal_damping_ratio"],
                         "none: modal damping of the rotor is not modelled")


def _number(source: str, where: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ModelError(source, where, value, "a finite number")
    return float(value)


def _get(source: str, key: str, table: dict, name: str, default=None) -> float:
    if name not in table:
        if default is None:
            raise ModelError(source, f"[{key}] {name}", "<missing>", "a number")
        return default
    return _number(source, f"[{key}] {name}", table[name])


# --------------------------------------------------------------------------- shaft


def _shaft(source: str, shafts: list, materials: dict) -> tuple[list, str, list]:
    """Sections (one per ROSS node pair, parallel elements as ``layers``), the rotor's shear
    option, and the axial position of every ROSS node [m]."""
    spans: dict[int, list] = {}
    shears = {}
    for key, table in shafts:
        n = table.get("n", "<missing>")     # was shown as 'n = None'
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise ModelError(source, f"[{key}] n", n, "the element's first node, an integer >= 0")
        spans.setdefault(n, []).append((key, table))
        shears[key] = _element_options(source, key, table)
    missing = sorted(set(range(max(spans) + 1)) - set(spans))
    if missing:
        _refuse_gap(source, spans, missing[0])
    if len(set(shears.values())) > 1:
        first = next(iter(shears))
        other = next(k for k, v in shears.items() if v != shears[first])
        raise ModelError(source, f"[{other}] shear", shears[other],
                         f"the shear option of the other elements ({shears[first]!r} in [{first}]): "
                         "one shear option per rotor")
    sections, node_z = [], [0.0]
    for n in range(len(spans)):
        (key, table), *parallel = spans[n]
        section = {"length": _get(source, key, table, "L"), **_tube(source, key, table, materials),
                   "elements": 1}
        for other_key, other in parallel:
            length = _get(source, other_key, other, "L")
            if abs(length - section["length"]) > 1e-9 * section["length"]:
                raise ModelError(source, f"[{other_key}] L", length, f"the length {section['length']!r} of "
                                 f"[{key}], which starts at the same node n = {n}: a repeated n is a parallel "
                                 "element over the same span, as in ROSS (or give the element the n of its own "
                                 "first node)")
            section.setdefault("layers", []).append(_tube(source, other_key, other, materials))
        sections.append(section)
        node_z.append(node_z[-1] + section["length"])
    return sections, next(iter(shears.values())), node_z


def _refuse_gap(source: str, spans: dict, gap: int) -> None:
    """Refuse shaft elements that leave node ``gap`` without an element starting there, naming
    the element whose repeated ``n`` most likely took its place (ROSS would join no element to
    that node: two pieces of shaft; a repeated ``n`` is a parallel element there and in ROSS)."""
    last = max(spans)
    repeated = sorted(n for n, group in spans.items() if len(group) > 1)
    if not repeated:
        raise ModelError(source, "ShaftElement n", gap, f"consecutive nodes 0..{last} "
                         "(no shaft element starts at this node)")
    n = max([r for r in repeated if r < gap] or repeated)
    first, again = spans[n][0][0], spans[n][-1][0]
    raise ModelError(source, f"[{again}] n", n, f"each node 0..{last} to start a shaft element: n = {n} is "
                     f"repeated ([{first}] starts there too; a repeated n is a parallel element over the same "
                     f"span, as in ROSS) and no shaft element starts at node {gap}")


def _repeated_note(shafts: list, node_z: list) -> str:
    """Why the shaft ends where it does when some shaft elements repeat an ``n``: words added to
    the message of a disk or bearing beyond its last node (ROSS: 'outside shaft'), or ''."""
    starts: dict = {}
    for key, table in shafts:
        starts.setdefault(table.get("n"), []).append(key)
    repeated = [(n, keys) for n, keys in starts.items() if len(keys) > 1]
    if not repeated:
        return ""
    n, keys = repeated[-1]
    return (f"; the shaft's last node is {len(node_z) - 1} because n = {n} is repeated ([{keys[0]}] and "
            f"[{keys[-1]}]: a repeated n is a parallel element over the same span, as in ROSS)")


def _element_options(source: str, key: str, table: dict) -> str:
    """The element's shear option (``cowper`` or ``none``); refuses what the package does not
    model: no rotary inertia, no gyroscopic terms, axial force, torque, proportional damping,
    ROSS's ``hutchinson`` shear coefficient (not Hutchinson's, ``docs/ross.md``)."""
    for option in ("rotary_inertia", "gyroscopic"):
        if table.get(option, True) is not True:
            raise ModelError(source, f"[{key}] {option}", table[option],
                             "true: shaft elements always carry rotary inertia and gyroscopic terms here")
    for option, meaning in (("axial_force", "axial force"), ("torque", "torque"),
                            ("alpha", "mass-proportional damping"), ("beta", "stiffness-proportional damping")):
        if _get(source, key, table, option, 0.0) != 0.0:
            raise ModelError(source, f"[{key}] {option}", table[option], f"0: {meaning} is not modelled")
    effects = table.get("shear_effects", True)
    if not isinstance(effects, bool):
        raise ModelError(source, f"[{key}] shear_effects", effects, "true or false")
    method = table.get("shear_method_calc", "cowper")
    if effects and method == "hutchinson":
        raise ModelError(source, f"[{key}] shear_method_calc", method, "'cowper': ROSS 3's 'hutchinson' "
                         "coefficient has (1 + nu) where Hutchinson's (2001), this package's, has (1 + nu)^2 "
                         "(0.71 against 0.93 for solid steel), so it cannot be reproduced")
    if effects and method != "cowper":
        raise ModelError(source, f"[{key}] shear_method_calc", method, "'cowper'")
    return "cowper" if effects else "none"


def _tube(source: str, key: str, table: dict, materials: dict) -> dict:
    """Outer and inner diameters (a [left, right] pair when tapered) and the material's name."""
    odl, idl = _get(source, key, table, "odl"), _get(source, key, table, "idl")
    odr, idr = _get(source, key, table, "odr", odl), _get(source, key, table, "idr", idl)
    for side, outer, inner in (("l", odl, idl), ("r", odr, idr)):
        if not outer > inner >= 0.0:
            raise ModelError(source, f"[{key}] id{side}, od{side}", [inner, outer],
                             "0 <= inner diameter < outer diameter")
    return {"outer_diameter": odl if odl == odr else [odl, odr],
            "inner_diameter": idl if idl == idr else [idl, idr],
            "material": _material(source, key, table.get("material"), materials)}


def _material(source: str, key: str, table, materials: dict) -> str:
    """Add the element's material to ``materials`` (once per distinct material); its name."""
    if table is None:   # was 'material = None': ROSS writes the materials last, so a save cut short lacks them
        raise ModelError(source, f"[{key}] material", "<missing>", f"a table [\"{key}\".material] with name, rho, E "
                         "and G_s (Rotor.save writes one for each shaft element after all the elements: is the "
                         "file cut short?)")
    if not isinstance(table, dict):
        raise ModelError(source, f"[{key}] material", table, "a table with name, rho, E and G_s")
    where = f"{key}.material"
    found = {"density": _get(source, where, table, "rho"), **_elastic(source, where, table)}
    base = str(table.get("name", "material"))
    name, count = base, 1
    while name in materials and {k: v for k, v in materials[name].items() if k != "name"} != found:
        count += 1
        name = f"{base}-{count}"  # a name ROSS gave two different materials
    materials.setdefault(name, {"name": name, **found})
    return name


def _elastic(source: str, where: str, table: dict) -> dict:
    """The material's elastic constants as the model file's keys: ROSS's ``Material`` takes
    two of ``E``, ``G_s`` and ``Poisson`` and computes the third (``Rotor.save`` writes ``E``
    and ``G_s``; a file written by hand may give ``Poisson``); all three must agree."""
    given = [name for name in ("E", "G_s", "Poisson") if name in table]
    e, g, nu = (_get(source, where, table, name, math.nan) for name in ("E", "G_s", "Poisson"))
    if len(given) < 2:
        missing = " or ".join(name for name in ("E", "G_s", "Poisson") if name not in given)
        raise ModelError(source, f"[{where}] {missing}", "<missing>", "two of E, G_s and Poisson (ROSS's "
                         f"Material computes the third); the table gives {', '.join(given) or 'none of them'}")
    if len(given) == 3 and not math.isclose(e / (2.0 * g) - 1.0, nu, rel_tol=1e-6, abs_tol=1e-9):
        raise ModelError(source, f"[{where}] Poisson", nu, f"E / (2 G_s) - 1 = {e / (2.0 * g) - 1.0:.9g} "
                         "of the table's E and G_s (or give two of the three)")
    if "E" not in given:   # ROSS: E = G_s (2 (1 + Poisson))
        return {"young_modulus": g * 2.0 * (1.0 + nu), "shear_modulus": g}
    if "G_s" not in given:
        return {"young_modulus": e, "poisson_ratio": nu}
    return {"young_modulus": e, "shear_modulus": g}


# --------------------------------------------------------------------------- disks, bearings


def _node(source: str, key: str, table: dict, node_z: list) -> float:
    n = table.get("n", "<missing>")         # was shown as 'n = None'
    if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n < len(node_z):
        raise ModelError(source, f"[{key}] n", n, f"a node of the shaft, 0..{len(node_z) - 1}")
    return node_z[n]


def _disks(source: str, disks: list, node_z: list) -> list:
    """Rigid disks at their nodes; two disks on one node become one (ROSS adds them)."""
    found: dict[float, dict] = {}
    for key, table in disks:
        z = _node(source, key, table, node_z)
        disk = {"name": str(table.get("tag", key.partition("_")[2])), "axial_position": z,
                "mass": _get(source, key, table, "m"), "polar_inertia": _get(source, key, table, "Ip"),
                "diametral_inertia": _get(source, key, table, "Id")}
        if z in found:
            same = found[z]
            same["name"] += " + " + disk["name"]
            for k in ("mass", "polar_inertia", "diametral_inertia"):
                same[k] += disk[k]
        else:
            found[z] = disk
    return sorted(found.values(), key=lambda d: d["axial_position"])


def _bearing(source: str, key: str, table: dict, node_z: list, rotor: str, pchip: list) -> dict:
    """A bearing (or seal) of ROSS: its coefficients, constant or tabulated over speed; appends
    to ``pchip`` where ROSS's PCHIP interpolation of its table differs from the linear one
    (:func:`_pchip_difference`)."""
    if table.get("n_link") is not None:
        raise ModelError(source, f"[{key}] n_link", table["n_link"],
                         "none: a bearing linked to a support mass (pedestal) is not read")
    speeds, values = _coefficient_tables(source, key, table)
    if len(speeds) > 2:
        pchip.extend(_pchip_difference(source, key, table, speeds, values))
    bearing = {"name": str(table.get("tag", key.partition("_")[2])), "rotor": rotor,
               "axial_position": _node(source, key, table, node_z)}
    if len(speeds) > 1:
        bearing["speeds_rpm"] = [s * _RAD_S_TO_RPM for s in speeds]
    bearing["stiffness"] = _radial(values, "k")
    if any(v != 0.0 for s in ("xx", "xy", "yx", "yy") for v in values["c" + s]):
        bearing["damping"] = _radial(values, "c")
    if any(v != 0.0 for v in values["kzz"]):
        bearing["axial_stiffness"] = _table_or_constant(values["kzz"])
        if any(v != 0.0 for v in values["czz"]):
            bearing["axial_damping"] = _table_or_constant(values["czz"])
    return bearing


def _coefficient_tables(source: str, key: str, table: dict) -> tuple[list, dict]:
    """The speed axis [rad/s] (empty for constant coefficients) and each coefficient's values
    on it. A table over the whirl ``frequency`` is read as over speed: ROSS's run_modal,
    run_campbell and unbalance responses evaluate it at the speed (synchronous)."""
    axes = [name for name in ("speed", "frequency") if table.get(name) is not None]
    if len(axes) == 2:
        raise ModelError(source, f"[{key}] speed, frequency", "both",
                         "coefficients tabulated over one axis (a table over speed and whirl frequency is not read)")
    axis = table[axes[0]] if axes else []
    if not isinstance(axis, list):
        axis = [axis]
    speeds = [_number(source, f"[{key}] {axes[0]}", s) for s in axis]
    if any(b <= a for a, b in zip(speeds, speeds[1:])):
        raise ModelError(source, f"[{key}] {axes[0]}", axis, "strictly increasing speeds [rad/s]")
    count = len(speeds) or 1
    stray = [name for name in table if name not in _BEARING_KEYS]     # 'speed_rpm' for 'speed' went unnamed
    axis_text = f"[{key}] {axes[0]} = {axis!r} [rad/s]" if axes else f"[{key}] speed, which the table lacks" + (
        f" (it has {', '.join(map(repr, stray[:3]))}{', ...' if len(stray) > 3 else ''}, not read here: the speeds "
        "go in 'speed' [rad/s])" if stray else "")
    for name in _MASS_COEFFICIENTS:
        if any(v != 0.0 for v in _values(source, key, table, name, count, axis_text)):
            raise ModelError(source, f"[{key}] {name}", table[name], "0: bearing mass coefficients are not modelled")
    values = {name: _values(source, key, table, name, count, axis_text) for name in _COEFFICIENTS}
    if count > 1 and all(len(set(v)) == 1 for v in values.values()):
        return [], {name: v[:1] for name, v in values.items()}  # constant over the table
    return (speeds if count > 1 else []), values


def _pchip_difference(source: str, key: str, table: dict, speeds: list, values: dict) -> list:
    """Where ROSS's PCHIP interpolation of a table of 3 or more speeds (``interpolation =
    "pchip"``, ROSS's default; ``"linear"`` is what this package does) differs from the linear
    one between the table's speeds: ``[(difference, key, coefficient, speed [rad/s])]`` for the
    largest difference at an interval's midpoint relative to the coefficient's largest magnitude
    in the table (above 1e-9), else ``[]``."""
    method = table.get("interpolation", "pchip")
    if method not in ("pchip", "linear"):
        raise ModelError(source, f"[{key}] interpolation", method, "'pchip' or 'linear' (ROSS 3.1's methods)")
    if method == "linear":
        return []
    from scipy.interpolate import PchipInterpolator

    axis = [float(s) for s in speeds]
    middle = [(a + b) / 2.0 for a, b in zip(axis, axis[1:])]
    worst = (0.0, "", 0.0)
    for name, column in values.items():
        scale = max(abs(v) for v in column)
        if scale == 0.0:
            continue
        cubic = PchipInterpolator(axis, column)(middle)
        linear = [(a + b) / 2.0 for a, b in zip(column, column[1:])]
        for speed, c, lin in zip(middle, cubic, linear):
            if abs(c - lin) / scale > worst[0]:
                worst = (abs(c - lin) / scale, name, speed)
    return [(worst[0], key, worst[1], worst[2])] if worst[0] > 1e-9 else []


def _warn_pchip(source: str, found: list) -> None:
    """One warning for the tables of ``found`` (:func:`_pchip_difference`), naming the largest."""
    if not found:
        return
    size, key, name, speed = max(found)
    tables = "1 table" if len(found) == 1 else f"{len(found)} tables"
    warnings.warn(f"{shown_text(source)}: {tables} interpolated with PCHIP by ROSS (interpolation = 'pchip') "
                  "and linearly here: between their speeds the coefficients differ (equal at the table "
                  f"speeds), the most [{key}] {name} by {size:.2g} of its largest value at {speed:.6g} rad/s "
                  "(compare at table speeds, or save the ROSS bearings with interpolation='linear'; "
                  "docs/ross.md)", ModelWarning, stacklevel=3)


def _values(source: str, key: str, table: dict, name: str, count: int, axis_text: str) -> list:
    """A coefficient as ``count`` numbers (ROSS defaults: kyy = kxx, cyy = cxx, others 0);
    ``axis_text`` names the table's speeds in the message of a count that differs. ``kxx`` and
    ``cxx`` are required, as ROSS's bearing and seal classes require them (they were read as 0)."""
    if name in ("kxx", "cxx") and name not in table:
        raise ModelError(source, f"[{key}] {name}", "<missing>", f"a number or one per speed: ROSS's {key.split('_')[0]} "
                         "requires kxx and cxx (ROSS's Rotor.save writes every coefficient)")
    default = {"kyy": "kxx", "cyy": "cxx", "myy": "mxx"}.get(name)
    value = table.get(name, table.get(default, 0.0) if default else 0.0)
    if not isinstance(value, list):
        value = [value] * count
    if len(value) != count:
        many = "1 value" if count == 1 else f"{count} values"
        raise ModelError(source, f"[{key}] {name}", value, f"{many}, one per speed of {axis_text}")
    return [_number(source, f"[{key}] {name}", v) for v in value]


def _radial(values: dict, kind: str):
    """``[[xx, xy], [yx, yy]]`` (or a 2-list ``[xx, yy]`` without cross terms), per speed when
    tabulated."""
    xx, xy, yx, yy = (values[kind + s] for s in ("xx", "xy", "yx", "yy"))
    cross = any(v != 0.0 for v in xy + yx)
    rows = [[[a, b], [c, d]] if cross else [a, d] for a, b, c, d in zip(xx, xy, yx, yy)]
    return rows[0] if len(rows) == 1 else rows


def _table_or_constant(values: list):
    return values[0] if len(values) == 1 else values
