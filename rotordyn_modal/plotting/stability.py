"""Stability figures: real parts over speed and maps over a parameter."""

from __future__ import annotations

import numpy as np

from ._style import new_figure, speed_label, speed_scale

__all__ = ["plot_stability", "plot_stability_map"]


#: the axes reach this many times the least damped mode's range (its lowest real part, its
#: highest log decrement over the speeds) where the modes that matter reach further
_REACH = 3.0
#: at most this many modes are drawn in colour beside those least damped at some speed ...
_SHOWN = 6
#: ... and only those whose log decrement comes below this somewhere (damping ratio ~0.16)
_LIGHTLY_DAMPED = 1.0
#: modes the axes show get their own colour and legend entry, this many at most
_LEGEND = 7
#: zero keeps at least this fraction of each panel's height from its bottom and top
_ZERO_ROOM = 0.12
#: real parts within this fraction of the largest root are round-off of undamped modes
_NOISE = 1e-4
#: real parts spanning less than this fraction of the largest root are round-off (the panel then
#: takes the height _NOISE of it)
_ROUND_OFF = 1e-9
_STYLES = ("-", "--", ":", "-.")
#: where a mode far above the running speed is less damped than every mode near it, the axes are
#: scaled to the modes that come below this many times the sweep's highest running frequency at
#: some speed (a decade: the running speed's first ten orders, and the modes that oil whirl,
#: internal damping and cross-coupling destabilise, which lie below or near it), and to every
#: mode unstable somewhere; the others are grey lines, named in a note with the least damped of
#: them (the flexible pump's 69 kHz shaft modes, log decrement 5e-9, 690 times its top speed,
#: scaled the figure so that every mode below 1 kHz lay off its axes)
_DECADE = 10.0


def plot_stability(result, speed_unit: str = "rpm", title: str | None = None):
    """Real parts and log decrements of the tracked modes over speed.

    The figure is scaled to the modes that decide stability (:func:`modes_that_matter`):
    those that are the least damped at some speed, and up to :data:`_SHOWN` more of the
    lightly damped ones. Those of them that the axes show, then any other mode the axes show,
    get their own colour (and line style) and a legend entry, the least damped first, seven
    at most; every other root is a thin grey line. The axes reach 10 % beyond the
    modes that matter, but no further than :data:`_REACH` times the least damped mode's
    range (its lowest real part, its highest log decrement over the speeds), and keep zero
    well inside; a note beside each panel names the roots that reach beyond it and how far
    (overdamped roots of journal bearings reach real parts of -10,000 1/s and log
    decrements of 1,000). Each panel's legend names the curves drawn inside it (a coloured
    mode that a panel does not show is named by its note instead). Where a mode far above the running speed is less damped than every mode near it,
    the figure is scaled to the modes near it (:func:`near_operating_range`), and a note names
    the far ones and the least damped of them. Each threshold speed is a labelled vertical
    line: red where a mode becomes unstable with rising speed, green where it becomes stable
    again.

    Parameters
    ----------
    result : StabilityResult
    speed_unit : {'rpm', 'rad/s', 'hz'}
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8.0, 7.0), layout="constrained")
    scale = speed_scale(speed_unit)
    x = result.speeds * scale
    real = np.where(np.isfinite(result.real_parts), result.real_parts, np.nan)
    log_dec = np.where(np.isfinite(result.log_decrements), result.log_decrements, np.nan)
    near = near_operating_range(result)
    focus = np.where(near, log_dec, np.nan)
    relevant = modes_that_matter(focus)
    size = np.abs(result.eigenvalues[np.isfinite(result.eigenvalues)])
    largest = size.max() if size.size and size.max() > 0 else 1.0
    top.set_ylim(*zero_centred_limits(*_real_part_span(np.where(near, real, np.nan), focus, relevant,
                                                       result.significant_real_parts),
                                      _NOISE * largest, tiny=_ROUND_OFF * largest))
    bottom.set_ylim(*zero_centred_limits(*_log_decrement_span(focus, relevant, result.significant_real_parts),
                                         1e-3))
    shown = [m for m in relevant + [m for m in _by_damping(focus) if m not in relevant]
             if _within(real[:, m], top.get_ylim()) or _within(log_dec[:, m], bottom.get_ylim())][:_LEGEND]
    _draw_modes(top, bottom, x, result, real, log_dec, shown, others="other roots (more damped)" if near.all()
                else "other roots")
    for axis, values, unit in ((top, real, "1/s"), (bottom, log_dec, "")):
        axis.axhline(0.0, color="k", linewidth=0.8, zorder=1.2)   # under the curves (undamped modes lie on it)
        axis.grid(True, alpha=0.3)
        _note_cut_off(axis, result.modes, values, unit)
    _note_far(top, result, log_dec, near, speed_unit)
    _note_on_zero(top, result, shown)
    _note_flat(bottom, result, log_dec, shown)
    top.set_xlim(x.min(), x.max() if x.max() > x.min() else x.min() + 1)
    top.set_ylabel("Real part of eigenvalue [1/s]\n(> 0: unstable)")
    bottom.set_ylabel("Log decrement [-]\n(< 0: unstable)")
    bottom.set_xlabel(speed_label(speed_unit))
    top.set_title(title or "Stability over speed")
    _panel_legends(top, bottom)
    _draw_thresholds(top, bottom, result, scale, speed_unit)
    return fig


def near_operating_range(result) -> np.ndarray:
    """(n_modes,) bool: the modes the stability figure is scaled to.

    Those whose frequency comes below :data:`_DECADE` times the sweep's highest running
    frequency (``max |speeds| / 2 pi``) at some speed, and every mode unstable somewhere (a real
    part above its round-off), where a mode far above is less damped than every mode near
    (it would set the axes); else, and where no mode is near, every mode."""
    log_dec = np.asarray(result.log_decrements, dtype=float)
    frequencies = np.where(np.isfinite(log_dec), result.frequencies_hz, np.nan)
    limit = _DECADE * np.abs(np.asarray(result.speeds, dtype=float)).max(initial=0.0) / (2 * np.pi)
    with np.errstate(invalid="ignore"):
        near = np.any(frequencies <= limit, axis=0) | np.any(result.significant_real_parts > 0, axis=0)
    lowest = np.where(np.isfinite(log_dec), log_dec, np.inf).min(axis=0)
    modes = np.isfinite(lowest)
    if not (near & modes).any() or not (~near & modes).any() or lowest[~near].min() >= lowest[near].min():
        return np.ones(len(near), dtype=bool)
    return near


def modes_that_matter(log_decrements):
    """Columns of the modes that decide stability, the least damped first.

    Those that have the smallest log decrement at some speed, then, up to :data:`_SHOWN`
    modes in all, those whose log decrement comes below :data:`_LIGHTLY_DAMPED` somewhere,
    by their smallest log decrement.

    Parameters
    ----------
    log_decrements : ndarray, shape (N, n_modes)
        NaN where a root is not a mode.

    Returns
    -------
    list of int
    """
    finite = np.isfinite(log_decrements)
    if not finite.any():
        return []
    lowest = np.where(finite, log_decrements, np.inf).min(axis=0)
    rows = finite.any(axis=1)
    least = set(np.argmin(np.where(finite, log_decrements, np.inf)[rows], axis=1).tolist())
    ranked = [int(m) for m in np.argsort(lowest, kind="stable") if np.isfinite(lowest[m])]
    light = [m for m in ranked if lowest[m] < _LIGHTLY_DAMPED and m not in least]
    chosen = set(least) | set(light[:max(_SHOWN - len(least), 0)])
    return [m for m in ranked if m in chosen]


def _by_damping(log_dec):
    """Columns of the modes (finite log decrement somewhere) by their smallest log decrement."""
    lowest = np.where(np.isfinite(log_dec), log_dec, np.inf).min(axis=0)
    return [int(m) for m in np.argsort(lowest, kind="stable") if np.isfinite(lowest[m])]


def _within(values, limits):
    """Some of ``values`` lie within ``limits``."""
    with np.errstate(invalid="ignore"):
        return bool(np.any((values >= limits[0]) & (values <= limits[1])))


def _nan(function, values):
    finite = np.asarray(values, float)[np.isfinite(values)]
    return float(function(finite)) if finite.size else np.nan


def _real_part_span(real, log_dec, relevant, significant=None):
    """(lowest, highest) real part to show [1/s]: the modes that matter, but no lower than
    :data:`_REACH` times the least-damped mode's lowest real part over the speeds; any
    positive real part (a root that diverges) always. With ``significant`` (the real parts
    with round-off set to 0, shape of ``real``), the least-damped mode is the least damped of
    those whose real part is not round-off, where some is: an undamped axial mode (real part 0)
    beside bending modes at -0.0016 to -0.5 1/s left the panel the round-off floor's height,
    +26 1/s, every damped mode flat on zero (compressor_rotor)."""
    modes = np.where(np.isfinite(log_dec), real, np.nan)
    chosen = modes[:, relevant] if relevant else real
    damped = modes if significant is None else np.where(np.asarray(significant) != 0, modes, np.nan)
    if not np.isfinite(damped).any():
        damped = modes
    least = np.array([_nan(np.max, row) for row in damped])
    # NaN where there is no mode (none below max_frequency): no warning
    lowest = _drawn_end(chosen, modes, _REACH * _nan(np.min, least), np.min)
    highest = _nan(np.max, [_nan(np.max, chosen), max(_nan(np.max, real), 0.0)])
    return lowest, highest


def _drawn_end(chosen, every, reach, end):
    """The panel's end on one side: ``end`` (np.min or np.max) of ``chosen`` (the modes that
    matter; NaN: none), no farther than ``reach`` (NaN: no bound); where some of them lie beyond
    it, the farthest value of ``every`` mode (same shape or columns of it) drawn inside ``reach``:
    the curves that leave the panel are named in its note, and the room between ``reach`` and
    the farthest curve inside was empty (unstable_cross_coupled: -3.6 1/s under curves ending
    at -2.2; compressor_rotor: -29 1/s under -9.4)."""
    whole = _nan(end, chosen)
    if not np.isfinite(reach) or not np.isfinite(whole):
        return whole
    sign = -1.0 if end is np.min else 1.0
    if sign * whole <= sign * reach:
        return whole
    every = np.asarray(every, float)
    with np.errstate(invalid="ignore"):
        inside = every[sign * every <= sign * reach]
    return _nan(end, inside) if np.isfinite(inside).any() else reach


def _log_decrement_span(log_dec, relevant, significant=None):
    """(lowest, highest) log decrement to show: the modes that matter, but no higher than
    :data:`_REACH` times the largest of the speeds' least log decrements (when it is > 0),
    and there no higher than the highest drawn inside (:func:`_drawn_end`). With
    ``significant`` (the real parts with round-off set to 0, shape of ``log_dec``), the least
    log decrements are those of the modes whose real part is not round-off, where some is: an
    undamped axial mode (log decrement 1e-31) held compressor_rotor's panel at 0-0.001, every
    bending mode (0.09-0.39) above it, the panel empty but for the zero line."""
    chosen = log_dec[:, relevant] if relevant else log_dec
    damped = log_dec if significant is None else np.where(np.asarray(significant) != 0, log_dec, np.nan)
    if not np.isfinite(damped).any():
        damped = log_dec
    least = np.array([_nan(np.min, row) for row in damped])
    reach = _REACH * _nan(np.max, least)
    return _nan(np.min, chosen), _drawn_end(chosen, log_dec, reach if reach > 0 else np.nan, np.max)


def zero_centred_limits(lowest, highest, floor, tiny=None):
    """(bottom, top) 10 % beyond ``lowest`` and ``highest`` (NaN: none), with zero inside.

    Zero keeps :data:`_ZERO_ROOM` of the height from either end; the panel is at least
    ``floor`` tall on each side of zero (an undamped machine's real parts are round-off), or,
    given ``tiny``, only where the values span less than ``tiny`` (the real parts of a machine
    with a 60 kHz shaft mode, floor 43 1/s, spanning -7 to 0 1/s, are drawn at their own scale).
    """
    below = max(-1.1 * lowest, 0.0) if np.isfinite(lowest) else 0.0
    above = max(1.1 * highest, 0.0) if np.isfinite(highest) else 0.0
    room = _ZERO_ROOM / (1 - _ZERO_ROOM)
    if tiny is not None and below + above >= tiny:
        floor = 0.0
    below, above = max(below, room * above, room * floor), max(above, room * below, floor)
    return -below, above


def _draw_modes(top, bottom, x, result, real, log_dec, relevant, others="other roots (more damped)"):
    """The coloured modes ``relevant`` (columns) in both panels, the other roots grey (legend
    entry ``others``). Each panel's legend (:func:`_panel_legends`) names the curves drawn
    inside it: a coloured mode whose values in a panel all lie beyond its axis is left out of
    that panel's legend (the panel's note of the roots beyond it names it); the top panel's
    legend listed it, marked '(bottom: above the axis)', as if the figure drew it there."""
    import matplotlib.pyplot as plt

    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for rank, m in enumerate(relevant):
        style = {"color": colours[rank % len(colours)], "linestyle": _STYLES[(rank // len(colours)) % len(_STYLES)],
                 "linewidth": 1.7}
        for axis, values in ((top, real[:, m]), (bottom, log_dec[:, m])):
            shown = _within(values, axis.get_ylim())
            axis.plot(x, values, label=f"mode {result.modes[m]}" if shown else None,
                      gid=f"mode {result.modes[m]}", **style)
    rest = [m for m in range(real.shape[1]) if m not in relevant]
    for axis, values in ((top, real), (bottom, log_dec)):
        inside = [m for m in rest if _within(values[:, m], axis.get_ylim())]
        for m in rest:
            axis.plot(x, values[:, m], label=others if inside and m == inside[0] else None,
                      color="0.72", linewidth=0.8, zorder=1.5)


def _panel_legends(top, bottom):
    """Each panel's legend beside its top right, naming the curves drawn inside it; the bottom
    panel's notes beside it (``flat-note``) moved below its legend."""
    for axis in (top, bottom):
        if axis.get_legend_handles_labels()[0]:      # none: no mode (none below max_frequency)
            axis.legend(fontsize="x-small", loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    legend = bottom.get_legend()
    if legend is None:
        return
    for note in [t for t in bottom.texts if t.get_gid() == "flat-note"]:
        text, colour = note.get_text(), note.get_color()
        note.remove()
        bottom.annotate(text, (0.0, 0.0), xycoords=legend, xytext=(0.0, -4.0), textcoords="offset points",
                        fontsize="x-small", ha="left", va="top", color=colour, gid="flat-note",
                        annotation_clip=False)


def _note_far(ax, result, log_dec, near, speed_unit):
    """Name the modes the axes are not scaled to (far above the running speed, stable:
    :func:`near_operating_range`), how far they lie, and the least damped of them with its log
    decrement, speed and frequency (beside the panel, under the legend)."""
    import textwrap

    far = ~near & np.isfinite(log_dec).any(axis=0)
    if not far.any():
        return
    limit = _DECADE * np.abs(np.asarray(result.speeds, dtype=float)).max() / (2 * np.pi)
    values = np.where(far[None, :], log_dec, np.inf)
    k, m = np.unravel_index(np.argmin(values), values.shape)
    unit = {"rpm": "rpm", "rad/s": "rad/s", "hz": "Hz"}[speed_unit]
    speed = float(result.speeds[k]) * speed_scale(speed_unit)
    note = (f"mode{'s' if far.sum() > 1 else ''} {_label_list(result.modes[far])} above {limit:,.0f} Hz "
            f"({_DECADE:g}x the top running speed): not scaled to; least damped of them: mode "
            f"{result.modes[m]}, log decrement {log_dec[k, m]:.2g} at {speed:,.0f} {unit}, "
            f"{result.frequencies_hz[k, m]:,.0f} Hz")
    ax.text(1.02, 0.64, textwrap.fill(note, 30), transform=ax.transAxes, fontsize="x-small", ha="left", va="top",
            color="0.3", gid="far-note", clip_on=False)


def _note_cut_off(ax, labels, values, unit):
    """Name the roots that leave the panel at its bottom or top, and how far they reach
    (beside the panel, under the legend: the note covers no curve)."""
    import textwrap

    low, high = ax.get_ylim()
    with np.errstate(invalid="ignore"):
        under = np.any(values < low, axis=0)
        over = np.any(values > high, axis=0)
    notes = []
    for mask, word, reach in ((under, "below", np.nanmin), (over, "above", np.nanmax)):
        if mask.any():
            names = _label_list(labels[mask])
            value = reach(values[:, mask])
            number = f"{value:,.0f}" if abs(value) >= 100 else f"{value:.3g}"
            notes.append(f"mode{'s' if mask.sum() > 1 else ''} {names} reach{'' if mask.sum() > 1 else 'es'} "
                         f"{word} the axis, to {number}{' ' + unit if unit else ''}")
    if notes:
        ax.text(1.02, 0.0, "\n".join(textwrap.fill(note, 30) for note in notes), transform=ax.transAxes,
                fontsize="x-small", ha="left", va="bottom", color="0.3", gid="cut-off-note", clip_on=False)


def _note_on_zero(ax, result, shown):
    """Name the coloured modes whose real part is zero to round-off wherever they are modes (an
    undamped machine): their curves lie on one another on the zero line, only the last drawn
    shows (beside the panel, below the legend)."""
    import textwrap

    significant = result.significant_real_parts
    modes = np.isfinite(result.log_decrements)
    flat = [m for m in shown if modes[:, m].any() and np.all(significant[modes[:, m], m] == 0)]
    if len(flat) < 2:
        return
    note = (f"modes {_label_list(sorted(result.modes[flat]))}: real part and log decrement 0 (to round-off) "
            f"at every speed, drawn on zero over one another")
    ax.text(1.02, 0.45, textwrap.fill(note, 30), transform=ax.transAxes, fontsize="x-small", ha="left", va="top",
            color="0.3", gid="zero-note", clip_on=False)


#: a coloured mode whose log decrement stays within this fraction of the panel's height of zero
#: lies on the zero line: named in a note
_ON_ZERO = 0.01


def _note_flat(ax, result, log_dec, shown):
    """Name the coloured modes whose log decrement stays so small that its curve lies on the zero
    line of the panel (``ax``) at every speed, with how small it is (but those the note of
    undamped modes names, :func:`_note_on_zero`): the
    flexible pump's 61-69 kHz shaft modes have log decrements of 1e-8 to 6e-6 beside bearing
    modes of 1e-3, and their colours were in the legend but nowhere on the figure (beside the
    panel, at its top, then moved under its legend by :func:`_panel_legends`; the note of the
    roots cut off is at its bottom)."""
    import textwrap

    low, high = ax.get_ylim()
    reach = _ON_ZERO * (high - low)
    significant = result.significant_real_parts
    modes = np.isfinite(log_dec)
    undamped = [m for m in shown if modes[:, m].any() and np.all(significant[modes[:, m], m] == 0)]
    named = undamped if len(undamped) > 1 else []           # by _note_on_zero
    flat = [m for m in shown if modes[:, m].any() and m not in named and np.nanmax(np.abs(log_dec[:, m])) < reach]
    if len(flat) < 2:                   # one curve on zero shows, drawn over the zero line
        return
    largest = max(np.nanmax(np.abs(log_dec[:, m])) for m in flat)
    names = _label_list(sorted(result.modes[flat]))
    note = (f"mode{'s' if len(flat) > 1 else ''} {names}: log decrement {largest:.1e} or less at every speed, "
            f"on the zero line")
    ax.text(1.02, 1.0, textwrap.fill(note, 30), transform=ax.transAxes, fontsize="x-small", ha="left", va="top",
            color="0.3", gid="flat-note", clip_on=False)


def _label_list(labels) -> str:
    """``[3, 4, 7, 8, 9, 10]`` -> ``'3, 4, 7-10'``: runs of three or more as ranges."""
    parts, run = [], []
    for label in [int(v) for v in labels] + [None]:
        if run and (label is None or label != run[-1] + 1):
            parts += [f"{run[0]}-{run[-1]}"] if len(run) > 2 else [str(v) for v in run]
            run = []
        if label is not None:
            run.append(label)
    return ", ".join(parts)


def _draw_thresholds(top, bottom, result, scale, speed_unit):
    """A vertical line at each threshold speed, labelled in the real-part panel where there is room:
    beside its line where no curve runs (upright, else lying; on one line, else on two or three;
    from the top down), else upright at the top."""
    from ._labels import CurveMap, laid_out_renderer

    unit = {"rpm": "rpm", "rad/s": "rad/s", "hz": "Hz"}[speed_unit]
    items = []
    at_speed = getattr(result, "threshold_modes_at_speed", None)
    at_speed = np.zeros(len(result.thresholds), dtype=int) if at_speed is None else at_speed
    for speed, mode, number, onset in zip(result.thresholds, result.threshold_modes, at_speed,
                                          result.threshold_onsets):
        colour = "tab:red" if onset else "tab:green"
        for axis in (top, bottom):
            axis.axvline(speed * scale, color=colour, linewidth=1.2, alpha=0.9, gid="threshold")
        # the legend's label is tracked over the sweep; 'modes --speed' there numbers it by frequency
        name = f"mode {mode}" if number <= 0 or number == mode else f"mode {mode} (no. {number} there)"
        items.append((speed * scale, (f"{speed * scale:,.0f} {unit}:", name,
                                      "becomes unstable" if onset else "stable again"), colour))
    if not items:
        return
    renderer = laid_out_renderer(top.figure)
    curves = CurveMap(top, renderer, units="axes")
    placed = []
    for at, parts, colour in items:
        _label_threshold(top, renderer, curves, placed, at, parts, colour)


def _label_threshold(top, renderer, curves, placed, at, parts, colour):
    """One threshold line's label (``parts``: its speed, its mode, what happens) beside the line at
    ``at`` [axis unit]: the first free place of :func:`_threshold_places`, upright, else lying, on
    one line, else two, else three; else upright at the top, on one line."""
    from ._labels import first_free_box, text_size

    frame = top.get_window_extent(renderer)
    lo, hi = top.get_xlim()
    u = (at - lo) / (hi - lo)
    pad = renderer.points_to_pixels(2.0) / frame.width
    own = (u - 2 * pad, 0.0, u + 2 * pad, 1.0)       # its own line runs beside it

    def free(box):
        return curves.free(box, own)

    first = None
    speed, mode, words = parts
    shapes = [f"{speed} {mode} {words}", f"{speed}\n{mode} {words}", f"{speed}\n{mode}\n{words}"]
    for text, upright in ((text, upright) for text in shapes for upright in (True, False)):
        w, h = text_size(top.figure, text, "x-small", renderer)
        w, h = (h / frame.width, w / frame.height) if upright else (w / frame.width, h / frame.height)
        boxes = _threshold_places(u, w, h, pad, colour == "tab:red")
        first = first or (text, boxes[:2])
        box = first_free_box(boxes, placed, frame=(0.0, 0.0, 1.0, 1.0), allowed=free)
        if box is not None:
            break
    else:                    # upright at the top, across the curves
        text, upright = first[0], True
        box = first_free_box(first[1], placed, frame=(0.0, 0.0, 1.0, 1.0))
        if box is None:
            return
    style = {"transform": top.transAxes, "fontsize": "x-small", "color": colour, "gid": "threshold-label",
             "bbox": {"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 0.5}}
    if upright:
        top.text(0.5 * (box[0] + box[2]), box[3], text, rotation=90, ha="center", va="top", **style)
    else:
        top.text(box[0], box[1], text, ha="left", va="bottom", **style)


def _threshold_places(u, w, h, pad, onset):
    """Boxes (axes fraction) ``w`` wide and ``h`` high beside a threshold line at ``u``, the
    stable side first (left of an onset, right of a return to stability), from the top down."""
    sides = [u - pad - w, u + pad] if onset else [u + pad, u - pad - w]
    return [(left, upper - h, left + w, upper) for upper in np.arange(0.98, h, -0.02) for left in sides]


def plot_stability_map(result, speed_unit: str = "rpm", quantity: str = "min_damping_ratio",
                       title: str | None = None):
    """Map over speed and one parameter, with the stability boundary drawn.

    The colours are centred on zero (white), each side scaled to its own extreme: the most
    unstable cell is the colour map's red end (``max_real_part``: blue end) however small
    beside the most stable. The legend, below the axes, names the boundary (the black line
    where the largest real part is zero), the root-found thresholds, or says that the map is
    stable everywhere.

    Parameters
    ----------
    result : StabilityMap
    speed_unit : {'rpm', 'rad/s', 'hz'}
    quantity : {'min_damping_ratio', 'max_real_part'}
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure()
    x = result.speeds * speed_scale(speed_unit)
    y = result.values
    field = result.min_damping_ratios if quantity == "min_damping_ratio" else result.max_real_parts
    mesh = ax.pcolormesh(x, y, field, cmap="RdBu" if quantity == "min_damping_ratio" else "RdBu_r",
                         norm=_zero_centred_norm(field), shading="nearest")
    fig.colorbar(mesh, ax=ax, label=quantity.replace("_", " "))
    if len(y) > 1 and len(x) > 1:
        boundary = ax.contour(x, y, result.max_real_parts, levels=[0.0], colors="k", linewidths=2.0)
        if any(len(segment) for level in boundary.allsegs for segment in level):
            ax.plot([], [], color="k", linewidth=2.0, label="stability boundary: largest real part 0")
    _mark_every_threshold(ax, result, speed_scale(speed_unit))
    if not any(r.unstable_intervals for r in result.results):
        ax.plot([], [], linestyle="none", label="stable everywhere on the map")
    ax.set_xlabel(speed_label(speed_unit))
    ylabel = result.key if result.mode_of_variation == "values" else f"scale of {result.key}"
    ax.set_ylabel(ylabel)
    ax.set_title(title or "Stability map (black line: boundary, red: unstable)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize="small", frameon=False)
    return fig


def _zero_centred_norm(field):
    """Colours centred on zero, each side reaching its own extreme of ``field`` (the other's
    when a side is empty)."""
    from matplotlib.colors import TwoSlopeNorm

    finite = field[np.isfinite(field)]
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (-1.0, 1.0)
    low, high = min(low, -high, 0.0) if low >= 0 else low, max(high, -low, 0.0) if high <= 0 else high
    if not low < 0 < high:
        low, high = -1.0, 1.0
    return TwoSlopeNorm(vcenter=0.0, vmin=low, vmax=high)


def _mark_every_threshold(ax, result, scale):
    """Each value's root-found speeds where a mode becomes unstable (filled) and where the
    machine becomes stable again (open): an island of stability shows as both."""
    points = [(speed * scale, value, onset) for value, row in zip(result.values, result.results)
              for speed, onset in zip(row.thresholds, row.threshold_onsets) if speed >= 0]
    for onset, style, label in ((True, dict(color="k"), "becomes unstable (root-found)"),
                                (False, dict(markerfacecolor="white", markeredgecolor="k"),
                                 "stable again (root-found)")):
        chosen = [(x, v) for x, v, o in points if bool(o) == onset]
        if chosen:
            xs, vs = zip(*chosen)
            ax.plot(xs, vs, "o", linestyle="none", markersize=4, label=label, gid=f"threshold-{onset}", **style)
