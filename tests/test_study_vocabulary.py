"""The study file speaks the command line's words (issue 27 §5): ``[analyses.unbalance]``'s
``quantity`` takes the motion (displacement, velocity, acceleration) or the FRF's name of it
(receptance, mobility, accelerance), as ``unbalance --quantity`` does, and ``forces`` adds the
force rows of ``unbalance --forces`` (suspensions, bearings, rotors, all) after the sensors:
their peak amplitudes and speeds."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.study import StudyError, parse_study

#: the motion a sensor reads and the FRF's name of that motion per unit force
WORDS = {"displacement": "receptance", "velocity": "mobility", "acceleration": "accelerance"}
SPEEDS = "300:3000:12"


@pytest.fixture(scope="module")
def gear():
    return rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml")


def _spec(**unbalance):
    return {"seed": 1, "samples": 2, "design": "latin-hypercube",
            "parameters": [{"key": "suspensions.mount-FL.stiffness", "apply": "scale", "distribution": "uniform",
                            "low": 0.9, "high": 1.1}],
            "analyses": {"unbalance": {"speeds_rpm": SPEEDS, **unbalance}}}


@pytest.mark.parametrize("motion", list(WORDS))
def test_quantity_takes_the_frf_name_of_the_motion(gear, motion):
    """Either word parses to the same options, and the study's peaks of ``mobility`` are those of
    ``velocity``."""
    by_motion = parse_study(_spec(quantity=motion), model=gear).analyses
    by_frf_name = parse_study(_spec(quantity=WORDS[motion]), model=gear).analyses
    assert by_motion["unbalance"]["quantity"] == by_frf_name["unbalance"]["quantity"] == motion


def test_a_mobility_study_gives_the_peaks_of_velocity(gear):
    """Whatever word names it, each peak is a point of the velocity curve: at the speed the study
    names, the amplitude of rdm.unbalance_response(quantity='displacement') of the variant's model
    times the rotor's spin frequency omega (the velocity of a harmonic), not the displacement."""
    a = rdm.study(gear, _spec(quantity="mobility")).dataset
    b = rdm.study(gear, _spec(quantity="velocity")).dataset
    np.testing.assert_array_equal(a["unbalance_peak_amplitude"].values, b["unbalance_peak_amplitude"].values)
    speeds = rdm.rpm(np.linspace(300, 3000, 12))
    for v, (k,) in enumerate(a["sample_value"].values):
        response = rdm.unbalance_response(gear.scaled({"suspensions.mount-FL.stiffness": k}), speeds)
        for i, output in enumerate(a["output"].values):
            for j, source in enumerate(a["unbalance_source"].values):
                at = int(np.argmin(np.abs(speeds - a["unbalance_peak_speed"].values[v, i, j])))
                s = response.sources.index(source)
                omega = 2 * np.pi * response.frequencies_hz[s, at]
                velocity = omega * response.amplitude[response.outputs.index(output), s, at]
                assert a["unbalance_peak_amplitude"].values[v, i, j] == pytest.approx(velocity, rel=1e-9)


@pytest.mark.parametrize("value, expected", [
    ("jerk", "expected displacement, velocity or acceleration (or the FRF's name of it: receptance, mobility, "
             "accelerance)"),
    (3, "expected displacement, velocity or acceleration"),
], ids=["word", "number"])
def test_other_quantities_are_refused_naming_both_sets_of_words(gear, value, expected):
    with pytest.raises(StudyError) as info:
        parse_study(_spec(quantity=value), model=gear)
    assert f"[analyses.unbalance] quantity = {value!r}: {expected}" in str(info.value)


@pytest.mark.parametrize("value", ["mounts", ["suspensions"], True], ids=["word", "list", "boolean"])
def test_forces_takes_the_words_of_unbalance_forces(gear, value):
    with pytest.raises(StudyError) as info:
        parse_study(_spec(forces=value), model=gear)
    assert (f"[analyses.unbalance] forces = {value!r}: expected one of suspensions, bearings, rotors, all"
            in str(info.value))


def test_forces_adds_the_force_rows_peaks_after_the_sensors(gear):
    """``forces = "suspensions"``: the sensors' variables stay as they were, and per (force row,
    source) the largest amplitude of the very rows ``unbalance --forces suspensions`` writes
    (``to_dataframe(forces=...)``, rebuilt here from each variant's model) and its speed."""
    speeds = rdm.rpm(np.linspace(300, 3000, 12))
    plain = rdm.study(gear, _spec()).dataset
    result = rdm.study(gear, _spec(forces="suspensions"))
    data = result.dataset
    assert not result.failed.any()
    np.testing.assert_array_equal(data["unbalance_peak_amplitude"].values, plain["unbalance_peak_amplitude"].values)
    mounts = [s.name for s in gear.suspensions]
    expected_rows = [f"{m}:{c}" for m in mounts for c in ("Fx", "Fy", "Fz", "Mx", "My", "Mz")]
    assert list(data["force_output"].values) == expected_rows
    for v, (k,) in enumerate(data["sample_value"].values):
        table = rdm.unbalance_response(gear.scaled({"suspensions.mount-FL.stiffness": k}), speeds).to_dataframe(
            forces="suspensions")
        for j, source in enumerate(data["unbalance_source"].values):
            for i, row in enumerate(expected_rows):
                curve = table[(table["output"] == row) & (table["source"] == source)]["amplitude"].to_numpy()
                at = int(np.argmin(np.abs(speeds - data["force_peak_speed"].values[v, i, j])))
                # a point of that row's curve: a local maximum inside the sweep, or its largest value
                assert data["force_peak_amplitude"].values[v, i, j] == pytest.approx(curve[at], rel=1e-12)
                inside = 0 < at < len(curve) - 1 and curve[at - 1] <= curve[at] >= curve[at + 1]
                assert inside or curve[at] == curve.max(), (row, source)
    assert np.nanmax(data["force_peak_amplitude"].values) > 0


def test_the_force_rows_are_shown_in_lbf_and_lbf_in_with_units_us(gear, tmp_path):
    """``rotordyn-modal --units us study`` with ``forces = "all"``: a force row's column in lbf, a
    moment row's (the motor's on the stator) in lbf in,
    the numbers the SI file holds divided by the exact factors (4.4482216152605 N, 0.0254 m)."""
    import pandas as pd
    import tomli_w

    from rotordyn_modal.cli.main import main

    spec = tmp_path / "study.toml"
    spec.write_text(tomli_w.dumps(_spec(forces="all")))
    model = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
    for system in ("si", "us"):
        assert main(["--units", system, "study", str(model), "--spec", str(spec), "--out", str(tmp_path / f"{system}.nc"),
                     "--table", str(tmp_path / f"{system}.csv"), "--quiet"]) == 0
    si, us = pd.read_csv(tmp_path / "si.csv"), pd.read_csv(tmp_path / "us.csv")
    pound_force = 0.45359237 * 9.80665
    for row, unit, factor in (("mount-FL:Fz", "lbf", pound_force), ("motor:My", "lbfin", pound_force * 0.0254)):
        column = f"force_peak_amplitude[{row},fan]"
        assert (si[column] > 0).all()
        np.testing.assert_allclose(us[f"{column}_{unit}"], si[column] / factor, rtol=1e-9)   # CSV: 10 digits
