"""The unbalance peaks' refinement assembles the model's matrices once per response, and its dense
solves run on one BLAS thread (issue 27 §1.9, issue 29 §7).

On a chain of geared rotors the report's time went mostly to the refinement of the peaks that
the swept line cuts (``unbalance_peaks.cut_maxima``): it calls ``frf.dof_response`` about 40
times per API case, and each call assembled the model's constant matrices again; its batched
``numpy.linalg.solve`` ran OpenBLAS's own threads, which on a shared machine burn CPU at every
speed. What is checked here is counted (matrix assemblies, BLAS threads during the solves), not
timed.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import frf as frf_module
from rotordyn_modal.analysis import unbalance as unbalance_module

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

UNBALANCES = """
[[unbalances]]
rotor = "r000"
amount = 2.0e-4
phase_deg = 0.0

[[unbalances]]
rotor = "r005"
amount = 5.0e-5
phase_deg = 90.0
axial_offset = 0.05

[[sensors]]
name = "acc-top-z"
position = [0.0, 0.0, 0.5]
direction = [0.0, 0.0, 1.0]
"""


def test_the_peak_refinement_assembles_the_matrices_once(tmp_path, monkeypatch):
    """A 6-rotor chain swept at 21 speeds: the response is refined at many cut peaks (dozens of
    ``dof_response`` calls), and the model's stiffness terms are assembled at most three times
    (the sweep, the damped critical speeds' response, the refinement), not once per call."""
    path = tmp_path / "chain6.toml"
    path.write_text(chained_gear_toml(6, 6) + UNBALANCES)
    model = rdm.load_model(path)
    built, solved = [], []
    real_terms, real_response = frf_module._StiffnessTerms, unbalance_module.dof_response

    class Counted(real_terms):
        def __init__(self, *args, **kwargs):
            built.append(1)
            super().__init__(*args, **kwargs)

    def counted_response(*args, **kwargs):
        solved.append(1)
        return real_response(*args, **kwargs)

    monkeypatch.setattr(frf_module, "_StiffnessTerms", Counted)
    monkeypatch.setattr(unbalance_module, "dof_response", counted_response)
    result = rdm.unbalance_response(model, rdm.rpm(np.linspace(100.0, 4500.0, 21)), resonances=True)
    assert np.isfinite(result.cut_peak_speeds).sum() >= 2        # peaks were refined
    assert len(solved) >= 20                                     # by many calls of the response
    assert len(built) <= 3, f"{len(built)} assemblies for {len(solved)} responses"


def test_the_dense_solves_run_on_one_blas_thread(monkeypatch):
    """compressor_rotor (53 coordinates, above the size where BLAS starts threads): every dense
    solve of ``dof_response`` runs with BLAS held to one thread, as the dense eigen-solutions."""
    threadpoolctl = pytest.importorskip("threadpoolctl")
    model = rdm.load_model(EXAMPLES / "compressor_rotor.toml")
    assert model.dofs.n >= 48
    threads = []
    real_solve = np.linalg.solve

    def counted_solve(a, b):
        threads.append(max((lib["num_threads"] for lib in threadpoolctl.threadpool_info()
                            if lib["user_api"] == "blas"), default=1))
        return real_solve(a, b)

    monkeypatch.setattr(np.linalg, "solve", counted_solve)
    n = model.dofs.n
    forces = np.zeros((n, 1))
    forces[0, 0] = 1.0
    q = frf_module.dof_response(model, 100.0, np.linspace(10.0, 500.0, 8), forces)
    assert q.shape == (8, n, 1) and np.all(np.isfinite(q))
    assert threads and max(threads) == 1, threads
