"""frf's modal superposition on a large machine (issue 27 §1.9): its eigen-solution runs with one
BLAS thread, as every other dense eigen-solution (OpenBLAS's threads on the shared cores: 500 geared
rotors, 2,006 coordinates, took 118 s of CPU where ``modes``' solve took 45 s), and a long one is
announced on stderr with its estimate before it starts (it ran about 4 minutes without a word)."""

from __future__ import annotations

import functools
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _eigensolve, _work
from rotordyn_modal.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_blas_threads import _blas_threads  # noqa: E402
from test_large_machine_cli import chained_gear_toml  # noqa: E402

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
EXCITATION = '\n[[excitations]]\nname = "tap"\nposition = [0.0, 0.0, 0.4]\ndirection = [0.0, 0.0, 1.0]\n'
SENSOR = '\n[[sensors]]\nname = "top"\nposition = [0.0, 0.0, 0.4]\ndirection = [0.0, 0.0, 1.0]\n'


def test_the_modal_superposition_solves_with_one_blas_thread(tmp_path, monkeypatch):
    pytest.importorskip("threadpoolctl")
    if _blas_threads() < 2:
        pytest.skip("BLAS runs one thread here anyway")
    model = rdm.Model.from_dict(__import__("tomllib").loads(chained_gear_toml(20, 20) + EXCITATION + SENSOR))
    assert model.dofs.n == 86                               # 172 states: BLAS would start threads
    seen, original, dgeev = [], scipy.linalg.eig, _eigensolve._dgeev()

    def spy(*args, _original=original, **kwargs):
        seen.append(_blas_threads())
        return _original(*args, **kwargs)

    monkeypatch.setattr(scipy.linalg, "eig", spy)
    monkeypatch.setattr(_eigensolve, "_dgeev", lambda: functools.partial(spy, _original=dgeev))  # scipy's LAPACK
    result = rdm.frf(model, 100.0, np.linspace(1.0, 50.0, 5))
    assert result.engine == "modal" and seen == [1]


def test_a_long_modal_superposition_is_announced_with_its_estimate(capsys, monkeypatch):
    monkeypatch.setattr(_cost, "_PESSIMISTIC", 1.0)              # every model passes the cheap gate
    monkeypatch.setattr(_work, "eig_seconds", lambda n_states: 150.0)
    path = EXAMPLES / "gear_machine.toml"
    assert main(["frf", str(path), "--speed", "3000", "--freqs", "1:100:5", "--out", "-"]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    n = rdm.load_model(path).dofs.n
    assert err == [f"frf: one eigen-solution of {2 * n:,} states ({n:,} coordinates) for the modal superposition: "
                   f"about {_cost.duration(150.0)} of CPU time (one LAPACK call: on a terminal a clock shows it running)"]
    assert main(["frf", str(path), "--speed", "3000", "--freqs", "1:100:5", "--out", "-", "--quiet"]) == 0
    assert capsys.readouterr().err.strip() == ""


def test_a_short_one_says_nothing(capsys):
    assert main(["frf", str(EXAMPLES / "gear_machine.toml"), "--speed", "3000", "--freqs", "1:100:5", "--out", "-"]) == 0
    assert capsys.readouterr().err.strip() == ""
