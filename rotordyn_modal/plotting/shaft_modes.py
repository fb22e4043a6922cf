"""Mode shapes as deflected shaft lines along the axis: one panel per mode, both planes.

Draws :class:`~rotordyn_modal.analysis.mode_shapes.ShaftLines` (the analysis computes the
lines; nothing is computed here). In each panel every rotor has its colour: the plane ``a``
solid, the plane ``b`` dashed (both at phase 0, the drawing's ``Re(u)``), the band of its whirl
orbits' largest excursion shaded, the undeformed axis thin grey, its nodes as ticks on the
axis, its bearings as triangles below, its disks as bars across the axis (height growing with
the disk's mass); the names of disks and bearings in the rotor's colour (darkened), names at one
axial position (two rotors side by side) moved apart along the axis when the figure is drawn. Every artist carries a gid (``line-a:ROTOR``, ``bearing:ROTOR:NAME``,
``disk:ROTOR:NAME``, ``nodes:ROTOR``, ...) so tests can find it.
"""

from __future__ import annotations

import numpy as np

from ..units import unit_scale
from ._labels import column_positions, draw_time_layout
from .modes import small_number
from ..units import rpm_text

__all__ = ["plot_shaft_modes"]

_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan")
#: where the bearings' triangles stand (normalised displacement units)
_BEARING_Y = -1.32
#: half-heights of the lightest and of the heaviest disk's bar
_DISK_HALF = (0.12, 0.45)


def plot_shaft_modes(views, title: str | None = None, relative: bool = False, columns: int | None = None,
                     units: str = "si"):
    """The deflected shaft lines of several modes, one panel each.

    Parameters
    ----------
    views : sequence of ShaftLines
        One per mode (:func:`rotordyn_modal.analysis.mode_shapes.shaft_lines`).
    title : str, optional
        The figure's title; default the speed.
    relative : bool
        Draw the rotors' motion relative to the stator (the bending and the bearings'
        deflection, without the casing's motion) instead of the absolute motion, scaled so that
        its largest in each panel is 1.
    columns : int, optional
        Panels per row (default 1 for up to 3 modes, else 2).
    units : {'si', 'us'}
        Unit system of the positions along the axis: m, or in (docs/units.md).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    views = list(views)
    if not views:
        raise ValueError("plot_shaft_modes: no mode to draw")
    cols = columns or (1 if len(views) <= 3 else 2)
    rows = int(np.ceil(len(views) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(7.0 * cols, 2.9 * rows + 0.6), layout="constrained",
                             squeeze=False, sharex=True)
    for ax in axes.ravel()[len(views):]:
        ax.set_visible(False)
    colours = {line.rotor: _COLOURS[i % len(_COLOURS)] for i, line in enumerate(views[0].lines)}
    factor, unit = unit_scale("length", units)
    for ax, view in zip(axes.ravel(), views):
        _panel(ax, view, colours, relative, factor)
    for ax in axes[-1]:
        ax.set_xlabel(f"position along {views[0].axis_names[2]} [{unit}]")
    for ax in axes[:, 0]:
        ax.set_ylabel("displacement (normalised)")
    _legend(fig, views[0], colours, 5 if cols > 1 else 3)
    speed = views[0].speed * 30 / np.pi
    what = "relative to the casing, largest = 1 in each panel" if relative else "absolute, largest = 1"
    fig.suptitle(title or f"Deflected shaft lines at {rpm_text(speed)} rpm ({what})", fontsize="medium")
    return fig


def _panel(ax, view, colours, relative, factor=1.0):
    """One mode's panel; positions along the axis drawn times ``factor`` (the unit system's)."""
    heaviest = max([mass for line in view.lines for _, _, mass in line.disks] or [1.0])
    # relative motions share the absolute lines' factor (the casing may carry most of the mode):
    # drawn with the largest of the panel at 1
    largest = max(float(np.abs(line.relative).max(initial=0.0)) for line in view.lines) if relative else 1.0
    disk_names, bearing_names, top = [], [], 1.0
    for line in view.lines:
        c = colours[line.rotor]
        u = line.relative / (largest or 1.0) if relative else line.displacement
        z = line.position * factor
        ax.plot([z[0], z[-1]], [0.0, 0.0], color="0.6", linewidth=0.8, gid=f"axis:{line.rotor}")
        reach = line.relative_excursion / (largest or 1.0) if relative else line.excursion
        ax.fill_between(z, -reach, reach, color=c, alpha=0.12, linewidth=0, gid=f"envelope:{line.rotor}")
        ax.plot(z, u[0].real, color=c, linewidth=1.6, gid=f"line-a:{line.rotor}")
        ax.plot(z, u[1].real, color=c, linewidth=1.3, linestyle="--", gid=f"line-b:{line.rotor}")
        if line.flexible:
            ax.plot(line.node_position * factor, np.zeros(len(line.node_position)), linestyle="none", marker="|",
                    markersize=5, color="0.35", gid=f"nodes:{line.rotor}")
        for name, position, mass in line.disks:
            position = position * factor
            half = _DISK_HALF[0] + (_DISK_HALF[1] - _DISK_HALF[0]) * (mass / heaviest) ** (1 / 3)
            ax.plot([position, position], [-half, half], color=c, linewidth=4.5, alpha=0.45,
                    solid_capstyle="butt", gid=f"disk:{line.rotor}:{name}")
            disk_names.append((name, position, c))
        top = max(top, float(reach.max(initial=0.0)), float(np.abs(u.real).max(initial=0.0)))
        for name, position in line.bearings:
            position = position * factor
            ax.plot([position], [_BEARING_Y], linestyle="none", marker="^", markersize=8, color=c,
                    markeredgecolor="k", markeredgewidth=0.6, gid=f"bearing:{line.rotor}:{name}")
            bearing_names.append(ax.annotate(name, (position, _BEARING_Y), xytext=(0, -9), textcoords="offset points",
                                             ha="center", va="top", fontsize="xx-small", color=_darker(c),
                                             annotation_clip=False, gid=f"bearing-name:{line.rotor}:{name}"))
    # the disks' names in a strip above every line and band (a name on the lines hides them),
    # each straight above its disk's bar
    name_y = top + 0.08
    names = [ax.annotate(name, (position, name_y), xytext=(0, 0), textcoords="offset points", ha="center",
                         va="bottom", fontsize="xx-small", color=_darker(c), gid=f"disk-name:{name}")
             for name, position, c in disk_names]
    # names at one axial position (two rotors' disks or bearings side by side) move apart
    # along the axis each time the panel is drawn, in the order of their positions
    for row in (names, bearing_names):
        if len(row) > 1:
            ax.add_artist(draw_time_layout(lambda renderer, row=row: _spread(ax, row, renderer)))
    ax.set_ylim(-1.6, name_y + 0.3 if disk_names else max(1.25, top + 0.1))
    ax.axhline(0.0, color="0.85", linewidth=0.5, zorder=0)
    whirl = f"{view.whirl} whirl" if view.whirl != "none" else "no whirl"
    if not view.lateral:
        whirl = "no lateral motion (an axial or torsional mode)"
    # as the bars' titles: '0.000' hid a damping of 1e-4 (and '0.0000' in the 3-D view's title 1.7e-8)
    ax.set_title(f"mode {view.mode}: {view.frequency_hz:.2f} Hz, ζ = {small_number(view.damping_ratio)}, {whirl}",
                 fontsize="small")
    ax.tick_params(labelsize="small")


def _darker(colour):
    """A rotor's colour, darkened for small text on white (its name reads as the rotor's)."""
    from matplotlib.colors import to_rgb

    return tuple(0.6 * c for c in to_rgb(colour))


def _spread(ax, names, renderer):
    """Move the names of one row (annotations centred above or below their positions) apart
    along the axis, each as near its own position as the others leave room for
    (:func:`~rotordyn_modal.plotting._labels.column_positions`), 3 points between neighbours."""
    from matplotlib.text import Text

    per_point = renderer.points_to_pixels(1.0)
    anchors = np.array([ax.transData.transform(name.xy)[0] for name in names])
    widths = np.array([Text.get_window_extent(name, renderer).width for name in names])
    frame = ax.get_window_extent(renderer)
    centres = column_positions(anchors, widths, frame.x0, frame.x1, gap=3.0 * per_point)
    for name, centre, anchor in zip(names, centres, anchors):
        offset = ((centre - anchor) / per_point, name.xyann[1])
        if not np.allclose(offset, name.xyann):
            name.xyann = offset


def _legend(fig, view, colours, columns):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    a, b, _ = view.axis_names
    handles = [Line2D([], [], color="0.2", linewidth=1.6, label=f"u_{a} (phase 0)"),
               Line2D([], [], color="0.2", linewidth=1.3, linestyle="--", label=f"u_{b} (phase 0)"),
               Patch(color="0.2", alpha=0.15, label="orbit's largest excursion")]
    handles += [Line2D([], [], color=colours[line.rotor], linewidth=3,
                       label=f"{line.rotor} ({'flexible' if line.flexible else 'rigid'})") for line in view.lines]
    present = [any(line.bearings for line in view.lines), any(line.disks for line in view.lines),
               any(line.flexible for line in view.lines)]
    markers = [Line2D([], [], linestyle="none", marker="^", color="0.6", markeredgecolor="k", label="bearing"),
               Line2D([], [], color="0.5", linewidth=4.5, alpha=0.45, label="disk (height ~ mass^1/3)"),
               Line2D([], [], linestyle="none", marker="|", color="0.35", label="node")]
    handles += [handle for handle, shown in zip(markers, present) if shown]
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), columns), fontsize="small",
               frameon=False)
