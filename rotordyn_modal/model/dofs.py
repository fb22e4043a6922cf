"""Generalized coordinates: the stator's six motions, then those of each rotor on bearings.

``q = [q_S, p_1, p_2, ...]``:

* ``q_S = [u_x, u_y, u_z, theta_x, theta_y, theta_z]``, the small motion of the
  stator at the reference point S (model axes). Without a stator the rotors
  ride on a massless frame with these six motions; without a stator but with
  bearings the frame is the ground and ``q_S`` is absent.
* ``p_j`` for each rotor on bearings: its motion *relative to the stator* at
  its centre of mass R_j, ``[u_a, u_b, (u_e,) theta_a, theta_b]`` along the
  transverse axes ``a, b`` of :func:`~rotordyn_modal.model.geometry.transverse_axes`
  (and the spin axis ``e`` when a bearing gives an axial stiffness). The spin
  itself is fixed by the speed ratio.
* ``p_j`` for a *flexible* rotor (one with a shaft, :mod:`rotordyn_modal.model.flexible`): per
  node ``k`` of its mesh (from the shaft's start, ``k = 0, 1, ...``) the node's motion relative
  to the stator ``[u_a, u_b, theta_a, theta_b]`` (names ``ROTOR.nK.ua`` ... ``ROTOR.nK.rb``, with
  model axis letters for ``a, b`` when they are model axes: ``pump.n3.uy``), then ``ROTOR.ue``
  when a bearing gives an axial stiffness: one axial motion of the whole rotor (the shaft is
  rigid axially). A station's motion on a flexible rotor is its node's motion: the relative
  motion ``N_P`` (6 x k_j) at a point P of the axis is that of the node at P; written as a
  rigid motion at S it is ``B_PS^T N_P`` (the motion of a rigid body that moves as the node).
  Where no point is named (a "body motion", :meth:`Dofs.body_motion`) a flexible rotor's
  motion is that of its node nearest its centre of mass.
* then, for each bearing on a pedestal (``pedestal_mass``), in model order: the pedestal's
  translation relative to the stator point at the bearing along ``a`` and ``b`` (names
  ``BEARING.pedestal.ua``, ``BEARING.pedestal.ub``, axis letters as above:
  ``DE.pedestal.uy``). It moves with the stator along the spin axis and does not turn.

Every body's small rigid motion, written at S, is a linear map of ``q``:
``T_stator = [I, 0]`` and, for rotor j, ``T_j = T_stator + B_RjS^T P_j E_j``
(``P_j`` the 6 x k_j basis of its relative motions at R_j, ``E_j`` picking
``p_j`` out of ``q``). The global matrices are ``sum_b T_b^T X_b T_b``; a
rotor without bearings has ``T_j = T_stator``, so a model without bearings
has exactly the six coordinates and the matrices of docs/theory.md §3-§6.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .geometry import shift_matrices, transverse_axes

__all__ = ["Dofs", "dofs", "frame_block"]


@dataclass(frozen=True)
class Dofs:
    """The generalized coordinates of a model.

    Attributes
    ----------
    names : tuple of str
        One per coordinate: ``stator.ux`` ... ``stator.rz``, then ``ROTOR.uy`` ...
        (axis letters of the model axes, or ``a``, ``b``, ``e`` for an inclined spin axis).
    reference_point : ndarray, shape (3,) [m]
    frame : {'stator', 'frame', 'ground'}
        What the rotors' bearings (and rigidly attached rotors) sit on.
    rotors : tuple of str
        Rotors on bearings, in model order.
    slices : tuple of slice
        Where each of those rotors' coordinates sit in ``q``.
    bases : tuple of ndarray, each shape (6, k_j)
        ``P_j``: relative motion ``[u, theta]`` at the rotor's centre of mass per coordinate.
    centres : tuple of ndarray, each shape (3,) [m]
        Centres of mass of those rotors.
    shafts : tuple
        Each of those rotors' :class:`~rotordyn_modal.model.flexible.Shaft` or None (empty when
        all are rigid).
    pedestals : tuple of (str, slice)
        Each bearing on a pedestal and where its two coordinates sit.
    spin_axis : ndarray, shape (3,)
    """

    names: tuple
    reference_point: np.ndarray
    frame: str
    rotors: tuple = ()
    slices: tuple = ()
    bases: tuple = ()
    centres: tuple = ()
    shafts: tuple = ()
    pedestals: tuple = ()
    spin_axis: np.ndarray | None = None

    @property
    def n(self) -> int:
        """Number of generalized coordinates."""
        return len(self.names)

    @property
    def n_frame(self) -> int:
        """6 when the stator (or the massless frame) moves, 0 on the ground."""
        return 0 if self.frame == "ground" else 6

    def on_bearings(self, rotor: str) -> bool:
        """True when ``rotor`` has coordinates of its own."""
        return rotor in self.rotors

    def frame_motion(self) -> np.ndarray:
        """``T_stator``: the stator's motion ``[u, theta]`` at S per coordinate, shape (6, n)."""
        return np.eye(6, self.n) if self.n_frame else np.zeros((6, self.n))

    def relative_motion(self, rotor: str) -> np.ndarray:
        """Motion of ``rotor`` relative to the stator, as a rigid motion at S, shape (6, n).

        Zero for a rotor without bearings.
        """
        return self.motions([(rotor, True)])[0]

    def local_relative_motion(self, rotor: str, point) -> np.ndarray:
        """``B_RP^T P_j``: relative motion at ``point`` per coordinate of ``rotor``, shape (6, k_j)."""
        return self.local_relative_motions(rotor, [point])[0]

    def local_relative_motions(self, rotor: str, points) -> np.ndarray:
        """:meth:`local_relative_motion` at each of ``points`` (P, 3), made together, (P, 6, k_j)."""
        j = self.rotors.index(rotor)
        if self.shafts and self.shafts[j] is not None:
            return _node_motions(self.shafts[j], self.bases[j].shape[1], points)
        return shift_matrices(self.centres[j], points).transpose(0, 2, 1) @ self.bases[j]

    def pedestal(self, bearing: str) -> slice | None:
        """Where the pedestal of ``bearing`` has its two coordinates in ``q`` (None: no pedestal)."""
        return dict(self.pedestals).get(bearing)

    def bearing_moves(self, rotor: str, positions, bearings) -> tuple[slice, np.ndarray]:
        """The motion across each bearing of ``rotor``: the rotor's motion at its point relative
        to the stator, less its pedestal's translation (when it stands on one).

        Parameters
        ----------
        rotor : str
        positions : array_like, shape (P, 3) [m]
        bearings : sequence of str
            The bearings' names, in the order of ``positions``.

        Returns
        -------
        rows : slice
            The coordinates the motions act on: the rotor's, through its bearings' pedestals.
        moves : ndarray, shape (P, 6, width)
            ``[u, theta]`` across each bearing per coordinate of ``rows``.
        """
        own = self.slices[self.rotors.index(rotor)]
        moves = self.local_relative_motions(rotor, positions)
        stands = [(p, self.pedestal(b)) for p, b in enumerate(bearings) if self.pedestal(b) is not None]
        if not stands:
            return own, moves
        rows = slice(own.start, max(where.stop for _, where in stands))
        wide = np.zeros(moves.shape[:2] + (rows.stop - rows.start,))
        wide[..., :own.stop - own.start] = moves
        lateral = -transverse_axes(self.spin_axis).T     # (3, 2): the pedestal's translation per coordinate
        for p, where in stands:
            wide[p, :3, where.start - rows.start:where.stop - rows.start] = lateral
        return rows, wide

    def pedestal_motion(self, bearing: str, point) -> np.ndarray:
        """The absolute translation of a bearing's pedestal at ``point`` per coordinate, (3, n) [m/m]:
        the stator's at the point plus its own lateral translation."""
        out = np.zeros((3, self.n))
        k = self.n_frame
        if k:
            out[:, :k] = shift_matrices(self.reference_point, [point])[0].T[:3, :k]
        out[:, self.pedestal(bearing)] = transverse_axes(self.spin_axis).T
        return out

    def shaft(self, rotor: str):
        """The flexible rotor's :class:`~rotordyn_modal.model.flexible.Shaft`, or None (rigid, or
        not on bearings)."""
        if not self.shafts or rotor not in self.rotors:
            return None
        return self.shafts[self.rotors.index(rotor)]

    def station(self, rotor: str, point=None) -> np.ndarray:
        """The node of a flexible rotor at ``point`` (default: nearest its centre of mass), (3,) [m]."""
        shaft = self.shafts[self.rotors.index(rotor)]
        target = self.centres[self.rotors.index(rotor)] if point is None else point
        return shaft.point(shaft.mesh.z[shaft.mesh.node(shaft.z_of(target))])

    def motion(self, body: str | None = None, relative: bool = False) -> np.ndarray:
        """:meth:`relative_motion` of ``body`` when ``relative``, else its :meth:`body_motion`."""
        return self.motions([(body, relative)])[0]

    def body_motion(self, body: str | None = None, point=None) -> np.ndarray:
        """Motion ``[u, theta]`` at S of the stator (``None``/'stator') or of a rotor, shape (6, n)
        (of a flexible rotor: as its node at ``point`` moves, see the module docstring)."""
        return self.motions([(body, False) if point is None else (body, False, tuple(point))])[0]

    def motions(self, keys, known=None) -> np.ndarray:
        """:meth:`motion` of each ``(body, relative)`` or ``(body, relative, point)`` key, shape
        (K, 6, n), made together (``point`` (3,) [m]: the station of a flexible rotor whose
        motion is meant; ignored for the stator and rigid rotors).

        A body's motion is the frame's (the identity on the frame's coordinates), plus on its
        own coordinates its relative motion ``B_RP^T P_j`` at S (added to the frame's zeros:
        ``0.0 + x``); a relative motion is ``B_RP^T P_j`` alone, zero for the stator and for a
        rotor without bearings. ``known``: a dict of some keys' motions the caller has.
        """
        out = np.zeros((len(keys), 6, self.n))
        k = self.n_frame
        for i, key in enumerate(keys):
            body, relative, point = (*key, None)[:3]
            if known is not None and key in known:
                out[i] = known[key]
                continue
            if not relative:
                out[i, :, :k] = _EYE6[:, :k]
            if body is not None and body != "stator" and self.on_bearings(body):
                own = self.slices[self.rotors.index(body)]
                if self.shaft(body) is not None:   # the node's motion, as a rigid motion at S
                    node = self.station(body, point)
                    local = shift_matrices(node, self.reference_point)[0].T @ self.local_relative_motion(body, node)
                else:
                    local = self.local_relative_motion(body, self.reference_point)
                if relative:
                    out[i, :, own] = local
                else:
                    out[i, :, own] += local
        return out


def dofs(model) -> Dofs:
    """The generalized coordinates of ``model`` (see the module docstring)."""
    frame = "stator" if model.stator is not None else ("ground" if model.bearings else "frame")
    names = [f"{'frame' if frame == 'frame' else 'stator'}.{kind}{axis}"
             for kind in "ur" for axis in "xyz"] if frame != "ground" else []
    letters = _axis_letters(model.spin_axis)
    rotors, slices, bases, centres, shafts = [], [], [], [], []
    for rotor in model.rotors:
        mine = [b for b in model.bearings if b.rotor == rotor.name]
        if not mine:
            continue
        axial = any(b.coefficients.axial for b in mine)
        if rotor.flexible is not None:
            basis, labels = _flexible_basis(rotor.flexible, axial, letters)
        else:
            basis, labels = _relative_basis(model.spin_axis, axial, letters)
        slices.append(slice(len(names), len(names) + basis.shape[1]))
        names += [f"{rotor.name}.{label}" for label in labels]
        rotors.append(rotor.name)
        bases.append(basis)
        centres.append(np.asarray(rotor.center_of_mass, dtype=float))
        shafts.append(rotor.flexible)
    pedestals = []
    for bearing in model.bearings:
        if getattr(bearing, "pedestal", None) is not None:
            pedestals.append((bearing.name, slice(len(names), len(names) + 2)))
            names += [f"{bearing.name}.pedestal.u{letters[0]}", f"{bearing.name}.pedestal.u{letters[1]}"]
    return Dofs(names=tuple(names), reference_point=np.asarray(model.reference_point, dtype=float),
                frame=frame, rotors=tuple(rotors), slices=tuple(slices), bases=tuple(bases),
                centres=tuple(centres), shafts=tuple(shafts) if any(s is not None for s in shafts) else (),
                pedestals=tuple(pedestals), spin_axis=np.asarray(model.spin_axis, dtype=float))


def _flexible_basis(shaft, axial: bool, letters):
    """A flexible rotor's ``P_j`` at its first node (6, k) (only its width is used: see
    :func:`_node_motions`) and its coordinate labels: 4 per node, then the axial one."""
    count = shaft.mesh.n_nodes
    labels = [f"n{k}.{kind}{letters[axis]}" for k in range(count) for kind, axis in
              (("u", 0), ("u", 1), ("r", 0), ("r", 1))]
    if axial:
        labels.append(f"u{letters[2]}")
    return _node_motions(shaft, len(labels), [shaft.start])[0], labels


def _node_motions(shaft, width: int, points) -> np.ndarray:
    """``N_P``: the relative motion ``[u, theta]`` of the node at each point per coordinate of
    the flexible rotor (node ``k``: ``u = a u_a + b u_b (+ e u_e)``, ``theta = a theta_a + b
    theta_b``), shape (P, 6, width)."""
    a, b = transverse_axes(shaft.axis)
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.zeros((len(points), 6, width))
    for p, point in enumerate(points):
        k = 4 * shaft.mesh.node(shaft.z_of(point))
        out[p, :3, k], out[p, :3, k + 1], out[p, 3:, k + 2], out[p, 3:, k + 3] = a, b, a, b
    if width % 4:
        out[:, :3, -1] = shaft.axis
    return out


def _relative_basis(spin_axis, axial: bool, letters):
    """``P_j`` (6, k) and the coordinate labels of a rotor on bearings."""
    a, b = transverse_axes(spin_axis)
    e = np.asarray(spin_axis, dtype=float)
    columns = [np.r_[a, 0, 0, 0], np.r_[b, 0, 0, 0]]
    labels = [f"u{letters[0]}", f"u{letters[1]}"]
    if axial:
        columns.append(np.r_[e, 0, 0, 0])
        labels.append(f"u{letters[2]}")
    columns += [np.r_[0, 0, 0, a], np.r_[0, 0, 0, b]]
    labels += [f"r{letters[0]}", f"r{letters[1]}"]
    return np.array(columns).T, labels


def _axis_letters(spin_axis) -> tuple[str, str, str]:
    """Names of the axes a, b, e: model axis letters when they are model axes."""
    axes = np.vstack([transverse_axes(spin_axis), spin_axis])
    if np.all(np.isclose(np.abs(axes).max(axis=1), 1.0, rtol=0, atol=1e-12)):
        return tuple("xyz"[int(np.argmax(np.abs(row)))] for row in axes)
    return ("a", "b", "e")


def frame_block(model, block6: np.ndarray) -> np.ndarray:
    """A 6x6 matrix on the stator's motion placed in the ``n x n`` generalized space.

    Parameters
    ----------
    model : Model
    block6 : ndarray, shape (..., 6, 6)

    Returns
    -------
    ndarray, shape (..., n, n) (zeros when the frame is the ground)
    """
    layout = model.dofs
    out = np.zeros(block6.shape[:-2] + (layout.n, layout.n), dtype=block6.dtype)
    k = layout.n_frame
    out[..., :k, :k] = block6[..., :k, :k]
    return out


_EYE6 = np.eye(6)
_EYE6.flags.writeable = False
