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
import pytest

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
    it): at least two of the ten critical speeds are labelled, one of them on the highest mode
    among them (mode 6, 346 and 706 rpm, the top curve of the cluster with nothing but order
    lines above it); no leader crosses a mode's curve beyond its circle; no label leaves the axes
    or lies over another, and no leader passes through another critical speed's circle. (346 lies
    2 pixels from 333, a circle of another group: a leader to it would end as near 333's circle.)"""
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
    assert len(written & set(words)) >= 2 and written & set(words[top]), (sorted(set(words[top])), sorted(written))
    assert not _leader_problems(fig, ax, critical, words)
    assert not _crossed_mode_curves(fig, ax, critical)
    plt.close(fig)


@pytest.mark.parametrize("example, speeds, words", [
    ("compressor_on_journals", (500.0, 12000.0, 116), {"5044", "5099"}),
    ("counter_rotating", (0.0, 6000.0, 121), {"1663", "1700"})])
def test_circles_side_by_side_under_freq_max_get_leaders_that_end_at_their_own(example, speeds, words):
    """``campbell examples/compressor_on_journals.toml --speeds 500:12000:116 --orders 1,2
    --freq-max 150``: 5044 and 5099 rpm (1X across modes 3 and 4), circles overlapping, were left
    to the note under empty axes, although the plain Campbell diagram labels them;
    counter_rotating.toml 0:6000:121: 1663 and 1700 likewise. On the drawn figure (150 dpi): both
    are labelled, no leader crosses a mode's curve, passes through another circle, and each
    leader ends nearer its own circle's centre than any other critical speed's."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(*speeds)), orders=(1, 2))
    critical = result.critical
    fig = result.plot(title=model.name, freq_range=(None, 150.0))
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    rpm = critical.speeds * 30 / np.pi
    text = np.array([f"{s:.0f}" if s >= 100 else f"{s:.3g}" for s in rpm])
    written = {w for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible() for w in t.get_text().split("/")}
    assert words <= written, sorted(written)
    assert not _leader_problems(fig, ax, critical, text)
    centres = ax.transData.transform(np.column_stack([rpm, critical.frequencies_hz]))
    for label in ax.texts:
        if label.get_gid() != "critical-label" or not label.get_visible() or not set(label.get_text().split("/")) & words:
            continue
        ends = [line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))[1]
                for line in ax.get_lines() if line.get_gid() == "critical-leader" and line.get_visible()]
        box = label.get_window_extent(fig.canvas.get_renderer())
        leader = [e for e, line in zip(ends, [l for l in ax.get_lines() if l.get_gid() == "critical-leader"
                                              and l.get_visible()])
                  if box.x0 - 2 <= line.get_transform().transform((line.get_xdata()[0], line.get_ydata()[0]))[0] <= box.x1 + 2
                  and box.y0 - 2 <= line.get_transform().transform((line.get_xdata()[0], line.get_ydata()[0]))[1] <= box.y1 + 2]
        for end in leader:
            distance = np.hypot(*(centres - end).T)
            nearest = text[np.argmin(distance)]
            assert nearest in label.get_text().split("/"), (label.get_text(), nearest)
    plt.close(fig)
