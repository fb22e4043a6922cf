"""Figures of model-versus-measurement correlation and of a fit."""

from __future__ import annotations

import numpy as np
from ..units import rpm_text

__all__ = ["plot_correlation", "plot_fit_correlation", "plot_rigid_body"]


def plot_correlation(result, title: str | None = None):
    """CSAC and CSF against frequency, FRAC of each FRF in the legend.

    Parameters
    ----------
    result : Correlation

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ._style import new_figure

    fig, ax = new_figure(figsize=(8.0, 4.0))
    ax.plot(result.frequencies_hz, result.csac, label="CSAC (shape)")
    ax.plot(result.frequencies_hz, result.csf, label="CSF (shape and amplitude)")
    for (o, i), value in zip(result.pairs, result.frac):
        ax.plot([], [], " ", label=f"FRAC {o} / {i}: {value:.3f}")
    ax.set_ylim(0, 1.05)
    ax.set_xlabel("Frequency [Hz]")
    ax.set_ylabel("Correlation [-]")
    ax.legend(fontsize="small", loc="lower left")
    ax.set_title(title or f"Model versus measurement at {rpm_text(result.speed * 30 / np.pi)} rpm")
    return fig


def plot_fit_correlation(result, title: str | None = None):
    """The parameter correlation matrix of a fit as an image.

    Parameters
    ----------
    result : FitResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ._style import new_figure

    fig, ax = new_figure(figsize=(6.0, 5.0))
    image = ax.imshow(result.correlation, vmin=-1, vmax=1, cmap="RdBu_r")
    labels = [k.split(".", 1)[-1] for k in result.keys]
    ax.set_xticks(range(len(labels)), labels, rotation=45, ha="right", fontsize="small")
    ax.set_yticks(range(len(labels)), labels, fontsize="small")
    for (i, j), v in np.ndenumerate(result.correlation):
        ax.text(j, i, f"{v:+.2f}", ha="center", va="center", fontsize="small")
    fig.colorbar(image, ax=ax, label="correlation")
    ax.set_title(title or "Correlation of the fitted parameters")
    return fig


def plot_rigid_body(result, x=None, title: str | None = None):
    """The six rigid-body motions of the stator (real part) against ``x``.

    Parameters
    ----------
    result : RigidBodyMotion
    x : array_like, optional
        Abscissa (sample index by default).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    q = np.real(result.q.reshape(6, -1))
    x = np.arange(q.shape[1]) if x is None else np.asarray(x)
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(8.0, 5.0), layout="constrained")
    for k, name in enumerate(("u_x", "u_y", "u_z")):
        top.plot(x, q[k], label=name)
    for k, name in enumerate(("θ_x", "θ_y", "θ_z")):
        bottom.plot(x, q[3 + k], label=name)
    top.set_ylabel("translation")
    bottom.set_ylabel("rotation")
    top.legend(fontsize="small")
    bottom.legend(fontsize="small")
    top.set_title(title or f"Stator rigid-body motion at {np.round(result.point, 3)} m")
    return fig
