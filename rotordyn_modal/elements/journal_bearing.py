"""Plain short journal bearing: stiffness and damping of the oil film from physical data.

:func:`short_journal_bearing` gives the eight linear coefficients of a plain journal bearing by
short-bearing (Ocvirk) theory with the pi-film (half-Sommerfeld) cavitation condition, batched
over speeds. The derivation is in ``docs/theory.md`` section 12.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..errors import InputError
from ..units import to_rpm

__all__ = ["JournalBearing", "short_journal_bearing"]

_PI2 = np.pi**2
_A = 16.0 - _PI2  # recurring constant of the load capacity


class JournalBearing(NamedTuple):
    """Static equilibrium and linear coefficients of a journal bearing over speed.

    Frame: ``x`` along the static load (the direction in which the load pushes the journal),
    ``y = e × x`` with ``e`` the spin axis. For a small motion ``(dx, dy)`` of the journal about
    its static position, the film force on the journal is ``-K [dx, dy] - C [dx', dy']``.

    Attributes
    ----------
    stiffness : ndarray, shape (N, 2, 2)
        ``K`` [N/m], rows and columns ``(x, y)``.
    damping : ndarray, shape (N, 2, 2)
        ``C`` [N s/m], symmetric for the short bearing.
    eccentricity : ndarray, shape (N,)
        Journal offset over the radial clearance, in [0, 1) [-].
    attitude_angle : ndarray, shape (N,)
        Angle from ``x`` to the journal's offset, positive about ``e`` [rad]; it has the sign
        of the speed. The journal centre sits at ``eccentricity * clearance *
        (cos(attitude_angle), sin(attitude_angle))``.
    sommerfeld : ndarray, shape (N,)
        Sommerfeld number ``S = viscosity * n * diameter * length / load * (radius /
        clearance)**2`` with ``n = |speed| / (2 pi)`` in rev/s (Raimondi and Boyd) [-].
    """

    stiffness: np.ndarray
    damping: np.ndarray
    eccentricity: np.ndarray
    attitude_angle: np.ndarray
    sommerfeld: np.ndarray


def short_journal_bearing(speed, *, diameter, length, clearance, viscosity, load) -> JournalBearing:
    """Coefficients of a plain short journal bearing (Ocvirk) at each speed.

    The eccentricity solves the short-bearing load capacity ``(1 - eps**2)**2 / (eps *
    sqrt(16 eps**2 + pi**2 (1 - eps**2))) = sigma``, ``sigma = viscosity * |speed| * diameter
    * length**3 / (8 * load * clearance**2)`` (``= pi S (length / diameter)**2``), then
    ``K = load / clearance * k(eps)`` and ``C = load / (clearance * |speed|) * c(eps)``
    in closed form (docs/theory.md section 12). A negative speed gives the mirror image
    ``y -> -y``. Valid for ``length / diameter`` up to about 0.5.

    Parameters
    ----------
    speed : array_like, shape (N,) or scalar
        Journal angular speed about the spin axis ``e`` [rad/s], signed, nonzero.
    diameter, length, clearance : float
        Journal diameter, bearing length and radial clearance [m].
    viscosity : float
        Dynamic viscosity of the oil [Pa s].
    load : float
        Magnitude of the static load on the journal [N].

    Returns
    -------
    JournalBearing
        ``stiffness`` and ``damping`` of shape ``speed.shape + (2, 2)``, the other fields of
        shape ``speed.shape``.

    Raises
    ------
    InputError
        Non-positive or non-finite data, a zero or non-finite speed, or a speed at which the
        film cannot carry the load (eccentricity 1 to round-off).

    Examples
    --------
    >>> import numpy as np
    >>> b = short_journal_bearing([300.0, -300.0], diameter=0.05, length=0.02,
    ...                           clearance=50e-6, viscosity=0.03, load=500.0)
    >>> b.eccentricity.round(4)
    array([0.4842, 0.4842])
    >>> np.allclose(b.stiffness[1], b.stiffness[0] * [[1, -1], [-1, 1]])
    True
    """
    data = {name: _positive(name, value) for name, value in
            dict(diameter=diameter, length=length, clearance=clearance, viscosity=viscosity,
                 load=load).items()}
    speed = _speeds(speed)
    sigma = (data["viscosity"] * np.abs(speed) * data["diameter"] * data["length"]**3
             / (8.0 * data["load"] * data["clearance"]**2))
    eps, film = _eccentricity(sigma)
    _check_film(speed, eps, sigma, data["load"])
    # y -> -y for the journal turning the other way flips the off-diagonal terms
    mirror = np.where(speed[..., None, None] < 0, np.array([[1.0, -1.0], [-1.0, 1.0]]), 1.0)
    scale = data["load"] / data["clearance"]
    with np.errstate(all="ignore"):
        k, c = _dimensionless_coefficients(eps, film)
        stiffness = scale * mirror * k
        damping = (scale / np.abs(speed))[..., None, None] * mirror * c
    _check_finite(speed, stiffness, damping, sigma)
    return JournalBearing(
        stiffness=stiffness,
        damping=damping,
        eccentricity=eps,
        attitude_angle=np.sign(speed) * np.arctan2(np.pi * np.sqrt(film), 4.0 * eps),
        sommerfeld=sigma / np.pi * (data["diameter"] / data["length"])**2,
    )


def _positive(name: str, value) -> float:
    """``value`` as a float, or InputError unless it is one finite number > 0."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = np.nan
    if np.ndim(value) != 0 or not (np.isfinite(number) and number > 0):
        raise InputError(f"short journal bearing: {name} = {value!r}: expected a finite number > 0")
    return number


def _speeds(speed) -> np.ndarray:
    """``speed`` as a float array, or InputError for a non-finite or zero speed."""
    speed = np.asarray(speed, dtype=float)
    bad = ~np.isfinite(speed)
    if bad.any():
        raise InputError(f"short journal bearing: speed = {float(speed[bad].flat[0])!r} rad/s: "
                         "expected finite speeds")
    if (speed == 0).any():
        raise InputError("short journal bearing: speed = 0 rpm: a journal that does not turn has "
                         "no oil film (eccentricity 1); start the speed sweep above zero")
    return speed


def _check_film(speed, eps, sigma, load) -> None:
    """InputError at the first speed whose eccentricity is 1 to round-off."""
    touching = ~(eps < 1.0)
    if touching.any():
        first = np.flatnonzero(touching.ravel())[0]
        rpm = to_rpm(float(speed.flat[first]))
        raise InputError(
            f"short journal bearing: at speed {rpm:.6g} rpm the oil film cannot carry the load of "
            f"{load:g} N: eccentricity {eps.flat[first]:.17g} (expected < 1; Ocvirk load number "
            f"{sigma.flat[first]:.3g}); raise the speed (start the sweep higher), the viscosity or "
            "the bearing length, or reduce the clearance or the load")


def _check_finite(speed, stiffness, damping, sigma) -> None:
    """InputError at the first speed whose coefficients overflow (a vanishing eccentricity)."""
    bad = ~(np.isfinite(stiffness).all(axis=(-2, -1)) & np.isfinite(damping).all(axis=(-2, -1)))
    if bad.any():
        first = np.flatnonzero(bad.ravel())[0]
        raise InputError(
            f"short journal bearing: at speed {to_rpm(float(speed.flat[first])):.6g} rpm the "
            f"coefficients overflow (Ocvirk load number {sigma.flat[first]:.3g}, eccentricity "
            "0 to round-off): expected bearing data in SI units (m, Pa s, N)")


def _eccentricity(sigma):
    """Eccentricity ``eps`` and ``1 - eps**2`` from the Ocvirk load number ``sigma`` [-].

    The load capacity ``sigma = (1 - eps**2)**2 / (eps sqrt(pi**2 + A eps**2))``,
    ``A = 16 - pi**2``, is decreasing in ``eps``; ``eps**2 <= 1/2`` exactly when ``sigma >=
    1 / (2 sqrt(16 + pi**2))``. There it is solved for ``eps`` (light load, ``eps ~ 1 / (pi
    sigma)``), otherwise for ``v = 1 - eps**2`` (heavy load, ``v ~ 2 sqrt(sigma)``), so that the
    small one of ``eps`` and ``1 - eps**2`` keeps its relative precision.
    """
    light = sigma >= 0.5 / np.sqrt(16.0 + _PI2)
    # the unused branch gets a sigma whose root, 0, is its starting point: it stops at once
    s_light = np.where(light, sigma, np.inf)
    s_heavy = np.where(light, 0.0, sigma)

    def light_load(eps):  # eps sqrt(pi^2 + A eps^2) - (1 - eps^2)^2 / sigma, increasing
        root, film = np.sqrt(_PI2 + _A * eps**2), 1 - eps**2
        return (eps * root - film**2 / s_light,
                root + _A * eps**2 / root + 4 * eps * film / s_light)

    def heavy_load(v):  # v^2 - sigma sqrt((1 - v)(16 - A v)), increasing
        root = np.sqrt((1 - v) * (16 - _A * v))
        return v**2 - s_heavy * root, 2 * v + s_heavy * (16 + _A - 2 * _A * v) / (2 * root)

    with np.errstate(divide="ignore"):
        eps = _increasing_root(light_load, np.minimum(1 / (np.pi * s_light), np.sqrt(0.5)),
                               np.sqrt(0.5))
    v = _increasing_root(heavy_load, np.minimum(2 * np.sqrt(s_heavy), 0.5), 0.5)
    return np.where(light, eps, np.sqrt(1 - v)), np.where(light, 1 - eps**2, v)


def _increasing_root(function, start, upper_end, iterations: int = 100):
    """Root in [0, upper_end] of increasing functions (one per element), by bracketed Newton.

    ``function(t)`` returns the values and derivatives; a Newton step that leaves the bracket
    is replaced by bisection. Each element stops when its step is below round-off, so the
    result does not depend on the other elements of the batch.
    """
    t, lower, upper = start, np.zeros_like(start), np.full_like(start, upper_end)
    done = np.zeros(np.shape(start), dtype=bool)
    for _ in range(iterations):
        value, slope = function(t)
        lower = np.where(value <= 0, t, lower)
        upper = np.where(value >= 0, t, upper)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = t - value / slope
        converged = (value == 0) | (np.abs(newton - t) <= 4 * np.finfo(float).eps * t)
        inside = (newton >= lower) & (newton <= upper)
        step = np.where(converged | inside, newton, 0.5 * (lower + upper))
        t = np.where(done, t, step)
        done |= converged
        if done.all():
            break
    return t


def _dimensionless_coefficients(eps, film):
    """``k = K clearance / load`` and ``c = C clearance |speed| / load``, shape (..., 2, 2).

    For positive speed, from ``eps`` and ``film = 1 - eps**2`` (docs/theory.md eq. 12.11).
    """
    e2, root = eps**2, np.sqrt(film)
    h0 = (_PI2 * film + 16 * e2)**-1.5
    k = _matrix(4 * h0 * (_PI2 * (1 + 2 * e2) + 32 * e2 * (1 + e2) / film),
                np.pi * h0 * (_PI2 * film * (1 + 2 * e2) + 32 * e2 * (1 + e2)) / (eps * root),
                -np.pi * h0 * (_PI2 * film**2 - 16 * e2**2) / (eps * root),
                4 * h0 * (_PI2 * (1 + film) + 16 * e2))
    cross = 8 * h0 * (_PI2 * (1 + 2 * e2) - 16 * e2)
    c = _matrix(2 * np.pi * h0 * (_PI2 * film**2 + 48 * e2) / (eps * root),
                cross, cross,
                2 * np.pi * h0 * root * (_PI2 * (1 + 2 * e2) - 16 * e2) / eps)
    return k, c


def _matrix(xx, xy, yx, yy):
    """Stack four arrays of one shape into 2x2 matrices, shape (..., 2, 2)."""
    return np.stack([np.stack([xx, xy], -1), np.stack([yx, yy], -1)], -2)
