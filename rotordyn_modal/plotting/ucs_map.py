"""The undamped critical speed map: critical speeds against bearing stiffness, log-log."""

from __future__ import annotations

import numpy as np

from ._style import new_figure

__all__ = ["plot_ucs_map"]

_MODE_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive",
                 "tab:cyan")
_BEARING_COLOURS = ("0.15", "tab:red", "0.45", "darkgoldenrod", "teal", "indigo")


def plot_ucs_map(result, title: str | None = None, ax=None):
    """Forward critical speeds of the first modes against the chosen bearings' stiffness.

    Log-log axes: bearing stiffness [N/m] across, speed [rpm] up. Each mode is a coloured line
    labelled at its right end, its rigid-support asymptote (the chosen bearings radially rigid)
    a dotted line of its colour beyond the sweep's end. Each bearing's own stiffness over speed is
    drawn over it (``Kxx`` solid, ``Kyy`` dashed; a constant bearing as vertical lines, bearings
    of equal stiffness named together), with its crossings with the modes marked and their speeds
    written beside them; the operating speed range is a grey band.

    Parameters
    ----------
    result : UcsMap
    title : str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = new_figure(ax, figsize=(8.5, 6.0))
    rpm = result.speeds_rpm
    k = result.stiffness
    for j in range(rpm.shape[1]):
        if not np.isfinite(rpm[:, j]).any():
            continue
        colour = _MODE_COLOURS[j % len(_MODE_COLOURS)]
        # points too: where a mode's whirl turns (a stator's elliptic modes) the n-th forward
        # critical speed passes from one mode to another between two stiffness values
        ax.plot(k, rpm[:, j], color=colour, linewidth=1.8, marker=".", markersize=4)
        _label_right_end(ax, k, rpm[:, j], f"{j + 1}", colour)
    ax.set_xscale("log")
    ax.set_yscale("log")
    limits = _speed_limits(rpm, result)
    ax.set_ylim(*limits)
    ax.set_xlim(k[0], k[-1])
    _draw_asymptotes(ax, result, limits)
    _draw_bearings(ax, result)
    _draw_crossings(ax, result, limits)
    if result.operating is not None:
        low, high = (s * 30 / np.pi for s in result.operating)
        ax.axhspan(low, high, color="0.6", alpha=0.25, zorder=0.5, label="operating range")
    ax.grid(True, which="both", alpha=0.25)
    ax.set_xlabel("Bearing radial stiffness, each chosen bearing [N/m]")
    ax.set_ylabel("Undamped critical speed (forward, 1X of the reference rotor) [rpm]")
    ax.set_title(title or (f"Undamped critical speed map: {result.title}" if result.title
                           else "Undamped critical speed map"), fontsize="medium")
    ax.legend(fontsize="x-small", loc="upper left", frameon=True, framealpha=0.85)
    return fig


def _speed_limits(rpm, result):
    """Speed axis: the map's finite speeds (and the crossings, the operating band), a margin."""
    values = [rpm[np.isfinite(rpm) & (rpm > 0)]]
    values.append(np.array([c.speed for c in result.crossings]) * 30 / np.pi)
    if result.operating is not None:
        values.append(np.array(result.operating) * 30 / np.pi)
    values = np.concatenate(values)
    values = values[np.isfinite(values) & (values > 0)]
    if not values.size:
        return 1.0, 1e4
    return values.min() / 1.5, values.max() * 1.5


def _label_right_end(ax, k, rpm, text, colour):
    finite = np.nonzero(np.isfinite(rpm))[0]
    if finite.size:
        last = finite[-1]
        ax.annotate(f"mode {text}", (k[last], rpm[last]), xytext=(4, 0), textcoords="offset points",
                    color=colour, fontsize="small", va="center", ha="left", annotation_clip=False)


def _draw_asymptotes(ax, result, limits):
    """The rigid-support speeds: short dotted lines at the right edge, in each mode's colour."""
    if result.rigid_speeds is None:
        return
    for j, speed in enumerate(result.rigid_speeds * 30 / np.pi):
        if np.isfinite(speed) and limits[0] <= speed <= limits[1]:
            ax.axhline(speed, xmin=0.82, xmax=1.0, color=_MODE_COLOURS[j % len(_MODE_COLOURS)], linestyle=":",
                       linewidth=1.2, label="rigid supports" if j == 0 else None)


def _draw_bearings(ax, result):
    """Each bearing's Kxx (solid) and Kyy (dashed) over speed; constant ones as vertical lines,
    one line per distinct stiffness with the bearings' names together."""
    vertical: dict = {}
    drawn: list = []          # [(curve, names)]: curves of equal values drawn once
    colours = iter(_BEARING_COLOURS * 4)
    for curve in result.curves:
        if curve.constant:
            for axis, value in (("xx", curve.kxx[0]), ("yy", curve.kyy[0])):
                vertical.setdefault(float(value), []).append((curve.name, axis))
            continue
        same = next((names for other, names in drawn if _equal(other, curve)), None)
        if same is not None:
            same.append(curve.name)
        else:
            drawn.append((curve, [curve.name]))
    for curve, names in drawn:
        colour = next(colours)
        rpm = curve.speeds * 30 / np.pi
        ax.plot(curve.kxx, rpm, color=colour, linewidth=1.3, label=f"{', '.join(names)} Kxx")
        ax.plot(curve.kyy, rpm, color=colour, linewidth=1.3, linestyle="--", label=f"{', '.join(names)} Kyy")
    for value, owners in sorted(vertical.items()):
        names = list(dict.fromkeys(name for name, _ in owners))
        axes = "/".join(sorted({axis for _, axis in owners}))
        ax.axvline(value, color=next(colours), linewidth=1.3, linestyle="-.",
                   label=f"{', '.join(names)} K{axes} = {value:.3g} N/m")


def _equal(a, b) -> bool:
    return (a.speeds.shape == b.speeds.shape and np.array_equal(a.speeds, b.speeds)
            and np.array_equal(a.kxx, b.kxx) and np.array_equal(a.kyy, b.kyy))


def _draw_crossings(ax, result, limits):
    """A marker at every crossing (once per point), its speed written beside it."""
    seen, written = set(), []
    for crossing in result.crossings:
        rpm = crossing.speed * 30 / np.pi
        key = (round(np.log(crossing.stiffness), 9), round(np.log(rpm), 9))
        if key in seen or not limits[0] <= rpm <= limits[1]:
            continue
        seen.add(key)
        ax.plot(crossing.stiffness, rpm, "o", markersize=6, markerfacecolor="white", markeredgecolor="k", zorder=5)
        here = np.log10([crossing.stiffness, rpm])
        if any(np.all(np.abs(here - other) < _TEXT_APART) for other in written):
            continue              # a number already written next to it (several close bearings)
        written.append(here)
        ax.annotate(f"{rpm:.0f}", (crossing.stiffness, rpm), xytext=(5, -10), textcoords="offset points",
                    fontsize="x-small", zorder=6)


#: a crossing's speed is written unless one is written within this (decades of stiffness, of speed)
_TEXT_APART = np.array([0.3, 0.05])
