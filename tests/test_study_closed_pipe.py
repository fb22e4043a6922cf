"""A study whose summary goes to a pipe that its reader closes early (``study ... | head -3``)
still writes its results (issue 27 §1.9's long studies: the work is not lost).

The summary was printed inside the block whose outputs appear together, before the figures:
the closed pipe's ``BrokenPipeError`` left that block, so the results file computed in full was
never put in place (exit 1, nothing said, the checkpoint left for a rerun).
"""

from __future__ import annotations

import os
import subprocess
import sys

from test_progress_terminal import EXAMPLES, PACKAGE_ROOT, STUDY  # the same study of three variants


def test_a_closed_pipe_on_stdout_loses_no_results(tmp_path):
    spec, out = tmp_path / "three.study.toml", tmp_path / "out.nc"
    spec.write_text(STUDY)
    read, write = os.pipe()
    os.close(read)                                  # the reader is gone before the summary
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(PACKAGE_ROOT), os.environ.get("PYTHONPATH", "")]))
    try:
        result = subprocess.run([sys.executable, "-m", "rotordyn_modal", "study", str(EXAMPLES / "gear_machine.toml"),
                                 "--spec", str(spec), "--out", str(out), "--workers", "1"], stdout=write,
                                stderr=subprocess.PIPE, text=True, env=env, timeout=180)
    finally:
        os.close(write)
    assert result.returncode in (0, 1), result.stderr
    assert out.is_file(), result.stderr
    assert not out.with_name(out.name + ".partial").exists()          # the checkpoint is done with
    import xarray as xr

    with xr.open_dataset(out) as results:
        assert results.sizes["variant"] == 3
        assert results["modal_frequency_hz"].notnull().all()
