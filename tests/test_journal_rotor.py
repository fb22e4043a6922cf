"""A rigid rotor in plain short journal bearings, through the whole model: its oil-whirl threshold
and whirl-frequency ratio equal Lund's stability analysis computed independently
(tests/journal_reference.py shares no code with the package), and bad journal input is refused."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from journal_reference import lund_threshold
from rotordyn_modal.cli import main

GEOMETRY = {"diameter": 0.05, "length": 0.025, "clearance": 5e-5, "viscosity": 0.02}
G = 9.81


def _rotor_in_journals(mass, spin_axis=(1.0, 0.0, 0.0), gravity=(0.0, 0.0, -G), half_span=0.3, **extra):
    e = np.asarray(spin_axis, dtype=float) / np.linalg.norm(spin_axis)
    return rdm.Model.from_dict({
        "spin_axis": list(spin_axis), "gravity": list(gravity),
        "rotors": [{"name": "r", "mass": mass, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.01 * mass,
                    "diametral_inertia": 0.04 * mass, "speed_ratio": 1.0}],
        "bearings": [{"name": n, "rotor": "r", "position": (s * e).tolist(), "type": "journal", **GEOMETRY, **extra}
                     for n, s in (("A", half_span), ("B", -half_span))],
    })


@pytest.mark.parametrize("mass, spin_axis", [(50.0, (1, 0, 0)), (8.0, (0, 1, 0)), (300.0, (0.6, 0.8, 0.0))])
def test_oil_whirl_threshold_and_whirl_ratio_equal_lunds_analysis(mass, spin_axis):
    """The cylindrical mode of a symmetric rotor carries half its mass on each bearing."""
    model = _rotor_in_journals(mass, spin_axis)
    expected, ratio = lund_threshold(mass / 2, **GEOMETRY, gravity=G)
    result = rdm.stability(model, np.linspace(0.3, 2.0, 35) * expected)
    assert result.threshold_speed == pytest.approx(expected, rel=1e-6)
    modes = rdm.modal(model, result.threshold_speed)
    critical = np.argmax(modes.eigenvalues.real)
    assert abs(modes.eigenvalues.real[critical]) < 1e-6 * abs(modes.eigenvalues[critical])
    assert modes.frequencies_hz[critical] * 2 * np.pi / result.threshold_speed == pytest.approx(ratio, rel=1e-6)
    assert modes.whirl[critical] == "forward"                       # oil whirl turns with the shaft


def test_an_explicit_load_equal_to_the_weight_share_gives_the_same_model():
    by_gravity = _rotor_in_journals(40.0)
    given = _rotor_in_journals(40.0, gravity=(0.0, 0.0, 0.0), load=20.0 * G, load_direction=[0.0, 0.0, -1.0])
    speeds = np.linspace(200.0, 3000.0, 8)
    np.testing.assert_allclose(rdm.campbell(given, speeds).eigenvalues, rdm.campbell(by_gravity, speeds).eigenvalues,
                               rtol=1e-12)


def test_journal_bearings_reach_the_film_and_cli_refuses_speed_zero(tmp_path, capsys):
    model = tmp_path / "journal.toml"
    lines = ['spin_axis = [1.0, 0.0, 0.0]', 'gravity = [0.0, 0.0, -9.81]', '[[rotors]]', 'name = "r"',
             'mass = 30.0', 'center_of_mass = [0.0, 0.0, 0.0]', 'polar_inertia = 0.3', 'diametral_inertia = 1.2',
             'speed_ratio = 1.0']
    for name, s in (("A", 0.25), ("B", -0.25)):
        lines += ["[[bearings]]", f'name = "{name}"', 'rotor = "r"', f"position = [{s}, 0.0, 0.0]",
                  'type = "journal"'] + [f"{k} = {v}" for k, v in GEOMETRY.items()]
    model.write_text("\n".join(lines) + "\n")
    assert main(["stability", str(model), "--speeds", "0:12000:13", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "[bearings.A]" in err and "0 rpm" in err and "eccentricity 1" in err and "Traceback" not in err
    assert main(["stability", str(model), "--speeds", "500:12000:24", "--quiet"]) == 0


@pytest.mark.parametrize("change, key, expected", [
    ({"clearance": 0.0}, "clearance", "> 0"),
    ({"clearance": 0.03}, "clearance", "smaller than the journal's radius"),
    ({"viscosity": -1.0}, "viscosity", "> 0"),
    ({"load_direction": [1.0, 0.0, 0.0]}, "load_direction", "normal to spin_axis"),
])
def test_bad_journal_data_is_refused(change, key, expected):
    with pytest.raises(rdm.ModelError, match=rf"\[bearings.A\] {key} = .*expected .*{expected}"):
        _rotor_in_journals(10.0, **change)


def test_without_gravity_a_journal_needs_a_load():
    with pytest.raises(rdm.ModelError, match=r"\[bearings.A\] load = '<missing>'.*weight share"):
        _rotor_in_journals(10.0, gravity=(0.0, 0.0, 0.0))
