"""H1/H2 and coherence from time records, against discrete systems with known transfer functions
and a spectral computation written out with numpy FFTs; double hits and overloads refused."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal as sig

from rotordyn_modal.analysis.spectra import TimeRecords, estimate_frf
from rotordyn_modal.errors import InputError
from rotordyn_modal.plotting.measurement import plot_coherence, plot_time_records

FS = 512.0
#: a lightly damped discrete resonance (poles at 40 Hz, radius 0.995) and a second-order FIR
B, A = [0.02, 0.01], [1.0, -2 * 0.995 * np.cos(2 * np.pi * 40 / FS), 0.995 ** 2]
FIR = [0.5, -0.2, 0.1]


def _hammer(n=4096, delay=20, width=6, hits=3):
    """Half-sine force pulses; accelerations through the two discrete systems (exact)."""
    pulse = np.zeros(n)
    pulse[delay:delay + width] = 100.0 * np.sin(np.pi * np.arange(width) / width)
    force = np.stack([pulse * (1 + 0.1 * h) for h in range(hits)])
    acc = np.stack([[sig.lfilter(B, A, f), sig.lfilter(FIR, [1.0], f)] for f in force])
    signals = np.concatenate([force[:, None, :], acc], axis=1)
    return TimeRecords(signals, FS, ("hammer", "a1", "a2"), ("force", "acceleration", "acceleration"))


def test_impact_h1_equals_the_transfer_functions():
    records = _hammer()
    # within the hammer's band: a 6-sample half-sine has its first spectral zero above 120 Hz
    result = estimate_frf(records, ["hammer"], ["a1", "a2"], band_hz=(0.1, 100.0))
    _, h1 = sig.freqz(B, A, worN=result.frequencies_hz, fs=FS)
    _, h2 = sig.freqz(FIR, [1.0], worN=result.frequencies_hz, fs=FS)
    assert result.quantity == "accelerance" and result.engine == "H1"
    # the resonance rings down to 0.995^4076 ~ 1e-9 within the record: no leakage to speak of
    np.testing.assert_allclose(result.H[0, 0], h1, rtol=1e-6)
    np.testing.assert_allclose(result.H[1, 0], h2, rtol=1e-12)
    np.testing.assert_allclose(result.coherence, 1.0, atol=1e-9)
    h2_estimate = estimate_frf(records, ["hammer"], ["a1", "a2"], estimator="H2", band_hz=(0.1, 100.0))
    np.testing.assert_allclose(h2_estimate.H, result.H, rtol=1e-9)
    assert plot_time_records(records).axes[-1].get_xlabel() == "Time [s]"
    # one record as a table and a figure: the record asked for, forces on top, responses below
    table = records.to_dataframe(record=2)
    assert list(table.columns) == ["time_s", "hammer", "a1", "a2"]
    np.testing.assert_array_equal(table["time_s"], np.arange(records.signals.shape[-1]) / FS)
    np.testing.assert_array_equal(table[["hammer", "a1", "a2"]].to_numpy().T, records.signals[2])
    top, bottom = records.plot(record=2).axes
    assert [line.get_label() for line in top.get_lines()] == ["hammer"]
    assert [line.get_label() for line in bottom.get_lines()] == ["a1", "a2"]
    np.testing.assert_array_equal(top.get_lines()[0].get_ydata(), records.signals[2, 0])
    np.testing.assert_array_equal(bottom.get_lines()[1].get_ydata(), records.signals[2, 2])
    assert top.get_title() == f"Record 3 of 3 ({FS:g} Hz sampling)" and top.get_ylabel().startswith("force [")
    assert plot_coherence(result).axes[0].get_ylabel() == "Coherence [-]"


def test_random_mimo_h1_matches_numpy_spectra():
    """Two random inputs, three outputs with noise: H1 = (S_ff^-1 S_fx)^T from Welch segments
    written out here with numpy (Hann window, half overlap, segment means removed)."""
    rng = np.random.default_rng(1)
    f = rng.normal(size=(2, 2, 2048))
    taps = rng.normal(size=(3, 2, 12))
    x = np.stack([[sum(sig.lfilter(taps[o, i], 1, f[r, i]) for i in range(2)) for o in range(3)] for r in range(2)])
    x += 0.2 * rng.normal(size=x.shape)
    records = TimeRecords(np.concatenate([f, x], axis=1), FS, ("f1", "f2", "x1", "x2", "x3"),
                          ("force",) * 2 + ("velocity",) * 3)
    result = estimate_frf(records, ["f1", "f2"], ["x1", "x2", "x3"], segment_s=256 / FS, window="hann")
    window = sig.get_window("hann", 256)

    def spectra(s):
        segments = np.lib.stride_tricks.sliding_window_view(s, 256, axis=-1)[..., ::128, :]
        return np.fft.rfft((segments - segments.mean(axis=-1, keepdims=True)) * window, axis=-1)

    F, X = spectra(f), spectra(x)
    S_ff = np.einsum("risf,rjsf->fij", F.conj(), F)
    S_fx = np.einsum("risf,rosf->fio", F.conj(), X)
    H = np.linalg.solve(S_ff, S_fx).transpose(2, 1, 0)[..., 1:]
    assert result.quantity == "mobility"
    np.testing.assert_allclose(result.H, H, rtol=1e-10, atol=1e-12 * np.abs(H).max())
    S_xx = np.einsum("rosf,rosf->of", X.conj(), X).real[:, 1:]
    explained = np.einsum("oif,fij,ojf->of", H.conj(), S_ff[1:], H).real
    np.testing.assert_allclose(result.coherence[:, 0], explained / S_xx, rtol=1e-9)
    assert np.all((result.coherence > 0) & (result.coherence < 1))


def test_h1_is_the_coherence_times_h2_with_one_noisy_input():
    """One random force, a response with noise: the estimators obey H1 = g2 H2 with g2 the
    ordinary coherence |S_fx|^2 / (S_ff S_xx), which both report (Bendat & Piersol)."""
    rng = np.random.default_rng(3)
    f = rng.normal(size=(2, 1, 2048))
    x = np.stack([[sig.lfilter(FIR, [1.0], f[r, 0])] for r in range(2)]) + 0.3 * rng.normal(size=(2, 1, 2048))
    records = TimeRecords(np.concatenate([f, x], axis=1), FS, ("f", "x"), ("force", "acceleration"))
    kwargs = dict(segment_s=256 / FS, window="hann")
    h1 = estimate_frf(records, ["f"], ["x"], **kwargs)
    h2 = estimate_frf(records, ["f"], ["x"], estimator="H2", **kwargs)
    np.testing.assert_allclose(h2.coherence, h1.coherence, rtol=1e-12)
    np.testing.assert_allclose(h1.H, h1.coherence * h2.H, rtol=1e-12)
    assert 0.2 < h1.coherence.min() and h1.coherence.max() < 1.0       # the noise shows


def test_double_hit_refused_with_its_record_and_time():
    records = _hammer()
    signals = records.signals.copy()
    signals[1, 0, 300:306] = 40.0 * np.sin(np.pi * np.arange(6) / 6)       # a bounce 0.55 s later
    bounced = TimeRecords(signals, FS, records.channels, records.quantities)
    with pytest.raises(InputError, match=r"record 2, channel hammer: double hit \(a second impact at 0.58"):
        estimate_frf(bounced, ["hammer"], ["a1"])


def test_overload_refused():
    records = _hammer()
    signals = records.signals.copy()
    signals[0, 1] = np.clip(signals[0, 1], -0.5 * np.abs(signals[0, 1]).max(), 0.5 * np.abs(signals[0, 1]).max())
    with pytest.raises(InputError, match="record 1, channel a1: overload"):
        estimate_frf(TimeRecords(signals, FS, records.channels, records.quantities), ["hammer"], ["a1"])


@pytest.mark.parametrize("kwargs,message", [
    ({"inputs": ["a1"], "outputs": ["a2"]}, "every input must be a force channel"),
    ({"inputs": ["hammer"], "outputs": ["hammer"]}, "expected response channels of one quantity"),
    ({"inputs": ["hammer"], "outputs": ["a1"], "estimator": "H3"}, "estimator 'H3'"),
    ({"inputs": ["hammer"], "outputs": ["a9"]}, "channel(s) a9 not in the records"),
    ({"inputs": ["hammer"], "outputs": ["a1"], "segment_s": 100.0}, "expected from 8 to the record length"),
])
def test_bad_requests_refused(kwargs, message):
    with pytest.raises(InputError) as info:
        estimate_frf(_hammer(), **kwargs)
    assert message in str(info.value)
