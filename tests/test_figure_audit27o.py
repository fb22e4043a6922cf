"""Figure audit of issue 27 (figs27o): the figures that could still mislead.

Measured on the drawn figure (the axes' limits, the lines they draw, the label boxes and the
leader lines as drawn), against the result's own numbers, never the placer's.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


# -- stability: each panel's legend names the modes it draws ------------------------------------

@pytest.mark.parametrize("example, speeds", [("unstable_cross_coupled", (0.0, 20000.0, 21)),
                                             ("motor_pump_on_mounts", (100.0, 6000.0, 12))])
def test_each_stability_panel_lists_exactly_the_coloured_modes_it_draws(example, speeds):
    """``stability unstable_cross_coupled.toml --speeds 0:20000:201``: the one legend (the top
    panel's) listed modes 6 and 2 as '(top: below the axis)', modes the top panel does not draw,
    and the bottom panel, which draws them, had no legend; motor_pump_on_mounts's modes 1 and 2
    likewise for the bottom panel. On the drawn figure, in each panel: a coloured mode (a line
    whose gid names it) has a legend entry in that panel exactly when some of its values (the
    result's real parts, log decrements) lie within the panel's limits."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / f"{example}.toml"), rdm.rpm(np.linspace(*speeds)))
    fig = result.plot()
    top, bottom = fig.axes[:2]
    coloured = {int(line.get_gid().split()[1]) for line in top.get_lines() if str(line.get_gid()).startswith("mode ")}
    off_somewhere = 0
    for ax, values in ((top, result.real_parts), (bottom, result.log_decrements)):
        legend = ax.get_legend()
        entries = [t.get_text() for t in legend.get_texts()] if legend else []
        low, high = ax.get_ylim()
        for mode in coloured:
            column = values[:, list(result.modes).index(mode)]
            inside = bool(np.any((column >= low) & (column <= high)))
            off_somewhere += not inside
            assert (f"mode {mode}" in entries) == inside, (ax.get_ylabel(), mode, inside, entries)
            assert not any(e.startswith(f"mode {mode} ") for e in entries), entries
    assert off_somewhere            # the case: some coloured mode lies off one panel
    plt.close(fig)
