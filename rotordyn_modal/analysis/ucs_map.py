"""Undamped critical speed map: forward synchronous critical speeds against bearing stiffness.

The first figure of an API 684 lateral analysis. The chosen bearings' radial stiffness is set
isotropic to ``k`` (their cross-coupling and all damping of the machine removed; axial and tilt
stiffness kept), ``k`` swept over decades, and at each ``k`` the **undamped critical speeds**
found: the reference rotor's speeds ``Omega > 0`` at which a forward-whirling mode's natural
frequency equals ``Omega`` (order 1 of the reference rotor). With ``lambda = i Omega`` and
``C = 0`` the eigenproblem ``(-Omega^2 M + i Omega^2 G + K) phi = 0`` is linear in ``Omega^2``::

    K phi = Omega^2 (M - i G) phi          (M - i G Hermitian, K real symmetric)

so every critical speed of every ``k`` comes from one batched Hermitian eigen-solve, no search:
``(M - i G) phi = nu K phi`` (``K`` positive definite once the machine's free motions are set
apart) gives real ``nu`` and ``Omega = nu^-1/2`` for ``nu > 0``. Each mode is followed over
the stiffness along its branch of the pencil (by the MAC, on points inserted wherever a step of
the user's grid is unclear: the curves do not depend on the grid's spacing), so that a curve of
the map is one branch: through a veering it keeps its order and changes its shape, where two
modes do not couple the curves cross. Each is named by the body and motion with most of its
kinetic energy at its two ends. A mode whose
gyroscopic stiffening outruns the speed (a disc's forward conical mode, polar above diametral
inertia) has ``nu <= 0``: no critical speed. Forward or backward is the package's whirl ratio of ``phi``
(``docs/theory.md``), repeated roots resolved into their circular combinations as everywhere.

Each chosen bearing's own radial stiffness ``Kxx``, ``Kyy`` (in its radial axes: a journal
bearing's load direction and the normal to it) over the reference speed is laid over the map;
where such a curve meets a mode's curve the machine would run at that critical speed.
``docs/level1_and_ucs.md`` gives the definitions and their checks.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.linalg
from scipy.optimize import brentq, linear_sum_assignment

from ..assembly import bearing_motion, body_inertias, constant_stiffness_damping, gyroscopic_matrix, mass_matrix
from ..elements.bearings import evaluate, table_left
from ..errors import InputError
from ..linear_system import checked_mass_inverse
from ..model._table import visible_names
from ..model.geometry import skew
from .. import _arguments
from . import _batches, _eigensolve, _vectors, _whirl

__all__ = ["UcsMap", "BearingCurve", "Crossing", "ucs_map", "forward_critical_speeds"]


@dataclass(frozen=True)
class BearingCurve:
    """A chosen bearing's own radial stiffness over the reference speed.

    Attributes
    ----------
    name : str
    speeds : ndarray, shape (S,) [rad/s] or None
        Reference speeds of the points (None for a constant bearing: its stiffness is a vertical
        line on the map).
    kxx, kyy : ndarray, shape (S,) (or (1,) when constant) [N/m]
        Direct stiffness along the bearing's two radial axes (a journal bearing's load direction
        and the normal to it).
    """

    name: str
    speeds: np.ndarray | None
    kxx: np.ndarray
    kyy: np.ndarray

    @property
    def constant(self) -> bool:
        return self.speeds is None


@dataclass(frozen=True)
class Crossing:
    """Where a bearing's stiffness curve meets a mode's curve on the map.

    Attributes
    ----------
    bearing : str
    axis : {'xx', 'yy'}
    mode : int
        The followed mode met: its number on the map (``UcsMap.mode_speeds[:, mode - 1]``).
    stiffness : float [N/m]
    speed : float [rad/s]
    name : str
        That mode's name (``UcsMap.mode_names``).
    """

    bearing: str
    axis: str
    mode: int
    stiffness: float
    speed: float
    name: str = ""


@dataclass(frozen=True)
class UcsMap:
    """Undamped critical speed map.

    Attributes
    ----------
    stiffness : ndarray, shape (K,) [N/m]
        Radial stiffness given to each chosen bearing, increasing.
    speeds : ndarray, shape (K, m) [rad/s]
        ``speeds[i, j]``: the (j+1)-th lowest forward critical speed at ``stiffness[i]`` (nan
        where there are fewer): a rank, not a mode (where two modes cross, column j passes from
        one to the other; see ``mode_speeds``).
    bearings : tuple of str
        The chosen bearings.
    curves : tuple of BearingCurve
    crossings : tuple of Crossing
    rigid_speeds : ndarray, shape (m,) [rad/s]
        The rigid-support asymptote, the limit of each curve as ``k`` grows without bound: the
        forward critical speeds with each chosen bearing radially rigid (its rotor pinned to
        the stator there; axial and tilt stiffness as given). A rotor on two chosen bearings
        without axial stiffness is then rigidly attached to the stator, as in a model without
        its bearings.
    operating : (float, float) [rad/s] or None
        Operating speed range, drawn as a band (low = high: one rated speed, drawn as a line).
    title : str
    mode_speeds : ndarray, shape (K, L) [rad/s]
        The modes drawn on the map, each followed over the stiffness along its branch (through
        a veering it keeps its order, its shape changing; the same whatever the grid's spacing):
        ``mode_speeds[i, j]`` is mode j+1's forward critical speed at ``stiffness[i]``, nan where
        it is none (it whirls backward or not at all there, or outruns the speed). The modes
        are those among the ``m`` lowest forward critical speeds at some stiffness, numbered by
        the stiffness where they first appear and their speed there. Curves may cross.
    mode_names : tuple of str, (L,)
        Each followed mode's body with the most kinetic energy and its motion ('pump conical',
        'stator rocking', a flexible rotor's 'pump bending'; see ``docs/level1_and_ucs.md``), at
        the curve's two ends, 'A -> B' where they differ ('pump conical -> pump bending').
    """

    stiffness: np.ndarray
    speeds: np.ndarray
    bearings: tuple
    curves: tuple = ()
    crossings: tuple = ()
    rigid_speeds: np.ndarray | None = None
    operating: tuple | None = None
    title: str = ""
    mode_speeds: np.ndarray | None = None
    mode_names: tuple = ()

    @property
    def speeds_rpm(self) -> np.ndarray:
        return self.speeds * 30.0 / np.pi

    def to_dataframe(self):
        """Long table ``stiffness_n_per_m, mode, speed_rpm, frequency_hz`` (one row per stiffness
        and mode; empty speed where the mode has no critical speed)."""
        import pandas as pd

        count, m = self.speeds.shape
        return pd.DataFrame({"stiffness_n_per_m": np.repeat(self.stiffness, m),
                             "mode": np.tile(np.arange(1, m + 1), count),
                             "speed_rpm": self.speeds_rpm.ravel(),
                             "frequency_hz": self.speeds.ravel() / (2 * np.pi)})

    def modes_dataframe(self):
        """Long table ``stiffness_n_per_m, mode, name, speed_rpm, frequency_hz`` of the followed
        modes (one row per stiffness and mode; empty speed where the mode is no forward critical
        speed)."""
        import pandas as pd

        count, m = self.mode_speeds.shape
        return pd.DataFrame({"stiffness_n_per_m": np.repeat(self.stiffness, m),
                             "mode": np.tile(np.arange(1, m + 1), count),
                             "name": np.tile(np.array(self.mode_names, dtype=object), count),
                             "speed_rpm": self.mode_speeds.ravel() * 30 / np.pi,
                             "frequency_hz": self.mode_speeds.ravel() / (2 * np.pi)})

    def crossings_dataframe(self):
        """Table ``bearing, axis, mode, name, stiffness_n_per_m, speed_rpm`` of the crossings
        (``mode``: the followed mode's number)."""
        import pandas as pd

        return pd.DataFrame({"bearing": [c.bearing for c in self.crossings],
                             "axis": [c.axis for c in self.crossings],
                             "mode": np.array([c.mode for c in self.crossings], dtype=int),
                             "name": [c.name for c in self.crossings],
                             "stiffness_n_per_m": np.array([c.stiffness for c in self.crossings], dtype=float),
                             "speed_rpm": np.array([c.speed for c in self.crossings], dtype=float) * 30 / np.pi})

    def plot(self, **kwargs):
        """The map; see :func:`rotordyn_modal.plotting.plot_ucs_map`."""
        from ..plotting import plot_ucs_map

        return plot_ucs_map(self, **kwargs)


def ucs_map(model, stiffness, modes: int = 4, bearings=None, speeds=None, operating=None) -> UcsMap:
    """Undamped critical speed map of ``model`` (see the module docstring).

    Parameters
    ----------
    model : Model
    stiffness : array_like, shape (K,) [N/m]
        Radial stiffness values, > 0, increasing (e.g. ``numpy.geomspace(1e5, 1e9, 41)``).
    modes : int
        How many forward critical speeds per stiffness (the lowest: ``speeds``); the followed
        modes (``mode_speeds``) are those among them at some stiffness.
    bearings : sequence of str, optional
        The bearings whose stiffness is swept (default all). The others keep their
        coefficients, which must then be constant.
    speeds : array_like, shape (S,) [rad/s], optional
        Reference speeds at which the speed-dependent bearings' own stiffness is drawn (default:
        over the map's critical speeds, a table's rows limiting it).
    operating : (float, float) [rad/s], optional
        Operating speed range, 0 <= low <= high, high > 0 (drawn as a band; low = high, one rated speed, as
        a line).

    Returns
    -------
    UcsMap

    Raises
    ------
    InputError
        No bearing, an unknown name, a bad stiffness list, mode count or operating range, an unchosen bearing
        whose coefficients depend on speed, or a chosen speed table whose axial or tilt
        coefficients change over speed.
    ModelError
        Masses and inertias so many orders of magnitude apart that rounding leaves the mass
        matrix singular (every analysis refuses such a model).
    """
    chosen = _chosen_bearings(model, bearings)
    stiffness = _check_stiffness(stiffness)
    modes = _check_modes(modes)
    operating = _check_operating(operating)
    check_operating_tables(model, operating, chosen)
    speeds = _check_speeds(speeds)
    # BLAS's own threads only wait for a core on a shared machine: 53 states, 9x faster on one
    with _batches.one_blas_thread(_batches._BLAS_THREADED_BYTES):
        return _ucs_map(model, chosen, stiffness, modes, speeds, operating)


def _ucs_map(model, chosen, stiffness, modes, speeds, operating) -> UcsMap:
    parts = _Pencil(model, chosen, polished=_polished_count(modes))
    constants = _constant_values(chosen)
    grid = np.union1d(stiffness, constants)           # the constant bearings' stiffness followed too
    roots = parts.roots(grid)
    mine = np.searchsorted(grid, stiffness)
    found = _lowest_forward(_Roots(*(x[mine] for x in roots)), modes)
    followed = _follow(parts, roots, grid, mine, modes, _following_order(parts, roots, grid, mine, modes))
    curves = tuple(_bearing_curve(model, b, speeds, found) for b in chosen)
    crossings = _constant_crossings(curves, grid, followed) + _curve_crossings_all(parts, curves, grid, followed)
    return UcsMap(stiffness=stiffness, speeds=found, bearings=tuple(b.name for b in chosen), curves=curves,
                  crossings=tuple(crossings), rigid_speeds=_rigid_support(parts, model, chosen, modes),
                  operating=operating,
                  title=model.name, mode_speeds=followed.speeds[mine], mode_names=followed.names)


def _check_speeds(speeds):
    """``speeds`` as a 1-D array of finite numbers [rad/s] with one > 0 at least (None stays None):
    NaN, an empty list or only speeds <= 0 drew no curve of a speed-dependent bearing without a
    word (its curve is drawn at the positive ones)."""
    if speeds is None:
        return None
    grid = _arguments.values(speeds, "speeds", "rad/s")
    if not (grid > 0).any():
        raise InputError(f"speeds = {_arguments._shown(speeds)}: expected at least one speed > 0 [rad/s] (the "
                         "speed-dependent bearings' stiffness is drawn at positive reference speeds)")
    return grid


def _check_operating(operating):
    """``operating`` as (low, high) [rad/s], 0 <= low <= high, high > 0 (None stays None)."""
    if operating is None:
        return None
    band = _arguments.values(operating, "operating", "rad/s", non_negative=True)
    if band.shape != (2,) or not band[0] <= band[1] or not band[1] > 0:
        raise InputError(f"operating = {_arguments._shown(operating)}: expected (low, high) [rad/s] with "
                         "0 <= low <= high and high > 0 (low = high: one rated speed)")
    return tuple(float(s) for s in band)


def check_operating_tables(model, operating, bearings, named=None) -> None:
    """Refuse an operating range that takes a chosen bearing's rotor outside its speed table.

    Its curve on the map ends at the table's rows, so the band would lie where no coefficient
    is known: ``report`` refuses the same case (``elements.bearings.table_left``, one check).

    Parameters
    ----------
    model : Model
    operating : (float, float) [rad/s] or None
    bearings : sequence of Bearing
        The chosen bearings.
    named : str, optional
        The range as the caller typed it (``--operating-range 6000:8000``); default
        ``operating = (low, high)``.
    """
    if operating is None or (left := table_left(model, operating, bearings)) is None:
        return
    bearing, own = left
    table, rpm = bearing.coefficients.speeds, 30.0 / np.pi
    named = named or f"operating = {_arguments._shown(tuple(operating))}"
    raise InputError(f"{named}: rotor {bearing.rotor!r} turns at {own.min() * rpm:.6g} .. {own.max() * rpm:.6g} rpm "
                     f"there: expected within [bearings.{bearing.name}] speeds_rpm {table[0] * rpm:.6g} .. "
                     f"{table[-1] * rpm:.6g} rpm (extend the table, or an operating range within it)")


class _Pencil:
    """``M``, ``G``, and ``K(k) = K_rest + k K_unit`` of a model with its chosen bearings' radial
    stiffness ``k`` (isotropic), and the forward critical speeds of any ``k``."""

    def __init__(self, model, chosen, polished=0):
        checked_mass_inverse(model)   # a mass matrix rounding leaves singular: refused, as every analysis does
        self.polished = polished     # the lowest roots polished where double precision leaves them inexact
        self.model = model
        self.M = mass_matrix(model)
        self.G = gyroscopic_matrix(model)
        self.forms = _whirl.whirl_forms(model)
        self.rest, self.unit = _split_stiffness(model, chosen)
        self._basis = None

    def roots(self, stiffness, polish=True) -> "_Roots":
        """:class:`_Roots` for the stiffness values (K,) [N/m]. Without ``polish`` (points where
        only the shapes are used, to follow the roots) the lowest are not polished and no root
        is called forward."""
        stiffness = np.asarray(stiffness, dtype=float)
        K = self.rest + stiffness[:, None, None] * self.unit
        exact = (self.rest, self.unit, stiffness, self.polished) if self.polished and polish else None
        if self._basis is None:          # the machine's free motions: the same at every k
            self._basis = _constrained_basis(self.M, self.M - 1j * self.G, _free_probe([self.rest, self.unit]))
        return _synchronous_roots(self.M, self.G, K, self.forms, exact=exact, basis=self._basis, whirl=polish)

    def weighted(self, shapes) -> np.ndarray:
        """Mass-weighted unit shapes (..., m, n) for the MAC."""
        return _vectors.mass_normalized(shapes, self.M)


def forward_critical_speeds(M, G, K, forms, count: int) -> np.ndarray:
    """The lowest forward synchronous critical speeds of undamped models (one batched solve).

    Parameters
    ----------
    M, G : ndarray, shape (n, n)
        Mass and gyroscopic matrix per unit reference speed.
    K : ndarray, shape (S, n, n)
        Stiffness matrices, symmetric positive semidefinite, all with the same null space (the
        machine's free motions, which carry no stiffness whatever the bearings).
    forms : WhirlForms
    count : int

    Returns
    -------
    ndarray, shape (S, count) [rad/s], increasing along each row, nan where fewer exist
    """
    return _lowest_forward(_synchronous_roots(M, G, K, forms), count)


class _Roots(NamedTuple):
    """Every root of the synchronous pencil at S stiffness matrices (m of them each).

    ``omega`` (S, m) [rad/s], increasing, inf where the root has no critical speed (``nu <= 0``);
    ``signed`` (S, m): ``sign(nu) |nu|^-1/2``, finite (what the tracking extrapolates);
    ``shapes`` (S, m, n) in the model's coordinates; ``forward`` (S, m) bool: a forward critical
    speed."""

    omega: np.ndarray
    signed: np.ndarray
    shapes: np.ndarray
    forward: np.ndarray


def _free_probe(parts) -> np.ndarray:
    """A stiffness matrix whose null space is the motions free in every one of ``parts`` (PSD
    matrices (n, n)): their sum, each scaled to a largest entry of 1. The free motions of a
    batch are found on it rather than on one member: on a bearing of 1e-3 N/m beside a shaft's
    1e9 N/m the rotor's rigid motions look free to round-off, and were dropped at every
    stiffness of the batch (a UCS map from 1e-3 N/m lost its rigid-body modes at 1e6 N/m too)."""
    probe = np.zeros(np.shape(parts[0]))
    for part in parts:
        size = np.abs(part).max()
        if size > 0:
            probe = probe + part / size
    return probe


def _synchronous_roots(M, G, K, forms, probe=None, exact=None, basis=None, whirl=True) -> _Roots:
    """:class:`_Roots` of ``K phi = Omega^2 (M - i G) phi`` for each of K (S, n, n), one batch;
    ``probe`` (n, n): a stiffness with the batch's free motions as its null space (default
    :func:`_free_probe` of the batch's matrices); ``exact``: ``(K_rest, K_unit, k, count)`` with ``K =
    K_rest + k K_unit`` (``k`` (S,)), where given the lowest ``count`` roots double precision leaves
    inexact are polished (:func:`_polished`); ``basis``: :func:`_constrained_basis` of the probe, where
    known; without ``whirl`` no root is called forward (the whirl not computed)."""
    B = M - 1j * G
    W = _constrained_basis(M, B, _free_probe(list(K)) if probe is None else probe) if basis is None else basis
    if not W.shape[1]:                      # every motion free: no mode at all
        empty = np.zeros((len(K), 0))
        return _Roots(empty, empty, np.zeros((len(K), 0, len(M)), dtype=complex), empty.astype(bool))
    Kw = W.conj().T @ K @ W          # (s, n, n): matrix products, not a three-operand einsum (n^4 per speed)
    Bw = W.conj().T @ B @ W
    R = np.linalg.cholesky(0.5 * (Kw + Kw.conj().swapaxes(-1, -2)))
    Ri = np.linalg.inv(R)                    # one factorisation; the products below are cheaper than solves
    H = Ri @ Bw @ Ri.conj().swapaxes(-1, -2)                         # R^-1 Bw R^-H
    nu, y = np.linalg.eigh(0.5 * (H + H.conj().swapaxes(-1, -2)))
    polished = None
    if exact is not None:
        nu, polished = _polished(M, G, *exact, nu, (W @ (Ri.conj().swapaxes(-1, -2) @ y)))
    with np.errstate(divide="ignore", invalid="ignore"):
        omega = np.where(nu > 0, 1 / np.sqrt(np.where(nu > 0, nu, 1.0)), np.inf)
        signed = np.sign(nu) / np.sqrt(np.maximum(np.abs(nu), 1e-300))
    order = np.argsort(omega, axis=-1)
    omega, signed, nu = (np.take_along_axis(x, order, axis=-1) for x in (omega, signed, nu))
    if polished is None:
        y = np.take_along_axis(y, order[:, None, :], axis=-1)
        shapes = (W @ (Ri.conj().swapaxes(-1, -2) @ y)).swapaxes(-1, -2)                 # (s, m, n)
    else:
        shapes = np.take_along_axis(polished, order[:, None, :], axis=-1).swapaxes(-1, -2)
    finite = np.isfinite(omega)
    lam = 1j * np.where(finite, omega, 0.0)
    shapes = _eigensolve.resolve_repeated(lam, shapes, forms)
    if not whirl:
        return _Roots(omega, signed, shapes, np.zeros(omega.shape, dtype=bool))
    ratios = _whirl.whirl_ratios(shapes, forms, np.ones(len(K)))
    return _Roots(omega, signed, shapes, finite & (_whirl.whirl_labels(ratios) == "forward"))


#: a root of the map whose estimated relative error (:func:`_round_off`) exceeds this is polished
#: (:func:`_polished`): the crossings are found to 1e-10 of the speed
_POLISH_LEVEL = 1e-10
#: roots polished together at most (a double root: a rotor's forward and backward cylindrical
#: motion where the gyroscopic moments do not act); chord steps at most; a group whose last step
#: is above ``_POLISHED`` (relative) is left as the solve gave it
_GROUP_LARGEST, _CHORD_STEPS, _POLISHED = 4, 12, 1e-13


def _round_off(M, G, rest, unit, k, nu, shapes, largest):
    """Estimated relative error of roots ``nu`` (S, c) = ``1 / Omega^2`` of ``K phi = Omega^2 (M -
    i G) phi`` at the stiffness values ``k`` (S,) [N/m], shapes (S, n, c): the conditioning of the
    root in the matrix's entries, ``eps |phi|^T (|K_rest| + k |K_unit|) |phi| / (Omega^2 |phi^H B
    phi|)`` (the Cholesky of ``K``), and the Hermitian solve's own ``eps max |nu| / |nu|`` (its
    absolute error is ``eps`` of the largest ``nu``, ``largest`` (S,): a rigid rotor's, 1e13 times a
    shaft mode's on bearings of 1e-3 N/m). Returns the two (S, c) each, inf where ``nu <= 0`` (no
    critical speed: not polished)."""
    a = np.abs(shapes)
    terms = np.einsum("sim,sim->sm", a, np.abs(rest) @ a) + k[:, None] * np.einsum("sim,sim->sm", a, np.abs(unit) @ a)
    inertia = np.abs(np.einsum("sim,sim->sm", shapes.conj(), (M - 1j * G) @ shapes))
    eps = np.finfo(float).eps
    with np.errstate(divide="ignore", invalid="ignore"):
        stiff, solve = eps * terms * nu / inertia, eps * largest[:, None] / np.abs(nu)
    return np.where(nu > 0, stiff, np.inf), np.where(nu > 0, solve, np.inf)


def _polished_count(modes):
    """How many of the lowest roots (forward and backward) the map polishes for ``modes`` forward
    critical speeds a stiffness: what it reports and follows, and the backward roots between."""
    return 2 * modes + 2


def _polished(M, G, rest, unit, stiffness, count, nu, shapes):
    """Roots ``nu`` (S, m) with shapes (S, n, m) of the map's pencil at the stiffness values
    ``stiffness`` (S,) [N/m], the ``count`` lowest (largest ``nu > 0``) at each, whose estimated error
    (:func:`_round_off`) exceeds ``_POLISH_LEVEL``,
    polished on ``K_rest phi + k K_unit phi = Omega^2 (M - i G) phi`` (:func:`_group_polished`: the
    stiffness term summed exactly from ``K_rest`` and ``k`` apart; formed, ``K_rest + k K_unit``
    loses a bearing of 1e-3 N/m beside a shaft's 1e10 N/m to rounding), together where roots are
    closer than their errors. Returns ``nu`` and the shapes, new arrays; the others untouched."""
    nu, shapes = nu.copy(), shapes.copy()
    lowest = np.argsort(-nu, axis=1)[:, :count]                                       # (S, c)
    parts = _round_off(M, G, rest, unit, np.asarray(stiffness, dtype=float), np.take_along_axis(nu, lowest, 1),
                       np.take_along_axis(shapes, lowest[:, None, :], 2), np.abs(nu).max(axis=1))
    stiffs, errors = (np.full(nu.shape, np.inf) for _ in range(2))
    np.put_along_axis(stiffs, lowest, parts[0], 1)
    np.put_along_axis(errors, lowest, parts[0] + parts[1], 1)
    over = np.isfinite(errors) & (errors > _POLISH_LEVEL)
    for s in np.flatnonzero(over.any(axis=1)):
        k, stiff, error, wanted = stiffness[s], stiffs[s], errors[s], over[s]
        for group in _groups(nu[s], error, wanted):
            exact = bool(np.any(stiff[group] > _POLISH_LEVEL))
            found = _group_polished(M, G, rest, unit, k, nu[s, group], shapes[s][:, group], exact)
            if found is not None:
                nu[s, group], shapes[s][:, group] = found
    return nu, shapes


def _groups(nu, error, wanted):
    """Index arrays of the roots ``nu`` (m,) to polish together: runs of positive roots each closer
    to the next than ten times their errors ``error`` (m,) allow to tell apart, those with a root
    ``wanted`` (m,) bool, at most ``_GROUP_LARGEST`` long (a root not estimated, inf: its
    neighbour's error decides)."""
    error = np.where(np.isfinite(error), error, 0.0)
    positive = np.flatnonzero(nu > 0)
    positive = positive[np.argsort(nu[positive])]
    runs, run = [], [positive[0]] if len(positive) else []
    for a, b in zip(positive[:-1], positive[1:]):
        gap = (nu[b] - nu[a]) / nu[b]
        if gap < 10 * max(error[a], error[b], _POLISH_LEVEL):
            run.append(b)
        else:
            runs.append(run)
            run = [b]
    if run:
        runs.append(run)
    return [np.array(r) for r in runs if wanted[r].any() and len(r) <= _GROUP_LARGEST]


def _group_polished(M, G, rest, unit, k, nu, shapes, exact=True):
    """Roots ``nu`` (g,) with shapes (n, g) of ``(K_rest + k K_unit) X = B X S``, ``B = M - i G``,
    polished together: chord steps of Newton's method for the invariant pair ``(X, S)`` with ``W^H
    X = I`` (``W`` the start's orthonormal basis; its Jacobian factored once), the residual's
    ``K_rest X`` summed exactly (:func:`._lowest_newton._exact_sums`) and ``k K_unit X`` apart, until
    the step is below ``_POLISHED`` (not ``exact``: summed in double, where the roots' error is
    the Hermitian solve's, not their conditioning's). Returns the roots ``1 / Omega^2`` (g,) and shapes (n, g) (each
    with its start's scale and, for one root, phase), or None where the steps do not converge."""
    from ._lowest_newton import _exact_sums

    n, g = shapes.shape
    B = M - 1j * G
    basis, triangle = np.linalg.qr(shapes)
    X = basis
    S = triangle @ np.diag(1.0 / nu) @ np.linalg.inv(triangle)              # Omega^2
    Ig = np.eye(g)
    K = rest + k * unit
    J = np.zeros((g * n + g * g, g * n + g * g), complex)
    J[:g * n, :g * n] = np.kron(Ig, K) - np.kron(S.T, B)
    J[:g * n, g * n:] = -np.kron(Ig, B @ X)
    J[g * n:, :g * n] = np.kron(Ig, basis.conj().T)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            factors = scipy.linalg.lu_factor(J, check_finite=False)
    except (ValueError, np.linalg.LinAlgError):
        return None
    for _ in range(_CHORD_STEPS):
        stiff = (_exact_sums(rest, X) if exact else rest @ X) + k * (unit @ X)
        residual = stiff - (B @ X) @ S
        d = scipy.linalg.lu_solve(factors, -np.concatenate([residual.reshape(-1, order="F"), np.zeros(g * g)]),
                                  check_finite=False)
        if not np.all(np.isfinite(d)):
            return None
        X = X + d[:g * n].reshape((n, g), order="F")
        step = d[g * n:].reshape((g, g), order="F")
        S = S + step
        if np.abs(step).max() <= _POLISHED * np.abs(S).max():
            break
    else:
        return None
    values, combinations = np.linalg.eig(S)
    if np.any(np.abs(values.imag) > 1e-8 * np.abs(values)) or np.any(values.real <= 0):
        return None                          # a Hermitian pencil's roots are real: a start that went astray
    out = X @ combinations
    out *= np.linalg.norm(shapes, axis=0) / np.linalg.norm(out, axis=0)
    if g == 1:
        out = _vectors.phase_aligned(out[:, 0], shapes[:, 0])[:, None]
    return 1.0 / values.real, out


def _lowest_forward(roots: _Roots, count: int) -> np.ndarray:
    """(S, count) [rad/s]: the lowest forward critical speeds of each row, nan where fewer."""
    picked = np.sort(np.where(roots.forward, roots.omega, np.inf), axis=-1)[:, :count]
    out = np.full((len(roots.omega), count), np.nan)
    out[:, :picked.shape[1]] = np.where(np.isfinite(picked), picked, np.nan)
    return out


def _constrained_basis(M, B, K) -> np.ndarray:
    """Orthonormal columns spanning ``{phi : N^H B phi = 0}``, ``N`` the null space of ``K``
    (free motions of the machine: frequency zero, no critical speed). Restricted to it the
    pencil keeps all its non-zero roots and ``K`` is positive definite. The identity when ``K``
    has no null space."""
    L = np.linalg.cholesky(M)
    scaled = np.linalg.solve(L, np.linalg.solve(L, K).T)       # L^-1 K L^-T, symmetric
    values, vectors = np.linalg.eigh(0.5 * (scaled + scaled.T))
    free = values <= 1e-12 * max(values.max(), 0.0)
    if not free.any():
        return np.eye(len(M))
    N = np.linalg.solve(L.T, vectors[:, free])                 # free motions in q
    return scipy.linalg.null_space(N.T @ B)


def _chosen_bearings(model, names):
    if not model.bearings:
        raise InputError(f"{model.source}: the model has no [[bearings]]: an undamped critical speed map "
                         "sweeps bearing stiffness")
    by_name = {b.name: b for b in model.bearings}
    if names is None:
        return list(model.bearings)
    names = [names] if isinstance(names, str) else list(names)
    unknown = [n for n in names if n not in by_name]
    if unknown or not names:
        raise InputError(f"bearings {', '.join(map(repr, unknown)) or '(none)'}: expected names of the "
                         f"model's bearings: {visible_names(by_name)}")
    return [by_name[n] for n in dict.fromkeys(names)]


#: the stiffness a map may sweep [N/m]: bearings are 1e3-1e10 N/m; far beyond, the pencil's
#: stiffness matrices lose the other elements' stiffness to round-off
STIFFNESS_RANGE = (1e-3, 1e16)


def _check_stiffness(stiffness) -> np.ndarray:
    low, high = STIFFNESS_RANGE
    try:
        values = np.atleast_1d(np.asarray(stiffness, dtype=float))
    except (TypeError, ValueError):   # '1e6:1e8:3' (the command line's form) raised numpy's ValueError
        raise InputError(f"stiffness = {_arguments._shown(stiffness)}: expected an array of increasing values from "
                         f"{low:g} to {high:g} N/m (e.g. numpy.geomspace(1e5, 1e9, 41))") from None
    if values.ndim != 1 or not len(values) or not np.all((values >= low) & (values <= high)) \
            or not np.all(np.diff(values) > 0):
        raise InputError(f"stiffness {np.array2string(values, threshold=6)}: expected increasing values from "
                         f"{low:g} to {high:g} N/m")
    return values


def _check_modes(modes) -> int:
    if isinstance(modes, bool) or not isinstance(modes, (int, np.integer)) or not 1 <= modes <= 1000:
        raise InputError(f"modes = {modes!r}: expected a whole number from 1 to 1000")
    return int(modes)


def _split_stiffness(model, chosen):
    """``K_rest`` (everything but the chosen bearings' radial stiffness) and ``K_unit`` (their
    radial stiffness for k = 1 N/m, isotropic), each (n, n)."""
    rest = constant_stiffness_damping(model)[0].copy()
    unit = np.zeros_like(rest)
    names = {b.name for b in chosen}
    radial = _RADIAL_OF(model)
    for bearing in model.bearings:
        coefficients = bearing.coefficients
        if bearing.name not in names:
            if coefficients.kind != "constant":
                raise InputError(f"{model.source}: [bearings.{bearing.name}] has speed-dependent coefficients: "
                                 "give it in the map's bearings (its stiffness is then swept) or make it constant")
            continue
        rows, moves = bearing_motion(model, bearing)
        own = _other_than_radial(model, bearing, radial)
        if coefficients.kind == "constant":      # its full coefficients are in K_rest: take the radial part out
            rest[rows, rows] -= moves.T @ (coefficients.stiffness[0] - own) @ moves
        else:                                     # not in K_rest at all: put its axial and tilt part in
            rest[rows, rows] += moves.T @ own @ moves
        unit[rows, rows] += moves.T @ radial @ moves
    return rest, unit


def _other_than_radial(model, bearing, radial):
    """A bearing's axial and tilt stiffness (6, 6), model axes: its coefficients without the
    radial translational block."""
    stiffness = bearing.coefficients.stiffness
    keep = np.eye(6) - radial
    parts = keep @ stiffness @ keep + radial @ stiffness @ keep + keep @ stiffness @ radial
    if not np.allclose(parts, parts[0], rtol=1e-12, atol=0.0):
        raise InputError(f"{model.source}: [bearings.{bearing.name}] axial or moment stiffness changes over its "
                         "speeds_rpm: an undamped critical speed map keeps them fixed; give them constant")
    return parts[0]


def _radial_axes(bearing):
    """The bearing's radial axes (2, 3): a journal bearing's load direction and the normal."""
    journal = bearing.coefficients.journal
    return np.asarray(journal.axes[:2] if journal is not None else bearing.axes, dtype=float)


def _direct(stiffness, axes):
    """``Kxx, Kyy`` (S,) of (S, 6, 6) model-axes coefficients along the two radial axes."""
    block = stiffness[:, :3, :3]
    return (np.einsum("i,sij,j->s", axes[0], block, axes[0]), np.einsum("i,sij,j->s", axes[1], block, axes[1]))


def _bearing_curve(model, bearing, speeds, found) -> BearingCurve:
    coefficients = bearing.coefficients
    axes = _radial_axes(bearing)
    if coefficients.kind == "constant":
        kxx, kyy = _direct(coefficients.stiffness[:1], axes)
        return BearingCurve(bearing.name, None, kxx, kyy)
    ratio = model.rotor(bearing.rotor).speed_ratio
    grid = _curve_speeds(coefficients, ratio, speeds, found)
    where = f"{model.source}: [bearings.{bearing.name}]"
    grid, k = _evaluated(coefficients, ratio, grid, where)
    kxx, kyy = _direct(k, axes)
    return BearingCurve(bearing.name, grid, kxx, kyy)


#: points of a speed-dependent bearing's curve
_CURVE_POINTS = 200


def _curve_speeds(coefficients, ratio, speeds, found):
    """Reference speeds (increasing, > 0) at which a speed-dependent bearing's curve is drawn."""
    if speeds is not None:
        grid = np.asarray(speeds, dtype=float)
    else:
        finite = found[np.isfinite(found)]
        low, high = (finite.min() / 3, finite.max() * 3) if finite.size else (1.0, 1e4)
        grid = np.geomspace(low, high, _CURVE_POINTS)
    if coefficients.kind == "table" and ratio != 0:
        ends = np.sort(coefficients.speeds[[0, -1]] / ratio)
        grid = np.clip(grid, *ends) if speeds is None else grid
        grid = np.unique(np.r_[grid, ends[(ends > grid.min()) & (ends < grid.max())]]) if speeds is None else grid
    return np.unique(grid[grid > 0])


def _evaluated(coefficients, ratio, grid, where):
    """(speeds kept, (S, 6, 6) stiffness): a journal bearing's speeds where it has no film
    (eccentricity reaching 1 at low speed) are left out of the drawing."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return grid, evaluate(coefficients, ratio * grid, where)[0]
        except InputError:
            if coefficients.kind != "journal":
                raise
        kept, values = [], []
        for speed in grid:
            try:
                values.append(evaluate(coefficients, [ratio * speed], where)[0][0])
                kept.append(speed)
            except InputError:
                continue
    if not kept:
        raise InputError(f"{where}: no film at any speed of the map's range: give the speeds (speeds=...)")
    return np.array(kept), np.array(values)


class _Followed(NamedTuple):
    """The modes shown on the map, each followed over the stiffness grid along its branch.

    ``order`` (G, n_shown): the root index of each shown mode at each grid stiffness;
    ``speeds`` (G, n_shown) [rad/s], nan where the mode is not a forward critical speed;
    ``weighted`` (G, n_shown, n): its mass-weighted unit shapes; ``names`` (n_shown,) str."""

    order: np.ndarray
    speeds: np.ndarray
    weighted: np.ndarray
    names: tuple


def _follow(parts, roots, grid, mine, count, order) -> _Followed:
    """Keep, of the roots followed over the grid (``order`` (G, m): label -> root, from
    :func:`_following_order`), the modes that are among the ``count`` lowest forward critical
    speeds at some of the user's stiffness values (rows ``mine`` of the grid; a speed equal to
    the ``count``-th to :data:`_SAME_SPEED` counts too, so that a tie is not decided by
    round-off), numbered by where they first appear on the map and their speed there."""
    weighted = parts.weighted(roots.shapes)
    rows = np.arange(len(order))[:, None]
    forward = roots.forward[rows, order]
    speeds = np.where(forward, roots.omega[rows, order], np.nan)
    lowest = _lowest_forward(roots, count)[:, -1:]                                     # (G, 1), nan where fewer
    within = ~(roots.omega[rows, order] > lowest * (1 + _SAME_SPEED))                 # nan: fewer, all count
    shown = (forward & within)[mine].any(axis=0)
    present = forward[mine][:, shown]
    first = present.argmax(axis=0)
    chosen = np.nonzero(shown)[0][np.lexsort((speeds[mine][first, shown], first))]
    names = _mode_names(parts, grid, roots.shapes[rows, order[:, chosen]], forward[:, chosen])
    return _Followed(order[:, chosen], speeds[:, chosen], weighted[rows, order[:, chosen]], names)


#: two forward critical speeds closer than this (relative) are one rank: the mode counted among
#: the lowest whichever round-off puts first
_SAME_SPEED = 1e-9
#: stiffness values closer than this (relative) are one point of the mode following
_SAME_STIFFNESS = 1e-9


def _following_order(parts, roots, grid, mine, count) -> np.ndarray:
    """Follow every root over the grid (G,) [N/m] along its branch: ``order`` (G, m),
    ``order[i, label]`` the root of mode ``label`` at ``grid[i]``.

    The roots are followed on a finer grid than the user's (:func:`_inserted`): points are
    inserted (bisecting log k) wherever a step between neighbours leaves a root below the map's
    highest speed without a clear continuation, until every such root finds one (MAC above
    ``_CLEAR_MAC``), so the curves are the pencil's branches whatever the user's spacing: through
    a veering (shapes exchanged over a short range of k) a curve keeps its rank and changes its
    shape, where two modes do not couple they cross. Following by shape over a decade-wide step
    jumped across the veering instead: grids of 5 and 161 values joined the roots otherwise
    (``docs/level1_and_ucs.md``). Only the grid's own points are returned.

    Values closer than ``_SAME_STIFFNESS`` are one point of the following, the others' roots
    matched to its roots by their MAC (``scipy.optimize.linear_sum_assignment``): a step of one
    ulp (the user's 1e8 N/m moved by one ulp beside the bearings' own 1e8, a point of the grid
    too) was decided by round-off."""
    keep, owner = _distinct(grid)
    found = _Roots(*(x[keep] for x in roots))
    users = np.searchsorted(keep, owner[mine])                      # the user's points among the kept
    path = _Path(grid[keep], found, parts.weighted(found.shapes))
    limit = _highest_speed(found, users, count)
    while True:          # the shown modes' highest speed is known once they are followed
        _insert(parts, path, limit)
        order = path.order()
        highest = _shown_highest(_Roots(*(x[users] for x in found)), order[path.at()[users]], order[-1],
                                 path.omega[path.last()], count)
        if not highest > limit:
            break
        limit = highest
    order, weighted = order[path.at()][np.searchsorted(keep, owner)], path.weighted   # (G, m)
    for i in np.nonzero(owner != np.arange(len(grid)))[0]:
        reference = weighted[np.searchsorted(keep, owner[i])][order[i]]
        order[i] = linear_sum_assignment(-_vectors.mac_matrix(reference, parts.weighted(roots.shapes[i])))[1]
    return order


#: a step between neighbouring stiffness values is clear where each root below the map's
#: highest speed has a continuation (one root, or a group of equal ones) with a MAC above this
_CLEAR_MAC = 0.9
#: steps are halved (in log k) down to this relative width, no further: a veering narrower is a crossing
_FINEST_STEP = 1e-5
#: roots closer than this (relative) are one group, their shapes any basis of its space
_SAME_ROOT = 1e-7


def _highest_speed(found, users, count) -> float:
    """The highest of the ``count``-th lowest forward critical speeds at the user's points
    (rows ``users`` of ``found``) [rad/s]: the roots below it are followed with care first (inf
    where a point has fewer: all roots)."""
    low = _lowest_forward(_Roots(*(x[users] for x in found)), count)[:, -1]
    return float(np.inf if np.isnan(low).any() else low.max())


def _shown_highest(found, order, last, speeds, count) -> float:
    """The highest critical speed [rad/s] at the last point (``speeds`` (m,), the roots followed
    there by ``last`` (m,)) of the modes that are among the ``count`` lowest forward critical
    speeds at some of the user's points (``found`` there, each mode's roots ``order`` (U, m)):
    the roots below it must be followed with care (a mode's critical speed grows with k along
    its branch)."""
    rows = np.arange(len(order))[:, None]
    low = _lowest_forward(found, count)[:, -1:]
    omega = found.omega[rows, order]
    shown = (found.forward[rows, order] & ~(omega > low * (1 + _SAME_SPEED))).any(axis=0)
    highest = speeds[last[shown]]
    return float(highest[np.isfinite(highest)].max(initial=0.0))


class _Path:
    """The points the roots are followed on, and the steps between neighbours.

    Points are kept in the order they were made (the given ones first: ``at()``), each with its
    stiffness (``values``) [N/m], critical speeds ``omega`` (m,) [rad/s] (inf where none), signed
    ``nu^-1/2`` (``signed``) and mass-weighted unit shapes ``weighted`` (m, n); ``steps`` lists
    the pairs of neighbours in increasing stiffness, each with its MAC (m, m), its continuation
    (:func:`_assigned`) and whether it is unclear for the limit it was judged at."""

    def __init__(self, values, found, weighted):
        self.values, self.omega, self.signed, self.weighted = list(values), list(found.omega), list(found.signed), \
            list(weighted)
        self.given = len(values)
        self.steps = [(i, i + 1) for i in range(len(values) - 1)]
        self.correlation, self.assigned = self._judged(self.steps)
        self.judged = [None] * len(self.steps)                   # (limit, unclear) of each step

    def _judged(self, steps):
        if not steps:
            return [], []
        a, b = (np.array([self.weighted[i] for i in ends]) for ends in zip(*steps))
        correlation = list(_vectors.mac_matrix(a, b))
        return correlation, [_assigned(c) for c in correlation]

    def add(self, split, values, found, weighted):
        """New points ``values`` (s,) in the steps ``split`` (s,) (indices, increasing)."""
        new = []
        for s, value, omega, signed, shapes in zip(split, values, found.omega, found.signed, weighted):
            self.values.append(value), self.omega.append(omega), self.signed.append(signed)
            self.weighted.append(shapes)
            a, b = self.steps[s]
            new += [(a, len(self.values) - 1), (len(self.values) - 1, b)]
        correlation, assigned = self._judged(new)
        for j, s in enumerate(reversed(split)):             # from the end: the indices before stay
            k = 2 * (len(split) - 1 - j)
            self.steps[s:s + 1] = new[k:k + 2]
            self.correlation[s:s + 1] = correlation[k:k + 2]
            self.assigned[s:s + 1] = assigned[k:k + 2]
            self.judged[s:s + 1] = [None, None]

    def unclear(self, limit) -> np.ndarray:
        """:func:`_unclear` of every step (judged anew only where new or judged at another limit)."""
        todo = [i for i, j in enumerate(self.judged) if j is None or j[0] != limit]
        if todo:
            a, b = (np.array(x) for x in zip(*[self.steps[i] for i in todo]))
            flags = _unclear(np.array(self.omega)[a], np.array(self.omega)[b], np.array(self.signed)[a],
                             np.array(self.signed)[b], np.array([self.correlation[i] for i in todo]),
                             np.array([self.assigned[i] for i in todo]), limit)
            for i, flag in zip(todo, flags):
                self.judged[i] = (limit, bool(flag))
        return np.array([j[1] for j in self.judged], dtype=bool)

    def points(self) -> np.ndarray:
        """The points' indices in increasing stiffness."""
        return np.array([self.steps[0][0]] + [b for _, b in self.steps]) if self.steps else np.arange(self.given)

    def at(self) -> np.ndarray:
        """The given points' places in :meth:`points`."""
        return np.argsort(self.points())[:self.given]

    def last(self) -> int:
        return int(self.points()[-1])

    def order(self) -> np.ndarray:
        """``order`` (P, m): each root followed from each point to the next (in increasing
        stiffness) by its continuation."""
        m = len(self.omega[0])
        order = np.empty((len(self.steps) + 1, m), dtype=int)
        order[0] = np.arange(m)
        for i, step in enumerate(self.assigned):
            order[i + 1] = step[order[i]]
        return order


def _unclear(start, end, signed_start, signed_end, correlation, assigned, limit) -> np.ndarray:
    """Whether each step (S,) leaves a root below ``limit`` [rad/s] (at either end; a root's
    critical speed only grows with k) without a clear continuation: its MAC (``correlation``
    (S, m, m)) summed over a group of equal roots (``_SAME_ROOT``) at the other end at most
    ``_CLEAR_MAC`` with every such group; or its continuation (``assigned`` (S, m)) passing
    another root (:func:`_passing`): two roots that cross over a step may be a veering the step
    jumped (their shapes exchanged and back), told from a crossing only by a finer step.
    ``start``, ``end`` (S, m): the critical speeds at the steps' ends [rad/s] (inf where none),
    ``signed_start``, ``signed_end`` their signed ``nu^-1/2``."""
    def groups(signed):
        return np.abs(signed[:, :, None] - signed[:, None, :]) <= _SAME_ROOT * np.abs(signed[:, :, None])
    ahead = (correlation @ groups(signed_end)).max(axis=-1)                       # (S, m): row i's best group
    behind = (groups(signed_start) @ correlation).max(axis=-2)                    # (S, m): column j's
    below_start = np.isfinite(start) & (start <= limit)
    below_end = np.isfinite(end) & (end <= limit)
    vague = ((below_start & (ahead <= _CLEAR_MAC)) | (below_end & (behind <= _CLEAR_MAC))).any(axis=-1)
    return vague | np.array([_passing(*x) for x in zip(start, end, assigned, below_start)], dtype=bool)


def _assigned(correlation) -> np.ndarray:
    """The roots (m,) at the next point continuing each root by the optimal assignment of their
    MAC (m, m)."""
    return linear_sum_assignment(-correlation)[1]


def _passing(start, end, continued, below) -> bool:
    """Whether a root ``below`` (m,) bool, with critical speed ``start`` (m,) [rad/s] (increasing,
    inf where none), continued by ``end[continued]``, passes another root or is passed by one
    (speeds within ``_SAME_ROOT`` are equal)."""
    after = end[continued]
    finite = np.isfinite(start)
    after, below = after[finite], below[finite]
    lower_after = np.minimum.accumulate(after[::-1])[::-1]               # the lowest continuation of the roots above
    passed = np.r_[lower_after[1:], np.inf] < after * (1 - _SAME_ROOT)
    higher_before = np.maximum.accumulate(after)                          # the highest of the roots below
    passes = np.r_[-np.inf, higher_before[:-1]] > after * (1 + _SAME_ROOT)
    return bool(np.any(below & (passed | passes)))


def _insert(parts, path, limit) -> None:
    """Add to ``path`` the geometric middle of each unclear step (:func:`_unclear`), all of a
    round in one batched solve (not polished: only their shapes are used), until every step is
    clear or ``_FINEST_STEP`` wide."""
    while True:
        values = np.array(path.values)
        a, b = (np.array(x, dtype=int) for x in zip(*path.steps)) if path.steps else (np.zeros(0, int),) * 2
        split = np.nonzero(path.unclear(limit) & (values[b] > values[a] * (1 + _FINEST_STEP)))[0]
        if not len(split):
            return
        middle = np.sqrt(values[a[split]] * values[b[split]])
        new = parts.roots(middle, polish=False)
        path.add(split, middle, new, parts.weighted(new.shapes))


def _distinct(grid):
    """(keep, owner): the grid's values (G,) increasing, kept where farther than
    ``_SAME_STIFFNESS`` (relative) from the last kept one; ``owner[i]`` the kept value standing
    for ``grid[i]``."""
    keep, owner = [], np.empty(len(grid), dtype=int)
    for i, value in enumerate(grid):
        if not keep or value > grid[keep[-1]] * (1 + _SAME_STIFFNESS):
            keep.append(i)
        owner[i] = keep[-1]
    return np.array(keep, dtype=int), owner


#: a body's four motions, in the order of :func:`_body_energies`, as a rotor's and the stator's words
_ROTOR_MOTIONS = ("axial", "cylindrical", "conical", "torsional")
_STATOR_MOTIONS = ("axial", "lateral", "rocking", "roll")


def _body_energies(model, shapes) -> tuple:
    """Each body's kinetic energy in each shape (per unit frequency squared, times 2), split
    into the translation of its centre of mass along the spin axis and normal to it, and the
    rotation about the transverse axes (tilt) and about the spin axis.

    Parameters
    ----------
    shapes : ndarray, shape (..., n), complex

    Returns
    -------
    names : list of str
        'stator' (when there is one), then the rotors.
    energies : ndarray, shape (..., B, 4) [kg m^2]
        Axial and lateral translation, tilt and spin-axis rotation.
    """
    bodies = body_inertias(model)
    names = (["stator"] if model.stator is not None else []) + [r.name for r in model.rotors]
    motions = model.dofs.motions([(None if name == "stator" else name, False) for name in names])  # (B, 6, n)
    arms = np.array([np.asarray(c, dtype=float) for _, c, _ in bodies]) - model.reference_point
    centres = motions[:, :3] - np.einsum("bij,bjn->bin", skew(arms), motions[:, 3:])  # u + theta x r
    moves = np.einsum("bin,...n->...bi", centres, shapes)
    turns = np.einsum("bin,...n->...bi", motions[:, 3:], shapes)
    masses = np.array([m for m, _, _ in bodies], dtype=float)
    inertias = np.array([np.asarray(j, dtype=float) for _, _, j in bodies])
    e = np.asarray(model.spin_axis, dtype=float)
    along = masses * np.abs(moves @ e) ** 2
    rotation = np.einsum("...bi,bij,...bj->...b", turns.conj(), inertias, turns).real
    roll = np.einsum("i,bij,j->b", e, inertias, e) * np.abs(turns @ e) ** 2
    translation = masses * np.sum(np.abs(moves) ** 2, axis=-1)
    return names, np.stack([along, translation - along, rotation - roll, roll], axis=-1)


def _mode_names(parts, grid, shapes, present) -> tuple:
    """A short name of each followed mode from its shapes (G, L, n) at the grid's stiffness
    values (G,) [N/m] where it is on the map (``present`` (G, L)): its name at each point
    (:func:`_point_names`) at the curve's two ends, ``'A -> B'`` where they differ (a rigid-body
    mode on soft bearings turning into a bending mode on stiff ones, the rotor's name then in
    both). A name by most points hid that change: a curve named 'pump conical' ended as the
    shaft's bending mode."""
    words = _point_names(parts, grid, shapes)
    out = []
    for j in range(words.shape[1]):
        here = words[present[:, j], j]
        if not len(here):
            out.append("")
        else:
            out.append(str(here[0]) if here[0] == here[-1] else f"{here[0]} -> {here[-1]}")
    return tuple(out)


def _point_names(parts, grid, shapes) -> np.ndarray:
    """Each shape's name (G, L) at the grid's stiffness values (G,) [N/m]: the body with the most
    kinetic energy and its motion that carries the most of it (a rotor's 'axial',
    'cylindrical', 'conical' or 'torsional', the stator's 'axial', 'lateral', 'rocking' or
    'roll'); a flexible rotor's motion is 'bending' where its shafts store more than
    ``modal.BENDING_FRACTION`` of the shape's strain energy at that stiffness."""
    from ..assembly import shaft_stiffness
    from .modal import BENDING_FRACTION

    model = parts.model
    names, energies = _body_energies(model, shapes)
    body = np.argmax(energies.sum(axis=-1), axis=-1)                                      # (G, L)
    motion = np.take_along_axis(energies, body[..., None, None], axis=-2)[..., 0, :].argmax(axis=-1)
    kinds = np.array([[f"{name} {word}" for word in (_STATOR_MOTIONS if name == "stator" else _ROTOR_MOTIONS)]
                      for name in names])
    words = kinds[body, motion]
    flexible = np.array([name != "stator" and model.rotor(name).flexible is not None for name in names])
    if not flexible.any():
        return words
    strain = _strain(shapes, shaft_stiffness(model))
    total = _strain(shapes, parts.rest) + np.asarray(grid, dtype=float)[:, None] * _strain(shapes, parts.unit)
    with np.errstate(divide="ignore", invalid="ignore"):
        bent = flexible[body] & (strain > BENDING_FRACTION * total)
    bending = np.array([f"{name} bending" for name in names])
    return np.where(bent, bending[body], words)


def _strain(shapes, K):
    """``Re(phi^H K phi)`` (G, L) of shapes (G, L, n), twice the strain energy."""
    return np.einsum("gln,gln->gl", shapes.conj(), shapes @ K.T).real


def _constant_values(chosen) -> np.ndarray:
    """The chosen constant bearings' direct radial stiffness values > 0 [N/m]."""
    values = [_direct(b.coefficients.stiffness[:1], _radial_axes(b)) for b in chosen
              if b.coefficients.kind == "constant"]
    values = np.array(values, dtype=float).ravel()
    return values[values > 0]


def _constant_crossings(curves, grid, followed) -> list:
    """A constant bearing's vertical line meets every shown mode that is a forward critical
    speed at its stiffness (a point of the grid)."""
    out = []
    for curve in curves:
        if not curve.constant:
            continue
        for axis, values in (("xx", curve.kxx), ("yy", curve.kyy)):
            if values[0] <= 0:
                continue
            row = followed.speeds[np.searchsorted(grid, values[0])]
            out += [Crossing(curve.name, axis, j + 1, float(values[0]), float(s), followed.names[j])
                    for j, s in enumerate(row) if np.isfinite(s)]
    return out


#: find the speed-dependent bearings' crossings on Rayleigh-Ritz subspaces, each finished on the whole
#: pencil (:mod:`._ucs_ritz`); False: always today's route (:func:`_curve_crossings`: the whole pencil
#: solved at each curve point and each refinement step), which the subspace route falls back to
SUBSPACE_CROSSINGS = True


def _curve_crossings_all(parts, curves, grid, followed) -> list:
    """Where each speed-dependent bearing's Kxx and Kyy curves meet each shown mode's curve: on a
    subspace where it shows it sees every crossing (:func:`._ucs_ritz.subspace_crossings`), else by
    :func:`_curve_crossings`."""
    from ._ucs_ritz import subspace_crossings

    out = []
    for curve in curves:
        if curve.constant:
            continue
        axes = [(axis, curve.speeds[values > 0], values[values > 0])
                for axis, values in (("xx", curve.kxx), ("yy", curve.kyy)) if (values > 0).any()]
        rules = (Crossing, _matched, _SAME_MODE_MAC)
        found = subspace_crossings(parts, curve, axes, grid, followed, rules) if SUBSPACE_CROSSINGS and axes else None
        if found is None:
            found = [c for axis, speeds, values in axes
                     for c in _curve_crossings(parts, curve, axis, speeds, values, grid, followed)]
        out += found
    return out


#: a root at a point of a bearing curve is a shown mode when its MAC with the mode's shape at the
#: nearest stiffness of the map's grid is above this
_SAME_MODE_MAC = 0.5


def _matched(parts, roots, reference):
    """Each reference shape's root among ``roots`` (S points): the largest MAC, above
    ``_SAME_MODE_MAC`` and forward, else none.

    Parameters
    ----------
    roots : _Roots, S points
    reference : ndarray, shape (S, L, n), mass-weighted unit shapes

    Returns
    -------
    speeds : ndarray, shape (S, L) [rad/s], nan where none
    index : ndarray of int, shape (S, L)
    """
    correlation = _vectors.mac_matrix(reference, parts.weighted(roots.shapes))         # (S, L, m)
    index = correlation.argmax(axis=-1)
    best = np.take_along_axis(correlation, index[..., None], axis=-1)[..., 0]
    points = np.arange(len(index))[:, None]
    good = (best > _SAME_MODE_MAC) & roots.forward[points, index]
    return np.where(good, roots.omega[points, index], np.nan), index


def _curve_crossings(parts, curve, axis, speeds, values, grid, followed):
    """Sign changes of ``critical(K(s)) - s`` of each shown mode along a bearing curve (the mode
    found at each point by its shape at the nearest grid stiffness), refined on the curve as
    drawn (its stiffness interpolated linearly between its points), the mode followed inside the
    bracket by its shape at the bracket's start: all brackets together (:func:`_refined`)."""
    roots = parts.roots(values)
    nearest = np.abs(np.log(values)[:, None] - np.log(grid)[None, :]).argmin(axis=-1)
    at, index = _matched(parts, roots, followed.weighted[nearest])                    # (S, L)
    brackets = []
    for j in range(at.shape[1]):
        gap = at[:, j] - speeds
        brackets += [(i, j) for i in np.nonzero(np.isfinite(gap[:-1]) & np.isfinite(gap[1:])
                                                & (np.sign(gap[:-1]) != np.sign(gap[1:])))[0]]
    if not brackets:
        return []
    starts, modes = (np.array(x, dtype=int) for x in zip(*brackets))
    shapes = parts.weighted(roots.shapes[starts, index[starts, modes]])               # (P, n)
    found = _refined(parts, speeds, values, starts, shapes)
    out = []
    for i, j, s in zip(starts, modes, found):
        t = (s - speeds[i]) / (speeds[i + 1] - speeds[i])
        out.append(Crossing(curve.name, axis, int(j) + 1, float((1 - t) * values[i] + t * values[i + 1]), float(s),
                            followed.names[j]))
    return out


#: relative step (of the speed) at which the vectorised regula falsi of :func:`_refined` stops,
#: and its most iterations
_REFINE_RTOL = 1e-13
_REFINE_STEPS = 60


def _along(parts, speeds, values, starts, shapes, s):
    """``critical(K(s)) - s`` (P,) [rad/s] of each bracket's mode (its shape ``shapes`` (P, n))
    at reference speeds ``s`` (P,) inside the brackets ``speeds[starts]``, ``speeds[starts + 1]``,
    the stiffness interpolated linearly: one batched solve; nan where the mode is lost."""
    low, high = speeds[starts], speeds[starts + 1]
    t = (s - low) / (high - low)
    roots = parts.roots((1 - t) * values[starts] + t * values[starts + 1])
    return _matched(parts, roots, shapes[:, None])[0][:, 0] - s


def _refined(parts, speeds, values, starts, shapes):
    """The crossing speed (P,) [rad/s] in each bracket ``speeds[starts]``, ``speeds[starts + 1]``:
    the Illinois regula falsi on all brackets at once, one batched eigen-solve per step (the
    tracked mode's critical speed is smooth in the stiffness: superlinear), converged to
    ``_REFINE_RTOL``. A bracket whose mode is lost (nan) or whose ends do not change sign is left
    to Brent's method one solve at a time, as before (the bracket's start if that fails too)."""
    a, b = speeds[starts].astype(float), speeds[starts + 1].astype(float)
    fa, fb = np.split(_along(parts, speeds, values, np.r_[starts, starts], np.r_[shapes, shapes], np.r_[a, b]), 2)
    active = np.isfinite(fa) & np.isfinite(fb) & (np.sign(fa) != np.sign(fb))
    slow = ~active
    done = active & ((fa == 0) | (fb == 0))
    best = np.where(fa == 0, a, b)
    active &= ~done
    for _ in range(_REFINE_STEPS):
        if not active.any():
            break
        p = np.nonzero(active)[0]
        c = b[p] - fb[p] * (b[p] - a[p]) / (fb[p] - fa[p])
        fc = _along(parts, speeds, values, starts[p], shapes[p], c)
        lost = ~np.isfinite(fc)
        slow[p[lost]], active[p[lost]] = True, False
        keep = ~lost
        p, c, fc = p[keep], c[keep], fc[keep]
        flip = np.sign(fc) != np.sign(fb[p])
        a[p] = np.where(flip, b[p], a[p])
        fa[p] = np.where(flip, fb[p], 0.5 * fa[p])            # Illinois: halve the kept end's value
        step = np.abs(c - b[p])
        b[p], fb[p] = c, fc
        best[p] = c
        finished = (fc == 0) | (step <= _REFINE_RTOL * np.abs(c))
        active[p[finished]] = False
    slow |= active                                              # not converged: Brent's method
    for q in np.nonzero(slow)[0]:
        best[q] = _brent(parts, speeds, values, starts[q], shapes[q])
    return best


def _brent(parts, speeds, values, i, shape):
    """One bracket's crossing by Brent's method, one solve per evaluation (the bracket's start
    where the mode is lost)."""
    def along(s):
        return _along(parts, speeds, values, np.array([i]), shape[None], np.array([s]))[0]
    try:
        return brentq(along, speeds[i], speeds[i + 1], xtol=1e-10 * speeds[i + 1])
    except ValueError:       # the mode is lost in between (nan): the grid point
        return speeds[i]


def _rigid_support(parts, model, chosen, modes, supports_fixed=False):
    """Forward critical speeds with the chosen bearings radially rigid: each rotor pinned to the
    stator at its chosen bearings' points (two pins fix its lateral motion and tilt; the axial
    and tilt stiffness stay as given): the limit of the map as ``k`` grows without bound. The
    coordinates are restricted to the null space of the pins' radial relative motions; with
    ``supports_fixed`` the stator (or frame) and the chosen bearings' pedestals are held too
    (API 617's rigid-support critical speed, :func:`rotordyn_modal.analysis.level1.rigid_support_critical_speed`).

    Returns
    -------
    ndarray, shape (modes,) [rad/s]
        The ``modes`` lowest, nan where there are fewer (all nan when the pins hold everything).
    """
    n = parts.M.shape[0]
    layout = model.dofs
    pins = [np.eye(layout.n_frame, n)] if supports_fixed else []
    for bearing in chosen:
        rows, moves = bearing_motion(model, bearing)
        block = np.zeros((6, n))
        block[:, rows] = _RADIAL_OF(model) @ moves
        pins.append(block[:3])
        pedestal = layout.pedestal(bearing.name) if supports_fixed else None
        if pedestal is not None:
            pins.append(np.eye(n)[pedestal])
    T = scipy.linalg.null_space(np.vstack(pins))
    if not T.shape[1]:
        return np.full(modes, np.nan)
    forms = _whirl.WhirlForms(*(T.T @ X @ T for X in parts.forms))
    return forward_critical_speeds(T.T @ parts.M @ T, T.T @ parts.G @ T, (T.T @ parts.rest @ T)[None],
                                   forms, modes)[0]


def _RADIAL_OF(model):
    """(6, 6): the translations normal to the spin axis (radial), nothing else."""
    e = np.asarray(model.spin_axis, dtype=float)
    radial = np.zeros((6, 6))
    radial[:3, :3] = np.eye(3) - np.outer(e, e)
    return radial
