"""Figures of the fourth audit (issue 27, section 3), measured on the drawn figure
(``fig.canvas.draw()``, window extents), independent of the code that places things: legends
that took half the figure, order lines left unnamed at the Campbell diagram's top edge, merged
order labels beside one of the lines they name, the orbit's axis that did not say what e is."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def pump():
    return rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")


def _figures(pump):
    """motor_pump_on_mounts (modes 5 Hz-1.2 kHz): its unbalance response with the suspensions'
    forces (three legends, notes of 50 characters); rubber_mounts' bearing forces (two blocks
    of force and moment panels, notes found on the layout)."""
    unbalance = rdm.unbalance_response(pump, rdm.rpm(np.linspace(0.0, 6000.0, 21)))
    yield "unbalance", unbalance.plot(forces="suspensions")
    rubber = rdm.load_model(EXAMPLES / "rubber_mounts.toml")
    yield "forces", rdm.force_frf(rubber, rdm.rpm(3000), np.linspace(1.0, 100.0, 40), where="bearings").plot()


def test_legends_leave_the_panels_most_of_the_width(pump):
    """The legends beside the panels, with long names and '(= ...)' notes, took up to half the
    figure's width (the panels 47-59 % of it). On the drawn figure: every panel with a legend is
    at least 70 % as wide as its figure (or block of panels), every legend lies inside the
    figure, overlaps no panel, no title and no other legend, and names every curve of its
    panel."""
    import matplotlib.pyplot as plt

    for name, fig in _figures(pump):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        frame = fig.bbox
        axes = [ax for ax in fig.axes if ax.get_visible()]
        legends = [ax.get_legend() for ax in axes if ax.get_legend() is not None]
        assert len(legends) >= 1, name
        boxes = [legend.get_window_extent(renderer) for legend in legends]
        titles = [t.get_window_extent(renderer) for ax in axes for t in (ax.title,) if t.get_text()]
        for ax in axes:
            if ax.get_legend() is None:
                continue
            holder = ax.get_figure(root=False).bbox
            assert ax.bbox.width >= 0.7 * holder.width, (name, ax.get_ylabel(), ax.bbox.width / holder.width)
            named = {t.get_text() for t in ax.get_legend().get_texts()}
            curves = [line.get_label() for line in ax.get_lines() if not line.get_label().startswith("_")]
            assert set(curves) <= named, (name, set(curves) - named)
        for k, box in enumerate(boxes):
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, name
            assert not any(box.overlaps(ax.bbox) for ax in axes), name
            assert not any(box.overlaps(title) for title in titles), name
            assert not any(box.overlaps(other) for other in boxes[k + 1:]), name
        plt.close(fig)


def test_orbit_axis_says_that_e_is_the_spin_axis(pump):
    """The orbit panels' vertical axis read 'e × probe-pump-x [µm]' with e defined nowhere on
    the figure: it names the spin axis."""
    import matplotlib.pyplot as plt

    fig = rdm.unbalance_response(pump, rdm.rpm(np.linspace(500.0, 3000.0, 6))).plot_orbits()
    labels = [ax.get_ylabel() for ax in fig.axes if ax.get_visible()]
    assert labels and all("e × " in label and "e: spin axis" in label for label in labels), labels
    plt.close(fig)
