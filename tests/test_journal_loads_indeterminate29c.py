"""A rotor on three or more journal bearings is statically indeterminate (issue 29: "the
journal-bearing loads of a rotor on three bearings equal the statically indeterminate
solution"): its journals' loads are solved at each speed on their nonlinear short-bearing films
(and a flexible shaft's bending, and pedestals' springs), with or without pedestals, the same in
the analyses' coefficients and in ``rdm.static``. Two journals keep the lever rule, exactly.
Journals whose ``load`` is given are fixed forces; the others carry the rest.

Truth from outside the package: the short (Ocvirk) bearing written here from its closed forms
(load number sigma(eps), attitude angle atan(pi sqrt(1 - eps^2) / (4 eps)); Ocvirk 1952, Childs
1993 §3), solved by brentq, and scipy's hybr root-finder on the compatibility and balance
equations, continued in speed from light load; Euler-Bernoulli closed forms of a simply
supported beam for the flexible shaft; the lever rule for two journals."""

import warnings

import numpy as np
import pytest
import scipy.optimize

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError, ModelWarning

G = 9.81
D, C, MU = 0.05, 5e-5, 0.02                    # journal diameter, radial clearance [m], viscosity [Pa s]
DOWN = np.array([0.0, -1.0])                   # (y, z) with gravity along -z; spin axis +x


def _ocvirk_offset(load, speed, length):
    """The journal's offset (y, z) [m] from its bearing's centre under ``load`` (y, z) [N] at
    ``speed`` [rad/s] (spin about +x), short bearing: sigma = mu |w| D L^3 / (8 W c^2) =
    (1 - e^2)^2 / (e sqrt(16 e^2 + pi^2 (1 - e^2))), the journal at c e from the centre, turned
    from the load line by atan(pi sqrt(1 - e^2) / (4 e)) in the sense of rotation."""
    magnitude = float(np.linalg.norm(load))
    sigma = MU * abs(speed) * D * length**3 / (8 * magnitude * C**2)
    eps = scipy.optimize.brentq(
        lambda e: (1 - e**2)**2 / (e * np.sqrt(16 * e**2 + np.pi**2 * (1 - e**2))) - sigma, 1e-15, 1 - 1e-15,
        xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)
    phi = np.sign(speed) * np.arctan2(np.pi * np.sqrt(1 - eps**2), 4 * eps)
    x = np.asarray(load, dtype=float) / magnitude
    turned = np.array([-x[1], x[0]])           # e x x, e = +x, in the (y, z) plane
    return C * eps * (np.cos(phi) * x + np.sin(phi) * turned)


def _root(speed, stations, lengths, weight, moment=np.zeros(2), pedestals=None, given=(), flexibility=None,
          sag=None):
    """The loads (N, 2) (y, z) [N] the journals at ``stations`` [m] put on their bearings, by hybr
    on: journal i's offset + its pedestal's settlement - (u + s_i theta) + the shaft's bending
    (sum_k phi_ik F_k - w_i) = 0, sum F = ``weight`` - sum of the ``given`` (s, F) loads, sum s F =
    ``moment`` - sum s_g F_g. Continued from 30,000 rpm (light load: start from equal shares).
    ``pedestals``: None or (k [N/m], m_p [kg]) per journal."""
    n = len(stations)
    s = np.asarray(stations, dtype=float)
    force = np.asarray(weight, dtype=float) - sum((f for _, f in given), np.zeros(2))
    torque = np.asarray(moment, dtype=float) - sum((z * np.asarray(f) for z, f in given), np.zeros(2))
    phi = np.zeros((n, n)) if flexibility is None else np.asarray(flexibility)
    w = np.zeros((n, 2)) if sag is None else np.asarray(sag)
    scale = float(np.linalg.norm(weight))

    def residual(state, speed):
        loads, u, theta = state[:2 * n].reshape(n, 2), state[2 * n:2 * n + 2], state[2 * n + 2:]
        rows = []
        for i in range(n):
            gap = _ocvirk_offset(loads[i], speed, lengths[i]) - u - s[i] * theta + phi[i] @ loads - w[i]
            if pedestals is not None and pedestals[i] is not None:
                k, m = pedestals[i]
                gap = gap + (loads[i] + m * G * DOWN) / k
            rows.append(gap / C)
        rows += [(loads.sum(0) - force) / scale, (s @ loads - torque) / (scale * np.ptp(s))]
        return np.concatenate(rows)

    state = np.concatenate([np.tile(force / n, n), np.zeros(4)])
    top = np.sign(speed) * max(abs(speed), rdm.rpm(30000.0))
    for step in np.geomspace(top, speed, 10):
        solution = scipy.optimize.root(residual, state, args=(step,), method="hybr", options={"xtol": 1e-14})
        assert np.max(np.abs(residual(solution.x, step))) < 1e-11
        state = solution.x
    return state[:2 * n].reshape(n, 2)


def _rigid(stations, lengths, mass=50.0, loads=None, pedestals=None):
    """A rigid rotor of ``mass`` [kg], centre of mass at the origin, on journals at ``stations``
    along +x; ``loads``: a given load [N] or None per journal; ``pedestals``: None or (k, m_p)."""
    bearings = []
    for i, (s, length) in enumerate(zip(stations, lengths)):
        bearing = {"name": f"j{i}", "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal", "length": length,
                   "diameter": D, "clearance": C, "viscosity": MU}
        if loads is not None and loads[i] is not None:
            bearing["load"] = loads[i]
        if pedestals is not None and pedestals[i] is not None:
            bearing.update(pedestal_stiffness=pedestals[i][0], pedestal_mass=pedestals[i][1])
        bearings.append(bearing)
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G], "spin_axis": [1.0, 0.0, 0.0],
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                    "diametral_inertia": 2.0, "speed_ratio": 1.0}],
        "bearings": bearings})


def _analyses_loads(model, speed):
    """The load (y, z) [N] at which each journal's film coefficients are taken at ``speed``:
    the force the journal puts on its bearing."""
    out = []
    for b in model.bearings:
        j = b.coefficients.journal
        vector = (j.load_over_speed(np.array([speed]))[0] if j.load_over_speed is not None
                  else j.load * j.axes[0])
        out.append(vector[1:])
    return np.array(out)


def _static_loads(model, speed):
    """The force (y, z) [N] each journal puts on its bearing in ``rdm.static`` (minus its reaction)."""
    result = rdm.static(model, speed=speed)
    return -np.array([r.force[1:] for r in result.reactions if r.kind == "bearing"])


@pytest.mark.parametrize("rpm", [1000.0, 3000.0, -3000.0])
def test_a_rigid_rotor_on_three_journals_carries_the_nonlinear_films_solution(rpm):
    """No pedestal: the loads of the analyses and of static are the root-finder's (at 1,000 rpm
    the light-load split the model used before, 185.2 / 160.2 / 145.1 N, is off by about 1 N)."""
    stations, lengths, mass = [-0.4, 0.1, 0.4], [0.02, 0.02, 0.02], 50.0
    model = _rigid(stations, lengths, mass)
    speed = rdm.rpm(rpm)
    expected = _root(speed, stations, lengths, mass * G * DOWN)
    np.testing.assert_allclose(_analyses_loads(model, speed), expected, rtol=0, atol=1e-9 * mass * G)
    np.testing.assert_allclose(_static_loads(model, speed), expected, rtol=0, atol=1e-9 * mass * G)


def test_the_analyses_film_coefficients_are_those_of_the_solved_loads():
    """What modes, campbell, stability and unbalance use: the bearing's 6x6 stiffness at the speed
    is the short bearing's at the root-finder's load, turned to its direction."""
    from rotordyn_modal.elements.bearings import evaluate
    from rotordyn_modal.elements.journal_bearing import short_journal_bearing

    stations, lengths, mass, speed = [-0.35, 0.0, 0.3], [0.02, 0.03, 0.025], 50.0, rdm.rpm(2000.0)
    model = _rigid(stations, lengths, mass)
    expected = _root(speed, stations, lengths, mass * G * DOWN)
    for bearing, load, length in zip(model.bearings, expected, lengths):
        stiffness = evaluate(bearing.coefficients, np.array([speed]), "test")[0][0][1:3, 1:3]
        film = short_journal_bearing([speed], diameter=D, length=length, clearance=C, viscosity=MU,
                                     load=np.linalg.norm(load))
        x = load / np.linalg.norm(load)
        frame = np.array([x, [-x[1], x[0]]]).T                  # columns: load line, e x load line
        np.testing.assert_allclose(stiffness, frame @ film.stiffness[0] @ frame.T, rtol=1e-7,
                                   atol=1e-7 * np.abs(film.stiffness[0]).max())


def test_four_journals_and_the_high_speed_limit():
    """Four journals (indeterminate twice) at 2,000 rpm: the root-finder's loads; at 1e6 rpm the
    films are at light load and the split is that of a rigid beam on springs k_i ~ L_i^3."""
    stations, lengths, mass = [-0.5, -0.1, 0.2, 0.45], [0.02, 0.03, 0.02, 0.025], 80.0
    model = _rigid(stations, lengths, mass)
    expected = _root(rdm.rpm(2000.0), stations, lengths, mass * G * DOWN)
    np.testing.assert_allclose(_analyses_loads(model, rdm.rpm(2000.0)), expected, rtol=0, atol=1e-9 * mass * G)
    np.testing.assert_allclose(_static_loads(model, rdm.rpm(2000.0)), expected, rtol=0, atol=1e-9 * mass * G)
    k, s = np.asarray(lengths)**3, np.asarray(stations)
    u, theta = np.linalg.solve([[k.sum(), k @ s], [k @ s, k @ s**2]], [mass * G, 0.0])
    beam = k * (u + theta * s)
    fast = _analyses_loads(model, rdm.rpm(1e6))
    np.testing.assert_allclose(-fast[:, 1], beam, rtol=2e-3)


def test_two_journals_keep_the_lever_rule_exactly():
    """Statically determinate: the loads are the lever rule's to round-off, at every speed, and no
    load is solved over speed (the same bits as before: checked against the previous code)."""
    model = _rigid([-0.2, 0.4], [0.02, 0.04], mass=30.0)
    loads = [b.coefficients.journal.load for b in model.bearings]
    np.testing.assert_allclose(loads, [30.0 * G * 0.4 / 0.6, 30.0 * G * 0.2 / 0.6], rtol=1e-15)
    assert all(b.coefficients.journal.load_over_speed is None for b in model.bearings)
    for rpm in (500.0, 5000.0):
        np.testing.assert_allclose(_static_loads(model, rdm.rpm(rpm)), [[0.0, -loads[0]], [0.0, -loads[1]]],
                                   rtol=1e-12, atol=1e-12 * loads[0])


# -- a flexible rotor on three journals without pedestals ---------------------------------------
E, DENSITY, SPAN, DISK, SHAFT = 2.1e11, 7850.0, 0.6, 20.0, 0.05
LENGTHS = [0.02, 0.03, 0.025]


def _flexible():
    """A 1.2 m steel shaft (Euler-Bernoulli, 50 mm) on journals at 0, 0.6, 1.2 m, a 20 kg disk at 0.3 m."""
    bearings = [{"name": f"j{i}", "rotor": "r", "type": "journal", "axial_position": z, "diameter": D,
                 "length": length, "clearance": C, "viscosity": MU}
                for i, (z, length) in enumerate(zip((0.0, SPAN, 2 * SPAN), LENGTHS))]
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G], "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": DENSITY, "young_modulus": E, "poisson_ratio": 0.3}],
        "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shear": "none", "shaft": [{"length": 2 * SPAN, "outer_diameter": SHAFT, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": SPAN / 2, "mass": DISK, "polar_inertia": 0.1,
                               "diametral_inertia": 0.05}]}],
        "bearings": bearings})


@pytest.mark.parametrize("rpm", [1000.0, 3000.0])
def test_a_flexible_rotor_on_three_journals_carries_its_films_and_bending_solution(rpm):
    """The shaft held at its end journals (a simply supported beam of span l = 1.2 m) sags at the
    middle one by 5 w l^4 / (384 E I) + P a (l - x)(2 l x - x^2 - a^2) / (6 l E I) (the disk's P
    at a = 0.3 m, x = 0.6 m) and bends there by l^3 / (48 E I) per newton; the journals move by
    u + z theta besides. The model used the continuous beam on rigid supports before (113.7 /
    248.3 / 15.6 N by Euler-Bernoulli), the films' limit."""
    inertia = np.pi * SHAFT**4 / 64
    w, P = DENSITY * np.pi * SHAFT**2 / 4 * G, DISK * G
    l, a, x = 2 * SPAN, SPAN / 2, SPAN
    sag = (5 * w * l**4 / 384 + P * a * (l - x) * (2 * l * x - x**2 - a**2) / (6 * l)) / (E * inertia)
    flexibility = np.zeros((3, 3))
    flexibility[1, 1] = l**3 / (48 * E * inertia)
    weight = (w * l + P) * DOWN
    moment = (w * l * l / 2 + P * a) * DOWN                     # about the shaft's start
    expected = _root(rdm.rpm(rpm), [0.0, SPAN, 2 * SPAN], LENGTHS, weight, moment, flexibility=flexibility,
                     sag=np.array([np.zeros(2), sag * DOWN, np.zeros(2)]))
    model = _flexible()
    scale = w * l + P
    np.testing.assert_allclose(_analyses_loads(model, rdm.rpm(rpm)), expected, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(_static_loads(model, rdm.rpm(rpm)), expected, rtol=0, atol=1e-9 * scale)


# -- given loads: fixed forces, the other journals carry the rest ---------------------------------
def test_given_loads_are_fixed_and_three_other_journals_solve_the_rest_with_a_pedestal():
    """Four journals, j1's load given (150 N, down), j2 on a 6 kg, 2e6 N/m pedestal: j0, j2, j3 are
    the root-finder's with j1's load a fixed force; `static` carries the given load at j1 and the
    same loads at the others."""
    stations, lengths, mass = [-0.45, -0.1, 0.15, 0.45], [0.02, 0.025, 0.02, 0.02], 60.0
    pedestal = (2e6, 6.0)
    model = _rigid(stations, lengths, mass, loads=[None, 150.0, None, None], pedestals=[None, None, pedestal, None])
    for rpm in (1000.0, 4000.0):
        speed = rdm.rpm(rpm)
        rest = _root(speed, [stations[i] for i in (0, 2, 3)], [lengths[i] for i in (0, 2, 3)], mass * G * DOWN,
                     pedestals=[None, pedestal, None], given=[(stations[1], 150.0 * DOWN)])
        expected = np.insert(rest, 1, 150.0 * DOWN, axis=0)
        np.testing.assert_allclose(_analyses_loads(model, speed), expected, rtol=0, atol=1e-9 * mass * G)
        np.testing.assert_allclose(_static_loads(model, speed), expected, rtol=0, atol=1e-9 * mass * G)


def test_two_journals_left_beside_a_given_load_take_the_lever_rule():
    """Three journals, the middle one's load given: the two others carry the rest of the weight
    and its moment by statics alone, with or without a pedestal under one of them, at every speed."""
    stations, mass, given = [-0.4, 0.1, 0.4], 50.0, 100.0
    weight = mass * G
    # F0 + F2 = W - P, -0.4 F0 + 0.4 F2 = -0.1 P (moments about the centre of mass)
    f2 = ((weight - given) * 0.4 - 0.1 * given) / 0.8
    f0 = weight - given - f2
    for pedestals in (None, [None, None, (2e6, 6.0)]):
        with warnings.catch_warnings():
            warnings.simplefilter("error", ModelWarning)        # no "films' split" warning any more
            model = _rigid(stations, [0.02] * 3, mass, loads=[None, given, None], pedestals=pedestals)
        np.testing.assert_allclose([b.coefficients.journal.load for b in model.bearings], [f0, given, f2],
                                   rtol=1e-13)
        for rpm in (1000.0, 5000.0):
            np.testing.assert_allclose(_static_loads(model, rdm.rpm(rpm)), [[0, -f0], [0, -given], [0, -f2]],
                                       rtol=0, atol=1e-9 * weight)


def test_one_journal_left_beside_given_loads_is_refused_naming_its_key():
    """Two of three loads given: the third is fixed by the force balance, and the moment balance
    then fails (unless the given loads happen to satisfy it): one line naming the key."""
    with pytest.raises(InputError, match=r"\[bearings\.j2\] load.*cannot balance its moment"):
        _rigid([-0.4, 0.1, 0.4], [0.02] * 3, loads=[200.0, 100.0, None])
    weight = 50.0 * G                                          # consistent: j0 -0.4, j1 0, j2 +0.4
    model = _rigid([-0.4, 0.0, 0.4], [0.02] * 3, loads=[weight / 4, weight / 2, None])
    assert model.bearings[2].coefficients.journal.load == pytest.approx(weight / 4, rel=1e-12)


def _simply_supported(x, a, l, inertia):
    """The deflection [m/N] at ``x`` of a simply supported beam of span ``l`` under a unit force at
    ``a`` (Roark, Table 8.1 case 1e): b x (l^2 - b^2 - x^2) / (6 l E I) for x <= a, b = l - a."""
    if x > a:
        x, a = l - x, l - a
    b = l - a
    return b * x * (l**2 - b**2 - x**2) / (6 * l * E * inertia)


def test_a_flexible_rotor_on_four_journals_with_a_given_load_bends_under_it():
    """Journals at 0, 0.4, 0.8 and 1.2 m on the shaft of ``_flexible``, j2's load given (60 N down):
    j0, j1, j3 are solved with the given load a fixed force that also bends the shaft. Held at its
    end journals the shaft sags at j1 (x = 0.4 m) by w x (l^3 - 2 l x^2 + x^3) / (24 E I) under its
    weight, by the point-load formula under the disk's weight at 0.3 m, and rises under j2's load
    pushing it up at 0.8 m; it bends at j1 by the same formula per newton there."""
    inertia = np.pi * SHAFT**4 / 64
    w, P, l, given = DENSITY * np.pi * SHAFT**2 / 4 * G, DISK * G, 2 * SPAN, 60.0
    x = 0.4
    sag = (w * x * (l**3 - 2 * l * x**2 + x**3) / (24 * E * inertia) + P * _simply_supported(x, SPAN / 2, l, inertia)
           - given * _simply_supported(x, 0.8, l, inertia))
    flexibility = np.zeros((3, 3))
    flexibility[1, 1] = _simply_supported(x, x, l, inertia)
    weight, moment = (w * l + P) * DOWN, (w * l * l / 2 + P * SPAN / 2) * DOWN
    data = _flexible().to_dict()
    data["bearings"] = [dict(data["bearings"][0], name=f"j{i}", axial_position=z) for i, z in
                        enumerate((0.0, 0.4, 0.8, 1.2))]
    data["bearings"][2]["load"] = given
    model = rdm.Model.from_dict(data)
    for rpm in (1500.0, 6000.0):
        rest = _root(rdm.rpm(rpm), [0.0, 0.4, 1.2], [LENGTHS[0]] * 3, weight, moment,
                     given=[(0.8, given * DOWN)], flexibility=flexibility,
                     sag=np.array([np.zeros(2), sag * DOWN, np.zeros(2)]))
        expected = np.insert(rest, 2, given * DOWN, axis=0)
        np.testing.assert_allclose(_analyses_loads(model, rdm.rpm(rpm)), expected, rtol=0, atol=1e-9 * (w * l + P))
        np.testing.assert_allclose(_static_loads(model, rdm.rpm(rpm)), expected, rtol=0, atol=1e-9 * (w * l + P))
