"""Compiled right-hand side: the equations of ``_kernels`` rewritten for speed under numba.

Same arguments and results as :func:`rotordyn_modal.simulation._kernels.rhs` (tested to
agree to round-off), written with scalar loops into a few scratch arrays instead of the
many small temporary arrays of the readable version, and with an in-place Cholesky solve
of the (symmetric positive definite) generalized mass matrix. Only used through numba.
"""

from __future__ import annotations

import numpy as np

SERIES = 0.05


def _mat3(a, b, out):
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]


def _mv3(a, v, out):
    for i in range(3):
        out[i] = a[i, 0] * v[0] + a[i, 1] * v[1] + a[i, 2] * v[2]


def _cross(a, b, out):
    x = a[1] * b[2] - a[2] * b[1]
    y = a[2] * b[0] - a[0] * b[2]
    z = a[0] * b[1] - a[1] * b[0]
    out[0], out[1], out[2] = x, y, z


def _rodrigues(cos_t, c, a, v, out):
    """``cos E + c v v^T + a skew(v)`` into ``out``."""
    for i in range(3):
        for j in range(3):
            out[i, j] = c * v[i] * v[j]
        out[i, i] += cos_t
    out[0, 1] -= a * v[2]
    out[0, 2] += a * v[1]
    out[1, 0] += a * v[2]
    out[1, 2] -= a * v[0]
    out[2, 0] -= a * v[1]
    out[2, 1] += a * v[0]


def _coefficients(t2):
    if t2 < SERIES * SERIES:
        a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0))
        c = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0))
        b = 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0))
        da = -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0
        dc = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0
        db = -1.0 / 60.0 + t2 / 1260.0 - t2 * t2 / 60480.0
        return a, c, b, da, dc, db
    t = np.sqrt(t2)
    s, co = np.sin(t), np.cos(t)
    return (s / t, (1.0 - co) / t2, (t - s) / (t2 * t), (t * co - s) / (t2 * t),
            (t * s - 2.0 * (1.0 - co)) / (t2 * t2), (1.0 - co) / (t2 * t2) - 3.0 * (t - s) / (t2 * t2 * t))


def _solve_spd(M, f, k, out):
    """Solve ``M[:k, :k] x = f[:k]`` by Cholesky (M overwritten)."""
    for j in range(k):
        d = M[j, j]
        for p in range(j):
            d -= M[j, p] * M[j, p]
        d = np.sqrt(d)
        M[j, j] = d
        for i in range(j + 1, k):
            v = M[i, j]
            for p in range(j):
                v -= M[i, p] * M[j, p]
            M[i, j] = v / d
    for i in range(k):
        v = f[i]
        for p in range(i):
            v -= M[i, p] * out[p]
        out[i] = v / M[i, i]
    for i in range(k - 1, -1, -1):
        v = out[i]
        for p in range(i + 1, k):
            v -= M[p, i] * out[p]
        out[i] = v / M[i, i]


def rhs(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC,
        mode, accel, t_start, t_stop):
    """``dy/dt`` (2n,); see :func:`rotordyn_modal.simulation._kernels.rhs`."""
    n = 6 + s
    m_rot = 2 + s
    gamma, gdot = np.empty(3), np.empty(3)
    for i in range(3):
        gamma[i] = E2[i, 0] * y[3] + E2[i, 1] * y[4]
        gdot[i] = E2[i, 0] * y[n + 3] + E2[i, 1] * y[n + 4]
    psi = y[5] if s == 1 else 0.0
    psi_dot = y[n + 5] if s == 1 else 0.0
    phi, phi_dot = y[n - 1], y[2 * n - 1]
    t2 = gamma[0] * gamma[0] + gamma[1] * gamma[1] + gamma[2] * gamma[2]
    a, c, b, da, dc, db = _coefficients(t2)
    Lg, Bg, R1, Rs = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    Rb, Ib, T3 = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    _rodrigues(1.0 - c * t2, c, a, gamma, Lg)
    _rodrigues(a, b, c, gamma, Bg)
    _rodrigues(np.cos(psi), 1.0 - np.cos(psi), np.sin(psi), e, R1)
    _mat3(Lg, R1, Rs)
    eg, og, omega, wdot0 = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    v1, v2, v3 = np.empty(3), np.empty(3), np.empty(3)
    _mv3(Lg, e, eg)
    H = np.empty((3, m_rot))
    for i in range(3):
        for k in range(2):
            H[i, k] = Bg[i, 0] * E2[0, k] + Bg[i, 1] * E2[1, k] + Bg[i, 2] * E2[2, k]
        if s == 1:
            H[i, 2] = eg[i]
    _mv3(Bg, gdot, og)
    for i in range(3):
        omega[i] = og[i] + psi_dot * eg[i]
    # D B(gamma)[gdot] gdot + psi_dot og x eg
    vw = gamma[0] * gdot[0] + gamma[1] * gdot[1] + gamma[2] * gdot[2]
    ww = gdot[0] * gdot[0] + gdot[1] * gdot[1] + gdot[2] * gdot[2]
    _cross(gamma, gdot, v1)
    _cross(og, eg, v2)
    for i in range(3):
        wdot0[i] = (da * vw * gdot[i] + db * vw * vw * gamma[i] + b * (vw * gdot[i] + ww * gamma[i])
                    + dc * vw * v1[i] + psi_dot * v2[i])
    M = np.zeros((n, n))
    f = np.zeros(n)
    P = np.zeros((3, n))
    W = np.zeros((3, n))
    IW = np.empty((3, n))
    w, arm, d, bo = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    al, a0, mom, rhs3 = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for bdy in range(mass.shape[0]):
        r = ratio[bdy]
        ang = r * phi
        _rodrigues(np.cos(ang), 1.0 - np.cos(ang), np.sin(ang), e, R1)
        _mat3(Rs, R1, Rb)
        _mv3(Rb, offset[bdy], w)
        _mv3(Rs, center[bdy], arm)
        for i in range(3):
            d[i] = arm[i] + w[i]
            bo[i] = omega[i] + r * phi_dot * eg[i]
        _cross(omega, eg, v1)
        for i in range(3):
            al[i] = wdot0[i] + r * phi_dot * v1[i]
        # a0 = wdot0 x arm + omega x (omega x arm) + al x w + bo x (bo x w)
        _cross(wdot0, arm, a0)
        _cross(omega, arm, v1)
        _cross(omega, v1, v2)
        _cross(al, w, v3)
        for i in range(3):
            a0[i] += v2[i] + v3[i]
        _cross(bo, w, v1)
        _cross(bo, v1, v2)
        for i in range(3):
            a0[i] += v2[i]
        for i in range(3):
            P[i, i] = 1.0
        for k in range(m_rot):
            # -d x H_k
            P[0, 3 + k] = -(d[1] * H[2, k] - d[2] * H[1, k])
            P[1, 3 + k] = -(d[2] * H[0, k] - d[0] * H[2, k])
            P[2, 3 + k] = -(d[0] * H[1, k] - d[1] * H[0, k])
            for i in range(3):
                W[i, 3 + k] = H[i, k]
        _cross(eg, w, v1)
        for i in range(3):
            P[i, n - 1] = r * v1[i]
            W[i, n - 1] = r * eg[i]
        # Ib = Rb I0 Rb^T
        _mat3(Rb, inertia[bdy], T3)
        for i in range(3):
            for j in range(3):
                Ib[i, j] = T3[i, 0] * Rb[j, 0] + T3[i, 1] * Rb[j, 1] + T3[i, 2] * Rb[j, 2]
        for i in range(3):
            for j in range(n):
                IW[i, j] = Ib[i, 0] * W[0, j] + Ib[i, 1] * W[1, j] + Ib[i, 2] * W[2, j]
        mb = mass[bdy]
        for i in range(n):
            for j in range(n):
                M[i, j] += (mb * (P[0, i] * P[0, j] + P[1, i] * P[1, j] + P[2, i] * P[2, j])
                            + W[0, i] * IW[0, j] + W[1, i] * IW[1, j] + W[2, i] * IW[2, j])
        _mv3(Ib, bo, mom)
        _cross(bo, mom, v1)
        _mv3(Ib, al, v2)
        for i in range(3):
            rhs3[i] = v2[i] + v1[i]
            v3[i] = mb * (gravity[i] - a0[i])
        for j in range(n):
            f[j] += (P[0, j] * v3[0] + P[1, j] * v3[1] + P[2, j] * v3[2]
                     - W[0, j] * rhs3[0] - W[1, j] * rhs3[1] - W[2, j] * rhs3[2])
    Z = np.zeros((6, n))
    z, zd, gz = np.empty(6), np.empty(6), np.empty(6)
    for i in range(3):
        Z[i, i] = 1.0
        for k in range(2):
            Z[3 + i, 3 + k] = E2[i, k]
        if s == 1:
            Z[3 + i, 5] = e[i]
    for sp in range(spos.shape[0]):
        _mv3(Rs, spos[sp], v1)
        for k in range(m_rot):
            Z[0, 3 + k] = -(v1[1] * H[2, k] - v1[2] * H[1, k])
            Z[1, 3 + k] = -(v1[2] * H[0, k] - v1[0] * H[2, k])
            Z[2, 3 + k] = -(v1[0] * H[1, k] - v1[1] * H[0, k])
        for i in range(3):
            z[i] = y[i] + v1[i] - spos[sp, i]
            z[3 + i] = gamma[i] + psi * e[i]
        for i in range(6):
            v = 0.0
            for j in range(n):
                v += Z[i, j] * y[n + j]
            zd[i] = v
        K, C = sK[sp], sC[sp]
        for i in range(6):
            v = 0.0
            for j in range(6):
                v += K[i, j] * z[j] + C[i, j] * zd[j]
            gz[i] = v
        for j in range(n):
            v = 0.0
            for i in range(6):
                v += Z[i, j] * gz[i]
            f[j] -= v
    out = np.empty(2 * n)
    for i in range(n):
        out[i] = y[n + i]
    qdd = np.empty(n)
    if mode == 0:
        _solve_spd(M, f, n, qdd)
    else:
        alpha = accel if t_start <= t <= t_stop else 0.0
        k = n - 1
        for i in range(k):
            f[i] -= M[i, k] * alpha
        _solve_spd(M, f, k, qdd)
        qdd[k] = alpha
    for i in range(n):
        out[n + i] = qdd[i]
    return out


def rhs_flat(t, y, floats, ints):
    """:func:`rhs` with its arguments packed by :func:`pack` (cheaper to call from Python)."""
    s, nb, ns, mode = ints[0], ints[1], ints[2], ints[3]
    o = 0
    e = floats[o:o + 3]
    o += 3
    E2 = floats[o:o + 6].reshape((3, 2))
    o += 6
    gravity = floats[o:o + 3]
    o += 3
    mass = floats[o:o + nb]
    o += nb
    center = floats[o:o + 3 * nb].reshape((nb, 3))
    o += 3 * nb
    offset = floats[o:o + 3 * nb].reshape((nb, 3))
    o += 3 * nb
    inertia = floats[o:o + 9 * nb].reshape((nb, 3, 3))
    o += 9 * nb
    ratio = floats[o:o + nb]
    o += nb
    spos = floats[o:o + 3 * ns].reshape((ns, 3))
    o += 3 * ns
    sK = floats[o:o + 36 * ns].reshape((ns, 6, 6))
    o += 36 * ns
    sC = floats[o:o + 36 * ns].reshape((ns, 6, 6))
    o += 36 * ns
    return rhs(t, y, e, E2, s, gravity, mass, center, offset, inertia, ratio, spos, sK, sC,
               mode, floats[o], floats[o + 1], floats[o + 2])


def pack(system, mode, accel, t_start, t_stop):
    """``(floats, ints)`` for :func:`rhs_flat` from a ``SystemArrays`` and the drive."""
    parts = [system.e, system.E2, system.gravity, system.mass, system.center, system.offset,
             system.inertia, system.ratio, system.spos, system.sK, system.sC, [accel, t_start, t_stop]]
    floats = np.concatenate([np.ascontiguousarray(p, dtype=float).ravel() for p in parts])
    ints = np.array([system.s, len(system.mass), len(system.spos), mode], dtype=np.int64)
    return floats, ints


FUNCTIONS = ("_mat3", "_mv3", "_cross", "_rodrigues", "_coefficients", "_solve_spd", "rhs", "rhs_flat")
