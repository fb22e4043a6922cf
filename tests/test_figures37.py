"""Issue 27, section 3 ("figures that cannot mislead"): leftovers of the figures the CLI draws.

- FRF: a resonance narrower than the frequency step stood as an open diamond above the drawn
  line, the line between the two computed frequencies around it 3.3 times lower
  (``frf motor_pump_on_mounts.toml --speed 1500 --freqs 1:2000:800``, the pump's 529 Hz mode).
  The unbalance curves were drawn up to their peaks last session; the FRF's now are too. Checked
  from outside the figure code: `modal`'s damped natural frequencies and `frf` on a dense grid
  around each give the true peak; the curve drawn in its colour reaches it.
- Run-up: the gear machine's label 'mode 2, 1X fan / 1403 rpm' lay across the 1333 rpm line,
  which ran through its text: it read as that line's label. Checked on the drawn figure: no
  critical line farther than 3 pt from a label's own line runs through the label's box (lines
  closer than that read as one with its own), every critical speed is labelled or listed in the
  note, the labels lie inside their axes and apart.
- Unbalance: the dotted line of an unbounded peak (an undamped mode: amplitude inf) is drawn
  from the peaks table's data, not from the words of its label.
"""

from __future__ import annotations

import types
from pathlib import Path

import matplotlib
import matplotlib.colors as mcolors
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
RPM = np.pi / 30.0


# --- FRF: the line reaches the peaks it passes between computed frequencies -------------------

def _dense_peaks(model, speed, f, sensors):
    """Each sensor's [(frequency [Hz], |H| there), ...]: the local maxima of |H| on a 0.0005 Hz
    grid 0.3 Hz either side of each damped natural frequency (`modal`) inside ``f``, that lie more
    than sqrt(2) above both values on ``f`` around them (the peaks a line through ``f`` cuts)."""
    def compute(x):
        return rdm.frf(model, speed, x, inputs=["hammer-z"], outputs=sensors)

    grid = compute(f)
    roots = rdm.modal(model, speed)
    fd = roots.frequencies_hz[roots.oscillatory]
    fd = np.unique(np.round(fd[(fd > f[0]) & (fd < f[-1])], 6))
    windows = fd[:, None] + np.arange(-600, 601) * 0.0005
    dense = compute(windows.ravel())
    out = {}
    for name in sensors:
        o = grid.outputs.index(name)
        h = np.abs(grid.H[o, 0])
        values = np.abs(dense.H[o, 0]).reshape(windows.shape)
        found = []
        for x, y in zip(windows, values):
            for i in np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1:
                if not any(abs(x[i] - a) < 0.002 for a, _ in found):
                    found.append((x[i], y[i]))
        k = np.searchsorted(f, [a for a, _ in found])
        out[name] = [(a, b) for (a, b), c in zip(found, np.maximum(h[k - 1], h[k])) if b > np.sqrt(2) * c]
    return grid, out


def _drawn_max(ax, colour, low, high, style=None):
    """The largest value drawn between ``low`` and ``high`` on ``ax`` by the lines (with a line
    style: ``style``, where given) of ``colour``, their straight segments' ends included."""
    best = 0.0
    for line in ax.get_lines():
        if line.get_linestyle() in ("None", "none", "", " ") or not mcolors.same_color(line.get_color(), colour) \
                or style is not None and line.get_linestyle() != style or line.get_label() == "_overlap":
            continue
        x, y = (np.asarray(v, float) for v in line.get_data())
        keep = np.isfinite(x) & np.isfinite(y) & (x >= low) & (x <= high)
        best = max(best, float(np.max(y[keep], initial=0.0)))
    return best


def test_the_frf_line_reaches_each_resonance_it_passes_between_computed_frequencies():
    import matplotlib.pyplot as plt

    model, speed = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"), rdm.rpm(1500.0)
    f = np.linspace(1.0, 2000.0, 800)
    sensors = ["acc-pump-z", "probe-pump-x"]
    result, peaks = _dense_peaks(model, speed, f, sensors)
    assert sum(len(v) for v in peaks.values()) >= 4          # the case: cut peaks on both curves
    fig = result.plot()
    try:
        fig.canvas.draw()
        mag = fig.axes[0]
        colours = {str(line.get_label()).split(" ")[0]: line.get_color() for line in mag.get_lines()
                   if str(line.get_label()).split(" ")[0] in sensors}
        for name, found in peaks.items():
            for a, b in found:
                k = np.searchsorted(f, a)
                drawn = _drawn_max(mag, colours[name], f[k - 1], f[k])
                # the true peak, as the diamond and cut_peaks give it (within the dense step)
                assert b * (1 - 1e-6) <= drawn < b * (1 + 1e-4), (name, a, drawn / b)
        # nothing drawn above the curves' computed values and their true peaks
        top = max(np.abs(result.H).max(), max(b for v in peaks.values() for _, b in v))
        assert max(_drawn_max(mag, c, 0, 1e9) for c in colours.values()) <= top * (1 + 1e-4)
    finally:
        plt.close(fig)


# --- run-up: no label on another critical line ---------------------------------------------

def _gear_runup():
    """The gear machine run up from 100 to 3000 rpm in 3 s, its sensor's signal the linear
    steady unbalance response of each rotor at its own speed (no time integration: the figure's
    geometry is the case), with the 1X critical speeds of `campbell` at 121 speeds."""
    from rotordyn_modal.analysis.campbell import campbell
    from rotordyn_modal.simulation.runup import steady_orders

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    sensor = "acc-top-z"
    low, high, duration = 100.0 * RPM, 3000.0 * RPM, 3.0
    t = np.linspace(0.0, duration, 3001)
    rate = (high - low) / duration
    omega, phi = low + rate * t, low * t + 0.5 * rate * t ** 2
    names = [r.name for r in model.rotors]
    ratios = np.array([1.0, -0.4])                     # the gear's 2.5:1, the fan turning the other way
    grid = np.linspace(0.5 * low, 1.2 * high, 400)
    steady = rdm.unbalance_response(model, grid, outputs=[sensor], resonances=False)
    signal = np.zeros_like(t)
    for j, name in enumerate(steady.sources):
        h = steady.response[0, j]
        along = np.interp(omega, grid, h.real) + 1j * np.interp(omega, grid, h.imag)
        signal += np.real(along * np.exp(1j * abs(ratios[names.index(name)]) * phi))
    result = types.SimpleNamespace(time=t, drive_speed=omega, rotor_angles=np.column_stack([phi, ratios[1] * phi]),
                                   speed_ratios=ratios, rotor_names=names, model_name=model.name,
                                   sensor_names=[sensor], sensor=lambda name: signal)
    critical = campbell(model, np.linspace(low, high, 121)).critical
    return result, critical, steady_orders(model, result, sensor), sensor


def test_no_run_up_label_lies_on_another_critical_line():
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.simulation import plot_runup

    result, critical, steady, sensor = _gear_runup()
    rotors = np.isin(critical.source, result.rotor_names)
    speeds = critical.speeds[rotors] / RPM
    assert np.min(np.diff(np.sort(speeds))) < 20           # the case: lines 17 rpm apart, and 70
    with pytest.warns(UserWarning, match="run-up"):
        fig = plot_runup(result, sensor, critical=critical, steady=steady)
    try:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        read, boxes = set(), []
        for ax in fig.axes:
            lines = [float(np.asarray(line.get_xdata(), float)[0]) for line in ax.get_lines()
                     if line.get_label() == "_critical"]
            frame = ax.get_window_extent(renderer)
            for label in [t for t in ax.texts if t.get_visible() and t.get_text().startswith("mode ")]:
                box = label.get_window_extent(renderer)
                own = float(label.xy[0])
                at = ax.transData.transform((own, 0.0))[0]
                for x in lines:
                    px = ax.transData.transform((x, 0.0))[0]
                    far = abs(px - at) * 72.0 / fig.dpi > 3.0
                    assert not (far and box.x0 < px < box.x1), (label.get_text(), x)
                assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                text = label.get_text().replace("\n", ", ")
                assert text.endswith(f"{own:.0f} rpm")
                read.add(round(own, 6))
                boxes.append(box)
            for note in [t for t in ax.texts if t.get_visible() and "no room" in t.get_text()]:
                for entry in note.get_text().split("\n")[1:]:
                    for item in entry.split("; "):
                        value = float(item.rsplit(": ", 1)[1])
                        match = speeds[np.argmin(np.abs(speeds - value))]
                        assert abs(match - value) <= 0.5
                        read.add(round(match, 6))
                boxes.append(note.get_window_extent(renderer))
        assert read == {round(s, 6) for s in speeds}
        for i, a in enumerate(boxes):
            assert not any(a.overlaps(b) for b in boxes[i + 1:])
    finally:
        plt.close(fig)


# --- unbalance: an unbounded peak's dotted line from the data -------------------------------

def _relabelled(peak, text):
    """``peak`` (a chosen peak of the figure: x, amplitude, text, colour, source) with its text
    replaced by ``text`` and whatever else it carries kept."""
    new = type(peak).__new__(type(peak), (peak[0], peak[1], text, peak[3], peak[4]))
    if hasattr(peak, "__dict__"):
        new.__dict__.update(vars(peak))
    return new


def test_an_unbounded_peak_is_marked_from_the_data_not_from_its_words(tmp_path, monkeypatch):
    """examples/spring_block_rotor.toml (no damping) with an unbalance: the peaks table's rows
    are unbounded (amplitude inf) at the forward critical speed; the figure draws a dotted line
    there for each, and the same lines when the labels' words are other (a number of a key)."""
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting import frf

    path = tmp_path / "spring_block.toml"
    path.write_text((EXAMPLES / "spring_block_rotor.toml").read_text()
                    + '\n[[unbalances]]\nrotor = "disk"\namount = 1e-4\n')
    result = rdm.unbalance_response(rdm.load_model(path), np.linspace(0.0, 300.0, 61) * RPM)
    table = result.peaks()
    unbounded = sorted(table.loc[np.isposinf(table["amplitude"]), "speed_rpm"])
    assert unbounded                                     # the case
    chosen = []
    original = frf._marked_peaks
    monkeypatch.setattr(frf, "_marked_peaks", lambda *a, **k: chosen.append(original(*a, **k)) or chosen[-1])
    fig = result.plot(peaks=table)
    try:
        dotted = [line for ax in fig.axes for line in ax.get_lines() if line.get_label() == "_unbounded"]
        assert dotted
        for line in dotted:
            assert min(abs(float(line.get_xdata()[0]) - s) for s in unbounded) <= 1e-9 * unbounded[0]
        ax = fig.axes[0]
        for peaks in chosen:
            for n, peak in enumerate(peaks, start=1):
                before = len(ax.get_lines())
                frf._mark_unbounded(ax, [_relabelled(peak, str(n))], ax.get_ylim()[1])
                drawn = ax.get_lines()[before:]
                is_unbounded = min(abs(peak[0] - s) for s in unbounded) <= 1e-9 * unbounded[0]
                assert len(drawn) == int(is_unbounded), (peak[2], len(drawn))
    finally:
        plt.close(fig)
