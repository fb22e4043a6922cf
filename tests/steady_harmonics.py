"""Test helper: the steady harmonics of a simulated run against ``rdm.unbalance_response``."""

from __future__ import annotations

import numpy as np

import rotordyn_modal as rdm


def assert_steady_harmonics_equal_the_linear_response(res, model, speed, after, rtol):
    """Fit ``A cos(w t) + B sin(w t)`` at every rotor's own frequency ``w`` (and a constant) to
    each sensor's signal after ``after`` [s]; each complex amplitude ``A - iB`` must equal the
    linear unbalance response's ``amplitude * exp(i phase)`` to ``rtol``."""
    linear = rdm.unbalance_response(model, [speed])
    last = res.time > after
    t = res.time[last]
    frequencies = [abs(model.speed_ratios[s] * speed) for s in linear.sources]
    basis = np.column_stack([f(w * t) for w in frequencies for f in (np.cos, np.sin)] + [np.ones_like(t)])
    for i, name in enumerate(linear.outputs):
        coefficients, *_ = np.linalg.lstsq(basis, res.sensor(name)[last], rcond=None)
        for j in range(len(linear.sources)):
            simulated = coefficients[2 * j] - 1j * coefficients[2 * j + 1]   # A cos(wt + p) -> A e^{ip}
            expected = linear.amplitude[i, j, 0] * np.exp(1j * np.radians(linear.phase_deg[i, j, 0]))
            assert abs(simulated - expected) < rtol * abs(expected), (name, linear.sources[j])
