"""The Campbell diagram both order-label audits draw (``test_figure_audit4.py``,
``test_figure_audit5.py``): a geared example at 0-12000 rpm with orders 1-4, drawn, its order
lines found on the figure (:func:`label_geometry.order_lines`), and the order lines a label
names read from its text."""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from label_geometry import named_orders, order_lines

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
#: an order label: ``2X fan``, ``2X, 3X, 4X motor``, ``2–4X gear``
ORDER_WORDS = r"(?P<orders>\d+(?:\.\d+)?X(?:, \d+(?:\.\d+)?X)*|\d+(?:\.\d+)?\u2013\d+(?:\.\d+)?X) (?P<source>.+)"
ORDERS = (1, 2, 3, 4)


@dataclass
class DrawnCampbell:
    """A drawn Campbell figure and what the audits read off it.

    Attributes
    ----------
    result : CampbellResult
    fig : matplotlib.figure.Figure
        Drawn (``fig.canvas.draw()``); the caller closes it.
    ax : matplotlib.axes.Axes
    renderer
    frame : matplotlib.transforms.Bbox
        The axes' window extent [display pixels].
    lines : dict
        :func:`label_geometry.order_lines`: slope [Hz per rpm] -> (display segment, line).
    multiplier : dict
        Excitation source -> its order lines' multiplier (rotor speed ratio, teeth, ...).
    """

    result: object
    fig: object
    ax: object
    renderer: object
    frame: object
    lines: dict
    multiplier: dict

    def named_slopes(self, text: str) -> set | None:
        """Slopes [Hz per rpm, 9 decimals] of the order lines the label ``text`` names (each
        one of :attr:`lines`: asserted), or None when ``text`` is no order label of a source."""
        match = re.fullmatch(ORDER_WORDS, text)
        if match is None or match["source"] not in self.multiplier:
            return None
        mine = {self.slope(match["source"], order) for order in named_orders(match["orders"])}
        assert mine <= set(self.lines), text
        return mine

    def slope(self, source: str, order: float) -> float:
        """Slope [Hz per rpm, 9 decimals] of ``source``'s order line ``order``."""
        return round(order * abs(self.multiplier[source]) / 60.0, 9)


@functools.lru_cache(maxsize=None)
def _campbell(model: str):
    """The Campbell diagram of ``examples/model`` (computed once per test process)."""
    return rdm.campbell(rdm.load_model(EXAMPLES / model), rdm.rpm(np.linspace(0, 12000, 25)), orders=ORDERS)


def drawn_campbell(model: str) -> DrawnCampbell:
    """``examples/model`` (gear_machine.toml, rubber_mounts.toml) at 0-12000 rpm, orders 1-4, drawn
    by ``result.plot()``; every source's four order lines found on the figure."""
    result = _campbell(model)
    fig = result.plot()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    drawn = DrawnCampbell(result, fig, ax, renderer, ax.get_window_extent(renderer), order_lines(ax),
                          dict(zip(result.sources.names, result.sources.multipliers)))
    assert len(drawn.lines) == len(ORDERS) * len(drawn.multiplier)
    return drawn
