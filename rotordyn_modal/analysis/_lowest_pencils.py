"""The full pencils of a lowest-modes sweep and their solves (``docs/theory.md`` section 17, step 3).

:class:`_Pencils`: ``Q(s) = s^2 M + s (C + Omega G + C_b(Omega)) + K + K_b(Omega)`` of every speed of
a sweep, the constant matrices once and the speed-dependent bearings' few entries per speed, each
pencil's entries on one pattern as one product, and ``Q(s)^-1 b`` batched: dense up to
``_DENSE_DOF`` coordinates, a banded LU with a border (a casing's coordinates) by Schur complement
where the pencils are banded (:func:`_band`), SuperLU otherwise. Dense and ``scipy.sparse``
matrices are served alike (:func:`_nonzero`, :func:`_block`, :func:`_diagonal`).
"""

from __future__ import annotations

import ctypes
import functools
import typing

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.linalg.lapack import zgbsv as _scipy_zgbsv

from .._blas import lapack
from . import _batches, _pencils

__all__: list[str] = []

#: pencils up to this many coordinates are solved dense and batched, larger banded ones by a banded
#: LU each (measured, 2,613 pencils: 36 coordinates dense 120 ms, banded 124 ms; 44 coordinates 221
#: against 120 ms)
_DENSE_DOF = 36

#: the Newton step's ``|x^H Q'(s) x| / |x|^2`` stands for the root's where the final vector's direction
#: is within this of the start's (``1 - cos^2`` of their angle: ``_Pencils.newton_chord``'s ``slope``)
_ALIGNED = 1e-8

#: a banded LU is taken where the band storage (2 kl + ku + 1 rows) is at most this part of n,
#: with at most ``_BORDER`` coordinates set apart as a border (a casing's six motions, mounts)
_BAND_SHARE, _BORDER = 2, 12


class _Pencils:
    """The full pencils ``Q(s) = s^2 M + s (C + Omega G + C_b(Omega)) + K + K_b(Omega)`` of every
    speed of a sweep: the constant matrices (n, n) and the speed-dependent bearings' few
    entries (S, nb), evaluated once for the sweep.

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (S,) [rad/s]
    """

    def __init__(self, stack, speeds):
        form = stack.forms[0]
        self.speeds = speeds
        if stack.sparse_constant is not None:     # a large model's, kept sparse (CSR)
            self.M, self.C, self.G, self.K = stack.sparse_constant
        else:
            self.M, self.C, self.G, self.K = form.matrices.M, form.matrices.C, stack.G[0], form.matrices.K
        n = self.M.shape[0]
        self.rows, self.cols, self.kb, self.cb = self._speed_entries(stack, speeds)
        self._values = None       # the matrices' entries on the pattern, made on first use
        self._layout = None       # the same in band storage (:meth:`_band_layout`), made on first use
        # the pattern's parts and the sparse products' matrices depend on the model alone (not on the
        # speeds): made once per stack (a small model's once, :func:`._stack.model_constants`)
        kept = stack.constants.setdefault("_lowest_patterns", {})
        key = (type(self).__name__, n, self.rows.tobytes(), self.cols.tobytes())
        if key not in kept:
            kept[key] = self._pattern_parts(n)
            for value in kept[key].values():
                for array in (value if isinstance(value, tuple) else (value,)):
                    if isinstance(array, np.ndarray):
                        array.flags.writeable = False
        self.__dict__.update(kept[key])
        # omega_max^2: the largest ratio of the stiffness's diagonal (with the bearings' at any speed) to the mass's
        diagonal = np.abs(_diagonal(self.K)).copy()
        on = self.rows == self.cols
        if on.any():
            np.maximum.at(diagonal, self.rows[on], np.abs(_diagonal(self.K)[self.rows[on]] + self.kb[:, on]).max(axis=0))
        mass = _diagonal(self.M)
        self.scale = float(np.max(diagonal / np.where(mass > 0, mass, np.inf)))
        self._stiffness = None        # M, C, G and K stacked as CSR, made on first use (:meth:`residual_times`)

    def _pattern_parts(self, n) -> dict:
        """The attributes that follow from the matrices and the bearing entries' places alone:
        the sparse LU's pattern (every entry of any of them, column by column: compressed-column
        order) and its ``indptr``, ``indices``, each bearing entry's place on it, the band, and the
        sparse matrices of the products ``Q'(s) x`` (a dense complex product of n x n per root cost
        more than the solves) with the bearings' scatter (n, nb)."""
        cols, rows = _pattern(self.M, self.C, self.G, self.K, self.rows, self.cols)
        sparse = [scipy.sparse.csr_matrix(matrix) for matrix in (self.M, self.C, self.G)]
        return {
            "pattern": (rows, cols),
            "indptr": np.concatenate([[0], np.cumsum(np.bincount(cols, minlength=n))]).astype(np.int32),
            "indices": rows.astype(np.int32),
            # its keys col * n + row ascend
            "bearing_at": np.searchsorted(cols * n + rows, self.cols * n + self.rows),
            "band": _band(rows, cols, n),
            "sparse": sparse,
            "_stacked": scipy.sparse.vstack(sparse, format="csr"),
            "scatter": scipy.sparse.csr_matrix((np.ones(len(self.rows)), (self.rows, np.arange(len(self.rows)))),
                                               shape=(n, len(self.rows))),
        }

    def _speed_entries(self, stack, speeds):
        """The entries of K and C that change with the speed (the bearings'): rows (nb,), columns
        (nb,), stiffness and damping (S, nb) each; a subclass adds entries of its own to the
        pattern and the completeness bound's coordinates (``_lowest_branches``)."""
        if stack.dependent:
            return _bearing_entries(stack.models[0], speeds)
        return np.zeros(0, int), np.zeros(0, int), np.zeros((len(speeds), 0)), np.zeros((len(speeds), 0))

    def more_terms(self, index, lam, x, precision=float, magnitude=False):
        """The pencil's terms beyond ``s^2 M + s (C + Omega G + C_b) + K + K_b`` times ``x`` (P, n)
        at roots ``lam`` (P,) in ``precision`` (with ``magnitude``: their entries' moduli times
        ``x``), for the residuals and the round-off estimate: none here (0); the Maxwell branches'
        rational stiffness in ``_lowest_branches``."""
        return 0.0

    def projected(self, first: int, basis):
        """``W^T (C + Omega G + C_b) W``, ``W^T (K + K_b) W`` at the speed ``first`` and ``W^T G W``
        of a basis ``W`` (n, m), (m, m) each, by products with the sparse matrices (a large model's)."""
        Wt = basis.T
        damping = Wt @ ((self.C + self.speeds[first] * self.G) @ basis)
        stiffness, gyroscopic = Wt @ (self.K @ basis), Wt @ (self.G @ basis)
        if len(self.rows):
            left, right = basis[self.rows].T, basis[self.cols]
            damping = damping + (left * self.cb[first]) @ right
            stiffness = stiffness + (left * self.kb[first]) @ right
        return damping, stiffness, gyroscopic

    def dense(self, index):
        """``C + Omega G + C_b`` and ``K + K_b`` of the speeds ``index`` (P,), (P, n, n) each."""
        damping = self.C + self.speeds[index, None, None] * self.G
        stiffness = np.array(np.broadcast_to(self.K, damping.shape))
        damping[:, self.rows, self.cols] += self.cb[index]
        stiffness[:, self.rows, self.cols] += self.kb[index]
        return damping, stiffness

    def derivative_times(self, index, lam, x):
        """``Q'(lam_p) x_p = (2 lam_p M + C + Omega G + C_b) x_p`` (P, n)."""
        n = x.shape[1]
        # one sparse product of [M; C; G] with every row (a column each), and the bearings' damping
        # scattered by a sparse product (a dense (nb, n) one cost as much as the rest together)
        products = self._stacked @ np.ascontiguousarray(x.T)                     # (3 n, P)
        out = 2 * lam * products[:n] + products[n:2 * n] + self.speeds[index] * products[2 * n:]
        if len(self.rows):
            out += self.scatter @ (self.cb[index] * x[:, self.cols]).T
        return out.T

    def solve(self, index, lam, rhs):
        """``Q(lam_p)^-1 rhs_p`` for every row: batched dense up to ``_DENSE_DOF`` coordinates; a
        banded LU each where the pencils are banded (a shaft on the ground: its elements couple
        neighbouring nodes), in threads; else a sparse LU each (SuperLU)."""
        n = self.M.shape[0]
        if n <= _DENSE_DOF:         # from the entries: a subclass's own terms (_lowest_branches) included
            rows, cols = self.pattern
            Q = np.zeros((len(lam), n * n), complex)
            Q[:, rows * n + cols] = self._entries(index, lam)
            return _pencils._solve(Q.reshape(-1, n, n), rhs[..., None])[..., 0]
        if self.band is not None:
            width = 2 * self.band.lower + self.band.upper + 1
            return _batches._threaded(self._banded_solve, index, lam, rhs, item_bytes=16 * n * (width + 2),
                                      thread_bytes=_batches.SOLVE_THREAD_BYTES)
        out = np.empty(rhs.shape, complex)
        for p in range(len(lam)):
            Q = scipy.sparse.csc_matrix((self._entries(index[p:p + 1], lam[p:p + 1])[0], self.indices, self.indptr),
                                        shape=(n, n))
            out[p] = scipy.sparse.linalg.splu(Q).solve(rhs[p])
        return out

    def newton_chord(self, index, lam, x, c, done):
        """One Newton step and one chord step (the same factorisation) from roots ``lam`` (P,) with
        vectors ``x`` (P, n), the scale fixed by ``c`` (P, n; None: ``conj(x)``, made a chunk at a
        time, the start's own length reused) as in ``_lowest_newton._refined``; no
        chord step where the Newton step is at most ``done`` times ``|s_1|`` (Newton's own
        rule for a root at round-off, ``_lowest_newton._STEP``: its second solve and residual are not
        needed).

        The Newton step: ``u = Q(s_0)^-1 Q'(s_0) x_0``, ``s_1 = s_0 - c^H x_0 / c^H u``,
        ``x_1 = u / c^H u``. The chord step is Newton's step on the bordered system
        ``Q(s) x = 0``, ``c^H x = c^H x_0`` with its Jacobian kept from ``s_0``: ``z = Q(s_0)^-1 Q(s_1) x_1``
        (the residual, one back-substitution), ``ds = -c^H z / c^H u``, ``s_2 = s_1 + ds``,
        ``x_2 = x_1 - z - ds u``. Its length is the error ``s_1`` left, and the error ``s_2`` leaves is
        about its square over the first step's (linear convergence at a rate of about the start's
        error): a root's accuracy told after one factorisation, not two. Where the pencils are
        banded without a border (a shaft on the ground); None otherwise.

        Returns
        -------
        lam : ndarray, shape (P,), complex; x : ndarray, shape (P, n), complex
        first, second : ndarray, shape (P,)
            The two steps' lengths relative to ``|s_2|`` (nan where a pencil was singular); where no
            chord step was taken, ``s_2 = s_1``, ``x_2 = x_1`` and ``second`` is 0.
        slope : ndarray, shape (P,)
            ``|x_0^H Q'(s_0) x_0| / |x_0|^2`` from the Newton step's own product, where ``x_2`` is
            within ``_ALIGNED`` of ``x_0``'s direction (``|x_2^H Q'(s_2) x_2| / |x_2|^2`` to about that,
            for the round-off estimate, ``_lowest_newton._roundoff``); nan elsewhere.
        """
        band = self.band
        n = self.M.shape[0]
        if n <= _DENSE_DOF or band is None or band.size != n or _lapack("zgbtrf") is None \
                or _lapack("zgbtrs") is None:
            return None
        width = 2 * band.lower + band.upper + 1
        if c is None:
            chord = functools.partial(self._banded_chord, c=None, done=done)
            return _batches._threaded(chord, index, lam, x, item_bytes=16 * n * (width + 4),
                                      thread_bytes=_batches.SOLVE_THREAD_BYTES)
        chord = functools.partial(self._banded_chord, done=done)
        return _batches._threaded(chord, index, lam, x, c, item_bytes=16 * n * (width + 4),
                                      thread_bytes=_batches.SOLVE_THREAD_BYTES)

    def _banded_chord(self, index, lam, x, c, done):
        """:meth:`newton_chord` of some rows: band storage in chunks, ``zgbtrf`` once per row and
        ``zgbtrs`` once, and again for the rows that take the chord step."""
        band = self.band
        n = self.M.shape[0]
        width = 2 * band.lower + band.upper + 1
        lam_out, x_out = np.empty(len(lam), complex), np.empty(x.shape, complex)
        first, second, slope = np.empty(len(lam)), np.empty(len(lam)), np.empty(len(lam))
        same = c is None
        for part in _batches.chunk_slices(len(lam), 16 * n * (width + 4), budget=2**24):
            rows, s0, x0 = index[part], lam[part], x[part]
            cc = x0.conj() if same else c[part]
            ab, _ = self._band_storage(rows, s0)
            pivots = np.empty((len(s0), n), np.int32)
            factored = _factored(band.lower, band.upper, ab, pivots)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                derivative = self.derivative_times(rows, s0, x0)
                start = cc if same else x0.conj()
                u = self._chord_solve(ab, pivots, factored, derivative)
                cu = np.einsum("pi,pi->p", cc, u)
                scale = np.einsum("pi,pi->p", cc, x0)
                step = scale / cu
                s1, x1 = s0 - step, u / cu[:, None]
                # the rows whose Newton step is not yet at round-off take the chord step
                chord = np.nonzero(~(np.abs(step) <= done * np.abs(s1)))[0]
                residual = self.residual_times(rows[chord], s1[chord], x1[chord])
                z = self._chord_solve(ab, pivots, factored, residual, chord)
                ds = -np.einsum("pi,pi->p", cc[chord], z) / cu[chord]
                s2, x2 = s1.copy(), x1
                s2[chord] = s1[chord] + ds
                x2[chord] = x1[chord] - z - ds[:, None] * u[chord]
                lam_out[part], x_out[part] = s2, x2
                first[part], second[part] = np.abs(step) / np.abs(s2), 0.0
                second[part][chord] = np.abs(ds) / np.abs(s2[chord])
                length = (scale if same else np.einsum("pi,pi->p", start, x0)).real
                aligned = np.abs(np.einsum("pi,pi->p", start, x2)) ** 2 \
                    >= (1 - _ALIGNED) * length * np.einsum("pi,pi->p", x2.conj(), x2).real
                slope[part] = np.where(aligned, np.abs(np.einsum("pi,pi->p", start, derivative)) / length, np.nan)
        return lam_out, x_out, first, second, slope

    def _chord_solve(self, ab, pivots, factored, rhs, which=None):
        """``Q^-1 rhs`` (P, n) from the banded LU factors ``ab`` (P, size, width) and ``pivots``
        (P, n) of ``zgbtrf`` (with ``which`` (R,): of the rows ``which`` of them, ``rhs`` (R, n));
        nan where a pencil was singular (``factored`` False)."""
        band = self.band
        if self.__dict__.get("_in_order") is None:      # the band in the coordinates' own order (a shaft)
            self._in_order = bool(np.array_equal(band.order, np.arange(len(band.order))))
        # a copy in the band's order (its own where that is the coordinates': no gather and scatter)
        y = np.array(rhs, dtype=complex, order="C") if self._in_order else np.ascontiguousarray(rhs[:, band.order])
        _back_solved(band.lower, band.upper, ab, pivots, y, which)
        y[~(factored if which is None else factored[which])] = np.nan
        if self._in_order:
            return y
        out = np.empty(y.shape, complex)
        out[:, band.order] = y
        return out

    def residual_times(self, index, lam, x):
        """``Q(lam_p) x_p`` (P, n) in double precision (``_lowest_newton._residuals`` is the
        extended-precision one of the polish)."""
        n = x.shape[1]
        if self._stiffness is None:       # [M; C; G; K] as CSR: one product (and one copy of the rows) for all four
            self._stiffness = scipy.sparse.vstack([self._stacked, scipy.sparse.csr_matrix(self.K)], format="csr")
        products = self._stiffness @ np.ascontiguousarray(x.T)                   # (4 n, P)
        out = lam * (lam * products[:n] + products[n:2 * n] + self.speeds[index] * products[2 * n:3 * n])
        out += products[3 * n:]
        if len(self.rows):
            out += self.scatter @ ((lam[:, None] * self.cb[index] + self.kb[index]) * x[:, self.cols]).T
        return out.T + self.more_terms(index, lam, x)

    @property
    def values(self) -> np.ndarray:
        """M, C, G and K on the pattern (nnz, 4), made on first use: every row's entries are one
        product with them (:meth:`_entries`)."""
        if self._values is None:
            rows, cols = self.pattern
            self._values = np.ascontiguousarray(np.stack(
                [_entries_at(matrix, rows, cols) for matrix in (self.M, self.C, self.G, self.K)], axis=-1))
        return self._values

    def _entries(self, index, lam):
        """The pencils' entries on the pattern, (P, nnz) complex: the coefficients ``s^2, s, s Omega, 1``
        of each row (real and imaginary parts, (P, 4, 2)) times the pattern's M, C, G and K (nnz, 4),
        one product (a quarter of the time of the terms summed as complex arrays)."""
        data = np.matmul(self.values, _coefficients(lam, self.speeds[index])).view(complex)[..., 0]  # (P, nnz)
        data[:, self.bearing_at] += lam[:, None] * self.cb[index] + self.kb[index]
        return data

    def _banded_solve(self, index, lam, rhs):
        """:meth:`solve` by LAPACK's banded LU with partial pivoting (``zgbsv``), one row at a
        time, and a Schur complement for the border (a casing's coordinates), batched. The band
        storage of a chunk of rows is one product (:meth:`_band_storage`), not a scatter of the
        pattern's entries (which cost a third of the solve)."""
        band = self.band
        n, k = self.M.shape[0], len(band.order) - band.size
        size, width = band.size, 2 * band.lower + band.upper + 1
        out = np.empty(rhs.shape, complex)
        for part in _batches.chunk_slices(len(lam), 16 * n * (width + 3 * k + 2), budget=2**24):
            ab, border = self._band_storage(index[part], lam[part])
            count = len(ab)
            b = rhs[part][:, band.order]
            # B^-1 [b_1, E]: one banded solve with k + 1 right-hand sides each
            y = np.empty((count, k + 1, size), complex)
            y[:, 0] = b[:, :size]
            if k:
                # the border's columns (every row) and rows (the band's columns), (P, n, k) and (P, k, size)
                columns, rows = np.zeros((count, n, k), complex), np.zeros((count, k, size), complex)
                columns[:, band.place_rows[band.right], band.cols[band.right] - size] = border[:, :band.right.sum()]
                rows[:, band.place_rows[band.below] - size, band.cols[band.below]] = border[:, band.right.sum():]
                y[:, 1:] = np.swapaxes(columns[:, :size], 1, 2)
            y[_solved_rows(band.lower, band.upper, ab, y) != 0] = np.nan
            solution = np.empty((count, n), complex)
            solution[:, :size] = y[:, 0]
            if k:
                schur = columns[:, size:] - rows @ np.swapaxes(y[:, 1:], 1, 2)                 # (P, k, k)
                border = _pencils._solve(schur, (b[:, size:] - np.einsum("pki,pi->pk", rows, y[:, 0]))[..., None])[..., 0]
                solution[:, size:] = border
                solution[:, :size] -= np.einsum("pki,pk->pi", y[:, 1:], border)
            out[part][:, band.order] = solution
        return out

    def _band_storage(self, index, lam):
        """LAPACK's band storage of the pencils of rows ``index``, ``lam`` (P,): (P, size, width)
        complex, C-ordered (each ``[p].T`` is the Fortran array ``zgbsv`` takes), and the border's
        entries (P, right + below) (the entries in its columns, then in its rows, in the pattern's
        order). The band's entries are the coefficients ``s^2, s, s Omega, 1`` times M, C, G and K
        laid out in band storage once (:meth:`_band_layout`): one product, as :meth:`_entries`; a
        subclass with terms of its own (``_lowest_branches``) scatters its entries instead."""
        band = self.band
        size, width = band.size, 2 * band.lower + band.upper + 1
        if type(self)._entries is not __class__._entries:      # a subclass's own terms (``__class__``: _Pencils)
            data = self._entries(index, lam)
            ab = np.zeros((len(lam), size, width), complex)
            ab[:, band.cols[band.inside], band.rows[band.inside]] = data[:, band.inside]
            return ab, np.hstack([data[:, band.right], data[:, band.below]])
        layout, bearing_in, at_in, outside, bearing_out, at_out = self._band_layout()
        coefficients = _coefficients(lam, self.speeds[index])
        ab = np.matmul(layout, coefficients).view(complex)[..., 0]                 # (P, size * width)
        speed_part = lam[:, None] * self.cb[index] + self.kb[index]
        ab[:, at_in] += speed_part[:, bearing_in]
        border = np.matmul(outside, coefficients).view(complex)[..., 0]
        border[:, at_out] += speed_part[:, bearing_out]
        return ab.reshape(len(lam), size, width), border

    def _band_layout(self):
        """M, C, G and K in LAPACK's band storage, (size * width, 4), zero off the pattern; the
        bearing entries in the band (which, where in it) and the border's entries (right, then
        below: their M, C, G, K (e, 4) and which bearing entries fall where among them). Made on
        first use."""
        if self._layout is None:
            band = self.band
            width = 2 * band.lower + band.upper + 1
            flat = np.full(len(band.inside), -1)
            flat[band.inside] = band.cols[band.inside] * width + band.rows[band.inside]
            layout = np.zeros((band.size * width, 4))
            layout[flat[band.inside]] = self.values[band.inside]
            outside = np.concatenate([np.nonzero(band.right)[0], np.nonzero(band.below)[0]])
            place = np.full(len(band.inside), -1)
            place[outside] = np.arange(len(outside))
            bearing_in = np.nonzero(band.inside[self.bearing_at])[0]
            bearing_out = np.nonzero(~band.inside[self.bearing_at])[0]
            self._layout = (layout, bearing_in, flat[self.bearing_at[bearing_in]],
                            np.ascontiguousarray(self.values[outside]), bearing_out, place[self.bearing_at[bearing_out]])
        return self._layout


class _Zgbsv:
    """LAPACK's ``zgbsv`` called as scipy's wrapper is, ``(kl, ku, ab, b, overwrite_ab, overwrite_b) ->
    (lu, pivots, x, info)``, through ``ctypes`` where both arrays are overwritten in place (complex,
    Fortran-ordered, as :meth:`_Pencils._banded_solve` gives them): ``ctypes`` lets other threads run
    during the call, scipy's wrapper holds the GIL (the threads sharing a sweep's banded solves
    waited for each other: measured, a second thread ran only after the first's 3,000 solves).
    Other arrays, or where the routine cannot be had from ``scipy.linalg.cython_lapack``: scipy's."""

    def __call__(self, kl, ku, ab, b, overwrite_ab=0, overwrite_b=0):
        function = _lapack("zgbsv")
        if (function is None or not (overwrite_ab and overwrite_b) or ab.dtype != complex or b.dtype != complex
                or ab.ndim != 2 or b.ndim != 2 or not (ab.flags.f_contiguous and b.flags.f_contiguous)
                or ab.shape[0] != 2 * kl + ku + 1 or ab.shape[1] != b.shape[0] or not ab.flags.writeable
                or not b.flags.writeable):
            return _scipy_zgbsv(kl, ku, ab, b, overwrite_ab=overwrite_ab, overwrite_b=overwrite_b)
        n = ab.shape[1]
        pivots, info = np.empty(n, np.int32), ctypes.c_int(0)
        sizes = _sizes(n, kl, ku, b.shape[1], ab.shape[0])
        function(sizes[0], sizes[1], sizes[2], sizes[3], ab.ctypes.data, sizes[4], pivots.ctypes.data, b.ctypes.data,
                 sizes[0], ctypes.byref(info))
        pivots -= 1                     # 0-based, as scipy's
        return ab, pivots, b, info.value


_zgbsv = _Zgbsv()


_lapack = lapack       # LAPACK's zgbsv, zgbtrf, zgbtrs as ctypes functions (:func:`.._blas.lapack`)


_NO_TRANSPOSE = ctypes.c_char(b"N")


def _rows_at(array, shape):
    """The address of ``array[0]`` and the step between its rows, where ``array`` (P, ...) holds
    C-ordered rows of ``shape`` one after the other at a fixed step (each row's transpose the
    Fortran array LAPACK takes), else None."""
    if array.shape[1:] != shape or array.dtype not in (np.complex128, np.int32) or len(array) == 0:
        return None
    item = array.itemsize
    inner = [item]
    for size in reversed(shape[1:]):
        inner.insert(0, inner[0] * size)
    if tuple(array.strides[1:]) != tuple(inner) or array.strides[0] < inner[0] * shape[0]:
        return None
    return array.ctypes.data, array.strides[0]


def _factored(kl: int, ku: int, ab, pivots) -> np.ndarray:
    """``zgbtrf`` of every row of ``ab`` (P, n, 2 kl + ku + 1) in place (each ``ab[p].T`` LAPACK's
    band storage), ``pivots`` (P, n) int32 filled: (P,) True where factored (False where singular).
    One loop over raw addresses: the rows' views and ``ctypes`` objects of :func:`_gbtrf` cost a
    fifth of each factorisation (measured at 224 coordinates, bandwidth 7)."""
    P, n, width = ab.shape
    where, pivot_at = _rows_at(ab, (n, width)), _rows_at(pivots, (n,))
    if where is None or pivot_at is None:
        return np.array([_gbtrf(kl, ku, ab[p].T, pivots[p]) == 0 for p in range(P)], bool)
    function, sizes = _lapack("zgbtrf"), _sizes(n, kl, ku, width)
    info = ctypes.c_int(0)
    status = ctypes.byref(info)
    (start, step), (pivot_start, pivot_step) = where, pivot_at
    out = np.empty(P, bool)
    for p in range(P):
        function(sizes[0], sizes[0], sizes[1], sizes[2], start + p * step, sizes[3], pivot_start + p * pivot_step,
                 status)
        out[p] = info.value == 0
    return out


def _back_solved(kl: int, ku: int, ab, pivots, y, which=None) -> None:
    """``zgbtrs`` of every row: ``y`` (P, n) overwritten by the solutions of the systems whose
    factors :func:`_factored` left in ``ab`` (P, n, width) and ``pivots`` (P, n) (rows that were
    not factored give what LAPACK gives: the caller marks them); with ``which`` (R,), of those
    rows only, ``y`` (R, n)."""
    P, n, width = ab.shape
    which = np.arange(P) if which is None else np.asarray(which)
    where, pivot_at, rhs_at = _rows_at(ab, (n, width)), _rows_at(pivots, (n,)), _rows_at(y, (n,))
    if where is None or pivot_at is None or rhs_at is None:
        for r, p in enumerate(which):
            _gbtrs(kl, ku, ab[p].T, pivots[p], y[r])
        return
    function, sizes = _lapack("zgbtrs"), _sizes(n, kl, ku, 1, width)
    info = ctypes.c_int(0)
    status, transpose = ctypes.byref(info), ctypes.byref(_NO_TRANSPOSE)
    (start, step), (pivot_start, pivot_step), (rhs_start, rhs_step) = where, pivot_at, rhs_at
    for r, p in enumerate(which.tolist()):
        function(transpose, sizes[0], sizes[1], sizes[2], sizes[3], start + p * step, sizes[4],
                 pivot_start + p * pivot_step, rhs_start + r * rhs_step, sizes[0], status)


def _solved_rows(kl: int, ku: int, ab, y) -> np.ndarray:
    """``zgbsv`` of every row: ``ab`` (P, size, width) factored in place, ``y`` (P, r, size)
    overwritten by the solutions (each ``y[p].T`` the Fortran right-hand sides); LAPACK's ``info``
    (P,) (0: solved). One loop over raw addresses where the arrays allow, else :data:`_zgbsv` per row."""
    P, n, width = ab.shape
    function = _lapack("zgbsv")
    where, rhs_at = _rows_at(ab, (n, width)), _rows_at(y, y.shape[1:])
    if function is None or where is None or rhs_at is None or y.shape[2] != n:
        return np.array([_zgbsv(kl, ku, ab[p].T, y[p].T, overwrite_ab=1, overwrite_b=1)[3] for p in range(P)])
    sizes = _sizes(n, kl, ku, y.shape[1], width)
    pivots, info = np.empty(n, np.int32), ctypes.c_int(0)
    status, pivot_at = ctypes.byref(info), pivots.ctypes.data
    (start, step), (rhs_start, rhs_step) = where, rhs_at
    out = np.empty(P, int)
    for p in range(P):
        function(sizes[0], sizes[1], sizes[2], sizes[3], start + p * step, sizes[4], pivot_at, rhs_start + p * rhs_step,
                 sizes[0], status)
        out[p] = info.value
    return out


def _gbtrf(kl: int, ku: int, ab, pivots) -> int:
    """LAPACK's banded LU ``zgbtrf`` in place: ``ab`` (2 kl + ku + 1, n) complex, Fortran-ordered
    (a row of :meth:`_Pencils._band_storage`, transposed), ``pivots`` (n,) int32 (1-based, as
    ``zgbtrs`` takes them); LAPACK's ``info`` (0: factored, > 0: singular)."""
    n, info = ab.shape[1], ctypes.c_int(0)
    sizes = _sizes(n, kl, ku, ab.shape[0])
    _lapack("zgbtrf")(sizes[0], sizes[0], sizes[1], sizes[2], ab.ctypes.data, sizes[3], pivots.ctypes.data,
                      ctypes.byref(info))
    return info.value


def _gbtrs(kl: int, ku: int, ab, pivots, b) -> None:
    """``zgbtrs``: ``b`` (n,) complex, contiguous, overwritten by the solution of the system whose
    factors :func:`_gbtrf` left in ``ab`` and ``pivots``."""
    n, info = ab.shape[1], ctypes.c_int(0)
    sizes = _sizes(n, kl, ku, 1, ab.shape[0])
    _lapack("zgbtrs")(ctypes.byref(_NO_TRANSPOSE), sizes[0], sizes[1], sizes[2], sizes[3], ab.ctypes.data,
                      sizes[4], pivots.ctypes.data, b.ctypes.data, sizes[0], ctypes.byref(info))


@functools.lru_cache(maxsize=64)
def _sizes(*values):
    """``ctypes`` references to the integers ``values`` (read only by LAPACK), made once for each
    set of a sweep's sizes (their making cost a tenth of a small solve)."""
    return tuple(ctypes.byref(ctypes.c_int(int(value))) for value in values)


def _coefficients(lam, speeds):
    """The pencil's coefficients ``s^2, s, s Omega, 1`` of roots ``lam`` at ``speeds`` (P,) each, as
    real and imaginary parts (P, 4, 2): the entries of M, C, G and K (e, 4) times them are the
    pencil's (P, e, 2), read as complex."""
    coefficients = np.empty((len(lam), 4, 2))
    for term, value in enumerate((lam * lam, lam, lam * speeds)):
        coefficients[:, term, 0], coefficients[:, term, 1] = value.real, value.imag
    coefficients[:, 3] = (1.0, 0.0)
    return coefficients


def _band(rows, cols, n):
    """The band of a pattern ``(rows, cols)`` (nnz,) each: a border of at most ``_BORDER``
    coordinates (a casing's, coupled to distant nodes) set apart, the others in their own order
    or reverse Cuthill-McKee's, whichever is narrower: ``_Band``, or None where the band is too
    wide to pay."""
    border = []
    for _ in range(_BORDER + 1):
        best = _narrowest(rows, cols, n, border)
        if (2 * best.lower + best.upper + 1) * _BAND_SHARE <= n:
            return best
        if len(border) == _BORDER:
            break
        # the coordinate coupled farthest in the band's order goes to the border
        keep = np.isin(rows, border, invert=True) & np.isin(cols, border, invert=True)
        where = best.place_rows[keep], best.cols[keep]
        reach = np.zeros(n)
        np.maximum.at(reach, best.order[where[0]], np.abs(where[0] - where[1]))
        reach[border] = -1.0
        border.append(int(np.argmax(reach)))
    return _densest_border(rows, cols, n)


def _densest_border(rows, cols, n):
    """:func:`_band` with the (at most ``_BORDER``) coordinates of the most entries as the border,
    where the greedy choice by reach found none: a casing's motions couple to every node of a
    shaft, and with reverse Cuthill-McKee placing them mid-band a shaft's own coordinate may reach
    as far (a fan shaft of 400 coordinates in the gear machine's casing: the greedy border took
    shaft coordinates after two of the casing's and left a SuperLU per root, 3x the time)."""
    degree = np.bincount(rows, minlength=n)
    border = [int(i) for i in np.argsort(-degree, kind="stable")[:_BORDER] if degree[i] > 2 * np.median(degree)]
    for count in range(1, len(border) + 1):
        best = _narrowest(rows, cols, n, border[:count])
        if (2 * best.lower + best.upper + 1) * _BAND_SHARE <= n:
            return best
    return None


def _narrowest(rows, cols, n, border):
    """:func:`_band` with the coordinates ``border`` set apart (last)."""
    import scipy.sparse.csgraph

    inner = np.setdiff1d(np.arange(n), border)
    keep = np.isin(rows, inner) & np.isin(cols, inner)
    graph = scipy.sparse.csr_matrix((np.ones(int(keep.sum())), (rows[keep], cols[keep])), shape=(n, n))
    graph = (graph + graph.T)[inner][:, inner]
    best = None
    for order in (inner, inner[scipy.sparse.csgraph.reverse_cuthill_mckee(graph.tocsr(), symmetric_mode=True)]):
        order = np.concatenate([order, np.asarray(border, int)])
        place = np.empty(n, int)
        place[order] = np.arange(n)
        i, j = place[rows], place[cols]
        size = len(inner)
        inside = (i < size) & (j < size)
        lower = int(max(0, np.max(i - j, where=inside, initial=0)))
        upper = int(max(0, np.max(j - i, where=inside, initial=0)))
        if best is None or lower + upper < best.lower + best.upper:
            best = _Band(lower, upper, order, size, i, j, lower + upper + i - j, inside, j >= size, (i >= size) & (j < size))
    return best


class _Band(typing.NamedTuple):
    lower: int
    upper: int
    order: np.ndarray          # (n,) the band's coordinates, then the border's: q[order]
    size: int                  # coordinates in the band
    place_rows: np.ndarray     # (nnz,) each entry's row in that order
    cols: np.ndarray           # (nnz,) each entry's column in that order
    rows: np.ndarray           # (nnz,) each entry's row in LAPACK's band storage
    inside: np.ndarray         # (nnz,) bool: the entry is in the band
    right: np.ndarray          # (nnz,) bool: in a border column
    below: np.ndarray          # (nnz,) bool: in a border row, a band column


def _pattern(M, C, G, K, bearing_rows, bearing_cols):
    """Where any of ``M, C, G, K`` (dense, or ``scipy.sparse`` for a large model) or a bearing
    entry is nonzero: ``(cols, rows)`` (nnz,) each, column by column, rows ascending in each."""
    if scipy.sparse.issparse(M):
        n = M.shape[0]
        found = (abs(M) + abs(C) + abs(G) + abs(K)).tocoo()
        keys = np.unique(np.concatenate([found.col[found.data != 0].astype(np.int64) * n + found.row[found.data != 0],
                                         bearing_cols.astype(np.int64) * n + bearing_rows]))
        return keys // n, keys % n
    pattern = (M != 0) | (C != 0) | (G != 0) | (K != 0)
    pattern[bearing_rows, bearing_cols] = True
    return np.nonzero(pattern.T)


def _entries_at(matrix, rows, cols) -> np.ndarray:
    """``matrix[rows, cols]`` (nnz,) of a dense or ``scipy.sparse`` matrix."""
    if scipy.sparse.issparse(matrix):
        return np.asarray(matrix.tocsr()[rows, cols]).reshape(-1)
    return matrix[rows, cols]


def _diagonal(matrix) -> np.ndarray:
    """The diagonal (n,) of a dense or ``scipy.sparse`` matrix."""
    return matrix.diagonal() if scipy.sparse.issparse(matrix) else np.diagonal(matrix)


def _nonzero(matrix):
    """``numpy.nonzero`` of a dense or ``scipy.sparse`` matrix: (rows, cols)."""
    if scipy.sparse.issparse(matrix):
        coo = matrix.tocoo()
        keep = coo.data != 0
        return coo.row[keep], coo.col[keep]
    return np.nonzero(matrix)


def _block(matrix, local) -> np.ndarray:
    """``matrix[local][:, local]`` dense (|L|, |L|) of a dense or ``scipy.sparse`` matrix."""
    if scipy.sparse.issparse(matrix):
        return matrix.tocsr()[local][:, local].toarray()
    return matrix[np.ix_(local, local)]


def _bearing_entries(model, speeds):
    """The speed-dependent bearings' entries of K and C: positions (nb,), (nb,) and values
    (S, nb), (S, nb) at every speed (the rows and columns a bearing's relative motion touches)."""
    from ..assembly import bearing_coefficients, bearing_motion

    n = model.dofs.n
    keys, stiffness, damping = [], [], []
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            continue
        k6, c6 = bearing_coefficients(model, bearing, speeds)
        where, moves = bearing_motion(model, bearing)
        used = np.nonzero(np.any(moves != 0, axis=0))[0]
        part = moves[:, used]
        index = np.arange(n)[where][used]
        keys.append((index[:, None] * n + index[None, :]).reshape(-1))
        stiffness.append((part.T @ k6 @ part).reshape(len(speeds), -1))
        damping.append((part.T @ c6 @ part).reshape(len(speeds), -1))
    if not keys:
        return np.zeros(0, int), np.zeros(0, int), np.zeros((len(speeds), 0)), np.zeros((len(speeds), 0))
    unique, inverse = np.unique(np.concatenate(keys), return_inverse=True)
    kb, cb = np.zeros((len(speeds), len(unique))), np.zeros((len(speeds), len(unique)))
    np.add.at(kb, (slice(None), inverse), np.hstack(stiffness))
    np.add.at(cb, (slice(None), inverse), np.hstack(damping))
    # the entries some speed's coefficients make nonzero (a bearing's tilt coordinates carry none)
    used = np.any(kb != 0, axis=0) | np.any(cb != 0, axis=0)
    return unique[used] // n, unique[used] % n, kb[:, used], cb[:, used]
