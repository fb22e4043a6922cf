"""Issue 27 §3: an unbalance peak marker stands on the curve it names.

`unbalance examples/fan_on_bearings.toml --speeds 100:9000:181` labelled `AF 263.1 at 3587 rpm
(1X motor)` at the peaks table's 7.8 um, near the dashed 1X fan curves, while the solid 1X motor
curve it names reached 2 um there: the peak (AF 263, a band of 14 rpm) lies between two swept
speeds 49 rpm apart, and the line through the swept speeds cut it. Each curve is now drawn up to
the analysis' exact peaks.

Checked from outside the plotting code, on the figure the CLI draws (its artists) and the peaks
table the CLI hands it: every peak marker (the '▽' of a labelled peak) stands at its table row's
speed and amplitude (the row named by the marker's label: output by its colour, the legend's
curve of that colour, source by its words), and on that named curve as drawn: the curve's value
at the marker's speed, read from the curve's artists (its line and the lines in its colour and
style; between two vertices the value where the straight segment on the log axis passes).
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal.plotting.frf as frf
from rotordyn_modal.cli.main import main

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

# every example with unbalances, with its own documented options (each file's header) where it
# has some; --api-unbalance where the example names an --mcs
CASES = [
    ("fan_on_bearings", ["--speeds", "100:9000:181", "--sensor", "probe-DE-x,probe-DE-y"]),
    ("fan_on_bearings", ["--speeds", "100:9000:446", "--sensor", "probe-DE-x,probe-DE-y"]),
    ("compressor_on_journals", ["--speeds", "500:9000:171", "--mcs", "6600", "--api-unbalance"]),
    ("compressor_rotor", ["--speeds", "500:12000:231"]),
    ("compressor_rotor", ["--speeds", "200:13500:134", "--mcs", "9000", "--api-unbalance"]),
    ("flexible_pump_on_mounts", ["--speeds", "100:3600:71"]),
    ("motor_pump_on_mounts", ["--speeds", "100:3600:351"]),
    ("gear_machine", ["--speeds", "100:12000:120"]),
    ("journal_rotor", ["--speeds", "500:20000:196"]),
    ("motor_fan_minimal", ["--speeds", "100:6000:119"]),
    ("rubber_mounts", ["--speeds", "100:3600:71"]),
]


def _drawn(monkeypatch, tmp_path, name, options, units, shared_analyses):
    """(result, peaks table, figure) of the CLI's unbalance figure; its analysis computed once per
    worker for both systems (``shared_analyses``: the same SI doubles in both)."""
    shared_analyses("rotordyn_modal.analysis.unbalance", "unbalance_response", "api_unbalance_response")
    seen = {}
    plot = frf.plot_unbalance

    def recorded(result, *args, **kwargs):
        fig = plot(result, *args, **kwargs)
        seen.update(result=result, peaks=kwargs.get("peaks"), fig=fig)
        return fig

    monkeypatch.setattr(frf, "plot_unbalance", recorded)
    code = main(["unbalance", str(EXAMPLES / f"{name}.toml"), *options, "--units", units, "--quiet",
                 "--plot", str(tmp_path / "u.png")])
    assert code == 0
    return seen["result"], seen["peaks"], seen["fig"]


def _curve_pieces(ax, named):
    """The polylines ``[(x, y), ...]`` drawing the curve of the line ``named``: its own data,
    and each run of another line of ``ax`` in its colour (between NaNs) that starts and ends on
    two of its vertices (a stretch of the curve drawn through points between them)."""
    x0, y0 = (np.asarray(v, float) for v in named.get_data())
    colour = matplotlib.colors.to_hex(named.get_color())
    pieces = [(x0, y0)]

    def on_curve(x, y):
        return np.any(np.isclose(x0, x, rtol=1e-12, atol=0) & np.isclose(y0, y, rtol=1e-12, atol=0))

    for line in ax.get_lines():
        if line is named or matplotlib.colors.to_hex(line.get_color()) != colour:
            continue
        xs, ys = (np.asarray(v, float) for v in line.get_data())
        finite = np.isfinite(xs) & np.isfinite(ys)
        for run in np.split(np.arange(len(xs)), np.flatnonzero(np.diff(finite.astype(int))) + 1):
            if finite[run[0]] and len(run) > 1 and on_curve(xs[run[0]], ys[run[0]]) \
                    and on_curve(xs[run[-1]], ys[run[-1]]):
                pieces.append((xs[run], ys[run]))
    return pieces


def _value_on(pieces, x):
    """The value at ``x`` of the curve drawn by the polylines ``pieces`` (log y axis): the
    largest of its vertices at ``x`` and of its segments crossing ``x`` (straight on the log
    axis)."""
    values = []
    for xs, ys in pieces:
        for a in range(len(xs) - 1):
            (x0, x1), (y0, y1) = xs[a:a + 2], ys[a:a + 2]
            if not np.all(np.isfinite([x0, x1, y0, y1])) or y0 <= 0 or y1 <= 0:
                continue
            if np.isclose(x, x0, rtol=1e-12, atol=0):
                values.append(y0)
            if np.isclose(x, x1, rtol=1e-12, atol=0):
                values.append(y1)
            if min(x0, x1) < x < max(x0, x1):
                t = (x - x0) / (x1 - x0)
                values.append(np.exp(np.log(y0) + t * (np.log(y1) - np.log(y0))))
    return max(values, default=np.nan)


def _full_text(ax, label):
    """A marker's label text, its key's line where the label is a number."""
    text = label.get_text()
    if text.isdigit():
        keys = [t.get_text() for t in ax.texts if t.get_gid() == "peak-key" and t.get_text().startswith(f"{text}: ")]
        assert len(keys) == 1, text
        text = keys[0]
    return text


@pytest.mark.parametrize("units", ["si", "us"])
@pytest.mark.parametrize("name, options", CASES, ids=[f"{n}-{i}" for i, (n, _) in enumerate(CASES)])
def test_each_peak_marker_stands_on_its_curve(monkeypatch, tmp_path, name, options, units, shared_analyses):
    result, peaks, fig = _drawn(monkeypatch, tmp_path, name, options, units, shared_analyses)
    checked = 0
    for ax in fig.axes:
        markers = [line for line in ax.get_lines() if line.get_label() == "_peak"]
        curves = [line for line in ax.get_lines() if ": 1X " in line.get_label() and not line.get_label().startswith("_")]
        for marker in markers:
            (x,), (y,) = (np.asarray(v, float) for v in marker.get_data())
            label, = [t for t in ax.texts if getattr(t, "xy", None) == (x, y)]
            text = _full_text(ax, label)
            if "response unbounded" in text:           # an undamped mode's: at the axis' top, by design
                continue
            source = re.search(r"\(1X (.+?)\)", text).group(1)
            colour = matplotlib.colors.to_hex(marker.get_color())
            named, = [c for c in curves if matplotlib.colors.to_hex(c.get_color()) == colour
                      and c.get_label().split(" (=")[0].endswith(f": 1X {source}")]
            output = named.get_label().split(": 1X ")[0]
            i, j = result.outputs.index(output), result.sources.index(source)
            # the curve's axis factor (unit and convention) from its own line and the result
            drawn = np.asarray(named.get_ydata(), float)
            ok = (result.amplitude[i, j] > 0) & np.isfinite(drawn)
            factor = np.median(drawn[ok] / result.amplitude[i, j][ok])
            column = peaks["case"] if "case" in peaks else peaks["source"]
            rows = peaks[(peaks["output"] == output) & (column == source)
                         & np.isclose(peaks["speed_rpm"], x, rtol=1e-9, atol=0)]
            assert len(rows) == 1, (text, output)
            assert y == pytest.approx(rows["amplitude"].iloc[0] * factor, rel=1e-9), text
            assert y == pytest.approx(_value_on(_curve_pieces(ax, named), x), rel=1e-6), (text, output)
            checked += 1
    assert checked > 0 or name == "journal_rotor"       # its peaks: AF below 2.5 (not marked)
