"""``rdm.frf(..., engine='direct')`` refuses a model whose mass matrix rounding leaves singular,
as the other engines and every analysis do (issue 27, item 1.3's family).

The direct engine solved ``Z(w) X = B`` and checked the mass matrix only where a solve failed;
with a stator of 1e-30 kg under a rotor of 10 kg the dynamic stiffness is dominated by the
bearings' and mounts' stiffness, every solve succeeds, and numbers of no meaning came back
(``tests/degenerate_models.py``: ``modes`` and ``engine='auto'`` refuse that model)."""

from __future__ import annotations

import tomllib
import warnings

import pytest

import rotordyn_modal as rdm
from degenerate_models import variant
from rotordyn_modal.errors import ModelError


def _model(**changes):
    with warnings.catch_warnings():        # the sag warning of a 1e30 kg rotor: not this test's
        warnings.simplefilter("ignore")
        return rdm.Model.from_dict(tomllib.loads(variant(**changes)), source="light.toml")


def _refusal(call):
    with pytest.raises(ModelError) as refused:
        call()
    return str(refused.value)


@pytest.mark.parametrize("changes, freqs", [
    ({"rotor_mass": "10.0"}, [1.0, 10.0, 100.0]),      # every solve succeeds: was returned
    ({}, [0.0]),                                          # the EXTREME model at 0 Hz (K alone): was returned
], ids=["light-stator", "extreme-static"])
def test_the_direct_engine_refuses_a_singular_mass_matrix_in_the_line_of_every_analysis(changes, freqs):
    model = _model(**changes)
    line = _refusal(lambda: rdm.modal(model, 0.0))
    assert "mass matrix invertible in double precision" in line and "\n" not in line
    for engine in ("auto", "modal", "direct"):
        assert _refusal(lambda: rdm.frf(model, 0.0, freqs, engine=engine)) == line, engine


def test_the_direct_engine_still_answers_a_sane_model():
    """The same machine with a stator of 100 kg: direct and modal agree (the check refuses nothing else)."""
    import numpy as np

    model = _model(stator_mass="100.0", rotor_mass="10.0")
    direct = rdm.frf(model, 100.0, [1.0, 10.0, 100.0], engine="direct").H
    modal = rdm.frf(model, 100.0, [1.0, 10.0, 100.0], engine="modal").H
    np.testing.assert_allclose(direct, modal, rtol=1e-8, atol=1e-12 * np.abs(modal).max())
