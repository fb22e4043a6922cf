"""The cost of a rotor on three journals (issue 29): its journals' loads are solved over speed
(statically indeterminate, on the nonlinear films), and a Campbell diagram evaluates its bearings
once for the sweep and again for the refinement of its roots. Each speed's loads are solved once,
and the films' coefficients are evaluated for the sweep's speeds together, not one speed at a time;
the results are those of each speed solved alone, to the bit.

A 200-speed campbell of this rotor cost 0.0084 s CPU before the loads were solved over speed
(d1c38ff) and about 1.0 s on d3a2e8b; see the report of api29l for the measured ratios."""

import numpy as np

import rotordyn_modal as rdm
import rotordyn_modal.elements.journal_bearing as journal_bearing
from test_journal_loads_indeterminate29c import _rigid

SPEEDS = rdm.rpm(np.linspace(500.0, 20000.0, 40))
STATIONS, LENGTHS = [-0.4, 0.1, 0.4], [0.02] * 3


def _counted(monkeypatch, name):
    """Replace ``journal_bearing.NAME`` by a wrapper that records the speeds of each call."""
    calls = []
    original = getattr(journal_bearing, name)

    def wrapper(speed, *args, **kwargs):
        calls.append(np.atleast_1d(np.asarray(speed, dtype=float)).copy())
        return original(speed, *args, **kwargs)

    monkeypatch.setattr(journal_bearing, name, wrapper)
    return calls


def test_a_campbell_solves_each_speeds_loads_once(monkeypatch):
    """The sweep's speeds are solved in one batch; the refinement of the roots, speed by speed,
    reuses them (it solved every speed again, one Newton solve each)."""
    calls = _counted(monkeypatch, "rigid_rotor_journal_loads")
    rdm.campbell(_rigid(STATIONS, LENGTHS), SPEEDS)
    solved = np.concatenate(calls)
    assert len(solved) == len(SPEEDS) and set(solved.tolist()) == set(SPEEDS.tolist())


def test_a_campbell_evaluates_the_films_for_the_speeds_together(monkeypatch):
    """Each journal's film coefficients: once for the sweep, and for the refinement twice (damping
    and stiffness) over all its speeds at once, not once a speed (3 + 2 x 40 x 3 calls before)."""
    calls = _counted(monkeypatch, "short_journal_bearing")
    rdm.campbell(_rigid(STATIONS, LENGTHS), SPEEDS)
    assert len(calls) <= 3 * len(STATIONS)
    assert all(len(speeds) == len(SPEEDS) for speeds in calls)


def test_the_loads_at_a_speed_do_not_depend_on_the_others_solved_with_it():
    """A speed's loads solved within the sweep equal those solved alone, to the bit; a model that
    has solved the sweep answers a single speed with them, as a fresh model solves it."""
    swept = _rigid(STATIONS, LENGTHS)
    journals = [b.coefficients.journal.load_over_speed for b in swept.bearings]
    together = np.stack([load(SPEEDS) for load in journals], axis=1)                  # (S, 3, 3)
    for i in (0, 17, len(SPEEDS) - 1):
        fresh = _rigid(STATIONS, LENGTHS)
        alone = np.stack([b.coefficients.journal.load_over_speed(SPEEDS[i:i + 1])[0] for b in fresh.bearings])
        np.testing.assert_array_equal(together[i], alone)
        np.testing.assert_array_equal(np.stack([load(SPEEDS[i])[0] for load in journals]), alone)
    assert np.allclose(together.sum(axis=1)[:, 2], -50.0 * 9.81, rtol=1e-12)          # they carry the weight


def test_a_campbell_equals_the_roots_solved_speed_by_speed():
    """The campbell's roots at a speed equal ``modal`` of a fresh model at that speed (its
    bearings evaluated at that speed alone) to round-off."""
    result = rdm.campbell(_rigid(STATIONS, LENGTHS), SPEEDS)
    for i in (3, 29):
        alone = rdm.modal(_rigid(STATIONS, LENGTHS), float(SPEEDS[i]))
        np.testing.assert_allclose(np.sort_complex(result.eigenvalues[i]), np.sort_complex(alone.eigenvalues),
                                   rtol=1e-10)
