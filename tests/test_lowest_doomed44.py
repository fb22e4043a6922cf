"""Speeds between anchors whose Gershgorin discs cannot show their count take their own projected
roots at once (``_lowest._doomed``), without a first Newton's iteration from the carried starts.

On ROSS's compressor_example (224 coordinates, bearings tabulated over speed) at 21 speeds, 13
speeds between anchors are such speeds: each of their 12 roots is the full model's (scipy's
eigenvalues of the full state matrix, 1e-9), and each is refined once.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.io.ross_file import read_ross_rotor
from shaft_models import assert_lowest_are_the_full_models

DATA = Path(__file__).parent / "data" / "ross"
SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 21)


@pytest.fixture(scope="module")
def sweep():
    """compressor_example's lowest 12 at 21 speeds, the speeds ``_doomed`` sent to their own
    projected roots, and the speeds refined by Newton from carried starts."""
    from rotordyn_modal.analysis import _lowest

    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    doomed, carried = _lowest._doomed, _lowest._continued
    taken, continued = [], []

    def recording(expansions, places, guesses, moved, count):
        out = doomed(expansions, places, guesses, moved, count)
        taken.extend(expansions.between[places][out].tolist())
        return out

    def recording_carried(pencils, guesses, vectors, rows):
        continued.extend(np.asarray(rows).tolist())
        return carried(pencils, guesses, vectors, rows)

    _lowest._doomed, _lowest._continued = recording, recording_carried
    try:
        result = rdm.campbell(model, SPEEDS, critical=False, modes=12)
    finally:
        _lowest._doomed, _lowest._continued = doomed, carried
    return model, result, sorted(set(taken)), continued


def test_the_route_is_taken_and_each_speed_refined_once(sweep):
    """Most speeds between anchors take the route here, and none of them is also carried."""
    _, _, taken, continued = sweep
    assert len(taken) >= 8
    assert not set(taken) & set(continued)


def test_doomed_speeds_roots_are_the_full_models(sweep):
    """Each speed taken by the route: its 12 roots are the 12 lowest of scipy's eigenvalues of the
    full state matrix, each to 1e-9."""
    model, result, taken, _ = sweep
    for row in taken:
        assert_lowest_are_the_full_models(model, SPEEDS[row], result.eigenvalues[row], rtol=1e-9)
