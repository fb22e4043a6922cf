"""The linear system ``M q'' + (C + Omega G) q' + K q = B_f u``, ``y = C_s q``, in state space.

State ``x = [q, q']`` (``2n`` states for ``n`` generalized coordinates, see
:mod:`rotordyn_modal.model.dofs`), then six states per Maxwell branch of the mounts.
With constant coefficients ``A(Omega) = A0 + Omega A1`` with::

    A0 = [[0, I], [-M^-1 K, -M^-1 C]],   A1 = [[0, 0], [0, -M^-1 G]]

so that all speeds of a sweep are built in one broadcast. Bearings whose
coefficients depend on speed add ``[[0, 0], [-M^-1 K_b(Omega), -M^-1 C_b(Omega)]]``,
evaluated for all speeds at once (each bearing only touches its rotor's columns).
"""

from __future__ import annotations

import contextlib

import numpy as np

from ._blas import one_blas_thread
from .assembly import Matrices, bearing_motion, constant_matrices, constant_stiffness_damping, \
    dependent_bearing_matrices, excitation_columns, is_large, mass_matrix, sensor_rows, sparse_constant_matrices
from .elements.bearings import evaluate
from .errors import InputError, ModelError
from . import _arguments
from .model.dofs import frame_block
from .stiffness_spread import refuse_lost_digits
from .elements.mounts import maxwell_branch_blocks, with_branch_states

__all__ = ["SpeedLinearForm", "speed_linear_form", "kept_form", "checked_mass_inverse", "same_inertia",
           "state_matrices", "state_space", "static_solution"]

_QUANTITY_ORDER = {"displacement": 0, "receptance": 0, "velocity": 1, "mobility": 1,
                   "acceleration": 2, "accelerance": 2}


def _mass_inverse(M: np.ndarray, model) -> np.ndarray:
    """The inverse of the mass matrix, or a :class:`ModelError` when rounding leaves it singular
    (masses and inertias, with their arms, many orders of magnitude apart)."""
    try:
        with one_blas_thread(72 * M.size):          # faster than BLAS's threads (rotordyn_modal/_blas.py)
            inverse = np.linalg.inv(M)
            residual = np.abs(inverse @ M - np.eye(M.shape[0])).max()
    except np.linalg.LinAlgError:
        inverse, residual = None, np.inf
    if not residual < 1e-3:
        raise ModelError(model.source, "[stator], [[rotors]] mass and inertia", "<mass matrix>",
                         "masses and inertias (with their arms to the reference point) that leave the "
                         "mass matrix invertible in double precision; they span too many orders of magnitude")
    return inverse


def _mass_factor(M, model):
    """A sparse LU factorisation of a large model's mass matrix ``M`` (``scipy.sparse``), with the
    check of :func:`_mass_inverse` (``|M^-1 M - I|`` below 1e-3) made a block of columns at a time
    (never an ``n x n`` array), or a :class:`ModelError`."""
    import scipy.sparse.linalg

    n = M.shape[0]
    residual = np.inf
    try:
        factor = scipy.sparse.linalg.splu(M.tocsc())
        # blocks of at most 16 MB and an eighth of the columns: the check's peak stays a small
        # part of one dense n x n array whatever the size (the FRF and unbalance routes of a large
        # model hold less than half of one)
        residual, step = 0.0, max(1, min((1 << 24) // (8 * n), -(-n // 8)))
        for start in range(0, n, step):
            stop = min(n, start + step)
            part = factor.solve(M[:, start:stop].toarray())
            part[np.arange(start, stop), np.arange(stop - start)] -= 1.0
            residual = max(residual, float(np.abs(part).max()))
    except RuntimeError:          # SuperLU: "Factor is exactly singular"
        factor = None
    if not residual < 1e-3:
        raise ModelError(model.source, "[stator], [[rotors]] mass and inertia", "<mass matrix>",
                         "masses and inertias (with their arms to the reference point) that leave the "
                         "mass matrix invertible in double precision; they span too many orders of magnitude")
    return factor


def checked_mass_inverse(model) -> np.ndarray:
    """The inverse of ``model``'s mass matrix, shape (n, n) [1/kg, 1/(kg m), 1/(kg m^2)]: the
    check every analysis and the time simulation make before any work.

    Raises
    ------
    ModelError
        Masses and inertias so many orders of magnitude apart that rounding leaves the mass
        matrix singular.
    """
    return _mass_inverse(mass_matrix(model), model)


def static_solution(stiffness: np.ndarray, load: np.ndarray):
    """``x`` with ``stiffness @ x = load`` (least norm where directions are free), or None when
    the load pushes a direction that nothing holds. Rows and columns are scaled to one size
    first (N/m beside N m/rad, long arms), so that only a stiffness singular to round-off, not
    one of mixed units, counts as free. Solved by LU where the scaled stiffness is clearly
    regular (:func:`_regular_solution`), else by its SVD, which finds the free directions.

    Parameters
    ----------
    stiffness : ndarray, shape (n, n) [N/m, N/rad, N m/m, N m/rad]
    load : ndarray, shape (n,) [N, N m]

    Returns
    -------
    ndarray, shape (n,) [m, rad], or None
    """
    size = np.sqrt(np.linalg.norm(stiffness, axis=0) * np.linalg.norm(stiffness, axis=1))
    held = size > 0
    if np.any(np.abs(load[~held]) > 1e-9 * np.abs(load).max()):
        return None
    # D^-1/2 K D^-1/2, unit diagonal (K / (size_i size_j) made it 1 / K_ii: the stiffest
    # coordinates, a shaft's, looked like the free ones beside soft bearings)
    root = np.sqrt(size[held])
    scaled = stiffness[np.ix_(held, held)] / np.outer(root, root)
    right = load[held] / root
    x = np.zeros(len(load))
    regular = _regular_solution(scaled, right)
    if regular is not None:
        x[held] = regular / root
        return x
    u, values, vt = np.linalg.svd(scaled)
    # zero to round-off (numpy's matrix_rank tolerance): a fixed 1e-12 took a shaft on soft
    # bearings (100 N/m under a stiff shaft, 3e-13 of the largest, 8 digits sure) for free
    kept = values > len(values) * np.finfo(float).eps * values[0]
    if np.linalg.norm(u[:, ~kept].T @ right) > 1e-6 * np.linalg.norm(right):
        return None
    x[held] = (vt[kept].T @ ((u[:, kept].T @ right) / values[kept])) / root
    return x


#: the least reciprocal condition number (LAPACK's 1-norm estimate) of the scaled stiffness
#: solved by LU in :func:`static_solution`, over ``n eps``: a thousand times clear of the
#: singular values the SVD would count as zero (``n eps`` of the largest), so that LU and SVD
#: give the same solution to round-off wherever LU is used
_REGULAR_MARGIN = 1e3


def _regular_solution(scaled: np.ndarray, right: np.ndarray):
    """``x`` with ``scaled @ x = right`` by LU (a tenth or less of the SVD's work), or None where
    ``scaled`` is singular or near it (its free directions are the SVD's to find) or not finite.

    Parameters
    ----------
    scaled : ndarray, shape (m, m)
        The stiffness scaled to unit size (:func:`static_solution`) [-].
    right : ndarray, shape (m,)
        The load scaled alike.
    """
    import warnings

    import scipy.linalg

    if not len(right) or not (np.isfinite(scaled).all() and np.isfinite(right).all()):
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)      # an exact zero pivot: rcond 0 below
        lu, pivots = scipy.linalg.lu_factor(scaled, check_finite=False)
    rcond, info = scipy.linalg.lapack.dgecon(lu, np.linalg.norm(scaled, 1), norm="1")
    if info != 0 or not rcond > _REGULAR_MARGIN * len(right) * np.finfo(float).eps:
        return None
    return scipy.linalg.lu_solve((lu, pivots), right, check_finite=False)


class SpeedLinearForm:
    """The state matrix ``A(Omega) = A0 + Omega A1 (+ A_b(Omega))`` with M and its inverse.

    A model of more than :data:`~rotordyn_modal.assembly.SPARSE_DOF` coordinates keeps its
    matrices sparse (``sparse``) and its mass matrix as a sparse LU factorisation: the dense
    ``matrices`` and ``mass_inverse`` are made only where an analysis asks for them (the state
    matrices of every root, python-control), never by the lowest modes, FRFs or unbalance
    responses (docs/theory.md §17, "Large models: what grows with n").

    Parameters
    ----------
    model : Model
    like : SpeedLinearForm, optional
        The form of a model with the very same bodies and coordinates (a study's variant
        and its base, see :meth:`~rotordyn_modal.model.machine.Model.same_bodies`): its ``M``, ``G``
        and ``M^-1`` are taken, not computed again (they are the same numbers).

    Attributes
    ----------
    matrices : Matrices
        ``M, C, G, K`` of the parts that do not depend on speed, dense (n, n) each (of a large
        model made from ``sparse`` on first use).
    sparse : Matrices or None
        The same as ``scipy.sparse`` CSR matrices for a large model, else None.
    n_dof : int
        Number of generalized coordinates n.
    A0, A1 : ndarray, shape (n_states, n_states)
    mass_inverse : ndarray, shape (n, n)
        (Of a large model made on first use from the factorisation.)
    speed_dependent : bool
        True when bearing coefficients depend on speed (then A is not linear in speed).
    branch_blocks : ndarray, shape (n_branches, 6, 6)
        The mounts' Maxwell branches' stiffness at the reference point [N/m, ...] (the stator's
        six motions; ``branch_stiffness`` (n_branches, n, n) places them, made on first use).
    branch_times : ndarray, shape (n_branches,)
        Their relaxation times [s].
    """

    def __init__(self, model, like: "SpeedLinearForm | None" = None):
        self.model = model
        self.sparse = self._dense = self._inverse = self.mass_factor = None
        if like is not None and same_inertia(like.model, model) and like.sparse is not None:
            self.sparse = sparse_constant_matrices(model)._replace(M=like.sparse.M, G=like.sparse.G)
            self.mass_factor = like.mass_factor
        elif like is not None and same_inertia(like.model, model):
            K, C = constant_stiffness_damping(model)
            self._dense = Matrices(M=like.matrices.M, C=C, G=like.matrices.G, K=K)
            self._inverse = like.mass_inverse
        elif is_large(model):
            self.sparse = sparse_constant_matrices(model)
            self.mass_factor = _mass_factor(self.sparse.M, model)
        else:
            self._dense = constant_matrices(model)
            self._inverse = _mass_inverse(self._dense.M, model)
        refuse_lost_digits(model)
        self.n_dof = model.dofs.n if self._dense is None else self._dense.M.shape[0]
        # the Maxwell branches as 6x6 blocks on the stator's motion: their n x n arrays
        # (``branch_stiffness``) are made only where an analysis asks for them
        self.branch_blocks, self.branch_times = maxwell_branch_blocks(model)
        self._branch_stiffness = None
        self._states = None        # (A0, A1, branch state names), made on first use
        self._dependent = _dependent_bearings(model, self._inverse_columns)
        self.speed_dependent = bool(self._dependent)

    @property
    def matrices(self) -> Matrices:
        """``M, C, G, K`` dense (n, n) each; a large model's made from its sparse ones on first use."""
        if self._dense is None:
            self._dense = Matrices(*(matrix.toarray() for matrix in self.sparse))
        return self._dense

    @property
    def branch_stiffness(self) -> np.ndarray:
        """The Maxwell branches' stiffness ``B_SP K_b B_SP^T`` on the stator's coordinates,
        (n_branches, n, n) [N/m, ...], made from ``branch_blocks`` (n_branches, 6, 6) on first use."""
        if self._branch_stiffness is None:
            self._branch_stiffness = frame_block(self.model, self.branch_blocks)
        return self._branch_stiffness

    @property
    def mass_inverse(self) -> np.ndarray:
        """``M^-1`` (n, n); a large model's solved from its factorisation on first use."""
        if self._inverse is None:
            self._inverse = self.mass_factor.solve(np.eye(self.n_dof))
        return self._inverse

    def _inverse_columns(self, rows) -> np.ndarray:
        """The columns ``rows`` (a slice or indices) of ``M^-1``, (n, k), without the whole inverse
        of a large model."""
        if self._inverse is not None:
            return self._inverse[:, rows]
        index = np.arange(self.n_dof)[rows]
        unit = np.zeros((self.n_dof, len(index)))
        unit[index, np.arange(len(index))] = 1.0
        return self.mass_factor.solve(unit)

    @property
    def A0(self) -> np.ndarray:
        """``A0`` (n_states, n_states), made on first use (the lowest modes and the FRFs of a
        large model work on M, C, G, K and never build the 2n x 2n state matrices)."""
        return self._state_matrices()[0]

    @property
    def A1(self) -> np.ndarray:
        """``A1`` (n_states, n_states), made on first use."""
        return self._state_matrices()[1]

    @property
    def branch_state_names(self) -> list:
        """Names of the Maxwell branches' states (see ``with_branch_states``)."""
        return self._state_matrices()[2]

    def _state_matrices(self):
        """``A0``, ``A1`` and the branch states' names, made once: ``[[0, I], [-M^-1 K, -M^-1 C]]``
        and ``[[0, 0], [0, -M^-1 G]]``, with the rubber mounts' Maxwell branches' 6 first-order
        states each after ``q, q'``."""
        if self._states is None:
            M, C, G, K = self.matrices
            n = self.n_dof
            with one_blas_thread(72 * n * n):       # as the solves that follow (rotordyn_modal/_blas.py)
                m_inv = self.mass_inverse
                A0 = np.zeros((2 * n, 2 * n))
                A0[:n, n:] = np.eye(n)
                A0[n:, :n] = -m_inv @ K
                A0[n:, n:] = -m_inv @ C
                A1 = np.zeros((2 * n, 2 * n))
                A1[n:, n:] = -m_inv @ G
                A0, _, names = with_branch_states(self.model, A0, np.zeros((2 * n, 0)), m_inv)
            extra = A0.shape[0] - A1.shape[0]
            if extra:
                A1 = np.pad(A1, ((0, extra), (0, extra)))
            self._states = A0, A1, names
        return self._states

    @property
    def n_states(self) -> int:
        """2n, plus 6 per Maxwell branch."""
        return 2 * self.n_dof + 6 * len(self.branch_times)

    def at(self, speeds) -> np.ndarray:
        """State matrices at ``speeds`` [rad/s].

        Parameters
        ----------
        speeds : array_like, shape (N,) or scalar

        Returns
        -------
        ndarray, shape (N, n_states, n_states) (or (n_states, n_states) for a scalar speed)
        """
        speeds = np.asarray(speeds, dtype=float)
        out = self.A0 + speeds[..., None, None] * self.A1
        if self._dependent:
            n = self.n_dof
            flat = out.reshape((-1,) + out.shape[-2:])
            with one_blas_thread(72 * n * n):       # BLAS's threads would spin on a shared machine
                for rows, stiffness, damping in self._bearing_parts(np.ravel(speeds)):
                    flat[:, n:2 * n, rows] -= stiffness
                    flat[:, n:2 * n, n + rows.start:n + rows.stop] -= damping
        return out

    def stiffness_at(self, speeds) -> np.ndarray:
        """Stiffness ``K(Omega)`` [N/m, ...], shape (N, n, n) (or (n, n) when constant)."""
        if not self._dependent:
            return self.matrices.K
        return self.matrices.K + dependent_bearing_matrices(self.model, speeds)[0]

    def damping_at(self, speeds) -> np.ndarray:
        """Damping ``C(Omega)`` without the gyroscopic part, shape (N, n, n) (or (n, n))."""
        if not self._dependent:
            return self.matrices.C
        return self.matrices.C + dependent_bearing_matrices(self.model, speeds)[1]

    def pencil_at(self, speeds) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness ``K(Omega)`` and damping ``C(Omega)`` (without the gyroscopic part) from one
        evaluation of the speed-dependent bearings (:meth:`stiffness_at` and :meth:`damping_at`
        each evaluate them whole).

        Parameters
        ----------
        speeds : array_like, shape (N,)
            Speeds [rad/s].

        Returns
        -------
        stiffness, damping : ndarray, shape (N, n, n) each (or (n, n) when constant)
            [N/m, ...] and [N s/m, ...].
        """
        if not self._dependent:
            return self.matrices.K, self.matrices.C
        bearing_k, bearing_c = dependent_bearing_matrices(self.model, speeds)
        return self.matrices.K + bearing_k, self.matrices.C + bearing_c

    def pattern(self, sparse: bool = False):
        """Where ``M``, ``C(Omega)``, ``G`` and ``K(Omega)`` may be nonzero at any speed: the
        constant parts' nonzero entries and each speed-dependent bearing's rotor block.

        Parameters
        ----------
        sparse : bool
            As a ``scipy.sparse`` matrix (a large model's: no ``n x n`` array).

        Returns
        -------
        ndarray of bool, shape (n, n), or scipy.sparse.csc_matrix of bool (n, n)
        """
        if sparse and self.sparse is not None:
            return self._sparse_pattern()
        if self.sparse is not None:       # a large model's, without its dense matrices
            M, C, G, K = self.sparse
            nonzero = ((abs(M) + abs(C) + abs(G) + abs(K)) != 0).toarray()
        else:
            M, C, G, K = self.matrices
            nonzero = (M != 0) | (C != 0) | (G != 0) | (K != 0)
        for rows, *_ in self._dependent:
            nonzero[rows, rows] = True
        return nonzero

    def _sparse_pattern(self):
        """:meth:`pattern` of a large model as a ``scipy.sparse.csc_matrix`` of bool (n, n)."""
        import scipy.sparse

        M, C, G, K = self.sparse
        found = (abs(M) + abs(C) + abs(G) + abs(K)).tocoo()
        keep = found.data != 0
        rows, cols = [found.row[keep]], [found.col[keep]]
        for where, _, moves, *_ in self._dependent:
            # the coordinates the bearing's relative motion touches (not its rotor's every one)
            block = np.arange(self.n_dof)[where][np.any(moves != 0, axis=0)]
            rows.append(np.repeat(block, len(block)))
            cols.append(np.tile(block, len(block)))
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        pattern = scipy.sparse.csc_matrix((np.ones(len(rows), bool), (rows, cols)), shape=(self.n_dof, self.n_dof))
        pattern.sum_duplicates()
        pattern.sort_indices()
        return pattern

    def _bearing_terms(self, speeds):
        """Per speed-dependent bearing: rotor rows, ``M^-1 E^T``, E, K_b(N), C_b(N)."""
        for rows, left, moves, coefficients, ratio, where in self._dependent:
            k, c = evaluate(coefficients, ratio * speeds, where)
            yield rows, left, moves, k, c

    def _bearing_parts(self, speeds):
        """The speed-dependent bearings' parts of the state matrices' lower rows at ``speeds`` (N,):
        ``(rows, M^-1 E^T K_b E, M^-1 E^T C_b E)`` ((N, n, r) each) per slice ``rows`` of rotor
        coordinates, the bearings on one rotor summed by one product ``[M^-1 E_b^T K_b] [E_b]``
        through all their motions: one (N, n, r) array per rotor, not one per bearing (ROSS's
        compressor_example, 14 seals on one shaft of 224 coordinates: 12 -> 3 ms at 3 speeds)."""
        groups = {}
        for rows, left, moves, k, c in self._bearing_terms(speeds):
            group = groups.setdefault((rows.start, rows.stop), ([], [], []))
            group[0].append(left @ k)
            group[1].append(left @ c)
            group[2].append(moves)
        for (start, stop), (stiffness, damping, moves) in groups.items():
            right = np.concatenate(moves, axis=0)
            yield (slice(start, stop), np.concatenate(stiffness, axis=-1) @ right,
                   np.concatenate(damping, axis=-1) @ right)


def _dependent_bearings(model, inverse_columns):
    """``(rows, M^-1[:, rows] E^T, E, coefficients, speed ratio, name)`` of each bearing
    whose coefficients depend on speed; empty when none does (``inverse_columns(rows)``:
    those columns of ``M^-1``)."""
    terms = []
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            continue
        rows, moves = bearing_motion(model, bearing)
        left = inverse_columns(rows) @ moves.T
        terms.append((rows, left, moves, bearing.coefficients,
                      model.rotor(bearing.rotor).speed_ratio, f"{model.source}: [bearings.{bearing.name}]"))
    return terms


def speed_linear_form(model, like: SpeedLinearForm | None = None) -> SpeedLinearForm:
    """The speed-dependent state matrix of ``model``; see :class:`SpeedLinearForm`. Inside a
    :func:`kept_form` block of this very model, the block's one form."""
    kept = _KEPT.get(id(model))
    if kept is None or kept[0] is not model:
        return SpeedLinearForm(model, like)
    if kept[1] is None:
        kept[1] = SpeedLinearForm(model, like)
    return kept[1]


#: the forms of :func:`kept_form` blocks running: ``id(model) -> [model, form or None]``
_KEPT = {}


@contextlib.contextmanager
def kept_form(model):
    """A block in which :func:`speed_linear_form` of this very ``model`` object gives one form,
    built on first use and let go at the block's end: a command whose steps each build it
    (``critical-speeds``: the sweep, the mode numbers, the terminal's round-off) builds it once,
    and no result keeps it."""
    key = id(model)
    if key in _KEPT:                      # an outer block keeps it already
        yield
        return
    _KEPT[key] = [model, None]
    try:
        yield
    finally:
        del _KEPT[key]


def same_inertia(a, b) -> bool:
    """Models whose mass and gyroscopic matrices are the same numbers without computing them:
    the very same bodies (:meth:`~rotordyn_modal.model.machine.Model.same_bodies`) and coordinates."""
    return a is b or (a.dofs is b.dofs and a.same_bodies(b))


def state_matrices(model, speeds) -> np.ndarray:
    """State matrices ``A(Omega)`` for many speeds at once.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s].

    Returns
    -------
    ndarray, shape (N, n_states, n_states) [1/s, 1/s^2]
    """
    return SpeedLinearForm(model).at(speeds)


def state_space(model, speed: float, quantity: str = "displacement", inputs=None, outputs=None):
    """python-control ``StateSpace`` of the machine at one speed.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s]; negative reverses every rotor's spin.
    quantity : {'displacement', 'velocity', 'acceleration'}
        What the sensors measure (also accepted: 'receptance', 'mobility', 'accelerance').
    inputs, outputs : list of str, optional
        Excitation and sensor names (default: all, in model order).

    Returns
    -------
    control.StateSpace
        Inputs named after the ``[[excitations]]`` [N or N m], outputs after the
        ``[[sensors]]`` [m, m/s or m/s^2], states ``q0..q{n-1}, dq0..dq{n-1}`` (the
        generalized coordinates ``model.dofs.names``), then six states per Maxwell
        branch of the mounts (see :func:`rotordyn_modal.elements.mounts.with_branch_states`).

    Raises
    ------
    InputError
        A ``speed`` that is not one finite number (of magnitude at most 1e30), an unknown
        quantity or name, or outputs without an input (sensors and no excitation, or
        ``inputs=[]``: python-control has no such system).
    """
    import control

    speed = _arguments.speed(speed)
    if quantity not in _QUANTITY_ORDER:
        raise InputError(f"quantity {quantity!r}: expected one of {', '.join(_QUANTITY_ORDER)}")
    columns = excitation_columns(model, inputs)
    rows = sensor_rows(model, outputs)
    _refuse_outputs_without_inputs(model, inputs, rows.shape[0], columns.shape[1])
    form = SpeedLinearForm(model)
    n = form.n_dof
    a = form.at(speed)
    b = np.zeros((form.n_states, columns.shape[1]))
    b[n:2 * n] = form.mass_inverse @ columns
    branch_states = form.branch_state_names
    c, d = _output_matrices(a, b, rows, _QUANTITY_ORDER[quantity])
    input_names = [x.name for x in _named(model.excitations, inputs)]
    output_names = [s.name for s in _named(model.sensors, outputs)]
    states = [f"q{i}" for i in range(n)] + [f"dq{i}" for i in range(n)] + branch_states
    return control.ss(a, b, c, d, inputs=input_names or None, outputs=output_names or None,
                      states=states, name=model.name or None)


def _refuse_outputs_without_inputs(model, inputs, n_outputs: int, n_inputs: int) -> None:
    """python-control has no system of outputs and no input (its ``StateSpace`` fails on the
    empty D matrix, ``ControlDimension``): refuse it in one line, naming what to add."""
    if n_outputs and not n_inputs:
        given = "" if inputs is None else f"inputs = {list(inputs) if not isinstance(inputs, str) else inputs!r}: "
        why = "none chosen" if inputs is not None else "the model has no [[excitations]]"
        raise InputError(f"{model.source}: {given}a state-space model of {n_outputs} output(s) and no input ({why}): "
                         "expected at least one input, an [[excitations]] table of the model (python-control "
                         "has no system of outputs without inputs), or outputs=[]")


def _output_matrices(a, b, rows, order: int):
    """C and D giving the ``order``-th time derivative of the sensor displacements."""
    n = rows.shape[1]
    selector = np.hstack([rows, np.zeros((rows.shape[0], a.shape[0] - n))])  # displacement: C x
    c = selector
    d = np.zeros((rows.shape[0], b.shape[1]))
    for _ in range(order):
        c, d = c @ a, c @ b  # d/dt (C x + D u) with u held: C A x + C B u
    return c, d


def _named(items, names):
    if names is None:
        return list(items)
    names = [names] if isinstance(names, str) else names
    by_name = {i.name: i for i in items}
    return [by_name[n] for n in names]
