"""The model as the plain arrays the right-hand side kernels take."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..kinematics import transverse_basis


@dataclass(frozen=True)
class SystemArrays:
    """A model reduced to arrays (bodies: stator first when there is one, then the rotors).

    Attributes
    ----------
    e : (3,) spin axis; E2 : (3, 2) transverse basis; s : 1 with a stator, 0 without
    gravity : (3,) [m/s^2]
    mass : (nb,) [kg]; center : (nb, 3) axis points from the reference point [m];
    offset : (nb, 3) centre of mass from the axis point at angle 0 [m];
    inertia : (nb, 3, 3) about the centre of mass at angle 0 [kg m^2]; ratio : (nb,)
    spos : (ns, 3) [m]; sK, sC : (ns, 6, 6) on ``[u_P, theta]``
    reference_point : (3,) [m]; rotor_index : (n_rotors,) body index of each rotor
    """

    e: np.ndarray
    E2: np.ndarray
    s: int
    gravity: np.ndarray
    mass: np.ndarray
    center: np.ndarray
    offset: np.ndarray
    inertia: np.ndarray
    ratio: np.ndarray
    spos: np.ndarray
    sK: np.ndarray
    sC: np.ndarray
    reference_point: np.ndarray
    rotor_index: np.ndarray

    @property
    def n_dof(self) -> int:
        return 6 + self.s

    def kernel_arguments(self):
        """Arguments of ``assemble``/``rhs`` after ``(t, y)``."""
        return (self.e, self.E2, self.s, self.gravity, self.mass, self.center, self.offset,
                self.inertia, self.ratio, self.spos, self.sK, self.sC)


def refuse_hysteretic(model) -> None:
    """Hysteretic damping ``K (1 + i eta)`` exists in the frequency domain only."""
    lossy = [s for s in model.suspensions if s.loss_factor]
    if lossy:
        names = ", ".join(f"{s.name!r} (loss_factor = {s.loss_factor:g})" for s in lossy)
        raise InputError(
            f"{model.source}: suspensions {names}: a hysteretic loss factor has no meaning in the time "
            "domain; set loss_factor = 0 to simulate, and give the suspension viscous damping instead "
            "(damping = loss_factor * stiffness / omega matches it at one circular frequency omega)")
    branched = [s.name for s in model.suspensions if getattr(s, "maxwell_stiffness_matrix", None) is not None]
    if branched:
        raise InputError(
            f"{model.source}: suspensions {', '.join(map(repr, branched))}: Maxwell branches "
            "(maxwell_stiffness, maxwell_time) are not simulated in time yet; remove them to simulate "
            "with the static stiffness and viscous damping")


def unbalance_directions(model, phases_deg=None) -> np.ndarray:
    """Unit vectors of the unbalances at angle 0 (phase from ``e1`` towards ``e2``).

    Returns
    -------
    ndarray, shape (n_unbalances, 3)
    """
    basis = transverse_basis(model.spin_axis)
    phases = np.radians([u.phase_deg for u in model.unbalances] if phases_deg is None else phases_deg)
    return np.cos(phases)[:, None] * basis[:, 0] + np.sin(phases)[:, None] * basis[:, 1]


def system_arrays(model, unbalance_phases_deg=None) -> SystemArrays:
    """Reduce ``model`` to :class:`SystemArrays`.

    Parameters
    ----------
    model : Model
    unbalance_phases_deg : array_like, shape (n_unbalances,), optional
        Phases overriding the model's ``phase_deg`` [deg].
    """
    refuse_hysteretic(model)
    e = np.asarray(model.spin_axis, dtype=float)
    reference = np.asarray(model.reference_point, dtype=float)
    masses, centers, offsets, inertias, ratios = [], [], [], [], []
    if model.stator is not None:
        masses.append(model.stator.mass)
        centers.append(np.asarray(model.stator.center_of_mass) - reference)
        offsets.append(np.zeros(3))
        inertias.append(np.asarray(model.stator.inertia, dtype=float))
        ratios.append(0.0)
    directions = unbalance_directions(model, unbalance_phases_deg)
    for rotor in model.rotors:
        first_moment, products = np.zeros(3), np.zeros((3, 3))
        for unbalance, d in zip(model.unbalances, directions):
            if unbalance.rotor == rotor.name:
                first_moment += unbalance.amount * d
                products -= unbalance.amount * unbalance.axial_offset * (np.outer(e, d) + np.outer(d, e))
        rho = first_moment / rotor.mass
        about_axis = rotor.diametral_inertia * np.eye(3) \
            + (rotor.polar_inertia - rotor.diametral_inertia) * np.outer(e, e) + products
        masses.append(rotor.mass)
        centers.append(np.asarray(rotor.center_of_mass) - reference)
        offsets.append(rho)
        inertias.append(about_axis - rotor.mass * (rho @ rho * np.eye(3) - np.outer(rho, rho)))
        ratios.append(rotor.speed_ratio)
    suspensions = model.suspensions
    start = 1 if model.stator is not None else 0
    return SystemArrays(
        e=e, E2=transverse_basis(e), s=1 if model.stator is not None else 0,
        gravity=np.asarray(model.gravity, dtype=float),
        mass=np.array(masses, dtype=float), center=np.array(centers, dtype=float).reshape(-1, 3),
        offset=np.array(offsets, dtype=float).reshape(-1, 3),
        inertia=np.array(inertias, dtype=float).reshape(-1, 3, 3),
        ratio=np.array(ratios, dtype=float),
        spos=np.array([np.asarray(s.position) - reference for s in suspensions], dtype=float).reshape(-1, 3),
        sK=np.array([s.stiffness_matrix for s in suspensions], dtype=float).reshape(-1, 6, 6),
        sC=np.array([s.damping_matrix for s in suspensions], dtype=float).reshape(-1, 6, 6),
        reference_point=reference,
        rotor_index=np.arange(start, start + len(model.rotors)),
    )
