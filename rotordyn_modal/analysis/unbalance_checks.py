"""Standard checks of an unbalance response: the API 617 probe limit and ISO 20816-3 zones,
and the API 617 / 684 unbalance cases of a model (``docs/standards.md``).

- **Probes** (sensors with ``measure = "relative"``: shaft relative to the stator): the
  peak-to-peak displacement ``sum_j 2 |x_j|`` over the sources (exact for one source; the
  largest the sum of harmonics of different frequencies reaches) against
  ``A1 = 25.4 um sqrt(12000 / N)``, at most 25.4 um, ``N`` [rpm] the maximum continuous speed
  of the probe's rotor (``|speed ratio|`` x the reference rotor's).
- **Casing** (sensors on the stator): the RMS vibration velocity
  ``sqrt(sum_j |v_j|^2 / 2)`` (exact for harmonics of different frequencies), ``|v_j|`` from
  the displacement (x w_j), the velocity, or the acceleration (/ w_j), in the ISO 20816-3 zones
  of a machine group and support class.

Both over the speeds of the sweep in the checked range ``min_speed <= |speed| <= mcs``; for a
response to the API unbalance cases
(:func:`~rotordyn_modal.analysis.unbalance.api_unbalance_response`) each case on its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model import Model
from ..unbalance_standards import api_analysis_unbalance, api_probe_limit, iso_zone_boundaries, iso_zones

__all__ = ["UnbalanceChecks", "unbalance_checks", "api_unbalance_cases", "sensor_groups"]

_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}


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

    def to_dataframe(self):
        """One row per check: ``output, check, speed_rpm, value, amplitude, limit, verdict, zone``
        (then ``case`` for the API unbalance cases).

        ``value`` is the largest over the checked speeds (at ``speed_rpm``): the probe's
        peak-to-peak displacement [m] against the API 617 limit A1 [m] (``verdict`` pass when
        ``value <= limit``), or the casing's RMS velocity [m/s] in its ISO 20816-3 zone
        (``limit`` the B/C boundary; ``verdict`` pass in zones A and B).
        """
        import pandas as pd

        rows = []
        for c, case in enumerate(self.cases):
            if self.mcs is not None:
                for name, values, limit in zip(self.probes, self.probe_pkpk[:, c], self.probe_limits):
                    k, value = self._largest(values)
                    rows.append({"output": name, "check": "API 617 probe limit", "speed_rpm": k, "value": value,
                                 "amplitude": "peak-to-peak", "limit": limit,
                                 "verdict": _verdict(value, value <= limit), "zone": "", "case": case})
            if self.zone_boundaries is not None:
                for name, values in zip(self.casing, self.casing_velocity_rms[:, c]):
                    k, value = self._largest(values)
                    zone = str(iso_zones(value, *self._group_support())) if np.isfinite(value) else ""
                    rows.append({"output": name, "check": f"ISO 20816-3 {self.iso_class}", "speed_rpm": k,
                                 "value": value, "amplitude": "RMS", "limit": self.zone_boundaries[1],
                                 "verdict": _verdict(value, zone in ("A", "B")), "zone": zone, "case": case})
        columns = ["output", "check", "speed_rpm", "value", "amplitude", "limit", "verdict", "zone", "case"]
        return pd.DataFrame(rows, columns=columns if self.cases != ("",) else columns[:-1])

    def _largest(self, values):
        """(speed [rpm], value) of the largest value over the checked speeds (NaN, NaN if none)."""
        if not self.checked.any():
            return np.nan, np.nan
        masked = np.where(self.checked, values, -np.inf)
        k = int(np.argmax(masked))
        return float(self.speeds[k] * 30 / np.pi), float(values[k])

    def _group_support(self):
        group, support = self.iso_class.replace("group ", "").split(", ")
        return int(group), support


def _verdict(value, passed) -> str:
    """'pass', 'fail', or 'no speed checked' (no speed of the sweep in the checked range)."""
    return "no speed checked" if not np.isfinite(value) else ("pass" if passed else "fail")


def unbalance_checks(result, model, mcs=None, min_speed: float = 0.0, iso_group=None,
                     iso_support=None) -> UnbalanceChecks:
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
    sensors = {s.name: s for s in model.sensors}
    probes = [i for i, name in enumerate(result.outputs) if sensors[name].measure == "relative"]
    casing = [i for i, name in enumerate(result.outputs) if sensors[name].rotor is None]
    w = 2 * np.pi * result.frequencies_hz                                   # (n_sources, N)
    limits = np.array([np.nan if mcs is None else
                       float(api_probe_limit(abs(model.rotor(sensors[result.outputs[i]].rotor).speed_ratio)
                                             * mcs * 30 / np.pi)) for i in probes])
    # the sources together (one signal), or each API case alone
    together = not result.case_rotors
    combine = (lambda a: a.sum(axis=1, keepdims=True)) if together else (lambda a: a)
    return UnbalanceChecks(
        speeds=result.speeds, checked=checked, mcs=mcs,
        probes=tuple(result.outputs[i] for i in probes),
        probe_pkpk=combine(2 * _derivative(result, probes, w, 0)),
        probe_limits=limits,
        casing=tuple(result.outputs[i] for i in casing),
        casing_velocity_rms=np.sqrt(combine(_derivative(result, casing, w, 1) ** 2 / 2)),
        zone_boundaries=bounds, iso_class="" if bounds is None else f"group {iso_group}, {iso_support}",
        cases=("",) if together else tuple(result.sources))


def _derivative(result, rows, w, order):
    """0-peak amplitude of derivative ``order`` (0 displacement, 1 velocity) of the rows'
    response, shape (n_rows, n_sources, N); NaN where the frequency is 0 and must divide."""
    amplitude = result.amplitude[rows]
    power = order - _ORDER[result.quantity]
    if power == 0:
        return amplitude
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(w > 0, w ** float(power), np.nan) if power < 0 else w ** float(power)
    return amplitude * scale[None]


def api_unbalance_cases(model, mcs: float):
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

    Parameters
    ----------
    model : Model
    mcs : float
        [rad/s] the reference rotor's maximum continuous speed, > 0.

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
    for rotor in model.rotors:
        n = abs(rotor.speed_ratio) * mcs * 30 / np.pi
        if n == 0:
            continue
        static = [{"rotor": rotor.name, "amount": _api_amount(model, rotor, rotor.mass, n)}]
        cases.append((f"api-static:{rotor.name}", static))
        couple = _couple_unbalances(model, rotor, n)
        if couple:
            cases.append((f"api-couple:{rotor.name}", couple))
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
