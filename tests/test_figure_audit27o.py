"""Figure audit of issue 27 (figs27o): the figures that could still mislead.

Measured on the drawn figure (the axes' limits, the lines they draw, the label boxes and the
leader lines as drawn), against the result's own numbers, never the placer's.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


# -- stability: each panel's legend names the modes it draws ------------------------------------

@pytest.mark.parametrize("example, speeds", [("unstable_cross_coupled", (0.0, 20000.0, 21)),
                                             ("motor_pump_on_mounts", (100.0, 6000.0, 12))])
def test_each_stability_panel_lists_exactly_the_coloured_modes_it_draws(example, speeds):
    """``stability unstable_cross_coupled.toml --speeds 0:20000:201``: the one legend (the top
    panel's) listed modes 6 and 2 as '(top: below the axis)', modes the top panel does not draw,
    and the bottom panel, which draws them, had no legend; motor_pump_on_mounts's modes 1 and 2
    likewise for the bottom panel. On the drawn figure, in each panel: a coloured mode (a line
    whose gid names it) has a legend entry in that panel exactly when some of its values (the
    result's real parts, log decrements) lie within the panel's limits."""
    import matplotlib.pyplot as plt

    result = rdm.stability(rdm.load_model(EXAMPLES / f"{example}.toml"), rdm.rpm(np.linspace(*speeds)))
    fig = result.plot()
    top, bottom = fig.axes[:2]
    coloured = {int(line.get_gid().split()[1]) for line in top.get_lines() if str(line.get_gid()).startswith("mode ")}
    off_somewhere = 0
    for ax, values in ((top, result.real_parts), (bottom, result.log_decrements)):
        legend = ax.get_legend()
        entries = [t.get_text() for t in legend.get_texts()] if legend else []
        low, high = ax.get_ylim()
        for mode in coloured:
            column = values[:, list(result.modes).index(mode)]
            inside = bool(np.any((column >= low) & (column <= high)))
            off_somewhere += not inside
            assert (f"mode {mode}" in entries) == inside, (ax.get_ylabel(), mode, inside, entries)
            assert not any(e.startswith(f"mode {mode} ") for e in entries), entries
    assert off_somewhere            # the case: some coloured mode lies off one panel
    plt.close(fig)


# -- critical speeds: a leader crosses no mode's curve where a box allows it ---------------------

def _ray(line) -> bool:
    """An order line: frequency proportional to speed (a ray from the origin), in data units."""
    x, y = (np.asarray(v, float) for v in (line.get_xdata(), line.get_ydata()))
    if line.get_transform() is not line.axes.transData or len(x) < 3 or not np.all(np.isfinite(x * y)):
        return False
    k = np.abs(x) > 0
    return bool(k.sum() >= 2 and np.allclose(y[k] / x[k], y[k][0] / x[k][0], rtol=1e-9) and np.all(y[~k] == 0))


def test_no_critical_speed_leader_crosses_a_modes_curve_on_the_compressor():
    """``critical-speeds examples/compressor_rotor.toml --speeds 0:12000:121 --orders 1 --plot``
    (150 dpi, as the command line saves it): the '11115' label stood above mode 4's line, its
    leader down across that line to the circle on mode 3, 7 pixels under it, as if naming a
    crossing on mode 4. On the drawn figure: no critical-speed leader crosses a curve of a mode
    (the axes' lines and line collections but the order lines, which every critical speed lies
    on) farther than the circle's radius from its own marker, and the crossing is labelled."""
    import matplotlib.pyplot as plt
    from label_geometry import curve_segments, segment_crossings

    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 121)), orders=(1,))
    fig = result.plot(title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    leaders = [line for line in ax.get_lines() if line.get_gid() == "critical-leader" and line.get_visible()]
    skip = [line for line in ax.get_lines() if line.get_gid() in ("critical-leader", "order-key-leader")
            or str(line.get_gid()).startswith("mode-leader") or not len(line.get_xdata()) or _ray(line)]
    modes = curve_segments(ax, skip=skip)
    labels = [t for t in ax.texts if t.get_gid() == "critical-label" and t.get_visible()]
    assert any("11115" in t.get_text() for t in labels), [t.get_text() for t in labels]
    markers = ax.transData.transform(np.column_stack([result.critical.speeds * 30 / np.pi,
                                                      result.critical.frequencies_hz]))
    radius = 0.5 * 6 * fig.dpi / 72.0 + 0.5          # the circle's (6 points across) and half a pixel
    for line in leaders:
        start, end = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
        anchor = markers[np.argmin(np.hypot(*(markers - end).T))]
        hits = segment_crossings(start, end, modes, anchor=anchor, radius=radius)
        assert not len(hits), (start, end, anchor, hits)
    # a label without a leader (since leaders40 '11115' stands under its circle: its leader ran 2
    # degrees off the 1X order line, under 3.5 points from it) reads as naming the circle nearest
    # it: that is its own crossing, and no mode's curve passes between them
    renderer = fig.canvas.get_renderer()
    speeds = result.critical.speeds * 30 / np.pi
    for label in labels:
        if any(np.allclose(line.get_xydata()[0], label.get_position()) for line in leaders):
            continue
        box = label.get_window_extent(renderer)
        own = markers[np.argmin(np.abs(speeds - float(label.get_text().split("/")[0])))]
        nearest = np.clip(own, [box.x0, box.y0], [box.x1, box.y1])
        assert np.argmin(np.hypot(*(markers - nearest).T)) == np.argmin(np.hypot(*(markers - own).T)), label.get_text()
        hits = segment_crossings(nearest, own, modes, anchor=own, radius=radius)
        assert not len(hits), (label.get_text(), nearest, own, hits)
    plt.close(fig)


# -- UCS map: each crossing's leader is seen, not laid along a curve -----------------------------

def _length_on_curves(start, end, segments, anchor, radius, width):
    """Length [pixels] of the segment ``start -> end`` lying within ``width`` of the curves
    ``segments`` (n, 4), its part within ``radius`` of ``anchor`` not counted (samples every
    half pixel)."""
    from label_geometry import point_segments_distance

    start, end = np.asarray(start, float), np.asarray(end, float)
    length = float(np.hypot(*(end - start)))
    steps = max(int(2 * length), 2)
    points = start + np.linspace(0.0, 1.0, steps)[:, None] * (end - start)
    on = [np.hypot(*(p - anchor)) > radius and point_segments_distance(segments, p) <= width for p in points]
    return length * np.count_nonzero(on) / steps


def test_no_ucs_crossing_label_hangs_on_a_leader_laid_along_a_curve():
    """``ucs-map examples/fan_on_bearings.toml --stiffness 1e5:1e9:41 --bearings fan-DE,fan-NDE
    --plot`` (150 dpi): the 3e6 N/m line's crossing with mode 7 (3943 rpm) had its label 58
    pixels to the right, beyond the Kyy line's circle on the same curve, its leader laid along
    mode 7's line, hidden by it: the label read as the 4.5e6 N/m circle's, the circle on the 3e6
    line as unlabelled (figs27m took it for a crossing in a gap of its curve). On the drawn
    figure: every crossing is labelled, and no label's leader (from its glyph box's nearest
    point to its circle) lies within 1.5 pixels of a drawn curve for more than half the label's
    height beyond its circle."""
    import matplotlib.pyplot as plt
    from label_geometry import curve_segments, glyph_box

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.ucs_map(model, np.geomspace(1e5, 1e9, 41), bearings=["fan-DE", "fan-NDE"])
    fig = result.plot()
    fig.set_dpi(150)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    segments = curve_segments(ax)
    radius = 0.5 * 6 * fig.dpi / 72.0 + 0.5           # the crossings' circles: 6 points across
    labels = {}
    for text in ax.texts:
        if text.get_gid() == "ucs-end-name" or text.arrow_patch is None:
            continue
        labels[(round(float(text.xy[0]), 3), text.get_text())] = text
    crossings = {(round(c.stiffness, 3), f"{c.speed * 30 / np.pi:.0f}") for c in result.crossings}
    assert crossings <= set(labels), crossings - set(labels)
    for text in labels.values():
        box = glyph_box(text, renderer)
        anchor = ax.transData.transform(text.xy)
        start = (min(max(anchor[0], box.x0), box.x1), min(max(anchor[1], box.y0), box.y1))
        along = _length_on_curves(start, anchor, segments, anchor, radius, 1.5)
        assert along <= 0.5 * box.height, (text.get_text(), text.xy, along, box.height)
    plt.close(fig)


# -- run-up: the legend's notes do not narrow the panels ----------------------------------------

def _two_rotor_run_up(duration=10.0, f0=2.0, f1=20.0, rate=200.0, ratio=1.25, small=1e-3):
    """One mode (6 Hz, damping ratio 0.03) pushed by two rotors' unbalance, the second turning
    ``ratio`` times as fast with 1000 times the first's: ramped from ``f0`` to ``f1`` [Hz] over
    ``duration`` [s] from rest, as a run-up record (the first rotor's 1X track is under the
    second's leakage at most speeds: its phase is not drawn, a legend note says so)."""
    from test_runup_passage27 import _swept_mode

    return _swept_mode(duration, f0, f1, rate, rotors=(("motor", 1.0, small), ("pump", ratio, 1.0)),
                       name="two rotors")


def test_the_run_up_legend_notes_leave_the_panels_their_width():
    """``simulate examples/motor_pump_on_mounts.toml --speed 0 --ramp 3000 --duration 3 --plot``:
    the phase panel's legend held one-line notes of 85 characters ('1X motor: not separable from
    free vibration (fast passage of a mode, start transient)') in two columns beside the phase
    note, wider than the panel: constrained layout narrowed all four panels to a fifth of the
    figure's width each, blank between the columns. On the drawn figure (150 dpi) of a two-rotor
    run-up with both notes: the four panels together take at least 70 % of the figure's width
    across its two columns, and the legend stays inside the figure."""
    import warnings

    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.simulation import plot_runup

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")             # the run-up's own 'may differ from the steady response' warning
        fig = plot_runup(_two_rotor_run_up(), "s")
    fig.set_dpi(150)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert len(panels) == 4
    phase = next(ax for ax in panels if ax.get_title() == "Order-tracked phase")
    texts = [t.get_text() for t in phase.get_legend().get_texts()]
    assert any("may differ from the steady response" in t for t in texts) and any("phase unknown" in t for t in texts), texts
    left = [ax for ax in panels if ax.get_position().x0 < 0.5]
    right = [ax for ax in panels if ax.get_position().x0 >= 0.5]
    width = fig.bbox.width
    for a, b in zip(left, right):
        share = (a.get_window_extent(renderer).width + b.get_window_extent(renderer).width) / width
        assert share >= 0.70, (a.get_title(), b.get_title(), share)
    box = phase.get_legend().get_window_extent(renderer)
    assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0
    plt.close(fig)
