"""Bearing coefficients: constant, tabulated over speed, or of a plain short journal bearing.

A bearing acts between a rotor and the stator (or the ground) at a point of the
rotor's spin axis. Its coefficients are 6x6 matrices in model axes acting on the
relative motion ``[u, theta]`` of the rotor at that point: radial stiffness and
damping (2x2, in the bearing's radial axes, cross-coupled and non-symmetric
allowed), an axial stiffness and damping, and a moment (tilt) stiffness and
damping (2x2). The rotation about the spin axis carries nothing: the spin is
fixed by the speed ratios.

Coefficients may depend on the carried rotor's own speed (signed about the spin
axis, rad/s): tables are interpolated linearly and refused outside their range;
a journal bearing's radial coefficients come from short-bearing theory at each
speed. :func:`evaluate` gives them for many speeds at once.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, ModelWarning

#: eccentricity of a journal bearing above which an analysis warns (once per bearing): the
#: thinnest film is under a tenth of the clearance, where short-bearing coefficients are rough
#: and a real bearing nears mixed lubrication (above 1 nm of film they are still given, see
#: :data:`rotordyn_modal.elements.journal_bearing.THINNEST_FILM`)
HIGH_ECCENTRICITY = 0.9
_WARNED: set = set()   # the bearings already warned about in this process

__all__ = ["BearingCoefficients", "JournalData", "evaluate", "local_to_model", "is_speed_dependent", "table_left",
           "light_load_stiffness"]


@dataclass(frozen=True)
class JournalData:
    """Physical data of a plain journal bearing (SI units).

    Attributes
    ----------
    diameter, length, clearance : float
        Journal diameter, bearing length and radial clearance [m].
    viscosity : float
        Dynamic viscosity of the oil [Pa s].
    load : float
        Static load on the journal [N], > 0.
    axes : ndarray, shape (3, 3)
        Rows ``x, y, e``: ``x`` the unit direction in which the load pushes the
        journal (normal to the spin axis), ``y = e x x``, ``e`` the spin axis. The
        film coefficients are computed in ``(x, y)``.
    load_over_speed : callable or None
        For a journal of a rotor (rigid or flexible) on three or more journals (three at least without a
        given ``load``), whose load moves with speed: own speeds (S,) [rad/s] to the load vectors (S, 3) [N], model axes
        (:class:`~rotordyn_modal.elements.journal_bearing.JournalLoadOverSpeed`); the film's
        coefficients then follow that load and its direction at each speed, ``load`` and ``axes``
        being the light-load films' split (a flexible rotor's: the continuous beam on rigid films and
        the pedestals' springs). None: ``load`` and ``axes`` at every speed.
    fixed_load : bool
        The journal's ``load`` is given and fixed in its rotor's statically indeterminate split (a
        rotor on three or more journals, two at least without a given ``load``, which carry the
        rest of its weight): ``rdm.static`` applies it as a fixed force on the rotor.
    """

    diameter: float
    length: float
    clearance: float
    viscosity: float
    load: float
    axes: np.ndarray
    load_over_speed: object = None
    fixed_load: bool = False


@dataclass(frozen=True)
class BearingCoefficients:
    """A bearing's coefficients after validation.

    Attributes
    ----------
    kind : {'constant', 'table', 'journal'}
    stiffness, damping : ndarray, shape (n_s, 6, 6)
        In model axes at the bearing point [N/m, N/rad, N m/m, N m/rad] and the
        corresponding damping; ``n_s = 1`` unless tabulated. For a journal bearing
        they hold the constant axial and moment parts; the radial part is computed.
    speeds : ndarray, shape (n_s,), or None
        Own speeds of the carried rotor at the table's rows [rad/s], increasing.
    axial : bool
        True when the bearing gives an axial stiffness (the rotor then moves axially).
    journal : JournalData or None
    """

    kind: str
    stiffness: np.ndarray
    damping: np.ndarray
    speeds: np.ndarray | None = None
    axial: bool = False
    journal: JournalData | None = None


def is_speed_dependent(coefficients: BearingCoefficients) -> bool:
    """True for tables and journal bearings."""
    return coefficients.kind != "constant"


def local_to_model(local: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """6x6 matrices in a bearing's own axes to model axes.

    Parameters
    ----------
    local : ndarray, shape (..., 6, 6)
        Acting on ``[u_1, u_2, u_3, theta_1, theta_2, theta_3]`` along the rows of ``axes``.
    axes : ndarray, shape (3, 3)
        Rows are the bearing's axes in model axes (orthonormal).

    Returns
    -------
    ndarray, shape (..., 6, 6)
    """
    rotation = np.zeros((6, 6))
    rotation[:3, :3] = axes
    # rotations are axial vectors: in left-handed axes their components change sign
    rotation[3:, 3:] = np.linalg.det(axes) * axes
    return rotation.T @ local @ rotation


def evaluate(coefficients: BearingCoefficients, own_speeds, where: str = "bearing"):
    """Stiffness and damping of a bearing at many own speeds of its rotor.

    Parameters
    ----------
    coefficients : BearingCoefficients
    own_speeds : array_like, shape (N,)
        The carried rotor's spin speed, signed about the spin axis [rad/s].
    where : str
        How to name the bearing in an error message (``"model.toml: [bearings.DE]"``).

    Returns
    -------
    stiffness, damping : ndarray, shape (N, 6, 6)
        Model axes, at the bearing point.

    Raises
    ------
    InputError
        A speed outside a table's range, or a journal bearing without a film.
    """
    speeds = np.atleast_1d(np.asarray(own_speeds, dtype=float))
    if coefficients.kind == "table":
        return _interpolate(coefficients, speeds, where)
    shape = (len(speeds), 6, 6)
    stiffness = np.broadcast_to(coefficients.stiffness[0], shape).copy()
    damping = np.broadcast_to(coefficients.damping[0], shape).copy()
    if coefficients.kind == "journal":
        k_film, c_film = _journal_film(coefficients.journal, speeds, where)
        stiffness += k_film
        damping += c_film
    return stiffness, damping


#: how far (relative to the table's largest end speed) a speed may lie beyond a coefficient
#: table's end and still be its end: round-off of unit conversions, never a real extrapolation
_TABLE_END_ROUNDOFF = 1e-12


def _outside(table: np.ndarray, speeds: np.ndarray) -> np.ndarray:
    """Which own speeds [rad/s] lie outside the speed table ``table`` [rad/s] (its ends widened
    by round-off)."""
    # a speed typed as the table's end can differ from it in the last bits (rpm and rad/s
    # converted on different routes, a ROSS table stored in rad/s): that is the end
    roundoff = _TABLE_END_ROUNDOFF * np.max(np.abs(table[[0, -1]]))
    return (speeds < table[0] - roundoff) | (speeds > table[-1] + roundoff)


def table_left(model, reference_speeds, bearings=None):
    """The first bearing whose speed table the reference speeds take its rotor out of.

    The check :func:`evaluate` makes, made before the work by the commands whose range of speeds
    is fixed by an option (``report --mcs``, ``ucs-map --operating-range``), each naming it.

    Parameters
    ----------
    model : Model
    reference_speeds : array_like, shape (N,) [rad/s]
        Speeds of the reference rotor; each rotor turns at its speed ratio times them.
    bearings : sequence of Bearing, optional
        The bearings checked (default all the model's).

    Returns
    -------
    (Bearing, ndarray of shape (N,) [rad/s]) or None
        The bearing and its rotor's own speeds, or None when every table holds them.
    """
    speeds = np.atleast_1d(np.asarray(reference_speeds, dtype=float))
    for bearing in model.bearings if bearings is None else bearings:
        table = bearing.coefficients.speeds
        if bearing.coefficients.kind != "table" or table is None:
            continue
        own = model.speed_ratios[bearing.rotor] * speeds
        if _outside(table, own).any():
            return bearing, own
    return None


def _interpolate(coefficients: BearingCoefficients, speeds: np.ndarray, where: str):
    table = coefficients.speeds
    outside = _outside(table, speeds)
    if np.any(outside):
        bad = speeds[outside]
        raise InputError(
            f"{where}: the rotor's own speed reaches {_rpm(bad[np.argmax(np.abs(bad))])} rpm, outside "
            f"the coefficient table's speeds_rpm range {_rpm(table[0])} .. {_rpm(table[-1])} rpm "
            "(own speed of the carried rotor, signed about spin_axis): extend the table or the "
            "sweep's range")
    speeds = np.clip(speeds, table[0], table[-1])
    right = np.clip(np.searchsorted(table, speeds, side="right"), 1, len(table) - 1)
    left = right - 1
    t = ((speeds - table[left]) / (table[right] - table[left]))[:, None, None]
    stiffness = (1 - t) * coefficients.stiffness[left] + t * coefficients.stiffness[right]
    damping = (1 - t) * coefficients.damping[left] + t * coefficients.damping[right]
    return stiffness, damping


def _journal_film(journal: JournalData, speeds: np.ndarray, where: str):
    """Radial film coefficients of a journal bearing, (N, 6, 6) each in model axes."""
    from .journal_bearing import short_journal_bearing

    if journal.load_over_speed is not None:
        return _journal_film_over_speed(journal, speeds, where)
    try:
        film = short_journal_bearing(speeds, diameter=journal.diameter, length=journal.length,
                                     clearance=journal.clearance, viscosity=journal.viscosity,
                                     load=journal.load)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
    _warn_high_eccentricity(film, speeds, journal, where)
    return _embed_radial(film.stiffness, journal.axes), _embed_radial(film.damping, journal.axes)


def light_load_stiffness(coefficients: BearingCoefficients) -> np.ndarray:
    """A plain journal bearing's stiffness (6, 6), model axes, at the bearing point [N/m, N/rad,
    N m/m, N m/rad], with its film as at light load: its constant part (axial and moment
    stiffness given) plus the symmetric part of the film's stiffness as the eccentricity goes to
    zero, ``load / clearance`` times :data:`~rotordyn_modal.elements.journal_bearing.LIGHT_LOAD_STIFFNESS`
    along and across its load (``JournalData.axes``; a rotor on three or more journals: the
    light-load films' split). No speed is needed: at rest the film has no stiffness, and at any
    running speed the symmetric part holds the journal with about ``load / clearance``.
    """
    from .journal_bearing import LIGHT_LOAD_STIFFNESS

    journal = coefficients.journal
    film = journal.load / journal.clearance * LIGHT_LOAD_STIFFNESS
    return coefficients.stiffness[0] + _embed_radial(film[None], journal.axes)[0]


def _journal_film_over_speed(journal: JournalData, speeds: np.ndarray, where: str):
    """The film's coefficients (N, 6, 6) at the load and load direction of each speed."""
    from .journal_bearing import short_journal_bearing

    try:
        vectors = journal.load_over_speed(speeds)                                   # (N, 3)
        load = np.linalg.norm(vectors, axis=-1)
        film = short_journal_bearing(speeds, diameter=journal.diameter, length=journal.length,
                                     clearance=journal.clearance, viscosity=journal.viscosity, load=load)
    except InputError as error:
        raise InputError(f"{where}: {error}") from None
    _warn_high_eccentricity(film, speeds, journal, where)
    x = vectors / load[:, None]
    radial = np.stack([x, np.cross(journal.axes[2], x)], 1)                         # (N, 2, 3)
    out = []
    for local in (film.stiffness, film.damping):
        model = np.zeros(local.shape[:-2] + (6, 6))
        model[:, :3, :3] = np.swapaxes(radial, 1, 2) @ local @ radial
        out.append(model)
    return tuple(out)


def _warn_high_eccentricity(film, speeds: np.ndarray, journal: JournalData, where: str) -> None:
    """One warning per bearing (and process) whose eccentricity exceeds :data:`HIGH_ECCENTRICITY`."""
    high = film.eccentricity > HIGH_ECCENTRICITY
    if not high.any() or where in _WARNED:
        return
    _WARNED.add(where)
    worst = int(np.argmax(film.eccentricity))
    warnings.warn(f"{where}: eccentricity {film.eccentricity[worst]:.4g} at {_rpm(speeds[worst])} rpm, above "
                  f"{HIGH_ECCENTRICITY:g} (thinnest film {journal.clearance * (1 - film.eccentricity[worst]):.3g} m, "
                  "under a tenth of the clearance): short-bearing coefficients are rough there and a real "
                  "bearing nears mixed lubrication; analyse from a higher speed", ModelWarning, stacklevel=3)


def _embed_radial(radial: np.ndarray, axes: np.ndarray) -> np.ndarray:
    """(N, 2, 2) in the frame of ``axes[:2]`` to (N, 6, 6) in model axes."""
    local = np.zeros(radial.shape[:-2] + (6, 6))
    local[..., :2, :2] = radial
    return local_to_model(local, axes)


def _rpm(speed: float) -> str:
    return f"{speed * 30.0 / np.pi:.6g}"
