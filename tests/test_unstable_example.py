"""The shipped unstable example against the closed form of its threshold speed.

Derivation (docs/theory.md, "Stability of the cross-coupled example"): the machine is
axisymmetric about the spin axis x through its centre of mass, so the tilts obey, with
z = theta_y + i theta_z,

    J_t z'' + (c_t - i Omega J_p) z' + (k_t - i q_t) z = 0,

c_t = 2 a^2 c, k_t = 2 a^2 k, q_t = 2 a^2 q for two supports at x = +-a. On the boundary
lambda = i w: c_t w = q_t, so w = q / c, and J_t w^2 - Omega J_p w - k_t = 0 gives

    Omega* = (k_t - J_t w^2) / (J_p |w|)        (q < 0: the backward mode, w < 0).
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm

A = 0.2          # m, support offset
K = 1.0e5        # N/m
Q = -8.0e3       # N/m, cross-coupling
C = 200.0        # N s/m
J_T = 1.5 + 0.08  # stator Iyy + rotor Jd, kg m^2
J_P = 0.12


def closed_form_threshold(polar_inertia=J_P, damping=C):
    w = Q / damping
    k_t = 2 * A**2 * K
    return (k_t - J_T * w**2) / (polar_inertia * abs(w))


@pytest.fixture
def model(examples_dir):
    return rdm.load_model(examples_dir / "unstable_cross_coupled.toml")


def test_threshold_speed_matches_closed_form(model):
    result = rdm.stability(model, rdm.rpm(np.linspace(0, 20000, 101)))
    assert result.threshold_speed == pytest.approx(closed_form_threshold(), rel=1e-9)
    onset = np.nonzero(result.threshold_onsets)[0]
    assert len(onset) == 1
    mode = result.threshold_modes[onset[0]]
    assert result.whirl[-1, mode - 1] == "backward"


def test_stable_below_and_unstable_above(model):
    threshold = closed_form_threshold()
    below = rdm.modal(model, 0.99 * threshold)
    above = rdm.modal(model, 1.01 * threshold)
    assert np.all(below.eigenvalues.real < 0)
    assert np.sum(above.eigenvalues.real > 0) == 1


def test_map_boundary_over_polar_inertia_matches_closed_form(model):
    factors = np.array([0.6, 0.8, 1.0, 1.2])
    result = rdm.stability_map(model, rdm.rpm(np.linspace(0, 30000, 61)),
                               "rotors.rotor.polar_inertia", scale=factors)
    expected = [closed_form_threshold(polar_inertia=J_P * f) for f in factors]
    np.testing.assert_allclose(result.threshold_speeds, expected, rtol=1e-9)


def test_whirl_frequency_at_threshold_is_q_over_c(model):
    threshold = closed_form_threshold()
    modes = rdm.modal(model, threshold)
    critical = np.argmin(np.abs(modes.eigenvalues.real))
    assert modes.eigenvalues[critical].imag == pytest.approx(abs(Q / C), rel=1e-9)
    assert modes.whirl[critical] == "backward"


def test_the_command_line_reports_the_threshold_in_rpm_to_eight_digits(examples_dir, capsys):
    """``rotordyn-modal stability`` prints where the mode loses stability, in rpm to 8
    significant digits: the closed form's."""
    import re

    from rotordyn_modal.cli.main import main

    assert main(["stability", str(examples_dir / "unstable_cross_coupled.toml"), "--speeds", "0:20000:101",
                 "--out", "-"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "stability at" in line]
    assert len(lines) == 1 and " loses stability at " in lines[0]
    printed = float(re.search(r"stability at ([0-9.e+]+) rpm", lines[0]).group(1))
    assert printed == float(f"{rdm.to_rpm(closed_form_threshold()):.8g}")


def test_the_stability_figure_marks_the_threshold_where_the_closed_form_puts_it(model):
    """Both panels (real parts, log decrements) draw a vertical line at the threshold speed in
    the figure's unit, and the real parts are drawn against speed in that unit."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = rdm.stability(model, rdm.rpm(np.linspace(0, 20000, 101)))
    fig = result.plot()
    threshold_rpm = rdm.to_rpm(closed_form_threshold())
    for axis in fig.axes[:2]:
        verticals = [line.get_xdata()[0] for line in axis.get_lines()
                     if len(line.get_xdata()) == 2 and line.get_xdata()[0] == line.get_xdata()[1]]
        assert verticals == pytest.approx([threshold_rpm], rel=1e-9)
    curves = [line for line in fig.axes[0].get_lines() if len(line.get_xdata()) == 101]
    np.testing.assert_allclose(curves[0].get_xdata(), np.linspace(0, 20000, 101), rtol=1e-12)
    plt.close(fig)
