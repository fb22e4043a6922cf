"""Batched eigen-solutions of the speed-dependent state matrix, whirl and MAC.

Speed: eigenvalues and eigenvectors of all speeds come from one batched LAPACK
call split over threads (numpy releases the GIL); a mode shape is the
displacement part of its state eigenvector. (One step of inverse iteration on the
quadratic pencil ``Q(lam) = lam^2 M + lam (C + Omega G) + K`` per mode, which an
earlier version used, costs as much for 6 coordinates and grows as n^4 per speed;
it still gives the shape at a single known eigenvalue, e.g. at a critical speed.)
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

from typing import NamedTuple

import numpy as np

from ..assembly import add_rotor_body, body_inertias, frame_block
from ..geometry import skew

__all__ = ["upper_eigenvalues", "mode_shapes", "solve_batch", "whirl_forms", "rotor_whirl_forms",
           "whirl_ratios",
           "mass_normalized", "mac_matrix", "WhirlForms", "OSCILLATORY_TOLERANCE", "WHIRL_TOLERANCE"]

#: |Im lam| below this fraction of the largest |lam| of a speed counts as non-oscillatory
OSCILLATORY_TOLERANCE = 1e-6
#: |whirl ratio| below this counts as no whirl (a straight-line orbit): for an elliptic
#: orbit the ratio is 2ab/(a^2+b^2), so this is a minor/major axis ratio of 5e-4
WHIRL_TOLERANCE = 1e-3

_THREADS = max(1, min(4, os.cpu_count() or 1))
_CHUNK = 64
_rng_vectors = np.random.default_rng(20261122).standard_normal((2, 64, 64))
_START_VECTORS = _rng_vectors[0] + 1j * _rng_vectors[1]


_POOL: ThreadPoolExecutor | None = None


def _eig(matrices: np.ndarray):
    """``numpy.linalg.eig`` over the first axis, in threads for large batches (see :func:`_threaded`)."""
    threads = int(os.environ.get("ROTORDYN_MODAL_THREADS", _THREADS))
    if len(matrices) < 2 * _CHUNK or threads <= 1:
        return np.linalg.eig(matrices)
    parts = _threaded(lambda a: np.concatenate([(r := np.linalg.eig(a))[0][:, None, :], r[1]], axis=1),
                      matrices)
    return parts[:, 0, :], parts[:, 1:, :]


def _threaded(function, *batches: np.ndarray) -> np.ndarray:
    """Apply a batched numpy routine over the first axis of its arrays using a few threads.

    LAPACK-backed numpy routines and large array arithmetic release the GIL, so
    the parts run in parallel. Set ``ROTORDYN_MODAL_THREADS=1`` (as parameter
    studies do in their worker processes) to stay on one core.
    """
    global _POOL
    threads = int(os.environ.get("ROTORDYN_MODAL_THREADS", _THREADS))
    if len(batches[0]) < 2 * _CHUNK or threads <= 1:
        return function(*batches)
    if _POOL is None or _POOL._max_workers != threads:
        _POOL = ThreadPoolExecutor(threads, thread_name_prefix="rotordyn-eig")
    parts = [np.array_split(batch, threads) for batch in batches]
    return np.concatenate(list(_POOL.map(function, *parts)))


def upper_eigenvalues(state_matrices: np.ndarray) -> np.ndarray:
    """The n eigenvalues with the largest imaginary parts of each state matrix.

    One of each complex-conjugate pair, and half of the real eigenvalues (the
    ones of smaller magnitude), sorted by imaginary part, then real part.

    Parameters
    ----------
    state_matrices : ndarray, shape (N, 2n, 2n)

    Returns
    -------
    ndarray, shape (N, n), complex [1/s]
    """
    values = _threaded(np.linalg.eigvals, state_matrices)
    return select_upper(values)


def select_upper(values: np.ndarray) -> np.ndarray:
    """Pick the upper half of each row of eigenvalues; see :func:`upper_eigenvalues`."""
    return upper_indices(values)[1]


def upper_indices(values: np.ndarray):
    """Where the upper half of each row of eigenvalues sits, and those eigenvalues.

    Returns
    -------
    index : ndarray of int, shape (..., n)
        Positions in ``values`` (and in the columns of the eigenvector matrices).
    upper : ndarray, shape (..., n), complex
        Sorted by imaginary part, then real part (see :func:`upper_eigenvalues`); roots
        whose imaginary part is round-off are made real.
    """
    n = values.shape[-1] // 2
    scale = np.abs(values).max(axis=-1, keepdims=True)
    tol = OSCILLATORY_TOLERANCE * np.where(scale > 0, scale, 1.0)
    imag = np.where(np.abs(values.imag) <= tol, 0.0, values.imag)
    # within the real block, prefer the smaller |lam|: a second stable sort by -|lam| first
    pre = np.argsort(-np.abs(values), axis=-1, kind="stable")
    imag_pre = np.take_along_axis(imag, pre, axis=-1)
    order = np.take_along_axis(pre, np.argsort(imag_pre, axis=-1, kind="stable"), axis=-1)
    chosen = order[..., n:]
    upper = np.take_along_axis(values, chosen, axis=-1)
    upper_imag = np.take_along_axis(imag, chosen, axis=-1)
    upper = np.where(upper_imag == 0.0, upper.real + 0j, upper)
    final = np.lexsort((upper.real, upper.imag), axis=-1)
    return np.take_along_axis(chosen, final, axis=-1), np.take_along_axis(upper, final, axis=-1)


def mode_shapes(M, damping, K, eigenvalues, branches=None) -> np.ndarray:
    """Right eigenvectors ``phi`` of ``Q(lam) phi = 0`` by one inverse-iteration step.

    Parameters
    ----------
    M : ndarray, shape (n, n)
    damping : ndarray, shape (N, n, n)
        ``C + Omega G`` at each speed.
    K : ndarray, shape (n, n) or (N, n, n)
        Stiffness (per speed when bearing coefficients depend on speed).
    eigenvalues : ndarray, shape (N, m), complex
    branches : (ndarray (n_b, n, n), ndarray (n_b,)), optional
        Maxwell branches' stiffness [N/m, ...] and relaxation times [s]: the pencil
        gains ``sum_b lam tau_b / (1 + lam tau_b) K_b``.

    Returns
    -------
    ndarray, shape (N, m, n), complex
        Unit-norm shapes (displacement part of the state eigenvectors).
    """
    if np.ndim(K) == 3:
        return _threaded(lambda d, lam, k: _mode_shapes_part(M, d, k[:, None], lam, branches),
                         damping, eigenvalues, K)
    return _threaded(lambda d, lam: _mode_shapes_part(M, d, K, lam, branches), damping, eigenvalues)


def _mode_shapes_part(M, damping, K, eigenvalues, branches=None):
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


def pencil_shapes(M, damping, stiffness, eigenvalues, branches=None) -> np.ndarray:
    """One inverse-iteration step per row for a single known eigenvalue: ``Q(lam) phi = 0``.

    Parameters
    ----------
    M, damping, stiffness : ndarray, shape (P, n, n)
        Each row's mass, ``C + Omega G`` and stiffness.
    eigenvalues : ndarray, shape (P,), complex
    branches : (ndarray (P, n_b, n, n), ndarray (P, n_b)), optional
        Each row's Maxwell branches (stiffness, relaxation times).

    Returns
    -------
    ndarray, shape (P, n), complex, unit norm
    """
    lam = np.asarray(eigenvalues)[:, None, None]
    shifted = lam + 1e-13 * (np.abs(lam) + 1e-300) * (1 + 1j)   # as in _mode_shapes_part
    pencil = shifted * damping + stiffness + shifted**2 * M
    if branches is not None and branches[1].shape[-1]:
        stiffness_b, times = branches
        factor = shifted[:, 0] * times / (1 + shifted[:, 0] * times)        # (P, n_b)
        pencil = pencil + np.einsum("pb,pbij->pij", factor, stiffness_b)
    start = np.broadcast_to(_start_vectors(1, M.shape[-1])[0][:, None], pencil.shape[:-1] + (1,))
    vectors = _solve(pencil, start)[..., 0]
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


def _start_vectors(m: int, n: int) -> np.ndarray:
    """Fixed pseudo-random start vectors (m, n) of inverse iteration, reproducible run to run."""
    if m <= _START_VECTORS.shape[0] and n <= _START_VECTORS.shape[1]:
        return _START_VECTORS[:m, :n]
    rng = np.random.default_rng([20261122, m, n])
    return rng.standard_normal((m, n)) + 1j * rng.standard_normal((m, n))


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
    eigenvalues : ndarray, shape (N, m), complex [1/s]
        ``m = n_states / 2`` roots per speed.
    shapes : ndarray, shape (N, m, n), complex
        Unit-norm displacement parts of the state eigenvectors.
    """
    speeds = np.asarray(speeds, dtype=float)
    values, vectors = _eig(form.at(speeds))
    index, eigenvalues = upper_indices(values)
    n = form.n_dof
    shapes = np.swapaxes(np.take_along_axis(vectors[:, :n, :], index[:, None, :], axis=-1), -1, -2)
    norms = np.linalg.norm(shapes, axis=-1, keepdims=True)
    # a Maxwell junction relaxing with the machine at rest has no displacement: keep it zero
    shapes = shapes / np.where(norms > 0, norms, 1.0)
    if forms is not None:
        shapes = resolve_repeated(eigenvalues, shapes, forms)
    return eigenvalues, shapes


#: eigenvalues closer than this (relative) are one repeated eigenvalue
REPEATED_TOLERANCE = 1e-9


def resolve_repeated(eigenvalues, shapes, forms, variants=None):
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
        Each (n, n), or (V, n, n) for rows of several variants.
    variants : ndarray of int, shape (N,), optional
        The variant of each row, with forms stacked over variants.

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
    if not len(rows):
        return shapes
    if variants is not None:
        forms = WhirlForms(*(f[variants[rows]] for f in forms))
    basis = np.stack([shapes[rows, first], shapes[rows, first + 1]], axis=-1)  # (P, n, 2)
    rule = "pia,pij,pjb->pab" if forms.total.ndim == 3 else "pia,ij,pjb->pab"
    total = np.einsum(rule, basis.conj(), forms.total, basis)
    # the two shapes must span a plane (two inverse iterations could give one direction)
    spans = np.abs(np.linalg.det(total)) > 1e-6 * np.abs(total[:, 0, 0] * total[:, 1, 1])
    rows, first, basis, total = rows[spans], first[spans], basis[spans], total[spans]
    if forms.total.ndim == 3:
        forms = WhirlForms(*(f[spans] for f in forms))
    if not rows.size:
        return shapes
    momentum = -1j * np.einsum(rule, basis.conj(), forms.W, basis)
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
def _bodies_quadratic(masses, centers, second_moments, X) -> np.ndarray:
    """``sum_p m_p Z_p^T X Z_p`` over the particles of each rigid body, Z_p = [I, -skew(r_p)].

    Needs only each body's mass, first moment and second-moment tensor about the reference
    point: ``sum_p m_p skew(r_p) X skew(r_p) = sum_kl Q_kl E_k X E_l`` with ``E_k = skew(unit_k)``.

    Parameters
    ----------
    masses : ndarray (B,); centers : ndarray (B, 3); second_moments : ndarray (B, 3, 3); X : (3, 3)

    Returns
    -------
    ndarray, shape (B, 6, 6)
    """
    basis = skew(np.eye(3))                                   # E_k, shape (3, 3, 3)
    products = np.einsum("kab,bc,lcd->klad", basis, X, basis)   # E_k X E_l
    first = skew(masses[:, None] * centers)                   # (B, 3, 3)
    out = np.zeros((len(masses), 6, 6))
    out[:, :3, :3] = masses[:, None, None] * X
    out[:, :3, 3:] = -X @ first
    out[:, 3:, :3] = first @ X
    out[:, 3:, 3:] = -np.einsum("zkl,klad->zad", second_moments, products)
    return out


class WhirlForms(NamedTuple):
    """Quadratic forms of the whirl ratio (each (n, n)); see :func:`whirl_forms`."""

    W: np.ndarray
    N: np.ndarray
    total: np.ndarray


_DIRECTIONS = ("W", "N", "total")


def _bodies_forms(model) -> dict:
    """The 6x6 forms W, N, total of each body's rigid motion at the reference point (stator
    first, then the rotors): name -> ndarray (B, 6, 6)."""
    e = model.spin_axis
    directions = {"W": skew(e), "N": np.eye(3) - np.outer(e, e), "total": np.eye(3)}
    bodies = body_inertias(model)
    masses = np.array([m for m, _, _ in bodies], dtype=float)
    arms = np.array([np.asarray(c, dtype=float) for _, c, _ in bodies]) - model.reference_point
    inertias = np.array([np.asarray(j, dtype=float) for _, _, j in bodies])
    traces = np.trace(inertias, axis1=1, axis2=2)
    second = (0.5 * traces[:, None, None] * np.eye(3) - inertias
              + masses[:, None, None] * arms[:, :, None] * arms[:, None, :])
    return {name: _bodies_quadratic(masses, arms, second, X) for name, X in directions.items()}


def whirl_forms(model) -> WhirlForms:
    """Quadratic forms ``W``, ``N`` and ``total`` of the whirl ratio of a mode shape phi.

    ``-i phi^H W phi`` is the mass-weighted orbital angular momentum of the
    whole machine's vibration about the spin axis (per unit frequency),
    ``phi^H N phi`` the mass-weighted mean square motion normal to it and
    ``phi^H total phi`` that of the whole motion (``total`` equals the mass
    matrix). Each body contributes ``T_b^T X_b T_b`` (its motion ``T_b`` over the
    generalized coordinates). See ``docs/theory.md``.
    """
    forms = _bodies_forms(model)
    parts = {name: frame_block(model, forms[name].sum(axis=0)) for name in _DIRECTIONS}
    first_rotor = len(forms["W"]) - len(model.rotors)
    for j, rotor in enumerate(model.rotors):
        if model.dofs.on_bearings(rotor.name):
            for name in _DIRECTIONS:
                add_rotor_body(parts[name], model, rotor.name, forms[name][first_rotor + j])
    return WhirlForms(**parts)


def rotor_whirl_forms(model, rotor: str) -> WhirlForms:
    """The whirl forms of one rotor's own motion (absolute), each (n, n)."""
    index = [r.name for r in model.rotors].index(rotor)
    forms = _bodies_forms(model)
    first_rotor = len(forms["W"]) - len(model.rotors)
    body = {name: forms[name][first_rotor + index] for name in _DIRECTIONS}
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
        Each (n, n), or stacked like the shapes' leading axes, (..., n, n).
    speeds : ndarray, shape (...) [rad/s]; the sign of the spin (0 counts as +)

    Returns
    -------
    ndarray, shape (..., m)
    """
    def form(matrix):  # phi^H X phi for every shape, as one batched product
        return (shapes.conj() * (shapes @ np.swapaxes(matrix, -1, -2))).sum(axis=-1)

    momentum = (-1j * form(forms.W)).real
    across = form(forms.N).real
    whole = form(forms.total).real
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
    norms = np.linalg.norm(weighted, axis=-1, keepdims=True)
    # relaxation roots of Maxwell junctions move no mass: their shape stays zero (MAC 0)
    return weighted / np.where(norms > 0, norms, 1.0)


def mac_matrix(a, b) -> np.ndarray:
    """Modal assurance criterion between unit shape sets ``a`` (..., m, n) and ``b`` (..., p, n).

    Returns
    -------
    ndarray, shape (..., m, p), values in [0, 1]
    """
    return np.abs(np.einsum("...in,...jn->...ij", a.conj(), b)) ** 2
