"""simulate's loose ends (issue 27 §1/§3, issue 28 §3).

* The linear (flexible-rotor) time model at rest: the basis keeps the modes the output times can
  see. Truth: the linear model's own impulse response, ``scipy.linalg.expm`` of its state matrix
  built here from ``model.matrices`` (main kept the six lowest modes at rest, whatever the output
  times, and sampled 201 times: 26 % off on the compressor).
* The run-up figure's phase panel draws the steady unbalance response's phase beside the track.
  Truth: ``rdm.unbalance_response`` at the track's speeds.
* The shade's words say what its share measures: the track's distance from the steady response
  (amplitude and phase together) over the resonance's steady peak, not the peak's shortfall. Truth:
  the closed-form steady response of one swept mode.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.simulation.runup import order_track, unsettled_spans
from test_runup30 import MACHINE, RPM, _shade_text
from test_runup_passage27 import F_N, ZETA, _crossing, _steady, _swept_mode


# ---------------------------------------------------------------------------------------------
# 1. the linear time model at rest


def _impulse_response(model, excitation, speed, times):
    """The linear model's sensors after a unit impulse through ``excitation`` at constant
    ``speed`` [rad/s], at the evenly spaced ``times`` [s], shape (N, sensors): the state matrix
    ``[[0, I], [-M^-1 K, -M^-1 (C + speed G)]]`` of ``model.matrices(speed)`` stepped by
    ``scipy.linalg.expm`` of it times the output step (no modes, no basis)."""
    from rotordyn_modal.assembly import excitation_columns, sensor_rows

    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    step = scipy.linalg.expm(A * (times[1] - times[0]))
    x = np.r_[np.zeros(n), np.linalg.solve(M, excitation_columns(model, [excitation])[:, 0])]
    rows = sensor_rows(model)
    out = np.empty((len(times), rows.shape[0]))
    for i in range(len(times)):
        out[i] = rows @ x[:n]
        x = step @ x
    return out


@pytest.mark.parametrize("speed, samples, tolerance", [(0.0, None, 1e-2), (0.0, 2001, 1e-3), (1.0, 2001, 1e-3)])
def test_an_impulse_at_rest_or_at_a_slow_spin_is_the_linear_models_impulse_response(examples_dir, speed, samples,
                                                                                    tolerance):
    """examples/compressor_rotor.toml hit by 1 N s at its mid-span shaker, at rest and at 1 rad/s,
    0.05 s: every sensor equals the linear model's own impulse response (expm) at the output times
    within 1 % of its largest value with the default output times, 0.1 % with 2,001 (a Nyquist
    frequency of 20 kHz). On main the basis held the six lowest modes (cutoff 4 x the spin: 0) and
    the output 201 times: 27 % off either way."""
    model = rdm.load_model(examples_dir / "compressor_rotor.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = rdm.simulate(model, 0.05, speed, impulse="shaker-y", impulse_size=1.0, samples=samples)
    truth = _impulse_response(model, "shaker-y", speed, run.time)
    assert np.allclose(np.diff(run.time), run.time[1], rtol=1e-9)
    error = np.abs(run.sensors - truth).max() / np.abs(truth).max()
    assert error <= tolerance, error


def test_the_default_output_times_at_rest_resolve_the_modes_the_basis_keeps(examples_dir):
    """At rest the default output times are at least 20 per period of the fastest of the lowest
    modes the basis keeps for the spin (the six lowest, from the model's own eigenvalues here; since
    sim32 more where the impulse reaches faster modes: tests/test_simulate32.py), and under an
    impulse the basis holds every mode below their Nyquist frequency (main: 201 output times over
    1 s, under 2 per period of the sixth mode, 444 Hz)."""
    from rotordyn_modal.simulation.flexible import output_nyquist, reduced_system

    model = rdm.load_model(examples_dir / "compressor_rotor.toml")
    M, C, G, K = model.matrices(0.0)
    sixth = np.sqrt(np.sort(scipy.linalg.eigvalsh(0.5 * (K + K.T), 0.5 * (M + M.T)))[5])
    run = rdm.simulate(model, 1.0, 0.0, impulse="shaker-y", impulse_size=1.0, samples=None)
    assert len(run.time) >= int(20 * sixth / (2 * np.pi) * 1.0 + 1)
    nyquist = output_nyquist(len(run.time), 1.0)
    assert nyquist > 8 * sixth
    values = np.sqrt(np.abs(scipy.linalg.eigvalsh(0.5 * (K + K.T), 0.5 * (M + M.T))))
    basis = reduced_system(model, 0.0, nyquist)
    assert basis.modes == int(np.sum(values < nyquist))


# ---------------------------------------------------------------------------------------------
# 2. the steady phase on the run-up figure


@pytest.fixture(scope="module")
def ramp(tmp_path_factory):
    """test_runup30's rotor on a pedestal run up from 600 to 9,000 rpm in 1 s (numpy backend)."""
    path = tmp_path_factory.mktemp("runup31") / "pedestal.toml"
    path.write_text(MACHINE, encoding="utf-8")
    model = rdm.load_model(path)
    run = rdm.simulate(model, 1.0, rdm.rpm(600.0), drive="ramp", final_speed=rdm.rpm(9000.0), backend="numpy")
    critical = rdm.campbell(model, np.linspace(rdm.rpm(600.0), rdm.rpm(9000.0), 121)).critical
    return path, model, run, critical


def _line(fig, gid):
    lines = [line for ax in fig.axes for line in ax.get_lines() if line.get_gid() == gid]
    assert len(lines) == 1, [line.get_label() for ax in fig.axes for line in ax.get_lines()]
    return lines[0]


def _turns_apart(a_deg, b_deg):
    """``a - b`` brought within (-180, 180] deg by whole turns [deg]."""
    return np.degrees(np.angle(np.exp(1j * np.radians(np.asarray(a_deg) - np.asarray(b_deg)))))


def test_the_phase_panel_draws_the_steady_phase_at_the_track_speeds(ramp):
    """The phase panel's dashed curve lies at the track's speeds, equals the phase of
    ``unbalance_response`` there to 1e-9 (modulo whole turns), sits beside the track's unwrapped
    phase (no turn away), and where the track is not shaded the two differ by no more than the
    stated tolerance allows: a complex distance of 10 % of the peak turns the phase by at most
    ``arcsin(0.1 peak / |A|)`` (main: no steady curve on the phase panel)."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.simulation.runup import steady_orders

    _, model, run, critical = ramp
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fig = run.plot(sensor="s", critical=critical, steady=steady_orders(model, run, "s"))
    line = _line(fig, "steady-phase-r")
    phase_ax = next(ax for ax in fig.axes if ax.get_title() == "Order-tracked phase")
    assert line in phase_ax.get_lines() and line.get_linestyle() == "--" and "steady" in line.get_label()
    track = order_track(run, "s")
    truth = rdm.unbalance_response(model, track.speeds, outputs=["s"]).response[0, 0]
    drawn = np.asarray(line.get_ydata(), dtype=float)
    assert np.allclose(line.get_xdata(), track.speeds * RPM, rtol=1e-12, atol=0)
    assert np.abs(np.radians(_turns_apart(drawn, np.degrees(np.angle(truth))))).max() <= 1e-9
    known = np.isfinite(track.unwrapped_phase_deg)
    assert known.sum() > len(known) // 2
    assert np.median(np.abs(drawn - track.unwrapped_phase_deg)[known]) < 180.0
    shaded = np.zeros(len(track.speeds), dtype=bool)
    for low, high in unsettled_spans(run, track, critical):
        shaded |= (track.speeds >= low) & (track.speeds <= high)
    check = known & ~shaded
    assert check.any()
    bound = np.degrees(np.arcsin(np.minimum(1.0, 0.1 * np.abs(truth).max() / np.abs(truth))))
    assert np.all(np.abs(drawn - track.unwrapped_phase_deg)[check] <= bound[check])
    plt.close(fig)


def test_simulate_ramp_plot_draws_the_steady_phase(ramp, tmp_path, monkeypatch):
    """``simulate MODEL --speed 600 --ramp 9000 --duration 1 --plot``: the saved figure's phase
    panel holds the steady curve, the phase of ``unbalance_response`` at the track's speeds to
    1e-9 (main: none)."""
    from rotordyn_modal.cli import main
    from rotordyn_modal.cli import simulate as command

    path, model, _, _ = ramp
    saved = []
    monkeypatch.setattr(command, "save_figure", lambda fig, args: saved.append(fig))
    code = main(["simulate", str(path), "--speed", "600", "--ramp", "9000", "--duration", "1", "--backend", "numpy",
                 "--plot", str(tmp_path / "runup.png"), "--quiet"])
    assert code == 0 and len(saved) == 1
    line = _line(saved[0], "steady-phase-r")
    speeds = np.asarray(line.get_xdata()) / RPM
    truth = rdm.unbalance_response(model, speeds, outputs=["s"]).response[0, 0]
    assert np.abs(np.radians(_turns_apart(line.get_ydata(), np.degrees(np.angle(truth))))).max() <= 1e-9


# ---------------------------------------------------------------------------------------------
# 3. the words of the lag


def test_the_lag_is_named_as_the_distance_it_is_not_as_the_peaks_shortfall():
    """One mode (6 Hz, zeta 0.03) swept at 0.8 ``(zeta f)^2``: the shade's legend and the warning
    state the estimate as the track's distance from the steady response over that resonance's
    steady peak, amplitude and phase together, and the number is that distance within 3 points
    (closed form); the peak's shortfall is far smaller (under a third of it), so words reading as
    'peak 13 % below' would be wrong (main: 'about 13% of the mode's peak')."""
    sweep = 0.8 * (ZETA * F_N) ** 2
    record = _swept_mode(3.0 / sweep, f0=4.5, f1=7.5, rate=100.0)
    note, warned = _shade_text(record, _crossing())
    track = order_track(record, "s")
    steady = _steady(track.speeds)
    near = np.abs(track.speeds / (2 * np.pi) - F_N) < 4 * ZETA * F_N
    tracked = track.amplitude * np.exp(1j * np.radians(track.phase_deg))
    peak = np.abs(steady).max()
    distance = np.abs(tracked - steady)[near].max() / peak
    shortfall = (peak - track.amplitude[near].max()) / peak
    for text in (note, warned):
        found = re.search(r"lag through mode 1 \(estimate: near it the track is off the steady response by up to "
                          r"(\d+)% of that resonance's steady peak, amplitude and phase together\)", text)
        assert found, text
        assert abs(float(found[1]) / 100 - distance) <= 0.03, (found[1], distance)
    assert abs(shortfall) < distance / 3, (shortfall, distance)
