"""Right-hand side of the large-rotation equations of a multi-rotor machine.

Written in the subset of numpy that numba compiles, so that the same functions run as
plain Python (the reference path) and, rebound by :func:`compiled_namespace`, as numba
machine code. Derivation: ``docs/theory-large-rotations.md``, sections 4 and 5.

Generalized coordinates (``n = nf + sum k_j + 1``)::

    q = [x (3), g (2), psi (1)]  [u_j (2 or 3), g_j (2)] for each rotor on bearings  [phi]
         \\_______ frame, nf = 6, 5 or 0 _______/

``x`` displacement of the reference point S [m] (ground axes = model axes at rest);
``gamma = E2 g`` the frame's transverse Euler vector [rad] (``E2``: basis normal to ``e``);
``psi`` the stator's axial (roll) angle [rad] (``nf = 6``; a massless carrier without a
stator has ``nf = 5``, no roll; the ground ``nf = 0``). The frame's rotation is
``R_s = L(gamma) L(psi e)``. A rotor on bearings has its own translation
``u_j = A_t u`` of its axis point and transverse Euler vector ``gamma_j = A_2 g_j`` relative
to the frame, in frame axes (``A3 = [a, b, e]``); its rotation is
``R_j = R_s L(gamma_j) L(r_j phi e)``. ``phi`` is the reference rotor's angle relative to the
frame (rotor j turns by ``r_j phi``). The generalized speeds are ``dq/dt``. Kane's equations
give ``M(q) d2q/dt2 = f(t, q, dq/dt)``; with a prescribed drive (constant speed or ramp) the
last row gives the drive torque instead.
"""

from __future__ import annotations

import types

import numpy as np

from . import kinematics
from ._jit import compile_together, numba_or_none
from .kinematics import axial_rotation, rotation_tensor, skew, zhilin_derivative, zhilin_tensor

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


def frame_kinematics(q, dq, e, E2, nf):
    """Rotation, angular velocity and its velocity-dependent rate of the frame.

    Returns
    -------
    Rs : (3, 3) rotation; eg : (3,) spin axis in ground axes; H : (3, m) with
    ``omega_s = H eta`` (``m = nf - 3`` rotational coordinates, 0 on the ground);
    omega_s : (3,) [rad/s]; wdot0 : (3,) ``d omega_s/dt`` at zero second derivatives
    [rad/s^2]; gamma : (3,) transverse Euler vector [rad].
    """
    m_rot = nf - 3 if nf > 0 else 0
    if nf == 0:
        return np.eye(3), e.copy(), np.zeros((3, 0)), np.zeros(3), np.zeros(3), np.zeros(3)
    gamma = E2 @ q[3:5]
    gamma_dot = E2 @ dq[3:5]
    psi = q[5] if m_rot == 3 else 0.0
    psi_dot = dq[5] if m_rot == 3 else 0.0
    Lg = rotation_tensor(gamma)
    Bg = zhilin_tensor(gamma)
    Rs = Lg @ axial_rotation(psi, e)
    eg = Lg @ e
    H = np.zeros((3, m_rot))
    H[:, :2] = Bg @ E2
    if m_rot == 3:
        H[:, 2] = eg
    omega_gamma = Bg @ gamma_dot
    omega = omega_gamma + psi_dot * eg
    wdot0 = zhilin_derivative(gamma, gamma_dot) @ gamma_dot + psi_dot * cross(omega_gamma, eg)
    return Rs, eg, H, omega, wdot0, gamma


def relative_motion(q, dq, j, kt, A3):
    """A rotor's translation ``u`` and transverse Euler vector ``gamma_j`` relative to the
    frame, and their rates, frame axes (zeros for a rotor fixed to the frame, ``j < 0``).

    Returns
    -------
    u, u_dot, gamma_j, gamma_j_dot : ndarray, shape (3,) each [m, m/s, rad, rad/s]
    """
    if j < 0:
        return np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3)
    At = A3[:, :kt].copy()
    A2 = A3[:, :2].copy()
    return (At @ q[j:j + kt], At @ dq[j:j + kt], A2 @ q[j + kt:j + kt + 2], A2 @ dq[j + kt:j + kt + 2])


def body_kinematics(q, dq, e, A3, nf, Rs, eg, H, omega, wdot0, r, j, kt, center, offset):
    """Partial velocities and velocity-dependent accelerations of a body.

    Parameters
    ----------
    r : float
        The body's speed ratio (0 for the stator).
    j, kt : int
        First coordinate of the body's own motion (-1: fixed to the frame) and its number
        of translations.
    center, offset : ndarray, shape (3,)
        Axis point from S (frame axes) and the point followed from the axis point (body
        axes at angle 0) [m].

    Returns
    -------
    P, W : ndarray, shape (3, n)
        ``V = P dq/dt`` (velocity of the point), ``Omega = W dq/dt`` (the body's angular velocity).
    a0, alpha0 : ndarray, shape (3,)
        Their rates at zero second derivatives [m/s^2, rad/s^2].
    Rb : ndarray, shape (3, 3)
        The body's rotation.
    body_omega : ndarray, shape (3,) [rad/s]
    """
    n = q.shape[0]
    phi, phi_dot = q[n - 1], dq[n - 1]
    m_rot = nf - 3 if nf > 0 else 0
    if j >= 0:   # on bearings: its own translation and tilt in the frame
        u, u_dot, gj, gj_dot = relative_motion(q, dq, j, kt, A3)
        Lj = rotation_tensor(gj)
        Bj = zhilin_tensor(gj)
        Hj = Rs @ Bj @ A3[:, :2].copy()
        omega_rel = Rs @ (Bj @ gj_dot)
        tilt_rate = Rs @ (zhilin_derivative(gj, gj_dot) @ gj_dot)
        ej = Rs @ (Lj @ e)
        v_rel = Rs @ u_dot
        Rt = Rs @ Lj
    else:        # fixed in the frame
        u, omega_rel, tilt_rate, v_rel = np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3)
        Hj = np.zeros((3, 2))
        ej = eg.copy()
        Rt = Rs.copy()
    Rb = Rt @ axial_rotation(r * phi, e)
    w = Rb @ offset
    arm = Rs @ (center + u)
    d = arm + w
    frame_and_tilt = omega + omega_rel
    body_omega = frame_and_tilt + r * phi_dot * ej
    alpha0 = wdot0 + cross(omega, omega_rel) + tilt_rate + r * phi_dot * cross(frame_and_tilt, ej)
    a0 = (cross(wdot0, arm) + cross(omega, cross(omega, arm)) + 2.0 * cross(omega, v_rel)
          + cross(alpha0, w) + cross(body_omega, cross(body_omega, w)))
    P = np.zeros((3, n))
    W = np.zeros((3, n))
    if nf > 0:
        P[0, 0] = P[1, 1] = P[2, 2] = 1.0
        P[:, 3:3 + m_rot] = -skew(d) @ H
        W[:, 3:3 + m_rot] = H
    if j >= 0:
        P[:, j:j + kt] = Rs @ A3[:, :kt].copy()
        P[:, j + kt:j + kt + 2] = -skew(w) @ Hj
        W[:, j + kt:j + kt + 2] = Hj
    P[:, n - 1] = r * cross(ej, w)
    W[:, n - 1] = r * ej
    return P, W, a0, alpha0, Rb, body_omega


def bearing_coefficients(speeds, count, K, C, own):
    """A bearing's 6x6 stiffness and damping at the rotor's own speed ``own`` [rad/s]:
    linear in the table's speeds, held at its ends (constant coefficients: ``count = 1``)."""
    if count == 1 or own <= speeds[0]:
        return K[0], C[0]
    last = count - 1
    if own >= speeds[last]:
        return K[last], C[last]
    k = 1
    while speeds[k] < own:
        k += 1
    t = (own - speeds[k - 1]) / (speeds[k] - speeds[k - 1])
    return (1.0 - t) * K[k - 1] + t * K[k], (1.0 - t) * C[k - 1] + t * C[k]


def sommerfeld_angle(theta, eps):
    """Sommerfeld's substitution ``psi(theta)``, ``tan(psi/2) = sqrt((1-eps)/(1+eps)) tan(theta/2)``,
    continued continuously over every turn (``psi = theta`` at multiples of pi)."""
    turns = np.floor((theta + np.pi) / (2.0 * np.pi))
    t = theta - 2.0 * np.pi * turns
    return 2.0 * np.arctan2(np.sqrt(1.0 - eps) * np.sin(0.5 * t), np.sqrt(1.0 + eps) * np.cos(0.5 * t)) \
        + 2.0 * np.pi * turns


def film_force(d, d_dot, own, axes, film):
    """Force of a plain short journal bearing's oil film on the journal (``docs/theory.md``
    §12, pi-film over the arc where the pressure is positive), frame axes [N].

    Parameters
    ----------
    d, d_dot : ndarray, shape (3,)
        Journal centre from the bearing centre and its velocity, frame axes [m, m/s].
    own : float
        Journal speed relative to the bearing, signed about the spin axis [rad/s].
    axes : ndarray, shape (2, 3)
        Rows ``x``, ``y`` of the bearing's radial frame (``x × y = e``).
    film : ndarray, shape (4,)
        Radius, length, radial clearance [m], viscosity [Pa s].

    Returns
    -------
    ndarray, shape (3,); NaN once the journal reaches the wall (eccentricity >= 1).

    Notes
    -----
    In the line of centres (``u_r`` from the bearing centre to the journal's, ``u_t = e × u_r``,
    ``theta`` from the widest gap) the integrated pressure is
    ``mu L³ (a sin(theta) - b cos(theta)) / (2 c² (1 + eps cos(theta))³)`` with
    ``a = eps (omega - 2 beta')``, ``b = 2 eps'``; it is positive on ``(theta0, theta0 + pi)``,
    ``theta0 = atan2(b, a)``. Sommerfeld's substitution turns the force integrals over that arc
    into trigonometric polynomials: ``(1 - eps²)^(3/2) I_ss = [psi/2 - sin(2 psi)/4]``,
    ``(1 - eps²)² I_sc = [sin²(psi)/2 + eps cos(psi)]``,
    ``(1 - eps²)^(5/2) I_cc = [(1/2 + eps²) psi + sin(2 psi)/4 - 2 eps sin(psi)]``, and
    ``F_r = k (a I_sc - b I_cc)``, ``F_t = k (a I_ss - b I_sc)``, ``k = mu R L³ / (2 c²)``.
    """
    radius, length, clearance, viscosity = film[0], film[1], film[2], film[3]
    x, y = axes[0], axes[1]
    X, Y = (d @ x) / clearance, (d @ y) / clearance
    Xd, Yd = (d_dot @ x) / clearance, (d_dot @ y) / clearance
    eps = np.sqrt(X * X + Y * Y)
    if eps >= 1.0:
        return np.full(3, np.nan)
    ur_x, ur_y = (X / eps, Y / eps) if eps > 0.0 else (1.0, 0.0)
    ut_x, ut_y = -ur_y, ur_x
    a = eps * own - 2.0 * (Xd * ut_x + Yd * ut_y)
    b = 2.0 * (Xd * ur_x + Yd * ur_y)
    if a == 0.0 and b == 0.0:
        return np.zeros(3)
    theta0 = np.arctan2(b, a)
    p0, p1 = sommerfeld_angle(theta0, eps), sommerfeld_angle(theta0 + np.pi, eps)
    room = 1.0 - eps * eps
    i_ss = ((p1 - p0) / 2.0 - (np.sin(2.0 * p1) - np.sin(2.0 * p0)) / 4.0) / room**1.5
    i_sc = ((np.sin(p1) ** 2 - np.sin(p0) ** 2) / 2.0 + eps * (np.cos(p1) - np.cos(p0))) / room**2
    i_cc = ((0.5 + eps * eps) * (p1 - p0) + (np.sin(2.0 * p1) - np.sin(2.0 * p0)) / 4.0
            - 2.0 * eps * (np.sin(p1) - np.sin(p0))) / room**2.5
    k = viscosity * radius * length**3 / (2.0 * clearance**2)
    radial = k * (a * i_sc - b * i_cc)
    tangential = k * (a * i_ss - b * i_sc)
    return (radial * ur_x + tangential * ut_x) * x + (radial * ur_y + tangential * ut_y) * y


def bearing_stretch(q, dq, j, kt, A3, point):
    """Relative motion ``z = [d, gamma_j]`` of rotor and frame at a bearing point and its
    Jacobian ``Z`` (``dz/dt = Z dq/dt``), frame axes.

    ``d = u + L(gamma_j) b - b`` (``b`` the bearing point from the rotor's axis point).

    Returns
    -------
    z : ndarray, shape (6,) [m, rad]; Z : ndarray, shape (6, n)
    """
    n = q.shape[0]
    u, _, gj, _ = relative_motion(q, dq, j, kt, A3)
    turned = rotation_tensor(gj) @ point
    z = np.empty(6)
    z[:3] = u + turned - point
    z[3:] = gj
    Z = np.zeros((6, n))
    Z[:3, j:j + kt] = A3[:, :kt]
    Z[:3, j + kt:j + kt + 2] = -skew(turned) @ zhilin_tensor(gj) @ A3[:, :2].copy()
    Z[3:, j + kt:j + kt + 2] = A3[:, :2]
    return z, Z


def suspension_stretch(q, e, E2, nf, Rs, H, point):
    """Motion ``z = [u_P, theta]`` of the frame at a suspension point and its Jacobian ``Z``.

    Returns
    -------
    z : ndarray, shape (6,) [m, rad]; Z : ndarray, shape (6, n)
    """
    n = q.shape[0]
    m_rot = nf - 3
    rp = Rs @ point
    Z = np.zeros((6, n))
    Z[0, 0] = Z[1, 1] = Z[2, 2] = 1.0
    Z[:3, 3:3 + m_rot] = -skew(rp) @ H
    Z[3:, 3:5] = E2
    z = np.empty(6)
    z[:3] = q[0:3] + rp - point
    z[3:] = E2 @ q[3:5]
    if m_rot == 3:
        Z[3:, 5] = e
        z[3:] += q[5] * e
    return z, Z


def assemble(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
             spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes):
    """Generalized mass matrix ``M`` (n, n) and force ``f`` (n,) at state ``y`` (2n,).

    Parameters
    ----------
    See :class:`rotordyn_modal.simulation._system.SystemArrays` (same names).
    """
    n = y.shape[0] // 2
    q, dq = y[:n], y[n:]
    Rs, eg, H, omega, wdot0, _ = frame_kinematics(q, dq, e, E2, nf)
    M = np.zeros((n, n))
    f = np.zeros(n)
    for b in range(mass.shape[0]):
        P, W, a0, alpha0, Rb, body_omega = body_kinematics(
            q, dq, e, A3, nf, Rs, eg, H, omega, wdot0, ratio[b], slot[b], ntrans[b], center[b], offset[b])
        Ib = Rb @ inertia[b] @ Rb.T
        momentum = Ib @ body_omega
        M += mass[b] * (P.T @ P) + W.T @ (Ib @ W)
        f += P.T @ (mass[b] * (gravity - a0)) - W.T @ (Ib @ alpha0 + cross(body_omega, momentum))
    if nf > 0:
        for i in range(spos.shape[0]):
            z, Z = suspension_stretch(q, e, E2, nf, Rs, H, spos[i])
            f -= Z.T @ (sK[i] @ z + sC[i] @ (Z @ dq))
    for i in range(bbody.shape[0]):
        b = bbody[i]
        z, Z = bearing_stretch(q, dq, slot[b], ntrans[b], A3, bpos[i])
        f -= Z.T @ bearing_wrench(z, Z @ dq, ratio[b] * dq[n - 1], bspeeds[i], bcount[i], bK[i], bC[i], bfilm[i],
                                  baxes[i])
    return M, f


def bearing_wrench(z, z_dot, own, speeds, count, K, C, film, axes):
    """What a bearing passes to the frame at its point, frame axes, shape (6,) [N, N m]: its
    springs and dampers ``K z + C dz/dt`` at the rotor's own speed ``own`` [rad/s], minus the
    oil film's force on the journal (journal bearings, ``film[2] > 0``)."""
    K_now, C_now = bearing_coefficients(speeds, count, K, C, own)
    out = K_now @ z + C_now @ z_dot
    if film[2] > 0.0:
        out[:3] -= film_force(z[:3], z_dot[:3], own, axes, film)
    return out


def accelerations(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                  spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop):
    """Second derivatives ``d2q/dt2`` (n,) and the drive torque [N m] at ``(t, y)``."""
    M, f = assemble(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                    spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes)
    return solve_motion(M, f, t, mode, accel, t_start, t_stop)


def solve_motion(M, f, t, mode, accel, t_start, t_stop):
    """``d2q/dt2`` and the drive torque [N m] from ``M d2q/dt2 = f`` (+ the drive torque in
    the last row): all of it free, or the last coordinate's acceleration prescribed."""
    n = f.shape[0]
    if mode == FREE:
        return np.linalg.solve(M, f), 0.0
    alpha = drive_acceleration(t, accel, t_start, t_stop)
    k = n - 1
    qdd = np.empty(n)
    qdd[:k] = np.linalg.solve(M[:k, :k], f[:k] - M[:k, k] * alpha)
    qdd[k] = alpha
    torque = M[k, :k] @ qdd[:k] + M[k, k] * alpha - f[k]
    return qdd, torque


def rhs(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
        spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop):
    """``dy/dt`` (2n,) of the first-order system ``y = [q, dq/dt]``."""
    n = y.shape[0] // 2
    qdd, _ = accelerations(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans,
                           A3, spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop)
    out = np.empty(2 * n)
    out[:n] = y[n:]
    out[n:] = qdd
    return out


def potential(y, e, E2, nf, gravity, mass, center, offset, ratio, slot, ntrans, A3, spos, sK,
              bbody, bpos, bspeeds, bcount, bK, bC):
    """Elastic (symmetric part of the stiffness) and gravitational potential energy [J].

    A bearing's stiffness is taken at the rotor's current own speed; an oil film stores none.
    """
    n = y.shape[0] // 2
    q, dq = y[:n], y[n:]
    Rs, _, H, _, _, _ = frame_kinematics(q, dq, e, E2, nf)
    elastic = 0.0
    if nf > 0:
        for i in range(spos.shape[0]):
            z, _ = suspension_stretch(q, e, E2, nf, Rs, H, spos[i])
            elastic += 0.5 * z @ (sK[i] @ z)
    for i in range(bbody.shape[0]):
        b = bbody[i]
        z, _ = bearing_stretch(q, dq, slot[b], ntrans[b], A3, bpos[i])
        K, _ = bearing_coefficients(bspeeds[i], bcount[i], bK[i], bC[i], ratio[b] * dq[n - 1])
        elastic += 0.5 * z @ (K @ z)
    weight = 0.0
    origin = q[0:3] if nf > 0 else np.zeros(3)
    for b in range(mass.shape[0]):
        u, _, gj, _ = relative_motion(q, dq, slot[b], ntrans[b], A3)
        spin = rotation_tensor(gj) @ axial_rotation(ratio[b] * q[n - 1], e)
        d = origin + Rs @ (center[b] + u + spin @ offset[b])
        weight -= mass[b] * (gravity @ d)
    return elastic, weight


def bearing_wrenches(y, nf, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes):
    """What every bearing passes to the frame at its point (frame axes), shape (nbr, 6)
    [N, N m]; see :func:`bearing_wrench`."""
    n = y.shape[0] // 2
    q, dq = y[:n], y[n:]
    out = np.empty((bbody.shape[0], 6))
    for i in range(bbody.shape[0]):
        b = bbody[i]
        z, Z = bearing_stretch(q, dq, slot[b], ntrans[b], A3, bpos[i])
        out[i] = bearing_wrench(z, Z @ dq, ratio[b] * dq[n - 1], bspeeds[i], bcount[i], bK[i], bC[i], bfilm[i],
                                baxes[i])
    return out


def sample_outputs(times, states, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans,
                   A3, spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop):
    """Per-sample derived outputs, in one loop (compiled, it runs without Python overhead).

    Returns
    -------
    kinetic, elastic, weight, torque : ndarray, shape (count,) [J, J, J, N m]
    omega : ndarray, shape (count, 3) [rad/s]
    wrenches : ndarray, shape (count, nbr, 6) [N, N m]
    """
    count = times.shape[0]
    n = states.shape[1] // 2
    kinetic, elastic, weight = np.empty(count), np.empty(count), np.empty(count)
    torque, omega = np.empty(count), np.empty((count, 3))
    wrenches = np.empty((count, bbody.shape[0], 6))
    for i in range(count):
        y = states[i]
        q, dq = y[:n], y[n:]
        M, f = assemble(times[i], y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans,
                        A3, spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes)
        kinetic[i] = 0.5 * dq @ (M @ dq)
        elastic[i], weight[i] = potential(y, e, E2, nf, gravity, mass, center, offset, ratio, slot, ntrans, A3,
                                          spos, sK, bbody, bpos, bspeeds, bcount, bK, bC)
        torque[i] = solve_motion(M, f, times[i], mode, accel, t_start, t_stop)[1]
        omega[i] = frame_kinematics(q, dq, e, E2, nf)[3]
        wrenches[i] = bearing_wrenches(y, nf, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC,
                                       bfilm, baxes)
    return kinetic, elastic, weight, torque, omega, wrenches


def point_partials(y, e, E2, nf, A3, r, j, kt, center, point):
    """Partial velocities of a point of a body and of its angular velocity at state ``y``.

    Parameters
    ----------
    r, j, kt, center : as :func:`body_kinematics` (``j = -1``, ``r = 0``: the frame)
    point : ndarray, shape (3,)
        The point from the body's axis point, body axes at angle 0 [m].

    Returns
    -------
    P, W : ndarray, shape (3, n)
    """
    n = y.shape[0] // 2
    q, dq = y[:n], y[n:]
    Rs, eg, H, omega, wdot0, _ = frame_kinematics(q, dq, e, E2, nf)
    P, W, _, _, _, _ = body_kinematics(q, dq, e, A3, nf, Rs, eg, H, omega, wdot0, r, j, kt, center, point)
    return P, W


#: kernels replaced by their allocation-light versions of ``_fast`` when compiled
_FAST = ("assemble", "rhs", "potential", "bearing_wrenches", "sample_outputs")
_KINEMATICS = ("skew", "_coefficients", "_inverse_coefficient", "rotation_tensor", "zhilin_tensor",
               "zhilin_inverse", "zhilin_derivative", "axial_rotation")
_KERNELS = ("cross", "drive_acceleration", "frame_kinematics", "relative_motion", "body_kinematics",
            "bearing_coefficients", "sommerfeld_angle", "film_force", "bearing_stretch", "bearing_wrench",
            "suspension_stretch", "assemble", "solve_motion", "accelerations", "rhs", "potential",
            "bearing_wrenches", "sample_outputs")


def compiled_namespace():
    """The kernels compiled by numba (``None`` when numba is not installed).

    Each function is rebound to a namespace whose globals are the compiled versions of the
    others (:func:`rotordyn_modal.simulation._jit.compile_together`), so numba can call them
    from machine code. The ones ``rdm.simulate`` calls
    (``assemble``, ``rhs``, ``potential``, ``bearing_wrenches``, ``sample_outputs``) are the
    allocation-light versions of :mod:`rotordyn_modal.simulation._fast` (same results to
    round-off, tested), which also compile much faster; the readable ones compile only
    when called.
    """
    from . import _fast

    if numba_or_none() is None:
        return None
    functions = [getattr(kinematics, name) for name in _KINEMATICS] + [globals()[name] for name in _KERNELS]
    namespace = compile_together(functions, {"np": np, "FREE": FREE, "PRESCRIBED": PRESCRIBED,
                                             "SERIES_ANGLE": kinematics.SERIES_ANGLE}, __name__)
    fast = compile_together([getattr(_fast, name) for name in _fast.FUNCTIONS],
                            {"np": np, "SERIES": _fast.SERIES, "ORDERED_FROM": _fast.ORDERED_FROM}, _fast.__name__,
                            inlined=_fast.INLINED, internal=_fast.INTERNAL)
    for name in _FAST:     # looked up by the readable callers when they compile, on first call
        namespace[name] = fast[name]
    compiled = types.SimpleNamespace(**{name: namespace[name] for name in _KERNELS})
    compiled.rhs_flat = fast["rhs_flat"]
    compiled.rhs = _fast.packed(fast["rhs_flat"])     # ``rhs`` is inlined into ``rhs_flat``
    return compiled


def plain_namespace():
    """The kernels as plain Python (numpy) functions."""
    return types.SimpleNamespace(**{name: globals()[name] for name in _KERNELS})
