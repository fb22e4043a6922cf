"""Critical speeds: the crossings of tracked natural frequencies with excitation orders.

The sweep of :mod:`.campbell` brackets every crossing of every mode with every source's order
lines between two speeds of its grid; here each crossing is refined on the eigenproblem itself,
all of a sweep (and of a study's chunk of variants) together: Newton's method on the eigenpair
and the speed together for the isolated modes of small pencils, secant steps on the speed with
an eigenpair converged at each step for the others, brackets whose tracked mode jumped between
close roots (or crowded with close roots) swept again finer. ``docs/theory.md``, section 10,
derives each step and gives the figures.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..model._validation import mesh_name
from . import _batches, _eigensolve, _pencils, _vectors, _whirl
from ._stack import Pencils, Stack
from .modal import damping_ratios, is_oscillating
from .tracking import track_modes_many

__all__ = ["CriticalSpeeds", "ExcitationSources", "excitation_sources", "off_order_line", "JUMP_TOLERANCE"]


@dataclass(frozen=True)
class ExcitationSources:
    """Excitation frequencies per unit reference speed.

    Attributes
    ----------
    names : tuple of str
        Rotor names (their spin orders) and ``mesh:DRIVER-DRIVEN`` for gear meshes.
    multipliers : ndarray, shape (n_sources,)
        Excitation frequency of order 1 / |reference speed|: ``|r_j|`` for a rotor,
        ``driver_teeth * |r_driver|`` for a gear mesh.
    """

    names: tuple
    multipliers: np.ndarray


def excitation_sources(model) -> ExcitationSources:
    """Every rotor's spin and every gear mesh with ``driver_teeth``."""
    names = [r.name for r in model.rotors]
    multipliers = [abs(r.speed_ratio) for r in model.rotors]
    for t in model.transmissions:
        if t.driver_teeth:
            names.append(mesh_name(t.driver, t.driver_teeth, t.driven))   # unique: validation
            multipliers.append(t.driver_teeth * abs(model.speed_ratios[t.driver]))
    return ExcitationSources(tuple(names), np.array(multipliers, dtype=float))


@dataclass(frozen=True)
class CriticalSpeeds:
    """Crossings of tracked natural frequencies with excitation orders.

    Attributes (one entry per crossing, sorted by speed)
    ----------------------------------------------------
    source : ndarray of str
    order : ndarray of float
    mode : ndarray of int
        Tracked mode label (1-based).
    speeds : ndarray [rad/s]
    frequencies_hz : ndarray [Hz]
    whirl : ndarray of str
    whirl_ratios, damping_ratios : ndarray
    mode_at_speed : ndarray of int
        The number ``modal(model, speed)`` (and ``modes --speed SPEED_RPM``) gives the
        crossing's mode at its critical speed: the mode whose shapes ``modes --shape`` draws,
        with the row's frequency (0 where the root is not a mode there); see
        :mod:`.mode_numbers`. Computed on first use from the sweep the crossings were found on
        (None for a table not made by a sweep).
    """

    source: np.ndarray
    order: np.ndarray
    mode: np.ndarray
    speeds: np.ndarray
    frequencies_hz: np.ndarray
    whirl: np.ndarray
    whirl_ratios: np.ndarray
    damping_ratios: np.ndarray
    #: the sweep the crossings were found on, for ``mode_at_speed``: (model, speeds (N,) [rad/s],
    #: tracked eigenvalues (N, m) [1/s]); no field, so that code copying a table row by row
    #: over its fields (``dataclasses.fields``) is unchanged
    _sweep = None

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    def __len__(self) -> int:
        return len(self.speeds)

    @functools.cached_property
    def mode_at_speed(self) -> np.ndarray | None:
        """(n_crossings,) int: the number ``modal`` gives each crossing's mode at its critical
        speed (see the class's attributes); None for a table not made by a sweep."""
        from .mode_numbers import numbers_at_crossings

        if not len(self):
            return np.zeros(0, dtype=int)
        if self._sweep is None:
            return None
        model, sweep_speeds, sweep_eigenvalues = self._sweep
        zeta = np.asarray(self.damping_ratios, dtype=float)
        imag = 2 * np.pi * np.asarray(self.frequencies_hz, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            eigenvalues = -zeta * imag / np.sqrt(1 - zeta**2) + 1j * imag
        return numbers_at_crossings(model, sweep_speeds, sweep_eigenvalues, self.speeds, self.mode, eigenvalues)

    def to_dataframe(self):
        """Table with the command line's columns (``pandas.DataFrame``): ``source, order, mode,
        speed_rpm, frequency_hz, whirl, whirl_ratio, damping_ratio, mode_at_speed`` (``mode`` the
        tracked label, ``mode_at_speed`` the number ``modal(model, speed)`` gives that mode at
        the row's speed, 0 where it is not a mode there; empty for a table not made by a sweep)."""
        import pandas as pd

        numbers = self.mode_at_speed
        return pd.DataFrame({
            "source": self.source, "order": self.order, "mode": self.mode,
            "speed_rpm": self.speeds_rpm, "frequency_hz": self.frequencies_hz,
            "whirl": self.whirl, "whirl_ratio": self.whirl_ratios,
            "damping_ratio": self.damping_ratios,
            "mode_at_speed": pd.array([pd.NA] * len(self), dtype="Int64") if numbers is None else numbers,
        })


def _with_sweep(table: CriticalSpeeds, model, speeds, eigenvalues) -> CriticalSpeeds:
    """``table`` knowing the sweep it was found on (its ``mode_at_speed``): ``model``, the
    sweep's ``speeds`` (N,) [rad/s] and tracked ``eigenvalues`` (N, m) [1/s]."""
    object.__setattr__(table, "_sweep", (model, speeds, eigenvalues))     # the table was just made
    return table


#: a critical speed's natural frequency off its order line by more than this (relative) is a jump
JUMP_TOLERANCE = 1e-6


def off_order_line(table: CriticalSpeeds, sources: ExcitationSources) -> np.ndarray:
    """Relative distance of each critical speed's natural frequency from the excitation
    frequency of its order and source at that speed: round-off at a crossing; more where the
    tracked mode jumps between two close roots inside the bracket (see
    :func:`.campbell.campbell`).

    Returns
    -------
    ndarray, shape (len(table),)
    """
    multiplier = dict(zip(sources.names, sources.multipliers))
    line = np.array([order * multiplier[name] for name, order in zip(table.source, table.order)], dtype=float)
    line = line * np.abs(table.speeds) / (2 * np.pi)
    return _relative_to_line(table.frequencies_hz, line)


def _warn_of_jumps(table, sources, model):
    """Warn of critical speeds that are jumps of a tracked mode, not crossings."""
    off = off_order_line(table, sources)
    jumps = off > JUMP_TOLERANCE
    if jumps.any():
        warnings.warn(f"{model.source}: {jumps.sum()} of {len(table)} critical speeds are not crossings but "
                      f"jumps of a tracked mode between close roots inside a bracket (its frequency there up "
                      f"to {100 * off.max():.2g} % off the order line; modes {sorted(set(table.mode[jumps].tolist()))}): "
                      f"a finer speed grid resolves them", stacklevel=4)


def _find_critical_speeds(stack, speeds, values, weighted, sources, orders, shapes=None, oscillating=None,
                          progress=False, check=None) -> list:
    """Every crossing of every mode with every source's order lines, for every variant,
    refined together. ``shapes`` (V, N, m, n), the sweep's unit shapes, start the cheap
    evaluation of isolated modes (:func:`_Iterates`); ``progress`` shows a bar over the
    crossings; ``check``, when given, is called with the number of crossings before they are
    refined (it may refuse them: see :func:`.campbell.campbell`). Returns one
    :class:`CriticalSpeeds` per variant."""
    brackets = _crossing_brackets(speeds, values, sources, orders, oscillating)
    count = len(stack)
    if not len(brackets.k):
        return [_critical_table([], [], [], [], [], [], [], []) for _ in range(count)]
    if check is not None:
        check(len(brackets.k))
    # one BLAS thread: the pencils' factorisations and solves are too small to share well
    with _batches.one_blas_thread(72 * stack.forms[0].n_states ** 2), _progress_bar(progress, len(brackets.k)):
        found = _refined(stack, speeds, values, weighted, shapes, brackets, sources, orders)
    ratios = found.ratio
    zeta = damping_ratios(found.lam)
    names = np.asarray(sources[0].names, dtype=str)[found.source]
    labels = _whirl.whirl_labels(ratios)
    roots, lam = found.roots, found.lam
    tables = []
    for v in range(count):
        mine = slice(None) if count == 1 else np.nonzero(found.variant == v)[0]
        order = np.lexsort((found.mode[mine], found.order[mine], names[mine], roots[mine]))
        if count > 1:
            order = mine[order]
        tables.append(_critical_table(names[order].astype(object), found.order[order], found.mode[order] + 1,
                                      roots[order], lam.imag[order] / (2 * np.pi), labels[order].astype(object),
                                      ratios[order], zeta[order]))
    return tables


class _Progress:
    """A progress bar over the sweep's crossings (a ``tqdm`` bar); the work of a part (a bracket
    swept again) advances it by that part's share, scaled to the units of its own crossings."""

    def __init__(self, bar):
        self.bar, self.scale, self.done, self.shown = bar, 1.0, 0.0, 0

    def advance(self, count):
        self.done += count * self.scale
        shown = min(int(self.done + 1e-6), self.bar.total)
        if shown > self.shown:
            self.bar.update(shown - self.shown)
            self.shown = shown


_PROGRESS = contextvars.ContextVar("rotordyn_modal_critical_progress", default=None)


@contextlib.contextmanager
def _progress_bar(enabled, total):
    """While refining ``total`` crossings: a bar (``tqdm.auto``) when ``enabled``."""
    if not enabled:
        yield
        return
    from tqdm.auto import tqdm

    with tqdm(total=total, desc="critical speeds", unit="crossing", leave=False) as bar:
        token = _PROGRESS.set(_Progress(bar))
        try:
            yield
        finally:
            _PROGRESS.reset(token)


def _progress_advance(count):
    """``count`` crossings (of the current part's units) done."""
    progress = _PROGRESS.get()
    if progress is not None:
        progress.advance(count)


@contextlib.contextmanager
def _progress_share(weight):
    """A part of the work worth ``weight`` of the current units (0: work already counted, such as
    a jump's bracket swept again); :func:`_progress_units` sets how many units of its own it
    has. On leaving, the bar stands exactly ``weight`` further."""
    progress = _PROGRESS.get()
    if progress is None:
        yield
        return
    outer, goal = progress.scale, progress.done + weight * progress.scale
    progress.scale = 0.0 if weight == 0 else outer * weight
    try:
        yield
    finally:
        progress.scale = outer
        progress.advance((goal - progress.done) / outer if outer else 0.0)


def _progress_units(count):
    """The current part (:func:`_progress_share`) has ``count`` crossings of its own."""
    progress = _PROGRESS.get()
    if progress is not None and count:
        progress.scale /= count


def _rows_of(table, rows):
    """The rows ``rows`` of every column of a table of arrays (a NamedTuple), as the same type."""
    return type(table)(*(column[rows] for column in table))


class _Found(NamedTuple):
    """Refined crossings, one row each: variant, tracked mode (0-based), source index and order;
    the speed [rad/s], the eigenvalue, the whirl ratio and the fingerprint of the shape there
    (:func:`_fingerprints`), and whether the eigenvalue was told apart by distance alone (see
    :func:`_refine_together`). The shapes themselves are not kept: a large machine's crossings
    would hold one shape each (32 GB for the million crossings of 2,006 coordinates)."""

    variant: np.ndarray
    mode: np.ndarray
    source: np.ndarray
    order: np.ndarray
    roots: np.ndarray
    lam: np.ndarray
    ratio: np.ndarray
    fingerprint: np.ndarray
    sure: np.ndarray

    subset = _rows_of


def _refined(stack, speeds, values, weighted, shapes, brackets, sources, orders, depth=0):
    """The crossings of ``brackets`` refined (:func:`_refine_parts`), with the brackets whose
    rows are not crossings of their own swept again (:func:`_resolve_jumps`); the brackets
    crowded with crossings among close roots (:func:`_crowded`) are swept again at once."""
    crowded = _crowded(brackets, shapes, depth)
    if not crowded.any():
        return _refined_alone(stack, speeds, values, weighted, shapes, brackets, sources, orders, depth)
    found = _refined_alone(stack, speeds, values, weighted, shapes, brackets.subset(~crowded), sources, orders, depth)
    swept = _swept_again(stack, speeds, values, weighted, shapes, brackets.subset(crowded), None, sources, orders,
                         depth)
    return _Found(*(np.concatenate(column) for column in zip(found, *swept)))


def _refined_alone(stack, speeds, values, weighted, shapes, brackets, sources, orders, depth):
    """:func:`_refined` of brackets each refined by itself (none crowded)."""
    if not len(brackets.k):
        return _no_crossings(brackets, stack.n_dof)
    found = _Found(brackets.variant, brackets.mode, brackets.source, brackets.order,
                   *_refine_parts(stack, speeds, values, weighted, brackets, shapes))
    unresolved = _unresolved(found, brackets)
    if unresolved.any():
        found = _resolve_jumps(stack, speeds, values, weighted, shapes, brackets, found, unresolved, sources, orders,
                               depth)
    return found


#: a bracket with at least this many crossings among close roots is swept again at once: each
#: of them would take every root at its first trial speed, the sub-sweep takes them at seven
_CROWDED = 14


def _crowded(brackets, shapes, depth):
    """Rows of the sweep's brackets (not a sub-sweep's) each of which holds, for its variant, at
    least ``_CROWDED`` crossings not isolated (:func:`_isolated`)."""
    if depth > 0 or depth >= _SUB_DEPTH or shapes is None or len(brackets.k) < _CROWDED:
        return np.zeros(len(brackets.k), dtype=bool)
    close = ~brackets.isolated
    key = brackets.variant * (int(brackets.k.max()) + 1) + brackets.k
    return np.bincount(key[close], minlength=int(key.max()) + 1)[key] >= _CROWDED


def _no_crossings(brackets, n_dof):
    """The _Found of no brackets (a jump with no crossing under it, a sweep whose brackets were
    all swept again)."""
    return _Found(brackets.variant, brackets.mode, brackets.source, brackets.order, np.zeros(0),
                  np.zeros(0, complex), np.zeros(0), np.zeros((0, min(n_dof, _FINGERPRINT)), complex),
                  np.zeros(0, bool))


def _off_line(found, slope):
    """Relative distance of each row's frequency from its order line (:func:`off_order_line`)."""
    return _relative_to_line(found.lam.imag, slope * np.abs(found.roots))


def _relative_to_line(frequency, line):
    """``|frequency - line| / line`` (``/ 1`` where the line is at zero)."""
    return np.abs(frequency - line) / np.where(line > 0, line, 1.0)


def _unresolved(found, brackets):
    """Rows that are not a crossing of their own: a jump (off the order line by more than
    ``JUMP_TOLERANCE``), or the same root as another mode's row of the same line and bracket
    (two tracked modes that close in on one root of a cluster)."""
    out = _off_line(found, brackets.slope) > JUMP_TOLERANCE
    if len(found.roots) < 2:
        return out
    key = (found.roots, brackets.k, brackets.order, brackets.source, brackets.variant)
    order = np.lexsort(key)
    same = np.ones(len(order) - 1, dtype=bool)
    for column in key[1:]:
        same &= column[order[1:]] == column[order[:-1]]
    roots, lam = found.roots[order], found.lam[order]
    same &= np.abs(np.diff(roots)) <= _SAME_ROOT * np.maximum(np.abs(roots[1:]), 1.0)
    same &= np.abs(np.diff(lam)) <= _SAME_ROOT * np.abs(lam[1:])
    if same.any():
        # a double root's two modes have shapes of their own; one root found twice has one shape
        first, second = order[:-1][same], order[1:][same]
        a, b = found.fingerprint[first], found.fingerprint[second]
        mac = np.abs(np.einsum("pi,pi->p", a.conj(), b)) ** 2 / (_vectors.row_norms(a)[:, 0] * _vectors.row_norms(b)[:, 0]) ** 2
        twice = mac > 1 - _SAME_ROOT
        out[first[twice]] = out[second[twice]] = True
    return out


#: two rows whose speeds and eigenvalues agree to this (relative), with shapes whose MAC is
#: within this of 1, are one root
_SAME_ROOT = 1e-9


#: speeds of the sub-sweep across a bracket whose tracked mode jumped (see :func:`_resolve_jumps`)
_SUB_SPEEDS = 9
#: sub-sweeps within sub-sweeps at most (each a further 8 times finer)
_SUB_DEPTH = 3


def _resolve_jumps(stack, speeds, values, weighted, shapes, brackets, found, unresolved, sources, orders, depth=0):
    """Crossings in place of the rows where the tracked mode jumped between close roots.

    Where two roots veer (come close and part with their shapes exchanged) between two speeds
    of the sweep, the mode tracked by its shape passes from one root to the other, and ``g``
    changes sign across the bracket without a root: the refinement closes in on the jump. Such
    a bracket is swept again at ``_SUB_SPEEDS`` speeds, every root tracked across that finer
    grid from the sweep's modes at the bracket's start, and every crossing of those paths with
    the line that jumped is refined as in the sweep, in place of all the sweep's rows of that
    line in that bracket: each is a root on the line, labelled with the mode it is at the
    bracket's start. Jumps left within a sub-sweep are resolved the same way, ``_SUB_DEPTH``
    levels deep; any still left stay as they are (and are warned of). A sub-sweep costs
    ``_SUB_SPEEDS - 2`` eigen-solves of the state matrix, at every size: on machines of 151
    coordinates, 0-17 % of the whole call (docs/theory.md, section 10).

    Parameters
    ----------
    stack, speeds, values, weighted, shapes, brackets : as :func:`_refine_together`'s
    found : _Found
        The refined rows of ``brackets``.
    unresolved : ndarray of bool
        Its rows that are not crossings of their own (:func:`_unresolved`).
    sources : list of ExcitationSources, one per variant; orders : tuple of float

    Returns
    -------
    _Found
    """
    if depth >= _SUB_DEPTH or shapes is None:
        return found
    # one group per (variant, bracket, line) with a jump: all its rows are found again
    group = np.stack([brackets.variant, brackets.k, brackets.source, brackets.order])
    # (by each row's group number: a table of every row against every redone group would
    # grow as their product)
    group = np.unique(group, axis=1, return_inverse=True)[1].reshape(-1)
    again = np.isin(group, group[unresolved])
    with _progress_share(0):                        # these crossings were counted once refined
        swept = _swept_again(stack, speeds, values, weighted, shapes, brackets, again, sources, orders, depth)
    return _Found(*(np.concatenate(column) for column in zip(found.subset(~again), *swept)))


def _swept_again(stack, speeds, values, weighted, shapes, brackets, rows, sources, orders, depth):
    """The crossings of the lines of ``rows`` (bool, all where None) of ``brackets``, each
    bracket swept again (:func:`_crossings_in`): one _Found per (variant, bracket)."""
    rows = np.ones(len(brackets.k), dtype=bool) if rows is None else rows
    singles = {}           # each variant's model alone, as its own analysis has it (bit for bit)
    out = []
    for v, k in np.unique(np.stack([brackets.variant[rows], brackets.k[rows]]), axis=1).T.astype(int):
        if v not in singles:
            singles[v] = stack if len(stack) == 1 else Stack([stack.models[v]])
        mine = rows & (brackets.variant == v) & (brackets.k == k)
        lines = set(zip(brackets.source[mine].tolist(), brackets.order[mine].tolist()))
        with _progress_share(int(mine.sum())):
            out.append(_crossings_in(singles[v], v, speeds[k:k + 2], values[v, k:k + 2], shapes[v, k:k + 2],
                                     weighted[v, k:k + 2], sources[v], orders, lines, depth))
    return out


def _crossings_in(single, v, ends, end_values, end_shapes, end_weighted, sources, orders, lines, depth):
    """Every crossing of the lines ``lines`` ({(source, order)}) inside the bracket ``ends`` of
    variant ``v``, found on a sub-sweep (see :func:`_resolve_jumps`) of ``single``, the stack of
    that variant's model alone. Returns a _Found of variant ``v``."""
    speeds = np.linspace(ends[0], ends[1], _SUB_SPEEDS)
    inner = speeds[1:-1]
    first = np.zeros(len(inner), dtype=int)
    lam, phi = _sub_sweep(single, inner, end_values.shape[-1])
    values = np.concatenate([end_values[:1], lam, end_values[1:]])[None]                  # (1, S, m)
    shapes = np.concatenate([end_shapes[:1], phi, end_shapes[1:]])[None]
    weighted = np.concatenate([end_weighted[:1], single.weighted(phi, first), end_weighted[1:]])[None]
    order = track_modes_many(values, weighted)                    # from the sweep's modes at the start
    rows = np.arange(len(speeds))[None, :, None]
    values, shapes, weighted = values[0, rows, order], shapes[0, rows, order], weighted[0, rows, order]
    brackets = _crossing_brackets(speeds, values, [sources], orders)
    wanted = [(s, o) in lines for s, o in zip(brackets.source.tolist(), brackets.order.tolist())]
    brackets = brackets.subset(np.nonzero(wanted)[0])
    _progress_units(len(brackets.k))
    found = _refined(single, speeds, values, weighted, shapes, brackets, [sources], orders, depth + 1)
    return found._replace(variant=np.full(len(found.roots), v))


def _sub_sweep(single, speeds, columns):
    """The roots (S, m) and unit shapes (S, m, n) of a bracket swept again at ``speeds``: every
    root, or, where the sweep has fewer ``columns`` than roots (a sweep of the lowest modes
    only), the ``columns`` lowest, the same roots inside. A large model's lowest roots come
    from the lowest modes' route (:func:`._lowest.lowest_roots`, its basis shared with the
    sweep's), never from every root of its state matrices (a flexible rotor of thousands of
    coordinates: minutes and GB per speed)."""
    from . import _lowest_branches
    from ._lowest import DENSE_BELOW, lowest_of, lowest_roots

    lowest = columns < single.forms[0].n_states // 2
    if lowest and single.branch_times.shape[-1]:       # Maxwell branches: the rational pencil's lowest roots
        lam, phi, _ = _lowest_branches.lowest_roots(single, speeds, columns)
        return lam, phi
    if lowest and single.n_dof >= DENSE_BELOW:
        lam, phi, _ = lowest_roots(single, speeds, columns)
        return lam, phi
    lam, phi = single.solve(single.sweep(speeds)[0], np.zeros(len(speeds), dtype=int))
    if lam.shape[-1] > columns:                  # a sweep of the lowest modes only: the same roots inside
        lam, phi = lowest_of(lam, phi, columns)
    return lam, phi


def _critical_table(source, order, mode, speeds, freq, whirl, ratios, zeta) -> CriticalSpeeds:
    return CriticalSpeeds(
        source=np.asarray(source, dtype=object), order=np.asarray(order, dtype=float),
        mode=np.asarray(mode, dtype=int), speeds=np.asarray(speeds, dtype=float),
        frequencies_hz=np.asarray(freq, dtype=float), whirl=np.asarray(whirl, dtype=object),
        whirl_ratios=np.asarray(ratios, dtype=float), damping_ratios=np.asarray(zeta, dtype=float),
    )


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


#: evaluations allowed per crossing (it needs two or three; bisection steps guarantee the rest)
_MAX_ITERATIONS = 200
#: a step below this fraction of max(|Omega|, 1 rad/s) ends the iteration (Brent's xtol before)
_STEP_TOLERANCE = 1e-13


def _refine_parts(stack, speeds, values, weighted, brackets, shapes=None):
    """The crossings refined (:func:`_refined_part`: Newton's method where it applies, else the
    secant of :func:`_refine_together`) with the eigenvalues and shapes at the roots, in parts
    of the crossings whose factorisations fit in ``_batches.CHUNK_BYTES``.

    Returns
    -------
    roots : ndarray (P,) [rad/s]; lam : ndarray (P,), complex; ratio : ndarray (P,), the whirl
    ratios; fingerprint : ndarray (P, f), complex (:func:`_fingerprints`); sure : ndarray (P,) bool
    """
    chunks = _batches.chunk_slices(len(brackets.k), 64 * stack.n_dof ** 2)
    if len(chunks) == 1:                             # all in one part (small models): no copies
        found = _compact(stack, brackets, *_refined_part(stack, speeds, values, weighted, brackets, shapes))
        _progress_advance(len(brackets.k))
        return found
    parts = []
    for part in chunks:
        mine = brackets.subset(part)
        parts.append(_compact(stack, mine, *_refined_part(stack, speeds, values, weighted, mine, shapes)))
        _progress_advance(len(mine.k))
    return _batches.concatenated(parts)


def _compact(stack, brackets, roots, lam, phi, sure):
    """A part's refined crossings with each shape replaced by what is kept of it: its whirl
    ratio and its fingerprint (:func:`_fingerprints`)."""
    ratio = stack.whirl_ratios(phi[:, None], brackets.variant, roots)[:, 0]
    return roots, lam, ratio, _fingerprints(phi), sure


#: shapes of more coordinates than this are kept as fingerprints of this many numbers
_FINGERPRINT = 48


def _fingerprints(phi):
    """What :func:`_unresolved` compares of the shapes ``phi`` (P, n): the shapes themselves up to
    ``_FINGERPRINT`` coordinates, else their products with a fixed random complex matrix (n,
    ``_FINGERPRINT``). The MAC of two fingerprints is 1 to round-off where the shapes are
    parallel (one root found twice); for shapes apart, a product that brings them within the
    test's 1e-9 of parallel would have to fall within about 1e-9 of a subspace of codimension
    ``_FINGERPRINT``: a chance far below 1e-100."""
    n = phi.shape[-1]
    if n <= _FINGERPRINT:
        return phi
    draws = np.random.default_rng(_FINGERPRINT_SEED).standard_normal((2, n, _FINGERPRINT))
    return phi @ (draws[0] + 1j * draws[1])


_FINGERPRINT_SEED = 20261128


def _refined_part(stack, speeds, values, weighted, brackets, shapes):
    """:func:`_refine_parts` of one part: the crossings of isolated modes of small pencils by
    :func:`_joint_newton`, the others (and any it leaves) by :func:`_refine_together` and
    :func:`_shapes_at`."""
    newton = _by_newton(stack, speeds, brackets, shapes)
    rows = newton.nonzero()[0]
    if len(rows):
        found = _joint_newton(stack, speeds, brackets if newton.all() else brackets.subset(rows), shapes)
        if found[-1].all() and newton.all():         # the usual case for small models: all done
            return found
        newton[rows] = found[-1]
    rest = (~newton).nonzero()[0]
    mine = brackets.subset(rest)
    roots, lam, sure, iterates = _refine_together(stack, speeds, values, weighted, mine, shapes)
    lam, phi = _shapes_at(stack, speeds, values, weighted, mine, roots, lam, sure, iterates)
    count = len(brackets.k)
    out = (np.empty(count), np.empty(count, dtype=complex), np.empty((count, stack.n_dof), dtype=complex),
           np.ones(count, dtype=bool))
    for column, value in zip(out, (roots, lam, phi, sure)):
        column[rest] = value
    if len(rows):
        ended = found[-1].nonzero()[0]
        for column, value in zip(out[:3], found[:3]):
            column[rows[ended]] = value[ended]
    return out


#: pencils of up to this many coordinates refine their isolated modes by :func:`_joint_newton`
#: (a dense bordered solve per step costs less than the Python calls of the secant's nested
#: iteration; above, one factorisation per crossing reused by every step costs less)
_NEWTON_DOF = 48
#: most joint Newton steps of a crossing (from the cubic start it takes two to four)
_NEWTON_STEPS = 12


def _by_newton(stack, speeds, brackets, shapes):
    """Crossings that :func:`_joint_newton` refines: isolated modes (:func:`_isolated`) of
    pencils of at most ``_NEWTON_DOF`` coordinates with constant coefficients, strictly between
    two speeds of the sweep on one side of zero."""
    count = len(brackets.k)
    if shapes is None or stack.dependent or stack.branch_times.shape[-1] or stack.n_dof > _NEWTON_DOF:
        return np.zeros(count, dtype=bool)
    a, b, ga, gb = _ends_and_gaps(speeds, brackets)
    return brackets.isolated & (ga != 0) & (gb != 0) & ((a >= 0) | (b <= 0))


def _joint_newton(stack, speeds, brackets, shapes):
    """Roots of ``g(Omega) = Im lam(Omega) - slope |Omega|`` in every bracket by Newton's method
    on the tracked mode's eigenpair and the speed together (:func:`_pencils.speed_newton_step`),
    all crossings in one batch.

    The start is the cubic's (:func:`_cubic_start`, error of order h^4), with the eigenvalue the
    cubic through the sweep's points gives there and the sweep's shape at the nearer end of the
    bracket (which also fixes the scaling ``c^H phi = 1``, so that the shape's entries are at
    most about 1). Each step's size is the largest of the speed's (relative to
    ``max(|Omega|, 1 rad/s)``), the eigenvalue's (relative) and the shape's largest entry. A
    crossing ends after a step below ``_STEP_TOLERANCE``: its point is then the root, with the
    eigenpair there, and the error left is of the order of that step squared. (Ending a step
    earlier, where the last two steps' sizes promised quadratic convergence, left errors of
    2e-13: the first step's size is the start shape's error, which says little of the
    speed's.)

    A crossing fails where its speed leaves the bracket, a step is not finite, it has not
    ended after ``_NEWTON_STEPS`` steps, or its eigenvalue is not the tracked mode's (farther
    than twice the mode's travel across the bracket from its interpolation, as in
    :func:`_pencil_at`): the caller refines those by :func:`_refine_together`, whose iteration
    keeps every point inside its bracket. Rows stop stepping as they end, so each row's numbers
    are its own whatever the others are (a study's variant equals its model's own analysis bit
    for bit).

    Returns
    -------
    roots : ndarray (P,) [rad/s]
    lam : ndarray (P,), complex
    phi : ndarray (P, n), complex, unit norm
    done : ndarray (P,) bool
        Ended at a root (the other rows' values are meaningless).
    """
    k, slope = brackets.k, brackets.slope
    count = len(k)
    a, b, ga, gb = _ends_and_gaps(speeds, brackets)
    x = _cubic_start(speeds, brackets, a, b, ga, gb)
    every = np.arange(count)
    lam = _cubic_value(speeds, brackets, every, x)
    phi = shapes[brackets.variant, np.where(x - a <= b - x, k, k + 1), brackets.mode]    # unit: c = phi
    normal_conj = phi.conj()
    line = np.where(b <= 0, -slope, slope)            # |Omega| = sign Omega across the bracket
    done = np.zeros(count, dtype=bool)
    active = every
    constant = (stack.M, stack.C, stack.G, stack.K)
    with np.errstate(all="ignore"):                  # a row whose step is not finite fails below
        for _ in range(_NEWTON_STEPS):
            i = slice(None) if len(active) == count else active
            matrices = tuple(m[0] for m in constant) if len(stack) == 1 else \
                tuple(m[brackets.variant[i]] for m in constant)
            steps = _pencils.speed_newton_step(matrices, x[i], lam[i], phi[i], normal_conj[i], line[i])
            x[i] += steps[0]
            lam[i] += steps[1]
            phi[i] += steps[2]
            size = np.maximum(np.abs(steps[0]) / np.maximum(np.abs(x[i]), 1.0),
                              np.maximum(np.abs(steps[1]) / np.abs(lam[i]), np.abs(steps[2]).max(axis=1)))
            ended = size <= _STEP_TOLERANCE
            inside = (x[i] >= a[i]) & (x[i] <= b[i])
            done[active[ended & inside]] = True
            active = active[~ended & inside & np.isfinite(size)]
            if not len(active):
                break
    done &= np.abs(lam - _interpolated(brackets, every, x)) <= 2 * brackets.spread
    return x, lam, _vectors.unit_rows(phi), done


def _refine_together(stack, speeds, values, weighted, brackets, shapes=None):
    """Roots of ``g(Omega) = Im lam(Omega) - slope |Omega|`` in every bracket, iterated together.

    The first point is the root of the cubic through the sweep's four nearest points of g
    (error of order h^4); then secant steps between the two latest points, kept strictly inside
    the bracket (regula falsi with the Illinois modification where they would leave it, and
    bisection where the bracket stops shrinking). Each step solves the eigenvalues of all
    unfinished crossings in one batch. A crossing is done when its next step is below
    ``1e-13 max(|Omega|, 1)``: the last point evaluated is the root, with its eigenvalue.
    The eigenvalue of a mode isolated from every other root across its bracket comes from
    residual inverse iteration on the quadratic pencil (:func:`_pencil_at`): one factorisation
    per crossing, at its first point, serves every later point. The others (and any that does
    not converge there) are picked from the roots near the bracket's interpolation (all
    eigenvalues of the state matrix, or for large models the nearest by shift-invert Arnoldi)
    as described in :func:`_tracked`, and then followed on the pencil where the next point is
    near enough (:func:`_followed`).

    Returns
    -------
    roots : ndarray (P,) [rad/s]
    lam : ndarray (P,), complex
        The tracked mode's eigenvalue at each root.
    sure : ndarray (P,) bool
        The eigenvalue was told apart by distance alone and is not repeated.
    iterates : _Iterates
        The pencil iteration's last points, eigenvalues and shapes.
    """
    slope = brackets.slope
    count = len(brackets.k)
    a, b, ga, gb = _ends_and_gaps(speeds, brackets)
    x = _cubic_start(speeds, brackets, a, b, ga, gb)
    iterates = _Iterates.start(stack, brackets, shapes)
    previous = np.full((2, count), np.nan)          # the last point evaluated and its g
    state = _Bracket(a, b, ga, gb, np.zeros(count, dtype=int), np.full((2, count), np.inf))
    on_grid = (ga == 0) | (gb == 0)
    if on_grid.any():
        roots = np.where(ga == 0, a, np.where(gb == 0, b, np.nan))
        lam = np.where(ga == 0, brackets.low, brackets.high)
        sure = np.zeros(count, dtype=bool)
        done, evaluations = on_grid, 0
    else:
        # every crossing between grid points (the usual case): the first evaluation of all of them,
        # which usually ends them all (the cubic start lands at round-off of the root)
        every = np.arange(count)
        lam, sure = _evaluate(stack, speeds, values, weighted, brackets, every, x.copy(), iterates, shapes)
        roots, done, evaluations = x.copy(), np.zeros(count, dtype=bool), 1
        x = _advance(state, previous, done, every, x, lam.imag - slope * np.abs(x))
    for _ in range(_MAX_ITERATIONS - evaluations):
        i = (~done).nonzero()[0]
        if not len(i):
            break
        x_i = x[i]
        lam_x, sure_x = _evaluate(stack, speeds, values, weighted, brackets, i, x_i, iterates, shapes)
        gx = lam_x.imag - slope[i] * np.abs(x_i)
        roots[i], lam[i], sure[i] = x_i, lam_x, sure_x
        x[i] = _advance(state, previous, done, i, x_i, gx)
    return roots, lam, sure, iterates


def _ends_and_gaps(speeds, brackets):
    """Each bracket's ends ``a = speeds[k]``, ``b = speeds[k + 1]`` [rad/s] and ``g`` there
    (see :func:`_refine_together`), each (P,)."""
    a, b = speeds[brackets.k], speeds[brackets.k + 1]
    return a, b, brackets.low.imag - brackets.slope * np.abs(a), brackets.high.imag - brackets.slope * np.abs(b)


def _advance(state, previous, done, rows, x, gx):
    """Update the brackets ``rows`` with the points (x, gx) (see :func:`_next_step`), mark those
    that end there done, and return the next points."""
    step = _next_step(state, rows, x, gx, previous[:, rows])
    previous[:, rows] = x, gx
    done[rows[_finished(x, gx, step)]] = True
    return step


def _finished(x, gx, step):
    """A crossing ends where ``g`` vanishes or its next step is below ``_STEP_TOLERANCE``."""
    return (gx == 0) | (np.abs(step - x) <= _STEP_TOLERANCE * np.maximum(np.abs(x), 1.0))


class _Bracket(NamedTuple):
    """Brackets being shrunk (arrays updated in place): ends, their g (Illinois-scaled), the end
    moved last (+1 a, -1 b) and the bracket's width one and two steps ago."""

    a: np.ndarray
    b: np.ndarray
    ga: np.ndarray
    gb: np.ndarray
    last: np.ndarray
    widths: np.ndarray


def _next_step(state, rows, x, gx, previous):
    """Update the brackets ``rows`` with the point (x, gx) and return the next point."""
    moved = gx != 0
    left = (np.sign(gx) == np.sign(state.ga[rows])) & moved
    right = ~left & moved
    if left.any():
        _illinois(state.a, state.ga, state.gb, state.last, rows[left], x[left], gx[left], +1)
    if right.any():
        _illinois(state.b, state.gb, state.ga, state.last, rows[right], x[right], gx[right], -1)
    a, b = state.a[rows], state.b[rows]
    width, gb = b - a, state.gb[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = x - gx * (x - previous[0]) / (gx - previous[1])
        falsi = b - gb * width / (gb - state.ga[rows])
    slow = width > 0.5 * state.widths[1, rows]
    state.widths[1, rows], state.widths[0, rows] = state.widths[0, rows], width
    inside = np.isfinite(secant) & (secant > a) & (secant < b)
    fallback = np.where(np.isfinite(falsi) & (falsi > a) & (falsi < b) & ~slow, falsi, 0.5 * (a + b))
    return np.where(gx == 0, x, np.where(inside, secant, fallback))


def _cubic_start(speeds, brackets, a, b, ga, gb):
    """Root in (a, b) of the cubic through g at the sweep's four points around each bracket
    (the chord's root where fewer than four oscillating points are at hand)."""
    width = b - a
    with np.errstate(all="ignore"):
        chord = b - gb * width / (gb - ga)
        chord = np.where(np.isfinite(chord) & (chord > a) & (chord < b), chord, 0.5 * (a + b))
        if len(speeds) < 4:
            return chord
        xs, lam = brackets.near_speeds, brackets.near_values
        gs = lam.imag - brackets.slope[:, None] * np.abs(xs)
        # the four speeds ascend: all on one side of zero where the first or the last is
        usable = brackets.near_oscillating & ((xs[:, 0] >= 0) | (xs[:, 3] <= 0))
        # the cubic in t = (x - a) / (b - a): coefficients from the 4x4 Vandermonde systems
        t_nodes = (xs - a[:, None]) / width[:, None]
        vandermonde = t_nodes[..., None] ** np.arange(4)
        coefficients = np.linalg.solve(vandermonde, gs[..., None])[..., 0]
        t = (chord - a) / width
        c0, c1, c2, c3 = coefficients.T
        slope3, slope2 = 3 * c3, 2 * c2                 # the derivative's coefficients
        for _ in range(4):                              # Newton on the cubic, from the chord's root
            t = t - (((c3 * t + c2) * t + c1) * t + c0) / ((slope3 * t + slope2) * t + c1)
        x = a + t * width
        good = usable & np.isfinite(x) & (x > a) & (x < b)
    return np.where(good, x, chord)


def _illinois(end, g_end, g_other, last_side, rows, x, gx, side):
    """Move one end of the brackets ``rows`` to ``x``; halve the other end's value when this
    end moved last time too (Illinois), so the other end moves next."""
    repeat = last_side[rows] == side
    g_other[rows[repeat]] *= 0.5
    end[rows] = x
    g_end[rows] = gx
    last_side[rows] = side


class _Iterates(NamedTuple):
    """Per crossing: whether its mode is isolated (see :func:`_isolated`) and may be evaluated
    on the pencil, the last point, eigenvalue and shape found (by the pencil, or by picking
    from the roots), the distance from that eigenvalue to the nearest other root where it was
    picked, and the factorisation of the pencil (at a point near the root) that the iteration
    reuses (updated in place)."""

    usable: np.ndarray
    x: np.ndarray
    lam: np.ndarray
    shape: np.ndarray
    gap: np.ndarray
    factors: _pencils.PencilFactors

    @classmethod
    def start(cls, stack, brackets, shapes):
        count = len(brackets.k)
        gap = np.full(count, np.nan)
        if shapes is None or stack.branch_times.shape[-1]:
            # Maxwell branches make the pencil rational: every evaluation takes all eigenvalues
            return cls(np.zeros(count, dtype=bool), np.full(count, np.nan), np.zeros(count, complex),
                       np.zeros((count, 0), complex), gap, _pencils.PencilFactors(0, 0))
        v, k, mode = brackets.variant, brackets.k, brackets.mode
        return cls(brackets.isolated, brackets.start.astype(float), brackets.low.copy(),
                   shapes[v, k, mode], gap, _pencils.PencilFactors(count, stack.n_dof))


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


def _evaluate(stack, speeds, values, weighted, brackets, rows, x, iterates, shapes=None):
    """The tracked modes' eigenvalues at speeds ``x`` and whether each is sure (see
    :func:`_tracked`): the pencil's iteration for isolated modes and for modes picked from the
    roots at a point so near that no other root can have come close (:func:`_followed`); for
    large models, the mode picked among the Ritz pairs of the sweep's shapes at the bracket's
    ends (:func:`_ritz_evaluated`, from ``shapes``) and refined on the pencil; the roots near
    the bracket's interpolation for the rest and for any that did not converge to the tracked
    mode."""
    fast = iterates.usable[rows]
    isolated = fast.all()
    if isolated:                         # every mode isolated (the usual case): all on the pencil
        found, ok = _pencil_at(stack, speeds, brackets, rows, x, iterates)
        if ok.all():
            return found, ok
    else:
        fast |= _followed(brackets, rows, x, iterates)
    lam = np.empty(len(rows), dtype=complex)
    sure = np.zeros(len(rows), dtype=bool)
    if isolated:
        lam[ok], sure[ok] = found[ok], True
        fast[~ok] = False
    elif fast.any():
        f = fast.nonzero()[0]
        found, ok = _pencil_at(stack, speeds, brackets, rows[f], x[f], iterates)
        lam[f[ok]], sure[f[ok]] = found[ok], True
        fast[f[~ok]] = False
    slow = (~fast).nonzero()[0]
    if len(slow) and _by_ritz(stack, shapes, iterates):
        found, ok = _ritz_evaluated(stack, speeds, values, shapes, weighted, brackets, rows[slow], x[slow], iterates)
        lam[slow[ok]], sure[slow[ok]] = found[ok], True
        slow = slow[~ok]
    if len(slow):
        lam[slow], sure[slow], shapes, known, gap = _tracked(stack, speeds, values, weighted, brackets, rows[slow],
                                                             x[slow])
        if iterates.shape.shape[-1]:
            # a mode told apart by distance among roots that came without shapes: its shape by one
            # inverse-iteration step, so that later points follow it on the pencil (_followed)
            # instead of taking every root again
            bare = (~known & sure[slow]).nonzero()[0]
            if len(bare):
                at = slow[bare]
                shapes[bare] = stack.shapes_at(brackets.variant[rows[at]], x[at], lam[at])
                known[bare] = True
            # kept for the shape at the root, should this point be it, and to follow the mode
            mine, at = rows[slow[known]], slow[known]
            iterates.x[mine], iterates.lam[mine], iterates.shape[mine] = x[at], lam[at], shapes[known]
            iterates.gap[mine] = gap[known]
    return lam, sure


#: roots at each end of a bracket whose shapes span the subspace that a crossing among close
#: roots first picks its mode from (:func:`_ritz_picked`)
_RITZ_ROOTS = 8


def _by_ritz(stack, shapes, iterates) -> bool:
    """Whether crossings among close roots are first picked from Ritz pairs (:func:`_ritz_picked`):
    one model of constant coefficients, large enough that the roots near a point come from
    shift-invert Arnoldi (see :func:`_roots_near`), with the sweep's shapes at hand (never where
    ``_RITZ_ROOTS`` is 0)."""
    return (_RITZ_ROOTS > 0 and shapes is not None and iterates.shape.shape[-1] > 0 and len(stack) == 1
            and not stack.dependent
            and not stack.branch_times.shape[-1] and stack.n_dof > max(_pencils.NEAREST_ROOTS_DOF, _NEAREST_ROOTS))


def _ritz_evaluated(stack, speeds, values, shapes, weighted, brackets, rows, x, iterates):
    """The tracked modes' eigenvalues at ``x`` for crossings among close roots, without the
    roots near each point (one shift-invert Arnoldi call per crossing): the mode picked among
    the Ritz pairs of the sweep's shapes at the bracket's ends (:func:`_ritz_picked`, all rows
    in a few batched calls), then refined on the pencil from that pair (:func:`_pencil_at`: one
    factorisation per crossing, reused by its later points, which follow it there).

    A row counts only where the pencil's eigenpair converged within a quarter of the distance
    from its Ritz value to the nearest other one (and to its own conjugate), with a shape
    whose MAC with the Ritz vector is at least ``_RITZ_MAC``; the others are left to
    :func:`_tracked` as before, with their iterates as they were.

    Returns
    -------
    lam : ndarray (P,), complex
    ok : ndarray (P,) bool
    """
    lam = np.full(len(rows), np.nan, dtype=complex)
    ok = np.zeros(len(rows), dtype=bool)
    size = 2 * min(_RITZ_ROOTS, values.shape[-1])
    for part in _batches.chunk_slices(len(rows), 64 * size * stack.n_dof, budget=_RITZ_BYTES):
        picked, vectors, gap, good = _ritz_picked(stack, values, shapes, weighted, brackets, rows[part], x[part])
        at = np.arange(part.start, part.stop)[good]
        if not len(at):
            continue
        mine = rows[at]
        saved = (iterates.x[mine], iterates.lam[mine], iterates.shape[mine], iterates.gap[mine],
                 iterates.factors.ready[mine])
        iterates.x[mine], iterates.lam[mine], iterates.shape[mine], iterates.gap[mine] = \
            x[at], picked[good], vectors[good], gap[good]
        found, converged = _pencil_at(stack, speeds, brackets, mine, x[at], iterates)
        mac = np.abs(np.einsum("pi,pi->p", vectors[good].conj(), iterates.shape[mine])) ** 2
        converged &= mac >= _RITZ_MAC
        lost = (~converged).nonzero()[0]
        if len(lost):                                   # as they were, for _tracked
            for column, value in zip((iterates.x, iterates.lam, iterates.shape, iterates.gap, iterates.factors.ready),
                                     saved):
                column[mine[lost]] = value[lost]
        lam[at], ok[at] = found, converged
    return lam, ok


#: the least MAC of a Ritz vector with the pencil's eigenvector refined from it
_RITZ_MAC = 0.9
#: the largest part of the Ritz subspaces built at once [bytes]
_RITZ_BYTES = 64 * 2**20


def _ritz_picked(stack, values, shapes, weighted, brackets, rows, x):
    """The tracked mode at ``x`` among the Ritz pairs (:func:`_pencils.projected_roots`) of the
    pencil in the span of the sweep's shapes of the ``_RITZ_ROOTS`` roots nearest the bracket's
    interpolation at each end of the bracket, picked as :func:`_identified` picks among roots:
    by the mass-weighted MAC with its shape at the bracket's start and the distance from the
    interpolation.

    Every root at ``x`` nearer the interpolation than ``radius`` (the nearest root left out at
    either end, less the fastest travel of any root across the bracket) was among those roots
    at both ends; a pick is kept where its cost is within ``radius / spread`` (as
    :func:`_identified` asks of the roots at hand), finite, and apart from every other Ritz
    value (and its own conjugate) by more than a repeated root.

    Returns
    -------
    picked : ndarray (P,), complex
        The Ritz value.
    vectors : ndarray (P, n), complex, unit norm
        Its Ritz vector.
    gap : ndarray (P,)
        Its distance to the nearest other Ritz value of the upper half-plane or its conjugate.
    kept : ndarray (P,) bool
    """
    count = min(_RITZ_ROOTS, values.shape[-1])
    every = np.arange(len(rows))
    v, k, mode = brackets.variant[rows], brackets.k[rows], brackets.mode[rows]
    expected = _interpolated(brackets, rows, x)
    spread = brackets.spread[rows]
    ends = k[:, None] + np.arange(2)                                                   # (P, 2)
    roots = values[v[:, None], ends]                                                   # (P, 2, m)
    distance = np.abs(roots - expected[:, None, None])
    distance[np.isnan(distance)] = np.inf
    nearest = np.argsort(distance, axis=-1)
    radius = np.full(len(rows), np.inf)
    if count < values.shape[-1]:
        beyond = np.take_along_axis(distance, nearest[..., count:count + 1], axis=-1)[..., 0]
        radius = beyond.min(axis=1) - brackets.travel[rows]
    vectors = shapes[v[:, None, None], ends[:, :, None], nearest[..., :count]]        # (P, 2, c, n)
    basis = np.linalg.qr(vectors.reshape(len(rows), 2 * count, -1).swapaxes(1, 2))[0]  # (P, n, 2c)
    theta, coefficients, mass = _pencils.projected_roots(basis, _basis_products(stack, basis), x)
    theta = np.where(theta.imag > 0, theta, np.nan)                                     # upper roots only
    # mass-weighted correlation with the reference: psi^H L^T W y, with M = L L^T
    left = stack.unweighted(weighted[v, k, mode].conj())                                # (P, n)
    along = np.einsum("pr,prj->pj", np.einsum("pn,pnr->pr", left, basis), coefficients)
    norms = np.einsum("prj,prs,psj->pj", coefficients.conj(), mass, coefficients).real
    with np.errstate(all="ignore"):
        cost = (1 - np.abs(along) ** 2 / norms) + np.abs(theta - expected[:, None]) / spread[:, None]
    cost[~np.isfinite(cost)] = np.inf
    j = np.argmin(cost, axis=1)
    picked, best = theta[every, j], cost[every, j]
    apart = np.abs(theta - picked[:, None])
    apart[every, j] = np.inf
    apart[np.isnan(apart)] = np.inf
    gap = np.minimum(apart.min(axis=1), 2 * np.abs(picked.imag))
    scale = np.nanmax(np.abs(roots[:, 0]), axis=1)
    kept = np.isfinite(best) & (best <= radius / spread) & (gap > _eigensolve.REPEATED_TOLERANCE * scale)
    vectors = _vectors.unit_rows(np.einsum("pnr,pr->pn", basis, coefficients[every, :, j]))
    return picked, vectors, gap, kept


def _basis_products(stack, basis):
    """``M W, C W, G W, K W`` of one model's constant matrices and bases ``W`` (P, n, r): sparse
    products where the model's pencils are sparse (:meth:`~._stack.Stack.sparse_entries`)."""
    count, n, r = basis.shape
    sparse = stack.sparse_matrices()
    if sparse is None:
        flat = basis.swapaxes(1, 2)                                                     # (P, r, n)
        return tuple(_vectors.real_product(flat, matrix[0].T).swapaxes(1, 2) for matrix in
                     (stack.M, stack.C, stack.G, stack.K))
    columns = basis.transpose(1, 0, 2).reshape(n, count * r)
    return tuple((matrix @ columns).reshape(n, count, r).transpose(1, 0, 2) for matrix in sparse)


def _followed(brackets, rows, x, iterates):
    """Crossings whose mode was picked from the roots at a point so near ``x`` that no root
    can have moved a tenth of the distance to its nearest neighbour there (at four times the
    fastest travel across the bracket of any root of the sweep): the pencil's iteration from
    that eigenpair then finds the same mode."""
    moved = 4 * brackets.travel[rows] * np.abs(x - iterates.x[rows]) / brackets.width[rows]
    with np.errstate(invalid="ignore"):
        return ~iterates.usable[rows] & (moved < 0.1 * iterates.gap[rows])


def _pencil_at(stack, speeds, brackets, rows, x, iterates):
    """Eigenvalues of isolated or followed modes (:func:`_followed`) at ``x`` by residual inverse
    iteration on the pencil (:func:`_pencils.residual_inverse_iteration`), started from the last
    point's eigenvalue (moved by the interpolation's change) and shape. A crossing's first
    evaluation factors its pencil at the cubic interpolation of the sweep's eigenvalues there;
    later ones reuse that factorisation, and factor anew only where the iteration did not
    converge. Returns the eigenvalues and which converged to the tracked mode."""
    pencils = Pencils(stack, brackets.variant[rows], x)
    unready = ~iterates.factors.ready[rows]
    if unready.all() and (iterates.x[rows] == brackets.start[rows]).all():
        # every crossing's first evaluation (the usual case): all start from the cubic, factored there
        expected = _interpolated(brackets, rows, x)
        start = _cubic_value(speeds, brackets, rows, x, expected)
        matrices = iterates.factors.factor(rows, pencils, start)
        again = ()
    else:
        matrices = None
        # the interpolation here and at the last point, together
        expected, before = _interpolated(brackets, rows, np.array((x, iterates.x[rows])))
        start = iterates.lam[rows] + expected - before
        fresh = unready.nonzero()[0]
        if len(fresh):
            untouched = fresh[iterates.x[rows[fresh]] == brackets.start[rows[fresh]]]    # nothing evaluated yet
            if len(untouched):
                start[untouched] = _cubic_value(speeds, brackets, rows[untouched], x[untouched])
        if iterates.factors.whole:
            # small pencils anew at this speed's start: the last point's are at its converged
            # eigenvalue, singular to round-off, and a residual step through them barely contracts
            # (a step of 4e-10 left an error of 1e-8 in the shape)
            matrices = iterates.factors.factor(rows, pencils, start)
            again = ()
        else:
            if len(fresh):
                iterates.factors.factor(rows[fresh], _pencils.PencilRows(pencils, fresh), start[fresh])
            again = None
    lam, shapes, converged = _pencils.residual_inverse_iteration(iterates.factors, rows, pencils, start,
                                                               iterates.shape[rows], matrices=matrices)
    if again is None:
        again = (~converged & np.isfinite(lam) & ~unready).nonzero()[0]
    if len(again):
        # far from the factored point (or a poor start there): factor here and iterate again
        part = _pencils.PencilRows(pencils, again)
        iterates.factors.factor(rows[again], part, lam[again])
        lam[again], shapes[again], converged[again] = _pencils.residual_inverse_iteration(
            iterates.factors, rows[again], part, lam[again], shapes[again])
    ok = converged & (np.abs(lam - expected) <= 2 * brackets.spread[rows])
    followed = ~iterates.usable[rows]
    if followed.any():
        with np.errstate(invalid="ignore"):
            ok[followed] &= np.abs(lam - start)[followed] < 0.25 * iterates.gap[rows[followed]]
    if ok.all():
        iterates.x[rows], iterates.lam[rows], iterates.shape[rows] = x, lam, shapes
    else:
        iterates.x[rows[ok]], iterates.lam[rows[ok]], iterates.shape[rows[ok]] = x[ok], lam[ok], shapes[ok]
    return lam, ok


def _cubic_value(speeds, brackets, rows, x, linear=None):
    """The tracked modes' eigenvalues at ``x`` by the cubic through the sweep's four nearest
    points (linear across the bracket where fewer than four oscillating points are at hand;
    ``linear``, :func:`_interpolated` at ``x``, when the caller has it)."""
    if len(speeds) < 4 or not len(rows):
        return _interpolated(brackets, rows, x) if linear is None else linear
    xs, lam = brackets.near_speeds[rows], brackets.near_values[rows]
    # Lagrange weights: factor[p, j, m] = (x - xs_m) / (xs_j - xs_m), 1 where m = j (exact, so the
    # products below equal the ones over m != j in the same order)
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = (x[:, None, None] - xs[:, None, :]) / (xs[:, :, None] - xs[:, None, :])
    factor.reshape(len(x), 16)[:, ::5] = 1.0                        # the diagonals
    weights = factor[..., 0] * factor[..., 1] * factor[..., 2] * factor[..., 3]
    cubic = np.einsum("pj,pj->p", weights, lam)
    cubic_here = brackets.near_oscillating[rows]
    if cubic_here.all():
        return cubic
    linear = _interpolated(brackets, rows, x) if linear is None else linear
    return np.where(cubic_here, cubic, linear)


def _interpolated(brackets, rows, x):
    """The tracked modes' eigenvalues interpolated linearly across their brackets at ``x``."""
    t = (x - brackets.start[rows]) / brackets.width[rows]
    return (1 - t) * brackets.low[rows] + t * brackets.high[rows]


def _tracked(stack, speeds, values, weighted, brackets, rows, x):
    """The tracked modes' eigenvalues at speeds ``x``: the nearest to the bracket's
    interpolation, confirmed by the mode shape where another eigenvalue is about as near.

    Returns
    -------
    lam : ndarray (P,), complex
    sure : ndarray (P,) bool
        Told apart by distance alone and single (its shape then follows from one
        inverse-iteration step).
    shapes : ndarray (P, n), complex
        The shape of each eigenvalue where ``known`` (the roots came with their shapes, or the
        mode was identified by its shape).
    known : ndarray (P,) bool
    gap : ndarray (P,)
        Distance from each eigenvalue to the nearest other root (of those at hand) [1/s].
    """
    expected = _interpolated(brackets, rows, x)
    lam, phi, radius = _candidates(stack, values, brackets.variant[rows], x, expected)
    distance = np.abs(lam - expected[:, None])
    nearest, second = np.argsort(distance, axis=1)[:, :2].T
    every = np.arange(len(x))
    picked = lam[every, nearest]
    shapes = np.zeros((len(x), stack.n_dof), dtype=complex)
    known = np.zeros(len(x), dtype=bool)
    if phi is not None:
        shapes, known = phi[every, nearest], np.ones(len(x), dtype=bool)
    unsure = distance[every, second] <= 4 * distance[every, nearest] + 2 * brackets.spread[rows]
    if unsure.any():
        mine = brackets.subset(rows[unsure])
        if phi is None:
            picked[unsure], shapes[unsure] = _modes_at(stack, speeds, values, weighted, mine, x[unsure])
        else:
            picked[unsure], shapes[unsure] = _identified(stack, speeds, values, weighted, mine, x[unsure],
                                                         lam[unsure], phi[unsure], radius[unsure])
        known |= unsure
    scale = np.nanmax(np.abs(lam), axis=1)
    if lam.shape[1] < values.shape[-1]:       # a few roots only: the largest is the sweep's
        scale = np.maximum(scale, np.abs(values[brackets.variant[rows], brackets.k[rows]]).max(axis=1))
    repeated = np.sort(np.abs(lam - picked[:, None]), axis=1)[:, 1] <= _eigensolve.REPEATED_TOLERANCE * scale
    known &= unsure | ~repeated            # a repeated root's shape is told by the MAC (_modes_at)
    gap = np.sort(np.abs(lam - picked[:, None]), axis=1)[:, 1]
    return picked, ~unsure & ~repeated, shapes, known, gap


#: roots nearest the interpolation that a large model's crossing first picks its mode from
#: (more where a root beyond them could be the mode: see :func:`_identified`)
_NEAREST_ROOTS = 8


def _roots_near(stack, variants, x, centers, shapes=False, count=None):
    """The upper roots at speeds ``x`` to pick the tracked mode from, their unit shapes, and the
    distance from ``centers`` within which every root is among them: for large models (see
    :func:`_pencils.nearest_roots`) the ``count`` nearest ``centers``, (R, count) and (R, count,
    n); else (or where ``count`` reaches the coordinates) all of them, (R, m), with shapes (R, m,
    n) only when ``shapes`` (None otherwise), and an infinite radius. ``count`` defaults to
    ``_NEAREST_ROOTS``."""
    count = _NEAREST_ROOTS if count is None else count
    if stack.n_dof <= max(_pencils.NEAREST_ROOTS_DOF, count) or stack.branch_times.shape[-1]:
        return (*_all_roots(stack, variants, x, shapes), np.full(len(x), np.inf))
    lam, phi, radius = _pencils.nearest_roots(Pencils(stack, variants, x), centers, count)
    failed = np.nonzero(np.all(np.isnan(lam), axis=1))[0]
    if len(failed):                                    # ARPACK did not converge: all roots, the nearest kept
        every, every_phi = _all_roots(stack, variants[failed], x[failed], True)
        distance = np.abs(every - centers[failed, None])
        nearest = np.argsort(distance, axis=1)
        kept = min(lam.shape[1], nearest.shape[1])     # a small model may have fewer roots than asked
        lam[failed, :kept] = np.take_along_axis(every, nearest[:, :kept], axis=1)
        phi[failed, :kept] = np.take_along_axis(every_phi, nearest[:, :kept, None], axis=1)
        radius[failed] = np.inf if kept == nearest.shape[1] else \
            np.take_along_axis(distance, nearest[:, kept:kept + 1], axis=1)[:, 0]
    lam = np.where(lam.imag < 0, np.nan, lam)          # the lower roots are not candidates
    return lam, _eigensolve.resolve_repeated(lam, phi, stack.repeated_forms, variants), radius


def _candidates(stack, values, variants, x, centers, shapes=False, count=None):
    """:func:`_roots_near`; where the sweep's roots ``values`` (V, S, k) are the lowest modes only
    (fewer columns than roots) of a model with Maxwell branches, the lowest modes up to past the
    centers from their rational pencil instead (no state matrix solved whole:
    :func:`._lowest_branches.roots_near`)."""
    if len(stack) == 1 and stack.branch_times.shape[-1] and values.shape[-1] < stack.forms[0].n_states // 2:
        from ._lowest_branches import roots_near

        return roots_near(stack, x, centers, _NEAREST_ROOTS if count is None else count)
    return _roots_near(stack, variants, x, centers, shapes, count)


def _all_roots(stack, variants, x, shapes):
    """All upper roots of the state matrices at ``x`` (R, m), with their unit shapes (R, m, n)
    when ``shapes`` (None otherwise)."""
    size = stack.forms[0].n_states
    if shapes:
        return _batches.concatenated([stack.solve(stack.at(variants[part], x[part]), variants[part])
                                    for part in _batches.chunk_slices(len(x), 80 * size * size)])
    return _batches.concatenated([_eigensolve.select_upper(_eigensolve.eigenvalues_of(stack.at(variants[part], x[part])))
                                for part in _batches.chunk_slices(len(x), 32 * size * size)]), None


def _shapes_at(stack, speeds, values, weighted, brackets, roots, lam, sure, iterates):
    """Eigenvalues and shapes at the roots: the last evaluation's where it was at the root and
    gave one (the pencil iteration's, the nearest roots', an identification's), else one
    inverse-iteration step on the eigenvalue found, or a full identification
    (:func:`_modes_at`) where it was unsure or the eigenvalue is repeated."""
    known = (iterates.x == roots) & (iterates.lam == lam)
    if known.all() and iterates.shape.shape[-1]:
        return lam.copy(), iterates.shape.copy()        # every root the pencil iteration's last point
    lam = lam.copy()
    phi = np.empty((len(roots), stack.n_dof), dtype=complex)
    if known.any():
        phi[known] = iterates.shape[known]
    rest = np.nonzero(~known & sure)[0]
    if len(rest):
        phi[rest] = stack.shapes_at(brackets.variant[rest], roots[rest], lam[rest])
    rows = np.nonzero(~sure & ~known)[0]
    if len(rows):
        lam[rows], phi[rows] = _modes_at(stack, speeds, values, weighted, brackets.subset(rows), roots[rows])
    return lam, phi


def _modes_at(stack, speeds, values, weighted, brackets, x):
    """Eigenvalue and shape of each bracket's tracked mode at ``x`` (see :func:`_identified`)."""
    expected = _interpolated(brackets, np.arange(len(x)), x)
    lam, phi, radius = _candidates(stack, values, brackets.variant, x, expected, True)
    return _identified(stack, speeds, values, weighted, brackets, x, lam, phi, radius)


def _identified(stack, speeds, values, weighted, brackets, x, lam, phi, radius):
    """The tracked mode among roots ``lam`` (P, j) with shapes ``phi`` (P, j, n) at ``x``:
    by the mass-weighted MAC against its shape at the bracket's start and the eigenvalue
    distance. Returns its eigenvalue (P,) and shape (P, n).

    The roots at hand are every root within ``radius`` (P,) of the bracket's interpolation. A
    root beyond costs at least ``radius / spread``; where the best at hand costs more (a
    cluster of many close roots, such as the like rotors of a large machine), that row takes
    four times as many roots nearest the interpolation, until this holds or it has them all."""
    rows = np.arange(len(x))
    expected = _interpolated(brackets, rows, x)
    psi = stack.weighted(phi, brackets.variant)
    reference = weighted[brackets.variant, brackets.k, brackets.mode]                   # (P, n)
    correlation = np.abs(np.einsum("pn,pjn->pj", reference.conj(), psi)) ** 2
    spread = brackets.spread[rows]
    cost = (1 - correlation) + np.abs(lam - expected[:, None]) / spread[:, None]
    j = np.argmin(np.where(np.isnan(cost), np.inf, cost), axis=1)
    picked, shape = lam[rows, j], phi[rows, j]
    short = np.nonzero(~(cost[rows, j] <= radius / spread) & np.isfinite(radius))[0]
    if len(short):
        more = _candidates(stack, values, brackets.variant[short], x[short], expected[short], True, 4 * lam.shape[1])
        picked[short], shape[short] = _identified(stack, speeds, values, weighted, brackets.subset(short), x[short],
                                                  *more)
    return picked, shape
