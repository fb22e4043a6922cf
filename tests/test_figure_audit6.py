"""Figures of the sixth audit (issue 27, section 3: no hidden curve, no overprinted text),
measured on the drawn figure, independent of the code that places things.

The compressor rotor's first two modes (backward and forward whirl of one bending mode) lie at
95 Hz within a fraction of a line width of each other over the whole sweep: the forward curve,
drawn last, hid the backward one, and their critical speeds (2842/2855 rpm) printed as one
double circle. The rendered pixels along the pair must show both curves' colours; every text
keeps clear of every other; every critical speed is named. The gear machine's run-up left its
critical-speed line at 2067 rpm unlabelled in all three panels.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import outline, outlines_overlap

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def compressor_result():
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    return rdm.campbell(model, rdm.rpm(np.linspace(0.0, 12000.0, 41)), orders=(1, 2), max_frequency=450.0)


@pytest.fixture
def compressor(compressor_result):
    """The compressor's Campbell diagram (0-12000 rpm, orders 1 and 2, up to 450 Hz), drawn
    (each test its own figure: the suite closes every figure after each test)."""
    fig = compressor_result.plot()
    fig.canvas.draw()
    return compressor_result, fig


def _pixels(fig):
    """The rendered image ``(rows, columns, 3)`` [0-255], row 0 at the top."""
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(float)


def _near(pixels, colour, tolerance=60.0):
    """Whether each pixel is within ``tolerance`` (RGB distance) of ``colour``."""
    rgb = 255.0 * np.asarray(matplotlib.colors.to_rgb(colour))
    return np.linalg.norm(pixels - rgb, axis=-1) < tolerance


def test_coincident_modes_both_show_along_their_curves(compressor):
    """Modes 1 (backward, red) and 2 (forward, blue) lie on each other: in each stretch of the
    drawn pair away from the order lines, pixels of both colours show on the curve."""
    result, fig = compressor
    ax = fig.axes[0]
    first, second = (int(np.nonzero(result.modes == m)[0][0]) for m in (1, 2))
    f = result.frequencies_hz
    assert set(result.whirl[:, first]) == {"backward"} and set(result.whirl[:, second]) == {"forward"}
    image = _pixels(fig)
    height = image.shape[0]
    checked = 0
    for rpm in (800.0, 1600.0, 4000.0, 8000.0, 10000.0):        # clear of the order lines' crossings
        k = int(np.argmin(np.abs(result.speeds_rpm - rpm)))
        x, y = ax.transData.transform((result.speeds_rpm[k], f[k, first]))
        apart = abs(ax.transData.transform((result.speeds_rpm[k], f[k, second]))[1] - y)
        assert apart < 1.6 * fig.dpi / 72.0           # closer than the curves' width: one hides the other
        rows = slice(int(height - y) - 4, int(height - y) + 5)
        columns = slice(int(x) - 15, int(x) + 16)
        window = image[rows, columns]
        assert _near(window, "tab:red").sum() >= 6, rpm
        assert _near(window, "tab:blue").sum() >= 6, rpm
        checked += 1
    assert checked == 5


def test_coincident_modes_are_named_and_no_text_overprints_another(compressor):
    """Both curves of the pair keep their label; no two visible texts of the axes overlap (their
    outlines as drawn); every critical speed inside the axes is named by a label (two circles
    that read as one share a label '2842/2855')."""
    result, fig = compressor
    ax = fig.axes[0]
    renderer = fig.canvas.get_renderer()
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    names = [t.get_text() for t in texts if t.get_gid() == "mode-label"]
    assert "mode 1" in names and "mode 2" in names
    shapes = [outline(t, renderer) for t in texts]
    for i in range(len(texts)):
        for j in range(i + 1, len(texts)):
            assert not outlines_overlap(shapes[i], shapes[j]), (texts[i].get_text(), texts[j].get_text())
    critical = [t.get_text() for t in texts if t.get_gid() == "critical-label"]
    named = {word for t in critical for word in t.split("/")}
    # circles whose centres lie within each other's circle read as one: one label names both
    markers, = [line for line in ax.get_lines() if line.get_label() == "critical speed"]
    centres = ax.transData.transform(np.column_stack([markers.get_xdata(), markers.get_ydata()]))
    words = [f"{s:.0f}" for s in markers.get_xdata()]
    radius = 0.5 * markers.get_markersize() * fig.dpi / 72.0
    double = 0
    for i in range(len(centres)):
        for j in range(i + 1, len(centres)):
            if np.hypot(*(centres[i] - centres[j])) < radius:
                assert any({words[i], words[j]} <= set(t.split("/")) for t in critical), (words[i], words[j])
                double += 1
    assert double >= 2                                  # 2842/2855 and 5672/5723 rpm
    top = ax.get_ylim()[1]
    for speed, freq in zip(result.critical.speeds_rpm, result.critical.frequencies_hz):
        if freq <= top:
            assert f"{speed:.0f}" in named, speed


def test_runup_critical_line_between_tracks_is_labelled(monkeypatch):
    """A critical-speed line whose one-line label fits in no panel (the tracks leave a gap
    shorter than it at every height, the signal fills its panel) is labelled all the same,
    clear of every curve: the gear machine's run-up lost its 2067 rpm line's label so."""
    import types

    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box
    from rotordyn_modal.plotting.simulation import plot_runup
    from rotordyn_modal.simulation import runup

    from rotordyn_modal.analysis.critical_speeds import CriticalSpeeds

    speeds = rdm.rpm(np.linspace(0.0, 4000.0, 41))
    line = 2067.0
    # one track rising across the panel, one flat: at the line they lie at a third and two thirds
    # of the panel's height, gaps shorter than the one-line label (two fifths of the height)
    rising = 3.0 * np.linspace(0.0, 1.0, len(speeds)) ** 1.6
    flat = np.full(len(speeds), 2.0)
    tracks = {"shaft": runup.OrderTrack(speeds, 1e-6 * rising, 100.0 * rising, "probe", "shaft", 1.0),
              "fan": runup.OrderTrack(speeds, 1e-6 * flat, 100.0 * flat, "probe", "fan", 1.0)}
    fall = runup.Waterfall(speeds, np.linspace(0.0, 200.0, 41), np.full((len(speeds), 41), 1e-9), "probe")
    monkeypatch.setattr(runup, "order_track", lambda *args, rotor=None, **kwargs: tracks[rotor])
    monkeypatch.setattr(runup, "waterfall", lambda *args, **kwargs: fall)
    t = np.linspace(0.0, 1.0, 4000)
    result = types.SimpleNamespace(drive_speed=np.linspace(speeds[0], speeds[-1], 4000),
                                   rotor_names=["shaft", "fan"], model_name="test",
                                   sensor=lambda name: 1e-6 * np.sin(3000 * t))
    at = rdm.rpm(np.array([line]))
    critical = CriticalSpeeds(np.array(["fan"]), np.ones(1), np.array([3]), at, at / (2 * np.pi),
                              np.array(["forward"]), np.ones(1), np.full(1, 0.01))
    fig = plot_runup(result, "probe", critical=critical)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    labels = [(ax, t) for ax in fig.axes for t in ax.texts if t.get_text().startswith("mode ")]
    assert len(labels) == 1
    ax, text = labels[0]
    assert f"{line:.0f} rpm" in text.get_text()
    lines = [c for c in ax.get_lines() if c.get_label() == "_critical"]
    assert len(crossings(glyph_box(text, renderer), curve_segments(ax, skip=lines))) == 0
    plt.close(fig)


def test_coincident_coloured_modes_all_show():
    """Coloured by log decrement, the cross-coupled rotor's modes 2, 3 and 4 lie on each other at
    10 Hz over the whole sweep with log decrements 0.40, 0.15, 0.65 (speed-independent): the
    last drawn hid the others. Along the drawn line, pixels of each mode's own colour (the
    colour map at its log decrement) show in every stretch."""
    result = rdm.campbell(rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml"),
                          rdm.rpm(np.linspace(0.0, 20000.0, 41)))
    fig = result.plot(color_by="log_decrement")
    fig.canvas.draw()
    ax = fig.axes[0]
    columns = [int(np.nonzero(result.modes == m)[0][0]) for m in (2, 3, 4)]
    f, delta = result.frequencies_hz, result.log_decrements
    assert np.ptp(f[:, columns]) < 0.05 and np.all(np.ptp(delta[:, columns], axis=0) < 1e-6)
    finite = delta[np.isfinite(delta) & result.oscillatory]
    norm = matplotlib.colors.Normalize(finite.min(), finite.max())
    colours = [matplotlib.colormaps["viridis"](norm(delta[0, c])) for c in columns]
    image = _pixels(fig)
    for rpm in (5000.0, 10000.0, 15000.0):
        x, y = ax.transData.transform((rpm, f[0, columns[0]]))
        window = image[int(image.shape[0] - y) - 3:int(image.shape[0] - y) + 4, int(x) - 15:int(x) + 16]
        for mode, colour in zip((2, 3, 4), colours):
            assert _near(window, colour[:3], tolerance=30.0).sum() >= 6, (rpm, mode)
