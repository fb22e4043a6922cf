"""The estimate of a dense eigen-solution's CPU time (analysis/_cost.py) and the announcements and
refusals that read it (issue 27, section 1.9: machines of 2,000 coordinates are refused before
the work with the estimate, or announced).

The estimate's accuracy is measured (``benchmarks/bench_cost_estimate.py``, the table in
benchmarks/README.md), never asserted here: a shared machine's times vary. What is asserted is
its logic, each against a closed form of a timing the test sets itself:

- one solution with vectors is a timed solution of ``min(n, 500)`` states scaled by the cube of
  the size (was: an eighth of the size scaled by ``n ** 2.7``), the timing the shortest of three;
  the eigenvalues alone are one fixed share of it;
- the dense solves run with one BLAS thread, as the estimate times them (``modes`` ran
  ``scipy.linalg.eig`` with OpenBLAS's own threads: 6-20 times the CPU time on a shared machine,
  the "8x" a factor of ``cli/modes.py`` had made up for);
- ``campbell``, ``critical-speeds``, ``stability`` and ``modes`` refuse exactly where the
  estimate crosses the limit (``ROTORDYN_MODAL_MAX_CPU_MINUTES`` set around it), in one line that
  names the estimate and ``--allow-long``; ``modes`` announces a solve exactly where its estimate
  crosses the notice's threshold.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _work
from rotordyn_modal.cli import main

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

#: the CPU seconds the tests say a solution of the fan's 32 states takes (below the pessimistic
#: bound 1e-8 n^3 of the sizes the quick bound sees, so the bound never passes what is refused)
ONE = 1e-4


@pytest.fixture(autouse=True)
def default_limit(monkeypatch):
    monkeypatch.delenv(_work.ENVIRONMENT, raising=False)


@pytest.fixture
def fan(examples_dir):
    return examples_dir / "fan_on_bearings.toml"


def _timing(monkeypatch, seconds=ONE):
    """Every calibration timed at ``seconds``, whatever its size; the sizes asked, recorded."""
    asked = []
    monkeypatch.setattr(_work, "_timed_eig", lambda size: asked.append(size) or seconds)
    return asked


def _limit(monkeypatch, seconds):
    monkeypatch.setenv(_work.ENVIRONMENT, repr(seconds / 60.0))


# ----------------------------------------------------------------------------- the estimate
def test_an_eigen_solution_scales_as_the_cube_of_the_size(monkeypatch):
    asked = _timing(monkeypatch, 2.0)
    size = _cost._CALIBRATION_STATES
    assert 400 <= size <= 1000 and size & (size - 1)              # no power of two (cache conflicts)
    assert _work.eig_seconds(4012) == pytest.approx(2.0 * (4012 / size) ** 3)
    assert _work.eig_seconds(2048) / _work.eig_seconds(1024) == pytest.approx(8.0)
    assert _work.eig_seconds(300) == pytest.approx(2.0)                       # timed at its own size
    assert asked == [size, size, size, 300]


def test_the_eigenvalues_alone_are_one_share_of_a_solution_with_vectors(monkeypatch):
    """geev without vectors skips the Schur vectors and the back-substitution; both share the
    Hessenberg reduction: between the operations' count's 0.4 and 1, the same share at every size."""
    timed = lambda size: 1e-9 * size ** 2.5                                  # noqa: E731
    shares = [_cost.eigvals_seconds(n, timed) / _cost.eig_seconds(n, timed) for n in (40, 500, 2000, 8000)]
    assert shares == pytest.approx([shares[0]] * 4)
    assert 0.4 < shares[0] < 1.0
    # the critical speeds' mode numbers are eigenvalues alone
    model = rdm.load_model(os.path.join(os.path.dirname(__file__), "..", "examples", "fan_on_bearings.toml"))
    _timing(monkeypatch, 1.0)
    work = _work.estimate(model, rdm.rpm(np.linspace(0, 9000, 41)), (1, 2), numbers=True)
    assert work.numbers_seconds == pytest.approx(work.crossings * _work._NUMBERS_SHARE * _cost.eigvals_seconds(
        32, lambda size: 1.0))


def test_the_calibration_is_the_shortest_of_repeated_timings(monkeypatch):
    """A shared machine's single timing of a small matrix varied ten-fold: the shortest is the work."""
    clock = iter([0.0, 5.0, 10.0, 10.1, 20.0, 23.0, 30.0, 31.0])              # durations 5, 0.1, 3, 1
    monkeypatch.setattr(_cost.time, "process_time", lambda: next(clock))
    _cost._timed_eig.cache_clear()
    try:
        assert _cost._timed_eig(17) == pytest.approx(0.1)
    finally:
        _cost._timed_eig.cache_clear()


def _blas_threads():
    from threadpoolctl import threadpool_info

    return max(library["num_threads"] for library in threadpool_info() if library["user_api"] == "blas")


def test_the_dense_solves_run_with_one_blas_thread_as_estimated(examples_dir, monkeypatch):
    """``modal`` (``modes``) and a sweep of one speed ran their geev with OpenBLAS's own threads."""
    pytest.importorskip("threadpoolctl")
    import scipy.linalg

    from rotordyn_modal.analysis import _eigensolve

    if _blas_threads() < 2:
        pytest.skip("BLAS runs one thread here anyway")
    seen = []
    for module, name in ((scipy.linalg, "eig"), (np.linalg, "eig")):
        original = getattr(module, name)

        def spy(*args, _original=original, **kwargs):
            seen.append(_blas_threads())
            return _original(*args, **kwargs)

        monkeypatch.setattr(module, name, spy)
    dgeev = _eigensolve._dgeev()                                             # scipy's LAPACK, the GIL released
    monkeypatch.setattr(_eigensolve, "_dgeev", lambda: lambda *args: spy(*args, _original=dgeev))
    model = rdm.load_model(examples_dir / "compressor_rotor.toml")           # 106 states
    rdm.modal(model, 300.0)
    _eigensolve.upper_shapes(rdm.linear_system.speed_linear_form(model).at(np.array([300.0])), model.dofs.n)
    assert seen == [1, 1]


def test_the_brackets_swept_again_are_counted_in_the_sweep(tmp_path, monkeypatch):
    """A bracket crowded with crossings (at least 14) is swept again at 9 speeds by the critical
    speeds: 7 more solutions of every root each, which the estimate had left out (a 500-rotor
    chain at 11 speeds: 11 counted, 67 solved). Counted here bracket by bracket, line by line,
    frequency by frequency."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from test_large_machine_cli import chained_gear_toml

    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(30, 30))                   # 126 coordinates
    model = rdm.load_model(path)
    speeds = rdm.rpm(np.linspace(0.0, 3000.0, 6))
    frequencies = _work._undamped_frequencies(model, float(speeds[3]))
    slopes = _work._line_slopes(model, (1.0,))
    crowded = 0
    for low, high in zip(speeds[:-1], speeds[1:]):
        inside = sum(1 for s in slopes for w in frequencies if w > 0 and s * low <= w < s * high)
        crowded += inside >= 14
    assert 0 < crowded < 5                                       # some brackets crowded, not all
    _timing(monkeypatch, 1.0)
    work = _work.estimate(model, speeds, (1.0,))
    assert work.swept_again == 7 * crowded
    assert work.sweep_seconds == pytest.approx((6 + 7 * crowded) * 1.0)
    assert f"6 eigen-solutions of 252 states and {7 * crowded} more in brackets swept again" in work.text()
    assert _work.estimate(model, speeds, (1.0,), critical=False).swept_again == 0


# ------------------------------------------------------------- refusals where the estimate crosses
def _exit(capsys, argv):
    code = main([str(a) for a in argv])
    return code, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("command", [["campbell", "--no-critical"], ["stability"]])
def test_a_sweep_is_refused_exactly_where_its_estimate_crosses_the_limit(fan, capsys, monkeypatch, tmp_path,
                                                                        command):
    """31 speeds of the fan's 32 states, one solution each at ONE s: 31 ONE."""
    _timing(monkeypatch)
    estimate = 31 * ONE
    argv = [command[0], fan, "--speeds", "0:9000:31", *command[1:], "--out", tmp_path / "out.csv"]
    _limit(monkeypatch, 0.98 * estimate)
    code, err = _exit(capsys, argv)
    assert code == 2 and len(err) == 1, err
    assert f"about {_cost.duration(estimate)} of CPU time (31 eigen-solutions of 32 states" in err[0]
    assert "--allow-long" in err[0] and _work.ENVIRONMENT in err[0]
    assert "--lowest N" in err[0] and "leave out the critical speeds" not in err[0]   # --no-critical is given
    assert _exit(capsys, argv + ["--allow-long"])[0] == 0
    _limit(monkeypatch, 1.02 * estimate)
    code, err = _exit(capsys, argv)
    assert code == 0, err


def test_critical_speeds_are_refused_exactly_where_their_estimate_crosses_the_limit(fan, capsys, monkeypatch,
                                                                                  tmp_path):
    """The sweep, the crossings' refinement (a dense pencil factored: 1/75 of a solution, and all
    its roots' eigenvalues at half of them) and their mode numbers (eigenvalues alone at half of
    them), from the crossings counted."""
    _timing(monkeypatch)
    model = rdm.load_model(fan)
    speeds = rdm.rpm(np.linspace(0, 9000, 31))
    crossings = _work.expected_crossings(model, speeds, (1.0,))
    assert crossings > 0
    estimate = (31 * ONE + crossings * (_work._COORDINATE_SECONDS * 16 + ONE / 75)
                + crossings * 0.5 * _cost.EIGVALS_SHARE * ONE          # every root a candidate (16 <= 96)
                + crossings * 0.5 * _cost.EIGVALS_SHARE * ONE)
    argv = ["critical-speeds", fan, "--speeds", "0:9000:31", "--out", tmp_path / "out.csv"]
    _limit(monkeypatch, 0.98 * estimate)
    code, err = _exit(capsys, argv)
    assert code == 2 and len(err) == 1, err
    assert f"about {_cost.duration(estimate)} of CPU time" in err[0] and "--allow-long" in err[0]
    _limit(monkeypatch, 1.02 * estimate)
    code, err = _exit(capsys, argv)
    assert code == 0, err


def test_modes_announces_and_refuses_exactly_where_its_estimate_crosses(fan, capsys, monkeypatch, tmp_path):
    """One solution of 32 states: ONE (no factor of its own: ``modal`` solves with one BLAS
    thread, as the estimate times it)."""
    from rotordyn_modal.cli import modes

    _timing(monkeypatch)
    argv = ["modes", fan, "--speed", "3000", "--out", tmp_path / "modes.csv"]
    monkeypatch.setattr(modes, "_NOTICE_SECONDS", 1.02 * ONE)
    code, err = _exit(capsys, argv)
    assert code == 0 and not any("eigen-solution" in line for line in err), err
    monkeypatch.setattr(modes, "_NOTICE_SECONDS", 0.98 * ONE)
    code, err = _exit(capsys, argv)
    assert code == 0 and any(f"one eigen-solution of 32 states (16 coordinates) with every root: about "
                             f"{_cost.duration(ONE)} of CPU time" in line for line in err), err
    _limit(monkeypatch, 0.98 * ONE)
    code, err = _exit(capsys, argv)
    assert code == 2 and len(err) == 1, err
    assert f"about {_cost.duration(ONE)} of CPU time (1 eigen-solution of 32 states" in err[0]
    assert "--allow-long" in err[0]
    _limit(monkeypatch, 1.02 * ONE)
    assert _exit(capsys, argv)[0] == 0
