"""A machine ``simulate`` integrates as its linear model says so in one line on stderr, once per
process, and only when it runs: a run it refuses prints the refusal alone (issue 27, fresh-checkout
robustness: the line came before the refusals of the linear time model, so that the first refused
run of a process printed two lines and a later one one)."""

from __future__ import annotations

import pytest

from rotordyn_modal.cli.main import main
from rotordyn_modal.io.model_file import save_model
from rotordyn_modal.simulation import flexible
from test_simulate_flexible_journal import _machine


@pytest.mark.parametrize("argv, words", [
    (["--speed", "0", "--initial", "equilibrium"], "no static equilibrium under gravity at speed 0"),
    (["--speed", "3800", "--duration", "1e9"], "--duration 1e9: expected"),
], ids=["equilibrium-at-rest", "duration"])
def test_a_refused_linear_run_is_one_line_in_a_fresh_process(argv, words, tmp_path, monkeypatch, capsys):
    path = tmp_path / "whip.toml"
    save_model(_machine(unbalance=1e-4), path)
    monkeypatch.setattr(flexible, "_NOTICED", [])          # no linear-model notice said yet, as in a fresh process
    duration = [] if "--duration" in argv else ["--duration", "0.01"]
    assert main(["simulate", str(path), *duration, *argv, "--quiet"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], lines
    assert flexible._NOTICED == []                          # a later run that works still says it
