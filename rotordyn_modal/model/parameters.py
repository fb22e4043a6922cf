"""Dotted keys that address one value of a model description.

``suspensions.mount-FL.damping`` names the key ``damping`` of the suspension
called ``mount-FL``; ``rotors.fan.polar_inertia`` likewise; ``stator.mass`` a
key of the stator table; ``spin_axis`` a top-level key. Tables of arrays
without names (transmissions, unbalances) are addressed by their index:
``transmissions.0.ratio``. One element of an array is selected with indices:
``suspensions.mount-FL.stiffness[2]`` or ``...stiffness[3][4]``. A flexible rotor's sections,
disks and point masses are reached through it: ``rotors.pump.shaft.3.outer_diameter`` (section 3,
counted from 0), ``rotors.pump.disks.impeller.mass``; a material's by its name:
``materials.steel.young_modulus``.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from ..errors import InputError
from ._table import plain, visible_names
from .components import ARRAY_TABLES

__all__ = ["parse_key", "get_value", "value_at", "set_value", "scale_value", "change_at"]

_INDEX = re.compile(r"\[(-?\d+)\]")


def parse_key(key: str, data: dict, source: str = "<model>", missing_ok: bool = False):
    """Split a dotted key into (container, field, indices), resolving table names.

    ``missing_ok``: a key its table leaves out (a section's ``inner_diameter``, a material's
    ``shear_modulus``) may be named, to be set: the model's validation then takes it or refuses
    it as a key of that table (with its own words, e.g. a misspelt key's suggestion).

    Returns
    -------
    container : dict
        The table that holds the field.
    field : str
    indices : tuple of int
    """
    if not isinstance(key, str) or not key:
        raise InputError(f"{source}: parameter key {key!r}: expected a dotted key such as "
                         "'suspensions.mount-FL.damping'")
    match = re.search(r"(\[-?\d+\])+$", key)
    indices = tuple(int(i) for i in _INDEX.findall(match.group(0))) if match else ()
    path = key[: match.start()] if match else key
    table, _, rest = path.partition(".")
    if table in ARRAY_TABLES:
        container, field = _array_element(data, table, rest, key, source)
        container, field = _nested_element(container, field, key, source)
    elif table == "stator" and rest:
        container, field = data.get("stator", {}), rest
        if "stator" not in data:
            raise InputError(f"{source}: parameter key {key!r}: the model has no [stator]")
    elif not rest:
        container, field = data, table
    else:
        raise InputError(f"{source}: parameter key {key!r}: expected it to start with one of "
                         + ", ".join(("stator",) + ARRAY_TABLES) + " or to be a top-level key")
    if field not in container and not (missing_ok and not indices):
        known = visible_names(k for k in container if not isinstance(container[k], (dict, list)) or
                          (isinstance(container[k], list) and container[k] and not isinstance(container[k][0], dict)))
        raise InputError(f"{source}: parameter key {key!r}: no value {field!r} there (it has {known})")
    return container, field, indices


def _array_element(data, table, rest, key, source):
    items = data.get(table, [])
    names = [str(item.get("name", i)) for i, item in enumerate(items)]
    for name, item in sorted(zip(names, items), key=lambda pair: -len(pair[0])):
        if rest.startswith(name + "."):
            return item, rest[len(name) + 1:]
    for i, item in enumerate(items):  # index for tables without names
        if rest.startswith(f"{i}."):
            return item, rest[len(str(i)) + 1:]
    raise InputError(f"{source}: parameter key {key!r}: expected {table}.NAME.KEY with NAME one of "
                     + (visible_names(names) or f"(no [[{table}]] defined)"))


def _nested_element(container, field, key, source):
    """Into the arrays of tables a table holds: ``shaft.3.outer_diameter`` of a rotor names the
    key ``outer_diameter`` of its section 3, ``disks.impeller.mass`` that of its disk called
    ``impeller`` (by name, or by index for tables without names)."""
    while "." in field:
        sub, _, rest = field.partition(".")
        items = container.get(sub)
        if not (isinstance(items, list) and items and all(isinstance(item, dict) for item in items)):
            break
        container, field = _array_element(container, sub, rest, key, source)
    return container, field


def get_value(data: dict, key: str, source: str = "<model>"):
    """The value a dotted key names."""
    return value_at(parse_key(key, data, source), key, source)


def value_at(located, key, source):
    """The value at a place :func:`parse_key` found (``(container, field, indices)``)."""
    container, field, indices = located
    if field not in container:        # named to be set (parse_key's missing_ok): nothing to read
        raise InputError(f"{source}: parameter key {key!r}: the model file gives no {field!r} there, so there is "
                         f"no value to multiply (set it with values / apply = 'value', or give {field} in the file)")
    value = container[field]
    for depth, index in enumerate(indices):
        value = _index(value, index, key, depth, source)
    return value


def _index(value, index, key, depth, source):
    if not isinstance(value, list) or not -len(value) <= index < len(value):
        size = len(value) if isinstance(value, list) else 0
        raise InputError(f"{source}: parameter key {key!r}: index {index} at depth {depth + 1} "
                         f"out of range (that level has {size} elements)")
    return value[index]


def set_value(data: dict, key: str, value: Any, source: str = "<model>") -> None:
    """Set the value a dotted key names (in place); a key its table leaves out is added (the
    model's validation takes or refuses it)."""
    change_at(parse_key(key, data, source, missing_ok=True), "value", value, key, source)


def scale_value(data: dict, key: str, factor: float, source: str = "<model>") -> None:
    """Multiply the value (a number, or every number of an array) a dotted key names."""
    change_at(parse_key(key, data, source), "scale", factor, key, source)


def change_at(located, apply: str, value, key: str, source: str = "<model>") -> None:
    """Set (``apply="value"``) or multiply (``"scale"``) the value at a place :func:`parse_key`
    found: ``located`` is its ``(container, field, indices)``, ``key`` names it in messages."""
    container, field, indices = located
    if apply != "value":
        current = value_at(located, key, source)
        try:
            with np.errstate(over="ignore", invalid="ignore"):  # an infinite result is refused by validation
                value = (np.asarray(current, dtype=float) * float(value)).tolist()
        except (TypeError, ValueError):
            raise InputError(f"{source}: parameter key {key!r}: holds {current!r}, which is not numeric "
                             "and cannot be scaled") from None
    if not indices:
        container[field] = plain(value)
        return
    target = container[field]
    for depth, index in enumerate(indices[:-1]):
        target = _index(target, index, key, depth, source)
    _index(target, indices[-1], key, len(indices) - 1, source)
    target[indices[-1]] = plain(value)
    if field == "inertia" and len(indices) == 2 and indices[0] != indices[1]:
        # a product of inertia is one parameter: keep the tensor symmetric
        container[field][indices[1]][indices[0]] = plain(value)
