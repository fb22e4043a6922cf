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


def _interpolate(speeds, count, K, C, own, Kout, Cout):
    """A bearing's coefficients at own speed ``own`` into ``Kout``, ``Cout`` (see
    :func:`rotordyn_modal.simulation._kernels.bearing_coefficients`)."""
    lo, hi, t = 0, 0, 0.0
    last = count - 1
    if count > 1 and own > speeds[0]:
        if own >= speeds[last]:
            lo, hi = last, last
        else:
            hi = 1
            while speeds[hi] < own:
                hi += 1
            lo = hi - 1
            t = (own - speeds[lo]) / (speeds[hi] - speeds[lo])
    for i in range(6):
        for k in range(6):
            Kout[i, k] = (1.0 - t) * K[lo, i, k] + t * K[hi, i, k]
            Cout[i, k] = (1.0 - t) * C[lo, i, k] + t * C[hi, i, k]


def rhs(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
        spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, mode, accel, t_start, t_stop):
    """``dy/dt`` (2n,); see :func:`rotordyn_modal.simulation._kernels.rhs`."""
    n = y.shape[0] // 2
    m_rot = nf - 3 if nf > 0 else 0
    nb = mass.shape[0]
    phi, phi_dot = y[n - 1], y[2 * n - 1]
    Lg, Bg, R1, Rs = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    Rb, Ib, T3, Rl = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 3))
    eg, og, omega, wdot0 = np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3)
    gamma, gdot = np.zeros(3), np.zeros(3)
    v1, v2, v3 = np.empty(3), np.empty(3), np.empty(3)
    H = np.zeros((3, 3))
    psi = 0.0
    for i in range(3):
        eg[i] = e[i]
        for k in range(3):
            Rs[i, k] = 1.0 if i == k else 0.0
    if nf > 0:
        for i in range(3):
            gamma[i] = E2[i, 0] * y[3] + E2[i, 1] * y[4]
            gdot[i] = E2[i, 0] * y[n + 3] + E2[i, 1] * y[n + 4]
        psi_dot = 0.0
        if m_rot == 3:
            psi, psi_dot = y[5], y[n + 5]
        t2 = gamma[0] * gamma[0] + gamma[1] * gamma[1] + gamma[2] * gamma[2]
        a, c, b, da, dc, db = _coefficients(t2)
        _rodrigues(1.0 - c * t2, c, a, gamma, Lg)
        _rodrigues(a, b, c, gamma, Bg)
        _rodrigues(np.cos(psi), 1.0 - np.cos(psi), np.sin(psi), e, R1)
        _mat3(Lg, R1, Rs)
        _mv3(Lg, e, eg)
        for i in range(3):
            for k in range(2):
                H[i, k] = Bg[i, 0] * E2[0, k] + Bg[i, 1] * E2[1, k] + Bg[i, 2] * E2[2, k]
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
    cols = np.empty(n, dtype=np.int64)
    Lrel, Brel = np.empty((nb, 3, 3)), np.empty((nb, 3, 3))
    Lj, Bj, Hj, BA = np.empty((3, 3)), np.empty((3, 3)), np.empty((3, 2)), np.empty((3, 2))
    u, ud, gj, gjd = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    orel, drel, ej, vrel, cu, fat = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    w, arm, d, bo = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    al, a0, mom, rhs3 = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for bdy in range(nb):
        r = ratio[bdy]
        j = slot[bdy]
        kt = ntrans[bdy]
        ncol = 0
        for k in range(nf):
            cols[ncol] = k
            ncol += 1
        if j >= 0:
            for k in range(kt + 2):
                cols[ncol] = j + k
                ncol += 1
            for i in range(3):
                u[i] = A3[i, 0] * y[j] + A3[i, 1] * y[j + 1]
                ud[i] = A3[i, 0] * y[n + j] + A3[i, 1] * y[n + j + 1]
                if kt == 3:
                    u[i] += A3[i, 2] * y[j + 2]
                    ud[i] += A3[i, 2] * y[n + j + 2]
                gj[i] = A3[i, 0] * y[j + kt] + A3[i, 1] * y[j + kt + 1]
                gjd[i] = A3[i, 0] * y[n + j + kt] + A3[i, 1] * y[n + j + kt + 1]
            t2 = gj[0] * gj[0] + gj[1] * gj[1] + gj[2] * gj[2]
            a, c, b, da, dc, db = _coefficients(t2)
            _rodrigues(1.0 - c * t2, c, a, gj, Lj)
            _rodrigues(a, b, c, gj, Bj)
            for i in range(3):
                for k in range(3):
                    Lrel[bdy, i, k] = Lj[i, k]
                    Brel[bdy, i, k] = Bj[i, k]
            for i in range(3):
                for k in range(2):
                    BA[i, k] = Bj[i, 0] * A3[0, k] + Bj[i, 1] * A3[1, k] + Bj[i, 2] * A3[2, k]
            for i in range(3):
                for k in range(2):
                    Hj[i, k] = Rs[i, 0] * BA[0, k] + Rs[i, 1] * BA[1, k] + Rs[i, 2] * BA[2, k]
            _mv3(Bj, gjd, v1)
            _mv3(Rs, v1, orel)
            vw = gj[0] * gjd[0] + gj[1] * gjd[1] + gj[2] * gjd[2]
            ww = gjd[0] * gjd[0] + gjd[1] * gjd[1] + gjd[2] * gjd[2]
            _cross(gj, gjd, v1)
            for i in range(3):
                v2[i] = (da * vw * gjd[i] + db * vw * vw * gj[i] + b * (vw * gjd[i] + ww * gj[i])
                         + dc * vw * v1[i])
            _mv3(Rs, v2, drel)
            _mv3(Lj, e, v1)
            _mv3(Rs, v1, ej)
            _mv3(Rs, ud, vrel)
            _mat3(Rs, Lj, Rl)
            for i in range(3):
                cu[i] = center[bdy, i] + u[i]
        else:
            for i in range(3):
                orel[i], drel[i], vrel[i], ej[i], cu[i] = 0.0, 0.0, 0.0, eg[i], center[bdy, i]
                for k in range(3):
                    Rl[i, k] = Rs[i, k]
        cols[ncol] = n - 1
        ncol += 1
        ang = r * phi
        _rodrigues(np.cos(ang), 1.0 - np.cos(ang), np.sin(ang), e, R1)
        _mat3(Rl, R1, Rb)
        _mv3(Rb, offset[bdy], w)
        _mv3(Rs, cu, arm)
        for i in range(3):
            d[i] = arm[i] + w[i]
            fat[i] = omega[i] + orel[i]
            bo[i] = fat[i] + r * phi_dot * ej[i]
        _cross(omega, orel, v1)
        _cross(fat, ej, v2)
        for i in range(3):
            al[i] = wdot0[i] + v1[i] + drel[i] + r * phi_dot * v2[i]
        # a0 = wdot0 x arm + omega x (omega x arm) + 2 omega x vrel + al x w + bo x (bo x w)
        _cross(wdot0, arm, a0)
        _cross(omega, arm, v1)
        _cross(omega, v1, v2)
        _cross(al, w, v3)
        for i in range(3):
            a0[i] += v2[i] + v3[i]
        _cross(omega, vrel, v1)
        _cross(bo, w, v2)
        _cross(bo, v2, v3)
        for i in range(3):
            a0[i] += 2.0 * v1[i] + v3[i]
        if nf > 0:
            for i in range(3):
                P[i, i] = 1.0
            for k in range(m_rot):
                # -d x H_k
                P[0, 3 + k] = -(d[1] * H[2, k] - d[2] * H[1, k])
                P[1, 3 + k] = -(d[2] * H[0, k] - d[0] * H[2, k])
                P[2, 3 + k] = -(d[0] * H[1, k] - d[1] * H[0, k])
                for i in range(3):
                    W[i, 3 + k] = H[i, k]
        if j >= 0:
            for k in range(kt):
                for i in range(3):
                    P[i, j + k] = Rs[i, 0] * A3[0, k] + Rs[i, 1] * A3[1, k] + Rs[i, 2] * A3[2, k]
                    W[i, j + k] = 0.0
            for k in range(2):
                # -w x Hj_k
                P[0, j + kt + k] = -(w[1] * Hj[2, k] - w[2] * Hj[1, k])
                P[1, j + kt + k] = -(w[2] * Hj[0, k] - w[0] * Hj[2, k])
                P[2, j + kt + k] = -(w[0] * Hj[1, k] - w[1] * Hj[0, k])
                for i in range(3):
                    W[i, j + kt + k] = Hj[i, k]
        _cross(ej, w, v1)
        for i in range(3):
            P[i, n - 1] = r * v1[i]
            W[i, n - 1] = r * ej[i]
        # Ib = Rb I0 Rb^T
        _mat3(Rb, inertia[bdy], T3)
        for i in range(3):
            for k in range(3):
                Ib[i, k] = T3[i, 0] * Rb[k, 0] + T3[i, 1] * Rb[k, 1] + T3[i, 2] * Rb[k, 2]
        for i in range(3):
            for cj in range(ncol):
                k = cols[cj]
                IW[i, k] = Ib[i, 0] * W[0, k] + Ib[i, 1] * W[1, k] + Ib[i, 2] * W[2, k]
        mb = mass[bdy]
        for ci in range(ncol):
            i = cols[ci]
            for cj in range(ncol):
                k = cols[cj]
                M[i, k] += (mb * (P[0, i] * P[0, k] + P[1, i] * P[1, k] + P[2, i] * P[2, k])
                            + W[0, i] * IW[0, k] + W[1, i] * IW[1, k] + W[2, i] * IW[2, k])
        _mv3(Ib, bo, mom)
        _cross(bo, mom, v1)
        _mv3(Ib, al, v2)
        for i in range(3):
            rhs3[i] = v2[i] + v1[i]
            v3[i] = mb * (gravity[i] - a0[i])
        for ci in range(ncol):
            k = cols[ci]
            f[k] += (P[0, k] * v3[0] + P[1, k] * v3[1] + P[2, k] * v3[2]
                     - W[0, k] * rhs3[0] - W[1, k] * rhs3[1] - W[2, k] * rhs3[2])
    z, zd, gz = np.empty(6), np.empty(6), np.empty(6)
    if nf > 0:
        Z = np.zeros((6, nf))
        for i in range(3):
            Z[i, i] = 1.0
            for k in range(2):
                Z[3 + i, 3 + k] = E2[i, k]
            if m_rot == 3:
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
                for k in range(nf):
                    v += Z[i, k] * y[n + k]
                zd[i] = v
            K, C = sK[sp], sC[sp]
            for i in range(6):
                v = 0.0
                for k in range(6):
                    v += K[i, k] * z[k] + C[i, k] * zd[k]
                gz[i] = v
            for k in range(nf):
                v = 0.0
                for i in range(6):
                    v += Z[i, k] * gz[i]
                f[k] -= v
    Kb, Cb, Zb = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 5))
    lb = np.empty(3)
    for br in range(bbody.shape[0]):
        bdy = bbody[br]
        j = slot[bdy]
        kt = ntrans[bdy]
        nk = kt + 2
        _interpolate(bspeeds[br], bcount[br], bK[br], bC[br], ratio[bdy] * phi_dot, Kb, Cb)
        for i in range(3):
            u[i] = A3[i, 0] * y[j] + A3[i, 1] * y[j + 1]
            if kt == 3:
                u[i] += A3[i, 2] * y[j + 2]
            gj[i] = A3[i, 0] * y[j + kt] + A3[i, 1] * y[j + kt + 1]
        _mv3(Lrel[bdy], bpos[br], lb)
        for i in range(3):
            z[i] = u[i] + lb[i] - bpos[br, i]
            z[3 + i] = gj[i]
            for k in range(nk):
                Zb[i, k] = 0.0
                Zb[3 + i, k] = 0.0
            for k in range(kt):
                Zb[i, k] = A3[i, k]
        Bj = Brel[bdy]
        for k in range(2):
            for i in range(3):
                BA[i, k] = Bj[i, 0] * A3[0, k] + Bj[i, 1] * A3[1, k] + Bj[i, 2] * A3[2, k]
                Zb[3 + i, kt + k] = A3[i, k]
            # -lb x (B A)_k
            Zb[0, kt + k] = -(lb[1] * BA[2, k] - lb[2] * BA[1, k])
            Zb[1, kt + k] = -(lb[2] * BA[0, k] - lb[0] * BA[2, k])
            Zb[2, kt + k] = -(lb[0] * BA[1, k] - lb[1] * BA[0, k])
        for i in range(6):
            v = 0.0
            for k in range(nk):
                v += Zb[i, k] * y[n + j + k]
            zd[i] = v
        for i in range(6):
            v = 0.0
            for k in range(6):
                v += Kb[i, k] * z[k] + Cb[i, k] * zd[k]
            gz[i] = v
        for k in range(nk):
            v = 0.0
            for i in range(6):
                v += Zb[i, k] * gz[i]
            f[j + k] -= v
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
    nf, nb, ns, nbr, length, mode = ints[0], ints[1], ints[2], ints[3], ints[4], ints[5]
    o = 6
    slot = ints[o:o + nb]
    o += nb
    ntrans = ints[o:o + nb]
    o += nb
    bbody = ints[o:o + nbr]
    o += nbr
    bcount = ints[o:o + nbr]
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
    A3 = floats[o:o + 9].reshape((3, 3))
    o += 9
    spos = floats[o:o + 3 * ns].reshape((ns, 3))
    o += 3 * ns
    sK = floats[o:o + 36 * ns].reshape((ns, 6, 6))
    o += 36 * ns
    sC = floats[o:o + 36 * ns].reshape((ns, 6, 6))
    o += 36 * ns
    bpos = floats[o:o + 3 * nbr].reshape((nbr, 3))
    o += 3 * nbr
    bspeeds = floats[o:o + nbr * length].reshape((nbr, length))
    o += nbr * length
    bK = floats[o:o + 36 * nbr * length].reshape((nbr, length, 6, 6))
    o += 36 * nbr * length
    bC = floats[o:o + 36 * nbr * length].reshape((nbr, length, 6, 6))
    o += 36 * nbr * length
    return rhs(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
               spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, mode, floats[o], floats[o + 1], floats[o + 2])


def pack(system, mode, accel, t_start, t_stop):
    """``(floats, ints)`` for :func:`rhs_flat` from a ``SystemArrays`` and the drive."""
    parts = [system.e, system.E2, system.gravity, system.mass, system.center, system.offset,
             system.inertia, system.ratio, system.A3, system.spos, system.sK, system.sC, system.bpos,
             system.bspeeds, system.bK, system.bC, [accel, t_start, t_stop]]
    floats = np.concatenate([np.ascontiguousarray(p, dtype=float).ravel() for p in parts])
    sizes = [system.nf, len(system.mass), len(system.spos), len(system.bbody), system.bspeeds.shape[1], mode]
    ints = np.concatenate([np.array(sizes, dtype=np.int64), system.slot, system.ntrans, system.bbody,
                           system.bcount]).astype(np.int64)
    return floats, ints


FUNCTIONS = ("_mat3", "_mv3", "_cross", "_rodrigues", "_coefficients", "_solve_spd", "_interpolate", "rhs",
             "rhs_flat")
