"""A peak that the swept line cuts is marked at the response's true maximum (issue 27, section 3:
"figures that cannot mislead"). ``unbalance motor_pump_on_mounts.toml --speeds 100:6000:60``:
two close pump modes (damped critical speeds near 526 and 578 rpm) share one peak at 545 rpm on
the pump's accelerometer; it was marked by two diamonds, one at each damped critical speed,
both below the peak (9.4e-6 and 8.6e-6 against 1.06e-5).

Checked from outside the code: a 0.1 rpm sweep of ``unbalance_response`` (without marks) gives
each true peak, and ``amplification_factors`` on it the API 684 amplification factor
``N_c / (N2 - N1)`` (half-power points of a curve that resolves the peak).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import amplification_factors

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
COARSE = np.linspace(100.0, 6000.0, 60)          # rpm, 100 rpm apart
FINE = np.arange(100.0, 1000.05, 0.1)            # rpm


@pytest.fixture(scope="module")
def pump():
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    coarse = rdm.unbalance_response(model, rdm.rpm(COARSE))
    fine = rdm.unbalance_response(model, rdm.rpm(FINE), resonances=False)
    return coarse, fine


def _fine_peak(fine, o, j, lo, hi):
    """``(rpm, amplitude, AF)`` of the fine sweep's highest peak between ``lo`` and ``hi`` rpm."""
    found = [(s * 30 / np.pi, a, af) for s, a, af in amplification_factors(fine.speeds, fine.amplitude[o, j])
             if lo < s * 30 / np.pi < hi]
    return max(found, key=lambda peak: peak[1])


def test_two_close_modes_sharing_one_peak_get_one_mark_at_it(pump):
    coarse, fine = pump
    o, j = coarse.outputs.index("acc-pump-z"), coarse.sources.index("pump")
    at, response, _ = coarse.cut_peaks("acc-pump-z", "pump")
    rpm = at * 30 / np.pi
    inside = (rpm > 500) & (rpm < 600)
    speed, peak, _ = _fine_peak(fine, o, j, 500, 600)
    assert 540 < speed < 550 and peak > 1.0e-5                      # the shared peak, as seen at 0.1 rpm
    assert inside.sum() == 1, rpm[inside]
    assert abs(rpm[inside][0] - speed) < 0.2
    assert abs(abs(response[inside][0]) / peak - 1) < 1e-4


def test_every_mark_is_a_true_peak_with_its_api_amplification_factor(pump):
    """Each mark and its peaks-table row against the 0.1 rpm sweep: speed within 0.2 rpm,
    amplitude within 1e-4, AF within 0.5 %."""
    coarse, fine = pump
    table = coarse.peaks()
    count = 0
    for o, output in enumerate(coarse.outputs):
        for j, source in enumerate(coarse.sources):
            at, response, width = coarse.cut_peaks(output, source)
            for s, value, w in zip(at * 30 / np.pi, response, width * 30 / np.pi):
                k = np.searchsorted(COARSE, s)
                speed, peak, af = _fine_peak(fine, o, j, COARSE[k - 1], COARSE[k])
                assert abs(s - speed) < 0.2, (output, source, s, speed)
                assert abs(abs(value) / peak - 1) < 1e-4, (output, source, s)
                rows = table[(table.output == output) & (table.source == source)
                             & (abs(table.speed_rpm - s) < 1e-9)]
                assert len(rows) == 1, (output, source, s)
                assert abs(rows.iloc[0].amplitude / peak - 1) < 1e-4
                assert abs(rows.iloc[0].amplification_factor / af - 1) < 5e-3, (output, source, s, af)
                assert abs(s / w / af - 1) < 5e-3
                count += 1
    assert count >= 8


def test_api_cases_keep_their_own_marks(pump):
    """The API cases' result carries each case's own marks (one source each, padded): the
    unbalance case of the pump rotor marks the shared peak once, as the model's own response."""
    coarse, _ = pump
    from rotordyn_modal.analysis.unbalance import api_unbalance_response

    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    api = api_unbalance_response(model, rdm.rpm(COARSE), rdm.rpm(3000.0))
    o = api.outputs.index("acc-pump-z")
    for k, case in enumerate(api.sources):
        if api.case_rotors[k] != "pump":
            continue
        at = api.cut_peak_speeds[o, k]
        rpm = at[np.isfinite(at)] * 30 / np.pi
        assert ((rpm > 500) & (rpm < 600)).sum() <= 1, (case, rpm)
