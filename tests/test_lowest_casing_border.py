"""The border of a lowest-modes sweep's banded pencils (``_lowest_pencils._band``) for a long
flexible shaft in a casing: the casing's motions couple to most of the shaft's nodes, so they must
be the border, and the shaft's own coordinates the band. Found by ``benchmarks/bench_flexible.py
--coordinates 400 --in-casing gear``: the greedy choice by reach took shaft coordinates after two
of the casing's, found no band, and each root's Newton step took a SuperLU (3x the sweep's time).
Truth from outside the code: the band read off the pattern here, and numpy's dense eig."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis._lowest_pencils import _band
from rotordyn_modal.io.model_file import read_toml

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}


def _fan_in_gear_casing(elements):
    """``examples/gear_machine.toml`` with its fan a steel shaft 0.8 m long, 40 mm thick, of
    ``elements`` elements, a 4 kg wheel at mid-span, on two bearings at its ends in the casing."""
    data = read_toml(str(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"), "model")
    fan = next(rotor for rotor in data["rotors"] if rotor["name"] == "fan")
    half = elements // 2
    data["materials"] = [STEEL]
    data["rotors"] = [rotor for rotor in data["rotors"] if rotor is not fan] + [{
        "name": "fan", "start": [fan["center_of_mass"][0] - 0.4, *fan["center_of_mass"][1:]],
        "shaft": [{"length": 0.4, "outer_diameter": 0.04, "material": "steel", "elements": half},
                  {"length": 0.4, "outer_diameter": 0.04, "material": "steel", "elements": elements - half}],
        "disks": [{"name": "wheel", "axial_position": 0.4, "mass": 4.0, "polar_inertia": 0.25,
                   "diametral_inertia": 0.13}]}]
    data["bearings"] = [{"name": name, "rotor": "fan", "axial_position": z, "stiffness": 2e7, "damping": 500.0}
                        for name, z in (("fan-A", 0.0), ("fan-B", 0.8))]
    data["unbalances"] = [dict(u, axial_position=0.4) if u["rotor"] == "fan" else u for u in data["unbalances"]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict(data)


def test_a_long_shaft_in_a_casing_is_banded_with_the_casing_as_border():
    """406 coordinates (the casing's 6, the shaft's 400): a band of at most 8 below and above the
    diagonal once the casing's coupled motions are the border (at most 6 coordinates, all the
    casing's), and the pencils' every entry inside the band or on the border."""
    model = _fan_in_gear_casing(99)
    M, C, G, K = model.matrices()
    n = len(M)
    assert n == 406
    rows, cols = np.nonzero((M != 0) | (C != 0) | (G != 0) | (K != 0))
    band = _band(rows, cols, n)
    assert band is not None, "no band found: a sparse LU per root"
    border = set(band.order[band.size:].tolist())
    assert border <= set(range(6)), border
    assert band.lower <= 8 and band.upper <= 8
    place = np.empty(n, int)
    place[band.order] = np.arange(n)
    i, j = place[rows], place[cols]
    inner = (i < band.size) & (j < band.size)
    assert np.all(np.abs(i - j)[inner] <= max(band.lower, band.upper))


def test_its_lowest_roots_are_the_dense_eigs():
    """The 12 lowest roots at three speeds equal the 12 lowest of numpy's eig of the state matrix
    to 1e-9 relative."""
    model = _fan_in_gear_casing(99)
    speeds = np.array([0.0, 700.0, 1500.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.campbell(model, speeds, critical=False, modes=12)
    got = np.sort_complex(np.where(result.oscillatory, result.eigenvalues, np.nan) * -1j) * 1j
    M, C, G, K = model.matrices()
    n = len(M)
    for k, speed in enumerate(speeds):
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
        lam = np.linalg.eigvals(A)
        lam = lam[lam.imag > 1e-6 * np.abs(lam)]
        expected = (np.sort_complex(lam * -1j) * 1j)[:12]
        np.testing.assert_allclose(got[k, :12], expected, rtol=1e-9)
