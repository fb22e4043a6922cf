"""The run-up figure's critical-speed labels are not struck out by other critical lines (issue
27, section 3: "no overprinted text"). Where critical lines crowd closer than a label's width a
label lies across its neighbours' lines (by design: never across the signal or the tracks); its
box was 70 % opaque, so the red dashed lines ran through the red text (the fan's run-up to
9000 rpm: 'mode 1, 1X fan, 798 rpm' under the lines at 866 and 880 rpm, 'mode 4, 1X fan,
1502 rpm' under 1385 rpm). Checked on the drawn figure: every label box that a critical line
other than its own passes through hides it (an opaque box drawn over the line).
"""

from __future__ import annotations

import types

import matplotlib
import numpy as np

matplotlib.use("Agg")


def crowded_runup(rpm):
    """A two-rotor run-up (300 to 540 rad/s in 8 s, rotor 'b' at 0.625) and critical speeds of
    rotor 'a' at ``rpm`` (n,) [rpm]: ``(result, critical)``."""
    from rotordyn_modal.analysis.critical_speeds import _critical_table

    t = np.arange(0.0, 8.0, 2e-4)
    omega, phi = 300.0 + 30.0 * t, 300.0 * t + 15.0 * t ** 2
    signal = np.cos(phi + 0.7) + 0.5 * np.cos(0.625 * phi)
    result = types.SimpleNamespace(time=t, drive_speed=omega, rotor_angles=np.column_stack([phi, 0.625 * phi]),
                                   speed_ratios=np.array([1.0, 0.625]), rotor_names=["a", "b"],
                                   model_name="crowded", sensor_names=["s"], sensor=lambda name: signal)
    n = len(rpm)
    critical = _critical_table(["a"] * n, np.ones(n), np.arange(1, n + 1), rpm * np.pi / 30.0,
                               rpm / 60.0, ["forward"] * n, np.full(n, 0.5), np.full(n, 0.01))
    return result, critical


def _crowded_runup():
    """Six critical speeds of rotor 'a', 20 rpm apart near 3,500 rpm, and two more near 4,600 rpm."""
    return crowded_runup(np.array([3500.0, 3520.0, 3540.0, 3560.0, 3580.0, 3600.0, 4600.0, 4630.0]))


def test_a_label_across_other_critical_lines_hides_them():
    import matplotlib.pyplot as plt

    from rotordyn_modal.plotting.simulation import plot_runup

    result, critical = _crowded_runup()
    fig = plot_runup(result, "s", critical=critical)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    crossed = 0
    for ax in fig.axes:
        lines = [line for line in ax.get_lines() if line.get_label() == "_critical"]
        for label in [t for t in ax.texts if t.get_text().startswith("mode ") and t.get_visible()]:
            box = label.get_window_extent(renderer)
            patch = label.get_bbox_patch()
            own = float(label.xy[0])
            for line in lines:
                x = float(np.asarray(line.get_xdata(), float)[0])
                px = ax.transData.transform((x, 0.0))[0]
                if x == own or not box.x0 + 0.5 < px < box.x1 - 0.5:
                    continue
                crossed += 1
                assert patch is not None and patch.get_visible(), label.get_text()
                assert patch.get_alpha() in (None, 1.0) and patch.get_facecolor()[3] == 1.0, \
                    (label.get_text(), x, patch.get_alpha())
                assert label.get_zorder() > line.get_zorder()
    assert crossed >= 2            # the case: labels lie across their crowded neighbours
    plt.close(fig)
