"""Two machines whose unbalance response has a closed form, shared by the unbalance-standard and
report tests (ISO 20816-3 zones, API 684 amplification factors and separation margins).

- A casing that only translates: a rotor rigidly at the stator's centre of mass on four equal
  mounts in the plane of that centre, ``|z| = U w^2 / |Kz - (m_stator + m_rotor) w^2 + i w Cz|``.
- A rigid rotor on two equal isotropic bearings to the ground, symmetric about its centre of
  mass, a probe at the centre of mass: ``|x| = U w^2 / |2k - m w^2 + 2 i w c|``.
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


K_B, C_B, M_R, HALF = 2.0e6, 400.0, 30.0, 0.25


def rotor_on_springs(unbalances):
    """The rigid rotor (mass ``M_R`` [kg]) on two bearings ``K_B`` [N/m], ``C_B`` [N s/m] at
    ``+-HALF`` [m], with the given unbalance tables and a relative probe "probe-x" at its centre."""
    return rdm.Model.from_dict({
        "name": "rotor on springs", "spin_axis": [1.0, 0.0, 0.0],
        "rotors": [{"name": "shaft", "mass": M_R, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": 0.4, "diametral_inertia": 0.9, "speed_ratio": 1.0}],
        "bearings": [{"name": n, "rotor": "shaft", "position": [x, 0.0, 0.0], "stiffness": K_B, "damping": C_B}
                     for n, x in (("DE", HALF), ("NDE", -HALF))],
        "unbalances": unbalances,
        "sensors": [{"name": "probe-x", "rotor": "shaft", "measure": "relative", "position": [0.0, 0.0, 0.0],
                     "direction": [0.0, 0.0, 1.0]}],
    })


def rotor_displacement(w, amount):
    """Closed-form probe displacement amplitude [m] (0-peak) at spin speeds ``w`` [rad/s]."""
    return amount * w ** 2 / np.abs(2 * K_B - M_R * w ** 2 + 2j * w * C_B)
