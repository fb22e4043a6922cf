"""Mode shape figure: participation of each degree of freedom."""

from __future__ import annotations

import numpy as np
from ..units import rpm_text, unit_scale
from ._style import WHIRL_STYLE

__all__ = ["plot_modes"]

_DOF = ["u_x", "u_y", "u_z", "θ_x", "θ_y", "θ_z"]


#: a coordinate's last part as the bars' tick writes it (translation u [m], rotation θ [rad])
_COORDINATE = {"ux": "u_x", "uy": "u_y", "uz": "u_z", "rx": "θ_x", "ry": "θ_y", "rz": "θ_z"}


def _labels(result) -> list[str]:
    """Coordinate labels without their body (the group label names it): ``u_x`` ... ``θ_z``;
    a flexible rotor's node coordinates as ``n0.u_y``."""
    names = list(result.dof_names)
    if not names:
        return list(_DOF)
    out = []
    for name in names:
        parts = name.split(".")[1:] or [name]
        out.append(".".join(parts[:-1] + [_COORDINATE.get(parts[-1], parts[-1])]))
    return out


def _groups(result) -> list[tuple[str, int, int]]:
    """``[(label, first, stop), ...]``: each body's run of coordinates (``dof_names[first:stop]``)
    and its label, the body's name; the stator's (or a stator-less model's carrier, ``frame``)
    also names the rotors without coordinates of their own (rotors without bearings, rigidly
    attached to it and moving with it). Empty without coordinate names."""
    bodies = [name.split(".")[0] for name in result.dof_names if "." in name]
    if len(bodies) != len(result.dof_names):
        return []
    groups = []
    for k, body in enumerate(bodies):
        if groups and groups[-1][0] == body:
            groups[-1][2] = k + 1
        else:
            groups.append([body, k, k + 1])
    attached = [r for r in getattr(result, "rotor_names", ()) if r not in bodies]
    labels = []
    for body, first, stop in groups:
        if attached and body in ("stator", "frame"):
            body = f"{body} (with {', '.join(attached)} attached)"
        labels.append((body, first, stop))
    return labels


def _name_bodies(ax, groups, count: int) -> None:
    """Write each body's name above its bars (a secondary x axis at the top, one label per
    group) and part the groups by thin vertical lines."""
    if not groups:
        return
    top = ax.secondary_xaxis("top")
    top.set_xticks([(first + stop - 1) / 2 for _, first, stop in groups], [label for label, _, _ in groups],
                   fontsize="x-small" if count > 6 else "small")
    top.tick_params(axis="x", length=0, pad=2)
    for _, first, _ in groups[1:]:
        ax.axvline(first - 0.5, color="0.6", linewidth=0.8, linestyle=":")


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


def _translation_scale(result, units: str):
    """Each coordinate's factor from SI to ``units``: a translation's (``u_x`` ...) the length
    unit's, a rotation's 1 (radians in both systems)."""
    factor = unit_scale("length", units)[0]
    return np.array([factor if label.rpartition(".")[2].startswith("u_") else 1.0 for label in _labels(result)])


#: by default a chart of panels with more than this many bars draws the lowest modes only, this
#: many of them; panels per row as many as fit this width [inches] (at least one)
_WIDE_BARS, _FIRST_WIDE, _WIDEST = 24, 6, 24.0


def plot_modes(result, title: str | None = None, modes=None, columns: int | None = None, units: str = "si",
               max_width: float | None = None):
    """Bar chart of each oscillatory mode's coordinates: ``|shape|`` (translations in m, or in in
    with ``units='us'``; rotations in rad) divided by the mode's largest, grouped by body (each group named above
    its bars; the stator's names the rotors rigidly attached to it), titled with the whirl in
    the words of the report's modes table ("forward whirl", "backward whirl", "no whirl").

    Parameters
    ----------
    result : ModalResult
    title : str, optional
    modes : sequence of int, optional
        The mode numbers drawn (as in ``result.to_dataframe()``, 1 = the lowest oscillatory
        mode); default every oscillatory mode, or the lowest :data:`_FIRST_WIDE` where a panel
        has more than :data:`_WIDE_BARS` bars (a flexible rotor's node coordinates: the title
        says so).
    columns : int, optional
        Panels per row (default up to 3, as many as fit ``max_width``).
    units : {'si', 'us'}
        Unit of the translations before the division (docs/units.md): m (SI) or in (US
        customary). A mode that both translates and rotates has other bars in either: a
        translation of 0.0254 m is 1 in, its bar 39.37 times as high against a rotation's.
    max_width : float, optional
        Widest the default columns make the figure [in] (default :data:`_WIDEST`): a page that
        shrinks a wider figure shrinks its bar labels with it (the report: 10 in, one panel a row
        for a 16-coordinate machine, whose two panels at 13 in made its labels 8 px high).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    oscillatory = np.nonzero(result.oscillatory)[0]
    labels = _labels(result)
    # compressor_rotor's 53 modes of 56 node coordinates drew 53 panels 20 inches wide, three a
    # row: a figure of 59 x 47 inches
    shown = len(oscillatory) if modes is not None or len(labels) <= _WIDE_BARS else min(len(oscillatory), _FIRST_WIDE)
    numbers = list(range(1, shown + 1)) if modes is None else [int(n) for n in modes]
    modes = oscillatory[np.asarray(numbers, dtype=int) - 1]
    groups = _groups(result)
    width = 3.2 if len(labels) <= 6 else 0.35 * len(labels) + 1.0
    widest = _WIDEST if max_width is None else max_width
    cols = max(1, min(columns or max(1, min(3, int(widest // width))), len(modes)))
    rows = max(1, int(np.ceil(len(modes) / cols)))
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, 2.6 * rows), layout="constrained",
                             squeeze=False)
    for ax in axes.ravel()[len(modes):]:
        ax.set_visible(False)
    scale = _translation_scale(result, units)
    for number, ax, m in zip(numbers, axes.ravel(), modes):
        magnitude = np.abs(result.shapes[m]) * scale
        ax.bar(np.arange(len(labels)), magnitude / magnitude.max(), color="tab:blue", tick_label=labels)
        if len(labels) > 6:
            ax.tick_params(axis="x", labelrotation=90, labelsize="small")
        ax.set_title(f"mode {number}: {result.frequencies_hz[m]:.2f} Hz, ζ={small_number(result.damping_ratios[m])}\n"
                     f"{WHIRL_STYLE[result.whirl[m]]['label']} (ratio {small_number(result.whirl_ratios[m], sign=True)})",
                     fontsize="small")
        ax.set_ylim(0, 1.05)
        _name_bodies(ax, groups, len(labels))
        if ax.get_subplotspec().is_first_col():
            ax.set_ylabel(f"|u| [{unit_scale('length', units)[1]}], |θ| [rad]\n÷ the mode's largest", fontsize="small")
    fig.suptitle((title or f"Mode shapes at {rpm_text(result.speed * 30 / np.pi)} rpm (|shape|, normalised)")
                 + (f"\nmodes 1\u2013{shown} of {len(oscillatory)} (modes=[...] draws others; plot_shaft_lines "
                    "draws a flexible rotor's shaft)" if shown < len(oscillatory) else ""))
    return fig
