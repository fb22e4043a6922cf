"""stability(max_frequency=F), ``stability --max-frequency HZ``: the log decrements and the threshold
speed of the modes below a frequency only, each equal to the full model's (issue 28, item 4). Truth
from outside the code under test: scipy's eigenvalues of the full state matrix built from
``model.matrices(speed)`` at each speed, and the threshold found by Brent's method on their largest
real part (as tests/test_stability_lowest.py does for ``modes=N``)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
from test_stability_lowest import (SPEEDS, _cross_coupled_shaft, _roots, assert_the_threshold_is_the_full_models,
                                   without_full_solves)

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest
from rotordyn_modal.analysis import stability as stability_module
from rotordyn_modal.analysis.modal import OVERDAMPED_LIMIT
from rotordyn_modal.cli.main import main
from rotordyn_modal.cli.stability import _summary
from rotordyn_modal.errors import InputError

#: the test shaft's first pair, 73.7 Hz at rest, splits: the backward mode falls to 67 Hz, the
#: forward one rises to 79 Hz and loses stability at 7,292 rpm (77 Hz); the next pair lies above 200 Hz
#: below 12,000 rpm but for its backward mode at the last speed (200.7 Hz)
ABOVE_THE_FIRST_PAIR, BELOW_THE_SECOND = 200.0, 74.0


@pytest.fixture(scope="module")
def shaft():
    return _cross_coupled_shaft()


def _quiet(function, *args, **kwargs):
    with warnings.catch_warnings():     # the repeated roots at rest are solved whole, with a warning
        warnings.simplefilter("ignore", UserWarning)
        return function(*args, **kwargs)


def _below(roots, limit_hz):
    """The modes among ``roots`` (upper roots by frequency) of frequency at most ``limit_hz``."""
    zeta = -roots.real / np.abs(roots)
    return roots[(zeta <= OVERDAMPED_LIMIT) & (roots.imag <= 2 * np.pi * limit_hz)]


@pytest.fixture(scope="module")
def below(shaft):
    """stability(max_frequency=200 Hz) of the shaft, solved without any full eigen-solution of a trial speed."""
    return without_full_solves(_quiet, rdm.stability, shaft, SPEEDS, max_frequency=ABOVE_THE_FIRST_PAIR)


def test_the_roots_below_the_limit_are_the_full_models(shaft, below):
    assert shaft.dofs.n >= _lowest.DENSE_BELOW          # the reduced basis and Newton, not every root
    assert below.max_frequency_hz == ABOVE_THE_FIRST_PAIR and below.lowest is None
    for row, speed in zip(below.eigenvalues, SPEEDS):
        expected = _below(_roots(shaft, speed), ABOVE_THE_FIRST_PAIR)
        got = np.sort_complex(row[np.isfinite(row)] * -1j) * 1j            # by imaginary part
        assert len(got) == len(expected) >= 2
        assert np.max(np.abs(got - expected) / np.abs(expected)) < 1e-9
    table = below.to_dataframe()
    assert len(table) == np.isfinite(below.eigenvalues).sum() and table["frequency_hz"].max() <= ABOVE_THE_FIRST_PAIR


def test_the_threshold_below_the_limit_is_the_full_models(shaft, below):
    assert_the_threshold_is_the_full_models(shaft, below)
    assert _summary(below) == ("unstable from 7291.91 rpm (among the modes below 200 Hz; modes above 200 Hz and "
                               "real roots not checked)")


def test_a_mode_above_the_limit_that_loses_stability_is_not_reported_and_the_line_says_so(shaft):
    """Below 74 Hz only the backward mode of the first pair is judged past rest: the forward mode,
    above 74 Hz from the second speed on, loses stability (the full model's largest real part turns
    positive) but is not checked; the summary line says which modes were not."""
    result = _quiet(rdm.stability, shaft, SPEEDS, max_frequency=BELOW_THE_SECOND)
    full = np.array([_roots(shaft, speed).real.max() for speed in SPEEDS])
    assert full[-1] > 0                                     # the full model is unstable at speed
    forward = np.array([_roots(shaft, speed)[1] for speed in SPEEDS])
    assert np.all(forward[1:].imag > 2 * np.pi * BELOW_THE_SECOND)    # ... by a mode above the limit
    assert len(result.thresholds) == 0 and result.stable.all()
    assert np.isnan(result.eigenvalues[1:, 1]).all() and result.to_dataframe()["frequency_hz"].max() <= 74.0
    assert _summary(result).startswith("stable over the range for the modes below 74 Hz; modes above 74 Hz and real "
                                       "roots not checked; least damped: mode ")


def test_with_modes_the_lowest_of_those_below_the_limit(shaft):
    """modes=1 with the limit above the first pair: only the backward mode, the lowest, is judged
    (stable), although the forward one below the limit loses stability."""
    result = _quiet(rdm.stability, shaft, SPEEDS, modes=1, max_frequency=ABOVE_THE_FIRST_PAIR)
    reference = np.array([_roots(shaft, speed)[0] for speed in SPEEDS])
    assert result.eigenvalues.shape == (len(SPEEDS), 1) and result.lowest == 1
    assert np.max(np.abs(result.eigenvalues[:, 0] - reference) / np.abs(reference)) < 1e-9
    assert len(result.thresholds) == 0 and result.stable.all()
    assert _summary(result).startswith("stable over the range for the lowest mode below 200 Hz; modes above it or "
                                       "above 200 Hz and real roots not checked; least damped: mode 1 at ")


def test_no_mode_below_the_limit(shaft):
    result = _quiet(rdm.stability, shaft, SPEEDS[:3], max_frequency=10.0)
    assert result.eigenvalues.shape == (3, 0) and len(result.thresholds) == 0 and len(result.to_dataframe()) == 0
    assert _summary(result) == ("stability not checked: no mode below 10 Hz at any speed (modes above it and real "
                                "roots not checked)")
    result.plot()                                           # an empty figure, no error


@pytest.mark.parametrize("bad", [0, -5.0, float("nan"), float("inf"), "450", True, [100.0, 200.0]])
def test_max_frequency_must_be_one_frequency_above_zero(bad, examples_dir, monkeypatch):
    def refused(*args, **kwargs):
        raise AssertionError("the work began")

    monkeypatch.setattr(stability_module, "_stability_lowest", refused)
    monkeypatch.setattr(stability_module, "stability_map", refused)
    model = rdm.load_model(examples_dir / "unstable_cross_coupled.toml")
    with pytest.raises(InputError, match="max_frequency"):
        rdm.stability(model, [0.0, 10.0], max_frequency=bad)
    with pytest.raises(InputError, match="max_frequency"):
        rdm.stability(model, [0.0, 10.0], vary="stator.mass", scale=[1.0, 2.0], max_frequency=bad)


def test_a_map_below_the_limit_is_each_values_own(examples_dir):
    model = rdm.load_model(examples_dir / "unstable_cross_coupled.toml")
    speeds = np.linspace(0.0, 20000.0, 21) * np.pi / 30
    result = rdm.stability(model, speeds, vary="suspensions.bearing-A.damping", scale=[0.5, 2.0], max_frequency=50.0)
    for factor, each in zip([0.5, 2.0], result.results):
        alone = rdm.stability(model.scaled({"suspensions.bearing-A.damping": factor}), speeds, max_frequency=50.0)
        assert each.max_frequency_hz == 50.0
        assert np.array_equal(each.eigenvalues, alone.eigenvalues, equal_nan=True)
        assert np.array_equal(each.thresholds, alone.thresholds)


def test_command_line_max_frequency(examples_dir, capsys, tmp_path):
    path = str(examples_dir / "unstable_cross_coupled.toml")
    out = tmp_path / "s.csv"
    assert main(["stability", path, "--speeds", "0:20000:41", "--max-frequency", "50", "--out", str(out)]) == 0
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines[-1] == ("unstable from 10886.2 rpm (among the modes below 50 Hz; modes above 50 Hz and real roots "
                         "not checked)")
    assert pd.read_csv(out)["frequency_hz"].max() <= 50.0
    assert main(["stability", path, "--speeds", "0:20000:41", "--max-frequency", "50", "--lowest", "1"]) == 0
    assert capsys.readouterr().err.strip().splitlines()[-1].endswith(
        " (among the lowest mode below 50 Hz; modes above it or above 50 Hz and real roots not checked)")
    for bad in ["0", "-3", "nan", "inf", "fast"]:
        assert main(["stability", path, "--speeds", "0:20000:5", "--max-frequency", bad]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and err.startswith(f"rotordyn-modal stability: error: --max-frequency {bad!r}")
