"""Run-up analyses of a simulated signal: order tracking and waterfall (spectrum vs speed)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["OrderTrack", "SteadyOrder", "Waterfall", "leakage_floor", "order_track", "passage_spans",
           "quasi_static_deviation", "shade_causes", "steady_orders", "track_speeds", "unsettled", "unsettled_spans", "waterfall",
           "window_turns"]


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
        Phase of the order relative to the angle the rotor has turned through [deg] (signal ~
        A cos(k |phi| + phase), ``|phi|`` growing whichever way the rotor turns): the phase
        ``unbalance_response`` gives, ``A cos(w t + phase)`` with ``w = |k r Omega|``, also for a
        rotor turning against the reference (a geared fan at ratio -0.4); NaN where the phase is
        unknown: the amplitude is below twice ``leakage_floor``.
    sensor, rotor : str
    order : float
    leakage_floor : ndarray, shape (K,), optional
        The most the same order of the other rotors can add to this order's complex amplitude
        through the window [m] (:func:`leakage_floor`); zeros with one rotor, None for a track
        built by hand.
    unsettled : ndarray of bool, shape (K,), optional
        Where the track is not the order's alone (:func:`unsettled`): the fit over windows
        shifted by half a window, taken at this window's middle, differs from this window's by
        more than :data:`UNSETTLED` of its amplitude. There other content that changes within a
        window (a casing ringing on its mounts at nearly the order's frequency, the start's
        transient, a response growing through a resonance faster than a window) is not told apart
        from the order, and the track need not follow the steady unbalance response. None for a
        track built by hand.
    """

    speeds: np.ndarray
    amplitude: np.ndarray
    phase_deg: np.ndarray
    sensor: str
    rotor: str
    order: float
    leakage_floor: np.ndarray | None = None
    unsettled: np.ndarray | None = None

    @property
    def phase_known(self) -> np.ndarray:
        """Where the phase is known, shape (K,) bool: not NaN."""
        return np.isfinite(self.phase_deg)

    @property
    def unwrapped_phase_deg(self) -> np.ndarray:
        """``phase_deg`` unwrapped [deg], shape (K,): over the known (finite) samples, taken in
        order, each step between neighbours brought within 180 deg by whole turns (the first
        known sample kept); NaN where the phase is unknown (a line drawn through it breaks
        there)."""
        phase = np.asarray(self.phase_deg, dtype=float)
        out = np.full(phase.shape, np.nan)
        known = self.phase_known
        out[known] = np.degrees(np.unwrap(np.radians(phase[known])))
        return out

    def to_dataframe(self):
        import pandas as pd

        columns = {"speed_rpm": self.speeds * 30 / np.pi, "sensor": self.sensor, "rotor": self.rotor,
                   "order": self.order, "amplitude": self.amplitude, "phase_deg": self.phase_deg}
        if self.leakage_floor is not None:
            columns["leakage_floor"] = self.leakage_floor
        if self.unsettled is not None:
            columns["unsettled"] = self.unsettled
        return pd.DataFrame(columns)


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


def order_track(result, sensor, order=1.0, rotor=None, revolutions=None) -> OrderTrack:
    """Order tracking by a least-squares fit against the rotor's own angle.

    Over consecutive windows of ``revolutions`` turns of the rotor (counted as travelled, so a
    run-down through zero speed works), the complex amplitude ``c`` of
    ``s ~ |c| cos(k phi + arg c)`` is fitted by least squares (:func:`_fitted`) together with
    the same order of the other rotors at another speed and a polynomial in time of degree
    :data:`_TREND_DEGREE`. The polynomial takes
    the slow part of the signal that plain demodulation (``2 <s exp(-i k phi)>``) passes: a
    casing ringing at its mounts' natural frequency after the ramp's start, and the offset of
    the ramp's reaction torque (motor_pump_on_mounts, 300 to 3,000 rpm in 2 s: that
    demodulation's 1X phases zig-zagged by about 120 deg from one window to the next above
    2,000 rpm, its amplitudes up to 3 times the steady unbalance response).

    The fitted order of another rotor is bounded by its leakage through the window: the same
    order ``k`` of another rotor (``A_j cos(k phi_j + theta_j)``, at another speed) would add at
    most ``A_j L_j`` to a demodulated ``c``, ``L_j`` the window's response to it
    (:func:`leakage_floor`). Where ``|c|`` is below twice that floor the order's own amplitude
    may be below the leakage, whose phase then rules: there the phase is taken as unknown, NaN
    (a conservative mark: the joint fit takes much of that leakage out).

    The same fit over windows shifted by half a window marks the windows it does not confirm
    (``OrderTrack.unsettled``, :func:`unsettled`). A free vibration within about a cycle a window
    of the order's frequency is not told apart at all (:func:`passage_spans` gives where a fast
    passage through a mode leaves one; the run-up figure shades both).

    Parameters
    ----------
    result : SimulationResult
    sensor : str
    order : float
        Multiple ``k`` of the rotor's angle.
    rotor : str, optional
        Rotor whose angle is tracked (default: the reference rotor, the first with ratio 1).
    revolutions : int, optional
        Turns per window (default :func:`window_turns`: 4 on one rotor; with other rotors the
        length from 4 to 8 turns that passes least of their same order, none where it can).

    Returns
    -------
    OrderTrack
    """
    signal = result.sensor(sensor)
    index = _rotor_index(result, rotor)
    if revolutions is None:
        revolutions = window_turns(result.speed_ratios, index)
    angles = np.asarray(result.rotor_angles, dtype=float)
    windows = _windows(result.time, angles[:, index], revolutions)
    others = _other_orders(result.speed_ratios, index)

    def fit(ws, j, rest):
        """The order's complex amplitude of rotor ``j`` in each window of ``ws``, the orders of the
        rotors ``rest`` fitted with it; shape (len(ws),)."""
        return np.array([_fitted(signal[w], order * angles[w, j], order * angles[w][:, rest], result.time[w], order)
                         for w in ws], dtype=complex)

    values = fit(windows, index, others)
    shifted = _windows(result.time, angles[:, index], revolutions, offset=0.5 * revolutions)
    moved = fit(shifted, index, others)
    speeds = _mean_speeds(result, windows)
    values = _as_turned(values, windows, angles[:, index])
    moved = _as_turned(moved, shifted, angles[:, index])
    middles = np.array([result.time[w].mean() for w in windows])
    neighbours = np.zeros((len(windows), len(others)))
    for k, j in enumerate(others):        # each other rotor's order through its own windows, at these times
        own = _windows(result.time, angles[:, j], revolutions)
        if own:
            found = np.abs(fit(own, j, _other_orders(result.speed_ratios, j)))
            neighbours[:, k] = np.interp(middles, [result.time[w].mean() for w in own], found)
    floors = np.array([leakage_floor(order * angles[w, index], order * angles[w][:, others], neighbours[i], result.time[w])
                       for i, w in enumerate(windows)])
    amplitude = np.abs(values)
    phase = np.where(amplitude >= 2.0 * floors, np.degrees(np.angle(values)), np.nan)
    unsure = unsettled(values, middles, moved, [result.time[w].mean() for w in shifted])
    return OrderTrack(speeds=speeds, amplitude=amplitude, phase_deg=phase, sensor=sensor,
                      rotor=result.rotor_names[index], order=float(order), leakage_floor=floors.reshape(-1),
                      unsettled=unsure)


def _mean_speeds(result, windows) -> np.ndarray:
    """The reference rotor's mean speed over each window (boolean masks) [rad/s], shape (K,)."""
    return np.array([np.trapezoid(result.drive_speed[w], result.time[w]) / np.ptp(result.time[w]) for w in windows])


def track_speeds(result, rotor=None, revolutions=None) -> np.ndarray:
    """The speeds [rad/s], shape (K,), of :func:`order_track`'s windows (the same arguments): the
    reference rotor's mean speed over each, without fitting any signal."""
    index = _rotor_index(result, rotor)
    if revolutions is None:
        revolutions = window_turns(result.speed_ratios, index)
    angles = np.asarray(result.rotor_angles, dtype=float)
    return _mean_speeds(result, _windows(result.time, angles[:, index], revolutions))


@dataclass
class SteadyOrder:
    """The steady response of a linear model to its unbalances, at one sensor and one rotor's
    order-track speeds: what the track is compared with.

    Attributes
    ----------
    speeds : ndarray, shape (K,)
        Reference rotor speeds [rad/s]: the track's (:func:`track_speeds`).
    response : ndarray, shape (K,), complex
        Complex amplitude [m] (``A cos(w t + phase)``, 0-peak) of the sum of the unbalance
        responses of every rotor turning as fast as ``rotor`` (either way): the order line the
        track cannot tell them apart on (:func:`_other_orders`).
    sensor, rotor : str
    sources : tuple of str
        The rotors whose unbalances make it.
    """

    speeds: np.ndarray
    response: np.ndarray
    sensor: str
    rotor: str
    sources: tuple = ()

    @property
    def amplitude(self) -> np.ndarray:
        """0-peak amplitude [m], shape (K,)."""
        return np.abs(self.response)

    @property
    def phase_deg(self) -> np.ndarray:
        """Phase [deg] of ``A cos(w t + phase)``, in (-180, 180], shape (K,): as
        ``unbalance_response`` and the order track give it."""
        return np.degrees(np.angle(self.response))

    def phase_beside(self, track) -> np.ndarray:
        """:attr:`phase_deg` unwrapped along the speeds and moved by whole turns to lie beside
        ``track``'s unwrapped phase (``OrderTrack.unwrapped_phase_deg``) [deg], shape (K,): the
        whole turns that bring it nearest the track's known phases (their median difference), none
        where no phase of the track is known. The same phase modulo 360 deg; what the run-up
        figure's phase panel draws."""
        steady = np.degrees(np.unwrap(np.angle(self.response)))
        tracked = np.asarray(track.unwrapped_phase_deg, dtype=float)
        known = np.isfinite(tracked) & np.isfinite(steady) if tracked.shape == steady.shape else np.zeros(0, bool)
        if not known.any():
            return steady
        return steady + 360.0 * np.round(np.median(tracked[known] - steady[known]) / 360.0)


def steady_orders(model, result, sensor) -> dict:
    """The linear model's steady unbalance response at ``sensor`` beside each rotor's 1X order
    track of the run ``result``: :func:`~rotordyn_modal.analysis.unbalance.unbalance_response` at
    the track's speeds (:func:`track_speeds`), the run-up figure draws it beside the track.

    Parameters
    ----------
    model : Model
        The simulated model.
    result : SimulationResult
        Its run-up.
    sensor : str

    Returns
    -------
    dict of str to SteadyOrder
        One entry per rotor whose order line some rotor's unbalance excites (none without
        ``[[unbalances]]``).
    """
    from ..analysis.unbalance import unbalance_response

    result.sensor(sensor)                                 # an unknown sensor refused by name
    if not model.unbalances:
        return {}
    ratios = np.asarray(result.speed_ratios, dtype=float)
    out = {}
    for index, rotor in enumerate(result.rotor_names):
        speeds = track_speeds(result, rotor)
        steady = unbalance_response(model, speeds, outputs=[sensor], resonances=False) if len(speeds) else None
        sources = tuple(name for name in (steady.sources if steady is not None else ())
                        if abs(abs(ratios[result.rotor_names.index(name)]) - abs(ratios[index]))
                        <= 1e-9 * max(abs(ratios[index]), 1.0))
        if sources:
            response = sum(steady.response[0, steady.sources.index(name)] for name in sources)
            out[rotor] = SteadyOrder(speeds=speeds, response=np.asarray(response, dtype=complex), sensor=sensor,
                                     rotor=rotor, sources=sources)
    return out


def _as_turned(values, windows, angle):
    """The fitted ``c`` of ``A cos(k phi + arg c)`` (shape (K,), one a window) as the phase
    against the angle turned through, ``A cos(k |phi| + phase)``: conjugated in the windows
    where the rotor's angle ``phi`` falls (it turns against the positive spin direction), so
    that the phase is the linear unbalance response's ``A cos(w t + phase)``, ``w > 0``."""
    falling = np.array([angle[w][-1] < angle[w][0] for w in windows], dtype=bool)
    return np.where(falling, np.conj(values), values) if len(windows) else values


#: the share of a window's tracked amplitude by which the track over windows shifted by half a
#: window may differ from it there before the window is :func:`unsettled`
UNSETTLED = 0.2


def unsettled(values, times, shifted, shifted_times) -> np.ndarray:
    """Windows whose tracked order the windows shifted by half a window do not confirm.

    An order whose complex amplitude changes slowly is tracked alike over any window of the same
    length: the shifted windows' track, interpolated (linearly, real and imaginary parts) to a
    window's middle, lies within :data:`UNSETTLED` of ``|c|`` of that window's ``c``. Content at
    nearly the order's frequency that the fit does not hold (a free vibration of a mode the order
    crosses, the start's transient) turns against the order from one window to the next and
    moves the two tracks apart; so does a response changing much within a window (a fast passage
    through a resonance).

    Parameters
    ----------
    values : ndarray, shape (K,) complex
        The tracked order over the windows [unit of the signal].
    times : array_like, shape (K,)
        The windows' middle times [s], rising.
    shifted : ndarray, shape (L,) complex
        The order over the windows shifted by half a window.
    shifted_times : array_like, shape (L,)
        Their middle times [s], rising.

    Returns
    -------
    ndarray of bool, shape (K,)
        True where ``|c_shifted(t_k) - c_k| > UNSETTLED |c_k|``; all False with fewer than two
        shifted windows (nothing to compare with).
    """
    values = np.asarray(values, dtype=complex)
    if len(shifted) < 2:
        return np.zeros(len(values), dtype=bool)
    there = (np.interp(times, shifted_times, np.real(shifted))
             + 1j * np.interp(times, shifted_times, np.imag(shifted)))
    return np.abs(there - values) > UNSETTLED * np.abs(values)


#: the shortest and longest order-tracking windows :func:`window_turns` chooses from [turns]
SHORTEST_WINDOW, LONGEST_WINDOW = 4, 8


def window_turns(speed_ratios, index) -> int:
    """The window length [whole turns of rotor ``index``] that passes least of the same order of
    the other rotors: over ``R`` turns at a steady speed the window's response to a rotor
    turning ``rho`` times as fast is ``|sinc(R (rho - 1))| + |sinc(R (rho + 1))|``
    (:func:`leakage_floor`), 0 where both ``R (rho -+ 1)`` are whole numbers. The ``R`` from
    :data:`SHORTEST_WINDOW` to :data:`LONGEST_WINDOW` whose largest response over the other
    rotors is least (within 1e-9, the shortest); :data:`SHORTEST_WINDOW` without other rotors
    at another speed. The fan's 1.6:1 belt: 8 turns of the motor (3 and 13 cycles of the
    difference and sum: a null) where 4 passed 0.26 of the fan's 1X, 5 of the fan.

    Parameters
    ----------
    speed_ratios : array_like, shape (R_rotors,)
        Each rotor's speed over the reference rotor's.
    index : int
        The tracked rotor.

    Returns
    -------
    int
    """
    ratios = np.asarray(speed_ratios, dtype=float)
    own = abs(ratios[index])
    others = _other_orders(ratios, index)
    if not others.size or own == 0:
        return SHORTEST_WINDOW
    rho = np.abs(ratios[others]) / own
    turns = np.arange(SHORTEST_WINDOW, LONGEST_WINDOW + 1)
    response = (np.abs(np.sinc(turns[:, None] * (rho[None] - 1))) + np.abs(np.sinc(turns[:, None] * (rho[None] + 1)))).max(axis=1)
    return int(turns[np.flatnonzero(response <= response.min() + 1e-9)[0]])


#: a free vibration turning fewer cycles than this over a window is taken by the window's
#: polynomial in time (:data:`_TREND_DEGREE`)
POLYNOMIAL_CYCLES = 0.7

#: the share of the peak steady response by which an order track may differ from it where it is
#: not marked (:func:`quasi_static_deviation`, :func:`passage_spans`)
STEADY_TOLERANCE = 0.1

#: a crossing is passed slowly, its response near the steady one, where the order's frequency
#: sweeps at most this many times ``(zeta f)^2`` [Hz/s] (:func:`passage_spans`): there the
#: deviation :func:`quasi_static_deviation` is at most :data:`STEADY_TOLERANCE` (before: 1, a
#: deviation of 16 %)
SLOW_PASSAGE = 2 * np.pi * STEADY_TOLERANCE


def quasi_static_deviation(sweep, frequency, zeta) -> float:
    """How far a swept mode's order is from its steady response, as a share of the peak steady
    response: ``sweep / (2 pi (zeta f)^2)``.

    An order of slowly varying complex amplitude ``A`` pushing one mode ``x'' + 2 zeta w x' + w^2 x
    = F exp(i phi)``, ``phi' = Omega``, ``Omega' = a`` (``x = A exp(i phi)``) obeys
    ``D A - i D' A' + i a A + A'' = F``, ``D(Omega) = w^2 - Omega^2 + 2 i zeta w Omega``. Its steady
    response is ``A0 = F / D``; the first correction, with ``A' = a dA0/dOmega``, is
    ``A1 = i a (D' dA0/dOmega - A0) / D``, at the peak (``Omega = w``, ``zeta`` small)
    ``A1 = i a / (zeta w)^2 A0``: a lag of the response behind the speed. With the order's sweep
    ``alpha = a / 2 pi`` [Hz/s] and ``w = 2 pi f``, ``|A1 / A0| = alpha / (2 pi (zeta f)^2)``.
    Measured on a 6 Hz mode, ``zeta`` 0.03, swept from 4.5 to 7.5 Hz at 0.05 ``(zeta f)^2``:
    the track's largest distance from the closed-form steady response was 1.01 times this
    (tests/test_runup_quasi_static27r.py).

    Parameters
    ----------
    sweep : float
        The order's frequency sweep ``alpha`` [Hz/s] (its sign ignored).
    frequency : float
        The mode's frequency ``f`` [Hz].
    zeta : float
        Its damping ratio.

    Returns
    -------
    float
        The share (1 for as large as the peak; inf for an undamped mode).
    """
    width = (zeta * frequency) ** 2
    return float(abs(sweep) / (2 * np.pi * width)) if width > 0 else np.inf


def passage_spans(critical, ratio, order, acceleration, revolutions=SHORTEST_WINDOW) -> list:
    """Reference speeds [rad/s] where rotor's order ``order`` is not told apart from the free
    vibration a fast passage through a mode leaves.

    A ramp that sweeps an order line through a mode (a crossing of ``critical``, damped
    frequency ``f`` [Hz], damping ratio ``zeta``) at ``alpha`` [Hz/s], faster than
    :data:`SLOW_PASSAGE` ``(zeta f)^2``, leaves the mode ringing at ``f`` with a size of the
    order of the peak response, and the order near ``f`` does not reach its steady response.
    A window of a few turns does not tell the ringing from the order while their frequencies are
    within about a cycle a window of each other. The track of order ``k`` of a rotor turning
    ``ratio`` times as fast as the reference rotor is marked where its frequency lies within
    ``f - 2 zeta f - sqrt(alpha)`` to ``f + 2 zeta f + 2 sqrt(alpha) + alpha / sigma``: the
    mode's half-power band widened by the passage's own band, ``sqrt(alpha)`` [Hz], and above
    the mode by how far the order moves while the ringing decays by ``e`` (``sigma = zeta 2 pi f
    / sqrt(1 - zeta^2)``), but not where the ringing turns under :data:`POLYNOMIAL_CYCLES` a
    window (the fitted polynomial takes it). One mode at 6 Hz, ``zeta`` 0.03, swept by an
    unbalance from 2 to 20 Hz from rest (4-turn windows): at ``alpha / (zeta f)^2`` of 0.5 and 1
    the track was at most 8 % and 15 % off the closed-form steady response, the
    :func:`quasi_static_deviation` 0.08 and 0.16 (1 is marked now: over :data:`SLOW_PASSAGE`); at 6,
    19 and 56, 0.7, 1.2 and 1.0 times off inside that band and within 10 % outside it and the
    start's unsettled windows (tests/test_runup_passage27.py).

    Parameters
    ----------
    critical : CriticalSpeeds
        The crossings over the ramp's speeds (``speeds`` [rad/s], ``frequencies_hz``,
        ``damping_ratios``): each crossing's order line sweeps at ``f / speed`` times the ramp
        rate; every rotor's fast passage rings the mode.
    ratio : float
        The tracked rotor's speed over the reference rotor's.
    order : float
        ``k``.
    acceleration : float
        The reference rotor's ramp rate [rad/s^2].
    revolutions : int
        The track's window [turns of the tracked rotor].

    Returns
    -------
    list of (float, float)
        Reference-speed spans [rad/s], merged where they overlap, rising.
    """
    if critical is None or not len(critical.speeds) or acceleration == 0 or ratio * order == 0:
        return []
    per_speed = abs(ratio * order) / (2 * np.pi)          # the track's frequency per reference speed [Hz s/rad]
    spans = []
    for speed, f, zeta in zip(critical.speeds, critical.frequencies_hz, critical.damping_ratios):
        if not (np.isfinite(f) and np.isfinite(zeta) and f > 0 and zeta > 0 and speed != 0):
            continue
        sweep = abs(f / speed * acceleration)     # the crossing order line's sweep [Hz/s]
        if sweep <= SLOW_PASSAGE * (zeta * f) ** 2:
            continue
        own = abs(per_speed * acceleration)       # the track's own sweep [Hz/s]
        decay = zeta * 2 * np.pi * f / np.sqrt(1 - zeta ** 2)       # the ringing's [1/s]
        high = (f + 2 * zeta * f + 2 * np.sqrt(own) + own / decay) / per_speed
        held = 2 * np.pi * f * revolutions / (POLYNOMIAL_CYCLES * abs(ratio))    # the polynomial takes it above
        spans.append((max(f - 2 * zeta * f - np.sqrt(own), 0.0) / per_speed, min(high, max(held, f / per_speed))))
    return _merged(spans)


def unsettled_spans(result, track, critical=None) -> list:
    """Reference speeds [rad/s], as merged ``(low, high)`` spans, where ``track`` need not follow
    the steady response (the run-up figure shades them).

    Parameters
    ----------
    result : SimulationResult
        The ramp the track was taken from.
    track : OrderTrack
        :func:`order_track` of ``result``.
    critical : CriticalSpeeds, optional
        The crossings over the ramp's speeds.

    Returns
    -------
    list of (float, float)
        The track's unsettled windows (``OrderTrack.unsettled``, each from halfway to its
        neighbours) and, with ``critical``, the spans of :func:`passage_spans`; merged, rising,
        cut to the run's speeds.
    """
    index = list(result.rotor_names).index(track.rotor)
    speeds = np.asarray(track.speeds, dtype=float)
    spans = []
    if getattr(track, "unsettled", None) is not None and len(speeds) > 1:
        edges = np.concatenate([[1.5 * speeds[0] - 0.5 * speeds[1]], 0.5 * (speeds[1:] + speeds[:-1]),
                                [1.5 * speeds[-1] - 0.5 * speeds[-2]]])
        spans += [tuple(sorted((edges[k], edges[k + 1]))) for k in np.flatnonzero(track.unsettled)]
    drive = np.asarray(result.drive_speed, dtype=float)
    time = np.asarray(getattr(result, "time", ()), dtype=float)    # a figure's stand-in may have none
    if critical is not None and len(time) == len(drive) > 1 and time[-1] > time[0]:
        acceleration = (drive[-1] - drive[0]) / (time[-1] - time[0])
        spans += passage_spans(critical, result.speed_ratios[index], track.order, acceleration,
                               window_turns(result.speed_ratios, index))
    low, high = drive.min(), drive.max()
    return [(max(a, low), min(b, high)) for a, b in _merged(spans) if b > low and a < high]


#: a passage whose lag :func:`quasi_static_deviation` estimates above this share of the peak is
#: fast: the order does not reach its steady response, and the mode's ringing after it shows in
#: the track (one mode at 6 Hz, zeta 0.03, swept from 3 to 12 Hz: above 6.6 Hz the track was 4 %
#: of the peak off at an estimated lag of 0.95, 20 % at 1.6 and 24 % at 3.2; near the peak its
#: distance was 0.92, 0.69 and 0.47 times the estimate at 0.16, 0.48 and 0.95: the lag)
FAST_PASSAGE = 1.0


def shade_causes(result, track, critical=None) -> list:
    """Why ``track`` may differ from the steady response where :func:`unsettled_spans` shades it:
    one short phrase a kind of cause.

    * a crossing of the track's own order passed faster than :data:`SLOW_PASSAGE` ``(zeta f)^2``
      where the span is shaded: :func:`lag_text`, the response lagging behind the steady one,
      off it by about :func:`quasi_static_deviation` of the mode's own resonant peak (amplitude and
      phase together; a mode the sensor hardly sees moves the track little); beyond
      :data:`FAST_PASSAGE`, ``'fast passage of modes 1-3: lag, ringing'``;
    * another rotor's (or order's) fast passage, where the track's frequency is the mode's in a
      shaded span: ``"modes 3-6 rung by 1X pump's passage"`` (:func:`passage_spans`);
    * the track's :func:`unsettled` windows: ``'unsettled windows (start transient, ringing)'``.

    Parameters
    ----------
    result : SimulationResult
        The ramp.
    track : OrderTrack
        :func:`order_track` of ``result``.
    critical : CriticalSpeeds, optional
        The crossings over the ramp's speeds.

    Returns
    -------
    list of str
        The lags, the fast passages, the ringing after each other order's passages, the unsettled
        windows (those present); empty where nothing is shaded.
    """
    spans = unsettled_spans(result, track, critical)
    causes, lags, fast, rung = [], {}, [], {}
    drive = np.asarray(result.drive_speed, dtype=float)
    time = np.asarray(getattr(result, "time", ()), dtype=float)
    if critical is not None and spans and len(time) == len(drive) > 1 and time[-1] > time[0]:
        acceleration = (drive[-1] - drive[0]) / (time[-1] - time[0])
        ratio = result.speed_ratios[list(result.rotor_names).index(track.rotor)]
        per_speed = abs(ratio * track.order) / (2 * np.pi)    # the track's frequency per reference speed [Hz s/rad]
        for k in np.argsort(critical.speeds):
            speed, f, zeta = critical.speeds[k], critical.frequencies_hz[k], critical.damping_ratios[k]
            if not (np.isfinite(f) and np.isfinite(zeta) and f > 0 and zeta > 0 and speed != 0):
                continue
            sweep = abs(f / speed * acceleration)     # the crossing order line's sweep [Hz/s]
            seen = f / per_speed if per_speed > 0 else np.inf      # where the track's frequency is f [rad/s]
            if sweep <= SLOW_PASSAGE * (zeta * f) ** 2 or not any(low <= seen <= high for low, high in spans):
                continue
            lag = quasi_static_deviation(sweep, f, zeta)
            mode, source, order = int(critical.mode[k]), critical.source[k], float(critical.order[k])
            if source != track.rotor or abs(order - track.order) > 1e-9:      # another order rings it
                rung.setdefault(f"{order:g}X {source}", []).append(mode)
            elif lag > FAST_PASSAGE:
                fast.append(mode)
            else:
                lags[mode] = max(lag, lags.get(mode, 0.0))
    if lags:
        causes.append(lag_text(lags))
    if fast:
        causes.append(f"fast passage of {_modes_text(fast)}: lag, ringing")
    causes += [f"{_modes_text(modes)} rung by {name}'s passage" for name, modes in rung.items()]
    if getattr(track, "unsettled", None) is not None and np.any(track.unsettled):
        causes.append("unsettled windows (start transient, ringing)")
    return causes


def lag_text(lags) -> str:
    """The shade's words for the lag through modes ``lags`` (mode number to its
    :func:`quasi_static_deviation`): ``"lag through mode 1 (estimate: near it the track is off the
    steady response by up to 13% of that resonance's steady peak, amplitude and phase together)"``.

    What the share measures: the distance between the tracked and the steady complex amplitude
    (``|A - A0|``, the vector difference) near the mode's crossing, over that resonance's steady
    peak ``|A0|``, the first term of the expansion in the sweep. It is not the peak's shortfall:
    one mode swept at 0.8 ``(zeta f)^2`` (13 %) kept its peak within 0.5 % of the steady one, and was
    off it by up to 8 % of the peak in amplitude and 7 deg in phase on its flanks (docs/simulate.md,
    "What the shade says")."""
    modes = sorted(lags)
    many = len(modes) > 1
    return (f"lag through mode{'s' if many else ''} " + ", ".join(str(m) for m in modes)
            + f" (estimate: near {'each' if many else 'it'} the track is off the steady response by up to "
            + ", ".join(f"{lags[m]:.0%}" for m in modes)
            + f" of {'its' if many else 'that'} resonance's steady peak, amplitude and phase together)")


def _modes_text(modes) -> str:
    """'mode 2', or 'modes 1-3, 5' (each once, rising)."""
    modes = sorted(set(int(m) for m in modes))
    if len(modes) == 1:
        return f"mode {modes[0]}"
    runs = []
    for m in modes:
        if runs and m == runs[-1][1] + 1:
            runs[-1][1] = m
        else:
            runs.append([m, m])
    return "modes " + ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs)


def _merged(spans) -> list:
    """Spans ``(low, high)`` merged where they overlap or touch, rising."""
    out = []
    for low, high in sorted(spans):
        if out and low <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], high))
        else:
            out.append((low, high))
    return out


def _windows(time, angle, revolutions, offset=0.0) -> list:
    """The windows of ``revolutions`` turns of ``angle`` [rad] (travelled, any direction), as
    boolean masks of the samples, those of at least 8 samples; the first starts ``offset`` turns
    after the record's start."""
    turns = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(angle)))]) / (2 * np.pi)
    edges = np.arange(offset, turns[-1] + 1e-12, revolutions)
    windows = [(turns >= start) & (turns <= stop) for start, stop in zip(edges[:-1], edges[1:])]
    return [w for w in windows if w.sum() >= 8]


#: the degree of the polynomial in time fitted with the orders over each window (the slow part
#: of the signal): a synthetic 6 Hz ringing of 40 um, 0.7 of a cycle a window, moves a 2.3 um 1X
#: by 1 % and 0.1 deg (a cubic: 10 % and 6 deg)
_TREND_DEGREE = 5


#: the rotor's own whole orders 1 to this fitted with the tracked one: over whole turns plain
#: demodulation is blind to them; the polynomial alone would pass some of them
_OWN_HARMONICS = 4


def _own_harmonics(phase, order):
    """The angles ``m phase / order`` (P, M) of the rotor's whole orders ``m`` = 1 to
    :data:`_OWN_HARMONICS` other than ``order`` (none for order 0)."""
    if order == 0:
        return np.zeros((len(phase), 0))
    whole = [m for m in range(1, _OWN_HARMONICS + 1) if abs(m - abs(order)) > 1e-9]
    return np.asarray(phase)[:, None] * (np.array(whole, dtype=float) / order)[None]


def _fitted(signal, phase, others, t, order=1.0) -> complex:
    """The complex amplitude ``c`` [unit of s] of ``s ~ Re(c exp(i phase))`` over one window,
    by least squares together with ``Re(c_j exp(i others_j))`` and a polynomial of degree
    :data:`_TREND_DEGREE` in time.

    Parameters
    ----------
    signal, phase : ndarray, shape (P,)
        The samples and the tracked order's angle ``k phi`` [rad] there.
    others : ndarray, shape (P, J)
        The other rotors' same order ``k phi_j`` [rad] (J may be 0).
    t : ndarray, shape (P,)
        Times [s].
    order : float
        ``k``: the rotor's own whole orders (:func:`_own_harmonics`) are fitted too.

    Returns
    -------
    complex
        Exact for ``s = A cos(phase + theta) + sum_j A_j cos(others_j + theta_j)`` plus the
        rotor's whole orders up to :data:`_OWN_HARMONICS` and the polynomial:
        ``A exp(i theta)``.
    """
    centred = 2.0 * (t - 0.5 * (t[0] + t[-1])) / (t[-1] - t[0])      # -1 to 1
    others = np.asarray(others, dtype=float).reshape(len(t), -1)
    own = _own_harmonics(phase, order)
    columns = np.column_stack([np.cos(phase), np.sin(phase), np.cos(others), np.sin(others),
                               np.cos(own), np.sin(own),
                               np.vander(centred, _TREND_DEGREE + 1, increasing=True)])
    scale = np.linalg.norm(columns, axis=0)
    scale[scale == 0] = 1.0
    coefficients = np.linalg.lstsq(columns / scale, signal, rcond=None)[0] / scale
    return complex(coefficients[0], -coefficients[1])


def leakage_floor(phase, others, amplitudes, t) -> float:
    """The most the other rotors' order adds to one window's demodulated amplitude [unit of the
    amplitudes].

    A component ``A cos(psi + theta)`` (``psi = k phi_j``, one column of ``others``) adds to
    ``c = 2 <s exp(-i k phi)>`` the amount ``A/T (exp(i theta) I_- + exp(-i theta) I_+)``,
    ``I_-+ = integral of exp(i (psi -+ k phi)) dt`` over the window of length ``T``: at most
    ``A L``, ``L = (|I_-| + |I_+|) / T`` (a rectangular window of ``R`` turns at a steady
    speed: ``L = |sinc(R (rho - 1))| + |sinc(R (rho + 1))|``, ``rho`` the speed ratio, about
    0.26 for the fan's 1.6:1 belt and four turns).

    Parameters
    ----------
    phase : ndarray, shape (P,)
        ``k phi`` of the tracked rotor over the window's samples [rad].
    others : ndarray, shape (P, J)
        ``k phi_j`` of the other rotors whose order is at another frequency [rad].
    amplitudes : ndarray, shape (J,)
        Their orders' amplitudes ``A_j`` (as tracked through their own windows).
    t : ndarray, shape (P,)
        Times [s].

    Returns
    -------
    float
        ``sum_j A_j L_j``; 0 without other rotors.
    """
    span = t[-1] - t[0]
    floor = 0.0
    for psi, size in zip(np.asarray(others, dtype=float).T, amplitudes):
        response = (abs(np.trapezoid(np.exp(1j * (psi - phase)), t)) + abs(np.trapezoid(np.exp(1j * (psi + phase)), t))) / span
        floor += response * size
    return float(floor)


def _other_orders(speed_ratios, index) -> np.ndarray:
    """Indices of the rotors (``speed_ratios``, shape (R,)) whose order lies at another frequency
    than rotor ``index``'s: a rotor turning as fast (either way) has the same order line, which no
    window tells apart."""
    ratios = np.asarray(speed_ratios, dtype=float)
    own = abs(ratios[index])
    return np.array([j for j in range(len(ratios)) if j != index and abs(abs(ratios[j]) - own) > 1e-9 * max(own, 1.0)],
                    dtype=int)


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
