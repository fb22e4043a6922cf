"""Bode figures: FRFs (model over measurement) and unbalance response vs speed."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..units import FRF_OUTPUT_KINDS, ratio_scale, unit_scale
from ..units import rpm_text

__all__ = ["plot_frf", "plot_unbalance", "plot_overlay"]

#: more FRFs than this are drawn in groups, each with its legend
_MAX_LEGEND = 12
_UNITS = {"receptance": "m/N", "mobility": "m/s/N", "accelerance": "m/s²/N", "force": "N/N"}


def _bode_axes(figsize=(8.0, 6.0)):
    import matplotlib.pyplot as plt

    fig, (mag, phase) = plt.subplots(2, 1, sharex=True, figsize=figsize, layout="constrained",
                                     gridspec_kw={"height_ratios": [2, 1]})
    phase.set_yticks([-180, -90, 0, 90, 180])
    phase.set_ylabel("Phase [deg]")
    return fig, mag, phase


def plot_frf(result, measured=None, pairs=None, title: str | None = None, units: str = "si", input_kinds=None):
    """Magnitude (log) and phase of FRFs against frequency, measured data dotted beneath.

    The frequency axis is logarithmic where the frequencies span more than 30 times (from
    above 0 Hz), else linear. Up to :data:`_MAX_LEGEND` FRFs of one unit share one magnitude and one phase panel;
    more, or forces beside moments, are drawn in groups (:func:`_frf_groups`: each force
    item, else each input), each group's forces, moments and phases in panels of their own,
    every curve named in its group's legend (beside the panels, or above each panel where a
    legend would take more than :data:`_LEGEND_SHARE` of its block's width:
    :func:`_place_legends`). Curves lying on each other are drawn there in turn, found on the
    layout of the figure's first drawing (its save or display:
    :func:`._overlap.at_first_layout`), or for groups when the figure is made.

    Parameters
    ----------
    result : FRFResult
    measured : FRFResult, optional
        Measured FRFs with the same output and input names (matched by name).
    pairs : list of (output, input), optional
        Which FRFs to draw (default all).
    title : str, optional
    units : {'si', 'us'}
        Unit system of the magnitudes: SI (m/N, m/s/N, m/s²/N, N/N) or US customary (in/lbf,
        in/s/lbf, g/lbf, lbf/lbf; lbf in for moments), docs/units.md.
    input_kinds : dict, optional
        ``{input name: 'force' or 'moment'}`` (default force): the unit of each input in US units.

    Returns
    -------
    matplotlib.figure.Figure
    """
    pairs = pairs or [(o, i) for o in result.outputs for i in result.inputs]
    if not pairs:                # force outputs of a part the model has none of (no [[suspensions]])
        from ..errors import InputError

        raise InputError(f"nothing to draw: the FRF has no {'outputs' if not result.outputs else 'inputs'} (force "
                         "outputs of a part the model has none of, e.g. --force-outputs suspensions without "
                         "[[suspensions]])")
    nonzero = [(o, i) for o, i in pairs if np.any(result.H[result.outputs.index(o), result.inputs.index(i)])]
    zero, pairs = len(pairs) - len(nonzero), nonzero or pairs
    default = (f"{result.quantity.capitalize()} at {rpm_text(result.speed * 30 / np.pi)} rpm"
               + (f" ({len(pairs)} FRFs)" if len(pairs) > _MAX_LEGEND else "")
               + (f"; {zero} FRFs zero at every frequency, not drawn" if zero and nonzero else ""))
    groups = _frf_groups(pairs)
    scale = _FrfScale(result.quantity, units, input_kinds)
    if len(groups) > 1 or _is_moment(pairs[0][0]) != _is_moment(pairs[-1][0]):
        return _plot_frf_groups(result, measured, groups, title or default, scale)
    fig, mag, phase = _bode_axes(figsize=(9.5, 6.0))
    _draw_frfs(mag, phase, result, measured, pairs, lambda o, i: f"{o} / {i}", scale)
    mag.set_ylabel(f"|H| [{_UNITS.get(result.quantity, '') if units == 'si' else scale.label(pairs)}]")
    phase.set_xlabel(frequency_label(result.frequencies_hz, measured))
    mag.set_title(title or default)
    # beside, off the curves, or above the panel where wider than a fifth of the figure (as the
    # groups' legends); the overlaps of curves lying on each other are found at the first
    # drawing, on this layout, and their notes may take the legend above then (see
    # docs/figures.md, "FRF and unbalance legends")
    legends = [_Legend(mag, "small", "model (line), measured (dots)" if measured is not None else None)]
    above = _place_legends([(fig, legends)])
    _show_frf_overlaps(fig, [mag, phase] if measured is None else [mag], result, [(fig, legends)], above)
    return fig


class _FrfScale:
    """The factor on an SI FRF ``(output, input)`` and the unit of a panel in ``units`` (the
    output's quantity over the input's: force, or moment per ``input_kinds``)."""

    def __init__(self, quantity, units="si", input_kinds=None):
        self.quantity, self.units, self.input_kinds = quantity, units, input_kinds or {}

    def _kinds(self, o, i):
        out = "moment" if self.quantity == "force" and _is_moment(o) else FRF_OUTPUT_KINDS.get(self.quantity, "length")
        return out, self.input_kinds.get(i, "force")

    def __call__(self, o, i) -> float:
        return ratio_scale(*self._kinds(o, i), self.units)[0]

    def label(self, pairs) -> str:
        return ", ".join(dict.fromkeys(ratio_scale(*self._kinds(o, i), self.units)[1] for o, i in pairs))


def _is_moment(output: str) -> bool:
    """A force FRF's moment component (``NAME:Mx``)."""
    return ":M" in output and output.rsplit(":", 1)[1] in ("Mx", "My", "Mz")


def _frf_groups(pairs):
    """``[(title, pairs), ...]``: one group when the pairs fit one legend; else one per force item
    (``NAME`` of ``NAME:Fx``) or, for sensors, per input; groups above the legend size in parts."""
    if len(pairs) <= _MAX_LEGEND:
        return [("", pairs)]
    by_item = all(":" in o for o, _ in pairs)
    groups = {}
    for o, i in pairs:
        groups.setdefault(o.rsplit(":", 1)[0] if by_item else f"input {i}", []).append((o, i))
    parts = []
    for name, members in groups.items():
        chunks = [members[k:k + _MAX_LEGEND] for k in range(0, len(members), _MAX_LEGEND)]
        parts += [(name if len(chunks) == 1 else f"{name} ({n + 1}/{len(chunks)})", chunk)
                  for n, chunk in enumerate(chunks)]
    return parts


def _blocks(count, size):
    """A figure of ``count`` blocks (subfigures) of ``size`` (width, height) [in] each, in up to
    two columns; returns the figure and the blocks, row by row (those past ``count`` hidden)."""
    import matplotlib.pyplot as plt

    columns = 1 if count == 1 else 2
    rows = int(np.ceil(count / columns))
    fig = plt.figure(figsize=(size[0] * columns, size[1] * rows), layout="constrained")
    blocks = np.atleast_1d(fig.subfigures(rows, columns, squeeze=False).ravel())
    for block in blocks[count:]:
        block.set_visible(False)
    return fig, blocks


def _plot_frf_groups(result, measured, groups, title, scale=None):
    """One block of panels per group (forces, moments when any, phase), in up to two columns."""
    fig, blocks = _blocks(len(groups), (7.5, 4.6))
    by_item = all(":" in o for _, members in groups for o, _ in members)
    drawn = []              # axes whose curves are drawn in turn where they lie on each other
    placed = []             # (block, its legends)
    for block, (name, members) in zip(blocks, groups):
        kinds = [[p for p in members if not _is_moment(p[0])], [p for p in members if _is_moment(p[0])]]
        kinds = [k for k in kinds if k]
        axes = block.subplots(len(kinds) + 1, 1, sharex=True, gridspec_kw={"height_ratios": [2] * len(kinds) + [1]})
        phase = axes[-1]
        # a block of one force item (its title) names the components only; a block of several
        # (a few FRFs, forces beside moments) names the items too: 'Fy / shaker-y' three times
        # (two bearings and the rotor) told the curves apart by nothing
        one_item = by_item and name and len({o.rsplit(":", 1)[0] for o, _ in members}) == 1
        first = 0                   # the moments' curves go on in the forces' styles: one phase panel
        for ax, kind in zip(axes, kinds):
            _draw_frfs(ax, phase, result, measured, kind,
                       (lambda o, i: f"{o.rsplit(':', 1)[1]} / {i}") if one_item else (lambda o, i: f"{o} / {i}"),
                       scale, first)
            first += len(kind)
            unit = "N m/N" if _is_moment(kind[0][0]) else _UNITS.get(result.quantity, "")
            if scale is not None and scale.units != "si":
                unit = scale.label(kind)
            ax.set_ylabel(f"|H| [{unit}]")
        phase.set_yticks([-180, -90, 0, 90, 180])
        phase.set_ylabel("Phase [deg]")
        phase.set_xlabel(frequency_label(result.frequencies_hz, measured))
        axes[0].set_title(name, fontsize="medium")
        drawn.extend(axes if measured is None else axes[:-1])   # measured dots share no samples
        placed.append((block, [_Legend(ax, "x-small", "line: model, dots: measured" if measured is not None else None)
                               for ax in axes[:-1]]))
    fig.suptitle(title)
    height = fig.get_figheight()
    above = _place_legends(placed)
    _grow(fig, height, above)
    # the overlaps found on a layout of their own: their notes may take the legends above the
    # panels, and the figure grows by their height (it cannot while it is drawn)
    _notes_and_legends(fig, drawn, (result.frequencies_hz, "hz"), placed, above,
                       lambda heights: _grow(fig, height, heights))
    return fig


def _notes_and_legends(fig, axes, speeds, placed, above, grow=None):
    """Curves of ``axes`` lying on each other drawn in turn on ``fig`` as now laid out (its
    layout run here), their legends' notes written (:func:`_show_overlaps`; ``speeds``: its
    ``x`` and ``speed_unit``) and the legends of ``placed`` placed again (``above``: their
    heights above each holder's panels so far, :func:`_place_legends`); where the notes change
    those heights (take the legends from beside the panels to above them: the panels widen;
    add rows above them), the overlaps are found again on the new layout. ``grow(heights)``
    resizes the figure; None: inside the figure's drawing, no resize. Returns whether a legend
    changed."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    def lay_out():
        if grow is None:                # inside the drawing: its layout only
            ConstrainedLayoutEngine.execute(fig.get_layout_engine(), fig)
        else:
            fig.draw_without_rendering()

    if grow is not None:
        lay_out()
    state = [(line, line.get_label(), line.get_linestyle()) for ax in axes for line in ax.get_lines()]
    if not _show_overlaps(axes, *speeds):
        return False
    heights = _place_legends(placed)
    if grow is not None:
        grow(heights)
    if heights != above:
        lay_out()
        for ax in axes:
            for line in [line for line in ax.get_lines() if line.get_label() == "_overlap"]:
                line.remove()
        for line, label, style in state:
            line.set_label(label)
            line.set_linestyle(style)
        _show_overlaps(axes, *speeds)
        heights = _place_legends(placed, above=any(heights))
        if grow is not None:
            grow(heights)
    return True


def _grow(fig, height, above):
    """Make ``fig`` of blocks (two a row, :func:`_blocks`) ``height`` [in] plus the height of
    the legends above the panels of each row's block (``above``, [in], one per block)."""
    fig.set_figheight(height + sum(max(above[k:k + 2]) for k in range(0, len(above), 2)))


#: a legend beside its panel takes at most this share of the width of its figure (or block of
#: panels); a wider one (long names, '(= ...)' notes) and every other legend of that figure
#: (block) stand above their panels instead, in as many columns as the width takes
_LEGEND_SHARE = 0.2
#: share of the figure's (block's) width a legend above its panel may take
_ABOVE_SHARE = 0.9


@dataclass
class _Legend:
    """The legend of the curves of ``ax`` (font size, title; ``beside``: its left edge beside
    the axes, in axes widths)."""

    ax: object
    fontsize: str = "small"
    title: str | None = None
    beside: float = 1.01


def _place_legends(placed, renderer=None, above=False) -> list:
    """Draw the legends of ``placed`` (``[(holder, [_Legend, ...]), ...]``: a figure or its
    blocks (subfigures), the legends of their panels): each beside its panel's top right when
    every one of them is at most :data:`_LEGEND_SHARE` of its holder's width, else each above
    its panel (under the panel's title) in columns, at most :data:`_ABOVE_SHARE` of the width:
    one place for all, the figure reads alike (``above``: above in any case). Returns, per
    holder, the height [in] of its legends above its panels (0 beside)."""
    renderer = renderer or _renderer(placed[0][0].get_figure(root=True))
    narrow = not above
    for holder, legends in placed:
        for legend, box in ((legend, _legend_beside(legend)) for legend in legends):
            narrow = narrow and (box is None or box.get_window_extent(renderer).width <= _LEGEND_SHARE * holder.bbox.width)
    if narrow:
        return [0.0] * len(placed)
    return [sum(_legend_above(legend, _ABOVE_SHARE * holder.bbox.width, renderer) for legend in legends)
            for holder, legends in placed]


def _renderer(fig):
    """A renderer of ``fig`` to measure text with (the canvas's own, as it draws)."""
    get = getattr(fig.canvas, "get_renderer", None)
    return get() if get is not None else fig._get_renderer()


def _legend_entries(ax):
    """``(handles, labels)`` of the legend of ``ax``: its named artists, then the entries that
    are no artist of it (``ax._legend_extra``: what a panel's marks mean, :func:`_draw_frfs`)."""
    handles, labels = ax.get_legend_handles_labels()
    extra = getattr(ax, "_legend_extra", [])
    return handles + extra, labels + [h.get_label() for h in extra]


def _legend_beside(legend):
    """``legend`` beside its panel's top right (None when the panel has no named curve)."""
    if not legend.ax.get_legend_handles_labels()[0]:
        return None
    return legend.ax.legend(*_legend_entries(legend.ax), fontsize=legend.fontsize, title=legend.title,
                            title_fontsize=legend.fontsize, loc="upper left", bbox_to_anchor=(legend.beside, 1.0))


def _legend_above(legend, width, renderer) -> float:
    """``legend`` centred above its panel in the most columns (up to six) that keep it within
    ``width`` [pixels], the panel's title moved above it; returns its height [in]."""
    from matplotlib.transforms import offset_copy

    ax = legend.ax
    if not ax.get_legend_handles_labels()[0]:
        return 0.0
    entries = _legend_entries(ax)
    count = len(entries[0])
    above = offset_copy(ax.transAxes, fig=ax.get_figure(root=True), y=_ABOVE_GAP, units="points")

    def drawn(columns):
        box = ax.legend(*entries, fontsize=legend.fontsize, title=legend.title, title_fontsize=legend.fontsize,
                        loc="lower center", bbox_to_anchor=(0.5, 1.0), bbox_transform=above, ncols=columns)
        return box.get_window_extent(renderer)

    columns = next((c for c in range(min(count, 6), 0, -1) if drawn(c).width <= width), 1)
    even = -(-count // -(-count // columns))          # as few columns as give that many rows
    extent = drawn(even)
    if extent.width > width:
        extent = drawn(columns)
    points = (extent.y1 - ax.bbox.y1) * 72.0 / ax.get_figure(root=True).dpi     # its top over the panel's
    if ax.get_title():
        ax.set_title(ax.get_title(), fontsize=ax.title.get_fontsize(), pad=_TITLE_PAD + points)
    return points / 72.0


#: points between a panel and the legend above it; matplotlib's pad of a title over its axes
_ABOVE_GAP, _TITLE_PAD = 3.0, 6.0


def _show_frf_overlaps(fig, axes, result, placed, above):
    """Model curves of ``axes`` lying on each other (a symmetric machine's mounts: the same
    force in two of them) drawn there in turn, each legend naming the curve it equals
    (:func:`_show_overlaps`), the legends of ``placed`` (``[(figure or block, [_Legend, ...]),
    ...]``; ``above``: their heights above the panels) placed again
    (:func:`_notes_and_legends`); found on the layout of the figure's first drawing
    (:func:`._overlap.at_first_layout`: no layout of their own)."""
    from functools import partial

    from ._overlap import at_first_layout

    at_first_layout(fig, partial(_notes_and_legends, fig, axes, (result.frequencies_hz, "hz"), placed, above))


def _draw_frfs(mag, phase, result, measured, pairs, label, scale=None, first=0, samples=True):
    """Each pair's model line (and measured dots, same colour) on ``mag`` (log) and ``phase``
    (``scale(o, i)``: the factor on the SI FRF, default 1; ``first``: the number of the first
    pair's style, so that a phase panel shared with another magnitude panel's curves gives
    every curve a style of its own; ``samples``: without measured dots, the computed
    frequencies dotted where sparse on a logarithmic axis, :func:`frequency_label`). An FRF below :data:`_DYNAMIC_RANGE`
    of the largest everywhere (zero but for round-off, by symmetry) is named so in the legend
    and has no phase drawn (the phase of round-off is noise)."""
    largest = max((float(np.max(np.abs(result.H[result.outputs.index(o), result.inputs.index(i)])))
                   for o, i in pairs), default=0.0)
    cut = 0
    sparse = _sparse_on_log(result.frequencies_hz) if measured is None and samples else None
    for n, (o, i) in enumerate(pairs, start=first):
        colour = f"C{n % 10}"
        style = "-" if n < 10 else "--"
        factor = 1.0 if scale is None or scale.units == "si" else scale(o, i)
        h = result.H[result.outputs.index(o), result.inputs.index(i)] * factor
        name, phase_values = label(o, i), np.degrees(np.angle(h))
        if np.max(np.abs(h)) < _DYNAMIC_RANGE * largest * abs(factor):
            name, phase_values = f"{name} (round-off: below 1e-6 of the largest)", np.full(h.shape, np.nan)
        if measured is not None and o in measured.outputs and i in measured.inputs:
            hm = measured.H[measured.outputs.index(o), measured.inputs.index(i)] * factor
            mag.semilogy(measured.frequencies_hz, np.abs(hm), ".", ms=2.5, color=colour, alpha=0.5)
            phase.plot(measured.frequencies_hz, _phase_beside(np.degrees(np.angle(hm)), measured.frequencies_hz,
                                                               phase_values, result.frequencies_hz),
                       ".", ms=2.5, color=colour, alpha=0.5)
        mag.semilogy(result.frequencies_hz, np.abs(h), color=colour, ls=style, label=name,
                     **({} if sparse is None else {"marker": ".", "ms": 3, "markevery": sparse}))
        phase.plot(*_broken_at_wraps(result.frequencies_hz, phase_values), color=colour, ls=style, lw=0.9)
        at, peak = result.cut_peaks(o, i)
        # the line taken up to each resonance it cuts, as the unbalance curves: the diamond
        # stands on the curve, not above a chord 3.3 times lower (motor_pump's 529 Hz mode)
        _draw_peak_tops(mag, result.frequencies_hz, np.abs(h), (at, np.abs(peak)), 1.0, abs(factor), colour, style)
        cut += _mark_cut(mag, at, np.abs(peak) * abs(factor), colour)
    if cut:
        _cut_legend(mag, "peak between computed frequencies")
    elif result.engine == "direct" and result.resonances_hz is None and pairs:
        # the direct engine (loss factors, Maxwell branches, a large model) has no roots: say so
        from matplotlib.lines import Line2D

        mag._legend_extra = [Line2D([], [], linestyle="none", label=_NOT_LOOKED_FOR)]
    _limit_range(mag)
    _frequency_scale(mag, result.frequencies_hz)


#: the legend's word on an FRF of the direct engine: no roots, so no cut peak is looked for
_NOT_LOOKED_FOR = "peaks between computed frequencies\nnot looked for (direct engine: no roots)"
#: the mark of a resonance's peak that the line between two computed frequencies cuts
_CUT_PEAK = {"marker": "D", "ms": 4.5, "mfc": "none", "mew": 1.0, "color": "0.2"}


def _mark_cut(mag, x, height, colour) -> int:
    """An open diamond in the curve's colour at each ``(x, height)`` (as drawn: axis units) of a
    peak that the curve's line cuts (:meth:`~rotordyn_modal.analysis.frf.FRFResult.cut_peaks`,
    :meth:`~rotordyn_modal.analysis.unbalance.UnbalanceResult.cut_peaks`: more than 3 dB above
    both computed points around it), on a dense-looking stretch as on a sparse one; returns
    how many."""
    if len(x):
        mag.plot(x, height, linestyle="none", gid="cut-peak", label="_cut-peak", **dict(_CUT_PEAK, color=colour))
    return len(x)


def _cut_legend(mag, label) -> None:
    """One legend entry of ``mag`` (no line of the axes) saying what the diamonds are."""
    from matplotlib.lines import Line2D

    mag._legend_extra = [Line2D([], [], linestyle="none", label=label, **_CUT_PEAK)]


#: on a logarithmic frequency axis, computed frequencies farther apart than this ratio (30 per
#: decade: about 10 pixels of a figure's decade) are dotted: the line between them is a chord,
#: which may cut a resonance's peak (an evenly spaced grid over decades: the mounts' modes at
#: 5-15 Hz drawn through points 2.5 Hz apart)
_SPARSE_RATIO = 10.0 ** (1.0 / 30.0)


def frequency_label(frequencies, measured=None) -> str:
    """The frequency axis' label: where the model lines are dotted (:func:`_sparse_on_log`,
    no measured dots), it says what the dots are (in the label, where the legend's size and the
    panels' layout stay as they are)."""
    sparse = None if measured is not None else _sparse_on_log(frequencies)
    if sparse is None:
        return "Frequency [Hz]"
    top = np.asarray(frequencies, float)[sparse].max()
    return f"Frequency [Hz]  (dots: the frequencies computed, sparse up to {top:.3g} Hz: chords between them)"


def _sparse_on_log(frequencies):
    """Which of ``frequencies`` [Hz] to dot, shape (F,) bool: those next to a neighbour more than
    :data:`_SPARSE_RATIO` times away, where the axis is logarithmic (:func:`_frequency_scale`);
    None where none is (or the axis is linear)."""
    from .campbell import LOG_SPAN, segment_ends

    f = np.asarray(frequencies, float)
    if f.size < 2 or not np.all(np.isfinite(f)) or f.min() <= 0 or f.max() <= LOG_SPAN * f.min():
        return None
    low, high = np.minimum(f[:-1], f[1:]), np.maximum(f[:-1], f[1:])
    apart = high > _SPARSE_RATIO * low
    if not apart.any():
        return None
    return segment_ends(apart)


#: degrees a measured phase may stand beyond +-180 to lie beside its model line (the phase
#: panel's limits leave this room)
_PHASE_MARGIN = 30.0


def _broken_at_wraps(frequencies, degrees):
    """``(frequencies, degrees)`` with a NaN point between neighbours whose phases [deg] differ by
    more than 180 (the phase wraps from -180 to 180 there): the line is broken at a wrap
    instead of running across the panel, where it read as a curve of its own."""
    degrees = np.asarray(degrees, float)
    wraps = np.nonzero(np.abs(np.diff(degrees)) > 180.0)[0] + 1
    return (np.insert(np.asarray(frequencies, float), wraps, np.nan), np.insert(degrees, wraps, np.nan))


def _phase_beside(degrees, frequencies, model_degrees, model_frequencies):
    """Measured phases [deg] each turned by whole turns to lie within 180 deg of the model's
    phase at the nearest model frequency (as drawn where that is NaN: round-off): a measurement
    that agrees with the model stays on its line where the phase is near +-180 deg, where
    the noise otherwise throws half the dots to the panel's other edge."""
    model = np.asarray(model_degrees, float)
    f = np.asarray(model_frequencies, float)
    if not np.isfinite(model).any() or f.size == 0:
        return degrees
    order = np.argsort(f)
    nearest = order[np.clip(np.searchsorted(f[order], frequencies), 0, len(f) - 1)]
    before = order[np.clip(np.searchsorted(f[order], frequencies) - 1, 0, len(f) - 1)]
    nearest = np.where(np.abs(f[before] - frequencies) < np.abs(f[nearest] - frequencies), before, nearest)
    reference = model[nearest]
    turns = np.where(np.isfinite(reference), np.round((reference - degrees) / 360.0), 0.0)
    turned = degrees + 360.0 * turns
    # a dot far from its line (a measured resonance off the model's) keeps its place in the panel
    return np.where(np.abs(turned) <= 180.0 + _PHASE_MARGIN, turned, degrees)


def _frequency_scale(ax, frequencies):
    """A logarithmic frequency axis (shared by the phase panel) when the frequencies [Hz], all
    > 0, span more than :data:`~rotordyn_modal.plotting.campbell.LOG_SPAN` times (mount modes at
    5 Hz beside bearing modes at 1 kHz), else linear; its ticks read as plain numbers (1, 10,
    100), and between the decades too where it spans less than two (1-60 Hz read '10^0, 10^1'
    only)."""
    from ._style import plain_log_ticks
    from .campbell import LOG_SPAN

    f = np.asarray(frequencies, float)
    f = f[np.isfinite(f)]
    if f.size and f.min() > 0 and f.max() > LOG_SPAN * f.min():
        ax.set_xscale("log")
        plain_log_ticks(ax.xaxis)


def plot_overlay(models, measured, title: str | None = None, units: str = "si", input_kinds=None):
    """Model over measurement at several speeds: one magnitude and phase panel per speed.

    In each speed's panels every FRF has a style of its own (as :func:`plot_frf`), named in that
    panel's legend, its measured dots in its colour; the panels stand in up to two columns.

    Parameters
    ----------
    models, measured : list of FRFResult
        Paired by position (same speeds, names and frequencies).
    title : str, optional
    units : {'si', 'us'}
        Unit system of the magnitudes, as :func:`plot_frf`'s.
    input_kinds : dict, optional
        ``{input name: 'force' or 'moment'}``, as :func:`plot_frf`'s.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, blocks = _blocks(len(models), (8.0, 5.2))
    scale = _FrfScale(models[0].quantity, units, input_kinds)
    pairs = [(o, i) for o in models[0].outputs for i in models[0].inputs]
    unit = _UNITS.get(models[0].quantity, "") if units == "si" else scale.label(pairs)
    for block, model, meas in zip(blocks, models, measured):
        mag, phase = block.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
        _draw_frfs(mag, phase, model, meas, pairs, lambda o, i: f"{o} / {i}", scale, samples=False)
        mag.set_ylabel(f"|H| [{unit}]")
        mag.set_title(f"at {rpm_text(model.speed * 30 / np.pi)} rpm", fontsize="medium")
        mag.legend(*_legend_entries(mag), fontsize="x-small", title="model (line), measured (dots)",
                   title_fontsize="x-small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
        phase.set_yticks([-180, -90, 0, 90, 180])
        phase.set_ylabel("Phase [deg]")
        phase.set_xlabel("Frequency [Hz]")
    fig.suptitle(title or "Model versus measurement")
    return fig


def plot_unbalance(result, outputs=None, speed_unit: str = "rpm", peaks=None, title: str | None = None,
                   groups=None, forces: str | None = None, amplitude: str = "peak", checks=None,
                   units: str = "si"):
    """Amplitude (log, 0-peak, peak-to-peak or RMS) and phase of each source's harmonic against
    speed, one pair of panels per group of sensors, and one amplitude panel per kind of force asked.

    Each amplitude panel's legend stands beside it, or, where one of them would take more than
    :data:`_LEGEND_SHARE` of the width (long names, notes of curves lying on each other), each
    above its panel in columns, the figure taller by their height (:func:`_place_legends`).

    Parameters
    ----------
    result : UnbalanceResult
    outputs : list of str, optional
        Sensors to draw (default all).
    speed_unit : {'rpm', 'rad/s', 'hz'}
    peaks : pandas.DataFrame, optional
        ``result.peaks(...)``: the peaks that matter (amplification factor at least
        :data:`_AF_MARKED`, amplitude at least :data:`_PEAK_SHARE` of their curve's largest)
        are marked, the largest of them labelled with their amplification factor (and
        separation margin when known), labels apart from each other inside the axes, where
        no curve runs, each joined to its peak by a leader line.
    groups : dict, optional
        Panel title of each sensor (``{'probe-DE-x': 'shaft relative to housing'}``): sensors
        with one title share a panel. Default: the probe pairs' sensors in one panel, the
        other sensors in another.
    forces : {None, 'suspensions', 'bearings', 'rotors', 'all'}
        Adds one panel per kind of force: the amplitude of each item's force vector
        ``sqrt(|Fx|^2 + |Fy|^2 + |Fz|^2)`` [N] (the moments are in ``to_dataframe``).
    amplitude : {'peak', 'pk-pk', 'rms'}
        Convention of the amplitudes drawn (the axis labels say which).
    checks : UnbalanceChecks, optional
        ``result.checks(...)``: the API 617 probe limit drawn (dashed, over the checked
        speeds) on the panels of its probes (up to :data:`_LIMIT_REACH` times their largest
        curve; further above, arrows on the top edge and named in the legend), and a panel
        of the casing sensors' RMS vibration velocity with the ISO 20816-3 zones A-D as bands.
    units : {'si', 'us'}
        Unit system of the amplitude axes: SI (m, m/s, m/s², N; mm/s RMS for the zones) or US
        customary (mil, in/s, g, lbf; in/s RMS), see docs/units.md.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from ._labels import laid_out_renderer
    from ._style import speed_label, speed_scale

    from ..unbalance_standards import amplitude_factor, amplitude_label

    factor, words = amplitude_factor(amplitude), amplitude_label(amplitude)
    panels = _sensor_panels(result, outputs, groups)
    force_panels = _force_panels(result, forces)
    zones = checks is not None and checks.zone_boundaries is not None and len(checks.casing) > 0
    ratios = [r for _ in panels for r in (2, 1)] + [2] * len(force_panels) + [2] * zones
    fig, axes = plt.subplots(len(ratios), 1, sharex=True, figsize=(9.5, 1.9 * sum(ratios) / 1.5 + 0.6),
                             layout="constrained", gridspec_kw={"height_ratios": ratios}, squeeze=False)
    axes = list(axes[:, 0])
    x = result.speeds * speed_scale(speed_unit)
    marked = [_sensor_pair(axes[2 * n], axes[2 * n + 1], result, name, rows, x, (factor, words), peaks, checks,
                           speed_unit, units) for n, (name, rows) in enumerate(panels)]
    for ax, (kind, names, values) in zip(axes[2 * len(panels):], force_panels):
        _draw_force_panel(ax, result, names, values, x, factor, words, units)
        ax.set_title(f"Force of the {kind} (vector amplitude, |F|)", fontsize="medium")
    if zones:
        _draw_zone_panel(axes[-1], checks, x, units)
    axes[-1].set_xlabel(speed_label(speed_unit))
    fig.suptitle(title or "Unbalance response")
    legends = [_Legend(ax) for ax in axes[0:2 * len(panels):2] + axes[2 * len(panels):len(axes) - zones]]
    legends += [_Legend(axes[-1], beside=1.04)] if zones else []     # clear of the zones' letters
    height = fig.get_figheight()
    above = _place_legends([(fig, legends)])
    fig.set_figheight(height + above[0])                  # the panels keep their height
    widened = _notes_and_legends(fig, axes[:2 * len(panels) + len(force_panels)], (x, speed_unit),
                                 [(fig, legends)], above, lambda heights: fig.set_figheight(height + heights[0]))
    if peaks is not None and marked:
        # the peaks' labels placed on the axes as drawn
        renderer = laid_out_renderer(fig) if widened else fig.canvas.get_renderer()
        for ax, chosen, top in marked:
            _label_peaks(ax, chosen, renderer, top)
    return fig


def _sensor_pair(mag, phase, result, name, rows, x, convention, peaks, checks, speed_unit, units="si"):
    """One group of sensors' amplitude (``convention``: factor on 0-peak, its words) and phase
    panels, with the probe limits of ``checks``; returns ``(mag, peaks to label, largest value drawn)``."""
    from ._style import plain_log_ticks, readable_scale, speed_scale

    convention_factor, words = convention
    largest = convention_factor * float(np.nanmax(result.amplitude[rows], initial=0.0))
    scale, unit = readable_scale(result.quantity, largest, units)
    factor = convention_factor * scale
    colours = _draw_sensor_panel(mag, phase, result, rows, x, factor, speed_scale(speed_unit))
    plain_log_ticks(mag.yaxis)
    top, above = _drawn_top(mag), []
    if checks is not None:
        top, above = _draw_probe_limits(mag, checks, [result.outputs[i] for i in rows], x, factor, units, top,
                                        convention=convention)
    _fit_top(mag, top, _HEADROOM if peaks is None else _LABEL_HEADROOMS[0])
    _mark_limits_above(mag, above)
    mag.set_ylabel(f"Amplitude, {words} [{unit}]")
    mag.set_title(name, fontsize="medium")
    if peaks is None:
        return mag, [], top
    chosen = _marked_peaks(peaks, result, rows, colours, speed_scale(speed_unit) * np.pi / 30, speed_unit, factor,
                           top)
    _mark_unbounded(mag, chosen, top)
    return mag, chosen, top


def _mark_unbounded(ax, chosen, top):
    """A dotted line up to ``top`` (the largest value drawn) at the speed of each unbounded peak of
    ``chosen`` (:func:`_marked_peaks`': a :class:`_Peak` whose ``unbounded`` is set from the
    peaks table's amplitude ``inf``; its label, which says so, stands at its top): the swept
    line's peak stands beside it, at a swept speed."""
    low = ax.get_ylim()[0]
    for peak in chosen:
        x, y, _, colour, _ = peak
        if getattr(peak, "unbounded", False) and np.isfinite(top) and top > low:
            ax.plot([x, x], [low, y], color=colour, ls=":", lw=1.2, label="_unbounded")


class _Peak(tuple):
    """A peak to mark, ``(x, amplitude as drawn, text, colour, source)``, and whether the
    analysis found it unbounded (``unbounded``: its amplitude ``inf``, an undamped mode at its
    critical speed), read from the data rather than from the words of its label."""

    def __new__(cls, items, unbounded=False):
        peak = super().__new__(cls, items)
        peak.unbounded = bool(unbounded)
        return peak


#: the second line of an unbounded peak's label (an undamped mode's: amplitude inf)
_UNBOUNDED_LINE = "response unbounded"


def _fit_top(ax, top, share):
    """End the log axis ``ax`` above ``top`` (the largest value drawn) by ``share`` of its height."""
    low = ax.get_ylim()[0]
    if np.isfinite(top) and top > low > 0:
        ax.set_ylim(low, top * (top / low) ** (share / (1 - share)))


def _drawn_top(ax) -> float:
    """The largest value of the curves drawn in ``ax`` (0 when none)."""
    values = [np.nanmax(np.asarray(line.get_ydata(), float), initial=0.0) for line in ax.get_lines()
              if np.any(np.isfinite(np.asarray(line.get_ydata(), float)))]
    return max(values, default=0.0)


#: API 684: a peak with an amplification factor below 2.5 is critically damped (no margin required)
_AF_MARKED = 2.5
#: peaks below this share of their own curve's largest amplitude are not marked
_PEAK_SHARE = 0.05
#: share of the amplitude axis' height above the largest value drawn: without peak labels, and
#: with them the least that labels as many peaks as the largest of these would (room for the
#: labels above the highest peaks; the others find room beside or below theirs)
_HEADROOM, _LABEL_HEADROOMS = 0.04, (0.12, 0.2, 0.3)
#: a probe limit at most this factor above the largest curve is drawn as a line (the axis reaching
#: it); one further above is marked at the axis' top edge and named in the legend, the axis
#: fitting the curves
_LIMIT_REACH = 10.0
#: at most this many peaks are labelled per panel, the largest
_LABELLED = 6
#: peaks of one source closer than this share of the sweep are one peak (seen by several sensors)
_SAME_PEAK = 0.01


def _sensor_panels(result, outputs, groups):
    """``[(title, [sensor index, ...]), ...]`` in the order of the result's outputs."""
    in_pairs = {name for pair in result.orbit_pairs for name in pair}
    panels = {}
    for i, o in enumerate(result.outputs):
        if outputs is not None and o not in outputs:
            continue
        if groups is not None:
            name = groups.get(o, "sensors")
        else:
            name = "probe pairs" if o in in_pairs else ("other sensors" if in_pairs else "sensors")
        panels.setdefault(name, []).append(i)
    return list(panels.items())


def _draw_sensor_panel(mag, phase, result, rows, x, factor=1.0, to_unit=1.0):
    """Each sensor and source: amplitude (0-peak times ``factor``) on a log axis, phase, over
    ``x`` (the speeds times ``to_unit``, the axis' unit per rad/s), the peaks the lines cut
    marked; returns the colour of each (i, j)."""
    colours, cut, silent = {}, 0, {}
    styles = ["-", "--", ":", "-."]
    for m, i in enumerate(rows):
        for j, s in enumerate(result.sources):
            colour, style = f"C{m % 10}", styles[j % len(styles)]
            colours[i, j] = colour
            if not np.any(result.amplitude[i, j] > 0):      # no response at all: no curve, no phase
                silent.setdefault(j, []).append(result.outputs[i])
                continue
            amplitude = np.where(result.amplitude[i, j] > 0, result.amplitude[i, j] * factor, np.nan)
            mag.semilogy(x, amplitude, color=colour, ls=style, label=f"{result.outputs[i]}: 1X {s}")
            # broken where the phase wraps: a line from -180 to 180 deg read as a curve of its own
            phase.plot(*_broken_at_wraps(x, result.phase_deg[i, j]), color=colour, ls=style, lw=0.9)
            _draw_peak_tops(mag, x, amplitude, _exact_peak_points(result, i, j), to_unit, factor, colour, style)
            at, response, _ = result.cut_peaks(result.outputs[i], s)
            cut += _mark_cut(mag, at * to_unit, np.abs(response) * factor, colour)
    if cut:
        _cut_legend(mag, "peak between swept speeds\n(near a damped critical speed)")
    elif getattr(result, "cut_peak_note", ""):        # say why no peak between swept speeds is marked
        from matplotlib.lines import Line2D

        mag._legend_extra = [Line2D([], [], linestyle="none", label=f"peaks between swept speeds\n{result.cut_peak_note}")]
    if silent:
        mag._legend_extra = getattr(mag, "_legend_extra", []) + _silent_entries(result, rows, silent)
    _limit_range(mag)
    phase.set_yticks([-180, -90, 0, 90, 180])
    phase.set_ylabel("Phase [deg]")
    return colours


def _exact_peak_points(result, i, j):
    """The analysis' peaks of curve ``(i, j)`` on the exact response, swept peaks
    (:attr:`~rotordyn_modal.analysis.unbalance.UnbalanceResult.peak_speeds`) and peaks between
    swept speeds (:meth:`~rotordyn_modal.analysis.unbalance.UnbalanceResult.cut_peaks`), finite
    ones only: ``(speeds [rad/s], amplitudes 0-peak)``, shapes (K,), (K,); none where not computed."""
    speeds, values = [], []
    if result.peak_speeds is not None and result.peak_swept_speeds is not None:
        known = np.isfinite(result.peak_swept_speeds[i, j]) & np.isfinite(result.peak_speeds[i, j])
        speeds.append(result.peak_speeds[i, j, known])
        values.append(np.abs(result.peak_response[i, j, known]))
    at, response, _ = result.cut_peaks(result.outputs[i], result.sources[j])
    speeds.append(at)
    values.append(np.abs(response))
    speeds, values = np.concatenate(speeds), np.concatenate(values)
    keep = np.isfinite(speeds) & np.isfinite(values) & (values > 0)
    return speeds[keep], values[keep]


def _draw_peak_tops(mag, x, drawn, points, to_unit, factor, colour, style):
    """The curve ``drawn`` (over ``x``, the axis' unit) taken up to each of its exact peaks
    ``points`` (:func:`_exact_peak_points`: the speeds [rad/s] times ``to_unit``, amplitudes
    times ``factor``) from the two swept speeds around it, in the curve's colour and style: a
    peak marker stands on the curve it names. The swept line alone cuts a sharp peak
    (fan_on_bearings' AF 263 motor peak at 3587 rpm, 7.8 um, drawn at 2 um at 181 speeds)."""
    speeds, values = points
    order = np.argsort(x)
    xs, ys = np.asarray(x, float)[order], np.asarray(drawn, float)[order]
    vx, vy = [], []
    for at, value in zip(speeds * to_unit, values * factor):
        k = int(np.searchsorted(xs, at))
        if k == 0 or k == len(xs):                 # outside the sweep: no swept speed on one side
            continue
        vx += [xs[k - 1], at, xs[k], np.nan]
        vy += [ys[k - 1], value, ys[k], np.nan]
    if vx:
        mag.plot(vx, vy, color=colour, ls=style, gid="peak-top", label="_peak-top")


def _silent_entries(result, rows, silent):
    """Legend entries (no line) naming the curves not drawn because the source gives no response
    at any speed (``silent``: source index -> the sensors): a rotor that does not turn (speed
    ratio 0: its 1X frequency 0 at every speed) or an unbalance no sensor sees."""
    from matplotlib.lines import Line2D

    entries = []
    for j, sensors in silent.items():
        still = np.all(np.asarray(result.frequencies_hz[j]) == 0)
        who = "" if len(sensors) == len(rows) else ", ".join(sensors) + ": "
        why = f" ({result.sources[j]} does not turn)" if still else ""
        entries.append(Line2D([], [], linestyle="none", label=f"{who}1X {result.sources[j]}: zero at every "
                                                              f"speed{why}, not drawn"))
    return entries


def _show_overlaps(axes, x, speed_unit):
    """Curves of ``axes`` (laid out) lying on each other drawn there in turn
    (:func:`._overlap.show_overlaps`), each curve's label naming the earlier curve it lies on
    ("(= probe-x)", "(= probe-x above 1520 rpm)"); returns whether a label in a legend changed
    (the caller places the legends again)."""
    from ._overlap import show_overlaps

    changed = False
    for ax in axes:
        named = any(not line.get_label().startswith("_") for line in ax.get_lines())   # a legend's panel
        curves = [line for line in ax.get_lines() if not (named and line.get_label().startswith("_"))
                  and line.get_gid() not in ("cut-peak", "peak-top")]
        names = {line: line.get_label() for line in curves}
        notes = {}
        for overlap in show_overlaps(ax, curves):
            notes.setdefault(overlap.line, []).append(overlap)
        notes = {line: found for line, found in notes.items() if _noted(line, found)}
        for line, overlaps in notes.items():
            line.set_label(f"{names[line]} ({_equal_note(names[line], overlaps, names, x, speed_unit)})")
        changed = changed or bool(notes and named)
    return changed


def _equal_note(name, overlaps, names, x, speed_unit):
    """"= other" (the earlier curve the line lies on longest), with the speeds where it does
    when that is one range but not all of the line's drawn range ("above 960 rpm"), else
    "in parts"."""
    lengths = {}
    for o in overlaps:
        lengths[o.other] = lengths.get(o.other, 0) + o.stop - o.start
    other = max(lengths, key=lambda line: (lengths[line], -list(names).index(line)))   # the earliest of equals
    twin = _equal_everywhere(overlaps[0].line, names)
    if twin is not None:
        return _equal_text(name, names[twin])
    text = _equal_text(name, names[other])
    ranges = _merged([(o.start, o.stop) for o in overlaps if o.other is other])
    drawn = np.flatnonzero(np.isfinite(np.asarray(overlaps[0].line.get_ydata(), float)))
    if len(ranges) == 1 and ranges[0][0] <= drawn[0] and ranges[0][1] >= drawn[-1]:
        return text
    if len(ranges) > 1:
        return f"{text} in parts"
    unit = {"rpm": " rpm", "rad/s": " rad/s", "hz": " Hz"}[speed_unit]
    (start, stop), = ranges
    if start <= drawn[0]:
        return f"{text} below {_speed_text(x[stop])}{unit}"
    if stop >= drawn[-1]:
        return f"{text} above {_speed_text(x[start])}{unit}"
    return f"{text} {_speed_text(x[start])}–{_speed_text(x[stop])}{unit}"


def _equal_text(name, other):
    """"= other", the other's output only where both are excited by the same source."""
    output, _, source = other.partition(": 1X ")
    same = source and name.partition(": 1X ")[2] == source
    return f"= {output if same else other}"


def _equal_everywhere(line, names):
    """The earliest curve of ``names`` before ``line`` equal to it within 1 % wherever either
    is drawn (the same sensor signal twice: an isotropic rotor's probes, a symmetric machine's
    mounts), else None."""
    y = np.asarray(line.get_ydata(), float)
    for earlier in names:
        if earlier is line:
            return None
        e = np.asarray(earlier.get_ydata(), float)
        if e.shape == y.shape and np.allclose(y, e, rtol=1e-2, atol=0.0, equal_nan=True):
            return earlier
    return None


#: a curve's legend names the curve it lies on when that is at least this share of its drawn
#: points (shorter stretches show on the figure only), with the speeds when they are one range
_NOTED_SHARE = 0.2


def _noted(line, overlaps) -> bool:
    """Whether ``line`` lies on earlier curves over :data:`_NOTED_SHARE` of its drawn points."""
    drawn = np.count_nonzero(np.isfinite(np.asarray(line.get_ydata(), float)))
    stretches = {(o.start, o.stop) for o in overlaps}
    return sum(stop - start + 1 for start, stop in stretches) >= _NOTED_SHARE * drawn


def _merged(ranges):
    """Index ranges ``[(start, stop), ...]`` joined where they touch, in order."""
    merged = []
    for start, stop in sorted(ranges):
        if merged and start <= merged[-1][1] + 1:
            merged[-1] = (merged[-1][0], max(stop, merged[-1][1]))
        else:
            merged.append((start, stop))
    return merged


def _speed_text(value):
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


def _force_panels(result, forces):
    """``[(kind, item names, complex values (items, 6, n_sources, N)), ...]`` of the asked forces."""
    if forces is None:
        return []
    names, values = result._force_rows(forces)
    values = np.concatenate(values) if values else np.zeros((0, len(result.sources), len(result.speeds)))
    components = len({n.rsplit(":", 1)[1] for n in names}) or 1          # Fx ... Mz
    items = [n.rsplit(":", 1)[0] for n in names[::components]]
    values = values.reshape(len(items), components, *values.shape[1:])
    rigid = len(result.rigid_rotor_names) if forces == "bearings" else 0
    bearings = (len(result.bearing_names) if result.bearing_point_forces is not None else 0) + rigid
    counts = {"suspensions": [("suspensions", len(result.suspension_names))],
              "bearings": [("bearings", bearings)], "rotors": [("rotors on the stator", len(result.rotor_names))],
              "all": [("suspensions", len(result.suspension_names)), ("bearings", bearings),
                      ("rotors on the stator", len(result.rotor_names))]}[forces]
    panels, start = [], 0
    for kind, count in counts:
        if count:
            panels.append((kind, items[start:start + count], values[start:start + count]))
        start += count
    return panels


def _draw_probe_limits(ax, checks, names, x, factor, units="si", top=np.inf, convention=(2.0, "peak-to-peak")):
    """The API 617 limit of the panel's probes (peak-to-peak, drawn in the panel's convention)
    over the checked speeds: one dashed line per distinct limit up to :data:`_LIMIT_REACH` times
    the curves' largest value ``top``; returns ``(top, [(speeds, label), ...])``: the largest
    value drawn, and the limits further above (for :func:`_mark_limits_above`)."""
    limits = sorted({float(limit) for name, limit in zip(checks.probes, checks.probe_limits)
                     if name in names and np.isfinite(limit)})
    span = np.where(checks.checked, 1.0, np.nan)
    above, reach = [], top * _LIMIT_REACH if top > 0 else np.inf
    for limit in limits:
        label = (f"API 617 probe limit {limit * 1e6:.1f} µm pk-pk" if units == "si" else
                 f"API 617 probe limit {limit * unit_scale('displacement', units)[0]:.2f} mil pk-pk")
        if convention[0] != 2.0:     # drawn in the panel's convention: its number first, the rule's after it
            label = _limit_in_convention(label, limit * convention[0] / 2, convention[1], units)
        if limit * factor / 2 > reach:
            above.append((x[checks.checked], f"{label} (above the axis)"))
            continue
        ax.plot(x, limit * factor / 2 * span, color="k", ls="--", lw=1.2, label=label)
        top = max(top, limit * factor / 2)
    return top, above


def _limit_in_convention(label, drawn, words, units):
    """``label`` of a pk-pk limit drawn as ``drawn`` [m] in the convention ``words`` ('0-peak',
    'RMS'): ``API 617 probe limit 8.98 µm RMS (25.4 µm pk-pk)``."""
    scale, unit = (1e6, "µm") if units == "si" else unit_scale("displacement", units)
    rule = label.removeprefix("API 617 probe limit ")
    return f"API 617 probe limit {drawn * scale:.3g} {unit} {words} ({rule})"


def _mark_limits_above(ax, above):
    """Each limit above the axis: upward arrows on the top edge over its checked speeds, named
    in the legend."""
    for speeds, label in above:
        ax.plot([], [], color="k", ls="--", lw=1.2, marker="^", ms=6, label=label)      # its legend entry
        for speed in speeds[[0, -1]] if len(speeds) else []:
            ax.annotate("", (speed, 1.0), xycoords=ax.get_xaxis_transform(), xytext=(0, -18),
                        textcoords="offset points", arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.2})


#: colours of the ISO 20816-3 zones A, B, C, D
_ZONE_COLOURS = ("#d9f0d3", "#fff7bc", "#fdd0a2", "#fcbba1")


def _draw_zone_panel(ax, checks, x, units="si"):
    """The casing sensors' RMS vibration velocity [mm/s; in/s in US units] over the ISO 20816-3
    zone bands."""
    from ._style import plain_log_ticks

    styles = ["-", "--", ":", "-."]
    scale, unit = (1e3, "mm/s") if units == "si" else unit_scale("velocity", units)
    for m, name in enumerate(checks.casing):
        for c, case in enumerate(checks.cases):
            ax.plot(x, checks.casing_velocity_rms[m, c] * scale, color=f"C{m % 10}", ls=styles[c % len(styles)],
                    label=f"{name} ({case})" if case else name)
    bounds = [b * scale for b in checks.zone_boundaries]
    top = max(bounds[2] * 3, float(np.nanmax(checks.casing_velocity_rms, initial=0)) * 2 * scale)
    checked = checks.zone_checked          # the speeds the zones judge (the operating range, where given)
    largest = np.nanmax(np.where(checked, checks.casing_velocity_rms, np.nan), axis=-1, initial=0) * scale
    shown = largest[largest > 0]             # each curve's largest checked value stays above the bottom
    bottom = max(min(bounds[0] / 30, 0.5 * float(shown.min()) if shown.size else np.inf), top * 1e-5)
    edges = (bottom, *bounds, top)
    for zone, (low, high, colour) in enumerate(zip(edges[:-1], edges[1:], _ZONE_COLOURS)):
        ax.axhspan(low, high, color=colour, zorder=0, lw=0)
        ax.text(1.0, np.sqrt(low * high), " " + "ABCD"[zone], transform=ax.get_yaxis_transform(),
                va="center", ha="left", fontsize="small", clip_on=False)
    ax.set_yscale("log")
    plain_log_ticks(ax.yaxis)
    ax.set_ylim(edges[0], top)
    if checks.mcs is not None or checked.sum() < len(checked):
        ax.plot(x, np.where(checked, edges[0], np.nan), color="k", lw=6, solid_capstyle="butt",
                label="checked speeds")
    ax.set_ylabel(f"Velocity, RMS [{unit}]")
    ax.set_title(f"Casing vibration velocity, ISO 20816-3 zones ({checks.iso_class})", fontsize="medium")


def _draw_force_panel(ax, result, names, values, x, factor=1.0, words="0-peak", units="si"):
    from ._style import plain_log_ticks

    scale, unit = unit_scale("force", units)
    factor = factor * scale
    styles = ["-", "--", ":", "-."]
    for m, name in enumerate(names):
        for j, s in enumerate(result.sources):
            size = result.vector_amplitude(values[m, :3, j])
            ax.semilogy(x, np.where(size > 0, size * factor, np.nan), color=f"C{m % 10}", ls=styles[j % len(styles)],
                        label=f"{name}: 1X {s}")
    _limit_range(ax)
    plain_log_ticks(ax.yaxis)
    ax.set_ylabel(f"Force amplitude, {words} [{unit}]")


def _marked_peaks(peaks, result, rows, colours, rpm_to_unit, unit="rpm", factor=1.0, top=np.nan):
    """Peaks that matter of the panel's sensors, largest (relative to the panel's) first:
    ``[(x, amplitude, text, colour, source), ...]``; an unbounded peak's (amplitude ``inf``: an
    undamped mode, at its critical speed) stands at ``top``, the largest value drawn, its text's
    second line :data:`_UNBOUNDED_LINE`."""
    index = {result.outputs[i]: i for i in rows}
    sources = {s: j for j, s in enumerate(result.sources)}
    chosen = []
    for row in peaks.itertuples(index=False):
        source = getattr(row, "case", row.source)          # a response to API cases: sources are cases
        i, j = index.get(row.output), sources.get(source)
        if i is None or j is None or np.isnan(row.amplification_factor)                 or row.amplification_factor < _AF_MARKED                 or row.amplitude < _PEAK_SHARE * np.nanmax(result.amplitude[i, j]):
            continue
        speed = f"{rpm_text(row.speed_rpm)} rpm" if unit == "rpm" else \
            f"{row.speed_rpm * rpm_to_unit:.4g} {'Hz' if unit == 'hz' else unit}"
        # an undamped mode's peak is unbounded: 'AF inf', as the summary and the AF table write it,
        # at the critical speed where the analysis found it, its amplitude inf
        unbounded = bool(np.isinf(row.amplitude))
        text = f"AF {row.amplification_factor:.1f} at {speed} (1X {source})"
        if unbounded:
            text += "\n" + _UNBOUNDED_LINE
        if np.isfinite(row.separation_margin_pct):
            text += f"\nSM {row.separation_margin_pct:.0f} % (API {row.required_margin_pct:.0f} %)"
        chosen.append(_Peak((row.speed_rpm * rpm_to_unit, top if unbounded else row.amplitude * factor, text,
                             colours[i, j], source), unbounded))
    kept, width = [], np.ptp(result.speeds) * rpm_to_unit * 30 / np.pi
    for peak in sorted(chosen, key=lambda c: -c[1]):    # one label per source's peak seen by several sensors
        if not any(peak[4] == k[4] and abs(peak[0] - k[0]) <= _SAME_PEAK * width for k in kept):
            kept.append(peak)
    return kept[:_LABELLED]


def _label_peaks(ax, chosen, renderer, top=np.nan):
    """Label the chosen peaks (the largest first) where there is room, the axis ending above
    ``top`` (the largest value drawn) by the least of :data:`_LABEL_HEADROOMS` that labels the
    largest peak and, of those, the most; mark those labelled. Where chosen peaks are left out
    (clustered under each other's curves: the report's casing panel of motor_pump_on_mounts
    labelled 1 of its 6), each gets a number at its peak instead and a key inside the axes,
    clear of the curves and labels, gives its text (:func:`_keyed_labels`)."""
    from ._labels import place_point_labels

    def place(share, texts=None):
        _fit_top(ax, top, share)
        return place_point_labels(ax, [(c[0], c[1]) for c in chosen], texts or [c[2] for c in chosen],
                                  [c[3] for c in chosen], renderer=renderer, crossing=False)

    # the largest peak labelled first, then as many as may be: the most labels at a headroom
    # that left the largest out put gear_machine's AF 21.6 at 1400 rpm (25 um, the panel's
    # highest) unlabelled beside three smaller ones
    counts = {}
    for share in _LABEL_HEADROOMS:
        drawn = place(share)
        counts[share] = (any(label.xy == tuple(chosen[0][:2]) for label in drawn), len(drawn))
        if len(drawn) == len(chosen) or not np.isfinite(top):
            break
        for label in drawn:
            label.remove()
    else:
        share = min(counts, key=lambda share: (not counts[share][0], -counts[share][1], share))
        drawn = place(share)
    if len(drawn) < len(chosen):
        drawn = _keyed_labels(ax, chosen, drawn, lambda texts: place(share, texts), renderer)
    for label in drawn:
        ax.plot(*label.xy, "v", color=label.get_color(), mec="k", mew=0.5, ms=5, label="_peak")


#: the font size of the key of the peaks labelled by a number
_KEY_FONT = "x-small"
#: share of its measured width by which the key's box exceeds its widest line (a text measured at
#: one resolution may draw a few per cent wider at another)
_KEY_GROWTH = 0.05


def _keyed_labels(ax, chosen, drawn, place, renderer):
    """``drawn`` (the labels placed, ``chosen`` the peaks) with the peaks left out labelled by a
    number ('1', '2', ...) at the peak instead, and a key inside ``ax`` giving each number's
    text in its colour ('1: AF 6.7 at 578 rpm (1X pump), SM 81 % (API 14 %)'), clear of the
    curves, the labels and their leaders; ``place(texts)`` places every chosen peak's label
    again (the full ones first kept, the numbers small enough to fit where a text did not).
    Where no room takes the key, ``drawn`` as it was. Returns the labels drawn."""
    full = {c[2] for c in chosen if any(label.xy == (c[0], c[1]) for label in drawn)}
    for _ in range(3):                       # a number may take a full label's room: number that one too
        numbered = [c for c in chosen if c[2] not in full]
        tags = {c[2]: str(n) for n, c in enumerate(numbered, start=1)}
        for label in drawn:
            label.remove()
        drawn = place([c[2] if c[2] in full else tags[c[2]] for c in chosen])
        shown = {label.get_text() for label in drawn}
        if full <= shown:
            break
        full &= shown
    # numbered in order of speed, those with no room for their number last, keyed without one
    by_tag = {label.get_text(): label for label in drawn if label.get_text() in tags.values()}
    numbered.sort(key=lambda c: (tags[c[2]] not in by_tag, c[0]))
    texts = []
    for n, c in enumerate(numbered, start=1):
        text = c[2].replace(chr(10), ", ")
        if tags[c[2]] in by_tag:
            texts.append(f"{n}: {text}")
        else:
            texts.append(f"no room at its peak: {text}")
    for n, c in enumerate(numbered, start=1):
        if tags[c[2]] in by_tag:
            by_tag[tags[c[2]]].set_text(str(n))
    colours = [c[3] for c in numbered]
    key = _place_key(ax, texts, colours, drawn, renderer) if texts else []
    if key:
        return drawn
    for label in drawn:                      # no room for the key: the full labels alone
        label.remove()
    return [label for label in place([c[2] for c in chosen]) if label.get_text() in {c[2] for c in chosen}]


def _place_key(ax, texts, colours, labels, renderer) -> list:
    """Lines of ``texts`` (each in its colour) stacked in a box inside ``ax`` where no curve,
    no label of ``labels`` or its leader, no other text or arrow of ``ax`` lies (the first
    free of a grid, top rows first, right to left); returns the texts drawn, or [] where none
    is free."""
    from ._labels import CurveMap, crosses_any, first_free_box, text_size

    fig = ax.figure
    sizes = [text_size(fig, t, _KEY_FONT, renderer) for t in texts]
    pad, gap = 3.0 * fig.dpi / 72.0, 1.0 * fig.dpi / 72.0           # around the key, between its lines
    # room for the text to grow where the report lays the figure out again at its own resolution:
    # fan_on_bearings' key ran 2 px under a label that the key had cleared at 100 dpi
    w = max(s[0] for s in sizes) * (1 + _KEY_GROWTH) + 2 * pad
    h = sum(s[1] + gap for s in sizes) - gap + 2 * pad
    frame = ax.get_window_extent(renderer)
    curves = CurveMap(ax, renderer)
    boxes = [tuple(label.get_window_extent(renderer).extents) for label in labels]
    leaders = [(label.arrow_patch.get_path().vertices[0], ax.transData.transform(label.xy)) for label in labels
               if label.arrow_patch is not None]
    markers = [tuple(ax.transData.transform(label.xy)) for label in labels]
    boxes += [(x - pad, y - pad, x + pad, y + pad) for x, y in markers]
    for other in ax.texts:                  # the axes' other texts and arrows (a probe limit above the axis)
        if other in labels or not other.get_visible():
            continue
        boxes.append(tuple(other.get_window_extent(renderer).extents))
        arrow = getattr(other, "arrow_patch", None)
        if arrow is not None:
            boxes.append(tuple(arrow.get_window_extent(renderer).extents))
    candidates = [(u, v, u + w, v + h) for v in np.linspace(frame.y1 - pad - h, frame.y0 + pad, 16)
                  for u in np.linspace(frame.x1 - pad - w, frame.x0 + pad, 16)]
    box = first_free_box(candidates, boxes, frame=(frame.x0 + pad, frame.y0 + pad, frame.x1 - pad, frame.y1 - pad),
                         allowed=lambda b: curves.free(b) and not crosses_any(leaders, [b]))
    if box is None:
        return []
    # aligned on the box's side nearer the axes' edge: a figure saved at another resolution,
    # laid out again, may draw the text a little wider, towards the axes' middle
    right = (box[0] + box[2]) / 2 > (frame.x0 + frame.x1) / 2
    drawn, y = [], box[3] - pad
    for text, colour, (_, height) in zip(texts, colours, sizes):
        y -= height
        at = ax.transAxes.inverted().transform((box[2] - pad if right else box[0] + pad, y))
        drawn.append(ax.text(*at, text, transform=ax.transAxes, fontsize=_KEY_FONT, color=colour,
                             ha="right" if right else "left", va="bottom", gid="peak-key"))
        y -= gap
    return drawn


#: magnitudes below this fraction of the largest are round-off (an FRF zero by symmetry): not shown
_DYNAMIC_RANGE = 1e-6


def _limit_range(ax):
    """Keep the magnitude axis to six decades below the largest value drawn, or deeper, down
    to :data:`_DEEPEST` of it, where a curve of the model (not round-off) reaches there (a
    genuine antiresonance is drawn whole); where a curve still runs below the axis, mark
    each stretch below it (:func:`_mark_clipped`)."""
    values = [np.nanmax(y) for y in (np.asarray(line.get_ydata(), float) for line in ax.get_lines())
              if np.any(~np.isnan(y))]              # an all-NaN curve (nothing drawn) has no largest value
    if values and np.isfinite(max(values)) and max(values) > 0:
        top = max(values)
        low = ax.get_ylim()[0]
        lowest = [np.nanmin(np.where(y > 0, y, np.nan)) for y in (np.asarray(line.get_ydata(), float)
                  for line in _model_lines(ax)) if np.any(y > 0)]
        floor = min([_DYNAMIC_RANGE * top] + [_MARGIN * v for v in lowest if v >= _DEEPEST * top])
        ax.set_ylim(max(low, floor, _DEEPEST * _MARGIN * top), ax.get_ylim()[1])
        _mark_clipped(ax)


#: the magnitude axis reaches down to this fraction of the largest value at most, for a
#: model curve's antiresonance (eight decades)
_DEEPEST = 1e-8
#: room below a curve's lowest value (a factor on the magnitude)
_MARGIN = 0.7


def _model_lines(ax):
    """The model's curves on a magnitude panel: lines with a line style, not round-off, not marks."""
    return [line for line in ax.get_lines() if line.get_linestyle() not in ("None", "", " ")
            and "(round-off" not in str(line.get_label()) and len(line.get_ydata())]


def _mark_clipped(ax):
    """A caret in the curve's colour on the bottom edge at the lowest point of each stretch of a
    model curve below the axis, and a note in the axes' lower right corner (or the first corner
    whose room no curve runs through, :func:`_clear_corner`), '▼ below the axis (clipped at
    1.5e-07)' (the legend names the curves only)."""
    bottom = ax.get_ylim()[0]
    first = True
    for line in _model_lines(ax):
        x, y = (np.asarray(v, float) for v in line.get_data())
        below = np.isfinite(y) & (y < bottom)
        if not below.any():
            continue
        edges = np.flatnonzero(np.diff(np.concatenate(([0], below.astype(int), [0]))))
        for start, stop in zip(edges[::2], edges[1::2]):
            k = start + int(np.argmin(y[start:stop]))
            ax.plot([x[k]], [bottom], marker=7, linestyle="none", ms=6, color=line.get_color(), clip_on=False,
                    gid="clipped", label="_clipped")
            if first:
                note = ax.text(0.995, 0.01, _clipped_words(bottom, ax.get_ylabel()), transform=ax.transAxes,
                               ha="right", va="bottom", fontsize="xx-small", color="0.25", gid="clipped-note",
                               bbox={"boxstyle": "square,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})
            first = False
    if not first:                                   # the corner chosen at draw time: final scales and layout
        from ._labels import draw_time_layout

        def place(renderer):
            note.set_text(_clipped_words(bottom, ax.get_ylabel()))     # the axis label is set by then
            _clear_corner(ax, note, renderer)

        layout = draw_time_layout(place)
        layout.set_gid("clipped-note-layout")
        ax.add_artist(layout)


def _clipped_words(bottom, label: str) -> str:
    """'▼ below the axis (clipped at 1.7e-04 µm)': the axis's bottom ``bottom`` in the unit the
    axis label ``label`` gives in its last brackets (none where it has none)."""
    import re

    unit = re.search(r"\[([^\[\]]+)\]\s*$", label or "")
    return f"\u25bc below the axis (clipped at {bottom:.1e}{' ' + unit.group(1) if unit else ''})"


#: corners of the axes the clipped-note may stand in, in order of preference: (x, y, ha, va)
_NOTE_CORNERS = ((0.995, 0.01, "right", "bottom"), (0.005, 0.01, "left", "bottom"),
                 (0.995, 0.99, "right", "top"), (0.005, 0.99, "left", "top"))


def _clear_corner(ax, note, renderer):
    """Move the text ``note`` to the first corner of :data:`_NOTE_CORNERS` where its box (grown by
    a third of its height) meets no line drawn in ``ax`` (curves and carets, each marker as its
    square); the lower right corner where none is clear. Measured in axes fractions with
    ``renderer`` (the one drawing: :func:`~._labels.draw_time_layout`)."""
    from matplotlib.path import Path

    from ._labels import set_if_changed

    to_axes = ax.transAxes.inverted()
    paths = []
    for line in ax.get_lines():
        xy = to_axes.transform(line.get_transform().transform(np.column_stack(line.get_data()).astype(float)))
        finite = np.all(np.isfinite(xy), axis=1)
        for run in np.split(np.arange(len(xy)), np.flatnonzero(np.diff(finite.astype(int))) + 1):
            if finite[run[0]] and len(run) > 1:
                paths.append(Path(xy[run]))
        if line.get_marker() not in ("None", "", " ", None):     # each marker as its square
            half = renderer.points_to_pixels(line.get_markersize()) / 2 / np.array([ax.bbox.width, ax.bbox.height])
            for point in xy[finite]:
                low, high = point - half, point + half
                paths.append(Path([low, (high[0], low[1]), high, (low[0], high[1]), low]))
    for x, y, ha, va in _NOTE_CORNERS + _NOTE_CORNERS[:1]:       # none clear: the first
        set_if_changed(note, position=(x, y), horizontalalignment=ha, verticalalignment=va)
        box = note.get_window_extent(renderer).transformed(to_axes)
        grow = box.height / 3
        box = box.from_extents(box.x0 - grow, box.y0 - grow, box.x1 + grow, box.y1 + grow)
        if not any(path.intersects_bbox(box, filled=False) for path in paths):
            return
