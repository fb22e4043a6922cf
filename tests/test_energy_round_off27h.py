"""Strain energy fractions within their round-off are 0, never negative or nan (issue 27 §1.1:
what an engineer reads must be right). A part's energy ``1/2 phi^H K phi`` of a shape that the
part does not strain is a sum of products that cancel: rounding leaves up to ``eps |phi|^T |K|
|phi|``, which for a very stiff shaft (2 mm long) is 1e-5 of the bearings' energy."""

from __future__ import annotations

import io
import math

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

_MATERIAL = """
[[materials]]
name = "steel"
density = 7800.0
young_modulus = 2.0e11
poisson_ratio = 0.3
"""


def _shaft(path, length, diameter, stiffness):
    """One uniform steel shaft on two isotropic bearings (N/m) at its ends, no damping."""
    path.write_text('name = "shaft"\n' + _MATERIAL + '\n[[rotors]]\nname = "s"\nspeed_ratio = 1.0\n'
                    'start = [0.0, 0.0, 0.0]\nshear = "none"\n'
                    f'\n[[rotors.shaft]]\nlength = {length!r}\nouter_diameter = {diameter!r}\nmaterial = "steel"\n'
                    f'\n[[bearings]]\nname = "b0"\nrotor = "s"\naxial_position = 0.0\nstiffness = {stiffness!r}\n'
                    f'\n[[bearings]]\nname = "b1"\nrotor = "s"\naxial_position = {length!r}\nstiffness = {stiffness!r}\n',
                    encoding="utf-8")
    return path


@pytest.mark.parametrize("length,diameter", [(0.002, 0.05), (10.0, 1000.0), (1000.0, 1000.0)])
def test_a_rigid_shafts_energy_fractions_are_in_range(tmp_path, length, diameter):
    """The rigid-body modes of a shaft far stiffer than its 1e7 N/m bearings store their energy
    in the bearings: fractions in [0, 1] summing to 1, the shaft's exactly 0 (a 2 mm shaft printed
    -2e-5, a 10 m shaft 1000 m across nan)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.load_model(_shaft(tmp_path / "s.toml", length, diameter, 1e7))
    result = rdm.modal(model, 3000 * math.pi / 30)
    fractions = result.energy_fractions[result.oscillatory]
    assert np.all(np.isfinite(fractions))
    assert np.all((fractions >= 0) & (fractions <= 1))
    np.testing.assert_allclose(fractions.sum(axis=1), 1.0, rtol=1e-12)
    shaft = fractions[:, list(result.energy_parts).index("shaft")]
    # the shaft strains or it does not: no fraction of round-off size (1e-5 of the bearings' was printed)
    assert np.all((shaft == 0.0) | (shaft > 1e-3)), shaft
    if length == 0.002:                  # a disk: its lowest four modes are rigid on the bearings
        assert np.all(shaft[:4] == 0.0)


def test_the_terminal_prints_no_negative_fraction(tmp_path, capsys):
    path = _shaft(tmp_path / "disk.toml", 0.002, 0.05, 1e7)
    assert main(["modes", str(path), "--speed", "3000", "--out", "-"]) == 0
    table = pd.read_csv(io.StringIO(capsys.readouterr().out))
    for column in ("shaft_energy", "bearing_energy"):
        assert (table[column] >= 0).all() and table[column].notna().all(), table
