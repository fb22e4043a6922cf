"""Bode figures: FRFs (model over measurement) and unbalance response vs speed."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_frf", "plot_unbalance", "plot_overlay"]

#: more FRFs than this are drawn without a legend
_MAX_LEGEND = 12
_UNITS = {"receptance": "m/N", "mobility": "m/s/N", "accelerance": "m/s²/N", "force": "N/N"}


def _bode_axes(figsize=(8.0, 6.0)):
    import matplotlib.pyplot as plt

    fig, (mag, phase) = plt.subplots(2, 1, sharex=True, figsize=figsize, layout="constrained",
                                     gridspec_kw={"height_ratios": [2, 1]})
    phase.set_yticks([-180, -90, 0, 90, 180])
    phase.set_ylabel("Phase [deg]")
    return fig, mag, phase


def plot_frf(result, measured=None, pairs=None, title: str | None = None):
    """Magnitude (log) and phase of FRFs against frequency, measured data dotted beneath.

    Parameters
    ----------
    result : FRFResult
    measured : FRFResult, optional
        Measured FRFs with the same output and input names (matched by name).
    pairs : list of (output, input), optional
        Which FRFs to draw (default all).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, mag, phase = _bode_axes()
    pairs = pairs or [(o, i) for o in result.outputs for i in result.inputs]
    for n, (o, i) in enumerate(pairs):
        colour = f"C{n % 10}"
        h = result.H[result.outputs.index(o), result.inputs.index(i)]
        if measured is not None and o in measured.outputs and i in measured.inputs:
            hm = measured.H[measured.outputs.index(o), measured.inputs.index(i)]
            mag.semilogy(measured.frequencies_hz, np.abs(hm), ".", ms=2.5, color=colour, alpha=0.5)
            phase.plot(measured.frequencies_hz, np.degrees(np.angle(hm)), ".", ms=2.5, color=colour, alpha=0.5)
        mag.semilogy(result.frequencies_hz, np.abs(h), color=colour, label=f"{o} / {i}")
        phase.plot(result.frequencies_hz, np.degrees(np.angle(h)), color=colour)
    _limit_range(mag)
    mag.set_ylabel(f"|H| [{_UNITS.get(result.quantity, '')}]")
    phase.set_xlabel("Frequency [Hz]")
    if len(pairs) <= _MAX_LEGEND:
        mag.legend(fontsize="small", title="model (line), measured (dots)" if measured is not None else None)
    mag.set_title(title or f"{result.quantity.capitalize()} at {result.speed * 30 / np.pi:.0f} rpm"
                  + (f" ({len(pairs)} FRFs)" if len(pairs) > _MAX_LEGEND else ""))
    return fig


def plot_overlay(models, measured, title: str | None = None):
    """Model over measurement at several speeds: one colour per speed.

    Parameters
    ----------
    models, measured : list of FRFResult
        Paired by position (same speeds, names and frequencies).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, mag, phase = _bode_axes()
    for n, (model, meas) in enumerate(zip(models, measured)):
        colour = f"C{n % 10}"
        for o in model.outputs:
            for i in model.inputs:
                hm = meas.H[meas.outputs.index(o), meas.inputs.index(i)]
                h = model.H[model.outputs.index(o), model.inputs.index(i)]
                mag.semilogy(meas.frequencies_hz, np.abs(hm), ".", ms=2.5, color=colour, alpha=0.5)
                phase.plot(meas.frequencies_hz, np.degrees(np.angle(hm)), ".", ms=2.5, color=colour, alpha=0.5)
                mag.semilogy(model.frequencies_hz, np.abs(h), color=colour)
                phase.plot(model.frequencies_hz, np.degrees(np.angle(h)), color=colour)
        mag.plot([], [], color=colour, label=f"{model.speed * 30 / np.pi:.0f} rpm")
    _limit_range(mag)
    mag.set_ylabel(f"|H| [{_UNITS.get(models[0].quantity, '')}]")
    phase.set_xlabel("Frequency [Hz]")
    mag.legend(fontsize="small", title="model (line), measured (dots)")
    mag.set_title(title or "Model versus measurement")
    return fig


def plot_unbalance(result, outputs=None, speed_unit: str = "rpm", peaks=None, title: str | None = None):
    """Amplitude (0-peak) and phase of each source's harmonic against speed.

    Parameters
    ----------
    result : UnbalanceResult
    outputs : list of str, optional
        Sensors to draw (default all).
    speed_unit : {'rpm', 'rad/s', 'hz'}
    peaks : pandas.DataFrame, optional
        ``result.peaks(...)``: each peak is marked with its amplification factor (and
        separation margin when known).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ._style import speed_label, speed_scale

    fig, mag, phase = _bode_axes()
    x = result.speeds * speed_scale(speed_unit)
    unit = {"displacement": "m", "velocity": "m/s", "acceleration": "m/s²"}[result.quantity]
    n = 0
    for i, o in enumerate(result.outputs):
        if outputs is not None and o not in outputs:
            continue
        for j, s in enumerate(result.sources):
            colour = f"C{n % 10}"
            mag.plot(x, result.amplitude[i, j], color=colour, label=f"{o}: {s} (1x {s})")
            phase.plot(x, result.phase_deg[i, j], color=colour)
            n += 1
    if peaks is not None:
        _mark_peaks(mag, peaks, outputs, speed_scale(speed_unit) * np.pi / 30)
        mag.margins(y=0.15)
    mag.set_ylabel(f"Amplitude, 0-peak [{unit}]")
    phase.set_xlabel(speed_label(speed_unit))
    mag.legend(fontsize="small")
    mag.set_title(title or "Unbalance response")
    return fig


def _mark_peaks(ax, peaks, outputs, rpm_to_unit):
    for row in peaks.itertuples(index=False):
        if (outputs is not None and row.output not in outputs) or not np.isfinite(row.amplification_factor):
            continue
        x = row.speed_rpm * rpm_to_unit
        text = f"AF {row.amplification_factor:.1f}"
        if np.isfinite(row.separation_margin_pct):
            text += f"\nSM {row.separation_margin_pct:.0f} % (API {row.required_margin_pct:.0f} %)"
        ax.plot(x, row.amplitude, "v", color="k", ms=4)
        ax.annotate(text, (x, row.amplitude), textcoords="offset points", xytext=(4, 4), fontsize="x-small")


#: magnitudes below this fraction of the largest are round-off (an FRF zero by symmetry): not shown
_DYNAMIC_RANGE = 1e-6


def _limit_range(ax):
    """Keep the magnitude axis to six decades below the largest value drawn."""
    values = [np.nanmax(line.get_ydata()) for line in ax.get_lines() if len(line.get_ydata())]
    if values and np.isfinite(max(values)) and max(values) > 0:
        top = max(values)
        low = ax.get_ylim()[0]
        ax.set_ylim(max(low, _DYNAMIC_RANGE * top), ax.get_ylim()[1])
