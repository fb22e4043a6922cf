"""Campbell diagram: tracked modes over speed, excitation orders, critical speeds.

The sweep (every speed's eigenvalues and shapes in batched LAPACK calls, modes tracked) is
here; the critical speeds' refinement, which the sweep's brackets start, is in
:mod:`.critical_speeds`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from .._limits import memory_problem
from .._progress import phase
from ..errors import InputError
from .. import _arguments
from . import _batches, _eigensolve, _roots, _whirl
from ._stack import Stack
from .critical_speeds import (_SUB_DEPTH, _SUB_SPEEDS, JUMP_TOLERANCE, ROUND_OFF_RELATIVE, WHIRL_ROUND_OFF,
                              CriticalSpeeds, ExcitationSources, _critical_table, _find_critical_speeds,
                              _warn_of_jumps, _with_sweep, excitation_sources, off_order_line)
from .modal import _constant_round_off, is_oscillating, modal_quantities
from .mode_numbers import numbers_at_speed
from ._weighted_rows import WeightedRows
from .tracking import track_modes_many

__all__ = ["CampbellResult", "CriticalSpeeds", "ExcitationSources", "campbell", "campbell_many",
           "critical_speeds", "excitation_sources", "off_order_line", "JUMP_TOLERANCE", "solve_sweep", "solve_sweeps",
           "memory_estimate"]

_CHUNK = 4096


@dataclass(frozen=True)
class CampbellResult:
    """Modes tracked over a speed sweep.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    eigenvalues : ndarray, shape (N, n_modes), complex [1/s]
        Column ``m`` is tracked mode ``m + 1`` at every speed; NaN where that mode lies above
        ``campbell(max_frequency=...)`` or is not among ``campbell(modes=N)``'s lowest N (not a
        mode there: ``oscillatory`` False).
    frequencies_hz, damping_ratios, log_decrements, whirl_ratios : ndarray, shape (N, n_modes)
    whirl : ndarray of str, shape (N, n_modes)
    shapes : ndarray, shape (N, n_modes, n), complex
        Unit-norm mode shapes over the generalized coordinates (the stator's six
        motions at the reference point, then each rotor on bearings).
    modes : ndarray of int, shape (n_modes,)
        Mode labels (1-based): the roots that are modes at the speed nearest zero
        first, by frequency there, then the others (real and overdamped roots).
    sources : ExcitationSources
    critical : CriticalSpeeds
        Crossings with the orders in ``orders``.
    orders : tuple of float
    whirl_round_off : ndarray, shape (N, n_modes), optional
        How far round-off can move each whirl ratio (:func:`._roots.whirl_round_off`, as
        ``modal`` takes it): within it the label is 'none', as in ``modes``' table. None (the
        lowest modes' route, which does not solve for every root) counts as 0.
    """

    speeds: np.ndarray
    eigenvalues: np.ndarray
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    log_decrements: np.ndarray
    whirl_ratios: np.ndarray
    whirl: np.ndarray
    shapes: np.ndarray
    modes: np.ndarray
    sources: ExcitationSources
    critical: CriticalSpeeds
    orders: tuple = field(default=(1.0,))
    whirl_round_off: np.ndarray | None = None

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    @property
    def oscillatory(self) -> np.ndarray:
        """(N, n_modes) bool: the root is a mode at that speed (Im lam > 0, not overdamped;
        see :func:`rotordyn_modal.analysis.modal.is_oscillating`)."""
        return is_oscillating(self.eigenvalues)

    @property
    def critical_jumps(self) -> np.ndarray:
        """(len(critical),) bool: the critical speed is a jump of its tracked mode between close
        roots inside a bracket, not a crossing (its frequency off its order line by more than
        :data:`~rotordyn_modal.analysis.critical_speeds.JUMP_TOLERANCE`; warned of by the
        analysis). The figure draws such a row on its order line, marked as uncertain."""
        if not len(self.critical):
            return np.zeros(0, dtype=bool)
        return off_order_line(self.critical, self.sources) > JUMP_TOLERANCE

    def order_frequencies(self, speeds=None) -> np.ndarray:
        """Excitation frequency of every source's every order: ``order * multiplier * |Omega| / 2 pi``.

        Parameters
        ----------
        speeds : array_like, shape (K,), optional
            Reference speeds [rad/s] (default: the sweep's ``speeds``); negative speeds
            (reversed spin) excite at the frequency of their magnitude.

        Returns
        -------
        ndarray, shape (n_sources, n_orders, K) [Hz]
            Row ``[s, o]`` is the line of source ``sources.names[s]`` (multiplier
            ``sources.multipliers[s]``) and order ``orders[o]``.
        """
        speeds = self.speeds if speeds is None else np.asarray(speeds, dtype=float)
        lines = np.empty((len(self.sources.names), len(self.orders), len(speeds)))
        for s, multiplier in enumerate(self.sources.multipliers):
            for o, order in enumerate(self.orders):
                lines[s, o] = order * multiplier * np.abs(speeds) / (2 * np.pi)
        return lines

    def order_slopes(self, scale: float = 1.0) -> np.ndarray:
        """The slope of each order line of :meth:`order_frequencies` (the line is
        ``slope * |speed|``): ``order * multiplier / (2 pi scale)``.

        Parameters
        ----------
        scale : float
            Units of the speed per rad/s (1: rad/s; ``30 / pi``: rpm).

        Returns
        -------
        ndarray, shape (n_sources, n_orders) [Hz per unit of the speed]
        """
        per_speed = 1 / (2 * np.pi * scale)
        return np.array([[order * multiplier * per_speed for order in self.orders]
                         for multiplier in self.sources.multipliers], dtype=float).reshape(-1, len(self.orders))

    @property
    def order_crossings(self) -> np.ndarray:
        """(n_sources, n_orders) bool: the order line (as :meth:`order_frequencies`) meets some
        mode's curve in the sweep: the difference of the mode's frequency and the line's changes
        sign (or is 0) between neighbouring speeds where the root is a mode (``oscillatory``).
        Where none does, the sweep has no critical speed of that line (the figure says so)."""
        frequencies = np.where(self.oscillatory, self.frequencies_hz, np.nan)
        lines = self.order_frequencies()
        crossings = np.zeros(lines.shape[:2], dtype=bool)
        for s, o in np.ndindex(*crossings.shape):
            gap = frequencies - lines[s, o][:, None]
            with np.errstate(invalid="ignore"):
                crossings[s, o] = np.any(gap[:-1] * gap[1:] <= 0) or np.any(gap == 0)
        return crossings

    @property
    def crosses_orders(self) -> bool:
        """Whether some order line meets some mode's curve in the sweep (any of
        :attr:`order_crossings`)."""
        return bool(self.order_crossings.any())

    @property
    def critical_line_frequencies(self) -> np.ndarray:
        """(len(critical),) [Hz]: the excitation frequency of each critical speed's source and
        order at its speed, ``order * multiplier * |speed| / 2 pi``: its own frequency to round-off
        at a crossing; where the row is a jump (:attr:`critical_jumps`), where the crossing it
        stands for lies (the figure draws it there)."""
        critical = self.critical
        multiplier = dict(zip(self.sources.names, self.sources.multipliers))
        return np.array([order * multiplier[name] for name, order in zip(critical.source, critical.order)],
                        dtype=float) * np.abs(critical.speeds) / (2 * np.pi)

    def mode_curves(self) -> list:
        """Each tracked mode's curve over the sweep with its critical speeds inserted at their
        refined (speed, frequency), so that a curve drawn through its points (straight between
        them) passes through its critical speeds' markers however sparse the sweep.

        A critical speed that is a jump (:attr:`critical_jumps`: its frequency on no curve) or
        that lies at a speed of the sweep is not inserted.

        Returns
        -------
        list of (speeds, frequencies, index), one per mode (column of ``eigenvalues``)
            ``speeds`` ndarray, shape (K_m,) [rad/s], increasing: the sweep's ``speeds`` with
            the mode's critical speeds among them; ``frequencies`` ndarray, shape (K_m,) [Hz]:
            ``frequencies_hz`` where the root is a mode (``oscillatory``), NaN elsewhere, the
            critical speeds' own frequencies at theirs; ``index`` ndarray of int, shape (K_m,):
            the sweep's speed at or before each point (an inserted point lies between
            ``index`` and ``index + 1``).
        """
        frequencies = np.where(self.oscillatory, self.frequencies_hz, np.nan)
        critical, jumps = self.critical, self.critical_jumps
        rows = np.asarray(critical.mode, dtype=int) - 1 if len(critical) else np.zeros(0, int)
        curves = []
        for m in range(frequencies.shape[1]):
            mine = np.flatnonzero((rows == m) & ~jumps)
            at = np.asarray(critical.speeds, dtype=float)[mine]
            mine = mine[~np.isin(at, self.speeds)]
            mine = mine[np.unique(np.asarray(critical.speeds, dtype=float)[mine], return_index=True)[1]]
            curves.append(_with_points(self.speeds, frequencies[:, m], np.asarray(critical.speeds, dtype=float)[mine],
                                       np.asarray(critical.frequencies_hz, dtype=float)[mine]))
        return curves

    def whirl_changes(self) -> list:
        """Where each mode's whirl label changes between two neighbouring speeds of the sweep
        where it is a mode: the speed where its whirl ratio, interpolated linearly between
        them, passes ``-WHIRL_TOLERANCE`` or ``+WHIRL_TOLERANCE`` (a ratio going from -0.03 to
        +0.41 over a step of 100 rpm changes at 6.6 and 7.0 rpm: backward, none, forward).

        The labels at the sweep's speeds are :attr:`whirl` (at rest, relative to the spin axis
        ``+e``: the limit of the whirl at small positive speeds, as the ratio is continuous in
        the speed); between them only the sweep's ratios are known, and the label changes
        where the straight line between them changes it, not over the whole step
        (docs/theory.md section 9). What is interpolated is the ratio about ``+e``, continuous
        through zero speed; the label is relative to the spin, which reverses there: a step
        through zero speed changes the label at zero where the whirl about ``+e`` is not 0.

        Returns
        -------
        list of (speeds, whirl), one per mode (column of ``eigenvalues``)
            ``speeds`` ndarray, shape (K_m,) [rad/s], increasing; ``whirl`` ndarray of str,
            shape (K_m,): the label from that speed on.
        """
        levels = self._whirl_levels()
        codes = _whirl.whirl_codes(self.whirl_ratios, levels)
        sign = np.where(self.speeds < 0, -1.0, 1.0)
        about_axis = self.whirl_ratios * sign[:, None]            # the ratio about +e
        mode = self.oscillatory
        through = (self.speeds[:-1] < 0) & (self.speeds[1:] > 0)    # the steps through zero speed
        changes = []
        for m in range(codes.shape[1]):
            at, after = [], []
            for k in np.flatnonzero(((codes[:-1, m] != codes[1:, m]) | through) & mode[:-1, m] & mode[1:, m]):
                s0, s1, e0, e1 = self.speeds[k], self.speeds[k + 1], about_axis[k, m], about_axis[k + 1, m]
                t0, t1 = levels[k, m], levels[k + 1, m]
                if s0 < 0 < s1:                      # the spin reverses inside the step
                    e_zero = e0 + (0 - s0) / (s1 - s0) * (e1 - e0)
                    t_zero = t0 + (0 - s0) / (s1 - s0) * (t1 - t0)
                    pieces = [(s0, 0.0, -e0, -e_zero, t0, t_zero), (0.0, s1, e_zero, e1, t_zero, t1)]
                else:
                    pieces = [(s0, s1, e0 * sign[k], e1 * sign[k], t0, t1)]
                previous = codes[k, m]
                for start, stop, a, b, level_a, level_b in pieces:
                    first = int(_whirl.whirl_codes(a, level_a))
                    if first != previous:            # at zero speed: the spin's direction flips
                        at.append(start)
                        after.append(str(_whirl._WHIRL_NAMES[first + 1]))
                    for speed, code in _level_crossings(start, stop, a, b, level_a, level_b):
                        at.append(speed)
                        after.append(str(_whirl._WHIRL_NAMES[code + 1]))
                    previous = int(_whirl.whirl_codes(b, level_b))
            changes.append((np.asarray(at, dtype=float), np.asarray(after, dtype=str)))
        return changes

    @property
    def whirl_none_by_round_off(self) -> bool:
        """Some mode has no whirl only because its ratio, larger than ``WHIRL_TOLERANCE``, lies
        within its round-off (:attr:`whirl_round_off`; ``modes``' rule)."""
        ratios = np.abs(self.whirl_ratios)
        return bool(np.any(self.oscillatory & (ratios > _whirl.WHIRL_TOLERANCE) & (ratios <= self._whirl_levels())))

    def _whirl_levels(self) -> np.ndarray:
        """(N, n_modes): the size a whirl ratio must exceed to be a whirl, ``WHIRL_TOLERANCE`` or
        its round-off (:attr:`whirl_round_off`) where that is larger (:func:`._whirl.whirl_codes`)."""
        if self.whirl_round_off is None:
            return np.full(self.whirl_ratios.shape, _whirl.WHIRL_TOLERANCE)
        return np.maximum(_whirl.WHIRL_TOLERANCE, self.whirl_round_off)

    @property
    def unstable(self) -> np.ndarray:
        """(N, n_modes) bool: the root is a mode (``oscillatory``) growing in time, its real part
        above :data:`ROUND_OFF_RELATIVE` times its size (an undamped mode's round-off is no
        instability)."""
        lam = self.eigenvalues
        return (lam.real > ROUND_OFF_RELATIVE * np.abs(lam)) \
            & np.isfinite(np.where(self.oscillatory, self.frequencies_hz, np.nan))

    def instability_onsets(self) -> list:
        """Where each mode becomes unstable: between two neighbouring speeds of the sweep where
        it is a mode, stable (:attr:`unstable` False) at the first and unstable at the second,
        the speed and frequency interpolated linearly to the real part's zero.

        Returns
        -------
        list of (speeds, frequencies), one per mode (column of ``eigenvalues``)
            ``speeds`` ndarray, shape (K_m,) [rad/s]; ``frequencies`` ndarray, shape (K_m,) [Hz].
        """
        unstable, real = self.unstable, self.eigenvalues.real
        frequencies = np.where(self.oscillatory, self.frequencies_hz, np.nan)
        onsets = []
        for m in range(unstable.shape[1]):
            f, r = frequencies[:, m], real[:, m]
            k = np.nonzero(~unstable[:-1, m] & unstable[1:, m] & np.isfinite(f[:-1]))[0]
            t = -r[k] / (r[k + 1] - r[k])
            onsets.append((self.speeds[k] + t * (self.speeds[k + 1] - self.speeds[k]), f[k] + t * (f[k + 1] - f[k])))
        return onsets

    def settled(self, quantity: str) -> np.ndarray:
        """The damping ``quantity`` ('log_decrement' or 'damping_ratio'), shape (N, n_modes), 0
        where the real part is within :data:`ROUND_OFF_RELATIVE` of the root's size (an undamped
        mode's round-off, +-2e-15 on the spring-block rotor, neither damped nor unstable)."""
        values = {"log_decrement": self.log_decrements, "damping_ratio": self.damping_ratios}[quantity]
        lam = self.eigenvalues
        return np.where(np.abs(lam.real) <= ROUND_OFF_RELATIVE * np.abs(lam), 0.0, values)

    def _whirl_about_axis(self) -> np.ndarray:
        """(N, n_modes): each whirl ratio about ``+spin_axis`` (the table's is relative to the
        spin, which a negative speed reverses; zero speed counts as +)."""
        return _whirl.about_spin_axis(self.whirl_ratios, self.speeds)

    def to_dataframe(self, oscillatory_only: bool = True):
        """Long table ``speed_rpm, mode, frequency_hz, damping_ratio, log_decrement, whirl, whirl_ratio,
        real_part, mode_at_speed`` (``mode`` the tracked label, ``mode_at_speed`` the number
        ``modes --speed SPEED`` gives that root)."""
        import pandas as pd

        count, n = self.eigenvalues.shape
        keep = self.oscillatory.ravel() if oscillatory_only else np.ones(count * n, bool)
        table = pd.DataFrame({
            "speed_rpm": np.repeat(self.speeds_rpm, n),
            "mode": np.tile(self.modes, count),
            "frequency_hz": self.frequencies_hz.ravel(),
            "damping_ratio": self.damping_ratios.ravel(),
            "log_decrement": self.log_decrements.ravel(),
            "whirl": self.whirl.ravel(),
            "whirl_ratio": self.whirl_ratios.ravel(),
            "real_part": self.eigenvalues.real.ravel(),
            # the number `modes --speed SPEED` gives the root (docs/model-file.md, mode numbers)
            "mode_at_speed": pd.array(numbers_at_speed(self.eigenvalues, self._whirl_about_axis()).ravel(),
                                      dtype="Int64"),
        })
        table.loc[table["mode_at_speed"] == 0, "mode_at_speed"] = pd.NA
        table = table[keep].reset_index(drop=True)
        # one number a column where it is constant (the damping ratio's 1e-10): pandas compares
        # the attrs of tables it concatenates, and arrays of two lengths cannot be compared
        table.attrs["round_off"] = _constant_round_off(self.round_off_rows(oscillatory_only))
        return table

    def round_off_rows(self, oscillatory_only: bool = True) -> dict:
        """What round-off can move the damping columns and the whirl ratio of :meth:`to_dataframe`
        by, row by row (:func:`_round_off_columns`).

        Returns
        -------
        dict of str -> ndarray, shape (rows of ``to_dataframe(oscillatory_only)``,)
            ``real_part`` [1/s], ``damping_ratio``, ``log_decrement``, ``whirl_ratio`` [-]. The
            terminal prints values within it as 0 (``cli._common.print_table``); the table's
            ``attrs['round_off']`` keeps only the columns where it is one number for every row.
        """
        keep = self.oscillatory.ravel() if oscillatory_only else np.ones(self.eigenvalues.size, bool)
        return _round_off_columns(
            self.eigenvalues.ravel()[keep], None if self.whirl_round_off is None else self.whirl_round_off.ravel()[keep])

    def plot(self, **kwargs):
        """Campbell diagram; see :func:`rotordyn_modal.plotting.plot_campbell`."""
        from ..plotting import plot_campbell

        return plot_campbell(self, **kwargs)


def _level_crossings(s0, s1, a, b, level_a=_whirl.WHIRL_TOLERANCE, level_b=_whirl.WHIRL_TOLERANCE) -> list:
    """Where the ratio going linearly from ``a`` at speed ``s0`` to ``b`` at ``s1`` changes its
    whirl code: where it passes minus or plus the level, itself linear from ``level_a`` to
    ``level_b`` (``WHIRL_TOLERANCE`` or the ratio's round-off, :func:`._whirl.whirl_codes`):
    [(speed, code after), ...] in order of speed. The codes at the ends are those of ``a`` and
    ``b`` at their own levels; each of ``ratio - level`` and ``ratio + level`` is linear, so it
    changes sign once at most and the codes run monotonically from the one to the other."""
    start, stop = int(_whirl.whirl_codes(a, level_a)), int(_whirl.whirl_codes(b, level_b))
    step = 1 if stop > start else -1
    out = []
    for code in range(start, stop, step):
        # the boundary between codes c and c + step: -level between -1 and 0, +level between 0 and 1
        side = -1.0 if min(code, code + step) == -1 else 1.0
        # a + (b - a) x = side (level_a + (level_b - level_a) x)
        out.append((s0 + (side * level_a - a) / ((b - a) - side * (level_b - level_a)) * (s1 - s0), code + step))
    return out


def _with_points(speeds, frequencies, at, values):
    """A curve (``speeds``, ``frequencies``, shape (N,), ``speeds`` increasing) with the points
    (``at``, ``values``), shape (C,), inserted in order of speed; returns ``(speeds, frequencies,
    index)`` (shape (N + C,)), ``index`` the sweep's speed at or before each point."""
    index = np.arange(len(speeds))
    if not len(at):
        return speeds, frequencies, index
    where = np.searchsorted(speeds, at)
    return (np.insert(speeds, where, at), np.insert(frequencies, where, values),
            np.insert(index, where, np.maximum(where - 1, 0)))




def _round_off_columns(eigenvalues, whirl_round_off=None) -> dict:
    """What round-off can move each damping column of the roots ``eigenvalues`` (shape (m,))
    by, row by row: ``ROUND_OFF_RELATIVE |lam|`` on the real part, and the whirl ratio by
    :data:`WHIRL_ROUND_OFF` or its own round-off ``whirl_round_off`` (m,) where that is larger
    (the level its whirl label uses, :attr:`CampbellResult.whirl_round_off`: a ratio labelled
    ``none`` for being within it prints 0). The terminal prints those
    within it as 0 (``cli._common.print_table``): a damping ratio of -3.9e-15 on an undamped
    axial mode must not read as unstable; the CSV keeps every digit."""
    lam = np.asarray(eigenvalues, dtype=complex)
    tolerance = ROUND_OFF_RELATIVE * np.abs(lam)
    with np.errstate(divide="ignore", invalid="ignore"):
        return {"real_part": tolerance, "damping_ratio": np.full(len(lam), ROUND_OFF_RELATIVE),
                "log_decrement": 2 * np.pi * tolerance / lam.imag,
                "whirl_ratio": np.full(len(lam), WHIRL_ROUND_OFF) if whirl_round_off is None
                else np.maximum(WHIRL_ROUND_OFF, whirl_round_off)}


# ----------------------------------------------------------------------------------------
def solve_sweep(model, speeds, progress=False, whirl_noise=False):
    """Eigenvalues and unit mass-weighted shapes at every speed, tracked.

    Parameters
    ----------
    model : Model
    speeds : ndarray, shape (N,) [rad/s]
    progress : bool
        Show a progress bar.
    whirl_noise : bool
        Also return how far round-off can move each shape's whirl ratio (as ``modal`` takes it).

    Returns
    -------
    eigenvalues : ndarray, shape (N, m), complex, tracked columns
    shapes : ndarray, shape (N, m, n), complex, unit norm
    weighted : array-like, shape (N, m, n), complex, unit mass-weighted
        Read like an array, computed a part at a time where read (:class:`._weighted_rows.WeightedRows`).
    noise : ndarray, shape (N, m), with ``whirl_noise`` only
    """
    values, shapes, weighted, *noise = solve_sweeps(Stack([model]), speeds, progress, whirl_noise)
    return (values[0], shapes[0], weighted.variant(0)) + tuple(part[0] for part in noise)


def solve_sweeps(stack, speeds, progress=False, whirl_noise=False):
    """:func:`solve_sweep` for every model of a :class:`~._stack.Stack` at once.

    ``whirl_noise``: also return how far round-off can move each shape's whirl ratio, tracked
    as the roots are (:func:`._eigensolve.ratio_round_off`, as ``modal`` takes it).

    Returns
    -------
    eigenvalues : ndarray, shape (V, N, m); shapes : ndarray, shape (V, N, m, n);
    weighted : WeightedRows, read like an array (V, N, m, n) of the mass-weighted shapes, computed
    a part at a time where read (one copy of the shapes held, not two); with ``whirl_noise`` also
    noise : ndarray, shape (V, N, m)
    """
    speeds = np.asarray(speeds, dtype=float)
    count = len(stack)
    size = stack.forms[0].n_states
    # speeds per chunk: the chunk's state matrices and eigenvectors within about CHUNK_BYTES
    largest = _CHUNK
    if progress and len(speeds) * count * 72 * size * size > _PROGRESS_BYTES:
        largest = min(_CHUNK, -(-len(speeds) // _PROGRESS_STEPS))     # the bar moves (the same numbers)
    chunks = _batches.chunk_slices(len(speeds), count * 72 * size * size, largest=largest)
    values = shapes = noise = None
    for part in _progress(chunks, progress, "eigen-solve"):
        lam, phi, part_noise = _solved_at(stack, speeds[part], whirl_noise)
        if len(chunks) == 1:
            values, shapes, noise = lam, phi, part_noise
        else:                       # each part into its place: no list of parts joined at the end (twice the shapes)
            if values is None:
                values = np.empty((count, len(speeds)) + lam.shape[2:], dtype=lam.dtype)
                shapes = np.empty((count, len(speeds)) + phi.shape[2:], dtype=phi.dtype)
                noise = np.empty(values.shape) if whirl_noise else None
            values[:, part], shapes[:, part] = lam, phi
            if whirl_noise:
                noise[:, part] = part_noise
        del lam, phi, part_noise
    # read by part where tracking and the critical speeds compare shapes (the rows of
    # Stack.weighted of the whole, bit for bit): not a second copy of every shape
    weighted = WeightedRows(stack, shapes)
    with phase(progress, "tracking modes"):         # a large model's tracking: tens of seconds
        order = _tracked(stack, speeds, values, shapes, weighted)
        extra = (noise,) if whirl_noise else ()
        if (order == np.arange(order.shape[-1])).all():     # every root keeps its place: nothing to reorder
            return (values, shapes, weighted) + extra
        variants, rows = np.arange(count)[:, None, None], np.arange(len(speeds))[None, :, None]
        extra = (noise[variants, rows, order],) if whirl_noise else ()
        shapes = _reordered(shapes, order)
        return (values[variants, rows, order], shapes, weighted.reordered(order, shapes)) + extra


def _solved_at(stack, speeds, whirl_noise=False):
    """Every variant's eigen-solution at ``speeds`` (S,) [rad/s] in one batch: eigenvalues
    (V, S, m), shapes (V, S, m, n) and (with ``whirl_noise``, else None) the whirl ratios'
    round-off (V, S, m)."""
    count = len(stack)
    matrices = stack.sweep(speeds)
    solved = stack.solve(matrices.reshape((-1,) + matrices.shape[-2:]), _variant_rows(count, len(speeds)), whirl_noise)
    del matrices
    lam = solved[0].reshape(count, len(speeds), -1)
    phi = solved[1].reshape((count, len(speeds)) + solved[1].shape[-2:])
    return lam, phi, solved[2].reshape(lam.shape) if whirl_noise else None


#: a sweep whose tracking doubts a step (:func:`.tracking.doubtful_steps`) is tracked again with
#: a speed put in the middle of each such step, at most this many rounds (each halving them) ...
_FINER_ROUNDS = 3
#: ... where its state matrices have at most this many states (a dense solution of milliseconds)
_FINER_STATES = 400
#: ... and at most max(_FINER_LEAST, N // 2) speeds added to a sweep of N speeds
_FINER_LEAST = 8


def _tracked(stack, speeds, values, shapes, weighted):
    """The tracking of a sweep (:func:`.tracking.track_modes_many`, numbered by
    :func:`_relabel_by_frequency`): ``order`` (V, N, m).

    Where a step of a small model's sweep leaves a mode's match in doubt (a grid too coarse for
    the modes' changes, :func:`.tracking.doubtful_steps`), the modes are tracked again over the
    sweep with speeds put inside those steps (:func:`_tracked_finer`), and the order at the
    sweep's own speeds is taken from it: the mode numbers a 5-speed grid gives are those of a
    fine one (``stability journal_rotor.toml --speeds 100:20000:5`` said "mode 4 loses
    stability", every finer grid "mode 2"). Where no step is in doubt, the tracking is the
    sweep's own, bit for bit."""
    from .tracking import doubtful_steps

    order = _relabel_by_frequency(track_modes_many(values, weighted), values, speeds, stack, shapes)
    if stack.forms[0].n_states > _FINER_STATES or len(speeds) < 2:
        return order
    doubtful = doubtful_steps(values, weighted, order)
    order = order.copy()
    for v in np.nonzero(doubtful.any(axis=1))[0]:      # each variant of a study on its own added speeds
        alone = stack if len(stack) == 1 else Stack([stack.models[v]])     # as its model alone is tracked
        order[v:v + 1] = _tracked_finer(alone, speeds, values[v:v + 1], shapes[v:v + 1], order[v:v + 1],
                                        doubtful[v:v + 1])
    return order


def _tracked_finer(stack, speeds, values, shapes, order, doubtful):
    """:func:`_tracked` over the sweep with a speed added in the middle of each doubtful step
    (V, N-1) of its tracking ``order`` (V, N, m), then in each step still in doubt,
    :data:`_FINER_ROUNDS` rounds at most and max(:data:`_FINER_LEAST`, N // 2) speeds in all;
    the order (V, N, m) at ``speeds`` (N,)."""
    from .tracking import doubtful_steps

    grid, own = np.asarray(speeds, dtype=float), np.ones(len(speeds), dtype=bool)
    budget = max(_FINER_LEAST, len(speeds) // 2)
    for _ in range(_FINER_ROUNDS):
        steps = np.nonzero(doubtful.any(axis=0))[0][:budget]
        budget -= len(steps)
        if not len(steps):
            break
        added = 0.5 * (grid[steps] + grid[steps + 1])
        lam, phi, _ = _solved_at(stack, added)
        at = np.argsort(np.concatenate([grid, added]), kind="stable")
        grid, own = np.concatenate([grid, added])[at], np.concatenate([own, np.zeros(len(added), dtype=bool)])[at]
        values, shapes = np.concatenate([values, lam], axis=1)[:, at], np.concatenate([shapes, phi], axis=1)[:, at]
        weighted = WeightedRows(stack, shapes)
        # numbered at the sweep's own speed nearest zero, not at an added one
        order = _relabel_by_frequency(track_modes_many(values, weighted, grid), values, np.where(own, grid, np.inf),
                                      stack, shapes)
        doubtful = doubtful_steps(values, weighted, order)
    return order[:, own]


#: a sweep of more work than this [bytes] shown by a progress bar is solved in at least
#: ``_PROGRESS_STEPS`` parts (each speed's eigen-solution is its own: the parts change no number)
_PROGRESS_BYTES = 64 * 2**20
_PROGRESS_STEPS = 20


#: the largest reordered copy of a part of a sweep's shapes [bytes]
_REORDER_BYTES = 16 * 2**20


def _reordered(shapes, order):
    """``shapes[v, k, order[v, k]]`` (V, N, c) over ``shapes`` (V, N, m, n) itself
    (:func:`._batches.reordered_over`, parts of ``_REORDER_BYTES``)."""
    return _batches.reordered_over(shapes, order, _REORDER_BYTES)


def _variant_rows(count, per):
    """The variant of each row of ``count`` variants' ``per`` rows each, variant after variant
    (``numpy.repeat(numpy.arange(count), per)``)."""
    return np.zeros(per, dtype=int) if count == 1 else np.repeat(np.arange(count), per)


def _relabel_by_frequency(order, values, speeds, stack=None, shapes=None):
    """Number tracked roots at the speed nearest zero: modes first, by ascending frequency,
    then the roots that are not modes there (so the labels are :func:`modal`'s numbers at that
    speed; :mod:`.mode_numbers` gives them at the others).

    ``order`` and ``values`` have a leading variant axis: (V, N, m). With the ``stack`` and
    its ``shapes`` (V, N, m, n), the members of a repeated root there (a symmetric rotor's
    whirl at rest) are numbered as :func:`modal` lists them, by whirl about ``+spin_axis``,
    backward first: a sweep through zero speed reaches them tracked in either order."""
    k0 = int(np.argmin(np.abs(speeds)))
    variants = np.arange(len(order))[:, None]
    at_k0 = values[variants, k0, order[:, k0]]
    whirl = None
    if stack is not None and shapes is not None and _has_ties(at_k0):
        ratios = stack.whirl_ratios(np.asarray(shapes[:, k0]), np.arange(len(order)),
                                    np.full(len(order), speeds[k0]))
        whirl = _whirl.about_spin_axis(ratios[variants, order[:, k0]], speeds[k0])
    labels = _eigensolve.frequency_order(at_k0, ~is_oscillating(at_k0), whirl)
    return order[variants[..., None], np.arange(order.shape[1])[:, None], labels[:, None, :]]


def _has_ties(roots) -> bool:
    """Whether two of ``roots`` (V, m) share a frequency to :data:`._eigensolve.TIE_TOLERANCE`
    of their row's largest root (a repeated root, whose members' order is their whirl's)."""
    ordered = np.sort(roots.imag, axis=-1)
    size = np.abs(roots)
    tie = _eigensolve.TIE_TOLERANCE * np.max(np.where(np.isfinite(size), size, 0.0), axis=-1, keepdims=True,
                                             initial=0.0)
    return bool((np.diff(ordered, axis=-1) <= tie).any())


def _progress(items, enabled, description):
    if not enabled:
        return items
    from .._progress import tqdm

    return tqdm(items, desc=description, unit="chunk", leave=False)


def campbell(model, speeds, orders=(1,), progress=False, critical=True, modes=None,
             max_frequency=None) -> CampbellResult:
    """Campbell diagram: all speeds solved in one batch, modes tracked.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s], increasing; negative reverses the spin.
    orders : sequence of float
        Excitation orders (1X, 2X, ...) whose critical speeds are found and marked.
    progress : bool
        Show progress bars (the eigen-solutions, the critical speeds' refinement).
    critical : bool
        Find the critical speeds (else ``critical`` is an empty table; the orders are still
        drawn).
    modes : int, optional
        Only the ``modes`` lowest-frequency oscillating roots at each speed, each the full
        model's root to round-off (a reduced basis gives starts, Newton's iteration on the full
        pencil refines them; a speed the basis cannot be shown to serve is solved whole, with a
        warning; ``docs/theory.md``, "The lowest modes only"). The result has a column for each
        tracked root, NaN (not a mode: ``oscillatory`` False) at the speeds where that root is not
        among the lowest ``modes`` (a root entering them, as its damping ratio falls below
        ``OVERDAMPED_LIMIT`` or as it passes below the last, starts a column of its own; where
        none does, ``modes`` columns). Default: every root.
    max_frequency : float, optional
        Only the oscillating roots of damped natural frequency ``Im lam / 2 pi`` at most this
        [Hz] at each speed, each the full model's root to round-off (the reduced basis made
        complete for this frequency; ``docs/theory.md``, "The modes below a frequency"); with
        ``modes``, the lowest ``modes`` of them. The result has a column for each tracked mode
        below it at some speed of the sweep, NaN (not a mode: ``oscillatory`` False) at the
        speeds where that mode lies above it; the critical speeds are the crossings at
        frequencies up to it. Default: no limit.

    Returns
    -------
    CampbellResult

    Raises
    ------
    InputError
        Before the sweep, where its arrays would not fit in the memory at hand
        (:func:`memory_estimate`, ``rotordyn_modal._limits.available_memory``); before the
        refinement, where its crossings would not. The message gives the estimate in GiB and
        how to need less.

    Notes
    -----
    Where the tracked mode passes from one root to another inside a bracket (two modes that
    veer, or clusters of like modes, such as many like rotors', on a coarse grid), that bracket
    is swept again, finer, and the crossings of its roots with the order line are found there;
    so is a bracket crowded with crossings among close roots (see ``docs/theory.md``,
    section 10).

    Warns
    -----
    UserWarning
        Where a critical speed is still not a crossing but a jump of the tracked mode between two
        close roots inside its bracket (a jump left after three finer sweeps, 512 times finer
        than the grid): the refinement closes in on the jump, and the frequency there is off the
        order line (see :func:`off_order_line`). A finer speed grid resolves them.
    """
    count = None if modes is None else _arguments_modes(modes)
    limit = None if max_frequency is None else 2 * np.pi * _arguments_frequency(max_frequency)
    if count is None and limit is None:
        return campbell_many([model], speeds, orders, progress, critical)[0]
    speeds, orders = _check_speeds(speeds), _arguments.orders(orders)
    stack = lowest_stack(model)
    if count is not None and count >= stack_root_count(stack):
        count = None                # N at least every root: every root (below max_frequency, if given)
        if limit is None:
            return campbell_many([model], speeds, orders, progress, critical)[0]
    return _campbell_lowest(stack, speeds, orders, critical, count, limit, progress)


def _arguments_modes(modes) -> int:
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or modes < 1:
        raise InputError(f"modes = {modes!r}: expected a whole number of modes >= 1")
    return int(modes)


def root_count(model) -> int:
    """Roots of the model at each speed, one of each conjugate pair (half its states, Maxwell
    branches included): ``campbell(modes=N)`` with N at least this many is every root. From
    the sizes alone (no matrix is built): ``n + 3 n_b`` for ``n`` coordinates and ``n_b``
    Maxwell branches (six states each)."""
    from ..elements.mounts import branch_count

    return model.dofs.n + 3 * branch_count(model)


def stack_root_count(stack) -> int:
    """:func:`root_count` of a one-model :class:`~._stack.Stack`, read from its state form."""
    return stack.forms[0].n_states // 2


def lowest_stack(model) -> Stack:
    """The :class:`~._stack.Stack` of one model for ``campbell(modes=N)`` and
    ``stability(modes=N)``, built with one BLAS thread (its n x n set-up: BLAS's own threads only
    wait for a core on a shared machine), as the lowest modes' work that uses it runs."""
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        return Stack([model])


def _arguments_frequency(value) -> float:
    """``max_frequency``: one finite number > 0 [Hz]."""
    expected = "one finite frequency > 0 [Hz]"
    array = _arguments._numbers(value, "max_frequency", expected)
    if array.ndim != 0 or not (np.isfinite(array) and array > 0):
        raise InputError(f"max_frequency = {_arguments._shown(value)}: expected {expected}")
    return float(array)


def _campbell_lowest(stack, speeds, orders, critical, count, limit=None, progress=False) -> CampbellResult:
    """:func:`campbell` of the ``count`` lowest modes at each speed (see its ``modes``), or of
    those of frequency ``Im lam`` up to ``limit`` [rad/s] (see its ``max_frequency``), of the
    model of a one-model stack (:func:`lowest_stack`), at checked ``speeds`` and ``orders``; a
    progress bar where ``progress`` and the speeds are solved by shift-invert Arnoldi."""
    from . import _lowest, _lowest_branches

    model = stack.models[0]
    # the shapes' products: BLAS's own threads only wait for a core on a shared machine (the
    # batched solves run in threads of their own, from _lowest.POOL_FROM coordinates on)
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES), \
            _batches.calling_thread(stack.n_dof < _lowest.POOL_FROM):
        wanted = None
        if limit is not None:
            if stack.branch_times.shape[1]:
                values, shapes, wanted, whole = _lowest_branches.roots_below(stack, speeds, limit, count)
            else:
                values, shapes, wanted, whole = _lowest.roots_below(stack, speeds, limit, count, progress)
            if not values.shape[-1]:
                return _no_modes(model, speeds, orders, stack.n_dof)
        elif stack.branch_times.shape[1]:          # Maxwell branches: the rational pencil (theory section 17)
            values, shapes, whole = _lowest_branches.lowest_roots(stack, speeds, count)
        else:
            values, shapes, whole = _lowest.lowest_roots(stack, speeds, count, progress)
        values, shapes = values[None], shapes[None]
        every = _variant_rows(1, len(speeds))
        # read by part where tracking and the critical speeds compare shapes: not a second copy of all
        weighted = WeightedRows(stack, shapes, one_thread=True)
    order = _relabel_by_frequency(track_modes_many(values, weighted), values, speeds, stack, shapes)
    rows = np.zeros((1, 1, 1), int), np.arange(len(speeds))[None, :, None]
    values = values[rows + (order,)]
    shapes = _reordered(shapes, order)
    weighted = weighted.reordered(order, shapes)
    # the lowest N alone: where a root enters them, a tracked column would pass to it (issue 27 section 3)
    roots = None if limit is not None else _root_columns(stack, speeds, values[0], weighted, count, progress)
    if wanted is not None:
        wanted = wanted[None][rows + (order,)]
        values, shapes, weighted, wanted = _columns_wanted(values, shapes, weighted, wanted)
        if not values.shape[-1]:
            return _no_modes(model, speeds, orders, stack.n_dof)
    # one product of every shape with the whirl forms: BLAS's own threads would wait for a core too
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        ratios = stack.whirl_ratios(shapes.reshape((-1,) + shapes.shape[-2:]), every, speeds)
    oscillating = is_oscillating(values)
    ratios = np.where(oscillating, ratios.reshape(values.shape), 0.0)
    sources = [excitation_sources(model)]
    critical = bool(critical) and len(orders) > 0 and values.shape[-1] > 0
    if critical:
        tables = _find_critical_speeds(stack, speeds, values, weighted, sources, tuple(orders), shapes,
                                       oscillating if wanted is None else oscillating & _near(wanted), progress,
                                       lambda crossings: _refuse_crossings(stack, len(speeds), crossings,
                                                                           values.shape[-1]))
        if wanted is not None:
            tables = [_table_below(tables[0], limit)]
        if roots is not None:
            tables = [_rows_of_roots(tables[0], speeds, roots, values[0], sources[0])]
        tables = [_crossings_only(tables[0], sources[0], model)]
        _warn_of_jumps(tables[0], sources[0], model)
    else:
        tables = [_critical_table([], [], [], [], [], [], [], [])]
    # its balancing's products: BLAS's own threads would only spin on a shared machine
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        noise = _lowest_whirl_round_off(stack, speeds, values[0], ~np.asarray(whole, dtype=bool))
    if wanted is not None:                     # the roots not asked for are no result
        values = np.where(wanted, values, complex(np.nan, np.nan))
        shapes[~wanted] = 0.0
        ratios = np.where(wanted, ratios, 0.0)
    if noise is not None:
        noise = np.where(oscillating[0] & np.isfinite(values[0]), noise, 0.0)
    if roots is not None:                      # a column per root, NaN where it is not among the lowest
        values, shapes, ratios, noise = _by_root(roots, values, shapes, ratios, noise)
    freq, zeta, log_dec = modal_quantities(values)
    return CampbellResult(
        speeds=speeds, eigenvalues=values[0], frequencies_hz=freq[0], damping_ratios=zeta[0],
        log_decrements=log_dec[0], whirl_ratios=ratios[0], whirl=_whirl.whirl_labels(ratios[0], noise), shapes=shapes[0],
        modes=np.arange(1, values.shape[-1] + 1), sources=sources[0],
        critical=_with_sweep(tables[0], model, speeds, values[0], progress),
        orders=tuple(float(o) for o in orders), whirl_round_off=noise)


#: the largest state matrix [bytes] whose round-off the lowest modes' route takes for its whirl
#: labels (:func:`_lowest_whirl_round_off`): 512 states. Above it the labels keep WHIRL_TOLERANCE
#: alone: the route forms no state matrix, and forming one to balance it cost a 4 m shaft of 404
#: coordinates 0.63 -> 0.82 s CPU at 101 speeds (804 coordinates: 1.40 -> 1.83 s); 212: 0.145 -> 0.146 s
_LOWEST_ROUND_OFF_BYTES = 2**21


def _lowest_whirl_round_off(stack, speeds, values, refined=None):
    """How far round-off can move the whirl ratio of each carried root ``values`` (S, k) of the
    lowest modes' route, as ``modes`` and the full Campbell diagram take it
    (:func:`._roots.whirl_round_off`): the round-off of each speed's state matrix over the gap to
    the nearest other root among the carried ones and their conjugates (a repeated root's partner
    excluded as there). No eigen-solve: the round-off of ``A0 + Omega A1`` comes from one
    balancing (:func:`._roots.affine_round_off`, within 0.87-1.23 of each speed's own on the
    examples); speed-dependent coefficients balance each speed's matrix. The roots not carried
    are not known: a gap to one of them is not seen (the top carried root's may be smaller).
    None (no round-off: ``WHIRL_TOLERANCE`` alone) for a model whose state matrix exceeds
    :data:`_LOWEST_ROUND_OFF_BYTES` or that the route keeps sparse. ``refined`` (S,) bool, where
    given: the speeds whose roots the route's Newton steps give to :data:`._eigensolve.POLISH_LEVEL`
    (or warn of; not those solved whole), each root's round-off there at most that part of itself,
    as the full solve's polished roots take it (:func:`._eigensolve.polished_ratio_round_off`).

    Returns
    -------
    ndarray, shape (S, k), or None
    """
    size = stack.forms[0].n_states
    if 8 * size * size > _LOWEST_ROUND_OFF_BYTES or not values.shape[-1] or stack.sparse_constant is not None:
        return None                     # a large model's route forms no dense matrix (assembly.SPARSE_DOF)
    if stack.dependent:
        noise = _dependent_round_off(stack, speeds)
    else:
        noise = _roots.affine_round_off(stack.A0[0], stack.A1[0], speeds)
    lam = np.where(np.isfinite(values), values, np.inf)        # a root not found is no neighbour
    every = np.concatenate([lam, lam.conj()], axis=-1)
    with np.errstate(invalid="ignore"):
        repeated = _eigensolve.REPEATED_TOLERANCE * np.abs(np.where(np.isfinite(values), values, 0)).max(axis=-1)
        if refined is None or not np.any(refined):
            return _roots.whirl_round_off(lam, every, noise, repeated)
        level = np.broadcast_to(noise[:, None], lam.shape)
        level = np.where(refined[:, None], np.minimum(level, _eigensolve.POLISH_LEVEL * np.abs(lam)), level)
        return _roots.whirl_round_off(lam, every, noise, repeated, level)


#: speeds at which a model with speed-dependent coefficients has its state matrix balanced for the
#: lowest route's whirl round-off (the others interpolated): forming and balancing the matrix at
#: each of 201 speeds cost compressor_example's Campbell diagram 0.61 -> 3.9 s CPU
_ROUND_OFF_SPEEDS = 3


def _dependent_round_off(stack, speeds) -> np.ndarray:
    """:func:`._roots.round_off` (S,) [1/s] of the state matrices of a model with speed-dependent
    coefficients (bearing tables): exact at :data:`_ROUND_OFF_SPEEDS` speeds spread over the
    sweep, linear in speed between them. The round-off only sets the whirl labels' tolerance,
    which a factor of 2 does not move for a ratio away from it, and the coefficients' tables are
    smooth in speed."""
    order = np.argsort(speeds, kind="stable")
    picked = np.unique(order[np.linspace(0, len(speeds) - 1, min(_ROUND_OFF_SPEEDS, len(speeds))).round().astype(int)])
    picked = picked[np.argsort(speeds[picked], kind="stable")]
    exact = _roots.round_off(stack.at(np.zeros(len(picked), int), speeds[picked]))
    return np.interp(speeds, speeds[picked], exact)


def _no_modes(model, speeds, orders, n) -> CampbellResult:
    """The :class:`CampbellResult` of no mode (none below the limit at any speed)."""
    empty = np.zeros((len(speeds), 0))
    return CampbellResult(
        speeds=speeds, eigenvalues=empty.astype(complex), frequencies_hz=empty, damping_ratios=empty,
        log_decrements=empty, whirl_ratios=empty, whirl=empty.astype(object),
        shapes=np.zeros((len(speeds), 0, n), complex), modes=np.zeros(0, int), sources=excitation_sources(model),
        critical=_critical_table([], [], [], [], [], [], [], []), orders=tuple(float(o) for o in orders))


def _columns_wanted(values, shapes, weighted, wanted):
    """The tracked columns (1, N, k) wanted at some speed; the others (roots above the limit at
    every speed: fillers of :func:`._lowest.roots_below`) left out."""
    keep = wanted[0].any(axis=0)
    if keep.all():
        return values, shapes, weighted, wanted
    # the shapes kept written over their first columns (views): no second copy of every speed's
    columns = np.broadcast_to(np.nonzero(keep)[0], shapes.shape[:2] + (int(keep.sum()),))
    shapes = _reordered(shapes, columns)
    return values[..., keep], shapes, weighted.reordered(columns, shapes), wanted[..., keep]


def _near(wanted):
    """(1, N, k) wanted at the speed or at a neighbouring one: a crossing between a speed where its
    mode lies below the limit and one where it lies above is still refined (on the full pencil)."""
    near = wanted.copy()
    near[:, 1:] |= wanted[:, :-1]
    near[:, :-1] |= wanted[:, 1:]
    return near


#: a step of the lowest modes' route where some tracked column's MAC with itself at the next speed
#: is below this may be one where a root enters or leaves the lowest N: it is checked
#: (:func:`_root_columns`); above it each column plainly holds one root (tracking's ``_KEPT_MAC``)
_SAME_ROOT_MAC = 0.99

#: roots more than the lowest N solved at the steps checked (:func:`_root_columns`): the roots that
#: leave the lowest N or enter them from above are among them on both sides of the step
_EXTRA_ROOTS = 2

#: an eigenvalue of the check this close to one of the sweep's (relative) is the same root (both
#: the full model's to round-off)
_SAME_VALUE = 1e-6

#: the largest part of the sweep's weighted shapes read at once for the MAC of each column with
#: itself at the next speed (:func:`_doubtful_steps`) [bytes]
_SAME_ROOT_BYTES = 8 * 2**20


def _root_columns(stack, speeds, values, weighted, count, progress=False):
    """The result column of each tracked root of the lowest modes' route, or None where the
    lowest ``count`` are the same roots all along the sweep.

    The route solves the lowest ``count`` modes of each speed; where a root enters them (a root
    becoming a mode as its damping ratio falls below ``OVERDAMPED_LIMIT``, or one passing below
    the last of them) another leaves, and tracking, which matches ``count`` roots to ``count``,
    hands the leaving root's column to the entering one: its curve jumps between two roots
    (redteam14: 283 Hz to 17.7 Hz). The steps where some column's weighted shape is not plainly
    its own at the next speed (MAC below :data:`_SAME_ROOT_MAC`) are solved again, both speeds,
    for ``count +`` :data:`_EXTRA_ROOTS` roots, which are tracked over the step: a root of the
    sweep whose partner there is none of the sweep's roots enters (or leaves) the lowest
    ``count``. Such a root starts a column of its own; the sweep's own tracking is kept at every
    other step. The check halves a step where its own pairing is unsure (:func:`_check_grids`),
    and a root that left and comes back gets its former column when it is plainly the same mode
    (:func:`_returning`).

    Parameters
    ----------
    stack : Stack
        One model.
    speeds : ndarray, shape (N,) [rad/s]
    values : ndarray, shape (N, count), complex [1/s]
        The tracked roots (column ``j`` is tracked mode ``j + 1``).
    weighted : WeightedRows, shape (1, N, count, n)
        Their weighted shapes.
    count : int
    progress : bool
        A line while the doubtful steps are checked (:func:`_check_grids`).

    Returns
    -------
    ndarray of int, shape (N, count), or None
        ``columns[k, j]``: the result's column of tracked root ``j`` at speed ``k``; columns are
        numbered as the tracked modes are (those that are modes at the speed nearest zero by
        frequency there, then the others by the speed and frequency where they enter).
    """
    steps = _doubtful_steps(values, weighted)
    if not len(steps):
        return None
    links = _links_of_steps(stack, speeds, values, steps, count, progress)
    if not links:
        return None
    columns = np.empty(values.shape, dtype=int)
    columns[0] = np.arange(count)
    label = count
    for k in range(len(speeds) - 1):
        columns[k + 1] = columns[k]
        entering = []
        for j, i in links.get(k, {}).items():      # a step where roots enter: their columns
            if i is None:
                entering.append(j)
            else:
                columns[k + 1, j] = columns[k, i]
        back = _returning(columns[:k + 1], label, entering, k + 1, speeds, values, weighted) if entering else {}
        if len(back) < len(entering):              # a shape changed in the gap: the check follows the root
            back.update(_followed_back(stack, speeds, columns[:k + 1], label, [j for j in entering if j not in back],
                                       k + 1, values, count, progress))
        for j in entering:
            if j in back:
                columns[k + 1, j] = back[j]
            else:
                columns[k + 1, j], label = label, label + 1
    return _numbered(columns, values, speeds, label)


def _returning(columns, total, entering, k, speeds, values, weighted) -> dict:
    """The roots of ``entering`` (tracked columns at speed ``k``) that are a root come back to the
    lowest modes: ``{j: its former result column}``.

    A result column whose root left the lowest modes before speed ``k`` (none of the tracked
    roots at speed ``k - 1`` is in it) is given back to an entering root as tracking would continue
    a mode over an unsure step (:mod:`.tracking`): the entering root's weighted shape has a MAC of at least
    ``_CONFIDENT_MAC`` with the column's last shape, and it lies within ``_KEPT_DISTANCE`` of
    |lambda| of the column's last root or of that root extrapolated (linearly in speed, from its
    last two) to the speed; one column to one root by the optimal assignment of (1 - MAC) plus
    that relative distance. The step's check told the entering roots from those that leave at
    it: a column that leaves there is never given back there.

    Parameters
    ----------
    columns : ndarray of int, shape (k, c)
        Result columns of the tracked roots at speeds 0 .. k - 1.
    total : int
        Result columns so far.
    entering : list of int
        Tracked columns whose root enters at speed ``k``.
    speeds : ndarray, shape (N,) [rad/s]
    values : ndarray, shape (N, c), complex [1/s]
    weighted : WeightedRows, shape (1, N, c, n)

    Returns
    -------
    dict
    """
    from scipy.optimize import linear_sum_assignment

    from .tracking import _CONFIDENT_MAC, _KEPT_DISTANCE

    gone = np.setdiff1d(np.arange(total), columns[-1])
    candidates = []
    for label in gone:                                 # each one's last two speeds where it is found
        rows, slots = np.nonzero((columns == label) & np.isfinite(values[:len(columns)]))
        if len(rows):
            candidates.append((int(label), rows[-2:], slots[-2:]))
    if not candidates:
        return {}
    now = values[k, entering]
    shapes = weighted[0, k, np.asarray(entering)]                                      # (e, n)
    cost = np.full((len(candidates), len(entering)), np.inf)
    for r, (label, rows, slots) in enumerate(candidates):
        last = values[rows[-1], slots[-1]]
        near = np.abs(now - last)
        if len(rows) == 2:
            slope = (last - values[rows[0], slots[0]]) / (speeds[rows[-1]] - speeds[rows[0]])
            near = np.minimum(near, np.abs(now - last - slope * (speeds[k] - speeds[rows[-1]])))
        near = near / abs(last)
        before = weighted[0, int(rows[-1]), int(slots[-1])]
        mac = np.abs(shapes.conj() @ before) ** 2
        cost[r] = np.where((mac >= _CONFIDENT_MAC) & (near <= _KEPT_DISTANCE), 1.0 - mac + near, np.inf)
    finite = np.isfinite(cost)
    if not finite.any():
        return {}
    rows, picked = linear_sum_assignment(np.where(finite, cost, 1e6))
    return {entering[c]: candidates[r][0] for r, c in zip(rows, picked) if finite[r, c]}


def _gone(columns, total, values) -> list:
    """The result columns whose root left the lowest modes before the last speed of ``columns``
    (k, c), each as ``(column, its last two speeds found, its tracked slots there)``."""
    candidates = []
    for label in np.setdiff1d(np.arange(total), columns[-1]):
        rows, slots = np.nonzero((columns == label) & np.isfinite(values[:len(columns)]))
        if len(rows):
            candidates.append((int(label), rows[-2:], slots[-2:]))
    return candidates


#: a gone root is followed back (:func:`_followed_back`) only to an entering root within this
#: fraction of its last |lambda| of its last root: a bound on the check's work (the ROSS compressor's
#: lowest 12 at 147 speeds: 1.7 -> 3.3 s CPU without it, its roots leaving at the top of the lowest
#: at 11,800 rad/s while new modes enter below 600 rad/s)
_FOLLOWED_DISTANCE = 0.5


def _followed_back(stack, speeds, columns, total, entering, k, values, count, progress=False) -> dict:
    """The roots of ``entering`` that the check follows back to a result column whose root left
    the lowest modes before speed ``k``: ``{j: its former column}``, for roots :func:`_returning`
    does not give back (their shape changed while they were out: MAC below ``_CONFIDENT_MAC``).

    The check solves ``count +`` :data:`_EXTRA_ROOTS` ``+`` (columns gone) roots at every sweep
    speed from the first of the gone roots' last speeds to ``k``, halving the steps where its
    tracking is unsure for one of them (:func:`_check_grids`), and tracks them as one run: an
    entering root is a gone column's root where the check's root of the column's last value is, at
    speed ``k``, the entering root (each to :data:`_SAME_VALUE`). A root that rose above the
    check's roots in between, or whose pairing the check could not tell (:func:`_unsure_labels`),
    or that comes back more than :data:`_FOLLOWED_DISTANCE` of its |lambda| from where it left, is
    not followed: it gets a column of its own, as before.

    Parameters
    ----------
    columns : ndarray of int, shape (k, c)
    total : int
    entering : list of int
    k : int
    values : ndarray, shape (N, c), complex [1/s]
    count : int

    Returns
    -------
    dict
    """
    candidates = [c for c in _gone(columns, total, values)
                  if np.any(np.abs(values[k, entering] - values[int(c[1][-1]), int(c[2][-1])])
                            <= _FOLLOWED_DISTANCE * abs(values[int(c[1][-1]), int(c[2][-1])]))]
    if not candidates:
        return {}
    start = min(int(rows[-1]) for _, rows, _ in candidates)
    steps = np.arange(start, k)
    more = min(count + _EXTRA_ROOTS + len(candidates), stack_root_count(stack))
    try:
        grids, lam, rows, where = _check_grids(stack, speeds, steps, min(count + len(candidates), more), more,
                                               progress)
    except InputError:                               # too long to solve again: new columns
        return {}
    at = np.concatenate([grids[steps[0]]] + [grids[s][1:] for s in steps[1:]])
    ends = np.cumsum([0] + [len(grids[s]) - 1 for s in steps])      # each sweep speed's place in ``at``
    order = track_modes_many(lam[at][None], rows[at][None], where[at])[0]
    untold = _unsure_labels(lam[at], rows[at], min(count + len(candidates), more), order)[1]
    found = {}
    for label, last_rows, slots in candidates:
        place = ends[int(last_rows[-1]) - start]
        index = _same_roots(lam[at[place]], values[int(last_rows[-1]), int(slots[-1])][None])
        if index is None:
            continue
        mine = np.flatnonzero(order[place] == index[0])[0]                # the check's label of the gone root
        if untold[place:, mine].any():                                     # lost on the way: a new column
            continue
        now = lam[at[ends[-1]], order[ends[-1], mine]]
        for j in entering:
            if j not in found and abs(values[k, j] - now) <= _SAME_VALUE * abs(now):
                found[j] = label
                break
    return found


def _doubtful_steps(values, weighted) -> np.ndarray:
    """The steps k (to speed k + 1) where some tracked column of ``values`` (N, c) whose roots are
    found at both speeds has a MAC of its weighted shapes (``weighted`` (1, N, c, n)) with itself
    below :data:`_SAME_ROOT_MAC`, or is found at one of them only."""
    found = np.isfinite(values)
    doubtful = np.any(found[:-1] != found[1:], axis=1)
    for part in _batches.chunk_slices(len(values) - 1, 32 * values.shape[1] * weighted.shape[-1],
                                      budget=_SAME_ROOT_BYTES):
        start, stop = part.start, part.stop
        rows = weighted[0, start:stop + 1]                               # (K + 1, c, n)
        same = np.abs(np.sum(rows[:-1].conj() * rows[1:], axis=-1)) ** 2
        doubtful[start:stop] |= np.any((same < _SAME_ROOT_MAC) & found[start:stop] & found[start + 1:stop + 1], axis=1)
    return np.flatnonzero(doubtful)


def _links_of_steps(stack, speeds, values, steps, count, progress=False) -> dict:
    """Which tracked root of ``values`` (N, c) continues which over each doubtful step, where some
    root enters or leaves the lowest ``count`` there, or where the sweep's tracking paired its roots
    otherwise: ``{k: {j: i or None}}``, root ``j`` at speed ``k + 1`` continuing root ``i`` at ``k``
    (None: it enters). A step whose roots continue as the sweep tracked them, or that the check
    cannot tell, is not in it (the sweep's tracking stands).

    The check tracks ``count +`` :data:`_EXTRA_ROOTS` roots over the step, on speeds between its two
    ends where a step of them is unsure (:func:`_check_grids`): the pairing does not depend on the
    sweep's step. Neighbouring doubtful steps whose shared sweep speed holds a root the check finds
    twice (two roots equal there, or a repeated root, whose shapes are any basis of its eigenspace)
    are tracked as one run of speeds, so that a root is the same root on both sides of that speed
    (and such a step's neighbour is checked too, :func:`_tied_neighbours`): each of the sweep's
    roots is the check's root of its value, and a link joins the sweep's roots the check's tracking
    calls one root (:func:`_sweep_labels`)."""
    more = min(count + _EXTRA_ROOTS, stack_root_count(stack))
    try:
        memo = {}                                    # the check's tracking of each grid
        grids, lam, rows, where = _check_grids(stack, speeds, steps, count, more, progress, memo)
        extra = _tied_neighbours(steps, grids, lam, values)
        if len(extra):                               # a run may not end where a root meets another
            added, more_lam, more_rows, more_where = _check_grids(stack, speeds, extra, count, more, progress)
            grids.update({k: grid + len(lam) for k, grid in added.items()})
            lam, rows = np.concatenate([lam, more_lam]), np.concatenate([rows, more_rows])
            where = np.concatenate([where, more_where])
            steps = np.union1d(steps, extra)
    except InputError:                               # too long to solve again: the tracking stands
        return {}
    links = {}
    for run in _runs(steps, [k for k in steps if np.any(_copies_of(values[k], lam[grids[int(k)][0]]) > 1)]):
        at = np.concatenate([grids[run[0]]] + [grids[k][1:] for k in run[1:]])
        ends = np.cumsum([0] + [len(grids[k]) - 1 for k in run])        # each sweep speed's place in ``at``
        if len(run) == 1:                            # one step: as the check last tracked its grid
            order, _, untold = _grid_tracking(lam, rows, count, where, at, memo)
        else:
            order = track_modes_many(lam[at][None], rows[at][None], where[at])[0]     # (P, m): label -> check root
            untold = _unsure_labels(lam[at], rows[at], count, order)[1]
        labels = _sweep_labels(lam[at[ends]], order[ends], values[run[0]:run[-1] + 2])
        for s, k in enumerate(run):
            link = _step_link(labels[s], labels[s + 1], np.flatnonzero(untold[ends[s]:ends[s + 1]].any(axis=0)))
            if link is not None:
                link = _within_repeated_roots(link, labels[s + 1], lam[at[ends[s]]], order[ends[s]], values[k],
                                              values[k + 1])
            if link is not None:
                links[int(k)] = link
    return links


def _within_repeated_roots(link, after, lam, order, values, following):
    """``link`` (:func:`_step_link`) with a root said to enter joined to the sweep's root it
    continues inside a repeated root: the check's label of root ``j`` at the step's second speed
    (``after[j]``) is, at its first, a copy (within :data:`_SAME_VALUE`) of a sweep root ``i`` no other
    root continues, and root ``j`` lies within tracking's ``_KEPT_DISTANCE`` of ``|lambda|`` of it (not
    a root born far below as one leaves at the top, which the check's tracking pairs). A repeated
    root's shapes are any basis of its eigenspace, so the sweep's copy and the check's copy of it
    are one root, whichever basis each solve chose (two identical uncoupled shafts at rest: a
    quadruple root, whose forward copy kept below the cut entered as a new column with OpenBLAS's
    Haswell kernels). ``lam`` (m,) and ``order`` (m,) are the check's roots and tracking at the
    first speed, ``values`` (c,) the sweep's roots there and ``following`` (c,) at the second.
    None where each sweep root then continues the one the sweep tracked."""
    from .tracking import _KEPT_DISTANCE

    claimed = {i for i in link.values() if i is not None}
    for j, i in link.items():
        if i is not None or after is None:
            continue
        there = lam[order[int(after[j])]]
        for candidate in range(len(values)):
            size = abs(values[candidate])
            if candidate not in claimed and np.isfinite(values[candidate]) \
                    and abs(values[candidate] - there) <= _SAME_VALUE * size \
                    and abs(following[j] - values[candidate]) <= _KEPT_DISTANCE * size:
                link[j] = candidate
                claimed.add(candidate)
                break
    return None if all(i == j for j, i in link.items()) else link


def _tied_neighbours(steps, grids, lam, values) -> np.ndarray:
    """The steps next to a run of ``steps`` (:func:`_runs`), not among them, at whose shared sweep
    speed one of the sweep's roots ``values`` (N, c) is found twice among the check's roots ``lam``
    (within :data:`_SAME_VALUE`: two roots meeting at that very speed, or a repeated root): which of
    the two it is the check can tell only by tracking through that speed (:func:`_sweep_labels`).
    ``grids`` as :func:`_check_grids` returns them."""
    extra = []
    for run in _runs(steps):
        for k, place, step in ((run[0], 0, run[0] - 1), (run[-1] + 1, -1, run[-1] + 1)):
            grid = grids[run[0] if place == 0 else run[-1]]
            if not 0 <= step < len(values) - 1 or not np.all(np.isfinite(values[k])):
                continue
            if np.any(_copies_of(values[k], lam[grid[place]]) > 1):
                extra.append(step)
    return np.setdiff1d(np.array(extra, dtype=int), steps)


def _copies_of(values, lam):
    """How many of the roots ``lam`` (m,) lie within :data:`_SAME_VALUE` of each of ``values`` (c,)."""
    return (np.abs(values[:, None] - lam[None, :]) <= _SAME_VALUE * np.abs(values)[:, None]).sum(axis=1)


def _runs(steps, joined=None) -> list:
    """``steps`` (increasing ints) in runs of consecutive ones, [[1, 2, 3], [7], ...]; with
    ``joined``, only those steps are joined to the step before them (the others start runs)."""
    steps = [int(k) for k in steps]
    joined = None if joined is None else {int(k) for k in joined}
    runs = []
    for k in steps:
        if runs and runs[-1][-1] == k - 1 and (joined is None or k in joined):
            runs[-1].append(k)
        else:
            runs.append([k])
    return runs


def _sweep_labels(lam, order, values):
    """The check's label (its tracked root) of each of the sweep's roots at each sweep speed of a run.

    Each of the sweep's roots is the check's root of its value (within :data:`_SAME_VALUE`). A root
    the check finds twice to that tolerance (a repeated root, or two roots that meet at that very
    speed) could be either copy; of such ties, the label (1) the sweep's same root has at a
    neighbouring speed of the run (its own pairing kept where the check does not say otherwise) and
    (2) found among the sweep's roots at the neighbouring speeds (a root that continues rather than
    one that leaves there) is taken.

    Parameters
    ----------
    lam : ndarray, shape (S, m), complex [1/s]
        The check's roots at the run's sweep speeds.
    order : ndarray of int, shape (S, m)
        The check's tracking there: ``order[s, label]`` is the root of ``label`` at speed s.
    values : ndarray, shape (S, c), complex [1/s]
        The sweep's tracked roots there.

    Returns
    -------
    list of (ndarray of int, shape (c,), or None)
        Each speed's labels of the sweep's roots; None where one is not among the check's roots.
    """
    count = len(values)
    label_of = np.empty_like(order)
    label_of[np.arange(count)[:, None], order] = np.arange(order.shape[1])[None, :]   # check root -> label
    plain = _plain_labels(lam, values, label_of)
    if plain is not None:
        return plain
    labels = [_labelled(lam[s], values[s], label_of[s], None) for s in range(count)]
    again = []
    for s in range(count):                               # ties settled by the first pass's neighbours
        near = [labels[t] for t in (s - 1, s + 1) if 0 <= t < count and labels[t] is not None]
        again.append(_labelled(lam[s], values[s], label_of[s], near))
    return again


def _plain_labels(lam, values, label_of):
    """:func:`_sweep_labels` where no root is near a tie at any speed of the run: each sweep root's
    nearest check root (relative distance) is another one than every other sweep root's, and nearer
    by more than the largest tie cost (half :data:`_SAME_VALUE`) than its next nearest. Then the
    optimal assignment of both passes, whatever the ties' costs, gives each sweep root its nearest
    root; None where some speed is not so plain (both passes run)."""
    if not np.all(np.isfinite(values)):
        return None
    with np.errstate(invalid="ignore"):
        gap = np.abs(values[:, :, None] - lam[:, None, :]) / np.abs(values)[:, :, None]     # (S, c, m)
    gap = np.minimum(np.where(np.isfinite(gap), gap, 1.0), 1.0)
    if gap.shape[-1] < 2:
        return None
    nearest = np.argmin(gap, axis=-1)                                                       # (S, c)
    two = np.partition(gap, 1, axis=-1)[..., :2]
    if np.any(two[..., 1] - two[..., 0] <= 0.5 * _SAME_VALUE):
        return None
    ranked = np.sort(nearest, axis=-1)
    if np.any(ranked[:, 1:] == ranked[:, :-1]):
        return None
    found = two[..., 0] <= _SAME_VALUE
    return [np.take_along_axis(label_of[s], nearest[s], axis=-1) if found[s].all() else None
            for s in range(len(values))]


def _labelled(lam, values, label_of, near):
    """:func:`_sweep_labels` at one speed: the check's label (``label_of`` (m,), of each check root
    ``lam`` (m,)) of each sweep root ``values`` (c,); ``near`` the labels of the neighbouring speeds
    (None on the first pass: ties go to the first copy)."""
    index = _same_roots(lam, values, None if near is None else _tie_cost(label_of, near, len(values)))
    return None if index is None else label_of[index]


def _tie_cost(label_of, near, c):
    """(c, m) cost, below :data:`_SAME_VALUE`, of giving sweep root j the check root of each label:
    half of it where that label is not the one the sweep's root j has at a neighbouring speed, half
    where the label is no sweep root's at a neighbouring speed."""
    cost = np.zeros((c, len(label_of)))
    for labels in near:
        cost += 0.25 * _SAME_VALUE * (label_of[None, :] != labels[:, None])
        cost += 0.25 * _SAME_VALUE * ~np.isin(label_of, labels)[None, :]
    return cost / max(len(near), 1)


#: the most halvings of a doubtful step the check makes (:func:`_check_grids`): a step of 2**-6 of
#: the sweep's at the finest, where a pair of its roots is still unsure
_CHECK_LEVELS = 6


def _check_grids(stack, speeds, steps, count, more, progress=False, memo=None):
    """The check's speeds over each doubtful step and its ``more`` lowest roots there.

    Each step is halved where the check's tracking over a part of it is unsure for one of the
    ``count`` lowest roots (:func:`_unsure_parts`), up to :data:`_CHECK_LEVELS` times, the new
    speeds of all steps solved in one batch a level; with ``progress``, a line
    (:func:`.._progress.phase`) names the steps checked and each level's halvings.

    Returns
    -------
    grids : dict
        ``{k: ndarray of int}``, the check's speeds of step ``k``, increasing, as indices into
        ``lam`` (the first and last: speeds ``k`` and ``k + 1``).
    lam : ndarray, shape (P, more), complex [1/s]
    rows : ndarray, shape (P, more, n), complex
        Their weighted shapes.
    where : ndarray, shape (P,) [rad/s]
        The speed of each.

    ``memo``, where given (a dict), receives the check's tracking of each step's grid as it was
    last judged (:func:`_grid_tracking`, keyed by the grid's indices into ``lam``): the caller
    that tracks a step alone over the same grid takes it from there instead of tracking it again.
    """
    described = f"checking {len(steps)} doubtful step{'s' if len(steps) != 1 else ''} of the lowest modes"
    with phase(progress, described) as bar:
        at = np.unique(np.concatenate([steps, steps + 1]))
        lam, rows = _check_roots(stack, speeds[at], more)
        return _halved(stack, speeds, steps, count, more, at, lam, rows, bar, described, memo)


def _halved(stack, speeds, steps, count, more, at, lam, rows, bar, described, memo=None):
    """:func:`_check_grids`' halvings, from the check's roots ``lam``, ``rows`` at the steps' ends
    ``speeds[at]``; ``bar`` (a :func:`.._progress.phase` line, or None) renamed each level. A step
    none of whose parts was halved at a level keeps its grid, and so its unsure parts (none): only
    the steps just halved are tracked again."""
    index = {int(k): i for i, k in enumerate(at)}
    grids = {int(k): np.array([index[int(k)], index[int(k) + 1]]) for k in steps}
    points = {int(k): [float(speeds[k]), float(speeds[k + 1])] for k in steps}
    where = speeds[at]
    memo = {} if memo is None else memo
    halves = dict(grids)                                 # the steps (re)judged at the next level
    for level in range(_CHECK_LEVELS):
        halves = {k: _grid_tracking(lam, rows, count, where, grids[k], memo, stack)[1] for k in halves}
        halves = {k: parts for k, parts in halves.items() if len(parts)}
        if not halves:
            break
        middle = [(k, p, 0.5 * (points[k][p] + points[k][p + 1])) for k, parts in halves.items() for p in parts]
        if bar is not None:
            bar.set_description(f"{described}: halving {len(middle)} unsure part{'s' if len(middle) != 1 else ''} "
                                f"(level {level + 1} of at most {_CHECK_LEVELS}): ", refresh=False)
        more_lam, more_rows = _check_roots(stack, np.array([m for _, _, m in middle]), more)
        start = len(lam)
        lam, rows = np.concatenate([lam, more_lam]), np.concatenate([rows, more_rows])
        where = np.concatenate([where, [m for _, _, m in middle]])
        for k in halves:
            mine = [(p, start + i, m) for i, (kk, p, m) in enumerate(middle) if kk == k]
            for p, i, m in reversed(mine):               # from the last part: earlier places stay
                grids[k] = np.insert(grids[k], p + 1, i)
                points[k].insert(p + 1, m)
    return grids, lam, rows, where


def _check_roots(stack, speeds, more):
    """The ``more`` lowest roots (P, more) at ``speeds`` (P,) [rad/s] and their weighted shapes
    (P, more, n), the route's own fallback warnings muted (a check: no news of the sweep's). The
    check compares shapes by their MAC alone: a small undamped gyroscopic model's come from its
    Hermitian matrix's eigenvectors (:func:`._lowest.weighted_lowest_roots`, the roots the same).
    Below ``_lowest.CHECK_DENSE_BELOW`` coordinates the roots are the dense route's
    (:func:`._lowest._small_lowest`: every root of the state matrix, within its round-off), not
    Newton's: the check tracks and matches roots (to ``_SAME_VALUE``), and there one ``eigvals``
    costs less than the reduced route's set-up for a few speeds."""
    from . import _lowest, _lowest_branches

    if not stack.branch_times.shape[1]:
        found = _lowest.weighted_lowest_roots(stack, speeds, more)
        if found is not None:
            return found
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if stack.branch_times.shape[1]:
            lam, phi, _ = _lowest_branches.lowest_roots(stack, speeds, more)
        elif stack.n_dof < _lowest.CHECK_DENSE_BELOW:
            lam, phi = _lowest._small_lowest(stack, speeds, more)
        else:
            lam, phi, _ = _lowest.lowest_roots(stack, speeds, more)
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        return lam, WeightedRows(stack, phi[None], one_thread=True)[0]


def _grid_tracking(lam, rows, count, where, grid, memo, stack=None):
    """The check's tracking over one step's ``grid`` (indices into ``lam`` (P, m), ``rows`` (P, m, n),
    ``where`` (P,)): ``(order, unsure parts, untold)`` as :func:`_unsure_parts` and
    :func:`_unsure_labels` give them, kept in ``memo`` by the grid's indices (the same indices are
    the same roots within one check: its arrays only grow). With ``stack``, a part whose unsure
    labels are each one of two neighbouring roots shown never to meet over it (nor another root)
    and tracked each to its own rank is sure (:func:`_pairs_settled`)."""
    key = tuple(int(i) for i in grid)
    if key not in memo:
        order = track_modes_many(lam[grid][None], rows[grid][None], where[grid])[0]
        unsure, untold = _unsure_labels(lam[grid], rows[grid], count, order)
        if stack is not None and unsure.any():
            unsure = _pairs_settled(stack, lam[grid], where[grid], order, unsure)
        memo[key] = order, [int(p) for p in np.flatnonzero(unsure.any(axis=1))], untold
    return memo[key]


def _pairs_settled(stack, lam, where, order, unsure):
    """``unsure`` (P - 1, m) with the labels cleared whose pairing over a part the roots' values
    settle: on the Hermitian route of an undamped gyroscopic model, two neighbouring roots that
    :func:`._lowest_pairs.pairs_kept` shows distinct, and apart from every other, at every speed of
    the part keep their ranks over it; a label that is one of them, and whose tracked root (as its
    partner's) has the same rank at both ends, is paired as the roots are. ``lam`` (P, m) the
    check's roots at its speeds ``where`` (P,) [rad/s] over one step, ``order`` (P, m) their tracking.

    Parameters
    ----------
    stack : Stack
    lam : ndarray, shape (P, m), complex [1/s]
    where : ndarray, shape (P,) [rad/s]
    order : ndarray of int, shape (P, m)
    unsure : ndarray of bool, shape (P - 1, m)

    Returns
    -------
    ndarray of bool, shape (P - 1, m)
    """
    from ._lowest_pairs import pairs_kept

    unsure = unsure.copy()
    frequency = np.abs(lam.imag)
    rank = np.argsort(np.argsort(frequency, axis=-1, kind="stable"), axis=-1, kind="stable")    # (P, m) of each root
    for p in np.flatnonzero(unsure.any(axis=1)):
        ranks = rank[p, order[p]]                            # each label's rank at the part's ends
        kept = ranks == rank[p + 1, order[p + 1]]
        by_rank = np.argsort(ranks)                          # the label of each rank at the first end
        ascending = frequency[p, order[p, by_rank]]
        lower = {}
        for label in np.flatnonzero(unsure[p]):
            r = int(ranks[label])
            below = ascending[r] - ascending[r - 1] if r > 0 else np.inf
            above = ascending[r + 1] - ascending[r] if r + 1 < len(ascending) else np.inf
            first = r - 1 if below < above else r            # the pair with its nearer neighbour
            if 0 <= first and first + 1 < len(ascending) and kept[by_rank[first]] and kept[by_rank[first + 1]]:
                lower[int(label)] = first
        if not lower:
            continue
        firsts = sorted(set(lower.values()))
        shown = dict(zip(firsts, pairs_kept(stack, float(where[p]), float(where[p + 1]), firsts)))
        for label, first in lower.items():
            if shown[first]:
                unsure[p, label] = False
    return unsure


def _unsure_parts(lam, rows, count, where=None) -> list:
    """The parts p (from the check's speed p to p + 1) of a step where the check's tracking of its
    roots ``lam`` (P, m), weighted shapes ``rows`` (P, m, n), is unsure for a root among the
    ``count`` lowest (by frequency: the sweep's roots) at either end: its weighted shapes at the
    two ends have a MAC below the tracking's ``_CONFIDENT_MAC``, and it moved at least half the way
    to the nearest other root at one of the ends, or its shape at the first end is plainly that of
    another root at the second (:func:`_elsewhere`): its pairing told by neither its shape nor its
    value, or by its value against its shape.

    A repeated root's copies (a rotor's forward and backward modes at rest), whose shapes are any
    basis of their eigenspace, are one root (:func:`_copies`): neither they nor the roots they
    become are each other's nearest other root. The top root at either end is not checked: where
    a root enters the check's roots (one becoming a mode) the top one leaves them, and tracking
    pairs the two, on every part however short. ``where`` (P,) [rad/s]: the check's speeds (the
    tracking's extrapolation over parts of unequal length)."""
    order = track_modes_many(lam[None], rows[None], where)[0]
    return [int(p) for p in np.flatnonzero(_unsure_labels(lam, rows, count, order)[0].any(axis=1))]


def _unsure_labels(lam, rows, count, order):
    """:func:`_unsure_parts`' test of each of the check's tracked roots (labels) on each part, the
    tracking ``order`` (P, m) given (``order[p, label]``: the label's root at speed p).

    Returns
    -------
    unsure : ndarray of bool, shape (P - 1, m)
        The label's pairing over the part is unsure (halved by :func:`_check_grids`).
    untold : ndarray of bool, shape (P - 1, m)
        The pairings of the top root at either end (not halved) that would be unsure, no copy at
        either end: a root entering the check's roots from below (one becoming a mode) while
        another leaves them at the top, paired by tracking, however short the part. Such a
        pairing is no link (two roots equal at a speed, copies, are told by tracking through that
        speed, :func:`_links_of_steps`).
    """
    from ._vectors import mac_matrix
    from .tracking import _CONFIDENT_MAC

    # every part at once (each part's numbers as its own: a stack of the same products)
    labelled = np.arange(len(lam))[:, None]
    values, shapes = lam[labelled, order], rows[labelled, order]            # (P, m), (P, m, n) by label
    a, b = values[:-1], values[1:]                                          # each part's two ends
    macs = mac_matrix(shapes[:-1], shapes[1:])                              # (P - 1, m, m)
    mac = np.diagonal(macs, axis1=-2, axis2=-1)
    other = np.abs(a[:, :, None] - a[:, None, :]) > _SAME_VALUE * np.abs(a)[:, :, None]   # not itself, nor its copies
    gap = np.minimum(np.where(other, np.abs(a[:, :, None] - a[:, None, :]), np.inf),
                     np.where(other, np.abs(b[:, :, None] - b[:, None, :]), np.inf)).min(axis=-1)
    copies = _copies(b)
    moved = (np.abs(b - a) >= 0.5 * gap) | _elsewhere(macs, ~other, copies)
    rank_a, rank_b = (np.argsort(np.argsort(np.abs(x.imag), axis=-1, kind="stable"), axis=-1, kind="stable")
                      for x in (a, b))
    lowest = (rank_a < count) | (rank_b < count)
    m = lam.shape[1]
    unsure = (mac < _CONFIDENT_MAC) & moved & lowest & (rank_a < m - 1) & (rank_b < m - 1)
    top = (rank_a == m - 1) | (rank_b == m - 1)
    untold = (mac < _CONFIDENT_MAC) & moved & lowest & top & ((~other).sum(axis=-1) == 1) & (copies.sum(axis=-1) == 1)
    return unsure, untold


def _copies(values):
    """(..., m, m) bool: the roots of ``values`` (..., m) within :data:`_SAME_VALUE` of each other (a
    repeated root's copies, each its own copy)."""
    return np.abs(values[..., :, None] - values[..., None, :]) <= _SAME_VALUE * np.abs(values)[..., :, None]


def _elsewhere(mac, before, after):
    """Of the check's tracked roots over a part (labels), those whose shape at the part's first end
    has a MAC of at least ``_CONFIDENT_MAC`` with another label's root at its second end: tracking
    paired them by value against their shapes (a coarse step where roots moved more than their
    gaps). The MACs are summed over a repeated root's copies at either end (``before``, ``after``
    (m, m) bool, :func:`_copies`), whose shapes are any basis of their eigenspace, and a label's own
    copies are not another's root.

    Parameters
    ----------
    mac : ndarray, shape (..., m, m)
        MAC of each label's weighted shape at the first end (rows) with each at the second
        (several parts stacked: each its own).
    before, after : ndarray of bool, shape (..., m, m)

    Returns
    -------
    ndarray of bool, shape (..., m)
    """
    from .tracking import _CONFIDENT_MAC

    a, b = before.astype(float), after.astype(float)
    grouped = a @ mac @ b                          # a's copies (rows) against b's copies (columns)
    own = (a @ b) > 0                              # the labels a label's copies became, and their copies
    return np.any((grouped >= _CONFIDENT_MAC) & ~own, axis=-1)


def _step_link(before, after, untold=()):
    """:func:`_links_of_steps` of one step from the check's labels (:func:`_sweep_labels`) of the
    sweep's roots at its two speeds, ``before`` and ``after`` (c,) (None: a root of the sweep is
    not among the check's): ``{j: i or None}``, root j at the second speed continuing root i at the
    first (None: the label of j is none of the first speed's roots, or one of ``untold``, whose
    pairing the check could not tell, :func:`_unsure_labels`), or None where each of the sweep's
    roots continues the one the sweep tracked (or one is not among the check's)."""
    if before is None or after is None:
        return None
    where = {int(label): i for i, label in enumerate(before) if label not in untold}
    link = {j: where.get(int(label)) for j, label in enumerate(after)}
    if all(i == j for j, i in link.items()):
        return None
    return link


def _assigned(gap):
    """:func:`scipy.optimize.linear_sum_assignment` of ``gap`` (rows, columns), its entries held to 1."""
    from scipy.optimize import linear_sum_assignment

    return linear_sum_assignment(np.minimum(gap, 1.0))


def _same_roots(lam, values, tie=None):
    """The index in ``lam`` (m,) of each root of ``values`` (c,) (within :data:`_SAME_VALUE`; a
    repeated root's copies each to one of its own, ``tie`` (c, m), below :data:`_SAME_VALUE`,
    choosing among them), or None where one is not there (or is not found)."""
    if not np.all(np.isfinite(values)):
        return None
    with np.errstate(invalid="ignore"):
        gap = np.abs(values[:, None] - lam[None, :]) / np.abs(values)[:, None]
    gap = np.where(np.isfinite(gap), gap, 1.0)
    rows, index = _assigned(gap if tie is None else np.minimum(gap, 1.0) + tie)
    if np.any(gap[rows, index] > _SAME_VALUE):
        return None
    return index


def _numbered(columns, values, speeds, total):
    """``columns`` (N, c) renumbered as the tracked modes: those found at the speed nearest zero
    by frequency there, then the others by the speed where they first are and their frequency
    there."""
    k0 = int(np.argmin(np.abs(speeds)))
    key = np.zeros((total, 3))
    seen = np.zeros(total, dtype=bool)
    for k in [k0] + [k for k in range(len(speeds)) if k != k0]:
        for j in np.flatnonzero(~seen[columns[k]]):
            label = columns[k, j]
            key[label] = (k != k0, k if k != k0 else 0, abs(values[k, j].imag))
            seen[label] = True
    rank = np.empty(total, dtype=int)
    rank[np.lexsort(key.T[::-1])] = np.arange(total)
    return rank[columns]


def _rows_of_roots(table, speeds, columns, values, sources):
    """``table`` (CriticalSpeeds of the tracked columns ``values`` (N, c)) with each row's mode the
    result's column of its root (:func:`_root_columns`). A row refined on a step where a root
    enters the lowest modes and more than :data:`NOT_A_CROSSING` off its order line is left out:
    the refinement followed a column from one root to another (no crossing; the step's change of
    roots says why, so no warning); on such a step a row on its line is the root's at the end
    nearer its frequency."""
    if not len(table):
        return table
    mode = np.asarray(table.mode, dtype=int) - 1
    k = np.clip(np.searchsorted(speeds, np.asarray(table.speeds, dtype=float), side="right") - 1, 0,
                max(len(speeds) - 2, 0))
    upper = np.minimum(k + 1, len(speeds) - 1)
    changed = np.any(columns[k] != columns[upper], axis=1)
    keep = ~changed | (off_order_line(table, sources) <= NOT_A_CROSSING)
    frequency = 2 * np.pi * np.asarray(table.frequencies_hz, dtype=float)
    nearer_upper = np.abs(values[upper, mode].imag - frequency) < np.abs(values[k, mode].imag - frequency)
    root = np.where(nearer_upper, columns[upper, mode], columns[k, mode])
    return _critical_table(*(np.asarray(column)[keep] for column in (
        table.source, table.order, root + 1, table.speeds, table.frequencies_hz, table.whirl,
        table.whirl_ratios, table.damping_ratios)))


def _by_root(columns, values, shapes, ratios, noise):
    """The arrays of the tracked columns (1, N, c[, n]) spread over one column per root
    (``columns`` (N, c), :func:`_root_columns`): NaN (zero shapes, ratios, round-off) where the root is
    not among the lowest."""
    total = int(columns.max()) + 1
    count = len(columns)
    rows = np.arange(count)[:, None]
    out_values = np.full((1, count, total), complex(np.nan, np.nan))
    out_values[0, rows, columns] = values[0]
    out_shapes = np.zeros((1, count, total, shapes.shape[-1]), dtype=complex)
    out_shapes[0, rows, columns] = shapes[0]
    out_ratios = np.zeros((1, count, total))
    out_ratios[0, rows, columns] = ratios[0]
    if noise is not None:
        out_noise = np.zeros((count, total))
        out_noise[rows, columns] = noise
        noise = out_noise
    return out_values, out_shapes, out_ratios, noise


#: a row of the lowest modes' route this far off its order line (relative) is no critical speed:
#: its tracked column passed to another root (see :func:`_crossings_only`)
NOT_A_CROSSING = 1e-2


def _crossings_only(table, sources, model):
    """``table`` (CriticalSpeeds of the lowest modes' route) without its rows that are no crossing.

    The route's columns are the lowest roots that are modes at each speed: where a root enters them
    (a root becoming a mode as its damping ratio falls below ``OVERDAMPED_LIMIT``, or one passing
    below the last of them), a tracked column passes from one root to another across the order
    lines. The refinement closes in on that step, and the row's root there lies far off the line
    (tens of % to several times the line's frequency). No finer grid removes it (the step
    is in the set of roots, not between grid speeds), so such rows are left out and counted in one
    warning; rows nearer the line than ``NOT_A_CROSSING`` stay (and are warned of as jumps)."""
    off = off_order_line(table, sources)
    away = off > NOT_A_CROSSING
    if not away.any():
        return table
    at = ", ".join(dict.fromkeys(f"{s * 30 / np.pi:.6g}" for s in np.sort(np.asarray(table.speeds)[away])))
    warnings.warn(f"{model.source}: {int(away.sum())} of {len(table)} critical speeds left out: not crossings "
                  f"(the natural frequency up to {100 * off.max():.3g} % off the order line, at {at} rpm), where "
                  f"a tracked mode passes to a root entering the lowest modes (a root becoming a mode, or "
                  f"passing below the last one asked for)", stacklevel=4)
    return _critical_table(*(np.asarray(column)[~away] for column in (
        table.source, table.order, table.mode, table.speeds, table.frequencies_hz, table.whirl, table.whirl_ratios,
        table.damping_ratios)))


def _table_below(table, limit):
    """The crossings of ``table`` (CriticalSpeeds) at frequencies up to ``limit`` [rad/s]."""
    keep = 2 * np.pi * np.asarray(table.frequencies_hz, dtype=float) <= limit
    return _critical_table(*(np.asarray(column)[keep] for column in (
        table.source, table.order, table.mode, table.speeds, table.frequencies_hz, table.whirl, table.whirl_ratios,
        table.damping_ratios)))


def campbell_many(models, speeds, orders=(1,), progress=False, critical=True) -> list:
    """Campbell diagrams of several models of the same structure (a study's variants) in one
    batch: one LAPACK call for every model and speed, tracking and critical speeds of all
    together. Each result equals :func:`campbell` of its model bit for bit for models of up to
    48 coordinates (pencils solved whole, every step row by row); above that one model's pencil
    products serve all its crossings in one matrix product (BLAS-3, see
    :meth:`~._stack.Pencils.products`) and the critical speeds agree to round-off (within
    1e-13 relative measured at 50 coordinates).

    Parameters
    ----------
    models : sequence of Model
        Same coordinates and states (variants of one model).
    speeds, orders, progress, critical : see :func:`campbell`

    Returns
    -------
    list of CampbellResult
    """
    speeds = _check_speeds(speeds)
    orders = _arguments.orders(orders)
    stack = Stack(models)
    critical = bool(critical) and len(orders) > 0
    _refuse_what_cannot_fit(stack, len(speeds), critical)
    values, shapes, weighted, noise = solve_sweeps(stack, speeds, progress, whirl_noise=True)
    count, n_speeds, m = values.shape
    with phase(progress, "round-off and whirl"):
        _refine_inexact(stack, speeds, values, shapes, noise)
        every = _variant_rows(count, n_speeds)
        ratios = stack.whirl_ratios(shapes.reshape((-1,) + shapes.shape[-2:]), every,
                                    speeds if count == 1 else np.tile(speeds, count))
    oscillating = is_oscillating(values)
    ratios = np.where(oscillating, ratios.reshape(values.shape), 0.0)
    freq, zeta, log_dec = modal_quantities(values)
    sources = [excitation_sources(model) for model in stack.models]
    if critical:
        tables = _find_critical_speeds(stack, speeds, values, weighted, sources, tuple(orders), shapes, oscillating,
                                       progress, lambda crossings: _refuse_crossings(stack, len(speeds), crossings),
                                       whirl_noise=noise)
    else:
        tables = [_critical_table([], [], [], [], [], [], [], []) for _ in range(count)]
    del weighted
    for table, source, model in zip(tables, sources, stack.models):
        _warn_of_jumps(table, source, model)
    noise = np.where(oscillating, noise, 0.0)
    labels = _whirl.whirl_labels(ratios, noise)          # modal's rule: within round-off no whirl
    return [CampbellResult(
        speeds=speeds, eigenvalues=values[v], frequencies_hz=freq[v], damping_ratios=zeta[v],
        log_decrements=log_dec[v], whirl_ratios=ratios[v], whirl=labels[v], shapes=shapes[v],
        modes=np.arange(1, m + 1), sources=sources[v],
        critical=_with_sweep(tables[v], stack.models[v], speeds, values[v], progress),
        orders=tuple(float(o) for o in orders), whirl_round_off=noise[v]) for v in range(count)]



def _refine_inexact(stack, speeds, values, shapes, noise=None):
    """The roots ``values`` (V, N, m) with ``shapes`` (V, N, m, n) at ``speeds`` [rad/s] that
    double precision leaves further off than :data:`._eigensolve.POLISH_LEVEL`
    (:func:`._eigensolve.pencil_round_off`): pairs closer than that polished in place
    (:func:`._eigensolve.refined_pairs`), the rest warned of, once per model (models with
    Maxwell branches on their rational pencil). ``noise`` (V, N, m), where given, the whirl ratios'
    round-off, the polished roots' made their own in place (:func:`._eigensolve.polished_ratio_round_off`).
    Returns whether any root needed the polish."""
    needed = False
    for v, form in enumerate(stack.forms):
        branches = _eigensolve.branch_terms(form)
        G, n = form.matrices.G, form.n_dof
        bound = np.zeros(values.shape[1:])
        # the bearings evaluated for a part of the speeds at a time (each speed's coefficients its
        # own: a journal's film and load over speed are computed once for the part, not once a speed),
        # a part's dense (n, n) matrices within _PART_BYTES (one speed at a time for a large model)
        for part in _batches.chunk_slices(len(speeds), _REFINE_ARRAYS * 8 * n * n, budget=_batches._PART_BYTES):
            stiffness, damping = form.pencil_at(speeds[part])
            damping = damping + speeds[part, None, None] * G
            stiffness = _at_speeds(stiffness, part)
            # every speed's estimate in one batched product; the polish only where a root needs it
            bound[part] = _eigensolve.pencil_round_off(values[v, part], shapes[v, part], form.matrices.M,
                                                       damping, stiffness, branches=branches)
            inexact = (bound[part] > _eigensolve.POLISH_LEVEL) & (values[v, part] != 0)     # real roots too
            needed |= bool((inexact & (values[v, part].imag > 0)).any())
            for j in np.flatnonzero(inexact.any(axis=-1)):
                i = part.start + j
                bound[i] = _eigensolve.refined_pairs(values[v, i], shapes[v, i], form.matrices.M, damping[j],
                                                     stiffness[j], bound[i], stack.whirl, v, branches=branches,
                                                     whirl=None if noise is None else noise[v, i])
        name = stack.models[v].name if len(stack.forms) > 1 else ""
        # the columns are the table's mode labels; those not oscillating there are no mode of it
        _eigensolve.warn_of_inexact_roots(speeds, bound, name, stacklevel=4, oscillating=is_oscillating(values[v]),
                                          values=values[v])
    stack.inexact = needed              # the critical speeds are then refined on polished roots too
    return needed


#: dense (n, n) arrays of one speed that :func:`_refine_inexact`'s bearing evaluation holds at once
#: (pencil_at's bearing K and C and their sums with the constant parts, the damping with ``Omega G``;
#: the estimate's |D|, |K| and its (n, m) products with the shapes)
_REFINE_ARRAYS = 10


def _at_speeds(matrices, part):
    """``matrices`` (P, n, n), or one constant (n, n), as (P, n, n) for the speeds of ``part``."""
    return np.broadcast_to(matrices, (part.stop - part.start,) + matrices.shape[-2:])


#: memory of the interpreter and the package's imports [bytes]
_BASE_BYTES = 256 * 2**20
#: memory per crossing of the critical speeds (its bracket, its refined row, the table's row
#: with its strings, the copies made while they are sorted) [bytes]
_CROSSING_BYTES = 4096


def memory_estimate(n_dof, n_states, n_speeds, variants=1, critical=True, crossings=0, roots=None,
                    sparse=False) -> float:
    """Peak memory of :func:`campbell_many` [bytes], estimated from the sizes alone.

    The sweep keeps one set of unit shapes (``V N m n`` complex numbers, ``m = n_states -
    n_states // 2`` roots per speed; their mass-weighted rows, which tracking and the critical
    speeds read, are computed a part of at most ``_batches._PART_BYTES`` at a time,
    :class:`._weighted_rows.WeightedRows`) beside its eigen-solver's work (a
    part of the speeds of ``_batches.CHUNK_BYTES``, at least one speed of about 72 bytes per
    entry of the state matrix); the critical speeds' refinement adds its parts' work and the
    brackets swept again (``_SUB_SPEEDS`` speeds' shapes, twice, at each of ``_SUB_DEPTH``
    levels, with one speed's eigen-solution), and ``_CROSSING_BYTES`` per crossing; the
    model's own matrices (the state matrix's two parts, mass, damping, gyroscopic, stiffness,
    whirl forms and their copies: about 24 real n x n matrices) are held throughout.

    Parameters
    ----------
    n_dof, n_states : int
        Coordinates and states of the model.
    n_speeds : int
    variants : int
        Models solved together (a study's chunk).
    critical : bool
        Critical speeds are refined.
    crossings : int
        Crossings to refine, where known (after the sweep).
    roots : int, optional
        Roots kept at each speed where fewer than every root: a sweep of the lowest modes
        (``campbell(modes=N)`` or ``max_frequency``), whose brackets are swept again by the
        lowest modes' route (no eigen-solution of the state matrices) where the model has
        ``_lowest.DENSE_BELOW`` coordinates or more.
    sparse : bool
        With ``roots``: a large model whose matrices are kept sparse (``assembly.SPARSE_DOF``),
        whose crossings are refined on its sparse pencils (a part of ``_batches.CHUNK_BYTES`` at a
        time) beside the lowest modes' basis (every undamped mode, one n x n array), never its
        dense matrices.

    Returns
    -------
    float
    """
    from ._lowest import DENSE_BELOW

    lowest = roots is not None and n_dof >= DENSE_BELOW
    sparse = sparse and lowest
    roots = n_states - n_states // 2 if roots is None else roots
    per_speed = variants * roots * n_dof * 16.0                        # one set of shapes at one speed
    one_speed = 72.0 * variants * n_states ** 2                        # the eigen-solver's work for one speed
    solver = max(min(_batches.CHUNK_BYTES, n_speeds * one_speed), one_speed)
    if sparse:                            # the lowest modes' basis: eigh of K_0 and M, its work and modes
        solver = 4 * 8.0 * variants * n_dof ** 2
    small = 16.0 * 12 * variants * n_speeds * roots                    # eigenvalues and their quantities
    work = solver + per_speed * n_speeds                                # while solving: the shapes so far
    # the shapes, and their weighted rows a part at a time (the whole where it is one part)
    after = per_speed * n_speeds + min(per_speed * n_speeds, _batches._PART_BYTES)
    if critical:
        refine = _batches.CHUNK_BYTES if sparse else max(_batches.CHUNK_BYTES, 64.0 * n_dof ** 2)
        sub = _SUB_DEPTH * 2 * _SUB_SPEEDS * roots * n_dof * 16.0 + (0.0 if lowest else one_speed / variants)
        after += max(refine, sub) + _CROSSING_BYTES * crossings
    matrices = (8.0 if sparse else 24 * 8.0) * variants * n_dof ** 2
    return _BASE_BYTES + matrices + small + max(work, after)


#: estimates below this are not checked (measuring the memory at hand costs more than a small
#: model's whole sweep; with less than this at hand the estimate's upper bounds mislead) [bytes]
_CHECKED_BYTES = 2**30


def _sizes(stack):
    return stack.n_dof, stack.forms[0].n_states


def _refuse_what_cannot_fit(stack, n_speeds, critical):
    """Refuse a sweep whose arrays would not fit (see :func:`memory_estimate`), naming the
    number of speeds that would."""
    _refuse_sizes_that_cannot_fit(*_sizes(stack), n_speeds, len(stack), critical, _source(stack))


def _source(stack) -> str:
    """``'MODEL: '``, the file of the stack's first model, that a refusal starts with ('' without one)."""
    source = getattr(stack.models[0], "source", None)
    return f"{source}: " if source else ""


def _refuse_sizes_that_cannot_fit(n_dof, n_states, n_speeds, variants, critical, source="", what="a Campbell sweep"):
    """:func:`_refuse_what_cannot_fit` from the sizes alone (``n_dof`` coordinates, ``n_states``
    states, ``variants`` models); ``source`` (``'MODEL: '``) starts the message, ``what`` names
    the sweep (``stability`` keeps the same arrays)."""
    needed = memory_estimate(n_dof, n_states, n_speeds, variants, critical)
    if needed < _CHECKED_BYTES:
        return
    fixed = memory_estimate(n_dof, n_states, 0, variants, critical)
    per_speed = memory_estimate(n_dof, n_states, 1, variants, critical) - fixed
    from .._limits import available_memory

    fitting = int(max(0.0, available_memory() - fixed) // max(per_speed, 1.0))
    advice = (f"use fewer speeds (about {fitting:,} fit)" if fitting >= 2 else
              "the model is too large for this machine's memory at any number of speeds")
    if critical:
        advice += ", or leave out the critical speeds (campbell --no-critical, critical=False)"
    if variants == 1:
        advice += f", or {_LOWEST_ADVICE}"
    problem = memory_problem(needed, f"{source}{what} of {n_dof:,} coordinates at {n_speeds:,} speeds"
                             + (f" of {variants} models" if variants > 1 else ""), advice)
    if problem:
        raise InputError(problem)


#: the way to a sweep of a large single model that fits: only the modes asked for
_LOWEST_ADVICE = ("ask for the lowest modes only (--lowest N or --max-frequency HZ; modes=N or max_frequency=F), "
                  "whose memory grows with the modes asked for")


def _refuse_crossings(stack, n_speeds, crossings, roots=None):
    """Refuse, before refining them, crossings that would not fit beside the sweep's arrays
    (``roots`` kept per speed: a sweep of the lowest modes, see :func:`memory_estimate`)."""
    n_dof, n_states = _sizes(stack)
    needed = memory_estimate(n_dof, n_states, n_speeds, len(stack), True, crossings, roots,
                             sparse=stack.sparse_constant is not None)
    if needed < _CHECKED_BYTES:
        return
    advice = "ask for fewer excitation orders (--orders) or a narrower speed range"
    if roots is None and len(stack) == 1:
        advice += f", {_LOWEST_ADVICE},"
    problem = memory_problem(needed, f"{_source(stack)}refining the {crossings:,} critical speeds found over {n_speeds:,} speeds "
                             f"of {n_dof:,} coordinates", f"{advice} or leave out the critical speeds "
                             "(campbell --no-critical, critical=False)")
    if problem:
        raise InputError(problem)


def critical_speeds(model, speeds, orders=(1,), progress=False, modes=None, max_frequency=None) -> CriticalSpeeds:
    """Critical speeds: tracked frequencies crossing every source's excitation orders.

    Each crossing is refined by root-finding on the eigenproblem itself, not
    taken from the nearest grid point.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Search grid [rad/s]; crossings between grid points are found when the
        grid is fine enough to bracket them.
    orders : sequence of float
        Orders of every source (rotor spins and gear meshes).
    modes, max_frequency : optional
        The crossings of the lowest ``modes`` modes at each speed, or of the modes below
        ``max_frequency`` [Hz] (the crossings at frequencies up to it); see :func:`campbell`.

    Returns
    -------
    CriticalSpeeds
    """
    return campbell(model, speeds, orders=orders, progress=progress, modes=modes, max_frequency=max_frequency).critical


def _check_speeds(speeds) -> np.ndarray:
    return _arguments.speeds(speeds)
