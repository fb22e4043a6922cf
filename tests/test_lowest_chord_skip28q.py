"""The carried roots' one solve (issue 28 section 4): a carried root whose Newton step is already at
round-off takes no chord step, and the starts are interpolated within a bearing table's pieces.

``_lowest_starts._affine_pieces`` cuts a sweep where the speed-dependent entries bend (a table's
knots, known here by construction); ``_lowest_starts._around`` keeps the interpolation's nodes on one
side of a knot; ``_lowest_pencils._back_solved`` of some rows of a chunk solves those rows (truth:
numpy's dense solve); ROSS's ``compressor_example`` at 201 speeds (tables with knots every 1,000 rpm
inside the sweep) takes under 1.5 back-substitutions a carried root, not two, and its roots are the
full state matrix's (scipy's eigenvalues) at the speeds around the knots."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest_pencils, _lowest_starts
from rotordyn_modal.io.ross_file import read_ross_rotor

from shaft_models import assert_lowest_are_the_full_models

DATA = Path(__file__).parent / "data" / "ross"
#: bench_ross.py's sweep of compressor_example: 6,000-10,000 rpm at 201 speeds
SPEEDS = np.linspace(628.3185307179587, 1047.1975511965977, 201)


def test_pieces_are_cut_at_the_knots():
    """Entries linear in the speed between knots at 4.0 (a speed of the sweep) and 6.5 (between
    two), and one constant entry: the pieces are speeds 0-4, 4-6 and 7-10 (a knot's own speed ends
    the piece before it and starts the one after; it is given the one before); a smooth curve
    everywhere is one piece."""
    speeds = np.arange(11.0)
    bent = np.stack([np.where(speeds < 4, speeds, 4 + 3 * (speeds - 4)),
                     np.where(speeds < 6.5, 2.0, 2.0 - (speeds - 6.5)), np.full(11, 5.0)], axis=1)
    pieces = _lowest_starts._affine_pieces(speeds, bent)
    expected = [(0, 4)] * 5 + [(4, 6)] * 2 + [(7, 10)] * 4
    assert [tuple(piece) for piece in pieces] == expected
    assert [tuple(piece) for piece in _lowest_starts._affine_pieces(speeds, np.exp(speeds / 3)[:, None])] \
        == [(0, 10)] * 11


def test_nodes_stay_in_the_piece():
    """Anchors every 4th of 41 speeds, a knot at speed 20 (an anchor, in both pieces): the four nodes
    of speeds 17-19 lie at or below it, those of 21-23 at or above it; without pieces, the nodes of
    19 and 21 straddle it."""
    speeds = np.arange(41.0)
    entries = np.where(speeds < 20, speeds, 20 + 2 * (speeds - 20))[:, None]
    pieces = _lowest_starts._affine_pieces(speeds, entries)
    grid = np.arange(0, 41, 4)
    below = _lowest_starts._around(grid, np.array([17, 18, 19]), 4, pieces)
    above = _lowest_starts._around(grid, np.array([21, 22, 23]), 4, pieces)
    assert (below <= 20).all() and (above >= 20).all()
    straddling = _lowest_starts._around(grid, np.array([19, 21]), 4)
    assert (straddling.min(axis=1) < 20).all() and (straddling.max(axis=1) > 20).all()


def test_back_solved_rows_of_a_chunk():
    """``zgbtrs`` of the rows 1 and 3 of four banded LU factors solves those two systems (numpy's
    dense solve of the same matrices)."""
    rng = np.random.default_rng(28)
    n, kl, ku, count = 12, 2, 3, 4
    dense = np.zeros((count, n, n), complex)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            dense[:, i, j] = rng.normal(size=count) + 1j * rng.normal(size=count)
    width = 2 * kl + ku + 1
    ab = np.zeros((count, n, width), complex)          # each ab[p].T LAPACK's band storage
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            ab[:, j, kl + ku + i - j] = dense[:, i, j]
    pivots = np.empty((count, n), np.int32)
    assert _lowest_pencils._factored(kl, ku, ab, pivots).all()
    which = np.array([1, 3])
    rhs = rng.normal(size=(2, n)) + 1j * rng.normal(size=(2, n))
    y = rhs.copy()
    _lowest_pencils._back_solved(kl, ku, ab, pivots, y, which)
    expected = np.linalg.solve(dense[which], rhs[..., None])[..., 0]
    assert np.allclose(y, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


@pytest.fixture(scope="module")
def sweep():
    """The model, ``campbell(modes=12)`` of 201 speeds, the roots given to the chord
    (``newton_chord``) and the back-substitutions of the chord's LU factors."""
    path = DATA / "compressor_example.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    chord, back = _lowest_pencils._Pencils.newton_chord, _lowest_pencils._back_solved
    roots, solves = [0], [0]

    def counted_chord(self, index, lam, *args, **kwargs):
        roots[0] += len(lam)
        return chord(self, index, lam, *args, **kwargs)

    def counted_back(kl, ku, ab, pivots, y, *args, **kwargs):
        solves[0] += len(y)
        return back(kl, ku, ab, pivots, y, *args, **kwargs)

    _lowest_pencils._Pencils.newton_chord, _lowest_pencils._back_solved = counted_chord, counted_back
    try:
        result = rdm.campbell(model, SPEEDS, critical=False, modes=12)
    finally:
        _lowest_pencils._Pencils.newton_chord, _lowest_pencils._back_solved = chord, back
    return model, result, roots[0], solves[0]


def test_most_carried_roots_take_one_solve(sweep):
    """The 2,275 carried roots take under 1.5 back-substitutions each (measured 1.3: the roots whose
    Newton step is at most 1e-11 of the root take no chord step; before, every root took two)."""
    _, _, roots, solves = sweep
    assert roots >= 2000
    assert solves < 1.5 * roots


@pytest.mark.parametrize("row", [49, 50, 51, 100, 101, 149, 151])
def test_roots_at_the_knots_are_the_full_models(sweep, row):
    """At the speeds around the tables' knots (speeds 50, 100, 150 of the sweep: 7,000, 8,000 and
    9,000 rpm), the 12 roots are the 12 lowest of scipy's eigenvalues of the full state matrix,
    each to 1e-10."""
    model, result, _, _ = sweep
    assert_lowest_are_the_full_models(model, SPEEDS[row], result.eigenvalues[row], rtol=1e-10)


def test_every_speed_between_anchors_is_carried_at_101_speeds():
    """At 101 speeds six nodes reach too far for the first speeds' roots to be followed to them:
    those speeds take their nearest four (``_Expansions.narrowed``), so every speed but the solved
    anchors is still carried over, except the two middle anchors (speeds 4 and 12) whose Gershgorin
    discs cannot show their count (``_lowest._doomed``): they take their own projected roots at once,
    and no speed is refined twice. A guard: main's four nodes carried them all too; with six and no
    fallback, 5 of the first 13 speeds were not. (Before ``_doomed``, speeds 4 and 12 were carried,
    failed the certificate and were refined again from their projected roots: the same bits.)"""
    from rotordyn_modal.analysis import _lowest

    path = DATA / "compressor_example.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    continued, carried = _lowest._continued, []
    projected, own = _lowest._projected_starts, []

    def recording(pencils, guesses, vectors, rows):
        carried.append(np.array(rows))
        return continued(pencils, guesses, vectors, rows)

    def recording_own(pencils, basis, want, index=None, vectors_at=None):
        own.append(np.array(index))
        return projected(pencils, basis, want, index, vectors_at)

    _lowest._continued, _lowest._projected_starts = recording, recording_own
    try:
        rdm.campbell(model, np.linspace(SPEEDS[0], SPEEDS[-1], 101), critical=False, modes=12)
    finally:
        _lowest._continued, _lowest._projected_starts = continued, projected
    solved = set(range(0, 101, 8)) | {100}
    carried = np.concatenate(carried).tolist()
    own = np.concatenate(own).tolist()
    assert sorted(own) == [4, 12]
    assert sorted(carried + own) == sorted(set(range(101)) - solved)
