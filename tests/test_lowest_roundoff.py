"""The lowest modes' roots where double precision cannot give 1e-9 (issue 28, "Size and speed":
the full model's eigenvalues to 1e-9 relative).

A low mode beside stiff elements (a shaft of short elements on soft supports) makes the products
``K x`` of its smooth shape cancel to a small part of their terms: Newton's iteration on the double
pencil then stalls (``_lowest_newton._stagnant``) or converges to a nearby pencil's root, measured 2.5e-7 to
5.9e-7 off on the model below. The truth here is an independent solve: Newton's iteration on the
*linearised* pencil ``(A - s B) z = 0`` of the model's own ``M, C, G, K`` (``2n`` states, dense
LAPACK solves of the bordered system), its residual in numpy's extended precision, the root's
correction falling to its own round-off, 1e-11 here (iterative refinement: the accuracy is the residual's, about
2,000 times double's there). It shares no code with ``_lowest``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest_newton

EXTENDED = np.finfo(np.longdouble).eps < 1e-18
needs_extended = pytest.mark.skipif(not EXTENDED, reason="numpy has no extended precision here")

STEEL = {"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}
SPEEDS = np.array([600.0, 3000.0]) * np.pi / 30


def _soft_shaft():
    """A 1 m shaft of 0.1 m in 40 elements with a 20 kg disk, on two bearings of 100 N/m (a rotor
    hung on soft supports): modes at 0.05-0.8 Hz beside elements of 25 mm (164 coordinates)."""
    return rdm.Model.from_dict({
        "materials": [STEEL],
        "rotors": [{"name": "s", "speed_ratio": 1.0, "start": [0, 0, 0], "shear": "cowper", "element_length": 0.025,
                    "shaft": [{"length": 1.0, "outer_diameter": 0.1, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": 0.3, "mass": 20.0, "polar_inertia": 0.3,
                               "diametral_inertia": 0.16}]}],
        "bearings": [{"name": n, "rotor": "s", "axial_position": z, "stiffness": 100.0, "damping": 2e-3}
                     for n, z in (("a", 0.05), ("b", 0.95))]})


def _reference_root(M, D, K, lam, phi, steps=3):
    """The root of ``s^2 M + s D + K`` near ``lam`` (start shape ``phi``) by Newton's iteration on
    ``(A - s B) z = 0``, ``A = [[0, I], [-K, -D]]``, ``B = [[I, 0], [0, M]]``, bordered by
    ``c^H z = c^H z_0``; the residual in extended precision, the corrections by a dense solve.
    Returns the root (extended complex) and its last relative correction."""
    n = len(M)
    wide = np.clongdouble
    Ml, Dl, Kl = (np.asarray(m, dtype=np.longdouble) for m in (M, D, K))
    z = np.concatenate([phi, lam * phi]).astype(wide)
    c = z.astype(complex).conj()
    s = wide(lam)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -D]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    for _ in range(steps):
        z1, z2 = z[:n], z[n:]
        residual = np.concatenate([z2 - s * z1, -(Kl @ z1) - Dl @ z2 - s * (Ml @ z2)])
        J = np.zeros((2 * n + 1, 2 * n + 1), complex)
        J[:2 * n, :2 * n] = A - complex(s) * B
        J[:2 * n, 2 * n] = -(B @ z.astype(complex))
        J[2 * n, :2 * n] = c
        d = np.linalg.solve(J, -np.append(residual.astype(complex), 0.0))
        z = z + d[:2 * n].astype(wide)
        s = s + wide(d[2 * n])
    return s, abs(d[2 * n]) / abs(complex(s))


def _errors(model, values, shapes):
    """Relative errors (S, k) of roots ``values`` at ``SPEEDS`` against :func:`_reference_root`."""
    errors = np.empty(values.shape)
    for i, speed in enumerate(SPEEDS):
        M, C, G, K = model.matrices(speed)
        for j in range(values.shape[1]):
            # one BLAS thread: the dense solves are small, BLAS's threads only wait on a loaded machine
            with threadpool_limits(1):
                root, last = _reference_root(M, C + speed * G, K, values[i, j], shapes[i, j])
            # the reference converged: its corrections fall to its own round-off (measured 1e-11
            # here: double's 2e-6 estimate over the 2,048 of the extended precision), 1e-10 at most
            assert last <= 1e-10
            errors[i, j] = float(abs(root - np.clongdouble(values[i, j])) / abs(root))
    return errors


def _counting_stagnation(monkeypatch):
    """Count the roots ``_lowest_newton._stagnant`` ends (the round-off stop rule fires)."""
    fired = [0]
    original = _lowest_newton._stagnant

    def counted(*args):
        out = original(*args)
        fired[0] += int(np.count_nonzero(out))
        return out

    monkeypatch.setattr(_lowest_newton, "_stagnant", counted)
    return fired


@needs_extended
def test_roots_stalled_at_round_off_are_the_full_models_to_1e_9(monkeypatch):
    """The round-off stop rule fires on these roots; each root returned equals the full model's
    to 1e-9 relative (before the polish: 2.5e-7 to 5.9e-7 off)."""
    model = _soft_shaft()
    fired = _counting_stagnation(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                  # no speed solved whole, no accuracy warned of
        result = rdm.campbell(model, SPEEDS, modes=4, critical=False)
    assert fired[0] >= 1
    assert np.all(_errors(model, result.eigenvalues, result.shapes) <= 1e-9)


def test_without_extended_precision_the_accuracy_reached_is_warned_of(monkeypatch):
    """Where the residual cannot be computed beyond double precision, the polish cannot reach 1e-9:
    a warning names the accuracy, and that figure is not below the roots' actual errors."""
    monkeypatch.setattr(_lowest_newton, "_EXTENDED", np.float64)
    # a model past the dense exact polish's reach (``_exactly_polished``, whose stiffness sums are
    # exact in any precision: it would leave nothing to warn of)
    monkeypatch.setattr(_lowest_newton, "_PAIR_LARGEST", 0)
    model = _soft_shaft()
    with pytest.warns(UserWarning, match=r"exact only to about .* relative, not 1e-9") as caught:
        result = rdm.campbell(model, SPEEDS, modes=4, critical=False)
    message = next(str(w.message) for w in caught if "exact only" in str(w.message))
    assert "600, 3,000 rpm" in message
    claimed = float(message.split("about ")[1].split(" relative")[0])
    if EXTENDED:
        assert np.max(_errors(model, result.eigenvalues, result.shapes)) <= claimed


@needs_extended
def test_polishing_every_root_of_speed_dependent_bearings_keeps_the_full_models_roots(monkeypatch):
    """Every root polished (journal bearings: the residual carries their speed-dependent entries,
    stiffness and damping); each stays the full model's to 1e-9."""
    monkeypatch.setattr(_lowest_newton, "_CERTAIN", 0.0)
    polished = [0]
    original = _lowest_newton._polished

    def counted(pencils, index, lam, x):
        polished[0] += len(lam)
        return original(pencils, index, lam, x)

    monkeypatch.setattr(_lowest_newton, "_polished", counted)
    model = rdm.load_model("examples/compressor_on_journals.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error")                  # no speed solved whole: the polished roots serve
        result = rdm.campbell(model, SPEEDS, modes=4, critical=False)
    assert polished[0] >= 2 * 4
    assert np.all(_errors(model, result.eigenvalues, result.shapes) <= 1e-9)
