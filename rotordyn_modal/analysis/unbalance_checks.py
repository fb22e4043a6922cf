"""Standard checks of an unbalance response: the API 617 probe limit and ISO 20816-3 zones,
and the API 617 / 684 unbalance cases of a model, and the API 684 separation margins of its peaks
from an operating range (``docs/standards.md``).

- **Probes** (sensors with ``measure = "relative"``: shaft relative to the stator): the
  peak-to-peak displacement ``sum_j 2 |x_j|`` over the sources' frequencies (exact for one
  frequency; the largest the sum of harmonics of different frequencies reaches; sources of one
  frequency, rotors at one ``|speed ratio|``, are one harmonic: ``x_j`` the sum of their complex
  amplitudes, :func:`same_frequency_groups`) against
  ``A1 = 25.4 um sqrt(12000 / N)``, at most 25.4 um, ``N`` [rpm] the maximum continuous speed
  of the probe's rotor (``|speed ratio|`` x the reference rotor's).
- **Casing** (sensors on the stator): the RMS vibration velocity
  ``sqrt(sum_j |v_j|^2 / 2)`` over the sources' frequencies (exact: harmonics of different
  frequencies; ``v_j`` of one frequency the sum of its sources' complex amplitudes), ``|v_j|`` from
  the displacement (x w_j), the velocity, or the acceleration (/ w_j), in the ISO 20816-3 zones
  of a machine group and support class.

Both over the speeds of the sweep in the checked range ``min_speed <= |speed| <= mcs``, the ISO
zones over the operating range instead where one is given (``iso_range``: ISO 20816-3 judges
steady operation, not the run-up through a mount's resonance); for a response to the API
unbalance cases
(:func:`~rotordyn_modal.analysis.unbalance.api_unbalance_response`) each case on its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Model
from ..unbalance_standards import (api_analysis_unbalance, api_probe_limit, iso_zone_boundaries, iso_zones,
                                   largest_margins_text, required_separation_margin)

__all__ = ["UnbalanceChecks", "unbalance_checks", "api_unbalance_cases", "api_mode_placements", "ModePlacement",
           "MODE_REACH", "sensor_groups", "separation_margins",
           "operating_range", "case_models", "AF_UNKNOWN", "AF_UNBOUNDED"]

_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}

#: a flexible rotor's API modes of interest reach up to this many times its 1X frequency (the API
#: separation margin's largest requirement is 26 %: a mode up to 1.26 x MCS can need a margin)
MODE_REACH = 1.3
#: a mode is a rotor's when more than this share of its lateral kinetic energy is that rotor's
MODE_ENERGY_SHARE = 0.5
#: an antinode of the other sign at least this fraction of the largest makes the mode's case a
#: couple (an S-shaped mode); a smaller one leaves the one unbalance at the largest
MODE_COUPLE_FRACTION = 0.5
#: two modes of interest of one rotor whose deflection lines have a MAC above this are one shape
#: (a backward/forward pair): one case
_SAME_SHAPE_MAC = 0.9


@dataclass(frozen=True)
class UnbalanceChecks:
    """API 617 probe limits and ISO 20816-3 zones of an unbalance response.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    checked : ndarray of bool, shape (N,)
        The speeds in the checked range.
    mcs : float or None
        [rad/s] maximum continuous speed of the reference rotor.
    probes : tuple of str
        Probe sensors (``measure = "relative"``).
    probe_pkpk : ndarray, shape (n_probes, n_cases, N) [m]
        Peak-to-peak shaft displacement at each probe.
    probe_limits : ndarray, shape (n_probes,) [m]
        API 617 limit A1 (peak-to-peak) of each probe (NaN without ``mcs``).
    casing : tuple of str
        Sensors on the stator.
    casing_velocity_rms : ndarray, shape (n_casing, n_cases, N) [m/s]
    zone_boundaries : tuple of 3 floats or None
        ISO 20816-3 boundaries A/B, B/C, C/D [m/s RMS] (None without a group and support).
    iso_class : str
        e.g. ``'group 2, rigid'`` ('' without zones).
    cases : tuple of str
        The API unbalance cases (one source each), or ``('',)``: all sources together.
    iso_checked : ndarray of bool, shape (N,), or None
        The speeds the ISO zones judge (None: :attr:`checked`): the operating range's, where one
        is given (:attr:`iso_span`).
    iso_span : (float, float) or None
        [rad/s] the operating range the ISO zones judge (None: the checked range).
    min_speed : float
        [rad/s] the bottom of the checked range.
    probe_peak_speeds, probe_peak_pkpk : ndarray, shape (n_probes, n_cases, Q), or None
        Each probe's maxima of the exact response between the swept speeds and at the MCS
        (:func:`.unbalance_peaks.refined_maxima`, as the clearance check) [rad/s] and its peak-to-peak
        displacement there [m], NaN after a curve's last; None where not looked for (no MCS, no
        probe, or a large model: ``UnbalanceResult.cut_peak_note``).
    """

    speeds: np.ndarray
    checked: np.ndarray
    mcs: float | None
    probes: tuple
    probe_pkpk: np.ndarray
    probe_limits: np.ndarray
    casing: tuple
    casing_velocity_rms: np.ndarray
    zone_boundaries: tuple | None = None
    iso_class: str = ""
    cases: tuple = ("",)
    iso_checked: np.ndarray | None = None
    iso_span: tuple | None = None
    min_speed: float = 0.0
    probe_peak_speeds: np.ndarray | None = None
    probe_peak_pkpk: np.ndarray | None = None

    @property
    def zone_checked(self) -> np.ndarray:
        """The speeds the ISO zones judge, shape (N,) of bool: :attr:`iso_checked`, else :attr:`checked`."""
        return self.checked if self.iso_checked is None else self.iso_checked

    def to_dataframe(self):
        """One row per check: ``output, check, speed_rpm, value, amplitude, limit, verdict, zone``
        (then ``case`` for the API unbalance cases).

        ``value`` is the largest over the checked speeds (at ``speed_rpm``): the probe's
        peak-to-peak displacement [m] (its maxima between the swept speeds included:
        :attr:`probe_peak_pkpk`) against the API 617 limit A1 [m] (``verdict`` pass when
        ``value <= limit``), or the casing's RMS velocity [m/s] in its ISO 20816-3 zone
        (``limit`` the B/C boundary; ``verdict`` pass in zones A and B).
        """
        import pandas as pd

        rows = []
        for c, case in enumerate(self.cases):
            if self.mcs is not None:
                for p, (name, values, limit) in enumerate(zip(self.probes, self.probe_pkpk[:, c], self.probe_limits)):
                    k, value = self._probe_largest(p, c, *self._largest(values))
                    rows.append({"output": name, "check": "API 617 probe limit", "speed_rpm": k, "value": value,
                                 "amplitude": "peak-to-peak", "limit": limit,
                                 "verdict": _verdict(value, value <= limit), "zone": "", "case": case})
            if self.zone_boundaries is not None:
                for name, values in zip(self.casing, self.casing_velocity_rms[:, c]):
                    k, value = self._largest(values, self.zone_checked)
                    zone = str(iso_zones(value, *self._group_support())) if np.isfinite(value) else ""
                    rows.append({"output": name, "check": f"ISO 20816-3 {self.iso_class}", "speed_rpm": k,
                                 "value": value, "amplitude": "RMS", "limit": self.zone_boundaries[1],
                                 "verdict": _verdict(value, zone in ("A", "B")), "zone": zone, "case": case})
        columns = ["output", "check", "speed_rpm", "value", "amplitude", "limit", "verdict", "zone", "case"]
        return pd.DataFrame(rows, columns=columns if self.cases != ("",) else columns[:-1])

    def _largest(self, values, checked=None):
        """(speed [rpm], value) of the largest value over the ``checked`` speeds (default
        :attr:`checked`; NaN, NaN if none)."""
        checked = self.checked if checked is None else checked
        if not checked.any():
            return np.nan, np.nan
        masked = np.where(checked, values, -np.inf)
        k = int(np.argmax(masked))
        return float(self.speeds[k] * 30 / np.pi), float(values[k])

    def _probe_largest(self, p, c, speed_rpm, value):
        """(speed [rpm], value [m]) of probe ``p``'s largest pk-pk in case ``c``: the swept
        largest (``speed_rpm``, ``value``) or, where larger, its largest maximum between the swept
        speeds in the checked range (:attr:`probe_peak_pkpk`)."""
        if self.probe_peak_pkpk is None or not np.isfinite(value):
            return speed_rpm, value
        at, peak = self.probe_peak_speeds[p, c], self.probe_peak_pkpk[p, c]
        speed = np.abs(at)
        inside = np.isfinite(at) & (speed >= self.min_speed) & (speed <= self.mcs * (1 + 1e-12))
        if not inside.any():
            return speed_rpm, value
        m = np.flatnonzero(inside)[np.argmax(peak[inside])]
        return (float(at[m] * 30 / np.pi), float(peak[m])) if peak[m] > value else (speed_rpm, value)

    def _group_support(self):
        group, support = self.iso_class.replace("group ", "").split(", ")
        return int(group), support


def _verdict(value, passed) -> str:
    """'pass', 'fail', or 'no speed checked' (no speed of the sweep in the checked range)."""
    return "no speed checked" if not np.isfinite(value) else ("pass" if passed else "fail")


def unbalance_checks(result, model, mcs=None, min_speed: float = 0.0, iso_group=None,
                     iso_support=None, iso_range=None, refine: bool = True) -> UnbalanceChecks:
    """API 617 probe limits and ISO 20816-3 zones of ``result`` (see the module's text).

    Parameters
    ----------
    result : UnbalanceResult
    model : Model
        The model of ``result`` (which sensors are probes, the rotors' speed ratios).
    mcs : float, optional
        [rad/s] the reference rotor's maximum continuous speed, > 0: the probe limits and the
        top of the checked range (default: no probe limit, every speed of the sweep checked).
    min_speed : float
        [rad/s] bottom of the checked range (default 0).
    iso_group : {1, 2}, optional
    iso_support : {'rigid', 'flexible'}, optional
        Both or neither: the ISO 20816-3 class of the machine.
    iso_range : (float, float), optional
        [rad/s] the operating range (:func:`operating_range`): the ISO zones judge the speeds of
        the sweep in it, steady operation (ISO 20816-3 clause 1: the zones apply to steady-state
        operation at the nominal operating speed range, not to transient run-up or run-down);
        default: the checked range (``min_speed`` to ``mcs``).
    refine : bool
        Whether the probes' maxima between the swept speeds are looked for
        (:attr:`UnbalanceChecks.probe_peak_pkpk`; default True); False: the swept speeds only.
    """
    if mcs is not None and not (np.isfinite(mcs) and mcs > 0):
        raise InputError(f"maximum continuous speed {mcs!r} rad/s: expected a finite speed > 0")
    if not (np.isfinite(min_speed) and min_speed >= 0):
        raise InputError(f"minimum speed {min_speed!r} rad/s: expected a finite speed >= 0")
    if mcs is not None and min_speed > mcs:
        raise InputError(f"minimum speed {min_speed!r} rad/s: expected at most the maximum continuous speed "
                         f"{mcs!r} rad/s (the checked speeds run from one to the other)")
    if (iso_group is None) != (iso_support is None):
        raise InputError(f"ISO 20816-3 group {iso_group!r}, support {iso_support!r}: give both (machine group "
                         "1 or 2, support 'rigid' or 'flexible') or neither")
    bounds = None if iso_group is None else iso_zone_boundaries(iso_group, iso_support)
    speed = np.abs(result.speeds)
    checked = (speed >= min_speed) & (speed <= (np.inf if mcs is None else mcs))
    span = None if iso_range is None else operating_range(iso_range)
    iso_checked = None if span is None else _in_range(result.speeds, span)
    sensors = {s.name: s for s in model.sensors}
    probes = [i for i, name in enumerate(result.outputs) if sensors[name].measure == "relative"]
    casing = [i for i, name in enumerate(result.outputs) if sensors[name].rotor is None]
    w = 2 * np.pi * result.frequencies_hz                                   # (n_sources, N)
    limits = np.array([np.nan if mcs is None else
                       float(api_probe_limit(abs(model.rotor(sensors[result.outputs[i]].rotor).speed_ratio)
                                             * mcs * 30 / np.pi)) for i in probes])
    # the sources together (one signal: those of one frequency as one harmonic), or each API case alone
    together = not result.case_rotors
    if together:
        groups = same_frequency_groups(result.frequencies_hz)
        probe_pkpk = 2 * _derivative(result, probes, w, 0, groups).sum(axis=1, keepdims=True)
        casing_rms = np.sqrt((_derivative(result, casing, w, 1, groups) ** 2 / 2).sum(axis=1, keepdims=True))
    else:
        probe_pkpk = 2 * _derivative(result, probes, w, 0)
        casing_rms = np.sqrt(_derivative(result, casing, w, 1) ** 2 / 2)
    peak_speeds, peak_pkpk = _probe_maxima(result, model, mcs, [result.outputs[i] for i in probes], probe_pkpk) \
        if refine else (None, None)
    return UnbalanceChecks(
        speeds=result.speeds, checked=checked, mcs=mcs,
        probes=tuple(result.outputs[i] for i in probes),
        probe_pkpk=probe_pkpk,
        probe_limits=limits,
        casing=tuple(result.outputs[i] for i in casing),
        casing_velocity_rms=casing_rms,
        zone_boundaries=bounds, iso_class="" if bounds is None else f"group {iso_group}, {iso_support}",
        cases=("",) if together else tuple(result.sources), iso_checked=iso_checked, iso_span=span,
        min_speed=float(min_speed), probe_peak_speeds=peak_speeds, probe_peak_pkpk=peak_pkpk)


def _probe_maxima(result, model, mcs, names, pkpk):
    """The probes' maxima between the swept speeds and at ``mcs`` [rad/s]
    (:func:`.unbalance_peaks.refined_maxima`, the clearance check's): (speeds [rad/s], pk-pk [m]),
    each shape (n_probes, n_cases, Q), from the probes' displacement solved again at the searched
    speeds (each API case's model alone, or the model's sources together: the sum of their
    amplitudes, as ``pkpk`` (n_probes, n_cases, N)); (None, None) without ``mcs`` or probes, or
    where the AF table's peaks are not looked for (``cut_peak_note``: a large model)."""
    from .unbalance_peaks import refined_maxima

    if mcs is None or not names or result.cut_peak_note:
        return None, None
    models = case_models(result, model, mcs)
    if models is None:
        return None, None
    bases = [result.source_curve(each, list(names), "displacement") for each in models]
    together = not result.case_rotors
    groups = same_frequency_groups(result.frequencies_hz) if together else None

    def curve(s, o, j):                                          # (K,): the 0-peak displacement
        s, o, j = np.asarray(s, dtype=float), np.asarray(o, dtype=int), np.asarray(j, dtype=int)
        if together:                                             # one harmonic per frequency
            return sum(np.abs(sum(bases[0](s, o, np.full(o.shape, k)) for k in group)) for group in groups) + 0j
        out = np.empty(s.shape, dtype=complex)
        for each in np.unique(j):
            mine = np.flatnonzero(j == each)
            out[mine] = bases[each](s[mine], o[mine], np.zeros(mine.size, dtype=int))
        return out

    return refined_maxima(curve, result.speeds, pkpk, mcs)


def case_models(result, model, mcs):
    """The models whose unbalances excite each case of ``result``: ``[model]`` for the model's own
    unbalances together, else each API case's model (:func:`api_unbalance_cases`
    of ``mcs`` [rad/s]) in the order of ``result.sources``; None where a case's model is not known
    (no ``mcs``, or a source that is no API case of it)."""
    if not result.case_rotors:
        return [model]
    cases = dict(api_unbalance_cases(model, mcs)) if mcs is not None else {}
    if any(name not in cases for name in result.sources):
        return None
    return [cases[name] for name in result.sources]


def operating_range(operating) -> tuple:
    """An operating range ``(low, high)`` [rad/s], or one operating speed (a range of one speed),
    checked: finite, both ends of one sign and not 0, ``|low| <= |high|`` after ordering.

    Returns
    -------
    (float, float)
        The range's ends ordered by magnitude: the one nearer zero speed first.
    """
    ends = np.atleast_1d(np.asarray(operating, dtype=float)).ravel()
    if ends.size == 1:
        ends = np.repeat(ends, 2)
    if ends.size != 2 or not np.all(np.isfinite(ends)) or not (np.all(ends > 0) or np.all(ends < 0)):
        raise InputError(f"operating range {np.asarray(operating).tolist()!r} rad/s: expected one speed or two "
                         "(low, high), finite, of one direction of spin and not 0 (the separation margin is a "
                         "percentage of them)")
    near, far = sorted(ends.tolist(), key=abs)
    return float(near), float(far)


def _in_range(speeds, span) -> np.ndarray:
    """Which of ``speeds`` (N,) [rad/s] lie in the range ``span`` (its direction of spin), shape (N,)."""
    sign = np.sign(span[0])
    speed = sign * np.asarray(speeds, dtype=float)
    return (speed >= abs(span[0]) * (1 - 1e-12)) & (speed <= abs(span[1]) * (1 + 1e-12))


def separation_margins(result, operating, outputs=None, amplitude: str = "peak"):
    """API 684 peaks of an unbalance response with their separation margin from an operating range.

    A peak below the range (nearer zero speed than its nearer end: the minimum operating
    speed) is measured from that end, one above it from its far end (the maximum continuous
    speed), each as a percentage of that end (``UnbalanceResult.peaks`` at that end, with its
    required margin: below or above); a peak inside the range has margin 0 (against the
    required margin of a critical speed above the range's low end) and fails where a margin is
    required (AF >= 2.5). One operating speed is a range of one speed: the table is then that of
    ``UnbalanceResult.peaks(speed)``. A peak of a curve at round-off is left out (as ``peaks``).

    Parameters
    ----------
    result : UnbalanceResult
    operating : float or (float, float) [rad/s]
        The operating speed or range (:func:`operating_range`), in the direction of spin of
        some speed of the sweep.
    outputs : sequence of str, optional
        The outputs whose peaks count (default all).
    amplitude : {'peak', 'pk-pk', 'rms'}
        As ``UnbalanceResult.peaks``.

    Returns
    -------
    pandas.DataFrame
        ``peaks`` columns plus ``verdict``: 'pass' when margin >= required, 'fail' else. Where the
        amplification factor is unknown (the amplitude does not fall to peak / sqrt(2) on both
        sides within the sweep), what is known: 'pass' where the margin is at least the largest
        any AF requires on its side (16 % below, 26 % above: ``required_margin_pct`` is then that
        largest), else 'not evaluated' (:data:`AF_UNKNOWN` says why in one line).
    """
    import pandas as pd

    near, far = operating_range(operating)
    below, above = result.peaks(near, amplitude=amplitude), result.peaks(far, amplitude=amplitude)
    speed = np.sign(near) * below["speed_rpm"].to_numpy(dtype=float) * np.pi / 30   # along the range's spin
    under, over = speed < abs(near), speed > abs(far)
    table = below.copy()
    table["separation_margin_pct"] = np.where(under, below["separation_margin_pct"],
                                              np.where(over, above["separation_margin_pct"], 0.0))
    # a peak above the range needs the margin of a critical speed above it (API 617)
    required = np.where(over, above["required_margin_pct"], below["required_margin_pct"]).astype(float)
    # an unknown AF: the margin against the largest any AF requires on its side (AF-independent)
    largest = np.where(over, required_separation_margin(np.inf, "above"), required_separation_margin(np.inf, "below"))
    met = np.isnan(required) & (table["separation_margin_pct"].to_numpy(dtype=float) >= largest)
    table["required_margin_pct"] = np.where(met, largest, required)
    if outputs is not None:
        table = table[table["output"].isin(list(outputs))].reset_index(drop=True)
    required = table["required_margin_pct"].to_numpy(dtype=float)
    table["verdict"] = np.where(np.isnan(required), "not evaluated",
                                np.where(table["separation_margin_pct"] >= required, "pass", "fail"))
    return pd.DataFrame(table)


#: why a peak's separation margin is 'not evaluated' (:func:`separation_margins`), one line
#: the line under a peaks table with an unbounded peak (amplitude inf: an undamped mode)
AF_UNBOUNDED = ("amplitude inf, AF inf: the response is unbounded at that speed, the critical speed where the "
                "source's 1X line meets an undamped mode (a root on the imaginary axis), found exactly: no damping "
                "bounds it (the swept curve's top is that of the swept speeds beside it)")
AF_UNKNOWN = ("AF unknown: the amplitude does not fall to peak/sqrt(2) on both sides of the peak within the "
              f"sweep; its margin passes only where it is at least what any AF requires "
              f"({largest_margins_text(' the range')}), else not evaluated")


def same_frequency_groups(frequencies_hz) -> list:
    """The sources of an unbalance response grouped by frequency: those whose frequency is the
    same at every speed (rotors at one ``|speed ratio|``: a belt or gear of ratio 1, a direct
    coupling) put one harmonic on a sensor, the sum of their complex amplitudes.

    Parameters
    ----------
    frequencies_hz : ndarray, shape (n_sources, N) [Hz]
        Each source's frequency at each speed (``UnbalanceResult.frequencies_hz``).

    Returns
    -------
    list of list of int
        The sources' indices, one list per frequency, in the order of their first source; equal
        within ``1e-12`` relative (a ratio reached through two transmissions may differ in its
        last bits).
    """
    f = np.asarray(frequencies_hz, dtype=float)
    groups = []
    for j in range(f.shape[0]):
        for group in groups:
            if np.allclose(f[j], f[group[0]], rtol=1e-12, atol=0.0):
                group.append(j)
                break
        else:
            groups.append([j])
    return groups


def _derivative(result, rows, w, order, groups=None):
    """0-peak amplitude of derivative ``order`` (0 displacement, 1 velocity) of the rows'
    response, shape (n_rows, n_sources, N); NaN where the frequency is 0 and must divide. With
    ``groups`` (:func:`same_frequency_groups`), one harmonic per group, shape (n_rows, n_groups,
    N): the modulus of the sum of its sources' complex amplitudes ``response`` (one frequency:
    one time signal ``Re(sum_j X_j e^{i w t})``, docs/model-file.md "Unbalance phase reference")."""
    amplitude = result.amplitude[rows]
    if groups is not None:
        phasor = result.response[rows]
        amplitude = np.stack([np.abs(phasor[:, group].sum(axis=1)) for group in groups], axis=1)
        w = w[[group[0] for group in groups]]
    power = order - _ORDER[result.quantity]
    if power == 0:
        return amplitude
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(w > 0, w ** float(power), np.nan) if power < 0 else w ** float(power)
    return amplitude * scale[None]


def api_unbalance_cases(model, mcs: float, reach: float = MODE_REACH):
    """The API 617 / API 684 unbalance cases of a model, each a model of its own.

    For every rotor ``j`` (maximum continuous speed ``N_j = |r_j| mcs`` [rpm]):

    - ``api-static:ROTOR`` (the cylindrical, first mode): one unbalance ``Ua = 2 x 6350 m_j / N_j``
      [g mm] (twice the residual unbalance, API 617) at the rotor's centre of mass (its "midspan"
      for a rigid rotor), ``m_j`` its mass;
    - ``api-couple:ROTOR`` (the conical, second mode), for a rotor on bearings at two or more
      axial places: one unbalance at each of its outermost bearings' planes, 180 deg apart,
      each ``2 x 6350 (m_j / 2) / N_j`` (the journal static load of a rotor centred between two
      bearings): a pure couple, whatever the place of the centre of mass. (Amounts from each
      bearing's own static load would cancel the couple about the centre of mass where the
      rotor overhangs its bearings: the lever rule's moment balance.)
    - ``api-mode1:ROTOR``, ``api-mode2:ROTOR``, ... for a flexible rotor (one with a shaft): one
      case per lateral mode of interest of the rotor (:func:`api_mode_placements`: the undamped
      modes at the MCS up to ``reach`` times its 1X frequency whose kinetic energy is mostly this
      rotor's lateral motion, a backward/forward pair once), numbered by ascending frequency among them, the
      unbalance at the mode's antinodes (a mesh node each, by ``axial_position``): the static
      amount at the largest, or, where an antinode of the other sign reaches half of it, the
      couple amounts at the two, 180 deg apart. Rigid rotors have none.

    Parameters
    ----------
    model : Model
    mcs : float
        [rad/s] the reference rotor's maximum continuous speed, > 0.
    reach : float
        The modes of interest of a flexible rotor reach up to ``reach`` times its 1X frequency
        ``N_j / 60`` [Hz] (default 1.3: the API separation margin's largest requirement, 26 %,
        with room), >= 0.

    Returns
    -------
    list of (str, Model)
        Case name and the model with that case's unbalances in place of its own.
    """
    if not (np.isfinite(mcs) and mcs > 0):
        raise InputError(f"maximum continuous speed {mcs!r} rad/s: expected a finite speed > 0")
    data = model.to_dict()
    cases = []
    if not model.rotors:
        raise InputError(f"{model.source}: the model has no [[rotors]]: no API unbalance case to make")
    placements = None
    for rotor in model.rotors:
        n = abs(rotor.speed_ratio) * mcs * 30 / np.pi
        if n == 0:
            continue
        static = [{"rotor": rotor.name, "amount": _api_amount(model, rotor, rotor.mass, n)}]
        cases.append((f"api-static:{rotor.name}", static))
        couple = _couple_unbalances(model, rotor, n)
        if couple:
            cases.append((f"api-couple:{rotor.name}", couple))
        if rotor.flexible is not None:
            if placements is None:             # one modal solution of the machine for every rotor
                placements = api_mode_placements(model, mcs, reach)
            for k, place in enumerate((p for p in placements if p.rotor == rotor.name), start=1):
                cases.append((f"api-mode{k}:{rotor.name}", _mode_unbalances(model, rotor, n, place)))
    return [(name, Model.from_dict({**data, "unbalances": tables}, model.source)) for name, tables in cases]


def _api_amount(model, rotor, mass, n_rpm) -> float:
    """``api_analysis_unbalance(mass, n_rpm)`` [kg m], or an :class:`InputError` where it is below
    the smallest amount a model holds (``_table.SMALLEST_POSITIVE``): a rotor of almost no mass,
    whose case the model would refuse naming an amount its file does not hold."""
    from ..model._table import SMALLEST_POSITIVE, visible

    amount = api_analysis_unbalance(mass, n_rpm)
    if not amount >= SMALLEST_POSITIVE:
        raise InputError(f"{model.source}: [rotors.{visible(rotor.name)}] mass = {rotor.mass!r}: the API unbalance "
                         f"case of this rotor at {n_rpm:.6g} rpm would be {amount:.3g} kg m, below the smallest "
                         f"amount a model holds ({SMALLEST_POSITIVE:g} kg m): expected a rotor mass that makes one")
    return amount


def _couple_unbalances(model, rotor, n_rpm):
    """The two ``[[unbalances]]`` tables of a rotor's couple case (none with fewer than two
    bearing planes): ``2 x 6350 (m / 2) / N`` at each outermost bearing plane, 180 deg apart."""
    e = model.spin_axis
    centre = np.asarray(rotor.center_of_mass, dtype=float)
    offsets = sorted({float((np.asarray(b.position, dtype=float) - centre) @ e) for b in model.bearings_of(rotor.name)})
    if len(offsets) < 2:
        return []
    amount = _api_amount(model, rotor, rotor.mass / 2, n_rpm)
    return [{"rotor": rotor.name, "amount": amount, "phase_deg": phase, "axial_offset": offset}
            for phase, offset in ((0.0, offsets[0]), (180.0, offsets[-1]))]


@dataclass(frozen=True)
class ModePlacement:
    """Where a flexible rotor's API mode case puts its unbalance (:func:`api_mode_placements`).

    Attributes
    ----------
    rotor : str
    frequency_hz : float
        The undamped mode's natural frequency at the MCS [Hz].
    energy_share : float
        The rotor's share of the mode's kinetic energy (its lateral motion), 0 to 1.
    stations : tuple of float
        [m] from the shaft's start (``axial_position``), each a mesh node: one (the largest
        deflection) or two (a couple: the two antinodes, increasing).
    phases_deg : tuple of float
        ``(0.0,)`` or ``(0.0, 180.0)``.
    position : ndarray, shape (N,) [m]
        The mesh nodes, from the shaft's start.
    deflection : ndarray, shape (N,)
        The mode's lateral deflection at the nodes in its plane of largest motion, real, the
        largest +1.
    """

    rotor: str
    frequency_hz: float
    energy_share: float
    stations: tuple
    phases_deg: tuple
    position: np.ndarray
    deflection: np.ndarray

    @property
    def couple(self) -> bool:
        """True for an S-shaped mode's two unbalances 180 deg apart."""
        return len(self.stations) == 2


def api_mode_placements(model, mcs: float, reach: float = MODE_REACH) -> list:
    """The lateral modes of interest of each flexible rotor and where its API mode case puts the
    unbalance (:func:`api_unbalance_cases`' ``api-mode{k}:ROTOR``).

    The machine's **undamped** modes at the reference speed ``mcs`` (every damping matrix left
    out, the gyroscopic terms and each bearing's stiffness at that speed kept:
    ``(lam^2 M + lam mcs G + K) phi = 0``, a dense eigen-solution of its states). A mode
    ``phi`` of natural frequency ``f = Im(lam) / 2 pi`` is a **mode of interest** of flexible
    rotor ``j`` (maximum continuous speed ``N_j = |r_j| mcs`` [rpm]) when

    - ``0 < f <= reach N_j / 60``, and
    - more than :data:`MODE_ENERGY_SHARE` (half) of its kinetic energy ``phi^H M phi`` is the
      lateral motion (translation and tilt normal to the spin axis) of rotor ``j``'s shaft, disks
      and point masses: the mode moves this rotor, not the casing, another rotor, or the shaft
      along or about its axis;
    - its deflection line is not one already taken (MAC above 0.9 with a lower one of the same
      rotor: the backward/forward pair of one shape, or the two planes of anisotropic bearings,
      give one case).

    The deflection line is the lateral displacement at the mesh nodes in the transverse axis
    (``a`` or ``b``) where the mode moves most, made real by the phase of its largest value (+1).
    Its antinodes are the nodes whose ``|w|`` is at least their neighbours'. The unbalance goes
    at the node of largest ``|w|`` (the static amount), unless an antinode of the opposite sign
    reaches :data:`MODE_COUPLE_FRACTION` (half) of it: then at the largest such antinode and the
    largest one, 180 deg apart (the couple amounts).

    Parameters
    ----------
    model : Model
    mcs : float
        [rad/s] the reference rotor's maximum continuous speed, > 0.
    reach : float
        >= 0 (default :data:`MODE_REACH`).

    Returns
    -------
    list of ModePlacement
        Rotor by rotor in model order, each rotor's by ascending frequency.
    """
    if not (np.isfinite(mcs) and mcs > 0):
        raise InputError(f"maximum continuous speed {mcs!r} rad/s: expected a finite speed > 0")
    if not (isinstance(reach, (int, float, np.floating, np.integer)) and np.isfinite(reach) and reach >= 0):
        raise InputError(f"reach {reach!r}: expected a finite number >= 0 (times the rotor's 1X frequency)")
    flexible = [r for r in model.rotors if r.flexible is not None and r.speed_ratio != 0]
    if not flexible:
        return []
    made = model.__dict__.setdefault("_api_mode_placements", {})
    key = (float(mcs), float(reach))
    if key not in made:
        made[key] = _mode_placements(model, float(mcs), float(reach), flexible)
    return list(made[key])


#: models up to this many coordinates get their undamped modes from the dense eigen-solution of
#: all their states; larger ones on a basis of the lowest modes of their symmetric parts
_FULL_STATES_DOF = 400
#: the basis reaches this many times the highest frequency of interest (the gyroscopic terms couple
#: a mode to its neighbours in frequency only)
_BASIS_REACH = 4.0
#: and holds at least this many modes
_BASIS_MODES = 24


def _undamped_modes(model, speed, top_hz):
    """``(frequencies [Hz] (m,), shapes (m, n), M)``: the undamped oscillating modes at ``speed``
    [rad/s] up to ``top_hz`` at least, increasing (dense or sparse ``M``)."""
    from ..assembly import is_large, sparse_bearing_matrices, sparse_constant_matrices

    if is_large(model):
        M, _, G, K = sparse_constant_matrices(model)
        if model.speed_dependent:
            K = K + sparse_bearing_matrices(model, speed, dependent_only=True)[0]
    else:
        M, _, G, K = (np.asarray(x) for x in model.matrices(speed))
    n = M.shape[0]
    if n <= _FULL_STATES_DOF:
        values, shapes = _state_modes(M, speed * G, K)
    else:
        basis = _symmetric_basis(M, K, 2 * np.pi * _BASIS_REACH * top_hz)
        project = lambda X: np.asarray(basis.T @ (X @ basis))             # noqa: E731
        values, reduced = _state_modes(project(M), speed * project(G), project(K))
        shapes = reduced @ basis.T
    return values.imag / (2 * np.pi), shapes, M


def _state_modes(M, G, K):
    """The oscillating roots ``lam`` (Im > 0, increasing) and shapes (m, n) of
    ``(lam^2 M + lam G + K) phi = 0``, from a dense eigen-solution of the states."""
    import scipy.linalg

    from . import _batches

    n = len(M)
    eye, zero = np.eye(n), np.zeros((n, n))
    A = np.block([[zero, eye], [-K, -G]])
    B = np.block([[eye, zero], [zero, M]])
    with _batches.one_blas_thread(72 * (2 * n) ** 2):
        values, vectors = scipy.linalg.eig(A, B)
    finite = np.isfinite(values)
    largest = float(np.abs(values[finite]).max()) if finite.any() else 0.0
    keep = np.flatnonzero(finite & (values.imag > 1e-9 * largest))
    keep = keep[np.argsort(values[keep].imag)]
    return values[keep], vectors[:n, keep].T


def _symmetric_basis(M, K, top):
    """(n, b): the modes of ``(sym K, M)`` up to ``top`` [rad/s] and at least :data:`_BASIS_MODES`
    (M-orthonormal; dense ``eigh`` or sparse shift-invert ``eigsh``, shifted below zero: a free
    motion's zero stiffness is no pole)."""
    import scipy.linalg
    import scipy.sparse
    import scipy.sparse.linalg

    from . import _batches

    n = M.shape[0]
    Ks = 0.5 * (K + K.T)
    if not scipy.sparse.issparse(M):
        with _batches.one_blas_thread(72 * n ** 2):
            squares, vectors = scipy.linalg.eigh(Ks, M)
        count = max(int(np.count_nonzero(squares <= top ** 2)), min(_BASIS_MODES, n))
        return vectors[:, :count]
    shift = -max(1e-6 * top ** 2, 1e-12)
    count = min(_BASIS_MODES, n - 2)
    while True:
        squares, vectors = scipy.sparse.linalg.eigsh(Ks.tocsc(), k=count, M=M.tocsc(), sigma=shift, which="LM")
        order = np.argsort(squares)
        squares, vectors = squares[order], vectors[:, order]
        if squares[-1] > top ** 2 or count >= n - 2:
            return vectors
        count = min(2 * count, n - 2)


def _mode_placements(model, mcs, reach, rotors):
    from ..assembly import flexible_rotor_matrices
    from ..model.geometry import transverse_axes

    top = reach * mcs / (2 * np.pi) * max(abs(r.speed_ratio) for r in rotors)       # [Hz]
    frequencies, shapes, M = _undamped_modes(model, mcs, top)
    e = np.asarray(model.spin_axis, dtype=float)
    a, b = transverse_axes(e)
    totals = np.array([np.real(phi.conj() @ (M @ phi)) for phi in shapes])
    out = []
    for rotor in rotors:
        top = reach * abs(rotor.speed_ratio) * mcs / (2 * np.pi)          # [Hz]
        parts = flexible_rotor_matrices(model, rotor, kinds=("M",))
        z = np.asarray(rotor.flexible.mesh.z, dtype=float)
        kept = []
        for f, phi, total in zip(frequencies, shapes, totals):
            if f > top * (1 + 1e-12) or not total > 0:
                continue
            motion = np.asarray(parts.motion @ phi).reshape(-1, 6)
            lateral = motion.copy()
            lateral[:, :3] -= np.outer(motion[:, :3] @ e, e)
            lateral[:, 3:] -= np.outer(motion[:, 3:] @ e, e)
            lateral = lateral.ravel()
            share = float(np.real(lateral.conj() @ (parts.M @ lateral)) / total)
            if not share > MODE_ENERGY_SHARE:
                continue
            u = motion[:, :3]
            planes = [u @ a, u @ b]
            plane = max(planes, key=lambda w: float(np.abs(w).max()))
            w = plane / plane[int(np.argmax(np.abs(plane)))]
            w = w.real
            if any(abs(w @ p.deflection) ** 2 > _SAME_SHAPE_MAC * (w @ w) * (p.deflection @ p.deflection)
                   for p in kept):
                continue
            stations, phases = _antinode_stations(z, w)
            kept.append(ModePlacement(rotor.name, float(f), share, stations, phases, z, w))
        out += kept
    return out


def _antinode_stations(z, w):
    """``(stations, phases)`` of a deflection line ``w`` (largest +1) at nodes ``z``: the largest,
    or it and the largest antinode of the other sign reaching :data:`MODE_COUPLE_FRACTION` of it."""
    size = np.abs(w)
    i0 = int(np.argmax(size))
    left = np.concatenate([[-np.inf], size[:-1]])
    right = np.concatenate([size[1:], [-np.inf]])
    antinodes = np.flatnonzero((size >= left) & (size >= right))
    other = [i for i in antinodes if np.sign(w[i]) == -np.sign(w[i0]) and size[i] >= MODE_COUPLE_FRACTION * size[i0]]
    if not other:
        return (float(z[i0]),), (0.0,)
    i1 = max(other, key=lambda i: size[i])
    first, second = sorted((i0, i1))
    return (float(z[first]), float(z[second])), (0.0, 180.0)


def _mode_unbalances(model, rotor, n_rpm, place):
    """The ``[[unbalances]]`` tables of a rotor's mode case at ``place`` (a :class:`ModePlacement`)."""
    mass = rotor.mass if not place.couple else rotor.mass / 2
    amount = _api_amount(model, rotor, mass, n_rpm)
    return [{"rotor": rotor.name, "amount": amount, "phase_deg": phase, "axial_position": z}
            for z, phase in zip(place.stations, place.phases_deg)]


def sensor_groups(model) -> dict:
    """Panel title of each sensor of ``model`` in the unbalance figure (``UnbalanceResult.plot(groups=...)``):
    what the checks judge it as, shaft probes (measure 'relative': API 617 probe limits), rotor
    points (absolute) or stator (casing) sensors (ISO 20816-3 zones); ``{name: title}``."""
    def title(sensor):
        if sensor.rotor is None:
            return "stator (casing) sensors, absolute"
        return "shaft relative to the stator (probes)" if sensor.measure == "relative" else \
            "rotor points, absolute"
    return {s.name: title(s) for s in model.sensors}


def with_bearing_probes(model):
    """``model`` with an X-Y pair of proximity probes (``measure = "relative"``: the shaft's
    motion relative to the stator point at the same place) at each bearing, where the model has
    no ``[[sensors]]``: the stations where API 684 reads a rotor's unbalance response when the
    machine's own probe positions are not given. Each pair measures along the two model axes
    normal to the spin axis (the spin axis off them: two directions normal to it), named
    ``"BEARING probe AXIS"`` (``"Bearing 0 probe x"``); placed as its bearing is (``position``,
    or ``axial_position`` on a flexible rotor).

    Parameters
    ----------
    model : Model

    Returns
    -------
    (Model, list of str)
        The model with the probes (``model`` itself where it has sensors or no bearings), and
        the probes' names (empty then).
    """
    if model.sensors or not model.bearings:
        return model, []
    data = model.to_dict()
    probes = [dict(name=f"{bearing['name']} probe {label}", rotor=bearing["rotor"], direction=[float(v) for v in direction],
                   measure="relative", **_station_of(bearing))
              for bearing in data.get("bearings", []) for label, direction in _lateral_axes(model.spin_axis)]
    data["sensors"] = probes
    return Model.from_dict(data, model.source), [p["name"] for p in probes]


def _station_of(bearing: dict) -> dict:
    """The placing keys of a bearing's table (``axial_position`` on a flexible rotor, else ``position``)."""
    return {key: bearing[key] for key in ("axial_position", "position") if key in bearing}


def _lateral_axes(spin_axis):
    """The two probe directions normal to ``spin_axis`` (3,), with their labels: the model axes
    normal to it (``"x"``, ``"y"``, ``"z"``) where it lies along one, else ``"a"`` (the model axis
    least along it, its part normal to the spin) and ``"b"`` (normal to both)."""
    spin = np.asarray(spin_axis, dtype=float)
    spin = spin / np.linalg.norm(spin)
    along = np.abs(spin)
    if np.isclose(along.max(), 1.0, rtol=0.0, atol=1e-12):
        return [("xyz"[i], np.eye(3)[i]) for i in range(3) if i != int(np.argmax(along))]
    first = np.eye(3)[int(np.argmin(along))]
    first = first - (first @ spin) * spin
    first /= np.linalg.norm(first)
    return [("a", first), ("b", np.cross(spin, first))]
