"""Large models keep M, C, G, K sparse (issue 28 item 4, issue 27 item 1.9): above
``assembly.SPARSE_DOF`` coordinates the FRFs, unbalance responses and lowest modes never form the
model's dense ``n x n`` matrices or the mass inverse, and give what the dense route gives.

Truth from outside the code under test: the dense assembly (the route every small model takes)
and its results, array sizes counted by tracemalloc in units of one dense ``n x n`` float array."""

from __future__ import annotations

import glob
import tomllib
import tracemalloc
import warnings

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal import assembly, linear_system
from rotordyn_modal.analysis import _lowest, _stack, _whirl
from rotordyn_modal.analysis import frf as frf_module
from rotordyn_modal.elements import mounts

from test_flexible_large import _on_bearings
from test_pedestals_meshes import _flexible_on_pedestals, _geared


def _models():
    """Every example that loads, a flexible rotor on pedestals with a gear mesh, and geared rigid rotors."""
    models = []
    for path in sorted(glob.glob("examples/*.toml")):
        try:
            models.append(rdm.load_model(path))
        except rdm.InputError:            # the journal bearings' models at rest
            continue
    return models + [rdm.Model.from_dict(_flexible_on_pedestals()),
                     rdm.Model.from_dict(_geared({"mesh_stiffness": 1e8, "mesh_damping": 100.0}))]


def test_sparse_matrices_and_whirl_forms_equal_the_dense_ones():
    """``sparse_constant_matrices`` and ``sparse_whirl_forms`` sum the same pieces as the dense
    assembly: equal to round-off on every example, pedestals, meshes and flexible rotors."""
    for model in _models():
        for dense, sparse in [*zip(assembly.constant_matrices(model), assembly.sparse_constant_matrices(model)),
                              *zip(_whirl.whirl_forms(model), _whirl.sparse_whirl_forms(model))]:
            assert sparse.shape == dense.shape
            assert np.abs(sparse.toarray() - dense).max() <= 1e-15 * max(np.abs(dense).max(), 1e-300), model.source


def _no_dense(monkeypatch, threshold=100):
    """Make every way to the model's dense matrices, mass inverse, whirl forms and Maxwell
    branches' ``n x n`` arrays fail (models above ``threshold`` coordinates kept sparse)."""
    def refuse(*args, **kwargs):
        pytest.fail("a dense n x n matrix of the model was formed")

    monkeypatch.setattr(assembly, "SPARSE_DOF", threshold, raising=False)
    monkeypatch.setattr(frf_module, "SPARSE_FRF_DOF", threshold)
    for module in (assembly, frf_module, linear_system):
        monkeypatch.setattr(module, "constant_matrices", refuse)
    monkeypatch.setattr(linear_system, "_mass_inverse", refuse)
    monkeypatch.setattr(_whirl, "whirl_forms", refuse)
    if isinstance(getattr(linear_system.SpeedLinearForm, "matrices", None), property):   # made on first use
        monkeypatch.setattr(linear_system.SpeedLinearForm, "matrices", property(refuse))
    monkeypatch.setattr(_stack.Stack, "factor", property(refuse))
    monkeypatch.setattr(_stack.Stack, "_constant_part", refuse)       # the stack's dense M, C, G, K
    for module in (mounts, linear_system):                              # a Maxwell branch's n x n array
        monkeypatch.setattr(module, "frame_block", refuse, raising=False)


def test_a_large_model_gives_the_dense_routes_roots_frfs_and_unbalance_without_its_dense_matrices(monkeypatch):
    """A shaft of 40 elements (164 coordinates) with the threshold put at 100: its 6 lowest roots,
    whirl ratios and critical speeds, FRFs and unbalance response are the dense route's to 1e-9;
    the lowest modes' sweep, its critical speeds (their refinement's sparse LUs, repeated roots'
    whirl forms), the FRFs and the unbalance response never form its dense M, C, G, K, mass
    inverse, whirl forms or M's Cholesky factor."""
    speeds = np.linspace(50.0, 600.0, 6)

    def sweep(model, critical):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return rdm.campbell(model, speeds, modes=6, orders=(1, 2), critical=critical)

    def results(model):
        # the direct engine (dense solves below the threshold), as the sparse route: the modal
        # engine's eig of 2n states costs more than all the rest here
        return (rdm.frf(model, 300.0, [5.0, 60.0, 200.0], engine="direct").H,
                rdm.unbalance_response(model, [150.0, 300.0]).response)

    model = _on_bearings(40, sensors=True)
    dense, dense_results = sweep(model, True), results(model)
    mass = assembly.constant_matrices(model).M
    _no_dense(monkeypatch)
    model = _on_bearings(40, sensors=True)
    assert model.dofs.n > 100
    assert linear_system.speed_linear_form(model).sparse is not None
    sparse = sweep(model, True)
    crossings = sparse.critical
    assert len(dense.critical) > 3 and len(crossings) == len(dense.critical)
    assert np.allclose(crossings.speeds, dense.critical.speeds, rtol=1e-9, atol=0)
    assert np.abs(sparse.eigenvalues - dense.eigenvalues).max() <= 1e-9 * np.abs(dense.eigenvalues).max()
    assert np.abs(sparse.whirl_ratios - dense.whirl_ratios).max() <= 1e-9
    for a, b in zip(results(model), dense_results):
        assert np.abs(a - b).max() <= 1e-9 * np.abs(b).max()
    # the shapes weighted for tracking (without M's Cholesky factor) keep the products x^H M y
    stack = _stack.Stack([model])
    _, shapes, _ = _lowest.lowest_roots(stack, speeds[1:3], 3)
    weighted = stack.weighted(shapes, np.zeros(2, int))
    products = np.einsum("sai,ij,sbj->sab", shapes.conj(), mass, shapes)
    norms = np.sqrt(np.einsum("saa->sa", products).real)
    assert np.allclose(np.einsum("sai,sbi->sab", weighted.conj(), weighted),
                       products / (norms[:, :, None] * norms[:, None, :]), rtol=0, atol=1e-9)


def _peak(call) -> float:
    """The peak memory traced while ``call()`` runs [bytes]."""
    tracemalloc.start()
    try:
        call()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_frf_unbalance_and_lowest_modes_of_a_large_model_stay_below_dense_matrices(monkeypatch):
    """A shaft of 250 elements (1,012 coordinates) above the threshold: an FRF at 20 frequencies
    and an unbalance response at 20 speeds peak below half of one dense ``n x n`` array (the dense
    route held four, M, C, G, K, and solved n x n systems); the lowest modes' sweep peaks at the
    basis's eigh (its K, M, modes and LAPACK's work space: about 4 arrays; the dense route held
    the model's matrices, M^-1 and its check, whirl forms and M's Cholesky factor beside it: 10)."""
    monkeypatch.setattr(assembly, "SPARSE_DOF", 1000, raising=False)
    monkeypatch.setattr(frf_module, "SPARSE_FRF_DOF", 1000)
    model = _on_bearings(250, sensors=True)
    n = model.dofs.n
    unit = 8.0 * n * n
    assert n > 1000
    freqs, speeds = np.linspace(1.0, 200.0, 20), np.linspace(10.0, 600.0, 20)

    def lowest():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rdm.campbell(model, np.linspace(100.0, 600.0, 3), modes=6, critical=False)

    for call in (lambda: rdm.frf(model, 300.0, freqs[:2]), lambda: rdm.unbalance_response(model, speeds[:2])):
        call()                            # the modules' imports and caches are not the analysis's memory
    peaks = [_peak(call) / unit for call in (lambda: rdm.frf(model, 300.0, freqs),
                                             lambda: rdm.unbalance_response(model, speeds), lowest)]
    assert peaks[0] < 0.5 and peaks[1] < 0.5 and peaks[2] < 6.0, peaks


@pytest.mark.parametrize("name", ["rubber_mounts", "journal_rotor", "flexible_pump_on_mounts"])
def test_sparse_frfs_with_losses_branches_and_speed_dependent_bearings_equal_the_dense_solves(name, monkeypatch):
    """The sparse FRF route (forced on small models) adds the loss factors (given to every mount
    of the flexible pump), the Maxwell branches (rubber mounts) and the speed-dependent bearings
    (journals) as the dense ``Z(w)`` has them: the same receptances to 1e-9 as the dense direct
    solves."""
    with open(f"examples/{name}.toml", "rb") as file:
        data = tomllib.load(file)
    if name == "flexible_pump_on_mounts":
        for suspension in data["suspensions"]:
            suspension["loss_factor"] = 0.15
    model = rdm.Model.from_dict(data)
    assert name != "flexible_pump_on_mounts" or all(s.loss_factor for s in model.suspensions)
    freqs, speed = np.linspace(2.0, 300.0, 7), 300.0
    dense = rdm.frf(model, speed, freqs, engine="direct").H
    monkeypatch.setattr(frf_module, "SPARSE_FRF_DOF", 0)
    monkeypatch.setattr(frf_module, "dynamic_stiffness", None)          # no dense Z on this route
    sparse = rdm.frf(model, speed, freqs, engine="direct").H
    assert np.abs(sparse - dense).max() <= 1e-9 * np.abs(dense).max()


def test_the_lowest_routes_undamped_modes_weight_a_large_models_shapes(monkeypatch):
    """``Stack.undamped_modes``: None until the lowest modes' route ran on the stack, then its
    basis's every undamped mode, mass-orthonormal (``Phi^T M Phi = I`` with the dense assembly's
    M); a large model's shapes are then weighted by it (``F^T x``, ``F = M Phi``), never by M's
    Cholesky factor, with the same products ``x^H M y`` (issue 28 item 4: the weighting asked the
    lowest route's cache by its attribute name)."""
    monkeypatch.setattr(assembly, "SPARSE_DOF", 100, raising=False)
    model = _on_bearings(40)
    mass = assembly.constant_matrices(model).M
    stack = _stack.Stack([model])
    assert stack.undamped_modes is None
    _, shapes, _ = _lowest.lowest_roots(stack, np.array([100.0, 300.0]), 3)
    modes = stack.undamped_modes
    assert modes.shape == (model.dofs.n, model.dofs.n)
    assert np.abs(modes.T @ mass @ modes - np.eye(model.dofs.n)).max() <= 1e-9
    monkeypatch.setattr(_stack.Stack, "factor", property(lambda self: pytest.fail("M's Cholesky factor")))
    weighted = stack.weighted(shapes, np.zeros(2, int))
    products = np.einsum("sai,ij,sbj->sab", shapes.conj(), mass, shapes)
    norms = np.sqrt(np.einsum("saa->sa", products).real)
    assert np.allclose(np.einsum("sai,sbi->sab", weighted.conj(), weighted),
                       products / (norms[:, :, None] * norms[:, None, :]), rtol=0, atol=1e-9)


def _journals():
    """examples/compressor_on_journals.toml meshed at 8 cm (133 coordinates): speed-dependent bearings."""
    with open("examples/compressor_on_journals.toml", "rb") as file:
        data = tomllib.load(file)
    data["rotors"][0]["element_length"] = 0.08
    return rdm.Model.from_dict(data)


def _on_maxwell_mounts():
    """examples/flexible_pump_on_mounts.toml (68 coordinates) with two Maxwell branches on each mount."""
    with open("examples/flexible_pump_on_mounts.toml", "rb") as file:
        data = tomllib.load(file)
    for mount in data["suspensions"]:
        k = np.asarray(mount["stiffness"])
        mount["maxwell_stiffness"] = [(0.5 * k).tolist(), k.tolist()]
        mount["maxwell_time"] = [0.02, 0.001]
    return rdm.Model.from_dict(data)


@pytest.mark.parametrize("make, rpm, modes, threshold", [
    (_journals, (1000.0, 12000.0, 5), 4, 100), (_on_maxwell_mounts, (0.0, 6000.0, 4), 8, 50)],
    ids=["journal bearings", "maxwell mounts"])
def test_critical_speeds_of_a_large_model_are_refined_on_its_sparse_pencils(make, rpm, modes, threshold,
                                                                            monkeypatch):
    """Above the threshold (lowered) the crossings of the lowest modes are refined on the sparse
    pencils (SuperLU of speed-dependent journal bearings' pencils at each trial speed; the Maxwell
    branches' rational pencil, its shapes at the roots by its banded LU): the critical speeds, their
    frequencies and whirl ratios are the dense route's to 1e-9, and no dense n x n matrix of the
    model is formed (issue 28 item 4)."""
    from rotordyn_modal.analysis import _pencils

    speeds = np.linspace(*rpm) * np.pi / 30

    def crossings(model):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return rdm.campbell(model, speeds, modes=modes, orders=(1,), critical=True).critical

    dense = crossings(make())
    monkeypatch.setattr(_pencils, "SPARSE_DOF", 0)       # the pencils' sparse LU at these sizes
    _no_dense(monkeypatch, threshold)
    model = make()
    assert model.dofs.n > threshold
    sparse = crossings(model)
    assert len(dense) >= 2 and len(sparse) == len(dense) and list(sparse.mode) == list(dense.mode)
    assert np.abs(sparse.speeds - dense.speeds).max() <= 1e-9 * dense.speeds.max()
    assert np.abs(sparse.frequencies_hz - dense.frequencies_hz).max() <= 1e-9 * dense.frequencies_hz.max()
    assert np.abs(sparse.whirl_ratios - dense.whirl_ratios).max() <= 1e-9


def test_the_crossings_memory_estimate_of_a_large_lowest_sweep_bounds_its_measured_peak():
    """``critical-speeds shaft2000.toml --speeds 0:6000:11 --lowest 6`` (the 4 m shaft of 2,000
    elements, 8,004 coordinates kept sparse; benchmarks/README.md, "Sparse Maxwell branches and
    crossings"): its sweep peaked at 2.149 GB of RSS (the basis's eigh), and its 4 crossings are
    refined on the sparse pencils. The estimate that decides whether they may be refined bounds
    that peak within a factor 2; it counted the dense matrices, refinement and state eigen-solver
    the route no longer makes and refused them for 28.9 GiB with 16.1 GiB at hand."""
    from rotordyn_modal.analysis import campbell as campbell_module

    measured = 2_149_164 * 1024.0
    needed = campbell_module.memory_estimate(8004, 16008, 11, 1, True, 4, 7, sparse=True)
    assert measured <= needed <= 2 * measured
    assert campbell_module.memory_estimate(8004, 16008, 11, 1, True, 4, 7) > 8 * measured      # dense: as before
