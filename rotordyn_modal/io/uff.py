"""Universal File Format dataset 58 / 58b (FRFs and coherence) through ``pyuff``.

Written: function type 4 (FRF), abscissa frequency [Hz] (type 18), ordinate
displacement (8), velocity (11) or acceleration (12) over excitation force
(13), SI unit labels, spin speed in the z-axis value [rpm]; coherence as
function type 6 next to each FRF. Read: the same, and files from other tools
whose unit labels are SI (``m``, ``m/s``, ``m/s^2`` over ``N``) or ``NONE``.

``pyuff`` pitfalls handled here: ``write_sets(mode='overwrite')`` corrupts a
file that starts with a binary 58b set, so every file is written new (a
temporary file, mode 'add', then renamed); ``orddenom_spec_data_type`` has no
default, so it is always given.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["read_uff58", "write_uff58", "ORDINATE_TYPES"]

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
    from .measured import assemble

    sets = _read_sets(path)
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
