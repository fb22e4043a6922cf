"""Figures of the eighth audit (issue 27, section 3, and issue 29: every figure the command line
draws, for every example and for machines whose modes span 5 Hz to 1 kHz, read by a fresh
reviewer), measured on the drawn figure (``fig.canvas.draw()``, glyph boxes, the curves as
drawn: ``tests/label_geometry.py``), independent of the code that places things.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import crossings, curve_segments, glyph_box

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("example, mode, rpm", [
    ("motor_pump_on_mounts", 6, 3000.0), ("motor_pump_on_mounts", 1, 3000.0), ("gear_machine", 5, 3000.0)])
def test_no_line_of_the_3d_view_runs_under_a_sensors_name(example, mode, rpm):
    """``modes motor_pump_on_mounts.toml --speed 3000 --shape 6``: the name 'hammer-z' stood beside
    its arrow, clear of the bodies and the arrows, but on a mount's whirl orbit, whose piece under
    the name's white background vanished. On the drawn 3-D view (mplot3d projects its lines and
    line collections at draw time, so the axes' lines hold what is drawn): no line or line
    collection the view draws (bodies, orbits and their arrows, springs, spin arcs, the sensors'
    and excitations' arrows), a name's own leader line aside, runs through a name's glyphs."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(rpm)), model, mode)
    fig = plot_mode_shape(view)                    # as the command line draws it: with projections
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    leaders = [line for line in ax.get_lines() if str(line.get_gid()).startswith("arrow-leader:")]
    segments = curve_segments(ax, skip=leaders)
    names = [text for text in ax.texts if str(text.get_gid()).startswith("arrow-label:")]
    assert len(names) == len(view.outline.arrows) and len(segments) > 100
    for text in names:
        through = crossings(glyph_box(text, renderer), segments)
        assert not len(through), f"a drawn line runs through the name {text.get_text()!r} at {through[0]}"


def test_a_followed_mode_that_crosses_zero_is_seen_crossing_it():
    """``level1 fan_on_bearings.toml --mcs 4500 --station fan --qa 2e5``: the fan's mode 10 dives to
    a log decrement of -2.5 at 10 Qa, and sets the axis; mode 8 (forward 1) becomes unstable at
    Q0/Qa = 0.33 and stable again near 4.7 Qa with log decrements of at most 0.014 either side of
    zero, a line 2 pixels from the zero line, its crossings hidden under it and under mode 10's
    Q0 marker. On the drawn figure: every followed mode whose log decrement changes sign over the
    sweep is drawn in some panel where, on both sides of the zero line, its curve reaches at least
    8 pixels from it inside the panel; the curves are found by their data (the result's log
    decrements), not by the code's labels."""
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.level1(model, rdm.rpm(4500.0), ["fan"], 2.0e5, steps_per_qa=5)
    crossing = [run for run in result.swept if np.nanmin(run.log_decrements) < 0 < np.nanmax(run.log_decrements)]
    assert len(crossing) >= 2                       # modes 8 and 10
    fig = result.plot()
    fig.canvas.draw()
    for run in crossing:
        seen = []
        for ax in fig.axes:
            frame = ax.get_window_extent()
            zero = ax.transData.transform((0.0, 0.0))[1]
            for line in ax.get_lines():
                y = np.asarray(line.get_ydata(), float)
                if y.shape != run.log_decrements.shape or not np.allclose(y, run.log_decrements, equal_nan=True):
                    continue
                points = line.get_transform().transform(np.column_stack([line.get_xdata(), y]))
                inside = points[(points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1)
                                & (points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1), 1]
                seen.append(inside.size and inside.max() - zero >= 8 and zero - inside.min() >= 8)
        assert any(seen), f"{run.mode_label}: its crossing of zero is not seen in any panel"


def test_order_labels_on_a_log_axis_stand_nearest_their_own_lines():
    """flexible_pump_on_mounts, 0-3600 rpm, orders 1 and 2: its shaft modes reach 100 kHz, so the
    logarithmic frequency axis squeezes the four order lines into its bottom third, 20 pixels
    apart at the right edge (each a constant ratio above the next). '1X pump', stepped down
    from its exit to find room, stood under the 1X motor line, nearer it than its own. On the
    drawn figure (each order line through its own transform, the labels' turned outlines):
    every order line is named by a label inside the axes, clear of every curve, whose centre
    lies nearer one of the lines it names than any other order line."""
    import re

    from label_geometry import named_orders, order_curves, outline, outline_crossings, point_segments_distance

    sweep = rdm.campbell(rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml"),
                         rdm.rpm(np.linspace(0.0, 3600.0, 37)), orders=(1, 2))
    fig = sweep.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    assert ax.get_yscale() == "log"
    lines = order_curves(ax)
    multiplier = dict(zip(sweep.sources.names, sweep.sources.multipliers))
    assert len(lines) == 2 * len(multiplier)
    segments = curve_segments(ax)
    frame = ax.get_window_extent()
    named = set()
    for text in ax.texts:
        match = re.fullmatch(r"(?P<orders>\d+X(?:, \d+X)*) (?P<source>\S+)", text.get_text())
        if not text.get_visible() or match is None or match["source"] not in multiplier:
            continue
        corners = outline(text, renderer)
        assert np.all((corners >= (frame.x0, frame.y0)) & (corners <= (frame.x1, frame.y1))), text.get_text()
        mine = {round(o * abs(multiplier[match["source"]]) / 60.0, 9) for o in named_orders(match["orders"])}
        centre = corners.mean(axis=0)
        nearest = min(lines, key=lambda slope: point_segments_distance(lines[slope], centre))
        assert nearest in mine, f"{text.get_text()!r} stands nearest the line of {nearest * 60:g} Hz per rpm/60"
        assert not len(outline_crossings(text, renderer, segments)), f"a curve runs through {text.get_text()!r}"
        named |= mine
    assert named == set(lines), sorted(set(lines) - named)


def _named_in(text, label) -> bool:
    """Whether a note's ``text`` names mode ``label`` ('modes 1-56, 59-68 reach ...')."""
    import re

    for first, last in re.findall(r"(\d+)(?:-(\d+))?", text.split(":")[0] if ":" in text else text.split(" reach")[0]):
        if int(first) <= label <= int(last or first):
            return True
    return False


@pytest.mark.parametrize("example, top_rpm", [("flexible_pump_on_mounts", 3600.0), ("compressor_rotor", 12000.0)])
def test_every_mode_the_stability_legend_names_is_seen_or_said_in_each_panel(example, top_rpm):
    """``stability flexible_pump_on_mounts.toml --speeds 0:3600:37``: the legend names seven modes
    in colour; in the log decrement panel, scaled by bearing modes' 1e-3, the shaft modes'
    log decrements (1e-8 to 6e-6) lay on the zero line, their colours seen nowhere and no note
    saying so. On the drawn figure, in each panel, each mode the legend names is either drawn
    (found by its data: the result's real parts or log decrements) at least 2 pixels from the
    zero line somewhere inside the panel (or is the one such mode lying on the zero line there,
    drawn over it), or named by a note beside the panel. The compressor
    rotor's axial mode is undamped (real part 0 to round-off) and lay under its shaft modes'
    curves on the zero line of the log decrement panel."""
    import re

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    result = rdm.stability(model, rdm.rpm(np.linspace(0.0, top_rpm, 13)))
    fig = result.plot()
    fig.canvas.draw()
    top, bottom = fig.axes[:2]
    # each panel's legend names the modes it draws (figs27o): the modes of both
    named = sorted({int(re.fullmatch(r"mode (\d+)", t.get_text())[1]) for ax in (top, bottom) if ax.get_legend()
                    for t in ax.get_legend().get_texts() if re.fullmatch(r"mode \d+", t.get_text())})
    assert len(named) >= 4          # (the flexible pump's: 4 since its axes fit the modes below 600 Hz)
    for ax, values in ((top, result.real_parts), (bottom, result.log_decrements)):
        frame = ax.get_window_extent()
        zero = ax.transData.transform((0.0, 0.0))[1]
        # beside the panel (the bottom one's under its legend, figs27o): right of its frame
        notes = [t.get_text().replace("\n", " ") for t in ax.texts if t.get_window_extent().x0 > frame.x1]
        unseen = []
        for label in named:
            column = values[:, list(result.modes).index(label)]
            seen = False
            for line in ax.get_lines():
                y = np.asarray(line.get_ydata(), float)
                if y.shape == column.shape and np.allclose(y, column, equal_nan=True, rtol=1e-12, atol=0.0):
                    pixels = line.get_transform().transform(np.column_stack([line.get_xdata(), y]))[:, 1]
                    inside = pixels[(pixels >= frame.y0) & (pixels <= frame.y1)]
                    seen |= bool(inside.size and np.abs(inside - zero).max() >= 2.0)
            if not seen and not any(_named_in(note, label) for note in notes):
                unseen.append(label)
        assert len(unseen) <= 1, \
            f"modes {unseen} are in the legend but lie on one another on zero, unnamed, in {ax.get_ylabel()!r}"


@pytest.mark.parametrize("color_by", [None, "log_decrement"])
def test_a_long_model_name_as_campbell_title_stays_inside_the_figure(color_by):
    """``campbell flexible_pump_on_mounts.toml --color-by log_decrement``: the model's name (80
    characters) is the title, centred over an axes that the colour bar narrows, and it ran off
    the figure's left edge ('otor and belt-driven pump ...'). On the drawn figure the title's
    glyphs lie inside the figure and it reads the whole name (its lines joined)."""
    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    sweep = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3600.0, 5)), orders=(1,))
    fig = sweep.plot(color_by=color_by, title=model.name)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    title = fig.axes[0].title
    box = glyph_box(title, renderer)
    assert " ".join(title.get_text().split()) == " ".join(model.name.split())
    assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and box.y1 <= fig.bbox.y1, (box, fig.bbox)


def test_the_shear_force_is_the_derivative_along_the_shafts_own_axis():
    """``static flexible_pump_on_mounts.toml --plot``: the pump's shaft runs along x ('position
    along x [m]', planes x-y and x-z in the legend) and the title read 'V = dM/dz', z being on
    this figure the transverse axis of the x-z plane. The title's derivative is along the axis
    the abscissa names."""
    import re

    static = rdm.static(rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml"))
    fig = static.plot_shafts()
    along = re.search(r"position along (\w+)", fig.axes[-1].get_xlabel() or fig.axes[2].get_xlabel())[1]
    derivative = re.search(r"V = dM/d(\w+)", fig.get_suptitle())[1]
    assert derivative == along == "x"


def test_ucs_map_names_moved_apart_are_joined_to_their_curves():
    """``ucs-map flexible_pump_on_mounts.toml --stiffness 1e5:1e10:41``: four modes end within 12 %
    of the axis' height at the sweep's last stiffness; their names beside the right edge were
    moved apart, '5 pump axial' 45 pixels above its curve with nothing joining them; and the
    title (the model's 80-character name) ran off both sides of the figure. On the drawn figure:
    every name beside the right edge either stands at its curve's end (its centre within half
    its height of it) or has a drawn leader line from its curve's end at the edge; the title
    lies inside the figure."""
    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    result = rdm.ucs_map(model, np.geomspace(1e5, 1e10, 21))
    fig = result.plot(title=f"Undamped critical speed map: {model.name}")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    frame = ax.get_window_extent()
    title = glyph_box(ax.title, renderer)
    assert fig.bbox.x0 <= title.x0 and title.x1 <= fig.bbox.x1, (title, fig.bbox)
    rpm = result.mode_speeds * 30 / np.pi
    checked = moved = 0
    for j, name in enumerate(result.mode_names):
        if not np.isfinite(rpm[-1, j]):
            continue
        text = next(t for t in ax.texts if t.get_text() == f"{j + 1} {name}")
        box = glyph_box(text, renderer)
        assert box.x0 >= frame.x1, text.get_text()
        end = ax.transData.transform((result.stiffness[-1], rpm[-1, j]))[1]
        checked += 1
        if abs(0.5 * (box.y0 + box.y1) - end) <= 0.5 * box.height:
            continue
        moved += 1
        arrow = getattr(text, "arrow_patch", None)
        assert arrow is not None and arrow.get_visible(), f"{text.get_text()!r} stands off its curve, no leader"
        points = arrow.get_path().vertices
        assert np.min(np.hypot(points[:, 0] - frame.x1, points[:, 1] - end)) < 1.5, text.get_text()
        assert np.min(np.hypot(points[:, 0] - box.x0, points[:, 1] - 0.5 * (box.y0 + box.y1))) < 0.5 * box.height + 2
    assert checked >= 4 and moved >= 1


def test_the_real_part_panel_is_scaled_to_the_damped_modes_beside_an_undamped_one():
    """``stability compressor_rotor.toml --speeds 0:12000:61``: its axial mode is undamped (real
    part 0 to round-off) and the least damped; the panel then took the round-off floor's height
    (1e-4 of the largest root: +26 1/s above zero, -3.6 below), no real part being positive,
    and the bending modes' real parts (-0.0016 to -0.5 1/s) lay flat on zero. On the drawn
    figure: where no real part is positive beyond round-off, the panel's part above zero is at
    most a fifth of its height, and the least damped mode that is damped (the largest real part
    below zero that is not round-off, at every speed) lies at least a tenth of the panel's
    height below zero."""
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    result = rdm.stability(model, rdm.rpm(np.linspace(0.0, 12000.0, 13)))
    significant = result.significant_real_parts
    assert np.nanmax(significant) <= 0 and np.any(np.all(significant == 0, axis=0))
    fig = result.plot()
    fig.canvas.draw()
    top = fig.axes[0]
    low, high = top.get_ylim()
    assert high <= 0.2 * (high - low), (low, high)
    damped = np.where(significant < 0, significant, -np.inf).max(axis=1)          # per speed
    assert np.all(damped >= low) and np.all(-damped >= 0.1 * (high - low)), (damped, low, high)


@pytest.mark.parametrize("example, top_rpm", [("counter_rotating", 6000.0), ("rubber_mounts", 6000.0)])
def test_a_critical_speed_leader_ends_at_its_own_circle_through_no_other(example, top_rpm):
    """counter_rotating, 0-6000 rpm, orders 1 and 2: the gear mesh's lines cross modes 1 and 2
    (11.3 and 12.3 Hz) at 11-24 rpm, four circles in two pairs 13 pixels apart, one above the
    other. The label '11/21.9' (mode 1's pair) stood above both, its leader running through
    mode 2's circles and ending as near them as its own. On the drawn figure: each leader line of
    a critical-speed label (found by its start on the label's glyph box) ends nearer a circle of
    a speed the label reads than any other circle, and passes no other circle's centre closer
    than the circle's radius plus a pixel. rubber_mounts: mode 6's crossings with the mesh's 2X
    and 1X lines, 38.6 and 77.2 rpm, are circles 5 pixels apart, overlapping; '38.6' had a
    label of its own whose leader ended on the 77.2 circle."""
    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    sweep = rdm.campbell(model, rdm.rpm(np.linspace(0.0, top_rpm, 121)), orders=(1, 2))
    fig = sweep.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    speeds = sweep.critical.speeds * 30 / np.pi
    centres = ax.transData.transform(np.column_stack([speeds, sweep.critical.frequencies_hz]))
    radius = 0.5 * 6 * fig.dpi / 72                 # the circles' markersize: 6 points across
    labels = [(t, glyph_box(t, renderer)) for t in ax.texts
              if t.get_visible() and t.get_text() and all(w.replace(".", "", 1).isdigit() for w in t.get_text().split("/"))]
    checked = 0
    for line in ax.get_lines():
        x, y = line.get_data()
        if not line.get_visible() or len(x) != 2 or line.get_linestyle() in ("None", ""):
            continue
        start, end = line.get_transform().transform(np.column_stack([x, y]))
        owner = [(t, b) for t, b in labels if b.x0 - 1.5 <= start[0] <= b.x1 + 1.5 and b.y0 - 1.5 <= start[1] <= b.y1 + 1.5]
        if len(owner) != 1:
            continue
        words = [float(w) for w in owner[0][0].get_text().split("/")]
        mine = np.array([any(abs(s - w) <= max(0.06, 0.0051 * w) for w in words) for s in speeds])
        assert mine.any(), owner[0][0].get_text()
        distance = np.hypot(*(centres - end).T)
        assert mine[np.argmin(distance)], f"{owner[0][0].get_text()!r}: its leader ends nearest another circle"
        d = end - start
        t = np.clip(((centres - start) @ d) / (d @ d), 0.0, 1.0)
        passing = np.hypot(*(start + t[:, None] * d - centres).T)
        assert np.all(passing[~mine] > radius + 1.0), f"{owner[0][0].get_text()!r}: its leader runs through a circle"
        checked += 1
    assert checked >= 5


def test_a_time_history_panel_titled_translation_draws_one():
    """``simulate spring_block_rotor.toml --free-spin --plot``: the rotor sits in its block of
    springs on the ground (no stator), so the panel draws the rotor's tilt only, and its title
    read 'Transverse rotation and translation'. On the drawn figure: a panel whose title names a
    translation has an axis whose label names it, with curves on it."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = rdm.simulate(model, 0.05, 50.0, drive="free", samples=50, backend="numpy")
    fig = result.plot()
    fig.canvas.draw()
    titled = [ax for ax in fig.axes if "translation" in ax.get_title().lower()]
    for ax in titled:
        twins = [other for other in fig.axes if other is not ax and other.bbox.bounds == ax.bbox.bounds]
        drawn = [other for other in twins if "Translation" in other.get_ylabel() and other.get_lines()]
        assert drawn, f"{ax.get_title()!r} draws no translation"
    assert any("rotation" in ax.get_title().lower() for ax in fig.axes)


def test_an_undamped_machine_coloured_by_log_decrement_reads_zero_not_noise():
    """``campbell spring_block_rotor.toml --color-by log_decrement``: the machine has no damping,
    its log decrements are round-off (+-2e-15), and the colour bar ran from -2e-15 to 3e-15
    ('1e-15' over it), the curves speckled over the whole colour map, half of it below zero:
    damping that varies and is negative, to a reader. On the drawn figure (every root's real
    part within 1e-12 of its size, checked first): the colour bar's scale holds no negative
    log decrement, spans a readable range (at least 0.01, no multiplier over it), and every
    curve is drawn in the colour of 0."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    sweep = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3000.0, 13)))
    roots = sweep.eigenvalues[np.isfinite(sweep.eigenvalues)]
    assert np.all(np.abs(roots.real) <= 1e-12 * np.abs(roots))
    fig = sweep.plot(color_by="log_decrement")
    fig.canvas.draw()
    colourbar = fig.axes[-1]
    low, high = colourbar.get_ylim()
    assert low >= 0.0 and high - low >= 0.01, (low, high)
    assert colourbar.yaxis.get_offset_text().get_text() == ""
    from matplotlib.collections import LineCollection

    coloured = [c for c in fig.axes[0].collections if isinstance(c, LineCollection) and c.get_array() is not None]
    assert coloured
    zero = np.asarray(coloured[0].cmap(coloured[0].norm(0.0)))
    for collection in coloured:
        colours = collection.get_colors()
        assert np.allclose(colours[:, :3], zero[:3], atol=1e-6), "a curve of an undamped mode is not the colour of 0"


def test_the_largest_peak_of_an_unbalance_panel_is_labelled_first():
    """``unbalance gear_machine.toml --speeds 0:6000:301 --operating-speed 3000 --plot``: of the
    headroom above the curves that it tries, the figure kept the one that labelled the most
    peaks, three smaller ones, and left the panel's highest peak unlabelled (acc-side-y, 1X fan,
    AF 21.6 at 1400 rpm, 25 um; at the headroom chosen its two-line label found no room). Drawn
    at the command line's resolution (150 dpi): among the peaks of the result's table that the
    figure labels at all (AF >= 2.5, the label reading 'AF ... at N rpm'), the one of the largest
    amplitude has its label."""
    import re

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    response = rdm.unbalance_response(model, rdm.rpm(np.linspace(0.0, 6000.0, 301)))
    peaks = response.peaks(rdm.rpm(3000.0))
    fig = response.plot(peaks=peaks)
    fig.set_dpi(150)
    fig.canvas.draw()
    ax = fig.axes[0]
    labelled = {(int(m[2]), m[3]) for m in
                (re.match(r"AF ([\d.]+) at (\d+) rpm \(1X (\w+)\)", t.get_text()) for t in ax.texts) if m}
    assert labelled, "no peak is labelled"
    eligible = peaks[(peaks.amplification_factor >= 2.5) & np.isfinite(peaks.amplification_factor)]
    largest = eligible.loc[eligible.amplitude.idxmax()]
    assert (round(largest.speed_rpm), largest.source) in labelled, (largest.to_dict(), labelled)


def test_unbalance_phase_lines_do_not_jump_across_the_panel():
    """``unbalance motor_fan_minimal.toml --speeds 100:3600:121 --plot``: the casing sensor's phase
    wraps from -180 to 180 deg near 3350 rpm and was joined there by a vertical line across the
    whole phase panel (as were the fan's and gear machine's), reading as a curve of its own (the
    FRF's phase had been broken at its wraps, the unbalance figure's not). On the drawn figure:
    no segment of a phase line joins neighbouring speeds more than 180 deg apart, and each phase
    line still draws the result's phases (every finite point one of them)."""
    model = rdm.load_model(EXAMPLES / "motor_fan_minimal.toml")
    response = rdm.unbalance_response(model, rdm.rpm(np.linspace(100.0, 3600.0, 121)))
    assert np.any(np.abs(np.diff(response.phase_deg, axis=-1)) > 180.0)       # the phase wraps
    fig = response.plot()
    fig.canvas.draw()
    phases = [ax for ax in fig.axes if ax.get_ylabel().startswith("Phase")]
    assert phases
    drawn = 0
    for ax in phases:
        for line in ax.get_lines():
            y = np.asarray(line.get_ydata(), float)
            if len(y) < 3:
                continue
            both = np.isfinite(y[:-1]) & np.isfinite(y[1:])
            assert np.all(np.abs(np.diff(y)[both]) <= 180.0), "a phase line jumps across the panel"
            values = response.phase_deg.reshape(-1, response.phase_deg.shape[-1])
            assert any(np.allclose(y[np.isfinite(y)], row) for row in values)
            drawn += 1
    assert drawn >= 1


def test_ucs_map_bearing_curves_outside_the_axes_say_so_in_the_legend():
    """``ucs-map journal_rotor.toml`` over stiffnesses the journal bearings never reach (here
    1e9-1e12 N/m; the same with --units us and 1e5:1e10 lbf/in): the legend listed 'DE, NDE Kxx'
    and 'Kyy' (1e7 N/m, left of the axis) though neither was drawn anywhere in the axes. On the
    drawn figure: each legend entry of a bearing's stiffness either has its line running inside
    the axes or says that it lies outside them."""
    model = rdm.load_model(EXAMPLES / "journal_rotor.toml")
    result = rdm.ucs_map(model, np.geomspace(1e9, 1e12, 11))
    fig = result.plot()
    fig.canvas.draw()
    ax = fig.axes[0]
    frame = ax.get_window_extent()
    entries = [line for line in ax.get_lines() if " K" in line.get_label() and not line.get_label().startswith("_")]
    assert entries
    for line in entries:
        with np.errstate(all="ignore"):
            points = line.get_transform().transform(np.column_stack(line.get_data()))
        inside = np.any((points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1)
                        & (points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1))
        assert inside or "outside the axes" in line.get_label(), line.get_label()


def test_a_sensitivity_bar_too_short_to_see_says_so_in_the_legend():
    """``study gear_machine.toml --spec mount_sobol.study.toml --plot-sensitivity``: the fan's
    diametral inertia has total Sobol indices of 6e-5 at most beside the mounts' 0.8, bars of no
    pixel, and the legend showed its orange entry over a chart with no orange on it. Drawn from
    a given table (the plotting computes nothing): a parameter whose every bar is shorter than a
    pixel of the drawn axis has a legend entry that says it is not seen; the others' entries are
    their names."""
    import pandas as pd

    from rotordyn_modal.plotting.study import plot_sensitivity

    rows = []
    for k, output in enumerate(["f1", "f2", "f3"]):
        for parameter, st in (("mass", 0.1 + 0.1 * k), ("inertia", 3e-5 * (k + 1)), ("mounts", 0.8 - 0.1 * k)):
            rows.append({"output": output, "parameter": parameter, "S1": 0.9 * st, "ST": st, "ST_se": 0.1 * st})
    fig = plot_sensitivity(pd.DataFrame(rows))
    fig.canvas.draw()
    ax = fig.axes[0]
    pixels = abs(ax.transData.transform((1.0, 0.0))[0] - ax.transData.transform((0.0, 0.0))[0])
    texts = {t.get_text() for t in ax.get_legend().get_texts()}
    for parameter in ("mass", "inertia", "mounts"):
        longest = max(r["ST"] for r in rows if r["parameter"] == parameter) * pixels
        entry = next(t for t in texts if t.split(" (")[0] == parameter)
        assert (longest < 1.0) == ("not seen" in entry or "no bar seen" in entry), (parameter, longest, entry)
