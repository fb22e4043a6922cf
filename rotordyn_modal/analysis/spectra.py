"""FRFs from measured time records: H1, H2 and coherence from cross spectra (``scipy.signal.csd``).

With the force spectra ``F`` and response spectra ``X`` of every record (and of every Welch
segment), the averaged cross spectra are ``S_ff[i, j] = <conj(F_i) F_j>``,
``S_fx[i, o] = <conj(F_i) X_o>`` and ``S_xx[o] = <|X_o|^2>``, each from
``scipy.signal.csd`` (one-sided, density scaling; scaling cancels in the ratios). Then

* H1 (noise on the outputs averages out): ``H = (S_ff^-1 S_fx)^T``, for one input
  ``H = S_fx / S_ff``;
* H2 (noise on the input averages out), one input: ``H_o = S_xx[o] / S_xf[o]``;
* coherence: ordinary ``|S_fx|^2 / (S_ff S_xx)`` for one input, multiple coherence
  ``(H S_ff H^H)_oo / S_xx[o]`` for several.

Impact (hammer) records are checked before any spectrum: a force that rises again above
``double_hit_level`` of its peak after the first pulse has ended is a double hit, and a channel
that sits at its extreme value for several samples is overloaded (clipped); either refuses the
record with its number.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["TimeRecords", "estimate_frf", "check_impacts", "QUANTITY_OF_RESPONSE"]

#: response quantity of a time channel -> FRF quantity
QUANTITY_OF_RESPONSE = {"displacement": "receptance", "velocity": "mobility", "acceleration": "accelerance"}


@dataclass(frozen=True)
class TimeRecords:
    """Sampled time records of several channels (each record: one hit, one run).

    Attributes
    ----------
    signals : ndarray, shape (n_records, n_channels, n_samples)
        SI units: N for forces, m, m/s, m/s^2 for responses, Pa for pressures.
    sampling_rate_hz : float
    channels : tuple of str
    quantities : tuple of str
        Per channel: 'force', 'displacement', 'velocity', 'acceleration' or 'pressure' (a microphone,
        read but not used as an FRF's input or output).
    speed : float
        Reference rotor speed during the records [rad/s].
    """

    signals: np.ndarray
    sampling_rate_hz: float
    channels: tuple
    quantities: tuple
    speed: float = 0.0

    @property
    def times(self) -> np.ndarray:
        """Sample times [s], shape (n_samples,)."""
        return np.arange(self.signals.shape[-1]) / self.sampling_rate_hz

    def select(self, channels) -> np.ndarray:
        """Signals of some channels (names), shape (n_records, len(channels), n_samples)."""
        missing = [c for c in channels if c not in self.channels]
        if missing:
            raise InputError(f"channel(s) {', '.join(missing)} not in the records (channels: "
                             f"{', '.join(self.channels)})")
        return self.signals[:, [self.channels.index(c) for c in channels]]

    def to_dataframe(self, record: int = 0):
        """One record as a table: ``time_s`` and one column per channel (``pandas.DataFrame``)."""
        import pandas as pd

        table = pd.DataFrame(self.signals[record].T, columns=list(self.channels))
        table.insert(0, "time_s", self.times)
        return table

    def plot(self, record: int = 0, **kwargs):
        """Forces and responses of one record; see :func:`rotordyn_modal.plotting.plot_time_records`."""
        from ..plotting.measurement import plot_time_records

        return plot_time_records(self, record, **kwargs)


def check_impacts(records, inputs, double_hit_level: float = 0.1, clip_samples: int = 3) -> None:
    """Refuse double hits and overloaded (clipped) channels.

    Parameters
    ----------
    records : TimeRecords
    inputs : list of str
        Force channels (hammer).
    double_hit_level : float
        After the first pulse has fallen below this fraction of its peak, a force rising above
        it again is a second hit.
    clip_samples : int
        Consecutive samples at a channel's extreme value that count as an overload.

    Raises
    ------
    InputError
        Naming the record (from 1), the channel and the time.
    """
    forces = records.select(inputs)
    dt = 1.0 / records.sampling_rate_hz
    for r, record in enumerate(forces):
        for name, force in zip(inputs, record):
            second = _second_hit(force, double_hit_level)
            if second is not None:
                raise InputError(f"record {r + 1}, channel {name}: double hit (a second impact at "
                                 f"{second * dt:.4g} s, above {100 * double_hit_level:g} % of the first): "
                                 "leave this record out and hit again")
    for r, record in enumerate(records.signals):
        for name, signal in zip(records.channels, record):
            if _clipped(signal, clip_samples):
                raise InputError(f"record {r + 1}, channel {name}: overload ({clip_samples} or more samples "
                                 "at the extreme value): lower the gain or the hit and measure again")


def _second_hit(force, level):
    """Index where the force rises again above ``level`` of its peak after the first pulse, or None."""
    magnitude = np.abs(force)
    threshold = level * magnitude.max()
    above = magnitude > threshold
    first = int(np.argmax(above))
    ended = first + int(np.argmin(above[first:])) if not above[first:].all() else len(force)
    again = np.nonzero(above[ended:])[0]
    return None if not again.size else ended + int(again[0])


def _clipped(signal, samples):
    peak = np.abs(signal).max()
    if peak == 0:
        return False
    at_peak = np.abs(signal) >= peak * (1 - 1e-9)
    run = np.convolve(at_peak.astype(int), np.ones(samples, dtype=int), mode="valid")
    return bool(run.max(initial=0) >= samples)


def estimate_frf(records, inputs, outputs, estimator: str = "H1", segment_s: float | None = None,
                 overlap: float = 0.5, window: str = "boxcar", impacts: bool | None = None,
                 band_hz=None):
    """Estimate FRFs and coherence from time records.

    Parameters
    ----------
    records : TimeRecords
    inputs : list of str
        Force channels.
    outputs : list of str
        Response channels (one quantity: all accelerations, velocities or displacements).
    estimator : {'H1', 'H2'}
        H2 needs a single input.
    segment_s : float, optional
        Welch segment length [s] (default: the whole record, as for impacts).
    overlap : float
        Segment overlap fraction.
    window : str
        ``scipy.signal`` window of the segments ('boxcar' for impacts that decay within the
        record, 'hann' for random excitation).
    impacts : bool, optional
        Check for double hits and overloads first (default: when ``segment_s`` is None).
    band_hz : (float, float), optional
        Keep only these frequency lines [Hz].

    Returns
    -------
    FRFResult
        ``H`` (n_outputs, n_inputs, n_freq), ``coherence`` of the same shape, engine 'H1'/'H2'.
    """
    from scipy.signal import csd

    from .frf import FRFResult

    records.select(list(inputs) + list(outputs))          # every name known
    quantity = _response_quantity(records, outputs)
    if [q for c, q in zip(records.channels, records.quantities) if c in inputs and q != "force"]:
        raise InputError(f"inputs {', '.join(inputs)}: every input must be a force channel")
    if estimator not in ("H1", "H2") or (estimator == "H2" and len(inputs) != 1):
        raise InputError(f"estimator {estimator!r}: expected 'H1', or 'H2' with a single input")
    if impacts or (impacts is None and segment_s is None):
        check_impacts(records, inputs)
    fs = records.sampling_rate_hz
    n = records.signals.shape[-1] if segment_s is None else int(round(segment_s * fs))
    if not 8 <= n <= records.signals.shape[-1]:
        raise InputError(f"segment of {n} samples: expected from 8 to the record length "
                         f"{records.signals.shape[-1]}")
    # random excitation: segments lose their mean (as scipy's default); an impact record is kept whole
    kwargs = dict(fs=fs, window=window, nperseg=n, noverlap=int(overlap * n) if segment_s else 0,
                  detrend="constant" if segment_s else False, axis=-1)
    f_sig, x_sig = records.select(inputs), records.select(outputs)
    _check_forces_recorded(f_sig, inputs)
    freqs, S_ff = csd(f_sig[:, :, None, :], f_sig[:, None, :, :], **kwargs)
    _, S_fx = csd(f_sig[:, :, None, :], x_sig[:, None, :, :], **kwargs)
    _, S_xx = csd(x_sig, x_sig, **kwargs)
    S_ff, S_fx, S_xx = S_ff.mean(axis=0), S_fx.mean(axis=0), S_xx.real.mean(axis=0)
    keep = freqs > 0 if band_hz is None else (freqs >= band_hz[0]) & (freqs <= band_hz[1])
    keep = _forced_lines(S_ff, freqs, keep, inputs)
    S_ff, S_fx, S_xx, freqs = S_ff[..., keep], S_fx[..., keep], S_xx[..., keep], freqs[keep]
    H, coherence = _h1(S_ff, S_fx, S_xx) if estimator == "H1" else _h2(S_ff, S_fx, S_xx)
    return FRFResult(H=H, frequencies_hz=freqs, speed=records.speed, inputs=tuple(inputs),
                     outputs=tuple(outputs), quantity=quantity, engine=estimator, coherence=coherence)


def _check_forces_recorded(f_sig, inputs) -> None:
    """Refuse an input channel that is 0 in every sample of every record (a hammer or shaker
    channel that recorded nothing): no force to divide by (was numpy's "Singular matrix").

    ``f_sig``: the inputs' signals, shape (records, inputs, samples)."""
    silent = [name for k, name in enumerate(inputs) if not np.any(f_sig[:, k, :])]
    if silent:
        raise InputError(f"input {', '.join(silent)}: 0 N in every sample of every record: expected a recorded "
                         "force to estimate FRFs from (a channel that did not record, or the wrong channel?)")


def _forced_lines(S_ff, freqs, keep, inputs):
    """``keep`` without the frequency lines where the inputs' cross-spectral matrix is singular
    (no force there, as a sampled symmetric hit at the Nyquist line; the FRF is undefined; was
    numpy's "Singular matrix"), said in a warning; refused when no line is left (two inputs
    recording one force, the same channel twice).

    ``S_ff``: shape (inputs, inputs, lines); ``freqs``, ``keep``: shape (lines,)."""
    import warnings

    from ..errors import ModelWarning

    singular = np.linalg.matrix_rank(np.moveaxis(S_ff, -1, 0), hermitian=True) < S_ff.shape[0]
    if keep.any() and singular[keep].all():
        raise InputError(f"inputs {', '.join(inputs)}: their cross-spectral matrix is singular at every "
                         "frequency line (two inputs recording one force, or one channel given twice): "
                         "expected independent forces, or estimate each input's FRFs from the records of its "
                         "own excitation")
    dropped = keep & singular
    if dropped.any():
        warnings.warn(f"estimate_frf: no FRF at {int(dropped.sum())} frequency line(s) where the inputs "
                      f"{', '.join(inputs)} carry no force (a singular cross-spectral matrix): "
                      f"{', '.join(f'{f:g}' for f in freqs[dropped][:5])}{' ...' if dropped.sum() > 5 else ''} Hz, "
                      "left out", ModelWarning, stacklevel=3)
    return keep & ~singular


def _response_quantity(records, outputs):
    kinds = {q for c, q in zip(records.channels, records.quantities) if c in outputs}
    if len(kinds) != 1 or not kinds <= set(QUANTITY_OF_RESPONSE):
        raise InputError(f"outputs {', '.join(outputs)}: expected response channels of one quantity "
                         f"(displacement, velocity or acceleration), found {sorted(kinds)}")
    return QUANTITY_OF_RESPONSE[kinds.pop()]


def _h1(S_ff, S_fx, S_xx):
    """H1 and (multiple) coherence; S_ff (i, j, f), S_fx (i, o, f), S_xx (o, f)."""
    Sff = np.moveaxis(S_ff, -1, 0)                         # (f, i, j)
    Sfx = np.moveaxis(S_fx, -1, 0)                         # (f, i, o)
    Ht = np.linalg.solve(Sff, Sfx)                         # (f, i, o) = H^T
    explained = np.einsum("fio,fij,fjo->fo", Ht.conj(), Sff, Ht).real
    H = np.moveaxis(Ht, 0, -1).transpose(1, 0, 2)          # (o, i, f)
    coherence = np.clip(_ratio(explained.T, S_xx), 0.0, 1.0)   # (o, f)
    return H, np.repeat(coherence[:, None, :], H.shape[1], axis=1)


def _h2(S_ff, S_fx, S_xx):
    """H2 = S_xx / S_xf for one input; ordinary coherence."""
    S_xf = S_fx[0].conj()                                  # (o, f)
    H = (S_xx / S_xf)[:, None, :]
    coherence = _ratio(np.abs(S_fx[0]) ** 2, S_ff[0, 0].real[None, :] * S_xx)
    return H, np.clip(coherence, 0.0, 1.0)[:, None, :]


def _ratio(numerator, denominator):
    """numerator / denominator, 0 where the denominator is 0 (a channel without power has no coherence)."""
    out = np.zeros(np.broadcast_shapes(np.shape(numerator), np.shape(denominator)))
    return np.divide(numerator, denominator, out=out, where=denominator > 0)
