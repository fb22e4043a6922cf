"""Measured mode shapes from Universal Files: dataset 55 (data at nodes), as modal analysis
programs (EMA, OMA) export identified modes.

Read by the dataset 55 definition (records 1 to 10; pyuff 2.5.8 reads records 7 and 8 as one
line each whatever their counts, and no complex 6-value node), one set a mode:

* record 6: data characteristic 2 (3 values a node: X, Y, Z) or 3 (6: X, Y, Z, RX, RY, RZ), or
  0 (unknown) with 3 or 6 values; real (data type 2) or complex (5) values; a specific data
  type of a motion (8 displacement, 11 velocity, 12 acceleration) or 0/1 (unknown, general);
* records 7 and 8 by their own counts (NINT integers, NRVAL reals, over as many lines as they
  take): analysis type 2 (normal mode: frequency [Hz], modal mass, viscous and hysteretic damping
  ratios; fewer reals leave the damping ratio unknown, nan; more are passed over) or 3/7
  (complex eigenvalue: the eigenvalue [rad/s], modal A, modal B, six reals);
* records 9 and 10 for each node: its label, then its values (6 a line).

Refused, in one line naming the file, the set and the field: other analysis types (static,
transient, frequency response, buckling: data at nodes, not modes); scalar or tensor data; a
complex eigenvalue's record 7 of other than 6 reals (e.g. 4, whose meaning cannot be told:
permas4edu's ema/examples/019/Rotor_2_BandsFit.uff writes such sets, its first two reals no
eigenvalue in rad/s); a normal mode without its frequency; a node given twice
in a set; a count of values that does not match record 6.

The values at the model's sensors come through the mapping of node and direction to channel
name (the FRFs' mapping, :mod:`.channels`): a sensor at node ``n`` direction ``-3`` reads minus
the set's Z value of node ``n``. A node missing from a set reads 0 there (definition, note 9); a
sensor whose node is in no set is not measured. Shapes are taken as the file gives them (no
unit conversion: a modal assurance criterion and the frequencies do not depend on their scale).

Dataset 2414 (analysis data, as finite element programs write results: NX/Simcenter, PERMAS,
FEMtools) is read where a set is a mode shape at nodes: record 3 dataset location 1 (data at
nodes); record 9 analysis type 2 (normal mode: record 12 field 2 the frequency [Hz], fields 5
and 6 the viscous and hysteretic damping ratios) or 3/7 (complex eigenvalue: record 13 fields 1
and 2, the eigenvalue [rad/s] as in dataset 55), data characteristic 2 or 3 (3 or 6 values a node;
0 with NVALDC 3 or 6), a result type of a motion (8 displacement, 11 velocity, 12 acceleration, 95
and 96 unknown 3- and 6-value vectors), real (2, 4) or complex (5, 6) values; record 10 field 6 the
mode number; records 14 and 15 a node and its values, over as many lines as they take (the
definition writes 6 a line, pyuff all on one). Its other sets (static or frequency response
results, stresses, strain energies, temperatures, data on elements) say no mode, nor does a normal
mode of frequency 0 or below (an FE model's rigid-body modes): beside modes they are passed over
with one warning naming them; a file of none but them is refused naming them. A
frequency response set is one frequency's response at the nodes to a load case whose force the
file does not give: it is no FRF (FRFs are read from dataset 58, ``frf --measured``). Dataset 55
and 2414 modes in one file are refused (whether they are the same modes cannot be told).
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from ..errors import InputError
from .limits import reads_pipes

__all__ = ["read_uff_modes"]

#: analysis types of dataset 55 (record 6, field 2)
_ANALYSIS = {0: "unknown", 1: "static", 2: "normal mode", 3: "complex eigenvalue first order", 4: "transient",
             5: "frequency response", 6: "buckling", 7: "complex eigenvalue second order"}
#: record 7 counts (integers, reals) the definition gives each modal analysis type
_COUNTS = {2: (2, 4), 3: (2, 6), 7: (2, 6)}
#: the fewest reals read: a normal mode's frequency (its damping ratios may be left out)
_FEWEST_REALS = {2: 1, 3: 6, 7: 6}
#: data characteristic -> values a node (3 DOF, 6 DOF)
_PER_NODE = {2: 3, 3: 6}
#: specific data types of a motion (or unknown/general), record 6 field 4
_MOTIONS = {0: "unknown", 1: "general", 8: "displacement", 11: "velocity", 12: "acceleration"}
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?")


@reads_pipes(".uff", "Universal File")
def read_uff_modes(path, model, mapping=None):
    """Measured modes (frequency, damping ratio, shape at the sensors) from the dataset 55 sets of
    a Universal File, or from its dataset 2414 sets of mode shapes at nodes.

    Parameters
    ----------
    path : path-like
    model : Model
        Gives the sensors (and the default mapping: sensor k is node k along its axis).
    mapping : path-like or ChannelMap, optional
        Node/direction to channel table (``name,node,direction[,sign]``).

    Returns
    -------
    MeasuredModes
        In the order of frequency: ``frequencies_hz`` (the package's damped frequency,
        ``Im(pole) / 2 pi``: a normal mode's record 8 frequency, a complex eigenvalue's imaginary
        part over 2 pi), ``damping_ratios``, ``poles`` [1/s], ``shapes`` of shape
        (n_modes, n_sensors, 1) at the sensors the file has, ``outputs`` those sensors, ``inputs``
        ``('uff-55',)``, ``method`` ``'uff-55'`` (``'uff-2414'`` for dataset 2414 modes).

    Raises
    ------
    InputError
        No mode shapes (dataset 55 or 2414), a layout that cannot be understood (see the module), no
        sensor in the file, modes as both datasets.
    """
    from ..analysis.identification import MeasuredModes
    from .channels import ChannelMap, default_mapping, read_mapping
    from .limits import input_path
    from .uff import _check_complete

    path = input_path(path, "path")
    complete = _check_complete(path)
    channels = mapping if isinstance(mapping, ChannelMap) else (
        read_mapping(mapping, model) if mapping is not None else default_mapping(model))
    blocks = _blocks(path, (55, 2414), complete)
    sets = [_mode(block, start, path) for block, start in blocks[55]]
    read_2414 = [_result_2414(block, start, path) for block, start in blocks[2414]]
    modes_2414 = [r for r in read_2414 if "nodes" in r]
    others = [r for r in read_2414 if "nodes" not in r]
    if sets and modes_2414:
        raise InputError(f"{path}: mode shapes as dataset 55 ({len(sets)} sets) and as dataset 2414 "
                         f"({len(modes_2414)} sets): whether they are the same modes cannot be told; export one")
    if not sets and not modes_2414:
        found = f"; its dataset 2414 holds no mode shape at nodes: {_others_named(others)}" if others else ""
        raise InputError(f"{path}: no dataset 55 or 2414 mode shapes (data at nodes) in the file{found}; "
                         f"{_holds(path)}")
    number = 55 if sets else 2414
    sets = sorted(sets or modes_2414, key=lambda s: s["frequency_hz"])
    if others:
        warnings.warn(f"{path}: read the {len(sets)} dataset {number} mode shapes and passed over "
                      f"{len(others)} other dataset 2414 sets: {_others_named(others)}", stacklevel=2)
    outputs, shapes = _at_sensors(sets, channels, path)
    return MeasuredModes(frequencies_hz=np.array([s["frequency_hz"] for s in sets]),
                         damping_ratios=np.array([s["damping"] for s in sets]),
                         poles=np.array([s["pole"] for s in sets]), shapes=shapes[:, :, None],
                         outputs=tuple(outputs), inputs=(f"uff-{number}",), method=f"uff-{number}")


def _holds(path) -> str:
    """What a file without dataset 55 holds: ``datasets found: 58 (function data), ...``, and
    where FRFs are read (``frf --measured``)."""
    from .uff import _datasets_named, _pyuff_read

    types = _pyuff_read(path, kinds=())[1]
    hint = " (FRFs and time records: frf --measured, rdm.read_measured)" if 58 in types else ""
    return f"datasets found: {_datasets_named(types)}{hint}"


def _blocks(path, numbers=(55,), complete=None) -> dict:
    """The blocks of each dataset number of ``numbers``, the file read once: number -> list of
    ``(lines, first_line_number)`` (the lines after its number line up to its closing ``-1``); a
    58b set's binary bytes elsewhere in the file are passed over. ``complete``: read the file's
    first lines only, its complete datasets (``uff._check_complete``)."""
    with open(path, "rb") as handle:
        text = handle.read().decode("latin-1").removeprefix("\xef\xbb\xbf")
    lines = text.splitlines()[:complete]
    return {number: list(_scan(lines, number)) for number in numbers}


def _scan(lines, number):
    """``(lines, first_line_number)`` of each dataset ``number`` block of ``lines`` (a file's)."""
    k = 0
    while k < len(lines) - 1:
        if lines[k].strip() == "-1" and lines[k + 1].strip() == str(number):
            end = next((j for j in range(k + 2, len(lines)) if lines[j].strip() == "-1"), len(lines))
            last = end
            while last > k + 2 and not lines[last - 1].strip():     # blank lines before the closing -1
                last -= 1
            yield lines[k + 2:last], k + 3
            k = end + 1
        else:
            k += 1


class _Lines:
    """The lines of one dataset, read in order, for messages with their line numbers."""

    def __init__(self, lines, first, path, number=55):
        self.lines, self.first, self.path, self.at, self.number = lines, first, path, 0, number

    def where(self) -> str:
        return f"{self.path}: line {self.first + self.at - 1}"

    def next(self, what) -> str:
        if self.at >= len(self.lines):
            raise InputError(f"{self.path}: dataset {self.number} from line {self.first - 1} ends before its {what}")
        self.at += 1
        return self.lines[self.at - 1]

    def integers(self, count, what):
        """``count`` integers over as many lines as they take (I10 fields)."""
        values = []
        while len(values) < count:
            line = self.next(what)
            try:
                values += [int(v) for v in line.split()]
            except ValueError:
                raise InputError(f"{self.where()}: {what}: expected whole numbers, found {line.strip()!r}") from None
        if len(values) != count:
            raise InputError(f"{self.where()}: {what}: expected {count} whole numbers, found {len(values)}")
        return values

    def reals(self, count, what):
        """``count`` reals over as many lines as they take (E13.5 fields, touching or not)."""
        values = []
        while len(values) < count:
            line = self.next(what)
            found = _NUMBER.findall(line)
            if "".join(found).replace(" ", "") != "".join(line.split()):
                raise InputError(f"{self.where()}: {what}: expected numbers, found {line.strip()!r}")
            values += [float(v.replace("D", "E").replace("d", "e")) for v in found]
        if len(values) != count:
            raise InputError(f"{self.where()}: {what}: expected {count} numbers, found {len(values)}")
        return values


def _mode(block, first, path) -> dict:
    """One dataset 55 set: ``mode``, ``frequency_hz``, ``damping``, ``pole`` and ``nodes``
    (label -> complex values, X, Y, Z[, RX, RY, RZ])."""
    lines = _Lines(block, first, path)
    for k in range(5):
        lines.next(f"ID line {k + 1}")
    _, analysis, character, specific, data_type, per_node = lines.integers(6, "record 6")
    where = f"{path}: dataset 55 from line {first - 1}"
    if analysis not in _COUNTS:
        raise InputError(f"{where}: analysis type {analysis} ({_ANALYSIS.get(analysis, 'not in the definition')}) "
                         "is not a mode: expected 2 (normal mode), 3 or 7 (complex eigenvalue)")
    values_per_node = _PER_NODE.get(character, per_node if character == 0 else None)
    if values_per_node not in (3, 6) or per_node != values_per_node:
        raise InputError(f"{where}: record 6: data characteristic {character} with {per_node} values a node: "
                         "expected 2 (3 values: X, Y, Z) or 3 (6 values: X, Y, Z, RX, RY, RZ)")
    if specific not in _MOTIONS:
        raise InputError(f"{where}: record 6: specific data type {specific} is not a motion: expected 8 "
                         "(displacement), 11 (velocity), 12 (acceleration), 0 or 1")
    if data_type not in (2, 5):
        raise InputError(f"{where}: record 6: data type {data_type}: expected 2 (real) or 5 (complex)")
    n_int, n_real, ints = _record7(lines)
    if n_int < 2 or n_real < _FEWEST_REALS[analysis] or (analysis != 2 and n_real != _COUNTS[analysis][1]):
        raise InputError(f"{where}: record 7 gives {n_int} integer and {n_real} real values where analysis type "
                         f"{analysis} ({_ANALYSIS[analysis]}) has {_COUNTS[analysis][0]} and "
                         f"{_COUNTS[analysis][1]}: a record 8 of another layout, whose fields cannot be told")
    reals = lines.reals(n_real, "record 8")
    frequency, damping, pole = _pole(analysis, reals, where)
    nodes = _node_values(lines, values_per_node, 2 if data_type == 5 else 1, ("record 9", "node label"), "record 10")
    return {"mode": ints[1] if len(ints) > 1 else None, "frequency_hz": frequency, "damping": damping, "pole": pole, "nodes": nodes,
            "where": where}


#: dataset 2414 record 9 result types of a motion (unknown 3- and 6-value vectors: a mode's shape)
_MOTIONS_2414 = {8: "displacement", 11: "velocity", 12: "acceleration", 95: "unknown 3 DOF vector",
                 96: "unknown 6 DOF vector"}
#: dataset 2414 result types named in messages (beside the motions)
_RESULTS_2414 = {**_MOTIONS_2414, 1: "unknown", 2: "stress", 3: "strain", 4: "element force", 5: "temperature",
                 6: "heat flux", 7: "strain energy", 9: "reaction force", 10: "kinetic energy",
                 13: "strain energy density", 14: "kinetic energy density", 15: "hydro-static pressure",
                 93: "unknown", 94: "unknown scalar", 97: "unknown symmetric tensor", 98: "unknown global tensor",
                 99: "unknown shell and plate resultant", 301: "sound pressure", 302: "sound power",
                 303: "sound intensity"}
_ANALYSIS_2414 = {**_ANALYSIS, 9: "static non-linear"}
_LOCATIONS_2414 = {1: "data at nodes", 2: "data on elements", 3: "data at nodes on elements", 5: "data at points"}
#: dataset 2414 data types (record 9 field 5) -> values of a number (1 real, 2 complex)
_PARTS_2414 = {2: 1, 4: 1, 5: 2, 6: 2}


def _result_2414(block, first, path) -> dict:
    """One dataset 2414 set: a mode (the keys of :func:`_mode`) where it is a mode shape at nodes,
    else ``{"what": ...}`` saying what it holds (passed over)."""
    lines = _Lines(block, first, path, 2414)
    where = f"{path}: dataset 2414 from line {first - 1}"
    lines.integers(1, "record 1 (analysis dataset label)")
    lines.next("record 2 (analysis dataset name)")
    location = lines.integers(1, "record 3 (dataset location)")[0]
    for k in range(5):
        lines.next(f"ID line {k + 1}")
    _, analysis, character, result, data_type, per_node = lines.integers(6, "record 9")
    what = (f"analysis type {analysis} ({_ANALYSIS_2414.get(analysis, 'not in the definition')}) "
            f"{_RESULTS_2414.get(result, f'result type {result}')}, {_LOCATIONS_2414.get(location, location)}")
    if location != 1 or analysis not in _COUNTS or result not in _MOTIONS_2414 or character not in (0, 2, 3):
        return {"what": what}
    values_per_node = _PER_NODE.get(character, per_node if character == 0 else None)
    if values_per_node not in (3, 6) or per_node != values_per_node:
        raise InputError(f"{where}: record 9: data characteristic {character} with NVALDC {per_node}: expected 2 "
                         "(3 values: X, Y, Z) or 3 (6 values: X, Y, Z, RX, RY, RZ)")
    if data_type not in _PARTS_2414:
        raise InputError(f"{where}: record 9: data type {data_type}: expected 2 or 4 (real), 5 or 6 (complex)")
    ints = _integers_line(lines, "record 10")
    _integers_line(lines, "record 11")
    reals = lines.reals(6, "record 12") + lines.reals(6, "record 13")
    if analysis == 2 and reals[1] <= 0:     # an FE model's free-free rigid-body modes (0 Hz, or round-off below)
        return {"what": f"analysis type 2 (normal mode) of frequency {reals[1]:g} Hz (a rigid-body mode)"}
    # normal mode: frequency, modal mass, viscous and hysteretic damping (fields 2, 4, 5, 6 of record 12);
    # complex eigenvalue: its real and imaginary parts (record 13 fields 1 and 2)
    frequency, damping, pole = _pole(analysis, [reals[1], *reals[3:6]] if analysis == 2 else reals[6:8], where,
                                     "record 12" if analysis == 2 else "record 13")
    nodes = _node_values(lines, values_per_node, _PARTS_2414[data_type], ("record 14", "node number"), "record 15")
    return {"mode": ints[5] if len(ints) > 5 else None, "frequency_hz": frequency, "damping": damping, "pole": pole,
            "nodes": nodes, "where": where}


def _integers_line(lines, what):
    """One line of whole numbers (records 10 and 11 of dataset 2414: 8I10 and 2I10; pyuff's
    writer puts 8 in record 11)."""
    line = lines.next(what)
    try:
        return [int(v) for v in line.split()]
    except ValueError:
        raise InputError(f"{lines.where()}: {what}: expected whole numbers, found {line.strip()!r}") from None


def _others_named(others) -> str:
    """The dataset 2414 sets passed over, grouped: ``3 sets of analysis type 1 (static) stress, data
    on elements; 1 set of ...``."""
    from collections import Counter

    counts = Counter(r["what"] for r in others)
    return "; ".join(f"{n} {'set' if n == 1 else 'sets'} of {what}" for what, n in counts.items())


def describe_2414(path) -> str:
    """What the dataset 2414 sets of a file hold, for the FRF reader's refusal of a file without
    dataset 58: mode shapes (read by ``modes --measured``), frequency response sets (no FRFs),
    other results; '' for a file without dataset 2414."""
    sets = []
    for block, start in _blocks(path, (2414,))[2414]:
        try:
            sets.append(_result_2414(block, start, path))
        except InputError as error:
            sets.append({"what": f"a set that cannot be read ({error})"})
    if not sets:
        return ""
    modes = sum("nodes" in r for r in sets)
    others = [r for r in sets if "nodes" not in r]
    parts = [f"{modes} dataset 2414 mode shapes (read by modes --measured, rdm.read_uff_modes)"] if modes else []
    if others:
        parts.append(f"dataset 2414: {_others_named(others)}")
    if any(r["what"].startswith("analysis type 5 ") for r in others):
        parts.append("a frequency response set is one frequency's response at the nodes to a load case whose force "
                     "the file does not give: no FRF (export FRFs as dataset 58)")
    return "; ".join(parts)


def _node_values(lines, values_per_node, parts, label_record, values_record) -> dict:
    """The rest of a set: each node's label (``label_record``: record name and field) and values
    (``values_record``), label -> complex values; ``parts`` 2 for complex numbers (real and
    imaginary parts in turn), 1 for real ones. A node given twice is refused."""
    nodes = {}
    while lines.at < len(lines.lines):
        label = lines.integers(1, f"{label_record[0]} ({label_record[1]})")[0]
        if label in nodes:
            raise InputError(f"{lines.where()}: node {label} is given twice in one mode")
        values = np.array(lines.reals(values_per_node * parts, f"{values_record} (the values of node {label})"))
        nodes[label] = values[0::2] + 1j * values[1::2] if parts == 2 else values.astype(complex)
    return nodes


def _record7(lines):
    """Record 7: its counts NINT and NRVAL and its NINT integers (8I10: a record of more than 8
    fields goes on over lines)."""
    line = lines.next("record 7")
    try:
        first = [int(v) for v in line.split()]
    except ValueError:
        raise InputError(f"{lines.where()}: record 7: expected whole numbers, found {line.strip()!r}") from None
    if len(first) < 2 or not 1 <= first[0] <= 10 or not 1 <= first[1] <= 12:
        raise InputError(f"{lines.where()}: record 7: expected NINT (1 to 10) and NRVAL (1 to 12) first, found "
                         f"{line.strip()!r}")
    values = first[2:]
    while len(values) < first[0]:
        values += lines.integers(min(8, first[0] - len(values)), "record 7")
    if len(values) != first[0]:
        raise InputError(f"{lines.where()}: record 7: NINT = {first[0]} integers, found {len(values)}")
    return first[0], first[1], values


def _pole(analysis, reals, where, record="record 8"):
    """``(frequency [Hz], damping ratio, pole [1/s])`` of a mode's record 8 (dataset 2414: records
    12 and 13, ``record`` naming them in messages)."""
    if analysis == 2:       # frequency, modal mass, viscous and hysteretic damping ratios (those given)
        frequency, _, viscous, hysteretic = (list(reals[:4]) + [np.nan] * 3)[:4]
        if not frequency > 0:
            raise InputError(f"{where}: {record}: frequency {frequency:g} Hz: expected > 0")
        damping = viscous
        if viscous == 0 and hysteretic != 0 and not np.isnan(hysteretic):
            warnings.warn(f"{where}: {record} gives a hysteretic damping ratio ({hysteretic:g}) and no viscous one: "
                          "read as no damping ratio (nan)", stacklevel=4)
            damping = np.nan
        if not (np.isnan(damping) or -1 < damping < 1):
            raise InputError(f"{where}: {record}: viscous damping ratio {damping:g}: expected between -1 and 1")
        zeta = 0.0 if np.isnan(damping) else damping
        omega = 2 * np.pi * frequency
        return frequency, damping, complex(-zeta * omega / np.sqrt(1 - zeta**2), omega)
    pole = complex(reals[0], abs(reals[1]))     # the upper half-plane root of the conjugate pair
    if pole.imag == 0:
        raise InputError(f"{where}: {record}: eigenvalue {reals[0]:g} + {reals[1]:g}i is real: not an oscillating "
                         "mode")
    if pole.real > 0:
        warnings.warn(f"{where}: eigenvalue {pole.real:g} + {pole.imag:g}i [rad/s] has a positive real part: read "
                      "as a growing mode (negative damping ratio)", stacklevel=4)
    return pole.imag / (2 * np.pi), -pole.real / abs(pole), pole


def _at_sensors(sets, channels, path):
    """``(outputs, shapes)``: the sensors whose node and direction some set has, and each mode's
    values there (n_modes, n_sensors); the mapping's sign and the direction's sign applied."""
    outputs, columns = [], []
    for (node, code), (name, sign) in channels.outputs.items():
        component = abs(int(code)) - 1     # direction 0 (a scalar channel of the FRFs' tables): no component
        if component >= 0 and any(node in s["nodes"] and component < len(s["nodes"][node]) for s in sets) \
                and name not in outputs:
            outputs.append(name)
            columns.append((node, component, float(np.sign(code)) * sign))
    if not outputs:
        found = sorted({node for s in sets for node in s["nodes"]})
        known = ", ".join(f"{n}:{d}={name}" for (n, d), (name, _) in sorted(channels.outputs.items()))
        shown = ", ".join(map(str, found[:12])) + (", ..." if len(found) > 12 else "")
        raise InputError(f"{path}: no sensor of the model is at a node of the mode shapes (nodes {shown or 'none'}; "
                         f"mapping node:direction=name: {known}); give --mapping FILE.csv with columns "
                         "name,node,direction")
    shapes = np.array([[s["nodes"][node][component] * sign if node in s["nodes"] else 0.0
                        for node, component, sign in columns] for s in sets], dtype=complex)
    return outputs, shapes
