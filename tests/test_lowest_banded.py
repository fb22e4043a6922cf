"""The banded solves of a lowest-modes sweep (``_lowest_pencils._Pencils._banded_solve``, issue 28,
speed): LAPACK's banded LU with partial pivoting and the border's Schur complement. Truth from
outside the code under test: numpy's dense solve and the residual of each solution in the dense
matrix built here, and NaN for a singular pencil."""

from __future__ import annotations

import numpy as np

from rotordyn_modal.analysis._lowest_pencils import _band, _Pencils


def _banded(rng, count, n, kl, ku, diagonal=1.0):
    """Random complex band matrices (count, n, n) with the diagonal scaled by ``diagonal``."""
    i, j = np.indices((n, n))
    inside = (i - j <= kl) & (j - i <= ku)
    A = np.zeros((count, n, n), complex)
    A[:, inside] = rng.normal(size=(count, inside.sum())) + 1j * rng.normal(size=(count, inside.sum()))
    A[:, np.arange(n), np.arange(n)] *= diagonal
    return A


def _relative_residual(A, x, b):
    return np.linalg.norm(A @ x - b, axis=(1, 2)) / (np.linalg.norm(A, axis=(1, 2)) * np.linalg.norm(x, axis=(1, 2)))


class _Matrices(_Pencils):
    """Given pencils (P, n, n) served as a sweep's: their entries on the pattern of all of them."""

    def __init__(self, Q):
        n = Q.shape[1]
        cols, rows = np.nonzero(np.any(Q != 0, axis=0).T)       # column by column, rows ascending
        self.M = np.zeros((n, n))
        self.pattern = rows, cols
        self.band = _band(rows, cols, n)
        self.data = Q[:, rows, cols]

    def _entries(self, index, lam):
        return self.data[index]


def test_banded_solve_with_a_border_equals_the_dense_solve():
    """A band (a shaft's nodes) with a zero diagonal (every pivot from below it) and two coordinates
    coupled to every one (a casing's) set apart as the border and solved by the Schur complement;
    one singular pencil gives NaN, the others stay finite."""
    rng = np.random.default_rng(5)
    count, n, kl, ku = 12, 60, 2, 4
    Q = _banded(rng, count, n, kl, ku, diagonal=0.0)
    for coordinate in (6, 30):
        Q[:, coordinate, :] = rng.normal(size=(count, n)) + 1j * rng.normal(size=(count, n))
        Q[:, :, coordinate] = rng.normal(size=(count, n)) + 1j * rng.normal(size=(count, n))
    pencils = _Matrices(Q)
    assert pencils.band is not None and pencils.band.size < n
    assert {6, 30} <= set(pencils.band.order[pencils.band.size:].tolist())
    rhs = rng.normal(size=(count, n)) + 1j * rng.normal(size=(count, n))
    x = pencils._banded_solve(np.arange(count), np.zeros(count), rhs)
    exact = np.linalg.solve(Q, rhs[..., None])[..., 0]
    error = np.linalg.norm(x - exact, axis=1) / np.linalg.norm(exact, axis=1)
    assert np.all(error < 1e-14 * np.linalg.cond(Q))
    assert _relative_residual(Q, x[..., None], rhs[..., None]).max() < 1e-12

    singular = Q.copy()
    singular[4] = Q[4]
    singular[4][:, 17] = 0.0
    pencils = _Matrices(singular)
    x = pencils._banded_solve(np.arange(count), np.zeros(count), rhs)
    assert np.isnan(x[4]).all()
    assert np.isfinite(np.delete(x, 4, axis=0)).all()
