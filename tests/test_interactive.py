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


@pytest.fixture(scope="module")
def motor_pump_figure():
    """``campbell motor_pump_on_mounts --speeds 0:3600:37 --orders 1`` and its plotly figure."""
    res = rdm.campbell(rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml"),
                       rdm.rpm(np.linspace(0.0, 3600.0, 37)), orders=(1,))
    return res, campbell_figure(res)


def _mode_traces(fig, label):
    """Mode ``label``'s traces: {whirl: (x [rpm], y [Hz])}, all on the same points."""
    out = {}
    for t in fig.data:
        if t.name.startswith(f"mode {label} ("):
            out[t.name.split("(")[1].rstrip(")")] = (np.asarray(t.x, float), np.asarray(t.y, float))
    xs = [x for x, _ in out.values()]
    assert all(np.array_equal(x, xs[0]) for x in xs)
    return out


def test_campbell_changes_style_at_the_whirl_ratio_threshold(motor_pump_figure):
    """Mode 7 (529 Hz) of the motor pump: 'none' up to 1,500 rpm, 'backward' from 1,600 rpm; its
    whirl ratio falls smoothly (2.3e-4 at rest, -2.6e-3 at 3,600 rpm) and passes -1e-3 between
    them. The plotly figure styled each sample by its own label, so neither style drew that step
    (a gap in the curve); now the grey line ends and the red starts at the speed where the ratio,
    straight between the two samples, passes -1e-3 (written out here), as the matplotlib figure
    does (``CampbellResult.whirl_changes``)."""
    res, fig = motor_pump_figure
    m = 6
    label = res.modes[m]
    ratio, rpm = res.whirl_ratios[:, m], res.speeds_rpm
    k = int(np.flatnonzero(res.whirl[1:, m] != res.whirl[:-1, m])[0])
    assert (res.whirl[k, m], res.whirl[k + 1, m]) == ("none", "backward")
    expected = rpm[k] + (-1e-3 - ratio[k]) / (ratio[k + 1] - ratio[k]) * (rpm[k + 1] - rpm[k])
    assert rpm[k] < expected < rpm[k + 1]
    traces = _mode_traces(fig, label)
    assert set(traces) == {"none", "backward"}
    grey_x, grey_y = traces["none"]
    red_x, red_y = traces["backward"]
    assert grey_x[np.isfinite(grey_y)].max() == pytest.approx(expected, abs=1e-6)
    assert red_x[np.isfinite(red_y)].min() == pytest.approx(expected, abs=1e-6)
    assert expected == pytest.approx(res.whirl_changes()[m][0][0] * 30 / np.pi, abs=1e-9)
    # the change point lies on the curve: between the samples' frequencies, straight
    at = np.flatnonzero(np.isclose(grey_x, expected, rtol=0, atol=1e-6))[0]
    f = res.frequencies_hz[:, m]
    t = (expected - rpm[k]) / (rpm[k + 1] - rpm[k])
    assert grey_y[at] == pytest.approx(f[k] + t * (f[k + 1] - f[k]), rel=1e-12)


def test_campbell_draws_each_step_in_one_style_changing_where_whirl_changes_says(motor_pump_figure):
    """For every mode of the motor pump (modes backward at rest turning forward within 35 rpm,
    modes gaining whirl with speed): each segment between two points of a curve over a step of
    the sweep where the root is a mode at both ends is drawn in exactly one style (no gap, no
    two styles over each other), that of the sweep's label at the step's ends unless the label
    changes in the step; and the points where two styles meet are the speeds of
    ``whirl_changes`` (the matplotlib figure's)."""
    res, fig = motor_pump_figure
    rpm = 30 / np.pi
    changes = res.whirl_changes()
    checked = 0
    for m, label in enumerate(res.modes):
        traces = _mode_traces(fig, label)
        x = next(iter(traces.values()))[0]
        drawn = {w: np.isfinite(y[:-1]) & np.isfinite(y[1:]) for w, (_, y) in traces.items()}
        count = sum(drawn.values())
        k = np.searchsorted(res.speeds_rpm, 0.5 * (x[:-1] + x[1:])) - 1
        mode = res.oscillatory[k, m] & res.oscillatory[k + 1, m]
        assert np.array_equal(count, mode.astype(int)), label
        steady = mode & (res.whirl[k, m] == res.whirl[k + 1, m]) \
            & ~np.isin(k, np.searchsorted(res.speeds, changes[m][0], side="right") - 1)
        for whirl, d in drawn.items():
            assert np.all(d[steady] == (res.whirl[k[steady], m] == whirl)), (label, whirl)
        meet = [xi for i, xi in enumerate(x)
                if sum(bool(np.isfinite(y[i])) for _, y in traces.values()) > 1]
        np.testing.assert_allclose(meet, changes[m][0] * rpm, rtol=1e-12, atol=0)
        checked += len(meet)
    assert checked >= 12
