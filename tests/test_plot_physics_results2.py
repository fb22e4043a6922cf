"""Physics the simulation, run-up, 3D mode shape and interactive Campbell figures draw, given by
the results (the figures only read it).

A run's tilt sizes and spin frequencies (``SimulationResult.gamma_deg``, ``rotor_tilts_deg``,
``spin_frequencies_hz``, ``highest_spin_frequency_hz``), an order track's unwrapped phase
(``OrderTrack.unwrapped_phase_deg``), a mode's points at a phase and their orbits
(``ModeShape3D.*_at_phase``, ``displaced``, ``whirl_orbit``, ``whirl_direction``): checked
against closed forms written out here. The interactive Campbell diagram draws each mode's curve
through its critical speeds (``CampbellResult.mode_curves``), as the matplotlib one does.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.simulation.result import SimulationResult
from rotordyn_modal.simulation.runup import OrderTrack

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
PLOTTING = ROOT / "rotordyn_modal" / "plotting"


def _run(gamma, tilts, drive_speed, ratios):
    """A hand-made record: only the fields the properties read are meaningful."""
    n, r = len(drive_speed), len(ratios)
    zeros = np.zeros(n)
    return SimulationResult(
        time=np.arange(n, dtype=float), displacement=np.zeros((n, 6)), velocity=np.zeros((n, 6)),
        gamma=np.asarray(gamma, float), drive_angle=zeros, drive_speed=np.asarray(drive_speed, float),
        spin_speed=zeros, rotor_angles=np.zeros((n, r)), drive_torque=zeros, rotor_centers=np.zeros((n, r, 3)),
        rotor_displacements=np.zeros((n, r, 3)), rotor_tilts=np.asarray(tilts, float), bearing_forces=np.zeros((n, 0, 6)),
        sensors=np.zeros((n, 0)), kinetic_energy=zeros, elastic_energy=zeros, gravity_energy=zeros,
        states=np.zeros((n, 2)), sensor_names=[], rotor_names=[f"r{j}" for j in range(r)], bearing_names=[],
        speed_ratios=np.asarray(ratios, float), drive="ramp")


def test_tilt_sizes_are_the_euler_vectors_lengths_in_degrees():
    # (3, 4, 0) mrad: 5 mrad = 0.2864789 deg; a tilt of pi/180 rad about any axis is 1 deg
    gamma = [[3e-3, 4e-3, 0.0], [0.0, 0.0, 0.0], [0.0, -np.pi / 180, 0.0]]
    tilts = np.zeros((3, 2, 3))
    tilts[0, 0] = [np.pi / 180 / np.sqrt(2), np.pi / 180 / np.sqrt(2), 0.0]     # 1 deg
    tilts[1, 1] = [0.0, 1e-3, 1e-3 * np.sqrt(3)]                               # 2 mrad
    run = _run(gamma, tilts, [0.0, 10.0, 20.0], [1.0, -2.5])
    np.testing.assert_allclose(run.gamma_deg, [5e-3 * 180 / np.pi, 0.0, 1.0], rtol=1e-14, atol=0)
    assert run.rotor_tilts_deg.shape == (3, 2)
    np.testing.assert_allclose(run.rotor_tilts_deg, [[1.0, 0.0], [0.0, 2e-3 * 180 / np.pi], [0.0, 0.0]],
                               rtol=1e-14, atol=0)


def test_spin_frequencies_are_ratio_times_speed_over_two_pi():
    speed = np.array([0.0, 100.0, -300.0])               # rad/s, a run down through zero
    ratios = np.array([1.0, -2.5, 0.4])
    run = _run(np.zeros((3, 3)), np.zeros((3, 3, 3)), speed, ratios)
    expected = np.array([[0.0, 0.0, 0.0], [100 / (2 * np.pi), -250 / (2 * np.pi), 40 / (2 * np.pi)],
                         [-300 / (2 * np.pi), 750 / (2 * np.pi), -120 / (2 * np.pi)]])
    np.testing.assert_allclose(run.spin_frequencies_hz, expected, rtol=1e-14)
    assert run.highest_spin_frequency_hz == pytest.approx(750 / (2 * np.pi), rel=1e-14)   # 119.366 Hz


def test_unwrapped_phase_continues_a_ramp_across_the_wrap_and_breaks_where_unknown():
    true = np.arange(12) * 50.0 - 100.0                   # -100 ... 450 deg, steps of 50 deg
    wrapped = (true + 180.0) % 360.0 - 180.0              # as the track gives it, in [-180, 180)
    wrapped[4] = np.nan                                    # unknown: the line breaks there
    track = OrderTrack(speeds=np.arange(12.0), amplitude=np.ones(12), phase_deg=wrapped, sensor="s",
                       rotor="r", order=1.0)
    out = track.unwrapped_phase_deg
    expected = true.copy()
    expected[4] = np.nan
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)
    # a falling ramp of 170 deg steps stays falling (each step within 180 deg)
    falling = OrderTrack(speeds=np.arange(4.0), amplitude=np.ones(4), phase_deg=np.array([170.0, 0.0, -170.0, 20.0]),
                         sensor="s", rotor="r", order=1.0)
    np.testing.assert_allclose(falling.unwrapped_phase_deg, [170.0, 0.0, -170.0, -340.0], atol=1e-12)


@pytest.fixture(scope="module")
def gear_view():
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d

    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    return mode_shape_3d(rdm.modal(model, rdm.rpm(3000.0)), model, 5)


def test_points_at_a_phase_are_rest_plus_the_real_part_of_the_turned_motion(gear_view):
    from rotordyn_modal.analysis.mode_shapes import displaced, whirl_direction, whirl_orbit

    # closed form: x + Re(d) cos(phi) - Im(d) sin(phi)
    phi = 1.1
    rest, d = np.array([1.0, 2.0, 3.0]), np.array([0.3 + 0.4j, -0.2j, 0.5])
    expected = rest + d.real * np.cos(phi) - d.imag * np.sin(phi)
    np.testing.assert_allclose(displaced(rest, d, phi), expected, rtol=1e-15)
    phases = np.linspace(0, 2 * np.pi, 9)
    np.testing.assert_allclose(whirl_orbit(rest, d, phases),
                               rest + np.outer(np.cos(phases), d.real) - np.outer(np.sin(phases), d.imag), atol=1e-15)
    np.testing.assert_allclose(whirl_direction(d), -d.imag, rtol=0, atol=0)
    # the view's brackets, springs and arrows follow the same form
    view = gear_view
    cos, sin = np.cos(phi), np.sin(phi)
    assert len(view.outline.springs) and len(view.outline.arrows)
    for (a, b), spring, motion in zip(view.springs_at_phase(phi), view.outline.springs, view.spring_motion):
        np.testing.assert_allclose(a, np.asarray(spring.point_a) + motion[0].real * cos - motion[0].imag * sin,
                                   rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(b, np.asarray(spring.point_b) + motion[1].real * cos - motion[1].imag * sin,
                                   rtol=1e-12, atol=1e-15)
    points = view.arrows_at_phase(phi)
    assert points.shape == (len(view.outline.arrows), 3)
    for point, arrow, motion in zip(points, view.outline.arrows, view.arrow_motion):
        np.testing.assert_allclose(point, arrow.point + motion.real * cos - motion.imag * sin, rtol=1e-12, atol=1e-15)
    for bracket, rest_b, motion in zip(view.brackets_at_phase(phi), view.outline.brackets, view.bracket_motion):
        np.testing.assert_allclose(bracket, rest_b + motion.real * cos - motion.imag * sin, rtol=1e-12, atol=1e-15)
    # the orbits: rest + Re(d) cos - Im(d) sin, from where the point is drawn at phase 0
    points, motions = view.orbit_points()
    paths = view.orbit_paths(phases)
    assert paths.shape == (len(points), len(phases), 3) and len(points)
    for path, p, d in zip(paths, points, motions):
        np.testing.assert_allclose(path, p + np.outer(np.cos(phases), d.real) - np.outer(np.sin(phases), d.imag),
                                   rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(view.orbit_directions(), -motions.imag, rtol=0, atol=0)
    # half a period later every point is as far the other way
    for now, later, body in zip(view.at_phase(phi), view.at_phase(phi + np.pi), view.outline.bodies):
        np.testing.assert_allclose(now + later, 2 * body.vertices, rtol=1e-12, atol=1e-12)


def _calls(path):
    """Every attribute, name and function defined or used in a module (its source)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    names |= {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    names |= {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}
    return names


def test_the_figures_read_the_moved_quantities_and_compute_none():
    simulation = _calls(PLOTTING / "simulation.py")
    assert not {"unwrap", "linalg", "degrees", "radians", "_unwrapped_deg", "_highest", "speed_ratios"} & simulation
    assert {"gamma_deg", "rotor_tilts_deg", "unwrapped_phase_deg"} <= simulation
    shapes = _calls(PLOTTING / "shapes3d.py")
    assert not {"real", "exp", "bracket_motion", "spring_motion", "arrow_motion"} & shapes
    assert {"brackets_at_phase", "springs_at_phase", "arrows_at_phase", "orbit_paths", "orbit_directions"} <= shapes
    interactive = _calls(PLOTTING / "interactive.py")
    assert "mode_curves" in interactive


def test_interactive_campbell_curves_pass_through_their_critical_speeds():
    """On a sweep of five speeds the critical speeds lie between the sweep's points; each mode's
    drawn curve holds the (speed, frequency) of each of its critical speeds that is no jump."""
    pytest.importorskip("plotly")
    from rotordyn_modal.plotting.interactive import campbell_figure

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    res = rdm.campbell(model, rdm.rpm(np.linspace(0, 9000, 5)), orders=(1, 2))
    critical = res.critical
    assert len(critical) >= 3
    fig = campbell_figure(res)
    rpm = 30 / np.pi
    checked = 0
    for k in range(len(critical)):
        if res.critical_jumps[k] or np.isin(critical.speeds[k], res.speeds):
            continue
        label = res.modes[int(critical.mode[k]) - 1]
        traces = [t for t in fig.data if t.name.startswith(f"mode {label} (")]
        hit = any(np.any(np.isclose(np.asarray(t.x, float), critical.speeds[k] * rpm, rtol=1e-12, atol=0)
                         & np.isclose(np.asarray(t.y, float), critical.frequencies_hz[k], rtol=1e-12, atol=0))
                  for t in traces)
        assert hit, (label, critical.speeds[k] * rpm, critical.frequencies_hz[k])
        checked += 1
    assert checked >= 3
    # and every curve keeps the sweep's own speeds
    for t in fig.data:
        if t.name.startswith("mode "):
            x = np.asarray(t.x, float) / rpm
            assert set(res.speeds) <= set(x)
