"""The undamped critical speed map: critical speeds against bearing stiffness, log-log."""

from __future__ import annotations

import itertools
from contextlib import contextmanager

import numpy as np

from ..units import unit_scale
from ..units import rpm_text
from ._style import fitted_title, new_figure
from ._labels import operating_band, overlaps_any

__all__ = ["plot_ucs_map"]

_MODE_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive",
                 "tab:cyan", "navy", "goldenrod")
#: the modes past the colours' count are told apart by their line: dashed, then dash-dotted (the
#: fan's 11th mode was drawn and listed in the legend exactly as its 1st)
_MODE_LINES = ("-", (0, (5, 2)), (0, (6, 2, 1, 2)))
_BEARING_COLOURS = ("0.15", "tab:red", "0.45", "darkgoldenrod", "teal", "indigo")


def plot_ucs_map(result, title: str | None = None, ax=None, units: str = "si"):
    """Forward critical speeds of the followed modes against the chosen bearings' stiffness.

    Log-log axes: bearing stiffness [N/m] across, speed [rpm] up. Each mode, followed over the
    stiffness along its branch (curves may cross), is a coloured line named at its right end and in
    the legend ("2 pump conical"); where it stops (or starts) being a forward critical speed
    inside the sweep its curve ends at a square, its number beside it. The axis runs on past the sweep's last
    stiffness, where the rigid-support asymptotes (the chosen bearings radially rigid) are
    dotted grey lines. Each bearing's own stiffness over speed is drawn over it (``Kxx`` solid,
    ``Kyy`` dashed; a constant bearing as vertical lines, bearings of equal stiffness named
    together), with its crossings with the modes marked and their speeds written beside them
    (every one, clear of the curves and of each other); the operating speed range is a grey
    band, a single operating speed (``LO = HI``) a dashed line named beside it and in the legend.
    The legend stands below the axes.

    Parameters
    ----------
    result : UcsMap
    title : str, optional
    ax : matplotlib Axes, optional
    units : {'si', 'us'}
        Unit system of the stiffness axis: N/m (SI) or lbf/in (US customary).

    Returns
    -------
    matplotlib.figure.Figure
    """
    own = ax is None
    fig, ax = new_figure(ax, figsize=(8.5, 6.0))
    scale, unit = unit_scale("stiffness", units)
    k = result.stiffness * scale
    rpm, names = _modes(result)
    ax.set_xscale("log")
    ax.set_yscale("log")
    limits = _speed_limits(rpm, result)
    ax.set_ylim(*limits)
    _label_short_speed_axis(ax, limits)
    rigid = _rigid_speeds(result, limits)
    ax.set_xlim(k[0], k[-1] * (_asymptote_margin(k) if rigid.size else 1.0))
    ends = []
    for j in range(rpm.shape[1]):
        colour = _MODE_COLOURS[j % len(_MODE_COLOURS)]
        line = _MODE_LINES[(j // len(_MODE_COLOURS)) % len(_MODE_LINES)]
        ax.plot(k, rpm[:, j], color=colour, linestyle=line, linewidth=1.8, marker=".", markersize=3,
                label=f"{j + 1} {names[j]}")
        ends += _draw_ends(ax, k, rpm[:, j], colour)
    if ends:
        ax.plot([], [], "s", color="0.3", markersize=4, label="a mode starts or stops being a forward crossing")
    inside = _label_right_ends(ax, k, rpm, names, limits)
    _draw_asymptotes(ax, result, rigid, scale)
    _draw_bearings(ax, result, (scale, unit))
    crossings = _draw_crossings(ax, result, limits, scale)
    operating = _draw_operating(ax, result.operating, k[0])
    ax.grid(True, which="both", alpha=0.25)
    ax.set_xlabel(f"Bearing radial stiffness, each chosen bearing [{unit}]")
    # two lines: on one the label was taller than the axes and ran into the title ('[rpm]')
    ax.set_ylabel("Undamped critical speed [rpm]\n(forward, 1X of the reference rotor)")
    ax.set_title(fitted_title(fig, title or (f"Undamped critical speed map: {result.title}" if result.title
                                             else "Undamped critical speed map"), 0.8, "medium"), fontsize="medium")
    _legend_below(ax, own)
    _place_labels(ax, inside + crossings + operating, len(inside), len(crossings))
    return fig


#: the legend's distance [points] below the x axis's label (a figure of its own)
_LEGEND_GAP = 4.0


def _legend_below(ax, own: bool):
    """The legend below the axes (inside, it covered curves and the labels placed among them).

    On a figure of its own (``own``) the legend stands at the figure's foot, centred on the
    figure, in three columns (two, or one, where three are wider than the figure) and left out
    of the layout, which keeps its height free below the axes: the axes' width then does not
    depend on the legend's text (centred under the axes and kept in the layout, the US legend's
    'lbf/in' entries narrowed motor_pump_on_mounts' axes from 567 to 418 pixels at 150 dpi, and
    its crossings' labels were grouped and placed otherwise than in SI). A legend wider than the
    figure in one column, or axes given by the caller, keep the legend in the layout under the
    axes.
    """
    options = {"fontsize": "x-small", "loc": "upper center", "bbox_to_anchor": (0.5, -0.1), "frameon": False}
    if not own:
        ax.legend(ncols=3, **options)
        return
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    for columns in (3, 2, 1):
        legend = ax.legend(ncols=columns, **options)
        box = legend.get_window_extent(renderer)
        if box.width <= fig.bbox.width:
            break
    else:
        ax.legend(ncols=3, **options)
        return
    legend.set_bbox_to_anchor((0.5, 0.0), transform=fig.transFigure)
    legend.set_loc("lower center")
    legend.set_in_layout(False)
    height = (box.height + _LEGEND_GAP * fig.dpi / 72.0) / fig.bbox.height
    fig.get_layout_engine().set(rect=(0.0, height, 1.0, 1.0 - height))


#: an operating range narrower than this ratio of its speeds (a single rated speed, LO = HI) is
#: drawn as a line: a band so thin would not show on the log axis
THINNEST_BAND = 1.01


def _draw_operating(ax, operating, left) -> list:
    """The operating speed range [rad/s] as a grey band, or a single speed (a range of zero width,
    or too thin to show) as a dashed line named in the legend and, where it finds room, beside
    the line (returned as (x, y, text, colour) for :func:`_place_labels`, at the axis's ``left``)."""
    if operating is None:
        return []
    low, high = (s * 30 / np.pi for s in operating)
    if high > low * THINNEST_BAND:
        operating_band(ax, low, high, "operating range", vertical=False)
        return []
    speed = np.sqrt(low * high)
    text = (f"operating speed {rpm_text(low)} rpm" if high == low
            else f"operating speed {rpm_text(low)} to {rpm_text(high)} rpm")
    operating_band(ax, speed, speed, text, vertical=False)
    return [(left, speed, text, "0.25")]


def _place_labels(ax, labels, first=0, count=0):
    """Names of the curves ending inside the axes and the crossings' speeds, each joined to
    its point by a leader line, clear of the curves, the markers and each other
    (:func:`._labels.place_point_labels`); ``labels``: (x, y, text, colour), most important first,
    the crossings' ``count`` from ``first`` on: those whose circles touch share one label
    (:func:`_touching`)."""
    if not labels:
        return
    with _steady_layout(ax.figure):
        _place_labels_laid_out(ax, labels, first, count)


def _place_labels_laid_out(ax, labels, first, count):
    """:func:`_place_labels` inside :func:`_steady_layout`."""
    from ._labels import place_point_labels

    renderer = _laid_out(ax.figure)
    maps = {}

    def curves():
        # the curves as drawn stay where they are while labels are placed again and again (joins,
        # pairs): one map for each place of the axes, its answers about leaders kept
        # (:meth:`._labels.CurveMap.cut`, :meth:`._labels.CurveMap.runs_along`)
        from ._labels import CurveMap

        key = (float(ax.figure.dpi), tuple(ax.get_window_extent(renderer).extents.tolist()))
        if key not in maps:
            maps[key] = CurveMap(ax, renderer)
        return maps[key]

    def grouped(touching, pairs=(), broken=(), apart=()):
        # the labels' groups (indices into ``labels``, the lead first) and texts of one placing
        groups = [[k] for k in range(first)] + _touching(ax, labels[first:first + count], first, touching) \
            + [[k] for k in range(first + count, len(labels))]
        for pair in pairs:              # two groups joined (:func:`_pair_long_leader`, :func:`_join_long_labels`)
            a, b = (next(g for g in groups if k in g) for k in pair)
            if a is not b:
                a += b
                groups.remove(b)
        for k in apart:                 # a circle split off its group (:func:`_split_long_labels`)
            group = next(g for g in groups if k in g)
            if len(group) > 1:
                group.remove(k)
                groups.append([k])
        return groups, [_shared_text(labels, g, set(g) & set(broken)) for g in groups]

    def place(touching, pairs=(), broken=(), apart=(), counted=True):
        # the labels drawn and (``counted``) how many of their leaders cross curves and circles
        groups, texts = grouped(touching, pairs, broken, apart)
        anchors = [labels[g[0]][:2] for g in groups]
        members = [[labels[k][:2] for k in g[1:]] for g in groups]
        drawn = place_point_labels(ax, anchors, texts, [labels[g[0]][3] for g in groups], renderer=renderer,
                                   curves=curves(), members=members)
        known = {}                      # the lines and texts, measured once for every label
        for text in drawn:
            _lead_to_nearest(ax, text, members[texts.index(text.get_text())], renderer, known)
            text.ucs_grouping = (touching, tuple(pairs), tuple(broken), tuple(apart))   # how the kept labels were grouped
            text.ucs_indices = groups[texts.index(text.get_text())]
        if not counted:
            return drawn
        return drawn, _crossing_leaders(ax, drawn, {t: m for t, m in zip(texts, members)}, circles)

    place.texts = lambda *grouping: grouped(*grouping)[1]

    circles = [c[:2] for c in labels[first:first + count]]
    drawn, crossing = place(_TOUCHING)
    longest = _longest_leader(ax, drawn) if count and not sum(crossing) else 0.0
    if longest > _LONG_LEADER:
        # circles that overlap share a label where one leader is long else (the fan's '3645',
        # three overlapping circles on one stiffness line: 41 points down the brown curve)
        for text in drawn:
            text.remove()
        wider, fewer = place(_OVERLAPPING)
        if not sum(fewer) and _longest_leader(ax, wider) < longest:
            drawn = wider
        else:
            for text in wider:
                text.remove()
            drawn, crossing = place(_TOUCHING)
    if sum(crossing) and count:
        # circles that overlap share a label where leaders cross curves or other circles else
        # (motor_pump_on_mounts' '52517', '56625' and '62212' at 1e8 N/m, 3.4 points apart on one
        # stiffness line: the leader of '56625' ran through its neighbours' circles and, drawn
        # at 150 dpi, across mode 2); kept where fewer leaders do, none more across a mode
        for text in drawn:
            text.remove()
        wider, fewer = place(_OVERLAPPING)
        if fewer[0] <= crossing[0] and sum(fewer) < sum(crossing):
            drawn = wider
        else:
            for text in wider:
                text.remove()
            drawn, crossing = place(_TOUCHING)
    _shorter_leaders(ax, drawn, [label[:2] for label in labels], _members(labels, first, count, drawn))
    if count:
        _pair_long_leader(ax, labels, first, count, drawn, place)
        _join_long_labels(ax, labels, (first, count), drawn, place)


def _join_long_labels(ax, labels, crossings, drawn, place):
    """Each label still more than :data:`_LONG_LEADER` points from its circles (longest first)
    shares one with one of the :data:`_JOINED` nearest other circles within :data:`_NEAR`
    points (whose own label stood where the shared one would go), kept if its leader gets
    shorter, no other label's longer (by 0.5 point) and no more leaders cross curves or circles;
    up to :data:`_ROUNDS` times (a label joined frees a place for another). With every bearing of
    fan_on_bearings chosen, '3939/3943/3959/4184' (four circles on two stiffness lines 4 points
    apart, between three rising curves and three bearing lines) stood 42.5 points from its
    circles; joined by '3608' (its circle 4 points below), '3608/3939/3943/3959/4184' stands
    7.7 points below them, where '3608' stood. Each join is tried on one line, then on two
    (:func:`_shared_text`), and a shared label alone on two lines: on that map '3644' stood 28.7
    points away, nearer the 3394 rpm circle than its own, and '8029/8514' 27 points away, nearer
    6956's; '3394/' over '3644' and '8029/' over '8514' stand 17 points from their circles."""
    for _ in range(_ROUNDS):
        before = _leader_lengths(ax, drawn)
        if not any(_join_one(ax, labels, crossings, drawn, place, (text, before))
                   or _split_one(ax, labels, crossings, drawn, place, (text, before))
                   for text in sorted(before, key=before.get, reverse=True) if before[text] > _LONG_LEADER):
            return


#: :func:`_join_long_labels` looks again this many times
_ROUNDS = 3


def _join_one(ax, labels, crossings, drawn, place, lengths) -> bool:
    """One try of :func:`_join_long_labels` for the label ``text`` (``lengths``: (text, each
    label's leader [points])): True if kept."""
    first, count = crossings
    text, before = lengths
    longest = before[text]
    owner = next(t for t in drawn if t.get_text() == text)
    if not hasattr(owner, "ucs_indices"):
        return False
    touching, pairs, broken, apart = owner.ucs_grouping
    circles = [label[:2] for label in labels[first:first + count]]
    crossing = _crossing_leaders(ax, drawn, _members(labels, first, count, drawn), circles)
    lead = owner.ucs_indices[0]
    # joined with one of the nearest circles, on one line, then on two; a shared label alone on two
    tries = [(joined, lines) for joined in _nearest_others(ax, labels, (first, count), owner.ucs_indices)
             for lines in (1, 2)] + [(None, 2)] * (len(owner.ucs_indices) > 1 and lead not in broken)
    for joined, lines in tries:
        group = owner.ucs_indices + ([] if joined is None else [joined])
        split = broken + ((lead,) if lines == 2 else ())
        shared = _shared_text(labels, group, lines == 2)
        grouping = (touching, pairs + ((() if joined is None else ((joined, lead),))), split, apart)

        def better(tried, after, shared=shared, lines=lines):
            # on two lines only where that ends the misreading: the label within _LONG_LEADER of
            # its circles and nearer them than any other (a two-line join 30 points away, kept for
            # a point's gain, took the place that let '6956' join '8029/8514' on the fan's 1e5 ..
            # 1e10 map)
            return after.get(shared, np.inf) < longest and _no_leader_longer(before, after, shared) \
                and (lines == 1 or after[shared] <= _LONG_LEADER
                     and _names_its_own(ax, next(t for t in tried if t.get_text() == shared), labels, crossings))

        if _kept_if_better(ax, labels, crossings, drawn, place, grouping, better, crossing):
            return True
    return False


def _split_one(ax, labels, crossings, drawn, place, lengths) -> bool:
    """Where :func:`_join_one` keeps no join for the shared label ``text`` (``lengths``: (text,
    each label's leader [points])), its group split in two: its highest or its lowest speed on
    a label of its own (where its circle lies on none of the others': :data:`_TOUCHING`), the
    others' label on one line, then on two; kept if both new labels
    stand nearer than ``text`` did and each nearer a circle it names than any other
    (:func:`_names_its_own`), no other label's leader is longer (by 0.5 point) and no more
    leaders cross curves or circles. With every bearing of fan_on_bearings chosen, no place
    within 24 points whose leader neither runs along a line nor passes by another text was
    left for '3394/3644/3943' (three circles on one stiffness line, 44 points away); '3943'
    stands beside its circle and '3394/' over '3644' 18 points below. True if kept."""
    first, count = crossings
    text, before = lengths
    longest = before[text]
    owner = next(t for t in drawn if t.get_text() == text)
    group = getattr(owner, "ucs_indices", [])
    if len(group) < 2:
        return False
    touching, pairs, broken, apart = owner.ucs_grouping
    circles = [label[:2] for label in labels[first:first + count]]
    crossing = None
    by_speed = sorted(group, key=lambda k: labels[k][1])
    # not a circle lying on another of the group: those share a label (:func:`_touching`)
    touching_groups = _touching(ax, labels[first:first + count], first, _TOUCHING)
    apart_ones = {g[0] for g in touching_groups if len(set(g) & set(group)) == 1}
    for alone in [k for k in dict.fromkeys((by_speed[-1], by_speed[0])) if k in apart_ones]:
        rest = [k for k in group if k != alone]
        for lines in (1, 2) if len(rest) > 1 else (1,):
            grouping = (touching, pairs, broken + ((rest[0],) if lines == 2 else ()), apart + (alone,))
            parts = [t for t in place.texts(*grouping) if set(_words(t)) <= set(_words(text))]
            crossing = crossing or _crossing_leaders(ax, drawn, _members(labels, first, count, drawn), circles)

            def better(tried, after, parts=parts):
                new = [t for t in tried if t.get_text() in parts]
                return len(new) == len(parts) == 2 and max(after[t] for t in parts) < longest \
                    and _no_leader_longer(before, after) and all(_names_its_own(ax, t, labels, crossings) for t in new)

            if _kept_if_better(ax, labels, crossings, drawn, place, grouping, better, crossing):
                return True
    return False


def _kept_if_better(ax, labels, crossings, drawn, place, grouping, better, crossing) -> bool:
    """Place the labels again grouped as ``grouping`` (the arguments of ``place``), their leaders
    shortened (:func:`_shorter_leaders`), and keep that placing in ``drawn`` where
    ``better(tried, after)`` (the labels placed; each one's leader [points]) and no more leaders
    cross curves or circles than ``crossing`` (:func:`_crossing_leaders` of ``drawn``): True if
    kept. The leaders' crossings are counted only where the lengths allow the placing (most
    tries fail on them: the fan's 1e5 .. 1e10 N/m map placed its labels 14 times)."""
    first, count = crossings
    for t in drawn:
        t.set_visible(False)
    tried = place(*grouping, counted=False)
    _shorter_leaders(ax, tried, [label[:2] for label in labels], _members(labels, first, count, tried))
    after = _leader_lengths(ax, tried)
    if better(tried, after):
        circles = [label[:2] for label in labels[first:first + count]]
        through = _crossing_leaders(ax, tried, _members(labels, first, count, tried), circles)
        if through[0] <= crossing[0] and sum(through) <= sum(crossing):
            for t in drawn:
                t.remove()
            drawn[:] = tried
            return True
    for t in tried:
        t.remove()
    for t in drawn:
        t.set_visible(True)
    return False


def _names_its_own(ax, text, labels, crossings) -> bool:
    """Whether the label ``text`` (an annotation naming crossings of ``labels``) stands nearer a
    circle it names than any other crossing's circle, laid out at :data:`SAVED_DPI`."""
    from matplotlib.text import Text

    first, count = crossings
    words = set(_words(text.get_text()))
    mine = np.array([labels[k][2] in words for k in range(first, first + count)])
    if not mine.any() or mine.all():
        return bool(mine.any())
    centres = _circle_centres(ax, labels, first, count)
    with _at_saved_dpi(ax.figure):
        renderer = _laid_out(ax.figure)
        text.update_positions(renderer)
        box = np.array(Text.get_window_extent(text, renderer).extents)
    distance = np.hypot(*(np.clip(centres, box[:2], box[2:]) - centres).T)
    return bool(distance[mine].min() < distance[~mine].min())


@contextmanager
def _at_saved_dpi(fig):
    """``fig`` at :data:`SAVED_DPI` inside the block (labels are placed and measured as saved),
    its own dpi back after it, also where the block raises."""
    dpi = fig.get_dpi()
    fig.set_dpi(SAVED_DPI)
    try:
        yield
    finally:
        fig.set_dpi(dpi)


@contextmanager
def _steady_layout(fig):
    """Inside the block, :func:`_laid_out` runs the constrained layout of ``fig`` only for axes
    places (and resolution and size) it has not started from before: the labels placed inside
    the block stand inside the axes and change no margin, so a layout from where an earlier one
    started ends where that one ended, and the axes are put there. The fan's map with every
    bearing chosen was laid out 30 times (6.6 s of its 12-15 s of CPU), compressor_on_journals'
    14 times; the places alternate between the two resolutions (the figure's and
    :data:`SAVED_DPI`) and settle within a few runs."""
    fig._ucs_layouts = {}
    try:
        yield
    finally:
        del fig._ucs_layouts


def _axes_places(fig) -> tuple:
    """Every axes' place in ``fig``: its corners (x0, y0, x1, y1) [figure fraction], as laid out
    and as given (the corners themselves: bounds give x1 back as x0 + width, a bit off at times)."""
    return tuple((tuple(ax.get_position().get_points().ravel().tolist()),
                  tuple(ax.get_position(original=True).get_points().ravel().tolist())) for ax in fig.get_axes())


def _laid_out(fig):
    """:func:`._labels.laid_out_renderer`; inside :func:`_steady_layout`, where a layout at this
    resolution and size started from these very axes places before, the axes are put where it
    left them instead (the same layout again: nothing it reads has changed)."""
    from matplotlib.transforms import Bbox

    from ._labels import laid_out_renderer

    layouts = getattr(fig, "_ucs_layouts", None)
    key = (float(fig.dpi), tuple(float(v) for v in fig.get_size_inches()), _axes_places(fig))
    if layouts is None or key not in layouts:
        renderer = laid_out_renderer(fig)
        if layouts is not None:
            layouts[key] = _axes_places(fig)
        return renderer
    for ax, (active, original) in zip(fig.get_axes(), layouts[key]):
        ax._set_position(Bbox(np.reshape(original, (2, 2))), which="original")
        ax._set_position(Bbox(np.reshape(active, (2, 2))), which="active")
    return fig.canvas.get_renderer()


def _circle_centres(ax, labels, first, count) -> np.ndarray:
    """The centres [pixels at :data:`SAVED_DPI`] of the crossings' circles ``labels[first:first +
    count]`` (their data points), shape (count, 2)."""
    with _at_saved_dpi(ax.figure):
        return ax.transData.transform(np.array([labels[k][:2] for k in range(first, first + count)], float))


#: how many of the nearest other circles :func:`_join_long_labels` tries to join
_JOINED = 2


def _nearest_others(ax, labels, crossings, indices) -> list:
    """The crossings (indices into ``labels``) whose circles lie nearest those of ``indices``,
    not among them, within :data:`_NEAR` points at :data:`SAVED_DPI`: :data:`_JOINED` at most,
    nearest first."""
    first, count = crossings
    centres = _circle_centres(ax, labels, first, count)
    mine = np.isin(np.arange(first, first + count), indices)
    if mine.all() or not mine.any():
        return []
    distance = np.hypot(*(centres[:, None] - centres[mine][None]).transpose(2, 0, 1)).min(axis=1) * 72.0 / SAVED_DPI
    distance[mine] = np.inf
    order = np.argsort(distance, kind="stable")[:_JOINED]
    return [first + int(k) for k in order if distance[k] < _NEAR]


def _pair_long_leader(ax, labels, first, count, drawn, place):
    """Where a crossing's label still stands more than :data:`_LONG_LEADER` points from its
    circle, its circle and the nearest other one (centres within :data:`_NEAR` points, at
    :data:`SAVED_DPI`) share one label, kept if that shortens the longest leader and lengthens
    no other label's (nor adds a leader across a curve or circle): flexible_pump_on_mounts' map
    over 1e5 .. 1e10 N/m, 41 values, had no free place beside '31315' at 1e8 N/m (the curves
    above and below it, the circle of '34642' 9.6 points above) and drew its leader 45 points
    long; '31315/34642' stands 8 points from its circles. Two circles only: a chain of such
    circles (the fan's, every bearing chosen) grouped five speeds on one label 48 points away."""
    before = _leader_lengths(ax, drawn)
    if not before:                     # no label drawn (all in the note)
        return
    text, longest = max(before.items(), key=lambda item: item[1])
    if longest <= _LONG_LEADER:
        return
    index = [k for k in range(first, first + count) if labels[k][2] == _words(text)[0]]
    if len(index) != 1 or "/" in text:
        return
    centres = _circle_centres(ax, labels, first, count)
    own = index[0] - first
    distance = np.hypot(*(centres - centres[own]).T) * 72.0 / SAVED_DPI
    distance[own] = np.inf
    other = int(np.argmin(distance))
    if not distance[other] < _NEAR:
        return
    circles = [label[:2] for label in labels[first:first + count]]
    crossing = _crossing_leaders(ax, drawn, _members(labels, first, count, drawn), circles)
    _kept_if_better(ax, labels, (first, count), drawn, place, (_TOUCHING, ((first + own, first + other),)),
                    lambda tried, after: max(after.values(), default=0.0) < longest
                    and _no_leader_longer(before, after), crossing)


def _members(labels, first, count, drawn) -> dict:
    """Each crossing label's text -> the points (data coordinates) of the speeds it names."""
    where = {labels[k][2]: labels[k][:2] for k in range(first, first + count)}
    return {t.get_text(): [where[part] for part in _words(t.get_text()) if part in where] for t in drawn}


def _shared_text(labels, group, broken=False) -> str:
    """The label of the crossings ``group`` (indices into ``labels``): their speeds, lowest
    first, joined by '/'; ``broken``: on two lines, broken after the middle '/' (a label
    naming two or more circles, narrow enough for a gap between curves where one line is not:
    '8029/' over '8514' on the fan's map with every bearing chosen)."""
    words = list(dict.fromkeys(labels[k][2] for k in sorted(group, key=lambda k: labels[k][1])))
    half = (len(words) + 1) // 2
    if not broken or len(words) < 2:
        return "/".join(words)
    return "/".join(words[:half]) + "/\n" + "/".join(words[half:])


def _no_leader_longer(before, after, skip=None) -> bool:
    """Whether every label of ``after`` (text -> leader length [points]) but ``skip`` has a leader
    at most half a point longer than the longest ``before`` of the labels naming its speeds:
    a join or pair may shorten the long leader it is for, not lengthen another's."""
    named = {part: length for label, length in before.items() for part in _words(label)}
    return all(length <= max(named.get(part, 0.0) for part in _words(label)) + 0.5
               for label, length in after.items() if label != skip)


def _words(text) -> list:
    """The speeds a crossing's label names ('3644/\\n3943' -> ['3644', '3943'])."""
    return text.replace("\n", "").split("/")


def _leader_lengths(ax, drawn) -> dict:
    """Each label's leader [points] (text -> length), from its box to its point, laid out at
    :data:`SAVED_DPI`."""
    from matplotlib.text import Text

    fig = ax.figure
    with _at_saved_dpi(fig):
        renderer = _laid_out(fig)
        out = {}
        for text in drawn:
            text.update_positions(renderer)
            anchor = ax.transData.transform(text.xy)
            box = np.array(Text.get_window_extent(text, renderer).extents)
            out[text.get_text()] = float(np.hypot(*(_nearest(box, anchor) - anchor))) * 72.0 / SAVED_DPI
    return out


#: a label whose leader is longer than this [points] is moved nearer its point where a place is free
_SHORT_LEADER = 8.0
#: where a crossing's leader is longer than this [points], overlapping circles share one label
_LONG_LEADER = 24.0


def _longest_leader(ax, drawn) -> float:
    """The longest leader of the labels ``drawn`` [points], from the text's box to its point."""
    from matplotlib.text import Text

    renderer = _laid_out(ax.figure)
    longest = 0.0
    for text in drawn:
        text.update_positions(renderer)
        anchor = ax.transData.transform(text.xy)
        box = np.array(Text.get_window_extent(text, renderer).extents)
        longest = max(longest, float(np.hypot(*(_nearest(box, anchor) - anchor))))
    return longest * 72.0 / ax.figure.dpi
#: the places tried around the point: steps of this [points], out to the leader's length
_STEP_POINTS = 1.5
#: a moved label keeps this far [points] from other labels, the axes' edge and the markers' circles,
#: and this much farther from the lines' middles (half the curves' width)
_CLEAR_POINTS, _LINE_POINTS = 1.0, 1.0


def _shorter_leaders(ax, drawn, points, members=None):
    """Move each label of ``drawn`` whose leader is longer than :data:`_SHORT_LEADER` to the
    free place nearest its point (the fan's '3645' and '3394', three circles on one stiffness
    line, stood 41 and 19 points away down the brown curve, '4184' 17 points away while a
    place beside its circle was free): a place inside the axes, clear of every other text, of
    the circles and squares drawn (``points``: the labelled points, data coordinates) and of
    every line, whose leader crosses no line outside the point's own circle, runs along none
    (:func:`._labels.runs_along_each`), passes :data:`._labels.LEADER_GAP_POINTS` clear of every
    other text (and no other leader as near the place), and crosses no other leader and no
    other circle. A label naming several circles (``members``: text ->
    their points, :func:`_members`) may lead to any of them, its leader crossing lines inside any. Measured on the figure laid out at :data:`SAVED_DPI`; a label with no
    nearer place stays where :func:`_place_labels` put it."""
    from matplotlib.text import Text

    from ._labels import _drawn_segments, crossing_pairs, crosses_segments

    if not drawn:
        return
    fig = ax.figure
    with _at_saved_dpi(fig):
        renderer = _laid_out(fig)
        scale = SAVED_DPI / 72.0
        frame = ax.get_window_extent(renderer)
        segments = _drawn_segments(ax, [], (frame.x0, frame.y0, frame.x1, frame.y1))
        radius = 0.5 * _CIRCLE_POINTS * scale
        centres = ax.transData.transform(np.asarray(points, float).reshape(-1, 2))
        texts = [t for t in ax.texts if t.get_visible()] + list(ax.artists)
        fresh = set()               # the labels placed for their xy as they are (unmoved since)
        extents = {}                # each text's box as it stands (a text's layout is slow to redo)

        def extent(t):
            if t not in extents:
                extents[t] = np.array(Text.get_window_extent(t, renderer).extents)
            return extents[t]

        for text in drawn:
            for t in drawn:
                if t not in fresh:
                    t.update_positions(renderer)
                    fresh.add(t)
                    extents.pop(t, None)
            box = extent(text)
            anchor = ax.transData.transform(text.xy)
            length = np.hypot(*(_nearest(box, anchor) - anchor))
            named = [tuple(text.xy)] + [tuple(p) for p in (members or {}).get(text.get_text(), [])
                                        if tuple(p) != tuple(text.xy)]
            group = ax.transData.transform(np.asarray(named, float))
            if _names_another(box, group, centres, radius):
                # nearer another circle than its own, it reads as naming that one: a place that
                # names its own within _LONG_LEADER will do, shorter or not (the fan's '8029/',
                # over '8514', 18.9 points up the cyan line nearer 6956's circle; 18.3 points
                # up beside it, nearer its own)
                length = max(length, _LONG_LEADER * scale + _STEP_POINTS * scale)
            elif length <= _SHORT_LEADER * scale:
                continue
            others = [extent(t) for t in texts if t is not text]
            leaders = [np.r_[_nearest(extent(t), ax.transData.transform(t.xy)), ax.transData.transform(t.xy)]
                       for t in drawn if t is not text]
            best = None
            for point, target in zip(named, group):     # a shared label may lead to any of its circles
                place = _nearer_place(box, target, length, (frame, segments, centres, radius, scale), others,
                                      leaders, (crossing_pairs, crosses_segments), group)
                if place is not None:
                    length = np.hypot(*(_nearest(place, target) - target))
                    best = (point, target, place)
            if best is not None:
                point, anchor, place = best
                w, h = box[2] - box[0], box[3] - box[1]
                end = _nearest(place, anchor)
                text.xy = point
                text.xyann = ((place[0] - anchor[0]) / scale, (place[1] - anchor[1]) / scale)
                _start_leader_at(text, ((end[0] - place[0]) / w, (end[1] - place[1]) / h))
                fresh.discard(text)


def _names_another(box, group, centres, radius) -> bool:
    """Whether the label's ``box`` [pixels] stands at least as near a point of ``centres`` (k, 2)
    [pixels] that is not one of its own (``group`` (m, 2): the points it names, within
    ``radius``) as near the nearest of its own: the test :func:`_nearer_place` puts on a new place."""
    group = np.reshape(group, (-1, 2))
    own = np.hypot(*(centres[:, None] - group[None]).transpose(2, 0, 1)).min(axis=1) <= radius
    if own.all():
        return False
    near = lambda points: np.hypot(*(np.clip(points, box[:2], box[2:]) - points).T)      # noqa: E731
    return bool(near(centres[~own]).min() <= near(group).min())


def _nearest(box, point):
    """The point of ``box`` (x0, y0, x1, y1) nearest ``point`` (pixels)."""
    return np.array([min(max(point[0], box[0]), box[2]), min(max(point[1], box[1]), box[3])])


def _nearer_place(box, anchor, length, scene, others, leaders, tests, group=None):
    """The box of ``box``'s size nearest ``anchor`` (its leader shorter than ``length`` by a
    step at least) that is free (:func:`_shorter_leaders`), or None; all in pixels. ``group``
    (k, 2): the points the label names (``anchor`` among them), inside whose circles its leader
    may cross lines."""
    from ._labels import LEADER_GAP_POINTS, widened

    frame, segments, centres, radius, scale = scene
    crossing_pairs, crosses_segments = tests
    gap = LEADER_GAP_POINTS * scale
    wide_others = widened(others, gap)
    w, h = box[2] - box[0], box[3] - box[1]
    step, clear, line = _STEP_POINTS * scale, _CLEAR_POINTS * scale, _LINE_POINTS * scale
    reach = np.arange(-length - w, length + step, step)
    x0 = anchor[0] + reach
    y0 = anchor[1] + np.arange(-length - h, length + step, step)
    grid = np.stack(np.meshgrid(x0, y0), axis=-1).reshape(-1, 2)
    near = np.column_stack([np.clip(anchor[0], grid[:, 0], grid[:, 0] + w), np.clip(anchor[1], grid[:, 1], grid[:, 1] + h)])
    distance = np.hypot(*(near - anchor).T)
    order = np.argsort(distance, kind="stable")
    order = order[distance[order] <= length - step]
    group = np.reshape(anchor if group is None else group, (-1, 2))
    own = np.hypot(*(centres[:, None] - group[None]).transpose(2, 0, 1)).min(axis=1) <= radius
    markers = np.column_stack([centres - radius - clear, centres + radius + clear])
    places = np.column_stack([grid[order], grid[order] + (w, h)])
    padded_all = places + (-clear, -clear, clear, clear)
    # inside the frame, off every other text and marker: every place at once
    open_ = (padded_all[:, 0] >= frame.x0) & (padded_all[:, 1] >= frame.y0) & (padded_all[:, 2] <= frame.x1) \
        & (padded_all[:, 3] <= frame.y1) & ~overlaps_any(padded_all, others) & ~overlaps_any(padded_all, markers)
    through = _lines_through(segments, padded_all[open_] + (-line, -line, line, line), crossing_pairs)
    for i, place, crossed in zip(order[open_], places[open_], through):
        if crossed:
            continue
        start = near[i]
        if len(centres[~own]) and np.hypot(*(np.clip(centres[~own], place[:2], place[2:]) - centres[~own]).T).min() \
                <= distance[i]:
            continue                  # nearer another point than its own: it would name that one
        # nor within the leader's gap of another text nor along a line, nor another leader
        # within the gap of the place
        if crosses_segments(start, anchor, leaders) or _breaks_leader_rules(start, anchor, segments, wide_others,
                                                                             radius, scale) \
                or (len(leaders) and np.any(crossing_pairs(leaders, widened(place, gap)))):
            continue
        hits = _meets(start, anchor, segments) if len(segments) else np.zeros((0, 2))
        if len(hits) and np.any(np.hypot(*(hits[:, None] - group[None]).transpose(2, 0, 1)).min(axis=1)
                                > radius + 0.5):
            continue
        way = anchor - start
        t = np.clip((centres[~own] - start) @ way / max(float(way @ way), 1e-12), 0.0, 1.0)
        if np.any(np.hypot(*(start + t[:, None] * way - centres[~own]).T) < radius + 0.5):
            continue
        return place
    return None


#: :func:`_lines_through` tests this many places at once (the first free one is often early)
_PLACES_AT_ONCE = 64


def _lines_through(segments, boxes, crossing_pairs):
    """Whether any of ``segments`` ((start, end) pairs [pixels]) passes through each of ``boxes``
    (n, 4) [pixels], in order, a chunk of :data:`_PLACES_AT_ONCE` boxes at a time as asked for
    (:func:`._labels.crossing_pairs`, the answer of ``crosses_any`` box by box); only the
    segments whose bounding boxes come within a pixel of the boxes' span are tested (a segment
    farther off crosses none of them). The fan's map asked ``crosses_any`` 110,000 times, each
    of the map's every segment against one place."""
    lines = np.asarray(segments, float).reshape(-1, 4)
    if not len(lines) or not len(boxes):
        yield from np.zeros(len(boxes), bool)
        return
    low, high = boxes[:, :2].min(axis=0) - 1.0, boxes[:, 2:].max(axis=0) + 1.0
    lo, hi = np.minimum(lines[:, :2], lines[:, 2:]), np.maximum(lines[:, :2], lines[:, 2:])
    # (not "inside": a segment with a NaN end stays, as crossing_pairs answers for it)
    lines = lines[~np.any((hi < low) | (lo > high), axis=1)]
    for start in range(0, len(boxes), _PLACES_AT_ONCE):
        part = boxes[start:start + _PLACES_AT_ONCE]
        yield from (np.any(crossing_pairs(lines, part), axis=0) if len(lines) else np.zeros(len(part), bool))


def _breaks_leader_rules(start, anchor, segments, others, radius, scale) -> bool:
    """Whether the leader ``start -> anchor`` [pixels] passes through one of ``others`` (the other
    texts' boxes (k, 4) [pixels], widened by :data:`._labels.LEADER_GAP_POINTS`: it would read as
    touching that text) or runs along one of the drawn ``segments`` (n, 4) [pixels], its part
    outside the circle of ``radius`` [pixels] around ``anchor`` (:func:`._labels.runs_along_each`:
    it would read as a piece of that line); ``scale``: pixels per point."""
    from ._labels import runs_along_each, short_of_each

    if any(_leader_through(start, anchor, box) for box in others):
        return True
    return bool(len(segments) and runs_along_each(segments, start, short_of_each(start, anchor, radius), scale)[0])


def _leader_through(start, end, box) -> bool:
    """Whether the segment ``start -> end`` passes through ``box`` (x0, y0, x1, y1) [pixels]:
    a leader drawn over another label."""
    from ._labels import segment_crosses_box

    return bool(segment_crosses_box(start, end, box))


def _overlap(a, b):
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _lead_to_nearest(ax, text, members, renderer, known=None):
    """Join a label naming several circles (``members``: the others', data coordinates) to the
    one nearest its text, the text staying where it is: its leader then ends at the group's edge
    and runs through none of the group's circles (the middle one of '52517/56625/62212', three
    circles 3.4 points apart on one stiffness line, drew a leader through the top circle, across
    mode 4's line inside it). Not where that leader would run along a drawn line or pass within
    :data:`._labels.LEADER_GAP_POINTS` of another text (:func:`_breaks_leader_rules`; the
    placer's leader, which keeps both rules, stays). ``known``: a dict keeping
    :func:`_leader_scene` for the next labels (their texts stay where they are), or None."""
    from matplotlib.text import Text

    from ._labels import LEADER_GAP_POINTS, widened

    if not members:
        return
    text.update_positions(renderer)
    box = Text.get_window_extent(text, renderer)
    points = ax.transData.transform(np.vstack([text.xy] + [list(p) for p in members]))
    near = [np.hypot(min(max(x, box.x0), box.x1) - x, min(max(y, box.y0), box.y1) - y) for x, y in points]
    k = int(np.argmin(near))
    if k == 0:
        return
    scale = ax.figure.dpi / 72.0
    end = (min(max(points[k][0], box.x0), box.x1), min(max(points[k][1], box.y0), box.y1))
    known = {} if known is None else known
    if "scene" not in known:
        known["scene"] = _leader_scene(ax, renderer)
    segments, boxes = known["scene"]
    others = np.reshape([b for t, b in boxes.items() if t is not text], (-1, 4))
    if _breaks_leader_rules(np.array(end), points[k], segments, widened(others, LEADER_GAP_POINTS * scale),
                            0.5 * _CIRCLE_POINTS * scale, scale):
        return
    shift = (points[k] - points[0]) / scale
    text.xy = tuple(members[k - 1])
    text.xyann = (text.xyann[0] - shift[0], text.xyann[1] - shift[1])
    _start_leader_at(text, ((end[0] - box.x0) / max(box.width, 1e-9), (end[1] - box.y0) / max(box.height, 1e-9)))


def _leader_scene(ax, renderer):
    """What :func:`_breaks_leader_rules` measures a leader against in ``ax`` as ``renderer`` lays
    it out: the drawn lines' segments (n, 4) and each visible text's box (text -> (4,)), pixels."""
    from matplotlib.text import Text

    from ._labels import _drawn_segments

    frame = ax.get_window_extent(renderer)
    boxes = {}
    for other in ax.texts:
        if other.get_visible() and other.get_text().strip():
            if hasattr(other, "update_positions"):
                other.update_positions(renderer)
            boxes[other] = np.array(Text.get_window_extent(other, renderer).extents)
    return _drawn_segments(ax, [], (frame.x0, frame.y0, frame.x1, frame.y1)), boxes


def _start_leader_at(text, relpos):
    """Start the leader of the annotation ``text`` at ``relpos`` (fractions of its box) as drawn:
    matplotlib reads ``arrowprops['relpos']`` once, when the annotation is made (into its
    ``_arrow_relpos``), so a label moved after that drew its leader from its old corner (the fan's
    '3608/3939/3943/3959/4184', moved below its circle, from its lower left corner, against the
    curve number '8', where the leader measured went from its upper left one)."""
    text.arrowprops["relpos"] = relpos
    text._arrow_relpos = relpos


def _crossing_leaders(ax, drawn, members, centres):
    """How many labels of ``drawn`` (annotations) have leaders (from the text's box to its point)
    that cross a mode's curve (a line named '<number> <name>') outside the circles of the points
    they name (``members``: text -> the other points, data coordinates), and how many pass
    through the circle of another crossing (``centres`` (n, 2), data coordinates): measured on
    the figure laid out at :data:`SAVED_DPI`, where labels placed at the figure's own dpi may
    cross a curve they only grazed there."""
    from matplotlib.text import Text

    from ._labels import _drawn_segments

    fig = ax.figure
    with _at_saved_dpi(fig):
        renderer = _laid_out(fig)
        frame = ax.get_window_extent(renderer)
        skip = [line for line in ax.get_lines() if not str(line.get_label())[:1].isdigit()]
        segments = _drawn_segments(ax, skip, (frame.x0, frame.y0, frame.x1, frame.y1))
        radius = 0.5 * _CIRCLE_POINTS * SAVED_DPI / 72.0
        points = ax.transData.transform(np.asarray(centres, float).reshape(-1, 2))
        crossing = through = 0
        for text in drawn:
            text.update_positions(renderer)
            box = Text.get_window_extent(text, renderer)            # the text's, not its leader's
            end = ax.transData.transform(text.xy)
            start = np.array([min(max(end[0], box.x0), box.x1), min(max(end[1], box.y0), box.y1)])
            circles = np.vstack([end] + [ax.transData.transform(p) for p in members.get(text.get_text(), [])])
            meets = _meets(start, end, segments) if len(segments) else np.zeros((0, 2))
            crossing += bool(np.any(np.hypot(*(meets[:, None] - circles[None]).transpose(2, 0, 1)).min(axis=1)
                                    > radius + 0.5))
            others = points[np.hypot(*(points[:, None] - circles[None]).transpose(2, 0, 1)).min(axis=1) > radius]
            way = end - start
            t = np.clip((others - start) @ way / max(float(way @ way), 1e-12), 0.0, 1.0)
            through += bool(np.any(np.hypot(*(start + t[:, None] * way - others).T) < radius - 0.5))
    return crossing, through


def _meets(start, end, segments):
    """Points (k, 2) [pixels] where the segment ``start -> end`` crosses ``segments`` (n, 4)."""
    d = end - start
    p, e = segments[:, :2], segments[:, 2:] - segments[:, :2]
    denominator = d[0] * e[:, 1] - d[1] * e[:, 0]
    w = p - start
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]) / denominator
        u = (w[:, 0] * d[1] - w[:, 1] * d[0]) / denominator
    hit = (denominator != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    return start + t[hit, None] * d


#: crossings' circles (6 points across) whose centres lie closer than this [points] share a
#: label; side by side (on two stiffness lines) twice as far
_TOUCHING = 3.0
#: ... and, where some leader crosses a curve so, closer than this (circles that overlap)
_OVERLAPPING, _CIRCLE_POINTS = 6.0, 6.0
#: a crossing whose label stands far from it shares one with the nearest circle within this [points]
_NEAR = 12.0
#: the figures are saved at this resolution [dpi] (``save_figure``), where leaders are checked
SAVED_DPI = 150.0


def _touching(ax, crossings, first=0, touching=_TOUCHING):
    """The crossings' indices (from ``first`` on) in groups whose circles (6 points across) lie
    on each other (centres closer than ``touching`` [points], side by side twice that, through a
    chain of such circles: :func:`._labels.touching_groups`), each led by the circle nearest the group's middle: one
    label names the group ('3939/4184', speeds increasing), its leader to that circle (five
    circles within 10 pixels at 4e6 and 4.5e6 N/m on the fan's map drew five leaders into one
    blot, one through another's circle; compressor_on_journals' Kxx and Kyy crossings lie on
    each other in pairs)."""
    from ._labels import touching_groups

    if not crossings:
        return []
    centres = ax.transData.transform(np.array([c[:2] for c in crossings], float))
    groups = []
    points = ax.figure.dpi / 72.0
    for members in touching_groups(centres, touching * points, beside=max(touching, 2 * _TOUCHING) * points):
        middle = centres[members].mean(axis=0)
        members.sort(key=lambda k: np.hypot(*(centres[k] - middle)))
        groups.append([first + k for k in members])
    return groups


def _modes(result):
    """(K, L) [rpm] and names of the curves: the followed modes (the ranks of a result made
    without them)."""
    if result.mode_speeds is None:
        return result.speeds_rpm, tuple(f"(rank {j + 1})" for j in range(result.speeds.shape[1]))
    return result.mode_speeds * 30 / np.pi, result.mode_names


#: the axis runs on past the sweep's last stiffness by this part of its decades (at least 0.3
#: decade), where the rigid-support asymptotes are drawn
_MARGIN = 0.1


def _asymptote_margin(k):
    return 10 ** max(0.3, _MARGIN * np.log10(k[-1] / k[0]))


def _label_short_speed_axis(ax, limits):
    """On a speed axis spanning less than two decades, ticks numbered in plain rpm: within one
    decade at round steps (60, 80, 100, 120, ...), else at each digit (20, 30, ..., 200): its
    powers of ten alone numbered one tick (spring_block_rotor's map, 62 to 194 rpm: only
    '10^2', the curves' plateau at 129 rpm unreadable)."""
    from matplotlib.ticker import LogFormatter, MaxNLocator, NullLocator, StrMethodFormatter

    if limits[1] < 10.0 * limits[0]:
        ax.yaxis.set_major_locator(MaxNLocator(nbins=8))
        ax.yaxis.set_major_formatter(StrMethodFormatter("{x:,.6g}"))
        ax.yaxis.set_minor_locator(NullLocator())
    elif limits[1] < 100.0 * limits[0]:
        ax.yaxis.set_major_formatter(LogFormatter(labelOnlyBase=False))
        ax.yaxis.set_minor_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2.0, 1.0)))


def _speed_limits(rpm, result):
    """Speed axis: the map's finite speeds (and the crossings, the operating band, the
    rigid-support asymptotes), a margin."""
    values = [rpm[np.isfinite(rpm) & (rpm > 0)]]
    values.append(np.array([c.speed for c in result.crossings]) * 30 / np.pi)
    if result.operating is not None:
        values.append(np.array(result.operating) * 30 / np.pi)
    if result.rigid_speeds is not None:
        values.append(result.rigid_speeds * 30 / np.pi)
    values = np.concatenate(values)
    values = values[np.isfinite(values) & (values > 0)]
    if not values.size:
        return 1.0, 1e4
    return values.min() / 1.5, values.max() * 1.5


def _draw_ends(ax, k, rpm, colour) -> list:
    """Squares where a curve starts or stops inside the sweep (its mode becomes or stops being a
    forward critical speed there)."""
    finite = np.isfinite(rpm)
    starts = np.nonzero(finite[1:] & ~finite[:-1])[0] + 1
    stops = np.nonzero(finite[:-1] & ~finite[1:])[0]
    ends = np.r_[starts, stops].astype(int)
    if ends.size:
        ax.plot(k[ends], rpm[ends], "s", color=colour, markersize=4, zorder=4)
    return list(ends)


#: the least distance between two names at the right edge [axes fraction]
_NAME_APART = 0.035
#: the names stand this far right of the right edge, their leaders between [axes fraction]
_NAME_OFFSET = 0.03


def _label_right_ends(ax, k, rpm, names, limits) -> list:
    """Each curve reaching the sweep's end named beside the right edge (the names moved apart
    where curves end close together); the others' numbers are returned as (x, y, text, colour)
    of their last point, to be placed among the curves (:func:`_place_labels`)."""
    ends, inside = [], []
    for j in range(rpm.shape[1]):
        finite = np.nonzero(np.isfinite(rpm[:, j]))[0]
        if not finite.size:
            continue
        last = finite[-1]
        text = f"{j + 1} {names[j]}"
        colour = _MODE_COLOURS[j % len(_MODE_COLOURS)]
        if last < len(k) - 1:        # its number, the legend's key: a crowd of long names finds no room
            inside.append((k[last], rpm[last, j], f"{j + 1}", colour))
        elif limits[0] <= rpm[last, j] <= limits[1]:
            ends.append([np.log(rpm[last, j] / limits[0]) / np.log(limits[1] / limits[0]), text, colour])
    ends.sort(key=lambda e: e[0])
    heights = [e[0] for e in ends]                    # where each curve meets the right edge
    for i in range(1, len(ends)):                     # upwards apart, then back under the top
        ends[i][0] = max(ends[i][0], ends[i - 1][0] + _NAME_APART)
    shift = max(0.0, ends[-1][0] - 1.0) if ends else 0.0
    for (place, text, colour), height in zip(ends, heights):
        # joined to its curve's end by a leader: a name moved apart from crowded ends stood
        # half a label's height or more off its curve, with nothing saying which it named
        ax.annotate(text, (1.0, height), xycoords="axes fraction", xytext=(1.0 + _NAME_OFFSET, place - shift),
                    textcoords="axes fraction", color=colour, fontsize="small", va="center", ha="left",
                    annotation_clip=False, gid="ucs-end-name",
                    arrowprops={"arrowstyle": "-", "color": colour, "linewidth": 0.7, "shrinkA": 0, "shrinkB": 0,
                                "relpos": (0.0, 0.5)})
    return inside


def _rigid_speeds(result, limits):
    """The rigid-support speeds [rpm] within the speed axis."""
    if result.rigid_speeds is None:
        return np.zeros(0)
    speeds = result.rigid_speeds * 30 / np.pi
    return speeds[np.isfinite(speeds) & (speeds >= limits[0]) & (speeds <= limits[1])]


def _draw_asymptotes(ax, result, speeds, scale=1.0):
    """The rigid-support speeds: dotted grey lines beyond the sweep's last stiffness (where the
    curves that tend to them have already reached them, drawn over them, they would not show);
    without any, the legend says that the supports made rigid leave no critical speed."""
    if not speeds.size:
        if result.rigid_speeds is not None:
            ax.plot([], [], ":", color="0.25", label="rigid supports: no critical speed")
        return
    end = result.stiffness[-1] * scale
    ax.axvline(end, color="0.5", linewidth=0.8)
    ax.hlines(speeds, end, ax.get_xlim()[1], colors="0.25", linestyles=":", linewidth=1.6,
              label="rigid supports (k -> infinity)")


def _draw_bearings(ax, result, units=(1.0, "N/m")):
    """Each bearing's Kxx (solid) and Kyy (dashed) over speed; constant ones as vertical lines,
    one line per distinct stiffness with the bearings' names together (``units``: the
    stiffness axis's factor on N/m and its unit)."""
    scale, unit = units
    vertical: dict = {}
    drawn: list = []          # [(curve, names)]: curves of equal values drawn once
    colours = itertools.cycle(_BEARING_COLOURS)         # a colour again past the sixth (60 rotors: 120 bearings)
    for curve in result.curves:
        if curve.constant:
            for axis, value in (("xx", curve.kxx[0]), ("yy", curve.kyy[0])):
                vertical.setdefault(float(value), []).append((curve.name, axis))
            continue
        same = next((names for other, names in drawn if _equal(other, curve)), None)
        if same is not None:
            same.append(curve.name)
        else:
            drawn.append((curve, [curve.name]))
    (k0, k1), (n0, n1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())

    def where(k, rpm):
        # a curve the axes do not show keeps its legend entry, saying so (journal bearings of
        # 1e7 N/m beside a sweep from 1e9 N/m: two entries drawn nowhere)
        if np.any((k >= k0) & (k <= k1) & (rpm >= n0) & (rpm <= n1)):
            return ""
        side = ", to the left" if np.nanmax(k) < k0 else ", to the right" if np.nanmin(k) > k1 else ""
        return f" (outside the axes{side})"

    for curve, names in drawn:
        colour = next(colours)
        rpm = curve.speeds * 30 / np.pi
        ax.plot(curve.kxx * scale, rpm, color=colour, linewidth=1.3,
                label=f"{', '.join(names)} Kxx{where(curve.kxx * scale, rpm)}")
        ax.plot(curve.kyy * scale, rpm, color=colour, linewidth=1.3, linestyle="--",
                label=f"{', '.join(names)} Kyy{where(curve.kyy * scale, rpm)}")
    for value, owners in sorted(vertical.items()):
        names = list(dict.fromkeys(name for name, _ in owners))
        axes = "/".join(sorted({axis for _, axis in owners}))
        outside = "" if k0 <= value * scale <= k1 else " (outside the axes)"
        ax.axvline(value * scale, color=next(colours), linewidth=1.3, linestyle="-.",
                   label=f"{', '.join(names)} K{axes} = {value * scale:.3g} {unit}{outside}")


def _equal(a, b) -> bool:
    return (a.speeds.shape == b.speeds.shape and np.array_equal(a.speeds, b.speeds)
            and np.array_equal(a.kxx, b.kxx) and np.array_equal(a.kyy, b.kyy))


def _draw_crossings(ax, result, limits, scale=1.0) -> list:
    """A marker at every crossing (once per point); returned: (x, y, text, colour) of the speed
    to write beside each (placed among the curves by :func:`_place_labels`)."""
    seen, labels = set(), []
    for crossing in result.crossings:
        rpm = crossing.speed * 30 / np.pi
        stiffness = crossing.stiffness * scale
        key = (round(np.log(stiffness), 9), round(np.log(rpm), 9))
        if key in seen or not limits[0] <= rpm <= limits[1]:
            continue
        seen.add(key)
        ax.plot(stiffness, rpm, "o", markersize=6, markerfacecolor="white", markeredgecolor="k", zorder=5)
        labels.append((stiffness, rpm, f"{rpm:.0f}", "k"))
    return labels
