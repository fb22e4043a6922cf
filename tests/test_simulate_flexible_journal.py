"""``simulate`` of a flexible rotor on plain journal bearings: the linear structure with the
oil films' nonlinear short-bearing force (docs/theory.md §19, "Journal bearings in the linear
time model"). Truths from outside the time model: the short-bearing static equilibrium by
quadrature of the pressure (tests/journal_reference.py), the linear unbalance response and the
roots of the linear model (``rdm.unbalance_response``, ``rdm.modal``, ``rdm.stability``: the
journal bearings linearised at their static load)."""

from __future__ import annotations

import functools

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
CLEARANCE = 4e-5
DISK, COLLAR = 8.0, 1.5


def _machine(diameter=0.025, unbalance=0.0, elements=2):
    """A steel shaft 0.6 m long (``diameter``), a disk of 8 kg at mid-span, collars of 1.5 kg at
    the two plain journal bearings at its ends (L/D = 0.5, clearance 40 um, 0.02 Pa s), on the
    ground under gravity: symmetric, so each bearing carries half the weight."""
    data = {"name": "whip", "spin_axis": [1.0, 0.0, 0.0], "gravity": [0.0, 0.0, -9.81], "materials": [STEEL],
            "rotors": [{"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                        "shaft": [{"length": 0.3, "outer_diameter": diameter, "material": "steel",
                                   "elements": elements}] * 2,
                        "disks": [{"name": "disk", "axial_position": 0.3, "mass": DISK, "polar_inertia": 0.04,
                                   "diametral_inertia": 0.02}]
                        + [{"name": f"collar-{n}", "axial_position": x, "mass": COLLAR, "polar_inertia": 1e-3,
                            "diametral_inertia": 1e-3} for n, x in (("A", 0.0), ("B", 0.6))]}],
            "bearings": [{"name": n, "rotor": "shaft", "axial_position": x, "type": "journal", "diameter": diameter,
                          "length": diameter / 2, "clearance": CLEARANCE, "viscosity": 0.02}
                         for n, x in (("A", 0.0), ("B", 0.6))],
            "sensors": [{"name": "disk-y", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 1, 0]},
                        {"name": "disk-z", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 0, 1]},
                        {"name": "A-y", "rotor": "shaft", "axial_position": 0.0, "direction": [0, 1, 0]},
                        {"name": "A-z", "rotor": "shaft", "axial_position": 0.0, "direction": [0, 0, 1]}],
            "excitations": [{"name": "tap", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 0.6, 0.8]}]}
    if unbalance:
        data["unbalances"] = [{"rotor": "shaft", "amount": unbalance, "axial_position": 0.3, "phase_deg": 30.0}]
    return rdm.Model.from_dict(data, source="whip.toml")


def test_equilibrium_is_the_short_bearing_static_position_under_half_the_weight():
    """``initial='equilibrium'``: each journal sits where the short-bearing film (pressure
    integrated by quadrature, independently of the package) carries half the rotor's weight
    (mass from the drawing: shaft, disk, collars), at its eccentricity and attitude angle; the
    default basis gives the equilibrium of the full model."""
    from journal_reference import Bearing, static_equilibrium

    diameter, speed = 0.025, 400.0
    model = _machine(diameter)
    weight = 9.81 * (7810.0 * np.pi * diameter ** 2 / 4 * 0.6 + DISK + 2 * COLLAR)
    position, eps, _ = static_equilibrium(Bearing(diameter, diameter / 2, CLEARANCE, 0.02), weight / 2, speed)
    assert 0.2 < eps < 0.8
    res = rdm.simulate(model, 1e-4, speed, initial="equilibrium", samples=2, backend="numpy")
    # the load pushes along x = -z; y = e × x = +y (e = +x)
    expected = np.array([position[1], -position[0]])
    np.testing.assert_allclose([res.sensor("A-y")[0], res.sensor("A-z")[0]], expected, rtol=0,
                               atol=1e-6 * CLEARANCE)
    # the bearings carry the weight: the film's force passed to the ground is half the weight each, down
    np.testing.assert_allclose(res.bearing_forces[0, :, :3], [[0.0, 0.0, -weight / 2]] * 2, rtol=0,
                               atol=1e-6 * weight)
    # the basis holds the static deflections under the weights and under forces at the journals,
    # so the equilibrium (weights against films) is the full model's, every mode kept, to round-off
    full = rdm.simulate(model, 1e-4, speed, initial="equilibrium", samples=2, backend="numpy", modes_below=np.inf)
    assert rdm.simulation.flexible.reduced_system(model, speed, 4 * speed).size < model.dofs.n   # reduced
    np.testing.assert_allclose(res.sensors[0], full.sensors[0], rtol=0, atol=1e-9 * np.abs(full.sensors[0]).max())


def _free_modes(model, speed, slower_than):
    """The linear model's roots (one of each pair) decaying slower than ``slower_than`` [1/s]."""
    roots = rdm.modal(model, speed).eigenvalues
    return roots[(roots.imag > 1.0) & (roots.real > -slower_than)]


def _harmonic(res, name, frequency, modes, after):
    """The complex amplitude at ``frequency`` [rad/s] (``A cos + B sin -> A - iB``) of a sensor
    after ``after`` [s], fitted with a constant and the free decaying ``modes`` (whose transient
    would otherwise leak into it)."""
    last = res.time > after
    t = res.time[last] - after
    columns = [np.cos(frequency * res.time[last]), np.sin(frequency * res.time[last]), np.ones_like(t)]
    for root in modes:
        columns += [np.exp(root.real * t) * np.cos(root.imag * t), np.exp(root.real * t) * np.sin(root.imag * t)]
    coefficients, *_ = np.linalg.lstsq(np.column_stack(columns), res.sensor(name)[last], rcond=None)
    return coefficients[0] - 1j * coefficients[1]


def test_steady_unbalance_orbit_equals_the_linear_response_to_the_square_of_orbit_over_clearance():
    """Below the threshold, from equilibrium, the 1X orbit at the disk and at a journal equals
    ``rdm.unbalance_response`` (films linearised at their static load) to the films' nonlinearity:
    its quadratic terms put the orbit's square into 0X and 2X, its cubic ones (and the quadratic
    twice) into 1X, so the relative error is ``~ (a / c)^2`` (``a`` the journal's orbit): halving
    the unbalance quarters it (the default basis: its truncation error is 1e-5 of the orbit, measured
    against every mode kept)."""
    speed = 400.0
    errors, ratios = [], []
    for amount in (1.6e-4, 8e-5):
        model = _machine(unbalance=amount)
        res = rdm.simulate(model, 0.12, speed, initial="equilibrium", samples=481, rtol=1e-7, atol=1e-12)
        linear = rdm.unbalance_response(model, [speed])
        modes = _free_modes(model, speed, 150.0)
        worst, orbit = 0.0, 0.0
        for i, name in enumerate(linear.outputs):
            expected = linear.amplitude[i, 0, 0] * np.exp(1j * np.radians(linear.phase_deg[i, 0, 0]))
            got = _harmonic(res, name, speed, modes, after=0.03)
            worst = max(worst, abs(got - expected) / abs(expected))
            if name.startswith("A-"):
                orbit = max(orbit, abs(expected))
        errors.append(worst)
        ratios.append(orbit / CLEARANCE)
    assert 0.05 < ratios[0] < 0.3, (ratios, errors)
    assert errors[0] < 5.0 * ratios[0] ** 2, (errors, ratios)       # an O(1) multiple (measured: 2.5)
    assert 3.0 < errors[0] / errors[1] < 5.0, errors


@functools.lru_cache(maxsize=None)
def _threshold():
    """The whirl test rotor's oil-whirl threshold [rad/s] (Lund's, ``rdm.stability``)."""
    return rdm.stability(_machine(diameter=0.035), np.linspace(300.0, 1500.0, 13)).threshold_speed


@pytest.mark.parametrize("fraction", [0.8, 1.3])
def test_whirl_below_the_threshold_dies_out_above_it_grows_at_the_unstable_roots_frequency(fraction):
    """No unbalance, from equilibrium, a tap on the disk: below Lund's threshold (``rdm.stability``)
    the whirl decays, above it the subsynchronous whirl grows, at the least stable root's
    frequency (the first bending mode's, below half the speed) and rate while it is small
    against the clearance."""
    model = _machine(diameter=0.035)
    threshold = _threshold()
    speed = fraction * threshold
    roots = rdm.modal(model, speed).eigenvalues
    roots = roots[roots.imag > 1.0]
    root = roots[np.argmax(roots.real)]
    assert (root.real > 20.0 and root.imag < 0.5 * speed) if fraction > 1 else (root.real < -5.0)
    res = rdm.simulate(model, 0.12, speed, initial="equilibrium", impulse="tap", impulse_size=2e-3, samples=1201,
                       rtol=1e-7, atol=1e-13)
    signal = res.sensor("disk-z") - res.sensor("disk-z")[0]
    early, late = (res.time > 0.02) & (res.time < 0.06), res.time > 0.08
    growth = np.log(np.abs(signal[late]).max() / np.abs(signal[early]).max()) / 0.06
    assert abs(growth - root.real) < 0.15 * abs(root.real), (growth, root.real)
    spectrum = np.abs(np.fft.rfft(signal[late] * np.hanning(late.sum()), 2 ** 16))
    frequency = 2 * np.pi * np.argmax(spectrum) / (2 ** 16 * (res.time[1] - res.time[0]))
    if fraction > 1:
        assert abs(frequency - root.imag) < 0.03 * root.imag, (frequency, root.imag)
        assert np.abs(res.sensor("A-z")).max() < CLEARANCE


def _stiff_machine():
    """A stiff flexible rotor for oil whirl (not whip): a steel shaft 0.6 m long, 70 mm between
    journals turned down to 50 mm, a 30 kg disk at mid-span and 10 kg sleeves at the journals, in
    two plain journal bearings (D 50 mm, L/D 0.5, clearance 40 um, a light oil of 0.003 Pa s) on
    the ground under gravity. Its first bending mode lies far above the half-speed whirl, so the
    whirl above the threshold is the rotor's motion in its films, which the films' nonlinearity
    limits (the sleeves give the journals the mass that keeps the integrator's steps long)."""
    sleeve = {"polar_inertia": 1e-2, "diametral_inertia": 1e-2, "mass": 10.0}
    data = {"name": "whirl", "spin_axis": [1.0, 0.0, 0.0], "gravity": [0.0, 0.0, -9.81], "materials": [STEEL],
            "rotors": [{"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                        "shaft": [{"length": 0.05, "outer_diameter": 0.05, "material": "steel", "elements": 1},
                                  {"length": 0.5, "outer_diameter": 0.07, "material": "steel", "elements": 4},
                                  {"length": 0.05, "outer_diameter": 0.05, "material": "steel", "elements": 1}],
                        "disks": [{"name": "disk", "axial_position": 0.3, "mass": 30.0, "polar_inertia": 0.15,
                                   "diametral_inertia": 0.08},
                                  {"name": "sleeve-A", "axial_position": 0.0, **sleeve},
                                  {"name": "sleeve-B", "axial_position": 0.6, **sleeve}]}],
            "bearings": [{"name": n, "rotor": "shaft", "axial_position": x, "type": "journal", "diameter": 0.05,
                          "length": 0.025, "clearance": CLEARANCE, "viscosity": 0.003}
                         for n, x in (("A", 0.0), ("B", 0.6))],
            "sensors": [{"name": f"{point}-{axis}", "rotor": "shaft", "axial_position": x, "direction": direction}
                        for point, x in (("disk", 0.3), ("A", 0.0))
                        for axis, direction in (("y", [0, 1, 0]), ("z", [0, 0, 1]))],
            "excitations": [{"name": "tap", "rotor": "shaft", "axial_position": 0.3, "direction": [0, 0.6, 0.8]}]}
    return rdm.Model.from_dict(data, source="whirl.toml")


def test_above_the_threshold_the_whirl_settles_on_one_limit_cycle_inside_the_clearance():
    """20 % above Lund's threshold (``rdm.stability``) the stiff rotor's whirl grows, from a small
    tap and from one ten times larger, onto the same orbit: over the last whirl periods the disk's
    orbit is the other run's (to 1 %) and has stopped growing, and the journals orbit inside the
    clearance (eccentricity 0.91), both runs alike. The limit cycle whirls subsynchronously, within
    12 % above the linear model's unstable root, at half the running speed: on a circular orbit about the bearing centre the
    short-bearing film carries no tangential force at a whirl of half the journal's speed (its
    squeeze and wedge terms cancel), so it neither feeds nor damps such a whirl."""
    model = _stiff_machine()
    threshold = rdm.stability(model, np.linspace(300.0, 1500.0, 13)).threshold_speed
    speed = 1.2 * threshold
    roots = rdm.modal(model, speed).eigenvalues
    roots = roots[roots.imag > 1.0]
    root = roots[np.argmax(roots.real)]
    assert root.real > 20.0 and root.imag < 0.5 * speed
    period, duration = 2 * np.pi / root.imag, 0.15
    runs = []
    for size in (0.2, 2.0):
        res = rdm.simulate(model, duration, speed, initial="equilibrium", impulse="tap", impulse_size=size,
                           samples=151, rtol=1e-5, atol=1e-13)
        y, z = (res.sensor(f"disk-{axis}") - res.sensor(f"disk-{axis}")[0] for axis in "yz")
        disk = np.hypot(y, z)
        eccentricity = np.hypot(res.sensor("A-y"), res.sensor("A-z")) / CLEARANCE
        first, last = res.time <= 2 * period, res.time > duration - 3 * period
        before = (res.time > duration - 6 * period) & ~last
        angle = np.unwrap(np.arctan2(z[last], y[last]))
        runs.append({"start": disk[first].max(), "orbit": disk[last].max(), "before": disk[before].max(),
                     "eccentricity": eccentricity[last].max(), "whirl": np.polyfit(res.time[last], angle, 1)[0]})
    small, large = runs
    assert large["start"] > 5 * small["start"] and small["orbit"] > 5 * small["start"], runs
    assert abs(small["orbit"] - large["orbit"]) < 0.01 * large["orbit"], runs
    for run in runs:
        # stopped: growing at the linear rate it would gain a factor exp(6 pi Re/Im) = 3.3 over 3 periods
        assert abs(run["orbit"] - run["before"]) < 0.02 * run["orbit"], runs
        assert 0.8 < run["eccentricity"] < 0.95, runs
        assert abs(run["whirl"] - 0.5 * speed) < 0.01 * speed, runs
        assert root.imag < run["whirl"] < 1.12 * root.imag, runs        # the root: 0.458 times the speed
    assert abs(small["eccentricity"] - large["eccentricity"]) < 0.01, runs


def test_free_spin_still_refused_and_a_given_journal_load_too():
    model = _machine()
    with pytest.raises(InputError, match="free spin") as error:
        rdm.simulate(model, 0.1, 100.0, drive="free")
    assert "\n" not in str(error.value)
    data = model.to_dict()
    data["bearings"][0]["load"] = 60.0
    data["bearings"][1]["load"] = 60.0
    with pytest.raises(InputError, match=r"\[bearings.A\] load = 60.*weight it carries") as error:
        rdm.simulate(rdm.Model.from_dict(data, source="whip.toml"), 0.1, 100.0)
    assert "\n" not in str(error.value)


def test_right_hand_side_is_the_linear_structure_plus_the_film_force_by_quadrature():
    """Every mode kept, at random states with the journals inside their clearance: the reduced
    equations are ``V^T`` times the structure's ``-(C + w G) q' - K q`` (the linear model without
    the films), plus the weights, plus each journal's film force from the short-bearing pressure integrated by
    quadrature (tests/journal_reference.py) at its relative position and velocity; the numba and
    numpy right-hand sides agree."""
    from journal_reference import Bearing, film_force as by_quadrature

    from rotordyn_modal.assembly import bearing_motion, constant_matrices
    from rotordyn_modal.simulation import flexible

    model = _machine()
    speed = 400.0
    system = flexible.reduced_system(model, speed, np.inf)
    V, r = system.V, system.size
    M, C, G, K = constant_matrices(model)
    bearing = Bearing(0.025, 0.0125, CLEARANCE, 0.02)
    plain = flexible._right_hand_side(system, speed, 0.0)
    rng = np.random.default_rng(3)
    for _ in range(3):
        q = rng.normal(size=len(V)) * 1e-6
        dq = rng.normal(size=len(V)) * 1e-4
        y = np.concatenate([V.T @ M @ q, V.T @ M @ dq])       # V^T M V = I: q, q' in the basis
        q, dq = V @ y[:r], V @ y[r:]
        force = -(C + speed * G) @ dq - K @ q
        for b in model.bearings:
            rows, local = bearing_motion(model, b)
            x, yy = b.coefficients.journal.axes[:2]
            T = local[:3]
            position, velocity = T @ q[rows], T @ dq[rows]
            assert np.hypot(position @ x, position @ yy) < 0.9 * CLEARANCE
            fx, fy = by_quadrature(bearing, (position @ x, position @ yy), (velocity @ x, velocity @ yy), speed)
            force[rows] += T.T @ (fx * x + fy * yy)
        expected = V.T @ force + system.gravity                   # the weights (tests/test_simulate_flexible.py)
        got = plain(0.0, y)
        np.testing.assert_allclose(got[r:], expected, rtol=0, atol=1e-9 * np.abs(expected).max())
        if flexible._compiled("auto", True) is not None:
            packed = (*flexible._packed(system, speed, 0.0), *system.films.arguments())
            np.testing.assert_allclose(flexible._compiled("auto", True)(0.0, y, *packed), got, rtol=0,
                                       atol=1e-12 * np.abs(got).max())


def test_command_line_simulates_a_flexible_rotor_on_journal_bearings(tmp_path, capsys):
    """``rotordyn-modal simulate`` on such a model: the run from equilibrium writes its CSV, the
    journal bearings' forces at the start carry half the weight each; at speed 0 the equilibrium
    is refused in one line (exit 2)."""
    from rotordyn_modal.cli.main import main
    from rotordyn_modal.io.model_file import save_model

    path = tmp_path / "whip.toml"
    save_model(_machine(unbalance=1e-4), path)
    out = tmp_path / "run.csv"
    assert main(["simulate", str(path), "--speed", "3800", "--duration", "0.01", "--initial", "equilibrium",
                 "--samples", "11", "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    table = pd.read_csv(out)
    weight = 9.81 * (7810.0 * np.pi * 0.025 ** 2 / 4 * 0.6 + DISK + 2 * COLLAR)
    np.testing.assert_allclose(table[["A_Fz", "B_Fz"]].iloc[0], [-weight / 2] * 2, rtol=1e-6)
    capsys.readouterr()
    assert main(["simulate", str(path), "--speed", "0", "--duration", "0.01", "--initial", "equilibrium",
                 "--quiet"]) == 2
    error = capsys.readouterr().err.strip()
    assert "speed 0" in error and "\n" not in error, error


def test_a_journal_that_cannot_carry_its_load_ends_the_run_with_one_line():
    """Started centred at a crawl the film has almost no wedge: the journals sink to their walls
    and the run stops with one line naming each journal's eccentricity, not a traceback."""
    with pytest.raises(InputError, match=r"journal bearings \(eccentricity at the last output time: "
                       r"\[bearings.A\] 0\.\d+, \[bearings.B\] 0\.\d+\).*bearing wall") as error:
        rdm.simulate(_machine(), 0.3, 2.0, samples=31)
    assert "\n" not in str(error.value)
