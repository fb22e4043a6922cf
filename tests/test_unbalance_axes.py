"""The unbalance response figure's amplitude axes fit their curves (issue 27 §3).

Measured on the figure the command line draws (``unbalance ... --plot``), captured when it is
saved and drawn: each amplitude panel ends just above the largest value drawn in it (on a log
axis the empty band above the curves is a small share of the axis' height, not the decades
the probe panels had above sub-µm data), an API 617 probe limit far above the curves is still
named in the panel, and the tick labels of one axis are all plain decimals or all powers of
ten.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from matplotlib.figure import Figure

from rotordyn_modal.cli.main import main

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: share of a log amplitude axis' height above the largest value drawn that still reads as
#: "the axis fits its data" (room for a peak label; the defect was about a quarter)
_EMPTY_SHARE = 0.15

CASES = {
    "motor-pump-mcs": ["motor_pump_on_mounts.toml", "--speeds", "0:6000:31", "--mcs", "3000"],
    "fan-mcs": ["fan_on_bearings.toml", "--speeds", "100:9000:46", "--mcs", "3000"],
}


@pytest.fixture(scope="module")
def figures(tmp_path_factory):
    """``case -> figure`` that ``unbalance ARGS --plot`` saves, drawn once (made when first asked)."""
    made = {}

    def figure(case):
        if case not in made:
            made[case] = _drawn_figure(CASES[case], tmp_path_factory.mktemp(case))
        return made[case]

    return figure


def _drawn_figure(args, folder):
    saved, savefig = [], Figure.savefig

    def keep(fig, target, *a, **k):         # the figure kept, the file left empty (fast)
        saved.append(fig)
        Path(target).write_bytes(b"")

    Figure.savefig = keep
    try:
        model, *options = args
        assert main(["unbalance", str(EXAMPLES / model), *options, "--plot", str(folder / "u.png")]) == 0
    finally:
        Figure.savefig = savefig
    fig, = saved
    fig.canvas.draw()
    return fig


def _amplitude_axes(fig):
    return [ax for ax in fig.axes if ax.get_yscale() == "log" and ax.get_ylabel().startswith("Amplitude")]


def _largest_drawn(ax) -> float:
    values = [np.nanmax(np.asarray(line.get_ydata(), float)) for line in ax.get_lines()
              if np.any(np.isfinite(np.asarray(line.get_ydata(), float)))]
    return max(values)


@pytest.mark.parametrize("case", CASES)
def test_each_amplitude_axis_ends_just_above_its_curves(case, figures):
    fig = figures(case)
    axes = _amplitude_axes(fig)
    assert len(axes) == 2                                  # casing sensors and probes
    for ax in axes:
        low, high = ax.get_ylim()
        top = _largest_drawn(ax)
        assert high >= top, ax.get_title()
        share = np.log10(high / top) / np.log10(high / low)
        assert share <= _EMPTY_SHARE, (ax.get_title(), top, (low, high), share)


@pytest.mark.parametrize("case", CASES)
def test_the_probe_limit_is_drawn_in_range_or_named_above_it(case, figures):
    # API 617: 25.4 µm * sqrt(12000 / MCS [rpm]) pk-pk, at most 25.4 µm: 25.4 µm at 3000 rpm
    limit_0_peak_um = 25.4 / 2
    fig = figures(case)
    probes, = [ax for ax in _amplitude_axes(fig) if "probe" in ax.get_title()]
    assert "0-peak [µm]" in probes.get_ylabel()
    named = [t.get_text() for legend in fig.legends + [probes.get_legend()] if legend is not None
             for t in legend.get_texts() if "API 617 probe limit" in t.get_text()]
    assert named and all("25.4 µm pk-pk" in text for text in named), named
    low, high = probes.get_ylim()
    if low <= limit_0_peak_um <= high:
        levels = [np.nanmax(np.asarray(line.get_ydata(), float)) for line in probes.get_lines()
                  if str(line.get_label()).startswith("API 617")]
        assert np.isclose(levels, limit_0_peak_um, rtol=1e-9).any(), levels
    else:
        assert limit_0_peak_um > high and all("above the axis" in text for text in named), (named, high)


def _kinds(axis, view):
    """The formats of ``axis``'s labelled ticks in ``view``: 'power' (10^n) or 'plain'."""
    low, high = sorted(view)
    kinds = set()
    for tick in axis.get_major_ticks() + axis.get_minor_ticks():
        text = tick.label1.get_text()
        if tick.label1.get_visible() and text and low <= tick.get_loc() <= high:
            kinds.add("power" if re.search(r"10\^", text) else "plain")
    return kinds


@pytest.mark.parametrize("case", CASES)
def test_tick_labels_of_one_axis_share_one_format(case, figures):
    fig = figures(case)
    for ax in _amplitude_axes(fig):
        kinds = _kinds(ax.yaxis, ax.get_ylim())
        assert len(kinds) == 1, (ax.get_title(), [t.get_text() for t in ax.get_yticklabels()])
