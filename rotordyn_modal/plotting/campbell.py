"""Campbell diagram figure."""

from __future__ import annotations

import numpy as np

from ._labels import exits_of_orders, laid_out_renderer, place_edge_labels, spread_apart
from ._style import WHIRL_STYLE, new_figure, speed_label, speed_scale

__all__ = ["plot_campbell"]


def plot_campbell(result, ax=None, speed_unit: str = "rpm", color_by: str | None = None,
                  sources=None, annotate_critical: bool = True, title: str | None = None):
    """Draw a Campbell diagram.

    Tracked modes are drawn solid blue where they whirl forward, dashed red
    backward and dotted grey without whirl; each rotor's (and gear mesh's)
    excitation orders are straight lines, labelled inside the axes where they leave
    them, apart from each other (close orders of one source share a label, a label with
    no room is left out: its line keeps its source's colour); critical speeds are marked.

    Parameters
    ----------
    result : CampbellResult
    ax : matplotlib Axes, optional
    speed_unit : {'rpm', 'rad/s', 'hz'}
    color_by : {None, 'log_decrement', 'damping_ratio'}
        Colour the mode curves by this quantity instead of by whirl.
    sources : list of str, optional
        Excitation sources to draw (default: all).
    annotate_critical : bool
        Write the critical speeds beside their markers.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure(ax)
    scale = speed_scale(speed_unit)
    x = result.speeds * scale
    if color_by:
        _draw_coloured(ax, fig, x, result, color_by)
    else:
        _draw_by_whirl(ax, x, result)
    top = 1.15 * (np.nanmax(np.where(result.oscillatory, result.frequencies_hz, np.nan))
                  if result.oscillatory.any() else 1.0)
    lines = _order_lines(result, sources)
    _draw_orders(ax, result, x, lines)
    _draw_critical(ax, result, scale, annotate_critical and len(result.critical) <= 24, sources)
    ax.set_ylim(0, top)
    ax.set_xlim(x.min(), x.max() if x.max() > x.min() else x.min() + 1)
    ax.set_xlabel(speed_label(speed_unit))
    ax.set_ylabel("Damped natural frequency [Hz]")
    ax.set_title(title or "Campbell diagram")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), fontsize="small", ncols=4, frameon=False)
    renderer = laid_out_renderer(fig)
    spread_apart([t for t in ax.texts if t.get_gid() == "mode-label"], renderer=renderer)
    place_edge_labels(ax, exits_of_orders(result.orders, lines, ax.get_xlim(), top, 1 / (2 * np.pi * scale)),
                      renderer=renderer)
    return fig


def _draw_by_whirl(ax, x, result):
    drawn = set()
    for m, label in enumerate(result.modes):
        f = np.where(result.oscillatory[:, m], result.frequencies_hz[:, m], np.nan)
        for whirl, style in WHIRL_STYLE.items():
            mask = _with_neighbours(result.whirl[:, m] == whirl)
            if not mask.any():
                continue
            kwargs = dict(style)
            if whirl in drawn:
                kwargs.pop("label")
            drawn.add(whirl)
            ax.plot(x, np.where(mask, f, np.nan), linewidth=1.6, **kwargs)
        _label_curve_end(ax, x, f, f"mode {label}")


def _with_neighbours(mask):
    """Extend a mask by one point each way so that segments join up."""
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    return out


def _draw_coloured(ax, fig, x, result, quantity):
    from matplotlib.collections import LineCollection

    values = {"log_decrement": result.log_decrements, "damping_ratio": result.damping_ratios}[quantity]
    finite = values[np.isfinite(values) & result.oscillatory]
    norm_range = (finite.min(), finite.max()) if finite.size else (0, 1)
    import matplotlib.colors as mcolors

    norm = mcolors.Normalize(*norm_range)
    for m, label in enumerate(result.modes):
        f = np.where(result.oscillatory[:, m], result.frequencies_hz[:, m], np.nan)
        points = np.stack([x, f], axis=1)
        segments = np.stack([points[:-1], points[1:]], axis=1)
        lines = LineCollection(segments, cmap="viridis", norm=norm, linewidth=2.0)
        lines.set_array(0.5 * (values[:-1, m] + values[1:, m]))
        ax.add_collection(lines)
        _label_curve_end(ax, x, f, f"mode {label}")
    fig.colorbar(lines, ax=ax, label=quantity.replace("_", " "))


def _label_curve_end(ax, x, f, text):
    valid = np.nonzero(np.isfinite(f))[0]
    if valid.size:
        k = valid[-1]
        ax.annotate(text, (x[k], f[k]), xytext=(3, 0), textcoords="offset points",
                    fontsize="x-small", va="center", gid="mode-label")


_ORDER_COLORS = ["0.2", "tab:green", "tab:purple", "tab:brown", "tab:olive", "tab:cyan"]


def _order_lines(result, sources):
    """(name, multiplier, colour) of each excitation source drawn."""
    return [(name, multiplier, _ORDER_COLORS[i % len(_ORDER_COLORS)])
            for i, (name, multiplier) in enumerate(zip(result.sources.names, result.sources.multipliers))
            if sources is None or name in sources]


def _draw_orders(ax, result, x, lines):
    """Straight order lines (labelled by :func:`place_edge_labels` once the axes are laid out)."""
    speeds_abs = np.abs(result.speeds)
    for _, multiplier, color in lines:
        for order in result.orders:
            ax.plot(x, order * multiplier * speeds_abs / (2 * np.pi), color=color, linewidth=0.9, alpha=0.8)


def _draw_critical(ax, result, scale, annotate, sources):
    critical = result.critical
    if not len(critical):
        return
    keep = np.array([sources is None or s in sources for s in critical.source], dtype=bool)
    ax.plot(critical.speeds[keep] * scale, critical.frequencies_hz[keep], "o", markersize=6,
            markerfacecolor="none", markeredgecolor="k", label="critical speed")
    if annotate:
        for speed, freq in zip(critical.speeds[keep] * scale, critical.frequencies_hz[keep]):
            ax.annotate(f"{speed:.0f}", (speed, freq), xytext=(4, -9), textcoords="offset points",
                        fontsize="xx-small")
