"""The time model of a machine with flexible rotors: the linear model integrated in time.

A machine with a flexible rotor, bearing pedestals or gear mesh stiffness (:func:`linear_only`)
is integrated as its linear model (docs/theory.md §19, docs/simulate.md "Flexible rotors"): the
reference rotor's angle ``phi(t)`` is prescribed (constant speed or a linear ramp), and every
other coordinate -- the flexible rotors' node motions, the rigid rotors' motions in their
bearings, the pedestals' lateral motions and the casing's six motions -- is a small
motion about the spinning, undeformed machine::

    M q'' + (C(w) + w G) q' + K(w) q = f_u(t) + f_g,      w = phi'(t)

with the matrices of the linearized model (``rotordyn_modal.assembly``: shaft elements,
disks, bearings at each rotor's own speed, mounts), the unbalances as rotating forces
``U (theta'^2 [cos theta, sin theta] - theta'' [-sin theta, cos theta])`` at their points (the
reaction of the eccentric mass's acceleration: it lags on a run-up)
(``theta = r_j phi + phase``) and the weights ``f_g = M a_g`` (gravity as a uniform
acceleration ``a_g`` of every body). ``q = V eta`` on a speed-independent basis: the undamped
modes at the start speed below a cutoff (at least the lowest :data:`LOWEST`; under a sudden load
also the modes it reaches at the sensors, :func:`reached_modes`) plus the static
deflections under the unbalances', weights' and impulse's forces that those modes leave out
(modal truncation augmentation), made M-orthonormal by a Rayleigh-Ritz step. With every mode
kept the reduction is exact. Plain journal bearings are left out of the matrices and push their
journals with the oil film's nonlinear force (:mod:`rotordyn_modal.simulation.flexible_journal`);
the basis then also holds the static deflections under forces at the journals.
"""

from __future__ import annotations

import logging
import re
import sys
from types import SimpleNamespace
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._jit import compile_together, numba_or_none
from ._system import IntegrationFailed, announce_compilation
from .flexible_journal import film_load

__all__ = ["simulate_linear", "reduced_system", "ReducedSystem", "NOTICE", "LINEAR_ONLY_NOTICE", "linear_only", "LOWEST",
           "CUTOFF_FACTOR", "reached_modes", "Reach", "REACHED_SHARE", "WARNED_SHARE", "POINTS_PER_PERIOD"]

#: printed once per process on stderr when a machine with a flexible rotor is simulated
NOTICE = ("simulate: the model has a flexible rotor: the machine is integrated as its linear model (small "
          "motions about the spinning undeformed machine, the casing's motions linear too; the drive's angle "
          "prescribed; docs/simulate.md, 'Flexible rotors')")
#: the same line for a machine of rigid rotors with bearing pedestals or gear mesh stiffness,
#: ``{what}`` naming them
LINEAR_ONLY_NOTICE = ("simulate: the model has {what}, which the nonlinear large-rotation model cannot carry: the "
                      "machine is integrated as its linear model (small motions about the spinning machine, the "
                      "casing's motions linear too; the drive's angle prescribed; docs/simulate.md, "
                      "'Flexible rotors')")
#: the basis keeps at least this many of the lowest modes (all when the model has fewer)
LOWEST = 6
#: by default the basis keeps the modes below this multiple of the fastest spin frequency
CUTOFF_FACTOR = 4.0
#: under a sudden load the default basis keeps, and the default output times resolve, every mode
#: whose response at a sensor is more than this share of the load's largest modal response at the
#: sensors (:func:`reached_modes`)
REACHED_SHARE = 1e-3
#: ``samples`` given (or the default's cap) that leave a mode carrying more than this share
#: unresolved (under :data:`POINTS_PER_PERIOD` output times a period) get one warning line
WARNED_SHARE = 1e-2
#: output times per period of the fastest mode a sudden load reaches, by default
POINTS_PER_PERIOD = 10
#: default output times raised past this multiple of the spin's default are said on stderr
#: always (else on the log: ``--verbose``)
ANNOUNCED_GROWTH = 10
#: a mode whose squared frequency is at most this share of the largest is a rigid-body mode:
#: kept always, outside the shares (its response to a load does not stay bounded)
_RIGID_SHARE = 1e-12
_LOG = logging.getLogger("rotordyn_modal.simulation")
_NOTICED: list = []


def linear_only(model) -> str:
    """What makes ``model`` a case for the linear time model, in words ('' when nothing does):
    a flexible rotor, bearing pedestals, gear mesh stiffness (the nonlinear large-rotation model
    has rigid rotors in bearings fixed in the casing and rigid gears)."""
    if any(r.flexible is not None for r in model.rotors):
        return "a flexible rotor"
    parts = []
    pedestals = [b.name for b in model.bearings if b.pedestal is not None]
    if pedestals:
        parts.append("bearing pedestals (" + ", ".join(f"[bearings.{name}]" for name in pedestals) + ")")
    meshes = [t.label for t in model.transmissions if t.mesh_stiffness is not None or t.mesh_damping is not None]
    if meshes:
        parts.append("gear mesh stiffness (" + ", ".join(f"[transmissions.{label}]" for label in meshes) + ")")
    return " and ".join(parts)


def notice_once(what: str = "a flexible rotor") -> bool:
    """Print :data:`NOTICE` (or :data:`LINEAR_ONLY_NOTICE` naming ``what``) on stderr, the first
    time only for each text. Returns whether it printed."""
    line = NOTICE if what == "a flexible rotor" else LINEAR_ONLY_NOTICE.format(what=what)
    if line in _NOTICED:
        return False
    _NOTICED.append(line)
    print(line, file=sys.stderr, flush=True)
    return True


def refuse(model, drive: str) -> None:
    """What the linear time model does not simulate, refused by one line (a journal bearing's
    given static load too: its load is the weight it carries under gravity, as in the
    large-rotation model)."""
    from ._system import refuse_hysteretic, refuse_journal_loads

    what = "a machine with " + re.sub(r" \([^)]*\)", "", linear_only(model) or "a flexible rotor")
    refuse_journal_loads(model)
    if drive == "free":
        raise InputError(f"{model.source}: drive 'free': {what} is simulated with its "
                         "drive's angle prescribed (drive 'constant' or 'ramp'), not in free spin")
    refuse_hysteretic(model)


@dataclass(frozen=True)
class ReducedSystem:
    """The linear time model on the basis ``q = V eta`` (``V^T M V = I``).

    Attributes
    ----------
    V : ndarray, shape (n, r)
        Basis: generalized coordinates per reduced coordinate.
    frequencies : ndarray, shape (r,) [rad/s]
        The basis vectors' (Ritz) undamped frequencies at the start speed.
    modes : int
        How many of them are modes of the full model (the first ``modes``); the rest are
        static corrections.
    K, C, G : ndarray, shape (r, r)
        Reduced stiffness and damping without the speed-dependent bearings, gyroscopic matrix
        per unit reference speed.
    dependent : tuple of (float, coefficients, str, ndarray (6, r))
        Each speed-dependent bearing: its rotor's speed ratio, coefficients, name for messages
        and relative motion at its point per reduced coordinate.
    ratio, phase, amount : ndarray, shape (U,)
        Each unbalance's rotor speed ratio, phase [rad] and amount [kg m].
    Fa, Fb : ndarray, shape (U, r)
        Reduced generalized force of a unit force along the phase reference ``a`` (``b``) at
        each unbalance's point.
    gravity : ndarray, shape (r,)
        Reduced weights.
    reaction : ndarray, shape (r,)
        Reduced reaction on the casing of the torque that accelerates the rotors' spins, per unit
        angular acceleration of the drive [N m / (rad/s^2)] (zeros on the ground).
    films : Films or None
        The journal bearings' oil films, nonlinear forces on the reduced coordinates
        (:mod:`rotordyn_modal.simulation.flexible_journal`); ``K`` and ``C`` hold only their
        constant (axial and moment) parts.
    """

    V: np.ndarray
    frequencies: np.ndarray
    modes: int
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    dependent: tuple
    ratio: np.ndarray
    phase: np.ndarray
    amount: np.ndarray
    Fa: np.ndarray
    Fb: np.ndarray
    gravity: np.ndarray
    reaction: np.ndarray
    films: object = None

    @property
    def size(self) -> int:
        return self.V.shape[1]

    def stiffness_damping(self, speeds):
        """Reduced ``K`` and ``C`` at reference speeds ``speeds`` (N,) [rad/s], shape (N, r, r) each."""
        from ..elements.bearings import evaluate

        speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
        K = np.broadcast_to(self.K, (len(speeds),) + self.K.shape).copy()
        C = np.broadcast_to(self.C, K.shape).copy()
        for ratio, coefficients, where, moves in self.dependent:
            k6, c6 = evaluate(coefficients, ratio * speeds, where)
            K += moves.T @ k6 @ moves
            C += moves.T @ c6 @ moves
        return K, C


def unbalance_loads(model, phases_deg=None):
    """Each unbalance's generalized force of a unit force along ``a`` and along ``b`` (the phase
    reference) at its point, with its rotor's speed ratio, phase [rad] and amount [kg m].

    A rigid rotor's unbalance acts at its centre of mass with the moment of its axial offset;
    a flexible rotor's at its node (as :func:`rotordyn_modal.analysis.unbalance.unbalance_response`).

    Returns
    -------
    ratio, phase, amount : ndarray, shape (U,)
    Fa, Fb : ndarray, shape (U, n)
    """
    from ..analysis.unbalance import phase_reference
    from ..assembly import generalized_force

    a, b = phase_reference(model.spin_axis)
    e = np.asarray(model.spin_axis, dtype=float)
    phases = [u.phase_deg for u in model.unbalances] if phases_deg is None else list(phases_deg)
    n = model.dofs.n
    Fa, Fb = np.zeros((len(model.unbalances), n)), np.zeros((len(model.unbalances), n))
    for k, u in enumerate(model.unbalances):
        rotor = model.rotor(u.rotor)
        centre = np.asarray(rotor.center_of_mass, dtype=float)
        for out, d in ((Fa, a), (Fb, b)):
            if rotor.flexible is not None:
                point = centre + u.axial_offset * e
                out[k] = generalized_force(model, u.rotor, point, np.r_[d, 0.0, 0.0, 0.0],
                                           motion=model.dofs.body_motion(u.rotor, point))
            else:
                out[k] = generalized_force(model, u.rotor, centre, np.r_[d, np.cross(u.axial_offset * e, d)])
    return (np.array([model.rotor(u.rotor).speed_ratio for u in model.unbalances], dtype=float),
            np.radians(np.asarray(phases, dtype=float)).reshape(-1),
            np.array([u.amount for u in model.unbalances], dtype=float), Fa, Fb)


def drive_reaction(model) -> np.ndarray:
    """Generalized force (n,) on the casing per unit angular acceleration of the drive: the
    reaction of the torque that spins the rotors up, a moment ``-sum_j r_j J_p,j e`` [N m s^2]
    (the rotors' angular momentum about ``e`` changes at ``alpha sum_j r_j J_p,j``; drives and
    transmissions sit in the casing). Zeros when the bearings stand on the ground."""
    from ..assembly import generalized_force

    if not model.dofs.n_frame:
        return np.zeros(model.dofs.n)
    momentum = sum(r.speed_ratio * r.polar_inertia for r in model.rotors)
    e = np.asarray(model.spin_axis, dtype=float)
    return generalized_force(model, None, model.reference_point, np.r_[0.0, 0.0, 0.0, -momentum * e])


def gravity_acceleration(model) -> np.ndarray:
    """``a_g``: the generalized coordinates of every body translated by the gravity vector
    (the frame's translation, or each rotor's relative translation on the ground), (n,) [m/s^2].

    A bearing's pedestal moves with the frame, plus its own two lateral coordinates: with a
    frame it is translated with it (its coordinates stay 0); on the ground its coordinates take
    the gravity vector's lateral components ``(g.a, g.b)`` (along the spin axis it stands on the
    ground, which carries that component of its weight). ``M a_g`` is then every mass's weight,
    the pedestals' ``m_p g`` included."""
    from ..model.geometry import transverse_axes

    layout = model.dofs
    g = np.asarray(model.gravity, dtype=float)
    out = np.zeros(layout.n)
    if layout.n_frame:
        out[:3] = g
        return out
    a, b = transverse_axes(model.spin_axis)
    along = (g @ a, g @ b, g @ np.asarray(model.spin_axis, dtype=float))
    for name, rows, basis in zip(layout.rotors, layout.slices, layout.bases):
        width = rows.stop - rows.start
        if layout.shaft(name) is not None:
            own = np.zeros(width)
            own[0:4 * (width // 4):4], own[1:4 * (width // 4):4] = along[0], along[1]
            if width % 4:
                own[-1] = along[2]
        else:
            own = basis.T @ np.r_[g, 0.0, 0.0, 0.0]
        out[rows] = own
    for _, rows in layout.pedestals:
        out[rows] = along[:2]
    return out


def reduced_system(model, speed: float, cutoff: float, extra_loads=(), phases_deg=None) -> ReducedSystem:
    """The machine's linear model on a basis of its modes below ``cutoff`` plus static corrections.

    Parameters
    ----------
    model : Model
    speed : float
        Reference speed [rad/s] at which speed-dependent bearings' stiffness sets the modes.
    cutoff : float
        Keep the undamped modes (symmetric stiffness, no gyroscopic or damping terms) below this
        [rad/s], at least the :data:`LOWEST` lowest; ``inf`` keeps all (exact).
    extra_loads : sequence of ndarray (n,)
        Further generalized forces whose static deflection the basis must hold (an impulse's).
    phases_deg : array_like, optional
        Unbalance phases overriding the model's [deg].

    Returns
    -------
    ReducedSystem
        Journal bearings (``type = 'journal'``) are left out of the matrices but for their
        constant parts; their films are ``films``, and the basis holds the static deflections
        under unit forces at the journals (:func:`flexible_journal.attachment_loads`).
    """
    from ..assembly import bearing_motion
    from . import flexible_journal

    M, C, G, K, K_start, dependent = _start_matrices(model, speed)
    if flexible_journal.journal_bearings(model):
        extra_loads = (*extra_loads, *flexible_journal.attachment_loads(model))
    ratio, phase, amount, Fa, Fb = unbalance_loads(model, phases_deg)
    gravity = M @ gravity_acceleration(model) if np.any(model.gravity) else np.zeros(len(M))
    reaction = drive_reaction(model)
    loads = np.column_stack([*Fa, *Fb, gravity, reaction, *extra_loads]) if len(M) else np.zeros((0, 0))
    V, frequencies, modes = _basis(0.5 * (M + M.T), 0.5 * (K_start + K_start.T), loads, cutoff)
    moves = []
    for bearing in dependent:
        rows, local = bearing_motion(model, bearing)
        moves.append((model.rotor(bearing.rotor).speed_ratio, bearing.coefficients,
                      f"{model.source}: [bearings.{bearing.name}]", local @ V[rows]))
    return ReducedSystem(V=V, frequencies=frequencies, modes=modes, K=V.T @ K @ V, C=V.T @ C @ V,
                         G=V.T @ G @ V, dependent=tuple(moves), ratio=ratio, phase=phase, amount=amount,
                         Fa=Fa @ V, Fb=Fb @ V, gravity=gravity @ V, reaction=reaction @ V,
                         films=flexible_journal.films(model, V))


def _start_matrices(model, speed):
    """The linear time model's ``M, C, G, K`` without the speed-dependent bearings (with only the
    constant parts of journal bearings), ``K_start`` with those bearings at reference speed
    ``speed`` [rad/s] (the stiffness whose undamped modes make the basis), and the list of the
    speed-dependent bearings."""
    from ..assembly import constant_matrices
    from . import flexible_journal

    M, C, G, K = constant_matrices(model)
    dependent = [b for b in model.bearings if b.coefficients.kind not in ("constant", "journal")]
    if flexible_journal.journal_bearings(model):
        k_j, c_j = flexible_journal.constant_parts(model)
        K, C = K + k_j, C + c_j
    K_start = K.copy()
    if dependent:
        K_start += _bearings_stiffness(model, dependent, speed)
    return M, C, G, K, K_start, dependent


def _bearings_stiffness(model, bearings, speed) -> np.ndarray:
    """Stiffness (n, n) of ``bearings`` at reference speed ``speed`` [rad/s]."""
    from ..assembly import bearing_coefficients, bearing_motion

    n = model.dofs.n
    K = np.zeros((n, n))
    for bearing in bearings:
        rows, local = bearing_motion(model, bearing)
        K[rows, rows] += local.T @ bearing_coefficients(model, bearing, [speed])[0][0] @ local
    return K


def _basis(M, K, loads, cutoff):
    """M-orthonormal basis: the modes of ``(K, M)`` below ``cutoff`` [rad/s] (at least
    :data:`LOWEST`), then the static deflections under ``loads`` (n, L) in the other modes,
    Rayleigh-Ritz orthonormalised. Returns ``V`` (n, r), its frequencies (r,), the mode count."""
    import scipy.linalg

    values, vectors = scipy.linalg.eigh(K, M)
    n = len(values)
    keep = max(int(np.sum(values < cutoff ** 2)) if np.isfinite(cutoff) else n, min(LOWEST, n))
    frequencies = np.sqrt(np.abs(values[:keep]))
    kept, rest, rest_values = vectors[:, :keep], vectors[:, keep:], values[keep:]
    if not rest.shape[1] or not loads.size:
        return kept, frequencies, keep
    # static deflection in the left-out modes: sum_k phi_k phi_k^T F / lambda_k (their
    # stiffness is positive: the rigid-body modes, if any, are among the lowest kept)
    corrections = rest @ ((rest.T @ loads) / rest_values[:, None])
    gram = corrections.T @ M @ corrections
    scale = np.abs(np.diag(gram)).max(initial=0.0)
    if scale == 0.0:
        return kept, frequencies, keep
    g_values, g_vectors = np.linalg.eigh(gram)
    independent = g_values > 1e-10 * scale
    Q = corrections @ (g_vectors[:, independent] / np.sqrt(g_values[independent]))   # M-orthonormal
    ritz, R = np.linalg.eigh(Q.T @ K @ Q)
    return (np.hstack([kept, Q @ R]), np.concatenate([frequencies, np.sqrt(np.abs(ritz))]), keep)


@dataclass(frozen=True)
class Reach:
    """How much of each sudden load's response at the sensors each undamped mode carries.

    Attributes
    ----------
    frequencies : ndarray, shape (m,) [rad/s]
        The undamped modes of the basis's pencil at the start speed (:func:`reduced_system`),
        ascending; mode ``j + 1`` is ``frequencies[j]``.
    shares : ndarray, shape (m,)
        Each mode's largest response at a sensor over the largest of every mode at every sensor,
        the largest over the loads (``inf`` for a rigid-body mode); 0 for a mode no load reaches.
    loads, sensors : list of str, length m
        The load and where each mode's share is read, 'at SENSOR' ('' where it is 0).
    """

    frequencies: np.ndarray
    shares: np.ndarray
    loads: list
    sensors: list

    def fastest(self, share) -> float:
        """The highest frequency [rad/s] of the elastic modes carrying more than ``share`` (0 if none)."""
        reached = np.isfinite(self.shares) & (self.shares > share)
        return float(self.frequencies[reached].max(initial=0.0))

    def spin_top(self, cutoff) -> float:
        """The highest frequency [rad/s] of the modes a basis of ``cutoff`` [rad/s] keeps (those
        below it, at least the :data:`LOWEST` lowest)."""
        keep = max(int(np.sum(self.frequencies < cutoff)), min(LOWEST, len(self.frequencies)))
        return float(self.frequencies[:keep].max(initial=0.0))

    def unresolved(self, step, share, below=np.inf):
        """Index of the mode carrying most (more than ``share``) of those below ``below``
        [rad/s] that get under :data:`POINTS_PER_PERIOD` output times of ``step`` [s] a period,
        and how many such modes there are; ``(None, 0)`` when there is none."""
        points = 2 * np.pi / np.maximum(self.frequencies * step, 1e-300)
        short = np.isfinite(self.shares) & (self.shares > share) & (points < POINTS_PER_PERIOD) & \
            (self.frequencies < below)
        if not short.any():
            return None, 0
        return int(np.argmax(np.where(short, self.shares, -1.0))), int(short.sum())


def sudden_loads(model, kick, initial, accel, impulse=None):
    """The sudden loads of a run, each ``(name, generalized force (n,), power)``: the impulse's
    (``power`` 1: the modes' velocity jump ``phi^T J`` rings at ``phi^T J / w``) and, from
    ``initial='rest'`` under ``gravity``, the weights (with a ramp's drive reaction) set on at
    t = 0 (``power`` 2: a step ``F`` rings about ``phi^T F / w^2``). Empty without one
    (:func:`sudden`)."""
    loads = []
    if kick is not None:
        loads.append((f"the impulse at {impulse}" if impulse else "the impulse", kick, 1))
    if initial == "rest" and np.any(model.gravity):
        from ..assembly import constant_matrices

        step = constant_matrices(model)[0] @ gravity_acceleration(model) + accel * drive_reaction(model)
        loads.append(("the weights set on at rest", step, 2))
    return loads


def reached_modes(model, speed, loads) -> Reach:
    """Each undamped mode's share of the sudden ``loads``' response at the model's sensors.

    A load ``L`` rings mode ``j`` (M-normalised shape ``phi_j``, frequency ``w_j``) with the
    amplitude ``|phi_j^T L| / w_j^p`` (``p`` 1 for an impulse, 2 for a step), which a sensor of
    row ``c`` reads as ``|c phi_j|`` times it. A mode's share of a load is the largest of these
    over the sensors, over the largest of every mode at every sensor (without sensors: the modal
    amplitude itself, the motion's M-norm). Damping and the spin are left out (an estimate that
    sets the default basis and output times).

    Parameters
    ----------
    model : Model
    speed : float
        Reference speed [rad/s] of the speed-dependent bearings, as :func:`reduced_system`.
    loads : sequence of (str, ndarray (n,), int)
        ``(name, generalized force [N s or N], power)`` (:func:`sudden_loads`).

    Returns
    -------
    Reach
    """
    import scipy.linalg

    from ..assembly import sensor_rows

    M, _, _, _, K_start, _ = _start_matrices(model, speed)
    values, vectors = scipy.linalg.eigh(0.5 * (K_start + K_start.T), 0.5 * (M + M.T))
    frequencies = np.sqrt(np.abs(values))
    rigid = values <= _RIGID_SHARE * np.abs(values).max(initial=0.0)
    shares = np.where(rigid, np.inf, 0.0)
    names = [s.name for s in model.sensors]
    seen = sensor_rows(model) @ vectors if names else None                # (sensors, modes)
    which, where = [""] * len(values), [""] * len(values)
    for name, load, power in loads:
        amplitude = np.zeros(len(values))
        amplitude[~rigid] = np.abs(vectors[:, ~rigid].T @ load) / frequencies[~rigid] ** power
        at = np.abs(seen) * amplitude if seen is not None else amplitude[None]
        largest = at.max(initial=0.0)
        if not largest > 0:
            continue
        share = at.max(axis=0) / largest
        for j in np.nonzero(~rigid & (share > shares))[0]:
            shares[j], which[j] = share[j], name
            where[j] = f"at {names[int(np.argmax(at[:, j]))]}" if seen is not None else "no sensors: the motion's M-norm"
    return Reach(frequencies=frequencies, shares=shares, loads=which, sensors=where)


def resolving_samples(rate, duration) -> int:
    """Output times over ``duration`` [s] with :data:`POINTS_PER_PERIOD` a period of ``rate``
    [rad/s] (at most 2,000,001, as :func:`._system.default_samples`)."""
    return int(min(np.ceil(POINTS_PER_PERIOD * rate / (2 * np.pi) * duration) + 1, 2_000_001))


def _say(line, loud):
    """``line`` on stderr after 'simulate: ' when ``loud`` (beside a progress bar, not through it),
    else on the log (``--verbose`` shows it)."""
    if not loud:
        _LOG.info(line)
        return
    from tqdm import tqdm

    tqdm.write("simulate: " + line, file=sys.stderr)
    sys.stderr.flush()


def _reached_words(reach, rate) -> str:
    """', undamped mode 9 (5,152 Hz), 35 % of ... (at probe-x)' where ``rate`` [rad/s] is a mode
    the sudden loads reach (``reach``, or None), else ''."""
    if reach is None or not len(reach.frequencies):
        return ""
    j = int(np.argmin(np.abs(reach.frequencies - rate)))
    if not (np.isclose(reach.frequencies[j], rate, rtol=1e-9) and np.isfinite(reach.shares[j]) and reach.shares[j] > 0):
        return ""
    return f", {_mode_words(reach, j)}"


def _mode_words(reach, j) -> str:
    """'undamped mode 9 (8,979 Hz), 35 % of the largest modal response to the impulse at shaker-y
    (at probe-x)' for the message lines."""
    share = 100 * reach.shares[j]
    shown = f"{share:.0f}" if share >= 10 else f"{share:.2g}"
    return (f"undamped mode {j + 1} ({reach.frequencies[j] / (2 * np.pi):,.0f} Hz), {shown} % of the largest modal "
            f"response to {reach.loads[j]} ({reach.sensors[j]})")


def _warn_unresolved(reach, count, duration, below, given):
    """One warning line when ``count`` output times over ``duration`` [s] leave a mode (below
    ``below`` [rad/s], so in the basis) that carries more than :data:`WARNED_SHARE` of a sudden
    load's response with under :data:`POINTS_PER_PERIOD` times a period."""
    import warnings

    step = duration / (count - 1)
    j, many = reach.unresolved(step, WARNED_SHARE, below)
    if j is None:
        return
    points = 2 * np.pi / (reach.frequencies[j] * step)
    needed = resolving_samples(reach.fastest(WARNED_SHARE), duration)
    others = f" (and {many - 1} other mode{'s' if many > 2 else ''})" if many > 1 else ""
    what = f"{count:,} output times (samples)" if given else f"the default output times, capped at {count:,},"
    warnings.warn(f"{what} give {points:.2g} a period of {_mode_words(reach, j)}{others}: under "
                  f"{POINTS_PER_PERIOD} a period draw it coarsely, under 2 fold it onto a slower frequency; "
                  f"{needed:,} output times resolve every mode above {100 * WARNED_SHARE:g} %", stacklevel=3)


def simulate_linear(model, duration, speed, *, drive, final_speed, initial, impulse, impulse_size, samples,
                    rtol, atol, unbalance_phases_deg, modes_below, progress, backend="auto"):
    """:func:`rotordyn_modal.simulation.simulate` of a machine with a flexible rotor (its
    arguments checked by it): the linear time model of the module docstring.

    Parameters
    ----------
    modes_below : float or None
        Cutoff of the basis [rad/s] (None: :data:`CUTOFF_FACTOR` times the fastest spin, at
        least the :data:`LOWEST` lowest modes; under a sudden load, :func:`sudden_loads` -- an
        impulse, or the weights from ``initial='rest'`` --, also every mode carrying over
        :data:`REACHED_SHARE` of a load's largest modal response at a sensor
        (:func:`reached_modes`) and every mode below the output times' Nyquist frequency
        :func:`output_nyquist` (of ``samples``, or of the spin's default output times); ``inf``:
        every mode, the linear model exactly). The default output times are 20 per period of the
        fastest of the spin and the modes kept for the spin (the :data:`LOWEST` lowest at least),
        at least 201, and under a sudden load (``modes_below`` None) :data:`POINTS_PER_PERIOD` per
        period of the fastest mode over :data:`REACHED_SHARE` where that is more (said on the log,
        on stderr past :data:`ANNOUNCED_GROWTH` times). Given ``samples`` under
        :data:`POINTS_PER_PERIOD` a period of a mode in the basis over :data:`WARNED_SHARE` give
        one ``UserWarning`` naming it.

    Returns
    -------
    SimulationResult
        ``states`` holds ``[q, q']`` in the linear model's coordinates ``model.dofs`` (the drive's
        angle is ``drive_angle``); the energies are those of the small motions: kinetic
        ``q'^T M q' / 2``, elastic ``q^T K_s q / 2`` (``K_s`` the symmetric part of the stiffness at
        the speed) and gravity ``-f_g^T q``; ``drive_torque`` is what spins the rotors' polar
        inertias up the ramp, ``accel sum_j r_j^2 J_p,j``.
    """
    from ._system import check_duration, check_resolution, default_samples

    refuse(model, drive)
    accel = 0.0 if drive == "constant" else (final_speed - speed) / duration
    fastest = max(abs(speed), abs(final_speed or 0.0)) * max(abs(r.speed_ratio) for r in model.rotors)
    cutoff = CUTOFF_FACTOR * fastest if modes_below is None else _cutoff(modes_below)
    kick = None
    if impulse is not None:
        kick = _impulse_load(model, impulse, float(impulse_size))
    loads = () if kick is None else (kick,)
    sudden_ones = sudden_loads(model, kick, initial, accel, impulse)
    # what the loads reach: for the default basis and output times, or the given output times' warning
    reach = reached_modes(model, speed, sudden_ones) if sudden_ones and (modes_below is None or samples) else None
    spin_count = None
    if modes_below is None and reach is not None:
        # every mode the output times can show as itself (the spin's default ones, or those given),
        # and every mode the sudden loads reach at the sensors (the margin takes a repeated pair whole)
        spin_count = default_samples(max(fastest, reach.spin_top(cutoff)), duration)
        cutoff = max(cutoff, output_nyquist(samples or spin_count, duration), 1.01 * reach.fastest(REACHED_SHARE))
    system = reduced_system(model, speed, cutoff, loads, unbalance_phases_deg)
    below = system.frequencies[:system.modes]
    rate = max(fastest, below[below < cutoff].max(initial=0.0) if np.isfinite(cutoff) else below.max(initial=0.0))
    check_duration(duration, rate, "" if modes_below is not None else
                   f"{_reached_words(reach, rate)}; --max-frequency HZ keeps only the flexible rotors' modes below HZ")
    check_resolution(duration, max(rate, system.frequencies.max(initial=0.0)), samples)   # every basis motion
    if samples:
        count = samples
    elif spin_count is None:       # the output times resolve the spin and the modes kept for it
        count = default_samples(max(fastest, below.max(initial=0.0)), duration)
    else:
        count = _reaching_count(reach, spin_count, duration)
    if reach is not None and (samples or count == 2_000_001):
        _warn_unresolved(reach, count, duration, cutoff, bool(samples))
    y0 = np.zeros(2 * system.size)
    if initial == "equilibrium" and system.films is not None:
        from .flexible_journal import equilibrium

        y0[:system.size] = equilibrium(system.stiffness_damping([speed])[0][0], system.gravity, system.films, speed,
                                       model.source)
    elif initial == "equilibrium":
        K0 = system.stiffness_damping([speed])[0][0]
        try:
            y0[:system.size] = np.linalg.solve(K0, system.gravity) if np.any(system.gravity) else 0.0
        except np.linalg.LinAlgError:
            raise InputError(f"{model.source}: no static equilibrium under gravity (the stiffness is singular: "
                             "do the suspensions and bearings restrain every direction?); use initial 'rest'") from None
    elif initial != "rest":
        raise InputError(f"initial {initial!r}: expected 'rest' or 'equilibrium'")
    if kick is not None:
        y0[system.size:] = kick @ system.V          # V^T M V = I: the velocity jump M^-1 Q, reduced
    times = np.linspace(0.0, duration, count)
    notice_once(linear_only(model) or "a flexible rotor")    # after every refusal: a refusal is one line
    try:
        states = _integrate(system, speed, accel, y0, times, rtol, atol, progress, backend)
    except IntegrationFailed as error:
        if system.films is None:
            raise IntegrationFailed(f"{model.source}: {error}", error.time, error.state) from None
        from .flexible_journal import failure

        raise failure(model, system.films, error.last, str(error), error.state, error.time) from None
    return _result(model, system, times, states, speed, accel, drive)


def _reaching_count(reach, spin_count, duration) -> int:
    """The default output times under a sudden load: the spin's (``spin_count``: 20 per period of
    the fastest of the spin and the modes kept for it, the :data:`LOWEST` lowest at least), or
    :data:`POINTS_PER_PERIOD` per period of the fastest mode the load reaches
    (:data:`REACHED_SHARE`, ``reach``) where that is more, said in one line: on stderr when past
    :data:`ANNOUNCED_GROWTH` times ``spin_count``, else on the log (``--verbose``)."""
    top = reach.fastest(REACHED_SHARE)
    count = max(spin_count, resolving_samples(top, duration))
    if count > spin_count:
        j = int(np.argmin(np.where(np.isfinite(reach.shares) & (reach.shares > REACHED_SHARE),
                                   np.abs(reach.frequencies - top), np.inf)))
        _say(f"{count:,} output times (not {spin_count:,}): {POINTS_PER_PERIOD} a period of "
             f"{_mode_words(reach, j)} (the default resolves every mode carrying over {100 * REACHED_SHARE:g} % of a "
             "sudden load's response at a sensor; --samples sets them)", count > ANNOUNCED_GROWTH * spin_count)
    return count


def sudden(model, impulse, initial) -> bool:
    """Whether the run starts with a sudden load, whose response holds every mode: an impulse, or
    the weights set on at t = 0 on a machine started undeformed (``initial='rest'`` under
    ``gravity``). The unbalances' forces grow with the spin, so they alone excite little beyond it."""
    return impulse is not None or (initial == "rest" and bool(np.any(model.gravity)))


def output_nyquist(samples, duration) -> float:
    """The Nyquist frequency of ``samples`` output times over ``duration`` [s]: ``pi / step``
    [rad/s]. A motion faster than this folds onto a slower one in the output; one slower shows as
    itself. Under a sudden load (:func:`sudden`) the default basis keeps the modes below it (of the
    given output times, or of the spin's default ones)."""
    return np.pi * (samples - 1) / duration


def _cutoff(value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"modes_below = {value!r}: expected a frequency [rad/s] > 0, or inf") from None
    if not value > 0:
        raise InputError(f"modes_below = {value!r}: expected a frequency [rad/s] > 0, or inf")
    return value


def _impulse_load(model, name, size) -> np.ndarray:
    """Generalized force (n,) of an impulse ``size`` [N s or N m s] through excitation ``name``."""
    from ..assembly import excitation_columns

    return size * excitation_columns(model, [name])[:, 0]


def _integrate(system, speed, accel, y0, times, rtol, atol, progress, backend="auto"):
    """States ``[eta, eta']`` at ``times``: scipy's Fortran DOP853 on the reduced equations
    (:func:`linear_rhs`, or :func:`journal_rhs` with journal bearings, compiled by numba when it
    is installed and no bearing depends on speed, else :func:`_right_hand_side` in numpy: the
    same equations). A failure raises :class:`._system.IntegrationFailed` (one line naming the
    cause) with the state where it stopped as ``.state``."""
    import warnings

    from scipy.integrate import ode

    from ._system import integration_failure, integrate_to, progress_bar

    journals = system.films is not None
    compiled = None if system.dependent or backend == "numpy" else _compiled(backend, journals)
    if compiled is not None:
        announce_compilation(SimpleNamespace(rhs_flat=compiled))
    if compiled is None:
        solver = ode(_right_hand_side(system, speed, accel))
    else:
        films = system.films.arguments() if journals else ()
        arguments = (*_packed(system, speed, accel), *films)
        compiled(times[0], y0, *arguments)      # compiled from Python, not inside the Fortran callback
        solver = ode(compiled).set_f_params(*arguments)
    solver.set_integrator("dop853", rtol=rtol, atol=atol, nsteps=10**9)
    solver.set_initial_value(y0, times[0])
    states = np.empty((len(times), len(y0)))
    states[0] = y0
    bar = progress_bar(times[-1], progress)
    try:
        for i in range(1, len(times)):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                states[i] = integrate_to(solver, times[i], stiffness_test=journals)   # as the rigid model's
            if not solver.successful() or not np.all(np.isfinite(states[i])):
                stopped = np.array(solver.y, copy=True)
                finite = bool(np.all(np.isfinite(stopped)) and np.all(np.isfinite(states[i])))
                failed = IntegrationFailed(integration_failure(solver.get_return_code(), solver.t, finite),
                                           solver.t, stopped if finite else None)
                failed.last = states[i - 1]      # the state at the last output time
                raise failed
            if bar is not None:
                bar.update(times[i] - times[i - 1])
    finally:
        if bar is not None:
            bar.close()
    return states


def _first_order(system):
    """``A``, ``B`` of ``y' = A y + w B y + [0, f]`` on ``y = [eta, eta']``, (2 r, 2 r) each."""
    r = system.size
    A = np.zeros((2 * r, 2 * r))
    A[:r, r:] = np.eye(r)
    A[r:, :r], A[r:, r:] = -system.K, -system.C
    B = np.zeros_like(A)
    B[r:, r:] = -system.G
    return A, B


def _packed(system, speed, accel):
    """The arguments of :func:`linear_rhs` after ``(t, y)``."""
    A, B = _first_order(system)
    return (A, B, np.ascontiguousarray(np.vstack([system.Fa, system.Fb])), system.ratio, system.phase,
            system.amount, system.gravity + accel * system.reaction, float(speed), float(accel))


def linear_rhs(t, y, A, B, loads, ratio, phase, amount, gravity, speed, accel):
    """``y'`` of the reduced equations at time ``t`` [s] (numba-compilable; constant bearings).

    ``loads`` (2 U, r): the unbalances' reduced forces along ``a`` then along ``b``; ``ratio``,
    ``phase`` [rad], ``amount`` [kg m] (U,); ``gravity`` (r,): the constant forces (weights and the
    drive's reaction); ``speed`` [rad/s] and ``accel`` [rad/s^2] of the drive."""
    r = gravity.shape[0]
    w = speed + accel * t
    phi = speed * t + 0.5 * accel * t * t
    out = A @ y + w * (B @ y)
    count = ratio.shape[0]
    for k in range(count):
        theta = ratio[k] * phi + phase[k]
        c, s = np.cos(theta), np.sin(theta)
        rate2, rate_dot = (ratio[k] * w) ** 2, ratio[k] * accel
        along_a = amount[k] * (rate2 * c + rate_dot * s)
        along_b = amount[k] * (rate2 * s - rate_dot * c)
        for i in range(r):
            out[r + i] += along_a * loads[k, i] + along_b * loads[count + k, i]
    for i in range(r):
        out[r + i] += gravity[i]
    return out


def journal_rhs(t, y, A, B, loads, ratio, phase, amount, gravity, speed, accel, fratio, fmoves, faxes, ffilm):
    """``y'`` of the reduced equations with journal bearings (numba-compilable): :func:`linear_rhs`
    plus the films' force :func:`rotordyn_modal.simulation.flexible_journal.film_load`
    (``fratio``, ``fmoves``, ``faxes``, ``ffilm``: the fields of its ``Films``)."""
    out = linear_rhs(t, y, A, B, loads, ratio, phase, amount, gravity, speed, accel)
    r = gravity.shape[0]
    out[r:] += film_load(y[:r], y[r:], speed + accel * t, fratio, fmoves, faxes, ffilm)
    return out


_COMPILED: dict = {}


def _compiled(backend, journals=False):
    """:func:`linear_rhs` (:func:`journal_rhs` with ``journals``) compiled by numba (cached on
    disk), or None without numba ('auto')."""
    if "rhs" not in _COMPILED:
        if numba_or_none() is None:
            _COMPILED["rhs"] = _COMPILED["journal"] = None
        else:
            from .flexible_journal import compiled_film_load

            namespace = compile_together([linear_rhs, journal_rhs], {"np": np, "film_load": compiled_film_load()},
                                         __name__)
            _COMPILED["rhs"], _COMPILED["journal"] = namespace["linear_rhs"], namespace["journal_rhs"]
    if _COMPILED["rhs"] is None and backend == "numba":
        raise InputError("backend 'numba': numba is not installed (pip install 'rotordyn_modal[fast]')")
    return _COMPILED["journal" if journals else "rhs"]


def _right_hand_side(system, speed, accel):
    """``f(t, y)`` of the reduced first-order equations, written for few numpy calls (it runs
    once per stage of every step): ``y' = A y + w(t) B y + [0, f(t)]``."""
    r = system.size
    A, B = _first_order(system)
    loads = np.vstack([system.Fa, system.Fb])                  # (2 U, r)
    ratio, phase, amount = system.ratio, system.phase, system.amount
    gravity = system.gravity + accel * system.reaction
    forcing = np.zeros(2 * r)
    dependent = system.dependent
    films = None if system.films is None else system.films.arguments()

    def rhs(t, y):
        w = speed + accel * t
        theta = ratio * (speed * t + 0.5 * accel * t * t) + phase
        c, s = np.cos(theta), np.sin(theta)
        rate2, rate_dot = (ratio * w) ** 2, ratio * accel
        forcing[r:] = np.concatenate([amount * (rate2 * c + rate_dot * s),
                                      amount * (rate2 * s - rate_dot * c)]) @ loads + gravity
        out = A @ y + w * (B @ y) + forcing
        if dependent:
            K, C = system.stiffness_damping([w])
            out[r:] -= (K[0] - system.K) @ y[:r] + (C[0] - system.C) @ y[r:]
        if films is not None:
            out[r:] += film_load(y[:r], y[r:], w, *films)
        return out

    return rhs


def _result(model, system, times, states, speed, accel, drive):
    """The :class:`SimulationResult` of the reduced states (see its docstring for the fields)."""
    from ..assembly import bearing_coefficients, bearing_motion, sensor_rows
    from ..model.geometry import shift_matrices
    from .result import SimulationResult

    layout = model.dofs
    V, r = system.V, system.size
    eta, deta = states[:, :r], states[:, r:]
    count = len(times)
    spin = speed + accel * times
    phi = speed * times + 0.5 * accel * times ** 2
    e = np.asarray(model.spin_axis, dtype=float)
    if layout.n_frame:
        stator, stator_rate = eta @ V[:6].T, deta @ V[:6].T
    else:
        stator, stator_rate = np.zeros((count, 6)), np.zeros((count, 6))
    roll, roll_rate = stator[:, 3:] @ e, stator_rate[:, 3:] @ e
    ratios = np.array([rotor.speed_ratio for rotor in model.rotors], dtype=float)
    centres = np.array([rotor.center_of_mass for rotor in model.rotors], dtype=float).reshape(-1, 3)
    moves, tilts = np.zeros((count, len(ratios), 3)), np.zeros((count, len(ratios), 3))
    centre_positions = np.empty((count, len(ratios), 3))
    for j, rotor in enumerate(model.rotors):
        motion = layout.motions([(rotor.name, False, tuple(centres[j]))])[0]            # (6, n) at S
        at_centre = shift_matrices(layout.reference_point, [centres[j]])[0].T @ motion
        centre_positions[:, j] = centres[j] + eta @ (at_centre[:3] @ V).T
        if layout.on_bearings(rotor.name):
            rows = layout.slices[layout.rotors.index(rotor.name)]
            local = layout.local_relative_motion(rotor.name, centres[j]) @ V[rows]        # (6, r)
            moves[:, j], tilts[:, j] = eta @ local[:3].T, eta @ local[3:].T
    forces = np.zeros((count, len(model.bearings), 6))
    if system.films is not None:
        from .flexible_journal import wrenches

        journal_forces = wrenches(model, V, system.films, eta, deta, spin)
    for i, bearing in enumerate(model.bearings):
        if bearing.coefficients.kind == "journal":
            forces[:, i] = journal_forces[:, system.films.names.index(bearing.name)]
            continue
        rows, local = bearing_motion(model, bearing)
        reduced = local @ V[rows]
        k6, c6 = bearing_coefficients(model, bearing, spin)
        forces[:, i] = np.einsum("nij,nj->ni", k6, eta @ reduced.T) + np.einsum("nij,nj->ni", c6, deta @ reduced.T)
    Ks = system.stiffness_damping(spin)[0] if system.dependent else system.K[None]
    elastic = 0.5 * np.einsum("ni,nij,nj->n", eta, 0.5 * (Ks + Ks.transpose(0, 2, 1)), eta)
    polar = np.array([rotor.polar_inertia for rotor in model.rotors], dtype=float)
    return SimulationResult(
        time=np.asarray(times), displacement=stator, velocity=stator_rate,
        gamma=stator[:, 3:] - roll[:, None] * e, drive_angle=phi, drive_speed=spin, spin_speed=spin + roll_rate,
        rotor_angles=roll[:, None] + phi[:, None] * ratios, drive_torque=np.full(count, accel * polar @ ratios ** 2),
        rotor_centers=centre_positions, rotor_displacements=moves, rotor_tilts=tilts, bearing_forces=forces,
        sensors=eta @ (sensor_rows(model) @ V).T, kinetic_energy=0.5 * np.einsum("ni,ni->n", deta, deta),
        elastic_energy=elastic, gravity_energy=-eta @ system.gravity, states=np.hstack([eta @ V.T, deta @ V.T]),
        sensor_names=[s.name for s in model.sensors], rotor_names=[rotor.name for rotor in model.rotors],
        bearing_names=[b.name for b in model.bearings], speed_ratios=ratios, drive=drive, model_name=model.name,
        frame=layout.frame)
