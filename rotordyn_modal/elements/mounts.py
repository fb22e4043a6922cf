"""Frequency-dependent mounts: generalized Maxwell branches of rubber.

A branch of suspension ``i`` is a spring ``K_b`` (6x6 at the mount point, model
axes) in series with a dashpot ``tau_b K_b``. In the frequency domain it adds
``K_b i w tau_b / (1 + i w tau_b)`` to the mount's stiffness: nothing at
``w = 0`` (the static stiffness is ``stiffness``), ``K_b`` at high frequency
(the rubber stiffens), with the largest loss near ``w = 1 / tau_b``. Shifted to
the reference point like every suspension: ``B_SP K_b B_SP^T``, and act on the
stator's six coordinates of the generalized space (:mod:`rotordyn_modal.model.dofs`).
"""

from __future__ import annotations

import numpy as np

from ..model.dofs import frame_block
from ..model.geometry import shift_matrix

__all__ = ["branch_count", "has_frequency_dependence", "maxwell_stiffness", "maxwell_branches", "maxwell_branch_blocks"]


def has_frequency_dependence(model) -> bool:
    """True when a suspension has Maxwell branches."""
    return any(getattr(s, "maxwell_stiffness_matrix", None) is not None for s in model.suspensions)


def branch_count(model) -> int:
    """Maxwell branches of every suspension (each adds six first-order states,
    :func:`with_branch_states`), counted without building them."""
    return sum(1 for s in model.suspensions if getattr(s, "maxwell_stiffness_matrix", None) is not None
               for _ in zip(s.maxwell_stiffness_matrix, s.maxwell_time))


def maxwell_branches(model):
    """Every branch of every suspension, shifted to the reference point.

    Returns
    -------
    stiffness : ndarray, shape (n_branches, n, n) [N/m, ...]
        ``B_SP K_b B_SP^T`` on the stator's coordinates of the generalized space.
    times : ndarray, shape (n_branches,) [s]
    """
    blocks, times = maxwell_branch_blocks(model)
    return frame_block(model, blocks), times


def maxwell_branch_blocks(model):
    """:func:`maxwell_branches` as 6x6 blocks at the reference point (the stator's motion), without
    the ``n x n`` array of each branch (a large model's: docs/theory.md section 17).

    Returns
    -------
    blocks : ndarray, shape (n_branches, 6, 6) [N/m, ...]
        ``B_SP K_b B_SP^T``; :func:`~rotordyn_modal.model.dofs.frame_block` places each.
    times : ndarray, shape (n_branches,) [s]
    """
    stiffness, times = [], []
    for _, _, shift, k_b, tau in _each_branch(model):
        stiffness.append(shift @ k_b @ shift.T)
        times.append(tau)
    return np.array(stiffness).reshape(-1, 6, 6), np.array(times)


def _each_branch(model):
    """``(suspension, index, B_SP, K_b, tau_b)`` for every Maxwell branch of the model."""
    reference = model.reference_point
    for s in model.suspensions:
        if getattr(s, "maxwell_stiffness_matrix", None) is None:
            continue
        shift = shift_matrix(reference, s.position)
        for k, (k_b, tau) in enumerate(zip(s.maxwell_stiffness_matrix, s.maxwell_time)):
            yield s, k, shift, k_b, float(tau)


def maxwell_stiffness(model, omega) -> np.ndarray | float:
    """Sum of the branches' complex stiffness at each frequency.

    Parameters
    ----------
    model : Model
    omega : array_like, shape (n_freq,) [rad/s]

    Returns
    -------
    ndarray, shape (n_freq, n, n), complex [N/m, ...], or 0.0 without branches
    """
    stiffness, times = maxwell_branches(model)
    if not len(times):
        return 0.0
    w = np.asarray(omega, dtype=float)[:, None]
    factor = 1j * w * times / (1 + 1j * w * times)        # (n_freq, n_branches)
    return np.einsum("fb,bij->fij", factor, stiffness)


def maxwell_frame_stiffness(model, omega) -> np.ndarray:
    """:func:`maxwell_stiffness` on the stator's six motions alone, (n_freq, 6, 6) complex
    [N/m, ...] (zeros without branches): what a large model adds to its sparse ``Z(w)``, placed by
    :func:`~rotordyn_modal.assembly.sparse_frame_block`, without an ``n x n`` array per branch."""
    w = np.asarray(omega, dtype=float)
    out = np.zeros((len(w), 6, 6), dtype=complex)
    for _, _, shift, k_b, tau in _each_branch(model):
        out += (1j * w * tau / (1 + 1j * w * tau))[:, None, None] * (shift @ k_b @ shift.T)
    return out


def with_branch_states(model, a, b, mass_inverse):
    """Add the Maxwell branches to a ``2n``-state model as 6 first-order states each.

    Branch ``b`` at point ``P`` has an internal coordinate ``z_b`` (the spring-dashpot
    junction, 6 components at ``P``, model axes): the stator feels
    ``-B_SP K_b (B_SP^T q - z_b)`` and ``tau_b z_b' = B_SP^T q - z_b``, which gives
    ``K_b i w tau_b / (1 + i w tau_b)`` in the frequency domain.

    Parameters
    ----------
    model : Model
    a : ndarray, shape (2n, 2n)
        State matrix of ``x = [q, q']`` at one speed.
    b : ndarray, shape (2n, n_inputs)
    mass_inverse : ndarray, shape (n, n)

    Returns
    -------
    a, b : ndarray, shapes (2n + 6 n_branches, ...) (unchanged without branches)
    names : list of str
        Names of the added states, ``"<suspension>.branch<k>.z<i>"``.
    """
    blocks, names = [], []
    for s, k, shift, k_b, tau in _each_branch(model):
        blocks.append((shift, k_b, tau))
        names += [f"{s.name}.branch{k}.z{i}" for i in range(6)]
    if not blocks:
        return a, b, []
    n_states, m = a.shape[0], a.shape[0] + 6 * len(blocks)
    n = mass_inverse.shape[0]
    frame = model.dofs.frame_motion()                                # (6, n): T_S
    out = np.zeros((m, m))
    out[:n_states, :n_states] = a
    for index, (shift, k_b, tau) in enumerate(blocks):
        rows = slice(n_states + 6 * index, n_states + 6 * index + 6)
        point = shift.T @ frame                                      # motion at P per coordinate
        out[n:2 * n, :n] -= mass_inverse @ point.T @ k_b @ point     # the branch's spring on q
        out[n:2 * n, rows] = mass_inverse @ point.T @ k_b            # ... released by z_b
        out[rows, :n] = point / tau
        out[rows, rows] = -np.eye(6) / tau
    return out, np.vstack([b, np.zeros((m - n_states, b.shape[1]))]), names
