"""Campbell diagram figure."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._labels import (ANCHOR_POINTS, BoxRows, CurveMap, box_distance, box_distances, boxes_around_array,
                      column_positions, crossing_pairs, cuts, cuts_each, draw_time_layout, LEADER_GAP_POINTS,
                      edge_label_boxes, exits_of_orders, first_free_box, font_points, lay_out_again_when,
                      ALONG_DEGREES, nearest_each, nearest_in, operating_band, runs_along_each, segment_bounds,
                      set_if_changed, text_size,
                      _drawn_segments, _overlap, _ROW_SPLIT, _segments_crossed, _short_orders, touching_groups)
from ._style import WHIRL_STYLE, fitted_title, new_figure, speed_label, speed_scale

__all__ = ["plot_campbell", "LOG_SPAN"]

#: ``freq_scale='auto'`` draws a logarithmic frequency axis when the modes shown span more than this ratio
LOG_SPAN = 30.0
#: the axis reaches this factor beyond the highest (and, logarithmic, below the lowest) mode shown
_HEADROOM = {"linear": 1.15, "log": 1.4}
#: a logarithmic axis chosen from the modes spans at most this many decades below its top
_LOG_DECADES = 5
#: limits a user may give: the highest frequency [Hz], the decades of a logarithmic axis
MAX_FREQUENCY_HZ, MAX_LOG_DECADES = 1e12, 12
_FONT = "x-small"
#: more critical speeds than this are marked but not labelled (the table lists them)
_MAX_CRITICAL_LABELS = 200
#: leader lines of the mode labels beside the axes: horizontal stub, then slanted to the label [points]
_STUB_POINTS, _LEADER_POINTS, _PAD_POINTS = 2.0, 10.0, 2.0
_UNSTABLE = {"color": "red", "alpha": 0.35, "linewidth": 7.0, "solid_capstyle": "butt"}
#: critical speeds' labels side by side keep this far apart [points], more than a digit's width,
#: so that two numbers never read as one ('1157' beside '2313' read '11572313')
_NUMBER_GAP_POINTS = 4.0
#: a leader line crossing a curve costs as much as this many label heights farther away; a
#: label costing more than :data:`_MOST_COST` label heights (distance and crossings) is left out
_CROSSING_COST, _MOST_COST = 2.0, 12.0
#: the note of the critical speeds left unlabelled lists them by mode up to this many (else counts them)
_MAX_LISTED = 60
#: lengths of the note's lines tried [characters], longest first (fewest lines)
_NOTE_WIDTHS = (160, 110, 80, 50)
#: the speed unit as the note writes it
_UNIT_WORDS = {"rpm": "rpm", "rad/s": "rad/s", "hz": "Hz"}
#: right-edge mode labels stand at most this many label heights from their curves' ends (curves
#: whose ends crowd share a label where they would stand farther)
_MOST_SHIFT = 4.0
#: a right-edge label writing more than this many mode numbers ('modes 3, 7–9' writes three) names
#: the lowest :data:`_FIRST_NUMBERS` and the highest and counts them all (:func:`_mode_words`)
_MOST_NUMBERS, _FIRST_NUMBERS = 5, 3
#: colour of a right-edge label naming curves of different whirl (its leaders have their colours)
_SHARED_COLOUR = "0.15"
#: size of a critical speed's circle [points]; circles whose centres lie within each other's
#: circle (closer than half this) read as one double circle and share one label
_MARKER_POINTS = 6
#: a leader's end lies at least this many times as far from any other circle's centre as from its own
_NEAREST_OWN = 1.25
#: a label at the end of a leader lies :data:`_NEAREST_OWN` times as far from any other circle's
#: centre as from its own circle's, or at least this far [points] from it: a label nearer (a label
#: without a leader stands 4 points from its circle's centre) reads as that circle's speed, its
#: leader notwithstanding
_BESIDE_POINTS = 11.0
#: where no box beside a critical speed's marker has a leader crossing no mode's curve, boxes
#: across it, this much of their width left of it (:func:`._labels.boxes_around`)
_STRADDLE = (0.1, 0.3, 0.5, 0.7, 0.9)
#: boxes above or below a critical speed's circle, this much of their width left of it (beyond the
#: circle's centre either way too: a steep order line through the circle leaves one side free)
_ACROSS = (-0.2, 0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0, 1.2)
#: where no box of those has a leader crossing no mode's curve, boxes in this many columns (label
#: widths) each side of the circle (:meth:`_CampbellLabels._wider_box`); where none has either,
#: the speed goes to the note: a leader across another mode's curve reads as naming that mode
_WIDE_COLUMNS = 4
#: a leader line that runs along a mode's curve (:data:`~._labels.ALONG_REACH_POINTS` and the
#: rest: :func:`~._labels.runs_along_each`) reads as a piece of it or as a second curve beside it
#: (flexible_pump_on_mounts' '700' hung 40 points right of its circle on a leader 3.5 degrees off
#: mode 5's line and under 3 points from it). No label takes such a leader: a box with a shorter
#: or steeper one does, else the speed goes to the note. Beside an order line the same within
#: this angle [degrees] (not :data:`~._labels.ALONG_DEGREES`): an order line runs straight through every
#: critical speed's circle, steep at low speeds, where the short steep leaders go; a leader a few
#: degrees off it reads as a second order line (unstable_cross_coupled's '5.76' Hz, straight up
#: 1 to 2 points beside the 2X line), one 10 degrees off opens away from it (gear_machine's '561'
#: at 0:12000:241, straight up between two order lines, 7 points off the 1X motor line at its end)
_ALONG_ORDER_DEGREES = 6.0
#: the signs that widen a box (left, bottom, right, top) on every side
_OUTWARD = np.array([-1.0, -1.0, 1.0, 1.0])


#: a right-edge label reaching nearer the figure's edge than this [pixels] has the figure laid
#: out again (:meth:`_CampbellLabels._after_layout`)
_EDGE_PIXELS = 0.5
#: the keys above the axes keep this many points from the title beside them (:meth:`_CampbellLabels._place_keys`)
_TITLE_GAP_POINTS = 8.0
#: the critical-speed note keeps at least this many points off the axes' spines
_NOTE_MARGIN_POINTS = 4.0


def plot_campbell(result, ax=None, speed_unit: str = "rpm", color_by: str | None = None,
                  sources=None, annotate_critical: bool = True, title: str | None = None,
                  freq_range=None, freq_scale: str = "auto", operating=None):
    """Draw a Campbell diagram.

    Tracked modes are drawn solid blue where they whirl forward, dashed red
    backward and dotted grey without whirl; where a mode is unstable (real part > 0) a
    broad red band lies under its curve, with a red triangle where it becomes unstable.
    Curves that lie on each other (closer than a line width) are drawn there in turn, in short
    dashes of each one's colour, at their true values (on the figure this function makes).
    Each mode is labelled where its curve leaves the axes: beside the right edge, in the
    curves' order, joined to its curve by a leader line (curves whose ends crowd share one
    label, 'modes 11, 12', with a leader to each, where separate labels would not fit or would
    stand far from their curves); inside the axes next to the curve's
    last point when the curve leaves through the top or bottom or ends before the right edge.
    Each rotor's (and gear mesh's) excitation orders are straight lines, labelled inside the
    axes where they leave them, apart from each other, or beside the line farther down where
    the exits are crowded, or written along its line (its turned outline clear of every curve
    and label); close orders of one source share a label; lines with no room inside the axes
    get a key above the top edge joined to their exit by a leader line (with no room there
    either, the line keeps its source's colour unnamed); critical
    speeds are marked and labelled with their speed where a label finds room clear of the
    other labels, markers and curves, beside the marker or nearby with a leader line (every
    critical speed is in the result's table); circles that read as one share a label
    ('2842/2855'). Where some critical speeds inside the axes find no label, a note in a free
    place inside the axes says how many are labelled and lists the others by mode ('mode 3:
    177, 257'; the count alone, or in the legend, where the list finds no room). No curve runs through a label but at its own
    anchor (:class:`~rotordyn_modal.plotting._labels.CurveMap`). The labels are placed again
    whenever the figure is drawn, so they follow zooming and resizing.

    Parameters
    ----------
    result : CampbellResult
    ax : matplotlib Axes, optional
    speed_unit : {'rpm', 'rad/s', 'hz'}
        Unit of the speed axis and of the critical speeds' labels.
    color_by : {None, 'log_decrement', 'damping_ratio'}
        Colour the mode curves by this quantity instead of by whirl.
    sources : list of str, optional
        Excitation sources to draw (default: all).
    annotate_critical : bool
        Write the critical speeds beside their markers (up to 200 of them).
    title : str, optional
    freq_range : (float or None, float or None), optional
        Lower and upper end of the frequency axis [Hz]; None (or a missing end) chooses
        from the modes drawn. On a logarithmic axis a lower end of 0 is chosen too.
    freq_scale : {'auto', 'linear', 'log'}
        'auto': logarithmic when, at some speed, the highest mode within ``freq_range``
        is more than :data:`LOG_SPAN` times the lowest (and the range does not start at
        0), else linear.
    operating : (float, float), optional
        Operating speed range (low, high) in ``speed_unit``: a grey band under the curves with
        its legend entry (one speed: a dashed line), where separation margins are measured.

    Returns
    -------
    matplotlib.figure.Figure
    """
    freqs = np.where(result.oscillatory, result.frequencies_hz, np.nan)
    far = _far_modes(result, freqs) if freq_range is None else None
    bottom, top, axis_scale = frequency_axis(freqs if far is None else np.where(far[0], np.nan, freqs),
                                             freq_range, freq_scale)
    fig, ax = new_figure(ax)
    scale = speed_scale(speed_unit)
    x = result.speeds * scale
    curves = _Curves(result, scale, axis_scale == "log", whirl=not color_by, frequencies=freqs)
    if color_by:
        _show_coincident_coloured(fig, ax, curves, _draw_coloured(ax, fig, curves, result, color_by))
    else:
        _show_coincident(fig, ax, _draw_by_whirl(ax, curves, result))
    _mark_unstable(ax, curves, result, scale)
    lines = _order_lines(result, sources)
    _draw_orders(ax, result, scale, lines, axis_scale == "log")
    critical = _draw_critical(ax, result, scale, sources)
    ax.set_yscale(axis_scale)
    ax.set_ylim(bottom, top)
    ax.set_xlim(x.min(), x.max() if x.max() > x.min() else x.min() + 1)
    ax.set_xlabel(speed_label(speed_unit))
    ax.set_ylabel("Damped natural frequency [Hz]" + (" (log scale)" if axis_scale == "log" else ""))
    # centred over an axes that a colour bar narrows: no wider than the axes' own share
    ax.set_title(fitted_title(fig, title or "Campbell diagram", 0.65 if color_by else 0.85))
    ax.grid(True, which="major", alpha=0.3)
    if axis_scale == "log":
        ax.grid(True, which="minor", alpha=0.1)
    _draw_operating(ax, operating)
    _legend_under(fig, ax)
    slopes = result.order_slopes(scale)[_drawn_sources(result, lines)]      # [Hz per unit of the axis]
    labels = _CampbellLabels(ax, curves, freqs, result, lines, slopes, critical[:2], annotate_critical,
                             color_by is None)
    labels.critical_modes, labels.speed_unit = critical[2], _UNIT_WORDS[speed_unit]
    labels.mark_uncertain(critical[3])
    if annotate_critical and not len(result.critical) and lines \
            and not result.order_crossings[_drawn_sources(result, lines)].any():
        labels.none_note = labels._text(f"no critical speed between {_speed_text(x.min())} and "
                                        f"{_speed_text(x.max())} {_UNIT_WORDS[speed_unit]}", gid="no-critical-note",
                                        fontsize="x-small")
    if far is not None:            # the modes far above every order line: named, not scaled to
        words = f"{_numbers_text(far[1])} above {far[2]:,.0f} Hz ({_ORDER_REACH:g}x the highest order line) " \
                "not drawn: freq_range / --freq-max draws them"
        if labels.none_note is None:
            labels.none_note = labels._text(words, gid="far-modes-note", fontsize="x-small")
        else:
            labels.none_note.set_text(labels.none_note.get_text() + "\n" + words)
    ax.add_artist(draw_time_layout(labels.place))
    return fig


#: without ``freq_range`` the frequency axis is scaled to the modes below this many times the
#: highest order line's frequency at the sweep's top speed; a mode above it at every speed is
#: named in a note, not drawn (a flexible shaft's modes up to 100 kHz squeezed the mounts' and
#: the bearings' modes, 5 Hz to 1 kHz, and all 25 critical speeds into the axis' bottom tenth;
#: the stability figure scales to ten times the top speed likewise)
_ORDER_REACH = 10.0


def _far_modes(result, freqs):
    """``(far, numbers, reach)``: the modes (columns of ``freqs``, shape (n_modes,) bool) above
    ``reach`` [Hz] (:data:`_ORDER_REACH` times the highest order line at the top speed) at
    every speed, their mode numbers; None where there is none, or no mode below it."""
    slopes = np.abs(np.asarray(result.order_slopes(), float))
    if not slopes.size or not len(result.speeds):
        return None
    reach = _ORDER_REACH * float(slopes.max()) * float(np.max(np.abs(result.speeds)))
    finite = np.isfinite(freqs)
    far = finite.any(axis=0) & np.all(~finite | (freqs > reach), axis=0)
    if not reach > 0 or not far.any() or not (finite & (freqs <= reach)).any():
        return None
    return far, [m + 1 for m in np.flatnonzero(far)], reach


def _numbers_text(numbers) -> str:
    """'mode 7' or 'modes 23-68' or 'modes 19, 21, 23-30' (runs of consecutive numbers joined)."""
    runs, start = [], None
    for k, n in enumerate(numbers):
        if start is None:
            start = n
        if k + 1 == len(numbers) or numbers[k + 1] != n + 1:
            runs.append(f"{start}" if start == n else f"{start}\u2013{n}")
            start = None
    return ("mode " if len(numbers) == 1 else "modes ") + ", ".join(runs)


def frequency_axis(freqs, freq_range=None, freq_scale: str = "auto"):
    """Limits and scale of the frequency axis.

    Parameters
    ----------
    freqs : ndarray [Hz]
        The modes' frequencies (NaN where a root is not a mode).
    freq_range, freq_scale
        As for :func:`plot_campbell`.

    Returns
    -------
    (bottom, top, scale) : (float, float, {'linear', 'log'})
    """
    low, high = _checked_range(freq_range)
    if freq_scale not in ("auto", "linear", "log"):
        raise InputError(f"freq_scale {freq_scale!r}: expected 'auto', 'linear' or 'log'")
    inside = np.isfinite(freqs) & (freqs > max(low or 0.0, 0.0))
    if high is not None:
        inside &= freqs <= high
    shown = freqs[inside]
    if freq_scale == "auto":
        freq_scale = "log" if not low == 0.0 and _span(np.where(inside, freqs, np.nan)) > LOG_SPAN else "linear"
    headroom = _HEADROOM[freq_scale]
    top = high if high is not None else (headroom * shown.max() if shown.size else 1.0)
    if freq_scale == "linear":
        return (low or 0.0), top, "linear"
    if low:
        if top > low * 10.0 ** MAX_LOG_DECADES:
            raise InputError(f"freq_range {freq_range!r}: a logarithmic axis spans at most {MAX_LOG_DECADES} "
                             "decades: expected high <= low x 1e12")
        return low, top, "log"
    bottom = shown.min() / headroom if shown.size else top / 100.0
    return max(bottom, top * 10.0 ** -_LOG_DECADES), top, "log"


def _span(freqs):
    """Largest ratio of the highest to the lowest mode at one speed (1 without modes)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        ratios = np.nanmax(freqs, axis=1, initial=-np.inf, where=np.isfinite(freqs)) \
            / np.nanmin(freqs, axis=1, initial=np.inf, where=np.isfinite(freqs))
    ratios = ratios[np.isfinite(ratios)]
    return float(ratios.max()) if ratios.size else 1.0


def _checked_range(freq_range):
    if freq_range is None:
        return None, None
    try:
        low, high = freq_range
        low = None if low is None else float(low)
        high = None if high is None else float(high)
    except (TypeError, ValueError):
        raise InputError(f"freq_range {freq_range!r}: expected (low, high) in Hz") from None
    if any(v is not None and not np.isfinite(v) for v in (low, high)) or (low is not None and low < 0) \
            or (high is not None and high <= 0) or (low is not None and high is not None and not low < high) \
            or any(v is not None and v > MAX_FREQUENCY_HZ for v in (low, high)):
        raise InputError(f"freq_range {freq_range!r}: expected (low, high) in Hz with 0 <= low < high <= 1e12")
    return low, high


class _Curves:
    """The modes' curves as drawn, on one set of speeds: the sweep's with every mode's critical
    speeds among them (:meth:`~rotordyn_modal.analysis.campbell.CampbellResult.mode_curves`), so
    that each curve passes through its critical speeds' markers and curves lying on each other
    share their samples (:func:`._overlap.show_overlaps`); drawn by whirl (``whirl=True``), the
    speeds where a mode's whirl label changes too
    (:meth:`~rotordyn_modal.analysis.campbell.CampbellResult.whirl_changes`), so that a curve
    changes its style there, not over the whole step of the sweep.

    At another mode's critical speed a curve has its point on its chord as drawn (straight in
    display space: linear in frequency, or geometric on a logarithmic axis): it is drawn as
    without that point.

    Attributes
    ----------
    x : ndarray, shape (K,)
        Speeds [axis unit].
    f : ndarray, shape (K, n_modes)
        Frequencies [Hz] (NaN where no mode).
    index : ndarray of int, shape (K,)
        The sweep's speed at or before each point.
    inserted : ndarray of bool, shape (K,)
        The point is no speed of the sweep.
    speeds : ndarray, shape (K,)
        Speeds [rad/s]; ``sweep`` the sweep's, shape (N,).
    changes : list or None
        ``result.whirl_changes()`` (``whirl=True``).
    """

    def __init__(self, result, scale, log, whirl=False, frequencies=None):
        sweep = result.speeds
        if frequencies is None:
            frequencies = np.where(result.oscillatory, result.frequencies_hz, np.nan)
        curves = result.mode_curves()
        self.sweep = sweep
        self.changes = result.whirl_changes() if whirl else None
        extra = [c[0] for c in self.changes] if whirl else []
        speeds = np.union1d(sweep, np.concatenate([c[0] for c in curves] + extra + [sweep]))
        self.speeds = speeds
        self.index = np.searchsorted(sweep, speeds, side="right") - 1
        self.inserted = speeds != sweep[self.index]
        self.x = speeds * scale
        self.f = frequencies[self.index]
        if self.inserted.any():
            k = self.index[self.inserted]
            after = np.minimum(k + 1, len(sweep) - 1)
            t = ((speeds[self.inserted] - sweep[k]) / (sweep[after] - sweep[k]))[:, None]
            low, high = frequencies[k], frequencies[after]
            with np.errstate(all="ignore"):
                self.f[self.inserted] = low * (high / low) ** t if log else low + t * (high - low)
            for m, (at, values, index) in enumerate(curves):
                own = at != sweep[index]
                self.f[np.searchsorted(speeds, at[own]), m] = values[own]

    def mask(self, mask):
        """``mask`` (shape (N,), over the sweep's speeds) on the points: an inserted point where
        both its neighbours of the sweep are (the segment it splits is drawn)."""
        after = mask[np.minimum(self.index + 1, len(mask) - 1)]
        return np.where(self.inserted, mask[self.index] & after, mask[self.index])

    def segment_whirl(self, whirl, m):
        """The whirl label of each segment between the points of mode ``m`` (shape (K - 1,)):
        :func:`segment_whirl` with ``result.whirl_changes()`` (made with ``whirl=True``)."""
        return segment_whirl(np.asarray(whirl)[:, m], self.sweep, self.speeds, self.index, self.changes[m])

    def segment_values(self, values):
        """Each segment between the points: the mean of ``values`` (shape (N,)) at the ends of the
        sweep's segment it lies on."""
        k = np.minimum(self.index[:-1], len(values) - 2)
        return 0.5 * (values[k] + values[k + 1])


def segment_whirl(whirl, sweep, speeds, index, changes):
    """The whirl label of each segment between a mode's drawn points, shape (K - 1,): that of the
    sweep's speed at its start, changed from each speed of ``changes`` on (the mode's
    :meth:`~rotordyn_modal.analysis.campbell.CampbellResult.whirl_changes`, which are points).

    Parameters
    ----------
    whirl : array_like of str, shape (N,)
        The mode's label at each speed of the sweep.
    sweep : ndarray, shape (N,)
        The sweep's speeds [rad/s], increasing.
    speeds : ndarray, shape (K,)
        The points drawn [rad/s], increasing, every change's speed among them.
    index : ndarray of int, shape (K,)
        The sweep's speed at or before each point.
    changes : (ndarray, ndarray)
        Speeds [rad/s] and the labels from them on.
    """
    k = index[:-1]
    labels = np.asarray(whirl)[k].astype(object)
    middle = 0.5 * (speeds[:-1] + speeds[1:])
    for at, name in zip(*changes):
        step = np.searchsorted(sweep, at, side="right") - 1
        labels[(middle > at) & (k == step)] = name
    return labels


def segment_ends(segments):
    """The points at either end of the segments ``segments`` (shape (K - 1,) bool) picks, shape
    (K,): a whirl's line is drawn over those segments and meets the next one's at a change."""
    at = np.zeros(len(segments) + 1, dtype=bool)
    at[:-1] |= segments
    at[1:] |= segments
    return at


def _draw_by_whirl(ax, curves, result):
    """Each mode's curve, one line per whirl direction (NaN elsewhere); returns the lines in
    drawing order."""
    from ..analysis._whirl import WHIRL_TOLERANCE

    drawn, lines = set(), []
    for m in range(len(result.modes)):
        segments = curves.segment_whirl(result.whirl, m)
        for whirl, style in WHIRL_STYLE.items():
            mask = segment_ends(segments == whirl)
            if not mask.any():
                continue
            kwargs = dict(style)
            if whirl in drawn:
                kwargs.pop("label")
            elif whirl == "none":     # the label is a threshold on a continuous ratio: say which
                kwargs["label"] = f"no whirl (|whirl ratio| \u2264 {WHIRL_TOLERANCE:g}" \
                    + (" or within its round-off)" if result.whirl_none_by_round_off else ")")
            drawn.add(whirl)
            lines += ax.plot(curves.x, np.where(mask, curves.f[:, m], np.nan), linewidth=1.6, **kwargs)
    return lines


def _show_coincident(fig, ax, curves):
    """Mode curves that lie on each other (an isotropic rotor's forward and backward modes at
    low speed) drawn there in turn, dashes of each in its own colour
    (:func:`._overlap.show_overlaps`), on the layout of the figure's first drawing: every curve
    shows, at its true values. Only on a figure with constrained layout (the one
    :func:`plot_campbell` makes); curves apart are drawn as before."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    from ._overlap import at_first_layout, show_overlaps

    if isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine) and len(curves) > 1:
        at_first_layout(fig, lambda: bool(show_overlaps(ax, curves)) and False)


def _with_neighbours(mask):
    """Extend a mask by one point each way so that segments join up."""
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    return out


def _draw_coloured(ax, fig, curves, result, quantity):
    """Each mode's curve coloured by ``quantity`` along it; returns the collections (one
    LineCollection per mode)."""
    from matplotlib.collections import LineCollection

    # an undamped mode's log decrement is round-off (+-2e-15 on the spring-block rotor): 0, as the
    # red band reads it (:func:`_mark_unstable`); its noise spread over the whole colour map read
    # as damping varying along the curves, half of it below zero
    values = result.settled(quantity)
    finite = values[np.isfinite(values) & result.oscillatory]
    norm_range = (finite.min(), finite.max()) if finite.size else (0, 1)
    if norm_range[1] <= norm_range[0]:                  # one value (0: an undamped machine)
        norm_range = (norm_range[0], norm_range[0] + max(abs(norm_range[0]), 0.1))
    import matplotlib.colors as mcolors

    norm = mcolors.Normalize(*norm_range)
    collections = []
    for m in range(len(result.modes)):
        points = np.stack([curves.x, curves.f[:, m]], axis=1)
        segments = np.stack([points[:-1], points[1:]], axis=1)
        lines = LineCollection(segments, cmap="viridis", norm=norm, linewidth=2.0)
        lines.set_array(curves.segment_values(values[:, m]))
        ax.add_collection(lines)
        collections.append(lines)
    fig.colorbar(lines, ax=ax, label=quantity.replace("_", " ") + " (red band: unstable)")
    return collections


def _show_coincident_coloured(fig, ax, curves, collections):
    """Coloured mode curves that lie on each other drawn there in turn (as
    :func:`_show_coincident`), each dash in its curve's colour at that speed: the stretches are
    found on an invisible stand-in line of each curve, and each dashed stretch drawn is redrawn
    as segments coloured as the curve's, the dashes' phase carried from segment to segment."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    from ._overlap import at_first_layout, show_overlaps

    if not isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine) or len(collections) < 2:
        return
    width = collections[0].get_linewidth()[0]
    stand_ins, lines = {}, []
    for m, collection in enumerate(collections):
        lines += ax.plot(curves.x, curves.f[:, m], color=f"#{m + 1:06x}", linewidth=width, visible=False, label="_nolegend_")
        stand_ins[lines[-1].get_color()] = collection

    def show():
        before = set(ax.get_lines())
        show_overlaps(ax, lines)
        for dashed in [line for line in ax.get_lines() if line not in before]:
            _recolour(ax, dashed, stand_ins[dashed.get_color()])
        return False

    at_first_layout(fig, show)


def _recolour(ax, dashed, collection):
    """Replace the dashed single-colour line ``dashed`` (a stretch of ``collection``'s curve) by
    its segments in the collection's colours, each segment's dashes starting where the previous
    one's ended (the dash pattern of one line along the stretch)."""
    from matplotlib.collections import LineCollection

    from ._overlap import dash_pattern

    offset, (on, off) = dash_pattern(dashed)       # as set: in line widths
    width = dashed.get_linewidth()
    points = np.column_stack([dashed.get_xdata(), dashed.get_ydata()]).astype(float)
    shown = dashed.get_transform().transform(points) / (ax.figure.dpi / 72.0)        # [points]
    along = np.concatenate([[0.0], np.cumsum(np.nan_to_num(np.hypot(*np.diff(shown, axis=0).T)))])
    colours = collection.get_colors() if len(collection.get_array()) == 0 else \
        collection.to_rgba(collection.get_array())
    first = _first_segment(collection, points[0])
    segments = np.stack([points[:-1], points[1:]], axis=1)
    pieces = LineCollection(segments, colors=colours[first:first + len(segments)], linewidth=width,
                            linestyles=[(offset + a / width, (on, off)) for a in along[:-1]],
                            zorder=dashed.get_zorder())
    ax.add_collection(pieces, autolim=False)
    dashed.remove()


def _first_segment(collection, point):
    """Index of the segment of ``collection`` starting at ``point`` (data); a segment not drawn
    (a mode above ``max_frequency`` there: NaN ends, an empty segment) starts nowhere."""
    starts = np.array([s[0] if len(s) else (np.nan, np.nan) for s in collection.get_segments()], float)
    return int(np.argmin(np.nan_to_num(np.hypot(*(starts - point).T), nan=np.inf)))


def _mark_unstable(ax, curves, result, scale):
    """A broad red band under each mode where it is unstable
    (:attr:`~rotordyn_modal.analysis.campbell.CampbellResult.unstable`); a triangle at each onset
    (:meth:`~rotordyn_modal.analysis.campbell.CampbellResult.instability_onsets`)."""
    unstable = result.unstable
    if not unstable.any():
        return
    band_label, onset_label = "unstable (real part > 0)", "becomes unstable"
    onsets = result.instability_onsets()
    for m in np.nonzero(unstable.any(axis=0))[0]:
        ax.plot(curves.x, np.where(curves.mask(_with_neighbours(unstable[:, m])), curves.f[:, m], np.nan),
                label=band_label, zorder=1.5,
                **_UNSTABLE)
        band_label = None
        speeds, frequencies = onsets[m]
        if speeds.size:
            ax.plot(speeds * scale, frequencies, "^", color="red",
                    markersize=8, markeredgecolor="k", label=onset_label, zorder=3.5)
            onset_label = None


_ORDER_COLORS = ["0.2", "tab:green", "tab:purple", "tab:brown", "tab:olive", "tab:cyan"]


def _order_lines(result, sources):
    """(name, multiplier, colour) of each excitation source drawn."""
    return [(name, multiplier, _ORDER_COLORS[i % len(_ORDER_COLORS)])
            for i, (name, multiplier) in enumerate(zip(result.sources.names, result.sources.multipliers))
            if sources is None or name in sources]


def _drawn_sources(result, lines):
    """Indices into ``result.sources`` of the sources of ``lines`` (:func:`_order_lines`)."""
    drawn = {name for name, _, _ in lines}
    return [s for s, name in enumerate(result.sources.names) if name in drawn]


def _draw_orders(ax, result, scale, lines, dense):
    """Straight order lines (:meth:`~rotordyn_modal.analysis.campbell.CampbellResult.order_frequencies`;
    labelled by :class:`_CampbellLabels` when the figure is drawn), through the sweep's speeds;
    with ``dense`` (a logarithmic frequency axis) and 1025 more
    across its range: there a line through the sweep's points alone is a polygon of chords (drawn straight in
    display space), up to tens of pixels off the true line and the critical speeds on it, and
    it starts at the first speed above zero."""
    speeds = np.union1d(result.speeds, np.linspace(result.speeds.min(), result.speeds.max(), 1025)) \
        if dense else result.speeds
    frequencies = result.order_frequencies(speeds)
    for (_, _, color), s in zip(lines, _drawn_sources(result, lines)):
        for o in range(len(result.orders)):
            ax.plot(speeds * scale, frequencies[s, o], color=color, linewidth=0.9, alpha=0.8, gid="order-line")


def _draw_critical(ax, result, scale, sources):
    """Markers of the critical speeds drawn; returns their (speeds in the axis' unit, Hz, modes,
    uncertain), ``uncertain`` True where a row is a jump of its tracked mode, not a crossing.

    A jump (:attr:`~rotordyn_modal.analysis.campbell.CampbellResult.critical_jumps`, warned of by
    the analysis) has a frequency on no curve of the figure: it is drawn as a grey diamond on its order line at
    its speed (where the crossing it stands for lies), with its own legend entry."""
    critical = result.critical
    if not len(critical):
        return np.empty(0), np.empty(0), np.empty(0), np.zeros(0, bool)
    keep = np.array([sources is None or s in sources for s in critical.source], dtype=bool)
    uncertain = result.critical_jumps[keep]
    on_line = result.critical_line_frequencies
    speeds, freqs = critical.speeds[keep] * scale, np.where(uncertain, on_line[keep], critical.frequencies_hz[keep])
    first = _distinct_points(speeds, freqs)
    speeds, freqs, uncertain = speeds[first], freqs[first], uncertain[first]
    # clipped to the axes with a margin of a circle's radius: a circle on the edge (a critical speed at
    # the sweep's last speed) is drawn whole
    ax.plot(speeds[~uncertain], freqs[~uncertain], "o", markersize=_MARKER_POINTS, markerfacecolor="none",
            markeredgecolor="k", label="critical speed", zorder=3)[0].set_clip_box(_padded_axes(ax))
    if uncertain.any():
        ax.plot(speeds[uncertain], freqs[uncertain], "D", markersize=0.8 * _MARKER_POINTS, markerfacecolor="none",
                markeredgecolor="0.4", zorder=3, gid="critical-uncertain",
                label="critical speed? (mode jumped)")
    return speeds, freqs, np.asarray(critical.mode)[keep][first], uncertain


def _distinct_points(speeds, freqs):
    """Indices of the points ``(speed, frequency)`` once each (to 1e-9 of the largest), in their
    order: where the coinciding order lines of two sources cross a mode there is one circle and
    one label."""
    if not len(speeds):
        return np.arange(0)
    points = np.column_stack([speeds, freqs])
    size = np.where(np.abs(points).max(axis=0) > 0, np.abs(points).max(axis=0), 1.0)
    _, first = np.unique(np.round(points / size, 9), axis=0, return_index=True)
    return np.sort(first)


def _speed_text(value: float) -> str:
    """A critical speed's label: whole units from 100 on, three digits below."""
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


def _draw_operating(ax, operating):
    """The operating speed range (low, high) [speed axis units] under the curves: a grey band,
    or a dashed line for one speed, with its legend entry (None: nothing)."""
    if operating is None:
        return
    low, high = sorted(float(v) for v in operating)
    operating_band(ax, low, high, "operating range" if high > low else "operating speed", edge=False,
                   gid="operating-range")


def _legend_under(fig, ax, critical_words=None):
    """The legend under ``ax``, in as few rows as keep it no wider than the axes.

    The axes' width is the one the figure's layout engine (constrained layout) gives it
    without the legend; one row when that fits, else the fewest rows that do (columns of
    equal height: 2 x 2 for four entries), else one column. So panels side by side keep
    their width and each legend stays under its own axes. Chosen when drawn first, and again
    where the critical speeds' entry takes the note's count (``critical_words``, its words:
    :meth:`_CampbellLabels._after_layout`); a resized figure keeps the columns.
    """
    kwargs = dict(loc="upper center", bbox_to_anchor=(0.5, -0.11), fontsize="small", frameon=False)
    count = len(ax.get_legend_handles_labels()[1])

    def made(columns):
        legend = ax.legend(ncols=columns, **kwargs)
        entry = _critical_entry(ax)
        if critical_words is not None and entry is not None:
            entry.set_text(critical_words)
        return legend

    legend = made(max(count, 1))
    if count < 2:
        return legend
    renderer = fig.canvas.get_renderer() if hasattr(fig.canvas, "get_renderer") else fig._get_renderer()
    width = _width_without(legend, renderer)
    for rows in range(1, count + 1):
        columns = -(-count // rows)
        if rows > 1 and columns == -(-count // (rows - 1)):
            continue                                           # the same columns as one row fewer
        legend = made(columns)
        if columns == 1 or legend.get_window_extent(renderer).width <= width:
            return legend
    return legend


def _critical_entry(ax):
    """The text of the critical speeds' entry in ``ax``'s legend ('critical speed', or with the
    note's count), or None."""
    legend = ax.get_legend()
    return next((t for t in (legend.get_texts() if legend else []) if t.get_text().startswith("critical speed")),
                None)


def _width_without(legend, renderer):
    """Width [px] of ``legend``'s axes as the figure's layout engine lays it out without the
    legend (the axes' own width when the figure has no engine). The axes of the figure are
    put back where they were, and a subclass's first-layout work waits for the first draw,
    so that the figure's first draw lays it out as before."""
    root = legend.axes.figure.get_figure(root=True)
    engine = root.get_layout_engine()
    if engine is None:
        return legend.axes.get_window_extent(renderer).width
    axes, figures = [], [root]
    while figures:
        figure = figures.pop()
        axes += figure.axes
        figures += figure.subfigs
    kept = [(a, a.get_position(original=True), a.get_position()) for a in axes]
    legend.set_in_layout(False)
    # matplotlib's own layout, not a subclass's first-layout work (_overlap.at_first_layout)
    plain = next(cls for cls in type(engine).__mro__ if cls.__module__.startswith("matplotlib."))
    plain.execute(engine, root)
    width = legend.axes.get_window_extent(renderer).width
    for a, original, active in kept:
        a._set_position(original, which="original")
        a._set_position(active, which="active")
    return width


class _CampbellLabels:
    """The Campbell diagram's labels (order lines, modes, critical speeds), placed at draw time.

    Every label is made once (so that ``ax.texts`` holds them); :meth:`place` moves, fills
    and shows or hides them for the axes' current limits and size.
    """

    def __init__(self, ax, curves, freqs, result, lines, slopes, critical, annotate, by_whirl):
        self.ax, self.curves_drawn, self.freqs, self.result = ax, curves, freqs, result
        self.lines, self.slopes, self.by_whirl = lines, slopes, by_whirl
        self.critical = critical
        self.order_texts = [self._text("") for _ in range(len(lines) * len(result.orders))]
        # keys above the top edge of the lines that find no room inside the axes (outside the layout)
        self.key_texts = [self._text("", gid="order-key", clip_on=False) for _ in self.order_texts]
        self.key_leaders = [ax.plot([], [], linewidth=0.6, transform=ax.transAxes, clip_on=False, visible=False,
                                    gid="order-key-leader")[0] for _ in self.order_texts]
        for artist in self.key_texts + self.key_leaders:
            artist.set_in_layout(False)
        self.modes = [m for m in range(freqs.shape[1]) if np.isfinite(freqs[:, m]).any()]
        # beside the right edge from the start, so that the layout leaves them room
        self.mode_texts = [self._text(f"mode {result.modes[m]}", gid="mode-label", va="center", visible=True,
                                      x=1.02, clip_on=False) for m in self.modes]
        self.leaders = [ax.plot([], [], linewidth=0.6, transform=ax.transAxes, clip_on=False,
                                gid=f"mode-leader {result.modes[m]}")[0] for m in self.modes]
        self._reserve_shared_words()
        # the right-edge labels as drawn, for the axes as laid out, before each drawing's layout
        # is final: shared as the first guess above could not know (the 20-rotor chain's
        # 'modes 15, 40, 85, 86' ran off the figure), where the layout leaves them room
        lay_out_again_when(ax.figure, self._after_layout)
        self.critical_words = [_speed_text(s) for s in critical[0]]
        self.critical_texts = [self._text(w, gid="critical-label", fontsize="xx-small")
                               for w in self.critical_words] if annotate and len(critical[0]) <= _MAX_CRITICAL_LABELS else []
        self.critical_leaders = [ax.plot([], [], linewidth=0.5, color="k", transform=ax.transAxes, visible=False,
                                         gid="critical-leader")[0] for _ in self.critical_texts]
        self.critical_modes, self.speed_unit = np.zeros(len(critical[0]), int), "rpm"
        # the note of the critical speeds left unlabelled (shown only when some are)
        self.critical_note = self._text("", gid="critical-note", fontsize="xx-small") \
            if annotate and len(critical[0]) else None
        self.none_note = None           # the note of a sweep with no critical speed (see plot_campbell)
        self.placed_for = None          # the state the labels were last placed for (:meth:`_drawn_state`)
        self.shared, self.note_modes = [], set()    # shared right-edge labels and their modes; modes the note lists
        self.legend_words = "critical speed"     # the legend entry's words its columns were chosen for
        self._own_lines = set(self.leaders + self.critical_leaders + self.key_leaders)

    def mark_uncertain(self, uncertain):
        """Suffix '?' to the words of the critical speeds that are jumps, not crossings."""
        for k in np.flatnonzero(uncertain):
            self.critical_words[k] += "?"
            if k < len(self.critical_texts):
                self.critical_texts[k].set_text(self.critical_words[k])

    def _reserve_shared_words(self):
        """The right-edge labels' words as :meth:`_beside` would share them at the axes' size
        before the layout: the constrained layout of the first drawing leaves room beside the
        axes for the widest label ('modes 21, 22' is wider than any 'mode 66')."""
        ax, fig = self.ax, self.ax.figure
        self.to_axes = (ax.transData + ax.transAxes.inverted()).transform
        ends = [self._visible_end(m) for m in self.modes]
        beside = [i for i, end in enumerate(ends) if end is not None and end[0] == "right"]
        if len(beside) < 2:
            return
        to_v = 1.0 / max(ax.get_position().height * fig.bbox.height, 1.0)
        renderer = fig.canvas.get_renderer() if hasattr(fig.canvas, "get_renderer") else None
        height = text_size(fig, "mode 1", _FONT, renderer)[1] if renderer is not None \
            else 1.4 * font_points(_FONT) * fig.dpi / 72.0
        groups, _ = _grouped_beside([ends[i][1] for i in beside], height * to_v, fig.dpi / 72.0 * to_v)
        for group in groups:
            if len(group) > 1:
                self.mode_texts[beside[group[0]]].set_text(
                    _mode_words([self.result.modes[self.modes[beside[g]]] for g in group]))

    def _after_layout(self, renderer):
        """Place every label (:meth:`place`) for the axes as the figure's layout left them;
        whether the figure is to be laid out again (:func:`._labels.lay_out_again_when`): a
        right-edge label now reaches farther right than before [pixels] and beyond the figure's
        edge, or the legend's entry of the critical speeds now carries the note's count
        (:meth:`_place_note`), longer than the words its columns were chosen for (chosen again
        for them, :func:`_legend_under`). The drawing that follows a layout left as it was finds
        the labels placed. The 60-rotor gear chain at 110 dpi wrote the count into the legend
        after the layout, and its first entry began 208 pixels left of the figure."""
        if self._drawn_state(renderer) == self.placed_for:     # placed so at the last drawing
            return False
        fig = self.ax.figure
        reach = max(self._reach(renderer), fig.bbox.x1 - _EDGE_PIXELS)
        self._set_scales(renderer)
        self.placed_for = None
        ends = self._reset_mode_texts()
        for i, end in enumerate(ends):      # (curves ending inside the axes: labelled there, by place)
            if end is not None and end[0] == "inside":
                self._set(self.mode_texts[i], visible=False)
        self._beside(renderer, [i for i, end in enumerate(ends) if end is not None and end[0] == "right"], ends)
        if self._reach(renderer) > reach:       # the right-edge labels alone ask for room: the rest waits
            return True
        self.place(renderer)
        again = self._reach(renderer) > reach
        entry = _critical_entry(self.ax)
        if entry is not None and len(entry.get_text()) > len(self.legend_words):
            self.legend_words = entry.get_text()
            _legend_under(fig, self.ax, self.legend_words)
            again = True
        return again

    def _reach(self, renderer):
        """The right end [pixels] of the visible mode labels (-inf: none)."""
        return max((t.get_window_extent(renderer).x1 for t in self.mode_texts if t.get_visible() and t.get_text()),
                   default=-np.inf)

    def _set_scales(self, renderer):
        """The axes' scales as drawn now: axes fraction per pixel, pixels per point, data to axes."""
        box = self.ax.get_window_extent(renderer)
        self.to_u, self.to_v = 1.0 / max(box.width, 1.0), 1.0 / max(box.height, 1.0)
        self.points = renderer.points_to_pixels(1.0)
        self.to_axes = (self.ax.transData + self.ax.transAxes.inverted()).transform
        self.critical_groups = None         # (:meth:`_critical_groups`, for these scales)

    def _text(self, text, gid=None, va="bottom", fontsize=_FONT, visible=False, x=0.5, clip_on=True):
        return self.ax.text(x, 0.5, text, transform=self.ax.transAxes, fontsize=fontsize, ha="left", va=va,
                            gid=gid, visible=visible, clip_on=clip_on)

    def _size(self, text, fontsize, renderer):
        """(width, height) [pixels] of a label, measured once per text, size and resolution."""
        key = (text, fontsize, renderer.points_to_pixels(1.0))
        sizes = self.__dict__.setdefault("sizes", {})
        if key not in sizes:
            sizes[key] = text_size(self.ax.figure, text, fontsize, renderer)
        return sizes[key]

    def place(self, renderer):
        """Place every label for the axes as they are now (called when the axes are drawn)."""
        ax = self.ax
        state = self._drawn_state(renderer)
        if state == self.placed_for:      # placed for this very state at the last drawing
            return
        self._set_scales(renderer)
        self.curves = CurveMap(ax, renderer, skip=self.leaders + self.critical_leaders + self.key_leaders,
                               units="axes")
        self.renderer, self.mode_map, self.order_map = renderer, None, None
        self.recorded = []          # the first run's settings, in order (:meth:`_set`)
        placed = self._place_all(renderer)
        first, self.recorded = (self.recorded, self.leader_lines, self.drawn_leaders, self.shared, placed), None
        unlabelled = self._unlabelled_critical() if self.critical_texts else []
        if self._orders_near(unlabelled, renderer):
            # an order line's label took the only room beside a critical speed's circle
            # (compressor_rotor's '1X compressor' over 14388 rpm, 0:15000:151): the order labels
            # once more, kept off the room straight above such circles (else below), where their
            # labels would stand; kept where that labels more critical speeds and leaves no order
            # line unnamed, else all as they were
            shown, tried = self._orders_shown(), False
            for side in (1, -1):
                reserved = self._reserved_at(unlabelled, side, renderer)
                if not reserved:
                    continue
                placed, tried = self._place_all(renderer, reserved), True
                if len(self._unlabelled_critical()) < len(unlabelled) and self._orders_shown() >= shown:
                    break
            else:
                if tried:
                    placed = self._replayed(*first)
        self._place_note(renderer, placed, self._marker_boxes())
        self._name_mentioned()
        self._place_none_note(renderer, placed, self._marker_boxes())
        self.placed_for = state

    def _place_all(self, renderer, reserved=()):
        """The mode, order-line and critical-speed labels (not the notes); the order lines'
        labels (and keys) kept clear of the boxes ``reserved`` (axes fraction). Returns the
        boxes taken (axes fraction)."""
        self.leader_lines = []          # (start, end) of the leader lines drawn inside the axes
        self.drawn_leaders = []         # (start, end) of those as drawn (short of their circles)
        placed = list(reserved)
        # the right-edge labels first: the order lines' keys above the axes keep clear of them
        ends = self._reset_mode_texts()
        inside = [i for i, end in enumerate(ends) if end is not None and end[0] == "inside"]
        for i in inside:
            self._set(self.mode_texts[i], visible=False)
        self._beside(renderer, [i for i, end in enumerate(ends) if end is not None and end[0] == "right"], ends)
        self._place_orders(renderer, placed, smaller=bool(reserved))
        del placed[:len(reserved)]
        markers = self._marker_boxes()
        self._inside(renderer, inside, ends, placed, markers)
        self._place_critical(renderer, placed, markers)
        return placed

    def _set(self, artist, **properties):
        """:func:`~._labels.set_if_changed`, the call kept while :attr:`recorded` is a list."""
        if self.__dict__.get("recorded") is not None:
            self.recorded.append((artist, properties))
        set_if_changed(artist, **properties)

    def _replayed(self, recorded, leader_lines, drawn_leaders, shared, placed):
        """The labels as a first :meth:`_place_all` (no box reserved) left them, its settings
        ``recorded`` made again in their order, and the boxes it took (``placed``): that run
        again would make the same settings, since it depends on nothing a run sets but what it
        sets itself first; the artists it does not set keep what the last run left them, as
        they would. (compressor_rotor's retry ran :meth:`_place_all` a third time for this.)"""
        for artist, properties in recorded:
            set_if_changed(artist, **properties)
        self.leader_lines, self.drawn_leaders, self.shared = leader_lines, drawn_leaders, shared
        return placed

    def _orders_shown(self):
        """How many order lines' labels and keys are shown."""
        return sum(t.get_visible() for t in self.order_texts + self.key_texts)

    def _orders_near(self, unlabelled, renderer):
        """Whether a shown order line's label stands in the room around the circle of one of the
        ``unlabelled`` critical speeds: its square widened by its label's size and gap on every
        side, where the label's first places are (:meth:`_place_critical`)."""
        if not unlabelled:
            return False
        frame = self.ax.get_window_extent(renderer)
        orders = [t.get_window_extent(renderer) for t in self.order_texts if t.get_visible()]
        orders = [((b.x0 - frame.x0) * self.to_u, (b.y0 - frame.y0) * self.to_v,
                   (b.x1 - frame.x0) * self.to_u, (b.y1 - frame.y0) * self.to_v) for b in orders]
        radius_u, radius_v = 4 * self.points * self.to_u, 4 * self.points * self.to_v
        for k in unlabelled:
            u, v = self.to_axes((self.critical[0][k], self.critical[1][k]))
            w, h = self._size(self.critical_words[k], "xx-small", renderer)
            reach_u = radius_u + (w + _NUMBER_GAP_POINTS * self.points) * self.to_u
            reach_v = radius_v + (h + self.points) * self.to_v
            if any(_overlap((u - reach_u, v - reach_v, u + reach_u, v + reach_v), o, 0.0, 0.0) for o in orders):
                return True
        return False

    def _reserved_at(self, unlabelled, side, renderer):
        """Boxes (axes fraction) the labels of the ``unlabelled`` critical speeds would take
        straight above their circles (``side`` 1) or below them (-1), as :meth:`_place_critical`
        tries them; only those inside the axes, off every other circle, that no curve crosses
        (but near the circle): the places an order label alone can have taken."""
        radius_u, radius_v = 4 * self.points * self.to_u, 4 * self.points * self.to_v
        margin_u, margin_v = self.points * self.to_u, self.points * self.to_v
        markers = self._marker_boxes()
        boxes = []
        for k in unlabelled:
            u, v = self.to_axes((self.critical[0][k], self.critical[1][k]))
            w, h = self._size(self.critical_words[k], "xx-small", renderer)
            w, h = w * self.to_u, h * self.to_v
            bottom = v + radius_v if side > 0 else v - radius_v - h
            box = (u - w / 2, bottom, u + w / 2, bottom + h)
            own = (u - radius_u, v - radius_v, u + radius_u, v + radius_v)
            keep = (u - ANCHOR_POINTS * self.points * self.to_u, v - ANCHOR_POINTS * self.points * self.to_v,
                    u + ANCHOR_POINTS * self.points * self.to_u, v + ANCHOR_POINTS * self.points * self.to_v)
            if margin_u <= box[0] and box[2] <= 1 - margin_u and margin_v <= box[1] and box[3] <= 1 - margin_v \
                    and self.curves.free(box, keep) \
                    and not any(_overlap(box, m, 0.0, 0.0) for m in markers if not np.allclose(m, own)):
                boxes.append(box)
        return boxes

    def _drawn_state(self, renderer):
        """What the labels' places depend on beyond the labels themselves: the resolution, the
        figure's and the axes' size and place, the limits and scales, the artists drawn and the
        title. A drawing in the same state places every label as the last one did (a report's
        figure is drawn three times: laid out, then saved), so :meth:`place` leaves them."""
        ax = self.ax
        return (renderer.points_to_pixels(1.0), tuple(ax.figure.bbox.bounds),
                tuple(ax.get_window_extent(renderer).bounds), tuple(ax.get_xlim()), tuple(ax.get_ylim()),
                ax.get_xscale(), ax.get_yscale(), len(ax.lines), len(ax.collections), len(ax.texts),
                len(ax.patches), ax.title.get_text(),
                tuple(a.get_visible() for a in ax.lines + ax.collections if a not in self._own_lines))

    # -- order lines ---------------------------------------------------------------------
    def _place_orders(self, renderer, placed, smaller=False):
        ax = self.ax
        bottom, top = ax.get_ylim()
        exits = exits_of_orders(self.result.orders, self.lines, self.slopes, ax.get_xlim(), top, bottom,
                                lambda x, f: tuple(self.to_axes((x, f))),
                                lambda x, f: self.to_axes(np.column_stack([x, f])))
        taken = edge_label_boxes(ax, exits, _FONT, renderer, placed, self.curves, along=True, smaller=smaller)
        for text, item in zip(self.order_texts, taken + [None] * (len(self.order_texts) - len(taken))):
            if item is None:
                self._set(text, visible=False)
                continue
            label, (left, low, _, _) = item
            self._set(text, text=label.text, color=label.color, position=(left, low), rotation=label.angle,
                           fontsize=label.fontsize or font_points(_FONT), visible=True)
        self._place_keys(renderer, _unnamed(exits, [label for label, _ in taken]))

    def _place_keys(self, renderer, unnamed):
        """Keys of the top-edge lines ``unnamed`` inside the axes (lists of one source's
        neighbouring :class:`EdgeLabel` s): flat, in a row just above the axes' top edge, each
        as near above its lines' exits as the other keys, the title, the tick labels and the
        figure's edge let it be, joined to the exit of its line nearest it by a leader line;
        a key with no such room is left out."""
        ax, fig = self.ax, self.ax.figure
        frame = ax.get_window_extent(renderer)
        gap = _PAD_POINTS * self.points
        titles = [ax.title, ax._left_title, ax._right_title]
        obstacles = [(artist.get_window_extent(renderer), artist in titles) for artist in
                     titles + ax.get_xticklabels() + ax.get_yticklabels()
                     + [t for t in self.mode_texts if t.get_visible()]
                     if artist.get_visible() and artist.get_text()]
        # a title keeps a word's space from the keys beside it (2 points read as one line of text)
        wider = (_TITLE_GAP_POINTS - _PAD_POINTS) * self.points
        obstacles = [(b.x0 - wider * title, b.y0, b.x1 + wider * title, b.y1) for b, title in obstacles]
        bottom = frame.y1 + 2 * gap
        shown, keyed = 0, []            # keys shown; their leaders' start, end, box and colour
        right_of = max(frame.x0, fig.bbox.x0 + gap)
        for members in sorted(unnamed, key=lambda group: group[0].u):
            text = self.key_texts[shown]
            words = _short_orders(", ".join(sorted((m.prefix for m in members), key=lambda p: float(p.rstrip("X"))))) \
                if all(m.prefix.rstrip("X").replace(".", "", 1).isdigit() for m in members) \
                else ", ".join(m.prefix for m in members)
            words = f"{words} {members[0].suffix}"
            w, h = self._size(words, _FONT, renderer)
            exits = [frame.x0 + m.u * frame.width for m in members]
            middle = 0.5 * (min(exits) + max(exits))
            box = None
            for left in middle - w / 2 + np.arange(0.0, 6.0) * w / 2:
                left = max(left, right_of)
                trial = (left, bottom, left + w, bottom + h)
                if trial[2] <= fig.bbox.x1 - gap and trial[3] <= fig.bbox.y1 - gap / 2 \
                        and not any(_overlap(trial, o, gap, gap) for o in obstacles):
                    box = trial
                    break
            if box is None:
                continue
            obstacles.append(box)
            right_of = box[2] + gap
            start = min(max(middle, box[0]), box[2])
            keyed.append((start, min(exits, key=lambda e: abs(e - start)), box, members[0].color))
            self._set(text, text=words, color=members[0].color, position=((box[0] - frame.x0) / frame.width,
                                                                               (bottom - frame.y0) / frame.height),
                           rotation=0.0, fontsize=font_points(_FONT), visible=True)
            shown += 1
        for leader, (start, end, box, colour) in zip(self.key_leaders, keyed):
            x, y = self._key_leader(start, end, bottom, frame.y1, [o for o in obstacles if o is not box], gap)
            self._set(leader, xdata=[(a - frame.x0) / frame.width for a in x],
                      ydata=[(b - frame.y0) / frame.height for b in y], color=colour, visible=True)
        for text, leader in zip(self.key_texts[shown:], self.key_leaders[shown:]):
            self._set(text, visible=False)
            self._set(leader, visible=False)

    def _key_leader(self, start, end, bottom, top, others, drop):
        """A key's leader [pixels]: (x, y) of its points, from its line's exit ``end`` on the axes'
        top edge ``top`` to ``start`` on the key's bottom edge ``bottom``. Straight, unless that
        line passes within :data:`~._labels.LEADER_GAP_POINTS` of one of the boxes ``others`` (the other
        keys, the title, the tick and mode labels: the 10-rotor chain's 'r006-r007' key, right of
        the 'r004-r005' key above its exit, ran its leader 0.2 points under that key's text): then
        straight down ``drop`` [pixels] from the key first and on to the exit from there, below
        the row of keys."""
        spacing = LEADER_GAP_POINTS * self.points * _OUTWARD
        if not others or not crossing_pairs([(end, top, start, bottom)],
                                             np.asarray(others, float).reshape(-1, 4) + spacing).any():
            return [end, start], [top, bottom]
        return [end, start, start], [top, bottom - drop, bottom]

    # -- modes ---------------------------------------------------------------------------
    def _reset_mode_texts(self):
        """Each mode label's own words again (a label shared at the last drawing), the labels and
        leaders of curves not in view hidden; the curves' ends (:meth:`_visible_end`)."""
        for text, m in zip(self.mode_texts, self.modes):
            self._set(text, text=f"mode {self.result.modes[m]}")
        ends = [self._visible_end(m) for m in self.modes]
        for i, end in enumerate(ends):
            if end is None:
                self._set(self.mode_texts[i], visible=False)
                self._set(self.leaders[i], visible=False)
        return ends

    def _visible_end(self, m):
        """('right', v, k) where mode ``m``'s curve (as drawn) meets the right edge at height
        ``v`` (axes fraction), ('inside', (u, v), k) at its last point inside the axes, or None;
        ``k`` is the sweep's speed at or before that end."""
        x, f, index = self.curves_drawn.x, self.curves_drawn.f[:, m], self.curves_drawn.index
        (lo, hi), (bottom, top) = sorted(self.ax.get_xlim()), sorted(self.ax.get_ylim())
        finite = np.isfinite(f)
        k = int(np.searchsorted(x, hi, side="right")) - 1
        if 0 <= k < len(x) and finite[k]:
            if k + 1 < len(x) and finite[k + 1] and x[k] < hi:
                edge = f[k] + (hi - x[k]) / (x[k + 1] - x[k]) * (f[k + 1] - f[k])
            else:
                edge = f[k] if np.isclose(x[k], hi, rtol=0, atol=1e-9 * max(hi - lo, 1e-300)) else None
            if edge is not None and bottom <= edge <= top:
                return "right", float(self.to_axes((hi, edge))[1]), int(index[k])
        view = finite & (x >= lo) & (x <= hi) & (f >= bottom) & (f <= top)
        if not view.any():
            return None
        k = int(np.nonzero(view)[0][-1])
        return "inside", tuple(float(c) for c in self.to_axes((x[k], f[k]))), int(index[k])

    def _colour(self, m, k):
        if not self.by_whirl:
            return "k"
        return WHIRL_STYLE.get(str(self.result.whirl[k, m]), WHIRL_STYLE["none"])["color"]

    def _beside(self, renderer, indices, ends):
        """Labels beside the right edge, in their curves' order, each joined to its curve by a
        leader line. Where the labels would not fit the axes' height, or would stand more than
        :data:`_MOST_SHIFT` label heights from their curves, curves whose ends lie close share one
        label ('modes 7, 8'; :func:`_grouped_beside`) with a leader line to each of them: every
        mode keeps its number on the figure (a long label in its compact form, '14 modes: 11, 21,
        23 … 111': :func:`_mode_words`)."""
        self.shared = []
        if not indices:
            return
        height = max(self._size(self.mode_texts[i].get_text(), _FONT, renderer)[1] for i in indices) * self.to_v
        gap = self.points * self.to_v
        groups, centres = _grouped_beside([ends[i][1] for i in indices], height, gap)
        stub, leader = _STUB_POINTS * self.points * self.to_u, _LEADER_POINTS * self.points * self.to_u
        pad = _PAD_POINTS * self.points * self.to_u
        for group, centre in zip(groups, centres):
            members = [indices[g] for g in group]
            colours = [self._colour(self.modes[i], ends[i][2]) for i in members]
            for i, colour in zip(members, colours):
                self._set(self.leaders[i], xdata=[1.0, 1.0 + stub, 1.0 + leader],
                               ydata=[ends[i][1], ends[i][1], centre], color=colour, visible=True)
                self._set(self.mode_texts[i], visible=False)
            numbers = [self.result.modes[self.modes[i]] for i in members]
            if len(numbers) > 1:
                self.shared.append((self.mode_texts[members[0]], numbers))
            self._set(self.mode_texts[members[0]], text=_mode_words(numbers), position=(1.0 + leader + pad, centre),
                           va="center", ha="left", color=colours[0] if len(set(colours)) == 1 else _SHARED_COLOUR,
                           visible=True, clip_on=False)

    def _inside(self, renderer, indices, ends, placed, markers):
        """Labels of curves that end inside the axes: next to the curve's last point, else
        nearby with a leader line (:meth:`_label_box`)."""
        pad_u, pad_v = _PAD_POINTS * self.points * self.to_u, _PAD_POINTS * self.points * self.to_v
        for i in indices:
            text = self.mode_texts[i]
            w, h = self._size(text.get_text(), _FONT, renderer)
            w, h = w * self.to_u, h * self.to_v
            u, v = ends[i][1]
            corners = [(u + pad_u, v - h / 2), (u - w - pad_u, v + pad_v), (u - w - pad_u, v - h - pad_v),
                       (u + pad_u, v + pad_v), (u + pad_u, v - h - pad_v), (u - w / 2, v + pad_v),
                       (u - w / 2, v - h - pad_v)]
            box, leader = self._label_box((u, v), [(a, b, a + w, b + h) for a, b in corners], (pad_u, pad_v),
                                          placed, markers, (0.0, 0.0))
            self._show_leader(self.leaders[i], leader, self._colour(self.modes[i], ends[i][2]))
            if box is None:
                self._set(text, visible=False)
                continue
            self._set(text, position=(box[0], box[1] + h / 2), va="center", ha="left", clip_on=True,
                           color=self._colour(self.modes[i], ends[i][2]), visible=True)

    def _label_box(self, anchor, near, gap, placed, markers, clear, own_nearest=False, wide=False, group=()):
        """A label's box (axes fraction) and its leader line ((start, end) or None), or (None, None).

        The first of the ``near`` boxes (touching the anchor) that lies inside the axes, clear
        of the labels ``placed`` (``gap`` from them), of the ``markers``, of every leader line
        and of every curve (but within :data:`ANCHOR_POINTS` of the anchor); else the box of a
        grid around the anchor (:func:`boxes_around`) so clear whose distance plus its leader
        line's crossings of curves costs least (at most :data:`_MOST_COST` label heights), the
        leader crossing no label nor any of the ``markers`` and ending ``clear`` (u, v) short of
        the anchor. ``own_nearest`` (critical speeds): every box, and every leader's end, lies
        :data:`_NEAREST_OWN` times as far from the centre of each of the ``markers`` as from the
        anchor (:meth:`_nearest_own`). ``group``: the centres (axes fraction) of the circles one
        label names (the anchor's first), the leader drawn to them (:meth:`_group_leader`).
        """
        u, v = anchor
        keep = (u - ANCHOR_POINTS * self.points * self.to_u, v - ANCHOR_POINTS * self.points * self.to_v,
                u + ANCHOR_POINTS * self.points * self.to_u, v + ANCHOR_POINTS * self.points * self.to_v)
        margin_u, margin_v = self.points * self.to_u, self.points * self.to_v
        frame = (margin_u, margin_v, 1 - margin_u, 1 - margin_v)

        markers_array = np.asarray(markers, float).reshape(-1, 4)

        def free(boxes, leader=False):
            # each of the boxes (n, 4): no curve through it, on no leader, naming its own circle
            ok = self._off_curves_and_leaders(boxes, keep)
            if own_nearest:
                ok &= self._nearest_own_each(boxes, anchor, markers, leader)
            return ok

        box = None if wide else first_free_box(near, placed, gap, frame, obstacles=markers, each=free)
        if box is not None:
            return box, None
        w, h = near[0][2] - near[0][0], near[0][3] - near[0][1]
        to_px = np.array([1 / self.to_u, 1 / self.to_v] * 2)
        clear_px = max(clear[0] / self.to_u, clear[1] / self.to_v)
        limit = _MOST_COST * h / self.to_v      # the farthest box [pixels]

        def around(**options):
            # the boxes (n, 4) of a grid around the anchor (boxes_around; axes fraction) and
            # their distances (n,) [pixels] (box_distances: distance's numbers)
            boxes = boxes_around_array(u / self.to_u, v / self.to_v, w / self.to_u, h / self.to_v,
                                       _PAD_POINTS * self.points, clear_px + _PAD_POINTS * self.points,
                                       split=_ROW_SPLIT, **options) / to_px
            return boxes, box_distances(boxes * to_px, u / self.to_u, v / self.to_v)

        grid, far = around()
        others = list(placed)
        others_array = np.asarray(others, float).reshape(-1, 4)      # (taken once: the checks run per box)
        # the labels placed, each widened by the leader's gap (LEADER_GAP_POINTS) on every side
        spaced = others_array + self._leader_spacing()

        def leader_clear(boxes, drawn=True):
            # each of the boxes (n, 4): its leader (from the box's point nearest the anchor) nor
            # through another marker: its end would touch that circle as much as its own
            # (counter_rotating's '11/21.9' reached mode 1's circles through mode 2's). The leader
            # as drawn, stopping short of its own circle: to the centre it ran through the squares
            # of circles beside it, 5 to 9 pixels away, and unstable_cross_coupled --freq-max 150
            # labelled none of its 10 critical speeds under 140 Hz of empty axes. A leader
            # across curves (the last resort) only where it would not pass a neighbour that close
            starts = nearest_each(boxes, anchor)
            short = self._short_of_each(starts, anchor, clear_px)
            ok = self._ends_nearest_each(short, markers, clear_px) & free(boxes, leader=True)
            to_anchor = np.column_stack([starts, np.broadcast_to(np.asarray(anchor, float), starts.shape)])
            if len(others_array):
                ok &= ~crossing_pairs(to_anchor, others_array).any(axis=1)
                # nor as drawn within the gap of another label's text (a leader too short to draw
                # is none: the box touches its circle)
                shown = ok & ~self._too_short_each(starts, anchor, clear_px)     # (the others fail anyway)
                ok[shown] = ~crossing_pairs(np.column_stack([starts, short])[shown], spaced).any(axis=1)
            ok &= ~_segments_crossed(starts, anchor, self._leader_array())
            if len(markers_array):
                ok &= ~crossing_pairs(np.column_stack([starts, short]) if drawn else to_anchor,
                                      markers_array).any(axis=1)
            return ok

        def cost(box):
            start = nearest_in(box, anchor)
            return distance(box) \
                + _CROSSING_COST * h / self.to_v * max(self.curves.crossings(start, anchor, keep),
                                                       self._mode_cuts(start, anchor, circle))

        distances = {}          # of each box, asked for many times (bounds, costs)

        def distance(box):
            if box not in distances:
                distances[box] = box_distance(box * to_px, u / self.to_u, v / self.to_v)
            return distances[box]

        radius = 0.5 * _MARKER_POINTS * self.points      # the circle's, as drawn
        circle = (u - radius * self.to_u, v - radius * self.to_v, u + radius * self.to_u, v + radius * self.to_v)

        def uncrossed(boxes, ok):
            # of the boxes (n, 4) the mask ``ok`` passes, those whose leaders cross no mode's curve
            # and run along no curve
            ok = ok.copy()
            starts = nearest_each(boxes[ok], anchor)
            uncut = self._mode_cuts_each(starts, anchor, circle) == 0
            ok[ok] = uncut
            if ok.any():
                starts = starts[uncut]
                ok[ok] = ~self._runs_along_each(starts, self._short_of_each(starts, anchor, clear_px))
            return ok

        # a leader across a mode's curve reads as pointing at that mode (compressor_rotor's
        # '11115' stood over mode 4's line, its leader across it): such a box only where no box
        # within the cost's reach has a leader crossing none (order lines it may cross: every
        # critical speed lies on one; nor the curves it runs beside into the marker: the anchor's
        # own. The square of ANCHOR_POINTS exempts any curve near the anchor: mode 4's line, 7
        # pixels above the circle, was crossed inside it)
        reach = grid[far <= limit]
        across = set()
        if own_nearest:
            # boxes across the circle too, their leaders short and steep: between two circles on
            # one mode's line a box at a slant lies nearer the neighbour (counter_rotating's '490'
            # between circles 42 pixels either side)
            boxes, distance_of = around(straddle=_ACROSS)
            # (above or below the circle, no curve through them but inside the circle)
            kept = (distance_of <= limit) & ((boxes[:, 1] >= v + clear[1]) | (boxes[:, 3] <= v - clear[1]))
            across = set(map(tuple, boxes[kept].tolist()))
            # nearest first, the first of equals first (as sorted() by distance would order them)
            both = np.concatenate([reach, np.asarray(list(across), float).reshape(-1, 4)])
            reach = both[np.argsort(box_distances(both * to_px, u / self.to_u, v / self.to_v), kind="stable")]

        def clear_of_curves(boxes):
            # leader_clear, and a box across the circle with no curve through it but inside the circle
            ok = leader_clear(boxes)
            if across:
                ok &= np.array([b not in across for b in map(tuple, boxes.tolist())], bool) \
                    | self.curves.free_each(boxes, circle)
            return uncrossed(boxes, ok)

        box = None if wide else first_free_box(
            BoxRows(reach), placed, gap, frame, obstacles=markers, cost=distance, bound=distance,
            each=clear_of_curves)
        if box is None and not wide:
            # boxes across the marker, their leaders short and steep: compressor_rotor's '12938'
            # (0:15000:151) sits on mode 4 between modes 5 and 3, 6 and 8 pixels away; every
            # slanting leader crossed one of them, a leader straight up crosses mode 5 inside the
            # circle (its box beside the anchor was taken by the '1X compressor' label)
            above, distance_of = around(straddle=_STRADDLE)
            # (no curve through such a box but inside the circle: its own curves run on through it)
            box = first_free_box(BoxRows(above[distance_of <= limit]), placed, gap,
                                 frame, obstacles=markers,
                                 each=lambda b: uncrossed(b, leader_clear(b) & self.curves.free_each(b, circle)),
                                 cost=distance, bound=distance)
        if box is None and own_nearest:
            if not wide:
                return None, None
            box = self._wider_box(anchor, (w, h), clear_px, set(map(tuple, grid.tolist())), placed, gap, frame,
                                  markers,
                                   lambda b: uncrossed(b, leader_clear(b)))
            if box is None:
                return None, None
        if box is None:
            box = first_free_box(BoxRows(grid), placed, gap, frame, obstacles=markers,
                                 each=lambda b: leader_clear(b, drawn=False), cost=cost, bound=distance)
        if box is None:
            return None, None
        if cost(box) > max(_MOST_COST * h / self.to_v, distance(box)):
            placed.pop()
            return None, None
        start = nearest_in(box, anchor)
        self.leader_lines.append((start, anchor))
        if len(group) > 1:
            return box, self._group_leader(start, group, clear)
        return box, self._drawn_leader(start, anchor, clear_px)

    def _wider_box(self, anchor, size, clear_px, tried, placed, gap, frame, markers, uncrossed):
        """A critical speed's label box (axes fraction) farther to the side than :meth:`_label_box`'s
        grid reaches (out to :data:`_WIDE_COLUMNS` label widths), within :data:`_MOST_COST` label
        heights, nearest first, its leader crossing no curve (``uncrossed``, a mask of boxes); or None. The boxes
        ``tried`` already are left out. flexible_pump_on_mounts' '700' (0:3600:121) crossed mode
        5's line from every box of the grid; a box 2.5 label widths right, between the curves, is clear
        (its leader, though, runs along mode 5's line: ``uncrossed`` refuses it now, and '700' goes to the note).

        Parameters
        ----------
        anchor : (float, float)
            The circle's centre [axes fraction].
        size : (float, float)
            The label's width and height [axes fraction].
        clear_px : float
            The leader's end stops this far from the centre [pixels].
        """
        u, v = anchor[0] / self.to_u, anchor[1] / self.to_v
        w, h = size[0] / self.to_u, size[1] / self.to_v
        pad = _PAD_POINTS * self.points
        boxes = boxes_around_array(u, v, w, h, pad, clear_px + pad, columns=_WIDE_COLUMNS, split=_ROW_SPLIT)
        far = box_distances(boxes, u, v)
        scale = np.array([self.to_u, self.to_v] * 2)
        wide = [b for b in (tuple(b) for b in (boxes[far <= _MOST_COST * h] * scale).tolist()) if b not in tried]
        return first_free_box(wide, placed, gap, frame, obstacles=markers, each=uncrossed)

    def _ends_nearest_each(self, ends, markers, clear_px):
        """Whether each of the leaders' drawn ``ends`` ((n, 2), axes fraction; ``clear_px`` [pixels]
        from its own circle's centre) lies :data:`_NEAREST_OWN` times as far from the centre of
        every other marker (``markers``: boxes, axes fraction): else it reads as pointing at that
        circle (counter_rotating's '1663' ended at the join of the 1663 and 1700 rpm circles).
        Mask (n,); the leaders are tested at once, each with the numbers of one alone."""
        ends = np.asarray(ends, float).reshape(-1, 2)
        if not len(markers):
            return np.ones(len(ends), bool)
        middle_u, middle_v, _ = self._marker_centres(markers)
        du = (middle_u[None, :] - ends[:, :1]) / self.to_u
        dv = (middle_v[None, :] - ends[:, 1:]) / self.to_v
        return np.all(np.hypot(du, dv) >= _NEAREST_OWN * clear_px, axis=1)

    def _nearest_own_each(self, boxes, anchor, markers, leader=False):
        """Whether each of the label ``boxes`` ((n, 4), axes fraction) reads as naming its own
        circle (centre ``anchor``) rather than one of the ``markers`` (boxes, axes fraction):
        without a leader, it lies :data:`_NEAREST_OWN` times as far from every other circle's
        centre as from its own; with one (``leader``), so, or :data:`_BESIDE_POINTS` from each.
        gear_machine's '1420' stood 13 pixels (150 dpi) from the 710 rpm circle and 18.5 from its
        own at the end of its leader, and was read as the 710 rpm circle's speed. Mask (n,)."""
        boxes = np.asarray(boxes, float).reshape(-1, 4)
        if not len(markers):
            return np.ones(len(boxes), bool)
        scale = np.array([self.to_u, self.to_v])
        centres = self._marker_centres(markers)[2]
        low, high = boxes[:, :2] / scale, boxes[:, 2:] / scale
        point = np.asarray(anchor) / scale
        gaps = np.maximum(np.maximum(low - point, point - high), 0.0)
        own = np.hypot(gaps[:, 0], gaps[:, 1])
        gaps = np.maximum(np.maximum(low[:, None, :] - centres[None], centres[None] - high[:, None, :]), 0.0)
        near = np.hypot(gaps[..., 0], gaps[..., 1])
        least = np.minimum(_NEAREST_OWN * own, _BESIDE_POINTS * self.points) if leader else _NEAREST_OWN * own
        return np.all(near >= least[:, None], axis=1)

    def _marker_centres(self, markers):
        """The centres of the ``markers`` (boxes, axes fraction): u and v (n,) [axes fraction] and
        (n, 2) [pixels]; worked out once for the list given (its boxes are tried many times)."""
        cached = self.__dict__.get("marker_centres")
        if cached is None or cached[0] is not markers or cached[1] != (self.to_u, self.to_v):
            boxes = np.asarray(markers, float).reshape(-1, 4)
            scale = np.array([self.to_u, self.to_v])
            centres = np.column_stack([boxes[:, 0] + boxes[:, 2], boxes[:, 1] + boxes[:, 3]]) / 2 / scale
            cached = self.marker_centres = (markers, (self.to_u, self.to_v), (boxes[:, 0] + boxes[:, 2]) / 2,
                                            (boxes[:, 1] + boxes[:, 3]) / 2, centres)
        return cached[2:]

    def _leader_array(self):
        """The leader lines drawn so far (:attr:`leader_lines`) as an (n, 4) array."""
        return self._rows_array("leader_lines")

    def _drawn_array(self):
        """The leader lines as drawn so far (:attr:`drawn_leaders`) as an (n, 4) array."""
        return self._rows_array("drawn_leaders")

    def _rows_array(self, name):
        """The list of (start, end) attribute ``name`` as an (n, 4) array, made again only when the
        list was replaced or one was added."""
        rows = getattr(self, name)
        cache = self.__dict__.setdefault("row_arrays", {})
        cached = cache.get(name)
        if cached is None or cached[0] is not rows or cached[1] != len(rows):
            cached = cache[name] = (rows, len(rows), np.asarray(rows, float).reshape(-1, 4))
        return cached[2]

    def _leader_spacing(self):
        """What widens a box (axes fraction) by :data:`~._labels.LEADER_GAP_POINTS` on every side:
        (-gap_u, -gap_v, gap_u, gap_v)."""
        gap = LEADER_GAP_POINTS * self.points
        return np.array([gap * self.to_u, gap * self.to_v] * 2) * _OUTWARD

    def _too_short_each(self, starts, centre, clear_px):
        """Whether each of ``starts`` ((n, 2), axes fraction) lies within ``clear_px`` [pixels] of
        ``centre`` (axes fraction): a leader from there, stopped ``clear_px`` short of the centre,
        would run back from its start into its own label (fan_on_bearings' '8845', 2.6 points
        above its circle, drew 1.4 points of leader inside its own text). Mask (n,)."""
        starts = np.asarray(starts, float).reshape(-1, 2)
        return np.hypot((starts[:, 0] - centre[0]) / self.to_u, (starts[:, 1] - centre[1]) / self.to_v) <= clear_px

    def _drawn_leader(self, start, centre, clear_px):
        """The leader line as drawn from ``start`` towards ``centre`` (axes fraction), stopped
        ``clear_px`` [pixels] short of it: (start, end), or None where it would run back
        (:meth:`_too_short_each`)."""
        if self._too_short_each([start], centre, clear_px)[0]:
            return None
        return tuple(start), self._short_of(start, centre, clear_px)

    def _short_of(self, start, centre, clear_px):
        """The end (axes fraction) of a leader line from ``start`` to ``centre`` (axes fraction)
        stopped ``clear_px`` [pixels] short of ``centre`` (outside its circle)."""
        u, v = centre
        direction = np.array([(start[0] - u) / self.to_u, (start[1] - v) / self.to_v])
        shorten = clear_px / max(float(np.hypot(*direction)), 1e-9)
        return (u + shorten * direction[0] * self.to_u, v + shorten * direction[1] * self.to_v)

    def _short_of_each(self, starts, centre, clear_px):
        """:meth:`_short_of` of each of ``starts`` (n, 2) at once: the ends (n, 2), the same numbers."""
        u, v = centre
        du, dv = (starts[:, 0] - u) / self.to_u, (starts[:, 1] - v) / self.to_v
        shorten = clear_px / np.maximum(np.hypot(du, dv), 1e-9)
        return np.column_stack([u + shorten * du * self.to_u, v + shorten * dv * self.to_v])

    def _mode_cuts(self, start, end, keep):
        """How many pieces of the curves but the order lines the segment ``start -> end`` crosses
        outside the marker's square ``keep`` (axes fraction, :func:`~._labels.cuts`); the curves'
        drawn segments are taken once per drawing."""
        segments, origin, size, bounds = self._mode_map()
        return cuts(segments, origin, size, start, end, keep, bounds=bounds)

    def _mode_cuts_each(self, starts, end, keep):
        """:meth:`_mode_cuts` of each segment ``starts[k] -> end`` (``starts`` (n, 2)) at once:
        counts (n,), the same numbers (:func:`~._labels.cuts_each`)."""
        segments, origin, size, bounds = self._mode_map()
        return cuts_each(segments, origin, size, starts, end, keep, bounds=bounds)

    def _runs_along_each(self, starts, ends):
        """Whether each leader ``starts[k] -> ends[k]`` ((n, 2), axes fraction; as drawn) runs
        along a mode's curve or an order line (:func:`~._labels.runs_along_each`; beside an order
        line within :data:`_ALONG_ORDER_DEGREES`). Mask (n,)."""
        runs = np.zeros(len(starts), bool)
        for (segments, origin, size, bounds), degrees in ((self._mode_map(), ALONG_DEGREES),
                                                          (self._order_map(), _ALONG_ORDER_DEGREES)):
            scale = np.asarray(size, float)
            starts_px, ends_px = np.asarray(origin) + starts * scale, np.asarray(origin) + ends * scale
            runs |= runs_along_each(segments, starts_px, ends_px, self.points, degrees, bounds)
        return runs

    def _order_map(self):
        """The order lines' drawn segments [pixels], the axes' origin and size [pixels] and the
        segments' bounds (as :meth:`_mode_map`), taken once per drawing."""
        if self.order_map is None:      # place() sets it to None before any leader is placed
            ax = self.ax
            self.order_map = self._segment_map([line for line in ax.get_lines() if line.get_gid() != "order-line"]
                                               + list(ax.collections))
        return self.order_map

    def _mode_map(self):
        """The drawn segments of the curves but the order lines [pixels], the axes' origin and size
        [pixels] and the segments' bounds (:func:`~._labels.segment_bounds`), taken once per drawing."""
        if self.mode_map is None:      # place() sets it to None before any leader is placed
            orders = [line for line in self.ax.get_lines() if line.get_gid() == "order-line"]
            self.mode_map = self._segment_map(self.leaders + self.critical_leaders + self.key_leaders + orders)
        return self.mode_map

    def _segment_map(self, skip):
        """The drawn segments of the axes' curves but ``skip`` [pixels], the axes' origin and size
        [pixels] and the segments' bounds."""
        frame = self.ax.get_window_extent(self.renderer)
        segments = _drawn_segments(self.ax, skip, (frame.x0, frame.y0, frame.x1, frame.y1))
        return segments, (frame.x0, frame.y0), (frame.width, frame.height), segment_bounds(segments)

    def _show_leader(self, line, leader, colour):
        """Draw ``line`` along ``leader`` ((start, end), axes fraction; kept in :attr:`drawn_leaders`),
        or hide it (None)."""
        if leader is None:
            self._set(line, visible=False)
            return
        self.drawn_leaders.append(leader)
        (x0, y0), (x1, y1) = leader
        self._set(line, xdata=[x0, x1], ydata=[y0, y1], color=colour, visible=True)

    # -- critical speeds -----------------------------------------------------------------
    def _marker_boxes(self):
        """Boxes (axes fraction) of the critical-speed markers inside the axes."""
        radius_u, radius_v = 4 * self.points * self.to_u, 4 * self.points * self.to_v
        if not len(self.critical[0]):
            return []
        # every point at once (the 60-rotor chain's 16,864 one by one took seconds), the same numbers
        u, v = np.asarray(self.to_axes(np.column_stack(self.critical)), float).T
        inside = (0 <= u) & (u <= 1) & (0 <= v) & (v <= 1)
        u, v = u[inside], v[inside]
        return list(zip((u - radius_u).tolist(), (v - radius_v).tolist(), (u + radius_u).tolist(),
                        (v + radius_v).tolist()))

    def _place_critical(self, renderer, placed, markers):
        """Each critical speed's label beside its marker, else nearby with a leader line
        (:meth:`_label_box`), else (a second pass) farther to the side (:meth:`_wider_box`), or none."""
        if not self.critical_texts:
            return
        gap = (_NUMBER_GAP_POINTS * self.points * self.to_u, 0.5 * self.points * self.to_v)
        left = [group for group in self._critical_groups()
                if not self._place_group(group, renderer, placed, markers, gap, wide=False)]
        # the places farther to the side only once every circle has had its near places: a
        # label far out took the room of another's near place (gear_machine's '281' took '561''s)
        for group in left:
            self._place_group(group, renderer, placed, markers, gap, wide=True)

    def _place_group(self, group, renderer, placed, markers, gap, wide):
        """The label of the critical speeds ``group`` (indices; circles that read as one) and its
        leader (:meth:`_label_box`, ``wide`` passed on), or none; whether it is labelled."""
        radius_u, radius_v = 4 * self.points * self.to_u, 4 * self.points * self.to_v
        j = group[0]
        text = self.critical_texts[j]
        for k in group[1:]:
            self._set(self.critical_texts[k], visible=False)
            self._set(self.critical_leaders[k], visible=False)
        self._set(text, text="/".join(dict.fromkeys(self.critical_words[k] for k in group)))
        u, v = self.to_axes((self.critical[0][j], self.critical[1][j]))
        own = [self.to_axes((self.critical[0][k], self.critical[1][k])) for k in group]
        w, h = self._size(text.get_text(), "xx-small", renderer)
        w, h = w * self.to_u, h * self.to_v
        corners = [(u + radius_u, v - radius_v - h * 0.5), (u + radius_u, v + radius_v - h * 0.5),
                   (u - radius_u - w, v - radius_v - h * 0.5), (u - radius_u - w, v + radius_v - h * 0.5),
                   (u - w / 2, v + radius_v), (u - w / 2, v - radius_v - h),
                   (u + radius_u, v - h / 2), (u - radius_u - w, v - h / 2)]
        box = leader = None
        if 0 <= u <= 1 and 0 <= v <= 1:
            # every other group's circle is an obstacle, one overlapping its own too (rubber_mounts'
            # 38.6 and 77.2 rpm, 5 pixels apart: the first's leader ended on the second's circle)
            mine = {(a - radius_u, b - radius_v, a + radius_u, b + radius_v) for a, b in own}
            box, leader = self._label_box((u, v), [(a, b, a + w, b + h) for a, b in corners], gap, placed,
                                          [m for m in markers if m not in mine], (radius_u, radius_v),
                                          own_nearest=True, wide=wide, group=own)
        self._show_leader(self.critical_leaders[j], leader, "k")
        if box is None:
            self._set(text, visible=False)
            return False
        self._set(text, position=(box[0], box[1]), va="bottom", ha="left", clip_on=True, visible=True)
        return True

    def _group_leader(self, start, own, clear):
        """The leader from ``start`` to a group's circles ``own`` (axes fraction): to the edge of the
        circle farthest along its way, so that it ends beside every circle of the group (ending at
        the first circle's edge on the side away from the second, the fan's '3898/3943', circles
        3.6 pixels apart, pointed at 3898 only); None where ``start`` lies inside that circle's
        clearance (:meth:`_drawn_leader`)."""
        px = np.array([1 / self.to_u, 1 / self.to_v])
        start_px, centres = np.asarray(start) * px, np.asarray(own) * px
        way = centres.mean(axis=0) - start_px
        target = own[int(np.argmax(centres @ way))]
        return self._drawn_leader(start, target, max(clear[0] / self.to_u, clear[1] / self.to_v))

    def _in_view(self):
        """Indices of the critical speeds whose markers lie inside the axes."""
        if not len(self.critical[0]):
            return []
        points = self.to_axes(np.column_stack(self.critical))
        return np.flatnonzero(np.all((points >= 0) & (points <= 1), axis=1)).tolist()

    def _unlabelled_critical(self):
        """Indices of the critical speeds inside the axes whose speed no visible label reads."""
        named = set()
        if self.critical_texts:
            for group in self._critical_groups():
                if self.critical_texts[group[0]].get_visible():
                    named.update(group)
        return [k for k in self._in_view() if k not in named]

    def _note_texts(self, left):
        """The note's wordings, longest first: the count, then the speeds left unlabelled by mode."""
        total = len(self._in_view())
        head = f"{total - len(left)} of {total} critical speeds labelled (all in the critical-speeds table)"
        if len(left) > _MAX_LISTED:
            return [head]
        by_mode = {}
        for k in sorted(left, key=lambda k: (self.critical_modes[k], self.critical[0][k])):
            by_mode.setdefault(self.critical_modes[k], []).append(self.critical_words[k])
        entries = [f"mode {mode}: {', '.join(words)}" for mode, words in by_mode.items()]
        lead = f"{head}; the others [{self.speed_unit}]"
        return [_wrapped([lead] + entries, width) for width in _NOTE_WIDTHS] + [head]

    def _place_note(self, renderer, placed, markers):
        """Where some critical speeds find no label: a note inside the axes, clear of the
        curves, labels and markers, as near the unlabelled markers as it fits, saying how many
        are labelled and listing the others by mode ('mode 3: 177, 257'); with no room for
        the list, the count only; with no room for that, the count in the legend."""
        note = self.critical_note
        self.note_modes = set()
        if note is None:
            return
        left = self._unlabelled_critical()
        entry = _critical_entry(self.ax)
        if entry is not None:
            self._set(entry, text="critical speed")
        if not left:
            self._set(note, visible=False)
            return
        # every point in one transform (the 60-rotor chain's 16,864 one by one took seconds), the same numbers
        centre = np.mean(self.to_axes(np.column_stack(self.critical)[left]), axis=0)
        margin_u, margin_v = self.points * self.to_u, self.points * self.to_v
        frame = (margin_u, margin_v, 1 - margin_u, 1 - margin_v)
        gap = (_PAD_POINTS * self.points * self.to_u, _PAD_POINTS * self.points * self.to_v)
        texts = self._note_texts(left)
        for n, words in enumerate(texts):
            w, h = self._size(words, "xx-small", renderer)
            w, h = w * self.to_u, h * self.to_v
            lefts, bottoms = np.arange(frame[0], frame[2] - w, 0.02), np.arange(frame[1], frame[3] - h, 0.02)
            # the grid's first row and column kept _NOTE_MARGIN_POINTS off the spines (1 pt read as
            # touching the left spine on the flexible pump's Campbell); the others as they were
            lefts = np.maximum(lefts, _NOTE_MARGIN_POINTS * margin_u)
            bottoms = np.maximum(bottoms, _NOTE_MARGIN_POINTS * margin_v)
            # every left with every bottom (bottoms the inner loop), nearest the centre first (a
            # stable sort: the first of equals first), tested many at a time
            a, b = np.repeat(lefts, len(bottoms)), np.tile(bottoms, len(lefts))
            inside = (a + w <= 1 - _NOTE_MARGIN_POINTS * margin_u) & (b + h <= 1 - _NOTE_MARGIN_POINTS * margin_v)
            boxes = np.column_stack([a, b, a + w, b + h])[inside]
            boxes = boxes[np.argsort(np.hypot((boxes[:, 0] + boxes[:, 2]) / 2 - centre[0],
                                              (boxes[:, 1] + boxes[:, 3]) / 2 - centre[1]), kind="stable")]
            box = first_free_box(BoxRows(boxes), placed, gap, frame, obstacles=markers,
                                 each=self._off_curves_and_leaders)
            if box is not None:
                self._set(note, text=words, position=(box[0], box[1]), va="bottom", ha="left",
                               clip_on=True, visible=True)
                if n < len(texts) - 1:          # the list by mode (the last wording is the count alone)
                    self.note_modes = {int(self.critical_modes[k]) for k in left}
                return
        self._set(note, visible=False)
        if entry is not None:           # on two lines: one as long as the note's reached past a small figure
            total = len(self._in_view())
            self._set(entry, text=f"critical speed ({total - len(left)} of {total} labelled,\n"
                                       "all in the critical-speeds table)")

    def _off_curves_and_leaders(self, boxes, keep=None):
        """Whether each of ``boxes`` ((n, 4), axes fraction) holds no curve (but inside ``keep``,
        :meth:`~._labels.CurveMap.free_each`) and no leader line drawn so far runs through it:
        mask (n,)."""
        ok = self.curves.free_each(boxes, keep)
        drawn_leaders = self._leader_array()
        if len(drawn_leaders):
            ok &= ~crossing_pairs(drawn_leaders, boxes).any(axis=0)
            # nor within the leader's gap of one as drawn (LEADER_GAP_POINTS)
            shown, left = self._drawn_array(), np.flatnonzero(ok)       # (the others fail anyway)
            if len(shown) and len(left):
                spaced = np.asarray(boxes, float).reshape(-1, 4)[left] + self._leader_spacing()
                ok[left] = ~crossing_pairs(shown, spaced).any(axis=0)
        return ok

    def _name_mentioned(self):
        """The compact right-edge labels (:func:`_mode_words`) that leave out a mode the note
        lists (:meth:`_place_note`) name it too: every mode number the figure writes is found
        at its curve's end."""
        for text, numbers in self.shared:
            mentioned = self.note_modes.intersection(int(n) for n in numbers)
            if mentioned:
                self._set(text, text=_mode_words(numbers, mentioned))

    def _place_none_note(self, renderer, placed, markers):
        """Where the sweep has no critical speed (no order line crosses a mode): the note
        saying so, near the top of the axes, clear of the curves and labels (at the top left
        where no place is clear)."""
        note = self.none_note
        if note is None:
            return
        margin_u, margin_v = 2 * self.points * self.to_u, 2 * self.points * self.to_v
        frame = (margin_u, margin_v, 1 - margin_u, 1 - margin_v)
        gap = (_PAD_POINTS * self.points * self.to_u, _PAD_POINTS * self.points * self.to_v)
        w, h = self._size(note.get_text(), "x-small", renderer)
        w, h = w * self.to_u, h * self.to_v
        lefts, bottoms = np.arange(frame[0], frame[2] - w, 0.02), np.arange(frame[1], frame[3] - h, 0.02)
        boxes = sorted(((a, b, a + w, b + h) for a in lefts for b in bottoms),
                       key=lambda box: np.hypot((box[0] + box[2]) / 2 - 0.5, box[3] - 0.97))
        box = first_free_box(boxes, placed, gap, frame, obstacles=markers,
                             each=self._off_curves_and_leaders)
        left, bottom = (box[0], box[1]) if box is not None else (frame[0], frame[3] - h)
        placed.append((left, bottom, left + w, bottom + h))
        self._set(note, position=(left, bottom), va="bottom", ha="left", clip_on=True, visible=True)

    def _critical_groups(self):
        """The critical speeds' indices in groups whose circles read as one (each centre closer
        than half :data:`_MARKER_POINTS` to the group's first, in order of speed; not a chain,
        so that a group stays within one circle: :func:`~._labels.touching_groups`), each in
        order of speed: one label names the group ('2842/2855'), so that two labels never print
        over each other at one place. Found once for the scales (:meth:`_set_scales`)."""
        if self.__dict__.get("critical_groups") is None:
            self.critical_groups = self._grouped_critical()
        return self.critical_groups

    def _grouped_critical(self):
        """:meth:`_critical_groups`, found."""
        # every point in one transform (as _marker_boxes: the 60-rotor chain's 16,864 one by one
        # took a third of a second at each scale), the same numbers
        points = np.asarray(self.to_axes(np.column_stack(self.critical)), float).reshape(-1, 2) \
            / np.array([self.to_u, self.to_v])
        order = np.argsort(self.critical[0], kind="stable")
        return [[int(order[k]) for k in group]
                for group in touching_groups(points[order], 0.5 * _MARKER_POINTS * self.points, chain=False)]


def _grouped_beside(targets, height, gap):
    """The right-edge labels of curves ending at ``targets``: groups of curves that share a label
    and the labels' centres (axes fraction).

    Each curve has its own label where all fit the axes' height within :data:`_MOST_SHIFT`
    label heights of their curves' ends
    (:func:`~rotordyn_modal.plotting._labels.column_positions`). Else, one merge at a time until
    they do, the two neighbouring labels of the column's crowd (the labels stacked edge to edge
    around the one farthest from its curves) whose curves' ends span least share one label,
    centred on that span: curves whose ends lie on each other first, and only where labels crowd.

    Parameters
    ----------
    targets : sequence of float, length n >= 1
        Heights where the curves meet the right edge (axes fraction).
    height, gap : float
        A label's height and the space kept between labels (axes fraction).

    Returns
    -------
    groups : list of list of int
        Indices into ``targets`` of each label's curves, labels from the bottom up, each
        group's curves from the bottom up.
    centres : ndarray, shape (len(groups),)
        The labels' centres (axes fraction).
    """
    targets = np.asarray(targets, float)
    groups = [[int(k)] for k in np.argsort(targets, kind="stable")]
    pitch = height + gap
    while True:
        low, high = np.array([targets[g[0]] for g in groups]), np.array([targets[g[-1]] for g in groups])
        if len(groups) > 1 and len(groups) * pitch > 1.0:
            # too many for the column: the neighbours spanning least share a label, wherever the
            # labels would stand (the 40-rotor chain's first 420 merges stacked none)
            j = int(np.argmin(high[1:] - low[:-1]))
            groups[j:j + 2] = [groups[j] + groups[j + 1]]
            continue
        wanted = 0.5 * (low + high)
        centres = column_positions(wanted, [height] * len(groups), 0.0, 1.0, gap=gap)
        shift = np.abs(centres - wanted)
        if len(groups) == 1 or (len(groups) * pitch <= 1.0 and shift.max() <= _MOST_SHIFT * pitch):
            return groups, centres
        first, last = 0, len(groups) - 1
        if len(groups) * pitch <= 1.0:          # the crowd around the label farthest from its curves
            first = last = int(np.argmax(shift))
            while first > 0 and centres[first] - centres[first - 1] <= pitch * (1 + 1e-9):
                first -= 1
            while last < len(groups) - 1 and centres[last + 1] - centres[last] <= pitch * (1 + 1e-9):
                last += 1
            if first == last:                   # alone, pushed by the axes' ends: with a neighbour
                first, last = (first, last + 1) if last + 1 < len(groups) else (first - 1, last)
        j = first + int(np.argmin(high[first + 1:last + 1] - low[first:last]))
        groups[j:j + 2] = [groups[j] + groups[j + 1]]


def _mode_words(numbers, mentioned=()):
    """A right-edge label's words: 'mode 7', 'modes 7, 8', 'modes 3, 7–9' (three or more
    consecutive numbers as a range, with an en dash); a label that would write more than
    :data:`_MOST_NUMBERS` numbers so, in a compact form that counts its modes and names the
    lowest :data:`_FIRST_NUMBERS`, the highest and those of ``mentioned`` among them, an
    ellipsis where numbers are left out: '14 modes: 11, 21, 23 … 111', '14 modes: 11, 21, 23 …
    57 … 111' (mode 57 named by the figure's note). The 60-rotor gear chain's label of 14 modes
    was 356 pixels wide at 110 dpi and squeezed the axes to half the figure."""
    numbers = sorted(int(n) for n in numbers)
    if len(numbers) == 1:
        return f"mode {numbers[0]}"
    runs = [[numbers[0]]]
    for n in numbers[1:]:
        if n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    if sum(2 if len(r) >= 3 else len(r) for r in runs) <= _MOST_NUMBERS:
        parts = [f"{r[0]}\u2013{r[-1]}" if len(r) >= 3 else ", ".join(map(str, r)) for r in runs]
        return "modes " + ", ".join(parts)
    shown = set(numbers[:_FIRST_NUMBERS]) | {numbers[-1]} | {int(n) for n in mentioned}
    words = ""
    for k, n in enumerate(numbers):
        if n in shown:
            words += ("" if not words else ", " if numbers[k - 1] in shown else " \u2026 ") + str(n)
    return f"{len(numbers)} modes: {words}"


def _unnamed(exits, taken):
    """The top-edge exits (:class:`EdgeLabel`) that no label of ``taken`` names, in groups of one
    source's neighbours (no other line's exit between them)."""
    def named(exit_):
        return any(t.edge == exit_.edge and t.suffix == exit_.suffix and t.u - 1e-12 <= exit_.u <= t.u + t.spread + 1e-12
                   and (t.prefix == exit_.prefix or not t.prefix.endswith("X") or t.spread or "," in t.prefix
                        or "\u2013" in t.prefix) for t in taken)
    tops = sorted([e for e in exits if e.edge == "top"], key=lambda e: e.u)
    groups = []
    for exit_ in tops:
        if named(exit_):
            groups.append(None)
        elif groups and groups[-1] is not None and groups[-1][-1].suffix == exit_.suffix:
            groups[-1].append(exit_)
        else:
            groups.append([exit_])
    return [group for group in groups if group is not None]


def _wrapped(entries, width):
    """``entries`` joined by '; ' into lines of at most ``width`` characters (an entry longer
    than that on a line of its own), the first entry followed by ':'."""
    lines = [entries[0] + ":"]
    for entry in entries[1:]:
        if len(lines) > 1 and len(lines[-1]) + 2 + len(entry) <= width:
            lines[-1] += "; " + entry
        else:
            lines.append(entry)
    return "\n".join(lines)


def _padded_axes(ax, pad: float = 0.025):
    """The axes' box grown by ``pad`` (a fraction of its width and height) on every side, in display
    coordinates, following the axes' size: a clip box that lets a marker on the edge show whole."""
    from matplotlib.transforms import Bbox, TransformedBbox

    return TransformedBbox(Bbox([[-pad, -pad], [1 + pad, 1 + pad]]), ax.transAxes)
