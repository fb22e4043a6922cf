"""A rigid rotor whose first forward mode is not its least stable, written out by hand: the
independent reference of the Level I tests (tests/test_report_review.py, tests/test_level1_modes.py).

A rigid rotor (mass m, diametral inertia Id, polar inertia ~0: no gyroscopic coupling) on two
isotropic bearings of slightly different stiffness: its lowest forward mode at the centre of
mass is nearly a pure tilt (the centre barely moves: a cross-coupling there hardly reaches it),
the second nearly a pure translation, which the cross-coupling drives unstable.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

MASS, DIAMETRAL = 50.0, 5.0
BEARINGS = ((0.25, 1.0e6, 300.0), (-0.25, 1.2e6, 300.0))      # (position x [m], stiffness, damping)
QA, MCS = 8.0e4, 3000 * np.pi / 30

MODEL = f"""
name = "rigid rotor, two forward modes"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = {MASS}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 1.0e-9
diametral_inertia = {DIAMETRAL}
speed_ratio = 1.0
""" + "".join(f"""
[[bearings]]
name = "B{i}"
rotor = "rotor"
position = [{x}, 0.0, 0.0]
stiffness = {k}
damping = {c}
""" for i, (x, k, c) in enumerate(BEARINGS))


def roots(q):
    """Eigenvalues of the rotor written out here: translations y, z of the centre of mass and
    tilts theta_z, theta_y (a bearing at x moves by y + x theta_z and z - x theta_y), the
    cross-coupling q [N/m] between y and z at the centre of mass; shape (8,)."""
    K, C = np.zeros((4, 4)), np.zeros((4, 4))
    for x, k, c in BEARINGS:
        for rows, sign in (([0, 1], 1.0), ([2, 3], -1.0)):      # (y, theta_z), (z, theta_y)
            arm = np.array([1.0, sign * x])
            K[np.ix_(rows, rows)] += k * np.outer(arm, arm)
            C[np.ix_(rows, rows)] += c * np.outer(arm, arm)
    K[0, 2] += q
    K[2, 0] -= q
    M = np.diag([MASS, DIAMETRAL, MASS, DIAMETRAL])
    A = np.block([[np.zeros((4, 4)), np.eye(4)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    return np.linalg.eigvals(A)


def threshold() -> float:
    """The machine's Q0 [N/m]: where its first root crosses into the right half-plane."""
    return brentq(lambda q: roots(q).real.max(), 1.0, 1e7, xtol=1e-6)


def least_log_decrement(q) -> float:
    """The lowest log decrement of the machine's modes at cross-coupling ``q`` [N/m]."""
    lam = roots(q)
    lam = lam[lam.imag > 0]
    return float((-2 * np.pi * lam.real / lam.imag).min())


def write_model(folder):
    """The model file in ``folder`` (a pathlib.Path); returns its path."""
    path = folder / "two_forward_modes.toml"
    path.write_text(MODEL, encoding="utf-8")
    return path
