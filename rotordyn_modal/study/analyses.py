"""The analyses a study runs on every variant: a registry of small adapters.

Each entry of :data:`ANALYSES` turns one single analysis of the package into
fixed-shape arrays per variant, so that variants stack into one data set:

* ``parse(table, where, source)`` validates the options of ``[analyses.NAME]``;
* ``describe(model, options)`` gives, from the base model, the output variables
  with their dimensions (after ``variant``) and the coordinates of those
  dimensions;
* ``run(model, options, layout, cache)`` returns ``{variable: ndarray}`` for one
  variant (shapes as described; NaN where a quantity does not exist).

A new analysis plugs in by adding an :class:`Analysis` to :data:`ANALYSES`.
The unbalance adapter is registered only when ``rotordyn_modal.analysis``
provides ``unbalance_response``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ._rules import StudyError, grid_values
from ..model._table import unknown_key

__all__ = ["Analysis", "ANALYSES", "parse_analyses", "describe", "run_analyses"]

_RPM = math.pi / 30.0
def mode_count(model) -> int:
    """Roots per speed (one of each conjugate pair): the coordinates, plus three per Maxwell
    branch (its six first-order states); the same for every variant of a study."""
    from ..linear_system import speed_linear_form

    return speed_linear_form(model).n_states // 2


@dataclass(frozen=True)
class Analysis:
    """Adapter of one single analysis; see the module docstring."""

    name: str
    keys: tuple
    parse: Callable
    describe: Callable
    run: Callable


# ---------------------------------------------------------------------------- options
def _error(source, where, value, expected):
    return StudyError(source, where, value, expected)


def _speeds(value, where, source, default=None) -> np.ndarray:
    """``'START:STOP:N'`` or a list [rpm] -> increasing speeds [rad/s]."""
    if value is None:
        if default is None:
            raise _error(source, where, value, "speeds in rpm: 'START:STOP:N' or a list")
        return default
    speeds = grid_values(value, where, source) * _RPM
    if len(speeds) > 1 and not np.all(np.diff(speeds) > 0):
        raise _error(source, where, value, "strictly increasing speeds")
    return speeds


def _orders(value, where, source) -> tuple:
    if value is None:
        return (1.0,)
    if not isinstance(value, list) or not value or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0 for v in value):
        raise _error(source, where, value, "a list of excitation orders > 0, e.g. [1, 2]")
    if len(set(map(float, value))) != len(value):
        raise _error(source, where, value, "a list of excitation orders > 0, each once, e.g. [1, 2]")
    return tuple(float(v) for v in value)


def _parse_sweep(table, where, source):
    return {"speeds": _speeds(table.get("speeds_rpm"), f"{where} speeds_rpm", source),
            "orders": _orders(table.get("orders"), f"{where} orders", source)}


def _parse_modes(table, where, source):
    speed = table.get("speed_rpm", 0.0)
    if not isinstance(speed, (int, float)) or isinstance(speed, bool) or not math.isfinite(speed):
        raise _error(source, f"{where} speed_rpm", speed, "a finite speed in rpm")
    return {"speed": float(speed) * _RPM}


def _parse_stability(table, where, source):
    return {"speeds": _speeds(table.get("speeds_rpm"), f"{where} speeds_rpm", source)}


def _parse_unbalance(table, where, source):
    outputs = table.get("outputs")
    if outputs is not None and (not isinstance(outputs, list) or not all(isinstance(o, str) for o in outputs)):
        raise _error(source, f"{where} outputs", outputs, "a list of sensor names")
    operating = table.get("operating_speed_rpm")
    if operating is not None and (not isinstance(operating, (int, float)) or isinstance(operating, bool)
                                  or not math.isfinite(operating) or operating == 0):
        raise _error(source, f"{where} operating_speed_rpm", operating, "a finite non-zero speed in rpm")
    return {"speeds": _speeds(table.get("speeds_rpm"), f"{where} speeds_rpm", source),
            "outputs": outputs, "quantity": _motion(table.get("quantity", "displacement"), f"{where} quantity", source),
            "forces": _forces(table.get("forces"), f"{where} forces", source),
            "operating_speed": None if operating is None else float(operating) * _RPM}


def _motion(value, where, source) -> str:
    """What the sensors read, in the words of the command line's ``--quantity``: the motion
    (displacement, velocity, acceleration) or the FRF's name of it (receptance, mobility,
    accelerance), either word the same; returned as the motion."""
    from ..analysis.spectra import QUANTITY_OF_RESPONSE

    for motion, frf_name in QUANTITY_OF_RESPONSE.items():
        if isinstance(value, str) and value in (motion, frf_name):
            return motion
    raise _error(source, where, value, "displacement, velocity or acceleration (or the FRF's name of it: "
                 "receptance, mobility, accelerance)")


def _forces(value, where, source):
    """Force rows added after the sensors' (the command line's ``unbalance --forces``): None,
    or 'suspensions', 'bearings', 'rotors', 'all'."""
    from ..analysis.unbalance import FORCE_CHOICES

    choices = [c for c in FORCE_CHOICES if c is not None]
    if value is not None and (not isinstance(value, str) or value not in choices):
        raise _error(source, where, value, "one of " + ", ".join(choices) + " (force rows added after the sensors')")
    return value


# ---------------------------------------------------------------------------- campbell
def _campbell_key(options):
    return ("campbell", options["speeds"].tobytes(), options["orders"])


def _campbell_of(model, options, cache):
    from ..analysis.campbell import campbell

    key = _campbell_key(options)
    if key not in cache:
        cache[key] = campbell(model, options["speeds"], orders=options["orders"])
    return cache[key]


def batch_caches(models, analyses) -> list:
    """Per variant, the results that can be computed for all of a chunk's variants at once
    (the Campbell sweep the campbell and critical-speed analyses share: one batched solve,
    see :func:`rotordyn_modal.analysis.campbell.campbell_many`), as caches for
    :func:`run_analyses`. Each result equals the variant's own analysis bit for bit (the
    critical speeds of models above 48 coordinates to round-off, see ``campbell_many``). Where the
    batch cannot be solved (a variant that fails), the caches stay empty and every variant
    is analysed on its own, so that the failure is recorded against the right variant."""
    from ..analysis.campbell import campbell_many

    caches = [{} for _ in models]
    options = analyses.get("campbell") or analyses.get("critical_speeds")
    if options is None or len(models) < 2:
        return caches
    try:
        results = campbell_many(models, options["speeds"], orders=options["orders"])
    except Exception:  # noqa: BLE001 - each variant then runs alone and records its own error
        return caches
    for cache, result in zip(caches, results):
        cache[_campbell_key(options)] = result
    return caches


def _describe_campbell(model, options):
    from ..analysis.campbell import excitation_sources

    dims = ("speed", "mode")
    variables = {name: dims for name in ("frequency_hz", "damping_ratio", "real_part", "whirl_ratio")}
    sources = excitation_sources(model)
    lines = [(f"{name} {order:g}X", order * multiplier / (2 * np.pi))
             for name, multiplier in zip(sources.names, sources.multipliers) for order in options["orders"]]
    coords = {"speed": ("speed", options["speeds"], {"units": "rad/s"}),
              "speed_rpm": ("speed", options["speeds"] / _RPM, {"units": "rpm"}),
              "mode": ("mode", np.arange(1, mode_count(model) + 1), {}),
              "excitation": ("excitation", np.array([line[0] for line in lines], dtype=str), {}),
              "excitation_slope": ("excitation", np.array([line[1] for line in lines]),
                                   {"units": "Hz per rad/s of the reference speed (base model)"})}
    return variables, coords, None


def _run_campbell(model, options, layout, cache):
    result = _campbell_of(model, options, cache)
    return {"frequency_hz": result.frequencies_hz, "damping_ratio": result.damping_ratios,
            "real_part": result.eigenvalues.real, "whirl_ratio": result.whirl_ratios}


def _describe_critical(model, options):
    from ..analysis.campbell import excitation_sources

    sources = excitation_sources(model).names
    modes = mode_count(model)           # once: it builds the model's state form (0.3 s at 606 coordinates)
    rows = [(s, o, m) for s in sources for o in options["orders"] for m in range(1, modes + 1)]
    coords = {"crossing": ("crossing", np.arange(len(rows)), {}),
              "crossing_source": ("crossing", np.array([r[0] for r in rows], dtype=str), {}),
              "crossing_order": ("crossing", np.array([r[1] for r in rows]), {}),
              "crossing_mode": ("crossing", np.array([r[2] for r in rows]), {})}
    variables = {"critical_speed": ("crossing",), "critical_frequency_hz": ("crossing",),
                 "critical_count": ()}
    return variables, coords, {row: i for i, row in enumerate(rows)}


def _run_critical(model, options, layout, cache):
    """Per (source, order, mode): the crossing nearest zero speed (NaN if none)."""
    critical = _campbell_of(model, options, cache).critical
    speeds = np.full(len(layout), np.nan)
    freqs = np.full(len(layout), np.nan)
    for source, order, mode, speed, freq in zip(critical.source, critical.order, critical.mode,
                                                critical.speeds, critical.frequencies_hz):
        i = layout.get((str(source), float(order), int(mode)))
        if i is not None and not abs(speed) >= abs(speeds[i]):  # NaN compares False: take it
            speeds[i], freqs[i] = speed, freq
    return {"critical_speed": speeds, "critical_frequency_hz": freqs,
            "critical_count": np.array(float(len(critical)))}


# ---------------------------------------------------------------------------- modes
def _describe_modes(model, options):
    coords = {"mode": ("mode", np.arange(1, mode_count(model) + 1), {})}
    return {"modal_frequency_hz": ("mode",), "modal_damping_ratio": ("mode",)}, coords, None


def _run_modes(model, options, layout, cache):
    from ..analysis.modal import modal

    result = modal(model, options["speed"])
    return {"modal_frequency_hz": result.frequencies_hz, "modal_damping_ratio": result.damping_ratios}


# ---------------------------------------------------------------------------- stability
def _describe_stability(model, options):
    coords = {"stability_speed": ("stability_speed", options["speeds"], {"units": "rad/s"})}
    variables = {"threshold_speed": (), "instability_speed": (), "max_real_part": ("stability_speed",)}
    return variables, coords, None


def _run_stability(model, options, layout, cache):
    from ..analysis.stability import stability

    result = stability(model, options["speeds"])
    largest = result.largest_real_parts        # zero within round-off, as the thresholds count it
    # lowest speed of the sweep where the machine is unstable: the threshold, or the
    # sweep's start when it is unstable there already (NaN: stable over the sweep)
    start = result.speeds[0] if largest[0] > 0 else result.threshold_speed
    return {"threshold_speed": np.array(result.threshold_speed), "instability_speed": np.array(start),
            "max_real_part": largest}


# ---------------------------------------------------------------------------- unbalance
def _describe_unbalance(model, options):
    from ..analysis.unbalance import unbalance_forces

    outputs = options["outputs"] or [s.name for s in model.sensors]
    sources = unbalance_forces(model, options["speeds"][:1])[0]
    coords = {"output": ("output", np.array(outputs, dtype=str), {}),
              "unbalance_source": ("unbalance_source", np.array(sources, dtype=str), {})}
    dims = ("output", "unbalance_source")
    variables = {name: dims for name in _UNBALANCE_VARIABLES}
    forces = ()
    if options.get("forces"):
        forces = tuple(_force_rows(_response(model, options, options["speeds"][:1], []), options["forces"])[0])
        coords["force_output"] = ("force_output", np.array(forces, dtype=str), {})
        variables |= {name: ("force_output", "unbalance_source") for name in _FORCE_VARIABLES}
    return variables, coords, (tuple(outputs), tuple(sources), forces)


#: per (output, unbalance_source): the sensors' peaks; the AF read off the swept speeds, as its netCDF
#: attribute ``peak_search`` says (the exact search of ``unbalance`` and ``report`` cost 3 to 9 times
#: the swept response for the largest peak alone: docs/study-file.md)
_UNBALANCE_VARIABLES = ("unbalance_peak_amplitude", "unbalance_peak_speed", "amplification_factor",
                        "separation_margin_pct", "required_margin_pct")
#: per (force_output, unbalance_source), with ``forces``: the force rows' peaks [N, N m; rad/s]
_FORCE_VARIABLES = ("force_peak_amplitude", "force_peak_speed")


def _response(model, options, speeds, outputs):
    from ..analysis.unbalance import unbalance_response

    return unbalance_response(model, speeds, outputs=list(outputs), quantity=options["quantity"], resonances=False)


def _run_unbalance(model, options, layout, cache):
    from ..analysis.unbalance import amplification_factors, required_separation_margin

    outputs, sources, forces = layout
    result = _response(model, options, options["speeds"], outputs)
    out = _peaks_of(outputs, sources, result.outputs, result.amplitude, result, options, amplification_factors,
                    required_separation_margin)
    if forces:
        names, amplitude = _force_rows(result, options["forces"])
        found = _peaks_of(forces, sources, names, amplitude, result, options, amplification_factors,
                          required_separation_margin)
        out |= {"force_peak_amplitude": found["unbalance_peak_amplitude"],
                "force_peak_speed": found["unbalance_peak_speed"]}
    return out


def _peaks_of(rows, sources, names, amplitude, result, options, factors, required):
    """The peak variables of :data:`_UNBALANCE_VARIABLES`, shape (len(rows), len(sources)), of
    the amplitude curves ``amplitude`` (len(names), n_sources, N) named ``names``; NaN for a row
    or source the variant lacks."""
    out = {name: np.full((len(rows), len(sources)), np.nan) for name in _UNBALANCE_VARIABLES}
    index = {name: r for r, name in enumerate(names)}
    for j, source in enumerate(sources):
        if source not in result.sources:
            continue
        k = result.sources.index(source)
        for i, name in enumerate(rows):
            if name in index:
                _unbalance_peak(out, i, j, options["speeds"], amplitude[index[name], k], options["operating_speed"],
                                factors, required)
    return out


def _force_rows(result, forces):
    """Names (``NAME:Fx`` ... ``NAME:Mz``) and 0-peak amplitudes [N, N m], shape (rows, n_sources,
    N), of the force rows ``result.to_dataframe(forces=forces)`` adds after the sensors'."""
    table = result.to_dataframe(forces=forces, amplitude="peak")
    rows = table.iloc[len(result.outputs) * len(result.sources) * len(result.speeds):]   # after the sensors'
    names = list(dict.fromkeys(rows["output"]))
    shape = (len(names), len(result.sources), len(result.speeds))
    return names, rows["amplitude"].to_numpy(dtype=float).reshape(shape)


def _unbalance_peak(out, i, j, speeds, amplitude, operating, factors, required):
    """The largest peak of one amplitude curve: its amplitude, speed, AF and margins."""
    peaks = factors(speeds, amplitude)
    if peaks:
        speed, amp, af = max(peaks, key=lambda p: p[1])
    else:  # monotonic curve: the end of the sweep
        k = int(np.argmax(amplitude))
        speed, amp, af = float(speeds[k]), float(amplitude[k]), np.nan
    out["unbalance_peak_amplitude"][i, j] = amp
    out["unbalance_peak_speed"][i, j] = speed
    out["amplification_factor"][i, j] = af
    above = operating is not None and abs(speed) > abs(operating)
    out["required_margin_pct"][i, j] = required(af, "above" if above else "below")
    if operating is not None:
        out["separation_margin_pct"][i, j] = 100 * abs(operating - speed) / abs(operating)


# ---------------------------------------------------------------------------- registry
ANALYSES = {
    "modes": Analysis("modes", ("speed_rpm",), _parse_modes, _describe_modes, _run_modes),
    "campbell": Analysis("campbell", ("speeds_rpm", "orders"), _parse_sweep, _describe_campbell,
                         _run_campbell),
    "critical_speeds": Analysis("critical_speeds", ("speeds_rpm", "orders"), _parse_sweep,
                                _describe_critical, _run_critical),
    "stability": Analysis("stability", ("speeds_rpm",), _parse_stability, _describe_stability,
                          _run_stability),
    "unbalance": Analysis("unbalance", ("speeds_rpm", "outputs", "operating_speed_rpm", "quantity", "forces"),
                          _parse_unbalance, _describe_unbalance, _run_unbalance),
}


def parse_analyses(table, source, model=None) -> dict:
    """Validate ``[analyses]``: name -> options (speeds in rad/s).

    ``critical_speeds`` without ``speeds_rpm`` takes the Campbell sweep's speeds
    and orders (one eigen-solution serves both).
    """
    if not isinstance(table, dict) or not table:
        raise _error(source, "[analyses]", table, "at least one of " + ", ".join(
            f"[analyses.{name}]" for name in ANALYSES))
    out = {}
    for name in sorted(table, key=lambda n: n == "critical_speeds"):
        options = table[name]
        where = f"[analyses.{name}]"
        if name not in ANALYSES:
            raise _error(source, "[analyses]", name, "analyses among " + ", ".join(ANALYSES))
        if not isinstance(options, dict):
            raise _error(source, where, options, "a table of options")
        for key in options:
            if key not in ANALYSES[name].keys:
                raise _error(source, f"{where} {key}", options[key],
                             "one of the keys " + (", ".join(ANALYSES[name].keys) or "(none)")
                             + unknown_key(key, ANALYSES[name].keys))
        if name == "critical_speeds" and "speeds_rpm" not in options and "campbell" in out:
            options = {"orders": table["campbell"].get("orders"), **options}
            out[name] = {"speeds": out["campbell"]["speeds"],
                         "orders": _orders(options["orders"], f"{where} orders", source)}
            continue
        out[name] = ANALYSES[name].parse(options, where, source)
    if model is not None:
        _check_sensors(out, table, source, model)
        try:
            describe(model, out)
        except Exception as error:  # an option the base model cannot serve (unknown sensor...)
            raise _error(source, "[analyses]", sorted(out), f"analyses the model supports ({error})") from None
    return out


def _check_sensors(analyses, table, source, model):
    """The unbalance response's outputs must be sensors of the model (else every variant fails)."""
    outputs = analyses.get("unbalance", {}).get("outputs") or []
    known = [sensor.name for sensor in model.sensors]
    if any(name not in known for name in outputs):
        raise _error(source, "[analyses.unbalance] outputs", table["unbalance"]["outputs"],
                     "names of the model's sensors: " + (", ".join(known) or "(the model has none)"))


def describe(model, analyses) -> tuple:
    """Variables (name -> dims after ``variant``), coordinates and per-analysis layouts."""
    variables, coords, layouts = {}, {}, {}
    for name, options in analyses.items():
        v, c, layout = ANALYSES[name].describe(model, options)
        variables.update(v)
        coords.update(c)
        layouts[name] = layout
    return variables, coords, layouts


def run_analyses(model, analyses, layouts, cache=None) -> dict:
    """Every analysis of one variant: ``{variable: ndarray}``.

    ``cache`` may hold results computed beforehand for a batch of variants
    (:func:`batch_caches`)."""
    cache = {} if cache is None else cache
    out = {}
    for name, options in analyses.items():
        out.update(ANALYSES[name].run(model, options, layouts[name], cache))
    return out
