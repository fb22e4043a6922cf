"""The lowest modes' Campbell diagram draws tracked roots, not ranks (issue 27 section 3, issue 28
section 4; redteam14's finding 4).

``campbell(modes=N)`` solves the N lowest modes of each speed. Where a root enters them (a root
becoming a mode as its damping ratio falls below ``OVERDAMPED_LIMIT``, or one passing below the
last of them) another leaves; on main tracking, which matches N roots to N, handed the leaving
root's column to the entering one, and its curve jumped between the two (a three-rotor machine:
"mode 9" from 283 Hz down to 17.7 Hz, drawn as a vertical line). Now each column is one root,
NaN where that root is not among the lowest N (as the ``max_frequency`` route's).

The model (redteam14's): a rigid rotor (m = 10 kg, Ip = 0.2, Id = 0.1 kg m^2) on two bearings at
+-0.1 m of k = 1e5 N/m, c = 50 N s/m and tilt damping 40 N m s/rad each: its tilt modes are
critically damped at rest and become modes once it spins, the lowest of them below the
cylindrical pair (22.49 Hz, a double root at every speed). Truth from outside the lowest route:
the full route's tracked roots (every root of the state matrix at every speed), whose own curves
do not jump (checked here), and the definition of the lowest N modes.
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli.main import main

SPEEDS = rdm.rpm(np.linspace(0.0, 3000.0, 31))
#: one root found twice (the full route's and the lowest route's solves) [relative]
SAME = 1e-7


def _description():
    return {
        "name": "rigid rotor whose tilt modes are overdamped at rest", "spin_axis": [0.0, 0.0, 1.0],
        "rotors": [{"name": "r", "mass": 10.0, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.2, "diametral_inertia": 0.1}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "position": [0.0, 0.0, z], "stiffness": 1e5,
                      "damping": 50.0, "moment_damping": 40.0} for i, z in enumerate((0.1, -0.1))]}


@pytest.fixture(scope="module")
def full():
    """The full route's tracked roots (N, n) over SPEEDS."""
    return rdm.campbell(rdm.Model.from_dict(_description()), SPEEDS).eigenvalues


def _full_modes_of(full, k, value):
    """The full route's tracked modes (columns) whose root at speed k is ``value``."""
    return set(np.flatnonzero(np.abs(full[k] - value) <= SAME * abs(value)).tolist())


def test_the_full_routes_modes_do_not_jump(full):
    """Guard (passes on main too): every root is tracked over the sweep by the full route, its
    frequency at most 32 Hz per step where it is a mode (the forward tilt mode rising at 1.07 X),
    the cylindrical pair's constant."""
    frequencies = np.where(rdm.analysis.modal.is_oscillating(full), full.imag / (2 * np.pi), np.nan)
    steps = np.abs(np.diff(frequencies, axis=0))
    assert np.nanmax(steps) < 33.0
    cylindrical = np.isclose(frequencies, 22.4938, rtol=1e-4)
    assert cylindrical.sum(axis=1).min() == 2


def _overhung():
    """A steel shaft (0.6 m, 40 mm, 12 elements: 52 coordinates, the route of Newton's iteration
    on the full pencil) on bearings at 0 and 0.4 m, an 8 kg wheel (Ip = 0.6 kg m^2) overhung at its
    end: its gyroscopic split makes two roots near 391 Hz exchange the 4th and 5th places at
    speed."""
    return rdm.Model.from_dict({
        "name": "overhung wheel", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "a", "start": [0.0, 0.0, 0.0], "element_length": 0.05,
                    "shaft": [{"length": 0.6, "outer_diameter": 0.04, "material": "steel"}],
                    "disks": [{"name": "wheel", "axial_position": 0.6, "mass": 8.0, "polar_inertia": 0.6,
                               "diametral_inertia": 0.3}]}],
        "bearings": [{"name": f"b{i}", "rotor": "a", "axial_position": z, "stiffness": 2e7, "damping": 300.0}
                     for i, z in enumerate((0.0, 0.4))]})


OVERHUNG_SPEEDS = rdm.rpm(np.linspace(0.0, 60000.0, 31))


def _assert_columns_are_roots(values, full):
    """Each column of ``values`` (N, c) holds, at neighbouring speeds where it is found, one
    tracked root of the full route ``full`` (N, n) (told by value)."""
    for m in range(values.shape[1]):
        for k in range(len(values) - 1):
            a, b = values[k, m], values[k + 1, m]
            if not (np.isfinite(a) and np.isfinite(b)):
                continue
            assert _full_modes_of(full, k, a) & _full_modes_of(full, k + 1, b), \
                f"column {m + 1} passes from {a} to {b} between speeds {k} and {k + 1}"


def test_a_root_passing_the_last_place_has_a_column_of_its_own():
    """Main: the lowest 4 of the overhung wheel kept 4 columns, one of which passed between the
    two roots near 391 Hz where they exchange the 4th and 5th places (a crossing of two modes,
    not one of the full route's modes). Now 5 columns, each one root of the full route."""
    model = _overhung()
    full = rdm.campbell(model, OVERHUNG_SPEEDS, critical=False).eigenvalues
    values = rdm.campbell(model, OVERHUNG_SPEEDS, modes=4, critical=False).eigenvalues
    _assert_columns_are_roots(values, full)
    assert (np.isfinite(values).sum(axis=1) == 4).all()


@pytest.mark.parametrize("modes", [2, 3])
def test_each_column_is_one_root_of_the_full_route(full, modes):
    """Main: with 2 modes, column 2 went from the cylindrical pair's 22.49 Hz at rest to the
    backward tilt mode's 0.99 Hz at 100 rad/s (not one of the full route's modes)."""
    result = rdm.campbell(rdm.Model.from_dict(_description()), SPEEDS, modes=modes, critical=False)
    _assert_columns_are_roots(result.eigenvalues, full)


@pytest.mark.parametrize("modes", [2, 3])
def test_each_speed_holds_its_lowest_modes_once(full, modes):
    """Guard (passes on main too): at each speed the modes (finite, oscillating entries) are the
    ``modes`` lowest oscillating roots of the full route, each in one column."""
    result = rdm.campbell(rdm.Model.from_dict(_description()), SPEEDS, modes=modes, critical=False)
    values = np.where(result.oscillatory, result.eigenvalues, np.nan)      # (at rest, 3: a real root too)
    oscillating = rdm.analysis.modal.is_oscillating(full)
    for k in range(len(SPEEDS)):
        mine = np.sort(values[k][np.isfinite(values[k])].imag)
        lowest = np.sort(full[k][oscillating[k]].imag)[:modes]
        np.testing.assert_allclose(mine, lowest, rtol=SAME)


def test_critical_speeds_are_the_crossings_without_a_warning():
    """Main: the 518.5 rpm row (160 % off the 1X line) was refined and left out with a warning
    that a tracked mode passes to a root entering the lowest modes; now no column passes, and the
    only crossing is the cylindrical pair's at its closed form sqrt(2k/m - (c/m)^2), in the
    column that holds it."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.campbell(rdm.Model.from_dict(_description()), SPEEDS, modes=2)
    assert [str(w.message) for w in caught] == []
    cylindrical = np.sqrt(2e5 / 10.0 - 5.0 ** 2)
    np.testing.assert_allclose(result.critical.speeds, [cylindrical], rtol=1e-9)
    column = result.eigenvalues[:, result.critical.mode[0] - 1]
    np.testing.assert_allclose(column.imag[np.isfinite(column)], cylindrical, rtol=1e-9)


def test_the_command_lines_modes_follow_roots(tmp_path, full):
    """``campbell --lowest 2``: each CSV mode's rows at neighbouring speeds are one root of the full
    route (main: mode 2 from 22.49 Hz at 0 rpm to 0.99 Hz at 100 rpm)."""
    import tomli_w

    path = tmp_path / "tilt.toml"
    path.write_bytes(tomli_w.dumps(_description()).encode())
    out = tmp_path / "c.csv"
    assert main(["campbell", str(path), "--speeds", "0:3000:31", "--lowest", "2", "--out", str(out)]) == 0
    table = pd.read_csv(out, comment="#")
    k_of = {round(rpm): k for k, rpm in enumerate(np.linspace(0.0, 3000.0, 31))}
    assert sorted(table.groupby("speed_rpm").size().unique()) == [2]
    for mode, rows in table.groupby("mode"):
        ks = [k_of[round(s)] for s in rows.speed_rpm]
        lam = rows.real_part.to_numpy() + 2j * np.pi * rows.frequency_hz.to_numpy()
        for i in range(len(ks) - 1):
            if ks[i + 1] != ks[i] + 1:
                continue
            assert _full_modes_of(full, ks[i], lam[i]) & _full_modes_of(full, ks[i + 1], lam[i + 1]), \
                f"mode {mode} passes from {lam[i]} to {lam[i + 1]} at {rows.speed_rpm.iloc[i]} rpm"
