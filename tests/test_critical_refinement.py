"""The batched refinement of critical speeds equals the one it replaced (Brent's method on each
crossing, from Python, kept below as the reference) to 1e-10 relative on every example, and the
closed forms where they exist (tests/test_bearings.py, tests/test_campbell.py)."""

from __future__ import annotations

import dataclasses
import warnings
import os

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

import rotordyn_modal as rdm
from rotordyn_modal.analysis import (_crossing_brackets, _crossing_refinement, _crossing_roots, _eigensolve, _pencils,
                                     _vectors, _whirl)
from rotordyn_modal.analysis.critical_speeds import excitation_sources
from rotordyn_modal.analysis.modal import is_oscillating, modal_quantities
from rotordyn_modal.linear_system import speed_linear_form

EXAMPLES = ["gear_machine", "rubber_mounts", "counter_rotating", "unstable_cross_coupled", "fan_on_bearings",
            "spring_block_rotor", "spring_block_rotor_suspension", "journal_rotor"]


def brent_critical_speeds(model, speeds, orders):
    """The previous implementation: every crossing refined on its own with brentq."""
    form = speed_linear_form(model)
    forms = _whirl.whirl_forms(model)
    result = rdm.campbell(model, speeds, orders=orders)
    values, weighted = result.eigenvalues, _vectors.mass_normalized(result.shapes, form.matrices.M)
    sources = result.sources
    rows = []
    for name, multiplier in zip(sources.names, sources.multipliers):
        for order in orders:
            slope = order * multiplier
            gap = values.imag - slope * np.abs(speeds)[:, None]
            for mode in range(values.shape[1]):
                ok = is_oscillating(values[:, mode])
                change = (np.sign(gap[:-1, mode]) != np.sign(gap[1:, mode])) & (gap[:-1, mode] != 0)
                for k in np.nonzero(change & ok[:-1] & ok[1:])[0]:
                    rows.append((name, order, mode + 1,
                                 *_refine(form, forms, speeds, values, weighted, mode, k, slope)))
    rows.sort(key=lambda r: (r[3], r[0], r[1], r[2]))
    return rows


def _refine(form, forms, speeds, values, weighted, mode, k, slope):
    a, b = speeds[k], speeds[k + 1]
    spread = abs(values[k + 1, mode] - values[k, mode]) + 1e-9 * abs(values[k, mode]) + 1e-300

    def mode_at(speed):
        lam, phi = _eigensolve.solve_batch(form, np.array([speed]), forms)
        psi = _vectors.mass_normalized(phi, form.matrices.M)
        t = (speed - a) / (b - a)
        expected = (1 - t) * values[k, mode] + t * values[k + 1, mode]
        correlation = _vectors.mac_matrix(weighted[k, mode][None], psi[0])[0]
        j = int(np.argmin((1 - correlation) + np.abs(lam[0] - expected) / spread))
        return lam[0, j], phi[0, j]

    def gap(speed):
        lam = _eigensolve.select_upper(np.linalg.eigvals(form.at(speed)))
        t = (speed - a) / (b - a)
        distance = np.abs(lam - ((1 - t) * values[k, mode] + t * values[k + 1, mode]))
        nearest, second = np.argsort(distance)[:2]
        chosen = lam[nearest] if distance[second] > 4 * distance[nearest] + 2 * spread else mode_at(speed)[0]
        return chosen.imag - slope * abs(speed)

    root = a if gap(a) == 0 else b if gap(b) == 0 else \
        brentq(gap, a, b, xtol=1e-13 * max(abs(a), abs(b), 1.0), rtol=8.9e-16, maxiter=200)
    lam, phi = mode_at(root)
    ratio = _whirl.whirl_ratios(phi[None, None], forms, np.array([root]))[0, 0]
    return root, lam.imag / (2 * np.pi), str(_whirl.whirl_labels(ratio)), float(modal_quantities(lam)[1])


@pytest.mark.parametrize("path", ["joint-newton", "whole-pencils", "lu-factors", "sparse-factors", "nearest-roots",
                                  "sparse-nearest-roots", "two-nearest-roots", "arnoldi-fails", "sparse-ritz"])
@pytest.mark.parametrize("name", EXAMPLES)
def test_batched_refinement_equals_brents_method_per_crossing(name, path, examples_dir, monkeypatch):
    """Every way of evaluating a crossing gives Brent's roots: isolated modes of small pencils
    by Newton's method on the eigenpair and the speed together, or by the secant's pencil
    iteration with small pencils solved whole in one batched call, or factored once per
    crossing as large ones are (dense, or sparse as large machines' sparse pencils are); the
    others (here all crossings) from the roots nearest the interpolation by shift-invert
    Arnoldi, as large models do (dense or sparse; with only the two nearest at first, many a
    crossing must take more, since a root beyond could be its mode), or all roots where Arnoldi
    fails, or (as large models first try) picked among the Ritz pairs of the sweep's shapes at
    the bracket's ends and refined on the (sparse) pencil; each forced here for the examples' few
    coordinates. (Dense Ritz pairs: test_crossings_among_close_roots_are_refined_without_a_shift_invert_call_each.)"""
    if path != "joint-newton":
        monkeypatch.setattr(_crossing_refinement, "_NEWTON_DOF", 0)
    if path == "lu-factors" or path.startswith("sparse"):
        monkeypatch.setattr(_pencils, "BATCHED_DOF", 0)
    if path.startswith("sparse"):
        monkeypatch.setattr(_pencils, "SPARSE_DOF", 0)
        monkeypatch.setattr(_pencils, "SPARSE_DENSITY", 1.0)
    if path == "arnoldi-fails":      # every shift-invert Arnoldi call fails: all roots instead
        import scipy.sparse.linalg

        def no_convergence(*args, **kwargs):
            raise scipy.sparse.linalg.ArpackNoConvergence("no convergence (test)", np.zeros(0), np.zeros((0, 0)))

        monkeypatch.setattr(scipy.sparse.linalg, "eigs", no_convergence)
    if path == "two-nearest-roots":
        monkeypatch.setattr(_crossing_roots, "_NEAREST_ROOTS", 2)
    if path in ("nearest-roots", "sparse-nearest-roots", "two-nearest-roots", "arnoldi-fails", "sparse-ritz"):
        monkeypatch.setattr(_pencils, "NEAREST_ROOTS_DOF", 0)
        monkeypatch.setattr(_crossing_brackets, "_isolated", lambda brackets: np.zeros(len(brackets.k), bool))
    if path != "sparse-ritz":
        monkeypatch.setattr(_crossing_roots, "_RITZ_ROOTS", 0)
    model = rdm.load_model(examples_dir / f"{name}.toml")
    top = 50.0 if name.startswith("spring_block") else rdm.rpm(12000.0)
    orders = (1, 2)
    bottom = 0.0
    if name == "journal_rotor":      # speed-dependent film: it needs speed; stiff: oil whirl's half order
        bottom, top, orders = rdm.rpm(100.0), rdm.rpm(30000.0), (0.5, 1, 2)
    speeds = np.linspace(bottom, top, 121)
    found = rdm.campbell(model, speeds, orders=orders).critical
    expected = brent_critical_speeds(model, speeds, orders)
    assert len(found) == len(expected) > 0
    source, order, mode, root, freq, whirl, zeta = (list(c) for c in zip(*expected))
    assert list(found.source) == source and list(found.order) == order and list(found.mode) == mode
    assert list(found.whirl) == whirl
    np.testing.assert_allclose(found.speeds, root, rtol=1e-10)
    np.testing.assert_allclose(found.frequencies_hz, freq, rtol=1e-10)
    np.testing.assert_allclose(found.damping_ratios, zeta, rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("path", ["joint-newton", "whole-pencils", "lu-factors"])
@pytest.mark.parametrize("seed", [3, 4])
def test_pencil_iteration_equals_all_eigenvalues_of_the_state_matrix(seed, path, monkeypatch):
    """Isolated modes' critical speeds come from Newton's method on the eigenpair and the speed
    together (small pencils) or from the secant with residual inverse iteration on the
    quadratic pencil; sending every crossing through all eigenvalues of the state matrix (the
    path checked against Brent's method above) gives the same critical speeds."""
    from reference_bearings import random_bearing_description

    rng = np.random.default_rng(seed)
    data = random_bearing_description(rng, n_rotors=6)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    model = rdm.Model.from_dict(data)
    if path != "joint-newton":
        monkeypatch.setattr(_crossing_refinement, "_NEWTON_DOF", 0)
    if path == "lu-factors":
        monkeypatch.setattr(_pencils, "BATCHED_DOF", 0)
    speeds = np.linspace(0.0, 3000.0, 41)
    newton = rdm.campbell(model, speeds, orders=(1, 2)).critical
    isolated = _crossing_brackets._isolated
    used = []
    monkeypatch.setattr(_crossing_brackets, "_isolated", lambda *a: used.append(isolated(*a)) or np.zeros_like(used[-1]))
    full = rdm.campbell(model, speeds, orders=(1, 2)).critical
    assert len(full) == len(newton) > 0 and used[0].sum() > 0.25 * len(used[0])
    assert list(newton.source) == list(full.source) and list(newton.mode) == list(full.mode)
    assert list(newton.whirl) == list(full.whirl)
    np.testing.assert_allclose(newton.speeds, full.speeds, rtol=1e-10)
    np.testing.assert_allclose(newton.frequencies_hz, full.frequencies_hz, rtol=1e-10)
    np.testing.assert_allclose(newton.damping_ratios, full.damping_ratios, rtol=1e-8, atol=1e-12)


def test_modes_in_clusters_of_roots_take_more_roots_than_the_nearest(monkeypatch):
    """Where a crossing's mode is told by its shape among the roots nearest the interpolation, a
    root beyond them could be the mode (a cluster of close roots: the like rotors of a large
    machine); those crossings take more roots. Starting from only the two nearest, 93 crossing
    evaluations do here, and the critical speeds equal those picked from all eigenvalues of the
    state matrix. (The 151-coordinate model of the long test below has clusters where the eight
    nearest roots miss the mode: 13 of its 4,000 critical speeds were another mode's.)"""
    from reference_bearings import random_bearing_description

    from rotordyn_modal.analysis import campbell as campbell_module

    rng = np.random.default_rng(5)
    data = random_bearing_description(rng, n_rotors=6)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    model = rdm.Model.from_dict(data)
    speeds = np.linspace(0.0, 3000.0, 41)
    monkeypatch.setattr(_crossing_brackets, "_isolated", lambda brackets: np.zeros(len(brackets.k), bool))
    # the sweep's own tracking, as a model too large for tracking on a finer grid has it (this
    # small one's finer tracking leaves no crossing needing more roots: the same critical speeds)
    monkeypatch.setattr(campbell_module, "_FINER_ROUNDS", 0)
    full = rdm.campbell(model, speeds, orders=(1, 2)).critical
    counts = []
    roots_near = _crossing_roots._roots_near
    monkeypatch.setattr(_crossing_roots, "_roots_near",
                        lambda *args: counts.append(args[5] if len(args) > 5 else None) or roots_near(*args))
    monkeypatch.setattr(_crossing_roots, "_NEAREST_ROOTS", 2)
    monkeypatch.setattr(_pencils, "NEAREST_ROOTS_DOF", 0)
    few = rdm.campbell(model, speeds, orders=(1, 2)).critical
    assert 8 in counts
    assert len(full) == len(few) > 100
    full, few = _by_crossing(full), _by_crossing(few)
    assert list(few.source) == list(full.source) and list(few.mode) == list(full.mode)
    assert list(few.whirl) == list(full.whirl)
    np.testing.assert_allclose(few.speeds, full.speeds, rtol=1e-10)
    np.testing.assert_allclose(few.frequencies_hz, full.frequencies_hz, rtol=1e-10)
    np.testing.assert_allclose(few.damping_ratios, full.damping_ratios, rtol=1e-8, atol=1e-12)


@pytest.mark.skipif(os.environ.get("ROTORDYN_MODAL_LARGE_MODELS", "") != "full",
                    reason="about 2 and 10 minutes: set ROTORDYN_MODAL_LARGE_MODELS=full")
@pytest.mark.parametrize("n_rotors, sparse", [(20, False), (30, True)])
@pytest.mark.filterwarnings("ignore:.*critical speeds are not crossings")
def test_large_model_paths_equal_all_eigenvalues_of_the_state_matrix(n_rotors, sparse, monkeypatch):
    """Models of 101 and 151 coordinates take the large models' paths unforced (each crossing's
    pencil factored once, dense or, for the larger, sparse; the roots near non-isolated modes by
    shift-invert Arnoldi, then followed on the pencil): their critical speeds (1,718 of the
    first) equal those from all eigenvalues of the state matrix at every trial speed (the path
    checked against Brent's method above)."""
    from reference_bearings import random_bearing_description

    from rotordyn_modal.analysis._stack import Stack

    rng = np.random.default_rng(5)
    data = random_bearing_description(rng, n_rotors=n_rotors)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    model = rdm.Model.from_dict(data)
    assert speed_linear_form(model).n_dof > max(_pencils.NEAREST_ROOTS_DOF, _pencils.BATCHED_DOF)
    assert (Stack([model]).sparse_layout(0) is not None) == sparse
    speeds = np.linspace(0.0, 3000.0, 21)
    large = rdm.campbell(model, speeds).critical
    monkeypatch.setattr(_pencils, "NEAREST_ROOTS_DOF", 10**9)
    monkeypatch.setattr(_crossing_brackets, "_isolated", lambda brackets: np.zeros(len(brackets.k), bool))
    full = rdm.campbell(model, speeds).critical
    assert len(full) == len(large) > 1000
    large, full = _by_crossing(large), _by_crossing(full)
    assert list(large.source) == list(full.source) and list(large.mode) == list(full.mode)
    np.testing.assert_allclose(large.speeds, full.speeds, rtol=1e-10)
    # In clusters of like rotors' roots on this coarse grid (21 speeds), the root picked as a
    # bracket's mode can jump from one root to another between two trial speeds a round-off
    # apart, and the refinement closes in on that jump: the speed is the same either way, but the
    # eigenvalue reported there is the root on one side or the other (neither on the order line).
    jump = ~_on_order_line(full, excitation_sources(model))
    assert jump.sum() < 0.02 * len(full)                       # 46 of 4,000 for the 151 coordinates
    assert (_on_order_line(large, excitation_sources(model)) == ~jump).all()
    crossing = ~jump
    assert list(large.whirl[crossing]) == list(full.whirl[crossing])
    np.testing.assert_allclose(large.frequencies_hz[crossing], full.frequencies_hz[crossing], rtol=1e-10)
    np.testing.assert_allclose(large.damping_ratios[crossing], full.damping_ratios[crossing], rtol=1e-8,
                               atol=1e-12)


def _on_order_line(table, sources):
    """Rows whose natural frequency is the excitation frequency of their order and source at
    their speed (to 1e-8): a crossing's eigenvalue."""
    multiplier = dict(zip(sources.names, sources.multipliers))
    line = np.array([order * multiplier[name] for name, order in zip(table.source, table.order)])
    line = line * np.abs(table.speeds) / (2 * np.pi)
    return np.abs(table.frequencies_hz - line) <= 1e-8 * line


def _by_crossing(table):
    """A critical-speed table's rows ordered by source, order, mode and speed: the table itself is
    ordered by speed, and the two modes of a double root cross an order line at the same speed
    to round-off, so their rows may come in either order."""
    index = np.lexsort((table.speeds, np.asarray(table.mode), np.asarray(table.order), np.asarray(table.source)))
    return type(table)(**{field.name: getattr(table, field.name)[index] for field in dataclasses.fields(table)})


@pytest.mark.parametrize("name", EXAMPLES)
def test_sparse_pattern_holds_every_nonzero_of_the_pencil_at_every_speed(name, examples_dir):
    """The layout a sparse factorisation uses has room for every nonzero entry of M, C(Omega),
    G and K(Omega) at any speed (the journal rotor's film coefficients change with speed)."""
    model = rdm.load_model(examples_dir / f"{name}.toml")
    form = speed_linear_form(model)
    pattern = form.pattern()
    speeds = np.linspace(rdm.rpm(100.0), rdm.rpm(30000.0), 7)
    M, _, G, _ = form.matrices
    damping = np.broadcast_to(form.damping_at(speeds), (len(speeds),) + M.shape)
    stiffness = np.broadcast_to(form.stiffness_at(speeds), (len(speeds),) + M.shape)
    for matrix in (M[None], G[None], damping, stiffness):
        assert not np.any((matrix != 0) & ~pattern)
    assert pattern.sum() < pattern.size or model.dofs.n <= 6


@pytest.mark.parametrize("name", ["gear_machine", "journal_rotor"])
def test_sparse_pencils_equal_the_dense_ones(name, examples_dir, monkeypatch):
    """A row's pencil built from its sparse layout equals the dense one at any shift."""
    from rotordyn_modal.analysis._stack import Pencils, Stack

    monkeypatch.setattr(_pencils, "SPARSE_DOF", 0)
    monkeypatch.setattr(_pencils, "SPARSE_DENSITY", 1.0)
    model = rdm.load_model(examples_dir / f"{name}.toml")
    stack = Stack([model])
    speeds = np.array([rdm.rpm(500.0), rdm.rpm(9000.0)])
    pencils = Pencils(stack, np.zeros(2, dtype=int), speeds)
    assert pencils.sparse(np.arange(2)).all()
    shift = -3.0 + 250.0j
    for row in range(2):
        layout, mass, damping, stiffness = pencils.sparse_parts(row)
        sparse = layout.matrix(shift**2 * mass + shift * damping + stiffness).toarray()
        M, D, K = (np.reshape(m, (-1,) + m.shape[-2:])[-1] for m in pencils.matrices(np.array([row])))
        dense = shift**2 * M + shift * D + K
        np.testing.assert_allclose(sparse, dense, rtol=0, atol=1e-15 * np.abs(dense).max())


def _clustered_machine():
    """Ten random rotors on bearings in a casing: clusters of close roots."""
    from reference_bearings import random_bearing_description

    rng = np.random.default_rng(3)
    data = random_bearing_description(rng, n_rotors=10)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    return rdm.Model.from_dict(data)


def _assert_same_crossings(table, reference):
    """The same crossings (source, order) at the same speeds and frequencies to 1e-10, in any
    order and whatever their mode labels (those of modes that veer inside a coarse bracket may
    differ)."""
    a, b = (np.lexsort((t.speeds, t.order, np.asarray(t.source))) for t in (table, reference))
    assert list(table.source[a]) == list(reference.source[b]) and np.array_equal(table.order[a], reference.order[b])
    np.testing.assert_allclose(table.speeds[a], reference.speeds[b], rtol=1e-10)
    np.testing.assert_allclose(table.frequencies_hz[a], reference.frequencies_hz[b], rtol=1e-10)


def _assert_coarse_grid_gives_the_fine_crossings(model, coarse_speeds, fine_speeds, count):
    """Both grids give ``count`` crossings, each on its order line, the same ones (see
    :func:`_assert_same_crossings`), without a warning."""
    sources = excitation_sources(model)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coarse = rdm.campbell(model, coarse_speeds).critical
        fine = rdm.campbell(model, fine_speeds).critical
    assert len(coarse) == len(fine) == count
    assert _on_order_line(coarse, sources).all() and _on_order_line(fine, sources).all()
    _assert_same_crossings(coarse, fine)


def test_jumps_of_the_tracked_mode_between_close_roots_are_resolved_by_a_sub_sweep():
    """On a coarse grid (21 speeds) a tracked mode among close roots can pass from one root to
    another inside a bracket (4 of this machine's 454 rows), or two modes close in on one root
    (5 pairs). Those brackets are swept again, finer: the coarse grid then gives the 454
    crossings of a grid ten times finer, each on its order line, without a warning."""
    _assert_coarse_grid_gives_the_fine_crossings(_clustered_machine(), np.linspace(0.0, 3000.0, 21),
                                                 np.linspace(0.0, 3000.0, 201), 454)


def test_jumps_of_a_large_model_are_resolved_by_a_sub_sweep():
    """A machine of 20 rotors on bearings (101 coordinates) at 150 rad/s steps has two jumps
    between veering roots, near 1018 and 1296 rad/s: they are swept again as a small model's
    are, and the 5 speeds give the 208 crossings of a grid ten times finer, each on its order
    line, without a warning."""
    from reference_bearings import random_bearing_description

    model = rdm.Model.from_dict(random_bearing_description(np.random.default_rng(1), n_rotors=20))
    _assert_coarse_grid_gives_the_fine_crossings(model, np.linspace(750.0, 1350.0, 5), np.linspace(750.0, 1350.0, 41),
                                                 208)


def test_whirl_and_damping_at_critical_speeds_are_those_of_the_eigenpair_there():
    """At each critical speed the reported damping ratio and whirl ratio are those of the
    state matrix's eigenpair there, solved afresh by LAPACK, to the refinement's 1e-10 wherever
    the root is apart from every other by 1e-6 of its size (its eigenvector then well defined).
    The refinement's last point must converge its shape, not stop after one step through the
    pencil of the point before, which is singular to round-off there (that left errors up to
    1.3e-9 in this machine's whirl ratios)."""
    from reference_bearings import random_bearing_description
    from rotordyn_modal.linear_system import state_matrices

    model = rdm.Model.from_dict(random_bearing_description(np.random.default_rng(1), n_rotors=3, stator=True))
    table = rdm.campbell(model, np.linspace(0.0, 3000.0, 21), orders=(1, 2)).critical
    forms = _whirl.whirl_forms(model)
    n = forms.total.shape[-1]
    checked = 0
    for speed, freq, zeta, whirl in zip(table.speeds, table.frequencies_hz, table.damping_ratios, table.whirl_ratios):
        values, vectors = scipy.linalg.eig(state_matrices(model, [speed])[0])
        reported = 2 * np.pi * freq * (-zeta / np.sqrt(1 - zeta**2) + 1j)
        distance = np.abs(values - reported)
        k = np.argmin(distance)
        if np.partition(distance, 1)[1] < 1e-6 * abs(values[k]):
            continue
        shape = vectors[:n, k] / np.linalg.norm(vectors[:n, k])
        assert abs(-values[k].real / abs(values[k]) - zeta) <= 1e-10
        assert abs(_whirl.whirl_ratios(shape[None, None], forms, np.array([speed]))[0, 0] - whirl) <= 1e-10
        checked += 1
    assert checked >= 0.9 * len(table) > 100


@pytest.mark.parametrize("failure", ["not-finite", "leaves-bracket"])
def test_crossings_that_newton_fails_are_refined_by_the_secant(failure, monkeypatch):
    """Where Newton's method on the eigenpair and the speed fails for a crossing (a step that
    is not finite, or a point outside the bracket), the secant's iteration, which keeps every
    point inside the bracket, refines it as it does without Newton, and the other crossings keep
    Newton's roots: every row equals, bit for bit, the row of the path that refined it."""
    from reference_bearings import random_bearing_description

    model = rdm.Model.from_dict(random_bearing_description(np.random.default_rng(1), n_rotors=3, stator=True))
    speeds = np.linspace(0.0, 3000.0, 21)
    newton = _by_crossing(rdm.campbell(model, speeds, orders=(1, 2)).critical)
    with monkeypatch.context() as patch:
        patch.setattr(_crossing_refinement, "_NEWTON_DOF", 0)
        secant = _by_crossing(rdm.campbell(model, speeds, orders=(1, 2)).critical)
    assert not np.array_equal(newton.speeds, secant.speeds)           # the paths' round-off differs
    threshold = speeds[4]              # a grid speed: every bracket lies on one side of it
    newton_step = _pencils.speed_newton_step
    failed = []

    def failing(matrices, x, *args):
        steps = newton_step(matrices, x, *args)
        above = x > threshold
        failed.append(int(above.sum()))
        steps[0][above] = np.nan if failure == "not-finite" else steps[0][above] + 2 * (speeds[1] - speeds[0])
        return steps

    monkeypatch.setattr(_pencils, "speed_newton_step", failing)
    mixed = _by_crossing(rdm.campbell(model, speeds, orders=(1, 2)).critical)
    above = mixed.speeds > threshold
    assert failed[0] > 10 and 10 < above.sum() < len(mixed) - 10
    assert list(mixed.source) == list(newton.source) and list(mixed.mode) == list(newton.mode)
    for column in ("speeds", "frequencies_hz", "whirl_ratios", "damping_ratios"):
        assert np.array_equal(getattr(mixed, column)[above], getattr(secant, column)[above]), column
        assert np.array_equal(getattr(mixed, column)[~above], getattr(newton, column)[~above]), column


def test_brackets_crowded_with_close_roots_are_swept_again_with_the_same_crossings(monkeypatch):
    """A bracket holding many crossings among close roots is swept again at once (seven
    eigen-solves instead of all the roots for each crossing): the same crossings as refining
    each by itself, to 1e-10; only the labels of modes that veer inside the bracket may differ
    (each is the mode at the bracket's start that the finer grid follows)."""
    from rotordyn_modal.analysis import critical_speeds as critical_module

    model = _clustered_machine()
    speeds = np.linspace(0.0, 3000.0, 21)
    swept = []
    crossings_in = critical_module._crossings_in
    monkeypatch.setattr(critical_module, "_crossings_in", lambda *args: swept.append(args[-1]) or crossings_in(*args))
    crowded = rdm.campbell(model, speeds).critical
    assert swept.count(0) >= 5                      # brackets of the sweep itself, swept again
    monkeypatch.setattr(critical_module, "_CROWDED", 10**9)
    alone = rdm.campbell(model, speeds).critical
    assert len(crowded) == len(alone) == 454
    _assert_same_crossings(crowded, alone)
    a, b = (np.lexsort((t.speeds, t.order, np.asarray(t.source))) for t in (crowded, alone))
    np.testing.assert_allclose(crowded.damping_ratios[a], alone.damping_ratios[b], rtol=0, atol=1e-10)


def test_jumps_left_in_a_sub_sweep_are_resolved_by_a_sub_sweep_of_their_own(monkeypatch):
    """Sub-sweeps of one inner speed (instead of 7) leave jumps of their own: they are swept
    again in turn, and the 21 speeds still give the crossings of 201 speeds."""
    from rotordyn_modal.analysis import critical_speeds as critical_module

    model = _clustered_machine()
    depths = []
    crossings_in = critical_module._crossings_in
    monkeypatch.setattr(critical_module, "_crossings_in", lambda *args: depths.append(args[-1]) or crossings_in(*args))
    monkeypatch.setattr(critical_module, "_SUB_SPEEDS", 3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coarse = rdm.campbell(model, np.linspace(0.0, 3000.0, 21)).critical
    assert max(depths) >= 1
    monkeypatch.undo()
    fine = rdm.campbell(model, np.linspace(0.0, 3000.0, 201)).critical
    assert _on_order_line(coarse, excitation_sources(model)).all()
    _assert_same_crossings(coarse, fine)


def test_jumps_left_unresolved_are_warned_of(monkeypatch):
    """Without sub-sweeps (none left at the deepest level) a bracket's jump stays: the
    refinement closes in on it, its frequency is off the order line, and those rows, and only
    those, are warned of."""
    from rotordyn_modal.analysis import critical_speeds as critical_module

    monkeypatch.setattr(critical_module, "_SUB_DEPTH", 0)
    model = _clustered_machine()
    sources = excitation_sources(model)
    with pytest.warns(UserWarning, match=r"4 of 454 critical speeds are not crossings") as caught:
        coarse = rdm.campbell(model, np.linspace(0.0, 3000.0, 21)).critical
    off = ~_on_order_line(coarse, sources)
    assert off.sum() == 4
    assert str(sorted(set(coarse.mode[off].tolist()))) in str(caught[0].message)


def test_the_command_line_prints_a_warning_on_one_line(examples_dir, monkeypatch, capsys):
    from rotordyn_modal.analysis import critical_speeds as critical_module
    from rotordyn_modal.cli.main import main

    monkeypatch.setattr(critical_module, "off_order_line", lambda table, sources: np.full(len(table), 0.01))
    assert main(["critical-speeds", str(examples_dir / "gear_machine.toml"), "--speeds", "0:3000:201"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("rotordyn-modal critical-speeds: warning: ")
    assert "critical speeds are not crossings" in err[0]


def test_a_singular_pencil_leaves_the_other_rows_their_own_solve():
    """numpy refuses a whole stack for one singular matrix; the other rows must still get the
    bits of their own solve (a study's variant then equals its model's own analysis) and the
    singular one its least-squares solution."""
    rng = np.random.default_rng(5)
    matrices = rng.normal(size=(37, 6, 6)) + 1j * rng.normal(size=(37, 6, 6))
    matrices[23, :, 0] = 0.0                                    # exactly singular
    rhs = rng.normal(size=(37, 6, 1)) + 1j * rng.normal(size=(37, 6, 1))
    with pytest.raises(np.linalg.LinAlgError):
        np.linalg.solve(matrices, rhs)
    found = _pencils._solve(matrices, rhs)
    for row in range(37):
        if row == 23:
            expected = np.linalg.lstsq(matrices[row], rhs[row], rcond=None)[0]
        else:
            expected = np.linalg.solve(matrices[row], rhs[row])
        assert found[row].tobytes() == expected.tobytes(), row


def test_crossings_among_close_roots_are_refined_without_a_shift_invert_call_each(monkeypatch):
    """A chain of geared rotors on bearings has clusters of close roots: a large machine's
    crossings there once took one shift-invert Arnoldi call each for the roots near their first
    trial speed (0.18 s each at 406 coordinates, 41,828 crossings). They now pick their mode
    among the Ritz pairs of the sweep's shapes at the bracket's ends, all together, and refine
    it on the pencil; Arnoldi is left for the few that do not settle there. Checked from
    outside: at every critical speed, the root of the dense state matrix (numpy's eigenvalues)
    nearest the reported one is on the order line, ``Im lam = order x multiplier x |Omega|``, to
    1e-9 relative, and equals the reported root."""
    import tomllib

    from test_large_machine_cli import chained_gear_toml

    from rotordyn_modal.analysis import critical_speeds as critical_module

    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(6, 6)))
    monkeypatch.setattr(_pencils, "NEAREST_ROOTS_DOF", 0)       # the large machines' path, forced (30 coordinates)
    arnoldi = []
    nearest_roots = _pencils.nearest_roots
    monkeypatch.setattr(_pencils, "nearest_roots", lambda pencils, centers, *a: arnoldi.append(len(centers))
                        or nearest_roots(pencils, centers, *a))
    speeds = rdm.rpm(np.linspace(0.0, 3000.0, 11))
    found = rdm.campbell(model, speeds).critical
    crowded = critical_module._crossing_brackets(speeds, *_sweep(model, speeds))
    among_close = int((~crowded.isolated).sum())
    assert len(found) > 200 and among_close > 50
    assert sum(arnoldi) <= 0.05 * among_close, (sum(arnoldi), among_close)
    sources = excitation_sources(model)
    multiplier = dict(zip(sources.names, sources.multipliers))
    line = np.array([order * multiplier[name] for name, order in zip(found.source, found.order)]) * np.abs(found.speeds)
    form = speed_linear_form(model)
    omega = 2 * np.pi * found.frequencies_hz
    reported = -found.damping_ratios * omega / np.sqrt(1 - found.damping_ratios ** 2) + 1j * omega
    for speed, root, excitation in zip(found.speeds, reported, line):
        roots = np.linalg.eigvals(form.at(speed))
        nearest = roots[np.argmin(np.abs(roots - root))]
        assert abs(nearest.imag - excitation) <= 1e-9 * excitation
        assert abs(nearest - root) <= 1e-9 * abs(root)


def _sweep(model, speeds):
    """The sweep's tracked roots (1, N, m) and one ExcitationSources list, as the critical speeds read them."""
    result = rdm.campbell(model, speeds, critical=False)
    return result.eigenvalues[None], [result.sources], (1.0,)
