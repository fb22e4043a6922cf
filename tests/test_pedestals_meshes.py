"""Bearing pedestals and gear mesh stiffness (issue 28, item 2): closed forms, limits, invariants.

Truth from outside the code: 2-DOF series systems solved by hand (pedestals), point masses joined
by a spring along a unit vector built here with numpy (gear meshes), the static tooth force's
direction (line of action), symmetry of the matrices (reciprocity) and moving the origin.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError, ModelError
from rotordyn_modal.model.geometry import gear_mesh

M_R, J_D, L, K_B = 10.0, 0.4, 0.2, 1.0e6        # rotor mass, diametral inertia, bearing arm, bearing stiffness
M_P, K_P = 5.0, 2.0e6                           # pedestal mass and stiffness


def _rotor_on_pedestals(pedestal: dict | None = None, **rotor) -> dict:
    """A rigid rotor on two identical bearings at +-L about its centre of mass, on the ground."""
    extra = {} if pedestal is None else pedestal
    return {"spin_axis": [1.0, 0.0, 0.0],
            "rotors": [{"name": "r", "mass": M_R, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.05,
                        "diametral_inertia": J_D, "speed_ratio": 1.0, **rotor}],
            "bearings": [{"name": name, "rotor": "r", "position": [x, 0.0, 0.0], "stiffness": K_B, **extra}
                         for name, x in (("A", -L), ("B", L))]}


def _two_dof(m1, m2, k11, k12, k22) -> np.ndarray:
    """The two natural frequencies [rad/s] of ``diag(m1, m2) x'' + [[k11, k12], [k12, k22]] x = 0``
    from the quadratic in w^2 (by hand: no eigen-solver)."""
    a, b, c = m1 * m2, -(k11 * m2 + k22 * m1), k11 * k22 - k12**2
    root = math.sqrt(b * b - 4 * a * c)
    return np.sqrt(np.array([(-b - root) / (2 * a), (-b + root) / (2 * a)]))


def _by_frequency(roots) -> np.ndarray:
    return roots[np.argsort(roots.imag)]


def _frequencies(model, speed=0.0) -> np.ndarray:
    return np.sort(2 * np.pi * rdm.modal(model, speed).frequencies_hz)


def test_rigid_rotor_on_pedestals_matches_the_two_dof_series_systems():
    """Translation: rotor y and both pedestals together, M = diag(m_r, 2 m_p),
    K = [[2 k_b, -2 k_b], [-2 k_b, 2 k_b + 2 k_p]]; tilt: rotor angle and the pedestals apart,
    M = diag(J_d, 2 m_p), K = [[2 k_b L^2, -2 k_b L], [-2 k_b L, 2 k_b + 2 k_p]]; each in y and z."""
    model = rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": K_P}))
    assert model.dofs.names[-4:] == ("A.pedestal.uy", "A.pedestal.uz", "B.pedestal.uy", "B.pedestal.uz")
    translation = _two_dof(M_R, 2 * M_P, 2 * K_B, -2 * K_B, 2 * K_B + 2 * K_P)
    tilt = _two_dof(J_D, 2 * M_P, 2 * K_B * L**2, -2 * K_B * L, 2 * K_B + 2 * K_P)
    expected = np.sort(np.repeat(np.r_[translation, tilt], 2))
    np.testing.assert_allclose(_frequencies(model), expected, rtol=1e-10)


def test_stiff_pedestals_tend_to_the_bearings_alone_as_one_over_k():
    """k_p -> infinity: the pedestal stands still, the rotor's frequencies are sqrt(2 k_b / m_r)
    and sqrt(2 k_b L^2 / J_d); the error falls as 1 / k_p (ten times per decade)."""
    rigid = np.sort(np.repeat([math.sqrt(2 * K_B / M_R), math.sqrt(2 * K_B * L**2 / J_D)], 2))
    errors = []
    for k_p in (1e9, 1e10, 1e11):
        model = rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": k_p}))
        errors.append(np.max(np.abs(_frequencies(model)[:4] / rigid - 1)))
    without = rdm.Model.from_dict(_rotor_on_pedestals())
    np.testing.assert_allclose(_frequencies(without), rigid, rtol=1e-12)
    assert errors[0] < 1e-2
    np.testing.assert_allclose(np.array(errors[:-1]) / errors[1:], 10.0, rtol=0.02)


def test_pedestal_axes_anisotropic_stiffness_and_damping_in_the_bearing_axes():
    """A 2-list stiffness is diagonal in the bearing's radial axes; damping only adds damping:
    with [k_y, k_z] the y and z translations follow their own 2-DOF systems."""
    pedestal = {"pedestal_mass": M_P, "pedestal_stiffness": [K_P, 3 * K_P]}
    model = rdm.Model.from_dict(_rotor_on_pedestals(pedestal))
    expected = np.r_[_two_dof(M_R, 2 * M_P, 2 * K_B, -2 * K_B, 2 * K_B + 2 * K_P),
                     _two_dof(M_R, 2 * M_P, 2 * K_B, -2 * K_B, 2 * K_B + 6 * K_P),
                     _two_dof(J_D, 2 * M_P, 2 * K_B * L**2, -2 * K_B * L, 2 * K_B + 2 * K_P),
                     _two_dof(J_D, 2 * M_P, 2 * K_B * L**2, -2 * K_B * L, 2 * K_B + 6 * K_P)]
    np.testing.assert_allclose(_frequencies(model), np.sort(expected), rtol=1e-10)
    damped = rdm.Model.from_dict(_rotor_on_pedestals({**pedestal, "pedestal_damping": 50.0}))
    assert np.all(rdm.modal(damped).damping_ratios > 0)


@pytest.mark.parametrize("key, value, expected", [
    ("pedestal_mass", -1.0, "> 0"),
    ("pedestal_mass", 0.0, "> 0"),
    ("pedestal_stiffness", [[1e6, 2e6], [2e6, 1e6]], "positive definite"),
    ("pedestal_stiffness", [1e6, 0.0], "positive definite"),
    ("pedestal_stiffness", [[1e6, 1e5], [0.0, 1e6]], "symmetric"),
    ("pedestal_damping", -3.0, "positive semidefinite"),
])
def test_bad_pedestals_are_refused_by_name(key, value, expected):
    pedestal = {"pedestal_mass": M_P, "pedestal_stiffness": K_P, key: value}
    with pytest.raises(ModelError, match=rf"\[bearings\.A\] {key} = .*{expected}"):
        rdm.Model.from_dict(_rotor_on_pedestals(pedestal))


def test_a_pedestal_needs_mass_and_stiffness():
    with pytest.raises(ModelError, match=r"\[bearings\.A\] pedestal_stiffness = '<missing>'"):
        rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P}))
    with pytest.raises(ModelError, match=r"\[bearings\.A\] pedestal_mass = '<missing>'"):
        rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_stiffness": K_P}))


def test_pedestal_mass_is_a_study_key_and_simulate_runs_pedestals_in_the_linear_time_model(monkeypatch, capsys):
    """``simulate`` integrates a rigid machine on pedestals as its linear model, saying so in one
    line on stderr: a blow on the rotor moves it as the 2-DOF series system solved by hand (the
    pedestals move); free spin, which the linear time model has not, is refused by one line."""
    from rotordyn_modal.simulation import flexible
    from rotordyn_modal.simulation._system import COMPILE_NOTICE

    model = rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": K_P}))
    heavier = model.variant([("bearings.A.pedestal_mass", "scale", 2.0), ("bearings.B.pedestal_mass", "scale", 2.0)])
    translation = _two_dof(M_R, 4 * M_P, 2 * K_B, -2 * K_B, 2 * K_B + 2 * K_P)
    assert np.min(np.abs(_frequencies(heavier)[:, None] - translation[None]), axis=0).max() < 1e-8 * translation.max()
    data = _rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": K_P})
    data["excitations"] = [{"name": "blow", "rotor": "r", "position": [0.0, 0.0, 0.0], "direction": [0, 1, 0]}]
    data["sensors"] = [{"name": "y", "rotor": "r", "position": [0.0, 0.0, 0.0], "direction": [0, 1, 0]}]
    monkeypatch.setattr(flexible, "_NOTICED", [])
    res = rdm.simulate(rdm.Model.from_dict(data), 0.05, speed=10.0, impulse="blow", impulse_size=2.0, samples=201,
                       rtol=1e-11, atol=1e-16)
    # numba's first compilation in a fresh checkout adds its own notice line (COMPILE_NOTICE)
    err = [line for line in capsys.readouterr().err.strip().splitlines() if line != COMPILE_NOTICE]
    assert len(err) == 1 and "bearing pedestals ([bearings.A], [bearings.B])" in err[0] and "linear model" in err[0]
    # the blow at the centre of mass excites the translation system alone (rotor y, both pedestals
    # together): y(t) = sum_k phi_k(r) phi_k(r) m_r v0 sin(w_k t) / w_k, its modes by hand
    m2, k11, k12 = 2 * M_P, 2 * K_B, -2 * K_B
    y = np.zeros_like(res.time)
    for w in _two_dof(M_R, m2, k11, k12, 2 * K_B + 2 * K_P):
        shape = np.array([1.0, -(k11 - w**2 * M_R) / k12])
        shape /= math.sqrt(M_R * shape[0] ** 2 + m2 * shape[1] ** 2)
        y += shape[0] ** 2 * 2.0 * np.sin(w * res.time) / w          # m_r v0 = the impulse, 2 N s
    np.testing.assert_allclose(res.sensor("y"), y, rtol=0, atol=1e-7 * np.abs(y).max())
    with pytest.raises(InputError, match=r"drive 'free': a machine with bearing pedestals is simulated") as error:
        rdm.simulate(model, 0.1, speed=10.0, drive="free")
    assert "\n" not in str(error.value)


# -- gear meshes ----------------------------------------------------------------------------
M1, M2, K1, K2, K_MESH = 12.0, 7.0, 2.0e6, 1.5e6, 5.0e6


def _geared(mesh: dict | None = None, shift=(0.0, 0.0, 0.0), **gear) -> dict:
    """Two rigid rotors on isotropic bearings at +-L (ground), their centres in the plane x = 0,
    a gear between them in that plane."""
    d = np.asarray(shift, dtype=float)
    rotors, bearings = [], []
    for name, mass, k, centre in (("pinion", M1, K1, [0.0, 0.0, 0.0]), ("wheel", M2, K2, [0.0, 0.06, 0.08])):
        c = np.asarray(centre) + d
        rotors.append({"name": name, "mass": mass, "center_of_mass": c.tolist(), "polar_inertia": 0.02,
                       "diametral_inertia": 0.05})
        bearings += [{"name": f"{name}-{side}", "rotor": name, "position": (c + [x, 0.0, 0.0]).tolist(),
                      "stiffness": k} for side, x in (("DE", -L), ("NDE", L))]
    rotors[0]["speed_ratio"] = 1.0
    transmission = {"type": "gear", "driver": "pinion", "driven": "wheel", "ratio": 1.5, **gear,
                    **({} if mesh is None else mesh)}
    return {"spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "pinion", "rotors": rotors, "bearings": bearings,
            "transmissions": [transmission]}


def _line_of_action(model) -> np.ndarray:
    """The tooth force's direction on the driver from ``rdm.static`` under a driving torque."""
    loads = [x for x in rdm.static(model, speed=100.0, torques=50.0).loads if x.kind == "gear" and x.body == "pinion"]
    return loads[0].force / np.linalg.norm(loads[0].force)


def test_line_of_action_at_twenty_degrees():
    """Normal to the spin axis, 20 deg from the tangent of the pitch circles, along the static
    tooth force; the pitch point on the line of centres at r = a / (1 + ratio)."""
    model = rdm.Model.from_dict(_geared({"mesh_stiffness": K_MESH}, pressure_angle=20.0))
    t = model.transmissions[0]
    mesh = gear_mesh(t, model.rotor("pinion"), model.rotor("wheel"), model.spin_axis)
    u = np.array([0.0, 0.6, 0.8])                 # centre line from pinion to wheel, a = 0.1 m
    n = mesh.direction
    assert abs(np.linalg.norm(n) - 1) < 1e-14 and abs(n[0]) < 1e-15
    assert math.degrees(math.asin(abs(n @ u))) == pytest.approx(20.0, abs=1e-12)
    assert math.degrees(math.acos(abs(n @ np.cross([1.0, 0, 0], u)))) == pytest.approx(20.0, abs=1e-12)
    np.testing.assert_allclose(mesh.pitch_point, 0.1 / 2.5 * u, atol=1e-15)
    assert abs(abs(n @ _line_of_action(model)) - 1) < 1e-12
    data = _geared({"mesh_stiffness": K_MESH}, pressure_angle=20.0)      # the driver turning backwards
    data["reference_rotor"] = "wheel"
    data["rotors"][0].pop("speed_ratio")
    data["rotors"][1]["speed_ratio"] = 1.0
    backwards = rdm.Model.from_dict(data)
    assert backwards.speed_ratios["pinion"] < 0
    mirrored = gear_mesh(backwards.transmissions[0], backwards.rotor("pinion"), backwards.rotor("wheel"),
                         backwards.spin_axis).direction
    assert abs(abs(mirrored @ _line_of_action(backwards)) - 1) < 1e-12 and abs(mirrored @ n) < 0.99


def test_geared_rotors_match_rigid_bodies_joined_along_the_line_of_action():
    """Zero speed, gear plane at x = s off both centres of mass: each rotor [u_y, u_z, r_y, r_z]
    with diag(m, m, J_d, J_d) on springs 2 k, 2 k L^2; the mesh k n_w n_w^T on the difference of
    the two gears' motions in the plane, u(s) = u + r x (s e) (built here; n from the static
    tooth force)."""
    s = 0.1
    model = rdm.Model.from_dict(_geared({"mesh_stiffness": K_MESH}, pressure_angle=20.0, position=[s, 0.0, 0.0]))
    n = _line_of_action(model)[1:]                                   # (y, z) components
    w = np.array([n[0], n[1], -s * n[1], s * n[0]])                  # n . u(s) per [u_y, u_z, r_y, r_z]
    w = np.r_[w, -w]
    K = np.diag([2 * K1, 2 * K1, 2 * K1 * L**2, 2 * K1 * L**2, 2 * K2, 2 * K2, 2 * K2 * L**2, 2 * K2 * L**2])
    K = K + K_MESH * np.outer(w, w)
    scale = 1 / np.sqrt([M1, M1, 0.05, 0.05, M2, M2, 0.05, 0.05])
    expected = np.sqrt(np.linalg.eigvalsh(scale[:, None] * K * scale[None]))
    np.testing.assert_allclose(_frequencies(model), expected, rtol=1e-10)
    without = rdm.Model.from_dict(_geared())
    assert not np.allclose(_frequencies(without), _frequencies(model), rtol=1e-3)


def test_mesh_keeps_reciprocity_and_damping_and_moving_the_origin_changes_nothing():
    """K and C symmetric, G skew: H(Omega) = H(-Omega)^T; the same machine moved by a vector
    has the same roots at speed (gyroscopic, damped mesh, pedestals)."""
    extra = {"mesh_stiffness": K_MESH, "mesh_damping": 80.0}
    model = rdm.Model.from_dict(_geared(extra, pressure_angle=25.0, driver_radius=0.03))
    on_pedestal = _geared(extra, pressure_angle=25.0, driver_radius=0.03)
    on_pedestal["bearings"][0].update(pedestal_mass=3.0, pedestal_stiffness=[[4e6, 1e6], [1e6, 5e6]],
                                      pedestal_damping=40.0, damping=[[90.0, 10.0], [10.0, 60.0]])
    for case in (model, rdm.Model.from_dict(on_pedestal)):
        M, C, G, K = case.matrices()
        s = 1j * 2 * np.pi * 170.0
        H = np.linalg.inv(M * s**2 + (C + 300.0 * G) * s + K)
        H_reversed = np.linalg.inv(M * s**2 + (C - 300.0 * G) * s + K)
        np.testing.assert_allclose(H, H_reversed.T, rtol=1e-10, atol=1e-12 * np.abs(H).max())
        assert np.abs(G).max() > 0
    roots = _by_frequency(rdm.modal(model, 300.0).eigenvalues)
    data = _geared(extra, shift=(0.7, -1.3, 2.1), pressure_angle=25.0, driver_radius=0.03)
    data["bearings"][0].update(pedestal_mass=3.0, pedestal_stiffness=[4e6, 5e6])
    moved_with = _by_frequency(rdm.modal(rdm.Model.from_dict(data), 300.0).eigenvalues)
    data = _geared(extra, pressure_angle=25.0, driver_radius=0.03)
    data["bearings"][0].update(pedestal_mass=3.0, pedestal_stiffness=[4e6, 5e6])
    here_with = _by_frequency(rdm.modal(rdm.Model.from_dict(data), 300.0).eigenvalues)
    moved = _by_frequency(rdm.modal(rdm.Model.from_dict(_geared(extra, shift=(0.7, -1.3, 2.1), pressure_angle=25.0,
                                                                   driver_radius=0.03)), 300.0).eigenvalues)
    np.testing.assert_allclose(moved, roots, rtol=1e-10)
    np.testing.assert_allclose(moved_with, here_with, rtol=1e-10)
    ratios = rdm.modal(model, 300.0).damping_ratios      # the mesh damps the modes that strain it
    assert ratios.min() > -1e-12 and (ratios > 1e-6).sum() >= 2


def test_mesh_keys_refused_by_name_and_simulate_refuses_free_spin_with_a_mesh():
    with pytest.raises(ModelError, match=r"mesh_stiffness = -1.0: expected a finite number > 0"):
        rdm.Model.from_dict(_geared({"mesh_stiffness": -1.0}))
    belt = _geared({"mesh_stiffness": K_MESH})
    belt["transmissions"][0]["type"] = "belt"
    with pytest.raises(ModelError, match=r"mesh_stiffness = .*this key is for type = 'gear'"):
        rdm.Model.from_dict(belt)
    with pytest.raises(ModelError, match=r"driver_radius = 0.2: expected a pitch radius below the centre distance"):
        rdm.Model.from_dict(_geared({"mesh_stiffness": K_MESH}, driver_radius=0.2))
    model = rdm.Model.from_dict(_geared({"mesh_stiffness": K_MESH}))
    with pytest.raises(InputError, match=r"drive 'free': a machine with gear mesh stiffness is simulated") as error:
        rdm.simulate(model, 0.1, speed=10.0, drive="free")
    assert "\n" not in str(error.value)


def test_bearing_force_on_a_pedestal_is_what_moves_the_pedestal():
    """Newton on the pedestal: the bearing's force on it equals (K_p + i w C_p - w^2 m_p) p for
    its harmonic motion p, through both force paths (per kind and all together)."""
    from rotordyn_modal.analysis.forces import all_forces, bearing_point_forces
    from rotordyn_modal.analysis.frf import dof_response

    pedestal = {"pedestal_mass": M_P, "pedestal_stiffness": [[K_P, 2e5], [2e5, 2 * K_P]], "pedestal_damping": 70.0}
    data = _rotor_on_pedestals(pedestal, center_of_mass=[0.05, 0.0, 0.0])
    data["bearings"][0]["damping"] = 120.0
    model = rdm.Model.from_dict(data)
    force = np.zeros((model.dofs.n, 2))
    force[0, 0], force[3, 1] = 1.0, 0.3                 # r.uy and a moment on r.rz
    w = np.array([150.0, 420.0, 900.0])
    q = dof_response(model, 200.0, w, force)
    for bearings in (bearing_point_forces(model, 200.0, w, q), all_forces(model, 200.0, w, q)[2]):
        for b, bearing in enumerate(model.bearings):
            rows = model.dofs.pedestal(bearing.name)
            p = q[:, rows]                                               # (F, 2, k): along y, z
            k, c = bearing.pedestal.stiffness[1:, 1:], bearing.pedestal.damping[1:, 1:]
            expected = (k[None] + 1j * w[:, None, None] * c[None] - w[:, None, None]**2 * M_P * np.eye(2)) @ p
            np.testing.assert_allclose(bearings[b][:, 1:3], expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max())


def test_pedestals_move_with_the_stator_and_count_in_its_mass():
    """A rigid translation of the whole machine (the stator's, every relative motion zero) moves
    the pedestals with it in all three directions: its kinetic energy is the total mass's."""
    data = _rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": K_P})
    data.update(stator={"mass": 40.0, "inertia": [2.0, 3.0, 4.0], "center_of_mass": [0.1, 0.2, -0.3]},
                suspensions=[{"name": f"s{i}", "position": p, "stiffness": [1e5, 1e5, 1e5]}
                             for i, p in enumerate([[0.5, 0.5, -0.5], [-0.5, 0.5, -0.5], [0.5, -0.5, -0.5],
                                                    [-0.5, -0.5, -0.5]])])
    model = rdm.Model.from_dict(data)
    M = model.matrices().M
    for axis in range(3):
        assert M[axis, axis] == pytest.approx(40.0 + M_R + 2 * M_P, rel=1e-14)


def test_a_rigid_motion_of_the_whole_machine_strains_no_mesh():
    """Gears on the stator (no bearings): the mesh never strains, the matrices are today's; gears
    on bearings in a stator on mounts: the stator's six motions (rotors riding along) strain nothing."""
    from rotordyn_modal.assembly import mesh_matrices

    base = rdm.load_model("examples/gear_machine.toml")
    data = base.to_dict()
    data["transmissions"][0].update(mesh_stiffness=K_MESH, mesh_damping=30.0, driver_radius=0.04)
    meshed = rdm.Model.from_dict(data)
    for a, b in zip(base.matrices(), meshed.matrices()):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-9 * np.abs(a).max())
    data = _geared({"mesh_stiffness": K_MESH}, position=[0.1, 0.0, 0.0])
    data.update(stator={"mass": 40.0, "inertia": [2.0, 3.0, 4.0], "center_of_mass": [0.3, -0.2, 0.1]},
                suspensions=[{"name": "s", "position": [0.0, 0.0, -0.4], "stiffness": [1e5] * 3 + [1e4] * 3}])
    model = rdm.Model.from_dict(data)
    K = mesh_matrices(model)[0]
    assert np.abs(K).max() > 1e6
    np.testing.assert_allclose(K[:, :6], 0.0, atol=1e-9 * np.abs(K).max())


def _flexible_on_pedestals(scale=1.0) -> dict:
    """test_flexible_rotors' machine (a flexible rotor in a casing on mounts) with its bearings on
    pedestals and a gear mesh to the rotor fixed in the casing, which drives it."""
    from test_flexible_rotors import _machine

    data = _machine(scale=scale)
    del data["rotors"][0]["speed_ratio"]
    data["transmissions"] = [{"type": "gear", "driver": "m", "driven": "r", "ratio": 1 / 1.5,
                              "position": [0.3, 0.0, 0.0], "pressure_angle": 22.0, "mesh_stiffness": 4e6}]
    data["bearings"][0].update(pedestal_mass=1.5, pedestal_stiffness=[5e6, 8e6])
    data["bearings"][1].update(pedestal_mass=2.5, pedestal_stiffness=6e6)
    return data


def test_flexible_rotor_on_pedestals_with_a_mesh_tends_to_the_rigid_rotor_as_one_over_e():
    from test_flexible_rotors import _refined, _rigid_twin

    speed = 300.0
    rigid = _rigid_twin(rdm.Model.from_dict(_flexible_on_pedestals()), _flexible_on_pedestals())
    assert rigid.dofs.pedestals and np.abs(rdm.assembly.mesh_matrices(rigid)[0]).max() > 0
    targets = np.sort(rdm.modal(rigid, speed).eigenvalues.imag)
    exact = np.array([_refined(rigid, speed, w) for w in targets])
    errors = []
    for scale in (1e3, 1e4):       # (at 1e6 the roots' round-off, 3e-7, would show)
        flexible = rdm.Model.from_dict(_flexible_on_pedestals(scale))
        found = np.array([_refined(flexible, speed, w) for w in exact])
        errors.append(np.max(np.abs(found - exact) / exact))
    assert errors[0] < 1e-3
    assert 9.5 < errors[0] / errors[1] < 10.5, errors


def test_a_mesh_on_a_flexible_rotor_acts_at_the_node_in_the_gear_plane():
    model = rdm.Model.from_dict(_flexible_on_pedestals())
    shaft = model.rotor("r").flexible
    node = int(np.flatnonzero(np.isclose(shaft.mesh.z, 0.3, rtol=0, atol=1e-12))[0])   # shaft starts at x = 0
    K = rdm.assembly.mesh_matrices(model)[0]
    touched = {name for name, column in zip(model.dofs.names, np.abs(K).max(axis=0)) if column > 0}
    assert touched == {f"r.n{node}.uy", f"r.n{node}.uz"}     # the pinion m rides on the casing: no stator motion strains it


def test_whirl_counts_the_pedestals_a_pedestal_mode_whirls_with_its_mass():
    """The whirl forms' total is the mass matrix (pedestals included); a pedestal-dominated mode
    of an isotropic machine at speed whirls forward or backward circularly (|ratio| near 1)."""
    from rotordyn_modal.analysis._whirl import whirl_forms

    model = rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": K_P}))
    np.testing.assert_allclose(whirl_forms(model).total, model.matrices().M, rtol=1e-14, atol=1e-14)
    result = rdm.modal(model, 400.0)
    assert np.all(np.abs(np.abs(result.whirl_ratios) - 1) < 1e-9)


def test_mesh_stiffness_is_a_study_key():
    model = rdm.Model.from_dict(_geared({"mesh_stiffness": K_MESH}))
    stiffer = model.variant([("transmissions.0.mesh_stiffness", "scale", 3.0)])
    direct = rdm.Model.from_dict(_geared({"mesh_stiffness": 3 * K_MESH}))
    np.testing.assert_array_equal(_frequencies(stiffer), _frequencies(direct))
    assert not np.allclose(_frequencies(stiffer), _frequencies(model), rtol=1e-3)


def test_static_deflection_on_pedestals_is_the_series_springs():
    """A force F at the rotor's centre: the rotor moves F / (2 k_b) + F / (2 k_p), each bearing
    carries F / 2 (on the y axis; stiffer pedestals along z as given)."""
    model = rdm.Model.from_dict(_rotor_on_pedestals({"pedestal_mass": M_P, "pedestal_stiffness": [K_P, 4 * K_P]}))
    force = 300.0
    result = rdm.static(model, forces=[("r", [0.0, 0.0, 0.0], [0.0, force, -force])])
    moved = result.rotor_motion("r")[:3]
    np.testing.assert_allclose(moved, [0.0, force / (2 * K_B) + force / (2 * K_P), -force / (2 * K_B) - force / (8 * K_P)],
                               rtol=1e-12, atol=1e-18)
    for reaction in (r for r in result.reactions if r.kind == "bearing"):
        np.testing.assert_allclose(reaction.force, [0.0, -force / 2, force / 2], rtol=1e-12, atol=1e-9)


def test_command_line_lists_pedestals_and_refuses_bad_ones_in_one_line(tmp_path, capsys, monkeypatch):
    import tomli_w

    from rotordyn_modal.cli.main import main
    from rotordyn_modal.simulation import flexible

    data = _geared({"mesh_stiffness": K_MESH})
    data["bearings"][0].update(pedestal_mass=3.0, pedestal_stiffness=[4e6, 5e6])
    good = tmp_path / "good.toml"
    good.write_text(tomli_w.dumps(data), encoding="utf-8")
    assert main(["check", str(good)]) == 0
    out = capsys.readouterr().out
    assert "pinion-DE.pedestal.uy, pinion-DE.pedestal.uz" in out and "on a pedestal of 3 kg" in out
    assert "mesh stiffness 5e+06 N/m" in out
    monkeypatch.setattr(flexible, "_NOTICED", [])
    assert main(["simulate", str(good), "--duration", "0.1"]) == 0     # the linear time model, said in one line
    err = capsys.readouterr().err.strip().splitlines()
    said = [line for line in err if "the nonlinear large-rotation model cannot carry" in line]
    assert len(said) == 1 and "bearing pedestals ([bearings.pinion-DE]) and gear mesh stiffness" in said[0]
    data["bearings"][0]["pedestal_stiffness"] = [[4e6, 5e6], [5e6, 4e6]]
    bad = tmp_path / "bad.toml"
    bad.write_text(tomli_w.dumps(data), encoding="utf-8")
    assert main(["modes", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "bad.toml: [bearings.pinion-DE] pedestal_stiffness = " in err


def test_a_mesh_needs_two_spin_axes_apart():
    data = _geared({"mesh_damping": 10.0})
    data["rotors"][1]["center_of_mass"] = [0.3, 0.0, 0.0]          # on the pinion's axis
    for bearing in data["bearings"][2:]:
        bearing["position"] = [0.3 + bearing["position"][0], 0.0, 0.0]
    with pytest.raises(ModelError, match=r"mesh_damping = 10.0: expected a gear between rotors whose spin axes are apart"):
        rdm.Model.from_dict(data)


def test_strain_energy_split_counts_pedestals_and_meshes():
    """With pedestals and a gear mesh the strain-energy parts are still the whole stiffness
    (none left out), every mode's fractions sum to 1 and the mesh is strained in some."""
    from rotordyn_modal.assembly import matrices, stiffness_parts

    model = rdm.Model.from_dict(_flexible_on_pedestals())
    parts = stiffness_parts(model, 300.0)
    assert {"pedestals", "meshes"} <= set(parts)
    total = matrices(model, 300.0).K
    assert np.allclose(sum(parts.values()), total, rtol=0, atol=1e-12 * np.abs(total).max())
    result = rdm.modal(model, 300.0)
    rows = result.energy_fractions[result.oscillatory]
    assert np.allclose(rows.sum(axis=1), 1.0, atol=1e-10)
    table = result.to_dataframe()
    assert {"pedestal_energy", "mesh_energy"} <= set(table.columns)
    assert (table["mesh_energy"] > 1e-6).any()
