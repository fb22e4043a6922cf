"""The lowest modes' fallback warning counts the speeds it names (red-team round 7): a
`critical-speeds --lowest` run over 11 speeds warned "2 of 2 speeds solved whole", counting the
speeds of a bracket swept again finer, not the user's sweep. The warning now says which speeds
it counts; the user's sweep keeps "N of S speeds"."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, critical_speeds
from rotordyn_modal.analysis._stack import Stack

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "flexible_pump_on_mounts.toml"


def _no_basis_holds(stack, speeds, count, progress=False):
    """The reduced basis shown insufficient at every speed: every speed falls back to a full solve."""
    n = stack.n_dof
    return (np.zeros((len(speeds), count), complex), np.zeros((len(speeds), count, n), complex),
            np.zeros(len(speeds), bool))


def test_the_fallback_warning_names_the_speeds_it_counts(monkeypatch):
    stack = Stack([rdm.load_model(EXAMPLE)])
    assert stack.n_dof >= _lowest.DENSE_BELOW            # the reduced-basis route, not the small one
    monkeypatch.setattr(_lowest, "_reduced_roots", _no_basis_holds)
    speeds = rdm.rpm(np.array([1000.0, 2000.0, 3000.0]))
    for what, expected in ((None, "3 of 3 speeds solved whole"),
                           ("speeds of a test", "3 of 3 speeds of a test solved whole")):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            kwargs = {} if what is None else {"what": what}
            lam, _, full = _lowest.lowest_roots(stack, speeds, 4, **kwargs)
        assert full.all() and np.all(np.isfinite(lam))
        assert [str(w.message) for w in caught if expected in str(w.message)], [str(w.message) for w in caught]


def test_a_finer_sweep_of_the_critical_speeds_names_its_speeds(monkeypatch):
    """The critical speeds' finer sweep of a bracket asks the lowest modes with its own wording."""
    stack = Stack([rdm.load_model(EXAMPLE)])
    asked = []

    def recording(single, speeds, count, progress=False, what="speeds"):
        asked.append(what)
        n = single.n_dof
        return np.zeros((len(speeds), count), complex), np.zeros((len(speeds), count, n), complex), \
            np.zeros(len(speeds), bool)

    monkeypatch.setattr(_lowest, "lowest_roots", recording)
    critical_speeds._sub_sweep(stack, rdm.rpm(np.array([1000.0, 1001.0])), 4)
    assert asked == [critical_speeds._SUB_SWEEP_SPEEDS]
    assert "critical speeds" in asked[0] and asked[0] != "speeds"
