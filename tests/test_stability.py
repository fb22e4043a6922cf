"""Stability over speed and stability maps, against the independent reference.

(The closed-form threshold of the shipped cross-coupled example is tested in
tests/test_unstable_example.py.)
"""

from __future__ import annotations

import copy
import tomllib

import numpy as np
import pytest
from scipy.optimize import brentq

import rotordyn_modal as rdm
from reference_model import ReferenceMachine, random_description


def largest_real_part(ref, speed):
    return ref.eig(speed)[0].real.max()


def reference_thresholds(data, speeds):
    """Roots of the reference's largest real part between grid points where it changes sign."""
    ref = ReferenceMachine(data)
    values = np.array([largest_real_part(ref, s) for s in speeds])
    roots = []
    for k in np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]:
        roots.append(brentq(lambda s: largest_real_part(ref, s), speeds[k], speeds[k + 1], xtol=1e-12, rtol=1e-14))
    return np.array(roots)


@pytest.fixture
def skewed_unstable(examples_dir):
    """The cross-coupled example made generic: rotor off the axis and off the centre of mass,
    a non-principal stator tensor, supports moved: no closed form, only the reference."""
    with open(examples_dir / "unstable_cross_coupled.toml", "rb") as handle:
        data = tomllib.load(handle)
    data = copy.deepcopy(data)
    data["stator"]["inertia"] = [[0.8, 0.05, 0.02], [0.05, 1.5, 0.1], [0.02, 0.1, 1.4]]
    data["rotors"][0]["center_of_mass"] = [0.03, 0.02, -0.01]
    data["suspensions"][0]["position"] = [0.22, 0.01, 0.0]
    return data


def test_threshold_speeds_equal_the_reference_roots(skewed_unstable):
    speeds = np.linspace(-2500.0, 2500.0, 101)
    result = rdm.stability(rdm.Model.from_dict(skewed_unstable), speeds)
    expected = reference_thresholds(skewed_unstable, speeds)
    assert len(expected) >= 1
    np.testing.assert_allclose(np.sort(result.thresholds), np.sort(expected), rtol=1e-9)
    onset = result.threshold_speed
    assert onset == pytest.approx(expected[expected >= 0].min(), rel=1e-9)
    ref = ReferenceMachine(skewed_unstable)
    assert largest_real_part(ref, 0.999 * onset) < 0 < largest_real_part(ref, 1.001 * onset)
    expected_stable = [largest_real_part(ref, s) < 0 for s in speeds]
    assert list(result.stable) == expected_stable


def test_map_thresholds_equal_the_reference(skewed_unstable):
    model = rdm.Model.from_dict(skewed_unstable)
    speeds = np.linspace(0.0, 3000.0, 61)
    factors = np.array([0.7, 1.0, 1.5])
    result = rdm.stability_map(model, speeds, "suspensions.bearing-A.damping", scale=factors)
    for v, (factor, found) in enumerate(zip(factors, result.threshold_speeds)):
        data = copy.deepcopy(skewed_unstable)
        data["suspensions"][0]["damping"] = (np.array(data["suspensions"][0]["damping"]) * factor).tolist()
        roots = reference_thresholds(data, speeds)
        assert found == pytest.approx(roots.min(), rel=1e-9)
        # the map's surfaces: the largest real part and the smallest damping ratio over the roots
        ref = ReferenceMachine(data)
        for k in (0, 30, 60):
            lam = ref.eig(speeds[k])[0]
            upper = lam[lam.imag >= 0]
            assert result.max_real_parts[v, k] == pytest.approx(lam.real.max(), rel=1e-10)
            assert result.min_damping_ratios[v, k] == pytest.approx(np.min(-upper.real / np.abs(upper)), rel=1e-9)
    table = result.to_dataframe()
    assert list(table.columns[:6]) == ["speed_rpm", "value", "mode", "real_part", "damping_ratio",
                                       "log_decrement"]
    assert sorted(set(table.value)) == list(factors)
    assert result.max_real_parts.shape == (3, 61)
    for bad in ([], [1.0, np.nan], [[1.0, 2.0]]):
        with pytest.raises(rdm.InputError, match="'suspensions.bearing-A.damping': expected a non-empty list of finite"):
            rdm.stability_map(model, speeds, "suspensions.bearing-A.damping", scale=bad)
    with pytest.raises(rdm.InputError, match="give exactly one of values or scale"):
        rdm.stability_map(model, speeds, "suspensions.bearing-A.damping", values=[1.0], scale=[1.0])


def test_damped_gyroscopic_machine_with_symmetric_supports_is_stable(examples_dir):
    """Symmetric K > 0, C > 0: stable at every speed (Thomson-Tait-Chetaev); no thresholds;
    real parts equal the reference's."""
    path = examples_dir / "gear_machine.toml"
    model = rdm.load_model(path)
    assert np.linalg.eigvalsh(model.matrices().C).min() > 0
    speeds = rdm.rpm(np.linspace(-12000, 12000, 49))
    result = rdm.stability(model, speeds)
    assert result.stable.all() and len(result.thresholds) == 0 and np.isnan(result.threshold_speed)
    with open(path, "rb") as handle:
        ref = ReferenceMachine(tomllib.load(handle))
    for k in (0, 20, 48):
        expected = np.sort(ref.modes(speeds[k])[0].real)
        np.testing.assert_allclose(np.sort(result.real_parts[k]), expected, rtol=1e-8)
    lam = result.eigenvalues
    np.testing.assert_allclose(result.damping_ratios, -lam.real / np.abs(lam), rtol=1e-12)
    np.testing.assert_allclose(result.log_decrements, -2 * np.pi * lam.real / lam.imag, rtol=1e-12)


def test_undamped_machine_is_marginal_without_spurious_thresholds():
    data = random_description(np.random.default_rng(4), n_rotors=2, damping=False)
    result = rdm.stability(rdm.Model.from_dict(data), np.linspace(-3000.0, 3000.0, 61))
    assert len(result.thresholds) == 0
    assert np.all(np.abs(result.real_parts) <= 1e-9 * np.abs(result.eigenvalues).max())


def test_unsupported_direction_is_not_read_as_instability():
    model = rdm.Model(stator=rdm.Stator(mass=50.0, inertia=[2.0, 3.0, 4.0]),
                      rotors=[rdm.Rotor("r", 5.0, [0.1, 0.0, 0.0], 0.05, 0.04, speed_ratio=1.0)],
                      suspensions=[rdm.Suspension(f"s{s}", [s * 0.3, 0.0, 0.0], [1e5, 1e5, 1e5],
                                                  [50.0, 50.0, 50.0]) for s in (1, -1)])
    result = rdm.stability(model, np.linspace(0.0, 2000.0, 21))  # roll about x is free
    assert len(result.thresholds) == 0 and result.stable.all()


def test_refusals(skewed_unstable):
    model = rdm.Model.from_dict(skewed_unstable)
    with pytest.raises(rdm.InputError):
        rdm.stability(model, [0.0, 1.0], vary="suspensions.bearing-A.damping")
    with pytest.raises(rdm.InputError):
        rdm.stability(model, [0.0, 1.0], values=[1.0])
    with pytest.raises(rdm.InputError, match="no value"):
        rdm.stability(model, [0.0, 1.0], vary="suspensions.bearing-A.nope", scale=[1.0])


def _cross_coupled_rotor(cross):
    """A rigid rotor, undamped, on two like bearings at +-0.2 m, each with radial stiffness
    [[k, q], [-q, k]]: ``cross`` gives q [N/m], a number or a table over ``speeds_rpm``."""
    k = 1.0e6

    def stiffness(q):
        return [[k, q], [-q, k]]

    bearings = []
    for name, s in (("A", 0.2), ("B", -0.2)):
        bearing = {"name": name, "rotor": "r", "position": [s, 0.0, 0.0]}
        if isinstance(cross, dict):
            bearing.update(speeds_rpm=cross["speeds_rpm"], stiffness=[stiffness(q) for q in cross["q"]])
        else:
            bearing.update(stiffness=stiffness(cross))
        bearings.append(bearing)
    return {"spin_axis": [1.0, 0.0, 0.0], "bearings": bearings,
            "rotors": [{"name": "r", "mass": 20.0, "center_of_mass": [0.0, 0.0, 0.0],
                        "polar_inertia": 0.3, "diametral_inertia": 0.5, "speed_ratio": 1.0}]}


def test_an_onset_from_marginal_stability_is_where_the_cross_coupling_starts():
    """Undamped, the machine is conservative (marginally stable) while its bearings' cross-coupled
    stiffness q is zero: up to s1 = 2950 rpm, where the table starts q growing linearly to q2 at
    s2 = 6000 rpm. Beyond s1 it is unstable: the bounce obeys m z'' + 2 (k - i q) z = 0 (z = u_y + i u_z),
    whose root i w sqrt(1 - i q / k), w = sqrt(2 k / m), has the real part w q / 2k (1 + O(q^2/k^2)).
    Real parts count once above 1e-10 of the largest |lam|, Lam, so the threshold lies in
    [s1, s1 + 2e-10 (k / q2) (Lam / w) (s2 - s1)] (doubled for the O(q^2) terms, plus the
    bisection's 1e-13 relative). The mode reported is the one unstable just above: its real part
    there is the largest of the independent reference's."""
    from reference_bearings import BearingMachine

    k, q2, m, jp, jd, a = 1.0e6, 2.0e5, 20.0, 0.3, 0.5, 0.2
    s1, s2 = rdm.rpm(2950.0), rdm.rpm(6000.0)
    model = rdm.Model.from_dict(_cross_coupled_rotor({"speeds_rpm": [0.0, 2950.0, 6000.0], "q": [0.0, 0.0, q2]}))
    speeds = rdm.rpm(np.linspace(0.0, 6000.0, 41))
    result = rdm.stability(model, speeds)
    assert len(result.thresholds) == 1 and result.threshold_onsets.tolist() == [True]
    w_bounce = np.sqrt(2 * k / m)
    w_forward = (jp * s1 + np.sqrt((jp * s1) ** 2 + 4 * jd * 2 * k * a * a)) / (2 * jd)   # conical, forward
    largest = max(w_bounce, w_forward)
    reach = 2 * 2e-10 * (k / q2) * (largest / w_bounce) * (s2 - s1)
    assert s1 * (1 - 1e-13) <= result.thresholds[0] <= s1 + reach + 1e-13 * s2
    above = int(np.searchsorted(speeds, s1))                      # the first grid speed past s1
    q = q2 * (speeds[above] - s1) / (s2 - s1)
    expected = BearingMachine(_cross_coupled_rotor(q)).eigenvalues(speeds[above]).real.max()
    mode = result.threshold_modes[0]
    assert result.eigenvalues[above, mode - 1].real == pytest.approx(expected, rel=1e-9)


def test_tables_hold_the_results_numbers(skewed_unstable):
    """The stability table (a row per speed and mode) and the modes table at one speed hold the
    results' own numbers: real part [1/s], damping ratio, log decrement, frequency."""
    model = rdm.Model.from_dict(skewed_unstable)
    result = rdm.stability(model, np.linspace(0.0, 2500.0, 11))
    table = result.to_dataframe()
    k = np.repeat(np.arange(11), result.eigenvalues.shape[1])
    m = table["mode"].to_numpy() - 1
    for column, values in (("real_part", result.real_parts), ("damping_ratio", result.damping_ratios),
                           ("log_decrement", result.log_decrements), ("frequency_hz", result.frequencies_hz)):
        np.testing.assert_array_equal(table[column], values[k, m])
    modes = rdm.modal(model, 1200.0)
    rows = modes.to_dataframe()
    for column, values in (("real_part", modes.eigenvalues.real), ("damping_ratio", modes.damping_ratios),
                           ("log_decrement", modes.log_decrements), ("frequency_hz", modes.frequencies_hz)):
        np.testing.assert_array_equal(rows[column], values[modes.oscillatory])
    assert np.any(rows["real_part"] != 0) and np.all(np.isfinite(rows["log_decrement"]))
