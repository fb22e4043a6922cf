"""A study is refused before any work, in one line with the estimate, when it cannot be done
within the limits the other commands keep (issue 27 §1.9): its unbalance responses counted in its
CPU time, a base model whose Campbell sweep cannot fit in memory refused as a whole; and a study
whose chunk size was chosen for its pool resumes on a pool of fewer workers (issue 27 §1.8: a
killed worker's chunks are computed again).

The truths are outside the estimates: the CPU time the analyses and the study really take
(``time.process_time``), and ``rdm.campbell``'s own refusal of the base model."""

from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np
import pytest

#: measures the CPU of the package's work in the test process against its estimates or limits (made
#: for the command's process): with OpenBLAS's own threads, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = str(ROOT / "examples" / "gear_machine.toml")

pytest.importorskip("xarray")

UNBALANCE = """seed = 4
samples = {samples}
[[parameters]]
key = "stator.mass"
distribution = "uniform"
low = 140.0
high = 160.0
[analyses.unbalance]
speeds_rpm = "100:6000:201"
"""


def _unbalance_seconds(model, speeds) -> float:
    """CPU seconds of the base model's unbalance response over ``speeds`` [rad/s] (no resonance
    search, as a study's variants), one BLAS thread: the shortest of three."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study.execution import limit_threads

    best = float("inf")
    with limit_threads():
        for _ in range(3):
            start = time.process_time()
            rdm.unbalance_response(model, speeds, resonances=False)
            best = min(best, time.process_time() - start)
    return best


def test_a_study_of_unbalance_responses_over_the_cpu_limit_is_refused_before_any_work(tmp_path, monkeypatch,
                                                                                       capsys):
    """400 variants of a 201-speed unbalance response (no eigen-solution at all: the estimate
    counted nothing and the study ran) under a limit of a quarter of the CPU time their responses
    alone take: one line naming the study file, ``samples = 400``, the unbalance part, the estimate
    and the limit, nothing computed. The estimate is of the size of the responses' own time, and
    ``--allow-long`` runs the study, which takes more CPU time than the limit indeed."""
    import rotordyn_modal as rdm
    from rotordyn_modal.cli import main
    from rotordyn_modal.study import execution

    samples = 400
    model = rdm.load_model(EXAMPLE)
    responses = samples * _unbalance_seconds(model, np.linspace(100, 6000, 201) * np.pi / 30)
    limit = responses / 4
    spec = tmp_path / "s.toml"
    spec.write_text(UNBALANCE.format(samples=samples))
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", repr(limit / 60))
    real_run_chunk = execution.run_chunk
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    argv = ["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith(f"rotordyn-modal study: error: {spec}: samples = 400: 400 variants x about "), err
    assert "unbalance at 201 speeds: about " in err and "more than the limit of" in err, err
    assert "--allow-long" in err and "rdm.long_work_allowed()" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    estimate = float(re.search(r"= about ([0-9.]+) s of CPU time", err).group(1))
    assert 0.3 * responses <= estimate <= 30 * responses, (estimate, responses)

    monkeypatch.setattr(execution, "run_chunk", real_run_chunk)
    start = time.process_time()
    assert main(argv + ["--allow-long"]) == 0
    assert time.process_time() - start > limit            # the refusal was right: it takes longer
    assert rdm.load_study(tmp_path / "r.nc").n_variants == samples


def test_the_python_study_over_the_cpu_limit_names_long_work_allowed_and_runs_inside_it(monkeypatch):
    """The study's limit is the other commands' (``ROTORDYN_MODAL_MAX_CPU_MINUTES``, lifted by
    ``rdm.long_work_allowed()``, the command line's ``--allow-long``): ``rdm.study`` refuses a
    study over it with the Python way named, and runs it inside ``with rdm.long_work_allowed()``."""
    import rotordyn_modal as rdm
    from rotordyn_modal.errors import InputError

    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 1, "samples": 8, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"unbalance": {"speeds_rpm": "100:6000:51"}}}
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-7")
    with pytest.raises(InputError, match=r"<study>: samples = 8: 8 variants x about .* more than the limit of "
                                         r".*or add --allow-long \(rdm\.long_work_allowed\(\) in Python; "
                                         r"ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit\)"):
        rdm.study(model, spec)
    with rdm.long_work_allowed():
        assert rdm.study(model, spec).n_variants == 8


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """150 rotors on bearings chained by gears: 606 coordinates, whose 101-speed Campbell sweep
    needs about 1.9 GiB by ``campbell``'s own estimate."""
    from test_large_machine_cli import chained_gear_toml

    path = tmp_path_factory.mktemp("chain") / "chain.toml"
    path.write_text(chained_gear_toml(150, 150))
    return path


CHAIN_STUDY = """seed = 1
samples = 3
[[parameters]]
key = "stator.mass"
distribution = "uniform"
low = 1900.0
high = 2100.0
[analyses.campbell]
speeds_rpm = "0:3000:101"
[analyses.critical_speeds]
"""


@pytest.mark.parametrize("allow_long", [False, True])
def test_a_base_model_whose_campbell_sweep_cannot_fit_refuses_the_study_as_a_whole(chain, tmp_path, monkeypatch,
                                                                                     capsys, allow_long):
    """Under 1 GiB, the chain's Campbell sweep is refused by ``rdm.campbell`` itself; the study ran
    every variant into that refusal (exit 0, every variant failed). It is refused as a whole before
    any work, with ``--allow-long`` too (memory is never lifted), in one line naming the study file,
    the analysis's key and value and campbell's own estimate."""
    import rotordyn_modal as rdm
    from rotordyn_modal.cli import main
    from rotordyn_modal.errors import InputError
    from rotordyn_modal.study import execution

    monkeypatch.setenv("ROTORDYN_MODAL_MEMORY_GB", "1")
    model = rdm.load_model(chain)
    with pytest.raises(InputError, match=r"needs about ([0-9.]+) GiB of memory") as refused:
        rdm.campbell(model, np.linspace(0, 3000, 101) * np.pi / 30)
    needed = re.search(r"needs about ([0-9.]+) GiB of memory", str(refused.value)).group(1)
    spec = tmp_path / "s.toml"
    spec.write_text(CHAIN_STUDY)
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a chunk was computed"))
    code = main(["study", str(chain), "--spec", str(spec), "--out", str(tmp_path / "r.nc"), "--quiet"]
                + ["--allow-long"] * allow_long)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith(f"rotordyn-modal study: error: {spec}: [analyses.campbell] speeds_rpm = '0:3000:101': "
                          "one variant's Campbell sweep of 606 coordinates at 101 speeds"), err
    assert f"needs about {needed} GiB of memory, 1.0 GiB is available: ask [analyses.campbell] for fewer " \
           "speeds (about " in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


SMALL = ('seed = 5\nsamples = 24\n[[parameters]]\nkey = "stator.mass"\ndistribution = "uniform"\nlow = 140.0\n'
         'high = 160.0\n[analyses.campbell]\nspeeds_rpm = "0:3000:7"\n')


def test_a_killed_worker_of_a_pool_whose_chunk_size_was_chosen_for_it_is_replaced(tmp_path, monkeypatch, capsys):
    """No chunk size in the study file: 2 workers chose chunks of 2 variants, the fresh pool after
    one died (1 worker, serial) would choose 3, whose fingerprint the checkpoint refused ("holds
    the chunks of a different study", exit 2, every rerun alike). The chunk size is kept in the
    checkpoint: the study ends with the warning alone, its results those of a serial run."""
    from test_study_robust import _run_with_killer, assert_same_results

    from rotordyn_modal.cli import main

    spec = tmp_path / "s.toml"
    spec.write_text(SMALL)
    assert main(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "serial.nc"), "--quiet"]) == 0
    code, err = _run_with_killer(["study", EXAMPLE, "--spec", str(spec), "--out", str(tmp_path / "r.nc"),
                                  "--workers", "2", "--quiet"], tmp_path, monkeypatch, capsys)
    assert (tmp_path / "killed").exists()          # a worker was killed
    lines = err.strip().splitlines()
    assert code == 0 and len(lines) == 1 and "warning: a worker process died" in lines[0], err
    assert_same_results(tmp_path / "r.nc", tmp_path / "serial.nc")
    assert not (tmp_path / "r.nc.partial").exists()


class _FourWorkers:
    """An executor of 4 workers as far as the chunk size goes, run in this process."""

    _max_workers = 4

    def map(self, function, tasks):
        return map(function, tasks)


def test_a_checkpoint_resumes_on_another_executor(tmp_path, monkeypatch):
    """A study interrupted on 4 workers resumes serially (another ``--workers``): every saved
    chunk is taken, none computed, and the results are those of the first run."""
    import rotordyn_modal as rdm
    from rotordyn_modal.study import execution

    model = rdm.load_model(EXAMPLE)
    spec = {"seed": 5, "samples": 24, "parameters": [
        {"key": "stator.mass", "distribution": "uniform", "low": 140.0, "high": 160.0}],
        "analyses": {"modes": {"speed_rpm": 1000.0}}}
    first = rdm.study(model, spec, executor=_FourWorkers(), checkpoint=tmp_path / "c")
    monkeypatch.setattr(execution, "run_chunk", lambda task: pytest.fail("a saved chunk was computed"))
    again = rdm.study(model, spec, checkpoint=tmp_path / "c")
    assert again.resumed_chunks == 24              # 1 variant a chunk, as 4 workers chose (serially 3)
    assert again.dataset.equals(first.dataset)
