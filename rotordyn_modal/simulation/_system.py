"""The model as the plain arrays the right-hand side kernels take."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.geometry import transverse_axes
from .kinematics import transverse_basis

#: frames the rotors sit on, by their number of coordinates
GROUND, CARRIER, STATOR = 0, 5, 6


@dataclass(frozen=True)
class SystemArrays:
    """A model reduced to arrays (bodies: stator first when there is one, then the rotors).

    Generalized coordinates ``q = [frame (nf), each rotor on bearings (k_j), phi]``: the frame
    is the stator (``nf = 6``: ``x, g, psi``), a massless carrier without a stator or bearings
    (``nf = 5``: ``x, g``) or the ground (``nf = 0``); a rotor on bearings has
    ``[u_a, u_b, (u_e), g_a, g_b]`` (``ntrans = 2`` or 3 translations); ``phi`` last.

    Attributes
    ----------
    e : (3,) spin axis; E2 : (3, 2) transverse basis of the frame's Euler vector
    nf : number of frame coordinates (0, 5 or 6)
    gravity : (3,) [m/s^2]
    mass : (nb,) [kg]; center : (nb, 3) axis points from the reference point [m];
    offset : (nb, 3) centre of mass from the axis point at angle 0 [m];
    inertia : (nb, 3, 3) about the centre of mass at angle 0 [kg m^2]; ratio : (nb,)
    slot : (nb,) first coordinate of a body on bearings, -1 for a body fixed to the frame
    ntrans : (nb,) its translational coordinates (2, or 3 with an axial bearing stiffness)
    A3 : (3, 3) columns ``a, b, e``: the axes of the rotors' coordinates
    spos : (ns, 3) [m]; sK, sC : (ns, 6, 6) on ``[u_P, theta]``
    bbody : (nbr,) body each bearing carries; bpos : (nbr, 3) bearing point from the
    body's axis point [m]; bspeeds : (nbr, L) own speeds of the coefficient tables [rad/s]
    (first ``bcount`` used); bcount : (nbr,); bK, bC : (nbr, L, 6, 6) on the relative
    ``[u, theta]`` at the bearing point, frame axes (a journal bearing's axial and moment parts)
    bfilm : (nbr, 4) a journal bearing's radius, length, radial clearance [m] and viscosity
    [Pa s] (zeros: no oil film); baxes : (nbr, 2, 3) rows ``x``, ``y`` of its radial frame
    reference_point : (3,) [m]; rotor_index : (n_rotors,) body index of each rotor
    """

    e: np.ndarray
    E2: np.ndarray
    nf: int
    gravity: np.ndarray
    mass: np.ndarray
    center: np.ndarray
    offset: np.ndarray
    inertia: np.ndarray
    ratio: np.ndarray
    slot: np.ndarray
    ntrans: np.ndarray
    A3: np.ndarray
    spos: np.ndarray
    sK: np.ndarray
    sC: np.ndarray
    bbody: np.ndarray
    bpos: np.ndarray
    bspeeds: np.ndarray
    bcount: np.ndarray
    bK: np.ndarray
    bC: np.ndarray
    bfilm: np.ndarray
    baxes: np.ndarray
    reference_point: np.ndarray
    rotor_index: np.ndarray

    @property
    def s(self) -> int:
        """1 when the frame has a roll coordinate (a stator), else 0."""
        return 1 if self.nf == STATOR else 0

    @property
    def n_dof(self) -> int:
        own = sum(2 + int(k) for k, j in zip(self.ntrans, self.slot) if j >= 0)
        return self.nf + own + 1

    def kernel_arguments(self):
        """Arguments of ``assemble``/``rhs`` after ``(t, y)``."""
        return (self.e, self.E2, self.nf, self.gravity, self.mass, self.center, self.offset,
                self.inertia, self.ratio, self.slot, self.ntrans, self.A3, self.spos, self.sK,
                self.sC, self.bbody, self.bpos, self.bspeeds, self.bcount, self.bK, self.bC, self.bfilm,
                self.baxes)


def refuse_hysteretic(model) -> None:
    """Hysteretic damping ``K (1 + i eta)`` exists in the frequency domain only."""
    lossy = [s for s in model.suspensions if s.loss_factor]
    if lossy:
        names = ", ".join(f"{s.name!r} (loss_factor = {s.loss_factor:g})" for s in lossy)
        raise InputError(
            f"{model.source}: suspensions {names}: a hysteretic loss factor has no meaning in the time "
            "domain; set loss_factor = 0 to simulate, and give the suspension viscous damping instead "
            "(damping = loss_factor * stiffness / omega matches it at one circular frequency omega)")
    branched = [s.name for s in model.suspensions if getattr(s, "maxwell_stiffness_matrix", None) is not None]
    if branched:
        raise InputError(
            f"{model.source}: suspensions {', '.join(map(repr, branched))}: Maxwell branches "
            "(maxwell_stiffness, maxwell_time) are not simulated in time yet; remove them to simulate "
            "with the static stiffness and viscous damping")


def refuse_journal_loads(model) -> None:
    """A journal bearing's static load comes from gravity in the time simulation."""
    given = [b for b in model.bearings if b.coefficients.kind == "journal" and b.load is not None]
    if given:
        names = ", ".join(f"[bearings.{b.name}] load = {b.load:g}" for b in given)
        raise InputError(
            f"{model.source}: {names}: the time simulation loads a journal bearing with the weight it "
            "carries under the model's gravity, not with a given load; leave load out (and set "
            "gravity), or give the bearing as type = 'linear' with its film coefficients (a speeds_rpm "
            "table computed by rotordyn_modal.elements.journal_bearing.short_journal_bearing)")


def unbalance_directions(model, phases_deg=None) -> np.ndarray:
    """Unit vectors of the unbalances at angle 0 (phase from ``e1`` towards ``e2``).

    Returns
    -------
    ndarray, shape (n_unbalances, 3)
    """
    basis = transverse_basis(model.spin_axis)
    phases = np.radians([u.phase_deg for u in model.unbalances] if phases_deg is None else phases_deg)
    return np.cos(phases)[:, None] * basis[:, 0] + np.sin(phases)[:, None] * basis[:, 1]


def frame_size(model) -> int:
    """Number of frame coordinates: 6 with a stator, 0 on the ground (bearings without a
    stator), 5 for the massless carrier of a model with neither."""
    if model.stator is not None:
        return STATOR
    return GROUND if model.bearings else CARRIER


def system_arrays(model, unbalance_phases_deg=None) -> SystemArrays:
    """Reduce ``model`` to :class:`SystemArrays`.

    Parameters
    ----------
    model : Model
    unbalance_phases_deg : array_like, shape (n_unbalances,), optional
        Phases overriding the model's ``phase_deg`` [deg].
    """
    refuse_hysteretic(model)
    refuse_journal_loads(model)
    e = np.asarray(model.spin_axis, dtype=float)
    reference = np.asarray(model.reference_point, dtype=float)
    suspensions = model.suspensions
    start = 1 if model.stator is not None else 0
    return SystemArrays(
        e=e, E2=transverse_basis(e), nf=frame_size(model),
        gravity=np.asarray(model.gravity, dtype=float),
        **_body_arrays(model, reference, unbalance_directions(model, unbalance_phases_deg)),
        A3=np.column_stack([*transverse_axes(e), e]),
        spos=np.array([np.asarray(s.position) - reference for s in suspensions], dtype=float).reshape(-1, 3),
        sK=np.array([s.stiffness_matrix for s in suspensions], dtype=float).reshape(-1, 6, 6),
        sC=np.array([s.damping_matrix for s in suspensions], dtype=float).reshape(-1, 6, 6),
        reference_point=reference,
        rotor_index=np.arange(start, start + len(model.rotors)),
        **_bearing_arrays(model, start),
    )


def _body_arrays(model, reference, directions):
    """The bodies' arrays of :class:`SystemArrays`: the stator (if any), then every rotor.

    ``slot`` is where a rotor on bearings' own coordinates start (-1 for the others),
    ``ntrans`` how many translations it has (3 with an axial bearing stiffness, else 2).
    """
    e = np.asarray(model.spin_axis, dtype=float)
    bodies = []                       # (mass, centre, offset, inertia, ratio, slot, ntrans)
    if model.stator is not None:
        bodies.append((model.stator.mass, np.asarray(model.stator.center_of_mass) - reference, np.zeros(3),
                       np.asarray(model.stator.inertia, dtype=float), 0.0, -1, 2))
    following = frame_size(model)
    for rotor in model.rotors:
        rho, inertia = _unbalanced_rotor(model, rotor, directions, e)
        mine = [b for b in model.bearings if b.rotor == rotor.name]
        axial = any(b.coefficients.axial for b in mine)
        bodies.append((rotor.mass, np.asarray(rotor.center_of_mass) - reference, rho, inertia, rotor.speed_ratio,
                       following if mine else -1, 3 if axial else 2))
        following += (4 + axial) if mine else 0
    masses, centers, offsets, inertias, ratios, slots, ntrans = zip(*bodies) if bodies else [()] * 7
    return dict(mass=np.array(masses, dtype=float), center=np.array(centers, dtype=float).reshape(-1, 3),
                offset=np.array(offsets, dtype=float).reshape(-1, 3),
                inertia=np.array(inertias, dtype=float).reshape(-1, 3, 3),
                ratio=np.array(ratios, dtype=float),
                slot=np.array(slots, dtype=np.int64), ntrans=np.array(ntrans, dtype=np.int64))


def _unbalanced_rotor(model, rotor, directions, e):
    """A rotor with its unbalances as masses turning with it.

    Returns
    -------
    rho : ndarray, shape (3,)
        Its centre of mass from its axis at angle 0, ``sum U_k d_k / m`` [m].
    inertia : ndarray, shape (3, 3)
        Its inertia about that centre of mass at angle 0 (couple unbalances add products
        ``-U_k a_k (e d_k^T + d_k e^T)``) [kg m^2].
    """
    first_moment, products = np.zeros(3), np.zeros((3, 3))
    for unbalance, d in zip(model.unbalances, directions):
        if unbalance.rotor == rotor.name:
            first_moment += unbalance.amount * d
            products -= unbalance.amount * unbalance.axial_offset * (np.outer(e, d) + np.outer(d, e))
    rho = first_moment / rotor.mass
    about_axis = rotor.diametral_inertia * np.eye(3) \
        + (rotor.polar_inertia - rotor.diametral_inertia) * np.outer(e, e) + products
    return rho, about_axis - rotor.mass * (rho @ rho * np.eye(3) - np.outer(rho, rho))


def _bearing_arrays(model, start):
    """The bearings' arrays of :class:`SystemArrays` (coefficient tables padded to one length)."""
    bearings = model.bearings
    names = [r.name for r in model.rotors]
    length = max([1] + [len(b.coefficients.stiffness) for b in bearings])
    speeds = np.zeros((len(bearings), length))
    stiffness = np.zeros((len(bearings), length, 6, 6))
    damping = np.zeros((len(bearings), length, 6, 6))
    count = np.ones(len(bearings), dtype=np.int64)
    for i, bearing in enumerate(bearings):
        c = bearing.coefficients
        rows = len(c.stiffness)
        count[i] = rows
        stiffness[i, :rows], damping[i, :rows] = c.stiffness, c.damping
        if c.speeds is not None:
            speeds[i, :rows] = c.speeds
    body = [start + names.index(b.rotor) for b in bearings]
    position = [np.asarray(b.position, dtype=float) - np.asarray(model.rotor(b.rotor).center_of_mass, dtype=float)
                for b in bearings]
    film, axes = np.zeros((len(bearings), 4)), np.zeros((len(bearings), 2, 3))
    for i, bearing in enumerate(bearings):
        journal = bearing.coefficients.journal
        if journal is not None:
            film[i] = 0.5 * journal.diameter, journal.length, journal.clearance, journal.viscosity
            axes[i] = journal.axes[:2]
    return dict(bbody=np.array(body, dtype=np.int64), bpos=np.array(position, dtype=float).reshape(-1, 3),
                bspeeds=speeds, bcount=count, bK=stiffness, bC=damping, bfilm=film, baxes=axes)


def check_table_speeds(model, reference_speeds, what: str) -> None:
    """Refuse a rotor's own speed outside its bearing's coefficient table.

    Parameters
    ----------
    model : Model
    reference_speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s]; each rotor's own speed is its speed ratio times them.
    what : str
        Where the speeds come from, for the message (``"the run-up from 0 to 300 rad/s"``).
    """
    from ..elements.bearings import evaluate

    speeds = np.atleast_1d(np.asarray(reference_speeds, dtype=float))
    for bearing in model.bearings:
        if bearing.coefficients.kind != "table":
            continue
        try:
            evaluate(bearing.coefficients, model.rotor(bearing.rotor).speed_ratio * speeds,
                     f"{model.source}: [bearings.{bearing.name}]")
        except InputError as error:
            raise InputError(f"{error}; in {what}") from None


def progress_bar(total, progress):
    """A tqdm bar over ``total`` simulated seconds, or None when not asked for."""
    if not progress:
        return None
    from .._progress import tqdm

    return tqdm(total=float(total), unit="s", desc="simulate", bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s")


#: DOP853's return code when its stiffness test stopped it (Hairer's ``IDID = -4``)
STIFF_STOP = -4


def integrate_to(solver, t, stiffness_test=False):
    """``solver.integrate(t)`` for scipy's DOP853 ``solver`` (``scipy.integrate.ode``), going on
    past Hairer's stiffness test unless ``stiffness_test``; returns the state at ``t`` (or where
    the solver stopped otherwise: ``solver.successful()`` says which).

    DOP853 checks every 1,000 accepted steps of a call whether its steps stay at the edge of their
    stability region and, after 15 such checks in a row, stops with code -4 ("the problem seems to
    become stiff"): a heuristic along a fast mode (the stiff casing of
    tests/test_simulate_stiff27s.py, 13.7 MHz), not a failure; ``solve_ivp``'s DOP853 (the rigid
    model's numpy backend) has no such test. Where it stops, the state returned is the one at the
    start of the step it checked (accepted steps only: scipy's ``src/dop.c`` returns before moving
    ``x`` and ``y``), so the run goes on from there by scipy's public ``set_initial_value``: a
    fresh start, as ``ode`` makes at every output time, its first step guessed again. Each stop
    comes after at least 1,000 steps of progress. The CPU limit of the run, not this test, bounds
    the work. With ``stiffness_test`` (journal bearings) code -4 is left to the caller: there it
    is a journal running into its wall, the film stiffening without limit.
    """
    y = solver.integrate(t)
    while not stiffness_test and solver.get_return_code() == STIFF_STOP and solver.t != t:
        solver.set_initial_value(np.array(solver.y, copy=True), solver.t)
        y = solver.integrate(t)
    return y


#: DOP853's failure codes (Hairer's ``IDID``), in words
_DOP853_CAUSES = {
    -1: "its input was inconsistent",
    -2: "it reached its limit of steps",
    -3: "its step fell below the float resolution of t (10 x 2.3e-16 x t, 'step size too small'): "
        "the motion grew faster than the integrator can follow (an unstable machine, a force without "
        "bound, or too tight --rtol/--atol for this --duration)",
    STIFF_STOP: "its stiffness test stopped it (the equations stiffened beyond an explicit integrator)",
}


class IntegrationFailed(InputError):
    """DOP853 stopped short of the end: one line naming the time and the cause (the command line's
    exit code 2; the remedy is another duration, tolerance or model). ``time`` [s], ``state`` the
    state where it stopped."""

    def __init__(self, message, time=None, state=None):
        super().__init__(message)
        self.time, self.state = time, state


def integration_failure(code, time, finite=True) -> str:
    """The line of a DOP853 run that stopped at ``time`` [s] with return ``code`` (``finite`` False:
    the state it returned was not finite)."""
    cause = ("the state became infinite or NaN (the motion grew without bound: an unstable machine or a force "
             "without bound)") if not finite else _DOP853_CAUSES.get(code, f"it failed (code {code})")
    return f"the integration stopped at t = {time:.6g} s (DOP853 code {code}): {cause}"


def check_duration(duration, rate, advice: str = ""):
    """Refuse a duration of more periods of the fastest motion (``rate`` [rad/s]) than the count
    limit: the integrator's steps grow with them, so such a run would not end in any useful time.
    ``advice``: words after the fastest motion's frequency (what the caller can change)."""
    from .._limits import count_problem

    periods = duration * rate / (2 * np.pi)
    problem = count_problem(int(min(periods, 1e18)), "periods of the fastest motion")
    if problem:
        raise InputError(f"duration = {duration!r} s: expected {problem} "
                         f"(the fastest motion is {rate / (2 * np.pi):.4g} Hz{advice})")


#: the end time's float resolution (``duration`` times the machine epsilon, 2.2e-16) must stay below
#: this share of the fastest motion's period: DOP853 stops (code -3, "step size too small") where its
#: step falls below 10 x 2.3e-16 x t (Hairer's ``UROUND``), and started afresh at each output time it
#: guesses a first step of about 0.01 / omega (compressor_rotor at rest, fastest motion 8,494 rad/s,
#: stopped at t = 4.55e8 s, where the resolution was 1.4e-4 of the period): 1e-6 leaves a margin of 100
RESOLUTION_SHARE = 1e-6


def check_resolution(duration, rate, samples=None):
    """Refuse, before any work, a ``duration`` [s] whose end time's float resolution
    (``duration * eps``) is not well below (:data:`RESOLUTION_SHARE`) the period of the fastest
    motion ``rate`` [rad/s] that the integrator's steps follow, or ``samples`` output times whose
    step is not: DOP853 could not take its steps there (``--allow-long`` does not lift this).
    The message names the largest duration (or count of output times) that passes."""
    eps = np.finfo(float).eps
    if samples is not None and samples - 1 > RESOLUTION_SHARE / eps:
        raise InputError(f"samples = {samples!r}: expected at most {int(RESOLUTION_SHARE / eps) + 1:,}: the output "
                         "step would not be well above the end time's float resolution (duration x 2.2e-16)")
    if not rate > 0 or not np.isfinite(rate):
        return
    period = 2 * np.pi / rate
    if duration * eps <= RESOLUTION_SHARE * period:
        return
    largest = _rounded_down(RESOLUTION_SHARE * period / eps)
    raise InputError(f"duration = {duration!r} s: expected at most {largest:.3g} s: at t = {duration:.3g} s a float "
                     f"resolves only {duration * eps:.2g} s (duration x 2.2e-16), not well below (at most "
                     f"{RESOLUTION_SHARE:g} of) the period of the fastest motion ({rate / (2 * np.pi):.4g} Hz, "
                     f"{period:.3g} s) that the integrator's steps follow: DOP853 stops where its step falls below "
                     "10 x 2.3e-16 x t ('step size too small'); --allow-long does not lift this")


def _rounded_down(value):
    """``value`` > 0 rounded down to 3 significant digits (so that it passes the check it states)."""
    shown = float(f"{value:.3g}")
    if shown > value:
        shown -= 10.0 ** (np.floor(np.log10(shown)) - 2)
    return float(f"{shown:.3g}")


def default_samples(rate, duration):
    """Output times: 20 per period of the fastest motion ``rate`` [rad/s], at least 201."""
    return int(min(max(201, 20.0 * rate / (2 * np.pi) * duration + 1), 2_000_001))


#: the line printed on stderr before numba compiles the kernels (first run only)
COMPILE_NOTICE = "compiling the simulation kernel (first run only, ~20 s)..."


def announce_compilation(kn) -> bool:
    """Print :data:`COMPILE_NOTICE` on stderr when the compiled right-hand side is about to be
    compiled: not yet compiled in this process and not in numba's on-disk cache.

    Returns
    -------
    bool
        Whether the notice was printed.
    """
    import sys

    dispatcher = getattr(kn, "rhs_flat", None)
    if dispatcher is None or getattr(dispatcher, "signatures", None) != []:
        return False                                  # plain numpy, or compiled already
    if _cached(dispatcher):
        return False
    print(COMPILE_NOTICE, file=sys.stderr, flush=True)
    return True


def _cached(dispatcher) -> bool:
    """Whether numba's cache holds a compiled version of ``dispatcher`` for its current source
    (numba's own index, stale stamps dropped; any failure to read it counts as not cached)."""
    try:
        return bool(dispatcher._cache._cache_file._load_index())
    except Exception:       # a private numba interface: a change of it only costs the notice
        return False
