"""Shift matrices of seed 000 (eqs. 1-11) and the motion of points of a rigid body."""

from __future__ import annotations

import numpy as np
import pytest

from rotordyn_modal.model.geometry import (point_force_column, point_motion_row, point_motion_rows, shift_cross,
                                     shift_matrices, shift_matrix, skew)

RNG = np.random.default_rng(11)
POINTS = RNG.uniform(-2, 2, (5, 3))


def test_skew_is_the_cross_product():
    a, b = RNG.standard_normal((2, 3))
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b), atol=1e-15)
    stacked = skew(RNG.standard_normal((4, 2, 3)))
    assert stacked.shape == (4, 2, 3, 3)
    np.testing.assert_array_equal(stacked, -np.swapaxes(stacked, -1, -2))


def test_eq2_layout_of_A_PO():
    p, o = np.array([1.0, 2.0, 3.0]), np.array([0.5, -1.0, 4.0])
    dx, dy, dz = p - o
    expected = np.array([[0, -dz, dy], [dz, 0, -dx], [-dy, dx, 0]])
    np.testing.assert_array_equal(shift_cross(p, o), expected)


@pytest.mark.parametrize("p, o", [(POINTS[0], POINTS[1]), (POINTS[2], POINTS[3])])
def test_eq3_antisymmetry(p, o):
    A = shift_cross(p, o)
    np.testing.assert_array_equal(A.T, -A)
    np.testing.assert_allclose(-A, shift_cross(o, p), atol=1e-15)


def test_eq7_moves_forces_and_moments():
    """T_P = B_PO T_O: same force, moment about P = C_O + (O - P) x F."""
    p, o = POINTS[0], POINTS[1]
    force, moment = RNG.standard_normal((2, 3))
    moved = shift_matrix(p, o) @ np.concatenate([force, moment])
    np.testing.assert_allclose(moved[:3], force, atol=1e-15)
    np.testing.assert_allclose(moved[3:], moment + np.cross(o - p, force), atol=1e-14)


def test_eq10_successive_shifts_and_eq11_inverse():
    n, p, o = POINTS[:3]
    np.testing.assert_allclose(shift_matrix(n, p) @ shift_matrix(p, o), shift_matrix(n, o), atol=1e-14)
    np.testing.assert_allclose(np.linalg.inv(shift_matrix(p, o)), shift_matrix(o, p), atol=1e-14)
    np.testing.assert_allclose(shift_matrix(p, o) @ shift_matrix(o, p), np.eye(6), atol=1e-14)
    np.testing.assert_array_equal(shift_matrix(p, p), np.eye(6))


def test_transpose_moves_small_motions():
    """Seed eq. 60: the motion of a rigid body at P is B_OP^T times its motion at O,
    u_P = u_O + theta x (P - O); and work is invariant: T_O . q_O = T_P . q_P."""
    p, o = POINTS[3], POINTS[4]
    u, theta = RNG.standard_normal((2, 3))
    q_o = np.concatenate([u, theta])
    q_p = shift_matrix(o, p).T @ q_o
    np.testing.assert_allclose(q_p[:3], u + np.cross(theta, p - o), atol=1e-14)
    np.testing.assert_allclose(q_p[3:], theta, atol=0)
    t_o = RNG.standard_normal(6)
    t_p = shift_matrix(p, o) @ t_o
    assert t_p @ q_p == pytest.approx(t_o @ q_o, rel=1e-13)


def test_point_rows_and_columns():
    """The row gives the displacement of P along d; the column is the generalized force at
    the reference of a unit force along d at P (force d, moment (P - S) x d)."""
    point, reference = POINTS[0], POINTS[1]
    d = np.array([0.3, -0.4, 0.5])
    q = RNG.standard_normal(6)
    row = point_motion_row(point, reference, d)
    displacement = q[:3] + np.cross(q[3:], point - reference)
    assert row @ q == pytest.approx(d @ displacement, rel=1e-13)
    column = point_force_column(point, reference, d)
    np.testing.assert_allclose(column[:3], d, atol=0)
    np.testing.assert_allclose(column[3:], np.cross(point - reference, d), atol=1e-15)
    np.testing.assert_allclose(column, shift_matrix(reference, point) @ np.concatenate([d, np.zeros(3)]),
                               atol=1e-15)


def test_rows_of_many_points_give_each_displacement():
    """Each row of ``point_motion_rows`` gives its point's displacement ``u + theta x (P - S)``
    along its direction, for any rigid motion ``q = [u, theta]``."""
    reference = POINTS[0]
    directions = RNG.standard_normal((len(POINTS), 3))
    rows = point_motion_rows(POINTS, reference, directions)
    assert rows.shape == (len(POINTS), 6)
    for _ in range(3):
        q = RNG.standard_normal(6)
        displacements = q[:3] + np.cross(q[3:], POINTS - reference)
        np.testing.assert_allclose(rows @ q, np.einsum("pi,pi->p", directions, displacements), rtol=1e-13, atol=1e-14)
    assert point_motion_rows([], reference, []).shape == (0, 6)


def test_shift_matrices_are_eq2_of_each_point():
    """The stacked shift matrices are ``[[I, 0], [-skew(P - O), I]]`` of each point (eq. 2)."""
    stacked = shift_matrices(POINTS[0], POINTS)
    for matrix, point in zip(stacked, POINTS):
        expected = np.block([[np.eye(3), np.zeros((3, 3))], [-skew(POINTS[0] - point), np.eye(3)]])
        np.testing.assert_array_equal(matrix, expected)
