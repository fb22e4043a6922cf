"""Mode shape figure: participation of each degree of freedom."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_modes"]

_DOF = ["u_x", "u_y", "u_z", "θ_x", "θ_y", "θ_z"]


def plot_modes(result, title: str | None = None):
    """Bar chart of each oscillatory mode's mass-weighted DOF participation.

    Parameters
    ----------
    result : ModalResult
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    modes = np.nonzero(result.oscillatory)[0]
    cols = max(1, min(3, len(modes)))
    rows = max(1, int(np.ceil(len(modes) / cols)))
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.6 * rows), layout="constrained",
                             squeeze=False)
    for ax in axes.ravel()[len(modes):]:
        ax.set_visible(False)
    for i, (ax, m) in enumerate(zip(axes.ravel(), modes)):
        magnitude = np.abs(result.shapes[m])
        ax.bar(_DOF, magnitude / magnitude.max(), color="tab:blue")
        ax.set_title(f"mode {i + 1}: {result.frequencies_hz[m]:.2f} Hz, ζ={result.damping_ratios[m]:.3f}\n"
                     f"{result.whirl[m]} (ratio {result.whirl_ratios[m]:+.2f})", fontsize="small")
        ax.set_ylim(0, 1.05)
    fig.suptitle(title or f"Mode shapes at {result.speed * 30 / np.pi:.0f} rpm (|shape|, normalised)")
    return fig
