"""The UCS map of a machine with more bearings of distinct constant stiffness than its colours
(issue 29 §7: the 30-rotor gear chain's report stopped at its page).

Each constant bearing's stiffness is a vertical line of its own colour; the colours were a list
of 6 taken 4 times, and ``next`` past its end raised StopIteration (RuntimeError in the report's
``render_html``) from the 25th line on. The colours now repeat.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib
import numpy as np

import rotordyn_modal as rdm

matplotlib.use("Agg")
sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402


def test_a_ucs_map_with_more_bearing_values_than_colours_is_drawn(tmp_path):
    import matplotlib.pyplot as plt
    from rotordyn_modal.analysis.ucs_map import ucs_map

    path = tmp_path / "chain25.toml"
    path.write_text(chained_gear_toml(25, 25))
    model = rdm.load_model(path)
    result = ucs_map(model, np.geomspace(1e5, 1e10, 11), modes=2)
    values = {float(v) for c in result.curves if c.constant for v in (c.kxx[0], c.kyy[0])}
    assert len(values) > 24                                       # more lines than 6 colours x 4
    fig = result.plot()
    lines = [line for line in fig.axes[0].get_lines() if line.get_linestyle() == "-."]
    assert len(lines) == len(values)                              # one vertical line a value
    plt.close(fig)
