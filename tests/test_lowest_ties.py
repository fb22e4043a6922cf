"""The lowest modes at a tie: an undamped model with cross-coupled (circulatory) bearing stiffness
has pairs of roots ``-a + ib``, ``a + ib`` of one frequency. Where the ``N``-th place falls inside
such a pair, ``campbell(modes=N)`` and ``stability(modes=N)`` keep the unstable root of it (the
least stable of a group of one frequency), never the stable one alone (issue 28, item 4).

Truth from outside the code: the closed form of a rigid rotor's translation on two bearings with
stiffness ``[[k, q], [-q, k]]`` each (``m s^2 w + 2 (k - i q) w = 0`` for ``w = y + i z``, and its
conjugate: ``s = +-i sqrt(2 (k -+ i q) / m)``), and scipy's eigenvalues of a flexible shaft's state
matrix built here from ``model.matrices``."""

from __future__ import annotations

import numpy as np
import scipy.linalg

import rotordyn_modal as rdm
from rotordyn_modal.analysis import _lowest

K, Q, MASS = 1e6, 2e5, 10.0


def _rigid_rotor():
    """A rigid rotor (10 kg) on two bearings at +-0.2 m, stiffness ``[[k, q], [-q, k]]``, no damping:
    its lowest pair is the translation, ``s = +-a + ib``."""
    def bearing(name, x):
        return {"name": name, "rotor": "r", "position": [x, 0.0, 0.0], "stiffness": [[K, Q], [-Q, K]],
                "damping": 0.0, "axial_stiffness": 3e6}

    return rdm.Model.from_dict({
        "name": "tie", "spin_axis": [1.0, 0.0, 0.0],
        "rotors": [{"name": "r", "mass": MASS, "center_of_mass": [0.0, 0.0, 0.0], "polar_inertia": 0.1,
                    "diametral_inertia": 0.3, "speed_ratio": 1.0}],
        "bearings": [bearing("A", 0.2), bearing("B", -0.2)]})


def _translation_pair():
    """The closed-form pair (unstable, stable) of the rigid rotor's translation [1/s]."""
    unstable, stable = 1j * np.sqrt(2 * (K - 1j * Q) / MASS), 1j * np.sqrt(2 * (K + 1j * Q) / MASS)
    assert unstable.real > 0 > stable.real and np.isclose(unstable.imag, stable.imag, rtol=1e-14)
    return unstable, stable


def test_one_mode_of_a_split_pair_is_the_unstable_one():
    model = _rigid_rotor()
    unstable, _ = _translation_pair()
    speeds = np.array([0.0, 20.0, 40.0])
    lowest = rdm.campbell(model, speeds, critical=False, modes=1)
    assert np.allclose(lowest.eigenvalues[:, 0], unstable, rtol=1e-9, atol=0)
    # three modes: the second pair (the conical whirl at rest) is split too
    three = rdm.campbell(model, np.array([0.0]), critical=False, modes=3)
    assert np.max(three.eigenvalues.real) > 0 and np.sum(three.eigenvalues.real > 0) == 2
    result = rdm.stability(model, speeds, modes=1)
    assert result.unstable.all()
    assert np.allclose(result.largest_real_parts, unstable.real, rtol=1e-9)


def test_the_modes_below_a_frequency_keep_the_unstable_root_of_a_split_pair():
    model = _rigid_rotor()
    unstable, _ = _translation_pair()
    below = rdm.campbell(model, np.array([0.0]), critical=False, modes=1, max_frequency=200.0)
    assert np.allclose(below.eigenvalues[0, 0], unstable, rtol=1e-9, atol=0)


def _undamped_cross_coupled_shaft():
    """A steel shaft of 44 coordinates (Newton's route of the lowest modes) on two undamped bearings
    with cross-coupled stiffness."""
    return rdm.Model.from_dict({
        "name": "shaft", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7800.0, "young_modulus": 2e11, "shear_modulus": 8e10}],
        "rotors": [{"name": "r", "start": [0.0, 0.0, 0.0], "element_length": 0.1,
                    "shaft": [{"length": 1.0, "outer_diameter": 0.05, "material": "steel"}],
                    "disks": [{"name": "d", "axial_position": 0.6, "mass": 8.0, "polar_inertia": 0.06,
                               "diametral_inertia": 0.04}]}],
        "bearings": [{"name": f"b{i}", "rotor": "r", "axial_position": z,
                      "stiffness": [[1e7, 3e6], [-3e6, 1e7]], "damping": 0.0}
                     for i, z in enumerate((0.05, 0.95))]})


def test_a_shaft_keeps_the_unstable_root_of_a_split_pair():
    """Above ``DENSE_BELOW`` coordinates: the reduced route cannot show that no root of the split
    pair's frequency was missed (its ``count + 1``-th start is the pair's other root, not above the
    ``count``-th), so the speed is solved whole, and the whole solve keeps the unstable root."""
    model = _undamped_cross_coupled_shaft()
    assert model.dofs.n >= _lowest.DENSE_BELOW
    M, C, G, Kmat = model.matrices(0.0)
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, Kmat), -np.linalg.solve(M, C)]])
    roots = scipy.linalg.eigvals(A)
    roots = roots[roots.imag > 0]
    roots = roots[np.argsort(roots.imag)]
    # the lowest two are one pair -a + ib, a + ib
    assert abs(roots[0].imag - roots[1].imag) < 1e-9 * abs(roots[0]) and roots[0].real * roots[1].real < 0
    for count in (1, 3):
        result = rdm.campbell(model, np.array([0.0]), critical=False, modes=count)
        got = result.eigenvalues[0]
        # each root the full model's, and of each split pair (the count-th) the unstable one
        assert np.max(np.min(np.abs(got[:, None] - roots[None, :]), axis=1) / np.abs(got)) < 1e-9
        assert got.real.max() > 0 and np.sum(got.real > 0) == (count + 1) // 2
