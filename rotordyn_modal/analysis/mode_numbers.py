"""One mode numbering: the number ``modes --speed S`` gives a root, for the tracked modes of a sweep.

A sweep (Campbell diagram, critical speeds, stability) labels each mode once and keeps the
label over its speeds (the number by frequency at the sweep's speed nearest zero); :func:`.modal.modal`
numbers the modes at one speed by frequency. Where frequencies cross, a tracked label and the
number at that speed differ, so the sweeps' tables and lines also give the number at the speed
(``mode_at_speed``): the mode ``modes --speed S --shape N`` draws.
"""

from __future__ import annotations

import numpy as np

from ..linear_system import speed_linear_form
from . import _eigensolve
from .modal import is_oscillating

__all__ = ["numbers_at_speed", "number_of_root", "numbers_at_crossings"]


def numbers_at_speed(eigenvalues) -> np.ndarray:
    """The number :func:`.modal.modal` (and ``modes``) gives each root of one speed.

    Parameters
    ----------
    eigenvalues : array_like, shape (..., m), complex [1/s]
        The upper roots of each speed (one of each conjugate pair), any order.

    Returns
    -------
    ndarray of int, shape (..., m)
        1, 2, ... by frequency (then real part) among the roots that are modes at that speed
        (:func:`.modal.is_oscillating`); 0 for the roots that are not modes.
    """
    lam = np.asarray(eigenvalues)
    modes = is_oscillating(lam)
    # the modes first, by frequency then real part: modal's order (its upper roots sorted by
    # imaginary, then real part, the modes numbered in that order)
    order = np.lexsort((lam.real, lam.imag, ~modes), axis=-1)
    ranks = np.empty(lam.shape, dtype=int)
    np.put_along_axis(ranks, order, np.broadcast_to(np.arange(lam.shape[-1]), lam.shape), axis=-1)
    return np.where(modes, ranks + 1, 0)


def number_of_root(roots, eigenvalue) -> int:
    """The number ``modes`` gives the root of ``roots`` (one speed's upper roots) nearest
    ``eigenvalue`` [1/s]; 0 when that root is not a mode."""
    roots = np.asarray(roots)
    return int(numbers_at_speed(roots)[int(np.argmin(np.abs(roots - eigenvalue)))])


def numbers_at_crossings(model, sweep_speeds, sweep_eigenvalues, speeds, modes, eigenvalues) -> np.ndarray:
    """The number ``modes --speed`` gives tracked modes at speeds between a sweep's speeds.

    Where the mode has the same number at both grid speeds around the speed, that number (no
    root crosses its frequency in between); otherwise the roots at the speed are solved (the
    state matrix is built only then).

    Parameters
    ----------
    model : Model
    sweep_speeds : ndarray, shape (N,) [rad/s], increasing
    sweep_eigenvalues : ndarray, shape (N, m), complex, tracked columns
    speeds : ndarray, shape (P,) [rad/s]
    modes : ndarray of int, shape (P,)
        Tracked labels (1-based columns of ``sweep_eigenvalues``).
    eigenvalues : ndarray, shape (P,), complex [1/s]
        The mode's eigenvalue at each speed.

    Returns
    -------
    ndarray of int, shape (P,); 0 where the root is not a mode at that speed
    """
    grid = numbers_at_speed(sweep_eigenvalues)
    k = np.clip(np.searchsorted(sweep_speeds, speeds) - 1, 0, max(len(sweep_speeds) - 2, 0))
    column = np.asarray(modes, dtype=int) - 1
    below, above = grid[k, column], grid[np.minimum(k + 1, len(sweep_speeds) - 1), column]
    out = np.where(below == above, below, 0)
    form = None
    for p in np.nonzero((below != above) | (below == 0))[0]:
        if form is None:
            form = speed_linear_form(model)
        roots = _eigensolve.select_upper(_eigensolve.eigenvalues_of(form.at(float(speeds[p]))[None]))[0]
        out[p] = number_of_root(roots, eigenvalues[p])
    return out
