"""Figure audit of issue 27 (figs27p): the rest of the figures that could mislead.

Measured on the drawn figure (the axes' lines, the label boxes and leader lines as drawn, exact
segment geometry: ``label_geometry``), against the result's own numbers, never the placer's.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

from test_figure_audit27o import _ray

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _crossed_mode_curves(fig, ax, critical):
    """{label text: crossing points} of the critical-speed leaders that cross a mode's curve (the
    axes' curves but the order lines, leaders and mode labels' leaders) farther than the circle's
    radius from the circle they end at."""
    from label_geometry import curve_segments, segment_crossings

    leaders = [line for line in ax.get_lines() if line.get_gid() == "critical-leader" and line.get_visible()]
    skip = [line for line in ax.get_lines() if line.get_gid() in ("critical-leader", "order-key-leader")
            or str(line.get_gid()).startswith("mode-leader") or not len(line.get_xdata()) or _ray(line)]
    modes = curve_segments(ax, skip=skip)
    markers = ax.transData.transform(np.column_stack([critical.speeds * 30 / np.pi, critical.frequencies_hz]))
    radius = 0.5 * 6 * fig.dpi / 72.0 + 0.5          # the circle's (6 points across) and half a pixel
    crossed = {}
    for line in leaders:
        start, end = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
        anchor = markers[np.argmin(np.hypot(*(markers - end).T))]
        hits = segment_crossings(start, end, modes, anchor=anchor, radius=radius)
        if len(hits):
            crossed[tuple(np.round(anchor))] = hits
    return crossed


# -- critical speeds: a leader crosses no mode's curve where a box between two curves allows it ---

@pytest.mark.parametrize("speeds", [(0.0, 15000.0, 151), (0.0, 12000.0, 121)])
def test_the_compressor_critical_speed_labels_cross_no_modes_curve(speeds):
    """``critical-speeds examples/compressor_rotor.toml --speeds 0:15000:151 --plot`` (150 dpi):
    the '11115' leader rose from its circle on mode 3 across modes 4 and 5, 4 to 7 pixels apart
    (the placer's grid of curves merged the three lines into one run, read as the circle's own),
    where the 23 pixels below right, between modes 3 and 2, held the label (no row of boxes met
    that gap). On the drawn figure: '11115' is labelled and its leader crosses no mode's curve
    beyond its circle (on figs27o's grid of 121 speeds, no leader does), and every critical
    speed is read in a label or in the note of those left out ('14388', whose only boxes hang
    across modes 3 and 4, is listed there)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(*speeds)), orders=(1,))
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    assert any("11115" in t.get_text() for t in labels), [t.get_text() for t in labels]
    crossed = _crossed_mode_curves(fig, ax, result.critical)
    eleven = ax.transData.transform((11114.7, result.critical.frequencies_hz[np.argmin(
        np.abs(result.critical.speeds * 30 / np.pi - 11114.7))]))
    assert not any(np.hypot(*(np.array(a) - eleven)) < 2 for a in crossed), crossed
    if speeds[2] == 121:
        assert not crossed, crossed
    # each critical speed is read somewhere: its label, or the note listing those left out
    words = {w for t in labels for w in t.get_text().split("/")}
    note = " ".join(t.get_text() for t in ax.texts if t.get_gid() == "critical-note" and t.get_visible())
    for speed in result.critical.speeds * 30 / np.pi:
        assert f"{speed:.0f}" in words or f"{speed:.0f}" in note, (speed, words, note)
    plt.close(fig)


def test_the_gear_machines_critical_speed_413_is_labelled_and_no_leader_crosses_a_mode():
    """``critical-speeds examples/gear_machine.toml --speeds 0:12000:241 --orders 1,2 --plot``:
    '413' (mode 3, 2X motor) was left out (20 of 36 labelled, the note listing it), its only boxes
    in the label-height rows lying across mode 3's or mode 4's line; a box between the two lines,
    above left, takes it. On the drawn figure (150 dpi): '413' is labelled, and no critical-speed
    leader crosses a mode's curve beyond its circle."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 241)), orders=(1, 2))
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    words = [w for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible() for w in t.get_text().split("/")]
    assert "413" in words, words
    assert not _crossed_mode_curves(fig, ax, result.critical)
    plt.close(fig)


# -- UCS map: crowded crossings, each labelled, no leader across a mode's curve --------------------

def test_the_fans_crowded_ucs_crossings_are_each_labelled_with_no_leader_across_a_mode(ucs_figure):
    """``ucs-map examples/fan_on_bearings.toml --stiffness 1e5:1e9:41 --plot`` (150 dpi): the
    3e6 N/m line meets modes 5, 7 and 8 at 3394, 3644 and 3943 rpm, circles within 12 pixels;
    '3644' took a box above left, its leader across mode 8's line, and '3943' (3e6) one below
    right, its leader across modes 5 and 7 and two bearing lines, because '3394' (placed first)
    had taken the one box of '3644' whose leader crosses no curve; and the 4.5e6 N/m crossing
    with mode 7 at 4184 rpm had no label at all. On the drawn figure: every crossing is labelled,
    and no leader of a crossing on the 3e6 N/m line crosses a mode's curve (a line the legend
    names '<number> <name>') beyond its circle."""
    import matplotlib.pyplot as plt
    from label_geometry import curve_segments, glyph_box, segment_crossings

    result, fig = ucs_figure("fan_on_bearings", (1e5, 1e9, 41))     # plotted once with test_figure_audit27r's
    fig.set_dpi(150)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    modes = [line for line in ax.get_lines() if str(line.get_label())[:1].isdigit()]
    assert modes
    segments = curve_segments(ax, skip=[line for line in ax.get_lines() if line not in modes] + list(ax.collections))
    # circles that lie on each other share a label ('3939/3959', figs27r): each speed is a word
    labels = {(round(float(t.xy[0]), 3), word): t for t in ax.texts
              if t.get_gid() != "ucs-end-name" and t.arrow_patch is not None
              for word in t.get_text().replace("\n", "").split("/")}      # a label may stand on two lines
    crossings = {(round(c.stiffness, 3), f"{c.speed * 30 / np.pi:.0f}") for c in result.crossings}
    # ... and circles side by side on two stiffness lines that touch (figs27r): such a label's
    # point is one of them, the others within a circle's width (6 points) of it
    touching = 6 * fig.dpi / 72.0 + 0.5
    shared = {(k, w) for k, w in crossings - set(labels) for (k2, w2), t in labels.items()
              if w2 == w and np.hypot(*(ax.transData.transform((k, float(w))) - ax.transData.transform(t.xy)))
              <= 2 * touching}
    assert crossings - shared <= set(labels), crossings - shared - set(labels)
    radius = 0.5 * 6 * fig.dpi / 72.0 + 0.5
    crowded = list({id(t): t for (k, _), t in labels.items() if abs(k - 3e6) < 1.0}.values())
    assert len(crowded) >= 4
    for text in crowded:
        box = glyph_box(text, renderer)
        anchor = ax.transData.transform(text.xy)
        start = (min(max(anchor[0], box.x0), box.x1), min(max(anchor[1], box.y0), box.y1))
        hits = segment_crossings(start, anchor, segments, anchor=anchor, radius=radius)
        assert not len(hits), (text.get_text(), hits)
    plt.close(fig)


# -- mode shapes: damping written as it is -------------------------------------------------------

@pytest.mark.parametrize("damping, words", [(1.7e-8, "ζ = 1.7e-08"), (-3e-18, "ζ = 0,"), (2.3e-4, "ζ = 2.3e-04"),
                                            (-2.3e-4, "ζ = -2.3e-04"), (0.0599533, "ζ = 0.060")])
def test_the_mode_shape_titles_write_the_damping_as_it_is(damping, words):
    """``modes ... --shape 61`` titled a mode of damping ratio 1.7e-8 'ζ = 0.0000' (four decimals),
    and the shaft lines' panels wrote every ratio under 5e-4 as 0.000 (an unstable -2.3e-4 as
    stable 0); round-off (-3e-18) must not read '-0'. Both titles (the 3-D view's and a shaft
    panel's) of compressor_rotor's first mode, its damping ratio set to ``damping``."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d, shaft_lines

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.modal(model, rdm.rpm(3000.0))
    for view, draw in ((mode_shape_3d(result, model, 1), rdm.plotting.plot_mode_shape),
                       (shaft_lines(result, model, 1), lambda v: rdm.plotting.plot_shaft_modes([v]))):
        fig = draw(dataclasses.replace(view, damping_ratio=damping))
        titles = [ax.get_title() for ax in fig.axes if "ζ" in ax.get_title()]
        assert titles and all(words in t for t in titles), titles
        plt.close(fig)
