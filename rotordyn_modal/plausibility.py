"""Plausibility checks: what is legal in a model but probably not meant, one warning line each.

A model that passes every rule of its tables may still hold a number in the wrong unit (a
stiffness in N/mm given as N/m, a mass in g given as kg, positions in mm, a relaxation time in
ms). :func:`implausible` looks at the model as a whole and says what it finds, one sentence
each (``load_model`` warns with them, ``check`` prints them; docs/model-file.md, "Warnings"):

* the machine's static sag on its suspensions under gravity, or its lowest mode on them;
* a rotor's sag in its bearings, a journal's given load far from its share of the weight, or a rigid-body mode of a rotor in its bearings (constant
  bearings at rest, speed tables at their lowest speed, journal films at light load);
* a long journal bearing, mount or bearing points far from their body, a mount matrix typed as
  one triangle, a slow Maxwell branch, a flexible rotor's sizes and materials, a wide close
  clearance;
* supports far stiffer than what they hold (:mod:`rotordyn_modal.stiffness_spread`).

The checks of single tables (a journal's clearance or viscosity, a gravity over 5 g) are made
where the tables are read (``elements``, ``model``).
"""

from __future__ import annotations

import numpy as np

from ._blas import one_blas_thread
from .assembly import bearing_motion, body_inertias, constant_stiffness_damping, mass_matrix, rigid_mass_matrix, \
    weight_force
from .elements._bearing_validation import LONG_JOURNAL
from .elements.bearings import light_load_stiffness
from .linear_system import static_solution
from .model._table import and_others, visible
from .model.geometry import shift_matrix, transverse_axes
from .stiffness_spread import spread_lines
from .units import to_system, unit_label

__all__ = ["implausible", "SAG_LIMIT", "SAG_CHECK_DOF", "LOW_MODE_CHECK_DOF", "LOWEST_MOUNT_FREQUENCY", "CLEARANCE_WARN", "SLOW_MAXWELL",
           "FAR_POINT", "LOAD_FACTOR", "LEAST_LOAD_SHARE"]


#: static sag [m] of a suspension point under the machine's weight above which a model draws a
#: warning: rubber mounts and steel springs deflect millimetres to a few centimetres (a 1.6 Hz
#: mount mode already sags 0.1 m, since f = sqrt(g / sag) / (2 pi)); metres mean a stiffness in
#: N/mm given as N/m or a mass in g given as kg (either makes the sag 1000 times too large)
SAG_LIMIT = 0.1
#: the most coordinates of a model whose rotors' sag in their bearings and journal loads are
#: looked at when it is read (a dense LU of the stiffness, ``linear_system.static_solution``:
#: about 0.1 s at this size on one thread, the 500-rotor gear chain's 2,006 coordinates; larger
#: models are left to ``static``)
SAG_CHECK_DOF = 2500
#: the most coordinates of a model whose rotors' lowest modes in their bearings are looked at
#: when it is read (dense generalized eigenproblems per rotor; larger models get the rigid-rotor
#: bound, :func:`_rigid_rotor_bound_lines`)
LOW_MODE_CHECK_DOF = 200
#: lowest natural frequency [Hz] of the machine on its suspensions below which a model without
#: gravity draws a warning (a stiffness 1000 times too small, or a mass 1000 times too large, puts a
#: 10 Hz mount mode at 0.3 Hz)
LOWEST_MOUNT_FREQUENCY = 0.5


def implausible(model, units: str = "si") -> list[str]:
    """What is legal in ``model`` but probably not meant, one sentence each (empty: nothing).

    * The machine on its suspensions, rigid (its rotors held in place), under ``gravity``: the
      static sag ``K x = weight`` of a suspension point above :data:`SAG_LIMIT`, or
      suspensions that do not hold the weight at all; without gravity, or when the sag is
      plausible, a mode of the machine on its suspensions below :data:`LOWEST_MOUNT_FREQUENCY`
      (unrestrained directions, frequency zero, are not counted: ``check`` notes them).
    * Without such a sag line, a rotor in its bearings under ``gravity`` deflecting more than
      :data:`SAG_LIMIT` at a bearing point (:func:`_bearing_sag_lines`: speed tables at their
      lowest speed, journals on their films, which hold them within their clearance; models of
      at most :data:`SAG_CHECK_DOF` coordinates).
    * A journal bearing's given ``load`` more than :data:`LOAD_FACTOR` times off its share of its
      rotor's weight under ``gravity`` (:func:`_journal_load_lines`).
    * A journal bearing longer than :data:`~rotordyn_modal.elements._bearing_validation.LONG_JOURNAL`
      diameters (short-bearing theory loses accuracy there).
    * A station of a flexible rotor placed at another's node, closer than
      :data:`~rotordyn_modal.model.flexible.MERGE_FRACTION` of its section's element length to it
      (:func:`~rotordyn_modal.model.flexible.merge_lines`).

    Parameters
    ----------
    model : Model
    units : {'si', 'us'}
        Unit system of the computed values said (the sag in m or in, the weight in kg or lb;
        docs/units.md); the model's keys are quoted as the file gives them (SI).

    Returns
    -------
    list of str, each naming the model's source
    """
    lines, sag, held, statics = [], "", [], {}
    if model.suspensions:
        try:   # a model whose numbers overflow here is refused by its analyses, not by a warning
            with np.errstate(all="ignore"):
                sag = _sag_line(model, units)
                lines += [sag] if sag else _low_mode_lines(model)
        except (np.linalg.LinAlgError, ValueError):
            pass
    # one sag line for one mistake: the machine's on its suspensions already names the units
    if model.bearings and not sag:
        held = _checked(_bearing_sag_lines, model, units, statics) \
            if np.any(model.gravity) and model.dofs.n <= SAG_CHECK_DOF else []
        lines += held or (_checked(_low_rotor_mode_lines, model) if model.dofs.n <= LOW_MODE_CHECK_DOF
                          else _checked(_rigid_rotor_bound_lines, model, dense=False))
    for b in model.bearings:
        journal = b.coefficients.journal
        if journal is not None and journal.length > LONG_JOURNAL * journal.diameter:
            lines.append(f"{model.source}: [bearings.{visible(b.name)}] length = {journal.length:g}: "
                         f"L/D = {journal.length / journal.diameter:.3g} is beyond {LONG_JOURNAL:g}, where "
                         "short-bearing (Ocvirk) theory stops matching measurements: its coefficients are rough")
    if model.bearings and np.any(model.gravity):
        try:
            with np.errstate(all="ignore"):
                lines += _journal_load_lines(model, units, statics)
        except (np.linalg.LinAlgError, ValueError):
            pass
    # a mass far too large (g typed as kg) makes the radii of gyration small too: said once, by the sag
    far = [] if sag or held else _far_point_lines(model)
    return lines + far + _circulatory_mount_lines(model) + _slow_maxwell_lines(model) + _merge_lines(model) \
        + _material_lines(model) + _clearance_lines(model) + spread_lines(model)


#: the largest radial running clearance [m] of a close-clearance station that draws no warning:
#: seals and impeller eyes run 0.1 to 2 mm
CLEARANCE_WARN = 0.01


def _checked(check, model, *arguments, dense=True) -> list[str]:
    """``check(model, *arguments)``'s lines, none where its numbers fail (a model whose numbers
    overflow here is refused by its analyses, not by a warning); ``dense``: on one BLAS thread
    (small dense work: a busy machine's many threads took 0.3 s for 68x68)."""
    import contextlib

    try:
        with np.errstate(all="ignore"), \
                (one_blas_thread(72 * model.dofs.n ** 2) if dense else contextlib.nullcontext()):
            return check(model, *arguments)
    except (np.linalg.LinAlgError, ValueError):
        return []


def _clearance_lines(model) -> list[str]:
    """A line for each ``[[rotors.clearances]]`` radial clearance over :data:`CLEARANCE_WARN`: a
    value in mm typed for m (0.25 for 0.25 mm) makes the API clearance check pass at any
    vibration (75 % of a diametral clearance of 0.5 m)."""
    return [f"{model.source}: [rotors.{visible(c.rotor)}.clearances.{visible(c.name)}] radial_clearance = "
            f"{c.radial_clearance:g}: over {CLEARANCE_WARN:g} m, no close clearance (seals run 0.1 to 2 mm), and "
            "the clearance check passes any vibration against it; a value in mm typed for m? (model files are SI)"
            for c in getattr(model, "clearances", ()) if c.radial_clearance > CLEARANCE_WARN]


def _merge_lines(model) -> list[str]:
    """A line for each flexible rotor's section thicker than any shaft and each station moved to
    another's node (model/flexible.py)."""
    from .model.flexible import merge_lines

    from .model.flexible import size_lines

    return [line for rotor in model.rotors if rotor.flexible is not None
            for line in (*size_lines(model.source, rotor.name, rotor.flexible),
                         *merge_lines(model.source, rotor.name, rotor.flexible))]


def _material_lines(model) -> list[str]:
    """A line for each number of a flexible shaft's material that no solid has."""
    from .elements.shaft import material_implausible

    if not any(rotor.shaft for rotor in model.rotors):
        return []
    used = {}
    for rotor, shaft in zip(model.dofs.rotors, model.dofs.shafts or ()):
        for section in shaft.sections if shaft is not None else ():
            for material in (section.material, *(layer.material for layer in section.layers)):
                used.setdefault(material.name, material)
    return [f"{model.source}: [materials.{visible(name)}] {key} = {value:g}: {why}"
            for name, material in used.items() for key, value, why in material_implausible(material)]


def _on_suspensions(model):
    """The rigid machine's mass and its suspensions' stiffness about the reference point, (6, 6)."""
    reference = model.reference_point
    mass = sum(rigid_mass_matrix(m, J, c, reference) for m, c, J in body_inertias(model))
    shifts = [shift_matrix(reference, s.position) for s in model.suspensions]
    stiffness = sum(shift @ s.stiffness_matrix @ shift.T for shift, s in zip(shifts, model.suspensions))
    return mass, stiffness, shifts


def _sag_line(model, units: str = "si") -> str:
    """The warning about the machine's static sag under gravity, or ''.

    The stator's rows of the static solution ``K q = f`` (docs/static.md): bearings act on the
    rotors' relative motion only, so the stator's sag on its suspensions is the rigid machine's,
    whatever the bearings (``rotordyn_modal.analysis.static`` solves the same rows); the sag and
    the weight in the unit system ``units``."""
    if not np.any(model.gravity):
        return ""
    _, stiffness, shifts = _on_suspensions(model)
    total = sum(m for m, _, _ in body_inertias(model)) + sum(b.pedestal.mass for b in model.bearings
                                                            if b.pedestal is not None)
    sag = static_solution(stiffness, weight_force(model)[:6])
    if sag is None:
        return (f"{model.source}: the [[suspensions]] do not hold the machine's weight "
                f"({to_system(total, 'mass', units):.4g} {unit_label('mass', units)} under "
                "gravity): they have no stiffness in a direction the weight pushes, so it would fall")
    drops = [np.linalg.norm((shift.T @ sag)[:3]) for shift in shifts]
    worst = int(np.argmax(drops))
    if not drops[worst] > SAG_LIMIT:
        return ""
    length = unit_label("length", units)
    return (f"{model.source}: under gravity the machine would sag {to_system(drops[worst], 'length', units):.3g} "
            f"{length} at [suspensions.{visible(model.suspensions[worst].name)}] (static deflection on its "
            f"suspensions; mounts deflect millimetres, over {to_system(SAG_LIMIT, 'length', units):.3g} {length} "
            "is unlikely): is a stiffness in N/mm given as N/m, or a mass in g given as kg?")


def _under_weight(model, statics=None):
    """The static solution ``K q = weight`` of the checks (:func:`_static_stiffness`), or None
    where nothing holds the weight; solved once for the dict ``statics`` (the sag and the
    journals' loads read the same solution), on one BLAS thread (small dense work)."""
    statics = {} if statics is None else statics
    if "q" not in statics:
        with one_blas_thread(72 * model.dofs.n ** 2):
            statics["q"] = static_solution(_static_stiffness(model), weight_force(model))
    return statics["q"]


def _bearing_sag_lines(model, units: str = "si", statics=None) -> list[str]:
    """The warning about a rotor's static deflection in its bearings under gravity, or none: the
    motion of the rotor at each bearing point relative to the stator in the static solution
    ``K q = weight`` (:func:`_static_stiffness`): across the bearing and its pedestal's settling
    on its springs, over :data:`SAG_LIMIT`. A bearing stiffness in N/mm given as N/m (a speed
    table's too, or a pedestal's), a mass in g given as kg, or a gravity in mm/s^2 is the likely
    cause (the suspensions' own check, :func:`_sag_line`, sees only the stator).

    A plain journal bearing's own deflection is not named: its journal sits inside its clearance
    whatever the speed and load (at rest on the shell, running at ``c eps`` with ``eps < 1``), far
    below :data:`SAG_LIMIT`, so it stands on its film as a stiff spring (:func:`_static_stiffness`)
    and the check sees what else deflects: pedestals, another rotor's bearings, tables."""
    if all(b.coefficients.kind == "journal" and b.pedestal is None for b in model.bearings):
        return []                   # nothing but films, each within its clearance
    q = _under_weight(model, statics)
    if q is None:
        return []
    lateral = transverse_axes(model.spin_axis).T                                    # (3, 2)
    drops = []
    for b in model.bearings:
        rows, moves = bearing_motion(model, b)
        drop = np.zeros(3) if b.coefficients.kind == "journal" else (moves @ q[rows])[:3]
        if b.pedestal is not None:          # the pedestal's own settling on its springs
            drop = drop + lateral @ q[model.dofs.pedestal(b.name)]
        drops.append(float(np.linalg.norm(drop)))
    worst = int(np.argmax(drops))
    if not drops[worst] > SAG_LIMIT:
        return []
    b, length = model.bearings[worst], unit_label("length", units)
    return [f"{model.source}: under gravity rotor {visible(b.rotor)!r} would sag "
            f"{to_system(drops[worst], 'length', units):.3g} {length} at [bearings.{visible(b.name)}] (static "
            f"deflection of its bearings{' and pedestals' if model.dofs.pedestals else ''}; over {to_system(SAG_LIMIT, 'length', units):.3g} {length} is unlikely): is a "
            "stiffness in N/mm given as N/m, a mass in g given as kg, or gravity not in m/s^2?"]


def _static_stiffness(model) -> np.ndarray:
    """The stiffness ``K`` (n, n) of the static checks (:func:`_bearing_sag_lines`,
    :func:`_journal_load_lines`): suspensions, constant bearings, pedestals, shafts and meshes as
    assembled; a speed table at its first row, its lowest speed, the nearest to the machine at
    rest under its weight (a table in N/mm is so at every row); a plain journal bearing as its
    film at light load (:data:`~rotordyn_modal.elements.journal_bearing.LIGHT_LOAD_STIFFNESS`)
    carrying its rotor's whole weight, ``4/pi W / c`` along and ``8/pi W / c`` across the weight
    (:func:`_journal_static_piece`): a spring that holds the journal within its clearance, and
    one that does not follow the journal's ``load`` as given, which :func:`_journal_load_lines`
    checks against this solution."""
    stiffness, _ = constant_stiffness_damping(model)
    for bearing in model.bearings:
        kind = bearing.coefficients.kind
        if kind == "constant":
            continue
        k6 = bearing.coefficients.stiffness[0] if kind == "table" else _journal_static_piece(model, bearing)
        rows, moves = bearing_motion(model, bearing)
        stiffness[rows, rows] += moves.T @ k6 @ moves
    return stiffness


def _journal_static_piece(model, bearing) -> np.ndarray:
    """A journal bearing's 6x6 stiffness (model axes) in :func:`_static_stiffness`: its constant
    part and its light-load film at the weight ``W`` of its rotor normal to the spin axis (the
    journal's given ``load`` where gravity gives none)."""
    import dataclasses

    journal = bearing.coefficients.journal
    weight = _normal_weight(model, bearing.rotor)
    if weight > 0:
        journal = dataclasses.replace(journal, load=weight)
    return light_load_stiffness(dataclasses.replace(bearing.coefficients, journal=journal))


def _normal_weight(model, rotor: str) -> float:
    """The weight [N] of rotor ``rotor`` normal to the spin axis (0 without gravity there)."""
    e = np.asarray(model.spin_axis, dtype=float)
    g = np.asarray(model.gravity, dtype=float)
    mass = next(r.mass for r in model.rotors if r.name == rotor)
    return float(mass * np.linalg.norm(g - (g @ e) * e))


#: the factor by which a journal's given ``load`` may differ from its share of its rotor's weight
#: without a warning: a kN typed as N is 1000 times, statics and films keep a share within it
LOAD_FACTOR = 3.0
#: the least share of its rotor's weight [-] a journal must carry for its given load to be
#: compared: near zero (the centre of mass over the other bearing) the weight says nothing
LEAST_LOAD_SHARE = 0.05


def _journal_load_lines(model, units: str = "si", statics=None) -> list[str]:
    """A line for each journal bearing whose given ``load`` differs from its share of its rotor's
    weight by more than :data:`LOAD_FACTOR` (a load in kN typed as N, 1000 times too small, or a
    load in N typed 1000 times too large, a mass in other units): the film's coefficients follow
    that load.

    The share: the lever rule where the rotor stands on one or two bearings without a moment
    stiffness (statically determinate, exact whatever the supports); otherwise the journal's
    reaction in the static solution of the machine under the weights (:func:`_static_stiffness`;
    models of at most :data:`SAG_CHECK_DOF` coordinates, larger ones are left to ``static``). Only where ``gravity`` has a part normal to the spin axis: without it the
    given load is the only weight information and is taken as it is. A rotor in a transmission
    is left out (its journals carry tooth or belt forces the weight does not tell), and so is a
    journal whose share is below :data:`LEAST_LOAD_SHARE` of the weight."""
    geared = {name for t in model.transmissions for name in (t.driver, t.driven)}
    lines = []
    for rotor in model.rotors:
        weight = _normal_weight(model, rotor.name)
        mates = [b for b in model.bearings if b.rotor == rotor.name]
        given = [b for b in mates if b.coefficients.kind == "journal" and b.load is not None]
        if not given or not weight > 0 or rotor.name in geared:
            continue
        shares = _lever_shares(model, rotor, mates)
        if shares is None and model.dofs.n <= SAG_CHECK_DOF:
            q = _under_weight(model, statics)
            shares = None if q is None else [_reaction(model, b, q) for b in mates]
        if shares is None:
            continue
        for b in given:
            share, load = abs(shares[mates.index(b)]), float(b.load)
            if not share > LEAST_LOAD_SHARE * weight or max(load / share, share / load) <= LOAD_FACTOR:
                continue
            force = unit_label("force", units)
            how = "lever rule" if len(mates) < 3 and b.moment_stiffness is None else "static solution"
            cause = ("a load in kN typed as N, or the rotor's mass in g typed as kg" if load < share else
                     "a load typed 1000 times too large (in mN, or a weight from a mass in g), or the rotor's mass "
                     "in t typed as kg")
            lines.append(f"{model.source}: [bearings.{visible(b.name)}] load = {load:g}: {max(load / share, share / load):.4g} "
                         f"times {'below' if load < share else 'above'} its share of rotor {visible(rotor.name)!r}'s "
                         f"weight, {to_system(share, 'force', units):.4g} {force} ({how}; over {LOAD_FACTOR:g} times "
                         f"is unlikely, and the film's coefficients follow the load): {cause}? (model files are SI: N)")
    return lines


def _lever_shares(model, rotor, mates):
    """The force [N] each of ``mates`` carries of ``rotor``'s weight normal to the spin axis by
    statics alone (one bearing: all of it; two at different stations without a moment stiffness:
    the lever rule about the centre of mass), or None where the split is statically
    indeterminate."""
    weight = _normal_weight(model, rotor.name)
    if len(mates) == 1:
        return [weight]
    if len(mates) > 2 or any(b.moment_stiffness is not None for b in mates):
        return None
    e = np.asarray(model.spin_axis, dtype=float)
    s = [float((np.asarray(b.position, dtype=float) - np.asarray(rotor.center_of_mass, dtype=float)) @ e)
         for b in mates]
    if s[0] == s[1]:
        return None
    return [weight * s[1] / (s[1] - s[0]), weight * s[0] / (s[0] - s[1])]


def _reaction(model, bearing, q) -> float:
    """The force [N] bearing ``bearing`` carries normal to the spin axis in the static solution
    ``q`` of :func:`_static_stiffness`."""
    rows, moves = bearing_motion(model, bearing)
    kind = bearing.coefficients.kind
    k6 = (bearing.coefficients.stiffness[0] if kind != "journal" else _journal_static_piece(model, bearing))
    force = (k6 @ (moves @ q[rows]))[:3]
    e = np.asarray(model.spin_axis, dtype=float)
    return float(np.linalg.norm(force - (force @ e) * e))


def _mount_frequencies(model) -> np.ndarray:
    """The natural frequencies [Hz] of the rigid machine on its suspensions' static
    ``stiffness``, unrestrained directions (frequency zero) left out; shape (k,), k <= 6."""
    mass, stiffness, _ = _on_suspensions(model)
    roots = np.linalg.eigvals(np.linalg.solve(mass, stiffness))
    scale = np.abs(roots).max(initial=0.0)
    held = roots[roots.real > 1e-9 * scale]                 # unrestrained directions are not modes
    return np.sqrt(np.abs(held)) / (2 * np.pi)


def _low_mode_lines(model) -> list[str]:
    """The warning about a mode of the rigid machine on its suspensions below
    :data:`LOWEST_MOUNT_FREQUENCY`, or none."""
    frequencies = _mount_frequencies(model)
    if not frequencies.size:
        return []
    lowest = float(frequencies.min())
    if not lowest < LOWEST_MOUNT_FREQUENCY:
        return []
    return [f"{model.source}: the machine's lowest mode on its suspensions is at {lowest:.3g} Hz, below "
            f"{LOWEST_MOUNT_FREQUENCY:g} Hz (a stiffness in N/mm given as N/m, or a mass in g given as kg, puts modes 32 times too low)"]


def _low_rotor_mode_lines(model) -> list[str]:
    """The warning about a rigid-body mode of the rotors in their bearings below
    :data:`LOWEST_MOUNT_FREQUENCY`, or none: the undamped modes at rest of the constant supports
    with the stator held (its own modes on the suspensions are :func:`_low_mode_lines`'), of
    the symmetric part of the stiffness, whose strain energy lies mostly in the supports, not in
    a flexible shaft's bending (a long thin shaft bends at 0.2 Hz between rigid bearings: a
    legal mode, not a unit slip). Bearings tabulated over speed count with their coefficients at
    their table's lowest speed (a table in N/mm is so at every speed); plain journal bearings with
    their films as at light load (:func:`~rotordyn_modal.elements.bearings.light_load_stiffness`:
    a film has no stiffness at rest, and at any running speed it holds the journal with about
    its load over its clearance; docs/model-file.md, "Warnings")."""
    import scipy.linalg

    from .assembly import shaft_stiffness

    first = model.dofs.n_frame
    stiffness, _ = constant_stiffness_damping(model)
    stiffness = (stiffness + _speed_dependent_stiffness(model))[first:, first:]
    if not stiffness.size:
        return []
    mass = mass_matrix(model)[first:, first:]
    # rows and columns to one size first (N/m beside N m/rad), as static_solution does
    size = np.sqrt(np.abs(np.diag(mass)))
    size[size == 0] = 1.0
    scaled_k = 0.5 * (stiffness + stiffness.T) / np.outer(size, size)
    values, vectors = scipy.linalg.eigh(scaled_k, mass / np.outer(size, size))
    # validation refuses bearings that leave a rotor free in any of its motions, so no direction
    # is unrestrained here; a flexible shaft's stiff elements set the eigenvalues' round-off
    noise = 10 * len(values) * np.finfo(float).eps * np.abs(values).max(initial=0.0)
    low = np.flatnonzero(np.sqrt(np.maximum(values, noise)) / (2 * np.pi) < LOWEST_MOUNT_FREQUENCY)
    if not low.size:
        return []
    shapes = vectors[:, low] / size[:, None]
    bending = shaft_stiffness(model)[first:, first:]
    total = np.einsum("ik,ij,jk->k", shapes, 0.5 * (stiffness + stiffness.T), shapes)
    shaft = np.einsum("ik,ij,jk->k", shapes, bending, shapes)
    rigid = np.flatnonzero(shaft < 0.5 * np.abs(total))       # the supports hold most of its energy
    if not rigid.size:
        return []
    k, shape = low[rigid[0]], shapes[:, rigid[0]]
    lowest = float(np.sqrt(max(values[k], noise)) / (2 * np.pi))
    energy = shape * (mass @ shape)
    rotor = _coordinate_rotor(model, first + int(np.argmax(np.abs(energy))))
    at = f"at {lowest:.3g} Hz" if values[k] > noise else f"below {lowest:.2g} Hz (how far, round-off hides)"
    return [_low_rotor_line(model, rotor, at, "the stator held")]


def _low_rotor_line(model, rotor: str, at: str, how: str) -> str:
    """The one line of :func:`_low_rotor_mode_lines` and :func:`_rigid_rotor_bound_lines`: rotor
    ``rotor``'s rigid-body mode ``at`` ("at 0.02 Hz"), found with ``how`` (what was held). A rotor
    on journal bearings is told what sets a film's stiffness (its load over its clearance: the
    rotor's mass cancels where the film carries its weight)."""
    held_by = [f"[bearings.{visible(b.name)}]" for b in model.bearings if b.rotor == rotor]
    kinds = {b.coefficients.kind for b in model.bearings if b.rotor == rotor}
    when = "at their tables' lowest speeds" if "table" in kinds else "at rest"
    if "journal" in kinds:
        when = "journal films at light load" if kinds == {"journal"} else f"{when}, journal films at light load"
        cause = ("a journal film holds about its load over its clearance: a load in kN given as N, or a mass in g "
                 "given as kg, or an inertia in kg mm^2 given as kg m^2, puts modes 32 times too low or more")
    else:
        cause = "a stiffness in N/mm given as N/m, or a mass in g given as kg, puts modes 32 times too low"
    return (f"{model.source}: rotor {visible(rotor)!r} has a rigid-body mode {at} in its bearings "
            f"({', '.join(held_by[:3])}{', ...' if len(held_by) > 3 else ''}; {when}, {how}), below "
            f"{LOWEST_MOUNT_FREQUENCY:g} Hz, where bearings hold a rotor far stiffer: {cause}")


def _rigid_rotor_bound_lines(model) -> list[str]:
    """:func:`_low_rotor_mode_lines` for a model over :data:`SAG_CHECK_DOF` coordinates, where a
    dense eigen-solution costs too much on every load: each rotor moved as a rigid body in its
    bearings, the stator, the other rotors and the pedestals held (Rayleigh-Ritz on the rotor's
    4 or 5 rigid motions, from the sparse stiffness). The lowest value is an upper bound of the
    machine's lowest mode at rest with the stator held, so a bound below
    :data:`LOWEST_MOUNT_FREQUENCY` means a mode below it; the shape strains no shaft. Speed tables
    count at their lowest speed and journal films as at light load, as there. One line, for the
    rotor of the lowest bound."""
    from .assembly import _sparse_mass, _sparse_stiffness_damping

    dofs = model.dofs
    # the sparse K and M of sparse_constant_matrices, without its gyroscopic matrix (a fifth of its cost)
    stiffness, mass = _rotor_blocks(_sparse_stiffness_damping(model)[0], dofs), _rotor_blocks(_sparse_mass(model), dofs)
    rigid = [_rigid_motions(dofs.shafts[j] if dofs.shafts else None, rows.stop - rows.start)
             for j, rows in enumerate(dofs.slices)]
    reduced = [(r.T @ (0.5 * (k + k.T)) @ r, r.T @ m @ r) for r, k, m in zip(rigid, stiffness, mass)]
    for bearing, k6 in _speed_dependent_pieces(model):
        j = dofs.rotors.index(bearing.rotor)
        moves = dofs.local_relative_motion(bearing.rotor, bearing.position) @ rigid[j]
        reduced[j] = (reduced[j][0] + moves.T @ (0.5 * (k6 + k6.T)) @ moves, reduced[j][1])
    lowest = _lowest_generalized(reduced)
    if not lowest.size:
        return []
    j = int(np.argmin(lowest))
    bound = float(np.sqrt(max(lowest[j], 0.0)) / (2 * np.pi))
    if not bound < LOWEST_MOUNT_FREQUENCY:
        return []
    return [_low_rotor_line(model, dofs.rotors[j], f"at {bound:.3g} Hz or below", "moved as a rigid body, the rest held")]


def _rotor_blocks(matrix, dofs) -> list:
    """The diagonal block of each rotor's coordinates of the sparse ``matrix``, dense, in
    ``dofs.rotors``' order: one pass over its entries (a slice per rotor cost 0.3 ms each)."""
    coo = matrix.tocoo()
    owner = np.full(dofs.n, -1)
    for j, rows in enumerate(dofs.slices):
        owner[rows] = j
    keep = (owner[coo.row] == owner[coo.col]) & (owner[coo.row] >= 0)
    rows, cols, values, which = coo.row[keep], coo.col[keep], coo.data[keep], owner[coo.row[keep]]
    blocks = [np.zeros((s.stop - s.start, s.stop - s.start)) for s in dofs.slices]
    starts = np.array([s.start for s in dofs.slices])
    order = np.argsort(which, kind="stable")
    bounds = np.searchsorted(which[order], np.arange(len(blocks) + 1))
    for j, block in enumerate(blocks):
        part = order[bounds[j]:bounds[j + 1]]
        np.add.at(block, (rows[part] - starts[j], cols[part] - starts[j]), values[part])
    return blocks


def _lowest_generalized(pairs) -> np.ndarray:
    """The lowest eigenvalue of each symmetric pencil ``(K, M)`` of ``pairs`` (M positive
    definite), those of one size solved together (Cholesky of M, then eigvalsh), shape (len,)."""
    lowest = np.empty(len(pairs))
    sizes = {}
    for j, (k, _) in enumerate(pairs):
        sizes.setdefault(k.shape[0], []).append(j)
    for size, index in sizes.items():
        k = np.array([pairs[j][0] for j in index])
        factor = np.linalg.cholesky(np.array([pairs[j][1] for j in index]))
        left = np.linalg.solve(factor, k)
        lowest[index] = np.linalg.eigvalsh(np.linalg.solve(factor, left.transpose(0, 2, 1)))[:, 0]
    return lowest


def _rigid_motions(shaft, width: int) -> np.ndarray:
    """A rotor's coordinates (``width``) per rigid motion of it: the identity for a rigid rotor;
    for a flexible one (:func:`rotordyn_modal.model.dofs._node_motions`: ``u_a, u_b, theta_a,
    theta_b`` per node, then the axial one) the translations along ``a, b`` and the tilts about
    them at the shaft's start, node ``z``'s ``u = U + Theta x (z e)`` (``a x e = -b``,
    ``b x e = a``), and the axial translation, shape (width, 4 or 5)."""
    if shaft is None:
        return np.eye(width)
    z = shaft.mesh.z
    columns = np.zeros((width, 5 if width % 4 else 4))
    nodes = 4 * np.arange(len(z))
    columns[nodes, 0] = 1.0                  # U_a
    columns[nodes + 1, 1] = 1.0              # U_b
    columns[nodes + 2, 2] = 1.0              # Theta_a: u_b = -z Theta_a
    columns[nodes + 1, 2] = -z
    columns[nodes + 3, 3] = 1.0              # Theta_b: u_a = z Theta_b
    columns[nodes, 3] = z
    if width % 4:
        columns[-1, 4] = 1.0
    return columns


def _speed_dependent_stiffness(model) -> np.ndarray:
    """The stiffness [N/m, N m/rad] of the bearings whose coefficients depend on speed, as the
    rigid-body checks take them (:func:`_speed_dependent_pieces`), shape (n, n); zeros without
    such bearings."""
    n = model.dofs.n
    stiffness = np.zeros((n, n))
    for bearing, k6 in _speed_dependent_pieces(model):
        rows, moves = bearing_motion(model, bearing)
        stiffness[rows, rows] += moves.T @ k6 @ moves
    return stiffness


def _speed_dependent_pieces(model):
    """``(bearing, K (6, 6))`` of each bearing whose coefficients depend on speed, model axes at
    the bearing point [N/m, N/rad, N m/m, N m/rad]: a table at its first (lowest) speed (a table
    in N/mm is so at every speed), a plain journal bearing with its film as at light load
    (:func:`~rotordyn_modal.elements.bearings.light_load_stiffness`)."""
    for bearing in model.bearings:
        if bearing.coefficients.kind == "table":
            yield bearing, bearing.coefficients.stiffness[0]
        elif bearing.coefficients.kind == "journal":
            yield bearing, light_load_stiffness(bearing.coefficients)


def _coordinate_rotor(model, index: int) -> str:
    """The rotor whose coordinates (or whose bearing's pedestal) hold coordinate ``index``."""
    dofs = model.dofs
    for name, rows in zip(dofs.rotors, dofs.slices):
        if rows.start <= index < rows.stop:
            return name
    for bearing, rows in dofs.pedestals:
        if rows.start <= index < rows.stop:
            return next(b.rotor for b in model.bearings if b.name == bearing)
    return dofs.rotors[0]


#: the largest ``maxwell_time`` x the lowest mount mode's angular frequency that draws no warning:
#: beyond it the branch dissipates at most 1 % of its stiffness at the machine's modes (its loss
#: ``k_b w tau / (1 + (w tau)^2)`` peaks at ``w tau = 1``) and is a plain spring there
SLOW_MAXWELL = 100.0


def _slow_maxwell_lines(model) -> list[str]:
    """A line for the slowest Maxwell branch whose relaxation time ``tau`` is more than
    :data:`SLOW_MAXWELL` / ``w_low`` (``w_low`` the lowest mode of the rigid machine on its
    suspensions' static stiffness, rad/s): a time in ms typed for s (20 for 0.02) relaxes a
    thousand times too slowly and damps nothing at the modes. One line for the model."""
    timed = [(tau, s, i) for s in model.suspensions for i, tau in enumerate(s.maxwell_time or ())]
    if not timed:
        return []
    try:
        with np.errstate(all="ignore"):
            frequencies = _mount_frequencies(model)
    except (np.linalg.LinAlgError, ValueError):
        return []
    if not frequencies.size:
        return []
    lowest = float(frequencies.min())
    tau, mount, i = max(timed, key=lambda t: t[0])
    if not 2 * np.pi * lowest * tau > SLOW_MAXWELL:
        return []
    slow = sum(1 for t, _, _ in timed if 2 * np.pi * lowest * t > SLOW_MAXWELL)
    others = f" (and {slow - 1} more branch{'es' if slow > 2 else ''})" if slow > 1 else ""
    return [f"{model.source}: [suspensions.{visible(mount.name)}] maxwell_time[{i}] = {tau:g}{others}: the branch "
            f"relaxes at 1/(2 pi tau) = {1 / (2 * np.pi * tau):.3g} Hz, {2 * np.pi * lowest * tau:.4g} times below the "
            f"machine's lowest mode on its mounts ({lowest:.3g} Hz; beyond {SLOW_MAXWELL:g} times it damps nothing "
            "there and acts as a plain spring): a relaxation time in ms typed for s? (model files are SI: 0.02 for 20 ms)"]


#: the most radii of gyration (sqrt(largest inertia / mass)) a rigid body's bearing or mount point
#: lies from its centre of mass without a warning: a machine's mounts and bearings sit within a
#: few (a disk on a long massless rod, 6), while positions in mm typed for m put them 1000 times
#: farther
FAR_POINT = 100.0


def _far_point_lines(model) -> list[str]:
    """A line for each rigid body (the stator, a rigid rotor) whose farthest mount or bearing point
    lies more than :data:`FAR_POINT` of its radii of gyration from its centre of mass: positions in
    mm typed for m (the rocking and tilting modes then come out far too stiff, without another
    word), or an inertia typed as a radius of gyration. Flexible rotors are left to their
    shaft's length (:func:`~rotordyn_modal.model.flexible.size_lines`)."""
    import math

    bodies = []
    if model.stator is not None:
        points = [("suspensions", s.name, s.position) for s in model.suspensions]
        points += [("bearings", b.name, b.position) for b in model.bearings if getattr(b, "pedestal", None) is None]
        inertia = np.asarray(model.stator.inertia, dtype=float)
        largest = float(np.max(inertia)) if inertia.ndim == 1 else float(np.linalg.eigvalsh(inertia)[-1])
        bodies.append(("the stator's", model.stator.mass, largest, model.stator.center_of_mass, points))
    carried = {}
    for b in model.bearings:
        carried.setdefault(b.rotor, []).append(("bearings", b.name, b.position))
    for rotor in model.rotors:
        if rotor.flexible is None:
            bodies.append((f"rotor {visible(rotor.name)!r}'s", rotor.mass, max(rotor.polar_inertia,
                           rotor.diametral_inertia), rotor.center_of_mass, carried.get(rotor.name, ())))
    lines = []
    for body, mass, largest, centre, points in bodies:
        if not points or not largest > 0 or not mass > 0:
            continue
        radius = math.sqrt(largest / mass)
        centre = [float(v) for v in centre]
        far = [(math.dist([float(v) for v in p], centre), table, name, p) for table, name, p in points]
        distance, table, name, point = max(far, key=lambda f: f[0])
        if not distance > FAR_POINT * radius:
            continue
        count = sum(1 for d, *_ in far if d > FAR_POINT * radius)
        others = and_others(count, "point")
        shown = "[" + ", ".join(f"{float(v):g}" for v in point) + "]"
        lines.append(f"{model.source}: [{table}.{visible(name)}] position = {shown}{others}: {distance:.3g} m from "
                     f"{body} centre of mass, {distance / radius:.3g} times its largest radius of gyration sqrt(I/m) = "
                     f"{radius:.3g} m (mounts and bearings sit within a few; beyond {FAR_POINT:g} its tilting modes "
                     "come out far too stiff): positions in mm typed for m, or an inertia typed as a radius of "
                     "gyration (I = m r^2)? (model files are SI)")
    return lines


def _circulatory_mount_lines(model) -> list[str]:
    """A line for each suspension whose ``stiffness``, ``damping`` or Maxwell branch is a matrix
    typed as one triangle (every entry on one side of the diagonal zero, some on the other not):
    a passive mount's matrices are symmetric, and the model takes the antisymmetric half such a
    matrix has as a cross-coupled (circulatory) support (docs/model-file.md), which can make the
    machine unstable. A matrix with both halves given (``[[k, q], [-q, k]]``, a cross-coupled
    support on purpose) draws no line."""
    lines = []
    for mount in model.suspensions:
        given = [("stiffness", mount.stiffness), ("damping", mount.damping)]
        given += [(f"maxwell_stiffness[{b}]", branch) for b, branch in enumerate(mount.maxwell_stiffness or ())]
        for key, value in given:
            found = _one_triangle(value)
            if found is None:
                continue
            i, j, a = found
            lines.append(f"{model.source}: [suspensions.{visible(mount.name)}] {key}[{i}][{j}] = {a:g} but "
                         f"{key}[{j}][{i}] = 0, and so for every pair: a matrix typed as one triangle? A passive "
                         "mount's matrix is symmetric (give both halves); as given, half of it is taken as an "
                         "antisymmetric (circulatory) part, a cross-coupled support (docs/model-file.md) that can "
                         "make the machine unstable")
    return lines


def _one_triangle(value):
    """``(i, j, value[i][j])`` of the largest entry of a square matrix whose entries on one side
    of the diagonal are all zero and on the other not, or None (a list, a full matrix, none given)."""
    try:
        matrix = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return None
    if matrix.ndim != 2 or matrix.shape[0] != matrix.shape[1] or matrix.shape[0] < 2:
        return None
    upper, lower = np.triu(matrix, 1), np.tril(matrix, -1)
    if np.any(upper) == np.any(lower):
        return None
    half = upper if np.any(upper) else lower
    i, j = np.unravel_index(int(np.argmax(np.abs(half))), half.shape)
    return int(i), int(j), float(matrix[i, j])
