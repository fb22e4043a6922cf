"""API 617 Level I figures: log decrement of the followed forward modes against Q / Qa; the
critical speed ratio against average gas density."""

from __future__ import annotations

import textwrap

import numpy as np

from ..units import unit_scale
from ._style import new_figure

__all__ = ["plot_level1", "plot_csr_chart"]


def plot_level1(result, title: str | None = None, ax=None, units: str = "si"):
    """Log decrement against the applied cross-coupling ``Q / Qa``, with ``Qa`` and ``Q0`` marked.

    One curve per followed forward mode (``result.swept``), the one judged at ``Qa`` (the lowest
    log decrement there) bold, each labelled with what it governs. The criterion 0.1 is a dashed
    line, the log decrement at ``Qa`` a marker on its vertical line, ``Q0`` (where the first
    mode's log decrement reaches 0) a marker on the zero line; the title gives
    the verdict: the criteria's values and whether Level II is required. A second axis along
    the top reads ``Q`` in N/m, kN/m, MN/m or GN/m (lbf/in, klbf/in, ... with ``units='us'``), the
    prefix chosen so that its ticks read below 1000 with no multiplier beside the axis.

    Parameters
    ----------
    result : Level1Result
    title : str, optional
    ax : matplotlib Axes, optional
    units : {'si', 'us'}
        Unit system of ``Q``: N/m (SI) or lbf/in (US customary).

    Returns
    -------
    matplotlib.figure.Figure
    """
    LOG_DEC_CRITERION, RATIO_CRITERION = result.log_decrement_criterion, result.ratio_criterion
    scale, unit = unit_scale("stiffness", units)
    flat = _flattened(result) if ax is None else []
    own = ax is None                    # the figure is this function's: its legend goes below it
    if flat:
        import matplotlib.pyplot as plt

        fig, (ax, detail) = plt.subplots(2, 1, figsize=(8.0, 7.5), layout="constrained", sharex=True,
                                         gridspec_kw={"height_ratios": [2.4, 1.0]})
    else:
        fig, ax = new_figure(ax, figsize=(8.0, 5.5))
    x = result.cross_coupling / result.qa
    _curves(ax, result, x)
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.axhline(LOG_DEC_CRITERION, color="tab:red", linestyle="--", linewidth=1.0,
               label=f"log decrement {LOG_DEC_CRITERION:g} (criterion at Qa)")
    ax.axvline(1.0, color="0.4", linestyle=":", linewidth=1.0)
    ax.axvline(RATIO_CRITERION, color="tab:red", linestyle=":", linewidth=1.0,
               label=f"Q0/Qa = {RATIO_CRITERION:g} (criterion)")
    colour = "tab:red" if not result.passes_log_decrement else "tab:green"
    ax.plot([1.0], [result.log_decrement_at_qa], "o", color=colour, markersize=8, zorder=5,
            label=f"at Qa = {result.qa * scale:.4g} {unit}: log dec {result.log_decrement_at_qa:.3g}")
    if np.isfinite(result.q0):
        colour = "tab:red" if not result.passes_ratio else "tab:green"
        # not clipped: Q0 may lie on the axis' left edge (Q = 0), its diamond is drawn whole
        ax.plot([result.q0 / result.qa], [0.0], "D", color=colour, markersize=8, zorder=5, clip_on=False,
                label=f"Q0 = {result.q0 * scale:.4g} {unit} (Q0/Qa = {result.ratio:.3g})")
    _limits(ax, result)
    ax.set_xlabel("Applied cross-coupled stiffness Q / Qa [-]")
    ax.set_ylabel(("Log decrement of the followed modes [-]" if len(result.swept) > 1
                   else "Log decrement of the followed mode [-]") + "\n(< 0: unstable)")
    prefix, factor = _prefix(float(np.nanmax(np.abs(result.cross_coupling), initial=0.0)) * scale)
    qa = result.qa * scale / factor
    top = ax.secondary_xaxis("top", functions=(lambda q: q * qa, lambda q: q / qa))
    top.xaxis.get_major_formatter().set_useOffset(False)
    top.xaxis.get_major_formatter().set_scientific(False)
    top.set_xlabel(f"Q [{prefix}{unit}]")
    ax.grid(True, alpha=0.3)
    stations = ", ".join(s.named(units) for s in result.stations)
    heading = title or (f"API 617 Level I: {result.title}" if result.title else "API 617 Level I")
    # the verdict (with the CSR a line of some 150 characters) wrapped to the figure's width
    # several stations (a compressor's impellers) made one line wider than the figure: wrapped too
    where = textwrap.fill(f"at {result.speed * 30 / np.pi:.6g} rpm, Q at {stations}", 80)
    ax.set_title(f"{textwrap.shorten(heading, 80)}\n{where}\n"
                 f"{textwrap.fill(result.verdict(units), 80)}",
                 fontsize="medium", color="tab:red" if result.level2_required else "darkgreen")
    if own:    # below the figure: inside the axes the legend hid the criterion lines it names
        fig.legend(*ax.get_legend_handles_labels(), fontsize="x-small", loc="outside lower center", ncols=2,
                   frameon=False)
    else:
        ax.legend(fontsize="x-small", loc="best", framealpha=0.85)
    if flat:
        _detail(detail, x, flat, RATIO_CRITERION)
    return fig


#: a followed mode whose log decrement stays this close to zero, as a fraction of the panel's
#: height, is drawn again in a panel of its own under the first (its curve and where it crosses
#: zero are not seen on the scale of a mode that dives to -2.5)
_FLAT = 0.05


def _flattened(result):
    """The followed modes (``result.swept``) whose log decrements lie within :data:`_FLAT` of
    the panel's height of zero: their curves would lie on the zero line."""
    low, high = _range(result)
    span = high - low
    flat = []
    for run in result.swept or (result,):
        values = run.log_decrements[np.isfinite(run.log_decrements)]
        if values.size and np.abs(values).max() < _FLAT * span:
            flat.append(run)
    return flat


def _detail(ax, x, flat, ratio_criterion):
    """The panel under the first: every followed mode's curve again, its y axis over the
    ``flat`` modes' log decrements and zero (where each crosses zero is seen; the legend gives
    its Q0 / Qa), the lines of ``Qa`` and of the ratio criterion."""
    lines = _mode_lines(ax.figure.axes[0])
    for line in lines:
        ax.plot(line.get_xdata(), line.get_ydata(), color=line.get_color(), linewidth=line.get_linewidth(),
                linestyle=line.get_linestyle(), zorder=line.get_zorder())
    ax.axhline(0.0, color="k", linewidth=0.8)
    ax.axvline(1.0, color="0.4", linestyle=":", linewidth=1.0)
    ax.axvline(ratio_criterion, color="tab:red", linestyle=":", linewidth=1.0)
    values = np.concatenate([run.log_decrements for run in flat])
    values = values[np.isfinite(values)]
    low, high = min(values.min(), 0.0), max(values.max(), 0.0)
    span = high - low if high > low else 1.0
    ax.set_ylim(low - 0.12 * span, high + 0.12 * span)
    ax.set_xlim(0.0, x[-1])
    names = ", ".join(run.mode_label for run in flat)
    ax.set_ylabel(f"Log decrement [-]\n(near zero: {names})", fontsize="small")
    ax.set_xlabel(ax.figure.axes[0].get_xlabel())
    ax.figure.axes[0].set_xlabel("")
    ax.grid(True, alpha=0.3)


def _mode_lines(ax):
    """The followed modes' curves of the first panel, in the order drawn (``result.swept``'s)."""
    return [line for line in ax.get_lines() if "(forward " in str(line.get_label())]


#: SI prefixes of the top axis' unit, so that its ticks read below 1000 without a floating
#: multiplier ('1e7' in the corner read as Q = 0.25 N/m)
_PREFIXES = ((1e9, "G"), (1e6, "M"), (1e3, "k"))


def _prefix(largest: float) -> tuple:
    """(prefix, factor) of the unit for values up to ``largest``: ('M', 1e6) for 2e7."""
    for factor, prefix in _PREFIXES:
        if largest >= factor:
            return prefix, factor
    return "", 1.0


def _curves(ax, result, x):
    """The log decrement of each followed mode; the judged one bold, in blue."""
    runs = result.swept if len(result.swept) > 1 else (result,)
    others = iter(["tab:orange", "tab:purple", "tab:brown", "tab:olive", "tab:cyan"])
    governs_q0 = result.governs_q0
    for run in runs:
        judged = run.forward_mode == result.forward_mode     # unique per followed root (mode may be 0)
        governs = [what for what, yes in (("log dec at Qa", judged and len(runs) > 1),
                                          ("Q0", governs_q0 is run and len(runs) > 1)) if yes]
        ax.plot(x, run.log_decrements, color="tab:blue" if judged else next(others, "0.5"),
                linewidth=2.0 if judged else 1.3, linestyle="-" if judged else "--", zorder=3 if judged else 2,
                label=f"{run.mode_label} (forward {run.forward_mode}), {run.frequencies_hz[0]:.4g} Hz at Q = 0"
                      + (f": governs {' and '.join(governs)}" if governs else "")
                      + (f"; Q0/Qa = {run.q0 / result.qa:.3g}" if np.isfinite(run.q0) and "Q0" not in governs
                         and len(runs) > 1 else ""))


def _limits(ax, result):
    """x from 0 to the sweep's end; y over the curves, zero and the criterion, with a margin."""
    x = result.cross_coupling / result.qa
    ax.set_xlim(0.0, x[-1])
    ax.set_ylim(*_range(result))


def _range(result):
    """(low, high) of the first panel's y axis: the curves, zero and the criterion, with a margin."""
    values = np.concatenate([r.log_decrements for r in result.swept or (result,)])
    values = values[np.isfinite(values)]
    low = min(values.min(initial=0.0), 0.0)
    high = max(values.max(initial=0.0), 0.12)
    span = high - low
    return low - 0.08 * span, high + 0.08 * span


def plot_csr_chart(screening, title: str | None = None, ax=None, units: str = "si", verdict: str | None = None):
    """API 617 Level I chart: critical speed ratio against average gas density.

    The dividing line (``screening.dividing_line()``, :func:`~rotordyn_modal.analysis.level1.csr_boundary`)
    separates Region A (below) from Region B (above, shaded); the machine's point is marked,
    red in Region B. A second axis along the top reads the density in the other unit system.

    Parameters
    ----------
    screening : CsrScreening
    title : str, optional
    ax : matplotlib Axes, optional
    units : {'si', 'us'}
        Density along the bottom in kg/m³ (SI) or lb/ft³ (US customary).
    verdict : str, optional
        A short line added under the title (the Level I verdict, 'Level II required').

    Returns
    -------
    matplotlib.figure.Figure
    """
    scale, unit = unit_scale("density", units)
    other = "us" if units == "si" else "si"
    other_scale, other_unit = unit_scale("density", other)
    fig, ax = new_figure(ax, figsize=(8.0, 5.5))
    rho, line = screening.dividing_line()
    end = rho[-1]
    top = max(3.0, 1.15 * screening.csr)
    ax.fill_between(rho * scale, line, top, color="tab:red", alpha=0.08, linewidth=0)
    ax.plot(rho * scale, line, color="k", linewidth=1.8, label="dividing line (ROSS's reading of API 617)")
    # the region names stand away from the machine's point (u, v: axes fraction)
    u, v = screening.density / end, screening.csr / top
    ax.text(0.03, 0.45 if u < 0.3 and v < 0.2 else 0.05, "Region A", transform=ax.transAxes, fontsize="large",
            color="0.35")
    x, side = (0.03, "left") if u > 0.5 else (0.97, "right")
    ax.text(x, 0.93, "Region B (Level II if Q0/Qa < 10)", transform=ax.transAxes, fontsize="large", color="tab:red",
            alpha=0.7, va="top", ha=side)
    colour = "tab:red" if screening.region == "B" else "tab:green"
    critical = (f"{screening.critical_speed * 30 / np.pi:.5g} rpm" if np.isfinite(screening.critical_speed)
                else "none (rigid rotor)")
    # not clipped: a rigid rotor's CSR 0 lies on the bottom spine
    ax.plot([screening.density * scale], [screening.csr], "o", color=colour, markersize=9, zorder=5, clip_on=False,
            label=f"machine: MCS {screening.speed * 30 / np.pi:.5g} rpm / first critical on rigid supports "
                  f"{critical}")
    ax.set_xlim(0.0, end * scale)
    ax.set_ylim(0.0, top)
    ax.set_xlabel(f"Average gas density [{unit}]")
    ax.set_ylabel("Critical speed ratio CSR [-]\n(MCS / first critical speed on rigid supports)")
    ratio = other_scale / scale
    second = ax.secondary_xaxis("top", functions=(lambda x: x * ratio, lambda x: x / ratio))
    second.set_xlabel(f"[{other_unit}]")
    ax.grid(True, alpha=0.3)
    heading = title or "API 617 Level I: critical speed ratio against gas density"
    import textwrap

    lines = [textwrap.shorten(heading, 80), screening.summary(units)]
    if verdict:
        lines.append(f"Level I verdict: {textwrap.shorten(verdict, 90)}")
    bad = screening.region == "B" or (verdict or "").strip() == "Level II required"
    ax.set_title("\n".join(lines), fontsize="medium", color="tab:red" if bad else "darkgreen")
    ax.legend(fontsize="x-small", loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)   # off the chart
    return fig
