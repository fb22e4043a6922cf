"""Large rotations: Euler vector, Zhilin tensor, and the axial + transverse split (Sorokin & Zhang 2018, docs/theory-large-rotations.md).

Conventions (derivation in ``docs/theory-large-rotations.md``):

* ``v`` is an Euler (rotation) vector, ``theta = |v|`` its angle [rad].
* ``L(v)`` is the rotation tensor (Rodrigues):
  ``L = cos(theta) E + (1 - cos(theta))/theta^2 v v^T + sin(theta)/theta skew(v)``.
* ``B(v)`` is Zhilin's tensor: if ``dL/dt = skew(omega) L`` (``omega`` the angular velocity in
  the fixed frame), then ``omega = B(v) dv/dt`` with
  ``B = sin(theta)/theta E + (theta - sin(theta))/theta^3 v v^T + (1 - cos(theta))/theta^2 skew(v)``.
* ``B^-1(v) = E - skew(v)/2 + (1 - (theta/2) cot(theta/2))/theta^2 skew(v)^2`` (closed form,
  singular at ``theta = 2 pi``).
* A rotation is split as ``L = L(gamma) L(phi e)``: first an axial rotation ``phi`` about the
  fixed unit vector ``e``, then a transverse rotation with Euler vector ``gamma``, ``gamma . e = 0``.
  The split is unique for a transverse angle ``|gamma| < pi`` and has no limit on ``phi``.

Every function takes and returns plain arrays (one vector of shape (3,)); the bodies use
only operations that numba compiles, so the simulation compiles them unchanged.
Conversions to and from matrices and quaternions go through
:class:`scipy.spatial.transform.Rotation`.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "skew", "rotation_tensor", "zhilin_tensor", "zhilin_inverse", "zhilin_derivative",
    "axial_rotation", "transverse_basis", "split_rotation", "compose_split", "split_rates",
    "angular_velocity_from_split", "to_scipy", "SERIES_ANGLE",
]

#: below this angle [rad] the coefficient functions use their Taylor series (cancellation-free)
SERIES_ANGLE = 0.05


def skew(v):
    """Cross-product matrix: ``skew(v) @ a == np.cross(v, a)``.

    Parameters
    ----------
    v : ndarray, shape (3,)

    Returns
    -------
    ndarray, shape (3, 3)
    """
    out = np.zeros((3, 3))
    out[0, 1] = -v[2]
    out[0, 2] = v[1]
    out[1, 0] = v[2]
    out[1, 2] = -v[0]
    out[2, 0] = -v[1]
    out[2, 1] = v[0]
    return out


def _coefficients(t2):
    """``sin t / t, (1 - cos t)/t^2, (t - sin t)/t^3`` for ``t^2 = t2``, series near zero."""
    if t2 < SERIES_ANGLE * SERIES_ANGLE:
        a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0))
        c = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0))
        b = 1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0))
        return a, c, b
    t = np.sqrt(t2)
    s, co = np.sin(t), np.cos(t)
    return s / t, (1.0 - co) / t2, (t - s) / (t2 * t)


def rotation_tensor(v):
    """Rotation tensor ``L(v)`` of an Euler vector (docs/theory-large-rotations.md §1).

    Parameters
    ----------
    v : ndarray, shape (3,)
        Euler vector [rad].

    Returns
    -------
    ndarray, shape (3, 3)
        Proper orthogonal matrix; ``L @ a`` is ``a`` turned by ``|v|`` about ``v``.

    Examples
    --------
    >>> import numpy as np
    >>> np.round(rotation_tensor(np.array([0, 0, np.pi / 2])) @ [1.0, 0, 0], 12) + 0.0
    array([0., 1., 0.])
    """
    t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    a, c, _ = _coefficients(t2)
    cos_t = 1.0 - c * t2  # cos = 1 - (1 - cos)
    return cos_t * np.eye(3) + c * np.outer(v, v) + a * skew(v)


def zhilin_tensor(v):
    """Zhilin's tensor ``B(v)``: the angular velocity is ``omega = B(v) dv/dt``.

    Parameters
    ----------
    v : ndarray, shape (3,)
        Euler vector [rad].

    Returns
    -------
    ndarray, shape (3, 3)
        ``omega`` [rad/s] in the fixed frame from ``dv/dt`` [rad/s]. ``B(v) v = v`` and
        ``B(v) = L(v) B(v)^T``; singular at ``|v| = 2 pi``.
    """
    t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    a, c, b = _coefficients(t2)
    return a * np.eye(3) + b * np.outer(v, v) + c * skew(v)


def _inverse_coefficient(t2):
    """``(1 - (t/2) cot(t/2)) / t^2`` for ``t^2 = t2``, series near zero."""
    if t2 < SERIES_ANGLE * SERIES_ANGLE:
        return 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
    t = np.sqrt(t2)
    return (1.0 - 0.5 * t / np.tan(0.5 * t)) / t2


def zhilin_inverse(v):
    """Closed-form inverse of Zhilin's tensor: ``dv/dt = B^-1(v) omega``.

    ``B^-1 = E - skew(v)/2 + k skew(v)^2``, ``k = (1 - (theta/2) cot(theta/2)) / theta^2``.

    Parameters
    ----------
    v : ndarray, shape (3,)
        Euler vector [rad], ``|v| < 2 pi``.

    Returns
    -------
    ndarray, shape (3, 3)
    """
    t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    k = _inverse_coefficient(t2)
    s = skew(v)
    return np.eye(3) - 0.5 * s + k * (s @ s)


def zhilin_derivative(v, w):
    """Directional derivative of Zhilin's tensor: ``d/ds B(v + s w)`` at ``s = 0``.

    Used for the angular acceleration ``d omega/dt = B(v) v'' + [D B(v)[v']] v'``.

    Parameters
    ----------
    v, w : ndarray, shape (3,)
        Euler vector [rad] and direction [rad].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    a, c, b = _coefficients(t2)
    if t2 < SERIES_ANGLE * SERIES_ANGLE:  # derivatives divided by theta
        da = -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0
        dc = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0
        db = -1.0 / 60.0 + t2 / 1260.0 - t2 * t2 / 60480.0
    else:
        t = np.sqrt(t2)
        s, co = np.sin(t), np.cos(t)
        da = (t * co - s) / (t2 * t)
        dc = (t * s - 2.0 * (1.0 - co)) / (t2 * t2)
        db = (1.0 - co) / (t2 * t2) - 3.0 * (t - s) / (t2 * t2 * t)
    vw = v[0] * w[0] + v[1] * w[1] + v[2] * w[2]
    return (da * vw * np.eye(3) + db * vw * np.outer(v, v) + b * (np.outer(w, v) + np.outer(v, w))
            + dc * vw * skew(v) + c * skew(w))


def axial_rotation(phi, e):
    """``L(phi e)``: rotation by ``phi`` [rad] about the unit vector ``e`` (any angle).

    Returns
    -------
    ndarray, shape (3, 3)
    """
    s, co = np.sin(phi), np.cos(phi)
    return co * np.eye(3) + (1.0 - co) * np.outer(e, e) + s * skew(e)


def transverse_basis(e):
    """Two unit vectors ``e1, e2`` normal to the unit vector ``e``, with ``e1 x e2 = e``.

    ``e1`` is the model z-axis made normal to ``e`` (the model x-axis when ``e`` is along z),
    ``e2 = e x e1``: for ``e = x``, ``e1 = z`` and ``e2 = -y``. This is the unbalance phase
    reference of ``rotordyn_modal.analysis.unbalance.phase_reference``: phases turn from
    ``e1`` towards ``e2``.

    Returns
    -------
    ndarray, shape (3, 2)
        Columns ``e1, e2``.
    """
    e = np.asarray(e, dtype=float)
    e = e / np.linalg.norm(e)
    axis = np.array([0.0, 0.0, 1.0])
    if np.linalg.norm(axis - (axis @ e) * e) <= 1e-6:
        axis = np.array([1.0, 0.0, 0.0])
    e1 = axis - (axis @ e) * e
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(e, e1)])


def split_rotation(rotation, e, phi_reference=0.0):
    """Split a rotation into axial angle and transverse Euler vector: ``L = L(gamma) L(phi e)``.

    Parameters
    ----------
    rotation : scipy.spatial.transform.Rotation or array_like, shape (3, 3)
    e : array_like, shape (3,)
        Unit axial vector (the rotor axis at rest).
    phi_reference : float
        The axial angle is returned within ``pi`` of this value [rad] (a rotation matrix
        knows ``phi`` only modulo ``2 pi``; give the previous value to count turns).

    Returns
    -------
    phi : float
        Axial angle [rad].
    gamma : ndarray, shape (3,)
        Transverse Euler vector [rad], ``gamma . e = 0``, ``|gamma| <= pi``: the rotation
        about ``e x f`` that takes ``e`` to ``f = L e`` along the shortest arc.
    """
    matrix = _as_matrix(rotation)
    e = np.asarray(e, dtype=float)
    f = matrix @ e
    normal = np.cross(e, f)
    sine = np.linalg.norm(normal)
    angle = np.arctan2(sine, float(e @ f))
    if sine < 1e-12 and e @ f < 0:
        raise ValueError("transverse angle is pi: the split is singular")
    gamma = normal * (angle / sine) if sine > 1e-300 else np.zeros(3)
    axial = rotation_tensor(gamma).T @ matrix  # L(phi e)
    n = transverse_basis(e)[:, 0]
    phi = np.arctan2(float(e @ np.cross(n, axial @ n)), float(n @ axial @ n))
    phi += 2.0 * np.pi * np.round((phi_reference - phi) / (2.0 * np.pi))
    return float(phi), gamma


def compose_split(phi, gamma, e):
    """``L(gamma) L(phi e)`` as a matrix (the inverse of :func:`split_rotation`).

    Returns
    -------
    ndarray, shape (3, 3)
    """
    return rotation_tensor(np.asarray(gamma, dtype=float)) @ axial_rotation(phi, np.asarray(e, dtype=float))


def split_rates(gamma, omega, e):
    """Kinematic equations of the split (docs/theory-large-rotations.md §3, paper eqs. 6 and 8).

    ``omega_phi = e . B^-1(gamma) omega / (e . B^-1(gamma) L(gamma) e)`` and
    ``d gamma/dt = B^-1(gamma) (omega - omega_phi L(gamma) e)``.

    Parameters
    ----------
    gamma : ndarray, shape (3,)
        Transverse Euler vector [rad] (``gamma . e = 0``, ``|gamma| < pi``).
    omega : ndarray, shape (3,)
        Angular velocity in the fixed frame [rad/s].
    e : ndarray, shape (3,)
        Unit axial vector.

    Returns
    -------
    omega_phi : float
        ``d phi / dt`` [rad/s].
    gamma_dot : ndarray, shape (3,)
        ``d gamma / dt`` [rad/s], normal to ``e``.
    """
    inverse = zhilin_inverse(gamma)
    axis = rotation_tensor(gamma) @ e
    omega_phi = (e @ (inverse @ omega)) / (e @ (inverse @ axis))
    return omega_phi, inverse @ (omega - omega_phi * axis)


def angular_velocity_from_split(gamma, gamma_dot, omega_phi, e):
    """docs/theory-large-rotations.md §3, paper eqs. (3)-(5): ``omega = B(gamma) d gamma/dt + omega_phi L(gamma) e``.

    Returns
    -------
    ndarray, shape (3,)
        Angular velocity in the fixed frame [rad/s].
    """
    return zhilin_tensor(gamma) @ gamma_dot + omega_phi * (rotation_tensor(gamma) @ e)


def to_scipy(v):
    """A :class:`scipy.spatial.transform.Rotation` from an Euler vector [rad]."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_rotvec(np.asarray(v, dtype=float))


def _as_matrix(rotation):
    if hasattr(rotation, "as_matrix"):
        return rotation.as_matrix()
    return np.asarray(rotation, dtype=float)
