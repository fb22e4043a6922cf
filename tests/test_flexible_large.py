"""Long flexible rotors (issue 28, "Size and speed"): meshes of hundreds to thousands of nodes
assembled from sparse node matrices. Truths from outside the code: the pinned-pinned uniform
Euler-Bernoulli beam's frequencies on a mesh above the old cap of 500 nodes (solved here by
scipy's sparse eigen-solver on the model's own M and K), the dense route of the first bending
frequencies against the sparse one, and the refusal of a mesh beyond the cap by key and value."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

import rotordyn_modal as rdm
from rotordyn_modal.errors import InputError
from rotordyn_modal.model import flexible

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}


def _pinned(count, length=4.0, diameter=0.1, shear="none", stiffness=1e15):
    """A uniform shaft of ``count`` elements on two point supports at its ends (radial springs
    ``stiffness``, no moment stiffness: pinned)."""
    return {"materials": [STEEL],
            "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0], "shear": shear,
                        "element_length": length / count,
                        "shaft": [{"length": length, "outer_diameter": diameter, "material": "steel"}]}],
            "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": stiffness} for n, z in
                         (("a", 0.0), ("b", length))]}


def test_pinned_shaft_of_600_nodes_has_the_euler_bernoulli_frequencies():
    """The lowest 6 frequencies (3 per plane) of a pinned-pinned uniform shaft meshed with 600
    elements (601 nodes, 2,404 coordinates: refused by the cap of 500 nodes before) equal
    ``w_k = (k pi / L)^2 sqrt(E I / (rho A))`` with rotary inertia (the element's consistent
    mass has it: the Rayleigh beam's ``1 + (I/A) beta^2`` in the denominator)."""
    length, diameter = 4.0, 0.1
    model = rdm.Model.from_dict(_pinned(600, length, diameter))
    assert model.rotors[0].flexible.mesh.n_nodes == 601
    M, _, _, K = (scipy.sparse.csc_matrix(m) for m in model.matrices())
    values = scipy.sparse.linalg.eigsh(K, k=6, M=M, sigma=0.0, which="LM", return_eigenvectors=False)
    found = np.sort(np.sqrt(values))
    area, second = np.pi / 4 * diameter ** 2, np.pi / 64 * diameter ** 4
    beta = np.arange(1, 4) * np.pi / length
    exact = np.sqrt(STEEL["young_modulus"] * second * beta ** 4
                    / (STEEL["density"] * area * (1 + second / area * beta ** 2)))
    # two planes: each frequency twice. The springs of 1e15 N/m lower the first by about 1e-8 of it;
    # the stiffness's conditioning, (L / h)^4 = 1.3e11, leaves its lowest eigenvalue about 1e-7 of
    # round-off (measured: 1e-8 with 400 elements, 1e-6 with 800, whatever the springs)
    assert found == pytest.approx(np.repeat(exact, 2), rel=1e-6)


def test_node_matrices_are_sparse_with_the_elements_band():
    """A shaft's node matrices store O(N) entries: each node couples to its neighbours only."""
    model = rdm.Model.from_dict(_pinned(200))
    M, K, G = flexible.node_matrices(model.rotors[0].flexible, model.rotors[0].flexible.mesh)
    for matrix in (M, K, G):
        assert scipy.sparse.issparse(matrix)
        rows, cols = matrix.nonzero()
        assert np.max(np.abs(rows // 6 - cols // 6)) == 1          # node i with i - 1, i, i + 1
        assert matrix.nnz <= 201 * 3 * 36


def test_sparse_first_bending_frequencies_equal_the_dense_ones(monkeypatch):
    """``check``'s first bending frequencies of a long mesh (shift-invert Lanczos on its lowest
    modes) equal those from every mode (dense eigh) of the same mesh."""
    model = rdm.Model.from_dict(_pinned(30, shear="cowper", stiffness=2e7))
    shaft = model.rotors[0].flexible
    supports = [(shaft.z_of(b.position), b.coefficients.stiffness[0]) for b in model.bearings]
    monkeypatch.setattr(flexible, "DENSE_BENDING", 10 ** 9)
    free, (lowest, share), bending = flexible.bending_frequencies(shaft, supports)
    monkeypatch.setattr(flexible, "DENSE_BENDING", 0)
    sparse_free, (sparse_lowest, sparse_share), sparse_bending = flexible.bending_frequencies(shaft, supports)
    assert sparse_free == pytest.approx(free, rel=1e-8)
    assert sparse_lowest == pytest.approx(lowest, rel=1e-8)
    assert sparse_share == pytest.approx(share, rel=1e-6)
    assert sparse_bending == pytest.approx(bending, rel=1e-8)
    assert free > 0 and 0 < share < 1


def test_a_mesh_beyond_the_cap_is_refused_by_key_and_value():
    count = flexible.MAX_NODES                 # count elements make count + 1 nodes: one too many
    data = _pinned(count)
    with pytest.raises(InputError) as caught:
        rdm.Model.from_dict(data)
    message = str(caught.value)
    assert "element_length" in message and f"{4.0 / count!r}"[:8] in message
    assert f"fewer than {flexible.MAX_NODES} nodes" in message and f"make {count} elements" in message
    data["rotors"][0]["element_length"] = 4.0 / (count - 1)       # count nodes: accepted (not built here)
    assert flexible.MAX_NODES >= 2500
