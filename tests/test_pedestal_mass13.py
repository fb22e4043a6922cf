"""A bearing's pedestal is part of the machine's mass (redteam13).

``check`` printed the "total mass" as the stator's plus the rotors', leaving the pedestals
out, while ``static`` hangs their weight on the mounts. The truth here is the file's own
masses summed by hand, and the weight the mounts carry in ``static`` (a separate route:
the static solve of ``K q = f`` with every body's weight).
"""
import subprocess
import sys
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm

STATOR, ROTOR, PEDESTAL = 50.0, 10.0, 4.0    # [kg], two pedestals
G = 9.81

MODEL = f'''name = "rotor on two pedestals in a casing on mounts"
spin_axis = [1.0, 0.0, 0.0]
gravity = [0.0, 0.0, -{G}]

[stator]
mass = {STATOR}
center_of_mass = [0.0, 0.0, 0.1]
inertia = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 3.5]]

[[rotors]]
name = "r"
mass = {ROTOR}
center_of_mass = [0.05, 0.0, 0.2]
polar_inertia = 0.02
diametral_inertia = 0.1
speed_ratio = 1.0
'''
for name, x in (("A", -0.2), ("B", 0.3)):
    MODEL += f'''
[[bearings]]
name = "{name}"
rotor = "r"
position = [{x}, 0.0, 0.2]
stiffness = 1.0e8
pedestal_mass = {PEDESTAL}
pedestal_stiffness = [5.0e7, 9.0e7]
'''
for name, (x, y) in {"FL": (0.4, 0.2), "FR": (0.4, -0.2), "RL": (-0.4, 0.2), "RR": (-0.4, -0.2)}.items():
    MODEL += f'''
[[suspensions]]
name = "{name}"
position = [{x}, {y}, 0.0]
stiffness = [3.0e4, 3.0e4, 6.0e4]
'''
TOTAL = STATOR + ROTOR + 2 * PEDESTAL       # 68 kg


def _model(tmp_path: Path) -> Path:
    path = tmp_path / "pedestals.toml"
    path.write_text(MODEL)
    return path


def test_total_mass_counts_the_pedestals(tmp_path):
    model = rdm.load_model(_model(tmp_path))
    assert abs(model.total_mass - TOTAL) <= 1e-12 * TOTAL
    # the mounts carry the whole weight in static: the same mass by another route
    reactions = rdm.static(model).reactions_table()
    mounts = reactions[reactions["kind"] == "mount"]
    assert len(mounts) == 4
    assert abs(mounts["Fz_N"].sum() / G - TOTAL) <= 1e-9 * TOTAL


def test_check_prints_the_pedestals_in_the_total_mass(tmp_path):
    out = subprocess.run([sys.executable, "-m", "rotordyn_modal", "check", str(_model(tmp_path))],
                         capture_output=True, text=True, check=True).stdout
    assert f"total mass {TOTAL:g} kg" in out, out
