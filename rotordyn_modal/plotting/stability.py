"""Stability figures: real parts over speed and maps over a parameter."""

from __future__ import annotations

import numpy as np

from ._style import WHIRL_STYLE, new_figure, speed_label, speed_scale

__all__ = ["plot_stability", "plot_stability_map"]


def plot_stability(result, speed_unit: str = "rpm", title: str | None = None):
    """Real parts and log decrements of the tracked modes over speed.

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
    x = result.speeds * speed_scale(speed_unit)
    for m, label in enumerate(result.modes):
        last_whirl = result.whirl[-1, m]
        style = WHIRL_STYLE.get(str(last_whirl), WHIRL_STYLE["none"])
        top.plot(x, result.real_parts[:, m], color=style["color"], linestyle=style["linestyle"],
                 label=f"mode {label} ({last_whirl} at the end)")
        bottom.plot(x, result.log_decrements[:, m], color=style["color"], linestyle=style["linestyle"])
    for axis in (top, bottom):
        axis.axhline(0.0, color="k", linewidth=0.8)
        for speed in result.thresholds:
            axis.axvline(speed * speed_scale(speed_unit), color="tab:red", linewidth=1.0, alpha=0.7)
        axis.grid(True, alpha=0.3)
    if np.isfinite(result.threshold_speed):
        top.annotate(f"threshold {result.threshold_speed * speed_scale(speed_unit):.0f}",
                     (result.threshold_speed * speed_scale(speed_unit), 0), xytext=(4, 6),
                     textcoords="offset points", color="tab:red", fontsize="small")
    top.set_ylabel("Real part of eigenvalue [1/s]\n(> 0: unstable)")
    bottom.set_ylabel("Log decrement [-]\n(< 0: unstable)")
    bottom.set_xlabel(speed_label(speed_unit))
    top.set_title(title or "Stability over speed")
    top.legend(fontsize="x-small", ncols=2)
    return fig


def plot_stability_map(result, speed_unit: str = "rpm", quantity: str = "min_damping_ratio",
                       title: str | None = None):
    """Map over speed and one parameter, with the stability boundary drawn.

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
    limit = np.nanmax(np.abs(field[np.isfinite(field)])) if np.isfinite(field).any() else 1.0
    mesh = ax.pcolormesh(x, y, field, cmap="RdBu" if quantity == "min_damping_ratio" else "RdBu_r",
                         vmin=-limit, vmax=limit, shading="nearest")
    fig.colorbar(mesh, ax=ax, label=quantity.replace("_", " "))
    if len(y) > 1 and len(x) > 1:
        ax.contour(x, y, result.max_real_parts, levels=[0.0], colors="k", linewidths=2.0)
    thresholds = result.threshold_speeds * speed_scale(speed_unit)
    ax.plot(thresholds, y, "k.", markersize=4, label="threshold speed (root-found)")
    ax.set_xlabel(speed_label(speed_unit))
    ylabel = result.key if result.mode_of_variation == "values" else f"scale of {result.key}"
    ax.set_ylabel(ylabel)
    ax.set_title(title or "Stability map (black line: boundary, red: unstable)")
    ax.legend(loc="upper right", fontsize="small")
    return fig
