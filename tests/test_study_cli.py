"""``rotordyn-modal study``: as a new user would try it (typo in a key, negative std,
Ctrl-C and run again), outputs, exit codes."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main
from rotordyn_modal.study import load_study

STUDY = """seed = 3
samples = {samples}
design = "latin-hypercube"
chunk_size = {chunk}
operating_band_rpm = [3400.0, 3700.0]

[[parameters]]
key = "{key}"
apply = "scale"
distribution = "normal"
mean = 1.0
std = {std}
truncate = [0.7, 1.3]

[analyses.campbell]
speeds_rpm = "0:6000:{speeds}"

[analyses.critical_speeds]
"""


def write_study(path, samples=6, chunk=2, key="suspensions.mount-FL.stiffness", std=0.1, speeds=31):
    path.write_text(STUDY.format(samples=samples, chunk=chunk, key=key, std=std, speeds=speeds))
    return path


def test_typo_in_a_dotted_key_exit_2_one_line_naming_file_key_and_choices(tmp_path, examples_dir, capsys):
    spec = write_study(tmp_path / "s.toml", key="suspensions.mount-FX.stiffness")
    code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec), "--out", str(tmp_path / "r.nc")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "s.toml: [[parameters]] 1 key = 'suspensions.mount-FX.stiffness'" in err
    assert "mount-FL, mount-FR, mount-RL, mount-RR" in err
    assert not (tmp_path / "r.nc").exists()


def test_negative_standard_deviation_exit_2(tmp_path, examples_dir, capsys):
    spec = write_study(tmp_path / "s.toml", std=-0.1)
    code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec), "--out", str(tmp_path / "r.nc")])
    err = capsys.readouterr().err
    assert code == 2 and "[[parameters]] 1 std = -0.1: expected a finite number > 0" in err


def test_bad_options_exit_2(tmp_path, examples_dir, capsys):
    spec = write_study(tmp_path / "s.toml")
    model = str(examples_dir / "gear_machine.toml")
    for extra in (["--out", str(tmp_path / "r.csv")], ["--out", str(tmp_path / "r.nc"), "--workers", "0"],
                  ["--out", str(spec)], ["--out", str(tmp_path / "r.nc"), "--plot", str(tmp_path / "c.txt")]):
        assert main(["study", model, "--spec", str(spec), *extra]) == 2
    assert capsys.readouterr().err.count("error:") == 4


def test_a_run_writes_results_table_and_figures_and_reports_the_band(tmp_path, examples_dir, capsys):
    spec = write_study(tmp_path / "s.toml")
    out = tmp_path / "r.nc"
    code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec), "--out", str(out),
                 "--workers", "2", "--table", str(tmp_path / "t.csv"), "--plot", str(tmp_path / "c.png"),
                 "--plot-histogram", str(tmp_path / "h.png"), "--plot-sensitivity", str(tmp_path / "s.png")])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "P(critical speed in 3400-3700 rpm)" in captured.out
    assert not (tmp_path / "r.nc.partial").exists()  # the checkpoint is removed when done
    for name in ("t.csv", "c.png", "h.png", "s.png"):
        assert (tmp_path / name).stat().st_size > 0
    serial = rdm.study(rdm.load_model(examples_dir / "gear_machine.toml"), spec)
    np.testing.assert_array_equal(load_study(out).dataset["critical_speed"].values,
                                  serial.dataset["critical_speed"].values)
    # the summary prints speeds in rpm (the mean of the first crossing's over the variants)
    row = next(line for line in captured.out.splitlines() if "critical_speed[motor,1,1] (rpm)" in line)
    mean_rpm = serial.dataset["critical_speed"].values[:, 0].mean() * 30 / np.pi
    assert float(row.split("(rpm)")[1].split()[1]) == pytest.approx(mean_rpm, rel=1e-5)   # printed to 6 digits


def test_a_study_of_campbell_curves_alone_ends_with_a_sentence_not_an_internal_error(tmp_path, examples_dir,
                                                                                       capsys):
    # only [analyses.campbell]: no scalar output to summarise (was "failed: KeyError: 'output'", exit 1)
    spec = tmp_path / "s.toml"
    spec.write_text(STUDY.format(samples=2, chunk=2, key="suspensions.mount-FL.stiffness", std=0.1, speeds=5)
                    .replace("[analyses.critical_speeds]\n", ""))
    out = tmp_path / "r.nc"
    code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec), "--out", str(out)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "no scalar output to summarise" in captured.out
    assert load_study(out).dataset["frequency_hz"].shape[0] == 2      # the curves of both variants were kept


def _sigint_delivered():
    """In the child before exec: SIGINT's default action and not blocked."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def test_ctrl_c_then_the_same_command_resumes(tmp_path, examples_dir):
    """A real SIGINT to the command: exit 130, chunks kept; the rerun computes only the rest."""
    # 180 samples: the chunks come in bursts of the pool's size and the last of 60 followed the
    # first two within ~1.4 s, a window a loaded test runner could miss
    spec = write_study(tmp_path / "s.toml", samples=180, chunk=2, speeds=201)
    out = tmp_path / "r.nc"
    folder = tmp_path / "r.nc.partial"
    command = [sys.executable, "-m", "rotordyn_modal.cli.main", "study", str(examples_dir / "gear_machine.toml"),
               "--spec", str(spec), "--out", str(out), "--quiet"]
    # Ctrl-C as a terminal delivers it: the child's SIGINT neither ignored nor blocked, whatever the
    # test runner's process inherited or left (both survive exec)
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               preexec_fn=_sigint_delivered)
    deadline = time.time() + 60
    # a chunk is finished when its manifest is written (after its arrays)
    while len(list(folder.glob("chunk-*.json"))) < 2 and time.time() < deadline and process.poll() is None:
        time.sleep(0.01)
    finished_first = process.poll() is not None
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert not finished_first, f"the study ended before two chunks were seen: {err}"
    assert process.returncode == 130, err
    assert "run the same command again to resume" in err and "Traceback" not in err
    kept = len(list(folder.glob("chunk-*.json")))
    assert 2 <= kept < 90 and not out.exists()
    rerun = subprocess.run(command[:-1], capture_output=True, text=True, timeout=120)
    assert rerun.returncode == 0, rerun.stderr
    assert f"{kept} chunks resumed" in rerun.stderr
    fresh = rdm.study(rdm.load_model(examples_dir / "gear_machine.toml"), spec)
    resumed = load_study(out)
    for name in ("sample_value", "frequency_hz", "critical_speed"):
        np.testing.assert_array_equal(resumed.dataset[name].values, fresh.dataset[name].values)


def test_help_lists_the_options(capsys):
    with pytest.raises(SystemExit):
        main(["study", "--help"])
    text = capsys.readouterr().out
    for option in ("--spec", "--workers", "--scheduler", "--out", "--operating-range", "--restart"):
        assert option in text


def test_scheduler_option_runs_on_a_dask_cluster(tmp_path, examples_dir, capsys):
    distributed = pytest.importorskip("distributed")
    spec = write_study(tmp_path / "s.toml", samples=4)
    out = tmp_path / "r.nc"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster:
        code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec), "--out", str(out),
                     "--scheduler", cluster.scheduler_address, "--quiet"])
    assert code == 0, capsys.readouterr().err
    serial = rdm.study(rdm.load_model(examples_dir / "gear_machine.toml"), spec)
    np.testing.assert_array_equal(load_study(out).dataset["frequency_hz"].values, serial.dataset["frequency_hz"].values)


def test_unreachable_scheduler_exit_2(tmp_path, examples_dir, capsys, monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr("rotordyn_modal.cli.study.SCHEDULER_TIMEOUT", 1)
    spec = write_study(tmp_path / "s.toml", samples=4)
    code = main(["study", str(examples_dir / "gear_machine.toml"), "--spec", str(spec),
                 "--out", str(tmp_path / "r.nc"), "--scheduler", "tcp://127.0.0.1:9", "--quiet"])
    assert code == 2 and "cannot connect" in capsys.readouterr().err


def test_without_xarray_a_study_is_refused_in_one_line_naming_the_extra(tmp_path, examples_dir, capsys, monkeypatch):
    """As for the other extras (tdms, ema, interactive, fast): exit code 2 and one line saying
    what to install, before any work; in Python still an ImportError."""
    monkeypatch.setitem(sys.modules, "xarray", None)        # `import xarray` raises ImportError
    spec = tmp_path / "s.study.toml"
    write_study(spec)
    model = examples_dir / "gear_machine.toml"
    assert main(["study", str(model), "--spec", str(spec), "--out", str(tmp_path / "r.nc")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("rotordyn-modal study: error: ")
    assert "pip install 'rotordyn_modal[study]'" in err and not (tmp_path / "r.nc").exists()
    with pytest.raises(ImportError, match=r"rotordyn_modal\[study\]"):
        rdm.study(rdm.load_model(model), spec)
