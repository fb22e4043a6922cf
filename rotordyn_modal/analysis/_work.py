"""The CPU time of an analysis that solves every root of the state matrix at many speeds
(Campbell diagrams, critical speeds, stability), estimated from the model's size before the
first eigen-solution, and the refusal of work above a limit, with the estimate.

The estimate adds three parts (``docs/theory.md``, "How long a sweep takes"):

- the sweep: one dense eigen-solution with vectors per speed (and per value of a map),
  ``t_eig(n_states)`` (:func:`._cost.eig_seconds`): a random matrix of the model's states, or of
  ``_cost._CALIBRATION_STATES`` for larger models, is solved, timed in CPU seconds with one BLAS
  thread (as every dense eigen-solution runs), and scaled by the cube of the size;
- the brackets the critical speeds sweep again (those crowded with crossings among close roots:
  ``_SUB_SPEEDS - 2`` more eigen-solutions each, :func:`swept_again`: an estimate, 0.75-3.2 times
  the brackets swept on gear chains of 20-500 rotors; a jump's sweeps are not foreseen);
- the critical speeds: the crossings expected (every oscillating mode of the undamped machine
  at rest, frequency ``w``, with every source's order line ``slope |Omega|`` that reaches ``w``
  inside the speed range) times the cost of one crossing, ``_COORDINATE_SECONDS`` per
  coordinate (residual inverse iteration on the pencil, its whirl ratio and fingerprint:
  measured 2.8 ms at 126, 6.5 ms at 406, 25-35 ms at 2,006 coordinates), plus a dense
  factorisation of the pencil per crossing where the pencil is factored dense (below
  ``_pencils.SPARSE_DOF`` coordinates) and ``_DENSE_ROOTS`` eigenvalue-only solutions where its
  candidates are every root (up to ``_pencils.NEAREST_ROOTS_DOF`` coordinates, but not where the
  mode is picked among Ritz pairs: constant coefficients from ``_crossing_roots._RITZ_DOF``);
- the numbers ``modes --speed`` gives the critical speeds' modes (``critical-speeds``' column
  ``mode_at_speed``): the roots solved at a share ``_NUMBERS_SHARE`` of the crossings, each the
  eigenvalues alone (``_cost.EIGVALS_SHARE`` of a solution with vectors).

Small models are passed by a bound of the same terms with a pessimistic eigen-solution and no
measurement at all (:func:`_quick_bound`). The limit is ``DEFAULT_MINUTES`` of CPU time; the
environment variable ``ROTORDYN_MODAL_MAX_CPU_MINUTES`` sets another (``inf``: no check); inside
:func:`._cost.long_work_allowed` (the command line's ``--allow-long``) nothing is refused for its
CPU time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from . import _batches, _cost
# the size-only part lives in _cost (the lowest modes' fallback reads it without this module)
from ._cost import _PESSIMISTIC, DEFAULT_MINUTES, ENVIRONMENT, limit_seconds
from ._cost import duration as _duration

__all__ = ["ENVIRONMENT", "DEFAULT_MINUTES", "Work", "limit_seconds", "eig_seconds", "expected_crossings",
           "swept_again", "estimate", "refuse_long_work"]

#: CPU seconds per coordinate of one crossing's refinement (measured on the gear chains of
#: tests/test_large_machine_cli.py: 126, 406 and 2,006 coordinates; 2 cores shared by several jobs)
_COORDINATE_SECONDS = 15e-6
#: a dense factorisation of the pencil costs about this share of a dense eigen-solution
_FACTOR_SHARE = 1 / 75
#: eigenvalue-only solutions of the whole state matrix per crossing where the pencil has at most
#: ``_pencils.NEAREST_ROOTS_DOF`` coordinates (its candidates are all the roots, not the nearest
#: by shift-invert Arnoldi): measured 0.49 on the 20-rotor gear chain (86 coordinates, 1,889
#: crossings at 22 speeds)
_DENSE_ROOTS = 0.5
#: share of the crossings whose mode number is solved for (measured on grids of 11 speeds: 0.36
#: on the 126-coordinate chain, 0.53 on the 406-coordinate one; 0.16 on a grid 6 times finer,
#: none on the bundled examples)
_NUMBERS_SHARE = 0.5
#: models up to this many coordinates get their undamped frequencies by a dense symmetric
#: eigen-solution; larger ones from the diagonals of K and M (an uncoupled estimate)
_DENSE_FREQUENCIES_DOF = 1200


#: the eigen-solution timed (tests replace it)
_timed_eig = _cost._timed_eig


def eig_seconds(n_states: int) -> float:
    """CPU seconds of one dense eigen-solution (with vectors) of ``n_states`` states on this
    machine, one BLAS thread (:func:`._cost.eig_seconds`, timed by :data:`_timed_eig`)."""
    return _cost.eig_seconds(n_states, _timed_eig)


def _undamped_frequencies(model, speed: float) -> np.ndarray | None:
    """Natural frequencies of the undamped machine [rad/s] (n,), its gyroscopic terms left out,
    its bearings' coefficients at ``speed`` [rad/s]: all of ``K, M`` up to
    ``_DENSE_FREQUENCIES_DOF`` coordinates, else ``sqrt(K_ii / M_ii)``; None where the
    matrices cannot be had at that speed (the caller then counts every mode)."""
    import scipy.linalg

    from ..errors import ModelError

    from ..assembly import is_large, sparse_bearing_matrices, sparse_constant_matrices

    try:
        if is_large(model):        # the diagonals alone, from the sparse matrices (never n x n)
            M, _, _, K = sparse_constant_matrices(model)
            if model.speed_dependent:
                K = K + sparse_bearing_matrices(model, speed, dependent_only=True)[0]
            return np.sqrt(np.clip(K.diagonal() / M.diagonal(), 0.0, None))
        M, _, _, K = model.matrices(speed)
    except (InputError, ModelError):
        return None
    if len(M) <= _DENSE_FREQUENCIES_DOF:
        try:
            with _batches.one_blas_thread(72 * len(M) ** 2):          # faster than BLAS's threads
                squares = scipy.linalg.eigh(K, M, eigvals_only=True)
        except (np.linalg.LinAlgError, ValueError):
            squares = np.diag(K) / np.diag(M)
    else:
        squares = np.diag(K) / np.diag(M)
    return np.sqrt(np.clip(squares, 0.0, None))


def _line_slopes(model, orders) -> np.ndarray:
    """Excitation [rad/s] per |reference speed| [rad/s] of every source's every order (L,)."""
    from .critical_speeds import excitation_sources

    multipliers = excitation_sources(model).multipliers
    return (np.abs(np.asarray(orders, dtype=float))[:, None] * multipliers[None, :]).ravel()


def expected_crossings(model, speeds, orders, frequencies=False) -> int:
    """Crossings of the undamped machine's frequencies at rest with every order line over
    ``speeds`` [rad/s]: a line of slope ``s`` meets a frequency ``w`` once on each side of zero
    where ``s |Omega|`` passes ``w`` inside that side's range of speeds (the matrices taken at
    the middle speed of the range; every mode with every line where they cannot be had).
    ``frequencies``: :func:`_undamped_frequencies` where the caller has them."""
    slopes = _line_slopes(model, orders)
    if not len(slopes) or not len(orders):
        return 0
    speeds = np.asarray(speeds, dtype=float)
    if frequencies is False:
        frequencies = _undamped_frequencies(model, float(speeds[len(speeds) // 2]))
    if frequencies is None:
        return 2 * model.dofs.n * len(slopes)
    frequencies = np.sort(frequencies[frequencies > 0])
    count = 0
    for side in (speeds[speeds >= 0], -speeds[speeds <= 0]):
        if len(side) < 2:
            continue
        low, high = slopes * side.min(), slopes * side.max()
        count += int((np.searchsorted(frequencies, high) - np.searchsorted(frequencies, low)).sum())
    return count


def swept_again(model, speeds, orders, frequencies=False) -> int:
    """Eigen-solutions of the brackets the critical speeds would sweep again: a bracket of the
    grid ``speeds`` [rad/s] that holds at least ``critical_speeds._CROWDED`` crossings among
    close roots is swept again at ``_SUB_SPEEDS`` speeds, ``_SUB_SPEEDS - 2`` more solutions of
    every root (:func:`.critical_speeds._crowded`); counted here from the crossings each bracket
    is expected to hold (as :func:`expected_crossings`), every one taken as among close roots.
    ``frequencies``: :func:`_undamped_frequencies` where the caller has them.

    An estimate, not a bound, and not made exact: which brackets are crowded depends on which
    crossings are isolated and on the frequencies at speed (gyroscopic and bearing terms), both
    known only from the sweep's roots and shapes. Counted against the brackets the critical speeds
    swept again (``_crossings_in`` counted by depth and cause): gear chains of 20 rotors on
    bearings at 31 speeds 14 counted / 11 swept, 40 rotors (4 on bearings) at 31 speeds 16 / 5, 40
    on bearings at 11 and 41 speeds 6 / 8 and 22 / 23, 100 at 11 speeds 10 / 8, 500 at 11 speeds
    10 / 8; the bundled examples (their documented grids) 0 / 0. Nothing deeper is left out of
    the crowded count: a bracket is judged crowded on the sweep's own grid only
    (:func:`.critical_speeds._crowded`), so a sub-sweep's brackets are never swept again for
    being crowded. What is left out is the sweeps of a jump (two roots veering between two grid
    speeds, and the sub-sweeps' own jumps up to ``_SUB_DEPTH`` levels deep): none in any of those
    runs, and not foreseeable from the sizes; counting every bracket as jumping at every level
    would count ``1 + 8 + 64`` sub-sweeps per bracket and refuse work that runs in minutes."""
    from .critical_speeds import _CROWDED, _SUB_SPEEDS

    slopes = _line_slopes(model, orders)
    speeds = np.asarray(speeds, dtype=float)
    if len(speeds) < 2 or not len(slopes) or not len(orders):
        return 0
    if frequencies is False:
        frequencies = _undamped_frequencies(model, float(speeds[len(speeds) // 2]))
    if frequencies is None:
        return (len(speeds) - 1) * (_SUB_SPEEDS - 2)
    frequencies = np.sort(frequencies[frequencies > 0])
    a, b = np.abs(speeds[:-1]), np.abs(speeds[1:])
    low = np.where(speeds[:-1] * speeds[1:] < 0, 0.0, np.minimum(a, b))      # a bracket across zero
    high = np.maximum(a, b)
    counts = (np.searchsorted(frequencies, slopes[:, None] * high[None])
              - np.searchsorted(frequencies, slopes[:, None] * low[None])).sum(axis=0)
    return int((counts >= _CROWDED).sum()) * (_SUB_SPEEDS - 2)


@dataclass(frozen=True)
class Work:
    """An analysis's estimated CPU time [s], by part."""

    n_dof: int
    n_states: int
    solutions: int
    """Eigen-solutions of the sweep (speeds x values of a map)"""
    crossings: int
    sweep_seconds: float
    crossing_seconds: float
    numbers_seconds: float = 0.0
    swept_again: int = 0
    """Eigen-solutions of the brackets swept again (:func:`swept_again`), in ``sweep_seconds``"""

    @property
    def seconds(self) -> float:
        return self.sweep_seconds + self.crossing_seconds + self.numbers_seconds

    def text(self) -> str:
        """``about 9.6 h of CPU time (11 eigen-solutions of 4,012 states: 12 min; about 1,000,000
        crossings to refine: 9.4 h)``."""
        again = f" and {self.swept_again:,} more in brackets swept again" if self.swept_again else ""
        parts = [f"{self.solutions:,} eigen-solution{'s' if self.solutions != 1 else ''} of {self.n_states:,} "
                 f"states{again}: {_duration(self.sweep_seconds)}"]
        if self.crossings:
            parts.append(f"about {self.crossings:,} crossings to refine: {_duration(self.crossing_seconds)}")
        if self.numbers_seconds:
            parts.append(f"their mode numbers: {_duration(self.numbers_seconds)}")
        return f"about {_duration(self.seconds)} of CPU time ({'; '.join(parts)})"


def _n_states(model) -> int:
    """States of the model's state matrix: twice the coordinates, plus Maxwell branches' own."""
    from ..linear_system import speed_linear_form

    if any(suspension.maxwell_time is not None for suspension in model.suspensions):
        return speed_linear_form(model).n_states
    return 2 * model.dofs.n


def _crossing_seconds(n_dof: int, n_states: int, eig: float, ritz: bool = False) -> float:
    """CPU seconds of one crossing's refinement (see the module's notes); ``ritz``: its mode is
    picked among Ritz pairs (:func:`_picks_from_ritz_pairs`), no root of the whole state matrix
    solved."""
    from . import _pencils

    dense = eig * _FACTOR_SHARE if n_dof < _pencils.SPARSE_DOF else 0.0
    if n_dof <= _pencils.NEAREST_ROOTS_DOF and not ritz:       # every root of the state matrix a candidate
        dense += _DENSE_ROOTS * _cost.EIGVALS_SHARE * eig
    return _COORDINATE_SECONDS * n_dof + dense


def _picks_from_ritz_pairs(model, n_states: int) -> bool:
    """Whether the critical speeds of ``model`` (one model, ``n_states`` states) pick a crossing's
    mode among Ritz pairs of the sweep's shapes rather than among every root of the state matrix
    (``_crossing_roots._by_ritz``: constant coefficients, no Maxwell branches, more than
    ``_crossing_roots._RITZ_DOF`` coordinates; the 11-, 15- and 20-rotor gear chains, 50-86
    coordinates, solve no state matrix whole for their 669-1,983 crossings)."""
    from . import _crossing_roots

    return (_crossing_roots._RITZ_ROOTS > 0 and not model.speed_dependent and n_states == 2 * model.dofs.n
            and _crossing_roots.ritz_sized(model.dofs.n))


def estimate(model, speeds, orders=(), critical=True, numbers=False, solutions=None) -> Work:
    """The CPU time of a sweep of ``model`` over ``speeds`` [rad/s] (``solutions``
    eigen-solutions, default one per speed), of its critical speeds with ``orders`` when
    ``critical``, and of their mode numbers when ``numbers``."""
    n_dof = model.dofs.n
    n_states = _n_states(model)
    eig = eig_seconds(n_states)
    solutions = len(speeds) if solutions is None else solutions
    crossings = again = 0
    if critical:
        speeds = np.asarray(speeds, dtype=float)
        frequencies = _undamped_frequencies(model, float(speeds[len(speeds) // 2])) if len(speeds) else None
        crossings = expected_crossings(model, speeds, orders, frequencies)
        again = swept_again(model, speeds, orders, frequencies)
    per = _crossing_seconds(n_dof, n_states, eig, _picks_from_ritz_pairs(model, n_states))
    return Work(n_dof, n_states, solutions, crossings, (solutions + again) * eig, crossings * per,
                crossings * _NUMBERS_SHARE * _cost.EIGVALS_SHARE * eig if numbers else 0.0, again)


def _quick_bound(model, speeds, orders, critical, numbers, solutions) -> float:
    """A pessimistic bound of :func:`estimate` [s] from the sizes alone (no timing, no
    matrices): every mode crossing every line."""
    n_dof = model.dofs.n
    n_states = 2 * n_dof + 6 * len(model.suspensions)
    eig = _PESSIMISTIC * n_states ** 3
    lines = len(_line_slopes(model, orders)) if critical else 0
    crossings = 2 * n_dof * lines
    numbers_seconds = crossings * _NUMBERS_SHARE * _cost.EIGVALS_SHARE * eig if numbers else 0.0
    from .critical_speeds import _SUB_SPEEDS

    again = (_SUB_SPEEDS - 2) * max(len(speeds) - 1, 0) if lines else 0      # every bracket swept again
    return ((solutions + again) * eig + crossings * 3 * _crossing_seconds(n_dof, n_states, eig)
            + numbers_seconds)


def refuse_long_work(model, speeds, orders=(), critical=True, numbers=False, solutions=None,
                     advice="", memory=False, what="a Campbell sweep") -> Work | None:
    """Refuse, before its first eigen-solution, an analysis estimated (:func:`estimate`) to take
    longer than :func:`limit_seconds`, unless long work is allowed
    (:func:`._cost.long_work_is_allowed`: ``--allow-long``); returns the estimate where one was
    made (None where the quick bound already passed it, or long work is allowed). With ``memory``,
    a Campbell sweep whose arrays would not fit is refused first (:func:`.campbell.campbell`'s own
    check, from the sizes; where long work is allowed, that check refuses it at its start), the
    message naming it ``what`` (``stability``'s sweep keeps the same arrays).

    Raises
    ------
    InputError
        ``MODEL: this analysis of N coordinates would take about 9.6 h of CPU time (...), more than the
        limit of 30 min: ADVICE, or add --allow-long (ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit)``.
    """
    if _cost.long_work_is_allowed():
        return None
    if memory:                              # what cannot fit is refused first: no option runs it
        from .campbell import _refuse_sizes_that_cannot_fit

        _refuse_sizes_that_cannot_fit(model.dofs.n, _n_states(model), len(speeds), 1, critical,
                                      f"{model.source}: " if getattr(model, "source", None) else "", what)
    limit = limit_seconds()
    solutions = len(speeds) if solutions is None else solutions
    if limit == float("inf") or _quick_bound(model, speeds, orders, critical, numbers, solutions) <= limit:
        return None
    work = estimate(model, speeds, orders, critical, numbers, solutions)
    if work.seconds > limit:
        where = f"{model.source}: " if getattr(model, "source", None) else ""
        raise InputError(f"{where}this analysis of {work.n_dof:,} coordinates would take {work.text()}, more than the "
                         f"limit of {_duration(limit)}: {advice + ', ' if advice else ''}or add --allow-long "
                         f"({ENVIRONMENT} sets the limit)")
    return work
