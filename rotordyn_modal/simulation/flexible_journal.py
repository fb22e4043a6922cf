"""Plain journal bearings in the linear time model of flexible machines (docs/theory.md §19,
"Journal bearings in the linear time model").

The structure stays linear (:mod:`rotordyn_modal.simulation.flexible`) and is assembled without
the journal bearings' oil films; each film pushes its journal with the nonlinear short-bearing
force (:func:`rotordyn_modal.simulation._fast._film_force`, the kernel of the large-rotation
model, plain or compiled by numba) of the journal centre's displacement ``z = B eta`` and velocity
``z' = B eta'`` relative to its housing (stator, pedestal or ground), at the journal's own speed
``r_j phi'``; on the reduced coordinates it acts as ``B^T F``. The basis holds, besides the
modes of the structure without the films, the static deflections under unit forces at every
journal along both lateral axes (:func:`attachment_loads`), so that the journals' motion under
their film forces is represented. The journal's static load comes from gravity, as in the
large-rotation model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ._fast import _film_force, _sommerfeld_angle
from ._jit import compile_together

__all__ = ["Films", "journal_bearings", "constant_parts", "attachment_loads", "films", "film_load",
           "equilibrium", "wrenches", "compiled_film_load", "failure"]


@dataclass(frozen=True)
class Films:
    """The journal bearings' oil films on the reduced coordinates ``eta`` (``r`` of them).

    Attributes
    ----------
    ratio : ndarray, shape (J,)
        Speed ratio of each journal's rotor (its own speed is ``ratio * phi'``).
    moves : ndarray, shape (J, 3, r)
        Journal centre's displacement relative to its housing per reduced coordinate, model axes [m].
    axes : ndarray, shape (J, 2, 3)
        Rows ``x``, ``y`` of each bearing's radial frame (``x × y = e``).
    film : ndarray, shape (J, 4)
        Radius, length, radial clearance [m], viscosity [Pa s].
    names : tuple of str
        The bearings' names.
    """

    ratio: np.ndarray
    moves: np.ndarray
    axes: np.ndarray
    film: np.ndarray
    names: tuple

    def arguments(self):
        """``(ratio, moves, axes, film)``: the arguments of :func:`film_load` after the state."""
        return self.ratio, self.moves, self.axes, self.film


def journal_bearings(model) -> list:
    """The model's plain journal bearings (``type = 'journal'``)."""
    return [b for b in model.bearings if b.coefficients.kind == "journal"]


def constant_parts(model):
    """Stiffness and damping (n, n) of the journal bearings' constant parts (axial and moment
    springs and dampers given beside the film; the film itself is left out)."""
    from ..assembly import bearing_motion

    n = model.dofs.n
    K, C = np.zeros((n, n)), np.zeros((n, n))
    for bearing in journal_bearings(model):
        rows, local = bearing_motion(model, bearing)
        K[rows, rows] += local.T @ bearing.coefficients.stiffness[0] @ local
        C[rows, rows] += local.T @ bearing.coefficients.damping[0] @ local
    return K, C


def attachment_loads(model) -> list:
    """Generalized forces (n,) of a unit force at each journal along its two radial axes: their
    static deflections join the basis (the journals' motion under their films)."""
    from ..assembly import bearing_motion

    out = []
    for bearing in journal_bearings(model):
        rows, local = bearing_motion(model, bearing)
        for axis in bearing.coefficients.journal.axes[:2]:
            load = np.zeros(model.dofs.n)
            load[rows] = local[:3].T @ axis
            out.append(load)
    return out


def films(model, V) -> Films | None:
    """The journal bearings' films on the basis ``V`` (n, r); None without journal bearings."""
    from ..assembly import bearing_motion

    journals = journal_bearings(model)
    if not journals:
        return None
    moves = []
    for bearing in journals:
        rows, local = bearing_motion(model, bearing)
        moves.append(local[:3] @ V[rows])
    data = [b.coefficients.journal for b in journals]
    return Films(ratio=np.array([model.rotor(b.rotor).speed_ratio for b in journals], dtype=float),
                 moves=np.ascontiguousarray(moves, dtype=float),
                 axes=np.ascontiguousarray([j.axes[:2] for j in data], dtype=float),
                 film=np.array([[0.5 * j.diameter, j.length, j.clearance, j.viscosity] for j in data], dtype=float),
                 names=tuple(b.name for b in journals))


def film_load(eta, deta, w, ratio, moves, axes, film):
    """The films' reduced generalized force ``sum_j B_j^T F_j(B_j eta, B_j eta', r_j w)``, (r,)
    (numba-compilable; NaN once a journal reaches its wall).

    ``eta``, ``deta`` (r,): reduced coordinates and their rates; ``w`` [rad/s]: the drive's
    speed; the rest as :class:`Films`."""
    r = eta.shape[0]
    out = np.zeros(r)
    z, z_dot, force = np.zeros(3), np.zeros(3), np.zeros(3)
    for j in range(ratio.shape[0]):
        for i in range(3):
            z[i], z_dot[i] = moves[j, i] @ eta, moves[j, i] @ deta
        _film_force(z, z_dot, ratio[j] * w, axes[j], film[j], force)
        out += force[0] * moves[j, 0] + force[1] * moves[j, 1] + force[2] * moves[j, 2]
    return out


def equilibrium(K, gravity, system_films, speed, source) -> np.ndarray:
    """Reduced coordinates (r,) where the structure's stiffness ``K`` (r, r), the films and the
    weights ``gravity`` (r,) balance, the rotors spinning at ``speed`` [rad/s]: Newton's method
    (MINPACK's hybrid) on ``K eta - F_film(eta, 0) - gravity``, from the journals centred."""
    from scipy.optimize import root

    arguments = system_films.arguments()
    still = np.zeros(len(gravity))
    scale = max(np.abs(gravity).max(initial=0.0), 1e-300)

    def residual(eta):
        return K @ eta - film_load(eta, still, speed, *arguments) - gravity

    if speed == 0.0 and np.any(gravity):
        raise InputError(f"{source}: no static equilibrium under gravity at speed 0: a journal bearing's film "
                         "carries no load when the journal does not turn; start at a running speed")
    guess = np.zeros(len(gravity))
    for share in (0.25, 0.5, 0.75, 1.0):      # the load raised in steps: each solution starts the next
        solution = root(lambda eta: residual(eta) + (1.0 - share) * gravity, guess, method="hybr", tol=1e-13)
        guess = solution.x
    worst = np.abs(residual(guess)).max()
    if not np.isfinite(worst) or worst > 1e-9 * scale:
        raise InputError(f"{source}: no static equilibrium under gravity found with the journal bearings' oil "
                         f"films at {speed:.6g} rad/s ({solution.message}): is the speed high enough for the films "
                         "to carry the weight? Use initial 'rest'")
    return guess


def wrenches(model, V, system_films, eta, deta, spin) -> np.ndarray:
    """What each journal bearing passes to its housing, (N, J, 6) [N, N m], model axes at its
    point: its constant springs and dampers ``K z + C z'`` minus the film's force on the journal
    (as the large-rotation model's ``bearing_wrench``).

    ``V`` (n, r) the basis; ``eta``, ``deta`` (N, r) reduced states; ``spin`` (N,) drive speeds [rad/s]."""
    from ..assembly import bearing_motion

    out = np.zeros((len(spin), len(system_films.names), 6))
    kernel = _COMPILED.get("film_force", _film_force)     # compiled when the run was: the same function
    force = np.zeros(3)
    for j, bearing in enumerate(journal_bearings(model)):
        rows, local = bearing_motion(model, bearing)
        reduced = local @ V[rows]                                   # (6, r)
        z, z_dot = eta @ reduced.T, deta @ reduced.T
        out[:, j] = z @ bearing.coefficients.stiffness[0].T + z_dot @ bearing.coefficients.damping[0].T
        for k in range(len(spin)):
            kernel(np.ascontiguousarray(z[k, :3]), np.ascontiguousarray(z_dot[k, :3]),
                   system_films.ratio[j] * spin[k], system_films.axes[j], system_films.film[j], force)
            out[k, j, :3] -= force
    return out


def failure(model, system_films, state, message, stopped=None, time=None) -> InputError:
    """The message of an integration that stopped with journal bearings: a journal at its wall is
    the model's limit (the film force grows without bound), with each journal's eccentricity at
    the last output time (``state``) and, where known, where the integrator stopped (``stopped`` at
    ``time`` [s]): the last output time may be long before (t = 0 for a run of a single step)."""
    from ._system import IntegrationFailed

    where = "" if stopped is None else (
        f", and where it stopped (t = {time:.6g} s): {_eccentricities(system_films, stopped)}")
    return IntegrationFailed(
        f"{model.source}: {message} with journal bearings (eccentricity at the last output time: "
        f"{_eccentricities(system_films, state)}){where}: a journal approached its bearing wall (eccentricity "
        "1), where the oil film's force grows without limit (contact is not modelled): a speed too low to "
        "carry the load, or whirl grown to the clearance. Start from initial='equilibrium' at a running speed, or stay below the "
        "oil-whirl threshold (rotordyn-modal stability)", time, stopped)


def _eccentricities(system_films, state) -> str:
    """``'[bearings.NAME] e, ...'``: each journal's eccentricity in the reduced state ``state``."""
    r = system_films.moves.shape[2]
    reached = []
    for j, name in enumerate(system_films.names):
        z = system_films.moves[j] @ state[:r]
        eccentricity = np.linalg.norm(system_films.axes[j] @ z) / system_films.film[j, 2]
        reached.append(f"[bearings.{name}] {eccentricity:.4f}")
    return ", ".join(reached)


_COMPILED: dict = {}


#: the functions :func:`compiled_film_load` compiles (``_film_force`` is called from Python too:
#: none of them may be compiled without its wrappers elsewhere, ``_fast.INTERNAL``)
FILM_FUNCTIONS = (_sommerfeld_angle, _film_force, film_load)


def compiled_film_load():
    """:func:`film_load` compiled by numba with the large-rotation model's own film kernel
    (:func:`rotordyn_modal.simulation._fast._film_force`, compiled in a namespace of its own)."""
    if "film_load" not in _COMPILED:
        namespace = compile_together(FILM_FUNCTIONS, {"np": np}, __name__)
        _COMPILED["film_load"], _COMPILED["film_force"] = namespace["film_load"], namespace["_film_force"]
    return _COMPILED["film_load"]
