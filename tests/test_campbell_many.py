"""A Campbell diagram with more critical speeds than labels fit (issue 27, section 3): every
critical speed stays identifiable on the figure.

motor_pump_on_mounts with orders 1-4: 48 critical speeds, most of them crowded where the
order lines cross the six mount modes (5-16 Hz) below 1,000 rpm, where only some labels find
room. The figure says how many are labelled and lists the others by mode, so that each marker
can be read off: checked against the result's own table (outside the placer), on the drawn
figure (``Text.get_window_extent``, the curves as drawn, exact geometry).
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import curve_segments, outline_crossings

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
COUNT = re.compile(r"^(\d+) of (\d+) critical speeds labelled \(all in the critical-speeds table\)")


def _words(value):
    """A critical speed as the figure writes it (whole units from 100 on, three digits below)."""
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


@pytest.fixture(scope="module")
def crowded():
    result = rdm.campbell(rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"), rdm.rpm(np.linspace(0, 3600, 73)),
                          orders=(1, 2, 3, 4))
    return result


def _table(result):
    """(mode, speed as written) of each distinct marker (two sources' coinciding orders crossing
    one mode at one point make one marker)."""
    table = result.critical
    points = {}
    for mode, speed, freq in zip(table.mode, table.speeds_rpm, table.frequencies_hz):
        points.setdefault((round(speed, 6), round(freq, 6)), (int(mode), _words(speed)))
    return list(points.values())


def test_every_critical_speed_is_labelled_or_listed_by_mode(crowded):
    import matplotlib.pyplot as plt

    result = crowded
    pairs = _table(result)
    assert len(pairs) > 40
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    labelled = [w for t in texts if t.get_gid() == "critical-label" for w in t.get_text().split("/")]
    notes = [t for t in texts if t.get_gid() == "critical-note"]
    assert len(notes) == 1, "no note of the critical speeds left unlabelled"
    note = notes[0]
    head = COUNT.match(note.get_text())
    assert head, note.get_text()
    assert (int(head.group(1)), int(head.group(2))) == (len(labelled), len(pairs))
    assert 0 < len(labelled) < len(pairs)
    listed = [(int(mode), word.strip()) for mode, words in re.findall(r"mode (\d+): ([^;\n]+)", note.get_text())
              for word in words.split(",")]
    # every marker once: labelled beside it, or listed under its own mode
    assert Counter(listed) <= Counter(pairs), sorted((Counter(listed) - Counter(pairs)).elements())
    assert Counter(labelled) + Counter(w for _, w in listed) == Counter(w for _, w in pairs)
    # the note lies inside the axes, on no other text, and no curve runs through it
    frame, box = ax.get_window_extent(renderer), note.get_window_extent(renderer)
    assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
    assert not any(box.overlaps(t.get_window_extent(renderer)) for t in texts if t is not note)
    leaders = [line for line in ax.get_lines() if (line.get_gid() or "").endswith("leader")
               or (line.get_gid() or "").startswith("mode-leader")]
    assert not len(outline_crossings(note, renderer, curve_segments(ax, skip=leaders)))
    plt.close(fig)


def test_no_note_where_every_critical_speed_is_labelled(crowded):
    """Zoomed to 740-3600 rpm, the two crossings there are each labelled: no note (the others
    lie outside the axes). (From 600 rpm, '722' finds only places whose leaders run along mode
    5's line and is listed in a note instead: tests/test_leaders40.py.)"""
    import matplotlib.pyplot as plt

    fig = crowded.plot()
    ax = fig.axes[0]
    ax.set_xlim(740, 3600)
    fig.canvas.draw()
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    inside = [s for s in crowded.critical.speeds_rpm if 740 <= s <= 3600]
    assert len(inside) and len([t for t in texts if t.get_gid() == "critical-label"]) == len(inside)
    assert not [t for t in texts if t.get_gid() == "critical-note"]
    plt.close(fig)
