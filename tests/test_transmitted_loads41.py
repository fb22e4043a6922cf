"""Journal loads of rotors in a transmission (issue 27 section 1.6, docs/static.md "Journal-bearing
loads of the model"): without ``load`` a journal's load is its share of the weight, while the
tooth force (gear) or belt pull (belt) at the operating point also loads it. Every command says
so in one line per rotor, naming the journals and the load taken; a journal with its ``load``
given, and a rotor outside any transmission, draw no such line.

The weight shares are the lever rule: a rotor of mass m with its centre of mass midway between
two journals puts m g / 2 on each.
"""

import warnings

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.errors import ModelWarning

G = 9.81
PINION, WHEEL = 50.0, 120.0   # kg


def _journal(name, rotor, x, z, **extra):
    return {"name": name, "rotor": rotor, "position": [x, 0.0, z], "type": "journal", "diameter": 0.05,
            "length": 0.025, "clearance": 5e-5, "viscosity": 0.02, **extra}


def _model(kind="gear", given=(), linked=True):
    """A pinion (50 kg, at the origin) and a wheel (120 kg, 0.4 m above), each midway between two
    journals 0.6 m apart, joined by a gear or belt (``linked``); ``given`` journals have a load."""
    bearings = [_journal(n, r, x, z, **({"load": 300.0} if n in given else {}))
                for n, r, x, z in (("P1", "pinion", 0.3, 0.0), ("P2", "pinion", -0.3, 0.0),
                                   ("W1", "wheel", 0.3, 0.4), ("W2", "wheel", -0.3, 0.4))]
    data = {"gravity": [0.0, 0.0, -G], "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "pinion",
            "rotors": [{"name": "pinion", "mass": PINION, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.5,
                        "diametral_inertia": 2.0, "speed_ratio": 1.0},
                       {"name": "wheel", "mass": WHEEL, "center_of_mass": [0.0, 0.0, 0.4], "polar_inertia": 3.0,
                        "diametral_inertia": 5.0, **({} if linked else {"speed_ratio": 0.5})}],
            "bearings": bearings}
    if linked:
        data["transmissions"] = [{"type": kind, "driver": "pinion", "driven": "wheel", "ratio": 3.0,
                                  **({"driver_teeth": 20} if kind == "gear" else {})}]
    return data


def _transmission_lines(data) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rdm.Model.from_dict(data)
    return [str(w.message) for w in caught
            if issubclass(w.category, ModelWarning) and "in a transmission" in str(w.message)]


def test_each_geared_rotor_names_its_weighed_journals_and_their_weight_shares():
    lines = _transmission_lines(_model("gear"))
    assert len(lines) == 2
    pinion, wheel = sorted(lines, key=lambda line: "'wheel'" in line)
    assert "rotor 'pinion'" in pinion and "gear pinion -> wheel" in pinion and "tooth force" in pinion
    for journal in ("P1", "P2"):
        assert f"[bearings.{journal}] {PINION * G / 2:.4g} N" in pinion
    for journal in ("W1", "W2"):
        assert f"[bearings.{journal}] {WHEEL * G / 2:.4g} N" in wheel
    assert "static --transmitted-power" in pinion


def test_a_belt_names_the_belt_pull():
    lines = _transmission_lines(_model("belt"))
    assert len(lines) == 2 and all("belt pull" in line and "tooth" not in line for line in lines)


def test_journals_with_their_load_given_are_not_named():
    lines = _transmission_lines(_model("gear", given=("P1", "W1", "W2")))
    assert len(lines) == 1
    assert "[bearings.P2]" in lines[0] and "[bearings.P1]" not in lines[0]


def test_rotors_outside_a_transmission_draw_no_line():
    assert _transmission_lines(_model(linked=False)) == []


def test_the_load_taken_is_the_one_the_line_names():
    """The journal data the films are computed from carry the weight share the line names."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        model = rdm.Model.from_dict(_model("gear"))
    loads = {b.name: b.coefficients.journal.load for b in model.bearings}
    np.testing.assert_allclose([loads["P1"], loads["W2"]], [PINION * G / 2, WHEEL * G / 2], rtol=1e-12)


def test_the_command_line_prints_the_line_once_per_rotor(tmp_path, capsys):
    import tomli_w
    path = tmp_path / "geared.toml"
    path.write_bytes(tomli_w.dumps(_model("gear")).encode())
    from rotordyn_modal.cli.main import main
    assert main(["check", str(path)]) == 0
    err = capsys.readouterr().err
    assert err.count("in a transmission") == 2
