"""The dense steps around the eigen-solutions run with one BLAS thread, as the solves do (issue 27
§1.9; rotordyn_modal/_blas.py): the mass matrix's inverse and the state matrices' products, the
Cholesky factors of the mass matrix, the undamped frequencies of the CPU-time estimate. On this
shared machine OpenBLAS's own threads made them 1.4-6 times slower (benchmarks/README.md).

Each LAPACK routine is replaced by a spy that records how many threads BLAS would use at that
moment (threadpoolctl's own account), then runs the routine.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_large_machine_cli import chained_gear_toml  # noqa: E402

#: checks BLAS's threads in the test process: with OpenBLAS's own, not the one conftest.py holds it to
pytestmark = pytest.mark.blas_threads


def _blas_threads():
    from threadpoolctl import threadpool_info

    return max(library["num_threads"] for library in threadpool_info() if library["user_api"] == "blas")


@pytest.fixture
def chain(tmp_path):
    """20 rotors on bearings chained by gears: 86 coordinates, enough for BLAS to start threads."""
    pytest.importorskip("threadpoolctl")
    import scipy.linalg  # noqa: F401 - its OpenBLAS loaded before the count

    if _blas_threads() < 2:
        pytest.skip("BLAS runs one thread here anyway")
    path = tmp_path / "chain.toml"
    path.write_text(chained_gear_toml(20, 20))
    model = rdm.load_model(path)
    assert model.dofs.n == 86
    return model


def _spied(monkeypatch, *targets):
    """Replace each (module, name) by a spy; returns the list of (name, threads) it fills."""
    seen = []
    for module, name in targets:
        original = getattr(module, name)

        def spy(*args, _original=original, _name=name, **kwargs):
            seen.append((_name, _blas_threads()))
            return _original(*args, **kwargs)

        monkeypatch.setattr(module, name, spy)
    return seen


def test_the_state_matrices_are_made_with_one_blas_thread(chain, monkeypatch):
    """``inv(M)``, its check ``inv(M) @ M`` and the products ``-inv(M) K``, ``-inv(M) C``,
    ``-inv(M) G`` (the spy on ``with_branch_states``, called right after them) with one thread."""
    from rotordyn_modal import linear_system

    seen = _spied(monkeypatch, (np.linalg, "inv"), (linear_system, "with_branch_states"))
    form = linear_system.speed_linear_form(chain)
    assert form.A0.shape == (172, 172)
    assert seen == [("inv", 1), ("with_branch_states", 1)]


def test_the_mass_factors_and_the_estimates_frequencies_use_one_blas_thread(chain, monkeypatch):
    """The Cholesky factor of the sweep's stack and of the mass-normalised shapes, and the
    undamped frequencies (``scipy.linalg.eigh``) of the CPU-time estimate."""
    import scipy.linalg

    from rotordyn_modal.analysis import _stack, _vectors, _work

    seen = _spied(monkeypatch, (np.linalg, "cholesky"), (scipy.linalg, "eigh"))
    stack = _stack.Stack([chain])
    assert stack.factor.shape == (1, 86, 86)
    M = chain.matrices(0.0)[0]
    _vectors.mass_normalized(np.eye(86, dtype=complex)[:3], M)
    frequencies = _work._undamped_frequencies(chain, 100.0)
    assert len(frequencies) == 86
    assert seen == [("cholesky", 1), ("cholesky", 1), ("eigh", 1)]
