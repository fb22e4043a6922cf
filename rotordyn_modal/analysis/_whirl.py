"""Whirl: mass-weighted orbital angular momentum of the machine about the spin axis
(``docs/theory.md`` section 9), its quadratic forms, ratios and labels."""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np
import scipy.sparse

from . import _pencils, _vectors
from ..assembly import add_rotor_bodies, body_inertias
from ..model.dofs import frame_block
from ..model.geometry import shift_matrices, skew

__all__ = ["WHIRL_TOLERANCE", "EntryForms", "WhirlForms", "entry_forms", "quadratic_forms", "rotor_whirl_forms", "stacked_forms", "whirl_forms",
           "sparse_whirl_forms", "whirl_codes", "whirl_labels", "whirl_ratios"]


#: |whirl ratio| below this counts as no whirl (a straight-line orbit): for an elliptic
#: orbit the ratio is 2ab/(a^2+b^2), so this is a minor/major axis ratio of 5e-4
WHIRL_TOLERANCE = 1e-3


# ----------------------------------------------------------------------------------------
_SKEW_BASIS = skew(np.eye(3))   # E_k = skew(unit_k), shape (3, 3, 3)


def _bodies_quadratic(masses, second_moments, X, first, products) -> np.ndarray:
    """``sum_p m_p Z_p^T X Z_p`` over the particles of each rigid body, Z_p = [I, -skew(r_p)],
    for several directions X at once.

    Needs only each body's mass, first moment and second-moment tensor about the reference
    point: ``sum_p m_p skew(r_p) X skew(r_p) = sum_kl Q_kl E_k X E_l`` with ``E_k = skew(unit_k)``.

    Parameters
    ----------
    masses : ndarray (B,); second_moments : ndarray (B, 3, 3)
    X : ndarray, shape (D, 3, 3)
    first : ndarray (B, 3, 3)
        ``skew(masses * centers)``.
    products : ndarray (D, 3, 3, 3, 3)
        ``E_k X E_l`` of each direction (see :func:`_directions`).

    Returns
    -------
    ndarray, shape (D, B, 6, 6)
    """
    X = X[:, None]                                            # (D, 1, 3, 3)
    out = np.zeros((len(X), len(masses), 6, 6))
    out[..., :3, :3] = masses[:, None, None] * X
    out[..., :3, 3:] = -X @ first
    out[..., 3:, :3] = first @ X
    out[..., 3:, 3:] = -np.einsum("zkl,xklad->xzad", second_moments, products)
    return out


def _direction_products(X) -> np.ndarray:
    """``E_k X E_l`` for a (3, 3) matrix X, shape (3, 3, 3, 3), with ``E_k = skew(unit_k)``."""
    return np.einsum("kab,bc,lcd->klad", _SKEW_BASIS, X, _SKEW_BASIS)


@functools.lru_cache(maxsize=16)
def _directions(axis: tuple):
    """The whirl forms' 3 x 3 directions W, N, total about the spin axis ``axis`` (a tuple of 3
    floats) and their :func:`_direction_products`, stacked: (3, 3, 3) and (3, 3, 3, 3, 3),
    read-only. A function of the axis alone, kept for the next model with the same axis."""
    e = np.array(axis, dtype=float)
    X = np.stack([skew(e), np.eye(3) - np.outer(e, e), np.eye(3)])
    products = np.stack([_direction_products(x) for x in X])
    X.flags.writeable = products.flags.writeable = False
    return X, products


class WhirlForms(NamedTuple):
    """Quadratic forms of the whirl ratio (each (n, n)); see :func:`whirl_forms`."""

    W: np.ndarray
    N: np.ndarray
    total: np.ndarray


_DIRECTIONS = ("W", "N", "total")


def _bodies_forms(model) -> np.ndarray:
    """The 6x6 forms W, N, total (stacked in this order) of each body's rigid motion at the
    reference point (stator first, then the rotors): shape (3, B, 6, 6)."""
    X, products = _directions(tuple(float(x) for x in model.spin_axis))
    bodies = body_inertias(model)
    masses = np.array([m for m, _, _ in bodies], dtype=float)
    arms = np.array([np.asarray(c, dtype=float) for _, c, _ in bodies]) - model.reference_point
    inertias = np.array([np.asarray(j, dtype=float) for _, _, j in bodies])
    traces = inertias.trace(axis1=1, axis2=2)
    second = (0.5 * traces[:, None, None] * np.eye(3) - inertias
              + masses[:, None, None] * arms[:, :, None] * arms[:, None, :])
    first = skew(masses[:, None] * arms)
    return _bodies_quadratic(masses, second, X, first, products)


def whirl_forms(model) -> WhirlForms:
    """Quadratic forms ``W``, ``N`` and ``total`` of the whirl ratio of a mode shape phi.

    ``-i phi^H W phi`` is the mass-weighted orbital angular momentum of the
    whole machine's vibration about the spin axis (per unit frequency),
    ``phi^H N phi`` the mass-weighted mean square motion normal to it and
    ``phi^H total phi`` that of the whole motion (``total`` equals the mass
    matrix). Each body contributes ``T_b^T X_b T_b`` (its motion ``T_b`` over the
    generalized coordinates). See ``docs/theory.md``.
    """
    forms = _bodies_forms(model)                                          # (3, B, 6, 6)
    first_rotor = forms.shape[1] - len(model.rotors)
    flexible = [j for j, rotor in enumerate(model.rotors) if rotor.flexible is not None]
    if flexible:     # their nodes' forms replace their rigid ones
        forms = np.delete(forms, [first_rotor + j for j in flexible], axis=1)
    parts = frame_block(model, forms.sum(axis=1))                         # (3, n, n)
    rigid = [rotor for rotor in model.rotors if rotor.flexible is None]
    for j, rotor in enumerate(rigid):
        if model.dofs.on_bearings(rotor.name):
            add_rotor_bodies([parts], model, rotor.name, [forms[:, first_rotor + j]])
    for j in flexible:
        _node_forms(model, model.rotors[j], out=parts)          # added in place: no third 3 n x n array
    if model.dofs.pedestals:
        parts = parts + _pedestal_forms(model)
    return WhirlForms(*parts)


def sparse_whirl_forms(model) -> WhirlForms:
    """:func:`whirl_forms` as ``scipy.sparse`` CSR matrices (n, n) each, summed from the same
    bodies' pieces without a dense ``n x n`` array (a large model's: docs/theory.md §17). Equal to
    the dense forms to round-off."""
    from ..assembly import sparse_frame_block, sparse_rotor_body

    forms = _bodies_forms(model)                                          # (3, B, 6, 6)
    first_rotor = forms.shape[1] - len(model.rotors)
    flexible = [j for j, rotor in enumerate(model.rotors) if rotor.flexible is not None]
    if flexible:
        forms = np.delete(forms, [first_rotor + j for j in flexible], axis=1)
    parts = [sparse_frame_block(model, block) for block in forms.sum(axis=1)]
    rigid = [rotor for rotor in model.rotors if rotor.flexible is None]
    for j, rotor in enumerate(rigid):
        if model.dofs.on_bearings(rotor.name):
            parts = [part + sparse_rotor_body(model, rotor.name, forms[d, first_rotor + j])
                     for d, part in enumerate(parts)]
    for j in flexible:
        parts = [part + piece for part, piece in zip(parts, _node_pieces(model, model.rotors[j]))]
    if model.dofs.pedestals:
        X, _ = _directions(tuple(float(x) for x in model.spin_axis))
        for bearing in model.bearings:
            if bearing.pedestal is not None:
                motion = scipy.sparse.csr_matrix(model.dofs.pedestal_motion(bearing.name, bearing.position))
                parts = [part + bearing.pedestal.mass * (motion.T @ scipy.sparse.csr_matrix(x) @ motion)
                         for part, x in zip(parts, X)]
    return WhirlForms(*(part.tocsr() for part in parts))


def _pedestal_forms(model) -> np.ndarray:
    """The whirl forms of the bearings' pedestals, point masses moving with their translation
    ``T_p`` (:meth:`Dofs.pedestal_motion`): ``sum_p m_p T_p^T X T_p``, shape (3, n, n)."""
    X, _ = _directions(tuple(float(x) for x in model.spin_axis))
    out = np.zeros((len(X), model.dofs.n, model.dofs.n))
    for bearing in model.bearings:
        if bearing.pedestal is not None:
            motion = model.dofs.pedestal_motion(bearing.name, bearing.position)          # (3, n)
            out += bearing.pedestal.mass * np.einsum("am,dab,bn->dmn", motion, X, motion)
    return out


def _node_forms(model, rotor, out=None) -> np.ndarray:
    """The whirl forms of a flexible rotor, each node a rigid body (its share of the mass matrix
    lumped: the row sums of the translations, the rotations' own block) moving as the node:
    ``sum_i T_i^T X_i T_i``, shape (3, n, n) (added to ``out`` where given, and returned)."""
    pieces = _node_pieces(model, rotor)
    if out is None:
        out = np.zeros((len(pieces), model.dofs.n, model.dofs.n))
    for d, piece in enumerate(pieces):
        out[d] += piece.toarray()       # a product's CSR holds no entry twice: each added once, as _add_sparse
    return out


def _node_pieces(model, rotor) -> list:
    """:func:`_node_forms` as three ``scipy.sparse`` matrices (n, n)."""
    from ..assembly import flexible_rotor_matrices

    shaft = rotor.flexible
    points = shaft.node_positions
    count = len(points)
    parts = flexible_rotor_matrices(model, rotor, kinds=("M",))
    M = parts.M                                                    # sparse (6 N, 6 N)
    # sum over the columns' nodes of each translation block, and its trace per node
    summed = (M @ np.tile(np.eye(6, 3), (count, 1))).reshape(count, 6, 3)
    masses = np.trace(summed[:, :3], axis1=1, axis2=2) / 3.0
    # the rotations' own 3 x 3 block of each node: rows 6 i + 3 + r, columns 6 i + 3 + c
    start = 6 * np.arange(count)[:, None, None] + 3
    rows, cols = np.broadcast_arrays(start + np.arange(3)[:, None], start + np.arange(3))
    inertias = np.asarray(M[rows.ravel(), cols.ravel()]).reshape(count, 3, 3)
    arms = points - model.reference_point
    second = (_particles_second_moments(inertias)
              + masses[:, None, None] * arms[:, :, None] * arms[:, None, :])
    X, products = _directions(tuple(float(x) for x in model.spin_axis))
    forms = _bodies_quadratic(masses, second, X, skew(masses[:, None] * arms), products)    # (3, N, 6, 6)
    motions = _node_motions_at_reference(model, shaft, parts.relative)                       # (6 N, n)
    # sum_i T_i^T X_i T_i = T^T blockdiag(X_i) T, sparse: a node moves with a few coordinates; the
    # three blockdiag(X_i) T in one product (a row's sum is its own: the same bits as three)
    moved = _block_diagonal(forms) @ motions
    across = motions.T
    return [across @ _rows_of(moved, d * 6 * count, (d + 1) * 6 * count) for d in range(len(forms))]


def _rows_of(matrix, start: int, stop: int):
    """Rows ``start:stop`` of a CSR ``matrix``, their arrays taken as they are (a view of its
    entries; scipy's slicing copies them through a general indexer, a tenth of a small model's
    whirl forms)."""
    first, last = matrix.indptr[start], matrix.indptr[stop]
    return scipy.sparse.csr_matrix((matrix.data[first:last], matrix.indices[first:last],
                                    matrix.indptr[start:stop + 1] - first), shape=(stop - start, matrix.shape[1]))


def _block_diagonal(blocks):
    """``scipy.sparse.block_diag(blocks[d], format="csr")`` of each ``d`` of dense blocks
    (D, N, r, c), stacked one above the other (D N r, N c), CSR: the same arrays as
    ``block_diag`` makes (every entry of a block stored, its zeros too; each row's columns
    increasing), built directly (block_diag goes through COO: some ten times the time, a third of
    a small flexible model's whirl forms)."""
    count, r, c = blocks.shape[-3:]
    columns = np.broadcast_to(c * np.arange(count)[:, None, None] + np.arange(c), blocks.shape)
    pointers = np.arange(0, blocks.size + 1, c)
    rows = blocks.size // c
    index = np.int32 if max(blocks.size, count * c) <= np.iinfo(np.int32).max else np.int64
    return scipy.sparse.csr_matrix((blocks.reshape(-1), columns.reshape(-1).astype(index), pointers.astype(index)),
                                   shape=(rows, count * c))


def _particles_second_moments(inertias) -> np.ndarray:
    """``sum_p m r r^T`` about each node, ``(tr J / 2) I - J``, of the node inertias ``J`` (N, 3, 3)
    read from the consistent mass matrix's rotation blocks, made positive semidefinite.

    Those blocks are no rigid body's inertia: the consistent mass puts most of an element's rotary
    inertia into the couplings of its nodes, so that an element shorter than about its diameter
    (``l^2 < 21 I / A`` for Euler-Bernoulli: the diagonal's ``4 rho I l / 30`` beside the torsion's
    ``rho J_p l / 3``) leaves a node's diametral inertia below half its polar one, against the
    triangle inequality of every body. Taken as they are, the axial second moment ``J_d - J_p / 2`` is
    negative, the mean square motion normal to the spin axis (the whirl form ``N``) is indefinite,
    and a short solid rotor's conical modes (the node tilts) read as no whirl (``N < 0``) or as a
    ratio of round-off. A node is a slice of the shaft: its particles' second moments are kept
    where they are a body's, and their negative part (a particle cannot have a negative square) is
    dropped elsewhere (the slice then lies in its plane: its tilt moves its particles along the
    axis only, which the whirl does not count, docs/theory.md section 9)."""
    traces = inertias.trace(axis1=1, axis2=2)
    second = 0.5 * traces[:, None, None] * np.eye(3) - inertias
    second = 0.5 * (second + np.swapaxes(second, 1, 2))
    scale = np.abs(second).max(axis=(1, 2), initial=0.0)
    bad = np.linalg.eigvalsh(second)[:, 0] < -1e-12 * scale if len(second) else np.zeros(0, dtype=bool)
    if bad.any():
        values, vectors = np.linalg.eigh(second[bad])
        second[bad] = (vectors * np.maximum(values, 0.0)[:, None, :]) @ np.swapaxes(vectors, 1, 2)
    return second


def _node_motions_at_reference(model, shaft, relative):
    """Each node's absolute motion as a rigid motion at the reference point S per coordinate,
    sparse (6 N, n): the frame's identity on its coordinates, plus ``B_{node S}^T`` times the
    node's relative motion (as ``Dofs.motions`` of the node)."""
    import scipy.sparse

    points = shaft.node_positions
    count = len(points)
    layout = model.dofs
    shifts = shift_matrices(points, layout.reference_point).transpose(0, 2, 1)               # (N, 6, 6)
    out = _block_diagonal(shifts) @ relative
    k = layout.n_frame
    if k:
        frame = np.zeros((6 * count, layout.n))
        frame[:, :k] = np.tile(np.eye(6)[:, :k], (count, 1))
        out = out + scipy.sparse.csr_matrix(frame)
    return out.tocsr()


def rotor_whirl_forms(model, rotor: str) -> WhirlForms:
    """The whirl forms of one rotor's own motion (absolute), each (n, n)."""
    index = [r.name for r in model.rotors].index(rotor)
    if model.rotors[index].flexible is not None:
        return WhirlForms(*_node_forms(model, model.rotors[index]))
    forms = _bodies_forms(model)
    body = forms[:, forms.shape[1] - len(model.rotors) + index]            # (3, 6, 6)
    motion = model.dofs.body_motion(rotor)
    return WhirlForms(*(motion.T @ body[d] @ motion for d in range(len(_DIRECTIONS))))


def stacked_forms(forms: WhirlForms) -> np.ndarray:
    """The transposes of the three whirl forms side by side, (..., n, 3 n), contiguous (see
    :func:`quadratic_forms`)."""
    return np.ascontiguousarray(
        np.concatenate([np.swapaxes(f, -1, -2) for f in (forms.W, forms.N, forms.total)], axis=-1))


def sparse_stacked_forms(forms: WhirlForms):
    """:func:`stacked_forms` of one model's forms (n, n) each as a ``scipy.sparse`` CSR matrix
    (n, 3 n): a large flexible model's forms couple each node with its neighbours only."""
    # each form's CSR from its own C-ordered array, then transposed (a transposed view would be copied whole)
    return scipy.sparse.hstack([scipy.sparse.csr_matrix(f).T for f in (forms.W, forms.N, forms.total)], format="csr")


class EntryForms(NamedTuple):
    """The whirl forms (each (n, n), real) by their nonzero entries: for each form its rows,
    columns (e,) int and values (e,). A flexible shaft's forms couple a node's coordinates with
    its own and its neighbours' only (compressor_example's 224 coordinates: 472 entries of the
    150,528 of three dense forms), so ``phi^H X phi`` summed over the entries costs a small part
    of a dense product with the three forms (measured there, 2,412 shapes: 12 ms against 42 ms),
    each shape's on its own (its bits do not depend on the other rows)."""

    entries: tuple

    def quadratic_forms(self, shapes) -> np.ndarray:
        """``phi^H X_k phi`` (..., m, K) complex of every shape (..., m, n) and form ``k``."""
        flat = shapes.reshape(-1, shapes.shape[-1])
        out = np.empty((len(flat), len(self.entries)), complex)
        for k, (rows, cols, values) in enumerate(self.entries):
            out[:, k] = np.einsum("pe,pe->p", flat[:, rows].conj(), flat[:, cols] * values)
        return out.reshape(shapes.shape[:-1] + (len(self.entries),))


def entry_forms(forms: WhirlForms) -> EntryForms:
    """:class:`EntryForms` of one model's forms (n, n) each, dense."""
    out = []
    for form in (forms.W, forms.N, forms.total):
        rows, cols = np.nonzero(form)
        out.append((rows, cols, form[rows, cols]))
    return EntryForms(tuple(out))


def whirl_ratios(shapes, forms: WhirlForms, speeds, stacked=None) -> np.ndarray:
    """Signed whirl ratio in [-1, 1] relative to the reference rotor's spin.

    +1 for a circular orbit normal to the spin axis turning with the spin, -1
    against it, 0 for straight-line orbits. Modes whose motion normal to the
    axis is below ``1e-9`` of their whole motion (pure axial or roll motion)
    get 0, not a ratio of round-off to round-off.

    Parameters
    ----------
    shapes : ndarray, shape (..., m, n)
    forms : WhirlForms
        Each (n, n), or stacked like the shapes' leading axes, (..., n, n); unused (may be None)
        when ``stacked`` is given.
    speeds : ndarray, shape (...) [rad/s]; the sign of the spin (0 counts as +)
    stacked : ndarray or scipy.sparse matrix or EntryForms, optional
        :func:`stacked_forms` (or :func:`sparse_stacked_forms`, :func:`entry_forms`) of ``forms``,
        when the caller keeps it.

    Returns
    -------
    ndarray, shape (..., m)
    """
    # phi^H X phi of the three forms for every shape from one product with [W^T N^T total^T]
    values = quadratic_forms(shapes, stacked_forms(forms) if stacked is None else stacked).reshape(
        shapes.shape[:-1] + (3,))
    return ratios_of_forms(values, speeds)


def about_spin_axis(ratios, speeds) -> np.ndarray:
    """Whirl ratios ``ratios`` (relative to the spin, as every table gives them) about
    ``+spin_axis``: the spin's sign undone, which a negative speed reverses (zero speed counts as
    +). ``speeds`` [rad/s] a scalar or of the leading shape of ``ratios`` (a speed per row)."""
    speeds = np.asarray(speeds, dtype=float)
    ratios = np.asarray(ratios, dtype=float)
    sign = np.where(speeds < 0, -1.0, 1.0)
    return ratios * sign.reshape(sign.shape + (1,) * (ratios.ndim - sign.ndim))


def ratios_of_forms(values, speeds) -> np.ndarray:
    """:func:`whirl_ratios` from the shapes' quadratic forms ``values`` (..., m, 3), complex:
    ``phi^H X phi`` of W, N and total (a shape known by its coordinates in a subspace: the forms
    projected there). Returns (..., m)."""
    momentum = values[..., 0].imag  # Re(-i phi^H W phi)
    across = values[..., 1].real
    whole = values[..., 2].real
    ratio = np.zeros(across.shape)
    np.divide(momentum, across, out=ratio, where=across > 1e-9 * whole)
    against = np.asarray(speeds) < 0
    if against.any():
        np.negative(ratio, out=ratio, where=np.broadcast_to(against[..., None], ratio.shape))
    np.maximum(ratio, -1.0, out=ratio)                                   # numpy.clip, in place
    return np.minimum(ratio, 1.0, out=ratio)


#: shapes of at most this many coordinates take their quadratic forms by one complex product
_COMPLEX_PRODUCT_DOF = 24


def quadratic_forms(shapes, stacked) -> np.ndarray:
    """``phi^H X_k phi`` of every shape (..., m, n) for real forms whose transposes are
    side by side in ``stacked`` (n, K n) or (..., n, K n).

    Returns
    -------
    ndarray, shape (..., m, K), complex
    """
    n = shapes.shape[-1]
    if isinstance(stacked, EntryForms):         # sparse forms by their entries (:class:`EntryForms`)
        return stacked.quadratic_forms(shapes)
    if scipy.sparse.issparse(stacked):          # a large model's forms, sparse (n, K n): no n x K n array
        flat = shapes.reshape(-1, n)
        product = (flat.real @ stacked + 1j * (flat.imag @ stacked)).reshape(shapes.shape[:-1] + (-1,))
        return np.einsum("...i,...ki->...k", shapes.conj(), product.reshape(shapes.shape[:-1] + (-1, n)))
    # small shapes: complex products, one per speed (numpy makes the forms complex, a few
    # hundred numbers), cost less than the real parts' copies and their product's large
    # temporaries, and each is too small to start BLAS threads (which a loaded machine makes
    # wait). Single shapes (critical speeds) of pencils solved whole also take one product per
    # row: in one product of all rows a row's bits depend on its place among the others, and a
    # study's variant would then differ from its model's own analysis in the last bit.
    single = shapes.shape[-2] == 1 and n <= _pencils.BATCHED_DOF
    if n > _COMPLEX_PRODUCT_DOF and not single:
        product = _vectors.real_product(shapes, stacked)
    else:
        product = shapes @ stacked
    products = product.reshape(shapes.shape[:-1] + (-1, n))   # (..., m, K, n)
    return np.einsum("...i,...ki->...k", shapes.conj(), products)


_WHIRL_NAMES = np.array(["backward", "none", "forward"])


def whirl_codes(ratios, round_off=None) -> np.ndarray:
    """-1, 0, +1 for backward, none, forward from whirl ratios (same shape, int).

    A ratio is no whirl where its size is at most :data:`WHIRL_TOLERANCE` or at most
    ``round_off``, how far round-off can move it (:func:`._roots.whirl_round_off`: a shape
    beside a nearly repeated root is known only to the eigen-solve's noise over the gap): the
    one rule of ``modes``' table and the Campbell diagram.

    Parameters
    ----------
    ratios : array_like, shape (...)
    round_off : array_like, shape (...), optional
        What round-off can move each ratio by (default 0).
    """
    ratios = np.asarray(ratios)
    if round_off is None:
        return (ratios > WHIRL_TOLERANCE).astype(np.intp) - (ratios < -WHIRL_TOLERANCE)
    level = np.maximum(WHIRL_TOLERANCE, round_off)
    return (ratios > level).astype(np.intp) - (ratios < -level)


def whirl_labels(ratios, round_off=None) -> np.ndarray:
    """'forward', 'backward' or 'none' from whirl ratios (array of str), by :func:`whirl_codes`
    (``round_off`` as there)."""
    return _WHIRL_NAMES[whirl_codes(ratios, round_off) + 1]
