"""The lowest modes of a model with frequency-dependent mount branches (Maxwell branches).

The branches' states eliminate into a rational stiffness (docs/theory.md section 17, "Mounts with
Maxwell branches"): the lowest modes come from the reduced route on that pencil, never from every
root of the state matrix with the branches' states (counted here: no full solve), and equal that
matrix's roots. Where the reduced route leaves speeds to the full solve (more modes asked for
than its projected pencil holds), that solve is refused before the work where it is over the
limit of CPU time (``--allow-long`` lifts it) or the memory at hand (not lifted), with the speeds,
the size, the estimate and the way out. Until this route, every speed of such a model was solved
whole and so refused: ``--lowest 4`` on ``rubber_mounts`` now runs under those limits."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse
from threadpoolctl import threadpool_limits

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_bound, _lowest_branches
from rotordyn_modal.analysis._stack import Stack
from rotordyn_modal.analysis.modal import OVERDAMPED_LIMIT, is_oscillating
from rotordyn_modal.cli.main import main
from rotordyn_modal.io.model_file import read_toml
from rotordyn_modal.linear_system import state_matrices

MODEL = "examples/rubber_mounts.toml"


@pytest.fixture(scope="module")
def pump():
    """examples/flexible_pump_on_mounts.toml (a flexible pump shaft on bearings in a casing, 68
    coordinates) with two Maxwell branches on each of its four mounts, as stiff as the mounts'
    static stiffness at high frequency, relaxing at 8 Hz and 160 Hz (48 branch states)."""
    from pathlib import Path

    # a module's fixture is made before the autouse fixture that starts each test in the repository
    data = read_toml(Path(__file__).resolve().parent.parent / "examples" / "flexible_pump_on_mounts.toml", "model")
    for mount in data["suspensions"]:
        k = np.asarray(mount["stiffness"])
        mount["maxwell_stiffness"] = [(0.5 * k).tolist(), k.tolist()]
        mount["maxwell_time"] = [0.02, 0.001]
    return rdm.Model.from_dict(data)


@pytest.fixture
def full_solves(monkeypatch):
    """Counts the state matrices built and solved whole (``Stack.sweep``, ``Stack.at``, ``Stack.solve``)."""
    calls = []
    for name in ("sweep", "at", "solve"):
        original = getattr(Stack, name)

        def counted(self, *args, _original=original, _name=name, **kwargs):
            calls.append(_name)
            return _original(self, *args, **kwargs)

        monkeypatch.setattr(Stack, name, counted)
    return calls


def _true_roots(A, count):
    # one BLAS thread: the matrices are small, BLAS's own threads only wait on a loaded machine
    with threadpool_limits(1):
        return _refined_roots(A, count)


def _refined_roots(A, count):
    """The ``count`` lowest oscillating roots of the state matrix ``A``: scipy's eigenvalues, each
    refined by Newton's iteration on ``(A - s I) z = 0`` (bordered by ``c^H z = 1``) with the
    residual in numpy's extended precision (the roots of ``A`` as given, free of the eigen-solver's
    round-off ``eps |A|``, which reaches 1e-9 of the lowest roots of a stiff shaft on soft mounts)."""
    values, vectors = scipy.linalg.eig(A)
    keep = np.nonzero(is_oscillating(values))[0]
    keep = keep[np.argsort(values[keep].imag)][:count]
    wide = np.clongdouble
    out = np.empty(len(keep), complex)
    N = len(A)
    wide_A = A.astype(np.longdouble)
    for j, k in enumerate(keep):
        s, z, c = wide(values[k]), vectors[:, k].astype(wide), vectors[:, k].conj()
        for _ in range(3):
            residual = wide_A @ z - s * z
            J = np.zeros((N + 1, N + 1), complex)
            J[:N, :N] = A - complex(s) * np.eye(N)
            J[:N, N] = -z.astype(complex)
            J[N, :N] = c
            d = np.linalg.solve(J, -np.append(residual.astype(complex), 0.0))
            z, s = z + d[:N].astype(wide), s + wide(d[N])
        out[j] = complex(s)
    return out


def test_the_lowest_modes_of_a_model_with_branches_are_its_state_matrix_roots(full_solves):
    model = rdm.load_model(MODEL)
    speeds = np.array([0.0, 150.0, 300.0])
    result = rdm.campbell(model, speeds, modes=4, critical=False)
    assert full_solves == []
    matrices = state_matrices(model, speeds)         # the branches' states included (theory section 6)
    for i in range(len(speeds)):
        roots = scipy.linalg.eigvals(matrices[i])
        modes = np.sort(roots[(roots.imag > 1e-6 * np.abs(roots))].imag)[:4]
        assert np.sort(result.eigenvalues[i].imag) == pytest.approx(modes, rel=1e-9)


def test_more_roots_than_modes_are_its_relaxation_roots_as_the_full_solve_gives(full_solves):
    """rubber_mounts has 6 modes: the 7th and 8th lowest roots are real roots of the state matrix
    (the branches' relaxations), after the modes, as the full solve's lowest roots (not listed as
    modes by the command line)."""
    model = rdm.load_model(MODEL)
    speeds = np.array([0.0, 200.0])
    values, _, full = _lowest_branches.lowest_roots(Stack([model]), speeds, 8)
    assert full_solves == [] and not full.any()
    assert is_oscillating(values[:, :6]).all() and not is_oscillating(values[:, 6:]).any()
    for i, A in enumerate(state_matrices(model, speeds)):
        roots = scipy.linalg.eigvals(A)
        for root in values[i]:
            assert np.min(np.abs(roots - root)) <= 1e-9 * abs(root)
        assert np.sort(values[i, :6].imag) == pytest.approx(np.sort(roots.imag[is_oscillating(roots)]), rel=1e-9)


def test_a_flexible_rotor_in_a_casing_on_maxwell_mounts(pump, full_solves):
    """The 10 lowest roots over a speed sweep are the roots of the state matrix with the branches'
    states (184 states) to 1e-9, and so are its critical speeds' roots (their sub-sweeps and
    refinement on the rational pencil too), without a full solve."""
    speeds = np.array([0.0, 3000.0, 6000.0]) * np.pi / 30
    result = rdm.campbell(pump, speeds, orders=(1,), modes=10)
    assert full_solves == []
    for i, A in enumerate(state_matrices(pump, speeds)):
        truth = _true_roots(A, 10)
        got = np.sort_complex(result.eigenvalues[i][np.argsort(result.eigenvalues[i].imag)])
        assert np.max(np.abs(got - np.sort_complex(truth)) / np.abs(truth)) <= 1e-9
    critical = result.critical
    assert len(critical.speeds) >= 4
    ratios = {"motor": 1.0, "pump": 1.25}             # the belt's: the pump turns 1.25 times the motor's speed
    for j in (0, len(critical.speeds) - 1):
        speed, frequency = critical.speeds[j], critical.frequencies_hz[j]
        assert frequency == pytest.approx(critical.order[j] * ratios[critical.source[j]] * speed / (2 * np.pi),
                                          rel=1e-9)
        truth = _true_roots(state_matrices(pump, np.array([speed]))[0], 10)
        assert np.min(np.abs(truth.imag / (2 * np.pi) - frequency)) <= 1e-9 * frequency


def test_the_modes_below_a_frequency_without_a_full_solve(pump, full_solves):
    """``max_frequency``: every mode below 15 Hz of the pump on Maxwell mounts (its five mount modes
    there), each the state matrix's root to 1e-9."""
    speeds = np.array([0.0, 6000.0]) * np.pi / 30
    result = rdm.campbell(pump, speeds, max_frequency=15.0, critical=False)
    assert full_solves == []
    for i, A in enumerate(state_matrices(pump, speeds)):
        truth = _true_roots(A, 8)
        truth = np.sort(truth[truth.imag <= 2 * np.pi * 15.0].imag)
        got = result.eigenvalues[i][np.isfinite(result.eigenvalues[i])]
        assert len(truth) == 5 and np.sort(got.imag) == pytest.approx(truth, rel=1e-9)


def test_stability_of_the_lowest_modes_without_a_full_solve(full_solves):
    model = rdm.load_model(MODEL)
    speeds = np.linspace(0.0, 300.0, 4)
    result = rdm.stability(model, speeds, modes=4)
    assert full_solves == [] and not len(result.thresholds)
    for i, A in enumerate(state_matrices(model, speeds)):
        roots = scipy.linalg.eigvals(A)
        lowest = roots[is_oscillating(roots)]
        lowest = lowest[np.argsort(lowest.imag)][:4]
        assert np.sort(result.real_parts[i]) == pytest.approx(np.sort(lowest.real), rel=1e-9)


def test_the_rational_stiffness_is_the_branch_states_eliminated():
    """``T(s) = s^2 M + s (C + Omega G) + K + sum_b K_b s tau_b / (1 + s tau_b)`` is the inverse of
    the state matrix's resolvent from force to displacement: ``T(s) [(s I - A)^-1]_{q, v} M^-1 = I``
    (``A`` with the branches' states, linear_system.state_matrices)."""
    model = rdm.load_model(MODEL)
    speed = np.array([150.0])
    A = state_matrices(model, speed)[0]
    stack = Stack([model])
    pencils = _lowest_branches.RationalPencils(stack, speed)
    n = stack.n_dof
    M = model.matrices()[0]
    for s in (30.0j - 3.0, 200.0 + 50.0j, -7.0 + 0.5j):
        resolvent = np.linalg.inv(s * np.eye(len(A)) - A)[:n, n:2 * n]
        rows, cols = pencils.pattern
        T = np.zeros((n, n), complex)
        T[rows, cols] = pencils._entries(np.zeros(1, int), np.array([s]))[0]
        assert np.abs(T @ resolvent @ np.linalg.inv(M) - np.eye(n)).max() <= 1e-9
        # and T'(s) x, against a central difference of T(s) x
        x = np.arange(1.0, n + 1.0)
        h = 1e-4 * abs(s)
        ends = [pencils._entries(np.zeros(1, int), np.array([s + d]))[0] for d in (h, -h)]
        difference = []
        for data in ends:
            Td = np.zeros((n, n), complex)
            Td[rows, cols] = data
            difference.append(Td @ x)
        numeric = (difference[0] - difference[1]) / (2 * h)
        exact = pencils.derivative_times(np.zeros(1, int), np.array([s]), x[None])[0]
        assert np.abs(exact - numeric).max() <= 1e-6 * np.abs(exact).max()


@pytest.mark.parametrize("rho_tau", [0.05, 0.5, 0.99, 1.0, 3.0, 100.0])
def test_largest_factor_is_the_supremum_over_oscillating_roots(rho_tau):
    """``|s tau / (1 + s tau)|`` over the modes ``|s| <= rho`` (``Im s > 0``, damping ratio at most
    OVERDAMPED_LIMIT), sampled on a fine polar grid, never exceeds the closed form and reaches it."""
    tau = 0.01
    rho = rho_tau / tau
    top = np.arccos(-OVERDAMPED_LIMIT)                 # the most damped angle from the positive real axis
    radii = rho * np.geomspace(1e-6, 1.0, 801)
    grid = radii[:, None] * np.exp(1j * np.linspace(1e-6, top, 801)[None, :])
    edge = rho * np.geomspace(1e-6, 1.0, 200001) * np.exp(1j * top)        # the most damped modes
    sampled = max(np.max(np.abs(s * tau / (1 + s * tau))) for s in (grid, edge))
    bound = _lowest_branches.largest_factor(rho, np.array([tau]))[0]
    assert sampled <= bound * (1 + 1e-12)
    assert sampled >= bound * (1 - 1e-3)


@pytest.mark.parametrize("below, speed", [(3, 400.0), (7, 0.0)], ids=["mount modes", "bending modes"])
def test_the_bound_bounds_the_roots_outside_the_basis(pump, below, speed):
    """docs/theory.md section 17: with the branches' stiffness at its largest up to ``rho``, every mode
    of the full model (the state matrix with the branches' states) up to ``rho`` has at most the
    bound's share of its mass-norm outside the basis of m undamped modes and k attachment
    directions (up to the mount modes, where the branches' stiffness outweighs the bearings'
    damping, and up to bending modes)."""
    speeds = np.array([speed])
    stack = Stack([pump])
    n = stack.n_dof
    pencils = _lowest_branches.RationalPencils(stack, speeds)
    omegas, symmetric, modes = _lowest_bound._basis(stack, speeds[:1])
    bound = _lowest_branches._RationalBound(pencils, omegas, modes, symmetric)
    M = pump.matrices()[0]
    tight = []
    for i, A in enumerate(state_matrices(pump, speeds)):
        with threadpool_limits(1):
            roots, vectors = scipy.linalg.eig(A)
        keep = is_oscillating(roots)
        roots, shapes = roots[keep], vectors[:n, keep]
        rho = 1.02 * np.sort(np.abs(roots))[below]
        x = shapes[:, np.abs(roots) <= rho]
        # its premise: the branches' stiffness at any mode up to rho (sampled) within the bound's norm
        bound.shares(n, rho)
        angle = np.arccos(-OVERDAMPED_LIMIT)
        samples = rho * np.geomspace(1e-3, 1.0, 200)[:, None] * np.exp(1j * np.linspace(0.01, angle, 50))[None, :]
        block = np.ix_(range(6), range(6))             # the stator's coordinates: where the branches act
        branches, times = stack.branch_stiffness[0], stack.branch_times[0]
        assert not np.any(branches.sum(axis=0)[6:]) and not np.any(branches.sum(axis=0)[:, 6:])
        s = samples.reshape(-1, 1, 1, 1)
        total = np.sum(branches[(slice(None),) + block] * s * times[:, None, None] / (1 + s * times[:, None, None]),
                       axis=1)
        largest = np.linalg.norm(total, 2, axis=(1, 2)).max()
        assert largest <= bound.stiffness_norms[i] * (1 + 1e-12)
        first = int(np.searchsorted(omegas, 1.05 * rho))
        for m in (first, first + 4, first + 10):
            for directions in (0, 3, None):
                shares, attached = bound.shares(m, rho, directions)
                basis = np.hstack([modes[:, :m], attached])
                outside = x - basis @ (basis.T @ M @ x)
                share = np.sqrt(np.real(np.einsum("ir,ij,jr->r", outside.conj(), M, outside))
                                / np.real(np.einsum("ir,ij,jr->r", x.conj(), M, x)))
                assert np.all(share <= shares[i] * (1 + 1e-9)), (m, directions, share.max(), shares[i])
                tight.append(share.max() / shares[i])
    assert max(tight) > 1e-3


def test_lowest_four_now_runs_under_the_cpu_limit(monkeypatch, tmp_path, capsys, full_solves):
    """Changed by the rational pencil: ``--lowest 4`` and ``--max-frequency 20`` of rubber_mounts
    (once every root of every speed, refused under a tiny limit) solve no speed whole, their critical
    speeds neither, so the limit does not apply."""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-7")
    for option in (["--lowest", "4"], ["--max-frequency", "20"]):
        out = tmp_path / f"campbell{option[0]}.csv"
        assert main(["campbell", MODEL, "--speeds", "0:3000:11", *option, "--out", str(out), "--quiet"]) == 0
        assert out.exists()
    assert full_solves == []


@pytest.mark.parametrize("command", [["campbell", "--lowest", "20"], ["stability", "--lowest", "20"]],
                         ids=["campbell", "stability"])
def test_over_the_cpu_limit_refused_before_the_work_and_allowed_long(command, monkeypatch, tmp_path, capsys):
    """Where the full solve remains (20 roots of rubber_mounts: more than its projected pencil's 6
    modes and 12 relaxations) it is refused as before."""
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-7")
    out = tmp_path / "out.csv"
    arguments = [command[0], MODEL, "--speeds", "0:3000:11", *command[1:], "--out", str(out), "--quiet"]
    assert main(arguments) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "Traceback" not in error
    assert "the full eigen-solve of 11 of 11 speeds (0, 300, 600, 900, 1,200, ... rpm" in error
    assert "Maxwell" in error and "eigen-solutions of 60 states" in error
    assert "would take about" in error and "use fewer speeds, or add --allow-long" in error
    assert not out.exists()
    assert main(arguments + ["--allow-long"]) == 0
    assert out.exists()


def test_over_the_memory_refused_even_with_allow_long(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(_lowest, "_CHECKED_BYTES", 0)
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1e-6")
    out = tmp_path / "out.csv"
    assert main(["campbell", MODEL, "--speeds", "0:3000:11", "--lowest", "20", "--out", str(out), "--allow-long",
                 "--quiet"]) == 2
    error = capsys.readouterr().err
    assert "Maxwell" in error and "memory" in error and error.count("\n") == 1
    assert not out.exists()


def test_a_large_model_with_branches_keeps_its_matrices_sparse(pump, monkeypatch, full_solves):
    """Above ``assembly.SPARSE_DOF`` (put at 50 here: the pump's 68 coordinates) the rational pencil
    works on the model's sparse M, C, G, K and each branch's 6x6 block: the 10 lowest roots are the
    dense route's to 1e-9 and the state matrix's (with the branches' states) to 1e-9, and neither
    they nor the sweep around them form the model's dense matrices or any branch's n x n array
    (issue 28 item 4)."""
    from rotordyn_modal import assembly, linear_system
    from rotordyn_modal.elements import mounts

    speeds = np.array([0.0, 3000.0, 6000.0]) * np.pi / 30
    dense, _, _ = _lowest_branches.lowest_roots(Stack([pump]), speeds, 10)
    truth = _true_roots(state_matrices(pump, speeds[-1:])[0], 10)

    def refuse(*args, **kwargs):
        pytest.fail("a dense n x n matrix of the model was formed")

    monkeypatch.setattr(assembly, "SPARSE_DOF", 50)
    for name in ("matrices", "mass_inverse"):
        monkeypatch.setattr(linear_system.SpeedLinearForm, name, property(refuse))
    for module in (mounts, linear_system):            # the branches' n x n arrays
        monkeypatch.setattr(module, "frame_block", refuse, raising=False)
    monkeypatch.setattr(Stack, "_constant_part", refuse)
    monkeypatch.setattr(Stack, "factor", property(refuse))
    stack = Stack([pump])
    assert stack.sparse_constant is not None
    pencils = _lowest_branches.RationalPencils(stack, speeds)
    assert all(scipy.sparse.issparse(matrix) for matrix in (pencils.M, pencils.C, pencils.G, pencils.K))
    values, _, full = _lowest_branches.lowest_roots(stack, speeds, 10)
    assert full_solves == [] and not full.any()
    assert np.max(np.abs(values - dense) / np.abs(dense)) <= 1e-9
    truth = truth[np.argsort(truth.imag)]
    assert np.max(np.abs(values[-1] - truth) / np.abs(truth)) <= 1e-9
    result = rdm.campbell(pump, speeds, modes=10, critical=False)      # tracked, weighted, whirl ratios
    assert full_solves == []
    tracked = np.take_along_axis(result.eigenvalues, np.argsort(result.eigenvalues.imag, axis=1), axis=1)
    assert np.max(np.abs(tracked - dense) / np.abs(dense)) <= 1e-9
