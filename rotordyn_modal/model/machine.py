"""The machine model: a rigid stator on suspensions carrying rigid rotors.

A :class:`Model` is built from a plain description (the structure of the TOML
model file, see ``docs/model-file.md``) and validated once, on construction.
Nothing is computed from a model that failed validation: every rule raises
:class:`~rotordyn_modal.errors.ModelError` naming the source, the table and
key, the value and what was expected.

All vectors and tensors are in *model axes* (the stator-fixed frame, the
seed's stereo-nodal frame S2), SI units.
"""

from __future__ import annotations

import copy
import dataclasses
from typing import Any, Mapping

import numpy as np

from . import _validation
from .components import (Bearing, Excitation, Rotor, Sensor, Stator, Suspension, Transmission,
                         Unbalance, input_keys)
from .parameters import change_at, get_value, parse_key, scale_value, set_value

__all__ = [
    "Model", "Stator", "Rotor", "Transmission", "Suspension", "Bearing", "Unbalance", "Sensor",
    "Excitation",
]

# ----------------------------------------------------------------------------------------
# The model
# ----------------------------------------------------------------------------------------
class Model:
    """A validated multi-rotor machine.

    Build it from a model file with :func:`rotordyn_modal.load_model`, from a
    description with :meth:`from_dict`, or in code::

        >>> import rotordyn_modal as rdm
        >>> machine = rdm.Model(
        ...     stator=rdm.Stator(mass=100.0, inertia=[5.0, 4.0, 4.0]),
        ...     rotors=[rdm.Rotor("r", 10.0, [0, 0, 0], 0.05, 0.04, speed_ratio=1.0)],
        ...     suspensions=[rdm.Suspension("s", [0, 0, 0], [1e5, 1e5, 1e5, 1e3, 1e3, 1e3])],
        ... )
        >>> machine.speed_ratios
        {'r': 1.0}
        >>> rdm.Model(rotors=[rdm.Rotor("r", -1.0, [0, 0, 0], 0.05, 0.04, speed_ratio=1.0)])
        Traceback (most recent call last):
        ...
        rotordyn_modal.errors.ModelError: <model>: [rotors.r] mass = -1.0: expected a finite number > 0

    Attributes
    ----------
    spin_axis : ndarray, shape (3,)
        Unit vector of every rotor's spin axis, model axes.
    reference_rotor : str
    speed_ratios : dict[str, float]
        Spin speed of each rotor / reference speed (signed about ``spin_axis``).
    source : str
        Where the description came from (file name), used in messages.
    clearances : tuple of Clearance
        The rotors' close-clearance stations (``[[rotors.clearances]]``), in file order.
    """

    def __init__(
        self,
        *,
        rotors=(),
        stator: Stator | Mapping | None = None,
        suspensions=(),
        bearings=(),
        transmissions=(),
        unbalances=(),
        sensors=(),
        excitations=(),
        spin_axis=(1.0, 0.0, 0.0),
        reference_rotor: str | None = None,
        gravity=None,
        name: str = "",
        source: str = "<model>",
    ):
        data: dict[str, Any] = {"name": name, "spin_axis": spin_axis}
        if reference_rotor is not None:
            data["reference_rotor"] = reference_rotor
        if gravity is not None:
            data["gravity"] = gravity
        if stator is not None:
            data["stator"] = _as_table(stator)
        for key, items in (("rotors", rotors), ("transmissions", transmissions),
                           ("suspensions", suspensions), ("bearings", bearings),
                           ("unbalances", unbalances),
                           ("sensors", sensors), ("excitations", excitations)):
            data[key] = [_as_table(item) for item in items]
        self._build(data, source)

    # -- construction --------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any], source: str = "<model>") -> "Model":
        """Validate a model description (the structure of the TOML file)."""
        self = cls.__new__(cls)
        self._build(data, source)
        return self

    def _build(self, data: Mapping[str, Any], source: str, earlier: "Model | None" = None) -> None:
        """Validate ``data``; with ``earlier`` (see :meth:`variant`) ``data`` is already a plain
        description of its own whose unchanged tables are ``earlier``'s."""
        self.source = source
        self._data = _validation.plain_copy(data, source) if earlier is None else data
        previous = None if earlier is None else (earlier._data, earlier._parts())
        validated = _validation.validate(self._data, source, previous)
        self.name = validated["name"]
        self.spin_axis = validated["spin_axis"]
        self.reference_rotor = validated["reference_rotor"]
        self.gravity = validated["gravity"]
        self.stator = validated["stator"]
        self.rotors = validated["rotors"]
        self.transmissions = validated["transmissions"]
        self.suspensions = validated["suspensions"]
        self.bearings = validated["bearings"]
        self.unbalances = validated["unbalances"]
        self.sensors = validated["sensors"]
        self.excitations = validated["excitations"]
        self.clearances = validated["clearances"]
        self.speed_ratios = {rotor.name: rotor.speed_ratio for rotor in self.rotors}
        if earlier is not None and self.same_bodies(earlier) and _same(self.bearings, earlier.bearings):
            self._dofs = earlier.dofs   # the coordinates follow from these alone

    def _parts(self) -> dict[str, Any]:
        """The validated parts by table name (as :func:`_validation.validate` returns them)."""
        return {"name": self.name, "spin_axis": self.spin_axis, "reference_rotor": self.reference_rotor,
                "gravity": self.gravity, "stator": self.stator, "rotors": self.rotors,
                "transmissions": self.transmissions, "suspensions": self.suspensions,
                "bearings": self.bearings, "unbalances": self.unbalances, "sensors": self.sensors,
                "excitations": self.excitations, "clearances": self.clearances}

    def same_bodies(self, other: "Model") -> bool:
        """True when both models hold the very same stator and rotor components (as a study's
        variants share them with their base model where no parameter touches them) about the
        same spin axis: then their masses, inertias, reference point and speed ratios are equal."""
        return (self.stator is other.stator and _same(self.rotors, other.rotors)
                and self.spin_axis.tobytes() == other.spin_axis.tobytes())

    def variant(self, changes) -> "Model":
        """A new, validated model with some values set or multiplied: a study's variant.

        The result equals ``Model.from_dict`` of the changed description, but the tables that
        no change touches are shared with this model's description and are not validated
        again (their validated parts, this model's, are shared too); the changed tables and
        every rule across tables are checked as usual.

        Parameters
        ----------
        changes : sequence of (str, str, float)
            ``(dotted key, "value" or "scale", number)``, applied in order (see
            :meth:`with_values` and :meth:`scaled`).

        Returns
        -------
        Model
        """
        data = dict(self._data)
        owned: set = set()
        for key, apply, value in changes:
            change_at(_own_value(data, key, self.source, owned), apply, value, key, self.source)
        model = Model.__new__(Model)
        model._build(data, self.source, earlier=self)
        return model

    # -- description ---------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model description as given (plain Python types), ready for TOML."""
        return copy.deepcopy(self._data)

    def get(self, key: str):
        """Value of a dotted key, e.g. ``"suspensions.mount-FL.stiffness[2]"``."""
        return get_value(self._data, key, self.source)

    def with_values(self, values: Mapping[str, Any]) -> "Model":
        """A new, validated model with dotted keys set to the given values."""
        data = self.to_dict()
        for key, value in values.items():
            set_value(data, key, value, self.source)
        return Model.from_dict(data, self.source)

    def scaled(self, factors: Mapping[str, float]) -> "Model":
        """A new, validated model with dotted keys (scalars or whole arrays) multiplied."""
        data = self.to_dict()
        for key, factor in factors.items():
            scale_value(data, key, factor, self.source)
        return Model.from_dict(data, self.source)

    # -- derived quantities --------------------------------------------------------------
    @property
    def reference_point(self) -> np.ndarray:
        """Point about which the matrices are written [m], model axes: the stator's
        centre of mass, or the machine's centre of mass when there is no stator."""
        if self.stator is not None:
            return self.stator.center_of_mass
        masses = np.array([r.mass for r in self.rotors])
        centres = np.array([r.center_of_mass for r in self.rotors])
        return masses @ centres / masses.sum()

    @property
    def total_mass(self) -> float:
        """Mass of the machine [kg]: the stator's, the rotors' and the bearings' pedestals'
        (a pedestal's weight is carried by the mounts as the others', docs/static.md)."""
        stator_mass = self.stator.mass if self.stator is not None else 0.0
        pedestals = sum(b.pedestal.mass for b in self.bearings if getattr(b, "pedestal", None) is not None)
        return stator_mass + sum(r.mass for r in self.rotors) + pedestals

    @property
    def dofs(self):
        """The generalized coordinates (:class:`rotordyn_modal.model.dofs.Dofs`): the stator's six
        motions, then those of each rotor on bearings."""
        if getattr(self, "_dofs", None) is None:
            from .dofs import dofs

            self._dofs = dofs(self)
        return self._dofs

    @property
    def speed_dependent(self) -> bool:
        """True when a bearing's coefficients depend on speed (tables, journal bearings)."""
        return any(b.coefficients.kind != "constant" for b in self.bearings)

    def bearings_of(self, rotor: str) -> list:
        """The bearings that carry ``rotor`` (empty: it is rigidly attached to the stator)."""
        return [b for b in self.bearings if b.rotor == rotor]

    def rotor(self, name: str) -> Rotor:
        """The rotor called ``name`` (``KeyError`` naming the model's rotors if none is)."""
        for rotor in self.rotors:
            if rotor.name == name:
                return rotor
        raise KeyError(f"no rotor {name!r}: the model's rotors are {', '.join(r.name for r in self.rotors)}")

    def matrices(self, speed: float | None = None):
        """``M, C, G, K`` over the generalized coordinates :attr:`dofs`, model axes.

        6x6 each, about :attr:`reference_point`, for a machine whose rotors are
        rigidly attached; rotors on bearings add their own coordinates. G is per
        unit reference speed [rad/s]: the velocity matrix at speed ``Omega`` is
        ``C + Omega * G``. ``speed`` [rad/s] is needed when bearing coefficients
        depend on speed. See :func:`rotordyn_modal.assembly.matrices`.
        """
        from ..assembly import matrices

        return matrices(self, speed)

    def state_space(self, speed: float, quantity: str = "displacement", inputs=None, outputs=None):
        """python-control ``StateSpace`` at ``speed`` [rad/s of the reference rotor].

        Inputs are the ``[[excitations]]``, outputs the ``[[sensors]]`` (named; ``inputs`` and
        ``outputs`` pick some of them by name, in the order given).
        See :func:`rotordyn_modal.linear_system.state_space`.
        """
        from ..linear_system import state_space

        return state_space(self, speed, quantity=quantity, inputs=inputs, outputs=outputs)

    def __repr__(self) -> str:
        return (f"Model({self.name!r}, rotors={[r.name for r in self.rotors]}, "
                f"suspensions={len(self.suspensions)}, source={self.source!r})")


def _same(a, b) -> bool:
    """The same component objects, in the same order."""
    return len(a) == len(b) and all(x is y for x, y in zip(a, b))


def _own_value(data: dict, key: str, source: str, owned: set):
    """Give ``data``, a shallow copy of a description, copies of its own of the table that
    ``key`` names and of the value there, so that setting the value leaves the original
    description as it was. ``owned`` records the copies already made (ids, and
    ``(id, field)`` pairs). Returns where the value sits (see
    :func:`~rotordyn_modal.model.parameters.parse_key`), in ``data``'s own copies."""
    container, field, indices = parse_key(key, data, source, missing_ok=True)
    if container is not data and id(container) not in owned:
        table = key.partition(".")[0]
        copy = dict(container)
        if table == "stator":
            data["stator"] = copy
        else:
            if id(data[table]) not in owned:
                data[table] = list(data[table])
                owned.add(id(data[table]))
            items = data[table]
            place = next((i for i, item in enumerate(items) if item is container), None)
            if place is None:       # a rotor's section, disk or point mass: copy the rotor's list too
                _own_nested(items, container, copy, owned)
            else:
                items[place] = copy
        owned.add(id(copy))
        container = copy
    if (id(container), field) not in owned and field in container:    # absent: set, not copied
        container[field] = _validation.plain_copy({field: container[field]}, source)[field]
        owned.add((id(container), field))
    return container, field, indices


def _own_nested(items: list, container: dict, copy: dict, owned: set) -> None:
    """Put ``copy`` where ``container`` sits inside one of ``items`` (``rotors[i][key][k]``, or deeper:
    ``rotors[i].shaft[k].layers[j]``), the tables and lists copied on the way (once: ``owned``)."""
    if not _replace_in(items, container, copy, owned):
        raise AssertionError("a nested table not found in its array")  # pragma: no cover


def _replace_in(items: list, container: dict, copy: dict, owned: set) -> bool:
    for i, item in enumerate(items):
        if item is container:
            items[i] = copy
            return True
        if not isinstance(item, dict):
            continue
        for key, inner in item.items():
            if isinstance(inner, list) and _holds(inner, container):
                if id(item) not in owned:
                    item = items[i] = dict(item)
                    owned.add(id(item))
                if id(item[key]) not in owned:
                    item[key] = list(inner)
                    owned.add(id(item[key]))
                return _replace_in(item[key], container, copy, owned)
    return False


def _holds(value, container: dict) -> bool:
    """``container`` is ``value`` or inside its arrays of tables."""
    if value is container:
        return True
    if isinstance(value, list):
        return any(_holds(x, container) for x in value)
    return isinstance(value, dict) and any(isinstance(v, list) and _holds(v, container) for v in value.values())


_TABLE_OF = {Stator: "stator", Rotor: "rotors", Transmission: "transmissions",
             Suspension: "suspensions", Bearing: "bearings", Unbalance: "unbalances",
             Sensor: "sensors", Excitation: "excitations"}


def _as_table(item) -> dict[str, Any]:
    if isinstance(item, Mapping):
        return dict(item)
    if dataclasses.is_dataclass(item):
        keys = input_keys(_TABLE_OF[type(item)])
        if isinstance(item, Unbalance) and item.grade is not None:
            keys = [k for k in keys if k != "amount"]   # the grade's amount, found again from it
        return {k: getattr(item, k) for k in keys if getattr(item, k) is not None}
    raise TypeError(f"expected a component or a mapping, got {type(item).__name__}")


