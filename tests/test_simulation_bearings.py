"""Time simulation of rotors on flexible bearings against independent answers: two free rigid
bodies integrated with quaternions, energy and momentum invariants, the linear model
(state matrix, impulse response, unbalance orbits at proximity probes), seed 001's example
written both ways, and bad input."""

from __future__ import annotations

from pathlib import Path

import control
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.linear_system import speed_linear_form
from steady_harmonics import assert_steady_harmonics_equal_the_linear_response

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
OMEGA0 = 50.0

FAN_DE = {"name": "fan-DE", "rotor": "fan", "position": [-0.15, 0.0, 0.25], "axial_stiffness": 1.5e5,
          "stiffness": [[2.0e5, 3.0e4], [3.0e4, 3.0e5]], "moment_stiffness": 50.0}
FAN_NDE = {"name": "fan-NDE", "rotor": "fan", "position": [-0.45, 0.0, 0.25], "stiffness": 2.5e5}
PROBES = [
    {"name": "probe-DE-y", "rotor": "fan", "measure": "relative", "position": [-0.15, 0.0, 0.25],
     "direction": [0.0, 1.0, 0.0]},
    {"name": "probe-DE-z", "rotor": "fan", "measure": "relative", "position": [-0.15, 0.0, 0.25],
     "direction": [0.0, 0.0, 1.0]},
    {"name": "fan-nose-z", "rotor": "fan", "position": [-0.6, 0.0, 0.25], "direction": [0.0, 0.3, 1.0]},
]


def _casing_machine(damping=1.0, table=False, cross_coupled=False, probes=False):
    """The gear machine with its fan on two flexible bearings (motor still rigidly attached,
    geared to the fan): a rotor-bearing-casing machine on mounts.

    ``damping`` scales the mounts' and the bearings' damping (0: undamped);
    ``table``: the non-drive-end bearing's stiffness tabulated over speed;
    ``cross_coupled``: a non-symmetric (circulatory) drive-end stiffness.
    """
    data = rdm.load_model(EXAMPLES / "gear_machine.toml").to_dict()
    for suspension in data["suspensions"]:
        if damping:
            suspension["damping"] = [damping * c for c in suspension["damping"]]
        else:
            suspension.pop("damping")
    de, nde = dict(FAN_DE), dict(FAN_NDE)
    if cross_coupled:
        de["stiffness"] = [[2.0e5, 3.0e4], [-2.0e4, 3.0e5]]
    if damping:
        de["damping"] = [[60.0 * damping, 10.0], [10.0, 80.0 * damping]]
        de["axial_damping"], nde["damping"] = 40.0 * damping, 70.0 * damping
    if table:
        nde["speeds_rpm"] = [-6000.0, 0.0, 6000.0]
        nde["stiffness"] = [2.0e5, 2.5e5, 3.5e5]
        if damping:
            nde["damping"] = [50.0 * damping, 70.0 * damping, 90.0 * damping]
    data["bearings"] = [de, nde]
    if probes:
        data["sensors"] = data["sensors"] + PROBES
        data["excitations"] = data["excitations"] + [
            {"name": "fan-hit-y", "rotor": "fan", "position": [-0.6, 0.0, 0.25], "direction": [0.0, 1.0, 0.0]}]
    return rdm.Model.from_dict(data)


# ----------------------------------------------------------------------------------------
# seed 001's example: the block of springs as a bearing to the ground, or as a suspension
@pytest.fixture(scope="module")
def seed_example_runs():
    runs = {}
    for name in ("spring_block_rotor.toml", "spring_block_rotor_suspension.toml"):
        model = rdm.load_model(EXAMPLES / name)
        runs[name] = rdm.simulate(model, 3.0, OMEGA0, drive="free", samples=301, rtol=1e-11, atol=1e-13)
    return runs


def test_seed_example_as_a_bearing_moves_as_the_suspension_writing(seed_example_runs):
    bearing = seed_example_runs["spring_block_rotor.toml"]
    suspension = seed_example_runs["spring_block_rotor_suspension.toml"]
    assert bearing.states.shape[1] == 2 * 6 and suspension.states.shape[1] == 2 * 6
    np.testing.assert_allclose(bearing.rotor_centers, suspension.rotor_centers, rtol=0, atol=1e-9)
    np.testing.assert_allclose(bearing.sensors, suspension.sensors, rtol=0, atol=1e-9)
    np.testing.assert_allclose(bearing.spin_speed, suspension.spin_speed, rtol=0, atol=1e-9)
    assert np.ptp(bearing.rotor_centers[:, 0, 2]) > 0.05   # it really moved
    # the bearing's force is the block's spring force on the rod end a (seed 001, section 4)
    rod_end = bearing.rotor_centers[:, 0] - 0.75 * Rotation.from_rotvec(bearing.rotor_tilts[:, 0]).apply([1.0, 0, 0])
    np.testing.assert_allclose(bearing.bearing_forces[:, 0, :3], 2000.0 * rod_end, rtol=0, atol=1e-7)
    np.testing.assert_allclose(bearing.bearing_forces[:, 0, 3:], 500.0 * bearing.rotor_tilts[:, 0], atol=1e-9)
    assert not bearing.displacement.any()   # the bearing stands on the ground


# ----------------------------------------------------------------------------------------
# a stator on mounts and a rotor on two bearings: two free rigid bodies, integrated apart
def _two_body_model():
    data = rdm.load_model(EXAMPLES / "gear_machine.toml").to_dict()
    fan = dict(data["rotors"][1], speed_ratio=1.0)
    data["rotors"], data["transmissions"] = [fan], []
    data["reference_rotor"] = "fan"
    data["bearings"] = [
        {"name": "DE", "rotor": "fan", "position": [-0.15, 0.0, 0.25], "stiffness": [[2.0e5, 3.0e4], [3.0e4, 3.0e5]],
         "damping": [[60.0, 10.0], [10.0, 80.0]], "axial_stiffness": 1.5e5, "axial_damping": 40.0},
        {"name": "NDE", "rotor": "fan", "position": [-0.45, 0.0, 0.25], "stiffness": 2.5e5, "damping": 70.0}]
    data["unbalances"] = [{"rotor": "fan", "amount": 2.0e-3, "phase_deg": 0.0}]
    data["gravity"] = [0.0, 0.0, -9.81]
    return rdm.Model.from_dict(data)


def _two_free_bodies(model, speed, times):
    """Newton-Euler equations of the stator and the rotor as two free rigid bodies (unit
    quaternions, body-frame Euler equations), joined by the mounts' and the bearings' springs
    and dampers as point forces, everything in ground axes. The bearing force acts along the
    rotor point's displacement from the stator point seen in the stator's axes, on the rotor
    at its axis point and, reversed, on the stator at the same place. Spin axis x, the
    unbalance at phase 0 along z.

    Returns
    -------
    ndarray, shape (N, 2, 3): centres of mass of stator and rotor [m]
    """
    e = np.array([1.0, 0.0, 0.0])
    stator, rotor = model.stator, model.rotors[0]
    m_s, S, J_s = stator.mass, np.asarray(stator.center_of_mass), np.asarray(stator.inertia)
    m_r, C = rotor.mass, np.asarray(rotor.center_of_mass)
    rho = model.unbalances[0].amount / m_r * np.array([0.0, 0.0, 1.0])
    J_r = (rotor.diametral_inertia * np.eye(3) + (rotor.polar_inertia - rotor.diametral_inertia) * np.outer(e, e)
           - m_r * (rho @ rho * np.eye(3) - np.outer(rho, rho)))
    g = np.asarray(model.gravity)
    mounts = [(np.asarray(s.position), s.stiffness_matrix[:3, :3], s.damping_matrix[:3, :3]) for s in model.suspensions]
    bearings = [(np.asarray(b.position), b.coefficients.stiffness[0][:3, :3], b.coefficients.damping[0][:3, :3])
                for b in model.bearings]

    def quaternion_rate(quat, w_body):
        x, y, z, s = quat
        wx, wy, wz = w_body / 2
        return np.array([s * wx + y * wz - z * wy, s * wy + z * wx - x * wz,
                         s * wz + x * wy - y * wx, -x * wx - y * wy - z * wz])

    def rhs(t, state):
        r_s, v_s, q_s, w_s = state[:3], state[3:6], state[6:10], state[10:13]
        r_r, v_r, q_r, w_r = state[13:16], state[16:19], state[19:23], state[23:26]
        R_s, R_r = Rotation.from_quat(q_s).as_matrix(), Rotation.from_quat(q_r).as_matrix()
        om_s, om_r = R_s @ w_s, R_r @ w_r
        F_s, M_s = m_s * g, np.zeros(3)
        F_r, M_r = m_r * g, np.zeros(3)
        for p, K, D in mounts:
            arm = R_s @ (p - S)
            force = -K @ (r_s + arm - p) - D @ (v_s + np.cross(om_s, arm))
            F_s, M_s = F_s + force, M_s + np.cross(arm, force)
        for b, K, D in bearings:
            arm_r, arm_s = R_r @ (b - C - rho), R_s @ (b - S)
            gap = r_r + arm_r - (r_s + arm_s)
            gap_rate = v_r + np.cross(om_r, arm_r) - v_s - np.cross(om_s, arm_s) - np.cross(om_s, gap)
            force = R_s @ (K @ (R_s.T @ gap) + D @ (R_s.T @ gap_rate))       # on the stator
            F_r, M_r = F_r - force, M_r - np.cross(arm_r, force)
            F_s, M_s = F_s + force, M_s + np.cross(arm_s + gap, force)
        out = np.empty_like(state)
        for k, (v, q, w, F, M_ext, m, J, R) in enumerate(((v_s, q_s, w_s, F_s, M_s, m_s, J_s, R_s),
                                                           (v_r, q_r, w_r, F_r, M_r, m_r, J_r, R_r))):
            o = 13 * k
            out[o:o + 3], out[o + 3:o + 6] = v, F / m
            out[o + 6:o + 10] = quaternion_rate(q, w)
            out[o + 10:o + 13] = np.linalg.solve(J, R.T @ M_ext - np.cross(w, J @ w))
        return out

    spin = speed * e
    y0 = np.concatenate([S, np.zeros(3), [0, 0, 0, 1.0], np.zeros(3),
                         C + rho, np.cross(spin, rho), [0, 0, 0, 1.0], spin])
    solution = solve_ivp(rhs, (0, times[-1]), y0, method="DOP853", t_eval=times, rtol=1e-12, atol=1e-14)
    return np.stack([solution.y[:3].T, solution.y[13:16].T], axis=1)


def test_rotor_on_bearings_in_a_stator_moves_as_two_free_bodies():
    model = _two_body_model()
    res = rdm.simulate(model, 0.3, 150.0, drive="free", samples=301, rtol=1e-12, atol=1e-15)
    reference = _two_free_bodies(model, 150.0, res.time[::30])
    stator = model.reference_point + res.displacement[::30, :3]
    np.testing.assert_allclose(stator, reference[:, 0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(res.rotor_centers[::30, 0], reference[:, 1], rtol=0, atol=1e-10)
    relative = res.rotor_centers[:, 0] - model.reference_point - res.displacement[:, :3]
    assert np.ptp(relative[:, 2]) > 1e-4 and np.ptp(res.displacement[:, 2]) > 1e-4   # both moved


# ----------------------------------------------------------------------------------------
# invariants
def test_undamped_rotor_bearing_casing_conserves_energy_over_10_s():
    data = _casing_machine(damping=0.0).to_dict()
    data["gravity"] = [0.0, 0.0, -9.81]
    model = rdm.Model.from_dict(data)
    res = rdm.simulate(model, 10.0, 300.0, drive="free", impulse="hammer-z", impulse_size=20.0, samples=2001,
                       rtol=1e-10, atol=1e-13)
    energy = res.total_energy
    assert np.abs(energy - energy[0]).max() < 1e-8 * energy[0]
    vibration = np.ptp(res.kinetic_energy)
    assert vibration > 1.0 and np.ptp(res.elastic_energy) > 0.5 * vibration   # energy really moved
    assert np.abs(energy - energy[0]).max() < 1e-6 * vibration
    assert np.abs(res.rotor_tilts).max() > 1e-3                                 # the fan tilts in its bearings


def test_free_floating_machine_with_a_rotor_on_bearings_keeps_its_momenta():
    """No mounts, no gravity, free spin: after a kick the casing tumbles and the fan whirls in
    its bearings; the centre of mass moves uniformly and the angular momentum about the fixed
    origin (from positions and orientations by finite differences) stays constant."""
    data = _two_body_model().to_dict()
    data["suspensions"], data["unbalances"], data["gravity"] = [], [], [0.0, 0.0, 0.0]
    data["excitations"] = [{"name": "kick", "position": [0, 0, 0], "direction": [1.0, 0.3, 0.0], "kind": "moment"}]
    for bearing in data["bearings"]:
        bearing.pop("damping", None)
        bearing.pop("axial_damping", None)
    model = rdm.Model.from_dict(data)
    res = rdm.simulate(model, 1.0, 300.0, drive="free", impulse="kick", impulse_size=20.0, samples=8001,
                       rtol=1e-12, atol=1e-14)
    e = model.spin_axis
    roll = res.displacement[:, 3:] @ e
    stator = Rotation.from_rotvec(res.gamma) * Rotation.from_rotvec(np.outer(roll, e))
    rotor = stator * Rotation.from_rotvec(res.rotor_tilts[:, 0]) * Rotation.from_rotvec(
        np.outer(res.rotor_angles[:, 0] - roll, e))
    assert np.ptp(roll) > 1.0 and np.abs(res.rotor_tilts).max() > 1e-4
    dt = res.time[1] - res.time[0]
    masses = [model.stator.mass, model.rotors[0].mass]
    positions = [model.reference_point + res.displacement[:, :3], res.rotor_centers[:, 0]]
    centre = sum(m * p for m, p in zip(masses, positions)) / sum(masses)
    np.testing.assert_allclose(centre, centre[0] + np.outer(res.time, (centre[1] - centre[0]) / dt), atol=1e-9)
    rotor_inertia = (model.rotors[0].diametral_inertia * np.eye(3)
                     + (model.rotors[0].polar_inertia - model.rotors[0].diametral_inertia) * np.outer(e, e))
    momentum = np.zeros((len(res.time), 3))
    for m, p, turn, inertia in zip(masses, positions, (stator, rotor), (model.stator.inertia, rotor_inertia)):
        momentum += m * np.cross(p, np.gradient(p, dt, axis=0, edge_order=2))
        R = turn.as_matrix()
        spin = np.gradient(R, dt, axis=0, edge_order=2) @ np.transpose(R, (0, 2, 1))
        omega = np.stack([spin[:, 2, 1], spin[:, 0, 2], spin[:, 1, 0]], axis=1)
        momentum += np.einsum("tij,jk,tlk,tl->ti", R, inertia, R, omega)
    inner = slice(5, -5)
    change = np.abs(momentum[inner] - momentum[inner][0]).max() / np.linalg.norm(momentum[inner][0])
    fastest = 300.0 + np.abs(res.velocity[:, 3:]).max()
    assert change < 3 * (fastest * dt) ** 2, change


# ----------------------------------------------------------------------------------------
# the linear model
@pytest.mark.parametrize("table", [False, True])
@pytest.mark.parametrize("speed", [0.0, 314.0, -500.0])
def test_linearisation_equals_the_linear_rotor_bearing_casing_model(table, speed):
    model = _casing_machine(table=table, cross_coupled=True)
    A = rdm.simulation.linearize(model, speed)
    reference = speed_linear_form(model).at(speed)
    assert A.shape == reference.shape == (2 * 11, 2 * 11)
    assert np.abs(A - reference).max() < 1e-8 * np.abs(reference).max()


def test_linearisation_of_a_rotor_on_bearings_to_the_ground():
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    A = rdm.simulation.linearize(model, OMEGA0)
    reference = speed_linear_form(model).at(OMEGA0)
    assert A.shape == (10, 10)
    assert np.abs(A - reference).max() < 1e-8 * np.abs(reference).max()


def test_small_impulse_on_the_rotor_equals_the_linear_response():
    """Undamped machine at 300 rad/s, the fan hit on its nose: every sensor (casing
    accelerometers, proximity probes, a point of the fan) against python-control."""
    model = _casing_machine(damping=0.0, probes=True)
    data = model.to_dict()
    data["unbalances"] = []
    model = rdm.Model.from_dict(data)
    speed, size = 300.0, 0.01
    res = rdm.simulate(model, 0.3, speed, impulse="fan-hit-y", impulse_size=size, samples=601, rtol=1e-11, atol=1e-15)
    column = [x.name for x in model.excitations].index("fan-hit-y")
    linear = control.impulse_response(model.state_space(speed), T=res.time, input=column)
    expected = size * np.atleast_2d(np.squeeze(linear.outputs)).T
    peak = np.abs(expected).max(axis=0)
    assert np.all(peak > 1e-7)
    difference = np.abs(res.sensors - expected).max(axis=0)
    rotation = max(np.abs(res.displacement[:, 3:]).max(), np.abs(res.rotor_tilts).max())
    assert np.all(difference < 5 * rotation * peak), (difference / peak, rotation)
    assert np.all(difference < 1e-3 * peak)


def test_steady_unbalance_orbits_at_the_probes_equal_the_linear_unbalance_response():
    """Constant speed, damped machine: after the transient the harmonic at each rotor's own
    frequency of every sensor (probes included) equals ``rdm.unbalance_response``."""
    model = _casing_machine(damping=10.0, table=True, probes=True)
    speed = rdm.rpm(3000.0)
    res = rdm.simulate(model, 1.2, speed, samples=12001, rtol=1e-10, atol=1e-14)
    assert_steady_harmonics_equal_the_linear_response(res, model, speed, after=0.7, rtol=1e-4)


# ----------------------------------------------------------------------------------------
# backends, bad input
def test_numpy_and_numba_backends_agree_on_a_bearing_model():
    model = _casing_machine(table=True, cross_coupled=True)
    runs = [rdm.simulate(model, 0.05, 300.0, drive="ramp", final_speed=400.0, samples=6, backend=b,
                         rtol=1e-12, atol=1e-14) for b in ("numpy", "numba")]
    np.testing.assert_allclose(runs[0].states, runs[1].states, rtol=0, atol=1e-10)
    np.testing.assert_allclose(runs[0].bearing_forces, runs[1].bearing_forces, rtol=1e-9, atol=1e-9)


def test_a_given_journal_load_is_refused_with_the_way_out():
    data = _casing_machine().to_dict()
    data["bearings"][1] = {"name": "fan-NDE", "rotor": "fan", "position": [-0.45, 0.0, 0.25], "type": "journal",
                           "diameter": 0.05, "length": 0.02, "clearance": 5e-5, "viscosity": 0.02, "load": 40.0,
                           "load_direction": [0.0, 0.0, -1.0]}
    with pytest.raises(InputError, match=r"\[bearings.fan-NDE\] load = 40: .*weight it carries under the model's "
                       r"gravity.*leave load out"):
        rdm.simulate(rdm.Model.from_dict(data), 0.1, 300.0)


def test_speed_outside_a_bearing_table_is_refused():
    model = _casing_machine(table=True)
    with pytest.raises(InputError, match=r"fan-NDE.*outside the coefficient table.*run-up|fan-NDE.*outside"):
        rdm.simulate(model, 0.1, 0.0, drive="ramp", final_speed=rdm.rpm(20000.0))


# ----------------------------------------------------------------------------------------
# plain journal bearings: the oil film's nonlinear force
JOURNAL_ROTOR = EXAMPLES / "journal_rotor.toml"


def _journal_rotor():
    data = rdm.load_model(JOURNAL_ROTOR).to_dict()
    data["unbalances"] = []
    return rdm.Model.from_dict(data)


def test_film_force_equals_the_pressure_integrated_by_quadrature():
    """The closed-form film force (Sommerfeld's substitution over the positive-pressure arc)
    against ``journal_reference.film_force`` (quadrature of the short-bearing pressure), at
    random journal positions up to eccentricity 0.97, velocities and speeds of both signs."""
    from journal_reference import Bearing, film_force as by_quadrature

    from rotordyn_modal.simulation._kernels import film_force

    bearing = Bearing(diameter=0.05, length=0.025, clearance=5e-5, viscosity=0.02)
    film = np.array([bearing.radius, bearing.length, bearing.clearance, bearing.viscosity])
    axes = np.array([[0.0, 0.6, -0.8], [0.0, 0.8, 0.6]])       # x, y normal to e = x, x × y = e
    rng = np.random.default_rng(11)
    for _ in range(60):
        position = rng.normal(size=2)
        position *= rng.uniform(0.0, 0.97) * bearing.clearance / np.linalg.norm(position)
        velocity = rng.normal(size=2) * bearing.clearance * 10.0 ** rng.uniform(0, 3.5)
        speed = rng.choice([-1.0, 1.0]) * rng.uniform(10.0, 3000.0)
        force = film_force(position @ axes, velocity @ axes, speed, axes, film)
        expected = by_quadrature(bearing, position, velocity, speed)
        np.testing.assert_allclose(axes @ force, expected, rtol=0, atol=1e-10 * np.abs(expected).max())
        assert abs(force @ [1.0, 0.0, 0.0]) < 1e-12 * np.abs(expected).max()


def test_compiled_and_plain_kernels_agree_with_journal_bearings():
    from rotordyn_modal.simulation._fast import pack, rhs_flat
    from rotordyn_modal.simulation._kernels import plain_namespace
    from rotordyn_modal.simulation._system import system_arrays
    from rotordyn_modal.simulation.simulate import kernels

    system = system_arrays(rdm.load_model(JOURNAL_ROTOR))
    rng = np.random.default_rng(2)
    states = rng.normal(size=(5, 2 * system.n_dof)) * 1e-5
    states[:, system.n_dof:] *= 1e3
    states[:, -1] = rng.uniform(200.0, 2000.0, 5)
    for mode in (0, 1):
        extra = (mode, 7.0, 0.0, 1.0)
        for y in states:
            plain = plain_namespace().rhs(0.5, y, *system.kernel_arguments(), *extra)
            assert np.all(np.isfinite(plain))
            np.testing.assert_allclose(rhs_flat(0.5, y, *pack(system, *extra)), plain, rtol=1e-11,
                                       atol=1e-11 * np.abs(plain).max())
        arguments = system.kernel_arguments() + extra
        times = np.linspace(0.1, 0.5, len(states))
        for a, b in zip(plain_namespace().sample_outputs(times, states, *arguments),
                        kernels("numba").sample_outputs(times, states, *arguments)):
            np.testing.assert_allclose(b, a, rtol=1e-11, atol=1e-11 * np.abs(a).max(initial=1.0))


@pytest.mark.parametrize("speed", [300.0, 800.0])
def test_linearised_oil_film_equals_the_short_bearing_coefficients(speed):
    """About the static equilibrium under gravity the nonlinear film's Jacobian is the linear
    model's (the eight closed-form coefficients of ``rotordyn_modal.elements.journal_bearing``)."""
    model = rdm.load_model(JOURNAL_ROTOR)
    A = rdm.simulation.linearize(model, speed, step=1e-9)
    reference = speed_linear_form(model).at(speed)
    assert np.abs(A - reference).max() < 1e-8 * np.abs(reference).max()


@pytest.mark.parametrize("fraction, size, duration", [(0.8, 0.002, 0.3), (1.2, 0.0005, 0.2)])
def test_journal_rotor_below_and_above_the_oil_whirl_threshold_follows_the_linear_model(fraction, size, duration):
    """From static equilibrium, a tap on the shaft: below the threshold (Lund's, from
    ``rdm.stability``) the whirl dies out, above it grows at half speed, and while the orbit is
    small against the clearance both equal python-control's impulse response of the linear
    model (the difference of the size of the orbit over the clearance)."""
    model = _journal_rotor()
    threshold = rdm.stability(model, rdm.rpm(np.linspace(500, 20000, 40))).threshold_speed
    speed = fraction * threshold
    res = rdm.simulate(model, duration, speed, initial="equilibrium", impulse="shaft-tap-z", impulse_size=size,
                       samples=1001, rtol=1e-11, atol=1e-15)
    column = [x.name for x in model.excitations].index("shaft-tap-z")
    linear = control.impulse_response(model.state_space(speed), T=res.time, input=column)
    expected = size * np.atleast_2d(np.squeeze(linear.outputs)).T
    moved = res.sensors - res.sensors[0]                      # about the equilibrium
    peak = np.abs(expected).max(axis=0)
    orbit = np.abs(moved).max() / 5e-5                          # against the radial clearance
    assert np.all(np.abs(moved - expected).max(axis=0) < 3 * orbit * peak)
    change = np.abs(moved[-100:]).max() / np.abs(moved[:200]).max()
    assert (change < 1e-2) if fraction < 1 else (change > 1e2)


def test_journal_that_cannot_carry_its_load_is_reported_not_integrated_forever():
    """At rest the film has no wedge: the journal sinks into its bearing; the simulation stops
    with one clear message, not a traceback."""
    with pytest.raises(InputError, match=r"journal bearings \(eccentricity at the last output time: "
                       r"\[bearings.DE\] 0\.\d+.*bearing wall.*initial='equilibrium'"):
        rdm.simulate(_journal_rotor(), 0.4, 0.0, samples=41)
