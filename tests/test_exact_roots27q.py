"""The full solve's roots right to 1e-9 where the state matrix's QR leaves them further off than
the pencil's first-order round-off says (issue 27 §1, issue 28 §4).

``tests/data/ross/hrs113.toml``: a random ROSS 3.1 rotor on bearings of 1e9 to 1e12 N/m (made by
a red-team generator). At rest its lowest pair (52.62 rad/s) is 1.1e-5 apart and lightly damped:
the QR left both roots 1.6e-6 and 1.9e-6 off (real parts 32 % and 66 %, log decrements likewise)
while the estimate said 1.4e-8, so nothing was polished or warned. Truth: 30-digit Newton
(``mpmath.lu_solve`` on the bordered system) on the imported model's own ``M``, ``C``, ``K``
(``notes/reports16/roots27q_scripts/mp_roots.py``).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _eigensolve
from rotordyn_modal.cli import main
from rotordyn_modal.linear_system import speed_linear_form

from test_exact_roots27l import _maxwell_model

ROSS = Path(__file__).parent / "data" / "ross" / "hrs113.toml"
#: hrs113 at rest, the lowest pair [1/s] (30-digit Newton)
PAIR = np.array([complex(-0.00026591693700500474823, 52.623427938378731835),
                 complex(0.00012739773279070746651, 52.62352939754164133)])
#: ``_maxwell_model`` at 3,000 rpm, the pair near 5 rad/s [1/s]: 30-digit Newton on the rational
#: pencil (``notes/reports16/roots27p_scripts/mp_34.py``); the full solve left it 4.3e-9 off
MAXWELL_PAIR = np.array([complex(-0.00008513885361192076818837588, 2 * np.pi * 0.7947609454474847498228374),
                         complex(-0.00008532523726247567748076869, 2 * np.pi * 0.7966173939722452983594184)])


def _imported(tmp_path):
    out = tmp_path / "hrs113.toml"
    assert main(["import-ross", str(ROSS), "--out", str(out), "--quiet"]) == 0
    return rdm.load_model(out)


def _nearest(values, truth):
    values = np.asarray(values).ravel()
    return np.array([values[np.argmin(np.abs(values - t))] for t in truth])


def test_modal_pair_on_stiff_bearings(tmp_path):
    """``modal``: the pair within 1e-9 (relative), its log decrements within 1e-6 (main: 1.9e-6
    and 66 %), without a warning (the roots are polished, not left)."""
    model = _imported(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = rdm.modal(model, 0.0)
    found = _nearest(result.eigenvalues, PAIR)
    assert np.all(np.abs(found - PAIR) <= 1e-9 * np.abs(PAIR))
    assert np.allclose(-2 * np.pi * found.real / found.imag, -2 * np.pi * PAIR.real / PAIR.imag, rtol=1e-6, atol=0)


def test_estimate_sees_the_qr_error(tmp_path):
    """The estimate of the raw solve's pair (the state matrix's QR, unpolished) is at least a third
    of its true error (main: 1.4e-8 against 1.9e-6, 130 times low)."""
    model = _imported(tmp_path)
    form = speed_linear_form(model)
    values, vectors = _eigensolve.eig(form.at(0.0))
    upper = _eigensolve.select_upper(values)
    index = [int(np.argmin(np.abs(values - lam))) for lam in upper]
    shapes = vectors[:form.n_dof, index].T
    bound, *_ = _eigensolve.round_off_at(form, 0.0, upper, shapes)
    for truth in PAIR:
        j = int(np.argmin(np.abs(upper - truth)))
        error = abs(upper[j] - truth) / abs(truth)
        assert error > 1e-7                     # the case still needs the polish
        assert bound[j] >= error / 3


def test_full_campbell_and_stability(tmp_path):
    """The full Campbell route and ``stability`` read the same polished pair: roots within 1e-9,
    the log decrements within 1e-6."""
    model = _imported(tmp_path)
    speeds = np.array([0.0, 10.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        campbell = rdm.campbell(model, speeds, critical=False)
        stability = rdm.stability(model, speeds)
    found = _nearest(np.asarray(campbell.eigenvalues)[0], PAIR)
    assert np.all(np.abs(found - PAIR) <= 1e-9 * np.abs(PAIR))
    found = _nearest(np.asarray(stability.eigenvalues)[0], PAIR)
    decrements = np.asarray(stability.log_decrements)[0]
    j = [int(np.argmin(np.abs(np.asarray(stability.eigenvalues)[0] - t))) for t in PAIR]
    assert np.all(np.abs(found - PAIR) <= 1e-9 * np.abs(PAIR))
    assert np.allclose(decrements[j], -2 * np.pi * PAIR.real / PAIR.imag, rtol=1e-6, atol=0)


def test_maxwell_pair_full_solve():
    """The Maxwell model's pair near 5 rad/s from ``modal`` (its estimate between 1e-9 and
    1e-6: left as the QR gave it on main, 4.3e-9 off) within 1e-11 of the 30-digit roots."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rdm.modal(_maxwell_model(), rdm.rpm(3000.0))
    found = _nearest(result.eigenvalues, MAXWELL_PAIR)
    assert np.all(np.abs(found - MAXWELL_PAIR) <= 1e-11 * np.abs(MAXWELL_PAIR))
