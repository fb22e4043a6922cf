"""Several models of the same structure solved as one batch: the variants of a study.

A parameter study changes values, never the structure, so its variants share their
coordinates and states. :class:`Stack` holds their state-matrix forms and whirl forms
stacked on a leading variant axis, so that a sweep of every variant of a chunk is one
batched LAPACK call and its post-processing (selection, normalisation, tracking, whirl) one
set of array operations instead of one per variant. A single model is a stack of one: the
single analyses and the studies run the same code, so a study's variant equals the single
analysis of its model bit for bit (critical speeds: up to 48 coordinates, see
:meth:`Pencils.products`; beyond, to round-off).
"""

from __future__ import annotations

import numpy as np

from ..linear_system import same_inertia, speed_linear_form
from . import _batches, _eigensolve, _pencils, _vectors, _whirl

__all__ = ["Stack", "Pencils"]


class Stack:
    """The forms of ``V`` models with the same coordinates and states.

    Parameters
    ----------
    models : sequence of Model

    Attributes
    ----------
    forms : list of SpeedLinearForm
    whirl : WhirlForms
        Each form stacked, shape (V, n, n).
    M, C, G, K : ndarray, shape (V, n, n)
        The constant parts (speed-dependent bearings come from each form).
    factor : ndarray, shape (V, n, n)
        Cholesky factor of each M (for mass-weighted shapes).
    inexact : bool
        Whether a sweep's roots needed the round-off polish (:func:`.campbell._refine_inexact`).
    """

    def __init__(self, models):
        self.models = list(models)
        # a small single model's speed-independent parts, shared by every stack of that model
        # object (:func:`model_constants`); None: this stack's own (see :attr:`constants`)
        self._kept = kept = model_constants(self.models[0]) if len(self.models) == 1 else None
        first = None if kept is None else kept.get("form")
        if first is None:
            first = speed_linear_form(self.models[0])
            if kept is not None:
                kept["form"] = first
        # variants with the first model's very bodies share its M, G, M^-1 and whirl forms
        self.forms = [first] + [speed_linear_form(m, like=first) for m in self.models[1:]]
        shapes = {(f.n_dof, f.n_states) for f in self.forms}
        if len(shapes) != 1:
            raise ValueError(f"models of different structure cannot be stacked: {sorted(shapes)}")
        #: every variant has the first one's mass matrix (and whirl forms): the single model's products apply
        self.shared_mass = len(self.forms) == 1 or all(f.matrices.M is first.matrices.M for f in self.forms)
        self.shared_whirl = all(same_inertia(self.models[0], m) for m in self.models[1:])
        # the whirl forms (3 n x n) and M's Cholesky factor, made on first use: the lowest modes'
        # route needs neither until its roots are found (its largest arrays are freed by then)
        self._whirl = None
        self._factor = None
        self._whirl_stacked = None     # the forms side by side for whirl ratios, made on first use
        self._whirl_sparse = None      # a large model's forms, sparse, made on first use
        # the constant parts stacked, made on first use: a large model's lowest modes and critical
        # speeds work on its sparse matrices (``sparse_constant``) and may never need them dense
        kept = {} if kept is None else kept
        self._stacked_parts = kept.get("parts")
        self._factor = kept.get("factor")
        self._whirl = kept.get("whirl")
        self._whirl_stacked = kept.get("whirl_stacked")
        self._weighting = None   # how shapes are mass-weighted: see _modal_weighting
        #: whether a sweep's roots needed the polish of double precision's round-off (set by
        #: :func:`.campbell._refine_inexact`): the critical speeds are then refined on polished roots
        self.inexact = False
        #: the lowest modes' route's basis, kept for its later sweeps of this stack (the critical
        #: speeds' sub-sweeps): ``{"basis": (omegas, modes, K_0), "products": ...}`` once that route
        #: ran (``_lowest._stack_bound``), else None; see :attr:`undamped_modes`
        self.lowest_basis = None
        self._state = None       # A0, A1 stacked, made on first use
        self.dependent = any(f.speed_dependent for f in self.forms)
        self.branch_times = _stacked([f.branch_times for f in self.forms])           # (V, n_b)
        self._branch_stiffness = None     # (V, n_b, n, n), made on first use (see branch_stiffness)
        self._layouts = {}       # variant -> (SparseLayout or None, its constant entries)
        self._sparse_matrices = {}   # 0 -> the first variant's sparse M, C, G, K (or None)

    def __len__(self) -> int:
        return len(self.forms)

    @property
    def constants(self) -> dict:
        """Where the speed-independent parts the lowest modes' route makes are kept (its Hermitian
        form, its pencils' pattern): a small model's dict shared by every stack of that model object
        (its linear form, stacked matrices, mass factor and whirl forms are there too,
        :func:`model_constants`), else this stack's own ``__dict__``."""
        return self.__dict__ if self._kept is None else self._kept

    def _constant_part(self, i: int) -> np.ndarray:
        """The forms' ``(M, C, G, K)[i]`` stacked (V, n, n), made on first use (a large model's
        from its sparse matrix, that part alone)."""
        if self._stacked_parts is None:
            self._stacked_parts = [None] * 4
        if self._stacked_parts[i] is None:
            sparse = self.sparse_constant
            if sparse is not None:
                self._stacked_parts[i] = sparse[i].toarray()[None]
            else:
                self._stacked_parts = [_stacked(parts) for parts in zip(*(f.matrices for f in self.forms))]
            self._keep("parts", self._stacked_parts)
        return self._stacked_parts[i]

    def _keep(self, name: str, value):
        """Keep ``value`` among a kept model's constants (:func:`model_constants`), read-only (no
        caller writes into a stack's constant arrays: a later stack of the model shares them)."""
        if self._kept is not None:
            for array in _arrays_of(value):
                array.flags.writeable = False
            self._kept[name] = value

    @property
    def M(self) -> np.ndarray:
        """The forms' mass matrices stacked (V, n, n), made on first use."""
        return self._constant_part(0)

    @property
    def C(self) -> np.ndarray:
        """The forms' constant damping stacked (V, n, n), made on first use."""
        return self._constant_part(1)

    @property
    def G(self) -> np.ndarray:
        """The forms' gyroscopic matrices stacked (V, n, n), made on first use."""
        return self._constant_part(2)

    @property
    def K(self) -> np.ndarray:
        """The forms' constant stiffness stacked (V, n, n), made on first use."""
        return self._constant_part(3)

    @property
    def branch_stiffness(self) -> np.ndarray:
        """The forms' Maxwell branches' stiffness stacked (V, n_b, n, n), made on first use (the
        rational pencil of the lowest modes takes each branch's 6x6 block, ``branch_blocks``)."""
        if self._branch_stiffness is None:
            self._branch_stiffness = _stacked([f.branch_stiffness for f in self.forms])
        return self._branch_stiffness

    def branch_blocks(self, variant: int = 0):
        """A variant's Maxwell branches on the stator's ``k`` coordinates (the model's first):
        stiffness (n_b, k, k) [N/m, ...] and relaxation times (n_b,) [s]."""
        k = self.models[variant].dofs.n_frame
        return self.forms[variant].branch_blocks[:, :k, :k], self.branch_times[variant]

    @property
    def sparse_constant(self):
        """The first form's ``M, C, G, K`` as ``scipy.sparse`` matrices where the model is large
        (:attr:`SpeedLinearForm.sparse`), else None."""
        return self.forms[0].sparse if len(self.forms) == 1 else None

    @property
    def whirl(self) -> _whirl.WhirlForms:
        """The whirl forms of every variant stacked, (V, n, n) each, made on first use."""
        if self._whirl is None:
            whirl = [_whirl.whirl_forms(self.models[0])]
            whirl += [whirl[0] if same_inertia(self.models[0], m) else _whirl.whirl_forms(m) for m in self.models[1:]]
            self._whirl = _whirl.WhirlForms(*(_stacked(parts) for parts in zip(*whirl)))
            self._keep("whirl", self._whirl)
        return self._whirl

    @property
    def repeated_forms(self) -> _whirl.WhirlForms:
        """The whirl forms that tell a repeated root's two shapes apart
        (:func:`_eigensolve.resolve_repeated`): :attr:`whirl`, or a large model's forms as
        ``scipy.sparse`` matrices (n, n) each where its dense ones are not made (3 n x n fewer)."""
        if self.sparse_constant is not None and self._whirl is None:
            return self._sparse_whirl()
        return self.whirl

    def _sparse_whirl(self) -> _whirl.WhirlForms:
        """A large model's whirl forms as ``scipy.sparse`` CSR matrices (n, n) each, made once."""
        if self._whirl_sparse is None:
            self._whirl_sparse = _whirl.sparse_whirl_forms(self.models[0])
        return self._whirl_sparse

    @property
    def factor(self) -> np.ndarray:
        """Cholesky factor of each M, (V, n, n) (one where the mass is shared), made on first use."""
        if self._factor is None:
            with _batches.one_blas_thread(72 * self.n_dof ** 2):     # faster than BLAS's threads
                self._factor = np.linalg.cholesky(self.M[:1] if self.shared_mass else self.M)
            self._keep("factor", self._factor)
        return self._factor

    @property
    def A0(self) -> np.ndarray:
        """The forms' ``A0`` stacked (V, n_states, n_states), made on first use (the lowest
        modes' route never needs the state matrices)."""
        return self._states()[0]

    @property
    def A1(self) -> np.ndarray:
        """The forms' ``A1`` stacked (V, n_states, n_states), made on first use."""
        return self._states()[1]

    def _states(self):
        if self._state is None:
            self._state = _stacked([f.A0 for f in self.forms]), _stacked([f.A1 for f in self.forms])
        return self._state

    @property
    def n_dof(self) -> int:
        return self.forms[0].n_dof

    # -- state matrices ------------------------------------------------------------------
    def sweep(self, speeds) -> np.ndarray:
        """State matrices of every variant at every speed, shape (V, N, n_states, n_states)."""
        speeds = np.asarray(speeds, dtype=float)
        if self.dependent:
            return np.stack([f.at(speeds) for f in self.forms])
        out = np.multiply(speeds[None, :, None, None], self.A1[:, None])
        out += self.A0[:, None]   # A0 + Omega A1 without a second temporary of the sweep's size
        return out

    def at(self, variants, x) -> np.ndarray:
        """State matrices of variant ``variants[p]`` at speed ``x[p]``, shape (P, n_s, n_s)."""
        if self.dependent:              # each form's own (A0 + Omega A1 made there, once)
            out = np.empty((len(x),) + self.A0.shape[1:])
            for v in np.unique(variants):
                rows = variants == v
                out[rows] = self.forms[v].at(x[rows])
            return out
        return self.A0[variants] + x[:, None, None] * self.A1[variants]

    def damping_stiffness(self, variants, x):
        """``C + Omega G`` (P, n, n) and ``K`` of variant ``variants[p]`` at ``x[p]``; with constant
        coefficients the stiffness is the model's own K (n, n) for one model, the rows' (P, n, n)
        for several (read-only: not to be written)."""
        one = len(self) == 1
        C, G, K = (matrix[0] if one else matrix[variants] for matrix in (self.C, self.G, self.K))
        damping = C + x[:, None, None] * G
        if not self.dependent:
            return damping, K
        stiffness = np.array(np.broadcast_to(K, damping.shape))
        for v in np.unique(variants):
            rows = variants == v
            stiffness[rows], damping[rows] = self.forms[v].pencil_at(x[rows])
            damping[rows] += x[rows, None, None] * self.G[v]
        return damping, stiffness

    def sparse_layout(self, variant: int):
        """The compressed-column layout of a variant's pencils (see :func:`_pencils.sparse_layout`),
        or None where they are factored dense."""
        return self.sparse_entries(variant)[0]

    def sparse_entries(self, variant: int):
        """The variant's layout and its constant matrices' entries there, (M, C, G, K) each
        (nnz,), computed once (the layout comes from the variant's own matrices, so that a study's
        variant and the single analysis of its model factor the very same matrices)."""
        if variant not in self._layouts:
            sparse = self.sparse_constant
            if sparse is not None:        # a large model's: from its sparse matrices, never n x n
                layout = _pencils.sparse_layout(self.forms[variant].pattern(sparse=True))
                entries = None if layout is None else tuple(_sparse_entries(matrix, layout) for matrix in sparse)
                self._layouts[variant] = layout, entries
                return self._layouts[variant]
            layout = _pencils.sparse_layout(self.forms[variant].pattern())
            entries = None
            if layout is not None:
                entries = tuple(matrix[variant if len(matrix) > 1 else 0][layout.rows, layout.cols]
                                for matrix in (self.M, self.C, self.G, self.K))
            self._layouts[variant] = layout, entries
        return self._layouts[variant]

    def sparse_matrices(self):
        """``M, C, G, K`` of the first variant as ``scipy.sparse`` matrices where its pencils are
        sparse (:meth:`sparse_layout`), else None; made once."""
        if 0 not in self._sparse_matrices:
            layout, entries = self.sparse_entries(0)
            self._sparse_matrices[0] = None if layout is None else tuple(layout.matrix(e).tocsr() for e in entries)
        return self._sparse_matrices[0]

    # -- eigen-solutions -----------------------------------------------------------------
    def solve(self, matrices, variants, whirl_noise=False):
        """Upper eigenvalues and unit-norm shapes of state matrices of the given variants.

        Parameters
        ----------
        matrices : ndarray, shape (R, n_s, n_s)
        variants : ndarray of int, shape (R,)
        whirl_noise : bool
            Also return how far round-off can move each shape's whirl ratio
            (:func:`._eigensolve.ratio_round_off`).

        Returns
        -------
        eigenvalues : ndarray (R, m), complex; shapes : ndarray (R, m, n), complex; with
        ``whirl_noise`` also noise : ndarray (R, m)
        """
        variants = np.asarray(variants)
        mass = self.M[0] if len(self.M) == 1 else self.M[variants]
        solved = _eigensolve.upper_shapes(matrices, self.n_dof, whirl_noise, mass)
        eigenvalues, shapes = solved[:2]
        return (eigenvalues, _eigensolve.resolve_repeated(eigenvalues, shapes, self.whirl, variants)) + solved[2:]

    @property
    def undamped_modes(self):
        """Every undamped mode of the symmetric stiffness and the mass, mass-orthonormal (n, n),
        where the lowest modes' route has found them for this stack (:attr:`lowest_basis`), else None."""
        return None if self.lowest_basis is None else self.lowest_basis["basis"][1]

    def _modal_weighting(self):
        """``(Phi, M)`` where a large model's shapes are weighted by its lowest modes' basis (all
        ``n`` undamped modes ``Phi``, :attr:`undamped_modes`; ``M`` sparse): the factor
        ``F = M Phi`` has ``F F^T = M`` as the Cholesky factor has, without the dense M and its
        factor (2 n x n); else None. Chosen once, so that :meth:`weighted` and :meth:`unweighted`
        use the same factor."""
        if self._weighting is None:
            modes, sparse = self.undamped_modes, self.sparse_constant
            self._weighting = (modes, sparse.M) if sparse is not None and modes is not None else False
        return self._weighting or None

    def unweighted(self, weighted_rows) -> np.ndarray:
        """``w F^T`` of rows ``w`` (P, n) of weighted shapes (``F`` the factor of :meth:`weighted`,
        ``F F^T = M``): ``M x`` for ``w = F^T x``, (P, n)."""
        modal = self._modal_weighting()
        if modal is None:
            return _vectors.real_product(weighted_rows, self.factor[0].T)
        modes, mass = modal
        return (mass @ _vectors.real_product(weighted_rows, modes.T).T).T

    def weighted(self, shapes, variants):
        """Mass-weighted unit shapes (see :func:`_vectors.mass_normalized`) of rows of variants,
        one product per part of :meth:`weighted_parts`."""
        out = np.empty(shapes.shape, dtype=complex)
        if not out.size:                # no shapes (and no parts of zero width to cut)
            return out
        parts = self.weighted_parts(shapes.shape, variants)
        modal = self._modal_weighting()
        if modal is not None:          # a large model's: F^T x = Phi^T M x
            modes, mass = modal
            flat, into = shapes.reshape(-1, shapes.shape[-1]), out.reshape(-1, shapes.shape[-1])
            for _, part in parts:
                into[part] = _vectors.unit_rows(_vectors.real_product((mass @ flat[part].T).T, modes))
            return out
        # in parts: the real and imaginary parts and their products are copies of the shapes
        width = int(np.prod(shapes.shape[1:-1], dtype=int))
        for variant, part in parts:
            rows = slice(part.start // width, part.stop // width)
            factor = self.factor[0 if self.shared_mass else variant]                   # real: L^H = L^T
            out[rows] = _vectors.unit_rows(_vectors.real_product(shapes[rows], factor))
        return out

    def weighted_parts(self, shape, variants) -> list:
        """The parts :meth:`weighted` multiplies as one product each, of shapes of ``shape``
        (R, ..., n) of rows of ``variants`` (R,): ``(variant, slice)``, the slice over the rows of
        the shapes flattened to (-1, n). A part computed alone (:meth:`weighted` of just its rows,
        of their shape) is one product of the same size: the same bits as in the whole
        (:class:`._weighted_rows.WeightedRows` computes a sweep's a part at a time)."""
        n = shape[-1]
        width = int(np.prod(shape[1:-1], dtype=int))
        if self._modal_weighting() is not None:
            return [(0, part) for part in _batches.chunk_slices(shape[0] * width, 64 * n)]
        return [(variant, slice(part.start * width, part.stop * width))
                for variant, part in _variant_parts(variants, 64 * width * n)]

    def whirl_ratios(self, shapes, variants, speeds):
        """Whirl ratios (see :func:`_whirl.whirl_ratios`) of shapes (R, m, n) of rows of variants."""
        out = np.empty(shapes.shape[:-1])
        speeds = np.asarray(speeds)
        if speeds.shape != shapes.shape[:-2]:
            speeds = np.broadcast_to(speeds, shapes.shape[:-2])
        # in parts: the products with the three forms are three times the shapes, twice over
        if self._whirl_stacked is None:
            if self.sparse_constant is not None and self._whirl is None:     # a large model's: never dense
                self._whirl_stacked = [_whirl.sparse_stacked_forms(self._sparse_whirl())]
            elif self.shared_whirl and self.n_dof > _pencils.SPARSE_SHAPES_DOF:    # sparse: 3 n x n fewer
                self._whirl_stacked = [_whirl.sparse_stacked_forms(_whirl.WhirlForms(*(f[0] for f in self.whirl)))]
            elif self.n_dof > _whirl._COMPLEX_PRODUCT_DOF and _sparse_forms(self.whirl):
                self._whirl_stacked = [_whirl.entry_forms(_whirl.WhirlForms(*(f[v] for f in self.whirl)))
                                       for v in range(1 if self.shared_whirl else len(self))]
            else:
                self._whirl_stacked = _whirl.stacked_forms(self.whirl)
            self._keep("whirl_stacked", self._whirl_stacked)
        for variant, part in _variant_parts(variants, 160 * shapes[0].size):
            stacked = self._whirl_stacked[0 if self.shared_whirl else variant]
            out[part] = _whirl.whirl_ratios(shapes[part], None, speeds[part], stacked)
        return out

    def shapes_at(self, variants, x, lam):
        """One inverse-iteration step on the pencil for each (variant, speed, eigenvalue), shape
        (P, n): in parts of bounded memory (each row holds its own pencil and matrices, n x n,
        several copies)."""
        out = np.empty((len(x), self.n_dof), dtype=complex)
        dense = np.arange(len(x))
        if self.sparse_constant is not None and self.branch_times.shape[-1]:
            # a large model's rational pencil (Maxwell branches): a banded or sparse LU each
            return _rational_shapes(self, x, lam)
        large = self.n_dof > _pencils.SPARSE_SHAPES_DOF or self.sparse_constant is not None
        if large and not self.branch_times.shape[-1]:
            sparse = np.array([self.sparse_layout(v) is not None for v in variants], dtype=bool)
            if sparse.any():            # a large sparse model: a sparse LU each, never n x n per row
                rows = np.nonzero(sparse)[0]
                out[rows] = _pencils.sparse_pencil_shapes(Pencils(self, variants[rows], x[rows]), lam[rows])
                dense = np.nonzero(~sparse)[0]
        for part in _batches.chunk_slices(len(dense), 80 * self.n_dof ** 2):
            rows = dense[part]
            mine = variants[rows]
            damping, stiffness = self.damping_stiffness(mine, x[rows])
            out[rows] = _pencils.pencil_shapes(self.M[0] if len(self) == 1 else self.M[mine], damping, stiffness,
                                             lam[rows], (self.branch_stiffness[mine], self.branch_times[mine]))
        return out


class Pencils:
    """The quadratic pencils ``Q(s) = s^2 M + s (C + Omega G) + K`` of rows (variant, speed) of a
    :class:`Stack`, applied to vectors without forming each row's matrices where the rows share
    them (one model with constant coefficients: ``C + Omega G`` is applied as ``C phi + Omega G
    phi``, one matrix product for all rows).

    Parameters
    ----------
    stack : Stack
    variants : ndarray of int, shape (P,)
    speeds : ndarray, shape (P,) [rad/s]
    """

    def __init__(self, stack, variants, speeds):
        self.stack, self.variants, self.speeds = stack, np.asarray(variants), np.asarray(speeds, dtype=float)
        self.shared = len(stack) == 1 and not stack.dependent
        self._constant = None       # M, C, G, K of every variant side by side, made on first use
        self._all = None            # the matrices of all rows, made on first use

    def __len__(self) -> int:
        return len(self.speeds)

    @property
    def n_dof(self) -> int:
        return self.stack.n_dof

    def sparse(self, rows) -> np.ndarray:
        """Which of ``rows`` have a sparse layout (bool array)."""
        return np.array([self.stack.sparse_layout(v) is not None for v in self.variants[rows]], dtype=bool)

    def sparse_parts(self, row: int):
        """Row ``row``'s layout and the entries of its mass, ``C + Omega G`` and stiffness there
        (each (nnz,), real)."""
        stack = self.stack
        variant, speed = self.variants[row], self.speeds[row]
        layout, (mass, damping, gyroscopic, stiffness) = stack.sparse_entries(variant)
        if stack.dependent and stack.sparse_constant is not None:     # a large model's: its bearings sparse
            k_b, c_b = _sparse_bearings(stack, speed)
            return (layout, mass, damping + speed * gyroscopic + _sparse_entries(c_b, layout),
                    stiffness + _sparse_entries(k_b, layout))
        if stack.dependent:
            damping, stiffness = (matrix[0][layout.rows, layout.cols]
                                  for matrix in stack.damping_stiffness(np.array([variant]), np.array([speed])))
            return layout, mass, damping, stiffness
        return layout, mass, damping + speed * gyroscopic, stiffness

    def matrices(self, rows):
        """Mass (n, n) or (R, n, n), ``C + Omega G`` (R, n, n) and stiffness (n, n) or (R, n, n)
        of ``rows`` (an index array or a slice): the mass and stiffness (n, n) where all rows share
        them (one model; the stiffness only with constant coefficients). Those of all rows
        (``slice(None)``) are made once: the small pencils' iteration refactors them at every step."""
        if isinstance(rows, slice) and rows == slice(None):
            if self._all is None:
                self._all = self._matrices(rows)
            return self._all
        return self._matrices(rows)

    def _matrices(self, rows):
        stack = self.stack
        variants = self.variants[rows]
        mass = stack.M[0] if len(stack) == 1 else stack.M[variants]
        return (mass, *stack.damping_stiffness(variants, self.speeds[rows]))

    def products(self, rows, vectors):
        """``M phi``, ``(C + Omega G) phi`` and ``K phi`` of ``rows`` for complex vectors (R, n),
        stacked: (3, R, n).

        Row by row: each result independent of the others, so that a study's variant and the
        single analysis of its model agree bit for bit, and a critical speed's refinement does not
        depend on which other crossings share its batch (issue 28: one matrix product over all
        rows of a model above ``BATCHED_DOF`` coordinates gave their last bits by the batch's
        size). A large machine's sparse matrices multiply all rows at once, each output entry
        summed over its row's entries in their stored order whatever the rows (``scipy.sparse``'s
        CSR product): row by row too."""
        stack = self.stack
        speeds = self.speeds[rows, None]
        if self.shared and vectors.shape[-1] > _pencils.BATCHED_DOF:
            sparse = stack.sparse_matrices()
            if sparse is not None:         # a large machine's sparse matrices: O(nnz) per vector
                m_phi, c_phi, g_phi, k_phi = ((matrix @ vectors.T).T for matrix in sparse)
                return np.array((m_phi, c_phi + speeds * g_phi, k_phi))
        if stack.dependent and stack.sparse_constant is not None:      # a large model's: sparse, row by row
            M, C, G, K = stack.sparse_constant
            columns = vectors.T
            out = np.array(((M @ columns).T, (C @ columns).T + speeds * (G @ columns).T, (K @ columns).T))
            for i, speed in enumerate(self.speeds[rows]):
                k_b, c_b = _sparse_bearings(stack, speed)
                out[1, i] += c_b @ vectors[i]
                out[2, i] += k_b @ vectors[i]
            return out
        if stack.dependent:
            variants = self.variants[rows]
            damping, stiffness = stack.damping_stiffness(variants, self.speeds[rows])
            mass = stack.M[0] if len(stack) == 1 else stack.M[variants]
            return np.array((_row_products(mass, vectors), _row_products(damping, vectors),
                             _row_products(stiffness, vectors)))
        # M, C, K and G times each row in one product (each matrix-vector product as by itself)
        if self._constant is None:
            self._constant = np.array((stack.M, stack.C, stack.K, stack.G))              # (4, V, n, n)
        matrices = self._constant[:, :1] if len(stack) == 1 else self._constant[:, self.variants[rows]]
        out = _row_products(matrices, vectors)
        out[1] += speeds * out[3]                                                        # C phi + Omega G phi
        return out[:3]


def _sparse_entries(matrix, layout) -> np.ndarray:
    """A ``scipy.sparse`` matrix's entries at the layout's places (nnz,)."""
    return np.asarray(matrix.tocsr()[layout.rows, layout.cols]).reshape(-1)


def _sparse_bearings(stack, speed: float):
    """The speed-dependent bearings' stiffness and damping of a large one-model stack at ``speed``
    [rad/s], ``scipy.sparse`` (n, n) each."""
    from ..assembly import sparse_bearing_matrices

    return sparse_bearing_matrices(stack.models[0], float(speed), dependent_only=True)


def _rational_shapes(stack, x, lam) -> np.ndarray:
    """:meth:`Stack.shapes_at` of a large one-model stack with Maxwell branches: the same shifted
    inverse-iteration step from the same start on the rational pencil ``T(s)``
    (:class:`._lowest_branches.RationalPencils`: its banded or sparse LU), (P, n) unit rows."""
    from ._lowest_branches import RationalPencils

    n = stack.n_dof
    shifted = _pencils.shifted_roots(lam)
    start = np.repeat(_pencils._start_vectors(1, n)[0][None].astype(complex), len(x), axis=0)
    pencils = RationalPencils(stack, np.asarray(x, dtype=float))
    return _vectors.unit_rows(pencils.solve(np.arange(len(x)), shifted, start))


def _row_products(matrices, vectors):
    """Real matrices (..., n, n) (broadcast against the rows: (n, n), (R, n, n), (K, 1, n, n) or (K,
    R, n, n)) times complex vectors (R, n), one row at a time: (..., R, n)."""
    column = vectors[..., None]
    return (matrices @ column.real)[..., 0] + 1j * (matrices @ column.imag)[..., 0]


#: whirl forms with at most this part of their entries nonzero are summed by their entries
#: (:class:`._whirl.EntryForms`), not multiplied dense
_SPARSE_FORMS = 1 / 16


def _sparse_forms(forms) -> bool:
    """Whether every variant's whirl forms (V, n, n) each have at most ``_SPARSE_FORMS`` of their
    entries nonzero (a flexible shaft's: each node coupled with its neighbours)."""
    n = forms.W.shape[-1]
    return all(np.count_nonzero(form, axis=(1, 2)).max() <= _SPARSE_FORMS * n * n for form in forms)


def _variant_parts(variants, item_bytes: int):
    """Parts of rows for products with one variant's matrix: ``(variant, slice)`` for each run of
    consecutive rows of one variant, cut as that variant's rows alone would be (in parts of
    bounded memory, ``_batches._PART_BYTES``: a sweep's peak memory does not grow with its speeds
    beyond the shapes themselves).

    A matrix product over many rows may give a row bits that depend on its place among them
    (the BLAS kernels block the rows, and the last block of a product can be summed another
    way), so a study's variant is multiplied exactly as the single analysis of its model is:
    its own rows, in the same parts, with its own matrix.

    Parameters
    ----------
    variants : ndarray of int, shape (R,)
        The variant of each row.
    item_bytes : int
        Work memory of one row [bytes].
    """
    variants = np.asarray(variants)
    ends = [0, *(np.flatnonzero(variants[1:] != variants[:-1]) + 1).tolist(), len(variants)]
    return [(int(variants[start]), slice(start + part.start, start + part.stop))
            for start, stop in zip(ends[:-1], ends[1:]) if stop > start
            for part in _batches.chunk_slices(stop - start, item_bytes, budget=_batches._PART_BYTES)]


#: models up to this many coordinates keep their speed-independent parts between analyses
#: (:func:`model_constants`): at most a few MB each. ROSS's ``Rotor`` keeps its ``M0``, ``K0`` and
#: ``G0`` the same way; a small model's Campbell diagram of 21 speeds spent a fifth of its time
#: building them again (rotor_example: 3 of 15 ms). 256 (100 before): ROSS's compressor_example (224
#: coordinates, its kept parts about 5 MB: M, C, G, K, M's factor, the whirl forms, the state matrices
#: of its tabulated bearings' round-off) spent 0.9 of its 7 ms a speed at 21 speeds making them again
KEPT_DOF = 256

#: how many models keep their constants at once (the most recently used): each is held, with its
#: model, until it is pushed out
KEPT_MODELS = 4

#: ``{id(model): (model, constants)}``, the most recently used last
_KEPT: dict = {}


def model_constants(model) -> dict | None:
    """The dict of speed-independent parts a small model's :class:`Stack` shares with every later
    stack of the very same model object (a model is never changed once validated: a study's
    variant or ``with_values`` is a new one), or None for a model of more than :data:`KEPT_DOF`
    coordinates. The :data:`KEPT_MODELS` most recently used models are kept (the dict holds the
    model: ids are not reused while it is kept)."""
    from .. import assembly

    if model.dofs.n > KEPT_DOF or assembly.is_large(model):
        return None
    key = id(model)
    entry = _KEPT.pop(key, None)
    settings = _settings()
    if entry is None or entry[0] is not model or entry[1].get("settings") != settings:
        entry = (model, {"settings": settings})
    _KEPT[key] = entry
    while len(_KEPT) > KEPT_MODELS:
        del _KEPT[next(iter(_KEPT))]
    return entry[1]


def _settings() -> tuple:
    """The sizes that choose how a model's parts are made (sparse or dense matrices and whirl
    forms): parts kept under other sizes are made again (the tests set them lower)."""
    from .. import assembly

    return (assembly.SPARSE_DOF, _pencils.SPARSE_SHAPES_DOF, _pencils.SPARSE_DOF, _whirl._COMPLEX_PRODUCT_DOF)


def _arrays_of(value):
    """The numpy arrays of ``value``: an array, or (nested) lists and tuples of them."""
    if isinstance(value, np.ndarray):
        return [value]
    if isinstance(value, (list, tuple)):
        return [array for item in value for array in _arrays_of(item)]
    return []


def _stacked(arrays) -> np.ndarray:
    """``numpy.stack`` of the arrays; of a single array a view with a leading axis of one."""
    return arrays[0][None] if len(arrays) == 1 else np.stack(arrays)
