"""A small model's speed-independent parts kept between analyses (issue 28 section 4, ross37).

``analysis._stack.model_constants`` keeps a small model's linear form, stacked matrices, mass
factor, whirl forms and the lowest modes' Hermitian form for every later stack of the very same
model object (as ROSS's ``Rotor`` keeps ``M0``, ``K0``, ``G0``), and ``_lowest_pencils`` makes its
pencils' pattern once per stack. Checked here: repeated and interleaved analyses of different
models give each model's own roots (closed forms, scipy's eigenvalues of the state matrices built
here from ``Model.matrices``), the kept arrays cannot be written, and what is kept is bounded.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest, _stack, campbell as campbell_module
from rotordyn_modal.io.ross_file import read_ross_rotor

DATA = Path(__file__).parent / "data" / "ross"

A = 0.25            # bearing half-span [m]
MASS, JP, JD = 30.0, 0.4, 0.9


def rigid_rotor(stiffness: float) -> rdm.Model:
    """A rigid rotor on two isotropic bearings at +-A to the ground: 4 lateral coordinates."""
    return rdm.Model.from_dict({
        "name": "rigid rotor",
        "rotors": [{"name": "rotor", "mass": MASS, "center_of_mass": [0.0, 0.0, 0.0],
                    "polar_inertia": JP, "diametral_inertia": JD, "speed_ratio": 1.0}],
        "bearings": [{"name": "a", "rotor": "rotor", "position": [-A, 0.0, 0.0], "stiffness": stiffness},
                     {"name": "b", "rotor": "rotor", "position": [A, 0.0, 0.0], "stiffness": stiffness}],
    })


def closed_form(speed, stiffness):
    """The four lateral frequencies [rad/s], ascending: cylindrical twice, conical backward and forward."""
    cylindrical = np.sqrt(2 * stiffness / MASS)
    kt = 2 * A**2 * stiffness
    root = np.sqrt((speed * JP) ** 2 + 4 * JD * kt)
    return np.sort(np.column_stack([cylindrical + 0 * speed, cylindrical + 0 * speed,
                                    (root - speed * JP) / (2 * JD), (root + speed * JP) / (2 * JD)]), axis=1)


def state_roots(model, speed):
    """Every root of ``s^2 M + s (C + speed G) + K`` from scipy's eigenvalues of the state matrix
    built here (upper half plane)."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    inverse = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ K, -inverse @ (C + speed * G)]])
    roots = scipy.linalg.eigvals(A)
    return roots[roots.imag > 0]


def test_interleaved_models_keep_their_own_roots():
    """Six models of different stiffness solved in turn, twice over (more than are kept at once):
    each call equals its model's closed form, and the second round equals the first bit for bit."""
    speeds = np.linspace(0.0, 1500.0, 9)
    stiffness = [1e5, 3e5, 1e6, 3e6, 1e7, 3e7]
    models = [rigid_rotor(k) for k in stiffness]
    first = {}
    for _ in range(2):
        for k, model in zip(stiffness, models):
            result = rdm.campbell(model, speeds, modes=4, critical=False)
            found = np.sort(result.eigenvalues.imag, axis=1)
            assert np.allclose(result.eigenvalues.real, 0.0, atol=1e-9 * np.abs(result.eigenvalues).max())
            np.testing.assert_allclose(found, closed_form(speeds, k), rtol=1e-9)
            if k in first:
                assert np.array_equal(first[k], result.eigenvalues)
            first[k] = result.eigenvalues
    assert len(_stack._KEPT) <= _stack.KEPT_MODELS


def test_a_model_from_the_same_description_gets_the_same_bits():
    """A second model object of the same description (its own constants) gives the very bits of
    the first model's second call (the kept constants)."""
    path = DATA / "rotor_example.toml"
    speeds = np.linspace(0.0, 3000.0, 21)
    one = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    rdm.campbell(one, speeds, modes=12, critical=False)
    again = rdm.campbell(one, speeds, modes=12, critical=False)
    other = rdm.campbell(rdm.Model.from_dict(read_ross_rotor(path), source=path), speeds, modes=12, critical=False)
    for name in ("eigenvalues", "shapes", "whirl_ratios"):
        assert np.array_equal(getattr(again, name), getattr(other, name), equal_nan=True), name
    assert np.array_equal(again.whirl, other.whirl)


@pytest.mark.parametrize("name", ["rotor_example", "speed_tables"])
def test_second_call_equals_the_state_matrices_roots(name):
    """ROSS's rotor_example (the Hermitian route) and a rotor on bearings tabulated over speed
    (the reduced basis' route, its pencils' pattern kept): the second call's lowest 12 roots are the
    12 lowest of scipy's eigenvalues of the full state matrix to 1e-9."""
    path = DATA / f"{name}.toml"
    reference = json.loads(path.with_suffix(".json").read_text())
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    speeds = np.linspace(min(c["speed"] for c in reference["modal"]), max(c["speed"] for c in reference["modal"]), 7)
    rdm.campbell(model, speeds, modes=12, critical=False)
    result = rdm.campbell(model, speeds, modes=12, critical=False)
    for k, speed in enumerate(speeds):
        roots = state_roots(model, speed)
        mine = result.eigenvalues[k][np.isfinite(result.eigenvalues[k])]
        for root in mine:
            assert np.min(np.abs(roots - root)) <= 1e-9 * abs(root)
        oscillating = roots[np.abs(roots.real) < np.abs(roots.imag)]
        lowest = np.sort(oscillating.imag)[:len(mine)]
        np.testing.assert_allclose(np.sort(mine.imag), lowest, rtol=1e-9)


def test_kept_constants_are_shared_and_read_only():
    """Two stacks of one small model share its constants; the arrays cannot be written (a caller
    writing into one would change every later analysis of the model)."""
    model = rigid_rotor(1e6)
    first = campbell_module.lowest_stack(model)
    rdm.campbell(model, np.linspace(0.0, 100.0, 3), modes=4, critical=False)
    second = campbell_module.lowest_stack(model)
    assert second.constants is first.constants
    assert second.forms[0] is first.forms[0]
    for array in (second.M, second.K, second.G, second.factor, second.whirl.W):
        with pytest.raises(ValueError):
            array[0, 0, 0] = 1.0
    constant, gyroscopic = _lowest._hermitian_form(second)
    with pytest.raises(ValueError):
        constant[0, 0] = 1.0


def test_large_models_keep_nothing(monkeypatch):
    """A model above KEPT_DOF coordinates: each stack its own constants, nothing kept (the bound
    set below compressor_example's 224 coordinates, which the default 256 keeps)."""
    monkeypatch.setattr(_stack, "KEPT_DOF", 100)
    path = DATA / "compressor_example.toml"
    with pytest.warns(Warning):
        model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    assert model.dofs.n > _stack.KEPT_DOF
    assert _stack.model_constants(model) is None
    one, two = _stack.Stack([model]), _stack.Stack([model])
    assert one.constants is not two.constants
    assert all(entry[0] is not model for entry in _stack._KEPT.values())


def test_pencils_share_their_pattern_within_a_stack():
    """The reduced route's pencils of two sweeps of one stack share the pattern's parts (the band,
    the sparse products' matrices), made once; their speed-dependent entries are each sweep's own."""
    path = DATA / "speed_tables.toml"
    model = rdm.Model.from_dict(read_ross_rotor(path), source=path)
    stack = campbell_module.lowest_stack(model)
    one = _lowest._Pencils(stack, np.array([10.0, 200.0]))
    two = _lowest._Pencils(stack, np.array([50.0]))
    assert one.band is two.band and one._stacked is two._stacked and one.scatter is two.scatter
    assert one.kb.shape[0] == 2 and two.kb.shape[0] == 1
    M, _, _, K = model.matrices(50.0)
    # the stiffness of the second pencil at its speed: the constant K plus the bearings' entries
    full = np.array(two.K, dtype=float, copy=True)
    np.add.at(full, (two.rows, two.cols), two.kb[0])
    np.testing.assert_allclose(full, K, rtol=1e-12, atol=1e-12 * np.abs(K).max())
