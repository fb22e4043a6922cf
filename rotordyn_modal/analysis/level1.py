"""API 617 Level I stability screening: log decrement against an applied cross-coupled stiffness.

A cross-coupled stiffness ``Q`` (the aerodynamic excitation of impellers and stages) is applied
between a rotor and the stator at named **stations** (a point on the rotor's axis: its centre of
mass for a rigid rotor, an impeller's plane given by its axial offset), swept from 0 to
``factor * Qa`` (API: 10 Qa), and the log decrement at the maximum continuous speed followed
for each of the rotor's first :data:`FORWARD_MODES` forward modes, the least stable judged (or
for one forward mode asked for). ``Qa``, the anticipated cross-coupling, comes from the API formula
(:func:`anticipated_cross_coupling`) or is given. Criteria: the log decrement at ``Qa`` at
least 0.1 and ``Q0 / Qa`` at least 2.0 (``Q0`` the ``Q`` at which it reaches 0); otherwise a
Level II analysis is required.

Sign: in the bearing's radial axes ``a, b`` with ``a x b = e`` (the spin axis), the force on the
rotor is ``F = -K u`` with ``K_ab = +Q``, ``K_ba = -Q``: ``F = Q (-u_b, u_a)`` is tangential,
along a forward (with the spin) whirl orbit, and feeds it. For a rotor spinning the other way
(a negative speed, a gear's counter-rotating pinion) the sign follows its own spin.
``docs/level1_and_ucs.md`` derives it and gives the formula's sources.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.optimize import brentq

from .._limits import memory_problem
from ..errors import InputError
from ..linear_system import speed_linear_form
from ..model._table import LARGEST
from ..model.geometry import transverse_axes
from ..units import to_system, unit_label
from .. import _arguments
from . import _eigensolve, _vectors, _whirl
from .modal import is_oscillating, modal_quantities
from .tracking import track_modes

__all__ = ["Station", "Level1Result", "level1", "anticipated_cross_coupling", "LOG_DEC_CRITERION",
           "RATIO_CRITERION", "B_COMPRESSOR", "B_TURBINE", "CsrScreening", "csr_screening", "csr_boundary",
           "rigid_support_critical_speed", "CSR_RATIO_LIMIT", "FORWARD_MODES", "least_stable"]

#: API 617 Level I criteria: log decrement at Qa, and Q0 / Qa
LOG_DEC_CRITERION = 0.1
RATIO_CRITERION = 2.0
#: by default Level I follows this many of the rotor's forward modes (the first, second, ...)
#: and judges the least stable
FORWARD_MODES = 3
#: the formula's factor B for centrifugal compressor impellers and for turbine (axial) stages
B_COMPRESSOR = 3.0
B_TURBINE = 1.5
#: the CSR chart applies while Q0 / Qa is below this (and at least RATIO_CRITERION)
CSR_RATIO_LIMIT = 10.0
#: the dividing line of the CSR chart as ROSS implements it (docs/standards.md): CSR 2.5 up to
#: 16.53 kg/m^3, then 2.69 - 0.0115 rho [rho in kg/m^3] down to 2.0 at 60 kg/m^3; beyond
#: 60 kg/m^3 the line is 0 (every CSR > 0 lies in Region B)
_CSR_FLAT, _CSR_KNEE, _CSR_END = 2.5, 16.53, 60.0
_CSR_INTERCEPT, _CSR_SLOPE = 2.69, -0.0115


@dataclass(frozen=True)
class Station:
    """A point on a rotor's axis where cross-coupling acts.

    Attributes
    ----------
    rotor : str
    offset : float [m]
        Along ``spin_axis`` from the rotor's centre of mass (0: the centre, the station of a
        rigid rotor). A flexible rotor's stations will be its axial positions the same way.
    """

    rotor: str
    offset: float = 0.0
    #: the unit system its OFFSET was typed in ('si': m, 'us': in): a refusal says lengths in it
    units: str = field(default="si", compare=False)

    @classmethod
    def parse(cls, text: str, units: str = "si") -> "Station":
        """``ROTOR`` or ``ROTOR@OFFSET`` (offset in m along ``spin_axis`` from its centre of mass;
        ``units`` names the length unit the refusal says the command line reads it in: in for 'us')."""
        rotor, at, offset = str(text).rpartition("@") if "@" in str(text) else (str(text), "", "0")
        try:
            value = float(offset)
        except ValueError:
            value = float("nan")
        if not rotor or not np.isfinite(value):
            raise InputError(f"station {text!r}: expected ROTOR or ROTOR@OFFSET (OFFSET [{unit_label('length', units)}] "
                             "along spin_axis from the rotor's centre of mass)")
        return cls(rotor, value)

    def point(self, model) -> np.ndarray:
        """The station in model axes [m], shape (3,)."""
        centre = np.asarray(model.rotor(self.rotor).center_of_mass, dtype=float)
        return centre + self.offset * np.asarray(model.spin_axis, dtype=float)

    def __str__(self) -> str:
        return self.rotor if self.offset == 0 else f"{self.rotor}@{self.offset:g}"

    def label(self, units: str = "si") -> str:
        """``ROTOR`` or ``ROTOR@OFFSET``, the offset in the length unit of ``units`` (m; in for 'us')."""
        if units == "si" or self.offset == 0:
            return str(self)
        return f"{self.rotor}@{to_system(self.offset, 'length', units):g}"

    def named(self, units: str = "si") -> str:
        """:meth:`label` with the offset's unit, as figures and reports print it: ``ROTOR`` at the
        centre of mass, ``fan@-0.1 m``, ``fan@-3.93701 in`` (``label`` stays the form ``--station``
        reads)."""
        return self.label(units) + (f" {unit_label('length', units)}" if self.offset else "")


def anticipated_cross_coupling(power, speed, diameter, height, density_ratio=1.0, machine: str = "compressor"):
    """Anticipated cross-coupling ``q_A`` of each stage (API 617 Level I), SI units.

    ``q_A = B T / (D H) (rho_d / rho_s)`` with ``T = P / Omega`` the stage's torque: in the
    standard's form ``q_A = B C P / (D H N) (rho_d / rho_s)``, ``C = 9.55`` (``60 / 2 pi``: P in
    W, N in rpm, D and H in m, q_A in N/m; US units: ``C = 63.0``, hp, in, rpm, klbf/in).
    ``B = 3`` for compressor impellers (``D`` the impeller diameter, ``H`` the smaller of the
    diffuser and impeller discharge width, the density ratio discharge over suction of the
    stage); ``B = 1.5`` for turbine stages (``D`` the blade pitch diameter, ``H`` the effective
    blade height; no density ratio).

    Parameters
    ----------
    power : array_like, shape (S,) [W]
        Rated power of each stage (impeller).
    speed : float [rad/s]
        Normal operating speed of the stages (> 0).
    diameter, height : array_like, shape (S,) [m]
    density_ratio : array_like, shape (S,) or float
        ``rho_discharge / rho_suction`` of each stage (compressors; ignored for turbines).
    machine : {'compressor', 'turbine'}

    Returns
    -------
    ndarray, shape (S,) [N/m]; their sum is ``Qa``.
    """
    if machine not in ("compressor", "turbine"):
        raise InputError(f"machine {machine!r}: expected 'compressor' or 'turbine'")
    power, diameter, height = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (power, diameter, height))
    ratio = np.broadcast_to(np.asarray(density_ratio, dtype=float), power.shape) if machine == "compressor" \
        else np.ones_like(power)
    for name, values in (("power", power), ("diameter", diameter), ("height", height), ("density_ratio", ratio)):
        if values.shape != power.shape or not np.all(np.isfinite(values)) or not np.all(values > 0):
            raise InputError(f"{name} = {values.tolist()}: expected finite values > 0, one per stage "
                             f"({len(power)} {'stage' if len(power) == 1 else 'stages'})")
    if not (np.isfinite(speed) and speed > 0):
        raise InputError(f"speed = {speed!r}: expected the operating speed > 0 [rad/s]")
    factor = B_COMPRESSOR if machine == "compressor" else B_TURBINE
    return factor * (power / speed) / (diameter * height) * ratio


@dataclass(frozen=True)
class Level1Result:
    """Log decrement of the governing forward mode against the applied cross-coupling.

    Attributes
    ----------
    speed : float [rad/s]
        The analysis speed (maximum continuous speed) of the reference rotor.
    stations : tuple of Station
    shares : ndarray, shape (P,)
        The part of ``Q`` applied at each station (summing to 1).
    cross_coupling : ndarray, shape (NQ,) [N/m]
        The total applied ``Q``, from 0.
    log_decrements, frequencies_hz : ndarray, shape (NQ,)
        Of the followed mode (tracked from Q = 0 by its shape); with several swept, the one of
        the lowest log decrement at Qa.
    mode : int
        That mode's number at Q = 0 among the modes (``modes --speed`` numbering); 0 when its
        root is no mode at Q = 0 (real or overdamped, on soft, heavily damped bearings: the
        cross-coupling makes it whirl), see :attr:`mode_label`.
    qa : float [N/m]
    q0 : float [N/m]
        Where the log decrement reaches 0 (root-found; with several modes swept, the smallest
        of theirs); nan when it stays positive over the sweep (then ``Q0 > cross_coupling[-1]``),
        0 when it is not positive at Q = 0.
    log_decrement_at_qa : float
    title : str
    csr : CsrScreening or None
    forward_mode : int
        The followed mode's rank among the rotor's forward modes by frequency (1 the first).
    swept : tuple of Level1Result
        The result of each followed mode, by ``forward_mode`` (each with its own ``q0`` and an
        empty ``swept``); this result is one of them with the judged ``q0``.
    """

    speed: float
    stations: tuple
    shares: np.ndarray
    cross_coupling: np.ndarray
    log_decrements: np.ndarray
    frequencies_hz: np.ndarray
    mode: int
    qa: float
    q0: float
    log_decrement_at_qa: float
    title: str = ""
    csr: "CsrScreening | None" = None
    forward_mode: int = 1
    swept: tuple = ()

    @property
    def mode_label(self) -> str:
        """``'mode N'``, or, when the followed root is no mode at Q = 0 (:attr:`mode` 0), what it
        is there: ``'a root that does not oscillate at Q = 0'``."""
        return f"mode {self.mode}" if self.mode else "a root that does not oscillate at Q = 0"

    @property
    def governs_q0(self) -> "Level1Result | None":
        """The swept mode whose log decrement reaches 0 first (its ``q0`` is this result's),
        None when none does over the sweep."""
        if not np.isfinite(self.q0):
            return None
        return next((r for r in self.swept or (self,) if r.q0 == self.q0), None)

    @property
    def ratio(self) -> float:
        """``Q0 / Qa`` (inf when Q0 lies beyond the sweep: at least ``cross_coupling[-1] / Qa``)."""
        return float(self.q0 / self.qa) if np.isfinite(self.q0) else float("inf")

    @property
    def log_decrement_criterion(self) -> float:
        """:data:`LOG_DEC_CRITERION` (the least log decrement at Qa)."""
        return LOG_DEC_CRITERION

    @property
    def ratio_criterion(self) -> float:
        """:data:`RATIO_CRITERION` (the least Q0 / Qa)."""
        return RATIO_CRITERION

    @property
    def passes_log_decrement(self) -> bool:
        return bool(self.log_decrement_at_qa >= LOG_DEC_CRITERION)

    @property
    def passes_ratio(self) -> bool:
        return bool(self.ratio >= RATIO_CRITERION)

    @property
    def csr_applies(self) -> bool:
        """The CSR chart judges this rotor: a gas density was given and ``Q0 / Qa`` is below
        :data:`CSR_RATIO_LIMIT` (taken as below when Q0 lies beyond a sweep shorter than that)."""
        if self.csr is None:
            return False
        if np.isfinite(self.q0):
            return bool(self.ratio < CSR_RATIO_LIMIT)
        return bool(self.cross_coupling[-1] / self.qa < CSR_RATIO_LIMIT)

    @property
    def passes_csr(self) -> bool:
        """False when the CSR chart applies and the rotor's point lies in Region B."""
        return not (self.csr_applies and self.csr.region == "B")

    @property
    def level2_required(self) -> bool:
        """True unless both criteria pass (and, with a gas density, the CSR chart: Region B with
        ``Q0 / Qa`` below 10 requires Level II too)."""
        return not (self.passes_log_decrement and self.passes_ratio and self.passes_csr)

    def verdict(self, units: str = "si") -> str:
        """One sentence: the criteria, their values and whether Level II is required (the gas
        density of the CSR in the density unit of ``units``: kg/m³, or lb/ft³ for 'us')."""
        ratio = (f"Q0/Qa = {self.ratio:.3g}" if np.isfinite(self.q0)
                 else f"Q0/Qa > {self.cross_coupling[-1] / self.qa:.3g}")
        checks = (f"log dec at Qa = {self.log_decrement_at_qa:.3g} ({'>=' if self.passes_log_decrement else '<'} "
                  f"{LOG_DEC_CRITERION:g}), {ratio} ({'>=' if self.passes_ratio else '<'} {RATIO_CRITERION:g})")
        if self.csr is not None:
            checks += f", {self.csr.summary(units)}" + ("" if self.csr_applies or not self.csr.evaluated
                                                        else f" (not applied: Q0/Qa >= "
                                                                               f"{CSR_RATIO_LIMIT:g})")
        return f"{checks}: Level II {'required' if self.level2_required else 'not required'}"

    def to_dataframe(self):
        """Table ``q_n_per_m, q_over_qa, log_decrement, frequency_hz`` (the judged mode), then
        ``log_decrement_mode_N, frequency_hz_mode_N`` for each swept mode ``N`` (``modes``
        numbering) when more than one was swept (``..._forward_K``, its rank among the forward
        modes, for a root that is no mode at Q = 0: two such would share ``mode_0``)."""
        import pandas as pd

        columns = {"q_n_per_m": self.cross_coupling, "q_over_qa": self.cross_coupling / self.qa,
                   "log_decrement": self.log_decrements, "frequency_hz": self.frequencies_hz}
        if len(self.swept) > 1:
            for run in self.swept:
                name = f"mode_{run.mode}" if run.mode else f"forward_{run.forward_mode}"
                columns[f"log_decrement_{name}"] = run.log_decrements
                columns[f"frequency_hz_{name}"] = run.frequencies_hz
        return pd.DataFrame(columns)

    def plot(self, **kwargs):
        """Log decrement against Q / Qa; see :func:`rotordyn_modal.plotting.plot_level1`."""
        from ..plotting import plot_level1

        return plot_level1(self, **kwargs)


def level1(model, speed, stations, qa, shares=None, factor: float = 10.0, steps_per_qa: int = 10,
           forward_mode: int | None = None, gas_density=None) -> Level1Result:
    """API 617 Level I screening of ``model`` at ``speed`` (see the module docstring).

    Parameters
    ----------
    model : Model
    speed : float [rad/s]
        Maximum continuous speed of the reference rotor (not 0).
    stations : sequence of Station (or rotor names)
        Where the cross-coupling acts; each station's rotor must be on bearings.
    qa : float [N/m]
        Anticipated cross-coupling (the sum over stages, :func:`anticipated_cross_coupling`), > 0.
    shares : array_like, shape (P,), optional
        The part of Q at each station (default equal parts); normalised to sum 1.
    factor : float
        The sweep reaches ``factor * qa`` (API: 10), rounded up to a whole step; 1 to 1000.
    steps_per_qa : int
        Points per ``qa`` of the sweep (``qa`` is a point of it).
    forward_mode : int, optional
        Default (None): follow the first :data:`FORWARD_MODES` forward modes by frequency (those
        there are) and judge the least stable (:func:`least_stable`): the first by frequency may
        be one the cross-coupling at the station barely reaches (a tilt whose centre hardly
        moves) while the next goes unstable. ``K``: follow the ``K``-th forward mode alone.
        Forward means whirling with the stations' rotor's spin in its motion relative to the
        stator at the (first) station, where the cross-coupling acts, in a mode of the rotor in
        its bearings; judged at a small Q (:func:`_small_q`, the first point of the sweep with as
        many forward modes as at 0.1 Qa), where Q has split the rotor's forward and backward modes
        of one frequency, and followed from there to Q = 0 and up (docs/level1_and_ucs.md).
    gas_density : float or (float, float), optional [kg/m^3]
        The average gas density, or the suction and discharge densities (averaged): adds the
        critical speed ratio criterion (:func:`csr_screening`) to the verdict.

    Returns
    -------
    Level1Result
        Its ``swept`` holds the result of each followed mode.
    """
    speed = _checked(speed, qa, factor, steps_per_qa)
    if forward_mode is not None and (isinstance(forward_mode, (bool, np.bool_)) or not isinstance(
            forward_mode, (int, np.integer)) or forward_mode < 1):     # before the work (True was mode 1)
        raise InputError(f"forward_mode = {forward_mode!r}: expected a whole number >= 1 (or None: the first "
                         f"{FORWARD_MODES}, the least stable judged)")
    csr = None if gas_density is None else _gas_densities(gas_density)
    if isinstance(stations, (str, Station)):   # one station ('fan' was read as the stations 'f', 'a', 'n')
        stations = (stations,)
    stations = tuple(s if isinstance(s, Station) else Station.parse(s) for s in stations)
    shares = _shares(shares, len(stations))
    _check_stations(model, stations)
    _warn_between_nodes(model, stations)
    steps = int(steps_per_qa)
    grid = qa * (np.arange(int(np.ceil(factor * steps - 1e-9)) + 1) / steps)    # grid[steps] is qa exactly
    form = speed_linear_form(model)
    base = form.at(speed)
    unit = _unit_state_matrix(model, form, stations, shares, speed)
    # the modes are followed over a sweep of the machine's own Q scale besides Qa's grid: chosen
    # at a Q far below anything that moves them (not at Qa / 10, which for a large Qa is a
    # machine of other modes: Q0 must not depend on Qa), followed up through Qa's grid
    sweep, at_grid = _sweep_grid(grid, _small_q(base, unit, form.n_dof))
    _refuse_what_cannot_fit(model, form, len(sweep))
    _refuse_long_work(model, form, len(sweep), 1 if forward_mode is not None else FORWARD_MODES)
    lam, shapes = _eigensolve.upper_shapes(base + sweep[:, None, None] * unit, form.n_dof)
    shapes = _eigensolve.resolve_repeated(lam, shapes, _whirl.whirl_forms(model))
    order = track_modes(lam, _vectors.mass_normalized(shapes, form.matrices.M))
    # chosen at the first Q > 0 where Q has split a forward and backward pair of one frequency
    # (a rotor's cylindrical modes, which at Q = 0 the solver may return as any two mixtures, and
    # which a casing's anisotropy keeps planar until Q outweighs it): the first point of the sweep
    # with as many forward modes as Qa's first grid point has (a small Q where the machine is
    # isotropic enough; never above Qa / 10)
    spin = np.sign(speed) * _spin_sign(model, stations)
    pick, forward = _pick_index(model, lam, shapes, form.matrices.M, stations[0], spin, at_grid[1], forward_mode, order)
    numbers = [forward_mode] if forward_mode is not None else range(1, max(1, min(FORWARD_MODES, len(forward))) + 1)
    runs = []
    for number in numbers:
        if not 1 <= number <= len(forward):
            count = f"is {len(forward)} mode" if len(forward) == 1 else f"are {len(forward)} modes"
            raise InputError(f"forward mode {number}: there {count} of rotor {stations[0].rotor!r} "
                             f"whirling forward at station {stations[0]} at this speed")
        label = int(np.nonzero(order[pick] == forward[number - 1])[0][0])
        followed_sweep = lam[np.arange(len(sweep)), order[:, label]]
        freq_sweep, _, log_dec_sweep = modal_quantities(followed_sweep)       # elementwise: Qa's grid is a part
        freq, log_dec = freq_sweep[at_grid], log_dec_sweep[at_grid]
        start = lam[0, order[0, label]]
        # its number among the modes at Q = 0; a root no mode there has none (the count of the
        # modes before it would name another mode)
        mode = int(is_oscillating(lam[0])[:order[0, label] + 1].sum()) if is_oscillating(start) else 0
        runs.append(Level1Result(
            speed=speed, stations=stations, shares=shares, cross_coupling=grid, log_decrements=log_dec,
            frequencies_hz=freq, mode=mode, qa=float(qa),
            q0=_zero_crossing(base, unit, form.n_dof, sweep, followed_sweep, log_dec_sweep),
            log_decrement_at_qa=float(log_dec[steps]), title=model.name, forward_mode=int(number)))
    judged = least_stable(runs) if forward_mode is None else replace(runs[0], swept=tuple(runs))
    return replace(judged, csr=None if csr is None else csr_screening(model, speed, csr))


def least_stable(runs) -> Level1Result:
    """The Level I result of several followed forward modes: the run of the least stable (the
    lowest log decrement at Qa), with ``Q0`` the smallest of all runs (the cross-coupling at
    which the first of them reaches a zero log decrement: the machine's threshold).

    Parameters
    ----------
    runs : sequence of Level1Result
        One per followed mode, each with its own ``q0``.

    Returns
    -------
    Level1Result
        ``swept`` the runs, in their order.
    """
    judged = min(runs, key=lambda r: r.log_decrement_at_qa)
    thresholds = [r.q0 for r in runs if np.isfinite(r.q0)]
    q0 = min(thresholds) if thresholds else judged.q0
    return replace(judged, q0=float(q0), swept=tuple(runs))


def _real(value, name: str, expected: str) -> float:
    """``value`` as a float when it is one real number (not a bool, a text or an array: ``qa=[1e5,
    1e5]`` and ``qa='1e5'`` raised numpy's ValueError and TypeError)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{name} = {value!r}: expected {expected}")
    return float(value)


def _checked(speed, qa, factor, steps_per_qa) -> float:
    """The speed [rad/s] after checking the numeric arguments of :func:`level1`."""
    speed = _arguments.speed(speed)
    if speed == 0:
        raise InputError("speed = 0: a Level I analysis runs at the maximum continuous speed (not 0)")
    qa = _real(qa, "qa", "the anticipated cross-coupling, one number [N/m] (the stages' sum; shares= splits it)")
    factor = _real(factor, "factor", "a factor from 1 to 1000 (the sweep reaches factor x Qa)")
    if isinstance(steps_per_qa, bool) or not isinstance(steps_per_qa, (int, np.integer)):
        raise InputError(f"steps_per_qa = {steps_per_qa!r}: expected a whole number of steps per Qa, 1 to 1000")
    if not (np.isfinite(qa) and 0 < qa <= LARGEST / 1000):   # swept to factor x Qa: products stay finite
        raise InputError(f"qa = {qa!r}: expected the anticipated cross-coupling > 0 and at most "
                         f"{LARGEST / 1000:g} [N/m]")
    if not (np.isfinite(factor) and 1 <= factor <= 1000):
        raise InputError(f"factor = {factor!r}: expected a factor from 1 to 1000 (the sweep reaches factor x Qa)")
    if not 1 <= int(steps_per_qa) <= 1000:
        raise InputError(f"steps_per_qa = {steps_per_qa!r}: expected 1 to 1000 steps per Qa")
    return speed


def _shares(shares, count):
    if count == 0:
        raise InputError("no station: give at least one (a rotor's name, or ROTOR@OFFSET)")
    values = np.full(count, 1.0 / count) if shares is None else np.asarray(shares, dtype=float).ravel()
    if values.shape != (count,) or not np.all(np.isfinite(values)) or not np.all(values >= 0) or not values.sum() > 0:
        raise InputError(f"shares = {values.tolist()}: expected {count} values >= 0, one per station")
    return values / values.sum()


def disk_offset_hint(model, text: str, units: str = "si") -> str:
    """The end of the refusal of a station ``ROTOR@NAME`` whose NAME is no number but one of the
    flexible rotor's disks (an impeller, named as the model names it): the OFFSET to type
    instead, ``"; disk 'impeller-1' of rotor 'compressor' is at OFFSET -0.283265 m from its centre
    of mass: --station compressor@-0.283265"``, in the length unit of ``units`` (m; in for 'us');
    ``""`` when NAME is none of its disks."""
    rotor_name, _, name = str(text).rpartition("@")
    rotor = next((r for r in model.rotors if r.name == rotor_name), None)
    disk = next((d for d in (getattr(rotor, "disks", None) or ()) if str(d.get("name")) == name.strip()), None)
    if disk is None:
        return ""
    axis = np.asarray(model.spin_axis, dtype=float)
    centre = float((np.asarray(rotor.center_of_mass, dtype=float) - np.asarray(rotor.start, dtype=float)) @ axis)
    offset = to_system(float(disk["axial_position"]) - centre, "length", units)
    return (f"; disk {name.strip()!r} of rotor {rotor_name!r} is at OFFSET {offset:.6g} {unit_label('length', units)} "
            f"from its centre of mass: --station {rotor_name}@{offset:.6g}")


def _check_stations(model, stations):
    """Each station's rotor exists and moves in bearings of its own."""
    names = [r.name for r in model.rotors]
    for station in stations:
        if station.rotor not in names:
            known = f"the model's rotors are {', '.join(names)}" if names else \
                "the model has no [[rotors]]: a Level I analysis needs a rotor in bearings"
            hint = next((h for r in model.rotors if (h := disk_offset_hint(model, f"{r.name}@{station.rotor}",
                                                                             station.units))), "")
            raise InputError(f"station {station}: no rotor {station.rotor!r}: {known}{hint}")
        if not model.dofs.on_bearings(station.rotor):
            raise InputError(f"station {station}: rotor {station.rotor!r} has no bearings (it is rigidly attached to "
                             "the stator): cross-coupling needs a rotor moving in its bearings")
        _check_on_shaft(model, station)
    _check_distinct(stations)


def _check_distinct(stations):
    """No station given twice (``--station c@0.3 --station c@0.3``, or ``c`` and ``c@0``): both
    shares then act at one point, as one station taking their sum, and the typo of a second
    stage's place went unsaid."""
    seen = {}
    for i, station in enumerate(stations):
        key = (station.rotor, float(station.offset))
        if key in seen:
            raise InputError(f"station {station}: given twice (stations {seen[key] + 1} and {i + 1}, the same point of "
                             f"rotor {station.rotor!r}): expected each stage at its own station (one station takes "
                             "all of Q)")
        seen[key] = i


def _check_on_shaft(model, station):
    """A station of a flexible rotor lies on its shaft (off it, the nearest end node took the
    cross-coupling without a word)."""
    from ..model.flexible import STATION_TOLERANCE

    dofs = model.dofs
    shaft = dofs.shafts[dofs.rotors.index(station.rotor)] if dofs.shafts else None
    if shaft is None:
        _check_on_rigid(model, station)
        return
    z, length = shaft.z_of(station.point(model)), shaft.length
    slack = STATION_TOLERANCE * (1.0 + length)
    if not -slack <= z <= length + slack:
        centre = shaft.z_of(model.rotor(station.rotor).center_of_mass)
        shown = _lengths(station.units)
        raise InputError(f"station {station.rotor}@OFFSET, OFFSET = {shown(station.offset)}: expected a point on "
                         f"rotor {station.rotor!r}'s shaft, OFFSET from {shown(-centre, bare=True)} to {shown(length - centre)} "
                         f"(the shaft runs 0 to {shown(length)} from its start, its centre of mass at {shown(centre)}; "
                         f"this OFFSET is at {shown(z)})")


def _warn_between_nodes(model, stations) -> None:
    """One warning line per station of a flexible rotor that is no node of its shaft's mesh: the
    cross-coupling acts at the nearest node (:meth:`Dofs.local_relative_motion`), and the
    results, labelled with the station, are those of that node. On examples/compressor_rotor.toml
    (nodes at 0.57 and 0.66 m) Q0 stepped from 1.22372e6 to 1.23698e6 N/m between
    ``compressor@0.0317`` and ``compressor@0.0318``, with no word said."""
    import warnings

    from ..errors import ModelWarning
    from ..model.flexible import off_node

    dofs = model.dofs
    for station in stations:
        shaft = dofs.shafts[dofs.rotors.index(station.rotor)] if dofs.shafts else None
        z = None if shaft is None else float(shaft.z_of(station.point(model)))
        where = None if shaft is None else off_node(shaft, z)
        if where is None:
            continue
        node, offset = where
        at = z - offset
        shown = _lengths(station.units)
        centre = float(shaft.z_of(model.rotor(station.rotor).center_of_mass))
        warnings.warn(ModelWarning(
            f"station {station.label(station.units)}: {shown(z)} from the shaft's start, between the nodes of rotor "
            f"{station.rotor}'s mesh: the cross-coupling acts at its nearest node n{node} ({shown(at)} from the "
            f"start, OFFSET {shown(at - centre)}); give the rotor a station there (a sensor at that point) for a "
            "node at it"), stacklevel=3)


def _lengths(units: str):
    """A length [m] as a refusal shows it in ``units``: with its unit (``'0.583265 m'``,
    ``'22.9632 in'``), or the number alone with ``bare=True`` (a range's first end)."""
    def shown(value, bare: bool = False) -> str:
        number = f"{to_system(value, 'length', units):.6g}"
        return number if bare else f"{number} {unit_label('length', units)}"
    return shown


def _rigid_extent(model, name: str) -> tuple[float, float]:
    """The extent of rigid rotor ``name`` along ``spin_axis`` [m], as offsets from its centre of
    mass (low, high): the span of its bearings, unbalance planes, sensors, excitations and
    close-clearance stations, widened to the slender rod of its mass ``m`` and diametral inertia
    ``Id`` (half-length ``sqrt(3 Id / m)``), the longest body of that mass and inertia with its
    mass on the axis. A rigid rotor gives no length of its own; this is where it may stand."""
    rotor = model.rotor(name)
    e = np.asarray(model.spin_axis, dtype=float)
    centre = np.asarray(rotor.center_of_mass, dtype=float)
    half = float(np.sqrt(3.0 * rotor.diametral_inertia / rotor.mass))
    points = [b.position for b in model.bearings if b.rotor == name]
    points += [p.position for p in (*model.sensors, *model.excitations, *model.clearances) if p.rotor == name]
    offsets = [float((np.asarray(p, dtype=float) - centre) @ e) for p in points]
    offsets += [u.axial_offset for u in model.unbalances if u.rotor == name]
    return min([-half, *offsets]), max([half, *offsets])


def _check_on_rigid(model, station):
    """A station of a rigid rotor lies within its extent (:func:`_rigid_extent`): an OFFSET of
    1e6 m was taken without a word, a cross-coupling lever arm of no machine."""
    low, high = _rigid_extent(model, station.rotor)
    slack = 1e-6 * (1.0 + high - low)
    if not low - slack <= station.offset <= high + slack:
        shown = _lengths(station.units)
        raise InputError(f"station {station.rotor}@OFFSET, OFFSET = {shown(station.offset)}: expected a point on "
                         f"rigid rotor {station.rotor!r}, OFFSET from {shown(low, bare=True)} to {shown(high)} (its extent along "
                         "spin_axis from its centre of mass: its bearings, the points the model places on it, "
                         "and a slender rod of its mass and diametral inertia)")


def _spin_sign(model, stations) -> float:
    """The stations' rotors' spin direction relative to the reference rotor (+1 or -1); the
    stations must share it."""
    signs = {np.sign(model.rotor(s.rotor).speed_ratio) for s in stations}
    if len(signs) != 1 or 0 in signs:
        raise InputError("stations on rotors that spin different ways (or not at all): give stations of one "
                         "spin direction")
    return float(signs.pop())


def _unit_state_matrix(model, form, stations, shares, speed):
    """The state matrix per unit total Q: ``-M^-1 K_Q`` in the velocity rows, (n_states, n_states)."""
    layout = model.dofs
    n = form.n_dof
    e = np.asarray(model.spin_axis, dtype=float)
    a, b = transverse_axes(e)
    direction = np.sign(speed) * _spin_sign(model, stations)    # forward: with the stations' rotor's own spin
    local = np.zeros((6, 6))
    local[:3, :3] = direction * (np.outer(a, b) - np.outer(b, a))      # K_ab = +Q, K_ba = -Q
    K = np.zeros((n, n))
    for station, share in zip(stations, shares):
        rows = layout.slices[layout.rotors.index(station.rotor)]
        moves = layout.local_relative_motion(station.rotor, station.point(model))
        K[rows, rows] += share * (moves.T @ local @ moves)
    unit = np.zeros((form.n_states, form.n_states))
    unit[n:2 * n, :n] = -form.mass_inverse @ K
    return unit


def _forward_modes(model, lam, shapes, M, station, spin, among_all=False) -> np.ndarray:
    """Indices among ``lam`` (one Q), lowest frequency first, of the modes of the stations'
    rotor whirling forward: its motion relative to the stator at ``station`` turns with the
    rotor's spin ``spin`` (+-1), ``-2 spin Im(conj(U_a) U_b) / (|U_a|^2 + |U_b|^2) > 1e-3`` for the
    radial amplitudes ``U_a, U_b`` of the orbit ``Re(U e^{i w t})``, and is a mode of the rotor in
    its bearings: ``|U|^2`` at least :data:`_ROTOR_SHARE` of the largest among the modes, the
    shapes mass-normalised (a casing's mode on soft mounts barely moves the rotor in its
    bearings, and cross-coupling there cannot reach it); with ``among_all``, the
    largest among every root, real ones too (an overdamped rotor's roots at a small Q)"""
    layout = model.dofs
    rows = layout.slices[layout.rotors.index(station.rotor)]
    moves = layout.local_relative_motion(station.rotor, station.point(model))[:3]
    a, b = transverse_axes(np.asarray(model.spin_axis, dtype=float))
    modal_mass = np.einsum("mi,ij,mj->m", shapes.conj(), M, shapes).real
    motion = (shapes[:, rows] @ moves.T) / np.sqrt(np.where(modal_mass > 0, modal_mass, 1.0))[:, None]
    u_a, u_b = motion @ a, motion @ b
    size = np.abs(u_a) ** 2 + np.abs(u_b) ** 2
    oscillating = is_oscillating(lam)
    largest = (size if among_all else size[oscillating]).max(initial=0.0)
    ratio = np.zeros(len(lam))
    np.divide(-2 * spin * np.imag(np.conj(u_a) * u_b), size, out=ratio, where=size > 0)
    candidates = np.nonzero(oscillating & (ratio > _whirl.WHIRL_TOLERANCE) & (size >= _ROTOR_SHARE * largest)
                            & (largest > 0))[0]
    return candidates[np.argsort(lam.imag[candidates], kind="stable")]


#: a mode is one of the station's rotor in its bearings when the station's motion relative to the
#: stator is at least this part (squared amplitude, mass-normalised shapes) of the largest
_ROTOR_SHARE = 1e-2


#: the Q at which the modes are chosen, as a part of the machine's own stiffness scale (:func:`_small_q`)
_SMALL_Q = 1e-9
#: points per decade of the machine's sweep below and between Qa's grid points
_DECADE_POINTS = 10


def _small_q(base, unit, n: int) -> float:
    """A Q [N/m] that splits a forward and backward pair but moves no mode: :data:`_SMALL_Q` of the
    Q at which the cross-coupling's state rows are as large as the stiffness's
    (``||A_vq(0)|| / ||A_vq per unit Q||``, both ``M^-1`` times a stiffness)."""
    per_unit = np.linalg.norm(unit[n:2 * n, :n])
    return _SMALL_Q * float(np.linalg.norm(base[n:2 * n, :n]) / per_unit) if per_unit > 0 else 0.0


def _pick_index(model, lam, shapes, M, station, spin, last: int, forward_mode, order) -> int:
    """The first index of the sweep (1 to ``last``, Qa's first grid point) where the station's
    rotor has as many forward modes (:func:`_forward_modes`, at most :data:`FORWARD_MODES`, or
    ``forward_mode``) as at ``last``, each of them (followed by ``order``, (n_q, n_roots)) a mode
    at Q = 0 too; else ``last``: a rotor whose roots at Q = 0 do not oscillate (overdamped) has no
    forward modes until Q makes them whirl, and is followed from there, as chosen at ``last``.

    Returns
    -------
    index : int
    forward : ndarray of int
        :func:`_forward_modes` at ``index`` (found once where it is ``last``).
    """
    wanted = forward_mode if forward_mode is not None else FORWARD_MODES
    at_last = _forward_modes(model, lam[last], shapes[last], M, station, spin)
    target = min(wanted, len(at_last))
    for index in range(1, last):
        forward = _forward_modes(model, lam[index], shapes[index], M, station, spin, among_all=True)
        if len(forward) >= max(target, 1) and _modes_at_rest(lam, order, index, forward[:max(target, 1)]):
            return index, _forward_modes(model, lam[index], shapes[index], M, station, spin)
    return last, at_last


def _modes_at_rest(lam, order, index, roots) -> bool:
    """Whether each of ``roots`` (indices among ``lam[index]``), followed to Q = 0 by ``order``, is
    a mode there (:func:`~rotordyn_modal.analysis.modal.is_oscillating`)."""
    labels = [int(np.nonzero(order[index] == root)[0][0]) for root in roots]
    return bool(np.all(is_oscillating(lam[0, order[0, labels]])))


#: bytes of the sweep per value of Q per squared state: its state matrices (8), the upper shapes
#: (4: half the states by half, complex) and the eigen-solutions' parts and copies (about 4)
_SWEEP_BYTES = 16


def _refuse_what_cannot_fit(model, form, count: int):
    """Refuse, before its arrays are made, a sweep of ``count`` values of Q whose state matrices and
    shapes (all held at once, :data:`_SWEEP_BYTES`) would not fit in the memory at hand: 500 geared
    rotors (4,012 states) at about 150 values asked for 20 GB and were killed by the system."""
    where = f"{model.source}: " if getattr(model, "source", None) else ""
    problem = memory_problem(_SWEEP_BYTES * count * form.n_states ** 2,
                             f"{where}an API 617 Level I sweep of {form.n_dof:,} coordinates at {count} "
                             "values of Q", "sweep a shorter range (a smaller factor, --factor) or use a smaller model")
    if problem:
        raise InputError(problem)


#: eigenvalue-only solutions of the search for Q0 per followed mode (:func:`_zero_crossing`: the
#: two ends of the bracket and Brent's steps to 1e-12 of it: 8-9 counted per mode on the bundled
#: examples' documented commands, taken with room)
ZERO_SOLUTIONS = 16


def sweep_solutions(count: int, followed: int = FORWARD_MODES) -> float:
    """Dense eigen-solutions with vectors a Level I sweep of ``count`` values of Q is reckoned to
    take: one per value, and :data:`ZERO_SOLUTIONS` eigenvalue-only ones per followed mode (each
    ``_cost.EIGVALS_SHARE`` of one with vectors) for its Q0."""
    from ._cost import EIGVALS_SHARE

    return count + followed * ZERO_SOLUTIONS * EIGVALS_SHARE


def sweep_size(model, speed, stations, qa, shares=None, factor: float = 10.0, steps_per_qa: int = 10) -> int:
    """Values of Q :func:`level1` sweeps for these arguments (its grid to ``factor * qa`` and the
    machine's own points below Qa's first), from the model's state matrices at ``speed``
    [rad/s] alone: no eigen-solution (``report`` estimates its work with it before any)."""
    speed = _checked(speed, qa, factor, steps_per_qa)
    if isinstance(stations, (str, Station)):
        stations = (stations,)
    stations = tuple(s if isinstance(s, Station) else Station.parse(s) for s in stations)
    shares = _shares(shares, len(stations))
    _check_stations(model, stations)
    steps = int(steps_per_qa)
    grid = qa * (np.arange(int(np.ceil(factor * steps - 1e-9)) + 1) / steps)
    form = speed_linear_form(model)
    unit = _unit_state_matrix(model, form, stations, shares, speed)
    return len(_sweep_grid(grid, _small_q(form.at(speed), unit, form.n_dof))[0])


def _refuse_long_work(model, form, count: int, followed: int):
    """Refuse, before its first eigen-solution, a sweep of ``count`` values of Q estimated
    (:func:`sweep_solutions`, :func:`._cost.eig_seconds`) to take more CPU time than the limit
    in force, unless long work is allowed (``--allow-long``, ``rdm.long_work_allowed()``): 500
    geared rotors (4,012 states) at 130 values of Q are about 3 h of CPU time."""
    from . import _cost

    solutions = sweep_solutions(count, followed)
    over = _cost.eigen_solutions_over_limit(form.n_states, solutions)
    if over is None:
        return
    seconds, limit = over
    where = f"{model.source}: " if getattr(model, "source", None) else ""
    raise InputError(f"{where}an API 617 Level I sweep of {form.n_dof:,} coordinates at {count} values of Q would take "
                     f"about {_cost.duration(seconds)} of CPU time ({count} eigen-solutions of {form.n_states:,} "
                     f"states, and about {followed * ZERO_SOLUTIONS} more of the eigenvalues alone for Q0), more than the limit "
                     f"of {_cost.duration(limit)}: sweep a shorter range (a smaller factor, --factor) or use a smaller "
                     f"model, or add --allow-long ({_cost.ENVIRONMENT} sets the limit)")


def _sweep_grid(grid, small: float):
    """The sweep's Q [N/m]: Qa's ``grid`` (0 first) with, where ``small`` is below its first
    Q > 0, the geometric points from ``small`` up to it (:data:`_DECADE_POINTS` per decade);
    and the index of each grid point in it."""
    if not 0 < small < grid[1]:
        return grid, np.arange(len(grid))
    count = int(np.ceil(_DECADE_POINTS * np.log10(grid[1] / small)))
    extra = np.geomspace(small, grid[1], count + 1)[:-1]
    sweep = np.concatenate([grid[:1], extra, grid[1:]])
    return sweep, np.concatenate([[0], np.arange(len(grid) - 1) + 1 + len(extra)])


def _zero_crossing(base, unit, n, grid, followed, log_dec) -> float:
    """The Q where the followed mode's real part reaches 0: Brent's method between the grid
    points around the first sign change, on the root nearest the followed one (interpolated).
    0 where the mode is undamped at Q = 0 (its log decrement within the round-off of
    :data:`.campbell.ROUND_OFF_RELATIVE`: any Q > 0 makes it grow; the spring-block rotor's
    +3.9e-16 gave Q0 = 3.3e-13 N/m, Q0/Qa = 1.65e-18, round-off printed as a result)."""
    from .campbell import ROUND_OFF_RELATIVE

    if not log_dec[0] > 2 * np.pi * ROUND_OFF_RELATIVE:
        return 0.0
    below = np.nonzero(log_dec <= 0)[0]
    if not len(below):
        return float("nan")
    k = int(below[0])

    def real_part(q):
        t = (q - grid[k - 1]) / (grid[k] - grid[k - 1])
        guess = (1 - t) * followed[k - 1] + t * followed[k]
        roots = np.linalg.eigvals(base + q * unit)
        return float(roots[np.argmin(np.abs(roots - guess))].real)

    low, high = real_part(grid[k - 1]), real_part(grid[k])
    if high == 0:
        return float(grid[k])
    if not low * high < 0:   # the sweep's sign change is round-off (a mode undamped at Q = 0): no root between
        return float(grid[k - 1] if low >= 0 else grid[k])   # unstable at the lower end already: Q0 there
    return float(brentq(real_part, grid[k - 1], grid[k], xtol=1e-12 * grid[k], rtol=8.9e-16))


def csr_boundary(density):
    """The CSR chart's dividing line between Region A (below) and Region B (above).

    As ROSS implements API 617's chart (docs/standards.md): 2.5 up to 16.53 kg/m^3, then
    ``2.69 - 0.0115 rho`` down to 2.0 at 60 kg/m^3, and 0 beyond 60 kg/m^3.

    Parameters
    ----------
    density : array_like [kg/m^3]
        Average gas density.

    Returns
    -------
    ndarray, the shape of ``density`` [-]
    """
    rho = np.asarray(density, dtype=float)
    line = np.where(rho <= _CSR_KNEE, _CSR_FLAT, _CSR_INTERCEPT + _CSR_SLOPE * rho)
    return np.where(rho > _CSR_END, 0.0, line)


@dataclass(frozen=True)
class CsrScreening:
    """The rotor's point on API 617's chart of critical speed ratio against average gas density.

    Attributes
    ----------
    speed : float [rad/s]
        Maximum continuous speed (> 0).
    critical_speed : float [rad/s]
        First forward critical speed on rigid supports (:func:`rigid_support_critical_speed`);
        nan when there is none (a rigid rotor pinned at its bearings cannot bend).
    densities : tuple of float [kg/m^3]
        As given: the average, or the suction and discharge densities.
    """

    speed: float
    critical_speed: float
    densities: tuple

    @property
    def density(self) -> float:
        """Average gas density [kg/m^3]: the mean of the given densities."""
        return float(np.mean(self.densities))

    @property
    def csr(self) -> float:
        """``MCS / critical_speed``; 0 when there is no critical speed on rigid supports."""
        return float(self.speed / self.critical_speed) if np.isfinite(self.critical_speed) else 0.0

    @property
    def boundary(self) -> float:
        """The dividing line's CSR at :attr:`density`."""
        return float(csr_boundary(self.density))

    @property
    def region(self) -> str:
        """'B' above the dividing line (strictly), 'A' on or below it."""
        return "B" if self.csr > self.boundary else "A"

    def dividing_line(self, end: float | None = None) -> tuple:
        """The chart's line from 0 to ``end`` [kg/m^3] (default: past 60 kg/m^3 and the
        machine's density): ``(rho, csr)``, each shape (N,), its kinks among the points (the
        drop at 60 kg/m^3 as two points, 60 and just above)."""
        end = max(80.0, 1.25 * self.density) if end is None else float(end)
        rho = np.linspace(0.0, end, 401)
        rho = np.unique(np.concatenate([rho, [x for x in (_CSR_KNEE, _CSR_END, np.nextafter(_CSR_END, np.inf))
                                              if x <= end]]))
        return rho, csr_boundary(rho)

    @property
    def evaluated(self) -> bool:
        """False where there is no critical speed on rigid supports (a rigid rotor pinned at its
        bearings has no bending mode): the ratio has nothing to judge."""
        return bool(np.isfinite(self.critical_speed))

    def summary(self, units: str = "si") -> str:
        """``CSR = 1.9 at 35 kg/m³: Region A (line 2.29)``, the density in ``units``; ``CSR not
        evaluated: no critical speed on rigid supports ...`` where :attr:`evaluated` is False."""
        scale, unit = _density_unit(units)
        if not self.evaluated:
            return f"CSR not evaluated at {self.density * scale:.4g} {unit}: {NO_RIGID_SUPPORT_CRITICAL}"
        return (f"CSR = {self.csr:.3g} at {self.density * scale:.4g} {unit}: Region {self.region} "
                f"(line {self.boundary:.3g})")

    def plot(self, **kwargs):
        """The chart; see :func:`rotordyn_modal.plotting.plot_csr_chart`."""
        from ..plotting import plot_csr_chart

        return plot_csr_chart(self, **kwargs)


#: why a critical speed ratio is not evaluated
NO_RIGID_SUPPORT_CRITICAL = ("no critical speed on rigid supports (the rotor pinned at its bearings has no "
                             "bending mode: a rigid rotor)")


def _density_unit(units):
    from ..units import unit_scale

    return unit_scale("density", units)


def _gas_densities(gas_density) -> tuple:
    """One average density, or suction and discharge, each finite and > 0 [kg/m^3]."""
    values = np.atleast_1d(np.asarray(gas_density, dtype=float)).ravel()
    if not 1 <= len(values) <= 2 or not np.all(np.isfinite(values)) or not np.all(values > 0):
        raise InputError(f"gas_density = {values.tolist()}: expected the average gas density, or the suction "
                         "and discharge densities, finite and > 0 [kg/m^3]")
    return tuple(float(v) for v in values)


def csr_screening(model, speed, gas_density) -> CsrScreening:
    """API 617 Level I: the rotor's critical speed ratio against the average gas density.

    Parameters
    ----------
    model : Model
    speed : float [rad/s]
        Maximum continuous speed of the reference rotor (its sign is ignored).
    gas_density : float or (float, float) [kg/m^3]
        The average gas density, or the suction and discharge densities (averaged).

    Returns
    -------
    CsrScreening
    """
    densities = _gas_densities(gas_density)
    speed = abs(_arguments.speed(speed))
    if speed == 0:
        raise InputError("speed = 0: the critical speed ratio needs the maximum continuous speed (not 0)")
    return CsrScreening(speed=speed, critical_speed=rigid_support_critical_speed(model), densities=densities)


def rigid_support_critical_speed(model) -> float:
    """First forward critical speed of ``model`` on rigid supports [rad/s] (nan when none).

    Every bearing radially rigid (each rotor pinned to its support at its bearings' points;
    their axial and tilt stiffness kept) and the supports fixed: the stator (or frame) and the
    pedestals do not move. Undamped, synchronous with the reference rotor, forward whirl, as in
    the UCS map (:func:`rotordyn_modal.analysis.ucs_map.forward_critical_speeds`); it is the
    map's rigid-support asymptote with the casing held as well.
    """
    from .ucs_map import _Pencil, _rigid_support

    if not model.bearings:
        raise InputError("no bearings: a critical speed on rigid supports needs a rotor on bearings")
    chosen = list(model.bearings)
    return float(_rigid_support(_Pencil(model, chosen), model, chosen, 1, supports_fixed=True)[0])
