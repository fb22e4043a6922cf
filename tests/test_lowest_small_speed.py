"""The lowest modes of small flexible models, fast (issue 28, item 4): the reduced route's Newton
solves of a banded shaft of 37 to 48 coordinates by a banded LU each (not a dense n x n pencil per
root), the pencils' entries as one product. Truth from outside the code under test: scipy's
eigenvalues of the state matrix built here, and each pencil written out entry by entry."""

from __future__ import annotations

import numpy as np
import scipy.linalg
from hypothesis import example, given, settings, strategies as st

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_pencils
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.io.ross_file import read_ross_rotor

SPEED_TABLES = "tests/data/ross/speed_tables.toml"


def _lowest_by_scipy(model, speeds, count, every=False):
    """The ``count`` lowest-frequency modes of the state matrix (built here from
    ``model.matrices(speed)``) at each speed, (S, count); with ``every`` all its modes too, a list
    of S arrays (their number may change with the speed). A mode is a root with Im > 0 and a
    damping ratio ``-Re/|lam|`` of at most 0.99, as docs/theory.md defines it (a pair damped beyond
    that is overdamped, not a mode)."""
    out, everything = [], []
    constant = None if model.speed_dependent else model.matrices()
    for speed in speeds:
        M, C, G, K = constant if constant is not None else model.matrices(speed)
        n = len(M)
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
        roots = scipy.linalg.eigvals(A)
        roots = roots[(roots.imag > 0) & (-roots.real <= 0.99 * np.abs(roots))]
        everything.append(np.sort_complex(roots))
        out.append(roots[np.argsort(roots.imag)][:count])
    return (np.array(out), everything) if every else np.array(out)


def _by_frequency(values):
    return np.take_along_axis(values, np.argsort(values.imag, axis=1), axis=1)


def _counted_solves(monkeypatch):
    """Banded LUs (``zgbsv``, row by row or a chunk's rows in one loop) and the sizes of numpy's
    dense solves from now on."""
    calls = {"banded": 0, "dense": []}
    banded, rows, dense = _lowest_pencils._zgbsv, _lowest_pencils._solved_rows, np.linalg.solve

    def counting_banded(*args, **kwargs):
        calls["banded"] += 1
        return banded(*args, **kwargs)

    def counting_rows(kl, ku, ab, y):
        calls["banded"] += len(ab)
        return rows(kl, ku, ab, y)

    def recording_dense(a, b):
        calls["dense"].append(np.shape(a))
        return dense(a, b)

    monkeypatch.setattr(_lowest_pencils, "_zgbsv", counting_banded)
    monkeypatch.setattr(_lowest_pencils, "_solved_rows", counting_rows)
    monkeypatch.setattr(np.linalg, "solve", recording_dense)
    return calls


def test_banded_shaft_of_44_coordinates_is_refined_by_banded_solves(monkeypatch):
    """ROSS's speed_tables rotor (44 coordinates, bearings tabulated over speed, the reduced
    route): Newton's solves are banded LUs, no n x n complex pencil per root is solved dense,
    and the 12 lowest roots are scipy's."""
    model = rdm.Model.from_dict(read_ross_rotor(SPEED_TABLES))
    n = model.dofs.n
    assert _lowest.DENSE_BELOW <= n
    speeds = np.linspace(100.0, 1000.0, 5)
    # the checks of the mode links take the dense route below CHECK_DENSE_BELOW coordinates
    # (ross40: their shapes by dense inverse iteration); this test is about the sweep's Newton solves
    monkeypatch.setattr(_lowest, "CHECK_DENSE_BELOW", _lowest.DENSE_BELOW)
    calls = _counted_solves(monkeypatch)
    result = rdm.campbell(model, speeds, critical=False, modes=12)
    assert calls["banded"] >= 12 * len(speeds)                      # every root, every iteration
    assert not [shape for shape in calls["dense"] if shape[-1] == n and len(shape) == 3 and shape[0] >= 12]
    reference = _lowest_by_scipy(model, speeds, 12)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9


def _random_shaft(sections, length, diameter, log_k, damping, cross):
    return {
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "shear_modulus": 8e10}],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": length / 10,
                    "shaft": [{"length": length / sections, "outer_diameter": diameter * (1 + 0.2 * i),
                               "material": "steel"} for i in range(sections)],
                    "disks": [{"name": "d", "axial_position": 0.6 * length, "mass": 8.0, "polar_inertia": 0.06,
                               "diametral_inertia": 0.04}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z,
                      "stiffness": [[10 ** log_k, cross * 10 ** log_k], [-cross * 10 ** log_k, 1.3 * 10 ** log_k]],
                      "damping": [[damping, 0.0], [0.0, 2 * damping]]}
                     for i, z in enumerate((0.05 * length, 0.95 * length))],
    }


@settings(max_examples=3, deadline=None)
@given(sections=st.integers(1, 3), length=st.floats(0.5, 1.5), diameter=st.floats(0.03, 0.08),
       log_k=st.floats(5.5, 8.5), damping=st.floats(0.0, 2000.0), cross=st.floats(-0.5, 0.5),
       count=st.integers(1, 10))
@example(sections=1, length=1.0, diameter=0.0625, log_k=6.0, damping=0.0, cross=0.5, count=1)   # found by a helper
def test_random_damped_shafts_lowest_roots_are_scipys(sections, length, diameter, log_k, damping, cross, count):
    """Random damped, cross-coupled shafts on two bearings above ``DENSE_BELOW`` coordinates
    (their Newton solves banded): the ``count`` lowest roots are those of scipy's eig of the state
    matrix to 1e-9: their frequencies are the ``count`` lowest, and each is one of scipy's roots
    (without damping, cross-coupling at rest gives pairs ``-a + ib``, ``a + ib`` of one frequency:
    which of a pair is the ``count``-th is not defined)."""
    model = rdm.Model.from_dict(_random_shaft(sections, length, diameter, log_k, damping, cross))
    assert _lowest.DENSE_BELOW <= model.dofs.n
    speeds = np.linspace(0.0, 1500.0, 4)
    result = rdm.campbell(model, speeds, critical=False, modes=count)
    reference, every = _lowest_by_scipy(model, speeds, count, every=True)
    # the columns follow roots (one column per tracked root): at rest the undamped, cross-coupled
    # pair -a + ib, a + ib of the count-th frequency may sit in two columns, each present at
    # different speeds; at every speed exactly ``count`` of them hold a root
    assert (np.isfinite(result.eigenvalues).sum(axis=1) == count).all(), result.eigenvalues
    got = _by_frequency(result.eigenvalues)[:, :count]        # NaN sorts last
    assert np.max(np.abs(got.imag - reference.imag) / np.abs(reference)) < 1e-9
    for at_speed, modes in zip(got, every):
        nearest = np.min(np.abs(at_speed[:, None] - modes[None, :]), axis=-1)
        assert np.max(nearest / np.abs(at_speed)) < 1e-9


def test_pencil_entries_are_the_pencils_written_out():
    """The entries on the pattern of ``s^2 M + s (C + Omega G + C_b) + K + K_b`` (bearings tabulated
    over speed) equal the pencils summed here entry by entry."""
    model = rdm.Model.from_dict(read_ross_rotor(SPEED_TABLES))
    speeds = np.array([150.0, 600.0, 950.0])
    pencils = _lowest._Pencils(Stack([model]), speeds)
    generator = np.random.default_rng(5)
    lam = generator.normal(size=6) * 30 + 1j * generator.uniform(100, 3000, size=6)
    index = np.array([0, 0, 1, 1, 2, 2])
    got = pencils._entries(index, lam)
    rows, cols = pencils.pattern
    for p in range(6):
        M, C, G, K = model.matrices(speeds[index[p]])
        Q = lam[p] ** 2 * M + lam[p] * (C + speeds[index[p]] * G) + K
        assert np.allclose(got[p], Q[rows, cols], rtol=1e-13, atol=1e-13 * np.abs(Q).max())


def test_stack_assembles_each_shafts_node_motions_once(monkeypatch):
    """A Stack of a model with a flexible rotor (its M, C, G, K and whirl forms) assembles the
    nodes' motions over the coordinates once, not once per matrix; the matrices and whirl forms
    equal those made from a fresh model each time."""
    from rotordyn_modal import assembly
    from rotordyn_modal.analysis import _whirl

    model = rdm.Model.from_dict(read_ross_rotor(SPEED_TABLES))
    plain, calls = assembly._node_relative, []

    def counting(*args):
        calls.append(1)
        return plain(*args)

    monkeypatch.setattr(assembly, "_node_relative", counting)
    stack = Stack([model])
    whirl = stack.whirl
    assert len(calls) == 1
    def fresh():
        return rdm.Model.from_dict(read_ross_rotor(SPEED_TABLES))

    assert np.array_equal(stack.M[0], assembly.mass_matrix(fresh()))
    assert np.array_equal(stack.G[0], assembly.gyroscopic_matrix(fresh()))
    assert np.array_equal(stack.K[0], assembly.constant_stiffness_damping(fresh())[0])
    for got, made in zip(whirl, _whirl.whirl_forms(fresh())):
        assert np.array_equal(got[0], made)
