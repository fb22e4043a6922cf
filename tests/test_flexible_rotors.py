"""Flexible rotors in the machine model: the model file, the mesh, the coordinates, the assembly
and the analyses (issue 28). Truths from outside the code: the rigid-rotor limit, the simply
supported beam's closed form, invariants of undamped gyroscopic systems, reciprocity, the
origin's freedom, and statics' signs."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.assembly import excitation_columns, sensor_rows
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}


def _machine(element_length=1.0, scale=1.0):
    """A flexible rotor (two sections, one tapered and hollow; an overhung disk) on two
    anisotropic bearings in a casing on four mounts, turning at -1.5 times the reference rotor
    (a rigid one fixed in the casing); undamped."""
    material = dict(STEEL, young_modulus=STEEL["young_modulus"] * scale,
                    shear_modulus=STEEL["shear_modulus"] * scale)
    return {
        "name": "t", "spin_axis": [1.0, 0.0, 0.0], "materials": [material],
        "stator": {"mass": 60.0, "inertia": [2.0, 3.0, 3.5], "center_of_mass": [0.3, 0.0, 0.1]},
        "reference_rotor": "m",
        "rotors": [{"name": "r", "speed_ratio": -1.5, "start": [0.0, 0.02, 0.15], "element_length": element_length,
                    "shaft": [{"length": 0.2, "outer_diameter": 0.04, "material": "steel"},
                              {"length": 0.4, "outer_diameter": [0.05, 0.04], "inner_diameter": 0.01,
                               "material": "steel"}],
                    "disks": [{"name": "imp", "axial_position": 0.05, "mass": 4.0, "polar_inertia": 0.02,
                               "diametral_inertia": 0.012}]},
                   {"name": "m", "speed_ratio": 1.0, "mass": 2.0, "center_of_mass": [0.5, 0.1, 0.2],
                    "polar_inertia": 0.004, "diametral_inertia": 0.003}],
        "bearings": [{"name": "A", "rotor": "r", "axial_position": 0.2, "stiffness": [2e6, 3e6],
                      "axial_stiffness": 1e6},
                     {"name": "B", "rotor": "r", "axial_position": 0.6, "stiffness": 2.5e6, "moment_stiffness": 1e3}],
        "suspensions": [{"name": f"m{i}", "position": p, "stiffness": [1e5, 1.2e5, 2e5]} for i, p in
                        enumerate([[0, 0.2, 0], [0, -0.2, 0], [0.6, 0.2, 0], [0.6, -0.2, 0]])],
    }


def _rigid_twin(flexible_model, description):
    """The same machine with the rotor rigid: its computed mass, centre and inertias."""
    rotor = flexible_model.rotors[0]
    data = copy.deepcopy(description)
    del data["materials"]
    data["rotors"][0] = {"name": "r", "speed_ratio": rotor.speed_ratio, "mass": rotor.mass,
                         "center_of_mass": rotor.center_of_mass.tolist(), "polar_inertia": rotor.polar_inertia,
                         "diametral_inertia": rotor.diametral_inertia}
    start = np.array(description["rotors"][0]["start"])
    for bearing in data["bearings"]:
        bearing["position"] = (start + [bearing.pop("axial_position"), 0.0, 0.0]).tolist()
    return rdm.Model.from_dict(data)


def _refined(model, speed, start):
    """The undamped gyroscopic model's natural frequency near ``start`` [rad/s]: H(w) = K - w^2 M
    + i w speed G is Hermitian; Newton on x^H H(w) x with inverse iteration for x (no state-space
    eigen-solve, whose round-off grows with the stiffest element)."""
    M, _, G, K = model.matrices()
    w = start * (1 + 1e-7)
    x = np.ones(len(M), dtype=complex)
    for _ in range(40):
        H = K - w * w * M + 1j * w * speed * G
        x = np.linalg.solve(H, x)
        x /= np.linalg.norm(x)
        H = K - w * w * M + 1j * w * speed * G
        step = np.real(x.conj() @ H @ x) / np.real(x.conj() @ (-2 * w * M + 1j * speed * G) @ x)
        w -= step
        if abs(step) < 1e-15 * w:
            break
    return w


def test_flexible_rotor_tends_to_the_rigid_rotor_as_one_over_e():
    speed = 300.0
    rigid = _rigid_twin(rdm.Model.from_dict(_machine()), _machine())
    M, _, G, K = rigid.matrices()
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -speed * np.linalg.solve(M, G)]])
    roots = np.linalg.eigvals(A)
    targets = np.sort(roots[roots.imag > 0].imag)
    exact = np.array([_refined(rigid, speed, w) for w in targets])
    errors = []
    for scale in (1e3, 1e6):
        flexible = rdm.Model.from_dict(_machine(scale=scale))
        found = np.array([_refined(flexible, speed, w) for w in exact])
        errors.append(np.max(np.abs(found - exact) / exact))
    assert errors[0] < 1e-3
    assert 1000 / 3 < errors[0] / errors[1] < 1000 * 3, errors


def test_mass_properties_are_the_shaft_and_disks():
    model = rdm.Model.from_dict(_machine())
    rotor = model.rotors[0]
    rho = STEEL["density"]
    # section 1: a cylinder; section 2: a hollow frustum (outer 0.05 -> 0.04, bore 0.01)
    m1 = rho * np.pi / 4 * 0.04 ** 2 * 0.2
    z = np.linspace(0, 0.4, 200001)
    outer = 0.05 - 0.01 * z / 0.4
    area = np.pi / 4 * (outer ** 2 - 0.01 ** 2)
    m2 = rho * np.trapezoid(area, z)
    z2 = rho * np.trapezoid(area * (0.2 + z), z) / m2
    mass = m1 + m2 + 4.0
    centre = (m1 * 0.1 + m2 * z2 + 4.0 * 0.05) / mass
    polar = rho * np.pi / 32 * 0.04 ** 4 * 0.2 + rho * np.trapezoid(np.pi / 32 * (outer ** 4 - 0.01 ** 4), z) + 0.02
    assert rotor.mass == pytest.approx(mass, rel=1e-9)
    assert rotor.center_of_mass == pytest.approx([centre, 0.02, 0.15], rel=1e-9, abs=1e-12)
    assert rotor.polar_inertia == pytest.approx(polar, rel=1e-8)


def test_undamped_gyroscopic_flexible_machine_keeps_imaginary_roots_and_reciprocity():
    data = _machine(element_length=0.1)
    data["sensors"] = [{"name": "s-imp", "rotor": "r", "axial_position": 0.05, "direction": [0, 1, 0]},
                       {"name": "s-mid", "rotor": "r", "axial_position": 0.4, "direction": [0, 0.6, 0.8]},
                       {"name": "s-cas", "position": [0.5, 0.1, 0.2], "direction": [0, 0, 1]}]
    data["excitations"] = [{"name": x["name"], **{k: v for k, v in x.items() if k != "name"}}
                           for x in data["sensors"]]
    model = rdm.Model.from_dict(data)
    M, C, G, K = model.matrices()
    assert not C.any()
    speed = 800.0
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -speed * np.linalg.solve(M, G)]])
    roots = np.linalg.eigvals(A)
    assert np.max(np.abs(roots.real)) < 1e-9 * np.max(np.abs(roots))
    rows, columns = sensor_rows(model), excitation_columns(model)
    assert np.allclose(rows, columns.T, rtol=0, atol=1e-15)    # collocated: the same points and directions
    for w in (50.0, 400.0, 3000.0):
        H = [rows @ np.linalg.solve(K - w * w * M + 1j * w * s * G, columns) for s in (speed, -speed)]
        assert np.abs(H[0] - H[1].T).max() <= 1e-9 * np.abs(H[0]).max()
        assert np.abs(H[0] - H[0].T).max() > 1e-6 * np.abs(H[0]).max()   # the gyroscopic coupling shows


def _moved(data, offset):
    data = copy.deepcopy(data)
    data["stator"]["center_of_mass"] = (np.add(data["stator"]["center_of_mass"], offset)).tolist()
    data["rotors"][0]["start"] = (np.add(data["rotors"][0]["start"], offset)).tolist()
    data["rotors"][1]["center_of_mass"] = (np.add(data["rotors"][1]["center_of_mass"], offset)).tolist()
    for s in data["suspensions"] + data.get("sensors", []) + data.get("excitations", []):
        if "position" in s:
            s["position"] = (np.add(s["position"], offset)).tolist()
    return data


def test_moving_the_origin_changes_nothing():
    data = _machine(element_length=0.1)
    data["bearings"][0]["damping"] = 300.0
    data["sensors"] = [{"name": "s", "rotor": "r", "position": [0.4, 0.02, 0.15], "direction": [0, 1, 0]}]
    data["excitations"] = [{"name": "x", "rotor": "r", "axial_position": 0.05, "direction": [0, 0, 1]}]
    data["unbalances"] = [{"rotor": "r", "amount": 1e-4, "axial_position": 0.05}]
    results = []
    for offset in ([0, 0, 0], [1.3, -0.7, 2.1]):
        model = rdm.Model.from_dict(_moved(data, offset))
        modes = rdm.modal(model, 500.0)
        frf = rdm.frf(model, 500.0, [20.0, 150.0, 600.0])
        unbalance = rdm.unbalance_response(model, [300.0, 900.0])
        results.append((np.sort_complex(modes.eigenvalues), frf.H, unbalance.response))
    for a, b in zip(*results):
        assert np.allclose(a, b, rtol=1e-8, atol=1e-8 * np.abs(a).max())


def test_uniform_shaft_on_stiff_end_bearings_is_the_simply_supported_rayleigh_beam():
    length, diameter = 1.0, 0.05
    data = {"materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0], "shear": "none",
                        "shaft": [{"length": length, "outer_diameter": diameter, "material": "steel", "elements": 40}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e13} for n, z in
                         (("a", 0.0), ("b", length))]}
    model = rdm.Model.from_dict(data)
    M, _, _, K = model.matrices()
    found = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True))[:6:2]
    area, second = np.pi / 4 * diameter ** 2, np.pi / 64 * diameter ** 4
    beta = np.arange(1, 4) * np.pi / length
    exact = np.sqrt(STEEL["young_modulus"] * second * beta ** 4
                    / (STEEL["density"] * area * (1 + second / area * beta ** 2)))
    assert found == pytest.approx(exact, rel=2e-5)


def test_node_coordinates_follow_the_right_hand_rule():
    """A force along a (b) at mid-span of a simply supported shaft bends it into u_a > 0 (u_b > 0):
    at the left end theta_b = +du_a/dz > 0 and theta_a = -du_b/dz < 0."""
    data = {"materials": [STEEL], "spin_axis": [0.0, 0.0, 1.0],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0],
                        "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e12} for n, z in
                         (("a", 0.0), ("b", 1.0))],
            "excitations": [{"name": "fa", "rotor": "s", "axial_position": 0.5, "direction": [1, 0, 0]},
                            {"name": "fb", "rotor": "s", "axial_position": 0.5, "direction": [0, 1, 0]}]}
    model = rdm.Model.from_dict(data)       # spin along z: a = x, b = y
    _, _, _, K = model.matrices()
    names = list(model.dofs.names)
    q = np.linalg.solve(K, excitation_columns(model))
    mid = model.rotors[0].flexible.mesh.node(0.5)
    assert q[names.index(f"s.n{mid}.ux"), 0] > 0 and q[names.index("s.n0.ry"), 0] > 0
    assert q[names.index(f"s.n{mid}.uy"), 1] > 0 and q[names.index("s.n0.rx"), 1] < 0


def test_mesh_has_a_node_at_every_station():
    data = _machine(element_length=0.07)
    data["sensors"] = [{"name": "p", "rotor": "r", "axial_position": 0.333, "direction": [0, 1, 0]}]
    data["unbalances"] = [{"rotor": "r", "amount": 1e-4, "axial_position": 0.111}]
    data["rotors"][0]["point_masses"] = [{"axial_position": 0.555, "mass": 0.5}]
    shaft = rdm.Model.from_dict(data).rotors[0].flexible
    z = shaft.mesh.z
    for station in (0.0, 0.05, 0.111, 0.2, 0.333, 0.555, 0.6):
        assert np.min(np.abs(z - station)) < 1e-12
    assert np.diff(z).max() <= 0.07 + 1e-12
    assert len(shaft.mesh.elements) == len(z) - 1


def test_unbalance_on_a_flexible_rotor_acts_at_its_node():
    data = _machine(element_length=0.1)
    data["unbalances"] = [{"rotor": "r", "amount": 2e-4, "phase_deg": 30.0, "axial_position": 0.05}]
    data["sensors"] = [{"name": "imp", "rotor": "r", "axial_position": 0.05, "direction": [0, 0, 1]}]
    data["rotors"][0]["speed_ratio"] = 1.0
    model = rdm.Model.from_dict(data)
    speed = 700.0
    result = rdm.unbalance_response(model, [speed])
    M, C, G, K = model.matrices()
    # the centrifugal force amount w^2 turning from z towards e x z = -y, phase 30 deg, at the disk's node
    f = np.zeros(len(M), dtype=complex)
    force = 2e-4 * speed ** 2 * np.exp(1j * np.radians(30.0)) * (np.array([0, 0, 1.0]) - 1j * np.array([0, -1.0, 0]))
    node = model.rotors[0].flexible.mesh.node(0.05)
    names = list(model.dofs.names)
    f[names.index(f"r.n{node}.uy")], f[names.index(f"r.n{node}.uz")] = force[1], force[2]
    # the stator feels the same force at the node: its six equations get B_SP [F, 0]
    arm = np.array([0.05, 0.02, 0.15]) - model.reference_point
    f[:3] += force
    f[3:6] += np.cross(arm, force)
    q = np.linalg.solve(K - speed ** 2 * M + 1j * speed * (C + speed * G), f)
    expected = q[names.index(f"r.n{node}.uz")] + q[2] + q[3] * arm[1] - q[4] * arm[0]
    assert result.response[0, 0, 0] == pytest.approx(expected, rel=1e-9)


def test_dotted_keys_reach_sections_disks_and_materials():
    model = rdm.Model.from_dict(_machine())
    thicker = model.with_values({"rotors.r.shaft.0.outer_diameter": 0.05})
    assert thicker.rotors[0].mass == pytest.approx(
        model.rotors[0].mass + STEEL["density"] * np.pi / 4 * (0.05 ** 2 - 0.04 ** 2) * 0.2, rel=1e-12)
    heavier = model.variant([("rotors.r.disks.imp.mass", "scale", 2.0)])
    assert heavier.rotors[0].mass == pytest.approx(model.rotors[0].mass + 4.0, rel=1e-12)
    assert model.rotors[0].mass == pytest.approx(thicker.rotors[0].mass - STEEL["density"] * np.pi / 4
                                                 * (0.05 ** 2 - 0.04 ** 2) * 0.2, rel=1e-12)   # unchanged
    stiffer = model.variant([("materials.steel.young_modulus", "scale", 4.0),
                             ("materials.steel.shear_modulus", "scale", 4.0)])
    from rotordyn_modal.assembly import shaft_stiffness

    shaft = shaft_stiffness(model)
    assert np.abs(stiffer.matrices().K - model.matrices().K - 3 * shaft).max() <= 1e-12 * np.abs(shaft).max()
    assert model.get("rotors.r.shaft.1.inner_diameter") == 0.01


# -- bad input, each refused by name -----------------------------------------------------------
def _flexible_only():
    data = _machine(element_length=0.1)
    data["sensors"] = [{"name": "p", "rotor": "r", "axial_position": 0.3, "direction": [0, 1, 0]}]
    data["excitations"] = [{"name": "x", "rotor": "r", "axial_position": 0.3, "direction": [0, 1, 0]}]
    data["unbalances"] = [{"rotor": "r", "amount": 1e-4, "axial_position": 0.05}]
    return data


def _set(path, value=None, delete=False):
    def change(data):
        *parents, last = path
        target = data
        for key in parents:
            target = target[key]
        if delete:
            del target[last]
        else:
            target[last] = value
    return change


def _extra_disk(**keys):
    def change(data):
        data["rotors"][0]["disks"].append({"name": "second", "mass": 1.0, "polar_inertia": 0.01,
                                           "diametral_inertia": 0.01, **keys})
    return change


def _widths(data):
    data["rotors"][0]["disks"][0]["width"] = 0.04
    data["rotors"][0]["disks"].append({"name": "second", "axial_position": 0.08, "width": 0.04, "mass": 1.0,
                                       "polar_inertia": 0.01, "diametral_inertia": 0.01})


BAD = {
    "inner diameter not below outer": (_set(["rotors", 0, "shaft", 0, "inner_diameter"], 0.04),
                                       "[rotors.r.shaft.0] inner_diameter = 0.04"),
    "section of zero length": (_set(["rotors", 0, "shaft", 1, "length"], 0.0), "[rotors.r.shaft.1] length = 0.0"),
    "bearing off the shaft's end": (_set(["bearings", 1, "axial_position"], 0.65), "[bearings.B] axial_position = 0.65"),
    "bearing off the axis": (lambda d: d["bearings"][0].update(position=[0.2, 0.03, 0.15]) or
                             d["bearings"][0].pop("axial_position"), "[bearings.A] position"),
    "disk off the shaft": (_set(["rotors", 0, "disks", 0, "axial_position"], -0.01),
                           "[rotors.r.disks.imp] axial_position = -0.01"),
    "sensor off the shaft": (_set(["sensors", 0, "axial_position"], 0.7), "[sensors.p] axial_position = 0.7"),
    "sensor off the axis": (lambda d: d["sensors"][0].update(position=[0.3, 0.02, 0.2]) or
                            d["sensors"][0].pop("axial_position"), "[sensors.p] position"),
    "excitation off the shaft": (_set(["excitations", 0, "axial_position"], -0.2),
                                 "[excitations.x] axial_position = -0.2"),
    "unbalance off the shaft": (_set(["unbalances", 0, "axial_position"], 0.9), "[unbalances[0]] axial_position = 0.9"),
    "two disks at one station": (_extra_disk(axial_position=0.05), "[rotors.r.disks.second] axial_position = 0.05"),
    "overlapping disk widths": (_widths, "[rotors.r.disks.second] axial_position = 0.08"),
    "material without E": (_set(["materials", 0, "young_modulus"], delete=True),
                           "[materials.steel] young_modulus = '<missing>'"),
    "unknown material": (_set(["rotors", 0, "shaft", 0, "material"], "brass"), "[rotors.r.shaft.0] material = 'brass'"),
    "inconsistent mass": (_set(["rotors", 0, "mass"], 5.0), "[rotors.r] mass = 5.0"),
    "inconsistent polar inertia": (_set(["rotors", 0, "polar_inertia"], 1.0), "[rotors.r] polar_inertia = 1.0"),
    "flexible rotor without bearings": (lambda d: d.update(bearings=[]), "[rotors.r] shaft"),
    "disks on a rigid rotor": (lambda d: d["rotors"].append({"name": "q", "mass": 1.0, "center_of_mass": [0, 0, 0],
                                                             "polar_inertia": 0.01, "diametral_inertia": 0.01,
                                                             "speed_ratio": 1.0, "disks": []})
                               , "[rotors.q] disks"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_flexible_input_is_refused_by_name(case):
    change, where = BAD[case]
    data = _flexible_only()
    change(data)
    with pytest.raises(ModelError) as error:
        rdm.Model.from_dict(data, source="m.toml")
    assert str(error.value).startswith("m.toml: " + where), str(error.value)
    assert "expected" in str(error.value) and "\n" not in str(error.value)


def test_consistent_given_mass_properties_are_accepted():
    model = rdm.Model.from_dict(_flexible_only())
    rotor = model.rotors[0]
    data = _flexible_only()
    data["rotors"][0].update(mass=rotor.mass * (1 + 5e-7), polar_inertia=rotor.polar_inertia,
                             diametral_inertia=rotor.diametral_inertia, center_of_mass=rotor.center_of_mass.tolist())
    assert rdm.Model.from_dict(data).rotors[0].mass == rotor.mass


def test_bad_flexible_file_exits_2_with_one_line(tmp_path, capsys):
    import tomli_w

    data = _flexible_only()
    data["rotors"][0]["shaft"][0]["inner_diameter"] = 0.05
    path = tmp_path / "bad.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "[rotors.r.shaft.0] inner_diameter = 0.05" in err


# -- the command line on the flexible examples ------------------------------------------------
COMMANDS = [
    ["check"], ["modes", "--speed", "3000"], ["campbell", "--speeds", "0:6000:4"],
    ["critical-speeds", "--speeds", "0:9000:7"], ["stability", "--speeds", "0:6000:3"],
    ["frf", "--speed", "3000", "--freqs", "10:400:8"], ["unbalance", "--speeds", "1000:6000:6"],
]


@pytest.mark.parametrize("example, commands", [("compressor_rotor.toml", COMMANDS),
                                               ("flexible_pump_on_mounts.toml", COMMANDS[:1])])
def test_analyses_run_on_the_flexible_examples(examples_dir, example, commands, capsys):
    for command in commands:
        assert main([command[0], str(examples_dir / example), *command[1:]]) == 0, command
        out = capsys.readouterr().out
        assert len(out.strip().splitlines()) >= 2, (command, out)


def test_simulate_runs_a_flexible_rotor_up_and_refuses_free_spin_by_one_line(examples_dir, tmp_path, capsys):
    """The compressor's run-up writes its table, saying once on stderr that the machine is
    integrated as its linear model; free spin, which that model does not have, is refused by one
    line (exit 2). (The run-up figure is the rigid machines' own, drawn by test_simulate_cli.)"""
    import pandas as pd

    model = str(examples_dir / "compressor_rotor.toml")
    table = tmp_path / "runup.csv"
    assert main(["simulate", model, "--speed", "5000", "--ramp", "5200", "--duration", "0.05", "--quiet",
                 "--samples", "801", "--modes-below", "300", "--out", str(table)]) == 0
    err = capsys.readouterr().err
    assert err.count("integrated as its linear model") <= 1          # said once per process
    frame = pd.read_csv(table)
    assert frame["drive_speed_rad_s"].iloc[-1] == pytest.approx(rdm.rpm(5200.0))
    assert frame["midspan-y"].abs().max() > 0
    assert main(["simulate", model, "--duration", "0.1", "--free-spin"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "free spin" in err
    assert main(["simulate", model, "--duration", "0.1", "--modes-below", "-3"]) == 2
    assert "--modes-below" in capsys.readouterr().err


def test_the_documented_short_flexible_model_loads(tmp_path):
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "model-file.md").read_text(encoding="utf-8")
    block = re.search(r"## Flexible rotors\n.*?```toml\n(.*?)```", page, re.S).group(1)
    path = tmp_path / "short.toml"
    path.write_text(block, encoding="utf-8")
    model = rdm.load_model(path)
    shaft = model.rotors[0].flexible
    assert shaft.length == pytest.approx(0.4) and len(shaft.disks) == 1 and len(shaft.point_masses) == 1
    assert model.dofs.names[:4] == ("pump.n0.uy", "pump.n0.uz", "pump.n0.ry", "pump.n0.rz")


def test_check_prints_the_mesh_mass_and_bending_frequencies(tmp_path, capsys):
    import re

    import tomli_w

    length, diameter = 1.0, 0.05
    data = {"materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0], "shear": "none",
                        "shaft": [{"length": length, "outer_diameter": diameter, "material": "steel",
                                   "elements": 40}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e13} for n, z in
                         (("a", 0.0), ("b", length))]}
    path = tmp_path / "s.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "mesh 41 nodes, 40 elements" in out
    area, second, rho, young = np.pi / 4 * diameter ** 2, np.pi / 64 * diameter ** 4, STEEL["density"], \
        STEEL["young_modulus"]
    mass = float(re.search(r"mass ([0-9.e+]+) kg, centre", out).group(1))
    assert mass == pytest.approx(rho * area * length, rel=1e-5)
    free = float(re.search(r"free-free ([0-9.e+]+) Hz", out).group(1))
    bending = float(re.search(r"first mostly bending \(over 50 % in the shaft\) ([0-9.e+]+) Hz", out).group(1))
    # Euler-Bernoulli free-free (beta L = 4.7300407) and the simply supported Rayleigh beam
    beam = np.sqrt(young * second / (rho * area)) / (2 * np.pi)
    assert free == pytest.approx(4.7300407 ** 2 / length ** 2 * beam, rel=5e-3)   # rotary inertia: -0.2 %
    beta = np.pi / length
    assert bending == pytest.approx(beam * beta ** 2 / np.sqrt(1 + second / area * beta ** 2), rel=2e-5)


def test_mode_shape_at_a_station_of_a_flexible_rotor_is_its_node(examples_dir):
    model = rdm.load_model(examples_dir / "compressor_rotor.toml")     # grounded: absolute = relative
    modes = rdm.modal(model, 500.0)
    shaft = model.rotors[0].flexible
    names = list(model.dofs.names)
    for k in (0, 5, shaft.mesh.n_nodes - 1):
        point = shaft.point(shaft.mesh.z[k])
        found = modes.shape_at(point, direction=[0, 0, 1], body="compressor")
        expected = modes.shapes[:, names.index(f"compressor.n{k}.uz")]
        assert np.abs(found - expected).max() <= 1e-12 * np.abs(modes.shapes).max()
        relative = modes.shape_at(point, direction=[0, 0, 1], body="compressor", relative=True)
        assert np.abs(relative - found).max() <= 1e-12 * np.abs(modes.shapes).max()


def test_check_does_not_invent_a_frequency_on_journal_bearings(tmp_path, capsys):
    import tomli_w

    journal = {"type": "journal", "diameter": 0.05, "length": 0.02, "clearance": 1e-4, "viscosity": 0.02}
    data = {"gravity": [0.0, 0.0, -9.81], "materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0],
                        "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, **journal} for n, z in
                         (("a", 0.05), ("b", 0.95))]}
    path = tmp_path / "j.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "on its bearings: not computed (a journal bearing has no stiffness at rest)" in out
