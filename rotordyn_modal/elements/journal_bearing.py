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

__all__ = ["JournalBearing", "short_journal_bearing", "THINNEST_FILM", "rigid_rotor_journal_loads", "JournalLoadOverSpeed",
           "LIGHT_LOAD_STIFFNESS"]

_PI2 = np.pi**2
_A = 16.0 - _PI2  # recurring constant of the load capacity
#: the symmetric part of the film's dimensionless stiffness ``K clearance / load`` (rows and columns
#: along and across the load) as the eccentricity goes to zero, a light load or a high speed: the
#: limit of eq. 12.11 (docs/theory.md §12), ``4/pi`` along the load and ``8/pi`` across it. The
#: cross-coupled terms grow as ``1/eps`` there, but with opposite signs: their symmetric part
#: vanishes. Over all eccentricities the symmetric part's lower eigenvalue stays between about 0.6
#: and ``4/pi``, so the film of a journal carrying ``load`` holds it with about ``load / clearance``
#: at any speed
LIGHT_LOAD_STIFFNESS = np.diag([4.0 / np.pi, 8.0 / np.pi])
#: thinnest film [m] the coefficients are given for: at clearance * (1 - eccentricity) below a
#: nanometre (a few oil molecules) the continuum film of Reynolds' equation means nothing
THINNEST_FILM = 1e-9


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
    load : float or array_like, shape (N,)
        Magnitude of the static load on the journal [N]; one per speed where it changes with
        speed (a rotor on three or more journals with pedestals,
        :func:`rigid_rotor_journal_loads`).

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
            dict(diameter=diameter, length=length, clearance=clearance, viscosity=viscosity).items()}
    speed = _speeds(speed)
    data["load"] = _positive("load", load) if np.ndim(load) == 0 else _loads(load, speed.shape)
    sigma = (data["viscosity"] * np.abs(speed) * data["diameter"] * data["length"]**3
             / (8.0 * data["load"] * data["clearance"]**2))
    eps, film = _eccentricity(sigma)
    _check_film(speed, eps, film, sigma, data["load"], data["clearance"])
    # y -> -y for the journal turning the other way flips the off-diagonal terms
    mirror = np.where(speed[..., None, None] < 0, np.array([[1.0, -1.0], [-1.0, 1.0]]), 1.0)
    scale = data["load"] / data["clearance"]
    if np.ndim(scale):
        scale = scale[..., None, None]
    with np.errstate(all="ignore"):
        k, c = _dimensionless_coefficients(eps, film)
        stiffness = scale * mirror * k
        damping = scale / np.abs(speed)[..., None, None] * mirror * c
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


def _loads(load, shape) -> np.ndarray:
    """Loads [N], one per speed, or InputError unless each is a finite number > 0."""
    values = np.asarray(load, dtype=float)
    if values.shape != shape or not (np.all(np.isfinite(values)) and np.all(values > 0)):
        raise InputError(f"short journal bearing: load = {np.asarray(load).tolist()!r}: expected a "
                         f"finite number > 0, or one per speed (shape {shape})")
    return values


def _speeds(speed) -> np.ndarray:
    """``speed`` as a float array, or InputError for a non-finite or zero speed."""
    speed = np.asarray(speed, dtype=float)
    bad = ~np.isfinite(speed)
    if bad.any():
        raise InputError(f"short journal bearing: speed = {float(speed[bad].flat[0])!r} rad/s: "
                         "expected finite speeds")
    if (speed == 0).any():
        raise InputError("short journal bearing: speed = 0 rpm: a journal that does not turn has "
                         "no oil film (eccentricity 1); give a speed above zero (a sweep's first speed too)")
    return speed


def _check_film(speed, eps, film, sigma, load, clearance) -> None:
    """InputError at the first speed whose eccentricity is 1 to round-off, or whose thinnest
    film ``clearance * (1 - eps)`` (from ``film = 1 - eps**2`` to full precision) is below
    :data:`THINNEST_FILM`."""
    gap = clearance * film / (1.0 + eps)
    touching = ~(eps < 1.0) | ~(gap >= THINNEST_FILM)
    if touching.any():
        first = np.flatnonzero(touching.ravel())[0]
        rpm = to_rpm(float(speed.flat[first]))
        limit = "expected < 1" if not eps.flat[first] < 1.0 else (
            f"thinnest film {gap.flat[first]:.3g} m, expected at least {THINNEST_FILM:g} m, a few oil "
            "molecules, for the film theory to mean anything")
        raise InputError(
            f"short journal bearing: at speed {rpm:.6g} rpm the oil film cannot carry the load of "
            f"{float(np.broadcast_to(load, speed.shape).flat[first]):g} N: eccentricity {eps.flat[first]:.17g} ({limit}; Ocvirk load number "
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


def rigid_rotor_journal_loads(speed, *, stations, weight, spin_axis, diameter, length, clearance, viscosity,
                              pedestal_stiffness=None, pedestal_weight=None, flexibility=None, sag=None,
                              given_stations=(), given_loads=(), iterations: int = 60) -> np.ndarray:
    """Static load on each journal of a rigid rotor on three or more plain short journal bearings,
    with or without pedestals, at each speed: the statically indeterminate split solved by Newton (a
    flexible rotor's too, given its shaft's ``flexibility`` and ``sag``).

    A journal carrying the load ``F`` (a vector normal to the spin axis) sits at the film's offset
    ``d(F) = c eps (cos phi x + sin phi e x x)`` from its bearing's centre (``x = F / |F|``,
    ``eps`` and ``phi`` the short-bearing eccentricity and attitude angle of ``|F|`` at that
    speed); a pedestal of stiffness ``K_p`` settles by ``K_p^-1 (F + m_p g)`` under the journal's
    load and its own weight. The rigid rotor moves by ``u + s theta`` at the station ``s`` from its
    centre of mass. Unknowns ``F_i, u, theta``; equations (docs/theory.md §12, "A rigid rotor on
    three or more journals")::

        d_i(F_i) + K_p,i^-1 (F_i + m_p,i g) - u - s_i theta = 0      (each journal)
        sum F_i = W,   sum s_i F_i = 0                              (force and moment balance)

    A flexible rotor's journal ``i`` moves by ``u + s_i theta + w_i - sum_k phi_ik F_k`` instead:
    ``w_i`` the shaft's sag under its weight and ``phi`` its flexibility, both on two of its
    journals held rigidly (the reference line ``u + s theta``; for loads in balance the free shaft
    bends as the shaft held there does, its two reactions being those journals' loads), so the
    journal's equation gains ``sum_k phi_ik F_k - w_i`` and Newton's matrix ``phi``.

    Journals whose load is given (``given_loads``) are fixed forces on the rotor: the journals
    solved here carry the rest, ``sum F_i = W - sum F_g``, ``sum s_i F_i = -sum s_g F_g`` (a
    flexible rotor's ``sag`` then includes the bending under them, ``w_i - sum_g phi_ig F_g``).

    The Jacobian of ``d_i`` is the inverse of the film's stiffness ``K`` of that load (a small
    journal motion ``delta`` changes the film force by ``K delta``), so Newton's matrix is built
    from the same coefficients the analyses use. The start is the light-load solution (each film a
    spring ``pi mu |speed| D L**3 / (8 c**3)`` turned by 90 degrees), the split ``rdm.static`` gives.

    Parameters
    ----------
    speed : array_like, shape (S,)
        The rotor's own speed [rad/s], signed about ``spin_axis``, nonzero.
    stations : array_like, shape (N,)
        Each journal's axial position from the rotor's centre of mass [m].
    weight : array_like, shape (3,)
        The rotor's weight normal to the spin axis, model axes [N], nonzero.
    spin_axis : array_like, shape (3,)
    diameter, length, clearance, viscosity : array_like, shape (N,)
        Each journal's data [m, m, m, Pa s].
    pedestal_stiffness : sequence of (ndarray, shape (3, 3), or None), length N, optional
        Model axes, positive definite normal to the spin axis [N/m]; None: the journal's bearing
        is held rigidly.
    pedestal_weight : sequence of (ndarray, shape (3,), or None), length N, optional
        Each pedestal's weight, model axes [N] (its part normal to the spin axis counts).
    flexibility : array_like, shape (N, N), optional
        A flexible rotor's: ``phi_ik`` [m/N], the shaft's deflection at journal ``i`` under a unit
        force at journal ``k``, the shaft held at two of its journals (an axisymmetric shaft: the
        same along any direction normal to the axis). None: a rigid rotor.
    sag : array_like, shape (N, 3), optional
        With ``flexibility``: the shaft's deflection [m] at each journal under its weight, held the
        same way, model axes.
    given_stations : array_like, shape (G,), optional
        The axial positions [m] from the centre of mass of journals whose load is given.
    given_loads : array_like, shape (G, 3), optional
        Those journals' loads [N], model axes: the force each puts on its bearing.
    iterations : int
        Newton steps at most.

    Returns
    -------
    ndarray, shape (S, N, 3)
        The force each journal puts on its bearing [N], model axes (normal to the spin axis).

    Raises
    ------
    InputError
        A zero or non-finite speed, or no equilibrium found in ``iterations`` steps.
    """
    speed = _speeds(np.atleast_1d(speed))
    e = np.asarray(spin_axis, dtype=float) / np.linalg.norm(spin_axis)
    weight = np.asarray(weight, dtype=float)
    weight = weight - (weight @ e) * e
    plane = np.array([weight / np.linalg.norm(weight), np.cross(e, weight / np.linalg.norm(weight))])
    films = np.array([diameter, length, clearance, viscosity], dtype=float)          # (4, N)
    s = np.asarray(stations, dtype=float)
    n = len(s)
    soft = np.zeros((n, 2, 2))
    settle = np.zeros((n, 2))
    for i in range(n):
        if pedestal_stiffness is not None and pedestal_stiffness[i] is not None:
            soft[i] = np.linalg.inv(plane @ np.asarray(pedestal_stiffness[i], dtype=float) @ plane.T)
            if pedestal_weight is not None and pedestal_weight[i] is not None:
                settle[i] = soft[i] @ (plane @ np.asarray(pedestal_weight[i], dtype=float))
    phi = np.zeros((n, n)) if flexibility is None else np.asarray(flexibility, dtype=float)
    if sag is not None:
        settle = settle - np.asarray(sag, dtype=float) @ plane.T      # the shaft's own sag: a settlement the other way
    given = np.asarray(given_loads, dtype=float).reshape(-1, 3)
    scale = float(np.linalg.norm(weight))
    total = np.r_[plane @ (weight - given.sum(0)) if len(given) else [scale, 0.0],            # the force balance
                  plane @ -(np.asarray(given_stations, dtype=float) @ given) if len(given) else [0.0, 0.0]]
    light = np.pi * films[3] * np.abs(speed)[:, None] * films[0] * films[1]**3 / (8 * films[2]**3)   # (S, N)
    turn = np.sign(speed)[:, None, None, None] * np.array([[0.0, -1.0], [1.0, 0.0]])            # R(+-90 deg)
    state = _newton_step(np.zeros((len(speed), n, 2)), turn / light[..., None, None], soft, s, settle, total,
                         np.zeros((len(speed), n, 2)), phi)
    done = np.zeros(len(speed), dtype=bool)
    for _ in range(iterations):
        loads = state[:, :2 * n].reshape(-1, n, 2)
        offset, compliance = _film_offset(loads, speed, films, scale)
        step = _newton_step(loads, compliance, soft, s, settle, total, offset, phi) - state
        done |= np.max(np.abs(step[:, :2 * n]), axis=1) <= 1e-13 * scale
        if done.all():
            return state[:, :2 * n].reshape(-1, n, 2) @ plane
        state = _damped(state, np.where(done[:, None], 0.0, step), offset, speed, films, soft, s, settle, scale,
                        phi)
    bad = int(np.flatnonzero(~done)[0])
    raise InputError(f"journal loads: no static equilibrium of the rigid rotor on its films and pedestals found at "
                     f"{to_rpm(float(speed[bad])):.6g} rpm (the films cannot carry the rotor there: start the sweep "
                     "higher, or give each journal's load)")


def _misfit(state, offset, soft, s, settle, clearance, phi):
    """The journals' compatibility misfit (12.16) in clearances, squared and summed: (S,)."""
    n = len(s)
    loads, u, theta = state[:, :2 * n].reshape(-1, n, 2), state[:, 2 * n:2 * n + 2], state[:, 2 * n + 2:]
    gap = (offset + np.einsum("nij,snj->sni", soft, loads) + np.einsum("nk,skj->snj", phi, loads) + settle
           - u[:, None] - s[None, :, None] * theta[:, None])
    return np.sum((gap / clearance[:, None])**2, axis=(1, 2))


def _damped(state, step, offset, speed, films, soft, s, settle, scale, phi, halvings: int = 40):
    """``state + a step``, ``a`` halved (per speed) from 1 until the compatibility misfit falls:
    the films' offset saturates at the clearance, where a full Newton step from a light-load
    guess overshoots. The balance equations, linear, hold along the whole step. Each speed is
    searched alone, and only while its step is being halved; a speed already converged (a step of
    0) is not searched at all (its misfit, at round-off, never fell: 40 halvings of nothing)."""
    n = len(s)
    before = _misfit(state, offset, soft, s, settle, films[2], phi)
    length = np.ones(len(state))
    trying = np.flatnonzero(np.any(step != 0, axis=1))     # the speeds whose step is still being halved
    for _ in range(halvings if len(trying) else 0):
        trial = state[trying] + length[trying, None] * step[trying]
        trial_offset = _film_offset(trial[:, :2 * n].reshape(-1, n, 2), speed[trying], films, scale, False)[0]
        after = _misfit(trial, trial_offset, soft, s, settle, films[2], phi)
        worse = ~(after <= (1 - 1e-4 * length[trying]) * before[trying]) & (before[trying] > 0)
        if not worse.any():
            break
        trying = trying[worse]                     # each speed's own halving: the others are settled
        length[trying] *= 0.5
    return state + length[:, None] * step


def _film_offset(loads, speed, films, scale, compliance: bool = True):
    """Each journal's offset from its bearing's centre (S, N, 2) and the film's compliance
    ``K^-1`` (S, N, 2, 2), in the plane's axes, under the loads (S, N, 2); without
    ``compliance`` (a line search's trial) the offset alone, and None."""
    magnitude = np.linalg.norm(loads, axis=-1)
    safe = np.maximum(magnitude, 1e-12 * scale)
    x = np.where(magnitude[..., None] > 0, loads / safe[..., None], [1.0, 0.0])
    y = np.stack([-x[..., 1], x[..., 0]], -1)
    diameter, length, clearance, viscosity = films
    sigma = viscosity * np.abs(speed)[:, None] * diameter * length**3 / (8.0 * safe * clearance**2)
    eps, film = _eccentricity(sigma)
    phi = np.sign(speed)[:, None] * np.arctan2(np.pi * np.sqrt(film), 4.0 * eps)
    offset = (clearance * eps)[..., None] * (np.cos(phi)[..., None] * x + np.sin(phi)[..., None] * y)
    if not compliance:
        return offset, None
    mirror = np.where(speed[:, None, None, None] < 0, np.array([[1.0, -1.0], [-1.0, 1.0]]), 1.0)
    with np.errstate(all="ignore"):
        local = (safe / clearance)[..., None, None] * mirror * _dimensionless_coefficients(eps, film)[0]
    frame = np.stack([x, y], -1)                                   # columns x, y
    stiffness = frame @ local @ np.swapaxes(frame, -1, -2)
    return offset, np.linalg.inv(stiffness)


def _newton_step(loads, compliance, soft, s, settle, total, offset, phi):
    """The state (S, 2N + 4): loads, ``u``, ``theta``, of one Newton step on the journals' equations, the films linearised
    about ``loads``: ``d(F_new) ~ offset + compliance (F_new - loads)``; ``soft`` (N, 2, 2) the
    pedestals' compliance, ``settle`` (N, 2) their settlement under their own weight (less a
    flexible shaft's sag), ``phi`` (N, N) the shaft's flexibility (zeros: a rigid rotor)."""
    count, n = loads.shape[:2]
    size = 2 * n + 4
    matrix = np.zeros((count, size, size))
    right = np.zeros((count, size))
    eye = np.eye(2)
    matrix[:, :2 * n, :2 * n] = np.kron(phi, eye)                 # the shaft's flexibility, each direction alike
    for i in range(n):
        rows = slice(2 * i, 2 * i + 2)
        matrix[:, rows, rows] += compliance[:, i] + soft[i]
        matrix[:, rows, 2 * n:2 * n + 2] = -eye
        matrix[:, rows, 2 * n + 2:] = -s[i] * eye
        matrix[:, 2 * n:2 * n + 2, rows] = eye
        matrix[:, 2 * n + 2:, rows] = s[i] * eye
        right[:, rows] = np.einsum("sij,sj->si", compliance[:, i], loads[:, i]) - offset[:, i] - settle[i]
    right[:, 2 * n:] = total
    return np.linalg.solve(matrix, right[..., None])[..., 0]


class JournalLoadOverSpeed:
    """The static load of one journal of a rotor (rigid or flexible) on three or more journals, with or
    without pedestals, at any speed (:func:`rigid_rotor_journal_loads`; the rotor's journals share one
    solver, which remembers the loads at each speed it has solved).

    The cache is per speed, not per sweep: an analysis that evaluates its coefficients at a whole
    sweep and then again speed by speed (campbell's refinement, ``stiffness_at`` and ``damping_at``
    of one speed) solves each speed once. Each speed's solution does not depend on the others of its
    batch (Newton stops per speed, the line search halves per speed), so a speed solved in a sweep
    and alone give the same loads to the bit.

    Parameters
    ----------
    index : int
        The journal's place among the rotor's journals.
    solver : dict
        The keyword arguments of :func:`rigid_rotor_journal_loads` but ``speed``, and a
        ``"cache"`` dict shared by the rotor's journals (speed [rad/s] -> loads (N, 3) [N]).
    """

    _KEEP = 100_000   # speeds remembered per rotor (then forgotten all at once)

    def __init__(self, index: int, solver: dict):
        self.index, self.solver = index, solver

    def __call__(self, speeds) -> np.ndarray:
        """The force [N] this journal puts on its bearing at each own speed (S,) [rad/s], (S, 3)."""
        speeds = np.atleast_1d(np.asarray(speeds, dtype=float)).ravel().tolist()
        cache = self.solver["cache"]
        missing = [speed for speed in dict.fromkeys(speeds) if speed not in cache]
        if missing:
            arguments = {name: value for name, value in self.solver.items() if name != "cache"}
            solved = rigid_rotor_journal_loads(np.array(missing), **arguments)          # (M, N, 3)
            if len(cache) + len(missing) > self._KEEP:
                cache.clear()
            cache.update(zip(missing, solved))
        return np.array([cache[speed][self.index] for speed in speeds], dtype=float).reshape(len(speeds), 3)
