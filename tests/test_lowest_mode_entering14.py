"""The lowest modes' route reports only crossings as critical speeds (redteam14, issue 27 §1,
issue 28 §4).

Its columns are the lowest roots that are modes at each speed. Where a root becomes a mode (its
damping ratio falls below ``OVERDAMPED_LIMIT``) it enters them and a tracked column passes from
one root to another across the order lines; on main that step was refined and reported as a
critical speed far off its order line (160 % here; 91 % on a three-rotor machine), warned of as
a jump that "a finer speed grid resolves", which no grid does.

The model: a rigid rotor (m = 10 kg, Ip = 0.2, Id = 0.1 kg m^2) on two bearings at +-0.1 m of
k = 1e5 N/m, c = 50 N s/m and tilt damping 40 N m s/rad each: its tilt modes are critically
damped at rest and become modes once it spins; its cylindrical pair does not depend on the speed
(no gyroscopic coupling at the centre of mass). Truth from outside the code: the cylindrical
motion ``m x'' + 2c x' + 2k x = 0`` has ``Im lam = sqrt(2k/m - (c/m)^2)``, and its 1X crossing is
at that speed [rad/s]; a critical speed's natural frequency lies on its order line (the
definition).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main

M, K, C = 10.0, 1e5, 50.0
#: the cylindrical pair's damped natural frequency [rad/s] = its 1X critical speed
CYLINDRICAL = math.sqrt(2 * K / M - (C / M) ** 2)
SPEEDS = rdm.rpm(np.linspace(0.0, 3000.0, 31))


def _description():
    return {
        "name": "rigid rotor whose tilt modes are overdamped at rest", "spin_axis": [0.0, 0.0, 1.0],
        "rotors": [{"name": "r", "mass": M, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.2, "diametral_inertia": 0.1}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "position": [0.0, 0.0, z], "stiffness": K,
                      "damping": C, "moment_damping": 40.0} for i, z in enumerate((0.1, -0.1))]}


def _campbell(modes):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.campbell(rdm.Model.from_dict(_description()), SPEEDS, modes=modes)
    return result, [str(w.message) for w in caught]


def _assert_crossings_of_the_cylindrical_pair(critical):
    speeds = np.asarray(critical.speeds)
    assert len(speeds) >= 1
    np.testing.assert_allclose(speeds, CYLINDRICAL, rtol=1e-9)
    # on the 1X line: frequency [Hz] = speed / 2 pi
    np.testing.assert_allclose(np.asarray(critical.frequencies_hz), speeds / (2 * np.pi), rtol=1e-9)


def test_a_root_becoming_a_mode_is_no_critical_speed():
    """Main: the two lowest modes gave a second critical speed at 518.5 rpm with the cylindrical
    pair's 22.49 Hz, 160 % off the 1X line (8.6 Hz there)."""
    result, _ = _campbell(2)
    _assert_crossings_of_the_cylindrical_pair(result.critical)


def test_no_row_is_left_out_where_the_columns_follow_roots():
    """redteam14 left the row out with one warning; lowcol27q: each column is one root (the tilt
    mode entering has a column of its own), so no column passes to it and nothing is warned of."""
    _, warned = _campbell(2)
    assert warned == []


def test_every_root_and_three_modes_keep_both_crossings():
    """Guard (passes on main too): where no root enters the columns, both roots of the pair cross
    1X at the closed form, in the full route and the lowest three modes'."""
    for modes in (None, 3):
        result, warned = _campbell(modes)
        _assert_crossings_of_the_cylindrical_pair(result.critical)
        assert len(result.critical.speeds) == 2 and warned == []


def test_critical_speeds_command_lists_crossings_only(tmp_path, capsys):
    import tomli_w

    path = tmp_path / "tilt.toml"
    path.write_bytes(tomli_w.dumps(_description()).encode())
    out = tmp_path / "cs.csv"
    assert main(["critical-speeds", str(path), "--speeds", "0:3000:31", "--lowest", "2", "--out", str(out)]) == 0
    import pandas as pd

    table = pd.read_csv(out)
    np.testing.assert_allclose(table.speed_rpm, CYLINDRICAL * 30 / np.pi, rtol=1e-9)
    assert "left out: not crossings" not in capsys.readouterr().err      # lowcol27q: columns follow roots
