"""Figures of the tenth audit (issue 27, section 3: figures that cannot mislead), measured on the
drawn figure (``fig.canvas.draw()``, glyph boxes, the curves as drawn: ``tests/label_geometry.py``)
and, for the order tracking, against closed forms.
"""

from __future__ import annotations

import types
from pathlib import Path

import matplotlib
import numpy as np

import rotordyn_modal as rdm
from label_geometry import crossings, curve_segments, glyph_box

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _visible_notes(ax, *words):
    """The visible texts of ``ax`` holding every one of ``words``."""
    return [t for t in ax.texts if t.get_visible() and all(w in t.get_text() for w in words)]


def _inside_and_clear(ax, text, renderer):
    """Whether the text's glyphs lie inside the axes' frame and no drawn curve crosses them."""
    box, frame = glyph_box(text, renderer), ax.get_window_extent(renderer)
    inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
    return inside and not len(crossings(box, curve_segments(ax)))


# -- 1. simulate without a [stator]: the ground is said, not drawn as zero lines ----------------

def test_a_machine_on_the_ground_says_so_instead_of_drawing_its_zero_motion():
    """``simulate examples/journal_rotor.toml --speed 3000 --initial equilibrium --plot``: the model
    has no [stator], its bearings stand on the ground. The time-history panel of the stator's
    motion drew four lines '0 throughout' (|gamma|, u_x, u_y, u_z) without saying whose they
    were, and the spin panel a flat zero line. Now the panel draws none of the ground's motion,
    says inside the axes (clear of the curves) that the ground is fixed, and the spin panel says
    why its deviation is zero throughout (the drive holds the speed, nothing rolls)."""
    model = rdm.load_model(EXAMPLES / "journal_rotor.toml")
    assert model.stator is None
    result = rdm.simulate(model, 0.005, rdm.rpm(3000.0), initial="equilibrium", samples=50, backend="numpy")
    assert not np.any(result.displacement) and not np.any(result.spin_speed - result.spin_speed[0])
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = [ax for ax in fig.axes if "Rotation" in ax.get_ylabel()]
    assert len(frame) == 1
    ax = frame[0]
    labels = [line.get_label() for other in fig.axes if other.bbox.bounds == ax.bbox.bounds
              for line in other.get_lines()]
    assert not any("transverse rotation [deg]" in label or label.startswith("u_") for label in labels), labels
    notes = _visible_notes(ax, "ground", "no stator")
    assert len(notes) == 1 and _inside_and_clear(ax, notes[0], renderer)
    spin, = [a for a in fig.axes if "ω_φ" in a.get_ylabel()]
    notes = _visible_notes(spin, "0 throughout")
    assert len(notes) == 1 and "drive" in notes[0].get_text() and _inside_and_clear(spin, notes[0], renderer)


def test_the_ground_note_stands_clear_of_a_tilting_rotor():
    """``simulate spring_block_rotor.toml --free-spin``: a rotor in a block of springs on the
    ground, tilting by up to 8 degrees; the note that the ground is fixed stands clear of its
    curve, and a machine with a stator gets no such note."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = rdm.simulate(model, 0.2, 50.0, drive="free", samples=200, backend="numpy")
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax, = [a for a in fig.axes if "Rotation" in a.get_ylabel()]
    assert any(np.any(line.get_ydata()) for line in ax.get_lines())
    notes = _visible_notes(ax, "ground", "no stator")
    assert len(notes) == 1 and _inside_and_clear(ax, notes[0], renderer)
    result.frame = "stator"
    fig = result.plot()
    assert not any(_visible_notes(a, "no stator") for a in fig.axes)


# -- 2. order tracking: a weak order's phase under the other rotor's leakage is unknown --------

RATIO = 0.625            # the fan example's belt: the second rotor turns 1.6 times slower
TURNS = 4                # order_track's default window


def _sinc(x):
    return np.sinc(x)    # sin(pi x) / (pi x)


def _leakage(ratio=RATIO, turns=TURNS):
    """The closed-form response of a rectangular window of ``turns`` turns at a steady speed to the
    1X of a rotor turning ``ratio`` times as fast (both its positive and negative frequency)."""
    return abs(_sinc(turns * (ratio - 1.0))) + abs(_sinc(turns * (ratio + 1.0)))


def _two_orders(speed, duration=8.0, step=2e-4, theta=0.7, ratio=RATIO):
    """A sensor reading ``A(t) cos(phi + theta) + cos(RATIO phi + 0.3)``: rotor 'a' (ratio 1) of
    amplitude ``A(t) = 10**(-2 + 3 t / duration)`` (0.01 to 10) and rotor 'b' of amplitude 1;
    ``speed(t)`` [rad/s] and its angle given in closed form as a pair of functions."""
    omega, angle = speed
    t = np.arange(0.0, duration, step)
    phi = angle(t)
    strong = lambda time: 10.0 ** (-2.0 + 3.0 * time / duration)     # noqa: E731
    signal = strong(t) * np.cos(phi + theta) + np.cos(ratio * phi + 0.3)
    result = types.SimpleNamespace(time=t, drive_speed=omega(t), rotor_angles=np.column_stack([phi, ratio * phi]),
                                   speed_ratios=np.array([1.0, ratio]), rotor_names=["a", "b"], model_name="two orders",
                                   sensor_names=["s"], sensor=lambda name: signal)
    return result, strong


def test_a_weak_order_under_the_leakage_of_a_strong_one_has_no_phase():
    """The fan's run-up drew the motor's 1X phase climbing to 3200 deg: the fan's 1X (1.6:1 belt)
    leaks through the motor's window of four turns and its phase, turning with the fan's angle,
    was read as the motor's. Closed form at a steady 300 rad/s: the window passes the other
    rotor's 1X of amplitude 1 with at most F = |sinc(4 (0.625 - 1))| + |sinc(4 (0.625 + 1))|
    = 0.261. Rotor 'a''s 1X (amplitude A rising from 0.01 to 10, phase 0.7 rad) has an unknown
    phase (NaN) in every window where A < F (its measured amplitude is then under twice the
    floor, whatever the phases), a known one where A > 3 F, right to within asin(F / A); where
    A is small the track reports the floor F itself; 'b''s phase (1, above a's leakage until A passes 2) is
    known where A < 1.5."""
    from rotordyn_modal.simulation.runup import order_track

    speed = (lambda t: np.full(t.shape, 300.0), lambda t: 300.0 * t)
    result, strong = _two_orders(speed)
    floor = _leakage()
    assert 0.25 < floor < 0.27
    track = order_track(result, "s", rotor="a", revolutions=TURNS)
    period = 2 * np.pi * TURNS / 300.0
    middle = (np.arange(len(track.amplitude)) + 0.5) * period                 # the windows' middles [s]
    low, high = strong(middle - period / 2), strong(middle + period / 2)
    assert len(track.amplitude) == int(result.time[-1] / period)
    below, above = high < floor, low > 3.0 * floor
    assert below.sum() >= 5 and above.sum() >= 5
    assert np.all(np.isnan(track.phase_deg[below]))
    known = track.phase_deg[above]
    assert np.all(np.isfinite(known))
    error = np.abs(np.angle(np.exp(1j * (np.radians(known) - 0.7))))
    assert np.all(error <= np.arcsin(1.05 * floor / low[above])), np.degrees(error)
    # where 'a' is weak, b's amplitude (tracked through b's own windows) is 1 to within 0.155 A
    # (a's leakage into them: |sinc(2.4)| + |sinc(10.4)|), so the floor is F to within that
    weak = high < 0.2
    assert weak.sum() >= 10
    np.testing.assert_allclose(track.leakage_floor[weak], floor, rtol=0.155 * 0.2 + 0.01)
    other = order_track(result, "s", rotor="b", revolutions=TURNS)
    middle_b = (np.arange(len(other.amplitude)) + 0.5) * period / RATIO
    assert np.all(np.isfinite(other.phase_deg[strong(middle_b + period / RATIO / 2) < 1.5]))


def test_the_run_up_figure_draws_no_unknown_phase_and_says_so():
    """The run-up figure of the two orders on a ramp of 300 to 540 rad/s (about 1 % of speed
    change per window: the steady closed form holds): the phase panel draws no point of rotor
    'a''s 1X at the speeds where its amplitude A is below the floor F, draws every one where
    A > 3 F, and its legend says that a's phase is unknown at some speeds. The second rotor
    turns 0.7 times as fast: no window of 4 to 8 turns nulls its 1X (the figure's windows are
    the least leaking of those, 7 turns: F = |sinc(2.1)| + |sinc(11.9)| = 0.055)."""
    from rotordyn_modal.plotting.simulation import plot_runup

    rate = 30.0
    speed = (lambda t: 300.0 + rate * t, lambda t: 300.0 * t + 0.5 * rate * t ** 2)
    result, strong = _two_orders(speed, ratio=0.7)
    floor = _leakage(0.7, 7)
    assert 0.05 < floor < 0.06
    fig = plot_runup(result, "s")
    fig.canvas.draw()
    phase_ax, = [ax for ax in fig.axes if "phase" in ax.get_ylabel()]
    line, = [line for line in phase_ax.get_lines() if line.get_label() == "1X a"]
    x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
    when = (x * np.pi / 30.0 - 300.0) / rate                  # the ramp's time at each point's speed
    half = np.pi * 7 / (x * np.pi / 30.0)                     # half a window [s]
    below, above = strong(when + half) < floor, strong(when - half) > 3.0 * floor
    assert below.sum() >= 5 and above.sum() >= 5
    assert not np.any(np.isfinite(y[below])) and np.all(np.isfinite(y[above]))
    entries = [t.get_text() for t in phase_ax.get_legend().get_texts()]
    assert any(e.startswith("1X a") and "phase unknown" in e for e in entries), entries


# -- 3. the report's unbalance figure: the casing panel's peaks are labelled too --------------

def _report_unbalance_figure(monkeypatch, points=61):
    """The unbalance figure of ``report examples/motor_pump_on_mounts.toml --standard api684
    --mcs 3000`` (only the sections it needs: the Campbell section computes the peaks), drawn by
    the report's own renderer (not rasterised)."""
    import dataclasses
    import importlib

    from rotordyn_modal.report import ReportInputs, collect, render

    collect_module = importlib.import_module("rotordyn_modal.report.collect")

    monkeypatch.setitem(collect_module.STANDARDS, "api684", ("campbell", "unbalance"))
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    data = collect(model, ReportInputs("api684", rdm.rpm(3000.0), points=points))
    figures = []
    monkeypatch.setattr(render, "figure_png", lambda fig, dpi=110: figures.append(fig) or "data:image/png;base64,")
    render.render_html(dataclasses.replace(data, sections=("unbalance",)))
    assert len(figures) == 1
    return figures[0]


def test_the_report_labels_the_casing_panels_peaks(monkeypatch):
    """The report's unbalance figure of the motor and pump on mounts (API 684) labelled the probes'
    peaks with their AF and left the casing sensors' panel without one (the report passed the
    probes' peaks only). On the drawn figure: the casing panel's highest peak (the largest value
    of its curves as drawn, an interior maximum whose amplitude falls to peak / sqrt(2) on both
    sides with an amplification factor N / (N2 - N1) of at least 2.5, API 684's threshold,
    interpolated on the drawn curve) carries a label reading its speed, and every AF label of
    the panel lies inside it, apart from the others, no curve through its glyphs but near its
    own peak."""
    import re

    fig = _report_unbalance_figure(monkeypatch)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    casing, = [ax for ax in fig.axes if "casing" in ax.get_title()]
    curves = [line for line in casing.get_lines() if not line.get_label().startswith("_")
              and line.get_linestyle() not in ("None", "")]
    best = max(curves, key=lambda line: np.nanmax(line.get_ydata()))
    x, y = np.asarray(best.get_xdata(), float), np.asarray(best.get_ydata(), float)
    k = int(np.nanargmax(y))
    # a peak the swept speeds cut is drawn at its true height by a mark (test_unbalance_cut_peaks14):
    # the highest of those, where above every curve, is the panel's highest peak
    marks = [p for line in casing.get_lines() if line.get_gid() == "cut-peak" for p in zip(*line.get_data())]
    highest = max(marks, key=lambda p: p[1], default=(np.nan, -np.inf))
    if highest[1] > y[k]:
        target = float(highest[0])
    else:
        assert 0 < k < len(y) - 1
        half = y[k] / np.sqrt(2.0)
        left = np.nonzero(y[:k] < half)[0][-1]
        right = k + np.nonzero(y[k:] < half)[0][0]
        n1 = np.interp(half, [y[left], y[left + 1]], [x[left], x[left + 1]])
        n2 = np.interp(half, [y[right], y[right - 1]], [x[right], x[right - 1]])
        assert x[k] / (n2 - n1) >= 2.5
        target = x[k]
    labels = [t for t in casing.texts if t.get_visible() and t.get_text().startswith("AF ")]
    speeds = [float(re.match(r"AF [\d.]+ at (\d+) rpm", t.get_text())[1]) for t in labels]
    assert any(abs(s - target) <= 0.5 for s in speeds), (target, [t.get_text() for t in labels])
    boxes = [glyph_box(t, renderer) for t in labels]
    frame = casing.get_window_extent(renderer)
    segments = curve_segments(casing)
    radius = 12.0 * fig.dpi / 72.0                          # a label may touch its own peak's curves
    for text, box in zip(labels, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        anchor = casing.transData.transform(text.xy)
        assert not len(crossings(box, segments, [anchor], radius)), text.get_text()
    for i, a in enumerate(boxes):
        assert not any(a.overlaps(b) for b in boxes[i + 1:])
    matplotlib.pyplot.close(fig)


# -- 4. the 3-D mode shape: no projection of uninitialised memory ------------------------------

def test_the_3d_view_projects_no_uninitialised_padding(monkeypatch):
    """One run of the suite printed matplotlib's 'mplot3d/proj3d.py: RuntimeWarning: overflow
    encountered in dot' in test_mode_shapes.py::test_arrow_names_clear_of_the_bodies_edges
    [motor_pump_on_mounts-2-3000-view_angles1], never alone. The cause: the rotors' faces
    (quadrilateral sides, many-sided ends) were given to ``Poly3DCollection`` as polygons of
    different lengths, which mplot3d pads into an array made by ``np.empty``, and projects
    padding and all (``np.dot``, overflow not silenced); whatever an earlier computation left in
    that memory is multiplied. Here the memory holds the largest double (``np.empty`` of mplot3d returning
    it, as stale memory may), and the figure of that case is drawn and turned to (15, -120) with
    RuntimeWarnings as errors; every vertex a face collection holds is finite and one of its
    body's points."""
    import warnings

    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d import art3d
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    stale = types.SimpleNamespace(**{name: getattr(np, name) for name in dir(np) if not name.startswith("__")})
    stale.empty = lambda shape, *args, **kwargs: np.full(shape, np.finfo(float).max, *args, **kwargs)
    monkeypatch.setattr(art3d, "np", stale)
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(3000.0)), model, 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fig = plot_mode_shape(view, projections=False)
        ax = fig.axes[0]
        ax.view_init(15, -120)
        fig.canvas.draw()
    collections = [c for c in ax.collections if isinstance(c, Poly3DCollection)]
    assert collections
    points = {body.name: p for body, p in zip(view.outline.bodies, view.at_phase(0.0))}
    for collection in collections:
        faces = np.asarray(collection._faces, float).reshape(-1, 3)
        assert np.all(np.isfinite(faces))
        own = points[collection.get_gid().split(":", 1)[1]]
        assert all(np.min(np.abs(own - vertex).sum(axis=1)) <= 1e-12 * (1 + np.abs(own).max()) for vertex in faces)
    plt.close(fig)


# -- 5. an FRF over decades computed at evenly spaced frequencies --------------------------------

def test_sparse_frequencies_on_a_log_axis_are_shown_as_the_points_they_are():
    """``frf examples/motor_pump_on_mounts.toml --speed 3000 --freqs 1:2000:800 --plot``: the
    frequencies are 2.5 Hz apart and the axis is logarithmic (modes from 5 Hz to 1.2 kHz), so the
    mounts' six modes (5-16 Hz) are drawn through eight points joined by straight chords that
    read as the curve (a resonance's peak cut off between two points, nothing said). On the
    drawn figure: every computed point on a line at least 15 pixels along the axis from its
    neighbour is drawn
    as a marker of that line, such points lie around each mount mode (their natural frequencies
    from ``rdm.modal``), and the figure says what the dots are (the frequency axis label)."""
    import matplotlib.pyplot as plt

    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    result = rdm.frf(model, rdm.rpm(3000.0), np.linspace(1.0, 2000.0, 800))
    fig = result.plot()
    fig.canvas.draw()
    mag = fig.axes[0]
    assert mag.get_xscale() == "log"
    mounts = rdm.modal(model, rdm.rpm(3000.0)).frequencies_hz
    mounts = mounts[mounts < 20.0]
    assert len(mounts) == 6
    lines = [line for line in mag.get_lines() if not line.get_label().startswith("_")]
    assert lines
    for line in lines:
        x = np.asarray(line.get_xdata(), float)
        pixels = line.get_transform().transform(np.column_stack([x, np.asarray(line.get_ydata(), float)]))
        gap = np.diff(pixels[:, 0])                       # along the frequency axis
        wide = np.zeros(len(x), bool)
        wide[:-1] |= gap >= 15.0
        wide[1:] |= gap >= 15.0
        assert wide.sum() >= 6
        for f in mounts:                                   # the points around each mount mode
            k = np.searchsorted(x, f)
            assert wide[k - 1] and wide[k], f
        every = line.get_markevery()
        marked = np.zeros(len(x), bool)
        if line.get_marker() not in (None, "None", "", " "):
            if every is None:
                marked[:] = True
            elif np.asarray(every).dtype == bool:
                marked = np.asarray(every, bool)
            else:
                marked[np.asarray(every, int)] = True
        assert np.all(marked[wide]), line.get_label()
    said = [ax.get_xlabel() for ax in fig.axes] + [ax.get_legend().get_title().get_text() for ax in fig.axes
                                                   if ax.get_legend() is not None]
    assert any("dots" in text and "computed" in text for text in said), said
    plt.close(fig)
