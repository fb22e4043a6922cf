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


def _cut_shaft(cuts=6, element=0.07):
    """The 10 m shaft of ``_cross_coupled_model`` with ``cuts`` 1 mm sections spread along it, meshed
    at ``element`` [m] (624 coordinates): ten inexact roots at 3,000 rpm, a big machine's polish."""
    step = 10.0 / (cuts + 1)
    return rdm.Model.from_dict({
        "name": "1 mm sections on cross-coupled bearings", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "s",
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2.0e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "element_length": element,
                    "shear": "none", "shaft": [{"length": L, "outer_diameter": 0.05, "material": "steel"}
                                               for L in [step] + [0.001, step - 0.001] * cuts]}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "stiffness": 1e3, "damping": 10.0}
                     for i, z in enumerate((1.0, 9.0))]})


def test_a_big_machines_polish_costs_about_its_solve(monkeypatch):
    """On 624 coordinates with ten inexact roots a speed, main polished all ten (``POLISH_WORK`` =
    10 eigen-solves, one root counted as one): 68 % of the run's CPU. The budget falls with size
    (``polish_budget``: 2 from about 540 coordinates) and a root counts ``sqrt(240 / n)`` (measured:
    0.34 of a solve at 600). Since roots32 the single roots are polished together
    (``BATCHED_ROOT_WORK``, 0.2 of a root's work) and a sparse pencil (this meshed shaft: 7,406 of
    389,376 entries) by sparse LUs (``SPARSE_ROOT_WORK`` a root): all 46 roots over 1e-9 within the
    budget, none by the dense block polish, nothing warned. Made dense, the budget takes the pair
    (1.24, the dense block) and six single roots (0.124 each), and the others are warned of."""
    from rotordyn_modal.analysis import _eigensolve, _lowest_newton

    calls = []
    original = _lowest_newton.block_polished

    def counted(M, damping, stiffness, roots, shapes, branches=None):
        calls.append(len(roots))
        return original(M, damping, stiffness, roots, shapes, branches)

    monkeypatch.setattr(_lowest_newton, "block_polished", counted)
    model = _cut_shaft()
    assert model.dofs.n > 540
    result, warned = _quiet(lambda: rdm.campbell(model, np.array([SPEED]), critical=False))
    assert calls == [] and warned == [], (calls, warned)
    monkeypatch.setattr(_eigensolve, "_SPARSE_SHARE", 0.0)
    result, warned = _quiet(lambda: rdm.campbell(model, np.array([SPEED]), critical=False))
    assert calls == [2], calls
    assert len(warned) == 1 and "3,000 rpm" in warned[0], warned
