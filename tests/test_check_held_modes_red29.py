"""``check``'s first bending frequency on the bearings and its note on unrestrained directions
must not take a held bending mode for a rigid-body motion (issue 28 review).

Both used to call an eigenvalue "zero" when it was below 1e-9 of the largest (the mesh's highest
mode). A fine mesh (the highest mode grows as the element length to the -2) or very stiff
bearings push a pinned shaft's first bending mode below that: a 2 m, 20 mm steel shaft of 500
elements on two 1e8 N/m bearings (its first mode 9.94 Hz) was reported as "the bearings leave
it free at rest" and "restrain 2002 of 2004 directions"; a 1 m, 50 mm shaft of 20 elements on
1e14 N/m bearings (99.35 Hz) as free too. Truth from outside the code: the pinned-pinned
Rayleigh beam, ``w_1 = (pi/L)^2 sqrt(E I / (rho A (1 + (I/A)(pi/L)^2)))``."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.model import flexible

STEEL = {"name": "steel", "density": 7800.0, "young_modulus": 2.0e11, "poisson_ratio": 0.3}


def _pinned(length, diameter, elements, stiffness):
    """A uniform Euler-Bernoulli (rotary inertia kept) shaft on radial springs at its two ends."""
    return {"name": "pinned", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
            "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "shear": "none",
                        "element_length": length / elements,
                        "shaft": [{"length": length, "outer_diameter": diameter, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": stiffness}
                         for n, z in (("A", 0.0), ("B", length))]}


def _rayleigh_hz(length, diameter):
    area, second = np.pi / 4 * diameter ** 2, np.pi / 64 * diameter ** 4
    beta = np.pi / length
    return np.sqrt(STEEL["young_modulus"] * second * beta ** 4
                   / (STEEL["density"] * area * (1 + second / area * beta ** 2))) / (2 * np.pi)


CASES = [  # (length, diameter, elements, bearing stiffness, route)
    (1.0, 0.05, 20, 1e14, "dense"),        # very stiff bearings: the highest mode 5e14 rad^2/s^2
    (2.0, 0.02, 500, 1e11, "sparse"),      # a fine mesh: the highest mode 5e12 rad^2/s^2
]


@pytest.mark.parametrize("length, diameter, elements, stiffness, route", CASES)
def test_first_mode_on_the_bearings_of_a_pinned_shaft_is_held(length, diameter, elements, stiffness, route):
    model = rdm.Model.from_dict(_pinned(length, diameter, elements, stiffness))
    shaft = model.rotors[0].flexible
    assert (4 * shaft.mesh.n_nodes <= flexible.DENSE_BENDING) == (route == "dense")
    supports = [(shaft.z_of(b.position), b.coefficients.stiffness[0]) for b in model.bearings]
    _, (lowest, share), bending = flexible.bending_frequencies(shaft, supports)
    exact = _rayleigh_hz(length, diameter)
    # the mesh's error (h^4) and the springs' compliance are below 1e-5 of it here
    assert lowest == pytest.approx(exact, rel=1e-5)
    assert bending == pytest.approx(exact, rel=1e-5)
    assert share == pytest.approx(1.0, abs=1e-5)         # the springs strain 1e-6 of it


@pytest.mark.parametrize("length, diameter, elements, stiffness, route", CASES)
def test_check_prints_the_held_bending_mode_and_no_free_direction(length, diameter, elements, stiffness,
                                                                  route, tmp_path, capsys):
    import tomli_w

    path = tmp_path / "pinned.toml"
    path.write_bytes(tomli_w.dumps(_pinned(length, diameter, elements, stiffness)).encode())
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "leave it free" not in out
    assert "note: the suspensions and bearings restrain" not in out
    held = out.split("on its bearings (stator held) lowest mode ")[1]
    assert float(held.split(" Hz")[0]) == pytest.approx(_rayleigh_hz(length, diameter), rel=1e-5)


def test_a_machine_free_in_three_directions_is_still_noted(tmp_path, capsys):
    """The rule still finds what nothing holds: a casing on four mounts stiff only vertically is
    free to slide along x and y and to turn about z (three directions), with the fine shaft in
    its bearings held (its first bending mode, 9.9 Hz, is not among them)."""
    import tomli_w

    data = _pinned(2.0, 0.02, 500, 1e8)
    data["stator"] = {"mass": 50.0, "center_of_mass": [1.0, 0.0, -0.2], "inertia": [5.0, 20.0, 20.0]}
    data["suspensions"] = [{"name": f"m{k}", "position": [x, y, -0.3], "stiffness": [0.0, 0.0, 1e5]}
                           for k, (x, y) in enumerate([(0.0, 0.2), (0.0, -0.2), (2.0, 0.2), (2.0, -0.2)])]
    path = tmp_path / "free.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "coordinates (2010)" in out
    assert "note: the suspensions and bearings restrain 2007 of 2010 directions" in out
