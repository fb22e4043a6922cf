"""``simulate`` at scale, the rest (issue 27 §1.4, §1.9): signals on a large machine, the clocks of its
eigen-solutions.

- A real process on 150 geared rotors on bearings (606 coordinates) is stopped by SIGTERM or SIGHUP
  while scipy's DOP853 integrates: it must end within seconds with the documented exit code (128 +
  N), its one line, and no file in its output folder (the run at 500 rotors this stands for took
  about 50 s to reach the integrator).
- A signal while the output times' derived outputs are made (the compiled ``sample_outputs`` loop)
  ended the run with ``SystemError: CPUDispatcher(...) returned a result with an exception set``
  (exit 1) once the whole loop had run (tested in Python: a real process spends 3.5 times as long
  integrating as deriving the outputs, so a signal there costs a long run).
- The dense eigen-solutions a large machine may still need (the fastest natural frequency where its
  largest roots are all real; the modes an impulse excites where their bound is refused) let another
  thread run, so that a progress line's clock moves, and are phases of the progress.
"""

from __future__ import annotations

import importlib
import os
import signal
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from test_large_machine_cli import chained_gear_toml
from test_simulate_signals import PROMPT, RUNNER

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")
ROOT = Path(__file__).resolve().parent.parent

#: rotors of the large machine (all on bearings: 6 + 4 x 150 coordinates and the drive angle)
ROTORS = 150
#: an unbalance on the first rotor, so that DOP853 has a motion to follow (at rest it would step
#: over the whole interval at once)
UNBALANCE = '\n[[unbalances]]\nrotor = "r000"\namount = 1.0e-4\n'


def _signalled(tmp_path, signum, runner=RUNNER, marker="INTEGRATING", extra=(), text=UNBALANCE):
    """Run ``simulate`` on the large machine in a real process, send ``signum`` 0.5 s after it has
    printed ``marker``; (exit code, stderr, seconds from the signal to the exit, files left)."""
    model, out = tmp_path / "chain.toml", tmp_path / "out"
    model.write_text(chained_gear_toml(ROTORS, ROTORS) + text)
    out.mkdir()
    command = [sys.executable, "-c", runner, "simulate", str(model), "--speed", "3000", "--allow-long",
               "--out", str(out / "run.csv"), *extra]
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    process = subprocess.Popen(command, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True, env=env,
                               cwd=out)
    try:
        lines = []
        for line in process.stderr:       # the compile notice (empty numba cache) may come first
            lines.append(line.strip())
            if line.strip() == marker:
                break
        else:
            process.wait()
            pytest.fail(f"the simulation ended before {marker}: {lines}")
        time.sleep(0.5)
        assert process.poll() is None, "the run ended before the signal"
        process.send_signal(signum)
        sent = time.monotonic()
        try:
            process.wait(timeout=PROMPT)
        except subprocess.TimeoutExpired:
            pytest.fail(f"{signal.Signals(signum).name} ignored: still running {PROMPT:g} s later")
        return process.returncode, process.stderr.read(), time.monotonic() - sent, os.listdir(out)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        process.stderr.close()


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_signal_during_dop853_on_150_geared_rotors_ends_the_run_at_once_and_writes_nothing(tmp_path, signum):
    code, err, waited, left = _signalled(tmp_path, signum, extra=("--duration", "50", "--samples", "3"))
    assert code == 128 + signum, err
    assert err.strip().splitlines() == [f"rotordyn-modal simulate: terminated by {signal.Signals(signum).name}"]
    assert left == []
    assert waited < PROMPT


def _machine(rotors, text=""):
    return rdm.Model.from_dict(tomllib.loads(chained_gear_toml(rotors, rotors) + text), "chain.toml")


def test_the_derived_outputs_heed_a_raising_handler_at_once_and_keep_their_bits(monkeypatch):
    """A program's own SIGALRM handler that raises, 0.2 s into the derived outputs of 3,000 output
    times of 150 geared rotors (about 2.5 s of CPU in one compiled loop; the integration is replaced
    by the rest state, which costs 3.5 times as long): its exception comes out within a part of the
    loop. main: ``SystemError: CPUDispatcher(<function sample_outputs ...>) returned a result with an
    exception set``, after the whole loop (the command line's SIGTERM there: exit 1, "failed", where
    143 is documented). Made in parts, the outputs are the bits of one loop over all of them."""
    from rotordyn_modal.simulation._system import system_arrays

    model = _machine(ROTORS)
    system = system_arrays(model)
    kn = simulate_module.kernels("numba")
    extra = (1, 0.0, 0.0, 1.0)
    n, count = system.n_dof, 3000
    states = np.zeros((count, 2 * n))
    states[:, -1] = 314.0
    states[:, :n] = np.random.default_rng(3).normal(size=(count, n)) * 1e-5
    times = np.linspace(0.0, 1.0, count)
    kn.sample_outputs(times[:2], states[:2], *system.kernel_arguments(), *extra)    # compiled here

    class Late(Exception):
        pass

    def late(signum, frame):
        raise Late()

    started, loop = [], kn.sample_outputs

    def timed(*args):
        if not started:                                      # 0.2 s from the loop's start
            started.append(time.process_time())
            signal.setitimer(signal.ITIMER_REAL, 0.2)
        return loop(*args)

    monkeypatch.setattr(simulate_module, "_integrate", lambda kn, system, extra, y0, times, *args:
                        np.tile(y0, (len(times), 1)))
    monkeypatch.setattr(kn, "sample_outputs", timed)
    previous = signal.signal(signal.SIGALRM, late)
    try:
        with pytest.raises(Late), rdm.long_work_allowed():
            rdm.simulate(model, 1.0, 314.0, samples=count)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)
    assert started and time.process_time() - started[0] < 1.0

    few = slice(0, 200)
    whole = kn.sample_outputs(times[few], states[few], *system.kernel_arguments(), *extra)
    parted = simulate_module._sampled_outputs(kn, times[few], states[few], system.kernel_arguments() + extra)
    assert all(np.array_equal(a, b) for a, b in zip(whole, parted))


def _ticks_during(call, *arguments):
    """(result of ``call(*arguments)``, how often a thread waking every 5 ms ran meanwhile, wall s)."""
    ticks, stop = [0], threading.Event()

    def count():
        while not stop.wait(0.005):
            ticks[0] += 1

    thread = threading.Thread(target=count, daemon=True)
    thread.start()
    start = time.monotonic()
    try:
        result = call(*arguments)
    finally:
        wall = time.monotonic() - start
        stop.set()
        thread.join()
    return result, ticks[0], wall


def test_the_dense_eigenvalues_of_the_fastest_rate_let_a_clock_run(monkeypatch):
    """scipy's ``eigvals`` held the GIL: a thread never ran during the dense eigenvalues (800 states
    whose largest roots are all real, one pair -1 +- 5i among them), so no progress clock moved."""
    rng = np.random.default_rng(5)
    diagonal = np.zeros((800, 800))
    diagonal[:798, :798] = np.diag(np.concatenate([-np.linspace(100.0, 1000.0, 500), -np.linspace(1.0, 2.0, 298)]))
    diagonal[798:, 798:] = [[-1.0, 5.0], [-5.0, -1.0]]
    basis, _ = np.linalg.qr(rng.normal(size=(800, 800)))
    matrix = basis @ diagonal @ basis.T
    monkeypatch.setattr(simulate_module, "_KRYLOV_DOF", 10**9)     # the dense route at once
    rate, ticks, wall = _ticks_during(simulate_module._largest_frequency, matrix)
    assert rate == pytest.approx(5.0, rel=1e-9)
    assert ticks >= 10, f"{ticks} ticks in {wall:.2f} s"              # main: 0 or 1


def test_the_modes_an_impulse_excites_are_a_phase_of_the_progress_and_announced(monkeypatch, capsys):
    """The modes an impulse excites (every root and shape of the state matrix: 142 s at 4,012 states)
    are made in a phase whose clock runs, and announced on stderr from 1,000 coordinates (here made
    to announce at any size). main: no phase, no line."""
    from rotordyn_modal import _progress

    shown, original = [], _progress.phase

    def recorded(enabled, description, *args, **kwargs):
        shown.append((enabled, description))
        return original(False, description, *args, **kwargs)

    monkeypatch.setattr(_progress, "phase", recorded)
    monkeypatch.setattr(simulate_module, "_ANNOUNCED_DOF", 1)
    model = rdm.load_model(ROOT / "examples" / "motor_pump_on_mounts.toml")
    rdm.simulate(model, 0.002, 157.0, impulse="hub-tap-y", samples=5, progress=True)
    assert (True, "simulate: the modes the impulse excites, for the CPU estimate") in shown
    err = capsys.readouterr().err
    assert err.count(simulate_module.STEPS_NOTICE.format(2 * model.dofs.n)) == 1


def test_where_arpack_fails_the_bounds_come_from_the_balanced_norm_not_a_dense_solve(monkeypatch):
    """ARPACK not converging: the bounds of the impulse's steps and of the natural frequencies (main:
    None, so every root and shape was made at once: 142 s at 4,012 states) are the norm of the
    balanced state matrix, an upper bound of every ``|lambda|``: checked against the dense roots."""
    import scipy.sparse.linalg

    from rotordyn_modal.analysis import _eigensolve
    from rotordyn_modal.linear_system import speed_linear_form

    model = rdm.load_model(ROOT / "examples" / "motor_pump_on_mounts.toml")
    roots = np.linalg.eigvals(speed_linear_form(model).at(157.0))
    rest = np.linalg.eigvals(speed_linear_form(model).at(0.0))

    def fails(*args, **kwargs):
        raise scipy.sparse.linalg.ArpackNoConvergence("no convergence", np.zeros(0), np.zeros((0, 0)))

    solved = []
    monkeypatch.setattr(scipy.sparse.linalg, "eigs", fails)
    monkeypatch.setattr(_eigensolve, "eig", lambda *args: solved.append(1))
    steps = simulate_module._most_steps(model, 157.0, 0.5, "hub-tap-y")
    rate = simulate_module._most_rate(model, 157.0, None)
    assert solved == []
    assert np.isfinite(steps) and steps >= 0.5 * np.abs(roots).max() / simulate_module._STEP_REACH
    assert np.isfinite(rate) and rate >= np.abs(rest.imag).max()
    assert steps <= 3 * 0.5 * np.abs(roots).max() / simulate_module._STEP_REACH   # a bound of use
