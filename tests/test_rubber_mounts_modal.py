"""Modal analyses of a machine on rubber mounts with Maxwell branches.

The frequency-domain model of a branch is ``K_b lam tau_b / (1 + lam tau_b)`` (docs/model-file.md),
so every eigenvalue of the machine must make the rational pencil

    Q(lam) = lam^2 M + lam (C + Omega G) + K + sum_b lam tau_b / (1 + lam tau_b) K_b

singular. Internal relaxation roots of the branches' junctions sit exactly on the poles
lam = -1 / tau_b with no stator motion; they are left out of the check.
"""

from __future__ import annotations

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.elements.mounts import maxwell_branches


@pytest.fixture
def model(examples_dir):
    return rdm.load_model(examples_dir / "rubber_mounts.toml")


def _pencil(model, lam, speed):
    M, C, G, K = model.matrices()
    stiffness, times = maxwell_branches(model)
    branch = np.einsum("b,bij->ij", lam * times / (1 + lam * times), stiffness)
    return lam**2 * M + lam * (C + speed * G) + K + branch


def _off_pole(model, eigenvalues):
    _, times = maxwell_branches(model)
    return [lam for lam in eigenvalues if np.min(np.abs(1 + lam * times)) > 1e-9]


def test_campbell_eigenvalues_are_roots_of_the_rational_pencil(model):
    result = rdm.campbell(model, rdm.rpm(np.linspace(0, 3000, 31)))
    for k in (0, 15, 30):
        roots = _off_pole(model, result.eigenvalues[k])
        assert len(roots) >= 12  # at least the six oscillating modes and their relaxations
        for lam in roots:
            singular = np.linalg.svd(_pencil(model, lam, result.speeds[k]), compute_uv=False)
            assert singular[-1] / singular[0] < 1e-10


def test_modal_eigenvalues_equal_the_state_space_poles(model):
    speed = rdm.rpm(1500)
    modes = rdm.modal(model, speed)
    poles = model.state_space(speed).poles()
    upper = np.sort_complex(poles[poles.imag > 1e-6])
    found = np.sort_complex(modes.eigenvalues[modes.oscillatory])
    np.testing.assert_allclose(found, upper, rtol=1e-10)


def test_rubber_stiffens_the_modes_against_static_stiffness(model, examples_dir):
    static = rdm.modal(rdm.load_model(examples_dir / "gear_machine.toml"), 0.0)
    rubber = rdm.modal(model, 0.0)
    assert rubber.oscillatory.sum() == static.oscillatory.sum() == 6
    assert np.all(rubber.frequencies_hz[rubber.oscillatory] > static.frequencies_hz[static.oscillatory])
