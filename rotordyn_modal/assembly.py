"""Assembly of the global matrices of the linearized machine (docs/theory.md §3-§7).

Coordinates ``q = [u_x, u_y, u_z, theta_x, theta_y, theta_z]``: small
translation [m] and rotation [rad] of the stator at the reference point S
(its centre of mass), model axes, followed by the coordinates of each rotor on
bearings relative to the stator (:mod:`rotordyn_modal.model.dofs`). The linearized
equation is::

    M q'' + (C + Omega G) q' + K q = f

* ``M = M_S + sum_j B_Sj M_j B_Sj^T`` (eq. 77), ``M_j = diag(m_j I, J_j)``
  about rotor j's centre of mass, ``J_j = J_d I + (J_p - J_d) e e^T``.
* ``G = sum_j B_Sj G_j B_Sj^T`` with ``G_j = diag(0, g_j)`` and
  ``g_j = -J_p,j r_j skew(e)`` per unit reference speed (eq. 52, r_j the
  speed ratio); the shift leaves it unchanged, since G_j acts on rotations only.
* ``K = sum_i B_SP_i K_i B_SP_i^T`` and likewise C for the suspensions.
* A rotor on bearings moves with ``T_j = T_S + B_RjS^T P_j E_j``: its mass and
  gyroscopic matrices enter as ``T_j^T X_j T_j``; a bearing at point P adds
  ``E_j^T P_j^T B_RjP K_b B_RjP^T P_j E_j`` (it only sees the relative motion).

* A flexible rotor (a shaft of beam elements with disks, :mod:`rotordyn_modal.model.flexible`)
  enters with its node matrices (6 per node, model axes) ``M_f, G_f, K_f``: each node's absolute
  motion is the stator's motion at the node plus its relative motion, ``T_f = T_S,nodes + N E_j``,
  and it adds ``T_f^T M_f T_f``, ``r_j T_f^T G_f T_f`` and, on the relative motion alone (a rigid
  motion strains nothing), ``E_j^T N^T K_f N E_j``. Its bearings, sensors, excitations and
  unbalances act at their nodes.
* A bearing on a pedestal acts between the rotor and the pedestal, a point mass with two lateral
  coordinates of its own held to the stator point (or the ground) by its stiffness and damping;
  a gear with ``mesh_stiffness`` adds a spring along its line of action between the two gears'
  motions at the pitch point (docs/theory.md §18).

Derivations and sign conventions: ``docs/theory.md``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .model.dofs import frame_block
from .errors import InputError
from .model.geometry import gear_mesh, point_force_column, point_motion_rows, shift_matrices, shift_matrix, skew, \
    transverse_axes

__all__ = ["Matrices", "matrices", "rigid_mass_matrix", "body_inertias", "loss_stiffness",
           "mass_matrix", "gyroscopic_matrix", "constant_matrices", "constant_stiffness_damping", "bearing_matrices", "bearing_motion", "frame_block",
           "add_rotor_body", "add_rotor_bodies", "rotor_gyroscopic", "rotor_matrices", "flexible_rotor_matrices", "dependent_bearing_matrices", "bearing_coefficients",
           "pedestal_mass", "pedestal_stiffness_damping", "mesh_matrices", "sensor_rows", "point_rows", "excitation_columns", "generalized_force", "weights", "pedestal_weights",
           "weight_force", "SPARSE_DOF", "is_large", "sparse_constant_matrices", "sparse_bearing_matrices",
           "sparse_frame_block", "sparse_rotor_body", "loss_block", "shaft_stiffness_diagonal"]

#: models of more generalized coordinates (a flexible rotor of some 600 nodes and more; 2,500
#: coordinates are 50 MB per dense ``n x n`` matrix) keep ``M, C, G, K`` sparse where they are
#: used (:func:`sparse_constant_matrices`: FRFs and unbalance responses, the mass check, the
#: support spreads; docs/theory.md §17, "Large models: what grows with n"); smaller models
#: assemble them dense, as always
SPARSE_DOF = 2500


def is_large(model) -> bool:
    """True when ``model`` has more than :data:`SPARSE_DOF` coordinates (its matrices kept sparse)."""
    return model.dofs.n > SPARSE_DOF


class Matrices(NamedTuple):
    """The global matrices, 6x6 each, about the reference point, model axes.

    Attributes
    ----------
    M : ndarray, shape (6, 6)
        Mass [kg, kg m, kg m^2].
    C : ndarray, shape (6, 6)
        Viscous damping [N s/m, ...].
    G : ndarray, shape (6, 6)
        Gyroscopic matrix per unit reference speed [kg m^2] (skew-symmetric).
    K : ndarray, shape (6, 6)
        Stiffness [N/m, N/rad, N m/m, N m/rad].
    """

    M: np.ndarray
    C: np.ndarray
    G: np.ndarray
    K: np.ndarray


def rigid_mass_matrix(mass: float, inertia, center, reference) -> np.ndarray:
    """Mass matrix of a rigid body about ``reference``: ``B_SR diag(m I, J) B_SR^T``.

    Parameters
    ----------
    mass : float
        [kg]
    inertia : array_like, shape (3, 3)
        Inertia tensor about the body's centre of mass [kg m^2].
    center, reference : array_like, shape (3,)
        Centre of mass R and reference point S [m].

    Returns
    -------
    ndarray, shape (6, 6)
    """
    local = np.zeros((6, 6))
    local[:3, :3] = mass * np.eye(3)
    local[3:, 3:] = inertia
    shift = shift_matrix(reference, center)
    return shift @ local @ shift.T


def body_inertias(model):
    """Mass, centre of mass and inertia tensor of every body (stator first).

    Returns
    -------
    list of (mass [kg], center (3,) [m], inertia (3, 3) [kg m^2])
    """
    bodies = []
    if model.stator is not None:
        bodies.append((model.stator.mass, model.stator.center_of_mass, model.stator.inertia))
    for rotor, (mass, _) in zip(model.rotors, rotor_matrices(model.spin_axis, model.rotors)):
        bodies.append((rotor.mass, rotor.center_of_mass, np.array([row[3:] for row in mass[3:]])))
    return bodies


def rotor_matrices(spin_axis, rotors) -> list:
    """Each rotor's mass matrix ``diag(m I, J)``, ``J = J_d I + (J_p - J_d) e e^T``, and its
    gyroscopic matrix per unit reference speed ``diag(0, -J_p r skew(e))`` (seed eq. 52), on
    its motion at its centre of mass.

    Written out in Python floats (a few 6 x 6 matrices are made faster so than by numpy's
    small-array calls), entry by entry the products and sums of the formulas: ``J_d * 1.0``
    on the diagonal, ``J_d * 0.0`` off it, ``c * s`` for every entry ``s`` of ``skew(e)``.

    Parameters
    ----------
    spin_axis : array_like, shape (3,)
    rotors : sequence of Rotor

    Returns
    -------
    list of (mass, gyroscopic), each nested tuples (6, 6) [kg, kg m, kg m^2]
    """
    x, y, z = (float(v) for v in np.asarray(spin_axis, dtype=float).tolist())
    outer = ((x * x, x * y, x * z), (y * x, y * y, y * z), (z * x, z * y, z * z))    # e e^T
    skew_e = ((0.0, -z, y), (z, 0.0, -x), (-y, x, 0.0))                                # geometry.skew(e)
    out = []
    for r in rotors:
        m, d = float(r.mass), float(r.diametral_inertia)
        axial, c = float(r.polar_inertia) - d, -float(r.polar_inertia) * float(r.speed_ratio)
        zm, zd = m * 0.0, d * 0.0
        inertia = [tuple((d if i == k else zd) + axial * outer[i][k] for k in range(3)) for i in range(3)]
        spin = [tuple(c * s for s in row) for row in skew_e]
        mass = ((m, zm, zm, 0.0, 0.0, 0.0), (zm, m, zm, 0.0, 0.0, 0.0), (zm, zm, m, 0.0, 0.0, 0.0),
                *((0.0, 0.0, 0.0) + row for row in inertia))
        gyroscopic = ((0.0,) * 6,) * 3 + tuple((0.0, 0.0, 0.0) + row for row in spin)
        out.append((mass, gyroscopic))
    return out


def _suspension_sum(model, attribute: str) -> np.ndarray:
    reference = model.reference_point
    total = np.zeros((6, 6))
    for suspension in model.suspensions:
        shift = shift_matrix(reference, suspension.position)
        total += shift @ getattr(suspension, attribute) @ shift.T
    return total


def suspension_block(model, suspension) -> np.ndarray:
    """One suspension's stiffness on the stator's six motions about the reference point, (6, 6)
    [N/m, ...] (its place in ``q``: :func:`~rotordyn_modal.model.dofs.frame_block`)."""
    shift = shift_matrix(model.reference_point, suspension.position)
    return shift @ suspension.stiffness_matrix @ shift.T


def add_rotor_body(out: np.ndarray, model, rotor: str, body6: np.ndarray) -> None:
    """Add ``T_j^T X T_j - T_S^T X T_S`` of a rotor on bearings to ``out`` (in place).

    ``X`` (6x6 about the reference point) is a quadratic form of the rotor's rigid
    motion; its stator block is assumed already in ``out`` (every body's share of
    the stator block is summed the way docs/theory.md §3 sums it), so only the coupling and
    the rotor's own blocks are added. Nothing for a rotor without bearings.
    """
    add_rotor_bodies([out], model, rotor, [body6])


def add_rotor_bodies(outs, model, rotor: str, bodies6) -> None:
    """:func:`add_rotor_body` of several forms ``bodies6[i]`` into ``outs[i]``, the rotor's
    motion found once (each may also be a stack: ``bodies6[i]`` (..., 6, 6) into ``outs[i]``
    (..., n, n))."""
    layout = model.dofs
    if not layout.on_bearings(rotor):
        return
    j = layout.rotors.index(rotor)
    own = layout.slices[j]
    moves = layout.local_relative_motion(rotor, layout.reference_point)     # (6, k)
    k = layout.n_frame
    for out, body6 in zip(outs, bodies6):
        if k:
            out[..., :k, own] += body6[..., :k, :] @ moves
            out[..., own, :k] += moves.T @ body6[..., :k]
        out[..., own, own] += moves.T @ body6 @ moves


def loss_stiffness(model) -> np.ndarray:
    """``sum_i eta_i B K_i B^T``: the imaginary part of the hysteretic stiffness ``K (1 + i eta)``.

    Returns
    -------
    ndarray, shape (n, n) [N/m, ...]
    """
    return frame_block(model, loss_block(model))


def loss_block(model) -> np.ndarray:
    """``sum_i eta_i B K_i B^T`` on the stator's six motions about the reference point, (6, 6)
    [N/m, ...] (:func:`loss_stiffness` places it in ``q``)."""
    reference = model.reference_point
    total = np.zeros((6, 6))
    for suspension in model.suspensions:
        if suspension.loss_factor:
            shift = shift_matrix(reference, suspension.position)
            total += suspension.loss_factor * (shift @ suspension.stiffness_matrix @ shift.T)
    return total


def rotor_gyroscopic(model, rotor) -> np.ndarray:
    """``diag(0, -J_p r skew(e))``: a rotor's gyroscopic matrix per unit reference speed
    (seed eq. 52), on its rotations, shape (6, 6) [kg m^2]."""
    return np.array(rotor_matrices(model.spin_axis, [rotor])[0][1])


def gyroscopic_matrix(model) -> np.ndarray:
    """Global gyroscopic matrix per unit reference speed (seed eq. 52 and 77).

    Returns
    -------
    ndarray, shape (n, n) [kg m^2]
    """
    polar_momentum = sum(r.polar_inertia * r.speed_ratio for r in model.rotors if r.flexible is None)
    stator = np.zeros((6, 6))
    stator[3:, 3:] = -polar_momentum * skew(model.spin_axis)
    out = frame_block(model, stator)
    for rotor in model.rotors:
        if rotor.flexible is not None:
            parts = flexible_rotor_matrices(model, rotor, kinds=("G",))
            _add_sparse(out, rotor.speed_ratio * (parts.motion.T @ parts.G @ parts.motion))
            continue
        add_rotor_body(out, model, rotor.name, rotor_gyroscopic(model, rotor))
    return out


def mass_matrix(model) -> np.ndarray:
    """Global mass matrix (seed eq. 77, with the rotors on bearings' own coordinates).

    Returns
    -------
    ndarray, shape (n, n) [kg, kg m, kg m^2]
    """
    reference = model.reference_point
    bodies = body_inertias(model)
    first_rotor = len(bodies) - len(model.rotors)
    rigid = bodies[:first_rotor] + [b for r, b in zip(model.rotors, bodies[first_rotor:]) if r.flexible is None]
    mass = frame_block(model, sum((rigid_mass_matrix(m, J, c, reference) for m, c, J in rigid), np.zeros((6, 6)))
                       if len(rigid) != len(bodies) else
                       sum(rigid_mass_matrix(m, J, c, reference) for m, c, J in rigid))
    for rotor, (m, c, J) in zip(model.rotors, bodies[first_rotor:]):
        if rotor.flexible is not None:
            parts = flexible_rotor_matrices(model, rotor, kinds=("M",))
            _add_sparse(mass, parts.motion.T @ parts.M @ parts.motion)
            continue
        add_rotor_body(mass, model, rotor.name, rigid_mass_matrix(m, J, c, reference))
    if model.dofs.pedestals:
        mass = mass + pedestal_mass(model)
    return 0.5 * (mass + mass.T)


def pedestal_mass(model) -> np.ndarray:
    """``sum_p m_p T_p^T T_p``: the bearings' pedestals as point masses, ``T_p`` (3, n) a
    pedestal's absolute translation (:meth:`Dofs.pedestal_motion`), shape (n, n) [kg]."""
    layout = model.dofs
    out = np.zeros((layout.n, layout.n))
    for bearing in model.bearings:
        if bearing.pedestal is not None:
            motion = layout.pedestal_motion(bearing.name, bearing.position)
            out += bearing.pedestal.mass * (motion.T @ motion)
    return out


def pedestal_stiffness_damping(model):
    """Stiffness and damping of the pedestals to the stator (or the ground), on each
    pedestal's two coordinates: ``P^T K_p P`` with ``P = [a, b]`` (3, 2).

    Returns
    -------
    K, C : ndarray, shape (n, n) each [N/m, N s/m]
    """
    layout = model.dofs
    K, C = np.zeros((layout.n, layout.n)), np.zeros((layout.n, layout.n))
    lateral = transverse_axes(model.spin_axis).T                                    # (3, 2)
    for bearing in model.bearings:
        if bearing.pedestal is not None:
            rows = layout.pedestal(bearing.name)
            K[rows, rows] += lateral.T @ bearing.pedestal.stiffness @ lateral
            C[rows, rows] += lateral.T @ bearing.pedestal.damping @ lateral
    return K, C


def pedestal_piece(model, bearing):
    """The diagonal of one bearing's pedestal stiffness in ``q``, (n,) [N/m], or None without
    a pedestal."""
    if bearing.pedestal is None:
        return None
    lateral = transverse_axes(model.spin_axis).T
    d = np.zeros(model.dofs.n)
    d[model.dofs.pedestal(bearing.name)] = np.diagonal(lateral.T @ bearing.pedestal.stiffness @ lateral)
    return d


def mesh_matrices(model):
    """Stiffness and damping of the gear meshes (``mesh_stiffness``, ``mesh_damping``) along
    their lines of action (docs/theory.md §18): ``k w^T w``, ``w = n^T [(T_1 - T_2) at C]``, the
    two gears' rigid motions at the pitch point C along the line of action n per coordinate.

    Returns
    -------
    K, C : ndarray, shape (n, n) each [N/m, N s/m]
    """
    layout = model.dofs
    K, C = np.zeros((layout.n, layout.n)), np.zeros((layout.n, layout.n))
    for t in model.transmissions:
        if t.mesh_stiffness is None and t.mesh_damping is None:
            continue
        w = mesh_row(model, t)
        K += (t.mesh_stiffness or 0.0) * (w.T @ w)
        C += (t.mesh_damping or 0.0) * (w.T @ w)
    return K, C


def mesh_row(model, t) -> np.ndarray:
    """``w``, (1, n): the two gears' relative motion along the line of action at the pitch point
    per coordinate (a mesh's stiffness is ``k w^T w``)."""
    layout = model.dofs
    driver, driven = model.rotor(t.driver), model.rotor(t.driven)
    mesh = gear_mesh(t, driver, driven, model.spin_axis)
    row = point_motion_rows([mesh.pitch_point], layout.reference_point, [mesh.direction])    # (1, 6)
    motions = layout.motions([_motion_key(layout, driver.name, False, mesh.driver_centre),
                              _motion_key(layout, driven.name, False, mesh.driven_centre)])
    return row @ (motions[0] - motions[1])


class FlexibleParts(NamedTuple):
    """A flexible rotor's node matrices (model axes, 6 per node, each (6 N, 6 N) or None when not
    asked for) and its nodes' motions per generalized coordinate, absolute and relative (6 N, n);
    all ``scipy.sparse`` (CSR): a node moves with its own four coordinates, the rotor's axial one
    and the casing's six."""

    M: object | None
    K: object | None
    G: object | None
    motion: object
    relative: object


def flexible_rotor_matrices(model, rotor, kinds=("M", "K", "G")) -> FlexibleParts:
    """The node matrices of a flexible rotor (:func:`rotordyn_modal.model.flexible.node_matrices`:
    G per unit spin of the rotor) and ``T_f``, its nodes' absolute motions, and ``N E_j``, their
    motions relative to the stator, per generalized coordinate.

    Parameters
    ----------
    model : Model
    rotor : Rotor
        A rotor with a shaft (on bearings).
    kinds : tuple of {'M', 'K', 'G'}

    Returns
    -------
    FlexibleParts
    """
    from .model.flexible import node_matrices

    shaft = rotor.flexible
    # the nodes' motions, made once per model and rotor and kept on the model (as its coordinates
    # are): the mass, gyroscopic and stiffness matrices and the whirl forms each read them, and
    # their sparse assembly was a third of a small model's set-up made four times over
    made = model.__dict__.setdefault("_node_motions", {})
    if made.get(rotor.name, (None,))[0] is not shaft:
        made[rotor.name] = (shaft, *_node_motions(model, rotor))
    _, motion, relative = made[rotor.name]
    matrices = dict(zip(kinds, node_matrices(shaft, shaft.mesh, kinds)))
    return FlexibleParts(M=matrices.get("M"), K=matrices.get("K"), G=matrices.get("G"), motion=motion,
                         relative=relative)


def _node_motions(model, rotor):
    """``T_f`` and ``N E_j`` of :func:`flexible_rotor_matrices` (6 N, n) each, sparse (CSR)."""
    import scipy.sparse

    shaft = rotor.flexible
    layout = model.dofs
    points = shaft.node_positions
    own = layout.slices[layout.rotors.index(rotor.name)]
    relative = _node_relative(shaft, own, layout.n)
    motion = relative
    k = layout.n_frame
    if k:
        frame = np.zeros((6 * len(points), layout.n))
        frame[:, :k] = shift_matrices(layout.reference_point, points).transpose(0, 2, 1).reshape(-1, 6)[:, :k]
        motion = (relative + scipy.sparse.csr_matrix(frame)).tocsr()
    return motion, relative


def _node_relative(shaft, own: slice, n: int):
    """``N E_j``: each node's motion ``[u, theta]`` relative to the stator per generalized
    coordinate, sparse (6 N, n): the lateral basis (:func:`~rotordyn_modal.model.flexible.lateral_basis`)
    on the rotor's coordinates ``own``, and its axial coordinate (when it has one, the last) moving
    every node along ``e`` (as ``Dofs.local_relative_motions`` at the nodes)."""
    import scipy.sparse

    from .model.flexible import lateral_basis

    lateral = lateral_basis(shaft).tocoo()
    count = shaft.mesh.n_nodes
    rows, cols, data = lateral.row, lateral.col, lateral.data
    width = own.stop - own.start
    if width % 4:
        node = np.arange(count)
        rows = np.concatenate([rows, (6 * node[:, None] + np.arange(3)).ravel()])
        cols = np.concatenate([cols, np.full(3 * count, width - 1)])
        data = np.concatenate([data, np.tile(shaft.axis, count)])
    keep = data != 0.0
    return scipy.sparse.csr_matrix((data[keep], (rows[keep], cols[keep] + own.start)), shape=(6 * count, n))


def _add_sparse(out: np.ndarray, matrix) -> None:
    """``out += matrix`` (in place) for a sparse ``matrix`` of ``out``'s shape."""
    coo = matrix.tocoo()
    coo.sum_duplicates()
    out[coo.row, coo.col] += coo.data


def _shaft_piece(model, rotor):
    """``(N E)^T K_shaft (N E)``, sparse (n, n): a flexible rotor's bending stiffness on the
    generalized coordinates. The rotor's axial coordinate (when it has one) moves every node
    alike along the axis, a rigid translation of the free shaft that strains no element: its row
    and column are zero in exact arithmetic, and are set so (the element matrices' round-off left
    ~4e-6 N/m there, which outweighed an ``axial_stiffness`` below ~1e-4 N/m). Every other entry
    is multiplied by 1.0 exactly (bit-identical)."""
    import scipy.sparse

    parts = flexible_rotor_matrices(model, rotor, kinds=("K",))
    piece = parts.relative.T @ parts.K @ parts.relative
    layout = model.dofs
    own = layout.slices[layout.rotors.index(rotor.name)]
    if (own.stop - own.start) % 4 == 0:                 # no axial coordinate
        return piece
    keep = np.ones(layout.n)
    keep[own.stop - 1] = 0.0
    mask = scipy.sparse.diags(keep, format="csr")
    return (mask @ piece @ mask).tocsr()


def shaft_stiffness(model) -> np.ndarray:
    """The flexible rotors' bending stiffness on their relative motions, (n, n) [N/m, ...]."""
    n = model.dofs.n
    K = np.zeros((n, n))
    for rotor in model.rotors:
        if rotor.flexible is not None:
            _add_sparse(K, _shaft_piece(model, rotor))
    return 0.5 * (K + K.T)


def stiffness_parts(model, speed: float | None = None) -> dict:
    """``K`` of :func:`matrices` split by where the strain energy is stored: ``'shaft'`` (the
    flexible rotors' bending, :func:`shaft_stiffness`), ``'bearings'``, ``'mounts'`` (the
    suspensions' static stiffness; their Maxwell branches are not in ``K``), ``'pedestals'`` (the
    bearings' pedestals' springs) and ``'meshes'`` (gear mesh stiffness). Only the parts the
    model has; they sum to ``matrices(model, speed).K`` (a new kind of element that adds to ``K``
    adds its part here too: ``tests/test_strain_energy.py`` checks the sum on every example).

    Parameters
    ----------
    model : Model
    speed : float, optional
        Reference speed [rad/s], needed for speed-dependent bearings.

    Returns
    -------
    dict of str -> ndarray, shape (n, n) [N/m, ...]
    """
    parts = {}
    if any(r.flexible is not None for r in model.rotors):
        parts["shaft"] = shaft_stiffness(model)
    if model.bearings:
        parts["bearings"] = bearing_matrices(model, speed)[0]
    if model.suspensions:
        parts["mounts"] = frame_block(model, _suspension_sum(model, "stiffness_matrix"))
    if model.dofs.pedestals:
        parts["pedestals"] = pedestal_stiffness_damping(model)[0]
    if any(t.mesh_stiffness is not None for t in model.transmissions):
        parts["meshes"] = mesh_matrices(model)[0]
    return parts


def bearing_matrices(model, speed: float | None = None, constant_only: bool = False,
                     dependent_only: bool = False):
    """Stiffness and damping of the bearings in the generalized space.

    Parameters
    ----------
    model : Model
    speed : float, optional
        Reference speed [rad/s]; needed for speed-dependent bearings unless ``constant_only``.
    constant_only, dependent_only : bool
        Only the bearings whose coefficients do not (do) depend on speed.

    Returns
    -------
    K, C : ndarray, shape (n, n) each
    """
    n = model.dofs.n
    K, C = np.zeros((n, n)), np.zeros((n, n))
    for rows, moves, k6, c6 in _bearings_at(model, speed, constant_only, dependent_only):
        rows, moves = _moved(rows, moves)
        K[rows] += moves.T @ k6[0] @ moves
        C[rows] += moves.T @ c6[0] @ moves
    return K, C


def _bearings_at(model, speed, constant_only: bool, dependent_only: bool):
    """Each bearing selected by ``constant_only``/``dependent_only`` (see :func:`bearing_matrices`):
    its block of ``q`` (a slice), its motion (6, k) and its 6x6 stiffness and damping at ``speed``
    [rad/s] (1, 6, 6) each; a speed-dependent one without a speed is refused."""
    for bearing in model.bearings:
        dependent = bearing.coefficients.kind != "constant"
        if (dependent and constant_only) or (not dependent and dependent_only):
            continue
        if dependent and speed is None:
            raise InputError(f"{model.source}: [bearings.{bearing.name}] has speed-dependent "
                             "coefficients: give the speed (matrices(speed=...))")
        k6, c6 = bearing_coefficients(model, bearing, [0.0 if speed is None else float(speed)])
        rows, moves = bearing_motion(model, bearing)
        yield rows, moves, k6, c6


def _moved(rows: slice, moves: np.ndarray):
    """A bearing's block of ``q`` and its motion ``moves`` (6, k) cut to the coordinates that move
    it: ``(rows, rows)`` as before where all do (a rigid rotor), else the index of those few (a
    flexible rotor's bearing moves one node's coordinates of thousands) and their columns."""
    used = np.any(moves != 0, axis=0)
    if used.all():
        return (rows, rows), moves
    index = np.arange(rows.start, rows.stop)[used]
    return np.ix_(index, index), moves[:, used]


def bearing_coefficients(model, bearing, speeds):
    """A bearing's 6x6 stiffness and damping at reference speeds ``speeds``: its coefficients
    evaluated at its own rotor's speed (speed ratio x reference speed).

    Parameters
    ----------
    model : Model
    bearing : Bearing
    speeds : array_like, shape (N,)
        Reference speeds [rad/s].

    Returns
    -------
    k6, c6 : ndarray, shape (N, 6, 6) each [N/m, N m/rad; N s/m, N m s/rad]
    """
    from .elements.bearings import evaluate

    own = model.rotor(bearing.rotor).speed_ratio * np.asarray(speeds, dtype=float)
    return evaluate(bearing.coefficients, own, f"{model.source}: [bearings.{bearing.name}]")


def dependent_bearing_matrices(model, speeds):
    """Stiffness and damping of the speed-dependent bearings at many reference speeds.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference speeds [rad/s].

    Returns
    -------
    K, C : ndarray, shape (N, n, n) each (zeros without such bearings)
    """
    speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
    n = model.dofs.n
    K, C = np.zeros((len(speeds), n, n)), np.zeros((len(speeds), n, n))
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            continue
        k6, c6 = bearing_coefficients(model, bearing, speeds)
        rows, moves = bearing_motion(model, bearing)
        K[:, rows, rows] += moves.T @ k6 @ moves
        C[:, rows, rows] += moves.T @ c6 @ moves
    return K, C


def bearing_motion(model, bearing):
    """Where a bearing's rotor coordinates sit, and the relative motion at the bearing point.

    Returns
    -------
    rows : slice
        The carried rotor's coordinates in ``q`` (on a pedestal: through the pedestal's).
    moves : ndarray, shape (6, k)
        Relative motion ``[u, theta]`` of rotor and stator (or its pedestal) at the bearing
        point per coordinate of ``rows``.
    """
    if getattr(bearing, "pedestal", None) is None:
        layout = model.dofs
        j = layout.rotors.index(bearing.rotor)
        return layout.slices[j], layout.local_relative_motion(bearing.rotor, bearing.position)
    rows, moves = model.dofs.bearing_moves(bearing.rotor, [bearing.position], [bearing.name])
    return rows, moves[0]


def matrices(model, speed: float | None = None) -> Matrices:
    """``M, C, G, K`` of the linearized global equation (docs/theory.md §7).

    Parameters
    ----------
    model : Model
    speed : float, optional
        Reference speed [rad/s], needed when bearing coefficients depend on speed.

    Returns
    -------
    Matrices
        Named tuple ``(M, C, G, K)``, each ndarray of shape (n, n) over the
        generalized coordinates ``model.dofs`` (6 x 6 without bearings).
    """
    constant = constant_matrices(model)
    if not model.speed_dependent:
        return constant
    k_b, c_b = bearing_matrices(model, speed, dependent_only=True)
    return constant._replace(K=constant.K + k_b, C=constant.C + c_b)


def constant_matrices(model) -> Matrices:
    """``M, C, G, K`` without the bearings whose coefficients depend on speed.

    Returns
    -------
    Matrices, each (n, n)
    """
    K, C = constant_stiffness_damping(model)
    return Matrices(M=mass_matrix(model), C=C, G=gyroscopic_matrix(model), K=K)


def constant_stiffness_damping(model):
    """``K`` and ``C`` of :func:`constant_matrices` (suspensions and constant bearings).

    Returns
    -------
    K, C : ndarray, shape (n, n)
    """
    K = frame_block(model, _suspension_sum(model, "stiffness_matrix"))
    C = frame_block(model, _suspension_sum(model, "damping_matrix"))
    if any(r.flexible is not None for r in model.rotors):
        K = K + shaft_stiffness(model)
    if model.bearings:
        k_b, c_b = bearing_matrices(model, constant_only=True)
        K, C = K + k_b, C + c_b
    if model.dofs.pedestals:
        k_p, c_p = pedestal_stiffness_damping(model)
        K, C = K + k_p, C + c_p
    if any(t.mesh_stiffness is not None or t.mesh_damping is not None for t in model.transmissions):
        k_m, c_m = mesh_matrices(model)
        K, C = K + k_m, C + c_m
    return K, C


def sparse_constant_matrices(model) -> Matrices:
    """:func:`constant_matrices` as ``scipy.sparse`` CSR matrices, assembled block by block from
    the same element pieces without any dense ``n x n`` array (a large model's: a flexible rotor
    couples each node to its neighbours, the casing's six motions and a rotor's axial coordinate
    only, so ``nnz`` grows as ``n``, the dense arrays as ``n^2``). Equal to the dense matrices to
    round-off (the pieces summed in another order).

    Returns
    -------
    Matrices
        Each ``scipy.sparse.csr_matrix`` of shape (n, n).
    """
    K, C = _sparse_stiffness_damping(model)
    return Matrices(M=_sparse_mass(model), C=C, G=_sparse_gyroscopic(model), K=K)


def sparse_bearing_matrices(model, speed: float | None = None, dependent_only: bool = False):
    """:func:`bearing_matrices` (at one reference ``speed`` [rad/s]) as ``scipy.sparse`` CSR
    matrices, each bearing's block at the coordinates that move it.

    Returns
    -------
    K, C : scipy.sparse.csr_matrix, shape (n, n) each
    """
    K, C = _Triplets(model.dofs.n), _Triplets(model.dofs.n)
    _add_bearings(model, K, C, speed, constant_only=False, dependent_only=dependent_only)
    return K.tocsr(), C.tocsr()


def sparse_frame_block(model, block6: np.ndarray):
    """:func:`~rotordyn_modal.model.dofs.frame_block` of one (6, 6) block (real or complex) as a
    ``scipy.sparse`` CSR matrix (n, n)."""
    out = _Triplets(model.dofs.n)
    k = model.dofs.n_frame
    out.add(range(k), range(k), np.asarray(block6)[:k, :k])
    return out.tocsr()


def sparse_rotor_body(model, rotor: str, body6):
    """:func:`add_rotor_body`'s terms (``T_j^T X T_j - T_S^T X T_S``) of a rotor on bearings as a
    ``scipy.sparse`` CSR matrix (n, n) (empty for a rotor without bearings)."""
    out = _Triplets(model.dofs.n)
    _add_rotor_body_sparse(out, model, rotor, body6)
    return out.tocsr()


def shaft_stiffness_diagonal(model) -> np.ndarray:
    """The diagonal of :func:`shaft_stiffness`, (n,) [N/m, N m/rad] (from the sparse matrix
    above :data:`SPARSE_DOF` coordinates)."""
    if is_large(model):
        K = _Triplets(model.dofs.n)
        _add_shafts(model, K)
        return K.tocsr().diagonal()
    return np.diagonal(shaft_stiffness(model))


class _Triplets:
    """Entries of an ``n x n`` matrix gathered block by block (row indices, column indices and a
    dense block each), summed into a CSR matrix at the end: never a dense ``n x n`` array."""

    def __init__(self, n: int):
        self.n = n
        self.parts = []

    def add(self, rows, cols, block) -> None:
        """Add ``block`` (len(rows), len(cols)) at ``rows`` x ``cols`` (ranges, slices or index arrays)."""
        rows, cols = (np.arange(x.start, x.stop) if isinstance(x, slice) else np.asarray(x, dtype=int)
                      for x in (rows, cols))
        block = np.asarray(block)                    # real, or complex (a Maxwell branch's stiffness)
        if rows.size and cols.size:
            self.parts.append((np.repeat(rows, len(cols)), np.tile(cols, len(rows)), block.reshape(-1)))

    def add_sparse(self, matrix) -> None:
        """Add a ``scipy.sparse`` matrix of shape (n, n)."""
        coo = matrix.tocoo()
        self.parts.append((coo.row, coo.col, coo.data))

    def tocsr(self):
        """The sum, ``scipy.sparse.csr_matrix`` (n, n) (duplicates summed, zeros left out)."""
        import scipy.sparse

        if not self.parts:
            return scipy.sparse.csr_matrix((self.n, self.n))
        rows, cols, data = (np.concatenate(x) for x in zip(*self.parts))
        keep = data != 0.0
        out = scipy.sparse.coo_matrix((data[keep], (rows[keep], cols[keep])), shape=(self.n, self.n)).tocsr()
        out.eliminate_zeros()
        return out


def _add_rotor_body_sparse(out: _Triplets, model, rotor: str, body6) -> None:
    """:func:`add_rotor_body` into triplets: a rotor on bearings' coupling and own blocks."""
    layout = model.dofs
    if not layout.on_bearings(rotor):
        return
    own = layout.slices[layout.rotors.index(rotor)]
    moves = layout.local_relative_motion(rotor, layout.reference_point)     # (6, k_j)
    body6 = np.asarray(body6, dtype=float)
    k = layout.n_frame
    if k:
        out.add(range(k), own, body6[:k, :] @ moves)
        out.add(own, range(k), moves.T @ body6[:, :k])
    out.add(own, own, moves.T @ body6 @ moves)


def _sparse_mass(model):
    """:func:`mass_matrix` as a CSR matrix (n, n)."""
    layout, reference = model.dofs, model.reference_point
    out = _Triplets(layout.n)
    bodies = body_inertias(model)
    first_rotor = len(bodies) - len(model.rotors)
    rigid = bodies[:first_rotor] + [b for r, b in zip(model.rotors, bodies[first_rotor:]) if r.flexible is None]
    k = layout.n_frame
    out.add(range(k), range(k), sum((rigid_mass_matrix(m, J, c, reference) for m, c, J in rigid),
                                    np.zeros((6, 6)))[:k, :k])
    for rotor, (m, c, J) in zip(model.rotors, bodies[first_rotor:]):
        if rotor.flexible is not None:
            parts = flexible_rotor_matrices(model, rotor, kinds=("M",))
            out.add_sparse(parts.motion.T @ parts.M @ parts.motion)
        else:
            _add_rotor_body_sparse(out, model, rotor.name, rigid_mass_matrix(m, J, c, reference))
    for bearing in model.bearings:
        if bearing.pedestal is not None:
            motion = layout.pedestal_motion(bearing.name, bearing.position)          # (3, n)
            used = np.flatnonzero(np.any(motion != 0, axis=0))
            out.add(used, used, bearing.pedestal.mass * (motion[:, used].T @ motion[:, used]))
    mass = out.tocsr()
    return (0.5 * (mass + mass.T)).tocsr()


def _sparse_gyroscopic(model):
    """:func:`gyroscopic_matrix` as a CSR matrix (n, n)."""
    out = _Triplets(model.dofs.n)
    polar_momentum = sum(r.polar_inertia * r.speed_ratio for r in model.rotors if r.flexible is None)
    k = model.dofs.n_frame
    stator = np.zeros((6, 6))
    stator[3:, 3:] = -polar_momentum * skew(model.spin_axis)
    out.add(range(k), range(k), stator[:k, :k])
    for rotor in model.rotors:
        if rotor.flexible is not None:
            parts = flexible_rotor_matrices(model, rotor, kinds=("G",))
            out.add_sparse(rotor.speed_ratio * (parts.motion.T @ parts.G @ parts.motion))
        else:
            _add_rotor_body_sparse(out, model, rotor.name, rotor_gyroscopic(model, rotor))
    return out.tocsr()


def _add_shafts(model, K: _Triplets) -> None:
    """The flexible rotors' bending stiffness (:func:`shaft_stiffness`) into triplets."""
    for rotor in model.rotors:
        if rotor.flexible is not None:
            piece = _shaft_piece(model, rotor)
            K.add_sparse(0.5 * (piece + piece.T))


def _add_bearings(model, K: _Triplets, C: _Triplets, speed, constant_only: bool, dependent_only: bool) -> None:
    """:func:`bearing_matrices` into triplets, each bearing's block at the coordinates that move it."""
    for rows, moves, k6, c6 in _bearings_at(model, speed, constant_only, dependent_only):
        used = np.any(moves != 0, axis=0)
        index, part = np.arange(rows.start, rows.stop)[used], moves[:, used]
        K.add(index, index, part.T @ k6[0] @ part)
        C.add(index, index, part.T @ c6[0] @ part)


def _sparse_stiffness_damping(model):
    """:func:`constant_stiffness_damping` as CSR matrices (n, n) each."""
    layout = model.dofs
    K, C = _Triplets(layout.n), _Triplets(layout.n)
    k = layout.n_frame
    K.add(range(k), range(k), _suspension_sum(model, "stiffness_matrix")[:k, :k])
    C.add(range(k), range(k), _suspension_sum(model, "damping_matrix")[:k, :k])
    _add_shafts(model, K)
    _add_bearings(model, K, C, None, constant_only=True, dependent_only=False)
    lateral = transverse_axes(model.spin_axis).T                                    # (3, 2)
    for bearing in model.bearings:
        if bearing.pedestal is not None:
            rows = layout.pedestal(bearing.name)
            K.add(rows, rows, lateral.T @ bearing.pedestal.stiffness @ lateral)
            C.add(rows, rows, lateral.T @ bearing.pedestal.damping @ lateral)
    for t in model.transmissions:
        if t.mesh_stiffness is None and t.mesh_damping is None:
            continue
        w = mesh_row(model, t)
        used = np.flatnonzero(w[0])
        ww = w[:, used].T @ w[:, used]
        K.add(used, used, (t.mesh_stiffness or 0.0) * ww)
        C.add(used, used, (t.mesh_damping or 0.0) * ww)
    return K.tocsr(), C.tocsr()


def sensor_rows(model, names=None, rotor_motions=None) -> np.ndarray:
    """Rows mapping ``q`` to the sensors' displacements along their directions.

    A sensor on the stator reads its point's motion; one on a rotor reads the
    rotor point's motion, or (``measure = "relative"``, a proximity probe) the
    rotor's motion relative to the stator at that point.

    Parameters
    ----------
    model : Model
    names : str or list of str, optional
        Sensor names (default all).
    rotor_motions : ndarray, shape (n_rotors, 6, n), optional
        ``Dofs.motions`` of the model's rotors (absolute), when the caller has them.

    Returns
    -------
    ndarray, shape (n_sensors, n) [m/m, m/rad]
    """
    return point_rows(model, _select(model.sensors, names, "sensor"), rotor_motions)


def point_rows(model, sensors, rotor_motions=None) -> np.ndarray:
    """Rows mapping ``q`` to displacements of points along directions, as :func:`sensor_rows`
    for any items with a sensor's ``rotor``, ``measure``, ``position`` and ``direction`` (the
    model's sensors, or points made by an analysis: a close-clearance station's two axes).

    Returns
    -------
    ndarray, shape (n_items, n) [m/m, m/rad]
    """
    layout = model.dofs
    if not sensors:
        return np.zeros((0, layout.n))
    order: dict = {}       # each body's motion (absolute or relative) found once for all its sensors
    which = [order.setdefault(_motion_key(layout, s.rotor, s.measure == "relative", s.position), len(order))
             for s in sensors]
    rows = point_motion_rows([s.position for s in sensors], layout.reference_point,
                             [s.direction for s in sensors])
    # each sensor's row times its body's motion: a stack of vector-matrix products
    known = None if rotor_motions is None else \
        {(r.name, False): motion for r, motion in zip(model.rotors, rotor_motions)}
    return np.matmul(rows[:, None, :], layout.motions(list(order), known)[which]).reshape(-1, layout.n)


def excitation_columns(model, names=None) -> np.ndarray:
    """Columns mapping the excitations' amplitudes to generalized forces.

    A force ``d`` at point P of a body is ``T_b^T B_SP [d, 0]``; a moment
    ``T_b^T [0, d]`` (``T_b`` the body's motion at S per coordinate).

    Returns
    -------
    ndarray, shape (n, n_excitations) [N/N, N m/N, ...]
    """
    excitations = _select(model.excitations, names, "excitation")
    layout = model.dofs
    reference = model.reference_point
    columns = []
    for x in excitations:
        if x.kind == "moment":
            at_reference = np.concatenate([np.zeros(3), x.direction])
        else:
            at_reference = point_force_column(x.position, reference, x.direction)
        columns.append(layout.motions([_motion_key(layout, x.rotor, False, x.position)])[0].T @ at_reference)
    return np.array(columns).reshape(-1, layout.n).T


def generalized_force(model, body: str | None, point, wrench, shift=None, motion=None) -> np.ndarray:
    """Generalized forces of wrenches ``[F, C]`` acting at ``point`` of a body.

    Parameters
    ----------
    model : Model
    body : str or None
        A rotor name, or None for the stator.
    point : array_like, shape (3,) [m]
    wrench : array_like, shape (..., 6)
        ``[F, C]`` at ``point`` [N, N m], complex allowed.
    shift, motion : ndarray, shape (6, 6) and (6, n), optional
        ``shift_matrix(S, point)`` and the body's ``Dofs.body_motion``, when the caller has them.

    Returns
    -------
    ndarray, shape (..., n)
    """
    if shift is None:
        shift = shift_matrix(model.reference_point, point)
    if motion is None:
        motion = model.dofs.body_motion(body)
    return (np.asarray(wrench) @ shift.T) @ motion


def weights(model) -> list:
    """The weight of every body under ``model.gravity``: ``(body, centre of mass, force)`` with
    ``body`` None for the stator, else the rotor's name; force [N], shape (3,), model axes.
    Empty without gravity."""
    if not np.any(model.gravity):
        return []
    out = [(None, model.stator.center_of_mass, model.stator.mass * model.gravity)] if model.stator else []
    return out + [(r.name, r.center_of_mass, r.mass * model.gravity) for r in model.rotors]


def pedestal_weights(model) -> list:
    """The weight of every bearing's pedestal under ``model.gravity``: ``(bearing name, its
    position, force)``, force ``m_p g`` [N], shape (3,), model axes. Empty without gravity."""
    if not np.any(model.gravity):
        return []
    return [(b.name, np.asarray(b.position, dtype=float), b.pedestal.mass * np.asarray(model.gravity, dtype=float))
            for b in model.bearings if b.pedestal is not None]


def weight_force(model) -> np.ndarray:
    """Generalized force of the weights of all bodies (:func:`weights`) and of the bearings'
    pedestals (:func:`pedestal_weights`, through each pedestal's absolute translation), shape
    (n,) [N, N m]."""
    total = np.zeros(model.dofs.n)
    for body, centre, force in weights(model):
        total += generalized_force(model, body, centre, np.r_[force, 0.0, 0.0, 0.0])
    for bearing, position, force in pedestal_weights(model):
        total += model.dofs.pedestal_motion(bearing, position).T @ force
    return total


def _motion_key(layout, rotor, relative: bool, position) -> tuple:
    """The :meth:`Dofs.motions` key of a point of a body: with the point on a flexible rotor
    (its node's motion), without it elsewhere (a rigid body's motion is one for all its points)."""
    if rotor is not None and layout.shaft(rotor) is not None:
        return (rotor, relative, tuple(np.asarray(position, dtype=float).tolist()))
    return (rotor, relative)


def _select(items, names, what: str):
    if names is None:
        return list(items)
    by_name = {item.name: item for item in items}
    if isinstance(names, str):
        names = [names]
    missing = [n for n in names if n not in by_name]
    if missing:
        known = f"the model's {what}s are {', '.join(by_name)}" if by_name else f"the model has no [[{what}s]]"
        raise InputError(f"unknown {what} {', '.join(map(repr, missing))}: {known}")
    return [by_name[n] for n in names]
