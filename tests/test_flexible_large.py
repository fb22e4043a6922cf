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
    assert f"at most {flexible.MAX_NODES} nodes" in message and f"make {count} elements" in message
    assert f"{4 * (count + 1)} coordinates" in message      # what the mesh would cost, 4 per node
    assert flexible.MAX_NODES >= 2500


def _on_bearings(count, sensors=False):
    """A 4 m uniform shaft of ``count`` elements with a disk at 1.2 m on two damped bearings near
    its ends (a sensor and an excitation at the disk when ``sensors``)."""
    data = _pinned(count, shear="cowper")
    data["rotors"][0]["disks"] = [{"name": "d", "axial_position": 1.2, "mass": 20.0, "polar_inertia": 0.3,
                                   "diametral_inertia": 0.16}]
    data["bearings"] = [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 1e8, "damping": 2000.0}
                        for n, z in (("a", 0.2), ("b", 3.8))]
    data["unbalances"] = [{"rotor": "s", "axial_position": 1.2, "amount": 1e-3}]
    if sensors:
        data["sensors"] = [{"name": "p", "rotor": "s", "axial_position": 1.2, "direction": [0, 1, 0]}]
        data["excitations"] = [{"name": "f", "rotor": "s", "axial_position": 1.2, "direction": [0, 1, 0]}]
    return rdm.Model.from_dict(data)


def test_lowest_roots_of_a_fine_mesh_are_refined_without_the_full_solve():
    """A 300-element shaft at 600 rpm: Newton's steps on its lowest roots stall at about 1e-9 of
    them (the stiffness's conditioning), above the step that ended the iteration before, so the
    speed was solved whole; now taken at that round-off. Each root is the pencil's own: the nearest
    root to it of the linearised pencil, by scipy's sparse shift-invert Arnoldi (no code shared)."""
    import warnings

    from rotordyn_modal.analysis import _lowest
    from rotordyn_modal.analysis._stack import Stack

    model = _on_bearings(300)
    speed = 600 * np.pi / 30
    with warnings.catch_warnings():
        warnings.simplefilter("error")                          # no "solved whole" warning
        lam, _, full = _lowest.lowest_roots(Stack([model]), np.array([speed]), 6)
    assert not full.any()
    M, C, G, K = (scipy.sparse.csc_matrix(m) for m in model.matrices())
    n = M.shape[0]
    eye = scipy.sparse.identity(n, format="csc")
    A = scipy.sparse.bmat([[None, eye], [-K, -(C + speed * G)]], format="csc").astype(complex)
    B = scipy.sparse.bmat([[eye, None], [None, M]], format="csc").astype(complex)
    for root in lam[0]:
        nearest = scipy.sparse.linalg.eigs(A, k=1, M=B, sigma=root, which="LM", return_eigenvectors=False)[0]
        assert abs(nearest - root) <= 1e-8 * abs(root)
    # forward and backward whirl of the three lowest bending pairs, apart by the gyroscopic split
    assert np.all(np.diff(lam[0].imag) > 0)


def test_frf_and_unbalance_of_a_long_mesh_by_sparse_solves_equal_the_dense_ones(monkeypatch):
    """Above ``SPARSE_FRF_DOF`` coordinates the direct engine solves each frequency by a sparse LU:
    the same responses as the dense solves of the same model."""
    from rotordyn_modal.analysis import frf as frf_module

    model = _on_bearings(40, sensors=True)
    freqs = [5.0, 14.0, 60.0, 200.0]
    dense = rdm.frf(model, 300.0, freqs, engine="direct").H
    unbalance = rdm.unbalance_response(model, [150.0, 300.0]).response
    monkeypatch.setattr(frf_module, "SPARSE_FRF_DOF", 10)
    sparse = rdm.frf(model, 300.0, freqs)
    assert sparse.engine == "direct"
    assert np.allclose(sparse.H, dense, rtol=1e-9, atol=1e-12 * np.abs(dense).max())
    again = rdm.unbalance_response(model, [150.0, 300.0]).response
    assert np.allclose(again, unbalance, rtol=1e-9, atol=1e-12 * np.abs(unbalance).max())


def test_modes_refuses_every_root_beyond_the_cpu_limit_with_its_estimate(monkeypatch, capsys):
    """``modes`` solves every root (one dense eigen-solution of 2n states: hours for a shaft of
    thousands of nodes): over the CPU limit it is refused before the work, with the estimate;
    ``--allow-long`` runs it."""
    from rotordyn_modal.cli.main import main

    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1e-7")
    assert main(["modes", "examples/compressor_rotor.toml", "--speed", "0"]) == 2
    error = capsys.readouterr().err
    assert "this analysis of 53 coordinates would take" in error and "1 eigen-solution of 106 states" in error
    assert error.count("\n") == 1
    assert main(["modes", "examples/compressor_rotor.toml", "--speed", "0", "--allow-long", "--quiet"]) == 0
