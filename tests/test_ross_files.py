"""Rotors saved by ROSS read into model files (``rotordyn_modal.io.ross_file``, ``import-ross``).

The reference data in tests/data/ross/ were made by ROSS itself (benchmarks/ross_reference.py,
run in a separate venv; tests/data/ross/README.md): each rotor's ``Rotor.save`` file and, in
JSON, ROSS's totals, lateral modes at several speeds and an unbalance response. ROSS is not
needed here. The reader's output is checked against ROSS's own numbers: the shaft's mass,
centre of mass, polar and diametral inertia computed here by quadrature over the sections
(independent of the package) equal ROSS's; the node positions equal ROSS's; every bearing
coefficient equals ROSS's at every speed of its table. The full comparison (frequencies, log
decrements, unbalance response) needs flexible rotors in the model and is skipped, saying so,
while the model refuses them.
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError
from rotordyn_modal.io.ross_file import read_ross_rotor

DATA = Path(__file__).parent / "data" / "ross"
ROTORS = ["rotor_example", "compressor_example", "tapered_hollow", "speed_tables", "bearing_and_seal"]

# 5-point Gauss-Legendre on [0, 1]: exact for the polynomials (degree <= 9) of a frustum's slices
_X, _W = np.polynomial.legendre.leggauss(5)
_X, _W = (_X + 1) / 2, _W / 2


def reference(name: str) -> dict:
    return json.loads((DATA / f"{name}.json").read_text())


def ross_tables(name: str) -> dict:
    return tomllib.loads((DATA / f"{name}.toml").read_text())


def _pair(value):
    return (value, value) if not isinstance(value, list) else tuple(value)


def rigid_properties(description: dict) -> dict:
    """Mass, centre of mass, polar and diametral inertia (about the centre of mass) of the
    imported rotor, by quadrature of thin slices of every section and layer plus the disks."""
    density = {m["name"]: m["density"] for m in description["materials"]}
    rotor = description["rotors"][0]
    z0, slices = 0.0, []
    for section in rotor["shaft"]:
        length = section["length"]
        for tube in [section, *section.get("layers", [])]:
            (o0, o1), (i0, i1) = _pair(tube["outer_diameter"]), _pair(tube["inner_diameter"])
            ro, ri = (o0 + (o1 - o0) * _X) / 2, (i0 + (i1 - i0) * _X) / 2
            rho, w = density[tube["material"]], length * _W
            slices.append((z0 + length * _X, rho * np.pi * (ro**2 - ri**2) * w, rho * np.pi / 4 * (ro**4 - ri**4) * w))
        z0 += length
    disks = rotor.get("disks", [])
    m_shaft = sum(dm.sum() for _, dm, _ in slices)
    m_disks = sum(d["mass"] for d in disks)
    mass = m_shaft + m_disks
    cg = (sum((z * dm).sum() for z, dm, _ in slices) + sum(d["mass"] * d["axial_position"] for d in disks)) / mass
    ip = sum(2 * j.sum() for _, _, j in slices) + sum(d["polar_inertia"] for d in disks)
    it = (sum((j + dm * (z - cg) ** 2).sum() for z, dm, j in slices)
          + sum(d["diametral_inertia"] + d["mass"] * (d["axial_position"] - cg) ** 2 for d in disks))
    return {"m": mass, "m_shaft": m_shaft, "m_disks": m_disks, "CG": cg, "Ip": ip, "It": it}


# --------------------------------------------------------------------------- the reader


@pytest.mark.parametrize("name", ROTORS)
def test_shaft_disks_and_totals_equal_rosss(name):
    description = read_ross_rotor(DATA / f"{name}.toml")
    totals = reference(name)["totals"]
    rotor = description["rotors"][0]
    nodes = np.concatenate([[0.0], np.cumsum([s["length"] for s in rotor["shaft"]])])
    np.testing.assert_allclose(nodes, totals["nodes_pos"], rtol=0, atol=1e-12)
    assert sum(1 + len(s.get("layers", [])) for s in rotor["shaft"]) == totals["n_shaft_elements"]
    assert all(s["elements"] == 1 for s in rotor["shaft"])  # ROSS's mesh, node for node
    assert len(rotor.get("disks", [])) == totals["n_disks"]
    assert len(description["bearings"]) == totals["n_bearings"]
    found = rigid_properties(description)
    for key, value in found.items():
        assert value == pytest.approx(totals[key], rel=1e-12, abs=1e-14), key


@pytest.mark.parametrize("name", ROTORS)
def test_element_options_become_the_rotors_shear_option(name):
    options = reference(name)["element_options"]
    assert options["rotary_inertia"] == [True] and options["gyroscopic"] == [True]
    expected = "none" if options["shear_effects"] == [False] else options["shear_method_calc"][0]
    assert read_ross_rotor(DATA / f"{name}.toml")["rotors"][0]["shear"] == expected


def test_axes_spin_and_start():
    """ROSS's x, y, z are the model axes: spin about +z, so the transverse axes a, b are x, y."""
    from rotordyn_modal.model.geometry import transverse_axes

    description = read_ross_rotor(DATA / "rotor_example.toml")
    assert description["spin_axis"] == [0.0, 0.0, 1.0]
    assert description["rotors"][0]["start"] == [0.0, 0.0, 0.0]
    np.testing.assert_array_equal(transverse_axes(description["spin_axis"]), [[1, 0, 0], [0, 1, 0]])
    assert all("axes" not in b for b in description["bearings"])  # the default axes: x, y


def _matrices(value, count):
    """A bearing coefficient as ``count`` 2x2 matrices (number, 2-list, 2x2, or a list of them)."""
    array = np.asarray(value, dtype=float)
    if array.ndim in (0, 1) or (array.ndim == 2 and array.shape == (2, 2) and count == 1):
        array = array[None]
    out = []
    for item in array:
        item = np.asarray(item)
        out.append(np.diag(item) if item.ndim == 1 else item * np.eye(2) if item.ndim == 0 else item)
    assert len(out) == count
    return np.array(out)


@pytest.mark.parametrize("name", ROTORS)
def test_every_bearing_coefficient_equals_rosss_at_every_table_speed(name):
    """[[kxx, kxy], [kyx, kyy]] in this package's bearing axes (x, y), signs kept; ROSS's table
    speeds [rad/s] in rpm."""
    imported = {b["name"]: b for b in read_ross_rotor(DATA / f"{name}.toml")["bearings"]}
    nodes = reference(name)["totals"]["nodes_pos"]
    for key, table in ross_tables(name).items():
        if not key.startswith(("BearingElement_", "SealElement_")):
            continue
        bearing = imported[table["tag"]]
        assert bearing["axial_position"] == pytest.approx(nodes[table["n"]], abs=1e-12)
        speeds = np.asarray(table.get("speed", [0.0]), dtype=float)
        count = len(speeds)
        if "speeds_rpm" in bearing:
            np.testing.assert_allclose(bearing["speeds_rpm"], speeds * 30 / math.pi, rtol=1e-15)
            rows = count
        else:
            rows = 1
        for kind in "kc":
            ross = np.array([[table[f"{kind}xx"], table[f"{kind}xy"]], [table[f"{kind}yx"], table[f"{kind}yy"]]],
                            dtype=float).transpose(2, 0, 1)
            given = bearing.get("stiffness" if kind == "k" else "damping", 0.0)
            ours = np.broadcast_to(_matrices(given, rows), ross.shape)
            np.testing.assert_array_equal(ours, ross, err_msg=f"{name} {key} {kind}")


def test_cross_coupling_keeps_its_sign():
    """tapered_hollow's first bearing: kxy = +1.5e6, kyx = -2.5e6, cxy = 40, cyx = -60
    (benchmarks/ross_reference.py): the force in x per displacement in y stays in row x."""
    bearing = read_ross_rotor(DATA / "tapered_hollow.toml")["bearings"][0]
    assert bearing["stiffness"] == [[2.0e7, 1.5e6], [-2.5e6, 3.0e7]]
    assert bearing["damping"] == [[900.0, 40.0], [-60.0, 1100.0]]


def test_parallel_elements_become_layers_of_one_section():
    """compressor_example's impeller sleeves: a second element over the same nodes, its own
    material (E = 1 psi: mass only)."""
    rotor = read_ross_rotor(DATA / "compressor_example.toml")["rotors"][0]
    layered = [s for s in rotor["shaft"] if "layers" in s]
    assert len(layered) == 36
    assert {layer["material"] for s in layered for layer in s["layers"]} == {"shaft_mat_2"}


# --------------------------------------------------------------------------- refused by name


def _rotor_example() -> dict:
    return ross_tables("rotor_example")


def _edit(data, key, **changes):
    data[key].update(changes)
    return data


def _tabulated(data, count):
    """Bearing 0's coefficients as tables over ``count`` speeds, as ROSS saves them."""
    table = data["BearingElement_Bearing 0"]
    for key, value in list(table.items()):
        if isinstance(value, list):
            table[key] = value * count
    table["speed"] = [10.0 * i for i in range(count)]
    return data


MUTATIONS = {
    "proportional damping": (lambda d: _edit(d, "parameters", alpha=2.0), "[parameters] alpha"),
    "point mass": (lambda d: {**d, "PointMass_Pm 0": {"n": 7, "m": 1.0, "tag": "Pm 0"}}, "PointMass"),
    "magnetic bearing": (lambda d: {("MagneticBearingElement_Bearing 0" if k == "BearingElement_Bearing 0" else k): v
                                    for k, v in d.items()}, "MagneticBearingElement"),
    "unknown element": (lambda d: {**d, "CouplingElement_C 0": {"n": 1}}, "CouplingElement"),
    "bearing mass": (lambda d: _edit(d, "BearingElement_Bearing 1", mxx=[3.0]), "mxx"),
    "pedestal": (lambda d: _edit(d, "BearingElement_Bearing 1", n_link=7), "n_link"),
    "no rotary inertia": (lambda d: _edit(d, "ShaftElement_Shaft Element 2", rotary_inertia=False), "rotary_inertia"),
    "no gyroscopic": (lambda d: _edit(d, "ShaftElement_Shaft Element 2", gyroscopic=False), "gyroscopic"),
    "axial force": (lambda d: _edit(d, "ShaftElement_Shaft Element 2", axial_force=1e3), "axial_force"),
    "mixed shear": (lambda d: _edit(d, "ShaftElement_Shaft Element 4", shear_effects=False), "shear"),
    "ross's hutchinson": (lambda d: {k: ({**v, "shear_method_calc": "hutchinson"} if k.startswith("Shaft") else v)
                                     for k, v in d.items()}, "shear_method_calc = 'hutchinson': expected 'cowper'"),
    "unknown shear": (lambda d: _edit(d, "ShaftElement_Shaft Element 4", shear_method_calc="timoshenko"),
                      "shear_method_calc"),
    "missing span": (lambda d: {k: v for k, v in d.items() if k != "ShaftElement_Shaft Element 3"}, "ShaftElement n"),
    "bore not below outer": (lambda d: _edit(d, "ShaftElement_Shaft Element 1", idl=0.05), "idl, odl"),
    "length as text": (lambda d: _edit(d, "ShaftElement_Shaft Element 1", L="0.25"), "L"),
    "disk off the shaft": (lambda d: _edit(d, "DiskElement_Disk 0", n=9), "[DiskElement_Disk 0] n"),
    "table over speed and frequency": (lambda d: _edit(d, "BearingElement_Bearing 0", speed=[0.0, 1.0],
                                                       frequency=[0.0, 1.0]), "speed, frequency"),
    "table lengths differ": (lambda d: _edit(_tabulated(d, 3), "BearingElement_Bearing 0", kxx=[1e6, 2e6]), "kxx"),
    "speeds not increasing": (lambda d: _edit(d, "BearingElement_Bearing 0", speed=[10.0, 0.0],
                                              kxx=[1e6, 2e6], kyy=[1e6, 2e6]), "speed"),
    "not a rotor": (lambda d: {"ross_version": "3.1.0", "parameters": d["parameters"]}, "<file>"),
}


@pytest.mark.parametrize("case", sorted(MUTATIONS))
def test_what_is_not_modelled_is_refused_by_name(case, tmp_path):
    mutate, where = MUTATIONS[case]
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(mutate(_rotor_example())))
    with pytest.raises(ModelError) as error:
        read_ross_rotor(path)
    message = str(error.value)
    assert message.startswith(f"{path}: ") and where in message, message
    assert "\n" not in message


def test_rosss_damped_example_is_refused_for_its_proportional_damping():
    with pytest.raises(ModelError, match=r"\[parameters\] alpha = 8.0501: expected 0"):
        read_ross_rotor(DATA / "rotor_example_with_damping.toml")


def test_a_constant_table_is_a_constant_and_two_disks_on_one_node_add(tmp_path):
    data = _rotor_example()
    _tabulated(data, 2)  # the same coefficients at two speeds
    data["DiskElement_Disk 2"] = {"n": 2, "m": 1.5, "Id": 0.01, "Ip": 0.02, "tag": "Disk 2"}
    path = tmp_path / "r.toml"
    path.write_text(tomli_w.dumps(data))
    description = read_ross_rotor(path)
    bearing = description["bearings"][0]
    assert "speeds_rpm" not in bearing and bearing["stiffness"] == [1e6, 8e5]
    disk = description["rotors"][0]["disks"][0]
    base = data["DiskElement_Disk 0"]
    assert disk["name"] == "Disk 0 + Disk 2" and disk["mass"] == base["m"] + 1.5
    assert disk["polar_inertia"] == base["Ip"] + 0.02 and disk["diametral_inertia"] == base["Id"] + 0.01


# --------------------------------------------------------------------------- command line


def test_import_ross_writes_the_description(tmp_path, capsys):
    out = tmp_path / "model.toml"
    assert main(["import-ross", str(DATA / "tapered_hollow.toml"), "--out", str(out), "--name", "spindle"]) == 0
    assert "8 shaft sections, 2 disks, 2 bearings" in capsys.readouterr().err
    assert tomllib.loads(out.read_text()) == read_ross_rotor(DATA / "tapered_hollow.toml", name="spindle")


def test_import_ross_to_standard_output(capsys):
    assert main(["import-ross", str(DATA / "speed_tables.toml"), "--out", "-"]) == 0
    assert tomllib.loads(capsys.readouterr().out) == read_ross_rotor(DATA / "speed_tables.toml")


def test_import_ross_refuses_a_bad_file_with_one_line_and_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(tomli_w.dumps(MUTATIONS["point mass"][0](_rotor_example())))
    out = tmp_path / "model.toml"
    assert main(["import-ross", str(bad), "--out", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and str(bad) in lines[0] and "PointMass" in lines[0], lines
    assert not out.exists()
    assert main(["import-ross", str(DATA / "rotor_example.toml"), "--out", str(tmp_path / "m.csv")]) == 2
    assert "expected a file ending in .toml" in capsys.readouterr().err


# --------------------------------------------------------------------------- against ROSS's results


def _flexible_rotors_missing() -> str | None:
    """Why the model cannot take a flexible rotor (None when it can): a bare shaft on two
    bearings, as docs/model-file.md ("Flexible rotors") writes it."""
    from rotordyn_modal.model import Model

    minimal = {
        "name": "capability", "spin_axis": [0.0, 0.0, 1.0],
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "shear_modulus": 8e10}],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "shaft": [{"length": 0.5, "outer_diameter": 0.05,
                                                                       "material": "steel"}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z, "stiffness": 1e6}
                     for i, z in enumerate((0.0, 0.5))],
    }
    try:
        Model.from_dict(minimal)
    except (ModelError, TypeError, KeyError, ValueError) as problem:
        text = str(problem)
        return f"{type(problem).__name__}: {text if len(text) <= 160 else '...' + text[-157:]}"
    return None


def _model(name: str, with_outputs: bool = False):
    from rotordyn_modal.model import Model

    missing = _flexible_rotors_missing()
    if missing is not None:
        pytest.skip(f"rotordyn_modal.model has no flexible rotors yet (a bare shaft on two bearings is "
                    f"refused: {missing}); the comparison with ROSS waits for them")
    description = read_ross_rotor(DATA / f"{name}.toml")
    if with_outputs:
        ref = reference(name)["unbalance"]
        nodes = reference(name)["totals"]["nodes_pos"]
        description["unbalances"] = [{"rotor": name, "amount": ref["magnitude_kg_m"],
                                      "phase_deg": math.degrees(ref["phase_rad"]),
                                      "axial_position": nodes[ref["node"]]}]
        description["sensors"] = [{"name": f"n{i}{axis}", "rotor": name, "position": [0.0, 0.0, z],
                                   "direction": direction}
                                  for i, z in enumerate(nodes)
                                  for axis, direction in (("x", [1.0, 0.0, 0.0]), ("y", [0.0, 1.0, 0.0]))]
    return Model.from_dict(description, source=str(DATA / f"{name}.toml"))


@pytest.mark.parametrize("name", ROTORS)
def test_lateral_modes_equal_rosss(name):
    """Every lateral root ROSS found (the lowest 16 at each speed) is a root of the imported
    model to 1e-6 relative, one to one, and its log decrement agrees to 1e-6."""
    model = _model(name)
    for case in reference(name)["modal"]:
        assert_roots_as_ross(model, case, name)


def assert_roots_as_ross(model, case, name):
    """Every root ROSS found at ``case["speed"]`` is one of ``model``'s to 1e-6 relative, one to
    one, and its log decrement agrees to 1e-6."""
    import rotordyn_modal as rdm

    ross = np.array(case["eigenvalues_re"]) + 1j * np.array(case["eigenvalues_im"])
    ours = np.asarray(rdm.modal(model, case["speed"]).eigenvalues)
    nearest = [int(np.argmin(np.abs(ours - lam))) for lam in ross]
    assert len(set(nearest)) == len(nearest), (name, case["speed"])
    error = np.abs(ours[nearest] - ross) / np.abs(ross)
    assert error.max() <= 1e-6, (name, case["speed"], error.max())
    log_dec = -2 * np.pi * ours[nearest].real / np.abs(ours[nearest].imag)
    np.testing.assert_allclose(log_dec, case["log_dec"], rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("name", ROTORS)
def test_unbalance_response_equals_rosss(name):
    """x and y at every node, complex, to 1e-6 of the largest amplitude at that speed."""
    import rotordyn_modal as rdm

    model = _model(name, with_outputs=True)
    ref = reference(name)["unbalance"]
    result = rdm.unbalance_response(model, np.asarray(ref["speeds"]))
    response = np.asarray(result.response)[:, 0, :]  # (outputs, speeds)
    x = (np.array(ref["x_re"]) + 1j * np.array(ref["x_im"])).T  # (nodes, speeds)
    y = (np.array(ref["y_re"]) + 1j * np.array(ref["y_im"])).T
    ross = np.stack([x, y], axis=1).reshape(-1, len(ref["speeds"]))  # n0x, n0y, n1x, ...
    scale = np.abs(ross).max(axis=0)
    assert np.all(np.abs(response - ross) <= 1e-6 * scale), np.max(np.abs(response - ross) / scale)


def test_random_damage_is_refused_by_name_or_read(tmp_path):
    """A ROSS file damaged at random (a key removed, a value made text, a boolean, negative,
    NaN, a list or a table): the reader returns a description or raises ModelError naming the
    file, never another exception."""
    rng = np.random.default_rng(28)
    bad_values = ["x", True, -1.0, float("nan"), [1.0, "a"], {"a": 1}, [], 0, 1e308, [[1.0, 2.0]]]
    base = _rotor_example()
    tables = [k for k, v in base.items() if isinstance(v, dict)]
    refused = 0
    for case in range(60):
        data = json.loads(json.dumps(base))
        for _ in range(1 + case % 3):
            table = data[tables[rng.integers(len(tables))]]
            key = list(table)[rng.integers(len(table))]
            if rng.random() < 0.2:
                del table[key]
            else:
                table[key] = bad_values[rng.integers(len(bad_values))]
        path = tmp_path / f"damaged{case}.toml"
        path.write_text(tomli_w.dumps(data))
        try:
            read_ross_rotor(path)
        except ModelError as error:
            refused += 1
            assert str(error).startswith(f"{path}: ") and "\n" not in str(error)
    assert refused > 20
