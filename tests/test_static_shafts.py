"""Sag, shear force and bending moment along flexible shafts (``StaticResult.shafts``) against the
closed forms of beams written out here: a uniform shaft on two supports under its weight and
under a central disk (Euler-Bernoulli and Timoshenko), an overhung disk, a shaft on three
supports (statically indeterminate), and the equilibrium of every node of a shaft on a moving
casing; the command line's summary, CSV rows, US units and figure.

Why the tolerances are tight: cubic (Timoshenko: Nelson's) shaft elements solve the homogeneous
beam equation exactly, so with consistent loads (the element's weight through its mass matrix)
the nodal displacements and the element end forces ``K_e q_e - f_e`` are the exact solution at
the nodes whatever the mesh; what is left is round-off, amplified by the ratio of the bearing
stiffness (1e12 N/m) to the shaft's (~1e6 N/m): about 1e-16 * 1e6 = 1e-10 relative. The
supports' own deflection ``R / k`` is part of the closed forms below (the chord through the
supports, the springs of the indeterminate beam), not a tolerance."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.elements.shaft import shear_coefficient
from rotordyn_modal.units import unit_size

G = 9.81
E, RHO, NU = 2.11e11, 7810.0, 0.3
K_BEARING = 1e12
#: relative round-off of the solution (see the module docstring)
TIGHT = 1e-9


def _shaft(length, supports, disks=(), d=0.05, inner=0.0, shear="none", n=8, axis=(1.0, 0.0, 0.0),
           gravity=(0.0, 0.0, -G), forces_at=(), casing=False):
    """A uniform steel shaft of ``length`` from the origin along ``axis`` on bearings of
    :data:`K_BEARING` at ``supports`` (distances from its start), with disks ``(z, mass)``."""
    data = {
        "spin_axis": list(axis), "gravity": list(gravity),
        "materials": [{"name": "steel", "density": RHO, "young_modulus": E, "poisson_ratio": NU}],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "shear": shear,
                    "element_length": length / n,
                    "shaft": [{"length": length, "outer_diameter": d, "inner_diameter": inner, "material": "steel"}],
                    "disks": [{"name": f"d{i}", "axial_position": z, "mass": m, "polar_inertia": 1e-3,
                               "diametral_inertia": 1e-3} for i, (z, m) in enumerate(disks)]}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "stiffness": K_BEARING}
                     for i, z in enumerate(supports)],
        "sensors": [{"name": f"at{i}", "rotor": "s", "axial_position": z, "direction": [0.0, 0.0, 1.0]}
                    for i, z in enumerate(forces_at)],      # a node at each given load
    }
    if casing:
        data["stator"] = {"mass": 80.0, "inertia": [3.0, 4.0, 5.0], "center_of_mass": [0.2, 0.05, -0.1]}
        data["suspensions"] = [{"name": f"m{i}", "position": [x, y, -0.2], "stiffness": [2e5, 3e5, 4e5]}
                               for i, (x, y) in enumerate(((0.6, 0.3), (0.6, -0.3), (-0.2, 0.3), (-0.2, -0.3)))]
    return rdm.Model.from_dict(data)


def _section(d=0.05, inner=0.0):
    area, second = np.pi / 4 * (d**2 - inner**2), np.pi / 64 * (d**4 - inner**4)
    return area, second, RHO * area * G


def _at(shaft, z, side=""):
    """Index of the station at ``z`` [m] from the start (on ``side`` where the node has two)."""
    hits = np.flatnonzero(np.isclose(shaft.z, z, atol=1e-9, rtol=0) & (shaft.side == side))
    assert hits.size == 1, (z, side, shaft.side[np.isclose(shaft.z, z)])
    return int(hits[0])


def _bearing_forces(result):
    return np.array([r.force for r in result.reactions if r.kind == "bearing"])


# -- a shaft on two supports ------------------------------------------------------------------------
@pytest.mark.parametrize("shear", ["none", "cowper"])
def test_a_shaft_on_two_supports_under_its_weight(shear):
    """Uniform load w = rho A g over L: reactions wL/2, shear w (L/2 - z), moment w z (L - z) / 2
    at every node, mid-span sag 5 w L^4 / (384 E I) (+ w L^2 / (8 kappa G A) with shear
    deformation) below the chord through the supports, stress M (d/2) / I."""
    length, d = 0.8, 0.05
    area, second, w = _section(d)
    result = rdm.static(_shaft(length, (0.0, length), d=d, shear=shear))
    shaft = result.shafts["s"]
    np.testing.assert_allclose(_bearing_forces(result)[:, 2], w * length / 2, rtol=TIGHT)
    z = shaft.z
    np.testing.assert_allclose(shaft.shear[:, 1], w * (length / 2 - z), rtol=0, atol=TIGHT * w * length)
    np.testing.assert_allclose(shaft.moment[:, 1], w * z * (length - z) / 2, rtol=0, atol=TIGHT * w * length**2)
    np.testing.assert_allclose(shaft.shear[:, 0], 0.0, atol=TIGHT * w * length)
    mid = _at(shaft, length / 2)
    chord = 0.5 * (shaft.sag[0, 1] + shaft.sag[-1, 1])        # the supports' own R / k
    exact = 5 * w * length**4 / (384 * E * second)
    if shear != "none":
        exact += w * length**2 / (8 * shear_coefficient(d, 0.0, NU, shear) * E / (2 * (1 + NU)) * area)
    assert shaft.sag[mid, 1] - chord == pytest.approx(-exact, rel=TIGHT)
    np.testing.assert_allclose(shaft.sag_absolute, shaft.sag, rtol=0, atol=0)      # on the ground
    assert shaft.stress[mid] == pytest.approx(w * length**2 / 8 * (d / 2) / second, rel=TIGHT)
    assert set(shaft.side) == {""}            # no point load between the ends: one station per node


def test_a_central_disk_makes_the_shear_force_jump_by_its_weight():
    """Disk P at mid-span of a hollow shaft: sag P L^3 / (48 E I) + 5 w L^4 / (384 E I), moment
    P L / 4 + w L^2 / 8, shear (P + w L) / 2 at the supports and +-P / 2 either side of the disk,
    whose node has a left and a right station; stress M (d/2) / I of the tube."""
    length, d, inner, mass = 1.0, 0.06, 0.03, 25.0
    area, second, w = _section(d, inner)
    P = mass * G
    result = rdm.static(_shaft(length, (0.0, length), disks=[(length / 2, mass)], d=d, inner=inner))
    shaft = result.shafts["s"]
    np.testing.assert_allclose(_bearing_forces(result)[:, 2], (P + w * length) / 2, rtol=TIGHT)
    left, right = _at(shaft, length / 2, "left"), _at(shaft, length / 2, "right")
    scale = P + w * length
    assert shaft.shear[left, 1] == pytest.approx(P / 2, abs=TIGHT * scale)
    assert shaft.shear[right, 1] == pytest.approx(-P / 2, abs=TIGHT * scale)
    assert shaft.shear[0, 1] == pytest.approx(scale / 2, rel=TIGHT)
    assert shaft.shear[-1, 1] == pytest.approx(-scale / 2, rel=TIGHT)
    moment = P * length / 4 + w * length**2 / 8
    for i in (left, right):
        assert shaft.moment[i, 1] == pytest.approx(moment, rel=TIGHT)
        assert shaft.stress[i] == pytest.approx(moment * (d / 2) / second, rel=TIGHT)
    chord = 0.5 * (shaft.sag[0, 1] + shaft.sag[-1, 1])
    exact = P * length**3 / (48 * E * second) + 5 * w * length**4 / (384 * E * second)
    assert shaft.sag[left, 1] - chord == pytest.approx(-exact, rel=TIGHT)
    assert shaft.disks == (("d0", 0.5, mass),)
    # the moment is continuous across the disk, the shear force is not: how the station is named
    assert (shaft.label(left, "moment"), shaft.label(left, "shear"), shaft.label(right)) == ("n4", "n4 left", "n4 right")


def test_an_overhung_disk():
    """Supports at 0 and L, a disk P at the tip of an overhang a, the shaft's weight w over
    L + a: reactions by the lever rule, moment -(P a + w a^2 / 2) over the second support
    (hogging), zero at both ends, shear +P just before the tip, tip sag
    P a^2 (L + a) / (3 E I) + w a (4 a^2 L - L^3 + 3 a^3) / (24 E I) (Roark) below the chord."""
    span, a, mass = 0.6, 0.25, 12.0
    length = span + a
    _, second, w = _section()
    P = mass * G
    result = rdm.static(_shaft(length, (0.0, span), disks=[(length, mass)], n=10))
    shaft = result.shafts["s"]
    far = (P * length + w * length**2 / 2) / span
    np.testing.assert_allclose(_bearing_forces(result)[:, 2], [P + w * length - far, far], rtol=TIGHT)
    scale = P * a + w * a**2
    for side in ("left", "right"):
        assert shaft.moment[_at(shaft, span, side), 1] == pytest.approx(-(P * a + w * a**2 / 2), rel=TIGHT)
    assert shaft.moment[0, 1] == pytest.approx(0.0, abs=TIGHT * scale)
    assert shaft.moment[-1, 1] == pytest.approx(0.0, abs=TIGHT * scale)
    assert shaft.shear[-1, 1] == pytest.approx(P, rel=TIGHT)
    supports = shaft.sag[[0, _at(shaft, span, "left")], 1]
    chord = supports[0] + (supports[1] - supports[0]) * length / span
    tip = P * a**2 * length / (3 * E * second) + w * a * (4 * a**2 * span - span**3 + 3 * a**3) / (24 * E * second)
    assert shaft.sag[-1, 1] - chord == pytest.approx(-tip, rel=TIGHT)


def test_three_supports_share_the_weight_as_the_continuous_beam():
    """Two equal spans l on three springs k (statically indeterminate): the middle reaction
    R2 = (w l / k + 5 w l^4 / (24 E I)) / (3 / (2 k) + l^3 / (6 E I)) (compatibility of the
    middle support's settlement), which is 10/8 w l on rigid supports; the outer ones
    (2 w l - R2) / 2 (3/8 w l), the moment over the middle support R1 l - w l^2 / 2 (-w l^2 / 8)."""
    span = 0.5
    _, second, w = _section()
    result = rdm.static(_shaft(2 * span, (0.0, span, 2 * span)))
    k = K_BEARING
    middle = (w * span / k + 5 * w * span**4 / (24 * E * second)) / (3 / (2 * k) + span**3 / (6 * E * second))
    outer = (2 * w * span - middle) / 2
    np.testing.assert_allclose(_bearing_forces(result)[:, 2], [outer, middle, outer], rtol=TIGHT)
    # the rigid supports' split, within the springs' compliance relative to the shaft's (~2e-5)
    np.testing.assert_allclose(_bearing_forces(result)[:, 2], np.array([3, 10, 3]) / 8 * w * span, rtol=1e-4)
    shaft = result.shafts["s"]
    assert shaft.moment[_at(shaft, span, "left"), 1] == pytest.approx(outer * span - w * span**2 / 2, rel=TIGHT)
    assert shaft.moment[_at(shaft, span, "left"), 1] == pytest.approx(-w * span**2 / 8, rel=1e-4)


# -- equilibrium on a moving casing, an inclined axis ---------------------------------------------
def test_every_node_balances_its_point_loads_on_a_casing_with_an_inclined_axis():
    """A shaft along an inclined axis, on bearings in a casing on mounts, with a disk and a given
    force between the bearings: at every node the shear force (both planes) jumps by the point
    load there (a bearing's reaction, a disk's weight, the given force) and the bending moment
    is continuous; the absolute sag is the relative one plus the casing's motion there; the
    rotor's loads and reactions balance."""
    axis = np.array([1.0, 0.3, 0.2]) / np.linalg.norm([1.0, 0.3, 0.2])
    length, mass, force = 0.9, 8.0, np.array([30.0, -50.0, 80.0])
    model = _shaft(length, (0.1, 0.7), disks=[(0.85, mass)], axis=axis, forces_at=(0.4,), casing=True)
    point = 0.4 * axis
    result = rdm.static(model, forces=[("s", point, force)])
    shaft = result.shafts["s"]
    a, b, _ = shaft.axes
    assert shaft.axis_names == ("a", "b", "e")
    bearings = {round(float(r.point @ axis), 9): r.force for r in result.reactions if r.kind == "bearing"}
    point_loads = {**bearings, 0.85: mass * np.asarray(model.gravity), 0.4: force}
    scale = np.linalg.norm(force) + mass * G + 50.0
    for z, load in point_loads.items():
        left, right = _at(shaft, z, "left"), _at(shaft, z, "right")
        np.testing.assert_allclose(shaft.shear[right] - shaft.shear[left], [load @ a, load @ b],
                                   atol=1e-9 * scale)
        np.testing.assert_allclose(shaft.moment[right], shaft.moment[left], atol=1e-9 * scale)
    stator = np.array([result.stator_motion(p)[:3] for p in shaft.point])
    np.testing.assert_allclose(shaft.sag_absolute - shaft.sag, np.c_[stator @ a, stator @ b], rtol=0,
                               atol=1e-12 * np.abs(shaft.sag_absolute).max())
    np.testing.assert_allclose(shaft.moment[[0, -1]], 0.0, atol=1e-9 * scale)     # free ends
    np.testing.assert_allclose(shaft.shear[0], 0.0, atol=1e-9 * scale)
    force_sum, moment_sum, total = result.imbalance("s")
    assert np.abs(force_sum).max() < 1e-11 * total and np.abs(moment_sum).max() < 1e-11 * total


def test_a_layered_section_carries_its_moment_by_the_stiffnesses_of_its_tubes():
    """A steel core (d = 0.04) with an aluminium sleeve (0.04 to 0.06) under a central force P on
    two supports, weightless: moment P L / 4 at mid-span however the section is made (statics),
    sag P L^3 / (48 sum E I), and the largest stress that of the steel core's outer fibre,
    E_steel (0.04 / 2) M / sum E I (plane sections; the sleeve's outer fibre, E_al 0.03 M / sum E I,
    carries about half of it)."""
    length, P, e_al = 1.0, 1000.0, 7.0e10
    model = rdm.Model.from_dict({
        "materials": [{"name": "steel", "density": RHO, "young_modulus": E, "poisson_ratio": NU},
                      {"name": "aluminium", "density": 2700.0, "young_modulus": e_al, "poisson_ratio": 0.33}],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "shear": "none", "element_length": 0.125,
                    "shaft": [{"length": length, "outer_diameter": 0.04, "material": "steel",
                               "layers": [{"outer_diameter": 0.06, "inner_diameter": 0.04, "material": "aluminium"}]}]}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "stiffness": K_BEARING}
                     for i, z in enumerate((0.0, length))]})
    result = rdm.static(model, forces=[("s", [0.5, 0.0, 0.0], [0.0, 0.0, -P])])
    shaft = result.shafts["s"]
    rigidity = E * np.pi / 64 * 0.04**4 + e_al * np.pi / 64 * (0.06**4 - 0.04**4)
    mid = _at(shaft, 0.5, "left")
    assert shaft.moment[mid, 1] == pytest.approx(P * length / 4, rel=TIGHT)
    chord = 0.5 * (shaft.sag[0, 1] + shaft.sag[-1, 1])
    assert shaft.sag[mid, 1] - chord == pytest.approx(-P * length**3 / (48 * rigidity), rel=TIGHT)
    assert E * 0.02 > 2 * e_al * 0.03
    assert shaft.stress[mid] == pytest.approx(E * 0.02 * P * length / 4 / rigidity, rel=TIGHT)
    assert shaft.outer_diameter[mid] == 0.06


def _belt_to_a_shaft(position=None):
    """A rigid motor (its centre at x = 1.5 m) pulling a flexible shaft (x from 0 to 1 m, bearings
    at 0.1 and 0.7 m, a pulley disk at 0.9 m) up with a belt's pretension, without gravity."""
    return rdm.Model.from_dict(_belt_data(position))


def _belt_data(position=None) -> dict:
    """The model file of :func:`_belt_to_a_shaft` as a dict."""
    belt = {"type": "belt", "driver": "motor", "driven": "s", "ratio": 1.0, "pretension": 400.0}
    if position is not None:
        belt["position"] = position
    return {
        "reference_rotor": "motor",
        "materials": [{"name": "steel", "density": RHO, "young_modulus": E, "poisson_ratio": NU}],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "shear": "none", "element_length": 0.1,
                    "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}],
                    "disks": [{"name": "pulley", "axial_position": 0.9, "mass": 2.0, "polar_inertia": 1e-3,
                               "diametral_inertia": 1e-3}]},
                   {"name": "motor", "mass": 10.0, "center_of_mass": [1.5, 0.0, 0.3], "polar_inertia": 0.02,
                    "diametral_inertia": 0.1, "speed_ratio": 1.0}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "stiffness": K_BEARING}
                     for i, z in enumerate((0.1, 0.7))] +
                    [{"name": f"m{i}", "rotor": "motor", "position": [x, 0.0, 0.3], "stiffness": K_BEARING}
                     for i, x in enumerate((1.4, 1.6))],
        "transmissions": [belt]}


def test_a_belt_on_a_flexible_shaft_pulls_at_its_pulley():
    """A belt whose plane is given at the pulley pulls the shaft there with twice its pretension
    along the line of centres (+z, towards the motor): the shear force in the plane of u_z jumps
    by that pull at the pulley, and the overhang bent up by it carries M = +P a over the outer
    bearing (the mirror of an overhung weight's -P a). Without a position the belt's plane is the
    motor's centre, off the shaft's end: a warning (the pull then acts at the end node)."""
    pull, overhang = 800.0, 0.2
    result = rdm.static(_belt_to_a_shaft(position=[0.9, 0.0, 0.0]))
    shaft = result.shafts["s"]
    left, right = _at(shaft, 0.9, "left"), _at(shaft, 0.9, "right")
    assert shaft.shear[right, 1] - shaft.shear[left, 1] == pytest.approx(pull, rel=TIGHT)
    assert shaft.moment[_at(shaft, 0.7, "right"), 1] == pytest.approx(pull * overhang, rel=TIGHT)
    assert [kind for kind, _, _ in shaft.loads] == ["belt"]
    with pytest.warns(rdm.errors.ModelWarning, match=r"transmissions.motor->s\] acts at \[1.5, 0, 0\] m, off rotor s"):
        rdm.static(_belt_to_a_shaft())


@pytest.mark.parametrize("units, unit, size", [("si", "m", 1.0), ("us", "in", 0.0254)])
def test_static_warns_and_refuses_off_the_shaft_in_the_unit_system(units, unit, size, tmp_path, capsys):
    """``--units us static``: the off-shaft belt's warning and a given force's refusal give the
    points and the shaft's ends in inches (1 in = 0.0254 m exactly), as the --force typed in."""
    import tomli_w

    from rotordyn_modal.cli import main

    path = tmp_path / "belt.toml"
    path.write_text(tomli_w.dumps(_belt_data()), encoding="utf-8")
    shown = (lambda metres: f"{metres / size:.6g}")
    ends = f"from [0, 0, 0] to [{shown(1.0)}, 0, 0] {unit}"
    assert main(["--units", units, "static", str(path), "--quiet"]) == 0
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert f"acts at [{shown(1.5)}, 0, 0] {unit}, off rotor s's shaft, {ends} (a load" in line
    force = f"s:{shown(1.2)},0,0:0,0,-10"
    assert main(["--units", units, "static", str(path), "--quiet", "--force", force]) == 2
    err = capsys.readouterr().err
    point = f"[{shown(1.2)}, 0, 0]" + ("" if units == "si" else " in")
    assert f"--force {force}: point = {point}: expected a point along rotor s's shaft, {ends} (a load" in err


def test_a_given_force_beyond_a_flexible_shaft_is_refused():
    model = _shaft(1.0, (0.0, 1.0))
    with pytest.raises(rdm.InputError, match=r"forces\[0\] point = \[1.2, 0, 0\]: expected a point along rotor s's shaft"):
        rdm.static(model, forces=[("s", [1.2, 0.0, 0.0], [0.0, 0.0, -10.0])])
    rdm.static(model, forces=[("s", [1.0, 0.3, 0.0], [0.0, 0.0, -10.0])])     # off the axis, on a lever: fine


def test_rigid_rotors_have_no_shafts_and_the_csv_keeps_its_columns(examples_dir):
    result = rdm.static(rdm.load_model(examples_dir / "motor_pump_on_mounts.toml"))
    assert result.shafts == {} and result.shafts_table() is None
    assert list(result.to_dataframe().columns) == [
        "table", "kind", "name", "body", "x_m", "y_m", "z_m", "Fx_N", "Fy_N", "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm",
        "ux_m", "uy_m", "uz_m", "rx_rad", "ry_rad", "rz_rad", "on", "eccentricity", "attitude_deg"]


@pytest.mark.parametrize("axis", [(1.0, 0.0, 0.0), (0.0, 0.6, 0.8)])
def test_a_force_at_an_axial_position_is_shared_by_the_lever_rule(axis):
    """A force F at axial_position z of a shaft on supports at 0 and L: the supports carry
    F (L - z) / L and F z / L (statics, no weight); the same as the force at the 3-D point
    start + z * axis of that station (session 46: the 3-D point was the only way to say it)."""
    length, z, force = 1.0, 0.3, np.array([0.0, 0.0, -100.0])
    if axis[2]:
        force = np.array([0.0, -80.0, 60.0])          # across the inclined axis
    model = _shaft(length, (0.0, length), axis=axis, gravity=(0.0, 0.0, 0.0), forces_at=(z,))
    by_station = rdm.static(model, forces=[{"body": "s", "axial_position": z, "force": force}])
    shares = np.array([(length - z) / length, z / length])
    np.testing.assert_allclose(_bearing_forces(by_station), -shares[:, None] * force, rtol=1e-9, atol=1e-9)
    by_point = rdm.static(model, forces=[("s", z * np.array(axis), force)])
    np.testing.assert_allclose(by_station.coordinates, by_point.coordinates, rtol=1e-12, atol=1e-20)


@pytest.mark.parametrize("item, message", [
    ({"body": "s", "axial_position": 1.2, "force": [0, 0, 1]},
     r"forces\[0\] axial_position = 1.2 m: expected a position along rotor s's shaft, from 0 \(its start\) to 1 m"),
    ({"body": "s", "axial_position": float("nan"), "force": [0, 0, 1]}, r"forces\[0\] axial_position = nan"),
    ({"body": "s", "axial_position": "0.3", "force": [0, 0, 1]}, r"forces\[0\] axial_position = '0.3'"),
    ({"body": "s", "axial_position": 0.3, "point": [0.3, 0, 0], "force": [0, 0, 1]},
     r"forces\[0\]: either point or axial_position, not both"),
])
def test_a_bad_axial_position_is_refused_by_name(item, message):
    with pytest.raises(rdm.InputError, match=message):
        rdm.static(_shaft(1.0, (0.0, 1.0)), forces=[item])


def test_axial_position_on_a_rigid_rotor_is_refused(examples_dir):
    model = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")
    with pytest.raises(rdm.InputError, match=r"forces\[0\] axial_position: expected no value: .* rotor motor has none"):
        rdm.static(model, forces=[{"body": "motor", "axial_position": 0.1, "force": [0, 0, 1]}])


def test_static_command_takes_a_force_at_a_station(tmp_path, examples_dir, capsys):
    """``--force pump@0.03:...`` is the force at the impeller's station, 0.03 m from the shaft's
    start [-0.5, -0.12, 0.22] along +x: the same tables as the 3-D point form; in US units
    AXIAL is in inches; a bad AXIAL is refused with exit code 2."""
    model = examples_dir / "flexible_pump_on_mounts.toml"
    station, point = tmp_path / "station.csv", tmp_path / "point.csv"
    assert main(["static", str(model), "--force", "pump@0.03:0,0,-200", "--out", str(station), "--quiet"]) == 0
    assert main(["static", str(model), "--force", "pump:-0.47,-0.12,0.22:0,0,-200", "--out", str(point),
                 "--quiet"]) == 0
    a, b = pd.read_csv(station), pd.read_csv(point)
    numbers = a.select_dtypes("number").columns
    np.testing.assert_allclose(a[numbers].to_numpy(float), b[numbers].to_numpy(float), rtol=1e-9, atol=1e-15)
    us = tmp_path / "us.csv"
    inch, pound_force = unit_size("length", "us"), unit_size("force", "us")
    axial, load = 0.03 / inch, 200.0 / pound_force
    assert main(["--units", "us", "static", str(model), "--force", f"pump@{axial!r}:0,0,-{load!r}", "--out", str(us),
                 "--quiet"]) == 0
    c = pd.read_csv(us)
    np.testing.assert_allclose(c["uz_in"].to_numpy(float) * inch, a["uz_m"].to_numpy(float), rtol=1e-9, atol=1e-15)
    capsys.readouterr()
    for typed, said in (("pump@0.6:0,0,-200", "axial_position = 0.6 m: expected a position along rotor pump's shaft, "
                                              "from 0 (its start) to 0.45 m"),
                        ("pump@x:0,0,-200", "AXIAL 'x': expected a number [m] from the shaft's start"),
                        ("motor@0.1:0,0,1", "axial_position: expected no value")):
        assert main(["static", str(model), "--force", typed, "--quiet"]) == 2
        assert said in capsys.readouterr().err


def test_a_moment_at_a_station_bends_the_shaft_as_the_closed_form():
    """A moment M (about z, in the x-y plane) at axial_position a of a shaft on supports at 0 and
    L: the supports carry +M/L and -M/L along y (statics); the bending moment jumps by M at the
    station (M a / L on one side, M (a / L - 1) on the other, up to the sign convention). Without
    a station the moment acts at the centre of mass, with one warning line."""
    length, a, M = 1.0, 0.3, 40.0
    model = _shaft(length, (0.0, length), gravity=(0.0, 0.0, 0.0), forces_at=(a,))
    result = rdm.static(model, forces=[{"body": "s", "axial_position": a, "moment": [0.0, 0.0, M]}])
    # about the first support: R_1 L (x^ cross y^ = z^) + M = 0, and R_0 + R_1 = 0
    np.testing.assert_allclose(_bearing_forces(result)[:, 1], [M / length, -M / length], rtol=1e-9)
    shaft = result.shafts["s"]
    left, right = shaft.moment[_at(shaft, a, "left")], shaft.moment[_at(shaft, a, "right")]
    np.testing.assert_allclose(sorted(np.abs([left[0], right[0]])), sorted([M * a / length, M * (1 - a / length)]),
                               rtol=1e-9)
    with pytest.warns(rdm.errors.ModelWarning, match=r"forces\[0\]: a moment on the flexible rotor s without its "
                                                     r"station acts at its centre of mass, 0.5 m from the shaft's start"):
        rdm.static(model, forces=[{"body": "s", "moment": [0.0, 0.0, M]}])


def test_static_command_takes_a_moment_at_a_station(tmp_path, examples_dir, capsys):
    """``--moment pump@0.03:0,50,0`` equals the moment at the 3-D point of that station; without
    the station the warning names the option as typed."""
    model = examples_dir / "flexible_pump_on_mounts.toml"
    station = tmp_path / "station.csv"
    assert main(["static", str(model), "--moment", "pump@0.03:0,50,0", "--out", str(station), "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    at_point = rdm.static(rdm.load_model(model), forces=[{"body": "pump", "point": [-0.47, -0.12, 0.22],
                                                            "moment": [0.0, 50.0, 0.0]}])
    rows = pd.read_csv(station)
    shaft_rows = rows[rows["table"] == "shaft"]
    np.testing.assert_allclose(shaft_rows["Mbz_Nm"], at_point.shafts["pump"].moment[:, 1], rtol=1e-9, atol=1e-9)
    assert main(["static", str(model), "--moment", "pump:0,50,0", "--quiet"]) == 0
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("rotordyn-modal static: warning: --moment pump:0,50,0: a moment on the flexible rotor pump")
    assert main(["static", str(model), "--moment", "pump@x:0,50,0", "--quiet"]) == 2
    assert "AXIAL 'x': expected a number [m] from the shaft's start" in capsys.readouterr().err


def test_a_rotor_named_with_an_at_sign_takes_a_moment_as_a_whole(tmp_path, examples_dir, capsys):
    """``--moment motor@1:0,5,0`` where the rotor is called 'motor@1' is a moment on that rotor, not
    one at a station 1 m along a rotor 'motor' (none): the same as the Python call."""
    import tomllib

    import tomli_w

    data = tomllib.loads((examples_dir / "motor_pump_on_mounts.toml").read_text())
    renamed = tomli_w.dumps(data).replace('"motor"', '"motor@1"')
    path = tmp_path / "at.toml"
    path.write_text(renamed, encoding="utf-8")
    out = tmp_path / "at.csv"
    assert main(["static", str(path), "--moment", "motor@1:0,5,0", "--out", str(out), "--quiet"]) == 0, \
        capsys.readouterr().err
    expected = rdm.static(rdm.load_model(path), forces=[{"body": "motor@1", "moment": [0.0, 5.0, 0.0]}])
    written = pd.read_csv(out)
    rows = written[written["table"] == "displacement"]
    np.testing.assert_allclose(rows["uz_m"], expected.displacements()["uz_m"], rtol=1e-12, atol=1e-18)


# -- the command line and the figure ----------------------------------------------------------------
def test_static_command_lists_the_shaft_and_writes_its_rows_in_us_units(tmp_path, examples_dir, capsys):
    model = examples_dir / "flexible_pump_on_mounts.toml"
    si, us = tmp_path / "si.csv", tmp_path / "us.csv"
    assert main(["static", str(model), "--out", str(si)]) == 0
    printed = capsys.readouterr().out
    assert "pump: largest sag" in printed and "bending stress" in printed and "MPa" in printed
    assert main(["static", str(model), "--units", "us", "--out", str(us), "--quiet"]) == 0
    a, b = pd.read_csv(si), pd.read_csv(us)
    assert list(a.columns[:22]) == list(rdm.static(rdm.load_model(examples_dir / "motor_pump_on_mounts.toml"))
                                        .to_dataframe().columns)
    shaft = rdm.static(rdm.load_model(model)).shafts["pump"]
    rows_si, rows_us = a[a["table"] == "shaft"], b[b["table"] == "shaft"]
    np.testing.assert_allclose(rows_si["Mby_Nm"], shaft.moment[:, 0], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(rows_si["Vz_N"], shaft.shear[:, 1], rtol=1e-9, atol=1e-12)
    inch, pound_force = unit_size("length", "us"), unit_size("force", "us")
    for si_column, us_column, size in (("uz_m", "uz_in", inch), ("Vz_N", "Vz_lbf", pound_force),
                                       ("Mbz_Nm", "Mbz_lbfin", pound_force * inch),
                                       ("stress_Pa", "stress_psi", pound_force / inch**2),
                                       ("from_start_m", "from_start_in", inch)):
        np.testing.assert_allclose(rows_us[us_column].to_numpy() * size, rows_si[si_column], rtol=1e-9, atol=1e-300)
    assert list(rows_si["name"]) == [f"n{k}" for k in shaft.node]


def test_static_plot_draws_the_stations_and_refuses_a_rigid_model(tmp_path, examples_dir, capsys):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = tmp_path / "shaft.png"
    assert main(["static", str(examples_dir / "flexible_pump_on_mounts.toml"), "--plot", str(out), "--quiet"]) == 0
    assert out.stat().st_size > 10_000
    shaft = rdm.static(rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")).shafts["pump"]
    fig = shaft.plot()
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.get_lines() if line.get_gid()}
    np.testing.assert_allclose(lines["shear-b:pump"].get_ydata(), np.r_[0.0, shaft.shear[:, 1], 0.0])
    np.testing.assert_allclose(lines["moment-a:pump"].get_ydata(), np.r_[0.0, shaft.moment[:, 0], 0.0])
    np.testing.assert_allclose(lines["sag-b:pump"].get_ydata(), shaft.sag[:, 1] * 1e6)
    assert {"bearing:pump:pump-IB", "bearing:pump:pump-OB", "disk:pump:impeller", "disk:pump:pulley"} <= \
        {artist.get_gid() for ax in fig.axes for artist in ax.get_children()}
    plt.close(fig)
    capsys.readouterr()
    rigid = tmp_path / "rigid.png"
    assert main(["static", str(examples_dir / "motor_pump_on_mounts.toml"), "--plot", str(rigid)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "no flexible rotor" in err and not rigid.exists()


def test_static_plot_names_every_bearing_and_disk_clear_of_the_curves(examples_dir):
    """Issue 27: the bearings' names stood under the zero line, where the sag ran through
    'pump-IB' and 'pump-OB'. Measured on the drawn figure (``label_geometry``): each bearing's
    and disk's name is drawn once, straight above its mark, and no curve of any panel crosses it."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    from label_geometry import crossings, curve_segments, glyph_box

    shaft = rdm.static(rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")).shafts["pump"]
    fig = shaft.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_lines()]
    segments = [curve_segments(ax) for ax in panels]
    marks = [(name, x) for name, x in shaft.bearings] + [(name, x) for name, x, _ in shaft.disks]
    for name, x in marks:
        drawn = [t for t in fig.findobj(Text) if t.get_text() == name and t.get_visible()]
        assert len(drawn) == 1, name
        box = glyph_box(drawn[0], renderer)
        assert box.x0 < panels[0].transData.transform((x, 0.0))[0] < box.x1, name
        for found in segments:
            assert len(crossings(box, found)) == 0, f"a curve runs through {name}"
    plt.close(fig)


def test_static_plot_largest_value_notes_hide_no_curve(examples_dir):
    """Issue 27: the note of the largest bending moment (an opaque box) stood on the moment
    line rising from its point and hid it. Measured on the drawn figure: no curve (but the
    disks' pale background bands) runs under a note's box, and the moment's note names the
    largest moment."""
    shaft = rdm.static(rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")).shafts["pump"]
    assert_largest_value_notes_hide_no_curve(shaft)


def test_a_shaft_without_load_says_so_in_the_figure_and_the_summary(examples_dir, capsys):
    """The compressor example has no gravity: every sag, shear force and moment is 0. The figure
    says there is no load (all-zero curves alone read as a shaft that does not bend under its
    loads) and marks no 'largest' value; the terminal says the same instead of 'largest sag 0'."""
    from rotordyn_modal.analysis.static import static
    from rotordyn_modal.cli import main
    from rotordyn_modal.io import load_model

    result = static(load_model(examples_dir / "compressor_rotor.toml"))
    fig = result.plot_shafts()
    texts = [t for ax in fig.axes for t in ax.texts]
    assert [t.get_gid() for t in texts if t.get_gid()] == ["no-load-note"]
    assert "no static load" in texts[0].get_text()
    assert main(["static", str(examples_dir / "compressor_rotor.toml")]) == 0
    out = capsys.readouterr().out
    assert "compressor: no static load on this shaft" in out and "largest sag" not in out


def assert_largest_value_notes_hide_no_curve(shaft):
    """The static shaft figure's two notes of the largest sag and moment (opaque boxes): no curve
    (but the disks' pale background bands) runs under either box, measured on the drawn figure
    (``label_geometry``), and the moment's note names the largest moment."""
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments

    fig = shaft.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    notes = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_text().startswith(("|u|", "|M|"))]
    assert len(notes) == 2
    for ax, note in notes:
        box = note.get_bbox_patch().get_window_extent(renderer)
        bands = [line for line in ax.get_lines() if str(line.get_gid()).startswith("disk:")]
        assert len(crossings(box, curve_segments(ax, skip=bands))) == 0, note.get_text()
    moment = next(t for _, t in notes if t.get_text().startswith("|M|")).get_text()
    assert f"{np.abs(shaft.moment).max():.3g} N m" in moment
    plt.close(fig)
