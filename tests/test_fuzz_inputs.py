"""Generated bad input never crashes the command line.

Each test mutates valid inputs (the example models and study files, measured-data files the
package writes, option values of every sub-command) and runs them through
``rotordyn_modal.cli.main`` in this process. Every outcome must be a valid run (exit 0) or a
refusal: exit 2 with one line naming the file (or the option), and no output file left behind.
Never a traceback, exit 1, several lines, or a run longer than the time limit
(``tests/fuzzing.py`` holds the mutators and the judge).

Hypothesis drives the mutations through ``st.randoms()`` (so a failure shrinks to a small
input) with ``derandomize=True``: the same inputs on every run. The number of inputs per test
is ``ROTORDYN_FUZZ_EXAMPLES`` (default 150; e.g. ``ROTORDYN_FUZZ_EXAMPLES=2000`` for a long run;
the model files' inputs in ``CHUNKS`` parametrized tests of an equal share);
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


#: the model files' inputs run as this many tests of EXAMPLES / CHUNKS inputs each, so that
#: pytest-xdist spreads them (as one test they held a worker for 53 s of a CI run's 844)
CHUNKS = 5


@pytest.mark.parametrize("chunk", range(CHUNKS))
@settings(FUZZ, max_examples=-(-EXAMPLES // CHUNKS))
@given(rng=st.randoms(use_true_random=False))
def test_mutated_model_files(folder, chunk, rng):
    """Each chunk draws its own inputs: hypothesis derandomizes a parametrized test from its node
    id (``...[chunk]``), so the chunks' inputs differ and are the same on every run."""
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

    fuzzing.run_cli(["check", fuzzing.EXAMPLES / "gear_machine.toml"])   # the command line imported
    start = time.process_time()   # CPU time: on a machine shared with other work the wall clock took 6.3 s
    outcome = fuzzing.judge(["campbell", fuzzing.EXAMPLES / "gear_machine.toml", "--speeds", "0:3000:100000000"],
                            "--speeds")
    assert outcome.verdict == "refused" and outcome.code == 2
    assert "1,000,000" in outcome.stderr and "ROTORDYN_MODAL_MAX_POINTS" in outcome.stderr
    assert time.process_time() - start < 5.0  # nothing of 1e8 points was built


def test_the_hang_guard_counts_cpu_time_not_waiting(monkeypatch):
    """A run that waits (another process has the core) is no hang: on a shared machine a 12 s run
    took over 60 s of wall-clock time and counted as a crash. Work that burns the CPU past the
    limit is one, and waiting past ``WALL_FACTOR`` times the limit too."""
    import time

    with fuzzing.time_limit(0.1):
        time.sleep(0.3)                          # wall-clock time beyond the limit, no CPU
    with pytest.raises(fuzzing.Timeout, match="wall-clock time"):
        with fuzzing.time_limit(0.02):
            time.sleep(5.0)                      # 250 x the limit: blocked, a hang all the same
    monkeypatch.setattr(fuzzing, "WALL_FACTOR", 1000.0)   # however little of the CPU this process gets
    with pytest.raises(fuzzing.Timeout, match="CPU time"):
        with fuzzing.time_limit(0.1):
            end = time.process_time() + 60.0
            while time.process_time() < end:     # CPU time beyond the limit
                pass


def test_the_runs_count_on_a_fixed_memory(monkeypatch):
    """Each run counts on ``fuzzing.MEMORY_GB`` whatever the machine has free, so that a refusal
    for memory (a mutated mesh of 6,805 coordinates needs 65 GiB) is the same on a machine whose
    other work leaves more or less of it; the setting is undone after the run."""
    monkeypatch.delenv("ROTORDYN_MODAL_MEMORY_GB", raising=False)
    seen = []
    import importlib

    monkeypatch.setattr(importlib.import_module("rotordyn_modal.cli.main"), "main",
                        lambda argv: seen.append(os.environ.get("ROTORDYN_MODAL_MEMORY_GB")) or 0)
    assert fuzzing.run_cli(["check", "model.toml"])[0] == 0
    assert seen == [fuzzing.MEMORY_GB] and "ROTORDYN_MODAL_MEMORY_GB" not in os.environ


def test_the_limit_is_raised_by_the_environment(monkeypatch):
    from rotordyn_modal.cli._common import parse_range

    with pytest.raises(Exception, match="at most 1,000,000 points"):
        parse_range("0:1:1000001", "--speeds")
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_POINTS", "2000000")
    assert len(parse_range("0:1:1000001", "--speeds")) == 1000001


# ----------------------------------------------------------------------------------------------
# each crash the generated inputs found, kept as a plain case (they all ended in exit 1, a
# traceback or several lines before their fix)
# ----------------------------------------------------------------------------------------------
def _edited(name, old, new):
    text = (fuzzing.EXAMPLES / name).read_text(encoding="utf-8")
    assert old in text
    return text.replace(old, new, 1)


_SINGULAR = """[stator]
mass = 1.0
inertia = [1.0, 1.0, 1.0]

[[rotors]]
name = "r"
mass = 1e29
center_of_mass = [0.0, 1.0, 0.0]
polar_inertia = 1e-3
diametral_inertia = 1e-3
speed_ratio = 1.0

[[suspensions]]
name = "s"
position = [0.0, 0.0, 0.0]
stiffness = [1e5, 1e5, 1e5, 1e3, 1e3, 1e3]
"""

MODEL_CASES = {
    "inertias 1e21 apart": (_edited("spring_block_rotor_suspension.toml", "diametral_inertia = 0.078125",
                                    "diametral_inertia = 1e20"), "diametral_inertia"),
    "a mass of 1e-300 kg": (_edited("gear_machine.toml", "mass = 8.0", "mass = 1e-300"), "mass = 1e-300"),
    "a stiffness of 1e300": (_edited("spring_block_rotor.toml", "stiffness = 2000.0 ", "stiffness = 1e300 "),
                             "stiffness = 1e+300"),
    "an empty key": (_edited("spring_block_rotor.toml", "spin_axis =", '"" ='), "'' = "),
    "a mass matrix singular in double precision": (_SINGULAR, "mass matrix"),
}


@pytest.mark.parametrize("text,message", MODEL_CASES.values(), ids=list(MODEL_CASES))
@pytest.mark.parametrize("command", ["check", "campbell"])
def test_found_model_crashes_are_refusals(tmp_path, text, message, command):
    model = tmp_path / "model.toml"
    model.write_text(text, encoding="utf-8")
    argv = [command, model] + (["--speeds", fuzzing.SPEEDS, "--out", tmp_path / "c.csv"] if command == "campbell" else [])
    outcome = fuzzing.judge(argv, str(model), [tmp_path / "c.csv"], style=fuzzing.HOUSE_STYLE)
    assert outcome.verdict == "refused", outcome.describe()
    assert message in outcome.stderr


STUDY_CASES = {
    "a distribution that is a list": ('distribution = "uniform"', "distribution = [1, 2]", "distribution"),
    "a seed beyond 32 bits": ("seed = 2026", "seed = 9223372036854775807", "seed"),
    "a chunk size beyond 32 bits": ('design = "latin-hypercube"', 'design = "latin-hypercube"\nchunk_size = 4294967296',
                             "chunk_size"),
}


@pytest.mark.parametrize("old,new,key", STUDY_CASES.values(), ids=list(STUDY_CASES))
def test_found_study_crashes_are_refusals(tmp_path, old, new, key):
    spec = tmp_path / "study.toml"
    spec.write_text(_edited("mount_tolerance.study.toml", old, new), encoding="utf-8")
    outcome = fuzzing.judge(["study", fuzzing.EXAMPLES / "gear_machine.toml", "--spec", spec,
                             "--out", tmp_path / "r.nc"], str(spec), [tmp_path / "r.nc"], tmp_path,
                            style=fuzzing.HOUSE_STYLE)
    assert outcome.verdict == "refused", outcome.describe()
    assert f"{key} = " in outcome.stderr


OPTION_CASES = {
    "operating speed 0": (["unbalance", "fan_on_bearings.toml", "--speeds", fuzzing.SPEEDS, "--operating-speed", "0"],
                          "--operating-speed"),
    "atol 0 (stalled)": (["simulate", "spring_block_rotor.toml", "--duration", "0.05", "--atol", "0"], "atol"),
    "a ramp to 1e300 rpm": (["simulate", "spring_block_rotor.toml", "--duration", "0.05", "--ramp", "1e300"],
                            "--ramp 1e300"),
    "samples beyond the limit": (["simulate", "spring_block_rotor.toml", "--duration", "0.05", "--samples",
                                  "10000000000"], "ROTORDYN_MODAL_MAX_POINTS"),
    "mode 0": (["modes", "gear_machine.toml", "--shape", "0", "--plot", "{tmp}/shape.svg"], "mode 0"),
    "a key that holds text": (["fit", "gear_machine.toml", "--measured", "{csv}", "--params", "name",
                               "--out", "{tmp}/f.toml"], "name = "),
    "a million starts": (["fit", "gear_machine.toml", "--measured", "{csv}", "--params",
                          "suspensions.mount-FL.stiffness", "--starts", "1000000", "--out", "{tmp}/f.toml"], "starts"),
    "a million workers": (["study", "gear_machine.toml", "--spec", str(fuzzing.EXAMPLES / "mount_sobol.study.toml"),
                           "--workers", "1000000", "--out", "{tmp}/r.nc"], "--workers"),
}


@pytest.mark.parametrize("argv,message", OPTION_CASES.values(), ids=list(OPTION_CASES))
def test_found_option_crashes_are_refusals(tmp_path, argv, message):
    csv = fuzzing._valid_measured(tmp_path)["valid.csv"]
    argv = [str(fuzzing.EXAMPLES / a) if a.endswith(".toml") and "/" not in a else
            a.replace("{tmp}", str(tmp_path)).replace("{csv}", str(csv)) for a in argv]
    outcome = fuzzing.judge(argv + ["--quiet"], message, folder=tmp_path)
    assert outcome.verdict == "refused", outcome.describe()


def _first_cell(text):
    """The CSV with its first data line's first cell (speed_rpm) replaced."""
    lines = text.splitlines()
    return lambda cell: "\n".join([lines[0], cell + lines[1][lines[1].index(","):], *lines[2:]]) + "\n"


MEASURED_CASES = {
    "a cell that is not a number": ("valid.csv", "x", None),
    "an empty speed cell": ("valid.csv", "", None),
    "a mapping node that is not a number": ("ascii.uff", None, "name,node,direction\nacc-top-z,x,3\n"),
    "a mapping sign of 0.5": ("ascii.uff", None, "name,node,direction,sign\nacc-top-z,1,3,0.5\n"),
    "a node and direction given twice": ("ascii.uff", None, "name,node,direction\nacc-top-z,1,3\nacc-side-y,1,3\n"),
}


@pytest.mark.parametrize("kind,edit,mapping", MEASURED_CASES.values(), ids=list(MEASURED_CASES))
def test_found_measured_crashes_are_refusals(tmp_path, kind, edit, mapping):
    valid = fuzzing._valid_measured(tmp_path)[kind]
    path = tmp_path / f"measured{valid.suffix}"
    text = valid.read_text(encoding="latin-1")
    path.write_text(text if edit is None else _first_cell(text)(edit), encoding="latin-1")
    argv = ["frf", fuzzing.MEASURED_MODEL, "--speed", fuzzing.MEASURED_RPM, "--freqs", fuzzing.MEASURED_FREQS,
            "--measured", path, "--quiet", "--out", tmp_path / "out.csv"]
    named = str(path)
    if mapping is not None:
        (tmp_path / "map.csv").write_text(mapping)
        argv += ["--mapping", tmp_path / "map.csv"]
        named = str(tmp_path / "map.csv")
    outcome = fuzzing.judge(argv, named, [tmp_path / "out.csv"])
    assert outcome.verdict == "refused", outcome.describe()


def test_duplicated_uff_channel_and_short_coherence_are_refused(tmp_path):
    import copy

    sets = fuzzing._uff_sets(binary=False)
    for label, changed, message in (
            ("duplicated", sets + [copy.deepcopy(sets[0])], "given 2 times"),
            ("short coherence", [dict(s, data=s["data"][:5], x=s["x"][:5]) if s["func_type"] == 6 and i == 1 else s
                                 for i, s in enumerate(sets)], "coherence")):
        path = tmp_path / f"{label.replace(' ', '-')}.uff"
        fuzzing._write_uff(changed, path, sets)
        outcome = fuzzing.judge(["frf", fuzzing.MEASURED_MODEL, "--speed", fuzzing.MEASURED_RPM, "--freqs",
                                 fuzzing.MEASURED_FREQS, "--measured", path, "--quiet", "--out", "-"], str(path))
        assert outcome.verdict == "refused" and message in outcome.stderr, outcome.describe()
