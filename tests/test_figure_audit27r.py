"""Figure audit of issue 27 §3 (figs27r): labels whose leaders crossed a mode's curve, or ran
through another crossing's circle, where the greedy placement lost.

Measured on the drawn figure at 150 dpi (the axes' lines, the label boxes and leader lines as
drawn, exact segment geometry: ``label_geometry``), against the result's own numbers (its
crossings and critical speeds), never the placer's.
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


def _ucs_label_problems(result, fig):
    """What is wrong with a UCS map's crossing labels, drawn at the figure's dpi: a crossing whose
    speed no label writes; a label outside the axes or over another; a leader (from the glyph
    box's nearest point to its point) that crosses a mode's curve (a line the legend names
    '<number> <name>') beyond its circle, or passes through the circle of a crossing it does not
    name (a circle whose centre lies outside its own)."""
    from label_geometry import curve_segments, glyph_box, segment_crossings

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    frame = ax.get_window_extent(renderer)
    modes = [line for line in ax.get_lines() if str(line.get_label())[:1].isdigit()]
    segments = curve_segments(ax, skip=[line for line in ax.get_lines() if line not in modes] + list(ax.collections))
    radius = 0.5 * 6 * fig.dpi / 72.0                       # the circles: 6 points across
    rpm = np.array([c.speed * 30 / np.pi for c in result.crossings])
    centres = ax.transData.transform(np.column_stack([[c.stiffness for c in result.crossings], rpm]))
    words = np.array([f"{s:.0f}" for s in rpm])
    labels = [t for t in ax.texts if t.get_gid() != "ucs-end-name" and t.arrow_patch is not None and t.get_visible()
              and t.get_text().replace("/", "").replace("\n", "").isdigit() and len(t.get_text()) >= 3]
    problems = [f"unlabelled {w}" for w in sorted(set(words) - {w for t in labels for w in t.get_text().replace("\n", "").split("/")})]
    boxes = [glyph_box(t, renderer) for t in labels]
    for text, box in zip(labels, boxes):
        name = text.get_text()
        if not (frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1):
            problems.append(f"outside {name}")
        anchor = ax.transData.transform(text.xy)
        start = np.array([min(max(anchor[0], box.x0), box.x1), min(max(anchor[1], box.y0), box.y1)])
        if len(segment_crossings(start, anchor, segments, anchor=anchor, radius=radius + 0.5)):
            problems.append(f"{name} crosses a mode")
        way = anchor - start
        t = np.clip((centres - start) @ way / max(float(way @ way), 1e-12), 0.0, 1.0)
        through = np.hypot(*(start + t[:, None] * way - centres).T) < radius - 0.5
        others = (np.hypot(*(centres - anchor).T) > radius) & ~np.isin(words, name.replace("\n", "").split("/"))
        if np.any(through & others):
            problems.append(f"{name} through the circle of {sorted(set(words[through & others]))}")
    for i, a in enumerate(boxes):
        for j in range(i + 1, len(boxes)):
            if a.overlaps(boxes[j]):
                problems.append(f"{labels[i].get_text()} over {labels[j].get_text()}")
    return problems


@pytest.mark.parametrize("example, stiffness", [("compressor_on_journals", (1e5, 1e10, 41)),
                                                ("fan_on_bearings", (1e5, 1e9, 41))])
def test_ucs_crossing_labels_cross_no_mode_and_no_other_circle(example, stiffness, ucs_figure):
    """``ucs-map examples/compressor_on_journals.toml --stiffness 1e5:1e10:41 --plot``: '31385'
    stood 93 pixels right of its circle, its leader across mode 3's line, because '31284' (its
    Kxx twin, a circle on the same point) took the row beside it; ``ucs-map
    examples/fan_on_bearings.toml --stiffness 1e5:1e9:41 --plot``: at 4e6 and 4.5e6 N/m five
    circles lie within 10 pixels, and the leaders of '3959' and '3939' ran through the circles of
    '4184' and '3943' beside them, as if naming them. On the drawn figure (150 dpi): every
    crossing's speed is written, each label inside the axes and over no other, and no leader
    crosses a mode's curve beyond its circle or passes through the circle of a crossing its
    label does not name."""
    import matplotlib.pyplot as plt

    result, fig = ucs_figure(example, stiffness)      # the fan's plotted once with test_figure_audit27p's
    fig.set_dpi(150)
    assert not _ucs_label_problems(result, fig)
    plt.close(fig)


def _critical_figure(example, speeds, orders):
    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(*speeds)), orders=orders)
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    return result, fig, fig.axes[0]


def test_the_compressors_12938_is_labelled_with_a_leader_across_no_mode():
    """``critical-speeds examples/compressor_rotor.toml --speeds 0:15000:151 --plot``: '12938'
    lies on mode 4 between modes 5 and 3, 6 and 8 pixels from it; its label stood 58 pixels
    left, its leader across mode 5's line (the box straight above, reached by a leader that meets
    mode 5 inside the circle, was never tried). On the drawn figure: '12938' is labelled, and no
    critical-speed leader crosses a mode's curve beyond its circle."""
    import matplotlib.pyplot as plt

    result, fig, ax = _critical_figure("compressor_rotor", (0.0, 15000.0, 151), (1,))
    words = [w for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible() for w in t.get_text().split("/")]
    assert "12938" in words, words
    assert not _crossed_mode_curves(fig, ax, result.critical)
    plt.close(fig)


def test_the_gear_machines_561_is_labelled_clear_of_every_curve():
    """``critical-speeds examples/gear_machine.toml --speeds 0:12000:241 --orders 1,2 --plot``:
    '561' (mode 2, 8 pixels above mode 1's line, between two order lines 20 pixels apart) was
    left to the note, every box beside its circle lying across an order line or with a leader
    across mode 1; a box straight above it, its leader up between the order lines, is clear. On
    the drawn figure: '561' is labelled, no curve (order lines included) runs through a
    critical-speed label beyond its circle, and no leader crosses a mode's curve."""
    import matplotlib.pyplot as plt
    from label_geometry import crossings, curve_segments, glyph_box

    result, fig, ax = _critical_figure("gear_machine", (0.0, 12000.0, 241), (1, 2))
    renderer = fig.canvas.get_renderer()
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    words = [w for t in labels for w in t.get_text().split("/")]
    assert "561" in words, words
    assert not _crossed_mode_curves(fig, ax, result.critical)
    segments = curve_segments(ax, skip=[line for line in ax.get_lines() if line.get_gid() == "critical-leader"])
    markers = ax.transData.transform(np.column_stack([result.critical.speeds * 30 / np.pi,
                                                      result.critical.frequencies_hz]))
    for text in labels:
        hits = crossings(glyph_box(text, renderer), segments, markers, 0.5 * 6 * fig.dpi / 72.0 + 1.0)
        assert not len(hits), (text.get_text(), hits)
    plt.close(fig)


def test_a_flexible_rotors_mode_bars_draw_the_lowest_modes_on_a_readable_page():
    """``rdm.modal(compressor_rotor, 3000 rpm).plot()`` drew a panel of 56 bars (node
    coordinates) for each of its 53 modes, three panels a row: a figure of 59 x 47 inches. Now,
    where a panel has more than 24 bars, the lowest six modes (the figure's title says which of
    how many), as many panels a row as fit 24 inches; asked for, every mode is still drawn."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.modal(model, rdm.rpm(3000.0))
    oscillatory = int(result.oscillatory.sum())
    assert oscillatory > 6 and len(result.dof_names) > 24
    fig = result.plot()
    panels = [ax for ax in fig.axes if ax.get_visible() and ax.get_title().startswith("mode ")]
    assert [ax.get_title().split(":")[0] for ax in panels] == [f"mode {n}" for n in range(1, 7)]
    width, height = fig.get_size_inches()
    assert width <= 24.0 and height <= 24.0, (width, height)
    assert f"1\u20136 of {oscillatory}" in fig._suptitle.get_text()
    plt.close(fig)
    fig = result.plot(modes=range(1, oscillatory + 1))
    assert len([ax for ax in fig.axes if ax.get_visible() and ax.get_title().startswith("mode ")]) == oscillatory
    plt.close(fig)
