"""The UCS map on very soft bearings (redteam11, issue 27 §1.1): a rigid rotor's cylindrical and
conical critical speeds to the closed form, where the map's Cholesky of ``K`` (condition about
1e13 on bearings of 1e-3 N/m beside a shaft's 1e10 N/m, and ``K_rest + k K_unit`` formed in double
losing ``k``) left them 0.03 % off and unsmooth, and the shaft modes 1e-6 off.

Truth from outside the code: a uniform steel shaft (1 m, 50 mm, 7800 kg/m^3; m = rho pi r^2 L,
J_d = m (3 r^2 + L^2) / 12 about its middle, J_p = m r^2 / 2) on two isotropic springs ``k`` at
0.125 m and 0.875 m (a = 0.375 m from the middle). As ``k -> 0`` the shaft is rigid and the
forward synchronous critical speeds are the roots of the 2 x 2 pencil of translation and tilt,
``K2 = [[2k, 0], [0, 2 k a^2]]``, ``M2 = diag(m, J_d - J_p)`` (the forward whirl's tilt inertia).
The shaft's own stiffness matrix, rounded to double, does not vanish on a rigid tilt exactly
(its entries of 1e10 N/m rounded leave about 1e-8 N m/rad, 1e-5 of ``2 k a^2`` at 1e-3 N/m, which
no solve of these matrices can remove): its translation/tilt quadratic forms on the exact rigid
motions (node spacing 1/16 m, every coordinate exact in binary), summed in exact rational
arithmetic, are added to ``K2`` (first order: their coupling to the shaft's modes moves the
roots by 1e-22 of them). The shaft's flexibility moves the roots by ``k`` over its own stiffness,
2.4e-11 at 1e-3 N/m.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import ucs_map as ucs

from test_input_families10 import _shaft_model

RHO, RADIUS, LENGTH, ARM = 7800.0, 0.025, 1.0, 0.375
STIFFNESS = np.array([1e-3, 10 ** -2.5, 1e-2])


def _model(tmp_path):
    path = _shaft_model(tmp_path / "shaft.toml", [(LENGTH, 2 * RADIUS)], [0.5 - ARM, 0.5 + ARM], 1e6,
                        element_length=0.0625)
    return rdm.load_model(path)


def _rigid_motions(n):
    """The exact rigid translation and tilt (about the middle) in one plane, (2, n): coordinates
    are ``uy, uz, ry, rz`` per node at 0, 1/16, ... 1 m (a tilt turning ``uy`` has ``rz`` = +1)."""
    z = np.arange(n // 4) / 16.0
    translation, tilt = np.zeros(n), np.zeros(n)
    translation[0::4] = 1.0
    tilt[0::4], tilt[3::4] = z - 0.5, 1.0
    return translation, tilt


def _exact_form(A, x, y):
    rows, cols = np.nonzero(A)
    return float(sum(Fraction(A[i, j]) * Fraction(x[i]) * Fraction(y[j]) for i, j in zip(rows, cols)
                     if x[i] != 0 and y[j] != 0))


def _shaft_forms(model):
    """(2, 2): the rounded stiffness matrix without the bearings' radial part, on the rigid
    translation and tilt, exactly."""
    parts = ucs._Pencil(model, list(model.bearings))
    t, r = _rigid_motions(parts.M.shape[0])
    return np.array([[_exact_form(parts.rest, a, b) for b in (t, r)] for a in (t, r)])


def _closed_form(rest, k):
    """(cylindrical, conical) forward critical speeds [rad/s] at bearing stiffness ``k`` (see the
    module docstring), with the rounded shaft matrix's own forms ``rest`` (2, 2) on the rigid motions."""
    mass = RHO * math.pi * RADIUS ** 2 * LENGTH
    jd, jp = mass * (3 * RADIUS ** 2 + LENGTH ** 2) / 12.0, mass * RADIUS ** 2 / 2.0
    K2 = np.array([[2 * k, 0.0], [0.0, 2 * k * ARM ** 2]]) + rest
    values = np.linalg.eigvals(np.diag([1 / mass, 1 / (jd - jp)]) @ K2).real
    return np.sqrt(np.sort(values))


def test_rigid_modes_on_soft_bearings_are_the_closed_form(tmp_path):
    """Main: 2e-4 (cylindrical) and 3e-4 (conical) off at 1e-3 N/m."""
    model = _model(tmp_path)
    found = rdm.ucs_map(model, STIFFNESS, modes=4)
    rest = _shaft_forms(model)
    for row, k in enumerate(STIFFNESS):
        exact = _closed_form(rest, k)
        error = np.abs(found.speeds[row, :2] / exact - 1)
        assert error.max() < 1e-9, (k, error)
        # what the rounded shaft matrix itself moves: nothing for the translation, 1e-5 for the tilt
        assert rest[0, 0] == 0.0 and abs(rest[1, 1]) < 3e-5 * 2 * k * ARM ** 2
    assert found.mode_names[:2] == ("s cylindrical", "s conical")


def test_rigid_modes_scale_as_the_square_root_of_the_stiffness(tmp_path):
    """Both rigid modes' curves are straight lines of slope 1/2 on the log-log map (with 21 values
    from 1e-3 to 1e-2 N/m: main's zig-zagged by 2e-4, its names swapping on other sweeps), the
    shaft modes flat (main: 1e-6 apart)."""
    model = _model(tmp_path)
    grid = np.geomspace(1e-3, 1e-2, 21)
    found = rdm.ucs_map(model, grid, modes=4)
    rest = _shaft_forms(model)
    exact = np.array([_closed_form(rest, k) for k in grid])
    assert np.abs(found.mode_speeds[:, :2] / exact - 1).max() < 1e-9
    shaft = found.mode_speeds[:, 2:4]
    assert np.abs(shaft / shaft[0] - 1).max() < 1e-9, shaft
