"""Shared look of the package's figures."""

from __future__ import annotations

import functools

import numpy as np

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


#: amplitude units of a kind and system, smallest first: (label, factor from the SI unit); the
#: figure takes the largest in which the largest amplitude drawn is at least 1
_READABLE_UNITS = {
    ("displacement", "si"): (("µm", 1e6), ("mm", 1e3), ("m", 1.0)),
    ("displacement", "us"): (("mil", 1e3 / 0.0254), ("in", 1.0 / 0.0254)),
    ("velocity", "si"): (("mm/s", 1e3), ("m/s", 1.0)),
}


def readable_scale(kind: str, largest: float, system: str = "si") -> tuple:
    """``(factor, label)`` of the unit that writes amplitudes of ``kind`` up to ``largest`` (in
    the SI unit of the kind) from 1 up where the system has one, else in its smallest (µm for
    a 25 µm casing curve and a 0.3 µm probe, mm for a 2 mm orbit; mil, or in, in US units): an
    SI value times ``factor`` is the number on the axis. Other kinds (acceleration, force) keep
    :func:`units.unit_scale`'s unit."""
    from ..units import check_system, unit_scale

    ladder = _READABLE_UNITS.get((kind, check_system(system)))
    if ladder is None:
        return unit_scale(kind, system)
    label, factor = ladder[0]
    for name, scale in ladder:
        if np.isfinite(largest) and largest * scale >= 1 - 1e-12:
            label, factor = name, scale
    return factor, label


def plain_log_ticks(axis):
    """Label a log ``axis`` (``ax.yaxis``) with plain decimals (0.0001, 0.01, 1, 100) where every
    decade in view lies from 0.000001 to 100,000, else all its ticks as powers of ten (one
    format per axis): the decades read in the axis' own unit."""
    formatter = _plain_log_formatter()
    axis.set_major_formatter(formatter())
    axis.set_minor_formatter(formatter(labelOnlyBase=False, minor_thresholds=(2, 0.4)))


#: tick values written as plain decimals on log axes (beyond: powers of ten, then on the whole
#: axis); down to a millionth: an unbalance panel's six decades below its largest curve
_PLAIN_LOW, _PLAIN_HIGH = 1e-6, 1e6


@functools.cache
def _plain_log_formatter():
    """matplotlib's log tick formatter (it decides which ticks are labelled) writing the values
    in [:data:`_PLAIN_LOW`, :data:`_PLAIN_HIGH`) as plain decimals."""
    from matplotlib.ticker import LogFormatterSciNotation

    class PlainLogFormatter(LogFormatterSciNotation):
        plain = True

        def set_locs(self, locs=None):
            # one format per axis: plain only when every decade in view is in the plain range
            super().set_locs(locs)
            low, high = sorted(self.axis.get_view_interval()) if self.axis is not None else (1.0, 1.0)
            self.plain = low > 0 and _PLAIN_LOW * (1 - 1e-9) <= 10 ** np.ceil(np.log10(low) - 1e-9) \
                and 10 ** np.floor(np.log10(high) + 1e-9) < _PLAIN_HIGH

        def __call__(self, x, pos=None):
            text = super().__call__(x, pos)
            if not text or not self.plain or not _PLAIN_LOW * (1 - 1e-9) <= abs(x) < _PLAIN_HIGH:
                return text
            return np.format_float_positional(float(f"{x:.6g}"), trim="-")

    return PlainLogFormatter


def fitted_title(fig, text: str, share: float, fontsize="large") -> str:
    """``text`` wrapped onto lines no wider than ``share`` of the figure's width, drawn at
    ``fontsize``: an axes' title is centred over the axes, so a long model name over an axes
    narrowed by a colour bar ran off the figure's left edge."""
    import textwrap

    from ._labels import text_size

    lines = text.split("\n")
    width = max(text_size(fig, line, fontsize, fig.canvas.get_renderer())[0] for line in lines)
    allowed = share * fig.bbox.width
    if width <= allowed:
        return text
    characters = max(int(max(len(line) for line in lines) * allowed / width), 20)
    return "\n".join(textwrap.fill(line, characters) for line in lines)
