"""``check MODEL``: validate a model and print a summary."""

from __future__ import annotations

import numpy as np

from ._common import add_model_argument, open_model

NAME = "check"
HELP = "validate a model file and print a summary"
DESCRIPTION = """Validate MODEL and print its masses, rotors with their speed ratios and
suspensions. Exit code 0 when the model is valid, 2 (with one message naming the
file, table, key, value and what was expected) when it is not."""


def add_arguments(parser):
    add_model_argument(parser)


def run(args) -> int:
    model = open_model(args)
    print(summary(model))
    return 0


def summary(model) -> str:
    M, C, G, K = model.matrices()
    lines = [f"{model.source}: valid model {model.name!r}",
             f"  spin axis {np.round(model.spin_axis, 6).tolist()}, reference rotor {model.reference_rotor!r}",
             f"  total mass {model.total_mass:.6g} kg, matrices about {np.round(model.reference_point, 6).tolist()} m"]
    if model.stator is not None:
        lines.append(f"  stator: {model.stator.mass:.6g} kg")
    lines.append(f"  rotors ({len(model.rotors)}):")
    for r in model.rotors:
        lines.append(f"    {r.name:<16} {r.mass:>9.4g} kg  Jp {r.polar_inertia:.4g}  Jd {r.diametral_inertia:.4g} "
                     f"kg m^2  speed ratio {r.speed_ratio:+.6g}")
    for t in model.transmissions:
        teeth = f", {t.driver_teeth} driver teeth" if t.driver_teeth else ""
        lines.append(f"  {t.type} {t.driver} -> {t.driven}: ratio {t.ratio:g}{teeth}")
    lines.append(f"  suspensions ({len(model.suspensions)}):")
    for s in model.suspensions:
        diag = np.diag(s.stiffness_matrix)[:3]
        lines.append(f"    {s.name:<16} at {np.round(s.position, 4).tolist()} m, translational stiffness "
                     f"(model axes) {np.array2string(diag, precision=4)} N/m, loss factor {s.loss_factor:g}")
    lines.append(f"  sensors: {', '.join(s.name for s in model.sensors) or 'none'}; "
                 f"excitations: {', '.join(x.name for x in model.excitations) or 'none'}; "
                 f"unbalances: {len(model.unbalances)}")
    rank = np.linalg.matrix_rank(K)
    if rank < 6:
        lines.append(f"  note: the suspensions restrain {rank} of 6 rigid-body directions "
                     "(the others give zero eigenvalues)")
    return "\n".join(lines)
