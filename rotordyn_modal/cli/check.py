"""``check MODEL``: validate a model and print a summary."""

from __future__ import annotations

import numpy as np

from ..model.geometry import transverse_axes
from ..units import to_system, unit_label
from ._common import add_model_argument, open_model

NAME = "check"
HELP = "validate a model file and print a summary"
DESCRIPTION = """Validate MODEL and print (in the units of --units: kg, m, N/m or lb, in, lbf/in,
lb in², oz in, reyn) its masses, rotors with their speed ratios,
suspensions, bearings and generalized coordinates; for each flexible rotor (one with a shaft) its
mesh (nodes, elements), mass, centre of mass, polar and diametral inertia computed from its shaft,
disks and point masses, and its first bending natural frequency at rest, free-free and on its
bearings (the stator held still; tabulated bearings at their first row, its speed named when not 0; not with journal bearings,
which hold nothing at rest): the lowest mode with the share of its strain energy in the shaft, and
the lowest mode with most of its strain energy in the shaft.
Exit code 0 when the model is valid, 2 (with one message naming the
file, table, key, value and what was expected) when it is not. What is legal but probably not
meant (a static sag of over 0.1 m under gravity: a stiffness in N/mm given as N/m, or a mass in g given as kg; a mount mode
below 0.5 Hz; a rotor's rigid-body mode in its bearings below 0.5 Hz, journal films taken at light load;
a journal bearing longer than its diameter; a flexible rotor's station within 1e-3 of an
element of another, placed at its node) is printed on stderr, one warning line
each, as every command does (docs/model-file.md, "Warnings")."""


def add_arguments(parser):
    add_model_argument(parser)
    parser.add_argument("--quiet", action="store_true",
                        help="print no summary: the exit code says whether the model is valid (warnings and "
                             "errors still go to stderr)")


def run(args) -> int:
    from ..linear_system import speed_linear_form

    model = open_model(args)
    speed_linear_form(model)  # refuses a mass matrix that rounding leaves singular, as every analysis would
    if not args.quiet:
        print(summary(model, args.units))
    return 0


def summary(model, system: str = "si") -> str:
    """The model in a few lines, its quantities in the units of ``system`` ('si' or 'us')."""
    from ..assembly import constant_matrices, is_large, sparse_constant_matrices

    u = _Units(system)
    K = sparse_constant_matrices(model).K if is_large(model) else constant_matrices(model).K   # large: sparse
    lines = [f"{model.source}: valid model {model.name!r}",
             f"  spin axis {np.round(model.spin_axis, 6).tolist()}, reference rotor {model.reference_rotor!r}",
             f"  total mass {u(model.total_mass, 'mass'):.6g} {u.label('mass')}, matrices about "
             f"{np.round(u(model.reference_point, 'length'), 6).tolist()} {u.label('length')}"]
    if model.stator is not None:
        lines.append(f"  stator: {u(model.stator.mass, 'mass'):.6g} {u.label('mass')}")
    lines.append(f"  rotors ({len(model.rotors)}):")
    for r in model.rotors:
        lines.append(f"    {r.name:<16} {u(r.mass, 'mass'):>9.4g} {u.label('mass')}  "
                     f"Jp {u(r.polar_inertia, 'inertia'):.4g}"
                     f"  Jd {u(r.diametral_inertia, 'inertia'):.4g} {u.label('inertia')}  speed ratio "
                     f"{r.speed_ratio:+.6g}")
    lines += _flexible_lines(model, u)
    for t in model.transmissions:
        teeth = f", {t.driver_teeth} driver teeth" if t.driver_teeth else ""
        mesh = f", mesh stiffness {u(t.mesh_stiffness, 'stiffness'):.4g} {u.label('stiffness')}" \
            if t.mesh_stiffness is not None else ""
        lines.append(f"  {t.type} {t.driver} -> {t.driven}: ratio {t.ratio:g}{teeth}{mesh}")
    lines.append(f"  suspensions ({len(model.suspensions)}):")
    for s in model.suspensions:
        diag = np.diag(s.stiffness_matrix)[:3]
        lines.append(f"    {s.name:<16} at {np.round(u(s.position, 'length'), 4).tolist()} {u.label('length')}, "
                     f"translational stiffness (model axes) {np.array2string(u(diag, 'stiffness'), precision=4)} "
                     f"{u.label('stiffness')}, loss factor {s.loss_factor:g}")
    lines += _bearing_lines(model, u)
    lines.append(f"  sensors: {', '.join(s.name for s in model.sensors) or 'none'}; "
                 f"excitations: {', '.join(x.name for x in model.excitations) or 'none'}; "
                 f"unbalances: {len(model.unbalances)}")
    lines += _grade_lines(model, u)
    layout = model.dofs
    lines.append(f"  coordinates ({layout.n}): {', '.join(_coordinate_names(model))}")
    rank = _dense_rank(K) if layout.n <= _DENSE_RANK else _sparse_rank(model, K)
    if rank < layout.n and not model.speed_dependent:
        lines.append(f"  note: the suspensions and bearings restrain {rank} of {layout.n} directions "
                     "(the others give zero eigenvalues)")
    return "\n".join(lines)


#: coordinates up to which the note on unrestrained directions takes the rank of K from its SVD;
#: beyond (a long flexible rotor), from the lowest eigenvalues of K's symmetric part (see
#: :func:`_sparse_rank`)
_DENSE_RANK = 2000


def _dense_rank(K) -> int:
    """The rank of ``K`` with its rows and columns scaled to a unit diagonal size first
    (``D^-1/2 K D^-1/2``): unscaled, a 1 mm shaft 20 m long beside a compressor's (element
    stiffnesses 1 against 1e9 N/m) fell below numpy's tolerance, and the note counted its 22
    bending modes of 0.002 Hz and up as directions nothing holds."""
    size = np.sqrt(np.linalg.norm(K, axis=0) * np.linalg.norm(K, axis=1))
    held = size > 0
    root = np.sqrt(size[held])
    return int(np.linalg.matrix_rank(K[np.ix_(held, held)] / np.outer(root, root))) if held.any() else 0


def _sparse_rank(model, K) -> int:
    """The rank of a large model's stiffness: ``n`` less the zero eigenvalues among the 12 lowest
    of its symmetric part against the mass (shift-invert Lanczos just below zero, as
    ``model.flexible.bending_frequencies``); zero: within the rounding of the mode's own
    ``phi^T K phi`` (``model.flexible.held_modes``; ``1e-9`` of the largest diagonal ratio
    ``K_ii / M_ii`` before, which counted a fine mesh's first bending modes as free)."""
    import scipy.sparse
    import scipy.sparse.linalg

    from .._blas import seeded_start
    from ..assembly import is_large, mass_matrix, sparse_constant_matrices
    from ..model.flexible import held_modes

    stiffness = scipy.sparse.csc_matrix(0.5 * (K + K.T))
    mass = scipy.sparse.csc_matrix(sparse_constant_matrices(model).M if is_large(model) else mass_matrix(model))
    diagonal = mass.diagonal()
    largest = float(np.max(np.abs(stiffness.diagonal()) / np.where(diagonal > 0, diagonal, np.inf)))
    shift = -1e-12 * largest
    values, vectors = scipy.sparse.linalg.eigsh(stiffness, k=min(12, K.shape[0] - 2), M=mass,
                                                sigma=shift, which="LM", v0=seeded_start(K.shape[0]))
    return K.shape[0] - int(np.count_nonzero(~held_modes(values, vectors, stiffness, shift)))


class _Units:
    """``u(value, kind)``: an SI value in ``system``'s unit (SI values untouched); ``u.label(kind)``
    its unit as this summary writes it (SI: as it always has)."""

    _SI_LABELS = {"inertia": "kg m^2"}

    def __init__(self, system: str = "si"):
        self.system = system

    def __call__(self, value, kind):
        return value if self.system == "si" else to_system(value, kind, self.system)

    def label(self, kind):
        return self._SI_LABELS.get(kind, unit_label(kind, "si")) if self.system == "si" else \
            unit_label(kind, self.system)


def _grade_lines(model, units=_Units()) -> list[str]:
    """The amount of each unbalance given by an ISO 21940-11 balance grade."""
    lines = []
    for k, u in enumerate(model.unbalances):
        if u.grade is not None:
            mass = model.rotor(u.rotor).mass if u.mass is None else u.mass
            amount = f"{u.amount * 1e6:.6g} g mm" if units.system == "si" else \
                f"{to_system(u.amount, 'unbalance', units.system):.6g} {units.label('unbalance')}"
            lines.append(f"    unbalances[{k}] on {u.rotor!r}: G{u.grade:g} at {u.service_speed_rpm:g} rpm of "
                         f"{units(mass, 'mass'):.6g} {units.label('mass')} -> {amount} (ISO 21940-11, G m / Omega)")
    return lines


def _coordinate_names(model) -> list[str]:
    """The coordinates' names, a flexible rotor's node coordinates as one range."""
    names = list(model.dofs.names)
    ranges = []
    for rotor in model.rotors:
        shaft = model.dofs.shaft(rotor.name)
        if shaft is not None:
            ranges.append((model.dofs.slices[model.dofs.rotors.index(rotor.name)].start, shaft.mesh.n_nodes))
    for start, count in sorted(ranges, reverse=True):   # from the last: earlier indices stay valid
        names[start:start + 4 * count] = [f"{names[start]} ... {names[start + 4 * count - 1]} "
                                          f"({count} nodes x 4)"]
    return names


def _flexible_lines(model, u=_Units()) -> list[str]:
    """Mesh, mass properties and first bending frequencies of each flexible rotor."""
    from ..model.flexible import bending_frequencies

    lines = []
    for rotor in model.rotors:
        shaft = rotor.flexible
        if shaft is None:
            continue
        bearings = model.bearings_of(rotor.name)
        at_rest = all(b.coefficients.kind != "journal" for b in bearings)   # a film holds nothing at rest
        supports = [(shaft.z_of(b.position), b.coefficients.stiffness[0]) for b in bearings] if at_rest else []
        free, (lowest, share), bending = bending_frequencies(shaft, supports)
        if not at_rest:
            held = "on its bearings: not computed (a journal bearing has no stiffness at rest)"
        elif not lowest > 0:
            held = "on its bearings: the bearings leave it free at rest"
        else:
            held = (f"on its bearings (stator held{_first_rows(bearings)}) lowest mode {lowest:.6g} Hz ({share:.0%} of its "
                    f"strain energy in the shaft), first mostly bending (over 50 % in the shaft) {bending:.6g} Hz")
        m, kg, inertia = u.label("length"), u.label("mass"), u.label("inertia")
        lines += [f"  flexible rotor {rotor.name}: shaft {u(shaft.length, 'length'):.6g} {m} from "
                  f"{np.round(u(shaft.start, 'length'), 6).tolist()} {m}, "
                  f"{len(shaft.sections)} sections, {len(shaft.disks)} disks, {len(shaft.point_masses)} point masses; "
                  f"mesh {shaft.mesh.n_nodes} nodes, {len(shaft.mesh.elements)} elements (shear {shaft.shear})",
                  f"    mass {u(rotor.mass, 'mass'):.6g} {kg}, centre of mass "
                  f"{np.round(u(rotor.center_of_mass, 'length'), 6).tolist()} {m}, polar inertia "
                  f"{u(rotor.polar_inertia, 'inertia'):.6g} {inertia}, diametral inertia "
                  f"{u(rotor.diametral_inertia, 'inertia'):.6g} {inertia}",
                  f"    at rest: first bending frequency free-free {free:.6g} Hz; {held}"]
    return lines


def _first_rows(bearings) -> str:
    """``; [bearings.A] at its table's first row, 1000 rpm`` for each speed table that does not
    start at rest (the stiffness of that row stands for the bearing at rest), else empty."""
    rows = [f"[bearings.{b.name}] at its table's first row, {b.coefficients.speeds[0] * 30 / np.pi:.6g} rpm"
            for b in bearings if b.coefficients.kind == "table" and b.coefficients.speeds[0] != 0]
    return "; " + "; ".join(rows) if rows else ""


def _bearing_lines(model, u=_Units()) -> list[str]:
    if not model.bearings:
        return []
    where = "the stator" if model.stator is not None else "the ground"
    lines = [f"  bearings ({len(model.bearings)}, to {where}):"]
    for b in model.bearings:
        lines.append(f"    {b.name:<16} rotor {b.rotor!r} at {np.round(u(b.position, 'length'), 4).tolist()} "
                     f"{u.label('length')}, " + _coefficient_text(b.coefficients, model.spin_axis, u,
                                                                   model.rotor(b.rotor).flexible is None,
                                                                   any(m.pedestal is not None
                                                                       for m in model.bearings_of(b.rotor)))
                     + _pedestal_text(b, model.spin_axis, u))
    return lines


def _pedestal_text(bearing, spin_axis, u=_Units()) -> str:
    """``, on a pedestal of M kg, stiffness [k1 k2] N/m`` (empty without a pedestal)."""
    if bearing.pedestal is None:
        return ""
    plane = transverse_axes(spin_axis)
    values = np.sort(np.linalg.eigvalsh(plane @ bearing.pedestal.stiffness @ plane.T))
    return (f", on a pedestal of {u(bearing.pedestal.mass, 'mass'):.4g} {u.label('mass')}, stiffness "
            f"{np.array2string(u(values, 'stiffness'), precision=4)} {u.label('stiffness')}")


def _solved_load_text(journal, rigid: bool, pedestals: bool) -> str:
    """What a journal's printed static load is when the analyses solve it at each speed (a rotor on
    three or more journals, docs/static.md), or that a given load is fixed in the split."""
    if journal.fixed_load:
        return " (given: a fixed force in the rotor's split)"
    if journal.load_over_speed is None:
        return ""
    if rigid:
        return (" on the films alone at light load (their high-speed limit); analyses and static solve it at each "
                "speed on the nonlinear films" + (" with the pedestals" if pedestals else "") + " (docs/static.md)")
    return (" on rigid films" + (" and the pedestals" if pedestals else "") + " (its high-speed limit); analyses and "
            "static solve it at each speed on the films" + (" with the pedestals" if pedestals else "")
            + " (docs/static.md)")


def _coefficient_text(coefficients, spin_axis, u=_Units(), rigid: bool = True, pedestals: bool = False) -> str:
    if coefficients.kind == "journal":
        j = coefficients.journal
        m = u.label("length")
        return (f"plain journal D {u(j.diameter, 'length'):g} {m} x L {u(j.length, 'length'):g} {m}, clearance "
                f"{u(j.clearance, 'length'):g} {m}, viscosity {u(j.viscosity, 'viscosity'):g} "
                f"{u.label('viscosity')}, static load {u(j.load, 'force'):.4g} {u.label('force')}"
                + _solved_load_text(j, rigid, pedestals))
    # the translational stiffness in the plane normal to the spin axis (whatever the axial one)
    plane = transverse_axes(spin_axis)                                          # (2, 3), orthonormal
    radial = np.linalg.eigvals(plane @ coefficients.stiffness[0][:3, :3] @ plane.T)
    text = f"radial stiffness {np.array2string(u(np.sort(np.abs(radial)), 'stiffness'), precision=4)} " \
        f"{u.label('stiffness')}"
    if coefficients.kind == "table":
        rpm = coefficients.speeds * 30 / np.pi
        text += f" at {rpm[0]:g} rpm, tabulated over {len(rpm)} speeds {rpm[0]:g} .. {rpm[-1]:g} rpm"
    return text
