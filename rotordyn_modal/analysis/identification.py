"""Modal identification from measured FRFs: poles, damping and mode shapes.

Two methods, chosen by :func:`identify_modes` (``method``):

* ``"lscf"`` (needs the ``ema`` extra, ``sdypy-ema``): the least-squares complex-frequency
  estimator of ``sdypy.EMA`` (one denominator common to every FRF, a z-domain polynomial) at
  every even model order up to ``2 max_order``; a stabilization chart compares each order's
  poles with the previous order's; the poles that stay stable over many orders are the
  physical modes; the modal constants come from ``sdypy.EMA``'s least-squares
  frequency-domain estimator (LSFD, with lower and upper residual terms). The LSCF poles are
  biased by noise (a linear least-squares estimator) and by the z-domain model, so by default
  they are refined: a nonlinear least squares over the poles of every FRF in the band at once,
  the modal constants solved linearly by the same LSFD at each step (variable projection).
* ``"single-pole"``: one pole shared by every FRF around each peak of the summed magnitudes,
  ``H_k(w) = A_k / (i w - lam) + B_k``. It needs no extra library and recovers isolated,
  lightly damped modes to a few 0.01 %, but modes closer than their half-power bandwidth bias
  it by percents.

The shapes are the modal constants of the receptance, ``H(w) = sum_r A_r / (i w - lam_r) +
conj(A_r) / (i w - conj(lam_r))`` [m/N per 1/s], whatever quantity was measured.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["MeasuredModes", "StabilizationChart", "identify_modes", "fit_measured_modes", "ema_available"]

_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}


def ema_available() -> bool:
    """True when ``sdypy-ema`` (the ``ema`` extra) can be imported."""
    import importlib.util

    return importlib.util.find_spec("sdypy") is not None and importlib.util.find_spec("sdypy.EMA") is not None


def _import_ema():
    try:
        from sdypy import EMA
    except ImportError:
        raise InputError("modal identification by LSCF needs sdypy-ema: pip install 'rotordyn_modal[ema]' "
                         "(or use method='single-pole')") from None
    return EMA


@dataclass(frozen=True)
class StabilizationChart:
    """Poles of every model order of an LSCF identification, classified against the order below.

    Attributes
    ----------
    orders : ndarray of int, shape (n_poles,)
        Model order (number of poles of the denominator) of each pole.
    frequencies_hz, damping_ratios : ndarray, shape (n_poles,)
        Damped natural frequency ``Im(lam) / 2 pi`` [Hz] and ``-Re(lam) / |lam|``.
    status : ndarray of str, shape (n_poles,)
        'stable' (frequency and damping within the tolerances of a pole of the order
        below), 'frequency' (only the frequency), 'new'.
    selected_hz : ndarray, shape (n_modes,)
        Frequencies of the modes chosen from the chart (before any refinement).
    band_hz : tuple of float
    frequency_lines_hz : ndarray, shape (n_freq,)
    summed_magnitude : ndarray, shape (n_freq,)
        Sum of |H| over the FRFs used (drawn behind the poles).
    tolerances : tuple of float
        Relative frequency and damping tolerances of 'stable'.
    """

    orders: np.ndarray
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    status: np.ndarray
    selected_hz: np.ndarray
    band_hz: tuple
    frequency_lines_hz: np.ndarray
    summed_magnitude: np.ndarray
    tolerances: tuple

    def to_dataframe(self):
        """``order,frequency_hz,damping_ratio,status`` (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame({"order": self.orders, "frequency_hz": self.frequencies_hz,
                             "damping_ratio": self.damping_ratios, "status": self.status})

    def plot(self, **kwargs):
        """The stabilization chart; see :func:`rotordyn_modal.plotting.plot_stabilization`."""
        from ..plotting.identification import plot_stabilization

        return plot_stabilization(self, **kwargs)


@dataclass(frozen=True)
class MeasuredModes:
    """Modes identified from measured FRFs.

    Attributes
    ----------
    frequencies_hz, damping_ratios : ndarray, shape (n_modes,)
        Damped natural frequency [Hz] and damping ratio (the package's convention,
        :func:`~rotordyn_modal.analysis.modal.modal_quantities`).
    poles : ndarray, shape (n_modes,), complex [1/s]
    shapes : ndarray, shape (n_modes, n_outputs, n_inputs), complex
        Receptance modal constants ``A`` of every FRF (zero where a pair was not measured).
    outputs, inputs : tuple of str
    method : str
        'lscf' (refined), 'lscf-unrefined' or 'single-pole'.
    stabilization : StabilizationChart or None
        The chart of an LSCF identification.
    """

    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    poles: np.ndarray
    shapes: np.ndarray
    outputs: tuple
    inputs: tuple
    method: str = "single-pole"
    stabilization: StabilizationChart | None = field(default=None, repr=False)

    def to_dataframe(self):
        """``mode,frequency_hz,damping_ratio,real_part,method`` (``pandas.DataFrame``)."""
        import pandas as pd

        return pd.DataFrame({"mode": np.arange(1, len(self.poles) + 1), "frequency_hz": self.frequencies_hz,
                             "damping_ratio": self.damping_ratios, "real_part": self.poles.real,
                             "method": self.method})

    def plot(self, **kwargs):
        """The stabilization chart (LSCF only)."""
        if self.stabilization is None:
            raise InputError(f"modes identified by {self.method!r} have no stabilization chart: use method='lscf'")
        return self.stabilization.plot(modes=self, **kwargs)


def _from_poles(poles, constants, measured, method, chart=None) -> MeasuredModes:
    from .modal import modal_quantities

    order = np.argsort(poles.imag)
    poles = poles[order]
    freq, zeta, _ = modal_quantities(poles)
    return MeasuredModes(frequencies_hz=freq, damping_ratios=zeta, poles=poles,
                         shapes=constants[order].reshape(len(poles), *measured.H.shape[:2]),
                         outputs=tuple(measured.outputs), inputs=tuple(measured.inputs), method=method,
                         stabilization=chart)


# ---------------------------------------------------------------------------------------------
# LSCF + LSFD through sdypy-ema
# ---------------------------------------------------------------------------------------------
def identify_modes(measured, method: str = "auto", band_hz=None, max_order: int = 20, refine: bool = True,
                   tolerances=(0.01, 0.10), min_stable_fraction: float = 0.2) -> MeasuredModes:
    """Identify the modes of a set of measured FRFs.

    Parameters
    ----------
    measured : FRFResult
        Measured FRFs of one speed (NaN where a pair was not measured), equally spaced lines.
    method : {'auto', 'lscf', 'single-pole'}
        'auto' is 'lscf' when ``sdypy-ema`` is installed and the lines are equally spaced,
        else 'single-pole'.
    band_hz : (float, float), optional
        Band identified [Hz] (default: every line above 0 Hz).
    max_order : int
        LSCF: highest order is ``2 max_order`` poles (every even order from 2).
    refine : bool
        LSCF: refine the chosen poles by nonlinear least squares over every FRF.
    tolerances : (float, float)
        LSCF: relative frequency and damping change that counts as stable.
    min_stable_fraction : float
        LSCF: a mode must be stable in at least this fraction of the orders.

    Returns
    -------
    MeasuredModes
    """
    if method == "auto":
        method = "lscf" if ema_available() and _equally_spaced(measured.frequencies_hz) else "single-pole"
    if method == "single-pole":
        return fit_measured_modes(measured)
    if method != "lscf":
        raise InputError(f"identification method {method!r}: expected 'auto', 'lscf' or 'single-pole'")
    rows, keep, scale, f, band = _prepared(measured, band_hz)
    EMA = _import_ema()
    lscf = EMA.Model(frf=rows, freq=f, lower=band[0], upper=band[1], pol_order_high=int(max_order),
                     frf_form=measured.quantity)
    lscf.get_poles("lscf", show_progress=False)
    chart = _chart(lscf.all_poles, band, tolerances, f, rows)
    start = _select(chart, lscf.all_poles, min_stable_fraction)
    chart = _with_selection(chart, start)
    if not len(start):
        return _from_poles(np.zeros(0, complex), np.zeros((0, rows.shape[0])), measured, "lscf", chart)
    poles = _refined(start, rows, f, band, measured.quantity) if refine else start
    constants = _lsfd(poles, rows, f, band, measured.quantity)[0]
    full = np.zeros((len(poles), keep.size), dtype=complex)
    full[:, keep] = (constants * scale[:, None]).T
    return _from_poles(poles, full, measured, "lscf" if refine else "lscf-unrefined", chart)


def _equally_spaced(frequencies_hz) -> bool:
    steps = np.diff(np.asarray(frequencies_hz, dtype=float))
    return len(steps) >= 7 and bool(np.allclose(steps, steps[0], rtol=1e-6, atol=0)) and steps[0] > 0


def _prepared(measured, band_hz):
    """FRF rows (finite pairs only) scaled to unit peak, their scale, frequencies and band."""
    f = np.asarray(measured.frequencies_hz, dtype=float)
    steps = np.diff(f)
    if not _equally_spaced(f):
        raise InputError("LSCF identification needs at least 8 equally spaced frequency lines "
                         f"(found {len(f)} lines, steps from {steps.min() if len(steps) else 0:g} to "
                         f"{steps.max() if len(steps) else 0:g} Hz)")
    if measured.quantity not in _POWER:
        raise InputError(f"cannot identify modes of {measured.quantity!r} FRFs: expected receptance, "
                         "mobility or accelerance")
    H = measured.H.reshape(-1, len(f))
    keep = np.all(np.isfinite(H), axis=1)
    if not keep.any():
        raise InputError("no complete measured FRF to identify modes from")
    low, high = (f[f > 0][0], f[-1]) if band_hz is None else (float(band_hz[0]), float(band_hz[1]))
    if not (f[0] <= low < high <= f[-1]):
        raise InputError(f"identification band {low:g}..{high:g} Hz: expected inside the measured lines "
                         f"{f[0]:g}..{f[-1]:g} Hz")
    scale = np.full(int(keep.sum()), np.abs(H[keep]).max() or 1.0)
    return H[keep] / scale[:, None], keep, scale, f, (low, high)


def _physical(poles, band):
    """Poles with Im > 0, Re < 0 and a damped frequency inside the band."""
    p = np.asarray(poles)
    f = p.imag / (2 * np.pi)
    return p[(p.imag > 0) & (p.real < 0) & (f >= band[0]) & (f <= band[1])]


def _chart(all_poles, band, tolerances, f, rows) -> StabilizationChart:
    orders, freqs, zetas, status = [], [], [], []
    previous = np.zeros(0, complex)
    for k, poles in enumerate(all_poles):
        p = _physical(poles, band)
        fk, zk = p.imag / (2 * np.pi), -p.real / np.abs(p)
        status.append(_status(fk, zk, previous, tolerances))
        orders.append(np.full(len(p), 2 * (k + 1)))
        freqs.append(fk)
        zetas.append(zk)
        previous = p
    inside = (f >= band[0]) & (f <= band[1])
    return StabilizationChart(orders=np.concatenate(orders), frequencies_hz=np.concatenate(freqs),
                              damping_ratios=np.concatenate(zetas), status=np.concatenate(status),
                              selected_hz=np.zeros(0), band_hz=tuple(band), frequency_lines_hz=f[inside],
                              summed_magnitude=np.abs(rows[:, inside]).sum(axis=0),
                              tolerances=tuple(tolerances))


def _status(fk, zk, previous, tolerances):
    """'stable', 'frequency' or 'new' for each pole against the nearest pole of the order below."""
    if not len(previous) or not len(fk):
        return np.full(len(fk), "new", dtype=object)
    fp, zp = previous.imag / (2 * np.pi), -previous.real / np.abs(previous)
    nearest = np.argmin(np.abs(fk[:, None] - fp[None, :]), axis=1)
    df = np.abs(fk - fp[nearest]) / fp[nearest]
    dz = np.abs(zk - zp[nearest]) / zp[nearest]
    same_f = df < tolerances[0]
    return np.where(same_f & (dz < tolerances[1]), "stable", np.where(same_f, "frequency", "new")).astype(object)


def _select(chart, all_poles, min_fraction):
    """Starting poles: the stable poles of the highest order that has as many as the chart supports.

    The number of modes is the largest ``n`` such that at least ``max(3, min_fraction *
    n_orders)`` orders have ``n`` or more stable poles; the poles are the stable ones of the
    highest order with exactly ``n`` (or, failing that, the ``n`` best supported of the highest
    order with more).
    """
    stable = chart.status == "stable"
    n_orders = len(all_poles)
    counts = np.array([np.count_nonzero(stable & (chart.orders == 2 * (k + 1))) for k in range(n_orders)])
    needed = max(3, int(np.ceil(min_fraction * n_orders)))
    n_modes = max([n for n in range(1, counts.max(initial=0) + 1) if np.count_nonzero(counts >= n) >= needed],
                  default=0)
    if n_modes == 0:
        return np.zeros(0, complex)
    exact = np.nonzero(counts == n_modes)[0]
    k = int(exact[-1]) if exact.size else int(np.nonzero(counts > n_modes)[0][-1])
    at = stable & (chart.orders == 2 * (k + 1))
    freqs = chart.frequencies_hz[at]
    support = [np.count_nonzero(stable & (np.abs(chart.frequencies_hz - f) <= chart.tolerances[0] * f))
               for f in freqs]
    best = np.sort(freqs[np.argsort(support)[::-1][:n_modes]])
    return np.array([_pole_of(all_poles[k], f) for f in best], dtype=complex)


def _pole_of(poles, frequency_hz):
    p = np.asarray(poles)
    p = p[p.imag > 0]
    return complex(p[np.argmin(np.abs(p.imag / (2 * np.pi) - frequency_hz))])


def _with_selection(chart, poles):
    from dataclasses import replace

    return replace(chart, selected_hz=np.sort(np.asarray(poles).imag / (2 * np.pi)))


def _lsfd(poles, rows, f, band, quantity):
    """``sdypy.EMA`` LSFD: modal constants (n_rows, n_modes) and the reconstruction (n_rows, n_freq)."""
    from sdypy.EMA.EMA import LSFD

    lower, upper = int(np.searchsorted(f, band[0])), int(np.searchsorted(f, band[1], side="right"))
    A, H, _, _ = LSFD(np.asarray(poles), rows, f, True, True, lower, upper, quantity)
    return A, H, slice(lower, upper)


def _refined(poles, rows, f, band, quantity):
    """Nonlinear least squares over the poles; the modal constants follow linearly (LSFD)."""
    import scipy.optimize

    scale = np.abs(poles)

    def unpack(x):
        return (-np.exp(x[: len(poles)]) + 1j * x[len(poles):]) * scale

    def residual(x):
        _, H, band_lines = _lsfd(unpack(x), rows, f, band, quantity)
        r = (H[:, band_lines] - rows[:, band_lines]).ravel()
        return np.concatenate([r.real, r.imag])

    x0 = np.concatenate([np.log(-poles.real / scale), poles.imag / scale])
    solution = scipy.optimize.least_squares(residual, x0, method="lm", xtol=1e-14, ftol=1e-14, gtol=1e-14)
    refined = unpack(solution.x)
    if not np.all(np.isfinite(refined)) or solution.cost > 0.5 * np.sum(residual(x0) ** 2) * 1.0001:
        return poles
    return refined


# ---------------------------------------------------------------------------------------------
# single-pole fits (no extra library)
# ---------------------------------------------------------------------------------------------
def fit_measured_modes(measured, max_modes: int = 12, band_fraction: float = 0.08) -> MeasuredModes:
    """Global single-pole fits around the peaks of the summed measured FRF magnitudes.

    Parameters
    ----------
    measured : FRFResult
    max_modes : int
        Largest peaks kept.
    band_fraction : float
        Half-width of the band fitted around a peak, relative to its frequency.

    Returns
    -------
    MeasuredModes
        ``method='single-pole'``.
    """
    from scipy.signal import find_peaks

    f, H = measured.frequencies_hz, np.nan_to_num(measured.H)
    total = np.abs(H).reshape(-1, len(f)).sum(axis=0)
    peaks, props = find_peaks(total, prominence=0.05 * total.max())
    order = np.argsort(props["prominences"])[::-1][:max_modes]
    power = _POWER.get(measured.quantity, 0)
    poles, constants = [], []
    for k in sorted(peaks[order]):
        band = np.abs(f - f[k]) <= band_fraction * f[k]
        if band.sum() < 5:
            continue
        pole, residues = _single_pole(2 * np.pi * f[band], H[..., band].reshape(-1, band.sum()), 2 * np.pi * f[k])
        poles.append(pole)
        constants.append(residues / pole ** power)   # near the pole (i w)^k ~ lam^k
    poles = np.array(poles, dtype=complex)
    return _from_poles(poles, np.array(constants).reshape(len(poles), -1), measured, "single-pole")


def _single_pole(w, H, w_peak):
    """Least squares over ``lam`` of ``H_k = A_k / (i w - lam) + B_k``; returns lam and A."""
    import scipy.optimize

    scale = np.abs(H).max() or 1.0
    H = H / scale                      # the optimiser's tolerances are absolute

    def solve_linear(x):
        lam = complex(-abs(x[0]), x[1])
        basis = np.stack([1 / (1j * w - lam), np.ones_like(w, dtype=complex)], axis=1)
        coef, *_ = np.linalg.lstsq(basis, H.T, rcond=None)
        return lam, coef, basis

    def residual(x):
        _, coef, basis = solve_linear(x)
        r = (basis @ coef - H.T).ravel()
        return np.concatenate([r.real, r.imag])

    sol = scipy.optimize.least_squares(residual, [0.02 * w_peak, w_peak], x_scale=[0.02 * w_peak, w_peak])
    lam, coef, _ = solve_linear(sol.x)
    return lam, coef[0] * scale
