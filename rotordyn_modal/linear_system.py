"""The linear system ``M q'' + (C + Omega G) q' + K q = B_f u``, ``y = C_s q``, in state space.

State ``x = [q, q']`` (``2n`` states for ``n`` generalized coordinates, see
:mod:`rotordyn_modal.model.dofs`), then six states per Maxwell branch of the mounts.
With constant coefficients ``A(Omega) = A0 + Omega A1`` with::

    A0 = [[0, I], [-M^-1 K, -M^-1 C]],   A1 = [[0, 0], [0, -M^-1 G]]

so that all speeds of a sweep are built in one broadcast. Bearings whose
coefficients depend on speed add ``[[0, 0], [-M^-1 K_b(Omega), -M^-1 C_b(Omega)]]``,
evaluated for all speeds at once (each bearing only touches its rotor's columns).
"""

from __future__ import annotations

import contextlib

import numpy as np

from ._blas import one_blas_thread
from .assembly import Matrices, bearing_motion, body_inertias, constant_matrices, constant_stiffness_damping, \
    dependent_bearing_matrices, excitation_columns, is_large, mass_matrix, rigid_mass_matrix, \
    sensor_rows, sparse_constant_matrices, weight_force
from .elements.bearings import evaluate
from .elements._bearing_validation import LONG_JOURNAL
from .model._table import and_others, visible
from .errors import InputError, ModelError
from .model.dofs import frame_block
from .model.geometry import shift_matrix
from .units import to_system, unit_label
from .elements.mounts import maxwell_branch_blocks, with_branch_states

__all__ = ["SpeedLinearForm", "speed_linear_form", "kept_form", "checked_mass_inverse", "implausible", "SAG_LIMIT",
           "stiffness_spread_lines", "support_spreads", "maxwell_spread_lines", "MAXWELL_REFUSE_DIGITS", "SPREAD_WARN_DIGITS", "SPREAD_REFUSE_DIGITS",
           "LOWEST_MOUNT_FREQUENCY", "same_inertia", "state_matrices", "state_space", "static_solution"]

_QUANTITY_ORDER = {"displacement": 0, "receptance": 0, "velocity": 1, "mobility": 1,
                   "acceleration": 2, "accelerance": 2}


def _mass_inverse(M: np.ndarray, model) -> np.ndarray:
    """The inverse of the mass matrix, or a :class:`ModelError` when rounding leaves it singular
    (masses and inertias, with their arms, many orders of magnitude apart)."""
    try:
        with one_blas_thread(72 * M.size):          # faster than BLAS's threads (rotordyn_modal/_blas.py)
            inverse = np.linalg.inv(M)
            residual = np.abs(inverse @ M - np.eye(M.shape[0])).max()
    except np.linalg.LinAlgError:
        inverse, residual = None, np.inf
    if not residual < 1e-3:
        raise ModelError(model.source, "[stator], [[rotors]] mass and inertia", "<mass matrix>",
                         "masses and inertias (with their arms to the reference point) that leave the "
                         "mass matrix invertible in double precision; they span too many orders of magnitude")
    return inverse


def _mass_factor(M, model):
    """A sparse LU factorisation of a large model's mass matrix ``M`` (``scipy.sparse``), with the
    check of :func:`_mass_inverse` (``|M^-1 M - I|`` below 1e-3) made a block of columns at a time
    (never an ``n x n`` array), or a :class:`ModelError`."""
    import scipy.sparse.linalg

    n = M.shape[0]
    residual = np.inf
    try:
        factor = scipy.sparse.linalg.splu(M.tocsc())
        # blocks of at most 16 MB and an eighth of the columns: the check's peak stays a small
        # part of one dense n x n array whatever the size (the FRF and unbalance routes of a large
        # model hold less than half of one)
        residual, step = 0.0, max(1, min((1 << 24) // (8 * n), -(-n // 8)))
        for start in range(0, n, step):
            stop = min(n, start + step)
            part = factor.solve(M[:, start:stop].toarray())
            part[np.arange(start, stop), np.arange(stop - start)] -= 1.0
            residual = max(residual, float(np.abs(part).max()))
    except RuntimeError:          # SuperLU: "Factor is exactly singular"
        factor = None
    if not residual < 1e-3:
        raise ModelError(model.source, "[stator], [[rotors]] mass and inertia", "<mass matrix>",
                         "masses and inertias (with their arms to the reference point) that leave the "
                         "mass matrix invertible in double precision; they span too many orders of magnitude")
    return factor


def checked_mass_inverse(model) -> np.ndarray:
    """The inverse of ``model``'s mass matrix, shape (n, n) [1/kg, 1/(kg m), 1/(kg m^2)]: the
    check every analysis and the time simulation make before any work.

    Raises
    ------
    ModelError
        Masses and inertias so many orders of magnitude apart that rounding leaves the mass
        matrix singular.
    """
    return _mass_inverse(mass_matrix(model), model)


#: static sag [m] of a suspension point under the machine's weight above which a model draws a
#: warning: rubber mounts and steel springs deflect millimetres to a few centimetres (a 1.6 Hz
#: mount mode already sags 0.1 m, since f = sqrt(g / sag) / (2 pi)); metres mean a stiffness in
#: N/mm given as N/m or a mass in g given as kg (either makes the sag 1000 times too large)
SAG_LIMIT = 0.1
#: the most coordinates of a model whose rotors' sag in their bearings is looked at when it is
#: read (a dense SVD of the stiffness, about 50 ms at this size on one thread: 0.3 s at 381;
#: larger models are left to ``static``)
SAG_CHECK_DOF = 200
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
    * Without such a sag line, a rotor in its constant bearings under ``gravity`` deflecting more
      than :data:`SAG_LIMIT` at a bearing point (:func:`_bearing_sag_lines`; models of at most
      :data:`SAG_CHECK_DOF` coordinates).
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
    lines, sag, held = [], "", []
    if model.suspensions:
        try:   # a model whose numbers overflow here is refused by its analyses, not by a warning
            with np.errstate(all="ignore"):
                sag = _sag_line(model, units)
                lines += [sag] if sag else _low_mode_lines(model)
        except (np.linalg.LinAlgError, ValueError):
            pass
    # one sag line for one mistake: the machine's on its suspensions already names the units
    if model.bearings and not sag and model.dofs.n <= SAG_CHECK_DOF:
        try:       # small dense work: one BLAS thread (a busy machine's many threads took 0.3 s for 68x68)
            with np.errstate(all="ignore"), one_blas_thread(72 * model.dofs.n ** 2):
                held = _bearing_sag_lines(model, units) if np.any(model.gravity) else []
                lines += held or _low_rotor_mode_lines(model)
        except (np.linalg.LinAlgError, ValueError):
            pass
    elif model.bearings and not sag:
        try:
            with np.errstate(all="ignore"):
                lines += _rigid_rotor_bound_lines(model)
        except (np.linalg.LinAlgError, ValueError):
            pass
    for b in model.bearings:
        journal = b.coefficients.journal
        if journal is not None and journal.length > LONG_JOURNAL * journal.diameter:
            lines.append(f"{model.source}: [bearings.{visible(b.name)}] length = {journal.length:g}: "
                         f"L/D = {journal.length / journal.diameter:.3g} is beyond {LONG_JOURNAL:g}, where "
                         "short-bearing (Ocvirk) theory stops matching measurements: its coefficients are rough")
    # a mass far too large (g typed as kg) makes the radii of gyration small too: said once, by the sag
    far = [] if sag or held else _far_point_lines(model)
    return lines + far + _circulatory_mount_lines(model) + _slow_maxwell_lines(model) + _merge_lines(model) \
        + _material_lines(model) + _clearance_lines(model) + _spread_lines(model)


def _spread_lines(model) -> list[str]:
    """:func:`stiffness_spread_lines` and :func:`maxwell_spread_lines`, the stiffness scales of
    the machine found once for both (:func:`_support_scales`). A model they do not refuse is
    marked, so that :func:`refuse_lost_digits` does not look again."""
    parts = _support_scales(model)
    lines = stiffness_spread_lines(model, parts) + maxwell_spread_lines(model, parts)
    model._digits_checked = True
    return lines


def refuse_lost_digits(model) -> None:
    """Refuse ``model`` (:class:`ModelError`) where a support or a Maxwell branch leaves its low
    modes no digit in double precision, as ``load_model`` and ``check`` do: the check every
    analysis makes (:class:`SpeedLinearForm`), so that a model built in Python
    (``Model.from_dict``, ``Model.variant``: no ``implausible``) or a study's variant gives no
    silently wrong answer. Looked at once per model; the warnings below the refusal are
    :func:`implausible`'s."""
    if not getattr(model, "_digits_checked", False):
        _spread_lines(model)


#: the largest radial running clearance [m] of a close-clearance station that draws no warning:
#: seals and impeller eyes run 0.1 to 2 mm
CLEARANCE_WARN = 0.01


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


def _bearing_sag_lines(model, units: str = "si") -> list[str]:
    """The warning about a rotor's static deflection in its bearings under gravity, or none: the
    relative motion at each bearing point in the static solution ``K q = weight`` of the
    constant supports (a model with speed-dependent bearings, whose static position is their
    film's, is left to its analyses). Over :data:`SAG_LIMIT` a bearing stiffness in N/mm given as
    N/m, a mass in g given as kg, or a gravity in mm/s^2 is the likely cause (the suspensions'
    own check, :func:`_sag_line`, sees only the stator)."""
    if any(b.coefficients.kind != "constant" for b in model.bearings):
        return []
    stiffness, _ = constant_stiffness_damping(model)
    q = static_solution(stiffness, weight_force(model))
    if q is None:
        return []
    drops = []
    for b in model.bearings:
        rows, moves = bearing_motion(model, b)
        drops.append(float(np.linalg.norm((moves @ q[rows])[:3])))
    worst = int(np.argmax(drops))
    if not drops[worst] > SAG_LIMIT:
        return []
    b, length = model.bearings[worst], unit_label("length", units)
    return [f"{model.source}: under gravity rotor {visible(b.rotor)!r} would sag "
            f"{to_system(drops[worst], 'length', units):.3g} {length} at [bearings.{visible(b.name)}] (static "
            f"deflection of its bearings; over {to_system(SAG_LIMIT, 'length', units):.3g} {length} is unlikely): is a "
            "stiffness in N/mm given as N/m, a mass in g given as kg, or gravity not in m/s^2?"]


def static_solution(stiffness: np.ndarray, load: np.ndarray):
    """``x`` with ``stiffness @ x = load`` (least norm where directions are free), or None when
    the load pushes a direction that nothing holds. Rows and columns are scaled to one size
    first (N/m beside N m/rad, long arms), so that only a stiffness singular to round-off, not
    one of mixed units, counts as free.

    Parameters
    ----------
    stiffness : ndarray, shape (n, n) [N/m, N/rad, N m/m, N m/rad]
    load : ndarray, shape (n,) [N, N m]

    Returns
    -------
    ndarray, shape (n,) [m, rad], or None
    """
    size = np.sqrt(np.linalg.norm(stiffness, axis=0) * np.linalg.norm(stiffness, axis=1))
    held = size > 0
    if np.any(np.abs(load[~held]) > 1e-9 * np.abs(load).max()):
        return None
    # D^-1/2 K D^-1/2, unit diagonal (K / (size_i size_j) made it 1 / K_ii: the stiffest
    # coordinates, a shaft's, looked like the free ones beside soft bearings)
    root = np.sqrt(size[held])
    scaled = stiffness[np.ix_(held, held)] / np.outer(root, root)
    u, values, vt = np.linalg.svd(scaled)
    right = load[held] / root
    # zero to round-off (numpy's matrix_rank tolerance): a fixed 1e-12 took a shaft on soft
    # bearings (100 N/m under a stiff shaft, 3e-13 of the largest, 8 digits sure) for free
    kept = values > len(values) * np.finfo(float).eps * values[0]
    if np.linalg.norm(u[:, ~kept].T @ right) > 1e-6 * np.linalg.norm(right):
        return None
    x = np.zeros(len(load))
    x[held] = (vt[kept].T @ ((u[:, kept].T @ right) / values[kept])) / root
    return x


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
    their table's lowest speed (a table in N/mm is so at every speed). A model with journal
    bearings is left out: a film has no stiffness at rest, and its running one follows the speed
    (docs/model-file.md, "Warnings")."""
    import scipy.linalg

    from .assembly import shaft_stiffness

    if any(b.coefficients.kind == "journal" for b in model.bearings):
        return []
    first = model.dofs.n_frame
    stiffness, _ = constant_stiffness_damping(model)
    stiffness = (stiffness + _lowest_table_stiffness(model))[first:, first:]
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
    ``rotor``'s rigid-body mode ``at`` ("at 0.02 Hz"), found with ``how`` (what was held)."""
    held_by = [f"[bearings.{visible(b.name)}]" for b in model.bearings if b.rotor == rotor]
    when = ("at their tables' lowest speeds" if any(b.coefficients.kind == "table" for b in model.bearings
                                                     if b.rotor == rotor) else "at rest")
    return (f"{model.source}: rotor {visible(rotor)!r} has a rigid-body mode {at} in its bearings "
            f"({', '.join(held_by[:3])}{', ...' if len(held_by) > 3 else ''}; {when}, {how}), below "
            f"{LOWEST_MOUNT_FREQUENCY:g} Hz, where bearings hold a rotor far stiffer: a stiffness in N/mm given as "
            "N/m, or a mass in g given as kg, puts modes 32 times too low")


def _rigid_rotor_bound_lines(model) -> list[str]:
    """:func:`_low_rotor_mode_lines` for a model over :data:`SAG_CHECK_DOF` coordinates, where a
    dense eigen-solution costs too much on every load: each rotor moved as a rigid body in its
    bearings, the stator, the other rotors and the pedestals held (Rayleigh-Ritz on the rotor's
    4 or 5 rigid motions, from the sparse stiffness). The lowest value is an upper bound of the
    machine's lowest mode at rest with the stator held, so a bound below
    :data:`LOWEST_MOUNT_FREQUENCY` means a mode below it; the shape strains no shaft. Journal
    bearings are left out as there; speed tables count at their lowest speed. One line, for the
    rotor of the lowest bound."""
    from .assembly import _sparse_mass, _sparse_stiffness_damping

    if any(b.coefficients.kind == "journal" for b in model.bearings):
        return []
    dofs = model.dofs
    # the sparse K and M of sparse_constant_matrices, without its gyroscopic matrix (a fifth of its cost)
    stiffness, mass = _rotor_blocks(_sparse_stiffness_damping(model)[0], dofs), _rotor_blocks(_sparse_mass(model), dofs)
    rigid = [_rigid_motions(dofs.shafts[j] if dofs.shafts else None, rows.stop - rows.start)
             for j, rows in enumerate(dofs.slices)]
    reduced = [(r.T @ (0.5 * (k + k.T)) @ r, r.T @ m @ r) for r, k, m in zip(rigid, stiffness, mass)]
    for bearing in model.bearings:
        if bearing.coefficients.kind == "table":
            j = dofs.rotors.index(bearing.rotor)
            moves = dofs.local_relative_motion(bearing.rotor, bearing.position) @ rigid[j]
            k6 = bearing.coefficients.stiffness[0]
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


def _lowest_table_stiffness(model) -> np.ndarray:
    """The stiffness [N/m, N m/rad] of the bearings tabulated over speed, each at its table's
    first (lowest) speed, shape (n, n); zeros without such bearings."""
    n = model.dofs.n
    stiffness = np.zeros((n, n))
    for bearing in model.bearings:
        if bearing.coefficients.kind == "table":
            rows, moves = bearing_motion(model, bearing)
            stiffness[rows, rows] += moves.T @ bearing.coefficients.stiffness[0] @ moves
    return stiffness


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


class SpeedLinearForm:
    """The state matrix ``A(Omega) = A0 + Omega A1 (+ A_b(Omega))`` with M and its inverse.

    A model of more than :data:`~rotordyn_modal.assembly.SPARSE_DOF` coordinates keeps its
    matrices sparse (``sparse``) and its mass matrix as a sparse LU factorisation: the dense
    ``matrices`` and ``mass_inverse`` are made only where an analysis asks for them (the state
    matrices of every root, python-control), never by the lowest modes, FRFs or unbalance
    responses (docs/theory.md §17, "Large models: what grows with n").

    Parameters
    ----------
    model : Model
    like : SpeedLinearForm, optional
        The form of a model with the very same bodies and coordinates (a study's variant
        and its base, see :meth:`~rotordyn_modal.model.machine.Model.same_bodies`): its ``M``, ``G``
        and ``M^-1`` are taken, not computed again (they are the same numbers).

    Attributes
    ----------
    matrices : Matrices
        ``M, C, G, K`` of the parts that do not depend on speed, dense (n, n) each (of a large
        model made from ``sparse`` on first use).
    sparse : Matrices or None
        The same as ``scipy.sparse`` CSR matrices for a large model, else None.
    n_dof : int
        Number of generalized coordinates n.
    A0, A1 : ndarray, shape (n_states, n_states)
    mass_inverse : ndarray, shape (n, n)
        (Of a large model made on first use from the factorisation.)
    speed_dependent : bool
        True when bearing coefficients depend on speed (then A is not linear in speed).
    branch_blocks : ndarray, shape (n_branches, 6, 6)
        The mounts' Maxwell branches' stiffness at the reference point [N/m, ...] (the stator's
        six motions; ``branch_stiffness`` (n_branches, n, n) places them, made on first use).
    branch_times : ndarray, shape (n_branches,)
        Their relaxation times [s].
    """

    def __init__(self, model, like: "SpeedLinearForm | None" = None):
        self.model = model
        self.sparse = self._dense = self._inverse = self.mass_factor = None
        if like is not None and same_inertia(like.model, model) and like.sparse is not None:
            self.sparse = sparse_constant_matrices(model)._replace(M=like.sparse.M, G=like.sparse.G)
            self.mass_factor = like.mass_factor
        elif like is not None and same_inertia(like.model, model):
            K, C = constant_stiffness_damping(model)
            self._dense = Matrices(M=like.matrices.M, C=C, G=like.matrices.G, K=K)
            self._inverse = like.mass_inverse
        elif is_large(model):
            self.sparse = sparse_constant_matrices(model)
            self.mass_factor = _mass_factor(self.sparse.M, model)
        else:
            self._dense = constant_matrices(model)
            self._inverse = _mass_inverse(self._dense.M, model)
        refuse_lost_digits(model)
        self.n_dof = model.dofs.n if self._dense is None else self._dense.M.shape[0]
        # the Maxwell branches as 6x6 blocks on the stator's motion: their n x n arrays
        # (``branch_stiffness``) are made only where an analysis asks for them
        self.branch_blocks, self.branch_times = maxwell_branch_blocks(model)
        self._branch_stiffness = None
        self._states = None        # (A0, A1, branch state names), made on first use
        self._dependent = _dependent_bearings(model, self._inverse_columns)
        self.speed_dependent = bool(self._dependent)

    @property
    def matrices(self) -> Matrices:
        """``M, C, G, K`` dense (n, n) each; a large model's made from its sparse ones on first use."""
        if self._dense is None:
            self._dense = Matrices(*(matrix.toarray() for matrix in self.sparse))
        return self._dense

    @property
    def branch_stiffness(self) -> np.ndarray:
        """The Maxwell branches' stiffness ``B_SP K_b B_SP^T`` on the stator's coordinates,
        (n_branches, n, n) [N/m, ...], made from ``branch_blocks`` (n_branches, 6, 6) on first use."""
        if self._branch_stiffness is None:
            self._branch_stiffness = frame_block(self.model, self.branch_blocks)
        return self._branch_stiffness

    @property
    def mass_inverse(self) -> np.ndarray:
        """``M^-1`` (n, n); a large model's solved from its factorisation on first use."""
        if self._inverse is None:
            self._inverse = self.mass_factor.solve(np.eye(self.n_dof))
        return self._inverse

    def _inverse_columns(self, rows) -> np.ndarray:
        """The columns ``rows`` (a slice or indices) of ``M^-1``, (n, k), without the whole inverse
        of a large model."""
        if self._inverse is not None:
            return self._inverse[:, rows]
        index = np.arange(self.n_dof)[rows]
        unit = np.zeros((self.n_dof, len(index)))
        unit[index, np.arange(len(index))] = 1.0
        return self.mass_factor.solve(unit)

    @property
    def A0(self) -> np.ndarray:
        """``A0`` (n_states, n_states), made on first use (the lowest modes and the FRFs of a
        large model work on M, C, G, K and never build the 2n x 2n state matrices)."""
        return self._state_matrices()[0]

    @property
    def A1(self) -> np.ndarray:
        """``A1`` (n_states, n_states), made on first use."""
        return self._state_matrices()[1]

    @property
    def branch_state_names(self) -> list:
        """Names of the Maxwell branches' states (see ``with_branch_states``)."""
        return self._state_matrices()[2]

    def _state_matrices(self):
        """``A0``, ``A1`` and the branch states' names, made once: ``[[0, I], [-M^-1 K, -M^-1 C]]``
        and ``[[0, 0], [0, -M^-1 G]]``, with the rubber mounts' Maxwell branches' 6 first-order
        states each after ``q, q'``."""
        if self._states is None:
            M, C, G, K = self.matrices
            n = self.n_dof
            with one_blas_thread(72 * n * n):       # as the solves that follow (rotordyn_modal/_blas.py)
                m_inv = self.mass_inverse
                A0 = np.zeros((2 * n, 2 * n))
                A0[:n, n:] = np.eye(n)
                A0[n:, :n] = -m_inv @ K
                A0[n:, n:] = -m_inv @ C
                A1 = np.zeros((2 * n, 2 * n))
                A1[n:, n:] = -m_inv @ G
                A0, _, names = with_branch_states(self.model, A0, np.zeros((2 * n, 0)), m_inv)
            extra = A0.shape[0] - A1.shape[0]
            if extra:
                A1 = np.pad(A1, ((0, extra), (0, extra)))
            self._states = A0, A1, names
        return self._states

    @property
    def n_states(self) -> int:
        """2n, plus 6 per Maxwell branch."""
        return 2 * self.n_dof + 6 * len(self.branch_times)

    def at(self, speeds) -> np.ndarray:
        """State matrices at ``speeds`` [rad/s].

        Parameters
        ----------
        speeds : array_like, shape (N,) or scalar

        Returns
        -------
        ndarray, shape (N, n_states, n_states) (or (n_states, n_states) for a scalar speed)
        """
        speeds = np.asarray(speeds, dtype=float)
        out = self.A0 + speeds[..., None, None] * self.A1
        if self._dependent:
            n = self.n_dof
            flat = out.reshape((-1,) + out.shape[-2:])
            for rows, left, right, k, c in self._bearing_terms(np.ravel(speeds)):
                flat[:, n:2 * n, rows] -= left @ k @ right
                flat[:, n:2 * n, n + rows.start:n + rows.stop] -= left @ c @ right
        return out

    def stiffness_at(self, speeds) -> np.ndarray:
        """Stiffness ``K(Omega)`` [N/m, ...], shape (N, n, n) (or (n, n) when constant)."""
        if not self._dependent:
            return self.matrices.K
        return self.matrices.K + dependent_bearing_matrices(self.model, speeds)[0]

    def damping_at(self, speeds) -> np.ndarray:
        """Damping ``C(Omega)`` without the gyroscopic part, shape (N, n, n) (or (n, n))."""
        if not self._dependent:
            return self.matrices.C
        return self.matrices.C + dependent_bearing_matrices(self.model, speeds)[1]

    def pencil_at(self, speeds) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness ``K(Omega)`` and damping ``C(Omega)`` (without the gyroscopic part) from one
        evaluation of the speed-dependent bearings (:meth:`stiffness_at` and :meth:`damping_at`
        each evaluate them whole).

        Parameters
        ----------
        speeds : array_like, shape (N,)
            Speeds [rad/s].

        Returns
        -------
        stiffness, damping : ndarray, shape (N, n, n) each (or (n, n) when constant)
            [N/m, ...] and [N s/m, ...].
        """
        if not self._dependent:
            return self.matrices.K, self.matrices.C
        bearing_k, bearing_c = dependent_bearing_matrices(self.model, speeds)
        return self.matrices.K + bearing_k, self.matrices.C + bearing_c

    def pattern(self, sparse: bool = False):
        """Where ``M``, ``C(Omega)``, ``G`` and ``K(Omega)`` may be nonzero at any speed: the
        constant parts' nonzero entries and each speed-dependent bearing's rotor block.

        Parameters
        ----------
        sparse : bool
            As a ``scipy.sparse`` matrix (a large model's: no ``n x n`` array).

        Returns
        -------
        ndarray of bool, shape (n, n), or scipy.sparse.csc_matrix of bool (n, n)
        """
        if sparse and self.sparse is not None:
            return self._sparse_pattern()
        if self.sparse is not None:       # a large model's, without its dense matrices
            M, C, G, K = self.sparse
            nonzero = ((abs(M) + abs(C) + abs(G) + abs(K)) != 0).toarray()
        else:
            M, C, G, K = self.matrices
            nonzero = (M != 0) | (C != 0) | (G != 0) | (K != 0)
        for rows, *_ in self._dependent:
            nonzero[rows, rows] = True
        return nonzero

    def _sparse_pattern(self):
        """:meth:`pattern` of a large model as a ``scipy.sparse.csc_matrix`` of bool (n, n)."""
        import scipy.sparse

        M, C, G, K = self.sparse
        found = (abs(M) + abs(C) + abs(G) + abs(K)).tocoo()
        keep = found.data != 0
        rows, cols = [found.row[keep]], [found.col[keep]]
        for where, _, moves, *_ in self._dependent:
            # the coordinates the bearing's relative motion touches (not its rotor's every one)
            block = np.arange(self.n_dof)[where][np.any(moves != 0, axis=0)]
            rows.append(np.repeat(block, len(block)))
            cols.append(np.tile(block, len(block)))
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        pattern = scipy.sparse.csc_matrix((np.ones(len(rows), bool), (rows, cols)), shape=(self.n_dof, self.n_dof))
        pattern.sum_duplicates()
        pattern.sort_indices()
        return pattern

    def _bearing_terms(self, speeds):
        """Per speed-dependent bearing: rotor rows, ``M^-1 E^T``, E, K_b(N), C_b(N)."""
        for rows, left, moves, coefficients, ratio, where in self._dependent:
            k, c = evaluate(coefficients, ratio * speeds, where)
            yield rows, left, moves, k, c


def _dependent_bearings(model, inverse_columns):
    """``(rows, M^-1[:, rows] E^T, E, coefficients, speed ratio, name)`` of each bearing
    whose coefficients depend on speed; empty when none does (``inverse_columns(rows)``:
    those columns of ``M^-1``)."""
    terms = []
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            continue
        rows, moves = bearing_motion(model, bearing)
        left = inverse_columns(rows) @ moves.T
        terms.append((rows, left, moves, bearing.coefficients,
                      model.rotor(bearing.rotor).speed_ratio, f"{model.source}: [bearings.{bearing.name}]"))
    return terms


def speed_linear_form(model, like: SpeedLinearForm | None = None) -> SpeedLinearForm:
    """The speed-dependent state matrix of ``model``; see :class:`SpeedLinearForm`. Inside a
    :func:`kept_form` block of this very model, the block's one form."""
    kept = _KEPT.get(id(model))
    if kept is None or kept[0] is not model:
        return SpeedLinearForm(model, like)
    if kept[1] is None:
        kept[1] = SpeedLinearForm(model, like)
    return kept[1]


#: the forms of :func:`kept_form` blocks running: ``id(model) -> [model, form or None]``
_KEPT = {}


@contextlib.contextmanager
def kept_form(model):
    """A block in which :func:`speed_linear_form` of this very ``model`` object gives one form,
    built on first use and let go at the block's end: a command whose steps each build it
    (``critical-speeds``: the sweep, the mode numbers, the terminal's round-off) builds it once,
    and no result keeps it."""
    key = id(model)
    if key in _KEPT:                      # an outer block keeps it already
        yield
        return
    _KEPT[key] = [model, None]
    try:
        yield
    finally:
        del _KEPT[key]


def same_inertia(a, b) -> bool:
    """Models whose mass and gyroscopic matrices are the same numbers without computing them:
    the very same bodies (:meth:`~rotordyn_modal.model.machine.Model.same_bodies`) and coordinates."""
    return a is b or (a.dofs is b.dofs and a.same_bodies(b))


def state_matrices(model, speeds) -> np.ndarray:
    """State matrices ``A(Omega)`` for many speeds at once.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s].

    Returns
    -------
    ndarray, shape (N, n_states, n_states) [1/s, 1/s^2]
    """
    return SpeedLinearForm(model).at(speeds)


def state_space(model, speed: float, quantity: str = "displacement", inputs=None, outputs=None):
    """python-control ``StateSpace`` of the machine at one speed.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s]; negative reverses every rotor's spin.
    quantity : {'displacement', 'velocity', 'acceleration'}
        What the sensors measure (also accepted: 'receptance', 'mobility', 'accelerance').
    inputs, outputs : list of str, optional
        Excitation and sensor names (default: all, in model order).

    Returns
    -------
    control.StateSpace
        Inputs named after the ``[[excitations]]`` [N or N m], outputs after the
        ``[[sensors]]`` [m, m/s or m/s^2], states ``q0..q{n-1}, dq0..dq{n-1}`` (the
        generalized coordinates ``model.dofs.names``), then six states per Maxwell
        branch of the mounts (see :func:`rotordyn_modal.elements.mounts.with_branch_states`).
    """
    import control

    if quantity not in _QUANTITY_ORDER:
        raise InputError(f"quantity {quantity!r}: expected one of {', '.join(_QUANTITY_ORDER)}")
    form = SpeedLinearForm(model)
    n = form.n_dof
    a = form.at(float(speed))
    columns = excitation_columns(model, inputs)
    rows = sensor_rows(model, outputs)
    b = np.zeros((form.n_states, columns.shape[1]))
    b[n:2 * n] = form.mass_inverse @ columns
    branch_states = form.branch_state_names
    c, d = _output_matrices(a, b, rows, _QUANTITY_ORDER[quantity])
    input_names = [x.name for x in _named(model.excitations, inputs)]
    output_names = [s.name for s in _named(model.sensors, outputs)]
    states = [f"q{i}" for i in range(n)] + [f"dq{i}" for i in range(n)] + branch_states
    return control.ss(a, b, c, d, inputs=input_names or None, outputs=output_names or None,
                      states=states, name=model.name or None)


def _output_matrices(a, b, rows, order: int):
    """C and D giving the ``order``-th time derivative of the sensor displacements."""
    n = rows.shape[1]
    selector = np.hstack([rows, np.zeros((rows.shape[0], a.shape[0] - n))])  # displacement: C x
    c = selector
    d = np.zeros((rows.shape[0], b.shape[1]))
    for _ in range(order):
        c, d = c @ a, c @ b  # d/dt (C x + D u) with u held: C A x + C B u
    return c, d


def _named(items, names):
    if names is None:
        return list(items)
    names = [names] if isinstance(names, str) else names
    by_name = {i.name: i for i in items}
    return [by_name[n] for n in names]


#: digits of the low modes a support may cost (docs/theory.md §8, "Stiffness spread") before a
#: model draws a warning: more than this leaves fewer than about ten of the sixteen
SPREAD_WARN_DIGITS = 6.0
#: digits double precision has, log10(1 / eps): a spread this large leaves none
SPREAD_REFUSE_DIGITS = float(-np.log10(np.finfo(float).eps))


def stiffness_spread_lines(model, parts=None) -> list[str]:
    """The warning about a support far stiffer than what it holds, one line each (or none).

    Each support (a bearing's radial or moment stiffness, a mount, a pedestal, a gear mesh)
    has a scale ``lam_e = max_j K_e,jj / m_j`` [1/s^2] over the coordinates it loads, ``m_j``
    the mass moving there against the casing (:func:`_moving_mass`: a light casing between
    stiff bearings under a heavy rotor moves with the reduced mass); every other stiffness of
    the machine (the flexible shafts' bending as one part, each other support alone) has its
    own ``max_j K_jj / M_jj``. What a support holds is the softest of the others, ``lam_h``;
    the support costs the low modes ``log10(lam_e / lam_h)`` significant digits (docs/theory.md
    §8, "Stiffness spread"). Journal bearings are not checked (their film sets its own
    stiffness from the viscosity, and a stiff film is solved well: theory §8).

    Raises
    ------
    ModelError
        A support that costs at least :data:`SPREAD_REFUSE_DIGITS` digits: no digit of the low
        modes is left (its stiffness also rounds the rest away in ``K``).
    """
    found = []
    for where, key, value, digits, rigid, unit in support_spreads(model, parts):
        if not digits > SPREAD_WARN_DIGITS:
            continue
        said = (f"{model.source}: {where} {key} = {value:.3g}: {10 ** digits:.1e} times the scale of what it holds "
                f"(the machine's softest other stiffness, as {rigid:.3g} {unit} there)")
        masses = _masses_clause(digits - float(np.log10(value / rigid)))
        # a support softer than what already acts as rigid is told no such value (a 500 N/m bearing
        # whose spread is the masses' was told '5e+05–5e+06 N/m already acts as rigid')
        rigid_at = f"{rigid * 1e3:.1g}–{rigid * 1e4:.1g} {unit} already acts as rigid" if value > rigid * 1e3 else ""
        if digits >= SPREAD_REFUSE_DIGITS:
            raise ModelError(model.source, f"{where} {key}", f"{value:.3g}",
                             f"a support stiffness that leaves the low modes a digit in double precision: "
                             f"{10 ** digits:.1e} times the scale of what it holds, at most about "
                             f"{value * 10 ** (SPREAD_REFUSE_DIGITS - 1 - digits):.1g} {unit}; "
                             + (f"{rigid_at} (docs/theory.md §8, stiffness spread); " if rigid_at else "")
                             + (f"{masses}; " if masses else "")
                             + "or else a mass or inertia where it acts far too small (the scale is stiffness over mass)")
        found.append((digits, f"{said}: the low modes lose about {digits:.0f} of 16 significant digits; "
                              + "; ".join(c for c in (masses, rigid_at) if c) + " (docs/theory.md §8)"))
    if not found:
        return []
    digits, line = max(found, key=lambda f: f[0])      # one line: the worst support, the others counted
    more = len(found) - 1
    return [line + (f" (and {more} other support{'s' if more > 1 else ''})" if more else "")]


def _masses_clause(digits: float) -> str:
    """The words for the ``digits`` of a support's spread that come from the masses where it acts
    (``log10(K_jj (M^-1)_jj / (K_jj / M_jj))``: a light body between stiffer supports moves with
    their reduced mass), no stiffness removes them; empty below one digit."""
    if not digits >= 1.0:
        return ""
    return (f"{10 ** digits:.1e} of that is the spread of the masses where it acts (a light body between "
            "stiffer supports moves with their reduced mass), which no stiffness removes")


#: digits ``log10(1 / (tau w_h))`` of a Maxwell branch's relaxation rate over the machine's slowest
#: stiffness scale from which it is refused: measured on ``rubber_mounts.toml`` and a flexible
#: rotor in a casing, the low modes then keep less than a digit (17 % off at 1e-14 s, modes lost
#: at 1e-15 s), where the estimate still says 12 of 16 are lost (docs/theory.md §8)
MAXWELL_REFUSE_DIGITS = 12.0


def maxwell_spread_lines(model, parts=None) -> list[str]:
    """The warning about a mount's Maxwell branch far faster than the machine's modes, one line
    (the worst branch, the others counted), or none.

    A branch of relaxation time ``tau`` adds the real root ``-1/tau`` to the state matrix; next to
    the slowest stiffness scale of the machine ``w_h = sqrt(lam_h)`` [rad/s] (the softest of the
    scales of :func:`support_spreads`) the low modes lose about ``log10(1 / (tau w_h))`` digits
    (measured: one or two more). A branch that fast relaxes at once: at the modes' frequencies it
    acts only as a damper ``k_b tau`` (``k_b`` its stiffness), so the warning says so.

    Raises
    ------
    ModelError
        A branch of at least :data:`MAXWELL_REFUSE_DIGITS` digits: the low modes keep no digit
        (they came out 17 % off, or vanished, without a word).
    """
    branches = [(s, i, float(tau)) for s in model.suspensions if s.maxwell_time is not None
                for i, tau in enumerate(np.ravel(s.maxwell_time))]
    if not branches:
        return []
    scales = [p[3][0] for p in (_support_scales(model) if parts is None else parts)]
    if not scales:
        return []
    slowest = float(np.sqrt(min(scales)))                 # [rad/s]
    found = []
    for suspension, i, tau in branches:
        digits = float(np.log10(1.0 / (tau * slowest)))
        if not digits > SPREAD_WARN_DIGITS:
            continue
        damper = float(np.abs(np.asarray(suspension.maxwell_stiffness_matrix[i])).max()) * tau
        where, key = f"[suspensions.{visible(suspension.name)}]", f"maxwell_time[{i}]"
        rate = (f"its relaxation rate 1/tau = {1.0 / tau:.3g} 1/s is {10 ** digits:.1e} times the machine's "
                f"slowest stiffness scale ({slowest:.3g} rad/s)")
        acts = (f"a branch this fast relaxes at once and acts only as a damper of maxwell_stiffness x tau = "
                f"{damper:.2g} N s/m (leave it out, or add that to damping)")
        if digits >= MAXWELL_REFUSE_DIGITS:
            raise ModelError(model.source, f"{where} {key}", f"{tau:.3g}",
                             f"a relaxation time that leaves the low modes a digit in double precision, at least "
                             f"about {10 ** -(MAXWELL_REFUSE_DIGITS - 1) / slowest:.1g} s: {rate}; {acts}")
        found.append((digits, f"{model.source}: {where} {key} = {tau:.3g}: {rate}: the low modes lose about "
                              f"{digits:.0f} of 16 significant digits; {acts} (docs/theory.md §8)"))
    if not found:
        return []
    digits, line = max(found, key=lambda f: f[0])
    more = len(found) - 1
    return [line + (f" (and {more} other branch{'es' if more > 1 else ''})" if more else "")]


def _support_scales(model) -> list:
    """``(where, key, value, (lam, j, top))`` of each stiffness of the machine
    (:func:`_stiffness_pieces`) with a finite positive scale ``lam = max_j K_jj / M_jj`` [1/s^2]
    (:func:`_scale`); ``top = max_j K_jj / m_j`` [1/s^2] is its scale as the stiff one, ``m_j``
    the mass that moves at ``j`` against the casing (:func:`_moving_mass`)."""
    import scipy.sparse
    from .assembly import _sparse_mass

    with np.errstate(all="ignore"):
        M = _sparse_mass(model).tocsr() if is_large(model) else scipy.sparse.csr_matrix(mass_matrix(model))
        mass = M.diagonal()                                # the matrix built once
        moving = _moving_mass(M, mass, model.dofs.n_frame)
        parts = [(where, key, value, _scale(K, mass, moving)) for where, key, value, K in _stiffness_pieces(model)]
    return [p for p in parts if np.isfinite(p[3][0]) and p[3][0] > 0]


def _moving_mass(M, mass: np.ndarray, n_frame: int) -> np.ndarray:
    """The mass [kg, kg m^2] that moves at each coordinate against the casing, (n,): at a rotor's
    or pedestal's coordinate ``j`` (relative to the casing) ``1 / (M_s^-1)_jj``, ``M_s`` the mass
    matrix of ``j`` and the casing's coordinates, ``M_jj - M_jf M_ff^-1 M_fj``: a light casing
    between stiff bearings under a heavy rotor moves with the reduced mass of the two, not with
    the rotor's ``M_jj`` (a 1 g casing under a 1e9 kg rotor: 1 g). The casing's own coordinates,
    and every one of a machine without a casing, keep ``M_jj`` (a flexible shaft's consistent
    masses are no such spread). ``M`` (n, n) sparse CSR, ``mass`` its diagonal; a reduced mass
    below ``1e3 eps M_jj`` keeps ``M_jj`` (no digit of it is left: the mass matrix is singular
    to round-off, :func:`checked_mass_inverse`'s refusal)."""
    out = mass.astype(float).copy()
    if not n_frame or n_frame >= len(mass):
        return out
    frame = M[:n_frame, :n_frame].toarray()
    coupling = M[n_frame:, :n_frame].toarray()                        # (n - n_frame, n_frame)
    try:
        held = np.einsum("ij,ij->i", coupling, np.linalg.solve(frame, coupling.T).T)
    except np.linalg.LinAlgError:
        return out
    rest = mass[n_frame:]
    reduced = rest - held
    # below 1e3 eps of M_jj the subtraction keeps no digit: the mass matrix is singular to
    # round-off, which checked_mass_inverse refuses in its own words (a stator of 1e-30 kg)
    out[n_frame:] = np.where(np.isfinite(held) & (reduced > 1e3 * np.finfo(float).eps * rest), reduced, rest)
    return out


def support_spreads(model, parts=None) -> list:
    """What each support costs the low modes: ``(where, key, value, digits, rigid, unit)``.

    ``digits = log10(lam_e / lam_h)`` (see :func:`stiffness_spread_lines`), ``lam_e`` the
    support's ``top`` scale (``K_jj / m_j``, :func:`_moving_mass`), ``lam_h`` the softest other's
    ``K_jj / M_jj``;
    ``value`` the support's largest coefficient, ``rigid = value lam_h / lam`` (``lam`` its own
    ``K_jj / M_jj``) what it holds against in the units of its key, ``unit`` (``'N/m'``; ``'N m/rad'`` for
    ``moment_stiffness``). Only supports that some other stiffness of the machine holds against
    are listed. ``parts``: the machine's :func:`_support_scales`, where already found.
    """
    parts = _support_scales(model) if parts is None else parts
    softest = sorted((p[3][0], p[0]) for p in parts)     # a few steps per support, not all pairs
    out = []
    for where, key, value, (scale, at, top) in parts:
        held = next((other for other, owner in softest if owner != where), None)
        if where == "shaft" or held is None:
            continue
        digits = float(np.log10(top / held))
        unit = "N m/rad" if key == "moment_stiffness" else "N/m"
        out.append((where, key, value, digits, value * held / scale, unit))
    return out


def _scale(diagonal: np.ndarray, mass: np.ndarray, moving: np.ndarray):
    """``max_j K_jj / M_jj`` over the coordinates a stiffness loads [1/s^2], that ``j``, and
    ``max_j K_jj / m_j`` [1/s^2] (``moving`` the masses ``m_j`` of :func:`_moving_mass`)."""
    ratio = np.where(mass > 0, np.abs(diagonal) / np.where(mass > 0, mass, 1.0), 0.0)
    at = int(np.argmax(ratio))
    top = np.where((mass > 0) & (moving > 0), np.abs(diagonal) / np.where(moving > 0, moving, 1.0), 0.0)
    return float(ratio[at]), at, max(float(top.max()), float(ratio[at]))


def _key_of(block: np.ndarray, key: str, spin_axis) -> tuple:
    """``(key, value)`` a bearing's 3x3 translational ``block`` (model axes) is named by: its
    ``axial_stiffness`` where that is its largest coefficient (a stiff axial bearing beside soft
    radial ones was named ``stiffness = '2e+08'``, its radial stiffness being 1e-10), else ``key``
    with the largest coefficient."""
    largest = float(np.abs(block).max())
    if key == "stiffness":
        e = np.asarray(spin_axis, dtype=float)
        axial = abs(float(e @ block @ e))
        radial = block - np.outer(e, e) * float(e @ block @ e)
        if axial > float(np.abs(radial).max()):
            return "axial_stiffness", axial
    return key, largest


def _stiffness_pieces(model):
    """``(where, key, value, d)`` of each stiffness of the machine, ``d`` (n,) the diagonal of its
    ``K`` in ``q`` (only diagonals: a machine of thousands of coordinates and bearings builds no
    n x n matrix per support): the flexible shafts' bending (one piece), each bearing's
    translational and tilt stiffness (a speed table at its largest), each mount, pedestal and
    gear mesh; ``value`` is the largest coefficient [N/m or N m/rad]."""
    from .assembly import mesh_row, shaft_stiffness_diagonal, suspension_block, pedestal_piece

    n = model.dofs.n
    if any(r.flexible is not None for r in model.rotors):
        yield "shaft", "bending", 0.0, shaft_stiffness_diagonal(model)
    for bearing in model.bearings:
        kind = bearing.coefficients.kind
        if kind == "journal":
            continue
        speeds = bearing.coefficients.speeds if kind == "table" else [0.0]
        k6s, _ = evaluate(bearing.coefficients, speeds, f"{model.source}: [bearings.{visible(bearing.name)}]")
        rows, moves = bearing_motion(model, bearing)
        for block, key in ((slice(0, 3), "stiffness"), (slice(3, 6), "moment_stiffness")):
            piece = np.zeros((6, 6))
            piece[block, block] = k6s[np.argmax(np.abs(k6s[:, block, block]).max(axis=(1, 2)))][block, block]
            d = np.zeros(n)
            d[rows] = np.einsum("ji,jk,ki->i", moves, piece, moves)
            yield f"[bearings.{visible(bearing.name)}]", *_key_of(piece[block, block], key, model.spin_axis), d
        if bearing.pedestal is not None:
            yield f"[bearings.{visible(bearing.name)}]", "pedestal_stiffness", \
                float(np.abs(bearing.pedestal.stiffness).max()), pedestal_piece(model, bearing)
    for suspension in model.suspensions:
        d = np.zeros(n)
        d[:model.dofs.n_frame] = np.diagonal(suspension_block(model, suspension))
        yield f"[suspensions.{visible(suspension.name)}]", "stiffness", \
            float(np.abs(suspension.stiffness_matrix).max()), d
    for t in model.transmissions:
        if t.mesh_stiffness:
            yield f"[transmissions.{visible(t.label)}]", "mesh_stiffness", float(t.mesh_stiffness), \
                t.mesh_stiffness * mesh_row(model, t)[0] ** 2
