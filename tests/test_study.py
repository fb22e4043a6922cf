"""Parameter studies (rotordyn_modal.study): samples, single-analysis equality, closed-form
Monte Carlo, failures, bad study files, checkpoint and resume, storage, sensitivity, figures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import rotordyn_modal as rdm
from rotordyn_modal.study import StudyError, load_study, parse_study, read_study, sample_variants
from rotordyn_modal.study.sampling import saltelli_matrix
from rotordyn_modal.study.sensitivity import sobol_indices, standardized_regression

# ---------------------------------------------------------------------------- models
STATOR_MASS, ROTOR_MASS, HALF_X, HALF_Y = 90.0, 10.0, 0.4, 0.5
K0, LOG_STD = 1.0e5, 0.2  # median and log-std of each mount's x stiffness [N/m]


def translating_machine():
    """Four mounts at the corners of a rectangle through the centre of mass (z = 0), rotor
    at the centre of mass, spin along z. An x translation meets only the x springs, whose
    moments cancel: omega_x^2 = 4 k_x / m exactly, the lowest mode (y, z, rotations stiffer)."""
    mounts = [{"name": f"m{i}", "position": [sx * HALF_X, sy * HALF_Y, 0.0],
               "stiffness": [K0, 10 * K0, 10 * K0], "damping": [0.0, 0.0, 0.0]}
              for i, (sx, sy) in enumerate([(1, 1), (1, -1), (-1, 1), (-1, -1)])]
    return rdm.Model.from_dict({
        "spin_axis": [0.0, 0.0, 1.0],
        "stator": {"mass": STATOR_MASS, "inertia": [5.0, 5.0, 5.0]},
        "rotors": [{"name": "r", "mass": ROTOR_MASS, "center_of_mass": [0, 0, 0], "polar_inertia": 0.05,
                    "diametral_inertia": 0.04, "speed_ratio": 1.0}],
        "suspensions": mounts}, "translating")


def lognormal_study(samples=400, seed=11, design="monte-carlo"):
    return {"seed": seed, "samples": samples, "design": design,
            "parameters": [{"name": "k", "keys": [f"suspensions.m{i}.stiffness[0]" for i in range(4)],
                            "distribution": "lognormal", "median": K0, "log_std": LOG_STD}],
            "analyses": {"modes": {"speed_rpm": 0.0}}}


@pytest.fixture
def gear(examples_dir):
    return rdm.load_model(examples_dir / "gear_machine.toml")


def small_gear_study(samples=6, seed=3):
    return {"seed": seed, "samples": samples, "design": "latin-hypercube",
            "parameters": [
                {"key": "suspensions.mount-FL.stiffness", "apply": "scale", "distribution": "uniform",
                 "low": 0.85, "high": 1.15},
                {"name": "rear", "keys": ["suspensions.mount-RL.damping", "suspensions.mount-RR.damping"],
                 "apply": "scale", "distribution": "normal", "mean": 1.0, "std": 0.2, "truncate": [0.5, 1.5]},
                {"key": "rotors.fan.polar_inertia", "distribution": "lognormal", "mean": 0.30, "std": 0.01}],
            "analyses": {"campbell": {"speeds_rpm": "0:6000:41", "orders": [1, 2]}, "critical_speeds": {},
                         "modes": {"speed_rpm": 1500.0}, "stability": {"speeds_rpm": "0:6000:21"},
                         "unbalance": {"speeds_rpm": "100:6000:40", "operating_speed_rpm": 3000.0}}}


# ---------------------------------------------------------------------------- samples
@pytest.mark.parametrize("design", ["monte-carlo", "latin-hypercube", "sobol", "saltelli"])
def test_same_seed_same_samples_other_seed_other_samples(gear, design):
    spec = small_gear_study()
    spec["design"] = design
    spec["parameters"] = spec["parameters"][:1] + spec["parameters"][2:]
    a = sample_variants(parse_study(spec, model=gear))
    b = sample_variants(parse_study(spec, model=gear))
    np.testing.assert_array_equal(a, b)
    spec["seed"] = 4
    assert not np.array_equal(a, sample_variants(parse_study(spec, model=gear)))
    rows = spec["samples"] * (4 if design == "saltelli" else 1)
    assert a.shape == (rows, 2)


def test_latin_hypercube_puts_one_sample_in_each_stratum(gear):
    spec = small_gear_study(samples=50)
    spec["parameters"] = spec["parameters"][:1]
    x = sample_variants(parse_study(spec, model=gear))[:, 0]
    strata = np.floor((x - 0.85) / 0.30 * 50).astype(int)
    assert sorted(strata) == list(range(50))


def test_a_grid_after_a_distribution_keeps_each_parameters_column(gear):
    """Variants: the full factorial of the grid values times the same samples of the
    distributions, each parameter in its own column in the order the study lists them."""
    spec = {"seed": 2, "samples": 5, "parameters": [
        {"name": "m", "key": "rotors.fan.mass", "distribution": "uniform", "low": 7.0, "high": 9.0},
        {"name": "k", "key": "suspensions.mount-FL.stiffness[0]", "values": [1e5, 2e5, 3e5]}],
        "analyses": {"modes": {}}}
    x = sample_variants(parse_study(spec, model=gear))
    assert x.shape == (15, 2)
    assert np.array_equal(x[:, 1], np.repeat([1e5, 2e5, 3e5], 5))                  # the grid, in order
    assert np.all((7.0 < x[:, 0]) & (x[:, 0] < 9.0))
    assert np.array_equal(x[:, 0], np.tile(x[:5, 0], 3))                          # the same samples at each


def test_truncation_and_correlation_follow_their_definitions(gear):
    spec = {"seed": 1, "samples": 4000, "parameters": [
        {"name": "a", "key": "stator.mass", "distribution": "normal", "mean": 150.0, "std": 10.0,
         "truncate": [140.0, 175.0]},
        {"name": "b", "key": "rotors.fan.mass", "distribution": "uniform", "low": 7.0, "high": 9.0}],
        "correlation": {"parameters": ["a", "b"], "matrix": [[1.0, 0.6], [0.6, 1.0]]},
        "analyses": {"modes": {}}}
    x = sample_variants(parse_study(spec, model=gear))
    assert x[:, 0].min() >= 140.0 and x[:, 0].max() <= 175.0
    exact = stats.truncnorm((140 - 150) / 10, (175 - 150) / 10, loc=150, scale=10)
    assert abs(x[:, 0].mean() - exact.mean()) < 4 * exact.std() / math.sqrt(len(x))
    # Gaussian copula: the normal scores of the two marginals have correlation 0.6
    z = stats.norm.ppf(np.column_stack([exact.cdf(x[:, 0]), (x[:, 1] - 7.0) / 2.0]))
    r = np.corrcoef(z.T)[0, 1]
    assert abs(r - 0.6) < 4 * (1 - 0.36) / math.sqrt(len(x))


# ---------------------------------------------------------------------------- equality with single analyses
def test_each_variant_equals_the_single_analyses_of_its_model(gear):
    spec = parse_study(small_gear_study(), model=gear)
    result = rdm.study(gear, spec)
    ds = result.dataset
    assert not result.failed.any()
    options = spec.analyses
    for v, (k, rear, inertia) in enumerate(ds["sample_value"].values):
        model = gear.scaled({"suspensions.mount-FL.stiffness": k, "suspensions.mount-RL.damping": rear,
                             "suspensions.mount-RR.damping": rear}).with_values({"rotors.fan.polar_inertia": inertia})
        camp = rdm.campbell(model, options["campbell"]["speeds"], orders=(1, 2))
        np.testing.assert_array_equal(ds["frequency_hz"].values[v], camp.frequencies_hz)
        np.testing.assert_array_equal(ds["damping_ratio"].values[v], camp.damping_ratios)
        np.testing.assert_array_equal(ds["whirl_ratio"].values[v], camp.whirl_ratios)
        crit = camp.critical
        for i, (src, order, mode) in enumerate(zip(ds["crossing_source"].values, ds["crossing_order"].values,
                                                    ds["crossing_mode"].values)):
            chosen = (crit.source == src) & (crit.order == order) & (crit.mode == mode)
            expected = crit.speeds[chosen][np.argmin(np.abs(crit.speeds[chosen]))] if chosen.any() else np.nan
            np.testing.assert_array_equal(ds["critical_speed"].values[v, i], expected)
        assert ds["critical_count"].values[v] == len(crit)
        modal = rdm.modal(model, rdm.rpm(1500.0))
        np.testing.assert_array_equal(ds["modal_frequency_hz"].values[v], modal.frequencies_hz)
        stab = rdm.stability(model, options["stability"]["speeds"])
        np.testing.assert_array_equal(ds["threshold_speed"].values[v], stab.threshold_speed)
        unb = rdm.unbalance_response(model, options["unbalance"]["speeds"])
        np.testing.assert_array_equal(ds["unbalance_peak_amplitude"].values[v].max(axis=1),
                                      unb.amplitude.max(axis=2).max(axis=1))


# ---------------------------------------------------------------------------- closed-form Monte Carlo
def test_monte_carlo_of_sqrt_k_over_m_reproduces_the_lognormal_moments_within_reported_error():
    model = translating_machine()
    result = rdm.study(model, lognormal_study())
    k = result.samples["k"].values
    f = result.dataset["modal_frequency_hz"].values[:, 0]
    m = STATOR_MASS + ROTOR_MASS
    # each variant: the exact frequency of the x translation
    np.testing.assert_allclose(f, np.sqrt(4 * k / m) / (2 * np.pi), rtol=1e-10)
    # the distribution: f is lognormal with median f0 and log-std LOG_STD / 2
    f0, s = math.sqrt(4 * K0 / m) / (2 * math.pi), LOG_STD / 2
    exact_mean = f0 * math.exp(s * s / 2)
    exact_std = exact_mean * math.sqrt(math.expm1(s * s))
    table = result.summary(["modal_frequency_hz[1]"], percentiles=(5, 50, 95), confidence=0.99).iloc[0]
    assert table["n"] == 400
    assert abs(table["mean"] - exact_mean) < 3 * table["mean_se"]
    assert table["mean_se"] == pytest.approx(exact_std / math.sqrt(400), rel=0.15)  # the error reported is right
    # and it is the standard error by its definition, from the sample's own standard deviation
    assert table["mean_se"] == pytest.approx(np.std(f, ddof=1) / math.sqrt(400), rel=1e-12)
    for q in (5, 50, 95):
        exact = f0 * math.exp(s * stats.norm.ppf(q / 100))
        assert table[f"p{q}_low"] <= exact <= table[f"p{q}_high"]
        # and its width is the asymptotic one, 2 z_0.995 sqrt(q (1 - q) / n) / pdf(x_q)
        pdf = stats.lognorm(s, scale=f0).pdf(exact)
        width = 2 * stats.norm.ppf(0.995) * math.sqrt(q / 100 * (1 - q / 100) / 400) / pdf
        assert table[f"p{q}_high"] - table[f"p{q}_low"] == pytest.approx(width, rel=0.5)


def test_probability_of_a_critical_speed_in_a_band_matches_the_lognormal_within_its_error():
    model = translating_machine()
    spec = lognormal_study(samples=300, seed=5)
    spec["analyses"] = {"critical_speeds": {"speeds_rpm": "0:4000:81"}}
    result = rdm.study(model, spec)
    m = STATOR_MASS + ROTOR_MASS
    low, high = 55.0, 65.0  # rad/s; the x translation crosses 1X at omega = sqrt(4 k / m)
    exact = stats.lognorm(LOG_STD, scale=K0).cdf(np.array([low, high]) ** 2 * m / 4) @ [-1, 1]
    p = result.probability_in_band(low, high, modes=[1])
    assert 0.1 < exact < 0.9 and p["n"] == 300
    assert abs(p["probability"] - exact) < 3 * p["standard_error"]
    assert p["low"] <= exact <= p["high"]
    # the Wilson interval inverts the score test: its ends solve (p - t)^2 = z^2 t (1 - t) / n
    z, share = stats.norm.ppf(0.975), p["hits"] / p["n"]
    for end in (p["low"], p["high"]):
        assert (share - end) ** 2 == pytest.approx(z * z * end * (1 - end) / p["n"], rel=1e-9)


def test_probability_in_band_counts_reversed_spin_by_its_magnitude():
    """The band is on |speed|: the machine spun backwards (speeds -4000..0 rpm) has the same
    critical speeds turned negative (its x translation has no gyroscopic coupling), and the same
    variants hit the band."""
    model = translating_machine()
    results = {}
    for grid in ("0:4000:81", "-4000:0:81"):
        spec = lognormal_study(samples=40, seed=5)
        spec["analyses"] = {"critical_speeds": {"speeds_rpm": grid}}
        results[grid] = rdm.study(model, spec)
    forward, backward = results["0:4000:81"], results["-4000:0:81"]
    chosen = forward.dataset["crossing_mode"].values == 1
    np.testing.assert_allclose(backward.dataset["critical_speed"].values[:, chosen],
                               -forward.dataset["critical_speed"].values[:, chosen], rtol=1e-12)
    band = forward.probability_in_band(55.0, 65.0, modes=[1])
    assert 0 < band["hits"] < band["n"] == 40
    assert backward.probability_in_band(55.0, 65.0, modes=[1]) == band


@pytest.mark.parametrize("n, q", [(20, 50.0), (100, 5.0), (400, 95.0), (37, 90.0), (1000, 50.0)])
def test_percentile_intervals_cover_with_the_promised_confidence(n, q):
    """[x_(j), x_(k)] holds the q-th percentile unless fewer than j or at least k of the n samples
    fall below it: its coverage is P(j <= B < k), B ~ binomial(n, q/100), at least the
    confidence, and each tail is at most half the rest (equal tails)."""
    from rotordyn_modal.study.results import percentile_interval

    low, high = percentile_interval(np.arange(1.0, n + 1.0), q, confidence=0.95)    # x_(i) = i
    j, k = int(low), int(high)
    below = stats.binom(n, q / 100)
    assert below.cdf(k - 1) - below.cdf(j - 1) >= 0.95
    if 1 < j:
        assert below.cdf(j - 1) <= 0.025
    if k < n:
        assert below.sf(k - 1) <= 0.025


# ---------------------------------------------------------------------------- failures and bad input
def test_a_failing_variant_is_recorded_with_its_reason_and_the_others_run(gear):
    spec = {"parameters": [{"key": "rotors.fan.polar_inertia", "values": [0.3, 0.5, 0.2]}],
            "analyses": {"modes": {}}}
    result = rdm.study(gear, spec)
    assert result.failed.tolist() == [False, True, False]
    error = result.dataset["error"].values[1]
    assert "ModelError" in error and "[rotors.fan] polar_inertia" in error
    assert np.isnan(result.dataset["modal_frequency_hz"].values[1]).all()
    ok = rdm.modal(gear.with_values({"rotors.fan.polar_inertia": 0.2}), 0.0)
    np.testing.assert_array_equal(result.dataset["modal_frequency_hz"].values[2], ok.frequencies_hz)


@pytest.mark.parametrize("change, message", [
    (lambda s: s["parameters"][0].update(key="suspensions.mount-FX.stiffness"),
     r"study.toml: \[\[parameters\]\] 1 key = 'suspensions.mount-FX.stiffness': expected a dotted key .*mount-FL"),
    (lambda s: s["parameters"][1].update(std=-0.2),
     r"study.toml: \[\[parameters\]\] 2 std = -0.2: expected a finite number > 0"),
    (lambda s: s["parameters"][0].update(distribution="gauss"),
     r"\[\[parameters\]\] 1 distribution = 'gauss': expected one of normal, lognormal, uniform"),
    (lambda s: s.update(design="random"), r"design = 'random': expected one of monte-carlo"),
    (lambda s: s.update(samples=1), r"samples = 1: expected a whole number >= 2"),
    (lambda s: s["analyses"].update(campbel={}), r"\[analyses\] = 'campbel': expected analyses among"),
    (lambda s: s["analyses"]["campbell"].update(speeds_rpm="0:100"), r"speeds_rpm = '0:100'"),
    (lambda s: s["parameters"][1].update(truncate=[2.0, 1.0]), r"truncate = \[2.0, 1.0\]"),
    (lambda s: s.update(correlation={"parameters": ["rear", "rotors.fan.polar_inertia"],
                                     "matrix": [[1.0, 1.2], [1.2, 1.0]]}), r"\[correlation\] matrix"),
    (lambda s: s.update(correlation={"parameters": ["rear", "rotors.fan.polar_inertia"],
                                     "matrix": [[1.0, "0.5"], ["0.5", 1.0]]}), r"\[correlation\] matrix"),
    (lambda s: s["parameters"][0].update(lows=0.8), r"\[\[parameters\]\] 1 lows = 0.8: expected one of the keys"),
    (lambda s: s["parameters"][0].update(apply="value"),
     r"1 key = 'suspensions.mount-FL.stiffness': expected a key holding one number to set"),
    (lambda s: s.pop("samples"), r"study.toml: samples = '<missing>': expected a whole number >= 2"),
    (lambda s: s["analyses"]["stability"].pop("speeds_rpm"),
     r"study.toml: \[analyses.stability\] speeds_rpm = '<missing>': expected speeds in rpm: 'START:STOP:N' or a list"),
    (lambda s: s["analyses"]["campbell"].update(speeds_rpm=[3000, 1000, 2000]),
     r"\[analyses.campbell\] speeds_rpm = \[3000, 1000, 2000\]: expected strictly increasing speeds"),
    (lambda s: s["analyses"]["campbell"].update(orders=[1, 0]),
     r"\[analyses.campbell\] orders = \[1, 0\]: expected a list of excitation orders > 0"),
    (lambda s: s["analyses"]["modes"].update(speed_rpm="fast"),
     r"\[analyses.modes\] speed_rpm = 'fast': expected a finite speed in rpm"),
    (lambda s: s["analyses"]["unbalance"].update(outputs="acc-top-z"),
     r"\[analyses.unbalance\] outputs = 'acc-top-z': expected a list of sensor names"),
    (lambda s: s["analyses"]["unbalance"].update(outputs=["acc-top-z", "acc-nope"]),
     r"\[analyses.unbalance\] outputs = \['acc-top-z', 'acc-nope'\]: expected names of the model's sensors: "
     r"acc-top-z, acc-side-y"),
    (lambda s: s["analyses"]["unbalance"].update(operating_speed_rpm=0),
     r"\[analyses.unbalance\] operating_speed_rpm = 0: expected a finite non-zero speed in rpm"),
    (lambda s: s["analyses"]["unbalance"].update(quantity="jerk"),
     r"\[analyses.unbalance\] quantity = 'jerk': expected displacement, velocity or acceleration"),
])
def test_bad_study_files_are_refused_naming_file_key_value_and_expectation(gear, tmp_path, change, message):
    import tomli_w

    spec = small_gear_study()
    change(spec)
    path = tmp_path / "study.toml"
    path.write_text(tomli_w.dumps(spec))
    with pytest.raises(StudyError, match=message):
        read_study(path, gear)


def _grid_only(spec):
    spec["parameters"] = [{"key": "suspensions.mount-FL.stiffness", "scale": "0.8:1.2:3"}]


def _saltelli_correlated(spec):
    spec["design"] = "saltelli"
    spec["correlation"] = {"parameters": ["rear", "rotors.fan.polar_inertia"], "matrix": [[1.0, 0.5], [0.5, 1.0]]}


def _saltelli_with_grid(spec):
    spec["design"] = "saltelli"
    spec["parameters"].append({"key": "suspensions.mount-FR.stiffness", "scale": [0.9, 1.1]})


def _correlation(names, matrix):
    return lambda spec: spec.update(correlation={"parameters": names, "matrix": matrix})


@pytest.mark.parametrize("change, message", [
    (_grid_only, "samples = 6: expected no samples: every parameter is a grid (give a distribution to sample)"),
    (_saltelli_correlated, "design = 'saltelli': expected independent parameters (Sobol indices assume no "
                           "correlation); remove [correlation] or use another design"),
    (_saltelli_with_grid, "design = 'saltelli': expected distributions only (a Saltelli design takes no grid "
                          "parameters)"),
    (lambda s: s.update(samples=2_000_000),
     "samples = 2000000: expected a study of at most 1,000,000 variants (asked for 2,000,000)"),
    (lambda s: s["parameters"][1].update(name=""), "[[parameters]] 2 name = '': expected a non-empty string"),
    (lambda s: s["parameters"][0].update(values=[1.0, 2.0]),
     "[[parameters]] 1 = ['apply', 'distribution', 'high', 'key', 'low', 'values']: expected exactly one of "
     "values, scale or distribution"),
    (lambda s: s["parameters"][0].update(apply="add"),
     "[[parameters]] 1 apply = 'add': expected 'value' (set the key) or 'scale' (multiply it)"),
    (lambda s: s.update(correlation=[1, 2]), "[correlation] = [1, 2]: expected a table with parameters and matrix"),
    (_correlation(["rear", "nope"], [[1.0, 0.5], [0.5, 1.0]]),
     "[correlation] parameters = ['rear', 'nope']: expected distinct names of distribution parameters: "
     "suspensions.mount-FL.stiffness, rear, rotors.fan.polar_inertia"),
    (_correlation(["rear", "rotors.fan.polar_inertia"], [["a", 1], [1, 1]]),
     "[correlation] matrix = [['a', 1], [1, 1]]: expected a symmetric 2x2 matrix with ones on the diagonal"),
    (_correlation(["rear", "rotors.fan.polar_inertia"], [[1.0, 1.0], [1.0, 1.0]]),
     "[correlation] matrix = [[1.0, 1.0], [1.0, 1.0]]: expected a positive definite matrix"),
])
def test_inconsistent_study_designs_are_refused(gear, tmp_path, change, message):
    """Samples of a grid, a Saltelli design with correlation or grids, too many variants, parameter
    and correlation tables that do not fit: each refused naming the key, its value and why."""
    import re

    import tomli_w

    spec = small_gear_study()
    change(spec)
    path = tmp_path / "study.toml"
    path.write_text(tomli_w.dumps(spec))
    with pytest.raises(StudyError, match=re.escape(f"study.toml: {message}")):
        read_study(path, gear)


def test_study_file_with_a_byte_order_mark_is_read_and_deep_nesting_refused(tmp_path, gear):
    """A UTF-8 BOM (Windows editors) is skipped; arrays nested thousands deep (Python's TOML parser
    recurses: RecursionError) or more than 32 deep are refused in one line naming the file."""
    import tomli_w

    text = tomli_w.dumps(small_gear_study())
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + text.encode())
    assert read_study(tmp_path / "bom.toml", gear).samples == 6
    for depth in (33, 5000):
        (tmp_path / "deep.toml").write_text(text + "chunk_size = " + "[" * depth + "]" * depth + "\n")
        with pytest.raises(StudyError, match=r"deep.toml: .*expected TOML with arrays and tables nested "
                                             r"at most 32 deep"):
            read_study(tmp_path / "deep.toml", gear)


def test_missing_and_broken_study_files(tmp_path, gear):
    with pytest.raises(StudyError, match="no such file"):
        read_study(tmp_path / "none.toml", gear)
    (tmp_path / "bad.toml").write_text("seed = = 1\n")
    with pytest.raises(StudyError, match="valid TOML"):
        read_study(tmp_path / "bad.toml", gear)


# ---------------------------------------------------------------------------- checkpoint and resume
class _InterruptingExecutor:
    """Runs ``map`` serially and raises KeyboardInterrupt after ``after`` results."""

    def __init__(self, after):
        self.after, self.calls = after, 0

    def map(self, function, tasks):
        for task in tasks:
            if self.calls == self.after:
                raise KeyboardInterrupt
            self.calls += 1
            yield function(task)


def test_an_interrupted_study_resumes_without_recomputing_finished_chunks(gear, tmp_path):
    spec = small_gear_study(samples=8)
    spec["analyses"] = {"modes": {}, "critical_speeds": {"speeds_rpm": "0:3000:31"}}
    folder = tmp_path / "out.nc.partial"
    with pytest.raises(KeyboardInterrupt):
        rdm.study(gear, spec, executor=_InterruptingExecutor(after=3), checkpoint=folder, chunk_size=2)
    assert len(list(folder.glob("chunk-*.npz"))) == 3
    counting = _InterruptingExecutor(after=10**9)
    resumed = rdm.study(gear, spec, executor=counting, checkpoint=folder, chunk_size=2)
    assert counting.calls == 1 and resumed.resumed_chunks == 3  # 4 chunks, 3 kept
    fresh = rdm.study(gear, spec, chunk_size=2)
    for name in ("modal_frequency_hz", "critical_speed", "sample_value"):
        np.testing.assert_array_equal(resumed.dataset[name].values, fresh.dataset[name].values)


def test_a_checkpoint_of_another_study_is_refused(gear, tmp_path):
    spec = small_gear_study(samples=4)
    spec["analyses"] = {"modes": {}}
    rdm.study(gear, spec, checkpoint=tmp_path / "c", chunk_size=2)
    spec["seed"] = 99
    with pytest.raises(rdm.InputError, match="different study"):
        rdm.study(gear, spec, checkpoint=tmp_path / "c", chunk_size=2)


# ---------------------------------------------------------------------------- storage and tables
def test_netcdf_opens_without_the_package_and_round_trips(gear, tmp_path):
    import scipy.io
    import xarray as xr

    result = rdm.study(gear, small_gear_study(samples=3))
    path = tmp_path / "r.nc"
    result.save(path)
    with scipy.io.netcdf_file(path, "r", mmap=False) as plain:  # no xarray, no rotordyn_modal
        np.testing.assert_array_equal(plain.variables["frequency_hz"][:], result.dataset["frequency_hz"].values)
        assert plain.variables["frequency_hz"].dimensions == ("variant", "speed", "mode")
        assert plain.variables["critical_speed"].units == b"rad/s"
    with xr.open_dataset(path, engine="scipy") as ds:
        np.testing.assert_array_equal(ds["sample_value"].values, result.dataset["sample_value"].values)
        assert list(ds["parameter"].values) == result.parameters
    loaded = load_study(path)
    np.testing.assert_array_equal(loaded.dataset["critical_speed"].values, result.dataset["critical_speed"].values)
    assert loaded.to_dataframe().shape == result.to_dataframe().shape


def test_tables(gear):
    result = rdm.study(gear, small_gear_study(samples=3))
    wide = result.to_dataframe()
    assert len(wide) == 3 and "threshold_speed" in wide and "critical_speed[motor,1,1]" in wide
    np.testing.assert_array_equal(wide["critical_speed[motor,1,1]"].values,
                                  result.dataset["critical_speed"].sel(crossing=0).values)
    long = result.to_dataframe("frequency_hz")
    assert len(long) == 3 * 41 * 6 and {"variant", "speed", "mode", "frequency_hz", "rear"} <= set(long)


# ---------------------------------------------------------------------------- sensitivity
def test_sobol_indices_of_a_linear_function_equal_the_variance_shares():
    a = np.array([1.0, 2.0, 0.5])
    rng = np.random.default_rng(0)
    rows = saltelli_matrix(rng.random((4096, 3)), rng.random((4096, 3)))
    result = sobol_indices(rows @ a, 3, bootstrap=100)
    exact = a**2 / np.sum(a**2)  # equal variances (uniform on [0, 1])
    assert np.all(np.abs(result["S1"] - exact) < 4 * result["S1_se"] + 1e-3)
    assert np.all(np.abs(result["ST"] - exact) < 4 * result["ST_se"] + 1e-3)
    # variance shares do not see a constant added to the output (here 1000 times its spread)
    shifted = sobol_indices(rows @ a + 1000.0, 3, bootstrap=100)
    for name in ("S1", "ST"):
        np.testing.assert_allclose(shifted[name], result[name], rtol=0, atol=1e-9)


def test_standardized_regression_of_an_exactly_linear_output():
    rng = np.random.default_rng(1)
    X = rng.normal(size=(200, 3)) * [1.0, 3.0, 0.1]
    y = X @ [2.0, -1.0, 5.0] + 7.0
    result = standardized_regression(X, y)
    np.testing.assert_allclose(result["SRC"], [2.0, -1.0, 5.0] * X.std(axis=0) / y.std(), rtol=1e-10)
    assert result["R2"] == pytest.approx(1.0, abs=1e-12)


def test_study_sensitivity_ranks_the_parameter_that_matters(examples_dir):
    model = translating_machine()
    spec = lognormal_study(samples=32, design="saltelli")
    spec["parameters"].append({"key": "rotors.r.polar_inertia", "distribution": "uniform", "low": 0.04,
                               "high": 0.06})
    table = rdm.study(model, spec).sensitivity(["modal_frequency_hz[1]"])
    s = table.set_index("parameter")
    # f1 depends on k alone: the other's AB rows repeat A's outputs, so its estimates are 0 exactly
    assert s.loc["rotors.r.polar_inertia", "ST"] == 0.0 and s.loc["rotors.r.polar_inertia", "S1"] == 0.0
    assert abs(s.loc["k", "ST"] - 1.0) < 3 * s.loc["k", "ST_se"]
    assert abs(s.loc["k", "S1"] - 1.0) < 3 * s.loc["k", "S1_se"]


# ---------------------------------------------------------------------------- figures
def test_figures(gear, examples_dir):
    import matplotlib.figure

    result = rdm.study(gear, small_gear_study(samples=4))
    for fig in (result.plot_campbell(band_rpm=(3400, 3700)), result.plot_critical_histograms(band_rpm=(3400, 3700)),
                result.plot_sensitivity()):
        assert isinstance(fig, matplotlib.figure.Figure)
    with pytest.raises(rdm.InputError, match="two grid parameters"):
        result.plot_stability_map()
    unstable = rdm.load_model(examples_dir / "unstable_cross_coupled.toml")
    grid = rdm.study(unstable, examples_dir / "stability_map.study.toml")
    fig = grid.plot_stability_map(speed_rpm=15000)
    assert isinstance(fig, matplotlib.figure.Figure)
    # the grid holds each combination once: 11 damping x 8 cross-coupling factors
    assert grid.n_variants == 88 and len(np.unique(grid.dataset["sample_value"].values, axis=0)) == 88


def test_critical_histograms_count_in_whole_variants(gear):
    """A histogram's axis counts variants: every tick within its limits is a whole number (four
    variants were ticked at 0.2, 0.4, ...)."""
    import matplotlib.pyplot as plt

    fig = rdm.study(gear, small_gear_study(samples=4)).plot_critical_histograms(band_rpm=(3400, 3700))
    fig.canvas.draw()
    checked = 0
    for ax in (a for a in fig.axes if a.get_visible()):
        low, high = ax.get_ylim()
        ticks = [t for t in ax.get_yticks() if low <= t <= high]
        assert len(ticks) >= 2 and all(float(t).is_integer() for t in ticks), ticks
        checked += 1
    assert checked >= 2
    plt.close(fig)


def test_sensitivity_legend_covers_no_bar():
    """The gear machine's mount tolerance study (six critical speeds, four mounts, coefficients
    0.35 to 0.85): the legend placed 'best' inside the axes covered the longest bars. Drawn from
    a given table (the plotting computes nothing), measured on the drawn figure."""
    import matplotlib.pyplot as plt
    import pandas as pd

    from rotordyn_modal.plotting.study import plot_sensitivity

    values = [[0.80, 0.78, 0.68, 0.65], [0.78, 0.80, 0.64, 0.62], [0.82, 0.85, 0.60, 0.54],
              [0.82, 0.85, 0.58, 0.53], [0.42, 0.35, 0.74, 0.82], [0.49, 0.51, 0.80, 0.77]]
    parameters = [f"suspensions.mount-{m}.stiffness" for m in ("FL", "FR", "RL", "RR")]
    table = pd.DataFrame([{"output": f"critical_speed[motor,1,{k + 1}]", "parameter": p, "SRC": v}
                          for k, row in enumerate(values) for p, v in zip(parameters, row)])
    fig = plot_sensitivity(table)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent(renderer)
    bars = [patch.get_window_extent(renderer) for patch in ax.patches]
    assert len(bars) == 24
    assert not any(legend.overlaps(bar) for bar in bars)
    plt.close(fig)


def test_a_study_without_seed_records_the_one_it_drew_and_resumes_with_it(gear, tmp_path):
    spec = small_gear_study(samples=6)
    del spec["seed"]
    spec["analyses"] = {"modes": {}}
    folder = tmp_path / "c"
    with pytest.raises(KeyboardInterrupt):
        rdm.study(gear, spec, executor=_InterruptingExecutor(after=1), checkpoint=folder, chunk_size=2)
    resumed = rdm.study(gear, spec, checkpoint=folder, chunk_size=2)
    assert resumed.resumed_chunks == 1
    seed = int(resumed.dataset.attrs["seed"])
    again = rdm.study(gear, {**spec, "seed": seed}, chunk_size=2)
    np.testing.assert_array_equal(resumed.dataset["sample_value"].values, again.dataset["sample_value"].values)
    np.testing.assert_array_equal(resumed.dataset["modal_frequency_hz"].values,
                                  again.dataset["modal_frequency_hz"].values)


@pytest.mark.parametrize("study_file, model_file", [
    ("mount_tolerance.study.toml", "gear_machine.toml"), ("mount_sobol.study.toml", "gear_machine.toml"),
    ("stability_map.study.toml", "unstable_cross_coupled.toml")])
def test_example_study_files_are_valid(examples_dir, study_file, model_file):
    definition = read_study(examples_dir / study_file, rdm.load_model(examples_dir / model_file))
    assert definition.analyses and definition.parameters


def test_sobol_example_indices_are_variance_shares(examples_dir):
    result = rdm.study(rdm.load_model(examples_dir / "gear_machine.toml"), examples_dir / "mount_sobol.study.toml")
    assert result.n_variants == 64 * (4 + 2) and not result.failed.any()
    table = result.sensitivity(["modal_frequency_hz[1]"]).set_index("parameter")
    # first-order shares of a nearly additive output: each in [0, 1] and together about 1
    assert np.all(table["S1"] > -3 * table["S1_se"]) and np.all(table["ST"] < 1 + 3 * table["ST_se"])
    assert abs(table["S1"].sum() - 1) < 3 * np.sqrt((table["S1_se"] ** 2).sum())


def test_study_campbell_names_each_excitation_line_beside_it_and_clear_of_the_curves(gear):
    """Issue 27: the excitation lines' names were anchored at the line's end with ha='right',
    so the line ran through its own name ('motor 1X', 'fan 1X') and 'mesh:motor-fan 1X' stuck
    out of the axes. Measured on the drawn figure (``label_geometry``): every name inside the
    axes, no curve crossing it, no two names overlapping, each nearer its own line than any
    other excitation line."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from label_geometry import crossings, curve_segments, glyph_box

    result = rdm.study(gear, {**small_gear_study(samples=2), "analyses": {"campbell": {"speeds_rpm": "0:6000:41",
                                                                                    "orders": [1]}}})
    fig = result.plot_campbell(band_rpm=(3400, 3700))
    ax = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    dashed = [line for line in ax.get_lines() if line.get_linestyle() == "--"]    # drawn in the table's order
    lines = dict(zip(map(str, result.dataset["excitation"].values), dashed))
    names = [t for t in ax.texts if t.get_text() in lines]
    assert len(lines) == 3 and {t.get_text() for t in names} == set(lines)
    segments = curve_segments(ax)
    boxes = [glyph_box(t, renderer) for t in names]
    for text, box in zip(names, boxes):
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, text.get_text()
        assert len(crossings(box, segments)) == 0, f"a curve runs through {text.get_text()}"
        corners = np.array([[box.x0, box.y0], [box.x1, box.y0], [box.x0, box.y1], [box.x1, box.y1]])

        def distance(line):          # from the box's nearest corner to the drawn segments
            xy = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
            a, d = xy[:-1], np.diff(xy, axis=0)
            t = np.clip(((corners[:, None] - a) * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-12), 0, 1)
            return np.hypot(*(a + t[..., None] * d - corners[:, None]).transpose(2, 0, 1)).min()
        assert min(lines, key=lambda n: distance(lines[n])) == text.get_text()
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    plt.close(fig)


# ---------------------------------------------------------------------------- keys the model file leaves out
def _hollowed(examples_dir, inner):
    """The flexible pump with its middle section's bore given by hand in the description (the
    route that shares no code with dotted keys)."""
    data = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml").to_dict()
    data["rotors"][1]["shaft"][1]["inner_diameter"] = inner
    return rdm.Model.from_dict(data, "hollowed")


def test_a_study_sets_a_key_the_model_file_leaves_out(examples_dir):
    """``rotors.pump.shaft.1.inner_diameter`` is optional (a solid section): a study may set it
    (session 46: it was refused as 'no value there'); each variant equals the model with the
    bore written into its description, and a bore of 0 the file as it is."""
    model = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")
    assert "inner_diameter" not in model.to_dict()["rotors"][1]["shaft"][1]
    spec = parse_study({"seed": 1, "parameters": [{"key": "rotors.pump.shaft.1.inner_diameter",
                                                   "values": [0.0, 0.02]}],
                        "analyses": {"modes": {"speed_rpm": 0.0}}}, model=model)
    ds = rdm.study(model, spec).dataset
    np.testing.assert_array_equal(ds["modal_frequency_hz"].values[0], rdm.modal(model, 0.0).frequencies_hz)
    hollow = rdm.modal(_hollowed(examples_dir, 0.02), 0.0).frequencies_hz
    np.testing.assert_array_equal(ds["modal_frequency_hz"].values[1], hollow)
    assert not np.array_equal(hollow, rdm.modal(model, 0.0).frequencies_hz)
    assert model.with_values({"rotors.pump.shaft.1.inner_diameter": 0.02}).rotor("pump").mass == \
        _hollowed(examples_dir, 0.02).rotor("pump").mass
    assert "inner_diameter" not in model.to_dict()["rotors"][1]["shaft"][1]      # the base model is unchanged


@pytest.mark.parametrize("parameter, message", [
    ({"key": "rotors.pump.shaft.1.inner_diameter", "scale": [0.5, 1.0]},
     "the model file gives no 'inner_diameter' there, so there is no value to multiply"),
    ({"key": "rotors.pump.shaft.1.inner_diamter", "values": [0.0, 0.01]},
     r"the file leaves 'inner_diamter' out and the model does not take it at 0: .*did you mean 'inner_diameter'"),
    ({"key": "materials.steel.shear_modulus", "values": [7e10, 8e10]},
     "expected exactly one of shear_modulus"),
])
def test_a_key_the_file_leaves_out_is_refused_before_any_variant_where_it_cannot_be_set(examples_dir, parameter,
                                                                                         message):
    model = rdm.load_model(examples_dir / "flexible_pump_on_mounts.toml")
    with pytest.raises(StudyError, match=message):
        parse_study({"seed": 1, "parameters": [parameter], "analyses": {"modes": {"speed_rpm": 0.0}}}, model=model)
