"""Figures of the fifth audit (issue 27, section 3), measured on the drawn figure
(``fig.canvas.draw()``), independent of the code that places things.

Campbell diagrams of the geared examples at 0-12000 rpm with orders 1-4: the steep order lines
(the gear mesh's, the motor's 1X, the fan's 3X) had no label, because the label written along
a line was tested with the axis-aligned box around the turned text. Here each text's own
outline is rebuilt from the figure (its box as drawn, its angle and its unturned size: the
rectangle inscribed in the box) and every order line must be named: by a label inside the
axes whose centre is nearer one of the lines it names than any other order line, or by a key
above the axes joined by a leader line to the top exit of a line it names.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from campbell_orders import drawn_campbell
from label_geometry import curve_segments, outline, outlines_overlap, point_segment_distance

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _curve_through(polygon, segments) -> bool:
    """Whether any of ``segments`` (n, 4) runs through the convex ``polygon`` shrunk by half a
    pixel (Cyrus-Beck: each segment clipped by the polygon's edges)."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    area = np.sum(polygon[:, 0] * np.roll(polygon[:, 1], -1) - np.roll(polygon[:, 0], -1) * polygon[:, 1])
    outward = np.sign(area) * np.column_stack([edges[:, 1], -edges[:, 0]])
    outward /= np.hypot(outward[:, 0], outward[:, 1])[:, None]
    limit = np.sum(polygon * outward, axis=1) - 0.5                  # (E,) inside: p . n < limit
    start, step = segments[:, :2], segments[:, 2:] - segments[:, :2]
    a, b = start @ outward.T - limit, step @ outward.T              # (S, E): a + t b < 0 inside
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -a / b
    low = np.max(np.where(b < 0, t, 0.0), axis=1, initial=0.0)
    high = np.min(np.where(b > 0, t, 1.0), axis=1, initial=1.0)
    parallel_out = np.any((b == 0) & (a >= 0), axis=1)
    return bool(np.any((low < high) & ~parallel_out))


@pytest.mark.parametrize("model", ["gear_machine.toml", "rubber_mounts.toml"])
def test_every_order_line_is_named_beside_itself(model):
    """gear_machine and rubber_mounts, 0-12000 rpm, orders 1-4 (12 order lines: the mesh's
    four within 1 % of the width, the motor's and the fan's steep lines between): every order
    line drawn is named. A label inside the axes lies inside them, no curve runs through its
    turned outline, and the order line nearest its centre is one it names; a key above the
    axes lies inside the figure, clear of the axes and the title, its leader line running
    from the key's bottom edge to the top exit of a line it names. No two texts of the axes
    (order, mode and critical-speed labels, keys) overlap, compared by their turned
    outlines."""
    import matplotlib.pyplot as plt

    drawn = drawn_campbell(model)
    fig, ax, renderer, frame, lines = drawn.fig, drawn.ax, drawn.renderer, drawn.frame, drawn.lines
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    outlines = [outline(t, renderer) for t in texts]
    for i, a in enumerate(outlines):
        for j in range(i + 1, len(outlines)):
            assert not outlines_overlap(a, outlines[j]), (texts[i].get_text(), texts[j].get_text())
    segments = curve_segments(ax)
    leaders = [line for line in ax.get_lines() if line.get_visible() and len(line.get_xdata()) == 2]
    title = ax.title.get_window_extent(renderer)
    named = set()
    for text, corners in zip(texts, outlines):
        mine = drawn.named_slopes(text.get_text())
        if mine is None:
            continue
        if np.all((corners >= (frame.x0, frame.y0)) & (corners <= (frame.x1, frame.y1))):
            assert not _curve_through(corners, segments), text.get_text()
            centre = corners.mean(axis=0)
            nearest = min(lines, key=lambda s: point_segment_distance(lines[s][0], centre))
            assert nearest in mine, (text.get_text(), nearest, mine)
        else:                               # a key above the axes, joined to its line's exit
            box = text.get_window_extent(renderer)
            assert box.y0 > frame.y1 and fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 \
                and box.y1 <= fig.bbox.y1, text.get_text()
            assert not box.overlaps(title), text.get_text()
            ends = [line.get_transform().transform(np.column_stack(line.get_data())) for line in leaders]
            joined = [e for e in ends if any(abs(p[1] - box.y0) < 1.0 and box.x0 - 1 <= p[0] <= box.x1 + 1 for p in e)]
            assert joined, text.get_text()
            exits = {s: lines[s][0][1] for s in mine if abs(lines[s][0][1][1] - frame.y1) < 1.0}
            assert any(np.hypot(*(p - exit_)) < 1.0 for e in joined for p in e for exit_ in exits.values()), \
                text.get_text()
        named |= mine
    assert named == set(lines), sorted(set(lines) - named)
    plt.close(fig)


# -- one panel of FRFs: a wide legend above the panel, not beside it -----------------------------

def _single_panel_frfs():
    """motor_pump_on_mounts' 8 FRFs (4 sensors x 2 excitations, names of 25 characters, '(= ...)'
    notes); motor_fan_minimal's 12 mount forces (equal by symmetry: the notes come at the
    first drawing)."""
    pump = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    yield "pump", rdm.frf(pump, rdm.rpm(3000), np.geomspace(1.0, 1500.0, 60))
    minimal = rdm.load_model(EXAMPLES / "motor_fan_minimal.toml")
    yield "minimal", rdm.force_frf(minimal, 0.0, np.linspace(1.0, 100.0, 300), where="suspensions")


def test_one_panel_of_frfs_keeps_the_width_its_legend_above():
    """The single-panel FRF figure kept its legend beside the panel whatever its width: the
    panels took 52 % of the figure (motor_pump_on_mounts, 8 FRFs). On the drawn figure: each
    panel is at least 80 % as wide as the figure; the legend lies inside the figure, overlaps
    no panel and not the title, and names every curve."""
    import matplotlib.pyplot as plt

    for name, result in _single_panel_frfs():
        fig = result.plot()
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        axes = [ax for ax in fig.axes if ax.get_visible()]
        assert len(axes) == 2, name
        for ax in axes:
            assert ax.bbox.width >= 0.8 * fig.bbox.width, (name, ax.bbox.width / fig.bbox.width)
        legend = axes[0].get_legend()
        box = legend.get_window_extent(renderer)
        frame = fig.bbox
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, name
        assert not any(box.overlaps(ax.bbox) for ax in axes), name
        title = axes[0].title.get_window_extent(renderer)
        assert not box.overlaps(title), name
        named = {t.get_text() for t in legend.get_texts()}
        curves = [line.get_label() for line in axes[0].get_lines() if not line.get_label().startswith("_")]
        assert len(curves) >= 8 and set(curves) <= named, (name, set(curves) - named)
        plt.close(fig)


# -- unbalance peaks: leader lines that cross each other -----------------------------------------

def test_unbalance_peak_leaders_do_not_cross_each_other():
    """motor_pump_on_mounts, 0-6000 rpm (the command line's figure: sensor panels by kind): the
    casing panel's 'AF 9.7 at 320 rpm' and 'AF 13.7 at 260 rpm' had leader lines crossing each
    other, each label seeming to point at the other's peak. On the drawn figure: no two leader
    lines of one panel cross (exact segment intersection), and each leader ends at a peak
    marker of the speed its label reads."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.cli.unbalance import sensor_groups

    pump = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    result = rdm.unbalance_response(pump, rdm.rpm(np.linspace(0.0, 6000.0, 301)))
    fig = result.plot(peaks=result.peaks(None), groups=sensor_groups(pump))
    fig.canvas.draw()
    total = 0
    for ax in fig.axes:
        labels = [t for t in ax.texts if t.get_visible() and t.get_text().startswith("AF ")]
        segments = []
        for label in labels:
            start = label.arrow_patch.get_path().vertices[0]
            anchor = ax.transData.transform(label.xy)
            assert f"at {label.xy[0]:.0f} rpm" in label.get_text(), (label.get_text(), label.xy)
            segments.append((start, anchor))
        total += len(segments)
        for i, (a, b) in enumerate(segments):
            for c, d in segments[i + 1:]:
                def side(p, q, r):
                    return np.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))
                assert not (side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0), \
                    [t.get_text() for t in labels]
    assert total >= 3
    plt.close(fig)


def test_orbit_tick_labels_do_not_run_into_each_other():
    """motor_pump_on_mounts, 0-6000 rpm: the motor's orbit (8 nm) had nine tick labels across
    ('-0.0075-0.0050-0.0025 0.0000 ...' printed over each other). On the drawn figure no two
    tick labels of an axis overlap."""
    import matplotlib.pyplot as plt

    pump = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    fig = rdm.unbalance_response(pump, rdm.rpm(np.linspace(0.0, 6000.0, 61))).plot_orbits()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        for ticks in (ax.get_xticklabels(), ax.get_yticklabels()):
            boxes = [t.get_window_extent(renderer) for t in ticks if t.get_visible() and t.get_text()]
            assert len(boxes) >= 3
            for i, a in enumerate(boxes):
                assert not any(a.overlaps(b) for b in boxes[i + 1:]), [t.get_text() for t in ticks]
    plt.close(fig)


def test_a_log_frequency_axis_of_under_two_decades_reads_between_them():
    """gear_machine's FRF from 1 to 60 Hz (the help's example) had two labelled frequencies,
    '10^0' and '10^1': the peaks at 14 and 26 Hz could not be read off. On the drawn figure the
    frequency axis labels at least four frequencies inside its range, as plain numbers, no two
    labels overlapping."""
    import matplotlib.pyplot as plt

    gear = rdm.load_model(EXAMPLES / "gear_machine.toml")
    fig = rdm.frf(gear, rdm.rpm(3000), np.linspace(1.0, 60.0, 120), outputs=["acc-top-z"],
                  inputs=["hammer-z"]).plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[-1]
    lo, hi = ax.get_xlim()
    labels = [t for t in ax.get_xticklabels(which="both")
              if t.get_visible() and t.get_text() and lo <= t.get_position()[0] <= hi]
    texts = [t.get_text() for t in labels]
    assert len(labels) >= 4 and all(re.fullmatch(r"\d+(\.\d+)?", text) for text in texts), texts
    boxes = [t.get_window_extent(renderer) for t in labels]
    for i, a in enumerate(boxes):
        assert not any(a.overlaps(b) for b in boxes[i + 1:]), texts
    plt.close(fig)
