"""Global sensitivity: Sobol indices from a Saltelli design, standardised regression
coefficients otherwise.

Sobol estimators (Saltelli et al. 2010, Comput. Phys. Commun. 181: 259-270):
first order ``S_i = mean(f(B) (f(AB_i) - f(A))) / V`` and total (Jansen)
``ST_i = mean((f(A) - f(AB_i))^2) / (2 V)``, ``V`` the variance of
``f(A), f(B)`` together; outputs are centred on the mean of ``f(A), f(B)``
first (same expectation, far smaller variance for outputs with a large mean).
Their standard errors come from a bootstrap over the N base rows (seeded).
"""

from __future__ import annotations

import numpy as np

__all__ = ["sobol_indices", "standardized_regression"]


def sobol_indices(y, d: int, bootstrap: int = 200, seed: int = 0) -> dict:
    """First-order and total Sobol indices from outputs of a Saltelli design.

    Parameters
    ----------
    y : array_like, shape (N (d + 2),)
        Outputs of the rows of :func:`rotordyn_modal.study.sampling.saltelli_matrix`
        (A, B, AB_1 ... AB_d).
    d : int
        Number of parameters.
    bootstrap : int
        Bootstrap resamples of the N base rows for the standard errors.
    seed : int

    Returns
    -------
    dict with ``S1``, ``ST``, ``S1_se``, ``ST_se``: ndarray, shape (d,) each
    """
    y = np.asarray(y, dtype=float)
    n = len(y) // (d + 2)
    blocks = y[: n * (d + 2)].reshape(d + 2, n)
    keep = np.all(np.isfinite(blocks), axis=0)  # drop base rows with a failed variant
    blocks = blocks[:, keep]
    s1, st = _estimate(blocks)
    rng = np.random.default_rng(seed)
    draws = [_estimate(blocks[:, rng.integers(0, blocks.shape[1], blocks.shape[1])]) for _ in range(bootstrap)]
    draws = np.array(draws)  # (bootstrap, 2, d)
    return {"S1": s1, "ST": st, "S1_se": draws[:, 0].std(axis=0, ddof=1),
            "ST_se": draws[:, 1].std(axis=0, ddof=1)}


def _estimate(blocks):
    # centred: the first-order estimator's variance grows with the outputs' mean squared
    blocks = blocks - np.concatenate([blocks[0], blocks[1]]).mean()
    fA, fB, fAB = blocks[0], blocks[1], blocks[2:]
    variance = np.var(np.concatenate([fA, fB]))
    if not variance > 0:
        nan = np.full(len(fAB), np.nan)
        return nan, nan
    s1 = np.mean(fB * (fAB - fA), axis=1) / variance
    st = 0.5 * np.mean((fA - fAB) ** 2, axis=1) / variance
    return s1, st


def standardized_regression(X, y) -> dict:
    """Standardised regression coefficients of ``y`` on the columns of ``X``.

    ``SRC_i = b_i std(x_i) / std(y)`` of the least-squares fit ``y ~ b0 + X b``;
    for a model close to linear (R^2 near 1) ``SRC_i^2`` is the share of the
    variance due to parameter i.

    Parameters
    ----------
    X : array_like, shape (n, d)
    y : array_like, shape (n,)

    Returns
    -------
    dict with ``SRC`` (ndarray, shape (d,)) and ``R2`` (float)
    """
    X, y = np.asarray(X, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(y) & np.all(np.isfinite(X), axis=1)
    X, y = X[keep], y[keep]
    sx, sy = X.std(axis=0), y.std()
    varied = sx > 0
    if len(y) < X.shape[1] + 2 or not sy > 0:
        return {"SRC": np.full(X.shape[1], np.nan), "R2": np.nan}
    Z = (X[:, varied] - X[:, varied].mean(axis=0)) / sx[varied]
    design = np.column_stack([np.ones(len(y)), Z])
    coefficients, *_ = np.linalg.lstsq(design, (y - y.mean()) / sy, rcond=None)
    src = np.zeros(X.shape[1])
    src[varied] = coefficients[1:]
    residual = (y - y.mean()) / sy - design @ coefficients
    return {"SRC": src, "R2": float(1 - np.mean(residual ** 2))}
