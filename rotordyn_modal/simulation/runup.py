"""Run-up analyses of a simulated signal: order tracking and waterfall (spectrum vs speed)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["OrderTrack", "Waterfall", "order_track", "waterfall"]


@dataclass
class OrderTrack:
    """Amplitude and phase of one order of a rotor in a sensor's signal, against speed.

    Attributes
    ----------
    speeds : ndarray, shape (K,)
        Reference rotor's mean speed over each window [rad/s].
    amplitude : ndarray, shape (K,)
        Amplitude of the order, 0-peak [m] (the signal's units).
    phase_deg : ndarray, shape (K,)
        Phase of the order relative to the rotor's angle [deg] (signal ~ A cos(k phi + phase)).
    sensor, rotor : str
    order : float
    """

    speeds: np.ndarray
    amplitude: np.ndarray
    phase_deg: np.ndarray
    sensor: str
    rotor: str
    order: float

    def to_dataframe(self):
        import pandas as pd

        return pd.DataFrame({"speed_rpm": self.speeds * 30 / np.pi, "sensor": self.sensor, "rotor": self.rotor,
                             "order": self.order, "amplitude": self.amplitude, "phase_deg": self.phase_deg})


@dataclass
class Waterfall:
    """Amplitude spectrum of a sensor's signal over consecutive segments of a run-up.

    Attributes
    ----------
    speeds : ndarray, shape (K,)
        Reference rotor's mean speed over each segment [rad/s].
    frequencies_hz : ndarray, shape (F,) [Hz]
    amplitude : ndarray, shape (K, F)
        Amplitude spectrum (Hann window, amplitude-corrected), 0-peak [m] (the signal's units).
    sensor : str
    """

    speeds: np.ndarray
    frequencies_hz: np.ndarray
    amplitude: np.ndarray
    sensor: str


def order_track(result, sensor, order=1.0, rotor=None, revolutions=4) -> OrderTrack:
    """Order tracking by demodulation with the rotor's own angle.

    Over consecutive windows of ``revolutions`` turns of the rotor (counted as travelled, so a
    run-down through zero speed works), the complex amplitude
    ``c = 2 <s(t) exp(-i k phi(t))>`` (time average) gives ``s ~ |c| cos(k phi + arg c)``.

    Parameters
    ----------
    result : SimulationResult
    sensor : str
    order : float
        Multiple ``k`` of the rotor's angle.
    rotor : str, optional
        Rotor whose angle is tracked (default: the reference rotor, the first with ratio 1).
    revolutions : int
        Turns per window.

    Returns
    -------
    OrderTrack
    """
    signal = result.sensor(sensor)
    index = _rotor_index(result, rotor)
    angle = result.rotor_angles[:, index]
    turns = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(angle)))]) / (2 * np.pi)  # travelled, any direction
    edges = np.arange(0.0, turns[-1] + 1e-12, revolutions)
    speeds, values = [], []
    for start, stop in zip(edges[:-1], edges[1:]):
        window = (turns >= start) & (turns <= stop)
        if window.sum() < 8:
            continue
        t = result.time[window]
        demodulated = signal[window] * np.exp(-1j * order * angle[window])
        span = t[-1] - t[0]
        values.append(2 * np.trapezoid(demodulated, t) / span)
        speeds.append(np.trapezoid(result.drive_speed[window], t) / span)
    values = np.array(values, dtype=complex)
    return OrderTrack(speeds=np.array(speeds), amplitude=np.abs(values), phase_deg=np.degrees(np.angle(values)),
                      sensor=sensor, rotor=result.rotor_names[index], order=float(order))


def waterfall(result, sensor, segments=60) -> Waterfall:
    """Spectra of ``segments`` Hann-windowed pieces of a sensor's signal, 75 % overlapping.

    Each piece is ``4 / (segments + 3)`` of the record long, so the frequency resolution is
    ``(segments + 3) / (4 duration)`` [Hz].

    Returns
    -------
    Waterfall
    """
    signal = result.sensor(sensor)
    segments = int(segments)
    count = 4 * len(signal) // (segments + 3)
    if count < 16:
        raise InputError(f"waterfall: {len(signal)} samples are too few for {segments} segments "
                         "(give more samples or fewer segments)")
    hop = max(1, count // 4)
    step = result.time[1] - result.time[0]
    window = np.hanning(count)
    spectra, speeds = [], []
    for start in range(0, len(signal) - count + 1, hop):
        piece = signal[start:start + count]
        spectra.append(2 * np.abs(np.fft.rfft((piece - piece.mean()) * window)) / window.sum())
        speeds.append(result.drive_speed[start:start + count].mean())
    return Waterfall(speeds=np.array(speeds), frequencies_hz=np.fft.rfftfreq(count, step),
                     amplitude=np.array(spectra), sensor=sensor)


def _rotor_index(result, rotor):
    if rotor is None:
        ones = np.nonzero(np.isclose(result.speed_ratios, 1.0))[0]
        return int(ones[0]) if len(ones) else 0
    if rotor not in result.rotor_names:
        raise InputError(f"unknown rotor {rotor!r}: the model's rotors are {', '.join(result.rotor_names)}")
    return result.rotor_names.index(rotor)
