"""The plausibility checks in a module of their own, and journal bearings in the rigid-body check
(issue 27 §1 and §6).

* ``rotordyn_modal.plausibility`` holds :func:`implausible`; ``linear_system`` keeps the state
  space only.
* A rotor's rigid-body mode in its bearings below 0.5 Hz is named on journal bearings too, their
  films taken at light load (the symmetric part of the short bearing's stiffness as the
  eccentricity goes to zero). Before, one journal bearing anywhere in the machine left every rotor
  out of the check. Expected frequencies come from scipy's ``eigh`` of hand-written 4 x 4
  matrices whose film stiffness is :func:`short_journal_bearing` at a speed where its
  eccentricity is 1e-7 (the limit approached, not the limit's formula); the examples on plain
  journal bearings stay quiet.
"""

from __future__ import annotations

import math
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import tomli_w

import rotordyn_modal as rdm
from rotordyn_modal import linear_system
from rotordyn_modal.elements.journal_bearing import short_journal_bearing
from rotordyn_modal.errors import ModelWarning

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
JOURNAL_ROTOR = EXAMPLES / "journal_rotor.toml"

def _aux(x: float, a: float, b: float) -> str:
    """A rigid rotor 'aux' of 10 kg on two linear bearings of 2 N/m at ``a`` and ``b`` along x (a
    stiffness in N/mm typed for N/m, as 2000 N/m read as 2), its centre at ``x``, 1 m off the
    other rotor's axis: TOML to append to a model file."""
    rotor = {"name": "aux", "mass": 10.0, "center_of_mass": [x, 1.0, 0.0], "polar_inertia": 0.05,
             "diametral_inertia": 0.1, "speed_ratio": 1.0}
    bearings = [{"name": f"aux-{end}", "rotor": "aux", "position": [at, 1.0, 0.0], "stiffness": 2.0}
                for end, at in (("a", a), ("b", b))]
    return "\n" + tomli_w.dumps({"rotors": [rotor], "bearings": bearings})


def _model_warnings(path) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rdm.load_model(path)
    return [str(w.message) for w in caught if issubclass(w.category, ModelWarning)]


def _rotor_lines(path) -> list[str]:
    return [line for line in _model_warnings(path) if "rigid-body mode" in line]


def _frequency(line: str) -> str:
    return re.search(r"rigid-body mode at ([0-9.e+-]+) Hz", line).group(1)


def _light_film(journal_table: dict, load: float) -> np.ndarray:
    """The symmetric part of the short bearing's film stiffness (2, 2) [N/m], rows along and across
    the load, at a speed where the eccentricity is about 1e-7."""
    film = short_journal_bearing([1e9], diameter=journal_table["diameter"], length=journal_table["length"],
                                 clearance=journal_table["clearance"], viscosity=journal_table["viscosity"],
                                 load=load)
    assert film.eccentricity[0] < 1e-6
    k = film.stiffness[0]
    return 0.5 * (k + k.T)


# --------------------------------------------------------------------------- the module
def test_the_checks_live_in_plausibility_and_not_in_linear_system():
    from rotordyn_modal import plausibility, stiffness_spread

    assert callable(plausibility.implausible) and callable(stiffness_spread.refuse_lost_digits)
    for name in ("implausible", "SAG_LIMIT", "LOWEST_MOUNT_FREQUENCY", "stiffness_spread_lines", "support_spreads",
                 "_low_rotor_line", "_rigid_rotor_bound_lines", "_far_point_lines"):
        assert not hasattr(linear_system, name), name


def test_the_layout_table_names_the_new_modules():
    text = (ROOT / "docs" / "DEVELOPING.md").read_text(encoding="utf-8")
    assert "`rotordyn_modal/plausibility.py`" in text and "`rotordyn_modal/stiffness_spread.py`" in text


# ----------------------------------------------------------------- the film at light load
def test_light_load_stiffness_is_the_short_bearings_limit():
    """The film's 6 x 6 at light load equals short-bearing theory at eccentricity 1e-7 (symmetric
    part), placed along the journal's load axes, to the limit's distance (1e-6)."""
    from rotordyn_modal.elements.bearings import light_load_stiffness

    model = rdm.load_model(JOURNAL_ROTOR)
    table = tomllib.loads(JOURNAL_ROTOR.read_text())["bearings"][0]
    bearing = model.bearings[0]
    journal = bearing.coefficients.journal
    assert journal.load == pytest.approx(50.0 * 9.81 / 2, rel=1e-12)           # lever rule, half each
    film = _light_film(table, journal.load)
    expected = journal.axes[:2].T @ film @ journal.axes[:2]
    got = light_load_stiffness(bearing.coefficients)
    np.testing.assert_allclose(got[:3, :3], expected, rtol=0, atol=1e-6 * np.abs(expected).max())
    assert not np.any(got[3:]) and not np.any(got[:, 3:])
    # 4/pi and 8/pi of load / clearance along and across the load
    scale = journal.load / table["clearance"]
    np.testing.assert_allclose(np.linalg.eigvalsh(got[:3, :3])[1:] / scale, [4 / math.pi, 8 / math.pi], rtol=1e-12)


# --------------------------------------------------------------- a rotor on journal bearings
def test_a_journal_rotor_with_an_inertia_in_kg_mm2_is_named(tmp_path):
    """journal_rotor.toml with diametral_inertia = 2.0e6 (kg mm^2 given as kg m^2): its tilting
    mode in the films is at 0.119 Hz. Before, a model with journal bearings was not looked at."""
    text = JOURNAL_ROTOR.read_text()
    assert "diametral_inertia = 2.0\n" in text
    path = tmp_path / "inertia.toml"
    path.write_text(text.replace("diametral_inertia = 2.0\n", "diametral_inertia = 2.0e6\n"))
    data = tomllib.loads(path.read_text())
    rotor, tables = data["rotors"][0], data["bearings"]
    load = rotor["mass"] * 9.81 / 2                          # gravity normal to the axis, half each
    film = _light_film(tables[0], load)                       # rows: along the load (-z), across (y)
    k_z, k_y = film[0, 0], film[1, 1]
    stations = [t["position"][0] for t in tables]             # along the spin axis x
    # coordinates (u_y, u_z, theta_y, theta_z): u_z = ... - x theta_y, u_y = ... + x theta_z
    K = np.zeros((4, 4))
    for x in stations:
        for k, rows in ((k_y, np.array([1.0, 0.0, 0.0, x])), (k_z, np.array([0.0, 1.0, -x, 0.0]))):
            K += k * np.outer(rows, rows)
    M = np.diag([rotor["mass"], rotor["mass"], rotor["diametral_inertia"], rotor["diametral_inertia"]])
    lowest = math.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[0]) / (2 * math.pi)
    assert lowest < 0.5
    (line,) = _rotor_lines(path)
    assert _frequency(line) == f"{lowest:.3g}" == "0.119"
    assert "rotor 'rotor'" in line and "[bearings.DE], [bearings.NDE]" in line
    assert "journal films at light load" in line and "load over its clearance" in line


def test_another_rotor_beside_journal_bearings_is_named(tmp_path):
    """A rotor on 2 N/m bearings beside one on journals: before, the journals left the whole
    machine out of the check; its translation mode is sqrt(2 k / m) / (2 pi) = 0.101 Hz."""
    text = JOURNAL_ROTOR.read_text().replace('spin_axis = [1.0, 0.0, 0.0]\n',
                                             'spin_axis = [1.0, 0.0, 0.0]\nreference_rotor = "rotor"\n')
    path = tmp_path / "mixed.toml"
    path.write_text(text + _aux(0.0, 0.2, -0.2))
    aux = [r for r in tomllib.loads(path.read_text())["rotors"] if r["name"] == "aux"][0]
    K = np.zeros((4, 4))
    for x in (0.2, -0.2):
        for rows in (np.array([1.0, 0.0, 0.0, x]), np.array([0.0, 1.0, -x, 0.0])):
            K += 2.0 * np.outer(rows, rows)
    M = np.diag([aux["mass"], aux["mass"], aux["diametral_inertia"], aux["diametral_inertia"]])
    lowest = math.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[0]) / (2 * math.pi)
    assert f"{lowest:.3g}" == f"{math.sqrt(4.0 / 10.0) / (2 * math.pi):.3g}"
    # under gravity (sag38) its sag in its bearings is the one line: 10 kg x 9.81 / (2 x 2 N/m)
    (line,) = _model_warnings(path)
    assert "rotor 'aux' would sag" in line and f"{10.0 * 9.81 / 4.0:.3g} m" in line
    # without gravity (the journals' loads given) the rigid-body mode is
    path.write_text(re.sub(r"gravity = \[[^]]*\][^\n]*\n", "", text).replace(
        'type = "journal"\n', 'type = "journal"\nload = 245.25\nload_direction = [0.0, 0.0, -1.0]\n') + _aux(0.0, 0.2, -0.2))
    (line,) = _rotor_lines(path)
    assert "rotor 'aux'" in line and _frequency(line) == f"{lowest:.3g}"
    assert "; at rest," in line and "a stiffness in N/mm given as N/m" in line      # the other rotor's words


def test_another_rotor_beside_journals_over_200_coordinates_is_named(tmp_path):
    """The same beside compressor_on_journals meshed at 2 cm (over 200 coordinates): under gravity
    its sag in its bearings is the one line, as at any size since the static solution is an LU
    (session 39: over 200 coordinates the sag was not looked at); without gravity (the journals'
    loads given) the rigid-body bound, exact for a rigid rotor, said "or below"."""
    text = (EXAMPLES / "compressor_on_journals.toml").read_text()
    assert "element_length = 0.2 " in text
    text = text.replace("element_length = 0.2 ", "element_length = 0.02 ").replace(
        'spin_axis = [1.0, 0.0, 0.0]\n', 'spin_axis = [1.0, 0.0, 0.0]\nreference_rotor = "compressor"\n')
    path = tmp_path / "fine_mixed.toml"
    path.write_text(text + _aux(0.85, 1.05, 0.65))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert rdm.load_model(path).dofs.n > 200
    (line,) = _model_warnings(path)
    assert "rotor 'aux' would sag" in line and f"{10.0 * 9.81 / 4.0:.3g} m" in line
    path.write_text(re.sub(r"gravity = \[[^]]*\][^\n]*\n", "", text).replace(
        'type = "journal"\n', 'type = "journal"\nload = 1339.0\nload_direction = [0.0, 0.0, -1.0]\n')
        + _aux(0.85, 1.05, 0.65))
    (line,) = _rotor_lines(path)
    expected = math.sqrt(2 * 2.0 / 10.0) / (2 * math.pi)
    assert "rotor 'aux'" in line and f"at {expected:.3g} Hz or below" in line


@pytest.mark.parametrize("name", ["journal_rotor.toml", "compressor_on_journals.toml"])
def test_plausible_journal_models_stay_quiet(name):
    assert _model_warnings(EXAMPLES / name) == []


def test_a_plausible_journal_model_over_200_coordinates_stays_quiet(tmp_path):
    text = (EXAMPLES / "compressor_on_journals.toml").read_text().replace("element_length = 0.2 ",
                                                                           "element_length = 0.02 ")
    path = tmp_path / "fine.toml"
    path.write_text(text)
    assert rdm.load_model(path).dofs.n > 200
    assert _model_warnings(path) == []


# --------------------------------------------------------- review: a study's keys parsed once
def test_a_studys_key_checks_parse_each_key_once(monkeypatch):
    """``_one_parameter_per_value`` parsed every key again after ``_check_keys`` (and a 'value'
    parameter's key was parsed twice there): now the places ``_check_keys`` found are used."""
    import sys

    from rotordyn_modal.model import parameters as parameters_module
    from rotordyn_modal.study import parse_study

    checks = {"_check_keys", "_one_parameter_per_value", "_holds_array"}
    calls = []
    original = parameters_module.parse_key

    def counted(key, data, source="<model>", **options):
        frame, names = sys._getframe(1), set()
        while frame is not None:
            names.add(frame.f_code.co_name)
            frame = frame.f_back
        if names & checks:
            calls.append(key)
        return original(key, data, source, **options)

    monkeypatch.setattr(parameters_module, "parse_key", counted)
    front = "suspensions.mount-FL.stiffness"
    study = {"parameters": [{"name": "front", "key": f"{front}[2]", "values": [1e5, 4e5]},
                            {"name": "rear", "keys": ["suspensions.mount-RR.stiffness", "stator.mass"],
                             "scale": [0.9, 1.1]}],
             "analyses": {"modes": {"speed_rpm": 1000.0}}}
    model = rdm.load_model(EXAMPLES / "rubber_mounts.toml")
    before = model.to_dict()
    parse_study(study, "s.toml", model)
    assert sorted(calls) == sorted([f"{front}[2]", "suspensions.mount-RR.stiffness", "stator.mass"])
    assert model.to_dict() == before


# ------------------------------------- review: one eigvalsh fallback for the Hermitian route
def _undamped_shaft():
    steel = {"name": "steel", "density": 7800.0, "young_modulus": 2.1e11, "shear_modulus": 8.1e10}
    return rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [steel],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shaft": [{"length": 0.6, "outer_diameter": 0.05, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": 0.36, "mass": 5.0, "polar_inertia": 0.05,
                               "diametral_inertia": 0.03}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z, "stiffness": [1e6, 3e6]}
                     for i, z in enumerate((0.0, 0.6))]})


def test_the_hermitian_routes_fall_back_to_eigvalsh_through_one_function(monkeypatch):
    """A speed whose LAPACK reduction failed (NaN) is solved again by ``eigvalsh`` of ``B`` in one
    function, for both routes (the kept reductions of a sweep, and the eigenvalues alone): the
    roots equal those of the sweep without the failure to 1e-12 of the largest."""
    from rotordyn_modal.analysis import _lowest

    model, speeds = _undamped_shaft(), np.linspace(0.0, 3000.0, 4)
    assert model.dofs.n < _lowest.DENSE_BELOW
    reference = rdm.campbell(model, speeds, critical=False, modes=6).eigenvalues
    original, filled = _lowest._hermitian_reductions, _lowest._eigvalsh_where_failed
    calls = []

    def failing(constant, gyroscopic, at):
        eigenvalues, reduced, taus = original(constant, gyroscopic, at)
        eigenvalues[len(at) // 2], taus[len(at) // 2] = np.nan, np.nan
        return eigenvalues, reduced, taus

    def spied(out, constant, gyroscopic, at):
        calls.append(int(np.isnan(out[:, 0]).sum()))
        return filled(out, constant, gyroscopic, at)

    monkeypatch.setattr(_lowest, "_hermitian_reductions", failing)
    monkeypatch.setattr(_lowest, "_eigvalsh_where_failed", spied)
    again = rdm.campbell(_undamped_shaft(), speeds, critical=False, modes=6).eigenvalues
    assert calls and calls[0] == 1
    np.testing.assert_allclose(again, reference, rtol=0, atol=1e-12 * np.abs(reference).max())
    # the eigenvalues-only route, on the matrices B of this model
    constant, gyroscopic = np.zeros((4, 4), complex), np.zeros((4, 4), complex)
    constant[:2, 2:] = -1j * np.array([[2.0, 0.5], [0.0, 1.0]])
    constant[2:, :2] = constant[:2, 2:].conj().T
    gyroscopic[2:, 2:] = 1j * np.array([[0.0, 1.0], [-1.0, 0.0]])
    calls.clear()
    out = _lowest._hermitian_eigenvalues(constant, gyroscopic, np.array([0.0, 2.0, 5.0]))
    assert calls == [1]
    for row, speed in zip(out, (0.0, 2.0, 5.0)):
        np.testing.assert_allclose(row, np.linalg.eigvalsh(constant + speed * gyroscopic), atol=1e-13)
