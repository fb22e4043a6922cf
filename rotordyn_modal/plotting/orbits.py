"""Orbit figure: the ellipses that probe pairs see, as on a rotor analyser's orbit display."""

from __future__ import annotations

import numpy as np

from ..units import unit_scale
from ..units import rpm_text

__all__ = ["plot_orbits"]

_SCALE = {"displacement": (1e6, "µm"), "velocity": (1e3, "mm/s"), "acceleration": (1.0, "m/s²")}
#: the orbit panels reach this much beyond the largest orbit drawn (a fraction of its reach)
_MARGIN = 0.1


def plot_orbits(result, speeds=None, source=None, title: str | None = None, units: str = "si"):
    """Orbits of every probe pair and source at a few speeds, with the keyphasor dot at t = 0:
    one panel per (pair, source), as in ``result.orbits()`` (rows pairs, columns sources).

    Parameters
    ----------
    result : UnbalanceResult
    speeds : array_like, optional
        Speeds to draw [rad/s] (nearest sweep points); default, per panel, the speed of
        that source's largest orbit and the sweep's last speed.
    source : str, optional
        Draw only this exciting rotor (default every source).
    title : str, optional
    units : {'si', 'us'}
        Unit system of the axes (SI: µm, mm/s, m/s²; US: mil, in/s, g).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    pairs = result.orbit_pairs
    if not pairs:
        raise ValueError("no probe pairs: give two sensors at one point with directions normal to the spin axis")
    sources = range(len(result.sources)) if source is None else [result.sources.index(source)]
    scale, unit = _SCALE.get(result.quantity, (1.0, "")) if units == "si" else unit_scale(result.quantity, units)
    rows, columns = len(pairs), len(sources)
    fig, axes = plt.subplots(rows, columns, figsize=(4.4 * columns, 4.4 * rows), squeeze=False,
                             layout="constrained")
    for p in range(rows):
        for c, s in enumerate(sources):
            _draw_orbit(axes[p, c], result, p, s, _chosen_speeds(result, s, speeds), scale, unit)
    fig.suptitle(title or "Unbalance orbits (each source rotor's 1X)")
    return fig


def _draw_orbit(ax, result, p, s, chosen, scale, unit):
    """The orbit of pair ``p`` excited by source ``s`` at the sweep points ``chosen``."""
    from matplotlib.ticker import MaxNLocator

    pair = result.orbit_pairs[p]
    reach = 0.0
    for n, k in enumerate(chosen):
        path = result.orbit_path(p, s, k) * scale
        reach = max(reach, float(np.max(np.abs(path))))
        colour = f"C{n % 10}"
        ax.plot(path[0], path[1], color=colour, label=f"{rpm_text(result.speeds[k] * 30 / np.pi)} rpm")
        ax.plot(path[0, 0], path[1, 0], "o", color=colour, ms=5)      # keyphasor: t = 0
        ax.annotate("", xy=(path[0, 12], path[1, 12]), xytext=(path[0, 6], path[1, 6]),
                    arrowprops={"arrowstyle": "->", "color": colour})
    # a square of fixed limits, the axes' box made square: with the limits left to the aspect
    # (adjustable 'datalim') they widened after the layout, and a tick label the layout had not
    # made room for ran off the figure ('0.010' of flexible_pump_on_mounts' pump orbit, US units)
    reach = reach * (1.0 + _MARGIN) if reach > 0.0 else 1.0
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal", adjustable="box")
    # at most five ticks across (the same up, on the square panel): labels like '-0.0075'
    # (orbits of nanometres) ran into each other, '-0.00030' at six ticks on the square
    ax.xaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.yaxis.set_major_locator(MaxNLocator(nbins=4))
    ax.axhline(0, color="0.8", lw=0.6)
    ax.axvline(0, color="0.8", lw=0.6)
    ax.set_xlabel(f"{pair[0]} [{unit}]")
    ax.set_ylabel(f"e × {pair[0]} [{unit}]  (e: spin axis)")     # the plane's second axis, w = e x u
    ax.set_title(f"{pair[0]} / {pair[1]}, 1X {result.sources[s]}", fontsize="medium")
    ax.legend(fontsize="small", title="dot: t = 0, arrow: direction", title_fontsize="small",
              loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=min(len(chosen), 3))


def _chosen_speeds(result, source, speeds):
    if speeds is not None:
        return [int(np.argmin(np.abs(result.speeds - v))) for v in np.atleast_1d(speeds)]
    size = np.abs(result.orbit_planes[:, source]).sum(axis=(0, 2))
    largest = int(np.argmax(size))
    last = len(result.speeds) - 1
    return [largest] if largest == last else [largest, last]
