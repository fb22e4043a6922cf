"""``frf`` from 0 Hz on a model free to move in a direction (no suspension holds it): at 0 Hz the
dynamic stiffness is the stiffness alone, singular along that rigid-body motion. The refusal said
"an undamped resonance there, or stiffnesses and masses many orders of magnitude apart"; now it
names the free coordinate, found here by construction (every mount without stiffness along x:
the skid free to slide along x, its other five motions held)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotordyn_modal.cli import main

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "motor_fan_minimal.toml"


def _free_along_x(tmp_path) -> Path:
    text = EXAMPLE.read_text()
    assert text.count("stiffness = [1.5e5, 1.5e5, 3.0e5]") == 4
    text = text.replace("stiffness = [1.5e5, 1.5e5, 3.0e5]", "stiffness = [0.0, 1.5e5, 3.0e5]")
    text = text.replace("damping = [120.0, 120.0, 240.0]", "damping = [0.0, 120.0, 240.0]")
    path = tmp_path / "free_x.toml"
    path.write_text(text)
    return path


def test_frf_from_zero_names_the_free_motion(tmp_path, capsys):
    model = _free_along_x(tmp_path)
    out = tmp_path / "h.csv"
    assert main(["frf", str(model), "--freqs", "0:50:11", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "at 0 Hz" in err and "free to move along stator.ux (" in err, err
    assert "undamped resonance" not in err
    assert len([line for line in err.splitlines() if line.strip()]) == 1
    assert not out.exists()
    # above 0 Hz the mass holds the free motion: the same model solves
    assert main(["frf", str(model), "--freqs", "1:50:11", "--out", str(out)]) == 0


def test_a_held_model_keeps_the_resonance_wording(tmp_path, capsys):
    """The free-motion sentence is only for a singular stiffness at 0 Hz: a model every mount holds
    solves from 0 Hz (damped: no singular frequency) and says nothing of the kind."""
    out = tmp_path / "h.csv"
    assert main(["frf", str(EXAMPLE), "--freqs", "0:50:11", "--out", str(out)]) == 0
    assert "free to move" not in capsys.readouterr().err
    assert np.isfinite(np.loadtxt(out, delimiter=",", skiprows=1, usecols=(3,))).all()
