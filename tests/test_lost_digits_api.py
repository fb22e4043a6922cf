"""A model whose low modes keep no digit is refused in Python too (issue 27 §1.1, §1.6; spread27q's
"left"): ``load_model`` and ``check`` refused redteam14's dec model (a 1 g casing between 1e15 N/m
bearings under a 1e9 kg rotor: 24 decades of eigenvalue), but a model built with
``Model.from_dict`` or ``Model.variant``, and a study's variant, went straight to the analyses,
which printed 0.00196 Hz for the exact 0.000159 Hz without a word. Truth from outside the code:
the 2-DOF chain casing-on-mounts, rotor-on-bearings (test_mass_spread27q's ``_chain``, mpmath)."""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.study.definition import parse_study
from test_mass_spread27q import _chain, _machine

DEC = (1e-3, 1e9, 1e3, 1e15)            # casing [kg], rotor [kg], mounts [N/m], bearings [N/m]
PLAIN = (1e3, 1e2, 1e6, 1e8)            # the same machine with digits to spare


def _refused(call, masses=True):
    with pytest.raises(rdm.ModelError) as refused:
        call()
    said = str(refused.value)
    assert "[bearings.b" in said and "stiffness" in said and ("reduced mass" in said or not masses), said


@pytest.mark.parametrize("analysis", [
    lambda m: rdm.modal(m, 0.0),
    lambda m: rdm.campbell(m, np.linspace(0.0, 100.0, 3)),
    lambda m: rdm.stability(m, np.linspace(0.0, 100.0, 3)),
])
def test_a_model_built_in_python_that_keeps_no_digit_is_refused_by_its_analyses(analysis):
    _refused(lambda: analysis(rdm.Model.from_dict(_machine(*DEC, isotropic=True))))


def test_a_variant_made_stiff_past_every_digit_is_refused():
    """``Model.variant`` (what fits and studies build) is a new model, looked at again."""
    model = rdm.Model.from_dict(_machine(*PLAIN, isotropic=True))
    rdm.modal(model, 0.0)                                       # 1e8 N/m bearings: fine
    stiff = model.scaled({"bearings.b0.stiffness": 1e14, "bearings.b1.stiffness": 1e14})   # 5e21 N/m: 17.4 digits
    _refused(lambda: rdm.modal(stiff, 0.0), masses=False)


def test_a_model_with_digits_to_spare_gives_the_chains_frequencies():
    """The check refuses nothing it should not: the plain machine's lateral pair is the chain's."""
    modes = rdm.modal(rdm.Model.from_dict(_machine(*PLAIN, isotropic=True)), 0.0)
    low, high = _chain(*PLAIN)
    found = np.asarray(modes.frequencies_hz) * 2 * np.pi
    for w in (low, high):
        assert np.min(np.abs(found - w)) / w < 1e-9, (w, found)


def test_a_study_variant_that_keeps_no_digit_is_failed_not_computed():
    """A study scaling the bearings past every digit records the variant as failed, with the
    reason, instead of frequencies (its warning column was '' and its numbers wrong)."""
    base = rdm.Model.from_dict(_machine(*PLAIN, isotropic=True))
    spec = parse_study({"parameters": [{"keys": ["bearings.b0.stiffness", "bearings.b1.stiffness"],
                                        "scale": [1.0, 1e14]}],
                        "analyses": {"modes": {"speed_rpm": 0.0}}}, model=base)
    result = rdm.study(base, spec)
    failed = np.asarray(result.failed)
    values = np.asarray(result.dataset["sample_value"].values)
    stiff = values.reshape(len(failed), -1).max(axis=1) > 1e6
    assert stiff.any() and (~stiff).any()
    assert failed[stiff].all() and not failed[~stiff].any(), (values, failed)
