"""The starts from the neighbouring speeds and the parts of bounded memory (``docs/theory.md``
section 17, step 3a and step 3) on the two routes beside the lowest N modes: the modes below a
frequency (``campbell(max_frequency=F)``, ``_lowest.roots_below``) and a model whose mounts have
Maxwell branches (the rational pencil, ``_lowest_branches``).

Truth from outside the code: scipy's eigenvalues of the full state matrix, built here from
``model.matrices(speed)`` (ROSS's ``compressor_example``, whose lowest roots swap places in
frequency between the anchors: ``tests/test_lowest_continuation.py``) or by ``linear_system``
with the branches' states (the pump of ``examples/flexible_pump_on_mounts.toml`` on Maxwell
mounts, refined in extended precision: ``tests/test_lowest_branches.py``). The memory rule is the
one of ``tests/test_lowest_memory.py``: doubling the speeds adds at most a few times the result's
own growth, not every speed's working arrays at once.
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest
from test_lowest_branches import _true_roots, pump  # noqa: F401 (pump: a fixture)
from test_lowest_continuation import SPEEDS, _dense_roots, _model
from shaft_models import fan_shaft as _shaft
from test_lowest_memory import _SMALL, _budgets

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _lowest_branches
from rotordyn_modal.analysis.campbell import lowest_stack
from rotordyn_modal.analysis.modal import is_oscillating
from rotordyn_modal.linear_system import state_matrices

#: the highest frequency of the modes below it on compressor_example [Hz]: its ten lowest modes
#: (157 to 605 Hz at the first speed; the next at 972 Hz)
LIMIT_HZ = 700.0


def _recorded(monkeypatch):
    """The starts given to the one-factorisation refinement of the continued speeds: a list of
    (rows, starts) filled by every call of ``_lowest._continued``."""
    given = []
    continued = _lowest._continued

    def recording(pencils, guesses, vectors, rows):
        given.append((np.array(rows), guesses.copy()))
        return continued(pencils, guesses, vectors, rows)

    monkeypatch.setattr(_lowest, "_continued", recording)
    return given


def _starts_near_distinct_roots(given, truth):
    """The largest relative distance of a continued start to its nearest true root, and whether
    every speed's starts are nearest to different roots."""
    worst, distinct = 0.0, True
    for rows, starts in given:
        for row, guesses in zip(rows, starts):
            roots = truth[row]
            distance = np.abs(guesses[:, None] - roots[None, :]) / np.abs(roots[None, :])
            worst = max(worst, float(np.max(np.min(distance, axis=1))))
            distinct &= len(set(np.argmin(distance, axis=1).tolist())) == len(guesses)
    return worst, distinct


@pytest.fixture(scope="module")
def compressor():
    model = _model()
    return model, [_dense_roots(model, speed) for speed in SPEEDS]


def test_modes_below_a_frequency_are_continued_between_anchors(compressor, monkeypatch):
    """``roots_below`` at nine speeds of compressor_example: no speed solved whole, the speeds
    between the anchors (0, 4, 8) started from the anchors' roots, each start within 1e-5 of a
    distinct root of the full model (the projected roots alone are 4e-5 off), and the roots below
    the limit the full model's to 1e-9, all of them."""
    model, dense = compressor
    given = _recorded(monkeypatch)
    limit = 2 * np.pi * LIMIT_HZ
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # no "solved whole"
        values, _, wanted, full = _lowest.roots_below(lowest_stack(model), SPEEDS, limit)
    assert not full.any()
    assert given and sorted(np.concatenate([rows for rows, _ in given]).tolist()) == [1, 2, 3, 5, 6, 7]
    worst, distinct = _starts_near_distinct_roots(given, dense)
    assert worst < 1e-5 and distinct
    for row, roots in enumerate(dense):
        expected = np.sort(roots[is_oscillating(roots) & (roots.imag <= limit)].imag)
        got = values[row][wanted[row]]
        assert len(expected) == 10 and len(got) == 10
        nearest = roots[np.argmin(np.abs(got[:, None] - roots[None, :]), axis=1)]
        assert np.max(np.abs(got - nearest) / np.abs(nearest)) < 1e-9
        assert np.sort(got.imag) == pytest.approx(expected, rel=1e-9, abs=0)


def test_maxwell_branches_are_continued_between_anchors(pump, monkeypatch):  # noqa: F811 (the fixture)
    """The ten lowest modes of the pump on Maxwell mounts at nine speeds (750 to 6,000 rpm): no
    speed solved whole, the speeds between the anchors started from the anchors' roots on the
    rational pencil, each within 1e-5 of a distinct root of the state matrix with the branches'
    states, and the roots that matrix's to 1e-9."""
    speeds = np.linspace(750.0, 6000.0, 9) * np.pi / 30
    given = _recorded(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        values, _, full = _lowest_branches.lowest_roots(lowest_stack(pump), speeds, 10)
    assert not full.any()
    truth = [_true_roots(A, 14) for A in state_matrices(pump, speeds)]
    assert given and sorted(np.concatenate([rows for rows, _ in given]).tolist()) == [1, 2, 3, 5, 6, 7]
    worst, distinct = _starts_near_distinct_roots(given, truth)
    assert worst < 1e-5 and distinct
    for row, roots in enumerate(truth):
        got = values[row]
        nearest = roots[np.argmin(np.abs(got[:, None] - roots[None, :]), axis=1)]
        assert np.max(np.abs(got - nearest) / np.abs(nearest)) < 1e-9
        assert np.sort(got.imag) == pytest.approx(np.sort(roots.imag)[:10], rel=1e-9, abs=0)


def _growth(model, counts, start, stop, **options):
    """The peak traced memory's growth [bytes] from ``counts[0]`` to ``counts[1]`` speeds of
    ``campbell(**options)``, and its result's shapes' growth [bytes]."""
    measured = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rdm.campbell(model, np.linspace(start, stop, 11), critical=False, **options)   # caches made first
        for count in counts:
            tracemalloc.start()
            try:
                result = rdm.campbell(model, np.linspace(start, stop, count), critical=False, **options)
                measured.append((tracemalloc.get_traced_memory()[1], result.shapes.nbytes))
            finally:
                tracemalloc.stop()
    return measured[1][0] - measured[0][0], measured[1][1] - measured[0][1]


def test_modes_below_a_frequency_grow_with_the_speeds_only_by_the_result(monkeypatch):
    """``campbell(max_frequency=1500)`` of the 60-coordinate shaft (12 modes below): from 150 to 300
    speeds the peak grows by at most 4 times the result's shapes (3.5 now: the shapes, the weighted
    shapes, the tracking's work; 4.2 before, with a copy of the wanted columns of both)."""
    _budgets(monkeypatch, _SMALL)
    grown, result_grown = _growth(_shaft(), (150, 300), 10.0, 1500.0, max_frequency=1500.0)
    assert grown <= 4 * result_grown, (grown, result_grown)


def test_maxwell_branches_grow_with_the_speeds_only_by_the_result(pump, monkeypatch):  # noqa: F811
    """``campbell(modes=10)`` of the pump on Maxwell mounts: from 60 to 120 speeds the peak grows
    by at most 4 times the result's shapes (3.3 now; 13.9 before: Newton's iteration on every root
    of every speed at once, and the projected state matrices' eigenvectors of every speed)."""
    _budgets(monkeypatch, _SMALL)
    grown, result_grown = _growth(pump, (60, 120), 50.0, 600.0, modes=10)
    assert grown <= 4 * result_grown, (grown, result_grown)


def test_shift_invert_arnoldi_grows_with_the_speeds_only_by_the_result(monkeypatch):
    """The lowest 12 roots of the 24-rotor chain (``tests/test_lowest_chain.py``: its basis would
    hold every mode, so shift-invert Arnoldi serves it): from 12 to 24 speeds the peak grows by at
    most twice the result's shapes (1.0 now; 11.1 before: Newton's iteration on every root of every
    speed at once, and copies of the roots' shapes)."""
    from test_lowest_chain import _chain

    _budgets(monkeypatch, _SMALL)
    stack = lowest_stack(_chain(24))
    _lowest.lowest_roots(stack, np.array([10.0, 300.0]), 12)          # caches made first
    measured = []
    for count in (12, 24):
        tracemalloc.start()
        try:
            shapes = _lowest.lowest_roots(stack, np.linspace(10.0, 300.0, count), 12)[1]
            measured.append((tracemalloc.get_traced_memory()[1], shapes.nbytes))
        finally:
            tracemalloc.stop()
    grown, result_grown = measured[1][0] - measured[0][0], measured[1][1] - measured[0][1]
    assert grown <= 2 * result_grown, (grown, result_grown)
