"""simulate's fastest natural frequency (its default output times and the duration check) comes
from the state matrix's eigenvalues alone, not from a whole modal analysis: on 500 geared rotors
(2,006 coordinates) ``modal``'s shapes, whirl forms and repeated roots kept ``simulate`` silent for
over 5 minutes before its CPU estimate (issue 27 §1.9)."""

from __future__ import annotations

import importlib

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import modal as modal_module
from rotordyn_modal.linear_system import speed_linear_form

simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("name", ["spring_block_rotor.toml", "gear_machine.toml", "fan_on_bearings.toml"])
def test_the_fastest_rate_is_the_largest_natural_frequency_without_a_modal_analysis(monkeypatch, name):
    model = rdm.load_model(EXAMPLES / name)
    # the truth: the largest |Im lambda| of the state matrix at rest, from scipy's eig directly
    expected_natural = np.abs(scipy.linalg.eig(speed_linear_form(model).at(0.0))[0].imag).max()

    def no_modal(*args, **kwargs):
        raise AssertionError("a whole modal analysis was made for the simulation's rate")

    monkeypatch.setattr(modal_module, "modal", no_modal)
    rate = simulate_module._fastest_rate(model, 10.0, None)
    spin = 10.0 * max(abs(r) for r in model.speed_ratios.values())
    assert rate == pytest.approx(max(expected_natural, spin), rel=1e-12)


def test_a_simulation_runs_without_a_modal_analysis(monkeypatch):
    calls = []
    monkeypatch.setattr(modal_module, "modal", lambda *args, **kwargs: calls.append(args))  # (any error is caught)
    model = rdm.load_model(EXAMPLES / "spring_block_rotor.toml")
    result = rdm.simulate(model, 0.05, speed=50.0, drive="free", samples=11, backend="numpy")
    assert len(result.time) == 11
    assert calls == []
