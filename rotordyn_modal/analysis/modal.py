"""Modal analysis at one speed: eigenvalues, frequencies, damping, whirl, shapes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..model.flexible import ENERGY_ROUND_OFF as _ENERGY_ROUND_OFF
from ..model.geometry import point_motion_row
from ..linear_system import speed_linear_form
from .. import _arguments
from . import _batches, _eigensolve, _roots, _vectors, _whirl

__all__ = ["ModalResult", "modal", "mac", "modal_quantities", "is_oscillating", "OVERDAMPED_LIMIT",
           "strain_energy_fractions", "BENDING_FRACTION"]

#: a root whose damping ratio exceeds this is overdamped: listed apart, never drawn as a mode
#: (log decrement above 44: the motion dies within a fraction of a period)
OVERDAMPED_LIMIT = 0.99
#: a mode with more than this fraction of its strain energy in the shafts is a bending mode
#: (the threshold of ``check``'s "first mostly bending" frequency too)
BENDING_FRACTION = 0.5
#: the ``kind`` of a mode that is not a bending mode, by the part holding most of its strain energy
_KINDS = {"bearings": "rigid-body", "mounts": "suspension", "pedestals": "pedestal", "meshes": "gear-mesh"}


def is_oscillating(eigenvalues) -> np.ndarray:
    """True for roots that are modes: ``Im lam > 0`` and damping ratio at most
    :data:`OVERDAMPED_LIMIT`. Real roots (rigid-body zeros, relaxations of rubber
    mounts) and near-critically damped pairs are not.

    The one test of every analysis. It reads each root alone: the eigen-solves have already made
    zero roots and imaginary parts within their own round-off exactly 0
    (:func:`._roots.snapped`, ``docs/theory.md`` section 8), so no other root decides.

    Parameters
    ----------
    eigenvalues : array_like, complex [1/s]

    Returns
    -------
    ndarray of bool, same shape
    """
    lam = np.asarray(eigenvalues)
    # where Im lam > 0, |lam| > 0 and the damping ratio is a number
    return (lam.imag > 0) & (damping_ratios(lam) <= OVERDAMPED_LIMIT)


def modal_quantities(eigenvalues):
    """Frequencies [Hz], damping ratios and log decrements from eigenvalues.

    Parameters
    ----------
    eigenvalues : array_like, complex [1/s]

    Returns
    -------
    frequencies_hz, damping_ratios, log_decrements : ndarray, same shape
        ``Im(lam) / 2 pi``, ``-Re(lam) / |lam|`` and ``-2 pi Re(lam) / Im(lam)``
        (inf where the mode does not oscillate, nan where lam = 0).
    """
    lam = np.asarray(eigenvalues)
    zeta = damping_ratios(lam)
    real, imag = lam.real, lam.imag
    # inf, -inf or nan by the sign of the real part where the root does not oscillate
    log_dec = np.where(real < 0, np.inf, np.where(real > 0, -np.inf, np.nan))
    with np.errstate(invalid="ignore"):
        np.divide(-2 * np.pi * real, imag, out=log_dec, where=imag > 0)
    return imag / (2 * np.pi), zeta, log_dec


def damping_ratios(eigenvalues) -> np.ndarray:
    """Damping ratios ``-Re(lam) / |lam|`` (nan where lam = 0) of eigenvalues [1/s], same shape
    (the damping ratios of :func:`modal_quantities`)."""
    lam = np.asarray(eigenvalues)
    magnitude = np.abs(lam)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(magnitude > 0, -lam.real / np.where(magnitude > 0, magnitude, 1), np.nan)


@dataclass(frozen=True)
class ModalResult:
    """Modes of the machine at one speed, sorted by frequency.

    Attributes
    ----------
    speed : float
        Reference rotor speed [rad/s].
    eigenvalues : ndarray, shape (n_roots,), complex [1/s]
        One of each conjugate pair (Im >= 0), and the real roots.
    frequencies_hz, damping_ratios, log_decrements : ndarray, shape (n_roots,)
    whirl_ratios : ndarray, shape (n_roots,)
        The machine's: +1 circular forward, -1 circular backward, 0 straight line
        (vs the reference spin); 0 for roots that do not oscillate.
    whirl : ndarray of str, shape (n_roots,)
        'forward', 'backward' or 'none'.
    shapes : ndarray, shape (n_roots, n), complex
        Over the generalized coordinates ``dof_names`` (the stator's
        ``[u_x, u_y, u_z, theta_x, theta_y, theta_z]`` at the reference point, then
        each rotor on bearings) [m, rad], unit mass-weighted norm, largest component real.
    reference_point : ndarray, shape (3,) [m]
    oscillatory : ndarray of bool, shape (n_roots,)
        The roots that are modes (see :func:`is_oscillating`); the others are
        rigid-body or relaxation roots, or overdamped.
    dof_names : tuple of str, length n
    rotor_names : tuple of str
    rotor_whirl_ratios : ndarray, shape (n_roots, n_rotors)
        Whirl ratio of each rotor's own (absolute) motion.
    body_motions : ndarray, shape (1 + n_rotors, 6, n)
        Rigid motion at the reference point of the stator, then of each rotor,
        per generalized coordinate (used by :meth:`shape_at`).
    round_off : float
        Round-off of the eigen-solve's eigenvalues [1/s] (:func:`._roots.round_off`).
    whirl_round_off : ndarray, shape (n_roots,)
        How far round-off can move each whirl ratio; within it the ratio is 0 on the terminal and
        the whirl 'none' (:func:`._roots.whirl_round_off`).
    dofs : Dofs, optional
        The model's coordinates, for a point of a flexible rotor in :meth:`shape_at` (its node's
        motion there; ``body_motions`` holds its node nearest its centre of mass).
    energy_parts : tuple of str
        Where strain energy is stored: those of ``'shaft'``, ``'bearings'``, ``'mounts'`` the
        model has (:func:`strain_energy_fractions`); empty (and ``energy_fractions`` None) for a
        model without a flexible rotor.
    energy_fractions : ndarray, shape (n_roots, n_parts), optional
        Each root's strain energy ``1/2 Re(phi^H K_part phi)`` in each part over the sum of all
        parts (rows sum to 1; nan where the shape strains nothing).
    state_real_roots : int, optional
        Real roots of the whole state matrix (round-off-split pairs counted as the real roots
        they are, docs/theory.md section 8); ``eigenvalues`` keeps the half of them nearest zero
        (:attr:`real_roots`), as it keeps one root of each pair. None where not known (a result
        not solved from a state matrix).
    unresolved_roots : int
        Roots of the state matrix below its round-off whose shapes their own stiffness loads but
        does not resolve (``docs/theory.md`` section 8): zero roots here, among the real roots,
        that may be slow modes the solve cannot tell (``modes`` says so on stderr).
    conservative : bool
        The machine has no damping and a symmetric positive semidefinite stiffness at this speed
        (:func:`._roots.conservative`): every root lies on the imaginary axis, so every real part
        (and damping ratio, log decrement) is round-off, however large (a 1 g casing under a
        1e9 kg rotor on stiff bearings: damping ratios of -0.079 and +0.079), and
        :meth:`to_dataframe` marks those columns so.
    """

    speed: float
    eigenvalues: np.ndarray
    frequencies_hz: np.ndarray
    damping_ratios: np.ndarray
    log_decrements: np.ndarray
    whirl_ratios: np.ndarray
    whirl: np.ndarray
    shapes: np.ndarray
    reference_point: np.ndarray
    oscillatory: np.ndarray
    dof_names: tuple = ()
    rotor_names: tuple = ()
    rotor_whirl_ratios: np.ndarray | None = None
    body_motions: np.ndarray | None = None
    round_off: float = 0.0
    whirl_round_off: np.ndarray | None = None
    dofs: Any = None
    energy_parts: tuple = ()
    energy_fractions: np.ndarray | None = None
    state_real_roots: int | None = None
    unresolved_roots: int = 0
    conservative: bool = False

    @property
    def kinds(self) -> np.ndarray:
        """Each root's kind by its strain energy, shape (n_roots,): ``'bending'`` when more than
        :data:`BENDING_FRACTION` of it is in the shafts, else ``'rigid-body'`` (most in the
        bearings: the rotors move nearly rigidly on them), ``'suspension'`` (most in the
        mounts), ``'pedestal'`` or ``'gear-mesh'``; ``'none'`` where the shape strains nothing."""
        fractions = self.energy_fractions
        if fractions is None or not self.energy_parts:
            return np.full(len(self.eigenvalues), "none", dtype=object)
        parts = list(self.energy_parts)
        others = [i for i, p in enumerate(parts) if p != "shaft"]
        out = np.full(len(self.eigenvalues), "none", dtype=object)
        for m, row in enumerate(fractions):
            if not np.all(np.isfinite(row)):
                continue
            if "shaft" in parts and row[parts.index("shaft")] > BENDING_FRACTION:
                out[m] = "bending"
            elif others:
                out[m] = _KINDS[parts[max(others, key=lambda i: row[i])]]
        return out

    @property
    def rotor_whirl(self) -> np.ndarray:
        """'forward', 'backward' or 'none' for each rotor, shape (n_roots, n_rotors)."""
        return _whirl.whirl_labels(self.rotor_whirl_ratios)

    def shape_at(self, point, direction=None, body=None, relative: bool = False) -> np.ndarray:
        """Mode shapes at a point of the stator or of a rotor.

        Parameters
        ----------
        point : array_like, shape (3,) [m], model axes
        direction : array_like, shape (3,), optional
            If given, the component along this (normalised) direction.
        body : str, optional
            A rotor name; default the stator.
        relative : bool
            The rotor's motion relative to the stator point at the same place.

        Returns
        -------
        ndarray, shape (n_roots, 3) or (n_roots,), complex [m per unit modal amplitude]
        """
        motion = self._motion(body, relative, point)
        rows = np.array([point_motion_row(point, self.reference_point, axis) for axis in np.eye(3)])
        motion = self.shapes @ (rows @ motion).T
        if direction is None:
            return motion
        d = np.asarray(direction, dtype=float)
        return motion @ (d / np.linalg.norm(d))

    def _motion(self, body, relative, point=None):
        if body is None or body == "stator":
            return self.body_motions[0]
        if body not in self.rotor_names:
            from ..errors import InputError

            raise InputError(f"body {body!r}: expected None (the stator) or one of the rotors "
                             + ", ".join(self.rotor_names))
        if point is not None and self.dofs is not None and self.dofs.shaft(body) is not None:
            motion = self.dofs.motions([(body, False, tuple(np.asarray(point, dtype=float).tolist()))])[0]
            return motion - self.body_motions[0] if relative else motion
        motion = self.body_motions[1 + self.rotor_names.index(body)]
        return motion - self.body_motions[0] if relative else motion

    def to_dataframe(self, oscillatory_only: bool = True):
        """Table with the command line's columns (``pandas.DataFrame``)."""
        import pandas as pd

        keep = self.oscillatory if oscillatory_only else np.ones_like(self.oscillatory)
        table = pd.DataFrame({
            "mode": np.arange(1, keep.sum() + 1),
            "frequency_hz": self.frequencies_hz[keep],
            "damping_ratio": self.damping_ratios[keep] + 0.0,        # + 0.0: never -0
            "log_decrement": self.log_decrements[keep] + 0.0,
            "whirl": self.whirl[keep],
            "whirl_ratio": self.whirl_ratios[keep] + 0.0,
            "real_part": self.eigenvalues.real[keep] + 0.0,
        })
        if "shaft" in self.energy_parts:          # a flexible rotor: where each mode stores its strain energy
            # a mode that strains nothing to round-off (a free machine's rigid-body motion) has no
            # fractions: 0 in every column, its kind 'none' (cli modes says so in a line)
            fractions = np.nan_to_num(self.energy_fractions[keep], nan=0.0)
            for i, part in enumerate(self.energy_parts):
                table[_ENERGY_COLUMNS[part]] = fractions[:, i] + 0.0
            table["kind"] = self.kinds[keep]
        table.attrs["round_off"] = _constant_round_off(self._round_off_columns(keep))
        return table

    def round_off_rows(self, oscillatory_only: bool = True) -> dict:
        """What round-off can move each column of :meth:`to_dataframe` by, row by row.

        Returns
        -------
        dict of str -> ndarray, shape (rows of ``to_dataframe(oscillatory_only)``,)
            In the column's unit. The terminal prints values within it as 0
            (``cli._common.print_table``); the table's ``attrs['round_off']`` keeps only the
            columns where it is one number for every row.
        """
        return self._round_off_columns(self.oscillatory if oscillatory_only else np.ones_like(self.oscillatory))

    def _round_off_columns(self, keep) -> dict:
        """What round-off can move each column's values by, row by row (the terminal prints those
        within it as 0; see ``cli._common.print_table``)."""
        lam = self.eigenvalues[keep]
        with np.errstate(divide="ignore", invalid="ignore"):
            noise = {"real_part": np.full(len(lam), self.round_off),
                     "damping_ratio": self.round_off / np.abs(lam),
                     "log_decrement": 2 * np.pi * self.round_off / lam.imag}
        if self.conservative:            # every root on the imaginary axis: any real part is round-off
            noise.update({column: np.full(len(lam), np.inf) for column in ("real_part", "damping_ratio", "log_decrement")})
        if self.whirl_round_off is not None:
            noise["whirl_ratio"] = self.whirl_round_off[keep]
        for part in self.energy_parts:           # fractions of sums of products of unit shapes
            noise[_ENERGY_COLUMNS[part]] = np.full(len(lam), 1e-12)
        return noise

    @property
    def real_roots(self) -> np.ndarray:
        """(n_roots,) bool: real roots (relaxation roots of rubber mounts, zero roots of directions
        without suspension): not modes."""
        return self.eigenvalues.imag == 0

    @property
    def overdamped(self) -> np.ndarray:
        """(n_roots,) bool: complex roots damped beyond :data:`OVERDAMPED_LIMIT` (not modes)."""
        return (self.eigenvalues.imag > 0) & ~self.oscillatory

    def plot(self, **kwargs):
        """Bar chart of the modes' DOF participation; see :func:`rotordyn_modal.plotting.plot_modes`."""
        from ..plotting import plot_modes

        return plot_modes(self, **kwargs)

    def plot_shape(self, mode: int, model, scale=None, outline=None, **kwargs):
        """3D figure of one mode (number as in :meth:`to_dataframe`) on the model's geometry;
        see :func:`rotordyn_modal.analysis.mode_shapes.mode_shape_3d` and
        :func:`rotordyn_modal.plotting.plot_mode_shape`."""
        from .mode_shapes import mode_shape_3d

        return mode_shape_3d(self, model, mode, scale=scale, outline=outline).plot(**kwargs)

    def plot_shaft_lines(self, model, modes=None, **kwargs):
        """Deflected shaft lines of ``modes`` (numbers as in :meth:`to_dataframe`; default the
        first six), one panel each; see :func:`rotordyn_modal.analysis.mode_shapes.shaft_lines`
        and :func:`rotordyn_modal.plotting.plot_shaft_modes`."""
        from ..plotting import plot_shaft_modes
        from .mode_shapes import shaft_lines

        modes = range(1, min(int(self.oscillatory.sum()), 6) + 1) if modes is None else modes
        return plot_shaft_modes([shaft_lines(self, model, m) for m in modes], **kwargs)

    def animate(self, mode: int, model, path=None, scale=None, outline=None, **kwargs):
        """Animation of one mode, written to ``path`` (.gif, .html, .mp4) if given; see
        :func:`rotordyn_modal.plotting.animate_mode_shape`."""
        from .mode_shapes import mode_shape_3d

        return mode_shape_3d(self, model, mode, scale=scale, outline=outline).animate(path, **kwargs)


def _rotor_whirl_ratios(model, shapes, speed) -> np.ndarray:
    """Each rotor's own whirl ratio of every shape (m, n) -> (m, R). A rotor's whirl forms read
    the coordinates its motion moves with (the frame's and its own) alone, so each is made and
    taken on those columns of the shapes: made over all n, a chain of 500 rigid rotors (2,006
    coordinates) took 500 products of (4,012 x 2,006) by (2,006 x 6,018), longer than its
    eigen-solution, and a chain of 100 rotors 2.6 s of CPU time to make its forms alone."""
    out = np.zeros((len(shapes), len(model.rotors)))
    bodies = None
    for k, rotor in enumerate(model.rotors):
        if rotor.flexible is not None:
            forms = _whirl.rotor_whirl_forms(model, rotor.name)
            used = np.flatnonzero(np.any([(f != 0).any(axis=0) | (f != 0).any(axis=1) for f in forms], axis=0))
            own = _whirl.WhirlForms(*(f[np.ix_(used, used)] for f in forms))
        else:                                   # _whirl.rotor_whirl_forms on the columns it reads
            if bodies is None:
                bodies = _whirl._bodies_forms(model)
            body = bodies[:, bodies.shape[1] - len(model.rotors) + k]                 # (3, 6, 6)
            motion = model.dofs.body_motion(rotor.name)
            used = np.flatnonzero((motion != 0).any(axis=0))
            if not len(used):               # held to the ground (no bearings, no [stator]): it does not whirl
                continue
            motion = motion[:, used]
            own = _whirl.WhirlForms(*(motion.T @ body[d] @ motion for d in range(len(body))))
        out[:, k] = _whirl.whirl_ratios(shapes[None][..., used], own, np.array([speed]))[0]
    return out


def _refine_inexact(form, speed, values, shapes, stacklevel=4, whirl=None) -> np.ndarray | None:
    """The roots ``values`` (m,) with shapes (m, n) at ``speed`` [rad/s] whose double-precision
    round-off (:func:`._eigensolve.pencil_round_off`) exceeds :data:`._eigensolve.POLISH_LEVEL`:
    polished in place (:func:`._eigensolve.refined_pairs`), those left over
    :data:`._eigensolve.INEXACT_LEVEL` warned of; ``whirl`` (m,), where given, the whirl ratios'
    round-off, the polished roots' made their own in place;
    returns the error left (m,) (a model with Maxwell branches: on its rational pencil)."""
    bound, damping, stiffness, branches = _eigensolve.round_off_at(form, speed, values, shapes)
    bound = _eigensolve.refined_pairs(values, shapes, form.matrices.M, damping, stiffness, bound, branches=branches,
                                        whirl=whirl)
    oscillating = is_oscillating(values)
    # the numbers modes' table prints: the modes counted in order, the real roots apart
    _eigensolve.warn_of_inexact_roots([speed], bound[None], stacklevel=stacklevel, oscillating=oscillating[None],
                                      labels=np.cumsum(oscillating)[None], values=np.asarray(values)[None])
    return bound


def modal(model, speed: float = 0.0) -> ModalResult:
    """Modal analysis at one speed.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s]; negative reverses every rotor's spin.

    Returns
    -------
    ModalResult
    """
    speed = _arguments.speed(speed)
    form = speed_linear_form(model)
    matrix = form.at(speed)
    # one BLAS thread, as every dense eigen-solution runs and as its estimate times it
    # (analysis/_cost.py): OpenBLAS's own threads cost 6-20 times the CPU on a shared machine
    with _batches.one_blas_thread(72 * matrix.shape[-1] ** 2):
        values, vectors = _eigensolve.eig(matrix)      # scipy.linalg.eig's, the GIL released (a clock ticks)
    n = form.n_dof
    noise = float(_roots.round_off(matrix))
    snapped, own, refined = _roots.snapped_with_round_off(values, noise, matrix, vectors, n, form.matrices.M)
    upper = _eigensolve.select_upper(snapped)
    # the LAPACK vectors of the chosen eigenvalues (nearest match; values are identical)
    index = [int(np.argmin(np.abs(values - lam))) for lam in upper]
    index = _unique_indices(index, values, upper)
    forms = _whirl.whirl_forms(model)
    shapes = vectors[:n, index].T
    # the whirl's round-off is the solve's, as the sweeps take it (_eigensolve.solve_batch): from
    # the roots before the polish moves them off their own copies in ``refined``; a polished
    # root's is its own (_eigensolve.polished_ratio_round_off), as the sweeps' polish makes it
    ratio_noise = _roots.whirl_round_off(upper, refined, noise, _eigensolve.REPEATED_TOLERANCE * np.abs(upper).max(),
                                         np.broadcast_to(own, values.shape)[index])
    _refine_inexact(form, speed, upper, shapes, whirl=ratio_noise)
    shapes = _eigensolve.resolve_repeated(upper[None], shapes[None], forms)[0]
    shapes = _normalise(shapes, form.matrices.M)
    oscillatory = is_oscillating(upper)
    ratios = np.where(oscillatory, _whirl.whirl_ratios(shapes[None], forms, np.array([speed]))[0], 0.0)
    rotor_ratios = _rotor_whirl_ratios(model, shapes, speed) * oscillatory[:, None]
    freq, zeta, log_dec = modal_quantities(upper)
    layout = model.dofs
    # the split is a flexible rotor's question (and costs a rigid machine's small modal analysis
    # ~10 %): computed with one only; strain_energy_fractions gives it for any model
    parts, fractions = strain_energy_fractions(model, speed, shapes, upper) if layout.shafts else ((), None)
    return ModalResult(
        speed=float(speed), eigenvalues=upper, frequencies_hz=freq, damping_ratios=zeta,
        log_decrements=log_dec, whirl_ratios=ratios,
        whirl=_whirl.whirl_labels(ratios, ratio_noise),
        shapes=shapes, reference_point=np.asarray(model.reference_point), oscillatory=oscillatory,
        dof_names=layout.names, rotor_names=tuple(r.name for r in model.rotors),
        rotor_whirl_ratios=rotor_ratios,
        body_motions=np.array([layout.frame_motion()] + [layout.body_motion(r.name) for r in model.rotors]),
        round_off=noise, whirl_round_off=ratio_noise, dofs=layout if layout.shafts else None,
        energy_parts=parts, energy_fractions=fractions, state_real_roots=int((snapped.imag == 0).sum()),
        unresolved_roots=_roots.unresolved_roots(values, noise, matrix, vectors, n, form.matrices.M),
        conservative=bool(_roots.conservative(form, [speed])[0]),
    )


#: the table's column of each part's fraction of the strain energy
_ENERGY_COLUMNS = {"shaft": "shaft_energy", "bearings": "bearing_energy", "mounts": "mount_energy",
                   "pedestals": "pedestal_energy", "meshes": "mesh_energy"}


def strain_energy_fractions(model, speed: float, shapes, eigenvalues):
    """Where each mode stores its strain (potential) energy: ``1/2 Re(phi^H K_part phi)`` in the
    shafts, the bearings and the mounts, over their sum.

    ``K_part`` are the parts of the model's stiffness (:func:`~rotordyn_modal.assembly.stiffness_parts`;
    the real part of ``phi^H K phi`` is that of the symmetric part of K, so cross-coupled bearings
    count with their symmetric part). The mounts' Maxwell branches add the energy of their springs:
    a branch of stiffness ``K_b`` and time ``tau`` stretched by the mode ``exp(lambda t)`` stores
    ``1/2 |lambda tau / (1 + lambda tau)|^2 phi^H K_b phi``.

    Parameters
    ----------
    model : Model
    speed : float
        Reference speed [rad/s] (speed-dependent bearings).
    shapes : ndarray, shape (n_roots, n), complex
    eigenvalues : ndarray, shape (n_roots,), complex [1/s]

    Returns
    -------
    parts : tuple of str
        Those of ``'shaft'``, ``'bearings'``, ``'mounts'``, ``'pedestals'``, ``'meshes'`` the
        model has.
    fractions : ndarray, shape (n_roots, n_parts)
        Rows summing to 1 (nan where the shape strains nothing: rigid-body zero roots).
    """
    from ..assembly import stiffness_parts
    from ..elements.mounts import maxwell_branches

    stiffness = stiffness_parts(model, speed)
    energies = {part: _energies(shapes, K) for part, K in stiffness.items()}
    bounds = {part: _energy_bounds(shapes, K) for part, K in stiffness.items()}
    branches, times = maxwell_branches(model)
    if len(times):
        with np.errstate(divide="ignore", invalid="ignore"):
            stretch = np.abs(eigenvalues[:, None] * times / (1.0 + eigenvalues[:, None] * times)) ** 2
        # lambda = -1 / tau: a branch relaxing alone, the machine at rest (its shape is zero)
        stretch = np.where(np.isfinite(stretch), stretch, 0.0)
        energies["mounts"] = energies["mounts"] + np.einsum(
            "mb,mb->m", stretch, np.stack([_energies(shapes, K) for K in branches], axis=1))
        bounds["mounts"] = bounds["mounts"] + np.einsum(
            "mb,mb->m", stretch, np.stack([_energy_bounds(shapes, K) for K in branches], axis=1))
    if not energies:
        return (), np.zeros((len(eigenvalues), 0))
    table = np.stack(list(energies.values()), axis=1)
    # a part's energy within the round-off of its product is none (a rigid-body mode's energy in
    # a stiff shaft came out as -2e-5 of the whole, and a shaft of 1000 m across balanced its
    # bearings' energy to a total of round-off: nan)
    table = np.where(np.abs(table) <= ENERGY_ROUND_OFF * np.finfo(float).eps
                     * np.stack(list(bounds.values()), axis=1), 0.0, table)
    total = table.sum(axis=1)
    strained = total > 1e-12 * np.abs(table).sum(axis=1)       # not a shape of zeros
    with np.errstate(divide="ignore", invalid="ignore"):
        fractions = np.where(strained[:, None], table / np.where(strained, total, 1.0)[:, None], np.nan)
    return tuple(energies), fractions


def _energies(shapes, K):
    """``1/2 Re(phi^H K phi)`` of each shape, (n_roots,)."""
    return 0.5 * _quadratic(shapes, K)


#: a part's strain energy is none where it is within this many ``eps`` of ``1/2 |phi|^T |K| |phi|``
#: (defined on the model's floor, where ``check``'s count of held modes reads it too)
ENERGY_ROUND_OFF = _ENERGY_ROUND_OFF


def _energy_bounds(shapes, K):
    """``1/2 |phi|^T |K| |phi|`` of each shape, (n_roots,): the scale of the rounding of
    :func:`_energies`."""
    if hasattr(K, "multiply"):                    # scipy.sparse
        K = abs(K)
    else:
        K = np.abs(K)
    return 0.5 * _quadratic(np.abs(shapes).astype(complex), K)


def _quadratic(shapes, A):
    """``Re(phi^H A phi)`` of each shape (m, n) for a real symmetric A (n, n), (m,): one matrix
    product by BLAS (``einsum("mi,ij,mj->m")`` looped in C without it: 8.4 of the 14.7 s of CPU
    of ``modal`` on a flexible shaft of 2,016 states)."""
    return np.einsum("mi,mi->m", _vectors.real_product(shapes.conj(), A), shapes).real


def _unique_indices(index, values, upper):
    """Resolve repeated eigenvalues to distinct LAPACK columns."""
    used: set[int] = set()
    out = []
    for i, lam in zip(index, upper):
        if i in used:
            candidates = np.argsort(np.abs(values - lam))
            i = next(int(c) for c in candidates if int(c) not in used)
        used.add(i)
        out.append(i)
    return out


def _normalise(shapes, M):
    """Unit mass-weighted norm, largest component real and positive."""
    norms = np.sqrt(_quadratic(shapes, M))
    # internal modes of Maxwell branches (a junction relaxing with the stator at rest)
    # have no displacement: keep their shape zero
    norms = np.where(norms > 0, norms, 1.0)
    shapes = shapes / norms[:, None]
    biggest = shapes[np.arange(len(shapes)), np.argmax(np.abs(shapes), axis=1)]
    phase = np.where(np.abs(biggest) > 0, np.abs(biggest) / np.where(biggest != 0, biggest, 1), 1.0)
    return shapes * phase[:, None]


def mac(shapes_a, shapes_b, mass=None) -> np.ndarray:
    """Modal assurance criterion between two sets of mode shapes.

    Parameters
    ----------
    shapes_a : array_like, shape (m, n)
    shapes_b : array_like, shape (p, n)
    mass : array_like, shape (n, n), optional
        Weighting matrix (e.g. the mass matrix, for unit-consistent shapes).

    Returns
    -------
    ndarray, shape (m, p), values in [0, 1]
    """
    a = np.atleast_2d(np.asarray(shapes_a, dtype=complex))
    b = np.atleast_2d(np.asarray(shapes_b, dtype=complex))
    weight = np.eye(a.shape[1]) if mass is None else np.asarray(mass)
    cross = np.abs(a.conj() @ weight @ b.T) ** 2
    norm_a = np.einsum("mi,ij,mj->m", a.conj(), weight, a).real
    norm_b = np.einsum("mi,ij,mj->m", b.conj(), weight, b).real
    return cross / np.outer(norm_a, norm_b)


def _constant_round_off(rows: dict) -> dict:
    """Of a table's round-off ``rows`` (column -> ndarray, one value a row), the columns whose
    round-off is one number for every row, as that number (float). A table's ``attrs`` holds
    these: pandas compares the attrs of the tables it concatenates (arrays of other lengths cannot
    be compared), deep-copies them on every operation, and keeps them on rows it selects or sorts,
    where an array a row would no longer line up (``round_off_rows()`` of the result gives every
    column's, row by row)."""
    return {column: float(values[0]) for column, values in rows.items()
            if len(values) and np.all(values == values[0])}
