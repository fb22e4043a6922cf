"""A root just above the cut, closer than the projection's error (issue 28 §4). A 400-coordinate
shaft's lowest 6 modes at 31 speeds from 0 to 1,500 rad/s fell back to the full eigen-solve at
300 rad/s on every run ("1 of 31 speeds solved whole"): there the 6th and 7th roots are a pair
split by the speed, 4101.0 and 4102.8 rad/s, and the reduced basis moved the roots by up to 0.96
rad/s from their projected starts, so the highest start (the 7th, 4101.9) less that move did not
lie above the 6th root found: no check could show that no root was missed below the 6th. Such a
speed is now refined again from one more start (the 8th, far above), as a cut inside a double
root is.

Truth from outside the code: scipy's eigenvalues of the full state matrix (``shaft_models``).
"""

from __future__ import annotations

import warnings

import numpy as np

import rotordyn_modal as rdm

from shaft_models import assert_lowest_are_the_full_models, fan_shaft


def test_a_split_pair_just_above_the_cut_is_not_solved_whole():
    model = fan_shaft(400)
    assert model.dofs.n == 400
    speeds = np.linspace(0.0, 1500.0, 31)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = rdm.campbell(model, speeds, modes=6, critical=False)
    assert not [w for w in caught if "solved whole" in str(w.message)], [str(w.message) for w in caught]
    for k in (5, 6, 7):                              # 300 rad/s and its neighbours
        row = result.eigenvalues[k]                  # a column per root: NaN where not among the 6 (lowcol27q)
        assert_lowest_are_the_full_models(model, speeds[k], row[np.isfinite(row)], count=6)
