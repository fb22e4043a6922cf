"""The lowest modes of ROSS's rotors, faster (issue 28 section 4, ross43).

Checked here against the definitions, not against the code's own numbers: the state matrices of a
model whose bearings are tabulated over speed (now one product per rotor for all its bearings) are
``[[0, I], [-M^-1 K(Omega), -M^-1 (C(Omega) + Omega G)]]`` built here from ``Model.matrices``; a
model of up to ``_stack.KEPT_DOF`` coordinates (now 256: ROSS's compressor_example, 224) keeps its
speed-independent parts between analyses, and its lowest roots stay the roots of the full state
matrix (scipy's ``eigvals``).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _stack, campbell as campbell_module
from rotordyn_modal.io.ross_file import read_ross_rotor

DATA = Path(__file__).parent / "data" / "ross"


def ross_model(name):
    path = DATA / f"{name}.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # compressor_example: PCHIP tables read linearly
        return rdm.Model.from_dict(read_ross_rotor(path), source=path)


def state_matrix(model, speed):
    """The state matrix at ``speed`` [rad/s] from the model's own M, C, G, K there."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    inverse = np.linalg.inv(M)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ K, -inverse @ (C + speed * G)]])


@pytest.mark.parametrize("name", ["speed_tables", "compressor_example"])
def test_state_matrices_of_tabulated_bearings_are_the_definition(name):
    model = ross_model(name)
    stack = campbell_module.lowest_stack(model)
    assert stack.dependent
    speeds = {"speed_tables": np.array([0.0, 333.3, 1047.2]),
              "compressor_example": np.array([450.0, 600.0, 1151.9])}[name]      # its tables' 4,000-11,000 rpm
    made = stack.at(np.zeros(len(speeds), int), speeds)
    for speed, matrix in zip(speeds, made):
        exact = state_matrix(model, speed)
        lower = slice(model.dofs.n, 2 * model.dofs.n)
        # each block row of M^-1 (K, C) to the round-off of its own products
        scale = np.abs(exact[lower]).max()
        assert np.abs(matrix - exact).max() <= 1e-12 * scale


def test_compressor_example_keeps_its_constants():
    model = ross_model("compressor_example")
    assert model.dofs.n <= _stack.KEPT_DOF
    one, two = campbell_module.lowest_stack(model), campbell_module.lowest_stack(model)
    assert one.constants is two.constants
    speeds = np.array([628.3, 837.8, 1047.2])
    first = rdm.campbell(model, speeds, modes=12, critical=False)
    again = rdm.campbell(model, speeds, modes=12, critical=False)     # from the kept constants
    for k, speed in enumerate(speeds):
        roots = scipy.linalg.eigvals(state_matrix(model, speed))
        for found in (first.eigenvalues[k], again.eigenvalues[k]):
            found = found[np.isfinite(found)]
            assert len(found) == 12
            nearest = roots[np.argmin(np.abs(roots[None, :] - found[:, None]), axis=1)]
            assert np.max(np.abs(found - nearest) / np.abs(nearest)) <= 1e-9
