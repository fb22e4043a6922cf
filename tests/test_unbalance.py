"""Unbalance response: an independent real-arithmetic solve, a time simulation, forces, API 684."""

from __future__ import annotations

from pathlib import Path

import control
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import rotordyn_modal as rdm
from reference_bearings import BearingMachine, random_bearing_description, with_mount_channels
from rotordyn_modal.analysis.unbalance import (amplification_factors, phase_reference,
                                               required_separation_margin, unbalance_response)
from rotordyn_modal.errors import InputError

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
SPEEDS = rdm.rpm(np.linspace(-6000, 6000, 61))


def _model(loss_factor=0.0, damping_scale=1.0):
    data = rdm.load_model(EXAMPLE).to_dict()
    for s in data["suspensions"]:
        s["loss_factor"] = loss_factor
        s["damping"] = [damping_scale * c for c in s["damping"]]
    return rdm.Model.from_dict(data)


def _real_steady_state(model, speed, source, eta):
    """Steady state of M x'' + (C + W G) x' + K x = F_c cos wt + F_s sin wt, x = X_c cos + X_s sin,
    solved as one real 12x12 system, with the force written from its definition (phase_deg
    measured from a towards b = e x a, turning with the rotor at r Omega)."""
    M, C, G, K = model.matrices()
    a, b = phase_reference(model.spin_axis)
    e = model.spin_axis
    rotor = model.rotor(source)
    spin = rotor.speed_ratio * speed
    w, s = abs(spin), np.sign(spin)
    Fc, Fs = np.zeros(6), np.zeros(6)
    for u in (u for u in model.unbalances if u.rotor == source):
        phi = np.radians(u.phase_deg)
        point = rotor.center_of_mass + u.axial_offset * e - model.reference_point
        fc = u.amount * w ** 2 * (np.cos(phi) * a + np.sin(phi) * b)
        fs = u.amount * w ** 2 * s * (-np.sin(phi) * a + np.cos(phi) * b)
        Fc += np.concatenate([fc, np.cross(point, fc)])
        Fs += np.concatenate([fs, np.cross(point, fs)])
    loss = sum(eta * rdm.shift_matrix(model.reference_point, p.position) @ p.stiffness_matrix
               @ rdm.shift_matrix(model.reference_point, p.position).T for p in model.suspensions)
    D = w * (C + speed * G) + loss
    big = np.block([[K - w ** 2 * M, D], [-D, K - w ** 2 * M]])
    X = np.linalg.solve(big, np.concatenate([Fc, Fs]))
    return X[:6], X[6:]


@pytest.mark.parametrize("eta", [0.0, 0.06])
def test_equals_independent_real_solve(eta):
    model = _model(eta)
    res = unbalance_response(model, SPEEDS)
    rows = rdm.assembly.sensor_rows(model)
    for j, source in enumerate(res.sources):
        for k, speed in enumerate(SPEEDS):
            Xc, Xs = _real_steady_state(model, speed, source, eta)
            yc, ys = rows @ Xc, rows @ Xs
            amplitude, phase = np.hypot(yc, ys), np.arctan2(-ys, yc)
            np.testing.assert_allclose(res.amplitude[:, j, k], amplitude, rtol=1e-9, atol=1e-18)
            big = amplitude > 1e-6 * res.amplitude.max()
            np.testing.assert_allclose(np.exp(1j * np.radians(res.phase_deg[big, j, k])),
                                       np.exp(1j * phase[big]), atol=1e-8)


def test_ground_forces_equal_independent_real_solve():
    model = _model(0.06)
    res = unbalance_response(model, SPEEDS)
    for j, source in enumerate(res.sources):
        for k in (5, 40, 55):
            Xc, Xs = _real_steady_state(model, SPEEDS[k], source, 0.06)
            w = 2 * np.pi * res.frequencies_hz[j, k]
            for i, p in enumerate(model.suspensions):
                shift = rdm.shift_matrix(model.reference_point, p.position)
                uc, us = shift.T @ Xc, shift.T @ Xs
                # F = K x + eta K x'/w + C x' with x' = w(-uc sin + us cos)
                fc = p.stiffness_matrix @ uc + (0.06 * p.stiffness_matrix + w * p.damping_matrix) @ us
                fs = p.stiffness_matrix @ us - (0.06 * p.stiffness_matrix + w * p.damping_matrix) @ uc
                np.testing.assert_allclose(res.ground_forces[i, :, j, k], fc - 1j * fs,
                                           rtol=1e-8, atol=1e-10 * np.abs(fc - 1j * fs).max())


def test_time_simulation_confirms_amplitude_and_phase():
    """Integrate the state space driven by the rotating force (from its definition) to steady state."""
    model = _model(damping_scale=10.0)
    speed = rdm.rpm(3000)
    a, b = phase_reference(model.spin_axis)
    data = model.to_dict()
    fan = model.rotor("fan")
    data["unbalances"] = [{"rotor": "fan", "amount": 2.0e-4, "phase_deg": 30.0}]
    data["excitations"] = [{"name": n, "position": list(fan.center_of_mass), "direction": list(d)}
                           for n, d in (("a", a), ("b", b))]
    model = rdm.Model.from_dict(data)
    res = unbalance_response(model, [speed])
    spin = fan.speed_ratio * speed
    t = np.arange(0, 2.0, 1 / 20000)
    theta = spin * t + np.radians(30.0)
    u = 2.0e-4 * spin ** 2 * np.array([np.cos(theta), np.sin(theta)])
    y = control.forced_response(model.state_space(speed), t, u).outputs
    w = abs(spin)
    last = t > 1.5
    basis = np.array([np.cos(w * t[last]), np.sin(w * t[last])]).T
    for i in range(len(model.sensors)):
        (yc, ys), *_ = np.linalg.lstsq(basis, y[i, last], rcond=None)
        expected = res.amplitude[i, 0, 0] * np.exp(1j * np.radians(res.phase_deg[i, 0, 0]))
        assert abs((yc - 1j * ys) - expected) < 1e-4 * abs(expected)


def test_each_rotor_at_its_own_frequency():
    model = _model()
    res = unbalance_response(model, SPEEDS)
    ratios = model.speed_ratios
    for j, source in enumerate(res.sources):
        np.testing.assert_allclose(res.frequencies_hz[j], abs(ratios[source] * SPEEDS) / (2 * np.pi))
    assert set(res.sources) == {"fan", "motor"}


def test_zero_speed_gives_zero_response():
    res = unbalance_response(_model(), [0.0])
    assert np.all(res.amplitude == 0)


def test_dataframe_columns():
    res = unbalance_response(_model(), SPEEDS[:3], outputs="acc-top-z")
    table = res.to_dataframe()
    assert list(table.columns) == ["speed_rpm", "output", "source", "frequency_hz", "amplitude", "phase_deg"]
    assert set(table.output) == {"acc-top-z"}
    assert set(res.to_dataframe(forces="suspensions").output) >= {"acc-top-z", "mount-FL:Fz"}
    # every row is the response of its output, source and speed: rpm, Hz, amplitude, degrees
    full = unbalance_response(_model(), SPEEDS[:3])
    for row in full.to_dataframe().itertuples():
        o, s = full.outputs.index(row.output), full.sources.index(row.source)
        k = int(np.argmin(np.abs(SPEEDS[:3] * 30 / np.pi - row.speed_rpm)))
        assert row.speed_rpm == pytest.approx(SPEEDS[k] * 30 / np.pi, rel=1e-15)
        assert row.frequency_hz == full.frequencies_hz[s, k]
        value = full.response[o, s, k]
        assert row.amplitude == pytest.approx(abs(value), rel=1e-15)
        assert row.phase_deg == pytest.approx(np.degrees(np.angle(value)), abs=1e-12)


def test_dataframe_refuses_unknown_forces():
    with pytest.raises(InputError, match="forces 'ground'"):
        unbalance_response(_model(), SPEEDS[:3], outputs="acc-top-z").to_dataframe(forces="ground")


def test_amplification_factor_of_a_single_oscillator():
    """Unbalance response of a 1-DOF oscillator, x = m e w^2 / (k - m w^2 + i c w): AF -> 1/(2 zeta).
    Half-power width of this curve differs from 2 zeta w_n by O(zeta^2): 1 % covers zeta = 0.02."""
    zeta, wn = 0.02, 100.0
    w = np.linspace(50, 150, 20001)
    amplitude = np.abs(w ** 2 / (wn ** 2 - w ** 2 + 2j * zeta * wn * w))
    (speed, _, af), = amplification_factors(w, amplitude)
    assert abs(speed - wn) < 0.1
    assert af == pytest.approx(1 / (2 * zeta), rel=1e-2)


@pytest.mark.parametrize("af,position,expected", [
    (2.0, "below", 0.0), (2.0, "above", 0.0),
    (3.0, "below", 17 * (1 - 1 / 1.5)), (3.0, "above", 10 + 17 * (1 - 1 / 1.5)),
    (5.5, "below", 17 * (1 - 1 / 4.0)), (5.5, "above", 10 + 17 * (1 - 1 / 4.0)),
    (30.0, "below", 16.0), (30.0, "above", 26.0), (np.nan, "above", np.nan)])
def test_required_separation_margin(af, position, expected):
    """API 617 (7th/8th ed.) / API 684 (SP6.8.2.10): no margin below AF 2.5; below the operating
    range ``min(16, 17 (1 - 1/(AF - 1.5)))`` %, above it ``min(26, 10 + 17 (1 - 1/(AF - 1.5)))`` %,
    as implemented and cited in petrobras/ross ``ross/api_report.py`` (``Report.unbalance_response``,
    last at commit e59e3fba^) and quoted with the API 617 8th ed. clause in public review tools
    (docs/standards.md). The old rule (15 % for 2.5 <= AF <= 3.55, one formula both sides) fails."""
    assert required_separation_margin(af, position) == pytest.approx(expected, nan_ok=True)


def test_study_peak_takes_the_margin_of_its_side():
    """A study's unbalance peak above its operating speed needs ``min(26, 10 + 17 (1 - 1/(AF - 1.5)))``
    %, below it ``min(16, 17 (1 - 1/(AF - 1.5)))`` % (API 617; docs/standards.md): the peak of a
    1-DOF oscillator of damping ratio 0.05 (AF about 10)."""
    from rotordyn_modal.analysis.unbalance import amplification_factors
    from rotordyn_modal.study.analyses import _unbalance_peak

    w = np.linspace(50, 150, 2001)
    amplitude = np.abs(w ** 2 / (100.0 ** 2 - w ** 2 + 2j * 0.05 * 100.0 * w))
    (_, _, af), = amplification_factors(w, amplitude)
    raw = 17 * (1 - 1 / (af - 1.5))
    for operating, expected in ((60.0, min(26.0, 10 + raw)), (140.0, min(16.0, raw))):
        out = {name: np.full((1, 1), np.nan) for name in ("unbalance_peak_amplitude", "unbalance_peak_speed",
                                                          "amplification_factor", "separation_margin_pct",
                                                          "required_margin_pct")}
        _unbalance_peak(out, 0, 0, w, amplitude, operating, amplification_factors, required_separation_margin)
        assert out["required_margin_pct"][0, 0] == pytest.approx(expected, rel=1e-12)


def test_required_separation_margin_refuses_an_unknown_position():
    with pytest.raises(rdm.InputError, match="'inside': expected 'below' or 'above'"):
        required_separation_margin(3.0, "inside")


def test_peaks_table_required_margin_follows_the_side_of_the_operating_speed():
    """A peak below the operating speed needs ``min(16, 17 (1 - 1/(AF - 1.5)))`` %, one above it
    ``min(26, 10 + 17 (1 - 1/(AF - 1.5)))`` % (API 617; docs/standards.md)."""
    res = unbalance_response(_model(), rdm.rpm(np.linspace(0, 3000, 301)))
    for operating in (rdm.rpm(200), rdm.rpm(2900)):
        for row in res.peaks(operating_speed=operating).itertuples():
            if not np.isfinite(row.amplification_factor) or row.amplification_factor < 2.5:
                continue
            raw = 17 * (1 - 1 / (row.amplification_factor - 1.5))
            above = row.speed_rpm * np.pi / 30 > operating
            assert row.required_margin_pct == pytest.approx(min(26, 10 + raw) if above else min(16, raw), rel=1e-12)


def test_peaks_table():
    res = unbalance_response(_model(), rdm.rpm(np.linspace(0, 3000, 301)))
    peaks = res.peaks(operating_speed=rdm.rpm(2400))
    assert list(peaks.columns) == ["output", "source", "speed_rpm", "amplitude", "amplification_factor",
                                   "separation_margin_pct", "required_margin_pct"]
    fan_peak = peaks[(peaks.source == "fan")].sort_values("amplitude").iloc[-1]
    assert fan_peak.separation_margin_pct == pytest.approx(100 * abs(2400 - fan_peak.speed_rpm) / 2400)
    for bad in (0.0, np.nan, np.inf):
        with pytest.raises(rdm.InputError, match="rad/s: expected a finite speed other than 0"):
            res.peaks(operating_speed=bad)


def test_figure():
    fig = unbalance_response(_model(), SPEEDS).plot()
    assert len(fig.axes) >= 2


def test_errors():
    data = _model().to_dict()
    data["unbalances"] = []
    with pytest.raises(InputError, match="the model has no \\[\\[unbalances\\]\\]"):
        unbalance_response(rdm.Model.from_dict(data, "x.toml"), SPEEDS)
    with pytest.raises(InputError, match="quantity 'force': expected one of displacement, velocity, acceleration"):
        unbalance_response(_model(), SPEEDS, quantity="force")


@settings(max_examples=20, deadline=None)
@given(factor=st.floats(0.1, 10.0), shift=st.floats(-180.0, 180.0), speed_rpm=st.floats(200.0, 6000.0))
def test_linear_in_amount_and_phase_turns_with_the_rotor(factor, shift, speed_rpm):
    """Scaling ``amount`` scales the response; adding ``shift`` to ``phase_deg`` of an unbalance on a
    rotor turning r Omega shifts its harmonic's phase by sign(r Omega) * shift (the unbalance is
    just further round at t = 0)."""
    base = _model()
    data = base.to_dict()
    for u in data["unbalances"]:
        u["amount"] *= factor
        u["phase_deg"] += shift
    moved = rdm.Model.from_dict(data)
    speed = rdm.rpm(speed_rpm)
    a, b = unbalance_response(base, [speed]), unbalance_response(moved, [speed])
    for j, source in enumerate(a.sources):
        s = np.sign(base.speed_ratios[source])
        np.testing.assert_allclose(b.response[:, j], factor * np.exp(1j * s * np.radians(shift)) * a.response[:, j],
                                   rtol=1e-10, atol=1e-20)


def test_figure_marks_peaks():
    res = unbalance_response(_model(), rdm.rpm(np.linspace(0, 6000, 301)))
    fig = res.plot(peaks=res.peaks(rdm.rpm(3000)))
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert any(t.startswith("AF ") and "SM " in t for t in texts)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rotors=st.integers(1, 3),
       speed=st.one_of(st.floats(50.0, 1500.0), st.floats(-1500.0, -50.0)))
def test_on_bearings_equals_the_reference_receptances(seed, rotors, speed):
    """Random machines on cross-coupled, non-symmetric bearings with an unbalance on every rotor:
    each sensor's response equals the sum of the absolute-coordinate reference's receptances
    (``reference_bearings.BearingMachine``, its own constraints and matrices) times the
    unbalance force written from its definition (as in :func:`_real_steady_state`; 720
    comparisons explored: within 5.2e-13)."""
    rng = np.random.default_rng(seed)
    data = with_mount_channels(random_bearing_description(rng, n_rotors=rotors, stator=True))
    data["unbalances"] = [{"rotor": r["name"], "amount": float(rng.uniform(1e-5, 1e-3)),
                           "phase_deg": float(rng.uniform(-180, 180)), "axial_offset": float(rng.uniform(-0.1, 0.1))}
                          for r in data["rotors"]]
    model, reference = rdm.Model.from_dict(data), BearingMachine(data)
    e = model.spin_axis
    a, b = phase_reference(e)
    res = unbalance_response(model, np.array([speed]))
    for j, source in enumerate(res.sources):
        rotor = model.rotor(source)
        spin = rotor.speed_ratio * speed
        w, s = abs(spin), np.sign(spin)
        expected = np.zeros(len(model.sensors), dtype=complex)
        for u in (u for u in model.unbalances if u.rotor == source):
            phi = np.radians(u.phase_deg)
            point = rotor.center_of_mass + u.axial_offset * e
            force = u.amount * w**2 * ((np.cos(phi) * a + np.sin(phi) * b)
                                       - 1j * s * (-np.sin(phi) * a + np.cos(phi) * b))   # fc - i fs
            for i, sensor in enumerate(model.sensors):
                expected[i] += sum(force[k] * reference.receptance(speed, w, point, np.eye(3)[k], source,
                                                                   sensor.position, sensor.direction, None)
                                   for k in range(3))
        found = res.amplitude[:, j, 0] * np.exp(1j * np.radians(res.phase_deg[:, j, 0]))
        assert np.abs(found - expected).max() <= 1e-9 * np.abs(expected).max()
