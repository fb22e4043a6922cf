"""Identification of model parameters from measured FRFs (least squares).

Each parameter is a dotted key of the model file (``suspensions.mount-FL.stiffness[2]``,
``suspensions.mount-FL.damping``, a whole array is scaled as one) or ``gain``
(a factor on every model FRF, e.g. a sensor calibration). The unknowns are the
logarithms of the factors that multiply the starting values, so that stiffness
and damping of different magnitudes are equally well scaled and stay positive.

Residual, stacked over speeds, FRFs and the frequency lines in the band::

    r = w (H_model - H_meas) / |H_meas|      (real and imaginary parts)

a relative complex error, so that every line counts alike whatever the FRF's
magnitude (``|H_meas|`` floored at 1e-3 of the RMS of the largest FRF of that
speed, a 60 dB dynamic range, so that anti-resonances and FRFs that vanish by
symmetry do not dominate). With coherence ``g2`` the weight is ``w = sqrt(g2 / (1 - g2))``
(the inverse of the relative standard error of an H1 estimate, up to the
number of averages), normalised to a mean of 1; ``1 - g2`` is floored at
1e-3. Uncertainties come from the Jacobian ``J`` and residual ``r`` at the optimum,
by the heteroscedasticity-consistent sandwich ``(J^T J)^-1 J^T diag(r^2) J (J^T J)^-1``
(see :func:`_covariance`). The fit is reported as
not converged when the optimiser did not converge, a parameter ends on a bound,
``J`` is rank deficient, or a parameter's log has a standard uncertainty above 1
(the data do not pin it within a factor e).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..linear_system import speed_linear_form
from .._arguments import _shown
from .frf import frf_of_checked_model

__all__ = ["FitResult", "fit"]

#: most starting points of one fit (each is a full least-squares search)
_MOST_STARTS = 100
_BOUND_FACTOR = 100.0
#: a parameter known only within a factor e (std of its log > 1) is not determined by the data
_MAX_LOG_STD = 1.0
#: forward-difference step of the Jacobian, relative to each log factor (scipy's diff_step);
#: below _SMALLEST_LOG the step is scipy's own at 0 instead (see _Problem.jacobian)
_DIFF_STEP = 1e-6
_SMALLEST_LOG = 1e-3


@dataclass(frozen=True)
class FitResult:
    """Fitted parameters with standard uncertainties.

    Attributes
    ----------
    keys : tuple of str
        Dotted keys (or ``gain``).
    start_values, values : tuple
        Values (scalars or lists, in the key's units) at the start and fitted.
    factors : ndarray, shape (n_params,)
        Fitted value / start value.
    std_relative : ndarray, shape (n_params,)
        Standard uncertainty of each factor, relative (std of the log).
    correlation : ndarray, shape (n_params, n_params)
    cost : float
        RMS of the weighted relative residual at the optimum.
    converged : bool
    message : str
        Why the optimiser stopped, or why the fit is not trusted.
    n_points : int
        Complex frequency lines used.
    start_costs : ndarray, shape (n_starts,)
        RMS residual reached from each starting point.
    """

    keys: tuple
    start_values: tuple
    values: tuple
    factors: np.ndarray
    std_relative: np.ndarray
    correlation: np.ndarray
    cost: float
    converged: bool
    message: str
    n_points: int
    start_costs: np.ndarray

    def fitted_model(self, model):
        """The model with the fitted values (``gain`` is not a model value)."""
        return _apply(model, self.keys, np.log(self.factors))

    def to_dataframe(self):
        """Table ``key,start,fitted,factor,std_relative`` (std_relative of the value)."""
        import pandas as pd

        return pd.DataFrame({"key": self.keys, "start": [_text(v) for v in self.start_values],
                             "fitted": [_text(v) for v in self.values], "factor": self.factors,
                             "std_relative": self.std_relative})

    def plot(self):
        """The parameter correlation matrix as an image."""
        from ..plotting.correlation import plot_fit_correlation

        return plot_fit_correlation(self)


def _text(value):
    return f"{value:.6g}" if np.ndim(value) == 0 else "[" + ", ".join(f"{v:.6g}" for v in np.ravel(value)) + "]"


def _apply(model, keys, logs):
    factors = {k: float(np.exp(x)) for k, x in zip(keys, logs) if k != "gain"}
    return model.scaled(factors) if factors else model


def _gain(keys, logs):
    return float(np.exp(logs[list(keys).index("gain")])) if "gain" in keys else 1.0


class _Problem:
    """The measured data cut to the band, with weights, and the residual function."""

    def __init__(self, model, measured, keys, band_hz, weighting):
        self.model, self.keys = model, tuple(keys)
        self.sets = []
        for res in measured:
            f = res.frequencies_hz
            keep = np.ones(len(f), bool) if band_hz is None else (f >= band_hz[0]) & (f <= band_hz[1])
            H = res.H[..., keep]
            valid = np.isfinite(H)
            H = np.where(valid, H, 0.0)
            weight = np.ones(H.shape)
            if weighting == "coherence" and res.coherence is not None:
                g2 = np.clip(np.nan_to_num(res.coherence[..., keep]), 0.0, 1.0)
                weight = np.sqrt(g2 / np.maximum(1.0 - g2, 1e-3))
            if keep.any():
                self.sets.append((res, f[keep], H, valid, weight * valid))
        n = sum(int(v.sum()) for *_, v, _ in self.sets)
        if n == 0:
            raise InputError("fit: no measured frequency line in the band "
                             f"{band_hz if band_hz is not None else ''}: nothing to fit")
        mean_w = np.mean(np.concatenate([w[v] for *_, v, w in self.sets]))
        if not mean_w > 0:
            raise InputError("fit: the coherence is 0 at every measured line in the band, so no line carries "
                             "weight: nothing to fit (weighting='none', --no-coherence, fits without it)")
        self.weights = [w / mean_w / _scale(H, v) for (_, _, H, v, w) in self.sets]
        self.n_points = n
        self.bar = None
        self.last = None                       # (logs, residual) of the last evaluation
        self.lower = self.upper = None         # the bounds of the logs, set by fit()

    def jacobian(self, logs):
        """Forward differences of :meth:`residual` in the log factors, shape (m, n): scipy's own
        ``diff_step`` (1e-6 relative to each log, sqrt(eps) at 0) except where that step shrinks
        below 1e-9 (a log within 1e-3 of 0: a factor near 1, the start): there, a step of
        1e-9 x |log| left the factor equal in every bit and the Jacobian exactly 0, and a
        parameter the data determine was reported as not determined."""
        logs = np.asarray(logs, dtype=float)
        base = self.last[1] if self.last is not None and np.array_equal(self.last[0], logs) else self.residual(logs)
        sign = np.where(logs >= 0, 1.0, -1.0)
        step = np.where(np.abs(logs) >= _SMALLEST_LOG, _DIFF_STEP * np.abs(logs),
                        np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(logs))) * sign
        step = np.where((logs + step > self.upper) | (logs + step < self.lower), -step, step)
        J = np.empty((base.size, logs.size))
        for i in range(logs.size):
            moved = logs.copy()
            moved[i] += step[i]
            J[:, i] = (self.residual(moved) - base) / (moved[i] - logs[i])
        return J

    def residual(self, logs):
        if self.bar is not None:
            self.bar.update(1)
        model = _apply(self.model, self.keys, logs)
        gain = _gain(self.keys, logs)
        parts = []
        for (res, f, H, valid, _), w in zip(self.sets, self.weights):
            Hm = frf_of_checked_model(model, res.speed, f, inputs=list(res.inputs), outputs=list(res.outputs),
                                      quantity=res.quantity).H * gain
            r = (w * (Hm - H))[valid]
            parts += [r.real, r.imag]
        result = np.concatenate(parts)
        self.last = (np.array(logs, dtype=float), result)
        return result


def _scale(H, valid):
    """Denominator of the relative residual: ``|H|`` floored at 1e-3 of the RMS of the largest FRF."""
    magnitude = np.where(valid, np.abs(H), 0.0)
    rms = np.sqrt(np.mean(magnitude ** 2, axis=-1, keepdims=True))
    return np.maximum(magnitude, 1e-3 * np.maximum(rms, rms.max()))


def fit(model, measured, params, bounds=None, band_hz=None, weighting: str = "coherence", starts: int = 3,
        seed: int = 0, progress: bool = False, max_evaluations: int = 400) -> FitResult:
    """Fit model parameters to measured FRFs.

    Parameters
    ----------
    model : Model
        The starting point (values of the keys are the starting values).
    measured : FRFResult or list of FRFResult
        Measured FRFs (one per speed), named after the model's sensors and excitations.
    params : list of str
        Dotted keys (positive values) or ``'gain'``.
    bounds : dict[str, (float, float)], optional
        Bounds on each key's **factor** relative to its start (default 1/100 to 100).
    band_hz : (float, float), optional
        Frequency band used [Hz].
    weighting : {'coherence', 'none'}
    starts : int
        Starting points: the model's values, then ``starts - 1`` log-uniform draws within the bounds.
    seed : int
        Seed of those draws.
    progress : bool
        tqdm bar counting model evaluations (with the current start).
    max_evaluations : int
        Model evaluations allowed per start.

    Returns
    -------
    FitResult
    """
    import scipy.optimize

    measured = [measured] if not isinstance(measured, (list, tuple)) else list(measured)
    keys = _check_params(model, params)
    speed_linear_form(model)   # a mass matrix rounding leaves singular: refused, as every analysis does
    if weighting not in ("coherence", "none"):
        raise InputError(f"weighting {weighting!r}: expected 'coherence' or 'none'")
    if starts < 1:
        raise InputError(f"starts = {starts}: expected at least 1")
    if starts > _MOST_STARTS:
        raise InputError(f"starts = {starts}: expected at most {_MOST_STARTS} starting points")
    lower, upper = _log_bounds(keys, bounds)
    for key, low, high in zip(keys, lower, upper):
        _check_changeable(model, key, float(np.exp(low)), float(np.exp(high)))
    problem = _Problem(model, measured, keys, band_hz, weighting)
    problem.lower, problem.upper = lower, upper
    rng = np.random.default_rng(seed)
    points = [np.zeros(len(keys))] + [rng.uniform(lower, upper) for _ in range(starts - 1)]
    outcomes = []
    if progress:
        from .._progress import tqdm

        problem.bar = tqdm(desc="fit (model evaluations)", unit="eval")
    try:
        for k, x0 in enumerate(points):
            if problem.bar is not None:
                problem.bar.set_postfix_str(f"start {k + 1}/{len(points)}")
            outcomes.append(scipy.optimize.least_squares(
                problem.residual, np.clip(x0, lower, upper), jac=problem.jacobian, bounds=(lower, upper),
                x_scale=1.0, max_nfev=max_evaluations, xtol=1e-12, ftol=1e-12, gtol=1e-12))
    finally:
        if problem.bar is not None:
            problem.bar.close()
    costs = np.array([np.sqrt(2 * o.cost / len(o.fun)) for o in outcomes])
    best = outcomes[int(np.argmin(costs))]
    return _result(model, keys, best, costs, problem.n_points, lower, upper)


#: what a fit can scale, said in every refusal of a key
FITTABLE = ("a key of a magnitude of the dynamics (a mass, inertia, stiffness or damping such as "
            "suspensions.NAME.stiffness, a transmission's ratio, a journal bearing's viscosity or geometry, a "
            "shaft's diameter or modulus) or 'gain'")
_PLACE = "places or orients a part: no magnitude a factor can scale"
#: fields a factor cannot fit, and why: scaling a direction leaves it the same after normalising
#: (a fit of spin_axis ran to its end and said the data did not determine it)
_NOT_SCALED = {**dict.fromkeys(("spin_axis", "center_of_mass", "position", "axes", "direction", "load_direction",
                                "start", "axial_position", "axial_offset", "coupling_position", "gravity",
                                "phase_deg", "pressure_angle"), _PLACE),
               "driver_teeth": "counts teeth: a whole number, no magnitude a factor can scale",
               "speeds_rpm": "is the speeds of a bearing's table, not a property of the machine",
               "element_length": "sets the mesh of a shaft, not a property of the machine",
               **dict.fromkeys(("radial_clearance", "allowable_stress", "grade", "service_speed_rpm"),
                               "enters no FRF")}


def _unfittable(model, key: str) -> str:
    """Why ``key`` cannot be fitted ('' when it can): a text or boolean, a place or direction, a
    count, a value that enters no FRF (an unbalance, a clearance)."""
    import re

    value = model.get(key)
    field = re.sub(r"\[.*$", "", key.rpartition(".")[2])
    flat = np.ravel(np.asarray(value, dtype=object))
    if any(isinstance(v, (str, bool, np.bool_)) or v is None for v in flat):
        return "it holds no number (a fitted value is scaled)"
    if field in _NOT_SCALED:
        return f"{field} {_NOT_SCALED[field]}"
    if key.startswith("unbalances."):
        return "an unbalance enters no FRF"
    try:
        np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return "it holds no number or array of numbers (a fitted value is scaled)"
    return ""


def _check_params(model, params):
    keys = [params] if isinstance(params, str) else list(params)
    if not keys:
        raise InputError("fit: give at least one parameter (a dotted key such as suspensions.mount-FL.stiffness)")
    if len(set(keys)) != len(keys):
        raise InputError(f"fit: a parameter is given twice in {', '.join(keys)}")
    for key in keys:
        if key == "gain":
            continue
        if (why := _unfittable(model, key)):
            raise InputError(f"fit: {key} = {_shown(model.get(key))}: {why}; expected {FITTABLE}")
        value = np.asarray(model.get(key), dtype=float)
        if not np.all(value >= 0) or not np.any(value > 0):
            raise InputError(f"fit: {key} = {model.get(key)!r}: a fitted value must be > 0 at the start "
                             "(the fit scales it by a positive factor)")
    return tuple(keys)


#: a parameter the model refuses to change by this factor either way is fixed by other keys
_NUDGE = 1.001


def _check_changeable(model, key: str, low: float, high: float) -> None:
    """Refuse a parameter the fit cannot scale over its bounds (factors ``low`` .. ``high``):
    one the model fixes (a speed ratio fixed by the reference rotor or a transmission), or one
    whose bound gives a model that is refused (a polar inertia beyond twice the diametral).
    Without this the fit stopped at the first such trial with the model's refusal of a value
    the user never wrote (``speed_ratio = 1.0000000149``)."""
    if key == "gain":
        return
    value = model.get(key)
    nudged = [_refusal(model, key, f) for f in (_NUDGE, 1 / _NUDGE)]
    if all(nudged) and key.rpartition(".")[2] == "speed_ratio":
        raise InputError(f"fit: {key} = {value!r}: expected a parameter the model lets change, but a rotor's "
                         "speed ratio is fixed by the reference rotor (ratio 1) and the transmissions from it "
                         "(fit a transmission's ratio, transmissions.N.ratio, instead)")
    if all(nudged):
        raise InputError(f"fit: {key} = {value!r}: expected a parameter the model lets change, but it refuses "
                         f"any other value ({_why(nudged[0])}); fit the keys that fix it instead")
    for factor, end in ((high, "upper"), (low, "lower")):
        problem = _refusal(model, key, factor)
        if problem:
            raise InputError(f"fit: {key} = {value!r}: expected bounds within which the model stays valid, but at "
                             f"its {end} bound (factor {factor:.6g}) it is refused ({_why(problem)}); give "
                             "narrower bounds (--bound-factor)")


def _refusal(model, key: str, factor: float) -> str:
    """The model's refusal of ``key`` scaled by ``factor`` ('' when it is valid)."""
    try:
        model.scaled({key: factor})
    except InputError as error:
        return str(error)
    return ""


def _why(message: str) -> str:
    """A model's refusal without its file name (the file holds the start, not the trial)."""
    head, _, rest = message.partition(": [")
    return "[" + rest if rest else message


def _log_bounds(keys, bounds):
    bounds = dict(bounds or {})
    unknown = set(bounds) - set(keys)
    if unknown:
        raise InputError(f"fit: bounds given for {', '.join(sorted(unknown))}, which is not fitted")
    lower, upper = [], []
    for key in keys:
        lo, hi = bounds.get(key, (1 / _BOUND_FACTOR, _BOUND_FACTOR))
        if not 0 < lo < 1 < hi:
            raise InputError(f"fit: bounds of {key} = ({lo}, {hi}): expected factors 0 < low < 1 < high "
                             "around the starting value")
        lower.append(np.log(lo))
        upper.append(np.log(hi))
    return np.array(lower), np.array(upper)


def _covariance(J, r):
    """Heteroscedasticity-consistent covariance of the log factors (White's sandwich, HC1).

    ``(J^T J)^-1 J^T diag(r^2) J (J^T J)^-1 m / (m - n)``: the noise of measured FRFs is not
    uniform on the relative scale (anti-resonances, the noise floor), and the textbook
    ``s^2 (J^T J)^-1`` then understates the scatter by a factor of about two (checked by
    Monte Carlo on the gear machine). Infinite where ``J`` is singular.

    Returns
    -------
    cov : ndarray, shape (n, n)
    singular : ndarray, shape (n,)
        Singular values of ``J``.
    """
    m, n = J.shape
    _, singular, vt = np.linalg.svd(J, full_matrices=False)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        bread = (vt.T * np.where(singular > 0, 1 / singular ** 2, np.inf)) @ vt
        meat = (J * r[:, None] ** 2).T @ J
        cov = bread @ meat @ bread * m / max(m - n, 1)
    if not np.all(np.isfinite(cov)) or not np.all(singular > 0):
        cov = np.full((n, n), np.inf)
    return cov, singular


def _result(model, keys, best, costs, n_points, lower, upper):
    J, r = best.jac, best.fun
    m, n = J.shape
    cov, singular = _covariance(J, r)
    std = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(std, std)
    converged, message = best.status > 0, best.message
    at_bound = np.isclose(best.x, lower, atol=1e-6) | np.isclose(best.x, upper, atol=1e-6)
    undetermined = ~np.isfinite(std) | (std > _MAX_LOG_STD)
    if singular.min() < 1e-8 * singular.max() or undetermined.any():
        converged = False
        weak = keys[int(np.argmax(np.where(np.isfinite(std), std, np.inf)))]
        message = (f"the measured FRFs do not determine the parameters: {weak} hardly changes them, or two "
                   "parameters change them alike (Jacobian rank deficient); fit fewer parameters or add data")
    elif at_bound.any():
        converged = False
        message = (f"{', '.join(k for k, b in zip(keys, at_bound) if b)} ended on a bound: the optimum lies "
                   "outside the bounds (widen them, or check the model and the data)")
    elif best.status <= 0:
        message = f"the optimiser stopped before converging: {best.message}"
    fitted = _apply(model, keys, best.x)
    values = tuple(_get(fitted, k, best.x, keys) for k in keys)
    starts = tuple(_get(model, k, np.zeros(len(keys)), keys) for k in keys)
    return FitResult(keys=tuple(keys), start_values=starts, values=values, factors=np.exp(best.x),
                     std_relative=std, correlation=corr, cost=float(np.sqrt(2 * best.cost / m)),
                     converged=bool(converged), message=str(message), n_points=n_points,
                     start_costs=costs)


def _get(model, key, logs, keys):
    if key == "gain":
        return _gain(keys, logs)
    value = model.get(key)
    return float(value) if np.ndim(value) == 0 else [float(v) for v in np.ravel(value)]
