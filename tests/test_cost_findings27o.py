"""The review's cost findings (issue 27 §1.9: memory bounded at every size, no work done twice).

1. ``unbalance_response``'s ``resonance_response`` solved every unbalance source at every
   source's damped critical speeds and kept each source's own: the systems solved are recorded
   here, and no source is solved at a speed that only another source needs.
2. ``_lowest_newton._exact_sums`` held (n, 2n, 2k) arrays at once (about 2 GB at n = 2,000,
   k = 4): its peak memory, counted by tracemalloc, stays within its parts' budget, and the parts
   give the same bits as one part (each row's sums are its own).
3. A command builds the model's linear form (``SpeedLinearForm``) once.
"""

from __future__ import annotations

import math
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _batches, _lowest_newton
from rotordyn_modal.analysis import unbalance as unbalance_module

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _recorded_solves(monkeypatch):
    """Every system ``(speed, omega)`` [rad/s] the unbalance response hands to the direct solve."""
    solved = []
    original = unbalance_module.dof_response

    def recorded(model, speed, omega, forces, terms=None):
        solved.extend(zip(np.broadcast_to(speed, np.shape(omega)).tolist(), np.asarray(omega).tolist()))
        return original(model, speed, omega, forces, terms)

    monkeypatch.setattr(unbalance_module, "dof_response", recorded)
    return solved


def test_each_unbalance_source_is_solved_only_at_its_own_damped_critical_speeds(monkeypatch):
    model = rdm.load_model(EXAMPLES / "fan_on_bearings.toml")       # fan (r = 0.625) and motor (r = 1)
    speeds = rdm.rpm(np.linspace(500.0, 9000.0, 18))
    solved = _recorded_solves(monkeypatch)
    result = rdm.unbalance_response(model, speeds)
    ratios = np.abs([model.rotor(name).speed_ratio for name in result.sources])
    assert len(set(ratios)) == len(ratios) == 2             # a system's source is told by omega / speed
    own = [set(row[np.isfinite(row)].tolist()) for row in result.resonance_speeds]
    assert all(own), own                                     # each source has damped critical speeds here
    others = [set().union(*(own[i] for i in range(len(own)) if i != j)) - own[j] - set(speeds.tolist())
              for j in range(len(own))]
    wasted = []
    for speed, omega in solved:
        j = int(np.argmin(np.abs(omega / abs(speed) - ratios)))
        assert omega == pytest.approx(ratios[j] * abs(speed), rel=1e-12)
        if speed in others[j]:
            wasted.append((result.sources[j], speed))
    assert wasted == []
    # and each source's value there is its own response, as a sweep through that speed gives it
    for j, row in enumerate(result.resonance_speeds):
        at = row[np.isfinite(row)]
        alone = rdm.unbalance_response(model, at, resonances=False).response[:, j, :]
        np.testing.assert_array_equal(result.resonance_response[:, j, :len(at)], alone)


def _matrix_and_shapes(n, k, seed=3):
    """A double matrix (n, n) whose entries span twelve decades and shapes (n, k), complex."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) * 10.0 ** rng.uniform(-6.0, 6.0, (n, n))
    X = rng.standard_normal((n, k)) + 1j * rng.standard_normal((n, k))
    return A, X


def test_exact_sums_work_in_parts_of_bounded_memory_with_the_same_bits(monkeypatch):
    n, k = 300, 2
    A, X = _matrix_and_shapes(n, k)
    monkeypatch.setattr(_batches, "_PART_BYTES", 2**40)        # one part: every row at once
    whole = _lowest_newton._exact_sums(A, X)
    budget = 2 * 2**20
    monkeypatch.setattr(_batches, "_PART_BYTES", budget)
    tracemalloc.start()
    try:
        parts = _lowest_newton._exact_sums(A, X)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    # the terms alone of every row at once: (n, 2n, 2k) doubles, 5.8 MB; the result (n, k) 9.6 kB
    assert peak <= 1.5 * budget, peak
    np.testing.assert_array_equal(parts, whole)
    # the sums themselves, against math.fsum of the exact products (Dekker): within the promise
    for i in range(0, n, 37):
        for c in range(k):
            for part, take in ((X[:, c].real, np.real), (X[:, c].imag, np.imag)):
                terms = [t for a, b in zip(A[i], part) for t in _exact_terms(a, b)]
                exact = math.fsum(terms)
                magnitude = math.fsum(abs(a * b) for a, b in zip(A[i], part))
                got = take(parts[i, c])
                assert abs(got - exact) <= np.finfo(float).eps * (abs(exact) + n * np.finfo(float).eps * magnitude)


def _exact_terms(a, b):
    """The product ``a b`` of two doubles as two doubles summing to it exactly (Dekker's TwoProduct,
    written here apart from the code under test)."""
    def split(x):
        c = 134217729.0 * x
        high = c - (c - x)
        return high, x - high

    p = a * b
    (ah, al), (bh, bl) = split(a), split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def test_a_simulation_of_a_large_machine_builds_its_linear_form_once(monkeypatch):
    """The rate's and the steps' bounds (ARPACK) and, where a check refuses on them, their exact
    values (dense eigen-solutions) each built the form: four times (review_io)."""
    import importlib
    import tomllib

    from rotordyn_modal import linear_system
    from rotordyn_modal.errors import InputError
    from test_large_machine_cli import chained_gear_toml

    simulate_module = importlib.import_module("rotordyn_modal.simulation.simulate")
    tap = '\n[[excitations]]\nname = "tap"\nposition = [0.0, 0.0, 0.4]\ndirection = [0.0, 0.0, 1.0]\n'
    model = rdm.Model.from_dict(tomllib.loads(chained_gear_toml(10, 10) + tap), source="chain.toml")
    monkeypatch.setattr(simulate_module, "_SMALL_DOF", 40)              # the large machine's checks, at 46
    builds, checks = [], []
    original = linear_system.SpeedLinearForm.__init__

    def counted(self, *args, **kwargs):
        builds.append(1)
        original(self, *args, **kwargs)

    def refused(*args, **kwargs):             # every CPU check refuses: the bounds, then the exact values
        checks.append(1)
        raise InputError("refused")

    monkeypatch.setattr(linear_system.SpeedLinearForm, "__init__", counted)
    monkeypatch.setattr(simulate_module, "_check_before_eigenvalues", lambda *args: None)
    monkeypatch.setattr(simulate_module, "_check_cpu_time", refused)
    monkeypatch.setenv("ROTORDYN_MODAL_MAX_CPU_MINUTES", "1000")          # a limit in force: the steps are read
    with pytest.raises(InputError, match="^refused$"):
        rdm.simulate(model, 1e-3, speed=100.0, samples=3, impulse="tap", backend="numpy")
    assert checks                             # the exact values made (main: four builds, ARPACK's bounds or not)
    assert len(builds) == 1
