"""The UCS map's speed-dependent bearings' crossings found on Rayleigh-Ritz subspaces (issue 29 §2,
``rotordyn_modal/analysis/_ucs_ritz.py``) against today's route (``ucs_map.SUBSPACE_CROSSINGS``
False: the whole pencil solved at every curve point and refinement step) and against
``critical_speeds`` of the machine held at each crossing's stiffness.

ROSS's compressor_example (224 coordinates, 14 speed-dependent bearings and seals) is measured in
``benchmarks/bench_ucs_map.py`` (its 22 crossings within 2.7e-13 of today's route, which takes
about two minutes of CPU: too long for a test).
"""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _ucs_ritz, ucs_map as module
from rotordyn_modal.io.ross_file import read_ross_rotor

ROOT = Path(__file__).resolve().parent.parent
STIFFNESS = np.geomspace(1e5, 1e10, 41)


def _model(name):
    if name.startswith("ross/"):
        path = ROOT / "tests" / "data" / "ross" / f"{name[5:]}.toml"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return rdm.Model.from_dict(read_ross_rotor(path), source=path)
    return rdm.load_model(ROOT / "examples" / f"{name}.toml")


def _mapped(monkeypatch, model, subspace):
    """The map by the route asked for, and how many crossings the subspace route finished."""
    finished = []
    real = _ucs_ritz._finished
    monkeypatch.setattr(_ucs_ritz, "_finished", lambda *a, **k: finished.append(1) or real(*a, **k))
    monkeypatch.setattr(module, "SUBSPACE_CROSSINGS", subspace)
    result = module.ucs_map(model, STIFFNESS, modes=4)
    monkeypatch.setattr(_ucs_ritz, "_finished", real)
    return result, len(finished)


def _same_crossings(new, old, rtol):
    assert [(c.bearing, c.axis, c.mode, c.name) for c in new] == [(c.bearing, c.axis, c.mode, c.name) for c in old]
    np.testing.assert_allclose([c.speed for c in new], [c.speed for c in old], rtol=rtol, atol=0)
    np.testing.assert_allclose([c.stiffness for c in new], [c.stiffness for c in old], rtol=rtol, atol=0)


@pytest.mark.parametrize("name", ["journal_rotor", "compressor_on_journals", "ross/speed_tables",
                                  "ross/tables_linear_tapered"])
def test_the_subspace_routes_crossings_are_todays(name, monkeypatch):
    """Every example with speed-dependent bearings and the quick ROSS files with speed tables:
    the same crossings (bearing, axis, mode, name) as today's route, speeds and stiffness to
    1e-12, all found on the subspace (each finished by Newton's method: none sent back), the rest
    of the map bit for bit."""
    model = _model(name)
    old, _ = _mapped(monkeypatch, model, False)
    new, finished = _mapped(monkeypatch, model, True)
    speed_dependent = [c for c in old.crossings if next(b for b in old.curves if b.name == c.bearing).speeds is not None]
    assert speed_dependent and finished == len(speed_dependent)
    _same_crossings(new.crossings, old.crossings, 1e-12)
    for field in ("speeds", "mode_speeds", "rigid_speeds"):
        np.testing.assert_array_equal(getattr(new, field), getattr(old, field))
    assert new.mode_names == old.mode_names


def test_points_in_doubt_are_solved_whole_and_too_many_send_the_curve_back(monkeypatch):
    """compressor_on_journals: every point made doubtful (a MAC margin of 1) and each solved whole
    gives today's crossings to 1e-12 (finished by Newton's method from the whole pencil's shapes);
    with no doubt allowed (share -1) the subspace route gives up and today's route runs: its
    crossings bit for bit."""
    model = _model("compressor_on_journals")
    old, _ = _mapped(monkeypatch, model, False)
    monkeypatch.setattr(_ucs_ritz, "_MAC_MARGIN", 1.0)
    monkeypatch.setattr(_ucs_ritz, "_MOST_WHOLE", 1.0)
    whole, finished = _mapped(monkeypatch, model, True)
    assert finished == len(old.crossings)
    _same_crossings(whole.crossings, old.crossings, 1e-12)
    monkeypatch.setattr(_ucs_ritz, "_MOST_WHOLE", -1.0)
    back, finished = _mapped(monkeypatch, model, True)
    assert finished == 0 and back.crossings == old.crossings


def _held_at(name, stiffness):
    """The example with each bearing made linear, isotropic ``stiffness`` [N/m], undamped (the map's
    pencil at that stiffness: its journal films' cross-coupling and damping removed, the thrust
    bearing's axial stiffness kept)."""
    path = ROOT / "examples" / f"{name}.toml"
    data = tomllib.loads(path.read_text())
    for bearing in data["bearings"]:
        for key in ("type", "diameter", "length", "clearance", "viscosity", "damping", "axial_damping"):
            bearing.pop(key, None)
        bearing["stiffness"] = float(stiffness)
    return rdm.Model.from_dict(data, source=str(path))


@pytest.mark.parametrize("name", ["journal_rotor", "compressor_on_journals"])
def test_each_crossing_is_a_critical_speed_of_the_machine_held_at_its_stiffness(name, monkeypatch):
    """At each journal-bearing crossing found on the subspace, ``critical_speeds`` (its own grid
    and refinement on the quadratic eigenproblem) of the machine on linear undamped bearings of
    the crossing's stiffness has a forward order-1 critical speed equal to the crossing's speed,
    to 1e-9."""
    result, finished = _mapped(monkeypatch, _model(name), True)
    assert finished == len(result.crossings) > 0
    for crossing in result.crossings:
        model = _held_at(name, crossing.stiffness)
        top = 1.5 * crossing.speed * 30 / np.pi
        table = rdm.critical_speeds(model, rdm.rpm(np.linspace(0.0, top, 61)), orders=(1,))
        forward = table.speeds[(table.order == 1) & (table.whirl == "forward")]
        assert np.min(np.abs(forward - crossing.speed)) <= 1e-9 * crossing.speed, (crossing, forward)
