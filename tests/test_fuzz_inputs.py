"""Generated bad input never crashes the command line.

Each test mutates valid inputs (the example models and study files, measured-data files the
package writes, option values of every sub-command) and runs them through
``rotordyn_modal.cli.main`` in this process. Every outcome must be a valid run (exit 0) or a
refusal: exit 2 with one line naming the file (or the option), and no output file left behind.
Never a traceback, exit 1, several lines, or a run longer than the time limit
(``tests/fuzzing.py`` holds the mutators and the judge).

Hypothesis drives the mutations through ``st.randoms()`` (so a failure shrinks to a small
input) with ``derandomize=True``: the same inputs on every run. The number of inputs per test
is ``ROTORDYN_FUZZ_EXAMPLES`` (default 150; e.g. ``ROTORDYN_FUZZ_EXAMPLES=2000`` for a long run);
the counts tried appear in the terminal summary ("fuzz: ..."). ``tests/fuzz_many.py`` runs
thousands outside pytest.
"""

from __future__ import annotations

import os
import tempfile
import warnings

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import fuzzing

#: inputs per test (ROTORDYN_FUZZ_EXAMPLES raises it)
EXAMPLES = int(os.environ.get("ROTORDYN_FUZZ_EXAMPLES", "150"))
#: seconds a single run may take before it counts as a hang
fuzzing.TIME_LIMIT = float(os.environ.get("ROTORDYN_FUZZ_TIMEOUT", "60"))

FUZZ = settings(max_examples=EXAMPLES, derandomize=True, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))

#: kind -> verdict -> count, for the terminal summary (conftest.py)
TRIED: dict = {}


@pytest.fixture(scope="module")
def folder():
    with tempfile.TemporaryDirectory(prefix="rotordyn-fuzz-") as path:
        yield path


def _check(kind, outcomes):
    counts = TRIED.setdefault(kind, {"inputs": 0, "valid": 0, "refused": 0, "crash": 0})
    counts["inputs"] += 1
    for outcome in outcomes:
        counts[outcome.verdict] += 1
    crashes = [o for o in outcomes if o.verdict == "crash"]
    assert not crashes, crashes[0].describe()


@pytest.fixture(autouse=True)
def _quiet_numpy():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


@FUZZ
@given(rng=st.randoms(use_true_random=False))
def test_mutated_model_files(folder, rng):
    _check("model files", fuzzing.model_case(rng, folder))


@FUZZ
@given(rng=st.randoms(use_true_random=False))
def test_mutated_study_files(folder, rng):
    _check("study files", fuzzing.study_case(rng, folder))


@FUZZ
@given(rng=st.randoms(use_true_random=False))
def test_mutated_measured_files(folder, rng):
    _check("measured-data files", fuzzing.measured_case(rng, folder))


@FUZZ
@given(rng=st.randoms(use_true_random=False))
def test_generated_options(folder, rng):
    _check("option sets", fuzzing.option_case(rng, folder))


def test_absurd_counts_are_refused_before_allocating(folder):
    """A range of 1e8 speeds is refused at once with the limit and the way around it."""
    import time

    start = time.perf_counter()
    outcome = fuzzing.judge(["campbell", fuzzing.EXAMPLES / "gear_machine.toml", "--speeds", "0:3000:100000000"],
                            "--speeds")
    assert outcome.verdict == "refused" and outcome.code == 2
    assert "1,000,000" in outcome.stderr and "ROTORDYN_MODAL_MAX_POINTS" in outcome.stderr
    assert time.perf_counter() - start < 5.0  # nothing of 1e8 points was built


def test_the_limit_is_raised_by_the_environment(monkeypatch):
    from rotordyn_modal.cli._common import parse_range

    with pytest.raises(Exception, match="at most 1,000,000 points"):
        parse_range("0:1:1000001", "--speeds")
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_POINTS", "2000000")
    assert len(parse_range("0:1:1000001", "--speeds")) == 1000001
