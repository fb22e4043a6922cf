"""A run-up's order track against the steady response, with a tolerance that follows from the ramp
rate (issue 27 §3).

A mode ``x'' + 2 zeta w x' + w^2 x = Omega^2 cos(phi)`` swept at ``alpha`` [Hz/s] lags its steady
response ``A0 = Omega^2 / (w^2 - Omega^2 + 2 i zeta w Omega)``: writing ``x = A exp(i phi)`` and
keeping the first term in the sweep, ``A - A0 = i a A0 / (zeta w)^2`` at the peak, ``a = 2 pi
alpha``, so the track differs from the steady response by ``alpha / (2 pi (zeta f)^2)`` of the
peak. The truth here: that expansion, and the closed-form steady response of the simulated mode
(scipy's ODE solution of the record, ``test_runup_passage27._swept_mode``). A slow ramp's track
equals the steady response to that tolerance; a ramp whose tolerance exceeds the one the figure
states (10 % of the peak) is marked there (main marked from 16 %: 0.8 (zeta f)^2, 13 % off,
was not).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from rotordyn_modal.simulation import runup
from rotordyn_modal.simulation.runup import order_track
from test_runup_passage27 import F_N, ZETA, _crossing, _marked, _steady, _swept_mode

START = 8.0        # s from rest during which the start's ringing (sigma = 1.1 /s) is left out


def _lag(ratio):
    """The expansion's distance from the steady response, as a share of its peak, of a sweep of
    ``ratio (zeta f)^2`` [Hz/s]: ``alpha / (2 pi (zeta f)^2)``."""
    return ratio / (2 * np.pi)


@functools.lru_cache(maxsize=None)
def _run(ratio):
    """The mode swept from 5.4 to 6.6 Hz at ``ratio (zeta f)^2``: the record, its track, the
    track's complex amplitude and the steady one, after :data:`START`."""
    sweep = ratio * (ZETA * F_N) ** 2
    record = _swept_mode(1.2 / sweep, f0=5.4, f1=6.6, rate=100.0)
    track = order_track(record, "s")
    tracked = track.amplitude * np.exp(1j * np.radians(track.phase_deg))
    later = track.speeds > 2 * np.pi * (5.4 + sweep * START)
    return record, track, tracked, _steady(track.speeds), later


@pytest.mark.parametrize("ratio", [0.2, 0.5])
def test_a_slow_ramps_track_is_the_steady_response_to_the_tolerance_of_its_rate(ratio):
    """At 0.2 and 0.5 (zeta f)^2 the track's largest distance from the steady response is 0.8 to
    1.2 times ``alpha / (2 pi (zeta f)^2)`` of the peak (3 % and 8 %): the lag, and no more."""
    _, _, tracked, steady, later = _run(ratio)
    worst = np.abs(tracked - steady)[later].max() / np.abs(steady).max()
    assert 0.8 * _lag(ratio) <= worst <= 1.2 * _lag(ratio), (worst, _lag(ratio))
    assert runup.quasi_static_deviation(ratio * (ZETA * F_N) ** 2, F_N, ZETA) == pytest.approx(_lag(ratio), rel=1e-12)


@pytest.mark.parametrize("ratio", [0.5, 0.8])
def test_unmarked_windows_are_within_the_stated_tolerance_and_a_faster_passage_is_marked(ratio):
    """The figure states that outside its shading the track is the steady response within 10 % of
    the peak. At 0.5 (zeta f)^2 (8 %) nothing near the mode is marked; at 0.8 (13 %) the mode's
    windows are, and every unmarked window is within 10 % (main: not marked, 13 % off)."""
    record, track, tracked, steady, later = _run(ratio)
    marked, spans = _marked(record, track, _crossing())
    near = np.abs(track.speeds / (2 * np.pi) - F_N) < 2 * ZETA * F_N
    assert marked[near].all() if _lag(ratio) > 0.1 else not marked[near & later].any(), spans
    error = np.abs(tracked - steady)[later & ~marked] / np.abs(steady).max()
    assert error.max(initial=0.0) <= getattr(runup, "STEADY_TOLERANCE", 0.1), error.max()
