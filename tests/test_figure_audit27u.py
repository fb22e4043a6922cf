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


def test_a_campbell_axis_is_not_stretched_by_modes_far_above_every_order_line():
    """flexible_pump_on_mounts: the shaft's finite-element modes reach 100 kHz, and the default
    axis ran to them: the mounts' and bearings' modes (5 Hz to 1.5 kHz) and every critical
    speed sat in the axis' bottom tenth. By default the axis is scaled to the modes below ten
    times the highest order line at the top speed (here 2X pump: 2 x 1.25 x 6000 rpm = 250 Hz,
    so 2,500 Hz); the modes above are named in a note inside the axes. Checked against the
    result's own frequencies; with freq_range given the axis is the user's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 6000.0, 7)), orders=(1, 2))
    freqs = np.where(result.oscillatory, result.frequencies_hz, np.nan)
    reach = 10 * 2 * 1.25 * 100.0                                  # Hz
    assert np.nanmax(freqs) > 10 * reach                          # modes far above (the shaft's)
    below = np.nanmax(np.where(freqs <= reach, freqs, np.nan))
    far = [m + 1 for m in range(freqs.shape[1]) if np.all(~np.isfinite(freqs[:, m]) | (freqs[:, m] > reach))]
    fig = result.plot()
    try:
        fig.canvas.draw()
        ax = fig.axes[0]
        low, high = ax.get_ylim()
        assert below < high < 2 * below, (below, high)
        notes = [t for t in ax.texts if t.get_visible() and t.get_gid() == "far-modes-note"]
        assert len(notes) == 1
        assert f"modes {far[0]}\u2013{far[-1]} above 2,500 Hz" in notes[0].get_text()
        assert far == list(range(far[0], far[-1] + 1))
        renderer = fig.canvas.get_renderer()
        box, frame = notes[0].get_window_extent(renderer), ax.get_window_extent(renderer)
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        others = [t.get_window_extent(renderer) for t in ax.texts if t.get_visible() and t is not notes[0]
                  and t.get_text()]
        assert not any(box.overlaps(o) for o in others)
    finally:
        plt.close(fig)
    fig = result.plot(freq_range=(None, 2e5))
    try:
        assert fig.axes[0].get_ylim()[1] == 2e5
        assert not [t for t in fig.axes[0].texts if t.get_gid() == "far-modes-note"]
    finally:
        plt.close(fig)
