"""The lowest modes' full-solve fallback in parts of bounded memory, and the shift-invert Arnoldi
route's shapes (issue 27 §1.9: a 2,006-coordinate gear chain's ``campbell --lowest 20`` solved
all 11 speeds whole, 2.45 GB after 2 minutes, with no bar).

- The fallback (:func:`._lowest._full_lowest`) keeps the lowest roots of each part of the speeds,
  so its peak memory grows with the part, not with the speeds (tracemalloc); the parts change no
  number.
- ARPACK (scipy 1.17, real shift-invert) gave some roots with their conjugate's shape; Newton's
  iteration started there left for distant roots and the speed was solved whole. The chain of 25
  rotors on bearings (106 coordinates, the Arnoldi route) lost 2 of 6 speeds that way.
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _arnoldi, _batches, _lowest
from rotordyn_modal.analysis._stack import Stack

from test_large_machine_cli import chained_gear_toml
from test_lowest_modes import _lowest_by_scipy

COMPRESSOR = "examples/compressor_rotor.toml"          # 53 coordinates, 106 states


def _peak(function, *args):
    """The peak of memory traced while ``function(*args)`` runs [bytes], and its result."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        start = tracemalloc.get_traced_memory()[0]
        result = function(*args)
        return tracemalloc.get_traced_memory()[1] - start, result
    finally:
        tracemalloc.stop()


def test_the_full_fallback_holds_one_part_not_every_speed(monkeypatch):
    """Parts of two speeds: each eigen-solve gets at most two speeds, and the peak is at most one
    part's budget (``CHUNK_BYTES``, what a part may take) beside the roots and shapes kept, at 64
    and at 256 speeds alike; on main every speed's state matrix and every root's shape were held
    at once (58 MB at 256 speeds against a bound of 2.5 MB).

    A bound, not the difference of two peaks: the set-up's work spaces (numpy's, LAPACK's) move a
    peak by up to 150 kB with what the process ran before, more than one state matrix."""
    stack = Stack([rdm.load_model(COMPRESSOR)])
    n_states, n = stack.forms[0].n_states, stack.n_dof
    part = 2 * 72 * n_states ** 2
    monkeypatch.setattr(_batches, "CHUNK_BYTES", part)                       # two speeds a part
    solved = []
    solve = stack.solve
    monkeypatch.setattr(stack, "solve", lambda A, *rest: solved.append(len(A)) or solve(A, *rest))
    _lowest._full_lowest(stack, np.linspace(10.0, 900.0, 2), 4)             # the lazy set-up done
    for count in (64, 256):
        speeds = np.linspace(10.0, 900.0, count)
        peak = _peak(_lowest._full_lowest, stack, speeds, 4)[0]
        kept = count * 4 * (n + 1) * 16                                     # the roots and shapes kept
        assert peak <= kept + part, (count, peak, kept, part)
    assert max(solved) <= 2, solved
    many = np.linspace(10.0, 900.0, 64)
    values, shapes = _lowest._full_lowest(stack, many, 4)
    # the parts change no number: every speed in one part gives the same bits
    monkeypatch.setattr(_batches, "CHUNK_BYTES", 2**30)
    whole_values, whole_shapes = _lowest._full_lowest(stack, many, 4)
    np.testing.assert_array_equal(values, whole_values)
    np.testing.assert_array_equal(shapes, whole_shapes)
    reference = _lowest_by_scipy(stack.models[0], many, 4)
    order = np.argsort(values.imag, axis=1)
    assert np.max(np.abs(np.take_along_axis(values, order, 1) - reference) / np.abs(reference)) < 1e-9


def test_the_refusal_counts_one_part_and_the_roots_kept():
    """The memory the refusal counts is a part's eigen-solutions and the roots kept, not every
    state matrix: 11 speeds of 4,012 states are one speed's 1.16 GB and 11 x 20 shapes."""
    assert _lowest._full_bytes(4012, 11) == 72.0 * 4012 ** 2
    assert _lowest._full_bytes(106, 11) == 72.0 * 11 * 106 ** 2


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    path = tmp_path_factory.mktemp("chain") / "chain25.toml"
    path.write_text(chained_gear_toml(25, 25))
    return rdm.load_model(path)


def test_arnoldi_shapes_are_their_own_roots(chain):
    """Each root ARPACK gives comes with its own shape: the MAC with the displacement part of
    scipy's dense eigenvector of the state matrix at the nearest root is 1 (on main some were
    their conjugate root's shape: a MAC near 0)."""
    import scipy.linalg

    from rotordyn_modal.analysis._lowest_pencils import _Pencils

    stack = Stack([chain])
    speeds = rdm.rpm(np.array([1500.0, 2000.0]))
    parts = _arnoldi._Parts(_Pencils(stack, speeds))
    M, C, G, K = (np.asarray(matrix) for matrix in chain.matrices())
    n = len(M)
    for p, speed in enumerate(speeds):
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
        lam, vectors = scipy.linalg.eig(A)
        roots, shapes, _ = _arnoldi._counted_roots(parts, p, 13)
        for s, x in zip(roots, shapes):
            t = vectors[:n, np.argmin(np.abs(lam - s))]
            mac = abs(np.vdot(x, t)) ** 2 / (np.vdot(x, x).real * np.vdot(t, t).real)
            assert mac > 0.999, (speed, s, mac)


def test_the_chain_of_rotors_on_bearings_needs_no_full_solve(chain):
    """The 12 lowest modes at 6 speeds (not at rest: double roots there) come from the Arnoldi
    route at every speed, as scipy's dense eigenvalues of the state matrix give them (on main 2 of
    6 speeds were solved whole)."""
    stack = Stack([chain])
    speeds = rdm.rpm(np.linspace(500.0, 3000.0, 6))
    values, _, full = _lowest.lowest_roots(stack, speeds, 12)
    assert not full.any(), full
    reference = _lowest_by_scipy(chain, speeds, 12)
    order = np.argsort(values.imag, axis=1)
    assert np.max(np.abs(np.take_along_axis(values, order, 1) - reference) / np.abs(reference)) < 1e-9
