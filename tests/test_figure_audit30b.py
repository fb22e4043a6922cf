"""Figure audit of issue 27 §3 (figs30b): every CLI figure opened; what the reviewer flagged.

An unbalance figure's peak label is joined to its peak by a leader that crosses no curve: a
leader across a curve reads as naming a point of that curve. The peak marker of a peak found
between swept speeds lies above the drawn curve (the curve joins the swept speeds), so the
curve passes a few points under the marker: a leader drawn down from it crossed that curve
within the square of 6 points around the marker where the placer let curves pass (its own
curve). Measured here on the drawn figure (150 dpi, exact geometry of
``label_geometry.segment_crossings``), not with the placer's grid.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: a leader meets its own peak's marker ('v', 5 points across) within this many points of the peak
_MARKER_POINTS = 3.0


def _leader_crossings(fig):
    """``[(axes number, label text, crossings)]`` of every peak label (an annotation with a
    leader to a point of its axes) whose leader line crosses a drawn curve of its axes farther
    than the marker's radius (plus a pixel) from the peak. The leader runs from the label's
    box point nearest the peak to the peak, as drawn."""
    from label_geometry import curve_segments, segment_crossings

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    radius = _MARKER_POINTS * fig.dpi / 72.0 + 1.0
    found = []
    for number, ax in enumerate(fig.axes):
        segments = curve_segments(ax)
        for text in ax.texts:
            if getattr(text, "arrow_patch", None) is None or text.xycoords != "data" or not text.get_visible():
                continue
            box = text.get_bbox_patch().get_window_extent(renderer)
            anchor = ax.transData.transform(text.xy)
            start = (min(max(anchor[0], box.x0), box.x1), min(max(anchor[1], box.y0), box.y1))
            hits = segment_crossings(start, anchor, segments, anchor=anchor, radius=radius)
            if len(hits):
                found.append((number, text.get_text(), len(hits)))
    return found


def test_no_unbalance_peak_leader_crosses_a_curve_below_its_peak():
    """``unbalance examples/flexible_pump_on_mounts.toml --speeds 0:6000:61 --plot``: the rotor
    point panel's 'AF 3.7 at 631 rpm (1X motor)' (a peak between swept speeds, its marker 3.5
    points above the drawn solid probe-impeller curve) had a leader down to the right across that
    curve. On the drawn figure no peak label's leader crosses a curve beyond its marker, and the
    peak is still named: a label or a number with a key line that says 'AF 3.7 at 631 rpm'."""
    import matplotlib.pyplot as plt

    import rotordyn_modal as rdm
    from rotordyn_modal.cli.unbalance import sensor_groups

    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "flexible_pump_on_mounts.toml")
    result = rdm.unbalance_response(model, np.linspace(0.0, 6000.0, 61) * np.pi / 30.0)   # rad/s
    fig = result.plot(peaks=result.peaks(), groups=sensor_groups(model))   # the CLI's panels
    fig.set_dpi(150)
    assert _leader_crossings(fig) == []
    written = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any("AF 3.7 at 631 rpm" in t for t in written), written
    plt.close(fig)


def test_no_unbalance_peak_leader_crosses_a_curve_beside_its_peak():
    """motor_pump_on_mounts over 100-3600 rpm (176 speeds), peaks with their separation margins
    at 3000 rpm: in the probe panel the leaders of 'AF 7.6 at 649 rpm' and 'AF 5.3 at 960 rpm'
    (1X motor, probe-pump-x) left their peaks across the probe-pump-y curve a few points beside
    them. On the drawn figure (150 dpi) no peak label's leader crosses a curve beyond its
    marker, and both peaks are still named (a label, or a number with a key line)."""
    import matplotlib.pyplot as plt

    import rotordyn_modal as rdm

    model = rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "motor_pump_on_mounts.toml")
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(100, 3600, 176)))
    fig = result.plot(peaks=result.peaks(rdm.rpm(3000)))
    fig.set_dpi(150)
    assert _leader_crossings(fig) == []
    written = [t.get_text() for ax in fig.axes for t in ax.texts]
    for peak in ("AF 7.6 at 649 rpm", "AF 5.3 at 960 rpm"):
        assert any(peak in t for t in written), (peak, written)
    plt.close(fig)
