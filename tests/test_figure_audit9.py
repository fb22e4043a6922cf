"""Figures of the ninth audit (issue 27, section 3: figures that cannot mislead), measured on the
drawn figure (``fig.canvas.draw()``, glyph boxes, the curves as drawn: ``tests/label_geometry.py``),
independent of the code that places things.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import glyph_box, order_curves, point_segments_distance

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _jumping_machine():
    """Five random rotors on bearings in a casing (``test_critical_refinement``'s clustered
    machine, smaller): on 21 speeds without sub-sweeps, one critical speed (r2's 1X near
    2618 rpm) is a jump of its tracked mode between close roots, 34 Hz where the 1X line is
    far above."""
    from reference_bearings import random_bearing_description

    rng = np.random.default_rng(5)
    data = random_bearing_description(rng, n_rotors=5)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    return rdm.Model.from_dict(data)


def test_a_jump_critical_speed_is_drawn_on_its_order_line_and_marked_uncertain(monkeypatch):
    """A red-team reviewer saw a 'jump' critical speed (a crossing where the tracked mode jumped
    between close roots; the terminal warns of it) drawn as a circle at 2.4 Hz, off every curve.
    Every critical-speed marker of the drawn figure lies on an excitation order line (a
    crossing lies on it by definition; a jump's true crossing lies on it at that speed), within
    a pixel; the jump's marker is not the crossings' circle, has a legend entry of its own, and
    its label ends in '?'."""
    from rotordyn_modal.analysis import campbell as campbell_module
    from rotordyn_modal.analysis import critical_speeds as critical_module
    from rotordyn_modal.plotting.campbell import plot_campbell

    monkeypatch.setattr(critical_module, "_SUB_DEPTH", 0)
    # nor the tracking on a finer grid, which follows its modes without a jump: a large model's
    # sweep, tracked on its own grid
    monkeypatch.setattr(campbell_module, "_FINER_ROUNDS", 0)
    model = _jumping_machine()
    with pytest.warns(UserWarning, match="jumps of a tracked mode"):
        result = rdm.campbell(model, np.linspace(0.0, 3000.0, 21))
    rpm = 60 / (2 * np.pi)
    multiplier = dict(zip(result.sources.names, result.sources.multipliers))
    line_hz = np.array([o * multiplier[s] for s, o in zip(result.critical.source, result.critical.order)]) \
        * np.abs(result.critical.speeds) / (2 * np.pi)
    jump = np.abs(result.critical.frequencies_hz - line_hz) > 1e-3 * line_hz     # outside: the table itself
    assert jump.sum() == 1
    fig = plot_campbell(result)
    fig.canvas.draw()
    ax = fig.axes[0]
    markers = [line for line in ax.get_lines() if line.get_marker() in ("o", "D")
               and line.get_linestyle() in ("None", "", " ")]
    lines = np.concatenate(list(order_curves(ax).values()))
    drawn = 0
    for marker in markers:
        points = marker.get_transform().transform(np.column_stack(marker.get_data()))
        for point in points:
            drawn += 1
            assert point_segments_distance(lines, point) < 1.0, f"a critical-speed marker at {point} is off every order line"
    assert drawn > 0
    speed = result.critical.speeds[jump][0] * rpm
    uncertain = [m for m in markers if np.any(np.isclose(m.get_xdata(), speed, rtol=1e-9))]
    assert len(uncertain) == 1 and uncertain[0].get_marker() != "o"
    entries = [t.get_text() for t in ax.get_legend().get_texts()]
    assert uncertain[0].get_label() in entries and uncertain[0].get_label() != "critical speed"
    words = [w for t in ax.texts if t.get_gid() == "critical-label" for w in t.get_text().split("/")]
    assert f"{speed:.0f}?" in words


def test_a_sweep_without_critical_speeds_says_so_in_the_axes():
    """``critical-speeds journal_rotor.toml --speeds 100:500:11 --plot``: the terminal says 'no
    critical speed between 100 and 500 rpm'; the figure drew the curves and said nothing. Now
    one line inside the axes says it, crossed by no curve; a sweep whose critical speeds were
    left out (critical=False; fan_on_bearings, whose 1X line crosses modes) says no such thing."""
    from label_geometry import crossings, curve_segments
    from rotordyn_modal.plotting.campbell import plot_campbell

    model = rdm.load_model(EXAMPLES / "journal_rotor.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(100.0, 500.0, 11)))
    assert not len(result.critical)
    fig = plot_campbell(result)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    notes = [t for t in ax.texts if t.get_visible() and "no critical speed between 100 and 500 rpm" in t.get_text()]
    assert len(notes) == 1
    box, frame = glyph_box(notes[0], renderer), ax.get_window_extent()
    assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
    assert not len(crossings(box, curve_segments(ax)))
    fan = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    assert len(rdm.campbell(fan, rdm.rpm(np.linspace(0.0, 6000.0, 13))).critical)
    skipped = rdm.campbell(fan, rdm.rpm(np.linspace(0.0, 6000.0, 13)), critical=False)
    fig = plot_campbell(skipped)
    fig.canvas.draw()
    assert not any("no critical speed" in t.get_text() for t in fig.axes[0].texts if t.get_visible())


_SIDE_BY_SIDE = """
name = "two flexible rotors side by side"
spin_axis = [1.0, 0.0, 0.0]
reference_rotor = "motor"

[[materials]]
name = "steel"
density = 7810.0
young_modulus = 2.11e11
poisson_ratio = 0.3

[[rotors]]
name = "motor"
start = [0.1, 0.10, 0.18]
[[rotors.shaft]]
length = 0.4
outer_diameter = 0.05
material = "steel"
[[rotors.disks]]
name = "core"
axial_position = 0.2
mass = 6.0
polar_inertia = 0.012
diametral_inertia = 0.04

[[rotors]]
name = "pump"
start = [0.0, -0.12, 0.18]
element_length = 0.05
speed_ratio = -1.0
[[rotors.shaft]]
length = 0.45
outer_diameter = 0.035
material = "steel"
[[rotors.disks]]
name = "gear"
axial_position = 0.30
mass = 1.5
polar_inertia = 0.004
diametral_inertia = 0.0025

[[bearings]]
name = "motor-DE"
rotor = "motor"
position = [0.40, 0.10, 0.18]
stiffness = 1.0e8
[[bearings]]
name = "motor-NDE"
rotor = "motor"
position = [0.18, 0.10, 0.18]
stiffness = 1.0e8
[[bearings]]
name = "pump-IB"
rotor = "pump"
axial_position = 0.12
stiffness = 2.0e7
[[bearings]]
name = "pump-OB"
rotor = "pump"
axial_position = 0.40
stiffness = 2.0e7
"""


def test_shaft_line_names_at_one_axial_position_stand_apart(tmp_path):
    """``modes --plot-shaft`` of two flexible rotors side by side (a red-team reviewer's motor
    and pump: the disks 'core' and 'gear', the bearings 'motor-DE' and 'pump-OB' at the same
    axial position): their names printed over each other. On the drawn figure no two names'
    glyph boxes overlap in any panel, and each name still spans or nearly touches its own
    position (within one of its widths)."""
    from matplotlib.text import Text
    from rotordyn_modal.analysis.mode_shapes import shaft_lines
    from rotordyn_modal.plotting.shaft_modes import plot_shaft_modes

    path = tmp_path / "side_by_side.toml"
    path.write_text(_SIDE_BY_SIDE)
    model = rdm.load_model(path)
    result = rdm.modal(model, rdm.rpm(3000.0))
    fig = plot_shaft_modes([shaft_lines(result, model, k) for k in (1, 2)])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        names = [t for t in ax.texts if t.get_visible() and t.get_text()]
        assert {"core", "gear", "motor-DE", "pump-OB"} <= {t.get_text() for t in names}
        boxes = [Text.get_window_extent(t, renderer) for t in names]
        for i, a in enumerate(boxes):
            for b, other in zip(boxes[i + 1:], names[i + 1:]):
                assert not a.overlaps(b), f"{names[i].get_text()!r} prints over {other.get_text()!r}"
        for name, box in zip(names, boxes):
            anchor = ax.transData.transform(name.xy)[0]
            assert box.x0 - box.width <= anchor <= box.x1 + box.width, name.get_text()


def test_an_frf_antiresonance_is_not_clipped_without_a_word():
    """``frf fan_on_bearings.toml --speed 3000 --freqs 1:200:800 --plot``: the magnitude axis
    stopped six decades below its top, and acc-motor-y / hammer-z's antiresonance near 120 Hz
    (6.3 decades below the top, 4.7 below its own peak: a real one) ran out of the axes without
    a word. On the drawn figure every model curve's lowest value (from the result's own H) lies
    inside its magnitude axis, or a mark on the bottom edge in its colour stands at each
    stretch below it."""
    from rotordyn_modal.plotting.frf import plot_frf

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.frf(model, rdm.rpm(3000.0), np.linspace(1.0, 200.0, 800))
    fig = plot_frf(result)
    fig.canvas.draw()
    ax = fig.axes[0]
    bottom = ax.get_ylim()[0]
    assert np.abs(result.H).min() < 1e-6 * np.abs(result.H).max()       # deeper than six decades
    marks = [line for line in ax.get_lines() if line.get_linestyle() in ("None", "", " ")]
    for line in ax.get_lines():
        if line in marks or "(round-off" in line.get_label():
            continue
        x, y = (np.asarray(v, float) for v in line.get_data())
        below = np.concatenate(([0], (y < bottom).astype(int), [0]))
        edges = np.flatnonzero(np.diff(below))
        for start, stop in zip(edges[::2], edges[1::2]):          # each stretch below the axis
            assert any(m.get_color() == line.get_color() and x[start] <= m.get_xdata()[0] <= x[stop - 1]
                       and np.isclose(m.get_ydata()[0], bottom) for m in marks), line.get_label()
        if line.get_label().startswith("acc-motor-y / hammer-z"):
            assert y.min() >= bottom, "the antiresonance near 120 Hz is clipped"


def test_a_curve_running_below_the_frf_axis_is_marked_where_it_does():
    """The fit overlay at 2400 rpm (test_frf's example, accelerance): acc-top-z / shaker-y, the
    gyroscopic cross-coupling, rises from far below the others at low frequencies (more than
    eight decades below the top: the axis does not follow it). Each stretch of it below the
    axis has a caret in its colour on the bottom edge within the stretch, and a visible note
    in the axes names the clipping; the 0 rpm panel (nothing below) has neither."""
    from test_frf import EXAMPLE, FREQS
    from rotordyn_modal.analysis.frf import frf
    from rotordyn_modal.plotting.frf import plot_overlay

    model = rdm.load_model(EXAMPLE)
    models = [frf(model, s, FREQS[1:], quantity="accelerance") for s in (0.0, rdm.rpm(2400))]
    fig = plot_overlay(models, models)
    fig.canvas.draw()
    magnitudes = [ax for ax in fig.axes if ax.get_yscale() == "log"]
    found = []
    for ax in magnitudes:
        bottom = ax.get_ylim()[0]
        marks = [line for line in ax.get_lines() if line.get_linestyle() in ("None", "", " ")
                 and line.get_marker() not in (".",)]
        notes = [t for t in ax.texts if t.get_visible() and "below the axis" in t.get_text()]
        stretches = 0
        for line in ax.get_lines():
            if line.get_linestyle() in ("None", "", " ") or "(round-off" in line.get_label():
                continue
            x, y = (np.asarray(v, float) for v in line.get_data())
            edges = np.flatnonzero(np.diff(np.concatenate(([0], (y < bottom).astype(int), [0]))))
            for start, stop in zip(edges[::2], edges[1::2]):
                stretches += 1
                assert any(m.get_color() == line.get_color() and x[start] <= m.get_xdata()[0] <= x[stop - 1]
                           and np.isclose(m.get_ydata()[0], bottom) for m in marks), line.get_label()
        assert bool(notes) == bool(stretches) and len(marks) == stretches
        found.append(stretches)
    assert found[0] == 0 and found[1] >= 1
