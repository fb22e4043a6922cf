"""Two close modes sharing one peak get one cut-peak mark, at the peak (issue 27, section 3).

One mass on two springs, y at 318 Hz and z at 320 Hz, each with a damper of 30 N s/m
(half-power bandwidth c / (2 pi m) = 4.8 Hz, wider than the 2 Hz between the modes), excited
and measured along (0, 1, 1): the receptance has one maximum near 318.9 Hz, between the two
damped natural frequencies, where neither mode's own response is largest. Computed every
10 Hz, the line between 315 and 325 Hz cuts it. Main marked the two damped natural
frequencies, each below the true peak.

Truth from outside the code: the closed form of the two uncoupled modes,
``u_y^2 / (k_y - m w^2 + i c w) + u_z^2 / (k_z - m w^2 + i c w)`` with ``u = (0, 1, 1) / sqrt(2)``,
evaluated every 0.001 Hz.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import marker_points

matplotlib.use("Agg")

M, C = 1.0, 30.0
KY, KZ = (2 * np.pi * 318.0) ** 2, (2 * np.pi * 320.0) ** 2
F = np.arange(5.0, 1000.0, 10.0)


def _model():
    return rdm.Model(stator=rdm.Stator(mass=M, inertia=[1.0, 1.0, 1.0]),
                     suspensions=[rdm.Suspension("s", [0, 0, 0], [1e12, KY, KZ, 1e9, 1e9, 1e9],
                                                 damping=[0, C, C, 0, 0, 0])],
                     sensors=[rdm.Sensor("d", [0, 0, 0], [0, 1, 1])],
                     excitations=[rdm.Excitation("f", [0, 0, 0], [0, 1, 1])])


def _closed_form(f_hz):
    w = 2 * np.pi * np.asarray(f_hz)
    return 0.5 / (KY - M * w ** 2 + 1j * C * w) + 0.5 / (KZ - M * w ** 2 + 1j * C * w)


@pytest.fixture(scope="module")
def truth():
    """(frequency [Hz], |H|) of the closed form's maximum, 0.001 Hz apart near the two modes."""
    f = np.arange(300.0, 340.0, 0.001)
    h = np.abs(_closed_form(f))
    k = int(h.argmax())
    assert 0 < k < len(f) - 1
    return f[k], h[k]


def test_the_shared_peak_is_one_maximum_at_the_closed_forms_peak(truth):
    """`cut_peaks` gives one resonance near 318-320 Hz: at the closed form's maximum (within its
    0.001 Hz step) and its height (not below it, within 1e-6); the two damped natural frequencies
    are 2 Hz apart and their own |H| lies below it."""
    at_true, top = truth
    result = rdm.frf(_model(), 0.0, F)
    roots = rdm.modal(_model(), 0.0)
    fd = np.sort(roots.frequencies_hz[roots.oscillatory])
    fd = fd[(fd > 300) & (fd < 340)]
    assert len(fd) == 2 and np.all(np.abs(_closed_form(fd)) < (1 - 1e-3) * top)   # the case
    at, h = result.cut_peaks("d", "f")
    assert len(at) == 1
    assert abs(at[0] - at_true) <= 0.001
    assert top <= abs(h[0]) <= (1 + 1e-6) * top
    assert abs(h[0] - _closed_form(at[0])) < 1e-6 * top


def test_the_figure_has_one_diamond_at_the_shared_peak_inside_the_axes(truth):
    """The Bode figure's magnitude panel has one marker-only line point: at the closed form's
    maximum, inside the axes' pixel frame."""
    import matplotlib.pyplot as plt

    at_true, top = truth
    fig = rdm.frf(_model(), 0.0, F).plot()
    fig.canvas.draw()
    mag = fig.axes[0]
    marks = marker_points(mag)
    assert len(marks) == 1
    x, y = marks[0]
    assert abs(x - at_true) <= 0.001 and top <= y <= (1 + 1e-6) * top
    frame = mag.get_window_extent()
    px, py = mag.transData.transform((x, y))
    assert frame.x0 < px < frame.x1 and frame.y0 < py < frame.y1
    plt.close(fig)
