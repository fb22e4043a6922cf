"""A resonance narrower than the FRF's frequency step is marked (issue 27, section 3: "figures
that cannot mislead"). ``frf motor_pump_on_mounts.toml --speed 1500 --freqs 1:2000:800``: the
pump's mode at 529 Hz has a half-power bandwidth of 0.15 Hz and the computed frequencies are
2.5 Hz apart, so the line between them drew its peak 3.3 times too low, on a stretch of the
axis that looks densely sampled (the dots mark sparse sampling on log axes only).

Checked from outside the figure code: `modal` gives the damped natural frequencies and `frf` at
each of them alone gives the true peak; the line drawn between the two computed frequencies
around it lies below the larger of them.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.colors as mcolors
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SENSORS = ["acc-pump-z", "probe-pump-x"]


@pytest.fixture(scope="module")
def pump():
    return rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"), rdm.rpm(1500.0)


def _true_cuts(model, speed, f):
    """{sensor: [(frequency, |H| there), ...]} of the maxima of |H| near the resonances (modal's
    damped natural frequencies; the interior local maxima of |H| on a dense 0.0005 Hz grid 1 Hz
    either side, one of those closer than 0.002 Hz: two close modes share one peak) that are
    more than sqrt(2) times both computed values around them."""
    grid = rdm.frf(model, speed, f, inputs=["hammer-z"], outputs=SENSORS)
    cuts = _dense_cuts(model, speed, f, np.abs(grid.H[:, 0]),
                       lambda x: rdm.frf(model, speed, x, inputs=["hammer-z"], outputs=SENSORS).H[:, 0])
    return dict(zip(SENSORS, cuts))


def _dense_cuts(model, speed, f, grid, evaluate):
    """Each curve's [(frequency, |H| there), ...] of :func:`_true_cuts`: ``grid`` (n_curves,
    len(f)) its values at ``f``, ``evaluate(x)`` (n_curves, len(x)) its response at ``x``."""
    roots = rdm.modal(model, speed)
    fd = roots.frequencies_hz[roots.oscillatory]
    fd = fd[(fd > f[0]) & (fd < f[-1])]
    step = np.arange(-2000, 2001) * 0.0005
    windows = fd[:, None] + step
    dense = np.abs(evaluate(windows.ravel()))
    out = []
    for h, values in zip(grid, dense):
        near = values.reshape(windows.shape)
        found = []
        for x, y in zip(windows, near):
            for i in np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1:
                if not any(abs(x[i] - a) < 0.002 for a, _ in found):
                    found.append((x[i], y[i]))
        k = np.searchsorted(f, [a for a, _ in found])
        around = np.maximum(h[k - 1], h[k])
        out.append([(a, b) for (a, b), c in zip(found, around) if b > np.sqrt(2) * c])
    return out


def _marks(ax):
    """The marker-only lines of the magnitude panel that are no curve: (colour, x, y) each point."""
    out = []
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if line.get_linestyle() in ("None", "none", "", " ") and len(x) and line.get_marker() not in (None, "None", "", "."):
            out += [(line.get_color(), a, b) for a, b in zip(x, y)]
    return out


def test_each_resonance_the_line_cuts_is_marked_at_its_peak_in_its_curves_colour(pump):
    """Every resonance whose true peak lies more than 3 dB above the drawn line (two on each
    curve's dense linear-looking stretch near 530-620 Hz, one in the sparse mount range) has a
    mark at its frequency and true height, in its curve's colour, inside the axes; no other
    mark. On main there were none."""
    import matplotlib.pyplot as plt

    model, speed = pump
    f = np.linspace(1.0, 2000.0, 800)
    cuts = _true_cuts(model, speed, f)
    assert any(500 < a < 650 for a, _ in cuts["acc-pump-z"])       # the dense stretch: the case
    result = rdm.frf(model, speed, f, inputs=["hammer-z"], outputs=SENSORS)
    fig = result.plot()
    fig.canvas.draw()
    mag = fig.axes[0]
    colours = {line.get_label().split(" ")[0]: line.get_color() for line in mag.get_lines()
               if line.get_label().split(" ")[0] in SENSORS}
    marks = _marks(mag)
    assert len(marks) == sum(len(v) for v in cuts.values())
    for name, expected in cuts.items():
        for a, b in expected:
            hits = [m for m in marks if mcolors.same_color(m[0], colours[name])
                    and abs(m[1] - a) < 0.0005 and b <= m[2] < (1 + 1e-4) * b]
            assert len(hits) == 1, (name, a)
    frame = mag.get_window_extent()
    low, high = mag.get_ylim()
    for _, x, y in marks:
        assert low < y < high and mag.get_xlim()[0] < x < mag.get_xlim()[1]
        px, py = mag.transData.transform((x, y))
        assert frame.x0 < px < frame.x1 and frame.y0 < py < frame.y1
    legend = fig.legends[0] if fig.legends else mag.get_legend()
    assert any("peak between computed frequencies" in t.get_text() for t in legend.get_texts())
    plt.close(fig)


def test_a_grid_that_resolves_every_resonance_has_no_mark(pump):
    """Around the 529 Hz mode at 0.02 Hz steps (its bandwidth 0.15 Hz): no resonance is cut,
    no mark, no legend entry (the figure as before)."""
    import matplotlib.pyplot as plt

    model, speed = pump
    f = np.linspace(520.0, 540.0, 1001)
    assert not any(_true_cuts(model, speed, f).values())
    fig = rdm.frf(model, speed, f, inputs=["hammer-z"], outputs=SENSORS).plot()
    fig.canvas.draw()
    assert not _marks(fig.axes[0])
    legend = fig.legends[0] if fig.legends else fig.axes[0].get_legend()
    assert not any("peak between" in t.get_text() for t in legend.get_texts())
    plt.close(fig)


def test_cut_peaks_of_a_single_mode_against_its_closed_form():
    """One mass on a spring and damper (m = 1 kg, k = 4e6 N/m, c = 4 N s/m: f_d = 318.3 Hz,
    half-power bandwidth c / (2 pi m) = 0.64 Hz), computed every 5 Hz: its peak |H| = 1 / (c w_d)
    is cut (more than 3 dB above the grid's values around it) and `cut_peaks` gives it at its
    maximum: f_r = f_n sqrt(1 - 2 zeta^2), |H| = 1 / (2 zeta k sqrt(1 - zeta^2))."""
    m, k, c = 1.0, 4e6, 4.0
    model = rdm.Model(stator=rdm.Stator(mass=m, inertia=[1.0, 1.0, 1.0]),
                      suspensions=[rdm.Suspension("s", [0, 0, 0], [k * 1e3, k * 1e3, k, 1e9, 1e9, 1e9],
                                                  damping=[0, 0, c, 0, 0, 0])],
                      sensors=[rdm.Sensor("z", [0, 0, 0], [0, 0, 1])],
                      excitations=[rdm.Excitation("f", [0, 0, 0], [0, 0, 1])])
    f = np.arange(1.0, 1000.0, 5.0)
    result = rdm.frf(model, 0.0, f)
    zeta = c / (2 * np.sqrt(k * m))
    wr = np.sqrt(k / m) * np.sqrt(1 - 2 * zeta ** 2)     # the receptance's maximum (f_d is 5e-7 above)
    at, h = result.cut_peaks("z", "f")
    assert at == pytest.approx([wr / (2 * np.pi)], rel=1e-7)
    # the closed form of the single mode's peak receptance
    expected = 1.0 / (2 * zeta * k * np.sqrt(1 - zeta ** 2))
    assert abs(h[0]) == pytest.approx(expected, rel=1e-9)


def test_force_frfs_mark_the_resonances_their_lines_cut(pump):
    """`frf --force-outputs suspensions` (the help's example) draws the mounts' forces through
    the same 2.5 Hz grid: each mount force's maxima near a damped natural frequency (`modal`;
    the dense maxima of `force_frf` as :func:`_true_cuts`) that are more than sqrt(2) times both
    grid values around them are given by `cut_peaks` (within the dense step, not below that
    height and within 1e-4 above it), and no other; the figure marks each (an open diamond at
    that height); the CSV's numbers are those of the grid alone."""
    import matplotlib.pyplot as plt

    model, speed = pump
    f = np.linspace(1.0, 2000.0, 800)
    result = rdm.force_frf(model, speed, f, inputs=["hammer-z"], where="suspensions")
    cuts = _dense_cuts(model, speed, f, np.abs(result.H[:, 0]),
                       lambda x: rdm.force_frf(model, speed, x, inputs=["hammer-z"], where="suspensions").H[:, 0])
    total = 0
    for o, name in enumerate(result.outputs):
        if np.abs(result.H[o, 0]).max() == 0:
            continue
        found, values = result.cut_peaks(name, "hammer-z")
        assert len(found) == len(cuts[o]), name
        for a, b in cuts[o]:
            hits = [(x, v) for x, v in zip(found, np.abs(values)) if abs(x - a) < 0.0005 and b <= v < (1 + 1e-4) * b]
            assert len(hits) == 1, (name, a)
        total += len(found)
    assert total >= 10
    fig = result.plot()
    fig.canvas.draw()
    marks = sum(len(_marks(ax)) for ax in fig.axes)
    assert marks == total
    plt.close(fig)
