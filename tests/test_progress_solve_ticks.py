"""The clock moves during every long eigen-solution (issue 27 §1.9, long work shows progress).

``scipy.linalg.eig``'s wrapper holds the GIL for the whole LAPACK call, so no other thread ran
during ``modes``' solve, frf's modal superposition or the modes at the stability thresholds: a
progress line's clock stood still (``modes`` at 500 geared rotors: 181 s without a word on a
terminal). And phases one after another, each shorter than a line's delay, showed nothing for
their sum (3.7 s at 200 geared rotors).

The solves here are real (a chain of geared rotors on bearings, about a second of LAPACK): a
watcher thread wakes every 20 ms and notes when it ran; the solve's window is read from the calls
on either side of it (the one-BLAS-thread limit entered just before, the round-off or the LU of
the eigenvectors just after), the same calls on main. Where the GIL is held, the watcher's
longest silence is the whole window.
"""

from __future__ import annotations

import io
import re
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal import _blas, _progress
from rotordyn_modal.analysis import _batches, _roots
from rotordyn_modal.cli import main

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: rotors of the chain (each on two bearings): 406 coordinates, 812 states, about 0.3 s of LAPACK
ROTORS = 100
SENSING = ('\n[[excitations]]\nname = "tap"\nposition = [0.0, 0.0, 0.4]\ndirection = [0.0, 0.0, 1.0]\n'
           '\n[[sensors]]\nname = "top"\nposition = [0.0, 0.0, 0.4]\ndirection = [0.0, 0.0, 1.0]\n')
#: the watcher's wait between two wake-ups [s]
WAKE = 0.02


@pytest.fixture(scope="module")
def chain_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("chain") / "chain.toml"
    path.write_text(chained_gear_toml(ROTORS, ROTORS) + SENSING)
    return path


class Window:
    """The times [s, monotonic] the state matrix's eigen-solution starts and ends: from the entry to
    the one-BLAS-thread limit of its size just before it to the first call after it
    (``_roots.round_off`` in ``modal``, ``scipy.linalg.lu_factor`` of the eigenvectors in frf)."""

    def __init__(self, monkeypatch, n_states, after):
        self.start = self.end = None
        original = _blas.one_blas_thread

        def limit(item_bytes):
            if item_bytes == 72 * n_states ** 2 and self.start is None:
                self.start = time.monotonic()
            return original(item_bytes)

        monkeypatch.setattr(_blas, "one_blas_thread", limit)
        monkeypatch.setattr(_batches, "one_blas_thread", limit)
        module, name = after
        following = getattr(module, name)

        def ended(*args, **kwargs):
            if self.start is not None and self.end is None:
                self.end = time.monotonic()
            return following(*args, **kwargs)

        monkeypatch.setattr(module, name, ended)

    def longest_silence(self, times):
        """The longest time [s] within the window with none of ``times`` (its edges included)."""
        inside = [t for t in times if self.start < t < self.end]
        edges = [self.start, *inside, self.end]
        return max(b - a for a, b in zip(edges, edges[1:]))


class Watcher:
    """A thread that notes the time each time it runs (every :data:`WAKE` seconds) while in use."""

    def __init__(self):
        self.times, self._stop = [], threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self):
        while not self._stop.wait(WAKE):
            self.times.append(time.monotonic())

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()


def n_states(path):
    return 2 * rdm.load_model(path).dofs.n


def test_a_thread_runs_during_modal_s_eigen_solution(chain_path, monkeypatch):
    """Another thread keeps running while ``modal``'s state matrix is solved (scipy's wrapper held
    the GIL: the watcher stood for the whole solve)."""
    window = Window(monkeypatch, n_states(chain_path), (_roots, "round_off"))
    model = rdm.load_model(chain_path)
    with Watcher() as watcher:
        rdm.modal(model, 300.0)
    solve = window.end - window.start
    assert solve > 10 * WAKE, solve                          # a solve long enough to tell
    assert window.longest_silence(watcher.times) < 0.5 * solve, (window.longest_silence(watcher.times), solve)


def test_a_thread_runs_during_frf_s_modal_superposition(chain_path, monkeypatch):
    """The same for frf's modal superposition's eigen-solution."""
    window = Window(monkeypatch, n_states(chain_path), (scipy.linalg, "lu_factor"))
    model = rdm.load_model(chain_path)
    with Watcher() as watcher:
        result = rdm.frf(model, 300.0, np.linspace(1.0, 50.0, 3))
    assert result.engine == "modal"
    solve = window.end - window.start
    assert solve > 10 * WAKE, solve
    assert window.longest_silence(watcher.times) < 0.5 * solve, (window.longest_silence(watcher.times), solve)


class Terminal(io.StringIO):
    """A stream that says it is a terminal, noting when each write came."""

    def __init__(self):
        super().__init__()
        self.times = []

    def isatty(self):
        return True

    def write(self, text):
        self.times.append(time.monotonic())
        return super().write(text)


@pytest.fixture
def quick_clock(monkeypatch):
    monkeypatch.setattr(_progress, "TICK_SECONDS", 0.05)
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.2)


def test_modes_on_a_terminal_draws_its_line_during_the_solve(chain_path, monkeypatch, tmp_path, quick_clock):
    """``modes`` on a terminal names its solve on one line whose clock is drawn again all through
    LAPACK's call (it showed nothing from its start to its table; with the line alone, the
    GIL held, the line stood during the call). The line shows at once here."""
    monkeypatch.setattr(_progress, "PHASE_DELAY", 0.0)
    window = Window(monkeypatch, n_states(chain_path), (_roots, "round_off"))
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["modes", str(chain_path), "--speed", "3000", "--out", str(tmp_path / "m.csv")]) == 0
    text = terminal.getvalue()
    assert re.search(r"modes: eigen-solution and shapes: \[00:0\d\]", text), text
    solve = window.end - window.start
    assert solve > 3 * _progress.TICK_SECONDS, solve        # several of the clock's ticks
    assert window.longest_silence(terminal.times) < 0.5 * solve, (window.longest_silence(terminal.times), solve)


def test_phases_one_after_another_show_once_the_silence_is_as_long_as_the_delay(quick_clock):
    """Three phases of 0.8 delays each, after a bar: the terminal stays silent at most about one
    delay (and one tick), not the 2.4 delays of their sum."""
    terminal = Terminal()
    bar = _progress.tqdm(total=1, file=terminal, desc="sweep")
    bar.update(1)
    bar.close()
    for name in ("tracking", "whirl", "thresholds"):
        with _progress.phase(True, name, file=terminal):
            time.sleep(0.8 * _progress.PHASE_DELAY)
    times = terminal.times + [time.monotonic()]
    silence = max(b - a for a, b in zip(times, times[1:]))
    assert silence < _progress.PHASE_DELAY + _progress.TICK_SECONDS, (silence, terminal.getvalue())
    assert "whirl: [" in terminal.getvalue() or "thresholds: [" in terminal.getvalue()


def test_a_phase_after_a_long_pause_waits_its_whole_delay(quick_clock):
    """A phase that does not follow other work at once (the last line ended more than a delay ago)
    keeps its whole delay: work shorter than it shows nothing."""
    terminal = Terminal()
    with _progress.phase(True, "first", file=terminal):
        pass
    time.sleep(1.5 * _progress.PHASE_DELAY)
    with _progress.phase(True, "short", file=terminal):
        time.sleep(0.5 * _progress.PHASE_DELAY)
    assert "short" not in terminal.getvalue()


@pytest.mark.parametrize("name", ["gear_machine", "compressor_rotor", "rubber_mounts", "flexible_pump_on_mounts"])
def test_the_eigen_solution_gives_scipy_s_bits(name):
    """``_eigensolve.eig`` returns what ``scipy.linalg.eig`` returns, bit for bit (the same LAPACK,
    workspace and packing of complex vectors), on the examples' state matrices and on a chain's
    (large enough for LAPACK's blocked steps), both with one BLAS thread as the analyses run."""
    from rotordyn_modal.analysis import _eigensolve
    from rotordyn_modal.linear_system import speed_linear_form

    matrix = speed_linear_form(rdm.load_model(EXAMPLES / f"{name}.toml")).at(314.0)
    with _blas.one_blas_thread(72 * matrix.shape[0] ** 2 + _blas.BLAS_THREADED_BYTES):
        expected, computed = scipy.linalg.eig(matrix), _eigensolve.eig(matrix)
    for want, got in zip(expected, computed):
        assert want.dtype == got.dtype and want.shape == got.shape and want.tobytes() == got.tobytes()


def test_the_eigen_solution_gives_scipy_s_bits_on_a_large_matrix_and_a_real_spectrum():
    from rotordyn_modal.analysis import _eigensolve

    rng = np.random.default_rng(27)
    symmetric = rng.standard_normal((40, 40))
    for matrix in (rng.standard_normal((400, 400)), symmetric + symmetric.T):
        with _blas.one_blas_thread(72 * matrix.shape[0] ** 2):
            expected, computed = scipy.linalg.eig(matrix), _eigensolve.eig(matrix)
        for want, got in zip(expected, computed):
            assert want.dtype == got.dtype and want.tobytes() == got.tobytes()
    assert computed[1].dtype == float                        # every root real: real vectors, as scipy's
