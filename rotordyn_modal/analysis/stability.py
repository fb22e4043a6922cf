"""Stability over speed, threshold speeds, and stability maps over a model parameter."""

from __future__ import annotations

import functools
import inspect
from dataclasses import dataclass

import numpy as np
import scipy.linalg.lapack
from scipy.optimize import brentq

from .._progress import phase
from ..errors import InputError, ModelWarning
from . import _eigensolve, _roots, _whirl
from ._stack import Stack
from .campbell import (_arguments_frequency, _arguments_modes, _campbell_lowest, _check_speeds, _refine_inexact,
                       _lowest_whirl_round_off, _progress, lowest_stack, solve_sweeps, stack_root_count)
from .modal import _constant_round_off, is_oscillating, modal, modal_quantities
from .mode_numbers import numbers_at_speed

__all__ = ["StabilityResult", "StabilityMap", "stability", "stability_map", "threshold_speeds", "unstable_intervals"]


def unstable_intervals(starts_unstable: bool, thresholds, onsets) -> list:
    """The intervals of speed where a sweep is unstable, from whether it is at its first speed and
    its thresholds [rad/s] with their kinds (``onsets``: True where stability is lost, False where
    regained): a list of (start, stop) [rad/s], start NaN when the sweep starts unstable, stop NaN
    when it stays unstable to its end (:attr:`StabilityResult.unstable_intervals`)."""
    intervals, start, open_ = [], float("nan"), bool(starts_unstable)
    for speed, onset in sorted(zip(np.asarray(thresholds).tolist(), np.asarray(onsets).tolist())):
        if onset and not open_:
            start, open_ = speed, True
        elif not onset and open_:
            intervals.append((start, speed))
            open_ = False
    if open_:
        intervals.append((start, float("nan")))
    return intervals


@dataclass(frozen=True)
class StabilityResult:
    """Real parts and damping of the tracked modes over speed.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    eigenvalues : ndarray, shape (N, n_modes), complex [1/s]; tracked columns
    real_parts, damping_ratios, log_decrements, frequencies_hz : ndarray, shape (N, n_modes)
    whirl : ndarray of str, shape (N, n_modes)
    modes : ndarray of int, shape (n_modes,)
    thresholds : ndarray, shape (n_thresholds,) [rad/s]
        Speeds where the largest real part crosses zero (refined by root-finding).
    threshold_modes : ndarray of int
        Mode whose real part crosses there.
    threshold_onsets : ndarray of bool
        True where stability is lost with increasing speed.
    roundoff : ndarray, shape (N,) [1/s], optional
        Round-off of the real parts at each speed (see :func:`roundoff_levels`): real parts
        within it of zero count as zero (marginal).
    threshold_frequencies_hz : ndarray, shape (n_thresholds,) [Hz], optional
        Frequency of the root that crosses, at the threshold.
    threshold_whirl : ndarray of str, shape (n_thresholds,), optional
        Its whirl there.
    threshold_modes_at_speed : ndarray of int, shape (n_thresholds,), optional
        The number ``modes --speed THRESHOLD`` gives it (0: not a mode there, a real or
        overdamped root); the tracked label is ``threshold_modes``.
    lowest : int, optional
        Set by ``stability(..., modes=N)``: only the N lowest-frequency modes of each speed were
        solved and judged (columns, thresholds, least damped); the modes above them, and real
        roots, are not checked. None: every root.
    max_frequency_hz : float, optional
        Set by ``stability(..., max_frequency=F)`` [Hz]: only the modes of damped natural
        frequency at most F at each speed were solved and judged (NaN columns where a mode lies
        above it); the modes above F, and real roots, are not checked. None: no limit.
    """

    speeds: np.ndarray
    eigenvalues: np.ndarray
    real_parts: np.ndarray
    damping_ratios: np.ndarray
    log_decrements: np.ndarray
    frequencies_hz: np.ndarray
    whirl: np.ndarray
    modes: np.ndarray
    thresholds: np.ndarray
    threshold_modes: np.ndarray
    threshold_onsets: np.ndarray
    roundoff: np.ndarray | None = None
    threshold_frequencies_hz: np.ndarray | None = None
    threshold_whirl: np.ndarray | None = None
    threshold_modes_at_speed: np.ndarray | None = None
    lowest: int | None = None
    max_frequency_hz: float | None = None

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    @property
    def significant_real_parts(self) -> np.ndarray:
        """(N, n_modes) [1/s]: the real parts, 0 where within round-off of zero and -inf for
        rigid-body roots (lam = 0 to round-off): what stability is judged on."""
        return _significant_real_parts(self.eigenvalues, roundoff=self.roundoff)

    @property
    def largest_real_parts(self) -> np.ndarray:
        """(N,) [1/s]: the largest real part at each speed, 0 where it is within round-off
        of zero (rigid-body roots left out; -inf where no root is judged: none below
        ``max_frequency_hz``)."""
        return self.significant_real_parts.max(axis=1, initial=-np.inf)

    @property
    def stable(self) -> np.ndarray:
        """(N,) bool: every real part < 0 at that speed (beyond round-off)."""
        return self.largest_real_parts < 0

    @property
    def unstable(self) -> np.ndarray:
        """(N,) bool: some real part > 0 at that speed (beyond round-off)."""
        return self.largest_real_parts > 0

    @property
    def modes_at_speed(self) -> np.ndarray:
        """(N, n_modes) int: the number ``modes --speed`` gives each tracked mode at each speed
        (0 where it is not a mode there); see :mod:`.mode_numbers`."""
        # a repeated root's members by their whirl about +spin_axis, backward first, as modes lists them
        turning = {"forward": 1.0, "backward": -1.0}
        about_axis = np.vectorize(lambda w: turning.get(w, 0.0), otypes=[float])(self.whirl) if self.whirl.size else None
        if about_axis is not None:
            about_axis = _whirl.about_spin_axis(about_axis, self.speeds)
        return numbers_at_speed(self.eigenvalues, about_axis)

    @property
    def threshold_speed(self) -> float:
        """Lowest non-negative speed where stability is lost [rad/s] (nan if none)."""
        onsets = self.thresholds[self.threshold_onsets & (self.thresholds >= 0)]
        return float(onsets.min()) if len(onsets) else float("nan")

    @property
    def unstable_intervals(self) -> list:
        """Every interval of speeds where the machine is unstable, in increasing speed.

        Returns
        -------
        list of (start, stop) [rad/s]
            ``start`` is the threshold where stability is lost, or nan when the sweep starts
            unstable; ``stop`` where it is regained, or nan when it stays unstable to the
            sweep's end.
        """
        return unstable_intervals(bool(self.unstable[0]), self.thresholds, self.threshold_onsets)

    def least_damped(self):
        """The least damped mode over the sweep: the tracked mode and speed of the smallest log
        decrement among the roots that are modes (0 where the real part is zero to round-off).

        Returns
        -------
        (mode, k) : (int, int)
            Tracked label and index of the speed; None when no root is a mode at any speed.
        """
        log_dec = np.where(self.significant_real_parts == 0, 0.0, self.log_decrements)
        log_dec = np.where(is_oscillating(self.eigenvalues), log_dec, np.inf)
        if not np.isfinite(log_dec).any():
            return None
        k, column = np.unravel_index(int(np.argmin(log_dec)), log_dec.shape)
        return int(self.modes[column]), int(k)

    def to_dataframe(self):
        """Long table ``speed_rpm, value, mode, real_part, damping_ratio, log_decrement,
        frequency_hz, whirl, mode_at_speed`` (``mode`` the tracked label, ``mode_at_speed`` the
        number ``modes --speed`` gives that root, empty where it is not a mode). With
        ``max_frequency_hz``, a mode's rows at the speeds where it lies above it are left out."""
        import pandas as pd

        count, n = self.eigenvalues.shape
        at_speed = self.modes_at_speed.ravel()
        asked = ~np.isnan(self.eigenvalues.ravel())         # NaN: above max_frequency_hz there
        table = pd.DataFrame({
            "speed_rpm": np.repeat(self.speeds_rpm, n), "value": "",
            "mode": np.tile(self.modes, count), "real_part": self.real_parts.ravel(),
            "damping_ratio": self.damping_ratios.ravel(), "log_decrement": self.log_decrements.ravel(),
            "frequency_hz": self.frequencies_hz.ravel(), "whirl": self.whirl.ravel(),
            "mode_at_speed": pd.array(np.where(at_speed > 0, at_speed, None), dtype="Int64"),
        })
        if not asked.all():
            table = table[asked].reset_index(drop=True)
        # one number a column where it is constant: pandas compares the attrs of tables it concatenates
        table.attrs["round_off"] = _constant_round_off(self.round_off_rows())
        return table

    def round_off_rows(self) -> dict:
        """What round-off can move the real parts, damping ratios and log decrements of
        :meth:`to_dataframe` by, row by row (:meth:`_round_off_columns`).

        Returns
        -------
        dict of str -> ndarray, shape (rows of ``to_dataframe()``,)
            ``real_part`` [1/s], ``damping_ratio``, ``log_decrement`` [-]. The terminal prints
            values within it as 0 (``cli._common.print_table``); the table's ``attrs['round_off']``
            keeps only the columns where it is one number for every row.
        """
        asked = ~np.isnan(self.eigenvalues.ravel())         # the rows to_dataframe keeps
        return {key: value[asked] for key, value in self._round_off_columns().items()}

    def _round_off_columns(self) -> dict:
        """What round-off can move the real parts, damping ratios and log decrements by, row by
        row: the tolerance the stability verdict uses (``roundoff``, or ``1e-10 |lam|``); the
        terminal prints those within it as 0 (``cli._common.print_table``)."""
        lam = self.eigenvalues.ravel()
        tolerance = _MARGINAL_TOLERANCE * np.abs(lam)
        if self.roundoff is not None:
            tolerance = np.maximum(tolerance, np.repeat(self.roundoff, self.eigenvalues.shape[1]))
        with np.errstate(divide="ignore", invalid="ignore"):
            return {"real_part": tolerance, "damping_ratio": tolerance / np.abs(lam),
                    "log_decrement": 2 * np.pi * tolerance / lam.imag}

    def plot(self, **kwargs):
        """Real parts and log decrements over speed; see :func:`rotordyn_modal.plotting.plot_stability`."""
        from ..plotting import plot_stability

        return plot_stability(self, **kwargs)


@dataclass(frozen=True)
class StabilityMap:
    """Stability over speed and one model parameter.

    Attributes
    ----------
    key : str
        Dotted key of the parameter.
    mode_of_variation : str
        'values' (the key set to each value) or 'scale' (the key multiplied).
    values : ndarray, shape (V,)
    speeds : ndarray, shape (N,) [rad/s]
    results : tuple of StabilityResult, one per value
    """

    key: str
    mode_of_variation: str
    values: np.ndarray
    speeds: np.ndarray
    results: tuple

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    @property
    def max_real_parts(self) -> np.ndarray:
        """(V, N): largest real part over the modes [1/s]."""
        return np.array([r.largest_real_parts for r in self.results])

    @property
    def min_damping_ratios(self) -> np.ndarray:
        """(V, N): smallest damping ratio over the modes."""
        return np.array([np.nanmin(r.damping_ratios, axis=1) for r in self.results])

    @property
    def threshold_speeds(self) -> np.ndarray:
        """(V,): lowest non-negative onset speed for each value [rad/s] (nan if stable)."""
        return np.array([r.threshold_speed for r in self.results])

    def to_dataframe(self):
        import pandas as pd

        tables = []
        for value, result in zip(self.values, self.results):
            table = result.to_dataframe()
            table["value"] = value
            tables.append(table)
        out = pd.concat(tables, ignore_index=True)
        out.attrs["round_off"] = _constant_round_off(self.round_off_rows())
        return out

    def round_off_rows(self) -> dict:
        """Every value's :meth:`StabilityResult.round_off_rows`, one after the other, as the rows
        of :meth:`to_dataframe`."""
        rows = [result.round_off_rows() for result in self.results]
        return {column: np.concatenate([each[column] for each in rows]) for column in rows[0]}

    def plot(self, **kwargs):
        """Map with the stability boundary; see :func:`rotordyn_modal.plotting.plot_stability_map`."""
        from ..plotting import plot_stability_map

        return plot_stability_map(self, **kwargs)


def stability(model, speeds, vary: str | None = None, values=None, scale=None, progress=False, modes=None,
              max_frequency=None):
    """Stability over speed, or a map over speed and one parameter.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,) [rad/s], increasing
    vary : str, optional
        Dotted key of a model parameter (e.g. ``"suspensions.mount-FL.damping"``);
        with it, give ``values`` (set) or ``scale`` (multiply) and get a map.
    values, scale : array_like, shape (V,), optional
    progress : bool
    modes : int, optional
        Only the ``modes`` lowest-frequency oscillating roots of each speed (of each value of a
        map), each the full model's root to round-off, as ``campbell(modes=N)`` finds them
        (``docs/theory.md``, "The lowest modes only"): the columns are those roots, and the
        thresholds are where the largest real part *among them* crosses zero, refined with
        Brent's method on the same N lowest roots. **Modes above the N lowest are not checked**,
        nor are real roots (a real root crossing zero, a divergence, is outside this route):
        a threshold of a higher mode, or of a real root, is not found. ``result.lowest`` is N.
        Default: every root of every speed.
    max_frequency : float, optional
        Only the oscillating roots of damped natural frequency ``Im lam / 2 pi`` at most this [Hz]
        at each speed (with ``modes``, the lowest ``modes`` of them), each the full model's root to
        round-off, as ``campbell(max_frequency=F)`` finds them (``docs/theory.md``, "The modes
        below a frequency"): a column for each tracked mode below F at some speed, NaN where it
        lies above; the thresholds are where the largest real part *among the roots below F*
        crosses zero, refined with Brent's method on those roots. **Modes above F are not
        checked**, nor are real roots. ``result.max_frequency_hz`` is F. Default: no limit.

    Returns
    -------
    StabilityResult, or StabilityMap when ``vary`` is given
    """
    if max_frequency is not None:
        max_frequency = _arguments_frequency(max_frequency)
    if modes is not None:
        modes = _arguments_modes(modes)
    if vary is not None:
        return stability_map(model, speeds, vary, values=values, scale=scale, progress=progress, modes=modes,
                             max_frequency=max_frequency)
    if values is not None or scale is not None:
        raise InputError("values/scale given without a parameter to vary (vary=KEY)")
    speeds = _check_speeds(speeds)
    if modes is not None or max_frequency is not None:
        stack = lowest_stack(model)
        if modes is not None and modes >= stack_root_count(stack):
            modes = None                        # N at least every root: every root, as campbell
        if modes is not None or max_frequency is not None:
            return _stability_lowest(stack, speeds, modes, max_frequency)
    stack = Stack([model])                  # one linear form for the sweep, the polish and the thresholds
    form = stack.forms[0]
    values, all_shapes, _, noise = solve_sweeps(stack, speeds, progress, whirl_noise=True)
    eigenvalues, shapes = values[0], all_shapes[0]
    with phase(progress, "whirl and round-off"):
        # the roots double precision leaves inexact polished, as campbell's (docs/theory.md, "Close roots")
        inexact = _refine_inexact(stack, speeds, values, all_shapes, noise)
        ratios = np.where(is_oscillating(eigenvalues),
                          _whirl.whirl_ratios(shapes, _whirl.whirl_forms(model), speeds), 0.0)
        freq, zeta, log_dec = modal_quantities(eigenvalues)
        roundoff = roundoff_levels(form, speeds)
    with phase(progress, _THRESHOLDS) as bar:          # each step of the refinement: a whole eigen-solution
        thresholds, threshold_modes, onsets = threshold_speeds(
            form, speeds, eigenvalues, roundoff,
            largest=_counted(functools.partial(_polished_largest_real_part, stack) if inexact
                             else functools.partial(_largest_real_part, form), bar))
    with phase(progress, "modes at the thresholds"):   # modal's solve lets the clock run (_eigensolve.eig)
        crossing = _crossing_roots(model, speeds, eigenvalues, thresholds, threshold_modes)
    return StabilityResult(
        speeds=speeds, eigenvalues=eigenvalues, real_parts=eigenvalues.real, damping_ratios=zeta,
        log_decrements=log_dec, frequencies_hz=freq, whirl=_whirl.whirl_labels(ratios, noise[0]),
        modes=np.arange(1, eigenvalues.shape[1] + 1), thresholds=thresholds,
        threshold_modes=threshold_modes, threshold_onsets=onsets, roundoff=roundoff, **crossing,
    )


#: the line shown while the thresholds are refined (:func:`.._progress.phase`)
_THRESHOLDS = "stability thresholds"


def _counted(largest, bar):
    """``largest`` (see :func:`threshold_speeds`) that names on ``bar`` (a :func:`.._progress.phase`
    line, or None) how many eigen-solutions the refinement has made."""
    if bar is None:
        return largest
    done = [0]

    def counted(speed, clip=True, near=None):
        value = largest(speed, clip, near)
        done[0] += 1
        bar.set_description(f"{_THRESHOLDS}: {done[0]} eigen-solution{'s' if done[0] > 1 else ''}", refresh=False)
        return value

    return counted


def _stability_lowest(stack, speeds, count, limit_hz=None) -> StabilityResult:
    """:func:`stability` of the ``count`` lowest modes of each speed (see its ``modes``), or of
    those below ``limit_hz`` [Hz] (see its ``max_frequency``; the lowest ``count`` of them when
    both are given), of the model of a one-model stack (:func:`.campbell.lowest_stack`), at
    checked speeds: the tracked roots of ``campbell(modes=count, max_frequency=limit_hz)``, the
    thresholds of their largest real part refined on the same roots of each trial speed, judged
    against the full state matrix's round-off (:func:`roundoff_levels`) as a full sweep's are.
    The stack's state form serves all three."""
    model = stack.models[0]
    limit = None if limit_hz is None else 2 * np.pi * limit_hz
    sweep = _campbell_lowest(stack, speeds, (1.0,), False, count, limit)
    form = stack.forms[0]
    roundoff = roundoff_levels(form, speeds)
    lowest = _LowestRoots(stack, count, limit)

    def largest(speed, clip=True, near=None):
        roots, _ = lowest.at(speed)
        roots = roots[np.isfinite(roots)]       # fewer roots than asked (a model of few coordinates)
        if near is not None:
            return _nearest_real_part(roots, near)
        # -inf: no root below max_frequency at that speed (nothing judged there)
        return float(_significant_real_parts(roots, clip, roundoff_levels(form, [speed]) if clip else None)
                     .max(initial=-np.inf))

    thresholds, threshold_modes, onsets = threshold_speeds(form, speeds, sweep.eigenvalues, roundoff, largest)
    crossing = _crossing_roots(model, speeds, sweep.eigenvalues, thresholds, threshold_modes, lowest.crossing)
    return StabilityResult(
        speeds=speeds, eigenvalues=sweep.eigenvalues, real_parts=sweep.eigenvalues.real,
        damping_ratios=sweep.damping_ratios, log_decrements=sweep.log_decrements,
        frequencies_hz=sweep.frequencies_hz, whirl=sweep.whirl, modes=sweep.modes, thresholds=thresholds,
        threshold_modes=threshold_modes, threshold_onsets=onsets, roundoff=roundoff, lowest=count,
        max_frequency_hz=limit_hz, **crossing,
    )


class _LowestRoots:
    """The ``count`` lowest oscillating roots of one model at one speed at a time (a threshold's
    trial speeds), as ``campbell(modes=count)`` finds them at its speeds; or those of frequency
    ``Im lam`` up to ``limit`` (the lowest ``count`` of them, if given), as
    ``campbell(max_frequency=...)`` finds them.

    Parameters
    ----------
    stack : Stack
        Of the one model.
    count : int or None
        None: every root below ``limit``.
    limit : float, optional
        Highest frequency ``Im lam`` [rad/s].
    """

    def __init__(self, stack, count, limit=None):
        self.stack, self.count, self.limit = stack, count, limit
        self.refined = None

    def at(self, speed):
        """Roots (k,) complex [1/s], by frequency (nan where the model has fewer than ``count``), and
        unit shapes (k, n) at ``speed`` [rad/s]; ``k`` is ``count``, or with ``limit`` the number of
        roots below it there (0 or more)."""
        from . import _batches, _lowest, _lowest_branches

        speeds = np.array([float(speed)])
        # BLAS's own threads only wait for a core on a shared machine (as in campbell(modes=N))
        with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
            if self.limit is not None:
                below = _lowest_branches.roots_below if self.stack.branch_times.shape[1] else _lowest.roots_below
                values, shapes, wanted, whole = below(self.stack, speeds, self.limit, self.count)
                self.refined = ~np.asarray(whole, dtype=bool)
                return values[0][wanted[0]], shapes[0][wanted[0]]
            if self.stack.branch_times.shape[1]:     # Maxwell branches: the rational pencil, as campbell does
                values, shapes, whole = _lowest_branches.lowest_roots(self.stack, speeds, self.count)
            else:
                values, shapes, whole = _lowest.lowest_roots(self.stack, speeds, self.count)
        self.refined = ~np.asarray(whole, dtype=bool)      # the last speed's (its whirl round-off, crossing)
        return values[0], shapes[0]

    def crossing(self, speed, guess):
        """Frequency [Hz], whirl label and ``modes --speed`` number of the root nearest ``guess``
        (nan, 'none' and 0 where no root is below the limit there)."""
        values, shapes = self.at(speed)
        if not np.isfinite(values).any():
            return float("nan"), "none", 0
        nearest = _crossing_index(values, guess)
        ratio = self.stack.whirl_ratios(shapes[None, nearest:nearest + 1], np.zeros(1, int), np.array([speed]))
        ratio = np.where(is_oscillating(values[nearest]), ratio.reshape(1), 0.0)
        noise = _lowest_whirl_round_off(self.stack, np.array([speed]), values[None], self.refined)    # as the sweep's labels
        noise = None if noise is None else noise[0, nearest:nearest + 1]
        # the lowest roots of a speed are its lowest modes: their order is modes' own numbering
        return (float(values[nearest].imag / (2 * np.pi)), str(_whirl.whirl_labels(ratio, noise)[0]),
                int(numbers_at_speed(values)[nearest]))


def _crossing_roots(model, speeds, eigenvalues, thresholds, threshold_modes, root_at=None) -> dict:
    """Frequency, whirl and ``modes`` number of the root that crosses at each threshold:
    ``root_at(speed, guess)`` (default :func:`_modal_root_at`: of :func:`.modal.modal` at the
    threshold) of the tracked mode's eigenvalue interpolated linearly between the grid speeds
    around the threshold (the one end's where the other is NaN: above ``max_frequency``)."""
    root_at = root_at or functools.partial(_modal_root_at, model)
    crossing = []
    for speed, mode in zip(thresholds, threshold_modes):
        k = int(np.clip(np.searchsorted(speeds, speed) - 1, 0, len(speeds) - 2))
        t = (speed - speeds[k]) / (speeds[k + 1] - speeds[k])
        ends = eigenvalues[k:k + 2, mode - 1]
        guess = (1 - t) * ends[0] + t * ends[1] if np.isfinite(ends).all() else ends[np.isfinite(ends)][0]
        crossing.append(root_at(speed, guess))
    frequencies, whirl, numbers = zip(*crossing) if crossing else ((), (), ())
    return {"threshold_frequencies_hz": np.array(frequencies, dtype=float),
            "threshold_whirl": np.array(whirl, dtype=str), "threshold_modes_at_speed": np.array(numbers, dtype=int)}


#: a root whose real part is within this fraction of its size is on the imaginary axis at a threshold
_ON_THE_AXIS = 1e-6


def _crossing_index(values, guess) -> int:
    """The index of the root of ``values`` (k,) complex [1/s], solved at a threshold, that crosses
    there: of the roots on the imaginary axis (real part within 1e-6 of their size; a zero root,
    rigid-body, is none) the one nearest ``guess``, else the root nearest ``guess``. The guess
    alone (the tracked mode interpolated between grid speeds) named another root on a coarse grid:
    ``unstable_cross_coupled.toml --speeds 0:1e5:3`` said "10.054 Hz; mode 4" for the 6.3662 Hz
    root (mode 2) that crosses at 10886 rpm."""
    values = np.asarray(values)
    finite = np.isfinite(values)
    on_axis = finite & (values != 0) & (np.abs(values.real) <= _ON_THE_AXIS * np.abs(values))
    pool = on_axis if on_axis.any() else finite
    return int(np.argmin(np.where(pool, np.abs(values - guess), np.inf)))


def _modal_root_at(model, speed, guess):
    """Frequency [Hz], whirl label and ``modes --speed`` number (0: not a mode) of the root of
    :func:`.modal.modal` at ``speed`` [rad/s] nearest ``guess``."""
    roots = modal(model, speed)
    nearest = _crossing_index(roots.eigenvalues, guess)
    # modes' own numbering: its modes in its order
    number = int(roots.oscillatory[:nearest + 1].sum()) if roots.oscillatory[nearest] else 0
    return float(roots.frequencies_hz[nearest]), str(roots.whirl[nearest]), number


def stability_map(model, speeds, key: str, values=None, scale=None, progress=False, modes=None,
                  max_frequency=None) -> StabilityMap:
    """Stability over speed for each value (or scale factor) of one model parameter.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,) [rad/s]
    key : str
        Dotted key, e.g. ``"suspensions.mount-FL.stiffness[0][1]"``.
    values : array_like, shape (V,), optional
        Values to set the key to (a scalar key or one element).
    scale : array_like, shape (V,), optional
        Factors to multiply the key (a whole array if it is one) by.
    modes : int, optional
        Only the ``modes`` lowest modes of each speed and value (see :func:`stability`; the modes
        above them and real roots are not checked).
    max_frequency : float, optional
        Only the modes below this frequency [Hz] (see :func:`stability`; the modes above it and
        real roots are not checked).

    Returns
    -------
    StabilityMap
    """
    if (values is None) == (scale is None):
        raise InputError(f"stability map over {key!r}: give exactly one of values or scale")
    grid = np.atleast_1d(np.asarray(values if values is not None else scale, dtype=float))
    if grid.ndim != 1 or len(grid) == 0 or not np.all(np.isfinite(grid)):
        raise InputError(f"stability map over {key!r}: expected a non-empty list of finite numbers")
    model.get(key)  # refuse an unknown key before any work
    results = []
    for value in _progress(list(grid), progress, f"map over {key}"):
        variant = _map_variant(model, key, value, scaled=values is None)
        results.append(stability(variant, speeds, modes=modes, max_frequency=max_frequency))
    return StabilityMap(key=key, mode_of_variation="values" if values is not None else "scale",
                        values=grid, speeds=np.asarray(results[0].speeds), results=tuple(results))


def _map_variant(model, key: str, value: float, scaled: bool):
    """The model with ``key`` set to ``value`` (or multiplied by it, ``scaled``); a refusal says
    that the value refused is the map's, not the file's: ``[bearings.DE] viscosity = 0.0 (the map's
    scale 0 x the file's 0.02)`` (it read as if the model file held 0)."""
    import re

    from ..errors import ModelError
    from .._arguments import _shown

    try:
        return model.scaled({key: value}) if scaled else model.with_values({key: value})
    except ModelError as error:
        how = (f"the map's scale {value:g} x the file's {_shown(model.get(key))}" if scaled else
               f"a value of the map; the file's is {_shown(model.get(key))}")
        field = re.sub(r"\[.*$", "", key.rpartition(".")[2])
        if not error.where.endswith(f" {field}"):       # another key refuses the change it makes
            how = f"with {key} {'scaled by' if scaled else 'set to'} {value:g}, {how}"
        raise InputError(f"{error.source}: {error.where} = {_shown(error.value)} ({how}): "
                         f"expected {error.expected}") from None


def threshold_speeds(form, speeds, eigenvalues, roundoff=None, largest=None):
    """Speeds where the largest real part of the eigenvalues crosses zero.

    Real parts within round-off of zero count as zero (marginal, as in an undamped machine):
    within ``1e-10`` of the root's own ``|lam|`` or within :func:`roundoff_levels`, the error
    bound of a computed eigenvalue. Only a change between stable or marginal and unstable is a
    threshold. Where the root that crosses has a real part beyond round-off on both grid speeds
    around the change (negative on the one, positive on the other), the threshold is the zero of
    that root's own real part (:func:`_crossing_zero`), whatever the other roots' round-off.
    Otherwise, a sign change beyond round-off on both sides (from the last speed below round-off
    through marginal speeds, if any, to the first above) is refined with Brent's method on the
    eigenproblem; a change from (or to) marginal throughout is located by bisection of the
    predicate "unstable beyond round-off". No root crossing beyond round-off: no threshold.

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    eigenvalues : ndarray, shape (N, n), tracked
    roundoff : ndarray, shape (N,) [1/s], optional
        :func:`roundoff_levels` (computed when not given).
    largest : callable, optional
        ``largest(speed, clip=True, near=None)``: the largest real part of the roots judged at one
        speed [1/s] (clipped: as :func:`_significant_real_parts`), for the refinement; with
        ``near`` (complex [1/s]), the unclipped real part of the root nearest it instead. Default:
        of every root of the state matrix (``stability(modes=N)`` gives its N lowest roots).

    Returns
    -------
    speeds : ndarray [rad/s]; modes : ndarray of int (1-based); onsets : ndarray of bool
    """
    if roundoff is None:
        roundoff = roundoff_levels(form, speeds)
    if largest is None:
        def largest(speed, clip=True, near=None):
            return _largest_real_part(form, speed, clip, near)
    real_part = largest
    # a caller's own ``largest(speed, clip)`` (before ``near``): the rules below only
    by_root = "near" in inspect.signature(real_part).parameters
    significant = _significant_real_parts(eigenvalues, roundoff=roundoff)
    largest = significant.max(axis=1, initial=-np.inf)
    unstable = largest > 0
    found, modes, onsets = [], [], []
    for k in np.nonzero(unstable[:-1] != unstable[1:])[0]:
        side = k + 1 if unstable[k + 1] else k  # the speed where it is unstable
        other = _last_stable(largest, k if side == k + 1 else k + 1, -1 if side == k + 1 else 1)
        # NaN: a mode above max_frequency at that speed, not judged
        column = int(np.argmax(np.where(np.isnan(eigenvalues[side]), -np.inf, eigenvalues[side].real)))
        root = _crossing_zero(real_part, speeds, eigenvalues, significant, k, column) if by_root else None
        if root is None and other is not None:
            a, b = sorted((speeds[other], speeds[side]))
            root = _brent(real_part, a, b)
        if root is None:
            root = _bisect_change(lambda s: real_part(s) > 0, speeds[k], speeds[k + 1])
        found.append(root)
        modes.append(column + 1)
        onsets.append(bool(unstable[k + 1]))
    return np.array(found), np.array(modes, dtype=int), np.array(onsets, dtype=bool)


def _crossing_zero(real_part, speeds, eigenvalues, significant, k, column):
    """The zero of the real part of the root that crosses between ``speeds[k]`` and
    ``speeds[k + 1]`` [rad/s]: Brent's method on ``real_part(speed, clip=False, near=guess)``, the
    real part of the root nearest the tracked column's eigenvalue interpolated linearly between
    the two grid speeds. None (the caller's rules then) unless the column's real part is beyond
    round-off at both ends with opposite signs (``significant``: :func:`_significant_real_parts`
    of ``eigenvalues``) and the roots solved again there keep them. Where the crossing root's
    neighbours are marginal (an undamped torsion or axial mode beside a damped lateral one), the
    largest real part is 0 below the threshold and its sign change is the crossing root's
    reaching the round-off level; its own zero lies ``eps ||B||_1 / slope`` before that."""
    ends = eigenvalues[k:k + 2, column]
    signs = np.sign(significant[k:k + 2, column])
    if not np.isfinite(ends).all() or signs[0] * signs[1] >= 0:
        return None
    a, b = speeds[k], speeds[k + 1]

    def _guess(speed):
        t = (speed - a) / (b - a)
        return (1 - t) * ends[0] + t * ends[1]

    solved = {}

    def f(speed):
        solved[speed] = real_part(speed, clip=False, near=_guess(speed))
        return solved[speed]

    fa, fb = f(a), f(b)
    if not (np.sign(fa) == signs[0] and np.sign(fb) == signs[1]):
        return None
    root = _brentq_known(f, a, b, fa, fb)
    value = solved[root] if root in solved else f(root)      # Brent's method ends on a speed it solved
    return root if _on_the_axis(value, _guess(root)) else None


def _on_the_axis(real_part: float, guess) -> bool:
    """Whether the real part [1/s] where Brent's method ended is a zero (to 1e-8 of the root's
    size ``|guess|``), not a jump. On a coarse grid the interpolated guess moves from one root to
    another between the grid speeds (``unstable_cross_coupled.toml``, ``--speeds 0:1e5:3``: mode 5
    falls from 11 to 2 Hz), the real part of the root nearest it jumps there, and Brent's method
    ends on the jump: "loses stability at 39990 rpm" where that real part was +0.72 1/s, the
    machine unstable from 10886 rpm. ``stability`` then takes the zero of the largest real part."""
    return abs(real_part) <= 1e-8 * abs(guess)


def _last_stable(largest, start, step):
    """From ``start`` on in direction ``step``, across marginal speeds (largest real part 0),
    the first speed where it is stable (< 0); None when the marginal run ends otherwise."""
    k = start
    while 0 <= k < len(largest) and largest[k] == 0:
        k += step
    return k if 0 <= k < len(largest) and largest[k] < 0 else None


def _brent(real_part, a, b):
    """The zero of the largest real part (``real_part(speed, clip=False)``) in [a, b] by Brent's
    method, or None when the real parts solved again at a and b do not change sign (round-off),
    or when one of them is -inf (no root judged there: none below ``max_frequency``, where the
    change is a mode passing the limit, a jump for the bisection)."""
    def f(s):
        value = real_part(s, clip=False)
        if not np.isfinite(value):
            raise _NoRootJudged
        return value

    try:
        fa, fb = f(a), f(b)
        if not fa * fb < 0:
            return None
        return _brentq_known(f, a, b, fa, fb)
    except _NoRootJudged:
        return None


def _brentq_known(f, a, b, fa, fb):
    """The zero of ``f`` in [a, b] by Brent's method (to 1e-13 relative), given ``fa = f(a)`` and
    ``fb = f(b)`` already solved: brentq's own first calls, at a and b, take them instead of
    solving the eigenproblem there again."""
    known = {a: fa, b: fb}
    return brentq(lambda s: known.pop(s) if s in known else f(s), a, b,
                  xtol=1e-13 * max(abs(a), abs(b), 1.0), rtol=8.9e-16, maxiter=200)


class _NoRootJudged(Exception):
    """Raised inside :func:`_brent` where no root is judged at a trial speed."""


def _bisect_change(predicate, a, b):
    """The point in [a, b] where a boolean predicate changes value (to 1e-13 relative)."""
    at_a = predicate(a)
    tolerance = 1e-13 * max(abs(a), abs(b), 1.0)
    while b - a > tolerance:
        middle = 0.5 * (a + b)
        if predicate(middle) == at_a:
            a = middle
        else:
            b = middle
    return 0.5 * (a + b)


def roundoff_levels(form, speeds) -> np.ndarray:
    """Round-off of the computed real parts at each speed [1/s], shape (N,).

    ``eps * ||B||_1``, ``B`` the state matrix balanced as LAPACK's ``geev`` balances it before
    solving: LAPACK's error bound of an eigenvalue of condition number 1 (the smallest). A real
    part within it of zero has no sign: it counts as zero (marginal).

    ``inf`` where the machine is conservative at that speed (:func:`._roots.conservative`): every
    root is then on the imaginary axis (``docs/theory.md`` section 8), and the computed real
    parts are round-off whatever their size; an ill-conditioned root (nearly repeated, beside
    roots many decades larger) has one far above ``eps ||B||_1``, which once read as unstable.

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    """
    speeds = np.asarray(speeds, dtype=float)
    out = np.empty(len(speeds))
    for k, speed in enumerate(speeds):  # one state matrix at a time
        # LAPACK's own balancing (scipy.linalg.matrix_balance calls it, at 8 times the cost)
        balanced = scipy.linalg.lapack.dgebal(form.at(float(speed)), scale=1, permute=0)[0]
        out[k] = np.abs(balanced).sum(axis=0).max()
    return np.where(_roots.conservative(form, speeds), np.inf, np.finfo(float).eps * out)


def passive_at(form, speeds) -> np.ndarray:
    """Where the machine provably has no root of positive real part, shape (N,) of bool: where
    its mass matrix is symmetric, its gyroscopic matrix skew-symmetric, its stiffness ``K`` and
    damping ``C`` at that speed symmetric and positive semidefinite (bearings' included), and its
    mounts' Maxwell branches' stiffness symmetric positive semidefinite with positive times. Then
    the energy ``q'* M q' / 2 + q* K q / 2`` (with the branches' springs' energy) never grows, as a
    root of positive real part would make it (Kelvin-Tait-Chetaev): such a
    speed is never unstable, whatever the gyroscopic terms. A circulatory term (a non-symmetric
    ``K``: cross-coupled bearings or supports, journal bearings' films) leaves it unproven (False).

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    """
    speeds = np.asarray(speeds, dtype=float)
    matrices = form.sparse if form.sparse is not None else form.matrices
    blocks_passive = all(_symmetric_psd(block) for block in form.branch_blocks) and bool(np.all(form.branch_times > 0))
    if not (blocks_passive and _symmetric(matrices.M) and _symmetric(matrices.G, sign=-1)):
        return np.zeros(len(speeds), dtype=bool)
    if not form.speed_dependent:
        return np.full(len(speeds), _symmetric_psd(matrices.K) and _symmetric_psd(matrices.C))
    stiffness, damping = form.pencil_at(speeds)
    return np.array([_symmetric_psd(k) and _symmetric_psd(c) for k, c in zip(stiffness, damping)], dtype=bool)


#: relative tolerance of :func:`passive_at`'s checks: an asymmetry ``|a_ij - a_ji|`` within it of
#: ``sqrt(|a_ii a_jj|)`` is round-off (measured below 1e-16 on the examples), as a negative
#: eigenvalue within it of the matrix scaled to a unit diagonal
_PASSIVE_TOLERANCE = 1e-12


def _dense(matrix) -> np.ndarray:
    return matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix, dtype=float)


def _symmetric(matrix, sign: int = 1) -> bool:
    """``matrix`` (n, n), dense or ``scipy.sparse``, equal to ``sign`` times its transpose to
    :data:`_PASSIVE_TOLERANCE` of its diagonal's scale (of its largest entry for ``sign = -1``)."""
    if hasattr(matrix, "toarray"):
        difference = abs(matrix - sign * matrix.T).max()
        scale = abs(matrix).max()
        return bool(difference <= _PASSIVE_TOLERANCE * scale)
    matrix = np.asarray(matrix, dtype=float)
    difference = np.abs(matrix - sign * matrix.T)
    if sign < 0:
        return bool(difference.max(initial=0.0) <= _PASSIVE_TOLERANCE * np.abs(matrix).max(initial=0.0))
    diagonal = np.sqrt(np.abs(np.outer(np.diag(matrix), np.diag(matrix))))
    return bool(np.all(difference <= _PASSIVE_TOLERANCE * diagonal))


def _symmetric_psd(matrix) -> bool:
    """``matrix`` (n, n) symmetric (:func:`_symmetric`) and positive semidefinite: no negative
    diagonal, rows of a zero diagonal entry zero, and a Cholesky factor of the rest scaled to a unit
    diagonal plus :data:`_PASSIVE_TOLERANCE`."""
    matrix = _dense(matrix)
    if not _symmetric(matrix):
        return False
    diagonal = np.diag(matrix)
    if np.any(diagonal < 0):
        return False
    zero = diagonal == 0
    if np.any(matrix[zero] != 0):
        return False
    keep = ~zero
    scale = 1 / np.sqrt(diagonal[keep])
    scaled = 0.5 * (matrix[np.ix_(keep, keep)] + matrix[np.ix_(keep, keep)].T) * np.outer(scale, scale)
    try:
        scipy.linalg.cholesky(scaled + _PASSIVE_TOLERANCE * np.eye(len(scaled)), lower=True, check_finite=True)
    except (np.linalg.LinAlgError, ValueError):
        return False
    return True


#: :func:`unstable_states`' band: a root's real part within this factor of its round-off level (below
#: or above) may be read on either side of it by another solution of the same matrix (the sweep's
#: batch, its polish)
STATE_BAND = 10.0


def unstable_states(form, speeds) -> np.ndarray:
    """Whether a sweep can read each speed as unstable, shape (N,) of int, from numpy's eigenvalues
    of the state matrix alone (one solution a speed, no shapes): 1 where an oscillating root's real
    part exceeds ``STATE_BAND`` times its round-off level (:func:`_significant_real_parts`'s:
    ``1e-10 |lam|`` or :func:`roundoff_levels`), -1 where no root's exceeds that level over
    ``STATE_BAND`` (every speed of a conservative machine), 0 in between (either). The roots a
    sweep may judge otherwise count as either where their real part is above that level: real
    roots (a sweep keeps half of them) and roots within ``STATE_BAND`` of the square root of the
    round-off (a sweep calls such a root zero, or a slow mode, by its shape:
    :func:`._roots.zero_roots`).

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    """
    speeds = np.asarray(speeds, dtype=float)
    out = np.empty(len(speeds), dtype=int)
    for k, speed in enumerate(speeds):
        noise = roundoff_levels(form, [speed])[0]
        if not np.isfinite(noise):
            out[k] = -1                          # conservative: every root on the imaginary axis
            continue
        roots = np.linalg.eigvals(form.at(float(speed)))
        level = np.maximum(_MARGINAL_TOLERANCE * np.abs(roots), noise)
        above = roots.real > level / STATE_BAND
        judged = (np.abs(roots.imag) > STATE_BAND * noise) & (np.abs(roots) > STATE_BAND * np.sqrt(noise))
        out[k] = 1 if np.any(judged & (roots.real > STATE_BAND * level)) else 0 if np.any(above) else -1
    return out


def threshold_count_bound(states) -> int:
    """The most thresholds :func:`threshold_speeds` can find on a sweep whose speeds' states are
    ``states`` (N,) (1 unstable, -1 not, 0 either: :func:`unstable_states`, or -1 where
    :func:`passive_at`): one per pair of neighbouring speeds unless both are surely the same."""
    states = np.asarray(states)
    return int(np.count_nonzero((states[:-1] == 0) | (states[1:] == 0) | (states[:-1] != states[1:])))


def _largest_real_part(form, speed, clip: bool = True, near=None) -> float:
    """The largest real part at one speed [1/s], of the roots a sweep keeps (one of each
    conjugate pair, their round-off removed as the sweep's, each slow root judged by its own
    shape: :func:`._eigensolve.eigenvalues_of`); with ``near``, that of the root nearest it."""
    matrix = form.at(speed)
    roundoff = roundoff_levels(form, [speed]) if clip and near is None else None
    roots = _eigensolve.select_upper(_eigensolve.eigenvalues_of(matrix[None], form.n_dof, form.matrices.M))
    if near is not None:
        return _nearest_real_part(roots[0], near)
    return float(_significant_real_parts(roots, clip, roundoff).max())


def _polished_largest_real_part(stack, speed, clip: bool = True, near=None) -> float:
    """:func:`_largest_real_part` of the model of a one-model ``stack`` some of whose roots double
    precision leaves further off than :data:`._eigensolve.POLISH_LEVEL`: of the roots the sweep
    keeps at one speed, with their shapes, polished as the sweep's (:func:`.campbell._refine_inexact`;
    the sweep has warned of what is left); with ``near``, that of the polished root nearest it."""
    import warnings

    speeds = np.array([float(speed)])
    values, shapes = solve_sweeps(stack, speeds)[:2]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        _refine_inexact(stack, speeds, values, shapes)
    if near is not None:
        return _nearest_real_part(values[0, 0], near)
    roundoff = roundoff_levels(stack.forms[0], speeds) if clip else None
    return float(_significant_real_parts(values[0], clip, roundoff).max())


def _nearest_real_part(roots, near) -> float:
    """The real part [1/s] of the root of ``roots`` (k,) complex nearest ``near`` (NaN roots left
    out)."""
    roots = np.asarray(roots).ravel()
    return float(roots[np.nanargmin(np.abs(roots - near))].real)


def _significant_real_parts(eigenvalues, clip: bool = True, roundoff=None) -> np.ndarray:
    """Real parts, with rigid-body roots (lam = 0, made exact by :func:`._roots.snapped`: a
    direction without suspension) set to -inf so that their round-off sign is not read as
    instability, and real parts within round-off of zero (undamped modes: within ``1e-10 |lam|``
    of the root's own size, or within ``roundoff``, shape (...,) [1/s], of each speed when
    given) set to exactly 0. NaN roots (above ``max_frequency`` at that speed) are -inf too: not
    judged."""
    rigid = (eigenvalues == 0) | np.isnan(eigenvalues)
    real = eigenvalues.real
    if clip:
        tolerance = _MARGINAL_TOLERANCE * np.abs(eigenvalues)
        if roundoff is not None:
            tolerance = np.maximum(tolerance, np.asarray(roundoff)[..., None])
        real = np.where(np.abs(real) <= tolerance, 0.0, real)
    return np.where(rigid, -np.inf, real)


_MARGINAL_TOLERANCE = 1e-10
