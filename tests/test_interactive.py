"""Interactive figures (plotly) carry the result's numbers in their hover data; the tuning widget
redraws the overlay for the factors given (and builds its sliders when ipywidgets is there)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.plotting.interactive import TuningWidget, campbell_figure, overlay_figure, stability_figure

pytest.importorskip("plotly")
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def gear():
    return rdm.load_model(EXAMPLES / "gear_machine.toml")


def test_campbell_hover_holds_mode_whirl_damping_and_critical_sources(gear):
    res = rdm.campbell(gear, rdm.rpm(np.linspace(0, 3000, 31)), orders=(1, 2))
    fig = campbell_figure(res)
    modes = [t for t in fig.data if t.name.startswith("mode ")]
    first = modes[0]
    m = list(res.modes).index(int(first.name.split()[1]))
    from rotordyn_modal.plotting._style import speed_scale

    # at the sweep's speeds (the curve also passes through its critical speeds, between them)
    sweep = np.isin(np.asarray(first.x, float), res.speeds * speed_scale("rpm"))
    assert sweep.sum() == len(res.speeds)
    y, custom = np.asarray(first.y, float)[sweep], np.asarray(first.customdata)[sweep]
    drawn = ~np.isnan(y)
    np.testing.assert_allclose(y[drawn], res.frequencies_hz[drawn, m])
    np.testing.assert_allclose(custom[drawn, 0].astype(float), res.damping_ratios[drawn, m])
    assert "whirl" in first.hovertemplate and "damping ratio" in first.hovertemplate
    critical, = [t for t in fig.data if t.name == "critical speeds"]
    np.testing.assert_allclose(np.asarray(critical.x, float), res.critical.speeds * 30 / np.pi)
    assert list(np.asarray(critical.customdata)[:, 0]) == list(res.critical.source)
    np.testing.assert_allclose(np.asarray(critical.customdata)[:, 1].astype(float), res.critical.order)
    assert "source %{customdata[0]}, order %{customdata[1]:g}X" in critical.hovertemplate
    # the order lines: order x multiplier x |Omega| / 2 pi Hz, cut at the top of the axis
    rpm = res.speeds * 30 / np.pi
    for name, multiplier in zip(res.sources.names, res.sources.multipliers):
        for order in (1, 2):
            line, = [t for t in fig.data if t.name == f"{order}X {name}"]
            np.testing.assert_allclose(np.asarray(line.x, float), rpm, rtol=1e-12)
            y, exact = np.asarray(line.y, float), order * multiplier * rpm / 60.0
            shown = ~np.isnan(y)
            np.testing.assert_allclose(y[shown], exact[shown], rtol=1e-12)
            assert np.all(exact[~shown] > fig.layout.yaxis.range[1])
    assert (~np.isnan(np.asarray(next(t for t in fig.data if t.name == "1X motor").y, float))).sum() > 10


def test_stability_and_overlay_figures(gear):
    res = rdm.stability(rdm.load_model(EXAMPLES / "unstable_cross_coupled.toml"), rdm.rpm(np.linspace(0, 15000, 31)))
    fig = stability_figure(res)
    assert len([t for t in fig.data if t.name.startswith("mode ")]) == len(res.modes)
    np.testing.assert_allclose(np.asarray(fig.data[0].y, float), res.real_parts[:, 0])
    measured = rdm.frf(gear, 0.0, np.linspace(2, 40, 77), quantity="accelerance")
    measured = rdm.FRFResult(**{**measured.__dict__, "coherence": np.full(measured.H.shape, 0.97)})
    modes = rdm.identify_modes(measured, method="single-pole")
    fig = overlay_figure([measured], [measured], modes=modes)
    dots = [t for t in fig.data if t.name and t.name.startswith("measured ")]
    assert len(dots) == 4
    np.testing.assert_allclose(np.asarray(dots[0].customdata)[:, 1], 0.97)


def test_tuning_widget_redraws_with_the_factors(gear):
    start = gear.scaled({"suspensions.mount-FL.stiffness": 1.6})
    measured = [rdm.frf(gear, 0.0, np.linspace(2, 40, 77))]
    tuner = TuningWidget(start, measured, ["suspensions.mount-FL.stiffness"])
    before = tuner.update()
    after = tuner.update(**{"suspensions.mount-FL.stiffness": 1 / 1.6})
    assert "mean FRAC 1.000" in after.axes[0].get_title() and "FRAC 1.000" not in before.axes[0].get_title()
    curves = [line for line in after.axes[0].get_lines() if line.get_label() != "_overlap"]
    assert len(curves) == 2 * 4      # four FRFs, model line and measured dots (not the dashes of overlaps)
    np.testing.assert_allclose(tuner.model_with_factors().get("suspensions.mount-FL.stiffness"),
                               gear.get("suspensions.mount-FL.stiffness"))
    with pytest.raises(InputError, match="unknown key\\(s\\) gain"):
        tuner.update(gain=2.0)
    pytest.importorskip("ipywidgets")
    box = tuner.widget()
    assert box.children[0].description == "mount-FL.stiffness"


def test_missing_plotly_is_named(without_module, gear):
    without_module("plotly")
    res = rdm.campbell(gear, rdm.rpm(np.linspace(0, 3000, 5)))
    with pytest.raises(InputError, match=r"pip install 'rotordyn_modal\[interactive\]'"):
        campbell_figure(res)


def test_missing_ipywidgets_is_named(without_module, gear):
    tuner = TuningWidget(gear, [rdm.frf(gear, 0.0, np.linspace(2, 40, 20))], ["suspensions.mount-FL.stiffness"])
    without_module("ipywidgets")
    with pytest.raises(InputError, match=r"the tuning widget needs ipywidgets: pip install 'rotordyn_modal\[interactive\]'"):
        tuner.widget()
