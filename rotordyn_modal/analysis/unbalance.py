"""Steady unbalance response over a speed sweep, each rotor at its own spin frequency.

Rotor ``j`` spins at ``r_j Omega`` about the spin axis ``e`` (``r_j`` its speed
ratio, negative = the other way). An unbalance ``amount`` [kg m] at
``phase_deg`` turns with it; its centrifugal force on the rotor is::

    F(t) = amount w_j^2 (cos(theta(t)) a + sin(theta(t)) b),  theta(t) = r_j Omega t + phase

with ``w_j = |r_j Omega|`` and the **phase reference** ``a``: the component of
the model z-axis normal to ``e`` (the model x-axis when ``e`` is along z),
``b = e x a``; ``phase_deg`` turns from ``a`` towards ``b`` (positive about
``e``). As a complex amplitude at ``e^{i w_j t}`` (``x(t) = Re(x_hat e^{i w_j t})``)
with ``s = sign(r_j Omega)``: ``F_hat = amount w_j^2 e^{i s phase} (a - i s b)``,
applied at ``R_j + axial_offset e``.

Every output ``x(t) = sum_j A_j cos(w_j t + phi_j)``: one harmonic per rotor
(source), reported separately with its 0-peak amplitude ``A_j`` and phase
``phi_j`` (the phase of the cosine at ``t = 0``, degrees).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .._progress import phase
from ..assembly import generalized_force, point_rows, sensor_rows
from ..errors import InputError
from ..linear_system import speed_linear_form
from ..model.components import Sensor
from ..model.geometry import cross, shift_matrices, transverse_axes
from ..unbalance_standards import amplitude_column, amplitude_factor, required_separation_margin
from .. import _arguments
from .forces import COMPONENTS, centre_motions, all_forces
from .frf import dof_response
from .orbits import orbit_ellipses, precession_labels, probe_pairs
from .unbalance_checks import api_unbalance_cases, unbalance_checks

__all__ = ["UnbalanceResult", "unbalance_response", "phase_reference", "unbalance_forces",
           "amplification_factors", "required_separation_margin", "api_unbalance_response"]

_ORDER = {"displacement": 0, "velocity": 1, "acceleration": 2}

#: what ``UnbalanceResult.to_dataframe(forces=...)`` (CLI ``--forces``) adds to the sensors
FORCE_CHOICES = (None, "suspensions", "bearings", "rotors", "all")


#: a response peak at most this share of the response's largest amplitude is round-off, not a
#: resonance (:meth:`UnbalanceResult.peaks` leaves it out)
ROUND_OFF_AMPLITUDE = 1e-9


def phase_reference(spin_axis) -> tuple[np.ndarray, np.ndarray]:
    """Axes ``a`` (phase 0) and ``b = e x a`` (phase 90 deg) in the rotors' plane.

    ``a`` is the model z-axis made normal to the spin axis ``e``; the model
    x-axis when ``e`` is along z.

    Returns
    -------
    a, b : ndarray, shape (3,) each, unit

    Examples
    --------
    >>> a, b = phase_reference([1.0, 0.0, 0.0])   # spin about x: phase 0 along z, 90 deg along -y
    >>> a.tolist(), (b + 0.0).tolist()
    ([0.0, 0.0, 1.0], [0.0, -1.0, 0.0])
    """
    e = np.asarray(spin_axis, dtype=float)
    e = e / np.linalg.norm(e)
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])):
        a = axis - (axis @ e) * e
        if np.linalg.norm(a) > 1e-6:
            a = a / np.linalg.norm(a)
            return a, cross(e, a)
    raise AssertionError("unreachable")  # pragma: no cover


def unbalance_forces(model, speeds):
    """Complex generalized unbalance forces of each rotor, at its centre of mass.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,) [rad/s]

    Returns
    -------
    sources : list of str
        Rotors that carry unbalances.
    frequencies : ndarray, shape (n_sources, N) [rad/s]
        ``|r_j Omega|``.
    forces : ndarray, shape (n_sources, N, 6), complex
        ``[F, C]`` at the rotor's centre of mass [N, N m].
    """
    speeds = np.asarray(speeds, dtype=float)
    a, b = phase_reference(model.spin_axis)
    e = model.spin_axis
    sources = [r.name for r in model.rotors if any(u.rotor == r.name for u in model.unbalances)]
    frequencies, forces = [], []
    for name in sources:
        rotor = model.rotor(name)
        spin = rotor.speed_ratio * speeds
        s, w = np.sign(spin), np.abs(spin)
        total = np.zeros((len(speeds), 6), dtype=complex)
        for u in (u for u in model.unbalances if u.rotor == name):
            force = _force(u, a, b, s, w)
            arm = u.axial_offset * e
            total += np.concatenate([force, np.cross(arm, force)], axis=1)
        frequencies.append(w)
        forces.append(total)
    return sources, np.array(frequencies).reshape(-1, len(speeds)), np.array(forces).reshape(-1, len(speeds), 6)


def _force(u, a, b, s, w) -> np.ndarray:
    """The complex force of unbalance ``u`` (N, 3) [N] at spin signs ``s`` and frequencies ``w``."""
    direction = degree_phasor(u.phase_deg, s)[:, None] * (a - 1j * s[:, None] * b)
    return u.amount * w[:, None] ** 2 * direction


def degree_phasor(phase_deg, sign=1.0):
    """``exp(i sign phase)`` of a phase in degrees, exact where the phase is a multiple of 90 deg
    (``scipy.special.cosdg``, ``sindg``): ``exp(1j * radians(180))`` has an imaginary part of
    1.2e-16, so two equal unbalances 180 deg apart left a force of that size and a response
    of 1e-21 m printed at a phase of 178 deg instead of none. ``sign`` (array_like): the spin
    signs, +-1."""
    import scipy.special

    return scipy.special.cosdg(phase_deg) + 1j * np.asarray(sign) * scipy.special.sindg(phase_deg)


def _flexible_generalized(model, name: str, speeds) -> np.ndarray:
    """Generalized forces of a flexible rotor's unbalances, each at its node, (N, n_dof)."""
    rotor = model.rotor(name)
    a, b = phase_reference(model.spin_axis)
    spin = rotor.speed_ratio * np.asarray(speeds, dtype=float)
    total = 0.0
    for u in (u for u in model.unbalances if u.rotor == name):
        point = np.asarray(rotor.center_of_mass) + u.axial_offset * model.spin_axis
        wrench = np.concatenate([_force(u, a, b, np.sign(spin), np.abs(spin)), np.zeros((len(spin), 3))], axis=1)
        total = total + generalized_force(model, name, point, wrench,
                                          motion=model.dofs.body_motion(name, point))
    return total


@dataclass(frozen=True)
class UnbalanceResult:
    """Steady unbalance response over speed, one harmonic per source rotor.

    Attributes
    ----------
    speeds : ndarray, shape (N,) [rad/s]
    sources : tuple of str
        Rotors with unbalances.
    frequencies_hz : ndarray, shape (n_sources, N) [Hz]
        Each source's excitation frequency ``|r_j Omega| / 2 pi``.
    outputs : tuple of str
        Sensor names.
    response : ndarray, shape (n_outputs, n_sources, N), complex
        Complex amplitude of each harmonic [m, m/s or m/s^2 by ``quantity``].
    quantity : str
    suspension_names, rotor_names : tuple of str
    ground_forces : ndarray, shape (n_suspensions, 6, n_sources, N), complex
        Force each suspension passes to the ground, ``[F, C]`` at its point [N, N m].
    bearing_forces : ndarray, shape (n_rotors, 6, n_sources, N), complex
        Force each rotor passes to the stator at its centre of mass [N, N m].
    bearing_names : tuple of str
        The model's ``[[bearings]]``.
    bearing_point_forces : ndarray, shape (n_bearings, 6, n_sources, N), complex
        Force each bearing passes to the stator (or the ground), ``[F, C]`` at its point.
    orbit_pairs : tuple of (str, str)
        Sensor pairs that see an orbit (same point, body and measure; directions normal
        to the spin axis), see :mod:`rotordyn_modal.analysis.orbits`.
    orbit_planes : ndarray, shape (n_pairs, n_sources, N, 2), complex
        In-plane amplitudes ``(D_u, D_w)`` of each pair's point (``u`` the first sensor's
        direction, ``w = e x u``).
    spin_signs : ndarray, shape (n_sources, N)
        +1 where the source rotor spins about +spin_axis, -1 about -spin_axis.
    rigid_rotor_names : tuple of str
        Rotors rigidly attached to the stator (no ``[[bearings]]``): their force on the
        stator is their bearings' force.
    amplitude_kind : {'peak', 'pk-pk', 'rms'}
        The amplitude convention of the tables' added column and of the figure (the
        ``amplitude`` column and attribute stay 0-peak).
    case_rotors : tuple of str
        Empty, or (a response to the API unbalance cases, see
        :func:`api_unbalance_response`) the rotor
        of each source, the sources then being the cases: the tables' ``source`` is the
        rotor and a last column ``case`` names the case.
    resonance_speeds : ndarray, shape (n_sources, P), or None
        Each source's damped critical speeds [rad/s] within the sweep that no swept speed
        resolves (none within a quarter of the mode's half-power band in speed), NaN after
        its last (:func:`~rotordyn_modal.analysis.unbalance_peaks.unresolved_criticals`);
        None where not computed (loss factors, a large model).
    resonance_bands : ndarray, shape (n_sources, P), or None
        The half-power band in speed [rad/s] of the mode there.
    resonance_response : ndarray, shape (n_outputs, n_sources, P), complex, or None
        The response at those speeds.
    cut_peak_speeds : ndarray, shape (n_outputs, n_sources, Q), or None
        Each curve's maxima of the amplitude between swept speeds that the line through the
        swept speeds cuts (more than sqrt(2) times both swept amplitudes around it), found on
        the exact response near those damped critical speeds
        (:func:`~rotordyn_modal.analysis.unbalance_peaks.cut_maxima`: two close modes sharing
        one peak give one maximum, at the peak) [rad/s], NaN after a curve's last; None where
        not computed.
    cut_peak_response : ndarray, shape (n_outputs, n_sources, Q), complex, or None
        The response there.
    cut_peak_widths : ndarray, shape (n_outputs, n_sources, Q), or None
        The width ``N2 - N1`` [rad/s] between the peak's half-power points on the exact
        response (API 684's amplification factor is ``|speed| / width``).
    peak_swept_speeds : ndarray, shape (n_outputs, n_sources, Q), or None
        Each curve's swept peaks (:func:`amplification_factors`' speeds) [rad/s], NaN after a
        curve's last; None where not computed (a large model, ``resonances=False``, or a search
        costing more than about a second: the table's AF then from the swept speeds).
    peak_speeds : ndarray, shape (n_outputs, n_sources, Q), or None
        The maximum of the exact response between each swept peak's two neighbours [rad/s]
        (:func:`~rotordyn_modal.analysis.unbalance_peaks.exact_peaks`).
    peak_response : ndarray, shape (n_outputs, n_sources, Q), complex, or None
        The response there.
    peak_half_power : ndarray, shape (n_outputs, n_sources, Q, 2), or None
        Its half-power points ``N1, N2`` on the exact response [rad/s] (NaN on a side where the
        amplitude does not fall to peak / sqrt(2) within the sweep).
    cut_peak_note : str
        Why those peaks were not looked for ('not looked for in a model of 5400 coordinates',
        :func:`~rotordyn_modal.analysis.unbalance_peaks.not_looked_for`; the figure's legend
        says it), or ''.
    """

    speeds: np.ndarray
    sources: tuple
    frequencies_hz: np.ndarray
    outputs: tuple
    response: np.ndarray
    quantity: str
    suspension_names: tuple
    rotor_names: tuple
    ground_forces: np.ndarray
    bearing_forces: np.ndarray
    bearing_names: tuple = ()
    bearing_point_forces: np.ndarray | None = None
    orbit_pairs: tuple = ()
    orbit_planes: np.ndarray | None = None
    spin_signs: np.ndarray | None = None
    rigid_rotor_names: tuple = ()
    amplitude_kind: str = "peak"
    case_rotors: tuple = ()
    clearance_names: tuple = ()
    clearance_planes: np.ndarray | None = None
    resonance_speeds: np.ndarray | None = None
    resonance_bands: np.ndarray | None = None
    resonance_response: np.ndarray | None = None
    cut_peak_speeds: np.ndarray | None = None
    cut_peak_response: np.ndarray | None = None
    cut_peak_widths: np.ndarray | None = None
    cut_peak_note: str = ""
    peak_swept_speeds: np.ndarray | None = None
    peak_speeds: np.ndarray | None = None
    peak_response: np.ndarray | None = None
    peak_half_power: np.ndarray | None = None

    @property
    def amplitude(self) -> np.ndarray:
        """0-peak amplitude, shape (n_outputs, n_sources, N)."""
        return np.abs(self.response)

    @property
    def phase_deg(self) -> np.ndarray:
        """Phase of ``A cos(w t + phase)`` [deg], shape (n_outputs, n_sources, N)."""
        return np.degrees(np.angle(self.response))

    def to_dataframe(self, forces: str | None = None, amplitude: str | None = None):
        """Table ``speed_rpm,output,source,frequency_hz,amplitude,phase_deg`` (``amplitude``
        0-peak), then ``amplitude_pkpk`` or ``amplitude_rms`` when that convention is asked.

        Parameters
        ----------
        forces : {None, 'suspensions', 'bearings', 'rotors', 'all'}
            Force rows ``NAME:Fx ... NAME:Mz`` [N, N m] after the sensors' rows: none
            (default), each suspension's force on the ground, each ``[[bearings]]`` entry's
            force at its point and each rigidly attached rotor's at its centre of mass, each
            rotor's total force on the stator, or the suspensions, bearings and rotors together.
        amplitude : {None, 'peak', 'pk-pk', 'rms'}
            Adds the column of that convention (none for 'peak'); default ``amplitude_kind``.
        """
        import pandas as pd

        force_names, force_values = self._force_rows(forces)
        names = list(self.outputs) + force_names
        values = np.concatenate([self.response, *force_values]) if force_values else self.response
        o, s, k = (x.ravel() for x in np.meshgrid(np.arange(len(names)), np.arange(len(self.sources)),
                                                  np.arange(len(self.speeds)), indexing="ij"))
        v = values[o, s, k]
        table = pd.DataFrame({
            "speed_rpm": self.speeds[k] * 30 / np.pi,
            "output": np.asarray(names, dtype=object)[o],
            "source": np.asarray(self.sources, dtype=object)[s],
            "frequency_hz": self.frequencies_hz[s, k],
            "amplitude": np.abs(v), "phase_deg": np.degrees(np.angle(v)),
        })
        return self._with_cases(_with_convention(table, amplitude or self.amplitude_kind))

    def _force_rows(self, forces):
        """Names and complex amplitudes, shape (6 n_items, n_sources, N), of the asked forces."""
        if forces not in FORCE_CHOICES:
            raise InputError(f"forces {forces!r}: expected one of {', '.join(map(str, FORCE_CHOICES))}")
        parts = []
        if forces in ("suspensions", "all"):
            parts.append((self.suspension_names, self.ground_forces))
        if forces in ("bearings", "all"):
            parts.append((self.bearing_names, self._point_forces()))
        if forces == "bearings":
            rigid = [j for j, name in enumerate(self.rotor_names) if name in self.rigid_rotor_names]
            parts.append(([self.rotor_names[j] for j in rigid], self.bearing_forces[rigid]))
        if forces in ("rotors", "all"):
            parts.append((self.rotor_names, self.bearing_forces))
        names = [f"{item}:{c}" for items, _ in parts for item in items for c in COMPONENTS]
        return names, [values.reshape(-1, *self.response.shape[1:]) for items, values in parts if len(items)]

    def _point_forces(self):
        if self.bearing_point_forces is None:
            return np.zeros((0, 6, *self.response.shape[1:]), dtype=complex)
        return self.bearing_point_forces

    def orbits(self):
        """Orbit of every probe pair, source and speed (``pandas.DataFrame``).

        Columns ``speed_rpm, pair, source, frequency_hz, major, minor, inclination_deg,
        precession, precession_ratio``: semi-axes [output unit], the major axis's angle from
        the first probe towards ``e x u`` [deg], 'forward'/'backward' (turning with/against
        the source rotor's spin) or 'none' (a straight line), and the signed ratio
        ``2ab / (a^2 + b^2)``.
        """
        import pandas as pd

        major, minor, inclination, ratio = orbit_ellipses(self.orbit_planes, self.spin_signs[None])
        p, s, k = (x.ravel() for x in np.meshgrid(np.arange(len(self.orbit_pairs)), np.arange(len(self.sources)),
                                                  np.arange(len(self.speeds)), indexing="ij"))
        return pd.DataFrame({
            "speed_rpm": self.speeds[k] * 30 / np.pi,
            "pair": np.array(["/".join(pair) for pair in self.orbit_pairs], dtype=object).reshape(-1)[p]
            if len(self.orbit_pairs) else np.array([], dtype=object),
            "source": np.asarray(self.sources, dtype=object)[s],
            "frequency_hz": self.frequencies_hz[s, k],
            "major": major[p, s, k], "minor": minor[p, s, k],
            "inclination_deg": inclination[p, s, k],
            "precession": precession_labels(ratio[p, s, k]), "precession_ratio": ratio[p, s, k],
        })

    @staticmethod
    def vector_amplitude(components) -> np.ndarray:
        """:func:`vector_amplitude`: ``sqrt(sum_k |c_k|^2)`` over the first axis (the figure's
        force panels read it here: no import of this module by the figures)."""
        return vector_amplitude(components)

    def orbit_path(self, pair: int, source: int, index: int, points: int = 181) -> np.ndarray:
        """The orbit of probe pair ``pair`` excited by source ``source`` at the sweep's speed
        ``index`` over one period: ``Re(D exp(i phi))`` at ``points`` phases ``phi`` from 0 to
        2 pi (``phi = 0`` the keyphasor's instant, ``t = 0``), ``D = orbit_planes[pair, source, index]``.

        Returns
        -------
        ndarray, shape (2, points) [output unit]
            The first probe's direction, then ``e x u``.
        """
        phase = np.linspace(0, 2 * np.pi, points)
        return np.real(self.orbit_planes[pair, source, index][:, None] * np.exp(1j * phase))

    def plot_orbits(self, speeds=None, **kwargs):
        """Orbits of the probe pairs at a few speeds; see :func:`rotordyn_modal.plotting.plot_orbits`."""
        from ..plotting.orbits import plot_orbits

        return plot_orbits(self, speeds=speeds, **kwargs)

    def cut_peaks(self, output: str, source: str):
        """The peaks of one output's curve of one source that the line drawn through the swept
        speeds cuts: the maxima of the exact response between swept speeds more than sqrt(2)
        (3 dB) times the amplitude at both swept speeds around them (:attr:`cut_peak_speeds`).

        Returns
        -------
        speeds : ndarray, shape (K,) [rad/s]; response : ndarray, shape (K,), complex;
        widths : ndarray, shape (K,) [rad/s] (between the peak's half-power points)
        """
        if self.cut_peak_speeds is None:
            return np.zeros(0), np.zeros(0, complex), np.zeros(0)
        o, j = self.outputs.index(output), self.sources.index(source)
        at = self.cut_peak_speeds[o, j]
        known = np.isfinite(at)
        return at[known], self.cut_peak_response[o, j, known], self.cut_peak_widths[o, j, known]

    def peaks(self, operating_speed: float | None = None, amplitude: str | None = None):
        """Peaks of each sensor's amplitude vs speed with API 684 figures.

        Parameters
        ----------
        operating_speed : float, optional
            [rad/s], not zero; gives the actual separation margin (a percentage of it) and the
            required one of a peak below it or above it (without it: the one below).
        amplitude : {None, 'peak', 'pk-pk', 'rms'}
            Adds the peak's amplitude in that convention as a last column (none for 'peak');
            default ``amplitude_kind``.

        Returns
        -------
        pandas.DataFrame
            ``output, source, speed_rpm, amplitude (0-peak), amplification_factor,
            separation_margin_pct, required_margin_pct`` [, ``amplitude_pkpk`` | ``amplitude_rms``].
            Each peak is reported at the maximum of the exact response, with the response there
            and ``AF = |speed| / (N2 - N1)``, its half-power points on the exact response
            (:attr:`peak_speeds`, :attr:`peak_half_power`; a peak that the line through the swept
            speeds cuts, :meth:`cut_peaks`, too): neither depends on the swept speeds (the swept
            points would give a lower peak and a band interpolated between them; a large model:
            those, ``cut_peak_note``). A peak of a curve at round-off (amplitude at most :data:`ROUND_OFF_AMPLITUDE` times
            the largest of the response, every output and source: an API couple case seen at
            the centre of mass of a symmetric rotor, 3.5e-21 m beside 1e-5 m) is no resonance
            and is left out. A peak of an undamped mode is reported where its response is
            unbounded, its amplitude and AF ``inf`` (at the exact speed where the source's line
            meets the undamped root: :func:`.unbalance_peaks.exact_peaks`), judged at round-off
            by its curve's largest swept amplitude.
        """
        import pandas as pd

        check_operating_speed(self.speeds, operating_speed)

        rows, sizes = [], []
        for i, out in enumerate(self.outputs):
            for j, src in enumerate(self.sources):
                for peak in self._resolved_peaks(out, src):
                    # an unbounded peak (amplitude inf) is judged at round-off by its curve's swept top
                    sizes.append(peak[1] if np.isfinite(peak[1]) else float(np.max(self.amplitude[i, j])))
                    speed, amp, af = peak
                    margin = np.nan if operating_speed is None else \
                        100 * abs(operating_speed - speed) / abs(operating_speed)
                    above = operating_speed is not None and abs(speed) > abs(operating_speed)
                    rows.append({"output": out, "source": src, "speed_rpm": speed * 30 / np.pi,
                                 "amplitude": amp, "amplification_factor": af,
                                 "separation_margin_pct": margin,
                                 "required_margin_pct": required_separation_margin(
                                     af, "above" if above else "below")})
        table = pd.DataFrame(rows, columns=["output", "source", "speed_rpm", "amplitude",
                                            "amplification_factor", "separation_margin_pct",
                                            "required_margin_pct"])
        largest = float(np.max(self.amplitude, initial=0.0))
        table = table[np.array(sizes, dtype=float).reshape(-1) > ROUND_OFF_AMPLITUDE * largest].reset_index(drop=True)
        return self._with_cases(_with_convention(table, amplitude or self.amplitude_kind, after=None))

    def _resolved_peaks(self, output: str, source: str):
        """The swept peaks of one curve read on the exact response (:meth:`_exact_peaks`; where not
        computed, :func:`amplification_factors`), and a peak that the swept speeds cut (:meth:`cut_peaks`) reported
        at the maximum of the exact response, with the response there and ``AF = |speed| / (N2 -
        N1)`` (its half-power points): one between the two swept speeds around a swept peak
        replaces it, one elsewhere (the swept curve showing no peak) is added; ``[(speed [rad/s],
        amplitude, AF), ...]`` by speed."""
        o, j = self.outputs.index(output), self.sources.index(source)
        found = amplification_factors(self.speeds, self.amplitude[o, j]) if self.peak_swept_speeds is None \
            else self._exact_peaks(o, j)
        at, response, band = self.cut_peaks(output, source)
        if not len(at):
            return found
        x = np.sort(self.speeds)
        out = []
        for speed, amp, af in found:
            k = int(np.searchsorted(x, speed))
            lo, hi = x[max(k - 1, 0)], x[min(k + 1, len(x) - 1)]
            inside = (at > lo) & (at < hi)
            if inside.any():
                m = np.flatnonzero(inside)[np.argmax(np.abs(response[inside]))]
                speed, amp, af = float(at[m]), float(abs(response[m])), float(abs(at[m]) / band[m])
                at, response, band = np.delete(at, np.flatnonzero(inside)), \
                    np.delete(response, np.flatnonzero(inside)), np.delete(band, np.flatnonzero(inside))
            out.append((speed, amp, af))
        out += [(float(a), float(abs(r)), float(abs(a) / b)) for a, r, b in zip(at, response, band)]
        return sorted(out, key=lambda peak: peak[0])

    def _exact_peaks(self, o: int, j: int):
        """``[(speed [rad/s], amplitude, AF), ...]`` of each swept peak of curve ``(o, j)`` on the
        exact response (:attr:`peak_speeds`, :attr:`peak_half_power`; AF infinite where the
        response is unbounded, ``N1 = N2``; NaN where a half-power point lies beyond the sweep).
        The swept peaks are :func:`amplification_factors`' (one search,
        :func:`.unbalance_peaks.spin_curves`, of the same curve), read from the fields directly."""
        out = []
        for m in np.flatnonzero(np.isfinite(self.peak_swept_speeds[o, j])):
            at, (low, high) = float(self.peak_speeds[o, j, m]), self.peak_half_power[o, j, m]
            width = abs(high - low)                  # 0: unbounded (an undamped mode), AF infinite
            af = abs(at) / width if width > 0 else (np.inf if width == 0 else np.nan)
            out.append((at, float(abs(self.peak_response[o, j, m])), float(af)))
        return out

    def _with_cases(self, table):
        """A table of the cases' response: ``source`` the case's rotor, the case in a last column."""
        if self.case_rotors:
            rotor_of = dict(zip(self.sources, self.case_rotors))
            table["case"] = table["source"]
            table["source"] = table["source"].map(rotor_of)
        return table

    def checks(self, model, mcs=None, min_speed: float = 0.0, iso_group=None, iso_support=None, iso_range=None):
        """API 617 probe limits and ISO 20816-3 zones (over ``iso_range``, the operating range,
        where given); see :func:`rotordyn_modal.analysis.unbalance_checks.unbalance_checks`
        (speeds in rad/s)."""
        return unbalance_checks(self, model, mcs=mcs, min_speed=min_speed, iso_group=iso_group,
                                iso_support=iso_support, iso_range=iso_range)

    def separation_margins(self, operating, outputs=None, amplitude: str | None = None):
        """:meth:`peaks` with the API 684 separation margin from an operating range ``(low,
        high)`` or speed [rad/s] and a verdict; see
        :func:`rotordyn_modal.analysis.unbalance_checks.separation_margins`."""
        from .unbalance_checks import separation_margins

        return separation_margins(self, operating, outputs=outputs, amplitude=amplitude or self.amplitude_kind)

    @staticmethod
    def station_planes(model, speeds):
        """The close-clearance stations' displacement relative to the stator along the transverse
        axes, shape (n_stations, n_src, K, 2), for ``model``'s unbalances at ``speeds`` (K,) [rad/s]
        (as a result's ``clearance_planes``); the clearance check's search calls it through a result,
        so that it need not import this module (which imports it)."""
        sources, w, rotor_forces = unbalance_forces(model, speeds)
        shifts = shift_matrices(model.reference_point, [r.center_of_mass for r in model.rotors])
        motions = model.dofs.motions([(r.name, False) for r in model.rotors])
        q = _coordinate_response(model, sources, rotor_forces, np.tile(speeds, len(sources)), w.ravel(), shifts,
                                 motions)
        return _clearance_planes(model, q, motions, len(sources), len(speeds))

    @staticmethod
    def source_curve(model, outputs, quantity: str = "displacement"):
        """``curve(s, o, j)``: the response of ``model``'s sensor ``outputs[o[k]]`` to its source
        ``j[k]`` alone at the speed ``s[k]`` [rad/s], shape (K,), complex (the AF table's search's,
        :func:`_own_source_curve`); the checks' searches call it through a result, so that they
        need not import this module (which imports them)."""
        return _own_source_curve(model, outputs, quantity)

    def clearance_check(self, model, mcs=None, min_speed: float = 0.0, trip_speed=None, **options):
        """The API 617 / 684 clearance check at the model's close-clearance stations, the response
        scaled by ``Scc = Avl / Amax`` (``scale_cap``, ``min_operating``); see
        :func:`rotordyn_modal.analysis.clearance.clearance_check`."""
        from .clearance import clearance_check

        return clearance_check(self, model, mcs=mcs, min_speed=min_speed, trip_speed=trip_speed, **options)

    def plot(self, outputs=None, **kwargs):
        """Bode figure: amplitude (in ``amplitude_kind``, or ``amplitude=``) and phase vs speed
        (``peaks=self.peaks(...)`` marks the API 684 figures, ``checks=self.checks(...)`` draws the
        probe limits and ISO zones); see :func:`rotordyn_modal.plotting.plot_unbalance`."""
        kwargs.setdefault("amplitude", self.amplitude_kind)
        from ..plotting.frf import plot_unbalance

        return plot_unbalance(self, outputs=outputs, **kwargs)


def vector_amplitude(components) -> np.ndarray:
    """The amplitude of a harmonic vector from its components' complex amplitudes,
    ``sqrt(sum_k |c_k|^2)`` (the figures' "vector amplitude, |F|" of a force).

    Parameters
    ----------
    components : ndarray, shape (k, ...), complex
        The components (``Fx, Fy, Fz``, say) along the first axis.

    Returns
    -------
    ndarray, shape (...) [as ``components``]
    """
    return np.sqrt(np.sum(np.abs(components) ** 2, axis=0))


def _with_convention(table, amplitude: str, after: str | None = "phase_deg"):
    """``table`` with the column of ``amplitude`` (0-peak ``amplitude`` times its factor) after
    ``after`` (None: last); unchanged for 'peak'."""
    factor, column = amplitude_factor(amplitude), amplitude_column(amplitude)
    if amplitude == "peak":
        return table
    position = len(table.columns) if after is None else list(table.columns).index(after) + 1
    table.insert(position, column, table["amplitude"].to_numpy() * factor)
    return table

def check_operating_speed(speeds, operating_speed) -> None:
    """Raise InputError unless ``operating_speed`` [rad/s] (None: not given) can measure the
    separation margins of a sweep over ``speeds`` (S,) [rad/s]: finite, not 0 (the margin is a
    percentage of it) and in the direction of spin of some speed of the sweep (a margin across
    zero speed, from a peak at +1500 rpm to -1500 rpm, is not a separation)."""
    if operating_speed is None:
        return
    if not (np.isfinite(operating_speed) and operating_speed != 0):
        raise InputError(f"operating speed {operating_speed!r} rad/s: expected a finite speed other than 0 "
                         "(the separation margin is a percentage of it)")
    speeds = np.asarray(speeds, dtype=float)
    if not np.any(np.sign(speeds) == np.sign(operating_speed)):
        low, high = (float(f(speeds)) * 30 / np.pi for f in (np.min, np.max))
        raise InputError(f"operating speed {operating_speed:.6g} rad/s ({operating_speed * 30 / np.pi:.6g} rpm): "
                         f"expected a speed in the sweep's direction of spin (the sweep runs from {low:.6g} to "
                         f"{high:.6g} rpm): its separation margins would be measured across zero speed")



def amplification_factors(speeds, amplitude):
    """Peaks of an amplitude-vs-speed curve and their API 684 amplification factor.

    ``AF = N_c / (N_2 - N_1)``: the peak speed over the width of the band where
    the amplitude exceeds ``peak / sqrt(2)`` (half-power points, linearly
    interpolated). NaN where the band leaves the sweep.

    Parameters
    ----------
    speeds : array_like, shape (N,) [rad/s]
        In any order (a run-down, repeated speeds); each direction of spin (negative speeds,
        the others) is a curve of its own, ordered by the magnitude of the speed.
    amplitude : array_like, shape (N,)

    Returns
    -------
    list of (speed [rad/s], amplitude, amplification factor), in the order of ``speeds``
    """
    from .unbalance_peaks import spin_curves

    speeds, amplitude = np.asarray(speeds, dtype=float), np.asarray(amplitude, dtype=float)
    out = []
    for _, index, x, y, peaks in spin_curves(speeds, amplitude):
        out += [(index[k], _curve_peak(x, y, k)) for _, k in peaks]
    return [(float(speeds[index]), amp, af) for index, (_, amp, af) in sorted(out, key=lambda item: item[0])]


def _curve_peak(x, y, k):
    """``(x_k, y_k, AF)`` of the peak ``k`` of ``y`` over increasing ``x``."""
    level = y[k] / np.sqrt(2)
    left, right = _crossing(x, y, k, level, -1), _crossing(x, y, k, level, +1)
    af = x[k] / (right - left) if np.isfinite(left) and np.isfinite(right) and right > left else np.nan
    return float(x[k]), float(y[k]), float(af)


def _crossing(x, y, k, level, step):
    i = k
    while 0 <= i + step < len(y) and y[i + step] > level:
        i += step
    j = i + step
    if not 0 <= j < len(y):
        return np.nan
    return x[i] + (level - y[i]) * (x[j] - x[i]) / (y[j] - y[i])


def unbalance_response(model, speeds, outputs=None, quantity: str = "displacement",
                       progress: bool = False, amplitude: str = "peak", resonances: bool = True,
                       _criticals=None, _label="unbalance", _roots=None) -> UnbalanceResult:
    """Steady response to the model's ``[[unbalances]]`` over a speed sweep.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,)
        Reference rotor speeds [rad/s] (negative reverses every rotor).
    outputs : str or list of str, optional
        Sensor names (default all).
    quantity : {'displacement', 'velocity', 'acceleration'}
    progress : bool
        Show a line naming the work under way (the model's check, the direct solves, the
        resonances) with its elapsed time, once it has run a few seconds (a sweep is one batched
        solve: there are no steps to count; 500 geared rotors, 2,006 coordinates, take about
        40 s on a shared machine).
    amplitude : {'peak', 'pk-pk', 'rms'}
        Amplitude convention of the result's tables and figure (``amplitude_kind``); the
        response itself is the same.
    resonances : bool
        Find the damped critical speeds that no swept speed resolves and the response there
        (``resonance_speeds``, ``resonance_response``: the figure marks the peaks its line cuts,
        :meth:`UnbalanceResult.cut_peaks`); False leaves them None (a study's variants: the
        eigen-solutions cost more than the response).

    Returns
    -------
    UnbalanceResult
    """
    if quantity not in _ORDER:
        raise InputError(f"quantity {quantity!r}: expected one of {', '.join(_ORDER)}")
    amplitude_factor(amplitude)                      # refuses an unknown convention by name
    if not model.unbalances:
        raise InputError(f"{model.source}: the model has no [[unbalances]]: nothing excites an unbalance response")
    speeds = _arguments.speeds(speeds, increasing=False)
    with phase(progress, f"{_label}: the model's matrices") as bar:      # _label: the line's start
        # a mass matrix rounding leaves singular: refused, as every analysis does; the form is
        # made once a call (500 geared rotors: about 4 s), and says whether the peaks are looked for
        form = speed_linear_form(model)
        _rename(bar, f"{_label}: direct solves at {len(speeds):,} speeds ({model.dofs.n:,} coordinates)")
        solved = _sensor_response(model, speeds, outputs, quantity)
        _rename(bar, f"{_label}: forces and resonances")
        fields = _result_fields(model, speeds, outputs, quantity, solved, resonances, _criticals, form, _roots)
    sources, w, response, _ = solved
    return UnbalanceResult(speeds=speeds, sources=tuple(sources), frequencies_hz=w / (2 * np.pi),
                           response=response, quantity=quantity, amplitude_kind=amplitude, **fields)


def _rename(bar, description):
    """Name the work under way on a :func:`.._progress.phase` line (None: no line)."""
    if bar is not None:
        bar.set_description(description, refresh=False)


def _result_fields(model, speeds, outputs, quantity, solved, resonances, criticals, form=None, roots=None) -> dict:
    """The fields of :class:`UnbalanceResult` beside the speeds, sources, frequencies, response,
    quantity and amplitude convention: the forces, orbits' planes, clearances and resonances
    (``solved``: :func:`_sensor_response`'s; ``resonances``, ``criticals``: see
    :func:`unbalance_response`; ``form``: the model's state form, if made already; ``roots``: the
    state roots at the sweep's speeds, if found already, :func:`_unresolved_fields`)."""
    sources, _, response, (rotor_forces, speed_all, omega, q, shifts, motions) = solved
    n_src, n = len(sources), len(speeds)
    names = tuple(s.name for s in model.sensors) if outputs is None else \
        ((outputs,) if isinstance(outputs, str) else tuple(outputs))
    by_name = {s.name: s for s in model.sensors}
    pairs = probe_pairs(model, [by_name[name] for name in names])
    planes = np.einsum("pij,pjsn->psni", pairs.to_plane, response[pairs.indices]) if len(pairs) else \
        np.zeros((0, n_src, n, 2), dtype=complex)
    ratios = [model.rotor(src).speed_ratio for src in sources]
    spin_signs = np.where(np.array(ratios, dtype=float)[:, None] * speeds < 0, -1.0, 1.0)
    return dict(
        outputs=names,
        suspension_names=tuple(s.name for s in model.suspensions),
        rotor_names=tuple(r.name for r in model.rotors),
        bearing_names=tuple(b.name for b in model.bearings),
        **_force_fields(model, sources, rotor_forces, speed_all, omega, q, centre_motions(shifts, motions)),
        orbit_pairs=pairs.names, orbit_planes=planes, spin_signs=spin_signs.reshape(n_src, n),
        rigid_rotor_names=tuple(r.name for r in model.rotors if not model.bearings_of(r.name)),
        clearance_names=tuple(c.name for c in model.clearances),
        clearance_planes=_clearance_planes(model, q, motions, n_src, n),
        **_unresolved_fields(model, speeds, outputs, quantity, ratios, response, resonances, criticals, form, roots),
    )


def _sensor_response(model, speeds, outputs, quantity, solved=None):
    """``(sources, w, response, (rotor_forces, speed_all, omega, q, shifts, motions))``: the sources, their
    circular frequencies ``w`` (n_src, N) [rad/s], the sensors' complex amplitudes ``response``
    (n_outputs, n_src, N) and what the forces are computed from (``q`` (n_src N, n_dof, 1));
    ``solved``: see :func:`_coordinate_response`."""
    sources, w, rotor_forces = unbalance_forces(model, speeds)
    n_src, n = len(sources), len(speeds)
    # (n_src * N,): sources one after another (one source: the speeds themselves, read only)
    speed_all, omega = (np.tile(speeds, n_src) if n_src > 1 else speeds), w.ravel()
    # every rotor's B_SR and motion T_j, found once for its unbalance force and its bearing force
    shifts = shift_matrices(model.reference_point, [r.center_of_mass for r in model.rotors])
    motions = model.dofs.motions([(r.name, False) for r in model.rotors])
    q = _coordinate_response(model, sources, rotor_forces, speed_all, omega, shifts, motions, solved)
    # (i w)^0 is 1 + 0i: that scalar, not an array of it
    factor = (1j * w) ** _ORDER[quantity] if _ORDER[quantity] else 1.0 + 0.0j
    response = (sensor_rows(model, outputs, motions) @ q[..., 0].T).reshape(-1, n_src, n) * factor
    return sources, w, response, (rotor_forces, speed_all, omega, q, shifts, motions)


def _unresolved_fields(model, speeds, outputs, quantity, ratios, swept, wanted=True, found=None, form=None,
                       roots=None) -> dict:
    """``resonance_speeds``, ``resonance_bands`` (n_src, P) [rad/s] and ``resonance_response``
    (n_outputs, n_src, P) of :class:`UnbalanceResult`: each source's damped critical speeds
    that no swept speed resolves (:func:`.unbalance_peaks.unresolved_criticals`) and the
    response there, NaN after a source's last; ``cut_peak_speeds``, ``cut_peak_response`` and
    ``cut_peak_widths`` (n_outputs, n_src, Q): each curve's maxima that the swept line cuts
    (:func:`.unbalance_peaks.cut_maxima`); None each where not computed or not ``wanted``.
    ``swept``: the response at ``speeds`` (n_outputs, n_src, N); ``found``: those speeds already
    found (:func:`api_unbalance_response`'s cases, one machine); ``form``: the model's state form,
    if made already (whether the peaks are looked for is read from it: where they are not, the
    form is not made again); ``roots``: the state roots at the sweep's speeds found with ``found``
    (:func:`.unbalance_peaks.unresolved_criticals`), if any: the AF table's search for undamped
    crossings (:func:`.unbalance_peaks.undamped_crossings`, every sweep) reads them instead of
    solving them again."""
    from ..assembly import is_large
    from .unbalance_peaks import _AF_SHARE, cut_maxima, not_looked_for, undamped_crossings, unresolved_criticals

    why = not_looked_for(model, speeds, form) if wanted and found is None else ""
    roots = {} if roots is None else roots
    if wanted and found is None and not why:
        found = unresolved_criticals(model, speeds, ratios, roots)
    curve = _own_source_curve(model, outputs, quantity) if wanted and not is_large(model) else None
    exact = _exact_peak_fields(curve, speeds, swept, float(model.dofs.n) ** 3,
                               None if found is None else [critical for critical, _ in found],
                               undamped_crossings(model, ratios, speeds, roots))
    if not wanted or found is None:
        return dict(dict.fromkeys(_RESONANCE_FIELDS), cut_peak_note=why, **exact)
    n_outputs = swept.shape[0]
    width = max(len(c) for c, _ in found)
    at = np.full((len(found), width), np.nan)
    bands = np.full((len(found), width), np.nan)
    for j, (critical, band) in enumerate(found):
        at[j, :len(critical)], bands[j, :len(band)] = critical, band
    values = np.full((n_outputs, len(found), width), np.nan + 0j)
    every = np.concatenate([c for c, _ in found])

    if every.size:
        start = np.cumsum([0] + [len(c) for c, _ in found])
        own = np.zeros((len(found), every.size), dtype=bool)          # each source at its own speeds only
        for j in range(len(found)):
            own[j, start[j]:start[j + 1]] = True
        computed = _sensor_response(model, every, outputs, quantity, own.ravel())[2]   # (n_out, n_src, K)
        for j in range(len(found)):
            values[:, j, :start[j + 1] - start[j]] = computed[:, j, start[j]:start[j + 1]]
    peak_at, peak_value, peak_width = cut_maxima(curve or _own_source_curve(model, outputs, quantity), speeds,
                                                 np.abs(swept), found, share=_AF_SHARE)
    return {"resonance_speeds": at, "resonance_bands": bands, "resonance_response": values,
            "cut_peak_speeds": peak_at, "cut_peak_response": peak_value, "cut_peak_widths": peak_width, **exact}


def _exact_peak_fields(curve, speeds, swept, solve_work, criticals=None, crossing=None) -> dict:
    """``peak_swept_speeds``, ``peak_speeds``, ``peak_response`` and ``peak_half_power`` of
    :class:`UnbalanceResult`: the swept peaks of ``swept`` (n_outputs, n_src, N) read on the exact
    response ``curve`` (:func:`.unbalance_peaks.exact_peaks`, ``solve_work`` one solve's work,
    ``criticals`` each source's damped critical speeds that no swept speed resolves, ``crossing``
    where an undamped peak's response is unbounded); None each without a curve or where the
    search would cost too much."""
    from .unbalance_peaks import exact_peaks

    found = None if curve is None else exact_peaks(curve, speeds, np.abs(swept), solve_work, criticals, crossing)
    return dict.fromkeys(_EXACT_PEAK_FIELDS) if found is None else dict(zip(_EXACT_PEAK_FIELDS, found))


def _own_source_curve(model, outputs, quantity):
    """``curve(s, o, j)`` of :func:`.unbalance_peaks.cut_maxima`: the response of output ``o[k]``
    to source ``j[k]`` at speed ``s[k]`` [rad/s], shape (K,), complex, each speed solved for its
    own source only, once a distinct speed (:func:`_sensor_response`'s numbers, one source at a
    time). The model's constant matrices are assembled at the first call and kept for the
    others (the search calls about 40 times a case)."""
    from .frf import stiffness_terms
    from .unbalance_peaks import per_source

    shifts = shift_matrices(model.reference_point, [r.center_of_mass for r in model.rotors])
    motions = model.dofs.motions([(r.name, False) for r in model.rotors])
    rows = sensor_rows(model, outputs, motions)
    kept = []                                               # the model's stiffness terms, once made

    def solve(at, each):
        if not kept:
            kept.append(stiffness_terms(model))
        sources, w, rotor_forces = unbalance_forces(model, at)
        q = _coordinate_response(model, [sources[each]], rotor_forces[each:each + 1], at, w[each], shifts, motions,
                                 terms=kept[0])
        factor = (1j * w[each]) ** _ORDER[quantity] if _ORDER[quantity] else np.ones(at.size, complex)
        return (rows @ q[..., 0].T) * factor

    return per_source(solve)


#: the fields of :class:`UnbalanceResult` that :func:`_unresolved_fields` gives
_RESONANCE_FIELDS = ("resonance_speeds", "resonance_bands", "resonance_response",
                     "cut_peak_speeds", "cut_peak_response", "cut_peak_widths")
#: ... and :func:`_exact_peak_fields`
_EXACT_PEAK_FIELDS = ("peak_swept_speeds", "peak_speeds", "peak_response", "peak_half_power")


def _clearance_planes(model, q, motions, n_src, n):
    """Each close-clearance station's displacement relative to the stator along the transverse
    axes ``a, b``, shape (n_clearances, n_src, N, 2) (``q`` (n_src N, n_dof, 1))."""
    a, b = transverse_axes(model.spin_axis)
    points = [Sensor(c.name, c.position, axis, rotor=c.rotor, measure="relative")
              for c in model.clearances for axis in (a, b)]
    rows = point_rows(model, points, motions)
    return (rows @ q[..., 0].T).reshape(-1, 2, n_src, n).transpose(0, 2, 3, 1)


def _coordinate_response(model, sources, rotor_forces, speed_all, omega, shifts, motions, solved=None, terms=None):
    """Complex amplitudes of the generalized coordinates, shape (n_src N, n_dof, 1), every
    source's unbalance force applied at its rotor's centre of mass (``shifts`` (R, 6, 6) and
    ``motions`` (R, 6, n_dof): each rotor's ``shift_matrix(S, R_j)`` and body motion);
    ``solved`` (n_src N,) bool, optional: only those systems solved, the others' amplitudes zero
    (each system is solved on its own: the solved ones are bit for bit as without it); ``terms``:
    the model's stiffness terms, if made already (:func:`.frf.stiffness_terms`)."""
    index = {r.name: k for k, r in enumerate(model.rotors)}
    each = [generalized_force(model, src, None, rotor_forces[j], shifts[index[src]], motions[index[src]])
            if model.rotor(src).flexible is None else
            _flexible_generalized(model, src, np.reshape(speed_all, (len(sources), -1))[j])
            for j, src in enumerate(sources)]                                  # (n_src, N, n_dof)
    generalized = (np.stack(each) if len(each) > 1 else each[0]).reshape(len(omega), -1)
    if solved is None:
        return dof_response(model, speed_all, omega, generalized[:, :, None], terms)
    q = np.zeros(generalized.shape + (1,), dtype=complex)
    q[solved] = dof_response(model, speed_all[solved], omega[solved], generalized[solved][:, :, None], terms)
    return q


def _force_fields(model, sources, rotor_forces, speed_all, omega, q, centres=None):
    """``ground_forces``, ``bearing_forces`` and ``bearing_point_forces`` of
    :class:`UnbalanceResult`, each shape (n_items, 6, n_src, N) (``centres``: see
    :func:`forces.all_forces`)."""
    n_src = len(sources)
    n = len(omega) // max(n_src, 1)
    rotor_names = [r.name for r in model.rotors]
    if rotor_names == list(sources) and n_src == 1:      # one rotor: its own force is all there is
        external = rotor_forces[:, :, :, None]
    else:
        external = np.zeros((len(model.rotors), len(omega), 6, 1), dtype=complex)
        for j, src in enumerate(sources):
            external[rotor_names.index(src), j * n:(j + 1) * n, :, 0] = rotor_forces[j]

    def per_source(forces):                                   # (items, n_src N, 6, 1) -> (items, 6, n_src, N)
        return forces[..., 0].reshape(len(forces), n_src, n, 6).transpose(0, 3, 1, 2)

    ground, rotors, bearings = all_forces(model, speed_all, omega, q, external, centres)
    return {"ground_forces": per_source(ground), "bearing_forces": per_source(rotors),
            "bearing_point_forces": per_source(bearings)}


def api_unbalance_response(model, speeds, mcs: float, outputs=None, quantity: str = "displacement",
                           amplitude: str = "peak", progress: bool = False):
    """Unbalance response to each API 617/684 case of the model, as one result whose sources
    are the cases (``case_rotors`` the rotor of each); cases: see
    :func:`~rotordyn_modal.analysis.unbalance_checks.api_unbalance_cases`.

    Parameters
    ----------
    model : Model
    speeds : array_like, shape (N,) [rad/s]
    mcs : float
        [rad/s] the reference rotor's maximum continuous speed, > 0.
    outputs, quantity, amplitude, progress
        As :func:`~rotordyn_modal.analysis.unbalance.unbalance_response` (the line shown names
        the case: ``unbalance case 2 of 4``).

    Returns
    -------
    UnbalanceResult
    """
    from .unbalance_peaks import not_looked_for, unresolved_criticals

    cases = api_unbalance_cases(model, mcs)
    # one machine: its damped critical speeds found once, for each case's rotor
    rotors = [case.unbalances[0].rotor for _, case in cases]
    roots: dict = {}                  # the state roots at the swept speeds, found once for every case
    with phase(progress, "unbalance: damped critical speeds"):
        found = unresolved_criticals(model, _arguments.speeds(speeds, increasing=False),
                                     [model.rotor(r).speed_ratio for r in rotors], roots)
    # resonances=True: each case's AF table on its exact response (its damped critical speeds are
    # the machine's, not looked for again where not found: not_looked_for says why)
    results = [unbalance_response(case, speeds, outputs=outputs, quantity=quantity, amplitude=amplitude,
                                  progress=progress, resonances=True,
                                  _criticals=None if found is None else [found[k]], _roots=roots,
                                  _label=f"unbalance case {k + 1} of {len(cases)}")
               for k, (_, case) in enumerate(cases)]
    first = results[0]

    def joined(name, axis):
        parts = [getattr(r, name) for r in results]
        return None if parts[0] is None else np.concatenate(parts, axis=axis)

    return dataclasses.replace(
        first, sources=tuple(name for name, _ in cases), case_rotors=tuple(r.sources[0] for r in results),
        frequencies_hz=joined("frequencies_hz", 0), response=joined("response", 1),
        ground_forces=joined("ground_forces", 2), bearing_forces=joined("bearing_forces", 2),
        bearing_point_forces=joined("bearing_point_forces", 2), orbit_planes=joined("orbit_planes", 1),
        spin_signs=joined("spin_signs", 0), clearance_planes=joined("clearance_planes", 1),
        **_joined_resonances(results), **_joined_exact_peaks(results),
        cut_peak_note="" if found is not None else not_looked_for(model, speeds))


def _joined_resonances(results) -> dict:
    """The resonance fields of :class:`UnbalanceResult` of ``results`` (one source each) as
    one result's, each source's padded with NaN to the longest."""
    if any(r.resonance_speeds is None for r in results):
        return dict.fromkeys(_RESONANCE_FIELDS)

    return {name: _padded_join([getattr(r, name) for r in results], 0 if name in ("resonance_speeds",
                                                                                  "resonance_bands") else 1)
            for name in _RESONANCE_FIELDS}


def _joined_exact_peaks(results) -> dict:
    """The exact peaks' fields (:func:`_exact_peak_fields`) of ``results`` (one source each) as one
    result's, each source's padded with NaN to the most peaks; None each where one is not computed."""
    if any(r.peak_speeds is None for r in results):
        return dict.fromkeys(_EXACT_PEAK_FIELDS)
    return {name: _padded_join([getattr(r, name) for r in results], 1, 2) for name in _EXACT_PEAK_FIELDS}


def _padded_join(parts, axis, last=None):
    """``parts`` joined along ``axis``, each padded with NaN along its axis ``last`` (default its
    last) to the longest."""
    last = parts[0].ndim - 1 if last is None else last
    width = max(part.shape[last] for part in parts)
    padded = [np.pad(part, [(0, width - part.shape[last]) if a == last else (0, 0) for a in range(part.ndim)],
                     constant_values=np.nan) for part in parts]
    return np.concatenate(padded, axis=axis)
