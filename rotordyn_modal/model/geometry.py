"""Shift matrices (docs/theory.md §2) and small vector helpers.

Conventions (see ``docs/theory.md``):

* ``A_PO = skew(P - O)``, so that ``A_PO @ a = (P - O) x a`` (eq. 2);
  ``A_PO.T = -A_PO = A_OP`` (eq. 3).
* ``B_PO = [[I, 0], [-A_PO, I]]`` moves a generalized force
  ``T = [F, C]`` from point O to point P: ``T_P = B_PO @ T_O`` (eqs. 7-9);
  ``B_NO = B_NP @ B_PO`` (eq. 10) and ``inv(B_PO) = B_OP`` (eq. 11).
* Its transpose moves small motions the other way: if ``q_P = [u_P, theta]``
  is the motion of a rigid body at P, its motion at O is ``q_O = B_PO.T @ q_P``
  (seed eq. 60 reads ``[u_1, w] = B_S1.T [u_S, w]``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["GearMesh", "gear_mesh", "skew", "shift_cross", "shift_matrix", "shift_matrices", "cross", "point_motion_row", "point_motion_rows",
           "point_force_column",
           "transverse_axes"]


def skew(vector) -> np.ndarray:
    """Cross-product matrix: ``skew(a) @ b == np.cross(a, b)``.

    Parameters
    ----------
    vector : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    v = np.asarray(vector, dtype=float)
    if v.shape == (3,):   # the common case, without the broadcast assignments' overhead
        x, y, z = v.tolist()
        return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def shift_cross(p, o) -> np.ndarray:
    """docs/theory.md §2, eq. (2): ``A_PO``, the matrix of ``(P - O) x``.

    Parameters
    ----------
    p, o : array_like, shape (3,)
        Points P and O [m].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    return skew(np.asarray(p, dtype=float) - np.asarray(o, dtype=float))


def shift_matrix(p, o) -> np.ndarray:
    """docs/theory.md §2, eq. (8): ``B_PO``, moving a generalized force from O to P.

    Parameters
    ----------
    p, o : array_like, shape (3,)
        Points P and O [m].

    Returns
    -------
    ndarray, shape (6, 6)
        ``[[I, 0], [-A_PO, I]]``: ``T_P = B_PO @ T_O`` for ``T = [F (N), C (N m)]``.

    Examples
    --------
    >>> import numpy as np
    >>> B = shift_matrix([1.0, 0, 0], [0, 0, 0])
    >>> B @ [0, 1.0, 0, 0, 0, 0]    # a force along y at O seen from P = (1, 0, 0)
    array([ 0.,  1.,  0.,  0.,  0., -1.])
    """
    arm = np.asarray(p, dtype=float) - np.asarray(o, dtype=float)
    if arm.shape != (3,):
        out = np.eye(6)
        out[3:, :3] = -shift_cross(p, o)
        return out
    return shift_matrices(p, o)[0]


def shift_matrices(p, points) -> np.ndarray:
    """``shift_matrix(p, o)`` for each ``o`` of ``points`` (S, 3): shape (S, 6, 6), the same
    numbers (signed zeros included), made together.

    ``p`` may be a stack of points too (S, 3), with ``points`` one point or as many."""
    arms = (np.asarray(p, dtype=float) - np.asarray(points, dtype=float)).reshape(-1, 3).tolist()
    # [[I, 0], [-skew(arm), I]] written out for every arm (-skew's diagonal is -0.0, as the
    # negated zeros of skew are; a flat list makes the array fastest)
    values: list = []
    for x, y, z in arms:
        values += (1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0,
                   0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -0.0, z, -y, 1.0, 0.0, 0.0,
                   -z, -0.0, x, 0.0, 1.0, 0.0, y, -x, -0.0, 0.0, 0.0, 1.0)
    return np.array(values, dtype=float).reshape(-1, 6, 6)


def point_motion_row(point, reference, direction) -> np.ndarray:
    """Row ``r`` with ``r @ q`` = displacement of ``point`` along ``direction``: the one row of
    :func:`point_motion_rows`, shape (6,)."""
    return point_motion_rows([point], reference, [direction])[0]


def point_motion_rows(points, reference, directions) -> np.ndarray:
    """Rows ``r`` with ``r @ q`` = displacement of each point along its direction.

    ``q = [u, theta]`` is the small motion of the rigid stator at ``reference``;
    the displacement of P is ``u + theta x (P - S)``, so the row is
    ``[d, (P - S) x d]`` (written out in Python floats: a few points are made faster
    so than by numpy's small-array calls; :func:`cross`'s products and differences).

    Parameters
    ----------
    points, directions : array_like, shape (k, 3)
    reference : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (k, 6)
    """
    sx, sy, sz = np.asarray(reference, dtype=float).tolist()
    rows = []
    for point, direction in zip(points, directions):
        px, py, pz = np.asarray(point, dtype=float).tolist()
        d0, d1, d2 = np.asarray(direction, dtype=float).tolist()
        a0, a1, a2 = px - sx, py - sy, pz - sz
        rows.append((d0, d1, d2, a1 * d2 - a2 * d1, a2 * d0 - a0 * d2, a0 * d1 - a1 * d0))
    return np.array(rows, dtype=float).reshape(-1, 6)


def cross(a, b) -> np.ndarray:
    """``numpy.cross(a, b)``; for two 3-vectors written out (the same products and differences,
    so the same numbers, without numpy's overhead for small arrays).

    Parameters
    ----------
    a, b : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    a, b = np.asarray(a), np.asarray(b)
    if a.shape == b.shape == (3,) and a.dtype == b.dtype == np.float64:
        (a0, a1, a2), (b0, b1, b2) = a.tolist(), b.tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    return np.cross(a, b)


def point_force_column(point, reference, direction) -> np.ndarray:
    """Generalized force at ``reference`` of a unit force along ``direction`` at ``point``.

    Equal to :func:`point_motion_row` (reciprocity): ``B_SP @ [d, 0]``.

    Returns
    -------
    ndarray, shape (6,)
    """
    return point_motion_row(point, reference, direction)


def transverse_axes(spin_axis) -> np.ndarray:
    """Two unit axes ``a, b`` normal to the spin axis ``e``, with ``a x b = e``.

    ``a`` is the model axis that follows ``e``'s largest component in the cycle
    x -> y -> z -> x, made normal to ``e``: for ``e`` along x, y or z the pair is
    (y, z), (z, x) or (x, y). Rotors on bearings move along these axes.

    Parameters
    ----------
    spin_axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (2, 3): rows ``a`` and ``b``

    Examples
    --------
    >>> transverse_axes([1.0, 0.0, 0.0]).tolist()
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    e = np.asarray(spin_axis, dtype=float)
    e = e / np.linalg.norm(e)
    following = np.eye(3)[(int(np.argmax(np.abs(e))) + 1) % 3]
    a = following - (following @ e) * e
    a = a / np.linalg.norm(a)
    return np.array([a, cross(e, a)]) + 0.0


class GearMesh(NamedTuple):
    """Where a gear pair meshes (docs/theory.md §18), model axes.

    Attributes
    ----------
    driver_centre, driven_centre : ndarray, shape (3,) [m]
        The two spin axes where they cross the gear plane.
    distance : float
        Centre distance [m].
    radius : float
        The driver's pitch radius [m].
    pitch_point : ndarray, shape (3,) [m]
        ``driver_centre + radius u``, ``u`` the unit line of centres from driver to driven.
    direction : ndarray, shape (3,)
        Unit line of action ``n = s cos(alpha) (e x u) + sin(alpha) u``, ``s`` the sign of the
        driver's speed ratio: the tooth force on the driver driving at positive reference speed
        is ``-F n`` (F > 0), as in ``rdm.static``.
    """

    driver_centre: np.ndarray
    driven_centre: np.ndarray
    distance: float
    radius: float
    pitch_point: np.ndarray
    direction: np.ndarray


def gear_mesh(transmission, driver, driven, spin_axis) -> GearMesh | None:
    """The :class:`GearMesh` of a gear ``transmission`` between rotors ``driver`` and ``driven``
    (the plane through its ``position``, else the driver's centre of mass; the pitch radius
    ``driver_radius``, else ``a / (1 + ratio)``; ``pressure_angle`` [deg], else 20), or None when
    the two spin axes coincide."""
    e = np.asarray(spin_axis, dtype=float)
    plane = np.asarray(driver.center_of_mass if transmission.position is None else transmission.position,
                       dtype=float)
    centres = [np.asarray(r.center_of_mass, dtype=float) for r in (driver, driven)]
    on_driver, on_driven = (c + ((plane - c) @ e) * e for c in centres)
    distance = float(np.linalg.norm(on_driven - on_driver))
    if not distance > 0:
        return None
    u = (on_driven - on_driver) / distance
    radius = distance / (1.0 + transmission.ratio) if transmission.driver_radius is None else transmission.driver_radius
    angle = np.radians(20.0 if transmission.pressure_angle is None else transmission.pressure_angle)
    sense = -1.0 if driver.speed_ratio is not None and driver.speed_ratio < 0 else 1.0
    direction = sense * np.cos(angle) * np.cross(e, u) + np.sin(angle) * u
    return GearMesh(on_driver, on_driven, distance, float(radius), on_driver + radius * u, direction)
