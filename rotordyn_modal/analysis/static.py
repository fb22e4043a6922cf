"""Static analysis: the machine's displacement and support reactions under static loads.

The loads are the weights under ``model.gravity``, forces and moments given at points of the
stator or of a rotor, and the tooth (gear) or strand (belt) forces of the torque each
transmission carries at an operating point. The static stiffness ``K`` (suspensions at zero
frequency, bearings at the operating speed) is solved for the generalized coordinates,
``K q = f`` (docs/static.md):

* a rubber mount's Maxwell branches add ``K_b i w tau_b / (1 + i w tau_b)``, nothing at
  ``w = 0``: its static stiffness is ``stiffness`` alone (its loss factor too adds nothing
  real);
* a bearing's stiffness at the carried rotor's own speed (constant, or its table's row);
  a plain journal bearing holds its journal with the light-load film (a spring of
  ``k = pi viscosity |speed| D L**3 / (8 c**3)`` turned by 90 degrees, the short bearing's
  limit at small eccentricity: a rotor on one or two journals, or on three or more whose loads are
  all given);
  each journal's eccentricity at its load is reported from the full short-bearing solution;
  a journal whose load the model solves at each speed (a rigid or flexible rotor on three or more
  journals, with or without pedestals: ``JournalData.load_over_speed``) stands instead on its **loaded film**, the
  secant of the short bearing at its load (the spring that moves the journal to the film's
  offset ``c eps (cos phi x + sin phi e x x)`` under that load), iterated until the loads it
  carries are those it was drawn at: under the weights alone the rotor's solved loads
  (``journal_bearing.rigid_rotor_journal_loads``), so that ``static`` and the analyses stand the
  rotor on the same films (:func:`_loaded_films`); a journal whose given load is fixed in such a
  rotor's split (``JournalData.fixed_load``) is that fixed force, no spring (:func:`_fixed_journal_forces`);
* each rotor's spin is held at its speed by a drive or a load outside the model (a coupling):
  the moment about its spin axis of the loads on it is taken there (a ``coupling`` load), not
  by its bearings.

A flexible rotor's shaft adds its bending stiffness, and its weight is distributed along it
(consistent loads, :func:`rotordyn_modal.analysis.shaft_statics.weight_force`); a load on it acts
at the node at its point. Its sag, shear force and bending moment station by station come from
the elements' end forces (:mod:`rotordyn_modal.analysis.shaft_statics`), in
``StaticResult.shafts``; rigid rotors have none.

A bearing on a pedestal acts between its rotor and the pedestal, a point mass on its own springs
(``pedestal_stiffness``) to the stator or the ground: the pedestal's weight ``m_p g`` is a load
(kind ``pedestal``), as in every mass of ``M`` (``M a_g``, what ``simulate`` applies), and the
pedestal's spring force is a reaction of kind ``pedestal``.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import _arguments
from .shaft_statics import shaft_statics, weight_force
from ..assembly import (bearing_motion, generalized_force, pedestal_stiffness_damping, pedestal_weights, shaft_stiffness,
                        weights)
from ..elements.bearings import evaluate
from ..errors import InputError, ModelWarning
from ..linear_system import static_solution
from ..model._table import LARGEST, visible
from ..model.dofs import frame_block
from ..model.flexible import STATION_TOLERANCE
from ..model.geometry import shift_matrix, skew, transverse_axes
from ..units import check_system, to_system, unit_label

__all__ = ["static", "StaticResult", "StaticLoad", "SupportReaction", "transmission_torques",
           "DEFAULT_PRESSURE_ANGLE"]

#: pressure angle of a gear [deg] when the model gives none (the standard involute's)
DEFAULT_PRESSURE_ANGLE = 20.0


@dataclass(frozen=True)
class StaticLoad:
    """A static load on one body.

    Attributes
    ----------
    kind : {'weight', 'pedestal', 'force', 'gear', 'belt', 'coupling'}
        ``pedestal``: the weight of a bearing's pedestal.
    source : str
        What applies it: the body (weight), the bearing (its pedestal's weight), ``force[i]``,
        the transmission ``DRIVER->DRIVEN``, or the rotor whose coupling holds its spin.
    body : str or None
        The rotor it acts on, None for the stator (or the frame) and for a pedestal (which moves
        with the stator along the spin axis and passes its loads to it).
    point : ndarray, shape (3,) [m]
    force, moment : ndarray, shape (3,) [N], [N m]
        Model axes; the moment is about ``point``.
    """

    kind: str
    source: str
    body: str | None
    point: np.ndarray
    force: np.ndarray
    moment: np.ndarray


@dataclass(frozen=True)
class SupportReaction:
    """What a suspension or a bearing exerts on the body it carries, and how far it deflects.

    Attributes
    ----------
    kind : {'mount', 'bearing', 'axial', 'pedestal'}
        ``axial``: a rotor on bearings without ``axial_stiffness`` moves axially with the
        stator (or stays on the ground), which holds it along its spin axis (a thrust face).
        ``pedestal``: what holds a bearing's pedestal: its springs normal to the spin axis, the
        stator (or the ground) along it and against its turning.
    name : str
        The mount or bearing (a pedestal: its bearing's name).
    body : str or None
        The carried body: None for the stator (a mount) and for a pedestal, else the rotor (a
        bearing).
    ground : bool
        True when the support stands on the ground (mounts; bearings and pedestals without a
        stator; a bearing on a pedestal stands on its pedestal).
    point : ndarray, shape (3,) [m]
    force, moment : ndarray, shape (3,) [N], [N m]
        On the carried body at ``point``, model axes.
    displacement : ndarray, shape (6,) [m, rad]
        Motion ``[u, theta]`` of the carried body at ``point`` relative to what carries it
        (the ground, the stator, or a bearing's pedestal).
    eccentricity, attitude_deg : float
        A journal bearing's eccentricity ratio [-] and attitude angle [deg] at its static load
        and speed (short-bearing solution); NaN for other supports.
    """

    kind: str
    name: str
    body: str | None
    ground: bool
    point: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    displacement: np.ndarray
    eccentricity: float = float("nan")
    attitude_deg: float = float("nan")


@dataclass(frozen=True)
class StaticResult:
    """The static solution ``K q = f`` of :func:`static`.

    Attributes
    ----------
    model : Model
    speed : float or None
        Reference speed [rad/s] of the operating point (None: at rest).
    coordinates : ndarray, shape (n,) [m, rad]
        ``q`` over ``model.dofs``.
    loads : tuple of StaticLoad
    reactions : tuple of SupportReaction
        Every suspension, then every bearing, then the axial holds and every pedestal.
    shafts : dict of str -> ShaftStatics
        Per flexible rotor's name, its shaft's stations with sag, shear force, bending moment
        and bending stress (:class:`~rotordyn_modal.analysis.shaft_statics.ShaftStatics`).
        Empty when every rotor is rigid.
    """

    model: Any
    speed: float | None
    coordinates: np.ndarray
    loads: tuple
    reactions: tuple
    shafts: dict = field(default_factory=dict)

    # -- motions -------------------------------------------------------------------------
    def stator_motion(self, point=None) -> np.ndarray:
        """Motion ``[u, theta]`` [m, rad] of the stator at ``point`` (default its centre of mass,
        the reference point), shape (6,); zeros when the rotors' bearings stand on the ground."""
        layout = self.model.dofs
        motion = self.coordinates[:layout.n_frame]
        if not layout.n_frame:
            return np.zeros(6)
        if point is None:
            return motion.copy()
        return shift_matrix(layout.reference_point, point).T @ motion

    def rotor_motion(self, rotor: str, point=None) -> np.ndarray:
        """Motion ``[u, theta]`` [m, rad] of ``rotor`` relative to the stator at ``point``
        (default its centre of mass), shape (6,); zeros for a rotor without bearings."""
        layout = self.model.dofs
        if not layout.on_bearings(rotor):
            return np.zeros(6)
        j = layout.rotors.index(rotor)
        point = layout.centres[j] if point is None else point
        return layout.local_relative_motion(rotor, point) @ self.coordinates[layout.slices[j]]

    def pedestal_motion(self, bearing: str) -> np.ndarray:
        """Motion ``[u, theta]`` [m, rad] of ``bearing``'s pedestal relative to the stator (or
        the ground), shape (6,): a translation normal to the spin axis (a pedestal does not turn)."""
        rows = self.model.dofs.pedestal(bearing)
        if rows is None:
            raise InputError(f"bearing {bearing!r}: expected a bearing on a pedestal (one with pedestal_mass)")
        return np.r_[transverse_axes(self.model.spin_axis).T @ self.coordinates[rows], 0.0, 0.0, 0.0]

    # -- balance -------------------------------------------------------------------------
    def imbalance(self, body: str | None = "machine"):
        """Sum of the forces and of the moments about the reference point on ``body``: zero to
        round-off when the reactions balance the loads.

        Parameters
        ----------
        body : str or None
            ``"machine"`` (default): the loads and the reactions of the ground; None or
            ``"stator"``: the stator with the loads on it (and on rotors without bearings) and
            the mounts and bearings on it; a rotor's name: it on its bearings.

        Returns
        -------
        force, moment : ndarray, shape (3,) [N], [N m]
        scale : float
            The sum of the magnitudes of every force entering the sums [N], to judge round-off.
        """
        wrenches = list(self._wrenches_on(body))
        reference = self.model.reference_point
        force, moment, scale = np.zeros(3), np.zeros(3), 0.0
        for point, f, m in wrenches:
            force += f
            moment += m + np.cross(np.asarray(point) - reference, f)
            scale += np.linalg.norm(f)
        return force, moment, scale

    def _wrenches_on(self, body):
        """``(point, force, moment)`` of every load and reaction on ``body``."""
        layout = self.model.dofs
        if body == "stator":
            body = None
        carried = (lambda b: b if b is not None and layout.on_bearings(b) else None)
        for load in self.loads:
            if body == "machine" or carried(load.body) == body:
                yield load.point, load.force, load.moment
        for r in self.reactions:
            if body == "machine":
                if r.ground:
                    yield r.point, r.force, r.moment
            elif r.kind == "pedestal":   # the pedestal counts with the stator: its support only from the ground
                if body is None and r.ground:
                    yield r.point, r.force, r.moment
            elif r.body == body:
                yield r.point, r.force, r.moment
            elif body is None and r.kind != "mount" and not r.ground:
                yield r.point, -r.force, -r.moment

    # -- tables --------------------------------------------------------------------------
    def displacements(self):
        """The stator at its centre of mass and at each mount, each rotor on bearings at its
        centre of mass and at each bearing (relative to the stator), and each bearing's pedestal
        (body ``pedestal``, point its bearing, relative to the stator): a DataFrame with columns
        ``body, point, x_m, y_m, z_m, ux_m, uy_m, uz_m, rx_rad, ry_rad, rz_rad``."""
        import pandas as pd

        model, layout = self.model, self.model.dofs
        rows = []
        if layout.n_frame:
            name = "stator" if model.stator is not None else "frame"
            rows.append((name, "centre of mass" if model.stator is not None else "reference point",
                         layout.reference_point, self.stator_motion()))
            rows += [(name, s.name, s.position, self.stator_motion(s.position)) for s in model.suspensions]
        for rotor in layout.rotors:
            rows.append((rotor, "centre of mass", model.rotor(rotor).center_of_mass, self.rotor_motion(rotor)))
            rows += [(rotor, b.name, b.position, self.rotor_motion(rotor, b.position))
                     for b in model.bearings_of(rotor)]
        rows += [("pedestal", b.name, b.position, self.pedestal_motion(b.name)) for b in model.bearings
                 if layout.pedestal(b.name) is not None]
        return pd.DataFrame([(body, where, *np.asarray(p, float), *motion) for body, where, p, motion in rows],
                            columns=["body", "point", "x_m", "y_m", "z_m", "ux_m", "uy_m", "uz_m",
                                     "rx_rad", "ry_rad", "rz_rad"])

    def reactions_table(self):
        """Every mount's and bearing's reaction on the body it carries: a DataFrame with
        columns ``support, kind, body, on, x_m, y_m, z_m, Fx_N, Fy_N, Fz_N, Mx_Nm, My_Nm, Mz_Nm,
        eccentricity, attitude_deg`` (``on``: ground, stator or pedestal; a pedestal's row has
        body ``pedestal``)."""
        import pandas as pd

        rows = [(r.name, r.kind, _carried(r), _stands_on(self.model, r), *r.point, *r.force, *r.moment,
                 r.eccentricity, r.attitude_deg) for r in self.reactions]
        return pd.DataFrame(rows, columns=["support", "kind", "body", "on", "x_m", "y_m", "z_m", "Fx_N", "Fy_N",
                                           "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm", "eccentricity", "attitude_deg"])

    def loads_table(self):
        """Every load: a DataFrame with columns ``kind, source, body, x_m, y_m, z_m, Fx_N, Fy_N,
        Fz_N, Mx_Nm, My_Nm, Mz_Nm`` (moments about the load's point)."""
        import pandas as pd

        rows = [(x.kind, x.source, "pedestal" if x.kind == "pedestal" else "stator" if x.body is None else x.body,
                 *x.point, *x.force, *x.moment) for x in self.loads]
        return pd.DataFrame(rows, columns=["kind", "source", "body", "x_m", "y_m", "z_m", "Fx_N", "Fy_N",
                                           "Fz_N", "Mx_Nm", "My_Nm", "Mz_Nm"])

    def shafts_table(self):
        """Every flexible rotor's stations (:meth:`ShaftStatics.table
        <rotordyn_modal.analysis.shaft_statics.ShaftStatics.table>`) one under the other; None
        when every rotor is rigid."""
        import pandas as pd

        if not self.shafts:
            return None
        return pd.concat([s.table() for s in self.shafts.values()], ignore_index=True)

    def to_dataframe(self):
        """The tables in one, a ``table`` column first (``load``, ``displacement``, ``reaction``,
        and ``shaft`` for the stations of flexible rotors, whose columns come after the
        others'): what ``rotordyn-modal static --out`` writes."""
        import pandas as pd

        parts = [self.loads_table().rename(columns={"source": "name"}).assign(table="load"),
                 self.displacements().rename(columns={"point": "name"}).assign(table="displacement"),
                 self.reactions_table().rename(columns={"support": "name"}).assign(table="reaction")]
        shafts = self.shafts_table()
        if shafts is not None:
            parts.append(shafts.rename(columns={"rotor": "body", "station": "name"}).assign(table="shaft"))
        table = pd.concat(parts, ignore_index=True)
        return table[["table"] + [c for c in table.columns if c != "table"]]

    def stress_checks(self) -> list:
        """Per flexible shaft, its stress verdict
        (:class:`~rotordyn_modal.analysis.shaft_statics.StressCheck`: the largest von Mises stress
        against the allowable stress, and where); empty when every rotor is rigid."""
        return [shaft.stress_check() for shaft in self.shafts.values()]

    def plot_shafts(self, **kwargs):
        """The sag, shear force and bending moment diagram of every flexible rotor; see
        :func:`rotordyn_modal.plotting.shaft_statics.plot_shaft_statics` (ValueError when every
        rotor is rigid)."""
        from ..plotting.shaft_statics import plot_shaft_statics

        return plot_shaft_statics(list(self.shafts.values()), **kwargs)


def _carried(reaction) -> str:
    """The body column of a reaction: the rotor, ``stator`` or ``pedestal``."""
    if reaction.kind == "pedestal":
        return "pedestal"
    return "stator" if reaction.body is None else reaction.body


def _stands_on(model, reaction) -> str:
    """What a support stands on: ``ground``, ``stator`` or (a bearing on one) ``pedestal``."""
    if reaction.kind == "bearing" and model.dofs.pedestal(reaction.name) is not None:
        return "pedestal"
    return "ground" if reaction.ground else "stator"


# ----------------------------------------------------------------------------------------
def static(model, speed=None, forces=None, torques=None, power=None, units: str = "si",
           allowable_stress=None) -> StaticResult:
    """Static displacement and support reactions of ``model`` under static loads.

    Parameters
    ----------
    model : Model
    speed : float, optional
        Reference speed [rad/s] of the operating point: needed for bearings whose stiffness
        depends on speed (tables, journal bearings) and for transmitted torques (the sense of
        rotation sets the tooth force's direction). None: at rest.
    forces : sequence, optional
        Static loads, each ``(body, point, force)`` or ``(body, point, force, moment)`` or a
        mapping with those keys: ``body`` ``"stator"`` or a rotor's name, ``point`` (3,) [m],
        ``force`` (3,) [N], ``moment`` (3,) [N m], model axes (a mapping may leave out
        ``force``, ``moment``, and ``point`` when it gives a moment alone). On a flexible rotor a
        mapping may give ``axial_position`` [m] from the shaft's start in place of ``point``, as
        the model file places its stations; a moment on a flexible rotor given without either acts
        at its centre of mass, with a ``ModelWarning`` (the shaft bends by where it acts).
    torques : float or mapping, optional
        Torque [N m] each transmission's driver passes on (positive: the driver drives the
        driven rotor), by ``"DRIVER->DRIVEN"``; one number: every transmission.
    power : float or mapping, optional
        Power [W] through each transmission instead (``torque = power / |driver speed|``),
        one number or by ``"DRIVER->DRIVEN"``; needs ``speed``.
    units : {'si', 'us'}
        Unit system of the points said in warnings and refusals (m or in; docs/units.md): the
        arguments and the result are SI whatever it says.
    allowable_stress : float, optional
        [Pa] allowable von Mises stress of every flexible shaft, in place of its materials'
        ``allowable_stress`` (``StaticResult.stress_checks``).

    Returns
    -------
    StaticResult

    Raises
    ------
    InputError
        A bad argument, a speed-dependent bearing without ``speed``, a transmission whose load
        cannot be placed, or loads that push a motion nothing holds (the sentence names it).
    """
    speed = None if speed is None else _arguments.speed(speed)
    units = check_system(units)
    if allowable_stress is not None and not (np.isfinite(allowable_stress) and allowable_stress > 0):
        raise InputError(f"allowable_stress = {allowable_stress!r}: expected a stress > 0 [Pa]")
    loads = _loads(model, speed, forces, _torques(model, speed, torques, power), units)
    loads += _couplings(model, loads)
    _warn_loads_between_nodes(model, loads, units, skip={f"forces[{i}]" for i, item in enumerate(forces or ())
                                                         if _without_station(item)})
    load_vector = _load_vector(model, loads) + _fixed_journal_forces(model)
    stiffness, supports, q = _loaded_films(model, speed, load_vector)
    reactions = tuple(_reaction(model, speed, q, *support) for support in supports) + _axial_holds(model, loads)
    reactions += _pedestal_reactions(model, q, reactions, loads)
    return StaticResult(model=model, speed=speed, coordinates=q, loads=tuple(loads), reactions=reactions,
                        shafts=_shaft_results(model, q, loads, allowable_stress))


def _shaft_results(model, q, loads, allowable_stress=None) -> dict:
    """Per flexible rotor: its shaft's stations with the sag, the shear force and the bending
    moment of the static solution, the torque and the stresses (empty when every rotor is rigid)."""
    return {r.name: shaft_statics(model, r, q, loads, allowable_stress) for r in model.rotors
            if r.flexible is not None and model.dofs.on_bearings(r.name)}


def _load_vector(model, loads) -> np.ndarray:
    """The generalized force of ``loads``: a flexible rotor's weight distributed along its
    shaft, any other load on it at the node at its point (offset from the node rigidly)."""
    total = np.zeros(model.dofs.n)
    for x in loads:
        flexible = x.body is not None and model.dofs.shaft(x.body) is not None
        if flexible and x.kind == "weight":
            total += weight_force(model, model.rotor(x.body))
            continue
        if x.kind == "pedestal":     # through the pedestal's absolute translation
            total += model.dofs.pedestal_motion(x.source, x.point).T @ x.force
            continue
        motion = model.dofs.body_motion(x.body, x.point) if flexible else None
        total += generalized_force(model, x.body, x.point, np.r_[x.force, x.moment], motion=motion)
    return total


# -- loads -------------------------------------------------------------------------------
def _loads(model, speed, forces, torques, units="si") -> list:
    loads = [StaticLoad("weight", "stator" if body is None else body, body, np.asarray(c, float),
                        np.asarray(f, float), np.zeros(3)) for body, c, f in weights(model)]
    loads += [StaticLoad("pedestal", bearing, None, point, force, np.zeros(3))
              for bearing, point, force in pedestal_weights(model)]
    loads += [_given_load(model, i, item, units) for i, item in enumerate(forces or ())]
    for t in model.transmissions:
        mine = _transmission_loads(model, t, torques.get(t.label, 0.0), speed)
        for x in mine:
            off = _off_shaft(model, x.body, x.point, units)
            if off:
                warnings.warn(ModelWarning(
                    f"{model.source}: [transmissions.{visible(t.label)}] acts at {_listed(x.point, units)} "
                    f"{unit_label('length', units)}, off {off}: "
                    "it is applied at the nearest end node through a rigid arm; give the transmission's "
                    "position (its plane) at the pulley or gear"), stacklevel=3)
        loads += mine
    return loads


def _given_load(model, index: int, item, units="si") -> StaticLoad:
    """One item of ``forces`` checked: ``(body, point, force[, moment])`` or a mapping."""
    name = f"forces[{index}]"
    axial = None
    if isinstance(item, dict):
        unknown = set(item) - {"body", "point", "axial_position", "force", "moment"}
        if unknown:
            raise InputError(f"{name}: unknown key {sorted(unknown)[0]!r}: expected body, point (or "
                             "axial_position), force, moment")
        body, point, force, moment = (item.get(k) for k in ("body", "point", "force", "moment"))
        axial = item.get("axial_position")
    elif isinstance(item, (tuple, list)) and len(item) in (3, 4):
        body, point, force, moment = (*item, None)[:4]
    else:
        raise InputError(f"{name} = {item!r}: expected (body, point, force) or (body, point, force, moment)")
    body = _body(model, body, name)
    if axial is not None:
        point = _station_point(model, body, axial, point, name, units)
    if point is None:    # a moment alone: its point does not matter; shown at the body's centre
        point = model.reference_point if body is None else model.rotor(body).center_of_mass
        _warn_moment_without_station(model, body, point, moment, name, units)
    vectors = [_vector3(value, f"{name} {key}") for key, value in
               (("point", point), ("force", force), ("moment", moment))]
    off = _off_shaft(model, body, vectors[0], units)
    if off:
        raise InputError(f"{name} point = {_listed(vectors[0], units)}"
                         f"{'' if units == 'si' else ' ' + unit_label('length', units)}: expected a point along {off}")
    return StaticLoad("force", name, body, *vectors)


def _warn_moment_without_station(model, body, point, moment, name: str, units="si") -> None:
    """One warning line for a moment on a flexible rotor given without its station: a rigid body
    takes a moment anywhere alike, a shaft bends (and twists) by where it acts, and it is taken at
    the rotor's centre of mass (flexible_pump_on_mounts: the pump shaft's largest bending moment
    under 50 N m is 28, 50 or 52 N m at its centre of mass, impeller or pulley)."""
    shaft = None if body is None else model.rotor(body).flexible
    if shaft is None or moment is None or not np.any(np.asarray(moment, dtype=float)):
        return
    length_unit = unit_label("length", units)
    where = float(to_system(shaft.z_of(point), "length", units))
    warnings.warn(ModelWarning(
        f"{name}: a moment on the flexible rotor {visible(body)} without its station acts at its centre of mass, "
        f"{where:.4g} {length_unit} from the shaft's start: where a moment acts changes how the shaft bends and "
        f"twists; give its station (axial_position, or --moment ROTOR@AXIAL:MX,MY,MZ)"), stacklevel=4)


def _without_station(item) -> bool:
    """Whether an item of ``forces`` gives neither its point nor its axial position (a moment
    alone, taken at the body's centre of mass: :func:`_warn_moment_without_station` says so)."""
    if isinstance(item, dict):
        return item.get("point") is None and item.get("axial_position") is None
    return isinstance(item, (tuple, list)) and len(item) in (3, 4) and item[1] is None


def _warn_loads_between_nodes(model, loads, units="si", skip=()) -> None:
    """One warning line per load on a flexible shaft whose point is no node of its mesh.

    Such a load acts at the nearest node, moved there rigidly with the moment of its offset
    (:func:`_load_vector`): the displacements and reactions are those of the load where it is,
    but between the node and the load's point the shear force and bending moment are not, and
    the bending moment jumps at the node by the force times the offset. A force of 1000 N at
    0.525 m on a 1 m shaft of 0.05 m elements on supports at its ends read its largest bending
    moment 262.5 N m at 0.5 m; the beam's is ``P a b / L`` = 249.4 N m at 0.525 m (237.5 N m at
    0.5 m), with no word said. A station there (a sensor on the rotor at that point) gives the
    mesh a node at the load. ``skip``: the sources of loads already warned about (a moment given
    without its station)."""
    from ..model.flexible import off_node

    length_unit = unit_label("length", units)
    for x in loads:
        shaft = None if x.body is None or x.kind not in ("force", "gear", "belt") or x.source in skip \
            else model.rotor(x.body).flexible
        if shaft is None or not (np.any(x.force) or np.any(x.moment)):
            continue
        z = float(shaft.z_of(x.point))
        slack = STATION_TOLERANCE * (1.0 + shaft.length)
        where = off_node(shaft, z) if -slack <= z <= shaft.length + slack else None   # beyond: _loads warns
        if where is None:
            continue
        node, offset = where
        shown = lambda value: f"{float(to_system(value, 'length', units)):.6g} {length_unit}"   # noqa: E731
        warnings.warn(ModelWarning(
            f"{x.source}: acts on rotor {visible(x.body)}'s shaft at {shown(z)} from its start, between the nodes "
            f"of its mesh: it is applied at the nearest node n{node} ({shown(shaft.mesh.z[node])}) with the moment of "
            f"its offset {shown(abs(offset))}, so the shaft's shear force and bending moment between the two are "
            "not the load's; give the rotor a station there (a sensor at that point) for a node at the load"),
            stacklevel=3)


def _station_point(model, body, axial, point, name: str, units="si") -> np.ndarray:
    """The point on a flexible rotor's axis at ``axial`` [m] from its shaft's start, as the
    model file's ``axial_position`` places a station (the 3-D point on a shaft that does not
    start at the origin was the only way to say it)."""
    shaft = None if body is None else model.rotor(body).flexible
    length_unit = unit_label("length", units)
    if shaft is None:
        raise InputError(f"{name} axial_position: expected no value: axial_position places a load "
                         f"on a flexible rotor's shaft and {'the stator' if body is None else 'rotor ' + visible(body)}"
                         " has none (give point, model axes)")
    if point is not None:
        raise InputError(f"{name}: either point or axial_position, not both")
    z = _arguments.number(axial, f"{name} axial_position", "m")
    slack = STATION_TOLERANCE * (1.0 + shaft.length)
    if not -slack <= z <= shaft.length + slack:
        length = float(to_system(shaft.length, "length", units))
        shown = float(to_system(z, "length", units))
        raise InputError(f"{name} axial_position = {shown:.6g} {length_unit}: expected a position along rotor "
                         f"{visible(body)}'s shaft, from 0 (its start) to {length:.6g} {length_unit}")
    return shaft.point(min(max(z, 0.0), shaft.length))


def _off_shaft(model, body, point, units="si") -> str:
    """'' when ``point`` lies along ``body``'s shaft (between its ends, at any distance from its
    axis) or ``body`` is not a flexible rotor; else the shaft's extent in words (m, or in for
    ``units='us'``)."""
    shaft = None if body is None else model.rotor(body).flexible
    if shaft is None:
        return ""
    slack = STATION_TOLERANCE * (1.0 + shaft.length)
    if -slack <= shaft.z_of(point) <= shaft.length + slack:
        return ""
    ends = shaft.point(np.array([0.0, shaft.length]))
    return (f"rotor {visible(body)}'s shaft, from {_listed(ends[0], units)} to {_listed(ends[1], units)} "
            f"{unit_label('length', units)} (a load on a "
            "flexible rotor acts at the shaft's node there)")


def _listed(vector, units="si") -> str:
    """``[x, y, z]`` of a point [m], in the length unit of ``units``."""
    return "[" + ", ".join(f"{v:.6g}" for v in to_system(np.asarray(vector, dtype=float), "length", units)) + "]"


def _body(model, body, name: str):
    """None for the stator, else a rotor's name; InputError for anything else."""
    rotors = [r.name for r in model.rotors]
    if body in rotors:
        return body
    if body == "stator" and (model.stator is not None or not model.bearings):
        return None
    what = ("'stator' or " if model.stator is not None or not model.bearings else "") + \
        "the name of a rotor (" + ", ".join(map(visible, rotors)) + ")"
    raise InputError(f"{name} body = {body!r}: expected {what}")


def _vector3(value, name: str) -> np.ndarray:
    if value is None:
        return np.zeros(3)
    vector = _arguments.values(value, name, "SI")
    if vector.shape != (3,):
        raise InputError(f"{name} = {value!r}: expected 3 finite numbers (model axes, SI units)")
    return vector


def transmission_torques(model, speed, power) -> dict:
    """Torque [N m] each transmission's driver passes on at ``power`` [W] (a number for every
    transmission, or a mapping by ``"DRIVER->DRIVEN"``) and reference ``speed`` [rad/s]:
    ``power / |driver's speed|``."""
    powers = _per_transmission(model, power, "power", "W")
    if not powers:
        return {}
    if speed is None or speed == 0:
        raise InputError(f"power = {power!r}: expected a speed (not zero) as well: the torque a power "
                         "gives is power / speed")
    torques = {label: p / abs(model.speed_ratios[label.split("->")[0]] * speed)
               for label, p in powers.items() if p}
    for label, torque in torques.items():      # a tiny speed: a torque no machine carries, forces overflow
        if not abs(torque) <= LARGEST:
            raise InputError(f"power: expected a power and speed whose torque power / speed is at most "
                             f"{LARGEST:g} N m (on the driver of {visible(label)} it is {abs(torque):.3g} N m "
                             f"at {abs(speed):.3g} rad/s)")
    return torques


def _torques(model, speed, torques, power) -> dict:
    if torques is not None and power is not None:
        raise InputError("torques and power: expected one of them (a power gives the torques)")
    if power is not None:
        return transmission_torques(model, speed, power)
    given = _per_transmission(model, torques, "torques", "N m")
    if any(given.values()) and speed is None:
        raise InputError("torques: expected a speed as well: the sense of rotation sets the direction "
                         "of the tooth forces")
    return given


def _per_transmission(model, value, name: str, unit: str) -> dict:
    """``{label: number}`` from one number (every transmission) or a mapping by label."""
    if value is None:
        return {}
    labels = [t.label for t in model.transmissions]
    if not labels:
        raise InputError(f"{name} = {value!r}: the model has no [[transmissions]]")
    if isinstance(value, dict):
        unknown = [k for k in value if k not in labels]
        if unknown:
            raise InputError(f"{name}: unknown transmission {unknown[0]!r}: expected one of "
                             + ", ".join(map(visible, labels)))
        return {k: _arguments.speed(v, f"{name}[{k!r}]") for k, v in value.items()}
    number = _arguments.values(value, name, unit)
    if number.shape != (1,):
        raise InputError(f"{name} = {value!r}: expected one number [{unit}] or a mapping by DRIVER->DRIVEN")
    return dict.fromkeys(labels, float(number[0]))


def _transmission_loads(model, t, torque: float, speed) -> list:
    """The tooth force (gear) or strand pull (belt) of transmission ``t`` carrying ``torque``
    [N m] on its driver, on the driver and the driven rotor (docs/static.md)."""
    tension = t.pretension or 0.0
    if not torque and not tension:
        return []
    e = model.spin_axis
    driver, driven = model.rotor(t.driver), model.rotor(t.driven)
    plane = driver.center_of_mass if t.position is None else t.position
    on_driver, on_driven = (np.asarray(r.center_of_mass) + ((plane - r.center_of_mass) @ e) * e
                            for r in (driver, driven))
    between = on_driven - on_driver
    distance = float(np.linalg.norm(between))
    where = f"{model.source}: [transmissions.{visible(t.label)}]"
    if not distance > 0:
        raise InputError(f"{where}: the driver's and the driven rotor's spin axes coincide: a {t.type} "
                         "between them has no line of centres to push along (give the rotors' centres of mass "
                         "apart, normal to spin_axis)")
    u = between / distance
    sense = np.sign(model.speed_ratios[t.driver] * speed) if torque else 0.0
    if t.type == "gear":
        return _gear_loads(t, torque, sense, on_driver, u, np.cross(e, u), distance, where)
    return _belt_loads(model, t, torque, sense, on_driver, on_driven, u, where)


def _gear_loads(t, torque, sense, on_driver, u, tangent, distance, where) -> list:
    """Tooth force at the pitch point, along the line of action: tangential ``torque / r``
    against the driver's rotation, radial ``|torque| / r * tan(pressure angle)`` pushing the
    wheels apart."""
    radius = distance / (1.0 + t.ratio) if t.driver_radius is None else t.driver_radius
    if not radius < distance:
        raise InputError(f"{where} driver_radius = {radius:g}: expected a pitch radius below the centre "
                         f"distance {distance:g} m of the two spin axes")
    angle = np.radians(DEFAULT_PRESSURE_ANGLE if t.pressure_angle is None else t.pressure_angle)
    pitch_point = on_driver + radius * u
    force = -sense * torque / radius * tangent - abs(torque) / radius * np.tan(angle) * u
    return [StaticLoad("gear", t.label, t.driver, pitch_point, force, np.zeros(3)),
            StaticLoad("gear", t.label, t.driven, pitch_point.copy(), -force, np.zeros(3))]


def _belt_loads(model, t, torque, sense, on_driver, on_driven, u, where) -> list:
    """The strands' pull along the line of centres, ``max(2 pretension, |torque| / r)``, and
    their torque on each pulley (strands taken parallel to the line of centres)."""
    if torque and t.driver_radius is None:
        raise InputError(f"{where} driver_radius = <missing>: expected the driver pulley's radius [m] "
                         "to turn a transmitted torque into the belt's pull")
    pull = max(2.0 * (t.pretension or 0.0), abs(torque) / t.driver_radius if torque else 0.0)
    e = model.spin_axis
    moment = -sense * torque * e
    return [StaticLoad("belt", t.label, t.driver, on_driver, pull * u, moment),
            StaticLoad("belt", t.label, t.driven, on_driven, -pull * u, -t.ratio * moment)]


def _couplings(model, loads) -> list:
    """Per rotor, the coupling's moment that holds its spin: minus the moment about its spin
    axis of the loads on it."""
    e = model.spin_axis
    out = []
    for rotor in model.rotors:
        centre = np.asarray(rotor.center_of_mass, dtype=float)
        mine = [x for x in loads if x.body == rotor.name]
        spin = sum(float((x.moment + np.cross(x.point - centre, x.force)) @ e) for x in mine)
        scale = sum(np.linalg.norm(x.moment) + np.linalg.norm(x.force) * np.linalg.norm(x.point - centre)
                    for x in mine)
        if abs(spin) > 1e-13 * scale:
            where = centre if rotor.coupling_position is None else rotor.flexible.point(rotor.coupling_position)
            out.append(StaticLoad("coupling", rotor.name, rotor.name, where, np.zeros(3), -spin * e))
    return out


# -- stiffness and solution --------------------------------------------------------------
#: secant steps at most of the loaded films (under the weights alone the first is the last)
LOADED_FILM_STEPS = 100


def _loaded_films(model, speed, load_vector):
    """``(K, supports, q)`` of the static solution, the journals whose load the model solves at
    each speed standing on their loaded film (:func:`_secant_film`): drawn at the model's loads at
    this speed, then at the loads the solution puts on them until these repeat (to 1e-12 of the
    largest); a journal's film is a secant, so the loads it is drawn at and those it carries agree
    only at the films' nonlinear equilibrium. Other journals stand on their light-load film."""
    journals = [b for b in model.bearings if _loaded_film(b)]
    loads = {b.name: _model_load(model, b, speed) for b in journals}
    for _ in range(LOADED_FILM_STEPS):
        stiffness, supports = _stiffness(model, speed, loads)
        q = _solve(model, stiffness, load_vector)
        if not journals:
            return stiffness, supports, q
        carried = {b.name: _journal_load(model, b, q, k6) for kind, b, k6 in supports
                   if kind == "bearing" and b.name in loads}
        scale = max(max(np.linalg.norm(f) for f in carried.values()), max(np.linalg.norm(f) for f in loads.values()))
        if all(np.linalg.norm(carried[n] - loads[n]) <= 1e-12 * scale for n in loads):
            return stiffness, supports, q
        loads = carried
    raise InputError(f"{model.source}: the journals {', '.join(visible(b.name) for b in journals)} on their loaded "
                     f"films: no static equilibrium found in {LOADED_FILM_STEPS} secant steps at "
                     f"{abs(speed) * 30 / np.pi:.6g} rpm (give each journal's load)")


def _fixed_load(bearing) -> np.ndarray | None:
    """The force [N] (3,) a journal whose given ``load`` is fixed in its rotor's split puts on its
    bearing (:attr:`JournalData.fixed_load`), else None."""
    journal = bearing.coefficients.journal if bearing.coefficients.kind == "journal" else None
    if journal is None or not journal.fixed_load:
        return None
    return journal.load * np.asarray(journal.axes[0], dtype=float)


def _fixed_journal_forces(model) -> np.ndarray:
    """The generalized force (n,) of the journals whose given load is fixed (:func:`_fixed_load`):
    each bearing pushes its rotor with ``-load`` (and its pedestal, or the stator, with ``+load``),
    whatever the journal's motion; their film adds no stiffness here (``_bearing_stiffness``)."""
    total = np.zeros(model.dofs.n)
    for b in model.bearings:
        load = _fixed_load(b)
        if load is not None:
            rows, moves = bearing_motion(model, b)
            total[rows] += moves.T @ np.r_[-load, np.zeros(3)]
    return total


def _loaded_film(bearing) -> bool:
    """A journal bearing whose static load the model solves at each speed."""
    journal = bearing.coefficients.journal if bearing.coefficients.kind == "journal" else None
    return journal is not None and journal.load_over_speed is not None


def _model_load(model, bearing, speed) -> np.ndarray:
    """The load [N] (3,) the model gives ``bearing``'s journal at the reference ``speed``."""
    own = 0.0 if speed is None else model.speed_ratios[bearing.rotor] * speed
    if own == 0:
        _bearing_stiffness(model, bearing, speed)        # the refusal of a film at rest
    return np.asarray(bearing.coefficients.journal.load_over_speed(np.array([own]))[0], dtype=float)


def _journal_load(model, bearing, q, k6) -> np.ndarray:
    """The force [N] (3,) the journal puts on its bearing in ``q``, normal to the spin axis."""
    rows, moves = bearing_motion(model, bearing)
    force = k6[:3] @ (moves @ q[rows])
    e = model.spin_axis
    return force - (force @ e) * e


def _secant_film(journal, own: float, load, spin_axis) -> np.ndarray:
    """The 3x3 stiffness [N/m] (model axes, normal to ``spin_axis``) of a journal's loaded film:
    the spring that holds the journal at the short bearing's offset ``d = c eps (cos phi x + sin
    phi e x x)`` under ``load`` (``x`` along it, ``eps`` and ``phi`` the eccentricity and signed
    attitude angle of its magnitude at the own speed), ``a (I - e e^T) + b [e]x`` with ``a = F.d /
    |d|^2``, ``b = e.(d x F) / |d|^2`` (``K d = F``); a journal carrying nothing stands on its
    light-load film."""
    from ..elements.journal_bearing import short_journal_bearing

    e = np.asarray(spin_axis, dtype=float)
    force = np.asarray(load, dtype=float)
    force = force - (force @ e) * e
    magnitude = float(np.linalg.norm(force))
    if not magnitude > 0:
        light = np.pi * journal.viscosity * abs(own) * journal.diameter * journal.length**3 / (8 * journal.clearance**3)
        return -np.sign(own) * light * skew(e)
    film = short_journal_bearing([own], diameter=journal.diameter, length=journal.length,
                                 clearance=journal.clearance, viscosity=journal.viscosity, load=magnitude)
    x = force / magnitude
    phi = float(film.attitude_angle[0])
    offset = journal.clearance * float(film.eccentricity[0]) * (np.cos(phi) * x + np.sin(phi) * np.cross(e, x))
    square = float(offset @ offset)
    return (force @ offset) / square * (np.eye(3) - np.outer(e, e)) + (e @ np.cross(offset, force)) / square * skew(e)


def _stiffness(model, speed, loaded=None):
    """The static stiffness ``K`` (n, n) and each support as ``(kind, item, k6)``: its 6x6
    stiffness at its point (model axes); ``loaded`` maps a journal bearing's name to the load [N]
    (3,) whose loaded film (:func:`_secant_film`) it stands on."""
    reference = model.reference_point
    supports, total = [], np.zeros((6, 6))
    for s in model.suspensions:
        shift = shift_matrix(reference, s.position)
        total += shift @ s.stiffness_matrix @ shift.T
        supports.append(("mount", s, s.stiffness_matrix))
    stiffness = frame_block(model, total)
    if any(r.flexible is not None for r in model.rotors):
        stiffness += shaft_stiffness(model)
    for b in model.bearings:
        k6 = _bearing_stiffness(model, b, speed, (loaded or {}).get(b.name))
        rows, moves = bearing_motion(model, b)
        stiffness[rows, rows] += moves.T @ k6 @ moves
        supports.append(("bearing", b, k6))
    if model.dofs.pedestals:     # the bearings' pedestals to the stator (their weight: a load of kind pedestal)
        stiffness += pedestal_stiffness_damping(model)[0]
    return stiffness, supports


def _bearing_stiffness(model, bearing, speed, load=None) -> np.ndarray:
    """A bearing's static 6x6 stiffness at the operating speed (journals: the light-load film, or
    with ``load`` [N] (3,) the loaded film at that load, :func:`_secant_film`)."""
    coefficients = bearing.coefficients
    where = f"{model.source}: [bearings.{visible(bearing.name)}]"
    if coefficients.kind != "constant" and speed is None:
        raise InputError(f"{where}: its stiffness depends on speed ({'a journal bearing' if coefficients.kind == 'journal' else 'a speed table'}): "
                         "give the operating speed (speed [rad/s]; on the command line --speed)")
    own = 0.0 if speed is None else model.speed_ratios[bearing.rotor] * speed
    if coefficients.kind != "journal":
        return evaluate(coefficients, [own], where)[0][0]
    journal = coefficients.journal
    if own == 0:
        raise InputError(f"{where}: a journal bearing at speed 0 has no oil film to stand on: give a speed "
                         "other than 0")
    k6 = coefficients.stiffness[0].copy()
    if journal.fixed_load:        # a fixed force (_fixed_journal_forces), no spring
        return k6
    if load is not None:
        try:
            k6[:3, :3] += _secant_film(journal, own, load, model.spin_axis)
        except InputError as error:
            raise InputError(f"{where} under its static load: {error}") from None
        return k6
    film = np.pi * journal.viscosity * abs(own) * journal.diameter * journal.length**3 / (8 * journal.clearance**3)
    # the film holds the journal at 90 degrees to its offset: force -k R(-phi) e, phi = sign(own) pi / 2
    k6[:3, :3] += -np.sign(own) * film * skew(model.spin_axis)
    return k6


def _solve(model, stiffness, load) -> np.ndarray:
    """``q`` with ``K q = f``, or InputError naming the motion the loads push that nothing holds."""
    if not np.any(load):
        return np.zeros(len(load))
    q = static_solution(stiffness, load)
    if q is None:
        raise InputError(f"{model.source}: the static loads push {_free_motion(model, stiffness, load)}, "
                         "which no suspension or bearing holds (a rigid-body motion): the machine would "
                         "not stand still")
    return q


def _free_motion(model, stiffness, load) -> str:
    """The coordinates of the free motion that the load pushes most, in words."""
    size = np.sqrt(np.linalg.norm(stiffness, axis=0) * np.linalg.norm(stiffness, axis=1))
    scaled_size = np.sqrt(np.where(size > 0, size, 1.0))       # D^-1/2 K D^-1/2, as static_solution
    u, values, vt = np.linalg.svd(stiffness / np.outer(scaled_size, scaled_size))
    free = ~(values > len(values) * np.finfo(float).eps * values[0]) if values[0] > 0 else np.ones(len(values), bool)
    pushes = np.abs(u[:, free].T @ (load / scaled_size))
    motion = np.abs(vt[free][int(np.argmax(pushes))] / scaled_size)
    names = [model.dofs.names[i] for i in np.argsort(-motion) if motion[i] > 0.1 * motion.max()]
    return " with ".join(_in_words(name) for name in names[:3])


def _in_words(coordinate: str) -> str:
    """``stator.ux`` -> ``the stator's translation along x (stator.ux)``."""
    body, _, motion = coordinate.rpartition(".")
    who = f"the {body}'s" if body in ("stator", "frame") else f"rotor {visible(body)}'s"
    what = "translation along" if motion.startswith("u") else "rotation about"
    return f"{who} {what} {motion[1:]} ({coordinate})"


def _reaction(model, speed, q, kind, item, k6) -> SupportReaction:
    """A support's deflection and its force and moment on the body it carries."""
    layout = model.dofs
    if kind == "mount":
        motion = shift_matrix(layout.reference_point, item.position).T @ q[:6]
        body, ground = None, True
    else:
        rows, moves = bearing_motion(model, item)
        motion = moves @ q[rows]
        body, ground = item.rotor, layout.frame == "ground" and item.pedestal is None
    wrench = -k6 @ motion
    fixed = _fixed_load(item) if kind == "bearing" else None
    if fixed is not None:
        wrench[:3] -= fixed
    extra = _journal_state(model, speed, item, wrench[:3]) if kind == "bearing" else {}
    return SupportReaction(kind=kind, name=item.name, body=body, ground=ground,
                           point=np.asarray(item.position, dtype=float), force=wrench[:3], moment=wrench[3:],
                           displacement=motion, **extra)


def _axial_holds(model, loads) -> tuple:
    """The thrust that holds along its spin axis each rotor on bearings without axial coordinate
    (its axial motion is the stator's): minus the axial part of the loads on it, at its centre."""
    layout, e = model.dofs, model.spin_axis
    out = []
    for rotor in layout.rotors:
        if any(b.coefficients.axial for b in model.bearings_of(rotor)):
            continue
        mine = [x.force for x in loads if x.body == rotor]
        axial = float(sum(mine, np.zeros(3)) @ e)
        if abs(axial) > 1e-13 * sum(np.linalg.norm(f) for f in mine):
            out.append(SupportReaction(kind="axial", name=f"{rotor} axial", body=rotor,
                                       ground=layout.frame == "ground",
                                       point=np.asarray(model.rotor(rotor).center_of_mass, dtype=float),
                                       force=-axial * e, moment=np.zeros(3), displacement=np.zeros(6)))
    return tuple(out)


def _pedestal_reactions(model, q, reactions, loads) -> tuple:
    """What holds each bearing's pedestal: its springs' force ``-K_p u_p`` normal to the spin
    axis, and along it and against turning the stator (or the ground), which takes the rest of
    the bearing's force on the pedestal and of its weight (the pedestal moves with it there)."""
    layout, e = model.dofs, np.asarray(model.spin_axis, dtype=float)
    bearings = {r.name: r for r in reactions if r.kind == "bearing"}
    pedestal_weight = {x.source: x.force for x in loads if x.kind == "pedestal"}
    out = []
    for b in model.bearings:
        if b.pedestal is None:
            continue
        motion = np.r_[transverse_axes(e).T @ q[layout.pedestal(b.name)], 0.0, 0.0, 0.0]
        spring = -b.pedestal.stiffness @ motion[:3]
        held = bearings[b.name].force - pedestal_weight.get(b.name, np.zeros(3))   # the pedestal's balance
        out.append(SupportReaction(kind="pedestal", name=b.name, body=None, ground=layout.frame == "ground",
                                   point=np.asarray(b.position, dtype=float), force=spring + (held @ e) * e,
                                   moment=bearings[b.name].moment.copy(), displacement=motion))
    return tuple(out)


def _journal_state(model, speed, bearing, force) -> dict:
    """A journal bearing's eccentricity and attitude angle at its static load (short bearing)."""
    from ..elements.journal_bearing import short_journal_bearing

    journal = bearing.coefficients.journal
    e = model.spin_axis
    load = float(np.linalg.norm(force - (force @ e) * e))
    if journal is None or not load > 0:
        return {}
    own = model.speed_ratios[bearing.rotor] * speed
    try:
        film = short_journal_bearing([own], diameter=journal.diameter, length=journal.length,
                                     clearance=journal.clearance, viscosity=journal.viscosity, load=load)
    except InputError as error:
        raise InputError(f"{model.source}: [bearings.{visible(bearing.name)}] under its static load: {error}") from None
    return {"eccentricity": float(film.eccentricity[0]), "attitude_deg": float(np.degrees(film.attitude_angle[0]))}
