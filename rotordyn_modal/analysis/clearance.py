"""The API 617 / API 684 clearance check of an unbalance response (``docs/standards.md``).

At every close-clearance station of the model (``[[rotors.clearances]]``: a point on a rotor's
axis and its radial running clearance ``c``) the rotor's motion **relative to the stator** (the
casing that holds the seal) traces an orbit; its peak-to-peak displacement in the worst
direction is twice the orbit's semi-major axis (``orbits.orbit_ellipses``), summed over the
sources (exact for one source or one API case; the largest the sum of harmonics of different
frequencies reaches). Scaled by the API 617 factor ``Scc`` it shall stay below 75 % of the
minimum diametral running clearance::

    Scc x pk-pk(station) <= 0.75 x 2 c            (0-peak: Scc x semi-major axis <= 0.75 c)

over the checked speeds ``min_speed <= |speed| <= trip speed`` (API 617: from zero to trip
speed; default the MCS), each API unbalance case on its own, at the swept speeds and at the
stations' maxima between them, found on the exact response by the AF table's search
(``unbalance_peaks.cut_maxima``: the maxima the swept line cuts) and its golden-section step on
each swept local maximum.
``Scc = Avl / Amax``, at most 6: the probe vibration limit ``Avl`` of the station's rotor over
the largest peak-to-peak amplitude ``Amax`` of that rotor's probes (``measure = "relative"``)
between ``min_speed`` and the MCS, in the same case, their peaks between swept speeds included
(``UnbalanceResult.cut_peaks``; not for several sources together); ``Scc = 1`` (unscaled) for
a rotor without a probe among the outputs or without an MCS. The analysis is linear: the
scaled response is the response to ``Scc`` times the unbalance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..unbalance_standards import API_SCALE_CAP, api_scale_factor
from .orbits import orbit_ellipses

__all__ = ["ClearanceCheck", "clearance_check", "CLEARANCE_SHARE", "CLEARANCE_CHECK"]

#: the share of the minimum diametral running clearance the pk-pk response may reach
CLEARANCE_SHARE = 0.75
#: the check's name in tables and the report's summary
CLEARANCE_CHECK = "API 617 clearance (75 % of diametral)"


@dataclass(frozen=True)
class ClearanceCheck:
    """Unbalance response at the close-clearance stations against 75 % of their clearance.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    checked : ndarray of bool, shape (N,)
        The speeds in the checked range.
    names, rotors : tuple of str
        Each station and its rotor.
    radial_clearances : ndarray, shape (n_stations,) [m]
    pkpk : ndarray, shape (n_stations, n_cases, N) [m]
        Peak-to-peak displacement of the rotor relative to the stator at each station (twice
        the orbit's semi-major axis).
    cases : tuple of str
        The API unbalance cases (one source each), or ``('',)``: all sources together.
    trip_speed : float or None [rad/s]
        Top of the checked speeds (None: every speed of the sweep).
    scale : ndarray, shape (n_stations, n_cases), optional
        The API 617 scale factor ``Scc`` of each station's rotor and case (default 1: unscaled).
    scaling : ndarray of str, shape (n_stations, n_cases), optional
        How ``scale`` was found (``'Avl/Amax'``, ``'Avl/Amax capped at 6'``, or why it is 1).
    peak_speeds, peak_pkpk : ndarray, shape (n_stations, n_cases, Q), optional
        [rad/s], [m] each station's maxima between swept speeds that the swept line cuts and
        the peak-to-peak displacement there, NaN after a curve's last (None: not looked for).
    """

    speeds: np.ndarray
    checked: np.ndarray
    names: tuple
    rotors: tuple
    radial_clearances: np.ndarray
    pkpk: np.ndarray
    cases: tuple = ("",)
    trip_speed: float | None = None
    scale: np.ndarray | None = None
    scaling: np.ndarray | None = None
    peak_speeds: np.ndarray | None = None
    peak_pkpk: np.ndarray | None = None

    @property
    def limits(self) -> np.ndarray:
        """[m] peak-to-peak: 75 % of the diametral clearance ``0.75 x 2 c``, shape (n_stations,)."""
        return CLEARANCE_SHARE * 2.0 * np.asarray(self.radial_clearances, dtype=float)

    @property
    def scale_factors(self) -> np.ndarray:
        """``Scc`` of each station and case, shape (n_stations, n_cases) (1 where not scaled)."""
        return np.ones(self.pkpk.shape[:2]) if self.scale is None else np.asarray(self.scale, dtype=float)

    def to_dataframe(self):
        """One row per station and case: ``clearance, rotor, speed_rpm, value, amplitude, limit,
        ratio, verdict, response, scale_factor, scaling`` (then ``case`` for the API cases).

        ``value`` [m] is the largest scaled peak-to-peak displacement ``Scc x response`` over the
        checked speeds and the maxima found between them (:attr:`peak_speeds`; at ``speed_rpm``), ``limit`` [m] 75 % of the diametral clearance, ``ratio``
        their quotient; ``verdict`` pass when ``value <= limit``. ``response`` [m] is the
        unscaled peak-to-peak displacement there, ``scale_factor`` the API 617 ``Scc`` and
        ``scaling`` how it was found.
        """
        import pandas as pd

        scale = self.scale_factors
        scaling = np.full(scale.shape, "unscaled", dtype=object) if self.scaling is None else self.scaling
        rows = []
        for c, case in enumerate(self.cases):
            for s, (name, rotor, values, limit) in enumerate(zip(self.names, self.rotors, self.pkpk[:, c],
                                                                  self.limits)):
                speed, response = self._largest(values, s, c)
                value = scale[s, c] * response
                verdict = "no speed checked" if not np.isfinite(value) else ("pass" if value <= limit else "fail")
                rows.append({"clearance": name, "rotor": rotor, "speed_rpm": speed, "value": value,
                             "amplitude": "peak-to-peak", "limit": limit, "ratio": value / limit,
                             "verdict": verdict, "response": response, "scale_factor": scale[s, c],
                             "scaling": scaling[s, c], "case": case})
        columns = ["clearance", "rotor", "speed_rpm", "value", "amplitude", "limit", "ratio", "verdict",
                   "response", "scale_factor", "scaling", "case"]
        return pd.DataFrame(rows, columns=columns if self.cases != ("",) else columns[:-1])

    def _largest(self, values, s=None, c=None):
        """(speed [rpm], value) of the largest value over the checked speeds (NaN, NaN if none),
        or of station ``s``'s maximum between them in case ``c`` (:attr:`peak_speeds`) in the
        checked range where it is larger."""
        if not self.checked.any():
            return np.nan, np.nan
        k = int(np.argmax(np.where(self.checked, values, -np.inf)))
        speed, value = float(self.speeds[k] * 30 / np.pi), float(values[k])
        if self.peak_speeds is None or s is None:
            return speed, value
        at, found = self.peak_speeds[s, c], self.peak_pkpk[s, c]
        low = np.abs(self.speeds[self.checked]).min()
        top = np.inf if self.trip_speed is None else self.trip_speed
        inside = np.isfinite(at) & (np.abs(at) >= low) & (np.abs(at) <= top)
        if inside.any() and found[inside].max() > value:
            m = np.flatnonzero(inside)[np.argmax(found[inside])]
            speed, value = float(at[m] * 30 / np.pi), float(found[m])
        return speed, value


def clearance_check(result, model, mcs=None, min_speed: float = 0.0, trip_speed=None,
                    scale_cap=API_SCALE_CAP, min_operating=None) -> ClearanceCheck:
    """The clearance check of ``result`` at ``model``'s close-clearance stations.

    Parameters
    ----------
    result : UnbalanceResult
        Of ``model`` (its ``clearance_planes``); the API cases
        (:func:`~rotordyn_modal.analysis.unbalance.api_unbalance_response`) are checked each alone,
        the model's own unbalances all together.
    model : Model
    mcs : float, optional
        [rad/s] the reference rotor's maximum continuous speed: the top of the checked speeds
        when ``trip_speed`` is not given.
    min_speed : float
        [rad/s] bottom of the checked speeds (default 0).
    trip_speed : float, optional
        [rad/s] top of the checked speeds (API 617: the trip speed), at least ``mcs``.
    scale_cap : float or None
        The largest scale factor ``Scc`` (API 617: 6); None for none.
    min_operating : float, optional
        [rad/s] the minimum allowable (operating) speed: ``Amax`` of ``Scc`` is the probes'
        largest amplitude from it to ``mcs`` (API 617: the operating speeds); default
        ``min_speed``.

    Returns
    -------
    ClearanceCheck
    """
    top = trip_speed if trip_speed is not None else mcs
    for value, what in ((mcs, "maximum continuous speed"), (trip_speed, "trip speed")):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise InputError(f"{what} {value!r} rad/s: expected a finite speed > 0")
    if trip_speed is not None and mcs is not None and trip_speed < mcs:
        raise InputError(f"trip speed {trip_speed!r} rad/s: expected at least the maximum continuous speed {mcs!r} rad/s")
    if not (np.isfinite(min_speed) and min_speed >= 0) or (top is not None and min_speed > top):
        raise InputError(f"minimum speed {min_speed!r} rad/s: expected a finite speed >= 0 and at most the top "
                         "of the checked speeds")
    if tuple(c.name for c in model.clearances) != tuple(result.clearance_names):
        raise InputError(f"{model.source}: the unbalance response holds the clearances "
                         f"{list(result.clearance_names)}, the model {[c.name for c in model.clearances]}: "
                         "expected the response of this model")
    speed = np.abs(result.speeds)
    checked = (speed >= min_speed) & (speed <= (np.inf if top is None else top))
    planes = result.clearance_planes
    n_src = len(result.sources)
    together = not result.case_rotors
    major = _majors(planes, result, together) if planes is not None and planes.size else \
        np.zeros((len(model.clearances), n_src, len(speed)))
    pkpk = 2.0 * (major.sum(axis=1, keepdims=True) if together else major)
    rotors = tuple(c.rotor for c in model.clearances)
    bottom = min_speed if min_operating is None else min_operating
    if not (np.isfinite(bottom) and bottom >= 0) or (mcs is not None and bottom > mcs):
        raise InputError(f"minimum operating speed {bottom!r} rad/s: expected a finite speed >= 0 and at most "
                         "the maximum continuous speed")
    scale, scaling = _scale_factors(result, model, rotors, pkpk.shape[1], mcs, bottom, scale_cap)
    peak_speeds, peak_pkpk = _cut_peaks(result, model, mcs, pkpk, together, top)
    return ClearanceCheck(speeds=result.speeds, checked=checked, names=tuple(c.name for c in model.clearances),
                          rotors=rotors,
                          radial_clearances=np.array([c.radial_clearance for c in model.clearances], dtype=float),
                          pkpk=pkpk, cases=("",) if together else tuple(result.sources), trip_speed=top,
                          scale=scale, scaling=scaling, peak_speeds=peak_speeds, peak_pkpk=peak_pkpk)


def _majors(planes, result, together):
    """The semi-major axes of the stations' orbits, shape (n_stations, n, K): one per source
    (each API case alone), or with the model's own sources together one per frequency
    (:func:`.unbalance_checks.same_frequency_groups`): sources of one frequency trace one orbit,
    that of the sum of their in-plane amplitudes ``planes`` (n_stations, n_sources, K, 2)."""
    if together:
        from .unbalance_checks import same_frequency_groups

        planes = np.stack([planes[:, group].sum(axis=1) for group in same_frequency_groups(result.frequencies_hz)],
                          axis=1)
    return orbit_ellipses(planes, 1.0)[0]


def _cut_peaks(result, model, mcs, pkpk, together, top=None):
    """Each station's maxima of the exact response near the swept speeds, and the peak-to-peak
    displacement there, each shape (n_stations, n_cases, Q), NaN after a curve's last (None,
    None where no case's model is known).

    Two searches on the semi-major axis of each station's orbit, solved again at the searched
    speeds: the AF table's (:func:`.unbalance_peaks.cut_maxima`, no half-power widths: the
    maxima the swept line cuts around the damped critical speeds no swept speed resolves), and
    its golden-section step on each swept local maximum between its two neighbours (a resolved
    peak's top lies between swept speeds too: examples/compressor_rotor.toml at the report's 151
    speeds read 9 % low). The model's own unbalances together (one curve, around every source's
    critical speeds), or each API case's model (:func:`.unbalance_checks.api_unbalance_cases`
    of ``mcs``) alone. The top of the checked speeds ``top`` [rad/s] too, where the sweep runs
    past it without it (the response still rising there). Not looked for where the AF table's peaks are not (``cut_peak_note``: a
    large model)."""
    from .unbalance_checks import case_models
    from .unbalance_peaks import cut_maxima, per_source, refined_maxima

    if not model.clearances or result.cut_peak_note:               # the AF table's peaks not looked for either
        return None, None
    models = case_models(result, model, mcs)
    if models is None:
        return None, None

    def solve(at, each):                                         # (n_stations, K): the semi-major axes
        major = _majors(result.station_planes(models[each], at), result, together)
        return (major.sum(axis=1) if together else major[:, 0]).astype(complex)

    curve = per_source(solve)
    peaks = [refined_maxima(curve, result.speeds, pkpk, top)]
    if result.resonance_speeds is not None:
        found = [(s[np.isfinite(s)], b[np.isfinite(b)]) for s, b in zip(result.resonance_speeds,
                                                                          result.resonance_bands)]
        if together:
            found = [(np.concatenate([s for s, _ in found]), np.concatenate([b for _, b in found]))]
        at, value, _ = cut_maxima(curve, result.speeds, pkpk / 2.0, found, half_power=False)
        peaks.append((at, 2.0 * np.abs(value)))
    return np.concatenate([p[0] for p in peaks], axis=2), np.concatenate([p[1] for p in peaks], axis=2)


def _scale_factors(result, model, rotors, n_cases, mcs, min_speed, cap):
    """API 617 ``Scc = Avl / Amax`` (at most ``cap``) of each station's rotor and case, from the
    probes of the rotor among the result's outputs between ``min_speed`` and ``mcs``; 1 where
    there is no probe, no MCS or no probe amplitude. Returns (scale, scaling), each of shape
    (n_stations, n_cases)."""
    from .unbalance_checks import unbalance_checks

    scale = np.ones((len(rotors), n_cases))
    scaling = np.full((len(rotors), n_cases), "unscaled: no MCS", dtype=object)
    if mcs is None:
        return scale, scaling
    probes = unbalance_checks(result, model, mcs=mcs, min_speed=min_speed, refine=False)
    window, where = _operating_speeds(np.abs(result.speeds), min_speed, mcs)
    rotor_of = {s.name: s.rotor for s in model.sensors}
    for s, rotor in enumerate(rotors):
        rows = [p for p, name in enumerate(probes.probes) if rotor_of[name] == rotor]
        if not rows:
            scaling[s] = f"unscaled: no probe on rotor {rotor}"
            continue
        largest = np.where(window, probes.probe_pkpk[rows], -np.inf).max(axis=(0, 2))   # (n_cases,)
        largest = np.maximum(largest, _probe_peaks(result, [probes.probes[p] for p in rows], n_cases, min_speed, mcs))
        if window.any():                    # else the sweep's speed nearest them stands for them, said
            largest = np.maximum(largest, _probe_ends(result, model, [probes.probes[p] for p in rows], n_cases,
                                                      min_speed, mcs))
        limit = probes.probe_limits[rows[0]]
        for c in range(n_cases):
            if not (np.isfinite(largest[c]) and largest[c] > 0):
                scaling[s, c] = "unscaled: no probe amplitude in the operating speeds"
                continue
            scale[s, c] = float(api_scale_factor(limit, largest[c], cap))
            capped = cap is not None and limit / largest[c] > cap
            scaling[s, c] = (f"Avl/Amax capped at {cap:g}" if capped else "Avl/Amax") + where
    return scale, scaling


def _probe_peaks(result, probes, n_cases, low, high):
    """The largest peak-to-peak amplitude of the ``probes`` of each case at their peaks between
    the swept speeds from ``low`` to ``high`` [rad/s] (the AF table's: ``result.cut_peaks``),
    shape (n_cases,), -inf where there is none (or the sources are summed: several together)."""
    largest = np.full(n_cases, -np.inf)
    if n_cases != len(result.sources):
        return largest
    for c, source in enumerate(result.sources):
        for name in probes:
            at, response, _ = result.cut_peaks(name, source)
            inside = (np.abs(at) >= low) & (np.abs(at) <= high)
            if inside.any():
                largest[c] = max(largest[c], 2.0 * float(np.abs(response[inside]).max()))
    return largest


def _probe_ends(result, model, probes, n_cases, low, high):
    """The largest peak-to-peak amplitude of the ``probes`` of each case at the ends ``low`` and
    ``high`` [rad/s] of the operating speeds that lie inside the sweep but are not swept speeds
    (``unbalance --speeds 180:13500:41 --operating-range 7000:9000`` sweeps neither 7,000 nor
    9,000 rpm, where compressor_rotor's probes read their largest: Amax 8 % low, unlike the
    report's sweep, which holds both), shape (n_cases,), -inf where none is read. The model's own
    sources together add their amplitudes (those of one frequency as one harmonic), as the swept
    ``probe_pkpk``."""
    from .unbalance_checks import case_models, same_frequency_groups

    largest = np.full(n_cases, -np.inf)
    speed = np.abs(result.speeds)
    ends = sorted({e for e in (low, high) if speed.size and speed.min() < e < speed.max() and not np.any(speed == e)})
    models = case_models(result, model, high) if ends and probes else None
    if models is None:
        return largest
    sign = np.sign(result.speeds[np.argmax(speed)])
    together = not result.case_rotors
    n_src = len(result.sources) if together else 1
    at = np.repeat(sign * np.array(ends, dtype=float), len(probes) * n_src)
    o = np.tile(np.repeat(np.arange(len(probes)), n_src), len(ends))
    j = np.tile(np.arange(n_src), len(ends) * len(probes))
    groups = same_frequency_groups(result.frequencies_hz) if together else [[0]]
    for c, each in enumerate(models):
        values = result.source_curve(each, list(probes), "displacement")(at, o, j if together else 0 * j)
        values = values.reshape(len(ends) * len(probes), n_src)
        zero_peak = sum(np.abs(values[:, group].sum(axis=1)) for group in groups)
        largest[c] = 2.0 * zero_peak.max()
    return largest


def _operating_speeds(speed, low, high):
    """The sweep's speeds [rad/s] from ``low`` to ``high`` (mask, ''), or, when none lies there,
    the one nearest to them (mask, note naming it)."""
    window = (speed >= low) & (speed <= high)
    if window.any() or not speed.size:
        return window, ""
    k = int(np.argmin(np.abs(speed - np.clip(speed, low, high))))
    window[k] = True
    return window, f" (Amax at {speed[k] * 30 / np.pi:.6g} rpm, the sweep's speed nearest the operating speeds)"
