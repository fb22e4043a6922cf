"""The lowest modes' pilot cache and Gershgorin count (issue 28 §4, speed30).

* The pilot's ``eig`` and products (``_lowest._solved_levels``) are held for the main pass only:
  the main pass adds none of its own anchors to the dict and takes the pilot's out as it uses
  them, so the memory held is at most what ``_PILOT_BYTES`` guards (before, up to twice it).
  ROSS's ``compressor_example`` at 101 speeds, where every middle anchor is solved by the main pass.
* The count of discs (``_lowest_bound._gershgorin_count``) from their connected parts equals a
  brute-force union of every touching pair (written here), and its memory grows with the discs,
  not with their square. The roots stay scipy's full state-matrix eigenvalues to 1e-9 (checked
  at a solved anchor and at carried speeds).
"""

from __future__ import annotations

import tracemalloc
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_starts
from rotordyn_modal.analysis._lowest_bound import _gershgorin_count
from rotordyn_modal.io.ross_file import read_ross_rotor

from shaft_models import assert_lowest_are_the_full_models

DATA = Path(__file__).parent / "data" / "ross"
#: the span of the file's ROSS reference speeds [rad/s] (6,000-10,000 rpm)
LOW, HIGH = 628.3185307179587, 1047.1975511965977


def _held(tree) -> int:
    """Bytes of the numpy arrays in nested dicts, tuples and lists."""
    if isinstance(tree, np.ndarray):
        return tree.nbytes
    if isinstance(tree, dict):
        return sum(_held(value) for value in tree.values())
    if isinstance(tree, (tuple, list)):
        return sum(_held(value) for value in tree)
    return 0


@pytest.fixture(scope="module")
def coarse():
    """compressor_example at 101 speeds with the pilot's dict read: the model, the result and what
    was seen (the pilot's anchors, the guard's estimate of their bytes, the main pass's anchors, and
    the dict's keys and bytes as the main pass began and after it)."""
    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    seen = {}
    original = _lowest._Expansions

    class Watched(original):
        def __init__(self, pencils, basis, solved, want, levels, eigen=None, nodes=True):
            if not nodes:
                seen["pilot"] = set(int(a) for a in solved)
                seen["estimate"] = 16 * len(solved) * 3 * (2 * basis.shape[1] + len(pencils.rows)) ** 2
            elif eigen is not None:
                seen["main"] = set(int(a) for a in solved)
                seen["before"], seen["held"] = set(eigen), _held(eigen)
            super().__init__(pencils, basis, solved, want, levels, eigen, nodes)
            if nodes and eigen is not None:
                seen["after"] = set(eigen)

    _lowest._Expansions = Watched
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = rdm.campbell(model, np.linspace(LOW, HIGH, 101), critical=False, modes=12)
    finally:
        _lowest._Expansions = original
    return model, result, seen


def test_the_main_pass_keeps_no_anchor_of_its_own(coarse):
    """The main pass solves more anchors than the pilot (at 101 speeds every middle anchor) and
    finds the pilot's in the dict; it adds none of its own."""
    _, _, seen = coarse
    assert seen["main"] - seen["pilot"], "the main pass solves anchors the pilot did not"
    assert seen["before"] == seen["pilot"]
    assert seen["after"] <= seen["pilot"]


def test_the_pilots_anchors_are_let_go_by_the_main_pass(coarse):
    """After the main pass the dict holds nothing: it took each of the pilot's anchors out as it
    used them."""
    _, _, seen = coarse
    assert seen["after"] == set()


def test_the_dict_holds_no_more_than_the_guards_estimate(coarse):
    """The bytes the pilot leaves for the main pass are within the estimate ``_solved_levels``
    compares with ``_PILOT_BYTES``."""
    _, _, seen = coarse
    assert 0 < seen["held"] <= seen["estimate"]


@pytest.mark.parametrize("row", [0, 4, 8, 50, 97, 100])
def test_the_roots_are_the_full_models(coarse, row):
    """At solved anchors (0, 8, 100) and carried speeds (4, 50, 97): scipy's 12 lowest, to 1e-9."""
    model, result, _ = coarse
    assert_lowest_are_the_full_models(model, np.linspace(LOW, HIGH, 101)[row], result.eigenvalues[row])


def _brute_count(centers, radii, limit):
    """The count of ``_gershgorin_count``'s rule from every pair of discs: the connected parts by
    repeated union of touching pairs (``|c_a - c_b| <= r_a + r_b``), each counted as its discs if
    it lies above the real axis, its centers with ``Im >= 0`` if it reaches the axis, none if it
    lies wholly at or above ``limit`` or below the axis."""
    p = len(centers)
    parent = list(range(p))

    def root(a):
        while parent[a] != a:
            a = parent[a]
        return a

    for a in range(p):
        for b in range(a + 1, p):
            if abs(centers[a] - centers[b]) <= radii[a] + radii[b]:
                parent[root(a)] = root(b)
    total = 0
    for part in {root(a) for a in range(p)}:
        members = [a for a in range(p) if root(a) == part]
        low = min(centers[a].imag - radii[a] for a in members)
        high = max(centers[a].imag + radii[a] for a in members)
        if low < limit and high > 0:
            total += len(members) if low > 0 else sum(centers[a].imag >= 0 for a in members)
    return total


def test_the_count_is_the_brute_force_union_of_touching_discs():
    """Random discs (wide and narrow, on the real axis, touching exactly on a grid of halves,
    chains across many discs): the count of every speed equals the brute-force one."""
    rng = np.random.default_rng(30)
    for trial in range(300):
        speeds, p = int(rng.integers(1, 5)), int(rng.integers(1, 25))
        if trial % 3 == 0:          # exact tangencies: integer centers, radii in halves
            centers = rng.integers(-4, 5, (speeds, p)) + 1j * rng.integers(-4, 5, (speeds, p))
            radii = rng.integers(0, 3, (speeds, p)) / 2.0
        else:
            centers = rng.standard_normal((speeds, p)) * 3 + 1j * rng.standard_normal((speeds, p)) * 3
            if trial % 3 == 1:
                centers[:, : p // 2] = centers[:, : p // 2].real
            radii = np.abs(rng.standard_normal((speeds, p))) * rng.choice([0.01, 0.3, 2.0])
        limit = rng.standard_normal(speeds) * 3 + 2
        expected = [_brute_count(centers[s], radii[s], limit[s]) for s in range(speeds)]
        assert _gershgorin_count(centers.astype(complex), radii, limit).tolist() == expected, trial


def test_a_chain_of_discs_is_one_part():
    """Discs touching only their neighbours along a line across the real axis: one part, counted
    by its centers with ``Im >= 0`` (6 of 11); cut the chain above the axis and the parts above it
    count all of their discs, those starting above the limit none."""
    centers = np.array([[0.3 * k + 1j * (k - 5) for k in range(11)]])
    radii = np.full((1, 11), 0.51 * abs(0.3 + 1j))      # neighbours overlap, the next apart
    assert _gershgorin_count(centers, radii, np.array([100.0]))[0] == 6
    radii[0, 7] = 0.1               # parts {0..6} (reaching the axis: 2), {7} (Im 2: 1), {8, 9, 10} (Im 3-5: 3)
    assert _gershgorin_count(centers, radii, np.array([100.0]))[0] == 6
    assert _gershgorin_count(centers, radii, np.array([2.4]))[0] == 3      # {8, 9, 10} start at 2.47


def test_the_count_needs_memory_of_the_discs_not_their_square():
    """3,000 discs far apart at one speed: the count allocates well under the 144 MB of their
    pairwise distances (3,000^2 complex)."""
    p = 3000
    centers = (np.arange(p) * 10.0 + 1j * np.arange(p) * 10.0)[None]
    radii = np.ones((1, p))
    tracemalloc.start()
    try:
        count = _gershgorin_count(centers, radii, np.array([p * 10.0 + 5]))[0]
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert count == p               # each disc is a part of its own below the limit (the first's center on the axis)
    assert peak < 16 * 2**20, peak


def _carried(count):
    """compressor_example at ``count`` speeds: the model, the main pass's expansions and basis, and
    the speeds at which ``F`` was made whole (``_lowest_starts._changed`` without ``order``)."""
    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    seen = {"whole": 0}
    original, changed = _lowest._Expansions, _lowest_starts._changed

    class Kept(original):
        def __init__(self, pencils, basis, solved, want, levels, eigen=None, nodes=True):
            super().__init__(pencils, basis, solved, want, levels, eigen, nodes)
            if nodes:
                seen["expansions"], seen["basis"] = self, basis

    def counted(pencils, at, anchor, factors, order=None):
        if order is None:
            seen["whole"] += len(at)
        return changed(pencils, at, anchor, factors, order)

    _lowest._Expansions, _lowest_starts._changed = Kept, counted
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rdm.campbell(model, np.linspace(LOW, HIGH, count), critical=False, modes=12)
    finally:
        _lowest._Expansions, _lowest_starts._changed = original, changed
    return model, seen


@pytest.fixture(scope="module")
def carried():
    """201 speeds: the bearing tables bend every 1,000 rpm, at speeds 50, 100 and 150."""
    return _carried(201)


def _projected_state(model, basis, speed):
    """``[[0, I], [-W^T K W, -W^T (C + Omega G) W]]`` from the model's own matrices (``W^T M W = I``)."""
    M, C, G, K = model.matrices(speed)
    m = basis.shape[1]
    return np.block([[np.zeros((m, m)), np.eye(m)], [-basis.T @ K @ basis, -basis.T @ (C + speed * G) @ basis]])


@pytest.mark.parametrize("count", [201, 67])
def test_the_discs_hold_the_exact_discs_across_the_tables_knots(carried, count):
    """At carried speeds near the knots and some others (201 speeds: knots at speeds 50, 100, 150;
    67 speeds: knots between speeds, 16-17, 33-34, 49-50), each Gershgorin disc of ``V^-1 A_j V`` (``V``: numpy's eigenvectors
    of the nearer anchor's projected state matrix ``A_a``, both built here from
    ``model.matrices``) lies inside one of the sweep's discs (to 1e-9 of the largest root), and
    the centers agree to that: the discs made from one matrix per piece of the bearing tables
    are the exact ones, on both sides of a knot."""
    model, seen = carried if count == 201 else _carried(count)
    ex, basis = seen["expansions"], seen["basis"]
    speeds = ex.speeds
    knots = LOW + np.array([1, 2, 3]) * (HIGH - LOW) / 4                 # 7,000, 8,000 and 9,000 rpm
    step = (HIGH - LOW) / (count - 1)
    rows = [row for row, speed in enumerate(ex.between)
            if np.min(np.abs(speeds[speed] - knots)) <= 3.5 * step or speed % 37 == 0]
    assert len(rows) > 15
    for row in rows:
        anchor = ex.solved[ex.near[row]]
        lam, V = np.linalg.eig(_projected_state(model, basis, speeds[anchor]))
        F = np.linalg.solve(V, _projected_state(model, basis, speeds[ex.between[row]]) @ V) - np.diag(lam)
        centers = lam + np.diag(F)
        radii = np.abs(F).sum(axis=1) - np.abs(np.diag(F))
        tolerance = 1e-9 * np.max(np.abs(lam))
        nearest = np.argmin(np.abs(centers[:, None] - ex.centers[row][None, :]), axis=1)
        assert np.all(np.abs(centers - ex.centers[row][nearest]) <= tolerance), row
        assert np.all(radii <= ex.radii[row][nearest] + tolerance), row


def test_the_whole_change_is_made_only_across_a_knot(carried):
    """``F`` is made whole only at the speeds whose table piece does not hold their anchor: at
    201 speeds, some of those within 8 speeds of a knot on the other side of their anchor (at most
    24 for the three knots), not the 185 carried speeds (every one before)."""
    _, seen = carried
    ex = seen["expansions"]
    assert len(ex.between) == 185
    assert 0 < seen["whole"] <= 24


def test_the_few_speeds_projected_roots_are_solved_once():
    """The Arnoldi test and the reduced route both take the highest root wanted from the projected
    roots of the same few speeds on the same modes: solved once, not twice (and the roots are
    scipy's: the sweep's lowest 12 at one of those speeds)."""
    from rotordyn_modal.analysis import _lowest_bound, _lowest_route

    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    speeds = np.linspace(LOW, HIGH, 41)
    picked = np.unique(np.round(np.linspace(0, len(speeds) - 1, _lowest_bound._FEW)).astype(int))     # 0, 10, ..., 40
    few = []
    modules = [module for module in (_lowest, _lowest_route, _lowest_starts) if hasattr(module, "_projected_starts")]
    saved = [module._projected_starts for module in modules]

    def counting(original):
        def counted(pencils, basis, want, index=None, vectors_at=None):
            if index is not None and np.array_equal(index, picked):
                few.append(len(index))
            return original(pencils, basis, want, index, vectors_at)
        return counted

    for module, original in zip(modules, saved):
        module._projected_starts = counting(original)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = rdm.campbell(model, speeds, critical=False, modes=12)
    finally:
        for module, original in zip(modules, saved):
            module._projected_starts = original
    assert few == [_lowest_bound._FEW]
    assert_lowest_are_the_full_models(model, speeds[10], result.eigenvalues[10])
