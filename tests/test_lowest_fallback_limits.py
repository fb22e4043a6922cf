"""The lowest modes' full-solve fallback (issue 28 item 4, issue 27: large machines refused before
the work with the estimate). A speed the reduced basis cannot serve (an axisymmetric rotor's double
roots at rest) is solved whole: a dense eigen-solution of every state, hours and GB for a shaft of
thousands of nodes. Over the CPU-time limit (``ROTORDYN_MODAL_MAX_CPU_MINUTES``, set low here) or
the memory at hand it is refused before that solve, in one line naming the speeds, the size and the
estimate and the way out; ``--allow-long`` runs it. Under the limit the roots are scipy's."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError

from test_lowest_modes import _by_frequency, _lowest_by_scipy

COMPRESSOR = "examples/compressor_rotor.toml"          # 53 coordinates, axisymmetric: double roots at rest
ENVIRONMENT = "ROTORDYN_MODAL_MAX_CPU_MINUTES"
SPEEDS = np.array([0.0, 500.0])                         # [rad/s]: speed 0 is left to the full solve


@pytest.fixture(autouse=True)
def cut_in_a_double_root_left_whole(monkeypatch):
    """The speed left to the full solve: the cut inside a double root at rest, as before its own
    refinement (``_lowest._cut_in_a_multiple_root``, tests/test_lowest_cut_in_double_root.py)
    serves it; these tests are of the fallback's limits, whatever the speed it serves."""
    monkeypatch.setattr(_lowest, "_cut_in_a_multiple_root", lambda *args, **kwargs: None)


@pytest.fixture
def no_full_solve(monkeypatch):
    """A full eigen-solve is a failure: the refusal comes before it."""
    def solved(*args):
        raise AssertionError("the full eigen-solve ran")

    monkeypatch.setattr(_lowest, "_full_lowest", solved)


# the 4th and 6th roots at rest are the first of a double root (its other half the next refined): no
# start above shows them to be the last below, and speed 0 is left to the full solve
@pytest.mark.parametrize("asked", [{"modes": 4}, {"modes": 4, "max_frequency": 450.0}, {"modes": 6, "max_frequency": 450.0}])
def test_a_fallback_over_the_cpu_limit_is_refused_before_it(monkeypatch, no_full_solve, asked):
    monkeypatch.setenv(ENVIRONMENT, "1e-9")            # 60 ns: one dense eigen-solution of 106 states exceeds it
    with pytest.raises(InputError) as refused:
        rdm.campbell(rdm.load_model(COMPRESSOR), SPEEDS, critical=False, **asked)
    line = str(refused.value)
    assert "\n" not in line
    assert line.startswith(f"{COMPRESSOR}: ")
    assert "the full eigen-solve of 1 of 2 speeds (0 rpm;" in line and "1 eigen-solution of 106 states" in line
    assert "of CPU time, more than the limit of" in line
    assert "leave those speeds out of the sweep, or add --allow-long" in line and ENVIRONMENT in line


def test_stability_of_the_lowest_modes_is_refused_alike(monkeypatch, no_full_solve):
    monkeypatch.setenv(ENVIRONMENT, "1e-9")
    with pytest.raises(InputError, match="the full eigen-solve of 1 of 2 speeds"):
        rdm.stability(rdm.load_model(COMPRESSOR), SPEEDS, modes=4)


def test_under_the_limit_the_fallback_gives_scipys_roots(monkeypatch):
    monkeypatch.delenv(ENVIRONMENT, raising=False)      # the default limit: 30 CPU minutes
    model = rdm.load_model(COMPRESSOR)
    with pytest.warns(UserWarning, match="1 of 2 speeds solved whole"):
        result = rdm.campbell(model, SPEEDS, critical=False, modes=4)
    reference = _lowest_by_scipy(model, SPEEDS, 4)
    assert np.max(np.abs(_by_frequency(result.eigenvalues) - reference) / np.abs(reference)) < 1e-9


def test_the_command_line_refuses_it_in_one_line_and_allow_long_runs_it(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv(ENVIRONMENT, "1e-9")
    arguments = ["campbell", COMPRESSOR, "--speeds", "0:3000:3", "--lowest", "4", "--no-critical", "--quiet"]
    out = tmp_path / "lowest.csv"
    assert main(arguments + ["--out", str(out)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "(0 rpm;" in error and "--allow-long" in error
    assert not out.exists()
    assert main(arguments + ["--out", str(out), "--allow-long"]) == 0
    assert out.exists()
    assert main(arguments + ["--out", str(out)]) == 2    # for that one run only


def test_a_fallback_that_cannot_fit_is_refused_even_with_allow_long(monkeypatch, no_full_solve):
    from rotordyn_modal.analysis._cost import long_work_allowed

    monkeypatch.setattr(_lowest, "_CHECKED_BYTES", 0)   # the check's floor: measured from any size
    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "0.0001")
    with long_work_allowed(), pytest.raises(InputError) as refused:
        rdm.campbell(rdm.load_model(COMPRESSOR), SPEEDS, critical=False, modes=4)
    line = str(refused.value)
    assert "1 eigen-solution of 106 states, needs about" in line and "GiB of memory" in line
    assert "ROTORDYN_MODAL_MEMORY_GB" in line
