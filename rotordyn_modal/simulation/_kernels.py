"""Right-hand side of the large-rotation equations of a multi-rotor machine.

Written in the subset of numpy that numba compiles, so that the same functions run as
plain Python (the reference path) and, rebound by :func:`compiled_namespace`, as numba
machine code. Derivation: ``docs/theory-large-rotations.md``, section 4.

Generalized coordinates (``n = 6 + s`` of them, ``s = 1`` with a stator, 0 without)::

    q = [x (3), g (2), psi (s), phi]

``x`` displacement of the reference point S [m] (ground axes = model axes at rest);
``gamma = E2 g`` the stator's transverse Euler vector [rad] (``E2``: basis normal to ``e``);
``psi`` the stator's axial (roll) angle [rad]; ``phi`` the reference rotor's angle relative
to the stator [rad] (rotor j turns by ``r_j phi``). The stator's rotation is
``R_s = L(gamma) L(psi e)``; the generalized speeds are ``dq/dt``. Kane's equations give
``M(q) d2q/dt2 = f(t, q, dq/dt)``; with a prescribed drive (constant speed or ramp) the last
row gives the drive torque instead.
"""

from __future__ import annotations

import types

import numpy as np

from .. import kinematics
from ..kinematics import axial_rotation, rotation_tensor, skew, zhilin_derivative, zhilin_tensor

FREE, PRESCRIBED = 0, 1


def cross(a, b):
    """``a x b`` for 3-vectors (faster than np.cross under numba)."""
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


def drive_acceleration(t, accel, t_start, t_stop):
    """Prescribed angular acceleration of the reference rotor [rad/s^2] at time ``t`` [s]."""
    if t_start <= t <= t_stop:
        return accel
    return 0.0


def stator_kinematics(q, dq, e, E2, s):
    """Rotation, angular velocity and its velocity-dependent rate of the stator.

    Returns
    -------
    Rs : (3, 3) rotation; eg : (3,) spin axis in ground axes; H : (3, 2 + s) with
    ``omega_s = H eta``; omega_s : (3,) [rad/s]; wdot0 : (3,) ``d omega_s/dt`` at zero
    second derivatives [rad/s^2]; gamma : (3,) transverse Euler vector [rad].
    """
    gamma = E2 @ q[3:5]
    gamma_dot = E2 @ dq[3:5]
    psi = q[5] if s == 1 else 0.0
    psi_dot = dq[5] if s == 1 else 0.0
    Lg = rotation_tensor(gamma)
    Bg = zhilin_tensor(gamma)
    Rs = Lg @ axial_rotation(psi, e)
    eg = Lg @ e
    H = np.zeros((3, 2 + s))
    H[:, :2] = Bg @ E2
    if s == 1:
        H[:, 2] = eg
    omega_gamma = Bg @ gamma_dot
    omega = omega_gamma + psi_dot * eg
    wdot0 = zhilin_derivative(gamma, gamma_dot) @ gamma_dot + psi_dot * cross(omega_gamma, eg)
    return Rs, eg, H, omega, wdot0, gamma


def assemble(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC):
    """Generalized mass matrix ``M`` (n, n) and force ``f`` (n,) at state ``y`` (2n,).

    Parameters
    ----------
    mass : (nb,) [kg]; center : (nb, 3) axis point of each body from S, model axes [m];
    offset : (nb, 3) its centre of mass from the axis point at angle 0 [m];
    inertia : (nb, 3, 3) about the centre of mass at angle 0 [kg m^2]; ratio : (nb,) speed
    ratio (0 for the stator); spos : (ns, 3) suspension points from S [m];
    sK, sC : (ns, 6, 6) stiffness and damping on ``[u_P, theta]``, model axes.
    """
    n = 6 + s
    q, dq = y[:n], y[n:]
    x = q[0:3]
    phi, phi_dot = q[n - 1], dq[n - 1]
    Rs, eg, H, omega, wdot0, gamma = stator_kinematics(q, dq, e, E2, s)
    m_rot = 2 + s
    M = np.zeros((n, n))
    f = np.zeros(n)
    P = np.zeros((3, n))
    W = np.zeros((3, n))
    for b in range(mass.shape[0]):
        r = ratio[b]
        Rb = Rs @ axial_rotation(r * phi, e)
        w = Rb @ offset[b]
        arm = Rs @ center[b]
        d = arm + w
        body_omega = omega + r * phi_dot * eg
        alpha0 = wdot0 + r * phi_dot * cross(omega, eg)
        a0 = (cross(wdot0, arm) + cross(omega, cross(omega, arm))
              + cross(alpha0, w) + cross(body_omega, cross(body_omega, w)))
        P[:, :] = 0.0
        W[:, :] = 0.0
        P[0, 0] = P[1, 1] = P[2, 2] = 1.0
        P[:, 3:3 + m_rot] = -skew(d) @ H
        P[:, n - 1] = r * cross(eg, w)
        W[:, 3:3 + m_rot] = H
        W[:, n - 1] = r * eg
        Ib = Rb @ inertia[b] @ Rb.T
        momentum = Ib @ body_omega
        M += mass[b] * (P.T @ P) + W.T @ (Ib @ W)
        f += P.T @ (mass[b] * (gravity - a0)) - W.T @ (Ib @ alpha0 + cross(body_omega, momentum))
    theta = gamma.copy()
    if s == 1:
        theta += q[5] * e
    Z = np.zeros((6, n))
    z = np.empty(6)
    for i in range(spos.shape[0]):
        rp = Rs @ spos[i]
        Z[:, :] = 0.0
        Z[0, 0] = Z[1, 1] = Z[2, 2] = 1.0
        Z[:3, 3:3 + m_rot] = -skew(rp) @ H
        Z[3:, 3:5] = E2
        if s == 1:
            Z[3:, 5] = e
        z[:3] = x + rp - spos[i]
        z[3:] = theta
        f -= Z.T @ (sK[i] @ z + sC[i] @ (Z @ dq))
    return M, f


def accelerations(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC,
                  mode, accel, t_start, t_stop):
    """Second derivatives ``d2q/dt2`` (n,) and the drive torque [N m] at ``(t, y)``."""
    n = 6 + s
    M, f = assemble(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC)
    if mode == FREE:
        return np.linalg.solve(M, f), 0.0
    alpha = drive_acceleration(t, accel, t_start, t_stop)
    k = n - 1
    qdd = np.empty(n)
    qdd[:k] = np.linalg.solve(M[:k, :k], f[:k] - M[:k, k] * alpha)
    qdd[k] = alpha
    torque = M[k, :k] @ qdd[:k] + M[k, k] * alpha - f[k]
    return qdd, torque


def rhs(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC,
        mode, accel, t_start, t_stop):
    """``dy/dt`` (2n,) of the first-order system ``y = [q, dq/dt]``."""
    n = 6 + s
    qdd, _ = accelerations(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio,
                           spos, sK, sC, mode, accel, t_start, t_stop)
    out = np.empty(2 * n)
    out[:n] = y[n:]
    out[n:] = qdd
    return out


def potential(y, e, E2, s, gravity, mass, center, offset, ratio, spos, sK):
    """Elastic (symmetric part of the stiffness) and gravitational potential energy [J]."""
    n = 6 + s
    q = y[:n]
    gamma = E2 @ q[3:5]
    psi = q[5] if s == 1 else 0.0
    Rs = rotation_tensor(gamma) @ axial_rotation(psi, e)
    theta = gamma + psi * e
    elastic = 0.0
    z = np.empty(6)
    for i in range(spos.shape[0]):
        z[:3] = q[0:3] + Rs @ spos[i] - spos[i]
        z[3:] = theta
        elastic += 0.5 * z @ (sK[i] @ z)
    weight = 0.0
    for b in range(mass.shape[0]):
        d = q[0:3] + Rs @ (center[b] + axial_rotation(ratio[b] * q[n - 1], e) @ offset[b])
        weight -= mass[b] * (gravity @ d)
    return elastic, weight


_KINEMATICS = ("skew", "_coefficients", "_inverse_coefficient", "rotation_tensor", "zhilin_tensor",
               "zhilin_inverse", "zhilin_derivative", "axial_rotation")
_KERNELS = ("cross", "drive_acceleration", "stator_kinematics", "assemble", "accelerations", "rhs",
            "potential", "sample_outputs")


def sample_outputs(times, states, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC,
                   mode, accel, t_start, t_stop):
    """Per-sample derived outputs, in one loop (compiled, it runs without Python overhead).

    Returns
    -------
    kinetic, elastic, weight, torque : ndarray, shape (count,) [J, J, J, N m]
    omega : ndarray, shape (count, 3) [rad/s]
    """
    count = times.shape[0]
    n = 6 + s
    kinetic, elastic, weight = np.empty(count), np.empty(count), np.empty(count)
    torque, omega = np.empty(count), np.empty((count, 3))
    for i in range(count):
        y = states[i]
        q, dq = y[:n], y[n:]
        M, _ = assemble(times[i], y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC)
        kinetic[i] = 0.5 * dq @ (M @ dq)
        elastic[i], weight[i] = potential(y, e, E2, s, gravity, mass, center, offset, ratio, spos, sK)
        torque[i] = accelerations(times[i], y, e, E2, s, gravity, mass, center, offset, inertia, ratio,
                                  spos, sK, sC, mode, accel, t_start, t_stop)[1]
        omega[i] = stator_kinematics(q, dq, e, E2, s)[3]
    return kinetic, elastic, weight, torque, omega


def compiled_namespace():
    """The kernels compiled by numba (``None`` when numba is not installed).

    Each function is rebound to a namespace whose globals are the compiled versions of the
    others, so numba can call them from machine code.
    """
    try:
        import numba
    except ImportError:
        return None
    namespace = {"__name__": __name__, "np": np, "FREE": FREE, "PRESCRIBED": PRESCRIBED, "SERIES_ANGLE": kinematics.SERIES_ANGLE}
    sources = [(kinematics, name) for name in _KINEMATICS] + [(None, name) for name in _KERNELS]
    for module, name in sources:
        function = getattr(module, name) if module is not None else globals()[name]
        rebound = types.FunctionType(function.__code__, namespace, name, function.__defaults__)
        namespace[name] = numba.njit(cache=True, fastmath=False)(rebound)
    compiled = types.SimpleNamespace(**{name: namespace[name] for name in _KERNELS})
    compiled.rhs, compiled.rhs_flat = _compiled_fast_rhs(numba)
    return compiled


def _compiled_fast_rhs(numba):
    """The allocation-light right-hand side of ``_fast``, compiled."""
    from . import _fast

    namespace = {"__name__": _fast.__name__, "np": np, "SERIES": _fast.SERIES}
    for name in _fast.FUNCTIONS:
        function = getattr(_fast, name)
        rebound = types.FunctionType(function.__code__, namespace, name, function.__defaults__)
        namespace[name] = numba.njit(cache=True)(rebound)
    return namespace["rhs"], namespace["rhs_flat"]


def plain_namespace():
    """The kernels as plain Python (numpy) functions."""
    return types.SimpleNamespace(**{name: globals()[name] for name in _KERNELS})
