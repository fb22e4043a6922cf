"""Nonlinear large-rotation time simulation of a multi-rotor machine: :func:`simulate`."""

from __future__ import annotations

import contextlib

import numpy as np

from .._progress import ONE_CALL_NOTE
from ..errors import InputError, ModelError
from ..linear_system import checked_mass_inverse
from . import _kernels
from ._system import check_table_speeds, system_arrays
from ._system import check_duration as _check_duration, check_resolution as _check_resolution
from ._system import default_samples as _default_samples
from ._system import IntegrationFailed, integration_failure
from ._system import progress_bar as _progress_bar
from ._system import COMPILE_NOTICE, announce_compilation  # noqa: F401  (their old home)
from .flexible import linear_only
from .result import SimulationResult

__all__ = ["simulate", "DRIVES", "BACKENDS", "kernels"]

#: drive modes: ideal drive at constant speed, ideal drive on a linear ramp, free spin
DRIVES = ("constant", "ramp", "free")
#: right-hand side implementations: numba-compiled when available, plain numpy
BACKENDS = ("auto", "numba", "numpy")

_CACHE: dict[str, object] = {}


def kernels(backend: str = "auto"):
    """The right-hand side kernels: ``"numba"`` (compiled), ``"numpy"`` (plain) or ``"auto"``."""
    if backend not in BACKENDS:
        raise InputError(f"backend {backend!r}: expected one of {', '.join(BACKENDS)}")
    if backend in ("auto", "numba"):
        if "numba" not in _CACHE:
            _CACHE["numba"] = _kernels.compiled_namespace()
        if _CACHE["numba"] is not None:
            return _CACHE["numba"]
        if backend == "numba":
            raise InputError("backend 'numba': numba is not installed (pip install 'rotordyn_modal[fast]')")
    return _kernels.plain_namespace()


def simulate(model, duration, speed=0.0, *, drive="constant", final_speed=None, initial="rest",
             impulse=None, impulse_size=1.0, samples=None, rtol=1e-9, atol=1e-12,
             unbalance_phases_deg=None, backend="auto", progress=False, modes_below=None) -> SimulationResult:
    """Integrate the machine's nonlinear equations of motion with large rotations.

    The stator is a rigid body whose rotation is an axial (roll) angle plus a transverse Euler
    vector (Sorokin & Zhang 2018, docs/theory-large-rotations.md); a rotor on ``[[bearings]]`` is a rigid body of its own that translates
    and tilts in its bearings' springs and dampers (its orientation relative to the stator
    again an axial angle plus a transverse Euler vector; the bearings stand on the ground
    without a ``[stator]``); the other rotors turn in bearings fixed in the stator. Every
    rotor's axial angle relative to the stator is its speed ratio times the drive angle;
    gyroscopic coupling, unbalances (rotating masses), gravity and suspension and bearing
    forces that follow their attachment points are exact. At t = 0 the machine is at rest
    (in its undeformed position, or in static equilibrium under gravity) and the rotors spin
    at ``speed``.

    Parameters
    ----------
    model : Model
        A model without hysteretic damping (``loss_factor`` must be 0), Maxwell branches or
        journal bearings; tabulated bearing coefficients are followed at each rotor's own
        speed (the simulated speeds must stay inside the tables).
    duration : float
        Simulated time [s], > 0.
    speed : float
        Reference rotor's speed relative to the stator at t = 0 [rad/s], magnitude at most 1e6.
    drive : {'constant', 'ramp', 'free'}
        ``'constant'``: an ideal drive holds the relative speed (the drive torque is an output);
        ``'ramp'``: the ideal drive changes it linearly from ``speed`` to ``final_speed`` over
        ``duration`` (the rotors' angular acceleration terms included); ``'free'``: no drive
        torque, the spin is a degree of freedom.
    final_speed : float, optional
        End speed of a ramp [rad/s] (required with ``drive='ramp'``), magnitude at most 1e6.
    initial : {'rest', 'equilibrium'}
        ``'rest'``: undeformed position, springs unstretched; ``'equilibrium'``: the static
        equilibrium under gravity (found by Newton's method on the machine without its
        unbalances, the rotors spinning at ``speed``, which only matters to speed-dependent
        bearings).
    impulse : str, optional
        Name of an ``[[excitations]]`` entry hit at t = 0 by an impulse of ``impulse_size``
        [N s, or N m s for a moment].
    samples : int, optional
        Number of output times, evenly spaced over ``[0, duration]`` (default: 20 per period of
        the fastest of the spin and the natural frequencies at rest, at least 201; in the linear
        time model see ``modes_below``).
    rtol, atol : float
        Tolerances of the integrator: DOP853 (Hairer's Fortran code in ``scipy.integrate.ode``
        with the numba backend, ``scipy.integrate.solve_ivp`` with the numpy one).
        ``rtol`` within 1e-13 .. 0.1, ``atol`` within 1e-20 .. 1 (a zero ``atol`` stalls the
        steps of a state that starts at zero).
    unbalance_phases_deg : array_like, shape (n_unbalances,), optional
        Phases overriding the model's ``phase_deg`` [deg].
    backend : {'auto', 'numba', 'numpy'}
        Right-hand side implementation; both give the same answers to the tolerances,
        numba (``pip install 'rotordyn_modal[fast]'``) is ~20x faster. Its first run
        compiles the kernels (~20 s) and prints :data:`COMPILE_NOTICE` on stderr first.
    progress : bool
        Show a progress bar (simulated time).
    modes_below : float, optional
        Only with a flexible rotor: the basis of the linear time model keeps the undamped modes
        (bearings' stiffness at the start ``speed``) below this [rad/s] (default: 4 times the
        fastest spin), at least the 6 lowest (:data:`rotordyn_modal.simulation.flexible.LOWEST`),
        and after an impulse or with weights set on from ``initial='rest'`` also the modes carrying
        over 1e-3 of that load's largest modal response at a sensor
        (:func:`rotordyn_modal.simulation.flexible.reached_modes`; the default ``samples`` then give
        10 a period of the fastest of them) and the modes below the output times' Nyquist frequency
        (at rest the spin gives no limit; :func:`rotordyn_modal.simulation.flexible.output_nyquist`),
        plus the static deflections under the unbalances, weights and impulse; ``math.inf``
        keeps every mode (the linear model exactly, slower).

    A model with a flexible rotor, with bearing pedestals or with gear mesh stiffness (which the
    nonlinear model cannot carry) is integrated as its linear model instead (docs/simulate.md,
    "Flexible rotors"; :mod:`rotordyn_modal.simulation.flexible`): small motions of every body
    and of the shafts' nodes about the spinning machine, the drive's angle prescribed
    (``drive='constant'`` or ``'ramp'``; ``'free'`` refused), plain journal bearings' oil films
    keeping their nonlinear force (:mod:`rotordyn_modal.simulation.flexible_journal`), the
    assumption said once on stderr; ``backend`` then selects a small right-hand side of its own.

    Returns
    -------
    SimulationResult

    Raises
    ------
    InputError
        Bad arguments, a model the time simulation does not take, or a run whose CPU time,
        estimated from below before the work, exceeds the limit of every analysis
        (``ROTORDYN_MODAL_MAX_CPU_MINUTES``; ``rdm.long_work_allowed()`` lifts it; docs/simulate.md,
        "The CPU time limit").

    Examples
    --------
    >>> import rotordyn_modal as rdm
    >>> model = rdm.load_model("examples/spring_block_rotor.toml")
    >>> res = rdm.simulate(model, 0.5, speed=50.0, drive="free", samples=11)
    >>> bool(abs(res.spin_speed[-1] / 50.0 - 1) < 1e-3)
    True
    """
    duration, speed = _positive(duration, "duration"), _speed(speed, "speed")
    final_speed = None if final_speed is None else _speed(final_speed, "final_speed")
    rtol, atol = _tolerance(rtol, "rtol", *_RTOL_RANGE), _tolerance(atol, "atol", *_ATOL_RANGE)
    checked_mass_inverse(model)    # the model every analysis refuses is refused here too
    if linear_only(model):
        if backend not in BACKENDS:
            raise InputError(f"backend {backend!r}: expected one of {', '.join(BACKENDS)}")
        return _simulate_flexible(model, duration, speed, drive, final_speed, initial, impulse, impulse_size,
                                  samples, rtol, atol, unbalance_phases_deg, modes_below, progress, backend)
    large = model.dofs.n >= _SMALL_DOF             # the eigen-solutions below cost minutes
    form = _form_once(model)                       # the checks below share one linear form
    rate = _fastest_spin(model, speed, final_speed) if large else _fastest_rate(model, speed, final_speed, form=form)
    _check_duration(duration, rate)                # before any work on a run that would not end
    _check_resolution(duration, rate, samples)     # nor on one that could not (the count limit lifted)
    system = system_arrays(model, unbalance_phases_deg)
    mode, accel = _drive(drive, speed, final_speed, duration)
    span = [speed] if final_speed is None else [speed, final_speed]
    check_table_speeds(model, span, "the simulation's speeds " + " .. ".join(f"{v:.6g}" for v in span) + " rad/s")
    kn = kernels(backend)
    extra = (mode, accel, 0.0, duration)
    if large:
        timed = _check_before_eigenvalues(kn, system, extra, duration, rate, samples, speed)
        # the output times given, the rate only enters the checks: its bound serves where they pass
        rate = _Bounded(lambda: _fastest_rate(model, speed, final_speed, announce=True, progress=progress,
                                                form=form),
                        _most_rate(model, speed, final_speed, form) if samples else None)
        _checked_with(lambda: _check_duration(duration, rate.value), rate)
        _checked_with(lambda: _check_resolution(duration, rate.value), rate)
    else:
        exact_rate, timed = rate, None
        rate = _Bounded(lambda: exact_rate, None)
    count = samples or _default_samples(rate.value, duration)
    steps = _Bounded(lambda: _fewest_steps(model, speed, duration, impulse, form, progress),
                     _most_steps(model, speed, duration, impulse, form) if large else None)
    _checked_with(lambda: _check_cpu_time(kn, system, extra, duration, rate.value, count, steps.value),
                  rate, steps)                                          # before compiling anything
    announce_compilation(kn)
    n = system.n_dof
    y0 = np.zeros(2 * n)
    if initial == "equilibrium":
        y0[:n - 1] = _static_equilibrium(model, kn, system.n_dof, speed)
    elif initial != "rest":
        raise InputError(f"initial {initial!r}: expected 'rest' or 'equilibrium'")
    y0[2 * n - 1] = speed
    if impulse is not None:
        y0[n:] += _impulse_velocity(model, system, kn, y0, impulse, impulse_size, mode)
    times = np.linspace(0.0, duration, count)
    _checked_with(lambda: _check_cpu_time(kn, system, extra, duration, rate.value, count, steps.value, y0=y0,
                                          each=timed), rate, steps)     # before the integration
    states = _integrate(kn, system, extra, y0, times, rtol, atol, progress, model)
    if drive == "free":
        check_table_speeds(model, states[:, -1], "free spin: the speed drifted outside the table; simulate "
                           "with an ideal drive, or extend the table")
    outputs = _sampled_outputs(kn, times, states, system.kernel_arguments() + extra)    # signals heeded
    return SimulationResult.from_states(model, system, times, states, drive=drive, outputs=outputs)


def _simulate_flexible(model, duration, speed, drive, final_speed, initial, impulse, impulse_size, samples,
                       rtol, atol, phases, modes_below, progress, backend):
    """The linear time model of a machine with a flexible rotor (arguments checked as for the others)."""
    from .flexible import refuse, simulate_linear

    refuse(model, drive)
    _drive(drive, speed, final_speed, duration)
    span = [speed] if final_speed is None else [speed, final_speed]
    check_table_speeds(model, span, "the simulation's speeds " + " .. ".join(f"{v:.6g}" for v in span) + " rad/s")
    return simulate_linear(model, duration, speed, drive=drive, final_speed=final_speed, initial=initial,
                           impulse=impulse, impulse_size=_finite(impulse_size, "impulse size"), samples=samples, rtol=rtol, atol=atol,
                           unbalance_phases_deg=phases, modes_below=modes_below, progress=progress,
                           backend=backend)


#: right-hand side evaluations the compiled path takes at least per output time:
#: ``scipy.integrate.ode`` starts DOP853 again at each (the initial step's 2 evaluations and one
#: step's 12). The default output times, 20 a period of the fastest motion, so make the cost of a
#: stiff mode: a casing of inertia [10, 10, 1.1e-11] kg m^2 (a 13.7 MHz mode) took about 18
#: evaluations an output time, 25 s of CPU per simulated ms, whereas DOP853 alone (``solve_ivp``,
#: the mode not excited) took 26 evaluations for 0.1 ms
_EVALUATIONS_PER_SAMPLE = 14
#: right-hand side evaluations of one DOP853 step (12 stages, the first the last one's)
_EVALUATIONS_PER_STEP = 12
#: DOP853's region of absolute stability (``|R(z)| <= 1``, ``R`` the polynomial of its
#: coefficients, ``scipy.integrate._ivp.dop853_coefficients``) reaches ``|z| = 5.96`` on the imaginary
#: axis and at most 6.77 (at 120 degrees): a step ``h`` that follows a motion of rate ``|lambda|`` keeps
#: ``h |lambda|`` about that, whatever the tolerances, once the motion is above round-off. Twice that
#: here, for a low bound: measured on an oscillator of 1e4 or 1e6 rad/s excited from 1 down to 1e-20 of
#: a slow one's amplitude, damping ratio 0 to 0.7, rtol 1e-9 to 0.1, ``solve_ivp`` took 1.24 to 19
#: times the steps of ``h |lambda| = 6.77``
_STEP_REACH = 2 * 6.77
#: a mode whose share of the impulse's initial state is below this (relative to the largest
#: share) is taken as round-off of the eigen-decomposition, not as excited
_EXCITED_SHARE = 1e-9
#: right-hand side calls timed for the estimate (the best of three runs of this many)
_TIMED_CALLS = 200
#: output times whose derived outputs (``sample_outputs``) are timed, for the numpy path
_TIMED_SAMPLES = 20
#: share of the timed derived outputs' cost counted in the estimate, so that it stays a low
#: bound: a run's output times cost up to a few % less each than the timed ones (spring block,
#: 3,001 output times on a loaded 2-core machine: 0.84 s taken against 0.87 s timed), and on a
#: shared machine the few milliseconds timed can fall in a slow moment: at 0.75 the estimate
#: exceeded the run's CPU in 3 of 40 trials at load 2.5, by up to 1.24 times (the same run,
#: 0.02 s); at 0.5 it is 0.6 to 0.85 of it
_OUTPUT_SHARE = 0.5


#: below this many coordinates one compiled right-hand side evaluation costs less than 10 ms
#: (while its Cholesky solve grew as n^3, 1.15 ms at 206 coordinates, 1.15 s at 2,006, 500 geared
#: rotors; 4.3 ms there solved rotor by rotor, ``_fast._solve_order``), the bound under which
#: :func:`_check_cpu_time` skips timing a short run
_SMALL_DOF = 300


def _check_before_eigenvalues(kn, system, extra, duration, spin, samples, speed):
    """Refuse, before any eigen-solution, a run on a large machine (:data:`_SMALL_DOF` coordinates
    or more) whose output times alone surely exceed the CPU limit.

    The fastest motion is at least the fastest spin ``spin`` [rad/s], so the default output times
    are at least those of ``spin`` (``samples`` given: those); the integrator's steps are not
    counted (0). The check without compilation (:func:`_check_cpu_time` with ``y0`` None) is made
    first; then the compiled right-hand side (whose evaluations may cost more than 10 ms at this
    size) is compiled, its notice first, and timed at the rest state spinning at ``speed``
    [rad/s]. At 2,006 coordinates (500 geared rotors) this refuses in seconds a run that
    the eigen-solutions of the state matrix kept silent for 4 min before refusing (or, before the
    evaluations were timed there, letting a run of about 3 h through).

    Returns
    -------
    float or None
        The CPU time of one compiled right-hand side evaluation [s], for the check before the
        integration to use instead of timing it again (None: not timed, no limit or the numpy path)."""
    from ..analysis._cost import long_work_is_allowed

    if long_work_is_allowed():
        return None
    count = samples or _default_samples(spin, duration)
    _check_cpu_time(kn, system, extra, duration, spin, count)
    if getattr(kn, "rhs_flat", None) is None:
        return None                                            # the numpy path was timed whole above
    announce_compilation(kn)
    rest = np.zeros(2 * system.n_dof)
    rest[-1] = speed
    return _check_cpu_time(kn, system, extra, duration, spin, count, y0=rest)


def _fewest_steps(model, speed, duration, impulse, form=None, progress=False) -> float:
    """A low bound of DOP853's steps over ``duration`` [s]: the fastest mode an impulse through
    ``impulse`` (an excitation's name, or None: no bound, 0) excites, of the linear model at
    ``speed`` [rad/s] (its roots ``lambda_k`` and shapes ``v_k``; the impulse's velocity jump
    ``M^-1 b`` as ``sum_k c_k v_k``), with a share ``|c_k| max|v_k|`` of at least
    :data:`_EXCITED_SHARE` of the largest, needs ``duration |lambda_k| /`` :data:`_STEP_REACH` steps
    at least: the explicit integrator's stability, whatever the tolerances and the output times.
    0 where no such mode is found (the estimate then rests on the output times), and where no CPU
    limit is in force (:func:`_check_cpu_time` would not read it). ``form``: see
    :func:`_form_once`.

    Only the block of the state matrix on the states the impulse reaches (:func:`_reached`) is
    solved: the others stay exactly 0. Below :data:`_KRYLOV_DOF` coordinates (half the block's
    states) every root and shape of the block (one LAPACK call, :func:`.analysis._eigensolve.eig`;
    the shares from a solve with the shapes); from there its largest roots and their shares
    alone (:func:`_fastest_excited`: ARPACK, no dense solve; 142 s of CPU had gone to the dense
    one at 4,012 states). Made inside a :func:`~rotordyn_modal._progress.phase` where ``progress``,
    whose clock runs through it; the dense solve from :data:`_ANNOUNCED_DOF` coordinates announced
    on stderr first (:data:`STEPS_NOTICE`). On a large machine it is made only where the check
    refused the bound :func:`_most_steps` (:class:`_Bounded`)."""
    if impulse is None:
        return 0.0
    from .._progress import phase
    from ..analysis import _eigensolve
    from ..assembly import _select, excitation_columns

    _select(model.excitations, [impulse], "excitation")      # an unknown name: the line of the impulse's own check
    from ..analysis._cost import limit_seconds, long_work_is_allowed

    if long_work_is_allowed() or not np.isfinite(limit_seconds()):
        return 0.0                                            # no limit to check it against: no eigen-solve
    try:
        form = (form or _form_once(model))()
        n = form.n_dof
        state = np.zeros(form.n_states)
        state[n:2 * n] = form.mass_inverse @ excitation_columns(model, [impulse])[:, 0]
        matrix, state = _reached(form.at(float(speed)), state)
        with phase(progress, "simulate: the modes the impulse excites, for the CPU estimate"):
            if len(state) >= 2 * _KRYLOV_DOF:
                return float(duration * _fastest_excited(matrix, state) / _STEP_REACH)
            if len(state) >= 2 * _ANNOUNCED_DOF:
                _say(STEPS_NOTICE.format(len(state)))
            roots, shapes = _eigensolve.eig(matrix)     # one BLAS thread, the GIL released: the clock runs
            shares = np.abs(np.linalg.solve(shapes, state)) * np.abs(shapes).max(axis=0)
    except Exception:   # noqa: BLE001 - no bound from the modes: the estimate rests on the output times
        return 0.0
    if not np.all(np.isfinite(shares)) or not shares.max(initial=0.0) > 0.0:
        return 0.0
    excited = shares >= _EXCITED_SHARE * shares.max()
    return float(duration * np.abs(roots[excited]).max() / _STEP_REACH)


def _reached(matrix, state):
    """The block of ``matrix`` (n, n) and of ``state`` (n,) on the states that ``x' = matrix x`` from
    ``state`` sets moving: those of ``state``'s nonzero entries and, in turn, every state ``i``
    with ``matrix[i, j] != 0`` for a state ``j`` reached (a breadth-first search over the nonzero
    entries). The other states stay exactly 0: the motion is the block's alone, and no mode
    outside it is excited.

    Returns
    -------
    block : ndarray, shape (r, r)
    reached : ndarray, shape (r,)
        ``r`` the states reached (0 where ``state`` is 0)."""
    import scipy.sparse
    import scipy.sparse.csgraph

    matrix = np.asarray(matrix, dtype=float)
    reached = np.zeros(len(state), dtype=bool)
    drives = scipy.sparse.csr_matrix(matrix.T != 0)           # row j: the states that state j drives
    for start in np.flatnonzero(state):
        if not reached[start]:
            reached[scipy.sparse.csgraph.breadth_first_order(drives, start, return_predecessors=False)] = True
    if reached.all():
        return matrix, np.asarray(state, dtype=float)         # no copy of the whole matrix
    index = np.flatnonzero(reached)
    return matrix[np.ix_(index, index)], np.asarray(state, dtype=float)[index]


def _fastest_excited(matrix, state) -> float:
    """The largest ``|lambda|`` [1/s] among the modes of ``matrix`` (r, r) that ``state`` (r,)
    excites, without a dense eigen-solution: the ``k`` roots of largest ``|lambda|`` (``k`` of
    :data:`_KRYLOV_COUNTS` in turn; ARPACK to machine precision, its one start vector), their right
    shapes ``v_k`` and left ones ``w_k`` (ARPACK on the transpose, the same roots: else more are
    sought), and each one's share of the state ``|c_k| max|v_k|``, ``c = (W^T V)^-1 W^T state``
    (the exact coefficients of the ``v_k``: ``W^T V`` is diagonal for distinct roots, a block for
    a repeated one).
    A mode is excited where its share is at least :data:`_EXCITED_SHARE` of the largest share found
    and of ``max|state|`` (``state = sum_k c_k v_k``: not all shares are below it over ``r``).
    Every root not found is no larger than the smallest found, so the largest excited one found
    is the largest of all; 0 (no bound) where none of the 32 largest is excited or ARPACK fails.
    At 4,012 states (500 geared rotors and a tap): about a second of CPU."""
    from scipy.sparse.linalg import eigs

    from .._blas import seeded_start

    start = seeded_start(matrix.shape[0])
    for k in _KRYLOV_COUNTS:
        if k >= matrix.shape[0] - 1:     # ARPACK's eigs takes k < n - 1
            break
        try:
            roots, right = eigs(matrix, k=k, which="LM", tol=0, v0=start)
            adjoint, left = eigs(matrix.T, k=k, which="LM", tol=0, v0=start)
        except Exception:  # noqa: BLE001 - no convergence: more roots
            continue
        if not (_matched(roots, adjoint) and _matched(adjoint, roots)):
            continue                     # not the same roots (a pair or a cluster cut apart): more roots
        pairing = left.T @ right         # diagonal for distinct roots; a block for a repeated one
        if not np.linalg.cond(pairing) < 1e10:
            continue
        shares = np.abs(np.linalg.solve(pairing, left.T @ state)) * np.abs(right).max(axis=0)
        if not np.all(np.isfinite(shares)):
            continue
        excited = shares >= _EXCITED_SHARE * max(shares.max(), np.abs(state).max())
        if excited.any():
            return float(np.abs(roots[excited]).max())
    return 0.0


def _matched(roots, others) -> bool:
    """Whether each of ``roots`` (k,) has one of ``others`` within 1e-8 of its ``|lambda|``."""
    gaps = np.abs(np.asarray(roots)[:, None] - np.asarray(others)[None, :]).min(axis=1)
    return bool(np.all(gaps <= 1e-8 * np.maximum(np.abs(roots), np.finfo(float).tiny)))


class _Bounded:
    """A number the CPU checks read, whose exact value costs eigen-solutions: on a large machine its
    upper bound (ARPACK's largest ``|lambda|``, 0.3 s at 2,006 coordinates where the dense
    eigen-solutions took minutes) is checked first. The checks refuse only more than the bound,
    so one the bound passes, the exact value passes too; only where the bound is refused is the
    exact value made (and the check made again with it, whose line is the one shown:
    :func:`_checked_with`).

    Parameters
    ----------
    exact : callable
        Makes the exact value (no arguments).
    bound : float or None
        Its upper bound; None: the exact value is made at once.

    Attributes
    ----------
    value : float
        The bound, or the exact value once made.
    """

    def __init__(self, exact, bound):
        self._exact, self.exact = exact, bound is None
        self.value = exact() if self.exact else bound

    def make_exact(self) -> bool:
        """Replace the bound by the exact value; False where it was exact already."""
        if self.exact:
            return False
        self.value, self.exact = self._exact(), True
        return True


def _checked_with(check, *numbers):
    """Call ``check`` (which reads the :class:`_Bounded` ``numbers``' values); where it refuses
    (InputError) on a bound, make every number exact and call it again, which alone may refuse."""
    try:
        check()
    except InputError:
        if not any([number.make_exact() for number in numbers]):
            raise
        check()


#: ARPACK's tolerance for the largest ``|lambda|`` (:func:`_most_steps`) and the factor it is
#: raised by, so that it bounds the true value (a Ritz value converges from below: 4099.89698991
#: at tolerance 1e-6 for 4099.89699095 at 2,006 coordinates; 1863.84212415 for 1863.84213846 at 406)
_ARPACK_TOLERANCE, _ARPACK_MARGIN = 1e-8, 1.05


def _most_steps(model, speed, duration, impulse, form=None):
    """An upper bound of :func:`_fewest_steps` (the same arguments): the fastest root of the linear
    model at ``speed`` [rad/s], ``|lambda|`` largest (ARPACK, times :data:`_ARPACK_MARGIN`; where
    ARPACK fails, the balanced matrix's norm, :func:`_balanced_norm`), as if the impulse excited it.
    0 where :func:`_fewest_steps` is 0 without an eigen-solution; None where the state matrix cannot
    be made (the exact count is then made). ``form``: see :func:`_form_once`."""
    if impulse is None:
        return 0.0
    from ..analysis._cost import limit_seconds, long_work_is_allowed
    from ..assembly import _select

    _select(model.excitations, [impulse], "excitation")      # an unknown name: the line of the impulse's own check
    if long_work_is_allowed() or not np.isfinite(limit_seconds()):
        return 0.0
    try:
        fastest = _largest_modulus((form or _form_once(model))().at(float(speed)))
    except Exception:   # noqa: BLE001 - no finite bound, or the model's fault that _fewest_steps takes as 0
        return None
    return duration * fastest * _ARPACK_MARGIN / _STEP_REACH


def _most_rate(model, speed, final_speed, form=None):
    """An upper bound of :func:`_fastest_rate` [rad/s] (the same arguments): at the same speed, the
    largest ``|lambda|`` (ARPACK, times :data:`_ARPACK_MARGIN`; where ARPACK fails, the balanced
    matrix's norm, :func:`_balanced_norm`) for the largest ``|Im lambda|``. None where neither is
    finite or the model is at fault (the exact rate is then made, and refuses).
    ``form``: see :func:`_form_once`."""
    try:
        natural = _at_first_speed(model, speed, final_speed, lambda matrix: _largest_modulus(matrix) * _ARPACK_MARGIN,
                                  form)
    except (ModelError, _NoBound):
        return None
    return max(_fastest_spin(model, speed, final_speed), natural)


def _at_first_speed(model, speed, final_speed, solve, form=None) -> float:
    """``solve`` (a function of a state matrix, to a number) on the linear model's state matrix at the
    first of the speeds 0, ``speed`` and ``final_speed`` [rad/s] that the model takes (bearing tables
    may not reach 0); 0 where it takes none (a model without restoring force still simulates). A fault
    of the model (:class:`ModelError`, not of one speed) and :class:`_NoBound` raise. ``form``: see :func:`_form_once`."""
    from .. import _arguments

    form = form or _form_once(model)
    for at in [v for v in (0.0, speed, final_speed) if v is not None]:
        try:
            return solve(form().at(_arguments.speed(at)))
        except (ModelError, _NoBound):
            raise
        except Exception:  # noqa: BLE001 - a speed the model cannot take: the next one
            continue
    return 0.0


class _NoBound(RuntimeError):
    """ARPACK did not give the largest root."""


def _largest_modulus(matrix) -> float:
    """An upper bound of the largest ``|lambda|`` of ``matrix`` (n, n): ARPACK's (``k = 1``, tolerance
    :data:`_ARPACK_TOLERANCE`; the callers raise it by :data:`_ARPACK_MARGIN`), or where ARPACK fails,
    :func:`_balanced_norm` (no eigen-solution); :class:`_NoBound` where neither is finite."""
    from scipy.sparse.linalg import eigs

    try:
        largest = float(np.abs(eigs(matrix, k=1, which="LM", tol=_ARPACK_TOLERANCE, return_eigenvectors=False)).max())
    except Exception:  # noqa: BLE001 - no convergence, a matrix too small for ARPACK
        largest = _balanced_norm(matrix)
    if not np.isfinite(largest):
        raise _NoBound("not finite")
    return largest


def _balanced_norm(matrix) -> float:
    """An upper bound of every ``|lambda|`` of ``matrix`` (n, n) without an eigen-solution: the smaller
    of the largest column and row sums of ``|D^-1 A D|``, ``D`` the diagonal scaling of LAPACK's
    balancing (``scipy.linalg.matrix_balance``, no permutation): the same roots, and no root exceeds
    an induced norm. Measured against the largest ``|lambda|`` at 100 rad/s: 1.13 to 2.10 times it
    on every example, 3.9 times on 200 geared rotors on bearings (1,612 states, 69 ms of CPU)."""
    import scipy.linalg

    balanced = np.abs(scipy.linalg.matrix_balance(np.asarray(matrix, dtype=float), permute=False,
                                                  separate=False)[0])
    return float(min(balanced.sum(axis=0).max(), balanced.sum(axis=1).max()))


def _check_cpu_time(kn, system, extra, duration, rate, samples, steps=0.0, y0=None, each=None):
    """Refuse, before the work, a run estimated to take more CPU time than the limit of every
    analysis (``analysis._cost``: ``ROTORDYN_MODAL_MAX_CPU_MINUTES``, ``--allow-long``).

    Evaluations of the right-hand side, at least: on the compiled path
    :data:`_EVALUATIONS_PER_SAMPLE` an output time (by default 20 a period of the fastest motion,
    ``rate`` [rad/s]: the highest natural frequency at the start speed, or the spin), and
    :data:`_EVALUATIONS_PER_STEP` a step of the ``steps`` that the fastest excited motion makes
    the integrator take at least (:func:`_fewest_steps`), the larger of the two; on the numpy path
    (``solve_ivp``: the output times from its steps' dense output, no evaluation of their own)
    those of the ``steps``, at least one, plus the derived outputs of each output time
    (``sample_outputs``, an ``assemble`` and a solve each, in Python: timed, measured as 1.7 to 2.1
    right-hand side evaluations on spring_block_rotor, gear_machine, fan_on_bearings and
    motor_fan_minimal; their runs of 0.02 s at the default 201 output times took 0.8 to 3.0
    evaluations an output time, all of them the steps'). ``y0`` None: the check before any compilation:
    the numpy path timed whole, the compiled path at least the Python call of a function that does
    nothing with the same arguments, so that a run far over the limit is refused before the
    kernel's compilation (~20 s on a fresh machine); with the state ``y0`` (shape (2 n_dof,)), the
    compiled right-hand side timed on it. All are low bounds (the timed compiled one measured 0.75
    of the CPU time taken, the integrator's own steps aside), so that only what would surely
    exceed the limit is refused. ``each`` [s]: the compiled right-hand side's evaluation already
    timed (by :func:`_check_before_eigenvalues`), used with ``y0`` instead of timing it again.

    Returns
    -------
    float or None
        The CPU time of one compiled right-hand side evaluation on ``y0`` [s] where it was timed
        (or given), else None."""
    from ..analysis._cost import limit_seconds, long_work_is_allowed

    if long_work_is_allowed():
        return
    limit = limit_seconds()
    compiled = getattr(kn, "rhs_flat", None) is not None
    if compiled:
        evaluations = max(samples * _EVALUATIONS_PER_SAMPLE, _EVALUATIONS_PER_STEP * steps)
    else:
        evaluations = _EVALUATIONS_PER_STEP * max(steps, 1.0)
    if y0 is not None and not compiled:
        return
    if (evaluations + samples) * 1e-2 <= limit and (y0 is None or system.n_dof < _SMALL_DOF):
        return                                                  # short even at 10 ms each
    zeros = np.zeros(2 * system.n_dof)
    if compiled:
        from ._fast import pack

        arguments, outputs, each_output = pack(system, *extra), "", 0.0
        if y0 is not None:
            each = _seconds_per_call(kn.rhs_flat, y0, arguments) if each is None else each
            what = "evaluations of {} us"
        else:
            each = _seconds_per_call(_does_nothing, zeros, arguments)
            what = "evaluations of more than the {} us of the call alone"
    else:
        arguments = system.kernel_arguments() + extra
        each, what = _seconds_per_call(kn.rhs, zeros, arguments), "evaluations of {} us"
        each_output = _OUTPUT_SHARE * _seconds_per_output(kn, zeros, arguments)
        outputs = f" of {each_output * 1e6:.2g} us each"
    seconds = evaluations * each + samples * each_output
    if seconds > limit:
        raise InputError(_too_long(duration, rate, samples, evaluations, each, what, limit, steps, seconds, outputs))
    return each if compiled and y0 is not None else None


def _does_nothing(t, y, floats, ints):
    return y


def _seconds_per_call(call, y, arguments) -> float:
    """CPU time of one ``call(0.0, y, *arguments)`` [s]: the best of three runs of
    :data:`_TIMED_CALLS` calls, after one call (which compiles a numba kernel); of fewer where a
    call costs more than 5 ms (runs of about 0.2 s, at least one call: 1.15 s a call at 2,006
    coordinates would have taken 11 min to time)."""
    import time

    call(0.0, y, *arguments)
    start = time.process_time()
    call(0.0, y, *arguments)
    once = time.process_time() - start
    count = _TIMED_CALLS if once * _TIMED_CALLS <= 1.0 else max(1, int(0.2 / once))
    best = once if count == 1 else np.inf
    for _ in range(3 if count > 1 else 2):
        start = time.process_time()
        for _ in range(count):
            call(0.0, y, *arguments)
        best = min(best, (time.process_time() - start) / count)
    return best


def _seconds_per_output(kn, y, arguments) -> float:
    """CPU time of the derived outputs of one output time on the numpy path [s]
    (``kn.sample_outputs`` of :data:`_TIMED_SAMPLES` copies of the state ``y``, the best of three)."""
    import time

    times, states = np.zeros(_TIMED_SAMPLES), np.tile(y, (_TIMED_SAMPLES, 1))
    best = np.inf
    for _ in range(3):
        start = time.process_time()
        kn.sample_outputs(times, states, *arguments)
        best = min(best, (time.process_time() - start) / _TIMED_SAMPLES)
    return best


def _too_long(duration, rate, samples, evaluations, each, what, limit, steps, seconds, outputs="") -> str:
    """The one line refusing a simulation over the CPU limit ``limit`` [s]: ``seconds`` [s] estimated
    from ``evaluations`` of ``each`` [s] (``steps`` of them the fewest the fastest excited motion
    needs) and ``samples`` output times (``outputs``: what each costs, where it is counted)."""
    from ..analysis._cost import ENVIRONMENT, duration as _duration

    periods = duration * rate / (2 * np.pi)
    stepped = f", at least {steps:.3g} integrator steps for the fastest mode the impulse excites" if steps else ""
    return (f"duration = {duration!r} s: this simulation would take at least {_duration(seconds)} of CPU "
            f"time, more than the limit of {_duration(limit)} ({periods:.3g} periods of the fastest "
            f"motion, {rate / (2 * np.pi):.4g} Hz; {samples:,} output times{outputs}{stepped}, at least "
            f"{evaluations:.3g} {what.format(f'{each * 1e6:.2g}')}): a shorter duration or fewer samples, or "
            f"add --allow-long ({ENVIRONMENT} sets the limit)")


def _integrate(kn, system, extra, y0, times, rtol, atol, progress, model=None):
    """States at ``times``: scipy's Fortran DOP853 driving the compiled right-hand side, or
    ``solve_ivp`` (DOP853) driving the plain one (same method, same tolerances)."""
    bar = _progress_bar(times[-1], progress)
    try:
        if getattr(kn, "rhs_flat", None) is not None:
            return _integrate_compiled(kn, system, extra, y0, times, rtol, atol, bar)
        return _integrate_plain(kn, system, extra, y0, times, rtol, atol, bar)
    except _Failed as failure:
        raise _explained(failure, model, system) from None
    finally:
        if bar is not None:
            bar.close()


class _Failed(RuntimeError):
    """The integration stopped; ``time`` [s] where it stopped, the ``state`` of the last output
    time and the state ``stopped`` where it stopped (None: not known)."""

    def __init__(self, message, time, state, stopped=None):
        super().__init__(message)
        self.time, self.state, self.stopped = time, state, stopped


def _explained(failure, model, system):
    """One line naming the failure's cause (:class:`._system.IntegrationFailed`): an oil film that
    lost its journal (eccentricity 1) is the model's limit, not a bug; it names each journal's
    eccentricity at the last output time and where the integrator stopped."""
    films = [i for i in range(len(system.bbody)) if system.bfilm[i, 2] > 0.0]
    source = f"{model.source}: " if model is not None else ""
    if model is None or not films:
        return IntegrationFailed(f"{source}{failure}", failure.time, failure.stopped)
    reached = _eccentricities(model, system, films, failure.state)
    stopped = "" if failure.stopped is None else (
        f", and where it stopped (t = {failure.time:.6g} s): {_eccentricities(model, system, films, failure.stopped)}")
    return IntegrationFailed(
        f"{model.source}: {failure} with journal bearings (eccentricity at the last output time: "
        f"{reached}){stopped}: a journal approached its bearing wall (eccentricity 1), where the oil "
        "film's force grows without limit (the equations stiffen beyond the integrator, and contact "
        "is not modelled): a speed too low to carry the load, or whirl grown to the clearance. Start "
        "from initial='equilibrium' at a running speed, or stay below the oil-whirl threshold "
        "(rotordyn-modal stability)", failure.time, failure.stopped)


def _eccentricities(model, system, films, state) -> str:
    """``'[bearings.NAME] e, ...'``: the eccentricity of each journal bearing ``films`` (indices)
    in the state ``state`` (2 n,) of the rigid model."""
    from ._kernels import bearing_stretch

    n = system.n_dof
    q, dq = state[:n], state[n:]
    reached = []
    for i in films:
        b = system.bbody[i]
        z, _ = bearing_stretch(q, dq, system.slot[b], system.ntrans[b], system.A3, system.bpos[i])
        eccentricity = np.linalg.norm(system.baxes[i] @ z[:3]) / system.bfilm[i, 2]
        reached.append(f"[bearings.{model.bearings[i].name}] {eccentricity:.4f}")
    return ", ".join(reached)


def _integrate_compiled(kn, system, extra, y0, times, rtol, atol, bar):
    from scipy.integrate import ode

    from ._fast import pack

    arguments = pack(system, *extra)
    # compiled (or loaded from numba's cache) here, from Python, not on the first call from
    # inside the Fortran integrator's callback (docs/DEVELOPING.md, "numba's cache")
    kn.rhs_flat(times[0], y0, *arguments)
    rhs_flat, (floats, ints) = kn.rhs_flat, arguments

    def rhs(t, y):     # the arguments bound here, not as f_params: see _stop_at_a_step_when
        return rhs_flat(t, y, floats, ints)

    with _signals_noted() as caught:
        solver = ode(rhs).set_integrator("dop853", rtol=rtol, atol=atol, nsteps=10**9)
        _stop_at_a_step_when(solver, caught)
        solver.set_initial_value(y0, times[0])
        # DOP853's stiffness test is kept with journal bearings only (see integrate_to)
        return _output_times(solver, times, y0, bar, caught, stiffness_test=bool(np.any(system.bfilm[:, 2] > 0.0)))


def _stop_at_a_step_when(solver, caught):
    """Make the DOP853 ``solver`` (scipy's ``ode``, before its initial value is set) stop at the end
    of its step in progress once the list ``caught`` is not empty.

    The step callback (``solout``, scipy's public ``ode.set_solout``) is the only Python code that
    runs while DOP853 drives the compiled right-hand side, so a signal's Python handler runs there,
    at the end of a step. It must not raise: an exception inside it does not stop scipy 1.17's
    DOP853, which then crawls on with steps of 1e-10 s for ever. The right-hand side must take no
    ``f_params``: scipy 1.17's DOP853 passes them to the callback too, and its own wrapper, which
    takes ``(t, y)`` only, raises TypeError (sim27k's attempt hung on that). ``iout = 1`` only calls
    it: the steps and the results are the same as without it. It is also called at the start point
    of each ``integrate`` (``solver.t``, before any step), where stopping fails the solver for good
    (return code -3, "step size too small"): a signal noted between two output times stops it at
    the end of the next one's first step instead."""
    def step(t, *_):
        return -1 if caught and t != solver.t else 0

    solver.set_solout(step)


def _output_times(solver, times, y0, bar, caught, stiffness_test=False):
    """The states at ``times`` (shape (len(times), len(y0))) from the DOP853 ``solver``, past its
    stiffness test unless ``stiffness_test`` (:func:`._system.integrate_to`). A signal
    noted in ``caught`` (``[(signum, frame, handler)]``) stops it at the end of its step, and the
    handler is called then (the command line's raises; where it returns, the integration goes on
    from there)."""
    import warnings

    from ._system import integrate_to

    states = np.empty((len(times), len(y0)))
    states[0] = y0
    for i in range(1, len(times)):
        last = solver.y.copy()
        while True:
            with warnings.catch_warnings():   # a failure is raised below with its return code
                warnings.simplefilter("ignore", UserWarning)
                states[i] = integrate_to(solver, times[i], stiffness_test)
            if not caught:
                break
            signum, frame, handler = caught.pop(0)
            caught.clear()
            handler(signum, frame)
        if not solver.successful() or not np.all(np.isfinite(states[i])):
            stopped = np.array(solver.y, copy=True)
            finite = bool(np.all(np.isfinite(stopped)) and np.all(np.isfinite(states[i])))
            raise _Failed(integration_failure(solver.get_return_code(), solver.t, finite), solver.t, last,
                          stopped if finite else None)
        if bar is not None:
            bar.update(times[i] - times[i - 1])
    return states


@contextlib.contextmanager
def _signals_noted():
    """Inside: every signal with a Python handler (Ctrl-C's ``KeyboardInterrupt``, the command
    line's SIGTERM and SIGHUP, a program's own, such as a SIGALRM time-out) is only noted in the
    yielded list, with that handler, as ``(signum, frame, handler)``; on leaving, the handlers are
    back. Signals left to their default action (SIGTERM outside the command line: the process
    ends at once) or ignored are not touched, nor is anything outside the main thread.

    Python runs a signal's handler only between its own instructions: inside scipy's DOP853 calling
    the compiled right-hand side none runs, and on 100 geared rotors ``timeout``'s SIGTERM went
    unheeded for minutes. The integrator's step callback runs the handler that notes the signal;
    :func:`_output_times` then calls the handler noted. Every Python handler is held so, not only
    those that stop the run: one raising inside the step callback would leave DOP853 crawling."""
    import signal
    import threading

    caught, previous = [], {}

    def note(signum, frame):
        caught.append((signum, frame, previous[signum]))

    if threading.current_thread() is threading.main_thread():
        for number in signal.valid_signals():
            try:
                if callable(signal.getsignal(number)):
                    previous[number] = signal.signal(number, note)
            except (OSError, ValueError):    # a signal Python may not handle
                continue
    try:
        yield caught
    finally:
        for number, handler in previous.items():
            if signal.getsignal(number) is note:
                signal.signal(number, handler)


#: the output times' derived outputs (:func:`_sampled_outputs`) are made in parts of about this many
#: entries of the mass matrix (n_dof squared each output time): a part of 2,006 coordinates is 4 output
#: times, of 606 coordinates 45 (about 40 ms of CPU), of an example all of them at once
_OUTPUT_PART_ENTRIES = 2 ** 24


def _sampled_outputs(kn, times, states, arguments):
    """``kn.sample_outputs(times, states, *arguments)`` (:func:`._kernels.sample_outputs`: each output
    time's own, the same bits), made in parts of :data:`_OUTPUT_PART_ENTRIES`, a signal's Python
    handler held (:func:`_signals_noted`) during each part and called between two (the command
    line's raises; where it returns, the rest is made).

    A signal's handler that raised inside the compiled loop (SIGTERM at 150 geared rotors on
    bearings, 3,000 output times) ended the run with ``SystemError: CPUDispatcher(...) returned a
    result with an exception set`` (exit 1, where 143 is documented) after the whole loop, 2.5 s of
    CPU later."""
    times, states = np.ascontiguousarray(times, dtype=float), np.ascontiguousarray(states, dtype=float)
    n_dof = states.shape[1] // 2
    part = max(1, _OUTPUT_PART_ENTRIES // max(n_dof * n_dof, 1))
    if len(times) <= part:
        return _heeding_signals(kn.sample_outputs, times, states, *arguments)
    pieces = [_heeding_signals(kn.sample_outputs, times[i:i + part], states[i:i + part], *arguments)
              for i in range(0, len(times), part)]
    return tuple(np.concatenate(outputs) for outputs in zip(*pieces))


def _heeding_signals(call, *arguments):
    """``call(*arguments)`` with the signals noted (:func:`_signals_noted`), the first one noted then
    handled (its handler called: the command line's raises)."""
    with _signals_noted() as caught:
        result = call(*arguments)
    if caught:
        signum, frame, handler = caught[0]
        handler(signum, frame)
    return result


def _integrate_plain(kn, system, extra, y0, times, rtol, atol, bar):
    from scipy.integrate import solve_ivp

    arguments = system.kernel_arguments() + extra

    def rhs(t, y):
        if bar is not None and t > bar.n:
            bar.update(t - bar.n)
        return kn.rhs(t, y, *arguments)

    try:
        solution = solve_ivp(rhs, (times[0], times[-1]), y0, method="DOP853", t_eval=times, rtol=rtol, atol=atol)
    except np.linalg.LinAlgError as error:  # a mass matrix that the motion made singular
        raise _Failed(f"integration failed: {error}", 0.0, y0) from None
    states = np.asarray(solution.y, dtype=float).reshape(len(y0), -1)
    if not solution.success or not np.all(np.isfinite(states)):
        last = states[:, -1] if states.shape[1] else y0
        raise _Failed(f"integration failed at t = {solution.t[-1] if len(solution.t) else 0.0:.6g} s: "
                      f"{solution.message}", solution.t[-1] if len(solution.t) else 0.0, last)
    return states.T


def _drive(drive, speed, final_speed, duration):
    if drive not in DRIVES:
        raise InputError(f"drive {drive!r}: expected one of {', '.join(DRIVES)}")
    if drive == "ramp":
        if final_speed is None:
            raise InputError("drive 'ramp' needs final_speed (the speed at the end of the run-up)")
        return _kernels.PRESCRIBED, (_finite(final_speed, "final_speed") - speed) / duration
    if final_speed is not None:
        raise InputError(f"final_speed is only used with drive 'ramp' (drive is {drive!r})")
    return (_kernels.FREE if drive == "free" else _kernels.PRESCRIBED), 0.0


def _static_equilibrium(model, kn, n, speed):
    """Coordinates (all but ``phi``) where gravity, the suspensions and the bearings balance,
    at rest (the rotors spinning at ``speed``, which only sets speed-dependent bearings)."""
    from scipy.optimize import root

    data = model.to_dict()
    data["unbalances"] = []
    still = system_arrays(type(model).from_dict(data, model.source))
    arguments = still.kernel_arguments() + (_kernels.PRESCRIBED, 0.0, 0.0, 0.0)

    def residual(coordinates):
        y = np.zeros(2 * n)
        y[:n - 1] = coordinates
        y[2 * n - 1] = speed
        return kn.rhs(0.0, y, *arguments)[n:2 * n - 1]

    solution = root(residual, np.zeros(n - 1), method="hybr", tol=1e-12)
    if np.abs(residual(solution.x)).max() > 1e-8:  # judged by the residual acceleration [m/s^2, rad/s^2]
        raise InputError(f"{model.source}: no static equilibrium under gravity found ({solution.message}); "
                         "do the suspensions and bearings restrain every direction? Use initial 'rest'")
    return solution.x


def _impulse_velocity(model, system, kn, y0, name, size, mode):
    """Velocity jump ``M^-1 Q`` of an impulse ``size`` through excitation ``name``."""
    from ..assembly import _select
    from ._kernels import point_partials

    excitation = _select(model.excitations, [name], "excitation")[0]
    size = _finite(size, "impulse size")
    n = system.n_dof
    M, _ = kn.assemble(0.0, y0, *system.kernel_arguments())
    point = np.asarray(excitation.position, dtype=float) - system.reference_point
    if excitation.rotor is None:
        body = (0.0, -1, 2, point, np.zeros(3))
    else:
        b = system.rotor_index[[r.name for r in model.rotors].index(excitation.rotor)]
        body = (system.ratio[b], system.slot[b], system.ntrans[b], system.center[b], point - system.center[b])
    P, W = point_partials(y0, system.e, system.E2, system.nf, system.A3, *body)
    force = (W if excitation.kind == "moment" else P).T @ (size * np.asarray(excitation.direction, dtype=float))
    jump = np.zeros(n)
    k = n if mode == _kernels.FREE else n - 1
    jump[:k] = np.linalg.solve(M[:k, :k], force[:k])
    fastest = float(np.abs(jump).max(initial=0.0))
    if not fastest <= _FASTEST_JUMP:
        # 1e15 N s on the gear machine (7e12 m/s) ran for minutes without an end, 1e308 ended in
        # a ZeroDivisionError inside the integrator
        raise InputError(f"impulse_size = {size:g} (excitation {excitation.name!r}): expected an impulse that a "
                         f"hammer or shaker gives: it would start the machine at {fastest:.3g} m/s or rad/s, more "
                         f"than {_FASTEST_JUMP:g}")
    return jump


#: the fastest velocity jump an impulse may give a coordinate [m/s or rad/s]: faster than a
#: projectile, no blow of a hammer or shaker
_FASTEST_JUMP = 1e4


def _form_once(model):
    """A callable giving ``model``'s linear form (:func:`.linear_system.speed_linear_form`), built
    on its first call only: one simulation's checks (the rate's and the steps' bounds and their
    exact values) share it (2,006 coordinates: its assembly and mass factor, about 4 s, had been
    made up to four times). A build that raises is tried again on the next call, as before."""
    import functools

    from ..linear_system import speed_linear_form

    return functools.cache(functools.partial(speed_linear_form, model))   # an exception is not cached


def _fastest_spin(model, speed, final_speed) -> float:
    """The fastest rotor's spin [rad/s] at the reference speeds ``speed`` and ``final_speed``."""
    return max(abs(speed), abs(final_speed or 0.0)) * max(abs(r) for r in model.speed_ratios.values())


def _fastest_rate(model, speed, final_speed, announce=False, progress=False, form=None):
    """The fastest of the rotors' spins and the natural frequencies at rest [rad/s].

    The natural frequencies are the state matrix's eigenvalues alone (the largest ``|Im lambda|``,
    as ``modal``'s): no shapes, whirl forms or repeated roots' resolution, which took over 5 min
    of CPU time at 2,006 coordinates (500 geared rotors) before the CPU estimate was made; on a
    large machine only its largest roots (:func:`_largest_frequency`). ``announce``: say so on
    stderr first where the dense eigenvalues are made at a size where they take long
    (:data:`_ANNOUNCED_DOF` coordinates or more: 22 s of CPU time at 2,006, more than 100 s on a
    loaded machine). ``progress``: the work shown as a :func:`~rotordyn_modal._progress.phase`. ``form``: see
    :func:`_form_once`."""
    from .._progress import phase

    with phase(progress, "simulate: the natural frequencies, for the default output times"):
        natural = _at_first_speed(model, speed, final_speed, lambda matrix: _largest_frequency(matrix, announce),
                                  form)
    return max(_fastest_spin(model, speed, final_speed), natural)


#: coordinates from which the natural frequencies that set the default output times are
#: announced where they are the dense eigenvalues (:data:`EIGENVALUE_NOTICE`)
_ANNOUNCED_DOF = 1000
#: the line on stderr before the natural frequencies of a large machine (the number of states)
EIGENVALUE_NOTICE = ("simulate: the natural frequencies of the {:,} states of the linear model, for the default "
                     "output times (seconds to minutes at this size; --samples spares them)...")
#: the line on stderr before the modes an impulse excites are made on a large machine (the number of
#: states; :func:`_fewest_steps`)
STEPS_NOTICE = ("simulate: the modes of the {:,} states of the linear model that the impulse excites, to count "
                "the integrator's steps for the CPU estimate (seconds to minutes at this size; " + ONE_CALL_NOTE +
                "; --allow-long spares them)...")


def _say(line):
    """``line`` on stderr, clearing and redrawing a progress line already drawn there (tqdm's
    ``write``), so that the two do not share a line."""
    import sys

    from tqdm import tqdm

    tqdm.write(line, file=sys.stderr)
    sys.stderr.flush()


#: coordinates (half the states) from which the largest natural frequency is first sought among
#: the largest roots (:func:`_largest_imaginary`) rather than among all of them
_KRYLOV_DOF = _SMALL_DOF
#: how many roots of largest ``|lambda|`` ARPACK is asked for, in turn, until they hold the largest
#: ``|Im lambda|`` (:func:`_largest_imaginary`)
_KRYLOV_COUNTS = (4, 8, 16, 32)


def _largest_frequency(matrix, announce=False) -> float:
    """The largest ``|Im lambda|`` [rad/s] of the state ``matrix`` (n, n): among its largest roots
    (:func:`_largest_imaginary`) from :data:`_KRYLOV_DOF` coordinates, else (or where that does not
    settle it) from the dense eigenvalues, on one BLAS thread as every dense eigen-solution
    (announced on stderr first from :data:`_ANNOUNCED_DOF` coordinates where ``announce``).

    The dense eigenvalues are numpy's (LAPACK's ``dgeev`` without vectors), which release the GIL,
    so that the clock of the phase around them (:func:`_fastest_rate`) runs: scipy's ``eigvals``,
    the same routine, held it (a thread ticked 1 to 2 times in a 1.4 s solve of 1,200 states, 28
    times with numpy's), and gave the same bits (every example's state matrix, and random ones of
    10 to 1,200 rows, compared with ``np.array_equal``). :func:`.analysis._eigensolve.eig` releases it
    too, but makes the eigenvectors: 1.6 times the CPU time."""
    from ..analysis import _batches

    states = matrix.shape[-1]
    if states >= 2 * _KRYLOV_DOF:
        try:
            return _largest_imaginary(matrix)
        except _NoBound:
            pass
    if announce and states >= 2 * _ANNOUNCED_DOF:
        _say(EIGENVALUE_NOTICE.format(states))          # inside the phase, whose line may be drawn
    with _batches.one_blas_thread(24 * states ** 2):
        values = np.linalg.eigvals(matrix)              # the GIL released: see above
    return float(np.max(np.abs(values.imag), initial=0.0))


def _largest_imaginary(matrix) -> float:
    """The largest ``|Im lambda|`` of ``matrix`` (n, n) from its ``k`` roots of largest ``|lambda|``
    (ARPACK to machine precision, its one start vector; ``k`` of :data:`_KRYLOV_COUNTS` in turn):
    every other root has ``|Im lambda| <= |lambda|`` at most the smallest ``|lambda|`` found, so where
    the largest ``|Im lambda|`` found is at least that, it is the largest of all. At 2,006
    coordinates (500 geared rotors, 4,012 states) 0.3 s of CPU time with ``k = 4``, where the dense
    eigenvalues took 22 s; the same number to 1e-13 (measured: docs/simulate.md). :class:`_NoBound`
    where no ``k`` settles it (all roots real, or ARPACK fails)."""
    from scipy.sparse.linalg import eigs

    from .._blas import seeded_start

    for k in _KRYLOV_COUNTS:
        if k >= matrix.shape[0] - 1:     # ARPACK's eigs takes k < n - 1
            break
        try:
            values = eigs(matrix, k=k, which="LM", tol=0, return_eigenvectors=False, v0=seeded_start(matrix.shape[0]))
        except Exception:  # noqa: BLE001 - no convergence: more roots, or the dense eigenvalues
            continue
        if not np.all(np.isfinite(values)):
            continue
        largest = float(np.abs(values.imag).max())
        if largest >= np.abs(values).min():
            return largest
    raise _NoBound("the largest roots do not hold the largest |Im lambda|")


def _positive(value, name):
    value = _finite(value, name)
    if value <= 0:
        raise InputError(f"{name} = {value!r}: expected a number > 0")
    return value


#: largest spin speed of a simulation [rad/s] (about 9.5 million rpm)
_LARGEST_SPEED = 1e6
_RTOL_RANGE = (1e-13, 0.1)
_ATOL_RANGE = (1e-20, 1.0)


def _speed(value, name):
    value = _finite(value, name)
    if abs(value) > _LARGEST_SPEED:
        raise InputError(f"{name} = {value!r} rad/s: expected a speed of magnitude at most {_LARGEST_SPEED:g} rad/s")
    return value


def _tolerance(value, name, low, high):
    value = _finite(value, name)
    if not low <= value <= high:
        raise InputError(f"{name} = {value!r}: expected a tolerance from {low:g} to {high:g}")
    return value


def _finite(value, name):
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r}: expected a number") from None
    if not np.isfinite(value):
        raise InputError(f"{name} = {value!r}: expected a finite number")
    return value
