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
    assert np.max(np.abs(_by_frequency(lowest.eigenvalues) - reference) / np.abs(reference)) < 1e-9


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
    from rotordyn_modal.analysis import _lowest

    model = rdm.Model.from_dict(_damped_machine(0.05, 1.0, 100.0, 1.0))
    speeds = np.linspace(0.0, 1500.0, 3)
    monkeypatch.setattr(_lowest, "_SHARE", 1e-30)                # no basis short of every mode passes
    monkeypatch.setattr(_lowest, "_needed_size", lambda *args: 0)
    with pytest.warns(UserWarning, match="3 of 3 speeds solved whole"):
        result = rdm.campbell(model, speeds, critical=False, modes=5)
    reference = _lowest_by_scipy(model, speeds, 5)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9
