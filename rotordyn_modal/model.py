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
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from .errors import ModelError

__all__ = [
    "Model",
    "Stator",
    "Rotor",
    "Transmission",
    "Suspension",
    "Unbalance",
    "Sensor",
    "Excitation",
]

#: keys read at the top level of a model description
TOP_LEVEL_KEYS = (
    "name", "spin_axis", "reference_rotor", "gravity", "stator", "rotors", "transmissions",
    "suspensions", "unbalances", "sensors", "excitations",
)
#: the tables that are arrays of tables
ARRAY_TABLES = ("rotors", "transmissions", "suspensions", "unbalances", "sensors", "excitations")



# ----------------------------------------------------------------------------------------
# Components. Their fields are the model-file keys; validation fills normalised values.
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Stator:
    """The rigid stator (casing, skid, housing).

    Parameters
    ----------
    mass : float
        Mass [kg], > 0.
    inertia : array_like, shape (3,) or (3, 3)
        Inertia tensor about the stator's centre of mass, model axes [kg m^2];
        a 3-vector means a diagonal tensor.
    center_of_mass : array_like, shape (3,)
        Centre of mass in model axes [m].
    """

    mass: float
    inertia: Any
    center_of_mass: Any = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Rotor:
    """A rigid, axisymmetric rotor spinning about an axis parallel to ``spin_axis``.

    Parameters
    ----------
    name : str
    mass : float
        [kg], > 0.
    center_of_mass : array_like, shape (3,)
        [m], model axes.
    polar_inertia, diametral_inertia : float
        About the spin axis and about any normal axis through the centre of mass
        [kg m^2]; ``polar_inertia <= 2 * diametral_inertia``.
    speed_ratio : float or None
        Spin speed / reference speed, signed about ``spin_axis``; None when a
        transmission fixes it. After validation it holds the resolved ratio.
    """

    name: str
    mass: float
    center_of_mass: Any
    polar_inertia: float
    diametral_inertia: float
    speed_ratio: float | None = None


@dataclass(frozen=True)
class Transmission:
    """A gear (opposite directions) or belt (same direction) between two rotors.

    ``ratio`` is tau = |omega_driver| / |omega_driven| (seed 000, eq. 14);
    ``driver_teeth`` gives the gear-mesh order per revolution of the driver.
    """

    type: str
    driver: str
    driven: str
    ratio: float
    driver_teeth: int | None = None

    @property
    def direction_sign(self) -> float:
        """-1 for a gear (external mesh), +1 for a belt."""
        return -1.0 if self.type == "gear" else 1.0


@dataclass(frozen=True)
class Suspension:
    """A spring-damper between a point of the stator and the ground.

    ``stiffness`` and ``damping`` are a 3-vector (diagonal, N/m and N s/m), a
    3x3 translational matrix or a 6x6 matrix coupling forces and moments at the
    point, in the suspension's own ``axes`` (rows are its axes in model axes).
    After validation :attr:`stiffness_matrix` and :attr:`damping_matrix` hold
    the 6x6 matrices in model axes acting on ``[u_P, theta]`` at the point.

    ``maxwell_stiffness`` (a list of branches, each shaped like ``stiffness``)
    and ``maxwell_time`` (their relaxation times [s]) add generalized Maxwell
    branches (a spring ``k_b`` in series with a dashpot ``k_b tau_b``) for
    rubber: ``K_b i w tau_b / (1 + i w tau_b)`` in the frequency domain.
    """

    name: str
    position: Any
    stiffness: Any
    damping: Any = None
    loss_factor: float = 0.0
    axes: Any = None
    maxwell_stiffness: Any = None
    maxwell_time: Any = None
    stiffness_matrix: np.ndarray | None = field(default=None, repr=False, compare=False)
    damping_matrix: np.ndarray | None = field(default=None, repr=False, compare=False)
    #: (n_branches, 6, 6) stiffness of each Maxwell branch in model axes [N/m, ...]
    maxwell_stiffness_matrix: np.ndarray | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class Unbalance:
    """A mass unbalance on a rotor: ``amount`` [kg m] at ``phase_deg`` [deg] at t = 0,
    ``axial_offset`` [m] along the spin axis from the rotor's centre of mass."""

    rotor: str
    amount: float
    phase_deg: float = 0.0
    axial_offset: float = 0.0


@dataclass(frozen=True)
class Sensor:
    """A measurement direction (unit vector after validation) at a point of the stator."""

    name: str
    position: Any
    direction: Any


@dataclass(frozen=True)
class Excitation:
    """A force [N] (or, with ``kind="moment"``, a moment [N m]) input at a point of the stator."""

    name: str
    position: Any
    direction: Any
    kind: str = "force"


_COMPONENTS = {
    "stator": Stator,
    "rotors": Rotor,
    "transmissions": Transmission,
    "suspensions": Suspension,
    "unbalances": Unbalance,
    "sensors": Sensor,
    "excitations": Excitation,
}


def _input_keys(cls) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls) if f.init and not f.name.endswith("_matrix"))


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
    """

    def __init__(
        self,
        *,
        rotors=(),
        stator: Stator | Mapping | None = None,
        suspensions=(),
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
                           ("suspensions", suspensions), ("unbalances", unbalances),
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

    def _build(self, data: Mapping[str, Any], source: str) -> None:
        from . import _validation  # the rules live in one module of their own

        self.source = source
        self._data = _validation.plain_copy(data, source)
        validated = _validation.validate(self._data, source)
        self.name = validated["name"]
        self.spin_axis = validated["spin_axis"]
        self.reference_rotor = validated["reference_rotor"]
        self.gravity = validated["gravity"]
        self.stator = validated["stator"]
        self.rotors = validated["rotors"]
        self.transmissions = validated["transmissions"]
        self.suspensions = validated["suspensions"]
        self.unbalances = validated["unbalances"]
        self.sensors = validated["sensors"]
        self.excitations = validated["excitations"]
        self.speed_ratios = {rotor.name: rotor.speed_ratio for rotor in self.rotors}

    # -- description ---------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model description as given (plain Python types), ready for TOML."""
        return copy.deepcopy(self._data)

    def get(self, key: str):
        """Value of a dotted key, e.g. ``"suspensions.mount-FL.stiffness[2]"``."""
        from .parameters import get_value

        return get_value(self._data, key, self.source)

    def with_values(self, values: Mapping[str, Any]) -> "Model":
        """A new, validated model with dotted keys set to the given values."""
        from .parameters import set_value

        data = self.to_dict()
        for key, value in values.items():
            set_value(data, key, value, self.source)
        return Model.from_dict(data, self.source)

    def scaled(self, factors: Mapping[str, float]) -> "Model":
        """A new, validated model with dotted keys (scalars or whole arrays) multiplied."""
        from .parameters import scale_value

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
        """Mass of the machine [kg]."""
        stator_mass = self.stator.mass if self.stator is not None else 0.0
        return stator_mass + sum(r.mass for r in self.rotors)

    def rotor(self, name: str) -> Rotor:
        """The rotor called ``name``."""
        for rotor in self.rotors:
            if rotor.name == name:
                return rotor
        raise KeyError(name)

    def matrices(self):
        """``M, C, G, K``: 6x6 each, about :attr:`reference_point`, model axes.

        G is per unit reference speed [rad/s]: the velocity matrix at speed
        ``Omega`` is ``C + Omega * G``. See :func:`rotordyn_modal.assembly.matrices`.
        """
        from .assembly import matrices

        return matrices(self)

    def state_space(self, speed: float, quantity: str = "displacement"):
        """python-control ``StateSpace`` at ``speed`` [rad/s of the reference rotor].

        Inputs are the ``[[excitations]]``, outputs the ``[[sensors]]`` (named).
        See :func:`rotordyn_modal.linear_system.state_space`.
        """
        from .linear_system import state_space

        return state_space(self, speed, quantity=quantity)

    def __repr__(self) -> str:
        return (f"Model({self.name!r}, rotors={[r.name for r in self.rotors]}, "
                f"suspensions={len(self.suspensions)}, source={self.source!r})")


def _as_table(item) -> dict[str, Any]:
    if isinstance(item, Mapping):
        return dict(item)
    if dataclasses.is_dataclass(item):
        keys = _input_keys(type(item))
        return {k: getattr(item, k) for k in keys if getattr(item, k) is not None}
    raise TypeError(f"expected a component or a mapping, got {type(item).__name__}")


def component_class(table: str):
    """The component dataclass of a table name (``"rotors"`` -> :class:`Rotor`)."""
    return _COMPONENTS[table]


def input_keys(table: str) -> tuple[str, ...]:
    """The keys a table of the model description may hold."""
    return _input_keys(_COMPONENTS[table])


def is_finite_number(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool) \
        and math.isfinite(float(value))


def model_error(source: str, where: str, value, expected: str) -> ModelError:
    return ModelError(source, where, value, expected)
