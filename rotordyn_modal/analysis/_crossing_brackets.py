"""The brackets of the critical speeds: every crossing of a tracked mode with an excitation order
line between two speeds of the sweep's grid, with what the refinement reads of the sweep there,
and whether the crossing's mode stays far from every other root over its bracket (``docs/theory.md``,
section 10).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import _batches
from .modal import is_oscillating

def _rows_of(table, rows):
    """The rows ``rows`` of every column of a table of arrays (a NamedTuple), as the same type."""
    return type(table)(*(column[rows] for column in table))


class _Brackets(NamedTuple):
    """One row per crossing: the variant, grid interval ``[speeds[k], speeds[k+1]]``, tracked
    mode (0-based), excitation slope [rad/s per rad/s], source index and order; and what the
    refinement reads of the sweep at every step, gathered once (:func:`_bracket_ends`)."""

    variant: np.ndarray
    k: np.ndarray
    mode: np.ndarray
    slope: np.ndarray
    source: np.ndarray
    order: np.ndarray
    start: np.ndarray
    """``speeds[k]`` [rad/s]"""
    width: np.ndarray
    """``speeds[k + 1] - speeds[k]`` [rad/s]"""
    low: np.ndarray
    """The tracked mode's eigenvalue at ``speeds[k]``"""
    high: np.ndarray
    """and at ``speeds[k + 1]``"""
    spread: np.ndarray
    """Its travel across the bracket (with a floor: ``+ 1e-9 |low| + 1e-300``)"""
    travel: np.ndarray
    """The fastest travel of any root of the sweep across the bracket"""
    near_speeds: np.ndarray
    """The sweep's four speeds around the bracket (two each side, or the four at the grid's
    end), (P, 4)"""
    near_values: np.ndarray
    """and the tracked mode's eigenvalues there, (P, 4)"""
    near_oscillating: np.ndarray
    """whether the mode oscillates at all four (:func:`~.modal.is_oscillating`)"""
    isolated: np.ndarray
    """Whether the mode stays far from every other root across the bracket (:func:`_isolated`)"""

    subset = _rows_of


def _crossing_brackets(speeds, values, sources, orders, oscillating=None) -> _Brackets:
    """Grid intervals where ``Im lam - slope |Omega|`` changes sign for an oscillating mode.

    ``values`` (V, N, m) and one ExcitationSources per variant (same names, the multipliers
    may differ)."""
    mode_ok = is_oscillating(values) if oscillating is None else oscillating
    both = mode_ok[:, :-1] & mode_ok[:, 1:]
    multipliers = np.array([s.multipliers for s in sources], dtype=float)            # (V, n_sources)
    factors = np.asarray(orders, dtype=float)
    # excitation [rad/s] per |speed| [rad/s] of every (source, order), source after source, per variant
    slopes = (factors[None, :, None] * multipliers.T[:, None, :]).reshape(-1, len(sources))
    # speeds along the last axis: the passes below run along them (contiguous where that copy is
    # no larger than the gaps of the lines taken at once)
    frequencies, magnitudes, both = values.imag.swapaxes(1, 2), np.abs(speeds), both.swapaxes(1, 2)
    if 8 * values.size <= _LINES_BYTES:
        frequencies = np.ascontiguousarray(frequencies)
    parts = []
    # the lines a few at a time: their gaps are each the size of the sweep's eigenvalues
    lines_at_once = max(1, _LINES_BYTES // (8 * values.size))
    for lines in (slice(i, i + lines_at_once) for i in range(0, len(slopes), lines_at_once)):
        slope = slopes[lines]
        gap = frequencies - slope[:, :, None, None] * magnitudes                    # (L, V, m, N)
        sign = np.sign(gap)
        change = (sign[..., :-1] != sign[..., 1:]) & (gap[..., :-1] != 0) & both
        if not (slope != 0).all():
            change &= (slope != 0)[:, :, None, None]
        line, v, k, mode = change.swapaxes(2, 3).nonzero()                          # by line, variant, speed, mode
        parts.append((v, k, mode, slope[line, v], line + lines.start))
    if not parts:                                        # no sources or no orders
        parts = [(*(np.zeros(0, dtype=int) for _ in range(3)), np.zeros(0), np.zeros(0, dtype=int))]
    v, k, mode, slope, line = parts[0] if len(parts) == 1 else (np.concatenate(c) for c in zip(*parts))
    source, order = np.divmod(line, max(len(factors), 1))
    return _Brackets(v, k, mode, slope, source, factors[order], *_bracket_ends(speeds, values, mode_ok, v, k, mode))


#: the largest part of the gaps to the excitation lines computed at once [bytes]
_LINES_BYTES = 4 * 2**20


def _bracket_ends(speeds, values, oscillating, v, k, mode):
    """The sweep's data of each crossing that the refinement reads (see :class:`_Brackets`).

    Every root at both ends of a bracket (what :func:`_isolated` and the travels read) is
    gathered a part of the crossings at a time (``_ENDS_BYTES``) and not kept: for a large
    machine it would be two full sets of roots per crossing (57 GiB for the crossings of a
    machine of 2,006 coordinates at 11 speeds)."""
    count = len(k)
    start = speeds[k]
    low, high = values[v, k, mode], values[v, k + 1, mode]
    spread, travel, isolated = np.empty(count), np.empty(count), np.empty(count, dtype=bool)
    for part in _batches.chunk_slices(count, 64 * values.shape[-1], budget=_ENDS_BYTES):
        ends = values[v[part, None], k[part, None] + np.arange(2)]                  # (p, 2, m)
        travels = np.abs(ends[:, 1] - ends[:, 0])
        spread[part] = travels[np.arange(len(ends)), mode[part]] + 1e-9 * np.abs(low[part]) + 1e-300
        travel[part] = travels.max(axis=1)
        isolated[part] = _isolated(_Ends(k[part], mode[part], ends, travels))
    if len(speeds) < 4:
        near = np.full((count, 4), np.nan), np.full((count, 4), np.nan, dtype=complex), np.zeros(count, bool)
    else:
        nodes = np.minimum(np.maximum(k - 1, 0), len(speeds) - 4)[:, None] + np.arange(4)
        near = (speeds[nodes], values[v[:, None], nodes, mode[:, None]],
                oscillating[v[:, None], nodes, mode[:, None]].all(axis=1))
    return (start, speeds[k + 1] - start, low, high, spread, travel) + near + (isolated,)


#: the largest part of the roots at the brackets' ends gathered at once [bytes]
_ENDS_BYTES = 16 * 2**20


class _Ends(NamedTuple):
    """A part of the crossings with every root at both ends of their brackets (what
    :func:`_isolated` reads): grid interval and tracked mode (P,), the roots (P, 2, m) and
    their travels across the bracket, ``|ends[:, 1] - ends[:, 0]|`` (P, m)."""

    k: np.ndarray
    mode: np.ndarray
    ends: np.ndarray
    travels: np.ndarray


def _isolated(brackets):
    """Crossings whose mode stays far from every other root over its bracket (``brackets``: an
    :class:`_Ends`).

    At both ends of the bracket, every other root (and every root's conjugate, its own
    included) is farther from the mode than twice the distance both can travel across the
    bracket (their spreads between the ends) plus seven of the mode's spreads. Then at any
    point of the bracket the mode's eigenvalue is the nearest to the linear interpolation
    by a wide margin (over 4x the distance plus twice the spread) and single: what
    :func:`_tracked` takes as told apart by distance alone.

    Returns
    -------
    ndarray of bool, shape (P,)
    """
    rows = np.arange(len(brackets.k))
    mode, ends, travels = brackets.mode, brackets.ends, brackets.travels                 # (P, 2, m), (P, m)
    own = ends[rows, :, mode]                                                            # (P, 2)
    own_travel = travels[rows, mode] + 1e-9 * np.abs(own).max(axis=1)
    margin = 2 * (travels + 7 * own_travel[:, None])                                    # (P, m)
    apart = np.minimum(np.abs(ends - own[..., None]), np.abs(ends.conj() - own[..., None])).min(axis=1)
    apart[rows, mode] = np.inf
    own_conjugate = 2 * np.abs(own.imag).min(axis=1)
    return (apart > margin).all(axis=1) & (own_conjugate > 2 * 8 * own_travel)
