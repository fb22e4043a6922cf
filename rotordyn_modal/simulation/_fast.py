"""Compiled right-hand side: the equations of ``_kernels`` rewritten for speed under numba.

Same arguments and results as :func:`rotordyn_modal.simulation._kernels.rhs` (tested to
agree to round-off), written with scalar loops into a few scratch arrays instead of the
many small temporary arrays of the readable version, and with an in-place Cholesky solve
of the (symmetric positive definite) generalized mass matrix. Only used through numba.
"""

from __future__ import annotations

import numpy as np

SERIES = 0.05
#: coordinates from which the mass matrix is solved in the order of :func:`_solve_order` (fewer:
#: the dense Cholesky of :func:`_solve_spd`, which costs less than making the order)
ORDERED_FROM = 40


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
    """Solve ``M[:k, :k] x = f[:k]`` by Cholesky (M overwritten). A pivot that is not > 0 (a mass
    matrix not positive definite in double precision) gives ``x`` = NaN: DOP853 rejects the trial
    step whose stage reached that state (a first step after a restart at an output time, 1e9 rad
    away on the stiff casing of tests/test_simulate_stiff27s.py) and tries a shorter one; a
    motion that truly reaches it fails with non-finite states."""
    for j in range(k):
        d = M[j, j]
        for p in range(j):
            d -= M[j, p] * M[j, p]
        if not d > 0.0:     # was a ZeroDivisionError (d = 0) or NaNs (d < 0) from here on
            for i in range(k):
                out[i] = np.nan
            return
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


def _solve_ordered(M, f, k, out, order, first, start, rows):
    """Solve ``M[:k, :k] x = f[:k]`` by Cholesky, the coordinates taken in ``order`` (shape (k,):
    row ``a`` of the factor is coordinate ``order[a]``), each row ``a`` of the factor zero left of
    its column ``first[a]`` (:func:`_solve_order`); only those zeros are skipped: in the order of the
    coordinates, the sums of :func:`_solve_spd`. The rows below column ``j`` that are not zero there
    are ``rows[start[j]:start[j + 1]]`` (:func:`_rows_below`), so the loops visit no other row.
    The factor overwrites ``M``'s entries ``M[order[a], order[b]]``, ``a >= b`` (M symmetric);
    ``x`` into ``out[order]``."""
    for j in range(k):
        rj, fj = order[j], first[j]
        d = M[rj, rj]
        for p in range(fj, j):
            c = M[rj, order[p]]
            d -= c * c
        if not d > 0.0:
            for i in range(k):
                out[order[i]] = np.nan
            return
        d = np.sqrt(d)
        M[rj, rj] = d
        for q in range(start[j], start[j + 1]):
            i = rows[q]
            fi = first[i]
            ri = order[i]
            v = M[ri, rj]
            for p in range(max(fi, fj), j):
                v -= M[ri, order[p]] * M[rj, order[p]]
            M[ri, rj] = v / d
    for i in range(k):
        ri = order[i]
        v = f[ri]
        for p in range(first[i], i):
            v -= M[ri, order[p]] * out[order[p]]
        out[ri] = v / M[ri, ri]
    for i in range(k - 1, -1, -1):
        ri = order[i]
        v = out[ri]
        for q in range(start[i], start[i + 1]):
            rp = order[rows[q]]
            v -= M[rp, ri] * out[rp]
        out[ri] = v / M[ri, ri]


def _solve_order(n, k, nf, slot, ntrans, order, first):
    """The order of the mass matrix's first ``k`` coordinates for :func:`_solve_ordered` (into
    ``order``, shape (k,)) and where each row of its Cholesky factor starts (into ``first``).

    A rotor on bearings moves with its own coordinates, the frame's and the reference angle
    (:func:`_body_columns`), so the mass matrix is zero between two rotors' own coordinates.
    Taken first, rotor by rotor, and the frame's and the angle's last, the factor keeps those
    zeros (it fills no entry left of the first one of its row in ``M``): its cost grows as n, not
    n^3. In the coordinates' own order, the frame's first fill the factor whole: the right-hand
    side took 1.25 s at 2,007 coordinates (500 geared rotors on bearings), 4.3 ms so. Without
    rotors on bearings the order is the coordinates' own."""
    nb = slot.shape[0]
    pos = np.full(n, -1, dtype=np.int64)
    own = np.zeros(n, dtype=np.bool_)
    for b in range(nb):
        if slot[b] >= 0:
            for c in range(slot[b], slot[b] + ntrans[b] + 2):
                own[c] = True
    a = 0
    for c in range(k):
        if own[c]:
            order[a], pos[c] = c, a
            a += 1
    for c in range(k):
        if not own[c]:
            order[a], pos[c] = c, a
            a += 1
    for a in range(k):
        first[a] = a
    cols = np.empty(n, dtype=np.int64)
    for b in range(nb):
        ncol = _body_columns(n, nf, slot[b], ntrans[b], cols)
        for ci in range(ncol):
            if cols[ci] >= k:
                continue
            row = pos[cols[ci]]
            for cj in range(ncol):
                if cols[cj] < k and pos[cols[cj]] < first[row]:
                    first[row] = pos[cols[cj]]


def _rows_below(first, k):
    """For each column ``j`` of the factor of :func:`_solve_ordered`, the rows ``i > j`` not zero
    there (``first[i] <= j``), ascending, as compressed rows.

    Parameters
    ----------
    first : ndarray of int, shape (k,)
        The column where each row of the factor starts (:func:`_solve_order`).
    k : int
        The number of coordinates solved for.

    Returns
    -------
    start : ndarray of int, shape (k + 1,)
        Column ``j``'s rows are ``rows[start[j]:start[j + 1]]``.
    rows : ndarray of int, shape (start[k],)
        The rows, column by column.
    """
    start = np.zeros(k + 1, dtype=np.int64)
    for i in range(k):
        for j in range(first[i], i):
            start[j + 1] += 1
    for j in range(k):
        start[j + 1] += start[j]
    rows = np.empty(start[k], dtype=np.int64)
    fill = start[:k].copy()
    for i in range(k):
        for j in range(first[i], i):
            rows[fill[j]] = i
            fill[j] += 1
    return start, rows


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


def _frame(y, n, e, E2, nf, Rs, H, eg, omega, wdot0, gamma, mats, vec):
    """The frame's rotation ``Rs``, ``H`` (columns of ``omega = H eta``), spin axis ``eg``,
    angular velocity, its rate at zero second derivatives, and Euler vector (all filled in;
    identity and zeros on the ground). ``mats`` (3, 3, 3) and ``vec`` (4, 3) are scratch.

    Returns
    -------
    psi : float
        The roll angle [rad] (0 without a stator).
    """
    m_rot = nf - 3 if nf > 0 else 0
    psi = 0.0
    for i in range(3):
        eg[i], omega[i], wdot0[i], gamma[i] = e[i], 0.0, 0.0, 0.0
        for k in range(3):
            Rs[i, k] = 1.0 if i == k else 0.0
    if nf == 0:
        return psi
    Lg, Bg, R1 = mats[0], mats[1], mats[2]
    gdot, og, v1, v2 = vec[0], vec[1], vec[2], vec[3]
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
    return psi


def _relative(y, n, j, kt, A3, u, ud, gj, gjd):
    """A rotor's translation, transverse Euler vector and their rates relative to the frame
    (frame axes), filled in from the coordinates starting at ``j``."""
    for i in range(3):
        u[i] = A3[i, 0] * y[j] + A3[i, 1] * y[j + 1]
        ud[i] = A3[i, 0] * y[n + j] + A3[i, 1] * y[n + j + 1]
        if kt == 3:
            u[i] += A3[i, 2] * y[j + 2]
            ud[i] += A3[i, 2] * y[n + j + 2]
        gj[i] = A3[i, 0] * y[j + kt] + A3[i, 1] * y[j + kt + 1]
        gjd[i] = A3[i, 0] * y[n + j + kt] + A3[i, 1] * y[n + j + kt + 1]


def _bearing_stretch(y, n, j, kt, A3, Lj, Bj, point, u, gj, z, zd, Zb, BA, lb):
    """A bearing's ``z = [u + Lj b - b, gamma_j]``, ``dz/dt`` and its Jacobian ``Zb`` (6, kt + 2)
    on the rotor's own coordinates (``u``, ``gj`` its relative motion, ``BA``, ``lb`` scratch)."""
    nk = kt + 2
    _mv3(Lj, point, lb)
    for i in range(3):
        z[i] = u[i] + lb[i] - point[i]
        z[3 + i] = gj[i]
        for k in range(nk):
            Zb[i, k] = 0.0
            Zb[3 + i, k] = 0.0
        for k in range(kt):
            Zb[i, k] = A3[i, k]
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


def _sommerfeld_angle(theta, eps):
    """See :func:`rotordyn_modal.simulation._kernels.sommerfeld_angle`."""
    turns = np.floor((theta + np.pi) / (2.0 * np.pi))
    t = theta - 2.0 * np.pi * turns
    return 2.0 * np.arctan2(np.sqrt(1.0 - eps) * np.sin(0.5 * t), np.sqrt(1.0 + eps) * np.cos(0.5 * t)) \
        + 2.0 * np.pi * turns


def _film_force(z, zd, own, axes, film, out):
    """The oil film's force on the journal into ``out`` (3,), from ``z[:3]``, ``zd[:3]``; see
    :func:`rotordyn_modal.simulation._kernels.film_force`."""
    radius, length, clearance, viscosity = film[0], film[1], film[2], film[3]
    X, Y, Xd, Yd = 0.0, 0.0, 0.0, 0.0
    for i in range(3):
        X += z[i] * axes[0, i]
        Y += z[i] * axes[1, i]
        Xd += zd[i] * axes[0, i]
        Yd += zd[i] * axes[1, i]
    X, Y, Xd, Yd = X / clearance, Y / clearance, Xd / clearance, Yd / clearance
    eps = np.sqrt(X * X + Y * Y)
    if eps >= 1.0:
        for i in range(3):
            out[i] = np.nan
        return
    ur_x, ur_y = 1.0, 0.0
    if eps > 0.0:
        ur_x, ur_y = X / eps, Y / eps
    ut_x, ut_y = -ur_y, ur_x
    a = eps * own - 2.0 * (Xd * ut_x + Yd * ut_y)
    b = 2.0 * (Xd * ur_x + Yd * ur_y)
    if a == 0.0 and b == 0.0:
        for i in range(3):
            out[i] = 0.0
        return
    theta0 = np.arctan2(b, a)
    p0, p1 = _sommerfeld_angle(theta0, eps), _sommerfeld_angle(theta0 + np.pi, eps)
    room = 1.0 - eps * eps
    s0, s1, c0, c1 = np.sin(p0), np.sin(p1), np.cos(p0), np.cos(p1)
    d2 = (np.sin(2.0 * p1) - np.sin(2.0 * p0)) / 4.0
    i_ss = ((p1 - p0) / 2.0 - d2) / (room * np.sqrt(room))
    i_sc = ((s1 * s1 - s0 * s0) / 2.0 + eps * (c1 - c0)) / (room * room)
    i_cc = ((0.5 + eps * eps) * (p1 - p0) + d2 - 2.0 * eps * (s1 - s0)) / (room * room * np.sqrt(room))
    k = viscosity * radius * length * length * length / (2.0 * clearance * clearance)
    radial = k * (a * i_sc - b * i_cc)
    tangential = k * (a * i_ss - b * i_sc)
    fx = radial * ur_x + tangential * ut_x
    fy = radial * ur_y + tangential * ut_y
    for i in range(3):
        out[i] = fx * axes[0, i] + fy * axes[1, i]


def _tilt(gj, Lj, Bj):
    """``L(gamma_j)``, ``B(gamma_j)`` into ``Lj``, ``Bj``; returns the coefficients of
    :func:`_coefficients` (for ``D B``)."""
    t2 = gj[0] * gj[0] + gj[1] * gj[1] + gj[2] * gj[2]
    a, c, b, da, dc, db = _coefficients(t2)
    _rodrigues(1.0 - c * t2, c, a, gj, Lj)
    _rodrigues(a, b, c, gj, Bj)
    return b, c, da, dc, db


def assemble_into(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                  spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, M, f):
    """Add the generalized mass matrix to ``M`` (n, n) and the force to ``f`` (n,), both
    zero on entry; see :func:`rotordyn_modal.simulation._kernels.assemble`.

    Body by body: its motion relative to the frame (:func:`_rotor_on_bearings` or
    :func:`_rotor_on_frame`); its rotation, arm and accelerations at zero second
    derivatives; the Jacobians ``P`` (velocity of its centre of mass) and ``W`` (angular
    velocity) on its coordinates; its share of ``M`` and ``f``. Those three steps stay
    inline: split into functions (even inlined by numba) they cost 4-7 % of the right-hand
    side's time (``benchmarks/bench_rhs.py``). Then the suspensions' and the bearings' forces.
    """
    n = y.shape[0] // 2
    m_rot = nf - 3 if nf > 0 else 0
    nb = mass.shape[0]
    phi, phi_dot = y[n - 1], y[2 * n - 1]
    mats = np.empty((13, 3, 3))    # scratch: one allocation for the small arrays
    R1, Rs, Rb, Ib, T3, Rl = mats[0], mats[1], mats[2], mats[3], mats[4], mats[5]
    Lj, Bj, H = mats[6], mats[7], mats[8]
    vec = np.zeros((32, 3))
    eg, omega, wdot0, gamma = vec[0], vec[1], vec[2], vec[3]
    v1, v2, v3 = vec[4], vec[5], vec[6]
    u, ud, gj, gjd, orel, drel = vec[7], vec[8], vec[9], vec[10], vec[11], vec[12]
    ej, vrel, cu, fat, w, arm = vec[13], vec[14], vec[15], vec[16], vec[17], vec[18]
    d, bo, al, a0, mom, rhs3, lb = vec[19], vec[20], vec[21], vec[22], vec[23], vec[24], vec[25]
    psi = _frame(y, n, e, E2, nf, Rs, H, eg, omega, wdot0, gamma, mats[9:12], vec[26:30])
    PW = np.zeros((3, 3, n))
    P, W, IW = PW[0], PW[1], PW[2]
    cols = np.empty(n, dtype=np.int64)
    rel = np.empty((2, nb, 3, 3))
    Lrel, Brel = rel[0], rel[1]
    HB = np.empty((2, 3, 2))
    Hj, BA = HB[0], HB[1]
    for bdy in range(nb):
        r, j, kt = ratio[bdy], slot[bdy], ntrans[bdy]
        ncol = _body_columns(n, nf, j, kt, cols)
        if j >= 0:
            _rotor_on_bearings(y, n, j, kt, A3, e, Rs, center[bdy], u, ud, gj, gjd, Lj, Bj, Lrel[bdy],
                               Brel[bdy], BA, Hj, orel, drel, ej, vrel, Rl, cu, v1, v2)
        else:
            _rotor_on_frame(eg, Rs, center[bdy], orel, drel, vrel, ej, Rl, cu)
        # rotation Rb, centre of mass d, angular velocity bo, accelerations al, a0
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
        # Jacobians P, W on the frame's coordinates, the rotor's own, the reference angle
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
        # its share of M (m P^T P + W^T Ib W) and f (gravity, centrifugal, gyroscopic); Ib = Rb I0 Rb^T
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
    sixes = np.empty((3, 6))
    blocks = np.zeros((4, 6, 6))
    _add_suspension_forces(y, n, nf, e, E2, Rs, H, gamma, psi, spos, sK, sC, sixes, blocks[3], v1, f)
    _add_bearing_forces(y, n, phi_dot, ratio, slot, ntrans, A3, Lrel, Brel, bbody, bpos, bspeeds, bcount,
                        bK, bC, bfilm, baxes, u, ud, gj, gjd, sixes, blocks, BA, lb, v1, f)


def _body_columns(n, nf, j, kt, cols):
    """The coordinates a body moves with into ``cols``: the frame's, its own (from ``j``,
    when on bearings) and the reference rotor's angle (last); returns how many."""
    ncol = 0
    for k in range(nf):
        cols[ncol] = k
        ncol += 1
    if j >= 0:
        for k in range(kt + 2):
            cols[ncol] = j + k
            ncol += 1
    cols[ncol] = n - 1
    return ncol + 1


def _rotor_on_bearings(y, n, j, kt, A3, e, Rs, center, u, ud, gj, gjd, Lj, Bj, Lrel, Brel, BA, Hj,
                       orel, drel, ej, vrel, Rl, cu, v1, v2):
    """A rotor on bearings relative to the frame, in model axes: angular velocity ``orel``
    and its rate at zero second derivatives ``drel``, spin axis ``ej``, translational
    velocity ``vrel``, rotation ``Rl = Rs L(gamma_j)``, centre ``cu``; ``Hj`` the columns of
    its angular velocity on its two tilts, ``Lrel``, ``Brel`` kept for its bearings."""
    _relative(y, n, j, kt, A3, u, ud, gj, gjd)
    b, c, da, dc, db = _tilt(gj, Lj, Bj)
    for i in range(3):
        for k in range(3):
            Lrel[i, k] = Lj[i, k]
            Brel[i, k] = Bj[i, k]
    for i in range(3):
        for k in range(2):
            BA[i, k] = Bj[i, 0] * A3[0, k] + Bj[i, 1] * A3[1, k] + Bj[i, 2] * A3[2, k]
    for i in range(3):
        for k in range(2):
            Hj[i, k] = Rs[i, 0] * BA[0, k] + Rs[i, 1] * BA[1, k] + Rs[i, 2] * BA[2, k]
    _mv3(Bj, gjd, v1)
    _mv3(Rs, v1, orel)
    # D B(gamma_j)[gjd] gjd
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
        cu[i] = center[i] + u[i]


def _rotor_on_frame(eg, Rs, center, orel, drel, vrel, ej, Rl, cu):
    """A rotor fixed in the frame: no relative motion, the frame's spin axis and rotation."""
    for i in range(3):
        orel[i], drel[i], vrel[i], ej[i], cu[i] = 0.0, 0.0, 0.0, eg[i], center[i]
        for k in range(3):
            Rl[i, k] = Rs[i, k]


def _add_suspension_forces(y, n, nf, e, E2, Rs, H, gamma, psi, spos, sK, sC, sixes, Z, v1, f):
    """Subtract the suspensions' spring and damper forces, ``Z^T (K z + C dz/dt)``, from the
    frame's entries of ``f`` (nothing on the ground); ``sixes`` (3, 6), ``Z`` (6, 6) scratch."""
    if nf == 0:
        return
    m_rot = nf - 3
    z, zd, gz = sixes[0], sixes[1], sixes[2]
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


def _add_bearing_forces(y, n, phi_dot, ratio, slot, ntrans, A3, Lrel, Brel, bbody, bpos, bspeeds, bcount,
                        bK, bC, bfilm, baxes, u, ud, gj, gjd, sixes, blocks, BA, lb, v1, f):
    """Subtract each bearing's force (coefficients at its rotor's own speed, plus the oil
    film of a journal bearing) from its rotor's entries of ``f``; ``sixes`` (3, 6),
    ``blocks`` (4, 6, 6), ``BA``, ``lb``, ``v1`` scratch."""
    z, zd, gz = sixes[0], sixes[1], sixes[2]
    Kb, Cb, Zb = blocks[0], blocks[1], blocks[2]
    for br in range(bbody.shape[0]):
        bdy = bbody[br]
        j = slot[bdy]
        kt = ntrans[bdy]
        _interpolate(bspeeds[br], bcount[br], bK[br], bC[br], ratio[bdy] * phi_dot, Kb, Cb)
        _relative(y, n, j, kt, A3, u, ud, gj, gjd)
        _bearing_stretch(y, n, j, kt, A3, Lrel[bdy], Brel[bdy], bpos[br], u, gj, z, zd, Zb, BA, lb)
        for i in range(6):
            v = 0.0
            for k in range(6):
                v += Kb[i, k] * z[k] + Cb[i, k] * zd[k]
            gz[i] = v
        if bfilm[br, 2] > 0.0:
            _film_force(z, zd, ratio[bdy] * phi_dot, baxes[br], bfilm[br], v1)
            for i in range(3):
                gz[i] -= v1[i]
        for k in range(kt + 2):
            v = 0.0
            for i in range(6):
                v += Zb[i, k] * gz[i]
            f[j + k] -= v


def assemble(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
             spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes):
    """``(M, f)``: :func:`rotordyn_modal.simulation._kernels.assemble`, allocation-light."""
    n = y.shape[0] // 2
    M = np.zeros((n, n))
    f = np.zeros(n)
    assemble_into(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                  spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, M, f)
    return M, f


def _solve_mass(M, f, k, out, nf, slot, ntrans):
    """Solve ``M[:k, :k] x = f[:k]`` into ``out[:k]`` (``M`` overwritten): from :data:`ORDERED_FROM`
    coordinates in the order of :func:`_solve_order` (``nf``, ``slot``, ``ntrans``: the coordinates'
    layout), below it the dense Cholesky :func:`_solve_spd`."""
    n = f.shape[0]
    if n < ORDERED_FROM:
        _solve_spd(M, f, k, out)
        return
    order, first = np.empty(k, dtype=np.int64), np.empty(k, dtype=np.int64)
    _solve_order(n, k, nf, slot, ntrans, order, first)
    start, rows = _rows_below(first, k)
    _solve_ordered(M, f, k, out, order, first, start, rows)


def _solve_motion(M, f, t, mode, accel, t_start, t_stop, qdd, nf, slot, ntrans):
    """``d2q/dt2`` into ``qdd`` (``M[:k, :k]`` and ``f[:k]`` overwritten); returns the drive
    torque [N m]; see :func:`rotordyn_modal.simulation._kernels.solve_motion` (``nf``, ``slot``,
    ``ntrans``: the coordinates' layout, :func:`_solve_mass`)."""
    n = f.shape[0]
    if mode == 0:
        _solve_mass(M, f, n, qdd, nf, slot, ntrans)
        return 0.0
    alpha = accel if t_start <= t <= t_stop else 0.0
    k = n - 1
    for i in range(k):
        f[i] -= M[i, k] * alpha
    _solve_mass(M, f, k, qdd, nf, slot, ntrans)     # leaves row k of M and f[k] alone
    qdd[k] = alpha
    torque = M[k, k] * alpha - f[k]
    for i in range(k):
        torque += M[k, i] * qdd[i]
    return torque


def rhs(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
        spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop):
    """``dy/dt`` (2n,); see :func:`rotordyn_modal.simulation._kernels.rhs`."""
    n = y.shape[0] // 2
    work = np.zeros(n * n + n)
    M = work[:n * n].reshape((n, n))
    f = work[n * n:]
    assemble_into(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                  spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, M, f)
    out = np.empty(2 * n)
    for i in range(n):
        out[i] = y[n + i]
    _solve_motion(M, f, t, mode, accel, t_start, t_stop, out[n:], nf, slot, ntrans)
    return out


def _bearing_now(y, n, br, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, Kb, Cb, Lj, Bj, vec,
                 z, zd, Zb, BA):
    """Bearing ``br``'s coefficients at its rotor's own speed (``Kb``, ``Cb``), stretch ``z``,
    its rate ``zd`` and Jacobian ``Zb``, from the state alone (``vec`` (5, 3) scratch); returns
    the carried body."""
    bdy = bbody[br]
    j, kt = slot[bdy], ntrans[bdy]
    u, ud, gj, gjd, lb = vec[0], vec[1], vec[2], vec[3], vec[4]
    _interpolate(bspeeds[br], bcount[br], bK[br], bC[br], ratio[bdy] * y[2 * n - 1], Kb, Cb)
    _relative(y, n, j, kt, A3, u, ud, gj, gjd)
    _tilt(gj, Lj, Bj)
    _bearing_stretch(y, n, j, kt, A3, Lj, Bj, bpos[br], u, gj, z, zd, Zb, BA, lb)
    return bdy


def potential(y, e, E2, nf, gravity, mass, center, offset, ratio, slot, ntrans, A3, spos, sK,
              bbody, bpos, bspeeds, bcount, bK, bC):
    """Elastic and gravitational potential energy [J]; see
    :func:`rotordyn_modal.simulation._kernels.potential`."""
    n = y.shape[0] // 2
    mats = np.empty((9, 3, 3))
    Rs, H, R1, Lj, Bj, Rl = mats[0], mats[1], mats[2], mats[3], mats[4], mats[5]
    blocks = np.empty((3, 6, 6))
    Kb, Cb, Zb = blocks[0], blocks[1], blocks[2]
    vec = np.zeros((16, 3))
    eg, omega, wdot0, gamma, u, ud, gj, gjd = vec[0], vec[1], vec[2], vec[3], vec[4], vec[5], vec[6], vec[7]
    v1, v2 = vec[9], vec[10]      # vec[8] serves only in the bearings' scratch vec[4:9]
    psi = _frame(y, n, e, E2, nf, Rs, H, eg, omega, wdot0, gamma, mats[6:9], vec[11:15])
    z, zd = np.empty(6), np.empty(6)
    BA = np.empty((3, 2))
    elastic = _suspension_energy(y, nf, e, Rs, gamma, psi, spos, sK, z, v1)
    for br in range(bbody.shape[0]):
        _bearing_now(y, n, br, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, Kb, Cb, Lj, Bj,
                     vec[4:9], z, zd, Zb, BA)
        elastic += 0.5 * _quadratic(Kb, z)
    weight = 0.0
    for bdy in range(mass.shape[0]):
        _center_of_mass(y, n, slot[bdy], ntrans[bdy], A3, e, ratio[bdy] * y[n - 1], Rs, center[bdy],
                        offset[bdy], u, ud, gj, gjd, Lj, Bj, R1, Rl, v1, v2)
        for i in range(3):
            weight -= mass[bdy] * gravity[i] * ((y[i] if nf > 0 else 0.0) + v2[i])
    return elastic, weight


def _suspension_energy(y, nf, e, Rs, gamma, psi, spos, sK, z, v1):
    """The suspensions' elastic energy ``sum z^T K z / 2`` [J] (0 on the ground)."""
    elastic = 0.0
    if nf > 0:
        for sp in range(spos.shape[0]):
            _mv3(Rs, spos[sp], v1)
            for i in range(3):
                z[i] = y[i] + v1[i] - spos[sp, i]
                z[3 + i] = gamma[i] + psi * e[i]
            elastic += 0.5 * _quadratic(sK[sp], z)
    return elastic


def _center_of_mass(y, n, j, kt, A3, e, angle, Rs, center, offset, u, ud, gj, gjd, Lj, Bj, R1, Rl, v1, out):
    """A body's centre of mass from the frame's origin, model axes, into ``out`` (3,) (the
    frame's translation not included); ``angle`` its turn about its axis."""
    for i in range(3):
        v1[i] = center[i]
    if j >= 0:
        _relative(y, n, j, kt, A3, u, ud, gj, gjd)
        _tilt(gj, Lj, Bj)
        for i in range(3):
            v1[i] += u[i]
    else:
        for i in range(3):
            for k in range(3):
                Lj[i, k] = 1.0 if i == k else 0.0
    _rodrigues(np.cos(angle), 1.0 - np.cos(angle), np.sin(angle), e, R1)
    _mat3(Lj, R1, Rl)
    _mv3(Rl, offset, out)
    for i in range(3):
        v1[i] += out[i]
    _mv3(Rs, v1, out)


def _quadratic(K, z):
    """``z . K z`` for a 6x6 ``K``."""
    total = 0.0
    for i in range(6):
        for k in range(6):
            total += z[i] * K[i, k] * z[k]
    return total


def bearing_wrenches(y, nf, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes):
    """``K z + C dz/dt`` of every bearing, shape (nbr, 6); see
    :func:`rotordyn_modal.simulation._kernels.bearing_wrenches`."""
    n = y.shape[0] // 2
    out = np.empty((bbody.shape[0], 6))
    mats = np.empty((2, 3, 3))
    Lj, Bj = mats[0], mats[1]
    blocks = np.empty((3, 6, 6))
    Kb, Cb, Zb = blocks[0], blocks[1], blocks[2]
    vec = np.empty((6, 3))
    oil = vec[5]
    z, zd = np.empty(6), np.empty(6)
    BA = np.empty((3, 2))
    for br in range(bbody.shape[0]):
        bdy = _bearing_now(y, n, br, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, Kb, Cb, Lj, Bj,
                           vec[:5], z, zd, Zb, BA)
        for i in range(6):
            v = 0.0
            for k in range(6):
                v += Kb[i, k] * z[k] + Cb[i, k] * zd[k]
            out[br, i] = v
        if bfilm[br, 2] > 0.0:
            _film_force(z, zd, ratio[bdy] * y[2 * n - 1], baxes[br], bfilm[br], oil)
            for i in range(3):
                out[br, i] -= oil[i]
    return out


def sample_outputs(times, states, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans,
                   A3, spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop):
    """Per-sample derived outputs; see :func:`rotordyn_modal.simulation._kernels.sample_outputs`."""
    count = times.shape[0]
    n = states.shape[1] // 2
    kinetic, elastic, weight = np.empty(count), np.empty(count), np.empty(count)
    torque, omega = np.empty(count), np.empty((count, 3))
    wrenches = np.empty((count, bbody.shape[0], 6))
    work = np.empty(n * n + 2 * n)
    M = work[:n * n].reshape((n, n))
    f = work[n * n:n * n + n]
    qdd = work[n * n + n:]
    mats = np.empty((5, 3, 3))
    vec = np.empty((7, 3))
    for s in range(count):
        y = states[s]
        for i in range(n * n + n):
            work[i] = 0.0
        assemble_into(times[s], y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3,
                      spos, sK, sC, bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, M, f)
        total = 0.0
        for i in range(n):
            for k in range(n):
                total += y[n + i] * M[i, k] * y[n + k]
        kinetic[s] = 0.5 * total
        torque[s] = _solve_motion(M, f, times[s], mode, accel, t_start, t_stop, qdd, nf, slot, ntrans)
        elastic[s], weight[s] = potential(y, e, E2, nf, gravity, mass, center, offset, ratio, slot, ntrans, A3,
                                          spos, sK, bbody, bpos, bspeeds, bcount, bK, bC)
        _frame(y, n, e, E2, nf, mats[0], mats[1], vec[0], omega[s], vec[1], vec[2], mats[2:5], vec[3:7])
        wrench = bearing_wrenches(y, nf, ratio, slot, ntrans, A3, bbody, bpos, bspeeds, bcount, bK, bC, bfilm,
                                  baxes)
        for br in range(wrench.shape[0]):     # element by element: ``wrenches[s] = ...`` makes numba
            for i in range(6):                # compile its shape-mismatch message (3 s of a 28 s compile)
                wrenches[s, br, i] = wrench[br, i]
    return kinetic, elastic, weight, torque, omega, wrenches


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
    bfilm = floats[o:o + 4 * nbr].reshape((nbr, 4))
    o += 4 * nbr
    baxes = floats[o:o + 6 * nbr].reshape((nbr, 2, 3))
    o += 6 * nbr
    return rhs(t, y, e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3, spos, sK, sC,
               bbody, bpos, bspeeds, bcount, bK, bC, bfilm, baxes, mode, floats[o], floats[o + 1], floats[o + 2])


def pack(system, mode, accel, t_start, t_stop):
    """``(floats, ints)`` for :func:`rhs_flat` from a ``SystemArrays`` and the drive."""
    return pack_arguments(system.kernel_arguments() + (mode, accel, t_start, t_stop))


def pack_arguments(arguments):
    """``(floats, ints)`` for :func:`rhs_flat` from :func:`rhs`'s arguments after ``(t, y)``."""
    (e, E2, nf, gravity, mass, center, offset, inertia, ratio, slot, ntrans, A3, spos, sK, sC, bbody, bpos,
     bspeeds, bcount, bK, bC, bfilm, baxes, mode, accel, t_start, t_stop) = arguments
    parts = [e, E2, gravity, mass, center, offset, inertia, ratio, A3, spos, sK, sC, bpos, bspeeds, bK, bC, bfilm,
             baxes, [accel, t_start, t_stop]]
    floats = np.concatenate([np.ascontiguousarray(p, dtype=float).ravel() for p in parts])
    sizes = [nf, len(mass), len(spos), len(bbody), np.shape(bspeeds)[1], mode]
    ints = np.concatenate([np.array(sizes, dtype=np.int64), slot, ntrans, bbody, bcount]).astype(np.int64)
    return floats, ints


def packed(compiled_rhs_flat):
    """:func:`rhs` called from Python through ``compiled_rhs_flat`` (numba's :func:`rhs_flat`), so
    that numba compiles the right-hand side once, as ``rhs_flat``, not again as ``rhs``."""
    def rhs(t, y, *arguments):
        return compiled_rhs_flat(t, y, *pack_arguments(arguments))
    return rhs


FUNCTIONS = ("_mat3", "_mv3", "_cross", "_rodrigues", "_coefficients", "_solve_spd", "_solve_ordered",
             "_solve_order", "_rows_below", "_solve_mass", "_interpolate", "_frame", "_relative", "_bearing_stretch",
             "_sommerfeld_angle", "_film_force", "_tilt", "_bearing_now",
             "assemble_into", "_body_columns", "_rotor_on_bearings", "_rotor_on_frame", "_add_suspension_forces",
             "_add_bearing_forces", "_suspension_energy", "_center_of_mass", "assemble", "_solve_motion", "rhs",
             "potential", "_quadratic", "bearing_wrenches", "sample_outputs", "rhs_flat")
#: steps of ``assemble_into`` and ``potential``, inlined into them by numba (``inline="always"``):
#: called as functions with many array arguments they would cost time in the right-hand side; and
#: functions with one compiled caller (the steps of the solve, ``rhs`` in ``rhs_flat``,
#: ``potential`` and ``bearing_wrenches`` in ``sample_outputs``): each compiled function of its own
#: is optimised and translated to machine code again in every compiled caller above it
INLINED = ("_body_columns", "_rotor_on_bearings", "_rotor_on_frame", "_add_suspension_forces",
           "_add_bearing_forces", "_suspension_energy", "_center_of_mass",
           "rhs")
#: compiled functions called only from other compiled functions: no wrapper for calls from Python.
#: Not the film's kernel (``_sommerfeld_angle``, ``_film_force``): the flexible rotors' journal
#: model compiles them too and calls ``_film_force`` from Python (``flexible_journal.FILM_FUNCTIONS``),
#: and numba's on-disk cache keys a function by its file, name, code and types, not by its
#: wrappers: whichever compiled first was loaded by the other, and the wrapperless kernel
#: called from Python crashed the process (a segmentation fault)
INTERNAL = ("_mat3", "_mv3", "_cross", "_rodrigues", "_coefficients", "_interpolate", "_frame", "_relative",
            "_bearing_stretch", "_tilt", "_bearing_now", "assemble_into",
            "_quadratic", "_solve_motion", "_solve_spd", "_solve_ordered", "_solve_order", "_rows_below",
            "_solve_mass")
