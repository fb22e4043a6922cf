"""``unbalance --min-operating-speed`` (the bottom of the probe amplitudes of the clearance
check's scale factor ``Scc = Avl / Amax``, API 617) defaults to the low end of the operating
range where one is given (``--operating-range LO:HI``, or ``--operating-speed S``, the range
``S:S``), as ``report`` takes it; else to ``--min-speed``.

The scale factor against the hand solve of ``tests/test_clearance.py``: a rigid rotor on two
isotropic bearings whirls in a forward circle under its unbalance; the probe at ``s = 0.5 m``
reads ``2 |z + s psi|`` pk-pk; ``Amax`` is its largest over the sweep's speeds from the minimum
operating speed to the MCS, ``Avl = 25.4 um sqrt(12000 / N)``.
"""

from __future__ import annotations

import numpy as np
import pytest
import tomli_w

from rotordyn_modal.cli.main import main
from test_clearance import _by_hand, _rigid_data, _scale

AMOUNT = 1e-3                                    # kg m: large enough that Scc stays below the cap of 6
SWEEP = (300.0, 8400.0, 28)                      # rpm: 300, 600, ..., 8400
MCS = 6000.0


def _model(tmp_path):
    data = _rigid_data()
    data["unbalances"] = [{"rotor": "rotor", "amount": AMOUNT}]
    path = tmp_path / "seals.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    return path


def _scale_by_hand(low_rpm):
    """Scc with Amax over the swept speeds from ``low_rpm`` to the MCS (the unbalance at the
    centre of mass: a force ``U w^2``, no moment)."""
    rpm = np.linspace(*SWEEP)
    w = rpm * np.pi / 30
    z, psi = _by_hand(w, AMOUNT * w ** 2, 0.0).T
    return _scale(z, psi, (rpm >= low_rpm - 1e-9) & (rpm <= MCS + 1e-9), MCS, cap=6.0)


def _scale_factors(tmp_path, capsys, *options, speeds=None):
    """The printed clearance table's scale_factor of each station (by name)."""
    capsys.readouterr()
    sweep = speeds or f"{SWEEP[0]:g}:{SWEEP[1]:g}:{SWEEP[2]}"
    assert main(["unbalance", str(_model(tmp_path)), "--speeds", sweep, "--mcs", f"{MCS:g}", *options,
                 "--out", str(tmp_path / "u.csv")]) == 0
    out, err = capsys.readouterr()
    assert "clearance check (API 617/684" in err                 # the heading; the table on stdout
    shown = out.splitlines()
    header = [line.split() for line in shown if line.split()[:1] == ["clearance"]]
    rows = [line.split() for line in shown if line.split()[:1] in (["inboard-seal"], ["overhung-seal"])]
    assert len(header) == 1 and header[0][9] == "scale_factor" and len(rows) == 2
    return {row[0]: float(row[9]) for row in rows}


def test_the_operating_range_sets_the_minimum_operating_speed(tmp_path, capsys):
    """--operating-range 4800:6000: Amax over 4800-6000 rpm (the resonance at 3600 rpm left out),
    the scale factor the hand solve's; without a range Amax runs from 0 and includes the peak."""
    from_range, from_zero = _scale_by_hand(4800.0), _scale_by_hand(0.0)
    assert from_range / from_zero > 2 and from_range < 6          # the two cases are told apart, uncapped
    shown = _scale_factors(tmp_path, capsys, "--operating-range", "4800:6000")
    assert shown == {name: pytest.approx(from_range, rel=1e-5) for name in shown}
    assert _scale_factors(tmp_path, capsys) == {name: pytest.approx(from_zero, rel=1e-5) for name in shown}


def test_an_operating_speed_and_a_negative_range_say_the_same(tmp_path, capsys):
    """--operating-speed 4800 is the range 4800:4800 (its low end 4800); a negative sweep's range
    -6000:-4800 has the low end 4800 in magnitude."""
    expected = _scale_by_hand(4800.0)
    shown = _scale_factors(tmp_path, capsys, "--operating-speed", "4800")
    assert shown == {name: pytest.approx(expected, rel=1e-5) for name in shown}
    shown = _scale_factors(tmp_path, capsys, "--operating-range", "-6000:-4800", speeds="-8400:-300:28")
    assert shown == {name: pytest.approx(expected, rel=1e-5) for name in shown}


def test_an_explicit_minimum_operating_speed_wins(tmp_path, capsys):
    shown = _scale_factors(tmp_path, capsys, "--operating-range", "4800:6000", "--min-operating-speed", "0")
    assert shown == {name: pytest.approx(_scale_by_hand(0.0), rel=1e-5) for name in shown}


def test_a_range_above_the_mcs_is_refused_in_one_line(tmp_path, capsys):
    """The low end above --mcs cannot be the bottom of the speeds up to the MCS: refused before
    anything is written."""
    out = tmp_path / "u.csv"
    assert main(["unbalance", str(_model(tmp_path)), "--speeds", "300:8400:28", "--mcs", "6000",
                 "--operating-range", "6500:7000", "--out", str(out)]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "--operating-range 6500:7000" in error[0] and "at most --mcs 6000" in error[0]
    assert not out.exists()
