"""Hidden-check families of issue 27 tried anew (scales across decades, roots of very different
sizes): each test here failed on the main of 2026-11-29 before its fix.

Truth from outside the code: a machine without damping and with a symmetric stiffness is
conservative, so every root is on the imaginary axis (no damping ratio can be anything but 0);
a short solid shaft is, in its conical modes, the rigid rotor of the same mass properties, whose
orbits are circles (whirl ratio +-1).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from rotordyn_modal.cli.main import main

_MATERIAL = """
[[materials]]
name = "steel"
density = 7800.0
young_modulus = 2.0e11
poisson_ratio = 0.3
"""


def _shaft_model(path, sections, bearings, stiffness, element_length=None):
    """A flexible rotor of ``sections`` (length, diameter) on two isotropic bearings of
    ``stiffness`` N/m at ``bearings`` (axial positions), no damping anywhere; written to ``path``."""
    text = 'name = "shaft"\n' + _MATERIAL + '\n[[rotors]]\nname = "s"\nspeed_ratio = 1.0\nstart = [0.0, 0.0, 0.0]\nshear = "none"\n'
    if element_length:
        text += f"element_length = {element_length!r}\n"
    for length, diameter in sections:
        text += f'\n[[rotors.shaft]]\nlength = {length!r}\nouter_diameter = {diameter!r}\nmaterial = "steel"\n'
    for i, at in enumerate(bearings):
        text += f'\n[[bearings]]\nname = "b{i}"\nrotor = "s"\naxial_position = {at!r}\nstiffness = {stiffness!r}\n'
    path.write_text(text, encoding="utf-8")
    return path


def _terminal_table(text):
    """The modes table printed on the terminal, as strings by column."""
    lines = [line.split() for line in text.splitlines() if line.strip()]
    header = lines[0]
    rows = [line for line in lines[1:] if len(line) == len(header) and line[0].isdigit()]
    return pd.DataFrame(rows, columns=header)


def test_modes_of_an_undamped_machine_print_no_damping(tmp_path, capsys):
    """A 10 m shaft meshed around a 1 mm section, on 1e3 N/m bearings, no damping: the eigen-solve's
    real parts (1e-6 .. 1e-5 1/s, above its round-off estimate: the roots are ill-conditioned) printed
    as damping ratios of +-4e-7 and log decrements of -2.6e-6 on main, which read as unstable."""
    model = _shaft_model(tmp_path / "shaft.toml", [(5.0, 0.05), (0.001, 0.05), (4.999, 0.05)], [1.0, 9.0],
                         1e3, element_length=1.0)
    assert main(["modes", str(model), "--speed", "3000"]) == 0
    table = _terminal_table(capsys.readouterr().out)
    assert len(table) >= 6
    for column in ("damping_ratio", "log_decrement", "real_part"):
        assert (table[column].astype(float) == 0.0).all(), (column, table[column].tolist())
