"""An API report of a model without [[sensors]] (every rotor read from ROSS) judges the unbalance
response at X-Y proximity probes placed at each bearing, where API 684 reads it.

Before: "API 684 separation margin: not evaluated: the model has no [[sensors]]: no response to
judge" and the same for the probe limits. The truth here is a closed form: a symmetric rigid rotor
on two equal isotropic bearings with the API static unbalance at its centre of mass moves in its
cylindrical mode only, each bearing's journal by ``U W^2 / |2k - m W^2 + 2 i c W|``.
"""

import math

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.report import ReportInputs, collect

M, K, C, SPACING = 30.0, 2.0e6, 400.0, 0.25         # kg, N/m, N s/m, m (each bearing from the centre)
MCS_RPM = 3000.0

MODEL = f"""
name = "rotor on two bearings, no sensors"
spin_axis = [1.0, 0.0, 0.0]

[[rotors]]
name = "shaft"
mass = {M}
center_of_mass = [0.0, 0.0, 0.0]
polar_inertia = 0.4
diametral_inertia = 0.9

[[bearings]]
name = "DE"
rotor = "shaft"
position = [{SPACING}, 0.0, 0.0]
stiffness = {K}
damping = {C}

[[bearings]]
name = "NDE"
rotor = "shaft"
position = [{-SPACING}, 0.0, 0.0]
stiffness = {K}
damping = {C}
"""


@pytest.fixture(scope="module")
def collected(tmp_path_factory):
    path = tmp_path_factory.mktemp("probes") / "rotor.toml"
    path.write_text(MODEL)
    inputs = ReportInputs("api684", rdm.rpm(MCS_RPM), points=61, stiffness=np.geomspace(1e5, 1e10, 5))
    return collect(rdm.load_model(path), inputs)


def test_the_probes_are_at_the_bearings_along_both_lateral_axes(collected):
    sensors = {s.name: s for s in collected.model.sensors}
    assert sorted(sensors) == ["DE probe y", "DE probe z", "NDE probe y", "NDE probe z"]
    for name, sensor in sensors.items():
        bearing = name.split()[0]
        assert sensor.rotor == "shaft" and sensor.measure == "relative"
        assert np.allclose(sensor.position, [SPACING if bearing == "DE" else -SPACING, 0, 0])
        assert np.allclose(sensor.direction, [0, 1, 0] if name.endswith("y") else [0, 0, 1])
    assert any("no [[sensors]]" in w and "DE probe y" in w for w in collected.warnings), collected.warnings


def test_the_static_case_response_at_each_probe_is_the_closed_form(collected):
    result = collected.results["unbalance"]
    case = next(i for i, name in enumerate(result.sources) if name.startswith("api-static"))
    # API 617: Ua = 2 x 6350 W / N [g mm], W the rotor's mass [kg], N its MCS [rpm]
    amount = 2 * 6350.0 * M / MCS_RPM * 1e-6                  # [kg m]
    w = result.speeds
    expected = amount * w ** 2 / np.abs(2 * K - M * w ** 2 + 2j * C * w)
    for name in ("DE probe y", "DE probe z", "NDE probe y", "NDE probe z"):
        got = np.abs(result.response[result.outputs.index(name), case])
        assert got == pytest.approx(expected, rel=1e-9), name


def test_separation_margin_and_probe_limits_are_judged(collected):
    judged = {c.name: c for c in collected.criteria}
    for name in ("API 684 separation margin", "API 617 probe vibration limit"):
        assert judged[name].verdict in ("pass", "fail"), (name, judged[name])
    # the peak: the cylindrical mode's, at sqrt(2k/m) raised by the damping (closed form, docs/standards.md)
    k, c, m = 2 * K, 2 * C, M
    peak_speed = math.sqrt(2 * k ** 2 / (2 * k * m - c ** 2)) * 30 / math.pi
    peaks = collected.results["peaks"]
    assert not peaks.empty and np.allclose(peaks["speed_rpm"].min(), peak_speed, rtol=1e-6), (peaks, peak_speed)


def test_a_model_with_sensors_is_judged_at_its_own():
    """The probes are added only where the model has no [[sensors]]: a model with one keeps it alone."""
    from rotordyn_modal.analysis.unbalance_checks import with_bearing_probes

    text = MODEL + '\n[[sensors]]\nname = "p"\nrotor = "shaft"\nmeasure = "relative"\nposition = [0, 0, 0]\n' \
                   'direction = [0, 0, 1]\n'
    model = rdm.Model.from_dict(__import__("tomllib").loads(text))
    same, names = with_bearing_probes(model)
    assert same is model and names == []
