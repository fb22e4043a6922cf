"""Identification: recovery of known mount parameters from noisy UFF58 data, and honest failures."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.fit import fit
from rotordyn_modal.analysis.frf import FRFResult
from rotordyn_modal.errors import InputError
from rotordyn_modal.io.measured import default_mapping, read_measured
from rotordyn_modal.io.uff import write_uff58

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "gear_machine.toml"
KEYS = ["suspensions.mount-FL.stiffness", "suspensions.mount-RR.damping", "suspensions.mount-FR.stiffness[2]"]
START = {KEYS[0]: 1.6, KEYS[1]: 0.6, KEYS[2]: 1.5}   # every start is off by a factor >= 1.5


@pytest.fixture(scope="module")
def measured_file(tmp_path_factory):
    """FRFs of the true model at two speeds with 3 % complex noise, written to UFF58 and read back."""
    true = rdm.load_model(EXAMPLE)
    rng = np.random.default_rng(7)
    sets = []
    for speed in (0.0, rdm.rpm(2400)):
        res = rdm.frf(true, speed, np.linspace(3.0, 40.0, 200), quantity="accelerance")
        noise = 0.03 * (rng.normal(size=res.H.shape) + 1j * rng.normal(size=res.H.shape)) / np.sqrt(2)
        coherence = 1 / (1 + np.abs(noise) ** 2)
        sets.append(FRFResult(**{**res.__dict__, "H": res.H * (1 + noise), "coherence": coherence}))
    path = tmp_path_factory.mktemp("fit") / "measured.uff"
    write_uff58(sets, path, default_mapping(true))
    return path


def test_recovers_known_parameters_within_two_percent(measured_file):
    true = rdm.load_model(EXAMPLE)
    start = true.scaled(START)
    measured = read_measured(measured_file, start)
    result = fit(start, measured, KEYS, starts=2)
    assert result.converged, result.message
    fitted = result.fitted_model(start)
    for key in KEYS:
        np.testing.assert_allclose(fitted.get(key), true.get(key), rtol=0.02)
    # the reported uncertainty is consistent with the actual error (within 4 standard deviations)
    error = np.abs(np.log(result.factors * [START[k] for k in KEYS]))
    assert np.all(error < 4 * result.std_relative + 1e-12)
    assert result.correlation.shape == (3, 3)
    np.testing.assert_allclose(np.diag(result.correlation), 1.0)


def test_gain_factor_and_band(measured_file):
    true = rdm.load_model(EXAMPLE)
    measured = read_measured(measured_file, true)
    scaled = [FRFResult(**{**m.__dict__, "H": 1.25 * m.H}) for m in measured]
    result = fit(true, scaled, ["gain"], band_hz=(5.0, 30.0), starts=1)
    assert result.values[0] == pytest.approx(1.25, rel=2e-3)
    assert result.n_points == sum(((m.frequencies_hz >= 5) & (m.frequencies_hz <= 30)).sum() * 4 for m in measured)


def test_coherence_weights_lines_by_the_inverse_of_their_scatter():
    """Half the lines are exact with coherence 0.999, the other half 1.5 times too large with
    coherence 0.5. Weighted by sqrt(g2 / (1 - g2)), the inverse of an FRF estimate's relative
    scatter (Bendat & Piersol), an exact line counts 999 times a bad one in the squares, and the
    least-squares gain on relative residuals is (999 + 2/3) / (999 + 4/9) = 1.00022 (it would
    be 1.09 with weights sqrt(g2), and 1.15 unweighted)."""
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, 0.0, np.linspace(3.0, 40.0, 120), quantity="accelerance")
    bad = np.arange(res.H.shape[-1]) % 2 == 1
    H = np.where(bad, 1.5 * res.H, res.H)
    coherence = np.where(bad, 0.5, 0.999) * np.ones(res.H.shape)
    measured = [FRFResult(**{**res.__dict__, "H": H, "coherence": coherence})]
    weighted = fit(model, measured, ["gain"], starts=1).values[0]
    assert weighted == pytest.approx((999 + 2 / 3) / (999 + 4 / 9), rel=1e-8)    # found to 5e-12 and 4e-10
    uniform = fit(model, measured, ["gain"], weighting="none", starts=1).values[0]
    assert uniform == pytest.approx((1 + 2 / 3) / (1 + 4 / 9), rel=1e-8)


def test_gain_uncertainty_is_whites_sandwich_with_the_small_sample_factor():
    """One fitted gain g on relative residuals r = (g H - H_meas) / s (real and imaginary parts, m
    of them; s = |H_meas| floored at 1e-3 of the largest FRF's RMS): d r / d log g = g H / s =: J,
    and the heteroscedasticity-consistent
    variance of log g is sum(J^2 r^2) / sum(J^2)^2 m / (m - 1) (HC1). Half the lines 1.5 times
    too large make the residuals uneven, so the sandwich is not the textbook s^2 / sum(J^2)."""
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, 0.0, np.linspace(3.0, 40.0, 120), quantity="accelerance")
    bad = np.arange(res.H.shape[-1]) % 2 == 1
    H_meas = np.where(bad, 1.5 * res.H, res.H)
    measured = [FRFResult(**{**res.__dict__, "H": H_meas, "coherence": None})]
    result = fit(model, measured, ["gain"], weighting="none", starts=1)
    g = result.values[0]
    magnitude = np.abs(H_meas)
    scale = np.maximum(magnitude, 1e-3 * np.sqrt(np.mean(magnitude ** 2, axis=-1)).max())
    r, J = (g * res.H - H_meas) / scale, g * res.H / scale
    r, J = np.concatenate([r.real.ravel(), r.imag.ravel()]), np.concatenate([J.real.ravel(), J.imag.ravel()])
    m = len(r)
    assert m == 2 * result.n_points
    hc1 = np.sqrt(np.sum(J ** 2 * r ** 2) / np.sum(J ** 2) ** 2 * m / (m - 1))
    # the Jacobian is a forward difference (step 1e-6 in log g): the variance to about 1e-6
    assert result.std_relative[0] == pytest.approx(hc1, rel=1e-5)
    textbook = np.sqrt(np.sum(r ** 2) / (m - 1) / np.sum(J ** 2))
    assert abs(hc1 / textbook - 1) > 0.01


def test_parameter_without_effect_is_reported_not_converged(measured_file):
    """A mount of 1e-6 N/m changes nothing the sensors see: the fit must say so, and why."""
    data = rdm.load_model(EXAMPLE).to_dict()
    data["suspensions"].append({"name": "feeler", "position": [0.0, 0.0, 0.0], "stiffness": [1e-6] * 3})
    model = rdm.Model.from_dict(data)
    result = fit(model, read_measured(measured_file, model), ["suspensions.feeler.stiffness"], starts=1)
    assert not result.converged
    assert "do not determine the parameters: suspensions.feeler.stiffness hardly changes them" in result.message


def test_optimum_outside_the_bounds_is_reported(measured_file):
    true = rdm.load_model(EXAMPLE)
    start = true.scaled({KEYS[0]: 3.0})
    result = fit(start, read_measured(measured_file, start), [KEYS[0]], bounds={KEYS[0]: (0.5, 2.0)}, starts=1)
    assert not result.converged
    assert "suspensions.mount-FL.stiffness ended on a bound" in result.message


def test_result_table_and_figure(measured_file):
    model = rdm.load_model(EXAMPLE)
    result = fit(model, read_measured(measured_file, model), ["gain"], starts=1)
    assert list(result.to_dataframe().columns) == ["key", "start", "fitted", "factor", "std_relative"]
    # the figure: the correlation matrix as the image, each value written in its cell
    two = fit(model, read_measured(measured_file, model), ["gain", KEYS[1]], starts=1)   # correlated -0.07
    ax = two.plot().axes[0]
    np.testing.assert_array_equal(ax.get_images()[0].get_array(), two.correlation)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["gain", KEYS[1].split(".", 1)[1]]
    assert [t.get_text() for t in ax.texts] == [f"{v:+.2f}" for v in two.correlation.ravel()]
    assert [t.get_position() for t in ax.texts] == [(j, i) for i in range(2) for j in range(2)]


@pytest.mark.parametrize("kwargs,message", [
    ({"params": []}, "give at least one parameter"),
    ({"params": ["gain", "gain"]}, "a parameter is given twice"),
    ({"params": ["rotors.motor.mass"], "bounds": {"gain": (0.5, 2)}}, "bounds given for gain, which is not fitted"),
    ({"params": ["gain"], "bounds": {"gain": (2, 3)}}, "bounds of gain = (2, 3): expected factors 0 < low < 1 < high"),
    ({"params": ["gain"], "band_hz": (100.0, 200.0)}, "no measured frequency line in the band"),
    ({"params": ["gain"], "weighting": "snr"}, "weighting 'snr': expected 'coherence' or 'none'"),
    ({"params": ["gain"], "starts": 0}, "starts = 0: expected at least 1"),
    ({"params": ["suspensions.mount-FL.loss_factor"]}, "suspensions.mount-FL.loss_factor = 0.0: a fitted value must be > 0"),
])
def test_errors(measured_file, kwargs, message):
    model = rdm.load_model(EXAMPLE)
    data = model.to_dict()
    data["suspensions"][0]["loss_factor"] = 0.0
    model = rdm.Model.from_dict(data)
    with pytest.raises(InputError) as info:
        fit(model, read_measured(measured_file, model), **kwargs)
    assert message in str(info.value)


def test_reported_uncertainty_matches_monte_carlo_scatter():
    """20 noisy data sets (2 % relative + a noise floor of 0.3 % of the largest FRF): the scatter of
    the fitted log factors equals the mean reported standard uncertainty within the sampling error
    of a standard deviation from 20 samples (1/sqrt(2 * 19) = 16 %; 3 of those allowed)."""
    model = rdm.load_model(EXAMPLE)
    clean = [rdm.frf(model, s, np.linspace(3.0, 40.0, 150), quantity="accelerance") for s in (0.0, rdm.rpm(2400))]
    fitted, reported = [], []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        noisy = []
        for c in clean:
            def noise():
                return (rng.normal(size=c.H.shape) + 1j * rng.normal(size=c.H.shape)) / np.sqrt(2)
            noisy.append(FRFResult(**{**c.__dict__, "H": c.H * (1 + 0.02 * noise()) + 0.003 * np.abs(c.H).max() * noise()}))
        result = fit(model, noisy, KEYS, starts=1)
        fitted.append(np.log(result.factors))
        reported.append(result.std_relative)
    ratio = np.std(fitted, axis=0, ddof=1) / np.mean(reported, axis=0)
    assert np.all((ratio > 0.52) & (ratio < 1.48)), ratio


def test_progress_bar_counts_model_evaluations_and_changes_nothing(measured_file, capsys):
    model = rdm.load_model(EXAMPLE)
    measured = read_measured(measured_file, model)
    quiet = fit(model, measured, ["gain", KEYS[0]], starts=2)
    capsys.readouterr()
    shown = fit(model, measured, ["gain", KEYS[0]], starts=2, progress=True)
    bar = capsys.readouterr().err
    assert "fit (model evaluations)" in bar and "start 2/2" in bar
    np.testing.assert_array_equal(shown.factors, quiet.factors)
    np.testing.assert_array_equal(shown.start_costs, quiet.start_costs)


def test_measured_lines_all_of_coherence_zero_are_refused_not_a_crash():
    """A measured file whose coherence is 0 on every line gives every line weight 0 (found by
    tests/fuzz_many.py: exit 1, "Residuals are not finite"): refused naming the cause; without the
    coherence weighting the same data fit."""
    model = rdm.load_model(EXAMPLE)
    res = rdm.frf(model, 0.0, np.linspace(3.0, 40.0, 40), quantity="accelerance")
    silent = FRFResult(**{**res.__dict__, "coherence": np.zeros(res.H.shape)})
    with pytest.raises(InputError, match="the coherence is 0 at every measured line in the band"):
        fit(model, [silent], ["gain"], starts=1)
    assert fit(model, [silent], ["gain"], weighting="none", starts=1).factors[0] == pytest.approx(1.0, rel=1e-6)
