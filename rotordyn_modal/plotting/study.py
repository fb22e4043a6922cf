"""Figures of parameter studies: Campbell tolerance bands, critical-speed histograms,
stability maps over two grid parameters, sensitivity bars. They draw a
:class:`~rotordyn_modal.study.StudyResult` (or a sensitivity table); they compute nothing
beyond percentiles of what is stored."""

from __future__ import annotations

import numpy as np

from ..units import rpm_text
from ._style import new_figure, speed_label, speed_scale

__all__ = ["plot_study_campbell", "plot_critical_histograms", "plot_study_stability_map", "plot_sensitivity"]


#: the figure each analysis of a study file draws: a figure asked of a study without its analysis
#: is refused with this line (the command checks it before the work)
FIGURE_ANALYSES = {"plot_study_campbell": ("campbell", "frequency_hz"),
                   "plot_critical_histograms": ("critical_speeds", "critical_speed"),
                   "plot_study_stability_map": ("stability", "instability_speed")}


def _needs(result, figure):
    """Refuse (InputError) to draw ``figure`` of a study that did not run its analysis."""
    from ..errors import InputError

    analysis, variable = FIGURE_ANALYSES[figure]
    if variable not in result.dataset:
        raise InputError(f"{figure}: the study has no '{analysis}' analysis (add [analyses.{analysis}] "
                         f"to the study file, docs/study-file.md)")


def _band(ax, band_rpm, scale_rpm, label="operating band"):
    """The operating band, hatched grey: a band filled in orange took mode 2's colour (its
    percentile band) and read as one of the modes' bands."""
    if band_rpm is not None:
        ax.axvspan(band_rpm[0] * scale_rpm, band_rpm[1] * scale_rpm, facecolor=(0.75, 0.75, 0.75, 0.25),
                   edgecolor="0.55", hatch="//", linewidth=0.0, label=label, zorder=0.5)


def plot_study_campbell(result, percentiles=(5.0, 95.0), band_rpm=None, speed_unit: str = "rpm",
                        ax=None, title: str | None = None):
    """Campbell diagram: median and percentile envelope of each tracked mode over variants.

    Parameters
    ----------
    result : StudyResult
        With the ``campbell`` analysis.
    percentiles : (float, float)
        Envelope drawn as a band [percent].
    band_rpm : (float, float), optional
        Operating band [rpm], shaded.
    speed_unit : {'rpm', 'rad/s', 'hz'}
    ax : matplotlib Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    _needs(result, "plot_study_campbell")
    ds = result.dataset
    fig, ax = new_figure(ax)
    x = ds["speed"].values * speed_scale(speed_unit)
    *bands, highest = result.frequency_envelope(percentiles)          # one pass over the modes
    colors = [f"C{i}" for i in range(10)]
    for m, label in enumerate(ds["mode"].values):
        low, mid, high = (band[m] for band in bands)
        if not np.isfinite(highest[m]):
            continue
        ax.fill_between(x, low, high, color=colors[m % 10], alpha=0.25, linewidth=0)
        ax.plot(x, mid, color=colors[m % 10], label=f"mode {label}")
    top = 1.1 * (np.nanmax(highest) if np.isfinite(highest).any() else 1.0)
    if "excitation" in ds.coords:
        _excitation_lines(ax, x, np.abs(ds["speed"].values), ds["excitation"].values, ds["excitation_slope"].values, top)
    _band(ax, band_rpm, speed_scale(speed_unit) * np.pi / 30)
    ax.set_ylim(0, top)
    ax.set_xlabel(speed_label(speed_unit))
    ax.set_ylabel("Damped natural frequency [Hz]")
    ax.set_title(title or f"Campbell diagram: median and {percentiles[0]:g}-{percentiles[1]:g} % band "
                 f"of {int((~result.failed).sum())} variants")
    ax.legend(fontsize="small", ncols=2, loc="lower right")
    ax.grid(True, alpha=0.3)
    if "excitation" in ds.coords:
        _label_excitations(ax, ds["excitation"].values, ds["excitation_slope"].values / speed_scale(speed_unit))
    return fig


def _excitation_lines(ax, x, speeds, names, slopes, top):
    """Dashed excitation lines (base model), labelled by :func:`_label_excitations`."""
    for name, slope in zip(names, slopes):
        ax.plot(x, slope * speeds, color="0.4", linewidth=0.8, linestyle="--", gid=f"excitation:{name}")


def _label_excitations(ax, names, slopes):
    """Each excitation line's name beside it where it leaves the frame, inside the axes, clear
    of the other labels, the legend and every curve (the Campbell diagram's edge labels);
    ``slopes`` [Hz per unit of the speed axis]."""
    from ._labels import CurveMap, EdgeLabel, edge_label_boxes, laid_out_renderer, line_exit

    renderer = laid_out_renderer(ax.figure)
    to_axes = ax.transAxes.inverted()
    placed = [tuple(to_axes.transform(ax.get_legend().get_window_extent(renderer)).ravel())] \
        if ax.get_legend() else []
    bottom, top = ax.get_ylim()
    labels = []
    for name, slope in zip(names, slopes):
        exit_ = line_exit(float(slope), ax.get_xlim(), top, bottom)
        if exit_ is not None:
            prefix, _, suffix = str(name).rpartition(" ")
            labels.append(EdgeLabel(prefix or str(name), suffix if prefix else "", "0.3", *exit_))
    curves = CurveMap(ax, renderer, units="axes")
    for label, (left, low, _, _) in edge_label_boxes(ax, labels, "x-small", renderer, placed, curves):
        ax.text(left, low, label.text.strip(), transform=ax.transAxes, fontsize="x-small", color=label.color,
                ha="left", va="bottom", gid="excitation-label")


def plot_critical_histograms(result, band_rpm=None, bins: int = 25, max_crossings: int = 6,
                             min_fraction: float = 0.5, title: str | None = None):
    """Histograms of critical speeds [rpm], one panel per crossing (source, order, mode).

    Parameters
    ----------
    result : StudyResult
        With the ``critical_speeds`` analysis.
    band_rpm : (float, float), optional
        Operating band [rpm], shaded; the crossings nearest it are drawn first.
    bins : int
    max_crossings : int
        At most this many panels (nearest the band, else the lowest by median).
    min_fraction : float
        Crossings present in fewer variants than this fraction are left out.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    _needs(result, "plot_critical_histograms")
    ds = result.dataset
    speeds = np.abs(ds["critical_speed"].values[~result.failed]) * 30 / np.pi  # (variant, crossing) rpm
    present = np.isfinite(speeds).mean(axis=0) >= min_fraction
    median = np.nanmedian(np.where(present, speeds, np.inf), axis=0)
    rank = median if band_rpm is None else np.abs(median - 0.5 * (band_rpm[0] + band_rpm[1]))
    chosen = [i for i in np.argsort(rank) if present[i]][:max_crossings]
    columns = 2 if len(chosen) > 1 else 1
    rows = max(1, -(-len(chosen) // columns))
    fig, axes = plt.subplots(rows, columns, figsize=(8.0, 2.4 * rows + 0.6), layout="constrained", squeeze=False)
    for ax, i in zip(axes.flat, sorted(chosen, key=lambda i: median[i])):
        x = speeds[:, i][np.isfinite(speeds[:, i])]
        ax.hist(x, bins=bins, color="tab:blue", alpha=0.7)
        _band(ax, band_rpm, 1.0)
        ax.set_title(f"{ds['crossing_source'].values[i]} {ds['crossing_order'].values[i]:g}X, "
                     f"mode {ds['crossing_mode'].values[i]}", fontsize="small")
        ax.set_xlim(*_window(x, band_rpm))
    for ax in axes.flat[len(chosen):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("Critical speed [rpm]")
    for ax in axes[:, 0]:
        ax.set_ylabel("Variants")
    for ax in axes.flat:            # counts: whole numbers (a few variants got ticks at 0.5)
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    fig.suptitle(title or f"Critical speeds over {int((~result.failed).sum())} variants"
                 + ("" if band_rpm is None else " (hatched: operating band)"))
    return fig


def _window(x, band):
    """x-limits: the data padded by 10 %, widened to the band when the band is near."""
    pad = 0.1 * (np.ptp(x) or abs(x.mean()) or 1.0)
    low, high = x.min() - pad, x.max() + pad
    if band is not None and band[0] < high + 3 * pad and band[1] > low - 3 * pad:
        low, high = min(low, band[0] - pad), max(high, band[1] + pad)
    return low, high


def plot_study_stability_map(result, x: str | None = None, y: str | None = None, speed_rpm: float | None = None,
                             ax=None, title: str | None = None, scales=None):
    """Threshold speed over two grid parameters, with the boundary of stability up to a speed.

    Parameters
    ----------
    result : StudyResult
        A grid study (two grid parameters, no distributions) with the
        ``stability`` analysis.
    x, y : str, optional
        Parameter names (default: the two grid parameters in order).
    speed_rpm : float, optional
        The boundary is where the lowest unstable speed equals this speed
        (default: half the top of the stability sweep).
    ax : matplotlib Axes, optional
    title : str, optional
    scales : dict, optional
        ``{parameter name: (factor, unit)}``: the parameter's values (SI) times ``factor`` are drawn,
        its axis named with ``unit`` (``rotordyn-modal --units us study``); default as sampled.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..errors import InputError

    _needs(result, "plot_study_stability_map")
    ds = result.dataset
    scales = scales or {}
    grid = [str(p) for p, g in zip(ds["parameter"].values, ds["parameter_is_grid"].values) if g]
    x, y = x or (grid[0] if grid else None), y or (grid[1] if len(grid) > 1 else None)
    if x is None or y is None or len(grid) != ds.sizes["parameter"]:
        raise InputError("a stability map needs a study over exactly two grid parameters")
    values = result.samples
    xs, ys = np.unique(values[x]), np.unique(values[y])
    table = values.assign(threshold=ds["instability_speed"].values * 30 / np.pi)
    field = table.pivot_table(index=y, columns=x, values="threshold", dropna=False, aggfunc="first")
    field = field.reindex(index=ys, columns=xs).values
    top = ds["stability_speed"].values.max() * 30 / np.pi
    level = 0.5 * top if speed_rpm is None else speed_rpm
    fig, ax = new_figure(ax)
    import matplotlib

    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85")
    (x_factor, x_unit), (y_factor, y_unit) = (scales.get(name, (1.0, None)) for name in (x, y))
    xs, ys = xs * x_factor, ys * y_factor
    mesh = ax.pcolormesh(xs, ys, np.ma.masked_invalid(field), cmap=cmap, shading="nearest")
    fig.colorbar(mesh, ax=ax, label="lowest unstable speed [rpm] (grey: stable over the sweep)")
    filled = np.where(np.isfinite(field), field, 2 * top)
    if len(xs) > 1 and len(ys) > 1 and filled.min() < level < filled.max():
        ax.contour(xs, ys, filled, levels=[level], colors="k", linewidths=2.0)
    ax.set_xlabel(x if x_unit is None else f"{x} [{x_unit}]")
    ax.set_ylabel(y if y_unit is None else f"{y} [{y_unit}]")
    ax.set_title(title or f"Stability map: stable up to {rpm_text(level)} rpm below/right of the black line")
    return fig


#: colour of the sensitivity bars' standard errors (grey: apart from the black S1 diamonds)
_ERROR_COLOUR = "0.45"


def _index_keys(column, table):
    """Legend entries of the sensitivity chart's marks: the S1 diamond, the standard error."""
    from matplotlib.lines import Line2D

    keys = []
    if column == "ST":
        keys.append(Line2D([], [], ls="none", marker="D", color="k", markeredgecolor="w", markersize=4.5,
                           label="first order index S1"))
    if f"{column}_se" in table:
        keys.append(Line2D([], [], color=_ERROR_COLOUR, lw=1.0, label="\u00b1 standard error"))
    return keys


#: bars shorter than this share of the chart's longest are not seen (a pixel or two)
_UNSEEN = 0.01


def plot_sensitivity(table, outputs=None, max_outputs: int = 6, ax=None, title: str | None = None):
    """Bar chart of sensitivity indices, grouped by output.

    Parameters
    ----------
    table : pandas.DataFrame
        From :meth:`StudyResult.sensitivity`: ``output, parameter`` and ``S1``/``ST``
        (Sobol) or ``SRC`` (regression).
    outputs : list of str, optional
        Outputs to draw (default: the first ``max_outputs``).
    max_outputs : int
    ax : matplotlib Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(outputs or list(dict.fromkeys(table["output"]))[:max_outputs])
    parameters = list(dict.fromkeys(table["parameter"]))
    column = "ST" if "ST" in table else "SRC"
    fig, ax = new_figure(ax, figsize=(8.0, 1.2 + 0.5 * len(names) * max(1, len(parameters)) ** 0.5))
    height = 0.8 / max(1, len(parameters))
    shown = table[table["output"].isin(names)]
    span = float(np.nanmax(np.abs(shown[column].to_numpy(float)), initial=0.0))
    for j, parameter in enumerate(parameters):
        rows = table[table["parameter"] == parameter].set_index("output").reindex(names)
        position = np.arange(len(names)) + j * height
        error = rows[f"{column}_se"].values if f"{column}_se" in rows else None
        # a parameter whose bars are too short to be seen says so in its legend entry (the fan's
        # inertia in mount_sobol: a colour in the legend, no bar of it on the chart)
        largest = float(np.nanmax(np.abs(rows[column].to_numpy(float)), initial=0.0))
        note = f" ({column} {largest:.1g} or less: no bar seen)" if largest < _UNSEEN * span else ""
        ax.barh(position, rows[column].values, height=height, xerr=error, label=f"{parameter}{note}",
                error_kw={"ecolor": _ERROR_COLOUR, "elinewidth": 1.0})
        if column == "ST":      # a diamond: a black '|' on the black error bar read as its end
            ax.plot(rows["S1"].values, position, "D", color="k", markeredgecolor="w", markersize=4.5,
                    gid="first-order")
    ax.set_yticks(np.arange(len(names)) + 0.4 - height / 2, names, fontsize="small")
    ax.invert_yaxis()
    ax.axvline(0.0, color="k", linewidth=0.8)
    ax.set_xlabel({"ST": "total Sobol index ST (\u25c6 first order index S1)",
                   "SRC": "standardised regression coefficient"}[column])
    ax.set_title(title or "Sensitivity of each output to each parameter")
    handles, _ = ax.get_legend_handles_labels()
    handles += _index_keys(column, table)
    # below the axes: inside ('best') it covered the longest bars
    ax.legend(handles=handles, fontsize="x-small", loc="upper center",
              bbox_to_anchor=(0.5, -0.1 if len(names) > 2 else -0.25), ncols=2, frameon=False)
    return fig
