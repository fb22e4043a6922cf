"""The lowest modes' Campbell sweep keeps one copy of its shapes (issue 27 §1.9, issue 28 §4:
memory bounded by chunking).

The lowest 12 modes of a 400-coordinate shaft at 1,001 speeds peaked at 217 MB for a result of
73 MB of shapes: a second copy of every shape (the mass-weighted ones, for tracking), the
reduced route's shapes copied twice (sorted by frequency, cut to the modes asked for) and the
starts' vectors of every speed between its anchors. The truth here is the result's own size: as
the speeds double, the peak may grow by the shapes kept (and the one spare root per speed the
route refines), not by several times them. The work parts are made small, so that the sweep is
many parts long at a test's size (each part is a fixed budget of work, not a share of the
sweep); they change no number (each speed's and each step's work is its own).
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, _lowest, campbell, tracking

from shaft_models import fan_shaft

MIB = 2**20


def _peak(model, speeds, modes):
    """The traced peak [bytes] of the sweep and its result."""
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = rdm.campbell(model, speeds, critical=False, modes=modes)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, result


@pytest.fixture
def small_parts(monkeypatch):
    """Every work part of the sweep of about 1 MB (the shapes' products, the MAC steps, Newton's
    parts, the starts between anchors, the shapes moved within their memory and reordered)."""
    monkeypatch.setattr(_batches, "_PART_BYTES", MIB)
    monkeypatch.setattr(campbell, "_REORDER_BYTES", MIB)
    monkeypatch.setattr(_lowest, "_MOVE_BYTES", MIB, raising=False)
    monkeypatch.setattr(tracking, "_MAC_BYTES", MIB)
    monkeypatch.setattr(_lowest, "_NEWTON_BYTES", MIB)
    monkeypatch.setattr(_lowest, "_LEVEL_BYTES", MIB, raising=False)


def test_the_peak_grows_with_the_speeds_by_the_shapes_kept(small_parts):
    model = fan_shaft(100)
    modes = 12
    assert model.dofs.n > _lowest.DENSE_BELOW                  # the reduced basis and Newton's route
    rdm.campbell(model, np.linspace(0.0, 1500.0, 5), critical=False, modes=modes)        # set-up outside
    peaks, kept = [], []
    for count in (201, 401):
        peak, result = _peak(model, np.linspace(0.0, 1500.0, count), modes)
        assert result.shapes.shape == (count, modes, model.dofs.n)
        peaks.append(peak)
        kept.append(result.shapes.nbytes)
    shapes = kept[1] - kept[0]                                  # the result's shapes the doubling adds
    growth = peaks[1] - peaks[0]
    print(f"peak {peaks[0] / MIB:.1f} -> {peaks[1] / MIB:.1f} MB; shapes kept {kept[0] / MIB:.1f} -> "
          f"{kept[1] / MIB:.1f} MB: growth {growth / shapes:.2f} x the shapes'")
    # the shapes once, with the spare root per speed the route refines (13 of 12: 1.08 times
    # them), the anchors' projected eigenvectors and start vectors (one speed in eight: 0.14) and
    # the small arrays per speed (roots, whirl ratios, indices, discs): on main 3.0 times them
    assert growth < 1.6 * shapes, (peaks, kept)


def test_weighted_rows_read_as_the_whole_array_bit_for_bit(small_parts):
    """:class:`WeightedRows` gives each row the bits ``Stack.weighted`` of the whole sweep gives it,
    read in any order, after the shapes are reordered in place and after columns are left out;
    computing parts of about 1 MB (many parts) and keeping one of them at a time."""
    from rotordyn_modal.analysis._weighted_rows import WeightedRows

    model = fan_shaft(100)
    stack = campbell.lowest_stack(model)
    speeds = np.linspace(0.0, 1500.0, 301)
    values, shapes, _ = _lowest.lowest_roots(stack, speeds, 12)
    shapes = shapes[None]
    whole = stack.weighted(shapes.reshape((-1,) + shapes.shape[-2:]), np.zeros(len(speeds), int)).reshape(shapes.shape)
    rows = WeightedRows(stack, shapes)
    assert len(stack.weighted_parts(shapes.shape[1:], np.zeros(len(speeds), int))) > 4
    assert np.array_equal(rows[:, 5:250], whole[:, 5:250])
    rng = np.random.default_rng(1)
    k, j = rng.integers(0, len(speeds), 50), rng.integers(0, 12, 50)
    assert np.array_equal(rows[0, k, j], whole[0, k, j]) and np.array_equal(rows.variant(0)[k[0], j[:3]], whole[0, k[0], j[:3]])
    order = np.argsort(rng.random(shapes.shape[:3]), axis=-1)           # each speed's columns shuffled
    expected = np.take_along_axis(whole, order[..., None], axis=2)
    reordered = campbell._reordered(shapes, order)
    rows = rows.reordered(order, reordered)
    assert np.array_equal(rows[:, ::-1][:, :, ::-1], expected[:, ::-1][:, :, ::-1])
    # four columns left (the others written over): still each former row's bits
    columns = np.broadcast_to(np.array([0, 3, 4, 9]), shapes.shape[:2] + (4,))
    kept = campbell._reordered(reordered, columns)
    rows = rows.reordered(columns, kept)
    assert np.array_equal(rows[0, 7:290:3], expected[0, 7:290:3][:, [0, 3, 4, 9]])
