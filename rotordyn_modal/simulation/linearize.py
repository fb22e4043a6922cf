"""Linearisation of the nonlinear equations about steady spin, in the core's coordinates."""

from __future__ import annotations

import numpy as np

from . import _kernels
from ._system import CARRIER, STATOR, check_table_speeds, system_arrays
from .simulate import kernels

__all__ = ["linearize", "coordinate_map"]


def coordinate_map(system) -> np.ndarray:
    """``T`` with ``q_core = T q_sim`` (the small-motion map at rest), all coordinates but ``phi``.

    Orthogonal. The frame's ``[x, g, psi]`` map to ``[u, theta]`` by ``theta = E2 g + psi e``; a rotor's
    ``[u_a, u_b, (u_e), g_a, g_b]`` are the core's coordinates of that rotor already.

    Returns
    -------
    ndarray, shape (n - 1, n - 1)
    """
    m = system.n_dof - 1
    T = np.eye(m)
    if system.nf == STATOR:
        T[3:6, 3:5] = system.E2
        T[3:6, 5] = system.e
    return T


def linearize(model, speed, step=1e-7, backend="auto") -> np.ndarray:
    """State matrix of the simulator's equations linearised about steady spin at ``speed``.

    Central finite differences of the right-hand side (ideal drive holding the rotors'
    speed relative to the stator, no unbalance) about the undeformed position without
    gravity, or, with journal bearings, about the static equilibrium under gravity (which
    loads their oil films), mapped to the core's states ``[q, dq/dt]`` (``model.dofs``: the
    stator's ``[u, theta]`` at the reference point, then each rotor on bearings' motion
    relative to the stator). It should equal
    ``rotordyn_modal.linear_system.speed_linear_form(model).at(speed)`` (with journal
    bearings, to the size of the static sag's geometric effect).

    Parameters
    ----------
    model : Model
        A model with a stator, or with bearings to the ground (without either, the massless
        carrier's roll about the spin axis is not a coordinate of the simulation).
    speed : float
        Reference rotor's speed [rad/s].
    step : float
        Finite-difference step [m, rad, m/s, rad/s].

    Returns
    -------
    ndarray, shape (2 n, 2 n), ``n = model.dofs.n``
    """
    from ..errors import InputError

    journals = any(b.coefficients.kind == "journal" for b in model.bearings)
    data = model.to_dict()
    data["unbalances"] = []
    if not journals:
        data["gravity"] = [0.0, 0.0, 0.0]
    system = system_arrays(type(model).from_dict(data, model.source))
    if system.nf == CARRIER:
        raise InputError("linearize: the model has no [stator]; its roll about the spin axis is not a "
                         "coordinate of the simulation, so there is no 12-state matrix to compare")
    check_table_speeds(model, [speed], "linearize")
    kn = kernels(backend)
    n = system.n_dof
    m = n - 1
    arguments = system.kernel_arguments() + (_kernels.PRESCRIBED, 0.0, 0.0, 1.0)
    rest = np.zeros(m)
    if journals:
        from .simulate import _static_equilibrium

        rest = _static_equilibrium(model, kn, n, speed)

    def derivative(z):
        y = np.zeros(2 * n)
        y[:m], y[n:n + m] = rest + z[:m], z[m:]
        y[2 * n - 1] = speed
        out = kn.rhs(0.0, y, *arguments)
        return np.concatenate([out[:m], out[n:n + m]])

    jacobian = np.empty((2 * m, 2 * m))
    for i in range(2 * m):
        dz = np.zeros(2 * m)
        dz[i] = step
        jacobian[:, i] = (derivative(dz) - derivative(-dz)) / (2 * step)
    T = np.kron(np.eye(2), coordinate_map(system))
    return T @ jacobian @ T.T   # T is orthogonal
