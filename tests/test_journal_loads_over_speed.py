"""A rigid rotor on three or more journals, some on pedestals: the journals' static loads at each
speed (`elements.journal_bearing.rigid_rotor_journal_loads`, docs/theory.md §12, "A rigid rotor on
three or more journals") against an independent root-finder, the symmetric split, and the two
limits (films much stiffer than the pedestals: the beam on the pedestals' springs in closed form;
pedestals much stiffer than the films: the films' own split)."""

import warnings

import numpy as np
import pytest
import scipy.optimize

import rotordyn_modal as rdm
from rotordyn_modal.elements._bearing_validation import journal_load_shares
from rotordyn_modal.elements.bearings import evaluate
from rotordyn_modal.elements.journal_bearing import rigid_rotor_journal_loads, short_journal_bearing
from rotordyn_modal.errors import ModelWarning

from test_journal_loads_pedestals import _rigid  # the 50 kg rotor on three journals, the middle one on a pedestal

G = 9.81
E = np.array([1.0, 0.0, 0.0])              # spin axis
DOWN = np.array([0.0, 0.0, -1.0])
FILM = dict(diameter=0.05, clearance=5e-5, viscosity=0.02)


def _offset(load2, speed, length):
    """The journal's offset from its bearing (y, z) [m] under the load (y, z) [N], from the
    public short-bearing result: c eps (cos phi x + sin phi e x x)."""
    magnitude = np.linalg.norm(load2)
    film = short_journal_bearing([speed], length=length, load=magnitude, **FILM)
    x = load2 / magnitude
    y = np.array([-x[1], x[0]])                  # e x x in the (y, z) plane, e = +x
    phi = float(film.attitude_angle[0])
    return FILM["clearance"] * float(film.eccentricity[0]) * (np.cos(phi) * x + np.sin(phi) * y)


def _independent(speed, stations, lengths, mass, pedestals):
    """The loads (N, 2) in (y, z) by scipy's hybrid root-finder on the compatibility and balance
    equations, the films' offsets from short_journal_bearing's eccentricity and attitude angle,
    continued in speed from 10,000 rpm (light load) down to ``speed`` when it is lower.
    ``pedestals``: None or (k (2, 2), m_p) per journal."""
    n = len(stations)
    weight = mass * G * np.array([0.0, -1.0])
    start = np.concatenate([np.outer(journal_load_shares(np.asarray(lengths)**3, stations), weight).ravel(),
                            np.zeros(4)])
    top = np.sign(speed) * max(abs(speed), rdm.rpm(10000.0))
    for step in np.geomspace(top, speed, 12):
        start = _root(step, stations, lengths, mass, pedestals, start)
    return start[:2 * n].reshape(n, 2)


def _root(speed, stations, lengths, mass, pedestals, start):
    n = len(stations)
    weight = mass * G * np.array([0.0, -1.0])

    def residual(z):
        loads, u, theta = z[:2 * n].reshape(n, 2), z[2 * n:2 * n + 2], z[2 * n + 2:]
        rows = []
        for i in range(n):
            gap = _offset(loads[i], speed, lengths[i]) - u - stations[i] * theta
            if pedestals[i] is not None:
                k, m = pedestals[i]
                gap = gap + np.linalg.solve(k, loads[i] + m * G * np.array([0.0, -1.0]))
            rows.append(gap / FILM["clearance"])
        rows.append((loads.sum(0) - weight) / (mass * G))
        rows.append((stations @ loads) / (mass * G))
        return np.concatenate(rows)

    solution = scipy.optimize.root(residual, start, method="hybr", options={"xtol": 1e-14})
    assert np.max(np.abs(residual(solution.x))) < 1e-11     # (hybr may report xtol unreachable at round-off)
    return solution.x


def _solve(speeds, stations, lengths, mass, pedestals):
    stiffness = [None if p is None else np.pad(p[0], ((1, 0), (1, 0))) for p in pedestals]
    weights = [None if p is None else p[1] * G * DOWN for p in pedestals]
    loads = rigid_rotor_journal_loads(speeds, stations=stations, weight=mass * G * DOWN, spin_axis=E,
                                      length=lengths, diameter=[FILM["diameter"]] * len(stations),
                                      clearance=[FILM["clearance"]] * len(stations),
                                      viscosity=[FILM["viscosity"]] * len(stations),
                                      pedestal_stiffness=stiffness, pedestal_weight=weights)
    assert np.all(loads[..., 0] == 0.0)              # normal to the spin axis
    return loads[..., 1:]


def test_the_film_offsets_jacobian_is_the_inverse_of_its_stiffness():
    """Newton's matrix: a small change dF of the load moves the journal by K^-1 dF, K the film's
    stiffness at that load (finite differences of the offset from eccentricity and attitude)."""
    for speed, load in ((rdm.rpm(1000), 300.0), (rdm.rpm(-3000), 80.0), (rdm.rpm(20000), 5.0)):
        film = short_journal_bearing([speed], length=0.02, load=load, **FILM)
        compliance = np.linalg.inv(film.stiffness[0])            # frame: x along the load (here y), e x x (z)
        base = np.array([load, 0.0])
        for column in range(2):
            step = np.zeros(2)
            step[column] = 1e-5 * load
            slope = (_offset(base + step, speed, 0.02) - _offset(base - step, speed, 0.02)) / (2 * step[column])
            np.testing.assert_allclose(slope, compliance[:, column], rtol=1e-6, atol=1e-6 * np.abs(compliance).max())


@pytest.mark.parametrize("rpm", [30.0, 200.0, 1000.0, 3000.0, 10000.0, -3000.0])
def test_the_loads_equal_an_independent_root_finder(rpm):
    """Three journals of different lengths at -0.4, 0.1, 0.4 m; the middle one on an anisotropic
    6 kg pedestal, the last on an isotropic 4 kg one."""
    stations, lengths, mass = np.array([-0.4, 0.1, 0.4]), [0.02, 0.03, 0.025], 50.0
    pedestals = [None, (np.diag([2e6, 3e6]), 6.0), (np.eye(2) * 5e6, 4.0)]
    ours = _solve(rdm.rpm([rpm]), stations, lengths, mass, pedestals)[0]
    theirs = _independent(rdm.rpm(rpm), stations, lengths, mass, pedestals)
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-9 * mass * G)


def test_a_symmetric_rotor_on_three_equal_pedestals_carries_a_third_on_each():
    """Equal journals at -a, 0, a from the centre of mass, each on an equal pedestal: by symmetry
    the rotor only translates and each journal carries a third of the weight, straight down, at
    every speed, though the films' stiffness changes by decades."""
    speeds = rdm.rpm(np.array([800.0, 3000.0, 30000.0, -5000.0]))
    pedestal = (np.eye(2) * 3e6, 5.0)
    loads = _solve(speeds, np.array([-0.3, 0.0, 0.3]), [0.02] * 3, 60.0, [pedestal] * 3)
    np.testing.assert_allclose(loads, np.broadcast_to([0.0, -20.0 * G], loads.shape), rtol=0, atol=1e-12 * 60 * G)


def test_films_much_stiffer_than_the_pedestals_give_the_beam_on_the_pedestals_springs():
    """Every journal on an isotropic pedestal k_i carrying m_i g: with rigid films the rotor sits on
    the springs, k_i (u + s_i theta) = F_i + m_i g with sum F = W and sum s F = 0 (Cramer's rule,
    written out here); the films' stiffness grows with speed and the loads tend to it as 1 / speed."""
    stations, k, m, mass = np.array([-0.4, 0.1, 0.4]), np.array([2e6, 1e6, 4e6]), np.array([6.0, 3.0, 8.0]), 50.0
    w, weight = m * G, mass * G
    a = np.array([[k.sum(), k @ stations], [k @ stations, k @ stations**2]])
    u, theta = np.linalg.solve(a, [weight + w.sum(), stations @ w])
    beam = k * (u + theta * stations) - w                       # downward loads [N]
    pedestals = [(np.eye(2) * ki, mi) for ki, mi in zip(k, m)]
    errors = []
    for rpm in (1e4, 1e5, 1e6):
        loads = _solve(rdm.rpm([rpm]), stations, [0.02] * 3, mass, pedestals)[0]
        errors.append(np.max(np.abs(loads - np.outer(-beam, [0.0, 1.0]))) / weight)
    assert errors[2] < 2e-3
    assert 5.0 < errors[0] / errors[1] < 20.0 and 5.0 < errors[1] / errors[2] < 20.0


def test_pedestals_much_stiffer_than_the_films_give_the_films_split():
    """Pedestals of 1e14 N/m: the films' own split; at light load (high speed) the rigid rotor on
    springs proportional to mu D L**3 / c**3 (journal_load_shares, the model's split without
    pedestals)."""
    stations, lengths, mass = np.array([-0.35, 0.0, 0.3]), [0.02, 0.03, 0.025], 50.0
    pedestals = [(np.eye(2) * 1e14, 5.0)] * 3
    loads = _solve(rdm.rpm([1e6]), stations, lengths, mass, pedestals)[0]
    shares = journal_load_shares(np.asarray(lengths)**3, stations)
    np.testing.assert_allclose(np.linalg.norm(loads, axis=1), shares * mass * G, rtol=1e-5)


def test_the_model_gives_each_journal_the_coefficients_of_its_load_at_each_speed():
    """A 50 kg rigid rotor on journals at -0.4, 0.1, 0.4 m, the middle one on a 6 kg, 2e6 N/m
    pedestal: no warning; at each speed each journal's film coefficients are the short bearing's
    at the load (and its direction) the independent root-finder gives, and the middle journal's
    load moves with speed."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        model = _rigid()
    pedestals = [None, (np.eye(2) * 2e6, 6.0), None]
    middle = []
    for rpm in (1000.0, 3000.0, 10000.0):
        expected = _independent(rdm.rpm(rpm), np.array([-0.4, 0.1, 0.4]), [0.02] * 3, 50.0, pedestals)
        middle.append(np.linalg.norm(expected[1]))
        for bearing, load in zip(model.bearings, expected):
            stiffness, damping = evaluate(bearing.coefficients, [rdm.rpm(rpm)])
            film = short_journal_bearing([rdm.rpm(rpm)], length=0.02, load=np.linalg.norm(load), **FILM)
            x = load / np.linalg.norm(load)
            frame = np.array([x, [-x[1], x[0]]]).T                 # columns x, e x x in (y, z)
            for ours, local in ((stiffness, film.stiffness), (damping, film.damping)):
                np.testing.assert_allclose(ours[0][1:3, 1:3], frame @ local[0] @ frame.T,
                                           rtol=1e-7, atol=1e-7 * np.abs(local).max())
    assert abs(middle[0] - middle[2]) > 0.2 * max(middle)


def test_a_journals_load_given_is_fixed_and_the_two_others_take_the_lever_rule():
    """Some loads given: they are fixed forces, and the two journals left (j1 on its pedestal, j2)
    carry the rest by statics alone (issue 29's follow-up; it was the films' split with a warning):
    F1 + F2 = W - 200 N, 0.1 F1 + 0.4 F2 = 0.4 * 200 N m, at every speed."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        model = _mixed()
    assert model.bearings[1].coefficients.journal.load_over_speed is None
    weight = 50.0 * G
    f2 = (80.0 - 0.1 * (weight - 200.0)) / 0.3
    np.testing.assert_allclose([b.coefficients.journal.load for b in model.bearings],
                               [200.0, weight - 200.0 - f2, f2], rtol=1e-13)


def _mixed():
    data = _rigid(pedestals=()).to_dict()
    data["bearings"][1].update(pedestal_mass=6.0, pedestal_stiffness=2e6)
    data["bearings"][0]["load"] = 200.0
    return rdm.Model.from_dict(data)


def test_check_says_the_films_split_is_not_the_analyses_load(tmp_path, capsys):
    """`check` prints each journal's load on the films alone and says the analyses solve it at each
    speed, with the pedestals (one journal on a pedestal) or without (no pedestal: since issue 29's
    follow-up every rotor on three or more journals has its loads solved at each speed)."""
    from rotordyn_modal.cli import main

    journal = 'type = "journal"\nlength = 0.02\ndiameter = 0.05\nclearance = 5e-5\nviscosity = 0.02\n'
    rotor = ('spin_axis = [1.0, 0.0, 0.0]\ngravity = [0.0, 0.0, -9.81]\n[[rotors]]\nname = "r"\nmass = 50.0\n'
             'center_of_mass = [0.0, 0.0, 0.0]\npolar_inertia = 0.5\ndiametral_inertia = 2.0\nspeed_ratio = 1.0\n')
    for pedestal, said in (("pedestal_mass = 6.0\npedestal_stiffness = 2e6\n", True), ("", False)):
        bearings = "".join(f'[[bearings]]\nname = "j{i}"\nrotor = "r"\nposition = [{s}, 0.0, 0.0]\n{journal}'
                           + (pedestal if i == 1 else "") for i, s in enumerate((-0.4, 0.1, 0.4)))
        path = tmp_path / f"m{int(said)}.toml"
        path.write_text(rotor + bearings)
        assert main(["check", str(path)]) == 0
        out = capsys.readouterr().out
        assert out.count("analyses and static solve it at each speed on the nonlinear films") == 3
        assert ("with the pedestals" in out) is said
        assert out.count("static load") == 3


@pytest.mark.parametrize("rpm", [1000.0, 3000.0])
def test_the_time_models_static_equilibrium_carries_the_same_loads(tmp_path, rpm):
    """simulate (its linear time model keeps each journal's film force whole, a function of the
    journal's position: it takes no static load) settles, without unbalance, where the rotor on its
    nonlinear films and its pedestal stands: the bearings' forces at the end equal the loads solved
    here (at 1,000 rpm the outer films run at eccentricity 0.62)."""
    import pandas as pd
    import tomli_w

    from rotordyn_modal.cli import main

    path, out = tmp_path / "m.toml", tmp_path / "run.csv"
    path.write_text(tomli_w.dumps(_rigid().to_dict()))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["simulate", str(path), "--speed", str(rpm), "--duration", "0.3", "--out", str(out), "--quiet"]) == 0
    last = pd.read_csv(out).iloc[-1]
    forces = np.array([[last[f"j{i}_Fy"], last[f"j{i}_Fz"]] for i in range(3)])
    expected = _solve(rdm.rpm([rpm]), np.array([-0.4, 0.1, 0.4]), [0.02] * 3, 50.0,
                      [None, (np.eye(2) * 2e6, 6.0), None])[0]
    np.testing.assert_allclose(forces, expected, rtol=0, atol=1e-7 * 50 * G)
