"""Mode shapes as deflected shaft lines (issue 28): the lines against closed forms and the rigid
motion, the figure's markers where the model puts them, the command line, the 3D view of a
flexible rotor."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.analysis.modal import modal
from rotordyn_modal.analysis.mode_shapes import mode_index, mode_shape_3d, shaft_lines
from rotordyn_modal.cli.main import main
from rotordyn_modal.elements.shaft import Material, lateral_deflection
from rotordyn_modal.io.model_file import load_model
from rotordyn_modal.plotting.shaft_modes import plot_shaft_modes
from rotordyn_modal.model.geometry import transverse_axes

ROOT = Path(__file__).resolve().parent.parent
LENGTH, ELEMENTS = 1.0, 8

UNIFORM = f'''name = "uniform shaft on stiff end bearings"
spin_axis = [1.0, 0.0, 0.0]
[[materials]]
name = "steel"
density = 7810.0
young_modulus = 2.11e11
poisson_ratio = 0.3
[[rotors]]
name = "shaft"
speed_ratio = 1.0
start = [0.0, 0.0, 0.0]
shear = "none"
[[rotors.shaft]]
length = {LENGTH}
outer_diameter = 0.05
material = "steel"
elements = {ELEMENTS}
[[rotors.disks]]
name = "hub"
axial_position = 0.25
mass = 1e-9
polar_inertia = 1e-12
diametral_inertia = 1e-12
[[bearings]]
name = "left"
rotor = "shaft"
axial_position = 0.0
stiffness = 1e14
[[bearings]]
name = "right"
rotor = "shaft"
axial_position = {LENGTH}
stiffness = 1e14
'''


@pytest.fixture(scope="module")
def uniform(tmp_path_factory):
    path = tmp_path_factory.mktemp("uniform") / "uniform.toml"
    path.write_text(UNIFORM)
    model = load_model(path)
    return model, modal(model, 0.0)


@pytest.fixture(scope="module")
def gear_machine():
    model = load_model(ROOT / "examples" / "gear_machine.toml")
    return model, modal(model, 3000 * np.pi / 30)


def _fit_error(u, reference):
    """Largest distance of ``u`` from its best multiple of ``reference`` (both planes)."""
    return max(np.abs(p - (p @ reference) / (reference @ reference) * reference).max() for p in u)


def test_first_mode_of_a_simply_supported_shaft_is_a_half_sine(uniform):
    """Pinned-pinned uniform beam (with or without rotary inertia): first mode sin(pi z / L).
    At the nodes the finite element's values are the exact ones (a uniform beam's cubic
    elements are nodally exact) up to the bearings' compliance, 48 E I / (L^3 k) ~ 3e-8; between
    the nodes the line is the element's cubic, whose distance from the sine is at most
    the Hermite interpolation bound h^4 max|w''''| / 384 = h^4 (pi / L)^4 / 384 (6e-5 here)."""
    model, result = uniform
    view = shaft_lines(result, model, 1)
    (line,) = view.lines
    assert line.flexible and view.lateral
    assert np.abs(line.displacement).max() == pytest.approx(1.0, abs=1e-12)
    assert _fit_error(line.node_displacement, np.sin(np.pi * line.node_position / LENGTH)) < 1e-6
    h = LENGTH / ELEMENTS
    bound = h ** 4 * (np.pi / LENGTH) ** 4 / 384
    error = _fit_error(line.displacement, np.sin(np.pi * line.position / LENGTH))
    assert error < bound
    # the rotations are the slopes of the sine: theta_b = +du_a/dz, theta_a = -du_b/dz
    slope = np.pi / LENGTH * np.cos(np.pi * line.node_position / LENGTH)
    u_a, u_b = line.node_displacement
    amplitude_a = u_a @ np.sin(np.pi * line.node_position) / (np.sin(np.pi * line.node_position) ** 2).sum()
    amplitude_b = u_b @ np.sin(np.pi * line.node_position) / (np.sin(np.pi * line.node_position) ** 2).sum()
    assert np.allclose(line.node_rotation[1], amplitude_a * slope, atol=1e-3)
    assert np.allclose(line.node_rotation[0], -amplitude_b * slope, atol=1e-3)


def test_the_line_passes_through_the_nodes_and_the_mode_shape(uniform):
    """The interpolated line equals the nodes' values at the nodes, and those are the mode
    shape's coordinates ``shaft.nK.uy`` (relative motion; the ground does not move), with one
    factor for all."""
    model, result = uniform
    for mode in (1, 3):
        (line,) = shaft_lines(result, model, mode).lines
        at_nodes = [int(np.argmin(np.abs(line.position - z))) for z in line.node_position]
        assert np.allclose(line.position[at_nodes], line.node_position, rtol=0, atol=1e-15)
        assert np.abs(line.displacement[:, at_nodes] - line.node_displacement).max() < 1e-14
        shape = result.shapes[mode_index(result, mode)]
        names = list(result.dof_names)
        coordinates = np.array([[shape[names.index(f"shaft.n{k}.u{axis}")] for k in range(ELEMENTS + 1)]
                                for axis in "yz"])
        factor = line.node_relative_displacement.ravel() @ coordinates.ravel().conj() / np.vdot(coordinates,
                                                                                                 coordinates)
        assert np.allclose(line.node_relative_displacement, factor * coordinates, rtol=0, atol=1e-12)
        assert np.allclose(line.node_displacement, line.node_relative_displacement, rtol=0, atol=1e-12)


def test_the_element_interpolation_reproduces_a_rigid_motion():
    """A rigid motion u = c + theta x z of a tapered, shear-deformable element: nodes carry
    u_a = c_a + theta_b z, u_b = c_b - theta_a z; the interpolated line is that straight line."""
    steel = Material("steel", 7810.0, 2.11e11, 8.1e10)
    length, c, theta = 0.3, np.array([0.2, -0.1]), np.array([0.7, 1.3])     # theta = (theta_a, theta_b)
    ends = np.array([0.0, length])
    u_a, u_b = c[0] + theta[1] * ends, c[1] - theta[0] * ends
    nodes = np.array([u_a[0], u_b[0], theta[0], theta[1], u_a[1], u_b[1], theta[0], theta[1]])
    xi = np.linspace(0, 1, 11)
    line = lateral_deflection(length, (0.08, 0.05), (0.02, 0.01), steel, nodes, xi, shear="cowper")
    assert np.allclose(line[0], c[0] + theta[1] * length * xi, rtol=0, atol=1e-14)
    assert np.allclose(line[1], c[1] - theta[0] * length * xi, rtol=0, atol=1e-14)


def test_a_rigid_rotor_is_a_straight_line_moving_as_the_rigid_body(gear_machine):
    """Each point of a rigid rotor's line is shape_at of that point (one complex factor for the
    whole mode, every rotor), and the line is straight."""
    model, result = gear_machine
    a, b = transverse_axes(model.spin_axis)
    e = np.asarray(model.spin_axis, float)
    view = shaft_lines(result, model, 2)
    k = mode_index(result, 2)
    expected, drawn = [], []
    for line in view.lines:
        assert not line.flexible
        centre = np.asarray(model.rotor(line.rotor).center_of_mass, float)
        for z, u in zip(line.position, line.displacement.T):
            motion = result.shape_at(centre + (z - centre @ e) * e, body=line.rotor)[k]
            expected.append([motion @ a, motion @ b])
            drawn.append(u)
        second = np.diff(line.displacement, 2, axis=1)
        assert np.abs(second).max() < 1e-12
    expected, drawn = np.array(expected), np.array(drawn)
    factor = drawn.ravel() @ expected.ravel().conj() / np.vdot(expected, expected)
    assert np.allclose(drawn, factor * expected, rtol=0, atol=1e-12)
    assert np.abs(drawn).max() == pytest.approx(1.0)


def test_markers_stand_where_the_model_puts_them(uniform):
    """Bearings (triangles), disks (bars) and nodes (ticks) at their positions on the axis."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model, result = uniform
    fig = shaft_lines(result, model, 1).plot()
    lines = {line.get_gid(): line for ax in fig.axes for line in ax.get_lines()}
    for bearing in model.bearings:
        marker = lines[f"bearing:shaft:{bearing.name}"]
        assert marker.get_marker() == "^"
        assert marker.get_xdata() == pytest.approx([bearing.position[0]])
    disk = lines["disk:shaft:hub"].get_xdata()
    assert disk == pytest.approx([0.25, 0.25])
    nodes = lines["nodes:shaft"].get_xdata()
    assert nodes == pytest.approx(np.linspace(0.0, LENGTH, ELEMENTS + 1))
    assert "mode 1:" in fig.axes[0].get_title()
    plt.close(fig)


def test_an_axial_mode_draws_no_lateral_line(tmp_path):
    """An axial mode (the shaft on its thrust bearing) moves nothing laterally: zero lines, said
    in the title, not round-off blown up to 1."""
    path = tmp_path / "axial.toml"
    path.write_text(UNIFORM.replace('axial_position = {0}\nstiffness = 1e14\n'.format(LENGTH),
                                    'axial_position = {0}\nstiffness = 1e14\naxial_stiffness = 1e7\n'
                                    .format(LENGTH)))
    model = load_model(path)
    result = modal(model, 0.0)
    names = list(result.dof_names)
    axial = [m for m in range(1, int(result.oscillatory.sum()) + 1)
             if np.argmax(np.abs(result.shapes[mode_index(result, m)])) == names.index("shaft.ux")]
    assert axial
    view = shaft_lines(result, model, axial[0])
    assert not view.lateral and np.abs(view.lines[0].displacement).max() == 0


def test_command_line_writes_the_figure_and_refuses_bad_modes(tmp_path, capsys):
    model = tmp_path / "uniform.toml"
    model.write_text(UNIFORM)
    out = tmp_path / "lines.png"
    assert main(["modes", str(model), "--speed", "3000", "--quiet", "--plot-shaft", str(out), "--modes", "1-2"]) == 0
    assert out.stat().st_size > 10_000
    for bad in ("0", "3-1", "x", "1-"):
        assert main(["modes", str(model), "--speed", "3000", "--plot-shaft", str(tmp_path / "b.png"),
                     "--modes", bad]) == 2
        assert f"--modes {bad!r}" in capsys.readouterr().err
    assert main(["modes", str(model), "--speed", "3000", "--modes", "1"]) == 2
    assert "--plot-shaft" in capsys.readouterr().err
    assert not (tmp_path / "b.png").exists()


def test_the_3d_view_draws_a_flexible_rotor_as_its_deflected_line(uniform):
    """The 3D body of a flexible rotor is its line (through the nodes, the element's cubic between
    them, as shaft_lines) and a circle per disk; at the nodes it moves as shape_at."""
    model, result = uniform
    view = mode_shape_3d(result, model, 1)
    (body,) = [b for b in view.outline.bodies if b.name == "shaft"]
    assert body.kind == "shaft"
    line = list(body.faces[0])
    (drawn,) = shaft_lines(result, model, 1).lines
    assert np.allclose(body.vertices[line, 0], drawn.position, rtol=0, atol=1e-15)
    motion = view.body_motion[0][line]
    k = mode_index(result, 1)
    for z in drawn.node_position:
        i = int(np.argmin(np.abs(body.vertices[line, 0] - z)))
        assert np.allclose(motion[i], view.scale * result.shape_at([z, 0.0, 0.0], body="shaft")[k], rtol=0,
                           atol=1e-12 * view.scale)
    # between the nodes the same line as shaft_lines, up to the one factor
    lateral = motion[:, 1:].T
    factor = np.vdot(drawn.displacement, lateral) / np.vdot(drawn.displacement, drawn.displacement)
    assert np.allclose(lateral, factor * drawn.displacement, rtol=0, atol=1e-12 * np.abs(lateral).max())



def test_absolute_line_is_the_relative_line_plus_the_casing(tmp_path):
    """On a casing on mounts, a node's absolute motion is the casing's rigid motion at the node
    (``shape_at`` of the stator there) plus its motion relative to the casing, and a line in
    between obeys the same sum (the casing's motion is a straight line, which the elements
    reproduce exactly)."""
    model = load_model(ROOT / "examples" / "flexible_pump_on_mounts.toml")
    result = modal(model, 3000 * np.pi / 30)
    a, b = transverse_axes(model.spin_axis)
    e = np.asarray(model.spin_axis, float)
    for mode in (1, 7):
        view = shaft_lines(result, model, mode)
        k = mode_index(result, mode)
        (pump,) = [line for line in view.lines if line.rotor == "pump"]
        shaft = model.rotor("pump").flexible
        casing = np.array([result.shape_at(shaft.start + (z - shaft.start @ e) * e)[k] for z in pump.node_position])
        drawn_casing = pump.node_displacement - pump.node_relative_displacement
        factor = np.vdot(casing @ np.array([a, b]).T, drawn_casing.T) / np.vdot(casing @ np.array([a, b]).T,
                                                                                casing @ np.array([a, b]).T)
        assert np.allclose(drawn_casing, factor * (casing @ np.array([a, b]).T).T, rtol=0, atol=1e-12)
        assert np.abs(drawn_casing).max() > 0.05                   # the casing moves: not 0 = 0
        between = pump.displacement - pump.relative
        basis = np.stack([np.ones_like(pump.position), pump.position], axis=1)
        fitted = basis @ np.linalg.lstsq(basis, between.T, rcond=None)[0]
        assert np.abs(fitted.T - between).max() < 1e-12 * np.abs(between).max()


@pytest.mark.parametrize("example, modes", [("compressor_rotor.toml", (4, 5, 6))])
def test_disk_names_are_clear_of_every_line_and_of_each_other(example, modes):
    """Issue 27: a disk's name stood on its bar's top, where the mode's lines run through it
    (the compressor's modes 4-6 at 3000 rpm). Measured on the rendered
    figure: no drawn line crosses a name's glyphs, no two names overlap, each name is straight
    above its disk's bar and inside its panel."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box

    model = load_model(ROOT / "examples" / example)
    result = modal(model, speed=3000 * np.pi / 30)
    fig = plot_shaft_modes([shaft_lines(result, model, m) for m in modes])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    checked = 0
    for ax in fig.axes:
        disks = {line.get_gid().split(":")[-1] for line in ax.get_lines() if (line.get_gid() or "").startswith("disk:")}
        names = [t for t in ax.texts if t.get_text() in disks]
        segments = curve_segments(ax)
        frame = ax.get_window_extent()
        boxes = [glyph_box(t, renderer) for t in names]
        for text, box in zip(names, boxes):
            assert len(crossings(box, segments)) == 0, f"{example} {ax.get_title()}: a line runs through {text.get_text()}"
            assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
            bar = next(line for line in ax.get_lines()
                       if (line.get_gid() or "").startswith("disk:") and line.get_gid().endswith(":" + text.get_text()))
            bar_x = ax.transData.transform((bar.get_xdata()[0], 0.0))[0]
            assert box.x0 < bar_x < box.x1
            checked += 1
        for i, a in enumerate(boxes):
            for b in boxes[i + 1:]:
                assert not a.overlaps(b), f"{example}: two disk names overprint each other"
    assert checked >= 15
    plt.close(fig)


def _png_size(path) -> tuple[int, int]:
    """(width, height) [px] of a PNG, from its header."""
    import struct

    header = Path(path).read_bytes()[16:24]
    return struct.unpack(">II", header)


def test_modes_plot_of_a_flexible_machine_draws_its_shaft_lines_not_a_bar_per_coordinate(examples_dir, tmp_path,
                                                                                         capsys):
    """``modes --plot`` on the compressor (53 modes, 53 coordinates) drew 53 panels of 53 bars
    each (8797 x 7020 px, minutes of drawing); it now draws the first six modes' deflected lines,
    as --plot-shaft does, and --modes chooses them."""
    out = tmp_path / "modes.png"
    model = str(examples_dir / "compressor_rotor.toml")
    assert main(["modes", model, "--speed", "3000", "--quiet", "--plot", str(out)]) == 0
    width, height = _png_size(out)
    assert width <= 2400 and height <= 1600
    assert main(["modes", model, "--speed", "3000", "--quiet", "--plot", str(out), "--modes", "2"]) == 0
    assert _png_size(out)[1] < height                       # one panel


def test_modes_plot_of_a_rigid_machine_with_many_modes_draws_the_first_twelve_and_says_so(tmp_path, capsys):
    """A rigid machine with more modes than a figure holds (8 geared rotors on bearings in a casing)
    gets the bars of modes 1-12, and one stderr line saying how to choose others."""
    from test_large_machine_cli import chained_gear_toml

    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(8, 8))
    out = tmp_path / "bars.png"
    assert main(["modes", str(path), "--speed", "1000", "--plot", str(out)]) == 0
    captured = capsys.readouterr()
    count = sum(1 for line in captured.out.splitlines()[1:] if line.split() and line.split()[0].isdigit())
    assert count > 24
    assert f"--plot: modes 1-12 of {count} drawn (choose with --modes" in captured.err
    assert main(["modes", str(path), "--speed", "1000", "--quiet", "--plot", str(out), "--modes", "30"]) == 0
    assert main(["modes", str(path), "--speed", "1000", "--quiet", "--plot", str(out), "--modes", "999"]) == 2
    assert "mode 999 does not exist" in capsys.readouterr().err
