"""One self-contained HTML page of a :class:`~.collect.ReportData`: figures drawn by
:mod:`rotordyn_modal.plotting` and embedded as base64 PNG, tables with a unit in every
column header, a summary of the criteria linking to their sections, print CSS for A4."""

from __future__ import annotations

import base64
import datetime
import io
from html import escape
from string import Template

import numpy as np

from ..analysis.unbalance_checks import sensor_groups
from ..unbalance_standards import amplitude_factor, amplitude_label, largest_margins_text
from ..units import check_system, unit_scale
from .collect import (AMPLITUDE_WORDS, LOWEST_MODES, MODE_WINDOW, MOST_MODES, SECTIONS, UCS_STIFFNESS, VELOCITY_DIGITS,
                      from_pkpk, shown_scale)

__all__ = ["render_html", "figure_png", "margins_table"]

_CSS = """
body { font-family: "DejaVu Sans", Arial, sans-serif; margin: 2em auto; max-width: 1100px; color: #222;
       line-height: 1.4; font-size: 14px; }
h1 { border-bottom: 2px solid #335; } h2 { border-bottom: 1px solid #99a; margin-top: 2em; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 12px; }
th, td { border: 1px solid #bbc; padding: 2px 6px; text-align: right; }
th { background: #eef; } td.text, th.text { text-align: left; }
.pass { background: #d8f3d8; } .fail { background: #f8d0d0; font-weight: bold; }
.not-evaluated { background: #eee; color: #555; } td.nowrap { white-space: nowrap; }
figure { margin: 1em 0; } figure img { max-width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 12px; color: #444; }
code, .mono { font-family: "DejaVu Sans Mono", monospace; font-size: 12px; word-break: break-all; }
nav ol { columns: 2; } .note { color: #555; font-size: 12px; }
@page { size: A4; margin: 15mm; }
@media print { body { margin: 0; max-width: none; font-size: 10pt; } h2 { page-break-before: always; }
  figure, table { page-break-inside: avoid; } a { color: inherit; text-decoration: none; } }
"""

_PAGE = Template("""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>$title</title><style>$css</style></head>
<body>
<h1>$title</h1>
<p>Rotordynamic report to <b>$standard</b> &mdash; rotordyn_modal $version, $date.</p>
<p>$conventions</p>
<nav><h2 id="contents">Contents</h2><ol>$toc</ol></nav>
<h2 id="summary">Summary of the criteria</h2>
$summary
$sections
</body></html>
""")


#: the report page's widest figure [px] (the body's max-width) and the figures' resolution [dpi]
PAGE_WIDTH_PX, FIGURE_DPI = 1100, 110


def figure_png(fig, dpi: int = FIGURE_DPI) -> str:
    """A ``data:image/png;base64,...`` URI of a matplotlib figure (the figure is closed).

    A figure with a layout engine (constrained layout) is laid out once, at ``dpi``, and then
    saved without its engine: ``savefig`` alone lays it out twice (a draw to lay it out, then
    the draw that renders, laying it out again), and the layout is most of a figure's cost.
    The second layout moves nothing once the first has run: the PNG is the same, byte for byte
    (tests/test_report_browser_all.py compares them).
    """
    import matplotlib.pyplot as plt

    buffer = io.BytesIO()
    if fig.get_layout_engine() is not None:
        fig.set_dpi(dpi)
        fig.draw_without_rendering()
        fig.set_layout_engine("none")
    fig.savefig(buffer, format="png", dpi=dpi)
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def render_html(data, date: str | None = None, units: str = "si") -> str:
    """The report page of ``data`` (a :class:`~.collect.ReportData`) as a string.

    ``units`` ('si' or 'us', docs/units.md): the unit system of every number with a unit shown in
    the tables, the summary and the figures; ``data`` stays SI (converted here, at the edge).
    """
    units = check_system(units)
    info = data.model_info
    names = {"api617": "API 617", "api684": "API RP 684", "iso": "ISO 21940-11 / ISO 20816-3"}
    toc = "".join(f'<li><a href="#{s}">{escape(SECTIONS[s])}</a></li>' for s in data.sections)
    body = "\n".join(_SECTION_RENDERERS[s](data, units) for s in data.sections)
    return _PAGE.substitute(
        title=escape(f"Rotordynamic report: {info['name']}"), css=_CSS, standard=names[data.inputs.standard],
        version=escape(info["version"]),
        date=escape(date or datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")),
        toc='<li><a href="#summary">Summary of the criteria</a></li>' + toc,
        summary=_summary(data, units), sections=body, conventions=_conventions(data))


def _conventions(data) -> str:
    """The sentence under the title that says the amplitude convention of the whole report."""
    chosen = data.inputs.amplitude
    words = amplitude_label(chosen)
    note = "" if chosen == "pk-pk" else (f" (the API limits, written peak-to-peak, are shown {words} too: "
                                         f"x {from_pkpk(chosen):.4g})")
    return escape(f"Vibration amplitudes are {words} throughout: tables, figures and summary{note}; "
                  "the ISO 20816-3 casing velocities RMS, as the zones are defined (docs/report.md).")


# -- pieces ---------------------------------------------------------------------------------
def _table(rows, headers) -> str:
    """An HTML table; ``headers`` (text, is_text) pairs; ``rows`` lists of cell strings (a
    cell may be ``(html, css_class)``)."""
    head = "".join(f'<th class="text">{escape(h)}</th>' if text else f"<th>{escape(h)}</th>"
                   for h, text in headers)
    out = []
    for row in rows:
        cells = []
        for cell, (_, text) in zip(row, headers):
            html, css = cell if isinstance(cell, tuple) else (escape(str(cell)), "text" if text else "")
            cells.append(f'<td class="{css}">{html}</td>' if css else f"<td>{html}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(out)}</tbody></table>"


def _verdict_cell(verdict: str):
    return escape(verdict), {"pass": "pass", "fail": "fail"}.get(verdict, "not-evaluated")


def _figure(fig, caption: str, alt: str) -> str:
    return (f'<figure><img src="{figure_png(fig)}" alt="{escape(alt)}">'
            f"<figcaption>{escape(caption)}</figcaption></figure>")


def _heading(section: str) -> str:
    return f'<h2 id="{section}">{escape(SECTIONS[section])}</h2>'


def _skipped(data, key) -> str:
    return f'<p class="note">Not evaluated: {escape(data.skipped[key])}</p>' if key in data.skipped else ""


def _g(value, digits=4) -> str:
    return "" if value is None or (isinstance(value, float) and not np.isfinite(value)) else f"{value:.{digits}g}"


def _summary(data, units) -> str:
    shown = [c.in_system(units, data.inputs.amplitude) for c in data.criteria]
    # a value and its limit each on one line: "25.4 µm pk-pk" broken after the number reads as two values
    rows = [[(f'<a href="#{c.section}">{escape(c.name)}</a>', "text"), (escape(c.value), "nowrap"),
             (escape(c.limit), "nowrap"), _verdict_cell(c.verdict), c.why, c.source] for c in shown]
    headers = [("criterion", True), ("value", False), ("limit", False), ("verdict", True), ("note", True),
               ("source of the rule", True)]
    warn = "".join(f"<li>{escape(w)}</li>" for w in data.warnings)
    return _table(rows, headers) + (f'<p class="note">Warnings of the analyses:</p><ul class="note">{warn}</ul>'
                                    if warn else "")


def _model(data, units) -> str:
    info, inputs = data.model_info, data.inputs
    kg, mass = shown_scale("mass", units)
    low, high = (x * 30 / np.pi for x in inputs.range)
    facts = [("model", info["name"]), ("model file", info["file"]), ("SHA-256 of the model file", info["sha256"]),
             ("rotordyn_modal version", info["version"]), ("command", inputs.command or "(Python call)"),
             ("maximum continuous speed [rpm]", f"{inputs.mcs * 30 / np.pi:.6g}"),
             ("operating range [rpm]", f"{low:.6g} to {high:.6g}" if high > low else f"{low:.6g} (one speed)"),
             ("speeds analysed [rpm]", f"{inputs.speeds[0] * 30 / np.pi:.6g} to {inputs.speeds[-1] * 30 / np.pi:.6g}"
                                       f" ({len(inputs.speeds)} points, the MCS and the operating range's ends among them)"),
             (f"stator (casing) mass [{mass}]",
              "none" if info["stator_mass"] is None else f"{info['stator_mass'] * kg:.6g}")]
    parts = [_heading("model"), _table([[k, (f'<span class="mono">{escape(v)}</span>', "text")] for k, v in facts],
                                       [("item", True), ("value", True)])]
    parts.append("<h3>Rotors</h3>" + _table([[n, f"{m * kg:.6g}", f"{r:.6g}"] for n, m, r in info["rotors"]],
                                            [("rotor", True), (f"mass [{mass}]", False), ("speed ratio [-]", False)]))
    parts.append("<h3>Bearings</h3>" + (_table([list(b) for b in info["bearings"]],
                                               [("bearing", True), ("rotor", True), ("type", True)])
                                        if info["bearings"] else "<p>none (rotors rigidly attached)</p>"))
    parts.append("<h3>Mounts (suspensions)</h3>" + ("<p>" + escape(", ".join(info["suspensions"])) + "</p>"
                                                    if info["suspensions"] else "<p>none</p>"))
    parts.append("<h3>Sensors</h3>" + (_table([list(s) for s in info["sensors"]],
                                              [("sensor", True), ("on", True), ("measure", True)])
                                       if info["sensors"] else "<p>none</p>"))
    return "\n".join(parts)


def _static_supports(model) -> str:
    """What carries the rotors in the static solve, for the static section's sentence: the
    bearings at their stiffness at the MCS, and the rotors without bearings (rigidly attached:
    they move with the stator, which carries their loads)."""
    loose = [r.name for r in model.rotors if not model.bearings_of(r.name)]
    if not model.bearings:
        return "no bearings in the model: its rotors move with the stator, which carries their loads"
    return "bearings at their stiffness at that speed" + (
        f"; {', '.join(loose)} without bearings move with the stator, which carries their loads" if loose else "")


def _static(data, units) -> str:
    result = data.results.get("static")
    if result is None:
        return _heading("static") + _skipped(data, "static")
    shown = result.displacements()
    (to_sag, sag_unit), (to_force, force_unit) = shown_scale("sag", units), shown_scale("force", units)
    sag = _at_round_off(shown[["ux_m", "uy_m", "uz_m"]].to_numpy()) * to_sag
    frame = len(data.model.suspensions) + 1 if data.model.dofs.n_frame else 0   # the stator's rows come first
    inside = "stator" if data.model.stator is not None else "frame" if frame else "ground"
    rows = [[r.body, r.point, "ground" if i < frame else inside, *(_g(v) for v in values)]
            for i, (r, values) in enumerate(zip(shown.itertuples(), sag))]
    reactions = result.reactions_table()
    forces = _at_round_off(reactions[["Fx_N", "Fy_N", "Fz_N"]].to_numpy()) * to_force
    # a journal bearing's true position at its load: the film's eccentricity and attitude angle
    journals = bool(np.isfinite(reactions["eccentricity"].to_numpy(dtype=float)).any())
    film = ([[_g(r.eccentricity, 4), _g(r.attitude_deg, 4)] for r in reactions.itertuples()] if journals
            else [[] for _ in range(len(reactions))])
    rrows = [[r.support, r.kind, r.body, r.on, *(_g(v) for v in values), *extra]
             for r, values, extra in zip(reactions.itertuples(), forces, film)]
    gravity = bool(np.any(np.asarray(data.model.gravity, dtype=float)))
    under = "Under the model's gravity at" if gravity else "At"
    return "\n".join([
        _heading("static"),
        f"<p>{under} the MCS "
        f"({data.inputs.mcs * 30 / np.pi:.6g} rpm), {_static_supports(data.model)} (docs/static.md).</p>",
        *([] if gravity else [_NO_GRAVITY]),
        "<h3>Static displacement (sag)</h3>",
        _table(rows, [("body", True), ("point", True), ("relative to", True),
                      *((f"u_{a} [{sag_unit}]", False) for a in "xyz")]),
        *([_JOURNAL_NOTE] if journals else []),
        "<h3>Reactions (force of each support on the body it carries)</h3>",
        _table(rrows, [("support", True), ("kind", True), ("body", True), ("on", True),
                       *((f"F_{a} [{force_unit}]", False) for a in "xyz"),
                       *([("eccentricity ratio [-]", False), ("attitude angle [deg]", False)] if journals else [])]),
        *_shaft_statics(result, units)])


#: a model without gravity: the report applies no other static load
_NO_GRAVITY = ('<p class="note">The model gives no gravity (its <code>gravity</code> is absent or zero) and the '
               "report applies no other static load: nothing sags and every reaction is 0.</p>")

#: under the sag table of a machine with journal bearings: which displacement it is (docs/static.md)
_JOURNAL_NOTE = ('<p class="note">At a journal bearing the displacement above is that of its light-load '
                 "linear film (the load over the film's stiffness, across the load: the film holds the journal at "
                 "90&deg; to its offset); the journal's position at its load is its eccentricity ratio (of the "
                 "radial clearance) and attitude angle (from the load, in the sense of rotation) in the reactions "
                 "table, from the full short-bearing solution. A journal whose load the analyses solve at each "
                 "speed (a rotor on three or more journals) stands on its loaded film instead: its "
                 "displacement is the film's offset at that load (docs/static.md).</p>")


def _shaft_statics(result, units) -> list:
    """The flexible shafts' largest sag, shear force, bending moment and bending stress (a table)
    and their diagram along the axis (a figure); nothing for rigid rotors."""
    shafts = list(result.shafts.values())
    if not shafts:
        return []
    from ..plotting.shaft_statics import statics_scales

    scales = statics_scales(units)          # the units of the figure and of the static command's summary
    to_length, length_unit = scales["length"]
    rows, loaded = [], False
    for shaft in shafts:
        for quantity, what in (("sag", "sag"), ("shear", "shear force"), ("moment", "bending moment"),
                               ("stress", "bending stress"), ("torque", "torque"), ("von_mises", "von Mises stress")):
            factor, unit = scales[{"torque": "moment", "von_mises": "stress"}.get(quantity, quantity)]
            value, i = shaft.largest(quantity)
            # 0 everywhere (no static load, no torque): no station governs, none is named
            where = ([shaft.label(i, quantity), f"{shaft.axis_names[2]} = {_g(shaft.position[i] * to_length)}"]
                     if value != 0 else ["none (0 everywhere)", ""])
            rows.append([shaft.rotor, f"largest {what} [{unit}]", _g(value * factor), *where])
            loaded = loaded or value != 0
    # every quantity 0 along every shaft (no gravity, no torque): a sentence, not a page of zeros
    figure = (_figure(result.plot_shafts(units=units),
                      "Figure: static sag relative to the stator, shear force and bending moment along each "
                      "flexible shaft, both bending planes; bearings and disks marked (docs/static.md).",
                      "Shaft sag, shear force and bending moment") if loaded else _NO_SHAFT_LOAD)
    return ["<h3>Flexible shafts: sag, shear force, bending moment and stress</h3>",
            "<p>Stresses at the outer fibre of the section: bending <i>&sigma; = M c / I</i>, torsion "
            "<i>&tau; = T c / J</i> (the torque of the loads' moments about the spin axis; none without "
            "a transmitted torque), von Mises <i>&radic;(&sigma;&sup2; + 3 &tau;&sup2;)</i> against the "
            "material's allowable_stress (the criterion above; docs/static.md).</p>",
            _table(rows, [("rotor", True), ("quantity", True), ("value", False), ("station", True),
                          (f"position, model axes [{length_unit}]", True)]),
            figure]


#: in place of the shaft diagram when no shaft carries a static load
_NO_SHAFT_LOAD = ('<p class="note">No static load acts on the flexible shafts: their sag, shear force, bending '
                  "moment and stress are 0 everywhere, so no diagram is drawn.</p>")


def _at_round_off(values, relative: float = 1e-9):
    """``values`` with the entries below ``relative`` x the largest made 0 (round-off of a solve)."""
    values = np.asarray(values, dtype=float)
    largest = np.nanmax(np.abs(values)) if values.size else 0.0
    return np.where(np.abs(values) <= relative * largest, 0.0, values) + 0.0


#: the report's Campbell diagram reaches this factor above the highest frequency of its order
#: lines: beyond API 617's largest separation margin above the range (26 %)
_ABOVE_ORDERS = 1.4


def campbell_top(result):
    """Top of the report's Campbell frequency axis [Hz], or None (the whole diagram).

    :data:`_ABOVE_ORDERS` times the highest frequency an order line reaches in the sweep
    (:func:`_order_reach`), at least 1.4 times the lowest mode; lowered, where no mode lies
    between, to :data:`_ABOVE_ORDERS` times the highest frequency of the modes below it (every
    mode an order line can cross, whole); None where no mode lies above. Modes higher up are
    crossed by no order line, and on an axis reaching them (bearing modes at 1 kHz over mount
    modes at 5 Hz) the crossings fill the bottom few per cent; so they did below an empty band
    up to the 1X lines' reach (examples/motor_pump_on_mounts.toml: modes up to 16 Hz, the axis
    to 131 Hz, the critical speeds' labels on each other).
    """
    freqs = np.where(result.oscillatory, result.frequencies_hz, np.nan)
    if not np.isfinite(freqs).any() or not len(result.sources.multipliers):
        return None
    top = max(_ABOVE_ORDERS * _order_reach(result), 1.4 * float(np.nanmin(freqs)))
    below = np.min(np.where(np.isfinite(freqs), freqs, np.inf), axis=0) < top    # the modes the axis shows
    highest = float(np.nanmax(freqs[:, below]))
    top = min(top, max(_ABOVE_ORDERS * highest, 1.4 * float(np.nanmin(freqs))))
    return top if float(np.nanmax(freqs)) > top else None


def _order_reach(result) -> float:
    """The highest frequency an order line reaches in the sweep [Hz]: the largest order times
    the largest source multiplier times the largest speed."""
    return float(np.max(np.abs(result.orders)) * np.max(np.abs(result.sources.multipliers))
                 * np.max(np.abs(result.speeds)) / (2 * np.pi))


def instability_text(result, low: float, high: float) -> str:
    """A sentence naming the lowest speed of the Campbell sweep ``result`` where a mode grows in
    time (:meth:`CampbellResult.instability_onsets`, interpolated between swept speeds; or unstable
    from the first), and where it lies against the operating range ``low`` to ``high`` [rpm]; ""
    where every mode decays over the sweep. The figure's red band alone said it before: a report
    whose machine turns unstable inside its operating range read "pass" everywhere."""
    first = None                                              # (speed [rpm], frequency [Hz], mode)
    unstable = result.unstable
    for m, (speeds, frequencies) in enumerate(result.instability_onsets()):
        for speed, frequency in zip(np.abs(speeds) * 30 / np.pi, frequencies):
            if first is None or speed < first[0]:
                first = (speed, frequency, result.modes[m], "at about")
    for m in np.flatnonzero(unstable[0]):
        speed = abs(result.speeds[0]) * 30 / np.pi
        if first is None or speed <= first[0]:
            first = (speed, result.frequencies_hz[0, m], result.modes[m], "from the sweep's first speed,")
    if first is None:
        return ""
    speed, frequency, mode, how = first
    where = ("inside the operating range" if low <= speed <= high else
             "below the operating range" if speed < low else "above the operating range")
    return (f" Mode {mode} becomes unstable {how} {speed:,.0f} rpm ({frequency:.4g} Hz, {where}; interpolated "
            "between the swept speeds: 'rotordyn-modal stability' finds the threshold); where a mode grows, "
            "the unbalance response is no steady state.")


def _campbell(data, units) -> str:
    result = data.results["campbell"]
    from ..analysis._roots import at_round_off

    critical = result.critical.to_dataframe(numbers=False)            # the table shows no mode_at_speed
    # a damping ratio within the solve's round-off (-1.6e-17 of an undamped mode) shows as 0, as in 'modes'
    noise = data.results.get("critical_round_off", np.zeros(len(critical)))
    critical["damping_ratio"] = at_round_off(critical["damping_ratio"].to_numpy(dtype=float), noise)
    low, high = (x * 30 / np.pi for x in data.inputs.range)
    rows = [[r.source, _g(r.order), r.mode, _g(r.speed_rpm, 6), _g(r.frequency_hz, 5), r.whirl,
             _g(r.damping_ratio, 3)] for r in critical.itertuples()]
    top = campbell_top(result)
    lowest = np.min(np.where(result.oscillatory, result.frequencies_hz, np.inf), axis=0)    # of each mode
    above = 0 if top is None else int(np.sum(np.isfinite(lowest) & (lowest > top)))
    parts = [_heading("campbell"),
             _figure(result.plot(title=data.model_info["name"], freq_range=None if top is None else (None, top),
                                 operating=(low, high)),
                     "Figure: Campbell diagram, natural frequencies against the reference rotor's speed "
                     "with the 1X lines; critical speeds marked. "
                     + (f"Operating range {low:.6g} to {high:.6g} rpm (shaded)." if high > low
                        else f"Operating speed {low:.6g} rpm (dashed).")
                     + instability_text(result, low, high)
                     + (f" Frequencies up to {top:.4g} Hz: the {above} modes above are crossed by no 1X line in "
                        f"the sweep (the highest reaches {_order_reach(result):.4g} Hz)." if above else ""),
                     "Campbell diagram"),
             "<h3>Critical speeds (1X crossings)</h3>",
             _table(rows, [("source", True), ("order [-]", False), ("mode", True), ("speed [rpm]", False),
                           ("frequency [Hz]", False), ("whirl", True), ("damping ratio [-]", False)])
             if rows else "<p>No critical speed in the sweep.</p>",
             "<h3 id=\"margins\">Amplification factors and separation margins (API 684)</h3>",
             "<p>Peaks of the unbalance response at the probes (every sensor when there is none); "
             "AF = N_c / (N_2 - N_1) at the half-power points; required separation margin from API 617 / 684: 0 for "
             "AF &lt; 2.5, else min(16, 17 (1 - 1/(AF - 1.5))) % below the range, min(26, 10 + 17 (1 - 1/(AF - 1.5))) % "
             "above it; margin measured from the nearer end "
             "of the operating range (docs/standards.md).</p>"]
    margins = data.results.get("margins")
    if margins is None:
        parts.append(_skipped(data, "unbalance"))
    elif margins.empty:
        parts.append("<p>No resonance peak in the sweep.</p>")
    else:
        parts.append(margins_table(margins, units, data.inputs.amplitude))
    return "\n".join(parts)


def margins_table(margins, units: str = "si", amplitude: str = "pk-pk") -> str:
    """The table of the API 684 peaks (``collect.separation_margins``: 0-peak amplitudes in m),
    one row per peak, its amplitude in the convention ``amplitude``. Each row names what excites
    it: its API case, or without cases its source (the rotor whose 1X it is: two rotors' peaks at
    one sensor are told apart, as the figure's labels tell them)."""
    has_case = "case" in margins
    to_vibration, vibration = shown_scale("vibration", units)
    to_vibration *= amplitude_factor(amplitude)                     # the table holds 0-peak amplitudes
    rows = [[r.output, r.case if has_case else r.source, _g(r.speed_rpm, 6),
             "unbounded\u2020" if np.isposinf(r.amplitude) else _g(r.amplitude * to_vibration),
             af_text(r.amplification_factor), _g(r.separation_margin_pct, 3),
             _g(r.required_margin_pct, 3) or "unknown*", _verdict_cell(r.verdict)] for r in margins.itertuples()]
    unknown = bool(np.any(np.isnan(np.asarray(margins["amplification_factor"], dtype=float))))
    unbounded = bool(np.any(np.isposinf(np.asarray(margins["amplitude"], dtype=float))))
    return _table(rows, [("output", True), ("case" if has_case else "source (1X of)", True),
                         ("peak speed [rpm]", False), (f"amplitude, {amplitude_label(amplitude)} [{vibration}]", False),
                         ("AF [-]", False), ("separation margin [%]", False), ("required margin [%]", False),
                         ("verdict", True)]) + (_AF_UNKNOWN if unknown else "") + (_UNBOUNDED if unbounded else "")


def af_text(af: float, digits: int = 3) -> str:
    """An amplification factor as the AF table shows it: ``unknown*`` where it is NaN (a
    half-power point beyond the sweep: the note under the table says so), ``inf`` where it is
    infinite (an undamped resonance: N1 = N2, known, judged against the largest margin any AF
    requires; the summary says ``AF inf``), else ``digits`` significant digits."""
    af = float(af)
    return "unknown*" if np.isnan(af) else "inf" if np.isinf(af) else f"{af:.{digits}g}"


#: under the AF table where a peak's AF is unknown (its rows "not evaluated")
_AF_UNKNOWN = ('<p class="note">* AF unknown: the amplitude does not fall to peak/&radic;2 on both sides of '
               "the peak within the sweep (a half-power point lies beyond its ends or past a neighbouring "
               "peak). Such a peak passes where its margin is at least the largest any AF requires "
               f"({largest_margins_text(' the range')}: its required margin shown); otherwise neither the required "
               "margin nor the verdict can be set (docs/standards.md).</p>")


#: under the AF table where a peak is unbounded (an undamped mode's critical speed)
_UNBOUNDED = ('<p class="note">\u2020 Unbounded: no damping acts on the mode, so the response grows without '
              "bound at its critical speed, where the unbalance's 1X line meets the undamped root (a root on the "
              "imaginary axis); the peak speed is that critical speed, found exactly (as the critical-speed table "
              "gives it), "
              "not a swept speed, and its AF is infinite. On isotropic supports an unbalance excites forward whirl "
              "only: a backward-whirl critical speed of the table then has no peak (docs/report.md).</p>")


#: a damping ratio or log decrement below this is the round-off of an undamped mode
_ROUND_OFF_DAMPING = 1e-9


def _modes(data, units) -> str:
    shapes = data.results.get("modes")
    if shapes is None:
        return _heading("modes") + _skipped(data, "modes")
    from ..analysis.mode_shapes import mode_index

    result, numbers = shapes.modal, shapes.numbers
    mcs = data.inputs.mcs * 30 / np.pi
    low, high = (x * 30 / np.pi for x in shapes.window)
    rows, captions = [], []
    from .collect import mode_label

    tracked = shapes.tracked or numbers                   # no Campbell sweep: the MCS numbers alone
    for number, reason, label in zip(numbers, shapes.reasons, tracked):
        k = mode_index(result, number)
        shown = mode_label(number, label)
        # a log decrement at round-off (an undamped axial mode: 1e-15) shows as 0
        delta, zeta = (x if abs(x) > _ROUND_OFF_DAMPING else 0.0
                       for x in (result.log_decrements[k], result.damping_ratios[k]))
        whirl = f"{result.whirl[k]} whirl" if result.whirl[k] != "none" else "no whirl"
        rows.append([shown, _g(result.frequencies_hz[k], 5), whirl, _g(delta, 3), _g(zeta, 3), reason])
        captions.append(f"mode {shown}: {result.frequencies_hz[k]:.4g} Hz, {whirl}, log dec {delta:.3g}")
    if shapes.lines is not None:
        from ..plotting.shaft_modes import plot_shaft_modes

        fig = plot_shaft_modes(shapes.lines, relative=data.model.stator is not None, units=units,
                               title=f"Mode shapes at the MCS, {mcs:.6g} rpm")
        what = "deflected shaft lines along the axis (both planes at phase 0, the orbits' largest excursion shaded)"
    else:
        # as many panels a row as the page holds unshrunk: their bar labels stay readable
        # two lines: one mode's panel is 3.2 in wide, and the title on one line ran off both its sides
        fig = result.plot(title=f"Mode shapes at the MCS\n{mcs:.6g} rpm, |shape| normalised", modes=numbers,
                          max_width=PAGE_WIDTH_PX / FIGURE_DPI, **_units(units))
        what = "each coordinate's share of the mode (|shape|, normalised)"
    _renumbered(fig, {number: mode_label(number, label) for number, label in zip(numbers, tracked)})
    return "\n".join([
        _heading("modes"),
        f"<p>Modes at the MCS ({mcs:.6g} rpm), numbered as the Campbell diagram, the critical-speed table and "
        "<code>stability</code> number them (tracked over the sweep: mode N is one mode throughout the report); "
        f"where <code>modes --speed {mcs:.6g}</code> numbers one otherwise, its number there follows in brackets "
        "(in the figure's panels too). Shown are "
        f"those whose 1X critical speed or whose frequency at the MCS (as a 1X speed) lies within "
        f"{100 * MODE_WINDOW[0]:.0f} % below or {100 * MODE_WINDOW[1]:.0f} % above (the largest separation "
        "margins API 617 asks) the operating range, "
        f"{low:.6g} to {high:.6g} rpm (at most {MOST_MODES}); the lowest {LOWEST_MODES} at the MCS when none does "
        "(docs/report.md).</p>" + (f"<p>{escape(shapes.note)}</p>" if shapes.note else ""),
        _table(rows, [("mode", True), ("frequency [Hz]", False), ("whirl", True), ("log decrement [-]", False),
                      ("damping ratio [-]", False), ("shown because", True)]),
        _figure(fig, f"Figure: {what}. " + "; ".join(captions) + ".", "Mode shapes")])


def _ucs(data, units) -> str:
    result = data.results.get("ucs")
    if result is None:
        return _heading("ucs") + _skipped(data, "ucs")
    factor, unit = shown_scale("stiffness", units)
    stiffness = result.stiffness * factor
    default = UCS_STIFFNESS * factor
    widened = (f", widened from the default {default[0]:.3g} to {default[-1]:.3g} {unit} to reach the bearings' own "
               "stiffness" if data.inputs.stiffness is None and len(result.stiffness) != len(UCS_STIFFNESS) else "")
    return _heading("ucs") + _figure(
        result.plot(**_units(units)), f"Figure: undamped critical speed map, forward critical speeds against the "
        f"bearings' radial stiffness ({stiffness[0]:.3g} to {stiffness[-1]:.3g} {unit}{widened}), the bearings' own "
        f"stiffness over speed drawn on it, {_operating_drawn(data.inputs.range)} (docs/level1_and_ucs.md).",
        "Undamped critical speed map")


def _operating_drawn(operating) -> str:
    """How the UCS map draws the operating range [rad/s]: a band, or one speed's dashed line where
    the band would be too thin to show (:data:`rotordyn_modal.plotting.ucs_map.THINNEST_BAND`:
    a single rated speed, the MCS alone by default)."""
    from ..plotting.ucs_map import THINNEST_BAND

    low, high = (s * 30 / np.pi for s in operating)
    if high > low * THINNEST_BAND:
        return "the operating range as a band"
    return f"the operating speed ({low:.6g} rpm) as a dashed line" if high == low else \
        f"the operating range ({low:.6g} to {high:.6g} rpm) as a dashed line"


def _unbalance(data, units) -> str:
    response, checks = data.results.get("unbalance"), data.results.get("checks")
    if response is None:
        return _heading("unbalance") + _skipped(data, "unbalance")
    chosen = data.inputs.amplitude
    # the same amount (API 617): 4 oz in/lb = 6350 g mm/kg
    amount = "6350 W/N g mm (W in kg" if units == "si" else "4 W/N oz in (W in lb"
    amount += (", N the MCS in rpm; api-static at the centre of mass, api-couple at the outermost bearings; for a "
               "flexible rotor api-mode1, api-mode2, ... for each lateral mode up to 1.3 x its 1X frequency, at the "
               "node of the mode's largest deflection, or a couple of W/2 at its two antinodes of opposite sign)")
    what = ("the model's [[unbalances]]" if data.inputs.standard == "iso" else
            f"the API 617/684 unbalance cases Ua = 2 Ur, Ur = {amount}, each case on its own")
    parts = [_heading("unbalance"), f"<p>Response to {escape(what)}.</p>",
             _figure(response.plot(amplitude=chosen, checks=checks, peaks=data.results.get("peaks", data.results.get("margins")),
                                   groups=sensor_groups(data.model), **_units(units)),
                     f"Figure: unbalance response, amplitude {amplitude_label(chosen)} and phase against speed; the largest peaks "
                     "of every panel with their AF and separation margin from the operating range (the probes' peaks "
                     "are judged in the table of section Campbell diagram and critical speeds); API 617 probe limits (informative in an ISO report) "
                     "and the ISO zones where checked.", "Unbalance response")]
    onset = data.results.get("onset", float("nan"))
    if np.isfinite(onset):
        parts.append(f'<p class="note">Not a steady state above {onset * 30 / np.pi:,.0f} rpm: a mode grows in time '
                     "from there (summary, \"Stability over the operating range\"; Campbell diagram). A linear model "
                     "unstable at a speed has no steady unbalance response there: the amplitudes shown above that "
                     "speed solve the equations but describe no vibration the machine settles to.</p>")
    from .collect import probe_limit_table

    table = probe_limit_table(data)
    if data.inputs.standard != "iso":
        factor, unit = shown_scale("vibration", units)
        shown = "" if chosen == "pk-pk" else f"; shown {amplitude_label(chosen)} below (x {from_pkpk(chosen):.4g})"
        parts.append(f"<h3>API 617 probe vibration limit</h3><p>A1 = {25.4e-6 * factor:.3g} {unit} sqrt(12000/N), "
                     f"at most {25.4e-6 * factor:.3g} {unit} peak-to-peak, N the probe's rotor's MCS [rpm]; largest "
                     f"over 0 to MCS, the peaks the AF table found between swept speeds included{shown}.</p>")
        parts.append(_check_table(table, factor * from_pkpk(chosen), f"{unit} {AMPLITUDE_WORDS[chosen]}")
                     if not table.empty else
                     "<p>No proximity probe (measure = \"relative\") in the model.</p>")
        parts.append(_clearance_table(data, units))
    return "\n".join(parts)


def _clearance_table(data, units) -> str:
    """The API 617 clearance check, one row per station and case (or why there is none)."""
    check = data.results.get("clearance")
    heading = '<h3 id="clearance">API 617 clearance check at close-clearance stations</h3>'
    if check is None:
        return heading + ("<p>No close-clearance station ([[rotors.clearances]]) in the model: not evaluated.</p>"
                          if not data.model.clearances else "")
    factor, unit = shown_scale("vibration", units)
    chosen = data.inputs.amplitude
    amplitude, words = factor * from_pkpk(chosen), f"{unit} {AMPLITUDE_WORDS[chosen]}"   # judged pk-pk
    table = check.to_dataframe()
    radial = dict(zip(check.names, check.radial_clearances))
    has_case = "case" in table
    how, notes = _scaling_notes(table["scaling"])
    rows = [[r.clearance, r.rotor, *([r.case] if has_case else []), _g(radial[r.clearance] * factor),
             _g(r.speed_rpm, 6), _g(r.response * amplitude), _g(r.scale_factor, 3), scaled,
             _g(r.value * amplitude), _g(r.limit * amplitude), _g(r.ratio, 3), _verdict_cell(r.verdict)]
            for r, scaled in zip(table.itertuples(), how)]
    shown = "" if chosen == "pk-pk" else f" (shown {amplitude_label(chosen)}: x {from_pkpk(chosen):.4g})"
    return heading + (
        "<p>At each station the rotor's motion relative to the casing (which holds the seal): its peak-to-peak "
        "response, twice the orbit's semi-major axis, scaled by the API 617 factor Scc = Avl/Amax (at most 6; "
        "Avl the probe limit A1 of the station's rotor, Amax the largest peak-to-peak amplitude at its probes over "
        "the operating range; 1 without a probe), largest over 0 to MCS, the maxima between swept speeds "
        "included (found on the exact response), against 75 % of the minimum diametral "
        f"running clearance (0.75 x 2 x the radial clearance){shown}, each API case on its own (docs/standards.md).</p>"
    ) + _table(rows, [("clearance", True), ("rotor", True), *([("case", True)] if has_case else []),
                      (f"radial clearance [{unit}]", False), ("speed [rpm]", False),
                      (f"response [{words}]", False), ("Scc [-]", False), ("scale factor", True),
                      (f"value = Scc x response [{words}]", False),
                      (f"limit [{words}]", False), ("ratio [-]", False), ("verdict", True)]) + notes


def _scaling_notes(scaling):
    """How each row's scale factor was found, short (``Avl/Amax capped at 6``), and its
    parenthesis (``Amax at 9968 rpm, the sweep's speed nearest the operating speeds``), the same
    for every row, said once under the table: on every row it made each row four lines high."""
    parts = [str(text).partition(" (") for text in scaling]
    notes = list(dict.fromkeys(tail.rstrip(")") for _, sep, tail in parts if sep))
    text = "".join(f'<p class="note">Scale factor: {escape(note)}.</p>' for note in notes)
    return [head for head, _, _ in parts], text


def _check_table(table, scale, unit, digits=4) -> str:
    """The API probe limits or the ISO zones, one row per output (and case); the zone column only
    where a row has a zone (the ISO checks: an API probe's is empty); a value of inf (the AF
    table's unbounded peak: an undamped mode) reads 'unbounded'."""
    has_case = "case" in table
    zoned = bool((table["zone"].fillna("").astype(str) != "").any())
    rows = [[r.output, *([r.case] if has_case else []), _g(r.speed_rpm, 6),
             "unbounded" if np.isposinf(r.value) else _g(r.value * scale, digits),
             _g(r.limit * scale, digits), *([r.zone] if zoned else []), _verdict_cell(r.verdict)] for r in table.itertuples()]
    return _table(rows, [("output", True), *([("case", True)] if has_case else []), ("speed [rpm]", False),
                         (f"value [{unit}]", False), (f"limit [{unit}]", False), *([("zone", True)] if zoned else []),
                         ("verdict", True)])


def _level1(data, units) -> str:
    result = data.results.get("level1")
    if result is None:
        return _heading("level1") + _skipped(data, "level1")
    ratio = f"{result.ratio:.3g}" if np.isfinite(result.q0) else f"> {result.cross_coupling[-1] / result.qa:.3g}"
    factor, unit = shown_scale("stiffness", units)
    rows = [[f"anticipated cross-coupling Qa [{unit}]", _g(result.qa * factor), ""],
            ["log decrement at Qa [-]", _g(result.log_decrement_at_qa, 3), f">= {result.log_decrement_criterion:g}"],
            [f"Q0 [{unit}]", _g(result.q0 * factor) if np.isfinite(result.q0) else "beyond the sweep", ""],
            ["Q0/Qa [-]", ratio, f">= {result.ratio_criterion:g}"]]
    csr = result.csr
    if csr is not None:
        dscale, dunit = shown_scale("density", units)
        critical = _g(csr.critical_speed * 30 / np.pi) if csr.evaluated else "none (rigid rotor)"
        rows += [["first critical speed on rigid supports [rpm]", critical, ""],
                 [f"average gas density [{dunit}]", _g(csr.density * dscale), ""],
                 ["critical speed ratio CSR [-]", _g(csr.csr, 3) if csr.evaluated else "not evaluated",
                  (f"Region A: <= {csr.boundary:.3g}" + ("" if result.csr_applies else " (Q0/Qa >= 10: not applied)"))
                  if csr.evaluated else "no critical speed on rigid supports: nothing to judge"]]
    runs = result.swept or (result,)
    return "\n".join([
        _heading("level1"),
        f"<p>Stations: {escape(', '.join(_station(s, units) for s in result.stations))}; at the MCS the "
        f"rotor's forward modes at the station ({len(runs)} followed) are swept and the least stable is judged: "
        f"{_level1_mode(data, result)} (docs/report.md; numbered as the Campbell diagram, the number "
        f"<code>modes --speed</code> gives it at the MCS in brackets where it differs). "
        f"{escape(result.verdict(units))}.</p>",
        _table(rows, [("quantity", True), ("value", False), ("criterion", False)]),
        _qa_inputs(getattr(getattr(data, "inputs", None), "level1", None), units),
        _runs_table(runs, result, units, data),
        _figure(_renumbered(result.plot(**_units(units)), {run.mode: _tracked_label(data, run.mode) for run in runs
                                                            if run.mode}),
                f"Figure: log decrement of each swept forward mode against the "
                f"applied cross-coupling Q, {_level1_mode(data, result)} (bold), the least stable at Qa; Q0 the smallest of "
                "the swept modes' (API 617 Level I; docs/level1_and_ucs.md).", "Level I stability")]
        + ([] if csr is None or not csr.evaluated else [_figure(csr.plot(verdict=result.verdict().rpartition(": ")[2], **_units(units)),
                                           "Figure: critical speed ratio against average gas density, the dividing "
                                           "line between Regions A and B (API 617 Level I; docs/standards.md).",
                                           "Critical speed ratio chart")]))


def _qa_inputs(given, units) -> str:
    """Where the report's Qa comes from: ``--qa`` as given, or a table of the stage data with each
    stage's ``q_A`` and their sum, in the report's units, so that Qa can be worked by hand
    (``given``: :attr:`ReportInputs.level1`; its ``stages``, :func:`..cli.level1.anticipated_stages`)."""
    from ..analysis.level1 import B_COMPRESSOR, B_TURBINE

    stages = (given or {}).get("stages")
    if not stages:
        return ("<p>Qa as given (<code>--qa</code>, or <code>level1={'qa': ...}</code> in Python), not computed "
                "from stage data.</p>")
    compressor = stages["machine"] == "compressor"
    b = B_COMPRESSOR if compressor else B_TURBINE
    power, power_unit = unit_scale("power", units)
    length, length_unit = unit_scale("length", units)
    stiffness, stiffness_unit = shown_scale("stiffness", units)
    n_r = stages["speed"] * 30 / np.pi
    rows = [[str(k + 1), _g(p * power, 6), _g(d * length, 6), _g(h * length, 6),
             _g(r, 6) if compressor else "not used", _g(q * stiffness, 6)]
            for k, (p, d, h, r, q) in enumerate(zip(stages["power"], stages["diameter"], stages["height"],
                                                    stages["density_ratio"], stages["qa"]))]
    rows.append(["sum: Qa", "", "", "", "", _g(float(np.sum(stages["qa"])) * stiffness, 6)])
    words = (("impeller diameter D", "restriction height H (the smaller of diffuser and impeller discharge width)")
             if compressor else ("blade pitch diameter D", "effective blade height H"))
    return (f"<p>Anticipated cross-coupling of each {'impeller' if compressor else 'stage'} (API 617 Level I, "
            f"{'compressor' if compressor else 'turbine'}): q<sub>A</sub> = B T / (D H)"
            f"{' (&rho;<sub>d</sub>/&rho;<sub>s</sub>)' if compressor else ''}, T = P / &Omega;<sub>r</sub> the "
            f"stage's torque (the standard's C P / N<sub>r</sub>, C = 60/2&pi; = 9.5493 taken exactly), B = {b:g}, "
            f"N<sub>r</sub> = {n_r:.6g} rpm; P the rated power, {words[0]}, {words[1]} "
            "(docs/level1_and_ucs.md).</p>"
            + _table(rows, [("stage", True), (f"P [{power_unit}]", False), (f"D [{length_unit}]", False),
                            (f"H [{length_unit}]", False), ("ρd/ρs [-]", False),
                            (f"q_A [{stiffness_unit}]", False)]))


def _renumbered(fig, labels: dict):
    """``fig`` with each "mode N" of its texts (panel titles, legend, axis labels) written
    "mode ``labels[N]``": the figures of :mod:`rotordyn_modal.plotting` number the modes as
    ``modes --speed MCS`` does, the report as the Campbell diagram (:func:`_tracked_label`);
    ``labels`` maps the first to the second, a number it lacks stays. Returns ``fig``."""
    import re

    from matplotlib.text import Text

    def label(match):
        return f"mode {labels.get(int(match.group(1)), match.group(1))}"

    for text in fig.findobj(Text):
        words = text.get_text()
        if "mode " in words:
            text.set_text(re.sub(r"\bmode (\d+)\b", label, words))
    return fig


def _level1_mode(data, run) -> str:
    """``mode N`` of a Level I run (its mode at Q = 0, the machine itself, at the MCS) by the
    Campbell diagram's number, ``modes --speed MCS``'s in brackets where it differs
    (:func:`mode_label`); the run's own label where it is no mode or there is no sweep."""
    return f"mode {_tracked_label(data, run.mode)}" if run.mode else run.mode_label


def _tracked_label(data, number: int) -> str:
    """:func:`mode_label` of the mode ``modes --speed MCS`` numbers ``number``."""
    from .collect import mode_label, tracked_numbers

    campbell = None if data is None else data.results.get("campbell")
    if campbell is None:
        return str(number)
    return mode_label(number, tracked_numbers(campbell, data.inputs.mcs, (number,))[0])


def _runs_table(runs, judged, units, data=None) -> str:
    """One row per forward mode the Level I swept: its frequency at Q = 0, log decrement at Qa,
    Q0 and Q0/Qa, and which criterion it governs; its mode numbered as the Campbell diagram
    (:func:`_tracked_label`; ``data`` None: ``modes --speed MCS``'s number)."""
    factor, unit = shown_scale("stiffness", units)
    rows = []
    for run in runs:
        governs = [what for what, yes in (("log decrement at Qa", run.forward_mode == judged.forward_mode),
                                          ("Q0", np.isfinite(judged.q0) and run.q0 == judged.q0)) if yes]
        beyond = f"> {run.cross_coupling[-1] / run.qa:.3g}"
        rows.append([_tracked_label(data, run.mode) if run.mode else "none (no oscillation at Q = 0)", _g(run.frequencies_hz[0], 5), _g(run.log_decrement_at_qa, 3),
                     _g(run.q0 * factor) if np.isfinite(run.q0) else "beyond the sweep",
                     f"{run.ratio:.3g}" if np.isfinite(run.q0) else beyond, ", ".join(governs)])
    return ("<h3>Forward modes swept</h3>"
            + _table(rows, [("mode", True), ("frequency at Q = 0 [Hz]", False), ("log decrement at Qa [-]", False),
                            (f"Q0 [{unit}]", False), ("Q0/Qa [-]", False), ("governs", True)]))


def _station(station, units) -> str:
    """``ROTOR@OFFSET UNIT``: the offset in the length unit of ``units``, named (m or in)."""
    return station.named(units) if hasattr(station, "named") else str(station)


def _iso(data, units) -> str:
    checks = data.results.get("checks")
    if "iso" in data.skipped:
        return _heading("iso") + _skipped(data, "iso")
    table = checks.to_dataframe()
    table = table[table["check"].str.startswith("ISO")]
    factor, unit = shown_scale("velocity", units)
    low, mid, high = (b * factor for b in checks.zone_boundaries)
    return "\n".join([_heading("iso"),
                      f"<p>RMS vibration velocity of every casing sensor, largest "
                      f"{escape(_iso_speeds(checks))}, "
                      f"{escape(checks.iso_class)}: zone boundaries A/B {_g(low, VELOCITY_DIGITS)}, B/C {_g(mid, VELOCITY_DIGITS)}, "
                      f"C/D {_g(high, VELOCITY_DIGITS)} {unit} "
                      "RMS; pass in zones A and B (docs/standards.md).</p>",
                      _check_table(table, factor, f"{unit} RMS", VELOCITY_DIGITS)])


def _iso_speeds(checks) -> str:
    """Which speeds the ISO zones judged (``collect.iso_span`` without its first word)."""
    from .collect import iso_span

    return iso_span(checks).partition(" ")[2]


def _units(units) -> dict:
    """The figures' ``units=`` keyword: none in SI (the figures as they were), ``units='us'`` else."""
    return {} if units == "si" else {"units": units}


_SECTION_RENDERERS = {"model": _model, "static": _static, "campbell": _campbell, "modes": _modes, "ucs": _ucs,
                      "unbalance": _unbalance, "level1": _level1, "iso": _iso}
