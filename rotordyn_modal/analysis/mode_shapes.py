"""3D mode shapes: the machine's geometry and the motion of each of its points in one mode.

The geometry (:class:`MachineOutline`, model axes [m]) is made of

* bodies, each a set of vertices and polygon faces: the stator as the box with its mass and
  principal inertias (a uniform box of half-sides ``a_i`` has
  ``a_i^2 = 3 (I_j + I_k - I_i) / (2 m)``), or an outline given by the user (polylines); each
  rotor as the solid cylinder with its mass, polar and diametral inertia
  (``r^2 = 2 J_p / m``, ``L^2 = 12 I_d / m - 3 r^2``) along the spin axis;
* brackets: lines from the stator's box to its attachment points that lie outside it; a rigid
  rotor's axis from its cylinder out to its bearings that lie beyond it (a body of kind 'rod');
* springs between two bodies, or a body and the ground (suspensions today), each from a point
  of one to a point of the other;
* sensors and excitations as arrows along their directions.

:func:`mode_shape_3d` gives every one of those points its complex displacement in one mode,
``scale * shape_at(point)``: the drawn position at phase ``phi`` is
``x + Re(d exp(i phi))`` (:func:`displaced`; :meth:`ModeShape3D.at_phase` and its siblings for
the brackets, springs and arrows), and ``phi`` from 0 to 2 pi traces each point's whirl orbit
(:func:`whirl_orbit`, :meth:`ModeShape3D.orbit_points`): the figures
(:mod:`rotordyn_modal.plotting.shapes3d`) draw these positions and compute none.
Every body's motion at a point comes from :func:`_point_motion`, the one place that knows how
a body moves in a mode.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, ModelWarning
from ..model._table import LARGEST

__all__ = ["MachineOutline", "Body", "Spring", "Arrow", "machine_outline", "ModeShape3D", "mode_shape_3d",
           "mode_index", "displaced", "whirl_orbit", "whirl_direction", "ShaftLine", "ShaftLines", "shaft_lines"]

#: segments of a rotor's circles
_CIRCLE = 24
#: largest displacement drawn, relative to the machine's size
_DISPLAY_FRACTION = 0.15


@dataclass(frozen=True)
class Body:
    """A rigid body's drawing: vertices [m] and faces (polygons as vertex indices).

    ``kind`` is 'stator', 'rotor', 'shaft' (a flexible rotor's line), 'rod' (a rigid rotor's
    axis out to bearings beyond its cylinder) or 'outline' (user polylines); for the last three
    ``faces`` are open polylines, drawn as lines, not filled.
    """

    name: str
    kind: str
    vertices: np.ndarray
    faces: tuple
    axis: np.ndarray | None = None
    spin: float = 0.0


@dataclass(frozen=True)
class Spring:
    """A spring-damper from ``point_a`` of ``body_a`` to ``point_b`` of ``body_b`` ('ground' is fixed)."""

    name: str
    kind: str
    body_a: str
    point_a: np.ndarray
    body_b: str
    point_b: np.ndarray


@dataclass(frozen=True)
class Arrow:
    """A sensor or excitation: ``kind`` 'sensor' or 'excitation', on ``body`` at ``point``."""

    name: str
    kind: str
    body: str
    point: np.ndarray
    direction: np.ndarray


@dataclass(frozen=True)
class MachineOutline:
    """What is drawn of a machine (model axes [m]).

    Attributes
    ----------
    bodies : tuple of Body
    brackets : ndarray, shape (n_brackets, 2, 3)
        Lines of the body that holds the suspensions, sensors and excitations: from the
        stator's box to its attachment points outside it, or (no stator) from the first
        rotor's centre to them (the massless carrier).
    bracket_body : str
        'stator', or the first rotor's name when there is no stator.
    springs : tuple of Spring
    arrows : tuple of Arrow
    size : float
        Largest extent of the drawing [m] (sets arrow lengths and the display scale).
    spin_axis : ndarray, shape (3,)
    """

    bodies: tuple
    brackets: np.ndarray
    bracket_body: str
    springs: tuple
    arrows: tuple
    size: float
    spin_axis: np.ndarray


def machine_outline(model, outline=None) -> MachineOutline:
    """The drawing of a machine: stator box (or ``outline``), rotors, springs, sensors.

    Parameters
    ----------
    model : Model
    outline : array_like, shape (n_points, 3), optional
        The stator's outline as polylines [m], model axes; rows of NaN separate the lines
        (``rotordyn_modal.io.outline.read_outline`` reads a file of them and names it).

    Returns
    -------
    MachineOutline

    Warns
    -----
    ModelWarning
        An outline more than 30 times wider than the machine's own drawing: a drawing's
        millimetres or inches read as metres (:func:`outline_scale_words`).
    """
    axis = np.asarray(model.spin_axis, dtype=float)
    bodies = [_rotor_body(model, rotor, axis) for rotor in model.rotors]
    brackets = np.zeros((0, 2, 3))
    if outline is not None:
        bodies.insert(0, _outline_body(outline))
        _warn_wide_outline(outline, model)
    elif model.stator is not None:
        box = _stator_box(model.stator)
        bodies.insert(0, box)
        brackets = _brackets(model, box)
    elif _holder(model) != "ground":        # sensors on the ground need no line to a rotor
        brackets = _carrier(model)
    bodies += [rod for rotor in model.rotors if (rod := _rotor_rod(model, rotor, axis)) is not None]
    points = np.concatenate([b.vertices for b in bodies] + [brackets.reshape(-1, 3)]
                            + [[s.position for s in model.suspensions]] * bool(model.suspensions))
    size = float(np.max(np.ptp(points, axis=0))) or 1.0
    springs = tuple(_suspension_spring(model, s, 0.3 * size) for s in model.suspensions) \
        + tuple(_bearing_spring(model, b) for b in model.bearings)
    arrows = tuple([Arrow(s.name, "sensor", s.rotor or _holder(model), np.asarray(s.position, float),
                          np.asarray(s.direction, float)) for s in model.sensors]
                   + [Arrow(x.name, "excitation", x.rotor or _holder(model), np.asarray(x.position, float),
                            np.asarray(x.direction, float)) for x in model.excitations if x.kind == "force"])
    return MachineOutline(bodies=tuple(bodies), brackets=brackets, bracket_body=_holder(model), springs=springs,
                          arrows=arrows, size=size, spin_axis=axis)


#: an outline this many times wider than the machine it draws was most likely typed in another unit
_WIDER = 30.0


def _warn_wide_outline(outline, model) -> None:
    """One warning for an outline far wider than the machine's own drawing (bodies, mounts,
    bearings, the stator box): said here, where the command line and the Python API meet."""
    import warnings

    words = outline_scale_words(outline, machine_outline(model).size, getattr(outline, "source", None))
    if words:
        warnings.warn(words, ModelWarning, stacklevel=4)


def outline_scale_words(points, machine_size: float, path) -> str | None:
    """The warning for an outline far wider than the machine (a drawing's millimetres or inches
    read as metres, no unit in its header: the machine shrinks to a dot in the figure), else None.

    Parameters
    ----------
    points : ndarray, shape (n, 3)
        The outline's points [m] (NaN rows between lines).
    machine_size : float
        The largest extent of the machine's own drawing [m] (bodies, mounts, bearings).
    path : path-like or None
        The file, for the words (None: an outline given as an array).
    """
    drawn = np.asarray(points, float)
    drawn = drawn[~np.isnan(drawn).any(axis=1)]
    size = float(np.max(np.ptp(drawn, axis=0))) if len(drawn) else 0.0
    if not machine_size > 0 or not size > _WIDER * machine_size:
        return None
    return (f"{str(path) + ': ' if path else ''}the outline spans {size:.4g} m, {size / machine_size:.3g} times the machine it draws "
            f"({machine_size:.4g} m: its bodies, mounts and bearings); coordinates in mm or inches read as metres? "
            "(a unit in the header converts them: 'x [mm]', 'y [in]')")


def _holder(model):
    """The body that carries sensors, excitations and suspensions: the stator, the ground when
    rotors sit on bearings to the ground, or else the first rotor (a massless frame)."""
    if model.stator is not None:
        return "stator"
    return "ground" if model.bearings else model.rotors[0].name


def _stator_box(stator) -> Body:
    m = float(stator.mass)
    inertia = np.asarray(stator.inertia, dtype=float)
    principal, axes = np.linalg.eigh(inertia)
    total = principal.sum()
    half = np.sqrt(np.maximum(3.0 * (total - 2 * principal) / (2 * m), 0.0))
    half = np.maximum(half, 0.05 * half.max())
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    vertices = np.asarray(stator.center_of_mass, float) + (corners * half) @ axes.T
    faces = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))
    return Body("stator", "stator", vertices, faces)


def _outline_body(outline) -> Body:
    points = np.asarray(outline, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2:
        raise InputError(f"outline: expected points of shape (n, 3) with n >= 2 (NaN rows separate lines), "
                         f"got shape {points.shape}")
    bad = ~np.isnan(points) & ~(np.abs(points) <= LARGEST)   # NaN separates lines; inf or 1e300 is no point
    if bad.any():
        row, column = (int(i) for i in np.argwhere(bad)[0])
        raise InputError(f"outline: point {row} {'xyz'[column]} = {points[row, column]:g}: expected finite "
                         f"coordinates of magnitude at most {LARGEST:g} m (NaN rows separate lines)")
    breaks = np.nonzero(np.isnan(points).any(axis=1))[0]
    lines, start = [], 0
    for stop in list(breaks) + [len(points)]:
        if stop - start >= 2:
            lines.append(tuple(range(start, stop)))
        start = stop + 1
    if not lines:
        raise InputError("outline: no line of two or more points")
    return Body("stator", "outline", np.nan_to_num(points), tuple(lines))


def _shaft_body(model, rotor, axis) -> Body:
    """A flexible rotor: its axis line through the points of :func:`shaft_lines` (the nodes and the
    points between them), then a circle at each disk (radius ``sqrt(2 J_p / m)``). ``faces`` are
    open polylines: the line first, then each closed circle."""
    shaft = rotor.flexible
    line = shaft.point(_line_z(shaft))
    e1, e2 = _ring_axes(axis)
    angles = 2 * np.pi * np.arange(_CIRCLE) / _CIRCLE
    vertices, faces = [line], [tuple(range(len(line)))]
    for disk in shaft.disks:
        radius = np.sqrt(2 * disk.polar_inertia / disk.mass)
        first = sum(len(v) for v in vertices)
        vertices.append(shaft.point(disk.z) + radius * (np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2))
        faces.append(tuple(range(first, first + _CIRCLE)) + (first,))
    return Body(rotor.name, "shaft", np.concatenate(vertices), tuple(faces), axis=axis,
                spin=float(model.speed_ratios[rotor.name]))


def _ring_axes(axis):
    e1 = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(axis, e1)


def _cylinder(rotor):
    """(radius, length) [m] of the solid cylinder drawn for a rigid rotor."""
    m = float(rotor.mass)
    radius = np.sqrt(2 * rotor.polar_inertia / m)
    length = np.sqrt(max(12 * rotor.diametral_inertia / m - 3 * radius ** 2, 0.0))
    return radius, max(length, 0.15 * radius)


def _rotor_rod(model, rotor, axis) -> Body | None:
    """A rigid rotor's axis from its cylinder to its bearings beyond it (a disk on a rod held in
    a bearing 0.75 m away), an open polyline of kind 'rod' that moves with the rotor; None
    when every bearing lies within the cylinder's length."""
    if rotor.flexible is not None:
        return None
    centre = np.asarray(rotor.center_of_mass, float)
    along = [float((np.asarray(b.position, float) - centre) @ axis) for b in model.bearings if b.rotor == rotor.name]
    half = 0.5 * _cylinder(rotor)[1]
    low, high = min(along + [-half]), max(along + [half])
    if low >= -half and high <= half:
        return None
    vertices = np.array([centre + low * axis, centre + high * axis])
    return Body(rotor.name, "rod", vertices, ((0, 1),), axis=axis)


def _rotor_body(model, rotor, axis) -> Body:
    if rotor.flexible is not None:
        return _shaft_body(model, rotor, axis)
    radius, length = _cylinder(rotor)
    e1 = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    angles = 2 * np.pi * np.arange(_CIRCLE) / _CIRCLE
    ring = radius * (np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2)
    centre = np.asarray(rotor.center_of_mass, float)
    vertices = np.concatenate([centre - 0.5 * length * axis + ring, centre + 0.5 * length * axis + ring,
                               [centre - 0.5 * length * axis, centre + 0.5 * length * axis]])
    n = _CIRCLE
    sides = tuple((k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n))
    faces = sides + (tuple(range(n)), tuple(range(n, 2 * n)))
    return Body(rotor.name, "rotor", vertices, faces, axis=axis, spin=float(model.speed_ratios[rotor.name]))


def _brackets(model, box) -> np.ndarray:
    """A line from each attachment point outside the box to the nearest point of the box."""
    centre = box.vertices.mean(axis=0)
    axes = _box_axes(box)
    half = 0.5 * np.ptp((box.vertices - centre) @ axes, axis=0)
    points = [s.position for s in model.suspensions] + [s.position for s in model.sensors] \
        + [x.position for x in model.excitations]
    lines = []
    for p in np.asarray(points, dtype=float).reshape(-1, 3):
        local = (p - centre) @ axes
        nearest = np.clip(local, -half, half)
        if np.linalg.norm(local - nearest) > 1e-9:
            lines.append([centre + axes @ nearest, p])
    return np.asarray(lines, dtype=float).reshape(-1, 2, 3)


def _carrier(model) -> np.ndarray:
    """Without a stator: lines from the first rotor's centre to the attachment points."""
    centre = np.asarray(model.rotors[0].center_of_mass, float)
    points = [s.position for s in model.suspensions] + [s.position for s in model.sensors] \
        + [x.position for x in model.excitations]
    lines = [[centre, p] for p in np.asarray(points, dtype=float).reshape(-1, 3)
             if np.linalg.norm(p - centre) > 1e-9]
    return np.asarray(lines, dtype=float).reshape(-1, 2, 3)


def _box_axes(box):
    v = box.vertices
    return np.stack([(v[4] - v[0]) / np.linalg.norm(v[4] - v[0]), (v[2] - v[0]) / np.linalg.norm(v[2] - v[0]),
                     (v[1] - v[0]) / np.linalg.norm(v[1] - v[0])], axis=1)


def _suspension_spring(model, suspension, length) -> Spring:
    """Ground end along the stiffest translational axis, away from the reference point."""
    K = np.asarray(suspension.stiffness_matrix, dtype=float)[:3, :3]
    values, vectors = np.linalg.eigh(0.5 * (K + K.T))
    direction = vectors[:, int(np.argmax(values))]
    p = np.asarray(suspension.position, dtype=float)
    outward = p - np.asarray(model.reference_point, float)
    if np.dot(direction, outward) < 0:
        direction = -direction
    return Spring(suspension.name, "suspension", _holder(model), p, "ground", p + length * direction)


def _bearing_spring(model, bearing) -> Spring:
    """A radial spoke from the rotor's axis at the bearing to the stator (or ground) just outside
    the rotor's drawn radius, so that the rotor's motion in its bearing shows."""
    rotor = model.rotor(bearing.rotor)
    radius = np.sqrt(2 * rotor.polar_inertia / rotor.mass)
    e = np.asarray(model.spin_axis, dtype=float)
    down = np.array([0.0, 0.0, -1.0]) - e[2] * e
    down = down / np.linalg.norm(down) if np.linalg.norm(down) > 1e-6 else np.cross(e, [0.0, 1.0, 0.0])
    p = np.asarray(bearing.position, dtype=float)
    return Spring(bearing.name, "bearing", rotor.name, p, _holder(model) if model.stator is not None else "ground",
                  p + 1.4 * radius * down)


# ---------------------------------------------------------------------------------------------
# one mode
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ModeShape3D:
    """The machine's drawing and the complex displacement of each of its points in one mode.

    Attributes
    ----------
    outline : MachineOutline
    mode : int
        Mode number as in ``ModalResult.to_dataframe()`` (1 = lowest oscillatory mode).
    frequency_hz, damping_ratio, whirl_ratio : float
    whirl : str
    speed : float
        Reference rotor speed [rad/s].
    scale : float
        Factor applied to the mode shape [m per unit modal amplitude]: largest drawn
        displacement 15 % of the machine's size unless given.
    body_motion : tuple of ndarray, each shape (n_vertices, 3), complex [m]
        Displacement of each body's vertices (same order as ``outline.bodies``).
    bracket_motion : ndarray, shape (n_brackets, 2, 3), complex [m]
    spring_motion : ndarray, shape (n_springs, 2, 3), complex [m]
        Displacement of each spring's two ends (zero at the ground).
    arrow_motion : ndarray, shape (n_arrows, 3), complex [m]
    label : str
        'model' or e.g. 'measured'.
    """

    outline: MachineOutline
    mode: int
    frequency_hz: float
    damping_ratio: float
    whirl: str
    whirl_ratio: float
    speed: float
    scale: float
    body_motion: tuple
    bracket_motion: np.ndarray
    spring_motion: np.ndarray
    arrow_motion: np.ndarray
    label: str = "model"

    def at_phase(self, phase: float):
        """Displaced vertices of every body at ``phase`` [rad]: list of (n_vertices, 3) [m]."""
        return [displaced(b.vertices, d, phase) for b, d in zip(self.outline.bodies, self.body_motion)]

    def brackets_at_phase(self, phase: float) -> list:
        """Displaced brackets at ``phase`` [rad]: list of (2, 3) [m], one per ``outline.brackets``."""
        return [displaced(bracket, d, phase) for bracket, d in zip(self.outline.brackets, self.bracket_motion)]

    def springs_at_phase(self, phase: float) -> list:
        """Displaced ends of every spring at ``phase`` [rad]: list of ``(a, b)``, each shape (3,)
        [m], one per ``outline.springs`` (a ground end does not move)."""
        return [(displaced(s.point_a, d[0], phase), displaced(s.point_b, d[1], phase))
                for s, d in zip(self.outline.springs, self.spring_motion)]

    def arrows_at_phase(self, phase: float) -> np.ndarray:
        """Displaced point of every sensor and excitation at ``phase`` [rad], shape (n_arrows, 3) [m]."""
        points = [displaced(a.point, d, phase) for a, d in zip(self.outline.arrows, self.arrow_motion)]
        return np.asarray(points, float).reshape(-1, 3)

    def reach(self):
        """How far the drawing goes over one period: for each drawn point (bodies' vertices,
        brackets, springs' ends), its lowest and highest coordinates over every phase. A point
        at ``p + Re(d exp(i phi))`` reaches ``p_k - |d_k|`` and ``p_k + |d_k|`` in each
        coordinate ``k`` and no further, whatever the ellipse it whirls on.

        Returns
        -------
        low, high : ndarray, shape (n, 3) [m]
        """
        points = [b.vertices for b in self.outline.bodies] + [np.reshape(self.outline.brackets, (-1, 3))]
        motions = [np.asarray(d, complex) for d in self.body_motion] + [np.reshape(self.bracket_motion, (-1, 3))]
        for spring, motion in zip(self.outline.springs, self.spring_motion):
            points += [np.reshape(spring.point_a, (1, 3)), np.reshape(spring.point_b, (1, 3))]
            motions += [motion[:1], motion[1:]]
        return _reach(points, motions)

    def arrow_reach(self):
        """:meth:`reach` of each sensor's and excitation's point (in ``outline.arrows``' order).

        Returns
        -------
        low, high : ndarray, shape (n_arrows, 3) [m]
        """
        return _reach([np.reshape([a.point for a in self.outline.arrows], (-1, 3))], [np.reshape(self.arrow_motion, (-1, 3))])

    def orbit_points(self):
        """The points whose whirl orbits the figures trace, and their complex displacements: each
        rotor's axis ends (its cylinder's two centres), a shaft line's two ends, the stator box's
        centre (the mean of its corners' motions: a rigid body's motion is linear in the point),
        the springs' ends on the machine.

        Returns
        -------
        points : ndarray, shape (P, 3) [m]
        motions : ndarray of complex, shape (P, 3) [m]
        """
        points, motions = [], []
        for body, motion in zip(self.outline.bodies, self.body_motion):
            if body.kind == "rotor":
                points.extend(body.vertices[-2:])
                motions.extend(motion[-2:])
            elif body.kind == "shaft":                  # the line's two ends
                ends = [body.faces[0][0], body.faces[0][-1]]
                points.extend(body.vertices[ends])
                motions.extend(motion[ends])
            elif body.kind == "stator":
                points.append(body.vertices.mean(axis=0))
                motions.append(motion.mean(axis=0))
        for spring, motion in zip(self.outline.springs, self.spring_motion):
            points.append(spring.point_a)
            motions.append(motion[0])
        return np.asarray(points, float).reshape(-1, 3), np.asarray(motions, complex).reshape(-1, 3)

    def orbit_paths(self, phases) -> np.ndarray:
        """The whirl orbits of :meth:`orbit_points` over ``phases`` [rad], shape (P, F, 3) [m]
        (:func:`whirl_orbit`; ``phases[0] = 0`` puts each path's first point where the mode is
        drawn at phase 0)."""
        points, motions = self.orbit_points()
        return np.asarray([whirl_orbit(p, d, phases) for p, d in zip(points, motions)], float) \
            .reshape(len(points), len(phases), 3)

    def orbit_directions(self) -> np.ndarray:
        """Velocity of each of :meth:`orbit_points` along its orbit at phase 0 per radian of
        phase [m/rad], shape (P, 3) (:func:`whirl_direction`)."""
        return whirl_direction(self.orbit_points()[1])

    def plot(self, **kwargs):
        """The 3D figure; see :func:`rotordyn_modal.plotting.plot_mode_shape`."""
        from ..plotting.shapes3d import plot_mode_shape

        return plot_mode_shape(self, **kwargs)

    def animate(self, path=None, **kwargs):
        """The animation; see :func:`rotordyn_modal.plotting.animate_mode_shape`."""
        from ..plotting.shapes3d import animate_mode_shape

        return animate_mode_shape(self, path, **kwargs)


def _reach(points, motions):
    """``(low, high)``, each shape (n, 3) [m]: ``p -+ |d|`` of the stacked ``points`` and their
    complex ``motions`` (lists of (m, 3) arrays)."""
    p = np.concatenate([np.asarray(x, float).reshape(-1, 3) for x in points])
    d = np.abs(np.concatenate([np.asarray(x, complex).reshape(-1, 3) for x in motions]))
    return p - d, p + d


def displaced(points, motion, phase: float) -> np.ndarray:
    """Points moved by their complex displacement in a mode at one phase:
    ``points + Re(motion exp(i phase))`` [m].

    Parameters
    ----------
    points : array_like, shape (..., 3)
        Positions at rest [m].
    motion : array_like of complex, shape (..., 3)
        Their complex displacements [m] (broadcast against ``points``).
    phase : float
        Phase of the motion [rad] (0: ``Re(motion)``).

    Returns
    -------
    ndarray, shape of ``points + motion``
    """
    return points + np.real(motion * np.exp(1j * phase))


def whirl_orbit(point, motion, phases) -> np.ndarray:
    """The orbit a point traces in a mode: ``point + Re(motion exp(i phi))`` at each ``phi``.

    Parameters
    ----------
    point : array_like, shape (3,)
        Position at rest [m].
    motion : array_like of complex, shape (3,)
        Its complex displacement [m].
    phases : array_like, shape (P,)
        Phases [rad] (0 to 2 pi: one period).

    Returns
    -------
    ndarray, shape (P, 3) [m]
    """
    return point + np.real(motion[None, :] * np.exp(1j * np.asarray(phases))[:, None])


def whirl_direction(motion) -> np.ndarray:
    """Velocity of a point along its orbit at phase 0 per radian of phase,
    ``d/dphi Re(motion exp(i phi)) = Re(i motion)`` [m/rad], shape of ``motion``: the direction
    it whirls from where it is drawn at phase 0."""
    return np.real(1j * np.asarray(motion))


def mode_index(result, mode: int) -> int:
    """Index into ``result`` of the oscillatory mode numbered ``mode`` (from 1, as in the table)."""
    oscillatory = np.nonzero(result.oscillatory)[0]
    # NaN or a string: this message, not numpy's or int()'s words without the argument's name;
    # True is an int to Python and drew mode 1 without a word
    is_number = isinstance(mode, (int, float, np.number)) and not isinstance(mode, (bool, np.bool_))
    number = np.asarray(mode) if is_number else np.asarray(np.nan)
    if not (number.ndim == 0 and np.isfinite(number) and 1 <= int(mode) <= len(oscillatory) and int(mode) == mode):
        raise InputError(f"mode {mode!r}: expected a mode number from 1 to {len(oscillatory)} "
                         "(the 'mode' column of the modes table)")
    return int(oscillatory[int(mode) - 1])


def mode_shape_3d(result, model, mode: int, scale: float | None = None, outline=None,
                  label: str = "model") -> ModeShape3D:
    """The motion of every drawn point of the machine in one mode.

    Parameters
    ----------
    result : ModalResult
    model : Model
        The model analysed (its geometry).
    mode : int
        Mode number as in ``result.to_dataframe()`` (1 = lowest oscillatory mode).
    scale : float, optional
        Displacement per unit modal amplitude drawn [m]; default: the largest displacement is
        15 % of the machine's size.
    outline : array_like, shape (n, 3), optional
        The stator as polylines (see :func:`machine_outline`).
    label : str

    Returns
    -------
    ModeShape3D
    """
    k = mode_index(result, mode)
    if scale is not None:      # NaN or inf drew a shape of NaN motions without a word; refused before the work
        from .._arguments import number

        scale = number(scale, "scale", "m per unit modal amplitude")
    drawing = machine_outline(model, outline)
    bodies = [_shaft_motion(result, model, b, k) if b.kind == "shaft" else _point_motion(result, b.vertices, b.name)[k]
              for b in drawing.bodies]
    brackets = _point_motion(result, drawing.brackets.reshape(-1, 3), drawing.bracket_body)[k].reshape(-1, 2, 3)
    springs = np.array([[_end_motion(result, s.body_a, s.point_a, k), _end_motion(result, s.body_b, s.point_b, k)]
                        for s in drawing.springs], dtype=complex).reshape(-1, 2, 3)
    arrows = np.array([_point_motion(result, a.point[None], a.body)[k, 0] for a in drawing.arrows],
                      dtype=complex).reshape(-1, 3)
    largest = max([np.abs(b).max(initial=0.0) for b in bodies] + [np.abs(springs).max(initial=0.0)])
    if scale is None:
        scale = _DISPLAY_FRACTION * drawing.size / largest if largest > 0 else 1.0
    return ModeShape3D(outline=drawing, mode=int(mode), frequency_hz=float(result.frequencies_hz[k]),
                       damping_ratio=float(result.damping_ratios[k]), whirl=str(result.whirl[k]),
                       whirl_ratio=float(result.whirl_ratios[k]), speed=float(result.speed), scale=float(scale),
                       body_motion=tuple(scale * b for b in bodies), bracket_motion=scale * brackets,
                       spring_motion=scale * springs, arrow_motion=scale * arrows, label=label)


def _shaft_motion(result, model, body, k):
    """A flexible rotor's drawing in mode ``k``: its line laterally as :func:`shaft_lines` draws it
    (the elements' shape functions between the nodes), axially and its disks' circles as their
    nodes move; (n_vertices, 3) complex [m per unit modal amplitude]."""
    from ..model.geometry import transverse_axes

    rotor = model.rotor(body.name)
    a, b = transverse_axes(model.spin_axis)
    e = np.asarray(model.spin_axis, dtype=float)
    motion = _point_motion(result, body.vertices, body.name)[k]
    line = list(body.faces[0])
    lateral = _flexible_line(result, model, rotor, k, (a, b, e), _POINTS_PER_ELEMENT)["displacement"]
    motion[line] = np.outer(motion[line] @ e, e) + np.outer(lateral[0], a) + np.outer(lateral[1], b)
    return motion


def _end_motion(result, body, point, k):
    if body == "ground":
        return np.zeros(3, complex)
    return _point_motion(result, np.asarray(point)[None], body)[k, 0]


def _point_motion(result, points, body):
    """Complex motion of points of ``body`` in every mode: (n_modes, n_points, 3) [m per unit amplitude].

    A rotor on bearings moves with its own coordinates, a rigidly attached rotor with the
    stator, the ground not at all; anything else (stator box, outline) is the stator.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    if not len(points) or body == "ground":
        return np.zeros((len(result.eigenvalues), len(points), 3), complex)
    rotor = body if body in getattr(result, "rotor_names", ()) else None
    return np.stack([result.shape_at(p, body=rotor) for p in points], axis=1)


# ---------------------------------------------------------------------------------------------
# deflected shaft lines along the axis
# ---------------------------------------------------------------------------------------------
#: points drawn inside each element of a flexible rotor (besides its nodes)
_POINTS_PER_ELEMENT = 8
#: most points :func:`shaft_lines` draws inside an element (a line of 2,500 nodes then holds 2.5
#: million points per rotor: a few hundred MB; 10**7 asked for the machine's whole memory)
MAX_POINTS_PER_ELEMENT = 1000
#: points along a rigid rotor's straight line
_RIGID_POINTS = 21
#: lateral motion below this fraction of the mode's largest motion is round-off (an axial mode)
_LATERAL_ROUND_OFF = 1e-8


@dataclass(frozen=True)
class ShaftLine:
    """One rotor's deflected line in one mode, normalised with the other rotors of the mode.

    Positions are along the model's spin axis ``e`` in model coordinates (``x . e`` [m]), so
    every rotor of the machine and its bearings share one axis. Displacements are along the
    transverse axes ``a, b`` (:func:`~rotordyn_modal.model.geometry.transverse_axes`); the
    drawn line at phase ``phi`` is ``Re(u exp(i phi))``.

    Attributes
    ----------
    rotor : str
    flexible : bool
        True for a rotor with a shaft (its nodes are the mesh's); False for a rigid rotor (a
        straight line; its "nodes" are the line's two ends).
    position : ndarray, shape (n,) [m]
        Points of the line along the axis, increasing.
    displacement : ndarray, shape (2, n), complex
        ``(u_a, u_b)`` at each point, absolute (the stator's motion there included), normalised:
        the largest ``|u|`` over the mode's lines is 1 and is real (phase 0).
    relative : ndarray, shape (2, n), complex
        The same relative to the stator's point at the same place (same factor).
    node_position : ndarray, shape (N,) [m]
    node_displacement, node_relative_displacement : ndarray, shape (2, N), complex
        ``(u_a, u_b)`` at the nodes (same normalisation).
    node_rotation, node_relative_rotation : ndarray, shape (2, N), complex
        ``(theta_a, theta_b)`` at the nodes, in radians per the same unit as the displacements
        [rad per normalised m: 1/m].
    bearings : tuple of (str, float)
        Each bearing's name and position [m] on the axis.
    disks : tuple of (str, float, float)
        Each disk's name, position [m] and mass [kg] (a flexible rotor's disks; none for a rigid
        rotor).
    whirl : str
        The rotor's own whirl in the mode: 'forward', 'backward' or 'none'.
    """

    rotor: str
    flexible: bool
    position: np.ndarray
    displacement: np.ndarray
    relative: np.ndarray
    node_position: np.ndarray
    node_displacement: np.ndarray
    node_rotation: np.ndarray
    node_relative_displacement: np.ndarray
    node_relative_rotation: np.ndarray
    bearings: tuple = ()
    disks: tuple = ()
    whirl: str = "none"

    @property
    def excursion(self) -> np.ndarray:
        """(n,) [as ``displacement``]: each point's largest distance from the axis over a period,
        the semi-major axis of its orbit ``Re(u exp(i phi))`` (:func:`orbit_excursion`)."""
        return orbit_excursion(self.displacement)

    @property
    def relative_excursion(self) -> np.ndarray:
        """(n,) [as ``relative``]: :attr:`excursion` of the motion relative to the stator."""
        return orbit_excursion(self.relative)


def orbit_excursion(u) -> np.ndarray:
    """Largest distance from the axis over a period of the orbit ``Re(u exp(i phi))``: its
    semi-major axis ``sqrt((|u_a|^2 + |u_b|^2 + |u_a^2 + u_b^2|) / 2)``.

    Parameters
    ----------
    u : ndarray, shape (2, n), complex
        ``(u_a, u_b)`` at each point.

    Returns
    -------
    ndarray, shape (n,) [as ``u``]
    """
    return np.sqrt(0.5 * (np.abs(u[0]) ** 2 + np.abs(u[1]) ** 2 + np.abs(u[0] ** 2 + u[1] ** 2)))


@dataclass(frozen=True)
class ShaftLines:
    """The deflected lines of every rotor in one mode.

    Attributes
    ----------
    mode : int
        Mode number as in the modes table (:func:`mode_index`).
    frequency_hz, damping_ratio, whirl_ratio : float
    whirl : str
        The machine's whirl in the mode.
    speed : float
        Reference rotor speed [rad/s].
    axis_names : tuple of str
        Names of ``a, b`` and ``e`` (model axis letters when they are model axes).
    lines : tuple of ShaftLine
        One per rotor, in model order.
    lateral : bool
        False when no rotor moves laterally in the mode (an axial or torsional mode): its lateral
        motions are round-off (below 1e-8 of the mode's largest motion) and the lines are zero.
    """

    mode: int
    frequency_hz: float
    damping_ratio: float
    whirl: str
    whirl_ratio: float
    speed: float
    axis_names: tuple
    lines: tuple
    lateral: bool = True

    def plot(self, **kwargs):
        """The panel; see :func:`rotordyn_modal.plotting.shaft_modes.plot_shaft_modes`."""
        from ..plotting.shaft_modes import plot_shaft_modes

        return plot_shaft_modes([self], **kwargs)


def shaft_lines(result, model, mode: int, points_per_element: int = _POINTS_PER_ELEMENT) -> ShaftLines:
    """Every rotor's deflected line along the axis in one mode.

    A flexible rotor's line goes through its nodes' motions and, inside each element, follows
    the element's own shape functions (:func:`~rotordyn_modal.elements.shaft.lateral_deflection`:
    cubic, exact for rigid motions); a rigid rotor's line is straight, its rigid motion at
    each point (:meth:`ModalResult.shape_at`), from its inertia-equivalent cylinder's ends or
    its outermost bearings, whichever reach further.

    Parameters
    ----------
    result : ModalResult
    model : Model
        The model analysed.
    mode : int
        Mode number as in ``result.to_dataframe()`` (1 = lowest oscillatory mode).
    points_per_element : int
        Points drawn inside each element of a flexible rotor, 0 to
        :data:`MAX_POINTS_PER_ELEMENT` (0: the nodes only).

    Returns
    -------
    ShaftLines
        Normalised together: the largest ``|u_a|`` or ``|u_b|`` of the absolute lines is 1 and
        real.
    """
    from ..model.dofs import _axis_letters
    from ..model.geometry import transverse_axes

    from .._arguments import whole_number

    k = mode_index(result, mode)
    points_per_element = whole_number(points_per_element, "points_per_element", 0, MAX_POINTS_PER_ELEMENT)
    a, b = transverse_axes(model.spin_axis)
    e = np.asarray(model.spin_axis, dtype=float)
    raw = [_flexible_line(result, model, rotor, k, (a, b, e), points_per_element) if rotor.flexible is not None
           else _rigid_line(result, model, rotor, k, (a, b, e)) for rotor in model.rotors]
    values = np.concatenate([line["displacement"].ravel() for line in raw])
    biggest = values[int(np.argmax(np.abs(values)))] if values.size else 0.0
    # an axial or torsional mode has no lateral motion: round-off, not drawn as a shape
    lateral = abs(biggest) > _LATERAL_ROUND_OFF * max(max([line.pop("largest") for line in raw], default=0.0),
                                                      float(np.abs(result.shapes[k]).max()))
    factor = 1.0 / biggest if lateral else 0.0
    scaled = {"displacement", "relative", "node_displacement", "node_rotation", "node_relative_displacement",
              "node_relative_rotation"}
    whirls = result.rotor_whirl[k] if result.rotor_whirl_ratios is not None else ["none"] * len(model.rotors)
    lines = tuple(ShaftLine(**{key: factor * value if key in scaled else value for key, value in line.items()},
                            whirl=str(whirl)) for line, whirl in zip(raw, whirls))
    return ShaftLines(mode=int(mode), frequency_hz=float(result.frequencies_hz[k]),
                      damping_ratio=float(result.damping_ratios[k]), whirl=str(result.whirl[k]),
                      whirl_ratio=float(result.whirl_ratios[k]), speed=float(result.speed),
                      axis_names=_axis_letters(model.spin_axis), lines=lines, lateral=bool(lateral))


def _node_motion(result, rotor, points, k, axes, relative):
    """``(u_a, u_b)`` and ``(theta_a, theta_b)`` of ``rotor`` at each point in mode ``k``, each (2, P),
    and the largest axial displacement ``|u_e|`` among the points."""
    from ..model.geometry import point_motion_rows

    a, b, e = axes
    u, theta, axial = [], [], [0.0]
    for p in np.asarray(points, dtype=float).reshape(-1, 3):
        motion = result._motion(rotor, relative, p) @ result.shapes[k]      # [u, theta] at S, (6,)
        rows = point_motion_rows([p, p, p], result.reference_point, [a, b, e])
        u_abe = rows @ motion
        u.append(u_abe[:2])
        axial.append(abs(u_abe[2]))
        theta.append([a @ motion[3:], b @ motion[3:]])
    return np.asarray(u, complex).reshape(-1, 2).T, np.asarray(theta, complex).reshape(-1, 2).T, max(axial)


def _markers(model, rotor, e):
    """A rotor's bearings ``(name, position)`` and disks ``(name, position, mass)`` on the axis [m]."""
    bearings = tuple((x.name, float(np.asarray(x.position, float) @ e)) for x in model.bearings
                     if x.rotor == rotor.name)
    disks = ()
    if rotor.flexible is not None:
        start = float(rotor.flexible.start @ e)
        disks = tuple((d.name, start + float(d.z), float(d.mass)) for d in rotor.flexible.disks)
    return bearings, disks


def _flexible_line(result, model, rotor, k, axes, points_per_element):
    from ..elements.shaft import Material, lateral_deflection

    shaft = rotor.flexible
    nodes = shaft.node_positions
    u, theta, axial = _node_motion(result, rotor.name, nodes, k, axes, relative=False)
    u_rel, theta_rel, _ = _node_motion(result, rotor.name, nodes, k, axes, relative=True)
    start = float(shaft.start @ axes[2])
    xi = _element_points(points_per_element)
    absolute, relative = [], []
    for left, index, length, outer, inner in shaft.mesh.elements:
        m = shaft.sections[index].material
        material = Material(m.name, m.density, m.young_modulus, m.shear_modulus)
        ends = slice(left, left + 2)
        for out, (dis, rot) in ((absolute, (u, theta)), (relative, (u_rel, theta_rel))):
            values = np.concatenate([dis[:, ends], rot[:, ends]]).T.ravel()   # per node: u_a, u_b, th_a, th_b
            out.append(lateral_deflection(length, outer, inner, material, values, xi, shear=shaft.shear))
    absolute.append(u[:, -1:])
    relative.append(u_rel[:, -1:])
    bearings, disks = _markers(model, rotor, axes[2])
    return dict(rotor=rotor.name, flexible=True, position=start + _line_z(shaft, points_per_element),
                displacement=np.concatenate(absolute, axis=1), relative=np.concatenate(relative, axis=1),
                node_position=start + np.asarray(shaft.mesh.z, float), node_displacement=u, node_rotation=theta,
                node_relative_displacement=u_rel, node_relative_rotation=theta_rel, bearings=bearings, disks=disks,
                largest=max(axial, float(np.abs(u).max())))


def _element_points(points_per_element):
    """``xi`` of the points drawn in an element: its left node and ``points_per_element`` inside."""
    return np.linspace(0.0, 1.0, points_per_element + 2)[:-1]


def _line_z(shaft, points_per_element=_POINTS_PER_ELEMENT):
    """Points of a flexible rotor's line from the shaft's start [m]: every node and
    ``points_per_element`` inside each element, increasing, shape (n,)."""
    xi = _element_points(points_per_element)
    inside = [shaft.mesh.z[left] + length * xi for left, _, length, _, _ in shaft.mesh.elements]
    return np.concatenate(inside + [[shaft.mesh.z[-1]]])


def _rigid_line(result, model, rotor, k, axes):
    e = axes[2]
    centre = np.asarray(rotor.center_of_mass, dtype=float)
    half = 0.5 * _rotor_size(rotor)[1]
    bearings, disks = _markers(model, rotor, e)
    reach = [centre @ e - half, centre @ e + half] + [z for _, z in bearings]
    ends = np.array([min(reach), max(reach)])
    position = np.linspace(ends[0], ends[1], _RIGID_POINTS)
    points = centre + np.outer(position - centre @ e, e)
    u, _, axial = _node_motion(result, rotor.name, points, k, axes, relative=False)
    u_rel, _, _ = _node_motion(result, rotor.name, points, k, axes, relative=True)
    node_u, node_theta, _ = _node_motion(result, rotor.name, points[[0, -1]], k, axes, relative=False)
    node_u_rel, node_theta_rel, _ = _node_motion(result, rotor.name, points[[0, -1]], k, axes, relative=True)
    return dict(rotor=rotor.name, flexible=False, position=position, displacement=u, relative=u_rel,
                node_position=ends, node_displacement=node_u, node_rotation=node_theta,
                node_relative_displacement=node_u_rel, node_relative_rotation=node_theta_rel,
                bearings=bearings, disks=disks, largest=max(axial, float(np.abs(u).max())))


def _rotor_size(rotor):
    """Radius and length [m] of the solid cylinder with the rotor's mass and inertias."""
    m = float(rotor.mass)
    radius = np.sqrt(2 * rotor.polar_inertia / m)
    length = np.sqrt(max(12 * rotor.diametral_inertia / m - 3 * radius ** 2, 0.0))
    return radius, max(length, 0.15 * radius)
