"""Rotor-bearing models through the workflows: studies over bearing keys, the fit of bearing
parameters to measured FRFs of probe channels, and the FRF overlay with probe channels."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.study import parse_study

KEY = "bearings.fan-DE.stiffness[0][0]"


@pytest.fixture(scope="module")
def fan():
    return rdm.load_model(Path(__file__).resolve().parent.parent / "examples" / "fan_on_bearings.toml")


def test_each_variant_of_a_study_over_bearing_keys_equals_its_single_analysis(fan):
    spec = parse_study({"seed": 5, "samples": 4, "design": "latin-hypercube",
                        "parameters": [{"key": KEY, "distribution": "uniform", "low": 2e6, "high": 4e6},
                                       {"key": "bearings.motor-NDE.damping", "apply": "scale",
                                        "distribution": "uniform", "low": 0.5, "high": 2.0}],
                        "analyses": {"campbell": {"speeds_rpm": "0:6000:31", "orders": [1]},
                                     "critical_speeds": {}}}, model=fan)
    result = rdm.study(fan, spec)
    assert not result.failed.any()
    ds = result.dataset
    assert ds["frequency_hz"].shape[-1] == fan.dofs.n          # 16 coordinates: 16 modes
    for v, (k, factor) in enumerate(ds["sample_value"].values):
        variant = fan.with_values({KEY: k}).scaled({"bearings.motor-NDE.damping": factor})
        campbell = rdm.campbell(variant, spec.analyses["campbell"]["speeds"], orders=(1,))
        np.testing.assert_array_equal(ds["frequency_hz"].values[v], campbell.frequencies_hz)
        assert ds["critical_count"].values[v] == len(campbell.critical)


def test_bearing_stiffness_and_damping_are_identified_from_probe_and_hub_frfs(fan):
    """Synthetic measurement from the true model (no noise); a fit started 40 % off recovers the
    bearing's coefficients."""
    truth = fan.with_values({KEY: 3.6e6, "bearings.fan-DE.damping": 420.0})
    freqs = np.linspace(20, 220, 400)
    measured = rdm.frf(truth, rdm.rpm(1500), freqs, inputs=["hub-tap-y", "hammer-z"],
                       outputs=["probe-DE-x", "probe-DE-y", "acc-fan-z"])
    start = fan.with_values({KEY: 2.2e6, "bearings.fan-DE.damping": 250.0})
    result = rdm.fit(start, [measured], [KEY, "bearings.fan-DE.damping"], weighting="none")
    assert result.converged
    np.testing.assert_allclose(result.values[0], 3.6e6, rtol=1e-6)
    np.testing.assert_allclose(result.values[1], 420.0, rtol=1e-6)


def test_overlay_of_model_and_measurement_on_probe_channels(fan, tmp_path):
    freqs = np.linspace(20, 220, 200)
    model = rdm.frf(fan, rdm.rpm(1500), freqs, inputs=["hub-tap-y"], outputs=["probe-DE-x", "probe-DE-y"])
    measured = rdm.frf(fan.with_values({KEY: 3.3e6}), rdm.rpm(1500), freqs, inputs=["hub-tap-y"],
                       outputs=["probe-DE-x", "probe-DE-y"])
    figure = model.plot(measured=measured)
    lines = [line for ax in figure.axes for line in ax.get_lines()]
    assert len(lines) >= 8                                   # 2 FRFs x (model, measured) x (magnitude, phase)
    figure.savefig(tmp_path / "overlay.png")


def test_3d_shape_moves_each_rotor_in_its_bearings(fan, tmp_path):
    """The drawn vertices of each body move by its own motion: the rotor in its bearings
    (shape_at with body=rotor), the housing by the stator's; bearings are springs between them."""
    from rotordyn_modal.analysis.mode_shapes import mode_shape_3d

    result = rdm.modal(fan, rdm.rpm(3000))
    view = mode_shape_3d(result, fan, 13)
    k = np.nonzero(result.oscillatory)[0][12]
    for body, motion in zip(view.outline.bodies, view.body_motion):
        owner = body.name if body.name in result.rotor_names else None
        expected = np.array([result.shape_at(p, body=owner)[k] for p in body.vertices])
        np.testing.assert_allclose(motion, view.scale * expected, rtol=1e-12, atol=1e-15)
    motor = [m for b, m in zip(view.outline.bodies, view.body_motion) if b.name == "motor"][0]
    stator = [m for b, m in zip(view.outline.bodies, view.body_motion) if b.name == "stator"][0]
    assert np.abs(motor).max() > 10 * np.abs(stator).max()      # mode 13: the motor whirls in its bearings
    assert sum(s.kind == "bearing" for s in view.outline.springs) == len(fan.bearings)
    result.plot_shape(13, fan).savefig(tmp_path / "shape.png")
