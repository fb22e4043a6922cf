"""Stability over speed, threshold speeds, and stability maps over a model parameter."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError
from ..linear_system import speed_linear_form
from . import _eigen, _roots
from .campbell import _check_speeds, _progress, solve_sweep
from .modal import is_oscillating, modal_quantities

__all__ = ["StabilityResult", "StabilityMap", "stability", "stability_map", "threshold_speeds"]


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

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    @property
    def stable(self) -> np.ndarray:
        """(N,) bool: every real part < 0 at that speed."""
        return np.all(_significant_real_parts(self.eigenvalues) < 0, axis=1)

    @property
    def threshold_speed(self) -> float:
        """Lowest non-negative speed where stability is lost [rad/s] (nan if none)."""
        onsets = self.thresholds[self.threshold_onsets & (self.thresholds >= 0)]
        return float(onsets.min()) if len(onsets) else float("nan")

    def to_dataframe(self):
        """Long table ``speed_rpm, value, mode, real_part, damping_ratio, log_decrement, ...``."""
        import pandas as pd

        count, n = self.eigenvalues.shape
        return pd.DataFrame({
            "speed_rpm": np.repeat(self.speeds_rpm, n), "value": "",
            "mode": np.tile(self.modes, count), "real_part": self.real_parts.ravel(),
            "damping_ratio": self.damping_ratios.ravel(), "log_decrement": self.log_decrements.ravel(),
            "frequency_hz": self.frequencies_hz.ravel(), "whirl": self.whirl.ravel(),
        })

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
        return np.array([_significant_real_parts(r.eigenvalues).max(axis=1) for r in self.results])

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
        return pd.concat(tables, ignore_index=True)

    def plot(self, **kwargs):
        """Map with the stability boundary; see :func:`rotordyn_modal.plotting.plot_stability_map`."""
        from ..plotting import plot_stability_map

        return plot_stability_map(self, **kwargs)


def stability(model, speeds, vary: str | None = None, values=None, scale=None, progress=False):
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

    Returns
    -------
    StabilityResult, or StabilityMap when ``vary`` is given
    """
    if vary is not None:
        return stability_map(model, speeds, vary, values=values, scale=scale, progress=progress)
    if values is not None or scale is not None:
        raise InputError("values/scale given without a parameter to vary (vary=KEY)")
    speeds = _check_speeds(speeds)
    form = speed_linear_form(model)
    eigenvalues, shapes, _ = solve_sweep(model, speeds, progress)
    ratios = np.where(is_oscillating(eigenvalues),
                      _eigen.whirl_ratios(shapes, _eigen.whirl_forms(model), speeds), 0.0)
    freq, zeta, log_dec = modal_quantities(eigenvalues)
    thresholds, threshold_modes, onsets = threshold_speeds(form, speeds, eigenvalues)
    return StabilityResult(
        speeds=speeds, eigenvalues=eigenvalues, real_parts=eigenvalues.real, damping_ratios=zeta,
        log_decrements=log_dec, frequencies_hz=freq, whirl=_eigen.whirl_labels(ratios),
        modes=np.arange(1, eigenvalues.shape[1] + 1), thresholds=thresholds,
        threshold_modes=threshold_modes, threshold_onsets=onsets,
    )


def stability_map(model, speeds, key: str, values=None, scale=None, progress=False) -> StabilityMap:
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
        variant = model.with_values({key: value}) if values is not None else model.scaled({key: value})
        results.append(stability(variant, speeds))
    return StabilityMap(key=key, mode_of_variation="values" if values is not None else "scale",
                        values=grid, speeds=np.asarray(results[0].speeds), results=tuple(results))


def threshold_speeds(form, speeds, eigenvalues):
    """Speeds where the largest real part of the eigenvalues crosses zero.

    Real parts within round-off of zero (``1e-10`` of the largest ``|lam|``, as in an
    undamped machine) count as zero: marginal stability is not read as crossings.
    A clean sign change is refined with Brent's method on the eigenproblem; a change
    from (or to) marginal is located by bisection of the predicate "unstable".

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    eigenvalues : ndarray, shape (N, n), tracked

    Returns
    -------
    speeds : ndarray [rad/s]; modes : ndarray of int (1-based); onsets : ndarray of bool
    """
    largest = _significant_real_parts(eigenvalues).max(axis=1)
    unstable = largest > 0
    found, modes, onsets = [], [], []
    for k in np.nonzero(unstable[:-1] != unstable[1:])[0]:
        a, b = speeds[k], speeds[k + 1]
        if largest[k] < 0 < largest[k + 1] or largest[k + 1] < 0 < largest[k]:
            root = brentq(lambda s: _largest_real_part(form, s, clip=False), a, b,
                          xtol=1e-13 * max(abs(a), abs(b), 1.0), rtol=8.9e-16, maxiter=200)
        else:
            root = _bisect_change(lambda s: _largest_real_part(form, s) > 0, a, b)
        side = k + 1 if unstable[k + 1] else k  # the speed where it is unstable
        found.append(root)
        modes.append(int(np.argmax(eigenvalues[side].real)) + 1)
        onsets.append(bool(unstable[k + 1]))
    return np.array(found), np.array(modes, dtype=int), np.array(onsets, dtype=bool)


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


def _largest_real_part(form, speed, clip: bool = True) -> float:
    matrix = form.at(speed)
    eigenvalues = _roots.snapped(np.linalg.eigvals(matrix), _roots.round_off(matrix))
    return float(_significant_real_parts(eigenvalues, clip).max())


def _significant_real_parts(eigenvalues, clip: bool = True) -> np.ndarray:
    """Real parts, with rigid-body roots (lam = 0, made exact by :func:`._roots.snapped`: a
    direction without suspension) set to -inf so that their round-off sign is not read as
    instability, and real parts within round-off of zero (undamped modes) set to exactly 0."""
    scale = np.abs(eigenvalues).max(axis=-1, keepdims=True)
    rigid = eigenvalues == 0
    real = eigenvalues.real
    if clip:
        real = np.where(np.abs(real) <= _MARGINAL_TOLERANCE * scale, 0.0, real)
    return np.where(rigid, -np.inf, real)


_MARGINAL_TOLERANCE = 1e-10
