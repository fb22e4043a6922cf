"""Issue 29 / 27 §5, one vocabulary and steady operation:

- ``unbalance --operating-range LO:HI`` measures the API 684 separation margin from the nearer
  end of the range (below it from LO, above it from HI, inside it 0), as ``report`` does, and
  ``--operating-speed S`` is the range ``S:S``;
- the ISO 20816-3 zones judge steady operation: with an operating range, the casing velocity over
  that range (a mount resonance crossed in the run-up fails no machine that runs in zone A);
- a rigid rotor's API 617 critical speed ratio (no critical speed on rigid supports) is
  ``not evaluated``, not ``pass (0; ...)``.

Truth: the closed-form response of a rigid body on isotropic springs
``|x| = U w^2 / |k - m w^2 + i w c|`` and the API 684 / ISO 20816-3 rules written out here.
"""

from __future__ import annotations

import importlib
import io
import math

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from closed_form_machines import casing_displacement, casing_model, rotor_displacement, rotor_on_springs
from rotordyn_modal.cli.main import main

report_collect = importlib.import_module("rotordyn_modal.report.collect")

# -- a rigid rotor on two isotropic bearings, a probe at its centre of mass ----------------------
U = 5e-5


def _rotor_model():
    return rotor_on_springs([{"rotor": "shaft", "amount": U}])


def _rotor_peak():
    """(N_c [rpm], AF) of ``|x| = U w^2 / |2k - m w^2 + 2 i w c|`` by hand: the maximum on a fine
    grid and API 684's AF = N_c / (N2 - N1) between its half-power points."""
    w = np.linspace(200.0, 600.0, 400001)
    x = rotor_displacement(w, U)
    k = int(np.argmax(x))
    band = w[x >= x[k] / math.sqrt(2)]
    return w[k] * 30 / np.pi, w[k] / (band[-1] - band[0])


def _required(af, above):
    """API 684 required separation margin [%], written out (docs/standards.md)."""
    if af < 2.5:
        return 0.0
    margin = 17.0 * (1 - 1 / (af - 1.5))
    return min(26.0, 10.0 + margin) if above else min(16.0, margin)


def _write(tmp_path, model, name="model.toml"):
    import tomli_w

    path = tmp_path / name
    path.write_bytes(tomli_w.dumps(model.to_dict()).encode())
    return path


def _peaks_table(out: str) -> pd.DataFrame:
    """The peaks table ``unbalance`` prints on stdout after the response's (whitespace-separated)."""
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if "amplification_factor" in line)
    return pd.read_csv(io.StringIO("\n".join(lines[start:])), sep=r"\s+")


@pytest.mark.parametrize("band", ["2000:2500", "2000:3000", "3000:4000", "4000:5000"])
def test_unbalance_operating_range_margin_is_measured_from_the_nearer_end(tmp_path, capsys, band):
    """The rotor's one critical speed (about 3490 rpm, AF about 13.7) above, inside and below the
    range: the margin from HI, 0, and from LO, against the API 684 rule for its position."""
    path = _write(tmp_path, _rotor_model())
    assert main(["unbalance", str(path), "--speeds", "100:6000:5901", "--operating-range", band,
                 "--out", str(tmp_path / "u.csv")]) == 0
    table = _peaks_table(capsys.readouterr().out)
    assert len(table) == 1
    row = table.iloc[0]
    nc, af = _rotor_peak()
    low, high = (float(v) for v in band.split(":"))
    assert row.speed_rpm == pytest.approx(nc, abs=0.5) and row.amplification_factor == pytest.approx(af, rel=2e-3)
    if nc < low:
        margin, required = 100 * (low - nc) / low, _required(af, above=False)
    elif nc > high:
        margin, required = 100 * (nc - high) / high, _required(af, above=True)
    else:                      # inside: margin 0 against the larger (above) requirement
        margin, required = 0.0, _required(af, above=True)
    assert row.separation_margin_pct == pytest.approx(margin, abs=0.03)    # the sweep's 1 rpm
    assert row.required_margin_pct == pytest.approx(required, abs=0.02)
    assert abs(margin - required) > 0.5                    # the verdict is not a matter of round-off
    assert row.verdict == ("pass" if margin >= required else "fail")


def test_operating_speed_is_the_range_of_one_speed(tmp_path, capsys):
    path = _write(tmp_path, _rotor_model())
    base = ["unbalance", str(path), "--speeds", "100:6000:5901", "--out", str(tmp_path / "u.csv")]
    assert main(base + ["--operating-speed", "3000"]) == 0
    one = _peaks_table(capsys.readouterr().out)
    assert main(base + ["--operating-range", "3000:3000"]) == 0
    assert one.equals(_peaks_table(capsys.readouterr().out))
    nc, _ = _rotor_peak()
    assert one.separation_margin_pct[0] == pytest.approx(100 * (nc - 3000) / 3000, abs=0.03)
    assert main(base + ["--operating-speed", "3000", "--operating-range", "2000:3000"]) == 2
    err = capsys.readouterr().err
    assert "--operating-speed 3000" in err and "--operating-range" in err and len(err.strip().splitlines()) == 1


def test_python_api_takes_the_range_too():
    """``UnbalanceResult.separation_margins((low, high))``: the same rule from Python."""
    model = _rotor_model()
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(100.0, 6000.0, 5901)))
    nc, af = _rotor_peak()
    table = result.separation_margins(rdm.rpm(np.array([4000.0, 5000.0])))
    assert table.separation_margin_pct[0] == pytest.approx(100 * (4000 - nc) / 4000, abs=0.03)
    assert table.verdict[0] == "fail" and 100 * (4000 - nc) / 4000 < _required(af, above=False)


# -- a casing on mounts: its mount resonance below the operating range ---------------------------
U_CASING, CZ_CASING = 5e-4, 400.0


def _casing_model():
    """The translating casing (tests/casing_on_mounts.py), resonance ~955 rpm."""
    return casing_model(U_CASING, cz=CZ_CASING)


def _casing_velocity_rms(w):
    return w * casing_displacement(w, U_CASING, cz=CZ_CASING) / math.sqrt(2)


#: ISO 20816-3 group 2, rigid support: A/B, B/C, C/D [m/s RMS] (Annex A, Table A.2)
GROUP2_RIGID = (1.4e-3, 2.8e-3, 4.5e-3)


def _zone(v):
    return "ABCD"[int(np.searchsorted(GROUP2_RIGID, v, side="left"))]


def test_iso_zones_judge_the_operating_range_not_the_run_up(tmp_path):
    """Zone D at the mount resonance (~955 rpm) crossed in the run-up, zone A over 2400-3000 rpm
    (closed form): the operating range passes, 0 to the MCS (no range: today's rule) fails."""
    speeds_rpm = np.linspace(200.0, 3000.0, 141)
    v = _casing_velocity_rms(speeds_rpm * np.pi / 30)
    inside = (speeds_rpm >= 2400.0) & (speeds_rpm <= 3000.0)
    assert _zone(v.max()) == "D" and _zone(v[inside].max()) == "A"      # the case the rule is about
    path = _write(tmp_path, _casing_model())
    base = ["unbalance", str(path), "--speeds", "200:3000:141", "--mcs", "3000", "--iso-group", "2",
            "--iso-support", "rigid", "--out", str(tmp_path / "u.csv"), "--quiet"]
    assert main(base + ["--operating-range", "2400:3000", "--checks", str(tmp_path / "range.csv")]) == 0
    assert main(base + ["--checks", str(tmp_path / "all.csv")]) == 0
    ranged, whole = (pd.read_csv(tmp_path / f"{n}.csv").iloc[0] for n in ("range", "all"))
    assert ranged.value == pytest.approx(v[inside].max(), rel=1e-8) and ranged.zone == "A" and ranged.verdict == "pass"
    assert ranged.speed_rpm == pytest.approx(speeds_rpm[inside][np.argmax(v[inside])])
    assert whole.value == pytest.approx(v.max(), rel=1e-8) and whole.zone == "D" and whole.verdict == "fail"


@pytest.mark.parametrize("operating, verdict, words", [
    ((2400.0, 3000.0), "pass", "over the operating range 2400 to 3000 rpm"),
    (None, "fail", "from 0 to the MCS 3000 rpm"),
])
def test_report_iso_criterion_says_which_speeds_it_judged(operating, verdict, words):
    model = _casing_model()
    rng = None if operating is None else tuple(rdm.rpm(np.array(operating)))
    inputs = report_collect.ReportInputs("iso", rdm.rpm(3000.0), operating=rng, points=141, iso_group=2,
                                         iso_support="rigid")
    data = report_collect.ReportData(inputs, model, {}, ("iso",))
    report_collect._iso(data)
    (criterion,) = data.criteria
    speeds = inputs.speeds
    lo, hi = rng if rng is not None else (0.0, rdm.rpm(3000.0))
    judged = speeds[(speeds >= lo * (1 - 1e-12)) & (speeds <= hi * (1 + 1e-12))]
    assert criterion.verdict == verdict and words in criterion.why
    expected = _casing_velocity_rms(judged).max()
    assert data.results["checks"].to_dataframe().value[0] == pytest.approx(expected, rel=1e-8)
    assert _zone(expected) == ("A" if verdict == "pass" else "D")


# -- a rigid rotor's critical speed ratio --------------------------------------------------------

def test_rigid_rotor_critical_speed_ratio_is_not_evaluated(tmp_path):
    """A rigid rotor pinned at its bearings has no bending mode: no critical speed on rigid
    supports, nothing for the CSR to judge: 'not evaluated' with why, in the summary, the terminal
    line and the Level I section (no CSR of 0 in Region A, no chart)."""
    from rigid_two_forward import MCS, QA, write_model

    from rotordyn_modal.analysis.level1 import Station
    from rotordyn_modal.cli.report import _terminal_line
    from rotordyn_modal.report import render

    model = rdm.load_model(write_model(tmp_path))
    inputs = report_collect.ReportInputs("api617", MCS, level1={"stations": [Station("rotor", 0.0)], "qa": QA,
                                                                "gas_density": 20.0})
    data = report_collect.ReportData(inputs, model, {}, ("level1",))
    report_collect._level1(data)
    (csr,) = [c for c in data.criteria if c.name == "API 617 Level I: critical speed ratio"]
    assert csr.verdict == "not evaluated" and csr.value == "" and "no critical speed on rigid supports" in csr.why
    line = _terminal_line(csr)
    assert "pass" not in line and "not evaluated" in line and "(0" not in line
    html = render._level1(data, "si")
    assert "not evaluated" in html and "Critical speed ratio chart" not in html
    assert "CSR = 0 " not in html and "Region A" not in html
