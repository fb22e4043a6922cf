"""UCS map (issue 27 §1/§3, issue 29 §2): the curves do not depend on the grid's spacing.

Which root at one stiffness continues which at the next was decided by the MAC over the user's
own steps: a decade-wide step jumped across a veering that a fine grid followed round, so maps
of 5 and 161 values of one range drew different curves through the same points. The roots are
now followed on points inserted where a step is unclear, along the pencil's branches: through a
veering a curve keeps its rank (the n-th critical speed stays the n-th), where two modes do not
couple they cross."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
CASES = {"fan": ("fan_on_bearings.toml", ["fan-DE", "fan-NDE"]),
         "flexible_pump": ("flexible_pump_on_mounts.toml", None),
         "motor_pump": ("motor_pump_on_mounts.toml", None)}


@pytest.fixture(scope="module")
def models():
    return {name: rdm.load_model(EXAMPLES / file) for name, (file, _) in CASES.items()}


def _curves_at(result, rows):
    """The followed modes' speeds (L, R) [rad/s] at the grid's rows ``rows``, those with a speed there."""
    speeds = result.mode_speeds[rows].T
    return speeds[np.isfinite(speeds).any(axis=1)]


def _assert_curves_within(coarse, fine):
    """Every curve of ``coarse`` (L, R) is one of ``fine`` (L', R): the same points drawn (nan
    where none) and the same speeds to 1e-9."""
    for curve in coarse:
        same = [np.array_equal(np.isnan(curve), np.isnan(other))
                and np.allclose(curve[np.isfinite(curve)], other[np.isfinite(other)], rtol=1e-9, atol=0.0)
                for other in fine]
        assert any(same), (np.round(curve * 30 / np.pi, 1), np.round(fine * 30 / np.pi, 1))


@pytest.mark.parametrize("name", sorted(CASES))
def test_coarse_grids_draw_the_curves_of_a_fine_grid_through_their_points(models, name):
    """Maps of 5, 9, 17 and 41 values over 1e5 .. 1e9 N/m against one of 161 values (which holds
    theirs): each coarse curve passes through the same roots at the coarse grid's values as a
    curve of the fine map. On the base every one of the three examples joined roots otherwise
    (fan, 5 values: '3619.6 3621.0 - 3611.3 3611.7 rpm' as one curve; the pump on mounts, 41
    values: the motor's cylindrical mode continued into its axial one)."""
    bearings = CASES[name][1]
    fine = rdm.ucs_map(models[name], np.geomspace(1e5, 1e9, 161), bearings=bearings)
    for count in (5, 9, 17, 41):
        coarse = rdm.ucs_map(models[name], np.geomspace(1e5, 1e9, count), bearings=bearings)
        step = 160 // (count - 1)
        assert np.allclose(fine.stiffness[::step], coarse.stiffness, rtol=1e-12)
        _assert_curves_within(_curves_at(coarse, slice(None)), _curves_at(fine, slice(None, None, step)))


@settings(max_examples=8, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.floats(5.0, 9.0).filter(lambda x: abs(x - round(x)) > 1e-3), min_size=1, max_size=12))
def test_any_grid_holding_the_same_points_draws_the_same_curves_through_them(models, extra):
    """The pump on mounts (four bearings, flexible pump shaft: the examples' map with the most
    veerings): the decades 1e5 .. 1e9 N/m, and the same with up to 12 values anywhere between
    (hypothesis): the decades' map's curves are curves of the other at the decades."""
    model = models["flexible_pump"]
    decades = np.geomspace(1e5, 1e9, 5)
    grid = np.union1d(decades, 10.0 ** np.array(extra))
    coarse = rdm.ucs_map(model, decades)
    finer = rdm.ucs_map(model, grid)
    _assert_curves_within(_curves_at(coarse, slice(None)), _curves_at(finer, np.searchsorted(grid, decades)))


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("count", [5, 17])
def test_every_curve_rises_with_the_stiffness(models, name, count):
    """Along a branch of ``K(k) phi = Omega^2 (M - i G) phi``, ``d(Omega^-2)/dk = -Omega^-2
    phi^H K_unit phi / phi^H K phi <= 0`` (K_unit positive semidefinite): a mode's critical
    speed never falls as its bearings stiffen. Following shapes across a decade-wide step over a
    veering joined a root to the lower branch past it: the fan's '3621 -> 3611 rpm' curve, the
    pump on mounts' modes falling by up to a third."""
    bearings = CASES[name][1]
    result = rdm.ucs_map(models[name], np.geomspace(1e5, 1e9, count), bearings=bearings)
    for j, curve in enumerate(result.mode_speeds.T):
        drawn = curve[np.isfinite(curve)]
        assert np.all(np.diff(drawn) >= -1e-9 * drawn[1:]), (j + 1, result.mode_names[j], drawn * 30 / np.pi)


def _segments_cross(p, q, a, b):
    """Whether segment p-q crosses segment a-b (2-D, strictly)."""
    def side(o, s, t):
        return (s[0] - o[0]) * (t[1] - o[1]) - (s[1] - o[1]) * (t[0] - o[0])
    return side(p, q, a) * side(p, q, b) < 0 and side(a, b, p) * side(a, b, q) < 0


def test_the_pump_on_mounts_crossing_labels_stand_near_their_circles(ucs_figure):
    """flexible_pump_on_mounts' map over 1e5 .. 1e10 N/m (41 values, as its figure audit draws
    it), measured at the saved 150 dpi: every crossing label's leader (from its box to its
    point) is at most 24 points long and crosses no mode's curve away from the circles it names
    (within 3 points + 0.5 px of one), and no two labels overlap. On the base '26494' stood 34
    points away; with the curves followed along their branches '31315' had no free place
    beside it (45 points away) until it shared one with '34642', 9.6 points above it."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.text import Annotation, Text

    # mapped and plotted once per worker with test_figure_audit30's (conftest.ucs_figure)
    result, fig = ucs_figure("flexible_pump_on_mounts", (1e5, 1e10, 41))
    ax = fig.axes[0]
    fig.set_dpi(150)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    points = 150 / 72
    curves = [ax.transData.transform(np.column_stack(line.get_data())) for line in ax.get_lines()
              if str(line.get_label())[:1].isdigit()]
    circles = np.array([ax.transData.transform((c.stiffness, c.speed * 30 / np.pi)) for c in result.crossings])
    labels = [t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() != "ucs-end-name"
              and t.get_text()[:1].isdigit() and len(t.get_text()) >= 3]
    assert len(labels) >= 4
    boxes = []
    for text in labels:
        box = Text.get_window_extent(text, renderer)
        end = ax.transData.transform(text.xy)
        start = np.array([min(max(end[0], box.x0), box.x1), min(max(end[1], box.y0), box.y1)])
        assert np.hypot(*(end - start)) <= 24 * points, (text.get_text(), np.hypot(*(end - start)) / points)
        speeds = [float(s) for s in text.get_text().split("/")]
        mine = np.array([c for c, x in zip(circles, result.crossings)
                         if any(abs(x.speed * 30 / np.pi - s) < 0.5 for s in speeds)])
        for curve in curves:
            for a, b in zip(curve[:-1], curve[1:]):
                if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))) or not _segments_cross(start, end, a, b):
                    continue
                d, e = end - start, b - a
                t = ((a[0] - start[0]) * e[1] - (a[1] - start[1]) * e[0]) / (d[0] * e[1] - d[1] * e[0])
                assert np.hypot(*(mine - (start + t * d)).T).min() <= 3 * points + 0.5, text.get_text()
        boxes.append(box)
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
