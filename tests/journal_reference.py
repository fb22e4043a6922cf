"""Independent reference computations for the plain short journal bearing (test helper).

Shares no code with ``rotordyn_modal.elements.journal_bearing``: everything here starts from the short-bearing
Reynolds equation written in a fixed frame and evaluates it by quadrature,

* :func:`film_force`: the film force on the journal for any position and velocity, by
  ``scipy.integrate.quad_vec`` of the pressure over the arc where it is positive;
* :func:`static_equilibrium`: the journal position under a load, by root-finding on that force;
* :func:`coefficients_by_differences`: the eight coefficients by fourth-order central finite
  differences of that force;
* :func:`coefficients_by_quadrature`: the same coefficients from the derivatives of the
  pressure integrand (the arc's end points carry zero pressure, so their motion does not
  enter to first order), fast enough for root-finding over speed;
* :func:`lund_threshold`: Lund's stability threshold of a symmetric rigid rotor in two
  identical short bearings, from :func:`coefficients_by_quadrature`.

Frame: ``x``, ``y`` with ``e = x × y`` the spin axis; the circumferential angle ``a`` is
measured from ``x`` towards ``y``; the speed ``w`` is positive about ``e``. Film thickness at
``a`` for the journal centre at ``(X, Y)``: ``h = c - X cos a - Y sin a``. The short-bearing
Reynolds equation ``h³ p_zz = 6 mu w h_a + 12 mu h_t`` with ``p = 0`` at ``z = ±L/2`` gives
``p = (6 mu w h_a + 12 mu h_t) (z² - L²/4) / (2 h³)``, whose integral over the length is
``P(a) = -(6 mu w h_a + 12 mu h_t) L³ / (12 h³)``; where it is negative the film cavitates
(``P = 0``). The film pushes the journal along ``-n``, ``n = (cos a, sin a)``:
``F = -R ∫ P n da``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize

GRAVITY = 9.80665  # standard gravity [m/s²]; the load on each bearing of lund_threshold


@dataclass(frozen=True)
class Bearing:
    """Plain journal bearing: diameter, length, radial clearance [m], viscosity [Pa s]."""

    diameter: float
    length: float
    clearance: float
    viscosity: float

    @property
    def radius(self) -> float:
        return 0.5 * self.diameter


def _arc_and_pressure(bearing, position, velocity, speed):
    """Positive-pressure arc (start, end) [rad] and the pressure per unit angle ``P(a)`` [N/m]."""
    X, Y = position
    Xd, Yd = velocity
    mu, c, L = bearing.viscosity, bearing.clearance, bearing.length
    # G(a) = 6 mu w h_a + 12 mu h_t = g_cos cos a + g_sin sin a, with
    # h_a = X sin a - Y cos a and h_t = -Xd cos a - Yd sin a
    g_cos = -6 * mu * speed * Y - 12 * mu * Xd
    g_sin = 6 * mu * speed * X - 12 * mu * Yd
    # G = rho cos(a - a_G) is negative (P positive) for a - a_G in (pi/2, 3 pi/2)
    a_g = np.arctan2(g_sin, g_cos)

    def pressure(a):
        h = c - X * np.cos(a) - Y * np.sin(a)
        return -(g_cos * np.cos(a) + g_sin * np.sin(a)) * L**3 / (12 * h**3)

    return (a_g + 0.5 * np.pi, a_g + 1.5 * np.pi), pressure


def film_force(bearing: Bearing, position, velocity, speed: float) -> np.ndarray:
    """Film force on the journal [N], shape (2,), by quadrature over the positive-pressure arc.

    ``position`` (2,) [m] and ``velocity`` (2,) [m/s] of the journal centre; ``speed`` [rad/s].
    """
    (start, end), pressure = _arc_and_pressure(bearing, position, velocity, speed)
    # both components at once: the error is controlled relative to the force's magnitude
    integral = integrate.quad_vec(lambda a: pressure(a) * np.array([np.cos(a), np.sin(a)]),
                                  start, end, epsabs=0.0, epsrel=1e-12, limit=200)[0]
    return -bearing.radius * integral


def _rotation(angle):
    return np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


def static_equilibrium(bearing: Bearing, load: float, speed: float):
    """Journal position under ``load`` [N] along ``+x`` at ``speed`` [rad/s].

    The bearing is axisymmetric, so the film force's magnitude depends only on the
    eccentricity: root-finding (Brent) on ``|F(eps c, 0)| = load``, then the position is turned
    about ``e`` until the film force points along ``-x``.

    Returns
    -------
    position : ndarray (2,) [m]; eccentricity [-]; attitude angle, from ``x`` to the position
    about ``e`` [rad].
    """
    c = bearing.clearance

    def force_on_x_axis(eps):
        return film_force(bearing, (eps * c, 0.0), (0.0, 0.0), speed)

    eps = optimize.brentq(lambda eps: np.hypot(*force_on_x_axis(eps)) - load, 1e-12, 1 - 1e-4,
                          xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=200)
    fx, fy = force_on_x_axis(eps)
    turn = np.pi - np.arctan2(fy, fx)
    position = _rotation(turn) @ np.array([eps * c, 0.0])
    return position, eps, np.arctan2(position[1], position[0])


def _derivative(function, step):
    """Fourth-order central difference of ``function(h)`` at ``h = 0`` with step ``step``."""
    return (function(-2 * step) - 8 * function(-step) + 8 * function(step)
            - function(2 * step)) / (12 * step)


def coefficients_by_differences(bearing: Bearing, load: float, speed: float, step: float = 1e-3):
    """Stiffness and damping (2, 2) [N/m], [N s/m] by finite differences of :func:`film_force`.

    Coefficients in the load frame (``x`` along the load) at the static equilibrium:
    ``K[:, j] = -dF/dq_j``, ``C[:, j] = -dF/dq'_j``. The position step is ``step`` times
    ``min(eps, 1 - eps) c``: the force's magnitude varies on the scale of the minimum film
    ``(1 - eps) c``, its direction on the scale ``eps c`` (the arc turns with the journal's
    angular position). The velocity step is ``|speed| / 2`` times that, since a velocity ``v``
    enters the Reynolds equation as a position ``2 e × v / speed`` would. Truncation error
    ``O(step⁴)`` (about 1e-12 relative for the default step), round-off from the quadrature's
    ``1e-12`` relative error over ``step``: about 1e-9.

    Returns
    -------
    stiffness, damping : ndarray (2, 2); eccentricity; attitude angle [rad]
    """
    position, eps, attitude = static_equilibrium(bearing, load, speed)
    dq = step * min(eps, 1 - eps) * bearing.clearance
    dv = 0.5 * abs(speed) * dq
    unit = np.eye(2)
    stiffness = -np.column_stack([
        _derivative(lambda h: film_force(bearing, position + h * unit[j], (0, 0), speed), dq)
        for j in range(2)])
    damping = -np.column_stack([
        _derivative(lambda h: film_force(bearing, position, h * unit[j], speed), dv)
        for j in range(2)])
    return stiffness, damping, eps, attitude


def coefficients_by_quadrature(bearing: Bearing, eps: float, speed: float):
    """Load, speed-independent parts and coefficients at eccentricity ``eps`` [-].

    With the journal at ``(eps c, 0)`` and the static arc, ``F = -R ∫ P n da`` and

    * ``K = R ∫ n (3 P / h nᵀ + mu w L³ / (2 h³) (e × n)ᵀ) da``: the first term from ``h``
      (``dh/dX = -cos a``, ``dh/dY = -sin a``), the second from the wedge term, in which a
      position change enters as ``-6 mu w (e × n) · dX``;
    * ``C = mu R L³ ∫ n nᵀ / h³ da``: the squeeze term ``12 mu h_t = -12 mu n · X'``,

    then everything is turned into the load frame.

    Returns
    -------
    load [N], stiffness (2, 2) [N/m], damping (2, 2) [N s/m] in the load frame, attitude
    angle [rad].
    """
    mu, c, L, R = bearing.viscosity, bearing.clearance, bearing.length, bearing.radius
    X = eps * c
    (start, end), pressure = _arc_and_pressure(bearing, (X, 0.0), (0.0, 0.0), speed)

    def integrand(a):
        n = np.array([np.cos(a), np.sin(a)])
        e_cross_n = np.array([-np.sin(a), np.cos(a)])
        h = c - X * np.cos(a)
        p = pressure(a)
        return np.concatenate([
            -R * p * n,
            (R * np.outer(n, 3 * p / h * n + mu * speed * L**3 / (2 * h**3) * e_cross_n)).ravel(),
            (mu * R * L**3 * np.outer(n, n) / h**3).ravel()])

    values = integrate.quad_vec(integrand, start, end, epsabs=0.0, epsrel=1e-12, limit=200)[0]
    force, stiffness, damping = values[:2], values[2:6].reshape(2, 2), values[6:].reshape(2, 2)
    load = np.hypot(*force)
    x_load = -force / load  # the load is opposite to the film force
    frame = np.column_stack([x_load, [-x_load[1], x_load[0]]])  # columns x, y = e × x
    attitude = np.arctan2(-x_load[1], x_load[0])  # the position (1, 0) seen from the load frame
    return load, frame.T @ stiffness @ frame, frame.T @ damping @ frame, attitude


def lund_parameters(stiffness, damping):
    """Lund's effective stiffness [N/m] and squared whirl frequency [rad²/s²] (per unit mass · m).

    From ``det(K + i w C - w² m I) = 0`` with real ``w``: the imaginary part gives
    ``m w² = K_eq = (kxx cyy + kyy cxx - kxy cyx - kyx cxy) / (cxx + cyy)``, the real part
    ``w² = ((K_eq - kxx)(K_eq - kyy) - kxy kyx) / (cxx cyy - cxy cyx)``.
    """
    (kxx, kxy), (kyx, kyy) = stiffness
    (cxx, cxy), (cyx, cyy) = damping
    k_eq = (kxx * cyy + kyy * cxx - kxy * cyx - kyx * cxy) / (cxx + cyy)
    w2 = ((k_eq - kxx) * (k_eq - kyy) - kxy * kyx) / (cxx * cyy - cxy * cyx)
    return k_eq, w2


def lund_threshold(mass_per_bearing, diameter, length, clearance, viscosity, *, gravity=GRAVITY):
    """Oil-whirl threshold of a symmetric rigid rotor in two identical plain short bearings.

    The rotor (mass ``2 m``) loads each bearing with ``m g``; in the cylindrical mode each
    bearing carries ``m`` and the rotor is unstable when ``m (gamma w)² > K_eq`` (Lund). The
    threshold is the highest eccentricity (lowest speed) at which ``m w_whirl² = K_eq``, found
    by Brent's method on the eccentricity, the speed following from the load capacity
    (the film force scales with speed at a fixed position).

    Parameters
    ----------
    mass_per_bearing : float
        ``m`` [kg], half the rotor's mass.
    diameter, length, clearance : float
        Journal diameter, bearing length, radial clearance [m].
    viscosity : float
        Dynamic viscosity [Pa s].
    gravity : float, optional
        [m/s²]; the static load on each bearing is ``mass_per_bearing * gravity``.

    Returns
    -------
    threshold_speed : float
        [rad/s].
    whirl_frequency_ratio : float
        Whirl frequency at the threshold over the speed [-].
    """
    bearing = Bearing(diameter, length, clearance, viscosity)
    load = mass_per_bearing * gravity

    def speed_and_parameters(eps):
        unit_load, stiffness, damping, _ = coefficients_by_quadrature(bearing, eps, 1.0)
        speed = load / unit_load  # at a fixed position the force grows with speed
        k_eq, w2 = lund_parameters(speed * stiffness, damping)
        return speed, k_eq, w2

    def margin(eps):  # > 0 unstable
        speed, k_eq, w2 = speed_and_parameters(eps)
        return mass_per_bearing * w2 / k_eq - 1.0

    grid = np.concatenate([np.geomspace(1e-6, 0.02, 12, endpoint=False), np.linspace(0.02, 0.98, 49)])
    values = np.array([margin(eps) for eps in grid])
    # scan from heavy load (low speed, stable) towards light load; first crossing
    unstable = np.flatnonzero(values > 0)
    if unstable.size == 0 or unstable[-1] == grid.size - 1:
        raise ValueError("no threshold on the eccentricity grid")
    upper = unstable[-1]
    eps = optimize.brentq(margin, grid[upper], grid[upper + 1], xtol=1e-300, rtol=1e-15)
    speed, k_eq, w2 = speed_and_parameters(eps)
    return speed, np.sqrt(w2) / speed
