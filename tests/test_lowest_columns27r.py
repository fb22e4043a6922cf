"""The lowest modes' Campbell columns follow roots through exits and coarse steps (issue 27 sections
2 and 3, issue 28 section 4).

``campbell(modes=N)`` keeps one column per root, NaN where the root is not among the lowest N
(tests/test_lowest_columns27q.py). Here: a root that leaves the lowest N and comes back later gets
its former column back (on main it got a new one: one mode, two numbers and two curves), and the
columns do not depend on the speed step (on main a coarse step handed a falling root the column
of a rising one).

The model, in closed form: two rigid rotors on isotropic undamped bearings to the ground, each
with its bearings at +-L = 0.1 m about its centre of mass (translation and tilt uncoupled). Rotor
b's axial mode (k_axial = 1e5 N/m, m = 10 kg) stands at C = 100 rad/s at every speed. Each tilt
pair splits with speed: Id w**2 -+ Ip Omega w - 2 k L**2 = 0 (forward -, backward +). Rotor a's
backward tilt mode falls from 147 rad/s through C at Omega_a = 77.4 rad/s; rotor b's forward tilt
mode rises from 62 rad/s through C at Omega_b = 307.8 rad/s. So, of the lowest 3 modes, C leaves
at Omega_a (two roots below it) and comes back at Omega_b (b's forward mode rises above it).
The cylindrical pairs (400 and 500 rad/s) and a's forward tilt mode stay above.
"""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main

L, M = 0.1, 10.0
K_A, K_B, K_AXIAL = 8e5, 1.25e6, 1e5
TILT_A, TILT_B = 147.0, 62.0                   # tilt frequencies at rest [rad/s]
ID_A, ID_B = 2 * K_A * L**2 / TILT_A**2, 2 * K_B * L**2 / TILT_B**2
IP_A, IP_B = 1.5 * ID_A, 0.2 * ID_B
#: one root found twice (closed form and solve) [relative]
SAME = 1e-7


def _description():
    def rotor(name, x, ip, id_):
        return {"name": name, "mass": M, "center_of_mass": [x, 0.0, 0.0], "polar_inertia": ip,
                "diametral_inertia": id_, "speed_ratio": 1.0}

    def bearing(name, rotor, x, z, k, **more):
        return {"name": name, "rotor": rotor, "position": [x, 0.0, z], "stiffness": k, **more}

    return {"name": "a root leaving and coming back", "spin_axis": [0.0, 0.0, 1.0], "reference_rotor": "a",
            "rotors": [rotor("a", 0.0, IP_A, ID_A), rotor("b", 1.0, IP_B, ID_B)],
            "bearings": [bearing("a0", "a", 0.0, L, K_A), bearing("a1", "a", 0.0, -L, K_A),
                         bearing("b0", "b", 1.0, L, K_B, axial_stiffness=K_AXIAL), bearing("b1", "b", 1.0, -L, K_B)]}


def _tilt(omega, ip, id_, tilt, sign):
    """Forward (sign +1) or backward (-1) tilt frequency [rad/s] at speed ``omega`` [rad/s]."""
    return (sign * ip * omega + np.sqrt((ip * omega) ** 2 + 4 * id_ ** 2 * tilt ** 2)) / (2 * id_)


def _branches(omega):
    """Every root's frequency [rad/s] at speed ``omega``, by name (closed form)."""
    return {"C": 100.0 + 0 * omega,
            "Ba": _tilt(omega, IP_A, ID_A, TILT_A, -1), "Fa": _tilt(omega, IP_A, ID_A, TILT_A, 1),
            "Bb": _tilt(omega, IP_B, ID_B, TILT_B, -1), "Fb": _tilt(omega, IP_B, ID_B, TILT_B, 1),
            "cyl_a": np.sqrt(2 * K_A / M) + 0 * omega, "cyl_b": np.sqrt(2 * K_B / M) + 0 * omega}


OMEGA_A = ID_A * (TILT_A**2 - 100.0**2) / (IP_A * 100.0)        # a's backward mode at C
OMEGA_B = ID_B * (100.0**2 - TILT_B**2) / (IP_B * 100.0)        # b's forward mode at C


def _named(speeds, values):
    """The closed-form root (name) each column of ``values`` (S, c) holds wherever it is found;
    fails where a column holds two roots."""
    names = []
    for j in range(values.shape[1]):
        mine = None
        for omega, value in zip(speeds, values[:, j]):
            if not np.isfinite(value):
                continue
            assert abs(value.real) <= SAME * abs(value)
            here = {name: f for name, f in _branches(omega).items() if abs(f - value.imag) <= SAME * f}
            assert here, f"column {j + 1}: {value} at {omega} rad/s is no root"
            mine = set(here) if mine is None else mine & set(here)
            assert mine, f"column {j + 1} holds two roots (at {omega} rad/s: {sorted(here)})"
        names.append(mine)
    return names


def _lowest3(speeds):
    return rdm.campbell(rdm.Model.from_dict(_description()), speeds, modes=3, critical=False).eigenvalues


def test_the_model_is_its_closed_form():
    """Guard (passes on main too): the full route's roots are the closed form's."""
    speeds = np.linspace(0.0, 500.0, 11)
    values = rdm.campbell(rdm.Model.from_dict(_description()), speeds, critical=False).eigenvalues
    for omega, row in zip(speeds, values):
        roots = _branches(omega)
        expected = np.sort(list(roots.values()) + [roots["cyl_a"], roots["cyl_b"]])   # the cylindrical pairs: double
        np.testing.assert_allclose(np.sort(row.imag), expected, rtol=SAME)
    assert 70 < OMEGA_A < 80 and 300 < OMEGA_B < 310


def test_a_root_that_comes_back_gets_its_column_back():
    """The axial root C is in one column, NaN exactly while two roots lie below it (main: a second
    column from Omega_b on; mode 3 and mode 5 were the same mode)."""
    speeds = np.linspace(0.0, 500.0, 26)
    values = _lowest3(speeds)
    names = _named(speeds, values)
    holding = [j for j, n in enumerate(names) if n == {"C"}]
    assert len(holding) == 1, names
    gone = (speeds > OMEGA_A) & (speeds < OMEGA_B)
    np.testing.assert_array_equal(np.isnan(values[:, holding[0]]), gone)
    assert values.shape[1] == 4                # Bb, Fb, C and Ba (entering at Omega_a)


#: grids over 0..500 rad/s: every coarse one a subset of the finest
GRIDS = (3, 6, 11, 26, 101)


def test_coarse_and_fine_sweeps_give_the_same_columns():
    """Each column holds one closed-form root, and the same one (same column number, same values,
    NaN at the same speeds) on every grid, down to three speeds (0, 250, 500 rad/s). Main: on three
    speeds b's forward mode's column went to a's falling backward mode at 250 rad/s."""
    fine_speeds = np.linspace(0.0, 500.0, GRIDS[-1])
    fine = _lowest3(fine_speeds)
    fine_names = _named(fine_speeds, fine)
    assert [len(n) for n in fine_names] == [1] * fine.shape[1], fine_names
    for count in GRIDS[:-1]:
        speeds = np.linspace(0.0, 500.0, count)
        values = _lowest3(speeds)
        names = _named(speeds, values)
        assert values.shape == (count, fine.shape[1]), (count, names)
        for mine, theirs in zip(names, fine_names):
            assert theirs <= mine, (count, names, fine_names)
        common = fine[np.searchsorted(fine_speeds, speeds)]
        np.testing.assert_allclose(values, common, rtol=SAME, equal_nan=True)


@pytest.fixture
def path(tmp_path):
    import tomli_w

    path = tmp_path / "comes_back.toml"
    path.write_bytes(tomli_w.dumps(_description()).encode())
    return path


def _csv(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    return pd.read_csv(io.StringIO(out))


def test_the_round_trip_to_modes_holds(path, capsys):
    """``critical-speeds --lowest 3``: the three closed-form 1X crossings (b's backward and forward
    modes, a's backward mode, which entered the lowest 3), each row's mode_at_speed the mode
    ``modes --speed`` lists on the line; ``campbell --lowest 3``: C is one mode all along, and
    each row's mode_at_speed is the one ``modes`` lists with its frequency."""
    table = _csv(["critical-speeds", path, "--speeds", "0:4800:49", "--lowest", "3", "--out", "-"], capsys)
    table = table[table.source == "a"]                   # b's 1X line is a's (speed ratio 1)
    expected = {"Bb": TILT_B / np.sqrt(1 + IP_B / ID_B), "Fb": TILT_B / np.sqrt(1 - IP_B / ID_B),
                "Ba": TILT_A / np.sqrt(1 + IP_A / ID_A)}
    np.testing.assert_allclose(np.sort(table.speed_rpm * np.pi / 30), sorted(expected.values()), rtol=1e-6)
    campbell = _csv(["campbell", path, "--speeds", "0:4800:49", "--lowest", "3", "--out", "-"], capsys)
    on_c = campbell[np.isclose(campbell.frequency_hz, 100 / (2 * np.pi), rtol=SAME)]
    assert on_c["mode"].nunique() == 1
    for _, row in table.iterrows():
        modes = _csv(["modes", path, "--speed", f"{row.speed_rpm:.10g}", "--out", "-"], capsys).set_index("mode")
        assert modes.loc[int(row.mode_at_speed), "frequency_hz"] == pytest.approx(row.speed_rpm / 60, rel=1e-6)
    for speed, rows in campbell.groupby("speed_rpm"):
        if speed % 1200:
            continue
        modes = _csv(["modes", path, "--speed", f"{speed:.10g}", "--out", "-"], capsys).set_index("mode")
        np.testing.assert_allclose(modes.loc[rows.mode_at_speed.astype(int), "frequency_hz"].to_numpy(),
                                   rows.frequency_hz.to_numpy(), rtol=1e-9)


def test_an_overhung_wheels_columns_do_not_depend_on_the_step():
    """tests/test_lowest_columns27q.py's overhung wheel (52 coordinates, Newton's route; two roots
    near 391 Hz exchange the 4th and 5th places): on 7 and 11 speeds over 0..60,000 rpm each column
    of the lowest 4 holds one root of the full route's sweep at 61 speeds (every root, tracked on
    steps of 1,000 rpm), told by value at the common speeds. Main: columns 2 and 3 each held two."""
    from test_lowest_columns27q import _overhung

    model = _overhung()
    fine_speeds = rdm.rpm(np.linspace(0.0, 60000.0, 61))
    full = rdm.campbell(model, fine_speeds, critical=False).eigenvalues
    for count in (7, 11):
        speeds = rdm.rpm(np.linspace(0.0, 60000.0, count))
        values = rdm.campbell(model, speeds, modes=4, critical=False).eigenvalues
        at = full[np.searchsorted(fine_speeds, speeds - 1e-9 * speeds[-1])]
        for j in range(values.shape[1]):
            found = np.flatnonzero(np.isfinite(values[:, j]))
            held = [set(np.flatnonzero(np.abs(at[k] - values[k, j]) <= SAME * abs(values[k, j])).tolist())
                    for k in found]
            assert held and set.intersection(*held), f"{count} speeds: column {j + 1} holds {held}"
