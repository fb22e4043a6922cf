"""Repeated eigenvalues of an axisymmetric machine: circular modes, one each way.

A rigid rotor on two isotropic supports has a double cylindrical eigenvalue at every speed:
any combination of its two shapes is a mode. The package must report the forward and
backward circular combinations (whirl ratios exactly +1 and -1), whatever basis the
eigen-solver happened to return, in ``modal``, in ``campbell`` and at critical speeds.
Closed form of the cylindrical frequency: sqrt(2 k / m).
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm

MASS, K = 50.0, 1.0e6


@pytest.fixture
def rotor_on_isotropic_supports():
    return rdm.Model(
        rotors=[rdm.Rotor("r", MASS, [0.0, 0.0, 0.0], 0.39, 0.86, speed_ratio=1.0)],
        suspensions=[rdm.Suspension("a", [0.25, 0, 0], [1e3, K, K, 10.0, 0, 0]),
                     rdm.Suspension("b", [-0.25, 0, 0], [1e3, K, K, 10.0, 0, 0])],
    )


def _cylindrical(frequencies_hz):
    expected = np.sqrt(2 * K / MASS) / (2 * np.pi)
    return np.nonzero(np.isclose(frequencies_hz, expected, rtol=1e-12))[0]


@pytest.mark.parametrize("speed_rpm", [0.0, 3000.0, -3000.0])
def test_modal_reports_one_forward_and_one_backward_circular_mode(rotor_on_isotropic_supports, speed_rpm):
    modes = rdm.modal(rotor_on_isotropic_supports, rdm.rpm(speed_rpm))
    pair = _cylindrical(modes.frequencies_hz)
    assert len(pair) == 2
    np.testing.assert_allclose(np.sort(modes.whirl_ratios[pair]), [-1.0, 1.0], atol=1e-9)
    assert sorted(modes.whirl[pair]) == ["backward", "forward"]


def test_campbell_and_critical_speeds_have_one_forward_and_one_backward(rotor_on_isotropic_supports):
    result = rdm.campbell(rotor_on_isotropic_supports, rdm.rpm(np.linspace(0, 10000, 51)))
    for k in range(len(result.speeds)):
        pair = _cylindrical(result.frequencies_hz[k])
        assert sorted(result.whirl[k, pair]) == ["backward", "forward"]
    omega = np.sqrt(2 * K / MASS)
    at_cylindrical = np.isclose(result.critical.speeds, omega, rtol=1e-10)
    assert sorted(result.critical.whirl[at_cylindrical]) == ["backward", "forward"]
