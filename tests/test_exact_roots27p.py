"""Exact roots where the rest of the code reads them (issue 27 §1, issue 28 §4 "exactly, to 1e-9"):
a stability threshold is the zero of the crossing root's own real part (not where it reaches the
sweep's round-off level), in ``stability``, ``stability_map`` and ``stability(modes=N)``; the
lowest-modes route (``campbell``/``stability`` with ``modes=N``) polishes the roots its extended
residual leaves inexact as the full solve does (``_lowest_newton._exactly_polished``).

Truth from outside the code: mpmath Newton solves of the models' matrices (as doubles), in 34 to
40 digits, on the bordered system ``[[T(s), T'(s) x], [c^H, 0]]``, and secant steps on the speed for
``Re s = 0`` (the constants of ``tests/test_exact_roots27o.py`` and the scripts beside roots27o's
report, ``notes/reports15/roots27o_scripts/mp_pair.py`` and ``mp_thr.py``; the threshold's solve
was run again for this file and gave the same digits).
"""

from __future__ import annotations

import warnings

import numpy as np

import rotordyn_modal as rdm

from test_exact_roots27l import _maxwell_model
from test_exact_roots27o import (PAIR_HZ, PAIR_REAL, SPEED, THRESHOLD_RPM, _cross_coupled_model,
                                 _lowest_pair)

SWEEP = rdm.rpm(np.linspace(0.0, 6000.0, 13))


def _quiet(call):
    """``call()``, and the messages of every warning it gave that says a root is inexact."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call()
    return result, [str(w.message) for w in caught if "exact only to" in str(w.message)]


def _rpm(thresholds):
    return np.asarray(thresholds) * 30 / np.pi


def test_stability_map_threshold_is_the_real_parts_zero():
    """The map reads ``stability``'s thresholds: main put the 1 mm shaft's at 2,085.7999333 rpm,
    where the forward mode's real part reaches the sweep's round-off level (3.7e-9 1/s: a torsion
    mode's real part is 0 below the threshold, so the largest real part was marginal and only the
    predicate "beyond round-off" was bisected), 6.7e-8 past the zero of the real part."""
    result, _ = _quiet(lambda: rdm.stability(_cross_coupled_model(), SWEEP, vary="bearings.b0.damping",
                                             scale=[1.0]))
    found = _rpm(result.results[0].thresholds)
    assert len(found) == 1 and result.results[0].threshold_onsets[0]
    assert abs(found[0] - THRESHOLD_RPM) < 1e-10 * THRESHOLD_RPM, found


def test_lowest_modes_threshold_is_the_real_parts_zero():
    """``stability(modes=4)`` refined the threshold on the lowest route's roots, which the
    extended residual left 1.8e-8 off (warned): 2,085.79979145 rpm, 1.06e-9 below the truth."""
    result, warned = _quiet(lambda: rdm.stability(_cross_coupled_model(), SWEEP, modes=4))
    found = _rpm(result.thresholds)
    assert len(found) == 1 and result.threshold_onsets[0]
    assert abs(found[0] - THRESHOLD_RPM) < 1e-10 * THRESHOLD_RPM, found
    assert warned == []


def test_lowest_modes_polish_the_maxwell_pair():
    """``campbell(modes=4)`` on the Maxwell model: main left its lowest pair 1.3e-5 and 6.5e-6 off
    (the one-root polish cannot tell two roots 6.5e-5 apart, round-off 2e-4, and quadratic pencils
    only were polished in pairs) and warned. Now within 1e-12 of the 40-digit solve."""
    result, warned = _quiet(lambda: rdm.campbell(_maxwell_model(), np.array([SPEED]), critical=False, modes=4))
    pair = _lowest_pair(result.eigenvalues[0])
    assert np.abs(pair.imag / (2 * np.pi) - PAIR_HZ).max() < 1e-12 * PAIR_HZ.max()
    assert np.abs(pair.real - PAIR_REAL).max() < 1e-12 * np.abs(pair).max()
    assert warned == []


def test_lowest_modes_stability_map_log_decrements():
    """``stability_map(modes=4)``: the pair's log decrements, whose real parts main left up to
    2.7e-6 |s| off (a log decrement 24 % off), now within 1e-8 of the truth's."""
    result, warned = _quiet(lambda: rdm.stability(_maxwell_model(), np.array([SPEED, SPEED + 1.0]),
                                                  vary="bearings.b0.stiffness", scale=[1.0], modes=4))
    run = result.results[0]
    order = np.argsort(run.eigenvalues[0].imag)[:2]
    truth = -PAIR_REAL / PAIR_HZ                               # -2 pi Re s / Im s
    assert np.abs(run.log_decrements[0][order] - truth).max() < 1e-8 * truth.max()
    assert warned == []
