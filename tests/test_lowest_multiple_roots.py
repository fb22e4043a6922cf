"""Multiple roots in the lowest modes' checks (issue 27 §1.9: a 500-rotor gear chain solved its
0 rpm speed whole, one 4,012-state eigen-solve and 1.44 GB, because axisymmetric rotors at rest
have double roots and two refined roots at one place were taken for one root found twice).

Coinciding refined roots are a multiple root where their shapes are independent (numerical rank
equal to their number, ``docs/theory.md`` section 17, "Multiple roots"); two starts that reach
one simple root reach its one shape and are still caught. The truth is scipy's eigenvalues of
the full state matrix and the rank of the shapes, not the code under test.
"""

from __future__ import annotations

import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.analysis._lowest_newton import _refined
from rotordyn_modal.analysis._lowest_pencils import _Pencils
from rotordyn_modal.analysis._stack import Stack

from test_lowest_modes import _lowest_by_scipy

COMPRESSOR = "examples/compressor_rotor.toml"       # 53 coordinates, axisymmetric on isotropic bearings


def _model():
    return rdm.load_model(COMPRESSOR)


def test_an_axisymmetric_rotor_at_rest_is_not_solved_whole():
    """The 5 lowest modes at 0, 1500 and 3000 rpm (two double roots at rest among them) come from
    the reduced basis at every speed, as scipy's eigenvalues of the state matrix give them (on
    main 0 rpm was solved whole, with the fallback's warning)."""
    model = _model()
    speeds = rdm.rpm(np.array([0.0, 1500.0, 3000.0]))
    reference = _lowest_by_scipy(model, speeds, 5)
    assert abs(reference[0, 1] - reference[0, 0]) < 1e-9 * abs(reference[0, 0])      # a double root at rest
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        values, _, full = _lowest.lowest_roots(Stack([model]), speeds, 5)
    assert not full.any(), full
    assert not [w for w in caught if "solved whole" in str(w.message)], [str(w.message) for w in caught]
    values = np.take_along_axis(values, np.argsort(values.imag, axis=1), 1)
    assert np.max(np.abs(values - reference) / np.abs(reference)) < 1e-9


def test_a_double_root_at_rest_whirls_as_in_the_full_solve():
    """The double roots' two shapes at rest are their backward and forward whirl combinations (whirl
    ratio -1 and +1), as the full sweep's eigen-solve makes them: not any basis of their plane."""
    model = _model()
    speeds = rdm.rpm(np.array([0.0, 1500.0]))
    columns = ["speed_rpm", "mode_at_speed", "whirl"]
    lowest = rdm.campbell(model, speeds, critical=False, modes=5).to_dataframe()
    full = rdm.campbell(model, speeds, critical=False).to_dataframe()
    full = full[full["mode_at_speed"] <= 5]
    assert lowest[columns].reset_index(drop=True).equals(full[columns].reset_index(drop=True))
    assert np.allclose(np.abs(lowest["whirl_ratio"][lowest["speed_rpm"] == 0].to_numpy()[[0, 1, 3, 4]]), 1.0)


def _newton_from(model, speed, root, vectors):
    """Newton's iteration on the full pencil from ``root`` [1/s] with each of ``vectors`` (g, n):
    the refined roots (1, g) and unit shapes (1, g, n)."""
    pencils = _Pencils(Stack([model]), np.array([speed]))
    starts = np.full((1, len(vectors)), root * (1 + 1e-4))
    values, shapes, converged = _refined(pencils, starts, np.asarray(vectors, complex)[None])
    assert converged.all()
    return values, shapes


def _state_eig(model, speed):
    """scipy's eigenvalues and displacement eigenvectors (n, 2n) of the state matrix."""
    import scipy.linalg

    M, C, G, K = (np.asarray(matrix) for matrix in model.matrices())
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    lam, vectors = scipy.linalg.eig(A)
    return lam, vectors[:n]


def test_two_starts_at_a_double_root_are_two_roots():
    """Newton from the double root at rest with scipy's two eigenvectors (plus noise) reaches that
    root twice with two independent shapes (rank 2 by numpy's SVD): a double root, distinct for
    the check. Without shapes the check still takes them for one root (main's rule)."""
    model = _model()
    lam, vectors = _state_eig(model, 0.0)
    reference = _lowest_by_scipy(model, [0.0], 1)[0, 0]
    pair = np.argsort(np.abs(lam - reference))[:2]
    noise = np.random.default_rng(1).standard_normal(vectors[:, pair].T.shape) * 1e-3
    values, shapes = _newton_from(model, 0.0, reference, vectors[:, pair].T + noise)
    assert np.abs(values - reference).max() < 1e-9 * abs(reference)
    assert np.linalg.svd(shapes[0], compute_uv=False)[-1] > 0.1         # independent shapes
    assert _lowest._distinct(values, shapes).all()
    assert not _lowest._distinct(values).any()


def test_two_starts_at_a_simple_root_are_still_one_root():
    """Newton from a simple root at 1500 rpm with two different start vectors (its eigenvector
    with two different perturbations of 30 %) reaches it twice with one shape: still one root found
    twice, and the speed fails the check (it would be solved whole)."""
    model = _model()
    speed = rdm.rpm(1500.0)
    lam, vectors = _state_eig(model, speed)
    reference = _lowest_by_scipy(model, [speed], 3)[0, 2]
    assert np.sort(np.abs(lam - reference))[1] > 1e-3 * abs(reference)          # a simple root
    x = vectors[:, np.argmin(np.abs(lam - reference))]
    x = x / np.linalg.norm(x)
    rng = np.random.default_rng(2)
    starts = [x + 0.3 * rng.standard_normal(len(x)) / np.sqrt(len(x)) for _ in range(2)]
    values, shapes = _newton_from(model, speed, reference, starts)
    assert np.abs(values - reference).max() < 1e-9 * abs(reference)
    assert np.linalg.svd(shapes[0], compute_uv=False)[-1] < 1e-6           # one shape (up to phase)
    assert not _lowest._distinct(values, shapes).any()


def test_a_double_root_with_one_shape_twice_is_not_accepted():
    """Two coinciding roots with parallel shapes (one shape, another phase) do not show a double
    root: rejected, while the same roots with orthogonal shapes are accepted."""
    rng = np.random.default_rng(3)
    x = rng.standard_normal(20) + 1j * rng.standard_normal(20)
    x /= np.linalg.norm(x)
    y = rng.standard_normal(20) + 0j
    y -= np.vdot(x, y) * x
    y /= np.linalg.norm(y)
    values = np.array([[-1.0 + 100j, -1.0 + 100j, -2.0 + 300j]])
    z = rng.standard_normal(20)
    z /= np.linalg.norm(z)
    parallel = np.array([[x, np.exp(0.7j) * x + 1e-9 * z, z]])
    independent = np.array([[x, y, z]])
    assert not _lowest._distinct(values, parallel).any()
    assert _lowest._distinct(values, independent).all()


def test_the_modes_below_a_frequency_show_the_fallback_bar(tmp_path):
    """``campbell --lowest 1 --max-frequency`` at rest leaves 0 rpm to the full eigen-solve on an
    undamped shaft on cross-coupled bearings (the lowest pair -a + ib, a + ib of one frequency: no
    projected root above it shows that none was missed below the cut; an axisymmetric rotor's
    double root at the cut, which this test used before, is refined with more starts since,
    tests/test_cut_in_double_root_routes28g.py). On a pseudo-terminal that fallback draws its bar,
    whole drawings within the width (on main ``roots_below`` took no ``progress``: no bar)."""
    from test_progress_terminal import _drawings, _on_terminal
    from test_progress_terminal_more import SPLIT_PAIR

    model = tmp_path / "split_pair.toml"
    model.write_text(SPLIT_PAIR)
    code, text = _on_terminal(["campbell", str(model), "--speeds", "0:3000:3",
                               "--lowest", "1", "--max-frequency", "500", "--out", str(tmp_path / "c.csv")], 100, 40)
    assert code == 0, text
    assert "1 of 3 speeds solved whole" in text, text
    drawings = _drawings(text, "lowest modes (full eigen-solve):")
    assert drawings, text
    assert all(drawing.endswith("]") and len(drawing) <= 99 for drawing in drawings), drawings
    assert "/1 " in drawings[0], drawings
