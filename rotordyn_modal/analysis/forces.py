"""Forces: what each suspension passes to the ground, and what each rotor passes to the stator.

* Suspension ``i`` at point ``P_i`` pushes on the ground with the generalized
  force (``[F, C]`` at ``P_i``, model axes)
  ``T_i = (K_i (1 + i eta_i) + K_b,i(w) + i w C_i) B_SP^T q``:
  the transmitted force, whose ratio to an input force is the transmissibility.
* Rotor ``j`` acts on the stator through its bearings with (seed 000 eq. 73/74,
  written at the rotor's centre of mass ``R_j``, where ``B_Bj,j = I``)
  ``T_Bj = F_U,j - M_j B_SRj^T q'' - Omega G_j B_SRj^T q'``, with ``M_j =
  diag(m_j I, J_j)``, ``G_j = diag(0, -J_p,j r_j skew(e))`` and ``F_U,j`` the
  unbalance force on the rotor moved to ``R_j``. Move it to a bearing at ``P``
  with ``shift_matrix(P, R_j) @ T_Bj``.

Both are linear in the complex amplitude ``q`` of the stator's motion; the
functions here take ``q`` from :func:`rotordyn_modal.analysis.frf.dof_response`.
"""

from __future__ import annotations

import numpy as np

from ..geometry import shift_matrix, skew
from .frf import FRFResult, _check_frequencies, _names, dof_response
from ..assembly import excitation_columns

__all__ = ["suspension_forces", "bearing_forces", "force_frf", "COMPONENTS"]

#: names of the six components of a generalized force
COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def suspension_forces(model, omega, q) -> np.ndarray:
    """Force each suspension passes to the ground.

    Parameters
    ----------
    model : Model
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, 6, n), complex
        Motion of the stator at the reference point [m, rad].

    Returns
    -------
    ndarray, shape (n_suspensions, n_freq, 6, n), complex
        ``[F, C]`` at each suspension's point, model axes [N, N m].
    """
    w = np.asarray(omega, dtype=float)[:, None, None]
    out = []
    for s in model.suspensions:
        shift = shift_matrix(model.reference_point, s.position)
        point_motion = np.einsum("dk,fdn->fkn", shift, q)          # B_SP^T q
        stiffness = s.stiffness_matrix * (1 + 1j * s.loss_factor) + 1j * w * s.damping_matrix
        if getattr(s, "maxwell_stiffness_matrix", None) is not None:
            stiffness = stiffness + _branch_stiffness(s, np.ravel(w))
        out.append(np.einsum("fij,fjn->fin", np.broadcast_to(stiffness, (len(w), 6, 6)), point_motion))
    return np.array(out).reshape(len(model.suspensions), len(w), 6, q.shape[-1])


def _branch_stiffness(suspension, omega):
    factor = 1j * omega[:, None] * np.asarray(suspension.maxwell_time, dtype=float)
    factor = factor / (1 + factor)
    return np.einsum("fb,bij->fij", factor, suspension.maxwell_stiffness_matrix)


def bearing_forces(model, speed, omega, q, rotor_forces=None) -> np.ndarray:
    """Force each rotor passes to the stator through its bearings (seed 000 eq. 73/74).

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,)
        Reference rotor speed [rad/s].
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, 6, n), complex [m, rad]
    rotor_forces : ndarray, shape (n_rotors, n_freq, 6, n), optional
        External forces on each rotor (unbalance), ``[F, C]`` at its centre of mass.

    Returns
    -------
    ndarray, shape (n_rotors, n_freq, 6, n), complex
        ``[F, C]`` at each rotor's centre of mass, model axes [N, N m].
    """
    w = np.asarray(omega, dtype=float)
    speed = np.broadcast_to(np.asarray(speed, dtype=float), w.shape)
    e = model.spin_axis
    out = []
    for j, rotor in enumerate(model.rotors):
        shift = shift_matrix(model.reference_point, rotor.center_of_mass)
        motion = np.einsum("dk,fdn->fkn", shift, q)                 # B_SR^T q at R_j
        local = np.zeros((6, 6))
        local[:3, :3] = rotor.mass * np.eye(3)
        local[3:, 3:] = rotor.diametral_inertia * np.eye(3) + \
            (rotor.polar_inertia - rotor.diametral_inertia) * np.outer(e, e)
        gyro = np.zeros((6, 6))
        gyro[3:, 3:] = -rotor.polar_inertia * rotor.speed_ratio * skew(e)
        inertia = (-w[:, None, None] ** 2 * local + 1j * (w * speed)[:, None, None] * gyro)
        force = -np.einsum("fij,fjn->fin", inertia, motion)
        if rotor_forces is not None:
            force = force + rotor_forces[j]
        out.append(force)
    return np.array(out).reshape(len(model.rotors), len(w), 6, q.shape[-1])


def force_frf(model, speed: float, freqs_hz, inputs=None, where: str = "suspensions") -> FRFResult:
    """Forces per unit excitation: transmissibility to the ground, or bearing forces.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s].
    freqs_hz : array_like, shape (n_freq,) [Hz]
    inputs : str or list of str, optional
        Excitation names (default all).
    where : {'suspensions', 'bearings'}
        Ground force of each suspension, or force of each rotor on the stator.

    Returns
    -------
    FRFResult
        ``quantity='force'``; outputs ``"NAME:Fx" ... "NAME:Mz"`` (6 per suspension
        or rotor) [N/N, N m/N]; H of shape (6 n_items, n_inputs, n_freq).
    """
    from ..errors import InputError

    if where not in ("suspensions", "bearings"):
        raise InputError(f"where {where!r}: expected 'suspensions' or 'bearings'")
    f = _check_frequencies(freqs_hz)
    omega = 2 * np.pi * f
    columns = excitation_columns(model, inputs)
    if columns.shape[1] == 0:
        raise InputError(f"{model.source}: the model has no [[excitations]]: a force FRF needs one")
    q = dof_response(model, speed, omega, columns)
    if where == "suspensions":
        forces, items = suspension_forces(model, omega, q), model.suspensions
    else:
        forces, items = bearing_forces(model, speed, omega, q), model.rotors
    H = np.moveaxis(forces, 1, -1).reshape(len(items) * 6, q.shape[-1], len(f))
    outputs = tuple(f"{item.name}:{c}" for item in items for c in COMPONENTS)
    return FRFResult(H=H, frequencies_hz=f, speed=float(speed), inputs=_names(model.excitations, inputs),
                     outputs=outputs, quantity="force", engine="direct")
