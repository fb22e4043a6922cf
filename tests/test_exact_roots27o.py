"""Exact roots wherever they are read (issue 27 §1, issue 28 §4 "exactly, to 1e-9"): a cluster of
roots closer than their round-off polished together on the rational pencil of Maxwell branches
(``_lowest_newton.block_polished(..., branches)``), the critical speeds and ``stability``'s
thresholds and log decrements refined on the polished roots, and the polish's work capped per
speed (``_polish_plan.POLISH_WORK``), past which the roots are warned of as before.

Truth from outside the code: mpmath 1.3.0 Newton solves of the models' matrices (as doubles) on
the bordered system ``[[T(s), T'(s) x], [c^H, 0]]`` with ``mpmath.lu_solve``, ``T(s) = M s^2 +
(C + Omega G) s + K (+ sum_t K_t s tau_t / (1 + s tau_t))`` (the full ``(n, n)`` branch matrices
``form.branch_stiffness``, not the stator blocks the code polishes with), until the step is below
1e-34 (40 digits) or 1e-27 (30 digits); a critical speed or a threshold by secant steps on the
speed over those solves (``Im s = Omega``, ``Re s = 0``) until the speed's step is below 1e-22
relative (the scripts ``mp_pair.py``, ``mp_crit.py`` and ``mp_thr.py``, kept beside the helper's
report, ``notes/reports15/roots27o_scripts``).
"""

from __future__ import annotations

import re

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve, _polish_plan

from test_exact_roots27l import _caught, _maxwell_model

SPEED = rdm.rpm(3000.0)
#: the Maxwell model's lowest pair at 3,000 rpm, 40-digit Newton: frequency [Hz] and real part [1/s]
PAIR_HZ = np.array([0.553086505762741033200679, 0.553122449053800861556568])
PAIR_REAL = np.array([-3.850937285102517445137707e-05, -3.852243288660997973766916e-05])


def _lowest_pair(values):
    values = np.asarray(values)
    upper = values[values.imag > 0]
    return upper[np.argsort(upper.imag)][:2]


def test_maxwell_pair_block_polished():
    """Main: the pair 6.5e-5 apart, closer than its round-off (2.1e-4), was 3.6e-4 and 3.2e-4 off
    and warned. Now it is polished as a block on the rational pencil, within 1e-12, unwarned."""
    result, warned = _caught(lambda: rdm.campbell(_maxwell_model(), np.array([SPEED]), critical=False))
    pair = _lowest_pair(result.eigenvalues[0])
    error = np.abs(pair.imag / (2 * np.pi) - PAIR_HZ) / PAIR_HZ
    assert error.max() < 1e-12, error
    assert np.abs(pair.real - PAIR_REAL).max() < 1e-12 * np.abs(pair).max()
    assert warned == []


def test_stability_log_decrements_on_polished_roots():
    """``stability`` read the full solve's roots unpolished: the pair's real parts -4.11e-5 and
    -3.51e-5 (truth -3.85e-5 both: 7 % and 9 % off in their log decrements)."""
    # unstable at both speeds (a mode at 76 rad/s): no threshold to refine between them
    result, warned = _caught(lambda: rdm.stability(_maxwell_model(), np.array([SPEED, SPEED + 1.0])))
    order = np.argsort(np.where(result.eigenvalues[0].imag > 0, result.eigenvalues[0].imag, np.inf))[:2]
    pair = result.eigenvalues[0][order]
    assert np.abs(pair.imag / (2 * np.pi) - PAIR_HZ).max() < 1e-12 * PAIR_HZ.max()
    truth = -2 * np.pi * PAIR_REAL / (PAIR_HZ * 2 * np.pi)          # -2 pi Re s / Im s
    assert np.abs(result.log_decrements[0][order] - truth).max() < 1e-8 * truth.max()
    assert warned == []


def test_polish_work_is_capped_and_the_rest_warned(monkeypatch):
    """Past ``POLISH_WORK`` a speed, the roots are left as the solve gave them and warned of as
    before: with a budget of one eigen-solve, the pair (a block: 2) is not polished, and is named;
    of the single roots (polished together, ``BATCHED_ROOT_WORK`` each since roots32; 1 each one at
    a time before) only the lowest five, the others named with their bounds."""
    monkeypatch.setattr(_polish_plan, "POLISH_WORK", 1.0)
    calls = []
    original = _eigensolve.single_roots_polished

    def counted(*args, **kwargs):
        calls.append(len(args[3]))
        return original(*args, **kwargs)

    monkeypatch.setattr(_eigensolve, "single_roots_polished", counted)
    result, warned = _caught(lambda: rdm.campbell(_maxwell_model(), np.array([SPEED]), critical=False))
    assert calls == [int(1.0 / _polish_plan.BATCHED_ROOT_WORK)]
    # the head names the roots over 1e-6 (the pair), the tail each mode left over 1e-9 (roots32)
    assert len(warned) == 1 and "mode(s) 1, 2 at 3,000 rpm" in warned[0], warned
    assert len(re.findall(r"mode \d+ [0-9.]+e-\d+", warned[0])) > 2, warned
    pair = _lowest_pair(result.eigenvalues[0])
    assert np.abs(pair.imag / (2 * np.pi) - PAIR_HZ).max() > 1e-5 * PAIR_HZ.max()    # left as solved


def test_polish_work_counts_clusters():
    """The work model, in eigen-solves of the speed: one root 1, a pair 2, a cluster of k
    ``k^3 / 4``; the budget takes ten single roots, five pairs or a cluster of three with a pair."""
    assert _polish_plan.polish_work(1) == 1.0
    assert _polish_plan.polish_work(2) == 2.0
    assert _polish_plan.polish_work(3) + _polish_plan.polish_work(2) < _polish_plan.POLISH_WORK < _polish_plan.polish_work(4)


def _cross_coupled_model(q=100.0, c=10.0):
    """The 10 m shaft with its 1 mm section (``test_exact_roots27l``) on two bearings of 1e3 N/m and
    10 N s/m whose cross-coupled stiffness grows with speed, 0 to ``q`` N/m at 0 to 6,000 rpm: the
    forward bounce mode (3.48 rad/s) loses stability where ``q(Omega) / c`` passes its frequency."""
    return rdm.Model.from_dict({
        "name": "1 mm section on cross-coupled bearings", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "s",
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2.0e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0, "element_length": 1.0, "shear": "none",
                    "shaft": [{"length": L, "outer_diameter": 0.05, "material": "steel"} for L in (5.0, 0.001, 4.999)]}],
        "bearings": [{"name": f"b{i}", "rotor": "s", "axial_position": z, "speeds_rpm": [0.0, 6000.0],
                      "stiffness": [[[1e3, 0.0], [0.0, 1e3]], [[1e3, q], [-q, 1e3]]], "damping": [[c, c], [c, c]]}
                     for i, z in enumerate((1.0, 9.0))]})


#: the threshold [rpm]: 34-digit Newton on ``M s^2 + (C + Omega G) s + K(Omega)``, ``K`` the bearings'
#: table interpolated linearly in rpm (the code's rule) between ``stiffness_at`` 0 and 6,000 rpm,
#: secant steps on the speed for ``Re s = 0``
THRESHOLD_RPM = 2085.799793656464484041


def test_stability_threshold_on_polished_roots():
    """Main refined the threshold on the unpolished roots: 2,085.96877 rpm, 8.1e-5 off. Then
    (roots27o) on the polished ones, to where the forward mode's real part reached the sweep's
    round-off level (eps ||B||_1 = 3.7e-9 1/s: 1.4e-4 rpm past its zero). Now (roots27p) the zero
    of the crossing root's own real part, within 1e-9 of the 34-digit solve."""
    model = _cross_coupled_model()
    result, _ = _caught(lambda: rdm.stability(model, rdm.rpm(np.linspace(0.0, 6000.0, 13))))
    assert len(result.thresholds) == 1 and result.threshold_onsets[0]
    found = result.thresholds[0] * 30 / np.pi
    assert abs(found - THRESHOLD_RPM) < 1e-9 * THRESHOLD_RPM, (found, THRESHOLD_RPM)


#: the Maxwell model's 1x critical speeds of its lowest pair [rpm] and frequencies there [Hz],
#: backward then forward: 30-digit Newton on ``T(s)`` and secant steps for ``Im s = Omega``
CRITICAL_RPM = np.array([33.186257604386350228, 33.186281460845725812])
CRITICAL_HZ = np.array([0.55310429340643917046, 0.5531046910140954302])


def test_critical_speeds_on_polished_roots():
    """Main refined the pair's crossings on unpolished roots: 33.1749 rpm, 3.4e-4 off (and called
    two of them jumps between close roots). Now both are within 1e-9 of the 30-digit solve."""
    result, _ = _caught(lambda: rdm.campbell(_maxwell_model(), rdm.rpm(np.linspace(0.0, 120.0, 13))))
    table = result.critical.to_dataframe()
    low = table[(table["order"] == 1.0) & (table["speed_rpm"] < 40.0)].sort_values("speed_rpm")
    assert list(low["whirl"]) == ["backward", "forward"], low
    assert np.abs(low["speed_rpm"].to_numpy() - CRITICAL_RPM).max() < 1e-9 * CRITICAL_RPM.max()
    assert np.abs(low["frequency_hz"].to_numpy() - CRITICAL_HZ).max() < 1e-9 * CRITICAL_HZ.max()
