"""Large-rotation simulation against independent answers: a quaternion integration of the
document's example, energy conservation, the linear model of seed 000 (state matrix and
impulse response), and bad input."""

from __future__ import annotations

import pickle

import control
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import rotordyn_modal as rdm
from rotordyn_modal.model.geometry import point_force_column
from rotordyn_modal.errors import InputError
from rotordyn_modal.linear_system import speed_linear_form
from steady_harmonics import assert_steady_harmonics_equal_the_linear_response

OMEGA0 = 50.0


@pytest.fixture(scope="module")
def example(request):
    from pathlib import Path

    return rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "spring_block_rotor.toml")


@pytest.fixture(scope="module")
def gear_machine():
    from pathlib import Path

    return rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml")


def _without(model, **changes):
    data = model.to_dict()
    data.update(changes)
    return rdm.Model.from_dict(data, model.source)


def _quaternion_reference(times):
    """Seed 001, section 4, integrated independently: quaternion, body-frame Euler equations.

    Disk m = 5 kg, D = 0.5 m; rod end a at l = 0.75 m behind the centre along the body x axis;
    force -C1 r_a at a, moment -C2 gamma with gamma the rotation about e x f taking
    e = x to the rod's direction f by the shortest arc; gravity -z; spin 50 rad/s about x.
    """
    m, D, l, C1, C2, g = 5.0, 0.5, 0.75, 2000.0, 500.0, 9.81
    inertia = np.array([m * D**2 / 8, m * D**2 / 16, m * D**2 / 16])
    e = np.array([1.0, 0, 0])

    def rhs(t, y):
        r, v, quat, w_body = y[:3], y[3:6], y[6:10], y[10:]
        R = Rotation.from_quat(quat).as_matrix()
        f = R @ e
        r_a = r - l * f
        axis = np.cross(e, f)
        angle = np.arctan2(np.linalg.norm(axis), e @ f)
        gamma = axis * (angle / np.linalg.norm(axis)) if np.linalg.norm(axis) > 0 else np.zeros(3)
        force = -C1 * r_a
        moment = np.cross(r_a - r, force) - C2 * gamma
        moment_body = R.T @ moment
        w_dot = (moment_body - np.cross(w_body, inertia * w_body)) / inertia
        x, yq, z, s = quat  # scipy order (x, y, z, w): dq/dt = q (x) [w/2, 0]
        wx, wy, wz = w_body / 2
        q_dot = np.array([s * wx + yq * wz - z * wy, s * wy + z * wx - x * wz,
                          s * wz + x * wy - yq * wx, -x * wx - yq * wy - z * wz])
        return np.concatenate([v, force / m + [0, 0, -g], q_dot, w_dot])

    y0 = np.concatenate([[l, 0, 0], [0, 0, 0], [0, 0, 0, 1.0], [OMEGA0, 0, 0]])
    sol = solve_ivp(rhs, (0, times[-1]), y0, method="DOP853", t_eval=times, rtol=1e-12, atol=1e-13)
    return sol.y[:3].T


@pytest.fixture(scope="module")
def example_run(example):
    return rdm.simulate(example, 3.0, OMEGA0, drive="free", samples=301, rtol=1e-11, atol=1e-13)


def test_example_matches_a_quaternion_integration(example_run):
    times = example_run.time[::50]
    reference = _quaternion_reference(times)
    np.testing.assert_allclose(example_run.rotor_centers[::50, 0, :], reference, atol=1e-9, rtol=0)
    assert np.abs(reference - reference[0]).max() > 0.05  # the disk really moved


def test_example_keeps_its_axial_speed_and_energy(example_run):
    deviation = np.abs(example_run.spin_speed / OMEGA0 - 1)
    assert 1e-5 < deviation.max() < 1e-3  # seed 001, Fig. 6: varies, below 0.1 %
    energy = example_run.total_energy
    assert np.abs(energy - energy[0]).max() < 1e-9 * example_run.kinetic_energy[0]
    assert np.ptp(example_run.kinetic_energy) > 1.0  # energy really moved between its terms
    assert abs(energy[0] - 0.5 * 5 * 0.5**2 / 8 * OMEGA0**2 + 5 * 0 * 9.81) < 1e-12


def test_time_history_figure_has_the_documents_panels(example_run):
    fig = example_run.plot()
    titles = [ax.get_title() for ax in fig.axes]
    assert any("Path" in t for t in titles) and any("Energy" in t for t in titles)
    assert any("Axial angular velocity" in t for t in titles)


def test_result_pickles_and_tabulates(example_run):
    copy = pickle.loads(pickle.dumps(example_run))
    np.testing.assert_array_equal(copy.states, example_run.states)
    table = example_run.to_dataframe()
    assert list(table.columns[:9]) == ["time_s", "u_x", "u_y", "u_z", "theta_x", "theta_y", "theta_z",
                                       "spin_speed_rad_s", "drive_torque_nm"]
    assert len(table) == len(example_run.time)
    # each column is the result's own array
    np.testing.assert_array_equal(table["potential_energy_j"], example_run.elastic_energy + example_run.gravity_energy)
    np.testing.assert_array_equal(table["total_energy_j"], example_run.total_energy)
    for j, name in enumerate(example_run.rotor_names):
        for k, axis in enumerate("xyz"):
            np.testing.assert_array_equal(table[f"{name}_center_{axis}"], example_run.rotor_centers[:, j, k])


def test_the_table_holds_each_bearings_forces(examples_dir):
    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    run = rdm.simulate(model, 0.02, 100.0, samples=21, initial="equilibrium")
    table = run.to_dataframe()
    assert len(run.bearing_names) == 4
    for j, name in enumerate(run.bearing_names):
        for k, component in enumerate(("Fx", "Fy", "Fz", "Mx", "My", "Mz")):
            np.testing.assert_array_equal(table[f"{name}_{component}"], run.bearing_forces[:, j, k])
    assert len({tuple(run.bearing_forces[-1, j]) for j in range(4)}) == 4        # four different bearings


@pytest.mark.parametrize("name", ["spring_block_rotor.toml", "spring_block_rotor_suspension.toml", "gear_machine.toml",
                                  "fan_on_bearings.toml"])
def test_compiled_and_plain_right_hand_sides_agree(name):
    """The allocation-free compiled kernel and the readable numpy one, at random states."""
    from pathlib import Path

    from rotordyn_modal.simulation._fast import pack, rhs_flat
    from rotordyn_modal.simulation._kernels import plain_namespace
    from rotordyn_modal.simulation._system import system_arrays

    system = system_arrays(rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / name))
    rng = np.random.default_rng(5)
    for mode in (0, 1):
        extra = (mode, 7.0, 0.0, 1.0)
        for _ in range(5):
            y = rng.normal(size=2 * system.n_dof) * 0.4
            plain = plain_namespace().rhs(0.5, y, *system.kernel_arguments(), *extra)
            np.testing.assert_allclose(rhs_flat(0.5, y, *pack(system, *extra)), plain, rtol=1e-12,
                                       atol=1e-12 * np.abs(plain).max())


@pytest.mark.parametrize("name", ["spring_block_rotor_suspension.toml", "gear_machine.toml", "fan_on_bearings.toml"])
def test_compiled_and_plain_derived_outputs_agree(name):
    """Energies, drive torque, angular velocity and bearing forces per sample: the compiled
    allocation-light loop against the readable numpy kernels, at random states."""
    from pathlib import Path

    from rotordyn_modal.simulation._kernels import plain_namespace
    from rotordyn_modal.simulation._system import system_arrays
    from rotordyn_modal.simulation.simulate import kernels

    system = system_arrays(rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / name))
    states = np.random.default_rng(7).normal(size=(4, 2 * system.n_dof)) * 0.4
    times = np.array([0.1, 0.5, 0.9, 1.5])
    for mode in (0, 1):
        arguments = system.kernel_arguments() + (mode, 7.0, 0.0, 1.0)
        plain = plain_namespace().sample_outputs(times, states, *arguments)
        compiled = kernels("numba").sample_outputs(times, states, *arguments)
        for a, b in zip(plain, compiled):
            np.testing.assert_allclose(b, a, rtol=1e-11, atol=1e-11 * np.abs(a).max(initial=1.0))


def test_numpy_and_numba_backends_give_the_same_motion(example):
    runs = [rdm.simulate(example, 0.5, OMEGA0, drive="free", samples=6, backend=b, rtol=1e-12, atol=1e-14)
            for b in ("numpy", "auto")]
    np.testing.assert_allclose(runs[0].states, runs[1].states, rtol=0, atol=1e-10)


@pytest.mark.parametrize("speed", [0.0, 314.0, -500.0])
def test_linearisation_reproduces_the_core_state_matrix(gear_machine, speed):
    A = rdm.simulation.linearize(gear_machine, speed)
    reference = speed_linear_form(gear_machine).at(speed)
    assert np.abs(A - reference).max() < 1e-8 * np.abs(reference).max()


def test_small_impulse_response_equals_the_linear_one(gear_machine):
    """Undamped, spinning two-rotor gear machine hit by a hammer: nonlinear vs python-control."""
    model = _without(gear_machine, unbalances=[], suspensions=[
        {k: v for k, v in s.items() if k != "damping"} for s in gear_machine.to_dict()["suspensions"]])
    speed, size, duration = 300.0, 0.05, 0.3
    res = rdm.simulate(model, duration, speed, impulse="hammer-z", impulse_size=size, samples=601,
                       rtol=1e-11, atol=1e-15)
    system = model.state_space(speed)
    column = [x.name for x in model.excitations].index("hammer-z")
    linear = control.impulse_response(system, T=res.time, input=column)
    expected = size * np.atleast_2d(np.squeeze(linear.outputs)).T
    peak = np.abs(expected).max()
    nonlinear = res.sensors - res.sensors[0]
    difference = np.abs(nonlinear - expected).max()
    assert peak > 1e-6
    # the neglected terms are quadratic in the motion: relative error of order |theta|
    rotation = np.abs(res.displacement[:, 3:]).max()
    assert difference < 5 * rotation * peak
    assert difference < 1e-3 * peak


def test_drive_torque_supplies_the_energy_of_a_run_up(gear_machine):
    """With an ideal drive, d(energy)/dt = drive torque x relative speed (no damping)."""
    model = _without(gear_machine, suspensions=[
        {k: v for k, v in s.items() if k != "damping"} for s in gear_machine.to_dict()["suspensions"]])
    res = rdm.simulate(model, 0.5, 0.0, drive="ramp", final_speed=400.0, samples=2001, rtol=1e-10)
    work = np.concatenate([[0], np.cumsum(np.diff(res.time) * 0.5 * (
        res.drive_torque[1:] * res.drive_speed[1:] + res.drive_torque[:-1] * res.drive_speed[:-1]))])
    energy = res.total_energy - res.total_energy[0]
    assert np.abs(energy - work).max() < 1e-4 * np.abs(energy).max()
    np.testing.assert_allclose(res.drive_speed, 800.0 * res.time, atol=1e-9)


def test_run_up_order_tracking_peaks_near_a_critical_speed(gear_machine):
    model = _without(gear_machine, excitations=[])
    res = rdm.simulate(model, 1.5, 0.0, drive="ramp", final_speed=400.0, samples=6001, rtol=1e-8)
    track = res.order_track("acc-top-z", rotor="fan")
    fall = res.waterfall("acc-top-z", segments=30)
    assert fall.amplitude.shape == (len(fall.speeds), len(fall.frequencies_hz)) and len(fall.speeds) >= 30
    assert np.all(np.diff(track.speeds) > 0) and track.amplitude.max() > 0
    critical = rdm.campbell(model, np.linspace(1, 400, 81), orders=(1,)).critical
    fan = critical.speeds[critical.source == "fan"]
    peak_speed = track.speeds[np.argmax(track.amplitude)]
    assert np.min(np.abs(fan - peak_speed)) < 0.15 * peak_speed


def test_hysteretic_loss_factor_is_refused(gear_machine):
    data = gear_machine.to_dict()
    data["suspensions"][0]["loss_factor"] = 0.05
    with pytest.raises(InputError, match="loss_factor = 0.05.*no meaning in the time domain"):
        rdm.simulate(rdm.Model.from_dict(data), 0.1, 100.0)


def test_unknown_excitation_and_bad_options_are_refused(gear_machine):
    with pytest.raises(InputError, match="unknown excitation 'nope'.*hammer-z, shaker-y"):
        rdm.simulate(gear_machine, 0.1, 100.0, impulse="nope")
    with pytest.raises(InputError, match="final_speed"):
        rdm.simulate(gear_machine, 0.1, 100.0, drive="ramp")
    with pytest.raises(InputError, match="drive 'spin'"):
        rdm.simulate(gear_machine, 0.1, 100.0, drive="spin")
    with pytest.raises(InputError, match="duration"):
        rdm.simulate(gear_machine, -1.0, 100.0)


def test_steady_unbalance_orbit_equals_the_linear_unbalance_response(gear_machine):
    """Constant speed, damped (x10) machine: after the transient, every sensor's harmonic at each
    rotor's own frequency equals ``rdm.unbalance_response`` (amplitude and phase)."""
    data = gear_machine.to_dict()
    for suspension in data["suspensions"]:
        suspension["damping"] = [10 * c for c in suspension["damping"]]
    model = rdm.Model.from_dict(data)
    speed = rdm.rpm(3000.0)
    res = rdm.simulate(model, 1.2, speed, samples=12001, rtol=1e-10, atol=1e-14)
    assert_steady_harmonics_equal_the_linear_response(res, model, speed, after=0.7, rtol=1e-4)
    # the order track's last window: the same amplitude and phase, also for the fan, geared at
    # ratio -0.4 (its phase was the linear one's negative: fitted against its falling angle)
    linear = rdm.unbalance_response(model, [speed])
    for i, name in enumerate(linear.outputs):
        for j, rotor in enumerate(linear.sources):
            track = res.order_track(name, rotor=rotor)
            tracked = track.amplitude[-1] * np.exp(1j * np.radians(track.phase_deg[-1]))
            expected = linear.amplitude[i, j, 0] * np.exp(1j * np.radians(linear.phase_deg[i, j, 0]))
            assert abs(tracked - expected) < 1e-3 * abs(expected), (name, rotor, tracked, expected)


def test_free_floating_machine_tumbling_keeps_momenta_and_energy(gear_machine):
    """No suspensions, no gravity, free spin, a large roll impulse: the stator turns more than a
    full turn about the spin axis and wobbles; linear and angular momentum about the fixed origin
    and energy stay constant (computed from positions and orientations, not the simulator's
    velocities)."""
    data = gear_machine.to_dict()
    data["suspensions"], data["unbalances"] = [], []
    data["excitations"] = [{"name": "kick", "position": [0, 0, 0], "direction": [1.0, 0.3, 0.0], "kind": "moment"}]
    model = rdm.Model.from_dict(data)
    res = rdm.simulate(model, 2.0, 300.0, drive="free", impulse="kick", impulse_size=50.0, samples=8001,
                       rtol=1e-12, atol=1e-14)
    assert np.ptp(res.displacement[:, 3:] @ model.spin_axis) > 2 * np.pi   # more than a turn of roll
    assert np.abs(res.gamma).max() > 0.05                      # and a real transverse wobble
    energy = res.total_energy
    assert np.abs(energy - energy[0]).max() < 1e-10 * energy[0]

    e = model.spin_axis
    roll = res.displacement[:, 3:] @ e                          # theta = gamma + psi e, gamma normal to e
    stator = Rotation.from_rotvec(res.gamma) * Rotation.from_rotvec(np.outer(roll, e))
    dt = res.time[1] - res.time[0]
    # bodies: stator centre of mass (reference point) and rotor centres, positions in model axes
    positions = [model.reference_point + res.displacement[:, :3]] + [res.rotor_centers[:, j] for j in range(2)]
    masses = [model.stator.mass] + [r.mass for r in model.rotors]
    centre = sum(m * p for m, p in zip(masses, positions)) / sum(masses)
    drift = centre - (centre[0] + np.outer(res.time, (centre[1] - centre[0]) / dt))
    assert np.abs(drift).max() < 1e-9                           # centre of mass: uniform motion

    matrices = stator.as_matrix()
    spin = np.gradient(matrices, dt, axis=0, edge_order=2) @ np.transpose(matrices, (0, 2, 1))
    omega_s = np.stack([spin[:, 2, 1], spin[:, 0, 2], spin[:, 1, 0]], axis=1)
    momentum = np.zeros((len(res.time), 3))
    for k, (m, p) in enumerate(zip(masses, positions)):
        velocity = np.gradient(p, dt, axis=0, edge_order=2)
        momentum += m * np.cross(p, velocity)
        if k == 0:
            inertia = np.einsum("tij,jk,tlk->til", matrices, model.stator.inertia, matrices)
            momentum += np.einsum("tij,tj->ti", inertia, omega_s)
        else:
            rotor = model.rotors[k - 1]
            axis = matrices @ e
            body = omega_s + np.gradient(res.rotor_angles[:, k - 1] - roll, dt)[:, None] * axis
            inertia = rotor.diametral_inertia * np.eye(3) + (rotor.polar_inertia - rotor.diametral_inertia) \
                * np.einsum("ti,tj->tij", axis, axis)
            momentum += np.einsum("tij,tj->ti", inertia, body)
    inner = slice(5, -5)  # away from the one-sided differences at the ends
    change = np.abs(momentum[inner] - momentum[inner][0]).max() / np.linalg.norm(momentum[inner][0])
    # second-order differences of motions turning at up to |omega| err by about (|omega| dt)^2
    assert change < (np.linalg.norm(omega_s, axis=1).max() * dt) ** 2, change


def test_static_equilibrium_under_gravity_stays_put(gear_machine):
    """Gravity on the gear machine: started in equilibrium the stator does not move; its sag
    equals the linear static deflection K^-1 f_gravity to the nonlinearity's size."""
    model = _without(gear_machine, unbalances=[], gravity=[0.0, 0.0, -9.81])
    res = rdm.simulate(model, 0.2, 200.0, initial="equilibrium", samples=21, rtol=1e-11, atol=1e-14)
    q0 = res.displacement[0]
    np.testing.assert_allclose(res.displacement, np.tile(q0, (21, 1)), atol=1e-12)
    M, C, G, K = model.matrices()
    weight = np.zeros(6)
    for mass, center, _ in rdm.assembly.body_inertias(model):
        weight += mass * 9.81 * point_force_column(center, model.reference_point, [0, 0, -1.0])
    linear = np.linalg.solve(K, weight)
    assert np.abs(q0 - linear).max() < 1e-3 * np.abs(linear).max()
    with pytest.raises(InputError, match="initial 'sideways'"):
        rdm.simulate(model, 0.1, 0.0, initial="sideways")


def test_order_tracking_and_waterfall_give_back_the_amplitude_and_phase_of_a_known_signal():
    """A sensor signal 0.3 cos(2 phi + 0.4) + 0.1 cos(phi) at a constant 100 rad/s: order 2 comes
    back as 0.3 at 0.4 rad, order 1 as 0.1. Windows of four turns (P = 2,513 samples) are cut at
    the nearest samples: each end adds or drops at most one sample of |s| <= 0.4 and the span
    changes by as much, so |c| errs by at most (2 x 2 x 0.4 + 2 |c|) / P (7.2e-4 for order 1,
    8.8e-4 for order 2, its phase 8.8e-4 / 0.3 rad). The waterfall's peak near 2 x 100 / 2 pi
    Hz is 0.3 to within the Hann window's scalloping (the line falls between 4 Hz bins: at most
    15 % low)."""
    from types import SimpleNamespace

    from rotordyn_modal.simulation.runup import order_track, waterfall

    time = np.arange(40000) * 1e-4
    phi = 100.0 * time
    signal = 0.3 * np.cos(2 * phi + 0.4) + 0.1 * np.cos(phi)
    result = SimpleNamespace(time=time, drive_speed=np.full(time.shape, 100.0), rotor_angles=phi[:, None],
                             speed_ratios=np.array([1.0]), rotor_names=["r"], sensor=lambda name: signal)
    second, first = order_track(result, "s", order=2), order_track(result, "s", order=1)
    samples = 2513
    np.testing.assert_allclose(second.amplitude, 0.3, rtol=0, atol=(1.6 + 0.6) / samples)
    np.testing.assert_allclose(np.radians(second.phase_deg), 0.4, atol=(1.6 + 0.6) / samples / 0.3)
    np.testing.assert_allclose(first.amplitude, 0.1, rtol=0, atol=(1.6 + 0.2) / samples)
    np.testing.assert_allclose(second.speeds, 100.0, rtol=1e-12)
    fall = waterfall(result, "s", segments=61)            # pieces of 2,500 samples: 4 Hz lines
    line = int(np.argmin(np.abs(fall.frequencies_hz - 200.0 / (2 * np.pi))))
    assert abs(fall.frequencies_hz[line] - 200.0 / (2 * np.pi)) < 2.0
    assert 0.85 * 0.3 <= fall.amplitude[:, line].max() <= 0.3 * 1.001
