"""The static sag, shear force and bending moment diagram of flexible shafts.

Draws :class:`~rotordyn_modal.analysis.shaft_statics.ShaftStatics` (the analysis computes the
stations; nothing is computed here): per flexible rotor a column of three panels sharing the
axis along the spin axis, the sag relative to the stator, the shear force and the bending
moment, each in both planes (plane ``e-a``: ``u_a`` and its shear force and bending moment,
solid; plane ``e-b``, dashed; bending moments ``E I u''``, sagging positive), with the bearings
(triangles), disks (bars) and point loads (red marks) marked on every panel. A node with a point
load has two stations, so the shear force steps there. Every artist carries a gid
(``sag-a:ROTOR``, ``shear-b:ROTOR``, ``moment-a:ROTOR``, ``bearing:ROTOR:NAME``,
``disk:ROTOR:NAME``, ``load:ROTOR:SOURCE``) so tests can find it.
"""

from __future__ import annotations

import numpy as np

from ..units import unit_scale

__all__ = ["plot_shaft_statics", "statics_scales"]

#: the two planes' look: plane e-a (u_a, its shear force and bending moment), plane e-b
_PLANES = ({"color": "tab:blue", "linestyle": "-", "linewidth": 1.6},
           {"color": "tab:orange", "linestyle": "--", "linewidth": 1.6})


def statics_scales(units: str = "si") -> dict:
    """``(factor, unit)`` of each quantity the shaft statics show (figure and terminal): an SI
    value times ``factor`` is the number shown in ``unit``. Keys ``sag`` (µm, not metres that
    would read 3e-05; mil), ``shear`` (N; lbf), ``moment`` (N m; lbf in), ``length`` (m; in) and
    ``stress`` (MPa; psi)."""
    return {"sag": (1e6, "µm") if units == "si" else unit_scale("displacement", units),
            "shear": unit_scale("force", units), "moment": unit_scale("moment", units),
            "length": unit_scale("length", units),
            "stress": (1e-6, "MPa") if units == "si" else unit_scale("pressure", units)}


def plot_shaft_statics(shafts, title: str | None = None, units: str = "si"):
    """Sag, shear force and bending moment along each flexible rotor's shaft.

    Parameters
    ----------
    shafts : sequence of ShaftStatics
        One column of panels each (``StaticResult.shafts.values()``).
    title : str, optional
    units : {'si', 'us'}
        Unit system of the axes: µm, N, N m (SI) or mil, lbf, lbf in (US customary); positions
        along the axis in m or in.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    shafts = list(shafts)
    if not shafts:
        raise ValueError("plot_shaft_statics: no flexible rotor to draw")
    scales = statics_scales(units)
    fig, axes = plt.subplots(3, len(shafts), figsize=(7.2 * len(shafts), 8.2), layout="constrained",
                             squeeze=False, sharex="col")
    for column, shaft in zip(axes.T, shafts):
        _column(column, shaft, scales)
    _legend(fig, shafts)
    # the derivative along the shaft's own axis (dM/dz read as the transverse z of the x-z plane)
    along = {shaft.axis_names[2] for shaft in shafts}
    along = along.pop() if len(along) == 1 else "s"
    fig.suptitle(title or "Static sag, shear force and bending moment along the shaft\n"
                 f"(V = dM/d{along}: force of the part before the cut on the part beyond; M sagging positive)",
                 fontsize="medium")
    _clear_notes(fig)
    return fig


def _clear_notes(fig):
    """Move each largest-value note to the first corner of its point where no curve runs under
    its box (it hid the moment line rising from its largest), else centred above or below it
    (under an arch's top, where the curve falls away on both sides: the compressor on journals'
    moment, 536 N m, hid the line falling from it at every corner)."""
    import matplotlib.text

    from ._labels import CurveMap, laid_out_renderer

    renderer = laid_out_renderer(fig)
    for ax in fig.axes:
        notes = [t for t in ax.texts if t.get_gid() == "largest-note"]
        if not notes:
            continue
        # the disks' bands are pale background marks, notes may stand on them
        curves = CurveMap(ax, renderer, skip=[line for line in ax.get_lines()
                                              if str(line.get_gid()).startswith("disk:")])
        frame = ax.get_window_extent(renderer)
        for note in notes:
            point = ax.transData.transform(note.xy)
            keep = (point[0] - 6, point[1] - 6, point[0] + 6, point[1] + 6)     # its own point and curve
            near = [(8, 8), (8, -8), (-8, 8), (-8, -8)]
            far = [(sx * dx, sy * dy) for dx in (30, 60, 100, 150) for dy in (16, 40, 70) for sx in (1, -1)
                   for sy in (1, -1)]
            centred = [(0, sy * dy) for dy in (24, 40, 70, 100) for sy in (-1, 1)]
            for dx, dy in near + far + centred:
                side = "center" if dx == 0 else "left" if dx > 0 else "right"
                note.set(position=(dx, dy), ha=side, va="bottom" if dy > 0 else "top")
                box = matplotlib.text.Text.get_window_extent(note, renderer).padded(3.0)   # its rounded box
                inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
                corner = (0.5 * (box.x0 + box.x1) if dx == 0 else box.x0 if dx > 0 else box.x1,
                          box.y0 if dy > 0 else box.y1)
                if inside and curves.free((box.x0, box.y0, box.x1, box.y1), keep=keep) \
                        and ((dx, dy) in near or curves.crossings(tuple(point), corner, keep=keep) == 0):
                    if (dx, dy) not in near:       # away from its point: a leader line to it
                        ax.annotate(note.get_text(), note.xy, xytext=(dx, dy), textcoords="offset points",
                                    fontsize=note.get_fontsize(), ha=note.get_ha(), va=note.get_va(),
                                    gid="largest-note", bbox=_NOTE_BOX,
                                    arrowprops={"arrowstyle": "-", "color": "0.5", "linewidth": 0.6,
                                                "shrinkA": 0, "shrinkB": 3,
                                                "relpos": (0.5 if dx == 0 else 0.0 if dx > 0 else 1.0,
                                                           0.0 if dy > 0 else 1.0)})
                        note.remove()
                    break
            else:
                note.set(position=(8, -8 if note.xy[1] > 0 else 8), ha="left", va="top" if note.xy[1] > 0 else "bottom")


def _column(axes, shaft, scales):
    e = shaft.axis_names[2]
    length_scale, length_unit = scales["length"]
    x = shaft.position * length_scale
    rows = (("sag", shaft.sag, "sag relative to the stator"), ("shear", shaft.shear, "shear force"),
            ("moment", shaft.moment, "bending moment"))
    for ax, (kind, values, what) in zip(axes, rows):
        scale, unit = scales[kind]
        closed = kind != "sag"       # section forces drop to 0 beyond the shaft's ends
        for plane, style in enumerate(_PLANES):
            xs, ys = (np.r_[x[0], x, x[-1]], np.r_[0.0, values[:, plane] * scale, 0.0]) if closed else \
                (x, values[:, plane] * scale)
            ax.plot(xs, ys, gid=f"{kind}-{'ab'[plane]}:{shaft.rotor}", **style)
        ax.axhline(0.0, color="0.6", linewidth=0.8, zorder=0)
        ax.set_ylabel(f"{what} [{unit}]", fontsize="small")
        ax.tick_params(labelsize="small")
        _marks(ax, shaft, length_scale)
    if not (np.any(shaft.sag) or np.any(shaft.shear) or np.any(shaft.moment)):
        # zeros everywhere read as a shaft that carries its loads without bending: say there are none
        axes[1].text(0.5, 0.5, "no static load on this shaft\n(the model has no gravity and no given force)",
                     transform=axes[1].transAxes, ha="center", va="center", fontsize="medium", gid="no-load-note",
                     bbox=dict(boxstyle="round", facecolor="white", edgecolor="0.6"))
    else:
        _mark_largest(axes[0], shaft, "sag", scales["sag"], x)
        _mark_largest(axes[2], shaft, "moment", scales["moment"], x, scales["stress"])
    axes[0].set_title(f"rotor {shaft.rotor}", fontsize="small")
    axes[-1].set_xlabel(f"position along {e} [{length_unit}]")


def _marks(ax, shaft, length_scale):
    """Bearings (triangles on the zero line), disks (bars across it), point loads (arrows)."""
    for name, position in shaft.bearings:
        ax.plot([position * length_scale], [0.0], linestyle="none", marker="^", markersize=9, color="0.55",
                markeredgecolor="k", markeredgewidth=0.6, zorder=3, gid=f"bearing:{shaft.rotor}:{name}")
    for name, position, _ in shaft.disks:
        ax.axvline(position * length_scale, color="tab:green", linewidth=4.0, alpha=0.25, zorder=0,
                   gid=f"disk:{shaft.rotor}:{name}")
    for _, source, position in shaft.loads:
        ax.plot([position * length_scale], [0.0], linestyle="none", marker="v", markersize=7, color="tab:red",
                zorder=3, gid=f"load:{shaft.rotor}:{source}")
    if ax.get_subplotspec().is_first_row():
        _name_marks(ax, shaft, length_scale)


def _name_marks(ax, shaft, length_scale):
    """The bearings' and disks' names as ticks of an axis along the first panel's top edge:
    outside the panel, where no curve runs through them (inside, the sag ran through them)."""
    marks = sorted([(position * length_scale, name, "0.25") for name, position in shaft.bearings]
                   + [(position * length_scale, name, "tab:green") for name, position, _ in shaft.disks])
    if not marks:
        return
    top = ax.secondary_xaxis("top")
    top.set_xticks([x for x, _, _ in marks], [name for _, name, _ in marks])
    top.tick_params(labelsize="xx-small", length=3, pad=1)
    for label, (_, _, colour) in zip(top.get_xticklabels(), marks):
        label.set_color(colour)


_NOTE_BOX = {"boxstyle": "round,pad=0.2", "facecolor": "white", "edgecolor": "0.7", "alpha": 0.9}


def _mark_largest(ax, shaft, quantity, scale_unit, x, stress=None):
    """The station of the largest magnitude, its value written beside it (and the largest
    bending stress on the moment panel)."""
    scale, unit = scale_unit
    value, i = shaft.largest(quantity)
    if not value > 0:
        return
    components = shaft.sag if quantity == "sag" else shaft.moment
    y = components[i, int(np.argmax(np.abs(components[i])))] * scale
    text = f"|{'u' if quantity == 'sag' else 'M'}| = {value * scale:.3g} {unit} at {shaft.label(i, quantity)}"
    if stress is not None:
        peak, j = shaft.largest("stress")
        text += f"\nlargest bending stress {peak * stress[0]:.3g} {stress[1]} at {shaft.label(j, 'stress')}"
    ax.plot([x[i]], [y], marker="o", markersize=5, color="k", linestyle="none", gid=f"largest-{quantity}:{shaft.rotor}")
    ax.annotate(text, (x[i], y), xytext=(8, -8 if y > 0 else 8), textcoords="offset points", fontsize="x-small", gid="largest-note",
                va="top" if y > 0 else "bottom", ha="left" if x[i] < 0.5 * (x[0] + x[-1]) else "right",
                bbox=_NOTE_BOX)


def _legend(fig, shafts):
    from matplotlib.lines import Line2D

    a, b, e = shafts[0].axis_names
    handles = [Line2D([], [], label=f"plane {e}-{a}: u_{a}, V_{a}, M = E I u_{a}''", **_PLANES[0]),
               Line2D([], [], label=f"plane {e}-{b}: u_{b}, V_{b}, M = E I u_{b}''", **_PLANES[1]),
               Line2D([], [], linestyle="none", marker="^", color="0.55", markeredgecolor="k", label="bearing"),
               Line2D([], [], color="tab:green", linewidth=4.0, alpha=0.25, label="disk"),
               Line2D([], [], linestyle="none", marker="v", color="tab:red", label="point load")]
    present = [True, True, any(s.bearings for s in shafts), any(s.disks for s in shafts), any(s.loads for s in shafts)]
    handles = [h for h, shown in zip(handles, present) if shown]
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 3), fontsize="small",
               frameon=False)
