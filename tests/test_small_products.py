"""Products of small mode shapes with a real matrix (``_vectors.real_product``): the plain
complex product to round-off, and every speed's rows the bits they get alone (a study's variant
must get the bits of its own analysis: docs/DEVELOPING.md, "Measuring small calls")."""

import numpy as np
import pytest

from rotordyn_modal.analysis._vectors import real_product


@pytest.mark.parametrize("n", [4, 11, 22])
def test_small_shapes_times_a_real_matrix_is_the_complex_product(n):
    rng = np.random.default_rng(n)
    shapes = rng.standard_normal((301, 7, n)) + 1j * rng.standard_normal((301, 7, n))
    matrix = rng.standard_normal((n, n))
    exact = np.einsum("smi,ij->smj", shapes.real, matrix) + 1j * np.einsum("smi,ij->smj", shapes.imag, matrix)
    found = real_product(shapes, matrix)
    assert found.shape == exact.shape
    assert np.allclose(found, exact, rtol=0.0, atol=1e-13 * np.abs(exact).max())
    rows = real_product(shapes[:, 0], matrix)                       # rows (P, n) of shapes
    assert np.allclose(rows, exact[:, 0], rtol=0.0, atol=1e-13 * np.abs(exact).max())


@pytest.mark.parametrize("n", [11, 22])
def test_each_speed_of_small_shapes_gets_the_bits_it_gets_alone(n):
    """One BLAS product over the rows of every speed gave a speed's shapes bits that depend on
    its place among the others (22 coordinates, 301 speeds: one speed differed in the last bit on
    an AVX2 machine); each speed's own product cannot."""
    rng = np.random.default_rng(100 + n)
    shapes = rng.standard_normal((301, 7, n)) + 1j * rng.standard_normal((301, 7, n))
    matrix = rng.standard_normal((n, n))
    together = real_product(shapes, matrix)
    for k in range(len(shapes)):
        assert np.array_equal(together[k], real_product(shapes[k:k + 1], matrix)[0]), k
