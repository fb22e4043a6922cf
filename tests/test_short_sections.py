"""A shaft section shorter than 1e-3 of a neighbouring section's element length makes no element
of its own (docs/theory.md §16, "Sections shorter than a thousandth of an element"): its ends share
one node, its mass and inertia are lumped there as a rigid piece, and ``check`` names it.

The references are independent builds of the same physics: the shaft with the short section's
length given to its neighbour, and a collar as the rigid disk of its closed-form mass and
inertia."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}


def _model(sections, bearings, element_length=None, disks=()):
    rotor = {"name": "s", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
             "shaft": [dict(section, material="steel") for section in sections], "disks": list(disks)}
    if element_length is not None:
        rotor["element_length"] = element_length
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict({
            "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL], "rotors": [rotor],
            "bearings": [{"name": name, "rotor": "s", "axial_position": z, "stiffness": 1e7, "damping": 300.0}
                         for name, z in zip("ab", bearings)]})


def _roots(model, speed=300.0):
    """The six lowest oscillating roots at ``speed`` [rad/s], by frequency."""
    result = rdm.modal(model, speed)
    lam = result.eigenvalues[result.frequencies_hz > 1.0]
    return np.sort_complex(lam * -1j)[:6] * 1j


def test_a_ten_micron_end_section_gives_the_roots_of_the_shaft_it_lengthens():
    """A 4 m shaft of two 2 m elements ending, beyond its bearing, in a section 10 um long: the
    roots equal those of the shaft whose last section is 10 um longer (the short section merged
    into its neighbour; the bearing 10 um from the end then sits at the end in both) to 1e-9. With
    the section kept as an element of 5e-6 of its neighbour's (before) they differed by 3.3e-5,
    and not in proportion to its length (4.3e-5 at 20 um, 2.5e-5 at 50 um): round-off."""
    disk = [{"name": "d", "axial_position": 1.0, "mass": 5.0, "polar_inertia": 0.02, "diametral_inertia": 0.012}]
    short = _model([{"length": 2.0, "outer_diameter": 0.05, "elements": 1},
                    {"length": 2.0, "outer_diameter": 0.05, "elements": 1},
                    {"length": 1e-5, "outer_diameter": 0.05}], bearings=(0.0, 4.0), disks=disk)
    merged = _model([{"length": 2.0, "outer_diameter": 0.05, "elements": 1},
                     {"length": 2.0 + 1e-5, "outer_diameter": 0.05, "elements": 1}], bearings=(0.0, 4.0), disks=disk)
    np.testing.assert_allclose(_roots(short), _roots(merged), rtol=1e-9, atol=0.0)
    mesh = short.rotors[0].flexible.mesh
    assert np.diff(mesh.z).min() > 0.5


def test_the_reach_over_an_absorbed_section_adds_no_element():
    """Two sections of exactly two element lengths (1 m elements) and a 10 um end section: four
    elements (the last section's two 5 um longer), not three elements in the last section."""
    model = _model([{"length": 2.0, "outer_diameter": 0.05}, {"length": 2.0, "outer_diameter": 0.05},
                    {"length": 1e-5, "outer_diameter": 0.05}], bearings=(0.0, 4.0), element_length=1.0)
    np.testing.assert_allclose(model.rotors[0].flexible.mesh.z, [0.0, 1.0, 2.0, 3.000005, 4.00001], rtol=0, atol=1e-12)


def test_a_short_collar_is_the_rigid_disk_of_its_closed_form_mass_and_inertia():
    """A collar 100 mm thick and 20 um long between two 50 mm sections of 0.1 m elements is what
    docs/theory.md §16 says it becomes, built independently: the uniform 50 mm shaft 20 um longer
    carrying, at the collar's middle, the disk of the annulus the collar adds (mass
    rho pi/4 (D^2 - d^2) L, polar m (D^2 + d^2) / 8, diametral half that plus m L^2 / 12); the
    roots agree to 1e-9 at three speeds (the collar's own bending stiffness, which this drops,
    moves them by 1.6e-5, measured with the collar kept as an element)."""
    L, D, d, rho = 2e-5, 0.1, 0.05, STEEL["density"]
    mass = rho * math.pi / 4.0 * (D ** 2 - d ** 2) * L
    polar = mass * (D ** 2 + d ** 2) / 8.0
    collar = _model([{"length": 0.4, "outer_diameter": d, "elements": 4}, {"length": L, "outer_diameter": D},
                     {"length": 0.4, "outer_diameter": d, "elements": 4}], bearings=(0.0, 0.8 + L),
                    element_length=0.1)
    disk = _model([{"length": 0.4 + L / 2, "outer_diameter": d, "elements": 4},
                   {"length": 0.4 + L / 2, "outer_diameter": d, "elements": 4}], bearings=(0.0, 0.8 + L),
                  disks=[{"name": "collar", "axial_position": 0.4 + L / 2, "mass": mass, "polar_inertia": polar,
                          "diametral_inertia": polar / 2.0 + mass * L ** 2 / 12.0}])
    for speed in (0.0, 300.0, 3000.0):
        np.testing.assert_allclose(_roots(collar, speed), _roots(disk, speed), rtol=1e-9, atol=0.0)


def _rigid_totals(model):
    """Mass [kg] and polar inertia [kg m^2] of the flexible rotor's node mass matrix: a unit
    translation across the axis and a unit rotation about it at every node (the nodes lie on
    the axis, x)."""
    from rotordyn_modal.model.flexible import node_matrices

    shaft = model.rotors[0].flexible
    (M,) = node_matrices(shaft, shaft.mesh, ("M",))
    nodes = shaft.mesh.n_nodes
    across, about = np.zeros(6 * nodes), np.zeros(6 * nodes)
    across[1::6] = 1.0
    about[3::6] = 1.0
    return float(across @ (M @ across)), float(about @ (M @ about))


@pytest.mark.parametrize("layout", ["start", "middle-two", "end"])
def test_absorbed_sections_keep_the_shafts_mass_and_polar_inertia(layout):
    """Hollow sections of 30 um (a tenth of the rule at 0.1 m elements) at the shaft's start, two
    in a row in its middle, or at its end, each of another diameter than its neighbours: no
    element of theirs in the mesh, and the node mass matrix holds the sections' closed-form
    mass (sum rho pi/4 (D^2 - d^2) L) and polar inertia (sum rho pi/32 (D^4 - d^4) L) to 1e-12."""
    tiny = [{"length": 3e-5, "outer_diameter": 0.09, "inner_diameter": 0.02},
            {"length": 4e-5, "outer_diameter": 0.03}]
    long = [{"length": 0.3, "outer_diameter": 0.05}, {"length": 0.5, "outer_diameter": 0.06, "inner_diameter": 0.01}]
    sections = {"start": [tiny[0], *long], "middle-two": [long[0], *tiny, long[1]], "end": [*long, tiny[0]]}[layout]
    total = sum(s["length"] for s in sections)
    model = _model(sections, bearings=(0.0, total), element_length=0.1)
    shaft = model.rotors[0].flexible
    assert shaft.mesh.absorbed, "no section absorbed"
    assert {index for _, index, *_ in shaft.mesh.elements} == {i for i, s in enumerate(sections) if s["length"] > 0.1}
    rho = STEEL["density"]
    mass = sum(rho * math.pi / 4 * (s["outer_diameter"] ** 2 - s.get("inner_diameter", 0.0) ** 2) * s["length"]
               for s in sections)
    polar = sum(rho * math.pi / 32 * (s["outer_diameter"] ** 4 - s.get("inner_diameter", 0.0) ** 4) * s["length"]
                for s in sections)
    got_mass, got_polar = _rigid_totals(model)
    assert got_mass == pytest.approx(mass, rel=1e-12)
    assert got_polar == pytest.approx(polar, rel=1e-12)


def test_a_section_at_twice_the_rule_keeps_its_element():
    """At 2e-3 of the neighbours' element length (over the 1e-3 rule) the section stays an element
    of its own: nodes at both of its ends."""
    model = _model([{"length": 0.4, "outer_diameter": 0.05}, {"length": 2e-4, "outer_diameter": 0.08},
                    {"length": 0.4, "outer_diameter": 0.05}], bearings=(0.0, 0.8002), element_length=0.1)
    mesh = model.rotors[0].flexible.mesh
    assert not mesh.absorbed
    assert np.isclose(mesh.z, 0.4).any() and np.isclose(mesh.z, 0.4002, rtol=0.0, atol=1e-12).any()


def test_an_absorbed_section_is_named_in_one_warning_line(tmp_path, capsys):
    """``check`` says on one stderr line which section made no element, its length, the rule and
    the neighbouring element length, where its ends now meet, and exits 0."""
    import tomli_w

    from rotordyn_modal.cli.main import main

    data = {"spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                        "shaft": [{"length": 0.4, "outer_diameter": 0.05, "material": "steel"},
                                  {"length": 2e-5, "outer_diameter": 0.1, "material": "steel"},
                                  {"length": 0.4, "outer_diameter": 0.05, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e7}
                         for n, z in (("a", 0.0), ("b", 0.80002))]}
    path = tmp_path / "short.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", "--quiet", str(path)]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "shaft.1" in line]
    assert len(lines) == 1, lines
    assert (f"{path}: [rotors.s.shaft.1] length = 2e-05 m is shorter than 0.001 of the neighbouring element "
            "length 0.1 m: it makes no element") in lines[0]
    assert "share the node at 0.40001 m" in lines[0] and "lumped there as a rigid piece" in lines[0]


def test_a_bearing_on_an_absorbed_section_is_at_its_joint():
    """A bearing at the far end of a 50 um section between a section of 0.1 m elements and one of
    0.01 m elements: the bearing sits at the joint the section's ends share (no node 25 um from
    it, which would be a short element beside the 0.1 m ones), and is named as moved."""
    model = _model([{"length": 0.4, "outer_diameter": 0.05}, {"length": 5e-5, "outer_diameter": 0.05},
                    {"length": 0.1, "outer_diameter": 0.05, "elements": 10}], bearings=(0.0, 0.40005),
                   element_length=0.1)
    mesh = model.rotors[0].flexible.mesh
    joint = 0.4 + 2.5e-5
    assert mesh.z[mesh.node(0.40005)] == pytest.approx(joint, abs=1e-12)
    assert np.abs(mesh.z - joint).min() < 1e-12
    assert np.abs(mesh.z - 0.40005).min() > 2e-5
    assert [label for label, *_ in mesh.merged] == ["bearing 'b'"]
    from rotordyn_modal.model.flexible import merge_lines

    (line,) = [x for x in merge_lines("f.toml", "s", model.rotors[0].flexible) if "bearing 'b'" in x]
    assert "bearing 'b' at 0.40005 m is 2.5e-05 m from the mesh's node at 0.400025 m: placed there (on shaft.1, " \
           "too short for an element of its own;" in line, line
