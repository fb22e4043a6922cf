"""Every critical speed of a crowded run-up figure is read somewhere (issue 27, section 3: "no
label off its curve, no hidden crossing"). Where critical lines crowd closer than their labels,
some lines found no room for a label in any panel and nothing named them. A note inside the
axes lists those; checked on the drawn figure: each critical speed is read by a visible label
or by the note, and the note lies inside its axes, off the spines, over no label.
"""

from __future__ import annotations

import matplotlib
import numpy as np

from test_runup_labels13 import crowded_runup

matplotlib.use("Agg")


def _crowded_runup():
    """14 critical speeds of rotor 'a' in test_runup_labels13's run-up: twelve 10 rpm apart from
    3,500 rpm, two near 4,600 rpm."""
    rpm = np.concatenate([3500.0 + 10.0 * np.arange(12), [4600.0, 4630.0]])
    return (*crowded_runup(rpm), rpm)


def test_every_critical_speed_is_labelled_or_listed():
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.simulation import plot_runup

    result, critical, rpm = _crowded_runup()
    fig = plot_runup(result, "s", critical=critical)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        labels = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_visible() and t.get_text().startswith("mode ")]
        notes = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_visible() and "no room" in t.get_text()]
        read = set()
        for _, label in labels:
            read.add(int(label.get_text().split("mode ")[1].split(",")[0]))
        assert len(read) < len(rpm)          # the case: some lines get no label
        assert len(notes) == 1
        ax, note = notes[0]
        for entry in note.get_text().split("\n")[1:]:
            for item in entry.split("; "):
                mode = int(item.split("mode ")[1].split(",")[0])
                assert item.endswith(f": {rpm[mode - 1]:.0f}"), item
                read.add(mode)
        assert read == set(range(1, len(rpm) + 1))
        box, frame = note.get_window_extent(renderer), ax.get_window_extent(renderer)
        gaps = np.array([box.x0 - frame.x0, box.y0 - frame.y0, frame.x1 - box.x1, frame.y1 - box.y1])
        assert np.all(gaps * 72.0 / fig.dpi >= 3.0), gaps
        for other_ax, label in labels:
            if other_ax is ax:
                assert not box.overlaps(label.get_window_extent(renderer)), label.get_text()
    finally:
        plt.close(fig)


def test_a_run_up_whose_lines_are_all_labelled_has_no_note():
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.critical_speeds import _critical_table
    from rotordyn_modal.plotting.simulation import plot_runup

    result, _, _ = _crowded_runup()
    rpm = np.array([3500.0, 4600.0])
    critical = _critical_table(["a"] * 2, np.ones(2), np.arange(1, 3), rpm * np.pi / 30.0, rpm / 60.0,
                               ["forward"] * 2, np.full(2, 0.5), np.full(2, 0.01))
    fig = plot_runup(result, "s", critical=critical)
    try:
        fig.canvas.draw()
        assert not [t for ax in fig.axes for t in ax.texts if "no room" in t.get_text()]
    finally:
        plt.close(fig)
