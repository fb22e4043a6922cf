"""Roots that are not modes are counted on the terminal by ``campbell`` as ``modes`` counts them
(issue 27 §1.1), and ``critical-speeds`` prints a whirl ratio within round-off as 0, as
``campbell`` and ``modes`` do (issue 27 §3: "whirl ratios as 2.2e-34")."""

import re
from pathlib import Path

import numpy as np
import pandas as pd

from rotordyn_modal.cli import main
from rotordyn_modal.linear_system import state_matrices
from rotordyn_modal import load_model

ROOT = Path(__file__).resolve().parents[1]

#: modes from 2e-3 Hz (a 100 kg stator on 0.01 N/m mounts) to 1e5 Hz (a 1 kg rotor on 2e11 N/m
#: bearings); the stator's modes are planar: their whirl ratio is 0 but for round-off
SPAN = """
name = "modes from 1e-3 Hz to 1e5 Hz"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "r"

[stator]
mass = 100.0
center_of_mass = [0.0, 0.0, 0.0]
inertia = [[10.0, 0.0, 0.0], [0.0, 8.0, 0.0], [0.0, 0.0, 8.0]]

[[rotors]]
name = "r"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.01
diametral_inertia = 0.006

[[bearings]]
name = "b1"
rotor = "r"
position = [0.1, 0.0, 0.0]
stiffness = 2.0e11
axial_stiffness = 2.0e11

[[bearings]]
name = "b2"
rotor = "r"
position = [-0.1, 0.0, 0.0]
stiffness = 2.0e11
""" + "".join(f"""
[[suspensions]]
name = "m{i}"
position = [{x}, {y}, -0.3]
stiffness = [1e-2, 1e-2, 1e-2]
""" for i, (x, y) in enumerate([(0.5, 0.4), (0.5, -0.4), (-0.5, 0.4), (-0.5, -0.4)]))


def test_critical_speeds_prints_a_round_off_whirl_ratio_as_zero(tmp_path, capsys):
    model = tmp_path / "span.toml"
    model.write_text(SPAN, encoding="utf-8")
    out = tmp_path / "c.csv"
    assert main(["critical-speeds", str(model), "--speeds", "0:3000:31", "--out", str(out)]) == 0
    written = pd.read_csv(out)
    capsys.readouterr()
    assert main(["critical-speeds", str(model), "--speeds", "0:3000:31"]) == 0
    lines = [line.split() for line in capsys.readouterr().out.splitlines()]
    column = lines[0].index("whirl_ratio")
    printed = [float(line[column]) for line in lines[1:] if len(line) == len(lines[0])]
    tiny = np.abs(written["whirl_ratio"].to_numpy()) < 1e-9
    assert tiny.any() and (written["whirl_ratio"].to_numpy()[tiny] != 0).any()    # the CSV keeps every digit
    shown = np.array(printed[:len(written)])
    assert np.all(shown[tiny[:len(shown)]] == 0)
    assert np.all(shown[~tiny[:len(shown)]] != 0)


def test_campbell_counts_the_real_roots_it_does_not_list(capsys):
    """rubber_mounts with Maxwell branches: 48 real roots of the state matrix at each speed (numpy's
    eigenvalues, real within 1e-9 of their size), of which the result keeps the half nearest zero."""
    path = ROOT / "examples" / "rubber_mounts.toml"
    speeds_rpm = np.linspace(0.0, 3000.0, 7)
    roots = np.linalg.eigvals(state_matrices(load_model(path), speeds_rpm * np.pi / 30.0))
    real = np.sum(np.abs(roots.imag) <= 1e-9 * np.abs(roots), axis=1)
    assert np.all(real == real[0]) and real[0] > 0
    assert main(["campbell", str(path), "--speeds", "0:3000:7"]) == 0
    err = capsys.readouterr().err
    found = re.search(r"(\d+) real roots kept .* at each speed not listed as modes", err)
    assert found, err
    assert int(found.group(1)) == real[0] // 2


def test_campbell_says_nothing_where_every_root_is_a_mode(capsys):
    """gear_machine: a casing on mounts with two rotors in bearings, no real root."""
    path = ROOT / "examples" / "gear_machine.toml"
    roots = np.linalg.eigvals(state_matrices(load_model(path), np.array([0.0, 300.0])))
    assert not np.any(np.abs(roots.imag) <= 1e-9 * np.abs(roots))
    assert main(["campbell", str(path), "--speeds", "0:3000:7"]) == 0
    assert "not listed as modes" not in capsys.readouterr().err


def test_critical_speed_tables_of_two_sweeps_concatenate():
    """The table's round-off is kept where pandas can compare it: the tables of two machines (as
    notebooks/07 puts a rigid and a flexible rotor side by side) concatenate."""
    import rotordyn_modal as rdm

    tables = [rdm.campbell(rdm.load_model(ROOT / "examples" / name), rdm.rpm(np.linspace(0.0, 3000.0, 16)))
              .critical.to_dataframe() for name in ("gear_machine.toml", "rubber_mounts.toml")]
    both = pd.concat(tables, ignore_index=True)
    assert len(both) == len(tables[0]) + len(tables[1])
