"""Figure audit of issue 27 §3 (figs31): critical-speed labels that name their own circle.

A reader takes a critical speed's label for the circle it stands nearest, its leader line
notwithstanding: on ``campbell examples/gear_machine.toml --speeds 0:12000:241 --orders 1,2``
the label '1420' (its leader to the 1420 rpm circle) stood 13 pixels from the 710 rpm circle and
18.5 from its own, '1554' 18.4 pixels from the 777 rpm circle, '498' 11 pixels from the 995 rpm
circle (150 dpi); rubber_mounts' '1619' stood 21 pixels from the 809 rpm circle, 18.5 from its own.

Measured on the drawn figure (150 dpi, as the command line saves it) with exact geometry
(``label_geometry``), against the result's own critical speeds (``result.critical``), never the
placer's: for every visible critical-speed label

- its box lies :data:`NEAREST_OWN` times as far from the centre of every other circle as from its
  own (at the end of a leader: so, or :data:`BESIDE_POINTS` from it), so that the label names
  the circle it stands beside;
- its leader's end lies :data:`NEAREST_OWN` times as far from every other circle's centre as
  from its own;
- no mode's curve runs through its text but inside its own circle.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: a leader's end, or a leaderless label's box, lies this many times as far from any other circle
#: as from its own (the placer's ``campbell._NEAREST_OWN``, stated here on its own)
NEAREST_OWN = 1.25
#: a label at the end of a leader within this many points of another circle, and less than
#: NEAREST_OWN times as far from its own, reads as that circle's (a label without a leader stands
#: 4 points from its circle's centre)
BESIDE_POINTS = 11.0
#: the circles: 6 points across
_CIRCLE_POINTS = 6.0


def _words(rpm):
    return np.array([f"{s:.0f}" if abs(s) >= 100 else f"{s:.3g}" for s in rpm])


def _box_distances(box, points):
    """Distance [pixels] from each of ``points`` (n, 2) to the box (0 inside it)."""
    dx = np.maximum(np.maximum(box.x0 - points[:, 0], points[:, 0] - box.x1), 0.0)
    dy = np.maximum(np.maximum(box.y0 - points[:, 1], points[:, 1] - box.y1), 0.0)
    return np.hypot(dx, dy)


def _mode_segments(ax):
    """The drawn segments of the modes' curves: the axes' curves but the order lines (rays from
    the origin), leader lines and keys' leaders."""
    from label_geometry import curve_segments
    from test_figure_audit27o import _ray

    skip = [line for line in ax.get_lines() if line.get_gid() in ("critical-leader", "order-key-leader", "order-line")
            or str(line.get_gid()).startswith("mode-leader") or not len(line.get_xdata()) or _ray(line)]
    return curve_segments(ax, skip=skip)


def misread_labels(fig, ax, critical):
    """What a reader would misread among the visible critical-speed labels (list of sentences):
    a label nearer another circle than its own, a leader ending nearer another circle, a mode's
    curve through a label's text."""
    from label_geometry import crossings, glyph_box

    renderer = fig.canvas.get_renderer()
    rpm = critical.speeds * 30 / np.pi
    centres = ax.transData.transform(np.column_stack([rpm, critical.frequencies_hz]))
    frame = ax.get_window_extent(renderer)
    inside = (centres[:, 0] >= frame.x0 - 0.5) & (centres[:, 0] <= frame.x1 + 0.5) \
        & (centres[:, 1] >= frame.y0 - 0.5) & (centres[:, 1] <= frame.y1 + 0.5)
    words = _words(rpm)
    radius = 0.5 * _CIRCLE_POINTS * fig.dpi / 72.0
    segments = _mode_segments(ax)
    leaders = [line.get_transform().transform(np.column_stack(line.get_data()))[[0, -1]]
               for line in ax.get_lines()
               if line.get_gid() == "critical-leader" and line.get_visible() and len(line.get_xdata())]
    problems = []
    for text in ax.texts:
        if text.get_gid() != "critical-label" or not text.get_visible():
            continue
        box = glyph_box(text, renderer)
        named = [w.rstrip("?") for w in text.get_text().split("/")]
        leader = next((end for start, end in leaders
                       if box.x0 - 1 <= start[0] <= box.x1 + 1 and box.y0 - 1 <= start[1] <= box.y1 + 1), None)
        to_box = _box_distances(box, centres)
        reach = to_box if leader is None else np.hypot(*(centres - leader).T)
        # its own circles: those of the speeds it reads, nearest its leader's end (or box) first, and
        # any of those words lying on one of them (circles drawn on each other)
        candidates = np.flatnonzero(np.isin(words, named) & inside)
        assert len(candidates), (text.get_text(), "reads no critical speed of the figure")
        own = candidates[np.argsort(reach[candidates], kind="stable")][:len(named)]
        own = candidates[np.min(np.hypot(*(centres[candidates][:, None] - centres[own][None]).transpose(2, 0, 1)),
                                axis=1) <= radius]
        others = np.setdiff1d(np.flatnonzero(inside), own)
        if not len(others):
            continue
        nearest = others[np.argmin(to_box[others])]
        least = NEAREST_OWN * to_box[own].min() if leader is None \
            else min(NEAREST_OWN * to_box[own].min(), BESIDE_POINTS * fig.dpi / 72.0)
        if to_box[nearest] < least:
            problems.append(f"'{text.get_text()}' stands {to_box[nearest]:.1f} px from the {words[nearest]} circle, "
                            f"{to_box[own].min():.1f} px from its own")
        if leader is not None:
            nearest = others[np.argmin(reach[others])]
            if reach[nearest] < NEAREST_OWN * reach[own].min():
                problems.append(f"the leader of '{text.get_text()}' ends {reach[nearest]:.1f} px from the "
                                f"{words[nearest]} circle, {reach[own].min():.1f} px from its own")
        through = crossings(box, segments, centres[own], radius + 0.5)
        if len(through):
            problems.append(f"a mode's curve runs through '{text.get_text()}'")
    return problems


FIGURES = [
    ("gear_machine", (0.0, 12000.0, 241), (1, 2)),             # the audit's 36 critical speeds
    ("gear_machine", (0.0, 3000.0, 301), (1, 2)),              # README quick start
    ("rubber_mounts", (0.0, 12000.0, 241), (1, 2)),
    # a guard (passes on 3f1536ec too): the clustered 2X and 1X crossings of modes 5-8
    pytest.param("compressor_on_journals", (500.0, 20000.0, 196), (1, 2), id="compressor_on_journals-guard"),
]


@pytest.mark.parametrize("example, speeds, orders", FIGURES)
def test_every_critical_speed_label_stands_nearest_its_own_circle(example, speeds, orders):
    """``campbell examples/EX.toml --speeds A:B:N --orders 1,2 --plot``: no critical-speed label
    nearer another circle than its own, no leader ending nearer another circle, no mode's curve
    through a label; and the figure still labels critical speeds (the rest are in its note)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(*speeds)), orders=orders)
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    assert len(labels) >= 4
    assert misread_labels(fig, ax, result.critical) == []
    plt.close(fig)


@pytest.mark.parametrize("example, speeds, orders, crowd", [
    ("gear_machine", (0.0, 12000.0, 241), (1, 2), {"710", "777", "1420", "1554"}),
    ("rubber_mounts", (0.0, 12000.0, 241), (1, 2), {"809", "888", "1619", "1776"})])
def test_the_circles_the_reviewer_named_are_labelled_or_in_the_note(example, speeds, orders, crowd):
    """The four circles of each crowd the reviewer read wrongly: each speed is in a label that
    stands nearest its circle (the test above) or in the note of those left out, and at least
    two of them are labelled."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(*speeds)), orders=orders)
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    labelled = {w for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()
                for w in t.get_text().split("/")}
    note = " ".join(t.get_text() for t in ax.texts if t.get_gid() == "critical-note" and t.get_visible())
    listed = {w.strip(",;") for w in note.replace("\n", " ").split()}
    assert crowd <= labelled | listed, (sorted(labelled), note)
    assert len(crowd & labelled) >= 2, sorted(labelled)
    assert misread_labels(fig, ax, result.critical) == []
    plt.close(fig)
