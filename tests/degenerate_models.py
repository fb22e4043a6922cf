"""Model texts of machines every analysis refuses, or that a model check refuses, shared by the
tests of their one-line refusals (``test_input_defects27.py``, ``test_simulate_cli.py``).

``EXTREME``: a stator of 1e-30 kg under a rotor of 1e30 kg on bearings. Read in, it is a model
(every number within the limits), but in the generalized coordinates (the rotor's motion
relative to the stator) the stator's rows hold the rotor's 1e30 kg plus its own 1e-30 kg, which
rounding loses: the mass matrix is singular in double precision, and every analysis refuses it
(``static``, which needs no mass matrix, runs). A 1e30 kg machine on 1e5 N/m mounts also draws
the sag warning (9.81e25 m). ``INSTRUMENTS`` gives it (or any model whose rotor is ``r`` with a
bearing at x = 0.2 m) an unbalance, two sensors and an excitation, for ``frf``, ``unbalance`` and
``fit``."""

from __future__ import annotations

#: a rigid rotor ``r`` (1e30 kg, polar and diametral inertia 0.05 kg m^2) on two bearings of 1e6 N/m
#: at x = +-0.2 m: ``EXTREME``'s rotor, alone for a machine without a stator
ROTOR_ON_BEARINGS = """[[rotors]]
name = "r"
mass = 1e30
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.05
[[bearings]]
name = "a"
rotor = "r"
position = [0.2, 0.0, 0.0]
stiffness = 1e6
[[bearings]]
name = "b"
rotor = "r"
position = [-0.2, 0.0, 0.0]
stiffness = 1e6
"""

EXTREME = """gravity = [0.0, 0.0, -9.81]
[stator]
mass = 1e-30
inertia = [1.0, 1.0, 1.0]
""" + ROTOR_ON_BEARINGS + """[[suspensions]]
name = "s"
position = [0.0, 0.0, 0.0]
stiffness = [1e5, 1e5, 1e5, 1e3, 1e3, 1e3]
"""

INSTRUMENTS = """[[unbalances]]
rotor = "r"
amount = 1e-4
[[sensors]]
name = "p"
rotor = "r"
measure = "relative"
position = [0.2, 0.0, 0.0]
direction = [0.0, 1.0, 0.0]
[[sensors]]
name = "acc"
position = [0.2, 0.0, 0.1]
direction = [0.0, 0.0, 1.0]
[[excitations]]
name = "hammer"
position = [0.2, 0.0, 0.1]
direction = [0.0, 0.0, -1.0]
"""


def variant(**changes: str) -> str:
    """``EXTREME`` with its instruments and the new value of each line named in ``changes``:
    ``stator_mass``, ``stator_inertia``, ``rotor_mass``, ``rotor_inertia`` (polar and diametral),
    ``bearing`` (both bearings' stiffness), ``mount`` (the suspension's six numbers), ``unbalance``
    (its amount: 1e-4 kg m is refused on a rotor of 1e-30 kg, an eccentricity of 1e26 m); e.g.
    ``variant(stator_mass="100.0", rotor_mass="1e-30", unbalance="1e-16")``."""
    text = EXTREME + INSTRUMENTS
    lines = {"stator_mass": ("mass = 1e-30", "mass = {}"),
             "stator_inertia": ("inertia = [1.0, 1.0, 1.0]", "inertia = {}"),
             "rotor_mass": ("mass = 1e30", "mass = {}"),
             "bearing": ("stiffness = 1e6", "stiffness = {}"),
             "mount": ("stiffness = [1e5, 1e5, 1e5, 1e3, 1e3, 1e3]", "stiffness = {}"),
             "unbalance": ("amount = 1e-4", "amount = {}")}
    for key, value in changes.items():
        if key == "rotor_inertia":
            text = text.replace("polar_inertia = 0.05", f"polar_inertia = {value}")
            text = text.replace("diametral_inertia = 0.05", f"diametral_inertia = {value}")
            continue
        old, new = lines[key]
        assert old in text, key
        text = text.replace(old, new.format(value))
    return text
