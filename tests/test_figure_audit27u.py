"""Figure audit of issue 27, section 3 (helper unb27c): what drawing every CLI figure of every
example found."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def test_a_force_frf_of_parts_the_model_has_none_of_is_refused_in_one_line(tmp_path):
    """``frf compressor_rotor.toml --force-outputs suspensions --plot f.png``: the rotor on its
    bearings has no suspensions; the figure died with IndexError (exit 1). Now one line, exit 2,
    and no figure written."""
    from rotordyn_modal.analysis.forces import force_frf

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    assert not model.suspensions
    result = force_frf(model, rdm.rpm(6000.0), np.linspace(1.0, 500.0, 30), where="suspensions")
    assert not result.outputs
    with pytest.raises(InputError, match="nothing to draw"):
        result.plot()
    out = tmp_path / "f.png"
    run = subprocess.run([sys.executable, "-m", "rotordyn_modal", "frf", str(EXAMPLES / "compressor_rotor.toml"),
                          "--speed", "6000", "--freqs", "1:500:30", "--force-outputs", "suspensions",
                          "--plot", str(out), "--quiet"], capture_output=True, text=True, cwd=tmp_path,
                         env={**os.environ, "MPLBACKEND": "Agg",
                              "PYTHONPATH": os.pathsep.join([str(ROOT)] + [p for p in [os.environ.get("PYTHONPATH")] if p])})
    assert run.returncode == 2, run.stderr
    lines = [line for line in run.stderr.splitlines() if line.strip() and "compil" not in line.lower()]
    assert len(lines) == 1 and "nothing to draw" in lines[0], run.stderr
    assert not out.exists()
