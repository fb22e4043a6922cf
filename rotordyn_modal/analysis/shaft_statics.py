"""Sag, shear force and bending moment along flexible shafts under static loads.

The static solution ``K q = f`` of :func:`rotordyn_modal.analysis.static.static` gives every
node's motion. Each element's end forces follow from its own stiffness and load:
``F_e = K_e q_e - f_e`` (local axes ``a, b, e``), the forces its two nodes exert on it, with
``f_e`` the element's own weight as a consistent load (its mass matrix times the rigid
translation by ``gravity``: the load vector of the distributed weight with the element's shape
functions). The section forces at the element's ends are then (docs/static.md)

* just right of its left node: ``-F_e[0:6]`` (the force and moment vector the shaft beyond
  the cut, at larger ``z``, exerts on the part before it);
* just left of its right node: ``+F_e[6:12]``.

For a uniform Euler-Bernoulli or Timoshenko element these are the exact section forces at
the nodes (the element's shape functions solve the homogeneous beam equation, so the
consistent load is the exact fixed-end load); a tapered element's are those of its
interpolation. They are reported per bending plane (:class:`ShaftStatics`): the shear force
``V = dM/dz`` and the bending moment ``M = E I u''``, sagging positive. Point loads (bearings,
disks, point masses, given loads) sit at nodes, where the section forces jump by them: such a
node has two stations, ``left`` and ``right``.

The weight of a flexible rotor is applied the same way in the static solution
(:func:`weight_force`), distributed along its shaft, its disks' and point masses' at their nodes.

The shaft's torque is not in the static solution (a rotor's spin is held by its coupling, not
by its stiffness): it follows from the loads' moments about the spin axis, each at its node
(a gear's tooth force, a belt's torque on its pulley, a given moment, and the coupling's that
holds the spin, at the rotor's centre of mass). The section's torque is minus the sum of those
before the cut. With the bending stress ``sigma = M c / I`` and the torsional shear stress
``tau = T c / J`` (``J = 2 I``; a layered section shares ``T`` by ``G J`` as it shares ``M`` by
``E I``) the section's von Mises stress is ``sqrt(sigma^2 + 3 tau^2)``, judged against the
material's ``allowable_stress``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..assembly import flexible_rotor_matrices
from ..model.flexible import _diameters, element_blocks, rotation

__all__ = ["ShaftStatics", "StressCheck", "shaft_statics", "weight_force"]


@dataclass(frozen=True)
class ShaftStatics:
    """Sag, shear force and bending moment of one flexible rotor's shaft, station by station.

    A station is a node of the shaft's mesh; a node where a point load acts (a bearing, a disk,
    a point mass, a given or transmitted load) or where the section changes has two: ``left``
    (just before it along ``e``, the end of the element before) and ``right`` (just after).
    Components are along the rotor's transverse axes ``a, b``
    (:func:`~rotordyn_modal.model.geometry.transverse_axes`, ``a x b = e``), named by
    :attr:`axis_names` (model axis letters when they are model axes).

    Attributes
    ----------
    rotor : str
    axis_names : tuple of str
        Names of ``a``, ``b`` and ``e`` (``('y', 'z', 'x')`` for a shaft along x).
    axes : ndarray, shape (3, 3)
        Rows ``a, b, e`` in model axes.
    node : ndarray of int, shape (P,)
        The station's node (0 at the shaft's start).
    side : ndarray of str, shape (P,)
        ``'left'``, ``'right'``, or ``''`` (a node with one station).
    z : ndarray, shape (P,) [m]
        Distance from the shaft's start along ``e``.
    position : ndarray, shape (P,) [m]
        Position along the spin axis in model coordinates (``point . e``), the abscissa the
        deflected shaft lines and the figures share.
    point : ndarray, shape (P, 3) [m]
        The station's point on the axis, model axes.
    sag : ndarray, shape (P, 2) [m]
        ``(u_a, u_b)`` relative to the stator: the shaft's deflection from its undeformed axis
        as the stator carries it (bending plus the bearings' deflection).
    sag_absolute : ndarray, shape (P, 2) [m]
        ``(u_a, u_b)`` relative to the ground (the stator's own motion at the station added).
    shear : ndarray, shape (P, 2) [N]
        Shear force in the plane of ``u_a`` and in that of ``u_b``: the force's component along
        ``a`` (``b``) that the part of the shaft before the cut (smaller ``z``) exerts on the part
        beyond it; ``V = dM/dz``. A shaft on two supports loaded along ``-b`` has ``V_b > 0``
        just after the first support and ``V_b < 0`` just before the second.
    moment : ndarray, shape (P, 2) [N m]
        Bending moment in the plane of ``u_a`` and in that of ``u_b``, positive when it bends the
        shaft concave towards ``+a`` (``+b``): ``M = E I u''`` (Euler-Bernoulli), sagging
        positive when ``+b`` is up. As moment vector components (of the part beyond the cut on
        the part before it, right-hand rule) they are ``M_b`` and ``-M_a``.
    outer_diameter : ndarray, shape (P,) [m]
        The section's outer diameter at the station (the outermost layer's).
    stress : ndarray, shape (P,) [Pa]
        Largest bending stress of the section, ``|M| c / I`` (for a layered section the largest
        ``E_i c_i |M| / sum(E_j I_j)`` over its tubes, plane sections remaining plane).
    torque : ndarray, shape (P,) [N m]
        Torque of the section: the moment about ``+e`` of the shaft beyond the cut on the part
        before it, from the loads' moments about the spin axis (0 without a transmitted torque
        or a given moment).
    shear_stress : ndarray, shape (P,) [Pa]
        Largest torsional shear stress of the section, ``|T| c / J`` (layered: the largest
        ``G_i c_i |T| / sum(G_j J_j)``).
    von_mises : ndarray, shape (P,) [Pa]
        Largest von Mises stress of the section, ``sqrt(sigma^2 + 3 tau^2)`` at the outer fibre
        of each tube (no stress concentration, no axial or transverse shear stress).
    allowable : ndarray, shape (P,) [Pa]
        The allowable stress of the tube that governs the section (the largest
        ``von_mises / allowable`` of its tubes); NaN where no allowable stress is given.
    utilization : ndarray, shape (P,)
        ``von_mises / allowable`` of the governing tube; NaN where no allowable stress is given.
    bearings : tuple of (str, float)
        Each bearing's name and :attr:`position` [m].
    disks : tuple of (str, float, float)
        Each disk's name, position [m] and mass [kg].
    loads : tuple of (str, str, float)
        Each point load's kind, source and position [m] (given forces, gear and belt forces).
    """

    rotor: str
    axis_names: tuple
    axes: np.ndarray
    node: np.ndarray
    side: np.ndarray
    z: np.ndarray
    position: np.ndarray
    point: np.ndarray
    sag: np.ndarray
    sag_absolute: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    outer_diameter: np.ndarray
    stress: np.ndarray
    bearings: tuple = ()
    disks: tuple = ()
    loads: tuple = ()
    torque: np.ndarray | None = None
    shear_stress: np.ndarray | None = None
    von_mises: np.ndarray | None = None
    allowable: np.ndarray | None = None
    utilization: np.ndarray | None = None

    @property
    def sag_magnitude(self) -> np.ndarray:
        """``|u|`` relative to the stator [m], shape (P,)."""
        return np.hypot(*self.sag.T)

    @property
    def shear_magnitude(self) -> np.ndarray:
        """``|V|`` [N], shape (P,)."""
        return np.hypot(*self.shear.T)

    @property
    def moment_magnitude(self) -> np.ndarray:
        """``|M|`` [N m], shape (P,)."""
        return np.hypot(*self.moment.T)

    def largest(self, quantity: str) -> tuple:
        """The largest magnitude of ``quantity`` and the station where it is.

        Parameters
        ----------
        quantity : {'sag', 'sag_absolute', 'shear', 'moment', 'stress', 'torque', 'shear_stress',
                    'von_mises'}

        Returns
        -------
        value : float
            [m], [N], [N m] or [Pa].
        station : int
            Index into the station arrays.
        """
        values = self._magnitudes(quantity)
        i = int(np.argmax(values))
        return float(values[i]), i

    def _magnitudes(self, quantity: str) -> np.ndarray:
        return {"sag": self.sag_magnitude, "sag_absolute": np.hypot(*self.sag_absolute.T),
                "shear": self.shear_magnitude, "moment": self.moment_magnitude, "stress": self.stress,
                "torque": np.abs(self.torque), "shear_stress": self.shear_stress,
                "von_mises": self.von_mises}[quantity]

    def stress_check(self) -> "StressCheck":
        """The shaft's stress verdict: its largest von Mises stress against the allowable stress
        (at the station of the largest ``von_mises / allowable``; the largest von Mises stress
        where no allowable stress is given)."""
        judged = np.isfinite(self.utilization)
        if judged.any():
            i = int(np.nanargmax(np.where(judged, self.utilization, np.nan)))
            verdict = "pass" if self.utilization[i] <= 1.0 else "fail"
        else:
            i, verdict = int(np.argmax(self.von_mises)), "not evaluated"
        return StressCheck(rotor=self.rotor, station=i, label=self.label(i, "von_mises"),
                           position=float(self.position[i]), von_mises=float(self.von_mises[i]),
                           bending=float(self.stress[i]), shear=float(self.shear_stress[i]),
                           torque=float(self.torque[i]), allowable=float(self.allowable[i]),
                           utilization=float(self.utilization[i]), verdict=verdict)

    def label(self, station: int, quantity: str | None = None) -> str:
        """``n3`` or ``n3 left``: the station's node and side; the node alone when ``quantity``
        (as :meth:`largest`) is the same on both its sides (within 1e-9 relative)."""
        side = self.side[station]
        if side and quantity is not None:
            values = {"sag": self.sag, "sag_absolute": self.sag_absolute, "shear": self.shear,
                      "moment": self.moment, "stress": self.stress[:, None], "torque": self.torque[:, None],
                      "shear_stress": self.shear_stress[:, None],
                      "von_mises": self.von_mises[:, None]}[quantity][self.node == self.node[station]]
            if np.linalg.norm(values[0] - values[-1]) <= 1e-9 * np.abs(values).max():
                side = ""
        return f"n{self.node[station]}" + (f" {side}" if side else "")

    def table(self):
        """The stations: a DataFrame with columns ``rotor, station, side, from_start_m, x_m, y_m,
        z_m, u{a}_m, u{b}_m, u_m, u{a}_abs_m, u{b}_abs_m, V{a}_N, V{b}_N, V_N, Mb{a}_Nm,
        Mb{b}_Nm, Mb_Nm, outer_diameter_m, stress_Pa, T_Nm, shear_stress_Pa, von_mises_Pa,
        allowable_Pa, utilization`` (``{a}``, ``{b}``: :attr:`axis_names`,
        each naming one plane: ``uy_m``, ``Vy_N``, ``Mby_Nm`` the sag, shear force and bending
        moment in the plane of ``u_y``; ``u``: relative to the stator, ``_abs``: to the ground;
        no letter: the magnitude)."""
        import pandas as pd

        a, b, _ = self.axis_names
        columns = {
            "rotor": [self.rotor] * len(self.z), "station": [f"n{k}" for k in self.node], "side": list(self.side),
            "from_start_m": self.z, "x_m": self.point[:, 0], "y_m": self.point[:, 1], "z_m": self.point[:, 2],
            f"u{a}_m": self.sag[:, 0], f"u{b}_m": self.sag[:, 1], "u_m": self.sag_magnitude,
            f"u{a}_abs_m": self.sag_absolute[:, 0], f"u{b}_abs_m": self.sag_absolute[:, 1],
            f"V{a}_N": self.shear[:, 0], f"V{b}_N": self.shear[:, 1], "V_N": self.shear_magnitude,
            f"Mb{a}_Nm": self.moment[:, 0], f"Mb{b}_Nm": self.moment[:, 1], "Mb_Nm": self.moment_magnitude,
            "outer_diameter_m": self.outer_diameter, "stress_Pa": self.stress, "T_Nm": self.torque,
            "shear_stress_Pa": self.shear_stress, "von_mises_Pa": self.von_mises, "allowable_Pa": self.allowable,
            "utilization": self.utilization,
        }
        return pd.DataFrame(columns)

    def plot(self, **kwargs):
        """The sag, shear force and bending moment diagram; see
        :func:`rotordyn_modal.plotting.shaft_statics.plot_shaft_statics`."""
        from ..plotting.shaft_statics import plot_shaft_statics

        return plot_shaft_statics([self], **kwargs)


@dataclass(frozen=True)
class StressCheck:
    """One flexible shaft's stress verdict (:meth:`ShaftStatics.stress_check`).

    Attributes
    ----------
    rotor, label : str
        The rotor and the governing station (``n4 left``).
    station : int
        Index into the shaft's station arrays.
    position : float [m]
        The station along the spin axis, model coordinates.
    von_mises, bending, shear : float [Pa]
        The section's von Mises, bending and torsional shear stress there.
    torque : float [N m]
    allowable : float [Pa]
        NaN when the shaft's materials give none (and no ``allowable_stress`` was given).
    utilization : float
        ``von_mises / allowable`` (NaN without an allowable stress).
    verdict : {'pass', 'fail', 'not evaluated'}
        'pass' when ``von_mises <= allowable``.
    """

    rotor: str
    station: int
    label: str
    position: float
    von_mises: float
    bending: float
    shear: float
    torque: float
    allowable: float
    utilization: float
    verdict: str


# ----------------------------------------------------------------------------------------
def weight_force(model, rotor) -> np.ndarray:
    """Generalized force of a flexible rotor's weight under ``model.gravity``, distributed: its
    node mass matrix times the rigid translation by ``gravity`` (consistent loads along the
    shaft, the disks' and point masses' weights at their nodes), shape (n,) [N, N m]."""
    parts = flexible_rotor_matrices(model, rotor, kinds=("M",))
    return parts.motion.T @ (parts.M @ _gravity_field(model.gravity, rotor.flexible.mesh.n_nodes))


def _gravity_field(gravity, count: int) -> np.ndarray:
    """``[g, 0, 0, 0]`` at each of ``count`` nodes, shape (6 count,)."""
    return np.tile(np.r_[np.asarray(gravity, dtype=float), 0.0, 0.0, 0.0], count)


def shaft_statics(model, rotor, q, loads=(), allowable_stress=None) -> ShaftStatics:
    """The stations of a flexible rotor's shaft in the static solution ``q``.

    Parameters
    ----------
    model : Model
    rotor : Rotor
        A rotor with a shaft, on bearings.
    q : ndarray, shape (n,) [m, rad]
        The static solution over ``model.dofs``.
    loads : sequence of StaticLoad
        The loads of the solution; those on this rotor at a point (not its weight, which is
        distributed, nor its coupling's moment about the spin axis) are marked as point loads.
        Their moments about the spin axis (the coupling's included) give the shaft's torque.
    allowable_stress : float, optional
        [Pa] the allowable von Mises stress of every tube of the shaft, in place of its
        materials' ``allowable_stress``.

    Returns
    -------
    ShaftStatics
    """
    from ..model.dofs import _axis_letters

    shaft = rotor.flexible
    count = shaft.mesh.n_nodes
    parts = flexible_rotor_matrices(model, rotor, kinds=())
    R = rotation(shaft.axis)
    relative = _local(R, (parts.relative @ q).reshape(count, 6))
    absolute = _local(R, (parts.motion @ q).reshape(count, 6))
    ends = _end_forces(shaft, relative, R @ np.asarray(model.gravity, dtype=float))
    point_loads = [x for x in loads if x.body == rotor.name and x.kind not in ("weight", "coupling")]
    spin = _spin_moments(shaft, [x for x in loads if x.body == rotor.name and x.kind != "weight"])
    sections = [_section(shaft, i) for i in range(len(shaft.mesh.elements))]
    marked = _loaded_nodes(model, rotor, point_loads) | set(np.flatnonzero(spin).tolist())
    rows = _stations(count, marked, sections)
    node, element, end = (np.array(column, dtype=int) for column in zip(*rows))   # end 0: left, 1: right
    forces = ends[element, end]                        # (P, 6): force, moment of beyond on before
    rigidity, reach, outer = (np.array(column) for column in zip(*(sections[e][k] for e, k in zip(element, end))))
    # per plane (a: u_a, b: u_b): V = dM/dz, M = E I u'' (theta_b = u_a', theta_a = -u_b')
    shear, moment = -forces[:, :2], np.column_stack([forces[:, 4], -forces[:, 3]])
    # the part before the cut holds: a station after its node (end 0) has the node's moment on it
    before = np.concatenate([[0.0], np.cumsum(spin)])
    torque = 0.0 - before[node + (end == 0)]      # 0.0 - : no -0.0 in the tables
    stresses = _stresses(np.hypot(*moment.T), torque, [_tubes(shaft, e, k) for e, k in zip(element, end)],
                         allowable_stress)
    points = shaft.point(shaft.mesh.z[node])
    e = shaft.axis
    return ShaftStatics(
        rotor=rotor.name, axis_names=_axis_letters(e), axes=R, node=node,
        side=np.array([side for _, _, side in _sides(rows)], dtype=object), z=shaft.mesh.z[node],
        position=points @ e, point=points, sag=relative[node, :2], sag_absolute=absolute[node, :2], shear=shear,
        moment=moment, outer_diameter=outer, stress=np.hypot(*moment.T) * reach / rigidity,
        bearings=tuple((b.name, float(np.asarray(b.position, dtype=float) @ e)) for b in model.bearings_of(rotor.name)),
        disks=tuple((d.name, float(shaft.point(d.z) @ e), d.mass) for d in shaft.disks),
        loads=tuple((x.kind, x.source, float(np.asarray(x.point) @ e)) for x in point_loads),
        torque=torque, **stresses)


def _spin_moments(shaft, loads) -> np.ndarray:
    """Moment about the spin axis [N m] of ``loads`` (StaticLoad) at each node, shape (N,): a
    load at the node nearest its point's projection on the axis (as the static solution places
    it); about any point of the axis, ``(moment + (point - start) x force) . e``."""
    out = np.zeros(shaft.mesh.n_nodes)
    for x in loads:
        point = np.asarray(x.point, dtype=float)
        arm = np.cross(point - shaft.start, np.asarray(x.force, dtype=float))
        out[shaft.mesh.node(min(max(shaft.z_of(point), 0.0), shaft.length))] += \
            float((np.asarray(x.moment, dtype=float) + arm) @ shaft.axis)
    scale = np.abs(out).max(initial=0.0)
    return np.where(np.abs(out) > 1e-12 * scale, out, 0.0)


def _tubes(shaft, index: int, end: int) -> tuple:
    """``(E, G, c, I, J, allowable)`` [Pa, Pa, m, m^4, m^4, Pa or NaN] of each tube of element
    ``index``'s section at its ``end`` (0 left, 1 right): the section's own and its layers."""
    out = []
    for outer, inner, material in _tube_list(shaft, index):
        o, i = float(outer[end]), float(inner[end])
        second = np.pi / 64.0 * (o ** 4 - i ** 4)
        allowable = material.allowable_stress if material.allowable_stress is not None else np.nan
        out.append((material.young_modulus, material.shear_modulus, o / 2.0, second, 2.0 * second, allowable))
    return tuple(out)


def _stresses(moment, torque, tubes, allowable_stress=None) -> dict:
    """Per station: the largest torsional shear stress, the largest von Mises stress and the
    governing tube's allowable stress and utilization (arrays (P,), see :class:`ShaftStatics`).

    ``moment`` (P,) [N m] ``|M|``, ``torque`` (P,) [N m], ``tubes`` per station (:func:`_tubes`);
    each tube takes ``E_i I_i / sum(E I)`` of the moment and ``G_i J_i / sum(G J)`` of the torque,
    so ``sigma_i = E_i c_i |M| / sum(E I)`` and ``tau_i = G_i c_i |T| / sum(G J)``."""
    count = len(tubes)
    shear, mises, allowable, utilization = (np.full(count, np.nan) for _ in range(4))
    for p, (m, t, section) in enumerate(zip(moment, torque, tubes)):
        E, G, c, second, polar, limit = (np.array(column, dtype=float) for column in zip(*section))
        if allowable_stress is not None:
            limit = np.full_like(limit, float(allowable_stress))
        sigma = E * c * abs(m) / np.sum(E * second)
        tau = G * c * abs(t) / np.sum(G * polar)
        vm = np.sqrt(sigma ** 2 + 3.0 * tau ** 2)
        shear[p], mises[p] = tau.max(), vm.max()
        ratio = vm / limit
        if np.isfinite(ratio).any():
            k = int(np.nanargmax(ratio))
            allowable[p], utilization[p] = limit[k], ratio[k]
    return {"shear_stress": shear, "von_mises": mises, "allowable": allowable, "utilization": utilization}


def _loaded_nodes(model, rotor, point_loads) -> set:
    """The nodes of a flexible rotor where a point load acts: bearings, disks, point masses and
    ``point_loads``."""
    shaft = rotor.flexible
    node = shaft.mesh.node
    return ({node(shaft.z_of(b.position)) for b in model.bearings_of(rotor.name)}
            | {node(d.z) for d in shaft.disks} | {node(p.z) for p in shaft.point_masses}
            | {node(shaft.z_of(x.point)) for x in point_loads})


def _local(R, motions) -> np.ndarray:
    """Node motions ``[u, theta]`` (N, 6), model axes -> local axes ``a, b, e``."""
    return np.hstack([motions[:, :3] @ R.T, motions[:, 3:] @ R.T])


def _end_forces(shaft, local, gravity) -> np.ndarray:
    """Section force and moment ``[V_a, V_b, N, M_a, M_b, T]`` at both ends of every element,
    shape (elements, 2, 6): ``-F[:6]`` at its left end, ``+F[6:]`` at its right end, with
    ``F = K_e q_e - f_e`` the forces its nodes exert on it (local axes)."""
    rigid = np.r_[gravity, 0.0, 0.0, 0.0, gravity, 0.0, 0.0, 0.0]    # the translation by g at both nodes
    out = np.empty((len(shaft.mesh.elements), 2, 6))
    for i, ((left, *_), (M, K, _)) in enumerate(zip(shaft.mesh.elements, element_blocks(shaft, shaft.mesh))):
        F = K @ local[left:left + 2].reshape(12) - M @ rigid
        out[i, 0], out[i, 1] = -F[:6], F[6:]
    return out


def _tube_list(shaft, index: int) -> list:
    """``(outer (2,), inner (2,), material)`` of each tube of element ``index``: its section's
    own and its layers', diameters [m] at the element's left and right ends."""
    left, section_index, _, outer, inner = shaft.mesh.elements[index]
    section = shaft.sections[section_index]
    z0, z1 = float(shaft.mesh.z[left]), float(shaft.mesh.z[left + 1])
    start = float(shaft.ends[section_index])
    return [(outer, inner, section.material)] + [
        (_diameters(layer.outer, section.length, start, z0, z1), _diameters(layer.inner, section.length, start, z0, z1),
         layer.material) for layer in section.layers]


def _section(shaft, index: int) -> tuple:
    """``(sum E I [N m^2], largest E c [Pa m], outer diameter [m])`` of element ``index``'s
    section at its left and at its right end: its tube and its section's layers."""
    tubes = _tube_list(shaft, index)
    out = []
    for end in (0, 1):
        rigidity = sum(t.young_modulus * np.pi / 64.0 * (o[end] ** 4 - i[end] ** 4) for o, i, t in tubes)
        reach = max(t.young_modulus * o[end] / 2.0 for o, i, t in tubes)
        out.append((rigidity, reach, max(o[end] for o, _, _ in tubes)))
    return tuple(out)


def _stations(count: int, marked, sections) -> list:
    """``(node, element, end)`` of every station: a node's left station is the end (1) of the
    element before it, its right station the start (0) of the element after; one station at a
    node that carries no point load and where the section does not change."""
    rows = []
    for k in range(count):
        before, after = k - 1, k
        if k == 0:
            rows.append((k, after, 0))
        elif k == count - 1:
            rows.append((k, before, 1))
        elif k in marked or sections[before][1] != sections[after][0]:
            rows += [(k, before, 1), (k, after, 0)]
        else:
            rows.append((k, after, 0))
    return rows


def _sides(rows) -> list:
    """The rows of :func:`_stations` with their side: ``left``/``right`` where a node has two."""
    counts = {}
    for k, _, _ in rows:
        counts[k] = counts.get(k, 0) + 1
    return [(k, e, ("left" if end == 1 else "right") if counts[k] == 2 else "") for k, e, end in rows]
