"""The report's estimate bounds the stability row's thresholds, an instability inside the sweep
included (issue 27 section 1.9; helper report31).

The estimate of the report's CPU time counts the stability row's refinement (a few one-speed
eigen-solutions a threshold) for :func:`_thresholds_bound` thresholds. It counted the roots that
grow at the sweep's highest speed: a mode unstable only inside the sweep (an island) counted none.

Truth from outside the code: a rigid rotor on two identical bearings placed symmetrically
(translation and tilt uncoupled) whose cross-coupling ``q`` rises linearly from 0 at 2,000 rpm to
``Q0`` at 4,000 rpm and falls back to 0 from 6,000 to 8,000 rpm. In ``r = y + i z`` the translation
obeys ``m r'' + 2 c r' + 2 (k - i q) r = 0``: a root ``i w`` needs ``w^2 = 2 k / m`` and ``c w = q``,
so the forward translation loses stability where ``q = c sqrt(2 k / m)``, once while ``q`` rises and
once while it falls. The tilt modes need ``q`` above ``c`` times their frequency (above 689 rad/s
at every speed of the sweep, over 1.3e5 N/m): inside that island.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from rotordyn_modal.analysis import stability as stability_module
from rotordyn_modal.analysis.stability import stability
from rotordyn_modal.io import load_model
from rotordyn_modal.linear_system import speed_linear_form
from rotordyn_modal.report import ReportInputs

collect_module = importlib.import_module("rotordyn_modal.report.collect")

RPM = np.pi / 30
MASS, STIFFNESS, DAMPING, Q0 = 10.0, 1.0e6, 200.0, 2.0e5
TABLE_RPM = (0.0, 2000.0, 4000.0, 6000.0, 8000.0, 10000.0)
CROSS = (0.0, 0.0, Q0, Q0, 0.0, 0.0)
MCS = 6000 * RPM                                    # the report's sweep: 120 to 9,000 rpm


def _island_toml() -> str:
    def bearing(name, x):
        stiffness = ", ".join(f"[[{STIFFNESS}, {q}], [{-q}, {STIFFNESS}]]" for q in CROSS)
        return f"""
[[bearings]]
name = "{name}"
rotor = "rotor"
position = [{x}, 0.0, 0.0]
speeds_rpm = [{", ".join(str(s) for s in TABLE_RPM)}]
stiffness = [{stiffness}]
damping = [{", ".join(str(DAMPING) for _ in TABLE_RPM)}]
"""
    return f"""
name = "rotor whose bearings' cross-coupling rises and falls with speed"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "rotor"
mass = {MASS}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.05
diametral_inertia = 0.1
speed_ratio = 1.0
""" + bearing("A", 0.2) + bearing("B", -0.2)


@pytest.fixture
def island(tmp_path):
    path = tmp_path / "island.toml"
    path.write_text(_island_toml())
    return load_model(path)


def _closed_form_thresholds_rpm():
    """Where ``q(Omega) = c sqrt(2 k / m)`` on the table's rising and falling ramps [rpm]."""
    share = DAMPING * np.sqrt(2 * STIFFNESS / MASS) / Q0
    return np.array([2000.0 + 2000.0 * share, 8000.0 - 2000.0 * share])


def test_island_case_has_two_thresholds_in_closed_form(island):
    """The case itself: ``stability`` finds the onset and the end of the island where the closed
    form puts them, and the machine is stable at the sweep's highest speed."""
    inputs = ReportInputs("api684", MCS, points=21)
    result = stability(island, inputs.speeds)
    np.testing.assert_allclose(np.sort(result.thresholds) / RPM, _closed_form_thresholds_rpm(), rtol=1e-8)
    assert result.threshold_onsets.tolist() == [True, False]
    assert not result.unstable[-1]


def test_bound_counts_the_island_and_its_refinement(island, monkeypatch):
    """The bound holds where the estimate counted none (fails on 3f1536e: 0 thresholds, 0 solves
    counted against 2 thresholds refined in about 12 eigen-solutions), for ``stability`` and for
    the report's own refinement (:func:`sweep_thresholds`), counted by a counter on the one-speed
    solutions they make."""
    from rotordyn_modal.analysis.campbell import campbell

    inputs = ReportInputs("api684", MCS, points=21)
    bound = collect_module._thresholds_bound(island, inputs)
    calls = [0]

    def counting(name):
        solve = getattr(stability_module, name)

        def counted(*args, **kwargs):
            calls[0] += 1
            return solve(*args, **kwargs)
        monkeypatch.setattr(stability_module, name, counted)

    counting("_largest_real_part")
    counting("_polished_largest_real_part")
    found = len(stability(island, inputs.speeds).thresholds)
    assert found == 2
    assert bound >= found
    assert 0 < calls[0] <= bound * collect_module.THRESHOLD_SOLVES

    calls[0] = 0
    result = campbell(island, inputs.speeds, orders=(1,))
    (thresholds, _, _), _ = collect_module.sweep_thresholds(island, result)
    assert len(thresholds) == found
    assert 0 < calls[0] <= bound * collect_module.THRESHOLD_SOLVES
    text = dict((p[0], p[2]) for p in collect_module.estimate_work(island, inputs).parts)["campbell"]
    assert f"the stability row's thresholds: at most {bound} refined" in text


@pytest.mark.parametrize("name, mcs_rpm, points", [
    ("journal_rotor", 40000.0, 21), ("unstable_cross_coupled", 50000.0, 41),
    ("compressor_on_journals", 20000.0, 21), ("compressor_rotor", 10000.0, 21),
])
def test_bound_holds_on_the_examples(name, mcs_rpm, points):
    """Wide sweeps of the examples (an onset each, or none): the bound is at least what
    ``stability`` finds over the report's speeds."""
    from pathlib import Path

    model = load_model(Path(__file__).resolve().parents[1] / "examples" / f"{name}.toml")
    inputs = ReportInputs("api684", mcs_rpm * RPM, points=points)
    found = int(np.isfinite(stability(model, inputs.speeds).thresholds).sum())
    assert collect_module._thresholds_bound(model, inputs) >= found


def test_bound_without_eigenvalues_is_every_pair_of_speeds(island, monkeypatch):
    """Past the budget of eigenvalue solutions, every pair of neighbouring speeds with a speed not
    proven stable counts: the island's bearings are circulatory from 2,000 to 8,000 rpm (the
    cross-coupling nonzero), passive elsewhere."""
    inputs = ReportInputs("api684", MCS, points=21)
    monkeypatch.setattr(collect_module, "THRESHOLD_SCAN_SECONDS", 0.0)
    speeds = np.asarray(inputs.speeds) / RPM
    circulatory = (speeds > 2000.0) & (speeds < 8000.0)
    expected = np.count_nonzero(circulatory[:-1] | circulatory[1:])
    assert collect_module._thresholds_bound(island, inputs) == expected


def test_passive_machine_never_grows():
    """``passive_at`` (no circulatory term) only where no root has a positive real part beyond
    round-off, checked by numpy's eigenvalues of the state matrix over a wide sweep; the
    cross-coupled example is not proven."""
    from pathlib import Path

    from rotordyn_modal.analysis.stability import passive_at

    examples = Path(__file__).resolve().parents[1] / "examples"
    speeds = np.linspace(0.0, 30000.0, 7) * RPM
    for name in ("compressor_rotor", "gear_machine", "rubber_mounts", "counter_rotating"):
        form = speed_linear_form(load_model(examples / f"{name}.toml"))
        assert passive_at(form, speeds).all(), name
        for speed in speeds:
            matrix = form.at(speed)
            roots = np.linalg.eigvals(matrix)
            scale = np.finfo(float).eps * np.abs(matrix).sum(axis=0).max() * 1e4
            assert roots.real.max() <= scale, (name, speed)
    form = speed_linear_form(load_model(examples / "unstable_cross_coupled.toml"))
    assert not passive_at(form, speeds).any()


@pytest.mark.parametrize("states, expected", [
    ([-1, -1, -1], 0), ([1, 1], 0), ([-1, 1, 1, -1], 2), ([-1, 0, -1], 2), ([0, 0, 0, 0], 3), ([1], 0),
])
def test_count_of_pairs_that_can_change(states, expected):
    from rotordyn_modal.analysis.stability import threshold_count_bound

    assert threshold_count_bound(states) == expected
