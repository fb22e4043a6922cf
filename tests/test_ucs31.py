"""UCS map (issue 27 §1/§3, issue 29 §2): the followed modes do not change with a one-ulp input,
a curve whose character changes along the stiffness says so in its name, and the figure's
labels sit near their crossings without leaders across curves."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
PUMP = EXAMPLES / "flexible_pump_on_mounts.toml"      # its four bearings: 1e8 N/m


def _moved(values, ulps):
    """``values`` each moved by its count of ulps (numpy.nextafter, one ulp at a time)."""
    out = np.array(values, dtype=float)
    for i, count in enumerate(ulps):
        for _ in range(abs(count)):
            out[i] = np.nextafter(out[i], np.inf if count > 0 else 0.0)
    return out


def _assert_same_map(a, b):
    assert a.mode_speeds.shape == b.mode_speeds.shape, (a.mode_names, b.mode_names)
    assert a.mode_names == b.mode_names
    assert np.array_equal(np.isnan(a.mode_speeds), np.isnan(b.mode_speeds))
    np.testing.assert_allclose(a.mode_speeds, b.mode_speeds, rtol=1e-9)


@pytest.fixture(scope="module")
def pump():
    return rdm.load_model(PUMP)


@pytest.mark.parametrize("direction", [np.inf, 0.0])
def test_one_ulp_beside_the_bearings_own_stiffness_keeps_the_modes(pump, direction):
    """geomspace(1e5, 1e9, 5) showed 9 modes; 1e8 moved by one ulp, 8 (the step of one ulp
    beside the bearings' own 1e8 N/m, a point of the following, changed how the next decade's
    step was decided)."""
    grid = np.geomspace(1e5, 1e9, 5)
    moved = grid.copy()
    moved[3] = np.nextafter(moved[3], direction)
    _assert_same_map(rdm.ucs_map(pump, grid), rdm.ucs_map(pump, moved))


@settings(max_examples=10, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(3, 6), st.floats(4.0, 6.5), st.floats(8.2, 10.0), st.booleans(),
       st.lists(st.integers(-3, 3), min_size=7, max_size=7))
def test_random_coarse_grids_moved_by_a_few_ulps_keep_their_modes(pump, count, low, high, own, ulps):
    """Random coarse grids (with or without the bearings' own 1e8 N/m among them), each value
    moved by up to 3 ulps: the same modes, names and critical speeds to 1e-9."""
    grid = np.geomspace(10.0 ** low, 10.0 ** high, count)
    if own:
        grid = np.unique(np.r_[grid[np.abs(np.log10(grid) - 8) > 0.05], 1e8])
    a = rdm.ucs_map(pump, grid)
    b = rdm.ucs_map(pump, _moved(grid, ulps[:len(grid)]))
    _assert_same_map(a, b)


_STEEL = '\n[[materials]]\nname = "steel"\ndensity = 7800.0\nyoung_modulus = 2.0e11\npoisson_ratio = 0.3\n'


def _uniform_shaft(path, length, diameter):
    """One uniform steel shaft (Euler-Bernoulli: no shear) on two bearings at its ends."""
    path.write_text('name = "shaft"\n' + _STEEL + '\n[[rotors]]\nname = "s"\nspeed_ratio = 1.0\n'
                    'start = [0.0, 0.0, 0.0]\nshear = "none"\n'
                    f'\n[[rotors.shaft]]\nlength = {length!r}\nouter_diameter = {diameter!r}\nmaterial = "steel"\n'
                    '\n[[bearings]]\nname = "b0"\nrotor = "s"\naxial_position = 0.0\nstiffness = 1e6\n'
                    f'\n[[bearings]]\nname = "b1"\nrotor = "s"\naxial_position = {length!r}\nstiffness = 1e6\n',
                    encoding="utf-8")
    return path


def test_a_rigid_body_mode_turning_into_bending_is_named_by_both_ends(tmp_path):
    """A uniform shaft (1 m, 50 mm) on two bearings: on 1e3 N/m its lowest forward critical speed
    is the rigid cylindrical mode sqrt(2 k / m), on 1e10 N/m the pinned-pinned first bending
    mode (pi / L)^2 sqrt(E I / (rho A)); the curve is one mode, named by both ('s cylindrical ->
    s bending'), and the second (rigid conical, then the second bending mode, 4 times the
    first) too. A name by most points said 's cylindrical' or 's bending' alone."""
    length, diameter = 1.0, 0.05
    model = rdm.load_model(_uniform_shaft(tmp_path / "shaft.toml", length, diameter))
    stiffness = np.geomspace(1e3, 1e10, 8)
    result = rdm.ucs_map(model, stiffness, modes=2)
    area, inertia = math.pi * diameter ** 2 / 4, math.pi * diameter ** 4 / 64
    mass = 7800.0 * area * length
    pinned = (math.pi / length) ** 2 * math.sqrt(2.0e11 * inertia / (7800.0 * area))
    first = result.mode_speeds[:, 0]
    assert first[0] == pytest.approx(math.sqrt(2 * 1e3 / mass), rel=1e-3)      # rigid on soft bearings
    assert first[-1] == pytest.approx(pinned, rel=3e-3)                        # bending on stiff ones
    assert result.mode_speeds[-1, 1] == pytest.approx(4 * pinned, rel=1e-2)
    assert result.mode_names[:2] == ("s cylindrical -> s bending", "s conical -> s bending")


def test_a_mode_of_one_character_keeps_one_name(tmp_path):
    """The same shaft over soft bearings only (1e2 .. 1e4 N/m, the shaft some 1e3 times stiffer):
    its rigid modes stay rigid, one name each."""
    model = rdm.load_model(_uniform_shaft(tmp_path / "shaft.toml", 1.0, 0.05))
    result = rdm.ucs_map(model, np.geomspace(1e2, 1e4, 5), modes=2)
    assert result.mode_names[:2] == ("s cylindrical", "s conical")


def _segments_cross(p, q, a, b):
    """Whether segment p-q crosses segment a-b (2-D, strictly)."""
    def side(o, s, t):
        return (s[0] - o[0]) * (t[1] - o[1]) - (s[1] - o[1]) * (t[0] - o[0])
    return side(p, q, a) * side(p, q, b) < 0 and side(a, b, p) * side(a, b, q) < 0


def test_the_fans_crossing_labels_sit_near_their_circles_and_lead_across_no_curve():
    """fan_on_bearings' map as the CLI draws it (its documented options), measured at the saved
    150 dpi: every crossing label's leader (from its box to its point) is at most 30 points long
    (the '3645' of three overlapping circles at 3e6 N/m stood 41 points away down the brown
    curve), crosses no mode's curve outside the circles, and no two labels overlap."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.text import Annotation, Text

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.ucs_map(model, np.geomspace(1e5, 1e9, 41), bearings=["fan-DE", "fan-NDE"],
                         operating=(1000 * math.pi / 30, 3000 * math.pi / 30))
    fig = result.plot()
    ax = fig.axes[0]
    fig.set_dpi(150)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    points = 150 / 72
    curves = [ax.transData.transform(np.column_stack(line.get_data())) for line in ax.get_lines()
              if str(line.get_label())[:1].isdigit()]
    circles = np.array([ax.transData.transform((c.stiffness, c.speed * 30 / math.pi)) for c in result.crossings])
    labels = [t for t in ax.texts if isinstance(t, Annotation) and t.get_gid() != "ucs-end-name"
              and t.get_text()[:1].isdigit() and len(t.get_text()) >= 3]
    assert labels
    boxes = []
    for text in labels:
        box = Text.get_window_extent(text, renderer)
        end = ax.transData.transform(text.xy)
        start = np.array([min(max(end[0], box.x0), box.x1), min(max(end[1], box.y0), box.y1)])
        assert np.hypot(*(end - start)) <= 30 * points, (text.get_text(), np.hypot(*(end - start)) / points)
        mine = circles[np.hypot(*(circles - end).T) < 12 * points]        # the circles it names, around its point
        for curve in curves:
            good = np.all(np.isfinite(curve), axis=1)
            for a, b, ok in zip(curve[:-1], curve[1:], good[:-1] & good[1:]):
                if not ok or not _segments_cross(start, end, a, b):
                    continue
                # where the leader meets the curve: within 3 points + 0.5 px of one of its circles
                d = end - start
                e = b - a
                t = ((a[0] - start[0]) * e[1] - (a[1] - start[1]) * e[0]) / (d[0] * e[1] - d[1] * e[0])
                meet = start + t * d
                assert np.hypot(*(mine - meet).T).min() <= 3 * points + 0.5, text.get_text()
        boxes.append(box)
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
