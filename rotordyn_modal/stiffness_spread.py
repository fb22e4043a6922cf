"""The stiffness spread (docs/theory.md §8): what each support of a machine, and each Maxwell
branch of its mounts, costs its low modes in significant digits.

A support far stiffer than what it holds, or a branch relaxing far faster than the machine's
slowest stiffness scale, leaves the low modes fewer digits in double precision. Over
:data:`SPREAD_WARN_DIGITS` a model draws a warning (part of
:func:`rotordyn_modal.plausibility.implausible`); where no digit is left it is refused
(:func:`refuse_lost_digits`, the check every analysis makes through
:class:`rotordyn_modal.linear_system.SpeedLinearForm`).
"""

from __future__ import annotations

import numpy as np

from .assembly import bearing_motion, is_large, mass_matrix
from .elements.bearings import evaluate
from .errors import ModelError
from .model._table import visible

__all__ = ["spread_lines", "refuse_lost_digits", "stiffness_spread_lines", "maxwell_spread_lines", "support_spreads",
           "SPREAD_WARN_DIGITS", "SPREAD_REFUSE_DIGITS", "MAXWELL_REFUSE_DIGITS"]


def spread_lines(model) -> list[str]:
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
    analysis makes (:class:`~rotordyn_modal.linear_system.SpeedLinearForm`), so that a model built in Python
    (``Model.from_dict``, ``Model.variant``: no ``implausible``) or a study's variant gives no
    silently wrong answer. Looked at once per model; the warnings below the refusal are
    :func:`~rotordyn_modal.plausibility.implausible`'s."""
    if not getattr(model, "_digits_checked", False):
        spread_lines(model)


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
    to round-off, :func:`~rotordyn_modal.linear_system.checked_mass_inverse`'s refusal)."""
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
