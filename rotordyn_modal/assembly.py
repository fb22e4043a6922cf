"""Assembly of the global matrices of seed 000, eq. (76)/(77).

Coordinates ``q = [u_x, u_y, u_z, theta_x, theta_y, theta_z]``: small
translation [m] and rotation [rad] of the stator at the reference point S
(its centre of mass), model axes. The linearized equation is::

    M q'' + (C + Omega G) q' + K q = f

* ``M = M_S + sum_j B_Sj M_j B_Sj^T`` (eq. 77), ``M_j = diag(m_j I, J_j)``
  about rotor j's centre of mass, ``J_j = J_d I + (J_p - J_d) e e^T``.
* ``G = sum_j B_Sj G_j B_Sj^T`` with ``G_j = diag(0, g_j)`` and
  ``g_j = -J_p,j r_j skew(e)`` per unit reference speed (eq. 52, r_j the
  speed ratio); the shift leaves it unchanged, since G_j acts on rotations only.
* ``K = sum_i B_SP_i K_i B_SP_i^T`` and likewise C for the suspensions.

Derivations and sign conventions: ``docs/theory.md``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import point_force_column, point_motion_row, shift_matrix, skew

__all__ = ["Matrices", "matrices", "rigid_mass_matrix", "body_inertias", "loss_stiffness",
           "sensor_rows", "excitation_columns"]


class Matrices(NamedTuple):
    """The global matrices, 6x6 each, about the reference point, model axes.

    Attributes
    ----------
    M : ndarray, shape (6, 6)
        Mass [kg, kg m, kg m^2].
    C : ndarray, shape (6, 6)
        Viscous damping [N s/m, ...].
    G : ndarray, shape (6, 6)
        Gyroscopic matrix per unit reference speed [kg m^2] (skew-symmetric).
    K : ndarray, shape (6, 6)
        Stiffness [N/m, N/rad, N m/m, N m/rad].
    """

    M: np.ndarray
    C: np.ndarray
    G: np.ndarray
    K: np.ndarray


def rigid_mass_matrix(mass: float, inertia, center, reference) -> np.ndarray:
    """Mass matrix of a rigid body about ``reference``: ``B_SR diag(m I, J) B_SR^T``.

    Parameters
    ----------
    mass : float
        [kg]
    inertia : array_like, shape (3, 3)
        Inertia tensor about the body's centre of mass [kg m^2].
    center, reference : array_like, shape (3,)
        Centre of mass R and reference point S [m].

    Returns
    -------
    ndarray, shape (6, 6)
    """
    local = np.zeros((6, 6))
    local[:3, :3] = mass * np.eye(3)
    local[3:, 3:] = inertia
    shift = shift_matrix(reference, center)
    return shift @ local @ shift.T


def body_inertias(model):
    """Mass, centre of mass and inertia tensor of every body (stator first).

    Returns
    -------
    list of (mass [kg], center (3,) [m], inertia (3, 3) [kg m^2])
    """
    e = model.spin_axis
    bodies = []
    if model.stator is not None:
        bodies.append((model.stator.mass, model.stator.center_of_mass, model.stator.inertia))
    for rotor in model.rotors:
        inertia = rotor.diametral_inertia * np.eye(3) + (rotor.polar_inertia - rotor.diametral_inertia) * np.outer(e, e)
        bodies.append((rotor.mass, rotor.center_of_mass, inertia))
    return bodies


def _suspension_sum(model, attribute: str) -> np.ndarray:
    reference = model.reference_point
    total = np.zeros((6, 6))
    for suspension in model.suspensions:
        shift = shift_matrix(reference, suspension.position)
        total += shift @ getattr(suspension, attribute) @ shift.T
    return total


def loss_stiffness(model) -> np.ndarray:
    """``sum_i eta_i B K_i B^T``: the imaginary part of the hysteretic stiffness ``K (1 + i eta)``.

    Returns
    -------
    ndarray, shape (6, 6) [N/m, ...]
    """
    reference = model.reference_point
    total = np.zeros((6, 6))
    for suspension in model.suspensions:
        if suspension.loss_factor:
            shift = shift_matrix(reference, suspension.position)
            total += suspension.loss_factor * (shift @ suspension.stiffness_matrix @ shift.T)
    return total


def gyroscopic_matrix(model) -> np.ndarray:
    """Global gyroscopic matrix per unit reference speed (seed eq. 52 and 77).

    Returns
    -------
    ndarray, shape (6, 6) [kg m^2]
    """
    polar_momentum = sum(r.polar_inertia * r.speed_ratio for r in model.rotors)
    out = np.zeros((6, 6))
    out[3:, 3:] = -polar_momentum * skew(model.spin_axis)
    return out


def matrices(model) -> Matrices:
    """``M, C, G, K`` of the linearized global equation (seed 000, eq. 77).

    Parameters
    ----------
    model : Model

    Returns
    -------
    Matrices
        Named tuple ``(M, C, G, K)``, each ndarray of shape (6, 6).
    """
    reference = model.reference_point
    mass = sum(rigid_mass_matrix(m, J, c, reference) for m, c, J in body_inertias(model))
    return Matrices(
        M=0.5 * (mass + mass.T),
        C=_suspension_sum(model, "damping_matrix"),
        G=gyroscopic_matrix(model),
        K=_suspension_sum(model, "stiffness_matrix"),
    )


def sensor_rows(model, names=None) -> np.ndarray:
    """Rows mapping ``q`` to the sensors' displacements along their directions.

    Returns
    -------
    ndarray, shape (n_sensors, 6) [m/m, m/rad]
    """
    sensors = _select(model.sensors, names, "sensor")
    reference = model.reference_point
    return np.array([point_motion_row(s.position, reference, s.direction) for s in sensors]).reshape(-1, 6)


def excitation_columns(model, names=None) -> np.ndarray:
    """Columns mapping the excitations' amplitudes to generalized forces at S.

    Returns
    -------
    ndarray, shape (6, n_excitations) [N/N, N m/N, ...]
    """
    excitations = _select(model.excitations, names, "excitation")
    reference = model.reference_point
    columns = []
    for x in excitations:
        if x.kind == "moment":
            columns.append(np.concatenate([np.zeros(3), x.direction]))
        else:
            columns.append(point_force_column(x.position, reference, x.direction))
    return np.array(columns).reshape(-1, 6).T


def _select(items, names, what: str):
    if names is None:
        return list(items)
    from .errors import InputError

    by_name = {item.name: item for item in items}
    if isinstance(names, str):
        names = [names]
    missing = [n for n in names if n not in by_name]
    if missing:
        known = ", ".join(by_name) or "none defined"
        raise InputError(f"unknown {what} {', '.join(map(repr, missing))}: the model's {what}s are {known}")
    return [by_name[n] for n in names]
