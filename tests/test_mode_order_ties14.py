"""Mode numbers of roots that share a frequency to round-off (redteam12's defect): the order
must not depend on the model's units. The cross-coupled example at rest has two double
frequencies (63.17 Hz and 71.03 Hz), each shared by two roots of different damping; scaling the
model's time by 1e-3 (stiffness x 1e6, damping x 1e3, speed x 1e3) multiplies every root by 1e3
exactly in exact arithmetic (dimensional analysis), so mode k of the scaled model must be mode k
of the original, times 1e3."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "unstable_cross_coupled.toml"
#: the scaled model's time unit [s] per original second
T = 1e-3


def _models():
    model = rdm.load_model(EXAMPLE)
    keys = {}
    for i, _ in enumerate(model.suspensions):
        keys[f"suspensions.{i}.stiffness"] = 1 / T ** 2
        keys[f"suspensions.{i}.damping"] = 1 / T
    return model, model.scaled(keys)


@pytest.mark.parametrize("speed", [0.0, 300.0])
def test_modal_mode_numbers_are_scale_free(speed):
    model, scaled = _models()
    original = rdm.modal(model, speed).eigenvalues
    other = rdm.modal(scaled, speed / T).eigenvalues * T
    assert original.shape == other.shape
    # the example really has frequencies that tie to round-off, with different damping
    f = original.imag
    tied = np.flatnonzero(np.abs(np.diff(f)) < 1e-12 * np.abs(original).max())
    assert tied.size >= 1 and np.all(np.abs(np.diff(original.real)[tied]) > 1.0)
    np.testing.assert_allclose(other, original, rtol=1e-9, atol=1e-9 * np.abs(original).max())


def test_tied_frequencies_ordered_by_damping():
    """Within a frequency shared to round-off the less damped mode (larger real part) comes first,
    in the model and in the scaled model alike."""
    model, scaled = _models()
    for lam in (rdm.modal(model, 0.0).eigenvalues, rdm.modal(scaled, 0.0).eigenvalues):
        close = np.abs(np.diff(lam.imag)) < 1e-12 * np.abs(lam).max()
        assert close.any()
        assert np.all(np.diff(lam.real)[close] < 0)


def test_stability_mode_numbers_are_scale_free():
    model, scaled = _models()
    speeds = np.array([0.0, 100.0, 300.0])
    original = rdm.stability(model, speeds).eigenvalues
    other = rdm.stability(scaled, speeds / T).eigenvalues * T
    np.testing.assert_allclose(other, original, rtol=1e-9, atol=1e-9 * np.abs(original).max())


def test_campbell_mode_numbers_are_scale_free():
    model, scaled = _models()
    speeds = np.array([0.0, 50.0, 200.0])
    original = rdm.campbell(model, speeds).eigenvalues
    other = rdm.campbell(scaled, speeds / T).eigenvalues * T
    np.testing.assert_allclose(other, original, rtol=1e-9, atol=1e-9 * np.abs(original).max())


def test_numbers_at_speed_are_scale_free():
    """``modes``' numbers of one speed's roots, given in any order: each root of the scaled model
    (matched to the original's by value, times 1e3) gets the original root's number."""
    from rotordyn_modal.analysis.mode_numbers import numbers_at_speed

    model, scaled = _models()
    original = rdm.modal(model, 0.0).eigenvalues
    other = rdm.modal(scaled, 0.0).eigenvalues * T
    matched = other[[int(np.argmin(np.abs(other - lam))) for lam in original]]
    assert np.allclose(matched, original, rtol=1e-9) and len(set(matched)) == len(matched)
    mixed = np.arange(len(original))[::-1]
    numbers = numbers_at_speed(original[mixed])
    assert sorted(numbers) == list(range(1, len(original) + 1))
    np.testing.assert_array_equal(numbers_at_speed(matched[mixed] / T), numbers)
