"""Figure audit of issue 27 §3 (figs30c): critical-speed labels under ``--freq-max`` where the
modes sit low.

``campbell examples/unstable_cross_coupled.toml --speeds 0:20000:201 --orders 1,2 --freq-max 150
--plot``: the ten critical speeds lie within 12 Hz of the axis' foot, their circles 5 to 9 pixels
apart, under 140 Hz of empty axes; none was labelled ("0 of 10 ... labelled" in the note). Every
leader was refused because its line, drawn to the circle's centre, ran through the square of a
neighbouring circle it never reaches (the leader stops 4 points short of its own circle's
centre). Measured on the drawn figure at 150 dpi (``label_geometry``, exact segment geometry),
against the result's own critical speeds, never the placer's.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

import rotordyn_modal as rdm

from test_figure_audit27p import _crossed_mode_curves

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _leader_problems(fig, ax, critical, words):
    """What is wrong with the visible critical-speed labels: a label outside the axes or over
    another; a leader (as drawn) passing through the circle of a critical speed its label does not
    name (a circle whose centre lies farther than a radius from the leader's own circle)."""
    from label_geometry import glyph_box

    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    centres = ax.transData.transform(np.column_stack([critical.speeds * 30 / np.pi, critical.frequencies_hz]))
    radius = 0.5 * 6 * fig.dpi / 72.0                       # the circles: 6 points across
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    boxes = [glyph_box(t, renderer) for t in labels]
    problems = []
    for text, box in zip(labels, boxes):
        if not (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1):
            problems.append(f"outside {text.get_text()}")
    for i, a in enumerate(boxes):
        for j in range(i + 1, len(boxes)):
            if a.overlaps(boxes[j]):
                problems.append(f"{labels[i].get_text()} over {labels[j].get_text()}")
    for line in ax.get_lines():
        if line.get_gid() != "critical-leader" or not line.get_visible():
            continue
        start, end = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
        own = centres[np.argmin(np.hypot(*(centres - end).T))]
        way = end - start
        t = np.clip((centres - start) @ way / max(float(way @ way), 1e-12), 0.0, 1.0)
        through = np.hypot(*(start + t[:, None] * way - centres).T) < radius - 0.5
        named = np.hypot(*(centres - own).T) <= radius
        if np.any(through & ~named):
            problems.append(f"leader to {np.round(own)} through the circles of {sorted(set(words[through & ~named]))}")
    return problems


def test_low_critical_speeds_under_freq_max_are_labelled_in_the_empty_space_above():
    """The unstable rotor's Campbell diagram to 150 Hz (the figure as ``--freq-max 150`` draws
    it): the critical speeds of the highest mode among them (mode 6, 346 and 706 rpm, the top
    curve of the cluster with nothing but order lines above it) are labelled, their leaders
    crossing no mode's curve; no label leaves the axes or lies over another, and no leader passes
    through another critical speed's circle."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 20000.0, 201)), orders=(1, 2))
    critical = result.critical
    fig = result.plot(title=model.name, freq_range=(None, 150.0))
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    rpm = critical.speeds * 30 / np.pi
    words = np.array([f"{s:.0f}" for s in rpm])
    assert np.all(rpm >= 100.0) and np.all(critical.frequencies_hz < 150.0 / 10)   # the case: all low, 3-digit
    top = np.asarray(critical.mode) == np.asarray(critical.mode)[np.argmax(critical.frequencies_hz)]
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    written = {w for t in labels for w in t.get_text().split("/")}
    assert set(words[top]) <= written, (sorted(set(words[top])), sorted(written))
    assert not _leader_problems(fig, ax, critical, words)
    centres = ax.transData.transform(np.column_stack([rpm, critical.frequencies_hz]))
    crossed = _crossed_mode_curves(fig, ax, critical)
    for anchor in crossed:
        near = np.hypot(*(centres - np.asarray(anchor)).T) <= 1.0
        assert not np.any(near & top), (anchor, crossed[anchor])
    plt.close(fig)
