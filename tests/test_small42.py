"""Small input families of issue 27 (hidden checks in the families of other tools' files and of
physics out of range), session 42."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from quiet_cli import run_quietly

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_RUBBER = ROOT / "examples" / "rubber_mounts.toml"


@pytest.mark.parametrize("delimiter", ["\t-1", "-1", " -1", "  \t-1", "      -1"])
def test_a_uff_dataset_delimiter_written_with_a_tab_or_fewer_blanks_is_read(tmp_path, delimiter):
    """The Universal File's delimiter is '    -1' (columns 1-6); hand-edited files and some exports
    write '\\t-1' or '-1'. pyuff finds only the first form, so such a file was refused as "a dataset
    is not closed by a '    -1' line (from line 2): the file is truncated"; it holds the same FRF as
    the file written with the standard delimiters."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.measured import read_measured

    model = rdm.load_model(EXAMPLE_RUBBER)
    good = tmp_path / "good.uff"
    code, err = run_quietly(["frf", str(EXAMPLE_RUBBER), "--speed", "0", "--freqs", "5:20:4", "--sensor", "acc-top-z",
                             "--excitation", "hammer-z", "--out", str(good)])
    assert code == 0, err
    lines = good.read_text().splitlines(keepends=True)
    marks = [k for k, line in enumerate(lines) if line.rstrip("\r\n") == "    -1"]
    assert len(marks) >= 2 and len(marks) % 2 == 0
    for k in marks:                                        # every delimiter, opening and closing
        lines[k] = delimiter + lines[k][len("    -1"):]
    odd = tmp_path / "odd_delimiters.uff"
    odd.write_text("".join(lines))
    (expected,), (read,) = read_measured(good, model), read_measured(odd, model)
    np.testing.assert_array_equal(read.frequencies_hz, expected.frequencies_hz)
    np.testing.assert_array_equal(read.H, expected.H)
    assert read.outputs == expected.outputs and read.inputs == expected.inputs
