"""Figures of measured data: time records of a test and the coherence of estimated FRFs."""

from __future__ import annotations


__all__ = ["plot_time_records", "plot_coherence"]

_UNITS = {"force": "N", "displacement": "m", "velocity": "m/s", "acceleration": "m/s²", "pressure": "Pa"}


def plot_time_records(records, record: int = 0, title: str | None = None):
    """Forces (top), responses and pressures (below) of one record against time.

    Parameters
    ----------
    records : TimeRecords
    record : int
        Index of the record (from 0).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    t = records.times
    forces = [k for k, q in enumerate(records.quantities) if q == "force"]
    responses = [k for k, q in enumerate(records.quantities) if q not in ("force", "pressure")]
    pressures = [k for k, q in enumerate(records.quantities) if q == "pressure"]
    rows = [group for group in (forces, responses, pressures) if group]
    fig, axes = plt.subplots(len(rows), 1, sharex=True, figsize=(8.0, 2.6 * len(rows) + 0.6), layout="constrained",
                             squeeze=False)
    for ax, group in zip(axes[:, 0], rows):
        for k in group:
            ax.plot(t, records.signals[record, k], linewidth=0.8, label=records.channels[k])
        ax.set_ylabel(f"{records.quantities[group[0]]} [{_UNITS[records.quantities[group[0]]]}]")
        ax.legend(fontsize="small", loc="upper right")
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("Time [s]")
    axes[0, 0].set_title(title or f"Record {record + 1} of {records.signals.shape[0]} "
                         f"({records.sampling_rate_hz:g} Hz sampling)")
    return fig


def plot_coherence(result, title: str | None = None):
    """Coherence of every estimated FRF against frequency.

    Parameters
    ----------
    result : FRFResult
        With ``coherence``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ._style import new_figure

    fig, ax = new_figure(figsize=(8.0, 3.5))
    for a, out in enumerate(result.outputs):
        for b, inp in enumerate(result.inputs):
            ax.plot(result.frequencies_hz, result.coherence[a, b], linewidth=1.0, label=f"{out} / {inp}")
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel("Coherence [-]")
    ax.grid(True, alpha=0.3)
    if result.H.shape[0] * result.H.shape[1] <= 12:
        ax.legend(fontsize="small", loc="lower left")
    ax.set_title(title or f"Coherence of the {result.engine} estimates", fontsize="medium")
    return fig
