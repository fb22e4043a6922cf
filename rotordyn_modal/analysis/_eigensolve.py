"""Roots of the speed-dependent state matrix: batched eigenvalues, one root of each conjugate
pair (the oscillating ones), shapes from state eigenvectors, repeated roots resolved into
their extreme-whirl basis.

Speed: eigenvalues and eigenvectors of all speeds come from one batched LAPACK call split
over threads (numpy releases the GIL); a mode shape is the displacement part of its state
eigenvector."""

from __future__ import annotations

import ctypes
import functools

import numpy as np

from .._blas import lapack
from . import _batches, _roots, _vectors
from ._polish_plan import POLISH_WORK, _clusters, _nearest_other, polish_budget, polish_work, run_work

__all__ = ["REPEATED_TOLERANCE", "TIE_TOLERANCE", "eig", "eigenvalues_of", "frequency_order", "resolve_groups", "resolve_repeated", "select_upper", "solve_batch", "upper_eigenvalues",
           "upper_indices", "upper_shapes", "ratio_round_off", "INEXACT_LEVEL", "POLISH_LEVEL", "pencil_round_off", "refined_pairs", "warn_of_inexact_roots", "branch_terms",
           "POLISH_WORK", "polish_work", "polish_budget", "polished_ratio_round_off"]


def upper_shapes(matrices: np.ndarray, n: int, whirl_noise: bool = False, mass=None):
    """Upper eigenvalues (see :func:`upper_indices`) and unit-norm displacement shapes of a
    stack of state matrices: ``numpy.linalg.eig`` in threads and parts of bounded memory, each
    part's eigenvectors reduced to its shapes at once (the parts' results are a quarter of
    the eigenvectors, so joining them copies little).

    Parameters
    ----------
    matrices : ndarray, shape (R, n_states, n_states)
    n : int
        Number of generalized coordinates (the displacement rows of the eigenvectors).
    whirl_noise : bool
        Also return how far round-off can move each shape's whirl ratio, as ``modal`` takes
        it (:func:`ratio_round_off`).
    mass : ndarray, shape (n, n) or (R, n, n), optional
        The mass matrix of the machine (of each matrix): a slow root is then a zero root only
        where its shape is free to round-off (:func:`._roots.zero_roots`).

    Returns
    -------
    eigenvalues : ndarray, shape (R, m), complex; shapes : ndarray, shape (R, m, n), complex;
    with ``whirl_noise`` also noise : ndarray, shape (R, m)
    """
    size = matrices.shape[-1]
    if mass is not None and np.ndim(mass) == 3:              # one mass matrix per state matrix
        return _batches._threaded(functools.partial(_upper_part, n=n, whirl_noise=whirl_noise), matrices,
                                  np.asarray(mass, dtype=float), item_bytes=72 * size * size)
    return _batches._threaded(functools.partial(_upper_part, n=n, whirl_noise=whirl_noise, mass=mass), matrices,
                              item_bytes=72 * size * size)


def ratio_round_off(upper, every, matrices, own=None) -> np.ndarray:
    """How far round-off can move the whirl ratio of each root's shape (:func:`._roots.whirl_round_off`),
    with the round-off of each solve (:func:`._roots.round_off` of its matrix) and its repeated
    roots (within :data:`REPEATED_TOLERANCE` of its largest root) as ``modal`` takes them.

    Parameters
    ----------
    upper : ndarray, shape (R, m), complex
        The roots whose shapes are used.
    every : ndarray, shape (R, M), complex
        All roots of each solve.
    matrices : ndarray, shape (R, n_s, n_s)
        The state matrices solved.
    own : ndarray, shape (R, m), optional
        Each root's own round-off where it differs (:func:`._roots.snapped_with_round_off`).

    Returns
    -------
    ndarray, shape (R, m)
    """
    noise = _roots.round_off(matrices)
    repeated = REPEATED_TOLERANCE * np.abs(upper).max(axis=-1, initial=0.0)
    if own is not None:
        own = np.where(own < noise[:, None], own, noise[:, None])
    return _roots.whirl_round_off(upper, every, noise, repeated, own)


def _upper_part(matrices: np.ndarray, mass=None, n: int = 0, whirl_noise: bool = False):
    values, vectors = np.linalg.eig(matrices)
    values, own, every = _roots.snapped_with_round_off(values, _roots.deciding_round_off(values, matrices), matrices,
                                                       vectors, n, mass)
    index, eigenvalues = upper_indices(values)
    # advanced indices apart put their axes first: shapes[r, k, j] = vectors[r, j, index[r, k]]
    shapes = vectors[np.arange(len(vectors))[:, None], :n, index]
    if whirl_noise:
        own = np.take_along_axis(np.broadcast_to(own, values.shape), index, axis=-1)
        return eigenvalues, _vectors.unit_rows(shapes), ratio_round_off(eigenvalues, every, matrices, own)
    return eigenvalues, _vectors.unit_rows(shapes)


def eigenvalues_of(matrices: np.ndarray, n: int | None = None, mass=None) -> np.ndarray:
    """``numpy.linalg.eigvals`` of a stack of matrices, in threads and parts of bounded memory,
    their round-off removed (:func:`._roots.snapped`).

    With the state matrices' ``n`` coordinates and ``mass`` (n, n) or (R, n, n), each root is
    judged by its own shape as :func:`upper_shapes` judges it: the matrices with a nonzero root
    at or below the square root of their round-off are solved again with their eigenvectors
    (:func:`._roots.zero_roots`; usually none), so a slow mode is never taken for a zero root
    because some other root of the machine is large. Without them every root below that square
    root is zero."""
    size = matrices.shape[-1]
    if mass is None:
        return _batches._threaded(_snapped_eigenvalues, matrices, item_bytes=24 * size * size)
    if np.ndim(mass) == 3:
        return _batches._threaded(functools.partial(_snapped_eigenvalues, n=n), matrices,
                                  np.asarray(mass, dtype=float), item_bytes=24 * size * size)
    return _batches._threaded(functools.partial(_snapped_eigenvalues, n=n, mass=mass), matrices,
                              item_bytes=24 * size * size)


def _snapped_eigenvalues(matrices: np.ndarray, mass=None, n: int | None = None) -> np.ndarray:
    values = np.linalg.eigvals(matrices)
    noise = _roots.deciding_round_off(values, matrices)
    if mass is None:
        return _roots.snapped(values, noise)
    rows = np.flatnonzero(_judged_by_shape(values, noise))
    out = _roots.snapped(values, noise)
    if len(rows):
        masses = mass[rows] if np.ndim(mass) == 3 else mass
        again, vectors = np.linalg.eig(matrices[rows])
        judged = _roots.snapped(again, _roots.deciding_round_off(again, matrices[rows]), matrices[rows], vectors,
                                n, masses)
        # eig's roots where its shapes keep a slow mode; elsewhere eigvals' (the same verdicts, the same bits)
        kept = (judged == 0).sum(axis=-1) != (out[rows] == 0).sum(axis=-1)
        out[rows[kept]] = judged[kept]
    return out


def _judged_by_shape(values, noise) -> np.ndarray:
    """(R,) bool: the solves whose roots ``values`` (R, M) have one that only its shape can tell
    from a zero root: nonzero and at or below :func:`._roots.zero_floor` of ``noise`` (R,)."""
    magnitude = np.abs(values)
    return ((magnitude > 0) & (magnitude <= _roots.zero_floor(noise)[:, None])).any(axis=-1)


def upper_eigenvalues(matrices: np.ndarray):
    """Upper eigenvalues (see :func:`upper_indices`) of a stack of state matrices from
    ``numpy.linalg.eigvals`` (no eigenvectors: about 60 % of ``eig``'s work), in threads and parts
    of bounded memory, and which rows need their eigenvectors to judge their roots: those with
    a nonzero root up to the square root of the round-off (whether it is a zero root depends on
    its shape, :func:`._roots.zero_roots`). Elsewhere the eigenvalues equal :func:`upper_shapes`' to
    round-off.

    Parameters
    ----------
    matrices : ndarray, shape (R, n_states, n_states)

    Returns
    -------
    eigenvalues : ndarray, shape (R, m), complex; vectors_needed : ndarray of bool, shape (R,)
    """
    size = matrices.shape[-1]
    return _batches._threaded(_upper_eigenvalues_part, matrices, item_bytes=24 * size * size)


def _upper_eigenvalues_part(matrices: np.ndarray):
    values = np.linalg.eigvals(matrices)
    noise = _roots.deciding_round_off(values, matrices)      # decides `needed` as the round-off would
    return upper_indices(_roots.snapped(values, noise))[1], _judged_by_shape(values, noise)


def eig(matrix: np.ndarray):
    """``scipy.linalg.eig(matrix)`` (eigenvalues and right eigenvectors), bit for bit, with the
    GIL released during LAPACK's ``dgeev``: scipy's own ``dgeev`` (from
    ``scipy.linalg.cython_lapack``, the library scipy's wrapper calls) through ``ctypes``, with
    scipy's workspace (``geev_lwork``) and its packing of complex vectors. scipy's wrapper holds
    the GIL (no ``threadsafe``): no other thread ran during it, so the clock of a progress line
    (:mod:`.._progress`) stood for the whole solve (500 geared rotors, 4,012 states: about 45 s of
    CPU). LAPACK runs with one BLAS thread (:func:`._batches.one_blas_thread`), as every dense
    eigen-solution. Matrices other than a real square one, or where the routine cannot be had:
    scipy's.

    Parameters
    ----------
    matrix : ndarray, shape (n, n)

    Returns
    -------
    values : ndarray, shape (n,), complex
    vectors : ndarray, shape (n, n), Fortran-ordered, real where every value is real, else complex
    """
    import scipy.linalg

    a = np.asarray_chkfinite(matrix)
    function = _dgeev()
    if function is None or a.dtype != np.float64 or a.ndim != 2 or a.shape[0] != a.shape[1] or a.size == 0:
        return scipy.linalg.eig(matrix)
    n = a.shape[0]
    work, info = scipy.linalg.get_lapack_funcs("geev_lwork", (a,))(n, compute_vl=0, compute_vr=1)
    if info != 0:                                                           # pragma: no cover
        return scipy.linalg.eig(matrix)
    a = np.array(a, order="F")
    lwork = int(work.real)
    wr, wi, left, vectors = np.empty(n), np.empty(n), np.empty((1, 1), order="F"), np.empty((n, n), order="F")
    space, status = np.empty(max(lwork, 1)), ctypes.c_int(0)
    size, one, length = ctypes.c_int(n), ctypes.c_int(1), ctypes.c_int(lwork)
    jobs = ctypes.c_char(b"N"), ctypes.c_char(b"V")                         # no left vectors, right ones
    with _batches.one_blas_thread(72 * n * n):      # asked once scipy.linalg is loaded: its library too
        function(ctypes.byref(jobs[0]), ctypes.byref(jobs[1]), ctypes.byref(size), a.ctypes.data, ctypes.byref(size),
                 wr.ctypes.data, wi.ctypes.data, left.ctypes.data, ctypes.byref(one), vectors.ctypes.data,
                 ctypes.byref(size), space.ctypes.data, ctypes.byref(length), ctypes.byref(status))
    if status.value != 0:
        return scipy.linalg.eig(matrix)                                     # scipy's own error
    values = wr + 1j * wi
    if np.all(values.imag == 0.0):
        return values, vectors
    out = np.array(vectors, dtype=complex)               # as scipy's _make_complex_eigvecs
    pairs = values.imag > 0
    pairs[:-1] |= values.imag[1:] < 0
    for i in np.flatnonzero(pairs):
        out.imag[:, i] = vectors[:, i + 1]
        np.conj(out[:, i], out[:, i + 1])
    return values, out


def _dgeev():
    """LAPACK's ``dgeev`` as a ``ctypes`` function (``ctypes`` releases the GIL during the call), or
    None where it cannot be had (:func:`.._blas.lapack`, cached there)."""
    return lapack("dgeev")


def select_upper(values: np.ndarray) -> np.ndarray:
    """Pick the upper half of each row of eigenvalues; one of each conjugate pair and the smaller half of the real roots."""
    return upper_indices(values)[1]


def upper_indices(values: np.ndarray):
    """Where the upper half of each row of eigenvalues sits, and those eigenvalues.

    ``values`` (..., 2 n) are all roots of each state matrix, rid of their round-off (zero roots
    and imaginary parts within it exactly 0: :func:`._roots.snapped`).

    Returns
    -------
    index : ndarray of int, shape (..., n)
        Positions in ``values`` (and in the columns of the eigenvector matrices).
    upper : ndarray, shape (..., n), complex
        Sorted by imaginary part, then real part (one of each conjugate pair and the smaller half
        of the real roots); imaginary parts within :data:`TIE_TOLERANCE` of the row's largest
        root of each other are one frequency, its modes ordered by damping, the least damped first
        (:func:`_ties_by_real_part`, so that the order does not depend on round-off or on the
        model's units).
    """
    n = values.shape[-1] // 2
    # by imaginary part; within the real block the smaller |lam| last, so that the upper half
    # takes it
    order = np.lexsort((-np.abs(values), values.imag), axis=-1)
    chosen = order[..., n:]
    along = _gather(values.shape)
    upper = along(values, chosen)
    final = frequency_order(upper)
    return along(chosen, final), along(upper, final)


def frequency_order(values, first=None, whirl=None):
    """The order (..., m) of roots ``values`` (..., m) by frequency, with the frequencies that
    agree to round-off taken as one, its modes by damping, the least damped first
    (:func:`_ties_by_real_part`): the order of mode numbers, whatever the model's units.

    Parameters
    ----------
    values : ndarray, shape (..., m), complex [1/s]
    first : ndarray of bool, shape (..., m), optional
        A key before the frequency: the roots where it is False first (e.g. ``~oscillating``:
        the modes first).
    whirl : ndarray, shape (..., m), optional
        Each root's whirl ratio about ``+spin_axis``: the members of a repeated root (one
        frequency and damping) by it, backward first, as :func:`resolve_repeated` makes and
        :func:`upper_indices` orders them at one speed (without it, as they stand).

    Returns
    -------
    ndarray of int, shape (..., m)
    """
    keys = (values.real, values.imag) + (() if first is None else (first,))
    order = np.lexsort(keys, axis=-1)
    if values.shape[-1] < 2:            # no root or one: nothing to tie (a sweep with no mode below a limit)
        return order
    along = _gather(values.shape)
    groups = None if first is None else along(np.asarray(first), order)
    within = None if whirl is None else along(np.asarray(whirl, dtype=float), order)
    return along(order, _ties_by_real_part(along(values, order), groups, within))


#: imaginary parts closer than this, relative to the largest root of their row, are one frequency
#: to :func:`upper_indices`, and real parts as close one damping: a frequency shared to round-off
#: by roots of different damping (an isotropic machine's two whirls under cross-coupling at rest)
#: is ordered by damping, not by which one round-off puts a few units in the last place higher
#: (which changes when the model's time is scaled)
TIE_TOLERANCE = 256 * np.finfo(float).eps


def _ties_by_real_part(upper, groups=None, whirl=None):
    """The order (..., n) of roots ``upper`` (..., n), sorted by imaginary part and then real part,
    that orders the modes of one frequency by damping, the least damped (largest real part) first.

    Runs of imaginary parts each within ``TIE_TOLERANCE * max |lam|`` (the row's largest finite
    root) of the next are one frequency; within a run, real parts each within as much of the next
    are one damping (a repeated root: its order, and its shapes' whirl, kept as they are). Roots
    that do not oscillate (imaginary part 0) stay by real part, the smallest first. So the order
    is unchanged wherever no two frequencies agree to that little with different damping.
    ``groups`` (..., n), optional: a key the roots are sorted by before their frequency (a
    change of it starts a new run).
    """
    size = np.abs(upper)
    tie = TIE_TOLERANCE * np.max(np.where(np.isfinite(size), size, 0.0), axis=-1, keepdims=True, initial=0.0)
    start = np.zeros(upper.shape[:-1] + (1,), dtype=bool)
    apart = ~(np.diff(upper.imag, axis=-1) <= tie)                       # NaN or inf: a run of its own
    if groups is not None:
        apart |= np.diff(groups.astype(int), axis=-1) != 0
    runs = np.cumsum(np.concatenate([start, apart], axis=-1), axis=-1)
    along = _gather(upper.shape)
    key = np.where(upper.imag > 0, -upper.real, upper.real)             # modes: the least damped first
    by_damping = np.lexsort((key, runs), axis=-1)
    damped, run = along(key, by_damping), along(runs, by_damping)
    apart = ~(np.diff(damped, axis=-1) <= tie) | (np.diff(run, axis=-1) != 0)   # NaN: a damping of its own
    damping = np.empty_like(runs)
    np.put_along_axis(damping, by_damping, np.cumsum(np.concatenate([start, apart], axis=-1), axis=-1), axis=-1)
    keys = (np.broadcast_to(np.arange(upper.shape[-1]), upper.shape),) + (() if whirl is None else (whirl,))
    return np.lexsort(keys + (damping,), axis=-1)


def _gather(shape):
    """``numpy.take_along_axis(array, index, axis=-1)`` for arrays of leading shape ``shape[:-1]``;
    for rows (2-D) one advanced index with the row numbers made once (the same elements, without
    take_along_axis's per-call index building)."""
    if len(shape) != 2:
        return lambda array, index: np.take_along_axis(array, index, axis=-1)
    rows = np.arange(shape[0])[:, None]
    return lambda array, index: array[rows, index]


def solve_batch(form, speeds, forms=None):
    """Upper eigenvalues and their mode shapes at many speeds.

    Parameters
    ----------
    form : SpeedLinearForm
    speeds : ndarray, shape (N,) [rad/s]
    forms : WhirlForms, optional
        When given, the shapes of repeated eigenvalues are made the circular
        (extreme-whirl) combinations; see :func:`resolve_repeated`.

    Returns
    -------
    eigenvalues : ndarray, shape (N, m), complex [1/s]
        ``m = n_states / 2`` roots per speed.
    shapes : ndarray, shape (N, m, n), complex
        Unit-norm displacement parts of the state eigenvectors.
    """
    speeds = np.asarray(speeds, dtype=float)
    eigenvalues, shapes = upper_shapes(form.at(speeds), form.n_dof, mass=form.matrices.M)
    if forms is not None:
        shapes = resolve_repeated(eigenvalues, shapes, forms)
    return eigenvalues, shapes


#: eigenvalues closer than this (relative) are one repeated eigenvalue
REPEATED_TOLERANCE = 1e-9


def resolve_repeated(eigenvalues, shapes, forms, variants=None, groups=True):
    """Make the shapes of a repeated eigenvalue its forward and backward whirl combinations.

    Any combination of the shapes of a double eigenvalue is a mode shape, so the
    solver's choice (and with it the whirl label) would be arbitrary. Within each
    pair this picks the two combinations with extreme whirl ratio: the
    eigenvectors of ``-i Phi^H W Phi v = mu Phi^H M Phi v`` (circular orbits, one
    turning each way, for an axisymmetric machine). Pairs whose motion has no
    whirl keep their shapes. Groups of three or more coinciding roots (identical
    rotors at rest: a root of multiplicity four) are made the whirl-sorted
    eigenvectors of the same pencil over their eigenspace, backward first
    (:func:`resolve_groups`).

    Parameters
    ----------
    eigenvalues : ndarray, shape (N, m), sorted so that equal values are adjacent
    shapes : ndarray, shape (N, m, n)
    forms : WhirlForms
        Each (n, n), or (V, n, n) for rows of several variants.
    variants : ndarray of int, shape (N,), optional
        The variant of each row, with forms stacked over variants.
    groups : bool
        Also resolve groups of three or more (False: the pairs only).

    Returns
    -------
    ndarray, shape (N, m, n): shapes, with repeated pairs replaced (backward first)
    """
    if groups:
        shapes = resolve_groups(eigenvalues, shapes, forms, variants, copy=True)
    rows, first = _repeated_pairs(eigenvalues)
    if not len(rows):
        return shapes
    # with forms per variant, each pair takes its variant's three (n, n) forms: a part of the pairs
    # at a time (81 double roots of a 2,006-coordinate machine at rest would take 7 GiB at once)
    n = shapes.shape[-1]
    parts = [slice(None)] if variants is None else _batches.chunk_slices(len(rows), 48 * n * n, budget=_batches._PART_BYTES)
    found = [_whirling_pairs(shapes, rows[part], first[part], forms, variants) for part in parts]
    rows, first, resolved = found[0] if len(found) == 1 else _batches.concatenated(found)
    if not rows.size:
        return shapes
    # complex: LAPACK gives real vectors when every root is real (an overdamped machine), and
    # their pairs' combinations are complex (numpy's ComplexWarning, the imaginary parts lost)
    out = shapes.astype(np.result_type(shapes.dtype, resolved.dtype))
    out[rows, first] = resolved[:, :, 0]
    out[rows, first + 1] = resolved[:, :, 1]
    return out


def resolve_groups(eigenvalues, shapes, forms, variants=None, rows=None, copy=False):
    """The shapes of each root of multiplicity three or more made the whirl-sorted combinations
    of its eigenspace, backward first: ``-i Phi^H W Phi v = mu Phi^H T Phi v`` (``T`` the total
    form), as :func:`resolve_repeated` makes a pair's. A group is a run of adjacent roots of
    ``eigenvalues`` (N, m) (by frequency; NaN where a row has fewer roots) within
    :data:`REPEATED_TOLERANCE` of the row's largest |lambda|, not zero. Two identical rotors at
    rest have four roots of each double root's value: any basis of them comes out of a solver
    (whirl ratios anywhere in ``[-1, 1]``); made two of ratio -1 and two of +1, each the same
    combination whichever basis the solver gave, so the shapes go on as the split roots' once
    the rotors turn. Groups whose shapes do not span their space, or do not whirl, keep their
    shapes.

    Parameters
    ----------
    eigenvalues : ndarray, shape (N, m)
    shapes : ndarray, shape (N, m, n)
        Written over where a group is resolved, unless ``copy`` or real (then a complex copy is).
    forms : WhirlForms
        Each (n, n), (V, n, n) with ``variants`` or ``scipy.sparse`` (n, n).
    variants : ndarray of int, shape (N,), optional
    rows : sequence of int, optional
        The rows to look at (all by default).
    copy : bool
        Leave ``shapes`` as it is: write a copy.

    Returns
    -------
    ndarray, shape (N, m, n): ``shapes``, or its complex copy where one was written
    """
    at = np.arange(len(eigenvalues)) if rows is None else np.asarray(rows, dtype=int)
    if eigenvalues.shape[-1] < 3 or not len(at):
        return shapes
    lam = eigenvalues[at]
    with np.errstate(invalid="ignore"):
        scale = np.nanmax(np.abs(lam), axis=-1) + 1e-300
        close = _roots.one_root(lam[..., 1:], lam[..., :-1], REPEATED_TOLERANCE * scale[:, None])
    # runs of three or more: two closes in a row somewhere
    candidates = np.nonzero((close[:, 1:] & close[:, :-1]).any(axis=-1))[0]
    copied = False
    for c in candidates:
        s = at[c]
        for start, stop in _runs(close[c]):
            if stop - start < 3 or eigenvalues[s, start] == 0:
                continue
            resolved = _whirl_sorted(shapes[s, start:stop].T, forms, None if variants is None else variants[s])
            if resolved is not None:
                if not copied and (copy or not np.iscomplexobj(shapes)):
                    shapes, copied = shapes.astype(complex), True
                shapes[s, start:stop] = resolved.T
    return shapes


def _whirl_sorted(basis, forms, variant=None):
    """The whirl-sorted combinations (n, g) of the ``g`` shapes ``basis`` (n, g) of one multiple
    root (:func:`resolve_groups`), or None where they do not span their space or do not whirl."""
    total, momentum = (basis.conj().T @ _dense(form, basis, variant) for form in (forms.total, forms.W))
    spread = np.linalg.eigvalsh(0.5 * (total + total.conj().T))
    if not spread[0] > 1e-6 * spread[-1]:
        return None
    mu, resolved = _extreme_whirl(basis[None], total[None], -1j * momentum[None])
    return resolved[0] if mu[0, -1] - mu[0, 0] > 1e-6 else None


def _dense(form, basis, variant=None):
    """``form @ basis`` (n, g) of a whirl form (n, n), (V, n, n) (``variant``'s; the first where
    None) or ``scipy.sparse``."""
    if getattr(form, "ndim", 2) == 3:
        form = form[0 if variant is None else variant]
    return form @ basis


def _runs(close):
    """``(start, stop)`` of each run of roots joined by ``close`` (k - 1,) bool: roots
    ``start:stop``, at least two."""
    runs, j = [], 0
    while j < len(close):
        if close[j]:
            start = j
            while j < len(close) and close[j]:
                j += 1
            runs.append((start, j + 1))
        j += 1
    return runs


def _whirling_pairs(shapes, rows, first, forms, variants):
    """The pairs ``(rows, first)`` of :func:`resolve_repeated` whose shapes span a plane and
    whirl, and their extreme-whirl combinations (P, n, 2)."""
    import scipy.sparse

    sparse = scipy.sparse.issparse(forms.total)       # one large model's forms (n, n), scipy.sparse
    which = None if sparse else _form_rows(forms.total, rows, variants)
    basis = np.stack([shapes[rows, first], shapes[rows, first + 1]], axis=-1)  # (P, n, 2)
    total = _sparse_form(forms.total, basis) if sparse else _pair_form(forms.total, which, basis)
    # the two shapes must span a plane (two inverse iterations could give one direction)
    spans = np.abs(np.linalg.det(total)) > 1e-6 * np.abs(total[:, 0, 0] * total[:, 1, 1])
    rows, first, basis, total = rows[spans], first[spans], basis[spans], total[spans]
    if not rows.size:
        return rows, first, np.zeros((0, shapes.shape[-1], 2), dtype=complex)
    which = which if which is None else which[spans]
    momentum = -1j * (_sparse_form(forms.W, basis) if sparse else _pair_form(forms.W, which, basis))
    mu, resolved = _extreme_whirl(basis, total, momentum)
    whirling = np.abs(mu[:, 1] - mu[:, 0]) > 1e-6
    return rows[whirling], first[whirling], resolved[whirling]


def _form_rows(form, rows, variants):
    """Which of the stacked forms ``form`` (V, n, n) each pair ``rows`` takes (P,): its variant's,
    or its own where the forms are per pair; None where one (n, n) form serves every pair (a 2-D
    form, or a stack of one variant's)."""
    if form.ndim == 2 or (variants is not None and len(form) == 1):
        return None
    return variants[rows] if variants is not None else np.arange(len(rows))


def _pair_form(form, which, basis):
    """``basis_p^H form_p basis_p`` (P, 2, 2) of dense forms (n, n) or (V, n, n) (``form[which]``
    for pair ``p``) and pairs (P, n, 2), each pair's bits its own. One three-operand ``einsum``:
    the shared (n, n) form gives the bits of its copies per pair (tested), without the copies.
    (Two matrix products would cost a fifth, but give other bits, and where the solver's pair
    is already nearly the extreme-whirl pair, as a flexible rotor's at rest, those bits turn
    the resolved shapes' phases.)"""
    one = form if which is None else form[which]
    if one.ndim == 3 and which is None:       # a stack of one variant's forms
        one = one[0]
    rule = "pia,pij,pjb->pab" if one.ndim == 3 else "pia,ij,pjb->pab"
    return np.einsum(rule, basis.conj(), one, basis)


def _sparse_form(form, basis):
    """``basis_p^H form basis_p`` (P, 2, 2) of a ``scipy.sparse`` form (n, n) and pairs (P, n, 2)."""
    count, n, _ = basis.shape
    product = (form @ basis.transpose(1, 0, 2).reshape(n, 2 * count)).reshape(n, count, 2).transpose(1, 0, 2)
    return np.einsum("pia,pib->pab", basis.conj(), product)


def _repeated_pairs(lam):
    """Rows and first columns of the eigenvalues equal to the next one, exactly two equal (not
    three) and not rigid-body zeros; ``lam`` shape (N, m), equal values adjacent. Equal: within
    :data:`REPEATED_TOLERANCE` of the row's largest root and within a part of their own size
    (:func:`._roots.one_root`)."""
    scale = np.abs(lam).max(axis=-1, keepdims=True) + 1e-300
    close = _roots.one_root(lam[..., 1:], lam[..., :-1], REPEATED_TOLERANCE * scale)  # (N, m-1)
    if not close.any():                    # the usual case: no repeated eigenvalue at all
        return close.nonzero()
    pair = close.copy()                    # not part of three equal: its neighbours not close
    pair[:, 1:] &= ~close[:, :-1]
    pair[:, :-1] &= ~close[:, 1:]
    pair &= lam[:, :-1] != 0                        # not zero roots (made exact, _roots.snapped)
    return pair.nonzero()


def _extreme_whirl(basis, total, momentum):
    """The combinations of each pair's two shapes with extreme whirl ratio.

    Solves ``momentum v = mu total v`` (both Hermitian, ``total`` positive definite) by a
    Cholesky reduction.

    Returns
    -------
    mu : ndarray, shape (P, 2)
        Whirl ratios, increasing (backward first).
    resolved : ndarray, shape (P, n, 2)
        The combined shapes, unit norm.
    """
    momentum = 0.5 * (momentum + np.conj(np.swapaxes(momentum, -1, -2)))
    factor = np.linalg.cholesky(0.5 * (total + np.conj(np.swapaxes(total, -1, -2))))
    inverse = np.linalg.inv(factor)
    reduced = inverse @ momentum @ np.conj(np.swapaxes(inverse, -1, -2))
    mu, vectors = np.linalg.eigh(reduced)
    combinations = np.conj(np.swapaxes(inverse, -1, -2)) @ vectors  # (P, 2, 2)
    resolved = basis @ combinations  # (P, n, 2)
    resolved /= np.linalg.norm(resolved, axis=1, keepdims=True)
    return mu, resolved


#: a root whose estimated relative error (:func:`pencil_round_off`) exceeds this is polished first
#: (:func:`refined_pairs`): one part in a million, the sixth significant digit of a frequency, which
#: the CSV files print and which a comparison of two designs or of a model with a test reads; and
#: warned of where the polish leaves one over it (:func:`warn_of_inexact_roots`, which then gives
#: every mode left over :data:`POLISH_LEVEL` its own bound)
INEXACT_LEVEL = 1e-6
#: a root whose estimated relative error (:func:`pencil_round_off`) exceeds this is polished
#: (:func:`refined_pairs`), within :func:`polish_budget`, and a mode left over it is warned of
#: (:func:`warn_of_inexact_roots`): the lowest modes' route polishes its roots
#: to it (:mod:`._lowest_newton`), so the full solve's agree with them, real parts (log decrements,
#: thresholds) included; those above :data:`INEXACT_LEVEL` first
POLISH_LEVEL = 1e-9


def pencil_round_off(values, shapes, mass, damping, stiffness, noise=None, branches=None) -> np.ndarray:
    """How far double precision can move each root of a dense eigen-solve, relative [-]: the
    first-order change of the root under a change of every entry of the pencil
    ``M s^2 + D s + K`` by ``eps`` of itself, for the root's own shape,
    ``eps |x|^T (|s|^2 |M| + |s| |D| + |K|) |x| / (|s| |x^H (2 s M + D) x|)`` (as the lowest
    modes' polish takes it, :func:`._lowest_newton._roundoff`), and at least the solve's own
    ``noise / |s|`` (:func:`._roots.round_off`, the backward error of the state matrix's QR), and at
    least the size of the solve's own first Newton correction (:func:`_newton_step`: the QR is
    backward stable for the state matrix, not for the pencil, and a lightly damped close pair can
    be off by 130 times the first-order term).

    The state matrix holds ``M^-1 K``: forming it rounds each product of a low mode's smooth
    shape with a stiff element (a 1 mm shaft section: terms 1e12 times their sum) to ``eps`` of
    the terms, not of the sum, and the root moves by that ratio whatever the solver (a 10 m shaft
    with a 1 mm section: 2e-4 for its lowest pair, whose roots ``eig`` gave 6.6e-5 and 4.7e-5 off).
    Near a root of the pencil the change is at most this much for an undamped (Hermitian) pencil
    even where two roots are closer than it (Weyl); a damped pair closer than its round-off can
    move by more (``docs/theory.md``, "Close roots").

    Parameters
    ----------
    values : ndarray, shape (..., m), complex [1/s]
        The roots of one speed, or of several (leading dimensions, e.g. (P,) speeds, each with
        its own ``damping`` and ``stiffness``: one batched product, not a loop over speeds).
    shapes : ndarray, shape (..., m, n), complex (any scale)
    mass, damping, stiffness : ndarray, shape (n, n) or (..., n, n)
        ``M``, ``D = C + Omega G`` (speed-dependent bearings' damping included) and ``K`` at the speed.
    noise : float, optional
        The solve's absolute round-off [1/s].
    branches : (ndarray (b, k, k), ndarray (b,)), optional
        Maxwell branches' stiffness ``K_t`` on the first ``k`` coordinates (the stator's,
        :func:`branch_terms`) and times ``tau_t`` [s]: the pencil is then the rational
        ``M s^2 + D s + K + sum_t K_t s tau_t / (1 + s tau_t)`` (the Schur complement of the state
        matrix's linear pencil on the branches' own states), each term's size and derivative
        counted as the others'; a root of the branches' own states (at a pole ``s = -1 / tau``,
        or without displacement) is not estimated (0).

    Returns
    -------
    ndarray, shape (..., m): 0 for a zero root
    """
    x = np.swapaxes(np.asarray(shapes), -1, -2)            # (..., n, m)
    s = np.asarray(values)
    m = x.shape[-1]
    a = np.abs(x)
    size = np.abs(s)
    terms = (size * size * np.einsum("...im,...im->...m", a, np.abs(mass) @ a)
             + size * np.einsum("...im,...im->...m", a, np.abs(damping) @ a)
             + np.einsum("...im,...im->...m", a, np.abs(stiffness) @ a))
    # real products of the real matrices with both parts (a complex product would cost twice as much)
    parts = np.concatenate([x.real, x.imag], axis=-1)
    Mx, Dx, Kx = mass @ parts, damping @ parts, stiffness @ parts
    Mx, Dx, Kx = Mx[..., :m] + 1j * Mx[..., m:], Dx[..., :m] + 1j * Dx[..., m:], Kx[..., :m] + 1j * Kx[..., m:]
    slope = np.einsum("...im,...im->...m", x.conj(), 2.0 * s[..., None, :] * Mx + Dx)
    parts = None
    if branches is not None:
        stiff = np.asarray(branches[0])
        k = stiff.shape[-1]
        As = a[..., None, :k, :]                                                      # (..., 1, k, m)
        sizes = np.einsum("...tim,...tim->...tm", As, np.abs(stiff) @ As)
        parts = _branch_parts(s, x, branches)             # shared with the Newton step's estimate
        with np.errstate(divide="ignore", invalid="ignore"):
            terms = terms + np.sum(np.abs(parts[1]) * sizes, axis=-2)
            slope = slope + np.sum(parts[2] * parts[3], axis=-2)
    derivative = np.abs(slope)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = np.finfo(float).eps * terms / (size * derivative)
        if noise is not None:
            out = np.maximum(out, noise / size)
        step = _newton_step(s, x, Mx, Dx, Kx, branches, parts) / size
    out = np.nan_to_num(out, nan=np.inf, posinf=np.inf)
    out = np.where(np.isfinite(out) & np.isfinite(step), np.maximum(out, step), out)
    if branches is not None:            # a root of the branches' own states (at a pole, s = -1/tau, or with
        out = np.where(np.isfinite(out), out, 0.0)     # no displacement): not estimated
    return np.where(size > 0, out, 0.0)


def _branch_parts(s, x, branches):
    """The Maxwell branches' terms at roots ``s`` (..., m) on shapes ``x`` (..., n, m), for
    :func:`pencil_round_off` and :func:`_newton_step`: ``K_t x`` (..., b, k, m) on the first ``k``
    coordinates, the factors ``s tau_t / (1 + s tau_t)`` and their derivatives ``tau_t / (1 + s
    tau_t)^2`` (..., b, m), and the forms ``x^H K_t x`` (..., b, m) (``branches`` as
    :func:`branch_terms`)."""
    stiff, times = np.asarray(branches[0]), np.asarray(branches[1])
    k = stiff.shape[-1]
    Bx = stiff @ x[..., None, :k, :]                                    # (..., b, k, m)
    tau, at = times[:, None], s[..., None, :]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        value, slope = at * tau / (1.0 + at * tau), tau / (1.0 + at * tau) ** 2             # (..., b, m)
    xb = np.einsum("...tim,...im->...tm", Bx, x[..., :k, :].conj())   # x^H K_t x, (..., b, m)
    return Bx, value, slope, xb


def _newton_step(s, x, Mx, Dx, Kx, branches=None, parts=None) -> np.ndarray:
    """The size of the first Newton correction of each root [1/s], shape (..., m): the smaller
    root ``mu`` of ``det(Q^H T(s) Q + mu Q^H T'(s) Q) = 0`` on the plane ``Q`` of the root's shape
    and its nearest neighbour's (by frequency, the closer in the complex plane of the two beside
    it) where that neighbour is within :data:`_PLANE_GAP` (relative) and the two shapes are not
    nearly parallel; elsewhere on the shape alone, ``|x^H T(s) x| / |x^H T'(s) x|``.

    The state matrix's QR is backward stable for the state matrix, not for the pencil: a root can
    be off by far more than :func:`pencil_round_off`'s first-order term says (a lightly damped
    pair 1.1e-5 apart of a rotor on 1e12 N/m bearings: 1.9e-6 off against 1.4e-8). The solve's
    own residual ``T(s) x`` says how far; its projection on the shape (a Rayleigh-quotient step)
    measures a single root's error to a few per cent, and on the pair's plane a close pair's
    (where the shape alone saw a third of it). Its own round-off is :func:`pencil_round_off`'s.
    Two roots within :data:`_DEFECTIVE_GAP` with nearly parallel shapes may be one defective root
    that round-off split (a Jordan block has one shape): at least twice their distance.

    Parameters
    ----------
    s : ndarray, shape (..., m), complex [1/s]
    x : ndarray, shape (..., n, m), complex
        The shapes, as columns.
    Mx, Dx, Kx : ndarray, shape (..., n, m), complex
        ``M x``, ``D x`` and ``K x``.
    branches : (ndarray (b, k, k), ndarray (b,)), optional
        Maxwell branches (:func:`branch_terms`).
    parts : tuple, optional
        :func:`_branch_parts` of ``s``, ``x`` and ``branches`` where the caller has them.

    Returns
    -------
    ndarray, shape (..., m) [1/s]
    """
    m = x.shape[-1]
    Bx = value = slope = xb = None
    if branches is not None:           # the branches' terms at each root, on the shapes
        Bx, value, slope, xb = _branch_parts(s, x, branches) if parts is None else parts

    def form(a, b):                                   # a^H b over the coordinates, (..., m)
        return np.einsum("...im,...im->...m", a.conj(), b)

    xm, xd, xk = form(x, Mx), form(x, Dx), form(x, Kx)
    a11, b11 = s * s * xm + s * xd + xk, 2.0 * s * xm + xd
    if branches is not None:
        a11, b11 = a11 + np.sum(value * xb, axis=-2), b11 + np.sum(slope * xb, axis=-2)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = np.abs(a11 / b11)
        near = _nearest_by_frequency(s)
        gap = np.abs(np.take_along_axis(s, near, axis=-1) - s) / np.abs(s)
    plane = (gap < _PLANE_GAP) & (near != np.arange(m))
    if plane.any():
        pair = _plane_step(s, x, Mx, Dx, Kx, Bx, value, slope, near, (xm, xd, xk), xb)
        out = np.where(plane & np.isfinite(pair), pair, out)
        # nearly parallel shapes of two roots this close: one defective root split by round-off
        split = plane & ~np.isfinite(pair) & (gap < _DEFECTIVE_GAP)
        if split.any():
            out = np.where(split, np.maximum(out, 2.0 * gap * np.abs(s)), out)
    return np.where(np.isfinite(out), out, np.inf)


def _plane_step(s, x, Mx, Dx, Kx, Bx, value, slope, near, own, own_branches):
    """:func:`_newton_step` on the plane of each root's shape ``x`` (..., n, m) and its neighbour
    ``near``'s (..., m): the smaller root of ``det(V^H T V + mu V^H T' V) = 0``, ``V`` the two shapes
    as they are (the roots do not depend on the plane's basis), from forms of the shapes with
    ``Mx``, ``Dx``, ``Kx`` (..., n, m), the branches' ``Bx`` (..., b, k, m) with ``value`` and
    ``slope`` (..., b, m), and each shape's own forms ``own`` (three (..., m)) and
    ``own_branches`` (..., b, m); inf where the two shapes are nearly parallel (sine below
    :data:`_PLANE_WIDTH`)."""
    def gathered(a):
        return np.take_along_axis(a, near[..., None, :], axis=-1)

    def form(a, b):
        return np.einsum("...im,...im->...m", a.conj(), b)

    y = gathered(x)
    xy, yx = [], []                   # x^H A y and y^H A x for A = M, D, K
    for A_x in (Mx, Dx, Kx):
        xy.append(form(x, gathered(A_x)))
        yx.append(form(y, A_x))
    yy = [np.take_along_axis(f, near, axis=-1) for f in own]
    xx = list(own)

    def pencil(f, root):              # (T, T') from the forms (M, D, K) of a pair of shapes
        return root * root * f[0] + root * f[1] + f[2], 2.0 * root * f[0] + f[1]

    (a11, b11), (a12, b12), (a21, b21), (a22, b22) = (pencil(f, s) for f in (xx, xy, yx, yy))
    if Bx is not None:
        k = Bx.shape[-2]
        By = np.take_along_axis(Bx, near[..., None, None, :], axis=-1)       # K_t y, (..., b, k, m)
        terms = (own_branches, np.einsum("...im,...tim->...tm", x[..., :k, :].conj(), By),
                 np.einsum("...im,...tim->...tm", y[..., :k, :].conj(), Bx),
                 np.take_along_axis(own_branches, near[..., None, :], axis=-1))
        a11, a12, a21, a22 = (a + np.sum(value * t, axis=-2) for a, t in zip((a11, a12, a21, a22), terms))
        b11, b12, b21, b22 = (b + np.sum(slope * t, axis=-2) for b, t in zip((b11, b12, b21, b22), terms))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        sizes = np.real(form(x, x) * form(y, y))
        width = 1.0 - np.abs(form(x, y)) ** 2 / sizes                       # the sine squared
        # det(A + mu B) = qa mu^2 + qb mu + qc; its smaller root 2 qc / (-qb -+ sqrt(qb^2 - 4 qa qc))
        qa, qb, qc = b11 * b22 - b12 * b21, a11 * b22 + a22 * b11 - a12 * b21 - a21 * b12, a11 * a22 - a12 * a21
        r = np.sqrt(qb * qb - 4.0 * qa * qc)
        below = np.where(np.abs(-qb - r) >= np.abs(-qb + r), -qb - r, -qb + r)
        pair = np.abs(2.0 * qc / below)
    return np.where(width >= _PLANE_WIDTH ** 2, pair, np.inf)


#: the largest distance (relative) to a root's neighbour at which :func:`_newton_step` takes their
#: plane (farther, the shape alone): over 40 random ROSS rotors the error was at most 2.0 times the
#: estimate with the plane for every root within its own size, 3.9 times with it within 1e-2 only
_PLANE_GAP = 1.0
#: the largest distance (relative) between two roots with nearly parallel shapes that
#: :func:`_newton_step` takes for the split of one defective root (a Jordan block: Friswell 5.9.4 at
#: rest, whose double roots round-off splits by 3.8e-7), estimated at twice their distance
_DEFECTIVE_GAP = 1e-5
#: the least width (sine of the angle) of a root's shape and its neighbour's for
#: :func:`_newton_step` to take their plane (nearly parallel shapes: the shape alone)
_PLANE_WIDTH = 1e-2


def _nearest_by_frequency(s):
    """Each root's neighbour (indices (..., m) into the last axis of ``s`` (..., m)): of the two
    beside it by frequency, the closer in the complex plane; itself where it is alone."""
    m = s.shape[-1]
    if m < 2:
        return np.zeros(s.shape, dtype=int)
    order = np.argsort(s.imag, axis=-1, kind="stable")
    ranked = np.take_along_axis(s, order, axis=-1)
    before = np.concatenate([order[..., :1], order[..., :-1]], axis=-1)
    after = np.concatenate([order[..., 1:], order[..., -1:]], axis=-1)
    gap_before = np.abs(ranked - np.take_along_axis(s, before, axis=-1))
    gap_after = np.abs(ranked - np.take_along_axis(s, after, axis=-1))
    gap_before[..., 0], gap_after[..., -1] = np.inf, np.inf
    chosen = np.where(gap_before <= gap_after, before, after)
    out = np.empty_like(order)
    np.put_along_axis(out, order, chosen, axis=-1)
    return out


def branch_terms(form):
    """A form's Maxwell branches for :func:`pencil_round_off` and :func:`refined_pairs`: their
    stiffness on the stator's coordinates, the first ``k`` (b, k, k), and times (b,) [s]; None
    without branches (not the (b, n, n) ``form.branch_stiffness``: 16 branches of a 2,000-coordinate
    model would hold 512 MB)."""
    if not len(form.branch_times):
        return None
    k = form.model.dofs.n_frame
    return np.asarray(form.branch_blocks)[:, :k, :k], np.asarray(form.branch_times)


def round_off_at(form, speed, values, shapes):
    """The round-off of one speed's roots (:func:`pencil_round_off`) and the pencil it is taken on,
    for :func:`refined_pairs` to polish them.

    Parameters
    ----------
    form : SpeedLinearForm
    speed : float
        The speed [rad/s].
    values : ndarray, shape (m,), complex
        The roots [1/s].
    shapes : ndarray, shape (m, n), complex
        Their shapes.

    Returns
    -------
    bound : ndarray, shape (m,)
        Each root's round-off [1/s].
    damping, stiffness : ndarray, shape (n, n)
        The pencil's damping (gyroscopic terms at ``speed`` included) and stiffness at ``speed``.
    branches : tuple or None
        The form's Maxwell branches (:func:`branch_terms`).
    """
    branches = branch_terms(form)
    stiffness, damping = form.pencil_at(np.array([speed]))
    damping = damping + speed * form.matrices.G
    damping, stiffness = damping.reshape(damping.shape[-2:]), stiffness.reshape(stiffness.shape[-2:])
    bound = pencil_round_off(values, shapes, form.matrices.M, damping, stiffness, branches=branches)
    return bound, damping, stiffness, branches


def refined_pairs(values, shapes, mass, damping, stiffness, bound, forms=None, variant=None, branches=None,
                  whirl=None):
    """The roots of one speed whose round-off ``bound`` (:func:`pencil_round_off`) exceeds
    :data:`POLISH_LEVEL`, polished in place on the quadratic pencil: those whose neighbour in
    frequency is closer than it together, as a cluster (:func:`_clusters`,
    :func:`._lowest_newton.pair_polished`: block Newton steps with the residual's stiffness term
    summed exactly; on a sparse pencil :func:`sparse_block_polished`), the single roots all at once
    (:func:`single_roots_polished`: the same steps for one root, its shape's phase kept, every
    root's residual in one product; the real ones with them, kept on the real axis,
    :func:`_singles_polished`), a run of real roots closer than their round-off as a cluster
    (:func:`_real_cluster`: a conjugate pair the solve snapped to the real axis); every root of a
    well-conditioned machine untouched. Those over
    :data:`INEXACT_LEVEL` first, then the others, each lowest first, within :func:`polish_budget` a
    speed (:func:`._polish_plan.run_work`: a single root 0.2 of a root's :func:`polish_work`, a
    root on a sparse pencil 0.02 of a solve; a small machine's, or a sparse one's, every root over
    1e-9 fits): past it the roots keep their bound (and are warned of,
    :func:`warn_of_inexact_roots`), but for a defective double root split by round-off
    (:func:`_defective_mean`).

    Parameters
    ----------
    values : ndarray, shape (m,), complex [1/s]
    shapes : ndarray, shape (m, n), complex, unit norm
    mass, damping, stiffness : ndarray, shape (n, n)
    bound : ndarray, shape (m,)
    forms : WhirlForms, optional
        Where given, a pair polished into one root (a double root: the machine at rest) has its
        shapes made the extreme-whirl pair (:func:`resolve_repeated`; the polish's basis of the
        plane is any), ``variant`` the row's variant where the forms are stacked.
    branches : (ndarray (b, k, k), ndarray (b,)), optional
        Maxwell branches (:func:`branch_terms`): every root polished on the rational pencil
        (single roots by :func:`._lowest_newton.rational_root_polished`, clusters by the same
        block Newton steps with the branches' terms).
    whirl : ndarray, shape (m,), optional
        How far round-off can move each root's whirl ratio (:func:`ratio_round_off`, the solve's):
        the polished roots' replaced in place by their own (:func:`polished_ratio_round_off`).

    Returns
    -------
    ndarray, shape (m,): ``bound``, the polished roots' the error the polish leaves (a root the
    polish could not converge keeps its bound; so do both roots of a pair it could not separate)
    """
    bound = np.array(bound, dtype=float)
    # a real root (a relaxation) too, with the single complex roots (below), not a zero root
    wanted = np.flatnonzero((bound > POLISH_LEVEL) & (np.asarray(values).imag >= 0) & (np.asarray(values) != 0))
    if not len(wanted):
        return bound
    mass, damping, stiffness = (matrix.toarray() if hasattr(matrix, "toarray") else np.asarray(matrix)
                                for matrix in (mass, damping, stiffness))
    n = mass.shape[0]
    spent, budget = 0.0, polish_budget(n)
    polished = np.zeros(len(bound), dtype=bool)
    # the complex roots' clusters and the real roots' apart (a real root is never polished with a complex one)
    real = values[wanted].imag == 0
    runs = [run for part in (wanted[~real], wanted[real]) if len(part)
            for run in _clusters(values, bound, part[np.lexsort((values[part].real, values[part].imag))])]
    # those a frequency's sixth digit could read wrong first, the modes before the real roots (the
    # budget is spent lowest first)
    runs.sort(key=lambda run: (not np.any(bound[run] > INEXACT_LEVEL), bool(np.any(values[run].imag == 0))))
    sparse = branches is None and _sparse(mass, damping, stiffness)
    singles = []       # the single roots the budget takes (complex and real), polished at once after the loop
    for run in runs:
        if len(run) == 1:
            work = run_work(1, n, sparse)
            if spent + work <= budget:
                spent += work
                singles.append(run[0])
            continue
        # real roots closer than their round-off: a conjugate pair the solve snapped to the real axis,
        # or a double real root; polished as a cluster (complex arithmetic), kept on the real axis
        alone = bool(values[run[0]].imag == 0)
        work = run_work(len(run), n, sparse)
        if spent + work > budget:      # left as the solve gave it (warned of, with its bound), but for
            # a defective double root split by round-off: the split's mean, at no cost
            if len(run) == 2 and not alone and _defective_mean(values, shapes, bound, run, mass, damping, stiffness,
                                                               branches):
                polished[run] = True
                if forms is not None:
                    shapes[run] = resolve_repeated(values[run][None], shapes[run][None], forms,
                                                   None if variant is None else np.array([variant]), groups=False)[0]
            continue
        spent += work
        defective = len(run) == 2 and _parallel(shapes[run[0]], shapes[run[1]])
        found = _cluster_polished(mass, damping, stiffness, values[run], shapes[run], branches)
        if found is None:
            continue
        if alone:
            polished[run] = _real_cluster(values, shapes, bound, run, found, defective)
            continue
        values[run], shapes[run], bound[run] = found
        polished[run] = True
        if defective:
            _one_defective_root(values, bound, run)
        if forms is not None and len(run) == 2:
            shapes[run] = resolve_repeated(values[run][None], shapes[run][None], forms,
                                           None if variant is None else np.array([variant]), groups=False)[0]
    for a in _singles_polished(values, shapes, bound, polished, np.array(singles, dtype=int), mass, damping,
                               stiffness, branches):
        # a single root whose steps did not converge: a neighbour near its round-off (a gap of a
        # few times it slows them to a crawl) polished with it, as a pair
        if spent + run_work(2, n, sparse) > budget:
            continue
        spent += run_work(2, n, sparse)
        pair = np.array([a, _nearest_other(values, a)])
        found = _cluster_polished(mass, damping, stiffness, values[pair], shapes[pair], branches)
        if found is not None:
            values[pair], shapes[pair], bound[pair] = found
            polished[pair] = True
    if whirl is not None and polished.any():        # never above the solve's
        whirl[polished] = np.minimum(whirl[polished], polished_ratio_round_off(values, polished, bound))
    return bound


def _singles_polished(values, shapes, bound, polished, which, mass, damping, stiffness, branches=None):
    """:func:`refined_pairs`'s single roots ``which`` (indices), complex and real, polished in place
    at once by :func:`single_roots_polished`, ``polished`` (m,) set where they were; returns the
    complex ones whose steps did not converge.

    A real root (a relaxation of rubber mounts, an overdamped root) is kept on the real axis, its
    error left the polish's plus its polished imaginary part (relative), where its steps converge within
    :data:`_REAL_REACH` times its bound of its start, nearer it than any other root's start (not
    another root's), and not at a Maxwell branch's pole (a root of the branches' own states, which
    no step on the pencil reaches: left as it is). Until roots33 each real root was polished alone,
    in real arithmetic, after the complex ones."""
    values_in = np.asarray(values).copy()
    real = values_in[which].imag == 0
    if branches is not None and real.any():
        times = np.asarray(branches[1], dtype=float)
        at_pole = real & np.any(np.abs(1.0 + values_in[which].real[:, None] * times[None, :]) <= _POLE, axis=1)
        which, real = which[~at_pole], real[~at_pole]
    if not len(which):
        return which
    found, found_shapes, left = single_roots_polished(mass, damping, stiffness, values[which], shapes[which], branches)
    done = np.isfinite(left)
    for j in np.flatnonzero(done & real):
        a, root = which[j], found[j].real
        start = values_in[a].real
        near = abs(root - start) <= _REAL_REACH * bound[a] * abs(start)
        done[j] = bool(near and np.argmin(np.abs(values_in - root)) == a)
        left[j] = left[j] + abs(found[j].imag) / abs(root) if root != 0 else np.inf
        found[j] = root + 0j
    values[which[done]], shapes[which[done]], bound[which[done]] = found[done], found_shapes[done], left[done]
    polished[which[done]] = True
    return which[~done & ~real]


def _real_cluster(values, shapes, bound, run, found, defective) -> bool:
    """A cluster ``run`` of real roots (sorted, closer than their round-off: a conjugate pair the
    solve's round-off snapped to the real axis, or a double real root) that :func:`_cluster_polished`
    polished into ``found`` (roots, shapes, error left), written in place on the real axis; returns
    whether it was (each polished root within :data:`_REAL_REACH` times its bound of its start).

    Each root is the real part of its polished root; its error left the polish's plus that root's
    imaginary part (relative): the truth is then a conjugate pair whose damping ratio is 1 to about
    1e-17, a relaxation as the table counts it, which the polish locates exactly and the real axis
    holds to its imaginary part. A pair with nearly parallel shapes (``defective``, one defective
    double root) is made its mean (:func:`_one_defective_root`). The Maxwell test model at 3,000
    rpm (``tests/test_exact_roots27l.py``): two such pairs near -33 1/s, -33.111525708 +- 9.0e-8 j
    and -32.925905800 +- 7.7e-8 j (a 40-digit solve); their real parts now to 1e-15, the solve's
    3e-9 and 3.5e-12 off, and until roots33 one root of the first was moved 1.4e-9 off its real
    part by a one-root real Newton (claiming 2.5e-10), the other left."""
    roots, found_shapes, left = found
    order = np.lexsort((roots.imag, roots.real))
    roots, found_shapes = roots[order], found_shapes[order]
    starts = values[run].real
    if not np.all(np.abs(roots - starts) <= _REAL_REACH * bound[run] * np.abs(starts)):
        return False
    out, each = roots.copy(), np.full(len(run), float(left))
    if defective:
        _one_defective_root(out, each, np.arange(2))
    elif len(out) == 2 and out[0].imag * out[1].imag < 0:
        # a conjugate pair: its two polished roots' real parts differ in the last bits with the
        # BLAS's threads (one thread: -33.1115257083708 and -33.11152570837079), its copies one value
        out.real = out.real.mean()
    each = each + np.abs(out.imag) / np.abs(out)         # the triangle: its polished error and the axis's
    values[run], shapes[run], bound[run] = out.real + 0j, found_shapes, each
    return True


def single_roots_polished(mass, damping, stiffness, roots, shapes, branches=None):
    """Single roots ``roots`` (m,) (complex [1/s], each farther from the others than its round-off)
    of the quadratic pencil ``T(s) = M s^2 + D s + K`` (``mass``, ``damping``, ``stiffness`` dense
    (n, n)) with shapes (m, n), polished all at once: what :func:`._lowest_newton.root_polished`
    does for one, the chord steps of Newton's bordered system ``[[T(s), T'(s) x], [x0^H, 0]]``
    (factored once a root, :func:`._lowest_newton.bordered_lu`), the residual's ``K x`` summed
    exactly and its mass and damping terms in ``longdouble``, ``x`` a double-double, but every
    root's residual in one product over the pencil's nonzero entries (:func:`_gathered_sums`).
    ``branches`` (:func:`branch_terms`), where given: on the rational pencil of Maxwell branches,
    ``+ sum_t K_t s tau_t / (1 + s tau_t)`` on the first ``k`` coordinates, as
    :func:`._lowest_newton.rational_root_polished` polishes one root (each ``K_t x`` summed exactly).

    One root at a time, each residual's exact sums cost a Python loop over the ``n`` rows: 0.5 to
    0.9 of the speed's eigen-solve a root at 48 to 240 coordinates, while the LU itself is 0.014 of
    it at 624 coordinates. Together the 16 single roots of the 48-coordinate 1 mm shaft cost about
    0.1 of its solve each; on a sparse pencil the factorisations are sparse
    (:func:`_bordered_solvers`): the cut shaft's 44, about 0.005 each (``docs/theory.md``, "Close
    roots"; :data:`._polish_plan.BATCHED_ROOT_WORK`, :data:`._polish_plan.SPARSE_ROOT_WORK`).

    Returns
    -------
    roots : ndarray, shape (m,), complex; shapes : ndarray, shape (m, n), unit, each with the phase
    of the one given; left : ndarray, shape (m,), the error left (relative), ``inf`` where a step
    failed or the steps did not converge below ``_lowest_newton._PROMISED`` (that root and its
    shape are then as given)
    """
    from ._lowest_newton import _EXTENDED, _PAIR_STEPS, _PROMISED, _round_off_of

    n, m = mass.shape[0], len(roots)
    given = np.asarray(shapes, dtype=complex)
    X = (given / np.linalg.norm(given, axis=1)[:, None]).T.copy()       # (n, m)
    s = np.asarray(roots, dtype=complex).copy()
    solvers = _bordered_solvers(mass, damping, stiffness, branches, s, X)
    low, moved = np.zeros_like(X), np.full(m, np.inf)             # X + low: the shapes as double-doubles
    active = np.array([f is not None for f in solvers])
    failed = ~active
    patterns = [_row_pattern(matrix) for matrix in (mass, damping, stiffness)]
    if branches is not None:        # every branch's rows, (b k, k)
        patterns.append(_row_pattern(np.asarray(branches[0], dtype=float).reshape(-1, np.shape(branches[0])[-1])))
    # a complex root's steps as root_polished's; a real one's up to _REAL_STEPS (chord steps from
    # further off: a relaxation beside a stiff branch)
    steps = np.where(np.asarray(roots).imag == 0, _REAL_STEPS, _PAIR_STEPS + 1)
    for step in range(int(steps.max(initial=0))):
        which = np.flatnonzero(active & (step < steps))
        if not len(which):
            break
        residual = _pencil_residual(patterns, s[which].astype(np.result_type(_EXTENDED, 1j)), X[:, which], low[:, which],
                                    None if branches is None else branches[1])
        for j, a in enumerate(which):
            d = solvers[a](-np.append(residual[:, j], 0.0))
            if not np.all(np.isfinite(d)):
                active[a] = False
                failed[a] = True
                continue
            more = low[:, a] + d[:n]
            high = X[:, a] + more
            X[:, a], low[:, a] = high, more - (high - X[:, a])    # two-sum: X + low the exact sum
            s[a] += d[n]
            moved[a] = abs(d[n]) / abs(s[a])
            active[a] = moved[a] > 4 * np.finfo(float).eps
    done = ~failed & (moved <= _PROMISED)
    out_roots, out_shapes = np.asarray(roots, dtype=complex).copy(), given.copy()
    left = np.full(m, np.inf)
    if done.any():
        unit = (X[:, done] / np.linalg.norm(X[:, done], axis=0)).T
        out_shapes[done] = [_vectors.phase_aligned(u, g) for u, g in zip(unit, given[done])]
        out_roots[done] = s[done]
        inertia = _round_off_of(mass, damping, s[done], unit) * np.finfo(_EXTENDED).eps / np.finfo(float).eps
        left[done] = np.maximum(np.maximum(moved[done], inertia), 4 * np.finfo(float).eps)
    return out_roots, out_shapes, left


def _bordered_solvers(mass, damping, stiffness, branches, roots, X):
    """For each root ``roots[a]`` with its shape ``X[:, a]`` (n,): a function giving the solution
    of Newton's bordered system ``[[T(s), T'(s) x], [x^H, 0]] d = r`` ((n + 1,) complex), factored
    once, or None where it cannot be factored. Where the pencil's entries are sparse (at most
    :data:`_SPARSE_SHARE` of ``T``'s, from :data:`_SPARSE_FROM` coordinates: a meshed shaft) by a
    sparse LU (``scipy.sparse.linalg.splu``; the dense border adds one row and column of fill),
    else by the dense one (:func:`._lowest_newton.bordered_lu`). The 624-coordinate cut shaft (7,406
    of 389,376 entries): 0.0027 s a factorisation where the dense one takes 0.017 to 0.076 s (its
    eigen-solve 1.0 to 1.2 s; one BLAS thread)."""
    import warnings

    import scipy.linalg
    import scipy.sparse
    import scipy.sparse.linalg

    from ._lowest_newton import bordered_lu

    n = mass.shape[0]
    solvers = []
    if not _sparse(mass, damping, stiffness):
        for a, v in enumerate(roots):
            lu = bordered_lu(*_pencil_and_slope(mass, damping, stiffness, branches, v, X[:, a]), X[:, a].conj())
            solvers.append(None if lu is None else
                           (lambda rhs, lu=lu: scipy.linalg.lu_solve(lu, rhs, check_finite=False)))
        return solvers
    pattern = (mass != 0) | (damping != 0) | (stiffness != 0)
    if branches is not None:
        k = np.shape(branches[0])[-1]
        pattern[:k, :k] |= np.any(np.asarray(branches[0]) != 0, axis=0)
    rows, cols = np.nonzero(pattern)
    entries = [matrix[rows, cols] for matrix in (mass, damping, stiffness)]
    if branches is not None:
        inside = np.flatnonzero((rows < k) & (cols < k))
        branch_entries = np.asarray(branches[0], dtype=float)[:, rows[inside], cols[inside]]     # (b, e)
    for a, v in enumerate(roots):
        T = entries[0] * v * v + entries[1] * v + entries[2] + 0j
        slope = 2.0 * v * (mass @ X[:, a]) + damping @ X[:, a]
        if branches is not None:
            times = np.asarray(branches[1], dtype=float)
            T[inside] += (v * times / (1.0 + v * times)) @ branch_entries
            slope[:k] += np.einsum("t,tij,j->i", times / (1.0 + v * times) ** 2, np.asarray(branches[0], dtype=float),
                                   X[:k, a])
        J = scipy.sparse.bmat([[scipy.sparse.csc_matrix((T, (rows, cols)), shape=(n, n)), slope[:, None]],
                               [X[:, a].conj()[None, :], None]], format="csc")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
                lu = scipy.sparse.linalg.splu(J)
        except RuntimeError:               # exactly singular
            solvers.append(None)
            continue
        solvers.append(lu.solve)
    return solvers


#: coordinates from which :func:`_bordered_solvers` may factor sparsely
_SPARSE_FROM = 100
#: the largest share of the pencil's entries that are nonzero for a sparse factorisation
_SPARSE_SHARE = 0.05


def _pencil_and_slope(mass, damping, stiffness, branches, s, x):
    """``T(s)`` (n, n) complex and ``T'(s) x`` (n,) of the quadratic pencil, with the Maxwell
    branches' terms (:func:`branch_terms`) on their first ``k`` coordinates where given."""
    T = mass * s * s + damping * s + stiffness + 0j
    slope = 2.0 * s * (mass @ x) + damping @ x
    if branches is not None:
        K_t, times = branches
        k = np.shape(K_t)[-1]
        for K, tau in zip(np.asarray(K_t, dtype=float), times):
            T[:k, :k] += s * tau / (1.0 + s * tau) * K
            slope[:k] += tau / (1.0 + s * tau) ** 2 * (K @ x[:k])
    return T, slope


def _row_pattern(matrix):
    """Each row's nonzero entries of a dense ``matrix`` (n, n), first in the row: their columns and
    values, (n, w) each (``w`` the most of a row, at least 1; a shorter row padded with column 0 and
    value 0, which adds nothing to a sum)."""
    nonzero = matrix != 0
    width = max(1, int(nonzero.sum(axis=1).max(initial=0)))
    columns = np.argsort(~nonzero, axis=1, kind="stable")[:, :width]
    return columns, np.take_along_axis(matrix, columns, axis=1).astype(float)


def _pencil_residual(patterns, s, X, low, times=None):
    """``M x s^2 + D x s + K x`` for each root ``s`` (k,) (``_EXTENDED`` complex) and its shape
    ``x + low`` (columns of ``X``, ``low`` (n, k), a double-double), rounded to complex (n, k): the
    products by :func:`_gathered_products`; ``patterns`` are :func:`_row_pattern`'s of ``M``, ``D``,
    ``K`` (and, with the Maxwell branches' ``times`` (b,) [s], of their stacked ``K_t`` (b q, q):
    ``+ sum_t K_t x s tau_t / (1 + s tau_t)`` on the first ``q`` rows, ``K_t x`` summed exactly)."""
    mass, damping, stiff = _gathered_products(patterns, X, low, s.dtype)
    out = (mass * s * s + damping * s + stiff).astype(complex)
    if times is not None:
        out += _branches_residual(patterns[3], s, X, low, times)
    return out


def _gathered_products(patterns, X, low, wide):
    """``M X``, ``D X`` and ``K X`` (n, k) each, in the complex precision ``wide``, of ``X + low``
    (n, k) (a double-double) and the dense matrices whose :func:`_row_pattern` are ``patterns``:
    ``K X`` summed exactly (:func:`_gathered_sums`; a low mode's smooth shape against a stiff
    element cancels its terms by up to 1e12), ``K low``, ``M X`` and ``D X`` in ``wide``. The rows
    go in groups of like width (:func:`_width_groups`), each padded to its own widest row."""
    n, k = X.shape
    (mc, mv), (dc, dv), (kc, kv) = patterns[:3]
    real = np.real(np.zeros(1, wide)).dtype
    Xw, lw = X.astype(wide) + low.astype(wide), low.astype(wide)
    parts = np.concatenate([X.real, X.imag], axis=1)        # (n, 2k)
    out = [np.empty((n, k), wide) for _ in range(3)]
    for group, (wm, wd, wk) in _width_groups(patterns[:3]):
        width = max(wm, wd, wk)
        # the gathered (r, w, k) terms of a part of the group's rows at a time (a dense pencil: w = n)
        for part in _batches.chunk_slices(len(group), _GATHER_BYTES * width * k, budget=_batches._PART_BYTES):
            rows = group[part]
            out[0][rows] = np.einsum("rw,rwk->rk", mv[rows, :wm].astype(real), Xw[mc[rows, :wm]])
            out[1][rows] = np.einsum("rw,rwk->rk", dv[rows, :wd].astype(real), Xw[dc[rows, :wd]])
            exact = _gathered_sums(kv[rows, :wk], parts[kc[rows, :wk]])
            out[2][rows] = np.einsum("rw,rwk->rk", kv[rows, :wk].astype(real), lw[kc[rows, :wk]]) \
                + (exact[:, :k] + 1j * exact[:, k:]).astype(wide)
    return out


def _width_groups(patterns):
    """The rows of :func:`_row_pattern`'s ``patterns`` (of ``M``, ``D``, ``K``) in groups, each with
    the widths (three ints) its rows need of each pattern: all rows at the patterns' own widths,
    but where a few rows are far wider than the rest (a casing's rows, coupled to every rotor:
    padded to them, every row of a machine of 448 coordinates cost as a full one, a single root's
    polish about one eigen-solve of the speed), the rows up to :data:`_WIDE_ROW` times the 90th
    percentile's width apart from the wider ones."""
    counts = np.stack([np.count_nonzero(values, axis=1) for _, values in patterns])      # (3, n)
    widths = [values.shape[1] for _, values in patterns]
    n = counts.shape[1]
    rows = counts.max(axis=0)
    limit = _WIDE_ROW * max(1.0, float(np.percentile(rows, 90))) if n else 0.0
    if not n or rows.max() <= limit:
        return [(np.arange(n), widths)]
    narrow = rows <= limit
    groups = []
    for chosen in (narrow, ~narrow):
        index = np.flatnonzero(chosen)
        groups.append((index, [max(1, int(c[index].max())) for c in counts]))
    return groups


#: how many times the 90th percentile's row width a row may be before :func:`_width_groups` takes
#: the wider rows apart
_WIDE_ROW = 4.0


def sparse_block_polished(mass, damping, stiffness, roots, shapes):
    """:func:`._lowest_newton.block_polished` (Newton's steps for an invariant pair ``(X, S)`` of
    ``k`` close roots, ``M X S^2 + D X S + K X = 0``, ``W^H X = I``) on a sparse pencil (dense
    (n, n) arrays whose nonzero entries are few: a meshed shaft), without Maxwell branches: the
    Jacobian's ``kron(S^2^T, M) + kron(S^T, D) + kron(I, K)`` factored sparsely
    (``scipy.sparse.linalg.splu``) and the residual over the nonzero entries
    (:func:`_gathered_products`, ``K X`` summed exactly), where the dense one solves ``k n + k^2``
    unknowns densely and sums each row in Python. Same steps, same returns (None where a step
    fails or the last is above ``_lowest_newton._PROMISED``)."""
    import warnings

    import scipy.sparse
    import scipy.sparse.linalg

    from ._lowest_newton import _EXTENDED, _PAIR_STEPS, _PROMISED, _round_off_of

    n, k = mass.shape[0], len(roots)
    wide = np.result_type(_EXTENDED, 1j)
    basis, triangle = np.linalg.qr(np.asarray(shapes).T)
    X, S = basis, triangle @ np.diag(roots) @ np.linalg.inv(triangle)
    W, Ik = basis.conj(), np.eye(k)
    low = np.zeros_like(X)
    patterns = [_row_pattern(matrix) for matrix in (mass, damping, stiffness)]
    M, D, K = (scipy.sparse.csr_matrix(matrix) for matrix in (mass, damping, stiffness))
    moved = np.inf
    for _ in range(_PAIR_STEPS):
        MX, DX, KX = _gathered_products(patterns, X, low, wide)
        Sw = S.astype(wide)
        residual = (MX @ Sw @ Sw + DX @ Sw + KX).astype(complex)
        right = -np.concatenate([residual.reshape(-1, order="F"), np.zeros(k * k)])
        top = scipy.sparse.kron((S @ S).T, M) + scipy.sparse.kron(S.T, D) + scipy.sparse.kron(Ik, K)
        MXd = M @ X
        J = scipy.sparse.bmat([[top, np.kron(S.T, MXd) + np.kron(Ik, MXd @ S + D @ X)],
                               [np.kron(Ik, W.T), None]], format="csc")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", scipy.sparse.linalg.MatrixRankWarning)
                d = scipy.sparse.linalg.splu(J).solve(right)
        except RuntimeError:
            return None
        if not np.all(np.isfinite(d)):
            return None
        more = low + d[:k * n].reshape((n, k), order="F")
        high = X + more
        X, low = high, more - (high - X)                   # two-sum: X + low the exact sum
        step = d[k * n:].reshape((k, k), order="F")
        S = S + step
        moved = np.abs(step).max() / np.abs(S).max()
    if not moved <= _PROMISED:
        return None
    found, combinations = np.linalg.eig(S)
    order = np.argsort(found.imag) if k < 2 or roots[0].imag <= roots[1].imag else np.argsort(-found.imag)
    shapes = _vectors.unit_rows((X @ combinations[:, order]).T)
    inertia = np.max(_round_off_of(mass, damping, found[order], shapes)) * np.finfo(_EXTENDED).eps / np.finfo(float).eps
    return found[order], shapes, max(moved, inertia, 4 * np.finfo(float).eps)


def _sparse(mass, damping, stiffness) -> bool:
    """Whether a pencil (dense (n, n) each) is factored sparsely (:func:`_bordered_solvers`,
    :func:`sparse_block_polished`): from :data:`_SPARSE_FROM` coordinates, at most
    :data:`_SPARSE_SHARE` of its entries nonzero."""
    n = mass.shape[0]
    return n >= _SPARSE_FROM and int(((mass != 0) | (damping != 0) | (stiffness != 0)).sum()) <= _SPARSE_SHARE * n * n


def _cluster_polished(mass, damping, stiffness, roots, shapes, branches=None):
    """A cluster of close roots polished as a block: :func:`sparse_block_polished` on a sparse
    pencil without branches (:func:`_sparse`), else :func:`._lowest_newton.pair_polished`."""
    if branches is None and _sparse(mass, damping, stiffness):
        return sparse_block_polished(mass, damping, stiffness, roots, shapes)
    from ._lowest_newton import pair_polished

    return pair_polished(mass, damping, stiffness, roots, shapes, branches)


def _branches_residual(pattern, s, X, low, times):
    """The Maxwell branches' part of :func:`_pencil_residual`, (n, k) complex: ``sum_t K_t x s tau_t
    / (1 + s tau_t)`` on the first ``q`` rows, ``pattern`` :func:`_row_pattern`'s of the stacked
    ``K_t`` (b q, q), each ``K_t x`` summed exactly and ``K_t low`` in ``s``'s precision."""
    columns, entries = pattern
    wide, (n, k), b = s.dtype, X.shape, len(times)
    q = len(columns) // b
    real = np.real(np.zeros(1, wide)).dtype
    parts = np.concatenate([X[:q].real, X[:q].imag], axis=1)[columns]              # (b q, w, 2k)
    exact = _gathered_sums(entries, parts)
    products = (exact[:, :k] + 1j * exact[:, k:]).astype(wide) \
        + np.einsum("rw,rwk->rk", entries.astype(real), low[:q].astype(wide)[columns])
    tau = np.asarray(times, dtype=real)[:, None]
    ratios = s[None, :] * tau / (1 + s[None, :] * tau)                           # (b, k)
    out = np.zeros((n, k), complex)
    out[:q] = np.einsum("tk,tqk->qk", ratios, products.reshape(b, q, k)).astype(complex)
    return out


#: work memory of :func:`_pencil_residual` per row, gathered entry and root [bytes]
_GATHER_BYTES = 400


def _gathered_sums(values, parts):
    """``sum_w values[r, w] parts[r, w, :]`` (r, c) of doubles ``values`` (r, w) and ``parts`` (r, w, c),
    each within ``eps`` of itself plus ``w eps^2`` of its terms' magnitudes: the products exact
    (Dekker's splitting, :func:`._lowest_newton._halves`) and summed in pairs with their rounding
    errors kept (``TwoSum`` in a tree, the errors added at the end), as
    :func:`._lowest_newton._exact_sums` sums a dense matrix's rows."""
    from ._lowest_newton import _halves, tree_sum

    a_hi, a_lo = _halves(values[:, :, None])
    b_hi, b_lo = _halves(parts)
    p = values[:, :, None] * parts
    e = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo
    terms = np.concatenate([p, e], axis=1)                  # (r, 2w, c)
    return tree_sum(terms)


def _parallel(x, y) -> bool:
    """Whether two shapes (n,) are nearly parallel: the sine of their angle below
    :data:`_PLANE_WIDTH` (two roots of one defective root, a Jordan block, have one shape)."""
    return bool(1.0 - abs(np.vdot(x, y)) ** 2 / (np.vdot(x, x).real * np.vdot(y, y).real) < _PLANE_WIDTH ** 2)


def _one_defective_root(values, bound, run):
    """The two roots ``values[run]`` of a polished pair whose shapes were nearly parallel
    (:func:`_parallel`) made their mean in place where they are within :data:`_DEFECTIVE_SPLIT` of
    each other: one defective double root (a Jordan block), which round-off splits by the square
    root of its own (the block Newton's invariant pair is exact to round-off, the eigenvalues of its
    2 x 2 ``S`` to its square root; their mean, the half trace of ``S``, to round-off). Friswell
    5.9.4 at rest, cross-coupled bearings (K block-triangular): its roots 1.9e-7 off from the solve,
    7e-12 from the pair's polish, exact from their mean; ``bound`` there at least half the split."""
    a, b = values[run]
    mean = 0.5 * (a + b)
    split = abs(a - b) / abs(mean) if mean != 0 else np.inf
    if split <= _DEFECTIVE_SPLIT:
        values[run] = mean
        bound[run] = np.maximum(bound[run], 0.5 * split)


#: the largest split (relative) of a polished pair with one shape taken for one defective root
#: (:func:`_one_defective_root`): the square root of double precision's round-off
_DEFECTIVE_SPLIT = float(np.sqrt(np.finfo(float).eps))


def _defective_mean(values, shapes, bound, run, mass, damping, stiffness, branches=None) -> bool:
    """The two roots ``values[run]`` of one defective double root (a Jordan block, one shape) that
    the solve split by round-off, made their mean in place where that mean is exact to
    :data:`POLISH_LEVEL`; returns whether it was. Their shapes must be nearly parallel
    (:func:`_parallel`) and the two within :data:`_DEFECTIVE_GAP` of each other.

    Round-off splits a Jordan block's double root by the square root of its own size, the two
    roots symmetric about the root: their mean (half the trace of the pair's block) moves only by
    the first-order round-off, as a simple root does. Its error is measured as
    :func:`pencil_round_off` measures a root's, on the mean of the two shapes (one shape, to
    first order): the first-order term and the Rayleigh-quotient step ``|x^H T(s) x| / |x^H T'(s)
    x|`` of the quadratic pencil, whichever is larger (on Friswell 5.9.4 at rest, modes 11 to 28:
    the mean 5e-16 to 2e-15 off a 50-digit solve, its step 1 to 6 times that). Costs two
    products with the pencil's matrices, no factorisation: it keeps the pairs the polish's budget
    (:func:`.polish_budget`) leaves (:func:`refined_pairs`). Not on a rational pencil (Maxwell
    branches): there the pair keeps its bound.

    Parameters
    ----------
    values : ndarray, shape (m,), complex [1/s]
    shapes : ndarray, shape (m, n), complex
    bound : ndarray, shape (m,)
        The roots' error [-], the pair's set in place to the mean's where it is taken.
    run : ndarray of int, shape (2,)
    mass, damping, stiffness : ndarray, shape (n, n)
    branches : tuple, optional
        Maxwell branches (:func:`branch_terms`): then nothing is done.
    """
    a, b = values[run]
    mean = 0.5 * (a + b)
    if branches is not None or mean == 0 or abs(a - b) > _DEFECTIVE_GAP * abs(mean):
        return False
    x, y = shapes[run[0]], shapes[run[1]]
    if not _parallel(x, y):
        return False
    y = y * (np.vdot(y, x) / abs(np.vdot(y, x)))           # the same phase as x's
    shape = (x / np.linalg.norm(x) + y / np.linalg.norm(y)) / 2.0
    left = float(pencil_round_off(np.array([mean]), shape[None], mass, damping, stiffness)[0])
    if not left <= POLISH_LEVEL:
        return False
    values[run] = mean
    bound[run] = max(left, 4 * np.finfo(float).eps)
    return True


#: chord steps at most of a real root in :func:`single_roots_polished` (from a root 1e-4 off: 1e-8,
#: 1e-12, 1e-16; a real root of rubber_mounts with a 1e-12 s branch 3.2e-4 off needs six to reach
#: 1e-12), a complex one's as :func:`._lowest_newton.root_polished`'s
_REAL_STEPS = 6


#: ``|1 + s tau|`` at or below which a real root ``s`` is at a Maxwell branch's pole ``-1/tau``
#: (:func:`_singles_polished`: rubber_mounts with a 1e-12 s branch has roots 1.3e-6 from the
#: 0.02 s branches' pole, its own states' -50 1/s split by round-off, which no step on the pencil reaches)
_POLE = 1e-3
#: how far a real root's polish may move it, in its bound (:func:`pencil_round_off`, measured 0.01 to
#: 0.35 of the error): farther, Newton's steps found another root
_REAL_REACH = 100.0


def polished_ratio_round_off(values, which, bound) -> np.ndarray:
    """How far round-off can move the whirl ratio of each polished root's shape (:func:`refined_pairs`):
    as :func:`ratio_round_off`, with the root's own error, what the polish promises
    (:data:`POLISH_LEVEL`, or the error ``bound`` it left where larger, relative), in place of the
    solve's round-off, over the gap to the nearest other root of ``values`` or its conjugate (a
    repeated root's partner excluded as there, :func:`._roots.whirl_round_off`). The polish solves the
    pencil itself (its residual's stiffness term summed exactly), so the solve's round-off no longer
    bounds its shape: a mount mode of rubber_mounts with a 1e-12 s branch, whirl ratio 2.2e-3 at 500
    rpm, had the solve's 3.2e-2 and read 'none' by it; its polished ratio is a 50-digit solve's to
    1e-13. The lowest modes' route, whose roots its Newton steps promise to the same level, takes
    the same (:func:`.campbell._lowest_whirl_round_off`).

    Parameters
    ----------
    values : ndarray, shape (m,), complex [1/s]
        The roots of one speed, polished.
    which : ndarray of bool, shape (m,)
        The roots polished.
    bound : ndarray, shape (m,)
        Their error left, relative (:func:`refined_pairs`).

    Returns
    -------
    ndarray, shape (which.sum(),)
    """
    lam = np.asarray(values)[which]
    every = np.concatenate([values, np.conj(values)])
    repeated = REPEATED_TOLERANCE * np.abs(values).max(initial=0.0)
    level = np.maximum(np.asarray(bound)[which], POLISH_LEVEL) * np.abs(lam)
    return _roots.whirl_round_off(lam, every, 0.0, repeated, level)


def warn_of_inexact_roots(speeds, bound, name="", stacklevel=3, oscillating=None, labels=None, values=None):
    """One :class:`~rotordyn_modal.errors.ModelWarning` naming the speeds [rad/s] (N,) and the
    modes whose estimated relative error ``bound`` (N, m) (:func:`pencil_round_off`, after the
    polish, :func:`refined_pairs`) exceeds :data:`INEXACT_LEVEL` (where none does, the modes over
    :data:`POLISH_LEVEL`: the 1e-9 that issue 28 asks of every mode), and the largest bound; nothing
    where no mode exceeds :data:`POLISH_LEVEL` and no real root :data:`INEXACT_LEVEL`. Returns
    whether it warned. (Until roots32 a machine whose modes were left between 1e-9 and 1e-6 was
    not warned of: the 48-coordinate 1 mm shaft's modes 17 to 30 at 3,000 rpm, 1.6e-9 off.)

    It then gives every mode the polish left over :data:`POLISH_LEVEL` its own bound (its largest
    over the speeds): after the polish each of them is one it left, past its budget a speed
    (:func:`.polish_budget`) or not converged. A 624-coordinate shaft at 3,000 rpm with 46 roots
    over 1e-9 keeps 43 (the budget polishes three): the line named modes 4 to 10 with one bound,
    3.7e-4, for all, and nothing of modes 11 and 12, 1.0e-7 off; it now lists each, mode 4 3.7e-04
    to mode 12 7.8e-07 and on.

    ``oscillating`` (N, m) bool, where given, tells the modes from the real roots (relaxations,
    overdamped pairs: no mode of any table), which are counted apart with their values ``values``
    (N, m) [1/s]; ``labels`` (N, m) or (m,) int are the modes' numbers as the caller's table prints
    them (default: the 1-based columns, every root a mode)."""
    import warnings

    from ..errors import ModelWarning

    bound = np.atleast_2d(np.asarray(bound, dtype=float))
    # a mode over POLISH_LEVEL (what the budget left: issue 28 asks the modes to 1e-9), a real root
    # (no mode of any table) over INEXACT_LEVEL; the line's head names those over INEXACT_LEVEL
    # where there are any, its tail each mode over POLISH_LEVEL with its bound
    left = (bound > POLISH_LEVEL) & (True if oscillating is None else np.atleast_2d(oscillating))    # modes only
    over = bound > INEXACT_LEVEL
    if not over.any():
        over = left
    if not over.any():
        return False
    modes = over if oscillating is None else over & np.atleast_2d(oscillating)
    labels = np.broadcast_to(np.arange(1, bound.shape[1] + 1) if labels is None else labels, bound.shape)
    speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
    rows = np.flatnonzero(over.any(axis=1))
    rpm = ", ".join(f"{speed * 30 / np.pi:,.6g}" for speed in speeds[rows[:5]]) + (", ..." if len(rows) > 5 else "")
    named = np.unique(labels[modes])
    numbers = ", ".join(str(k) for k in named[:8]) + (", ..." if len(named) > 8 else "")
    real = over & ~modes
    real_text = _real_roots_text(np.atleast_2d(values)[real] if values is not None else None, real.any(axis=0).sum())
    what = (f"mode(s) {numbers}" + (f" and {real_text}" if real.any() else "")) if modes.any() else real_text
    quantity = "frequencies" if modes.any() else "values"
    warnings.warn(f"{name + ': ' if name else ''}{what} at {rpm} rpm: {quantity} exact only to about "
                  f"{np.max(bound[over]):.1e} relative (double precision's round-off of a low mode beside stiff "
                  f"elements{_each_mode_text(bound, left, labels)}; docs/theory.md, \"Close roots\")",
                  ModelWarning, stacklevel=stacklevel)
    return True


#: the modes a warning gives their own error of at most (:func:`_each_mode_text`), lowest first
_EACH_NAMED = 12


def _each_mode_text(bound, modes, labels) -> str:
    """', left unpolished: mode 4 3.7e-04, mode 5 3.6e-05, ...': each mode where ``modes`` (N, m)
    (by number, ``labels`` (N, m)) with its largest ``bound`` (N, m) there; at most
    :data:`_EACH_NAMED`, then how many more and their largest; '' without modes."""
    named = np.unique(labels[modes])
    if not len(named):
        return ""
    worst = [float(np.max(bound[modes & (labels == k)])) for k in named]
    text = ", ".join(f"mode {k} {e:.1e}" for k, e in zip(named[:_EACH_NAMED], worst))
    if len(named) > _EACH_NAMED:
        text += f" and {len(named) - _EACH_NAMED} more up to {max(worst[_EACH_NAMED:]):.1e}"
    return ", left unpolished: " + text


def _real_roots_text(values, count) -> str:
    """'N real root(s) (-50 1/s, ...; not modes)': the non-oscillating roots a warning names, by
    their values [1/s] where known (the distinct ones, 4 digits, at most 4)."""
    if values is None or not len(values):
        return f"{count} real root(s) (not modes)"
    shown = list(dict.fromkeys(f"{v:.4g}" for v in np.sort(np.asarray(values).real)))
    text = ", ".join(shown[:4]) + (", ..." if len(shown) > 4 else "")
    return f"{count} real root(s) ({text} 1/s; not modes)"
