"""``simulate`` of machines with flexible rotors: the linear time model (docs/simulate.md,
"Flexible rotors"). Truths from outside the time model: the linear steady unbalance response,
the energy of an undamped gyroscopic system (gyroscopic forces do no work), the Campbell
diagram's critical speed, and the linear model's own matrices."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from steady_harmonics import assert_steady_harmonics_equal_the_linear_response

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
DISKS = [{"name": "disk", "axial_position": 0.3, "mass": 10.0, "polar_inertia": 0.05, "diametral_inertia": 0.03},
         {"name": "collar-A", "axial_position": 0.0, "mass": 2.0, "polar_inertia": 0.004, "diametral_inertia": 0.01},
         {"name": "collar-B", "axial_position": 0.6, "mass": 2.0, "polar_inertia": 0.004, "diametral_inertia": 0.01}]
MOUNTS = [[0, 0.2, -0.2], [0, -0.2, -0.2], [0.6, 0.2, -0.2], [0.6, -0.2, -0.2]]


def _machine(damping=1.0, casing=True, gear=True, anisotropic=True):
    """A flexible shaft (two Euler-Bernoulli elements, a disk at mid-span, collars at the
    bearings) on two damped bearings, in a casing on four mounts beside a rigid gear on
    bearings turning at -1.5 times the shaft with a couple unbalance; ``damping`` scales every
    damper (0: undamped)."""
    data = {
        "name": "small", "reference_rotor": "shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
        "rotors": [{"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": "none",
                    "shaft": [{"length": 0.3, "outer_diameter": 0.03, "material": "steel", "elements": 1}] * 2,
                    "disks": DISKS}],
        "bearings": [{"name": "A", "rotor": "shaft", "axial_position": 0.0,
                      "stiffness": [1.0e6, 1.3e6] if anisotropic else 1.1e6, "damping": 800.0 * damping},
                     {"name": "B", "rotor": "shaft", "axial_position": 0.6, "stiffness": 1.1e6,
                      "damping": 800.0 * damping}],
        "unbalances": [{"rotor": "shaft", "amount": 1e-4, "axial_position": 0.3, "phase_deg": 30.0}],
        "sensors": [{"name": "disk-y", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 1, 0]},
                    {"name": "disk-z", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 0, 1]},
                    {"name": "probe-A-y", "rotor": "shaft", "measure": "relative", "axial_position": 0.0,
                     "direction": [0, 1, 0]}],
        "excitations": [{"name": "hammer", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 0.6, 0.8]}],
    }
    if casing:
        data["stator"] = {"mass": 40.0, "inertia": [1.0, 1.5, 1.6], "center_of_mass": [0.3, 0.0, -0.1]}
        data["suspensions"] = [{"name": f"m{i}", "position": p, "stiffness": [2e5, 2.2e5, 3e5],
                                "damping": [300.0 * damping] * 3} for i, p in enumerate(MOUNTS)]
        data["sensors"].append({"name": "casing-z", "position": [0.6, 0.1, 0.0], "direction": [0, 0, 1]})
    if gear:
        data["rotors"].append({"name": "gear", "speed_ratio": -1.5, "mass": 3.0, "center_of_mass": [0.3, 0.15, 0.0],
                               "polar_inertia": 0.01, "diametral_inertia": 0.008})
        data["bearings"].append({"name": "G", "rotor": "gear", "position": [0.3, 0.15, 0.0], "stiffness": 5e6,
                                 "moment_stiffness": 2e4, "damping": 500.0 * damping,
                                 "moment_damping": 2.0 * damping})
        data["unbalances"].append({"rotor": "gear", "amount": 5e-5, "axial_offset": 0.02, "phase_deg": -40.0})
        data["sensors"].append({"name": "gear-y", "rotor": "gear", "position": [0.3, 0.15, 0.0],
                                "direction": [0, 1, 0]})
    return rdm.Model.from_dict(data, source="small.toml")


def test_steady_unbalance_orbits_equal_the_linear_unbalance_response():
    """Constant speed, damped machine (flexible shaft, casing on mounts, a rigid gear turning the
    other way with a couple unbalance), every mode kept: after the transient every sensor's
    harmonic at each rotor's own frequency equals ``rdm.unbalance_response`` to 1e-6."""
    model = _machine(damping=5.0)
    speed = 300.0
    res = rdm.simulate(model, 0.5, speed, modes_below=np.inf, samples=2001, rtol=1e-10, atol=1e-14)
    assert_steady_harmonics_equal_the_linear_response(res, model, speed, after=0.4, rtol=1e-6)


def test_undamped_spinning_machine_keeps_its_energy():
    """No damping, no unbalance, constant speed, a hammer blow on the disk: the small motions'
    energy q'^T M q' / 2 + q^T K q / 2 (the linear model's own matrices) stays constant to the
    integrator's tolerance, while the spin changes the motion (gyroscopic forces, which do no
    work, are at work)."""
    data = _machine(damping=0.0).to_dict()
    data["unbalances"] = []
    model = rdm.Model.from_dict(data)
    M, C, G, K = model.matrices(0.0)
    assert not C.any() and np.abs(G).max() > 0
    runs = [rdm.simulate(model, 0.2, speed, impulse="hammer", impulse_size=0.5, samples=401, rtol=1e-11,
                         atol=1e-14) for speed in (0.0, 800.0)]
    n = model.dofs.n
    for res in runs:
        q, dq = res.states[:, :n], res.states[:, n:]
        energy = 0.5 * np.einsum("ti,ij,tj->t", dq, M, dq) + 0.5 * np.einsum("ti,ij,tj->t", q, K, q)
        assert energy[0] > 0
        assert np.abs(energy - energy[0]).max() < 1e-8 * energy[0]
        np.testing.assert_allclose(res.total_energy, energy, rtol=1e-9)
    difference = np.abs(runs[1].sensor("disk-z") - runs[0].sensor("disk-z")).max()
    assert difference > 0.05 * np.abs(runs[0].sensor("disk-z")).max()


def test_run_up_passes_the_first_critical_speed_where_the_campbell_diagram_says():
    """A run-up through the forward critical speed of a flexible shaft on isotropic bearings:
    the order-tracked 1x amplitude peaks at the Campbell diagram's critical speed, within the
    speed travelled over one tracking window plus the ramp's delay ``alpha / (zeta w_c)`` (the
    response's envelope lags by its time constant ``1 / (zeta w_c)``)."""
    model = _machine(casing=False, gear=False, anisotropic=False)
    critical = rdm.campbell(model, np.linspace(0.0, 400.0, 81)).critical
    forward = [k for k, w in enumerate(critical.whirl) if w == "forward"][0]
    speed, zeta = critical.speeds[forward], critical.damping_ratios[forward]
    assert 200.0 < speed < 350.0
    alpha = 100.0
    res = rdm.simulate(model, 1.5, 200.0, drive="ramp", final_speed=350.0, samples=3001)
    track = res.order_track("disk-y")
    peak = int(np.argmax(track.amplitude))
    window = track.speeds[peak + 1] - track.speeds[peak]
    delay = alpha / (zeta * speed)
    assert speed - window <= track.speeds[peak] <= speed + window + delay, (track.speeds[peak], speed, window, delay)
    steady = np.abs(rdm.unbalance_response(model, np.linspace(200.0, 350.0, 301)).response[0, 0]).max()
    assert 0.7 * steady < track.amplitude[peak] < steady                 # passed too fast to build up fully


def test_a_flexible_machine_in_free_spin_or_on_a_journal_bearing_with_a_given_load_is_refused_by_one_line():
    """Free spin stays refused; a journal bearing is simulated (tests/test_simulate_flexible_journal.py)
    with the load gravity puts on it, so a given ``load`` is refused as in the large-rotation model."""
    model = _machine()
    with pytest.raises(InputError, match="free spin") as error:
        rdm.simulate(model, 0.1, 100.0, drive="free")
    assert "\n" not in str(error.value)
    data = model.to_dict()
    data["bearings"][0] = {"name": "A", "rotor": "shaft", "axial_position": 0.0, "type": "journal",
                           "diameter": 0.03, "length": 0.015, "clearance": 3e-5, "viscosity": 0.02, "load": 80.0,
                           "load_direction": [0.0, 0.0, -1.0]}
    with pytest.raises(InputError, match=r"\[bearings.A\] load = 80: the time simulation loads a journal") as error:
        rdm.simulate(rdm.Model.from_dict(data, source="small.toml"), 0.1, 100.0)
    assert "\n" not in str(error.value)


def test_a_run_up_from_rest_starts_with_the_unbalances_tangential_force():
    """From standstill the unbalance's force is its angular acceleration term alone: the
    eccentric mass ``m`` at ``eps`` is accelerated by ``eps alpha`` along ``t = -sin(phase) a +
    cos(phase) b`` and pulls the rotor back by ``U alpha`` along ``-t`` (Newton: the centre of mass
    ``x + eps r(theta)`` moves only by the bearings' forces); and the casing takes the reaction
    of the torque that spins the rotor up, ``-J_p alpha`` about the spin axis. At first the
    machine moves as ``M^-1 f t^2 / 2``, with M, the sensor rows and the force columns of a point
    force at the unbalance and of a moment on the casing taken from the linear model."""
    from rotordyn_modal.analysis.unbalance import phase_reference
    from rotordyn_modal.assembly import excitation_columns, sensor_rows

    data = _machine(gear=False).to_dict()
    a, b = phase_reference(data["spin_axis"])
    phase = np.radians(data["unbalances"][0]["phase_deg"])
    data["excitations"] = [{"name": "tangential", "rotor": "shaft", "axial_position": 0.3,
                            "direction": (-np.sin(phase) * a + np.cos(phase) * b).tolist()},
                           {"name": "roll", "kind": "moment", "position": [0.3, 0.0, 0.0], "direction": [1.0, 0.0, 0.0]}]
    model = rdm.Model.from_dict(data)
    alpha, t = 1e4, 1e-5                          # t far below the fastest mode's period (1.6 ms)
    res = rdm.simulate(model, 2 * t, 0.0, drive="ramp", final_speed=2 * t * alpha, samples=3, modes_below=np.inf,
                       rtol=1e-12, atol=1e-20)
    columns = excitation_columns(model)
    force = -alpha * (data["unbalances"][0]["amount"] * columns[:, 0] + model.rotors[0].polar_inertia * columns[:, 1])
    expected = sensor_rows(model) @ np.linalg.solve(model.matrices(0.0).M, force) * t ** 2 / 2
    np.testing.assert_allclose(res.sensors[1], expected, rtol=1e-2, atol=1e-3 * np.abs(expected).max())


def test_linear_time_model_of_a_rigid_machine_follows_the_nonlinear_simulation(examples_dir):
    """The time model of flexible machines run on a rigid one (the belt-driven fan on bearings in
    its casing on mounts, without gravity) through the start of a run-up from standstill: it
    follows the nonlinear large-rotation simulation (exact kinematics of the unbalanced rotors
    and the casing) to the size of the neglected terms, which shrink with the motion: the
    tangential unbalance force and the casing's reaction to the torque that spins the rotors up
    are both in it (without either, the motion differs by its own size)."""
    from rotordyn_modal.simulation.flexible import simulate_linear

    data = rdm.load_model(examples_dir / "fan_on_bearings.toml").to_dict()
    data["gravity"] = [0.0, 0.0, 0.0]
    model = rdm.Model.from_dict(data)
    errors = []
    for top in (30.0, 60.0):             # the casing's roll (and the neglected terms) grow with the ramp
        nonlinear = rdm.simulate(model, 0.05, 0.0, drive="ramp", final_speed=top, samples=101, rtol=1e-10,
                                 atol=1e-14)
        linear = simulate_linear(model, 0.05, 0.0, drive="ramp", final_speed=top, initial="rest", impulse=None,
                                 impulse_size=1.0, samples=101, rtol=1e-10, atol=1e-14, unbalance_phases_deg=None,
                                 modes_below=np.inf, progress=False)
        errors.append(np.abs(linear.sensors - nonlinear.sensors).max() / np.abs(nonlinear.sensors).max())
    assert errors[0] < 1e-2 and errors[1] > 1.5 * errors[0], errors


@pytest.mark.parametrize("table", [False, True])
def test_right_hand_sides_are_the_linear_models_equations(table):
    """At any time of a ramp the reduced equations (every mode kept) are ``V^T`` times the linear
    model's ``f - (C(w) + w G) q' - K(w) q`` with its matrices at the drive speed ``w`` (a bearing
    of the gear, turning at -1.5 times the drive, tabulated over speed); the compiled and the
    numpy right-hand sides agree."""
    from rotordyn_modal.simulation import flexible

    data = _machine().to_dict()
    data["unbalances"] = []
    if table:
        data["bearings"][2].update(speeds_rpm=[-6000.0, 0.0, 6000.0], stiffness=[4e6, 5e6, 7e6],
                                   damping=[400.0, 500.0, 700.0], moment_stiffness=[2e4] * 3,
                                   moment_damping=[2.0] * 3)
    model = rdm.Model.from_dict(data)
    speed, accel = 100.0, 300.0
    system = flexible.reduced_system(model, speed, np.inf)
    V, r = system.V, system.size
    plain = flexible._right_hand_side(system, speed, accel)
    rng = np.random.default_rng(1)
    for t in (0.0, 0.37, 0.8):
        y = rng.normal(size=2 * r)
        w = speed + accel * t
        M, C, G, K = model.matrices(w)
        q, dq = V @ y[:r], V @ y[r:]
        expected = V.T @ (-(C + w * G) @ dq - K @ q + accel * flexible.drive_reaction(model))
        got = plain(t, y)
        np.testing.assert_allclose(got[:r], y[r:], rtol=0, atol=0)
        np.testing.assert_allclose(got[r:], expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        if not table:
            compiled = flexible.linear_rhs(t, y, *flexible._packed(system, speed, accel))
            np.testing.assert_allclose(compiled, got, rtol=1e-12, atol=1e-12 * np.abs(got).max())


def test_the_flexible_kernel_announces_its_first_compilation(monkeypatch):
    """Before numba compiles the flexible path's right-hand side the user is told (issue 27: a
    silent ~20 s wait); the announcement is given the dispatcher that is about to run."""
    pytest.importorskip("numba")
    import rotordyn_modal.simulation.flexible as flexible

    seen = []
    monkeypatch.setattr(flexible, "announce_compilation", lambda kn: seen.append(kn.rhs_flat) or False)
    rdm.simulate(_machine(), 0.01, 100.0, samples=3, backend="numba")
    assert len(seen) == 1 and seen[0] is flexible._compiled("numba")
