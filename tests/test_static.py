"""Static analysis (``rdm.static``, ``rotordyn-modal static``) against closed forms written out here:
a rigid casing on mounts, a rigid rotor on two and on three supports (the statically
indeterminate beam on springs), gear tooth and belt forces, the journal bearings' weight split,
and the balance of loads and reactions over random machines."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError, ModelError

G = 9.81
JOURNAL = {"diameter": 0.05, "clearance": 5e-5, "viscosity": 0.02}


def _casing(mass=200.0, centre=(0.0, 0.0, 0.0), k=(2e5, 3e5, 4e5), a=0.5, b=0.3, **mount):
    """A rigid casing on four equal mounts at (+-a, +-b, 0) under gravity along -z."""
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G],
        "stator": {"mass": mass, "inertia": [10.0, 20.0, 25.0], "center_of_mass": list(centre)},
        "rotors": [{"name": "r", "mass": 1e-9, "center_of_mass": list(centre), "polar_inertia": 1e-12,
                    "diametral_inertia": 1e-12, "speed_ratio": 1.0}],
        "suspensions": [{"name": f"m{i}", "position": [sx * a, sy * b, 0.0], "stiffness": list(k), **mount}
                        for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1)))],
    })


def _rotor_on(stations, stiffness, mass=40.0, centre=0.0, stator=False, gravity=(0.0, 0.0, -G), **extra):
    """A rigid rotor along x on bearings at x = ``stations`` of radial ``stiffness`` each."""
    data = {
        "gravity": list(gravity),
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [centre, 0.0, 0.0], "polar_inertia": 0.2,
                    "diametral_inertia": 1.0, "speed_ratio": 1.0}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "position": [s, 0.0, 0.0], "stiffness": k, **extra}
                     for i, (s, k) in enumerate(zip(stations, stiffness))],
    }
    if stator:
        data["stator"] = {"mass": 300.0, "inertia": [20.0, 30.0, 30.0], "center_of_mass": [0.1, 0.0, -0.2]}
        data["suspensions"] = [{"name": f"m{i}", "position": [x, y, -0.3], "stiffness": [1e6, 1e6, 2e6]}
                               for i, (x, y) in enumerate(((0.6, 0.4), (0.6, -0.4), (-0.6, 0.4), (-0.6, -0.4)))]
    return rdm.Model.from_dict(data)


def _forces(result, kind="bearing"):
    return np.array([r.force for r in result.reactions if r.kind == kind])


# -- the casing on its mounts -----------------------------------------------------------------
@pytest.mark.parametrize("mount", [{}, {"loss_factor": 0.2},
                                   {"maxwell_stiffness": [[1e5, 2e5, 3e5]], "maxwell_time": [0.01]}])
def test_a_casing_on_mounts_sags_by_weight_over_stiffness(mount):
    """Vertical sag W / (4 k_z), each mount W / 4; Maxwell branches and loss add nothing at rest."""
    model = _casing(**mount)
    result = rdm.static(model)
    weight = (model.stator.mass + 1e-9) * G
    motion = result.stator_motion()
    assert motion[2] == pytest.approx(-weight / (4 * 4e5), rel=1e-12)
    np.testing.assert_allclose(motion[[0, 1, 3, 4, 5]], 0.0, atol=1e-12 * abs(motion[2]))
    np.testing.assert_allclose(_forces(result, "mount")[:, 2], weight / 4, rtol=1e-12)


def test_an_offset_centre_of_mass_tilts_the_casing_by_the_moment_balance():
    """Centre of mass at x = c over mounts at x = +-a: the sag at the pattern's centre is W / (4k),
    the tilt theta_y = c W / (4 k a**2), the front mounts carry W / 4 (1 + c / a)."""
    c, a, k = 0.12, 0.5, 4e5
    model = _casing(centre=(c, 0.0, 0.0), a=a)
    result = rdm.static(model)
    weight = (model.stator.mass + 1e-9) * G
    at_centre = result.stator_motion([0.0, 0.0, 0.0])
    assert at_centre[2] == pytest.approx(-weight / (4 * k), rel=1e-12)
    assert at_centre[4] == pytest.approx(c * weight / (4 * k * a**2), rel=1e-12)
    front = [r.force[2] for r in result.reactions if r.point[0] > 0]
    np.testing.assert_allclose(front, weight / 4 * (1 + c / a), rtol=1e-12)


# -- rigid rotors on their bearings -------------------------------------------------------------
@pytest.mark.parametrize("centre", [0.1, -0.25, 0.6])           # 0.6: overhung beyond the bearings
@pytest.mark.parametrize("stator", [False, True])
def test_a_rotor_on_two_bearings_follows_the_lever_rule(centre, stator):
    s1, s2, mass = -0.3, 0.4, 40.0
    result = rdm.static(_rotor_on([s1, s2], [2e7, 5e7], mass=mass, centre=centre, stator=stator))
    weight = mass * G
    expected = [weight * (s2 - centre) / (s2 - s1), weight * (centre - s1) / (s2 - s1)]
    np.testing.assert_allclose(_forces(result)[:, 2], expected, rtol=1e-12)
    np.testing.assert_allclose(_forces(result)[:, :2], 0.0, atol=1e-12 * weight)


def _beam_on_springs(stations, stiffness, weight, centre):
    """Reactions of a rigid beam on springs k_i at s_i under a weight at s_G, by hand: the beam
    moves w + phi s; sum k (w + phi s) = W and sum k (w + phi s) s = W s_G (Cramer's rule)."""
    k, s = np.asarray(stiffness, float), np.asarray(stations, float)
    a11, a12, a22 = k.sum(), (k * s).sum(), (k * s * s).sum()
    det = a11 * a22 - a12 * a12
    w = (weight * a22 - a12 * weight * centre) / det
    phi = (a11 * weight * centre - a12 * weight) / det
    return k * (w + phi * s)


@pytest.mark.parametrize("stator", [False, True])
def test_a_rotor_on_three_bearings_is_the_beam_on_springs(stator):
    stations, stiffness, centre, mass = [-0.4, 0.05, 0.5], [3e7, 8e7, 1e7], 0.12, 60.0
    result = rdm.static(_rotor_on(stations, stiffness, mass=mass, centre=centre, stator=stator))
    expected = _beam_on_springs(stations, stiffness, mass * G, centre)
    np.testing.assert_allclose(_forces(result)[:, 2], expected, rtol=1e-10)
    # and the rotor's sag at each bearing is its reaction over its stiffness
    sag = [result.rotor_motion("r", [s, 0, 0])[2] for s in stations]
    np.testing.assert_allclose(sag, -expected / np.asarray(stiffness), rtol=1e-10)


# -- bearings on pedestals: the pedestals' own weight is a load (as M a_g in simulate) --------------
M_PED, K_PED = 30.0, (4e6, 2.5e6)             # pedestal mass; its stiffness along y and z


def _pedestal_model(stator: bool, centre=0.1, stations=(-0.3, 0.4), mass=40.0, casing=None, gravity=(0.0, 0.0, -G)):
    data = {
        "gravity": list(gravity),
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [centre, 0.0, 0.0], "polar_inertia": 0.2,
                    "diametral_inertia": 1.0, "speed_ratio": 1.0}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "position": [s, 0.0, 0.0], "stiffness": k,
                      "pedestal_mass": M_PED, "pedestal_stiffness": list(K_PED)}
                     for i, (s, k) in enumerate(zip(stations, [2e7, 5e7]))],
    }
    if stator:
        data["stator"] = {"mass": 300.0, "inertia": [20.0, 30.0, 30.0], "center_of_mass": [0.0, 0.0, 0.0]}
        data["suspensions"] = [{"name": f"m{i}", "position": [x, y, -0.3], "stiffness": list(casing or (1e6, 1e6, 2e6))}
                               for i, (x, y) in enumerate(((0.6, 0.4), (0.6, -0.4), (-0.6, 0.4), (-0.6, -0.4)))]
    return rdm.Model.from_dict(data)


@pytest.mark.parametrize("stator", [False, True])
def test_a_pedestal_sags_by_its_share_of_the_rotor_and_its_own_weight(stator):
    """Rotor (m, centre c) on bearings at s1, s2 (k_b), each on a pedestal (m_p, k_p): the bearings
    carry the lever rule's shares R_i; each pedestal carries R_i + m_p g on its spring, so it sags
    (R_i + m_p g) / k_pz relative to what carries it, and the rotor at the bearing R_i / k_b more."""
    s1, s2, c, mass = -0.3, 0.4, 0.1, 40.0
    result = rdm.static(_pedestal_model(stator, centre=c, stations=(s1, s2), mass=mass))
    shares = mass * G * np.array([(s2 - c) / (s2 - s1), (c - s1) / (s2 - s1)])
    np.testing.assert_allclose(_forces(result)[:, 2], shares, rtol=1e-12)
    held = shares + M_PED * G
    np.testing.assert_allclose(_forces(result, "pedestal")[:, 2], held, rtol=1e-12)
    np.testing.assert_allclose(_forces(result, "pedestal")[:, :2], 0.0, atol=1e-12 * held.max())
    sag = np.array([result.pedestal_motion(f"b{i}")[2] for i in range(2)])
    np.testing.assert_allclose(sag, -held / K_PED[1], rtol=1e-12)
    np.testing.assert_allclose([result.pedestal_motion(f"b{i}")[1] for i in range(2)], 0.0, atol=1e-12 * abs(sag).max())
    rotor = [result.rotor_motion("r", [s, 0.0, 0.0])[2] for s in (s1, s2)]
    np.testing.assert_allclose(rotor, sag - shares / np.array([2e7, 5e7]), rtol=1e-12)
    table = result.displacements()
    np.testing.assert_allclose(table[table["body"] == "pedestal"]["uz_m"], sag, rtol=1e-12)
    reactions = result.reactions_table()
    assert list(reactions[reactions["kind"] == "bearing"]["on"]) == ["pedestal"] * 2
    assert list(reactions[reactions["kind"] == "pedestal"]["on"]) == ["stator" if stator else "ground"] * 2
    for body in ["machine", "stator", "r"]:
        force, moment, scale = result.imbalance(body)
        assert np.abs(force).max() < 1e-11 * scale and np.abs(moment).max() < 1e-11 * scale, body
    if not stator:    # the ground carries every weight, the pedestals' too
        ground = sum(r.force[2] for r in result.reactions if r.ground)
        assert ground == pytest.approx((mass + 2 * M_PED) * G, rel=1e-12)


def test_on_the_ground_pedestals_pass_their_weight_along_the_spin_axis_to_it():
    """Gravity inclined to the spin axis, the rotor held axially by the stator (no axial_stiffness):
    the ground's reactions (the pedestals' and the rotor's axial hold) carry every weight, the
    pedestals' along the axis too: their sum is -(m + 2 m_p) g."""
    gravity = np.array([-0.6, 0.0, -0.8]) * G
    mass = 40.0
    result = rdm.static(_pedestal_model(False, mass=mass, gravity=gravity))
    held = sum(r.force for r in result.reactions if r.ground)
    np.testing.assert_allclose(held, -(mass + 2 * M_PED) * gravity, rtol=1e-12, atol=1e-12 * G * mass)
    for r in (r for r in result.reactions if r.kind == "pedestal"):    # the pedestal's own axial weight
        assert r.force[0] == pytest.approx(0.6 * G * M_PED, rel=1e-12)
    for body in ["machine", "stator", "r"]:
        force, moment, scale = result.imbalance(body)
        assert np.abs(force).max() < 1e-11 * scale and np.abs(moment).max() < 1e-11 * scale, body


def test_a_casing_carrying_pedestals_sags_by_the_whole_weight_over_its_mounts():
    """A casing centred over four equal mounts with a rotor centred between two bearings on
    pedestals: the mounts carry (M_s + m + 2 m_p) g, a quarter each, the casing sags by that over
    4 k_z, and each pedestal (m / 2 + m_p) g / k_pz relative to the casing."""
    mass, kz = 40.0, 2e6
    model = _pedestal_model(True, centre=0.0, stations=(-0.3, 0.3), mass=mass, casing=(1e6, 1e6, kz))
    result = rdm.static(model)
    total = (300.0 + mass + 2 * M_PED) * G
    np.testing.assert_allclose(_forces(result, "mount")[:, 2], total / 4, rtol=1e-12)
    assert result.stator_motion()[2] == pytest.approx(-total / (4 * kz), rel=1e-12)
    np.testing.assert_allclose([result.pedestal_motion(f"b{i}")[2] for i in range(2)],
                               -(mass * G / 2 + M_PED * G) / K_PED[1], rtol=1e-12)
    loads = result.loads_table()
    np.testing.assert_allclose(loads[loads["kind"] == "pedestal"]["Fz_N"], -M_PED * G, rtol=1e-15)
    from rotordyn_modal.plausibility import implausible
    soft = _pedestal_model(True, centre=0.0, stations=(-0.3, 0.3), mass=mass, casing=(1e3, 1e3, 2e3))
    (line,) = implausible(soft)                         # the check's sag: the same weights
    assert float(line.split("would sag ")[1].split(" m ")[0]) == pytest.approx(total / (4 * 2e3), rel=2e-3)


def test_the_static_weights_are_every_mass_of_m_as_the_time_model_applies_them(examples_dir):
    """A flexible shaft (with disks and a point mass), a rigid rotor, a casing on mounts and two
    bearings on pedestals under gravity: the static solution satisfies K q = M a_g, the weight of
    every mass of M as ``simulate`` applies it (docs/theory.md §19), and the loads and reactions
    balance."""
    import tomllib

    from rotordyn_modal.simulation.flexible import gravity_acceleration

    data = tomllib.loads((examples_dir / "flexible_pump_on_mounts.toml").read_text(encoding="utf-8"))
    for b in data["bearings"]:
        if b["name"] in ("pump-IB", "motor-NDE"):
            b.update(pedestal_mass=4.0, pedestal_stiffness=[3e7, 2e7])
    pump = next(r for r in data["rotors"] if "shaft" in r)
    pump["point_masses"] = [{"axial_position": 0.2, "mass": 0.8}]
    model = rdm.Model.from_dict(data)
    result = rdm.static(model)
    matrices = model.matrices()
    weight = matrices.M @ gravity_acceleration(model)
    np.testing.assert_allclose(matrices.K @ result.coordinates, weight, rtol=0, atol=1e-12 * np.abs(weight).max())
    for body in ["machine", "stator"] + [r.name for r in model.rotors]:
        force, moment, scale = result.imbalance(body)
        assert np.abs(force).max() < 1e-11 * scale and np.abs(moment).max() < 1e-11 * scale, body


def _journal_rotor(lengths, stations, centre=0.08, mass=50.0, loads=None):
    return rdm.Model.from_dict({
        "gravity": [0.0, 0.0, -G],
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [centre, 0.0, 0.0], "polar_inertia": 0.5,
                    "diametral_inertia": 2.0, "speed_ratio": 1.0}],
        "bearings": [{"name": f"j{i}", "rotor": "r", "position": [s, 0.0, 0.0], "type": "journal",
                      "length": length, **JOURNAL, **({} if loads is None else {"load": loads[i]})}
                     for i, (s, length) in enumerate(zip(stations, lengths))],
    })


def test_three_journal_bearings_carry_the_statically_indeterminate_split():
    """Journal films at light load are springs k = pi mu |w| D L**3 / (8 c**3): the weight splits as
    on a rigid beam on springs proportional to L**3 (the journals' printed load, the high-speed
    limit). At a speed rdm.static carries the split of the nonlinear films, which the independent
    root-finder of tests/test_journal_loads_indeterminate29c.py gives (the light-load split was
    off by 2 % at 3,000 rpm), and tends to the beam on springs as the speed grows."""
    from test_journal_loads_indeterminate29c import DOWN, _root

    lengths, stations, mass, centre = [0.02, 0.03, 0.025], [-0.35, 0.0, 0.3], 50.0, 0.08
    model = _journal_rotor(lengths, stations, centre, mass)
    expected = _beam_on_springs(stations, np.asarray(lengths)**3, mass * G, centre)
    loads = [b.coefficients.journal.load for b in model.bearings]
    np.testing.assert_allclose(loads, np.abs(expected), rtol=1e-12)
    for rpm in (3000.0, 12000.0):
        result = rdm.static(model, speed=rdm.rpm(rpm))
        films = _root(rdm.rpm(rpm), np.asarray(stations) - centre, lengths, mass * G * DOWN)
        np.testing.assert_allclose(_forces(result)[:, 1:], -films, rtol=0, atol=1e-9 * mass * G)
    result = rdm.static(model, speed=rdm.rpm(1e6))
    np.testing.assert_allclose(_forces(result)[:, 2], expected, rtol=2e-3)


def test_two_journal_bearings_keep_the_lever_rule():
    model = _journal_rotor([0.02, 0.04], [-0.3, 0.3], centre=0.1, mass=50.0)
    loads = [b.coefficients.journal.load for b in model.bearings]
    np.testing.assert_allclose(loads, [50 * G * 0.2 / 0.6, 50 * G * 0.4 / 0.6], rtol=1e-15)
    journal = rdm.static(model, speed=rdm.rpm(6000)).reactions[0]
    from rotordyn_modal.elements.journal_bearing import short_journal_bearing
    film = short_journal_bearing(rdm.rpm(6000), length=0.02, load=loads[0], **JOURNAL)
    assert journal.eccentricity == pytest.approx(float(film.eccentricity), rel=1e-12)


def test_journal_bearings_mixed_with_others_need_their_loads():
    data = _journal_rotor([0.02, 0.03, 0.025], [-0.35, 0.0, 0.3]).to_dict()
    data["bearings"][1] = {"name": "j1", "rotor": "r", "position": [0.0, 0.0, 0.0], "stiffness": 1e8}
    with pytest.raises(ModelError, match=r"\[bearings.j0\] load = .<missing>.: expected a static load"):
        rdm.Model.from_dict(data)


# -- transmissions ------------------------------------------------------------------------------
def _pair(kind="gear", **transmission):
    """Two rotors along x, on two bearings each, 0.25 m apart along y, joined by ``kind``."""
    rotors = [{"name": "a", "mass": 10.0, "center_of_mass": [0.0, 0.0, 0.0], "speed_ratio": 1.0},
              {"name": "b", "mass": 20.0, "center_of_mass": [0.0, 0.25, 0.0]}]
    return rdm.Model.from_dict({
        "reference_rotor": "a",
        "rotors": [{**r, "polar_inertia": 0.1, "diametral_inertia": 0.3} for r in rotors],
        "transmissions": [{"type": kind, "driver": "a", "driven": "b", "ratio": 1.5, **transmission}],
        "bearings": [{"name": f"{r['name']}{i}", "rotor": r["name"], "position": [x, r["center_of_mass"][1], 0.0],
                      "stiffness": 1e8} for r in rotors for i, x in enumerate((-0.2, 0.2))],
    })


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_gear_tooth_force_is_torque_over_pitch_radius_along_the_line_of_action(sense):
    radius, angle, torque = 0.08, 25.0, 120.0
    model = _pair(driver_radius=radius, pressure_angle=angle, position=[0.05, 0.0, 0.0])
    result = rdm.static(model, speed=sense * 300.0, torques=torque)
    on_driver = next(x for x in result.loads if x.kind == "gear" and x.body == "a")
    np.testing.assert_allclose(on_driver.point, [0.05, radius, 0.0], atol=1e-15)
    tangential, radial = on_driver.force[2], on_driver.force[1]       # tangent e x u = z, u = y
    # the driver's tooth at r y moves along sense * z: the driven wheel pushes it back
    assert tangential == pytest.approx(-sense * torque / radius, rel=1e-14)
    assert radial == pytest.approx(-torque / radius * np.tan(np.radians(angle)), rel=1e-14)  # apart
    assert np.linalg.norm(on_driver.force) == pytest.approx(torque / (radius * np.cos(np.radians(angle))), rel=1e-14)
    # power P at the driver's speed is the torque P / w; the bearings balance the tooth forces
    by_power = rdm.static(model, speed=sense * 300.0, power=torque * 300.0)
    np.testing.assert_allclose(_forces(by_power), _forces(result), rtol=1e-12, atol=1e-9)
    for body in ("a", "b", "machine"):
        force, moment, scale = result.imbalance(body)
        assert np.abs(np.r_[force, moment]).max() < 1e-12 * scale


def test_a_gear_pitch_radius_defaults_to_the_centre_distance_split():
    result = rdm.static(_pair(), speed=100.0, torques=50.0)
    on_driver = next(x for x in result.loads if x.kind == "gear" and x.body == "a")
    assert on_driver.point[1] == pytest.approx(0.25 / 2.5, rel=1e-14)       # a / (1 + ratio)
    assert abs(on_driver.force[2]) == pytest.approx(50.0 / 0.1, rel=1e-14)


@pytest.mark.parametrize("pretension, pull", [(0.0, 60.0 / 0.05), (1000.0, 2000.0)])
def test_belt_pull_is_torque_over_radius_or_twice_the_pretension(pretension, pull):
    model = _pair("belt", driver_radius=0.05, pretension=pretension)
    result = rdm.static(model, speed=200.0, torques=60.0)
    on_driver = next(x for x in result.loads if x.kind == "belt" and x.body == "a")
    np.testing.assert_allclose(on_driver.force, [0.0, pull, 0.0], rtol=1e-14)
    np.testing.assert_allclose(_forces(result)[:2].sum(axis=0), [0.0, -pull, 0.0], rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("key, value, expected", [
    ("pressure_angle", 50.0, "pressure_angle = 50.0: expected a pressure angle in degrees"),
    ("pretension", 10.0, "pretension = 10.0: expected no value: this key is for type = 'belt'"),
    ("driver_radius", -0.1, "driver_radius = -0.1: expected a finite number > 0"),
    ("position", [0, 1], "position = [0, 1]: expected a 3-list"),
])
def test_bad_transmission_geometry_is_refused_by_name(key, value, expected):
    with pytest.raises(ModelError, match="transmissions.*" + expected.replace("(", r"\(").replace(")", r"\)")
                       .replace("[", r"\[").replace("]", r"\]").replace(".", r"\.")):
        _pair(**{key: value})


def test_belt_torque_without_pulley_radius_is_refused():
    with pytest.raises(InputError, match=r"a->b\] driver_radius = <missing>"):
        rdm.static(_pair("belt"), speed=100.0, torques=10.0)


# -- refusals and the balance -------------------------------------------------------------------
def test_a_load_on_a_free_motion_is_refused_naming_it():
    model = _casing(k=(0.0, 3e5, 4e5))                 # nothing holds the casing along x
    rdm.static(model)                                  # the weight does not push along x
    with pytest.raises(InputError, match=r"push the stator's translation along x \(stator\.ux\), which no suspension or bearing holds"):
        rdm.static(model, forces=[("stator", [0.0, 0.0, 0.0], [10.0, 0.0, 0.0])])


def test_check_warns_of_the_sag_the_static_solution_gives():
    model = _casing(k=(2e2, 3e2, 4e2))                 # N/mm given as N/m
    from rotordyn_modal.plausibility import implausible
    (line,) = implausible(model)
    sag = max(abs(r.displacement[2]) for r in rdm.static(model).reactions)
    assert f"would sag {sag:.3g} m" in line


@st.composite
def _machines(draw):
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    rotors, bearings = [], []
    for j in range(draw(st.integers(1, 2))):   # r0, the reference rotor, turns at speed ratio 1
        centre = rng.uniform(-0.5, 0.5, 3)
        rotors.append({"name": f"r{j}", "mass": float(rng.uniform(1, 50)), "center_of_mass": centre.tolist(),
                       "polar_inertia": 0.1, "diametral_inertia": 0.2, "speed_ratio": 1.0 if j == 0 else -2.0})
        for i in range(draw(st.integers(2, 3))):
            bearings.append({"name": f"b{j}{i}", "rotor": f"r{j}",
                             "position": (centre + rng.uniform(-0.4, 0.4) * axis).tolist(),
                             "stiffness": float(rng.uniform(1e6, 1e8)),
                             **({"axial_stiffness": 1e7} if rng.random() < 0.5 else {})})
    for bearing in bearings:         # some on pedestals (their weight, along an inclined axis too)
        if draw(st.booleans()):
            bearing.update(pedestal_mass=float(rng.uniform(1, 20)),
                           pedestal_stiffness=rng.uniform(1e6, 1e8, 2).tolist())
    return {
        "spin_axis": axis.tolist(), "gravity": (rng.normal(size=3) * 5).tolist(), "reference_rotor": "r0",
        "stator": {"mass": float(rng.uniform(50, 500)), "inertia": [10.0, 12.0, 15.0],
                   "center_of_mass": rng.uniform(-0.2, 0.2, 3).tolist()},
        "rotors": rotors, "bearings": bearings,
        "suspensions": [{"name": f"m{i}", "position": rng.uniform(-1, 1, 3).tolist(),
                         "stiffness": rng.uniform(1e5, 1e6, 3).tolist()} for i in range(4)],
    }, [(str(rng.choice(["stator"] + [r["name"] for r in rotors])), rng.uniform(-1, 1, 3), rng.normal(size=3) * 100,
         rng.normal(size=3) * 10) for _ in range(2)]


@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(_machines())
def test_reactions_balance_the_loads_on_every_body(machine):
    data, forces = machine
    model = rdm.Model.from_dict(data)
    result = rdm.static(model, forces=forces)
    for body in ["machine", "stator"] + [r.name for r in model.rotors]:
        force, moment, scale = result.imbalance(body)
        assert np.abs(force).max() < 1e-11 * scale and np.abs(moment).max() < 1e-11 * scale, body


# -- the command line ---------------------------------------------------------------------------
def test_static_command_writes_its_tables(tmp_path, examples_dir, capsys):
    out = tmp_path / "static.csv"
    argv = ["static", str(examples_dir / "gear_machine.toml"), "--speed", "3000", "--power", "15000",
            "--force", "stator:0.1,0,0:0,0,-500", "--out", str(out)]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "reactions" in printed and "balance of loads and reactions" in printed
    import pandas as pd
    table = pd.read_csv(out)
    assert set(table["table"]) == {"load", "displacement", "reaction"}
    reactions = table[table["table"] == "reaction"]
    assert reactions["Fz_N"].sum() == pytest.approx(500.0, rel=1e-9)   # the mounts carry the given force


@pytest.mark.parametrize("options, message", [
    (["--force", "nobody:0,0,0:1,0,0"], "--force nobody:0,0,0:1,0,0: body = 'nobody': expected 'stator' or the name "
                                        "of a rotor"),      # the options as typed (round 5)
    (["--force", "stator:0,0:1,0,0"], "--force 'stator:0,0:1,0,0': expected 3 comma-separated numbers"),
    (["--power", "1000"], "--power 1000: expected a speed"),
    (["--speed", "3000", "--power", "motor->pump=10"], "--power motor->pump=10: unknown transmission 'motor->pump'"),
    (["--moment", "fan"], "--moment 'fan': expected BODY:MX,MY,MZ"),
])
def test_static_command_refuses_bad_input_in_one_line(options, message, examples_dir, capsys):
    assert main(["static", str(examples_dir / "gear_machine.toml"), *options]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err, err
