"""Fewer solved anchors where the Gershgorin discs allow (``_lowest._solved_levels``, issue 28 §4):
ROSS's ``compressor_example``, ``campbell(modes=12)`` over the file's reference speeds.

A solved anchor solves its projected pencil whole (one ``eig`` of its state matrix); the speeds
between are carried over. Where a pilot shows the discs hold halfway between every sixteenth
speed, only those are solved (401 speeds: 26 ``eig``, every eighth speed before: 51); where they
do not (101 speeds), every eighth speed is solved as before. Truth from outside the code: scipy's
eigenvalues of the full state matrix built from ``model.matrices(speed)``, to 1e-9."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.io.ross_file import read_ross_rotor

from shaft_models import assert_lowest_are_the_full_models

DATA = Path(__file__).parent / "data" / "ross"
#: the span of the file's ROSS reference speeds [rad/s] (6,000-10,000 rpm)
LOW, HIGH = 628.3185307179587, 1047.1975511965977


def _sweep(count):
    """The model, ``campbell(modes=12)`` of ``count`` speeds, how many state matrices ``eig``
    solved (every projected pencil solved whole with its vectors) and the warnings."""
    path = DATA / "compressor_example.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    eig, solved = np.linalg.eig, []

    def counted(matrices):
        solved.append(1 if np.ndim(matrices) == 2 else len(matrices))
        return eig(matrices)

    np.linalg.eig = counted
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = rdm.campbell(model, np.linspace(LOW, HIGH, count), critical=False, modes=12)
    finally:
        np.linalg.eig = eig
    return model, result, sum(solved), [str(warning.message) for warning in caught]


@pytest.fixture(scope="module")
def dense():
    return _sweep(401)


@pytest.fixture(scope="module")
def coarse():
    return _sweep(101)


def test_a_dense_sweep_solves_every_sixteenth_speed(dense):
    """401 speeds: the discs hold halfway between every sixteenth speed, so 26 projected pencils
    are solved whole (speeds 0, 16, ..., 400), not 51 (every eighth and the last)."""
    _, _, solved, caught = dense
    assert not [message for message in caught if "solved whole" in message]
    assert solved == 26


@pytest.mark.parametrize("row", [0, 8, 9, 100, 392, 397, 400])
def test_the_dense_sweeps_lowest_twelve_are_the_full_models(dense, row):
    """At solved anchors (0, 400), at anchors carried over from sixteen speeds away (8, 392:
    halfway), and at other speeds (9, 100, 397): the 12 lowest of scipy's eigenvalues, each to 1e-9."""
    model, result, _, _ = dense
    assert_lowest_are_the_full_models(model, np.linspace(LOW, HIGH, 401)[row], result.eigenvalues[row])


def test_a_coarse_sweep_solves_every_eighth_speed(coarse):
    """101 speeds (twice as far apart): the discs halfway between every sixteenth speed do not
    show the count, so every eighth speed is solved whole as before: 14 (0, 8, ..., 96 and 100),
    the 7 of the pilot's among them solved once."""
    _, _, solved, caught = coarse
    assert not [message for message in caught if "solved whole" in message]
    assert solved == 14


@pytest.mark.parametrize("row", [8, 12, 50, 99])
def test_the_coarse_sweeps_lowest_twelve_are_the_full_models(coarse, row):
    """At a solved anchor (8), a carried anchor (12) and other speeds: scipy's, each to 1e-9."""
    model, result, _, _ = coarse
    assert_lowest_are_the_full_models(model, np.linspace(LOW, HIGH, 101)[row], result.eigenvalues[row])
