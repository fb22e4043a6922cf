"""Campbell diagram: tracked modes over speed, excitation orders, critical speeds."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..linear_system import speed_linear_form
from . import _eigen
from .modal import is_oscillating, modal_quantities
from .tracking import track_modes

__all__ = ["CampbellResult", "CriticalSpeeds", "ExcitationSources", "campbell", "critical_speeds",
           "excitation_sources", "solve_sweep"]

_CHUNK = 4096


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
            names.append(f"mesh:{t.driver}-{t.driven}")
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
    """

    source: np.ndarray
    order: np.ndarray
    mode: np.ndarray
    speeds: np.ndarray
    frequencies_hz: np.ndarray
    whirl: np.ndarray
    whirl_ratios: np.ndarray
    damping_ratios: np.ndarray

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    def __len__(self) -> int:
        return len(self.speeds)

    def to_dataframe(self):
        """Table with the command line's columns (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame({
            "source": self.source, "order": self.order, "mode": self.mode,
            "speed_rpm": self.speeds_rpm, "frequency_hz": self.frequencies_hz,
            "whirl": self.whirl, "whirl_ratio": self.whirl_ratios,
            "damping_ratio": self.damping_ratios,
        })


@dataclass(frozen=True)
class CampbellResult:
    """Modes tracked over a speed sweep.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    eigenvalues : ndarray, shape (N, n_modes), complex [1/s]
        Column ``m`` is tracked mode ``m + 1`` at every speed.
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

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    @property
    def oscillatory(self) -> np.ndarray:
        """(N, n_modes) bool: the root is a mode at that speed (Im lam > 0, not overdamped;
        see :func:`rotordyn_modal.analysis.modal.is_oscillating`)."""
        return is_oscillating(self.eigenvalues)

    def to_dataframe(self, oscillatory_only: bool = True):
        """Long table ``speed_rpm, mode, frequency_hz, damping_ratio, log_decrement, whirl, ...``."""
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
        })
        return table[keep].reset_index(drop=True)

    def plot(self, **kwargs):
        """Campbell diagram; see :func:`rotordyn_modal.plotting.plot_campbell`."""
        from ..plotting import plot_campbell

        return plot_campbell(self, **kwargs)


# ----------------------------------------------------------------------------------------
def solve_sweep(model, speeds, progress=False, form=None, forms=None):
    """Eigenvalues and unit mass-weighted shapes at every speed, tracked.

    Parameters
    ----------
    model : Model
    speeds : ndarray, shape (N,) [rad/s]
    progress : bool
        Show a progress bar.

    Returns
    -------
    eigenvalues : ndarray, shape (N, m), complex, tracked columns
    shapes : ndarray, shape (N, m, n), complex, unit norm
    weighted : ndarray, shape (N, m, n), complex, unit mass-weighted
    """
    form = form or speed_linear_form(model)
    forms = forms if forms is not None else _eigen.whirl_forms(model)
    speeds = np.asarray(speeds, dtype=float)
    chunks = [speeds[i:i + _CHUNK] for i in range(0, len(speeds), _CHUNK)]
    values, shapes = [], []
    for chunk in _progress(chunks, progress, "eigen-solve"):
        lam, phi = _eigen.solve_batch(form, chunk, forms)
        values.append(lam)
        shapes.append(phi)
    values = np.concatenate(values)
    shapes = np.concatenate(shapes)
    weighted = _eigen.mass_normalized(shapes, form.matrices.M)
    order = track_modes(values, weighted)
    order = _relabel_by_frequency(order, values, speeds)
    rows = np.arange(len(speeds))[:, None]
    return values[rows, order], shapes[rows, order], weighted[rows, order]


def _relabel_by_frequency(order, values, speeds):
    """Number tracked roots at the speed nearest zero: modes first, by ascending frequency,
    then the roots that are not modes there (so mode labels match :func:`modal`'s)."""
    k0 = int(np.argmin(np.abs(speeds)))
    at_k0 = values[k0, order[k0]]
    labels = np.lexsort((at_k0.real, at_k0.imag, ~is_oscillating(at_k0)))
    return order[:, labels]


def _progress(items, enabled, description):
    if not enabled:
        return items
    from tqdm.auto import tqdm

    return tqdm(items, desc=description, unit="chunk", leave=False)


def campbell(model, speeds, orders=(1,), progress=False) -> CampbellResult:
    """Campbell diagram: all speeds solved in one batch, modes tracked.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s], increasing; negative reverses the spin.
    orders : sequence of float
        Excitation orders (1X, 2X, ...) whose critical speeds are found and marked.
    progress : bool
        Show a progress bar.

    Returns
    -------
    CampbellResult
    """
    speeds = _check_speeds(speeds)
    form = speed_linear_form(model)
    forms = _eigen.whirl_forms(model)
    values, shapes, weighted = solve_sweep(model, speeds, progress, form, forms)
    ratios = np.where(is_oscillating(values), _eigen.whirl_ratios(shapes, forms, speeds), 0.0)
    freq, zeta, log_dec = modal_quantities(values)
    sources = excitation_sources(model)
    n = values.shape[1]
    critical = _find_critical_speeds(form, forms, speeds, values, weighted, sources, tuple(orders))
    return CampbellResult(
        speeds=speeds, eigenvalues=values, frequencies_hz=freq, damping_ratios=zeta,
        log_decrements=log_dec, whirl_ratios=ratios, whirl=_eigen.whirl_labels(ratios),
        shapes=shapes, modes=np.arange(1, n + 1), sources=sources, critical=critical,
        orders=tuple(float(o) for o in orders),
    )


def critical_speeds(model, speeds, orders=(1,), progress=False) -> CriticalSpeeds:
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

    Returns
    -------
    CriticalSpeeds
    """
    return campbell(model, speeds, orders=orders, progress=progress).critical


def _check_speeds(speeds) -> np.ndarray:
    from ..errors import InputError

    speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
    if speeds.ndim != 1 or len(speeds) == 0 or not np.all(np.isfinite(speeds)):
        raise InputError(f"speeds: expected a non-empty 1-D array of finite numbers, got shape {speeds.shape}")
    if len(speeds) > 1 and not np.all(np.diff(speeds) > 0):
        raise InputError("speeds: expected strictly increasing values")
    return speeds


def _find_critical_speeds(form, whirl_forms, speeds, values, weighted, sources, orders) -> CriticalSpeeds:
    rows = []
    for name, multiplier in zip(sources.names, sources.multipliers):
        for order in orders:
            slope = order * multiplier  # excitation [rad/s] per |speed| [rad/s]
            if slope == 0:
                continue
            gap = values.imag - slope * np.abs(speeds)[:, None]
            for mode in range(values.shape[1]):
                for k in _sign_changes(gap[:, mode], values[:, mode]):
                    rows.append(_refine_crossing(form, whirl_forms, speeds, values, weighted,
                                                 mode, k, slope, name, order))
    rows.sort(key=lambda r: (r[3], r[0], r[1], r[2]))
    columns = list(zip(*rows)) if rows else [[]] * 8
    return CriticalSpeeds(
        source=np.array(columns[0], dtype=object), order=np.array(columns[1], dtype=float),
        mode=np.array(columns[2], dtype=int), speeds=np.array(columns[3], dtype=float),
        frequencies_hz=np.array(columns[4], dtype=float), whirl=np.array(columns[5], dtype=object),
        whirl_ratios=np.array(columns[6], dtype=float), damping_ratios=np.array(columns[7], dtype=float),
    )


def _sign_changes(gap, lam):
    """Indices k with a crossing in [speeds[k], speeds[k+1]] of an oscillating mode."""
    mode = is_oscillating(lam)
    oscillating = mode[:-1] & mode[1:]
    change = (np.sign(gap[:-1]) != np.sign(gap[1:])) & (gap[:-1] != 0)
    return np.nonzero(change & oscillating)[0]


def _refine_crossing(form, whirl_forms, speeds, values, weighted, mode, k, slope, name, order):
    M = form.matrices.M
    a, b = speeds[k], speeds[k + 1]

    spread = abs(values[k + 1, mode] - values[k, mode]) + 1e-9 * abs(values[k, mode]) + 1e-300

    def eigenvalue_at(speed):
        """The tracked mode's eigenvalue: the nearest to the bracket's interpolation,
        confirmed by its shape when another eigenvalue is about as near."""
        lam = _eigen.select_upper(np.linalg.eigvals(form.at(speed)))
        t = (speed - a) / (b - a)
        distance = np.abs(lam - ((1 - t) * values[k, mode] + t * values[k + 1, mode]))
        nearest, second = np.argsort(distance)[:2]
        if distance[second] > 4 * distance[nearest] + 2 * spread:
            return lam[nearest]
        return mode_at(speed)[0]

    def mode_at(speed):
        lam, phi = _eigen.solve_batch(form, np.array([speed]), whirl_forms)
        psi = _eigen.mass_normalized(phi, M)
        t = (speed - a) / (b - a)
        expected = (1 - t) * values[k, mode] + t * values[k + 1, mode]
        correlation = _eigen.mac_matrix(weighted[k, mode][None], psi[0])[0]
        j = int(np.argmin((1 - correlation) + np.abs(lam[0] - expected) / spread))
        return lam[0, j], phi[0, j]

    def gap(speed):
        return eigenvalue_at(speed).imag - slope * abs(speed)

    if gap(a) == 0:
        root = a
    elif gap(b) == 0:
        root = b
    else:
        root = brentq(gap, a, b, xtol=1e-13 * max(abs(a), abs(b), 1.0), rtol=8.9e-16, maxiter=200)
    lam, phi = mode_at(root)
    ratio = _eigen.whirl_ratios(phi[None, None], whirl_forms, np.array([root]))[0, 0]
    _, zeta, _ = modal_quantities(lam)
    return (name, float(order), mode + 1, float(root), lam.imag / (2 * np.pi),
            str(_eigen.whirl_labels(ratio)), float(ratio), float(zeta))
