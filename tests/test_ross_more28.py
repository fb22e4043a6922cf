"""Four more ROSS rotors through ``import-ross``, against ROSS's own results over a speed range
(issue 28: "the same rotors with the same element options give the same lateral frequencies and
log decrements to 1e-6 relative over a speed range, and the same unbalance response"), and the
warning where ROSS's PCHIP tables make the two codes differ between table speeds.

The data (tests/data/ross/NAME.toml and NAME.json) were written by ROSS 3.1 itself
(``benchmarks/ross_reference.py --only NAME``, in ROSS's venv; tests/data/ross/README.md):

* ``friswell_5_9_4``: Friswell et al. Example 5.9.4 as ROSS's tests build it (disks from
  geometry, a cross-coupled kxy = 0.5 MN/m alone);
* ``ball_roller_mixed``: ROSS's ball and roller bearing elements (coefficients ROSS computed), an
  aluminium hollow span whose material ROSS got by Poisson's ratio, two disks on one node;
* ``damping_geometry``: ``rotor_example_with_damping``'s 33 unequal elements and inboard,
  strongly anisotropic damped bearings, without its proportional damping (which is refused);
* ``tables_linear_tapered``: Euler-Bernoulli tapered hollow elements, a bearing (with kzz) and a
  seal (over ``frequency``) whose tables are not linear in speed, saved with
  ``interpolation="linear"``: ROSS's results between the table speeds are compared too.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import ModelError, ModelWarning

from test_ross_files import assert_roots_as_ross

DATA = Path(__file__).parent / "data" / "ross"
ROTORS = ["friswell_5_9_4", "ball_roller_mixed", "damping_geometry", "tables_linear_tapered"]


def _imported(name: str, tmp_path) -> Path:
    """The model file ``import-ross`` writes for the ROSS file (the command line, as a user)."""
    out = tmp_path / f"{name}_model.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)   # these rotors import without a warning
        assert main(["import-ross", str(DATA / f"{name}.toml"), "--out", str(out), "--quiet"]) == 0
    return out


def _reference(name: str) -> dict:
    return json.loads((DATA / f"{name}.json").read_text())


def _defective_at_rest(name: str, speed: float) -> bool:
    """Friswell 5.9.4 at rest: kxy alone makes K block-triangular, so every root is a defective
    double root (a Jordan block); both codes' roots there carry round-off of about sqrt(eps)."""
    return name == "friswell_5_9_4" and speed == 0.0


@pytest.mark.parametrize("name", ROTORS)
def test_lateral_roots_and_log_decrements_equal_rosss_over_speed(name, tmp_path):
    """Every lateral root ROSS found (the lowest 16 at each of 4-11 speeds) is one root of the
    imported model to 1e-6 relative, one to one, with its log decrement to 1e-6."""
    import rotordyn_modal as rdm

    model = rdm.load_model(_imported(name, tmp_path))
    for case in _reference(name)["modal"]:
        if _defective_at_rest(name, case["speed"]):
            continue   # test_defective_roots_at_rest_are_the_uncoupled_rotors
        assert_roots_as_ross(model, case, name)


def test_defective_roots_at_rest_are_the_uncoupled_rotors(tmp_path):
    """At rest Friswell 5.9.4's roots are exactly those of the same rotor with kxy = 0 (a
    block-triangular K): ours and ROSS's frequencies both within 1e-6 of them."""
    import rotordyn_modal as rdm

    model = rdm.load_model(_imported("friswell_5_9_4", tmp_path))
    uncoupled = model.with_values({f"bearings.{b.name}.stiffness": [1.0e6, 1.0e6] for b in model.bearings})
    truth = np.asarray(rdm.modal(uncoupled, 0.0).eigenvalues)
    ours = np.asarray(rdm.modal(model, 0.0).eigenvalues)
    case = _reference("friswell_5_9_4")["modal"][0]
    assert case["speed"] == 0.0
    ross = np.array(case["eigenvalues_re"]) + 1j * np.array(case["eigenvalues_im"])
    for roots in (ross, ours[[int(np.argmin(np.abs(ours - lam))) for lam in ross]]):
        nearest = truth[[int(np.argmin(np.abs(truth - lam))) for lam in roots]]
        assert np.max(np.abs(roots - nearest) / np.abs(nearest)) <= 1e-6


@pytest.mark.parametrize("name", ROTORS)
def test_unbalance_response_equals_rosss(name, tmp_path):
    """ROSS's ``run_unbalance_response`` (1e-4 kg m at 0.3 rad at one node): x and y at every
    node, complex, to 1e-6 of the largest amplitude at that speed."""
    import rotordyn_modal as rdm
    from rotordyn_modal.io.model_file import read_toml
    from rotordyn_modal.model import Model

    out = _imported(name, tmp_path)
    description = read_toml(out, "model")
    ref = _reference(name)["unbalance"]
    nodes = _reference(name)["totals"]["nodes_pos"]
    rotor = description["rotors"][0]["name"]
    description["unbalances"] = [{"rotor": rotor, "amount": ref["magnitude_kg_m"],
                                  "phase_deg": math.degrees(ref["phase_rad"]), "axial_position": nodes[ref["node"]]}]
    description["sensors"] = [{"name": f"n{i}{axis}", "rotor": rotor, "position": [0.0, 0.0, z], "direction": d}
                              for i, z in enumerate(nodes)
                              for axis, d in (("x", [1.0, 0.0, 0.0]), ("y", [0.0, 1.0, 0.0]))]
    result = rdm.unbalance_response(Model.from_dict(description, source=str(out)), np.asarray(ref["speeds"]))
    response = np.asarray(result.response)[:, 0, :]
    x = (np.array(ref["x_re"]) + 1j * np.array(ref["x_im"])).T
    y = (np.array(ref["y_re"]) + 1j * np.array(ref["y_im"])).T
    ross = np.stack([x, y], axis=1).reshape(-1, len(ref["speeds"]))
    scale = np.abs(ross).max(axis=0)
    assert np.all(np.abs(response - ross) <= 1e-6 * scale), np.max(np.abs(response - ross) / scale)


def test_between_table_speeds_too():
    """tables_linear_tapered's ROSS results include speeds between its table's (150, 950, 1700
    rad/s among others): the comparison above covers interpolated coefficients."""
    table = [0.0, 300.0, 700.0, 1200.0, 2000.0]
    speeds = [case["speed"] for case in _reference("tables_linear_tapered")["modal"]]
    assert sum(s not in table for s in speeds) >= 5


def _pchip_file(tmp_path, interpolation: str | None) -> Path:
    """tables_linear_tapered's file with its tables' interpolation changed (None: the key
    removed, as in files of ROSS before 3.1, where PCHIP was the only method)."""
    text = (DATA / "tables_linear_tapered.toml").read_text()
    line = 'interpolation = "linear"\n'
    assert text.count(line) == 2
    path = tmp_path / "tables.toml"
    path.write_text(text.replace(line, "" if interpolation is None else f'interpolation = "{interpolation}"\n'))
    return path


@pytest.mark.parametrize("interpolation", ["pchip", None])
def test_pchip_tables_are_warned_with_the_largest_difference(interpolation, tmp_path, capsys):
    """ROSS's default PCHIP interpolation of a table that is not linear in speed differs from this
    package's linear one between the table's speeds (ROSS's roots of this very file with PCHIP
    differ by 3e-3 at 150 rad/s): main imported it silently. Now one warning names the tables,
    the largest difference (the bearing's kyx: PCHIP against linear at the 150 rad/s midpoint,
    computed here by hand) and what to do; the file is still written."""
    from scipy.interpolate import PchipInterpolator

    out = tmp_path / "model.toml"
    assert main(["import-ross", str(_pchip_file(tmp_path, interpolation)), "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert out.exists()
    lines = [line for line in err.splitlines() if "PCHIP" in line]
    assert len(lines) == 1, err
    speed = np.array([0.0, 300.0, 700.0, 1200.0, 2000.0])
    kyx = -0.12 * 2e7 * (1 + 0.5 * np.sqrt(speed / 2000.0))
    difference = abs(PchipInterpolator(speed, kyx)(150.0) - (kyx[0] + kyx[1]) / 2) / np.abs(kyx).max()
    assert "1 table " in lines[0] and "[BearingElement_tab] kyx" in lines[0], lines[0]
    assert f"by {difference:.2g} of its largest value at 150 rad/s" in lines[0], lines[0]
    assert "interpolation='linear'" in lines[0]


def test_linear_tables_and_tables_linear_in_speed_are_not_warned(tmp_path):
    """``interpolation = "linear"`` (what this package does) and a PCHIP table whose coefficients
    are linear in speed (ROSS's PCHIP then is that line: speed_tables) import without it."""
    from rotordyn_modal.io.ross_file import read_ross_rotor

    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        read_ross_rotor(DATA / "tables_linear_tapered.toml")
        read_ross_rotor(DATA / "speed_tables.toml")


def test_an_unknown_interpolation_is_refused_by_name(tmp_path, capsys):
    path = _pchip_file(tmp_path, "cubic")
    with pytest.raises(ModelError, match=r"\[BearingElement_tab\] interpolation.*'pchip' or 'linear'"):
        from rotordyn_modal.io.ross_file import read_ross_rotor

        read_ross_rotor(path)
    out = tmp_path / "model.toml"
    assert main(["import-ross", str(path), "--out", str(out)]) == 2
    assert not out.exists()
    assert "interpolation" in capsys.readouterr().err
