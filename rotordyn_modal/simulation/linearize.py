"""Linearisation of the nonlinear equations about steady spin, in the core's coordinates."""

from __future__ import annotations

import numpy as np

from . import _kernels
from ._system import system_arrays
from .simulate import kernels

__all__ = ["linearize", "coordinate_map"]


def coordinate_map(system) -> np.ndarray:
    """``T`` (6, 6+s-1) with ``[u, theta] = T [x, g, (psi)]`` (the small-motion map at rest)."""
    m = 5 + system.s
    T = np.zeros((6, m))
    T[:3, :3] = np.eye(3)
    T[3:, 3:5] = system.E2
    if system.s:
        T[3:, 5] = system.e
    return T


def linearize(model, speed, step=1e-7, backend="auto") -> np.ndarray:
    """State matrix of the simulator's equations linearised about steady spin at ``speed``.

    Central finite differences of the right-hand side (ideal drive holding the rotors'
    speed relative to the stator, no gravity, no unbalance) about the undeformed position,
    mapped to the core's states ``[q, dq/dt]``, ``q = [u, theta]`` at the reference point.
    It should equal ``rotordyn_modal.linear_system.speed_linear_form(model).at(speed)``.

    Parameters
    ----------
    model : Model
        A model with a stator (without one the stator's roll is not a coordinate).
    speed : float
        Reference rotor's speed [rad/s].
    step : float
        Finite-difference step [m, rad, m/s, rad/s].

    Returns
    -------
    ndarray, shape (12, 12)
    """
    from ..errors import InputError

    data = model.to_dict()
    data["unbalances"], data["gravity"] = [], [0.0, 0.0, 0.0]
    system = system_arrays(type(model).from_dict(data, model.source))
    if not system.s:
        raise InputError("linearize: the model has no [stator]; its roll about the spin axis is not a "
                         "coordinate of the simulation, so there is no 12-state matrix to compare")
    kn = kernels(backend)
    n = system.n_dof
    m = n - 1
    arguments = system.kernel_arguments() + (_kernels.PRESCRIBED, 0.0, 0.0, 1.0)

    def derivative(z):
        y = np.zeros(2 * n)
        y[:m], y[n:n + m] = z[:m], z[m:]
        y[2 * n - 1] = speed
        out = kn.rhs(0.0, y, *arguments)
        return np.concatenate([out[:m], out[n:n + m]])

    jacobian = np.empty((2 * m, 2 * m))
    for i in range(2 * m):
        dz = np.zeros(2 * m)
        dz[i] = step
        jacobian[:, i] = (derivative(dz) - derivative(-dz)) / (2 * step)
    T = np.kron(np.eye(2), coordinate_map(system))
    return T @ jacobian @ T.T
