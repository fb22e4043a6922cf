"""stability(modes=N), ``stability --lowest N``: the log decrements and the threshold speed of the N
lowest modes only, each equal to the full model's (issue 28, item 4). Truth from outside the code
under test: scipy's eigenvalues of the full state matrix built here from ``model.matrices(speed)``
at each speed, and the threshold found by Brent's method on their largest real part."""

from __future__ import annotations

import tomllib
import warnings

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _work
from rotordyn_modal.analysis._batches import one_blas_thread
from rotordyn_modal.analysis import stability as stability_module
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.cli.main import main
from rotordyn_modal.errors import InputError

STEEL = {"name": "steel", "density": 7800.0, "young_modulus": 2.1e11, "poisson_ratio": 0.3}

#: the test rotor's speeds [rad/s]: it loses stability near 7,292 rpm, inside the 14th interval
SPEEDS = np.linspace(0.0, 12000.0, 25) * np.pi / 30


def _cross_coupled_shaft():
    """A flexible steel shaft (1 m, 50 mm, eleven nodes: 44 coordinates) with a 15 kg wheel on
    two damped bearings, grounded, whose cross-coupled stiffness grows with speed (as a seal's or
    an oil film's): its first forward mode loses stability where the cross-coupling beats the
    bearings' damping."""
    k, c, q = 2e7, 1.5e3, 1.2e6

    def bearing(name, x):
        return {"name": name, "rotor": "shaft", "axial_position": x, "speeds_rpm": [0.0, 12000.0],
                "stiffness": [[[k, 0.0], [0.0, k]], [[k, q], [-q, 1.2 * k]]], "damping": [[c, c], [c, c]]}

    return rdm.Model.from_dict({
        "name": "cross-coupled shaft", "spin_axis": [1.0, 0.0, 0.0], "materials": [STEEL],
        "rotors": [{"name": "shaft", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}],
                    "disks": [{"name": "wheel", "axial_position": 0.7, "mass": 15.0, "polar_inertia": 0.3,
                               "diametral_inertia": 0.16}]}],
        "bearings": [bearing("A", 0.05), bearing("B", 0.95)]})


@pytest.fixture(scope="module")
def shaft():
    return _cross_coupled_shaft()


def _roots(model, speed):
    """Every upper root of the full state matrix at ``speed`` [rad/s], by frequency."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    with one_blas_thread(A.nbytes * 9):     # BLAS's own threads only wait for a core on a shared machine
        roots = scipy.linalg.eigvals(A)
    roots = roots[roots.imag > 0]
    return roots[np.argsort(roots.imag)]


def _by_frequency(values):
    return np.take_along_axis(values, np.argsort(values.imag, axis=1), axis=1)


def without_full_solves(function, *args, **kwargs):
    """``function(*args, **kwargs)`` with stability's routes that solve every root of a trial
    speed refused (an AssertionError if one is taken)."""
    patch = pytest.MonkeyPatch()

    def refused(*args, **kwargs):
        raise AssertionError("every root of a trial speed was solved")

    patch.setattr(stability_module, "_largest_real_part", refused)
    patch.setattr(stability_module, "modal", refused)
    try:
        return function(*args, **kwargs)
    finally:
        patch.undo()


@pytest.fixture(scope="module")
def lowest(shaft):
    """stability(modes=6) of the shaft, solved without any full eigen-solution of a trial speed."""
    with warnings.catch_warnings():     # the repeated roots at rest are solved whole, with a warning
        warnings.simplefilter("ignore", UserWarning)
        return without_full_solves(rdm.stability, shaft, SPEEDS, modes=6)


def test_the_lowest_modes_log_decrements_are_the_full_models(shaft, lowest):
    assert shaft.dofs.n >= _lowest.DENSE_BELOW          # the reduced basis and Newton, not every root
    assert lowest.eigenvalues.shape == (len(SPEEDS), 6) and lowest.lowest == 6
    reference = np.array([_roots(shaft, speed)[:6] for speed in SPEEDS])
    got = _by_frequency(lowest.eigenvalues)
    assert np.max(np.abs(got - reference) / np.abs(reference)) < 1e-9
    log_dec = -2 * np.pi * reference.real / reference.imag
    by_frequency = np.take_along_axis(lowest.log_decrements, np.argsort(lowest.eigenvalues.imag, axis=1), axis=1)
    # relative where the log decrement is clear of zero; where it crosses zero (the mode that loses
    # stability), as the roots' 1e-9 relative makes it: 2 pi 1e-9 |lam| / Im lam (the reference's
    # own real parts are only good to eps times the state matrix's norm there)
    clear = np.abs(log_dec) >= 0.01
    assert clear.sum() > 0.8 * clear.size
    assert np.max(np.abs(by_frequency - log_dec)[clear] / np.abs(log_dec[clear])) < 1e-9
    assert np.max(np.abs(by_frequency - log_dec) / (2 * np.pi * np.abs(reference) / reference.imag)) < 1e-9


def assert_the_threshold_is_the_full_models(shaft, result):
    """``result``'s one threshold equals Brent's method on the largest real part of scipy's
    eigenvalues of the full state matrix (one onset, unstable after it) to 1e-9, and its
    crossing root's frequency, ``modes`` number and whirl are the full model's there."""
    largest = np.array([_roots(shaft, speed).real.max() for speed in SPEEDS])
    k = int(np.nonzero((largest[:-1] < 0) & (largest[1:] > 0))[0][0])
    assert np.all(largest[:k + 1] < 0) and np.all(largest[k + 1:] > 0)     # one onset, stays unstable
    threshold = brentq(lambda s: _roots(shaft, s).real.max(), SPEEDS[k], SPEEDS[k + 1], xtol=1e-12, rtol=1e-15)
    assert len(result.thresholds) == 1 and result.threshold_onsets[0]
    assert abs(result.threshold_speed - threshold) <= 1e-9 * threshold
    # the root that crosses: its frequency and its number among the modes at the threshold
    roots = _roots(shaft, result.thresholds[0])
    crossing = int(np.argmin(np.abs(roots.real)))
    assert abs(result.threshold_frequencies_hz[0] - roots[crossing].imag / (2 * np.pi)) <= 1e-9 * roots[crossing].imag
    assert result.threshold_modes_at_speed[0] == int(is_oscillating(roots[:crossing + 1]).sum())
    assert result.threshold_whirl[0] == "forward"


def test_the_threshold_of_the_lowest_modes_is_the_full_models(shaft, lowest):
    assert_the_threshold_is_the_full_models(shaft, lowest)


def test_modes_above_the_lowest_are_not_checked_and_the_summary_says_so(shaft, lowest):
    from rotordyn_modal.cli.stability import _summary

    # the mode that loses stability is the second lowest at rest: the lowest alone stays stable
    with warnings.catch_warnings():     # the repeated roots at rest are solved whole, with a warning
        warnings.simplefilter("ignore", UserWarning)
        only_first = rdm.stability(shaft, SPEEDS, modes=1)
    assert len(only_first.thresholds) == 0 and only_first.stable.all()
    line = _summary(only_first)
    assert line.startswith("stable over the range for the lowest mode; modes above it and real roots not checked; "
                           "least damped: mode 1 at ")
    assert "unstable from" in _summary(lowest) and "(among the 6 lowest modes; modes above them and real roots " \
        "not checked)" in _summary(lowest)


def _example(examples_dir):
    return rdm.Model.from_dict(tomllib.loads((examples_dir / "unstable_cross_coupled.toml").read_text()))


@pytest.mark.parametrize("bad", [0, -2, 2.5, True, "3"])
def test_modes_must_be_a_whole_number(bad, examples_dir, monkeypatch):
    def refused(*args, **kwargs):
        raise AssertionError("the work began")

    monkeypatch.setattr(stability_module, "stability_map", refused)
    monkeypatch.setattr(stability_module, "_stability_lowest", refused)
    model = _example(examples_dir)
    with pytest.raises(InputError, match="modes"):
        rdm.stability(model, [0.0, 10.0], modes=bad)
    with pytest.raises(InputError, match="modes"):
        rdm.stability(model, [0.0, 10.0], vary="stator.mass", scale=[1.0, 2.0], modes=bad)


def test_a_map_of_the_lowest_modes_is_each_values_own(examples_dir):
    model = _example(examples_dir)
    speeds = np.linspace(0.0, 20000.0, 21) * np.pi / 30
    result = rdm.stability(model, speeds, vary="suspensions.bearing-A.damping", scale=[0.5, 2.0], modes=3)
    for factor, each in zip([0.5, 2.0], result.results):
        alone = rdm.stability(model.scaled({"suspensions.bearing-A.damping": factor}), speeds, modes=3)
        assert each.lowest == 3 and np.array_equal(each.eigenvalues, alone.eigenvalues, equal_nan=True)
        assert np.array_equal(each.thresholds, alone.thresholds)


def test_command_line_lowest(examples_dir, capsys, monkeypatch, tmp_path):
    path = str(examples_dir / "unstable_cross_coupled.toml")
    out = tmp_path / "s.csv"
    # refused as long work without --lowest, run with it (the long-work estimate is of every root)
    monkeypatch.setattr(_work, "_timed_eig", lambda size: 1e-3)
    monkeypatch.setenv(_work.ENVIRONMENT, "1e-6")
    assert main(["stability", path, "--speeds", "0:20000:41"]) == 2
    assert "--lowest N" in capsys.readouterr().err
    assert main(["stability", path, "--speeds", "0:20000:41", "--lowest", "3", "--out", str(out)]) == 0
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines[-1] == ("unstable from 10886.2 rpm (among the 3 lowest modes; modes above them and real roots "
                         "not checked)")
    import pandas as pd

    table = pd.read_csv(out)
    # the 3 lowest at each speed; a backward mode falling below the third (at 2,500 rpm) has a
    # column of its own, not the one of the mode it pushes out (lowcol27q)
    assert set(table.groupby("speed_rpm").size()) == {3}
    assert set(table["mode"]) == {1, 2, 3, 4}
    for bad in ["0", "x", "2.5", "-1"]:
        assert main(["stability", path, "--speeds", "0:20000:5", "--lowest", bad]) == 2
        assert capsys.readouterr().err.strip() == (f"rotordyn-modal stability: error: --lowest '{bad}': expected a "
                                                   "whole number of modes >= 1")
