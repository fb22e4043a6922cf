"""Unbalance phases in degrees made exact where they are multiples of 90 deg: two equal unbalances
180 deg apart on one plane of a rigid rotor put no force on it, so its response is none. The
phasor ``exp(1j * radians(180))`` has an imaginary part of 1.2e-16: the response read 1.19e-21 m at
a phase of 176 deg (found by the session's red-team). Truth: the forces' sum by hand (zero), and a
pair 90 deg apart whose response is the single unbalance's times ``1 + i`` (linearity)."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.unbalance import degree_phasor
from rotordyn_modal.cli import main


def _model(phases):
    return rdm.Model.from_dict({
        "name": "rotor with two unbalances on one plane", "spin_axis": [1.0, 0.0, 0.0], "reference_rotor": "r",
        "rotors": [{"name": "r", "mass": 10.0, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.2,
                    "diametral_inertia": 0.5}],
        "bearings": [{"name": n, "rotor": "r", "position": [x, 0.0, 0.0], "stiffness": 1e6, "damping": 100.0}
                     for n, x in (("a", -0.3), ("b", 0.3))],
        "unbalances": [{"rotor": "r", "amount": 1e-4, "phase_deg": p} for p in phases],
        "sensors": [{"name": "y", "rotor": "r", "position": [0.3, 0.0, 0.0], "direction": [0.0, 1.0, 0.0]},
                    {"name": "z", "rotor": "r", "position": [0.3, 0.0, 0.0], "direction": [0.0, 0.0, 1.0]}]})


SPEEDS = rdm.rpm(np.array([-3000.0, 1000.0, 2000.0, 3000.0]))


@pytest.mark.parametrize("phases", [(0.0, 180.0), (90.0, 270.0), (-90.0, 90.0), (45.0, 225.0, 135.0, 315.0)])
def test_unbalances_that_cancel_give_no_response(phases):
    result = rdm.unbalance_response(_model(phases), SPEEDS)
    bound = 0.0 if all(p % 90 == 0 for p in phases) else 1e-15 * np.abs(
        rdm.unbalance_response(_model((phases[0],)), SPEEDS).response).max()
    assert np.abs(result.response).max() <= bound


def test_a_pair_90_degrees_apart_is_the_single_response_times_one_plus_i():
    single = rdm.unbalance_response(_model((0.0,)), SPEEDS).response
    pair = rdm.unbalance_response(_model((0.0, 90.0)), SPEEDS).response
    spin = np.sign(SPEEDS)        # the phase turns with the spin: +90 deg is i about +spin_axis
    np.testing.assert_allclose(pair, single * (1 + 1j * spin), rtol=1e-13, atol=0)


def test_degree_phasor_is_exact_at_quarter_turns_and_the_exponential_elsewhere():
    quarter = np.array([0.0, 90.0, 180.0, 270.0, 360.0, -90.0, -180.0, 450.0])
    assert np.array_equal(degree_phasor(quarter), np.array([1, 1j, -1, -1j, 1, -1j, -1, 1j]))
    assert np.array_equal(degree_phasor(90.0, -1.0), -1j)
    other = np.array([1e-3, 30.0, 45.0, 123.456, -77.7])
    np.testing.assert_allclose(degree_phasor(other), np.exp(1j * np.radians(other)), rtol=0, atol=3e-16)


def test_the_command_line_prints_a_cancelled_response_as_zero(tmp_path):
    path = tmp_path / "cancel.toml"
    rdm.save_model(_model((0.0, 180.0)), path)
    out = tmp_path / "u.csv"
    assert main(["unbalance", str(path), "--speeds", "1000:3000:3", "--out", str(out)]) == 0
    import pandas as pd

    table = pd.read_csv(out)
    assert (table["amplitude"] == 0).all() and (table["phase_deg"] == 0).all()
