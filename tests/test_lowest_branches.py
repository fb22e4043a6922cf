"""The lowest modes of a model with frequency-dependent mount branches (Maxwell branches: states
outside the pencil the reduced route refines) are every root of every speed: refused before that
work where it is over the limit of CPU time (``--allow-long`` lifts it) or the memory at hand (not
lifted), with the speeds, the size, the estimate and the way out; under the limits the results are
the full model's (scipy's eigenvalues of its state matrix with the branches' states)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.cli.main import main
from rotordyn_modal.linear_system import state_matrices

MODEL = "examples/rubber_mounts.toml"


def test_the_lowest_modes_of_a_model_with_branches_are_its_state_matrix_roots():
    model = rdm.load_model(MODEL)
    speeds = np.array([0.0, 150.0, 300.0])
    result = rdm.campbell(model, speeds, modes=4, critical=False)
    matrices = state_matrices(model, speeds)         # the branches' states included (theory section 6)
    for i in range(len(speeds)):
        roots = scipy.linalg.eigvals(matrices[i])
        modes = np.sort(roots[(roots.imag > 1e-6 * np.abs(roots))].imag)[:4]
        assert np.sort(result.eigenvalues[i].imag) == pytest.approx(modes, rel=1e-9)


@pytest.mark.parametrize("command", [["campbell", "--lowest", "4"], ["campbell", "--max-frequency", "20"],
                                     ["stability", "--lowest", "4"]], ids=["campbell", "max-frequency", "stability"])
def test_over_the_cpu_limit_refused_before_the_work_and_allowed_long(command, monkeypatch, tmp_path, capsys):
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
    assert main(["campbell", MODEL, "--speeds", "0:3000:11", "--lowest", "4", "--out", str(out), "--allow-long",
                 "--quiet"]) == 2
    error = capsys.readouterr().err
    assert "Maxwell" in error and "memory" in error and error.count("\n") == 1
    assert not out.exists()
