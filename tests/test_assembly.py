"""Global matrices M, C, G, K (seed 000 eqs. 52, 76-77) against the independent reference."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

import rotordyn_modal as rdm
from reference_model import ReferenceMachine, random_description, rotated, rotation, translated


def to_origin(model, matrix):
    """A matrix about the reference point S in coordinates at the model origin:
    u_S = u_O + theta x S, so q_S = T q_O with T = [[I, -skew(S)], [0, I]]."""
    T = np.eye(6)
    T[:3, 3:] = -rdm.skew(model.reference_point)
    return T.T @ matrix @ T


def descriptions():
    rng = np.random.default_rng(5)
    out = [random_description(rng, n_rotors=n, matrix_mount=mm) for n, mm in ((1, False), (2, True), (3, False))]
    with open(__file__.rsplit("/", 2)[0] + "/examples/gear_machine.toml", "rb") as handle:
        out.append(tomllib.load(handle))
    return out


@pytest.mark.parametrize("data", descriptions())
def test_matrices_equal_the_particle_reference(data):
    model = rdm.Model.from_dict(data)
    ref = ReferenceMachine(data)
    M, C, G, K = model.matrices()
    for name, mine, theirs in (("M", M, ref.M), ("C", C, ref.C), ("G", G, ref.G), ("K", K, ref.K)):
        scale = max(np.abs(theirs).max(), 1e-300)
        np.testing.assert_allclose(to_origin(model, mine), theirs, rtol=0, atol=1e-13 * scale, err_msg=name)


@pytest.mark.parametrize("data", descriptions())
def test_structure(data):
    M, C, G, K = rdm.Model.from_dict(data).matrices()
    np.testing.assert_array_equal(M, M.T)
    assert np.linalg.eigvalsh(M).min() > 0
    np.testing.assert_array_equal(G, -G.T)
    np.testing.assert_allclose(K, K.T, atol=1e-9 * np.abs(K).max())
    np.testing.assert_allclose(C, C.T, atol=1e-9 * max(np.abs(C).max(), 1e-300))
    assert np.linalg.eigvalsh(0.5 * (K + K.T)).min() >= -1e-9 * np.abs(K).max()
    np.testing.assert_array_equal(G[:3], 0.0)
    np.testing.assert_array_equal(G[:, :3], 0.0)


def test_mass_matrix_about_centre_of_mass_of_the_whole_machine():
    """The machine's total mass, first moment about S and centroidal inertia tensor."""
    data = descriptions()[1]
    model = rdm.Model.from_dict(data)
    M = model.matrices().M
    ref = ReferenceMachine(data)
    total = ref.masses.sum()
    np.testing.assert_allclose(M[:3, :3], total * np.eye(3), rtol=1e-14)
    arm = ref.points - model.reference_point
    first = (ref.masses[:, None] * arm).sum(axis=0)
    np.testing.assert_allclose(M[3:, :3], rdm.skew(first), atol=1e-12)
    inertia = sum(m * ((r @ r) * np.eye(3) - np.outer(r, r)) for m, r in zip(ref.masses, arm))
    np.testing.assert_allclose(M[3:, 3:], inertia, rtol=1e-12, atol=1e-12 * np.abs(inertia).max())


def test_eq52_gyroscopic_block_for_spin_along_x():
    """Seed eq. 52 with e = x: g = [[0, 0, 0], [0, 0, Jp r], [0, -Jp r, 0]] per unit speed."""
    model = rdm.Model(stator=rdm.Stator(mass=10.0, inertia=[1.0, 1.0, 1.0]),
                      rotors=[rdm.Rotor("a", 1.0, [0.3, 0.2, 0.1], 0.07, 0.05, speed_ratio=1.0),
                              rdm.Rotor("b", 1.0, [-0.3, 0.0, 0.1], 0.11, 0.06, speed_ratio=-0.4)],
                      reference_rotor="a", spin_axis=[2.0, 0.0, 0.0])
    net = 0.07 * 1.0 + 0.11 * -0.4
    expected = np.zeros((6, 6))
    expected[4, 5], expected[5, 4] = net, -net
    np.testing.assert_allclose(model.matrices().G, expected, atol=1e-17)


def test_gear_fixes_opposite_speed_ratio_belt_same():
    base = dict(stator={"mass": 10.0, "inertia": [1.0, 1.0, 1.0]},
                rotors=[{"name": "a", "mass": 1.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.1,
                         "diametral_inertia": 0.1, "speed_ratio": 1.0},
                        {"name": "b", "mass": 1.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.1,
                         "diametral_inertia": 0.1},
                        {"name": "c", "mass": 1.0, "center_of_mass": [0, 0, 0], "polar_inertia": 0.1,
                         "diametral_inertia": 0.1}],
                reference_rotor="a",
                transmissions=[{"type": "gear", "driver": "a", "driven": "b", "ratio": 2.5},
                               {"type": "belt", "driver": "c", "driven": "b", "ratio": 0.5}])
    model = rdm.Model.from_dict(base)
    assert model.speed_ratios["b"] == pytest.approx(-1 / 2.5, rel=1e-15)   # eq. 17
    assert model.speed_ratios["c"] == pytest.approx(-0.5 / 2.5, rel=1e-15)  # belt: omega_b = omega_c / 0.5


def test_origin_shift_moves_nothing_but_numbers():
    data = descriptions()[0]
    model = rdm.Model.from_dict(data)
    shift = np.array([3.0, -1.0, 7.0])
    moved = rdm.Model.from_dict(translated(data, shift))
    np.testing.assert_allclose(moved.reference_point, model.reference_point + shift, rtol=1e-14)
    for a, b in zip(model.matrices(), moved.matrices()):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-11 * max(np.abs(a).max(), 1e-300))


def test_axes_rotation_turns_the_matrices():
    data = descriptions()[1]
    R = rotation(np.random.default_rng(9))
    T = np.kron(np.eye(2), R)
    model, turned = rdm.Model.from_dict(data), rdm.Model.from_dict(rotated(data, R))
    for a, b in zip(model.matrices(), turned.matrices()):
        np.testing.assert_allclose(b, T @ a @ T.T, rtol=0, atol=1e-11 * max(np.abs(a).max(), 1e-300))


def test_six_by_six_and_non_symmetric_mounts():
    """A 6x6 local matrix in inclined axes, non-symmetric: K non-symmetric, equal to the
    virtual-work reference."""
    rng = np.random.default_rng(21)
    data = random_description(rng, n_rotors=1)
    # a passive mount: the symmetric part positive definite (validation refuses any other), the
    # antisymmetric (cross-coupled) part free
    coupling = rng.uniform(-1, 1, (6, 6)) * 1e4
    local = np.diag([3e5, 3e5, 3e5, 1e3, 1e3, 1e3]) + (coupling - coupling.T) / 2
    data["suspensions"][1]["stiffness"] = local.tolist()
    data["suspensions"][1]["damping"] = np.diag(rng.uniform(1, 5, 6)).tolist()
    model = rdm.Model.from_dict(data)
    ref = ReferenceMachine(data)
    K = model.matrices().K
    assert np.abs(K - K.T).max() > 1e-3 * np.abs(K).max()
    np.testing.assert_allclose(to_origin(model, K), ref.K, rtol=0, atol=1e-12 * np.abs(ref.K).max())
    np.testing.assert_allclose(to_origin(model, model.matrices().C), ref.C, rtol=0,
                               atol=1e-12 * np.abs(ref.C).max())
