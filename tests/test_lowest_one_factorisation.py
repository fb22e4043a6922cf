"""The speeds between solved anchors on one factorisation a root (``docs/theory.md`` section 17,
step 3a): ROSS's ``compressor_example`` at 201 speeds, ``campbell(modes=12)``.

The start vectors are the nodes' shapes turned to one phase and interpolated in the speed, so
every carried-over root passes the chord step's test (no Newton's iteration after it), and the
anchors between the solved ones are carried over like the other speeds (no projected pencil of
their own) where four solved anchors give the cubic. Truth from outside the code: scipy's
eigenvalues of the full state matrix built here from ``model.matrices(speed)``."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_newton
from rotordyn_modal.io.ross_file import read_ross_rotor

from shaft_models import assert_lowest_are_the_full_models

DATA = Path(__file__).parent / "data" / "ross"
#: the span of the file's ROSS reference speeds [rad/s] (6,000-10,000 rpm) at 201 speeds, as bench_ross.py sweeps it
SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 201)


@pytest.fixture(scope="module")
def sweep():
    """The model, ``campbell(modes=12)`` of 201 speeds, the speeds (rows) and roots given to the
    one-factorisation refinement, the roots given to Newton's iteration, and the warnings."""
    path = DATA / "compressor_example.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    continued, newton, projected = _lowest._continued, _lowest_newton._newton, _lowest._projected_guesses
    chord, iterated = [], []

    def recording_continued(pencils, guesses, vectors, rows):
        chord.append(np.array(rows))
        return continued(pencils, guesses, vectors, rows)

    def recording_newton(pencils, index, lam, x):
        iterated.append(np.array(index))
        return newton(pencils, index, lam, x)

    def refused(*args, **kwargs):
        raise AssertionError("an anchor between solved ones took its own projected roots")

    _lowest._continued, _lowest_newton._newton, _lowest._projected_guesses = \
        recording_continued, recording_newton, refused
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = rdm.campbell(model, SPEEDS, critical=False, modes=12)
    finally:
        _lowest._continued, _lowest_newton._newton, _lowest._projected_guesses = continued, newton, projected
    return model, result, chord, iterated, [str(warning.message) for warning in caught]


def test_the_carried_over_roots_take_one_factorisation(sweep):
    """Every speed but the solved anchors is carried over, the anchors between the solved ones
    included, and at most 1 % of their roots go on to Newton's iteration after the chord step
    (measured: 7 of 2,405; with the nearest node's shape as the start vector 327 of 2,275, 14 %):
    Newton's iteration serves the solved anchors' 13 roots and those few. The solved anchors are
    the first speed, the last, and no more than 16 (every sixteenth speed, and those halfway where
    the Gershgorin discs do not show the count, ``_lowest._solved_levels``; before, every eighth:
    26)."""
    _, _, chord, iterated, caught = sweep
    assert not [message for message in caught if "solved whole" in message]
    carried = np.concatenate(chord)
    assert len(set(carried.tolist())) == len(carried)                    # each speed carried once
    solved = set(range(201)) - set(carried.tolist())
    assert {0, 200} <= solved and len(solved) <= 16
    newton_speeds = np.concatenate(iterated)
    assert set(newton_speeds.tolist()) >= solved
    assert np.sum(np.isin(newton_speeds, list(solved))) == 13 * len(solved)
    assert len(newton_speeds) - 13 * len(solved) <= 0.01 * 13 * len(carried)


@pytest.mark.parametrize("row", [0, 3, 4, 13, 100, 196, 199, 200])
def test_the_lowest_twelve_are_the_full_models_to_1e_9(sweep, row):
    """At solved anchors (0, 200), anchors carried over (4, 100, 196) and other speeds (3, 13, 199):
    the 12 roots are the 12 lowest of scipy's eigenvalues of the full state matrix, each to 1e-9."""
    model, result, _, _, _ = sweep
    assert_lowest_are_the_full_models(model, SPEEDS[row], result.eigenvalues[row])
