"""Figures of a time simulation: time histories, and run-up (order track, waterfall)."""

from __future__ import annotations

import itertools
import warnings

import numpy as np

from ..units import unit_scale
from ..units import rpm_text

__all__ = ["plot_simulation", "plot_runup"]


def plot_simulation(result, title: str | None = None, units: str = "si"):
    """Four panels: rotor centres' path, stator (or carrier) motion and the rotors' tilt in
    their bearings, spin speed, energy terms.

    Parameters
    ----------
    result : SimulationResult
    title : str, optional
    units : {'si', 'us'}
        Unit system of the displacements: the paths in m and translations in mm, or both in
        mil (docs/units.md).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), layout="constrained")
    _draw_paths(axes[0, 0], result, None if units == "si" else unit_scale("displacement", units))
    _draw_frame_motion(axes[0, 1], result, None if units == "si" else unit_scale("displacement", units))
    _draw_spin(axes[1, 0], result)
    _draw_energy(axes[1, 1], result)
    fig.suptitle(title or result.model_name or "Simulation")
    _place_notes(fig)
    return fig


def _draw_paths(ax, result, scale=None):
    """The rotors' centres in the y-z plane, from where each started (``scale``: (factor, unit),
    or None: µm, mm or m, whichever writes them without an offset multiplier)."""
    paths = [result.rotor_centers[:, j] - result.rotor_centers[0, j] for j in range(len(result.rotor_names))]
    factor, unit = scale or _length_unit(max([float(np.abs(p[:, 1:]).max(initial=0.0)) for p in paths] or [0.0]))
    for k, (name, path) in enumerate(zip(result.rotor_names, paths)):
        if np.ptp(path[:, 1:], axis=0).any():
            ax.plot(path[:, 1] * factor, path[:, 2] * factor, lw=0.8, label=name)
        else:   # a path of no length draws nothing: its point, rings of growing size (rotors at one place)
            ax.plot(path[:1, 1] * factor, path[:1, 2] * factor, "o", fillstyle="none", ms=6 + 4 * k,
                    label=f"{name} (no motion)")
    ax.set(xlabel=f"y displacement of the rotor centre [{unit}]", ylabel=f"z displacement [{unit}]",
           title="Path of the rotors' centres (y-z)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize="small")


def _length_unit(largest):
    """``(scale, unit)`` that writes lengths up to ``largest`` [m] without a 1e-5 offset."""
    if largest < 1e-3:
        return 1e6, "µm"
    return (1e3, "mm") if largest < 1.0 else (1.0, "m")


def _draw_frame_motion(ax, result, scale=None):
    """The stator's (or carrier's) transverse rotation and translation (``scale``: (factor,
    unit), or None: µm, mm or m by the largest), and each rotor on bearings' tilt in them.
    Without a stator the bearings stand on the ground, which does not move: the panel draws the
    rotors' tilts alone and says so in a line inside it (:func:`_draw_ground`)."""
    if getattr(result, "frame", "stator") == "ground":
        _draw_ground(ax, result)
        return
    t = result.time
    lines = []
    if result.displacement.any() or not result.rotor_tilts.any():
        gamma = result.gamma_deg
        lines += ax.plot(t, gamma, label=_zero_note("|γ| transverse rotation [deg]", gamma))
    lines += _draw_tilts(ax, result, every=False)
    translation = bool(result.displacement.any() or not result.rotor_tilts.any())
    # the title names what the panel draws (a machine without a stator: rotations only)
    ax.set(xlabel="Time [s]", ylabel="Rotation [deg]",
           title="Transverse rotation and translation" if translation else "Transverse rotation")
    if translation:
        right = ax.twinx()       # lengths on an axis of their own
        factor, unit = scale or _length_unit(float(np.abs(result.displacement).max(initial=0.0)))
        for k, axis in enumerate("xyz"):
            lines += right.plot(t, result.displacement[:, k] * factor, lw=0.8, ls="--", color=f"C{k + 1 + len(lines)}",
                                label=_zero_note(f"u_{axis} [{unit}]", result.displacement[:, k]))
        right.set_ylabel(f"Translation [{unit}]")
    _legend_below(ax, lines)


#: the line inside the time-history panel of a machine whose bearings stand on the ground
GROUND_NOTE = "ground (no stator): fixed"


def _draw_tilts(ax, result, every):
    """Each rotor on bearings' tilt in them [deg] against time: the rotors that tilt, or
    ``every`` rotor (a tilt zero throughout said so in its legend entry); returns the lines."""
    lines = []
    tilts = result.rotor_tilts_deg
    for j, name in enumerate(result.rotor_names):
        tilt = tilts[:, j]
        if every or tilt.any():
            lines += ax.plot(result.time, tilt, lw=0.8, label=_zero_note(f"|γ| {name} in its bearings [deg]", tilt))
    return lines


def _draw_ground(ax, result):
    """The panel of a machine without a stator: its frame is the ground, fixed (its rotation
    and translation, zero by definition, are not drawn); each rotor's tilt in its bearings, and
    :data:`GROUND_NOTE` inside the axes."""
    lines = _draw_tilts(ax, result, every=True)
    ax.set(xlabel="Time [s]", ylabel="Rotation [deg]", title="Transverse rotation of the rotors in their bearings")
    _note(ax, GROUND_NOTE)
    _legend_below(ax, lines)


def _note(ax, text):
    """A line of text inside ``ax`` (``gid='panel-note'``), placed clear of the curves by
    :func:`_place_notes` once the figure is laid out."""
    ax.text(0.02, 0.97, text, transform=ax.transAxes, ha="left", va="top", fontsize="small",
            gid="panel-note", bbox={"boxstyle": "round,pad=0.3", "fc": "white", "ec": "0.6"})


def _place_notes(fig):
    """Move each panel's note (:func:`_note`) to the first corner of its axes where no curve runs
    under it (upper left, upper right, lower left, lower right); where every corner is crossed,
    raise the top of the axes by the note's height and keep it in the upper left."""
    from ._labels import CurveMap, laid_out_renderer

    noted = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_gid() == "panel-note"]
    if not noted:
        return
    renderer = laid_out_renderer(fig)
    for ax, note in noted:
        curves = CurveMap(ax, renderer)
        for x, y, ha, va in ((0.02, 0.97, "left", "top"), (0.98, 0.97, "right", "top"),
                             (0.02, 0.03, "left", "bottom"), (0.98, 0.03, "right", "bottom")):
            note.set(x=x, y=y, ha=ha, va=va)
            box = note.get_window_extent(renderer)
            if curves.free((box.x0, box.y0, box.x1, box.y1)):
                break
        else:
            note.set(x=0.02, y=0.97, ha="left", va="top")
            low, high = ax.get_ylim()
            share = min((note.get_window_extent(renderer).height + 12.0) / ax.get_window_extent(renderer).height, 0.5)
            ax.set_ylim(low, high + (high - low) * share / (1.0 - share))


def _zero_note(label, values):
    """``label``, saying '0 throughout' where ``values`` are all zero: such curves lie on each
    other along the zero line, where only the last drawn shows."""
    return f"{label}: 0 throughout" if not np.any(values) else label


def _draw_spin(ax, result):
    """The reference rotor's axial angular velocity less its start; where that is zero
    throughout, a line inside the panel says so, and why where the cause is known (an ideal
    drive on the fixed ground: no roll of a stator adds to the held speed)."""
    deviation = result.spin_speed - result.spin_speed[0]
    ax.plot(result.time, deviation)
    ax.set(xlabel="Time [s]", ylabel="ω_φ − ω_φ(0) [rad/s]",
           title=f"Axial angular velocity deviation (ω_φ(0) = {result.spin_speed[0]:.4g} rad/s)")
    if not np.any(deviation):
        held = getattr(result, "frame", "stator") == "ground" and getattr(result, "drive", "") == "constant"
        _note(ax, "0 throughout: the drive holds the speed, on the fixed ground (no stator)" if held
              else "0 throughout")


def _draw_energy(ax, result):
    """Changes of the kinetic, total and potential energy from the start."""
    t = result.time
    potential = result.elastic_energy + result.gravity_energy
    ax.plot(t, result.kinetic_energy - result.kinetic_energy[0], label="1: change of kinetic energy")
    # dashed and on top: it lies on 1 where 3 stays 0, on 3 where 1 does (a rotor at constant speed)
    ax.plot(t, result.total_energy - result.total_energy[0], ls="--", label="2: change of total energy", zorder=2.5)
    ax.plot(t, potential - potential[0], label="3: change of potential energy")
    ax.set(xlabel="Time [s]", ylabel="Energy change [J]", title="Energy")
    _legend_below(ax, ax.get_lines())


def _legend_below(ax, lines):
    """The legend of a time history under its axes: inside, it hid the curves' peaks."""
    ax.legend(lines, [line.get_label() for line in lines], fontsize="small", loc="upper center",
              bbox_to_anchor=(0.5, -0.16), ncols=min(len(lines), 2), frameon=False)


def plot_runup(result, sensor: str, critical=None, title: str | None = None, segments: int = 60,
               units: str = "si", steady=None):
    """Run-up: sensor signal, order-tracked amplitude (beside the steady response, where given)
    and phase (unwrapped, joined), waterfall (frequencies up to its content), all against speed.

    Parameters
    ----------
    result : SimulationResult
        A ramp (run-up) simulation.
    sensor : str
    critical : CriticalSpeeds, optional
        The rotors' own orders' crossings: vertical lines, each labelled with its mode, order
        and speed where there is room (on the waterfall: points at their frequencies).
    units : {'si', 'us'}
        Unit system of the sensor's displacement: µm, or mil (docs/units.md).
    steady : dict of str to SteadyOrder, optional
        The linear model's steady unbalance response at the tracks' speeds
        (:func:`~rotordyn_modal.simulation.runup.steady_orders`): its amplitude and phase drawn
        dashed beside each rotor's track, in its colour (the phase moved by whole turns beside the
        track's unwrapped one: ``SteadyOrder.phase_beside``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from ..simulation.runup import STEADY_TOLERANCE, order_track, shade_causes, unsettled_spans, waterfall
    from ._labels import laid_out_renderer

    if critical is not None:  # the rotors' own orders (gear-mesh crossings sit at very low speeds)
        critical = _rotor_orders(critical, result.rotor_names)
    rpm = 30.0 / np.pi
    scale, unit = (1e6, "µm") if units == "si" else unit_scale("displacement", units)
    fig, axes = plt.subplots(2, 2, figsize=(13, 8.5), layout="constrained")
    ax = axes[0, 0]
    ax.plot(result.drive_speed * rpm, result.sensor(sensor) * scale, lw=0.5)
    ax.set(xlabel="Speed of the reference rotor [rpm]", ylabel=f"{sensor} [{unit}]", title="Sensor during the run-up")
    amplitude_ax, phase_ax = axes[0, 1], axes[1, 0]
    notes, unsure = [], []
    for rotor in result.rotor_names:
        track = order_track(result, sensor, rotor=rotor)
        amplitude_ax.plot(track.speeds * rpm, track.amplitude * scale, ".-", ms=3, label=f"1X {rotor}")
        drawn = phase_ax.plot(track.speeds * rpm, track.unwrapped_phase_deg, ".-", ms=3, label=f"1X {rotor}")
        if steady and rotor in steady:
            amplitude_ax.plot(steady[rotor].speeds * rpm, steady[rotor].amplitude * scale, "--", lw=1.0,
                              color=drawn[0].get_color(), gid=f"steady-{rotor}",
                              label=f"1X {rotor}, steady (linear)")
            phase_ax.plot(steady[rotor].speeds * rpm, steady[rotor].phase_beside(track), "--", lw=1.0,
                          color=drawn[0].get_color(), gid=f"steady-phase-{rotor}",
                          label=f"1X {rotor}, steady (linear)")
        notes += _unknown_phase_note(track, result.rotor_names, drawn[0].get_color())
        spans = unsettled_spans(result, track, critical)
        causes = shade_causes(result, track, critical)
        notes += _shade_unsettled((amplitude_ax, phase_ax), spans, rotor, drawn[0].get_color(), rpm, causes)
        if spans:
            unsure.append(f"1X {rotor} at " + ", ".join(f"{rpm_text(low * rpm)}-{rpm_text(high * rpm)}"
                                                        for low, high in spans) + " rpm"
                          + (f" ({'; '.join(causes)})" if causes else ""))
    amplitude_ax.set(xlabel="Speed of the reference rotor [rpm]", ylabel=f"{sensor}, 1X amplitude, 0-peak [{unit}]",
                     title="Order-tracked amplitude")
    phase_ax.set(xlabel="Speed of the reference rotor [rpm]", ylabel=f"{sensor}, 1X phase, unwrapped [deg]",
                 title="Order-tracked phase")
    # ticks every 90 deg where they make at least three (a span under 270 deg got one tick: the
    # compressor's run-up, 60-125 deg), else matplotlib's
    phase_ax.yaxis.set_major_locator(plt.MultipleLocator(90) if 270 <= _span(phase_ax) <= 1080 else plt.MaxNLocator())
    for axis in (amplitude_ax, phase_ax):
        # below the axes: placed 'best' inside, the critical speeds' lines drawn after it (which
        # cross every place) drove it onto the tracks
        _legend_below(axis, axis.get_lines() + (notes if axis is phase_ax else []))
        axis.set_xlim(axes[0, 0].get_xlim())            # the run's speeds, as the signal's panel
    _taller_for_legend(fig, phase_ax)
    _draw_waterfall(fig, axes[1, 1], waterfall(result, sensor, segments=segments), result, critical, sensor,
                    (scale, unit))
    fig.suptitle(title or f"Run-up of {result.model_name or 'the machine'}")
    if unsure:
        warnings.warn(f"run-up: order track may differ from the steady response by more than {STEADY_TOLERANCE:.0%} "
                      "of its peak at " + "; ".join(unsure) + ": shaded on the figure (elsewhere the track is "
                      f"the steady response within {STEADY_TOLERANCE:.0%} of its peak); a slower ramp or a later "
                      "start narrows it")
    if critical is not None and len(critical):
        for axis in (axes[0, 0], amplitude_ax, phase_ax):
            for speed in critical.speeds:
                axis.axvline(speed * rpm, color="tab:red", lw=0.7, ls="--", label="_critical")
        _label_critical_lines([amplitude_ax, phase_ax, axes[0, 0]], critical, laid_out_renderer(fig))
    return fig


#: lines of text the phase panel's legend column may hold before the run-up figure grows taller
#: (two notes of two lines each: the legend's height the figure's 8.5 in were laid out for)
_LEGEND_LINES = 4


def _taller_for_legend(fig, ax):
    """Make ``fig`` taller by the lines of ``ax``'s legend's tallest column beyond
    :data:`_LEGEND_LINES` (at its font's line spacing): otherwise constrained layout takes them
    from the panels, and the amplitude panel's label ran past the figure's top (the shade's notes
    naming their causes, motor_pump_on_mounts: 12 lines)."""
    legend = ax.get_legend()
    if legend is None or not legend.get_texts():
        return
    texts = [t.get_text() for t in legend.get_texts()]
    # the columns as matplotlib fills them (np.array_split), in :func:`_legend_below`'s count
    columns = np.array_split(np.arange(len(texts)), min(len(texts), 2))
    tallest = max(sum(texts[k].count("\n") + 1 for k in column) for column in columns)
    if tallest > _LEGEND_LINES:
        size = legend.get_texts()[0].get_fontsize()
        fig.set_figheight(fig.get_figheight() + (tallest - _LEGEND_LINES) * 1.25 * size / 72.0)


def _shade_unsettled(axes, spans, rotor, color, rpm, causes=()):
    """Shade ``spans`` [rad/s] on ``axes`` (speed axis in rpm, ``rpm`` the factor from rad/s) in
    the track's colour; a legend entry saying what the shade means and why (``causes``:
    :func:`~rotordyn_modal.simulation.runup.shade_causes`), or none without spans."""
    import textwrap

    from matplotlib.patches import Patch

    from ..simulation.runup import STEADY_TOLERANCE

    if not spans:
        return []
    for axis in axes:
        for low, high in spans:
            axis.axvspan(low * rpm, high * rpm, color=color, alpha=0.12, lw=0, zorder=0)
    text = (f"1X {rotor}: may differ from the steady response by more than {STEADY_TOLERANCE:.0%} of its peak"
            + (": " + "; ".join(causes) if causes else ""))
    return [Patch(color=color, alpha=0.25, lw=0, label="\n".join(textwrap.wrap(text, _NOTE_WIDTH)))]


#: the run-up's legend notes are wrapped at this many characters
_NOTE_WIDTH = 45


def _unknown_phase_note(track, rotors, color):
    """A legend entry (a handle of no line) saying at how many speeds the track's phase is not
    drawn and why (the other rotors' same order leaks through the window: ``OrderTrack``),
    or no entry where every phase is known."""
    import textwrap

    from matplotlib.lines import Line2D

    unknown = int(np.count_nonzero(~np.isfinite(track.phase_deg)))
    if not unknown:
        return []
    others = ", ".join(f"{track.order:g}X {name}" for name in rotors if name != track.rotor)
    where = "throughout" if unknown == len(track.phase_deg) else f"at {unknown} of {len(track.phase_deg)} speeds"
    # in lines of at most about 45 characters: the legend below the phase panel is as wide as its
    # two columns, and constrained layout narrowed every panel to fit it (two rotors: each panel
    # a fifth of the figure's width, half of it blank between the columns)
    text = "\n".join(textwrap.wrap(f"{track.order:g}X {track.rotor}: phase unknown {where}, not drawn: its "
                                  f"amplitude is under 2x the leakage of {others}", _NOTE_WIDTH))
    return [Line2D([], [], ls="none", marker="x", color=color, label=text)]


def _span(ax) -> float:
    low, high = ax.get_ylim()
    return high - low


#: the waterfall shows frequencies up to where its amplitude falls below this share of its largest
_WATERFALL_FLOOR = 1e-3
#: ... times this margin (and at least the highest critical speed's frequency times it)
_WATERFALL_MARGIN = 1.25


def _draw_waterfall(fig, ax, fall, result, critical, sensor, shown=(1e6, "µm")):
    """Amplitude over frequency and speed on a log colour scale of three decades, frequencies up
    to the content (:data:`_WATERFALL_FLOOR`) or the highest critical speed's frequency;
    ``shown``: the amplitude's factor and unit."""
    from matplotlib.colors import LogNorm

    rpm = 30.0 / np.pi
    values = fall.amplitude * shown[0]
    top = np.nanmax(values) if values.size and np.nanmax(values) > 0 else 1.0
    image = ax.pcolormesh(fall.frequencies_hz, fall.speeds * rpm, np.maximum(values, top * _WATERFALL_FLOOR),
                          shading="nearest", cmap="viridis", norm=LogNorm(top * _WATERFALL_FLOOR, top))
    fig.colorbar(image, ax=ax, label=f"{sensor}, amplitude, 0-peak [{shown[1]}]")
    ax.set(xlabel="Frequency [Hz]", ylabel="Speed of the reference rotor [rpm]", title="Waterfall",
           xlim=(0, _waterfall_limit(fall, critical)))
    if critical is not None and len(critical):
        points = ax.plot(critical.frequencies_hz, critical.speeds * rpm, "o", mfc="none", color="tab:red",
                         label="critical speeds (Campbell)")
        _legend_below(ax, points)     # inside, its box hid the highest critical speeds' circles


def _waterfall_limit(fall, critical) -> float:
    """Highest frequency worth showing [Hz]: where the content ends, with a margin."""
    f = fall.frequencies_hz
    if not f.size:
        return 1.0
    above = np.nonzero(np.nanmax(fall.amplitude, axis=0) >= _WATERFALL_FLOOR * np.nanmax(fall.amplitude))[0] \
        if np.nanmax(fall.amplitude, initial=0.0) > 0 else np.array([len(f) - 1])
    highest = f[above[-1]] if above.size else f[-1]
    if critical is not None and len(critical):
        highest = max(highest, float(np.max(critical.frequencies_hz)))
    return float(min(f[-1], max(_WATERFALL_MARGIN * highest, f[1] if len(f) > 1 else 1.0)))


def _label_critical_lines(axes, critical, renderer):
    """Label each critical-speed line ('mode 4, 1X fan, 1412 rpm', vertical, at the top of the
    line) in the first of ``axes`` where it overlaps no other label, in two lines where one
    finds no room; returns the labels."""
    from ._labels import CurveMap

    rpm = 30.0 / np.pi
    placed = {id(ax): [ax.get_legend().get_window_extent(renderer)] if ax.get_legend() else [] for ax in axes}
    # a label may lie across other critical lines (where they crowd closer than its width: the
    # last passes), never across the signal or the tracks
    data = {id(ax): CurveMap(ax, renderer, skip=[line for line in ax.get_lines() if line.get_label() == "_critical"])
            for ax in axes}
    labels = []
    texts = {k: f"mode {critical.mode[k]}, {critical.order[k]:g}X {critical.source[k]}, "
                f"{rpm_text(critical.speeds[k] * rpm)} rpm" for k in range(len(critical.speeds))}
    # each label where no other critical line runs through its text (a line through the text
    # reads as the one it names: the gear machine's 'mode 2, 1X fan / 1403 rpm' lay on the 1333
    # rpm line), but for lines that read as one with its own (:data:`_BUNDLE`), in one line, then
    # in two (half as long: the line at 2067 rpm of the gear machine's run-up, between tracks
    # that leave a shorter gap than its label in every panel), clear of the signal and the
    # tracks; last, where critical lines crowd closer than a label's width in every panel,
    # across the fewest of them
    missing = list(np.argsort(critical.speeds))
    passes = [(False, 0), (True, 0), (False, None), (True, None)]
    for wrap, most in passes:
        still = []
        for k in missing:
            speed = f"{rpm_text(critical.speeds[k] * rpm)} rpm"
            text = texts[k].replace(f", {speed}", f"\n{speed}") if wrap else texts[k]
            label = _first_room(axes, critical.speeds[k] * rpm, text, placed, renderer, data, most)
            if label is None:
                still.append(k)
            else:
                labels.append(label)
        missing = still
        if not missing:
            break
    if missing:
        labels.append(_unlabelled_note(axes, critical, sorted(missing, key=lambda k: critical.speeds[k]),
                                       placed, renderer, data))
    return labels


#: the note of the unlabelled critical speeds: entries per line, and its distance from the spines [pt]
_NOTE_ENTRIES, _NOTE_MARGIN = 3, 4.0


def _unlabelled_note(axes, critical, missing, placed, renderer, maps):
    """A note listing the critical speeds ``missing`` (indices) whose lines found no room for a
    label ('no room to label [rpm]: mode 3, 1X pump: 412; ...'), inside the first of ``axes``
    where it lies clear of the labels ``placed``, of the signal and the tracks (``maps``: the
    critical lines may pass behind its opaque box) and :data:`_NOTE_MARGIN` off the spines,
    trying the top, the bottom and the middle from left to right; where none has room, at the
    top left of the first axes. Returns the note."""
    from ._labels import first_free_box

    rpm = 30.0 / np.pi
    entries = [f"mode {critical.mode[k]}, {critical.order[k]:g}X {critical.source[k]}: {critical.speeds[k] * rpm:.0f}"
               for k in missing]
    rows = ["; ".join(entries[i:i + _NOTE_ENTRIES]) for i in range(0, len(entries), _NOTE_ENTRIES)]
    text = "critical speeds with no room for a label [rpm]:\n" + "\n".join(rows)
    style = {"fontsize": "xx-small", "color": "tab:red", "ha": "left", "va": "bottom", "zorder": 5,
             "bbox": {"boxstyle": "square,pad=0.2", "fc": "white", "ec": "tab:red", "lw": 0.5}}
    for ax in axes:
        frame = ax.get_window_extent(renderer)
        margin = _NOTE_MARGIN * ax.figure.dpi / 72.0
        note = ax.text(0.0, 0.0, text, transform=None, **style)
        box = note.get_window_extent(renderer)
        w, h = box.width, box.height
        candidates = [(u, v, u + w, v + h)
                      for v in (frame.y1 - margin - h, frame.y0 + margin, frame.y0 + (frame.height - h) / 2)
                      for u in np.linspace(frame.x0 + margin, frame.x1 - margin - w, 12)]
        # a copy: first_free_box appends the box it takes, which _note_at adds to placed
        found = first_free_box(candidates, [tuple(b.extents) for b in placed[id(ax)]],
                               frame=(frame.x0 + margin, frame.y0 + margin, np.inf, np.inf),
                               allowed=maps[id(ax)].free)
        note.remove()
        if found is not None:
            return _note_at(ax, text, style, found[:2], (w, h), placed[id(ax)])
    ax = axes[0]
    frame = ax.get_window_extent(renderer)
    margin = _NOTE_MARGIN * ax.figure.dpi / 72.0
    return ax.text(margin / frame.width, 1 - margin / frame.height, text, transform=ax.transAxes,
                   **dict(style, va="top"))


def _note_at(ax, text, style, corner, size, placed):
    """The note drawn at its lower left ``corner`` (display units) in axes fraction; its box added to ``placed``."""
    from matplotlib.transforms import Bbox

    frame = ax.transAxes.inverted().transform([corner])[0]
    placed.append(Bbox.from_bounds(corner[0], corner[1], *size))
    return ax.text(frame[0], frame[1], text, transform=ax.transAxes, gid="unlabelled-critical", **style)


def _first_room(axes, x, text, placed, renderer, curves, across=0):
    """The label of the line at ``x`` [rpm] in the first of ``axes`` with room for it, or None
    (``across``: the most other critical lines that may run through its text, see
    :func:`_vertical_label`; None: the place of all ``axes`` where the fewest do)."""
    if across is None:
        found = [(crossed, n, ax, place) for n, ax in enumerate(axes)
                 for crossed, place in _free_places(ax, x, text, placed[id(ax)], renderer, curves[id(ax)])]
        if not found:
            return None
        _, _, ax, place = min(found, key=lambda item: item[:2])
        return _vertical_label(ax, x, text, placed[id(ax)], renderer, curves[id(ax)], np.inf, [place])
    for ax in axes:
        label = _vertical_label(ax, x, text, placed[id(ax)], renderer, curves[id(ax)], across)
        if label is not None:
            return label
    return None


#: critical lines closer than this to a label's own line [pt] read as one with it: a label may
#: lie across them (the gear machine's 1420 rpm line, 2 pt right of the 1403 rpm line, runs
#: through the gap between the 1403 rpm line and its label's text)
_BUNDLE = 3.0
#: critical lines linked by gaps under this [pt] crowd: a label that finds no place clear of
#: the others' lines may lie across those of its crowd (the speed in its text tells them
#: apart), never across a line outside it, which would read as the one it names
_CROWD = 6.0
#: the places of a critical line's label: (side: ha, offset sign), (height: axes fraction, va, rise [pt])
_PLACES = list(itertools.product((("left", 1), ("right", -1)),
                                 ((1.0, "top", -3), (0.0, "bottom", 3), (0.5, "center", 0), (0.35, "center", 0),
                                  (0.65, "center", 0))))


def _vertical_label(ax, x, text, placed, renderer, curves=None, across=0, places=_PLACES):
    """A vertical label just right (else left) of the line at ``x``, at the top of the axes (else
    at the bottom, else at three heights between: ``places``), inside the axes, clear of the boxes in ``placed`` (display
    units, updated), of every curve of ``curves`` (a CurveMap of the signal and the tracks) and
    of the other critical lines but ``across`` of them (none: where they crowd closer than its
    width) and those that read as one with its own (:data:`_BUNDLE`); None where there is no
    room. A label across other critical lines hides them behind an opaque box: seen through its
    box they struck its text out (the fan's run-up: 'mode 1, 1X fan, 798 rpm' under the lines at
    866 and 880 rpm)."""
    for crossed, _, label, box, covers in _free_labels(ax, x, text, placed, renderer, curves, places):
        if crossed <= across:
            if covers:
                label.get_bbox_patch().set_alpha(1.0)
            placed.append(box)
            return label
        label.remove()
    return None


def _free_places(ax, x, text, placed, renderer, curves=None, places=_PLACES):
    """``(other critical lines through the label's text, place)`` of each place of ``places``
    where the label of the line at ``x`` lies inside ``ax``, clear of the boxes ``placed`` and of
    the curves of ``curves`` (:func:`_free_labels`; no label is left drawn)."""
    for crossed, place, label, _, _ in _free_labels(ax, x, text, placed, renderer, curves, places):
        label.remove()
        yield crossed, place


def _free_labels(ax, x, text, placed, renderer, curves=None, places=_PLACES):
    """``(crossed, place, label, box, covers)`` of each place of ``places`` where the label of the
    line at ``x`` lies inside ``ax``, clear of the boxes ``placed`` and of the curves of
    ``curves``: how many other critical lines run through its text, the place as in ``places``,
    the label drawn there, its box (display units) and whether it covers another critical line.
    The labels of the places not given are removed here; the caller removes those it does not
    take."""
    frame = ax.get_window_extent(renderer)
    pad = 2.0 * ax.figure.dpi / 72.0
    line_x = ax.transData.transform((x, 0.0))[0]
    own = (line_x - 0.5, frame.y0, line_x + 0.5, frame.y1)       # its own line, beside it
    others, bundled, foreign = _other_lines(ax, x, line_x)
    for place in places:
        (ha, shift), (y, va, rise) = place
        label = ax.annotate(text, (x, y), xycoords=("data", "axes fraction"), xytext=(shift * 2, rise),
                            textcoords="offset points", rotation=90, ha=ha, va=va, fontsize="x-small",
                            color="tab:red", bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none",
                                                   "alpha": 0.7})
        box = label.get_window_extent(renderer)
        inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        clear = curves is None or curves.free((box.x0, box.y0, box.x1, box.y1), keep=own)
        if inside and clear and not np.any((foreign > box.x0) & (foreign < box.x1)) and not any(
                box.x0 < b.x1 + pad and b.x0 < box.x1 + pad and box.y0 < b.y1 + pad and b.y0 < box.y1 + pad
                for b in placed):
            crossed = int(np.count_nonzero((others > box.x0) & (others < box.x1)))
            yield crossed, place, label, box, bool(crossed or np.any((bundled > box.x0) & (bundled < box.x1)))
            continue
        label.remove()


def _other_lines(ax, x, line_x):
    """The display x of the critical lines of ``ax`` (its lines labelled '_critical') other than
    the one at ``x`` [rpm] (at ``line_x`` on the display): ``(farther, nearer, foreign)``,
    farther and nearer than :data:`_BUNDLE` from it, and those of the farther outside its crowd
    (the lines linked to it by gaps under :data:`_CROWD`), shapes (n,), (m,), (k,)."""
    xs = np.array([float(np.asarray(line.get_xdata(), float)[0]) for line in ax.get_lines()
                   if line.get_label() == "_critical" and float(np.asarray(line.get_xdata(), float)[0]) != x])
    if not len(xs):
        return xs, xs, xs
    px = ax.transData.transform(np.column_stack([xs, np.zeros_like(xs)]))[:, 0]
    points = ax.figure.dpi / 72.0
    far = np.abs(px - line_x) > _BUNDLE * points
    every = np.sort(np.append(px, line_x))
    groups = np.concatenate([[0], np.cumsum(np.diff(every) > _CROWD * points)])
    own = groups[np.searchsorted(every, line_x)]
    crowd = (px >= every[groups == own][0]) & (px <= every[groups == own][-1])
    return px[far], px[~far], px[far & ~crowd]


def _rotor_orders(critical, rotor_names):
    from dataclasses import fields, replace

    keep = np.isin(critical.source, rotor_names)
    return replace(critical, **{f.name: getattr(critical, f.name)[keep] for f in fields(critical)})

