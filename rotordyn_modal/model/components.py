"""The components of a machine model, one dataclass per table of the model file.

Their fields are the model-file keys (``docs/model-file.md``); validation
(:mod:`rotordyn_modal.model._validation`) fills the normalised values. All vectors and
tensors are in *model axes* (the stator-fixed frame), SI units.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "Stator", "Rotor", "Transmission", "Suspension", "Bearing", "Pedestal", "Unbalance", "Sensor", "Excitation",
    "Clearance", "TOP_LEVEL_KEYS", "ARRAY_TABLES", "component_class", "input_keys", "is_finite_number",
]

#: keys read at the top level of a model description
TOP_LEVEL_KEYS = (
    "name", "spin_axis", "reference_rotor", "gravity", "stator", "rotors", "transmissions",
    "suspensions", "bearings", "unbalances", "sensors", "excitations", "materials",
)
#: the tables that are arrays of tables
ARRAY_TABLES = ("rotors", "transmissions", "suspensions", "bearings", "unbalances", "sensors",
                "excitations", "materials")



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
    shaft, disks, point_masses, start, shear, element_length, coupling_position
        The keys of a flexible rotor (docs/model-file.md, "Flexible rotors"). After validation
        :attr:`flexible` holds its :class:`~rotordyn_modal.model.flexible.Shaft` with the mesh,
        and ``mass`` ... ``diametral_inertia`` the values computed from it; None for a rigid rotor.
    clearances : list of dict, optional
        ``[[rotors.clearances]]``: close-clearance stations (seals), validated into
        :class:`Clearance` items (``Model.clearances``).
    """

    name: str
    mass: float
    center_of_mass: Any
    polar_inertia: float
    diametral_inertia: float
    speed_ratio: float | None = None
    shaft: Any = None
    disks: Any = None
    point_masses: Any = None
    start: Any = None
    shear: str | None = None
    element_length: float | None = None
    coupling_position: float | None = None
    clearances: Any = None
    flexible: Any = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class Clearance:
    """A close-clearance station of a rotor (a labyrinth seal, an impeller eye seal, a balance
    piston): a point on the rotor's axis and the radial running clearance there.

    Parameters
    ----------
    name : str
        Unique among the model's clearances.
    rotor : str
    position : ndarray, shape (3,) [m]
        The point on the rotor's axis, model axes (a node of a flexible rotor's mesh).
    radial_clearance : float [m]
        The minimum design radial running clearance (half the diametral one), > 0.
    axial_position : float or None [m]
        On a flexible rotor, the station from the shaft's start; None on a rigid rotor.
    """

    name: str
    rotor: str
    position: Any
    radial_clearance: float
    axial_position: float | None = None

    @property
    def diametral_clearance(self) -> float:
        """[m] twice the radial clearance."""
        return 2.0 * self.radial_clearance


@dataclass(frozen=True)
class Transmission:
    """A gear (opposite directions) or belt (same direction) between two rotors.

    ``ratio`` is tau = |omega_driver| / |omega_driven| (docs/theory.md §5);
    ``driver_teeth`` gives the gear-mesh order per revolution of the driver.

    For the static loads of a transmitted torque (docs/static.md): ``position`` [m], a point
    of the plane (normal to the spin axis) in which the wheels or pulleys sit (default: the
    driver's centre of mass); ``driver_radius`` [m], the driver's pitch radius (gear; default
    from the centre distance a: ``a / (1 + ratio)``) or pulley radius (belt); a gear's
    ``pressure_angle`` [deg] (default 20); a belt's ``pretension`` [N] in each strand at rest
    (default 0).

    ``mesh_stiffness`` [N/m] and ``mesh_damping`` [N s/m] of a gear: a spring and damper along
    the line of action at the pitch point, between the two gears' lateral motions
    (docs/theory.md §18); without them the transmission fixes the speed ratio only.
    """

    type: str
    driver: str
    driven: str
    ratio: float
    driver_teeth: int | None = None
    position: Any = None
    driver_radius: float | None = None
    pressure_angle: float | None = None
    pretension: float | None = None
    mesh_stiffness: float | None = None
    mesh_damping: float | None = None

    @property
    def label(self) -> str:
        """``DRIVER->DRIVEN``: how messages and static loads name the transmission."""
        return f"{self.driver}->{self.driven}"

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
class Bearing:
    """A bearing: springs and dampers between a rotor and the stator (or the ground).

    It acts at ``position``, a point on the rotor's spin axis, between the rotor
    and the stator point at the same place. A rotor with at least one bearing
    moves relative to the stator (lateral translations and tilts, and axially
    when a bearing gives ``axial_stiffness``); its spin stays fixed by its speed
    ratio. Without a ``[stator]`` the bearings connect the rotors to the ground.

    Coefficients (in the bearing's radial ``axes``, normal to the spin axis):
    ``stiffness``/``damping`` radial [N/m, N s/m], ``axial_stiffness``/
    ``axial_damping`` [N/m, N s/m], ``moment_stiffness``/``moment_damping`` (tilt)
    [N m/rad, N m s/rad]; each a scalar (isotropic), a 2-list (diagonal) or a 2x2
    matrix (cross-coupled, non-symmetric allowed); axial ones scalars. With
    ``speeds_rpm`` each is given per speed (a list of such values) and
    interpolated linearly in the carried rotor's own speed. ``type = "journal"``
    computes the radial coefficients of a plain short journal bearing from
    ``diameter``, ``length``, ``clearance`` (radial), ``viscosity`` and the static
    ``load`` (given, or the rotor's weight share under ``gravity``).

    After validation :attr:`coefficients` holds the normalised description
    (see :class:`rotordyn_modal.bearing_coefficients.BearingCoefficients`).

    A bearing may stand on a pedestal: ``pedestal_mass`` [kg] moving in the two directions
    normal to the spin axis, held by ``pedestal_stiffness`` [N/m] (and ``pedestal_damping``
    [N s/m]; each a number, 2-list or symmetric 2x2 in the bearing's radial ``axes``) to the
    stator point (or the ground); the bearing then acts between the rotor and the pedestal.
    After validation :attr:`pedestal` holds its :class:`Pedestal` (None without one).
    """

    name: str
    rotor: str
    position: Any
    type: str = "linear"
    stiffness: Any = None
    damping: Any = None
    axial_stiffness: Any = None
    axial_damping: Any = None
    moment_stiffness: Any = None
    moment_damping: Any = None
    axes: Any = None
    speeds_rpm: Any = None
    diameter: float | None = None
    length: float | None = None
    clearance: float | None = None
    viscosity: float | None = None
    load: float | None = None
    load_direction: Any = None
    axial_position: float | None = None
    pedestal_mass: float | None = None
    pedestal_stiffness: Any = None
    pedestal_damping: Any = None
    coefficients: Any = field(default=None, repr=False, compare=False)
    pedestal: Any = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class Pedestal:
    """A bearing's pedestal after validation: a point mass moving normal to the spin axis
    between the bearing and the stator (or the ground).

    Attributes
    ----------
    mass : float
        [kg], > 0.
    stiffness, damping : ndarray, shape (3, 3)
        Model axes [N/m, N s/m], acting on the pedestal's translation relative to the stator
        point at the bearing (zero along the spin axis); symmetric.
    """

    mass: float
    stiffness: np.ndarray
    damping: np.ndarray


@dataclass(frozen=True)
class Unbalance:
    """A mass unbalance on a rotor: ``amount`` [kg m] at ``phase_deg`` [deg] at t = 0,
    ``axial_offset`` [m] along the spin axis from the rotor's centre of mass.

    Or, instead of ``amount``, an ISO 21940-11 balance ``grade`` G [mm/s] (given as
    ``"G2.5"`` or 2.5) at ``service_speed_rpm`` [rpm] of that rotor: after validation
    ``amount`` holds the permissible residual unbalance ``G m / Omega``, ``m`` the rotor's
    mass or ``mass`` [kg] when given (a part of it).
    """

    rotor: str
    amount: float | None = None
    phase_deg: float = 0.0
    axial_offset: float = 0.0
    grade: Any = None
    service_speed_rpm: float | None = None
    mass: float | None = None
    axial_position: float | None = None


@dataclass(frozen=True)
class Sensor:
    """A measurement direction (unit vector after validation) at a point of the machine.

    By default the point belongs to the stator (an accelerometer on the casing).
    With ``rotor`` it belongs to that rotor: ``measure = "absolute"`` gives the
    rotor point's motion, ``measure = "relative"`` its motion relative to the
    stator point at the same place (a proximity probe mounted in a bearing
    housing, reading the shaft).
    """

    name: str
    position: Any
    direction: Any
    rotor: str | None = None
    measure: str = "absolute"
    axial_position: float | None = None


@dataclass(frozen=True)
class Excitation:
    """A force [N] (or, with ``kind="moment"``, a moment [N m]) input at a point of the
    stator, or of ``rotor`` when given."""

    name: str
    position: Any
    direction: Any
    kind: str = "force"
    rotor: str | None = None
    axial_position: float | None = None


_COMPONENTS = {
    "stator": Stator,
    "rotors": Rotor,
    "transmissions": Transmission,
    "suspensions": Suspension,
    "bearings": Bearing,
    "unbalances": Unbalance,
    "sensors": Sensor,
    "excitations": Excitation,
}


def _input_keys(cls) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls)
                 if f.init and not f.name.endswith("_matrix") and f.name not in ("coefficients", "flexible", "pedestal"))


def component_class(table: str):
    """The component dataclass of a table name (``"rotors"`` -> :class:`Rotor`)."""
    return _COMPONENTS[table]


@functools.lru_cache(maxsize=None)
def input_keys(table: str) -> tuple[str, ...]:
    """The keys a table of the model description may hold."""
    return _input_keys(_COMPONENTS[table])


def is_finite_number(value) -> bool:
    """True for an int or float (not a bool) that is finite (an integer beyond every float is not)."""
    if not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False
