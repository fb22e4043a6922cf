"""The linear (flexible-rotor) time model keeps, and its default output times resolve, the modes a
sudden load reaches at the sensors (issue 27 §1, issue 28 §3).

Truth, computed here without the code under test: the linear model's own response, the state matrix
``[[0, I], [-M^-1 K, -M^-1 (C + speed G)]]`` of ``model.matrices`` stepped by ``scipy.linalg.expm``
(augmented by a constant state for the weights set on at t = 0), and each undamped mode's share of a
load's response at the sensors from ``scipy.linalg.eigh`` of ``(K, M)``: ``|c phi_j| |phi_j^T J| / w_j``
after an impulse ``J``, ``|c phi_j| |phi_j^T F| / w_j^2`` after a step ``F``, over the largest.
On main (sim31) the basis at rest followed the output times' Nyquist frequency only: with the default
201 times over 0.5 s, flexible_pump_on_mounts' impeller-hub tap left out the pump's bending modes
(2.4e-2 off), and nothing said that given output times could not show a mode that carried 17 % of
the response.
"""

from __future__ import annotations

import logging
import re
import warnings

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm

PUMP = "flexible_pump_on_mounts.toml"
COMPRESSOR = "compressor_rotor.toml"


def _linear_response(model, speed, times, impulse=None, size=1.0):
    """The linear model's sensors [m], shape (N, sensors), at the evenly spaced ``times`` [s] after
    an impulse ``size`` [N s] through ``impulse`` at t = 0 and, from the undeformed machine, its
    weights ``M a_g`` set on at t = 0 (``a_g``: ``model.gravity`` on the casing's translation, the
    machine being on mounts), at constant ``speed`` [rad/s] without unbalance (at rest)."""
    from rotordyn_modal.assembly import excitation_columns, sensor_rows

    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.zeros((2 * n + 1, 2 * n + 1))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -np.linalg.solve(M, K)
    A[n:2 * n, n:2 * n] = -np.linalg.solve(M, C + speed * G)
    if np.any(model.gravity):
        assert model.dofs.n_frame == 6            # the weights: the casing's uniform acceleration
        A[n:n + 3, -1] = model.gravity
    step = scipy.linalg.expm(A * (times[1] - times[0]))
    x = np.zeros(2 * n + 1)
    x[-1] = 1.0
    if impulse is not None:
        x[n:2 * n] = np.linalg.solve(M, size * excitation_columns(model, [impulse])[:, 0])
    rows = sensor_rows(model)
    out = np.empty((len(times), rows.shape[0]))
    for i in range(len(times)):
        out[i] = rows @ x[:n]
        x = step @ x
    return out


def _shares(model, impulse=None, weights=False):
    """Each undamped mode's frequency [Hz] and share of the load's largest modal response at a
    sensor (largest over the sensors; over the impulse and the weights), ascending."""
    from rotordyn_modal.assembly import excitation_columns, sensor_rows

    M, _, _, K = model.matrices(0.0)
    values, vectors = scipy.linalg.eigh(0.5 * (K + K.T), 0.5 * (M + M.T))
    assert values.min() > 0                         # on mounts: no rigid-body mode
    w = np.sqrt(values)
    seen = np.abs(sensor_rows(model) @ vectors)
    share = np.zeros(len(w))
    loads = []
    if impulse is not None:
        loads.append((excitation_columns(model, [impulse])[:, 0], 1))
    if weights:
        loads.append((M @ np.r_[model.gravity, np.zeros(len(M) - 3)], 2))
    for load, power in loads:
        at = seen * np.abs(vectors.T @ load) / w ** power
        share = np.maximum(share, at.max(axis=0) / at.max())
    return w / (2 * np.pi), share


def _run(model, duration, speed=0.0, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.simulate(model, duration, speed, **options)


def _error(run, truth):
    """Largest sensor difference over the largest value."""
    return np.abs(run.sensors - truth).max() / np.abs(truth).max()


@pytest.mark.parametrize("example, impulse, duration, tolerance", [
    (PUMP, "hub-tap-y", 0.5, 2e-3),      # main 2.4e-2: the pump's bending modes left out
    (PUMP, "hammer-z", 0.5, 2e-3),       # main 1.7e-3
    (PUMP, None, 0.5, 1e-5),             # the weights set on from rest; main 1.4e-6
    (COMPRESSOR, "shaker-y", 0.05, 1e-3),  # main 2.2e-3
])
def test_a_sudden_load_at_rest_with_the_defaults_is_the_linear_models_response(examples_dir, example, impulse,
                                                                             duration, tolerance):
    """At rest with the default basis and output times, every sensor after a tap (1 N s) or the
    weights set on from rest equals the linear model's own response (expm) at the output times
    within ``tolerance`` of its largest value, the output times evenly spaced."""
    model = rdm.load_model(examples_dir / example)
    run = _run(model, duration, impulse=impulse, impulse_size=1.0)
    assert np.allclose(np.diff(run.time), run.time[1], rtol=1e-9)
    error = _error(run, _linear_response(model, 0.0, run.time, impulse))
    assert error <= tolerance, error


def test_the_default_output_times_resolve_every_mode_the_tap_reaches_and_say_so(examples_dir, capsys):
    """The hub tap reaches the pump's bending modes at the bearing's probes: the default output
    times give at least 10 per period of every mode carrying over 1e-3 of the tap's largest modal
    response at a sensor (and not more than needed for the fastest), and, past 10 times the
    spin's 201, one line on stderr says how many, naming the fastest such mode and its frequency
    (main: 201, 1.9 a period of the 280 Hz bending mode)."""
    model = rdm.load_model(examples_dir / PUMP)
    hz, share = _shares(model, "hub-tap-y", weights=True)
    fastest = hz[share > 1e-3].max()
    assert fastest > 1000.0                       # beyond the mounts and the first bending modes
    run = _run(model, 0.5, impulse="hub-tap-y", impulse_size=1.0)
    per_period = 1.0 / (fastest * run.time[1])
    assert 10.0 <= per_period < 10.0 * (1 + 1e-3), per_period
    lines = [line for line in capsys.readouterr().err.splitlines() if "output times" in line]
    assert len(lines) == 1, lines
    assert f"{len(run.time):,} output times (not 201)" in lines[0]
    shown = re.search(r"undamped mode (\d+) \(([\d,]+) Hz\)", lines[0])
    assert shown and abs(float(shown[2].replace(",", "")) - fastest) <= 0.5, (lines[0], fastest)
    assert int(shown[1]) == int(np.argmin(np.abs(hz - fastest))) + 1


def test_a_smaller_growth_is_said_on_the_log(examples_dir, caplog, capsys):
    """A tap on the compressor at 6,000 rpm for 10 ms: the default output times grow under 10
    times (from 201), said on the log ('--verbose') and not on stderr."""
    model = rdm.load_model(examples_dir / COMPRESSOR)
    with caplog.at_level(logging.INFO, logger="rotordyn_modal.simulation"):
        run = _run(model, 0.01, rdm.rpm(6000.0), impulse="shaker-y", impulse_size=1.0)
    assert 201 < len(run.time) < 2010
    said = [r.getMessage() for r in caplog.records if "output times" in r.getMessage()]
    assert len(said) == 1 and said[0].startswith(f"{len(run.time):,} output times (not 201)"), said
    assert "output times" not in capsys.readouterr().err


def test_given_output_times_that_cannot_resolve_a_mode_carrying_over_1_percent_warn_once(examples_dir):
    """``samples=2001`` over 0.05 s on the compressor's shaker tap: 2,001 output times are under
    10 a period of modes carrying over 1 % of the tap's response: one warning names the one
    carrying most and its frequency. Output times enough for every mode over 1 % give none, and
    the given output times are obeyed either way (main: no word)."""
    model = rdm.load_model(examples_dir / COMPRESSOR)
    hz, share = _shares(model, "shaker-y")
    step = 0.05 / 2000
    short = (share > 1e-2) & (1.0 / (hz * step) < 10)
    assert short.any()
    named = int(np.argmax(np.where(short, share, -1.0)))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = rdm.simulate(model, 0.05, 0.0, impulse="shaker-y", impulse_size=1.0, samples=2001)
    assert len(run.time) == 2001
    lines = [str(w.message) for w in caught if "a period of undamped mode" in str(w.message)]
    assert len(lines) == 1, lines
    shown = re.search(r"undamped mode (\d+) \(([\d,]+) Hz\)", lines[0])
    assert shown and int(shown[1]) == named + 1, (lines[0], named + 1)
    assert abs(float(shown[2].replace(",", "")) - hz[named]) <= 0.5
    enough = int(np.ceil(10 * hz[share > 1e-2].max() * 0.05)) + 1
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run = rdm.simulate(model, 0.05, 0.0, impulse="shaker-y", impulse_size=1.0, samples=enough)
    assert len(run.time) == enough
    assert not [w for w in caught if "a period of undamped mode" in str(w.message)]


@pytest.mark.parametrize("speed_rpm, drive, final_rpm, initial", [
    (3000.0, "constant", None, "equilibrium"),     # a steady unbalance response
    (3000.0, "constant", None, "rest"),            # ... with the weights set on from rest
    (0.0, "ramp", 3000.0, "rest"),                 # a run-up from rest
])
def test_runs_whose_loads_reach_no_faster_mode_keep_their_basis_and_output_times(examples_dir, speed_rpm, drive,
                                                                                 final_rpm, initial):
    """Runs whose only sudden load is the weights (which reach the mount modes only) keep the
    spin's rule: 20 output times per period of the fastest of the spin and the modes kept for
    it, and the basis of the modes below 4 times the fastest spin frequency or, under the weights
    set on from rest, the output times' Nyquist frequency: the same sensors, bit for bit, as the
    run given that cutoff (unchanged from main)."""
    from rotordyn_modal.simulation.flexible import output_nyquist

    model = rdm.load_model(examples_dir / PUMP)
    hz, share = _shares(model, weights=initial == "rest")
    spin = max(speed_rpm, final_rpm or 0.0) / 60 * max(abs(r.speed_ratio) for r in model.rotors)
    kept = hz[:max(6, int(np.sum(hz < 4 * spin)))]
    assert hz[share > 1e-3].max(initial=0.0) <= kept.max()
    count = int(max(201, 20 * max(spin, kept.max()) * 0.5 + 1))
    options = dict(drive=drive, final_speed=None if final_rpm is None else rdm.rpm(final_rpm), initial=initial)
    run = _run(model, 0.5, rdm.rpm(speed_rpm), **options)
    assert len(run.time) == count
    cutoff = 2 * np.pi * 4 * spin
    if initial == "rest":
        cutoff = max(cutoff, output_nyquist(count, 0.5))
    given = _run(model, 0.5, rdm.rpm(speed_rpm), modes_below=cutoff, samples=count, **options)
    assert np.array_equal(run.sensors, given.sensors)
