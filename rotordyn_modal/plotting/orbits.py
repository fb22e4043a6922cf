"""Orbit figure: the ellipses that probe pairs see, as on a rotor analyser's orbit display."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_orbits"]

_SCALE = {"displacement": (1e6, "µm"), "velocity": (1e3, "mm/s"), "acceleration": (1.0, "m/s²")}


def plot_orbits(result, speeds=None, source=None, title: str | None = None):
    """Orbits of every probe pair at a few speeds, with the keyphasor dot at t = 0.

    Parameters
    ----------
    result : UnbalanceResult
    speeds : array_like, optional
        Speeds to draw [rad/s] (nearest sweep points); default the speed of the
        largest orbit and the sweep's last speed.
    source : str, optional
        The exciting rotor (default the first source).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    pairs = result.orbit_pairs
    if not pairs:
        raise ValueError("no probe pairs: give two sensors at one point with directions normal to the spin axis")
    s = 0 if source is None else result.sources.index(source)
    scale, unit = _SCALE.get(result.quantity, (1.0, ""))
    columns = min(len(pairs), 3)
    rows = int(np.ceil(len(pairs) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 4.2 * rows), squeeze=False,
                             layout="constrained")
    for ax in axes.ravel()[len(pairs):]:
        ax.set_visible(False)
    chosen = _chosen_speeds(result, s, speeds)
    phase = np.linspace(0, 2 * np.pi, 181)
    for p, ax in zip(range(len(pairs)), axes.ravel()):
        for n, k in enumerate(chosen):
            plane = result.orbit_planes[p, s, k] * scale
            path = np.real(plane[:, None] * np.exp(1j * phase))
            colour = f"C{n % 10}"
            ax.plot(path[0], path[1], color=colour, label=f"{result.speeds[k] * 30 / np.pi:.0f} rpm")
            ax.plot(path[0, 0], path[1, 0], "o", color=colour, ms=5)      # keyphasor: t = 0
            ax.annotate("", xy=(path[0, 12], path[1, 12]), xytext=(path[0, 6], path[1, 6]),
                        arrowprops={"arrowstyle": "->", "color": colour})
        ax.set_aspect("equal", adjustable="datalim")
        ax.axhline(0, color="0.8", lw=0.6)
        ax.axvline(0, color="0.8", lw=0.6)
        ax.set_xlabel(f"{pairs[p][0]} [{unit}]")
        ax.set_ylabel(f"e × {pairs[p][0]} [{unit}]")
        ax.set_title(f"{pairs[p][0]} / {pairs[p][1]}", fontsize="medium")
        ax.legend(fontsize="small", title="dot: t = 0, arrow: direction")
    fig.suptitle(title or f"Unbalance orbits, excited by {result.sources[s]}")
    return fig


def _chosen_speeds(result, source, speeds):
    if speeds is not None:
        return [int(np.argmin(np.abs(result.speeds - v))) for v in np.atleast_1d(speeds)]
    size = np.abs(result.orbit_planes[:, source]).sum(axis=(0, 2))
    largest = int(np.argmax(size))
    last = len(result.speeds) - 1
    return [largest] if largest == last else [largest, last]
