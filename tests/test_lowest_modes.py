"""campbell(modes=N): only the N lowest modes at each speed, each the full model's root (issue 28,
item 4). Truth from outside the code under test: scipy's eigenvalues of the full state matrix at
each speed, the full sweep's critical speeds, and the imaginary roots of an undamped gyroscopic
system."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings, strategies as st

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.ross_file import read_ross_rotor

from test_flexible_rotors import _machine


def _lowest_by_scipy(model, speeds, count):
    """The ``count`` lowest-frequency oscillating roots of the state matrix at each speed, (S, count)."""
    M, C, G, K = model.matrices()
    n = len(M)
    out = []
    for speed in speeds:
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
        roots = scipy.linalg.eigvals(A)
        roots = roots[(roots.imag > 1e-9 * np.abs(roots)) & is_oscillating(roots)]
        out.append(roots[np.argsort(roots.imag)][:count])
    return np.array(out)


def _by_frequency(values):
    return np.take_along_axis(values, np.argsort(values.imag, axis=1), axis=1)


def _damped_machine(element_length, bearing_scale, damping, ratio):
    data = _machine(element_length=element_length)
    data["rotors"][0]["speed_ratio"] = ratio
    for bearing in data["bearings"]:
        stiffness = np.atleast_1d(bearing["stiffness"]) * bearing_scale
        bearing["stiffness"] = stiffness.tolist() if len(stiffness) > 1 else float(stiffness[0])
        bearing["damping"] = damping
    return data


@settings(max_examples=4, deadline=None)
@given(element_length=st.sampled_from([0.1, 0.2]), bearing_scale=st.floats(0.3, 3.0),
       damping=st.floats(0.0, 300.0), ratio=st.sampled_from([-1.5, 1.0, 2.0]), count=st.integers(1, 8))
def test_lowest_roots_are_the_full_models_roots(element_length, bearing_scale, damping, ratio, count):
    model = rdm.Model.from_dict(_damped_machine(element_length, bearing_scale, damping, ratio))
    speeds = np.linspace(0.0, 1500.0, 7)
    result = rdm.campbell(model, speeds, critical=False, modes=count)
    assert result.eigenvalues.shape == (7, count) and result.shapes.shape[:2] == (7, count)
    reference = _lowest_by_scipy(model, speeds, count)
    got = _by_frequency(result.eigenvalues)
    assert np.max(np.abs(got - reference) / np.abs(reference)) < 1e-9


def test_rigid_machine_lowest_roots():
    model = rdm.load_model("examples/motor_pump_on_mounts.toml")
    M = model.matrices()[0]
    speeds = np.linspace(0.0, 600.0, 5)
    result = rdm.campbell(model, speeds, critical=False, modes=4)
    reference = _lowest_by_scipy(model, speeds, 4)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9
    assert len(M) >= 8


def test_compressor_example_lowest_twelve_equal_the_full_sweep():
    model = rdm.Model.from_dict(read_ross_rotor("tests/data/ross/compressor_example.toml"))
    speeds = np.array([420.0, 1150.0])
    lowest = rdm.campbell(model, speeds, critical=False, modes=12)
    full = rdm.campbell(model, speeds, critical=False)
    roots = np.where(full.oscillatory, full.eigenvalues, np.nan + 1e30j)
    reference = _by_frequency(roots)[:, :12]
    # a column per root, NaN where it is not among the 12 (lowcol27q): each speed's 12 found
    kept = np.array([row[np.isfinite(row)] for row in lowest.eigenvalues])
    assert np.max(np.abs(_by_frequency(kept) - reference) / np.abs(reference)) < 1e-9


def test_undamped_gyroscopic_roots_stay_imaginary():
    model = rdm.Model.from_dict(_machine(element_length=0.1))
    assert not model.matrices()[1].any()
    result = rdm.campbell(model, np.linspace(0.0, 2000.0, 6), critical=False, modes=6)
    lam = result.eigenvalues
    assert np.all(np.abs(lam.real) <= 1e-12 * np.abs(lam))


def test_critical_speeds_of_the_modes_inside_equal_the_full_ones():
    model = rdm.Model.from_dict(_damped_machine(0.1, 1.0, 50.0, 1.0))
    speeds = np.linspace(0.0, 3000.0, 61)
    full = rdm.campbell(model, speeds).critical
    lowest = rdm.campbell(model, speeds, modes=4)
    top = lowest.frequencies_hz.max(axis=1).min()         # below this every speed's 4 lowest are all there
    inside = full.frequencies_hz < 0.95 * top
    assert inside.sum() >= 2
    assert len(lowest.critical) >= inside.sum()
    for speed in full.speeds_rpm[inside]:
        assert np.min(np.abs(lowest.critical.speeds_rpm - speed)) <= 1e-7 * speed


@pytest.mark.parametrize("bad", [0, -2, 2.5, True, "3"])
def test_modes_must_be_a_whole_number(bad):
    model = rdm.Model.from_dict(_machine(element_length=0.2))
    with pytest.raises(InputError, match="modes"):
        rdm.campbell(model, [0.0, 10.0], modes=bad)


def test_command_line_lowest(tmp_path, capsys):
    from rotordyn_modal.cli.main import main

    out = tmp_path / "c.csv"
    assert main(["campbell", "examples/motor_pump_on_mounts.toml", "--speeds", "0:3000:4", "--lowest", "3",
                 "--no-critical", "--out", str(out)]) == 0
    import pandas as pd

    table = pd.read_csv(out)
    assert set(table["mode"]) <= {1, 2, 3} and len(table) == 12
    assert main(["campbell", "examples/motor_pump_on_mounts.toml", "--speeds", "0:3000:4", "--lowest", "0"]) == 2
    assert "--lowest '0'" in capsys.readouterr().err


def test_command_line_critical_speeds_lowest(tmp_path):
    import pandas as pd

    from rotordyn_modal.cli.main import main

    full, low = tmp_path / "full.csv", tmp_path / "low.csv"
    arguments = ["critical-speeds", "examples/flexible_pump_on_mounts.toml", "--speeds", "0:6000:41"]
    assert main(arguments + ["--out", str(full)]) == 0
    assert main(arguments + ["--lowest", "6", "--out", str(low)]) == 0
    full, low = pd.read_csv(full), pd.read_csv(low)
    top = low["frequency_hz"].max()
    inside = full[full["frequency_hz"] < 0.5 * top]
    assert len(inside) >= 1
    for _, row in inside.iterrows():
        match = low[np.isclose(low["speed_rpm"], row["speed_rpm"], rtol=1e-7, atol=0)]
        assert len(match) == 1 and match["mode_at_speed"].iloc[0] == row["mode_at_speed"]


def test_speeds_the_bound_cannot_serve_are_solved_whole(monkeypatch):
    from rotordyn_modal.analysis import _lowest, _lowest_bound

    model = rdm.Model.from_dict(_damped_machine(0.05, 1.0, 100.0, 1.0))
    speeds = np.linspace(0.0, 1500.0, 3)
    monkeypatch.setattr(_lowest_bound, "_SHARE", 1e-30)                # no basis short of every mode passes
    monkeypatch.setattr(_lowest, "_needed_size", lambda *args: 0)
    with pytest.warns(UserWarning, match="3 of 3 speeds solved whole"):
        result = rdm.campbell(model, speeds, critical=False, modes=5)
    reference = _lowest_by_scipy(model, speeds, 5)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9


def _full_shapes(model, speed):
    """Every oscillating root of the state matrix at ``speed`` and its shape over the coordinates."""
    M, C, G, K = model.matrices(speed) if model.speed_dependent else model.matrices()
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    roots, vectors = scipy.linalg.eig(A)
    keep = (roots.imag > 1e-9 * np.abs(roots)) & is_oscillating(roots)
    return roots[keep], vectors[:n, keep].T


@pytest.mark.parametrize("damping, speeds", [(300.0, [0.0, 800.0, 1500.0]), (2000.0, [200.0, 1200.0])])
def test_completeness_bound_bounds_the_roots_outside_the_basis(damping, speeds):
    """theory section 17: every root up to rho has at most the bound's share of its mass-norm
    outside the basis of m undamped modes and k attachment directions (checked on scipy's roots
    and shapes, for several m and k)."""
    from rotordyn_modal.analysis import _lowest, _lowest_bound
    from rotordyn_modal.analysis._stack import Stack

    model = rdm.Model.from_dict(_damped_machine(0.05, 1.0, damping, 1.0))
    speeds = np.array(speeds)
    pencils = _lowest._Pencils(Stack([model]), speeds)
    omegas, symmetric, modes = _lowest_bound._basis(Stack([model]), speeds[:1])
    bound = _lowest._Bound(pencils, omegas, modes, symmetric)
    M = model.matrices()[0]
    tight = []
    for i, speed in enumerate(speeds):
        roots, shapes = _full_shapes(model, speed)
        rho = 1.02 * np.sort(np.abs(roots))[7]
        below = np.abs(roots) <= rho
        first = int(np.searchsorted(omegas, 1.05 * rho))
        for m in (first, first + 3, first + 8):
            for directions in (0, 3, None):
                shares, attached = bound.shares(m, rho, directions)
                basis = np.hstack([modes[:, :m], attached])
                x = shapes[below].T                                                  # (n, r)
                outside = x - basis @ (basis.T @ M @ x)
                share = np.sqrt(np.real(np.einsum("ir,ij,jr->r", outside.conj(), M, outside))
                                / np.real(np.einsum("ir,ij,jr->r", x.conj(), M, x)))
                assert np.all(share <= shares[i] * (1 + 1e-9)), (m, directions, share.max(), shares[i])
                tight.append(share.max() / shares[i])
    assert max(tight) > 1e-3          # the bound is not vacuous: within three orders of the truth somewhere


def test_bordered_band_solves_equal_dense_solves():
    """The pencils of a shaft in a casing: banded with the casing's coordinates as a border; the
    banded LU with its Schur complement solves Q(s) x = b as numpy's dense solve does."""
    from rotordyn_modal.analysis import _lowest
    from rotordyn_modal.analysis._stack import Stack

    model = rdm.Model.from_dict(_damped_machine(0.05, 1.0, 300.0, 1.0))
    n = model.dofs.n
    speeds = np.array([0.0, 700.0, 1500.0])
    pencils = _lowest._Pencils(Stack([model]), speeds)
    band = pencils.band
    assert band is not None and n - 6 <= band.size < n and max(band.lower, band.upper) <= 7
    assert set(band.order[band.size:]) <= {model.dofs.names.index(f"stator.{c}") for c in ("ux", "uy", "uz", "rx", "ry", "rz")}
    generator = np.random.default_rng(3)
    lam = generator.normal(size=9) * 300 + 1j * generator.uniform(50, 900, size=9)
    index = np.repeat(np.arange(3), 3)
    rhs = generator.normal(size=(9, n)) + 1j * generator.normal(size=(9, n))
    got = pencils.solve(index, lam, rhs)
    M, C, G, K = model.matrices()
    for p in range(9):
        Q = lam[p] ** 2 * M + lam[p] * (C + speeds[index[p]] * G) + K
        assert np.allclose(got[p], np.linalg.solve(Q, rhs[p]), rtol=1e-10, atol=0)


@pytest.mark.parametrize("dense_below", [0, 10_000])
def test_both_routes_give_the_full_models_lowest_roots(monkeypatch, dense_below):
    """Below ``DENSE_BELOW`` coordinates the dense eig of every root, above it the reduced basis
    and Newton: both the N lowest roots of the full model (here a bordered band of 59 coordinates,
    damped and turning against the reference rotor)."""
    from rotordyn_modal.analysis import _lowest

    monkeypatch.setattr(_lowest, "DENSE_BELOW", dense_below)
    data = _damped_machine(0.05, 1.7, 150.0, -1.5)
    model = rdm.Model.from_dict(data)
    speeds = np.linspace(0.0, 1500.0, 5)
    result = rdm.campbell(model, speeds, critical=False, modes=10)
    reference = _lowest_by_scipy(model, speeds, 10)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9
