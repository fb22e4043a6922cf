"""3D mode shape figures and animations (matplotlib's 3D axes and animation writers).

They draw a :class:`~rotordyn_modal.analysis.mode_shapes.ModeShape3D`: the machine undeformed
(grey), displaced at one phase of the mode (coloured), the whirl orbit of the rotors' axis ends
and of the spring points with an arrowhead in the direction of motion, the rotors' spin
direction, and the sensors and excitations as arrows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..units import unit_scale
from .modes import small_number
from ..units import rpm_text

__all__ = ["plot_mode_shape", "plot_mode_shapes", "animate_mode_shape", "ANIMATION_FORMATS"]

#: file endings of animations and how each is written
ANIMATION_FORMATS = (".gif", ".html", ".mp4")
_BODY_COLOURS = {"stator": "tab:blue", "outline": "tab:blue", "rotor": "tab:orange", "shaft": "tab:orange",
                 "rod": "tab:orange"}
_ARROW_COLOURS = {"sensor": "tab:green", "excitation": "tab:purple"}
_SPRING_COILS = 6
#: resolution of animation frames (a 12 x 8 inch figure: 864 x 576 pixels)
_ANIMATION_DPI = 72


def plot_mode_shape(view, ax=None, phase: float = 0.0, orbits: bool = True, labels: bool = True,
                    projections: bool | None = None, title: str | None = None, units: str = "si"):
    """Draw the machine undeformed and displaced in one mode.

    Parameters
    ----------
    view : ModeShape3D
    ax : matplotlib 3D Axes, optional
        Draw the 3D view there (and no projections unless asked).
    phase : float
        Phase of the displaced drawing [rad] (0: the largest motion component real, at its
        positive extreme).
    orbits : bool
        Trace the whirl orbits (one period) with an arrowhead in the direction of motion.
    labels : bool
        Name the sensors and excitations.
    projections : bool, optional
        Add the top (x-y), front (x-z) and side (y-z) views beside the 3D view (default: when
        ``ax`` is not given).
    title : str, optional
    units : {'si', 'us'}
        Unit system of the axes' lengths: m, or in (docs/units.md). The drawing is the same; the
        ticks stand at round numbers of the unit.

    Returns
    -------
    matplotlib.figure.Figure
    """
    projections = ax is None if projections is None else projections
    fig, ax, flat = _figure(ax, projections)
    # frame first and hold it: mplot3d's autoscaling can overflow to infinite limits when
    # collections arrive on a fresh 3D axes
    _frame(ax, flat, view, units, phase)
    ax.set_autoscale_on(False)
    _draw_static(ax, flat, view, orbits)
    _draw_displaced(ax, flat, view, phase)
    if labels:
        _label_arrows(ax, view, phase)
    _frame(ax, flat, view, units, phase)
    ax.set_title(title or _title(view), fontsize="medium")
    _legend(ax, view, orbits)
    return fig


def plot_mode_shapes(views, titles=None, phase: float = 0.0, suptitle: str | None = None):
    """Several mode shapes side by side (e.g. model and measured), one 3D panel each.

    Parameters
    ----------
    views : list of ModeShape3D
    titles : list of str, optional
    phase : float [rad]
    suptitle : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    n = len(views)
    fig = plt.figure(figsize=(5.6 * n, 5.8), layout="constrained")
    for k, view in enumerate(views):
        ax = fig.add_subplot(1, n, k + 1, projection="3d")
        plot_mode_shape(view, ax=ax, phase=phase, labels=False,
                        title=None if titles is None else titles[k])
    if suptitle:
        fig.suptitle(suptitle)
    return fig


def animate_mode_shape(view, path=None, frames: int = 36, fps: int = 18, inputs=(), units: str = "si"):
    """Animate one period of the mode; write it to ``path`` (.gif, .html or .mp4) if given.

    Parameters
    ----------
    view : ModeShape3D
    path : str or path-like, optional
        ``.gif`` (Pillow), ``.html`` (self-contained, JavaScript player) or ``.mp4`` (needs
        ffmpeg); written whole or not at all.
    frames : int
        Frames per period.
    fps : int
        Frames per second of the file.
    inputs : iterable of path-like
        Files that must not be overwritten.
    units : {'si', 'us'}
        Unit system of the axes' lengths (:func:`plot_mode_shape`).

    Returns
    -------
    matplotlib.animation.FuncAnimation
    """
    from matplotlib.animation import FuncAnimation

    suffix = None if path is None else Path(path).suffix.lower()
    if suffix is not None and suffix not in ANIMATION_FORMATS:
        raise InputError(f"{path}: expected an animation file ending in {', '.join(ANIMATION_FORMATS)}")
    # refused before the animation exists: one dropped unrendered makes matplotlib warn
    ffmpeg = _ffmpeg_path(path) if suffix == ".mp4" else None
    if path is not None:
        from ..io.atomic import check_not_input

        check_not_input(Path(path), inputs)
    fig = plot_mode_shape(view, units=units)
    ax, flat = fig.axes[0], list(zip(fig.axes[1:4], [pair for _, pair in _PROJECTIONS]))
    _frame(ax, flat, view, units, cycle=True)   # held by every frame: an elliptic mode is largest elsewhere
    phases = 2 * np.pi * np.arange(int(frames)) / int(frames)

    def update(k):
        for axes in [ax] + [panel for panel, _ in flat]:
            for artist in [a for a in axes.get_children() if str(a.get_gid()).startswith("displaced")]:
                artist.remove()
        _draw_displaced(ax, flat, view, phases[k])
        for layout in [a for a in ax.artists if a.get_gid() == "arrow-labels"]:
            layout.arrow_labels.phase = phases[k]       # the names follow their arrows
        return []

    animation = FuncAnimation(fig, update, frames=len(phases), interval=1000.0 / fps, blit=False)
    if path is not None:
        _write_animation(animation, fig, Path(path), suffix, fps, ffmpeg)
    return animation


def _write_animation(animation, fig, path, suffix, fps, ffmpeg):
    import matplotlib
    from matplotlib import animation as mpl_animation

    from ..io.atomic import atomic_write

    fig.set_dpi(_ANIMATION_DPI)
    if suffix == ".html":
        text = animation.to_jshtml(fps=fps)
        with atomic_write(path, "w") as handle:
            handle.write(text)
        return
    writer = mpl_animation.PillowWriter(fps=fps) if suffix == ".gif" else mpl_animation.FFMpegWriter(fps=fps)
    with matplotlib.rc_context({"animation.ffmpeg_path": ffmpeg} if ffmpeg else {}):
        with atomic_write(path, None) as temporary:
            animation.save(str(temporary), writer=writer, dpi=_ANIMATION_DPI)


def _ffmpeg_path(path):
    """The ffmpeg to write MP4 with: matplotlib's (the PATH) or the static one of ``imageio-ffmpeg``."""
    import shutil

    import matplotlib

    configured = matplotlib.rcParams["animation.ffmpeg_path"]
    if shutil.which(configured):
        return configured
    try:
        import imageio_ffmpeg
    except ImportError:
        raise InputError(f"{path}: writing MP4 needs ffmpeg on the PATH or the video extra "
                         "(pip install 'rotordyn_modal[video]'); write .gif or .html instead") from None
    return imageio_ffmpeg.get_ffmpeg_exe()


# ---------------------------------------------------------------------------------------------
# drawing: polylines (n, 3) drawn in the 3D view and projected on the flat views
# ---------------------------------------------------------------------------------------------
#: flat views: title and the two model axes shown
_PROJECTIONS = (("top view (from +z)", (0, 1)), ("front view (from -y)", (0, 2)), ("side view (from +x)", (1, 2)))
_AXIS_NAMES = "xyz"


def _figure(ax, projections):
    import matplotlib.pyplot as plt

    if ax is not None:
        return ax.figure, ax, []
    if not projections:
        fig = plt.figure(figsize=(8.0, 7.0), layout="constrained")
        return fig, fig.add_subplot(projection="3d"), []
    fig = plt.figure(figsize=(12.0, 8.0), layout="constrained")
    grid = fig.add_gridspec(3, 3, width_ratios=[1.0, 1.0, 0.9])
    ax = fig.add_subplot(grid[:, :2], projection="3d")
    flat = [(fig.add_subplot(grid[k, 2]), pair) for k, (_, pair) in enumerate(_PROJECTIONS)]
    return fig, ax, flat


def _polyline(ax, flat, xyz, gid, **style):
    """One polyline in the 3D view and in every flat view, tagged ``gid``."""
    xyz = np.asarray(xyz, dtype=float)
    (line,) = ax.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], **style)
    line.set_gid(gid)
    for panel, (i, j) in flat:
        (projected,) = panel.plot(xyz[:, i], xyz[:, j], **style)
        projected.set_gid(gid)


def _arrow(ax, flat, start, vector, gid, colour, head=0.3, width=1.5):
    """An arrow in the 3D view (quiver) and in every flat view (annotate)."""
    quiver = ax.quiver(*start, *vector, color=colour, linewidth=width, arrow_length_ratio=head)
    quiver.set_gid(gid)
    for panel, (i, j) in flat:
        if np.hypot(vector[i], vector[j]) < 1e-12:
            continue
        note = panel.annotate("", xy=(start[i] + vector[i], start[j] + vector[j]), xytext=(start[i], start[j]),
                              arrowprops={"arrowstyle": "-|>", "color": colour, "lw": width, "shrinkA": 0,
                                          "shrinkB": 0, "mutation_scale": 9})
        note.set_gid(gid)


def _edges(body, points):
    """Polylines of a body's edges through ``points`` (NaN-separated), shape (n, 3)."""
    if body.kind == "rotor":
        n = (len(points) - 2) // 2
        loops = [list(range(n)) + [0], list(range(n, 2 * n)) + [n]]
        loops += [[k, n + k] for k in range(0, n, max(1, n // 4))]
    elif body.kind in ("outline", "shaft", "rod"):  # open polylines (a shaft: its line, then its disks' circles)
        loops = [list(line) for line in body.faces]
    else:
        loops = [list(face) + [face[0]] for face in body.faces]
    rows = []
    for loop in loops:
        rows.extend(points[loop])
        rows.append([np.nan] * 3)
    return np.asarray(rows)


def _draw_static(ax, flat, view, orbits):
    """What does not move: the machine at rest, the ground, the orbits and the spin arrows."""
    for body in view.outline.bodies:
        _polyline(ax, flat, _edges(body, body.vertices), f"undeformed:{body.name}", color="0.55",
                  linewidth=0.8, linestyle="--")
    for k, bracket in enumerate(view.outline.brackets):
        _polyline(ax, flat, bracket, f"undeformed-bracket:{k}", color="0.55", linewidth=0.8, linestyle="--")
    for spring in view.outline.springs:
        _ground(ax, flat, spring, view.outline.size)
    if orbits:
        _draw_orbits(ax, flat, view)
    _draw_spin(ax, flat, view)


def _draw_displaced(ax, flat, view, phase):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    for body, points in zip(view.outline.bodies, view.at_phase(phase)):
        colour = _BODY_COLOURS[body.kind]
        _polyline(ax, flat, _edges(body, points), f"displaced:{body.name}", color=colour,
                  linewidth=2.2 if body.kind == "shaft" else 1.4)
        if body.kind not in ("outline", "shaft", "rod"):
            faces = Poly3DCollection(_padded_faces(points, body.faces), facecolor=colour,
                                     alpha=0.15 if body.kind == "stator" else 0.35, edgecolor="none")
            faces.set_gid(f"displaced-faces:{body.name}")
            ax.add_collection3d(faces, autolim=False)
    for k, bracket in enumerate(view.brackets_at_phase(phase)):
        _polyline(ax, flat, bracket, f"displaced-bracket:{k}", color="tab:blue", linewidth=1.4)
    for spring, (a, b) in zip(view.outline.springs, view.springs_at_phase(phase)):
        _polyline(ax, flat, _zigzag(a, b, view.outline.size), f"displaced-spring:{spring.name}", color="0.2",
                  linewidth=1.0)
    for arrow, (tail, tip) in zip(view.outline.arrows, _arrow_segments(view, phase)):
        _arrow(ax, [], tail, tip - tail, f"displaced-arrow:{arrow.name}", _ARROW_COLOURS[arrow.kind])


def _padded_faces(points, faces):
    """The polygons ``faces`` (vertex indices) of ``points`` (n, 3) [m] as one array (F, V, 3), a
    shorter polygon's last vertex repeated up to the longest's V (a repeated vertex draws
    nothing).

    Given polygons of different lengths (a cylinder's quadrilateral sides and its many-sided
    ends), mplot3d's ``Poly3DCollection`` pads them itself into an array made by ``np.empty``:
    the padding holds whatever that memory held before, and its projection (``np.dot`` of the
    view matrix with every vertex, padding included, under ``errstate`` for invalid values and
    division only) raised 'RuntimeWarning: overflow encountered in dot' where a previous
    computation had left huge numbers there (issue 27: seen in one run of the suite only)."""
    longest = max(len(face) for face in faces)
    return np.stack([points[list(face) + [face[-1]] * (longest - len(face))] for face in faces])


def _arrow_segments(view, phase):
    """Tail and tip [m] of each sensor's and excitation's arrow at ``phase`` [rad], shape (n, 2, 3):
    a sensor's arrow starts at its point, an excitation's ends there."""
    segments = []
    for arrow, start in zip(view.outline.arrows, view.arrows_at_phase(phase)):
        d = 0.12 * view.outline.size * arrow.direction / np.linalg.norm(arrow.direction)
        segments.append((start - d, start) if arrow.kind == "excitation" else (start, start + d))
    return np.asarray(segments, float).reshape(-1, 2, 3)


def _zigzag(a, b, size):
    """A spring drawn as a zigzag from ``a`` to ``b`` (straight leads at both ends)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    axis = b - a
    length = np.linalg.norm(axis)
    if length == 0:
        return np.array([a, b])
    unit = axis / length
    side = np.cross(unit, [0.0, 0.0, 1.0] if abs(unit[2]) < 0.9 else [1.0, 0.0, 0.0])
    side = side / np.linalg.norm(side) * 0.025 * size
    t = np.linspace(0.2, 0.8, 2 * _SPRING_COILS + 1)
    swing = np.where(np.arange(len(t)) % 2, 1.0, -1.0)
    swing[[0, -1]] = 0.0
    middle = a + t[:, None] * axis + swing[:, None] * side
    return np.vstack([a, middle, b])


def _ground(ax, flat, spring, size):
    if spring.body_b != "ground":
        return
    p = np.asarray(spring.point_b, float)
    unit = (p - spring.point_a) / np.linalg.norm(p - spring.point_a)
    side = np.cross(unit, [0.0, 0.0, 1.0] if abs(unit[2]) < 0.9 else [1.0, 0.0, 0.0])
    side = side / np.linalg.norm(side) * 0.04 * size
    _polyline(ax, flat, np.array([p - side, p + side]), f"ground:{spring.name}", color="k", linewidth=2.5)


def _draw_orbits(ax, flat, view):
    """Each orbit over one period, and an arrow along the motion where the drawing stands (phase 0)."""
    _, motions = view.orbit_points()
    paths = view.orbit_paths(np.linspace(0, 2 * np.pi, 73))
    for k, (path, velocity, d) in enumerate(zip(paths, view.orbit_directions(), motions)):
        _polyline(ax, flat, path, f"orbit:{k}", color="tab:red", linewidth=0.9)
        if np.linalg.norm(velocity) > 0.05 * np.linalg.norm(np.abs(d)):   # an orbit that is no line
            _arrow(ax, flat, path[0], 0.8 * velocity, f"orbit-arrow:{k}", "tab:red", head=0.5, width=1.4)


def _draw_spin(ax, flat, view):
    """A three-quarter arc with an arrowhead around each rotor's front face, turning its way."""
    if view.speed == 0:
        return
    for body in view.outline.bodies:
        if body.kind not in ("rotor", "shaft") or body.spin == 0:
            continue
        centre, radial = _spin_circle(body, view.outline.size)
        e1 = radial / np.linalg.norm(radial)
        e2 = np.cross(body.axis, e1)
        angles = np.linspace(0, 1.5 * np.pi, 28) * np.sign(body.spin * view.speed)
        arc = centre + 1.2 * np.linalg.norm(radial) * (np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2)
        along = _facing(flat, body.axis)
        _polyline(ax, along, arc[:-3], f"spin:{body.name}", color="k", linewidth=1.0)
        _arrow(ax, along, arc[-4], arc[-1] - arc[-4], f"spin-arrow:{body.name}", "k", head=0.8, width=1.0)


def _spin_circle(body, size):
    """Centre and a radius vector of the circle the spin arc goes around: a rigid rotor's front
    face; a flexible rotor's last end, with its first disk's radius (or 4 % of the drawing)."""
    if body.kind == "rotor":
        n = (len(body.vertices) - 2) // 2
        return body.vertices[-1], body.vertices[n] - body.vertices[-1]
    centre = body.vertices[body.faces[0][-1]]
    if len(body.faces) > 1:
        ring = body.vertices[list(body.faces[1])]
        return centre, ring[0] - ring[:-1].mean(axis=0)
    side = np.cross(body.axis, [1.0, 0.0, 0.0] if abs(body.axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    return centre, 0.04 * size * side / np.linalg.norm(side)


def _facing(flat, axis):
    """The flat views looking along ``axis`` (where a spin arc is a circle, not a line)."""
    normals = {(0, 1): 2, (0, 2): 1, (1, 2): 0}
    return [(panel, pair) for panel, pair in flat if abs(axis[normals[pair]]) > 0.7]


#: arrows' labels keep this far from the arrows, from each other and from the frame [points]
_LABEL_PAD_POINTS = 3.0
#: room [points] kept between two names side by side, more than a space's width: 'acc-fan-z' and
#: 'probe-DE-x' 3 points apart (their white backgrounds less) read as one name (figs30b review)
_LABEL_APART_POINTS = 7.0
#: directions tried for an arrow's label from its free end, turned from the arrow's own [degrees]
_LABEL_TURNS = (0, 30, -30, 60, -60, 90, -90, 120, -120, 150, -150, 180)
#: distances tried for an arrow's label beyond the pad [label heights]
_LABEL_STEPS = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0)
#: a name moves off the bodies' edges to at most this many of its heights from its arrow's end
#: (farther it would read as another arrow's)
_BODY_REACH = 2.9
#: a name placed away from its arrow (no room beside it) is joined to the arrow's free end by a
#: line this wide [points]
_LEADER_WIDTH = 0.7
#: at most this many free boxes are tried for a leader's name, the nearest first
_LEADER_TRIES = 400
#: a leader crossing no other leader nor arrow may be this many name heights longer than the
#: shortest one that crosses no name (longer, the crossing reads better than the detour)
_LEADER_DETOUR = 6.0
#: the names stand above the bodies (mplot3d orders the collections from 1 up, one per collection)
_LABEL_ZORDER = 1.0e6
#: a light background keeps a name readable over the bodies (inside the pad)
_LABEL_BACKGROUND = {"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.7}


class _ArrowLabels:
    """The sensors' and excitations' names in the 3D view, placed each time it is drawn.

    A rotation of the view (and the animation's phase) moves the arrows on the screen, so the
    names are laid out at draw time (:func:`._labels.draw_time_layout`), in display pixels:
    each beside its arrow's free end (a sensor's tip, an excitation's tail), straight on along
    the arrow first, else turned from it or a little farther away, within :data:`_BODY_REACH`
    of its heights, where its box crosses no arrow, overlaps no name placed before nor the
    legend, inside the axes, and is off the bodies as drawn at the phase (their edges, displaced
    and at rest, and the filled outlines of rotors and stator box, projected as the view now
    stands). A name with no such spot stands in clear space, the nearest spot off every drawn
    line, arrow, outline, name and the legend inside the axes' drawn box (else off the bodies'
    edges and outlines, the arrows, names and legend only), joined to its arrow's free end by a
    thin leader line in the arrow's colour that crosses no name (and, where possible, no other
    leader nor arrow). Where the axes hold no such spot either, the name stays beside its
    arrow, off the bodies' edges if it can, else on the fewest of them.

    Parameters
    ----------
    ax : matplotlib 3D Axes
    view : ModeShape3D
    phase : float
        Phase of the drawn arrows [rad] (the animation sets it for each frame).
    """

    def __init__(self, ax, view, phase):
        self.ax, self.view, self.phase = ax, view, phase
        self.texts = [ax.text2D(0.0, 0.0, arrow.name, transform=ax.transAxes, fontsize="x-small",
                                color=_ARROW_COLOURS[arrow.kind], ha="left", va="bottom", gid=f"arrow-label:{arrow.name}",
                                zorder=_LABEL_ZORDER, bbox=_LABEL_BACKGROUND)
                      for arrow in view.outline.arrows]
        for text in self.texts:
            text.set_in_layout(False)
        self.leaders = [_leader_line(ax, arrow) for arrow in view.outline.arrows]

    def place(self, renderer):
        """Put every name where :class:`_ArrowLabels` says (``renderer``: the one drawing)."""
        from ._labels import first_free_box

        ax = self.ax
        pad = _LABEL_PAD_POINTS * renderer.points_to_pixels(1.0)
        gap = (_LABEL_APART_POINTS * renderer.points_to_pixels(1.0), pad)
        segments = self._pixels(_arrow_segments(self.view, self.phase))
        frame = ax.get_window_extent(renderer)
        inner = (frame.x0 + pad, frame.y0 + pad, frame.x1 - pad, frame.y1 - pad)
        legend = ax.get_legend()
        obstacles = [] if legend is None else [tuple(legend.get_window_extent(renderer).extents)]
        placed, leaders = [], []
        edges, hulls = self._bodies()
        clear, crossings = _preferences(segments, edges, hulls, pad, self._drawn())
        ends = self._ends(segments)
        sizes = [(e.width, e.height) for e in (text.get_window_extent(renderer) for text in self.texts)]
        boxes, lines = [None] * len(self.texts), [None] * len(self.texts)
        for k, ((attached, free), (w, h)) in enumerate(zip(ends, sizes)):      # beside the arrow, clear
            near = [b for b in _boxes_beyond(free, free - attached, w, h, pad)
                    if _distance_to_box(free, b) <= _BODY_REACH * h]
            boxes[k] = first_free_box(near, placed, gap, inner, obstacles, allowed=clear[0])
        spaces = None
        for k, ((attached, free), (w, h)) in enumerate(zip(ends, sizes)):      # in clear space, with a leader
            if boxes[k] is None:
                spaces = spaces or self._clear_space(frame, pad, segments, edges, hulls, obstacles)
                boxes[k], lines[k] = _leader_spot(spaces, free, free - attached, w, h, pad, placed, leaders,
                                                  segments, inner, apart=gap[0])
        for k, ((attached, free), (w, h)) in enumerate(zip(ends, sizes)):      # no room: as before
            if boxes[k] is None:
                boxes[k] = self._fallback(free, attached, w, h, gap, placed, leaders, segments, inner,
                                          obstacles, clear, crossings)
        for text, leader, box, line in zip(self.texts, self.leaders, boxes, lines):
            self._show(text, leader, box, line)

    def _fallback(self, free, attached, w, h, gap, placed, leaders, segments, inner, obstacles, clear, crossings):
        """The box beside the arrow where no clear spot is, near or with a leader: the nearest clear
        of the bodies' edges, else on the fewest of them, else clear of the arrows (and leaders).
        ``gap``: (across, up) [pixels] kept from the names ``placed``, ``gap[1]`` the pad."""
        from ._labels import crosses_any, first_free_box

        pad = gap[1]

        def off_leaders(test):
            return lambda b: test(b) and not crosses_any(leaders, [_widened(b, pad)])

        boxes = _boxes_beyond(free, free - attached, w, h, pad)
        near = [b for b in boxes if _distance_to_box(free, b) <= _BODY_REACH * h]
        for allowed in clear[1:-1]:
            box = first_free_box(near, placed, gap, inner, obstacles, allowed=off_leaders(allowed))
            if box is not None:
                return box
        box = first_free_box(near, placed, gap, inner, obstacles, allowed=off_leaders(clear[-1]),
                             cost=crossings)
        if box is None:
            box = first_free_box(boxes, placed, gap, inner, obstacles, allowed=off_leaders(clear[-1]))
        if box is None:
            box = next((b for b in boxes if not _crosses_arrows(b, segments, pad)), boxes[0])
            placed.append(box)
        return box

    def _show(self, text, leader, box, line):
        """Move ``text`` to ``box`` (pixels) and draw its ``leader`` along ``line`` (pixels, or hide it)."""
        from ._labels import set_if_changed

        to_axes = self.ax.transAxes.inverted()
        u, v = to_axes.transform((box[0], box[1]))
        set_if_changed(text, position=(u, v))
        if line is None:
            set_if_changed(leader, visible=False)
            return
        (u0, v0), (u1, v1) = to_axes.transform(np.asarray(line, float))
        set_if_changed(leader, xdata=[u0, u1], ydata=[v0, v1], visible=True)

    def _clear_space(self, frame, pad, segments, edges, hulls, obstacles):
        """Where a name may stand away from its arrow, the strictest first (:class:`_Occupied`):
        off every line drawn in the 3D view, the arrows, the bodies' outlines and the legend, inside
        the drawn box of the axes (the tick labels are outside it); then off the bodies' edges, the
        arrows, their outlines and the legend only."""
        cube = _convex_hull(self._project(_cube_corners(self.ax)))
        drawn = [self._project(np.column_stack([np.asarray(c, float) for c in line.get_data_3d()]))
                 for line in self.ax.get_lines() if hasattr(line, "get_data_3d")]
        spaces = []
        for lines in ([_segments(points) for points in drawn] + list(edges), list(edges)):
            space = _Occupied(frame, pad)
            for part in lines:
                space.add_segments(part)
            space.add_arrows(segments)
            for hull in hulls:
                space.add_polygon(hull)
            space.add_outside(cube)
            for box in obstacles:
                space.add_box(box)
            spaces.append(space)
        return spaces

    def _drawn(self):
        """Every other line the 3D view draws, in display pixels, (n, 4): the orbits and their
        arrows, the springs, the ground bars, the spin arcs and arrows, the brackets (the bodies'
        edges and the sensors' arrows are :meth:`_bodies`' and ``segments``)."""
        pieces = [_segments(self._project(np.column_stack([np.asarray(c, float) for c in line.get_data_3d()])))
                  for line in self.ax.get_lines() if hasattr(line, "get_data_3d")
                  and not str(line.get_gid()).startswith(("displaced:", "undeformed:"))]
        for collection in self.ax.collections:
            if str(collection.get_gid()).startswith(("orbit-arrow:", "spin-arrow:")):
                for segment in getattr(collection, "_segments3d", ()):
                    pieces.append(_segments(self._project(np.asarray(segment, float).reshape(-1, 3))))
        return np.concatenate(pieces or [np.empty((0, 4))])

    def _bodies(self):
        """The bodies as drawn now, in display pixels: their edges' segments ``(displaced, at rest)``,
        each (n, 4), and the outlines (convex hulls) of the filled bodies (rotors, stator box)."""
        displaced, at_rest, hulls = [], [], []
        for body, points in zip(self.view.outline.bodies, self.view.at_phase(self.phase)):
            displaced.append(_segments(self._project(_edges(body, points))))
            at_rest.append(_segments(self._project(_edges(body, body.vertices))))
            if body.kind in ("stator", "rotor"):
                hulls.append(_convex_hull(self._project(points)))
        return (np.concatenate(displaced or [np.empty((0, 4))]), np.concatenate(at_rest or [np.empty((0, 4))])), hulls

    def _project(self, points):
        """``points`` (n, 3) [m] projected to display pixels, (n, 2) (NaN rows stay NaN)."""
        from mpl_toolkits.mplot3d import proj3d

        x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], self.ax.get_proj())
        return self.ax.transData.transform(np.column_stack([x, y]))

    def _pixels(self, segments):
        """``segments`` (n, 2, 3) [m] projected to display pixels, (n, 2, 2)."""
        from mpl_toolkits.mplot3d import proj3d

        points = segments.reshape(-1, 3)
        x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], self.ax.get_proj())
        return self.ax.transData.transform(np.column_stack([x, y])).reshape(-1, 2, 2)

    def _ends(self, segments):
        """(attached end, free end) of each arrow in pixels: the label goes at the free end."""
        return [(tip, tail) if arrow.kind == "excitation" else (tail, tip)
                for arrow, (tail, tip) in zip(self.view.outline.arrows, segments)]


def _leader_line(ax, arrow):
    """The thin line from an arrow's name to its free end, hidden until a name needs it (pixels
    set at draw time, in axes coordinates)."""
    from matplotlib.lines import Line2D

    line = Line2D([], [], transform=ax.transAxes, color=_ARROW_COLOURS[arrow.kind], linewidth=_LEADER_WIDTH,
                  zorder=_LABEL_ZORDER - 1, visible=False, gid=f"arrow-leader:{arrow.name}")
    line.set_in_layout(False)
    ax.add_artist(line)
    return line


def _leader_spot(spaces, free, direction, w, h, pad, placed, leaders, segments, inner, apart=None):
    """A box ``w x h`` [pixels] for a name in clear space and its leader to the arrow's ``free``
    end: the nearest box (rings around ``free``, along ``direction`` first) that the first of
    ``spaces`` (:class:`_Occupied`) that has one leaves free, inside ``inner``, clear of the names
    ``placed``, whose leader crosses no name, preferably (up to :data:`_LEADER_DETOUR` name heights
    farther) no other leader and no arrow, ``apart`` [pixels] across from the names placed
    (default ``pad``). The box and the leader are added to ``placed``, ``leaders`` and every space.

    Returns
    -------
    tuple
        ``(box, ((x0, y0), (x1, y1)))`` [pixels], or ``(None, None)`` where there is no room.
    """
    from ._labels import crosses_any

    reach = np.hypot(inner[2] - inner[0], inner[3] - inner[1])
    boxes = _ring_boxes(free, direction, w, h, pad, reach)
    ok = (boxes[:, 0] >= inner[0]) & (boxes[:, 1] >= inner[1]) & (boxes[:, 2] <= inner[2]) & (boxes[:, 3] <= inner[3])
    if placed:
        other = np.asarray(placed, float)[None, :, :]
        b = boxes[:, None, :]
        apart = pad if apart is None else apart        # across, between names side by side
        ok &= ~np.any((b[..., 0] < other[..., 2] + apart) & (other[..., 0] < b[..., 2] + apart)
                      & (b[..., 1] < other[..., 3] + pad) & (other[..., 1] < b[..., 3] + pad), axis=1)
    others = [s for s in segments if np.hypot(*(s[1] - free)) > 0.5 and np.hypot(*(s[0] - free)) > 0.5]
    for space in spaces:
        found, first = [None, None, None], None     # crossing nothing; no other leader; only no name
        for box in boxes[ok & space.free(boxes, pad)][:_LEADER_TRIES]:
            line = (tuple(np.clip(free, box[:2], box[2:])), tuple(free))
            if first is not None and _distance_to_box(free, box) > first + _LEADER_DETOUR * h:
                break
            if crosses_any([line], [_widened(p, 0.5 * pad) for p in placed]):
                continue
            first = _distance_to_box(free, box) if first is None else first
            off_leaders = not crosses_any(leaders, [_widened(box, pad)]) and not _touches_segments(line, leaders)
            rank = 0 if off_leaders and not _touches_segments(line, others) else 1 if off_leaders else 2
            found[rank] = found[rank] or (box, line)
            if rank == 0:
                break
        best = next((each for each in found if each is not None), None)
        if best is not None:
            box, line = best
            placed.append(tuple(box))
            leaders.append(line)
            for each in spaces:
                each.add_segments(np.array([[*line[0], *line[1]]]))
            return tuple(box), line
    return None, None


def _touches_segments(line, segments):
    """Whether ``line`` ((x0, y0), (x1, y1)) crosses any of ``segments`` ((start, end) pairs)
    away from its own ends."""
    from ._labels import crosses_segments

    return bool(len(segments)) and crosses_segments(line[0], line[1], np.asarray(segments, float).reshape(-1, 4))


def _widened(box, by):
    return (box[0] - by, box[1] - by, box[2] + by, box[3] + by)


def _ring_boxes(point, direction, w, h, pad, reach):
    """Boxes ``w x h`` [pixels] around ``point`` on rings half a box height apart out to ``reach``
    [pixels], each ring along ``direction`` first then turned from it both ways, shape (n, 4)."""
    length = np.hypot(*direction)
    angle = np.arctan2(direction[1], direction[0]) if length > pad else np.pi / 4
    turns = np.radians(np.concatenate([[0.0], np.repeat(np.arange(15.0, 181.0, 15.0), 2)
                                       * np.tile([1.0, -1.0], 12)]))
    steps = np.arange(0.0, max(reach / h, 1.0), 0.5)
    c, s = np.cos(angle + turns)[None, :], np.sin(angle + turns)[None, :]
    along = pad + steps[:, None] * h + 0.5 * (w * np.abs(c) + h * np.abs(s))
    cx, cy = (point[0] + along * c).ravel(), (point[1] + along * s).ravel()
    return np.column_stack([cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2])


def _cube_corners(ax):
    """The eight corners [m] of a 3D axes' drawn box (its limits), shape (8, 3)."""
    limits = (ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d())
    return np.array([[x, y, z] for x in limits[0] for y in limits[1] for z in limits[2]], float)


class _Occupied:
    """Which cells of a grid over the axes' frame [pixels] are taken (by drawn lines, filled
    outlines, boxes, what lies outside a polygon): a box is free where it covers no taken cell
    (a summed-area table, one look-up per box however many lines are drawn).

    Parameters
    ----------
    frame : matplotlib Bbox
        The axes' frame [pixels].
    cell : float
        Side of a cell [pixels]; a line marks every cell it passes through.
    """

    def __init__(self, frame, cell):
        self.origin, self.cell = np.array([frame.x0, frame.y0]), max(float(cell), 1.0)
        self.grid = np.zeros((int(frame.height / self.cell) + 2, int(frame.width / self.cell) + 2), bool)
        self._table = None

    def _mark(self, points):
        index = np.floor((np.asarray(points, float).reshape(-1, 2) - self.origin) / self.cell)
        index = index[np.all(np.isfinite(index), axis=1)].astype(int)
        ny, nx = self.grid.shape
        keep = (index[:, 0] >= 0) & (index[:, 0] < nx) & (index[:, 1] >= 0) & (index[:, 1] < ny)
        self.grid[index[keep, 1], index[keep, 0]] = True
        self._table = None

    def add_segments(self, lines):
        """Take the cells the segments ``lines`` (n, 4) [pixels] pass through."""
        lines = np.asarray(lines, float).reshape(-1, 4)
        lines = lines[np.all(np.isfinite(lines), axis=1)]
        if not len(lines):
            return
        delta = lines[:, 2:] - lines[:, :2]
        count = np.minimum(np.ceil(np.hypot(delta[:, 0], delta[:, 1]) / (0.5 * self.cell)), 1e4).astype(int) + 1
        which = np.repeat(np.arange(len(lines)), count)
        first = np.cumsum(count) - count
        t = (np.arange(count.sum()) - first[which]) / np.maximum(count[which] - 1, 1)
        self._mark(lines[which, :2] + t[:, None] * delta[which])

    def add_arrows(self, segments):
        """Take the cells of arrows (n, 2, 2) [pixels]: shaft and head (a tenth of the length to
        either side of its last third)."""
        for start, end in np.asarray(segments, float).reshape(-1, 2, 2):
            side = 0.1 * np.array([start[1] - end[1], end[0] - start[0]])
            back = end - 0.3 * (end - start)
            self.add_segments(np.array([[*start, *end], [*(back + side), *end], [*(back - side), *end],
                                        [*(back + side), *(back - side)]]))

    def _centres(self):
        ny, nx = self.grid.shape
        i, j = np.meshgrid(np.arange(nx), np.arange(ny))
        return self.origin + (np.column_stack([i.ravel(), j.ravel()]) + 0.5) * self.cell

    def add_polygon(self, corners):
        """Take the cells inside (and on) the polygon ``corners`` (k, 2) [pixels]."""
        from matplotlib.path import Path

        if len(corners) < 3:
            return
        closed = np.vstack([corners, corners[:1]])
        self.add_segments(np.hstack([closed[:-1], closed[1:]]))
        inside = Path(corners).contains_points(self._centres()).reshape(self.grid.shape)
        self.grid |= inside

    def add_outside(self, corners):
        """Take the cells outside the polygon ``corners`` (k, 2) [pixels]."""
        from matplotlib.path import Path

        if len(corners) >= 3:
            self.grid |= ~Path(corners).contains_points(self._centres()).reshape(self.grid.shape)
            self._table = None

    def add_box(self, box):
        """Take the cells of ``box`` (x0, y0, x1, y1) [pixels]."""
        (i0, j0), (i1, j1) = self._index(np.array([box[:2]])), self._index(np.array([box[2:]]))
        self.grid[j0[0]:j1[0] + 1, i0[0]:i1[0] + 1] = True
        self._table = None

    def _index(self, points):
        ny, nx = self.grid.shape
        index = np.floor((points - self.origin) / self.cell).astype(int)
        return np.clip(index[:, 0], 0, nx - 1), np.clip(index[:, 1], 0, ny - 1)

    def free(self, boxes, widen=0.0):
        """Mask of the ``boxes`` (n, 4) [pixels], widened by ``widen``, that cover no taken cell."""
        if self._table is None:
            self._table = np.pad(self.grid.astype(np.int32).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
        boxes = np.asarray(boxes, float).reshape(-1, 4)
        i0, j0 = self._index(boxes[:, :2] - widen)
        i1, j1 = self._index(boxes[:, 2:] + widen)
        t = self._table
        return (t[j1 + 1, i1 + 1] - t[j0, i1 + 1] - t[j1 + 1, i0] + t[j0, i0]) == 0


def _boxes_beyond(point, direction, w, h, pad):
    """Boxes ``w x h`` [pixels] beside ``point``, ``pad`` away from it: along ``direction`` first
    (an arrow seen end-on: to the upper right), then turned from it, then farther away."""
    length = np.hypot(*direction)
    angle = np.arctan2(direction[1], direction[0]) if length > pad else np.pi / 4
    boxes = []
    for step in _LABEL_STEPS:
        for turn in np.radians(_LABEL_TURNS):
            c, s = np.cos(angle + turn), np.sin(angle + turn)
            reach = pad + step * h + 0.5 * (w * abs(c) + h * abs(s))     # the box's edge ``pad`` from the point
            cx, cy = point[0] + reach * c, point[1] + reach * s
            boxes.append((cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2))
    return boxes


def _crosses_arrows(box, segments, pad):
    """Whether an arrow (pixels, (n, 2, 2)) runs through ``box`` widened by ``pad`` and by the
    spread of the arrow's head (a tenth of its length)."""
    from ._labels import crosses_any

    for (start, end) in segments:
        spread = pad + 0.1 * np.hypot(*(end - start))
        if crosses_any([(start, end)], [(box[0] - spread, box[1] - spread, box[2] + spread, box[3] + spread)]):
            return True
    return False


def _preferences(segments, edges, hulls, pad, drawn=np.empty((0, 4))):
    """Tests a name's box must pass, the strictest first: clear of every arrow, of the bodies'
    edges (displaced and at rest), of their filled outlines and of every other line ``drawn``
    (n, 4) [pixels] (orbits, springs, spin arcs: a name's white background hid a piece of an
    orbit); then of the arrows and edges only; then of the displaced edges; then of the arrows
    only. And the cost of a box where none passes but the last: the body edges through it (a
    displaced one counts twice: drawn solid)."""
    from ._labels import crosses_any

    displaced, at_rest = edges

    def clear_of(lines, b):
        return not crosses_any(lines.reshape(-1, 2, 2), [_widened(b, pad)])

    def crossings(b):
        widened = _widened(b, pad)
        return 2 * _count_through(displaced, widened) + _count_through(at_rest, widened)

    def arrows(b):
        return not _crosses_arrows(b, segments, pad)

    # the cheapest test first (the outlines: a few corners each), the arrows' last (one call each)
    return [lambda b: not any(_box_meets_polygon(b, hull) for hull in hulls) and clear_of(displaced, b)
            and clear_of(at_rest, b) and arrows(b) and clear_of(drawn, b),
            lambda b: arrows(b) and clear_of(displaced, b) and clear_of(at_rest, b),
            lambda b: arrows(b) and clear_of(displaced, b),
            arrows], crossings


def _distance_to_box(point, box):
    """Distance [pixels] from ``point`` (x, y) to the nearest point of ``box`` (x0, y0, x1, y1)."""
    return float(np.hypot(max(box[0] - point[0], 0.0, point[0] - box[2]), max(box[1] - point[1], 0.0, point[1] - box[3])))


def _count_through(lines, box):
    """How many of the segments ``lines`` (n, 4) pass through ``box`` (x0, y0, x1, y1)."""
    from ._labels import segment_crosses_box

    near = (np.minimum(lines[:, 0], lines[:, 2]) <= box[2]) & (np.maximum(lines[:, 0], lines[:, 2]) >= box[0]) \
        & (np.minimum(lines[:, 1], lines[:, 3]) <= box[3]) & (np.maximum(lines[:, 1], lines[:, 3]) >= box[1])
    return sum(segment_crosses_box(line[:2], line[2:], box) for line in lines[near])


def _segments(polyline):
    """Segments (n, 4) [x0, y0, x1, y1] of a NaN-separated polyline (m, 2)."""
    pairs = np.hstack([polyline[:-1], polyline[1:]])
    return pairs[np.all(np.isfinite(pairs), axis=1)]


def _convex_hull(points):
    """Corners (k, 2) of the convex hull of the finite ``points`` (n, 2), counter-clockwise from
    the lowest x (then y) (scipy's Qhull); where fewer than 3 distinct points, those, and where all
    lie on one line (Qhull refuses a flat hull), its two ends: no polygon (:meth:`_Occupied.add_polygon`)."""
    from scipy.spatial import ConvexHull, QhullError

    points = np.unique(points[np.all(np.isfinite(points), axis=1)], axis=0)       # sorted by x, then y
    if len(points) < 3:
        return points
    try:
        corners = ConvexHull(points).vertices
    except QhullError:
        return points[[0, -1]]
    return points[np.roll(corners, -np.argmin(corners))]


def _box_meets_polygon(box, corners):
    """Whether the box (x0, y0, x1, y1) and the convex polygon ``corners`` (k, 2) overlap
    (separating axes: the box's two and the polygon's edge normals)."""
    if len(corners) < 3:
        return False
    square = np.array([[box[0], box[1]], [box[2], box[1]], [box[2], box[3]], [box[0], box[3]]])
    sides = np.roll(corners, -1, axis=0) - corners
    axes = np.vstack([[1.0, 0.0], [0.0, 1.0], np.column_stack([-sides[:, 1], sides[:, 0]])])
    a, b = square @ axes.T, corners @ axes.T
    return not np.any((a.max(axis=0) <= b.min(axis=0)) | (b.max(axis=0) <= a.min(axis=0)))


def _label_arrows(ax, view, phase):
    """Name the sensors and excitations beside their arrows (:class:`_ArrowLabels`)."""
    from ._labels import draw_time_layout

    labels = _ArrowLabels(ax, view, phase)
    layout = draw_time_layout(labels.place)
    layout.set_gid("arrow-labels")
    layout.arrow_labels = labels
    ax.add_artist(layout)


def _frame(ax, flat, view, units="si", phase=None, cycle=False):
    """Limits, labels and ticks of the 3D axes ``ax`` and its projections ``flat``: one cube
    around the machine at rest and, given ``phase`` [rad], its displaced drawing at that phase
    (a displaced body beyond the outline is drawn whole, not cut at the frame's edge), or with
    ``cycle`` at every phase of the period (an animation: :func:`_cycle_points`), with a margin
    of 0.15 of the outline's size."""
    points = np.concatenate(_frame_points(view, phase) + (_cycle_points(view) if cycle else []))
    low, high = points.min(axis=0), points.max(axis=0)
    centre, half = 0.5 * (low + high), 0.5 * (high - low).max() + 0.15 * view.outline.size
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    factor, unit = unit_scale("length", units)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_zlabel(f"z [{unit}]")
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        _unit_ticks(axis, factor)
    ax.tick_params(labelsize="x-small")
    for (panel, (i, j)), (name, _) in zip(flat, _PROJECTIONS):
        panel.set_xlim(centre[i] - half, centre[i] + half)
        panel.set_ylim(centre[j] - half, centre[j] + half)
        panel.set_aspect("equal")
        panel.set_xlabel(f"{_AXIS_NAMES[i]} [{unit}]", fontsize="small", labelpad=1)
        panel.set_ylabel(f"{_AXIS_NAMES[j]} [{unit}]", fontsize="small", labelpad=1)
        _unit_ticks(panel.xaxis, factor)
        _unit_ticks(panel.yaxis, factor)
        panel.set_title(name, fontsize="small")
        panel.tick_params(labelsize="x-small")
        panel.grid(True, alpha=0.3)


def _frame_points(view, phase=None):
    """Points [m] the frame must hold, a list of (n, 3) arrays: the bodies and springs at rest
    and, given ``phase`` [rad], the displaced bodies, brackets and springs."""
    points = [b.vertices for b in view.outline.bodies]
    points.append(np.array([s.point_b for s in view.outline.springs]).reshape(-1, 3))
    if phase is not None:
        points += list(view.at_phase(phase))
        points += [np.asarray(b, float).reshape(-1, 3) for b in view.brackets_at_phase(phase)]
        points += [np.asarray(pair, float).reshape(-1, 3) for pair in view.springs_at_phase(phase)]
    return [p for p in points if len(p)]


def _cycle_points(view):
    """Corners [m] of the box every phase of the period stays in, a list of (n, 3) arrays: each
    drawn point's reach over the period (``view.reach()``: an elliptic or backward mode is
    largest at another phase than 0) and the arrows' tails and tips at their points' reach."""
    low, high = view.reach()
    arrow_low, arrow_high = view.arrow_reach()
    points = [low, high]
    for arrow, a, b in zip(view.outline.arrows, arrow_low, arrow_high):
        d = 0.12 * view.outline.size * arrow.direction / np.linalg.norm(arrow.direction)
        ends = (-d, np.zeros(3)) if arrow.kind == "excitation" else (np.zeros(3), d)   # as _arrow_segments
        points += [np.array([a + e, b + e]) for e in ends]
    return points


def _unit_ticks(axis, factor):
    """Ticks of an axis drawn in metres at round numbers of the shown unit (``factor`` per metre),
    labelled in that unit; SI (factor 1) keeps matplotlib's own ticks."""
    if factor == 1.0:
        return
    from matplotlib.ticker import FuncFormatter, Locator, MaxNLocator

    class _Scaled(Locator):
        def __init__(self):
            self.inner = MaxNLocator()

        def __call__(self):
            return self.tick_values(*self.axis.get_view_interval())

        def tick_values(self, vmin, vmax):
            return np.asarray(self.inner.tick_values(vmin * factor, vmax * factor)) / factor

    axis.set_major_locator(_Scaled())
    axis.set_major_formatter(FuncFormatter(lambda value, _: f"{round(value * factor, 9):g}"))


def _title(view):
    rpm = view.speed * 30 / np.pi
    whirl = "no whirl" if view.whirl == "none" else f"{view.whirl} whirl ({small_number(view.whirl_ratio, sign=True)})"
    return (f"{view.label.capitalize()} mode {view.mode}: {view.frequency_hz:.3f} Hz, "
            f"ζ = {small_number(view.damping_ratio)}, {whirl}, {rpm_text(rpm)} rpm")


def _displaced_kinds(view):
    """``[(colour, words), ...]``: the colours the displaced bodies are drawn in, each once, with
    what it marks (the stator and its brackets; the rotors), in the order of the bodies."""
    words = {"tab:blue": "stator", "tab:orange": "rotors"}
    colours = [_BODY_COLOURS[body.kind] for body in view.outline.bodies]
    if len(view.outline.brackets):
        colours.append("tab:blue")
    return [(colour, words[colour]) for colour in dict.fromkeys(colours)]


def _legend(ax, view, orbits):
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color="0.55", linestyle="--", label="at rest")]
    handles += [Line2D([], [], color=colour, label=f"{words} displaced (exaggerated)")
                for colour, words in _displaced_kinds(view)]
    if orbits:
        handles.append(Line2D([], [], color="tab:red", marker=">", label="orbit; arrow: direction of motion"))
    if view.speed != 0 and any(b.kind in ("rotor", "shaft") for b in view.outline.bodies):
        handles.append(Line2D([], [], color="k", marker=">", label="spin of the rotors"))
    kinds = {a.kind for a in view.outline.arrows}
    handles += [Line2D([], [], color=_ARROW_COLOURS[k], label=k) for k in ("sensor", "excitation") if k in kinds]
    ax.legend(handles=handles, loc="upper left", fontsize="x-small", framealpha=0.8)
