"""The lowest modes' Campbell columns where two roots meet exactly at a sweep speed, and over coarse
steps where a root's value and its shape disagree (issue 27 sections 2 and 3).

``campbell(modes=N)`` keeps one column per root, NaN where the root is not among the lowest N
(tests/test_lowest_columns27q.py, 27r). The check of a doubtful step tracks more roots over it and
halves it where its pairing is unsure. On main:

- a coarse step where a root moved less than half its gap but its shape is plainly another root's
  at the other end was taken as sure by value: over 0 -> 321 rad/s b's forward tilt mode (60 ->
  100.15 rad/s, leaving the lowest 3) handed its column to a's backward tilt mode (150 -> 42.9);
- two roots equal at a sweep speed (a double root there, its shapes any basis of the eigenspace)
  were told apart by value only, so the column of one passed to the other at that speed.

The model, in closed form (as tests/test_lowest_columns27r.py, other tilt frequencies): two rigid
rotors on isotropic undamped bearings to the ground, bearings at +-L about each centre of mass.
Rotor b's axial mode C stands at 100 rad/s. Each tilt pair splits with speed: Id w**2 -+ Ip Omega w
- 2 k L**2 = 0. Rotor a's backward tilt mode (150 rad/s at rest, Ip = 1.5 Id) falls through C at
Omega_a = 83.3 rad/s; rotor b's forward tilt mode (60 rad/s at rest, Ip = 0.2 Id) rises through C
at exactly Omega_b = Id (100**2 - 60**2) / (Ip 100) = 320 rad/s, a speed of every grid below.
"""

from __future__ import annotations

import contextlib

import numpy as np
import pytest

import rotordyn_modal as rdm
import rotordyn_modal.analysis.campbell as campbell_module

L, M = 0.1, 10.0
K_A, K_B, K_AXIAL = 8e5, 1.25e6, 1e5
TILT_A, TILT_B = 150.0, 60.0                   # tilt frequencies at rest [rad/s]
ID_A, ID_B = 2 * K_A * L**2 / TILT_A**2, 2 * K_B * L**2 / TILT_B**2
IP_A, IP_B = 1.5 * ID_A, 0.2 * ID_B
OMEGA_A = ID_A * (TILT_A**2 - 100.0**2) / (IP_A * 100.0)        # a's backward mode at C: 83.3 rad/s
OMEGA_B = ID_B * (100.0**2 - TILT_B**2) / (IP_B * 100.0)        # b's forward mode at C: 320 rad/s
#: one root found twice (closed form and solve) [relative]
SAME = 1e-7


def _model():
    def rotor(name, x, ip, id_):
        return {"name": name, "mass": M, "center_of_mass": [x, 0.0, 0.0], "polar_inertia": ip,
                "diametral_inertia": id_, "speed_ratio": 1.0}

    def bearing(name, rotor, x, z, k, **more):
        return {"name": name, "rotor": rotor, "position": [x, 0.0, z], "stiffness": k, **more}

    return rdm.Model.from_dict({
        "name": "a crossing at a grid speed", "spin_axis": [0.0, 0.0, 1.0], "reference_rotor": "a",
        "rotors": [rotor("a", 0.0, IP_A, ID_A), rotor("b", 1.0, IP_B, ID_B)],
        "bearings": [bearing("a0", "a", 0.0, L, K_A), bearing("a1", "a", 0.0, -L, K_A),
                     bearing("b0", "b", 1.0, L, K_B, axial_stiffness=K_AXIAL), bearing("b1", "b", 1.0, -L, K_B)]})


def _tilt(omega, ip, id_, tilt, sign):
    """Forward (sign +1) or backward (-1) tilt frequency [rad/s] at speed ``omega`` [rad/s]."""
    return (sign * ip * omega + np.sqrt((ip * omega) ** 2 + 4 * id_ ** 2 * tilt ** 2)) / (2 * id_)


def _branches(omega):
    """Every root's frequency [rad/s] at speed ``omega``, by name (closed form)."""
    return {"C": 100.0 + 0 * omega,
            "Ba": _tilt(omega, IP_A, ID_A, TILT_A, -1), "Fa": _tilt(omega, IP_A, ID_A, TILT_A, 1),
            "Bb": _tilt(omega, IP_B, ID_B, TILT_B, -1), "Fb": _tilt(omega, IP_B, ID_B, TILT_B, 1),
            "cyl_a": np.sqrt(2 * K_A / M) + 0 * omega, "cyl_b": np.sqrt(2 * K_B / M) + 0 * omega}


def _named(speeds, values):
    """The closed-form roots (names) each column of ``values`` (S, c) can be wherever it is found;
    fails where a column holds two roots."""
    names = []
    for j in range(values.shape[1]):
        mine = None
        for omega, value in zip(speeds, values[:, j]):
            if not np.isfinite(value):
                continue
            assert abs(value.real) <= SAME * abs(value)
            here = {name for name, f in _branches(omega).items() if abs(f - value.imag) <= SAME * f}
            assert here, f"column {j + 1}: {value} at {omega} rad/s is no root"
            mine = here if mine is None else mine & here
            assert mine, f"column {j + 1} holds two roots (at {omega} rad/s: {sorted(here)})"
        names.append(mine)
    return names


def _lowest3(speeds):
    return rdm.campbell(_model(), np.asarray(speeds, dtype=float), modes=3, critical=False).eigenvalues


def test_the_model_is_its_closed_form():
    """Guard (passes on main too): the full route's roots are the closed form's, and b's forward
    tilt mode meets C exactly at 320 rad/s."""
    speeds = np.array([0.0, 160.0, 320.0, 640.0])
    values = rdm.campbell(_model(), speeds, critical=False).eigenvalues
    for omega, row in zip(speeds, values):
        roots = _branches(omega)
        expected = np.sort(list(roots.values()) + [roots["cyl_a"], roots["cyl_b"]])   # the cylindrical pairs: double
        np.testing.assert_allclose(np.sort(row.imag), expected, rtol=SAME)
    assert OMEGA_B == 320.0 and 80 < OMEGA_A < 90
    assert abs(_branches(320.0)["Fb"] - 100.0) <= 1e-12 * 100.0


@pytest.mark.parametrize("top", [321.0, 330.0])
def test_a_coarse_step_is_told_by_shape_where_value_misleads(top):
    """One step 0 -> top: b's forward tilt mode leaves the lowest 3 (above C), a's backward tilt mode
    enters them. Each column holds one root (main: b's forward mode's column went on as a's
    backward mode, which lies nearer by value)."""
    speeds = [0.0, top]
    values = _lowest3(speeds)
    names = _named(speeds, values)
    assert {"Ba"} in names and {"C"} in names, names
    backward_a = names.index({"Ba"})
    assert np.isnan(values[0, backward_a]) and np.isfinite(values[1, backward_a])


#: grids with 320 rad/s (the crossing) as a speed: (speeds, top)
CROSSING_GRIDS = [(2, 320.0), (3, 640.0), (4, 960.0), (4, 480.0), (5, 640.0), (17, 640.0), (26, 500.0)]


@pytest.mark.parametrize("count, top", CROSSING_GRIDS)
def test_roots_meeting_at_a_grid_speed_keep_their_columns(count, top):
    """Each column holds one closed-form root, on every grid with the crossing speed as one of its
    speeds, and C is one column, found wherever it is among the lowest 3 by the closed form
    (below Omega_a, and from Omega_b on, where b's forward mode rises above it). Main: on 0, 320,
    640 rad/s one column held b's forward mode at rest, then a's backward mode."""
    speeds = np.linspace(0.0, top, count)
    values = _lowest3(speeds)
    names = _named(speeds, values)
    holding = [j for j, n in enumerate(names) if "C" in n and "Fb" not in n]
    if not holding:                      # on 0 and 320 only: C and b's forward mode meet at the end
        holding = [j for j, n in enumerate(names) if "C" in n]
    assert len(holding) == 1, names
    below = np.sort(np.array([[f for name, f in _branches(s).items() if name != "C"] for s in speeds]), axis=1)
    among = below[:, 1] > 100.0 * (1 + SAME)            # fewer than two roots clearly below C
    assert np.all(np.isfinite(values[among, holding[0]])), (names, values[:, holding[0]])
    assert np.all(np.isnan(values[(speeds > OMEGA_A) & (speeds < OMEGA_B), holding[0]]))


def test_the_same_columns_on_a_coarse_and_a_fine_grid():
    """The 5-speed grid (0, 160, ..., 640 rad/s) gives the columns of the 33-speed grid at its
    speeds: same numbers, same values, NaN at the same places."""
    fine_speeds = np.linspace(0.0, 640.0, 33)
    fine = _lowest3(fine_speeds)
    assert [len(n) for n in _named(fine_speeds, fine)] == [1] * fine.shape[1]
    speeds = np.linspace(0.0, 640.0, 5)
    values = _lowest3(speeds)
    assert values.shape == (5, fine.shape[1])
    np.testing.assert_allclose(values, fine[np.searchsorted(fine_speeds, speeds)], rtol=SAME, equal_nan=True)


def test_the_check_of_doubtful_steps_shows_its_progress(monkeypatch):
    """With ``progress``, the check's halvings have a line of their own (the package's
    ``_progress.phase``), naming the steps checked and each level's halvings (main: none)."""
    shown = []

    class Bar:
        def set_description(self, text, refresh=True):
            shown.append(text)

    @contextlib.contextmanager
    def phase(enabled, description, delay=None, file=None):
        shown.append(description)
        yield Bar() if enabled else None

    monkeypatch.setattr(campbell_module, "phase", phase)
    rdm.campbell(_model(), np.array([0.0, 321.0]), modes=3, critical=False, progress=True)
    assert any("checking 1 doubtful step" in text for text in shown), shown
    assert any("halving" in text and "level 1 of at most 6" in text for text in shown), shown


# A root that comes back with another shape. Rotor c (m = 10 kg, Id = 0.2, Ip = 0.3 kg m**2) sits
# on two bearings of 4e4 N/m (y) and 6e4 N/m (z) at +0.05 and -0.3 m from its centre of mass:
# translation and tilt couple, and the bearings' anisotropy makes its modes planar at rest and
# elliptical with speed. Its mode X (81.6 rad/s at rest, 89.0 at 500 rad/s) so changes its shape:
# its weighted MAC between 40 and 340 rad/s is 0.51. Rotors a and b as above, with tilt frequencies
# 120 and 45 rad/s at rest: a's backward mode falls below X near 57 rad/s, b's forward mode rises
# above it near 335 rad/s, so of the lowest 4, X leaves and comes back. The truth: every root of the
# full route (dense eigen-solutions) at 1,001 speeds, X followed by hand from the top speed down
# (the root nearest its value extrapolated from the two speeds above).
TILT_A_X, TILT_B_X = 120.0, 45.0
IP_C, ID_C, Z_C, K_C = 0.3, 0.2, (0.05, -0.3), [[4e4, 0.0], [0.0, 6e4]]


def _with_x():
    def rotor(name, x, ip, id_):
        return {"name": name, "mass": M, "center_of_mass": [x, 0.0, 0.0], "polar_inertia": ip,
                "diametral_inertia": id_, "speed_ratio": 1.0}

    def bearing(name, rotor, x, z, k):
        return {"name": name, "rotor": rotor, "position": [x, 0.0, z], "stiffness": k}

    id_a, id_b = 2 * K_A * L**2 / TILT_A_X**2, 2 * K_B * L**2 / TILT_B_X**2
    return rdm.Model.from_dict({
        "name": "a root coming back with another shape", "spin_axis": [0.0, 0.0, 1.0], "reference_rotor": "a",
        "rotors": [rotor("a", 0.0, 1.5 * id_a, id_a), rotor("b", 1.0, 0.2 * id_b, id_b), rotor("c", 2.0, IP_C, ID_C)],
        "bearings": [bearing("a0", "a", 0.0, L, K_A), bearing("a1", "a", 0.0, -L, K_A),
                     bearing("b0", "b", 1.0, L, K_B), bearing("b1", "b", 1.0, -L, K_B),
                     bearing("c0", "c", 2.0, Z_C[0], K_C), bearing("c1", "c", 2.0, Z_C[1], K_C)]})


def _followed_by_hand(speeds, every):
    """The root of ``every`` (S, n) followed from the top speed's root nearest 89 rad/s down to
    speeds[0]: at each speed the root nearest the value extrapolated from the two speeds above."""
    path = np.empty(len(speeds), complex)
    path[-1] = every[-1][np.argmin(np.abs(every[-1].imag - 89.0))]
    path[-2] = every[-2][np.argmin(np.abs(every[-2] - path[-1]))]
    for k in range(len(speeds) - 3, -1, -1):
        guess = path[k + 1] + (path[k + 1] - path[k + 2]) * (speeds[k] - speeds[k + 1]) / (speeds[k + 1] - speeds[k + 2])
        path[k] = every[k][np.argmin(np.abs(every[k] - guess))]
    return path


def test_a_root_that_comes_back_with_another_shape_gets_its_column_back():
    """X is one column of the lowest 4 over 0..500 rad/s at 26 speeds, equal to the hand-followed
    root wherever it is found, and found exactly where it is among the lowest 4 (main: a second
    column from 340 rad/s on, its MAC with its last shape below 0.8: X was two modes)."""
    model = _with_x()
    fine = np.linspace(0.0, 500.0, 1001)
    every = rdm.campbell(model, fine, critical=False).eigenvalues
    x = _followed_by_hand(fine, np.where(every.imag > 0, every, np.nan))
    assert abs(x[0].imag - 81.64) < 0.01 and abs(x[-1].imag - 88.97) < 0.01
    speeds = np.linspace(0.0, 500.0, 26)
    values = rdm.campbell(model, speeds, modes=4, critical=False).eigenvalues
    truth = x[np.searchsorted(fine, speeds)]
    holding = [j for j in range(values.shape[1]) if np.isfinite(values[-1, j])
               and abs(values[-1, j] - truth[-1]) <= SAME * abs(truth[-1])]
    assert len(holding) == 1
    column = values[:, holding[0]]
    found = np.isfinite(column)
    assert found[0] and found[-1] and not found.all()
    np.testing.assert_allclose(column[found], truth[found], rtol=SAME)
    lowest = np.sort(np.where(every.imag > 0, every.imag, np.inf), axis=1)[np.searchsorted(fine, speeds), 3]
    np.testing.assert_array_equal(found, truth.imag <= lowest * (1 + SAME))   # found where among the lowest 4


def test_roots_leaving_at_the_top_while_modes_are_born_below_keep_apart():
    """Guard (passes on main): the ROSS compressor's lowest 12 from 420 to 1150 rad/s. Four roots
    leave the check's roots at the top (near 11,800 rad/s) while four modes are born below 600 rad/s
    (overdamped roots becoming modes); tracking pairs each leaving root with one born, however
    short the step. On the 2 end speeds alone each column holds one root of the 74-speed sweep (a
    first version of this branch gave two columns a root at 11,800 and one at 1,800 rad/s)."""
    import warnings
    from pathlib import Path

    from rotordyn_modal.io.ross_file import read_ross_rotor

    path = Path(__file__).parent / "data" / "ross" / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
        fine_speeds = np.linspace(420.0, 1150.0, 74)
        fine = rdm.campbell(model, fine_speeds, modes=12, critical=False).eigenvalues
        values = rdm.campbell(model, fine_speeds[[0, -1]], modes=12, critical=False).eigenvalues
    assert values.shape[1] == fine.shape[1] == 16
    for j in range(values.shape[1]):
        held = [set(np.flatnonzero(np.abs(fine[k] - values[s, j]) <= 1e-6 * abs(values[s, j])).tolist())
                for s, k in ((0, 0), (1, -1)) if np.isfinite(values[s, j])]
        assert held and set.intersection(*held), f"column {j + 1} holds {held}"
