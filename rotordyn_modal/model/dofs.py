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
    """

    names: tuple
    reference_point: np.ndarray
    frame: str
    rotors: tuple = ()
    slices: tuple = ()
    bases: tuple = ()
    centres: tuple = ()

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
        return shift_matrices(self.centres[j], points).transpose(0, 2, 1) @ self.bases[j]

    def motion(self, body: str | None = None, relative: bool = False) -> np.ndarray:
        """:meth:`relative_motion` of ``body`` when ``relative``, else its :meth:`body_motion`."""
        return self.motions([(body, relative)])[0]

    def body_motion(self, body: str | None = None) -> np.ndarray:
        """Motion ``[u, theta]`` at S of the stator (``None``/'stator') or of a rotor, shape (6, n)."""
        return self.motions([(body, False)])[0]

    def motions(self, keys, known=None) -> np.ndarray:
        """:meth:`motion` of each ``(body, relative)`` key, shape (K, 6, n), made together.

        A body's motion is the frame's (the identity on the frame's coordinates), plus on its
        own coordinates its relative motion ``B_RP^T P_j`` at S (added to the frame's zeros:
        ``0.0 + x``); a relative motion is ``B_RP^T P_j`` alone, zero for the stator and for a
        rotor without bearings. ``known``: a dict of some keys' motions the caller has.
        """
        out = np.zeros((len(keys), 6, self.n))
        k = self.n_frame
        for i, (body, relative) in enumerate(keys):
            if known is not None and (body, relative) in known:
                out[i] = known[body, relative]
                continue
            if not relative:
                out[i, :, :k] = _EYE6[:, :k]
            if body is not None and body != "stator" and self.on_bearings(body):
                own = self.slices[self.rotors.index(body)]
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
    rotors, slices, bases, centres = [], [], [], []
    for rotor in model.rotors:
        mine = [b for b in model.bearings if b.rotor == rotor.name]
        if not mine:
            continue
        axial = any(b.coefficients.axial for b in mine)
        basis, labels = _relative_basis(model.spin_axis, axial, letters)
        slices.append(slice(len(names), len(names) + basis.shape[1]))
        names += [f"{rotor.name}.{label}" for label in labels]
        rotors.append(rotor.name)
        bases.append(basis)
        centres.append(np.asarray(rotor.center_of_mass, dtype=float))
    return Dofs(names=tuple(names), reference_point=np.asarray(model.reference_point, dtype=float),
                frame=frame, rotors=tuple(rotors), slices=tuple(slices), bases=tuple(bases),
                centres=tuple(centres))


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
