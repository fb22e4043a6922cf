"""Where the 3D mode view's sensor and excitation names stand against the drawn bodies.

Not a timing: a count over a fixed grid of views, measured on the rendered figure (the CLI's
``modes --shape N`` figure, 3D view and projections), independently of the placer in
``rotordyn_modal.plotting.shapes3d``: the names' glyph boxes (``Text.get_window_extent``), the
displaced bodies' edges as mplot3d projects the drawn lines, and each filled body's outline (the
convex hull of its projected edges: rotor cylinders, stator box). For every view it counts

* ``edge``: names whose box a displaced body's edge runs through (the count of issue 27 §3);
* ``outline``: names whose box overlaps a rotor's or the stator box's projected outline;
* ``overlap``: pairs of names whose boxes overlap; ``arrow``: names an arrow runs through;
* ``any line``: names any line drawn in the 3D view runs through (springs, orbits, spin arcs, the
  bodies at rest included);
* ``leader``: names drawn with a leader line; ``bad leader``: leaders that do not run from their
  name's box to their arrow's free end, or cross another name; ``leaders crossing``: pairs of
  leaders that cross; ``longest leader``: in name heights.

The grid: motor_pump_on_mounts modes 1, 2 at 0 and 3000 rpm, fan_on_bearings modes 2, 3 at
3000 rpm, each in the default view and turned to (elevation 15, azimuth -120); gear_machine modes
1, 3, 5 at 3000 rpm (15 views), and flexible_pump_on_mounts modes 1, 2 at 3000 rpm in both views
(4 more). Run::

    PYTHONPATH=. MPLBACKEND=Agg python benchmarks/bench_arrow_names.py [--png DIR]

``--png DIR`` also writes each view's figure there.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rotordyn_modal as rdm  # noqa: E402
from rotordyn_modal.analysis.mode_shapes import mode_shape_3d  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from label_geometry import arrow_segments, clip_segments, glyph_box  # noqa: E402

TURNED = (15, -120)
GRID = ([("motor_pump_on_mounts", mode, rpm, angles) for mode in (1, 2) for rpm in (0, 3000)
         for angles in (None, TURNED)]
        + [("fan_on_bearings", mode, 3000, angles) for mode in (2, 3) for angles in (None, TURNED)]
        + [("gear_machine", mode, 3000, None) for mode in (1, 3, 5)])
FLEXIBLE = [("flexible_pump_on_mounts", mode, 3000, angles) for mode in (1, 2) for angles in (None, TURNED)]


def projected(ax, points):
    """``points`` (n, 3) [m] as mplot3d projects them, in display pixels (n, 2)."""
    from mpl_toolkits.mplot3d import proj3d

    x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], ax.get_proj())
    return ax.transData.transform(np.column_stack([x, y]))


def drawn_bodies(ax, view):
    """Displaced edges (n, 4) [pixels] of every body, from the lines drawn with gid
    ``displaced:NAME``, and the outlines (convex hulls, matplotlib Paths) of the filled bodies
    (rotor cylinders, stator box) at the drawn phase (0), projected as the view stands."""
    from matplotlib.path import Path as PixelPath
    from scipy.spatial import ConvexHull

    edges = []
    for line in ax.get_lines():
        if str(line.get_gid()).startswith("displaced:"):
            points = projected(ax, np.column_stack([np.asarray(c, float) for c in line.get_data_3d()]))
            pairs = np.hstack([points[:-1], points[1:]])
            edges.append(pairs[np.all(np.isfinite(pairs), axis=1)])
    outlines = []
    for body, points in zip(view.outline.bodies, view.at_phase(0.0)):
        if body.kind in ("rotor", "stator"):
            flat = projected(ax, np.asarray(points, float))
            outlines.append(PixelPath(flat[ConvexHull(flat).vertices]))
    return np.concatenate(edges or [np.empty((0, 4))]), outlines


def free_end(ax, view, name, shaft):
    """The end [pixels] of an arrow's drawn shaft (x0, y0, x1, y1) away from its point (the point
    moved as drawn at phase 0, projected)."""
    k = next(k for k, arrow in enumerate(view.outline.arrows) if arrow.name == name)
    point = projected(ax, (view.outline.arrows[k].point + np.real(view.arrow_motion[k]))[None, :])[0]
    ends = shaft.reshape(2, 2)
    return ends[np.argmax(np.hypot(*(ends - point).T))]


def _crossing(a, b):
    """Whether the segments ``a`` and ``b`` (2, 2) cross (strictly inside both)."""
    r, t = a[1] - a[0], b[1] - b[0]
    denominator = r[0] * t[1] - r[1] * t[0]
    if denominator == 0:
        return False
    q = b[0] - a[0]
    u, v = (q[0] * t[1] - q[1] * t[0]) / denominator, (q[0] * r[1] - q[1] * r[0]) / denominator
    return bool(0 < u < 1 and 0 < v < 1)


def box_meets_outline(box, outline):
    """Whether the box (Bbox) and the convex outline (Path) overlap."""
    corners = np.array([[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1], [box.x0, box.y1]])
    if outline.intersects_bbox(box, filled=True):
        return True
    return bool(np.any(outline.contains_points(corners)))


def measure(example, mode, rpm, angles, png=None):
    model = rdm.load_model(ROOT / "examples" / f"{example}.toml")
    view = mode_shape_3d(rdm.modal(model, rdm.rpm(rpm)), model, mode)
    fig = view.plot()
    ax = fig.axes[0]
    if angles is not None:
        ax.view_init(*angles)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    names = {arrow.name for arrow in view.outline.arrows}
    boxes = {t.get_text(): glyph_box(t, renderer) for t in ax.texts if t.get_text() in names}
    edges, outlines = drawn_bodies(ax, view)
    arrows = arrow_segments(ax)
    counts = dict.fromkeys(("names", "edge", "outline", "any line", "overlap", "arrow", "leader", "bad leader",
                            "leaders crossing", "longest leader"), 0)
    counts["names"] = len(boxes)
    which = []
    drawn = [projected(ax, np.column_stack([np.asarray(c, float) for c in line.get_data_3d()]))
             for line in ax.get_lines() if hasattr(line, "get_data_3d")]
    lines = np.concatenate([np.hstack([p[:-1], p[1:]]) for p in drawn])
    lines = lines[np.all(np.isfinite(lines), axis=1)]
    for name, box in boxes.items():
        counts["any line"] += bool(len(clip_segments(lines, box.extents)))
        if len(clip_segments(edges, box.extents)):
            counts["edge"] += 1
            which.append(name)
        counts["outline"] += any(box_meets_outline(box, outline) for outline in outlines)
        counts["arrow"] += any(len(clip_segments(s, box.extents)) for s in arrows.values())
        counts["overlap"] += int(sum(other < name and box.overlaps(b) for other, b in boxes.items()))
    drawn_leaders = []
    for line in ax.get_lines():
        gid = str(line.get_gid())
        if gid.startswith("arrow-leader:") and line.get_visible():
            counts["leader"] += 1
            name = gid.split(":", 1)[1]
            ends = line.get_transform().transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
            box, free = boxes[name], free_end(ax, view, name, arrows[name][0])
            starts_at_name = box.padded(2.0).contains(*ends[0])
            others = [b for n, b in boxes.items() if n != name]
            crosses = any(len(clip_segments(np.hstack([ends[:-1], ends[1:]]), b.extents)) for b in others)
            counts["bad leader"] += not (starts_at_name and np.hypot(*(ends[-1] - free)) < 1.5) or crosses
            length = float(np.hypot(*(ends[-1] - ends[0]))) / box.height
            counts["longest leader"] = max(counts["longest leader"], round(length, 1))
            drawn_leaders.append(ends)
    for k, a in enumerate(drawn_leaders):
        for b in drawn_leaders[:k]:
            counts["leaders crossing"] += _crossing(a, b)
    if png is not None:
        tag = f"{example}-m{mode}-{rpm}rpm{'-turned' if angles else ''}"
        fig.savefig(Path(png) / f"{tag}.png", dpi=80)
    plt.close(fig)
    return counts, which


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--png", help="write each view's figure to this folder")
    args = parser.parse_args(argv)
    if args.png:
        Path(args.png).mkdir(parents=True, exist_ok=True)
    for title, grid in (("15 views (motor_pump, fan, gear)", GRID), ("4 views (flexible_pump)", FLEXIBLE)):
        print(title)
        rows = []
        for case in grid:
            counts, which = measure(*case, png=args.png)
            rows.append(counts)
            print(f"  {case[0]:24s} mode {case[1]} {case[2]:5d} rpm {str(case[3] or 'default'):10s} "
                  + " ".join(f"{k} {v}" for k, v in counts.items())
                  + (f"  on edges: {', '.join(which)}" if which else ""))
        total = {k: (max if k == "longest leader" else sum)(row[k] for row in rows) for k in rows[0]}
        print("  total: " + ", ".join(f"{k} {v}" for k, v in total.items()))

if __name__ == "__main__":
    main()
