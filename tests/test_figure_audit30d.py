"""Figure audit of issue 27 §3 (figs30d): nothing cut at the figure's edge.

figs30b's review of every CLI figure found four drawings cut at an axes' edge:

- ``modes --shape 3`` of spring_block_rotor (and its suspension variant): the top and front
  views were framed around the machine at rest, so the displaced disk ran out of the right edge;
- ``level1``: the Q0 diamond at Q = 0 stood on the axes' left edge, half clipped;
- flexible_pump's Campbell diagram: the critical speed at 5981 rpm, on the sweep's last speed,
  had its circle cut in half by the right edge;
- rubber_mounts' FRF: the note '▼ below the axis (clipped at ...)' stood on a curve's end.

Each is measured on the drawn figure from geometry the drawing does not choose: the shape's
displaced vertices (``ModeShape3D.at_phase``), a marker's extent (its size in points around its
centre) against the region it is clipped to, and the note's box against every drawn curve.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

#: the projections' (title words, axes of the machine drawn across and up)
_PANELS = {"top view": (0, 1), "front view": (0, 2), "side view": (1, 2)}


def _close(fig):
    import matplotlib.pyplot as plt

    plt.close(fig)


# -- 3-D shape views: the displaced drawing inside every panel -------------------------------------

@pytest.mark.parametrize("example", ["spring_block_rotor", "spring_block_rotor_suspension"])
def test_the_displaced_shape_lies_inside_every_view(example):
    """``modes EX --speed 3000 --shape 3``: every displaced vertex (bodies, brackets, springs at
    phase 0, the phase drawn) lies inside the limits of the 3-D axes and of each projection."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(3000.0)), model, 3)
    points = np.concatenate([np.asarray(p, float).reshape(-1, 3) for p in view.at_phase(0.0)]
                            + [np.asarray(b, float).reshape(-1, 3) for b in view.brackets_at_phase(0.0)]
                            + [np.asarray(s, float).reshape(-1, 3) for s in view.springs_at_phase(0.0)])
    fig = view.plot()
    try:
        fig.canvas.draw()
        checked = 0
        for ax in fig.axes:
            if hasattr(ax, "get_zlim"):
                limits = [ax.get_xlim(), ax.get_ylim(), ax.get_zlim()]
                axes = (0, 1, 2)
            else:
                panel = [key for key in _PANELS if key in ax.get_title()]
                if not panel:
                    continue
                axes = _PANELS[panel[0]]
                limits = [ax.get_xlim(), ax.get_ylim()]
            for k, (low, high) in zip(axes, limits):
                outside = (points[:, k] < low) | (points[:, k] > high)
                assert not outside.any(), (ax.get_title(), "xyz"[k], (low, high),
                                           points[outside, k].min(), points[outside, k].max())
            checked += 1
        assert checked == 4, checked
    finally:
        _close(fig)


# -- markers drawn whole: their extent inside the region they are clipped to -----------------------

def _clip_region(fig, line):
    """Display box a line's markers are cut to: its clip box, or the figure when not clipped."""
    if not line.get_clip_on():
        return fig.bbox
    box = line.get_clip_box()
    return box if box is not None else fig.bbox


def _cut_markers(fig, ax, line):
    """Centres [data] of the markers of ``line`` whose extent (a square of the marker's size in
    points around the centre, the whole marker for 'o' and 'D') is not inside the region the line
    is clipped to, counting only markers whose centre lies within the axes' limits."""
    fig.canvas.draw()
    region = _clip_region(fig, line)
    half = line.get_markersize() / 2 * fig.dpi / 72.0
    (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    cut = []
    for x, y in zip(*(np.asarray(v, float) for v in line.get_data())):
        if not (x0 <= x <= x1 and y0 <= y <= y1):
            continue
        cx, cy = ax.transData.transform((x, y))
        if cx - half < region.x0 - 0.5 or cx + half > region.x1 + 0.5 or cy - half < region.y0 - 0.5 \
                or cy + half > region.y1 + 0.5:
            cut.append((x, y))
    return cut


@pytest.mark.parametrize("example, mcs, station", [("compressor_on_journals", 12000.0, "compressor"),
                                                   ("journal_rotor", 20000.0, "rotor"),
                                                   ("spring_block_rotor", 6000.0, "disk")])
def test_the_q0_diamond_is_drawn_whole(example, mcs, station):
    """``level1 EX --mcs MCS --station S --qa 2e5``: Q0 lies at Q = 0 (the left edge), its diamond
    (8 points) was half clipped by the axes; it is drawn whole."""
    from rotordyn_modal.analysis.level1 import level1

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = level1(model, rdm.rpm(mcs), [station], qa=2e5)
    fig = result.plot()
    try:
        ax = fig.axes[0]
        diamonds = [line for line in ax.get_lines() if str(line.get_label()).startswith("Q0 =")]
        assert len(diamonds) == 1, [line.get_label() for line in ax.get_lines()]
        assert diamonds[0].get_xdata()[0] == pytest.approx(ax.get_xlim()[0], abs=0.02 * np.ptp(ax.get_xlim())), \
            "the case is a Q0 on the left edge"
        assert not _cut_markers(fig, ax, diamonds[0])
    finally:
        _close(fig)


def test_the_flexible_pumps_critical_speed_circle_on_the_right_edge_is_drawn_whole():
    """``campbell flexible_pump_on_mounts.toml --speeds 0:6000:61 --orders 1,2``: the critical
    speed at 5981 rpm lies 19 rpm (a third of a circle's width) inside the right edge; every
    critical speed's circle inside the axes' limits is drawn whole."""
    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 6000.0, 61)), orders=(1, 2))
    fig = result.plot()
    try:
        ax = fig.axes[0]
        circles = [line for line in ax.get_lines() if line.get_label() == "critical speed"]
        assert len(circles) == 1
        speeds = np.asarray(circles[0].get_xdata(), float)
        assert np.any(speeds > 5900.0), speeds                       # the case: a circle on the edge
        assert not _cut_markers(fig, ax, circles[0])
    finally:
        _close(fig)


# -- FRF: the clipped-note stands on no curve -------------------------------------------------------

def test_the_rubber_mounts_clipped_note_stands_on_no_curve():
    """``frf rubber_mounts.toml --speed 3000 --freqs 1:1000:600 --plot``: the green curve's end
    (1000 Hz) ran through the note in the lower right corner. The note's box (text and its
    white pad) meets no drawn curve nor caret of its panel."""
    from rotordyn_modal.analysis.frf import frf
    from rotordyn_modal.cli._common import parse_range
    from rotordyn_modal.cli.frf import _input_kinds

    model = rdm.load_model(EXAMPLES / "rubber_mounts.toml")
    result = frf(model, rdm.rpm(3000.0), parse_range("1:1000:600", "--freqs"))
    fig = result.plot(input_kinds=_input_kinds(model))
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        notes = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_gid() == "clipped-note"]
        assert notes, "the case: a curve below the axis"
        for ax, note in notes:
            box = note.get_bbox_patch().get_window_extent(renderer)
            frame = ax.get_window_extent(renderer)
            for line in ax.get_lines():
                xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
                # the part drawn: clipped to the axes (a curve below the axis is not drawn there)
                finite = np.all(np.isfinite(xy), axis=1)
                if line.get_linestyle() not in ("None", "", " "):
                    for run in np.split(np.arange(len(xy)), np.flatnonzero(np.diff(finite.astype(int))) + 1):
                        if finite[run[0]] and len(run) > 1:
                            assert not _segments_meet(xy[run], box, frame), (line.get_label(), note.get_text())
                half = line.get_markersize() / 2 * fig.dpi / 72.0
                if line.get_marker() not in ("None", "", " ", None) and line.get_gid() == "clipped":
                    for cx, cy in xy[finite]:
                        assert cx + half < box.x0 or cx - half > box.x1 or cy + half < box.y0 \
                            or cy - half > box.y1, ("caret", cx, cy)
    finally:
        _close(fig)


def _segments_meet(xy, box, frame, samples: int = 64):
    """Whether the polyline ``xy`` (n, 2) [display], where it lies inside ``frame``, passes through
    ``box``: each segment sampled at ``samples`` points (a pixel apart or closer at 150 dpi on
    these curves' short segments) and the samples inside both boxes counted."""
    t = np.linspace(0.0, 1.0, samples)[:, None]
    for a, b in zip(xy[:-1], xy[1:]):
        points = a + t * (b - a)
        inside = ((points[:, 0] >= max(box.x0, frame.x0)) & (points[:, 0] <= min(box.x1, frame.x1))
                  & (points[:, 1] >= max(box.y0, frame.y0)) & (points[:, 1] <= min(box.y1, frame.y1)))
        if inside.any():
            return True
    return False


# -- 3-D shape views: names side by side read as two ------------------------------------------------

#: white space [points] between two names' backgrounds side by side: more than a space's width
#: ('x-small' text: about 2 points), so two names never read as one
_APART_POINTS = 4.0


@pytest.mark.parametrize("example, at_rest", [("fan_on_bearings", False), ("spring_block_rotor", False),
                                              ("fan_on_bearings", True)])
def test_the_names_of_the_arrows_stand_apart(example, at_rest, monkeypatch):
    """``modes EX --speed 3000 --shape 3``: fan_on_bearings' 'acc-fan-z' and 'probe-DE-x' stood
    side by side with less than 2 points of white between them and read as one name. Every two
    names' drawn boxes (text and background) overlap in height only with
    :data:`_APART_POINTS` or more between them across, and overlap nowhere. ``at_rest``: framed
    around the machine at rest only (as main framed it, where the two names came side by side),
    to hold the names' spacing itself, not the frame that moved them apart."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting import shapes3d

    if at_rest:
        frame = shapes3d._frame
        monkeypatch.setattr(shapes3d, "_frame", lambda ax, flat, view, units="si", phase=None:
                            frame(ax, flat, view, units))

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    fig = mode_shape_3d(rdm.modal(model, rdm.rpm(3000.0)), model, 3).plot()
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        layouts = [a for ax in fig.axes for a in ax.artists if a.get_gid() == "arrow-labels"]
        assert len(layouts) == 1
        texts = [t for t in layouts[0].arrow_labels.texts if t.get_visible() and t.get_text()]
        assert len(texts) >= 2
        boxes = [t.get_bbox_patch().get_window_extent(renderer) for t in texts]
        apart = _APART_POINTS * fig.dpi / 72.0
        for i in range(len(boxes)):
            for j in range(i):
                a, b = boxes[i], boxes[j]
                if a.y0 < b.y1 and b.y0 < a.y1:             # side by side (their heights overlap)
                    across = max(b.x0 - a.x1, a.x0 - b.x1)
                    assert across >= apart, (texts[i].get_text(), texts[j].get_text(), across * 72.0 / fig.dpi)
    finally:
        _close(fig)
