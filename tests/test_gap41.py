"""Campbell leader lines that touch another label's text (issue 27 §3, "no overprinted text").

On 047f8b0b ``campbell unstable_cross_coupled.toml --speeds 0:12000:13 --orders 1,2 --speed-unit
hz`` drew '11.8''s leader 0.24 points over the top of the '10.9' label, and motor_fan_minimal in
Hz drew '7.01''s leader 0.3 points under '8.76', whose own leader (1.4 points long, its label
2.6 points above its circle) ran back from the label's edge into its own text. The 20-rotor
gear chain (0-4500 rpm, 22 speeds, saved at 150 dpi) ran the leader of its order key
'1X mesh:r006-r007' 0.24 points under the key '1X mesh:r004-r005', which stands above its exit.

Measured on the drawn figure (150 dpi, as the command line saves it), independently of the
placer: the leaders are the figure's visible ``critical-leader``, ``mode-leader`` and
``order-key-leader`` lines, the
texts every visible text of the axes (critical-speed, order-line and mode labels, the note) by
its glyph box (``Text.get_window_extent``), all in display points; the distance of a segment
from a box is exact geometry (``label_geometry.segment_box_distance``).

Every leader keeps :data:`GAP_POINTS` from every other text's box: the 0.5-point line then
leaves about 0.75 point of white (1.5 pixels at 150 dpi) outside the box, whose top lies at the
digits' tops; at half a point the eye closes the one pixel left. It runs inside its own
label's box for no more than :data:`INSIDE_POINTS` (it starts on the box's edge).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest

import rotordyn_modal as rdm
from label_geometry import glyph_box, leader_lines, length_inside, segment_box_distance

matplotlib.use("Agg")

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

GAP_POINTS = 1.0
INSIDE_POINTS = 0.1

#: (example, speeds [rpm], speed unit): the fewest speeds that drew the leaders above on 047f8b0b
CASES = [("unstable_cross_coupled.toml", np.linspace(0.0, 12000.0, 13), "hz"),
         ("motor_fan_minimal.toml", np.linspace(0.0, 3600.0, 13), "hz")]


def test_segment_box_distance_is_the_least_distance_of_the_segment_s_points():
    """The helper against dense sampling of the segment (each point's distance from the box by
    its coordinates' overshoot), for random segments beside, across and inside a box."""
    rng = np.random.default_rng(41)
    box = (2.0, 1.0, 5.0, 3.0)
    for segment in rng.uniform(-2.0, 9.0, size=(60, 4)):
        t = np.linspace(0.0, 1.0, 10001)[:, None]
        points = segment[:2] + t * (segment[2:] - segment[:2])
        dx = np.maximum(np.maximum(box[0] - points[:, 0], points[:, 0] - box[2]), 0.0)
        dy = np.maximum(np.maximum(box[1] - points[:, 1], points[:, 1] - box[3]), 0.0)
        sampled = np.hypot(dx, dy)
        assert segment_box_distance(segment, box) == pytest.approx(sampled.min(), abs=2e-3)
        inside = (dx == 0) & (dy == 0)
        length = np.hypot(*(segment[2:] - segment[:2]))
        assert length_inside(segment, box) == pytest.approx(inside.mean() * length, abs=2e-3 * length + 1e-9)


def _figure(example, speeds, unit):
    model = rdm.load_model(EXAMPLES / example)
    result = rdm.campbell(model, rdm.rpm(speeds), orders=(1, 2))
    fig = result.plot(speed_unit=unit, title=model.name)
    fig.set_dpi(150)
    fig.canvas.draw()
    return fig, fig.axes[0]


@pytest.mark.parametrize("example, speeds, unit", CASES, ids=[c[0].split(".")[0] for c in CASES])
def test_no_leader_touches_another_label_s_text(example, speeds, unit):
    import matplotlib.pyplot as plt

    fig, ax = _figure(example, speeds, unit)
    _assert_leaders_clear(fig, ax)
    plt.close(fig)


def test_no_order_key_s_leader_touches_another_key(chain_campbell):
    """The 20-rotor chain's figure saved at 150 dpi (its sweep shared with
    test_campbell_labels32 through ``conftest.chain_campbell``), measured as saved."""
    import io

    import matplotlib.pyplot as plt

    fig = chain_campbell(20, np.linspace(0.0, 4500.0, 22)).plot()
    fig.savefig(io.BytesIO(), format="png", dpi=150)
    fig.set_dpi(150)
    ax = fig.axes[0]
    assert any(line.get_gid() == "order-key-leader" and line.get_visible() for line in ax.get_lines())
    _assert_leaders_clear(fig, ax)
    plt.close(fig)


def _assert_leaders_clear(fig, ax):
    """Every visible leader of ``ax`` at least :data:`GAP_POINTS` from every other text's box,
    and at most :data:`INSIDE_POINTS` inside its own."""
    renderer = fig.canvas.get_renderer()
    points = fig.dpi / 72.0
    texts = [t for t in ax.texts if t.get_visible() and t.get_text()]
    boxes = [glyph_box(t, renderer) for t in texts]
    boxes = [(b.x0, b.y0, b.x1, b.y1) for b in boxes]
    critical = [t for t in ax.texts if t.get_gid() == "critical-label"]
    critical_lines = [line for line in ax.get_lines() if line.get_gid() == "critical-leader"]
    gids = {line.get_gid() for line in ax.get_lines() if str(line.get_gid()).startswith("mode-leader")}
    drawn = leader_lines(ax, ("critical-leader", "order-key-leader") + tuple(gids))
    for line, segments in drawn:
        if line.get_gid() == "critical-leader":
            # its label is the critical-speed label made with it; the leader starts on its box
            own = texts.index(critical[critical_lines.index(line)])
            assert segment_box_distance(np.tile(segments[0, :2], 2), boxes[own]) < 0.5, own
        else:                   # a mode's or a key's: the mode label or key nearest its ends
            ends = np.vstack([segments[0, :2], segments[-1, 2:]])
            kind = "order-key" if line.get_gid() == "order-key-leader" else "mode-label"
            own = min((k for k, t in enumerate(texts) if t.get_gid() == kind),
                      key=lambda k: min(segment_box_distance(np.tile(e, 2), boxes[k]) for e in ends))
        words = texts[own].get_text()
        inside = sum(length_inside(s, boxes[own]) for s in segments) / points
        assert inside <= INSIDE_POINTS, (words, inside)
        for k, (text, box) in enumerate(zip(texts, boxes)):
            if k != own:
                gap = min(segment_box_distance(s, box) for s in segments) / points
                assert gap >= GAP_POINTS, (words, text.get_text(), gap)
