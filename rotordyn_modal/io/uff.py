"""Universal Files (UFF) through ``pyuff``: FRFs and coherence (dataset 58/58b) written and read;
time records (58, function type 1), header (151), units (164), coordinate systems (18, 2420)
and node coordinates (15, 2411) read.

Written: function type 4 (FRF), abscissa frequency [Hz] (type 18), ordinate
displacement (8), velocity (11) or acceleration (12) over excitation force
(13), SI unit labels, spin speed in the z-axis value [rpm]; coherence as
function type 6 next to each FRF. Read: the same, and files from other tools
whose unit labels are SI (``m``, ``m/s``, ``m/s^2`` over ``N``) or ``NONE``; a file whose
dataset 164 declares other units is refused for FRFs and time records (node coordinates are
converted with its length factor).

``pyuff`` pitfalls handled here: ``write_sets(mode='overwrite')`` corrupts a
file that starts with a binary 58b set, so every file is written new (a
temporary file, mode 'add', then renamed); ``orddenom_spec_data_type`` has no
default, so it is always given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .channels import assemble

__all__ = ["read_uff58", "write_uff58", "ORDINATE_TYPES", "read_uff_info", "read_uff_nodes", "NodeTable",
           "UffUnits", "read_uff_time_records", "place_channels"]

#: UFF specific data type of the ordinate -> FRF quantity
ORDINATE_TYPES = {8: "receptance", 11: "mobility", 12: "accelerance"}
_TYPE_OF = {v: k for k, v in ORDINATE_TYPES.items()}
_UNIT_LABELS = {"receptance": {"m"}, "mobility": {"m/s"},
                "accelerance": {"m/s^2", "m/s2", "m/s**2", "m/s²", "m/s/s"}}
_FORCE = 13
_FREQUENCY = 18
_FRF, _COHERENCE = 4, 6


def write_uff58(results, path, mapping, binary: bool | None = None, inputs=()) -> None:
    """Write FRF sets (one per speed) as UFF 58 (ASCII) or 58b (binary), atomically.

    ASCII dataset 58 holds the values to 12 significant digits but an uneven abscissa
    (and the speed) only to 6 (format E13.5); with ``binary=None`` the file is ASCII when
    every frequency line survives that, else 58b (doubles throughout).

    Parameters
    ----------
    results : list of FRFResult
    path : str or path-like
    mapping : ChannelMap
        Node and direction of every sensor and excitation.
    binary : bool or None
        58b when True, ASCII 58 when False (a warning if frequencies lose digits), automatic when None.
    inputs : iterable of path-like
        Files that must not be overwritten.
    """
    import pyuff

    from .atomic import atomic_write, check_not_input

    check_not_input(path, inputs)
    lossless = all(_survives_ascii(res.frequencies_hz) and _survives_ascii([res.speed * 30 / np.pi])
                   for res in results)
    if binary is None:
        binary = not lossless
    elif not binary and not lossless:
        import warnings

        warnings.warn(f"{path}: ASCII UFF 58 keeps frequencies and speeds to 6 significant digits only; "
                      "binary=True (58b) keeps them exactly", stacklevel=2)
    sets = [d for res in results for d in _datasets(res, mapping, binary)]
    with atomic_write(path, None) as temporary:
        pyuff.UFF(temporary).write_sets(sets, mode="add")


def _datasets(res, mapping, binary):
    import pyuff

    rpm = res.speed * 30 / np.pi
    for a, out in enumerate(res.outputs):
        for b, inp in enumerate(res.inputs):
            rsp_node, rsp_dir, rsp_sign = mapping.node_of(out)
            ref_node, ref_dir, ref_sign = mapping.node_of(inp)
            common = dict(binary=int(binary), rsp_node=rsp_node, rsp_dir=rsp_dir, ref_node=ref_node,
                          ref_dir=ref_dir, rsp_ent_name=out[:10], ref_ent_name=inp[:10],
                          abscissa_spec_data_type=_FREQUENCY, x=np.asarray(res.frequencies_hz, float),
                          z_axis_value=float(rpm), id1=f"{out} / {inp}"[:80], id4=f"{rpm:.6g} rpm"[:80])
            frf = res.H[a, b] * rsp_sign * ref_sign
            yield pyuff.prepare_58(func_type=_FRF, ordinate_spec_data_type=_TYPE_OF[res.quantity],
                                   ordinate_len_unit_exp=1, ordinate_axis_units_lab=_label(res.quantity),
                                   orddenom_spec_data_type=_FORCE, orddenom_force_unit_exp=1,
                                   orddenom_axis_units_lab="N", data=np.asarray(frf, complex), **common)
            if res.coherence is not None:
                yield pyuff.prepare_58(func_type=_COHERENCE, ordinate_spec_data_type=0,
                                       orddenom_spec_data_type=0,
                                       data=np.asarray(res.coherence[a, b], float), **common)


def _survives_ascii(values) -> bool:
    values = np.asarray(values, dtype=float)
    return bool(np.all(np.array([float(f"{v:13.5e}") for v in values]) == values))


def _label(quantity):
    return {"receptance": "m", "mobility": "m/s", "accelerance": "m/s^2"}[quantity]


def read_uff58(path, model, mapping):
    """Read every dataset 58/58b of a UFF file into model-named FRF sets (one per speed).

    Parameters
    ----------
    path : path-like
    model : Model
    mapping : ChannelMap

    Returns
    -------
    list of FRFResult
    """
    sets = _read_sets(path)
    units = _file_units(path)
    if not units.is_si:
        raise InputError(f"{path}: dataset 164 gives units {units.description!r} (length factor {units.length:g}, "
                         f"force factor {units.force:g}): FRFs are read in SI units only")
    frfs = [s for s in sets if s.get("func_type") == _FRF]
    if not frfs:
        kinds = sorted({int(s.get("func_type", -1)) for s in sets})
        raise InputError(f"{path}: no FRF (dataset 58, function type 4) in the file; function types found: {kinds}")
    quantity = _quantity(frfs, path)
    coherence = {_key(s): np.real(np.asarray(s["data"])) for s in sets if s.get("func_type") == _COHERENCE}
    parts = []
    for s in frfs:
        _check_set(s, path)
        out, out_sign = _lookup(mapping.outputs, s["rsp_node"], s["rsp_dir"], "response", path)
        inp, in_sign = _lookup(mapping.inputs, s["ref_node"], s["ref_dir"], "reference", path)
        x = np.asarray(s["x"], float)
        coh = coherence.get(_key(s))
        if coh is not None and len(coh) != len(x):
            raise InputError(f"{path}: coherence of the FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:"
                             f"{s['ref_dir']} has {len(coh)} values for {len(x)} frequencies: expected one per frequency")
        parts.append({"speed_rpm": np.full(len(x), round(float(s.get("z_axis_value", 0.0)), 9)),
                      "frequency_hz": x, "output": np.full(len(x), out), "input": np.full(len(x), inp),
                      "value": np.asarray(s["data"], complex) * out_sign * in_sign,
                      "coherence": np.full(len(x), np.nan) if coh is None else coh})
    records = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    if not coherence:
        records["coherence"] = None
    return assemble(records, model, quantity, str(path))


def _check_complete(path):
    """Refuse a truncated or padded ASCII file: datasets sit between pairs of ``-1`` lines."""
    from .limits import check_size

    check_size(path, "measured", "measured-data file")
    with open(path, "rb") as handle:
        head = handle.read(4096)
    if b"\0" in head or b"58b" in head.lower():
        return  # binary 58b sets: pyuff checks their byte counts
    lines = open(path, encoding="latin-1").read().splitlines()
    marks = [k for k, line in enumerate(lines) if line.strip() == "-1" and line.startswith("    -1")]
    tail = [line for line in lines[(marks[-1] + 1 if marks else 0):] if line.strip()]
    if len(marks) % 2 or tail:
        line = (marks[-1] + 2) if marks else 1
        raise InputError(f"{path}: incomplete Universal File: a dataset is not closed by a '    -1' line "
                         f"(from line {line}): the file is truncated or has trailing text")


def _read_sets(path):
    import pyuff

    _check_complete(path)
    try:
        uff = pyuff.UFF(str(path))
        types = list(uff.get_set_types())
        if 58 not in types:
            raise InputError(f"{path}: no dataset 58/58b (FRF) in the file; datasets found: "
                             f"{sorted(set(int(t) for t in types)) or 'none'}")
        sets = uff.read_sets([i for i, t in enumerate(types) if t == 58])
    except InputError:
        raise
    except Exception as error:  # pyuff raises many kinds on a broken file
        raise InputError(f"{path}: not a readable Universal File ({type(error).__name__}: {error})") from None
    return [sets] if isinstance(sets, dict) else list(sets)


def _file_units(path):
    import pyuff

    uff = pyuff.UFF(str(path))
    types = [int(t) for t in uff.get_set_types()]
    return _units([{**uff.read_sets(types.index(164)), "type": 164}], path) if 164 in types else UffUnits()


def _key(s):
    return (int(s["rsp_node"]), int(s["rsp_dir"]), int(s["ref_node"]), int(s["ref_dir"]),
            round(float(s.get("z_axis_value", 0.0)), 9))


def _quantity(frfs, path):
    kinds = {int(s.get("ordinate_spec_data_type", -1)) for s in frfs}
    names = {ORDINATE_TYPES.get(k) for k in kinds}
    if None in names or len(names) != 1:
        raise InputError(f"{path}: ordinate data type(s) {sorted(kinds)}: expected one of 8 (displacement), "
                         "11 (velocity), 12 (acceleration), the same for every FRF")
    return names.pop()


def _check_set(s, path):
    where = f"{path}: FRF {s['rsp_node']}:{s['rsp_dir']} / {s['ref_node']}:{s['ref_dir']}"
    if int(s.get("abscissa_spec_data_type", _FREQUENCY)) not in (_FREQUENCY, 0):
        raise InputError(f"{where}: abscissa data type {s['abscissa_spec_data_type']}: expected 18 (frequency, Hz)")
    if int(s.get("orddenom_spec_data_type", _FORCE)) != _FORCE:
        raise InputError(f"{where}: denominator data type {s['orddenom_spec_data_type']}: expected 13 "
                         "(excitation force, N)")
    quantity = ORDINATE_TYPES[int(s["ordinate_spec_data_type"])]
    label = str(s.get("ordinate_axis_units_lab", "NONE")).strip()
    if label.upper() not in ("NONE", "") and label.removesuffix("/N") not in _UNIT_LABELS[quantity]:
        raise InputError(f"{where}: ordinate unit {label!r}: expected SI {_label(quantity)} for "
                         f"{quantity} (convert the file, e.g. g or mm/s, to SI first)")
    denominator = str(s.get("orddenom_axis_units_lab", "NONE")).strip()
    if denominator.upper() not in ("NONE", "", "N"):
        raise InputError(f"{where}: denominator unit {denominator!r}: expected N")
    data = np.asarray(s["data"])
    if len(data) != len(np.asarray(s["x"])) or not np.all(np.isfinite(data)):
        raise InputError(f"{where}: {len(data)} values for {len(np.asarray(s['x']))} frequencies, or non-finite values")


def _lookup(table, node, direction, what, path):
    key = (int(node), int(direction))
    if key in table:
        return table[key]
    known = ", ".join(f"{n}:{d}={name}" for (n, d), (name, _) in sorted(table.items()))
    raise InputError(f"{path}: {what} node {node} direction {direction} is not in the mapping table "
                     f"(node:direction=name: {known}); give --mapping FILE.csv with columns name,node,direction")


# ---------------------------------------------------------------------------------------------
# header (151), units (164), coordinate systems (18, 2420), nodes (15, 2411), time records (58)
# ---------------------------------------------------------------------------------------------
_TIME = 17
_TIME_QUANTITIES = {8: "displacement", 11: "velocity", 12: "acceleration", 13: "force"}
_TIME_UNITS = {"displacement": {"m"}, "velocity": {"m/s"}, "acceleration": _UNIT_LABELS["accelerance"],
               "force": {"N"}}
_SI_LABEL = {"displacement": "m", "velocity": "m/s", "acceleration": "m/s^2", "force": "N"}
_GENERAL = 1


class UffUnits:
    """Dataset 164: factors from the file's units to SI (SI value = file value / factor).

    Attributes
    ----------
    code : int
    description : str
    length, force, temperature : float
    """

    def __init__(self, code=1, description="SI (no dataset 164)", length=1.0, force=1.0, temperature=1.0):
        self.code, self.description = int(code), str(description).strip()
        self.length, self.force, self.temperature = float(length), float(force), float(temperature)

    @property
    def is_si(self) -> bool:
        return self.length == 1.0 and self.force == 1.0

    def __repr__(self) -> str:
        return (f"UffUnits(code={self.code}, description={self.description!r}, length={self.length:g}, "
                f"force={self.force:g}, temperature={self.temperature:g})")


def read_uff_info(path) -> dict:
    """Header (dataset 151) and units (dataset 164) of a Universal File.

    Returns
    -------
    dict
        ``program``, ``model_name``, ``description``, ``date`` (from 151, '' where absent),
        ``units`` (:class:`UffUnits`, SI when there is no 164) and ``datasets`` (the dataset
        numbers in file order).
    """
    sets, types = _all_sets(path)
    header = next((s for s in sets if s["type"] == 151), {})
    return {"program": str(header.get("program", "")).strip(), "model_name": str(header.get("model_name", "")).strip(),
            "description": str(header.get("description", "")).strip(),
            "date": str(header.get("date_file_written", "")).strip(), "units": _units(sets, path),
            "datasets": types}


def _all_sets(path):
    import pyuff

    _check_complete(path)
    try:
        uff = pyuff.UFF(str(path))
        types = [int(t) for t in uff.get_set_types()]
        sets = uff.read_sets() if types else []
    except Exception as error:  # pyuff raises many kinds on a broken file
        raise InputError(f"{path}: not a readable Universal File ({type(error).__name__}: {error})") from None
    sets = [sets] if isinstance(sets, dict) else list(sets)
    for s, t in zip(sets, types):
        s.setdefault("type", t)
    return sets, types


def _units(sets, path) -> UffUnits:
    found = [s for s in sets if s["type"] == 164]
    if not found:
        return UffUnits()
    u = found[0]
    units = UffUnits(u.get("units_code", 1), u.get("units_description", ""), u.get("length", 1.0),
                     u.get("force", 1.0), u.get("temp", 1.0))
    if not (units.length > 0 and units.force > 0):
        raise InputError(f"{path}: dataset 164 unit factors length={units.length:g}, force={units.force:g}: "
                         "expected positive numbers")
    return units


@dataclass(frozen=True)
class NodeTable:
    """Node coordinates of a Universal File, in SI and global axes.

    Attributes
    ----------
    numbers : ndarray of int, shape (n_nodes,)
    coordinates : ndarray, shape (n_nodes, 3) [m]
        Global position (dataset 15/2411 coordinates in their definition system, times the
        dataset 164 length factor's inverse).
    axes : ndarray, shape (n_nodes, 3, 3)
        Rows: the node's displacement directions 1, 2, 3 (+X, +Y, +Z of its displacement
        coordinate system) in global axes.
    units : UffUnits
    """

    numbers: np.ndarray
    coordinates: np.ndarray
    axes: np.ndarray
    units: UffUnits

    def position(self, node: int) -> np.ndarray:
        """Global position of a node [m]."""
        return self.coordinates[self._index(node)]

    def direction(self, node: int, code: int) -> np.ndarray:
        """Unit vector of a UFF direction code (1/2/3 = +X/+Y/+Z, negative for minus) at a node."""
        if abs(int(code)) not in (1, 2, 3):
            raise InputError(f"node {node} direction {code}: expected a translation code +-1, +-2 or +-3")
        return np.sign(code) * self.axes[self._index(node), abs(int(code)) - 1]

    def _index(self, node):
        found = np.nonzero(self.numbers == int(node))[0]
        if not found.size:
            raise InputError(f"node {node} is not in the file's node table (nodes {self.numbers.min()} to "
                             f"{self.numbers.max()})")
        return int(found[0])

    def to_dataframe(self):
        """``node,x,y,z`` [m] (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame({"node": self.numbers, "x": self.coordinates[:, 0], "y": self.coordinates[:, 1],
                             "z": self.coordinates[:, 2]})


def read_uff_nodes(path) -> NodeTable:
    """Nodes of a Universal File (dataset 15 or 2411) in metres and global axes.

    Coordinates are converted with dataset 164 (SI value = file value / length factor); nodes
    defined or displaced in a local Cartesian system are placed through dataset 18 or 2420.

    Raises
    ------
    InputError
        No node dataset, or a node in an undefined or non-Cartesian coordinate system.
    """
    sets, types = _all_sets(path)
    nodes = [s for s in sets if s["type"] in (15, 2411)]
    if not nodes:
        raise InputError(f"{path}: no node coordinates (dataset 15 or 2411) in the file; datasets found: "
                         f"{sorted(set(types)) or 'none'}")
    units = _units(sets, path)
    systems = _coordinate_systems(sets, path)
    numbers, coordinates, axes = [], [], []
    for block in nodes:
        local = np.column_stack([block["x"], block["y"], block["z"]]).astype(float) / units.length
        for k, number in enumerate(np.asarray(block["node_nums"], dtype=float).astype(int)):
            origin, rotation = _system(systems, block["def_cs"][k], number, path)
            coordinates.append(origin / units.length + local[k] @ rotation)
            axes.append(_system(systems, block["disp_cs"][k], number, path)[1])
            numbers.append(number)
    return NodeTable(numbers=np.array(numbers), coordinates=np.array(coordinates), axes=np.array(axes),
                     units=units)


def _coordinate_systems(sets, path):
    """``{number: (origin [file units], rotation rows = local axes in global, type)}`` from 18 and 2420."""
    systems = {}
    for s in sets:
        if s["type"] == 18:
            for k, number in enumerate(np.asarray(s["cs_num"]).astype(int)):
                origin = np.asarray(s["ref_o"][k], float)
                ex = np.asarray(s["x_point"][k], float) - origin
                ex = ex / np.linalg.norm(ex)
                in_xz = np.asarray(s["xz_point"][k], float) - origin
                ey = np.cross(in_xz, ex)
                ey = ey / np.linalg.norm(ey)
                systems[int(number)] = (origin, np.array([ex, ey, np.cross(ex, ey)]), int(s["cs_type"][k]),
                                        int(s["ref_cs_num"][k]))
        elif s["type"] == 2420:
            for number, kind, matrix in zip(s["CS_sys_labels"], s["CS_types"], s["CS_matrices"]):
                matrix = np.asarray(matrix, float)
                systems[int(number)] = (matrix[3], matrix[:3], int(kind), 0)
    return systems


def _system(systems, number, node, path):
    """Origin (file units, global) and rotation (rows: local axes in global) of a coordinate system."""
    number = int(number)
    if number == 0 or (number not in systems and number == 1):
        return np.zeros(3), np.eye(3)       # 0 is global; 1 is the global system when not defined
    if number not in systems:
        raise InputError(f"{path}: node {node} uses coordinate system {number}, which the file does not define "
                         "(datasets 18 or 2420)")
    origin, rotation, kind, parent = systems[number]
    if kind != 0:
        raise InputError(f"{path}: node {node} uses coordinate system {number} of type {kind}: only Cartesian "
                         "systems (type 0) are read")
    if parent:
        parent_origin, parent_rotation = _system(systems, parent, node, path)
        return parent_origin + origin @ parent_rotation, rotation @ parent_rotation
    return origin, rotation


def read_uff_time_records(path, mapping=None, speed: float = 0.0):
    """Time records (dataset 58/58b, function type 1) of a Universal File.

    Each channel is a response node and direction; a channel that appears several times gives
    several records (e.g. one per hit), in file order. Forces (ordinate data type 13) and
    responses (8, 11, 12; or 1 'general' with an SI unit label of one of them) must carry SI
    units (labels ``N``, ``m``, ``m/s``, ``m/s^2`` or ``NONE``; a dataset 164 of other units is
    refused).

    Parameters
    ----------
    path : path-like
    mapping : ChannelMap, optional
        Names the channels after the model (forces from its inputs, responses from its outputs);
        default ``NODE:DIRECTION`` (e.g. ``7:+3``).
    speed : float
        Reference rotor speed during the records [rad/s].

    Returns
    -------
    TimeRecords
    """
    from ..analysis.spectra import TimeRecords

    sets, types = _all_sets(path)
    records = [s for s in sets if s["type"] == 58 and int(s.get("func_type", -1)) == 1]
    if not records:
        kinds = sorted({int(s.get("func_type", -1)) for s in sets if s["type"] == 58})
        raise InputError(f"{path}: no time record (dataset 58, function type 1) in the file; "
                         f"dataset 58 function types found: {kinds or 'none'}")
    units = _units(sets, path)
    if not units.is_si:
        raise InputError(f"{path}: dataset 164 gives units {units.description!r} (length factor {units.length:g}, "
                         f"force factor {units.force:g}): time records are read in SI units only")
    channels, quantities, columns, rate = {}, {}, {}, None
    for s in records:
        quantity = _time_quantity(s, path)
        name = _channel_name(s, quantity, mapping, path)
        dt = _time_step(s, path)
        rate = 1.0 / dt if rate is None else rate
        if abs(1.0 / dt - rate) > 1e-6 * rate:
            raise InputError(f"{path}: channel {name} is sampled at {1 / dt:g} Hz, another at {rate:g} Hz: "
                             "every record must share one sampling rate")
        channels.setdefault(name, quantity)
        columns.setdefault(name, []).append(np.asarray(s["data"], dtype=float) * _sign(s, mapping, quantity))
        quantities[name] = quantity
    counts = {len(v) for v in columns.values()}
    lengths = {len(x) for v in columns.values() for x in v}
    if len(counts) != 1 or len(lengths) != 1:
        raise InputError(f"{path}: channels have different numbers of records ({sorted(counts)}) or lengths "
                         f"({sorted(lengths)}): every record must hold every channel with as many samples")
    names = list(columns)
    signals = np.stack([np.stack([columns[n][r] for n in names]) for r in range(counts.pop())])
    return TimeRecords(signals=signals, sampling_rate_hz=float(rate), channels=tuple(names),
                       quantities=tuple(quantities[n] for n in names), speed=float(speed))


def _time_quantity(s, path):
    kind = int(s.get("ordinate_spec_data_type", -1))
    label = str(s.get("ordinate_axis_units_lab", "NONE")).strip()
    where = f"{path}: time record {s.get('rsp_node')}:{s.get('rsp_dir')}"
    if int(s.get("abscissa_spec_data_type", _TIME)) not in (_TIME, 0):
        raise InputError(f"{where}: abscissa data type {s['abscissa_spec_data_type']}: expected 17 (time, s)")
    if kind == _GENERAL:
        found = [q for q, labels in _TIME_UNITS.items() if label in labels]
        if not found:
            raise InputError(f"{where}: ordinate data type 1 (general) with unit {label!r}: expected a force (N) "
                             "or a response in SI units (m, m/s, m/s^2)")
        return found[0]
    if kind not in _TIME_QUANTITIES:
        raise InputError(f"{where}: ordinate data type {kind}: expected 8 (displacement), 11 (velocity), "
                         "12 (acceleration) or 13 (force)")
    quantity = _TIME_QUANTITIES[kind]
    if label.upper() not in ("NONE", "") and label not in _TIME_UNITS[quantity]:
        raise InputError(f"{where}: ordinate unit {label!r}: expected SI {_SI_LABEL[quantity]} for {quantity} "
                         "(convert the file, e.g. g or mm/s, to SI first)")
    return quantity


def _time_step(s, path):
    """Sampling interval [s]: the header's increment, or the abscissa's (written to 6 digits in ASCII)."""
    dt = float(s.get("abscissa_inc", 0.0))
    if int(s.get("abscissa_spacing", 1)) == 1 and dt > 0:
        return dt
    x = np.asarray(s["x"], dtype=float)
    dt = (x[-1] - x[0]) / (len(x) - 1) if len(x) > 1 else 0.0
    even = x[0] + dt * np.arange(len(x))
    if not dt > 0 or np.any(np.abs(x - even) > 1e-5 * np.abs(x) + 1e-9 * dt):
        raise InputError(f"{path}: time record {s.get('rsp_node')}:{s.get('rsp_dir')} is not evenly sampled")
    return float(dt)


def _channel_name(s, quantity, mapping, path):
    node, direction = int(s.get("rsp_node", 0)), int(s.get("rsp_dir", 0))
    if mapping is None:
        return f"{node}:{direction:+d}"
    table = mapping.inputs if quantity == "force" else mapping.outputs
    what = "force" if quantity == "force" else "response"
    return _lookup(table, node, direction, what, path)[0]


def _sign(s, mapping, quantity):
    if mapping is None:
        return 1.0
    table = mapping.inputs if quantity == "force" else mapping.outputs
    return table[(int(s.get("rsp_node", 0)), int(s.get("rsp_dir", 0)))][1]


def place_channels(model, nodes, mapping):
    """The model with its sensors and excitations placed at their mapped nodes and directions.

    Parameters
    ----------
    model : Model
    nodes : NodeTable
    mapping : ChannelMap
        Node and direction of each channel (channels not in the mapping keep their place).

    Returns
    -------
    Model
    """
    from ..model.machine import Model

    data = model.to_dict()
    for table, entries in (("sensors", mapping.outputs), ("excitations", mapping.inputs)):
        placed = {name: (node, code, sign) for (node, code), (name, sign) in entries.items()}
        for item in data.get(table, []):
            if item["name"] in placed:
                node, code, sign = placed[item["name"]]
                item["position"] = [float(v) for v in nodes.position(node)]
                item["direction"] = [float(v) for v in sign * nodes.direction(node, code)]
    return Model.from_dict(data, model.source)
