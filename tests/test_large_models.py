"""Campbell diagrams of machines with many coordinates (many rotors on bearings).

The batched eigen-solver takes the mode shapes from LAPACK's eigenvectors (or, with Maxwell
states, from inverse iteration on the rational pencil) and splits large batches into parts
of bounded memory over threads. Checked here: machines with more than 64 coordinates
against the independent absolute-coordinate reference (eigenvalues, whirl), the rational
pencil's shapes beyond 64 coordinates, and results that do not depend on how a sweep is
split into parts and threads.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import rotordyn_modal as rdm
from reference_bearings import BearingMachine, random_bearing_description
from rotordyn_modal.analysis import _batches
from rotordyn_modal.elements.mounts import maxwell_branches


def _many_rotors(seed, n_rotors=14):
    """A random casing on mounts with ``n_rotors - 1`` rotors on two bearings each (five
    coordinates each) and one rigidly attached; spin ratios drawn in -2..2 (no gear chain,
    whose ratios would multiply up)."""
    rng = np.random.default_rng(seed)
    data = random_bearing_description(rng, n_rotors=n_rotors)
    data["transmissions"] = []
    for j, rotor in enumerate(data["rotors"]):
        rotor["speed_ratio"] = 1.0 if j == 0 else float(rng.choice([-1, 1]) * rng.uniform(0.3, 2.0))
    return data


@pytest.mark.parametrize("seed", [5, 6])
def test_machines_with_more_than_64_coordinates_equal_the_independent_reference(seed):
    data = _many_rotors(seed)
    model = rdm.Model.from_dict(data)
    assert model.dofs.n == 6 + 13 * 5
    reference = BearingMachine(data)
    speeds = np.array([-900.0, 0.0, 400.0, 1500.0])
    result = rdm.campbell(model, speeds, orders=())
    for k, speed in enumerate(speeds):
        values, shapes = reference.modes(speed)
        found = result.eigenvalues[k][result.oscillatory[k]]
        assert len(found) == len(values)
        i, j = linear_sum_assignment(np.abs(values[:, None] - found[None]))
        np.testing.assert_allclose(found[j], values[i], rtol=1e-9)
        ratios = np.array([reference.whirl_ratio(shapes[m], speed) for m in i])
        np.testing.assert_allclose(result.whirl_ratios[k][result.oscillatory[k]][j], ratios, atol=1e-6)


def test_shapes_beyond_64_coordinates_solve_the_rational_pencil_of_maxwell_mounts():
    data = _many_rotors(7)
    for mount in data["suspensions"]:
        mount["maxwell_stiffness"] = [(0.4 * np.asarray(mount["stiffness"])).tolist()]
        mount["maxwell_time"] = [0.004]
    model = rdm.Model.from_dict(data)
    M, C, G, K = model.matrices()
    stiffness, times = maxwell_branches(model)
    speeds = np.array([0.0, 700.0])
    result = rdm.campbell(model, speeds, orders=())
    checked = 0
    for k, speed in enumerate(speeds):
        for lam, phi in zip(result.eigenvalues[k], result.shapes[k]):
            if np.min(np.abs(1 + lam * times)) < 1e-9:
                continue  # a junction's internal relaxation: no motion of the coordinates
            branch = np.einsum("b,bij->ij", lam * times / (1 + lam * times), stiffness)
            pencil = lam**2 * M + lam * (C + speed * G) + K + branch
            residual = np.linalg.norm(pencil @ phi) / (np.linalg.norm(pencil) * np.linalg.norm(phi))
            assert residual < 1e-9
            checked += 1
    assert checked >= 2 * 71


def test_results_do_not_depend_on_how_the_sweep_is_split(monkeypatch):
    model = rdm.Model.from_dict(_many_rotors(8, n_rotors=4))
    speeds = np.linspace(0.0, 1200.0, 600)
    whole = rdm.campbell(model, speeds)
    monkeypatch.setattr(_batches, "_PART_BYTES", 1)  # one speed per part, over the threads
    for threads in ("1", "2"):
        monkeypatch.setenv("ROTORDYN_MODAL_THREADS", threads)
        parts = rdm.campbell(model, speeds)
        np.testing.assert_array_equal(parts.eigenvalues, whole.eigenvalues)
        np.testing.assert_array_equal(parts.shapes, whole.shapes)
        np.testing.assert_array_equal(parts.critical.speeds, whole.critical.speeds)
