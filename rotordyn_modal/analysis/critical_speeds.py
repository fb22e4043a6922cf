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

import functools
import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..model._validation import mesh_name
from . import _batches, _vectors, _whirl
from ._critical_progress import _progress_bar, _progress_share, _progress_units
from ._crossing_brackets import _crossing_brackets, _rows_of
from ._crossing_refinement import _FINGERPRINT, _refine_parts
from ._stack import Stack
from .modal import damping_ratios
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


#: relative round-off of a sweep's root, ``|lam|`` times it (as ``stability``'s verdict takes it)
ROUND_OFF_RELATIVE = 1e-10
#: what round-off can move a sweep's whirl ratio by, at most (a shape is known to about the
#: eigen-solve's noise over the gap to the next root): a ratio of -2e-15 on a casing without
#: rotors, or -2.5e-10 on a rotor at rest on anisotropic bearings, is a planar mode's 0
WHIRL_ROUND_OFF = 1e-9


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
    #: whether working out ``mode_at_speed`` shows a bar (the sweep's ``progress``)
    _progress = False

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
        return numbers_at_crossings(model, sweep_speeds, sweep_eigenvalues, self.speeds, self.mode, eigenvalues,
                                    progress=self._progress, whirl_ratios=self.whirl_ratios)

    def to_dataframe(self, numbers: bool = True):
        """Table with the command line's columns (``pandas.DataFrame``): ``source, order, mode,
        speed_rpm, frequency_hz, whirl, whirl_ratio, damping_ratio, mode_at_speed`` (``mode`` the
        tracked label, ``mode_at_speed`` the number ``modal(model, speed)`` gives that mode at
        the row's speed, 0 where it is not a mode there; empty for a table not made by a sweep).

        ``numbers=False`` leaves out ``mode_at_speed``, and the work of it (roots solved at about
        half the critical speeds: most of a large machine's table) where it was not done yet."""
        import pandas as pd

        table = pd.DataFrame({
            "source": self.source, "order": self.order, "mode": self.mode,
            "speed_rpm": self.speeds_rpm, "frequency_hz": self.frequencies_hz,
            "whirl": self.whirl, "whirl_ratio": self.whirl_ratios,
            "damping_ratio": self.damping_ratios,
        })
        if numbers:
            found = self.mode_at_speed
            table["mode_at_speed"] = pd.array([pd.NA] * len(self), dtype="Int64") if found is None else found
        # the terminal prints values within them as 0 (``cli._common.print_table``), as campbell's table:
        # a planar mode's whirl ratio of 6e-38 or an undamped mode's damping ratio of -5e-25 is a 0.
        # Numbers, not arrays: pandas compares the attrs of tables it concatenates
        table.attrs["round_off"] = {"whirl_ratio": WHIRL_ROUND_OFF, "damping_ratio": ROUND_OFF_RELATIVE}
        return table


def _with_sweep(table: CriticalSpeeds, model, speeds, eigenvalues, progress=False) -> CriticalSpeeds:
    """``table`` knowing the sweep it was found on (its ``mode_at_speed``): ``model``, the
    sweep's ``speeds`` (N,) [rad/s] and tracked ``eigenvalues`` (N, m) [1/s]; ``progress``: a bar
    over the mode numbers solved, as over the sweep's other work."""
    object.__setattr__(table, "_sweep", (model, speeds, eigenvalues))     # the table was just made
    object.__setattr__(table, "_progress", bool(progress))
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
                          progress=False, check=None, whirl_noise=None) -> list:
    """Every crossing of every mode with every source's order lines, for every variant,
    refined together. ``shapes`` (V, N, m, n), the sweep's unit shapes, start the cheap
    evaluation of isolated modes (:func:`_Iterates`); ``progress`` shows a bar over the
    crossings; ``check``, when given, is called with the number of crossings before they are
    refined (it may refuse them: see :func:`.campbell.campbell`); ``whirl_noise`` (V, N, m),
    where given, how far round-off moves the sweep's whirl ratios: a crossing's whirl is no
    whirl within the larger of its two neighbouring speeds' (``modes``' rule,
    :func:`._whirl.whirl_codes`). Returns one :class:`CriticalSpeeds` per variant."""
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
    labels = _whirl.whirl_labels(ratios, None if whirl_noise is None else _crossing_noise(whirl_noise, speeds, found))
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


def _crossing_noise(noise, speeds, found) -> np.ndarray:
    """How far round-off moves each crossing's whirl ratio: the larger of the sweep's at the two
    speeds around it (``noise`` (V, N, m); the crossing's own solve is no full eigen-solve)."""
    k = np.clip(np.searchsorted(speeds, found.roots) - 1, 0, max(len(speeds) - 2, 0))
    upper = np.minimum(k + 1, len(speeds) - 1)
    return np.maximum(noise[found.variant, k, found.mode], noise[found.variant, upper, found.mode])


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


#: what a finer sweep's speeds are, in the lowest modes' fallback warning (not the user's sweep)
_SUB_SWEEP_SPEEDS = "speeds of a bracket swept again finer for the critical speeds"


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
        lam, phi, _ = _lowest_branches.lowest_roots(single, speeds, columns, what=_SUB_SWEEP_SPEEDS)
        return lam, phi
    if lowest and single.n_dof >= DENSE_BELOW:
        lam, phi, _ = lowest_roots(single, speeds, columns, what=_SUB_SWEEP_SPEEDS)
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
