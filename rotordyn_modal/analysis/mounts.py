"""Frequency-dependent mounts: generalized Maxwell branches of rubber.

A branch of suspension ``i`` is a spring ``K_b`` (6x6 at the mount point, model
axes) in series with a dashpot ``tau_b K_b``. In the frequency domain it adds
``K_b i w tau_b / (1 + i w tau_b)`` to the mount's stiffness: nothing at
``w = 0`` (the static stiffness is ``stiffness``), ``K_b`` at high frequency
(the rubber stiffens), with the largest loss near ``w = 1 / tau_b``. Shifted to
the reference point like every suspension: ``B_SP K_b B_SP^T``.
"""

from __future__ import annotations

import numpy as np

from ..geometry import shift_matrix

__all__ = ["has_frequency_dependence", "maxwell_stiffness", "maxwell_branches"]


def has_frequency_dependence(model) -> bool:
    """True when a suspension has Maxwell branches."""
    return any(getattr(s, "maxwell_stiffness_matrix", None) is not None for s in model.suspensions)


def maxwell_branches(model):
    """Every branch of every suspension, shifted to the reference point.

    Returns
    -------
    stiffness : ndarray, shape (n_branches, 6, 6) [N/m, ...]
        ``B_SP K_b B_SP^T``.
    times : ndarray, shape (n_branches,) [s]
    """
    reference = model.reference_point
    stiffness, times = [], []
    for s in model.suspensions:
        if getattr(s, "maxwell_stiffness_matrix", None) is None:
            continue
        shift = shift_matrix(reference, s.position)
        for k_b, tau in zip(s.maxwell_stiffness_matrix, s.maxwell_time):
            stiffness.append(shift @ k_b @ shift.T)
            times.append(float(tau))
    return np.array(stiffness).reshape(-1, 6, 6), np.array(times)


def maxwell_stiffness(model, omega) -> np.ndarray | float:
    """Sum of the branches' complex stiffness at each frequency.

    Parameters
    ----------
    model : Model
    omega : array_like, shape (n_freq,) [rad/s]

    Returns
    -------
    ndarray, shape (n_freq, 6, 6), complex [N/m, ...], or 0.0 without branches
    """
    stiffness, times = maxwell_branches(model)
    if not len(times):
        return 0.0
    w = np.asarray(omega, dtype=float)[:, None]
    factor = 1j * w * times / (1 + 1j * w * times)        # (n_freq, n_branches)
    return np.einsum("fb,bij->fij", factor, stiffness)
