"""A coarse speed grid names each mode as a fine one does: the tracking of a step that leaves a
mode's match in doubt is made again with speeds put inside that step.

Before: ``stability examples/journal_rotor.toml --speeds 100:20000:5`` said "mode 4 loses stability
at 11627.649 rpm", every finer grid "mode 2"; ``campbell fan_on_bearings.toml --speeds 0:9000:7``
swapped modes 14 and 15 (the backward and forward whirl of one pair) from 1500 rpm on.

The truth is an independent continuation: the state matrices' eigenvalues (scipy) on a grid of
thousands of speeds, each root matched to the nearest one at the next speed (optimal assignment),
which follows every root without any shape.
"""

import functools

import numpy as np
import pytest
from scipy.linalg import eigvals
from scipy.optimize import linear_sum_assignment

import rotordyn_modal as rdm
from conftest import EXAMPLES

RPM = np.pi / 30


@functools.lru_cache(maxsize=None)
def _continuation(name, top_rpm, low_rpm, count):
    """Every root of ``examples/NAME`` at ``low_rpm`` (n,) and the root each becomes at
    ``top_rpm`` (n,), followed by nearest eigenvalues over ``count`` speeds."""
    model = rdm.load_model(EXAMPLES / name)
    first = roots = eigvals(model.state_space(low_rpm * RPM).A)
    where = np.arange(len(roots))                  # each first root's index among the current roots
    for speed in np.linspace(low_rpm, top_rpm, count)[1:] * RPM:
        following = eigvals(model.state_space(float(speed)).A)
        rows, columns = linear_sum_assignment(np.abs(roots[:, None] - following[None, :]))
        where = columns[np.argsort(rows)][where]
        roots = following
    return first, roots[where]


def _continued(name, low_rpm, top_rpm, start, count):
    """The root at ``top_rpm`` that the root nearest ``start`` at ``low_rpm`` becomes."""
    first, last = _continuation(name, top_rpm, low_rpm, count)
    return last[int(np.argmin(np.abs(first - start)))]


@pytest.mark.parametrize("count", [3, 4, 5, 6, 7, 11])
def test_stability_names_the_mode_that_a_fine_continuation_follows(count):
    model = rdm.load_model(EXAMPLES / "journal_rotor.toml")
    result = rdm.stability(model, np.linspace(100.0, 20000.0, count) * RPM)
    assert len(result.thresholds) == 1
    mode = int(result.threshold_modes[0])
    # the root the sweep calls that mode at its first speed, followed finely to the last speed: it is
    # the one that is unstable there (the root the threshold names)
    start = result.eigenvalues[0, mode - 1]
    end = _continued("journal_rotor.toml", 100.0, 20000.0, start, 2001)
    assert end.real > 0, (mode, start, end)
    assert end == pytest.approx(result.eigenvalues[-1, mode - 1], rel=1e-9)


def test_a_coarse_campbell_follows_each_mode_as_a_fine_continuation_does():
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    result = rdm.campbell(model, np.linspace(0.0, 9000.0, 7) * RPM, critical=False)
    for mode in (14, 15):
        end = _continued("fan_on_bearings.toml", 0.0, 9000.0, result.eigenvalues[0, mode - 1], 901)
        assert end == pytest.approx(result.eigenvalues[-1, mode - 1], rel=1e-9), mode


def test_a_studys_variants_tracked_on_finer_grids_equal_each_alone():
    """Each variant of a stack is tracked on its own added speeds: its Campbell equals its model's
    own, bit for bit (the study's rule), where the coarse grid leaves its steps in doubt."""
    from rotordyn_modal.analysis.campbell import campbell_many

    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")
    keys = [f"bearings.{b.name}.stiffness" for b in model.bearings]
    variants = [model] + [model.variant([(key, "scale", scale) for key in keys]) for scale in (0.5, 2.0)]
    speeds = np.linspace(0.0, 9000.0, 7) * RPM
    for together, variant in zip(campbell_many(variants, speeds, critical=False), variants):
        alone = rdm.campbell(rdm.Model.from_dict(variant.to_dict(), variant.source), speeds, critical=False)
        assert together.eigenvalues.tobytes() == alone.eigenvalues.tobytes()
