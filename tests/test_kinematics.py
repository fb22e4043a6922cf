"""Large-rotation kinematics (seed 001): identities, finite differences, the split."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rotordyn_modal.simulation import kinematics as kin

RNG = np.random.default_rng(20180522)
E = np.array([1.0, 0.0, 0.0])


def _random_vectors(count, largest):
    directions = RNG.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    return directions * RNG.uniform(0, largest, size=count)[:, None]


ANGLES = [0.0, 1e-9, 1e-4, 0.049, 0.051, 0.5, 2.0, 3.1, 6.0]


@pytest.mark.parametrize("angle", ANGLES)
def test_rotation_tensor_is_scipys_rotation_and_orthogonal(angle):
    for direction in _random_vectors(5, 1.0):
        v = angle * direction / np.linalg.norm(direction)
        L = kin.rotation_tensor(v)
        np.testing.assert_allclose(L @ L.T, np.eye(3), atol=1e-15)
        np.testing.assert_allclose(L, Rotation.from_rotvec(v).as_matrix(), atol=2e-16 * max(1, angle) * 4)
        assert np.linalg.det(L) == pytest.approx(1.0, abs=1e-14)


@pytest.mark.parametrize("angle", ANGLES)
def test_zhilin_inverse_is_the_inverse(angle):
    for direction in _random_vectors(5, 1.0):
        v = angle * direction / np.linalg.norm(direction)
        B = kin.zhilin_tensor(v)
        np.testing.assert_allclose(kin.zhilin_inverse(v) @ B, np.eye(3), atol=1e-13 * max(1, 1 / (2 * np.pi - angle)))
        np.testing.assert_allclose(B @ v, v, atol=1e-15)
        np.testing.assert_allclose(B, kin.rotation_tensor(v) @ B.T, atol=1e-15)


def test_series_and_closed_forms_meet_at_the_switch():
    v = np.array([0.3, -0.4, 1.2])
    v *= kin.SERIES_ANGLE / np.linalg.norm(v)
    below, above = v * (1 - 1e-12), v * (1 + 1e-12)
    for function in (kin.rotation_tensor, kin.zhilin_tensor, kin.zhilin_inverse):
        np.testing.assert_allclose(function(below), function(above), atol=1e-14)
    w = np.array([0.2, 0.7, -0.1])
    np.testing.assert_allclose(kin.zhilin_derivative(below, w), kin.zhilin_derivative(above, w), atol=1e-11)


@pytest.mark.parametrize("angle", [1e-6, 0.03, 0.8, 2.5, 5.5])
def test_angular_velocity_is_zhilin_times_rate_by_finite_differences(angle):
    """omega = B(v) v' where skew(omega) = L' L^T, L' by central differences."""
    for v0, rate in zip(_random_vectors(4, 1.0), _random_vectors(4, 2.0)):
        v0 = angle * v0 / np.linalg.norm(v0)
        h = 1e-6
        derivative = (kin.rotation_tensor(v0 + h * rate) - kin.rotation_tensor(v0 - h * rate)) / (2 * h)
        spin = derivative @ kin.rotation_tensor(v0).T
        omega = np.array([spin[2, 1], spin[0, 2], spin[1, 0]])
        np.testing.assert_allclose(spin, -spin.T, atol=1e-9)
        np.testing.assert_allclose(kin.zhilin_tensor(v0) @ rate, omega, atol=1e-9)


@pytest.mark.parametrize("angle", [0.0, 1e-7, 0.04, 1.0, 3.0])
def test_zhilin_derivative_by_finite_differences(angle):
    for v0, w in zip(_random_vectors(4, 1.0), _random_vectors(4, 1.0)):
        v0 = angle * v0 / max(np.linalg.norm(v0), 1e-300)
        h = 1e-6
        numeric = (kin.zhilin_tensor(v0 + h * w) - kin.zhilin_tensor(v0 - h * w)) / (2 * h)
        np.testing.assert_allclose(kin.zhilin_derivative(v0, w), numeric, atol=1e-9)


def _scaled(basis, count, largest):
    angles = RNG.uniform(0, 2 * np.pi, count)
    sizes = RNG.uniform(0, largest, count)
    return (np.column_stack([np.cos(angles), np.sin(angles)]) @ basis.T) * sizes[:, None]


@pytest.mark.parametrize("phi", [0.0, 0.3, -2.9, 1000.3, -12345.678])
def test_split_reproduces_the_rotation_whatever_the_axial_turns(phi):
    for gamma in _scaled(kin.transverse_basis(E), 20, 3.1):
        matrix = kin.compose_split(phi, gamma, E)
        phi_back, gamma_back = kin.split_rotation(Rotation.from_matrix(matrix), E, phi_reference=phi + 1.0)
        np.testing.assert_allclose(kin.compose_split(phi_back, gamma_back, E), matrix, atol=1e-12)
        np.testing.assert_allclose(gamma_back, gamma, atol=1e-10)
        assert phi_back == pytest.approx(phi, abs=1e-9)
        assert abs(gamma_back @ E) < 1e-15


def test_split_of_any_random_rotation():
    for matrix in Rotation.random(200, random_state=1).as_matrix():
        phi, gamma = kin.split_rotation(matrix, E)
        np.testing.assert_allclose(kin.compose_split(phi, gamma, E), matrix, atol=1e-12)


@pytest.mark.parametrize("size", [0.0, 1e-8, 0.02, 1.0, 2.5, np.pi - 1e-3])
def test_split_rates_invert_the_composition_of_angular_velocities(size):
    """Eqs. (6), (8) are the inverse of eqs. (3)-(5) up to transverse angles near pi."""
    basis = kin.transverse_basis(E)
    for gamma in _scaled(basis, 5, 1.0):
        gamma = gamma * size / max(np.linalg.norm(gamma), 1e-300) if size else gamma * 0
        gamma_dot = RNG.normal(size=2) @ basis.T
        omega_phi = RNG.normal() * 50
        omega = kin.angular_velocity_from_split(gamma, gamma_dot, omega_phi, E)
        rate, gamma_dot_back = kin.split_rates(gamma, omega, E)
        scale = 1 / np.cos(min(size, np.pi - 1e-3) / 2) ** 2
        assert rate == pytest.approx(omega_phi, abs=1e-11 * scale * 50)
        np.testing.assert_allclose(gamma_dot_back, gamma_dot, atol=1e-11 * scale * 50)


def test_split_rates_by_finite_differences_of_a_motion():
    """Along L(t) = L(gamma(t)) L(phi(t) e) the rates from eqs. (6), (8) are d gamma/dt, d phi/dt."""
    basis = kin.transverse_basis(E)

    def motion(t):
        return 2.0 * t + 40 * t ** 2, (np.array([np.sin(3 * t), 0.4 + t]) * 1.3) @ basis.T

    t, h = 0.7, 1e-6
    phi, gamma = motion(t)
    (phi_p, gamma_p), (phi_m, gamma_m) = motion(t + h), motion(t - h)
    spin = (kin.compose_split(phi_p, gamma_p, E) - kin.compose_split(phi_m, gamma_m, E)) / (2 * h) \
        @ kin.compose_split(phi, gamma, E).T
    omega = np.array([spin[2, 1], spin[0, 2], spin[1, 0]])
    omega_phi, gamma_dot = kin.split_rates(gamma, omega, E)
    assert omega_phi == pytest.approx((phi_p - phi_m) / (2 * h), rel=1e-8)
    np.testing.assert_allclose(gamma_dot, (gamma_p - gamma_m) / (2 * h), atol=1e-7)


def test_split_is_singular_at_a_transverse_half_turn():
    """e . B^-1(gamma) L(gamma) e = (theta/2) cot(theta/2) -> 0 as |gamma| -> pi."""
    basis = kin.transverse_basis(E)
    for theta in (3.0, np.pi - 1e-4, np.pi - 1e-7):
        gamma = theta * basis[:, 0]
        denominator = E @ kin.zhilin_inverse(gamma) @ kin.rotation_tensor(gamma) @ E
        assert denominator == pytest.approx(theta / 2 / np.tan(theta / 2), rel=1e-7)
    with pytest.raises(ValueError, match="singular"):
        kin.split_rotation(kin.rotation_tensor(np.pi * basis[:, 1]), E)


def test_transverse_basis_is_right_handed():
    for e in (E, np.array([0, 0, 1.0]), np.array([1.0, 2.0, -2.0]) / 3):
        b = kin.transverse_basis(e)
        np.testing.assert_allclose(b.T @ b, np.eye(2), atol=1e-15)
        np.testing.assert_allclose(np.cross(b[:, 0], b[:, 1]), e, atol=1e-15)
