"""Forces: what each suspension passes to the ground, what each rotor passes to the stator,
and what each bearing carries.

* Suspension ``i`` at point ``P_i`` pushes on the ground with the generalized
  force (``[F, C]`` at ``P_i``, model axes)
  ``T_i = (K_i (1 + i eta_i) + K_b,i(w) + i w C_i) B_SP^T q``:
  the transmitted force, whose ratio to an input force is the transmissibility.
* Rotor ``j`` acts on the stator through its bearings with (docs/theory.md §13,
  written at the rotor's centre of mass ``R_j``, where ``B_Bj,j = I``)
  ``T_Bj = F_U,j - M_j B_SRj^T q'' - Omega G_j B_SRj^T q'``, with ``M_j =
  diag(m_j I, J_j)``, ``G_j = diag(0, -J_p,j r_j skew(e))`` and ``F_U,j`` the
  unbalance force on the rotor moved to ``R_j``. Move it to a bearing at ``P``
  with ``shift_matrix(P, R_j) @ T_Bj``.

  The rotor's motion is its own (``T_j q``): for a rotor on bearings it moves
  relative to the stator, and this is the sum of its bearings' forces.
* Bearing ``b`` at point ``P`` of rotor j pushes the stator (or the ground) with
  ``(K_b + i w C_b) B_RjP^T P_j p_j``: its springs and dampers acting on the
  rotor's motion relative to the stator there (``[F, C]`` at P). A bearing on a pedestal
  pushes its pedestal: the motion is the rotor's relative to the pedestal.

All are linear in the complex amplitude ``q`` of the generalized coordinates;
the functions here take ``q`` from :func:`rotordyn_modal.analysis.frf.dof_response`.
"""

from __future__ import annotations

import numpy as np

from ..assembly import excitation_columns, rotor_matrices
from ..elements.bearings import evaluate
from ..model.geometry import shift_matrices, shift_matrix
from .. import _arguments
from . import _batches
from .frf import FRFResult, _broadcast, _check_frequencies, _names, dof_response

__all__ = ["suspension_forces", "bearing_forces", "bearing_point_forces", "all_forces", "force_frf", "COMPONENTS"]

#: names of the six components of a generalized force
COMPONENTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: memory of the items' motions taken in one part by :func:`bearing_forces` (its temporaries
#: are about three times this) [bytes]
_FORCE_PART_BYTES = 2**20


def suspension_forces(model, omega, q) -> np.ndarray:
    """Force each suspension passes to the ground.

    Parameters
    ----------
    model : Model
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, n_dof, n), complex
        Generalized coordinates [m, rad].

    Returns
    -------
    ndarray, shape (n_suspensions, n_freq, 6, n), complex
        ``[F, C]`` at each suspension's point, model axes [N, N m].
    """
    w = np.asarray(omega, dtype=float)
    suspensions = model.suspensions
    count, n = len(w), q.shape[-1]
    if not suspensions:
        return np.zeros((0, count, 6, n), dtype=complex)
    # every suspension at once: the stator's motion at S, B_SP^T of it in one product, then each
    # suspension's stiffness and damping on its own point's motion
    points = _items(_suspension_motions(model, _rows(q)), len(suspensions))                  # (S, F n, 6)
    matrices = np.array([(s.stiffness_matrix, s.damping_matrix) for s in suspensions])      # (S, 2, 6, 6)
    out = _stiffness_damping(points, _with_losses(matrices[:, 0], suspensions), matrices[:, 1], w)
    _add_branches(out, suspensions, points, w)
    return out


def _suspension_motions(model, rows, out=None):
    """The motion at every suspension's point, ``B_SP^T T_stator q``, of coordinates ``rows``
    (F n, n_dof): the stator's motion at S, then ``B_SP^T`` of it in one product, (F n, 6 S)."""
    shifts = shift_matrices(model.reference_point, [s.position for s in model.suspensions])
    stator = rows @ model.dofs.frame_motion().T                                              # (F n, 6)
    return np.matmul(stator, shifts.transpose(0, 2, 1).reshape(-1, 6).T, out=out)


def _with_losses(stiffness, suspensions):
    """``K (1 + i eta)`` of each suspension's stiffness (S, 6, 6), complex; ``K`` itself without
    loss factors (``K (1 + 0i)`` is what the products' cast to complex makes of it anyway)."""
    if not any(s.loss_factor for s in suspensions):
        return stiffness
    losses = np.array([s.loss_factor for s in suspensions], dtype=float)
    return stiffness * (1 + 1j * losses)[:, None, None]


def _add_branches(out, suspensions, points, w):
    """Add each Maxwell branch's force ``K_b(w) x`` to its suspension's ``out[i]`` (F, 6, n)."""
    for i, s in enumerate(suspensions):
        if getattr(s, "maxwell_stiffness_matrix", None) is not None:
            out[i] = out[i] + _branch_stiffness(s, w) @ _columns(points[i], len(w))


def _rows(q):
    """(F, d, n) -> (F n, d): every column of every frequency as a row (a view when n = 1)."""
    count, d, n = q.shape
    return q.transpose(0, 2, 1).reshape(count * n, d)


def _items(rows, items):
    """(F n, 6 items) -> (items, F n, 6): each item's six components as the rows of one matrix
    (a view)."""
    return rows.reshape(len(rows), items, 6).transpose(1, 0, 2)


def _columns(rows, count):
    """(..., F n, k) -> (..., F, k, n): the inverse of :func:`_rows` (a view)."""
    return rows.reshape(*rows.shape[:-2], count, -1, rows.shape[-1]).swapaxes(-1, -2)


def _stiffness_damping(motion, stiffness, damping, w, out=None):
    """``K_i x + i w C_i x`` for each item's motion ``x`` (one product per matrix kind for all
    items; side by side in one product, the signs of structural zeros would change).

    Parameters
    ----------
    motion : ndarray, shape (items, F n, 6), complex
    stiffness, damping : ndarray, shape (items, 6, 6)
    w : ndarray, shape (F,) [rad/s]
    out : ndarray, shape (items, F, 6, n), complex, optional
        Where to write the result.

    Returns
    -------
    ndarray, shape (items, F, 6, n), complex (n columns of each frequency's motion)
    """
    a = _columns(motion @ stiffness.transpose(0, 2, 1), len(w))
    b = _columns(motion @ damping.transpose(0, 2, 1), len(w))
    return _elastic(a, b, w, a if out is None else out)


def _elastic(stiffness, damping, w, out):
    """``K x + (i w) C x`` from the products ``K x`` and ``C x`` (items, F, 6, n), in place
    (``damping`` is overwritten): the same operations, without fresh arrays of their size."""
    np.multiply(1j * w[:, None, None], damping, out=damping)
    return np.add(stiffness, damping, out=out)


def _inertial(inertial, spinning, w, speed, external, out):
    """``w^2 M x - (i w Omega) G x (+ external)``: a rotor's force on its bearings from the
    products ``M x`` and ``G x`` (items, F, 6, n), in place (both are overwritten)."""
    np.multiply(w[:, None, None] ** 2, inertial, out=inertial)
    np.multiply(1j * (w * speed)[:, None, None], spinning, out=spinning)
    np.subtract(inertial, spinning, out=out)
    if external is not None:
        np.add(out, external, out=out)
    return out


def _branch_stiffness(suspension, omega):
    factor = 1j * omega[:, None] * np.asarray(suspension.maxwell_time, dtype=float)
    factor = factor / (1 + factor)
    return np.einsum("fb,bij->fij", factor, suspension.maxwell_stiffness_matrix)


def bearing_forces(model, speed, omega, q, rotor_forces=None) -> np.ndarray:
    """Force each rotor passes to the stator through its bearings (docs/theory.md §13).

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,)
        Reference rotor speed [rad/s].
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, n_dof, n), complex [m, rad]
    rotor_forces : ndarray, shape (n_rotors, n_freq, 6, n), optional
        External forces on each rotor (unbalance), ``[F, C]`` at its centre of mass.

    Returns
    -------
    ndarray, shape (n_rotors, n_freq, 6, n), complex
        ``[F, C]`` at each rotor's centre of mass, model axes [N, N m].
    """
    w = np.asarray(omega, dtype=float)
    speed = _broadcast(speed, w.shape)
    rotors = model.rotors
    count, n = len(w), q.shape[-1]
    if not rotors:
        return np.zeros((0, count, 6, n))
    if any(r.flexible is not None for r in rotors):
        return _flexible_bearing_forces(model, speed, w, q, rotor_forces)
    return _inertial_forces(model, rotors, speed, w, q, rotor_forces)


def _inertial_forces(model, rotors, speed, w, q, rotor_forces):
    """:func:`bearing_forces` of some rigid ``rotors`` (their inertia and external forces)."""
    count, n = len(w), q.shape[-1]
    # every rotor's motion at its centre of mass B_SR^T T_j q in one product, then its mass and
    # gyroscopic matrices on it: -(-w^2 M_j + i w Omega G_j) motion
    to_centres = _to_centres(model, rotors)                                              # (6 R, n_dof)
    matrices = np.array(rotor_matrices(model.spin_axis, rotors), dtype=float).reshape(-1, 2, 6, 6)
    masses, gyroscopic = matrices[:, 0], matrices[:, 1]
    rows = _rows(q)
    out = np.empty((len(rotors), count, 6, n), dtype=complex)
    for part in _parts(len(rotors), len(rows)):
        motion = _items(rows @ to_centres[6 * part.start:6 * part.stop].T, len(out[part]))   # (R', F n, 6)
        _inertial(_columns(motion @ masses[part].transpose(0, 2, 1), count),
                  _columns(motion @ gyroscopic[part].transpose(0, 2, 1), count), w, speed,
                  None if rotor_forces is None else rotor_forces[part], out[part])
    return out


def _flexible_bearing_forces(model, speed, w, q, rotor_forces):
    """:func:`bearing_forces` of a model with flexible rotors: a flexible rotor passes the sum of
    its bearings' forces (moved to its centre of mass); a rigid rotor's as usual."""
    rigid = [j for j, r in enumerate(model.rotors) if r.flexible is None]
    out = np.zeros((len(model.rotors), len(w), 6, q.shape[-1]), dtype=complex)
    if rigid:
        out[rigid] = _inertial_forces(model, [model.rotors[j] for j in rigid], speed, w, q,
                                      None if rotor_forces is None else rotor_forces[rigid])
    points = bearing_point_forces(model, speed, w, q)
    for b, bearing in enumerate(model.bearings):
        j = next(i for i, r in enumerate(model.rotors) if r.name == bearing.rotor)
        if model.rotors[j].flexible is not None:
            out[j] += shift_matrix(model.rotors[j].center_of_mass, bearing.position) @ points[b]
    return out


def _to_centres(model, rotors):
    """``B_SR^T T_j`` of each rotor (its motion at its centre of mass per coordinate), shape
    (6 R, n_dof): :func:`centre_motions` of every rotor's shift matrix and body motion."""
    return centre_motions(shift_matrices(model.reference_point, [r.center_of_mass for r in rotors]),
                    model.dofs.motions([(r.name, False) for r in rotors]))


def centre_motions(shifts, motions):
    """Each rotor's motion at its centre of mass per generalized coordinate: the rotors'
    ``shift_matrix(S, R_j).T @ body_motion`` in one product.

    Parameters
    ----------
    shifts : ndarray, shape (R, 6, 6)
        Shift matrices from the model's reference point S to each rotor's centre R_j.
    motions : ndarray, shape (R, 6, n_dof)
        Each rotor's body motion (translations [m], rotations [rad] per coordinate).

    Returns
    -------
    ndarray, shape (6 R, n_dof)
    """
    return (shifts.transpose(0, 2, 1) @ motions).reshape(-1, motions.shape[-1])


def _parts(items, rows):
    """Slices of ``items`` whose motions, ``rows`` x 6 complex numbers each, hold about
    ``_FORCE_PART_BYTES`` together (all of a small model's at once; large models' forces in
    parts, so that their temporaries stay a fraction of the result)."""
    return _batches.chunk_slices(items, 96 * rows, budget=_FORCE_PART_BYTES)


def _bearing_moves(layout, rotor, bearings):
    """Where a rotor's coordinates sit in ``q`` (a slice; through its bearings' pedestals), and
    the motion across each of its ``bearings`` per coordinate (:meth:`Dofs.bearing_moves`: the
    relative motion ``B_RP^T P_j`` at its point, less its pedestal's), stacked (6 B_j, width)."""
    own, moves = layout.bearing_moves(rotor, [b.position for b in bearings], [b.name for b in bearings])
    return own, moves.reshape(-1, moves.shape[-1])


def bearing_point_forces(model, speed, omega, q) -> np.ndarray:
    """Force each of the model's ``[[bearings]]`` passes to the stator (or the ground).

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,)
        Reference rotor speed [rad/s] (the coefficients may depend on it).
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, n_dof, n), complex [m, rad]

    Returns
    -------
    ndarray, shape (n_bearings, n_freq, 6, n), complex
        ``[F, C]`` at each bearing's point, model axes [N, N m].
    """
    w = np.asarray(omega, dtype=float)
    speed = _broadcast(speed, w.shape)
    bearings = model.bearings
    count, n = len(w), q.shape[-1]
    if not bearings:
        return np.zeros((0, count, 6, n))
    # the relative motion at every bearing of a rotor in one product of that rotor's coordinates
    layout = model.dofs
    by_rotor: dict = {}
    for b, bearing in enumerate(bearings):
        by_rotor.setdefault(bearing.rotor, []).append(b)
    coordinates = _rows(q)
    out = np.empty((len(bearings), count, 6, n), dtype=complex)
    for rotor, which in by_rotor.items():
        own, moves = _bearing_moves(layout, rotor, [bearings[b] for b in which])
        relative = _items(coordinates[:, own] @ moves.T, len(which))                     # (B_j, F n, 6)
        constant = [i for i, b in enumerate(which) if bearings[b].coefficients.kind == "constant"]
        if constant:     # the same 6 x 6 matrices at every speed
            chosen = [which[i] for i in constant]
            matrices = np.array([(bearings[b].coefficients.stiffness[0], bearings[b].coefficients.damping[0])
                                 for b in chosen])                                      # (B', 2, 6, 6)
            motion = relative if len(constant) == len(which) else relative[constant]
            if chosen == list(range(chosen[0], chosen[-1] + 1)):     # in place
                _stiffness_damping(motion, matrices[:, 0], matrices[:, 1], w, out=out[chosen[0]:chosen[-1] + 1])
            else:
                out[chosen] = _stiffness_damping(motion, matrices[:, 0], matrices[:, 1], w)
        for i, b in enumerate(which):
            coefficients = bearings[b].coefficients
            if coefficients.kind != "constant":
                own = model.rotor(bearings[b].rotor).speed_ratio * speed
                k6, c6 = evaluate(coefficients, own, f"{model.source}: [bearings.{bearings[b].name}]")
                out[b] = (k6 + 1j * w[:, None, None] * c6) @ _columns(relative[i], count)
    return out


def all_forces(model, speed, omega, q, rotor_forces=None, centres=None):
    """:func:`suspension_forces`, :func:`bearing_forces` and :func:`bearing_point_forces` together.

    For a small model with constant bearings every item's motion goes into one array and the
    items' two matrix products (stiffness and damping, or mass and gyroscopic) are one stacked
    product each: per item the same products, so the same numbers as the three functions,
    which are called instead for larger models (their memory taken in parts) or
    speed-dependent bearings.

    Parameters
    ----------
    model : Model
    speed : float or array_like, shape (n_freq,) [rad/s]
    omega : array_like, shape (n_freq,) [rad/s]
    q : ndarray, shape (n_freq, n_dof, n), complex [m, rad]
    rotor_forces : ndarray, shape (n_rotors, n_freq, 6, n), optional
        External forces on each rotor, as for :func:`bearing_forces`.
    centres : ndarray, shape (6 n_rotors, n_dof), optional
        ``B_SR^T T_j`` of every rotor (:func:`centre_motions`), when the caller has it.

    Returns
    -------
    ground, rotors, bearings : ndarray, shapes (n_suspensions | n_rotors | n_bearings, n_freq, 6, n)
    """
    suspensions, rotors, bearings = model.suspensions, model.rotors, model.bearings
    items = len(suspensions) + len(rotors) + len(bearings)
    groups = _constant_bearing_groups(bearings)
    if any(r.flexible is not None for r in rotors):
        groups = None        # a flexible rotor's force is its bearings' (see bearing_forces)
    if not items or groups is None or 96 * q.shape[0] * q.shape[-1] * items > _FORCE_PART_BYTES:
        return (suspension_forces(model, omega, q), bearing_forces(model, speed, omega, q, rotor_forces),
                bearing_point_forces(model, speed, omega, q))
    w = np.asarray(omega, dtype=float)
    speed = _broadcast(speed, w.shape)
    count, layout = len(w), model.dofs
    s, b = len(suspensions), len(suspensions) + len(bearings)         # items: suspensions, bearings, rotors
    rows = _rows(q)
    motion = np.empty((len(rows), 6 * items), dtype=complex)
    if suspensions:
        _suspension_motions(model, rows, out=motion[:, :6 * s])
    for rotor, which in groups:     # each rotor's bearings' relative motions from its coordinates
        own, moves = _bearing_moves(layout, rotor, [bearings[i] for i in which])
        np.matmul(rows[:, own], moves.T, out=motion[:, 6 * (s + which[0]):6 * (s + which[-1] + 1)])
    if rotors:
        np.matmul(rows, (_to_centres(model, rotors) if centres is None else centres).T, out=motion[:, 6 * b:])
    motion = _items(motion, items)                                                      # (items, F n, 6)
    matrices = np.array([(x.stiffness_matrix, x.damping_matrix) for x in suspensions]
                        + [(x.coefficients.stiffness[0], x.coefficients.damping[0]) for x in bearings]
                        + rotor_matrices(model.spin_axis, rotors), dtype=float).reshape(-1, 2, 6, 6)
    first = matrices[:, 0]
    if any(x.loss_factor for x in suspensions):
        first = first.astype(complex)
        first[:s] = _with_losses(first[:s].real, suspensions)
    # stiffness (mass) and damping (gyroscopic) products of every item
    a = _columns(motion @ first.transpose(0, 2, 1), count)
    c = _columns(motion @ matrices[:, 1].transpose(0, 2, 1), count)
    # suspensions and bearings: K x + (i w) C x; rotors: w^2 M x - (i w Omega) G x (+ external)
    _elastic(a[:b], c[:b], w, a[:b])
    if rotors:
        _inertial(a[b:], c[b:], w, speed, rotor_forces, a[b:])
    _add_branches(a, suspensions, motion, w)
    empty = np.zeros((0, count, 6, q.shape[-1]))     # as the three functions give no items
    return a[:s], a[b:] if rotors else empty, a[s:b] if bearings else empty


def _constant_bearing_groups(bearings):
    """``(rotor, bearing indices)`` of each rotor's bearings, or None when a bearing's
    coefficients depend on speed or some rotor's bearings are not consecutive in the model's
    order."""
    groups: dict = {}
    last = None
    for i, bearing in enumerate(bearings):
        if bearing.coefficients.kind != "constant" or (bearing.rotor != last and bearing.rotor in groups):
            return None
        groups.setdefault(bearing.rotor, []).append(i)
        last = bearing.rotor
    return list(groups.items())


def force_frf(model, speed: float, freqs_hz, inputs=None, where: str = "suspensions") -> FRFResult:
    """Forces per unit excitation: transmissibility to the ground, or bearing forces.

    Parameters
    ----------
    model : Model
    speed : float
        Reference rotor speed [rad/s].
    freqs_hz : array_like, shape (n_freq,) [Hz]
    inputs : str or list of str, optional
        Excitation names (default all).
    where : {'suspensions', 'bearings', 'rotors', 'all'}
        Ground force of each suspension; force of each of the model's ``[[bearings]]``
        at its point and of each rigidly attached rotor at its centre of mass (without
        ``[[bearings]]``: of each rotor); the total force of each rotor on the stator; or
        all of them: the suspensions, the ``[[bearings]]`` and the rotors' totals (as
        ``UnbalanceResult.to_dataframe(forces='all')``).

    Returns
    -------
    FRFResult
        ``quantity='force'``; outputs ``"NAME:Fx" ... "NAME:Mz"`` (6 per suspension,
        bearing or rotor) [N/N, N m/N]; H of shape (6 n_items, n_inputs, n_freq).
    """
    from ..errors import InputError

    if where not in ("suspensions", "bearings", "rotors", "all"):
        raise InputError(f"where {where!r}: expected 'suspensions', 'bearings', 'rotors' or 'all'")
    speed = _arguments.speed(speed)
    f = _check_frequencies(freqs_hz)
    columns = excitation_columns(model, inputs)
    if columns.shape[1] == 0:
        raise InputError(f"{model.source}: the model has no [[excitations]]: a force FRF needs one")
    H, items = _force_frf(model, speed, f, columns, where)
    outputs = tuple(f"{item.name}:{c}" for item in items for c in COMPONENTS)
    found = _resonances(model, speed, f)
    peaks = peak_H = cut_hz = cut_H = None
    if found is not None:
        peaks, band = found
        peak_H = _force_frf(model, speed, peaks, columns, where)[0] if len(peaks) \
            else np.zeros(H.shape[:2] + (0,), complex)
        cut_hz, cut_H = _cut_maxima(model, speed, f, columns, where, H, peaks, band)
    return FRFResult(H=H, frequencies_hz=f, speed=float(speed), inputs=_names(model.excitations, inputs),
                     outputs=outputs, quantity="force", engine="direct", resonances_hz=peaks, resonance_H=peak_H,
                     cut_hz=cut_hz, cut_H=cut_H)


def _cut_maxima(model, speed, f, columns, where, H, resonances, band):
    """The maxima of each force FRF ``H`` (6 n_items, n_inputs, len(f)) between the computed
    frequencies ``f`` [Hz] that its line cuts, near the damped natural frequencies
    ``resonances`` (P,) [Hz] of half-power bandwidths ``band`` (P,) [Hz]
    (:func:`.frf.frf_cut_maxima`): each candidate solves for its own input at its own frequency
    (:func:`_force_frf`, one call an input, each distinct frequency once). Returns ``(cut_hz, cut_H)``, shape
    (6 n_items, n_inputs, Q), NaN after an FRF's last."""
    from .frf import frf_cut_maxima
    from .unbalance_peaks import per_source

    def solve(at, each):
        return _force_frf(model, speed, at, columns[:, each:each + 1], where)[0][:, 0]   # (6 n_items, K')

    return frf_cut_maxima(per_source(solve), f, H, resonances, band)


#: the largest state matrix whose roots a force FRF solves to mark the resonances its frequencies
#: cut (:func:`.frf.unresolved_resonances`; the dense eigen-solve's cost grows as its cube)
_RESONANCE_STATES = 1200


def _resonances(model, speed, f):
    """The damped natural frequencies [Hz] within ``f`` that no frequency of ``f`` resolves
    (:func:`.frf.unresolved_resonances`), from the roots of the state matrix at ``speed``, and
    their half-power bandwidths ``|Re lam| / pi`` [Hz], each shape (P,); None where the model has
    loss factors (no state form) or more than :data:`_RESONANCE_STATES` states (the figure then
    marks none)."""
    from ..linear_system import speed_linear_form
    from .frf import choose_engine, unresolved_resonances

    if choose_engine(model) != "modal" or len(f) < 2:
        return None
    form = speed_linear_form(model)
    if form.n_states > _RESONANCE_STATES:
        return None
    with _batches.one_blas_thread(72 * form.n_states ** 2):
        roots = np.linalg.eigvals(form.at(float(speed)))
    return unresolved_resonances(roots, f)


def _force_frf(model, speed, f, columns, where):
    """The force FRFs (6 n_items, n_inputs, len(f)) of ``where`` at frequencies ``f`` [Hz] and their
    items (:func:`force_frf`)."""
    omega = 2 * np.pi * np.asarray(f, dtype=float)
    q = dof_response(model, speed, omega, columns)
    if where == "suspensions":
        forces, items = suspension_forces(model, omega, q), model.suspensions
    elif where == "rotors":
        forces, items = bearing_forces(model, speed, omega, q), model.rotors
    elif where == "bearings":
        forces, items = _bearing_items(model, speed, omega, q)
    else:
        forces = np.concatenate([suspension_forces(model, omega, q), bearing_point_forces(model, speed, omega, q),
                                 bearing_forces(model, speed, omega, q)])
        items = list(model.suspensions) + list(model.bearings) + list(model.rotors)
    return np.moveaxis(forces, 1, -1).reshape(len(items) * 6, q.shape[-1], len(omega)), items


def _bearing_items(model, speed, omega, q):
    """Forces of the ``[[bearings]]``, then of the rotors that are rigidly attached."""
    attached = [j for j, r in enumerate(model.rotors) if not model.bearings_of(r.name)]
    rotors = bearing_forces(model, speed, omega, q)[attached]
    forces = np.concatenate([bearing_point_forces(model, speed, omega, q), rotors])
    return forces, list(model.bearings) + [model.rotors[j] for j in attached]
