"""What the terminal shows (issue 27 §1.7 and §3): a sentence instead of an empty table, and
numbers within the eigen-solve's round-off as 0 (never -0), whirl labels that round-off cannot
flip; the CSV keeps its header and its precision, without -0."""

from __future__ import annotations

import io

import numpy as np
import pandas as pd
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

# critically overdamped in every direction (c^2 > 4 k m): twelve real roots (six kept), no mode
_OVERDAMPED = """
name = "a rotor in an overdamped block"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "rotor"

[[rotors]]
name = "rotor"
mass = 1.0
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.05

[[suspensions]]
name = "block"
position = [0.0, 0.0, 0.0]
stiffness = [1e6, 1e6, 1e6, 1e4, 1e4, 1e4]
damping = [1e6, 1e6, 1e6, 1e4, 1e4, 1e4]
"""


@pytest.fixture
def overdamped(tmp_path):
    path = tmp_path / "overdamped.toml"
    path.write_text(_OVERDAMPED)
    return path


def _run(argv, capsys):
    assert main([str(a) for a in argv]) == 0
    captured = capsys.readouterr()
    assert "Empty DataFrame" not in captured.out + captured.err
    return captured.out


def test_no_critical_speed_is_a_sentence_and_the_csv_keeps_its_header(examples_dir, tmp_path, capsys):
    """The gear machine's lowest mode is at 8.9 Hz: no crossing of 1X or 2X below 10 rpm."""
    out = _run(["critical-speeds", examples_dir / "gear_machine.toml", "--speeds", "0:10:3", "--orders", "1,2"],
               capsys)
    assert out.strip() == "no critical speed between 0 and 10 rpm (orders 1,2)"
    path = tmp_path / "none.csv"
    _run(["critical-speeds", examples_dir / "gear_machine.toml", "--speeds", "0:10:3", "--out", path], capsys)
    table = pd.read_csv(path)
    assert table.empty and list(table.columns)[:4] == ["source", "order", "mode", "speed_rpm"]


def test_no_mode_is_a_sentence_with_the_roots_counted(overdamped, capsys):
    out = _run(["modes", overdamped, "--speed", "0"], capsys)
    assert out.strip() == ("no oscillating modes at 0 rpm: 12 real roots (relaxation, rigid-body; the 6 nearest zero "
                           "kept as the result's half, docs/theory.md section 8)")
    out = _run(["campbell", overdamped, "--speeds", "0:100:3"], capsys)
    assert out.strip().startswith("no oscillating modes between 0 and 100 rpm")


def test_no_unbalance_peak_is_a_sentence(examples_dir, capsys):
    assert main(["unbalance", str(examples_dir / "gear_machine.toml"), "--speeds", "0:10:3"]) == 0
    captured = capsys.readouterr()
    assert "no resonance peak between 0 and 10 rpm" in captured.out
    assert "Empty DataFrame" not in captured.out


def _terminal_table(out):
    # the modes table's whirl 'no whirl' (the CSV's none) is one cell of two words
    lines = [line.replace("no whirl", "no-whirl").split() for line in out.strip().splitlines()]
    return pd.DataFrame(lines[1:], columns=lines[0])


@pytest.mark.parametrize("name", ["spring_block_rotor.toml", "spring_block_rotor_suspension.toml"])
@pytest.mark.parametrize("rpm", ["0", "3000"])
def test_an_undamped_machine_prints_zero_damping(examples_dir, capsys, name, rpm):
    """These models have no damping at all: every damping ratio, log decrement and real part is
    0 (the solver's 1e-25 and -0 are round-off)."""
    table = _terminal_table(_run(["modes", examples_dir / name, "--speed", rpm], capsys))
    for column in ("damping_ratio", "log_decrement", "real_part"):
        assert set(table[column]) == {"0"}, column


def test_the_csv_has_no_negative_zero(examples_dir, capsys):
    out = _run(["modes", examples_dir / "spring_block_rotor_suspension.toml", "--speed", "3000", "--out", "-"],
               capsys)
    fields = [field for line in out.splitlines() for field in line.split(",")]
    assert "-0" not in fields and not any(field.startswith("-0e") for field in fields)
    table = pd.read_csv(io.StringIO(out))
    assert not np.any(np.signbit(table.select_dtypes(float).to_numpy()) & (table.select_dtypes(float) == 0))


def test_round_off_cannot_flip_a_whirl_label(examples_dir, tmp_path):
    """At rest the rubber-mounted gear machine's modes have no whirl (|ratio| < 1e-6 with a 2 ms
    branch). With a 1e-12 s branch the state matrix's norm is 7e12 1/s, and round-off moves the
    computed ratios by up to about 1e-3: the labels stay 'none' (and the terminal prints 0)."""
    text = (examples_dir / "rubber_mounts.toml").read_text()
    path = tmp_path / "fast.toml"
    path.write_text(text.replace("maxwell_time = [0.02, 0.002]", "maxwell_time = [0.02, 1e-12]"))
    reference = rdm.modal(rdm.load_model(examples_dir / "rubber_mounts.toml"), 0.0)
    assert np.all(np.abs(reference.whirl_ratios) < 1e-6)
    result = rdm.modal(rdm.load_model(path), 0.0)
    assert result.oscillatory.sum() == 6
    assert set(result.whirl[result.oscillatory]) == {"none"}
    table = result.to_dataframe()
    noise = result.round_off_rows()["whirl_ratio"]          # row by row (attrs keep one number a column)
    assert np.all(np.abs(table["whirl_ratio"]) <= noise)
