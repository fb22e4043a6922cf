"""Journal loads of a flexible rotor on three journals, one on a pedestal (issue 29 section 1,
docs/static.md "Journal-bearing loads of the model").

A journal on a pedestal is an elastic support of the pedestal's stiffness k, loaded by the
journal's reaction R and by the pedestal's own weight m_p g: it settles by (R + m_p g) / k, and
the continuous beam's reactions depend on it (the three-moment equation with a support
settlement). The closed forms here are the flexibility method with the elastic support's reaction
as the redundant.
"""

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import ModelWarning

G = 9.81
DENSITY, YOUNG, SPAN, DISK, DIAMETER = 7850.0, 2.1e11, 0.6, 20.0, 0.05
PEDESTAL = 6.0   # kg


def _model(pedestal_stiffness=None, pedestal_mass=PEDESTAL, on="j1"):
    """A 1.2 m steel shaft (Euler-Bernoulli) on journals at 0, 0.6 and 1.2 m, a 20 kg disk at 0.3 m,
    journal ``on`` on a pedestal of ``pedestal_stiffness`` [N/m] (a number or a 2-list along y, z)."""
    bearings = []
    for i, (z, length) in enumerate(zip((0.0, SPAN, 2 * SPAN), (0.02, 0.03, 0.025))):
        bearing = {"name": f"j{i}", "rotor": "r", "type": "journal", "axial_position": z, "diameter": 0.05,
                   "length": length, "clearance": 5e-5, "viscosity": 0.02}
        if f"j{i}" == on and pedestal_stiffness is not None:
            bearing.update(pedestal_mass=pedestal_mass, pedestal_stiffness=pedestal_stiffness)
        bearings.append(bearing)
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G], "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": DENSITY, "young_modulus": YOUNG, "poisson_ratio": 0.3}],
        "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shear": "none", "shaft": [{"length": 2 * SPAN, "outer_diameter": DIAMETER,
                                                "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": SPAN / 2, "mass": DISK, "polar_inertia": 0.1,
                               "diametral_inertia": 0.05}]}],
        "bearings": bearings})


def _signed_loads(model):
    """Each journal's model load [N], positive when it pushes the journal down (with gravity)."""
    return np.array([b.coefficients.journal.load * -np.sign(b.coefficients.journal.axes[0][2])
                     for b in model.bearings])


def _loads(expected, *args, **kwargs):
    """The signed loads of ``_model(*args, **kwargs)``, whose journals with a negative ``expected`` load
    must each say in one warning that they hold the shaft down."""
    if not (np.asarray(expected) < 0).any():
        return _signed_loads(_model(*args, **kwargs))
    with pytest.warns(ModelWarning, match="holds the shaft down") as caught:
        loads = _signed_loads(_model(*args, **kwargs))
    assert len([w for w in caught if "holds the shaft down" in str(w.message)]) == (np.asarray(expected) < 0).sum()
    return loads


def _elastic_middle(k, pedestal_mass=PEDESTAL):
    """Reactions [N] (up) of the beam over two spans L on rigid end supports and a middle support
    of stiffness k [N/m] carrying a pedestal of ``pedestal_mass`` [kg], under the beam's weight w
    per metre and the disk's P at L / 2.

    Without the middle support the beam of length l = 2 L sags at mid-span by
    5 w l^4 / (384 E I) + P a (l - x)(2 l x - x^2 - a^2) / (6 l E I) (a = L / 2, x = L); the middle
    reaction R lifts it by R l^3 / (48 E I), and the support settles by (R + m_p g) / k."""
    inertia = np.pi * DIAMETER**4 / 64
    w = DENSITY * np.pi * DIAMETER**2 / 4 * G
    P = DISK * G
    l, a, x = 2 * SPAN, SPAN / 2, SPAN
    sag = (5 * w * l**4 / 384 + P * a * (l - x) * (2 * l * x - x**2 - a**2) / (6 * l)) / (YOUNG * inertia)
    middle = (sag - pedestal_mass * G / k) / (l**3 / (48 * YOUNG * inertia) + 1 / k)
    # the end reactions from the moment balance about each end: the weight w l at l / 2, P at a
    right = (w * l * l / 2 + P * a - middle * SPAN) / l
    left = w * l + P - middle - right
    return np.array([left, middle, right])


@pytest.mark.parametrize("k", [3e5, 1.79e6, 2e7, 1e12])
def test_a_journal_on_a_pedestal_is_an_elastic_support_of_the_continuous_beam(k):
    """Pedestal stiffness from softer to far stiffer than the shaft (48 E I / l^3 = 1.79e6 N/m)."""
    np.testing.assert_allclose(_loads(_elastic_middle(k), k), _elastic_middle(k), rtol=1e-9)


def test_the_elastic_middle_support_tends_to_the_rigid_and_to_the_two_support_results():
    """The closed form's limits: k -> infinity the three-moment result on rigid supports
    (3/8, 10/8, 3/8 w L; 13/32, 22/32, -3/32 P), k -> 0 the beam on its two ends."""
    w, P, L = DENSITY * np.pi * DIAMETER**2 / 4 * G, DISK * G, SPAN
    rigid = np.array([3 / 8, 10 / 8, 3 / 8]) * w * L + np.array([13 / 32, 22 / 32, -3 / 32]) * P
    two = np.array([w * L + 3 / 4 * P, 0.0, w * L + P / 4])
    np.testing.assert_allclose(_elastic_middle(1e18), rigid, rtol=1e-9)
    np.testing.assert_allclose(_elastic_middle(1e-6, pedestal_mass=0.0), two, atol=1e-8 * (2 * w * L + P))
    np.testing.assert_allclose(_loads(rigid, 1e15), rigid, rtol=1e-6)
    np.testing.assert_allclose(_loads(two, 1.0, pedestal_mass=1e-9), two, atol=1e-3)


def test_the_pedestal_stiffness_along_the_load_counts_and_its_weight_settles_it():
    """A pedestal soft across the load (y) and stiff along it (z), or the other way round: only the
    vertical stiffness counts. A pedestal ten times heavier settles by 54 m_p g / k more, which
    the middle journal's load feels (not its weight: that sits on the pedestal's springs)."""
    np.testing.assert_allclose(_loads(_elastic_middle(2e6), [1e3, 2e6]), _elastic_middle(2e6), rtol=1e-9)
    np.testing.assert_allclose(_loads(_elastic_middle(2e6), [4e6, 2e6]), _elastic_middle(2e6), rtol=1e-9)
    np.testing.assert_allclose(_loads(_elastic_middle(4e6), [2e6, 4e6]), _elastic_middle(4e6), rtol=1e-9)
    heavy = _elastic_middle(2e6, pedestal_mass=10 * PEDESTAL)
    assert heavy[1] < _elastic_middle(2e6)[1] - 10.0
    np.testing.assert_allclose(_loads(heavy, 2e6, pedestal_mass=10 * PEDESTAL), heavy, rtol=1e-9)


def test_an_end_journal_on_a_pedestal():
    """The pedestal under the end journal j2: the flexibility method with that end's reaction as
    the redundant, the beam on j0 and j1 with an overhang of L beyond j1: the tip sags under
    w and P by (w L^4 / 4 - P L^3 / 16) / E I."""
    k, pedestal = 5e5, PEDESTAL * G
    inertia = np.pi * DIAMETER**4 / 64
    EI = YOUNG * inertia
    w, P, L = DENSITY * np.pi * DIAMETER**2 / 4 * G, DISK * G, SPAN
    # tip deflection (down) of a beam on supports at 0 and L with an overhang L, by the unit-load
    # method: the span's rotation at j1 carried to the tip plus the overhang's cantilever sag
    # (Roark: the overhang's own load w a^3 (4 L + 3 a) / 24, the span's load tilting j1 back by
    # w L^3 / 24 and P L^2 / 16, times the overhang a = L)
    tip = (7 * w * L**4 / 24 - w * L**4 / 24 - P * L**3 / 16) / EI
    # a unit upward tip force lifts the tip by a^2 (L + a) / (3 E I); the support settles by (R + m_p g) / k
    end = (tip - pedestal / k) / (L**2 * 2 * L / (3 * EI) + 1 / k)
    middle = (w * 2 * L * L + P * L / 2 - end * 2 * L) / L
    first = w * 2 * L + P - middle - end
    np.testing.assert_allclose(_loads([first, middle, end], k, on="j2"), [first, middle, end], rtol=1e-9)


def test_static_tends_to_the_model_loads_with_the_pedestal_as_the_films_stiffen():
    """rdm.static solves the shaft on its light-load films in series with the pedestal's springs:
    as the films stiffen past shaft and pedestal (speed up) its vertical reactions tend to the
    loads of the beam on the pedestal, the difference falling as 1 / speed^2. (On main the model
    ignored the pedestal: 113.7 / 248.3 / 15.6 N, 27 N off the 131 N that rdm.static tends to.)"""
    model = _model(2e6)
    loads = _signed_loads(model)
    differences = []
    for rpm in (30_000.0, 300_000.0):
        reactions = np.array([r.force for r in rdm.static(model, speed=rdm.rpm(rpm)).reactions
                              if r.kind == "bearing"])
        differences.append(np.abs(reactions[:, 2] - loads).max())
    assert differences[1] < 1e-5 * loads.sum()
    assert 50.0 < differences[0] / differences[1] < 200.0


def _rigid(pedestals=("j1",), loads=None):
    """A 50 kg rigid rotor on three journals at -0.4, 0.1 and 0.4 m from its centre of mass."""
    bearings = []
    for i, s in enumerate((-0.4, 0.1, 0.4)):
        bearing = {"name": f"j{i}", "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal", "length": 0.02,
                   "diameter": 0.05, "clearance": 5e-5, "viscosity": 0.02}
        if f"j{i}" in pedestals:
            bearing.update(pedestal_mass=PEDESTAL, pedestal_stiffness=2e6)
        if loads is not None:
            bearing["load"] = loads[i]
        bearings.append(bearing)
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G],
        "rotors": [{"name": "r", "mass": 50.0, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                    "diametral_inertia": 2.0, "speed_ratio": 1.0}],
        "bearings": bearings})


def test_a_rigid_rotor_with_a_journal_on_a_pedestal_gets_its_split_at_each_speed():
    """The films in series with the pedestal: the split moves with speed (the middle journal
    carries 31 N at 1,000 rpm, 46 N at 3,000 rpm in rdm.static, which stands such journals on the
    model's loaded films: tests/test_static_loaded_films.py; on their light-load films it gave 127
    and 80 N), so the model solves it at each speed on the nonlinear films
    (tests/test_journal_loads_over_speed.py) instead of keeping the films' split with a warning,
    as it did before: no warning now."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        model = _rigid()
    middle = []
    for rpm in (1000.0, 3000.0):
        reactions = [r.force for r in rdm.static(model, speed=rdm.rpm(rpm)).reactions if r.kind == "bearing"]
        middle.append(np.linalg.norm(reactions[1]))
    assert abs(middle[0] - middle[1]) > 0.1 * max(middle)
    loads = model.bearings[1].coefficients.journal.load_over_speed(rdm.rpm(np.array([1000.0, 10000.0])))
    assert abs(np.linalg.norm(loads[0]) - np.linalg.norm(loads[1])) > 0.2 * np.linalg.norm(loads[1])


@pytest.mark.parametrize("pedestals, loads", [((), None), (("j1",), [180.0, 150.0, 160.0])])
def test_no_such_line_without_a_pedestal_or_with_every_load_given(pedestals, loads):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        _rigid(pedestals, loads)
