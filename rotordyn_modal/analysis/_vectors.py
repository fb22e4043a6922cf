"""Mode-shape vectors: row norms, unit and mass-normalised rows, real products, the MAC."""

from __future__ import annotations

import numpy as np

__all__ = ["mac_matrix", "mass_normalized", "real_product", "row_norms", "unit_rows"]


def real_product(shapes, matrix) -> np.ndarray:
    """``shapes @ matrix`` for complex shapes (..., m, n) and a real matrix (n, p) or (..., n, p),
    as real products of the real and imaginary parts (half the work of a complex product;
    one matrix product over all shapes when the matrix is shared)."""
    if np.iscomplexobj(matrix):
        return shapes @ matrix
    parts = np.empty((2,) + shapes.shape, dtype=shapes.real.dtype)   # contiguous, (2, ..., m, n)
    parts[0], parts[1] = shapes.real, shapes.imag
    if matrix.ndim == 2:
        out = (parts.reshape(-1, parts.shape[-1]) @ matrix).reshape(parts.shape[:-1] + matrix.shape[-1:])
    else:
        out = parts @ matrix
    combined = np.empty(out.shape[1:], dtype=complex)
    combined.real, combined.imag = out[0], out[1]
    return combined


def row_norms(x) -> np.ndarray:
    """Euclidean norms of the last axis of a complex array, shape (..., 1) (``numpy.linalg.norm``
    with ``keepdims``, without its temporaries)."""
    pairs = np.ascontiguousarray(x).view(float)
    return np.sqrt(np.einsum("...i,...i->...", pairs, pairs))[..., None]


def unit_rows(x) -> np.ndarray:
    """Rows of the last axis scaled to unit length; zero rows stay zero (a Maxwell junction's
    relaxation root moves no mass and has no displacement: its shape stays zero, MAC 0)."""
    norms = row_norms(x)
    return x / np.where(norms > 0, norms, 1.0)


def mass_normalized(shapes, M) -> np.ndarray:
    """``L^T phi`` normalised to unit length, with ``M = L L^T``: shapes whose plain
    inner product is the mass-weighted one (unit-consistent MAC)."""
    factor = np.linalg.cholesky(M)
    return unit_rows(real_product(shapes, factor))


def mac_matrix(a, b) -> np.ndarray:
    """Modal assurance criterion between unit shape sets ``a`` (..., m, n) and ``b`` (..., p, n).

    Returns
    -------
    ndarray, shape (..., m, p), values in [0, 1]
    """
    return np.abs(a.conj() @ np.swapaxes(b, -1, -2)) ** 2  # batched BLAS, not einsum's loops
