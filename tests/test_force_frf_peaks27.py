"""A force FRF's cut-peak mark sits at the force's true maximum, not at the damped natural
frequency (issue 27, section 3).

One mass m = 1 kg on a mount of stiffness k (f_n = 100 Hz) and damper c (zeta = 0.05) along z,
excited along z; the force the mount passes to the ground per unit force is the
transmissibility ``T = (k + i c w) / (k - m w^2 + i c w)``. Its maximum lies at
``r^2 = (sqrt(1 + 8 zeta^2) - 1) / (4 zeta^2)`` (r = f / f_n: 99.752 Hz), with
``|T|^2 = (1 + (2 zeta r)^2) / ((1 - r^2)^2 + (2 zeta r)^2)`` there (10.062), below the damped
natural frequency f_d = f_n sqrt(1 - zeta^2) = 99.875 Hz, where main marked it. Computed every
50 Hz (25, 75, 125 Hz, ...), the line between 75 and 125 Hz passes far below that peak.

Truth from outside the code: the closed form above (a textbook result for a base-excited or
force-excited single-degree-of-freedom isolator), and a dense 0.0001 Hz sweep of the closed form.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import marker_points

matplotlib.use("Agg")

M, FN, ZETA = 1.0, 100.0, 0.05
K = M * (2 * np.pi * FN) ** 2
C = 2 * ZETA * np.sqrt(K * M)
F = np.arange(25.0, 300.0, 50.0)


def _model():
    return rdm.Model(stator=rdm.Stator(mass=M, inertia=[1.0, 1.0, 1.0]),
                     suspensions=[rdm.Suspension("s", [0, 0, 0], [1e12, 1e12, K, 1e9, 1e9, 1e9],
                                                 damping=[0, 0, C, 0, 0, 0])],
                     excitations=[rdm.Excitation("f", [0, 0, 0], [0, 0, 1])])


def _transmissibility(f_hz):
    w = 2 * np.pi * np.asarray(f_hz, dtype=float)
    return (K + 1j * C * w) / (K - M * w ** 2 + 1j * C * w)


@pytest.fixture(scope="module")
def peak():
    """(frequency [Hz], |T|) of the closed form's maximum; checked against a dense sweep."""
    r2 = (np.sqrt(1 + 8 * ZETA ** 2) - 1) / (4 * ZETA ** 2)
    at = FN * np.sqrt(r2)
    top = np.sqrt((1 + 4 * ZETA ** 2 * r2) / ((1 - r2) ** 2 + 4 * ZETA ** 2 * r2))
    dense = np.arange(99.0, 101.0, 1e-4)
    k = int(np.abs(_transmissibility(dense)).argmax())
    assert abs(dense[k] - at) < 1e-4 and abs(np.abs(_transmissibility(at)) - top) < 1e-12 * top
    return at, top


def test_the_mount_force_is_marked_at_its_maximum_not_at_the_damped_frequency(peak):
    """`cut_peaks` of the mount's z force gives one peak: within 1e-3 Hz of the closed form's
    maximum (f_d lies 0.12 Hz above it), its |T| within 1e-7 of the closed form's peak; the
    other components (zero) have none."""
    at_true, top = peak
    fd = FN * np.sqrt(1 - ZETA ** 2)
    assert fd - at_true > 0.1                                                     # the case
    result = rdm.force_frf(_model(), 0.0, F, where="suspensions")
    np.testing.assert_allclose(result.H[result.outputs.index("s:Fz"), 0], _transmissibility(F), rtol=1e-9)
    at, h = result.cut_peaks("s:Fz", "f")
    assert len(at) == 1
    assert abs(at[0] - at_true) < 1e-3
    assert abs(abs(h[0]) - top) < 1e-7 * top
    assert abs(h[0] - _transmissibility(at[0])) < 1e-9 * top
    for name in result.outputs:
        if name != "s:Fz":
            assert len(result.cut_peaks(name, "f")[0]) == 0, name


def test_the_force_figure_has_one_diamond_at_the_maximum(peak):
    """The force FRF's figure has one marker-only point on its magnitude panel: at the closed
    form's maximum, inside the axes' pixel frame."""
    import matplotlib.pyplot as plt

    at_true, top = peak
    fig = rdm.force_frf(_model(), 0.0, F, where="suspensions").plot()
    fig.canvas.draw()
    mag = fig.axes[0]
    marks = marker_points(mag)
    assert len(marks) == 1
    x, y = marks[0]
    assert abs(x - at_true) < 1e-3 and abs(y - top) < 1e-7 * top
    frame = mag.get_window_extent()
    px, py = mag.transData.transform((x, y))
    assert frame.x0 < px < frame.x1 and frame.y0 < py < frame.y1
    plt.close(fig)
