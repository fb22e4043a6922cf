"""Variants of a study: grid points times samples of the distributions.

Samples come from one ``numpy.random.Generator`` seeded with the study's seed
(or from ``scipy.stats.qmc`` designs seeded from it), drawn once in the calling
process, so the same seed gives the same variants whatever executes them.
Distributions are sampled by their inverse CDF from uniform numbers ``u``;
correlation acts through a Gaussian copula (``z = Phi^-1(u)``, ``z L^T``,
``u = Phi(z)``); truncation maps ``u`` into ``[F(low), F(high)]``.
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np

__all__ = ["sample_variants", "uniform_design", "to_distribution"]


def uniform_design(design: str, n: int, d: int, seed) -> np.ndarray:
    """Points in the unit cube, shape (rows, d).

    Parameters
    ----------
    design : {'monte-carlo', 'latin-hypercube', 'sobol', 'saltelli'}
    n : int
        Samples; for 'saltelli' the base sample N (rows = N (d + 2)).
    d : int
        Dimensions (distribution parameters).
    seed : int or None

    Returns
    -------
    ndarray, shape (n, d) (or (N (d + 2), d) for 'saltelli'), values in (0, 1)
    """
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    if design == "monte-carlo":
        return rng.random((n, d))
    if design == "latin-hypercube":
        return qmc.LatinHypercube(d, rng=rng).random(n)
    with warnings.catch_warnings():  # balance properties need n = 2^m; other n still work
        warnings.simplefilter("ignore", UserWarning)
        if design == "sobol":
            return qmc.Sobol(d, scramble=True, rng=rng).random(n)
        both = qmc.Sobol(2 * d, scramble=True, rng=rng).random(n)
    return saltelli_matrix(both[:, :d], both[:, d:])


def saltelli_matrix(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Stack ``A``, ``B`` and ``AB_i`` (A with column i from B), each (N, d): (N (d + 2), d)."""
    blocks = [A, B]
    for i in range(A.shape[1]):
        AB = A.copy()
        AB[:, i] = B[:, i]
        blocks.append(AB)
    return np.concatenate(blocks)


def to_distribution(parameters, u: np.ndarray, correlation: np.ndarray) -> np.ndarray:
    """Uniform numbers -> parameter values through copula, truncation and inverse CDF.

    Parameters
    ----------
    parameters : sequence of Parameter (distributions), length d
    u : ndarray, shape (n, d), in (0, 1)
    correlation : ndarray, shape (d, d)

    Returns
    -------
    ndarray, shape (n, d)
    """
    from scipy.special import ndtr, ndtri

    u = np.clip(u, 1e-300, 1 - 1e-16)
    if not np.array_equal(correlation, np.eye(len(parameters))):
        u = ndtr(ndtri(u) @ np.linalg.cholesky(correlation).T)
    out = np.empty_like(u)
    for j, p in enumerate(parameters):
        dist = p.frozen()
        uj = u[:, j]
        if p.truncate is not None:
            lo, hi = dist.cdf(p.truncate[0]), dist.cdf(p.truncate[1])
            uj = lo + uj * (hi - lo)
        out[:, j] = np.clip(dist.ppf(uj), *(p.truncate or (-np.inf, np.inf)))
    return out


def sample_variants(definition) -> np.ndarray:
    """Parameter values of every variant, in the order of ``definition.parameters``.

    Grid points form the full factorial product (the last grid parameter varies
    fastest); each grid point takes the same samples of the distributions.

    Returns
    -------
    ndarray, shape (n_variants, n_parameters)
    """
    grid = definition.grid_parameters
    random = definition.random_parameters
    count = int(np.prod([len(p.grid) for p in grid]))
    points = np.array(list(itertools.product(*(p.grid for p in grid))), dtype=float).reshape(count, len(grid))
    if random:
        u = uniform_design(definition.design, definition.samples, len(random), definition.seed)
        draws = to_distribution(random, u, definition.correlation)
    else:
        draws = np.empty((1, 0))
    rows = np.concatenate([np.repeat(points, len(draws), axis=0), np.tile(draws, (len(points), 1))], axis=1)
    order = [p.name for p in grid] + [p.name for p in random]
    return rows[:, [order.index(p.name) for p in definition.parameters]]
