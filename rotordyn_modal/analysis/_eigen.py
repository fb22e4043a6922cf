"""Batched eigen-solutions of the speed-dependent state matrix, whirl and MAC.

Speed: all speeds are solved by batched LAPACK calls split over threads (numpy
releases the GIL), in parts of bounded memory. Without Maxwell states the mode
shapes are the displacement parts of LAPACK's eigenvectors of the 2n x 2n state
matrix. With Maxwell states (state matrix larger than 2n, and roots whose
eigenvector has no displacement part) each shape comes from one step of inverse
iteration on the n x n pencil
``Q(lam) = lam^2 M + lam (C + Omega G) + K + sum_b lam tau_b / (1 + lam tau_b) K_b``,
batched over speeds and modes, which is also the cheaper of the two there
(n small against the number of states).
"""

from __future__ import annotations

import contextlib
import os
from concurrent.futures import ThreadPoolExecutor

from typing import NamedTuple

import numpy as np

from ..assembly import add_rotor_body, body_inertias, frame_block
from ..geometry import skew

__all__ = ["select_upper", "inverse_iteration", "solve_batch", "whirl_forms", "rotor_whirl_forms",
           "whirl_ratios",
           "mass_normalized", "mac_matrix", "WhirlForms", "OSCILLATORY_TOLERANCE", "WHIRL_TOLERANCE"]

#: |Im lam| below this fraction of the largest |lam| of a speed counts as non-oscillatory
OSCILLATORY_TOLERANCE = 1e-6
#: |whirl ratio| below this counts as no whirl (a straight-line orbit): for an elliptic
#: orbit the ratio is 2ab/(a^2+b^2), so this is a minor/major axis ratio of 5e-4
WHIRL_TOLERANCE = 1e-3

_THREADS = max(1, min(4, os.cpu_count() or 1))
#: batches whose work arrays exceed this are shared between threads [bytes]
_THREAD_BYTES = 4 * 2**20
#: upper bound of the work arrays of one part of a batch [bytes]
_PART_BYTES = 64 * 2**20
_START_SEED = 20261122


def _start_vectors(m: int, n: int) -> np.ndarray:
    """Fixed pseudo-random complex start vectors of inverse iteration, shape (m, n)."""
    size = max(64, m, n)
    draws = np.random.default_rng(_START_SEED).standard_normal((2, size, size))
    return (draws[0] + 1j * draws[1])[:m, :n]


_POOL: ThreadPoolExecutor | None = None


def _threaded(function, *batches: np.ndarray, item_bytes: int = 0):
    """Apply a batched numpy routine over the first axis of its arrays using a few threads.

    LAPACK-backed numpy routines and large array arithmetic release the GIL, so
    the parts run in parallel. Set ``ROTORDYN_MODAL_THREADS=1`` (as parameter
    studies do in their worker processes) to stay on one core. ``item_bytes``
    (the work memory per item, a measure of its cost) splits large batches into
    parts of at most about ``_PART_BYTES``, and shares batches beyond
    ``_THREAD_BYTES`` between threads. ``function`` returns an array or a tuple
    of arrays; the parts' results are concatenated.
    """
    global _POOL
    count = len(batches[0])
    threads = int(os.environ.get("ROTORDYN_MODAL_THREADS", _THREADS))
    pieces = max(1, min(count, -(-count * item_bytes // _PART_BYTES)))
    if threads > 1 and count * item_bytes >= _THREAD_BYTES:
        pieces = max(pieces, min(count, threads))
    if pieces == 1:
        return function(*batches)
    parts = [np.array_split(batch, pieces) for batch in batches]
    if threads > 1:
        if _POOL is None or _POOL._max_workers != threads:
            _POOL = ThreadPoolExecutor(threads, thread_name_prefix="rotordyn-eig")
        with _one_blas_thread():
            results = list(_POOL.map(function, *parts))
    else:
        results = [function(*part) for part in zip(*parts)]
    if isinstance(results[0], tuple):
        return tuple(np.concatenate(column) for column in zip(*results))
    return np.concatenate(results)


def _one_blas_thread():
    """One BLAS/LAPACK thread each while our own threads share the cores (through
    threadpoolctl when installed): BLAS's own threads on top of ours would oversubscribe
    the cores, which slows large eigenproblems several times over."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def select_upper(values: np.ndarray) -> np.ndarray:
    """The n eigenvalues with the largest imaginary parts of each row of 2n eigenvalues.

    One of each complex-conjugate pair, and half of the real eigenvalues (the
    ones of smaller magnitude), sorted by imaginary part, then real part.

    Parameters
    ----------
    values : ndarray, shape (..., 2n), complex [1/s]

    Returns
    -------
    ndarray, shape (..., n), complex [1/s]
    """
    return _upper(values)[0]


def _upper(values: np.ndarray):
    """The upper eigenvalues of each row and where they sit in it.

    Returns
    -------
    upper : ndarray, shape (..., n), complex
        As :func:`select_upper` (imaginary parts within ``OSCILLATORY_TOLERANCE`` set to zero).
    index : ndarray of int, shape (..., n)
        ``values[..., index]`` are those eigenvalues as given.
    """
    n = values.shape[-1] // 2
    scale = np.abs(values).max(axis=-1, keepdims=True)
    tol = OSCILLATORY_TOLERANCE * np.where(scale > 0, scale, 1.0)
    imag = np.where(np.abs(values.imag) <= tol, 0.0, values.imag)
    # within the real block, prefer the smaller |lam|: a second stable sort by -|lam| first
    pre = np.argsort(-np.abs(values), axis=-1, kind="stable")
    imag_pre = np.take_along_axis(imag, pre, axis=-1)
    order = np.take_along_axis(pre, np.argsort(imag_pre, axis=-1, kind="stable"), axis=-1)
    upper = np.take_along_axis(values, order[..., n:], axis=-1)
    upper_imag = np.take_along_axis(imag, order[..., n:], axis=-1)
    upper = np.where(upper_imag == 0.0, upper.real + 0j, upper)
    final = np.lexsort((upper.real, upper.imag), axis=-1)
    return np.take_along_axis(upper, final, axis=-1), np.take_along_axis(order[..., n:], final, axis=-1)


def inverse_iteration(M, damping, K, eigenvalues, branches=None) -> np.ndarray:
    """Right eigenvectors ``phi`` of ``Q(lam) phi = 0`` by one inverse-iteration step.

    Parameters
    ----------
    M : ndarray, shape (n, n)
    damping : ndarray, shape (N, n, n)
        ``C + Omega G`` at each speed.
    K : ndarray, shape (n, n) or (N, 1, n, n)
        Stiffness (per speed when bearing coefficients depend on speed).
    eigenvalues : ndarray, shape (N, m), complex
    branches : (ndarray (n_b, n, n), ndarray (n_b,)), optional
        Maxwell branches' stiffness [N/m, ...] and relaxation times [s]: the pencil
        gains ``sum_b lam tau_b / (1 + lam tau_b) K_b``.

    Returns
    -------
    ndarray, shape (N, m, n), complex
        Unit-norm shapes.
    """
    lam = eigenvalues[..., None, None]
    scale = np.abs(eigenvalues).max(axis=-1, keepdims=True)[..., None, None] + 1e-300
    # a shift at round-off level keeps an exactly singular pencil (lam = 0 with an
    # unsupported direction) solvable without changing the converged direction
    shifted = lam + 1e-13 * scale * (1 + 1j)
    pencil = shifted * damping[:, None]
    pencil += K
    pencil += shifted**2 * M
    if branches is not None and len(branches[1]):
        stiffness, times = branches
        # a relaxation root sits near the pole lam = -1/tau; the round-off shift keeps it finite
        factor = shifted[..., 0, 0, None] * times / (1 + shifted[..., 0, 0, None] * times)
        pencil += np.einsum("nmb,bij->nmij", factor, stiffness)
    m, n = eigenvalues.shape[-1], M.shape[0]
    start = np.broadcast_to(_start_vectors(m, n)[..., None], pencil.shape[:-2] + (n, 1))
    # one step suffices: the shift is at round-off level, so the other modes' share of the
    # result is |lam - shifted| / |lam_other - shifted|, about 1e-13 of the gap
    vectors = _solve(pencil, start)[..., 0]
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


def _solve(matrices, rhs):
    try:
        return np.linalg.solve(matrices, rhs)
    except np.linalg.LinAlgError:
        out = np.empty(rhs.shape, dtype=complex)
        for index in np.ndindex(matrices.shape[:-2]):
            out[index] = np.linalg.lstsq(matrices[index], rhs[index], rcond=None)[0]
        return out


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
    eigenvalues : ndarray, shape (N, n), complex [1/s]
    shapes : ndarray, shape (N, n, n), complex
    """
    speeds = np.asarray(speeds, dtype=float)
    size, n = form.n_states, form.n_dof
    if size == 2 * n:
        # state matrices, eigenvectors and LAPACK's work arrays of one speed
        eigenvalues, shapes = _threaded(lambda part: _lapack_shapes(form, part), speeds,
                                        item_bytes=72 * size * size)
    else:
        # state matrices, then the pencils of every root and their LU factors
        eigenvalues, shapes = _threaded(lambda part: _pencil_shapes(form, part), speeds,
                                        item_bytes=24 * size * size + 32 * size * n * n)
    if forms is not None:
        shapes = resolve_repeated(eigenvalues, shapes, forms)
    return eigenvalues, shapes


def _lapack_shapes(form, speeds):
    """Upper eigenvalues (N, n) and unit-norm displacement parts (N, n, n) of LAPACK's
    eigenvectors of the state matrices at ``speeds`` (state ``[q, q']``, no extra states)."""
    values, vectors = np.linalg.eig(form.at(speeds))
    upper, index = _upper(values)
    shapes = np.take_along_axis(vectors[:, :form.n_dof, :], index[:, None, :], axis=-1)
    shapes = np.swapaxes(shapes, -1, -2)
    return upper, shapes / np.linalg.norm(shapes, axis=-1, keepdims=True)


def _pencil_shapes(form, speeds):
    """Upper eigenvalues (N, m) of the state matrices at ``speeds`` and their shapes
    (N, m, n) by inverse iteration on the rational pencil (see :func:`inverse_iteration`)."""
    eigenvalues = select_upper(np.linalg.eigvals(form.at(speeds)))
    M, _, G, _ = form.matrices
    damping = form.damping_at(speeds) + speeds[:, None, None] * G
    K = form.stiffness_at(speeds)
    K = K[:, None] if np.ndim(K) == 3 else K
    branches = (form.branch_stiffness, form.branch_times)
    return eigenvalues, inverse_iteration(M, damping, K, eigenvalues, branches)


#: eigenvalues closer than this (relative) are one repeated eigenvalue
REPEATED_TOLERANCE = 1e-9


def resolve_repeated(eigenvalues, shapes, forms):
    """Make the shapes of a repeated eigenvalue its forward and backward whirl combinations.

    Any combination of the shapes of a double eigenvalue is a mode shape, so the
    solver's choice (and with it the whirl label) would be arbitrary. Within each
    pair this picks the two combinations with extreme whirl ratio: the
    eigenvectors of ``-i Phi^H W Phi v = mu Phi^H M Phi v`` (circular orbits, one
    turning each way, for an axisymmetric machine). Pairs whose motion has no
    whirl keep their shapes. Groups of three or more are left as they are.

    Parameters
    ----------
    eigenvalues : ndarray, shape (N, m), sorted so that equal values are adjacent
    shapes : ndarray, shape (N, m, n)
    forms : WhirlForms

    Returns
    -------
    ndarray, shape (N, m, n): shapes, with repeated pairs replaced (backward first)
    """
    lam = eigenvalues
    scale = np.abs(lam).max(axis=-1, keepdims=True) + 1e-300
    close = np.abs(np.diff(lam, axis=-1)) <= REPEATED_TOLERANCE * scale  # (N, m-1)
    padded = np.pad(close, ((0, 0), (1, 1)))
    pair = close & ~padded[:, :-2] & ~padded[:, 2:]  # exactly two equal, not three
    pair &= np.abs(lam[:, :-1]) > OSCILLATORY_TOLERANCE * scale  # not rigid-body zeros
    rows, first = np.nonzero(pair)
    basis = np.stack([shapes[rows, first], shapes[rows, first + 1]], axis=-1)  # (P, n, 2)
    total = np.einsum("pia,ij,pjb->pab", basis.conj(), forms.total, basis)
    # the two shapes must span a plane (two inverse iterations could give one direction)
    spans = np.abs(np.linalg.det(total)) > 1e-6 * np.abs(total[:, 0, 0] * total[:, 1, 1])
    rows, first, basis, total = rows[spans], first[spans], basis[spans], total[spans]
    if not rows.size:
        return shapes
    momentum = -1j * np.einsum("pia,ij,pjb->pab", basis.conj(), forms.W, basis)
    momentum = 0.5 * (momentum + np.conj(np.swapaxes(momentum, -1, -2)))
    factor = np.linalg.cholesky(0.5 * (total + np.conj(np.swapaxes(total, -1, -2))))
    inverse = np.linalg.inv(factor)
    reduced = inverse @ momentum @ np.conj(np.swapaxes(inverse, -1, -2))
    mu, vectors = np.linalg.eigh(reduced)
    combinations = np.conj(np.swapaxes(inverse, -1, -2)) @ vectors  # (P, 2, 2)
    resolved = basis @ combinations  # (P, n, 2)
    whirling = np.abs(mu[:, 1] - mu[:, 0]) > 1e-6
    resolved /= np.linalg.norm(resolved, axis=1, keepdims=True)
    out = shapes.copy()
    out[rows[whirling], first[whirling]] = resolved[whirling, :, 0]
    out[rows[whirling], first[whirling] + 1] = resolved[whirling, :, 1]
    return out


# ----------------------------------------------------------------------------------------
def _body_quadratic(mass, center, second_moment, X) -> np.ndarray:
    """``sum_p m_p Z_p^T X Z_p`` over the particles of a rigid body, Z_p = [I, -skew(r_p)].

    Needs only the body's mass, first moment and second-moment tensor about the
    reference point.
    """
    basis = skew(np.eye(3))  # E_k = skew(unit_k), shape (3, 3, 3)
    first = skew(mass * np.asarray(center))
    out = np.zeros((6, 6))
    out[:3, :3] = mass * X
    out[:3, 3:] = -X @ first
    out[3:, :3] = first @ X
    out[3:, 3:] = -np.einsum("kl,kab,bc,lcd->ad", second_moment, basis, X, basis)
    return out


class WhirlForms(NamedTuple):
    """Quadratic forms of the whirl ratio (each (n, n)); see :func:`whirl_forms`."""

    W: np.ndarray
    N: np.ndarray
    total: np.ndarray


_DIRECTIONS = ("W", "N", "total")


def _body_forms(model, mass, center, inertia) -> dict:
    """The 6x6 forms W, N, total of one rigid body's motion at the reference point."""
    e = model.spin_axis
    directions = {"W": skew(e), "N": np.eye(3) - np.outer(e, e), "total": np.eye(3)}
    arm = np.asarray(center) - model.reference_point
    second = 0.5 * np.trace(inertia) * np.eye(3) - inertia + mass * np.outer(arm, arm)
    return {name: _body_quadratic(mass, arm, second, X) for name, X in directions.items()}


def whirl_forms(model) -> WhirlForms:
    """Quadratic forms ``W``, ``N`` and ``total`` of the whirl ratio of a mode shape phi.

    ``-i phi^H W phi`` is the mass-weighted orbital angular momentum of the
    whole machine's vibration about the spin axis (per unit frequency),
    ``phi^H N phi`` the mass-weighted mean square motion normal to it and
    ``phi^H total phi`` that of the whole motion (``total`` equals the mass
    matrix). Each body contributes ``T_b^T X_b T_b`` (its motion ``T_b`` over the
    generalized coordinates). See ``docs/theory.md``.
    """
    bodies = body_inertias(model)
    forms = [_body_forms(model, *body) for body in bodies]
    parts = {name: frame_block(model, sum(f[name] for f in forms)) for name in _DIRECTIONS}
    first_rotor = len(bodies) - len(model.rotors)
    for rotor, body in zip(model.rotors, forms[first_rotor:]):
        for name in _DIRECTIONS:
            add_rotor_body(parts[name], model, rotor.name, body[name])
    return WhirlForms(**parts)


def rotor_whirl_forms(model, rotor: str) -> WhirlForms:
    """The whirl forms of one rotor's own motion (absolute), each (n, n)."""
    index = [r.name for r in model.rotors].index(rotor)
    mass, center, inertia = body_inertias(model)[len(body_inertias(model)) - len(model.rotors) + index]
    body = _body_forms(model, mass, center, inertia)
    motion = model.dofs.body_motion(rotor)
    return WhirlForms(**{name: motion.T @ body[name] @ motion for name in _DIRECTIONS})


def whirl_ratios(shapes, forms: WhirlForms, speeds) -> np.ndarray:
    """Signed whirl ratio in [-1, 1] relative to the reference rotor's spin.

    +1 for a circular orbit normal to the spin axis turning with the spin, -1
    against it, 0 for straight-line orbits. Modes whose motion normal to the
    axis is below ``1e-9`` of their whole motion (pure axial or roll motion)
    get 0, not a ratio of round-off to round-off.

    Parameters
    ----------
    shapes : ndarray, shape (..., m, n)
    forms : WhirlForms
    speeds : ndarray, shape (...) [rad/s]; the sign of the spin (0 counts as +)

    Returns
    -------
    ndarray, shape (..., m)
    """
    n = shapes.shape[-1]
    # phi^H X phi of the three forms for every shape: one batched product with [W^T N^T total^T]
    stacked = np.concatenate([forms.W.T, forms.N.T, forms.total.T], axis=1)
    products = (shapes @ stacked).reshape(shapes.shape[:-1] + (3, n))
    values = np.einsum("...i,...ki->...k", shapes.conj(), products)
    momentum = values[..., 0].imag  # Re(-i phi^H W phi)
    across = values[..., 1].real
    whole = values[..., 2].real
    whirling = across > 1e-9 * whole
    ratio = np.where(whirling, momentum / np.where(whirling, across, 1.0), 0.0)
    sign = np.where(np.asarray(speeds) < 0, -1.0, 1.0)
    return np.clip(ratio * np.asarray(sign)[..., None], -1.0, 1.0)


def whirl_labels(ratios) -> np.ndarray:
    """'forward', 'backward' or 'none' from whirl ratios (array of str)."""
    ratios = np.asarray(ratios)
    return np.where(ratios > WHIRL_TOLERANCE, "forward",
                    np.where(ratios < -WHIRL_TOLERANCE, "backward", "none"))


def mass_normalized(shapes, M) -> np.ndarray:
    """``L^T phi`` normalised to unit length, with ``M = L L^T``: shapes whose plain
    inner product is the mass-weighted one (unit-consistent MAC)."""
    factor = np.linalg.cholesky(M)
    weighted = shapes @ factor.conj()
    return weighted / np.linalg.norm(weighted, axis=-1, keepdims=True)


def mac_matrix(a, b) -> np.ndarray:
    """Modal assurance criterion between unit shape sets ``a`` (..., m, n) and ``b`` (..., p, n).

    Returns
    -------
    ndarray, shape (..., m, p), values in [0, 1]
    """
    return np.abs(a.conj() @ np.swapaxes(b, -1, -2)) ** 2  # batched BLAS, not einsum's loops
