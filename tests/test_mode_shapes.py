"""3D mode shapes: the drawn displacement of every point is the mode shape there, the geometry
has the bodies' inertia, orbits turn the way the mode whirls; figures, animations, command line."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.mode_shapes import machine_outline, mode_shape_3d
from rotordyn_modal.errors import InputError
from rotordyn_modal.plotting.shapes3d import animate_mode_shape, plot_mode_shape, plot_mode_shapes

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.fixture(scope="module")
def gear():
    model = rdm.load_model(EXAMPLES / "gear_machine.toml")
    return model, rdm.modal(model, rdm.rpm(3000))


def _lines(axes, gid):
    return [line for line in axes.get_lines() if line.get_gid() == gid]


def _xyz(line):
    x, y, z = line.get_data_3d()
    xyz = np.column_stack([x, y, z]).astype(float)
    return xyz[~np.isnan(xyz).any(axis=1)]


@pytest.mark.parametrize("mode", [1, 5, 6])
@pytest.mark.parametrize("body", ["stator", "motor", "fan"])
def test_drawn_displacement_is_the_scaled_mode_shape(gear, mode, body):
    """Every drawn vertex moved by Re(scale shape_at(vertex)) from where it is drawn at rest."""
    model, result = gear
    view = mode_shape_3d(result, model, mode)
    fig = view.plot()
    ax = fig.axes[0]
    rest, = _lines(ax, f"undeformed:{body}")
    moved, = _lines(ax, f"displaced:{body}")
    k = np.nonzero(result.oscillatory)[0][mode - 1]
    expected = np.array([p + np.real(view.scale * result.shape_at(p)[k]) for p in _xyz(rest)])
    np.testing.assert_allclose(_xyz(moved), expected, rtol=0, atol=1e-12)
    # the top view draws the same points projected on x-y
    top = fig.axes[1]
    x, y = _lines(top, f"displaced:{body}")[0].get_data()
    keep = ~np.isnan(np.asarray(x, float))
    np.testing.assert_allclose(np.column_stack([x, y])[keep].astype(float), expected[:, :2], atol=1e-12)


def test_displacement_at_a_quarter_period(gear):
    model, result = gear
    view = mode_shape_3d(result, model, 3, scale=0.5)
    k = np.nonzero(result.oscillatory)[0][2]
    for body, points in zip(view.outline.bodies, view.at_phase(np.pi / 2)):
        expected = body.vertices + np.real(0.5 * np.array([result.shape_at(p)[k] for p in body.vertices]) * 1j)
        np.testing.assert_allclose(points, expected, atol=1e-14)


def test_springs_and_arrows_move_with_the_machine_and_the_ground_stays(gear):
    model, result = gear
    view = mode_shape_3d(result, model, 2)
    k = np.nonzero(result.oscillatory)[0][1]
    for spring, motion in zip(view.outline.springs, view.spring_motion):
        np.testing.assert_allclose(motion[0], view.scale * result.shape_at(spring.point_a)[k], atol=1e-15)
        np.testing.assert_array_equal(motion[1], 0.0)
    for arrow, motion in zip(view.outline.arrows, view.arrow_motion):
        np.testing.assert_allclose(motion, view.scale * result.shape_at(arrow.point)[k], atol=1e-15)
    largest = max(np.abs(m).max() for m in view.body_motion)
    assert largest == pytest.approx(0.15 * view.outline.size, rel=1e-12)


def test_stator_box_has_the_stators_inertia(gear):
    """A uniform box of the stator's mass on the drawn corners: its inertia tensor is the stator's."""
    model, _ = gear
    box = machine_outline(model).bodies[0]
    centre = box.vertices.mean(axis=0)
    edges = [box.vertices[4] - box.vertices[0], box.vertices[2] - box.vertices[0], box.vertices[1] - box.vertices[0]]
    lengths = np.array([np.linalg.norm(e) for e in edges])
    axes = np.column_stack([e / np.linalg.norm(e) for e in edges])
    m = model.stator.mass
    principal = m / 12 * np.array([lengths[1] ** 2 + lengths[2] ** 2, lengths[0] ** 2 + lengths[2] ** 2,
                                   lengths[0] ** 2 + lengths[1] ** 2])
    np.testing.assert_allclose(axes @ np.diag(principal) @ axes.T, model.stator.inertia, atol=1e-12)
    np.testing.assert_allclose(centre, model.stator.center_of_mass, atol=1e-15)


def test_rotor_cylinders_have_the_rotors_inertia(gear):
    """Solid cylinder: J_p = m r^2 / 2, I_d = m (3 r^2 + L^2) / 12, on the spin axis at the centre of mass."""
    model, _ = gear
    for body, rotor in zip(machine_outline(model).bodies[1:], model.rotors):
        n = (len(body.vertices) - 2) // 2
        back, front = body.vertices[-2], body.vertices[-1]
        np.testing.assert_allclose(0.5 * (back + front), rotor.center_of_mass, atol=1e-15)
        axis = (front - back) / np.linalg.norm(front - back)
        np.testing.assert_allclose(np.abs(axis), np.abs(model.spin_axis), atol=1e-15)
        r = np.linalg.norm(np.cross(body.vertices[:n] - back, axis), axis=1)
        L = np.linalg.norm(front - back)
        np.testing.assert_allclose(rotor.mass * r ** 2 / 2, rotor.polar_inertia, rtol=1e-12)
        assert rotor.mass * (3 * r[0] ** 2 + L ** 2) / 12 == pytest.approx(rotor.diametral_inertia, rel=1e-12)


@pytest.mark.parametrize("mode,sense", [(1, -1.0), (2, 1.0)])
def test_orbit_arrow_turns_the_way_the_mode_whirls(mode, sense):
    """Rotor in a block of springs at 3000 rpm: mode 1 whirls backward, mode 2 forward (docs/theory.md).
    The arrow drawn on the disk centre's orbit in the side view (looking along the spin axis
    +x) turns against / with the spin (+x, counter-clockwise in that view)."""
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = rdm.modal(model, rdm.rpm(3000))
    assert result.whirl[np.nonzero(result.oscillatory)[0][mode - 1]] == ("backward" if sense < 0 else "forward")
    view = mode_shape_3d(result, model, mode)
    fig = view.plot()
    side = fig.axes[3]
    assert side.get_title() == "side view (from +x)"
    centre_index = 0  # the disk's back face centre is the first orbit point
    arrow, = [a for a in side.texts if a.get_gid() == f"orbit-arrow:{centre_index}"]
    start, tip = np.asarray(arrow.xyann), np.asarray(arrow.xy)
    rest = view.outline.bodies[0].vertices[-2][1:]
    radius = start - rest
    turn = radius[0] * (tip - start)[1] - radius[1] * (tip - start)[0]
    assert np.sign(turn) == sense


def test_machine_without_stator_is_drawn_on_its_carrier():
    model = rdm.load_model(EXAMPLES / "spring_block_rotor_suspension.toml")
    outline = machine_outline(model)
    assert [b.kind for b in outline.bodies] == ["rotor"] and outline.bracket_body == "disk"
    np.testing.assert_allclose(outline.brackets[0], [model.rotors[0].center_of_mass, [0.0, 0.0, 0.0]])


def test_user_outline_replaces_the_box(gear):
    model, result = gear
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [np.nan] * 3, [0, 0, 1], [0, 1, 1]]
    view = mode_shape_3d(result, model, 1, outline=square)
    body = view.outline.bodies[0]
    assert body.kind == "outline" and body.faces == ((0, 1, 2), (4, 5))
    # drawn at rest as the user's open polylines, 0-1-2 and 4-5, not closed like the box's faces
    drawn, = _lines(view.plot().axes[0], f"undeformed:{body.name}")
    x, y, z = drawn.get_data_3d()
    np.testing.assert_array_equal(np.column_stack([x, y, z]), np.array(square)[[0, 1, 2, 3, 4, 5, 3]])
    with pytest.raises(InputError, match="outline: expected points of shape"):
        machine_outline(model, [[0, 1]])


def test_side_by_side_and_python_methods(gear, tmp_path):
    model, result = gear
    fig = plot_mode_shapes([mode_shape_3d(result, model, 1), mode_shape_3d(result, model, 1, label="measured")],
                           titles=["model", "measured"])
    assert [ax.get_title() for ax in fig.axes] == ["model", "measured"]
    assert result.plot_shape(4, model).axes[0].name == "3d"
    result.animate(4, model, tmp_path / "m.gif", frames=3, fps=10)
    assert (tmp_path / "m.gif").read_bytes()[:6] in (b"GIF89a", b"GIF87a")
    assert _gif_frame_durations(tmp_path / "m.gif") == [100] * 3     # 3 frames of 1000 / 10 ms
    assert _gif_size(tmp_path / "m.gif") == (864, 576)                # 12 x 8 inches at 72 dpi
    with pytest.raises(InputError, match="mode 0: expected a mode number from 1 to 6"):
        result.plot_shape(0, model)


@pytest.mark.parametrize("mode", [True, np.bool_(True), False])
def test_a_boolean_is_not_a_mode_number(gear, mode):
    """True is an int to Python: it drew mode 1 without a word (session 46)."""
    model, result = gear
    for draw in (mode_shape_3d, rdm.shaft_lines):
        with pytest.raises(InputError, match="expected a mode number from 1 to 6"):
            draw(result, model, mode)


def _gif_frame_durations(path):
    """How long each frame of a GIF is shown [ms]."""
    from PIL import Image

    with Image.open(path) as gif:
        durations = []
        for k in range(gif.n_frames):
            gif.seek(k)
            durations.append(gif.info["duration"])
    return durations


def _gif_size(path):
    """A GIF's width and height [pixels]."""
    from PIL import Image

    with Image.open(path) as gif:
        return gif.size


def test_animation_files(gear, tmp_path):
    model, result = gear
    view = mode_shape_3d(result, model, 6)
    animate_mode_shape(view, tmp_path / "m.html", frames=3, fps=8)
    text = (tmp_path / "m.html").read_text()
    assert "<script" in text and text.count("data:image/png;base64,") == 3
    # the player steps every 1000 / 8 ms
    interval = re.search(r"new Animation\(frames, img_id, slider_id, ([0-9.]+)", text)
    assert interval is not None and float(interval.group(1)) == 125.0
    with pytest.raises(InputError, match="expected an animation file ending in .gif, .html, .mp4"):
        animate_mode_shape(view, tmp_path / "m.avi", frames=3)
    keep = tmp_path / "model.toml"
    keep.write_text("x")
    with pytest.raises(InputError, match="refusing to write over the input file"):
        animate_mode_shape(view, keep.with_suffix(".gif"), frames=3, inputs=[keep.with_suffix(".gif")])


def test_mp4_holds_one_period_of_frames(gear, tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    model, result = gear
    animate_mode_shape(mode_shape_3d(result, model, 6), tmp_path / "m.mp4", frames=5, fps=10)
    data = (tmp_path / "m.mp4").read_bytes()
    assert data[4:8] == b"ftyp"  # an ISO base media (MP4) file
    n_frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "m.mp4"))
    assert n_frames == 5
    assert seconds == pytest.approx(0.5)
    assert [p.name for p in tmp_path.iterdir()] == ["m.mp4"]


def test_mp4_without_any_ffmpeg_is_refused(gear, tmp_path, monkeypatch):
    """Refused before any animation exists: matplotlib warns of one dropped unrendered, a
    stray warning after the command line's clean error."""
    import gc
    import warnings

    import matplotlib

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", str(tmp_path / "no-ffmpeg"))
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    model, result = gear
    view = mode_shape_3d(result, model, 6)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(InputError, match="writing MP4 needs ffmpeg on the PATH or the video extra"):
            animate_mode_shape(view, tmp_path / "m.mp4", frames=3)
        gc.collect()
    assert [str(w.message) for w in caught if "Animation" in str(w.message)] == []
    assert list(tmp_path.iterdir()) == []


def _cli(capsys, *args):
    """``rotordyn-modal ARGS`` run by ``cli.main`` in this process (these tests read its exit code
    and its error lines, not the process's own behaviour: tests/test_cli.py runs real processes)."""
    from types import SimpleNamespace

    from rotordyn_modal.cli import main

    capsys.readouterr()
    code = main([str(a) for a in args])
    return SimpleNamespace(returncode=code, stderr=capsys.readouterr().err)


def test_command_line_shape_and_animation(tmp_path, capsys):
    gear = EXAMPLES / "gear_machine.toml"
    done = _cli(capsys, "modes", gear, "--speed", 3000, "--shape", 5, "--plot", tmp_path / "m5.png", "--quiet")
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "m5.png").read_bytes()[:4] == b"\x89PNG"
    outline = tmp_path / "outline.csv"
    outline.write_text("x,y,z\n0,0,0\n0.5,0,0\n\n0,0,0.3\n0.5,0,0.3\n")
    done = _cli(capsys, "modes", gear, "--speed", 3000, "--animate", 2, "--frames", 3, "--outline", outline,
                "--plot", tmp_path / "m2.gif", "--quiet")
    assert done.returncode == 0, done.stderr
    assert len(_gif_frame_durations(tmp_path / "m2.gif")) == 3


@pytest.mark.parametrize("args,message", [
    (["--animate", "2"], "--animate MODE needs --plot FILE.gif, FILE.html or FILE.mp4"),
    (["--animate", "2", "--plot", "{tmp}/x.png"], "expected a file ending in .gif, .html or .mp4"),
    (["--shape", "2"], "--shape MODE needs --plot FILE.png"),
    (["--shape", "7", "--plot", "{tmp}/x.png"], "mode 7: expected a mode number from 1 to 6"),
    (["--outline", "{tmp}/o.csv"], "--outline is drawn with --shape MODE or --animate MODE only"),
    (["--shape", "1", "--outline", "{tmp}/o.csv", "--plot", "{tmp}/x.png"], "the outline needs the columns x,y,z"),
    (["--animate", "1", "--frames", "1", "--plot", "{tmp}/x.gif"], "--frames 1: expected a whole number"),
])
def test_command_line_refusals(tmp_path, capsys, args, message):
    (tmp_path / "o.csv").write_text("a,b\n1,2\n")
    done = _cli(capsys, "modes", EXAMPLES / "gear_machine.toml", *[a.format(tmp=tmp_path) for a in args])
    assert done.returncode == 2 and message in done.stderr, done.stderr
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "x.gif").exists()


def _displaced_drawing(fig):
    """Per axes, the displaced artists: gid, kind and the drawn coordinates of each line."""
    drawing = []
    for axes in fig.axes:
        for artist in axes.get_children():
            gid = str(artist.get_gid())
            if not gid.startswith("displaced"):
                continue
            data = (np.asarray(artist.get_data_3d(), dtype=float) if hasattr(artist, "get_data_3d")
                    else np.asarray(artist.get_xydata(), dtype=float) if hasattr(artist, "get_xydata") else None)
            drawing.append((gid, type(artist).__name__, data))
    return drawing


def _same_drawing(a, b):
    return len(a) == len(b) and all(
        ga == gb and ka == kb and ((da is None and db is None) or np.array_equal(da, db, equal_nan=True))
        for (ga, ka, da), (gb, kb, db) in zip(a, b))


def test_animation_frames_are_one_period_of_the_mode(gear, tmp_path):
    """Frame k of F draws the mode at phase 2 pi k / F, exactly as the still figure at that phase
    (and nothing of the frames before it): one period, without its end repeating its start."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import AbstractMovieWriter

    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    class Recorder(AbstractMovieWriter):
        def __init__(self):
            super().__init__(fps=5)
            self.frames = []

        def setup(self, fig, outfile, dpi=None):
            super().setup(fig, outfile, dpi)

        def grab_frame(self, **savefig_kwargs):
            self.frames.append(_displaced_drawing(self.fig))

        def finish(self):
            pass

    model, result = gear
    view = mode_shape_3d(result, model, 5)
    frames = 4
    recorder = Recorder()
    animation = animate_mode_shape(view, frames=frames)
    animation.save(str(tmp_path / "unused.gif"), writer=recorder)
    assert len(recorder.frames) == frames
    stills = []
    for k in range(frames):
        fig = plot_mode_shape(view, phase=2 * np.pi * k / frames)
        stills.append(_displaced_drawing(fig))
        plt.close(fig)
    assert all(_same_drawing(frame, still) for frame, still in zip(recorder.frames, stills))
    # the frames differ from each other: the mode moves (a half period turns every displacement)
    assert not _same_drawing(stills[0], stills[2])
    plt.close(animation._fig)



@pytest.mark.parametrize("kind, message", [
    ("text", "column x line 3 = 'foo': expected a number (an empty row starts a new line)"),
    ("folder", "cannot read the outline (a folder, not a file)"),
    # a UTF-16 byte-order mark: read as UTF-16 text (a spreadsheet's "Unicode text"), whose header names no x,y,z
    ("binary", "the outline needs the columns x,y,z (metres, model axes); found 戀摡"),
    ("missing", "cannot read the outline (no such file)"),
])
def test_unreadable_outlines_are_refused_by_name(tmp_path, capsys, kind, message):
    from rotordyn_modal.cli import main

    outline = tmp_path / "outline.csv"
    if kind == "text":
        outline.write_text("x,y,z\n0,0,0\nfoo,1,2\n")
    elif kind == "folder":
        outline.mkdir()
    elif kind == "binary":
        outline.write_bytes(b"\xff\xfe\x00bad")
    argv = ["modes", str(EXAMPLES / "gear_machine.toml"), "--speed", "3000", "--shape", "2",
            "--outline", str(outline), "--plot", str(tmp_path / "x.png"), "--quiet"]
    assert main(argv) == 2
    assert f"{outline}: {message}" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def _label_boxes_and_arrows(fig, names):
    """Rendered glyph boxes of the names (display pixels) and the drawn arrows' segments as projected,
    measured on the figure (a 3D text is measured where mplot3d draws it: its point projected)."""
    from matplotlib.text import Text
    from mpl_toolkits.mplot3d import proj3d
    from mpl_toolkits.mplot3d.art3d import Text3D

    from label_geometry import arrow_segments, glyph_box

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    boxes = {}
    for text in ax.texts:
        if text.get_text() not in names:
            continue
        if isinstance(text, Text3D):
            x, y, _ = proj3d.proj_transform(text._x, text._y, text._z, ax.get_proj())
            text = Text(*ax.transData.transform((x, y)), text.get_text(), fontproperties=text.get_fontproperties(),
                        ha=text.get_ha(), va=text.get_va(), figure=fig)
        boxes[text.get_text()] = glyph_box(text, renderer)
    arrows = arrow_segments(ax)
    return ax, boxes, arrows


@pytest.mark.parametrize("example, mode, view_angles", [
    ("gear_machine", 2, None), ("motor_pump_on_mounts", 2, None), ("motor_pump_on_mounts", 2, (15, -120))])
def test_arrow_names_clear_of_every_arrow_and_of_each_other(example, mode, view_angles):
    """Each sensor's and excitation's name is drawn beside its own arrow (or, with no clear spot
    there, joined to it by a leader line: test_names_stand_off_the_bodies_with_leaders_to_their_arrows),
    where no arrow (its own included) runs through its rendered glyphs and no other name overlaps
    it, inside the 3D axes; after the view is turned too (the names are placed where the arrows are drawn)."""
    import matplotlib.pyplot as plt

    from label_geometry import clip_segments
    from rotordyn_modal.plotting.shapes3d import plot_mode_shape

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(3000)), model, mode)
    names = [arrow.name for arrow in view.outline.arrows]
    fig = plot_mode_shape(view, projections=False)     # the 3D view alone: the names are placed there
    if view_angles is not None:
        fig.axes[0].view_init(*view_angles)
    ax, boxes, arrows = _label_boxes_and_arrows(fig, names)
    assert sorted(boxes) == sorted(names) == sorted(arrows)
    frame = ax.get_window_extent()
    for name, box in boxes.items():
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, name
        for other, segments in arrows.items():
            assert not len(clip_segments(segments, box.extents)), f"arrow {other} runs through the name {name}"
        for other, other_box in boxes.items():
            assert other == name or not box.overlaps(other_box), f"names {name} and {other} overlap"
        # beside its own arrow: within three of its heights of the arrow's drawn segments, or
        # (no room there) joined to it by its leader line
        if name in _leaders(ax):
            continue
        ends = arrows[name].reshape(-1, 2)
        near = np.hypot(np.maximum(0, np.maximum(box.x0 - ends[:, 0], ends[:, 0] - box.x1)),
                        np.maximum(0, np.maximum(box.y0 - ends[:, 1], ends[:, 1] - box.y1))).min()
        assert near <= 3 * box.height, f"{name} is {near:.0f} px from its arrow"
    plt.close(fig)


def test_a_bearing_beyond_the_rotors_body_is_joined_to_it_by_its_axis(examples_dir):
    """spring_block_rotor: the disk's centre is 0.75 m from its bearing (a rigid massless rod
    along the spin axis). The 3D drawing showed the disk and, 0.75 m away, the bearing's spring
    hanging from nothing. The rotor's axis is drawn from its body to the bearing and moves with
    it: in the drawn figure the spring's rotor end lies on a line drawn in the rotor's colour,
    at every phase of an animation too (checked at 0 and a quarter period)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = rdm.load_model(examples_dir / "spring_block_rotor.toml")
    result = rdm.modal(model, rdm.rpm(3000))
    view = mode_shape_3d(result, model, 1)
    spring, = view.outline.springs
    for phase in (0.0, np.pi / 2):
        fig = view.plot(phase=phase)
        ax = fig.axes[0]
        end = spring.point_a + np.real(view.spring_motion[0][0] * np.exp(1j * phase))
        drawn = [np.column_stack(line.get_data_3d()) for line in ax.get_lines()
                 if (line.get_gid() or "").startswith("displaced") and line.get_gid() != "displaced-spring:spring-block"
                 and matplotlib.colors.to_hex(line.get_color()) == matplotlib.colors.to_hex("tab:orange")]
        nearest = min(_distance_to_polyline(end, points) for points in drawn)
        assert nearest < 1e-9 * view.outline.size, nearest
        plt.close(fig)


def _distance_to_polyline(point, points):
    """Shortest distance [m] from ``point`` to the segments of ``points`` (n, 3), NaN rows
    separating polylines."""
    a, b = points[:-1], points[1:]
    keep = np.all(np.isfinite(a), axis=1) & np.all(np.isfinite(b), axis=1)
    a, b = a[keep], b[keep]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * d - point, axis=1)))


def _drawn_body_edges(ax, prefix):
    """Segments (n, 4) [display pixels] of the bodies' edges drawn with gid ``prefix:NAME``, by
    body name, as mplot3d projects them."""
    from mpl_toolkits.mplot3d import proj3d

    edges = {}
    for line in ax.get_lines():
        gid = str(line.get_gid())
        if gid.startswith(prefix):
            x, y, z = (np.asarray(c, float) for c in line.get_data_3d())
            px, py, _ = proj3d.proj_transform(x, y, z, ax.get_proj())
            points = ax.transData.transform(np.column_stack([px, py]))
            pairs = np.hstack([points[:-1], points[1:]])
            name = gid.split(":", 1)[1]           # a rotor and its axis ('rod') share its name
            edges[name] = np.vstack([edges.get(name, np.empty((0, 4))), pairs[np.all(np.isfinite(pairs), axis=1)]])
    return edges


@pytest.mark.parametrize("example, mode, rpm, view_angles", [
    ("motor_pump_on_mounts", 1, 0, None), ("motor_pump_on_mounts", 2, 3000, (15, -120)),
    ("fan_on_bearings", 2, 0, None), ("gear_machine", 1, 3000, None)])
def test_arrow_names_clear_of_the_bodies_edges(example, mode, rpm, view_angles):
    """No drawn edge of a displaced body (rotor cylinders, stator box) runs through the name of a
    sensor or excitation whose arrow ends outside every rotor's drawn outline (there is room
    beside it): motor_pump_on_mounts drew 'hammer-z' over the motor's cylinder. Measured on the
    rendered figure (glyph boxes, edges as projected), after the view is turned too."""
    import matplotlib.pyplot as plt
    from matplotlib.path import Path as PixelPath
    from scipy.spatial import ConvexHull

    from label_geometry import clip_segments

    model = rdm.load_model(EXAMPLES / f"{example}.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(rpm)), model, mode)
    names = [arrow.name for arrow in view.outline.arrows]
    fig = plot_mode_shape(view, projections=False)
    if view_angles is not None:
        fig.axes[0].view_init(*view_angles)
    ax, boxes, arrows = _label_boxes_and_arrows(fig, names)
    edges = _drawn_body_edges(ax, "displaced:")
    rotors = [body.name for body in view.outline.bodies if body.kind == "rotor"]
    outlines = [PixelPath(points[ConvexHull(points).vertices])
                for points in (edges[name].reshape(-1, 2) for name in rotors)]
    checked = 0
    for arrow in view.outline.arrows:
        shaft = arrows[arrow.name][0]           # the quiver's first segment: tail -> tip
        free = shaft[:2] if arrow.kind == "excitation" else shaft[2:]
        if any(outline.contains_point(free) for outline in outlines):
            continue
        checked += 1
        for body, segments in edges.items():
            assert not len(clip_segments(segments, boxes[arrow.name].extents)), \
                f"the {body}'s edge runs through the name {arrow.name}"
    assert checked >= 1                         # the test can fail
    plt.close(fig)


def _leaders(ax):
    """The leader lines drawn from names to arrows: pixels (n, 2) of each, by name."""
    return {str(line.get_gid()).split(":", 1)[1]: line.get_transform().transform(
            np.column_stack([line.get_xdata(), line.get_ydata()]))
            for line in ax.get_lines() if str(line.get_gid()).startswith("arrow-leader:") and line.get_visible()}


def _projected_outline(ax, points):
    """The convex outline (a matplotlib Path, display pixels) of ``points`` (n, 3) as mplot3d projects them."""
    from matplotlib.path import Path as PixelPath
    from mpl_toolkits.mplot3d import proj3d
    from scipy.spatial import ConvexHull

    x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], ax.get_proj())
    flat = ax.transData.transform(np.column_stack([x, y]))
    return PixelPath(flat[ConvexHull(flat).vertices])


@pytest.mark.parametrize("mode, phase, view_angles", [(1, 0.0, None), (2, np.pi / 2, (15, -120))])
def test_names_stand_off_the_bodies_with_leaders_to_their_arrows(mode, phase, view_angles):
    """motor_pump_on_mounts: the pump's probes end inside the pump's cylinder and the stator box,
    where no spot beside them is clear, and their names were drawn over the bodies. Now no name's
    rendered box meets the projected outline of a displaced rotor or of the stator box (the
    bodies' own corners at the drawn phase, projected as the view stands), nor a drawn edge; a
    name moved away is joined to its arrow by a line from its box to the arrow's free end (the
    drawn shaft's end away from the arrow's point) that crosses no other name. At an animation's
    phase and after the view is turned too."""
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d import proj3d

    from label_geometry import clip_segments

    model = rdm.load_model(EXAMPLES / "motor_pump_on_mounts.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(3000)), model, mode)
    names = [arrow.name for arrow in view.outline.arrows]
    fig = plot_mode_shape(view, phase=phase, projections=False)
    if view_angles is not None:
        fig.axes[0].view_init(*view_angles)
    ax, boxes, arrows = _label_boxes_and_arrows(fig, names)
    edges = np.concatenate(list(_drawn_body_edges(ax, "displaced:").values()))
    outlines = {body.name: _projected_outline(ax, points)
                for body, points in zip(view.outline.bodies, view.at_phase(phase)) if body.kind in ("rotor", "stator")}
    for name, box in boxes.items():
        for body, outline in outlines.items():
            corners = [(box.x0, box.y0), (box.x1, box.y0), (box.x1, box.y1), (box.x0, box.y1)]
            assert not outline.intersects_bbox(box) and not outline.contains_points(corners).any(), \
                f"the name {name} stands on the {body}"
        assert not len(clip_segments(edges, box.extents)), f"a body's edge runs through the name {name}"
    leaders = _leaders(ax)
    assert leaders                              # the probes' names are joined to their arrows
    for name, line in leaders.items():
        box = boxes[name]
        start, end = line[0], line[-1]
        assert box.x0 - 1 <= start[0] <= box.x1 + 1 and box.y0 - 1 <= start[1] <= box.y1 + 1, f"{name}'s leader"
        arrow = names.index(name)
        point = view.outline.arrows[arrow].point + np.real(view.arrow_motion[arrow] * np.exp(1j * phase))
        x, y, _ = proj3d.proj_transform(*point, ax.get_proj())
        point = ax.transData.transform((x, y))
        shaft = arrows[name][0].reshape(2, 2)
        free = shaft[np.argmax(np.hypot(*(shaft - point).T))]
        assert np.hypot(*(end - free)) < 1.0, f"{name}'s leader ends {np.hypot(*(end - free)):.1f} px from its arrow"
        for other, other_box in boxes.items():
            assert other == name or not len(clip_segments(np.hstack([line[:-1], line[1:]]), other_box.extents)), \
                f"{name}'s leader runs through the name {other}"
    plt.close(fig)
