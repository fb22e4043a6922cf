"""A shaft section's ``layers``: concentric tubes in parallel over the section, as ROSS's parallel
shaft elements (issue 28). Truths from outside the model: matrices summed by hand from
``elements.shaft.element_matrices``, closed-form volumes and inertias of frustums, and
``I = pi d^4 / 64`` summing exactly over concentric rings."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.elements.shaft import Material, element_matrices
from rotordyn_modal.errors import ModelError

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}
ALU = {"name": "alu", "density": 2700.0, "young_modulus": 7.0e10, "poisson_ratio": 0.33}
BEARING = 3e6      # [N/m] isotropic, at both ends
LENGTH = 0.6       # [m]
ELEMENTS = 3


def _model(section, shear="cowper"):
    """One flexible rotor of one section (3 elements) on two isotropic end bearings, grounded."""
    data = {"materials": [STEEL, ALU],
            "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": shear,
                        "shaft": [{"length": LENGTH, "elements": ELEMENTS, **section}]}],
            "bearings": [{"name": n, "rotor": "r", "axial_position": z, "stiffness": BEARING}
                         for n, z in (("a", 0.0), ("b", LENGTH))]}
    return data


LAYERED = {"outer_diameter": [0.05, 0.04], "inner_diameter": 0.01, "material": "steel",
           "layers": [{"outer_diameter": [0.07, 0.06], "inner_diameter": [0.05, 0.04], "material": "alu"}]}


def _frequencies(M, K):
    return np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))


def _linear(pair, t):
    return pair[0] * (1 - t) + pair[1] * t


def test_two_layers_are_the_hand_summed_element_matrices():
    model = rdm.Model.from_dict(_model(LAYERED))
    steel = Material("steel", STEEL["density"], STEEL["young_modulus"], STEEL["shear_modulus"])
    alu_g = ALU["young_modulus"] / (2 * (1 + ALU["poisson_ratio"]))
    alu = Material("alu", ALU["density"], ALU["young_modulus"], alu_g)
    tubes = [((0.05, 0.04), (0.01, 0.01), steel), ((0.07, 0.06), (0.05, 0.04), alu)]
    n = ELEMENTS + 1
    M, K = np.zeros((6 * n, 6 * n)), np.zeros((6 * n, 6 * n))
    h = LENGTH / ELEMENTS
    for e in range(ELEMENTS):
        t0, t1 = e / ELEMENTS, (e + 1) / ELEMENTS
        rows = slice(6 * e, 6 * e + 12)
        for outer, inner, material in tubes:
            m, k, _ = element_matrices(h, (_linear(outer, t0), _linear(outer, t1)),
                                       (_linear(inner, t0), _linear(inner, t1)), material, shear="cowper")
            M[rows, rows] += m
            K[rows, rows] += k
    for node in (0, n - 1):
        K[6 * node, 6 * node] += BEARING
        K[6 * node + 1, 6 * node + 1] += BEARING
    lateral = [6 * i + j for i in range(n) for j in (0, 1, 3, 4)]   # no axial bearing, spin not a coordinate
    expected = _frequencies(M[np.ix_(lateral, lateral)], K[np.ix_(lateral, lateral)])
    found = _frequencies(model.matrices().M, model.matrices().K)
    assert found == pytest.approx(expected, rel=1e-9)


def _frustum_integrals(outer, inner):
    """Over the section: volume [m^3] and the integral of (d_o^4 - d_i^4) [m^5] (diameters linear)."""
    def square(d):
        return LENGTH * (d[0] ** 2 + d[0] * d[1] + d[1] ** 2) / 3

    def fourth(d):
        return LENGTH * sum(d[0] ** (4 - k) * d[1] ** k for k in range(5)) / 5

    return np.pi / 4 * (square(outer) - square(inner)), fourth(outer) - fourth(inner)


def test_layers_add_their_mass_and_polar_inertia():
    rotor = rdm.Model.from_dict(_model(LAYERED)).rotors[0]
    v_steel, q_steel = _frustum_integrals((0.05, 0.04), (0.01, 0.01))
    v_alu, q_alu = _frustum_integrals((0.07, 0.06), (0.05, 0.04))
    assert rotor.mass == pytest.approx(STEEL["density"] * v_steel + ALU["density"] * v_alu, rel=1e-12)
    polar = np.pi / 32 * (STEEL["density"] * q_steel + ALU["density"] * q_alu)
    assert rotor.polar_inertia == pytest.approx(polar, rel=1e-12)


def test_a_solid_core_and_a_ring_are_the_solid_section_without_shear():
    d1, d2 = 0.03, 0.05
    solid = rdm.Model.from_dict(_model({"outer_diameter": d2, "material": "steel"}, shear="none"))
    rings = rdm.Model.from_dict(_model({"outer_diameter": d1, "material": "steel", "layers": [
        {"outer_diameter": d2, "inner_diameter": d1, "material": "steel"}]}, shear="none"))
    assert rings.rotors[0].mass == pytest.approx(solid.rotors[0].mass, rel=1e-13)
    assert rings.rotors[0].diametral_inertia == pytest.approx(solid.rotors[0].diametral_inertia, rel=1e-13)
    assert _frequencies(*rings.matrices()[::3]) == pytest.approx(_frequencies(*solid.matrices()[::3]), rel=1e-10)


def test_dotted_keys_reach_a_layer():
    data = _model(LAYERED)
    model = rdm.Model.from_dict(data)
    key = "rotors.r.shaft.0.layers.0.outer_diameter"
    assert model.get(key) == [0.07, 0.06]
    thicker = model.with_values({key: [0.08, 0.06]})
    extra = ALU["density"] * np.pi / 4 * LENGTH * (0.08 ** 2 + 0.08 * 0.06 - 0.07 ** 2 - 0.07 * 0.06) / 3
    assert thicker.rotors[0].mass == pytest.approx(model.rotors[0].mass + extra, rel=1e-12)
    steel = model.variant([("rotors.r.shaft.0.layers.0.material", "value", "steel"),
                           ("rotors.r.shaft.0.layers.0.inner_diameter", "scale", 1.1)])
    v_alu, _ = _frustum_integrals((0.07, 0.06), (0.05, 0.04))
    v_steel, _ = _frustum_integrals((0.07, 0.06), (0.055, 0.044))
    assert steel.rotors[0].mass == pytest.approx(
        model.rotors[0].mass + STEEL["density"] * v_steel - ALU["density"] * v_alu, rel=1e-12)
    assert model.get("rotors.r.shaft.0.layers.0.material") == "alu"          # the original unchanged
    assert model.get("rotors.r.shaft.0.layers.0.inner_diameter") == [0.05, 0.04]
    assert data["rotors"][0]["shaft"][0]["layers"][0] == LAYERED["layers"][0]


def _layer(**keys):
    def change(data):
        data["rotors"][0]["shaft"][0]["layers"][0].update(keys)
    return change


BAD = {
    "unknown material": (_layer(material="brass"), "[rotors.r.shaft.0.layers.0] material = 'brass'"),
    "bore not below outer": (_layer(inner_diameter=[0.05, 0.06]), "[rotors.r.shaft.0.layers.0] inner_diameter = [0.05, 0.06]"),
    "negative diameter": (_layer(outer_diameter=-0.07), "[rotors.r.shaft.0.layers.0] outer_diameter = -0.07"),
    "no outer diameter": (lambda d: d["rotors"][0]["shaft"][0]["layers"][0].pop("outer_diameter"),
                          "[rotors.r.shaft.0.layers.0] outer_diameter"),
    "unknown key": (_layer(length=0.3), "[rotors.r.shaft.0.layers.0] length"),
    "not tables": (lambda d: d["rotors"][0]["shaft"][0].update(layers=[0.07]), "[rotors.r.shaft.0] layers = [0.07]"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_layers_are_refused_by_name(case):
    change, where = BAD[case]
    data = copy.deepcopy(_model(LAYERED))
    change(data)
    with pytest.raises(ModelError) as error:
        rdm.Model.from_dict(data, source="m.toml")
    assert str(error.value).startswith("m.toml: " + where), str(error.value)
    assert "\n" not in str(error.value)
