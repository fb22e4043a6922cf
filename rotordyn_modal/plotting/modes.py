"""Mode shape figure: participation of each degree of freedom."""

from __future__ import annotations

import numpy as np
from ..units import rpm_text

__all__ = ["plot_modes"]

_DOF = ["u_x", "u_y", "u_z", "θ_x", "θ_y", "θ_z"]


def _labels(result) -> list[str]:
    """Coordinate labels: the stator's six as u_x ... θ_z, rotors' as ROTOR.uy ..."""
    names = list(result.dof_names) or _DOF
    return _DOF + names[6:] if names[:1] and names[0].startswith(("stator.", "frame.")) else names


#: a damping or whirl ratio within this of zero is round-off: written 0
_ROUND_OFF = 1e-10


def small_number(value: float, sign: bool = False) -> str:
    """A ratio for a title: three decimals, two significant digits below 0.01 (``-0.00`` would
    hide a backward whirl's -0.003 and read a round-off -1e-25 damping as unstable), and ``0``
    within :data:`_ROUND_OFF` of zero."""
    if not np.isfinite(value):
        return f"{value}"
    if abs(value) <= _ROUND_OFF:
        return "0"
    if abs(value) < 0.01:
        return f"{value:+.1e}" if sign else f"{value:.1e}"
    return f"{value:+.2f}" if sign else f"{value:.3f}"


def plot_modes(result, title: str | None = None, modes=None, columns: int | None = None):
    """Bar chart of each oscillatory mode's mass-weighted DOF participation.

    Parameters
    ----------
    result : ModalResult
    title : str, optional
    modes : sequence of int, optional
        The mode numbers drawn (as in ``result.to_dataframe()``, 1 = the lowest oscillatory
        mode); default every oscillatory mode.
    columns : int, optional
        Panels per row (default up to 3).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    oscillatory = np.nonzero(result.oscillatory)[0]
    numbers = list(range(1, len(oscillatory) + 1)) if modes is None else [int(n) for n in modes]
    modes = oscillatory[np.asarray(numbers, dtype=int) - 1]
    cols = max(1, min(columns or 3, len(modes)))
    rows = max(1, int(np.ceil(len(modes) / cols)))
    labels = _labels(result)
    width = 3.2 if len(labels) <= 6 else 0.35 * len(labels) + 1.0
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, 2.6 * rows), layout="constrained",
                             squeeze=False)
    for ax in axes.ravel()[len(modes):]:
        ax.set_visible(False)
    for number, ax, m in zip(numbers, axes.ravel(), modes):
        magnitude = np.abs(result.shapes[m])
        ax.bar(labels, magnitude / magnitude.max(), color="tab:blue")
        if len(labels) > 6:
            ax.tick_params(axis="x", labelrotation=90, labelsize="x-small")
        ax.set_title(f"mode {number}: {result.frequencies_hz[m]:.2f} Hz, ζ={small_number(result.damping_ratios[m])}\n"
                     f"{result.whirl[m]} (ratio {small_number(result.whirl_ratios[m], sign=True)})", fontsize="small")
        ax.set_ylim(0, 1.05)
    fig.suptitle(title or f"Mode shapes at {rpm_text(result.speed * 30 / np.pi)} rpm (|shape|, normalised)")
    return fig
