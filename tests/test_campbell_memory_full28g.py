"""The full sweep (``campbell`` of every root, ``campbell_many``) keeps one copy of its shapes
(issue 28 §4: memory bounded by chunking). It kept two: the unit shapes and their mass-weighted
copy, which tracking and the critical speeds compare (``memory_estimate`` counted both); the
weighted rows are now computed a part at a time where they are read
(``_weighted_rows.WeightedRows``, as the lowest modes' sweep has since track28e).

The truth is the result's own size: as the speeds double, the peak traced memory may grow by the
shapes kept, not by twice them. The work parts are made small (each part a fixed budget, not a
share of the sweep), so that the sweep is many parts long at a test's size; they change no number.
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, campbell, tracking

from shaft_models import fan_shaft

MIB = 2**20


@pytest.fixture
def small_parts(monkeypatch):
    """The eigen-solver's chunks, the shapes' products, the MAC steps and the reorder of about 1 MB."""
    monkeypatch.setattr(_batches, "CHUNK_BYTES", MIB)
    monkeypatch.setattr(_batches, "_PART_BYTES", MIB)
    monkeypatch.setattr(campbell, "_REORDER_BYTES", MIB)
    monkeypatch.setattr(tracking, "_MAC_BYTES", MIB)


def _peak(model, speeds, critical):
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = rdm.campbell(model, speeds, critical=critical, orders=(1,))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, result


@pytest.mark.parametrize("critical", [False, True])
def test_the_full_sweeps_peak_grows_with_the_speeds_by_the_shapes_kept(small_parts, critical):
    model = fan_shaft(40)
    rdm.campbell(model, np.linspace(0.0, 1500.0, 5), critical=critical, orders=(1,))      # set-up outside
    peaks, kept = [], []
    for count in (101, 201):
        peak, result = _peak(model, np.linspace(0.0, 1500.0, count), critical)
        assert result.shapes.shape == (count, model.dofs.n, model.dofs.n)          # every root
        peaks.append(peak)
        kept.append(result.shapes.nbytes)
    shapes = kept[1] - kept[0]
    growth = peaks[1] - peaks[0]
    print(f"peak {peaks[0] / MIB:.1f} -> {peaks[1] / MIB:.1f} MB; shapes kept {kept[0] / MIB:.1f} -> "
          f"{kept[1] / MIB:.1f} MB: growth {growth / shapes:.2f} x the shapes'")
    # the shapes once and the small arrays per speed (roots, whirl ratios, tracking's order):
    # with the weighted copy (main) over 2 times them
    assert growth < 1.5 * shapes, (peaks, kept)


def test_the_estimate_counts_one_copy():
    """``memory_estimate``'s growth per speed of a full sweep is one set of shapes (and the
    eigenvalues' small arrays), not two."""
    n, states = 400, 800
    per_speed = campbell.memory_estimate(n, states, 2001, critical=False) - campbell.memory_estimate(
        n, states, 1001, critical=False)
    shapes = 1000 * (states // 2) * n * 16.0
    assert shapes <= per_speed < 1.2 * shapes
    # a small sweep's weighted rows are one part: counted whole, as before
    small = campbell.memory_estimate(6, 12, 121, critical=False) - campbell.memory_estimate(6, 12, 0, critical=False)
    assert small >= 2 * 121 * 6 * 6 * 16
