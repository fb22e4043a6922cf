"""The lowest modes of a speed sweep, exact, without every root at every speed.

Three steps (``docs/theory.md``, "The lowest modes only"):

1. a speed-independent basis: the ``m`` lowest undamped modes of the symmetric parts of the
   stiffness and mass at the sweep's first speed, mass-orthonormal, and ``k`` attachment
   directions (the static response to forces where the bearings act, outside those modes);
2. the projected pencils (``(m + k)`` square) of the anchors (every fourth speed), solved by a
   batched ``eig`` (``eigvals`` at every second one): starts for the wanted roots; the speeds between
   take their starts from the anchors' roots carried over in an anchor's eigenbasis, and their
   completeness from its Gershgorin discs (:func:`_swept`);
3. each start refined to the full model's root by Newton's iteration on the full quadratic
   pencil ``Q(s) = s^2 M + s (C + Omega G) + K`` (a banded LU per root and iteration where the
   pencils are banded, with a casing's coordinates as a border; batched dense LU for small
   models; SuperLU otherwise), until the error left is at round-off.

A speed where the refined roots are not ``count + 1`` distinct modes, where a projected root
left unrefined could stand for a lower root, or where the basis cannot be shown to hold every
root below the wanted ones (see :class:`_Bound`), is solved whole instead (the full
eigen-solve), with a notice. Models below ``DENSE_BELOW`` coordinates solve every root of every
speed (eigenvalues alone, the wanted roots' shapes by inverse iteration: :func:`_dense_lowest`;
an undamped gyroscopic model's from a Hermitian matrix of its states: :func:`_gyroscopic_lowest`).

This module holds the routes and their checks; each concept is a module of its own:
:mod:`._lowest_route` (Arnoldi told before the dense set-up), :mod:`._lowest_bound` (the basis and
its completeness bound), :mod:`._lowest_starts` (the projected pencils' roots, and which roots are
the lowest), :mod:`._lowest_pencils` (the full pencils and their solves) and :mod:`._lowest_newton`
(Newton's iteration and the polish); :mod:`._arnoldi` serves crowded spectra.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import scipy.linalg

from . import _arnoldi, _batches, _cost, _eigensolve, _lowest_bound, _lowest_route, _roots
from ._lowest_bound import _FEW, _MARGIN, _Bound, _stack_bound  # noqa: F401 (_Bound: for _lowest_branches)
from ._lowest_newton import _continued, _refined, _speeds_named
from ._lowest_pencils import _Pencils
from ._lowest_starts import (_CLOSE, _NODES, _SOLVED, _anchors, _by_frequency, _close, _continuation_guesses, _Expansions,
                             _expansion_guesses, _pencil_shapes_part, _projected_guesses, _projected_starts,
                             frequency_key, lowest_order, projected_roots_kept)
from ._vectors import unit_rows
from .modal import is_oscillating

__all__ = ["lowest_roots"]

#: refined roots closer than this times |lam| are one root reached twice
_SAME = 1e-8

#: models of fewer coordinates solve every root of every speed (one batched eig) and keep the
#: lowest: faster there (benchmarks/README.md, "The lowest modes only": the dense solve is faster
#: up to about 50 coordinates, but from 39 on the Newton roots are kept, 10-20 % dearer: they keep
#: an undamped gyroscopic model's roots on the imaginary axis to 1e-12, the dense eig to 3e-10)
DENSE_BELOW = 38
#: ``campbell``'s checks of its mode links (a few speeds a call, roots to track, not results) take
#: the dense route (:func:`_small_lowest`) below this many coordinates: there every root of the
#: state matrix costs less than the reduced route's set-up (its basis, the estimate of the highest
#: root, the projected ``eig``, Newton) for a few speeds. Measured, CPU of ``campbell(modes=12)`` at
#: 21 speeds: ROSS's speed_tables (44 coordinates) 52 -> 44 ms, hrs113 (64) 559 -> 447 ms;
#: damping_geometry (136) 118 -> 207 ms, so not there
CHECK_DENSE_BELOW = 72
#: ``campbell``'s lowest modes share their batches between the pool's threads
#: (:func:`._batches._threaded`) from this many coordinates on; below, every batch runs in the
#: calling thread (:func:`._batches.calling_thread`), the same bits. Measured on this 2-core machine
#: shared with other sessions (load 1-3), wall / CPU time of ``campbell(modes=12)``, one thread
#: against the pool: ROSS's rotor_example (28 coordinates, 21 speeds) 11.0 / 11.0 against 12.4 /
#: 13.8 ms, speed_tables (44) 38 / 38 against 39 / 39 ms, compressor_example (224) 136 / 136 against
#: 142 / 153 ms, and at 201 speeds 506-524 / 469-494 against 637-652 / 550-586 ms;
#: bench_flexible's fan shaft at 201 speeds, 100 coordinates 178 / 178 against 188 / 188 ms, 400
#: coordinates 1,553-1,598 / 1,466-1,498 against 1,432-1,539 / 1,532-1,542 ms (the pool a little
#: shorter in wall time there)
POOL_FROM = 300


def lowest_roots(stack, speeds, count: int, progress: bool = False, what: str = "speeds"):
    """The ``count`` lowest-frequency oscillating roots of a one-model stack at every speed.

    Parameters
    ----------
    stack : Stack
        One model without frequency-dependent branches (``stack.branch_times`` empty).
    speeds : ndarray, shape (S,) [rad/s]
    count : int
        Modes wanted per speed (>= 1).
    progress : bool
        A progress bar over the speeds where they are solved by shift-invert Arnoldi.
    what : str
        What ``speeds`` are, in the fallback's warning ("2 of 11 speeds solved whole"; the
        critical speeds' sub-sweeps say "speeds of the critical speeds' finer sweeps").

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex [1/s]
        By frequency at each speed (not tracked).
    shapes : ndarray, shape (S, count, n), complex, unit norm
    full : ndarray of bool, shape (S,)
        The speeds solved whole (fallback).
    """
    if stack.n_dof < DENSE_BELOW:           # every root of every speed costs less here
        lam, phi = _small_lowest(stack, speeds, count)
        return lam, phi, np.ones(len(speeds), bool)
    # its dense steps are small BLAS calls (n x n once, m x m per speed): BLAS's own threads only
    # wait for a core on a shared machine (measured up to 10x slower at load 5); the batched
    # eigen-solves and banded solves run in threads of their own
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        values, shapes, ok = _reduced_roots(stack, speeds, count, progress)
    out_values, out_shapes = _first_columns(values, shapes, count)
    full = ~ok
    _by_whirl(stack, out_values, out_shapes, ok)
    if full.any():
        _refuse_long_full(stack, speeds[full], len(speeds), "lowest modes", _UNSERVED, modes=count)
        warnings.warn(f"lowest modes: {int(full.sum())} of {len(speeds)} {what} solved whole (the reduced basis "
                      "could not be shown to hold every root below the wanted ones there)", stacklevel=3)
        lam, phi = _full_lowest(stack, speeds[full], count, progress)
        out_values[full], out_shapes[full] = lam, phi
    return out_values, out_shapes, full


#: the largest part of a sweep's shapes copied at once where they are moved within their own
#: memory (:func:`_first_columns`) [bytes]
_MOVE_BYTES = 8 * 2**20


def _first_columns(values, shapes, count):
    """The first ``count`` roots (S, count) and shapes (S, count, n) of each speed of ``values``
    (S, k) and ``shapes`` (S, k, n); NaN and zero shapes where fewer than ``count`` were found.
    Where ``k >= count`` the shapes are written over the front of ``shapes``' own memory, a part of
    the speeds at a time (each speed's goes no further than its own began, so no speed is written
    over before it is moved), and returned as a view of it: not a second copy of every speed's
    shapes (issue 28: 77 MB for the lowest 12 of 400 coordinates at 1,001 speeds)."""
    speeds, k, n = shapes.shape
    out_values = np.full((speeds, count), np.nan + 0j)
    out_values[:, :min(count, k)] = values[:, :count]
    if k < count or not shapes.flags.c_contiguous:
        out_shapes = np.zeros((speeds, count, n), dtype=complex)
        out_shapes[:, :k] = shapes[:, :count]
        return out_values, out_shapes
    front = shapes.reshape(-1)[:speeds * count * n].reshape(speeds, count, n)
    for part in _batches.chunk_slices(speeds, 16 * count * n, budget=_MOVE_BYTES):
        front[part] = shapes[part, :count]             # numpy buffers a copy where the two overlap
    return out_values, front


def _reduced_roots(stack, speeds, count, progress=False):
    """The ``count + 1`` lowest roots of every speed from the reduced basis, refined: roots (S, k),
    shapes (S, k, n) and whether the speed passed every check (S,); by shift-invert Arnoldi
    (:mod:`._arnoldi`, with a progress bar where ``progress``) where that basis would be too large."""
    n = stack.n_dof
    size = min(n, max(3 * count, count + 10))
    pencils = _Pencils(stack, speeds)
    if _lowest_route._crowded(stack, pencils, count=count):      # Arnoldi, shown without the dense set-up below
        return _arnoldi_roots(stack, pencils, count, progress)
    bound = _stack_bound(stack, pencils)
    want = min(count + 1, size)
    # the highest root wanted, from a few speeds (an underestimate only makes the final check stricter)
    few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _FEW))).astype(int))
    rho, cheap = _highest_wanted(pencils, bound, want, size, few)
    found = _sized_sweep(stack, pencils, bound, count, want, rho, progress, cheap)
    if found is None:                   # the cheap estimate was too low for the basis: the careful one
        rho = _highest_wanted(pencils, bound, want, size, few, cheap=False)[0]
        found = _sized_sweep(stack, pencils, bound, count, want, rho, progress)
    return found


#: the cheap estimate of the highest root wanted (:func:`_highest_wanted`) projects on the undamped
#: modes up to the first above this many times the ``want``-th undamped frequency, and at least
#: ``want + _ESTIMATE_EXTRA`` of them
_ESTIMATE_REACH, _ESTIMATE_EXTRA = 1.5, 4


def _highest_wanted(pencils, bound, want, size, few, cheap=True):
    """``rho`` [rad/s], ``_MARGIN`` times the highest of the ``want`` lowest projected roots at the
    speeds ``few`` (:func:`._lowest_starts.projected_roots_kept`), and whether it is the cheap
    estimate. The careful estimate projects on the first ``size`` undamped modes (``3 count``, as
    the Arnoldi test does, whose roots it takes again where that test made them); the cheap one
    (with ``cheap``, where the Arnoldi test made none) on the modes up to the first above
    ``_ESTIMATE_REACH`` times the ``want``-th undamped frequency: ``eigvals`` of 34 states instead
    of 72 on ROSS's speed_tables (44 coordinates), a tenth of the work, the same ``rho`` to 1e-5.
    ``rho`` only sizes the basis: the basis is checked at the highest root refined
    (:func:`_basis_suffices`), and where the cheap ``rho`` fails that check the caller sizes the
    basis again from the careful one (:func:`_sized_sweep`)."""
    modes, omegas = bound.modes, bound.omegas
    if cheap and pencils.__dict__.get("_kept_roots") is None:
        reach = int(np.searchsorted(omegas, _ESTIMATE_REACH * omegas[want - 1])) + 1
        fewer = min(size, max(want + _ESTIMATE_EXTRA, reach))
        if fewer < size:
            roots = _projected_starts(pencils, modes[:, :fewer], want, few, vectors_at=np.zeros(len(few), bool))[0]
            return _MARGIN * np.max(np.abs(roots)), True
    return _MARGIN * np.max(np.abs(projected_roots_kept(pencils, modes[:, :size], want, few))), False


def _sized_sweep(stack, pencils, bound, count, want, rho, progress=False, cheap=False):
    """:func:`_reduced_roots`' sweep on the basis sized for roots up to ``rho`` [rad/s]: roots
    (S, k), shapes (S, k, n) and whether each speed passed every check (S,); None where ``cheap``
    (``rho`` the cheap estimate, :func:`_highest_wanted`) and the basis fails its check at a speed
    that passed the others (the careful estimate may size it larger)."""
    n = stack.n_dof
    size = min(n, max(_needed_size(bound, rho, want), want))
    _, attached = bound.shares(size, rho)
    if _arnoldi.takes(size + attached.shape[1], n):     # the undamped modes crowd above the wanted roots
        return _arnoldi_roots(stack, pencils, count, progress)
    basis = np.hstack([bound.modes[:, :size], attached])
    values, shapes, ok, unmissed = _swept(pencils, basis, want, count)
    ok &= _distinct(values, shapes)
    near = ok & ~unmissed               # every root refined and distinct; the next start within the error
    ok &= unmissed
    # Newton may reorder roots of close frequency: by frequency again
    values, shapes = _by_frequency_over(values, shapes, count)
    suffices = _basis_suffices(values, bound, size, attached.shape[1], rho)
    if cheap and np.any(ok & ~suffices):
        return None
    ok &= suffices
    _cut_in_a_multiple_root(stack, pencils, bound, (values, shapes, ok), count, near=near)
    return values, shapes, ok


def _arnoldi_roots(stack, pencils, count, progress=False, limit=None):
    """:func:`_reduced_roots` by shift-invert Arnoldi (:func:`._arnoldi.lowest`; with a ``limit``
    [rad/s], :func:`_reduced_below`'s, :func:`._arnoldi.below`): the ``count + 1`` roots by
    frequency, a multiple root's shapes by whirl, backward first, before the cut keeps the first
    ``count`` (where the cut falls inside a double root, the root kept is its backward whirl, as on
    the reduced route, :func:`_cut_in_a_multiple_root`; ARPACK's ``k`` cutting inside it is retried
    there, :func:`._arnoldi._arnoldi`)."""
    if limit is None:
        values, shapes, ok = _arnoldi.lowest(pencils, count, _refined, _distinct, progress)
    else:
        values, shapes, ok = _arnoldi.below(pencils, limit, count, _refined, _distinct)
    values, shapes = _by_frequency(values, shapes, count)
    _by_whirl(stack, values, shapes, ok)
    return values, shapes, ok


#: the most roots of one multiple root across the cut refined beyond the ``count + 1``
_MULTIPLE_EXTRA = 4


def _cut_in_a_multiple_root(stack, pencils, bound, out, count, project=None, near=None):
    """The speeds that failed a check because the cut falls inside a multiple root, refined again
    with more starts, written into ``out`` = (values (S, k), shapes (S, k, n), ok (S,)), ``k =
    count + 1``, by frequency.

    An axisymmetric rotor at rest has double roots: where the ``count``-th and the ``count +
    1``-th root are one of them, the highest start (the root's other half) is not above the
    ``count``-th root found, so :func:`_unmissed` cannot show that no root was missed below it, and
    the speed was solved whole (issue 28). Refined from ``k + e`` projected starts (``e`` up to
    ``_MULTIPLE_EXTRA``, the fewest that leave a start above the multiple root), the speed passes
    the same checks with the cut above the whole multiple root: its roots distinct or independent
    (:func:`_distinct`), no root missed below the multiple root's top (:func:`_unmissed`), the
    basis (made for the ``k + e`` roots, :func:`_basis_for`, from ``bound``) sufficing. The multiple root's shapes across
    the cut, where it is a double root, are its backward and forward whirl combinations, backward
    first (:func:`._eigensolve.resolve_repeated`): the root kept below the cut is the backward one,
    the lower of the two as soon as the rotor turns (``docs/theory.md`` section 17, "Multiple
    roots"); the full eigen-solve, before, kept either. ``project`` (``pencils``, basis, ``want``,
    rows) -> starts, vectors: the projected pencils' roots (:func:`._lowest_starts._projected_starts`
    by default; the rational pencil's, :func:`._lowest_branches._projected_starts`, for mounts with
    Maxwell branches). The modes route, :func:`roots_below` with a ``count`` and the Maxwell route
    take it alike.

    ``near`` (S,) bool: speeds whose roots all converged and are distinct but whose highest start,
    less the projection's error, does not lie above the ``count``-th root (:func:`_unmissed`)
    where the ``count + 1``-th is a distinct root just above the ``count``-th (a pair split by the
    speed, closer than the projection's error: a 400-coordinate shaft at 300 rad/s, 4101.0 and
    4102.8 rad/s with an error of 0.96): refined again the same way, the next start then the
    ``count + 2``-th, well above (issue 28).
    """
    project = _projected_starts if project is None else project
    values, shapes, ok = out
    k = values.shape[1]
    if k <= count or ok.all():
        return
    with np.errstate(invalid="ignore"):
        cut = np.abs(values[:, count] - values[:, count - 1]) <= _SAME * np.abs(values[:, count - 1])
    if near is not None:                # a distinct root just above the cut (not a multiple root)
        with np.errstate(invalid="ignore"):
            cut |= near & (np.abs(values[:, count].imag - values[:, count - 1].imag)
                           > _SAME * np.abs(values[:, count - 1]))
    rows = np.nonzero(~ok & cut)[0]
    n = len(bound.omegas)
    for extra in range(1, _MULTIPLE_EXTRA + 1):
        if not len(rows) or k + extra > n:
            return
        want = k + extra
        basis, suffices = _basis_for(pencils, bound, want, rows, project)
        starts, vectors = project(pencils, basis, want, rows)
        found, found_shapes, converged = _refined(pencils, starts, vectors, rows)
        top = _top_of_group(found, count)                              # (R,) the multiple root's last place
        above = top + 1 < want                                          # a start above it was refined
        unmissed = np.zeros(len(rows), bool)
        for place in np.unique(top[above]):                            # nothing missed below its top
            at = above & (top == place)
            unmissed[at] = _unmissed(starts[at], found[at], int(place) + 1)
        padded = np.full((len(values), want), np.nan + 0j)               # the bound is of every speed
        padded[rows] = found
        passed = converged & unmissed & _distinct(found, found_shapes) & suffices(padded)[rows]
        found, found_shapes = _by_frequency_over(found, found_shapes, count)
        # the multiple root across the cut by whirl, backward first, before the cut keeps its lower part
        _by_whirl(stack, found, found_shapes, np.ones(len(rows), bool))
        done = rows[passed]
        values[done], shapes[done], ok[done] = found[passed, :k], found_shapes[passed, :k], True
        rows = rows[~passed & ~above]                                   # more starts may reach above it


def _basis_for(pencils, bound, want, rows, project=None):
    """The reduced basis (n, m) for the ``want`` lowest roots at the speeds ``rows``, sized as
    :func:`_reduced_roots` sizes it, and its check (roots (S, want), NaN at the other speeds ->
    (S,) bool, :func:`_basis_suffices`). ``project``: as :func:`_cut_in_a_multiple_root`'s."""
    project = _projected_starts if project is None else project
    n = len(bound.omegas)
    size = min(n, max(3 * want, want + 10))
    rho = _MARGIN * np.nanmax(np.abs(project(pencils, bound.modes[:, :size], want, rows)[0]))
    size = min(n, max(_needed_size(bound, rho, size), want))
    _, attached = bound.shares(size, rho)
    return (np.hstack([bound.modes[:, :size], attached]),
            lambda found: _basis_suffices(found, bound, size, attached.shape[1], rho))


def _top_of_group(values, count):
    """(R,) the last place (0-based) of the group of roots of ``values`` (R, k), by frequency,
    that coincide (within ``_SAME``) with the ``count``-th, counting on from it."""
    key = np.sort(values.imag, axis=1)
    top = np.full(len(values), count - 1)
    for j in range(count, values.shape[1]):
        with np.errstate(invalid="ignore"):
            joined = (top == j - 1) & (np.abs(key[:, j] - key[:, count - 1]) <= _SAME * np.abs(key[:, count - 1]))
        top[joined] = j
    return top


def _swept(pencils, basis, want, count):
    """The full roots (S, want) of every speed from the projected pencils, unit shapes (S, want, n),
    whether each speed's converged (S,) and whether no projected root left unrefined can stand for
    a root below the ``count``-th found (S,, :func:`_unmissed` or its certificate between anchors).

    The solved anchors (every ``_SOLVED``-th of the anchors, every ``_STRIDE``-th speed and the
    last, :func:`._lowest_starts._anchors`) solve their projected pencils whole (``eig``,
    :class:`._lowest_starts._Expansions`) and start Newton's iteration from the lowest roots and
    vectors; :func:`_unmissed` checks them. The other speeds solve no projected pencil, the other
    anchors first (from the solved ones), then the rest (from every anchor): their starts are the
    nodes' refined roots carried over by the projected roots' second-order changes in the nearer
    solved anchor's eigenbasis, their vectors the nodes' shapes interpolated
    (:func:`._lowest_starts._expansion_guesses`), one factorisation per root
    (:func:`._lowest_newton._continued`), and the Gershgorin discs of that eigenbasis show that
    the projected pencil has no more than ``count`` roots below the ``count``-th found plus the
    projection's error (:func:`_certified`), the check :func:`_unmissed` makes where the projected
    roots are known. A speed whose roots cannot be carried over, or whose discs do not show it,
    solves its projected pencil (:func:`._lowest_starts._projected_starts`) and is refined and
    checked as an anchor."""
    speeds = len(pencils.speeds)
    values = np.empty((speeds, want), complex)
    shapes = np.empty((speeds, want, pencils.M.shape[0]), complex)
    ok, unmissed = np.zeros(speeds, bool), np.zeros(speeds, bool)
    solved, levels, eigen, refined = _solved_levels(pencils, basis, want, count, (values, shapes, ok))
    expansions = _Expansions(pencils, basis, solved, want, levels, eigen)
    places = np.nonzero(~np.isin(solved, refined))[0]
    _refine_into(_refined, pencils, expansions.starts[places], expansions.vectors[places], solved[places],
                 (values, shapes, ok))
    unmissed[solved] = _unmissed(expansions.starts, values[solved], count)
    moved = np.max(np.abs(expansions.starts - values[solved]), axis=1)      # the projection's error there
    # the anchors between the solved ones are carried over like the other speeds where the solved
    # anchors give a cubic in the speed; fewer (a coarse sweep) take their own projected roots
    projected_level = 0 if len(solved) < _NODES else -1
    first = 0
    for level, (part, _) in _level_parts(levels, 16 * want * shapes.shape[2]):
        places = first + np.arange(len(part))
        first += len(part)
        if level == projected_level:
            guesses, vectors, sure, projected = _projected_guesses(expansions, places, values, shapes, ok)
        else:
            guesses, vectors, sure = _expansion_guesses(expansions, places, values, shapes, ok)
            sure &= ~_doomed(expansions, places, guesses, moved, count)
        rows = part[sure]
        if len(rows):
            if not sure.all():
                guesses, vectors = guesses[sure], vectors[sure]
            _refine_into(_continued, pencils, guesses, vectors, rows, (values, shapes, ok))
            unmissed[rows] = _unmissed(projected[sure], values[rows], count) if level == projected_level \
                else _certified(expansions, places[sure], values, moved, count)
        del vectors
        # the speeds not carried over, and those whose discs show nothing: their own projected roots
        rows = part[~sure | (~unmissed[part] & ok[part])]
        if len(rows):
            again, vectors = _projected_starts(pencils, basis, want, rows)
            _refine_into(_refined, pencils, again, vectors, rows, (values, shapes, ok))
            unmissed[rows] = _unmissed(again, values[rows], count)
            del vectors
    return values, shapes, ok, unmissed


#: every this many anchors solve their projected pencils whole where the Gershgorin discs allow
#: (:func:`_solved_levels`; measured on ``compressor_example``, CPU against every ``_SOLVED``-th in
#: one process, median of 8-10 pairs: 401 speeds 7-9 % less, no middle anchor solved; 201 speeds
#: 3 % less, 2 of 12 solved; 101 speeds the same (0.99), every middle anchor solved)
_SPARSE_SOLVED = 4
#: the pilot's decompositions are kept for the main pass up to this much memory [bytes] (the main
#: pass takes them out as it uses them and keeps none of its own); beyond, every ``_SOLVED``-th
#: anchor is solved
_PILOT_BYTES = 64 * 2**20


def _solved_levels(pencils, basis, want, count, out):
    """The solved anchors (A,) of :func:`_swept`, its ``levels`` (each a part of the other speeds and
    the refined speeds its nodes are taken from, in the order they are refined), the anchors'
    ``eig`` already made (a dict for :class:`._lowest_starts._Expansions`, or None) and the anchors
    already refined into ``out`` = (values (S, k), shapes (S, k, n), ok (S,)).

    Every ``_SOLVED``-th anchor is solved, the other anchors are carried from them and the remaining
    speeds from every anchor (``docs/theory.md`` section 17). Where a sweep holds enough anchors, a
    pilot first solves every ``_SPARSE_SOLVED``-th (twice as far apart) and asks whether the Gershgorin
    discs of the nearer one's eigenbasis show the count (:func:`_certified`) at each
    ``_SOLVED``-th anchor between them (the speeds farthest from them), with the roots there
    predicted (the anchor's refined roots plus their second-order changes, :class:`._lowest_starts._Expansions`).
    Those where the discs do not are solved as well; the others are carried in levels of halved
    spacing, each level's nodes the speeds refined before it, the remaining speeds last. The
    pilot's ``eig`` and refined roots are kept: at most its ``_decomposed`` products are made twice.
    """
    speeds = len(pencils.speeds)
    grid = _anchors(speeds)
    rest = (np.setdiff1d(np.arange(speeds), grid), grid)
    solved = np.unique(np.append(grid[::_SOLVED], grid[-1]))
    sparse = np.unique(np.append(grid[::_SPARSE_SOLVED], grid[-1]))
    middles = np.setdiff1d(solved, sparse)
    kept = 16 * len(sparse) * 3 * (2 * basis.shape[1] + len(pencils.rows)) ** 2
    if len(sparse) < 2 * _NODES or not len(middles) or kept > _PILOT_BYTES:
        return solved, [(np.setdiff1d(grid, solved), solved), rest], None, np.zeros(0, int)
    eigen = {}
    pilot = _Expansions(pencils, basis, sparse, want, [(middles, sparse)], eigen, nodes=False)
    values, shapes, ok = out
    _refine_into(_refined, pencils, pilot.starts, pilot.vectors, sparse, out)
    moved = np.max(np.abs(pilot.starts - values[sparse]), axis=1)
    predicted = np.full(values.shape, np.nan + 0j)
    predicted[middles] = values[sparse[pilot.near]] + pilot.changes
    with np.errstate(invalid="ignore"):
        shown = _certified(pilot, np.arange(len(middles)), predicted, moved, count) & ok[sparse[pilot.near]]
    solved = np.union1d(sparse, middles[~shown])
    levels, done, step = [], solved, _SPARSE_SOLVED // 2
    while step >= 1:
        finer = np.union1d(np.append(grid[::step], grid[-1]), solved)
        levels.append((np.setdiff1d(finer, done), done))
        done, step = finer, step // 2
    return solved, levels + [rest], eigen, sparse


#: the starts' vectors of the speeds between anchors made at once (:func:`_swept`) [bytes]
_LEVEL_BYTES = 16 * 2**20


def _level_parts(levels, item_bytes):
    """``(level, (part, nodes))`` of :func:`_swept`'s ``levels``, in turn, each level's speeds a
    part of at most ``_LEVEL_BYTES`` of ``item_bytes`` each at a time (each speed's starts are its
    own, so the parts change no number): their starts' vectors are not held for every speed of a
    level at once (62 MB at 400 coordinates and 1,001 speeds)."""
    for level, (part, nodes) in enumerate(levels):
        for chunk in _batches.chunk_slices(len(part), item_bytes, budget=_LEVEL_BYTES):
            yield level, (part[chunk], nodes)


def _certified(expansions, places, values, moved, count):
    """(R,) at the speeds ``expansions.between[places]``: the projected pencil has at most
    ``count`` roots with ``0 < Im s < T``, ``T`` the ``count``-th root found (``values`` (S, k)) plus
    twice the larger projection error (``moved`` (A,), the largest move from projected to full root
    at each anchor) of the two anchors around the speed, by the Gershgorin discs of the nearer
    anchor's eigenbasis (:func:`._lowest_bound._gershgorin_count`). The ``count`` roots found below
    ``T`` stand for ``count`` of them, so a projected root that could stand for one more root below
    the ``count``-th found would be one too many: :func:`_unmissed`'s meaning, without that root."""
    between = expansions.between[places]
    if values.shape[1] <= count:        # a basis of every mode: the projected pencil is the full one
        return np.ones(len(between), bool)
    right = np.clip(np.searchsorted(expansions.solved, between), 1, len(moved) - 1)
    error = 2 * np.maximum(moved[right - 1], moved[right])
    found = np.sort(values[between].imag, axis=1)[:, count - 1]
    with np.errstate(invalid="ignore"):
        return _lowest_bound._gershgorin_count(expansions.centers[places], expansions.radii[places],
                                               found + error) <= count


#: a speed between anchors whose discs (:func:`_certified`) count more than ``count`` roots below
#: its predicted ``count``-th root less this share of it is not carried over (:func:`_doomed`)
_DOOMED_SHARE = 0.02


def _doomed(expansions, places, guesses, moved, count):
    """(R,) the speeds ``expansions.between[places]`` whose certificate (:func:`_certified`) is
    bound to fail: the Gershgorin discs of the nearer anchor's eigenbasis count more than
    ``count`` roots below ``T``, the ``count``-th of Newton's starts ``guesses`` (R, k) less
    ``_DOOMED_SHARE`` of it, plus the projection's error. The count grows with ``T``, and Newton's
    iteration moves a start far less than that share (the starts are second-order), so such a
    speed would be refined from its starts, fail :func:`_certified` and be refined again from
    its own projected roots (:func:`._lowest_starts._projected_starts`): it takes them at once,
    and the first Newton's iteration is saved (ROSS's compressor_example, 21 speeds: 13 of 17
    speeds between anchors, each the same bits as before). A speed taken here wrongly (its
    certificate would hold) is refined from its projected roots: the same roots to round-off."""
    if guesses.shape[1] <= count or not len(places):
        return np.zeros(len(places), bool)
    between = expansions.between[places]
    right = np.clip(np.searchsorted(expansions.solved, between), 1, len(moved) - 1)
    error = 2 * np.maximum(moved[right - 1], moved[right])
    with np.errstate(invalid="ignore"):
        key = np.sort(np.where(np.isfinite(guesses), guesses.imag, np.inf), axis=1)[:, count - 1]
        low = (1 - _DOOMED_SHARE) * key + error
        counted = _lowest_bound._gershgorin_count(expansions.centers[places], expansions.radii[places], low)
    return np.isfinite(low) & (counted > count)


#: Newton's iteration holds about this many complex vectors of ``n`` per root at once (the vectors,
#: their products with ``Q'``, the solves, the round-off's terms, :mod:`._lowest_newton`; measured
#: 19-28 at 400 coordinates)
_NEWTON_VECTORS = 24
#: the work memory of one part of the speeds refined together [bytes]: the speeds are refined in
#: parts of at most this much, so the peak memory of a sweep does not grow with its speeds beyond
#: the result's own arrays (issue 28: 884 MB at 1,001 speeds and 400 coordinates before)
_NEWTON_BYTES = 32 * 2**20


def _refine_into(refine, pencils, starts, vectors, rows, out, by_speed=False):
    """``refine(pencils, starts, vectors, rows)`` (:func:`._lowest_newton._refined` or
    ``_continued``) of the speeds ``rows`` (R,) in parts of at most ``_NEWTON_BYTES`` of work,
    written into ``out`` = (values (S, k), shapes (S, k, n), ok (S,)) at those rows. ``starts``
    (R, k) and ``vectors`` (R, k, n) are by row of ``rows``, or with ``by_speed`` (S, k) and
    (S, k, n) by speed (read at ``rows`` before they are written). Each root's iteration is its
    own (batched, not coupled), so the parts give the roots of one call bit for bit."""
    values, shapes, ok = out
    k, n = vectors.shape[1:]
    for part in _batches.chunk_slices(len(rows), 16 * _NEWTON_VECTORS * k * n, budget=_NEWTON_BYTES):
        at = rows[part]
        take = at if by_speed else part
        values[at], shapes[at], ok[at] = refine(pencils, starts[take], vectors[take], at)


def _needed_size(bound, rho, size):
    """The modes of the basis: of the sizes from the first mode above ``rho`` on, the one whose
    bound holds at every speed with the fewest modes and attachment directions together."""
    n = len(bound.omegas)
    first = int(np.searchsorted(bound.omegas, 1.1 * rho))
    best, best_total = n, n
    for m in np.unique(np.round(np.geomspace(max(first, 1), n, 24)).astype(int)):
        if m >= best_total:
            break
        shares, directions = bound.shares(int(m), rho, vectors=False)
        if np.all(shares <= _lowest_bound._SHARE) and m + directions.shape[1] < best_total:
            best, best_total = int(m), int(m) + directions.shape[1]
    return best


def _by_whirl(stack, values, shapes, rows):
    """A multiple root's shapes (any basis of its eigenspace, as Newton's iteration left them) made
    its whirl-sorted combinations, backward first, at the speeds ``rows`` (S,) bool, written over
    ``shapes`` (S, k, n): as the full eigen-solve gives them (:func:`._eigensolve.resolve_repeated`,
    pairs and groups of three or more), so an axisymmetric rotor at rest has the same whirl either
    way. ``values`` (S, k) by frequency."""
    from ._eigensolve import _repeated_pairs, resolve_groups, resolve_repeated

    every = np.nonzero(rows)[0]
    rows = np.unique(every[_repeated_pairs(values[every])[0]]) if len(every) else every
    if len(rows):
        shapes[rows] = resolve_repeated(values[rows], shapes[rows], stack.repeated_forms,
                                        np.zeros(len(rows), int), groups=False)
    resolve_groups(values, shapes, stack.repeated_forms, rows=every)


def _distinct(values, shapes=None):
    """(S,) no two refined roots of a speed are one root, and all are modes.

    Roots within ``_SAME`` of each other (relative) are one root reached twice, unless ``shapes``
    (S, k, n) is given and their shapes are independent: ``g`` coinciding roots whose ``g`` unit
    shapes have numerical rank ``g`` (:func:`_independent`) are a root of multiplicity ``g`` (an
    axisymmetric rotor at rest), not one simple root found by ``g`` starts (``docs/theory.md``
    section 17, "Multiple roots")."""
    lam = values
    gaps = np.abs(lam[:, :, None] - lam[:, None, :])
    same = gaps <= _SAME * np.abs(lam[:, :, None])
    np.einsum("sii->si", same)[...] = False
    apart = ~same.any(axis=(1, 2))
    if shapes is not None:
        for s in np.nonzero(~apart)[0]:
            apart[s] = all(_independent(shapes[s, group]) for group in _groups(same[s]))
    return apart & is_oscillating(lam).all(axis=1)


#: coinciding roots' unit shapes are independent where their smallest singular value exceeds this
#: times their largest: one simple root's shapes differ by its shape's error, about the square root
#: of the root's (``_SAME``; a root is stationary in its shape, docs/theory.md section 17)
_RANK = np.sqrt(_SAME)


def _groups(same):
    """The groups (lists of indices) of more than one root joined by ``same`` (k, k) bool."""
    left, groups = set(np.nonzero(same.any(axis=1))[0].tolist()), []
    while left:
        group, new = set(), {left.pop()}
        while new:
            group |= new
            new = set(np.nonzero(same[sorted(new)].any(axis=0))[0].tolist()) - group
        left -= group
        groups.append(sorted(group))
    return groups


def _independent(shapes):
    """The ``g`` shapes (g, n) have numerical rank ``g``: their smallest singular value exceeds
    ``_RANK`` times their largest (scale-free: the shapes need not be unit)."""
    sigma = np.linalg.svd(np.asarray(shapes), compute_uv=False)
    return bool(np.isfinite(sigma).all() and sigma[-1] > _RANK * sigma[0])


def _unmissed(starts, values, count):
    """(S,) no projected root left unrefined can stand for a root below the ``count``-th found.

    The starts are the lowest projected roots by frequency (S, k), ``values`` (S, k) their refined
    roots in the same order. A root of the full model missing from ``values`` has a projected root
    near it (see :func:`_basis_suffices`) that was not refined: its frequency is at least the
    highest start's. Taking the largest move from start to root of the speed as how near, that root
    lies above the ``count``-th lowest found when the highest start, less that move, does."""
    if starts.shape[1] <= count:        # a basis of every mode (n <= count): the projected pencil is the full one
        return np.ones(len(values), bool)
    moved = np.max(np.abs(starts - values), axis=1)
    found = np.sort(values.imag, axis=1)[:, count - 1]
    return starts[:, -1].imag - moved > found


def _basis_suffices(values, bound, size, directions, rho):
    """(S,) the basis (``size`` modes, ``directions`` attachment directions) holds at least 90 % of
    every root up to the highest one refined (:class:`_Bound`, at ``rho`` or that root if higher);
    otherwise the projected pencil may lack a root and the speed is solved whole."""
    highest = np.max(np.abs(values), axis=1)
    top = np.max(highest[np.isfinite(highest)], initial=rho)
    shares, _ = bound.shares(size, max(rho, top), directions)
    return np.isfinite(highest) & (shares <= _lowest_bound._SHARE)


#: why the reduced basis leaves a speed to the full eigen-solve, for the refusal's message
_UNSERVED = ("the reduced basis could not be shown to hold every root there; an axisymmetric rotor at rest has "
             "double roots")
#: the full eigen-solve's memory is measured against the memory at hand above this [bytes]
_CHECKED_BYTES = 2**30


def _refuse_long_full(stack, speeds, total: int, what: str, why: str, advice: str = "",
                      modes: int | None = None) -> None:
    """Refuse, before it, the full eigen-solve of ``speeds`` [rad/s] (of ``total``) where its
    arrays would not fit in the memory at hand, or where it is estimated to take longer than the
    limit of CPU time (``_cost``, lifted by ``--allow-long``): one line naming the speeds, the
    size, the estimate and the way out (``advice``, default: leave those speeds out). A long
    flexible rotor's full solve is a dense eigen-solution of thousands of states per speed
    (minutes each, GB of memory).

    The memory is :func:`_full_lowest`'s: one part's eigen-solutions (:func:`_full_bytes`) and the
    ``modes`` roots and shapes kept of every speed (default: every root, as the modes below a
    frequency keep them).

    Raises
    ------
    InputError
        ``MODEL: lowest modes: the full eigen-solve of 1 of 5 speeds (0 rpm; WHY), 1 eigen-solution
        of 16,008 states, would take about 39.8 min of CPU time, more than the limit of 30 min: leave
        those speeds out of the sweep, or add --allow-long (ROTORDYN_MODAL_MAX_CPU_MINUTES sets the
        limit)``; or ``MODEL: ... needs about 4.1 GiB of memory, 2.0 GiB is available: ...``.
    """
    from .._limits import memory_problem
    from ..errors import InputError

    n_states, count = stack.forms[0].n_states, len(speeds)
    named = _speeds_named(speeds)
    source = getattr(stack.models[0], "source", None)
    head = (f"{f'{source}: ' if source else ''}{what}: the full eigen-solve of {count:,} of {total:,} speeds "
            f"({named}; {why})")
    advice = advice or "leave those speeds out of the sweep"
    solutions = f"{count:,} eigen-solution{'s' if count > 1 else ''} of {n_states:,} states"
    kept = n_states // 2 if modes is None else min(int(modes), n_states // 2)
    needed = _full_bytes(n_states, count) + 16.0 * count * kept * (stack.n_dof + 1)
    if needed >= _CHECKED_BYTES:
        problem = memory_problem(needed, f"{head}, {solutions},", advice)
        if problem:
            raise InputError(problem)
    over = _cost.eigen_solutions_over_limit(n_states, count)
    if over is not None:
        seconds, limit = over
        raise InputError(f"{head}, {solutions}, would take about "
                         f"{_cost.duration(seconds)} of CPU time, more than the limit of {_cost.duration(limit)}: "
                         f"{advice}, or add --allow-long ({_cost.ENVIRONMENT} sets the limit)")


#: the work memory of one speed's full eigen-solution per squared state [bytes]: its state matrix,
#: ``eig``'s copy, vectors and values, the complex shapes (as a sweep's chunks count it,
#: :func:`.campbell.solve_sweeps`)
_FULL_ITEM = 72
#: a bar over the full eigen-solves moves in at least this many steps (the parts change no number:
#: each speed's eigen-solution is its own)
_FULL_STEPS = 20


def _full_parts(n_states: int, count: int, progress: bool = False) -> list:
    """The parts (slices) of ``count`` speeds whose full eigen-solutions of ``n_states`` states are
    solved together: at most ``_batches.CHUNK_BYTES`` of work each (one speed where its own is
    more), and, with a progress bar, at most a ``_FULL_STEPS``-th of the speeds."""
    largest = -(-count // _FULL_STEPS) if progress else None
    return _batches.chunk_slices(count, _FULL_ITEM * n_states ** 2, largest=largest)


def _full_bytes(n_states: int, count: int) -> float:
    """The work memory [bytes] of the largest part of :func:`_full_parts` (``count`` speeds of
    ``n_states`` states): what :func:`_full_lowest` holds beside the roots it keeps."""
    largest = max(part.stop - part.start for part in _full_parts(n_states, max(count, 1)))
    return float(_FULL_ITEM) * largest * n_states ** 2


#: why a model with frequency-dependent branches is solved whole, for the refusal's message
_BRANCHES = "the mounts' frequency-dependent (Maxwell) branches add states the reduced basis does not hold"


def _full_lowest(stack, speeds, count, progress=False):
    """The full eigen-solve of some speeds, their ``count`` lowest oscillating roots.

    The speeds are solved in parts (:func:`_full_parts`: about ``_batches.CHUNK_BYTES`` of work,
    one speed at a time where a speed's own is more), and each part's roots and shapes are cut to
    the ``count`` lowest before the next part: the memory is one part's eigen-solutions and the
    roots kept, not every root and shape of every speed (11 speeds of a 2,006-coordinate machine
    had taken 2.45 GB after 2 minutes, the state matrices of every speed at once).

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (S,) [rad/s]
    count : int
        Roots kept per speed (every root where it is more).
    progress : bool
        A progress bar over the speeds ("lowest modes (full eigen-solve)").

    Returns
    -------
    eigenvalues : ndarray, shape (S, k), complex [1/s]
        ``k = min(count, n_states / 2)``, the lowest oscillating first (:func:`lowest_of`).
    shapes : ndarray, shape (S, k, n), complex, unit norm
    """
    n_states = stack.forms[0].n_states
    k = min(int(count), n_states // 2)
    values = np.empty((len(speeds), k), complex)
    shapes = np.empty((len(speeds), k, stack.n_dof), complex)
    parts = _full_parts(n_states, len(speeds), progress)
    bar = None
    if progress:
        from .._progress import tqdm

        bar = tqdm(total=len(speeds), desc="lowest modes (full eigen-solve)", unit="speed", leave=False)
    small = stack.n_dof < DENSE_BELOW and 16 * len(speeds) * n_states * stack.n_dof <= _KEPT_REDUCTIONS_BYTES
    kept = _kept_full(stack) if small else None

    def solve(chunk):
        return stack.solve(stack.sweep(chunk)[0], np.zeros(len(chunk), int))

    try:
        for part in parts:
            chunk = speeds[part]
            if kept is None:
                lam, phi = solve(chunk)
            else:
                lam, phi = _kept_or_solved(kept, chunk, solve)
            values[part], shapes[part] = lowest_of(lam, phi, k)
            del lam, phi
            if bar is not None:
                bar.update(len(chunk))
    finally:
        if bar is not None:
            bar.close()
    return values, shapes


def _kept_full(stack) -> dict:
    """``{speed: (roots (m,), shapes (m, n))}`` of :func:`_full_lowest`'s solves of a small model
    (below ``DENSE_BELOW`` coordinates; a call of at most ``_KEPT_REDUCTIONS_BYTES`` of them) on
    ``stack`` (:func:`_kept_by_speed`): ``campbell``'s checks of its mode links solve some sweep
    speeds again, for more roots (each speed's solve is its own: the same bits)."""
    return _kept_by_speed(stack, "_lowest_full")


def _kept_by_speed(stack, name: str) -> dict:
    """A memo ``{speed [rad/s] (float): a tuple of that speed's arrays}`` kept on ``stack`` under
    ``name``, empty at first: the lowest modes' route keeps some solves of a stack's speeds in
    such memos (:func:`_kept_full`, :func:`_kept_upper`, :func:`_kept_vectors`,
    :func:`_kept_reductions`) for ``campbell``'s checks, which solve some sweep speeds again."""
    return stack.__dict__.setdefault(name, {})


def _kept_or_solved(kept, speeds, solve):
    """Each speed's arrays of ``speeds`` (S,) [rad/s], stacked by speed: a tuple of (S, ...)
    arrays, those ``kept`` (:func:`_kept_by_speed`) taken from it and the others solved together
    by ``solve(speeds)`` (a tuple of arrays by speed) and added to it. Each speed's solve is its own
    (the same bits with any other speeds or alone)."""
    new = np.array([p for p, speed in enumerate(speeds) if float(speed) not in kept], dtype=int)
    if len(new):
        made = solve(speeds[new])
        kept.update((float(speeds[p]), tuple(part[i] for part in made)) for i, p in enumerate(new))
    rows = [kept[float(speed)] for speed in speeds]
    return tuple(np.array([row[j] for row in rows]) for j in range(len(rows[0]))) if rows else None


def lowest_of(lam, phi, count):
    """The ``count`` lowest oscillating roots (then the others) of full eigen-solves, by speed:
    ``lam`` (N, m), ``phi`` (N, m, n) -> (N, count), (N, count, n)."""
    order = lowest_order(lam, count)[:, :count]
    rows = np.arange(len(lam))[:, None]
    return lam[rows, order], phi[rows, order]


# ----------------------------------------------------------------------------------------
# The modes below a frequency (campbell(max_frequency=F), campbell --max-frequency F)

def roots_below(stack, speeds, limit: float, count: int | None = None, progress: bool = False):
    """Every oscillating root of frequency ``Im lam`` at most ``limit`` at every speed (the lowest
    ``count`` of them where ``count`` is given), each the full model's root to round-off.

    The basis is made complete for ``limit`` (:class:`_Bound` at ``1.05 limit``, or at the
    largest ``|lam|`` of the projected roots below it) instead of for a number of roots; every root
    below the limit is refined with the first above it, and a speed passes the checks of
    :func:`lowest_roots` with the limit in place of the ``count``-th root (no projected root left
    unrefined can stand for a root below it), else it is solved whole.

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (S,) [rad/s]
    limit : float
        Highest frequency wanted, ``Im lam`` [rad/s] (> 0).
    count : int, optional
        At most this many roots per speed (the lowest).
    progress : bool
        A progress bar over the speeds solved whole (:func:`_full_lowest`), as in
        :func:`lowest_roots`.

    Returns
    -------
    eigenvalues : ndarray, shape (S, K), complex [1/s]
        By frequency at each speed (not tracked); ``K`` the most roots wanted at any speed. The
        entries past a speed's wanted roots are other roots of the full model (exact, but not
        shown to be the next ones): fillers that let the columns be tracked.
    shapes : ndarray, shape (S, K, n), complex, unit norm
    wanted : ndarray of bool, shape (S, K)
        The roots asked for (the first ones of each row).
    full : ndarray of bool, shape (S,)
        The speeds solved whole.
    """
    reduced = None
    if stack.n_dof >= DENSE_BELOW and not stack.branch_times.shape[1]:
        with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
            reduced = _reduced_below(stack, speeds, limit, count)
    if reduced is None:             # a small model, branches, or a basis of every mode: every root of every speed
        if stack.branch_times.shape[1]:
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency", _BRANCHES, "use fewer speeds")
        elif stack.n_dof >= DENSE_BELOW:
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency",
                              "a basis for the frequency would hold every mode",
                              "use fewer speeds, or a lower frequency")
        values, shapes = _full_lowest(stack, speeds, stack.forms[0].n_states)
        return _cut_below(values, shapes, limit, count) + (np.ones(len(speeds), bool),)
    values, shapes, ok = reduced
    full = ~ok
    _by_whirl(stack, values, shapes, ok)
    if full.any():
        _refuse_long_full(stack, speeds[full], len(speeds), "modes below a frequency", _UNSERVED)
        warnings.warn(f"modes below a frequency: {int(full.sum())} of {len(speeds)} speeds solved whole (the "
                      "reduced basis could not be shown to hold every root below it there)", stacklevel=3)
        lam, phi = _by_frequency(*_full_lowest(stack, speeds[full], stack.forms[0].n_states, progress), count)
        if _wanted(lam, limit, count).sum(axis=1).max(initial=0) > values.shape[1]:
            # more roots below the limit than columns (a root the basis missed): every speed whole
            _refuse_long_full(stack, speeds, len(speeds), "modes below a frequency",
                              "the reduced basis missed a root below it", "use fewer speeds")
            values, shapes = _full_lowest(stack, speeds, stack.forms[0].n_states, progress)
            return _cut_below(values, shapes, limit, count) + (np.ones(len(speeds), bool),)
        k = values.shape[1]
        values[full], shapes[full] = lam[:, :k], phi[:, :k]
    return values, shapes, _wanted(values, limit, count), full


def _wanted(values, limit, count):
    """(S, k) the roots asked for, of roots (S, k) sorted by frequency with the modes first."""
    wanted = is_oscillating(values) & (values.imag <= limit)
    if count is not None:
        wanted[:, count:] = False
    return wanted


def _cut_below(values, shapes, limit, count):
    """Roots (S, k) and shapes by frequency cut to the most wanted at any speed: the roots, the
    shapes and which are wanted (``shapes`` reordered over itself)."""
    values, shapes = _by_frequency_over(values, shapes, count)
    wanted = _wanted(values, limit, count)
    k = int(wanted.sum(axis=1).max(initial=0))
    return values[:, :k], shapes[:, :k], wanted[:, :k]


def _reduced_below(stack, speeds, limit, count):
    """:func:`_reduced_roots` for the roots below ``limit`` [rad/s] (at most ``count``): roots (S, k)
    by frequency, the wanted ones first, shapes (S, k, n) and whether the speed passed every check;
    by shift-invert Arnoldi (:func:`._arnoldi.below`) where the basis would be too large
    (:func:`._arnoldi.takes`); None where the basis would hold every mode of a model below that
    route's size (the full eigen-solve costs less)."""
    n = stack.n_dof
    pencils = _Pencils(stack, speeds)
    if _lowest_route._crowded(stack, pencils, limit=limit):      # Arnoldi, shown without the dense set-up below
        return _arnoldi_roots(stack, pencils, count, limit=limit)
    bound = _stack_bound(stack, pencils)
    omegas, modes = bound.omegas, bound.modes
    # the largest |lam| below the limit, from a few speeds' projected roots on the modes up to twice it
    few = np.unique(np.round(np.linspace(0, len(speeds) - 1, min(len(speeds), _FEW))).astype(int))
    size = min(n, int(np.searchsorted(omegas, 2.0 * limit)) + 10)
    starts = _projected_starts(pencils, modes[:, :size], size, few)[0]
    below = _wanted(starts, limit, count)
    rho = _MARGIN * max(limit, np.max(np.abs(starts), where=below, initial=0.0))
    size = min(n, _needed_size(bound, rho, size))
    attached = bound.shares(size, rho)[1] if size < n else np.zeros((n, 0))
    if _arnoldi.takes(size + attached.shape[1], n):     # the undamped modes crowd above the limit
        return _arnoldi_roots(stack, pencils, count, limit=limit)
    if size >= n:
        return None
    basis = np.hstack([modes[:, :size], attached])
    anchors, at = _anchored(len(speeds))
    starts, vectors = _starts_below(pencils, basis, limit, count, int(below.sum(axis=1).max(initial=0)) + 3, at)
    values, shapes, ok = _continued_sweep(pencils, starts, vectors, anchors,
                                          functools.partial(_projected_starts, pencils, basis, starts.shape[1]))
    del vectors
    ok &= _distinct(values, shapes) & _unmissed_below(starts, values, limit, count)
    values, shapes = _by_frequency_over(values, shapes, count)
    # the bound at the wanted roots (a missed one lies below the limit, :func:`_unmissed_below`)
    wanted = _wanted(values, limit, count)
    ok &= _basis_suffices(np.where(wanted, values, 0), bound, size, attached.shape[1], rho)
    if count is not None:               # the count-th root's other half the first start above it
        _cut_in_a_multiple_root(stack, pencils, bound, (values, shapes, ok), count)
    return values, shapes, ok


def _starts_below(pencils, basis, limit, count, want, vectors_at=None):
    """The projected roots of every speed up to the first above ``limit`` (or past the ``count``-th),
    the same number at every speed (the most any speed needs): starts (S, k) and vectors (S, k, n)
    (with ``vectors_at`` (S,) bool, at those speeds only: :func:`._lowest_starts._projected_starts`).
    ``want`` is a first guess of ``k``, doubled until every speed has a start above the limit."""
    most = basis.shape[1]
    while True:
        want = min(want, most)
        starts, vectors = _projected_starts(pencils, basis, want, vectors_at=vectors_at)
        needed = _wanted(starts, limit, count).sum(axis=1) + 1
        if needed.max() <= want or want == most:
            k = int(min(needed.max(), want))
            return starts[:, :k], vectors[:, :k]
        want *= 2


def _unmissed_below(starts, values, limit, count):
    """:func:`_unmissed` for the roots below ``limit``: (S,) no projected root left unrefined can
    stand for a root below the limit (or below the ``count``-th root found, where lower)."""
    top = np.full(len(values), float(limit))
    if count is not None and values.shape[1] >= count:
        top = np.minimum(top, np.sort(frequency_key(values), axis=1)[:, count - 1])
    moved = np.max(np.abs(starts - values), axis=1)
    return starts[:, -1].imag - moved > top


def _by_frequency_over(values, shapes, count=None):
    """:func:`._lowest_starts._by_frequency` with ``shapes`` (S, k, n) reordered over itself, a part
    of the speeds at a time (:func:`._batches.reordered_over`, as campbell's tracking): no second
    copy of every speed's shapes. Returns the roots (S, k) by frequency and ``shapes``."""
    order = lowest_order(values, count)
    _batches.reordered_over(shapes[None], order[None], _NEWTON_BYTES)
    return np.take_along_axis(values, order, 1), shapes


def _anchored(count: int):
    """The anchors (A,) of ``count`` speeds (:func:`._lowest_starts._anchors`) and where they are
    (count,) bool: the speeds whose projected vectors start Newton's iteration."""
    anchors = _anchors(count)
    at = np.zeros(count, bool)
    at[anchors] = True
    return anchors, at


def _continued_sweep(pencils, starts, vectors, anchors, restart):
    """The full roots of projected starts at every speed: the anchors refined from their starts,
    the speeds between them continued from the anchors' roots (``docs/theory.md`` section 17, step
    3a), in parts of bounded memory (:func:`_refine_into`); the route of :func:`_reduced_below` and
    of the Maxwell branches' rational pencil (:mod:`._lowest_branches`).

    Parameters
    ----------
    pencils : _Pencils
        The sweep's full pencils (or :class:`._lowest_branches.RationalPencils`).
    starts : ndarray, shape (S, k), complex [1/s]
        The projected roots of every speed, by frequency.
    vectors : ndarray, shape (S, k, n), complex
        Their vectors in full coordinates at the ``anchors`` (any values elsewhere); overwritten by
        the shapes.
    anchors : ndarray of int, shape (A,)
        :func:`_anchored`.
    restart : callable
        ``restart(rows) -> (starts (R, k), vectors (R, k, n))``: the projected starts with their
        vectors at the speeds ``rows``, for those that cannot be continued (a root that cannot be
        followed between the anchors, or an anchor that failed).

    Returns
    -------
    values : ndarray, shape (S, k), complex [1/s]
        The full roots, in their starts' order.
    shapes : ndarray, shape (S, k, n), complex
        ``vectors``, the unit shapes.
    ok : ndarray of bool, shape (S,)
        Every root of the speed converged.
    """
    values = np.empty(starts.shape, complex)
    ok = np.zeros(len(starts), bool)
    out = (values, vectors, ok)
    _refine_into(_refined, pencils, starts, vectors, anchors, out, by_speed=True)
    k = starts.shape[1]
    # the anchors' shapes by their place (A, k, 1): the continued speeds' vectors are gathered part by
    # part (:class:`_Gathered`), not copied for every speed at once
    places = np.arange(len(anchors) * k).reshape(len(anchors), k, 1)
    between, guesses, nearer, sure = _continuation_guesses(starts, pencils.speeds, anchors, values[anchors],
                                                           places, ok[anchors])
    rows = between[sure]
    if len(rows):
        _refine_into(_continued, pencils, guesses[sure], _Gathered(vectors, anchors, nearer[sure, :, 0]), rows, out)
    rows = between[~sure]
    n = vectors.shape[2]
    for part in _batches.chunk_slices(len(rows), 16 * _NEWTON_VECTORS * k * n, budget=_NEWTON_BYTES):
        again, again_vectors = restart(rows[part])
        _refine_into(_refined, pencils, again, again_vectors, rows[part], out)
    return values, vectors, ok


class _Gathered:
    """The anchors' shapes at given places, read part by part: ``self[part]`` is
    ``shapes[anchors[p // k], p % k]`` for the places ``p`` of the rows ``part`` (R, k, n); shape
    (J, k, n). The Newton starts of the continued speeds (:func:`_continued_sweep`) without a copy
    of every speed's vectors at once."""

    def __init__(self, shapes, anchors, places):
        self.shapes, self.anchors, self.places = shapes, anchors, places
        self.shape = places.shape + shapes.shape[2:]

    def __len__(self):
        return len(self.places)

    def __getitem__(self, part):
        places = self.places[part]
        k = self.shapes.shape[1]
        return self.shapes[self.anchors[places // k], places % k]


def _dense_lowest(stack, speeds, count):
    """:func:`_full_lowest` of a small model (``DENSE_BELOW``) from eigenvalues alone: every root of
    every speed by one batched ``eigvals``, the ``count`` lowest oscillating roots' shapes by one
    inverse-iteration step each on the pencil (``_pencils.pencil_shapes``). A speed whose roots
    need their eigenvectors to be judged, whose wanted roots are not all modes, or where a
    wanted root lies within ``_CLOSE`` of another, is solved whole by :func:`_full_lowest`.

    Returns
    -------
    eigenvalues : ndarray, shape (S, count), complex; shapes : ndarray, shape (S, count, n)
    """
    upper, whole = _kept_or_solved(_kept_upper(stack), speeds,
                                   lambda new: _eigensolve.upper_eigenvalues(stack.sweep(new)[0]))
    return _lowest_of_upper(stack, speeds, count, upper, whole.astype(bool))


def _kept_upper(stack) -> dict:
    """``{speed: (upper roots (m,), solved whole)}`` of :func:`_dense_lowest`'s ``eigvals`` at the
    speeds solved on ``stack`` (:func:`_kept_by_speed`; ``m`` roots of a model below ``DENSE_BELOW``
    coordinates: a few kB a speed): ``campbell``'s checks of its mode links solve some sweep
    speeds again, for more roots, from the same eigenvalues (each row's alone: the same bits)."""
    return _kept_by_speed(stack, "_lowest_upper")


def _small_lowest(stack, speeds, count):
    """The lowest roots of a small model: :func:`_gyroscopic_lowest` where the model is undamped
    gyroscopic, else :func:`_dense_lowest`."""
    lowest = _gyroscopic_lowest(stack, speeds, count)
    return _dense_lowest(stack, speeds, count) if lowest is None else lowest


def _gyroscopic_lowest(stack, speeds, count):
    """:func:`_dense_lowest` of an undamped gyroscopic model, its roots from the eigenvalues of a
    Hermitian matrix (:func:`_gyroscopic_roots`) instead of ``eigvals`` of the state matrices;
    None for any other model."""
    upper, whole = _gyroscopic_roots(stack, speeds)
    return None if upper is None else _lowest_of_upper(stack, speeds, count, upper, whole)


def _lowest_of_upper(stack, speeds, count, upper, whole):
    """The ``count`` lowest oscillating roots (S, count) of every speed's upper roots ``upper``
    (S, m) and their shapes (S, count, n) by inverse iteration on the pencil; the speeds ``whole``
    (S,), and those where the roots kept are not all modes or one lies within ``_CLOSE`` of another,
    solved whole (:func:`_full_lowest`)."""
    order = lowest_order(upper, count)[:, :count]
    lam = np.take_along_axis(upper, order, axis=1)
    whole |= ~is_oscillating(lam).all(axis=1) | _close(lam, upper, order)
    shapes = np.empty(lam.shape + (stack.n_dof,), complex)
    if whole.any():
        lam[whole], shapes[whole] = _full_lowest(stack, speeds[whole], count)
    sure = np.nonzero(~whole)[0]
    if len(sure):
        shapes[sure] = _pencil_shapes(stack, speeds[sure], lam[sure])
    return lam, shapes


def _gyroscopic_roots(stack, speeds):
    """The upper roots (S, n) of an undamped gyroscopic model at every speed from the eigenvalues
    of a Hermitian matrix of its ``2 n`` states, and which speeds are to be solved whole (a root
    within the square root of the round-off of zero); ``(None, None)`` for any other model.

    With ``M = L L^T``, ``K_h = L^-1 K L^-T = R^T R`` (both Cholesky: M and K positive definite)
    and ``G_h = L^-1 G L^-T`` (skew), the state ``y = [R x_h, s x_h]``, ``x_h = L^T x``, of a root
    ``s`` of ``s^2 M + s Omega G + K`` solves ``s y = H y``, ``H = [[0, R], [-R^T, -Omega G_h]]``
    real and skew: ``B = -i H`` is Hermitian, its eigenvalues the ``+-omega`` of the roots
    ``s = i omega``. ``eigvalsh`` of ``B`` costs a third of ``eigvals`` of the real state matrix
    (benchmarks/README.md, "Undamped gyroscopic models") and keeps the roots on the imaginary
    axis; within ``eps |B|`` of the roots where ``eig`` of the state matrix is within ``eps |A|``
    (rotor_example: 1e-13 against 1.5e-12 relative, from an extended-precision Newton
    refinement).

    Parameters
    ----------
    stack : Stack
        One model; the route applies where its damping is zero, its stiffness constant, symmetric
        and positive definite, its gyroscopic matrix skew, and it has no Maxwell branches.
    speeds : ndarray, shape (S,) [rad/s]

    Returns
    -------
    upper : ndarray, shape (S, n), complex [1/s], or None
        ``i omega``, ascending.
    whole : ndarray of bool, shape (S,), or None
    """
    hermitian = _hermitian_form(stack)
    if hermitian is None:
        return None, None
    constant, gyroscopic = hermitian
    n = stack.n_dof
    if len(speeds) * 32 * n * n <= _KEPT_REDUCTIONS_BYTES:        # kept for the checks of the links
        omega, reduced, taus = _batches._threaded(functools.partial(_hermitian_reductions, constant, gyroscopic),
                                                  speeds, item_bytes=64 * n * n)
        _kept_reductions(stack).update(
            (float(speed), (reduced[p], taus[p], omega[p])) for p, speed in enumerate(speeds) if taus[p, 0] == taus[p, 0])
        _eigvalsh_where_failed(omega, constant, gyroscopic, speeds)
    else:
        omega = _batches._threaded(functools.partial(_hermitian_eigenvalues, constant, gyroscopic), speeds,
                                   item_bytes=64 * n * n)
    return 1j * omega[:, n:], _near_zero(constant, gyroscopic, speeds, omega)


#: the sweep's Hessenberg reductions of the Hermitian route kept on its stack, at most this many
#: bytes (201 speeds of rotor_example: 5 MB): ``campbell``'s checks of its mode links solve some
#: sweep speeds again, with eigenvectors (:func:`weighted_lowest_roots`), from the same reductions
_KEPT_REDUCTIONS_BYTES = 8 * 2**20


def _kept_vectors(stack) -> dict:
    """``{speed: (eigenvalues (N,), eigenvectors (N, count))}`` of the Hermitian route's ``B`` at the
    speeds :func:`weighted_lowest_roots` solved on ``stack``, kept on it (the latest of a speed's):
    ``_lowest_pairs.pairs_kept`` starts from them."""
    return _kept_by_speed(stack, "_lowest_vectors")


def _kept_reductions(stack) -> dict:
    """``{speed: (reduction (N, N), tau (N - 1,), eigenvalues (N,))}`` of the Hermitian route's
    ``B`` at the speeds solved on ``stack`` (:func:`_gyroscopic_roots`), kept on it."""
    return _kept_by_speed(stack, "_lowest_reductions")


def _near_zero(constant, gyroscopic, speeds, omega):
    """(S,) the lowest upper root of each speed, ``omega[:, n]`` of the ascending eigenvalues
    ``omega`` (S, 2 n) of ``B = constant + speeds gyroscopic``, lies within the square root of the
    solve's round-off of zero (``eps |B|_F``, as :func:`._roots.round_off` takes it from the
    balanced state matrix): its shape is needed to judge it, and the speed is solved whole."""
    noise = _roots.BACKWARD_FACTOR * np.finfo(float).eps * np.hypot(np.linalg.norm(constant),
                                                                     speeds * np.linalg.norm(gyroscopic))
    return omega[:, omega.shape[1] // 2] <= _roots.zero_floor(noise)


def weighted_lowest_roots(stack, speeds, count):
    """The ``count`` lowest roots (S, count) of an undamped gyroscopic small model (the route of
    :func:`_gyroscopic_lowest`) and their mass-weighted unit shapes (S, count, n), the shapes from
    the Hermitian matrix's own eigenvectors: for ``campbell``'s checks of its mode links
    (``campbell._check_roots``), which compare shapes by their MAC only. None where the model
    takes another route, or where :func:`_lowest_of_upper` would solve a speed whole (a root
    near zero, not a mode, or within ``_CLOSE`` of another): the caller takes
    :func:`lowest_roots` there.

    The roots are :func:`_gyroscopic_roots`' (the same bits). An eigenvector ``z`` of the
    symmetric tridiagonal ``J`` of :func:`_hermitian_eigenvalues` (LAPACK's ``dstein``, inverse
    iteration at the root) is one of ``B = Q (i T) Q^T`` as ``y = Q conj(D) z``,
    ``D = diag(i^k)`` (``Q`` from the same ``dgehrd``, ``dorghr``), within ``eps |B|`` over the
    gap to the next root as the shape of the pencil's one inverse-iteration step is; its lower
    half ``s L^T x`` is the root's mass-weighted shape ``L^T x`` (``M = L L^T``) times ``s``. Its
    MAC with the pencil's shape (:func:`_pencil_shapes`) weighted differs from 1 by 1e-15 on
    ``rotor_example``; the shapes' phase is not ``eig``'s (a MAC does not read it). Per speed one
    ``dstein`` and ``dorghr`` against ``count`` complex ``n x n`` LU solves, and no product with
    the mass matrix's factor (``tests/test_speed33.py``).

    Parameters
    ----------
    stack : Stack
    speeds : ndarray, shape (S,) [rad/s]
    count : int

    Returns
    -------
    (eigenvalues, weighted) : (ndarray, shape (S, count), complex [1/s]; ndarray, shape (S, count, n), complex), or None
    """
    n = stack.n_dof
    if n >= DENSE_BELOW or not 0 < count <= n:
        return None
    hermitian = _hermitian_form(stack)
    if hermitian is None:
        return None
    constant, gyroscopic = hermitian
    with _batches.one_blas_thread(64 * n * n):
        omega, vectors = _hermitian_eigenvectors(constant, gyroscopic, speeds, count, _kept_reductions(stack))
    if vectors is None:
        return None
    _kept_vectors(stack).update((float(speed), (omega[p], vectors[p])) for p, speed in enumerate(speeds))
    if _near_zero(constant, gyroscopic, speeds, omega).any() or _close_upper(omega[:, n:], count).any():
        return None
    return 1j * omega[:, n:n + count], unit_rows(np.swapaxes(vectors[:, n:], 1, 2))


def _close_upper(upper, count):
    """(S,) :func:`_lowest_of_upper`'s test of the ``count`` lowest of the ascending frequencies
    ``upper`` (S, m) [rad/s] of an undamped gyroscopic model's roots ``i omega``: a root lies
    within ``_CLOSE`` of its modulus of another root or of its own conjugate (``_close``; of sorted
    numbers the nearest other is a neighbour, and ``|i a - i b| = |a - b|`` exactly), or the lowest
    is not above zero (a speed :func:`_near_zero` solves whole too). Two roots of one frequency
    (``lowest_order``'s ties) are close, so where none is, ``lowest_order`` keeps the ascending
    order and every root kept is a mode: with :func:`_near_zero` the same speeds as
    :func:`_lowest_of_upper` solves whole, without its general sorts."""
    top = min(count + 1, upper.shape[1])
    gaps = np.diff(upper[:, :top], axis=1)                          # (S, top - 1): j to j + 1
    nearest = 2 * upper[:, :count]                                  # to its own conjugate
    nearest[:, :top - 1] = np.minimum(nearest[:, :top - 1], gaps[:, :count])
    nearest[:, 1:] = np.minimum(nearest[:, 1:], gaps[:, :count - 1])
    return ~(upper[:, 0] > 0) | (nearest <= _CLOSE * upper[:, :count]).any(axis=1)


def _hermitian_eigenvectors(constant, gyroscopic, speeds, count, kept=None):
    """:func:`_hermitian_eigenvalues` (S, 2 n), the same bits, and the eigenvectors (S, 2 n, count)
    of ``B`` of the ``count`` lowest nonnegative ones (``n`` to ``n + count - 1``) as
    :func:`weighted_lowest_roots` takes them; ``(eigenvalues, None)`` where LAPACK's inverse
    iteration does not converge or the tridiagonal splits (a zero off-diagonal). ``kept``: the
    reductions of some speeds already made (:func:`_kept_reductions`), the same bits."""
    size = constant.shape[0]
    half = size // 2
    out = np.empty((len(speeds), size))
    vectors = np.empty((len(speeds), size, count), complex)
    kept = {} if kept is None else kept
    new = [p for p, speed in enumerate(speeds) if float(speed) not in kept]
    made = _hermitian_reductions(constant, gyroscopic, speeds[new]) if new else None
    zero = np.zeros(size)
    blocks, split = np.ones(size, np.int32), np.zeros(size, np.int32)
    split[0] = size
    turn = (1j ** -np.arange(size))[:, None]                        # conj(D), D = diag(i^k)
    where = {p: i for i, p in enumerate(new)}
    for p, speed in enumerate(speeds):
        if p in where:
            out[p], reduced, tau = (part[where[p]] for part in made)
        else:
            reduced, tau, out[p] = kept[float(speed)]
        off = np.diagonal(reduced.T, -1)
        if tau[0] != tau[0] or not np.all(off):       # a failed reduction or eigenvalue solve (NaN), or a split
            return out, None
        z, info = scipy.linalg.lapack.dstein(zero, off, out[p, half:half + count], blocks, split)
        if info != 0:
            return out, None
        q, info = scipy.linalg.lapack.dorghr(reduced.T, tau)
        if info != 0:           # pragma: no cover
            return out, None
        vectors[p] = q @ (turn * z)
    return out, vectors


def _hermitian_reductions(constant, gyroscopic, speeds):
    """The orthogonal Hessenberg reductions (``dgehrd``) of ``S = Im(constant + speeds[p]
    gyroscopic)`` (real skew: ``B = i S``) and the eigenvalues of ``B`` from them (``dsterf``),
    as :func:`_hermitian_eigenvalues` takes them.

    Returns
    -------
    eigenvalues : ndarray, shape (P, N)
        Ascending (NaN where LAPACK failed).
    reduced : ndarray, shape (P, N, N)
        Each speed's reduction of ``S^T``, transposed (``reduced[p].T`` is LAPACK's output).
    taus : ndarray, shape (P, N - 1)
        Its reflectors' factors (NaN where LAPACK failed).
    """
    matrices = np.multiply(speeds[:, None, None], gyroscopic.imag)
    matrices += constant.imag
    out = np.empty(matrices.shape[:2])
    taus = np.empty((len(speeds), matrices.shape[1] - 1))
    zero = np.zeros(matrices.shape[1])
    for p, matrix in enumerate(matrices):
        # S^T = -S, Fortran-ordered as LAPACK takes it (no copy): its reduction is -T, the same eigenvalues
        reduced, taus[p], info = scipy.linalg.lapack.dgehrd(matrix.T, overwrite_a=1)
        if info == 0:
            out[p], info = scipy.linalg.lapack.dsterf(zero, np.diagonal(reduced, -1).copy(), overwrite_e=1)
        if not np.shares_memory(reduced, matrix):      # pragma: no cover (f2py wrote a copy)
            matrix[...] = reduced.T
        if info != 0:           # pragma: no cover (LAPACK's reduction and root-free QR do not fail on finite input)
            out[p], taus[p] = np.nan, np.nan
    return out, matrices, taus


def _hermitian_form(stack):
    """``B(Omega) = B_0 + Omega B_1`` of :func:`_gyroscopic_roots`: ``B_0 = [[0, -i R], [i R^T, 0]]``
    and ``B_1`` (2 n, 2 n), complex, each Hermitian; None where the model is not undamped
    gyroscopic with M and K positive definite. Made once per stack (kept on it) and with one BLAS
    thread: ``campbell``'s checks of its mode links solve the lowest modes of the same stack at
    finer speeds six times more (``campbell._check_grids``), and BLAS's own threads on these small
    products only wait for a core on a shared machine (measured on ``rotor_example``, 21 speeds, load
    about 20: 57 ms of CPU a ``campbell(modes=12)`` of 111 ms, against 2.9 ms with one thread)."""
    kept = stack.constants        # a small model's: shared by its stacks
    cached = kept.get("_lowest_hermitian", False)
    if cached is False:
        with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
            cached = kept["_lowest_hermitian"] = _hermitian_form_made(stack)
        for array in cached or ():
            array.flags.writeable = False
    return cached


def _hermitian_form_made(stack):
    """:func:`_hermitian_form`, made."""
    if len(stack) != 1 or stack.dependent or stack.branch_times.shape[1] or np.any(stack.C[0]):
        return None
    M, G, K = stack.M[0], stack.G[0], stack.K[0]
    if not (_within_round_off(K - K.T, K) and _within_round_off(G + G.T, G) and _within_round_off(M - M.T, M)):
        return None             # cross-coupled (or circulatory) stiffness: the state matrices' eigvals
    n = len(M)
    inverse = scipy.linalg.solve_triangular(stack.factor[0], np.eye(n), lower=True, check_finite=False)
    stiffness = inverse @ (0.5 * (K + K.T)) @ inverse.T
    gyroscopic = inverse @ (0.5 * (G - G.T)) @ inverse.T
    try:
        root = np.linalg.cholesky(0.5 * (stiffness + stiffness.T)).T       # K_h = R^T R
    except np.linalg.LinAlgError:       # K singular (a rotor free to move): eigvals of the state matrix
        return None
    constant = np.zeros((2 * n, 2 * n), complex)
    constant[:n, n:] = -1j * root
    constant[n:, :n] = 1j * root.T
    speed_part = np.zeros((2 * n, 2 * n), complex)
    speed_part[n:, n:] = 0.5j * (gyroscopic - gyroscopic.T)
    return constant, speed_part


def _within_round_off(part, matrix) -> bool:
    """``part`` (the departure of ``matrix`` from symmetry or skew symmetry) is round-off of the
    assembly: no entry above ``8 eps`` times the largest of ``matrix``."""
    return bool(np.max(np.abs(part), initial=0.0) <= 8 * np.finfo(float).eps * np.max(np.abs(matrix), initial=0.0))


def _hermitian_eigenvalues(constant, gyroscopic, speeds):
    """Ascending eigenvalues (P, 2 n) of ``B = constant + speeds[p] gyroscopic`` (Hermitian, each
    ``i`` times a real skew matrix ``S``), in real arithmetic: an orthogonal Hessenberg reduction
    of ``S`` (``dgehrd``) is skew and so tridiagonal, ``T`` with subdiagonal ``e`` (2 n - 1,), and
    ``i T`` is unitarily similar (``diag(i^k)``) to the real symmetric tridiagonal with zero
    diagonal and off-diagonals ``e``, whose eigenvalues ``dsterf`` gives. Within ``eps |B|`` of
    ``B``'s, as ``eigvalsh``'s (the reduction is backward stable and ``T`` is taken exactly skew),
    at two thirds of its time (a real reduction, not a complex one: rotor_example, 56 states)."""
    return _eigvalsh_where_failed(_hermitian_reductions(constant, gyroscopic, speeds)[0], constant, gyroscopic,
                                  speeds)


def _eigvalsh_where_failed(out, constant, gyroscopic, speeds):
    """``out`` (P, 2 n), the eigenvalues of :func:`_hermitian_reductions`, with each row its
    LAPACK reduction left NaN solved again by ``eigvalsh`` of ``B`` at that speed (in place)."""
    for p in np.flatnonzero(np.isnan(out[:, 0])):   # pragma: no cover (LAPACK does not fail on finite input)
        out[p] = np.linalg.eigvalsh(1j * (constant.imag + speeds[p] * gyroscopic.imag))
    return out


def _pencil_shapes(stack, speeds, lam):
    """Unit shapes (S, k, n) of the roots ``lam`` (S, k), one inverse-iteration step each on its
    speed's pencil (``_pencils.pencil_shapes``), the speeds shared between threads."""
    damping, stiffness = stack.damping_stiffness(np.zeros(len(speeds), int), speeds)
    k, n = lam.shape[1], stack.n_dof
    if stiffness.ndim == 2:             # one stiffness for every speed
        part = functools.partial(_pencil_shapes_part, stack.M[0], stiffness)
        return _batches._threaded(part, lam, damping, item_bytes=48 * k * n * n,
                                  thread_bytes=_batches.SOLVE_THREAD_BYTES)
    return _batches._threaded(functools.partial(_pencil_shapes_part, stack.M[0]), stiffness, lam, damping,
                              item_bytes=48 * k * n * n, thread_bytes=_batches.SOLVE_THREAD_BYTES)
