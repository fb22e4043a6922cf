"""More progress bars on a real pseudo-terminal (issue 27 §1.9: long work shows its progress):
the lowest modes' full-solve fallback, and a study's resume (the saved chunks read, each once)
and its results file being written. The terminal and its reading are those of
``tests/test_progress_terminal.py``."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

import rotordyn_modal as rdm

from test_progress_terminal import EXAMPLES, STUDY, _drawings, _environment, _on_terminal

#: an undamped shaft on cross-coupled bearings (tests/test_lowest_ties.py): at rest its lowest
#: pair is -a + ib, a + ib, one frequency, and the reduced route cannot show that no root of it was
#: missed below the cut: 0 rpm is solved whole (an axisymmetric rotor's double roots at rest, which
#: this test used before, are refined with more starts since, tests/test_lowest_cut_in_double_root.py)
SPLIT_PAIR = """name = "shaft"
spin_axis = [1.0, 0.0, 0.0]
materials = [{name = "steel", density = 7800.0, young_modulus = 2e11, shear_modulus = 8e10}]

[[rotors]]
name = "r"
start = [0.0, 0.0, 0.0]
element_length = 0.1
shaft = [{length = 1.0, outer_diameter = 0.05, material = "steel"}]
disks = [{name = "d", axial_position = 0.6, mass = 8.0, polar_inertia = 0.06, diametral_inertia = 0.04}]

[[bearings]]
name = "b0"
rotor = "r"
axial_position = 0.05
stiffness = [[1e7, 3e6], [-3e6, 1e7]]
damping = 0.0

[[bearings]]
name = "b1"
rotor = "r"
axial_position = 0.95
stiffness = [[1e7, 3e6], [-3e6, 1e7]]
damping = 0.0
"""


def test_the_full_solve_fallback_shows_its_bar(tmp_path):
    """``campbell --lowest`` with a speed left to the full eigen-solve (0 rpm) draws the fallback's
    bar over the speeds solved whole, whole drawings within the width."""
    model = tmp_path / "split_pair.toml"
    model.write_text(SPLIT_PAIR)
    code, text = _on_terminal(["campbell", str(model), "--speeds", "0:3000:3", "--lowest", "1",
                               "--out", str(tmp_path / "c.csv")], 100, 40)
    assert code == 0, text
    assert "1 of 3 speeds solved whole" in text, text
    drawings = _drawings(text, "lowest modes (full eigen-solve):")
    assert drawings, text
    assert all(drawing.endswith("]") and len(drawing) <= 99 for drawing in drawings), drawings
    assert "/1 " in drawings[0], drawings


def _study(tmp_path):
    spec = tmp_path / "three.study.toml"
    spec.write_text(STUDY)
    out = tmp_path / "out.nc"
    argv = ["study", str(EXAMPLES / "gear_machine.toml"), "--spec", str(spec), "--out", str(out),
            "--workers", "1", "--chunk-size", "1"]
    return spec, out, argv


def test_the_results_file_is_written_with_a_bar(tmp_path, monkeypatch):
    """A results file of more than one block is written with a bar over the variants (here on a
    pseudo-terminal as this process's stderr, blocks of one variant); the file reads back whole."""
    import io
    import os
    import pty

    from rotordyn_modal.study import results

    spec, _, _ = _study(tmp_path)
    result = rdm.study(rdm.load_model(EXAMPLES / "gear_machine.toml"), spec, chunk_size=1)
    monkeypatch.setattr(results, "_BLOCK_BYTES", 1)                      # one variant a block
    master, slave = pty.openpty()
    terminal = io.TextIOWrapper(os.fdopen(slave, "wb", buffering=0), encoding="utf-8", write_through=True)
    monkeypatch.setattr(sys, "stderr", terminal)
    try:
        result.save(tmp_path / "out.nc", progress=True)
        terminal.flush()
        text = os.read(master, 65536).decode("utf-8", "replace")
    finally:
        terminal.close()
        os.close(master)
    drawings = _drawings(text, "writing results:")
    assert drawings and all(drawing.endswith("]") for drawing in drawings), text
    assert "/3 " in drawings[0], drawings
    written = rdm.load_study(tmp_path / "out.nc")
    np.testing.assert_array_equal(written.dataset["modal_frequency_hz"].values,
                                  result.dataset["modal_frequency_hz"].values)


def test_a_resumed_study_shows_its_saved_chunks_checked_and_read(tmp_path):
    """A study resumed from three saved chunks draws a bar while it reads them (each once: checked
    and written into the results); the results equal those computed afresh."""
    spec, out, argv = _study(tmp_path)
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    fresh = rdm.study(model, spec, checkpoint=tmp_path / "out.nc.partial", chunk_size=1)
    assert len(list((tmp_path / "out.nc.partial").glob("chunk-*.npz"))) == 3
    code, text = _on_terminal(argv, 100, 40)
    assert code == 0, text
    drawings = _drawings(text, "reading saved chunks:")
    assert drawings and all(drawing.endswith("]") for drawing in drawings), text
    assert "/3 " in drawings[0], drawings
    assert "checking saved chunks" not in text      # no second pass over them
    resumed = rdm.load_study(out)
    for name in fresh.dataset.data_vars:
        if fresh.dataset[name].dtype.kind in "fc":
            np.testing.assert_array_equal(resumed.dataset[name].values, fresh.dataset[name].values)


def test_no_resume_or_writing_bar_where_stderr_is_no_terminal(tmp_path):
    """With stderr sent to a file, a resumed study writes no bar and no carriage return there."""
    spec, _, argv = _study(tmp_path)
    rdm.study(rdm.load_model(EXAMPLES / "gear_machine.toml"), spec, checkpoint=tmp_path / "out.nc.partial",
              chunk_size=1)
    result = subprocess.run([sys.executable, "-m", "rotordyn_modal", *argv], capture_output=True, text=True,
                            env=_environment(), timeout=180)
    assert result.returncode == 0, result.stderr
    assert "saved chunks" not in result.stderr and "\r" not in result.stderr, result.stderr
