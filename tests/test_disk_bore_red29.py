"""A disk given by its geometry whose bore is below the shaft's diameter counts the shaft inside
it twice, and says so (issue 28 review).

``[[rotors.disks]]`` by ``outer_diameter``, ``width`` and ``material`` is a solid ring
``m = rho pi/4 (D^2 - d^2) w`` with the bore ``d = inner_diameter`` defaulting to 0, while the
shaft's elements carry their own mass under the disk: a 0.3 m steel disk 0.05 m wide on a 0.05 m
shaft, bore left out, made the rotor ``rho pi/4 0.05^2 0.05`` = 0.766 kg heavier than it is, with
no word said (ROSS's ``DiskElement.from_geometry`` asks ``i_d``, the diameter of the shaft the
disk is mounted on). Now one warning line names the disk, its bore, the shaft's diameter there
and the mass counted twice; with the bore at the shaft's diameter the rotor's mass is the
shaft's plus the ring's, by hand."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.plausibility import implausible

RHO = 7810.0
DATA = {
    "spin_axis": [1.0, 0.0, 0.0],
    "materials": [{"name": "steel", "density": RHO, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
    "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0],
                "shaft": [{"length": 0.5, "outer_diameter": 0.05, "material": "steel"},
                          {"length": 0.5, "outer_diameter": [0.05, 0.03], "material": "steel"}],
                "disks": [{"name": "wheel", "axial_position": 0.3, "outer_diameter": 0.3, "width": 0.05,
                           "material": "steel"}]}],
    "bearings": [{"name": n, "rotor": "r", "axial_position": z, "stiffness": 1e8} for n, z in (("a", 0.0), ("b", 1.0))],
}


def _with(**disk):
    data = copy.deepcopy(DATA)
    data["rotors"][0]["disks"][0].update(disk)
    return data


def _lines(data):
    return [line for line in implausible(rdm.Model.from_dict(data, source="m.toml")) if "bore" in line]


def test_a_disk_without_its_bore_warns_with_the_mass_counted_twice(tmp_path):
    twice = RHO * np.pi / 4 * 0.05 ** 2 * 0.05
    assert _lines(_with()) == [f"m.toml: [rotors.r.disks.wheel] inner_diameter = 0: a bore below the shaft's outer "
                               f"diameter 0.05 m at its station: the disk's ring holds the shaft inside it, {twice:.3g} kg "
                               "the shaft's elements carry already (counted twice); give the disk's bore, "
                               "inner_diameter = 0.05 (a disk around the shaft)"]
    import tomli_w

    path = tmp_path / "m.toml"                        # load_model (check, every command) says it
    path.write_bytes(tomli_w.dumps(_with()).encode())
    with pytest.warns(rdm.errors.ModelWarning, match=r"\[rotors.r.disks.wheel\] inner_diameter = 0: a bore below"):
        rdm.load_model(path)


def test_on_a_tapered_section_the_shaft_diameter_is_the_one_at_the_station():
    """At 0.75 m the second section tapers from 0.05 to 0.03 m: 0.04 m there."""
    (line,) = _lines(_with(axial_position=0.75, inner_diameter=0.035))
    assert "inner_diameter = 0.035: a bore below the shaft's outer diameter 0.04 m at its station" in line


@pytest.mark.parametrize("disk", [{"inner_diameter": 0.05}, {"axial_position": 0.75, "inner_diameter": 0.04},
                                  {"outer_diameter": None, "width": None, "material": None, "mass": 27.0,
                                   "polar_inertia": 0.3, "diametral_inertia": 0.16}])
def test_a_disk_around_the_shaft_or_given_by_mass_draws_no_such_line(disk):
    data = _with(**disk)
    data["rotors"][0]["disks"][0] = {k: v for k, v in data["rotors"][0]["disks"][0].items() if v is not None}
    assert _lines(data) == []
    model = rdm.Model.from_dict(data)
    if "mass" not in disk and disk.get("axial_position") is None:
        shaft = RHO * np.pi / 4 * 0.05 ** 2 * 0.5 + RHO * np.pi / 12 * 0.5 * (0.05 ** 2 + 0.05 * 0.03 + 0.03 ** 2)
        ring = RHO * np.pi / 4 * (0.3 ** 2 - 0.05 ** 2) * 0.05
        assert model.rotors[0].mass == pytest.approx(shaft + ring, rel=1e-12)
