"""Campbell diagrams: batch equals single-speed solves, flat diagrams of counter-rotating
pairs, excitation orders of every rotor and gear mesh, critical speeds against closed forms."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import rotordyn_modal as rdm
from reference_model import ReferenceMachine
from test_tracking import JD, JP, JT_S, JX, K, K_ROLL, KX, KY_EXTRA, A, MR, MS, crossing_machine


def closed_form_critical(order):
    """Speeds Omega > 0 where a branch of the crossing machine meets w = order * Omega."""
    m, jt, kt = MS + MR, JT_S + JD, 2 * K * A**2
    flat = np.array([np.sqrt(2 * KX / m), np.sqrt((2 * K + KY_EXTRA) / m), np.sqrt(2 * K / m),
                     np.sqrt(2 * K_ROLL / (JX + JP))]) / order
    # (Omega Jp +- s) / (2 Jt) = n Omega  =>  Omega^2 (4 n^2 Jt^2 -+ 4 n Jt Jp) = 4 Jt kt
    forward = np.sqrt(kt / (order**2 * jt - order * JP))
    backward = np.sqrt(kt / (order**2 * jt + order * JP))
    return flat, forward, backward


@pytest.mark.parametrize("order", [1, 2])
def test_critical_speeds_equal_the_closed_form(order):
    flat, forward, backward = closed_form_critical(order)
    result = rdm.campbell(crossing_machine(), np.linspace(0.0, 3000.0, 61), orders=(order,))
    crit = result.critical
    crit_order = crit.order == order
    speeds = crit.speeds[crit_order]
    expected = np.sort(np.concatenate([flat, [forward, backward]]))
    assert len(speeds) == len(expected)
    np.testing.assert_allclose(np.sort(speeds), expected, rtol=1e-9)
    whirl = dict(zip(np.round(speeds, 6), crit.whirl[crit_order]))
    assert whirl[round(forward, 6)] == "forward"
    assert whirl[round(backward, 6)] == "backward"
    np.testing.assert_allclose(crit.frequencies_hz * 2 * np.pi, order * crit.speeds, rtol=1e-12)
    assert set(crit.source) == {"rotor"}


def test_critical_speeds_at_negative_speeds_mirror():
    result = rdm.campbell(crossing_machine(), np.linspace(-3000.0, 3000.0, 121))
    flat, forward, backward = closed_form_critical(1)
    expected = np.sort(np.concatenate([flat, [forward, backward]]))
    np.testing.assert_allclose(np.sort(-result.critical.speeds[result.critical.speeds < 0]), expected, rtol=1e-9)
    np.testing.assert_allclose(np.sort(result.critical.speeds[result.critical.speeds > 0]), expected, rtol=1e-9)
    labels = dict(zip(np.round(result.critical.speeds, 6), result.critical.whirl))
    assert labels[round(-forward, 6)] == "forward" and labels[round(-backward, 6)] == "backward"


def test_batch_equals_single_speed_solves(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speeds = np.linspace(-2000.0, 2000.0, 9)
    result = rdm.campbell(model, speeds)
    for k, speed in enumerate(speeds):
        single = rdm.modal(model, speed).eigenvalues
        i, j = linear_sum_assignment(np.abs(result.eigenvalues[k][:, None] - single[None]))
        np.testing.assert_allclose(result.eigenvalues[k][i], single[j], rtol=1e-10)


def test_a_mesh_driven_by_a_reverse_spinning_gear_excites_at_its_teeth_times_its_speed(examples_dir):
    """The gear machine's mesh described from the fan's side: the fan (spinning backwards at
    0.4 of the motor's speed) drives the motor with 10 teeth. The mesh frequency is the teeth
    times the fan's rotation frequency, 4 |Omega|, whatever the direction of spin; its 1X
    critical speeds are eigenfrequencies of the independent reference there."""
    with open(examples_dir / "gear_machine.toml", "rb") as handle:
        data = tomllib.load(handle)
    data["transmissions"] = [{"type": "gear", "driver": "fan", "driven": "motor", "ratio": 0.4, "driver_teeth": 10}]
    model = rdm.Model.from_dict(data)
    sources = rdm.excitation_sources(model)
    assert sources.names == ("motor", "fan", "mesh:fan-motor")
    np.testing.assert_allclose(sources.multipliers, [1.0, 0.4, 4.0], rtol=1e-15)
    crit = rdm.campbell(model, np.linspace(0.0, rdm.rpm(6000), 121)).critical
    mesh = np.asarray(crit.source) == "mesh:fan-motor"
    assert mesh.sum() >= 2
    ref = ReferenceMachine(data)
    for speed, f_hz in zip(crit.speeds[mesh], crit.frequencies_hz[mesh]):
        w = 2 * np.pi * f_hz
        assert w == pytest.approx(4.0 * abs(speed), rel=1e-10)
        assert np.abs(ref.modes(speed)[0].imag - w).min() <= 1e-9 * w


def test_gear_machine_sources_orders_and_crossings(examples_dir):
    path = examples_dir / "gear_machine.toml"
    model = rdm.load_model(path)
    sources = rdm.excitation_sources(model)
    assert sources.names == ("motor", "fan", "mesh:motor-fan")
    np.testing.assert_allclose(sources.multipliers, [1.0, 1 / 2.5, 23.0], rtol=1e-15)
    result = rdm.campbell(model, np.linspace(-rdm.rpm(12000), rdm.rpm(12000), 241), orders=(1, 2))
    crit = result.critical
    assert len(crit) > 0 and set(crit.source) <= set(sources.names)
    with open(path, "rb") as handle:
        ref = ReferenceMachine(tomllib.load(handle))
    multiplier = dict(zip(sources.names, sources.multipliers))
    for source, order, speed, f_hz, ratio, zeta in zip(crit.source, crit.order, crit.speeds,
                                                       crit.frequencies_hz, crit.whirl_ratios,
                                                       crit.damping_ratios):
        w = 2 * np.pi * f_hz
        assert w == pytest.approx(order * multiplier[source] * abs(speed), rel=1e-10)
        values, shapes = ref.modes(speed)
        m = int(np.argmin(np.abs(values.imag - w)))
        assert abs(values[m].imag - w) <= 1e-9 * w  # an eigenfrequency of the machine there
        assert ratio == pytest.approx(ref.whirl_ratio(shapes[m], speed), abs=1e-6)
        assert zeta == pytest.approx(-values[m].real / abs(values[m]), abs=1e-9)
    assert np.all(np.diff(crit.speeds) >= 0)
    table = crit.to_dataframe()
    assert list(table.columns[:6]) == ["source", "order", "mode", "speed_rpm", "frequency_hz", "whirl"]


def test_counter_rotating_gear_with_momenta_cancelling_is_flat():
    """Gear ratio tau, driven polar inertia tau * Jp: Jp * 1 + tau Jp * (-1 / tau) = 0."""
    tau, jp = 2.5, 0.08
    model = rdm.Model(
        stator=rdm.Stator(mass=90.0, inertia=[[5.0, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 3.0]]),
        rotors=[rdm.Rotor("m", 10.0, [0.2, 0.1, 0.1], jp, 0.06, speed_ratio=1.0),
                rdm.Rotor("f", 7.0, [-0.3, 0.0, 0.2], tau * jp, 0.15)],
        transmissions=[rdm.Transmission("gear", "m", "f", tau, 19)], reference_rotor="m",
        suspensions=[rdm.Suspension(f"s{i}", p, [2e5, 1e5, 3e5], [50.0, 50.0, 80.0])
                     for i, p in enumerate([[0.4, 0.3, -0.2], [0.4, -0.3, -0.2], [-0.4, 0.0, -0.2]])],
    )
    np.testing.assert_allclose(model.matrices().G, 0.0, atol=4 * np.finfo(float).eps * jp)  # round-off of Jp - tau Jp / tau
    result = rdm.campbell(model, np.linspace(-rdm.rpm(20000), rdm.rpm(20000), 41))
    spread = np.abs(result.eigenvalues - result.eigenvalues[0]).max()
    assert spread <= 1e-12 * np.abs(result.eigenvalues).max()


def test_result_table_and_labels(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(-6000, 6000, 13)))
    table = result.to_dataframe()
    assert list(table.columns[:6]) == ["speed_rpm", "mode", "frequency_hz", "damping_ratio",
                                       "log_decrement", "whirl"]
    assert set(table.whirl) <= {"forward", "backward", "none"}
    np.testing.assert_allclose(np.unique(table.speed_rpm), np.linspace(-6000, 6000, 13), rtol=1e-12)
    assert result.frequencies_hz.shape == (13, 6)
    np.testing.assert_allclose(result.log_decrements,
                               -2 * np.pi * result.eigenvalues.real / result.eigenvalues.imag, rtol=1e-12)


@pytest.mark.parametrize("speeds", [[], [0.0, 0.0], [1.0, np.nan], [3.0, 2.0]])
def test_bad_speed_grids_are_refused(speeds):
    with pytest.raises(rdm.InputError):
        rdm.campbell(crossing_machine(), speeds)


@pytest.mark.parametrize("seed", range(3))
def test_campbell_whirl_and_damping_equal_the_reference(seed, examples_dir):
    """The sweep's shapes come from its own batched solver (not modal's scipy.linalg.eig):
    their whirl ratios must still equal the reference's particle-orbit definition."""
    from reference_model import random_description

    rng = np.random.default_rng(300 + seed)
    data = random_description(rng, n_rotors=2, damping=seed != 1)
    if seed == 2:
        with open(examples_dir / "gear_machine.toml", "rb") as handle:
            data = tomllib.load(handle)
    ref = ReferenceMachine(data)
    speeds = np.linspace(-2000.0, 2000.0, 21)
    result = rdm.campbell(rdm.Model.from_dict(data), speeds)
    for k, speed in enumerate(speeds):
        values, shapes = ref.modes(speed)
        osc = result.oscillatory[k]
        i, j = linear_sum_assignment(np.abs(values[:, None] - result.eigenvalues[k][osc][None]))
        np.testing.assert_allclose(result.eigenvalues[k][osc][j], values[i], rtol=1e-9)
        ratios = np.array([ref.whirl_ratio(shapes[m], speed) for m in i])
        np.testing.assert_allclose(result.whirl_ratios[k][osc][j], ratios, atol=1e-6)
        zeta = -values[i].real / np.abs(values[i])
        np.testing.assert_allclose(result.damping_ratios[k][osc][j], zeta, atol=1e-9)


def test_every_crossing_is_found(examples_dir):
    """Count the crossings independently: the reference's sorted frequencies (continuous
    curves) minus each excitation line, on a fine grid, change sign once per crossing."""
    path = examples_dir / "gear_machine.toml"
    with open(path, "rb") as handle:
        ref = ReferenceMachine(tomllib.load(handle))
    model = rdm.load_model(path)
    top = rdm.rpm(12000)
    result = rdm.campbell(model, np.linspace(0.0, top, 97), orders=(1, 2))
    fine = np.linspace(0.0, top, 1201)
    sorted_w = np.array([np.sort(ref.modes(s)[0].imag) for s in fine])
    sources = rdm.excitation_sources(model)
    for name, multiplier in zip(sources.names, sources.multipliers):
        for order in (1, 2):
            gap = sorted_w - order * multiplier * fine[:, None]
            expected = int(np.sum(np.sign(gap[:-1]) != np.sign(gap[1:])))
            found = np.sum((result.critical.source == name) & (result.critical.order == order))
            assert found == expected, (name, order)


def test_labels_ascend_in_frequency_at_the_speed_nearest_zero(examples_dir):
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    speeds = np.linspace(-1500.0, 3000.0, 31)  # nearest to zero: 0.0
    result = rdm.campbell(model, speeds)
    k0 = int(np.argmin(np.abs(speeds)))
    assert np.all(np.diff(result.frequencies_hz[k0]) >= 0)
    np.testing.assert_array_equal(result.modes, np.arange(1, 7))


def test_damped_critical_speeds_equal_the_closed_form_roots():
    """Damped symmetric machine: the crossings Im lam(Omega) = Omega of its closed-form
    branches (tests/test_tracking.py), solved with brentq to round-off."""
    from scipy.optimize import brentq

    from test_tracking import damped_branches, damped_crossing_machine

    grid = np.linspace(0.0, 3000.0, 3001)
    w = damped_branches(grid).imag
    expected = []
    for b in range(6):
        gap = w[:, b] - grid
        for k in np.nonzero(np.sign(gap[:-1]) != np.sign(gap[1:]))[0]:
            expected.append(brentq(lambda s: damped_branches(np.array([s]))[0, b].imag - s,
                                   grid[k], grid[k + 1], xtol=1e-14, rtol=4 * np.finfo(float).eps))
    result = rdm.campbell(damped_crossing_machine(), np.linspace(0.0, 3000.0, 41))
    np.testing.assert_allclose(np.sort(result.critical.speeds), np.sort(expected), rtol=1e-9)


def test_critical_speeds_do_not_depend_on_origin_or_axes(examples_dir):
    from reference_model import rotated, rotation, translated

    with open(examples_dir / "gear_machine.toml", "rb") as handle:
        data = tomllib.load(handle)
    speeds = np.linspace(-rdm.rpm(9000), rdm.rpm(9000), 91)
    base = rdm.campbell(rdm.Model.from_dict(data), speeds, orders=(1, 2)).critical
    other = rotated(translated(data, [2.0, -3.0, 0.5]), rotation(np.random.default_rng(8)))
    moved = rdm.campbell(rdm.Model.from_dict(other), speeds, orders=(1, 2)).critical
    np.testing.assert_allclose(moved.speeds, base.speeds, rtol=1e-9)
    assert list(moved.source) == list(base.source) and list(moved.whirl) == list(base.whirl)
    np.testing.assert_array_equal(moved.mode, base.mode)


def test_tables_hold_the_results_numbers(examples_dir):
    """The Campbell table has a row per speed and oscillating mode with that mode's numbers (speed
    in rpm, real part in 1/s); the critical-speed table has the critical speeds' columns."""
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0, 6000, 25)), orders=(1,))
    table = result.to_dataframe(oscillatory_only=False)
    k = np.repeat(np.arange(25), result.eigenvalues.shape[1])
    m = table["mode"].to_numpy() - 1
    np.testing.assert_array_equal(table["speed_rpm"], result.speeds[k] * 30 / np.pi)
    for column, values in (("frequency_hz", result.frequencies_hz), ("damping_ratio", result.damping_ratios),
                           ("whirl_ratio", result.whirl_ratios), ("real_part", result.eigenvalues.real)):
        np.testing.assert_array_equal(table[column], values[k, m])
    crit = result.critical
    critical_table = crit.to_dataframe()
    assert len(critical_table) == len(crit) > 0
    for column, values in (("speed_rpm", crit.speeds * 30 / np.pi), ("frequency_hz", crit.frequencies_hz),
                           ("whirl_ratio", crit.whirl_ratios), ("damping_ratio", crit.damping_ratios)):
        np.testing.assert_array_equal(critical_table[column], values)
