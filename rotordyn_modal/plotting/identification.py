"""Stabilization chart of a modal identification."""

from __future__ import annotations


__all__ = ["plot_stabilization"]

_MARKERS = {
    "new": {"marker": "o", "color": "0.6", "markersize": 3, "label": "new pole",
            "markerfacecolor": "none", "linestyle": "none"},
    "frequency": {"marker": "^", "color": "tab:orange", "markersize": 4, "label": "stable frequency",
                  "markerfacecolor": "none", "linestyle": "none"},
    "stable": {"marker": "s", "color": "tab:blue", "markersize": 4, "label": "stable frequency and damping",
               "linestyle": "none"},
}


def plot_stabilization(chart, modes=None, ax=None, title: str | None = None):
    """Poles of every model order over the summed FRF magnitude; the chosen modes as lines.

    Parameters
    ----------
    chart : StabilizationChart
    modes : MeasuredModes, optional
        Identified (refined) modes, drawn as labelled vertical lines; otherwise the
        chart's selected frequencies are drawn.
    ax : matplotlib Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ._style import new_figure

    fig, ax = new_figure(ax, figsize=(8.5, 5.5))
    for status, style in _MARKERS.items():
        at = chart.status == status
        ax.plot(chart.frequencies_hz[at], chart.orders[at], **style)
    lines = chart.selected_hz if modes is None else modes.frequencies_hz
    for k, f in enumerate(lines):
        ax.axvline(f, color="tab:red", linewidth=0.9, alpha=0.8,
                   label=_identified_label(lines) if k == 0 else None)
    ax.set_xlim(*chart.band_hz)
    ax.set_ylim(0, chart.orders.max(initial=2) + 2)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel("Model order (number of poles)")
    _magnitude_behind(ax, chart)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), fontsize="small", ncols=2, frameon=False)
    ax.set_title(title or f"Stabilization chart (LSCF; stable: frequency within {100 * chart.tolerances[0]:g} %, "
                 f"damping within {100 * chart.tolerances[1]:g} %)", fontsize="medium")
    return fig


def _identified_label(frequencies_hz):
    values = ", ".join(f"{f:.3f}" for f in frequencies_hz[:8]) + (", ..." if len(frequencies_hz) > 8 else "")
    return f"identified modes: {values} Hz"


def _magnitude_behind(ax, chart):
    twin = ax.twinx()
    twin.semilogy(chart.frequency_lines_hz, chart.summed_magnitude, color="0.3", linewidth=0.8, alpha=0.6)
    twin.set_ylabel("sum of |H| over the FRFs (relative)", color="0.35")
    twin.tick_params(axis="y", colors="0.35", labelsize="small")
    ax.set_zorder(twin.get_zorder() + 1)
    ax.patch.set_visible(False)
