"""The transformation matrix for the experimental analysis (docs/theory.md): the stator's six
rigid-body motions from a set of accelerometer channels.

A channel at point ``P_c`` along the unit direction ``d_c`` reads
``a_c = [d_c, (P_c - S) x d_c] . q`` (the row of the shift matrix ``B_SP^T``
projected on ``d_c``), with ``q = [u, theta]`` the stator's motion at the point
``S``. Stacking the channels gives ``a = T q`` with ``T`` of shape (n_channels, 6);
``q`` is its least-squares solution, which exists only when ``T`` has rank 6:
at least six channels, not all through one point, not all parallel, ...
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.geometry import point_motion_row, shift_matrix

__all__ = ["transformation_matrix", "RigidBodyMotion", "stator_motion", "shift_motion", "measured_modal_result"]

_DOF = ("u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z")
#: singular values below this fraction of the largest count as missing
_RANK_TOLERANCE = 1e-8


def transformation_matrix(positions, directions, point) -> np.ndarray:
    """``T`` with ``a = T q``: channel readings from the rigid motion ``q`` at ``point``.

    Parameters
    ----------
    positions, directions : array_like, shape (n_channels, 3)
        Channel points [m] and directions (normalised here), model axes.
    point : array_like, shape (3,) [m]

    Returns
    -------
    ndarray, shape (n_channels, 6)
    """
    d = np.asarray(directions, dtype=float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    return np.array([point_motion_row(p, point, di) for p, di in zip(np.asarray(positions, float), d)])


@dataclass(frozen=True)
class RigidBodyMotion:
    """The stator's rigid-body motion estimated from channels.

    Attributes
    ----------
    q : ndarray, shape (6, ...)
        ``[u_x, u_y, u_z, theta_x, theta_y, theta_z]`` at ``point`` (same units as the
        channels: m, m/s, m/s^2 for u; rad, rad/s, rad/s^2 for theta), trailing axes as the data.
    point : ndarray, shape (3,) [m]
    residual : ndarray, shape (n_channels, ...)
        Readings minus the rigid-body fit (non-rigid motion, noise).
    condition : float
        Condition number of the transformation matrix.
    """

    q: np.ndarray
    point: np.ndarray
    residual: np.ndarray
    condition: float

    def to_dataframe(self):
        """``dof`` and the motion (first trailing index flattened to columns)."""
        import pandas as pd

        flat = self.q.reshape(6, -1)
        return pd.DataFrame(flat.T, columns=list(_DOF))

    def plot(self, x=None):
        """The six motions against ``x`` (e.g. time or frequency)."""
        from ..plotting.correlation import plot_rigid_body

        return plot_rigid_body(self, x)


def stator_motion(model, readings, sensors=None, point=None) -> RigidBodyMotion:
    """Least-squares rigid-body motion of the stator from sensor readings.

    Parameters
    ----------
    model : Model
        Gives the sensors' positions and directions.
    readings : array_like, shape (n_sensors, ...)
        One row per sensor (time samples, or complex spectra along the trailing axes).
    sensors : list of str, optional
        Sensor names of the rows (default all, in model order).
    point : array_like, shape (3,), optional
        Where to express the motion [m] (default the model's reference point).

    Returns
    -------
    RigidBodyMotion

    Raises
    ------
    InputError
        When the channels do not determine all six motions (rank < 6), naming the
        undetermined combination.
    """
    from ..assembly import _select

    chosen = _select(model.sensors, sensors, "sensor")
    data = np.asarray(readings)
    if data.shape[0] != len(chosen):
        raise InputError(f"readings: {data.shape[0]} rows for {len(chosen)} sensors ({', '.join(s.name for s in chosen)})")
    point = np.asarray(model.reference_point if point is None else point, dtype=float)
    T = transformation_matrix([s.position for s in chosen], [s.direction for s in chosen], point)
    _check_rank(T, [s.name for s in chosen])
    flat = data.reshape(len(chosen), -1)
    q, *_ = np.linalg.lstsq(T, flat, rcond=None)
    singular = np.linalg.svd(T, compute_uv=False)
    return RigidBodyMotion(q=q.reshape((6,) + data.shape[1:]), point=point,
                           residual=(flat - T @ q).reshape(data.shape), condition=float(singular[0] / singular[-1]))


def _check_rank(T, names):
    if T.shape[0] < 6:
        raise InputError(f"{T.shape[0]} channel(s) ({', '.join(names)}) cannot determine the stator's six "
                         "rigid-body motions: at least six are needed")
    _, singular, vt = np.linalg.svd(T)
    missing = singular < _RANK_TOLERANCE * singular[0]
    if missing.any():
        null = vt[np.nonzero(missing)[0][0]]
        combo = " + ".join(f"{v:.2f} {n}" for v, n in zip(null, _DOF) if abs(v) > 1e-3)
        raise InputError(f"the channels {', '.join(names)} do not determine all six rigid-body motions "
                         f"(rank {int((~missing).sum())} of 6): the motion {combo} is not seen by any of them; "
                         "add channels at other points or along other directions")


def shift_motion(q, from_point, to_point):
    """Rigid motion at ``to_point`` from the motion at ``from_point``: ``B_{from,to}^T q``."""
    return np.einsum("ij,i...->j...", shift_matrix(from_point, to_point), q)


def measured_modal_result(model, modes, excitation=None, speed=None):
    """Identified modes as a :class:`~rotordyn_modal.analysis.modal.ModalResult` of the stator's
    rigid-body motion, so that they are tabled, paired and drawn (in 3D) like the model's.

    Each mode's shape is the least-squares rigid-body motion (:func:`stator_motion`) of its
    modal constants at the sensors for one excitation, scaled to its largest component real.

    Parameters
    ----------
    model : Model
        Gives the sensors (at least six channels that see every rigid-body motion).
    modes : MeasuredModes
    excitation : str, optional
        The input whose modal constants are the shapes (default: for each mode the input
        with the largest modal constants, the one that excites it best).
    speed : float, optional
        Reference rotor speed [rad/s] (default 0).

    Returns
    -------
    ModalResult
        ``shapes`` of shape (n_modes, n) over the model's coordinates: the stator's six from the
        fit, the rotors on bearings' relative coordinates zero (stator sensors do not see them).
    """
    from . import _whirl
    from .modal import ModalResult, modal_quantities

    if excitation is None:        # per mode, the input that excites it most
        columns = np.argmax(np.linalg.norm(modes.shapes, axis=1), axis=1)
    else:
        columns = np.full(len(modes.poles), list(modes.inputs).index(excitation))
    constants = modes.shapes[np.arange(len(columns)), :, columns]                               # (n_modes, n_outputs)
    q = stator_motion(model, constants.T, sensors=list(modes.outputs)).q.T                     # (n_modes, 6)
    biggest = q[np.arange(len(q)), np.argmax(np.abs(q), axis=1)] if len(q) else np.zeros(0)
    q = q * np.where(biggest != 0, np.abs(biggest) / np.where(biggest != 0, biggest, 1), 1.0)[:, None]
    speed = 0.0 if speed is None else float(speed)
    layout = model.dofs
    q = q @ layout.frame_motion()                                   # (n_modes, n): rotors' own motion unseen
    ratios = _whirl.whirl_ratios(q[None], _whirl.whirl_forms(model), np.array([speed]))[0]
    freq, zeta, log_dec = modal_quantities(modes.poles)
    return ModalResult(speed=speed, eigenvalues=np.asarray(modes.poles), frequencies_hz=freq, damping_ratios=zeta,
                       log_decrements=log_dec, whirl_ratios=ratios, whirl=_whirl.whirl_labels(ratios), shapes=q,
                       reference_point=np.asarray(model.reference_point, float),
                       oscillatory=np.ones(len(q), dtype=bool), dof_names=layout.names,
                       rotor_names=tuple(r.name for r in model.rotors),
                       body_motions=np.array([layout.frame_motion()]
                                             + [layout.body_motion(r.name) for r in model.rotors]))
