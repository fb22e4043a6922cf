"""Property tests over random valid machines with a flexible rotor (issue 28: "undamped
gyroscopic models keep purely imaginary eigenvalues; moving the origin changes nothing").

``tests/test_properties.py`` draws rigid rotors only and ``tests/test_flexible_rotors.py`` checks
these invariants on one fixed machine; here hypothesis draws the flexible rotor too: one to three
sections (tapered or not, hollow or not) of a random material and shear option, a disk and a
point mass anywhere on the shaft, two bearings anywhere on it with symmetric positive definite
radial stiffness in their own (random) radial axes, the rotor's speed ratio of either sign, and
either the ground or a casing on four mounts carrying a rigid rotor spinning in it.

Truths from outside the code:

* an undamped gyroscopic system ``M q'' + Omega G q' + K q = 0`` (M, K symmetric positive
  (semi-)definite, G skew-symmetric) has only purely imaginary roots (``x^H (K - w^2 M + i w
  Omega G) x`` is real);
* its spectrum at ``-Omega`` is the same (the transpose of the pencil at ``Omega``);
* the roots are the machine's: describing it from another origin or in turned model axes (every
  point, axis and tensor of the description moved with them) changes none of them.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from threadpoolctl import threadpool_limits

import rotordyn_modal as rdm

SETTINGS = settings(max_examples=8, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])
finite = dict(allow_nan=False, allow_infinity=False)
#: [m] section lengths and stations are whole multiples of it: two marks of the mesh are one node or
#: at least 1 cm apart (stations microns apart would make elements whose stiffness, ~ E I / h^3, swamps
#: the rest in round-off; the mesh merges those closer than 1e-3 of an element: docs/theory.md §16)
GRID = 0.01


@pytest.fixture(autouse=True)
def one_blas_thread():
    """Small dense solves: BLAS threads only wait for a second core on a loaded machine."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


@st.composite
def rotations(draw):
    """A random proper rotation (3, 3), from a quaternion."""
    from scipy.spatial.transform import Rotation

    q = np.array(draw(st.lists(st.floats(-1, 1, **finite), min_size=4, max_size=4)))
    assume(np.linalg.norm(q) > 0.1)
    return Rotation.from_quat(q).as_matrix()


def _radial_axes(e, turn):
    """Two orthonormal rows normal to ``e``, turned by ``turn`` [rad] about it."""
    helper = np.eye(3)[int(np.argmin(np.abs(e)))]
    a = _unit(helper - (helper @ e) * e)
    b = np.cross(e, a)
    return np.array([np.cos(turn) * a + np.sin(turn) * b, -np.sin(turn) * a + np.cos(turn) * b])


@st.composite
def flexible_machines(draw):
    """A random valid, undamped machine with one flexible rotor (see the module docstring)."""
    e = np.array(draw(st.lists(st.floats(-1, 1, **finite), min_size=3, max_size=3)))
    assume(np.linalg.norm(e) > 0.2)
    e = _unit(e)
    poisson = draw(st.floats(0.2, 0.35))
    material = {"name": "metal", "density": draw(st.floats(2500.0, 9000.0)),
                "young_modulus": draw(st.floats(5e10, 3e11)), "poisson_ratio": poisson}
    sections = []
    for _ in range(draw(st.integers(1, 3))):
        outer = [draw(st.floats(0.02, 0.08)), draw(st.floats(0.02, 0.08))]
        section = {"length": GRID * draw(st.integers(8, 40)), "material": "metal",
                   "outer_diameter": outer if draw(st.booleans()) else outer[0]}
        if draw(st.booleans()):
            section["inner_diameter"] = draw(st.floats(0.0, 0.8)) * min(outer if isinstance(section["outer_diameter"],
                                                                                             list) else outer[:1])
        sections.append(section)
    length = sum(s["length"] for s in sections)
    start = np.array(draw(st.lists(st.floats(-0.3, 0.3, **finite), min_size=3, max_size=3)))
    cells = round(length / GRID)
    z = sorted(draw(st.lists(st.integers(0, cells), min_size=2, max_size=2, unique=True)))
    assume(z[1] - z[0] >= cells / 5)
    disk_z, mass_z = draw(st.integers(0, cells)), draw(st.integers(0, cells))
    assume(len({disk_z, mass_z, *z}) == 4)
    diametral = draw(st.floats(0.002, 0.05))
    rotor = {"name": "shaft", "start": start.tolist(), "shear": draw(st.sampled_from(["cowper", "hutchinson", "none"])),
             "element_length": length / draw(st.integers(3, 8)), "shaft": sections,
             "disks": [{"name": "disk", "axial_position": disk_z * GRID, "mass": draw(st.floats(0.5, 20.0)),
                        "diametral_inertia": diametral, "polar_inertia": diametral * draw(st.floats(0.1, 1.9))}],
             "point_masses": [{"axial_position": mass_z * GRID, "mass": draw(st.floats(0.1, 3.0))}]}
    bearings = []
    for i, station in enumerate(z):
        kxx, kyy = draw(st.floats(1e5, 1e8)), draw(st.floats(1e5, 1e8))
        kxy = draw(st.floats(-0.9, 0.9)) * np.sqrt(kxx * kyy)            # symmetric positive definite
        bearings.append({"name": f"b{i}", "rotor": "shaft", "axial_position": station * GRID,
                         "stiffness": [[kxx, kxy], [kxy, kyy]],
                         "axes": _radial_axes(e, draw(st.floats(0.0, np.pi))).tolist()})
    data = {"name": "flexible", "spin_axis": e.tolist(), "materials": [material], "rotors": [rotor],
            "bearings": bearings}
    if draw(st.booleans()):              # in a casing on mounts, with a rigid rotor spinning in it
        data["stator"] = {"mass": draw(st.floats(20.0, 200.0)), "inertia": [2.0, 3.0, 3.5],
                          "center_of_mass": (start + 0.5 * length * e).tolist()}
        data["reference_rotor"] = "motor"          # the shaft then turns at its own ratio
        data["rotors"][0]["speed_ratio"] = draw(st.sampled_from([1.0, -1.0])) * draw(st.floats(0.5, 3.0))
        data["rotors"].append({"name": "motor", "speed_ratio": 1.0, "mass": 3.0,
                               "center_of_mass": (start + [0.2, 0.1, -0.1]).tolist(),
                               "polar_inertia": 0.01, "diametral_inertia": 0.008})
        corners = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
        a, b = _radial_axes(e, 0.0)
        data["suspensions"] = [{"name": f"m{i}", "position": (start + (0.5 + 0.6 * sx) * length * e
                                                              + 0.2 * sy * a - 0.15 * b).tolist(),
                                "stiffness": [draw(st.floats(5e4, 5e6)) for _ in range(3)],
                                "axes": draw(rotations()).tolist()}
                               for i, (sx, sy) in enumerate(corners)]
    return data


def _moved(data, shift=(0.0, 0.0, 0.0), turn=np.eye(3)):
    """The same machine described from another origin (``x -> turn x + shift``): every point,
    direction, axis row and inertia tensor of the description moved with the axes."""
    out = copy.deepcopy(data)
    R, t = np.asarray(turn, dtype=float), np.asarray(shift, dtype=float)
    out["spin_axis"] = (R @ data["spin_axis"]).tolist()
    for rotor in out["rotors"]:
        key = "start" if "shaft" in rotor else "center_of_mass"
        rotor[key] = (R @ rotor[key] + t).tolist()
    for bearing in out["bearings"]:
        bearing["axes"] = (np.asarray(bearing["axes"]) @ R.T).tolist()
    if "stator" in out:
        out["stator"]["center_of_mass"] = (R @ out["stator"]["center_of_mass"] + t).tolist()
        out["stator"]["inertia"] = (R @ np.diag(out["stator"]["inertia"]) @ R.T).tolist()
        for mount in out["suspensions"]:
            mount["position"] = (R @ mount["position"] + t).tolist()
            mount["axes"] = (np.asarray(mount["axes"]) @ R.T).tolist()
    return out


def _roots(model, speed):
    """The roots with Im >= 0 of the model's M q'' + speed G q' + K q = 0 (its assembled
    matrices, one dense eigen-solve of the state matrix), by frequency."""
    M, _, G, K = model.matrices()
    n = len(M)
    state = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -speed * np.linalg.solve(M, G)]])
    roots = np.linalg.eigvals(state)
    roots = roots[roots.imag >= 0]
    return roots[np.argsort(roots.imag)]


speeds = st.floats(-3000.0, 3000.0, **finite).filter(lambda s: abs(s) > 1.0)


@SETTINGS
@given(flexible_machines(), speeds)
def test_undamped_flexible_machines_have_purely_imaginary_roots_at_either_spin(data, speed):
    model = rdm.Model.from_dict(data)
    M, C, G, K = model.matrices()
    assert not C.any() and np.abs(G).max() > 0
    roots = _roots(model, speed)
    assert len(roots) == len(M)
    assert np.all(np.abs(roots.real) <= 1e-9 * np.abs(roots).max()), np.abs(roots.real).max() / np.abs(roots).max()
    np.testing.assert_allclose(_roots(model, -speed).imag, roots.imag, rtol=1e-8, atol=1e-10 * np.abs(roots).max())


@SETTINGS
@given(flexible_machines(), speeds, st.lists(st.floats(-5.0, 5.0, **finite), min_size=3, max_size=3), rotations())
def test_moving_and_turning_the_model_axes_changes_no_root(data, speed, shift, turn):
    roots = _roots(rdm.Model.from_dict(data), speed)
    for moved in (_moved(data, shift=shift), _moved(data, turn=turn)):
        np.testing.assert_allclose(_roots(rdm.Model.from_dict(moved), speed), roots, rtol=1e-8,
                                   atol=1e-10 * np.abs(roots).max())


def _overhung_data(gap, disk=0.15):
    """A shaft of 0.4 m on bearings at 0.1 m and at ``gap`` [m] before its end, a disk at ``disk`` [m]
    (six elements of 0.4 / 6 m: :data:`ELEMENT`)."""
    steel = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}
    return {
        "spin_axis": [1.0, 0.0, 0.0], "materials": [steel],
        "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": "none",
                    "shaft": [{"length": 0.4, "outer_diameter": 0.06, "material": "steel", "elements": 6}],
                    "disks": [{"name": "d", "axial_position": disk, "mass": 10.0, "polar_inertia": 0.01,
                               "diametral_inertia": 0.03}]}],
        "bearings": [{"name": "a", "rotor": "s", "axial_position": 0.1, "stiffness": [3e6, 8e7]},
                     {"name": "b", "rotor": "s", "axial_position": 0.4 - gap, "stiffness": [1e7, 6e7]}]}


def _overhung(gap, disk=0.15):
    return rdm.Model.from_dict(_overhung_data(gap, disk))


#: [m] the element length of :func:`_overhung`'s shaft
ELEMENT = 0.4 / 6


def _lowest(model, count=6):
    """The lowest ``count`` natural frequencies [rad/s] at 1500 rad/s, ascending."""
    return np.sort(rdm.modal(model, 1500.0).eigenvalues.imag)[:count]


def test_a_bearing_microns_from_the_shaft_end_moves_no_frequency_beyond_its_shift():
    """Moving a bearing 4 um (1e-5 of the shaft) changes the frequencies by about that much (the
    measured trend: 3e-3 for 1 mm, 3e-4 for 0.1 mm, linear in the shift), so well within 1e-3;
    a mesh that cannot carry the short element must merge the stations or refuse them by name.
    (Before stations closer than 1e-3 of the element length were merged: 4.8e-2.)"""
    np.testing.assert_allclose(_lowest(_overhung(4e-6)), _lowest(_overhung(0.0)), rtol=1e-3)


def test_stations_two_thousandths_of_an_element_apart_keep_their_node_and_their_physics():
    """A disk 2e-3 element lengths from a bearing is not merged with it (a node of its own): its
    shift from the bearing's place changes the frequencies as the physics does, i.e. as a shift
    50 times larger scaled down (linear in the shift), to the larger shift's quadratic part and
    the round-off of a 500 times shorter element (measured: within 7 % of the largest change)."""
    at_bearing = _overhung(0.0, disk=0.1)
    assert at_bearing.rotors[0].flexible.mesh.n_nodes == 8      # the 7 of the six elements and the bearing's (the disk on it)
    small, large = 2e-3 * ELEMENT, 0.1 * ELEMENT
    near = _overhung(0.0, disk=0.1 + small)
    assert near.rotors[0].flexible.mesh.n_nodes == at_bearing.rotors[0].flexible.mesh.n_nodes + 1
    reference = _lowest(at_bearing)
    slope = (_lowest(_overhung(0.0, disk=0.1 + large)) / reference - 1) / large       # per metre
    change = (_lowest(near) / reference - 1) / small
    assert np.abs(change).max() > 0.2 * np.abs(slope).max()            # not merged: the shift shows
    np.testing.assert_allclose(change, slope, rtol=0.1, atol=0.05 * np.abs(slope).max())


def test_a_merged_station_is_named_in_one_warning_line(tmp_path, capsys):
    """A disk 1e-4 element lengths from bearing 'a' shares its node; ``check`` says so on one
    stderr line naming both, the distance and the rule, and exits 0."""
    import tomli_w

    from rotordyn_modal.cli.main import main

    data = _overhung_data(0.0, disk=0.1 + 1e-4 * ELEMENT)
    data["bearings"][1]["axial_position"] = 0.4 - 5e-6
    path = tmp_path / "close.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", "--quiet", str(path)]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "placed" in line]
    assert len(lines) == 2, lines
    (disk,), (end,) = ([line for line in lines if word in line] for word in ("disk 'd'", "bearing 'b'"))
    assert "[rotors.s] disk 'd' at 0.1000067 m is 6.7e-06 m from bearing 'a' at 0.1 m: placed at its node" in disk
    assert "bearing 'b' at 0.399995 m is 5e-06 m from the shaft's end: placed at the end" in end
    assert all("closer than 0.001 of the element length 0.06667 m" in line for line in lines)
    model = rdm.Model.from_dict(data)
    mesh = model.rotors[0].flexible.mesh
    assert np.all(np.diff(mesh.z) > 0.5 * ELEMENT * 1e-3)             # no element shorter than the rule
