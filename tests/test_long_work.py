"""Work too long to do is refused before it starts, with its estimate (analysis/_work.py).

``campbell``, ``critical-speeds`` and ``stability`` solve every root at every speed; a machine of
500 geared rotors on bearings (2,006 coordinates) would take about ten hours of CPU time for the
critical speeds of 11 speeds (a million crossings of its 999 order lines). Such work is refused
before the first eigen-solution, in one line that gives the estimate; the bundled examples are
passed without any measurement. The estimate's accuracy is measured
(benchmarks/bench_cost_estimate.py), not asserted here (a shared machine's times vary); what is
asserted is the estimator's inputs: eigen-solutions timed at the size (at most 500 states) and
scaled by its cube (tests/test_cost_estimate.py), one per speed and value, and the crossings
counted from the undamped frequencies and the order lines.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _cost, _work
from rotordyn_modal.cli import main
from rotordyn_modal.cli.campbell import NO_CRITICAL_ADVICE
from rotordyn_modal.errors import InputError

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402


@pytest.fixture(autouse=True)
def default_limit(monkeypatch):
    monkeypatch.delenv(_work.ENVIRONMENT, raising=False)


def _refusal(capsys, argv):
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2, err
    assert len(err) == 1, err
    return err[0]


def test_500_geared_rotors_on_bearings_are_refused_before_the_work_with_the_estimate(tmp_path, capsys, no_solutions):
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(500, 500))
    line = _refusal(capsys, ["campbell", path, "--speeds", "0:3000:11"])
    assert line.startswith(f"rotordyn-modal campbell: error: {path}: this analysis of 2,006 coordinates would take")
    assert "2,006 coordinates" in line and "11 eigen-solutions of 4,012 states" in line
    hours = float(line.split("would take about ")[1].split(" h of CPU time")[0])
    assert hours > 1.0                                          # far above the 30 minutes
    crossings = int(line.split("about ")[2].split(" crossings")[0].replace(",", ""))
    # 2,006 modes below the 499 gear meshes' lines (17-29 teeth) at 3000 rpm, the lowest ones
    # also below some of the 500 rotors' spin lines: between the meshes' share and every pair
    assert 2006 * 499 * 0.9 < crossings < 2006 * 999
    assert "--lowest N" in line and "--allow-long" in line and _work.ENVIRONMENT in line


def test_a_stability_map_counts_every_value(tmp_path, capsys, no_solutions, monkeypatch):
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1e-3)     # timed at its own 32 states
    path = Path(__file__).resolve().parent.parent / "examples" / "fan_on_bearings.toml"
    monkeypatch.setenv(_work.ENVIRONMENT, "1e-6")
    line = _refusal(capsys, ["stability", path, "--speeds", "0:9000:31", "--vary", "suspensions.mount-FL.damping",
                             "--scale", "0.5:2:4"])
    assert "124 eigen-solutions of 32 states" in line and "fewer values" in line


def test_the_examples_pass_without_a_measurement(examples_dir, capsys, monkeypatch):
    def measured(size):
        raise AssertionError("a small model was timed")

    monkeypatch.setattr(_work, "_timed_eig", measured)
    code = main(["campbell", str(examples_dir / "fan_on_bearings.toml"), "--speeds", "0:9000:31", "--orders", "1,2",
                 "--out", "-"])
    assert code == 0, capsys.readouterr().err


def test_a_lower_limit_refuses_and_allow_long_runs_it_anyway(examples_dir, capsys, monkeypatch):
    path = examples_dir / "gear_machine.toml"
    monkeypatch.setenv(_work.ENVIRONMENT, "1e-9")
    line = _refusal(capsys, ["critical-speeds", path, "--speeds", "0:3000:31"])
    assert "of CPU time" in line and "--allow-long" in line
    assert main(["critical-speeds", str(path), "--speeds", "0:3000:31", "--allow-long", "--out", "-"]) == 0
    monkeypatch.setenv(_work.ENVIRONMENT, "inf")
    assert main(["critical-speeds", str(path), "--speeds", "0:3000:31", "--out", "-"]) == 0
    capsys.readouterr()
    monkeypatch.setenv(_work.ENVIRONMENT, "soon")
    assert _refusal(capsys, ["campbell", path, "--speeds", "0:3000:31"]).endswith(
        f"{_work.ENVIRONMENT}='soon': expected a number of CPU minutes > 0 (or inf)")


@pytest.mark.parametrize("text", ["lots", "0", "1.5", "inf"])
def test_a_thread_count_that_is_no_whole_number_is_refused_in_one_line(examples_dir, capsys, monkeypatch, text):
    """ROTORDYN_MODAL_THREADS (the eigen-solutions' threads) is read like the other limits: a value
    that is no whole number >= 1 is named in one line, exit 2 (was ValueError, exit 1)."""
    monkeypatch.setenv("ROTORDYN_MODAL_THREADS", text)
    assert _refusal(capsys, ["campbell", examples_dir / "fan_on_bearings.toml", "--speeds", "0:3000:31"]).endswith(
        f"ROTORDYN_MODAL_THREADS={text!r}: expected a whole number of threads >= 1")


def test_an_eigen_solution_is_timed_at_its_size_or_the_calibration_size_and_scaled(monkeypatch):
    asked = []
    monkeypatch.setattr(_work, "_timed_eig", lambda size: asked.append(size) or 2.0)
    assert _work.eig_seconds(4012) == pytest.approx(2.0 * (4012 / _cost._CALIBRATION_STATES) ** 3)
    assert _work.eig_seconds(100) == pytest.approx(2.0)
    assert asked == [_cost._CALIBRATION_STATES, 100]              # dense eigen-solutions: n^3 work


def test_the_work_is_one_solution_per_speed_and_the_crossings_cost_per_coordinate(examples_dir, monkeypatch):
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1.0)
    model = rdm.load_model(examples_dir / "fan_on_bearings.toml")
    speeds = rdm.rpm(np.linspace(0, 9000, 41))
    work = _work.estimate(model, speeds, (1, 2), critical=True, numbers=True)
    eig = 1.0                                                      # 32 states: timed at that size
    assert (work.n_dof, work.n_states, work.solutions) == (16, 32, 41)
    assert work.sweep_seconds == pytest.approx(41 * eig)
    per = _work._COORDINATE_SECONDS * 16 + _work._FACTOR_SHARE * eig          # a dense pencil (16 < SPARSE_DOF)
    per += _work._DENSE_ROOTS * _cost.EIGVALS_SHARE * eig          # every root a candidate (16 <= 96)
    assert work.crossing_seconds == pytest.approx(work.crossings * per)
    assert work.numbers_seconds == pytest.approx(work.crossings * _work._NUMBERS_SHARE * _cost.EIGVALS_SHARE * eig)
    assert _work.estimate(model, speeds, (1, 2), critical=False).crossings == 0


def test_the_crossings_expected_are_those_of_the_undamped_frequencies_with_the_order_lines(examples_dir):
    """Counted independently: each undamped frequency at rest (generalized eigenvalues of K, M)
    against each source's order line over the range, on both sides of zero."""
    import scipy.linalg

    model = rdm.load_model(examples_dir / "gear_machine.toml")
    M, _, _, K = model.matrices()
    omega = np.sqrt(np.clip(scipy.linalg.eigh(K, M, eigvals_only=True), 0, None))
    omega = omega[omega > 0]
    sources = rdm.excitation_sources(model)
    orders = (1.0, 2.0)
    lines = [o * m for o in orders for m in sources.multipliers]
    top = rdm.rpm(3000.0)
    expected = sum(int(((w < s * top)).sum()) for s in lines for w in [omega])
    assert _work.expected_crossings(model, rdm.rpm(np.linspace(0, 3000, 31)), orders) == expected
    assert _work.expected_crossings(model, rdm.rpm(np.linspace(-3000, 3000, 31)), orders) == 2 * expected
    low = rdm.rpm(1000.0)
    within = sum(int(((w >= s * low) & (w < s * top)).sum()) for s in lines for w in [omega])
    assert _work.expected_crossings(model, rdm.rpm(np.linspace(1000, 3000, 31)), orders) == within
    # and the sweep finds about as many (the gyroscopic terms move the frequencies a little)
    found = len(rdm.campbell(model, rdm.rpm(np.linspace(0, 3000, 61)), orders=orders).critical)
    assert 0.5 * found <= expected <= 2 * found
    assert math.isfinite(_work.limit_seconds())


@pytest.mark.filterwarnings("ignore:lowest modes")
def test_python_and_the_command_line_allow_long_work_by_one_switch(examples_dir, capsys, monkeypatch):
    """Both checks of the CPU time, the sweep's estimate (the command line's, ``analysis/_work.py``)
    and the lowest modes' full-solve fallback (``analysis/_lowest.py``), refuse the same work with
    the same line from Python and from the command line, and both run it inside
    ``rdm.long_work_allowed()`` as with ``--allow-long`` (was: the sweep's check read only the
    command line's option)."""
    from rotordyn_modal.analysis import _lowest

    # axisymmetric: the cut inside its double root at rest is left to the full solve, as before that
    # cut got its own refinement (tests/test_lowest_cut_in_double_root.py; as test_lowest_fallback_limits)
    monkeypatch.setattr(_lowest, "_cut_in_a_multiple_root", lambda *args, **kwargs: None)
    path = str(examples_dir / "compressor_rotor.toml")
    model, speeds = rdm.load_model(path), np.array([0.0, 500.0])
    command = ["campbell", path, "--speeds", "0:500:2", "--speed-unit", "rad/s", "--no-critical", "--quiet",
               "--out", "-"]
    routes = [(lambda: _work.refuse_long_work(model, speeds, critical=False, advice=NO_CRITICAL_ADVICE, memory=True), []),
              (lambda: rdm.campbell(model, speeds, critical=False, modes=4), ["--lowest", "4"])]
    monkeypatch.setenv(_work.ENVIRONMENT, "1e-9")
    for analysis, options in routes:
        with pytest.raises(InputError) as refused:
            analysis()
        assert _refusal(capsys, command + options) == f"rotordyn-modal campbell: error: {refused.value}"
        with rdm.long_work_allowed():
            analysis()
        assert main(command + options + ["--allow-long"]) == 0, capsys.readouterr().err
        with pytest.raises(InputError):                         # for the block only
            analysis()
