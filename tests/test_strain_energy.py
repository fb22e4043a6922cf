"""Which modes are bending modes (issue 28): each mode's strain energy split between the shafts,
the bearings and the mounts (``ModalResult.energy_fractions``, ``modes``' columns). Truths from
outside the code: a rigid-body motion strains no shaft, a very stiff support stores no energy, the
parts add up to the assembled stiffness, and an undamped mode's strain energy equals its kinetic
energy (the bearings' share computed from the bearings' own deflections)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.modal import BENDING_FRACTION, strain_energy_fractions
from rotordyn_modal.assembly import matrices, stiffness_parts
from rotordyn_modal.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
LENGTH, DIAMETER = 1.0, 0.05                      # [m]
STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "shear_modulus": 8.12e10}
OLD_COLUMNS = ["mode", "frequency_hz", "damping_ratio", "log_decrement", "whirl", "whirl_ratio", "real_part"]


def _shaft_on_bearings(stiffness, elements=10):
    """A uniform steel shaft (1 m, 50 mm) on two isotropic bearings at its ends, to the ground."""
    return rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
        "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                    "shaft": [{"length": LENGTH, "outer_diameter": DIAMETER, "material": "steel",
                               "elements": elements}]}],
        "bearings": [{"name": "A", "rotor": "r", "axial_position": 0.0, "stiffness": stiffness},
                     {"name": "B", "rotor": "r", "axial_position": LENGTH, "stiffness": stiffness}],
    })


def _shaft_in_casing():
    """The shaft (6 elements, a disk) on bearings of 5e6 N/m in a 40 kg casing on four mounts."""
    data = _shaft_on_bearings(5e6, elements=6).to_dict()
    data["stator"] = {"mass": 40.0, "inertia": [1.0, 3.0, 3.0], "center_of_mass": [0.5, 0.0, -0.1]}
    data["rotors"][0]["disks"] = [{"name": "d", "axial_position": 0.5, "mass": 10.0, "polar_inertia": 0.05,
                                   "diametral_inertia": 0.03}]
    data["suspensions"] = [{"name": f"m{i}", "position": [x, y, -0.2], "stiffness": [2e5, 2e5, 4e5]}
                           for i, (x, y) in enumerate([(0, 0.2), (0, -0.2), (1, 0.2), (1, -0.2)])]
    return rdm.Model.from_dict(data)


def _fractions(result):
    """{part: fractions of the oscillating modes}."""
    keep = result.oscillatory
    return {p: result.energy_fractions[keep, i] for i, p in enumerate(result.energy_parts)}


def test_stiff_bearings_first_modes_are_all_bending():
    """On bearings 1e6 times stiffer than the shaft (48 EI / L^3 = 3.1e6 N/m) the bearings hardly
    deflect: the first modes (the pinned-pinned shaft's) store their strain energy in the shaft."""
    result = rdm.modal(_shaft_on_bearings(3e12), 0.0)
    shaft = _fractions(result)["shaft"][:4]
    assert np.all(shaft > 1 - 1e-5)
    assert list(result.kinds[result.oscillatory][:4]) == ["bending"] * 4


def test_soft_bearings_rigid_body_modes_strain_no_shaft():
    """On bearings 1e-6 of the shaft's stiffness the two lowest pairs are the rigid shaft's
    bounce and rock on its bearings (closed forms: sqrt(2 k / m) and sqrt(k L^2 / (2 J)) for a
    uniform shaft of mass m on two springs k at its ends, J = m (L^2 / 12 + d^2 / 16) its
    diametral inertia about the centre, the disks of its cross-sections included);
    a rigid motion strains no shaft, so their shaft fraction vanishes (as k / (48 EI / L^3))."""
    k = 3.0
    result = rdm.modal(_shaft_on_bearings(k), 0.0)
    mass = STEEL["density"] * np.pi / 4 * DIAMETER ** 2 * LENGTH
    frequencies = result.eigenvalues[result.oscillatory].imag[:4]
    inertia = mass * (LENGTH ** 2 / 12 + DIAMETER ** 2 / 16)
    closed = [np.sqrt(2 * k / mass), np.sqrt(k * LENGTH ** 2 / (2 * inertia))]
    assert np.allclose(frequencies, np.repeat(closed, 2), rtol=1e-5)
    fractions = _fractions(result)
    assert np.all(fractions["shaft"][:4] < 1e-5)
    assert np.allclose(fractions["bearings"][:4], 1.0, atol=1e-5)
    assert list(result.kinds[result.oscillatory][:4]) == ["rigid-body"] * 4
    assert np.all(fractions["shaft"][4:6] > BENDING_FRACTION)        # the first bending pair


def test_bearing_share_from_the_bearings_own_deflection():
    """An undamped mode at rest stores as much strain energy as kinetic energy at its peak
    (omega^2 phi^H M phi / 2 with the mass-normalised shape: omega^2 / 2); the bearings' part is
    k |u_b|^2 / 2 from each bearing's deflection read off the shape at its station."""
    k = 2e6
    model = _shaft_on_bearings(k, elements=8)
    result = rdm.modal(model, 0.0)
    keep = np.flatnonzero(result.oscillatory)[:8]
    omega = result.eigenvalues[keep].imag
    strain = 0.0
    for z in (0.0, LENGTH):
        u = result.shape_at([z, 0.0, 0.0], body="r", relative=True)[keep]      # (modes, 3)
        strain = strain + 0.5 * k * np.sum(np.abs(u[:, 1:]) ** 2, axis=1)
    bearings = result.energy_fractions[keep, list(result.energy_parts).index("bearings")]
    assert np.allclose(bearings, strain / (0.5 * omega ** 2), rtol=1e-8)


@pytest.mark.parametrize("name", sorted(p.name for p in (ROOT / "examples").glob("*.toml")
                                        if not p.name.endswith(".study.toml")))
def test_parts_add_up_to_the_stiffness(name):
    """On every example: the parts are the whole assembled stiffness (none left out or counted
    twice), so that the fractions are of the whole strain energy."""
    model = rdm.load_model(ROOT / "examples" / name)
    speed = 150.0
    parts = stiffness_parts(model, speed)
    total = matrices(model, speed).K
    assert np.allclose(sum(parts.values()), total, rtol=0, atol=1e-12 * np.abs(total).max())


def test_fractions_sum_to_one_in_a_casing():
    """A shaft on bearings in a casing on mounts: every mode's three fractions sum to 1, each
    within [0, 1] (every part's stiffness here is positive semidefinite); the casing's modes on
    its mounts are 'suspension' modes."""
    result = rdm.modal(_shaft_in_casing(), 100.0)
    assert result.energy_parts == ("shaft", "bearings", "mounts")
    rows = result.energy_fractions[result.oscillatory]
    assert np.allclose(rows.sum(axis=1), 1.0, atol=1e-12)
    assert np.all((rows > -1e-12) & (rows < 1 + 1e-12))
    kinds = result.kinds[result.oscillatory]
    assert list(kinds[:6]) == ["suspension"] * 6 and "bending" in kinds


def test_maxwell_branches_count_in_the_mounts():
    """A rubber mount's Maxwell branch is a spring in series with a dashpot; the spring's energy
    counts with the mounts (here in a machine without a flexible rotor, where ``modal`` leaves the
    split out and ``strain_energy_fractions`` gives it). Independent route: the full state eigenvector holds each branch's
    junction z_b (the branch's states), so the spring's energy is
    (B^T q - z_b)^H K_b (B^T q - z_b) / 2 straight from it."""
    import tomllib

    from rotordyn_modal.linear_system import speed_linear_form
    from rotordyn_modal.model.geometry import shift_matrix

    data = tomllib.loads((ROOT / "examples" / "rubber_mounts.toml").read_text())
    data["bearings"] = [{"name": n, "rotor": "motor", "position": [x, 0.0, 0.15], "stiffness": 4e5}
                        for n, x in (("DE", 0.1), ("NDE", 0.3))]
    model = rdm.Model.from_dict(data)
    result = rdm.modal(model, 0.0)
    assert result.energy_fractions is None                  # no flexible rotor: not computed by modal
    parts, fractions = strain_energy_fractions(model, 0.0, result.shapes, result.eigenvalues)
    assert parts == ("bearings", "mounts")
    values, vectors = np.linalg.eig(speed_linear_form(model).at(0.0))
    n, frame = model.dofs.n, model.dofs.frame_motion()
    static = stiffness_parts(model, 0.0)
    checked = 0
    for m in np.flatnonzero(result.oscillatory):
        v = vectors[:, np.argmin(np.abs(values - result.eigenvalues[m]))]
        q, branch = v[:n], 0.0
        z = v[2 * n:].reshape(-1, 6)
        index = 0
        for s in model.suspensions:
            point = shift_matrix(model.reference_point, s.position).T @ frame
            for k_b in s.maxwell_stiffness_matrix:
                stretch = point @ q - z[index]
                branch += 0.5 * (stretch.conj() @ k_b @ stretch).real
                index += 1
        plain = {p: 0.5 * (q.conj() @ K @ q).real for p, K in static.items()}
        mounts = (plain["mounts"] + branch) / (sum(plain.values()) + branch)
        assert fractions[m, parts.index("mounts")] == pytest.approx(mounts, rel=1e-8)
        checked += branch > 1e-3 * plain["mounts"]
    assert checked >= 3                       # the branches hold a share worth checking in several modes


def test_rigid_rotor_model_table_unchanged(tmp_path, capsys):
    """Without a flexible rotor, the table and the CSV keep exactly their columns."""
    result = rdm.modal(rdm.load_model(ROOT / "examples" / "gear_machine.toml"), 300.0)
    assert list(result.to_dataframe().columns) == OLD_COLUMNS
    out = tmp_path / "modes.csv"
    assert main(["modes", str(ROOT / "examples" / "gear_machine.toml"), "--speed", "3000", "--out", str(out),
                 "--quiet"]) == 0
    assert out.read_text().splitlines()[0] == ",".join(OLD_COLUMNS)


def test_flexible_rotor_table_appends_the_split(tmp_path):
    """With a flexible rotor the CSV keeps the old columns first and appends the fractions of
    the parts the model has and the kind; the terminal shows the same columns."""
    model_file = tmp_path / "casing.toml"
    rdm.save_model(_shaft_in_casing(), model_file)
    out = tmp_path / "modes.csv"
    assert main(["modes", str(model_file), "--speed", "1000", "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    table = pd.read_csv(out)
    assert list(table.columns) == OLD_COLUMNS + ["shaft_energy", "bearing_energy", "mount_energy", "kind"]
    parts = table[["shaft_energy", "bearing_energy", "mount_energy"]]
    assert np.allclose(parts.sum(axis=1), 1.0, atol=1e-8)
    bending = table["shaft_energy"] > 0.5          # the threshold docs/model-file.md gives
    assert bending.any() and list(table["kind"][bending].unique()) == ["bending"]
    assert set(table["kind"][~bending]) <= {"rigid-body", "suspension"}
