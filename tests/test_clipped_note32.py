"""The FRF figure's note on curves below the axis gives the axis's bottom in the axis's unit
(issue 27 §3: a number without its unit; issue 29 §6: the SI and US pages showed '1.7e-04' and
'6.5e-06' with nothing to say which unit)."""

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("units", ["si", "us"])
def test_the_clipped_note_names_the_axis_unit(units):
    """``frf rubber_mounts.toml --speed 3000 --freqs 1:1000:600 --plot``: a curve runs below the
    magnitude axis; the note's number is the axis's bottom as drawn, followed by the unit in the
    axis label's brackets."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.frf import frf
    from rotordyn_modal.cli.frf import _input_kinds

    model = rdm.load_model(EXAMPLES / "rubber_mounts.toml")
    result = frf(model, rdm.rpm(3000.0), np.linspace(1.0, 1000.0, 600))
    fig = result.plot(input_kinds=_input_kinds(model), **({"units": units} if units != "si" else {}))
    try:
        fig.canvas.draw()
        notes = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_gid() == "clipped-note"]
        assert notes, "the case: a curve below the axis"
        for ax, note in notes:
            unit = ax.get_ylabel().rsplit("[", 1)[1].rstrip("] ")
            assert unit
            text = note.get_text()
            assert text.endswith(f" {unit})"), (text, ax.get_ylabel())
            number = float(text.split("clipped at ")[1].split()[0])
            assert number == pytest.approx(ax.get_ylim()[0], rel=0.05)
    finally:
        plt.close(fig)
