"""Figures of the eleventh audit (issue 27, section 3: figures that cannot mislead): where the
Campbell diagram changes a mode's whirl style (checked against the whirl ratio of modal analyses
at speeds between the sweep's), and what the stability figure's legend and axes show.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
TOLERANCE = 1e-3          # |whirl ratio| of 'no whirl' (docs/theory.md section 9)
COLOURS = {"forward": "tab:blue", "backward": "tab:red", "none": "0.45"}


@pytest.fixture(scope="module")
def motor_pump():
    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    return model, rdm.campbell(model, rdm.rpm(np.linspace(0.0, 3600.0, 37)), orders=(1,), critical=False)


def _stretches(ax, result, mode, whirl):
    """The speed intervals [rpm] over which ``mode``'s (1-based) curve is drawn in ``whirl``'s
    style: the segments of the lines of that colour that pass through the mode's own points at
    the sweep's speeds."""
    import matplotlib.colors as mcolors

    f = np.where(result.oscillatory[:, mode - 1], result.frequencies_hz[:, mode - 1], np.nan)
    rpm = result.speeds_rpm
    out = []
    for line in ax.get_lines():
        if not mcolors.same_color(line.get_color(), COLOURS[whirl]):
            continue
        x, y = (np.asarray(v, dtype=float) for v in line.get_data())
        if len(x) < len(rpm):
            continue
        at = np.argmin(np.abs(x[:, None] - rpm[None, :]), axis=0)
        if not np.allclose(x[at], rpm):
            continue
        if not np.any(y[at] == f):                    # another mode's line
            continue
        drawn = np.isfinite(y[:-1]) & np.isfinite(y[1:])
        out += [(x[i], x[i + 1]) for i in np.flatnonzero(drawn)]
    return out


def _true_change(model, f0, low, high, level):
    """The speed [rpm] between ``low`` and ``high`` where the whirl ratio of the mode near ``f0``
    [Hz] passes ``level``, by bisection on modal analyses (independent of the sweep)."""
    def ratio(rpm):
        r = rdm.modal(model, rdm.rpm(rpm))
        modes = np.flatnonzero(r.oscillatory)
        return r.whirl_ratios[modes[np.argmin(np.abs(r.frequencies_hz[modes] - f0))]] - level

    a, b = low, high
    fa = ratio(a)
    assert fa * ratio(b) < 0
    for _ in range(14):
        c = 0.5 * (a + b)
        fc = ratio(c)
        a, b, fa = (c, b, fc) if fa * fc > 0 else (a, c, fa)
    return 0.5 * (a + b)


def test_a_mode_that_whirls_backward_at_rest_changes_style_where_its_whirl_changes(motor_pump):
    """``campbell motor_pump_on_mounts --speeds 0:3600:37``: mode 10 (775 Hz) whirls backward at
    rest (ratio -0.07 about the spin axis: the machine has no mirror plane, its damping is not
    proportional) and forward from about 31 rpm on (the gyroscopic moments). The figure drew the
    whole first step, 0-100 rpm, in both styles, the dashed red over the blue: a backward stub 3x
    longer than the backward stretch. Now the red ends, and the blue starts, at the speed where the
    whirl ratio passes -1e-3 and +1e-3 (found here by bisection on `modal`), within 3 rpm: the
    backward whirl at rest is not hidden either."""
    model, result = motor_pump
    assert result.whirl[0, 9] == "backward" and result.whirl[1, 9] == "forward"
    fig = result.plot()
    ax = fig.axes[0]
    f0 = result.frequencies_hz[0, 9]
    backward_end = _true_change(model, f0, 0.0, 100.0, -TOLERANCE)
    forward_start = _true_change(model, f0, 0.0, 100.0, TOLERANCE)
    assert 25.0 < backward_end < forward_start < 40.0
    red = [s for s in _stretches(ax, result, 10, "backward") if s[0] < 100.0]
    blue = [s for s in _stretches(ax, result, 10, "forward") if s[0] < 100.0]
    assert red and min(a for a, _ in red) == 0.0              # drawn backward from rest ...
    assert abs(max(b for _, b in red) - backward_end) < 3.0     # ... to where it stops whirling backward
    assert abs(min(a for a, _ in blue) - forward_start) < 3.0   # and forward from where it does
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_a_near_planar_mode_gaining_whirl_changes_label_once_where_the_threshold_says(motor_pump):
    """Mode 7 (529 Hz) of the motor pump: 'none' up to 1,500 rpm, 'backward' from 1,600 rpm. That
    is physics, not noise: its whirl ratio falls linearly with speed (2.3e-4 at rest, -2.6e-3 at
    3,600 rpm, second differences below 0.2 % of the first), so the label changes once, where
    the ratio passes -1e-3 (a minor/major axis ratio of 5e-4). The figure changes the curve's
    style at that speed (the straight line through the two neighbouring ratios) and its legend
    says what 'no whirl' means; it drew both styles over the whole step."""
    model, result = motor_pump
    ratio = result.whirl_ratios[:, 6]
    first, second = np.diff(ratio), np.diff(ratio, 2)
    assert np.all(first < 0) and np.abs(second).max() < 2e-3 * np.abs(first).max()   # smooth: physics
    labels = result.whirl[:, 6]
    changes = np.flatnonzero(labels[1:] != labels[:-1])
    assert len(changes) == 1 and labels[0] == "none" and labels[-1] == "backward"
    k = changes[0]
    rpm = result.speeds_rpm
    expected = rpm[k] + (-TOLERANCE - ratio[k]) / (ratio[k + 1] - ratio[k]) * (rpm[k + 1] - rpm[k])
    fig = result.plot()
    ax = fig.axes[0]
    grey, red = _stretches(ax, result, 7, "none"), _stretches(ax, result, 7, "backward")
    assert max(b for _, b in grey) == pytest.approx(expected, abs=1e-6)
    assert min(a for a, _ in red) == pytest.approx(expected, abs=1e-6)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("no whirl" in t and "0.001" in t for t in legend), legend
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_whirl_changes_against_hand_made_ratios(motor_pump):
    """`CampbellResult.whirl_changes` on made-up ratios over speeds 0, 10, 20, 30 rad/s: -0.03 to
    +0.41 (backward, none from 10 (0.029/0.44) rad/s, forward from 10 (0.031/0.44)), +0.41 to
    +0.0005 (none from 10 + 10 (0.409/0.4095)), +0.0005 to -0.0005 (no change); a step where the
    root is no mode has no change."""
    _, result = motor_pump
    speeds = np.array([0.0, 10.0, 20.0, 30.0])
    ratios = np.array([[-0.03, 0.5], [0.41, -0.5], [0.0005, 0.5], [-0.0005, -0.5]])
    values = np.array([[1j * 100.0, 1j * 200.0]] * 4)
    values[2, 1] = -5.0                                      # a real root: not a mode at 20 rad/s
    codes = (ratios > TOLERANCE).astype(int) - (ratios < -TOLERANCE)
    whirl = np.array(["backward", "none", "forward"])[codes + 1]
    made = dataclasses.replace(result, speeds=speeds, eigenvalues=values, frequencies_hz=values.imag / (2 * np.pi),
                               whirl_ratios=ratios, whirl=whirl, modes=np.array([1, 2]),
                               shapes=np.zeros((4, 2, 1), complex), whirl_round_off=None)
    (at, after), (at2, after2) = made.whirl_changes()
    np.testing.assert_allclose(at, [10 * 0.029 / 0.44, 10 * 0.031 / 0.44, 10 + 10 * 0.409 / 0.4095], rtol=1e-12)
    assert list(after) == ["none", "forward", "none"]
    np.testing.assert_allclose(at2, [10 * 0.499 / 1.0, 10 * 0.501 / 1.0], rtol=1e-12)
    assert list(after2) == ["none", "backward"]
    # through zero speed: ratios relative to the spin, -0.5 at -10 rad/s (+0.5 about +e: the spin is
    # -e there) and +0.1 at +30 rad/s. About +e the ratio goes from 0.5 to 0.1, 0.4 at rest: the
    # label is backward up to zero speed and forward from it (a circulatory machine's whirl), not
    # 'none' between -0.5 and 0.1 of the spin-relative ratios (at 23.3 and 23.4 rad/s)
    through = dataclasses.replace(made, speeds=np.array([-10.0, 30.0]), eigenvalues=values[:2, :1],
                                  frequencies_hz=values[:2, :1].imag / (2 * np.pi),
                                  whirl_ratios=np.array([[-0.5], [0.1]]), whirl=np.array([["backward"], ["forward"]]),
                                  modes=np.array([1]), shapes=np.zeros((2, 1, 1), complex))
    (at3, after3), = through.whirl_changes()
    assert list(at3) == [0.0] and list(after3) == ["forward"]


def test_a_circulatory_machine_keeps_its_whirl_at_rest():
    """``unstable_cross_coupled.toml``: its supports' stiffness [[k, q], [-q, k]] makes modes 3
    and 5 circular backward orbits at rest (ratio -1 about the spin axis), and they stay backward:
    drawn backward from 0 rpm, and never forward."""
    model = rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml")
    result = rdm.campbell(model, rdm.rpm(np.linspace(0.0, 1000.0, 11)), orders=(1,), critical=False)
    fig = result.plot()
    ax = fig.axes[0]
    for mode in (3, 5):
        assert result.whirl_ratios[0, mode - 1] == pytest.approx(-1.0, abs=1e-9)
        red = _stretches(ax, result, mode, "backward")
        assert min(a for a, _ in red) == 0.0 and max(b for _, b in red) == 1000.0
        assert not _stretches(ax, result, mode, "forward")
    import matplotlib.pyplot as plt

    plt.close(fig)


# -- stability: the legend says what each panel draws; the axes fit the modes near the speeds ------

@pytest.fixture(scope="module")
def flexible_pump_stability():
    model = rdm.load_model(EXAMPLES / "flexible_pump_on_mounts.toml")
    return rdm.stability(model, rdm.rpm(np.linspace(0.0, 6000.0, 13)))


def test_the_stability_legend_marks_the_modes_a_panel_does_not_draw(flexible_pump_stability):
    """``stability flexible_pump_on_mounts --speeds 0:6000:61``: the legend (the top panel's)
    listed modes 49, 50, 56, 59, 60, whose real parts all lay below the top panel's axis, as if it
    drew them. Now each panel's legend names only the coloured modes it draws inside its axis
    (figs27o: an entry '(bottom: above the axis)' still listed a mode the panel did not show),
    and the panel's note of the roots beyond it names the others."""
    import matplotlib.pyplot as plt

    result = flexible_pump_stability
    fig = result.plot()
    top, bottom = fig.axes[:2]
    coloured = {int(line.get_gid().split()[1]) for line in top.get_lines() if str(line.get_gid()).startswith("mode ")}
    assert coloured
    for name, ax, values in (("top", top, result.real_parts), ("bottom", bottom, result.log_decrements)):
        entries = [t for t in ax.get_legend_handles_labels()[1] if t.startswith("mode ")]
        note = " ".join(t.get_text() for t in ax.texts if t.get_gid() == "cut-off-note").replace("\n", " ")
        low, high = ax.get_ylim()
        for mode in coloured:
            column = values[:, list(result.modes).index(mode)]
            column = column[np.isfinite(column)]
            if np.any((column >= low) & (column <= high)):
                assert f"mode {mode}" in entries, (name, mode, entries)
            else:
                assert f"mode {mode}" not in entries, (name, mode, entries)
                assert ("below" if np.all(column < low) else "above") in note, (name, note)
    plt.close(fig)


def test_the_stability_axes_fit_the_modes_near_the_running_speed(flexible_pump_stability):
    """The flexible pump's 69 kHz shaft modes (log decrement 5e-9, 690 times the top running
    frequency of 100 Hz) scaled both panels: every mode below 1 kHz lay off the axes. Now the
    least damped mode below a decade above the top speed (1 kHz), at each speed, lies inside both
    panels and reaches a tenth of each panel's height from zero; and a note names the least damped
    mode of all (mode and log decrement, found here from the result) as not scaled to."""
    import matplotlib.pyplot as plt

    result = flexible_pump_stability
    log_dec = np.where(np.isfinite(result.log_decrements), result.log_decrements, np.inf)
    near = np.nanmin(np.where(np.isfinite(log_dec), result.frequencies_hz, np.nan), axis=0) <= 1000.0
    least = np.argmin(np.where(near[None, :], log_dec, np.inf), axis=1)
    rows = np.arange(len(least))
    fig = result.plot()
    for ax, values in zip(fig.axes[:2], (result.real_parts[rows, least], result.log_decrements[rows, least])):
        low, high = ax.get_ylim()
        assert low <= values.min() and values.max() <= high
        assert np.abs(values).max() >= (high - low) / 10, (np.abs(values).max(), low, high)
    k, m = np.unravel_index(np.argmin(log_dec), log_dec.shape)
    assert not near[m]
    note = " ".join(t.get_text() for t in fig.axes[0].texts if t.get_gid() == "far-note").replace("\n", " ")
    assert f"mode {result.modes[m]}," in note and f"{log_dec[k, m]:.2g}" in note, note
    fig.canvas.draw()                       # the notes and the legend: inside the figure, apart
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for ax in fig.axes for t in ax.texts if t.get_text()]
    boxes += [ax.get_legend().get_window_extent(renderer) for ax in fig.axes if ax.get_legend()]
    for i, box in enumerate(boxes):
        assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1 and fig.bbox.y0 <= box.y0 and box.y1 <= fig.bbox.y1
        assert not any(box.overlaps(other) for other in boxes[i + 1:])
    plt.close(fig)
