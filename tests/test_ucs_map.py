"""Undamped critical speed map (``ucs-map``): against ``critical-speeds``, closed forms of a rigid
rotor on two springs, the rigid-support asymptote and a bearing curve's crossings."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.ucs_map import ucs_map
from rotordyn_modal.cli import main

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
MASS, IP, ID, SPAN = 30.0, 0.2, 1.1, 0.35          # kg, kg m^2, kg m^2, m (bearings at +-SPAN)


def _rotor_on_springs(stiffness=2e6, polar=IP, casing=False, damping=0.0, **bearing):
    """A rigid rotor on two isotropic bearings at +-SPAN; with ``casing`` the bearings sit in a
    casing on four undamped mounts (no axial stiffness: the rotor follows the casing axially)."""
    bearings = [dict(name=name, rotor="r", position=[x, 0.0, 0.0], stiffness=stiffness, **bearing)
                for name, x in (("A", SPAN), ("B", -SPAN))]
    if damping:
        for b in bearings:
            b["damping"] = damping
    extra = {}
    if casing:
        extra = dict(stator=rdm.Stator(mass=80.0, inertia=[4.0, 6.0, 7.0], center_of_mass=[0.05, 0.0, -0.1]),
                     suspensions=[rdm.Suspension(f"m{i}", [x, y, -0.3], [3e5, 4e5, 6e5])
                                  for i, (x, y) in enumerate([(0.4, 0.3), (0.4, -0.3), (-0.4, 0.3), (-0.4, -0.3)])])
    return rdm.Model(rotors=[rdm.Rotor("r", MASS, [0.0, 0.0, 0.0], polar, ID, speed_ratio=1.0)],
                     bearings=bearings, **extra)


def test_map_at_the_bearing_stiffness_equals_critical_speeds():
    """At the model's own (constant, isotropic, undamped) bearing stiffness the map's critical
    speeds are the forward order-1 critical speeds of ``critical_speeds`` (its own grid and
    refinement on the quadratic eigenproblem), to 1e-9."""
    k0 = 2e6
    model = _rotor_on_springs(k0, casing=True)
    result = ucs_map(model, [k0 / 10, k0, k0 * 10], modes=6)
    table = rdm.critical_speeds(model, rdm.rpm(np.linspace(0, 20000, 201)), orders=(1,))
    forward = np.sort(table.speeds[(table.source == "r") & (table.order == 1) & (table.whirl == "forward")])
    found = result.speeds[1][np.isfinite(result.speeds[1])]
    assert len(found) == len(forward) == 4         # the casing's modes whirl every way: four forward
    np.testing.assert_allclose(found, forward, rtol=1e-9)


@pytest.mark.parametrize("polar", [IP, 2.0])
def test_rigid_rotor_on_two_springs_equals_the_closed_form(polar):
    """Cylindrical ``sqrt(2k/m)`` and forward conical ``sqrt(2 k L^2 / (Id - Ip))`` (gyroscopic
    stiffening at Omega = omega: ``Id w^2 - Ip Omega w = 2 k L^2``) as k varies over decades; a
    disc (Ip > Id) has no forward conical critical speed, and the backward conical crossing
    ``sqrt(2 k L^2 / (Id + Ip))`` is never in the map."""
    k = np.geomspace(1e4, 1e10, 13)
    result = ucs_map(_rotor_on_springs(polar=polar), k, modes=3)
    cylindrical = np.sqrt(2 * k / MASS)
    if polar < ID:
        conical = np.sqrt(2 * k * SPAN**2 / (ID - polar))
        expected = np.sort(np.c_[cylindrical, conical], axis=1)
        np.testing.assert_allclose(result.speeds[:, :2], expected, rtol=1e-10)
        assert np.isnan(result.speeds[:, 2]).all()
    else:
        np.testing.assert_allclose(result.speeds[:, 0], cylindrical, rtol=1e-10)
        assert np.isnan(result.speeds[:, 1:]).all()


def test_each_mode_is_followed_through_the_crossings_of_its_curve_with_others():
    """Rotor r1 on the swept bearings, rotor r2 (heavier) on bearings of its own, fixed: r1's
    cylindrical sqrt(2k/m) and forward conical sqrt(2 k L^2 / (Id - Ip)) rise through r2's
    k-independent cylindrical and conical speeds. Each followed curve is one closed form on both
    sides of every crossing (the j-th lowest speed passes from one to another), named by its
    rotor and motion; the map's ranks stay the closed forms sorted."""
    m2, ip2, id2, span2, k2 = 50.0, 0.5, 2.0, 0.3, 5e6
    r2 = rdm.Rotor("r2", m2, [0.0, 0.6, 0.0], ip2, id2, speed_ratio=1.0)
    bearings = [dict(name=name, rotor=rotor, position=[x, y, 0.0], stiffness=stiffness)
                for name, rotor, x, y, stiffness in (("A", "r1", SPAN, 0.0, 2e6), ("B", "r1", -SPAN, 0.0, 2e6),
                                                     ("C", "r2", span2, 0.6, k2), ("D", "r2", -span2, 0.6, k2))]
    model = rdm.Model(rotors=[rdm.Rotor("r1", MASS, [0.0, 0.0, 0.0], IP, ID, speed_ratio=1.0), r2], bearings=bearings,
                      reference_rotor="r1")
    k = np.geomspace(1e5, 1e9, 17)
    result = ucs_map(model, k, modes=4, bearings=["A", "B"])
    closed = np.c_[np.sqrt(2 * k / MASS), np.sqrt(2 * k * SPAN**2 / (ID - IP)),
                   np.full_like(k, np.sqrt(2 * k2 / m2)), np.full_like(k, np.sqrt(2 * k2 * span2**2 / (id2 - ip2)))]
    names = np.array(["r1 cylindrical", "r1 conical", "r2 cylindrical", "r2 conical"])
    first = np.argsort(closed[0])                       # numbered by their speed at the first stiffness
    assert (np.diff(np.argsort(closed, axis=1), axis=0) != 0).any()          # the curves do cross
    np.testing.assert_allclose(result.mode_speeds, closed[:, first], rtol=1e-10)
    assert result.mode_names == tuple(names[first])
    np.testing.assert_allclose(result.speeds, np.sort(closed, axis=1), rtol=1e-10)
    # bearing A's own 2e6 N/m (not a point of the sweep) meets every mode, each by its number and name
    at = {(c.axis, c.mode, c.name): c.speed for c in result.crossings if c.bearing == "A"}
    own = np.c_[np.sqrt(2 * 2e6 / MASS), np.sqrt(2 * 2e6 * SPAN**2 / (ID - IP)), closed[:1, 2:]][0, first]
    for axis in ("xx", "yy"):
        found = np.array([at[axis, j + 1, name] for j, name in enumerate(names[first])])
        np.testing.assert_allclose(found, own, rtol=1e-10)


def test_followed_modes_cover_the_lowest_forward_speeds_each_root_once():
    """A rotor in a casing on mounts, whose modes change their whirl (and so start and stop
    being forward critical speeds) as k varies: at every stiffness the ``modes`` lowest forward
    critical speeds are all on followed curves, every point of a curve is a forward critical
    speed there, and no root is on two curves."""
    k = np.geomspace(1e4, 1e10, 25)
    model = _rotor_on_springs(casing=True)
    result = ucs_map(model, k, modes=4)
    every = ucs_map(model, k, modes=40).speeds                  # all forward critical speeds
    for row, lowest, forward in zip(result.mode_speeds, result.speeds, every):
        on = np.sort(row[np.isfinite(row)])
        assert len(np.unique(on)) == len(on)
        assert all(np.isclose(on, s, rtol=1e-12).any() for s in lowest[np.isfinite(lowest)])
        assert all(np.isclose(forward, s, rtol=1e-12).any() for s in on)
    ended = np.isfinite(result.mode_speeds[:-1]) & ~np.isfinite(result.mode_speeds[1:])
    assert ended.any()                                       # the case is one where modes stop


def test_figure_draws_the_rigid_asymptotes_beyond_the_sweep():
    """The rigid-support lines lie past the sweep's last stiffness (at it they hide under the
    curves that have reached them), at the asymptote's speeds."""
    import matplotlib

    matplotlib.use("Agg")
    k = np.geomspace(1e5, 1e10, 11)
    result = ucs_map(_rotor_on_springs(casing=True), k, modes=2)
    fig = result.plot()
    ax = fig.axes[0]
    lines = [c for c in ax.collections if str(c.get_label()).startswith("rigid supports")]
    assert len(lines) == 1 and ax.get_xlim()[1] > 1.9 * k[-1]
    segments = np.array(lines[0].get_segments())                    # (lines, 2 points, x y)
    np.testing.assert_allclose(segments[:, :, 0], [[k[-1], ax.get_xlim()[1]]] * len(segments))
    expected = result.rigid_speeds[np.isfinite(result.rigid_speeds)] * 30 / np.pi
    np.testing.assert_allclose(np.sort(segments[:, 0, 1]), np.sort(expected), rtol=1e-12)
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_rigid_support_asymptote_is_the_rotor_fixed_to_the_casing():
    """The map's limit as k grows: each chosen bearing radially rigid. A rotor on two such
    bearings without axial stiffness is rigidly attached to the casing: the asymptote equals the
    forward critical speeds of the same machine without its bearings (``critical_speeds``), and
    the map at 1e13 N/m has reached it (the mounts' 1e5 N/m beside it: 1e-6 relative)."""
    model = _rotor_on_springs(casing=True)
    result = ucs_map(model, np.geomspace(1e5, 1e13, 17), modes=2)
    attached = rdm.Model(rotors=model.rotors, stator=model.stator, suspensions=model.suspensions)
    table = rdm.critical_speeds(attached, rdm.rpm(np.linspace(0, 6000, 201)), orders=(1,))
    forward = np.sort(table.speeds[(table.order == 1) & (table.whirl == "forward")])
    np.testing.assert_allclose(result.rigid_speeds[:len(forward)], forward, rtol=1e-9)
    assert np.isnan(result.rigid_speeds[len(forward):]).all()
    np.testing.assert_allclose(result.speeds[-1, :len(forward)], forward, rtol=1e-5)
    assert abs(result.speeds[0, 0] / forward[0] - 1) > 1e-2            # far from it at 1e5 N/m


def test_a_speed_table_bearing_crosses_the_modes_where_the_closed_form_says():
    """Two bearings tabulated linearly over speed, K(s) = a + b s: the cylindrical mode's curve
    sqrt(2K/m) meets the bearings' curve where m s^2 - 2 b s - 2 a = 0; the curve drawn is the
    table's own stiffness."""
    a, b = 1e6, 2e3                                      # N/m, N/m per rad/s
    speeds = np.array([0.0, 20000.0])                    # rpm
    stiffness = a + b * rdm.rpm(speeds)
    model = _rotor_on_springs(stiffness=[float(s) for s in stiffness], speeds_rpm=speeds.tolist())
    result = ucs_map(model, np.geomspace(1e5, 1e9, 9), modes=2)
    expected = (2 * b + np.sqrt(4 * b**2 + 8 * a * MASS)) / (2 * MASS)
    crossings = [c for c in result.crossings if c.mode == 1]
    assert {c.bearing for c in crossings} == {"A", "B"} and {c.axis for c in crossings} == {"xx", "yy"}
    for crossing in crossings:
        assert crossing.speed == pytest.approx(expected, rel=1e-9)
        assert crossing.stiffness == pytest.approx(a + b * expected, rel=1e-9)
    curve = result.curves[0]
    np.testing.assert_allclose(curve.kxx, a + b * curve.speeds, rtol=1e-12)


def test_refusals():
    model = _rotor_on_springs()
    for kwargs, words in (({"stiffness": [1e6, 1e5]}, "increasing"), ({"stiffness": [0.0, 1e5]}, "from 0.001"),
                          ({"stiffness": [1e5, 1e6], "bearings": ["C"]}, "expected names"),
                          ({"stiffness": [1e5, 1e6], "modes": 0}, "whole number")):
        with pytest.raises(rdm.InputError, match=words):
            ucs_map(model, **kwargs)
    journal = rdm.load_model("examples/journal_rotor.toml")
    with pytest.raises(rdm.InputError, match="speed-dependent"):
        ucs_map(journal, [1e6, 1e7], bearings=["DE"])


def test_command_line(tmp_path, capsys):
    out, plot = tmp_path / "ucs.csv", tmp_path / "ucs.png"
    code = main(["ucs-map", "examples/journal_rotor.toml", "--stiffness", "1e5:1e10:11", "--modes", "2",
                 "--operating", "1000:3000", "--out", str(out), "--plot", str(plot)])
    assert code == 0 and plot.stat().st_size > 0
    assert out.read_text().splitlines()[0] == "stiffness_n_per_m,mode,name,speed_rpm,frequency_hz"
    assert "meets mode 1" in capsys.readouterr().err
    # one numbering: the CSV's modes are the figure's followed modes (numbers and names)
    import pandas as pd

    written = pd.read_csv(out)
    result = ucs_map(rdm.load_model("examples/journal_rotor.toml"), np.geomspace(1e5, 1e10, 11), modes=2)
    assert sorted(set(zip(written["mode"], written["name"]))) == \
        [(j + 1, name) for j, name in enumerate(result.mode_names)]
    np.testing.assert_allclose(written["speed_rpm"].to_numpy().reshape(result.mode_speeds.shape),
                               result.mode_speeds * 30 / np.pi, rtol=1e-9)
    assert main(["ucs-map", "examples/journal_rotor.toml", "--stiffness", "0:1e10:11"]) == 2
    assert main(["ucs-map", "examples/journal_rotor.toml", "--stiffness", "1e5:1e10:11", "--bearings", "X"]) == 2


def test_speeds_on_constant_bearings_say_they_change_nothing(tmp_path, capsys):
    """``--speeds`` sets where speed-dependent bearings' curves are drawn: on a map of constant
    bearings it changed nothing and was ignored without a word; now one warning line says so, and
    the map is the one without it. On journal bearings it is used, and no such line is written."""
    fan = ["ucs-map", "examples/fan_on_bearings.toml", "--stiffness", "1e5:1e9:5"]
    assert main(fan + ["--out", str(tmp_path / "a.csv")]) == 0
    assert "changes nothing" not in capsys.readouterr().err
    assert main(fan + ["--speeds", "100:3000:5", "--out", str(tmp_path / "b.csv")]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "changes nothing" in line]
    assert len(lines) == 1 and "--speeds 100:3000:5" in lines[0] and "fan-NDE" in lines[0], lines
    assert (tmp_path / "a.csv").read_text() == (tmp_path / "b.csv").read_text()
    journal = ["ucs-map", "examples/journal_rotor.toml", "--stiffness", "1e5:1e10:5", "--speeds", "100:3000:5",
               "--out", str(tmp_path / "c.csv")]
    assert main(journal) == 0
    assert "changes nothing" not in capsys.readouterr().err


def test_figure_writes_every_crossing_and_name_clear_of_curves_markers_and_each_other():
    """The fan's map (three bearing stiffnesses meeting the modes in tight clusters, five curves
    ending inside the axes): every crossing's speed is written (none hidden behind a neighbour's),
    and every label inside the axes, measured on the rendered figure, overlaps no other label and
    no crossing marker, and no curve runs through it but within its own anchor's marker."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = ucs_map(model, np.geomspace(1e5, 1e10, 31))
    fig = result.plot()
    ax = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    labels = [t for t in ax.texts if getattr(t, "xycoords", "data") == "data"]
    markers = np.concatenate([ax.transData.transform(line.get_xydata()) for line in ax.get_lines()
                              if line.get_marker() == "o" and line.get_linestyle() == "None"])
    speeds = sorted({(round(c.stiffness, 6), round(c.speed * 30 / np.pi, 6)) for c in result.crossings})
    # circles that lie on each other share a label ('3939/3959', figs27r), a speed written once
    written = sorted(w for t in labels if len(t.get_text()) >= 3 for w in t.get_text().split("/"))
    assert set(written) == {f"{rpm:.0f}" for _, rpm in speeds} and len(written) >= 12
    stopped = [j for j in range(result.mode_speeds.shape[1]) if not np.isfinite(result.mode_speeds[-1, j])
               and np.isfinite(result.mode_speeds[:, j]).any()]
    assert sorted(t.get_text() for t in labels if len(t.get_text()) < 3) == sorted(str(j + 1) for j in stopped)
    segments = curve_segments(ax)
    radius = 6 * fig.dpi / 72 * np.sqrt(2) + 1
    marker = 3 * fig.dpi / 72                      # the circles' radius (6 points across)
    boxes = [glyph_box(t, renderer) for t in labels]
    for t, box in zip(labels, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, t.get_text()
        anchor = ax.transData.transform(t.xy)
        assert not len(crossings(box, segments, [anchor], radius)), t.get_text()
        gap = np.hypot(np.maximum(0, np.maximum(box.x0 - markers[:, 0], markers[:, 0] - box.x1)),
                       np.maximum(0, np.maximum(box.y0 - markers[:, 1], markers[:, 1] - box.y1)))
        assert gap.min() >= marker - 0.5, f"a crossing's marker under {t.get_text()}"
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b), "two labels overlap"
    plt.close(fig)


# -- flexible rotors (issue 29: "where rotors are flexible, every item covers them") ----------------
STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}


def _flexible_shaft(stiffness, length=1.0, diameter=0.05, elements=8, disk=True):
    """A uniform Rayleigh shaft (no shear deformation) along x on two isotropic bearings at its
    ends, with a disk at 0.4 of its length (or bare)."""
    rotor = {"name": "s", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "shear": "none",
             "shaft": [{"length": length, "outer_diameter": diameter, "material": "steel", "elements": elements}]}
    if disk:
        rotor["disks"] = [{"name": "d", "axial_position": 0.4 * length, "mass": 5.0, "polar_inertia": 0.03,
                           "diametral_inertia": 0.016}]
    return rdm.Model.from_dict({
        "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL], "rotors": [rotor],
        "bearings": [{"name": name, "rotor": "s", "axial_position": z, "stiffness": stiffness}
                     for name, z in (("a", 0.0), ("b", length))]})


def test_flexible_rotor_map_at_the_bearing_stiffness_equals_critical_speeds():
    """A flexible shaft with a disk on two constant bearings: the map's critical speeds at the
    bearings' own stiffness are the forward order-1 critical speeds of ``critical_speeds`` (a
    sweep of the damped-model machinery: the pencil's roots crossing the order line, refined),
    three bending-mode crossings, to 1e-9."""
    k0 = 3e6
    model = _flexible_shaft(k0)
    result = ucs_map(model, [k0 / 10, k0, k0 * 10], modes=3)
    table = rdm.critical_speeds(model, rdm.rpm(np.linspace(0, 30000, 31)), orders=(1,))
    forward = np.sort(table.speeds[(table.order == 1) & (table.whirl == "forward")])
    assert len(forward) == 3 and np.all(np.isfinite(result.speeds[1]))
    np.testing.assert_allclose(result.speeds[1], forward, rtol=1e-9)


def test_flexible_rotor_rigid_support_asymptote_is_the_pinned_spinning_shaft():
    """A bare uniform Rayleigh shaft on end bearings whose stiffness grows: the map reaches the
    pinned-pinned shaft's forward synchronous critical speeds, whose closed form (mode sin(k z),
    k = j pi / L; the whirl equation (rho A + rho I k^2) w^2 - 2 rho I k^2 Omega w - E I k^4 = 0
    at w = Omega) is w^2 = E I k^4 / (rho A - rho I k^2). The finite elements lie above it by
    less than (k h)^4 / 1000 (docs/theory.md §15), and the map at 1e14 N/m is at the asymptote
    within the bearings' compliance: below the mode's modal stiffness E I k^4 L / 2 over 1e14
    (1e-6, 1.5e-5 and 8e-5 for the three modes)."""
    length, diameter, elements = 0.6, 0.08, 12
    model = _flexible_shaft(1e7, length, diameter, elements, disk=False)
    result = ucs_map(model, np.geomspace(1e5, 1e14, 10), modes=3)
    area, second = np.pi / 4 * diameter**2, np.pi / 64 * diameter**4
    k = np.arange(1, 4) * np.pi / length
    exact = np.sqrt(STEEL["young_modulus"] * second * k**4 / (STEEL["density"] * (area - second * k**2)))
    error = result.rigid_speeds[:3] / exact - 1
    assert np.all(error > 0) and np.all(error < (k * length / elements) ** 4 / 1000), error
    modal_stiffness = STEEL["young_modulus"] * second * k**4 * length / 2
    assert np.all(np.abs(result.speeds[-1] / result.rigid_speeds[:3] - 1) < modal_stiffness / 1e14)
    assert np.all(result.speeds[0] < 0.5 * result.rigid_speeds[:3])        # far from it at 1e5 N/m
