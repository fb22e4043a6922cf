"""Models and reference roots the lowest-modes tests share (each was written in several files).

``fan_shaft`` is benchmarks/bench_flexible.py's fan shaft alone; ``lowest_state_roots`` are the
reference a reduced route is checked against: scipy's eigenvalues of the full state matrix."""

from __future__ import annotations

import contextlib

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm


def fan_shaft(coordinates: int = 60) -> rdm.Model:
    """A uniform steel shaft (0.8 m, 40 mm) with a 4 kg wheel at mid-span on two damped bearings
    (2e7 N/m, 500 N s/m), spinning at the reference speed: ``coordinates`` lateral coordinates (4
    per node)."""
    elements = coordinates // 4 - 1
    section = {"length": 0.4, "outer_diameter": 0.04, "material": "steel"}
    return rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "fan", "start": [0.0, 0.0, 0.0], "speed_ratio": 1.0,
                    "shaft": [dict(section, elements=elements // 2), dict(section, elements=elements - elements // 2)],
                    "disks": [{"name": "wheel", "axial_position": 0.4, "mass": 4.0, "polar_inertia": 0.25,
                               "diametral_inertia": 0.13}]}],
        "bearings": [{"name": name, "rotor": "fan", "axial_position": z, "stiffness": 2e7, "damping": 500.0}
                     for name, z in (("A", 0.0), ("B", 0.8))]})


def one_blas_thread():
    """A context of one BLAS thread (threadpoolctl), where BLAS's own threads would only wait for
    a core on a loaded machine; nothing without threadpoolctl."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


def assert_lowest_are_the_full_models(model, speed, got, count=12, rtol=1e-9, blas_context=one_blas_thread):
    """Assert that ``got`` (count,) are the ``count`` lowest roots (Im > 0) of scipy's eigenvalues of
    the full state matrix at ``speed`` [rad/s]: each to ``rtol`` of its nearest, their frequencies the
    lowest ``count`` to ``rtol``."""
    M, C, G, K = model.matrices(speed)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C + speed * G)]])
    with blas_context():
        roots = scipy.linalg.eigvals(A)
    roots = roots[roots.imag > 0]
    expected = np.sort(roots[np.argsort(roots.imag)[:count]].imag)
    nearest = roots[np.argmin(np.abs(got[:, None] - roots[None, :]), axis=1)]
    assert np.max(np.abs(got - nearest) / np.abs(nearest)) < rtol
    assert np.allclose(np.sort(got.imag), expected, rtol=rtol, atol=0)
