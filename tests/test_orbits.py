"""Orbits at probe pairs against closed forms: a rigid symmetric rotor on two bearings to ground.

Undamped, unbalance U at the centre of mass, spin about +x: the centre's response along a
bearing axis with stiffness k (two bearings) is U w^2 / (2 k - m w^2). Isotropic bearings give a
circular forward orbit; anisotropic ones (k_y < k_z) an ellipse on the y and z axes, which
precesses *backward* between the two critical speeds (both responses change sign at different
speeds) and forward outside them.
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm

MASS, UNBALANCE, HALF = 10.0, 2e-4, 0.15


def _model(ky, kz, probe_angle_deg=90.0):
    second = np.radians(probe_angle_deg)
    return rdm.Model.from_dict({
        "spin_axis": [1.0, 0.0, 0.0],
        "rotors": [{"name": "r", "mass": MASS, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.05,
                    "diametral_inertia": 0.2, "speed_ratio": 1.0}],
        "bearings": [{"name": n, "rotor": "r", "position": [s, 0.0, 0.0], "stiffness": [ky, kz]}
                     for n, s in (("A", HALF), ("B", -HALF))],
        "unbalances": [{"rotor": "r", "amount": UNBALANCE}],
        "sensors": [
            {"name": "x", "position": [0.0, 0.0, 0.0], "direction": [0.0, 1.0, 0.0], "rotor": "r"},
            {"name": "y", "position": [0.0, 0.0, 0.0], "direction": [0.0, np.cos(second), np.sin(second)],
             "rotor": "r"},
            {"name": "tilted", "position": [0.0, 0.0, 0.0], "direction": [0.3, 0.0, 1.0], "rotor": "r"},
        ],
    })


@pytest.mark.parametrize("angle", [90.0, 60.0, 135.0])
def test_isotropic_bearings_give_circular_forward_orbits(angle):
    k = 2e6
    speeds = np.array([150.0, 420.0, 700.0])           # below and above sqrt(2k/m) = 632 rad/s
    orbits = rdm.unbalance_response(_model(k, k, angle), speeds).orbits()
    radius = np.abs(UNBALANCE * speeds**2 / (2 * k - MASS * speeds**2))
    np.testing.assert_allclose(orbits["major"], radius, rtol=1e-10)
    np.testing.assert_allclose(orbits["minor"], radius, rtol=1e-10)
    assert list(orbits["precession"]) == ["forward"] * 3
    assert list(orbits["pair"]) == ["x/y"] * 3               # the tilted sensor pairs with nothing


def test_anisotropic_bearings_precess_backward_between_the_two_critical_speeds():
    ky, kz = 1e6, 3e6
    low, high = np.sqrt(2 * ky / MASS), np.sqrt(2 * kz / MASS)
    speeds = np.array([0.5 * low, 0.5 * (low + high), 1.5 * high])
    orbits = rdm.unbalance_response(_model(ky, kz), speeds).orbits()
    along_y = np.abs(UNBALANCE * speeds**2 / (2 * ky - MASS * speeds**2))
    along_z = np.abs(UNBALANCE * speeds**2 / (2 * kz - MASS * speeds**2))
    np.testing.assert_allclose(orbits["major"], np.maximum(along_y, along_z), rtol=1e-10)
    np.testing.assert_allclose(orbits["minor"], np.minimum(along_y, along_z), rtol=1e-10)
    np.testing.assert_allclose(orbits["inclination_deg"], np.where(along_y > along_z, 0.0, 90.0), atol=1e-8)
    assert list(orbits["precession"]) == ["forward", "backward", "forward"]
    # reversing the spin reverses the orbit and the spin together: precession is unchanged
    reversed_ = rdm.unbalance_response(_model(ky, kz), -speeds).orbits()
    assert list(reversed_["precession"]) == ["forward", "backward", "forward"]


def test_orbit_figure_draws_every_pair(tmp_path):
    result = rdm.unbalance_response(_model(1e6, 3e6), np.linspace(100, 1000, 50))
    figure = result.plot_orbits()
    assert len([ax for ax in figure.axes if ax.get_visible()]) == 1
    figure.savefig(tmp_path / "orbits.png")


def test_the_orbit_figure_draws_the_circle_turning_forward():
    """Isotropic bearings, 150 rad/s: the drawn orbit is the circle of the closed-form radius
    (in the figure's unit), and its arrow turns from the first probe's direction towards
    e x u, the way the rotor whirls (forward, about +x)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.orbits import _SCALE

    k, speed = 2e6, 150.0
    result = rdm.unbalance_response(_model(k, k), np.array([speed]))
    fig = result.plot_orbits(speeds=[speed])
    ax = fig.axes[0]
    path = np.column_stack([ax.get_lines()[0].get_xdata(), ax.get_lines()[0].get_ydata()])
    radius = UNBALANCE * speed**2 / (2 * k - MASS * speed**2) * _SCALE[result.quantity][0]
    np.testing.assert_allclose(np.hypot(*path.T), radius, rtol=1e-9)
    arrow, = [a for a in ax.texts if getattr(a, "arrow_patch", None) is not None]
    tail, head = np.asarray(arrow.xyann, float), np.asarray(arrow.xy, float)
    step = head - tail
    assert tail[0] * step[1] - tail[1] * step[0] > 0             # counter-clockwise in (u, e x u)
    plt.close(fig)
