"""The UCS map's crossings of journal-bearing curves are refined in batches (no eigen-solve of
one stiffness at a time), to the definition of a crossing: the followed mode's forward critical
speed at the crossing's stiffness is the crossing's speed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rotordyn_modal as rdm
from rotordyn_modal.analysis import ucs_map as module

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_journal_crossings_are_refined_in_batches_to_the_critical_speed(monkeypatch):
    """journal_rotor: fewer eigen-solve calls than three per crossing (the old Brent refinement
    solved one stiffness per evaluation, ~5 per crossing), and at each crossing's stiffness an
    independent solve has a forward critical speed equal to the crossing's speed to 1e-9."""
    sizes = []
    solve = module._synchronous_roots

    def counted(M, G, K, forms, **options):
        sizes.append(len(K))
        return solve(M, G, K, forms, **options)

    monkeypatch.setattr(module, "_synchronous_roots", counted)
    model = rdm.load_model(EXAMPLES / "journal_rotor.toml")
    result = module.ucs_map(model, np.geomspace(1e5, 1e10, 21), modes=2)
    monkeypatch.setattr(module, "_synchronous_roots", solve)
    journal = [c for c in result.crossings if next(b for b in result.curves if b.name == c.bearing).speeds is not None]
    assert journal, "journal_rotor's bearing curves cross its modes"
    # a refinement one crossing at a time solves at least its two ends and one point inside per
    # crossing; batched, one step serves all of a curve's crossings
    assert len(sizes) <= 2 + len(result.curves) * 2 + 3 * len(journal), sizes
    parts = module._Pencil(model, module._chosen_bearings(model, None))
    for crossing in journal:
        roots = parts.roots([crossing.stiffness])
        forward = roots.omega[0][roots.forward[0]]
        assert np.min(np.abs(forward - crossing.speed)) <= 1e-9 * crossing.speed, crossing
