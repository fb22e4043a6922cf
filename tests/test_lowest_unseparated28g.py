"""The lowest modes' error estimate bounds the error of two roots closer than double precision
can tell apart (issue 28 §4, redteam10's "1 mm section"). A 10 m shaft meshed around a 1 mm
section on 1e3 N/m undamped bearings has at 3,000 rpm a pair of roots 6.5e-5 apart whose
double-precision round-off is 2e-4: the polish (residual in extended precision, solves in
double) cannot separate them, and ``campbell(modes=4)`` gave them 2.4e-5 and 1.7e-5 off while
its warning said "exact only to about 1.0e-07".

Truth from outside the code: the roots of the same pencil (the model's M, C + Omega G, K as
doubles) in 40-digit arithmetic, by mpmath 1.3.0 (``mpmath.eig`` of the state matrix built with
``mpmath`` from ``M^-1 K`` and ``M^-1 (C + Omega G)``, ``mp.dps = 40``; 150 s, so stored here):
"""

from __future__ import annotations

import warnings

import numpy as np

import rotordyn_modal as rdm

from test_input_families10 import _shaft_model

#: the four lowest frequencies [Hz] at 3,000 rpm, mpmath (see the module's docstring)
TRUTH_HZ = np.array([0.553245067741, 0.553281054653, 0.795006681631, 0.796863109821])


def test_the_warned_accuracy_bounds_the_error_of_an_unseparated_pair(tmp_path):
    path = _shaft_model(tmp_path / "shaft.toml", [(5.0, 0.05), (0.001, 0.05), (4.999, 0.05)], [1.0, 9.0],
                        1e3, element_length=1.0)
    model = rdm.load_model(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.campbell(model, rdm.rpm(np.array([3000.0])), modes=4, critical=False)
    found = np.sort(result.frequencies_hz[0])
    error = np.abs(found - TRUTH_HZ) / TRUTH_HZ
    warned = [str(w.message) for w in caught if "exact only to about" in str(w.message)]
    # the pair polished together (cond28h, ``_lowest_newton.pair_polished``): within 1e-9 as the others;
    # the roots the extended residual left inexact polished as the full solve's (roots27p): none warned of
    assert warned == [], warned
    assert error.max() < 1e-9, error
