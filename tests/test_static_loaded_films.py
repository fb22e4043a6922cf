"""rdm.static on the model's loaded films: a rigid rotor on three or more journals, some on
pedestals, whose journal loads the model solves at each speed (docs/static.md, "Journal
bearings"), stands in `static` on the same nonlinear films at those loads, so that its reactions
are the analyses' loads and its journal displacements the films' offsets at them.

Closed forms: the short (Ocvirk) bearing's eccentricity and attitude angle at a load, and the
rigid rotor on three identical journals carrying a third each; independent builds: a root-finder
on the compatibility and balance equations (scipy's hybr, continued in speed), with and without
an extra force on the rotor."""

import warnings

import numpy as np
import pytest
import scipy.optimize

import rotordyn_modal as rdm
from rotordyn_modal.elements.journal_bearing import short_journal_bearing
from rotordyn_modal.errors import ModelWarning

from rotordyn_modal.elements._bearing_validation import journal_load_shares
from test_journal_loads_over_speed import FILM, _offset
from test_journal_loads_pedestals import _rigid

G = 9.81
MASS = 50.0
STATIONS = np.array([-0.4, 0.1, 0.4])          # the journals of _rigid() from the centre of mass
CLEARANCE, DIAMETER, LENGTH, VISCOSITY = FILM["clearance"], FILM["diameter"], 0.02, FILM["viscosity"]
MIDDLE = [None, (np.eye(2) * 2e6, 6.0), None]     # _rigid()'s pedestal: 6 kg on 2e6 N/m under j1


def _quiet(build):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return build()


def _bearing_forces(result):
    """The force each journal puts on its bearing, (y, z) [N] (minus the reaction on the rotor)."""
    return -np.array([r.force[1:] for r in result.reactions if r.kind == "bearing"])


def _journal_offsets(result, model):
    """Each journal's motion (y, z) [m] relative to what carries it (its pedestal or the ground)."""
    out = []
    for b in model.bearings:
        motion = result.rotor_motion("r", b.position)[1:3]
        if b.pedestal is not None:
            motion = motion - result.pedestal_motion(b.name)[1:3]
        out.append(motion)
    return np.array(out)


@pytest.mark.parametrize("rpm", [1000.0, -3000.0])
def test_static_carries_the_loads_an_independent_root_finder_gives(rpm):
    """The 50 kg rotor on journals at -0.4, 0.1, 0.4 m, the middle one on a 6 kg, 2e6 N/m pedestal
    (at 1,000 rpm the outer films run at eccentricity 0.62): the journals' loads in `static` are
    the root-finder's, and each journal sits at its film's offset under that load (on its
    light-load films `static` put 127 N on the middle journal at 1,000 rpm, the root-finder 31 N)."""
    model = _rigid()
    result = rdm.static(model, speed=rdm.rpm(rpm))
    expected = _rigid_root(rdm.rpm(rpm), MIDDLE)
    np.testing.assert_allclose(_bearing_forces(result), expected, rtol=0, atol=1e-9 * MASS * G)
    offsets = [_offset(load, rdm.rpm(rpm), LENGTH) for load in expected]
    np.testing.assert_allclose(_journal_offsets(result, model), offsets, rtol=0, atol=1e-9 * CLEARANCE)
    for reaction, load in zip([r for r in result.reactions if r.kind == "bearing"], expected):
        film = short_journal_bearing([rdm.rpm(rpm)], length=LENGTH, load=np.linalg.norm(load), **FILM)
        assert reaction.eccentricity == pytest.approx(float(film.eccentricity[0]), rel=1e-9)


def _three_identical(a=2e-5, b=1e-5, pedestal_mass=5.0):
    """A 60 kg rigid rotor on three identical journals at s = -0.4, 0.1, 0.3 m from its centre of
    mass (sum s = 0), each on a pedestal of ``pedestal_mass`` whose stiffness settles it by
    ``a + b s`` under a third of the rotor's weight and its own: ``k = (W / 3 + m_p g) / (a + b s)``."""
    mass, stations = 60.0, np.array([-0.4, 0.1, 0.3])
    settle = a + b * stations
    stiffness = (mass * G / 3 + pedestal_mass * G) / settle
    bearings = [{"name": f"j{i}", "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal", "length": LENGTH,
                 "diameter": DIAMETER, "clearance": CLEARANCE, "viscosity": VISCOSITY,
                 "pedestal_mass": pedestal_mass, "pedestal_stiffness": float(k)}
                for i, (s, k) in enumerate(zip(stations, stiffness))]
    model = rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G],
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                    "diametral_inertia": 2.0, "speed_ratio": 1.0}],
        "bearings": bearings})
    return model, mass, settle


@pytest.mark.parametrize("eps", [0.2, 0.5, 0.8])
def test_three_identical_journals_carry_a_third_each_at_the_short_bearings_offset(eps):
    """Equal loads W / 3 satisfy balance (sum s = 0) and compatibility (equal films, the pedestals'
    settlements linear in s: the rotor tilts by b): the statically indeterminate solution in
    closed form. The speed is the one at which the short bearing carries W / 3 at eccentricity
    ``eps`` (Ocvirk: W = mu Omega D L^3 / (8 c^2) eps sqrt(pi^2 + (16 - pi^2) eps^2) / (1 - eps^2)^2),
    where it sits at ``c eps`` with attitude angle atan(pi sqrt(1 - eps^2) / (4 eps)), turned from
    the load (down) towards e x down = +y, the spin axis e = +x. The pedestals settle by a + b s."""
    model, mass, settle = _three_identical()
    load = mass * G / 3
    speed = load * 8 * CLEARANCE**2 * (1 - eps**2)**2 / (
        VISCOSITY * DIAMETER * LENGTH**3 * eps * np.sqrt(np.pi**2 + (16 - np.pi**2) * eps**2))
    result = rdm.static(model, speed=speed)
    np.testing.assert_allclose(_bearing_forces(result), np.tile([0.0, -load], (3, 1)), rtol=0, atol=1e-10 * load)
    phi = np.arctan(np.pi * np.sqrt(1 - eps**2) / (4 * eps))
    offset = CLEARANCE * eps * np.array([np.sin(phi), -np.cos(phi)])        # cos phi (down) + sin phi (+y)
    np.testing.assert_allclose(_journal_offsets(result, model), np.tile(offset, (3, 1)), rtol=0,
                               atol=1e-10 * CLEARANCE)
    pedestals = np.array([result.pedestal_motion(b.name)[1:3] for b in model.bearings])
    np.testing.assert_allclose(pedestals, np.outer(settle, [0.0, -1.0]), rtol=0, atol=1e-10 * settle.max())
    for reaction in (r for r in result.reactions if r.kind == "bearing"):
        assert reaction.eccentricity == pytest.approx(eps, rel=1e-9)


def test_very_stiff_pedestals_give_the_pedestal_free_films_loads():
    """Every journal on a pedestal of 1e20 N/m (a settlement 1e-12 of the films'): the loads of the
    rotor on its nonlinear films alone, the root-finder's without pedestals, to round-off."""
    data = _rigid(pedestals=("j0", "j1", "j2")).to_dict()
    for bearing in data["bearings"]:
        bearing["pedestal_stiffness"] = 1e20
    model = _quiet(lambda: rdm.Model.from_dict(data))
    for rpm in (1000.0,):
        result = _quiet(lambda: rdm.static(model, speed=rdm.rpm(rpm)))
        expected = _rigid_root(rdm.rpm(rpm), [None] * 3)
        np.testing.assert_allclose(_bearing_forces(result), expected, rtol=0, atol=1e-9 * MASS * G)


def _rigid_root(speed, pedestals, force=(0.0, 0.0), at=0.0):
    """The loads (3, 2) (y, z) [N] of the 50 kg rotor of ``_rigid`` on its films by scipy's
    root-finder on the compatibility and balance equations, with a force (y, z) [N] on the rotor
    at ``at`` [m] from its centre of mass besides its weight; continued from 10,000 rpm (light
    load, the films' split) down to ``speed``, the force grown from 0 on the way. ``pedestals``:
    None or (k (2, 2) [N/m], m_p [kg]) per journal."""
    weight = MASS * G * np.array([0.0, -1.0])
    state = np.concatenate([np.outer(journal_load_shares([1.0] * 3, STATIONS), weight).ravel(), np.zeros(4)])
    steps = np.geomspace(np.sign(speed) * max(abs(speed), rdm.rpm(10000.0)), speed, 5)
    for part, step in zip(np.linspace(0.2, 1.0, len(steps)), steps):
        extra = part * np.asarray(force)

        def residual(z):
            loads, u, theta = z[:6].reshape(3, 2), z[6:8], z[8:]
            rows = []
            for i in range(3):
                gap = _offset(loads[i], step, LENGTH) - u - STATIONS[i] * theta
                if pedestals[i] is not None:
                    k, m = pedestals[i]
                    gap = gap + np.linalg.solve(k, loads[i] + m * G * np.array([0.0, -1.0]))
                rows.append(gap / CLEARANCE)
            rows.append((loads.sum(0) - weight - extra) / (MASS * G))
            rows.append((STATIONS @ loads - at * extra) / (MASS * G))
            return np.concatenate(rows)

        solution = scipy.optimize.root(residual, state, method="hybr", options={"xtol": 1e-14})
        assert np.max(np.abs(residual(solution.x))) < 1e-11
        state = solution.x
    return state[:6].reshape(3, 2)


@pytest.mark.parametrize("force", [[200.0, 0.0], [-300.0, 300.0]], ids=["sideways", "up-and-across"])
def test_a_force_on_the_rotor_moves_the_loads_as_the_nonlinear_films_do(force):
    """A force beside the weight (a gear's or a belt's, here given at 0.25 m) is carried on the
    nonlinear films too: `static` iterates the loaded films to the root-finder's equilibrium."""
    speed = rdm.rpm(1000.0)
    result = rdm.static(_rigid(), speed=speed, forces=[("r", [0.25, 0.0, 0.0], [0.0, *force])])
    np.testing.assert_allclose(_bearing_forces(result), _rigid_root(speed, MIDDLE, force, 0.25), rtol=0,
                               atol=1e-9 * MASS * G)


# -- a flexible rotor on three journals, the middle one on a pedestal -----------------------------
from test_journal_loads_pedestals import DENSITY, DISK, SPAN, YOUNG, _model  # noqa: E402

SHAFT = 0.05                                    # the shaft's diameter [m]
LENGTHS = [0.02, 0.03, 0.025]


def _flexible_root(speed, pedestal=(2e6, 6.0)):
    """The loads (3, 2) (y, z) [N] of the 1.2 m Euler-Bernoulli shaft of ``_model`` on its three
    films, the middle one on a pedestal ``(k [N/m], m_p [kg])`` (None: none), by scipy's
    root-finder continued from 100,000 rpm down to ``speed``. The shaft held at its end journals
    sags at the middle one by 5 w l^4 / (384 E I) + P a (l - x)(2 l x - x^2 - a^2) / (6 l E I)
    under its weight w per metre and the disk's P at a = L / 2 (x = L, l = 2 L), and bends there
    by l^3 / (48 E I) per newton; the journals then move by u + z theta (z from the shaft's start)
    plus that bending, and the loads balance the weight and its moment about the start."""
    inertia = np.pi * SHAFT**4 / 64
    w, P = DENSITY * np.pi * SHAFT**2 / 4 * G, DISK * G
    l, a, x = 2 * SPAN, SPAN / 2, SPAN
    sag = (5 * w * l**4 / 384 + P * a * (l - x) * (2 * l * x - x**2 - a**2) / (6 * l)) / (YOUNG * inertia)
    bend = l**3 / (48 * YOUNG * inertia)
    z = np.array([0.0, SPAN, 2 * SPAN])
    down = np.array([0.0, -1.0])
    weight, moment = (w * l + P) * down, (w * l * l / 2 + P * a) * down

    def residual(state, speed):
        loads, u, theta = state[:6].reshape(3, 2), state[6:8], state[8:]
        rows = []
        for i in range(3):
            gap = _offset(loads[i], speed, LENGTHS[i]) - u - z[i] * theta
            if i == 1:
                gap = gap + bend * loads[1] - sag * down
                if pedestal is not None:
                    gap = gap + (loads[1] + pedestal[1] * G * down) / pedestal[0]
            rows.append(gap / CLEARANCE)
        rows.append((loads.sum(0) - weight) / (w * l + P))
        rows.append((z @ loads - moment) / ((w * l + P) * SPAN))
        return np.concatenate(rows)

    state = np.concatenate([np.outer([0.4, 0.3, 0.3], weight).ravel(), np.zeros(4)])
    for step in np.geomspace(rdm.rpm(1e5), speed, 6):
        solution = scipy.optimize.root(residual, state, args=(step,), method="hybr", options={"xtol": 1e-14})
        assert np.max(np.abs(residual(solution.x, step))) < 1e-11
        state = solution.x
    return state[:6].reshape(3, 2), w * l + P


@pytest.mark.parametrize("rpm", [1000.0])
def test_a_flexible_rotor_on_a_pedestal_carries_its_films_loads_in_the_analyses_and_in_static(rpm):
    """The model's loads at each speed (the analyses' films) and `static`'s reactions are the
    shaft's on its nonlinear films and the pedestal's springs: 181.7 / 112.3 / 83.6 N at 1,000 rpm
    where the films taken rigid give 186.3 / 103.2 / 88.2 N at every speed (and `static` on
    light-load films 185.9 / 104.5 / 87.9 N at 3,000 rpm)."""
    model = _model(2e6)
    expected, weight = _flexible_root(rdm.rpm(rpm))
    solved = np.array([b.coefficients.journal.load_over_speed(np.array([rdm.rpm(rpm)]))[0][1:]
                       for b in model.bearings])
    np.testing.assert_allclose(solved, expected, rtol=0, atol=1e-9 * weight)
    result = rdm.static(model, speed=rdm.rpm(rpm))
    np.testing.assert_allclose(_bearing_forces(result), expected, rtol=0, atol=1e-9 * weight)
    offsets = [_offset(load, rdm.rpm(rpm), length) for load, length in zip(expected, LENGTHS)]
    np.testing.assert_allclose(_journal_offsets(result, model), offsets, rtol=0, atol=1e-8 * CLEARANCE)


def test_a_flexible_rotor_on_a_very_stiff_pedestal_carries_the_pedestal_free_films_loads():
    """A pedestal of 1e20 N/m: the shaft on its three films alone, to round-off."""
    model = _quiet(lambda: _model(1e20))
    for rpm in (3000.0,):
        expected, weight = _flexible_root(rdm.rpm(rpm), pedestal=None)
        result = _quiet(lambda: rdm.static(model, speed=rdm.rpm(rpm)))
        np.testing.assert_allclose(_bearing_forces(result), expected, rtol=0, atol=1e-9 * weight)
