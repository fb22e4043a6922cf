"""``simulate`` on a large machine refuses a run over the CPU limit before any eigen-solution (issue 27 §1.9).

On 500 geared rotors (2,006 coordinates) the state matrix's eigenvalues (the fastest rate) and
its eigenvectors (the fastest excited mode) took 4 min of silence before the CPU estimate, and
that estimate, assuming at most 10 ms an evaluation, let through a run of about 3 h (one
compiled evaluation cost 1.15 s there: the mass matrix's Cholesky solve grew as n^3; 4.3 ms since
sim27o's reordered solve). The same machine scaled down: 75 rotors chained by gears, 306
coordinates (0.17 ms an evaluation; 3 ms before), with the CPU limit lowered so that its 201 output
times are over it. The truth the estimate is checked
against is the CPU time the run then takes (``--allow-long``): the estimate is a low bound.
"""

from __future__ import annotations

import re
import time
import tomllib
import types

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError
from rotordyn_modal.simulation._system import COMPILE_NOTICE, system_arrays
from test_large_machine_cli import chained_gear_toml

import importlib

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")

ROTORS = 75                 # 306 coordinates
SPEED = 100.0               # rad/s of the first rotor
DURATION, SAMPLES = 0.01, 201
LIMIT_MINUTES = "0.002"     # 0.12 s of CPU


def _model():
    return rdm.Model.from_dict(tomllib.loads(chained_gear_toml(ROTORS, ROTORS)), source="chain.toml")


def _record_eigen_solutions(monkeypatch):
    """Every call of scipy's dense eigen-solvers, recorded (simulate catches their errors)."""
    calls = []
    for name in ("eig", "eigvals"):
        original = getattr(scipy.linalg, name)

        def recorded(*args, _original=original, _name=name, **kwargs):
            calls.append(_name)
            return _original(*args, **kwargs)

        monkeypatch.setattr(scipy.linalg, name, recorded)
    return calls


def test_a_large_machine_over_the_limit_is_refused_before_any_eigen_solution_with_a_low_bound(monkeypatch):
    model = _model()
    assert model.dofs.n == 4 * ROTORS + 6 == 306
    calls = _record_eigen_solutions(monkeypatch)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", LIMIT_MINUTES)
    with pytest.raises(InputError, match=rf"^duration = {DURATION!r} s: this simulation would take at least") as refused:
        rdm.simulate(model, DURATION, speed=SPEED, samples=SAMPLES)
    assert calls == []
    line = str(refused.value)
    assert "\n" not in line and f"{SAMPLES} output times" in line and "--allow-long" in line
    evaluations, each_us = map(float, re.search(r"at least ([0-9.e+]+) evaluations of ([0-9.e+]+) us", line).groups())
    assert evaluations == pytest.approx(SAMPLES * 14, rel=1e-2)
    monkeypatch.delenv("ROTORDYN_MODAL_MAX_CPU_MINUTES")
    start = time.process_time()
    with rdm.long_work_allowed():
        result = rdm.simulate(model, DURATION, speed=SPEED, samples=SAMPLES)
    assert len(result.time) == SAMPLES and np.isfinite(result.states).all()
    assert time.process_time() - start >= evaluations * each_us * 1e-6


def test_the_command_line_refuses_it_in_one_line_exit_2_without_output(monkeypatch, tmp_path, capsys):
    path, out = tmp_path / "chain.toml", tmp_path / "s.csv"
    path.write_text(chained_gear_toml(ROTORS, ROTORS), encoding="utf-8")
    calls = _record_eigen_solutions(monkeypatch)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", LIMIT_MINUTES)
    code = main(["simulate", str(path), "--speed", str(SPEED * 30 / np.pi), "--duration", repr(DURATION),
                 "--samples", str(SAMPLES), "--out", str(out)])
    lines = [line for line in capsys.readouterr().err.strip().splitlines() if line != COMPILE_NOTICE]
    assert code == 2 and not out.exists() and calls == []
    assert len(lines) == 1 and lines[0].startswith(f"rotordyn-modal simulate: error: --duration {DURATION!r}: "), lines
    assert "would take at least" in lines[0] and "--allow-long" in lines[0]


def test_a_slow_right_hand_side_is_timed_even_where_10_ms_an_evaluation_would_be_short(monkeypatch):
    """The check before the integration took every evaluation for at most 10 ms: 201 output times
    (2,814 evaluations) were let through under a limit of 45 s whatever they cost. An evaluation
    of 20 ms of CPU makes them 56 s."""
    system = system_arrays(_model())

    def slow(t, y, floats, ints):
        start = time.process_time()
        while time.process_time() - start < 0.02:
            pass
        return y

    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "0.75")
    kn = types.SimpleNamespace(rhs_flat=slow)
    extra = (0, 0.0, 0.0, 1.0)
    with pytest.raises(InputError, match=r"would take at least 5\d s of CPU time"):
        simulate_module._check_cpu_time(kn, system, extra, 1.0, 2 * np.pi, 201, 0.0, y0=np.zeros(2 * system.n_dof))
