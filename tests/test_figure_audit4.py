"""Figures of the fourth audit (issue 27, section 3), measured on the drawn figure
(``fig.canvas.draw()``, window extents), independent of the code that places things: legends
that took half the figure, order lines left unnamed at the Campbell diagram's top edge, merged
order labels beside one of the lines they name, the orbit's axis that did not say what e is."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from campbell_orders import drawn_campbell
from label_geometry import outline, outlines_overlap, point_segment_distance

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def pump():
    return rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")


def _figures(pump):
    """motor_pump_on_mounts (modes 5 Hz-1.2 kHz): its unbalance response with the suspensions'
    forces (three legends, notes of 50 characters); rubber_mounts' bearing forces (two blocks
    of force and moment panels, notes found on the layout)."""
    unbalance = rdm.unbalance_response(pump, rdm.rpm(np.linspace(0.0, 6000.0, 21)))
    yield "unbalance", unbalance.plot(forces="suspensions")
    rubber = rdm.load_model(EXAMPLES / "rubber_mounts.toml")
    yield "forces", rdm.force_frf(rubber, rdm.rpm(3000), np.linspace(1.0, 100.0, 40), where="bearings").plot()


def test_legends_leave_the_panels_most_of_the_width(pump):
    """The legends beside the panels, with long names and '(= ...)' notes, took up to half the
    figure's width (the panels 47-59 % of it). On the drawn figure: every panel with a legend is
    at least 70 % as wide as its figure (or block of panels), every legend lies inside the
    figure, overlaps no panel, no title and no other legend, and names every curve of its
    panel."""
    import matplotlib.pyplot as plt

    for name, fig in _figures(pump):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        frame = fig.bbox
        axes = [ax for ax in fig.axes if ax.get_visible()]
        legends = [ax.get_legend() for ax in axes if ax.get_legend() is not None]
        assert len(legends) >= 1, name
        boxes = [legend.get_window_extent(renderer) for legend in legends]
        titles = [t.get_window_extent(renderer) for ax in axes for t in (ax.title,) if t.get_text()]
        for ax in axes:
            if ax.get_legend() is None:
                continue
            holder = ax.get_figure(root=False).bbox
            assert ax.bbox.width >= 0.7 * holder.width, (name, ax.get_ylabel(), ax.bbox.width / holder.width)
            named = {t.get_text() for t in ax.get_legend().get_texts()}
            curves = [line.get_label() for line in ax.get_lines() if not line.get_label().startswith("_")]
            assert set(curves) <= named, (name, set(curves) - named)
        for k, box in enumerate(boxes):
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, name
            assert not any(box.overlaps(ax.bbox) for ax in axes), name
            assert not any(box.overlaps(title) for title in titles), name
            assert not any(box.overlaps(other) for other in boxes[k + 1:]), name
        plt.close(fig)


def test_orbit_axis_says_that_e_is_the_spin_axis(pump):
    """The orbit panels' vertical axis read 'e × probe-pump-x [µm]' with e defined nowhere on
    the figure: it names the spin axis."""
    import matplotlib.pyplot as plt

    fig = rdm.unbalance_response(pump, rdm.rpm(np.linspace(500.0, 3000.0, 6))).plot_orbits()
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
    assert labels and all("e × " in label and "e: spin axis" in label for label in labels), labels
    plt.close(fig)


# -- Campbell: order labels beside their own lines, naming only neighbouring lines ---------------

@pytest.mark.parametrize("model", ["gear_machine.toml", "rubber_mounts.toml"])
def test_order_labels_name_neighbouring_lines_beside_their_own(model):
    """gear_machine and rubber_mounts, 0-12000 rpm, orders 1-4: the motor's and the gear
    mesh's steep lines had no label (no room between their exits at the top edge), and
    '2X, 3X, 4X fan' stood beside the fan's 2X line only, the motor's lines running between
    the lines it named. On the drawn figure (lines through the origin, label window extents):
    the lines a label names are neighbours (no other order line between them); each label lies
    inside the axes, overlaps no other label, and the order line nearest its centre is one it
    names; the motor's lines 2X-4X (between the mesh's and the fan's, no room for a flat
    label at their exits) are named, along their lines."""
    import matplotlib.pyplot as plt

    drawn = drawn_campbell(model)
    fig, ax, renderer, frame = drawn.fig, drawn.ax, drawn.renderer, drawn.frame
    lines = {slope: segment for slope, (segment, _) in drawn.lines.items()}
    # keys above the axes (lines with no room inside them) are checked in test_figure_audit5
    texts = [t for t in ax.texts if t.get_visible() and t.get_text() and t.get_gid() != "order-key"]
    boxes = [t.get_window_extent(renderer) for t in texts]
    outlines = [outline(t, renderer) for t in texts]     # labels along steep lines: the turned texts
    for i, a in enumerate(outlines):
        assert not any(outlines_overlap(a, b) for b in outlines[i + 1:]), texts[i].get_text()
    named = set()
    slopes = sorted(lines)
    for text, box in zip(texts, boxes):
        mine = drawn.named_slopes(text.get_text())
        if mine is None:
            continue
        named |= mine
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, text.get_text()
        centre = np.array([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
        nearest = min(lines, key=lambda s: point_segment_distance(lines[s], centre))
        assert nearest in mine, (text.get_text(), nearest)
        between = [s for s in slopes if min(mine) < s < max(mine) and s not in mine]
        assert not between, (text.get_text(), between)
    motor = {drawn.slope("motor", o) for o in (2, 3, 4)}
    assert motor <= named, sorted(motor - named)
    plt.close(fig)
