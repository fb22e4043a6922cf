"""A static load or a Level I station between the nodes of a flexible shaft's mesh is said, not
moved silently (issues 28 and 29 review).

Both act at the nearest node (a static load with the moment of its offset). The static
solution's displacements and reactions stay exact, but its shear force and bending moment
between the node and the load are not the load's: a force P = 1000 N at a = 0.525 m of a 1 m
shaft on supports at its ends (elements of 0.05 m, nodes at 0.5 and 0.55 m) read its largest
bending moment 262.5 N m at 0.5 m; the beam's is ``P a b / L`` = 249.375 N m at the load
(``P b x / L`` = 237.5 N m at 0.5 m). A Level I station between nodes took the nearest node's Q
(examples/compressor_rotor.toml: Q0 stepped by 1 % between two offsets 0.1 mm apart). Neither
said so. Now each draws one warning line naming the node and the remedy (a station at the
point), and with that station the bending moment is the closed form's."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.cli import main

STEEL = {"name": "steel", "density": 7800.0, "young_modulus": 2.0e11, "poisson_ratio": 0.3}
P, A, L = 1000.0, 0.525, 1.0


def _beam(sensor_at=None):
    data = {"name": "beam", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
            "rotors": [{"name": "s", "start": [0.0, 0.0, 0.0], "shear": "none", "element_length": 0.05,
                        "shaft": [{"length": L, "outer_diameter": 0.05, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e12}
                         for n, z in (("A", 0.0), ("B", L))]}
    if sensor_at is not None:
        data["sensors"] = [{"name": "load", "rotor": "s", "axial_position": sensor_at, "direction": [0.0, 0.0, 1.0]}]
    return rdm.Model.from_dict(data)


def _largest_moment(result):
    shaft = result.shafts["s"]
    return float(np.max(np.linalg.norm(shaft.moment, axis=-1)))


def test_a_force_between_nodes_warns_and_a_station_there_gives_the_closed_form():
    force = [{"body": "s", "axial_position": A, "force": [0.0, 0.0, -P]}]
    with pytest.warns(rdm.errors.ModelWarning, match=r"forces\[0\]: acts on rotor s's shaft at 0.525 m from its start, "
                      r"between the nodes of its mesh: it is applied at the nearest node n10 \(0.5 m\) with the "
                      r"moment of its offset 0.025 m"):
        between = rdm.static(_beam(), forces=force)
    reactions = sorted(abs(r.force[2]) for r in between.reactions)
    assert reactions == pytest.approx(sorted([P * A / L, P * (L - A) / L]), rel=1e-9)   # exact either way
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        at_station = rdm.static(_beam(sensor_at=A), forces=force)
    assert _largest_moment(at_station) == pytest.approx(P * A * (L - A) / L, rel=1e-9)


def test_a_force_at_a_node_draws_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rdm.static(_beam(), forces=[{"body": "s", "axial_position": 0.5, "force": [0.0, 0.0, -P]}])


def test_the_static_command_names_the_option_and_its_node(tmp_path, capsys):
    import tomli_w

    path = tmp_path / "beam.toml"
    path.write_bytes(tomli_w.dumps(_beam().to_dict()).encode())
    assert main(["static", str(path), "--force", f"s@{A}:0,0,-{P}", "--quiet"]) == 0
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"rotordyn-modal static: warning: --force s@{A}:0,0,-{P}: acts on rotor s's shaft at "
                           "0.525 m from its start, between the nodes of its mesh: it is applied at the nearest node n10")


def test_a_level1_station_between_nodes_warns_and_one_at_a_node_does_not(examples_dir):
    model = rdm.load_model(examples_dir / "compressor_rotor.toml")
    # nodes at 0.57 and 0.66 m from the start, the centre of mass at 0.583265 m
    with pytest.warns(rdm.errors.ModelWarning, match=r"station compressor@0.0317: 0.614965 m from the shaft's start, "
                      r"between the nodes of rotor compressor's mesh: the cross-coupling acts at its nearest node n5 "
                      r"\(0.57 m from the start, OFFSET -0.0132652 m\)"):
        rdm.level1(model, rdm.rpm(9000), ["compressor@0.0317"], 1e6, factor=2.0, steps_per_qa=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rdm.level1(model, rdm.rpm(9000), ["compressor@0.0767"], 1e6, factor=2.0, steps_per_qa=2)   # n6, 35 µm off
