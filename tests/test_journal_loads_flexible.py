"""Journal loads of rotors on three journal bearings (issue 29 section 1, docs/static.md).

A flexible shaft on three journals carries its weight as the continuous beam on rigid supports
at the journals (the statically indeterminate beam of the three-moment equation); a rigid rotor
keeps the split of a rigid beam on its light-load films. A journal whose share holds the shaft
down says so in one line.
"""

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import ModelWarning

G = 9.81
DENSITY, SPAN, DISK = 7850.0, 0.6, 20.0


def _flexible(diameter, shear="none"):
    """A 1.2 m steel shaft on journals at 0, 0.6 and 1.2 m, a 20 kg disk at 0.3 m."""
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G], "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": DENSITY, "young_modulus": 2.1e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shear": shear, "shaft": [{"length": 2 * SPAN, "outer_diameter": diameter, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": SPAN / 2, "mass": DISK, "polar_inertia": 0.1,
                               "diametral_inertia": 0.05}]}],
        "bearings": [{"name": f"j{i}", "rotor": "r", "type": "journal", "axial_position": z, "diameter": 0.05,
                      "length": length, "clearance": 5e-5, "viscosity": 0.02}
                     for i, (z, length) in enumerate(zip((0.0, SPAN, 2 * SPAN), (0.02, 0.03, 0.025)))]})


def _three_moment(diameter):
    """Reactions [N] (up) of a uniform beam on three supports, two equal spans L, under its own
    weight w per metre and a point load P at the middle of the first span. Three-moment equation:
    the middle support's moment is -w L^2 / 8 (weight) - 3 P L / 32 (point load); the end
    reactions follow from each span's moment balance."""
    w = DENSITY * np.pi * diameter**2 / 4 * G
    P = DISK * G
    weight = np.array([3 / 8, 10 / 8, 3 / 8]) * w * SPAN
    point = np.array([13 / 32, 22 / 32, -3 / 32]) * P
    return weight + point


def _signed_loads(model):
    """Each journal's model load [N], positive when it pushes the journal down (with gravity)."""
    return np.array([b.coefficients.journal.load * -np.sign(b.coefficients.journal.axes[0][2])
                     for b in model.bearings])


def test_flexible_shaft_on_three_journals_carries_the_continuous_beam_reactions():
    model = _flexible(0.05)
    np.testing.assert_allclose(_signed_loads(model), _three_moment(0.05), rtol=1e-9)


def test_continuous_beam_is_the_static_solution_on_films_much_stiffer_than_the_shaft():
    """rdm.static solves the shaft on its light-load films, springs k ~ speed turned by 90 degrees:
    as the films stiffen past the shaft its reactions tend to the continuous beam's. The turn puts
    the first-order (1 / speed) difference across the load (horizontal), so the vertical one falls
    as 1 / speed^2."""
    model = _flexible(0.05, shear="cowper")
    loads = _signed_loads(model)
    vertical, across = [], []
    for rpm in (30_000.0, 300_000.0):
        reactions = np.array([r.force for r in rdm.static(model, speed=rdm.rpm(rpm)).reactions
                              if r.kind == "bearing"])
        vertical.append(np.abs(reactions[:, 2] - loads).max())
        across.append(np.abs(reactions[:, 1]).max())
    weight = loads.sum()
    assert vertical[1] < 1e-6 * weight and across[1] < 1e-3 * weight
    assert 50.0 < vertical[0] / vertical[1] < 200.0
    assert 5.0 < across[0] / across[1] < 20.0


def test_a_journal_holding_a_thin_shaft_down_says_so_in_one_line():
    with pytest.warns(ModelWarning) as caught:
        model = _flexible(0.03)
    expected = _three_moment(0.03)
    assert expected[2] < 0
    np.testing.assert_allclose(_signed_loads(model), expected, rtol=1e-9)
    lines = [str(w.message) for w in caught if "[bearings.j2] load" in str(w.message)]
    assert len(lines) == 1 and "\n" not in lines[0]
    assert f"{expected[2]:.4g} N" in lines[0] and "holds the shaft down" in lines[0]
    assert not any("[bearings.j0]" in str(w.message) or "[bearings.j1]" in str(w.message) for w in caught)


def test_rigid_rotor_keeps_the_split_on_its_films_and_warns_of_a_hold_down():
    """A rigid rotor on three equal films at s = -0.05, 0.45, 0.95 m from its centre of mass:
    shares u + theta s with (Cramer) u = 1.1075 / 1.5, theta = -1.35 / 1.5: the third is negative."""
    mass = 50.0
    stations = np.array([-0.05, 0.45, 0.95])
    shares = 1.1075 / 1.5 - 1.35 / 1.5 * stations
    with pytest.warns(ModelWarning, match=r"\[bearings\.j2\] load: .*holds the shaft down"):
        model = rdm.Model.from_dict({
            "gravity": [0.0, 0.0, -G],
            "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                        "diametral_inertia": 2.0, "speed_ratio": 1.0}],
            "bearings": [{"name": f"j{i}", "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal",
                          "length": 0.02, "diameter": 0.05, "clearance": 5e-5, "viscosity": 0.02}
                         for i, s in enumerate(stations)]})
    np.testing.assert_allclose(_signed_loads(model), shares * mass * G, rtol=1e-12)
