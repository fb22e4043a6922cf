"""Order tracking with a window that nulls the other rotors' same order (issue 27, section 3,
the run-up figure). The fan's run-up: a window of four turns of the motor passes 0.26 of the
fan's 1X (1.6:1 belt), so the motor's 1X phase was unknown at 26 of 27 speeds and its amplitude
carried the fan's leakage. A rectangular window of R turns at a steady speed passes a rotor
turning rho times as fast with |sinc(R (rho - 1))| + |sinc(R (rho + 1))|: 0 where both are whole
numbers of cycles, R = 8 for rho = 0.625 (3 and 13 cycles).
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from rotordyn_modal.simulation.runup import order_track, window_turns


def _two_orders(ratio, amplitude, duration=8.0, step=2e-4, speed=300.0, theta=0.7):
    """A sensor reading ``amplitude(t) cos(phi + theta) + cos(ratio phi + 0.3)`` at a steady
    ``speed`` [rad/s] of rotor 'a' (rotor 'b' turning ``ratio`` times as fast)."""
    t = np.arange(0.0, duration, step)
    phi = speed * t
    signal = amplitude(t) * np.cos(phi + theta) + np.cos(ratio * phi + 0.3)
    return types.SimpleNamespace(time=t, drive_speed=np.full(t.shape, speed),
                                 rotor_angles=np.column_stack([phi, ratio * phi]), speed_ratios=np.array([1.0, ratio]),
                                 rotor_names=["a", "b"], model_name="two orders", sensor_names=["s"],
                                 sensor=lambda name: signal)


def _response(turns, rho):
    return abs(np.sinc(turns * (rho - 1.0))) + abs(np.sinc(turns * (rho + 1.0)))


@pytest.mark.parametrize("ratios, index, expected", [
    ([1.0, 0.625], 0, 8),      # the motor of the fan's belt: 3 and 13 cycles, a null
    ([1.0, 0.625], 1, 5),      # the fan: rho = 1.6, 3 and 13 cycles over 5 turns
    ([1.0], 0, 4),             # one rotor: nothing to null, the shortest window
    ([1.0, -1.0, 1.0], 0, 4),  # rotors as fast either way share the order line: nothing to null
    ([1.0, 0.7], 0, 7),        # no null from 4 to 8 turns: the least leaking, 0.055 at 7
])
def test_window_turns_nulls_the_other_rotors_order(ratios, index, expected):
    assert window_turns(ratios, index) == expected
    rho = [abs(r / ratios[index]) for j, r in enumerate(ratios) if j != index and abs(abs(r) - abs(ratios[index])) > 1e-9]
    if rho:                    # the closed form at the chosen length is the least of 4-8 turns
        chosen = max(_response(expected, r) for r in rho)
        assert all(chosen <= max(_response(R, r) for r in rho) + 1e-12 for R in range(4, 9))


def test_the_weak_order_keeps_its_phase_where_the_window_nulls_the_strong_one():
    """Rotor 'a''s 1X grows from 0.01 to 10 beside 'b''s 1X of amplitude 1 (rho = 0.625, the fan's
    belt), steady 300 rad/s. The default window (8 turns: a null) gives a's phase, 0.7 rad, in
    every window, to within what the windows' ends (on samples, not on whole turns) leak of b
    (0.05 rad where a > 0.1), and its amplitude to that leak; its leakage floor is below 1 % of
    b's amplitude. With four turns
    (the old default) the floor was 0.26 and the phase unknown wherever a < 0.26."""
    strong = lambda time: 10.0 ** (-2.0 + 3.0 * time / 8.0)     # noqa: E731
    result = _two_orders(0.625, strong)
    track = order_track(result, "s", rotor="a")
    period = 2 * np.pi * 8 / 300.0                            # one window of 8 turns [s]
    middle = (np.arange(len(track.amplitude)) + 0.5) * period
    assert len(track.amplitude) == int(result.time[-1] / period)
    assert np.all(track.leakage_floor < 0.01)
    assert np.all(np.isfinite(track.phase_deg))
    weak = strong(middle) < 0.1
    assert weak.sum() >= 5
    error = np.abs(np.angle(np.exp(1j * (np.radians(track.phase_deg) - 0.7))))
    low, high = strong(middle - period / 2), strong(middle + period / 2)
    # the windows end on samples (2e-4 s apart): up to a sample at each end off 8 whole turns,
    # which passes at most 2 x 2 samples / window of b's unit 1X (both of its terms)
    leak = 4 * 2e-4 / period
    assert leak < 5e-3
    # and a's own negative frequency, nulled by whole turns, comes back with its growth over the
    # window (a factor high / low = 1.16): at most that share of it
    assert np.all(error <= np.arcsin(np.minimum(1.0, leak / low + (high - low) / low)))
    assert error[low > 0.1].max() < 0.05
    # the window averages the growing amplitude: its size lies between the ends'
    assert np.all(track.amplitude > low - leak) and np.all(track.amplitude < high + leak)
    old = order_track(result, "s", rotor="a", revolutions=4)
    assert np.all(np.isnan(old.phase_deg[strong((np.arange(len(old.amplitude)) + 0.5) * period / 2) < 0.1]))
