"""Figures of the seventh audit (issue 27, section 3: figures that cannot mislead), measured on
the drawn figure, independent of the code that draws it: the 3-D mode shapes of ``modes
--shape``, the model-over-measurement FRF of ``frf --measured``, the study figures and the
run-up of ``simulate --ramp``.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("model, mode", [("spring_block_rotor.toml", 1), ("fan_on_bearings.toml", 5)])
def test_mode_shape_legend_names_every_displaced_colour(model, mode):
    """The legend's 'displaced' entries show exactly the colours the displaced bodies are drawn
    in: a machine of rotors only (the spring block's rotor, the compressor's shaft: orange) had
    one blue 'displaced' entry and no orange one; a stator (blue) and rotors (orange) get one
    entry each."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    machine = rdm.load_model(EXAMPLES / model)
    view = mode_shape_3d(rdm.modal(machine, rdm.rpm(3000.0)), machine, mode)
    fig = plot_mode_shape(view, orbits=False, labels=False, projections=False)
    ax = fig.axes[0]
    drawn = {matplotlib.colors.to_hex(line.get_color()) for line in ax.get_lines()
             if str(line.get_gid()).startswith("displaced") and not str(line.get_gid()).startswith("displaced-")
             or str(line.get_gid()).startswith("displaced-bracket")}
    keyed = {matplotlib.colors.to_hex(handle.get_color()) for handle in ax.get_legend().legend_handles
             if "displaced" in handle.get_label()}
    assert drawn and keyed == drawn
