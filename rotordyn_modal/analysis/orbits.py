"""Orbits at probe pairs: the ellipse that two sensors at one point trace in a harmonic.

Two sensors at the same point of the same body (typically two proximity probes
in a bearing housing, 90 degrees apart), reading the same kind of motion along
directions normal to the spin axis ``e``, see the point's motion in the plane
normal to ``e``. With ``u`` the first sensor's direction and ``w = e x u``, a
harmonic ``D(t) = Re((D_u u + D_w w) e^{i w t})`` traces an ellipse; in complex
notation ``z = D_u + i D_w`` it is ``A_f e^{i w t} + A_b e^{-i w t}`` with::

    A_f = (D_u + i D_w) / 2,   A_b = conj(D_u - i D_w) / 2

Semi-axes ``|A_f| + |A_b|`` and ``| |A_f| - |A_b| |``; the major axis lies at
``(arg A_f + arg A_b) / 2`` from ``u`` towards ``w``; the orbit turns about
``+e`` when ``|A_f| > |A_b|``. It precesses *forward* when it turns the way
the exciting rotor spins.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.geometry import cross

__all__ = ["ProbePairs", "probe_pairs", "orbit_ellipses", "PRECESSION_TOLERANCE"]

#: |(|A_f|^2 - |A_b|^2) / (|A_f|^2 + |A_b|^2)| (= 2ab / (a^2 + b^2)) below this is a straight line
PRECESSION_TOLERANCE = 1e-3
_NORMAL_TOLERANCE = 1e-6
_SAME_POINT = 1e-9  # m


@dataclass(frozen=True)
class ProbePairs:
    """Pairs of sensors that together see a point's orbit.

    Attributes
    ----------
    names : tuple of (str, str)
        The two sensors of each pair (x probe, y probe).
    indices : ndarray of int, shape (n_pairs, 2)
        Their positions among the outputs.
    to_plane : ndarray, shape (n_pairs, 2, 2)
        Maps the two readings to the in-plane components ``(D_u, D_w)``.
    """

    names: tuple
    indices: np.ndarray
    to_plane: np.ndarray

    def __len__(self) -> int:
        return len(self.names)


def probe_pairs(model, sensors) -> ProbePairs:
    """Pair the given sensors that share a point, a body and a measure, with directions
    normal to the spin axis and not parallel (in the given order, two at a time).

    Parameters
    ----------
    model : Model
    sensors : sequence of Sensor

    Returns
    -------
    ProbePairs
    """
    e = np.asarray(model.spin_axis, dtype=float)
    e0, e1, e2 = e.tolist()
    directions = [np.asarray(s.direction, dtype=float) for s in sensors]
    listed = [d.tolist() for d in directions]
    positions = [np.asarray(s.position, dtype=float).tolist() for s in sensors]
    groups: dict = {}
    for index, sensor in enumerate(sensors):
        d0, d1, d2 = listed[index]
        if abs(d0 * e0 + d1 * e1 + d2 * e2) > _NORMAL_TOLERANCE:
            continue
        key = (sensor.rotor, sensor.measure, tuple(round(x / _SAME_POINT) for x in positions[index]))
        groups.setdefault(key, []).append(index)
    names, indices, transforms = [], [], []
    for members in groups.values():
        while len(members) >= 2:
            first = members.pop(0)
            normal = cross(e, directions[first])                              # e x u
            w = normal.tolist()
            partner = next((k for k in members
                            if abs(listed[k][0] * w[0] + listed[k][1] * w[1] + listed[k][2] * w[2]) > 0.1), None)
            if partner is None:
                continue
            members.remove(partner)
            d = directions[partner]
            transforms.append(_unit_lower_inverse(float(d @ directions[first]), float(d @ normal)))
            names.append((sensors[first].name, sensors[partner].name))
            indices.append((first, partner))
    return ProbePairs(names=tuple(names), indices=np.array(indices, dtype=int).reshape(-1, 2),
                      to_plane=np.array(transforms).reshape(-1, 2, 2))


def _unit_lower_inverse(a, b):
    """``numpy.linalg.inv([[1, 0], [a, b]])`` for ``b != 0``; written out where LAPACK's LU does
    not pivot (|a| <= 1, unit directions): the same numbers (``0 - a`` times the reciprocal of
    ``b``), signed zeros included."""
    if not abs(a) <= 1.0:
        return np.linalg.inv(np.array([[1.0, 0.0], [a, b]]))
    r = 1.0 / b
    return [[1.0, 0.0], [(0.0 - a) * r, r]]


#: an orbit whose smaller circular part (forward or backward) is at most this fraction of the
#: larger is a circle: its inclination is 0 (a circular response computes its other part as
#: round-off, ~1e-16 of it, whose phase would make the angle noise: 0.02 deg beside 180 deg)
CIRCLE = 1e-9


def orbit_ellipses(plane, spin_sign):
    """Semi-axes, inclination and precession of harmonic orbits.

    Parameters
    ----------
    plane : ndarray, shape (..., 2), complex
        In-plane amplitudes ``(D_u, D_w)``.
    spin_sign : array_like, broadcastable to ``plane.shape[:-1]``
        +1 where the exciting rotor spins about +e, -1 about -e.

    Returns
    -------
    major, minor : ndarray [same unit as ``plane``]
    inclination_deg : ndarray
        Angle of the major axis from the first probe's direction towards ``e x u``, in [0, 180);
        0 for a circle (the smaller of the forward and backward parts below :data:`CIRCLE` of
        the larger: a circle has no major axis, and the angle of a part that is round-off is noise).
    precession : ndarray of float
        Signed ratio ``2ab / (a^2 + b^2)``: +1 circular forward, -1 circular backward.
    """
    forward = 0.5 * (plane[..., 0] + 1j * plane[..., 1])
    backward = 0.5 * np.conj(plane[..., 0] - 1j * plane[..., 1])
    f, b = np.abs(forward), np.abs(backward)
    major, minor = f + b, np.abs(f - b)
    inclination = np.degrees(0.5 * (np.angle(forward) + np.angle(backward))) % 180.0
    inclination = np.where(np.minimum(f, b) <= CIRCLE * np.maximum(f, b), 0.0, inclination)
    with np.errstate(invalid="ignore", divide="ignore"):
        turning = np.where(f * f + b * b > 0, (f * f - b * b) / (f * f + b * b), 0.0)
    return major, minor, inclination, turning * np.asarray(spin_sign)


def precession_labels(ratios) -> np.ndarray:
    """'forward', 'backward' or 'none' (a straight-line orbit) from signed precession ratios."""
    ratios = np.asarray(ratios)
    return np.where(ratios > PRECESSION_TOLERANCE, "forward",
                    np.where(ratios < -PRECESSION_TOLERANCE, "backward", "none"))
