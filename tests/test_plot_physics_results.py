"""Physics the figures draw, given by the results (the figures only read it).

An orbit over one period (``UnbalanceResult.orbit_path``), a shaft line's largest excursion
(``ShaftLine.excursion``, ``orbit_excursion``), a force's vector amplitude
(``unbalance.vector_amplitude``) and a Campbell sweep's instability (``CampbellResult.unstable``,
``instability_onsets``, ``settled``): checked against closed forms written out here, brute force
over the phase, and a hand-made sweep.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis.mode_shapes import orbit_excursion
from rotordyn_modal.analysis.unbalance import vector_amplitude

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_orbit_excursion_is_the_largest_distance_over_a_period():
    phi = np.linspace(0, 2 * np.pi, 20001)
    rng = np.random.default_rng(7)
    u = rng.normal(size=(2, 5)) + 1j * rng.normal(size=(2, 5))
    brute = np.hypot(*np.real(u[:, :, None] * np.exp(1j * phi))).max(axis=-1)
    assert orbit_excursion(u) == pytest.approx(brute, rel=1e-6)
    # circular (1, i): radius 1 at every phase; planar (3, 0): 3; (1, 1): a line at 45 deg, sqrt 2
    assert orbit_excursion(np.array([[1.0, 3.0, 1.0], [1j, 0.0, 1.0]])) == pytest.approx([1.0, 3.0, np.sqrt(2)],
                                                                                        rel=1e-15)


def test_vector_amplitude_is_the_root_sum_of_squared_component_amplitudes():
    components = np.array([[3.0 + 0j, 1j], [4j, 0.0], [0.0, -1.0]])
    assert vector_amplitude(components) == pytest.approx([5.0, np.sqrt(2)], rel=1e-15)


def test_orbit_path_is_the_real_part_of_the_plane_over_one_period():
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(1000, 6000, 6)), outputs=["probe-DE-x", "probe-DE-y"])
    path = result.orbit_path(0, 1, 4, points=9)
    plane = result.orbit_planes[0, 1, 4]
    assert path.shape == (2, 9)
    for k, phi in enumerate(np.linspace(0, 2 * np.pi, 9)):          # written out: Re(D) cos phi - Im(D) sin phi
        expected = plane.real * np.cos(phi) - plane.imag * np.sin(phi)
        assert path[:, k] == pytest.approx(expected, rel=1e-12, abs=1e-12 * np.abs(plane).max())
    # its largest radius is the ellipse's semi-major axis of the orbits table
    table = result.orbits()
    row = table[(table["source"] == result.sources[1])].iloc[4]
    assert np.hypot(*result.orbit_path(0, 1, 4, points=20001)).max() == pytest.approx(row["major"], rel=1e-6)


def test_shaft_line_excursion_reads_its_own_displacement():
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    modes = rdm.modal(model, rdm.rpm(10000))
    from rotordyn_modal.analysis.mode_shapes import shaft_lines

    for line in shaft_lines(modes, model, 1).lines:
        assert np.array_equal(line.excursion, orbit_excursion(line.displacement))
        assert np.array_equal(line.relative_excursion, orbit_excursion(line.relative))
        assert line.excursion.shape == line.position.shape


def _sweep(real_parts, imag=2 * np.pi * 10.0):
    from rotordyn_modal.analysis.campbell import CampbellResult
    from rotordyn_modal.analysis.critical_speeds import ExcitationSources, _critical_table

    real = np.asarray(real_parts, float)[:, None]
    n = len(real)
    lam = real + 1j * imag
    freq = np.abs(lam.imag) / (2 * np.pi) + 0 * real
    return CampbellResult(
        speeds=np.arange(n, dtype=float) * 10.0, eigenvalues=lam, frequencies_hz=freq,
        damping_ratios=-real / np.abs(lam), log_decrements=-2 * np.pi * real / lam.imag,
        whirl_ratios=np.ones((n, 1)), whirl=np.full((n, 1), "forward", object), shapes=np.zeros((n, 1, 2), complex),
        modes=np.array([1]), sources=ExcitationSources(("r",), np.array([1.0])),
        critical=_critical_table([], [], [], [], [], [], [], []), orders=(1.0,))


def test_instability_of_a_hand_made_sweep():
    # real parts -2, -1, +1, +3 at 0, 10, 20, 30 rad/s: unstable from the zero at 15 rad/s; a real part
    # of 1e-14 (round-off of an undamped 10 Hz root, |lam| = 62.8) is neither
    result = _sweep([-2.0, -1.0, 1.0, 3.0])
    assert result.unstable[:, 0].tolist() == [False, False, True, True]
    (speeds, freqs), = result.instability_onsets()
    assert speeds == pytest.approx([15.0], rel=1e-15) and freqs == pytest.approx([10.0], rel=1e-15)
    undamped = _sweep([1e-14, -1e-14, 1e-14])
    assert not undamped.unstable.any() and not len(undamped.instability_onsets()[0][0])
    assert np.all(undamped.settled("log_decrement") == 0) and np.all(undamped.settled("damping_ratio") == 0)
    assert result.settled("log_decrement")[0, 0] == pytest.approx(2 * np.pi * 2 / (2 * np.pi * 10), rel=1e-15)


def test_study_frequency_bands_are_percentiles_over_the_variants_that_succeeded():
    xr = pytest.importorskip("xarray")
    from rotordyn_modal.study.results import StudyResult

    # 5 variants (the last failed), 2 speeds, 2 modes; mode 2 no mode anywhere (0); variant 2's mode 1 no
    # mode at speed 1 (0): left out there
    f = np.zeros((5, 2, 2))
    f[:, 0, 0] = [1.0, 2.0, 3.0, 4.0, 99.0]
    f[:, 1, 0] = [10.0, 20.0, 0.0, 40.0, 99.0]
    ds = xr.Dataset({"frequency_hz": (("variant", "speed", "mode"), f),
                     "failed": (("variant",), np.array([0, 0, 0, 0, 1], bool))})
    low, median, high = StudyResult(ds).frequency_bands((0.0, 100.0))
    assert median[0].tolist() == [2.5, 20.0] and low[0].tolist() == [1.0, 10.0] and high[0].tolist() == [4.0, 40.0]
    assert np.isnan(median[1]).all() and low.shape == (2, 2)
    low, _, high = StudyResult(ds).frequency_bands((25.0, 75.0))       # linear interpolation between ranks
    assert low[0].tolist() == [1.75, 15.0] and high[0].tolist() == [3.25, 30.0]


def test_the_force_panel_reads_the_vector_amplitude_from_the_result():
    from rotordyn_modal.analysis.unbalance import UnbalanceResult

    components = np.array([[3.0 + 0j], [4j], [0.0]])
    assert UnbalanceResult.vector_amplitude(components) == pytest.approx([5.0], rel=1e-15)
