"""Shared look of the package's figures."""

from __future__ import annotations

WHIRL_STYLE = {
    "forward": {"color": "tab:blue", "linestyle": "-", "label": "forward whirl"},
    "backward": {"color": "tab:red", "linestyle": "--", "label": "backward whirl"},
    "none": {"color": "0.45", "linestyle": ":", "label": "no whirl"},
}


def new_figure(ax=None, figsize=(8.0, 5.5)):
    """A figure and axes, or the figure of the axes given."""
    import matplotlib.pyplot as plt

    if ax is not None:
        return ax.figure, ax
    fig, ax = plt.subplots(figsize=figsize, layout="constrained")
    return fig, ax


def speed_label(unit: str) -> str:
    return {"rpm": "Speed of the reference rotor [rpm]", "rad/s": "Speed of the reference rotor [rad/s]",
            "hz": "Speed of the reference rotor [Hz]"}[unit]


def speed_scale(unit: str) -> float:
    """Factor from rad/s to ``unit``."""
    import math

    return {"rpm": 30.0 / math.pi, "rad/s": 1.0, "hz": 1.0 / (2.0 * math.pi)}[unit]
