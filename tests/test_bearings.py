"""Rotors on flexible bearings: closed forms, the independent reference, limits, invariants.

* Ground limit: a rigid rotor on two bearings to ground has textbook closed forms
  (docs/theory.md §13), with gyroscopic coupling, offset centre of mass, anisotropy.
* Any rotor-bearing-casing machine equals ``tests/reference_bearings.py`` (absolute
  coordinates of every body, constraints by a null space, no code of the package).
* Rigid limit: as bearings stiffen, the casing modes converge to the rigidly attached
  model's, with an error that falls as 1/k.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import linear_sum_assignment

import rotordyn_modal as rdm
from reference_bearings import BearingMachine, random_bearing_description
from reference_model import translated
from rotordyn_modal.errors import ModelError
from rotordyn_modal.linear_system import speed_linear_form

SETTINGS = settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])

MASS, POLAR, DIAMETRAL = 12.0, 0.06, 0.25


def _rotor_on_bearings(stiffness_a, stiffness_b, a, b, damping=None, spin_axis=(1.0, 0.0, 0.0)):
    """A rigid rotor (centre at the origin) on bearings at +a and -b along the spin axis, to ground."""
    e = np.asarray(spin_axis, dtype=float) / np.linalg.norm(spin_axis)
    bearings = []
    for name, k, s in (("A", stiffness_a, a), ("B", stiffness_b, -b)):
        bearing = {"name": name, "rotor": "r", "position": (s * e).tolist(), "stiffness": k}
        if damping is not None:
            bearing["damping"] = damping
        bearings.append(bearing)
    return {"spin_axis": list(spin_axis),
            "rotors": [{"name": "r", "mass": MASS, "center_of_mass": [0.0, 0.0, 0.0],
                        "polar_inertia": POLAR, "diametral_inertia": DIAMETRAL, "speed_ratio": 1.0}],
            "bearings": bearings}


def _matched_error(found, expected):
    """Largest relative distance after pairing two sets of complex numbers optimally."""
    found, expected = np.asarray(found), np.asarray(expected)
    assert found.shape == expected.shape
    cost = np.abs(found[:, None] - expected[None, :])
    rows, cols = linear_sum_assignment(cost)
    return float(np.max(cost[rows, cols] / np.abs(expected[cols])))


# -- ground limit: closed forms -------------------------------------------------------------
@pytest.mark.parametrize("speed", [0.0, 400.0, 2500.0, -900.0])
def test_offset_rotor_on_isotropic_bearings_whirls_as_the_closed_form(speed):
    """Complex coordinates r = u_y + i u_z, phi = theta_z - i theta_y turn the four equations
    into two; r ~ exp(i w t) gives (2k - m w^2)(k(a^2 + b^2) - J_d w^2 + J_p Omega w) = k^2 (a - b)^2:
    roots w > 0 whirl forward, w < 0 backward (docs/theory.md §13)."""
    k, a, b = 3.0e6, 0.18, 0.07
    model = rdm.Model.from_dict(_rotor_on_bearings(k, k, a, b))
    coefficients = [MASS * DIAMETRAL, -MASS * POLAR * speed,
                    -(2 * k * DIAMETRAL + MASS * k * (a * a + b * b)), 2 * k * POLAR * speed,
                    2 * k * k * (a * a + b * b) - k * k * (a - b) ** 2]
    roots = np.roots(coefficients).real
    modes = rdm.modal(model, speed)
    assert np.max(np.abs(modes.frequencies_hz * 2 * np.pi - np.sort(np.abs(roots))) / np.abs(roots).max()) < 1e-12
    for w in roots:
        j = int(np.argmin(np.abs(modes.eigenvalues.imag - abs(w))))
        if speed != 0:
            spin = np.sign(speed)
            assert modes.whirl[j] == ("forward" if w * spin > 0 else "backward")
        assert abs(modes.eigenvalues.imag[j] - abs(w)) <= 1e-9 * abs(w)


@pytest.mark.parametrize("speed", [0.0, 700.0, 3000.0])
def test_symmetric_rotor_on_anisotropic_bearings_equals_the_closed_form(speed):
    """Centre midway: translations decouple, w^2 = 2 k_y / m and 2 k_z / m; the tilts obey
    J_d^2 w^4 - (J_d (K_a + K_b) + (J_p Omega)^2) w^2 + K_a K_b = 0 with K_a = 2 k_z L^2 (tilt about y)
    and K_b = 2 k_y L^2 (tilt about z)."""
    ky, kz, half = 2.0e6, 5.0e6, 0.15
    model = rdm.Model.from_dict(_rotor_on_bearings([ky, kz], [ky, kz], half, half))
    k_a, k_b = 2 * kz * half**2, 2 * ky * half**2
    tilt = np.sqrt(np.roots([DIAMETRAL**2, -(DIAMETRAL * (k_a + k_b) + (POLAR * speed) ** 2), k_a * k_b]))
    expected = np.sort(np.r_[np.sqrt(2 * ky / MASS), np.sqrt(2 * kz / MASS), tilt])
    found = rdm.modal(model, speed).frequencies_hz * 2 * np.pi
    np.testing.assert_allclose(found, expected, rtol=1e-12)


def test_critical_speeds_of_the_conical_forward_mode_equal_the_closed_form():
    """1X forward conical critical: w = Omega in J_d w^2 - J_p Omega w = 2 k L^2 gives
    Omega = sqrt(2 k L^2 / (J_d - J_p)) (exists since J_p < J_d)."""
    k, half = 1.0e6, 0.12
    model = rdm.Model.from_dict(_rotor_on_bearings(k, k, half, half))
    result = rdm.campbell(model, np.linspace(0, 2000, 201), orders=(1,))
    conical = np.sqrt(2 * k * half**2 / (DIAMETRAL - POLAR))
    forward = result.critical.speeds[result.critical.whirl == "forward"]
    assert np.min(np.abs(forward - conical)) <= 1e-10 * conical


# -- any machine against the independent reference -------------------------------------------
@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), stator=st.booleans(), speed=st.floats(-1500, 1500))
def test_rotor_bearing_casing_machines_equal_the_independent_reference(seed, stator, speed):
    data = random_bearing_description(np.random.default_rng(seed), n_rotors=2, stator=stator)
    model = rdm.Model.from_dict(data)
    found = np.linalg.eigvals(speed_linear_form(model).at(speed))
    assert _matched_error(found, BearingMachine(data).eigenvalues(speed)) < 1e-9


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), speed=st.floats(-1500, 1500))
def test_undamped_machines_with_symmetric_bearings_have_imaginary_eigenvalues(seed, speed):
    data = random_bearing_description(np.random.default_rng(seed), n_rotors=2, damping=False)
    for bearing in data["bearings"]:
        k = np.asarray(bearing["stiffness"])
        bearing["stiffness"] = (0.5 * (k + k.T) + 3 * np.abs(k).max() * np.eye(2)).tolist()
    values = np.linalg.eigvals(speed_linear_form(rdm.Model.from_dict(data)).at(speed))
    assert np.max(np.abs(values.real)) <= 1e-9 * np.abs(values).max()


def _probe_model(symmetric: bool):
    data = random_bearing_description(np.random.default_rng(7), n_rotors=2)
    if symmetric:
        for bearing in data["bearings"]:
            for key in ("stiffness", "damping"):
                k = np.asarray(bearing[key])
                bearing[key] = (0.5 * (k + k.T)).tolist()
    e = np.asarray(data["spin_axis"])
    centre = np.asarray(data["rotors"][0]["center_of_mass"])
    a = np.cross(e, [0.3, -0.4, 0.85])
    a /= np.linalg.norm(a)
    data["sensors"] = [
        {"name": "casing", "position": [0.3, 0.1, 0.2], "direction": [0.0, 0.6, 0.8]},
        {"name": "shaft", "position": (centre + 0.1 * e).tolist(), "direction": a.tolist(), "rotor": "r0"},
        {"name": "probe", "position": (centre - 0.1 * e).tolist(), "direction": np.cross(e, a).tolist(),
         "rotor": "r0", "measure": "relative"},
    ]
    data["excitations"] = [
        {"name": "hammer", "position": [0.3, 0.1, 0.2], "direction": [0.0, 0.6, 0.8]},
        {"name": "shaft-tap", "position": (centre + 0.1 * e).tolist(), "direction": a.tolist(), "rotor": "r0"},
        {"name": "probe-tap", "position": (centre - 0.1 * e).tolist(), "direction": np.cross(e, a).tolist(),
         "rotor": "r0"},
    ]
    return data


def test_frfs_of_rotor_sensors_and_probes_equal_the_independent_reference():
    data = _probe_model(symmetric=False)
    model = rdm.Model.from_dict(data)
    reference = BearingMachine(data)
    speed, freqs = 350.0, np.array([3.0, 17.0, 41.0, 160.0])
    H = rdm.frf(model, speed, freqs).H
    for i, sensor in enumerate(data["sensors"]):
        for j, force in enumerate(data["excitations"]):
            for f, h in zip(freqs, H[i, j]):
                w = 2 * np.pi * f
                args = (force["position"], force["direction"], force.get("rotor"))
                absolute = reference.receptance(speed, w, *args, sensor["position"], sensor["direction"],
                                                sensor.get("rotor"))
                if sensor.get("measure") == "relative":
                    absolute -= reference.receptance(speed, w, *args, sensor["position"], sensor["direction"], None)
                assert abs(h - absolute) <= 1e-9 * abs(absolute)


@pytest.mark.parametrize("symmetric", [True, False])
def test_reciprocity_with_spin_holds_for_symmetric_bearings_only(symmetric):
    """H_ij(Omega) = H_ji(-Omega) for a gyroscopic machine with symmetric K and C; cross-coupled
    (non-symmetric) bearing coefficients break it, as physics says."""
    data = _probe_model(symmetric)
    data["sensors"] = [dict(s, measure="absolute") for s in data["sensors"]]
    model = rdm.Model.from_dict(data)
    freqs = np.array([5.0, 30.0, 90.0])
    forward = rdm.frf(model, 400.0, freqs).H
    backward = rdm.frf(model, -400.0, freqs).H
    gap = np.max(np.abs(forward - np.swapaxes(backward, 0, 1))) / np.max(np.abs(forward))
    assert (gap < 1e-10) if symmetric else (gap > 1e-4)


# -- invariants ----------------------------------------------------------------------------------
def test_results_do_not_change_when_the_model_origin_moves():
    data = _probe_model(symmetric=False)
    moved = translated(data, [1.7, -0.4, 2.2])
    for bearing in moved.get("bearings", []):
        bearing["position"] = (np.asarray(bearing["position"]) + [1.7, -0.4, 2.2]).tolist()
    a, b = rdm.Model.from_dict(data), rdm.Model.from_dict(moved)
    speeds = np.linspace(0, 1500, 16)
    ca, cb = rdm.campbell(a, speeds), rdm.campbell(b, speeds)
    np.testing.assert_allclose(cb.eigenvalues, ca.eigenvalues, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(rdm.frf(b, 300.0, [4.0, 40.0]).H, rdm.frf(a, 300.0, [4.0, 40.0]).H, rtol=1e-9)


def test_a_rotor_without_bearings_is_the_rigidly_attached_rotor_of_today(examples_dir):
    """Adding bearings to one rotor leaves the matrices of the others' share untouched: with
    no bearings at all the coordinates are the stator's six and the matrices seed 000's."""
    model = rdm.load_model(examples_dir / "gear_machine.toml")
    assert model.dofs.names == ("stator.ux", "stator.uy", "stator.uz", "stator.rx", "stator.ry", "stator.rz")
    assert model.matrices().M.shape == (6, 6)


def _gear_machine_on_bearings(examples_dir, factor):
    """The gear machine with each rotor on two bearings ``factor`` times stiffer than a mount."""
    data = rdm.load_model(examples_dir / "gear_machine.toml").to_dict()
    mount = max(np.max(s["stiffness"]) for s in data["suspensions"])
    e = np.asarray(data["spin_axis"], dtype=float)
    data["bearings"] = []
    for rotor in data["rotors"]:
        centre = np.asarray(rotor["center_of_mass"])
        for side, s in (("DE", 0.08), ("NDE", -0.06)):
            data["bearings"].append({"name": f"{rotor['name']}-{side}", "rotor": rotor["name"],
                                     "position": (centre + s * e).tolist(), "stiffness": factor * mount,
                                     "axial_stiffness": factor * mount})
    return rdm.Model.from_dict(data)


def test_stiff_bearings_converge_to_the_rigidly_attached_rotors_as_one_over_k(examples_dir):
    rigid = rdm.modal(rdm.load_model(examples_dir / "gear_machine.toml"), 300.0)
    casing = rigid.eigenvalues[rigid.oscillatory]
    errors = []
    for factor in (1e4, 1e5, 1e6):
        flexible = rdm.modal(_gear_machine_on_bearings(examples_dir, factor), 300.0)
        lowest = flexible.eigenvalues[flexible.oscillatory][: len(casing)]
        errors.append(np.max(np.abs(lowest - casing) / np.abs(casing)))
    assert errors[-1] < 1e-6
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 8) & (ratios < 12))          # error ~ 1/k


# -- speed-dependent coefficients -------------------------------------------------------------
def _table_model(values_at_speeds, speeds_rpm):
    data = _rotor_on_bearings(1.0, 1.0, 0.15, 0.1)
    for bearing in data["bearings"]:
        bearing["speeds_rpm"] = list(speeds_rpm)
        bearing["stiffness"] = [[[k, 0.2 * k], [-0.2 * k, 1.3 * k]] for k in values_at_speeds]
        bearing["damping"] = [1e-4 * k for k in values_at_speeds]
    return rdm.Model.from_dict(data)


def test_tabulated_coefficients_are_interpolated_linearly_in_the_rotors_own_speed():
    table = _table_model([1e6, 3e6, 2e6], [0.0, 3000.0, 6000.0])
    speeds = rdm.rpm(np.array([0.0, 1000.0, 4500.0, 6000.0]))
    found = rdm.campbell(table, speeds).eigenvalues
    for speed, row in zip(speeds, found):
        k = np.interp(speed, rdm.rpm(np.array([0.0, 3000.0, 6000.0])), [1e6, 3e6, 2e6])
        constant = _table_model([k, k], [0.0, 6000.0])
        expected = np.linalg.eigvals(speed_linear_form(constant).at(speed))
        assert _matched_error(row, expected[expected.imag >= 0]) < 1e-12


def test_a_sweep_outside_the_table_is_refused_with_the_range():
    table = _table_model([1e6, 2e6], [1000.0, 6000.0])
    with pytest.raises(rdm.InputError, match=r"\[bearings.A\].*outside the coefficient table's speeds_rpm "
                                             r"range 1000 \.\. 6000 rpm"):
        rdm.campbell(table, rdm.rpm(np.linspace(0, 3000, 4)))


@pytest.mark.parametrize("low, high, refused", [
    (1000.0, 6000.0, False),                                       # the table's own ends: inside
    (1000.0 * (1 - 1e-14), 6000.0 * (1 + 1e-14), False),           # its ends to round-off: inside
    (1000.0, 6000.0 * (1 + 1e-9), True), (1000.0 * (1 - 1e-9), 6000.0, True)])
def test_the_table_range_ends_exactly_at_its_first_and_last_speeds(low, high, refused):
    """Coefficients are never extrapolated, not even a hair (1e-9) beyond the table; a speed
    within round-off of an end (rpm and rad/s converted on another route, a table read from ROSS
    in rad/s) is that end."""
    table = _table_model([1e6, 2e6], [1000.0, 6000.0])
    speeds = rdm.rpm(np.linspace(low, high, 4))
    if refused:
        with pytest.raises(rdm.InputError, match="outside the coefficient table's speeds_rpm range"):
            rdm.campbell(table, speeds)
    else:
        assert np.isfinite(rdm.campbell(table, speeds).frequencies_hz).any()


# -- bad input --------------------------------------------------------------------------------
@pytest.mark.parametrize("change, where, expected", [
    (lambda d: d["bearings"][0].update(rotor="shaft"), r"\[bearings.A\] rotor", "one of the rotors r"),
    (lambda d: d["bearings"][0].update(position=[0.1, 0.02, 0.0]), r"\[bearings.A\] position",
     "a point on the spin axis of rotor 'r'.*0.02 m off it"),
    (lambda d: d["bearings"][0].update(speeds_rpm=[0.0, 3000.0, 2000.0], stiffness=[1e6, 2e6, 3e6]),
     r"\[bearings.A\] speeds_rpm", "strictly increasing"),
    (lambda d: d["bearings"][0].update(stiffness=[[1e6, 0.0]]), r"\[bearings.A\] stiffness", "2x2 matrix"),
    (lambda d: d["bearings"][0].update(stiffness=-1.0), r"\[bearings.A\] stiffness", "non-negative"),
    (lambda d: d["bearings"][0].update(speeds_rpm=[0.0, 3000.0], stiffness=["1e6", 2e6]),
     r"\[bearings.A\] stiffness\[0\]", r"a number .*\(the string '1e6', not a number\)"),
    (lambda d: d["bearings"][0].update(damping=[True, 10.0]), r"\[bearings.A\] damping",
     r"\[0\] is the boolean True, not a number"),
    (lambda d: d["bearings"][0].update(speeds_rpm=[0.0, 3000.0]), r"\[bearings.A\] stiffness",
     "a list of 2 values, one per speed"),
    (lambda d: d["bearings"].pop(), r"\[bearings.A\] moment_stiffness", "nothing holds it in tilt"),
    (lambda d: d["bearings"][0].update(type="journal"), r"\[bearings.A\] stiffness", "type = 'journal'"),
    (lambda d: d["bearings"][0].update(clearance=1e-4), r"\[bearings.A\] clearance", "type = 'journal'"),
    (lambda d: d["bearings"][0].update(spin=1.0), r"\[bearings.A\] spin", "unknown key"),
    (lambda d: d.update(suspensions=[{"name": "s", "position": [0, 0, 0], "stiffness": [1.0, 1.0, 1.0]}]),
     "suspensions", r"without a \[stator\] the \[\[bearings\]\] connect the rotors to the ground"),
    (lambda d: d.update(sensors=[{"name": "acc", "position": [0, 0, 0], "direction": [0, 0, 1]}]),
     r"\[sensors.acc\] rotor", "fixed to the ground"),
    (lambda d: d.update(sensors=[{"name": "p", "position": [0, 0, 0], "direction": [0, 0, 1],
                                  "measure": "relative"}]), r"\[sensors.p\] measure", "needs rotor = NAME"),
])
def test_bad_bearing_tables_are_refused_naming_table_key_and_value(change, where, expected):
    data = _rotor_on_bearings(1e6, 1e6, 0.1, 0.1)
    change(data)
    with pytest.raises(ModelError, match=where + r" = .*: expected .*" + expected):
        rdm.Model.from_dict(copy.deepcopy(data))


def test_a_journal_bearing_with_zero_clearance_is_refused():
    data = _rotor_on_bearings(1e6, 1e6, 0.1, 0.1)
    data["gravity"] = [0.0, 0.0, -9.81]
    for bearing in data["bearings"]:
        bearing.pop("stiffness")
        bearing.update(type="journal", diameter=0.05, length=0.02, clearance=0.0, viscosity=0.02)
    with pytest.raises(ModelError, match=r"\[bearings.A\] clearance = 0.0: expected a finite number > 0"):
        rdm.Model.from_dict(data)


def test_a_rotors_bearing_forces_add_up_to_what_its_inertia_and_unbalance_leave(examples_dir):
    """Newton for rotor j: the forces its bearings pass to the stator, moved to its centre of mass,
    equal F_unbalance - M_j a - Omega G_j v (seed 000 eq. 73/74 with the rotor's own motion) in
    every component but the torque about the spin axis, which the drive carries."""
    from rotordyn_modal.model.geometry import shift_matrix

    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(500, 8000, 16)))
    names = list(result.bearing_names)
    for j, rotor in enumerate(model.rotors):
        total = np.zeros_like(result.bearing_forces[j])
        for bearing in model.bearings_of(rotor.name):
            shift = shift_matrix(rotor.center_of_mass, bearing.position)        # B_{R P}: P -> R
            total += np.einsum("ij,jsn->isn", shift, result.bearing_point_forces[names.index(bearing.name)])
        carried = [0, 1, 2, 4, 5]                  # all but M_x: the spin axis is x
        scale = np.abs(result.bearing_forces[j]).max()
        assert np.max(np.abs(total - result.bearing_forces[j])[carried]) <= 1e-9 * scale
        assert np.max(np.abs(total[3])) <= 1e-12 * scale


# -- stiffness that cannot hold a rotor, in any spelling ----------------------------------------
NEGATIVE_DEFINITE = [[-1e6, 0.0], [0.0, -2e6]]


@pytest.mark.parametrize("key, value", [
    ("stiffness", NEGATIVE_DEFINITE),                       # -1e6 as a scalar is refused too
    ("stiffness", [[1e6, 3e6], [3e6, 1e6]]),                # symmetric part's eigenvalues 4e6, -2e6
    ("damping", [[-10.0, 0.0], [0.0, 5.0]]),
    ("moment_stiffness", [[-1e3, 0.0], [0.0, -1e3]])])
def test_a_bearing_matrix_whose_symmetric_part_is_not_semidefinite_is_refused(key, value):
    """A 2x2 matrix stores energy through its symmetric part: a negative eigenvalue there is the
    negative stiffness (or damping) a scalar or 2-list is refused for."""
    data = _rotor_on_bearings(1e6, 1e6, 0.1, 0.1)
    data["bearings"][0][key] = value
    with pytest.raises(ModelError, match=rf"\[bearings.A\] {key} = .*: expected a matrix whose symmetric "
                                         r"part is positive semidefinite \(its lowest eigenvalue is -"):
        rdm.Model.from_dict(data)


def test_cross_coupled_bearing_and_suspension_matrices_stay_legal(examples_dir):
    """An antisymmetric (cross-coupled) part is what makes oil films and seals destabilising: legal."""
    data = _rotor_on_bearings([[1e6, 4e6], [-4e6, 1e6]], 1e6, 0.1, 0.1)
    data["bearings"][1]["stiffness"] = [[0.0, 1e6], [-1e6, 0.0]]          # purely circulatory
    assert rdm.Model.from_dict(data).bearings[0].coefficients.stiffness[0][1, 2] != 0
    assert rdm.load_model(examples_dir / "unstable_cross_coupled.toml").suspensions


def test_a_suspension_matrix_whose_symmetric_part_is_not_semidefinite_is_refused(examples_dir):
    import tomllib

    data = tomllib.loads((examples_dir / "unstable_cross_coupled.toml").read_text())
    data["suspensions"][0]["stiffness"][3][3] = -500.0
    with pytest.raises(ModelError, match=r"\[suspensions.bearing-A\] stiffness = .*symmetric part is "
                                         r"positive semidefinite \(its lowest eigenvalue is -500"):
        rdm.Model.from_dict(data)


@pytest.mark.parametrize("change, key, motion", [
    (lambda d: (d["bearings"].pop(), d["bearings"][0].update(moment_stiffness=0.0)),
     "moment_stiffness", "its tilt about the [yz] axis"),
    (lambda d: (d["bearings"].pop(), d["bearings"][0].update(moment_stiffness=[0.0, 50.0])),
     "moment_stiffness", "its tilt about the y axis"),
    (lambda d: [b.update(stiffness=0.0) for b in d["bearings"]], "stiffness", "its translation along the [yz] axis"),
    (lambda d: [b.update(stiffness=[1e6, 0.0]) for b in d["bearings"]], "stiffness",
     "its translation along the z axis"),
    (lambda d: d["bearings"][0].update(axial_stiffness=0.0), "axial_stiffness", "its translation along the x axis"),
    (lambda d: [b.update(speeds_rpm=[0.0, 3000.0], stiffness=[1e6, 0.0]) for b in d["bearings"]],
     "stiffness", r"its translation along the [yz] axis at speeds_rpm\[1\]")])
def test_a_rotor_its_bearings_leave_free_in_one_motion_is_refused(change, key, motion):
    """A rotor on bearings has coordinates of its own (two translations, two tilts, axial with
    axial_stiffness): its bearings together must hold each of them. One bearing with
    moment_stiffness = 0 leaves it free to tilt (the model once loaded, with zero eigenvalues)."""
    data = _rotor_on_bearings(1e6, 1e6, 0.1, 0.1)
    change(data)
    with pytest.raises(ModelError, match=rf"\[bearings.A\] {key} = .*: expected bearings that together hold "
                                         rf"rotor 'r' in each of its motions: nothing holds {motion}"):
        rdm.Model.from_dict(data)


def test_a_rotor_held_by_a_single_bearing_with_a_tilt_stiffness_or_by_two_points_is_legal():
    data = _rotor_on_bearings(1e6, 1e6, 0.1, 0.1)
    assert rdm.Model.from_dict(data).dofs.n == 4
    data["bearings"].pop()
    data["bearings"][0]["moment_stiffness"] = [20.0, 50.0]
    data["bearings"][0]["axial_stiffness"] = 1e5
    assert rdm.Model.from_dict(data).dofs.n == 5


@pytest.mark.parametrize("length", [0.1 * (1 + 1e-9), 0.25, 2.5])
def test_a_journal_bearing_far_longer_than_short_bearing_theory_allows_is_refused(examples_dir, length):
    """L/D = 5 or 50: the film's coefficients come from short-bearing (Ocvirk) theory, close to
    measurements up to L/D = 1 (DuBois and Ocvirk 1953): refused beyond L/D = 2."""
    import tomllib

    data = tomllib.loads((examples_dir / "journal_rotor.toml").read_text())
    data["bearings"][1]["length"] = length                  # diameter 0.05 m
    with pytest.raises(ModelError, match=rf"\[bearings.NDE\] length = {length!r}: expected a bearing length at "
                                         r"most 2 x its diameter 0.05 m \(L/D = .*short-bearing \(Ocvirk\)"):
        rdm.Model.from_dict(data)
    data["bearings"][1]["length"] = 0.1                     # L/D = 2: legal
    assert rdm.Model.from_dict(data).bearings[1].coefficients.journal.length == 0.1


def test_an_analysis_where_a_journal_runs_above_eccentricity_09_warns_once_per_bearing(examples_dir):
    """journal_rotor at 20 rpm: eccentricity 0.92 (thinnest film 4 um of a 50 um clearance), legal
    but rough: one warning per bearing, not one per call; at 500 rpm (eccentricity 0.63) none."""
    import tomllib
    import warnings

    data = tomllib.loads((examples_dir / "journal_rotor.toml").read_text())
    model = rdm.Model.from_dict(data, source="eccentric-journal.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rdm.modal(model, rdm.rpm(500.0))
        assert caught == []
        rdm.modal(model, rdm.rpm(20.0))
        rdm.modal(model, rdm.rpm(15.0))
    lines = [str(w.message) for w in caught if issubclass(w.category, rdm.errors.ModelWarning)]
    assert len(lines) == 2 and all("eccentricity 0.9" in line and "above 0.9" in line for line in lines)
    assert "[bearings.DE]" in lines[0] and "[bearings.NDE]" in lines[1]
