"""``simulate``'s CPU estimate (issue 27): a low bound for both backends, counting the integrator's
steps for the fastest motion an impulse excites, and a refusal over the limit in one line.

The machine: a casing of inertia [10, 10, 1.1e-11] kg m^2 on a 10 kg rotor in bearings of 1e6 N/m
(``tests/degenerate_models.py``): its roll about z is a 13.7 MHz mode, which an impulse of a force
along y at x = 0.2 m (a moment about z) excites. With 3 output times the estimate counted 3 x 14
evaluations (compiled) or nothing (numpy); DOP853 cannot step farther than its stability region
(``h |lambda| <= 6.77``) along that motion, so it takes at least ``duration |lambda| / 13.54`` steps
of 12 evaluations (the bound with a margin of 2)."""

from __future__ import annotations

import re
import time
import tomllib

import numpy as np
import pytest

import rotordyn_modal as rdm
from degenerate_models import variant
from rotordyn_modal.cli import main
from rotordyn_modal.errors import InputError

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

KICK = '[[excitations]]\nname = "kick"\nposition = [0.2, 0.0, 0.0]\ndirection = [0.0, 1.0, 0.0]\n'
#: (duration [s], limit [CPU minutes]) of each backend's run: about a second of CPU each
RUNS = {"numba": (1e-4, "1e-6"), "numpy": (3e-6, "1e-6")}
SPEED = 100.0      # rad/s


def _text():
    return variant(stator_mass="100.0", rotor_mass="10.0", stator_inertia="[10.0, 10.0, 1.1e-11]") + KICK


def _model():
    return rdm.Model.from_dict(tomllib.loads(_text()), source="stiff.toml")


def _fewest_evaluations(model, duration):
    """12 evaluations a step, ``duration |lambda| / (2 x 6.77)`` steps for the fastest root of
    the linear model (the impulse excites it: checked by the refusal naming it)."""
    fastest = np.abs(rdm.modal(model, SPEED).eigenvalues).max()
    assert fastest / (2 * np.pi) == pytest.approx(1.366e7, rel=1e-3)
    return 12 * duration * fastest / (2 * 6.77)


@pytest.mark.parametrize("backend", list(RUNS))
def test_the_estimate_counts_the_steps_of_the_excited_stiff_mode_and_is_a_low_bound(backend, monkeypatch):
    duration, limit = RUNS[backend]
    model = _model()
    arguments = dict(speed=SPEED, impulse="kick", impulse_size=1e-18, samples=3, backend=backend)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", limit)
    with pytest.raises(InputError, match=rf"^duration = {duration!r} s: this simulation would take at least") as refused:
        rdm.simulate(model, duration, **arguments)
    line = str(refused.value)
    assert "\n" not in line and "3 output times" in line and "--allow-long" in line
    steps = float(re.search(r"at least ([0-9.e+]+) integrator steps for the fastest mode the impulse excites", line)[1])
    evaluations = float(re.search(r"at least ([0-9.e+]+) evaluations of", line)[1])
    fewest = _fewest_evaluations(model, duration)
    assert steps == pytest.approx(fewest / 12, rel=2e-3) and evaluations == pytest.approx(fewest, rel=2e-3)
    estimate = float(re.search(r"at least ([0-9.e+-]+) s of CPU", line)[1])
    start = time.process_time()
    with rdm.long_work_allowed():
        result = rdm.simulate(model, duration, **arguments)
    assert np.isfinite(result.states).all()
    assert time.process_time() - start >= estimate


@pytest.mark.parametrize("backend", list(RUNS))
def test_the_command_line_refuses_that_run_in_one_line_before_any_work(backend, tmp_path, monkeypatch, capsys):
    """One line on stderr, exit 2, no output file; the compiled path refuses before its kernel's
    compilation (no compile notice in a fresh checkout)."""
    duration, limit = RUNS[backend]
    path, out = tmp_path / "stiff.toml", tmp_path / "s.csv"
    path.write_text(_text(), encoding="utf-8")
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", limit)
    code = main(["simulate", str(path), "--speed", str(SPEED * 30 / np.pi), "--duration", repr(duration),
                 "--excitation", "kick", "--impulse-size", "1e-18", "--samples", "3", "--backend", backend,
                 "--out", str(out)])
    # the model's own conditioning warning (its casing's 1.1e-11 kg m^2 roll inertia is the stiff
    # mode: docs/theory.md section 8, the spread of masses) is not part of the refusal
    lines = [line for line in capsys.readouterr().err.strip().splitlines()
             if "times the scale of what it holds" not in line]
    assert code == 2 and not out.exists()
    assert len(lines) == 1 and lines[0].startswith(f"rotordyn-modal simulate: error: --duration {duration!r}: "), lines
    assert "integrator steps for the fastest mode the impulse excites" in lines[0] and "--allow-long" in lines[0]


def test_an_impulse_of_a_mode_that_is_not_stiff_adds_no_steps(monkeypatch):
    """The hammer of ``degenerate_models`` (a force along -z at z = 0.1 m: a moment about y) leaves
    the roll about z at rest: the steps come from the slower modes it excites, so the estimate
    of a 0.1 ms run is far below the stiff mode's (nothing is refused under a limit of 6 s)."""
    model = _model()
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "0.1")
    from rotordyn_modal.simulation.simulate import _fewest_steps

    hammer, kick = _fewest_steps(model, SPEED, 1e-4, "hammer"), _fewest_steps(model, SPEED, 1e-4, "kick")
    assert kick == pytest.approx(_fewest_evaluations(model, 1e-4) / 12, rel=2e-3)
    assert 0 < hammer < 1e-3 * kick
    assert _fewest_steps(model, SPEED, 1e-4, None) == 0.0


def test_the_numpy_path_counts_its_output_times_and_errs_low(examples_dir, monkeypatch):
    """Without an impulse the numpy path's output times cost no evaluation of the integrator
    (``solve_ivp`` interpolates them) but each one's derived outputs (forces, energies: an
    assembly and a solve in Python): 3,001 of them over 0.02 s of the spring block are refused
    under a limit of 0.06 s, and the run's CPU time inside ``long_work_allowed`` is at least the
    estimate. (The estimate had no numpy path: nothing was refused.)"""
    model = rdm.load_model(examples_dir / "spring_block_rotor.toml")
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-3")
    with pytest.raises(InputError, match=r"^duration = 0.02 s: this simulation would take at least") as refused:
        rdm.simulate(model, 0.02, speed=50.0, samples=3001, backend="numpy")
    line = str(refused.value)
    assert re.search(r"3,001 output times of [0-9.e+]+ us each", line) and "integrator steps" not in line
    estimate = float(re.search(r"at least ([0-9.e+-]+) s of CPU", line)[1])
    start = time.process_time()
    with rdm.long_work_allowed():
        result = rdm.simulate(model, 0.02, speed=50.0, samples=3001, backend="numpy")
    assert len(result.time) == 3001
    assert time.process_time() - start >= estimate
