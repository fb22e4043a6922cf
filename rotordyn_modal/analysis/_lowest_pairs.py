"""A bound that two neighbouring roots of an undamped gyroscopic model do not cross over a speed step.

``campbell``'s checks of its mode links halve a step where the tracking of two close roots is
unsure (``campbell._check_grids``): at rest, a rotor's forward and backward modes of one bending
shape lie a few rad/s apart on anisotropic bearings, and their shapes turn from the bearings' axes
to circular whirl within a few rad/s of speed, so that neither value nor shape tells the pairing
over a coarse step. On the Hermitian route (:func:`._lowest._gyroscopic_roots`) the roots are the
eigenvalues of ``B(Omega) = B_0 + Omega B_1``; where two neighbouring ones stay apart, and apart
from every other, over the whole step, each is one analytic branch there and keeps its rank:
the lower continues to the lower. :func:`pairs_kept` shows that from the step's first speed alone
(docs/theory.md section 17, "Two close roots over a step"):

- ``V`` (2 n, 2): the pair's orthonormal eigenvectors at the first speed ``a``, ``W`` the rest.
  In the basis ``[V W]``, ``B(a + t) = [[A(t), E(t)^H], [E(t), C(t)]]`` with the 2 x 2
  ``A(t) = V^H B(a) V + t V^H B_1 V`` (affine in ``t``) and ``|E(t)| <= |r| + |t| e_1``, ``r`` the
  residual of ``V`` and ``e_1 = |(I - V V^H) B_1 V|``.
- ``C(t)``'s eigenvalues lie within ``|t| |B_1| + delta`` of the rest of ``B(a)``'s computed
  eigenvalues (Weyl; ``delta`` their round-off), so their distance ``eta`` to ``A(t)``'s is bounded
  below; then each eigenvalue of ``B`` lies within ``2 |E|^2 / (eta + sqrt(eta^2 + 4 |E|^2))`` of the
  matching one of ``A`` and ``C`` (Li and Li, 2005, sorted order).
- ``A(t)``'s gap is the square root of a quadratic in ``t``, its least on a part of the step exact.

Where, on each of :data:`_PIECES` parts of the step, ``A``'s gap and ``eta`` both exceed twice that
bound, the pair's two eigenvalues of ``B`` neither meet nor meet another over the step.
"""

from __future__ import annotations

import numpy as np

#: parts of the step on which the bounds are taken (each with its end's |t|: the bound holds over it)
_PIECES = 32

#: round-off allowance on the computed eigenvalues of ``B(a)`` [times eps |B(a)|_F]
_ROUND_OFF = 64


def pairs_kept(stack, start: float, stop: float, ranks) -> np.ndarray:
    """Whether the roots of ranks ``r`` and ``r + 1`` (0 the lowest, by frequency), for each ``r``
    of ``ranks``, of an undamped gyroscopic small model (:func:`._lowest._gyroscopic_roots`' route)
    stay two distinct roots, apart from every other, at every speed from ``start`` to ``stop``
    [rad/s]: each then continues to the root of its own rank at ``stop``. False where that is not
    shown, or the model takes another route.

    Parameters
    ----------
    stack : Stack
        One model.
    start, stop : float
        The step's speeds [rad/s].
    ranks : sequence of int
        Each pair's lower root's rank among the roots ``i omega``, ``omega > 0``, ascending.

    Returns
    -------
    ndarray of bool, shape (len(ranks),)
    """
    from ._lowest import DENSE_BELOW, _hermitian_eigenvectors, _hermitian_form, _kept_reductions, _kept_vectors

    ranks = [int(r) for r in ranks]
    kept = np.zeros(len(ranks), dtype=bool)
    n = stack.n_dof
    hermitian = None if n >= DENSE_BELOW or not ranks else _hermitian_form(stack)
    if hermitian is None or not all(0 <= r < n - 1 for r in ranks):
        return kept
    constant, gyroscopic = hermitian
    known = _kept_vectors(stack).get(float(start))
    if known is not None and known[1].shape[1] >= max(ranks) + 2:      # the check's own solve at the speed
        omega, vectors = known[0][None], known[1][None]
    else:
        omega, vectors = _hermitian_eigenvectors(constant, gyroscopic, np.array([float(start)]), max(ranks) + 2,
                                                 _kept_reductions(stack))
    if vectors is None:
        return kept
    matrix = constant + float(start) * gyroscopic
    scale = _ROUND_OFF * np.finfo(float).eps * np.linalg.norm(matrix)
    firsts = np.array(ranks)
    bases = _orthonormal(np.stack([vectors[0][:, firsts].T, vectors[0][:, firsts + 1].T], axis=-1))   # (k, N, 2)
    others = np.ones((len(ranks), len(omega[0])), dtype=bool)
    others[np.arange(len(ranks)), n + firsts] = others[np.arange(len(ranks)), n + firsts + 1] = False
    rest = np.broadcast_to(omega[0], others.shape)[others].reshape(len(ranks), -1)
    return _pair_bounds_hold(matrix, gyroscopic, bases, rest, float(stop) - float(start),
                             _speed_norm(stack, gyroscopic), scale)


def _orthonormal(pairs):
    """The two columns of each of ``pairs`` (k, N, 2) made orthonormal (Gram-Schmidt, twice)."""
    first = pairs[..., 0] / np.linalg.norm(pairs[..., 0], axis=-1, keepdims=True)
    second = pairs[..., 1]
    for _ in range(2):
        second = second - first * np.sum(first.conj() * second, axis=-1, keepdims=True)
    return np.stack([first, second / np.linalg.norm(second, axis=-1, keepdims=True)], axis=-1)


def _norms_2(columns):
    """Spectral norms (k,) of ``columns`` (k, N, 2): the square roots of the larger eigenvalues of
    their 2 x 2 Gram matrices."""
    gram = np.swapaxes(columns.conj(), -1, -2) @ columns
    return np.sqrt(np.maximum(_top_eigenvalues(gram), 0.0))


def _top_eigenvalues(hermitian):
    """The larger eigenvalues (k,) of 2 x 2 Hermitian matrices (k, 2, 2) (closed form)."""
    mean = 0.5 * (hermitian[:, 0, 0] + hermitian[:, 1, 1]).real
    half = 0.5 * (hermitian[:, 0, 0] - hermitian[:, 1, 1]).real
    return mean + np.hypot(half, np.abs(hermitian[:, 0, 1]))


def _speed_norm(stack, gyroscopic) -> float:
    """``|B_1|_2``, the spectral norm of the speed part of ``B`` (kept on the stack)."""
    kept = stack.constants        # a small model's: shared by its stacks
    cached = kept.get("_lowest_speed_norm")
    if cached is None:
        part = gyroscopic.imag if not np.any(gyroscopic.real) else gyroscopic      # B_1 = i S_1: |B_1| = |S_1|
        cached = kept["_lowest_speed_norm"] = float(np.linalg.norm(part, 2)) * (1 + 1e-12)
    return cached


def _pair_bounds_hold(matrix, speed_part, bases, rest, step, speed_norm, scale) -> np.ndarray:
    """:func:`pairs_kept`'s test from ``B(a)`` (``matrix``, Hermitian (N, N)), ``B_1``
    (``speed_part``), each pair's orthonormal basis ``bases`` (k, N, 2), the other computed
    eigenvalues ``rest`` (k, N - 2) of ``B(a)``, the ``step`` to the last speed [rad/s], ``|B_1|_2``
    (``speed_norm``) and the eigenvalues' round-off ``scale``.

    Returns
    -------
    ndarray of bool, shape (k,)
        Over every ``t`` between 0 and ``step``, ``A(t)``'s gap and the distance ``eta`` of its
        eigenvalues to ``C(t)``'s each exceed twice the Li-Li bound.
    """
    step_sign = 1.0 if step >= 0 else -1.0
    length = abs(step)
    adjoint = np.swapaxes(bases.conj(), -1, -2)                  # (k, 2, N)
    applied = matrix @ bases
    first = adjoint @ applied
    first = 0.5 * (first + np.swapaxes(first.conj(), -1, -2))    # A(0)
    moved = speed_part @ bases
    slope = adjoint @ moved
    slope = step_sign * 0.5 * (slope + np.swapaxes(slope.conj(), -1, -2))     # dA/dt, t = |Omega - a|
    residual = _norms_2(applied - bases @ first)
    coupling = _norms_2(moved - bases @ (adjoint @ moved))                   # e_1
    slope_norm = np.maximum(np.abs(_top_eigenvalues(slope)), np.abs(_top_eigenvalues(-slope)))
    edges = np.linspace(0.0, length, _PIECES + 1)
    low, high = edges[:-1], edges[1:]                            # (pieces,)
    # A(t)'s gap squared, (a11 - a22)^2 + 4 |a12|^2, a quadratic in t: its least on each part exactly
    d0, d1 = (first[:, 0, 0] - first[:, 1, 1]).real[:, None], (slope[:, 0, 0] - slope[:, 1, 1]).real[:, None]
    o0, o1 = first[:, 0, 1][:, None], slope[:, 0, 1][:, None]
    c2 = d1 * d1 + 4 * np.abs(o1) ** 2                           # (k, 1)
    c1 = 2 * d0 * d1 + 8 * (o0.conj() * o1).real
    c0 = d0 * d0 + 4 * np.abs(o0) ** 2

    def square(t):
        return (c2 * t + c1) * t + c0

    least = np.minimum(square(low), square(high))                # (k, pieces)
    with np.errstate(invalid="ignore", divide="ignore"):
        vertex = np.where(c2 > 0, -c1 / np.where(c2 > 0, 2 * c2, 1.0), -np.inf)
    inside = (low < vertex) & (vertex < high)
    least = np.where(inside, np.minimum(least, square(np.where(inside, vertex, 0.0))), least)
    gap = np.sqrt(np.maximum(least, 0.0)) - 2 * scale
    # A(t)'s eigenvalues at each part's start, then moving at most |dA/dt| over it
    mean = 0.5 * (first[:, 0, 0] + first[:, 1, 1]).real[:, None] + 0.5 * (slope[:, 0, 0] + slope[:, 1, 1]).real[:, None] * low
    half = 0.5 * np.sqrt(np.maximum(square(low), 0.0))
    ends = np.stack([mean - half, mean + half], axis=-1)                         # (k, pieces, 2)
    if rest.shape[-1]:
        distance = np.abs(ends[..., None] - rest[:, None, None, :]).min(axis=(-2, -1))
    else:
        distance = np.full(ends.shape[:2], np.inf)
    eta = distance - (high - low) * slope_norm[:, None] - high * speed_norm - residual[:, None] - scale
    size = residual[:, None] + high * coupling[:, None]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        bound = np.where(eta > 0, 2 * size * size / (eta + np.sqrt(eta * eta + 4 * size * size)), np.inf)
    return np.all((eta > 0) & (gap > 2 * bound) & (eta > 2 * bound), axis=-1)
