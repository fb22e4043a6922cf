"""The results of a report: the analyses a standard asks for, each criterion with its value,
limit and verdict (no figure here: :mod:`.render` draws them).

Sections (``ReportData.sections``, in order; a later one, such as the mode shapes of a
flexible rotor, is one more entry of :data:`SECTIONS` and one more ``_collect_*`` step):
``model``, ``static``, ``campbell`` (critical speeds, amplification factors and separation
margins), ``modes`` (the mode shapes of the modes near the operating range), ``ucs`` (undamped
critical speed map), ``unbalance`` (probe limits and the clearance check at close-clearance
stations), ``level1`` (API 617 Level I stability), ``iso`` (ISO 20816-3 zones).
"""

from __future__ import annotations

import functools
import hashlib
import io
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from .._progress import phase
from ..errors import InputError
from ..unbalance_standards import AMPLITUDE_WORDS, amplitude_factor, largest_margins_text, required_separation_margin
from ..io.text import shown_text
from ..units import check_system, rpm_text, unit_scale

__all__ = ["STANDARDS", "SECTIONS", "SHOWN_UNITS", "shown_scale", "AMPLITUDE_WORDS", "from_pkpk", "CRITERION_SOURCES", "Criterion", "ReportInputs", "ReportData", "collect",
           "separation_margins", "iso_span", "ucs_stiffness", "UCS_STIFFNESS", "ReportWork", "estimate_work",
           "refuse_long_work", "ModeShapes", "MODE_WINDOW", "LOWEST_MODES", "MOST_MODES"]

#: section id -> heading
SECTIONS = {"model": "Model", "static": "Static loads and sag", "campbell": "Campbell diagram and critical speeds",
            "modes": "Mode shapes near the operating range", "ucs": "Undamped critical speed map", "unbalance": "Unbalance response and probe limits",
            "level1": "API 617 Level I stability", "iso": "ISO 20816-3 vibration zones"}

#: standard -> its sections, in order
STANDARDS = {"api617": ("model", "static", "campbell", "modes", "ucs", "unbalance", "level1"),
             "api684": ("model", "static", "campbell", "modes", "ucs", "unbalance"),
             "iso": ("model", "static", "campbell", "modes", "unbalance", "iso")}

#: the modes section's window: the operating range widened by the largest separation margins
#: API 617 requires (below it 16 %, above it 26 %: ``min(16, 17 (1 - 1/(AF - 1.5)))`` and
#: ``min(26, 10 + 17 (1 - 1/(AF - 1.5)))``): a mode whose 1X critical speed or whose frequency at
#: the MCS (as a 1X speed) lies in it could fail the margin
MODE_WINDOW = tuple(required_separation_margin(np.inf, side) / 100 for side in ("below", "above"))
#: modes shown when none lies in the window: the lowest at the MCS
LOWEST_MODES = 4
#: most modes shown (the lowest numbers of those in the window)
MOST_MODES = 8


#: what the report shows of each quantity: report kind -> {system: (factor from SI, label)}
#: (vibration amplitudes in µm or mil, casing velocity in mm/s or in/s, static displacement in
#: µm or in; the US units are those of docs/units.md)
SHOWN_UNITS = {
    "vibration": {"si": (1e6, "µm"), "us": unit_scale("displacement", "us")},
    "velocity": {"si": (1e3, "mm/s"), "us": unit_scale("velocity", "us")},
    "sag": {"si": (1e6, "µm"), "us": unit_scale("length", "us")},
    "force": {"si": unit_scale("force", "si"), "us": unit_scale("force", "us")},
    "stiffness": {"si": unit_scale("stiffness", "si"), "us": unit_scale("stiffness", "us")},
    "mass": {"si": unit_scale("mass", "si"), "us": unit_scale("mass", "us")},
    "density": {"si": unit_scale("density", "si"), "us": unit_scale("density", "us")},
    "stress": {"si": (1e-6, "MPa"), "us": unit_scale("pressure", "us")},
}


def shown_scale(kind: str, system: str = "si") -> tuple:
    """``(factor, label)``: an SI value of report kind ``kind`` (:data:`SHOWN_UNITS`) times
    ``factor`` is the number the report shows in ``label``, the unit of ``system``."""
    return SHOWN_UNITS[kind][check_system(system)]


def from_pkpk(amplitude: str) -> float:
    """Factor from a peak-to-peak amplitude (the API probe limits and clearances are judged
    peak-to-peak) to the convention ``amplitude`` ('peak', 'pk-pk', 'rms'): 1/2, 1, 1/(2 sqrt 2)."""
    return amplitude_factor(amplitude) / amplitude_factor("pk-pk")


#: where each criterion's rule comes from, by the beginning of its name (first match): the
#: standard, edition and clause as far as checked, and the page of the docs that writes the rule
#: out with its public sources and what stays unverified (no quantity with a unit: the text is
#: the same in every unit system)
CRITERION_SOURCES = (
    ("Shaft stress", "the material's allowable_stress of the model file; von Mises stress, docs/static.md (Stress)"),
    ("API 684 separation margin", "API 617 / API RP 684 (2nd ed.) SP6.8.2.1 and SP6.8.2.10 as ROSS cites them "
                                  "(clauses not verified); docs/standards.md"),
    ("API 617 probe vibration limit", "API 617 (9th ed.) 6.8.2.10 as ROSS cites it; docs/standards.md"),
    ("API 617 clearance", "API 617 (9th ed.) 6.8.2.10 and 6.8.2.11 as ROSS PR 1377 implements them; "
                          "docs/standards.md"),
    ("API 617 Level I: critical speed ratio", "API 617 (7th ed.) Level I chart, its line as ROSS implements it "
                                              "(unverified against the standard); docs/standards.md"),
    ("API 617 Level I", "API 617 (7th ed., kept in the 8th) Level I, API RP 684 (2nd ed.) SP6.8.5, as ROSS "
                        "implements it (unverified against the standard); docs/level1_and_ucs.md"),
    ("Stability over the operating range", "not an API or ISO criterion: a linear model with a growing mode has "
                                           "no steady unbalance response there; onset as 'rotordyn-modal stability' "
                                           "refines it; docs/report.md, docs/standards.md"),
    ("ISO 20816-3", "ISO 20816-3 zone boundaries (those of ISO 10816-3:2009 Annex A); docs/standards.md"),
)


@dataclass(frozen=True)
class Criterion:
    """One line of the summary: a criterion, its value, limit and verdict.

    ``verdict`` is 'pass', 'fail' or 'not evaluated'; ``why`` says why not evaluated (or which
    item governs); ``section`` the id of the section that holds its numbers. ``value``,
    ``limit`` and ``why`` are the SI text; ``quantities`` holds, for those with a unit,
    ``(field, template, kind, si_values)``: the text is ``template.format(*numbers, unit=label,
    amplitude=words)`` with the numbers in the unit of a system and, for kind 'vibration' (whose
    SI values are peak-to-peak), in an amplitude convention (:meth:`in_system`).
    """

    name: str
    value: str
    limit: str
    verdict: str
    section: str
    why: str = ""
    quantities: tuple = ()

    @classmethod
    def of(cls, name, verdict, section, why="", value="", limit="", quantities=()):
        """A criterion whose fields named in ``quantities`` are written from their SI values."""
        made = cls(name, value, limit, verdict, section, why, tuple(quantities))
        return made.in_system("si")

    @property
    def source(self) -> str:
        """Where the criterion's rule comes from (:data:`CRITERION_SOURCES`)."""
        return next((text for start, text in CRITERION_SOURCES if self.name.startswith(start)), "")

    def in_system(self, system: str, amplitude: str = "pk-pk") -> "Criterion":
        """This criterion with its quantities written in ``system`` ('si' or 'us'), its
        vibration amplitudes in the convention ``amplitude`` ('peak', 'pk-pk', 'rms'; the words
        :data:`AMPLITUDE_WORDS` after the unit); the verdict is the same (judged in SI, pk-pk)."""
        def scale(kind):
            return shown_scale(kind, system)[0] * (from_pkpk(amplitude) if kind == "vibration" else 1.0)

        texts = {field: template.format(*(v * scale(kind) for v in values), unit=shown_scale(kind, system)[1],
                                        amplitude=AMPLITUDE_WORDS[amplitude])
                 for field, template, kind, values in self.quantities}
        return replace(self, **texts)


@dataclass(frozen=True)
class ReportInputs:
    """What a report is asked for (speeds in rad/s).

    Parameters
    ----------
    standard : {'api617', 'api684', 'iso'}
    mcs : float [rad/s]
        Maximum continuous speed of the reference rotor, > 0.
    operating : (float, float) [rad/s]
        Operating speed range (0 < low <= high <= mcs); default (mcs, mcs).
    points : int
        Speeds of the sweeps, from 2 % of the MCS to 1.5 MCS (journal bearings have no film at rest);
        the MCS and the operating range's ends are added to them (:attr:`speeds`).
    iso_group, iso_support : ISO 20816-3 class (both or neither).
    amplitude : {'pk-pk', 'peak', 'rms'}
        Convention of every vibration amplitude shown (tables, figure, summary; default
        peak-to-peak, as probes are read and the API limits are written); the ISO zones judge
        the RMS velocity whatever it is.
    level1 : dict, optional
        ``{"stations": [Station], "qa": float [N/m], "shares": array or None}``, and optionally
        ``"gas_density"``: the average, or suction and discharge densities [kg/m^3] (adds the
        critical speed ratio criterion).
    stiffness : ndarray [N/m], optional
        Bearing stiffness values of the UCS map; default (None) :data:`UCS_STIFFNESS`, widened by
        whole decades to reach the chosen bearings' own stiffness where it lies outside.
    command : str
        The command line that produced the report.
    """

    standard: str
    mcs: float
    operating: tuple | None = None
    points: int = 151
    iso_group: int | None = None
    iso_support: str | None = None
    level1: dict | None = None
    stiffness: np.ndarray | None = None
    command: str = ""
    amplitude: str = "pk-pk"

    @property
    def speeds(self) -> np.ndarray:
        """The sweeps' speeds [rad/s]: ``points`` from 2 % of the MCS to 1.5 MCS, and the MCS and
        the operating range's ends themselves (the checks run "from 0 to the MCS" and the margins
        from the range: a grid point just below the MCS would miss a peak between it and the MCS);
        a grid point within 1e-9 of one of them gives way to it."""
        grid = np.linspace(0.02 * self.mcs, 1.5 * self.mcs, self.points)
        marks = np.unique([self.mcs, *self.range])
        apart = np.all(np.abs(grid[:, None] - marks[None, :]) > 1e-9 * self.mcs, axis=1)
        return np.sort(np.concatenate([grid[apart], marks]))

    @property
    def range(self) -> tuple:
        return tuple(self.operating) if self.operating is not None else (self.mcs, self.mcs)


@dataclass(frozen=True)
class ModeShapes:
    """The modes of the ``modes`` section, at the MCS.

    Attributes
    ----------
    modal : ModalResult
        At the MCS: its mode numbers are those of ``modes --speed MCS``.
    numbers : tuple of int
        The modes shown, increasing.
    reasons : tuple of str
        Why each is shown (its 1X critical speed or its frequency in the window, or the lowest).
    window : (float, float) [rad/s]
    tracked : tuple of int
        Each shown mode's number in the Campbell diagram and the critical-speed table (tracked over
        the sweep, as ``stability`` and ``critical-speeds`` number it; 0 where no tracked column is
        that root at the MCS); () without a Campbell sweep.
    lines : tuple of ShaftLines or None
        Each mode's deflected shaft lines when a rotor is flexible (None: rigid rotors only,
        drawn as the mode-shape bar chart).
    note : str
        Said under the section's introduction: why the modes shown are not the window's (it
        holds only axial or torsional modes of a flexible rotor, whose lines are flat), or "".
    """

    modal: object
    numbers: tuple
    reasons: tuple
    window: tuple
    lines: tuple | None = None
    note: str = ""
    tracked: tuple = ()


@dataclass
class ReportData:
    """Everything a report shows: ``results`` (section id -> analysis result objects, or
    ``None`` with ``skipped[id]`` saying why), ``criteria`` (the summary), ``model_info``."""

    inputs: ReportInputs
    model: object
    model_info: dict
    sections: tuple
    results: dict = field(default_factory=dict)
    skipped: dict = field(default_factory=dict)
    criteria: list = field(default_factory=list)
    warnings: list = field(default_factory=list)


def collect(model, inputs: ReportInputs, progress: bool = False, allow_long: bool = False) -> ReportData:
    """Run the analyses of ``inputs.standard`` on ``model`` (``progress``: a line naming the section
    under way, with its elapsed time, where it runs more than a few seconds).

    Work estimated to take more CPU time than the limit in force (``ROTORDYN_MODAL_MAX_CPU_MINUTES``,
    30 min by default) is refused before any section runs (:func:`refuse_long_work`), as the
    ``report`` command refuses it, unless ``allow_long`` (the command's ``--allow-long``) or inside
    ``rdm.long_work_allowed()``.

    Parameters
    ----------
    model : Model
    inputs : ReportInputs
    progress : bool
    allow_long : bool
        Run work estimated over the limit anyway (the sections' own refusals lifted too).

    Returns
    -------
    ReportData

    Raises
    ------
    InputError
        Bad inputs, or work over the limit: ``MODEL: this report of N coordinates would take about
        ... of CPU time (...), more than the limit of 30 min: ...``.
    """
    from ..analysis._cost import long_work_allowed, long_work_is_allowed

    with long_work_allowed(allow_long or long_work_is_allowed()):
        return _collected(model, inputs, progress)


def _collected(model, inputs, progress) -> ReportData:
    """:func:`collect`, its limit of CPU time as :func:`..analysis._cost.long_work_is_allowed` says."""
    if inputs.standard not in STANDARDS:
        raise InputError(f"standard {inputs.standard!r}: expected one of {', '.join(STANDARDS)}")
    if not (np.isfinite(inputs.mcs) and inputs.mcs > 0):
        raise InputError(f"maximum continuous speed {inputs.mcs!r} rad/s: expected a speed > 0")
    amplitude_factor(inputs.amplitude)                 # refuses an unknown convention by name
    low, high = inputs.range
    if not 0 < low <= high:
        raise InputError(f"operating range {low!r}:{high!r} rad/s: expected 0 < low <= high")
    if high > inputs.mcs * (1 + 1e-12):
        raise InputError(f"operating range {low!r}:{high!r} rad/s: expected its top at most the maximum continuous "
                         f"speed {inputs.mcs!r} rad/s (the top of the operating range)")
    model, probes = _judged_at_bearings(model, inputs)
    refuse_long_work(model, inputs)          # before any section: one line with the estimate
    data = ReportData(inputs, model, model_summary(model), STANDARDS[inputs.standard])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if probes:
            warnings.warn(f"the model has no [[sensors]]: the unbalance response is judged at X-Y proximity probes "
                          f"placed at each bearing ({', '.join(probes)}); give [[sensors]] with measure = "
                          "\"relative\" where the machine's probes are", stacklevel=2)
        if "level1" in data.sections:   # first: a bad --station is refused before the long work
            with phase(progress, f"report: {SECTIONS['level1']}"):
                _level1(data)
        for section in data.sections:
            if section != "level1":
                with phase(progress, f"report: {SECTIONS[section]}"):
                    _STEPS[section](data)
    order = {s: i for i, s in enumerate(data.sections)}
    data.criteria.sort(key=lambda c: order[c.section])
    data.warnings = sorted({str(w.message) for w in caught})
    return data


#: the report's undamped critical speed map, per value of its stiffness grid (its own and the
#: constant bearings' values) and of its speed-dependent bearings' anchors
#: (``_ucs_ritz.CURVE_ANCHORS`` a bearing; today's route: ``_CURVE_POINTS`` a bearing and axis):
#: a complex Hermitian eigen-solution of the coordinates, its
#: factorisations and the modes' following, as a share of one dense eigen-solution of the state
#: matrix (:func:`.._cost.eig_seconds`; measured about 0.1 on the 60-rotor gear chain, 246
#: coordinates and 443 values, a map of 41 values taking 6.1 s of CPU)
UCS_SHARE = 0.25
#: one API unbalance case (a model of its own, its state form made, checked and solved at every
#: speed), as a share of one dense eigen-solution of the state matrix: per case, and per case
#: and speed (the direct solve). Measured on gear chains with a sensor, making the case included,
#: its peaks not looked for: a case at 41 speeds 0.75 at 100 rotors (406 coordinates), 0.43 at
#: 200 (806 coordinates; at 5 speeds 0.13): these take 0.92, 0.92 and 0.38
CASE_SHARE = 0.3
SOLVE_SHARE = 0.015
#: each API unbalance case's work outside its solves (its model made and checked, its forces
#: :func:`..analysis.forces.all_forces`) [CPU s per coordinate]: measured about 30 ms a case at
#: 30 coordinates (6-rotor gear chain) and 0.12 s at 86 (20 rotors); work of Python, not of
#: LAPACK, so counted in seconds, not in eigen-solutions
CASE_DOF_SECONDS = 1.4e-3
#: the checks' own searches: the clearance check's and the probe limits' (measured 0.05-0.2 s)
#: [CPU s] each, where the model has clearances, proximity probes
CHECK_SECONDS = 0.2
#: a Level I sweep's values of Q beyond Qa's grid taken by the bound without timing (the
#: machine's own points below Qa's first grid point, :data:`_DECADE_POINTS` a decade: 300 is 30
#: decades)
_LEVEL1_EXTRA = 300


@dataclass(frozen=True)
class ReportWork:
    """A report's estimated CPU time [s], by section (:func:`estimate_work`).

    Attributes
    ----------
    n_dof, n_states : int
        Coordinates and states of the model.
    parts : tuple of (str, float, str)
        ``(section id, seconds, what)``: each section's estimate and what it counts.
    """

    n_dof: int
    n_states: int
    parts: tuple

    @property
    def seconds(self) -> float:
        return float(sum(seconds for _, seconds, _ in self.parts))

    def text(self) -> str:
        """``about 9.6 h of CPU time (Campbell diagram and critical speeds: 2.1 h, 153
        eigen-solutions of 4,012 states...; Unbalance response...: 7.5 h, 1,000 API cases at
        153 speeds)``, the sections that take any time, the longest first."""
        from ..analysis._cost import duration

        shown = sorted((p for p in self.parts if p[1] > 0), key=lambda p: -p[1])
        inner = "; ".join(f"{SECTIONS.get(section, PAGE_PART)}: {duration(seconds)}, {what}"
                          for section, seconds, what in shown)
        return f"about {duration(self.seconds)} of CPU time ({inner})"


def _sweep_counts(model, inputs) -> dict:
    """What each section of ``inputs.standard`` solves, from the sizes (no matrix): section id
    -> count (eigen-solutions of the sweep, values of the UCS map, (cases, speeds) of the
    unbalance response, or the Level I sweep's values of Q before its machine's own points)."""
    sections, speeds = STANDARDS[inputs.standard], len(inputs.speeds)
    counts = {"campbell": speeds, "modes": 1}
    if "ucs" in sections and model.bearings:
        stiffness = UCS_STIFFNESS if inputs.stiffness is None else np.asarray(inputs.stiffness, dtype=float)
        counts["ucs"] = _map_values(model, stiffness)
    if "unbalance" in sections and model.sensors:
        if inputs.standard != "iso":
            counts["unbalance"] = (_api_cases(model, inputs.mcs), speeds)
        elif model.unbalances:
            counts["unbalance"] = (len({u.rotor for u in model.unbalances}), speeds)
    return counts


def _api_cases(model, mcs=None) -> int:
    """How many API unbalance cases :func:`..analysis.unbalance_checks.api_unbalance_cases`
    makes, without making them (each is a model of its own): a static case per turning rotor,
    a couple case for one on bearings at two axial places or more, and a flexible rotor's mode
    cases at ``mcs`` [rad/s] (counted where it is given)."""
    return len(_api_case_ratios(model, mcs))


def _api_case_ratios(model, mcs=None) -> list:
    """The speed ratio of each API unbalance case's rotor, in the order
    :func:`..analysis.unbalance_checks.api_unbalance_cases` makes them (not made here; a flexible
    rotor's mode cases from :func:`..analysis.unbalance_checks.api_mode_placements` at ``mcs``
    [rad/s], one undamped modal solution kept on the model for the cases: none without ``mcs`` or
    where the model's matrices cannot be had, the cases then refusing it by name)."""
    from ..analysis.unbalance_checks import api_mode_placements
    from ..errors import ModelError

    placements = []
    if mcs is not None and any(r.flexible is not None and r.speed_ratio != 0 for r in model.rotors):
        try:
            placements = api_mode_placements(model, mcs)
        except (InputError, ModelError, np.linalg.LinAlgError, ValueError):
            placements = []
    ratios = []
    for rotor in model.rotors:
        if rotor.speed_ratio == 0:
            continue
        centre = np.asarray(rotor.center_of_mass, dtype=float)
        places = {float((np.asarray(b.position, dtype=float) - centre) @ model.spin_axis)
                  for b in model.bearings_of(rotor.name)}
        modes = sum(p.rotor == rotor.name for p in placements)
        ratios += [abs(float(rotor.speed_ratio))] * (1 + (len(places) >= 2) + modes)
    return ratios


#: the name of the estimate's part (``"page"``) that is no section: the page made of the results
PAGE_PART = "Figures and page"
#: the page (:func:`.render.render_html`: each figure drawn, laid out and encoded as a PNG), work of
#: Python and matplotlib, not of LAPACK, counted in reference drawings
#: (:func:`reference_drawing_seconds`, timed on the machine that runs the report): by section, a
#: part of its own and a part per unit of its size (:func:`_render_sizes`). Measured by
#: ``benchmarks/report_page_cost.py`` (0.13-0.15 s a reference drawing there) on the gear chains
#: of 1, 3, 6, 10 and 20 rotors (10 to 86 coordinates, 6 to 1,889 crossings, two sensors) and on
#: four examples (journal_rotor, compressor_rotor, compressor_on_journals,
#: flexible_pump_on_mounts): the Campbell diagram 2.2, 20, 71, 31, 82 drawings (its labels'
#: placement: 0.35 a crossing up to the 200 the figure labels) and 1.7-3.5 on the examples; the
#: rigid machines' mode shapes (a bar panel of every coordinate a mode) 1.0, 6.1, 11.8, 16.3, 29.4,
#: the shaft lines of flexible rotors 3.5-4.0; the UCS map 5.5-12.4; the unbalance figure 5.2-18.8
#: at two sensors, 12.1-22.2 at five; the static loads' shafts 3.2-4.3; Level I 1.6-1.8
RENDER_DRAWINGS = {"campbell": (1.5, 0.35), "modes": (0.0, 0.34), "shaft_modes": (4.0, 0.0), "ucs": (8.0, 0.0),
                   "unbalance": (2.0, 3.0), "static": (4.0, 0.0), "level1": (2.0, 0.0)}
#: a reference drawing's CPU seconds taken without timing it (the pessimistic bound): twice the
#: test machine's
UNTIMED_DRAWING_SECONDS = 0.3


def reference_drawing_seconds() -> float:
    """CPU seconds [s] of one reference drawing on this machine: a 6 x 4 in figure of eight lines
    of 200 points with labels, legend and grid, laid out (constrained) and encoded as a 110 dpi PNG
    as the report's figures are; the shortest of ``_cost._REPEATS`` timings, made once a process.
    The unit of :data:`RENDER_DRAWINGS`: a machine that draws twice as fast makes its page twice
    as fast, which the fixed seconds of one machine did not follow."""
    return _timed_drawing()


@functools.lru_cache(maxsize=1)
def _timed_drawing() -> float:
    from ..analysis import _cost

    _reference_drawing()                                          # fonts and the backend loaded
    return max(_cost.shortest_cpu(_reference_drawing), 1e-3)


def _reference_drawing() -> None:
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(layout="constrained", figsize=(6.0, 4.0))
    x = np.linspace(0.0, 1.0, 200)
    for k in range(8):
        ax.plot(x, np.sin(3.0 * (k + 1) * x) + k, label=f"line {k}")
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize=7)
    ax.grid(True)
    fig.set_dpi(110)
    fig.draw_without_rendering()
    fig.set_layout_engine("none")
    fig.savefig(io.BytesIO(), format="png", dpi=110)
    plt.close(fig)


def _render_sizes(model, crossings: int) -> dict:
    """Each section's size for :data:`RENDER_DRAWINGS`: the Campbell diagram's labelled critical
    speeds (``crossings`` expected, at most the figure's labels), the coordinates of a rigid
    machine's mode shapes (none for shaft lines), the unbalance figure's sensors."""
    from ..plotting.campbell import _MAX_CRITICAL_LABELS

    return {"campbell": min(int(crossings), _MAX_CRITICAL_LABELS), "modes": model.dofs.n, "shaft_modes": 0,
            "ucs": 0, "unbalance": len(model.sensors), "static": 0, "level1": 0}


def _render_seconds(model, inputs, crossings: int, drawing: float) -> tuple:
    """``(CPU seconds [s], figures)`` of the page of ``inputs.standard``'s sections on ``model``
    (:data:`RENDER_DRAWINGS` of ``drawing`` [s] each; ``crossings`` the Campbell diagram's
    expected critical speeds; the shafts' figure of the static loads where a rotor is flexible,
    the UCS map where there are bearings, the unbalance figure where there are sensors)."""
    flexible = any(r.flexible is not None for r in model.rotors)
    drawn = {"campbell": True, "modes": True, "ucs": bool(model.bearings), "unbalance": bool(model.sensors),
             "static": flexible, "level1": inputs.level1 is not None}
    shown = [s for s in STANDARDS[inputs.standard] if s in drawn and drawn[s]]
    sizes = _render_sizes(model, crossings)
    kinds = ["shaft_modes" if s == "modes" and flexible else s for s in shown]
    drawings = sum(RENDER_DRAWINGS[k][0] + RENDER_DRAWINGS[k][1] * sizes[k] for k in kinds)
    return float(drawings * drawing), len(shown)


#: the static loads (one solve of the stiffness at the MCS, the shafts' stresses), as a share of
#: one dense eigen-solution of the state matrix (measured below 0.01 on the gear chains)
STATIC_SHARE = 1.0
#: the mode shapes at the MCS (``modal``: its eigen-solution, the modes' names and numbers), in
#: eigen-solutions of the state matrix (measured 10 on the 20-rotor gear chain, 172 states: the
#: solution is a small part at that size)
MODES_SHARE = 10.0
#: each critical speed's round-off (:func:`critical_round_off`: its state matrix made and
#: balanced, work of the square of its size) [CPU s per squared state]: measured 7e-9 at 172
#: states (1,910 critical speeds of the 20-rotor gear chain in 0.4 s)
ROUND_OFF_SECONDS = 1e-8
#: the damped critical speeds the unbalance response looks for
#: (:func:`..analysis.unbalance_peaks.unresolved_criticals`): eigenvalue-only solutions per
#: bracket (a mode's frequency crossing a source's line between two swept speeds), the bracket
#: halved until it is a 64th of the mode's band: here only the pessimistic bound without timing
#: (measured on gear chains at 22 speeds: 7.5 a bracket at 10 rotors, 7.0 at 20, 6.9 at 30, 6.6
#: at 60); the estimate counts each bracket's own (:func:`_halvings`)
HALVINGS = 8.0
#: each API case's peaks cut between swept speeds, refined on the exact response
#: (:func:`..analysis.unbalance_peaks.cut_maxima`): calls of the response (the matrices
#: assembled once a case, the solves on one BLAS thread; measured 40 a case on the 20-rotor
#: chain) ...
PEAK_CALLS = 40
#: ... and speeds solved per bracket of the case's rotor's line (measured 11-40 there, 29 on a case of
#: the 60-rotor chain)
PEAK_SPEEDS = 10
#: the AF table's exact search (:func:`..analysis.unbalance_peaks.exact_peaks`: each swept peak's
#: maximum and half-power points on the exact response): calls of the response a source (every
#: peak's step in one call; measured 75 a case on examples/compressor_rotor.toml, 91 on
#: flexible_pump_on_mounts, fan_on_bearings and gear_machine at 151 speeds) ...
EXACT_CALLS = 90
#: ... each call's work of Python outside the direct solve that :func:`_timed_response` times (the
#: sources' forces and sensor rows of :func:`..analysis.unbalance._own_source_curve`, the search's
#: own steps) [CPU s]: measured 0.1-1.5 ms a call (examples and the 10-rotor gear chain)
EXACT_CALL_SECONDS = 3e-4
#: ... and speeds solved a peak, the search's own skip rule's count
#: (:data:`..analysis.unbalance_peaks._AF_CALLS`; measured 46-99 on the examples, 137-142 on the
#: 10- and 20-rotor gear chains at 21 speeds), each the timed solve's speed and
#: :data:`EXACT_SPEED_SECONDS` of Python (the curve's speed measured 1.3-4 times the timed one's:
#: 10-40 us more). The peaks are not known before the run: :func:`_exact_peaks_bound` bounds them
#: by the sensors times the modes met by the source's line in the sweep (measured 1.5-3 times the
#: swept peaks on the examples, 2.5-4.4 on the gear chains, where each sensor sees a few modes)
EXACT_SPEEDS = 60
EXACT_SPEED_SECONDS = 2e-5


#: one-speed solves of the stability row's refinement of a threshold (:func:`sweep_thresholds`:
#: Brent's method on the eigenproblem, each step a solve with its shapes, polished as the sweep's;
#: measured 6 on journal_rotor and unstable_cross_coupled, 11 on compressor_on_journals at 151
#: points) ...
THRESHOLD_SOLVES = 10
#: ... each one eigen-solution and this much work of Python [CPU s] (measured about 20 ms a solve
#: on those examples, of 4 to 53 coordinates)
THRESHOLD_SOLVE_SECONDS = 0.02


#: the eigenvalue solutions :func:`_thresholds_bound` may make, counted as the bound without
#: timing counts them (:data:`.._cost._PESSIMISTIC` per cubed state, :data:`.._cost.EIGVALS_SHARE`
#: of one) [CPU s]; past it every speed not proven stable counts as either
THRESHOLD_SCAN_SECONDS = 5.0


def _thresholds_bound(model, inputs) -> int:
    """The most thresholds the stability row can refine (:func:`sweep_thresholds`), counted before
    the sweep: one per pair of neighbouring speeds of the sweep unless both are surely stable or
    surely unstable (:func:`..analysis.stability.threshold_count_bound`), so that an instability
    inside the sweep (a mode unstable and stable again) counts its onset and its end. A speed is
    surely stable where the machine is passive (:func:`..analysis.stability.passive_at`: no
    circulatory term, its energy never grows); the others are judged by their eigenvalues
    (:func:`..analysis.stability.unstable_states`, a band of round-off either way) where solving
    them is counted at most :data:`THRESHOLD_SCAN_SECONDS` (from the size: the same count on
    every machine), and count as either beyond.

    Returns
    -------
    int, at most ``len(inputs.speeds) - 1``
    """
    from .._blas import one_blas_thread
    from ..analysis import _cost
    from ..analysis.stability import passive_at, threshold_count_bound, unstable_states
    from ..errors import ModelError
    from ..linear_system import speed_linear_form

    speeds = np.asarray(inputs.speeds, dtype=float)
    if len(speeds) < 2:
        return 0
    try:
        form = speed_linear_form(model)
        states = np.where(passive_at(form, speeds), -1, 0)
    except (InputError, ModelError):
        return len(speeds) - 1
    unknown = np.flatnonzero(states == 0)
    scan = unknown.size * _cost.EIGVALS_SHARE * _cost._PESSIMISTIC * float(form.n_states) ** 3
    if unknown.size and scan <= THRESHOLD_SCAN_SECONDS:
        with one_blas_thread(72 * form.n_states ** 2):
            try:
                states[unknown] = unstable_states(form, speeds[unknown])
            except (InputError, ModelError, np.linalg.LinAlgError):
                pass                                    # not judged: either, as beyond the budget
    return threshold_count_bound(states)


def _line_crossings(model, x) -> np.ndarray:
    """The undamped machine's positive frequencies at the sweep's middle speed, increasing
    [rad/s] (:func:`..analysis._work._undamped_frequencies`; none where it has none): where one
    meets a source's line ``ratio x`` inside the sweep ``x`` (S,) [rad/s] there is a bracket."""
    from ..analysis import _work

    frequencies = _work._undamped_frequencies(model, float(x[len(x) // 2]))
    return np.zeros(0) if frequencies is None else np.sort(frequencies[frequencies > 0])


def _exact_peaks_bound(model, inputs, frequencies=None) -> list:
    """Each searched source's bound on the swept peaks the AF table's exact search refines
    (:func:`..analysis.unbalance_peaks.exact_peaks`), in :func:`_searched_ratios`' order: the
    sensors times the modes (``frequencies`` [rad/s], :func:`_line_crossings`'s, made here where
    None) whose frequency meets the source's line inside the sweep (at most half the swept speeds
    a curve: a swept peak is above both its neighbours), at most the peaks the search's
    own skip lets run (``peaks * _AF_CALLS * n_dof^3 <= _WORK``: over it the AF read off the sweep,
    so the search costs at most that); none for a large model (:func:`..assembly.is_large`)."""
    from ..analysis.unbalance_peaks import _AF_CALLS, _WORK
    from ..assembly import is_large

    x = np.unique(np.abs(inputs.speeds))
    ratios = _searched_ratios(model, inputs)
    if not ratios or x.size < 3 or is_large(model) or not model.sensors:
        return [0] * len(ratios)
    frequencies = _line_crossings(model, x) if frequencies is None else frequencies
    most = int(_WORK // (_AF_CALLS * float(model.dofs.n) ** 3))
    sides = 1 + bool(np.any(np.asarray(inputs.speeds) < 0) and np.any(np.asarray(inputs.speeds) > 0))
    per_curve = sides * ((x.size - 1) // 2)                # a swept peak is above both its neighbours
    met = [int(np.count_nonzero((frequencies / r > x[0]) & (frequencies / r < x[-1]))) if r else 0 for r in ratios]
    return [min(most, len(model.sensors) * min(m, per_curve)) for m in met]


def _searched_ratios(model, inputs) -> list:
    """The speed ratio of each source whose damped critical speeds the unbalance response looks
    for: each API case's rotor (each unbalanced rotor for ``iso``)."""
    if inputs.standard != "iso":
        return _api_case_ratios(model, inputs.mcs)
    rotors = sorted({u.rotor for u in model.unbalances})
    return [abs(float(model.rotor(name).speed_ratio)) for name in rotors]


def _peak_search(model, inputs, n_states) -> tuple:
    """``(eigenvalue-only solutions, brackets of every source)`` of the unbalance response's search
    for damped critical speeds and peaks between swept speeds (0, 0 where it does not look for
    them: :func:`..analysis.unbalance_peaks.not_looked_for`'s rule, from the sizes). The brackets
    are counted from the undamped machine's frequencies at the middle speed
    (:func:`..analysis._work._undamped_frequencies`) between each ratio's line's ends, and each
    one's halvings from the damping of the damped root of its rank there (:func:`_middle_roots`,
    :func:`_halvings`): the search solves every swept speed once a distinct ratio and each
    bracket's halvings."""
    from ..assembly import is_large

    x = np.unique(np.abs(inputs.speeds))
    ratios = _searched_ratios(model, inputs)
    if not ratios or x.size < 2 or is_large(model):
        return 0.0, 0
    # imported here, not first: it binds _eigensolve's functions when first imported (tests replace them)
    from ..analysis import unbalance_peaks

    if unbalance_peaks.not_looked_for(model, x, n_states=n_states):
        return 0.0, 0
    middle = float(x[len(x) // 2])
    frequencies = _line_crossings(model, x)
    roots = _middle_roots(model, middle)
    decay = -roots.real[np.argsort(roots.imag)]
    # by rank; no oscillating root there (or no matrix): HALVINGS a bracket
    decay = decay[np.minimum(np.arange(frequencies.size), decay.size - 1)] if decay.size else None
    searched = {r: _halvings(frequencies, decay, x, r) for r in {r for r in ratios if r}}
    solutions = len(searched) * x.size + sum(float(h.sum()) for h in searched.values())
    return solutions, sum(searched[r].size for r in ratios if r)


def _middle_roots(model, speed) -> np.ndarray:
    """The oscillating roots (``Im > 0``, damped more than round-off, as
    :func:`..analysis.unbalance_peaks.unresolved_criticals` keeps them) of the state matrix at
    ``speed`` [rad/s], (m,) complex [1/s]: one eigenvalue-only solution, on one BLAS thread (a
    model with hysteretic mounts: their loss left out, so its modes count less damped)."""
    from .._blas import one_blas_thread
    from ..analysis.unbalance_peaks import _LEAST_DAMPING
    from ..errors import ModelError
    from ..linear_system import speed_linear_form

    try:
        matrix = speed_linear_form(model).at(np.array([speed]))[0]
    except (InputError, ModelError):
        return np.zeros(0, dtype=complex)
    if not np.all(np.isfinite(matrix)):
        return np.zeros(0, dtype=complex)
    with one_blas_thread(72 * matrix.shape[0] ** 2):
        values = np.linalg.eigvals(matrix)
    return values[(values.imag > 0) & (values.real < -_LEAST_DAMPING * np.abs(values))]


def _halvings(frequencies, decay, x, ratio) -> np.ndarray:
    """Eigenvalue-only solutions of each bracket of a source of speed ratio ``ratio`` (> 0) on the
    sweep ``x`` (S,) [rad/s], increasing: a bracket wherever a mode's frequency
    (``frequencies`` (m,) [rad/s], as at every speed) meets the line ``ratio x`` inside the
    sweep; it is halved until a 64th of its mode's band in speed, ``2 |Re lam| / ratio``
    (``decay`` (m,) ``|Re lam|`` [1/s]; the line's slope taken for the distance's), so
    ``ceil(log2(32 ratio dx / |Re lam|))`` times for the swept step ``dx`` around it (at most
    :data:`..analysis.unbalance_peaks._HALVINGS`; :data:`HALVINGS` where ``decay`` is None).
    Measured on gear chains at 22 speeds: see docs/report.md."""
    from ..analysis.unbalance_peaks import _HALVINGS

    at = frequencies / ratio                                          # where each mode meets the line [rad/s]
    inside = (at > x[0]) & (at < x[-1])
    if not inside.any():
        return np.zeros(0)
    if decay is None:
        return np.full(int(inside.sum()), HALVINGS)
    k = np.searchsorted(x, at[inside])
    dx = x[k] - x[k - 1]
    with np.errstate(divide="ignore"):
        count = np.ceil(np.log2(32.0 * ratio * dx / decay[inside]))
    return np.clip(count, 0, _HALVINGS)


def _timed_response(model, speed) -> tuple:
    """CPU seconds of one call of the unbalance response's direct solve
    (:func:`..analysis.frf.dof_response`) at one speed, and per speed of a call at 8 speeds,
    near ``speed`` [rad/s]: timed on the model, as the peaks' refinement runs it (its matrices
    assembled once before, as the refinement does once a case; the solve on one BLAS thread).
    The one assembly a case is not counted: at 246 coordinates it takes about 9 ms, against
    the 40 calls' 60 ms and the case's sweep."""
    from ..analysis import _cost
    from ..analysis.frf import dof_response, stiffness_terms

    forces = np.ones((model.dofs.n, 1))
    terms = stiffness_terms(model)
    times = []
    for count in (1, 8):
        w = np.linspace(0.9, 1.1, count) * speed
        times.append(_cost.shortest_cpu(lambda: dof_response(model, np.full(count, speed), w, forces, terms)))
    return times[0], times[1] / 8


def _ucs_widened(model, inputs) -> int:
    """Values (as :func:`_map_values` counts them) of the second UCS map :func:`_ucs` makes where the bearings' own stiffness lies
    outside the default grid (:func:`ucs_stiffness`), 0 where it does not: the constant bearings'
    values, and the speed-dependent ones' at the ends of the operating range (as the map's own
    curves give them, not solved here)."""
    from types import SimpleNamespace

    from ..analysis.ucs_map import _direct, _radial_axes
    from ..elements.bearings import evaluate

    if inputs.stiffness is not None or not model.bearings:
        return 0
    curves = []
    for bearing in model.bearings:
        if bearing.coefficients.kind == "constant":
            k = np.asarray(bearing.coefficients.stiffness[:1], dtype=float)
        else:
            ratio = model.rotor(bearing.rotor).speed_ratio
            try:
                k = evaluate(bearing.coefficients, ratio * np.asarray(inputs.range, dtype=float), str(model.source))[0]
            except InputError:                  # no film there: the map's own curve decides
                continue
        kxx, kyy = _direct(k, _radial_axes(bearing))
        curves.append(SimpleNamespace(constant=True, kxx=kxx, kyy=kyy))
    wider = ucs_stiffness(SimpleNamespace(curves=curves, stiffness=UCS_STIFFNESS), inputs.range)
    return 0 if wider is None else _map_values(model, wider)


def estimate_work(model, inputs, quick: bool = False) -> "ReportWork | float":
    """The CPU time the report's sections are estimated to take [s], before any of them runs.

    Every piece of work is counted in dense eigen-solutions of the state matrix, as
    ``campbell``, ``critical-speeds`` and ``stability`` count theirs (:func:`..analysis._work.estimate`:
    one solution timed on this machine and scaled by the cube of its size):

    - the static loads: :data:`STATIC_SHARE` of a solution;
    - the Campbell diagram with its 1X critical speeds, their mode numbers and their round-off
      (:data:`ROUND_OFF_SECONDS` a crossing and squared state), and the stability row's
      thresholds (:func:`_thresholds_bound`, :data:`THRESHOLD_SOLVES` solutions each);
    - the mode shapes at the MCS: :data:`MODES_SHARE` solutions;
    - the UCS map: :data:`UCS_SHARE` of a solution per value of its stiffness grid and of its
      speed-dependent bearings' curves, and a second map where the bearings' own stiffness lies
      outside the default grid (:func:`_ucs_widened`), and the refinement of each map's
      speed-dependent bearings' crossings (:func:`_ucs_refined`);
    - the unbalance response: :data:`CASE_SHARE` per case, :data:`SOLVE_SHARE` per case and
      speed, the damped critical speeds it looks for (:func:`_peak_search`, eigenvalues alone)
      and each case's peaks refined between swept speeds (:data:`PEAK_CALLS` calls of the
      direct solve a case, :data:`PEAK_SPEEDS` speeds a bracket, timed on the model:
      :func:`_timed_response`), and the AF table's exact search of each swept peak
      (:func:`_exact_seconds`: the peaks bounded by :func:`_exact_peaks_bound`, the same rule as
      the search's own skip);
    - the Level I sweep (:func:`..analysis.level1.sweep_solutions`, and :data:`LEVEL1_FOLLOWING`
      a value of Q).

    Counted in CPU seconds measured on this package's test machine, not in eigen-solutions (work
    of Python): each unbalance case's set-up and the checks' searches (:func:`_case_seconds`).
    Counted in reference drawings timed here (:func:`reference_drawing_seconds`): the page the
    ``report`` command makes of the results, its figures drawn (:func:`_render_seconds`, the part
    ``"page"``).

    Parameters
    ----------
    model : Model
    inputs : ReportInputs
    quick : bool
        A pessimistic bound [s] from the sizes alone instead (no timing, no matrices: every mode
        crossing every order line, :data:`.._cost._PESSIMISTIC` per cubed state, the Level I
        sweep with :data:`_LEVEL1_EXTRA` more values, every mode a bracket of every source and a
        peak of every sensor, a stability threshold between every two speeds, twice the seconds
        of the page and of the cases' set-up).

    Returns
    -------
    ReportWork, or float [s] with ``quick``
    """
    from ..analysis import _cost, _work
    from ..analysis.level1 import sweep_size, sweep_solutions

    model, _ = _judged_at_bearings(model, inputs)      # the probes the report adds are judged too
    counts = _sweep_counts(model, inputs)
    speeds = inputs.speeds
    level1 = inputs.level1 if "level1" in STANDARDS[inputs.standard] else None
    cases, points = counts.get("unbalance", (0, 0))
    shares = {"static": STATIC_SHARE, "modes": MODES_SHARE, "ucs": UCS_SHARE * counts.get("ucs", 0),
              "unbalance": cases * (CASE_SHARE + SOLVE_SHARE * points)}
    if quick:
        n_states = 2 * model.dofs.n + 6 * len(model.suspensions)
        grid = int(np.ceil(10 * 10 - 1e-9)) + 1 + _LEVEL1_EXTRA          # factor 10, 10 steps per Qa
        every = 2 * model.dofs.n * cases if "unbalance" in counts else 0        # every mode, every case's line
        search = (cases * points + HALVINGS * every) * _cost.EIGVALS_SHARE + (cases * PEAK_CALLS + PEAK_SPEEDS * every)
        search += cases * EXACT_CALLS + EXACT_SPEEDS * every * len(model.sensors)      # the AF's exact search
        shares["ucs"] += UCS_SHARE * _ucs_refined(model)
        ucs = 2 * shares["ucs"]                                                 # and a map widened
        crossings = 2 * model.dofs.n * len(_work._line_slopes(model, (1,)))
        thresholds = max(len(speeds) - 1, 0) * THRESHOLD_SOLVES        # every pair of speeds a threshold
        solutions = (sum(shares.values()) + ucs + search + crossings / n_states + thresholds
                     + (sweep_solutions(grid) if level1 else 0))
        return (_work._quick_bound(model, speeds, (1,), True, True, len(speeds))
                + solutions * _cost._PESSIMISTIC * float(n_states) ** 3
                + 2 * (_render_seconds(model, inputs, crossings, UNTIMED_DRAWING_SECONDS)[0]
                       + _case_seconds(model, cases)))
    # no mode numbers at the critical speeds (``mode_at_speed``): the report shows none
    campbell = _work.estimate(model, speeds, (1,), critical=True, numbers=False)
    eig = _work.eig_seconds(campbell.n_states)
    round_off = ROUND_OFF_SECONDS * campbell.crossings * float(campbell.n_states) ** 2
    thresholds = _thresholds_bound(model, inputs)
    refined = thresholds * THRESHOLD_SOLVES * (eig + THRESHOLD_SOLVE_SECONDS)
    parts = [("static", shares["static"] * eig, "1 solve at the MCS"),
             ("campbell", campbell.seconds + round_off + refined,
              campbell.text().split(" of CPU time (", 1)[1][:-1] + f"; their round-off: {_cost.duration(round_off)}"
              + (f"; the stability row's thresholds: at most {thresholds:,} refined" if thresholds else "")),
             ("modes", shares["modes"] * eig, f"1 eigen-solution of {campbell.n_states:,} states")]
    if "ucs" in counts:
        wider = _ucs_widened(model, inputs)
        refined = _ucs_refined(model) * (1 + (wider > 0))
        values = counts["ucs"] + wider
        parts.append(("ucs", UCS_SHARE * (values + refined) * eig, f"{values:,} stiffness values"
                      + (f" (a second map of {wider:,} reaching the bearings' own stiffness)" if wider else "")
                      + (f"; their crossings' refinement: at most {refined:,} more" if refined else "")))
    if "unbalance" in counts:
        what = "API unbalance cases" if inputs.standard != "iso" else "rotors unbalanced"
        search, brackets = _peak_search(model, inputs, campbell.n_states)
        seconds = (shares["unbalance"] + search * _cost.EIGVALS_SHARE) * eig + _case_seconds(model, cases)
        exact, exact_seconds = _exact_peaks_bound(model, inputs), 0.0
        if search or any(exact):
            call, per_speed = _timed_response(model, inputs.mcs)
            seconds += (cases * PEAK_CALLS * call + PEAK_SPEEDS * brackets * per_speed) * bool(search)
            exact_seconds = _exact_seconds(exact, call, per_speed)
        found = (f"; their damped critical speeds and peaks between speeds: {search:,.0f} eigenvalue solutions, "
                 f"{brackets:,} brackets") if search else ""
        found += f"; the AF's exact search: at most {sum(exact):,} peaks" if any(exact) else ""
        parts.append(("unbalance", seconds + exact_seconds, f"{cases:,} {what} at {points:,} speeds{found}"))
    if level1:
        count = sweep_size(model, inputs.mcs, level1["stations"], level1["qa"], shares=level1.get("shares"))
        parts.append(("level1", (sweep_solutions(count) + LEVEL1_FOLLOWING * count) * eig, f"{count:,} values of Q"))
    page, figures = _render_seconds(model, inputs, campbell.crossings, reference_drawing_seconds())
    parts.append(("page", page, f"{figures} figure sections drawn"))
    return ReportWork(campbell.n_dof, campbell.n_states, tuple(parts))


def _exact_seconds(peaks, call, per_speed) -> float:
    """CPU seconds [s] of the AF table's exact search (:func:`..analysis.unbalance_peaks.exact_peaks`)
    of sources with ``peaks`` (:func:`_exact_peaks_bound`'s) each: :data:`EXACT_CALLS` calls of the
    response a source that has any (and :data:`EXACT_CALL_SECONDS` each), :data:`EXACT_SPEEDS`
    speeds solved a peak (and :data:`EXACT_SPEED_SECONDS` each; ``call`` [s] a call, ``per_speed``
    [s] a speed: :func:`_timed_response`'s)."""
    return float(EXACT_CALLS * (call + EXACT_CALL_SECONDS) * sum(1 for p in peaks if p)
                 + EXACT_SPEEDS * (per_speed + EXACT_SPEED_SECONDS) * sum(peaks))


def _case_seconds(model, cases) -> float:
    """CPU seconds [s] of the unbalance response's work outside its solves: each of ``cases``'
    set-up (:data:`CASE_DOF_SECONDS` per coordinate) and the checks' searches
    (:data:`CHECK_SECONDS` for the clearances, the same for the proximity probes)."""
    probes = any(s.measure == "relative" for s in model.sensors)
    return cases * CASE_DOF_SECONDS * model.dofs.n + CHECK_SECONDS * (bool(model.clearances) + probes)


#: stiffness values solved to refine one crossing of a speed-dependent bearing's curve with a
#: mode's on the UCS map by today's route (``ucs_map.SUBSPACE_CROSSINGS`` False:
#: :func:`..analysis.ucs_map._refined`: the bracket's two ends and the regula falsi's steps;
#: measured 5.5 on examples/journal_rotor.toml, 5.75 on compressor_on_journals.toml)
UCS_REFINE_VALUES = 6
#: stiffness values counted for one crossing's finish on the whole pencil by the subspace route
#: (:func:`..analysis._ucs_ritz._finished`: Newton's method, about 2 bordered solves of the
#: coordinates and 2 on the subspace; measured at most 0.8 of one value of the map: 0.8 on
#: journal_rotor, 4 coordinates, where Python's work is the cost, 0.2 on compressor_on_journals,
#: 0.02 on ROSS's compressor_example, 224 coordinates)
UCS_FINISH_VALUES = 1
#: the API 617 Level I sweep's following of its modes from one value of Q to the next (the
#: MAC of their shapes, :func:`..analysis._vectors.mac_matrix`), in eigen-solutions of the state
#: matrix per value of Q, on top of :func:`..analysis.level1.sweep_solutions`' one (measured on
#: gear chains: the sweep took 1.8-2.2 times that count at 10 rotors, 2.1-2.4 at 20)
LEVEL1_FOLLOWING = 1.2


def _ucs_refined(model) -> int:
    """At most the stiffness values a UCS map of ``model`` solves to refine its speed-dependent
    bearings' crossings with the 4 modes it shows (the report's map): each curve (Kxx and Kyy of
    each such bearing) meeting each mode once, :data:`UCS_FINISH_VALUES` values a crossing
    (:data:`UCS_REFINE_VALUES` by today's route; the constant bearings' crossings are points of its
    grid: none)."""
    from ..analysis import ucs_map

    curves = sum(b.coefficients.kind != "constant" for b in model.bearings)
    return 2 * curves * 4 * (UCS_FINISH_VALUES if ucs_map.SUBSPACE_CROSSINGS else UCS_REFINE_VALUES)


def _map_values(model, stiffness) -> int:
    """Values a UCS map of ``stiffness`` (G,) [N/m] solves: its grid with the constant bearings'
    values, the rigid supports, and each speed-dependent bearing's anchors
    (``_ucs_ritz.CURVE_ANCHORS``; today's route: its Kxx and Kyy curves' points); their
    crossings' refinement: :func:`_ucs_refined`. A bearing whose crossings the subspace cannot
    show is mapped by today's route (``_ucs_ritz``): its curves' points are not counted."""
    from ..analysis import ucs_map
    from ..analysis._ucs_ritz import CURVE_ANCHORS

    curves = sum(b.coefficients.kind != "constant" for b in model.bearings)
    each = CURVE_ANCHORS if ucs_map.SUBSPACE_CROSSINGS else 2 * ucs_map._CURVE_POINTS
    return len(np.union1d(stiffness, ucs_map._constant_values(model.bearings))) + 1 + each * curves


def refuse_long_work(model, inputs) -> "ReportWork | None":
    """Refuse, before any section runs, a report estimated (:func:`estimate_work`) to take more
    CPU time than the limit in force (``ROTORDYN_MODAL_MAX_CPU_MINUTES``, 30 min by default),
    unless long work is allowed (``--allow-long``, ``rdm.long_work_allowed()``); returns the
    estimate where one was made (None where the bound without timing passed it).

    Raises
    ------
    InputError
        ``MODEL: this report of N coordinates would take about 9.6 h of CPU time (SECTION: TIME,
        WHAT; ...), more than the limit of 30 min: fewer speeds (--points), ..., or add
        --allow-long (ROTORDYN_MODAL_MAX_CPU_MINUTES sets the limit)``, one line.
    """
    from ..analysis import _cost

    if _cost.long_work_is_allowed():
        return None
    limit = _cost.limit_seconds()
    if limit == float("inf") or estimate_work(model, inputs, quick=True) <= limit:
        return None
    work = estimate_work(model, inputs)
    if work.seconds <= limit:
        return work
    where = f"{model.source}: " if getattr(model, "source", None) else ""
    raise InputError(f"{where}this report of {work.n_dof:,} coordinates would take {work.text()}, more than the limit "
                     f"of {_cost.duration(limit)}: fewer speeds (--points), a smaller model, or add --allow-long "
                     f"({_cost.ENVIRONMENT} sets the limit)")


def model_summary(model) -> dict:
    """Name, file, SHA-256 of its bytes, bodies, bearings, mounts, sensors, package version."""
    from .._version import __version__

    path = Path(model.source)
    digest = hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else "(not a file)"
    stator = None if model.stator is None else float(model.stator.mass)
    return {"name": model.name or shown_text(path.stem), "file": shown_text(path.name), "sha256": digest, "version": __version__,
            "stator_mass": stator, "rotors": [(r.name, float(r.mass), float(r.speed_ratio)) for r in model.rotors],
            "bearings": [(b.name, b.rotor, b.type) for b in model.bearings],
            "suspensions": [s.name for s in model.suspensions],
            "sensors": [(s.name, s.rotor or "stator", s.measure) for s in model.sensors]}


def _static(data):
    from ..analysis.static import static

    try:
        data.results["static"] = static(data.model, speed=data.inputs.mcs)
    except InputError as error:
        data.skipped["static"] = _reason(error, data.model)
        return
    for check in data.results["static"].stress_checks():
        _stress_criterion(data, check)


def _stress_criterion(data, check):
    """A flexible shaft's largest von Mises stress under its static loads against its material's
    ``allowable_stress`` (docs/static.md)."""
    name = f"Shaft stress, {check.rotor} (von Mises, static)"
    # a shaft with no static load (no gravity, force or torque) is 0 everywhere: no place governs
    where = f"at {check.label}" if check.von_mises > 0 else "(no static load)"
    if check.verdict == "not evaluated":
        data.criteria.append(Criterion.of(
            name, "not evaluated", "static", "no allowable_stress given for the shaft's material "
            "(docs/model-file.md)", quantities=[("value", "{0:.3g} {unit} " + where, "stress", (check.von_mises,))]))
        return
    data.criteria.append(Criterion.of(
        name, check.verdict, "static", f"governing: {check.label}, utilization {check.utilization:.3g}",
        quantities=[("value", "{0:.3g} {unit} " + where, "stress", (check.von_mises,)),
                    ("limit", "<= {0:.3g} {unit} (allowable_stress)", "stress", (check.allowable,))]))


#: bytes of state matrices held at once by :func:`critical_round_off`
_ROUND_OFF_BYTES = 64e6


def critical_round_off(model, critical) -> np.ndarray:
    """What round-off can move each critical speed's damping ratio by, reckoned as ``modes``
    reckons it (``ModalResult.to_dataframe``): the eigen-solve's round-off at that speed over
    ``|lambda|``; infinite where the machine is conservative (no damping, a symmetric
    semidefinite stiffness: every root imaginary, as ``critical-speeds`` prints it).

    Parameters
    ----------
    model : Model
    critical : CriticalSpeeds
        Its ``speeds_rpm`` (the reference rotor's) and ``frequencies_hz``, shape (N,).

    Returns
    -------
    ndarray, shape (N,) [-]
    """
    from ..analysis._roots import conservative, round_off
    from ..linear_system import speed_linear_form

    speeds = np.asarray(critical.speeds_rpm, dtype=float) * (np.pi / 30)
    if not len(speeds):
        return np.zeros(0)
    form = speed_linear_form(model)
    # a part of the state matrices at a time (60 geared rotors: 16,600 critical speeds of 492
    # states would be 32 GB at once); each matrix's round-off is its own
    step = max(1, int(_ROUND_OFF_BYTES // (8 * form.n_states ** 2)))
    noise = np.concatenate([round_off(np.stack([form.at(speed) for speed in speeds[k:k + step]]))
                            for k in range(0, len(speeds), step)])
    zeta = np.clip(np.abs(np.asarray(critical.damping_ratios, dtype=float)), 0.0, 1.0 - 1e-12)
    size = 2 * np.pi * np.asarray(critical.frequencies_hz, dtype=float) / np.sqrt(1 - zeta ** 2)   # |lambda|
    with np.errstate(divide="ignore"):
        return np.where(conservative(form, speeds), np.inf, noise / size)


def _campbell(data):
    from ..analysis.campbell import campbell

    data.results["campbell"] = campbell(data.model, data.inputs.speeds, orders=(1,))
    data.results["critical_round_off"] = critical_round_off(data.model, data.results["campbell"].critical)
    _stability(data)
    name = _MARGIN + (" (informative)" if data.inputs.standard == "iso" else "")
    _unbalance(data)                      # the amplification factors come from the response
    response = data.results.get("unbalance")
    if response is None:
        data.criteria.append(Criterion(name, "", "", "not evaluated", "campbell",
                                       data.skipped.get("unbalance", "")))
        return
    # every sensor's peaks label the unbalance figure's panels (the casing's too, as the CLI's
    # figure does); the margin is judged on the probes' (_peak_outputs)
    data.results["peaks"] = every = separation_margins(response, data.inputs.range)
    table = every[every["output"].isin(_peak_outputs(data.model, response))].reset_index(drop=True)
    data.results["margins"] = table
    if table.empty:
        speeds = np.asarray(data.inputs.speeds, dtype=float) * 30 / np.pi
        data.criteria.append(Criterion(name, "no resonance peak", MARGIN_LIMIT, "pass", "campbell",
                                       f"no peak of the response over the sweep, {speeds.min():.6g} to "
                                       f"{speeds.max():.6g} rpm (the Model section's speeds): no margin to meet"))
        return
    judged = table[table["verdict"] != "not evaluated"]
    unknown = len(table) - len(judged)
    # an unknown AF's peak is judged against the largest margin any AF requires where it meets it
    # (an undamped resonance's AF is inf: known, judged against the margin an infinite AF requires)
    passed = int(np.sum(np.isnan(judged["amplification_factor"].to_numpy(dtype=float))))
    note = (f"; {unknown} peak(s) not evaluated: AF unknown (the amplitude does not fall to peak/sqrt(2) on "
            "both sides within the sweep) and a margin below what some AF requires" if unknown else "") + \
        (f"; {passed} peak(s) of unknown AF pass: margin at least what any AF requires ({largest_margins_text()})"
         if passed else "")
    if judged.empty:
        data.criteria.append(Criterion(name, "", "", "not evaluated", "campbell", note[2:]))
        return
    worst = judged.iloc[int(np.argmin(judged["separation_margin_pct"] - judged["required_margin_pct"]))]
    verdict = "fail" if (judged["verdict"] == "fail").any() else ("not evaluated" if unknown else "pass")
    af = "AF unknown" if np.isnan(worst.amplification_factor) else f"AF {worst.amplification_factor:.2f}"
    data.criteria.append(Criterion(
        name, f"{worst.separation_margin_pct:.1f} % ({af})",
        f">= {worst.required_margin_pct:.1f} %", verdict, "campbell",
        f"governing peak: {worst.output} at {rpm_text(worst.speed_rpm)} rpm" + (_case(worst) or f", 1X {worst.source}")
        + note))


#: the separation margin's limit where the response has no peak: the rule, as no peak sets a number
MARGIN_LIMIT = "each peak's required SM"

#: the summary row of the machine's stability over its operating range
STABILITY_CRITERION = "Stability over the operating range"


def sweep_thresholds(model, result):
    """The stability thresholds of the Campbell sweep ``result`` of ``model``, as
    :func:`rotordyn_modal.analysis.stability.stability` refines them on the same speeds: its
    sweep is the same (one batch solve, roots tracked and polished alike, so the Campbell's mode
    N is ``stability``'s mode N), and its crossings are root-found by the same
    :func:`..analysis.stability.threshold_speeds` (Brent's method on the eigenproblem), at the cost
    of the refinement's few eigen-solutions only.

    Returns
    -------
    thresholds : ndarray [rad/s]; modes : ndarray of int (the Campbell's numbers); onsets : ndarray of bool
    """
    import functools

    from ..analysis._stack import Stack
    from ..analysis.stability import _polished_largest_real_part, roundoff_levels, threshold_speeds

    stack = Stack([model])
    roundoff = roundoff_levels(stack.forms[0], result.speeds)
    # the polished roots, as stability's sweep where double precision leaves some inexact (the same
    # roots where it does not: _refine_inexact polishes only those)
    return threshold_speeds(stack.forms[0], result.speeds, result.eigenvalues, roundoff,
                            largest=functools.partial(_polished_largest_real_part, stack)), roundoff


def unstable_spans(result, thresholds, onsets, roundoff) -> list:
    """Intervals of speed [rad/s] where the sweep ``result`` is unstable, as
    :attr:`..analysis.stability.StabilityResult.unstable_intervals` (start NaN: unstable from the
    sweep's first speed; stop NaN: to its last)."""
    from ..analysis.stability import _significant_real_parts, unstable_intervals

    largest = _significant_real_parts(result.eigenvalues, roundoff=roundoff).max(axis=1, initial=-np.inf)
    return unstable_intervals(largest[0] > 0, thresholds, onsets)


def mode_words(result, index: int, column: int) -> str:
    """What a reader needs to find tracked mode ``column + 1`` of the Campbell sweep ``result`` at
    its speed number ``index``: its damped natural frequency and whirl, ``20851 Hz, forward whirl``
    (a least-damped mode may lie far above the Campbell figure's axis, e.g. a shaft's high bending
    mode; without its frequency the summary's mode number points at nothing drawn)."""
    frequency, whirl = float(result.frequencies_hz[index, column]), str(result.whirl[index, column])
    return f"{frequency:.5g} Hz, " + ("no whirl" if whirl == "none" else f"{whirl} whirl")


def _stability(data):
    """The summary row :data:`STABILITY_CRITERION`: fail where a mode grows (real part > 0 beyond
    round-off) at some speed of the operating range, naming the mode (the Campbell's number), the
    onset (the refined threshold) and its least log decrement in the range; pass with the least log
    decrement over the range's swept speeds otherwise. ``data.results["onset"]``: the lowest
    threshold [rad/s] where the machine turns unstable below the range's top (or the sweep's first
    speed when it starts unstable), NaN when none: the unbalance section marks the response above it."""
    from ..analysis.modal import is_oscillating
    from ..analysis.stability import _significant_real_parts

    result = data.results["campbell"]
    (thresholds, modes, onsets), roundoff = sweep_thresholds(data.model, result)
    low, high = data.inputs.range
    spans = unstable_spans(result, thresholds, onsets, roundoff)
    inside = [(a, b) for a, b in spans if (np.isnan(a) or a <= high) and (np.isnan(b) or b >= low)]
    data.results["onset"] = (result.speeds[0] if inside and np.isnan(inside[0][0]) else
                             inside[0][0] if inside else float("nan"))
    in_range = (result.speeds >= low * (1 - 1e-12)) & (result.speeds <= high * (1 + 1e-12))
    significant = _significant_real_parts(result.eigenvalues[in_range], roundoff=roundoff[in_range])
    log_dec = np.where(significant == 0, 0.0, result.log_decrements[in_range])
    log_dec = np.where(is_oscillating(result.eigenvalues[in_range]), log_dec, np.inf)
    rpm = 30 / np.pi
    where = (f"operating range {rpm_text(low * rpm)} to {rpm_text(high * rpm)} rpm" if high > low
             else f"operating speed {rpm_text(low * rpm)} rpm")
    if inside:
        start = inside[0][0]
        at = (np.isfinite(thresholds) & onsets & np.isclose(thresholds, start)) if np.isfinite(start) else None
        mode = int(modes[at][0]) if at is not None and at.any() else \
            int(result.modes[int(np.argmax(_significant_real_parts(result.eigenvalues[:1], roundoff=roundoff[:1])[0]))])
        column = log_dec[:, mode - 1] if log_dec.size else np.array([np.nan])
        k = int(np.argmin(column)) if np.isfinite(column).any() else None
        onset = ("from the sweep's first speed, " + rpm_text(result.speeds[0] * rpm) + " rpm" if np.isnan(start)
                 else f"from {rpm_text(start * rpm)} rpm")
        least = (f"; its least log decrement there at {rpm_text(result.speeds[in_range][k] * rpm)} rpm "
                 f"({mode_words(result, np.flatnonzero(in_range)[k], mode - 1)})" if k is not None else "")
        data.criteria.append(Criterion.of(
            STABILITY_CRITERION, "fail", "campbell",
            f"mode {mode} (Campbell diagram's number) unstable {onset} ({where}){least}; a linear model with a "
            "growing mode has no steady unbalance response there: the unbalance results above the onset are no "
            "steady state", value=(f"log dec {column[k]:.3g} (mode {mode})" if k is not None else f"mode {mode}"),
            limit="log dec >= 0"))
        return
    if not np.isfinite(log_dec).any():
        data.criteria.append(Criterion.of(STABILITY_CRITERION, "not evaluated", "campbell",
                                          f"no oscillating mode at the swept speeds of the {where}"))
        return
    k, column = np.unravel_index(int(np.argmin(log_dec)), log_dec.shape)
    above = [a for a, _ in spans if np.isfinite(a) and a > high]
    later = (f"; mode {int(modes[np.isclose(thresholds, above[0])][0])} becomes unstable from "
             f"{rpm_text(above[0] * rpm)} rpm, above the range" if above else "")
    undamped = "; 0: an undamped mode, neither growing nor decaying" if log_dec[k, column] == 0 else ""
    data.criteria.append(Criterion.of(
        STABILITY_CRITERION, "pass", "campbell",
        f"no mode grows over the {where}; least damped{undamped}: mode {int(result.modes[column])} (Campbell diagram's "
        f"number; {mode_words(result, np.flatnonzero(in_range)[k], column)}) at "
        f"{rpm_text(result.speeds[in_range][k] * rpm)} rpm{later}",
        value=f"log dec {log_dec[k, column]:.3g} (mode {int(result.modes[column])})", limit="log dec >= 0"))


#: the separation margin's criterion (in an ISO report informative: ISO sets no margin)
_MARGIN = "API 684 separation margin"


def _case(row) -> str:
    return f", case {row.case}" if "case" in row.index and row.case else ""


def separation_margins(response, operating, outputs=None):
    """API 684 peaks of ``response`` with their separation margin from the operating range: the
    one function ``unbalance --operating-range`` calls too,
    :func:`rotordyn_modal.analysis.unbalance_checks.separation_margins` (0-peak amplitudes)."""
    from ..analysis.unbalance_checks import separation_margins as margins

    return margins(response, operating, outputs=outputs, amplitude="peak")


def _peak_outputs(model, response):
    """The probes (measure = 'relative') when there are some, else every sensor."""
    probes = [s.name for s in model.sensors if s.measure == "relative" and s.name in response.outputs]
    return probes or list(response.outputs)


def _modes(data):
    """The modes near the operating range at the MCS (:data:`MODE_WINDOW`), else the lowest."""
    from ..analysis.modal import modal

    mcs = data.inputs.mcs
    result = modal(data.model, mcs)
    count = int(result.oscillatory.sum())
    if not count:
        data.skipped["modes"] = f"no oscillating mode at the MCS ({mcs * 30 / np.pi:.6g} rpm)"
        return
    low, high = data.inputs.range
    window = (low * (1 - MODE_WINDOW[0]), high * (1 + MODE_WINDOW[1]))
    reasons: dict = {}
    frequencies = 2 * np.pi * result.frequencies_hz[result.oscillatory]
    for number, w in enumerate(frequencies, start=1):
        if window[0] <= w <= window[1]:
            reasons.setdefault(number, f"frequency at the MCS {rpm_text(w * 30 / np.pi)} rpm (1X) in the window")
    for number, speed, tracked in _critical_numbers(data, result):
        if window[0] <= speed <= window[1]:
            # the critical-speed table numbers the Campbell sweep's tracked modes: say so where it differs
            other = f" (the critical-speed table's mode {tracked})" if tracked != number else ""
            reasons[number] = f"1X critical speed {rpm_text(speed * 30 / np.pi)} rpm{other} in the window"
    if not reasons:
        reasons = {n: "one of the lowest at the MCS (none in the window)" for n in range(1, min(count, LOWEST_MODES) + 1)}
    numbers = tuple(sorted(reasons)[:MOST_MODES])
    lines, note = None, ""
    if any(r.flexible is not None for r in data.model.rotors):
        from ..analysis.mode_shapes import shaft_lines

        lines = tuple(shaft_lines(result, data.model, n) for n in numbers)
        if not any(line.lateral for line in lines):
            # only axial or torsional modes in the window: their shaft lines are flat; the
            # lateral modes nearest the window are drawn instead
            nearest = _nearest_lateral(data.model, result, window)
            if nearest:
                labels = tracked_numbers(data.results.get("campbell"), mcs, numbers) or (0,) * len(numbers)
                note = (f"The window holds no lateral mode: "
                        f"{', '.join(f'mode {mode_label(n, t)}' for n, t in zip(numbers, labels))} "
                        f"{'is' if len(numbers) == 1 else 'are'} axial or torsional (no lateral motion to draw); "
                        "the lateral modes nearest the operating range, below and above the window, are shown "
                        "instead.")
                reasons = {n: why for n, (why, _) in nearest.items()}
                numbers = tuple(sorted(nearest))
                lines = tuple(nearest[n][1] for n in numbers)
    data.results["modes"] = ModeShapes(result, numbers, tuple(reasons[n] for n in numbers), window, lines, note,
                                       tracked_numbers(data.results.get("campbell"), mcs, numbers))


def mode_label(number: int, tracked: int) -> str:
    """A mode-shape row's mode: its tracked (Campbell) number ``tracked``, with the number
    ``number`` that ``modes --speed MCS`` gives it in brackets where the two differ ("5 (2 at
    the MCS)"); ``number`` alone where no tracked column is that root (``tracked`` 0)."""
    if not tracked:
        return f"{number} at the MCS"
    return str(tracked) if tracked == number else f"{tracked} ({number} at the MCS)"


def tracked_numbers(campbell, mcs, numbers) -> tuple:
    """The Campbell sweep's (tracked) number of each mode ``numbers`` as ``modes --speed MCS``
    numbers them: the column whose root at the sweep's speed nearest ``mcs`` [rad/s] (the MCS is
    among the report's speeds) ``modes`` numbers so; 0 where none is; () without a sweep."""
    from ..analysis._whirl import about_spin_axis
    from ..analysis.mode_numbers import numbers_at_speed

    if campbell is None:
        return ()
    k = int(np.argmin(np.abs(np.abs(campbell.speeds) - mcs)))
    # a repeated root's members by their whirl about +spin_axis
    about_axis = about_spin_axis(campbell.whirl_ratios[k], campbell.speeds[k])
    at_mcs = numbers_at_speed(campbell.eigenvalues[k], about_axis)
    return tuple(int(campbell.modes[np.flatnonzero(at_mcs == n)[0]]) if (at_mcs == n).any() else 0
                 for n in numbers)


#: the lateral modes shown on each side of the window when it holds only axial or torsional ones
#: (a whirl pair: backward and forward)
NEAREST_LATERAL = 2


def _nearest_lateral(model, result, window) -> dict:
    """The :data:`NEAREST_LATERAL` lateral modes nearest below and above ``window`` [rad/s] by
    their frequency at the MCS taken as a 1X speed.

    Parameters
    ----------
    model : Model
    result : ModalResult
        At the MCS.
    window : (float, float) [rad/s]

    Returns
    -------
    dict
        ``{number: (reason, ShaftLines)}``, the numbers as ``modes`` numbers them.
    """
    from ..analysis.mode_shapes import shaft_lines

    speeds = 2 * np.pi * result.frequencies_hz[result.oscillatory]
    numbers = np.arange(1, len(speeds) + 1)
    below, above = numbers[speeds < window[0]][::-1], numbers[speeds > window[1]]
    chosen = {}
    for side, candidates in (("below", below), ("above", above)):
        found = 0
        for number in candidates:
            line = shaft_lines(result, model, int(number))
            if line.lateral:
                speed = speeds[number - 1] * 30 / np.pi
                chosen[int(number)] = (f"nearest lateral mode {side} the window (frequency at the MCS "
                                       f"{rpm_text(speed)} rpm as 1X), shown as the window has none", line)
                found += 1
                if found == NEAREST_LATERAL:
                    break
    return chosen


def _critical_numbers(data, result):
    """(number at the MCS, critical speed [rad/s], the Campbell sweep's mode number) of each 1X
    critical speed of the Campbell sweep: its tracked mode's root at the sweep speed nearest the
    MCS, numbered as ``modes`` numbers the nearest root at the MCS; the last is the number the
    critical-speed table gives it (the sweep's tracked column, numbered at its first speed)."""
    from ..analysis.mode_numbers import number_of_root, repeated_in_whirl_order

    campbell = data.results.get("campbell")
    if campbell is None:
        return []
    table = campbell.critical.to_dataframe(numbers=False)
    table = table[np.isclose(table["order"].astype(float), 1.0)]
    nearest = int(np.argmin(np.abs(np.abs(campbell.speeds) - data.inputs.mcs)))
    columns = table["mode"].to_numpy(dtype=int) - 1
    roots = campbell.eigenvalues[nearest, columns]
    numbers = np.array([number_of_root(result.eigenvalues, lam) for lam in roots], dtype=int)
    # the members of a repeated root at the MCS (a symmetric rotor's whirl pair) by their whirl, as modes lists them
    numbers = repeated_in_whirl_order(np.full(len(numbers), campbell.speeds[nearest]), roots,
                                      campbell.whirl_ratios[nearest, columns], numbers, columns)
    return [(int(number), row.speed_rpm * np.pi / 30, int(row.mode))
            for number, row in zip(numbers, table.itertuples()) if number]


def _unbalance(data):
    from ..analysis.unbalance import api_unbalance_response, unbalance_response
    from ..analysis.unbalance_checks import unbalance_checks

    if "unbalance" in data.results or "unbalance" in data.skipped:
        return
    if not data.model.sensors:
        data.skipped["unbalance"] = "the model has no [[sensors]]: no response to judge"
        return
    inputs = data.inputs
    if inputs.standard == "iso":
        if not data.model.unbalances:
            data.skipped["unbalance"] = "the model has no [[unbalances]] (an amount or an ISO 21940-11 grade)"
            return
        data.results["unbalance"] = unbalance_response(data.model, inputs.speeds)
    else:
        data.results["unbalance"] = api_unbalance_response(data.model, inputs.speeds, inputs.mcs)
    group = inputs.iso_group if inputs.standard == "iso" else None
    # ISO 20816-3 judges steady operation: the zones over the operating range where one is given
    data.results["checks"] = unbalance_checks(
        data.results["unbalance"], data.model, mcs=inputs.mcs, min_speed=0.0, iso_group=group,
        iso_support=inputs.iso_support if group else None, iso_range=inputs.operating)
    if data.model.clearances and inputs.standard != "iso":
        data.results["clearance"] = data.results["unbalance"].clearance_check(data.model, mcs=inputs.mcs,
                                                                              min_operating=inputs.range[0])


#: the UCS map's default stiffness [N/m]: 1e5 to 1e10 N/m, 8 points a decade
UCS_STIFFNESS = np.geomspace(1e5, 1e10, 41)


def _ucs(data):
    from ..analysis.ucs_map import ucs_map

    given = data.inputs.stiffness
    try:
        result = ucs_map(data.model, UCS_STIFFNESS if given is None else given, modes=4, operating=data.inputs.range)
        wider = None if given is not None else ucs_stiffness(result, data.inputs.range)
        if wider is not None:       # the bearings' own stiffness off the default map: where the machine is
            result = ucs_map(data.model, wider, modes=4, operating=data.inputs.range)
    except InputError as error:
        data.skipped["ucs"] = _reason(error, data.model)
        return
    data.results["ucs"] = result


def ucs_stiffness(result, operating):
    """The UCS map's stiffness [N/m] widened to the bearings' own, or None where it reaches them.

    The bearings' own radial stiffness (``Kxx`` and ``Kyy``; of a speed-dependent bearing at
    the map's speeds within ``operating`` [rad/s], else at the one nearest it) lying outside the
    map's range would leave the map without the crossings that locate the machine
    (examples/spring_block_rotor.toml: 2e3 N/m against 1e5 to 1e10 N/m). The range is then
    widened to one decade beyond them (whole decades, 8 points a decade, inside
    ``ucs_map.STIFFNESS_RANGE``).

    Parameters
    ----------
    result : UcsMap
    operating : (float, float) [rad/s]

    Returns
    -------
    ndarray [N/m] or None
    """
    from ..analysis.ucs_map import STIFFNESS_RANGE

    own = [np.concatenate([c.kxx, c.kyy]) if c.constant else _in_range(c, operating) for c in result.curves]
    own = np.concatenate(own) if own else np.zeros(0)
    own = own[np.isfinite(own) & (own > 0)]
    low, high = float(result.stiffness[0]), float(result.stiffness[-1])
    if not own.size or (own.min() >= low and own.max() <= high):
        return None
    first = max(min(np.log10(low), np.floor(np.log10(own.min())) - 1), np.log10(STIFFNESS_RANGE[0]))
    last = min(max(np.log10(high), np.ceil(np.log10(own.max())) + 1), np.log10(STIFFNESS_RANGE[1]))
    return np.logspace(first, last, int(round(8 * (last - first))) + 1)


def _in_range(curve, operating) -> np.ndarray:
    """A speed-dependent bearing's ``Kxx`` and ``Kyy`` [N/m] at its speeds within ``operating``
    (the nearest one when none is)."""
    speeds = np.abs(np.asarray(curve.speeds, dtype=float))
    inside = (speeds >= operating[0] * (1 - 1e-12)) & (speeds <= operating[1] * (1 + 1e-12))
    if not inside.any():
        inside = np.abs(speeds - 0.5 * (operating[0] + operating[1])) == np.min(
            np.abs(speeds - 0.5 * (operating[0] + operating[1])))
    return np.concatenate([np.asarray(curve.kxx)[inside], np.asarray(curve.kyy)[inside]])


def _reason(error, model) -> str:
    """Why an analysis is not evaluated: the refusal's message with the model file named as the
    Model section names it (its name, not the path of the machine that ran the report)."""
    source = str(getattr(model, "source", "") or "")
    return str(error).replace(source, Path(source).name) if source else str(error)


def _judged_at_bearings(model, inputs):
    """The model an API report judges, and the names of the probes it adds: a model without
    ``[[sensors]]`` (every rotor read from ROSS) gets an X-Y pair of proximity probes at each
    bearing (:func:`..analysis.unbalance_checks.with_bearing_probes`), where API 684 reads the
    unbalance response, its amplification factors, separation margins and probe limits; an ISO
    report judges the casing's own sensors and gets none."""
    from ..analysis.unbalance_checks import with_bearing_probes

    if inputs.standard == "iso":
        return model, []
    return with_bearing_probes(model)


def _probe_limits(data):
    _unbalance(data)
    if data.inputs.standard == "iso":    # ISO judges the casing (section iso), not the probes
        return
    checks = data.results.get("checks")
    if checks is None:
        data.criteria.append(Criterion("API 617 probe vibration limit", "", "", "not evaluated", "unbalance",
                                       data.skipped.get("unbalance", "")))
        return
    table = probe_limit_table(data)
    if table.empty:
        data.criteria.append(Criterion("API 617 probe vibration limit", "", "", "not evaluated", "unbalance",
                                       "no proximity probe (sensor with measure = \"relative\") in the model"))
        return
    worst = table.iloc[int(np.argmax(table["value"] / table["limit"]))]
    verdict = "pass" if (table["verdict"] == "pass").all() else "fail"
    data.criteria.append(Criterion.of("API 617 probe vibration limit", verdict, "unbalance",
                                      f"governing: {worst.output} at {rpm_text(worst.speed_rpm)} rpm" + _case(worst)
                                      + (", where the response is unbounded (an undamped mode's critical speed)"
                                         if np.isposinf(worst.value) else ""),
                                      quantities=[("value", "{0:.3g} {unit} {amplitude}", "vibration", (worst.value,)),
                                                  ("limit", "<= {0:.3g} {unit} {amplitude}", "vibration", (worst.limit,))]))


def probe_limit_table(data):
    """The API 617 probe-limit rows of ``data.results["checks"]`` (its ``to_dataframe``: each
    probe's maxima between the swept speeds and at the MCS included, the clearance check's
    refinement, :func:`..analysis.unbalance_peaks.refined_maxima`), each probe's value raised to the
    largest peak of its case between 0 and the MCS that the AF table found between the swept
    speeds (``data.results["peaks"]``, 0-peak: twice it is the peak-to-peak) where that is
    larger, with its speed and verdict: the sweep's largest misses the top of a sharp peak
    (examples/compressor_rotor.toml at 41 speeds: 35.7 µm pk-pk at a swept 5,841 rpm, the AF
    table's peak 57.4 µm at 5,726 rpm; at 151 speeds 52.1 µm at 5,686 rpm, which the AF
    table's 3 dB search does not look past, the refined maximum 57.4 µm)."""
    checks = data.results["checks"]
    table = checks.to_dataframe()
    table = table[table["check"] == "API 617 probe limit"].copy()
    peaks = data.results.get("peaks")
    if peaks is None or peaks.empty or table.empty or checks.mcs is None:
        return table
    top = abs(checks.mcs) * 30 / np.pi * (1 + 1e-12)
    for index, row in table.iterrows():
        found = peaks[(peaks["output"] == row["output"]) & (np.abs(peaks["speed_rpm"]) <= top)]
        if "case" in table and "case" in peaks:
            found = found[found["case"] == row["case"]]
        if found.empty:
            continue
        best = found.loc[found["amplitude"].idxmax()]
        if 2.0 * best["amplitude"] > row["value"]:
            value = 2.0 * float(best["amplitude"])
            table.loc[index, ["speed_rpm", "value"]] = [float(best["speed_rpm"]), value]
            table.loc[index, "verdict"] = "pass" if value <= row["limit"] else "fail"
    return table


def _clearance(data):
    """The API 617 clearance criterion (only for a model with close-clearance stations)."""
    if not data.model.clearances or data.inputs.standard == "iso":
        return
    from ..analysis.clearance import CLEARANCE_CHECK

    check = data.results.get("clearance")
    if check is None:
        data.criteria.append(Criterion(CLEARANCE_CHECK, "", "", "not evaluated", "unbalance",
                                       data.skipped.get("unbalance", "")))
        return
    table = check.to_dataframe()
    worst = table.iloc[int(np.argmax(table["ratio"]))]
    verdict = "pass" if (table["verdict"] == "pass").all() else "fail"
    data.criteria.append(Criterion.of(
        CLEARANCE_CHECK, verdict, "unbalance",
        f"governing: {worst.clearance} at {rpm_text(worst.speed_rpm)} rpm" + _case(worst) + f", ratio {worst.ratio:.3g}",
        quantities=[("value", "{0:.3g} {unit} {amplitude}", "vibration", (worst.value,)),
                    ("limit", "<= {0:.3g} {unit} {amplitude}", "vibration", (worst.limit,))]))


def _level1(data):
    given = data.inputs.level1
    if not given:
        data.skipped["level1"] = "no --station with --qa or stage data given"
    else:
        from ..analysis.level1 import level1

        # the least stable of the rotor's first forward modes, each in its ``swept``
        data.results["level1"] = level1(data.model, data.inputs.mcs, given["stations"], given["qa"],
                                        shares=given.get("shares"), gas_density=given.get("gas_density"))
    result = data.results.get("level1")
    if result is None:
        for name in ("API 617 Level I: log decrement at Qa", "API 617 Level I: Q0/Qa"):
            data.criteria.append(Criterion(name, "", "", "not evaluated", "level1", data.skipped["level1"]))
        return
    ratio = f"{result.ratio:.3g}" if np.isfinite(result.q0) else f"> {result.cross_coupling[-1] / result.qa:.3g}"
    data.criteria.append(Criterion.of("API 617 Level I: log decrement at Qa",
                                      "pass" if result.passes_log_decrement else "fail", "level1",
                                      value=f"{result.log_decrement_at_qa:.3g}",
                                      limit=f">= {result.log_decrement_criterion:g}",
                                      quantities=[("why", "Qa = {0:.4g} {unit}", "stiffness", (result.qa,))]))
    data.criteria.append(Criterion("API 617 Level I: Q0/Qa", ratio, f">= {result.ratio_criterion:g}",
                                   "pass" if result.passes_ratio else "fail", "level1",
                                   _level2_note(result)))
    if result.csr is not None:
        _csr_criterion(data, result)


def _csr_criterion(data, result):
    """The critical speed ratio against the average gas density: Region B with Q0/Qa < 10 fails;
    not evaluated without a critical speed on rigid supports (a rigid rotor)."""
    from ..analysis.level1 import NO_RIGID_SUPPORT_CRITICAL

    csr = result.csr
    if not csr.evaluated:        # nothing to judge: not a pass (a CSR of 0 read as Region A was)
        data.criteria.append(Criterion("API 617 Level I: critical speed ratio", "", "", "not evaluated", "level1",
                                       NO_RIGID_SUPPORT_CRITICAL))
        return
    why = ("Region A" if csr.region == "A" else "Region B" + ("" if result.csr_applies else ", not applied: Q0/Qa >= 10")) \
        + " at {0:.4g} {unit}; MCS / first critical speed on rigid supports"
    data.criteria.append(Criterion.of("API 617 Level I: critical speed ratio",
                                      "pass" if result.passes_csr else "fail", "level1",
                                      value=f"{csr.csr:.3g}", limit=f"<= {csr.boundary:.3g}",
                                      quantities=[("why", why, "density", (csr.density,))]))


def _iso(data):
    _unbalance(data)
    checks = data.results.get("checks")
    name = "ISO 20816-3 zone (casing velocity)"
    if data.inputs.iso_group is None:
        data.skipped["iso"] = "no --iso-group and --iso-support given"
    elif checks is None:
        data.skipped["iso"] = data.skipped.get("unbalance", "")
    elif not checks.casing:
        data.skipped["iso"] = "no sensor on the stator (casing) in the model"
    if "iso" in data.skipped:
        data.criteria.append(Criterion(name, "", "", "not evaluated", "iso", data.skipped["iso"]))
        return
    table = checks.to_dataframe()
    table = table[table["check"].str.startswith("ISO")]
    worst = table.iloc[int(np.argmax(table["value"]))]
    verdict = "pass" if (table["verdict"] == "pass").all() else "fail"
    data.criteria.append(Criterion.of(
        name, verdict, "iso", f"governing: {worst.output} at {rpm_text(worst.speed_rpm)} rpm; {iso_span(checks)}",
        quantities=[("value", "{0:.%dg} {unit} RMS (zone %s)" % (VELOCITY_DIGITS, worst.zone), "velocity", (worst.value,)),
                    ("limit", "<= {0:.%dg} {unit} RMS (zone B)" % VELOCITY_DIGITS, "velocity", (worst.limit,))]))


#: significant digits of an ISO 20816-3 casing velocity and zone boundary, in the summary, the zones'
#: sentence and the checks table alike: 2.8 mm/s is 0.1102 in/s, which 3 digits wrote as 0.11
VELOCITY_DIGITS = 4


def _level2_note(result) -> str:
    """Whether API 617 Level II is required and, where it is, which criterion requires it: the
    note sits on the Q0/Qa row, which may pass while the log decrement fails (compressor_rotor:
    Q0/Qa 6.12 'pass' beside 'Level II required')."""
    if not result.level2_required:
        return "Level II not required"
    why = [what for what, passes in (("the log decrement at Qa", result.passes_log_decrement),
                                     ("Q0/Qa", result.passes_ratio),
                                     ("the critical speed ratio", result.passes_csr)) if not passes]
    return f"Level II required (by {' and '.join(why)})" if why else "Level II required"


def iso_span(checks) -> str:
    """The speeds the ISO 20816-3 zones judged, in words: the operating range (steady operation,
    ISO 20816-3 clause 1), or from 0 to the MCS where no range was given."""
    if checks.iso_span is not None:
        low, high = (abs(x) * 30 / np.pi for x in checks.iso_span)
        where = f"at the operating speed {low:.6g} rpm" if low == high else \
            f"over the operating range {low:.6g} to {high:.6g} rpm"
        return f"judged {where} (steady operation)"
    return (f"judged from 0 to the MCS {checks.mcs * 30 / np.pi:.6g} rpm, run-up included "
            "(no operating range given)")


def _nothing(data):
    return None


def _probe_limits_and_clearances(data):
    _probe_limits(data)
    _clearance(data)


_STEPS = {"model": _nothing, "static": _static, "campbell": _campbell, "modes": _modes, "ucs": _ucs,
          "unbalance": _probe_limits_and_clearances, "level1": _level1, "iso": _iso}
