"""The lowest modes' starts continued from speed to speed (``docs/theory.md`` section 17, "Starts
from the neighbouring speeds"): between two anchors, each projected root takes its projection
error from the anchors' refined roots, followed from speed to speed; where two roots swap places
in frequency between the anchors, a start that took its neighbour's error (by place, not by
root) would be off by the difference of their errors.

Truth from outside the code: scipy's eigenvalues of the full state matrix
``[[0, I], [-M^-1 K, -M^-1 (C + Omega G)]]`` built here from ``model.matrices(speed)`` at every
speed, on ROSS's ``compressor_example`` (224 coordinates, bearings tabulated over speed), whose
heavily damped roots near 1,000 rad/s swap places in frequency with lightly damped ones twice
within nine speeds of 2.1 rad/s (between the anchors 0, 4 and 8)."""

from __future__ import annotations

from pathlib import Path

import warnings

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest

from shaft_models import one_blas_thread as _one_blas_thread

DATA = Path(__file__).parent / "data" / "ross"

#: nine speeds of ROSS's reference range (628 to 1,047 rad/s at 201 speeds), the second to the
#: tenth: the lowest roots' order by frequency changes between the third and fourth and between
#: the seventh and eighth (places 1-3 and 2-4), both between anchors
SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 201)[1:10]


def _model():
    from rotordyn_modal.io.ross_file import read_ross_rotor

    path = DATA / "compressor_example.toml"
    return rdm.Model.from_dict(read_ross_rotor(path), source=path)


def _dense_roots(model, speed):
    """Every root of the full model at ``speed`` [rad/s] with ``Im > 0``, by scipy's ``eigvals``."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    with _one_blas_thread():          # BLAS's own threads only wait for a core on a loaded machine
        roots = scipy.linalg.eigvals(A)
    return roots[roots.imag > 0]


@pytest.fixture(scope="module")
def swept():
    """The model, the dense roots of every speed, ``campbell(modes=12)``, and the starts that
    Newton's iteration was given at the speeds between anchors (rows, starts)."""
    model = _model()
    dense = [_dense_roots(model, speed) for speed in SPEEDS]
    given = []
    continued = _lowest._continued

    def recording(pencils, guesses, vectors, rows):
        given.append((np.array(rows), guesses.copy()))
        return continued(pencils, guesses, vectors, rows)

    _lowest._continued = recording
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = rdm.campbell(model, SPEEDS, critical=False, modes=12)
    finally:
        _lowest._continued = continued
    return model, dense, result, given, [str(warning.message) for warning in caught]


def test_the_sweep_has_the_two_swaps_between_anchors(swept):
    """The case is what it claims: by the dense roots, the places by frequency of the lowest five
    roots change between speeds 2-3 and 6-7, neither an anchor (0, 4, 8)."""
    _, dense, _, _, _ = swept
    lowest = [np.sort_complex(roots[np.argsort(roots.imag)[:5]]) for roots in dense]
    orders = []
    for roots, following in zip(dense[:-1], dense[1:]):
        low, after = roots[np.argsort(roots.imag)[:5]], following[np.argsort(following.imag)[:5]]
        orders.append(tuple(int(np.argmin(np.abs(low - x))) for x in after))
    changed = [i for i, order in enumerate(orders) if order != tuple(range(5))]
    assert changed == [2, 6] and len(lowest) == 9


def test_every_start_between_anchors_is_its_own_roots_to_1e_5(swept):
    """Each start given to the one-factorisation refinement lies within 1e-5 (relative) of a root of
    the full model, a different one for each place: the projected root plus that same root's
    projection error (1.3e-6 at most here, against the projected roots' 4e-5). Taking the error of
    the root at the same place at the anchor (the place, not the root: roots not followed from
    speed to speed) puts the starts of swapped roots off by the difference of their errors (1.4e-3
    here; the checks on the refined roots then send every speed to the full eigen-solve)."""
    _, dense, _, given, _ = swept
    assert given, "no speed was continued"
    rows = np.concatenate([part for part, _ in given])
    starts = np.concatenate([guesses for _, guesses in given])
    # the anchor 4 carried over from 0 and 8 (solved whole), then the others from 0, 4 and 8
    assert sorted(rows.tolist()) == [1, 2, 3, 4, 5, 6, 7]
    for row, guesses in zip(rows, starts):
        roots = dense[row]
        distance = np.abs(guesses[:, None] - roots[None, :]) / np.abs(roots[None, :])
        nearest = np.argmin(distance, axis=1)
        assert np.max(np.min(distance, axis=1)) < 1e-5, f"speed {row}"
        assert len(set(nearest.tolist())) == len(guesses)


def test_the_lowest_twelve_are_the_full_models_to_1e_9(swept):
    """``campbell(modes=12)`` at every speed: the twelve lowest roots of the dense solve, none solved
    whole."""
    _, dense, result, _, caught = swept
    assert not [message for message in caught if "solved whole" in message]
    for row, roots in enumerate(dense):
        expected = np.sort(roots[np.argsort(roots.imag)[:12]].imag)
        got = result.eigenvalues[row]
        assert np.all(np.isfinite(got))
        nearest = roots[np.argmin(np.abs(got[:, None] - roots[None, :]), axis=1)]
        assert np.max(np.abs(got - nearest) / np.abs(nearest)) < 1e-9
        assert np.allclose(np.sort(got.imag), expected, rtol=1e-9, atol=0)
