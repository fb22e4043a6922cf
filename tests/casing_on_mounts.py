"""A casing that only translates: a rotor rigidly at the stator's centre of mass on four equal
mounts in the plane of that centre, driven by the rotor's unbalance.

The vertical displacement amplitude has the closed form
``|z| = U w^2 / |Kz - (m_stator + m_rotor) w^2 + i w Cz|``: shared by the unbalance-standard
and report tests (ISO 20816-3 zones, API 684 margins against a mount resonance).
"""
import numpy as np

import rotordyn_modal as rdm

M_STATOR, M_ROTOR = 80.0, 20.0
MOUNT_CORNERS = [(0.4, 0.3), (0.4, -0.3), (-0.4, 0.3), (-0.4, -0.3)]


def casing_model(amount, kz=1.0e6, cz=1200.0):
    """The casing model with unbalance ``amount`` [kg m], total vertical mount stiffness ``kz``
    [N/m] and damping ``cz`` [N s/m] (a quarter on each mount); one vertical sensor "casing-z"."""
    return rdm.Model.from_dict({
        "name": "casing", "spin_axis": [1.0, 0.0, 0.0],
        "stator": {"mass": M_STATOR, "center_of_mass": [0.0, 0.0, 0.0], "inertia": [4.0, 6.0, 7.0]},
        "rotors": [{"name": "rotor", "mass": M_ROTOR, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.3, "diametral_inertia": 0.2, "speed_ratio": 1.0}],
        "suspensions": [{"name": f"m{i}", "position": [x, y, 0.0], "stiffness": [2e5, 2e5, kz / 4],
                         "damping": [300.0, 300.0, cz / 4]}
                        for i, (x, y) in enumerate(MOUNT_CORNERS)],
        "unbalances": [{"rotor": "rotor", "amount": amount}],
        "sensors": [{"name": "casing-z", "position": [0.0, 0.0, 0.0], "direction": [0.0, 0.0, 1.0]}],
    })


def casing_displacement(w, amount, kz=1.0e6, cz=1200.0):
    """Closed-form vertical displacement amplitude [m] (0-peak) at spin speeds ``w`` [rad/s]."""
    return amount * w ** 2 / np.abs(kz - (M_STATOR + M_ROTOR) * w ** 2 + 1j * w * cz)
