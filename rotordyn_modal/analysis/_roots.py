"""Which roots of a dense eigen-solve are modes, and which numbers are its round-off.

LAPACK's QR algorithm is backward stable: the eigenvalues it returns are exact for ``B + E``
with ``||E|| <= c eps ||B||_F``, ``B`` the matrix as LAPACK balances it first (:func:`round_off`). So every test of a root compares that root with this round-off
of its own solve (``docs/theory.md`` section 8), never with the other roots:

- a root whose ``|lam|`` is below ``noise`` is a zero root (a direction without suspension);
  so is one below ``sqrt(noise)`` whose shape the stiffness does not load: a free direction
  without damping is a double zero root with one eigenvector, the Jordan block
  ``[[0, 1], [0, 0]]`` of the rows ``q' = v`` of ``A``, which the perturbation splits into
  ``+-sqrt(||E||)``, a pair that would read as an undamped mode;
- a root whose ``|Im lam|`` is below ``noise`` is real (a relaxation root, or a repeated real
  root split into a pair by round-off);
- a modal number (damping ratio, whirl ratio) within what that round-off can move it is
  printed as 0.
"""

from __future__ import annotations

import numpy as np

from . import _batches

__all__ = ["BACKWARD_FACTOR", "round_off", "affine_round_off", "deciding_round_off", "conservative", "balanced_norm", "snapped", "snapped_with_round_off", "zero_roots", "unresolved_roots", "zero_floor", "FREE_LOADING", "whirl_round_off", "one_root", "REPEATED_OWN", "at_round_off"]

#: the backward error of a dense eigen-solve taken as this many ``eps ||B||_F``, ``B`` the
#: balanced matrix (LAPACK's bound grows slowly with the size; measured errors are a few eps ||B||)
BACKWARD_FACTOR = 100.0
#: sweeps of the balancing (each halves the remaining imbalance of every row and column)
_BALANCE_SWEEPS = 64


def round_off(matrices) -> np.ndarray:
    """Absolute round-off of the eigenvalues of state matrices [1/s].

    LAPACK's ``geev`` (numpy's ``eig`` and ``eigvals``) balances a matrix before it solves:
    ``B = D^-1 A D`` with ``D`` diagonal, which leaves the eigenvalues as they are. Its backward
    error is relative to ``B``, not to ``A``: a machine with a very stiff film next to a soft
    rotor has ``||A||`` set by the film (1e17 for a film of 1e9 Pa s) while its whirl roots, of a
    few hundred 1/s, are computed to ``eps ||B||``, three orders of magnitude smaller. So the
    round-off of a root is read from the balanced matrix (:func:`balanced_norm`), never from the
    size of the largest entry of ``A``.

    Parameters
    ----------
    matrices : ndarray, shape (..., n_s, n_s)

    Returns
    -------
    ndarray, shape (...): ``BACKWARD_FACTOR * eps * ||B||_F``
    """
    return BACKWARD_FACTOR * np.finfo(float).eps * balanced_norm(matrices)


def deciding_round_off(values, matrices) -> np.ndarray:
    """:func:`round_off` of each matrix wherever it can change what :func:`snapped` makes of
    its roots ``values``; elsewhere ``BACKWARD_FACTOR eps ||A||_F`` (1 + 1e-8), an upper bound
    of it, with which :func:`snapped` gives the same bits.

    The balancing never raises the Frobenius norm (:func:`balanced_norm`: each sweep scales the
    squares of every index ``k``'s row by ``1 / sqrt(y_k)`` and of its column by ``sqrt(y_k)``,
    ``y_k = 16^s`` between 1 and ``r_k / c_k``, its off-diagonal row and column sums of
    squares, so ``c_k y_k + r_k / y_k <= r_k + c_k``, and with ``sqrt(y_j / y_i) <= (y_j + 1 /
    y_i) / 2`` the off-diagonal sum of squares does not grow; ``docs/theory.md`` section 8), so
    ``round_off <= U``, the bound (its 1e-8 covers the rounding of both norms). A
    root whose ``|Im lam|`` is 0 or above ``U`` and whose ``|lam|`` is above ``zero_floor(U)``
    is snapped alike by every noise up to ``U``: only matrices with a root within those bounds
    (a zero root, a real root split by round-off) are balanced. For the roots of a sweep's
    oscillating modes that is none: the balancing took 1.4 of the 10.2 ms of CPU of a rigid
    rotor's Campbell call at 201 speeds (``benchmarks/README.md``).

    Parameters
    ----------
    values : ndarray, shape (..., m), complex
        All roots of each solve.
    matrices : ndarray, shape (..., n_s, n_s)

    Returns
    -------
    ndarray, shape (...) [1/s]
    """
    matrices = np.asarray(matrices, dtype=float)
    bound = BACKWARD_FACTOR * np.finfo(float).eps * np.sqrt(np.einsum("...ij,...ij->...", matrices, matrices))
    bound = np.asarray(bound * (1.0 + _BOUND_SLACK))       # an array also for one matrix
    values = np.asarray(values)
    limit = bound[..., None]
    imaginary = np.abs(values.imag)
    with np.errstate(invalid="ignore"):
        open_ = ((imaginary > 0) & (imaginary <= limit)) | (np.abs(values) <= zero_floor(limit))
        needed = open_.any(axis=-1) | ~np.isfinite(bound)
    if needed.any():
        bound[needed] = round_off(matrices[needed])
    return bound


#: relative allowance for the rounding of the two norms in :func:`deciding_round_off`'s bound
_BOUND_SLACK = 1e-8


def balanced_norm(matrices) -> np.ndarray:
    """Frobenius norm of each matrix balanced as LAPACK's ``gebal`` balances it (scaling only).

    ``B = D^-1 A D`` with ``D`` powers of two chosen so that each row and column of the
    off-diagonal part of ``B`` have norms within a factor of four; all rows and columns are
    scaled together, each step half the one that would balance it alone (whole steps
    overshoot: scaling one index changes the others' norms). The result is within a small
    factor of the norm of LAPACK's own balanced matrix (tested against ``dgebal``), at the cost
    of a few products of the stack, with no Python loop over the matrices.

    Parameters
    ----------
    matrices : ndarray, shape (..., n, n)

    Returns
    -------
    ndarray, shape (...)
    """
    a = np.asarray(matrices, dtype=float)
    n = a.shape[-1]
    flat = a.reshape((-1, n, n))
    out = np.empty(len(flat))
    # a part of the stack at a time, its sweeps in the cache (the whole stack's passes ran at memory speed)
    for part in _batches.chunk_slices(len(flat), 8 * n * n, budget=_BALANCE_BYTES):
        out[part] = _balanced_norms(flat[part])
    return out.reshape(a.shape[:-2])


#: the part of a stack balanced at once [bytes]
_BALANCE_BYTES = 2**21


def affine_round_off(A0, A1, speeds) -> np.ndarray:
    """:func:`round_off` of state matrices ``A0 + Omega A1`` (n_s, n_s) each at ``speeds`` (N,)
    [rad/s] without forming them: the balancing ``D`` of the one at the largest ``|Omega|``
    (:func:`balanced_norm`'s) kept for all, so ``||D^-1 A D||_F^2`` is a quadratic in ``Omega``
    (three sums). Equal to :func:`round_off` at that speed; elsewhere the norm of a balancing that
    is not that matrix's own, within the factor by which the balancing moves with speed (measured
    on the examples with a rotor: within 2 % across 0-600 rad/s).

    Returns
    -------
    ndarray, shape (N,) [1/s]
    """
    speeds = np.asarray(speeds, dtype=float)
    if not len(speeds):
        return np.zeros(0)
    reference = speeds[np.argmax(np.abs(speeds))]
    log_d = _balanced_norms((A0 + reference * A1)[None], exponents=True)[1][0]
    scale = np.exp2(log_d[None, :] - log_d[:, None])              # b_ij = a_ij d_j / d_i
    B0, B1 = A0 * scale, A1 * scale
    squares = np.sum(B0 * B0) + 2.0 * speeds * np.sum(B0 * B1) + speeds * speeds * np.sum(B1 * B1)
    return BACKWARD_FACTOR * np.finfo(float).eps * np.sqrt(np.maximum(squares, 0.0))


def _balanced_norms(matrices, exponents: bool = False):
    """:func:`balanced_norm` of a stack (P, n, n): the sweeps go on for the matrices not yet
    balanced only; each matrix's products are its own (a row's bits do not depend on the others).
    With ``exponents`` also ``log2`` of each balancing's ``D`` (P, n)."""
    squares = matrices * matrices
    diagonal = np.einsum("pii->pi", squares).copy()
    np.einsum("pii->pi", squares)[...] = 0.0             # the off-diagonal part
    log_d = np.zeros(squares.shape[:-1])      # log2 of D's entries: b_ij = a_ij d_j / d_i
    active = None                             # the matrices still moving: all, until some stop
    part, d2 = squares, np.ones(squares.shape[:-1])
    # few numpy calls per sweep (a small stack's sweeps cost their calls, not their arithmetic);
    # the matrices still moving are taken apart only when some stop (a matrix whose step is
    # zero keeps its D: its next step would be zero again)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(_BALANCE_SWEEPS):
            columns = ((1.0 / d2)[:, None, :] @ part)[:, 0] * d2      # sum_i a_ij^2 d_j^2 / d_i^2
            rows = (part @ d2[:, :, None])[..., 0] / d2
            step = np.trunc(0.25 * np.log2(rows / columns))
            np.copyto(step, 0.0, where=~np.isfinite(step))
            moving = step.any(axis=-1)
            if not moving.all():
                if not moving.any():
                    break
                active = moving.nonzero()[0] if active is None else active[moving]
                step, part = step[moving], squares[active]
            if active is None:
                log_d += step
                d2 = np.exp2(2.0 * log_d)
            else:
                log_d[active] += step
                d2 = np.exp2(2.0 * log_d[active])
    d2 = np.exp2(2.0 * log_d)
    off_squares = (((1.0 / d2)[:, None, :] @ squares) @ d2[:, :, None])[:, 0, 0]
    norms = np.sqrt(off_squares + diagonal.sum(axis=-1))
    return (norms, log_d) if exponents else norms


def zero_floor(noise) -> np.ndarray:
    """``|lam|`` at or below which a root is a zero root: ``max(noise, sqrt(noise))`` (the
    square root is the split of a double zero root by a perturbation ``noise``), same shape."""
    noise = np.asarray(noise, dtype=float)
    return np.maximum(noise, np.sqrt(noise))


def snapped(values, noise, matrices=None, vectors=None, n: int | None = None, mass=None) -> np.ndarray:
    """Eigenvalues with their round-off removed: zero roots (:func:`zero_roots`) made exactly 0
    and imaginary parts within ``noise`` made exactly 0.

    Parameters
    ----------
    values : ndarray, shape (..., m), complex [1/s]
        All roots of each solve.
    noise : ndarray, shape (...) [1/s]
        :func:`round_off` of each solve.
    matrices, vectors, n, mass : optional
        See :func:`zero_roots`.

    Returns
    -------
    ndarray, shape (..., m), complex
    """
    return snapped_with_round_off(values, noise, matrices, vectors, n, mass)[0]


def snapped_with_round_off(values, noise, matrices=None, vectors=None, n: int | None = None, mass=None):
    """:func:`snapped`, the round-off of each root (..., m) [1/s]: ``noise``, or for a slow
    mode below it that its own shape resolves, that shape's (:func:`_below_noise`, whose root
    replaces the solve's), and ``values`` with those roots replaced (nothing else snapped: the
    roots a whirl's gap is measured to, :func:`whirl_round_off`)."""
    values = np.asarray(values, dtype=complex)
    zero, own, values = _judged(values, noise, matrices, vectors, n, mass)
    out = np.where(np.abs(values.imag) <= own, values.real + 0j, values)
    return np.where(zero, 0j, out), own, values


def zero_roots(values, noise, matrices=None, vectors=None, n: int | None = None, mass=None) -> np.ndarray:
    """Which roots are zero roots (directions without suspension) to round-off.

    ``|lam| <= noise``; or ``|lam| <= sqrt(noise)`` (the split of a double zero root) where the
    shape is a free direction to round-off. Two tests, both on the mode's own numbers:

    - ``||A_vq phi||`` within :func:`_free_bound` ``||x||``, with ``A_vq = -M^-1 K`` the rows
      ``v'`` and columns ``q`` of the state matrix, ``phi`` the ``q`` part of the eigenvector
      ``x`` (the shape is not loaded beyond what its own root ``lam`` explains);
    - with ``mass`` given: the shape's own stiffness and damping (gyroscopic) terms
      ``phi^H K phi = -phi^H M A_vq phi`` (with the Maxwell branches' states) and
      ``lam phi^H (C + Omega G) phi = -phi^H M A_vv x_v`` are each within the round-off of
      forming them from ``M`` and the state matrix, :data:`FREE_LOADING` ``eps ||M|| ||A_..||
      ||phi|| ||x_.||`` (:func:`_loaded`). A free direction's shape ``phi0`` has ``K phi0 = 0``
      and ``(C + Omega G) phi0 = 0``, so round-off in its eigenvector enters these forms to second
      order only, while its root is the square root of the solve's round-off; a slow mode's root is
      made by its own stiffness (``lam^2 m = -k - lam (c + Omega g)``), whatever the other roots
      of the machine. The first test alone calls every undamped, non-gyroscopic root below
      ``sqrt(noise)`` free (its residual is exactly ``|lam|^2``): a rotor of 1e6 kg on 1e-6 N/m
      bearings spinning at 100 rad/s lost its cylindrical pair (1.4e-6 1/s) that way.

    Without the eigenvectors every root below ``sqrt(noise)`` is one. (A slow mode of a rotor,
    such as the backward conical whirl of a fast rotor on soft bearings, has ``K phi != 0`` and
    stays a mode.)

    Parameters
    ----------
    values : ndarray, shape (..., m), complex [1/s]
    noise : ndarray, shape (...) [1/s]
    matrices : ndarray, shape (..., n_s, n_s), optional
        The state matrices solved.
    vectors : ndarray, shape (..., n_s, m), optional
        Their eigenvectors (columns).
    n : int, optional
        Number of generalized coordinates (``q`` is the first ``n`` states, ``v`` the next ``n``).
    mass : ndarray, shape (n, n) or (..., n, n), optional
        The mass matrix of each solve [kg, kg m^2]; without it only the first test is made.

    Returns
    -------
    ndarray of bool, shape (..., m)
    """
    return _judged(values, noise, matrices, vectors, n, mass)[0]


def _judged(values, noise, matrices=None, vectors=None, n: int | None = None, mass=None):
    """:func:`zero_roots` of ``values`` (..., m), the round-off (..., m) of each root (below which
    its imaginary part is 0): ``noise``, or for a slow mode below ``noise`` kept by its own shape
    that shape's, and the roots with such modes' values from their shapes (:func:`_below_noise`)."""
    values = np.asarray(values)
    noise = np.asarray(noise, dtype=float)[..., None]
    own = np.broadcast_to(noise, values.shape)
    magnitude = np.abs(values)
    zero = magnitude <= noise
    split = (magnitude <= zero_floor(noise)) & ~zero
    if vectors is None:
        return zero | split, own, values
    if mass is not None and (zero & (magnitude > 0)).any():
        zero, own, values = _below_noise(values, noise, zero & (magnitude > 0), matrices, vectors, n, mass)
    if not split.any():
        return zero | split, own, values
    return _split_roots(values, noise, zero, split, matrices, vectors, n, mass), own, values


def _split_roots(values, noise, zero, split, matrices, vectors, n, mass):
    """:func:`zero_roots` given the roots ``zero`` below ``noise`` (..., m) and the candidates
    ``split`` between it and its square root (..., m)."""
    # the few candidates only: usually none
    rows = np.broadcast_to(np.arange(values.size // values.shape[-1]).reshape(values.shape[:-1] + (1,)), values.shape)
    flat_matrices = np.asarray(matrices).reshape((-1,) + np.shape(matrices)[-2:])
    flat_vectors = np.asarray(vectors).reshape((-1,) + np.shape(vectors)[-2:])
    r, k = rows[split], np.nonzero(split.reshape(-1, values.shape[-1]))[1]
    state = flat_vectors[r, :, k]                                                    # (P, n_s)
    residual = np.linalg.norm(np.einsum("pij,pj->pi", flat_matrices[r, n:2 * n, :n], state[:, :n]), axis=-1)
    free = residual <= _free_bound(values[split], np.broadcast_to(noise, values.shape)[split],
                                   flat_matrices, r, n) * np.linalg.norm(state, axis=-1)
    if mass is not None and free.any():
        masses = np.asarray(mass, dtype=float)
        masses = masses.reshape((-1,) + masses.shape[-2:])
        which = r[free] if len(masses) > 1 else np.zeros(int(free.sum()), dtype=int)
        free[free] = ~_loaded(flat_matrices[r[free]], masses[which], state[free], n)
    out = zero.copy()
    out[split] = free
    return out


#: how many times the round-off of forming a shape's stiffness or damping term it may reach and
#: still be a free direction's (measured: up to 1e3 for the free directions of the gear machine,
#: the pumps and a casing without mounts, from a K that the assembly leaves singular only to
#: round-off; a slow mode's own stiffness is above 1e6 of it)
FREE_LOADING = 1e4


def _loaded(matrices, masses, states, n: int) -> np.ndarray:
    """(P,) bool: the shape of each candidate is loaded by the model's own stiffness or damping
    beyond round-off (:func:`zero_roots`).

    Parameters
    ----------
    matrices : ndarray, shape (P, n_s, n_s)
        The state matrix of each candidate.
    masses : ndarray, shape (P, n, n)
    states : ndarray, shape (P, n_s), complex
        The candidates' eigenvectors.
    n : int
    """
    stiffness, damping, _, stiffness_noise, damping_noise = _terms(matrices, masses, states, n)
    return (np.abs(stiffness) > FREE_LOADING * stiffness_noise) | (np.abs(damping) > FREE_LOADING * damping_noise)


def _terms(matrices, masses, states, n: int):
    """The terms of each candidate's scalar equation ``m lam^2 + lam d + k = 0`` from its own
    shape (``phi^H M`` times the ``v`` rows of ``A x = lam x``), and the round-off of forming
    them (arguments as :func:`_loaded`).

    Returns
    -------
    stiffness, damping, inertia : ndarray, shape (P,), complex
        ``k = -phi^H M (A_vq phi + A_vz x_z)`` (``phi^H K phi`` without Maxwell branches ``z``),
        ``lam d = -phi^H M A_vv x_v`` (``lam phi^H (C + Omega G) phi``) and ``phi^H M x_v``
        (``lam m``).
    stiffness_noise, damping_noise : ndarray, shape (P,)
        ``eps ||M|| ||phi||`` times ``||A_vq|| ||phi|| + ||A_vz|| ||x_z||`` and ``||A_vv|| ||x_v||``
        (Frobenius norms).
    """
    eps = np.finfo(float).eps
    phi, velocity, branches = states[:, :n], states[:, n:2 * n], states[:, 2 * n:]
    weighted = np.einsum("pij,pj->pi", masses, phi).conj()                          # (M phi)^H
    rows = matrices[:, n:2 * n]
    stiffness = -(np.einsum("pi,pij,pj->p", weighted, rows[:, :, :n], phi)
                  + np.einsum("pi,pij,pj->p", weighted, rows[:, :, 2 * n:], branches))
    damping = -np.einsum("pi,pij,pj->p", weighted, rows[:, :, n:2 * n], velocity)
    inertia = np.einsum("pi,pi->p", weighted, velocity)
    size = eps * np.linalg.norm(masses, axis=(-2, -1)) * np.linalg.norm(phi, axis=-1)
    stiffness_noise = size * (np.linalg.norm(rows[:, :, :n], axis=(-2, -1)) * np.linalg.norm(phi, axis=-1)
                              + np.linalg.norm(rows[:, :, 2 * n:], axis=(-2, -1)) * np.linalg.norm(branches, axis=-1))
    damping_noise = size * np.linalg.norm(rows[:, :, n:2 * n], axis=(-2, -1)) * np.linalg.norm(velocity, axis=-1)
    return stiffness, damping, inertia, stiffness_noise, damping_noise


def _candidates(values, which, matrices, vectors, mass):
    """The state matrix (P, n_s, n_s), mass matrix (P, n, n) and eigenvector (P, n_s) of each
    root ``which`` (..., m) bool of ``values``."""
    rows = np.broadcast_to(np.arange(values.size // values.shape[-1]).reshape(values.shape[:-1] + (1,)), values.shape)
    flat_matrices = np.asarray(matrices).reshape((-1,) + np.shape(matrices)[-2:])
    flat_vectors = np.asarray(vectors).reshape((-1,) + np.shape(vectors)[-2:])
    r, k = rows[which], np.nonzero(which.reshape(-1, values.shape[-1]))[1]
    masses = np.asarray(mass, dtype=float)
    masses = masses.reshape((-1,) + masses.shape[-2:])
    return flat_matrices[r], masses[r if len(masses) > 1 else np.zeros(len(r), dtype=int)], flat_vectors[r, :, k]


def _below_noise(values, noise, which, matrices, vectors, n: int, mass):
    """Which of the nonzero roots ``which`` (..., m) below ``noise`` are modes made by their own
    stiffness, and the round-off of each root's imaginary part (..., m).

    A root below the solve's round-off is a mode where its shape's own stiffness term ``k =
    phi^H K phi`` is above :data:`FREE_LOADING` times the round-off of forming it (:func:`_terms`)
    and the root is resolved by its shape's own equation ``m lam^2 + d lam + k = 0``: ``|lam|``
    above :data:`FREE_LOADING` times :func:`_own_round_off`, and within :data:`AGREEMENT` of
    that equation's root (:func:`_shape_root`, which it takes: the shape's Rayleigh value). The backward conical whirl of a
    1e6 kg rotor on 1e-6 N/m bearings at 100 rad/s, ``2 k_t / (I_p Omega + ...) = 8.9e-15`` 1/s,
    has ``k`` 1e12 times its round-off, while the solve's round-off is 5.7e-12 1/s. A direction
    without suspension (``K phi = 0``: a free rotor's precession, whose root ``-k/d`` is nothing
    but round-off) stays a zero root. The imaginary part of a kept root is 0 within its own
    round-off, not the solve's (which is larger than the root itself).

    Returns
    -------
    zero : ndarray of bool, shape (..., m)
        ``|lam| <= noise`` and not such a mode.
    own : ndarray, shape (..., m) [1/s]
    refined : ndarray, shape (..., m), complex
        ``values``, the modes kept with the root of their shape's equation (:func:`_shape_root`).
    """
    lam = values[which]
    loaded, mode, resolution, own_root = _verdicts(values, which, matrices, vectors, n, mass)
    zero = np.abs(values) <= noise
    zero[which] = ~mode
    refined = np.array(values, dtype=complex)
    kept = np.where(mode, own_root, lam)
    refined[which] = np.where(np.abs(kept.real) <= resolution, 1j * kept.imag, kept)    # no -0 nor 1e-63
    own = np.array(np.broadcast_to(noise, values.shape), dtype=float)
    own[which] = np.where(mode, np.fmax(resolution, np.abs(own_root - lam)), own[which])
    return zero, own, refined


def _verdicts(values, which, matrices, vectors, n: int, mass):
    """For the roots ``which`` (..., m) bool of ``values`` (:func:`_below_noise`), each (P,):
    whether its shape's stiffness term is loaded, whether it is a mode, its own round-off and
    the root of its shape's equation."""
    matrices_p, masses_p, states = _candidates(values, which, matrices, vectors, mass)
    lam = values[which]
    stiffness, damping, inertia, stiffness_noise, damping_noise = _terms(matrices_p, masses_p, states, n)
    resolution = _own_round_off(lam, stiffness, damping, inertia, stiffness_noise + damping_noise)
    own_root = _shape_root(lam, matrices_p, masses_p, states[:, :n], stiffness, n)
    loaded = np.abs(stiffness) > FREE_LOADING * stiffness_noise
    mode = loaded & (np.abs(lam) > FREE_LOADING * resolution) & (np.abs(own_root - lam) <= AGREEMENT * np.abs(lam))
    return loaded, mode, resolution, own_root


def unresolved_roots(values, noise, matrices, vectors, n: int, mass) -> int:
    """How many nonzero roots below ``noise`` have a shape that its own stiffness loads (not a
    direction without suspension) but are not resolved by it (:func:`_below_noise`): zero roots
    that may be slow modes, which the solve cannot tell (``modes`` says so on stderr). Arguments
    as :func:`zero_roots`, one solve or a stack."""
    values = np.asarray(values)
    noise = np.asarray(noise, dtype=float)[..., None]
    which = (np.abs(values) <= noise) & (np.abs(values) > 0)
    if not which.any():
        return 0
    loaded, mode = _verdicts(values, which, matrices, vectors, n, mass)[:2]
    return int((loaded & ~mode).sum())


#: how near a root below the solve's round-off must be to the root of its own shape's equation
#: (:func:`_shape_root`), relative, to be that shape's mode: the same root, its disagreement its
#: round-off (the cross-coupled, damped rotor of 1e6 kg on 1e-6 N/m at 100 rad/s: numpy's backward
#: conical root is 2.6e-3 from its shape's, which is the one that goes on smoothly from the speeds
#: where the two agree to 4e-6)
AGREEMENT = 0.1


def _shape_root(lam, matrices, masses, phi, stiffness, n: int):
    """The root nearest ``lam`` (P,) of each shape's own equation ``m mu^2 + d mu + k = 0``, ``m
    = phi^H M phi``, ``d = phi^H (C + Omega G) phi = -phi^H M A_vv phi`` and ``k`` (:func:`_terms`)
    (P,): its Rayleigh value, exact for an exact shape (the backward conical whirl 2 k_t / (I_p
    Omega + sqrt(...)) of a rotor on 1e-6 N/m at 1e4 rad/s to 1e-10, where the solve's root is
    9e-7 off), each root of the quadratic taken without cancellation."""
    weighted = np.einsum("pij,pj->pi", masses, phi).conj()
    m = np.einsum("pi,pi->p", weighted, phi)
    d = -np.einsum("pi,pij,pj->p", weighted, matrices[:, n:2 * n, n:2 * n], phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(d * d - 4.0 * m * stiffness + 0j)
        q = -0.5 * np.where(np.abs(d + disc) >= np.abs(d - disc), d + disc, d - disc)
        roots = np.stack([q / m, stiffness / q])
    roots = np.where(np.isfinite(roots), roots, np.inf)
    return roots[np.argmin(np.abs(roots - lam), axis=0), np.arange(len(lam))]


def _own_round_off(lam, stiffness, damping, inertia, noise):
    """How far the round-off ``noise`` (P,) of a shape's terms (:func:`_terms`) moves the root
    ``lam`` (P,) of its scalar equation ``m lam^2 + d lam + k = 0`` [1/s]: ``noise / |P'(lam)|``,
    ``P'(lam) = 2 m lam + d = (m lam^2 - k) / lam``, at most ``sqrt(noise / |m|)`` (a double root
    of the scalar equation)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        mass = np.abs(inertia / lam)
        slope = np.abs(inertia * lam - stiffness) / np.abs(lam)
        return np.fmin(noise / slope, np.sqrt(noise / mass))


def _free_bound(values, noise, matrices, rows, n: int) -> np.ndarray:
    """How large ``||A_vq x_q|| / ||x||`` can be for a free, undamped direction's root ``lam``
    (values, (P,)) of the solve of ``matrices[rows]`` with round-off ``noise`` (P,) [1/s^2].

    An eigenpair of ``A + E`` (``||E|| <= noise``): the ``q`` rows give ``x_v = lam x_q - (E x)_q``
    and the ``v`` rows ``A_vq x_q = lam x_v - A_vv x_v - (E x)_v``, so for a direction that
    neither stiffness, damping nor the gyroscopic terms load (``A_vq phi = A_vv phi = 0``)
    ``||A_vq x_q|| <= (|lam|^2 + noise (1 + |lam| + ||A_vv||)) ||x||``: round-off reaches the
    stiffness rows through the damping rows too (``A_vv (E x)_q``). A slow mode that the
    gyroscopic or damping terms load has ``||A_vq x_q|| ~ |lam| ||A_vv x_q||``, above this
    wherever ``|lam|`` is above its own round-off. ``||A_vv||_2`` is bounded by
    ``sqrt(||A_vv||_1 ||A_vv||_inf)`` (exact for a rotor's gyroscopic block), one per matrix."""
    unique, which = np.unique(rows, return_inverse=True)
    blocks = (np.abs(matrices[i, n:2 * n, n:2 * n]) for i in unique)
    damping = np.array([np.sqrt(b.sum(axis=0).max() * b.sum(axis=1).max()) for b in blocks])[which]
    size = np.abs(values)
    return size * size + noise * (1.0 + size + damping)


def whirl_round_off(eigenvalues, every, noise, repeated: float, own=None) -> np.ndarray:
    """How far round-off can move the whirl ratio of each root's shape (dimensionless).

    An eigenvector is known to about ``noise / gap``, ``gap`` the distance to the nearest other
    root; a repeated root's partner (within ``repeated``) does not count: the pair's shapes are
    chosen by their whirl (``_eigensolve.resolve_repeated``).

    Parameters
    ----------
    eigenvalues : ndarray, shape (..., m), complex
        The roots whose shapes are used.
    every : ndarray, shape (..., M), complex
        All roots of the solve (both halves).
    noise : float or ndarray, shape (...)
        :func:`round_off` of the solve [1/s].
    repeated : float or ndarray, shape (...)
        Distance below which two roots are one repeated root [1/s] (as
        ``_eigensolve.resolve_repeated`` decides).
    own : ndarray, shape (..., m), optional
        The round-off of each root where it is its own (:func:`snapped_with_round_off`: a slow
        mode below ``noise`` that its shape resolves); ``noise`` for every root by default.

    Returns
    -------
    ndarray, shape (..., m)
    """
    lam = np.asarray(eigenvalues, dtype=complex)
    every = np.asarray(every, dtype=complex)
    distance = np.abs(lam[..., :, None] - every[..., None, :])
    distance[one_root(lam[..., :, None], every[..., None, :], np.asarray(repeated, dtype=float)[..., None, None])] = np.inf
    gap = distance.min(axis=-1, initial=np.inf)
    level = np.asarray(noise, dtype=float)[..., None] if own is None else np.asarray(own, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(gap > 0, level / gap, np.inf)


#: two roots further apart than this part of the larger are two roots, never one repeated root
REPEATED_OWN = 1e-3


def one_root(a, b, tolerance) -> np.ndarray:
    """Whether the roots ``a`` and ``b`` (broadcast) are one repeated root: within ``tolerance``
    [1/s] (``_eigensolve.REPEATED_TOLERANCE`` of the solve's largest root) and within
    :data:`REPEATED_OWN` of their own size. The second keeps a tolerance set by another root from
    joining roots that differ by their whole size: the cylindrical pair of a 1e6 kg rotor on
    1e-6 N/m bearings (1.4e-6 1/s) with its backward conical whirl (8.9e-16 1/s) at 1000 rad/s,
    within 1.8e-6 1/s of each other, made a group of three, and the pair's whirl was the
    solver's planar shapes' (ratio 0, not +-1)."""
    distance = np.abs(np.asarray(a) - np.asarray(b))
    return (distance <= tolerance) & (distance <= REPEATED_OWN * np.maximum(np.abs(a), np.abs(b)))


def at_round_off(values, noise) -> np.ndarray:
    """``values`` with those within ``noise`` of zero (and -0) made 0, same shape."""
    values = np.asarray(values, dtype=float)
    return np.where(np.abs(values) <= noise, 0.0, values) + 0.0


def conservative(form, speeds) -> np.ndarray:
    """(N,) bool: the machine has no damping and a symmetric positive semidefinite stiffness at
    each speed (no Maxwell branch, ``C(Omega) = 0``, ``K(Omega) = K(Omega)^T >= 0`` to
    round-off). Then ``phi^H (lam^2 M + lam Omega G + K) phi = 0`` with ``m > 0``, ``g``
    imaginary (``G`` skew) and ``k >= 0`` puts every root ``lam`` on the imaginary axis."""
    speeds = np.asarray(speeds, dtype=float)
    if form.n_states != 2 * form.n_dof:
        return np.zeros(len(speeds), dtype=bool)
    stiffness, damping = form.pencil_at(speeds)
    if damping.ndim == 2 and stiffness.ndim == 2:         # constant: one test for every speed
        return np.full(len(speeds), not np.any(damping) and _symmetric_semidefinite(stiffness))
    damping = np.broadcast_to(damping, (len(speeds),) + (form.n_dof,) * 2)
    stiffness = np.broadcast_to(stiffness, damping.shape)
    return np.array([not np.any(c) and _symmetric_semidefinite(k) for c, k in zip(damping, stiffness)],
                    dtype=bool)


def _symmetric_semidefinite(K) -> bool:
    """``K = K^T >= 0`` to round-off (``100 n eps max|K|``)."""
    scale = 100.0 * np.finfo(float).eps * K.shape[0] * max(np.abs(K).max(), np.finfo(float).tiny)
    return bool(np.abs(K - K.T).max() <= scale and np.linalg.eigvalsh(0.5 * (K + K.T))[0] >= -scale)
