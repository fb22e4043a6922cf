"""Issue 29 §4 / 27: the API 684 amplification factor and separation margins come from the exact
response, not from the swept speeds.

``AF = N_c / (N2 - N1)``: ``N_c`` the peak of the response, ``N1``, ``N2`` where it is
``peak / sqrt(2)``. The AF table read them off the line through the swept speeds, so a report's
AF depended on ``--points`` (examples/compressor_rotor.toml, probe-left-y: 25.9 at the report's 151
speeds, 32.4 from a 0.5 rpm sweep). Now each peak is the maximum of the exact response between its
swept neighbours and its half-power points are bisected on the exact response.

Truth from outside the code:

- a rigid rotor on two isotropic bearings (``tests/closed_form_machines.py``), the probe at its
  centre of mass: ``|x|^2 = U^2 u^2 / ((K - M u)^2 + C^2 u)``, ``u = w^2``, ``K = 2k``, ``C = 2c``;
  its maximum at ``u = 2 K^2 / (2 K M - C^2)`` and its half-power points the roots of the
  quadratic in ``u`` ``(P M^2 - 2 U^2) u^2 + (P C^2 - 2 P K M) u + P K^2 = 0`` (``P`` the peak of
  ``|x|^2``): the quartic in ``w`` solved by hand;
- an example's AF is the same at 51 and 401 report points (the peak and its band are the
  response's, not the grid's);
- an undamped model's response is unbounded at its resonance (AF infinite: the largest margin);
- API 684's largest required margins, 16 % below the range and 26 % above (any AF), written out.
"""

from __future__ import annotations

import importlib
import math
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from closed_form_machines import C_B, K_B, M_R, rotor_on_springs
from rotordyn_modal.analysis.unbalance import api_unbalance_response
from rotordyn_modal.cli.main import main

report_collect = importlib.import_module("rotordyn_modal.report.collect")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
U = 5e-5
RPM = np.pi / 30


def _closed_form():
    """(N_c, N1, N2) [rad/s] and the peak amplitude [m] of the rigid rotor, by hand."""
    k, c, m = 2 * K_B, 2 * C_B, M_R
    u = 2 * k ** 2 / (2 * k * m - c ** 2)
    peak2 = U ** 2 * u ** 2 / ((k - m * u) ** 2 + c ** 2 * u)
    a, b, e = peak2 * m ** 2 - 2 * U ** 2, peak2 * c ** 2 - 2 * peak2 * k * m, peak2 * k ** 2
    roots = np.sort(np.roots([a, b, e]).real)
    return math.sqrt(u), math.sqrt(roots[0]), math.sqrt(roots[1]), math.sqrt(peak2)


@pytest.mark.parametrize("points", [51, 401])
def test_rigid_rotor_af_is_the_closed_form(points):
    """The one peak's speed, amplitude, half-power points and AF equal the closed form's to 1e-6
    at 51 and at 401 swept speeds (closed form 3491.57 rpm, AF 13.6199; main: 3522 rpm, AF 12.70
    at 51 speeds, 3492.5 rpm, AF 13.6161 at 401)."""
    n_c, n1, n2, peak = _closed_form()
    result = rdm.unbalance_response(rotor_on_springs([{"rotor": "shaft", "amount": U}]),
                                    np.linspace(100.0, 6000.0, points) * RPM)
    table = result.peaks()
    assert len(table) == 1
    row = table.iloc[0]
    assert row.speed_rpm == pytest.approx(n_c / RPM, rel=1e-6)
    assert row.amplitude == pytest.approx(peak, rel=1e-9)
    assert row.amplification_factor == pytest.approx(n_c / (n2 - n1), rel=1e-6)
    assert result.peak_half_power[0, 0, 0] == pytest.approx([n1, n2], rel=1e-8)


def test_report_margins_of_the_rigid_rotor_are_the_closed_form():
    """The report's AF table (API static case, ``collect.separation_margins``) at the report's 51
    points: AF, margin from the range's low end and the required margin by hand."""
    n_c, n1, n2, _ = _closed_form()
    model = rotor_on_springs([{"rotor": "shaft", "amount": U}])
    inputs = report_collect.ReportInputs("api684", 6000 * RPM, (5000 * RPM, 6000 * RPM), points=51)
    response = api_unbalance_response(model, inputs.speeds, inputs.mcs)
    table = report_collect.separation_margins(response, inputs.range)
    row = table[table["case"] == "api-static:shaft"].iloc[0]
    af = n_c / (n2 - n1)
    assert row.amplification_factor == pytest.approx(af, rel=1e-6)
    assert row.separation_margin_pct == pytest.approx(100 * (5000 * RPM - n_c) / (5000 * RPM), rel=1e-6)
    assert row.required_margin_pct == pytest.approx(min(16.0, 17 * (1 - 1 / (af - 1.5))), rel=1e-6)


def test_an_example_af_is_the_same_at_51_and_401_points():
    """examples/compressor_rotor.toml, the report's API cases (MCS 9000 rpm): every peak of the
    static case has the same speed and AF at 51 and 401 report points (1e-6); main: 25.9 at 151
    points, and the 51-point sweep's differs from the 401-point one by percents."""
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")

    def static_peaks(points):
        inputs = report_collect.ReportInputs("api684", 9000 * RPM, (7000 * RPM, 9000 * RPM), points=points)
        table = report_collect.separation_margins(api_unbalance_response(model, inputs.speeds, inputs.mcs),
                                                  inputs.range)
        return table[table["case"] == "api-static:compressor"].sort_values(["output", "speed_rpm"])

    coarse, fine = static_peaks(51), static_peaks(401)
    assert list(coarse["output"]) == list(fine["output"]) and len(coarse) == 5     # 4 probes, midspan
    np.testing.assert_allclose(coarse["speed_rpm"], fine["speed_rpm"], rtol=1e-6)
    np.testing.assert_allclose(coarse["amplification_factor"], fine["amplification_factor"], rtol=1e-6)
    probes = coarse[coarse["output"].str.startswith("probe")]["amplification_factor"]
    assert len(probes) == 4 and np.all(probes > 32.0)                  # the 0.5 rpm sweep's 32.4


def test_an_undamped_resonance_has_an_infinite_af():
    """examples/spring_block_rotor.toml has no damping (every mode's damping ratio 0): its response
    is unbounded at the resonance, so AF is infinite and needs the largest margin (16 % below
    the range); main read AF 3.8 off the swept line."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    assert not any(b.damping for b in model.bearings)
    inputs = report_collect.ReportInputs("api684", 3000 * RPM)
    table = report_collect.separation_margins(api_unbalance_response(model, inputs.speeds, inputs.mcs),
                                              inputs.range)
    assert len(table) and np.all(np.isinf(table["amplification_factor"]))
    assert np.all(table["required_margin_pct"] == 16.0) and np.all(table["verdict"] == "pass")


@pytest.mark.parametrize("band, verdict, required", [((5000, 6000), "pass", 16.0), ((3300, 4000), "not evaluated",
                                                                                     np.nan),
                                                      ((2000, 2700), "pass", 26.0)])
def test_unknown_af_is_judged_against_the_largest_margin(band, verdict, required):
    """The sweep starts at 3450 rpm, above the lower half-power point (3370.4 rpm): AF
    unknown. A margin of 30 % below the range passes whatever the AF (16 % is the most API 684
    asks below), 29 % above it too (26 %); 0 % (the peak inside the range) is not evaluated.
    Main: 'not evaluated' in all three."""
    result = rdm.unbalance_response(rotor_on_springs([{"rotor": "shaft", "amount": U}]),
                                    np.linspace(3450.0, 6000.0, 101) * RPM)
    table = result.separation_margins((band[0] * RPM, band[1] * RPM))
    assert len(table) == 1 and np.isnan(table["amplification_factor"][0])
    assert table["verdict"][0] == verdict
    np.testing.assert_equal(table["required_margin_pct"][0], required)


def test_the_cli_says_why_an_unknown_af_is_judged_so(tmp_path, capsys):
    """``unbalance --operating-range``: a peak of unknown AF gets one line saying what its verdict
    rests on (main printed 'not evaluated' and no reason)."""
    import tomli_w

    path = tmp_path / "rotor.toml"
    path.write_bytes(tomli_w.dumps(rotor_on_springs([{"rotor": "shaft", "amount": U}]).to_dict()).encode())
    assert main(["unbalance", str(path), "--speeds", "3450:6000:101", "--operating-range", "5000:6000",
                 "--out", str(tmp_path / "u.csv")]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("AF unknown")]
    assert len(lines) == 1 and "16 % below" in lines[0] and "26 % above" in lines[0]


def test_a_search_over_its_work_keeps_the_swept_reading(monkeypatch):
    """Where the exact peaks' search would cost more than ``unbalance_peaks._WORK`` (a model of
    a few hundred coordinates with many peaks), the AF table reads the swept speeds, as
    ``amplification_factors`` does (no search is started)."""
    from rotordyn_modal.analysis import unbalance_peaks
    from rotordyn_modal.analysis.unbalance import amplification_factors

    speeds = np.linspace(100.0, 6000.0, 51) * RPM
    model = rotor_on_springs([{"rotor": "shaft", "amount": U}])
    monkeypatch.setattr(unbalance_peaks, "_AF_CALLS", 1e12)
    result = rdm.unbalance_response(model, speeds)
    assert result.peak_speeds is None
    ((speed, amplitude, af),) = amplification_factors(speeds, result.amplitude[0, 0])
    row = result.peaks().iloc[0]
    assert (row.amplitude, row.amplification_factor) == (amplitude, af)
    assert row.speed_rpm == pytest.approx(speed / RPM, rel=1e-15) == 3522.0         # a swept speed


def test_a_half_power_point_is_the_nearest_crossing_beside_a_hidden_peak():
    """examples/fan_on_bearings.toml, report at MCS 3000 rpm: the motor's 3891 rpm peak has a
    sharper one (AF about 101) at 3949 rpm beside it, between the 51 report points' swept speeds.
    Its upper half-power point is where the response first falls to peak / sqrt(2), before that
    neighbour (about 3932 rpm), at 51 points as at 401 (before the minimum between them was
    searched: AF 27.1 at 51 points, 35.7 at 401; main, swept: 24.8 and 35.95)."""
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")

    def peak(points):
        inputs = report_collect.ReportInputs("api684", 3000 * RPM, points=points)
        response = api_unbalance_response(model, inputs.speeds, inputs.mcs)
        o, j = response.outputs.index("probe-DE-x"), response.sources.index("api-static:motor")
        k = int(np.nanargmin(np.abs(response.peak_speeds[o, j] - 3891.4 * RPM)))
        return response.peak_speeds[o, j, k], response.peak_half_power[o, j, k]

    (coarse, (low, high)), (fine, band) = peak(51), peak(401)
    assert coarse == pytest.approx(fine, rel=1e-7) and abs(coarse / RPM - 3891.4) < 1
    np.testing.assert_allclose([low, high], band, rtol=1e-7)
    assert 3900 < high / RPM < 3945                                   # before the 3949 rpm peak
