"""campbell(modes=N) of small models (below ``_lowest.DENSE_BELOW`` coordinates): every root of
every speed from eigenvalues alone, the N lowest roots' shapes by inverse iteration on the pencil
(issue 28, speed). Truth from outside the code under test: scipy's eigenvalues of the state
matrix built here, the eigen-equation Q(lam) phi = 0 of each shape, and the circular whirl of
the two shapes of a repeated root of an axisymmetric rotor at rest."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _roots
from rotordyn_modal.io.ross_file import read_ross_rotor

ROTOR_EXAMPLE = "tests/data/ross/rotor_example.toml"


def _state_matrix(M, C, G, K, speed):
    n = len(M)
    return np.block([[np.zeros((n, n)), np.eye(n)],
                     [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])


def _recorded_sizes(monkeypatch, name: str) -> list:
    """The sizes of the matrices ``numpy.linalg.<name>`` is called with from now on (a list that
    grows as the calls come)."""
    sizes, plain = [], getattr(np.linalg, name)

    def recording(a):
        sizes.append(np.shape(a)[-1])
        return plain(a)

    monkeypatch.setattr(np.linalg, name, recording)
    return sizes


def test_small_model_lowest_modes_need_no_eigenvectors_of_the_state_matrices(monkeypatch):
    """ROSS's rotor_example (28 coordinates, the dense route): no eigenvectors of the 56-state
    matrices are computed, and the roots are scipy's, the shapes solve the pencil."""
    model = rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))
    n = model.dofs.n
    assert n < _lowest.DENSE_BELOW
    eigen_sizes = _recorded_sizes(monkeypatch, "eig")
    speeds = np.linspace(100.0, 3000.0, 7)
    result = rdm.campbell(model, speeds, critical=False, modes=12)
    assert 2 * n not in eigen_sizes
    M, C, G, K = model.matrices()
    for k, speed in enumerate(speeds):
        roots = scipy.linalg.eigvals(_state_matrix(M, C, G, K, speed))
        roots = np.sort_complex(roots[roots.imag > 0])           # lightly damped: all are modes
        reference = roots[np.argsort(roots.imag, kind="stable")][:12]
        lam = result.eigenvalues[k][np.argsort(result.eigenvalues[k].imag)]
        assert np.max(np.abs(lam - reference) / np.abs(reference)) < 1e-9      # round-off of a 56-state solve
        for root, shape in zip(result.eigenvalues[k], result.shapes[k]):
            Q = root ** 2 * M + root * (C + speed * G) + K
            assert np.linalg.norm(Q @ shape) <= 1e-12 * np.linalg.norm(Q) * np.linalg.norm(shape)


def _axisymmetric_shaft():
    """A uniform steel shaft on two isotropic bearings at its ends, spinning about x: at rest
    every bending root is a double root (the two planes alike)."""
    return rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "shear_modulus": 8e10}],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shaft": [{"length": 0.6, "outer_diameter": 0.05, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": 0.4, "mass": 5.0, "polar_inertia": 0.03,
                               "diametral_inertia": 0.02}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z, "stiffness": 1e7, "damping": 50.0}
                     for i, z in enumerate((0.0, 0.6))],
    })


def test_repeated_roots_keep_their_circular_shapes():
    """At rest the double roots' shapes are the forward and backward circular combinations (whirl
    ratios -1 and +1, as campbell of every root gives them); inverse iteration alone would give
    both roots of a pair one and the same shape."""
    model = _axisymmetric_shaft()
    assert model.dofs.n < _lowest.DENSE_BELOW
    speeds = np.array([0.0, 500.0, 1000.0])
    lowest = rdm.campbell(model, speeds, critical=False, modes=6)
    full = rdm.campbell(model, speeds, critical=False)
    at_rest = np.sort(lowest.whirl_ratios[0])
    assert np.allclose(at_rest, [-1, -1, -1, 1, 1, 1], atol=1e-9)
    roots = np.where(full.oscillatory, full.eigenvalues, np.nan + 1e30j)
    order = np.argsort(roots.imag, axis=1)[:, :6]
    for k in range(len(speeds)):
        mine = np.argsort(lowest.eigenvalues[k].imag)
        theirs = order[k]
        assert np.allclose(lowest.eigenvalues[k][mine], full.eigenvalues[k][theirs], rtol=1e-12, atol=0)
        assert np.allclose(lowest.whirl_ratios[k][mine], full.whirl_ratios[k][theirs], atol=1e-9)


def test_balanced_norm_of_a_matrix_is_its_own_in_any_stack(monkeypatch):
    """The balanced norm of each matrix does not depend on the other matrices of the stack nor on
    the parts the stack is cut into, and it is the Frobenius norm of a diagonal similarity of it
    (a power-of-two scaling: no larger than the plain norm where the matrix is badly scaled)."""
    rng = np.random.default_rng(7)
    scales = 10.0 ** rng.uniform(-6, 6, size=(9, 1, 12))
    stack = rng.standard_normal((9, 12, 12)) * scales * np.swapaxes(1.0 / scales, 1, 2)
    whole = _roots.balanced_norm(stack)
    alone = np.array([_roots.balanced_norm(matrix[None])[0] for matrix in stack])
    monkeypatch.setattr(_roots, "_BALANCE_BYTES", 3 * 8 * 12 * 12)
    assert np.array_equal(_roots.balanced_norm(stack), whole)
    assert np.array_equal(alone, whole)
    assert np.all(whole <= np.linalg.norm(stack, axis=(1, 2)))
    assert np.all(whole >= np.sqrt(np.sum(np.diagonal(stack, axis1=1, axis2=2) ** 2, axis=1)))


@pytest.mark.parametrize("name, count", [("rotor_example", 1), ("rotor_example", 5), ("speed_tables", 6)])
def test_dense_route_equals_the_whole_solve(name, count):
    """_dense_lowest and the whole solve of every root (eig with eigenvectors) agree: the same
    roots to round-off, the same shapes up to a phase (speed_tables: bearings tabulated over
    speed, a stiffness per speed)."""
    from rotordyn_modal.analysis._stack import Stack

    stack = Stack([rdm.Model.from_dict(read_ross_rotor(f"tests/data/ross/{name}.toml"))])
    speeds = np.linspace(0.0, 1500.0, 9)
    lam, phi = _lowest._dense_lowest(stack, speeds, count)
    lam_whole, phi_whole = _lowest._full_lowest(stack, speeds, count)
    assert np.allclose(lam, lam_whole, rtol=1e-13, atol=0)
    mac = np.abs(np.einsum("ski,ski->sk", phi.conj(), phi_whole)) ** 2
    assert np.all(mac >= 1 - 1e-12)


@pytest.mark.parametrize("analysis", ["campbell", "stability"])
def test_lowest_modes_build_the_state_form_once(analysis, monkeypatch):
    """campbell(modes=N) and stability(modes=N) build the model's state form (M^-1, A0, A1) once:
    N is compared with the roots of the stack that does the work, and stability's round-off and
    threshold roots use that stack too (issue 28, speed: each further build cost 0.2-0.6 s of
    ROSS's 224-coordinate compressor_example on a loaded machine)."""
    from rotordyn_modal import linear_system

    model = rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))
    builds = []
    plain = linear_system.SpeedLinearForm.__init__

    def counting(self, *args, **kwargs):
        builds.append(1)
        plain(self, *args, **kwargs)

    monkeypatch.setattr(linear_system.SpeedLinearForm, "__init__", counting)
    getattr(rdm, analysis)(model, np.linspace(100.0, 3000.0, 5), modes=4)
    assert len(builds) == 1


@pytest.mark.parametrize("name", ["rubber_mounts.toml", "fan_on_bearings.toml"])
def test_root_count_is_half_the_states_and_the_route_switches_there(name, examples_dir):
    """root_count (from the sizes: n + 3 per Maxwell branch) is half the state matrix's size, built
    here from the model's matrices and branches; campbell(modes=N) is every root from that N on
    (the same roots as campbell()) and the N lowest below it."""
    from rotordyn_modal.analysis.campbell import root_count
    from rotordyn_modal.elements.mounts import maxwell_branches

    model = rdm.load_model(examples_dir / name)
    M = model.matrices()[0]
    branches = len(maxwell_branches(model)[1])
    assert (name == "rubber_mounts.toml") == (branches > 0)
    assert root_count(model) == (2 * len(M) + 6 * branches) // 2
    speeds = np.linspace(0.0, 300.0, 4)
    every = rdm.campbell(model, speeds, critical=False)
    all_of_them = rdm.campbell(model, speeds, critical=False, modes=root_count(model))
    # the shapes too: the lowest route's shapes (inverse iteration) differ from eig's in the last bits
    assert np.array_equal(all_of_them.eigenvalues, every.eigenvalues, equal_nan=True)
    assert np.array_equal(all_of_them.shapes, every.shapes)
    assert rdm.campbell(model, speeds, critical=False, modes=root_count(model) - 1).eigenvalues.shape == \
        (len(speeds), root_count(model) - 1)


# ----------------------------------------------------------------------------------------
# Undamped gyroscopic models: the roots from a Hermitian matrix of the states

def _refined_root(root, shape, M, G, K, speed):
    """The root of ``s^2 M + s speed G + K`` near ``root`` (start shape ``shape``), by Newton's
    iteration on the bordered system with the residual in extended precision (numpy's longdouble)
    and the correction in double: the truth the roots are measured against."""
    n, wide = len(M), np.clongdouble
    Ml, Gl, Kl = (matrix.astype(np.longdouble) for matrix in (M, G, K))
    j = int(np.argmax(np.abs(shape)))
    s, x = wide(root), (shape / shape[j]).astype(wide)
    for _ in range(5):
        Q = Ml * s * s + Gl * (s * speed) + Kl
        residual = np.append(-(Q @ x), wide(1) - x[j])
        jacobian = np.zeros((n + 1, n + 1), complex)
        jacobian[:n, :n] = Q.astype(complex)
        jacobian[:n, n] = ((2 * s * Ml + speed * Gl) @ x).astype(complex)
        jacobian[n, j] = 1.0
        step = np.linalg.solve(jacobian, residual.astype(complex))
        x, s = x + step[:n].astype(wide), s + wide(step[n])
    return s


def _eig_lowest(M, G, K, speed, count):
    """The ``count`` lowest upper roots of the state matrix (numpy's eig, built here) and their
    unit displacement shapes."""
    values, vectors = np.linalg.eig(_state_matrix(M, np.zeros_like(M), G, K, speed))
    order = np.argsort(np.where(values.imag > 0, values.imag, np.inf))[:count]
    shapes = vectors[:len(M), order].T
    return values[order], shapes / np.linalg.norm(shapes, axis=1, keepdims=True)


def _check_gyroscopic_route(model, speeds, count, exact):
    """The lowest roots of ``model`` (undamped gyroscopic) by the Hermitian route: purely
    imaginary, as close to the extended-precision roots as eig's of the state matrix (within
    ``exact`` relative, or three times eig's worst error over the speeds: the round-off of a model
    whose M and K span many decades), and with eig's shapes up to a phase."""
    from rotordyn_modal.analysis._stack import Stack

    stack = Stack([model])
    lowest = _lowest._gyroscopic_lowest(stack, speeds, count)
    assert lowest is not None                            # the route applies
    lam, phi = lowest
    M, C, G, K = model.matrices()
    assert not C.any()
    whole = _lowest._full_lowest(stack, speeds, count)[0]
    errors, eig_errors = [0.0], [0.0]
    for k, speed in enumerate(speeds):
        if np.array_equal(lam[k], whole[k]):    # a speed of double roots: solved whole, as before
            continue
        reference, shapes = _eig_lowest(M, G, K, speed, count)
        truth = np.array([_refined_root(r, x, M, G, K, speed) for r, x in zip(reference, shapes)]).astype(complex)
        assert np.all(lam[k].real == 0)
        errors.append(np.max(np.abs(lam[k] - truth) / np.abs(truth)))
        eig_errors.append(np.max(np.abs(reference - truth) / np.abs(truth)))
        mac = np.abs(np.einsum("ki,ki->k", phi[k].conj(), shapes)) ** 2
        assert np.all(mac >= 1 - 1e-10)
    assert max(errors) <= max(exact, 3 * max(eig_errors))
    return max(errors), max(eig_errors)


def test_undamped_gyroscopic_roots_come_from_a_hermitian_matrix(monkeypatch):
    """ROSS's rotor_example (no damping): no eigenvalues of the 56-state matrices are computed (a
    Hermitian matrix of the states instead: a third of the work), the roots are on the imaginary
    axis and within 5e-13 of the extended-precision roots (eig of the state matrix: within 1.6e-12),
    the shapes eig's."""
    model = rdm.Model.from_dict(read_ross_rotor(ROTOR_EXAMPLE))
    sizes = _recorded_sizes(monkeypatch, "eigvals")
    speeds = np.linspace(0.0, 1500.0, 11)
    result = rdm.campbell(model, speeds, critical=False, modes=12)
    assert 2 * model.dofs.n not in sizes
    assert np.all(result.eigenvalues[1:].real == 0)          # speed 0: double roots, solved whole
    error, eig_error = _check_gyroscopic_route(model, speeds, 12, 5e-13)
    assert error <= 5e-13 < eig_error


_steel = {"name": "steel", "density": 7800.0, "young_modulus": 2.1e11, "shear_modulus": 8.1e10}


@given(st.integers(1, 3), st.floats(0.3, 1.0), st.integers(2, 6), st.floats(0.03, 0.08),
       st.tuples(st.floats(5.0, 8.5), st.floats(5.0, 8.5)), st.floats(0.0, 30.0), st.integers(1, 8),
       st.floats(100.0, 2000.0))
@settings(max_examples=5, deadline=None, database=None)
def test_random_undamped_shafts_take_the_hermitian_route(sections, length, elements, diameter, log_k,
                                                         disk_mass, count, top_speed):
    """Random undamped shafts (sections of random diameters, a disk, bearings of random anisotropic
    stiffness): the Hermitian route's roots are as close to the extended-precision roots as eig's
    of the state matrix, its shapes eig's."""
    model = rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [_steel],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": length / elements,
                    "shaft": [{"length": length / sections, "outer_diameter": diameter * (1 + 0.3 * i),
                               "material": "steel"} for i in range(sections)],
                    "disks": [{"name": "d", "axial_position": 0.6 * length, "mass": disk_mass + 0.1,
                               "polar_inertia": 0.01 * (disk_mass + 0.1), "diametral_inertia": 0.006 * (disk_mass + 0.1)}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z,
                      "stiffness": [10 ** log_k[0], 10 ** log_k[1]]} for i, z in enumerate((0.0, length))],
    })
    assume(model.dofs.n < _lowest.DENSE_BELOW)
    _check_gyroscopic_route(model, np.linspace(0.0, top_speed, 3), min(count, model.dofs.n), 1e-12)


def test_damped_cross_coupled_or_free_models_keep_the_state_matrix_route():
    """The Hermitian route refuses the models it does not hold for: damping, a cross-coupled
    (non-symmetric) stiffness, a singular stiffness (a rotor free to roll on its mounts)."""
    from rotordyn_modal.analysis._stack import Stack

    assert _lowest._hermitian_form(Stack([_axisymmetric_shaft()])) is None          # damped bearings
    crossed = rdm.Model.from_dict({
        "name": "crossed", "spin_axis": [1.0, 0.0, 0.0], "materials": [_steel],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shaft": [{"length": 0.4, "outer_diameter": 0.05, "material": "steel"}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z, "stiffness": [[1e7, 2e6], [-2e6, 1e7]]}
                     for i, z in enumerate((0.0, 0.4))],
    })
    assert _lowest._hermitian_form(Stack([crossed])) is None
    stiff = [1e2, 1e6, 1e6, 0.0, 0.0, 0.0]
    free = rdm.Model(name="free to roll", rotors=[rdm.Rotor("rotor", 50.0, [0.0, 0.0, 0.0], 0.4, 0.9, speed_ratio=1.0)],
                     suspensions=[rdm.Suspension(f"s{i}", [x, 0.0, 0.0], stiff) for i, x in enumerate((-0.25, 0.25))])
    assert not np.any(free.matrices()[1])
    assert _lowest._hermitian_form(Stack([free])) is None
