"""Mode-shape vectors: row norms, unit and mass-normalised rows, real products, the MAC."""

from __future__ import annotations

import numpy as np

from .._blas import one_blas_thread

__all__ = ["mac_matrix", "mass_normalized", "phase_aligned", "real_product", "row_norms", "unit_rows"]

#: shapes of at most this many coordinates are multiplied by a real matrix as complex rows
#: (see :func:`real_product`)
_SMALL_DOF = 24


def real_product(shapes, matrix) -> np.ndarray:
    """``shapes @ matrix`` for complex shapes (..., m, n) and a real matrix (n, p) or (..., n, p),
    as real products of the real and imaginary parts (half the work of a complex product;
    one matrix product over all shapes when the matrix is shared). Shapes of at most
    ``_SMALL_DOF`` coordinates take one complex product per row of shapes instead: the shared
    real product of a small matrix is a tall, thin one, which BLAS computes slowly and shares
    between threads of its own (that wait for a core on a shared machine: measured 10 to 50
    times the per-row products for a sweep of 11 coordinates)."""
    if np.iscomplexobj(matrix):
        return shapes @ matrix
    if shapes.shape[-1] <= _SMALL_DOF:
        if shapes.ndim == 1 or (shapes.ndim == 2 and matrix.ndim == 2):
            return (shapes[..., None, :] @ matrix)[..., 0, :]      # each row a product of its own
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


def phase_aligned(x, ref) -> np.ndarray:
    """``x`` (n,) turned by a unit complex factor so that ``x^H ref`` is real and positive (the
    phase of a reference shape ``ref`` (n,)); unchanged where ``x^H ref`` is 0."""
    turn = np.vdot(x, ref)
    return x * (turn / abs(turn) if abs(turn) > 0 else 1.0)


def unit_rows(x) -> np.ndarray:
    """Rows of the last axis scaled to unit length; zero rows stay zero (a Maxwell junction's
    relaxation root moves no mass and has no displacement: its shape stays zero, MAC 0)."""
    norms = row_norms(x)
    return x / np.where(norms > 0, norms, 1.0)


def mass_normalized(shapes, M) -> np.ndarray:
    """``L^T phi`` normalised to unit length, with ``M = L L^T``: shapes whose plain
    inner product is the mass-weighted one (unit-consistent MAC)."""
    with one_blas_thread(72 * M.shape[-1] ** 2):        # faster than BLAS's threads
        factor = np.linalg.cholesky(M)
    return unit_rows(real_product(shapes, factor))


def mac_matrix(a, b) -> np.ndarray:
    """Modal assurance criterion between unit shape sets ``a`` (..., m, n) and ``b`` (..., p, n).

    Returns
    -------
    ndarray, shape (..., m, p), values in [0, 1]
    """
    return np.abs(a.conj() @ np.swapaxes(b, -1, -2)) ** 2  # batched BLAS, not einsum's loops

