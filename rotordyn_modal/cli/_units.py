"""The unit system of the command line (``--units si|us``, or ROTORDYN_MODAL_UNITS): chosen
once, applied to the tables printed and written and to the figures (docs/units.md). The
analyses stay in SI; only what is shown is converted, here and in the figures."""

from __future__ import annotations

import argparse
import os
import re

import numpy as np

from ..errors import InputError
from ..units import UNIT_SYSTEMS, from_system, to_system, unit_label

#: environment variable naming the unit system when ``--units`` is not given
ENVIRONMENT = "ROTORDYN_MODAL_UNITS"

UNITS_HELP = (f"unit system of the tables and figures: si (default) or us (in, mil, lbf, lbf/in, lb in², "
              f"rpm; docs/units.md); also set once by the environment variable {ENVIRONMENT} (this option wins). "
              "Model files are always SI")

#: column-name endings that carry an SI unit -> the US ending (``x_m`` -> ``x_in``)
US_ENDINGS = {"_m": "_in", "_N": "_lbf", "_Nm": "_lbfin", "_n_per_m": "_lbf_per_in", "_Pa": "_psi"}


#: ``--units`` help of the sub-commands whose output has nothing to convert (their module's UNITS_HELP)
NOTHING_TO_CONVERT = ("accepted (as in every sub-command: set once, e.g. by {env}) but nothing here changes "
                      "with it: speeds are rpm (or --speed-unit), frequencies Hz, damping ratios and log "
                      "decrements have no unit (docs/units.md)").format(env=ENVIRONMENT)
#: ``--units`` help of the sub-commands that stay SI for now (their module's UNITS_HELP)
STAYS_SI = ("accepted (as in every sub-command: set once, e.g. by {env}) but this sub-command reads, prints and "
            "writes SI (m, kg, N, N/m) whatever it says: not converted yet (docs/units.md)").format(env=ENVIRONMENT)


def add_units_option(parser, suppress: bool = False, help: str | None = None):
    """``--units`` on the main parser (default None) or a sub-command's (``suppress``: it sets
    nothing when not given, so the main parser's value stands); ``help`` replaces the usual text
    (a sub-command that converts nothing says so)."""
    parser.add_argument("--units", metavar="si|us", default=argparse.SUPPRESS if suppress else None,
                        help=help or UNITS_HELP)


def resolve_units(given) -> str:
    """The unit system: ``--units`` if given, else ROTORDYN_MODAL_UNITS, else 'si'.

    Raises
    ------
    InputError
        A value that is not si or us (one line naming where it came from).
    """
    source, value = ("--units", given) if given is not None else (ENVIRONMENT, os.environ.get(ENVIRONMENT))
    if value is None or (source == ENVIRONMENT and not value.strip()):
        return "si"
    name = str(value).strip().lower()
    if name not in UNIT_SYSTEMS:
        raise InputError(f"{source} {value!r}: expected one of {', '.join(UNIT_SYSTEMS)} (SI or US customary units)")
    return name


def us_column(name: str) -> str:
    """The US name of a column whose name ends in its SI unit (``Fx_N`` -> ``Fx_lbf``); others unchanged."""
    for ending in sorted(US_ENDINGS, key=len, reverse=True):
        if name.endswith(ending):
            return name[:-len(ending)] + US_ENDINGS[ending]
    return name


#: quantity kind of the columns whose name ends in an SI unit
_ENDING_KINDS = {"_m": "length", "_N": "force", "_Nm": "moment", "_n_per_m": "stiffness", "_Pa": "pressure"}


def kinds_by_ending(columns) -> dict:
    """Column -> kind of every column whose name ends in an SI unit (``x_m``: length, ``Fx_N``:
    force, ``Mx_Nm``: moment, ``stiffness_n_per_m``: stiffness, ``stress_Pa``: pressure); for
    :func:`convert_table`."""
    kinds = {}
    for column in columns:
        ending = next((e for e in sorted(_ENDING_KINDS, key=len, reverse=True) if str(column).endswith(e)), None)
        if ending:
            kinds[column] = _ENDING_KINDS[ending]
    return kinds


def convert_table(table, kinds: dict, system: str, row_kinds=None, unit_column: bool = False):
    """``table`` (SI) in ``system``: the table itself for 'si' (SI output stays as it was).

    Parameters
    ----------
    table : pandas.DataFrame
    kinds : dict
        Column -> quantity kind (:data:`rotordyn_modal.units.QUANTITIES`) of its values; columns
        not named are left as they are. Columns whose name ends in an SI unit are renamed
        (:func:`us_column`).
    system : {'si', 'us'}
    row_kinds : array_like of str, shape (len(table),), optional
        The kind of each row's values in the columns of ``kinds`` whose kind is ``'row'`` (a
        column that mixes quantities, such as ``amplitude`` with sensors and forces).
    unit_column : bool
        Add a last column ``unit``: each row's unit of the ``'row'`` columns.
    """
    if system == "si":
        return table
    table = table.copy()
    for column, kind in kinds.items():
        if column not in table:
            continue
        values = table[column].to_numpy(dtype=float)
        if kind == "row":
            table[column] = _by_row(values, row_kinds, system)
        else:
            table[column] = to_system(values, kind, system)
    if unit_column and row_kinds is not None:
        table["unit"] = [unit_label(kind, system) if kind else "" for kind in row_kinds]
    round_off = table.attrs.get("round_off", {})
    table.attrs["round_off"] = {us_column(c): _round_off(v, kinds.get(c), row_kinds, system)
                                for c, v in round_off.items()}
    return table.rename(columns={c: us_column(c) for c in table.columns if c in kinds})


def _by_row(values, row_kinds, system):
    out = np.array(values, dtype=float)
    row_kinds = np.asarray(row_kinds, dtype=object)
    for kind in set(row_kinds):
        if kind:
            rows = row_kinds == kind
            out[rows] = to_system(values[rows], kind, system)
    return out


def _round_off(noise, kind, row_kinds, system):
    """The round-off of a converted column (``table.attrs['round_off']``) in its new unit."""
    if kind is None:
        return noise
    if kind == "row":
        return _by_row(np.broadcast_to(np.asarray(noise, dtype=float), (len(row_kinds),)), row_kinds, system)
    return to_system(noise, kind, system)


# -- model keys (fit, study): the quantity of a dotted key's value ---------------------------------
#: quantity kind (:data:`rotordyn_modal.units.QUANTITIES`) of a model key's value by its field
#: name (docs/model-file.md, SI there); a field not named here is shown as the model file gives it
KEY_KINDS = {
    **dict.fromkeys(("mass", "pedestal_mass"), "mass"),
    **dict.fromkeys(("polar_inertia", "diametral_inertia", "inertia"), "inertia"),
    **dict.fromkeys(("stiffness", "maxwell_stiffness", "pedestal_stiffness", "axial_stiffness", "mesh_stiffness"),
                    "stiffness"),
    **dict.fromkeys(("damping", "pedestal_damping", "axial_damping", "mesh_damping"), "damping"),
    "moment_stiffness": "moment",                                      # N m/rad: a moment per radian
    **dict.fromkeys(("center_of_mass", "position", "axial_position", "axial_offset", "start", "length",
                     "outer_diameter", "inner_diameter", "element_length", "width", "diameter", "clearance",
                     "radial_clearance", "driver_radius"), "length"),
    "amount": "unbalance", "viscosity": "viscosity", "load": "force", "pretension": "force",
    "density": "density", **dict.fromkeys(("young_modulus", "shear_modulus", "allowable_stress"), "pressure"),
}
#: the unit of the fields that keep their model-file unit in every system
KEY_UNITS = {"maxwell_time": "s", "phase_deg": "deg", "pressure_angle": "deg", "service_speed_rpm": "rpm",
             "gravity": "m/s²", "moment_damping": "N m s/rad"}
#: a suspension's stiffness or damping with rotations (a 6-list, 6x6): the kind of each block
#: (translations, rotations); N m s/rad has no kind (shown in SI)
_SIX_BY_SIX = {"stiffness": (("stiffness", "force"), ("force", "moment")),
               "maxwell_stiffness": (("stiffness", "force"), ("force", "moment")),
               "damping": (("damping", None), (None, None))}
_FIELD = re.compile(r"^(?P<path>.*?)(?P<indices>(\[-?\d+\])*)$")


def key_kind(key: str, model=None):
    """The quantity kind of a dotted model key's value (``suspensions.FL.stiffness[2]``:
    'stiffness'), or None when it has no unit to convert (ratios, times, angles, ``gain``) or
    mixes units (a suspension's whole 6-list or 6x6 stiffness, translations beside rotations).

    Parameters
    ----------
    key : str
    model : Model, optional
        Tells a suspension's 6-list or 6x6 matrix from its 3-list or 3x3 (without it, a
        suspension's stiffness and damping count as translational).
    """
    match = _FIELD.match(key)
    path, field = match.group("path"), match.group("path").rpartition(".")[2]
    if key.startswith("suspensions.") and field in _SIX_BY_SIX and model is not None:
        indices = [int(i) for i in re.findall(r"-?\d+", match.group("indices"))]
        whole = model.get(path)
        if field.startswith("maxwell"):    # a list of branches: the first index picks one
            if not indices:
                return None if any(np.size(branch) > 9 or np.size(branch) == 6 for branch in whole) else "stiffness"
            whole, indices = whole[indices[0]], indices[1:]
        shape = np.shape(whole)
        if max(shape, default=0) == 6:     # rotations too: the kind of the entry's block
            rows = [indices[0] % 6 >= 3] if indices else []
            if len(shape) == 2:
                rows = [indices[0] % 6 >= 3, indices[1] % 6 >= 3] if len(indices) == 2 else []
            elif rows:
                rows = rows * 2                # a diagonal entry
            return _SIX_BY_SIX[field][rows[0]][rows[1]] if rows else None
    return KEY_KINDS.get(field)


def key_unit(key: str, system: str, model=None) -> str:
    """The unit a dotted key's value is shown in (``lbf/in``), ``-`` for a number without unit,
    ``SI`` for one whose units are mixed (a suspension's 6x6, shown as the model file gives it)."""
    kind = key_kind(key, model)
    if kind is not None:
        return unit_label(kind, system)
    field = _FIELD.match(key).group("path").rpartition(".")[2]
    if key.startswith("suspensions.") and field in _SIX_BY_SIX and model is not None:
        return "SI"
    return KEY_UNITS.get(field, "-")


def key_value_in(key: str, value, system: str, model=None, inverse: bool = False):
    """A dotted key's SI ``value`` (scalar or list) in ``system`` (``inverse``: from it to SI);
    unchanged when its kind is None (:func:`key_kind`)."""
    kind = key_kind(key, model)
    if kind is None or system == "si":
        return value
    convert = from_system if inverse else to_system
    return float(convert(value, kind, system)) if np.ndim(value) == 0 else \
        [float(v) for v in np.ravel(convert(np.asarray(value, dtype=float), kind, system))]
